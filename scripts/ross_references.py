#!/usr/bin/env python
"""Store ROSS's answers for the rotors of tests/modal/test_ross.py in data/ross_references.json.

ROSS (``ross-rotordynamics``) is not a dependency of rubdiag: on Python 3.11 its newest
release is 2.3.0, which needs ``plotly < 6`` and brings ~1.4 GB of packages. So its answers
are computed once, by this script in an interpreter that has both ROSS and rubdiag, and
stored with ROSS's version, the Python version and the date. The test compares rubdiag with
the stored values in every run, and with ROSS itself where ROSS is installed (so that the
stored file cannot silently go stale).

The rotors (:func:`inputs`) are the paper rig without blades and casing: 24 Timoshenko
elements with the lengths of rubdiag/model/presets/paper.toml, rigid discs r = 35 mm,
t = 15 mm at nodes 11 and 19, bearings k_y = 500e6, k_z = 200e6 N/m at nodes 4 and 26,
E = 210 GPa, ν = 0.3, ρ = 7850 kg/m³; with the paper rig's solid 10 mm shaft and with a
thick hollow 40/20 mm one on which shear deformation and rotary inertia move the critical
speeds by per cents. Stored for each: the forward critical speeds; for the paper shaft also
the undamped natural frequencies at 0 and 8000 rpm and, with bearing dampers, the complex
unbalance response at six speeds; and, to show what the comparison can tell apart, ROSS's
critical speeds with Hutchinson's shear coefficient and without shear deformation.

Both codes get the same physics: shear deformation (Cowper's κ), rotary inertia and
gyroscopic terms of the shaft, rigid discs whose mass and inertias are given to ROSS
explicitly (closed form for a solid disc; rubdiag computes its own from r and t), no
Rayleigh damping. Axes: rubdiag spins about x with lateral y, z; ROSS spins about z with
lateral x, y; rubdiag y -> ROSS x, z -> ROSS y (handedness kept: forward whirl is forward in
both). ROSS node = rubdiag node - first shaft node.

Setup (once, anywhere outside the checkout) and use, from the repository root::

    python3.11 -m venv ../rossenv
    ../rossenv/bin/pip install "ross-rotordynamics==2.3.0" "plotly<6" pytest -e .
    ../rossenv/bin/python scripts/ross_references.py        # rewrite the JSON file
    ../rossenv/bin/python -m pytest tests/modal/test_ross.py   # stored == ROSS now?

Without ROSS (any interpreter with rubdiag), ``--agreement`` prints how far rubdiag is from
the stored values.
"""

from __future__ import annotations

import argparse
import contextlib
import datetime
import json
import math
import os
import platform
import re
import sys
import warnings
from pathlib import Path

import numpy as np

PATH = Path(__file__).resolve().parents[1] / "data" / "ross_references.json"
RPM = math.pi / 30.0            # rad/s per rpm
# forward critical speeds per rotor: the paper shaft's 3rd and 4th were not fitted to anything
N_CRITICAL = {"paper-solid-10mm": 4, "hollow-40-20mm": 2}
N_CRITICAL_VARIANTS = 2         # per rotor, for ROSS's other-physics variants

E, NU, RHO = 210e9, 0.3, 7850.0
DISC_NODES, DISC_RADIUS_M, DISC_THICKNESS_M = (11, 19), 0.035, 0.015
BEARING_NODES, K_Y, K_Z = (4, 26), 500e6, 200e6

# what every ROSS ShaftElement gets unless a variant changes it
SHAFT_PHYSICS = {"shear_effects": True, "rotary_inertia": True, "gyroscopic": True,
                 "shear_method_calc": "cowper"}
VARIANTS = {"hutchinson_kappa": {"shear_method_calc": "hutchinson"},
            "no_shear": {"shear_effects": False}}
