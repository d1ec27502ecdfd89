"""The rig description: frozen dataclasses in SI units.

A :class:`Rig` says *what* the machine is — shaft, discs, bearings, optional blades, casing
ring and contacts, loading, damping — and nothing about how it is discretised into matrices
(that is :mod:`rubdiag.assembly`) or run (that is :mod:`rubdiag.simulation`). Every field is
validated on construction; variants come from :func:`dataclasses.replace`.

Conventions: the rotor spins about +x at speed Ω; lateral displacements are y and z;
angles in the y-z plane are measured from +y towards +z. Node numbers follow the study:
shaft nodes are numbered from ``Shaft.first_node`` (3 when the coupling is left out), so
the bearings sit at nodes 4 and 26 and the discs at 11 and 19 of the paper rig.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from rubdiag import _check

__all__ = [
    "Bearing",
    "BladeContact",
    "Blades",
    "Casing",
    "Damping",
    "Disc",
    "JournalFilm",
    "Loading",
    "Material",
    "Pedestal",
    "Rig",
    "Shaft",
    "StatorContact",
    "Unbalance",
]


def _set(obj, name: str, value) -> None:
    """Normalise a field of a frozen dataclass during ``__post_init__``."""
    object.__setattr__(obj, name, value)


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material shared by shaft, discs, blades and casing.

    Parameters
    ----------
    youngs_modulus_pa : float
        Young's modulus E (Pa, > 0).
    poisson_ratio : float
        Poisson's ratio ν (-1 < ν < 0.5).
    density_kg_m3 : float
        Density ρ (kg/m³, > 0).
    """

    youngs_modulus_pa: float = 210e9
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0

    def __post_init__(self):
        _check.positive("Material.youngs_modulus_pa", self.youngs_modulus_pa)
        _check.number("Material.poisson_ratio", self.poisson_ratio, lo=-1.0, hi=0.5,
                      lo_open=True, hi_open=True)
        _check.positive("Material.density_kg_m3", self.density_kg_m3)

    @property
    def shear_modulus_pa(self) -> float:
        return self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))


@dataclass(frozen=True)
class Shaft:
    """Shaft of Timoshenko beam elements; element i joins nodes first_node+i and +i+1.

    ``outer_diameters_m`` and ``inner_diameters_m`` are per element; a single number applies
    to every element (inner 0 means a solid shaft).

    Parameters
    ----------
    element_lengths_m : tuple of float
        Length of each beam element (m, > 0), in axial order.
    outer_diameters_m : tuple of float or float
        Outer diameter of each element (m, > 0), or one for all.
    inner_diameters_m : tuple of float or float
        Bore of each element (m, >= 0 and below its outer diameter), or one for all.
    first_node : int
        Node number of the shaft's first node (>= 0).
    """

    element_lengths_m: tuple[float, ...]
    outer_diameters_m: tuple[float, ...] | float
    inner_diameters_m: tuple[float, ...] | float = 0.0
    first_node: int = 3

    def __post_init__(self):
        lengths = _check.numbers("Shaft.element_lengths_m", self.element_lengths_m)
        n = len(lengths)
        outer = _check.numbers("Shaft.outer_diameters_m", self.outer_diameters_m, length=n)
        inner = _check.numbers("Shaft.inner_diameters_m", self.inner_diameters_m,
                               check=_check.non_negative, length=n)
        for i, (do, di) in enumerate(zip(outer, inner, strict=True)):
            if di >= do:
                raise _check.out_of_range(f"Shaft.inner_diameters_m[{i}]", di,
                                          f"< outer diameter {do:g} m")
        _check.integer("Shaft.first_node", self.first_node, lo=0)
        _set(self, "element_lengths_m", lengths)
        _set(self, "outer_diameters_m", outer)
        _set(self, "inner_diameters_m", inner)

    @property
    def n_elements(self) -> int:
        return len(self.element_lengths_m)

    @property
    def nodes(self) -> range:
        """Paper node numbers of the shaft nodes, in axial order."""
        return range(self.first_node, self.first_node + self.n_elements + 1)

    @property
    def node_positions_m(self) -> tuple[float, ...]:
        """Axial position x of every shaft node, the first node at x = 0."""
        x = [0.0]
        for length in self.element_lengths_m:
            x.append(x[-1] + length)
        return tuple(x)


