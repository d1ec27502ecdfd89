"""What holds the rotor: linear bearings, plain journal bearings' oil films, and the
pedestals a bearing may sit on.
"""

from __future__ import annotations

from dataclasses import dataclass

from rubdiag import _check

__all__ = ["LOAD_DIRECTIONS", "Bearing", "JournalFilm", "Pedestal"]


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
