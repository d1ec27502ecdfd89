"""A breathing transverse crack in one Timoshenko shaft element, as a nonlinear element.

The cracked section's added compliance
--------------------------------------
A straight-fronted crack of depth a in a solid circular shaft of radius R adds a local
bending flexibility at its section (the strain-energy-release approach of Dimarogonas and
Papadopoulos: Dimarogonas A.D., Papadopoulos C.A., "Vibration of cracked shafts in bending",
J. Sound Vib. 91(4) (1983) 583-593; review: Papadopoulos C.A., "The strain energy release
approach for modeling cracks in rotors: A state of the art review", Mech. Syst. Signal
Process. 22 (2008) 763-789). The crack is cut into strips of width dη along its edge; the
strip at η has height ``h = 2 sqrt(R² - η²)`` and crack depth ``α_max = sqrt(R² - η²) -
(R - a)``, and is a plane-strain edge-cracked strip with Tada's stress-intensity factors
(Tada H., Paris P.C., Irwin G.R., *The Stress Analysis of Cracks Handbook*, 1973), with
``λ = π s / 2``, ``s = α / h``::

    F1(s) = sqrt(tan λ / λ) [0.752 + 2.02 s + 0.37 (1 - sin λ)³] / cos λ   (tension)
    F2(s) = sqrt(tan λ / λ) [0.923 + 0.199 (1 - sin λ)⁴] / cos λ           (bending)

The compliance is ``c = (2 (1 - ν²) / E) ∫∫ (∂K_I / ∂M)² dα dη``:

* ``c55`` — the moment whose stress varies across the depth (moment vector along the crack
  edge, "about the perpendicular" of the crack normal): ``K_I = (M sqrt(R² - η²) / I)
  sqrt(πα) F2(α/h)``, integrated over the whole crack;
* ``c44`` — the moment whose stress varies along the edge (moment vector along the crack
  normal): ``K_I = (M η / I) sqrt(πα) F1(α/h)``, integrated over the half of the crack that
  this moment opens (η > 0; the other half is pressed shut).

``I = π R⁴ / 4``. The integrals are evaluated by Gauss-Legendre quadrature (32 x 32 points:
10 significant digits). Checked (tests/simulation/test_crack.py): in dimensionless form ``c
E R³ / (1 - ν²)`` they reproduce the table ROSS ships as ``ross/faults/data/PAPADOPOULOS.csv``
(attributed there to Papadopoulos 2004, J. Sound Vib. 278, 1205-1211, which we have not seen)
to its 6 digits at a/R = 0.1, 0.2, 0.5, 1 (c55 1.22153 and c44 0.12323 at a/D = 0.25),
and they tend, for a -> 0, to the closed forms of the same integrals with ``F = 1.122``:
``c55 E R³/(1-ν²) -> (256 sqrt(2) / 15π) 1.122² (a/R)^2.5`` and ``c44 E R³/(1-ν²) ->
(256 sqrt(2) / 105π) 1.122² (a/R)^3.5`` (derived here). The coupling c45 of the two bending
moments vanishes by the crack's symmetry about its normal; the shear and axial terms
(c11, c22, c33, c14, c15 of the 6 x 6 matrix) are left out: bending dominates for slender
elements. The approach is linear fracture mechanics for a/D <= 0.5 (deeper cracks: not
allowed).

The cracked element
-------------------
The crack is a hinge of compliance ``C = c55 n nᵀ + c44 t tᵀ`` (n the crack normal, t along
the edge, in the y-z plane) at a distance s from the element's first node. In each bending
plane (deflection v, rotation θ = dv/dx: x-y is (u_y, θ_z), x-z is (u_z, -θ_y); the DOF
order of :func:`rubdiag.assembly._elements.shaft_element`) the element clamped at node 1 and
loaded at node 2 by (P, m) has the flexibility ``G0 = [[L³/(3EI) + L/(κGA), L²/(2EI)],
[L²/(2EI), L/(EI)]]`` (exact for the Timoshenko element under end loads) and the hinge adds
``c [L - s, 1]ᵀ [L - s, 1]`` (the moment at the crack is ``m + P (L - s)`` and a kink Δθ
turns the tip by Δθ and moves it by Δθ (L - s)). The element stiffness is ``T (G0 +
C_plane)⁻¹ Tᵀ`` with the equilibrium map T (node 1 carries ``(-P, -m - P L)``); with C = 0
it is the intact element (to rounding). In the crack's frame (n along y) the planes
decouple: c55 acts in x-y, c44 in x-z. ``ΔK_open = K_cracked - K_intact`` (negative
semidefinite, rotating frame) is what :class:`BreathingCrack` packs; the kernel law
(:mod:`rubdiag._kernels.crack`) turns it with the shaft and scales it by the breathing
function.

The signature
-------------
Under the shaft's weight a breathing crack adds 2x (and a weaker 3x) to the unbalance's 1x.
Gasch (1993, "A survey of the dynamic behaviour of a simple rotating shaft with a transverse
crack", J. Sound Vib. 160(2) 313-332) and the review of Dimarogonas (1996, "Vibration of
cracked structures: a state of the art review", Eng. Fract. Mech. 55(5) 831-857) put its
resonance at half a critical speed, where 2x meets the critical: there a deep crack's 2x is
of the order of 1x or larger, while at the critical speed itself 1x dominates; Bently &
Hatch (2002, "Fundamentals of Rotating Machinery Diagnostics") read it as a forward 2x (a
stiffness loss that turns with the shaft under a fixed load makes a 2x force that turns
with it). tests/simulation/test_crack_signature.py checks all three on ``paper-journal``
(a/D = 0.45 beside the disc: 2x/1x 1.17 at half the first critical speed, 0.009-0.022 at
it, forward).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from rubdiag import _check
from rubdiag._kernels import crack as crack_kernel
from rubdiag.assembly._elements import circular_section
from rubdiag.simulation._elements import Packed

__all__ = ["BreathingCrack", "crack_compliance", "cracked_element_stiffness"]

#: the breathing laws by name, as the kernel codes them
LAWS = {"mayes": crack_kernel.MAYES, "gasch": crack_kernel.GASCH}

_XG, _WG = np.polynomial.legendre.leggauss(32)


def _tada(s: np.ndarray, c0: float, poly) -> np.ndarray:
    lam = 0.5 * np.pi * s
    return np.sqrt(np.tan(lam) / lam) * (c0 + poly(s, lam)) / np.cos(lam)


def _f1(s):
    return _tada(s, 0.752, lambda s, lam: 2.02 * s + 0.37 * (1.0 - np.sin(lam)) ** 3)


def _f2(s):
    return _tada(s, 0.923, lambda s, lam: 0.199 * (1.0 - np.sin(lam)) ** 4)


def crack_compliance(depth_ratio: float, radius: float, E: float, nu: float
                     ) -> tuple[float, float]:
    """``(c44, c55)`` (rad/(N m)): the added bending compliance of a straight-fronted crack
    of depth ``depth_ratio`` x diameter, in (0, 0.5], in a solid shaft of ``radius`` (m),
    Young's modulus ``E`` (Pa) and Poisson's ratio ``nu`` (module docstring). c44: the
    moment about the crack normal; c55: the moment about the perpendicular (the one that
    opens the crack across its depth)."""
    _check.number("depth_ratio", depth_ratio, lo=0.0, hi=0.5, lo_open=True,
                  allowed="in (0, 0.5]")
    R = _check.positive("radius", radius, "m")
    a = 2.0 * R * depth_ratio
    b = math.sqrt(a * (2.0 * R - a))            # half-width of the crack's edge
    inertia = math.pi * R**4 / 4.0
    # strips at η in (-b, b); depth α in (0, α_max(η)): a tensor Gauss rule on both
    eta = b * _XG[:, None]
    half = np.sqrt(R * R - eta * eta)
    alpha_max = half - (R - a)
    alpha = 0.5 * alpha_max * (_XG[None, :] + 1.0)
    weight = (b * _WG[:, None]) * (0.5 * alpha_max * _WG[None, :])
    s = alpha / (2.0 * half)
    g55 = (half / inertia) ** 2 * np.pi * alpha * _f2(s) ** 2
    g44 = (eta / inertia) ** 2 * np.pi * alpha * _f1(s) ** 2
    factor = 2.0 * (1.0 - nu * nu) / E
    c55 = factor * float(np.sum(weight * g55))
    c44 = factor * 0.5 * float(np.sum(weight * g44))   # the tensile half only (η > 0)
    return c44, c55


def _plane_flexibility(length, EI, kGA, compliance, position):
    """The 2 x 2 flexibility of one bending plane, node 1 clamped, (P, m) at node 2."""
    L = length
    G0 = np.array([[L**3 / (3.0 * EI) + L / kGA, L**2 / (2.0 * EI)],
                   [L**2 / (2.0 * EI), L / EI]])
    arm = np.array([L - position * L, 1.0])
    return G0 + compliance * np.outer(arm, arm), arm


def _equilibrium(length):
    """T (4 x 2): the plane's nodal forces (v1, θ1, v2, θ2) of end loads (P, m) at node 2."""
    return np.array([[-1.0, 0.0], [-length, -1.0], [1.0, 0.0], [0.0, 1.0]])


