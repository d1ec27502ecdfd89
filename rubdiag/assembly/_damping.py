"""Rayleigh damping coefficients.

C_s = α M + β K gives a mode of frequency ω the damping ratio ξ(ω) = α/(2ω) + βω/2.
Asking for ξ1 at ω1 and ξ2 at ω2 (rad/s) gives the standard formulas

    α = 2 ω1 ω2 (ξ1 ω2 − ξ2 ω1) / (ω2² − ω1²),     β = 2 (ξ2 ω2 − ξ1 ω1) / (ω2² − ω1²).

The study's eqs. (5)-(6) write them with ω in rpm and the two unit factors swapped (60/π
where 2π/60·… belongs and π/15 where 60/π·… belongs); taken literally they give
α ≈ 907 1/s and β ≈ 1.16e-6 s for ξ = 0.04 at 1500 and 5700 rpm, which makes the first mode
overdamped (ξ ≈ 2.9) so that nothing would rub. rubdiag uses the standard formulas
(α ≈ 9.948 1/s, β ≈ 1.061e-4 s for the paper rig).
"""

from __future__ import annotations

from rubdiag import _check

__all__ = ["rayleigh_coefficients"]


def rayleigh_coefficients(omega_1: float, omega_2: float, xi_1: float,
                          xi_2: float) -> tuple[float, float]:
    """(α in 1/s, β in s) giving damping ratio ξ1 at ω1 and ξ2 at ω2 (rad/s, ω1 < ω2).

    Parameters
    ----------
    omega_1, omega_2 : float
        The two reference angular frequencies (rad/s, 0 < ω1 < ω2).
    xi_1, xi_2 : float
        The damping ratios wanted there (0-1).

    Returns
    -------
    alpha : float
        Mass-proportional coefficient α (1/s).
    beta : float
        Stiffness-proportional coefficient β (s).

    Examples
    --------
    The paper rig's ξ = 0.04 at its critical speeds, 1500 and 5700 rpm:

    >>> import math
    >>> w1, w2 = 1500 * math.pi / 30, 5700 * math.pi / 30      # rad/s
    >>> alpha, beta = rayleigh_coefficients(w1, w2, 0.04, 0.04)
    >>> print(f"{alpha:.3f} 1/s, {beta:.4g} s")
    9.948 1/s, 0.0001061 s
    >>> print(f"{alpha / (2 * w1) + beta * w1 / 2:.4f}")
    0.0400
    """
    _check.positive("omega_1", omega_1)
    _check.number("omega_2", omega_2, lo=omega_1, lo_open=True)
    _check.number("xi_1", xi_1, lo=0.0, hi=1.0)
    _check.number("xi_2", xi_2, lo=0.0, hi=1.0)
    denominator = omega_2**2 - omega_1**2
    alpha = 2.0 * omega_1 * omega_2 * (xi_1 * omega_2 - xi_2 * omega_1) / denominator
    beta = 2.0 * (xi_2 * omega_2 - xi_1 * omega_1) / denominator
    return alpha, beta