CRITICAL_RTOL = 1e-8            # ROSS run_critical_speed's secant tolerance (its default: 5e-3)
MODAL_NUM_MODES = 20            # ROSS run_modal's num_modes for the natural frequencies


# ---------------------------------------------------------------- the compared rotors


def rotor(outer_diameter_m: float = 0.010, inner_diameter_m: float = 0.0,
          bearing_damping_ns_m: tuple[float, float] = (0.0, 0.0)) -> dict:
    """One rotor as plain data (JSON-ready): the paper rig's element lengths and nodes."""
    from rubdiag.model import paper_rig

    shaft = paper_rig().shaft
    mass = RHO * math.pi * DISC_RADIUS_M**2 * DISC_THICKNESS_M
    disc = {"outer_radius_m": DISC_RADIUS_M, "thickness_m": DISC_THICKNESS_M,
            # given to ROSS; rubdiag computes its own from r and t
            "mass_kg": mass, "polar_inertia_kg_m2": mass * DISC_RADIUS_M**2 / 2,
            "diametral_inertia_kg_m2": mass * (3 * DISC_RADIUS_M**2 + DISC_THICKNESS_M**2) / 12}
    c_y, c_z = bearing_damping_ns_m
    return {
        "element_lengths_m": list(shaft.element_lengths_m),
        "outer_diameter_m": outer_diameter_m,
        "inner_diameter_m": inner_diameter_m,
        "first_node": shaft.first_node,
        "material": {"youngs_modulus_pa": E, "poisson_ratio": NU, "density_kg_m3": RHO},
        "discs": [{"node": node, **disc} for node in DISC_NODES],
        "bearings": [{"node": node, "k_y_n_m": K_Y, "k_z_n_m": K_Z,
                      "c_y_ns_m": c_y, "c_z_ns_m": c_z} for node in BEARING_NODES],
    }


def inputs() -> dict:
    """Everything the stored values depend on besides the two codes themselves."""
    return {
        "rotors": {"paper-solid-10mm": rotor(),
                   "hollow-40-20mm": rotor(0.040, 0.020),
                   "paper-bearing-dampers": rotor(bearing_damping_ns_m=(2e3, 1e3))},
        "critical_speeds": {"rotors": list(N_CRITICAL), "n_forward": N_CRITICAL,
                            "n_forward_variants": N_CRITICAL_VARIANTS},
        "natural_frequencies": {"rotor": "paper-solid-10mm", "speeds_rpm": [0.0, 8000.0],
                                "n_lateral": 6},
        # undamped; at every shaft node u_y then u_z (ROSS x, y), see mode_shape()
        "mode_shapes": {"rotor": "paper-solid-10mm", "speeds_rpm": [0.0, 8000.0],
                        "n_lateral": 4, "directions": ["y", "z"]},
        "unbalance_response": {"rotor": "paper-bearing-dampers",
                               "magnitudes_kg_m": [1.56e-4, 1.56e-4],   # out of phase
                               "phases_rad": [0.3, math.pi + 0.3],
                               "speeds_rpm": [500.0, 1500.0, 1596.0, 3000.0, 6030.0, 8000.0],
                               "points": [[11, "y"], [11, "z"], [19, "y"], [19, "z"],
                                          [4, "z"]]},
        "ross_settings": {"shaft_element": SHAFT_PHYSICS, "variants": VARIANTS,
                          "run_critical_speed_rtol": CRITICAL_RTOL,
                          "run_modal_num_modes": MODAL_NUM_MODES},
    }


