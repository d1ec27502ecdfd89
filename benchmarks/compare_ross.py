"""Cross-check rubdiag's forward critical speeds against ROSS (ross-rotordynamics).

The rotor is the paper rig without blades and casing: 24 solid Timoshenko shaft elements of
10 mm diameter (element lengths from rubdiag/model/presets/paper.toml), two rigid discs
r = 35 mm, t = 15 mm at paper nodes 11 and 19, and two undamped bearings with
k_y = 500e6 N/m, k_z = 200e6 N/m at paper nodes 4 and 26. Material E = 210 GPa, ν = 0.3,
ρ = 7850 kg/m³.

Both codes get the same physics: shear deformation (Cowper's κ), rotary inertia and
gyroscopic terms of the shaft, rigid discs with the same mass and inertias (given to ROSS
explicitly), no damping. Axes: rubdiag spins about x with lateral y, z; ROSS spins about z
with lateral x, y, so rubdiag y -> ROSS x and rubdiag z -> ROSS y (a cyclic, handedness-
preserving relabelling: forward whirl is forward in both). ROSS node indices are 0-based
from the first shaft node (paper node 3 -> ROSS node 0).

rubdiag solves the synchronous eigenproblem K q = Ω²(M − iG) q directly; ROSS's
``Rotor.run_critical_speed`` iterates ``run_modal`` with a secant (Newton) method on
Ω − ω_i(Ω) and classifies the whirl at the crossing. The forward crossings are compared.

A sensitivity table (ROSS with shear, rotary inertia or shaft gyroscopics switched off, or
Hutchinson's κ) shows how far each modelling choice moves the critical speeds, i.e. how
meaningful the agreement of the reference comparison is.

The rotor and the ROSS side (building the rotor, picking the forward crossings) are
scripts/ross_references.py's, which stores ROSS's values for tests/modal/test_ross.py.

Needs an interpreter with both packages; from the repository root::

    python3.11 -m venv ../rossenv
    ../rossenv/bin/pip install "ross-rotordynamics==2.3.0" "plotly<6" -e .
    ../rossenv/bin/python benchmarks/compare_ross.py [--repeat 5] [--n 2]

Exit status 0 when every compared critical speed agrees within 1 %, 1 otherwise.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _threads import limit_threads  # benchmarks/ is on sys.path when run as a script

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
import ross_references as ref

RPM = ref.RPM           # rad/s per rpm
TOLERANCE = 0.01        # relative: the pass/fail bar
NOTE_ABOVE = 0.002      # relative: differences above this need an explanation


def rubdiag_forward(rig, n):
    """(forward critical speeds rad/s, seconds for assemble + critical_speeds)."""
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds

    t0 = time.perf_counter()
    speeds = critical_speeds(assemble(rig), n=n)
    return np.asarray(speeds), time.perf_counter() - t0


def ross_forward(rs, spec, n, rtol, **physics):
    """ROSS's forward critical speeds: (rad/s array, build s, solve s, all crossings).

    A fresh Rotor each call: ``Rotor.run_modal`` is memoised per instance, so a second
    ``run_critical_speed`` on the same rotor would only time the cache. The forward
    crossings are picked by the net whirl of ROSS's eigenvectors
    (:func:`ross_references.forward_crossings` says why not by ROSS's label).
    """
    t0 = time.perf_counter()
    rotor = ref.ross_rotor(rs, spec, **physics)
    t1 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_critical_speed(num_modes=ref.ross_num_modes(n), rtol=rtol)
    t2 = time.perf_counter()
    forward, crossings = ref.forward_crossings(rotor, result, n)
    return forward, t1 - t0, t2 - t1, crossings


def relative_differences(a, b):
    k = min(len(a), len(b))
    return (np.asarray(a[:k]) - np.asarray(b[:k])) / np.asarray(b[:k])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5,
                        help="timed runs per code, the median is shown (default 5)")
    parser.add_argument("--n", type=int, default=2,
                        help="forward critical speeds to compare (default 2)")
    parser.add_argument("--rtol", type=float, default=1e-6,
                        help="ROSS run_critical_speed secant tolerance (default 1e-6; "
                        "ROSS's own default is 5e-3)")
    parser.add_argument("--shaft-mm", type=float, nargs=2, default=(10.0, 0.0),
                        metavar=("OD", "ID"),
                        help="shaft outer and inner diameter in mm (default 10 0, the paper "
                        "rig; e.g. 40 20 for a thick hollow shaft where shear matters)")
    parser.add_argument("--threads", type=int, default=None,
                        help="limit BLAS/OpenMP threads (threadpoolctl) for both codes "
                        "(default: library default, usually one per CPU)")
    parser.add_argument("--no-sensitivity", action="store_true",
                        help="skip the ROSS physics-switch sensitivity table")
    args = parser.parse_args(argv)
    if args.repeat < 1 or args.n < 1 or not args.rtol > 0:
        parser.error("--repeat and --n must be >= 1 and --rtol > 0")
    if args.threads is not None and args.threads < 1:
        parser.error("--threads must be >= 1")

    import rubdiag

    t0 = time.perf_counter()
    rs = ref.import_ross()
    t_import_ross = time.perf_counter() - t0
    import rubdiag.modal  # loads SciPy's BLAS, so that the limit below reaches it

    pools = limit_threads(args.threads)
    outer_mm, inner_mm = args.shaft_mm
    spec = ref.rotor(outer_mm * 1e-3, inner_mm * 1e-3)
    rig = ref.rig(spec)

    # cold (first) calls, after the imports: numba compilation in ROSS, first-call set-up
    crit_rd, t_cold_rd = rubdiag_forward(rig, args.n)
    crit_ross, t_build, t_solve, crossings = ross_forward(rs, spec, args.n, args.rtol)
    t_cold_ross = t_build + t_solve

    rd_times = [rubdiag_forward(rig, args.n)[1] for _ in range(args.repeat)]
    ross_runs = [ross_forward(rs, spec, args.n, args.rtol) for _ in range(args.repeat)]
    for run in ross_runs:   # every run must give the same answer
        assert np.allclose(run[0], crit_ross, rtol=1e-6), (run[0], crit_ross)

    section = (f"solid {outer_mm:g} mm" if inner_mm == 0
               else f"hollow {outer_mm:g}/{inner_mm:g} mm")
    print(f"rotor: {rig.name}; {rig.shaft.n_elements} Timoshenko elements, "
          f"{section}; discs r = {ref.DISC_RADIUS_M * 1e3:g} mm, "
          f"t = {ref.DISC_THICKNESS_M * 1e3:g} mm at nodes {ref.DISC_NODES}; bearings "
          f"k_y = {ref.K_Y:.3g}, k_z = {ref.K_Z:.3g} N/m at nodes {ref.BEARING_NODES}")
    m, ip, idiam = rig.discs[0].inertia(ref.RHO)
    print(f"disc: m = {m:.6f} kg, Ip = {ip:.6e} kg m2, Id = {idiam:.6e} kg m2 (same in both)")
    print(f"rubdiag {rubdiag.__version__}, ROSS {rs.__version__}, Python "
          f"{platform.python_version()}, numpy {np.__version__}; thread pools: {pools}")
    print()
    print(f"ROSS run_critical_speed crossings (rtol {args.rtol:g}), whirl from its eigenvectors")
    print(f"{'rpm':>11}  {'ROSS label':>10}  {'net whirl':>9}  {'lateral':>7}")
    for rpm, label, ratio, lateral in crossings:
        print(f"{rpm:11.3f}  {label:>10}  {ratio:+9.3f}  {lateral:7.3f}")
    print()
    print("forward critical speeds (rel. diff = rubdiag / ROSS - 1)")
    print(f"{'mode':>4}  {'rubdiag rpm':>13}  {'ROSS rpm':>13}  {'rel. diff':>10}")
    ok = len(crit_rd) >= args.n and len(crit_ross) >= args.n
    diffs = relative_differences(crit_rd, crit_ross)
    for i in range(args.n):
        rd = f"{crit_rd[i] / RPM:13.3f}" if i < len(crit_rd) else f"{'missing':>13}"
        ro = f"{crit_ross[i] / RPM:13.3f}" if i < len(crit_ross) else f"{'missing':>13}"
        df = f"{diffs[i]:+10.2e}" if i < len(diffs) else f"{'-':>10}"
        print(f"{i + 1:>4}  {rd}  {ro}  {df}")
    worst = float(np.max(np.abs(diffs))) if len(diffs) else float("inf")
    ok = ok and worst <= TOLERANCE
    print(f"largest |difference| = {worst:.2e} (bar {TOLERANCE:.0%}): "
          f"{'PASS' if ok else 'FAIL'}")
    if ok and worst > NOTE_ABOVE:
        print(f"note: difference above {NOTE_ABOVE:.1%}: see the sensitivity table")

    print()
    print(f"timing (median of {args.repeat}; cold = first call in this process, after imports)")
    print(f"  rubdiag assemble + critical_speeds  : {statistics.median(rd_times) * 1e3:9.2f} ms"
          f"   (cold {t_cold_rd * 1e3:.1f} ms)")
    ross_total = [b + s for _, b, s, _ in ross_runs]
    print(f"  ROSS Rotor(...) + run_critical_speed: {statistics.median(ross_total) * 1e3:9.2f} ms"
          f"   (build {statistics.median(b for _, b, _, _ in ross_runs) * 1e3:.1f} ms, solve "
          f"{statistics.median(s for _, _, s, _ in ross_runs) * 1e3:.1f} ms; cold "
          f"{t_cold_ross:.2f} s incl. numba compilation)")
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg())
    print(f"  machine: {os.cpu_count()} CPUs, load average {load} (1, 5, 15 min)")
    print(f"  ROSS / rubdiag: {statistics.median(ross_total) / statistics.median(rd_times):.0f}x"
          f"   (import ross: {t_import_ross:.2f} s)")

    if not args.no_sensitivity:
        variants = [
            ("Hutchinson kappa", {"shear_method_calc": "hutchinson"}),
            ("no shear deformation", {"shear_effects": False}),
            ("no rotary inertia", {"rotary_inertia": False}),
            ("Euler-Bernoulli (neither)", {"shear_effects": False, "rotary_inertia": False}),
            ("no shaft gyroscopics", {"gyroscopic": False}),
        ]
        print()
        print("sensitivity: ROSS with one modelling choice changed, relative to rubdiag")
        print(f"{'ROSS variant':<26}" + "".join(f"{f'mode {i + 1}':>11}" for i in range(args.n)))
        for label, physics in variants:
            speeds = ross_forward(rs, spec, args.n, args.rtol, **physics)[0]
            d = relative_differences(speeds, crit_rd)
            print(f"{label:<26}" + "".join(f"{x:+11.3%}" for x in d))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