# the 4 plane DOFs (v1, θ1, v2, θ2) of each plane in the element's 8, with θ's sign
_PLANE_DOFS = {"xy": ([0, 3, 4, 7], [1.0, 1.0, 1.0, 1.0]),
               "xz": ([1, 2, 5, 6], [1.0, -1.0, 1.0, -1.0])}


def _scatter(plane: str) -> np.ndarray:
    idx, sign = _PLANE_DOFS[plane]
    S = np.zeros((4, 8))
    S[range(4), idx] = sign
    return S


def _section(diameter, E, nu):
    area, inertia, _, kappa = circular_section(diameter, 0.0, nu)
    return E * inertia, kappa * E / (2.0 * (1.0 + nu)) * area


def cracked_element_stiffness(length, diameter, E, nu, c_xy, c_xz, position):
    """The 8 x 8 stiffness of a solid Timoshenko shaft element with a hinge of compliance
    ``c_xy`` in the x-y plane and ``c_xz`` in the x-z plane (rad/(N m); 0: intact) at
    ``position`` x length from its first node (module docstring)."""
    EI, kGA = _section(diameter, E, nu)
    T = _equilibrium(length)
    K = np.zeros((8, 8))
    for plane, c in (("xy", c_xy), ("xz", c_xz)):
        G, _ = _plane_flexibility(length, EI, kGA, c, position)
        S = _scatter(plane)
        K += S.T @ (T @ np.linalg.solve(G, T.T)) @ S
    return K