def rig(spec: dict):
    """The rubdiag Rig of one rotor of :func:`inputs` (no Rayleigh damping, as in ROSS)."""
    from rubdiag.model import Bearing, Damping, Disc, Material, Rig, Shaft

    return Rig(
        shaft=Shaft(tuple(spec["element_lengths_m"]), spec["outer_diameter_m"],
                    spec["inner_diameter_m"], spec["first_node"]),
        bearings=tuple(Bearing(b["node"], b["k_y_n_m"], b["k_z_n_m"], b["c_y_ns_m"],
                               b["c_z_ns_m"]) for b in spec["bearings"]),
        discs=tuple(Disc(d["node"], outer_radius_m=d["outer_radius_m"],
                         thickness_m=d["thickness_m"]) for d in spec["discs"]),
        material=Material(**spec["material"]),
        damping=Damping(0.0, 0.0, (1.0, 2.0)),
        name="paper rig shaft + discs + bearings",
    )


# ---------------------------------------------------------------- rubdiag's values


def rubdiag_values(inp: dict) -> dict:
    """rubdiag's answers, in the layout of the stored ``ross`` values."""
    from rubdiag.assembly import assemble
    from rubdiag.modal import critical_speeds, modes, unbalance_response
    from rubdiag.model import Unbalance

    rotors = inp["rotors"]
    crit = inp["critical_speeds"]
    out = {"forward_critical_speeds_rpm": {
        name: list(critical_speeds(assemble(rig(rotors[name])), n=crit["n_forward"][name]) / RPM)
        for name in crit["rotors"]}}

    nat = inp["natural_frequencies"]
    model = assemble(rig(rotors[nat["rotor"]]))
    out["natural_frequencies_rad_s"] = [
        list(modes(model, speed * RPM, n_modes=nat["n_lateral"], damped=False).damped_frequencies)
        for speed in nat["speeds_rpm"]]

    shp = inp["mode_shapes"]
    spec = rotors[shp["rotor"]]
    model = assemble(rig(spec))
    nodes = range(spec["first_node"], spec["first_node"] + len(spec["element_lengths_m"]) + 1)
    rows = [model.dofs.index(node, d) for d in shp["directions"] for node in nodes]
    shapes = [[mode_shape(column) for column in
               modes(model, speed * RPM, n_modes=shp["n_lateral"], damped=False).shapes[rows].T]
              for speed in shp["speeds_rpm"]]
    out["mode_shapes"] = _parts(shapes)

    unb = inp["unbalance_response"]
    response = unbalance_response(
        assemble(rig(rotors[unb["rotor"]])), np.asarray(unb["speeds_rpm"]) * RPM,
        Unbalance(tuple(unb["magnitudes_kg_m"]), tuple(unb["phases_rad"])),
        points=[tuple(p) for p in unb["points"]]).amplitudes
    out["unbalance_response"] = _polar(response)
    return out


def _polar(response) -> dict:
    """A complex (speeds × points) array as plain amplitude and phase lists."""
    return {"amplitude_m": np.abs(response).tolist(), "phase_rad": np.angle(response).tolist()}


def mode_shape(values) -> np.ndarray:
    """A mode's lateral translations (u_y at every shaft node, then u_z) scaled to unit
    largest modulus, that entry real positive (the first of equal moduli: on this symmetric
    rotor mirror nodes tie, so compare shapes up to a phase, see :func:`shape_agreement`)."""
    v = np.asarray(values, dtype=complex)
    return v / v[np.argmax(np.abs(v))]


def _parts(shapes) -> dict:
    """Complex shapes (speeds × modes × entries) as plain real and imaginary lists."""
    a = np.asarray(shapes)
    return {"real": a.real.tolist(), "imag": a.imag.tolist()}


def shapes(values: dict) -> np.ndarray:
    """The stored mode shapes, complex (speeds × modes × entries)."""
    parts = values["mode_shapes"]
    return np.asarray(parts["real"]) + 1j * np.asarray(parts["imag"])


