"""Result types of :func:`rubdiag.simulation.simulate_system`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:   # pandas is loaded by to_frame only: a run does not need it (0.4 s)
    import pandas as pd

__all__ = ["EpisodeLog", "SimulationDiverged", "StatusLog", "SystemResult"]

STATUS_MESSAGES = {
    0: "The simulation reached the requested duration.",
    1: "The contact iteration did not converge at the smallest step.",
    2: "The state became non-finite.",
}


@dataclass(frozen=True)
class EpisodeLog:
    """Contact episodes gathered at every step (not only at recorded samples).

    An episode is a contiguous run of closed status (2 sliding or 3 sticking) of one element.
    One row per episode, in the order the episodes ended (episodes still closed when the run
    stopped come last, with ``complete = False`` and ``t_end`` = the final time).

    Fields (all shape (n_episodes,)): ``element`` (int, contact element number, 1-based as
    everywhere public), ``t_start``, ``t_end``
    (s; the instants where the normal trial force ``lam - k_N g`` crosses zero, linearly
    interpolated inside the closing/opening step), ``n_steps`` (closed steps),
    ``peak_normal_force`` (N, largest end-of-step F_N of the episode), ``n_slide_entries``,
    ``n_stick_entries`` (entries into status 2 / 3 within the episode, the first closed step
    included), ``slide_time``, ``stick_time`` (s, summed step lengths whose end-of-step
    status is 2 / 3), ``slide_impulse``, ``stick_impulse`` (N s, ∫F_N dt over those steps),
    ``complete`` (bool).

    Parameters
    ----------
    element, t_start, t_end, n_steps, peak_normal_force : numpy.ndarray
        The fields above.
    n_slide_entries, n_stick_entries, slide_time, stick_time : numpy.ndarray
        The fields above.
    slide_impulse, stick_impulse, complete : numpy.ndarray
        The fields above.
    """

    element: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray
    n_steps: np.ndarray
    peak_normal_force: np.ndarray
    n_slide_entries: np.ndarray
    n_stick_entries: np.ndarray
    slide_time: np.ndarray
    stick_time: np.ndarray
    slide_impulse: np.ndarray
    stick_impulse: np.ndarray
    complete: np.ndarray

    def __len__(self) -> int:
        return int(self.element.size)

    @property
    def duration(self) -> np.ndarray:
        """Episode durations (s)."""
        return self.t_end - self.t_start

    def to_frame(self) -> pd.DataFrame:
        """One row per episode."""
        import pandas as pd

        return pd.DataFrame(
            {
                "element": self.element,
                "t_start": self.t_start,
                "t_end": self.t_end,
                "duration": self.duration,
                "n_steps": self.n_steps,
                "peak_normal_force": self.peak_normal_force,
                "n_slide_entries": self.n_slide_entries,
                "n_stick_entries": self.n_stick_entries,
                "slide_time": self.slide_time,
                "stick_time": self.stick_time,
                "slide_impulse": self.slide_impulse,
                "stick_impulse": self.stick_impulse,
                "complete": self.complete,
            }
        )


@dataclass(frozen=True)
class StatusLog:
    """Status segments gathered at every step: what the contact-status panel draws.

    A segment is a maximal run of one closed status (2 sliding or 3 sticking) of one element;
    the segments of an episode tile it without gaps. Each step counts with its end-of-step
    status, so a change of status inside an episode happens at a step boundary; the first and
    last segment of an episode start and end at the episode's interpolated ``t_start`` and
    ``t_end``. Segments still running when the run stopped end at the final time.

    Fields (all shape (n_segments,)): ``element`` (int, contact element number from 1),
    ``status`` (int8, 2 sliding / 3 sticking), ``t_start``, ``t_end`` (s).
    """

    element: np.ndarray
    status: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray

    def __len__(self) -> int:
        return int(self.element.size)

    def to_frame(self) -> pd.DataFrame:
        """One row per segment, in the order the segments ended."""
        import pandas as pd

        return pd.DataFrame({"element": self.element, "status": self.status,
                             "t_start": self.t_start, "t_end": self.t_end})


@dataclass(frozen=True)
class SystemResult:
    """Everything a run of :func:`simulate_system` computed (also when it failed).

    Samples (``n_out`` rows at ``t = k * output_dt``, exact: sample times are step ends):

    * ``t`` (n_out,) s; ``q`` (n_out, n_rec) m, displacements of ``record_dofs``.
    * ``contact_fn`` (n_out, n_c) N, normal force F_N >= 0; ``contact_ft`` (n_out, n_c) N,
      signed tangential force on body a along the element tangent; ``contact_status``
      (n_out, n_c) int8, 1 open / 2 sliding / 3 sticking; ``contact_gap`` (n_out, n_c) m
      (negative = penetration); ``contact_slip`` (n_out, n_c) m, relative tangential
      displacement s (kind 1: ``t.(u_a - u_b)``; kind 2: accumulated slip while closed,
      surface travel included).
    * Energy ledger (n_out,) J, cumulative from t = 0: ``work_external`` (work of f(t),
      trapezoid on the step — exact for Newmark), ``work_drive`` (work of prescribed motions on
      the contacts: the shaft drive through kind-2 friction, ``-F_T Ω R h`` per step, and
      the gap ramp, ``-F̄_N Δg0``), ``dissipated_viscous`` (``h v̄ᵀ C v̄`` per step),
      ``dissipated_friction`` (``|F_T| |Δ plastic slip|`` per sliding step, never negative),
      ``contact_algorithmic`` (contact work not accounted for by the contact elastic energy
      and friction: the penalty/trapezoid impact error and augmentation jumps). State
      energies: ``kinetic`` (½ vᵀMv), ``strain`` (½ qᵀKq), ``contact_elastic``
      (Σ ½F_N²/k_N + ½F_T²/k_T over closed elements).
      Exact discrete identity: work_external + work_drive = Δ(kinetic + strain +
      contact_elastic) + dissipated_viscous + dissipated_friction + contact_algorithmic.

    Gathered at every step: ``episodes`` (:class:`EpisodeLog`), ``status_segments``
    (:class:`StatusLog`); per element (n_c, 3) with
    columns status 1, 2, 3: ``time_in_status`` (s), ``normal_impulse`` (N s, ∫F_N dt),
    ``tangential_impulse`` (N s, ∫|F_T| dt) — each step is attributed to its end-of-step
    status; running maxima (n_c,): ``max_normal_force`` (N), ``max_tangential_force`` (N),
    ``max_penetration`` (m, 0 if never closed); ``max_cone_excess`` (N): max of
    ``|F_T| - mu F_N`` over all steps and elements (≤ round-off if the law holds).

    Step control: ``dt_levels`` (n_lev,) s, the step sizes dt_max/2^k (dt_max = dt unless
    long steps were allowed: ``TimeGrid.dt_max``); ``steps_per_level``
    (n_lev,) accepted steps per level; ``level_change_t`` (s), ``level_change_level`` — every
    change of level (the time at which the new level starts and the new level index);
    ``n_steps`` accepted steps; ``n_rejected_newton`` / ``n_rejected_abrupt`` rejected steps
    (contact iteration failed / abrupt closing), ``n_rejected_error`` long steps rejected by
    the local error estimate; ``n_abrupt_at_min`` abrupt closings accepted at
    the smallest step; ``newton_iterations`` (total) and ``newton_iterations_max`` (per step);
    ``augment_iterations`` / ``augment_iterations_max`` (multiplier updates).

    Final state: ``t_final`` (s), ``q_final``, ``v_final``, ``a_final`` (n,).
    Sensor stream (empty unless ``sensor_dofs`` were given): ``sensor_dofs`` (n_s,),
    ``sensor_dt`` (s, = dt), ``sensor_q``, ``sensor_v``, ``sensor_a`` (n_sen, n_s):
    displacement, velocity and acceleration at ``t = k sensor_dt`` from the integrator.
    ``extra``: diagnostics (``setup_seconds``, ``kernel_seconds`` wall times, ``lu_nnz`` and
    ``lu_ordering`` of the factorization per level).
    Outcome: ``status`` (0 success, 1 no convergence at the smallest step, 2 non-finite state),
    ``message``, ``failure_time`` (s, NaN on success), ``failure_element`` (contact element number
    from 1, or 0 when no contact element is to blame).

    Parameters
    ----------
    t, record_dofs, q : numpy.ndarray
        Sample times (s), the recorded DOFs and their displacements (m).
    contact_fn, contact_ft, contact_status, contact_gap, contact_slip : numpy.ndarray
        The contact samples (above).
    work_external, work_drive, dissipated_viscous, dissipated_friction : numpy.ndarray
        The energy ledger's works and dissipations (J, above).
    contact_algorithmic, kinetic, strain, contact_elastic : numpy.ndarray
        The energy ledger's algorithmic term and state energies (J, above).
    episodes : EpisodeLog
        Every contact episode.
    status_segments : StatusLog
        Every element's stretches of constant status.
    time_in_status, normal_impulse, tangential_impulse : numpy.ndarray
        Per element and status (above).
    max_normal_force, max_tangential_force, max_penetration : numpy.ndarray
        Per element running maxima (N, N, m).
    max_cone_excess : float
        Largest ``|F_T| - mu F_N`` (N).
    dt, dt_min, output_dt : float
        The largest and the smallest step, and the output interval (s).
    dt_levels, steps_per_level, level_change_t, level_change_level : numpy.ndarray
        Step control (above).
    n_steps, n_rejected_newton, n_rejected_abrupt, n_abrupt_at_min : int
        Step counts (above).
    newton_iterations, newton_iterations_max, augment_iterations, augment_iterations_max : int
        Iteration counts (above).
    t_final : float
        Final time (s).
    q_final, v_final, a_final : numpy.ndarray
        Final displacements (m), velocities (m/s) and accelerations (m/s²), every DOF.
    status : int
        0 success, 1 no convergence at the smallest step, 2 non-finite state.
    message : str
        What happened.
    failure_time : float
        When the run failed (s); NaN on success.
    failure_element : int
        The contact element to blame (from 1), or 0.
    sensor_dofs, sensor_q, sensor_v, sensor_a : numpy.ndarray
        The sensor stream (above).
    sensor_dt : float
        Its interval (s).
    n_rejected_error : int
        Long steps rejected by the error estimate.
    extra : dict
        Diagnostics (above).
    """

    t: np.ndarray
    record_dofs: np.ndarray
    q: np.ndarray
    contact_fn: np.ndarray
    contact_ft: np.ndarray
    contact_status: np.ndarray
    contact_gap: np.ndarray
    contact_slip: np.ndarray
    work_external: np.ndarray
    work_drive: np.ndarray
    dissipated_viscous: np.ndarray
    dissipated_friction: np.ndarray
    contact_algorithmic: np.ndarray
    kinetic: np.ndarray
    strain: np.ndarray
    contact_elastic: np.ndarray
    episodes: EpisodeLog
    status_segments: StatusLog
    time_in_status: np.ndarray
    normal_impulse: np.ndarray
    tangential_impulse: np.ndarray
    max_normal_force: np.ndarray
    max_tangential_force: np.ndarray
    max_penetration: np.ndarray
    max_cone_excess: float
    dt: float
    dt_min: float
    output_dt: float
    dt_levels: np.ndarray
    steps_per_level: np.ndarray
    level_change_t: np.ndarray
    level_change_level: np.ndarray
    n_steps: int
    n_rejected_newton: int
    n_rejected_abrupt: int
    n_abrupt_at_min: int
    newton_iterations: int
    newton_iterations_max: int
    augment_iterations: int
    augment_iterations_max: int
    t_final: float
    q_final: np.ndarray
    v_final: np.ndarray
    a_final: np.ndarray
    status: int
    message: str
    failure_time: float = float("nan")
    failure_element: int = 0
    sensor_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    sensor_dt: float = float("nan")
    sensor_q: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    sensor_v: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    sensor_a: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    n_rejected_error: int = 0
    extra: dict = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def mechanical_energy(self) -> np.ndarray:
        """kinetic + strain + contact elastic energy at the samples (J)."""
        return self.kinetic + self.strain + self.contact_elastic

    @property
    def energy_balance_residual(self) -> np.ndarray:
        """External + drive work − Δ(mechanical energy) − viscous − friction dissipation (J).

        Equals ``contact_algorithmic`` up to round-off; its size measures how well the contact
        events are resolved in time.
        """
        e = self.mechanical_energy
        return (
            self.work_external + self.work_drive - (e - e[0])
            - self.dissipated_viscous - self.dissipated_friction
        )

    def to_frame(self) -> pd.DataFrame:
        """Samples as a DataFrame indexed by ``t``: ``q_<dof>`` then ``fn_<k>``, ``ft_<k>``,
        ``status_<k>``, ``gap_<k>``, ``slip_<k>`` per contact element k = 1…, then the
        energies."""
        import pandas as pd

        cols: dict[str, np.ndarray] = {}
        for j, dof in enumerate(self.record_dofs):
            cols[f"q_{int(dof)}"] = self.q[:, j]
        for e in range(self.contact_fn.shape[1]):
            k = e + 1
            cols[f"fn_{k}"] = self.contact_fn[:, e]
            cols[f"ft_{k}"] = self.contact_ft[:, e]
            cols[f"status_{k}"] = self.contact_status[:, e]
            cols[f"gap_{k}"] = self.contact_gap[:, e]
            cols[f"slip_{k}"] = self.contact_slip[:, e]
        for name in (
            "work_external", "work_drive", "dissipated_viscous", "dissipated_friction",
            "contact_algorithmic", "kinetic", "strain", "contact_elastic",
        ):
            cols[name] = getattr(self, name)
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))


class SimulationDiverged(RuntimeError):
    """A run stopped before its end; ``result`` holds everything computed up to then.

    Parameters
    ----------
    message : str
        Why the run stopped.
    result : SystemResult
        The run up to the failure.
    """

    def __init__(self, message: str, result: SystemResult):
        super().__init__(message)
        self.result = result

    def __reduce__(self):
        # picklable with its partial result, so it crosses process boundaries (table2 workers)
        return type(self), (str(self), self.result)