@dataclass(frozen=True)
class Disc:
    """Rigid disc on a shaft node, given by its geometry or by its mass and inertias.

    Give either ``outer_radius_m`` and ``thickness_m`` (a uniform disc of the rig's material,
    optional bore ``inner_radius_m``) or all three of ``mass_kg``, ``polar_inertia_kg_m2``
    and ``diametral_inertia_kg_m2``.

    Parameters
    ----------
    node : int
        Shaft node the disc sits on.
    outer_radius_m : float or None
        Outer radius (m) of a uniform disc.
    thickness_m : float or None
        Axial thickness (m) of a uniform disc.
    inner_radius_m : float
        Bore radius (m) of a uniform disc, 0 <= bore < outer radius.
    mass_kg : float or None
        Mass (kg) of a disc given by its inertia.
    polar_inertia_kg_m2 : float or None
        Polar moment of inertia about the shaft axis (kg·m²).
    diametral_inertia_kg_m2 : float or None
        Diametral moment of inertia (kg·m²).
    """

    node: int
    outer_radius_m: float | None = None
    thickness_m: float | None = None
    inner_radius_m: float = 0.0
    mass_kg: float | None = None
    polar_inertia_kg_m2: float | None = None
    diametral_inertia_kg_m2: float | None = None

    def __post_init__(self):
        _check.integer("Disc.node", self.node, lo=0)
        geometry = (self.outer_radius_m, self.thickness_m)
        inertia = (self.mass_kg, self.polar_inertia_kg_m2, self.diametral_inertia_kg_m2)
        has_geometry = all(v is not None for v in geometry)
        has_inertia = all(v is not None for v in inertia)
        if has_geometry == has_inertia:
            raise ValueError(
                f"Disc at node {self.node}: give either outer_radius_m and thickness_m, or "
                "mass_kg, polar_inertia_kg_m2 and diametral_inertia_kg_m2 (exactly one set)")
        if has_geometry:
            _check.positive("Disc.outer_radius_m", self.outer_radius_m)
            _check.positive("Disc.thickness_m", self.thickness_m)
            _check.number("Disc.inner_radius_m", self.inner_radius_m, lo=0.0,
                          hi=self.outer_radius_m, hi_open=True)
        else:
            _check.positive("Disc.mass_kg", self.mass_kg)
            _check.positive("Disc.polar_inertia_kg_m2", self.polar_inertia_kg_m2)
            _check.positive("Disc.diametral_inertia_kg_m2", self.diametral_inertia_kg_m2)

    def inertia(self, density_kg_m3: float) -> tuple[float, float, float]:
        """(mass kg, polar inertia kg·m², diametral inertia kg·m²)."""
        if self.mass_kg is not None:
            return self.mass_kg, self.polar_inertia_kg_m2, self.diametral_inertia_kg_m2
        ro, ri, t = self.outer_radius_m, self.inner_radius_m, self.thickness_m
        m = density_kg_m3 * math.pi * (ro**2 - ri**2) * t
        ip = 0.5 * m * (ro**2 + ri**2)
        idiam = m * (3.0 * (ro**2 + ri**2) + t**2) / 12.0
        return m, ip, idiam


@dataclass(frozen=True)
class Pedestal:
    """A bearing's pedestal: a lumped mass (kg) between the bearing and the ground, on its
    own support spring-dampers in y and z (N/m, N·s/m).

    With a pedestal the bearing's spring-damper joins the shaft node to the pedestal's (y, z)
    DOFs (node ``"pedestal K"``, K the bearing's 0-based index in ``Rig.bearings``), and the
    support joins the pedestal to the ground. The support stiffnesses must be > 0 (a
    pedestal free in a direction would leave the linear model singular); a loose pedestal
    (:class:`rubdiag.simulation._faults.Looseness`) replaces one direction's support spring by
    a seat that lifts off.

    Parameters
    ----------
    mass_kg : float
        Pedestal mass (kg, > 0).
    k_y_n_m, k_z_n_m : float
        Support stiffness to the ground in y and z (N/m, > 0).
    c_y_ns_m, c_z_ns_m : float
        Support damping in y and z (N·s/m, >= 0).
    """

    mass_kg: float
    k_y_n_m: float
    k_z_n_m: float
    c_y_ns_m: float = 0.0
    c_z_ns_m: float = 0.0

    def __post_init__(self):
        _check.positive("Pedestal.mass_kg", self.mass_kg)
        _check.positive("Pedestal.k_y_n_m", self.k_y_n_m)
        _check.positive("Pedestal.k_z_n_m", self.k_z_n_m)
        _check.non_negative("Pedestal.c_y_ns_m", self.c_y_ns_m)
        _check.non_negative("Pedestal.c_z_ns_m", self.c_z_ns_m)


#: the directions a journal bearing's static load may act along
LOAD_DIRECTIONS = ("-y", "+y", "-z", "+z")