def shape_agreement(ours, theirs) -> tuple[np.ndarray, np.ndarray]:
    """(1 − MAC, largest entry-wise difference after the best phase) of each pair of shapes
    (speeds × modes × entries; theirs with unit largest modulus).

    MAC = |a^H b|² / (a^H a · b^H b) is 1 for proportional shapes whatever the complex scale.
    Entry-wise: ours is scaled by the complex c minimising ‖c·ours − theirs‖ (the
    least-squares phase and size), then max |c·ours − theirs| over the entries.
    """
    a, b = np.asarray(ours), np.asarray(theirs)
    ab = np.sum(a.conj() * b, axis=-1)
    aa = np.sum(np.abs(a) ** 2, axis=-1)
    bb = np.sum(np.abs(b) ** 2, axis=-1)
    mac = np.abs(ab) ** 2 / (aa * bb)
    c = ab / aa
    return 1.0 - mac, np.max(np.abs(c[..., None] * a - b), axis=-1)


def arrays(values: dict) -> dict[str, np.ndarray]:
    """The values of :func:`rubdiag_values` / :func:`ross_values` as one array per quantity
    (the unbalance response complex), for comparing."""
    out = {f"forward critical speeds (rpm), {name}": np.asarray(speeds)
           for name, speeds in values["forward_critical_speeds_rpm"].items()}
    out["natural frequencies (rad/s)"] = np.asarray(values["natural_frequencies_rad_s"])
    unb = values["unbalance_response"]
    out["unbalance response (m)"] = (np.asarray(unb["amplitude_m"])
                                     * np.exp(1j * np.asarray(unb["phase_rad"])))
    return out


def largest_differences(ours: dict, theirs: dict) -> dict[str, float]:
    """max |ours − theirs| / |theirs| per quantity of :func:`arrays`."""
    a, b = arrays(ours), arrays(theirs)
    return {key: float(np.max(np.abs(a[key] - b[key]) / np.abs(b[key]))) for key in b}


# ---------------------------------------------------------------- ROSS's values


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


def ross_rotor(rs, spec: dict, **physics):
    """One rotor of :func:`inputs` in ROSS (6 DOF per node; axial and torsional DOFs free);
    ``physics`` overrides :data:`SHAFT_PHYSICS`."""
    mat = spec["material"]
    steel = rs.Material(name="rubdiag_steel", rho=mat["density_kg_m3"],
                        E=mat["youngs_modulus_pa"], Poisson=mat["poisson_ratio"])
    options = {**SHAFT_PHYSICS, **physics}
    first = spec["first_node"]
    shaft = [rs.ShaftElement(L=length, idl=spec["inner_diameter_m"],
                             odl=spec["outer_diameter_m"], material=steel, **options)
             for length in spec["element_lengths_m"]]
    discs = [rs.DiskElement(n=d["node"] - first, m=d["mass_kg"],
                            Id=d["diametral_inertia_kg_m2"], Ip=d["polar_inertia_kg_m2"])
             for d in spec["discs"]]
    bearings = [rs.BearingElement(n=b["node"] - first, kxx=b["k_y_n_m"], kyy=b["k_z_n_m"],
                                  cxx=b["c_y_ns_m"], cyy=b["c_z_ns_m"])
                for b in spec["bearings"]]
    return rs.Rotor(shaft, discs, bearings)


def ross_num_modes(n: int) -> int:
    """``num_modes`` for ROSS: it keeps num_modes // 2 modes (both whirls, plus torsion)."""
    return max(12, 4 * n + 8)