def _moment_row(length, diameter, E, nu, position) -> np.ndarray:
    """g (8,): the intact element's bending moment at the crack in the x-y plane, ``M =
    EI v''(s) = g · x`` (N m) for the element's displacements x."""
    EI, kGA = _section(diameter, E, nu)
    G, arm = _plane_flexibility(length, EI, kGA, 0.0, position)
    return arm @ np.linalg.solve(G, _equilibrium(length).T) @ _scatter("xy")


@dataclass(frozen=True, kw_only=True)
class BreathingCrack:
    """A breathing transverse crack in one solid Timoshenko shaft element (module
    docstring; the law: :mod:`rubdiag._kernels.crack`).

    ``element_dofs``: the element's 8 DOFs ``[u_y1, u_z1, θ_y1, θ_z1, u_y2, u_z2, θ_y2, θ_z2]``
    (:meth:`in_rig` finds them); ``length`` (m), ``diameter`` (m, solid), ``youngs_modulus``
    (Pa) and ``poisson_ratio`` of the element; ``depth_ratio`` a/D in (0, 0.5];
    ``position``: the crack's distance from the element's first node, as a fraction of its
    length in [0, 1]; ``law``: ``"mayes"`` or ``"gasch"``; ``angle`` (rad): the crack
    normal's angle from +y towards +z at shaft angle 0 (it turns with the shaft: ψ = φ +
    angle). Mayes's crack is fully open when its normal points along +y, which is the
    tension side when the static load pushes the shaft along +y (add π for a load along
    -y); Gasch's opens whenever the bending moment stretches its mouth.
    """

    element_dofs: tuple
    length: float
    diameter: float
    youngs_modulus: float
    poisson_ratio: float
    depth_ratio: float
    position: float = 0.5
    law: str = "mayes"
    angle: float = 0.0

    kernel: ClassVar = crack_kernel
    impacts: ClassVar[bool] = False     # a smooth stiffness change, no impact

    def __post_init__(self):
        name = "BreathingCrack"
        idx = _check.indices(f"{name}.element_dofs", self.element_dofs)
        if idx.size != 8 or np.any(idx < 0) or np.unique(idx).size != 8:
            raise _check.out_of_range(f"{name}.element_dofs", idx.tolist(),
                                      "8 distinct DOF indices >= 0 (one shaft element)")
        object.__setattr__(self, "element_dofs", tuple(int(i) for i in idx))
        _check.positive(f"{name}.length", self.length, "m")
        _check.positive(f"{name}.diameter", self.diameter, "m")
        _check.positive(f"{name}.youngs_modulus", self.youngs_modulus, "Pa")
        _check.number(f"{name}.poisson_ratio", self.poisson_ratio, lo=-1.0, hi=0.5,
                      lo_open=True, hi_open=True, allowed="in (-1, 0.5)")
        _check.number(f"{name}.depth_ratio", self.depth_ratio, lo=0.0, hi=0.5, lo_open=True,
                      allowed="in (0, 0.5] (linear fracture mechanics: a/D <= 0.5)")
        _check.number(f"{name}.position", self.position, lo=0.0, hi=1.0,
                      allowed="in [0, 1] (fraction of the element's length)")
        _check.choice(f"{name}.law", self.law, LAWS)
        _check.number(f"{name}.angle", self.angle, allowed="a finite angle (rad)")

    @classmethod
    def in_rig(cls, rig, element: int, **crack) -> BreathingCrack:
        """The crack in shaft element ``element`` (0-based, axial order) of ``rig``
        (:class:`rubdiag.model.Rig`): its DOFs, length, diameter and material; ``crack``
        the other fields."""
        from rubdiag.assembly import dof_map

        shaft, material = rig.shaft, rig.material
        _check.integer("element", element, lo=0, hi=shaft.n_elements - 1)
        if shaft.inner_diameters_m[element] > 0.0:
            raise _check.out_of_range(f"Shaft.inner_diameters_m[{element}]",
                                      shaft.inner_diameters_m[element],
                                      "0 (the crack's compliance is for a solid shaft)")
        dofs = dof_map(rig)
        nodes = list(shaft.nodes)
        idx = [dofs.index(nodes[element + k], d) for k in (0, 1)
               for d in ("y", "z", "ry", "rz")]
        return cls(element_dofs=tuple(idx), length=shaft.element_lengths_m[element],
                   diameter=shaft.outer_diameters_m[element],
                   youngs_modulus=material.youngs_modulus_pa,
                   poisson_ratio=material.poisson_ratio, **crack)

    def compliance(self) -> tuple[float, float]:
        """``(c44, c55)`` (rad/(N m)), :func:`crack_compliance`."""
        return crack_compliance(self.depth_ratio, 0.5 * self.diameter, self.youngs_modulus,
                                self.poisson_ratio)

    def _element(self, c_xy: float, c_xz: float) -> np.ndarray:
        return cracked_element_stiffness(self.length, self.diameter, self.youngs_modulus,
                                         self.poisson_ratio, c_xy, c_xz, self.position)

    def stiffness_intact(self) -> np.ndarray:
        """The intact element's 8 x 8 stiffness (N/m, N, N m), from its flexibility."""
        return self._element(0.0, 0.0)

    def stiffness_open(self) -> np.ndarray:
        """The fully open element's stiffness in the crack's frame (normal along y)."""
        c44, c55 = self.compliance()
        return self._element(c55, c44)

    def delta_open(self) -> np.ndarray:
        """``ΔK_open = K_open - K_intact`` in the crack's frame (negative semidefinite)."""
        return self.stiffness_open() - self.stiffness_intact()

    def moment_row(self) -> np.ndarray:
        """g (8,): the bending moment at the crack across its depth, ``M_n = g · x_r``
        (N m) for the element's displacements x_r in the crack's frame."""
        return _moment_row(self.length, self.diameter, self.youngs_modulus,
                           self.poisson_ratio, self.position)

    def pack(self, omega: float, ramp=None) -> Packed:
        par = np.zeros(crack_kernel.N_PAR)
        par[crack_kernel.LAW] = LAWS[self.law]
        par[crack_kernel.ANGLE] = self.angle
        par[crack_kernel.G0:crack_kernel.G0 + 8] = self.moment_row()
        par[crack_kernel.DK0:crack_kernel.DK0 + 64] = self.delta_open().reshape(-1)
        rows = np.column_stack([self.dofs(), -np.ones(8, np.int64)])
        return Packed(crack_kernel.KIND, rows, np.eye(8), par,
                      np.zeros(crack_kernel.N_STATE), False, 0.0)

    def stiffness_ratio(self, w: np.ndarray) -> float:
        return 0.0      # a stiffness loss asks for no smaller step

    def multiplier_stiffness(self, w: np.ndarray, boost: float) -> float:
        return 0.0

    def dofs(self) -> np.ndarray:
        """The element's 8 DOFs."""
        return np.array(self.element_dofs, dtype=np.int64)
