"""The integrator's numerical settings: the :class:`Solver` a user gives, checked."""

from __future__ import annotations

from dataclasses import dataclass

from rubdiag import _check

__all__ = ["Settings", "Solver"]


@dataclass(frozen=True, kw_only=True)
class Solver:
    """The integrator's numerical settings (the defaults suit the study's rig).

    Caveat (measured, see the tests): enforcing the augmented Lagrangian's band within each
    step is a rigid wall at depth ε; with the trapezoidal rule it gives impulsive forces
    and, in sustained contact, force chatter — pure penalty (the default) has none.

    Parameters
    ----------
    gamma : float
        Newmark γ in [0.5, 1], β = (γ + 1/2)² / 4. The default 1/2 is average acceleration
        (second order, no numerical damping, exact energy identity); γ > 1/2 damps the
        highest frequencies (first order; three more sparse products per step; the energy
        residual then holds the numerical dissipation).
    linear_solver : {"sparse", "dense"}
        LU triangular solves, or a product with K_eff's inverse (for small dense systems
        such as a reduced model).
    max_newton : int
        The element solve's Newton iterations per step (>= 0).
    newton_tol : float
        The element solve's tolerance (m, > 0).
    max_augment : int
        The augmented Lagrangian's multiplier updates per step (>= 0).
    augment_boost : float
        In [0, 1]. 0: the study's eq. (2) literally, creeping into the band; > 0: ``λ <-
        max(0, λ - (k_N + boost / W_ee)(g + 0.98 ε))``, a few updates.
    augment_strict : bool
        A step whose multipliers miss the band fails (False: it is accepted and counted).
    gap_jump : float
        A step in which an element closes deeper than this (m, > 0) is retried at half the
        step.
    contact_stiffness_ratio : float or None
        An engaged element allows a step only when its step requirement holds (for a
        contact ``k_N W_ee <= ratio``, ``W_ee`` its diagonal of ``B K_eff⁻¹ Bᵀ``, about
        ``(ω_c h)² / 4`` for a lumped mass; the default 0.25 brought the energy residual
        of the stiff robustness corners from 110–190 % to below 1 %). None: off.
    grow_after : int
        Accepted steps at one level before the step doubles again (>= 1).
    episode_capacity : int
        The episode log's first size (>= 1; it grows as needed).
    step_error : float or None
        The local error tolerance of steps longer than dt (``TimeGrid.dt_max``), relative
        to the largest recorded displacement at the last recorded sample (> 0; None: off).
        The estimate is Zienkiewicz and Xie's (1991), ``(β - 1/6) h² (a_{n+1} - a_n)``,
        largest over the recorded and sensor DOFs and the impact elements' local
        coordinates; a long step above the tolerance is retried shorter, and the step
        doubles past dt only when the estimate is below 0.7/8 of it (the estimate grows as
        h³).
    """

    gamma: float = 0.5
    linear_solver: str = "sparse"
    max_newton: int = 25
    newton_tol: float = 1e-12
    max_augment: int = 10000
    augment_boost: float = 0.0
    augment_strict: bool = True
    gap_jump: float = 1e-5
    contact_stiffness_ratio: float | None = 0.25
    grow_after: int = 8
    episode_capacity: int = 4096
    step_error: float | None = None


@dataclass(frozen=True)
class Settings:
    """A :class:`Solver`'s settings checked, with the shaft speed the elements see."""

    omega: float
    gamma: float
    max_newton: int
    max_augment: int
    grow_after: int
    newton_tol: float
    augment_boost: float
    augment_strict: bool
    gap_jump: float
    contact_stiffness_ratio: float | None
    episode_capacity: int
    step_error: float
    dense: bool

    @property
    def beta(self) -> float:
        """Newmark β = (γ + 1/2)² / 4."""
        return 0.25 * (self.gamma + 0.5) ** 2

    @classmethod
    def checked(cls, solver: Solver, omega) -> Settings:
        """``solver``'s settings at shaft speed ``omega`` (rad/s), checked: a bad value
        raises ``ValueError`` naming the field and its allowed range."""
        if not isinstance(solver, Solver):
            raise _check.wrong_type("solver", type(solver).__name__, "a Solver or None")
        ratio = solver.contact_stiffness_ratio
        return cls(
            omega=_check.number("omega", omega),
            gamma=_check.number("gamma", solver.gamma, lo=0.5, hi=1.0),
            max_newton=_check.integer("max_newton", solver.max_newton, lo=0),
            max_augment=_check.integer("max_augment", solver.max_augment, lo=0),
            grow_after=_check.integer("grow_after", solver.grow_after, lo=1),
            newton_tol=_check.number("newton_tol", solver.newton_tol, lo=0.0, lo_open=True),
            augment_boost=_check.number("augment_boost", solver.augment_boost, lo=0.0, hi=1.0),
            augment_strict=bool(solver.augment_strict),
            gap_jump=_check.number("gap_jump", solver.gap_jump, lo=0.0, lo_open=True),
            contact_stiffness_ratio=None if ratio is None else _check.number(
                "contact_stiffness_ratio", ratio, lo=0.0, lo_open=True),
            episode_capacity=_check.integer("episode_capacity", solver.episode_capacity,
                                            lo=1),
            step_error=0.0 if solver.step_error is None else _check.number(
                "step_error", solver.step_error, lo=0.0, lo_open=True,
                allowed="finite and > 0 (relative), or None"),
            dense=_check.choice("linear_solver", solver.linear_solver,
                                ("sparse", "dense")) == "dense",
        )
