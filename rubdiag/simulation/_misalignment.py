"""Coupling misalignment: the loads a misaligned spacer coupling puts on the rotor's end.

The model is DERIVED here, not quoted. The published misalignment models (Sekhar &
Prabhu, J. Sound Vib. 185 (1995) 655-671; Patel & Darpe, J. Sound Vib. 325 (2009) 609-628,
whose misalignment stiffness comes from their measurements; Al-Hussain & Redmond,
J. Sound Vib. 249 (2002) 483-498) could not be checked equation by equation, so none of
their expressions is used. What is used is the kinematics of Hooke's (Cardan) joints, a
textbook result (the speed ratio of one joint, ω₂/ω₁ = cos α / (1 − sin²α cos²θ), follows
from it), applied to a double-joint spacer coupling — the kinematic idealisation of a gear
or disc coupling with two flex planes. ROSS (``ross/faults/misalignment.py``, after Xia et
al., Applied Acoustics 155 (2019) 286-296) models a three-pin hexangular coupling
instead; it is the open peer to compare with.

The coupling
------------
The rotor turns about x by φ (from +y towards +z); its end, the shaft node ``node``, is the
rotor-side flex plane B. A massless spacer of length L joins B to the drive-side flex
plane A. Misalignment lies in the plane at angle β from +y (``direction_rad``; unit vector
n = (0, cos β, sin β)): A sits ``offset_m`` δ off the rotor's axis along n, so the spacer
axis is e_s = cos γ x − sin γ n with sin γ = δ/L, and the drive (motor) shaft, held by its
own bearings, turns about e_d = cos α₀ x + sin α₀ n (``angle_rad`` α₀) with the drive torque
T (``drive_torque_n_m``). Joint B bends by γ, joint A by α₀ + γ.

A joint passes moments about its two pin axes only: its massless cross, with arms p and
q, takes from each yoke a moment ⊥ its arm, so it passes a moment along p × q. With the
rotor's arm v = (0, cos φ, sin φ), the spacer's arm at B is u ∝ e_s × v, its arm at A is u
too (the spacer's yokes in phase, as couplings are built), the drive's arm is a ∝ e_d × u,
and

    M_A = T w_A / (w_A · e_d),   w_A = a × u     (the drive carries T about e_d),
    M_B = T_s w_B / (w_B · e_s), w_B = u × v,   T_s = M_A · e_s (the spacer's torque).

The spacer's moment balance about B, M_A − M_B − L e_s × F = 0, gives the force F it
passes (its component ⊥ e_s; the axial one is not determined and rubdiag has no axial
DOF). The rotor receives at B the moment M_B and the force F = −e_s × (M_A − M_B) / L; their
y, z components are the loads (moments on the node's ry, rz; forces on its y, z; M_B's x
part is the torque, and rubdiag has no torsion DOF).

Lines
-----
A Hooke's joint is symmetric under φ → φ + π, so the loads hold even orders only: a static
part (the preload) and 2×, with 4×, 6×, ... smaller by about r = tan²(α/2) each (r ≈ α²/4,
2.5e-5 at α = 10 mrad). The loads are computed at 64 shaft angles and their Fourier
coefficients of orders 0, 2 and 4 kept (:data:`JOINT_ORDERS`; what is left out is ~r² of
the 2×). For small angles the 2× scales as T × (joint angles): linear in δ/L and in α₀.
A single joint's secondary moment has the closed form (the test checks it)

    M_⊥ = T sin α sin θ (sin θ, −cos θ) / (1 − sin²α cos²θ)

in the frame of its bend, θ the driven arm's angle from the bend plane: T tan(α/2) static
and ≈ Tα/2 at 2×.

Misaligned rotors also show 1× and 3× (Patel & Darpe 2009 measured them), which the
kinematic model does not give: ``ratio_1x`` and ``ratio_3x`` add, at 1× and 3×, copies of
the 2× terms scaled by that ratio — CALIBRATIONS (default 0: the derived model alone),
limited to [0, 1) so that 2× stays the dominant line.

The signature, and where the sources disagree
---------------------------------------------
The coupling's loads are even orders, 2x first; the rotor amplifies that 2x where it meets
a critical speed, near half of it, as Sekhar & Prabhu (1995) found, and Patel & Darpe
(2009) measured 2x of the order of 1x or above. The direction of that 2x is where published
models differ: ROSS's hexangular-coupling model turns it purely backward, while the
kinematics here (a joint's secondary moment, its bend fixed in space, turns forward at 2φ)
turn the load's 2x purely forward. This model follows the kinematics: they come from the
coupling's geometry alone, with no fitted stiffness, and are checked against closed forms;
the response's direction then depends on the supports (journal films make the 2x orbit an
ellipse with a reverse part). tests/simulation/test_misalignment_signature.py checks it on
``paper-journal`` (α₀ = 10 mrad: 2x/1x 2.0-5.4 at half the first critical speed,
0.018-0.050 at it; the 2x response forward).

Every term is a load by order (:mod:`rubdiag.simulation._loads`) with the law "constant": T
does not depend on the speed (a torque that does is a "table" law, left to the caller).
Units SI: m, rad, N·m, N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag.simulation._loads import HarmonicForce

__all__ = ["Misalignment"]

#: the orders of the joints' loads that are kept (the static part and the first two even)
JOINT_ORDERS = (0, 2, 4)
#: shaft angles per revolution the loads' Fourier coefficients are computed from
N_ANGLES = 64
#: the load components, in the order of :meth:`Misalignment.loads_at`
COMPONENTS = ("y", "z", "ry", "rz")


@dataclass(frozen=True, kw_only=True)
class Misalignment:
    """A misaligned double-joint spacer coupling at the driven end of the shaft.

    The coupling's two flex planes are Hooke's joints joined by a massless spacer; the drive
    torque passed through their bends puts a static load and 2× (and 4×) forces and moments
    on the rotor's end (the module docstring derives them). Set it on a run through
    :class:`Faults`.

    Parameters
    ----------
    node : int
        The shaft node of the rotor-side flex plane (the driven end), >= 0.
    drive_torque_n_m : float
        The drive torque T (N·m), in [-1e6, 1e6]; positive about +x.
    spacer_length_m : float
        The spacer's length L between the flex planes (m), in (0, 10].
    offset_m : float
        Parallel offset δ of the drive-side flex plane from the rotor's axis (m), in
        [0, 0.05] and at most L/4. Default 0.
    angle_rad : float
        Angular misalignment α₀ of the drive shaft (rad), in [0, 0.2]. Default 0.
    direction_rad : float
        β, the misalignment plane's angle from +y towards +z (rad), in [-2π, 2π]. Default 0.
    ratio_1x, ratio_3x : float
        Calibrations in [0, 1): 1× and 3× copies of the 2× terms, scaled by this ratio,
        for the 1× and 3× that measured misaligned rotors show and the kinematics do not
        give. Default 0 (the derived model alone).

    Raises
    ------
    ValueError
        A field out of its range, naming it and the range allowed.

    See Also
    --------
    Faults : The faults of a run, this misalignment among them.

    References
    ----------
    The kinematics of Hooke's (Cardan) joints, applied to a double-joint spacer coupling.
    Compared with the published models of A. S. Sekhar and B. S. Prabhu, J. Sound Vib. 185
    (1995) 655-671, and T. H. Patel and A. K. Darpe, J. Sound Vib. 325 (2009) 609-628 (who
    measured the 1× and 3× the calibrations stand for).

    Examples
    --------
    A 1 mm parallel offset over a 0.1 m spacer bends the rotor-side joint by asin(0.01):

    >>> from rubdiag.simulation import Faults, Misalignment
    >>> m = Misalignment(node=0, drive_torque_n_m=50.0, spacer_length_m=0.1, offset_m=1e-3)
    >>> round(m.spacer_angle_rad, 6)
    0.01
    >>> Faults(misalignment=m).names
    ('misalignment',)
    """

    node: int
    drive_torque_n_m: float
    spacer_length_m: float
    offset_m: float = 0.0
    angle_rad: float = 0.0
    direction_rad: float = 0.0
    ratio_1x: float = 0.0
    ratio_3x: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "node", _check.integer("misalignment.node", self.node, lo=0))
        checks = {
            "drive_torque_n_m": dict(lo=-1e6, hi=1e6, unit="N·m"),
            "spacer_length_m": dict(lo=0.0, hi=10.0, lo_open=True, unit="m"),
            "offset_m": dict(lo=0.0, hi=0.05, unit="m"),
            "angle_rad": dict(lo=0.0, hi=0.2, unit="rad"),
            "direction_rad": dict(lo=-2 * math.pi, hi=2 * math.pi, unit="rad"),
            "ratio_1x": dict(lo=0.0, hi=1.0, hi_open=True),
            "ratio_3x": dict(lo=0.0, hi=1.0, hi_open=True),
        }
        for name, bounds in checks.items():
            object.__setattr__(self, name, _check.number(f"misalignment.{name}",
                                                         getattr(self, name), **bounds))
        if self.offset_m > 0.25 * self.spacer_length_m:
            raise _check.out_of_range("misalignment.offset_m", self.offset_m,
                                      f"<= spacer_length_m / 4 = "
                                      f"{0.25 * self.spacer_length_m:g} m")

    @property
    def spacer_angle_rad(self) -> float:
        """γ = asin(δ/L): joint B's bend (rad); joint A bends by α₀ + γ."""
        return math.asin(self.offset_m / self.spacer_length_m)

    def loads_at(self, phi) -> np.ndarray:
        """The loads on the rotor at shaft angles ``phi`` (rad), (len(phi), 4): forces
        along y, z (N) and moments about y, z (N·m) (module docstring)."""
        T, L = self.drive_torque_n_m, self.spacer_length_m
        cb, sb = math.cos(self.direction_rad), math.sin(self.direction_rad)
        x, n = np.array([1.0, 0.0, 0.0]), np.array([0.0, cb, sb])
        g, a0 = self.spacer_angle_rad, self.angle_rad
        e_s = math.cos(g) * x - math.sin(g) * n
        e_d = math.cos(a0) * x + math.sin(a0) * n
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        v = np.column_stack([np.zeros_like(phi), np.cos(phi), np.sin(phi)])
        u = np.cross(e_s, v)                 # the spacer's arm (both ends)
        a = np.cross(e_d, u)                 # the drive's arm
        w_a, w_b = np.cross(a, u), np.cross(u, v)
        m_a = T * w_a / (w_a @ e_d)[:, None]
        t_s = m_a @ e_s
        m_b = (t_s / (w_b @ e_s))[:, None] * w_b
        force = -np.cross(e_s, m_a - m_b) / L
        return np.column_stack([force[:, 1], force[:, 2], m_b[:, 1], m_b[:, 2]])

    def lines(self) -> dict[int, np.ndarray]:
        """The loads' complex amplitudes by order k: ``{k: (4,)}`` in the order of
        :data:`COMPONENTS`, the load being Σ_k Re(F_k e^{ikφ}) (N, N·m)."""
        if self.drive_torque_n_m == 0.0 or (self.offset_m == 0.0 and self.angle_rad == 0.0):
            return {}
        phi = 2 * np.pi * np.arange(N_ANGLES) / N_ANGLES
        c = np.fft.fft(self.loads_at(phi), axis=0) / N_ANGLES
        out = {0: c[0].real.astype(complex)}
        out.update({k: 2.0 * c[k] for k in JOINT_ORDERS[1:]})   # mean(Re(F e^{ikφ}) e^{-ikφ}) = F/2
        for k, ratio in ((1, self.ratio_1x), (3, self.ratio_3x)):
            if ratio > 0.0:
                out[k] = ratio * out[2]
        return dict(sorted(out.items()))

    def forces(self, dofs, speed_rad_s: float) -> HarmonicForce:
        """The coupling's loads on the rotor as a :class:`HarmonicForce` at speed Ω
        (``speed_rad_s``, rad/s): forces at the node's y, z and moments at its ry, rz, by
        order (0, 2, 4, and 1, 3 with the calibrations), law "constant". ``dofs``: a model
        (its ``.dofs``) or a :class:`~rubdiag.assembly._dofs.DofMap`."""
        speed = _check.number("speed_rad_s", speed_rad_s, lo=0.0, hi=1e5, lo_open=True)
        dmap = getattr(dofs, "dofs", dofs)
        try:
            idx = [dmap.index(self.node, d) for d in COMPONENTS]
        except ValueError:
            raise ValueError(f"misalignment.node = {self.node} is not a shaft node of the "
                             "model (allowed: a shaft node number)") from None
        rows, amps, orders = [], [], []
        for k, amp in self.lines().items():
            rows += idx
            amps += amp.tolist()
            orders += [k] * len(idx)
        if not rows:
            return HarmonicForce.zero()
        return HarmonicForce(np.array(rows, dtype=np.int64), np.array(amps), speed,
                             order=np.array(orders, dtype=float), law="constant")
