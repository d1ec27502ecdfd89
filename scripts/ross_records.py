#!/usr/bin/env python
"""Probe records of another simulator's faults, for scoring rubdiag's classifiers on records
rubdiag did not make: ROSS's breathing crack, coupling misalignment and shaft-on-stator rub
on a rotor close to rubdiag's paper rig, run once and stored small in data/ross_records/.

ROSS (``ross-rotordynamics``) is not a dependency of rubdiag and these records are never
used for training: the transfer table (scripts/transfer.py) scores models on them, and the
tests read the stored files only. Setup (once, outside the checkout, as for
scripts/ross_references.py) and use, from the repository root::

    python3.11 -m venv ../rossenv
    ../rossenv/bin/pip install "ross-rotordynamics==2.3.0" "plotly<6" "pandas<3" -e .
    ../rossenv/bin/python scripts/ross_records.py          # rewrites data/ross_records/

``pandas<3``: ROSS 2.3.0's crack model reads its compliance table with ``pandas.eval`` of a
Series, which pandas 3 refuses ("expr must be a string").

The rotor (:func:`rotor_spec`) is scripts/ross_references.py's paper shaft — 24 Timoshenko
elements with the paper rig's lengths, solid 10 mm, rigid discs r = 35 mm, t = 15 mm at
rubdiag nodes 11 and 19, bearings k_y = 500e6, k_z = 200e6 N/m with 2e3 N s/m at nodes 4
and 26 — without blades or casing (ROSS has neither), so its first forward critical speed
is ROSS's 1596 rpm, not the bladed rig's 1500. Its shaft elements carry stiffness-
proportional damping giving 4 % of critical damping at that speed (the paper rig's modal
damping ratio), so that the start from rest dies out in :data:`SETTLE_S`. The unbalance is
a tenth of the paper rig's case 1 (as on the preset ``paper-journal``): 1.56e-5 kg m at each
disc, in phase; with the full one the crack's 2× is 0.3–3 % of 1× at half the critical.

The runs (:data:`RUNS`, 8 per fault; ROSS's own models, its Newmark integration at 0.1 ms
with its pseudo-modal reduction to 12 modes):

``crack``
    Mayes's breathing crack (``run_crack``), mid-span between the discs, depth 0.3 and 0.5
    of the diameter, at 0.45, 0.5, 0.55 and 0.75 of the first critical speed: near half of
    it the 2× resonance makes 2× large (Bently & Hatch 2002; Muszynska 2005).
``misalignment``
    A flexible coupling's parallel misalignment (``run_misalignment``, coupling "flex") at
    the drive-end overhang, offsets 0.01 and 0.03 mm (equal in both directions), coupling
    radial stiffness 40 kN/m (ROSS's example), at 0.5, 0.65, 0.8 and 0.9 of the critical.
``rub``
    Shaft-on-stator rub at the first disc (``run_rubbing``: contact stiffness 1.1 MN/m,
    damping 40 N s/m, friction 0.3, ROSS's example values), the clearance 0.5 and 0.8 of
    the run's own linear 1× orbit radius there (so that every run touches), at 0.8, 0.9,
    1.0 and 1.1 of the critical.

Stored per run: ``data/ross_records/<name>.npz`` — the six shaft probes rubdiag's sensors
name (``shaft4_y_disp`` … ``shaft26_z_disp``, metres; rubdiag y is ROSS x, z is ROSS y) over
:data:`RECORD_S` after :data:`SETTLE_S`, decimated from 10 kHz to :data:`FS_HZ` (scipy's
zero-phase FIR ``decimate``), float32, and ``fs``; ``records.csv`` lists each file with its
``faults`` label, ``kind``, ``speed_rpm`` and the fault's parameters. ``rubdiag predict``
and ``rubdiag evaluate MODEL data/ross_records/records.csv`` read them as they are.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ross_references as rr  # the same paper shaft in ROSS

OUT = Path(__file__).resolve().parents[1] / "data" / "ross_records"
CRITICAL_RPM = 1595.5           # ROSS's first forward critical of the paper shaft
DAMPING_RATIO = 0.04            # at the first critical, stiffness-proportional
DT_S = 1e-4
SETTLE_S, RECORD_S = 1.5, 2.0
FS_HZ = 2000.0
UNBALANCE_KG_M = 1.56e-5
REDUCTION = {"num_modes": 12}
PROBE_NODES = (4, 11, 26)       # rubdiag nodes; ROSS node = rubdiag node - 3
DISC_NODES = (11, 19)
CRACK_ELEMENT = 12              # ROSS element from node 12 (rubdiag 15): mid-span
COUPLING_ELEMENT = 0            # the drive-end overhang
RUB_ELEMENT = 8                 # from ROSS node 8: the first disc (rubdiag node 11)

RUNS = (
    [{"faults": "crack", "kind": "crack", "depth_ratio": d, "speed_ratio": s}
     for d in (0.3, 0.5) for s in (0.45, 0.5, 0.55, 0.75)]
    + [{"faults": "misalignment", "kind": "misalignment", "offset_m": o, "speed_ratio": s}
       for o in (1e-5, 3e-5) for s in (0.5, 0.65, 0.8, 0.9)]
    + [{"faults": "rub", "kind": "seal rub", "clearance_of_orbit": c, "speed_ratio": s}
       for c in (0.5, 0.8) for s in (0.8, 0.9, 1.0, 1.1)]
)


def rotor_spec() -> dict:
    """The paper shaft of scripts/ross_references.py with dampers at the bearings."""
    return rr.rotor(bearing_damping_ns_m=(2e3, 2e3))


def damped_rotor(rs, spec: dict):
    """The rotor in ROSS, its shaft damped in proportion to stiffness (module docstring)."""
    beta = 2.0 * DAMPING_RATIO / (CRITICAL_RPM * rr.RPM)
    return rr.ross_rotor(rs, spec, beta=beta)


def run_name(run: dict) -> str:
    """File stem of a run: its kind, parameter and speed ratio."""
    value = {"crack": f"depth{run.get('depth_ratio', 0):.2f}",
             "misalignment": f"offset{run.get('offset_m', 0) * 1e6:.0f}um",
             "rub": f"clearance{run.get('clearance_of_orbit', 0):.2f}"}[run["faults"]]
    return f"{run['faults']}_{value}_speed{run['speed_ratio']:.2f}"


def linear_radius_m(rotor, node: int, speed_rad_s: float, first: int) -> float:
    """Radius of the linear 1× orbit (the larger semi-axis) at ROSS ``node``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_unbalance_response(
            node=[n - first for n in DISC_NODES], unbalance_magnitude=[UNBALANCE_KG_M] * 2,
            unbalance_phase=[0.0, 0.0], frequency=np.array([speed_rad_s]))
    resp = np.asarray(result.forced_resp)[:, 0]
    x, y = resp[rotor.number_dof * node], resp[rotor.number_dof * node + 1]
    turn = np.exp(1j * np.linspace(0.0, 2.0 * np.pi, 721))
    return float(np.hypot((x * turn).real, (y * turn).real).max())


