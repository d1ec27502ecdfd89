"""Benchmark of the contact time-integration kernel on a 412-DOF rig-like system.

Builds ``bladed_rotor_casing`` of ``tests/testsystems.py`` (shaft + 16 blades + 40-node
casing ring, 8 point contacts, rotating unbalance near the first critical speed, gap 0.6x the
linear tip amplitude), starts from the linear steady state with the gap ramped down, runs into
rub, then times repeated runs that continue from the rubbing state.

Usage::

    PYTHONPATH=. .venv/bin/python benchmarks/bench_kernel.py [--dt 1e-5] [--duration 0.05]
        [--repeat 5] [--fixed]

Prints the median kernel µs per step (the rubbing segment), steps/s, the share of steps with
at least one closed contact, step-level counts and Newton statistics.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np

from rubdiag.simulation import LinearSystem, Recording, TimeGrid, simulate_system

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))  # the tests' systems
from testsystems import bladed_rotor_casing, linear_response


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt", type=float, default=1e-5)
    ap.add_argument("--duration", type=float, default=0.05, help="timed segment (s)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--fixed", action="store_true", help="fixed step")
    ap.add_argument("--mu", type=float, default=0.3)
    ap.add_argument("--gap-fraction", type=float, default=0.3,
                    help="gap as a fraction of the linear radial tip amplitude")
    args = ap.parse_args()

    sysm = bladed_rotor_casing(mu=args.mu, gap_fraction=args.gap_fraction)
    u = linear_response(sysm.M, sysm.C, sysm.K, sysm.force)
    q0 = u.real.copy()
    v0 = (1j * sysm.speed * u).real
    tips = sysm.tip_dofs
    amp = float(np.abs(u[tips[:, 0]]).max())
    recording = Recording(record_dofs=[sysm.disc_dofs[0], int(tips[0, 0]),
                                       int(sysm.casing_dofs[0, 0])])

    def grid(duration):
        return TimeGrid(duration=duration, dt=args.dt, fixed_step=args.fixed,
                        output_dt=10 * args.dt)

    def system(q0, v0, a0=None):
        return LinearSystem(M=sysm.M, C=sysm.C, K=sysm.K, force=sysm.force, q0=q0, v0=v0,
                            a0=a0, omega=sysm.speed)

    gaps = [c.gap for c in sysm.contacts]
    print(
        f"system: n = {sysm.n}, nnz(K) = {sysm.K.nnz}, nnz(M) = {sysm.M.nnz}, "
        f"n_c = {len(sysm.contacts)}, gap = {gaps[0] * 1e6:.1f} µm, "
        f"linear tip amplitude = {amp * 1e6:.1f} µm, speed = {sysm.speed:.0f} rad/s"
    )
    # warm-up (compiles or loads the cache) and run into rub: ramp the gap over 0.02 s
    t0 = time.perf_counter()
    warm = simulate_system(system(q0, v0), sysm.contacts, grid(0.06), recording,
                           gap_ramp=(0.02, max(1.2 * amp, max(gaps))))
    print(f"warm-up run (incl. compile/cache load): {time.perf_counter() - t0:.2f} s; "
          f"lu nnz per level {warm.extra['lu_nnz']} ({warm.extra['lu_ordering'][0]})")
    rubbing = []
    for _ in range(args.repeat):
        res = simulate_system(system(warm.q_final, warm.v_final, warm.a_final),
                              sysm.contacts, grid(args.duration), recording)
        us = res.extra["kernel_seconds"] / res.n_steps * 1e6
        rubbing.append((us, res))
    med = statistics.median(r[0] for r in rubbing)
    res = rubbing[0][1]
    closed = res.time_in_status[:, 1:].sum(axis=1) / res.t_final
    any_closed = 1.0 - np.prod(1.0 - np.minimum(closed, 1.0))
    print(f"timed segment: {args.duration} s simulated, {res.n_steps} steps, "
          f"rejected {res.n_rejected_newton} (Newton) + {res.n_rejected_abrupt} (abrupt)")
    print(f"steps per level {res.steps_per_level.tolist()} (dt levels {res.dt_levels.tolist()})")
    print(f"contact time share per element: {np.round(closed, 3).tolist()} "
          f"(~{any_closed:.2f} of the time at least one closed, independence estimate)")
    print(f"episodes: {len(res.episodes)}, max F_N = {res.max_normal_force.max():.1f} N, "
          f"Newton iterations {res.newton_iterations} (max {res.newton_iterations_max}/step)")
    print(f"setup (factorizations) {res.extra['setup_seconds'] * 1e3:.1f} ms per run")
    print(f"kernel µs/step (runs): {[round(r[0], 2) for r in rubbing]}")
    print(f"MEDIAN kernel time per step while rubbing: {med:.2f} µs  "
          f"({1e6 / med:,.0f} steps/s; real-time factor at dt: {args.dt / (med * 1e-6):.2f})")


if __name__ == "__main__":
    main()