@dataclass(frozen=True)
class JournalFilm:
    """The oil film of a plain journal bearing (:mod:`rubdiag._fluidfilm`: the short-bearing
    π-film force): oil viscosity (Pa·s), journal radius, bearing length and radial clearance
    (m), all > 0 with the clearance below the radius, and the static load the bearing
    carries (N, > 0) along ``load_direction`` (default "-y": gravity along -y). The load
    sets the static eccentricity at which the linear analysis linearises the film; a run
    applies its own static load (:class:`rubdiag.simulation._static_load.StaticLoad`), which
    should give the bearing the same reaction.

    Parameters
    ----------
    viscosity_pa_s : float
        Dynamic viscosity of the oil (Pa·s).
    radius_m : float
        Journal radius (m).
    length_m : float
        Bearing length (m).
    clearance_m : float
        Radial clearance (m), below ``radius_m``.
    load_n : float
        Static load the bearing carries (N).
    load_direction : {"-y", "+y", "-z", "+z"}
        Direction of that load on the journal.
    """

    viscosity_pa_s: float
    radius_m: float
    length_m: float
    clearance_m: float
    load_n: float
    load_direction: str = "-y"

    def __post_init__(self):
        for name in ("viscosity_pa_s", "radius_m", "length_m", "clearance_m", "load_n"):
            _check.positive(f"JournalFilm.{name}", getattr(self, name))
        if not self.clearance_m < self.radius_m:
            raise _check.out_of_range("JournalFilm.clearance_m", self.clearance_m,
                                      f"< radius_m = {_check.plain(self.radius_m)} m")
        _check.choice("JournalFilm.load_direction", self.load_direction, LOAD_DIRECTIONS)

    @property
    def load_vector(self) -> tuple[float, float]:
        """The unit (y, z) direction of the static load on the journal."""
        sign = -1.0 if self.load_direction[0] == "-" else 1.0
        return (sign, 0.0) if self.load_direction[1] == "y" else (0.0, sign)


@dataclass(frozen=True)
class Bearing:
    """Linear bearing between a shaft node and the ground (or its ``pedestal``, when it has
    one: :class:`Pedestal`); cross terms neglected. A plain journal bearing (``journal``: a
    :class:`JournalFilm`) has no fixed stiffness: its springs and dampers are 0 and its film
    gives speed-dependent, cross-coupled coefficients to the linear analysis
    (:meth:`rubdiag.assembly.Model.bearing_matrices`) and a nonlinear element to a run.

    Parameters
    ----------
    node : int
        Shaft node of the bearing.
    k_y_n_m, k_z_n_m : float
        Direct stiffness in y and z (N/m, >= 0; 0 for a journal bearing).
    c_y_ns_m, c_z_ns_m : float
        Direct damping in y and z (N·s/m, >= 0; 0 for a journal bearing).
    pedestal : Pedestal or None
        The pedestal between bearing and ground; None: the bearing is grounded.
    journal : JournalFilm or None
        The oil film of a plain journal bearing; None: a linear bearing.
    """

    node: int
    k_y_n_m: float
    k_z_n_m: float
    c_y_ns_m: float = 0.0
    c_z_ns_m: float = 0.0
    pedestal: Pedestal | None = None
    journal: JournalFilm | None = None

    def __post_init__(self):
        _check.integer("Bearing.node", self.node, lo=0)
        _check.non_negative("Bearing.k_y_n_m", self.k_y_n_m)
        _check.non_negative("Bearing.k_z_n_m", self.k_z_n_m)
        _check.non_negative("Bearing.c_y_ns_m", self.c_y_ns_m)
        _check.non_negative("Bearing.c_z_ns_m", self.c_z_ns_m)
        if self.pedestal is not None and not isinstance(self.pedestal, Pedestal):
            raise ValueError(f"Bearing.pedestal has the wrong type "
                             f"({type(self.pedestal).__name__}; allowed: a Pedestal or None)")
        if self.journal is not None:
            if not isinstance(self.journal, JournalFilm):
                raise ValueError(f"Bearing.journal has the wrong type "
                                 f"({type(self.journal).__name__}; allowed: a JournalFilm or "
                                 "None)")
            for name in ("k_y_n_m", "k_z_n_m", "c_y_ns_m", "c_z_ns_m"):
                if getattr(self, name) != 0.0:
                    raise _check.out_of_range(f"Bearing.{name}", getattr(self, name),
                                              "0 for a journal bearing (its film gives them)")


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