def simulate(rs, rotor, spec: dict, run: dict) -> np.ndarray:
    """ROSS's response of one run: (time steps, DOFs)."""
    from ross.units import Q_

    first = spec["first_node"]
    speed_rpm = run["speed_ratio"] * CRITICAL_RPM
    common = {"node": [n - first for n in DISC_NODES],
              "unbalance_magnitude": [UNBALANCE_KG_M] * 2, "unbalance_phase": [0.0, 0.0],
              "speed": Q_(speed_rpm, "RPM"), "t": np.arange(0.0, SETTLE_S + RECORD_S, DT_S),
              "model_reduction": REDUCTION}
    with warnings.catch_warnings(), rr._quiet_fds():
        warnings.simplefilter("ignore")
        if run["faults"] == "crack":
            result = rotor.run_crack(n=CRACK_ELEMENT, depth_ratio=run["depth_ratio"],
                                     crack_model="Mayes", **common)
        elif run["faults"] == "misalignment":
            d = run["offset_m"] / math.sqrt(2.0)
            result = rotor.run_misalignment(
                coupling="flex", n=COUPLING_ELEMENT, mis_type="parallel",
                radial_stiffness=40e3, bending_stiffness=38e3, mis_distance_x=d,
                mis_distance_y=d, mis_angle=0.0, input_torque=0, load_torque=0, **common)
        else:
            radius = linear_radius_m(rotor, RUB_ELEMENT, speed_rpm * rr.RPM, first)
            result = rotor.run_rubbing(
                n=RUB_ELEMENT, distance=run["clearance_of_orbit"] * radius,
                contact_stiffness=1.1e6, contact_damping=40.0, friction_coeff=0.3, **common)
    return np.asarray(result.yout)


def probes(rotor, response: np.ndarray, first: int) -> dict[str, np.ndarray]:
    """The six shaft probes over the record, decimated to :data:`FS_HZ`, float32."""
    from scipy.signal import decimate

    factor = round(1.0 / (DT_S * FS_HZ))
    start = round(SETTLE_S / DT_S)
    out = {}
    for node in PROBE_NODES:
        for offset, direction in ((0, "y"), (1, "z")):
            x = response[:, rotor.number_dof * (node - first) + offset]
            x = decimate(x, factor, ftype="fir", zero_phase=True)[start // factor:]
            out[f"shaft{node}_{direction}_disp"] = x[: round(RECORD_S * FS_HZ)].astype(
                np.float32)
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT, help="folder to write")
    parser.add_argument("--only", help="run only the runs whose name contains this text")
    args = parser.parse_args(argv)
    rs = rr.import_ross()
    spec = rotor_spec()
    rotor = damped_rotor(rs, spec)
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for run in RUNS:
        name = run_name(run)
        if args.only and args.only not in name:
            continue
        start = time.perf_counter()
        signals = probes(rotor, simulate(rs, rotor, spec, run), spec["first_node"])
        np.savez_compressed(args.out / f"{name}.npz", fs=np.float64(FS_HZ), **signals)
        rows.append({"file": f"{name}.npz", "faults": run["faults"], "kind": run["kind"],
                     "speed_rpm": round(run["speed_ratio"] * CRITICAL_RPM, 3),
                     **{k: v for k, v in run.items() if k not in ("faults", "kind")}})
        print(f"{name}: {time.perf_counter() - start:.0f} s", flush=True)
    table = pd.DataFrame(rows)
    path = args.out / "records.csv"
    if args.only and path.exists():           # a partial run keeps the other rows
        old = pd.read_csv(path)
        table = pd.concat([old[~old["file"].isin(table["file"])], table], ignore_index=True)
    table.to_csv(path, index=False)
    print(f"wrote {len(table)} records to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
