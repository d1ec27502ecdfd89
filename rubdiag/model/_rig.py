"""The rig description: frozen dataclasses in SI units, assembled into a :class:`Rig`.

A :class:`Rig` says *what* the machine is — shaft, discs, bearings, optional blades, casing
ring and contacts, loading, damping — and nothing about how it is discretised into matrices
(that is :mod:`rubdiag.assembly`) or run (that is :mod:`rubdiag.simulation`). Every field is
validated on construction; variants come from :func:`dataclasses.replace`. Its parts are
defined by part: the rotor (:mod:`rubdiag.model._rotor`), the bearings
(:mod:`rubdiag.model._bearings`), what rubs (:mod:`rubdiag.model._contacts`) and the loading
(:mod:`rubdiag.model._loading`); this module holds the damping and the rig that joins them.

Conventions: the rotor spins about +x at speed Ω; lateral displacements are y and z;
angles in the y-z plane are measured from +y towards +z. Node numbers follow the study:
shaft nodes are numbered from ``Shaft.first_node`` (3 when the coupling is left out), so
the bearings sit at nodes 4 and 26 and the discs at 11 and 19 of the paper rig.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rubdiag import _check
from rubdiag._tolerances import ON_LEVEL
from rubdiag.model._bearings import Bearing
from rubdiag.model._contacts import BladeContact, Blades, Casing, StatorContact
from rubdiag.model._frozen import set_field as _set
from rubdiag.model._loading import Loading, Unbalance
from rubdiag.model._rotor import Disc, Material, Shaft

__all__ = ["Damping", "Rig"]


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
            if abs(position - round(position)) > ON_LEVEL:
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