@dataclass(frozen=True)
class Unbalance:
    """Unbalance per disc, in disc order: magnitude u (kg·m) and phase (rad).

    The force on disc j is u_j Ω² (cos(Ωt + φ_j), sin(Ωt + φ_j)) in (y, z).

    Parameters
    ----------
    magnitudes_kg_m : tuple of float
        Unbalance u of each disc (kg·m, >= 0).
    phases_rad : tuple of float
        Phase φ of each disc's unbalance (rad), one per magnitude.
    """

    magnitudes_kg_m: tuple[float, ...]
    phases_rad: tuple[float, ...]

    def __post_init__(self):
        mags = _check.numbers("Unbalance.magnitudes_kg_m", self.magnitudes_kg_m,
                              check=_check.non_negative)
        phases = _check.numbers("Unbalance.phases_rad", self.phases_rad,
                                check=_check.number, length=len(mags))
        _set(self, "magnitudes_kg_m", mags)
        _set(self, "phases_rad", phases)


@dataclass(frozen=True)
class Loading:
    """The rig's unbalance magnitudes per disc and the study's two phase patterns.

    Case 1 (API 617, first mode) puts the unbalances in phase; case 2 (second mode) puts
    them out of phase.

    Parameters
    ----------
    unbalance_kg_m : tuple of float
        Unbalance magnitude of each disc (kg·m, >= 0).
    case1_phases_rad : tuple of float or None
        Phases of case 1 (rad); None: all 0.
    case2_phases_rad : tuple of float or None
        Phases of case 2 (rad); None: 0, π, 0, ... along the shaft.
    """

    unbalance_kg_m: tuple[float, ...]
    case1_phases_rad: tuple[float, ...] | None = None
    case2_phases_rad: tuple[float, ...] | None = None

    def __post_init__(self):
        mags = _check.numbers("Loading.unbalance_kg_m", self.unbalance_kg_m,
                              check=_check.non_negative)
        n = len(mags)
        _set(self, "unbalance_kg_m", mags)
        case1 = (0.0,) * n if self.case1_phases_rad is None else self.case1_phases_rad
        # out of phase: alternate 0, π along the shaft
        case2 = (tuple(math.pi * (i % 2) for i in range(n))
                 if self.case2_phases_rad is None else self.case2_phases_rad)
        _set(self, "case1_phases_rad",
             _check.numbers("Loading.case1_phases_rad", case1, check=_check.number, length=n))
        _set(self, "case2_phases_rad",
             _check.numbers("Loading.case2_phases_rad", case2, check=_check.number, length=n))

    def case(self, case: int) -> Unbalance:
        """The unbalance of the study's case 1 (in phase) or case 2 (out of phase)."""
        case = _check.integer("case", case, lo=1, hi=2)
        phases = self.case1_phases_rad if case == 1 else self.case2_phases_rad
        return Unbalance(self.unbalance_kg_m, phases)


@dataclass(frozen=True)
class Damping:
    """Modal damping ratios ξ1, ξ2 at two reference speeds, turned into Rayleigh damping.

    ``reference_speeds_rad_s = None`` uses the rig's first two forward critical speeds
    (the study's choice). See :func:`rubdiag.assembly.rayleigh_coefficients`.

    Parameters
    ----------
    xi_1, xi_2 : float
        Damping ratios at the first and second reference speed (0-1).
    reference_speeds_rad_s : tuple of float or None
        The two reference speeds, increasing (rad/s); None: the first two forward critical
        speeds.
    """

    xi_1: float = 0.04
    xi_2: float = 0.04
    reference_speeds_rad_s: tuple[float, float] | None = None

    def __post_init__(self):
        _check.number("Damping.xi_1", self.xi_1, lo=0.0, hi=1.0)
        _check.number("Damping.xi_2", self.xi_2, lo=0.0, hi=1.0)
        if self.reference_speeds_rad_s is not None:
            speeds = _check.numbers("Damping.reference_speeds_rad_s",
                                    self.reference_speeds_rad_s, length=2)
            if speeds[0] >= speeds[1]:
                raise _check.out_of_range("Damping.reference_speeds_rad_s", speeds,
                                          "two increasing speeds")
            _set(self, "reference_speeds_rad_s", speeds)


