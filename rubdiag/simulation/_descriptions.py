"""What :func:`~rubdiag.simulation._system.simulate_system` integrates, as described objects.

A run of the integrator is ``simulate_system(system, elements, grid, outputs, solver=...,
gap_ramp=...)``:

* :class:`LinearSystem` — ``M q'' + C q' + K q = f(t)`` plus the element forces, its start
  state and the shaft's speed;
* the nonlinear elements — a :class:`~rubdiag.simulation.Contacts` or a sequence of element
  descriptions (:mod:`rubdiag.simulation._elements`);
* :class:`TimeGrid` — how long, with which steps, sampled how often;
* :class:`Recording` — what is recorded and reported;
* :class:`Solver` — the numerical settings (defaults suit the study's rig).

Every field is in SI units; the values are checked when the run starts (against the system
they belong to) and a wrong one raises ``ValueError`` naming it and its allowed range.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import numpy as np

from rubdiag.simulation._loads import HarmonicForce
from rubdiag.simulation._speed_profile import SpeedProfile

__all__ = ["LinearSystem", "Recording", "Solver", "TimeGrid", "legacy_call"]


@dataclass(frozen=True, kw_only=True)
class LinearSystem:
    """``M q'' + C q' + K q = f(t) + Σ_e B_eᵀ p_e``, where it starts and how fast it spins.

    ``M``, ``C``, ``K`` (n, n), sparse or dense: mass (kg), damping (N s/m; damping + Ω G,
    constant) and stiffness (N/m). M must be nonsingular; the energy ledger assumes M and K
    symmetric (C may carry a skew gyroscopic part, which does no work). ``force``: the
    external load (:class:`~rubdiag.simulation._loads.HarmonicForce`, N; None: none). ``q0``,
    ``v0`` (n,): the start state (m, m/s); ``a0`` (n,) the start acceleration (m/s²; None:
    from equilibrium, ``M a0 = f(0) + Bᵀp(q0) - C v0 - K q0``). ``omega``: the shaft speed
    Ω (rad/s: the surface speed Ω R of annular clearances). ``gyroscopic`` (n, n): the
    unit-speed gyroscopic matrix G (N s/m per rad/s), with ``speed_profile``: a spin speed
    that changes in time (:mod:`rubdiag.simulation._speed_profile`; the damping is then ``C +
    Ω(t) G`` with C without the gyroscopic part, the load rotates with the shaft angle and
    its ``omega`` must be the profile's start speed). Ω(t) G is held at a reference speed
    over stretches in which Ω stays within ``speed_tolerance`` of it (relative, in (0,
    0.5]; 0: a stretch per largest step). ``recovery`` (n_phys, n): the coordinates are
    generalised (a reduced model) and the physical displacements are ``recovery @ q``.
    """

    M: object
    C: object
    K: object
    force: HarmonicForce | None = None
    q0: np.ndarray | None = None
    v0: np.ndarray | None = None
    a0: np.ndarray | None = None
    omega: float = 0.0
    gyroscopic: object = None
    speed_profile: SpeedProfile | None = None
    speed_tolerance: float = 0.005
    recovery: np.ndarray | None = None

    def start(self) -> tuple[np.ndarray, np.ndarray]:
        """``(q0, v0)``, zeros where not given."""
        n = self.M.shape[0]
        return (np.zeros(n) if self.q0 is None else self.q0,
                np.zeros(n) if self.v0 is None else self.v0)


@dataclass(frozen=True, kw_only=True)
class TimeGrid:
    """The run's length and steps (s).

    ``duration``: simulated time, at least one step; the run ends at ``N dt`` with ``N =
    floor(duration / dt)`` (``round`` when within 1e-9 of an integer). ``dt``: the largest
    (and first) step. ``dt_min``: the smallest step, in (0, dt]; the steps are ``dt / 2^k``
    down to the largest such value >= dt_min (default ``dt / 64``). ``fixed_step``: a
    constant step ``dt`` (for convergence studies): nothing is halved, and an element solve
    that fails stops the run. ``output_dt``: the interval of the recorded samples, a
    positive integer multiple of dt (default dt); samples are exact states at step ends.
    ``dt_max``: steps longer than dt, up to ``2^k dt`` (k <= 3; default dt: none), where
    the local error estimate stays within ``Solver.step_error`` and every element that can
    close on impact (a contact, a pedestal's seat) is open and not about to close: dt
    stays the step of every closed contact, and the sensor stream's interval (filled in
    within a long step by cubic Hermite interpolation); a long step ends at every recorded
    sample.
    """

    duration: float
    dt: float
    dt_min: float | None = None
    fixed_step: bool = False
    output_dt: float | None = None
    dt_max: float | None = None


@dataclass(frozen=True, kw_only=True)
class Recording:
    """What a run records and reports.

    ``record_dofs``: the DOFs whose displacements are sampled every ``output_dt`` (default
    all; physical DOFs of a reduced model). ``sensor_dofs``: the DOFs whose displacement,
    velocity and acceleration (the integrator's state) are recorded at every multiple of dt,
    the raw stream sensors are filtered from (default none). ``progress(t, duration)``:
    called about 100 times during the run. ``profile``: count the CPU cycles of each
    section of a step (``extra['profile_cycles']``; the results are the same bits).
    ``raise_on_failure``: a failed run raises :class:`~rubdiag.simulation._result.
    SimulationDiverged` carrying the partial result (False: the partial result is returned
    with ``status != 0``).
    """

    record_dofs: Sequence[int] | np.ndarray | None = None
    sensor_dofs: Sequence[int] | np.ndarray | None = None
    progress: Callable[[float, float], None] | None = None
    profile: bool = False
    raise_on_failure: bool = True


@dataclass(frozen=True, kw_only=True)
class Solver:
    """The integrator's numerical settings.

    ``gamma``: Newmark γ in [0.5, 1], β = (γ + 1/2)² / 4. The default 1/2 is average
    acceleration (second order, no numerical damping, exact energy identity); γ > 1/2 damps
    the highest frequencies (first order; three more sparse products per step; the energy
    residual then holds the numerical dissipation). ``linear_solver``: ``"sparse"`` (LU
    triangular solves) or ``"dense"`` (a product with K_eff's inverse, for small dense
    systems such as a reduced model). ``max_newton`` (>= 0) and ``newton_tol`` (m, > 0):
    the element solve's Newton iterations and tolerance. ``max_augment`` (>= 0),
    ``augment_boost`` (in [0, 1]) and ``augment_strict``: the augmented Lagrangian's updates
    per step, their boost (0: the study's eq. (2) literally, creeping into the band; > 0:
    ``λ <- max(0, λ - (k_N + boost / W_ee)(g + 0.98 ε))``, a few updates) and whether a
    step whose multipliers miss the band fails (else it is accepted and counted). Caveat
    (measured, see the tests): enforcing the band within each step is a rigid wall at depth
    ε; with the trapezoidal rule it gives impulsive forces and, in sustained contact, force
    chatter — pure penalty (the default) has none. ``gap_jump`` (m): a step in which an
    element closes deeper than this is retried at half the step. ``contact_stiffness_ratio``
    (None: off): an engaged element allows a step only when its step requirement holds (for
    a contact ``k_N W_ee <= ratio``, ``W_ee`` its diagonal of ``B K_eff⁻¹ Bᵀ``, about ``(ω_c
    h)² / 4`` for a lumped mass; the default 0.25 brought the energy residual of the stiff
    robustness corners from 110–190 % to below 1 %). ``grow_after`` (>= 1): accepted steps
    at one level before the step doubles again. ``episode_capacity`` (>= 1): the episode
    log's first size (it grows as needed). ``step_error`` (> 0; None: off): the local error
    tolerance of steps longer than dt (``TimeGrid.dt_max``), relative to the largest
    recorded displacement at the last recorded sample. The estimate is Zienkiewicz and
    Xie's (1991), ``(β - 1/6) h² (a_{n+1} - a_n)``, largest over the recorded and sensor
    DOFs and the impact elements' local coordinates; a long step above the tolerance is
    retried shorter, and the step doubles past dt only when the estimate is below 0.7/8 of
    it (the estimate grows as h³).
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


def _owners() -> dict[str, type]:
    owners = {}
    for cls in (LinearSystem, TimeGrid, Recording, Solver):
        owners.update({f.name: cls for f in fields(cls)})
    return owners


def legacy_call(M, C, K, force, contacts, q0, v0, **options):
    """The described objects of the old call ``simulate_system(M, C, K, force, contacts,
    q0, v0, duration=..., dt=..., ...)``: each keyword is the field of the same name of one
    of the objects, ``gap_ramp`` the function's own. Returns ``(system, elements, grid,
    outputs, solver, gap_ramp)``."""
    owners = _owners()
    gap_ramp = options.pop("gap_ramp", None)
    unknown = sorted(set(options) - set(owners))
    if unknown:
        raise TypeError(f"simulate_system() got an unexpected keyword argument {unknown[0]!r}")
    groups = {cls: {} for cls in (LinearSystem, TimeGrid, Recording, Solver)}
    for name, value in options.items():
        groups[owners[name]][name] = value
    if "duration" not in options or "dt" not in options:
        missing = "duration" if "duration" not in options else "dt"
        raise TypeError(f"simulate_system() missing required keyword argument {missing!r}")
    system = LinearSystem(M=M, C=C, K=K, force=force, q0=q0, v0=v0, **groups[LinearSystem])
    return (system, contacts, TimeGrid(**groups[TimeGrid]), Recording(**groups[Recording]),
            Solver(**groups[Solver]), gap_ramp)
