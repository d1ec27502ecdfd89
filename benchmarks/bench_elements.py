"""What each kind of nonlinear element costs per time step, on the paper rig (full model).

Runs case 1 at 750 rpm (half the first critical speed) far from the casing with gravity,
once without any element and once with each fault (a breathing crack by each law, a
misaligned coupling: loads only); and case 1 at the first critical speed with rub (the 8
point contacts) beside the same run without contacts, for scale; and the paper rig with
bearing 0 on a pedestal at twice the first critical speed, linear and loose (lifting off);
and the paper rig on two plain journal bearings (R 5 mm, L 4 mm, c 30 um, 0.01 Pa s, the
weight each carries) at 750 rpm with gravity, beside the first run. Prints the kernel's µs per
step (median of ``--repeat`` runs) and the difference to the first run.

Usage::

    .venv/bin/python benchmarks/bench_elements.py [--repeat 5] [--duration 0.2]
"""

from __future__ import annotations

import argparse
import os
import statistics

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import dataclasses

from rubdiag.model import Bearing, JournalFilm, Pedestal, paper_rig
from rubdiag.simulation import Run, simulate
from rubdiag.simulation._faults import Crack, Faults, Looseness
from rubdiag.simulation._misalignment import Misalignment
from rubdiag.simulation._static_load import StaticLoad

GRAVITY = StaticLoad(direction="y", gravity_m_s2=-9.81)


def cases(duration: float) -> dict[str, Run]:
    base = dict(speed_rpm=750.0, duration_s=duration, discard_s=0.0, static_load=GRAVITY)
    coupling = Misalignment(node=3, drive_torque_n_m=20.0, spacer_length_m=0.05,
                            offset_m=5e-4)
    rig = paper_rig()       # bearing 0 on a 20 kg pedestal (tests/simulation/test_looseness…)
    seat = Pedestal(mass_kg=20.0, k_y_n_m=2e7, k_z_n_m=2e7, c_y_ns_m=500.0, c_z_ns_m=500.0)
    pedestal = dataclasses.replace(
        rig, bearings=(dataclasses.replace(rig.bearings[0], pedestal=seat), *rig.bearings[1:]))
    fast = dict(speed_rpm=2999.0, duration_s=duration, discard_s=0.0)
    # the weight each bearing of the paper rig carries (N; the casing supports the rest)
    films = dataclasses.replace(rig, bearings=tuple(
        Bearing(b.node, 0.0, 0.0, journal=JournalFilm(0.01, 0.005, 0.004, 30e-6, load))
        for b, load in zip(rig.bearings, (7.42, 6.90), strict=True)))
    return {
        "no element": Run.paper_case(1, None, **base),
        "crack (Mayes)": Run.paper_case(1, None, faults=Faults(
            crack=Crack(element=10, depth_ratio=0.4)), **base),
        "crack (Gasch)": Run.paper_case(1, None, faults=Faults(
            crack=Crack(element=10, depth_ratio=0.4, law="gasch")), **base),
        "misalignment (loads)": Run.paper_case(1, None, faults=Faults(misalignment=coupling),
                                               **base),
        "2 journal bearings (films)": Run.paper_case(1, None, rig=films, **base),
        "no element, 1st critical, no gravity": Run.paper_case(1, None, duration_s=duration,
                                                               discard_s=0.0),
        "pedestal rig, linear, 2x 1st critical": Run.paper_case(
            1, None, rig=pedestal, **fast),
        "pedestal rig, loose (lifting off), 2x 1st critical": Run.paper_case(
            1, None, rig=pedestal, faults=Faults(looseness=Looseness(
                bearing=0, preload_n=2.0, loose_stiffness_n_m=2e6)), **fast),
        "8 point contacts rubbing, 1st critical": Run.paper_case(1, 1.9, duration_s=duration,
                                                                 discard_s=0.0,
                                                                 gap_ramp_s=0.0),
    }


def us_per_step(run: Run) -> float:
    system = simulate(run).system
    return 1e6 * system.extra["kernel_seconds"] / system.n_steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--duration", type=float, default=0.2, help="simulated time (s)")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    runs = cases(args.duration)
    for run in runs.values():       # compile and warm every path first
        us_per_step(run)
    medians = {name: statistics.median(us_per_step(run) for _ in range(args.repeat))
               for name, run in runs.items()}
    base = medians["no element"]
    print(f"paper rig, full model, {args.duration:g} s per run, median of {args.repeat}; "
          f"1-min load {load:.2f} at start, {os.getloadavg()[0]:.2f} at end")
    print("| run | µs per step | over no element |")
    print("|---|---:|---:|")
    for name, value in medians.items():
        print(f"| {name} | {value:.2f} | {value - base:+.2f} |")


if __name__ == "__main__":
    main()