def net_whirl(evector, number_dof: int) -> tuple[float, float]:
    """(whirl ratio, lateral share) of a ROSS eigenvector (state space; λ with Im λ > 0).

    Whirl ratio as in rubdiag: 2 Σ Im(x·conj(y)) / Σ(|x|² + |y|²) over the shaft nodes,
    +1 circular forward … −1 circular backward. Lateral share: the fraction of |evector|²
    in the lateral DOFs (x, y, α, β), ~0 for the torsional and axial modes.
    """
    q = np.asarray(evector)
    q = q[: q.size // 2].reshape(-1, number_dof)      # per node [x, y, z, α, β, θ]
    x, y = q[:, 0], q[:, 1]
    den = np.sum(np.abs(x) ** 2 + np.abs(y) ** 2)
    ratio = 2.0 * np.sum((x * y.conj()).imag) / den if den > 0 else 0.0
    lateral = np.sum(np.abs(q[:, [0, 1, 3, 4]]) ** 2) / np.sum(np.abs(q) ** 2)
    return float(ratio), float(lateral)


def forward_crossings(rotor, result, n: int):
    """(the ``n`` lowest forward critical speeds in rad/s, every crossing) of ROSS's
    ``run_critical_speed`` result.

    The whirl of a crossing is the net whirl of ROSS's own eigenvector there, not ROSS's
    ``whirl_direction`` label: ROSS says "Mixed" unless every node's orbit whirls the same
    way, and a node that sits at a node of the mode shape (e.g. mid-span in an
    antisymmetric mode, amplitude ~1e-8 of the maximum) whirls either way by round-off.
    ``crossings`` holds (rpm, ROSS label, net whirl ratio, lateral share) of each.
    """
    crossings, forward = [], []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for i, (w_n, w_d, label) in enumerate(zip(result.wn(), result.wd(),
                                                  result.whirl_direction, strict=True)):
            # the same (memoised) run_modal call that run_critical_speed made for mode i
            modal = rotor.run_modal(w_d, ross_num_modes(n))
            ratio, lateral = net_whirl(modal.evectors[:, i], rotor.number_dof)
            crossings.append((w_n / RPM, str(label), ratio, lateral))
            if ratio > 0 and lateral > 0.5:
                forward.append(w_n)
    return np.sort(forward)[:n], crossings


def ross_forward_rpm(rs, spec: dict, n: int, **physics) -> list[float]:
    """ROSS's ``n`` lowest forward critical speeds (rpm) of one rotor."""
    rotor = ross_rotor(rs, spec, **physics)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_critical_speed(num_modes=ross_num_modes(n), rtol=CRITICAL_RTOL)
    return list(forward_crossings(rotor, result, n)[0] / RPM)


def ross_values(rs, inp: dict) -> tuple[dict, dict]:
    """(ROSS's answers in the layout of :func:`rubdiag_values`, ROSS's variants' critical
    speeds in rpm)."""
    rotors = inp["rotors"]
    crit = inp["critical_speeds"]
    out = {"forward_critical_speeds_rpm": {
        name: ross_forward_rpm(rs, rotors[name], crit["n_forward"][name])
        for name in crit["rotors"]}}
    n = crit["n_forward_variants"]
    variants = {label: {name: ross_forward_rpm(rs, rotors[name], n, **physics)
                        for name in crit["rotors"]}
                for label, physics in inp["ross_settings"]["variants"].items()}

    nat = inp["natural_frequencies"]
    spec = rotors[nat["rotor"]]
    rotor = ross_rotor(rs, spec)
    shp = inp["mode_shapes"]
    assert shp["rotor"] == nat["rotor"] and set(shp["speeds_rpm"]) <= set(nat["speeds_rpm"])
    # rubdiag y -> ROSS x (dof 0 of each node), z -> y (dof 1); all nodes are shaft nodes
    offsets = [0 if d == "y" else 1 for d in shp["directions"]]
    out["natural_frequencies_rad_s"], mode_shapes = [], []
    for speed in nat["speeds_rpm"]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            modal = rotor.run_modal(speed * RPM, num_modes=MODAL_NUM_MODES)
        # lateral modes only: rubdiag models no torsion (nor the axial rigid-body mode)
        lateral = [i for i, w in enumerate(modal.wd) if w > 1.0
                   and net_whirl(modal.evectors[:, i], rotor.number_dof)[1] > 0.5]
        out["natural_frequencies_rad_s"].append(
            [float(modal.wd[i]) for i in lateral[: nat["n_lateral"]]])
        if speed in shp["speeds_rpm"]:
            ev = np.asarray(modal.evectors)
            q = ev[: ev.shape[0] // 2].reshape(-1, rotor.number_dof, ev.shape[1])
            mode_shapes.append([mode_shape(np.concatenate([q[:, k, i] for k in offsets]))
                                for i in lateral[: shp["n_lateral"]]])
    out["mode_shapes"] = _parts(mode_shapes)

    unb = inp["unbalance_response"]
    spec = rotors[unb["rotor"]]
    rotor = ross_rotor(rs, spec)
    first = spec["first_node"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_unbalance_response(
            node=[d["node"] - first for d in spec["discs"]],
            unbalance_magnitude=list(unb["magnitudes_kg_m"]),
            unbalance_phase=list(unb["phases_rad"]),
            frequency=np.asarray(unb["speeds_rpm"]) * RPM)
    # rubdiag y -> ROSS x (dof 0 of the node), z -> y (dof 1)
    rows = [rotor.number_dof * (node - first) + (0 if direction == "y" else 1)
            for node, direction in unb["points"]]
    out["unbalance_response"] = _polar(np.asarray(result.forced_resp)[rows, :].T)
    return out, variants


def generate(rs) -> dict:
    """The whole reference file, computed now."""
    import importlib.metadata as meta

    import scipy

    inp = inputs()
    values, variants = ross_values(rs, inp)
    return {
        "about": "ROSS's answers for the rotors of tests/modal/test_ross.py; written by "
                 "scripts/ross_references.py, described in data/README.md",
        "generated": {"date": datetime.datetime.now(datetime.UTC).date().isoformat(),
                      "ross": rs.__version__, "python": platform.python_version(),
                      "numpy": np.__version__, "scipy": scipy.__version__,
                      "plotly": meta.version("plotly")},
        "inputs": inp,
        "ross": values,
        "ross_variants_forward_critical_speeds_rpm": variants,
    }


def dumps(data: dict) -> str:
    """JSON with every innermost list or object (one without lists or objects inside) on
    one line."""
    text = json.dumps(data, indent=1, ensure_ascii=False)
    for innermost in (r"\[[^\[\]{}]*\]", r"\{[^\[\]{}]*\}"):
        text = re.sub(innermost, lambda m: re.sub(r"([\[{])\s+|\s+([\]}])|\s*\n\s*",
                                                  lambda g: g[1] or g[2] or " ", m.group()),
                      text)
    return text + "\n"


def load(path: Path = PATH) -> dict:
    return json.loads(path.read_text(encoding="utf-8"))


def print_agreement(stored: dict) -> None:
    print(f"rubdiag vs ROSS {stored['generated']['ross']} "
          f"(stored {stored['generated']['date']}), largest relative difference:")
    for key, d in largest_differences(rubdiag_values(stored["inputs"]), stored["ross"]).items():
        print(f"  {key:<50} {d:.1e}")
    one_minus_mac, entrywise = shape_agreement(shapes(rubdiag_values(stored["inputs"])),
                                               shapes(stored["ross"]))
    print(f"  {'mode shapes: 1 - MAC':<50} {np.max(one_minus_mac):.1e}")
    print(f"  {'mode shapes: entry-wise (unit max, best phase)':<50} {np.max(entrywise):.1e}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--agreement", action="store_true",
                        help="only print rubdiag's agreement with the stored file (no ROSS)")
    args = parser.parse_args(argv)
    if args.agreement:
        print_agreement(load())
        return 0
    try:
        rs = import_ross()
    except ImportError as exc:
        raise SystemExit(f"needs ROSS ({exc}); see this script's docstring for a venv") from None
    fresh = generate(rs)
    PATH.write_text(dumps(fresh), encoding="utf-8")
    print(f"wrote {PATH.relative_to(PATH.parents[1])} (ROSS {rs.__version__})")
    print_agreement(fresh)
    return 0


if __name__ == "__main__":
    sys.exit(main())
