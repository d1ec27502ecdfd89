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

Needs an interpreter with both packages, e.g.::

    /tmp/rossenv/bin/pip install -e /work/main     # rubdiag into the ROSS venv
    /tmp/rossenv/bin/python benchmarks/compare_ross.py [--repeat 5] [--n 2]

Exit status 0 when every compared critical speed agrees within 1 %, 1 otherwise.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import platform
import statistics
import sys
import time
import warnings

import numpy as np
from _threads import limit_threads  # benchmarks/ is on sys.path when run as a script

RPM = np.pi / 30.0      # rad/s per rpm
TOLERANCE = 0.01        # relative: the pass/fail bar
NOTE_ABOVE = 0.002      # relative: differences above this need an explanation

E, NU, RHO = 210e9, 0.3, 7850.0
SHAFT_DIAMETER_M = 0.010
DISC_NODES, DISC_RADIUS_M, DISC_THICKNESS_M = (11, 19), 0.035, 0.015
BEARING_NODES, K_Y, K_Z = (4, 26), 500e6, 200e6


@contextlib.contextmanager
def _quiet_fds():
    """Silence stdout/stderr at the file-descriptor level (C-level prints included)."""
    sys.stdout.flush()
    sys.stderr.flush()
    saved = [os.dup(1), os.dup(2)]
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 1)
        os.dup2(devnull, 2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            yield
    finally:
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        for fd in (*saved, devnull):
            os.close(fd)


def import_ross():
    """``import ross`` without the REFPROP banner its ``ccp`` dependency prints."""
    with _quiet_fds():
        import ross
    return ross


def build_rig(outer_diameter_m=SHAFT_DIAMETER_M, inner_diameter_m=0.0):
    """The paper rig's shaft, discs and bearings (no blades, casing or damping).

    The default shaft is the paper rig's solid 10 mm one; other diameters give a variant
    (e.g. a thick hollow shaft, for which shear deformation matters much more).
    """
    from rubdiag.model import Bearing, Disc, Material, Rig, Shaft, paper_rig

    paper = paper_rig()
    shaft = Shaft(element_lengths_m=paper.shaft.element_lengths_m,
                  outer_diameters_m=outer_diameter_m, inner_diameters_m=inner_diameter_m,
                  first_node=paper.shaft.first_node)
    return Rig(
        shaft=shaft,
        bearings=tuple(Bearing(node, K_Y, K_Z) for node in BEARING_NODES),
        discs=tuple(Disc(node, outer_radius_m=DISC_RADIUS_M, thickness_m=DISC_THICKNESS_M)
                    for node in DISC_NODES),
        material=Material(E, NU, RHO),
        name="paper rig shaft + discs + bearings",
    )


def build_ross_rotor(rs, rig, shear_effects=True, rotary_inertia=True, gyroscopic=True,
                     shear_method_calc="cowper"):
    """The same rotor in ROSS (6 DOF per node; axial and torsional DOFs are free)."""
    mat = rig.material
    steel = rs.Material(name="rubdiag_steel", rho=mat.density_kg_m3,
                        E=mat.youngs_modulus_pa, Poisson=mat.poisson_ratio)
    first = rig.shaft.first_node
    shaft = [
        rs.ShaftElement(L=length, idl=di, odl=do, material=steel, shear_effects=shear_effects,
                        rotary_inertia=rotary_inertia, gyroscopic=gyroscopic,
                        shear_method_calc=shear_method_calc)
        for length, do, di in zip(rig.shaft.element_lengths_m, rig.shaft.outer_diameters_m,
                                  rig.shaft.inner_diameters_m, strict=True)
    ]
    discs = []
    for disc in rig.discs:
        m, ip, idiam = disc.inertia(mat.density_kg_m3)
        discs.append(rs.DiskElement(n=disc.node - first, m=m, Id=idiam, Ip=ip))
    bearings = [rs.BearingElement(n=b.node - first, kxx=b.k_y_n_m, kyy=b.k_z_n_m,
                                  cxx=b.c_y_ns_m, cyy=b.c_z_ns_m) for b in rig.bearings]
    return rs.Rotor(shaft, discs, bearings)


def rubdiag_forward(rig, n):
    """(forward critical speeds rad/s, seconds for assemble + critical_speeds)."""
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds

    t0 = time.perf_counter()
    speeds = critical_speeds(assemble(rig), n=n)
    return np.asarray(speeds), time.perf_counter() - t0


def ross_num_modes(n):
    """``num_modes`` for ROSS: it keeps num_modes // 2 modes (both whirls, plus torsion)."""
    return max(12, 4 * n + 8)


def net_whirl(evector, number_dof):
    """(whirl ratio, lateral share) of a ROSS eigenvector (state space; λ with Im λ > 0).

    Whirl ratio as in rubdiag: 2 Σ Im(x·conj(y)) / Σ(|x|² + |y|²) over the shaft nodes,
    +1 circular forward … −1 circular backward. Lateral share: the fraction of |evector|²
    in the lateral DOFs (x, y, α, β), ~0 for the torsional and axial modes.
    """
    q = np.asarray(evector)
    ndof = q.size // 2
    q = q[:ndof].reshape(-1, number_dof)      # per node [x, y, z, α, β, θ]
    x, y = q[:, 0], q[:, 1]
    den = np.sum(np.abs(x) ** 2 + np.abs(y) ** 2)
    ratio = 2.0 * np.sum((x * y.conj()).imag) / den if den > 0 else 0.0
    lateral = np.sum(np.abs(q[:, [0, 1, 3, 4]]) ** 2) / np.sum(np.abs(q) ** 2)
    return float(ratio), float(lateral)


def ross_forward(rs, rig, n, rtol, **physics):
    """ROSS's forward critical speeds: (rad/s array, build s, solve s, all crossings).

    A fresh Rotor each call: ``Rotor.run_modal`` is memoised per instance, so a second
    ``run_critical_speed`` on the same rotor would only time the cache.

    The whirl of each crossing is taken from the net whirl of ROSS's own eigenvector at
    the crossing speed, not from ROSS's ``whirl_direction`` label: ROSS labels a mode
    "Mixed" unless every node's orbit whirls the same way, and a node that sits at a node
    of the mode shape (e.g. mid-span in an antisymmetric mode, amplitude ~1e-8 of the
    maximum) whirls either way by round-off, so the label of a forward mode changes
    between runs and variants, which would drop it from the list. ``crossings`` holds
    (rpm, ROSS label, net whirl ratio, lateral share) for every crossing, for the record.
    """
    t0 = time.perf_counter()
    rotor = build_ross_rotor(rs, rig, **physics)
    t1 = time.perf_counter()
    num_modes = ross_num_modes(n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_critical_speed(num_modes=num_modes, rtol=rtol)
    t2 = time.perf_counter()
    wn, wd = np.asarray(result.wn()), np.asarray(result.wd())
    crossings, forward = [], []
    for i, (w_n, w_d, label) in enumerate(zip(wn, wd, result.whirl_direction, strict=True)):
        # the same (cached) run_modal call that run_critical_speed used for mode i's whirl
        modal = rotor.run_modal(w_d, num_modes)
        ratio, lateral = net_whirl(modal.evectors[:, i], rotor.number_dof)
        crossings.append((w_n / RPM, str(label), ratio, lateral))
        if ratio > 0 and lateral > 0.5:
            forward.append(w_n)
    return np.sort(forward)[:n], t1 - t0, t2 - t1, crossings


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
    rs = import_ross()
    t_import_ross = time.perf_counter() - t0
    import rubdiag.modal  # loads SciPy's BLAS, so that the limit below reaches it

    pools = limit_threads(args.threads)
    outer_mm, inner_mm = args.shaft_mm
    rig = build_rig(outer_mm * 1e-3, inner_mm * 1e-3)

    # cold (first) calls, after the imports: numba compilation in ROSS, first-call set-up
    crit_rd, t_cold_rd = rubdiag_forward(rig, args.n)
    crit_ross, t_build, t_solve, crossings = ross_forward(rs, rig, args.n, args.rtol)
    t_cold_ross = t_build + t_solve

    rd_times = [rubdiag_forward(rig, args.n)[1] for _ in range(args.repeat)]
    ross_runs = [ross_forward(rs, rig, args.n, args.rtol) for _ in range(args.repeat)]
    for run in ross_runs:   # every run must give the same answer
        assert np.allclose(run[0], crit_ross, rtol=1e-6), (run[0], crit_ross)

    section = (f"solid {outer_mm:g} mm" if inner_mm == 0
               else f"hollow {outer_mm:g}/{inner_mm:g} mm")
    print(f"rotor: {rig.name}; {rig.shaft.n_elements} Timoshenko elements, "
          f"{section}; discs r = {DISC_RADIUS_M * 1e3:g} mm, "
          f"t = {DISC_THICKNESS_M * 1e3:g} mm at nodes {DISC_NODES}; bearings "
          f"k_y = {K_Y:.3g}, k_z = {K_Z:.3g} N/m at nodes {BEARING_NODES}")
    m, ip, idiam = rig.discs[0].inertia(RHO)
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
            speeds = ross_forward(rs, rig, args.n, args.rtol, **physics)[0]
            d = relative_differences(speeds, crit_rd)
            print(f"{label:<26}" + "".join(f"{x:+11.3%}" for x in d))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
