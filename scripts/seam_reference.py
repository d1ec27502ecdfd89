"""The simulator's results before its nonlinear elements moved behind one seam.

Runs that reach every path of the contact code, made by the code *before* the element seam
and stored as SHA-256 digests of every array of their
:class:`~rubdiag.simulation._result.SystemResult`, with the library versions and OpenBLAS
kernels they were made with (see ``scripts/presplit_reference.py`` for why the bits depend on
those and not on the CPU):

* ``annular`` — a shaft–stator annular clearance with friction and the shaft's surface speed
  on the lumped disc of ``tip_casing_system`` (``tests/testsystems.py``), variable
  step, the clearance ramped down;
* ``mixed`` — point contacts at two blade tips and an annular clearance at the disc in one
  run (both kinds side by side), variable step;
* ``augmented`` — the point contacts with the augmented Lagrangian (boosted updates, pending
  steps accepted);
* ``general`` — Newmark γ = 0.6 (the general right-hand side, M v recomputed);
* ``dense`` — the mixed run through the dense linear path;
* ``profile`` — a speed run-up (stretches of step operators, the load's order factors);
* ``reduced`` — Table 2's case 2 cell on the reduced model for 60 ms.

``tests/simulation/test_seam_reference.py`` asks the current code for the same bits when the
versions and kernels match.

    python scripts/seam_reference.py   # -> data/seam/reference-<kernels>.json

Made with the code at d56cb76 (before the seam).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import warnings
from pathlib import Path

import rubdiag

if __name__ == "__main__":     # a run starts here (imported, numpy is loaded already)
    rubdiag.pin_blas_kernels()  # first: before numpy loads OpenBLAS (the same bits anywhere)

# isort: split
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "seam"
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "tests"))     # testsystems: the tests' synthetic systems

from presplit_reference import arrays, digest, made_on, versions  # noqa: E402


def _lumped(**options):
    from testsystems import linear_response, tip_casing_system

    ts = tip_casing_system(**options)
    u = linear_response(ts.M, ts.C, ts.K, ts.force)
    return ts, (u.real.copy(), (1j * ts.speed * u).real), np.abs(u)


def _annular(ts, amplitude, share: float):
    """An annular clearance at the disc, ``share`` of its linear orbit radius."""
    from rubdiag.simulation import AnnularContact

    y, z = ts.disc_dofs
    radius = float(max(amplitude[y], amplitude[z]))
    return (AnnularContact(dof_a=(y, z), clearance=share * radius, radius=0.05, k_n=5e7,
                           mu=0.2),), radius


def _run(ts, contacts, q0, v0, *, duration=0.04, solver=None, gap_ramp=None, **system):
    """``contacts`` on ``ts`` from (q0, v0) at its speed for ``duration`` (s), at 10 µs
    steps, sampled at 10 kHz; ``system``: more of the LinearSystem's fields."""
    from rubdiag.simulation import LinearSystem, Recording, TimeGrid, simulate_system

    return simulate_system(
        LinearSystem(M=ts.M, C=ts.C, K=ts.K, force=ts.force, q0=q0, v0=v0, omega=ts.speed,
                     **system),
        contacts, TimeGrid(duration=duration, dt=1e-5, output_dt=1e-4),
        Recording(sensor_dofs=[0, 1, 2]), solver=solver, gap_ramp=gap_ramp)


def runs() -> dict:
    """Every reference run's SystemResult, by name (module docstring)."""
    from rubdiag.reduce import Reduction
    from rubdiag.simulation import Run, Solver, SpeedProfile, simulate

    ts, (q0, v0), amplitude = _lumped(gap=30e-6)
    annular, radius = _annular(ts, amplitude, 0.7)
    mixed = ts.contacts + annular
    gaps = np.array([c.gap for c in ts.contacts])
    out = {
        "annular": _run(ts, annular, q0, v0, gap_ramp=(0.01, 1.2 * radius)),
        "mixed": _run(ts, mixed, q0, v0, gap_ramp=(0.01, np.r_[gaps + 1e-4, 1.2 * radius])),
        "dense": _run(ts, mixed, q0, v0, gap_ramp=(0.01, np.r_[gaps + 1e-4, 1.2 * radius]),
                      solver=Solver(linear_solver="dense")),
        "general": _run(ts, ts.contacts, q0, v0, solver=Solver(gamma=0.6)),
    }
    aug = tuple(dataclasses.replace(c, augmented=True, eps=2e-6) for c in ts.contacts)
    out["augmented"] = _run(ts, aug, q0, v0, solver=Solver(augment_boost=0.9,
                                                           augment_strict=False,
                                                           max_augment=20))
    start = ts.speed * 30.0 / np.pi
    profile = SpeedProfile.ramp(start, start + 200.0, 4000.0)
    out["profile"] = _run(ts, mixed, q0, v0, speed_profile=profile,
                          gyroscopic=0.0 * ts.K, duration=0.05)
    with warnings.catch_warnings():     # the ramp inside the (unused) analysis window
        warnings.simplefilter("ignore")
        cell = Run.paper_case(2, 1.9, duration_s=0.06, discard_s=0.0, reduction=Reduction())
    out["reduced"] = simulate(cell).system
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    from rubdiag import __version__

    args.out.mkdir(parents=True, exist_ok=True)
    made = {name: arrays(result) for name, result in runs().items()}
    meta = {"rubdiag": __version__, "versions": versions(), "made_on": made_on()}
    meta |= {name: {k: digest(v) for k, v in got.items()} for name, got in made.items()}
    path = args.out / f"reference-{meta['versions']['blas'].lower()}.json"
    path.write_text(json.dumps(meta, indent=1) + "\n")
    print(f"{path}: {', '.join(f'{k} {len(v)}' for k, v in made.items())} digests, made "
          f"with {meta['versions']}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
