"""The simulator's results before it is split into small parts: a reference.

Three runs, made by the code *before* the split and stored with the library versions and the
OpenBLAS kernels they were made with:

* ``short`` — case 1 serious (g0 = 1.9 mm) at a fixed 10-µs step for 30 ms, the gap closed
  over the first 10 ms so that the blades touch, with the default sensors: every array of its
  :class:`~rubdiag.simulation._result.SystemResult` (short and not
  chaotic), as SHA-256 digests;
* ``portable`` — the same rig and case through ``simulate_system`` directly, on inputs that
  no LAPACK routine computes (Rayleigh α, β as numbers, Ω given, from rest with a0 = 0,
  g0 = 0.1 mm so that the blades touch within its 30 ms, fixed 10-µs step); stored in full,
  so that other libraries or kernels can be compared to it to 1e-12 of each array's scale;
* ``cell`` — Table 2's case 2 serious cell, the default 2.3-s run (adaptive step, default
  sensors): a SHA-256 of every
  array (the run is chaotic over 230 000 steps, so only the same libraries and kernels can
  give the same bits).

The bits depend on the OpenBLAS kernels, not on the CPU as such: the SkylakeX kernels give
other bits than the Haswell ones on the same machine, and a znver3 and a rocketlake machine give
the same bits with the same kernels (``rubdiag/_blas.py`` pins Haswell). The CPU a reference
was made on is stored, and not compared.

``tests/simulation/test_presplit_reference.py`` asks the current code for the same bits when
the versions and kernels match and, otherwise, for the portable run to 1e-12 of each array's
largest magnitude.

    python scripts/presplit_reference.py   # -> data/presplit/reference-<kernels>.json, portable.npz

Made with the code before the split (a worktree at 6b73d28, Haswell kernels pinned by
``OPENBLAS_CORETYPE=Haswell``) on rocketlake; its short run and cell equal, bit for bit, those
the same code gave on znver3 earlier.
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import json
import platform
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "presplit"


def short_run():
    from rubdiag.model import paper_rig
    from rubdiag.simulation import Run
    from rubdiag.simulation._sensors import default_sensors

    rig = paper_rig()
    return Run.paper_case(1, 1.9, rig=rig, duration_s=0.03, discard_s=0.02, gap_ramp_s=0.01,
                          fixed_step=True, dt_s=1e-5, sensors=default_sensors(rig))


#: Rayleigh coefficients of the paper rig (documentation: "The model and its physics
#: choices"), as numbers: not computed here
PORTABLE_RAYLEIGH = (9.948, 1.061e-4)
PORTABLE_SPEED_RAD_S = 1500.0 * np.pi / 30.0


def portable_run():
    """The ``portable`` run's SystemResult (module docstring)."""
    from rubdiag.assembly import assemble
    from rubdiag.model import paper_rig
    from rubdiag.simulation import (
        HarmonicForce,
        LinearSystem,
        PointContact,
        Recording,
        TimeGrid,
        simulate_system,
    )

    rig = paper_rig()
    model = assemble(rig)
    alpha, beta = PORTABLE_RAYLEIGH
    speed = PORTABLE_SPEED_RAD_S
    C = (alpha * model.M + beta * model.K_structural + model.C_discrete + speed * model.G)
    F = model.unbalance_force(rig.unbalance(1), speed)
    loaded = np.flatnonzero(F)
    geo = model.blade_contacts
    law = rig.contact
    contacts = [PointContact(dof_a=tuple(tip.tolist()), dof_b=tuple(casing.tolist()),
                             normal=tuple(normal.tolist()), tangent=tuple(tangent.tolist()),
                             gap=1e-4, k_n=law.normal_stiffness_n_m,
                             k_t=law.tangential_stiffness_n_m, mu=law.friction_coefficient)
                for tip, casing, normal, tangent in zip(geo.tip_dofs, geo.casing_dofs,
                                                        geo.normal, geo.tangent, strict=True)]
    n = model.n_dof
    record = [model.dofs.index(p, d) for p in ("shaft 11", "shaft 19") for d in "yz"]
    return simulate_system(
        LinearSystem(M=model.M, C=C.tocsr(), K=model.K,
                     force=HarmonicForce(loaded, F[loaded], speed), a0=np.zeros(n)),
        contacts, TimeGrid(duration=0.03, dt=1e-5, fixed_step=True, output_dt=1e-4),
        Recording(record_dofs=record, sensor_dofs=[geo.casing_dofs[0, 0]]))


