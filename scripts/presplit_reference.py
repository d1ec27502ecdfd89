"""The simulator's results before it is split into small parts (issue 13): a reference.

Two runs, made by the code *before* the split and stored with the library versions and the
CPU they were made on:

* ``short`` — case 1 serious (g0 = 1.9 mm) at a fixed 10-µs step for 30 ms, the gap closed
  over the first 10 ms so that the blades touch, with the default sensors: every array of its
  :class:`~rubdiag.simulate.result.SystemResult` is stored in full (short and not
  chaotic, so another numpy or numba may move it by round-off only);
* ``cell`` — Table 2's case 2 serious cell, the default 2.3-s run (adaptive step, default
  sensors): a SHA-256 of every
  array (the run is chaotic over 230 000 steps, so only the same libraries on the same CPU
  can give the same bits).

``tests/simulate/test_presplit_reference.py`` asks the current code for the same bits when
the versions match and, otherwise, for the short run to rtol 1e-12.

    python scripts/presplit_reference.py          # -> data/presplit/ (made once, before the split)
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
    from rubdiag.simulate import Run
    from rubdiag.simulate.sensors import default_sensors

    rig = paper_rig()
    return Run.paper_case(1, 1.9, rig=rig, duration_s=0.03, discard_s=0.02, gap_ramp_s=0.01,
                          fixed_step=True, dt_s=1e-5, sensors=default_sensors(rig))


def cell_run():
    from rubdiag.model import paper_rig
    from rubdiag.simulate import Run
    from rubdiag.simulate.sensors import default_sensors

    rig = paper_rig()
    return Run.paper_case(2, 1.9, rig=rig, sensors=default_sensors(rig))


def versions() -> dict:
    """What the bits of a run depend on besides the code: libraries and CPU."""
    import llvmlite
    import llvmlite.binding as llvm
    import numba
    import scipy

    return {"python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "numba": numba.__version__,
            "llvmlite": llvmlite.__version__, "machine": platform.machine(),
            "cpu": llvm.get_host_cpu_name()}


def arrays(system) -> dict[str, np.ndarray]:
    """Every array a run computed: the SystemResult's array fields, and those of its logs,
    by name (``episodes.t_start`` …). Wall times (``extra``) are left out."""
    out = {}
    for f in dataclasses.fields(system):
        value = getattr(system, f.name)
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
    from rubdiag.simulate import simulate

    args.out.mkdir(parents=True, exist_ok=True)
    short = arrays(simulate(short_run()).system)
    np.savez_compressed(args.out / "short.npz", **short)
    cell = arrays(simulate(cell_run()).system)
    meta = {"rubdiag": __version__, "versions": versions(),
            "short": {k: digest(v) for k, v in short.items()},
            "cell": {k: digest(v) for k, v in cell.items()}}
    (args.out / "reference.json").write_text(json.dumps(meta, indent=1) + "\n")
    print(f"{args.out}: short run {len(short)} arrays, Table 2 cell {len(cell)} digests, "
          f"made with {meta['versions']}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