@dataclass(frozen=True)
class Rig:
    """A single-span rotor with optional blades, casing ring and contacts.

    A plain shaft-disc-bearing rotor (no blades, casing or contacts) is a valid rig.

    Parameters
    ----------
    shaft : Shaft
        The shaft.
    bearings : tuple of Bearing
        At least one bearing, each on a shaft node.
    discs : tuple of Disc
        The discs, at most one per node.
    material : Material
        Material of shaft, discs, blades and casing.
    damping : Damping
        The Rayleigh damping's reference ratios.
    blades : Blades or None
        The blades of one disc.
    casing : Casing or None
        The casing ring around the blades.
    contact : BladeContact or None
        Blade-tip/casing contact elements (needs blades and a casing).
    stator_contacts : tuple of StatorContact
        Shaft/seal contacts.
    loading : Loading or None
        The unbalance of the study's two cases; None: runs give their own.
    name : str
        A name for tables and logs.
    """

    shaft: Shaft
    bearings: tuple[Bearing, ...]
    discs: tuple[Disc, ...] = ()
    material: Material = field(default_factory=Material)
    damping: Damping = field(default_factory=Damping)
    blades: Blades | None = None
    casing: Casing | None = None
    contact: BladeContact | None = None
    stator_contacts: tuple[StatorContact, ...] = ()
    loading: Loading | None = None
    name: str = "rig"

    def __post_init__(self):
        _set(self, "bearings", tuple(self.bearings))
        _set(self, "discs", tuple(self.discs))
        _set(self, "stator_contacts", tuple(self.stator_contacts))
        if not self.bearings:
            raise ValueError("Rig.bearings is empty (allowed: at least one bearing)")
        nodes = self.shaft.nodes
        allowed = f"shaft nodes {nodes.start}..{nodes.stop - 1}"
        for what, items in (("Bearing", self.bearings), ("Disc", self.discs),
                            ("StatorContact", self.stator_contacts)):
            for item in items:
                if item.node not in nodes:
                    raise ValueError(f"{what}.node = {item.node} is not a shaft node "
                                     f"(allowed: {allowed})")
        disc_nodes = [d.node for d in self.discs]
        if len(set(disc_nodes)) != len(disc_nodes):
            raise ValueError(f"Rig.discs: two discs on one node ({disc_nodes})")
        self._check_blades_and_casing(disc_nodes)
        if self.loading is not None and len(self.loading.unbalance_kg_m) != len(self.discs):
            raise ValueError(f"Loading.unbalance_kg_m has {len(self.loading.unbalance_kg_m)} "
                             f"entries (allowed: one per disc, {len(self.discs)})")

    def _check_blades_and_casing(self, disc_nodes: list[int]) -> None:
        blades, casing, contact = self.blades, self.casing, self.contact
        if blades is not None and blades.disc_node not in disc_nodes:
            raise ValueError(f"Blades.disc_node = {blades.disc_node} has no disc "
                             f"(allowed: {disc_nodes})")
        if blades is not None and casing is not None:
            if blades.tip_radius_m >= casing.inner_radius_m:
                raise ValueError(
                    f"Blades do not fit inside the casing: tip radius {blades.tip_radius_m:g} m"
                    f" >= casing inner radius {casing.inner_radius_m:g} m")
        if contact is None:
            return
        if blades is None or casing is None:
            raise ValueError("Rig.contact needs both blades and a casing")
        for k, blade in enumerate(contact.blades, start=1):
            if blade > blades.count:
                raise ValueError(f"BladeContact.blades[{k - 1}] = {blade} is out of range "
                                 f"(allowed: 1..{blades.count})")
            position = (blade - 1) * casing.n_elements / blades.count
            if abs(position - round(position)) > 1e-9:
                raise ValueError(
                    f"BladeContact.blades[{k - 1}] = {blade}: no casing node at the blade's "
                    f"angle (casing n_elements = {casing.n_elements}, blade count "
                    f"{blades.count})")

    # --- derived quantities -----------------------------------------------------------
    def disc_at(self, node: int) -> Disc:
        for disc in self.discs:
            if disc.node == node:
                return disc
        raise KeyError(node)

    def contact_casing_node(self, k: int) -> int:
        """Casing node (1-based) paired with contact element ``k`` (1-based)."""
        blade = self.contact.blades[k - 1]
        return round((blade - 1) * self.casing.n_elements / self.blades.count) + 1

    def nominal_gap_m(self) -> float:
        """Radial gap between blade tips and casing inner surface in the rig geometry."""
        if self.blades is None or self.casing is None:
            raise ValueError("nominal_gap_m needs blades and a casing")
        return self.casing.inner_radius_m - self.blades.tip_radius_m

    def unbalance(self, case: int) -> Unbalance:
        """The unbalance pattern of the study's case 1 or 2 for this rig."""
        if self.loading is None:
            raise ValueError("Rig.loading is not set: give the unbalance explicitly")
        return self.loading.case(case)
