"""What holds the rotor: linear bearings, plain journal bearings' oil films, and the
pedestals a bearing may sit on.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag._fluidfilm import eccentricity_for_load, linearised_coefficients, load_capacity

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

    def _film(self) -> tuple[float, float, float, float]:
        return self.viscosity_pa_s, self.radius_m, self.length_m, self.clearance_m

    def load_capacity(self, eccentricity_ratio: float, speed_rad_s: float) -> float:
        """The static load the film carries with the journal at ``eccentricity_ratio``.

        The short-bearing π-film closed form,
        W = μ Ω R L³ ε √(16 ε² + π² (1 − ε²)) / (4 c² (1 − ε²)²).

        Parameters
        ----------
        eccentricity_ratio : float
            The journal's eccentricity over the radial clearance, in [0, 1).
        speed_rad_s : float
            The spin speed Ω (rad/s), > 0.

        Returns
        -------
        float
            The load (N).

        See Also
        --------
        eccentricity_ratio : Its inverse: where the film carries ``load_n``.
        """
        eps = _check.number("eccentricity_ratio", eccentricity_ratio, lo=0.0, hi=1.0,
                            hi_open=True)
        speed = _check.number("speed_rad_s", speed_rad_s, lo=0.0, lo_open=True)
        return load_capacity(eps, speed, *self._film())

    def eccentricity_ratio(self, speed_rad_s: float) -> float:
        """Where the journal sits under the film's static load ``load_n``.

        Parameters
        ----------
        speed_rad_s : float
            The spin speed Ω (rad/s), > 0.

        Returns
        -------
        float
            The eccentricity ratio ε in (0, 1) at which :meth:`load_capacity` is ``load_n``.

        Examples
        --------
        >>> film = JournalFilm(viscosity_pa_s=0.02, radius_m=0.02, length_m=0.01,
        ...                    clearance_m=50e-6, load_n=20.0)
        >>> eps = film.eccentricity_ratio(300.0)
        >>> round(film.load_capacity(eps, 300.0), 9)
        20.0
        """
        speed = _check.number("speed_rad_s", speed_rad_s, lo=0.0, lo_open=True)
        return eccentricity_for_load(self.load_n, speed, *self._film())

    def coefficients(self, speed_rad_s: float) -> tuple[np.ndarray, np.ndarray]:
        """The film's stiffness and damping, linearised at its static load.

        The Jacobian of the same film force the time integrator uses, at the journal's
        static equilibrium under ``load_n`` along ``load_direction``: what the linear
        analysis adds to the rig's K and C (speed-dependent and cross-coupled).

        Parameters
        ----------
        speed_rad_s : float
            The spin speed Ω (rad/s), > 0.

        Returns
        -------
        K : numpy.ndarray
            Stiffness (2, 2), N/m, in the (y, z) frame: K = −∂F/∂(y, z).
        C : numpy.ndarray
            Damping (2, 2), N·s/m: C = −∂F/∂(ẏ, ż).

        References
        ----------
        The short-bearing (Ocvirk) film with the π-film (Gümbel) cavitation condition:
        M. I. Friswell, J. E. T. Penny, S. D. Garvey and A. W. Lees, *Dynamics of Rotating
        Machines*, Cambridge University Press, 2010, section 5.5.

        Examples
        --------
        With the load along −z, the direct stiffness across it (y) matches the
        short-bearing closed form 4 W h₀ (π² (2 − ε²) + 16 ε²) / c, with
        h₀ = (π² (1 − ε²) + 16 ε²)^(−3/2):

        >>> import math
        >>> film = JournalFilm(viscosity_pa_s=0.02, radius_m=0.02, length_m=0.01,
        ...                    clearance_m=50e-6, load_n=20.0, load_direction="-z")
        >>> K, C = film.coefficients(300.0)
        >>> e = film.eccentricity_ratio(300.0)
        >>> h0 = (math.pi**2 * (1 - e**2) + 16 * e**2) ** -1.5
        >>> closed = 4 * 20.0 * h0 * (math.pi**2 * (2 - e**2) + 16 * e**2) / 50e-6
        >>> bool(abs(K[0, 0] / closed - 1) < 1e-6)
        True
        """
        speed = _check.number("speed_rad_s", speed_rad_s, lo=0.0, lo_open=True)
        K, C, _ = linearised_coefficients(self.load_n, speed, *self._film(), self.load_vector)
        return K, C


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