def cell_run():
    from rubdiag.model import paper_rig
    from rubdiag.simulation import Run
    from rubdiag.simulation._sensors import default_sensors

    rig = paper_rig()
    return Run.paper_case(2, 1.9, rig=rig, sensors=default_sensors(rig))


def versions() -> dict:
    """What the bits of a run depend on besides the code: libraries and OpenBLAS kernels."""
    import llvmlite
    import numba
    import scipy
    import scipy.linalg  # scipy's own OpenBLAS, loaded
    from threadpoolctl import threadpool_info

    # not rubdiag._blas.kernels_in_use: the reference is made with the pre-split code,
    # which has no rubdiag._blas (and this names numpy's and scipy's kernels if they differ)

    kernels = sorted({i.get("architecture") for i in threadpool_info()
                      if i.get("internal_api") == "openblas"})
    return {"python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "numba": numba.__version__,
            "llvmlite": llvmlite.__version__, "machine": platform.machine(),
            "blas": "+".join(kernels)}


def made_on() -> str:
    """The CPU, for the record (the bits do not depend on it: module docstring)."""
    import llvmlite.binding as llvm

    return llvm.get_host_cpu_name()


#: SystemResult fields added after the references were made, for what those runs do not
#: do (``n_rejected_error`` counts long steps, which they do not take: 0)
ADDED_SINCE = {"n_rejected_error": 0}


def arrays(system) -> dict[str, np.ndarray]:
    """Every array a run computed: the SystemResult's array fields, and those of its logs,
    by name (``episodes.t_start`` …). Wall times (``extra``) are left out, and so are the
    fields :data:`ADDED_SINCE` when they hold the value the references' runs imply."""
    out = {}
    for f in dataclasses.fields(system):
        value = getattr(system, f.name)
        if f.name in ADDED_SINCE and value == ADDED_SINCE[f.name]:
            continue
        if isinstance(value, np.ndarray):
            out[f.name] = value
        elif dataclasses.is_dataclass(value):
            for g in dataclasses.fields(value):
                inner = getattr(value, g.name)
                if isinstance(inner, np.ndarray):
                    out[f"{f.name}.{g.name}"] = inner
        elif isinstance(value, int | float) and not isinstance(value, bool):
            out[f.name] = np.asarray(value)
    return out


def digest(a: np.ndarray) -> str:
    a = np.ascontiguousarray(a)
    return hashlib.sha256(str((a.dtype.str, a.shape)).encode() + a.tobytes()).hexdigest()


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args(argv)
    from rubdiag import __version__
    from rubdiag.simulation import simulate

    args.out.mkdir(parents=True, exist_ok=True)
    short = arrays(simulate(short_run()).system)
    portable = arrays(portable_run())
    np.savez_compressed(args.out / "portable.npz", **portable)
    cell = arrays(simulate(cell_run()).system)
    meta = {"rubdiag": __version__, "versions": versions(), "made_on": made_on(),
            "short": {k: digest(v) for k, v in short.items()},
            "portable": {k: digest(v) for k, v in portable.items()},
            "cell": {k: digest(v) for k, v in cell.items()}}
    path = args.out / f"reference-{meta['versions']['blas'].lower()}.json"
    path.write_text(json.dumps(meta, indent=1) + "\n")
    print(f"{path}: short run {len(short)}, portable run {len(portable)}, Table 2 cell "
          f"{len(cell)} digests, made with {meta['versions']}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
