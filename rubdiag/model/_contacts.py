"""What rubs: the blades of one disc, the casing ring around them, and the contact elements
between blade tips and casing or between the shaft and a seal.

Angles in the y-z plane are measured from +y towards +z: blade 1 and casing node 1 lie on +y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rubdiag import _check
from rubdiag.model._frozen import set_field as _set

__all__ = ["BladeContact", "Blades", "Casing", "StatorContact"]


@dataclass(frozen=True)
class Blades:
    """Equally spaced radial blades in the plane of one disc, blade 1 on the +y axis.

    Each blade is ``n_elements`` planar Timoshenko frame elements; ``width_m`` is the axial
    size of the section and ``thickness_m`` the tangential one (in-plane bending). The root
    (at ``root_radius_m``) is clamped to the disc centre: it follows the shaft node's lateral
    motion and does not rotate about x (torsion is neglected).

    Parameters
    ----------
    count : int
        Number of blades (1-360).
    length_m : float
        Blade length, root to tip (m).
    width_m : float
        Axial size of the blade section (m).
    thickness_m : float
        Tangential size of the blade section (m).
    root_radius_m : float
        Radius of the blade roots (m).
    disc_node : int
        Shaft node of the disc that carries the blades.
    n_elements : int
        Frame elements per blade (1-100).
    """

    count: int
    length_m: float
    width_m: float
    thickness_m: float
    root_radius_m: float
    disc_node: int
    n_elements: int = 4

    def __post_init__(self):
        _check.integer("Blades.count", self.count, lo=1, hi=360)
        _check.positive("Blades.length_m", self.length_m)
        _check.positive("Blades.width_m", self.width_m)
        _check.positive("Blades.thickness_m", self.thickness_m)
        _check.positive("Blades.root_radius_m", self.root_radius_m)
        _check.integer("Blades.disc_node", self.disc_node, lo=0)
        _check.integer("Blades.n_elements", self.n_elements, lo=1, hi=100)

    @property
    def tip_radius_m(self) -> float:
        return self.root_radius_m + self.length_m

    def angle_rad(self, blade: int) -> float:
        """Angle of blade ``blade`` (1-based) from +y towards +z."""
        return 2.0 * math.pi * (blade - 1) / self.count


@dataclass(frozen=True)
class Casing:
    """Elastic casing ring in the blades' plane: straight planar frame elements.

    ``radius_m`` is the centreline radius; the section is ``axial_width_m`` (along x) by
    ``radial_height_m`` (in the plane, the bending thickness). Casing node 1 is on +y and
    nodes run towards +z.

    ``support`` says how the ring is held (the study's single spring-damper is ambiguous):

    - ``"distributed"`` (default): every node gets y and z springs and dampers such that
      their sums equal ``support_k_*``/``support_c_*`` (the rigid-ring stiffness);
    - ``"point"``: one node, ``support_node`` (default: the node opposite casing node 1,
      i.e. opposite contact element 1, so that the casing is not measured where it is
      held), carries the whole spring-damper, plus a rotational spring
      ``support_k_rx_nm_rad`` about x so that the ring cannot spin freely (default k_y·R²).

    Parameters
    ----------
    radius_m : float
        Centreline radius of the ring (m).
    axial_width_m : float
        Axial size of the ring's section (m).
    radial_height_m : float
        Radial size of the section, its bending thickness (m, below ``radius_m``).
    n_elements : int
        Number of frame elements (and nodes) around the ring (3-10000).
    support : {"distributed", "point"}
        How the ring is held (above).
    support_k_y_n_m, support_k_z_n_m : float
        Total support stiffness in y and z (N/m, >= 0).
    support_c_y_ns_m, support_c_z_ns_m : float
        Total support damping in y and z (N·s/m, >= 0).
    support_node : int or None
        The supported casing node (1-based) of a ``"point"`` support; None: the node opposite
        casing node 1.
    support_k_rx_nm_rad : float or None
        Rotational support stiffness about x of a ``"point"`` support (N·m/rad); None: k_y·R².
    """

    radius_m: float
    axial_width_m: float
    radial_height_m: float
    n_elements: int = 40
    support: str = "distributed"
    support_k_y_n_m: float = 1e6
    support_k_z_n_m: float = 1e6
    support_c_y_ns_m: float = 1e3
    support_c_z_ns_m: float = 1e3
    support_node: int | None = None
    support_k_rx_nm_rad: float | None = None

    def __post_init__(self):
        _check.positive("Casing.radius_m", self.radius_m)
        _check.positive("Casing.axial_width_m", self.axial_width_m)
        _check.number("Casing.radial_height_m", self.radial_height_m, lo=0.0,
                      hi=self.radius_m, lo_open=True, hi_open=True)
        _check.integer("Casing.n_elements", self.n_elements, lo=3, hi=10_000)
        _check.choice("Casing.support", self.support, ("distributed", "point"))
        for name in ("support_k_y_n_m", "support_k_z_n_m", "support_c_y_ns_m",
                     "support_c_z_ns_m"):
            _check.non_negative(f"Casing.{name}", getattr(self, name))
        if self.support_node is None:
            _set(self, "support_node", self.n_elements // 2 + 1)
        _check.integer("Casing.support_node", self.support_node, lo=1, hi=self.n_elements)
        if self.support_k_rx_nm_rad is not None:
            _check.non_negative("Casing.support_k_rx_nm_rad", self.support_k_rx_nm_rad)

    @property
    def inner_radius_m(self) -> float:
        return self.radius_m - 0.5 * self.radial_height_m

    def angle_rad(self, node: int) -> float:
        """Angle of casing node ``node`` (1-based) from +y towards +z."""
        return 2.0 * math.pi * (node - 1) / self.n_elements


@dataclass(frozen=True)
class BladeContact:
    """Point-point blade-tip/casing contact elements (the study's Conta178).

    One element per listed blade (1-based), paired with the casing node at the same angle;
    contact element k is ``blades[k-1]``. Normal = radial, tangent = circumferential.
    Normal law: penalty ``normal_stiffness_n_m`` plus, when ``augmented``, Lagrange
    multiplier updates until the penetration is below ``penetration_tolerance_m`` (the
    study's eqs. 1-2). Coulomb friction with a stick state of tangential penalty
    ``tangential_stiffness_n_m`` (default: equal to the normal stiffness).

    Parameters
    ----------
    blades : tuple of int
        The blades (1-based) that carry a contact element, each once.
    normal_stiffness_n_m : float
        Normal penalty stiffness (N/m).
    tangential_stiffness_n_m : float or None
        Tangential (stick) penalty stiffness (N/m); None: the normal stiffness.
    friction_coefficient : float
        Coulomb friction coefficient μ (0-10).
    augmented : bool
        Augmented Lagrangian iterations on the normal force.
    penetration_tolerance_m : float
        Penetration the augmented iterations stop below (m).
    """

    blades: tuple[int, ...] = (1, 3, 5, 7, 9, 11, 13, 15)
    normal_stiffness_n_m: float = 80e6
    tangential_stiffness_n_m: float | None = None
    friction_coefficient: float = 0.3
    augmented: bool = False
    penetration_tolerance_m: float = 20e-6

    def __post_init__(self):
        if isinstance(self.blades, int) or not self.blades:
            raise ValueError(f"BladeContact.blades = {_check.plain(self.blades)} is out of range "
                             "(allowed: a non-empty list of blade numbers)")
        blades = tuple(_check.integer(f"BladeContact.blades[{i}]", b, lo=1)
                       for i, b in enumerate(self.blades))
        if len(set(blades)) != len(blades):
            raise ValueError(f"BladeContact.blades = {_check.plain(blades)} lists a blade twice")
        _set(self, "blades", blades)
        _check.positive("BladeContact.normal_stiffness_n_m", self.normal_stiffness_n_m)
        if self.tangential_stiffness_n_m is None:
            _set(self, "tangential_stiffness_n_m", float(self.normal_stiffness_n_m))
        _check.positive("BladeContact.tangential_stiffness_n_m", self.tangential_stiffness_n_m)
        _check.number("BladeContact.friction_coefficient", self.friction_coefficient,
                      lo=0.0, hi=10.0)
        if not isinstance(self.augmented, bool):
            raise _check.wrong_type("BladeContact.augmented", self.augmented, "true or false")
        _check.positive("BladeContact.penetration_tolerance_m", self.penetration_tolerance_m)


@dataclass(frozen=True)
class StatorContact:
    """Shaft-stator rub at a shaft node with an annular radial clearance (a seal).

    Parameters
    ----------
    node : int
        Shaft node at the seal.
    clearance_m : float
        Radial clearance between shaft and seal (m).
    stiffness_n_m : float
        Contact penalty stiffness (N/m).
    friction_coefficient : float
        Coulomb friction coefficient μ (0-10).
    shaft_radius_m : float or None
        Shaft radius at the seal (m), the lever arm of the friction force; None: half the outer
        diameter of the shaft element there.
    """

    node: int
    clearance_m: float
    stiffness_n_m: float
    friction_coefficient: float = 0.3
    shaft_radius_m: float | None = None

    def __post_init__(self):
        _check.integer("StatorContact.node", self.node, lo=0)
        _check.positive("StatorContact.clearance_m", self.clearance_m)
        _check.positive("StatorContact.stiffness_n_m", self.stiffness_n_m)
        _check.number("StatorContact.friction_coefficient", self.friction_coefficient,
                      lo=0.0, hi=10.0)
        if self.shaft_radius_m is not None:
            _check.positive("StatorContact.shaft_radius_m", self.shaft_radius_m)
