"""A simulated run's result, and its file.

Result files (``result.save(path)``, ``load_result(path)``) are NumPy ``.npz`` archives:
every array of the result under its field name (``system.<field>``, ``episodes.<field>``)
plus ``meta``, a JSON document with the rubdiag version, the run description (the rig as in
its TOML file, SI units: :func:`~rubdiag.simulation._run_dict.run_to_dict`) and the scalar
fields. Written atomically (a temporary file in the same folder, then renamed); the folder
must exist.
"""

from __future__ import annotations

import dataclasses
import io
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rubdiag._atomic import write_bytes
from rubdiag._tolerances import BOUND_SLACK
from rubdiag._version import __version__
from rubdiag.simulation._result import EpisodeLog, StatusLog, SystemResult
from rubdiag.simulation._run import Run
from rubdiag.simulation._run_dict import run_from_dict, run_to_dict
from rubdiag.simulation._sensors import sensor_signals

__all__ = ["FORMAT_VERSION", "SimulationResult", "load_result"]

# Version 2: contact elements numbered from 1 in the logs (format 1: from 0); the per-step
# status-segment log. Format 1 files are refused: their runs are simulated again.
FORMAT_VERSION = 2
_LOGS = {"episodes": EpisodeLog, "status_segments": StatusLog}


@dataclass(frozen=True)
class SimulationResult:
    """A simulated run: its description, waveforms, contact forces/status and event log.

    Parameters
    ----------
    run : Run
        What was simulated.
    points : tuple of str
        Names of the recorded displacements, e.g. ``"shaft 11 y"``, ``"casing 1 y"``.
    system : SystemResult
        Everything the integrator computed: samples ``t`` (s), ``q`` (m, columns =
        ``points``), ``contact_fn``/``contact_ft`` (N) and ``contact_status`` (1 open,
        2 sliding, 3 sticking) per element, the per-step event log ``episodes``, step-size
        history, Newton counts, the energy ledger, ``status`` and ``message``.
    wall_s : float
        Wall-clock time of ``simulate`` (s).
    version : str
        rubdiag version that produced it.
    """

    run: Run
    points: tuple[str, ...]
    system: SystemResult
    wall_s: float
    version: str = __version__

    # --- convenient views ----------------------------------------------------------------
    @property
    def t(self) -> np.ndarray:
        return self.system.t

    @property
    def fs(self) -> float:
        """Sampling rate of the waveforms (Hz)."""
        return 1.0 / self.run.output_dt_s

    @property
    def status(self) -> int:
        return self.system.status

    @property
    def message(self) -> str:
        return self.system.message

    @property
    def success(self) -> bool:
        return self.system.status == 0

    @property
    def window(self) -> np.ndarray:
        """Boolean mask of the samples in the analysis window (t >= discard_s)."""
        return self.t >= self.run.discard_s - BOUND_SLACK

    def displacement(self, point: str, windowed: bool = False) -> np.ndarray:
        """Recorded displacement (m) of a point such as ``"shaft 11 y"``."""
        try:
            j = self.points.index(point)
        except ValueError:
            raise ValueError(f"no recorded point {point!r} (recorded: "
                             f"{', '.join(self.points)})") from None
        q = self.system.q[:, j]
        return q[self.window] if windowed else q

    @property
    def angle_rad(self) -> np.ndarray:
        """The shaft angle φ (rad) at the samples ``t``: ∫ Ω dt from 0, exact."""
        return self.run.angle_at(self.t)

    @property
    def tacho(self) -> np.ndarray:
        """A once-per-revolution pulse channel at the samples ``t``, as a key-phasor gives
        it: 1 over the first 5 % of each revolution (φ mod 2π < 0.1 π), else 0 — the input
        of ``rubdiag.signal``'s tacho functions for simulated runs, as for measured ones."""
        return (np.mod(self.angle_rad, 2 * np.pi) < 0.1 * np.pi).astype(float)

    def sensor_signals(self, windowed: bool = False) -> dict[str, np.ndarray]:
        """The run's sensors (``run.sensors``), anti-alias filtered and sampled at the
        output rate (:mod:`rubdiag.simulation._sensors`): name -> values at ``t`` (SI: m, m/s,
        m/s², N); only the analysis window with ``windowed``."""
        signals = sensor_signals(self.run, self.system)
        if windowed:
            return {k: v[self.window] for k, v in signals.items()}
        return signals

    @property
    def linear_approach_m(self) -> float:
        """The largest radial approach of the linear (contact-free) unbalance response over
        all contact elements (m): where the gap ramp starts, and, over g0, how deep the
        rotor would reach into the casing if nothing stopped it. NaN for results saved
        before it was recorded."""
        return float(self.system.extra.get("linear_approach_m", float("nan")))

    @property
    def n_contacts(self) -> int:
        """How many of the run's nonlinear elements are contacts (numbered first, from 1);
        the fault elements (a breathing crack, a loose pedestal) and the journal bearings'
        films follow them."""
        faults = self.run.faults
        n_faults = 0 if faults is None else len(faults.elements(self.run.rig))
        n_films = sum(b.journal is not None for b in self.run.rig.bearings)
        return self.system.contact_fn.shape[1] - n_faults - n_films

    def contact_episodes(self) -> EpisodeLog:
        """The episodes of the contact elements (not those of fault elements)."""
        ep = self.system.episodes
        keep = ep.element <= self.n_contacts
        return EpisodeLog(**{f.name: getattr(ep, f.name)[keep]
                             for f in dataclasses.fields(EpisodeLog)})

    def window_episodes(self) -> EpisodeLog:
        """Contact episodes that start inside the analysis window."""
        ep = self.contact_episodes()
        keep = ep.t_start >= self.run.discard_s
        return EpisodeLog(**{f.name: getattr(ep, f.name)[keep]
                             for f in dataclasses.fields(EpisodeLog)})

    def summary(self) -> dict:
        """Headline numbers over the analysis window (SI units), as ``rubdiag simulate
        --json`` prints them. Forces come from the per-step event log (peaks are shorter
        than the output interval) over the episodes that start in the window, displacements
        from the recorded waveforms."""
        started = self.window_episodes()
        first = started.element == 1
        window = self.window
        out = {
            "label": self.run.label,
            "model": self.run.model_kind,
            "status": self.status,
            "message": self.message,
            "speed_rpm": self.run.speed_rpm,
            "gap_m": self.run.gap_m,
            "window_s": [self.run.discard_s, float(self.t[-1]) if self.t.size else 0.0],
            "dt_s": self.run.dt_s,
            "n_steps": int(self.system.n_steps),
            "wall_s": self.wall_s,
            "n_episodes": len(started),
            "max_contact_force_n": _max(started.peak_normal_force),
            "contact1_max_force_n": _max(started.peak_normal_force[first]),
            "contact1_sliding_entries": int(started.n_slide_entries[first].sum()),
            "contact1_sticking_entries": int(started.n_stick_entries[first].sum()),
        }
        for key, prefix in (("shaft", "shaft"), ("casing", "casing")):
            names = [p for p in self.points if p.startswith(prefix) and p.endswith(" y")]
            if names and window.any():
                out[f"{key}_max_y_m"] = float(self.displacement(names[0], True).max())
        return out

    def to_frame(self):
        """Waveforms as a DataFrame indexed by time (s): one column per recorded point (m),
        then ``fn_k``, ``ft_k`` (N) and ``status_k`` for contact element k = 1…; with a
        speed profile also ``angle_rad`` and ``tacho``."""
        import pandas as pd

        cols = {p: self.system.q[:, j] for j, p in enumerate(self.points)}
        for k in range(self.system.contact_fn.shape[1]):
            cols[f"fn_{k + 1}"] = self.system.contact_fn[:, k]
            cols[f"ft_{k + 1}"] = self.system.contact_ft[:, k]
            cols[f"status_{k + 1}"] = self.system.contact_status[:, k]
        if self.run.speed_profile is not None:    # the measured-signal path needs them
            cols["angle_rad"] = self.angle_rad
            cols["tacho"] = self.tacho
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t_s"))

    # --- files ---------------------------------------------------------------------------
    def save(self, path: str | Path) -> Path:
        """Write the result (see the module docstring for the format); returns the path."""
        path = Path(path)
        if path.suffix != ".npz":
            path = path.with_suffix(".npz")
        arrays, scalars = {}, {}
        for f in dataclasses.fields(SystemResult):
            value = getattr(self.system, f.name)
            if f.name in _LOGS:
                for g in dataclasses.fields(value):
                    arrays[f"{f.name}.{g.name}"] = getattr(value, g.name)
            elif isinstance(value, np.ndarray):
                arrays[f"system.{f.name}"] = value
            else:
                scalars[f.name] = _jsonable(value)
        meta = {"format": "rubdiag.simulation-result", "format_version": FORMAT_VERSION,
                "rubdiag_version": self.version, "points": list(self.points),
                "wall_s": self.wall_s, "run": run_to_dict(self.run), "system": scalars}
        if path.is_dir():
            raise IsADirectoryError(f"{path}: is a folder; give a file name")
        if not path.parent.is_dir():   # say so before writing, naming the file asked for
            raise FileNotFoundError(f"{path}: the folder {path.parent} does not exist")
        sink = io.BytesIO()
        np.savez_compressed(sink, meta=np.array(json.dumps(meta)), **arrays)
        return write_bytes(path, sink.getvalue())     # a reader never sees half a file


def load_result(path: str | Path) -> SimulationResult:
    """Read a result written by :meth:`SimulationResult.save`.

    Parameters
    ----------
    path : str or Path
        The result file.

    Returns
    -------
    SimulationResult
        The result as saved.
    """
    path = Path(path)
    try:
        archive = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as exc:
        raise ValueError(f"{path}: not a rubdiag result file ({exc})") from None
    with archive:
        if "meta" not in archive.files:
            raise ValueError(f"{path}: not a rubdiag result file (no 'meta' entry)")
        meta = json.loads(str(archive["meta"]))
        if meta.get("format") != "rubdiag.simulation-result":
            raise ValueError(f"{path}: not a rubdiag result file")
        version = meta.get("format_version", 1)
        if version > FORMAT_VERSION:
            raise ValueError(f"{path}: result format {version} is newer than this rubdiag "
                             f"reads ({FORMAT_VERSION}): upgrade rubdiag")
        if version < FORMAT_VERSION:
            raise ValueError(f"{path}: result format {version} is older than this rubdiag "
                             f"reads ({FORMAT_VERSION}: contact elements numbered from 1, "
                             "the per-step status log): simulate the run again")
        fields = {}
        for f in dataclasses.fields(SystemResult):
            if f.name in _LOGS:
                if f"{f.name}.t_start" in archive.files:
                    fields[f.name] = _LOGS[f.name](**{
                        g.name: archive[f"{f.name}.{g.name}"]
                        for g in dataclasses.fields(_LOGS[f.name])})
            elif f"system.{f.name}" in archive.files:
                fields[f.name] = archive[f"system.{f.name}"]
            else:   # JSON has no NaN: a NaN scalar (e.g. failure_time) was stored as null
                value = meta["system"][f.name]
                fields[f.name] = float("nan") if value is None else value
    return SimulationResult(run=run_from_dict(meta["run"]), points=tuple(meta["points"]),
                            system=SystemResult(**fields), wall_s=meta["wall_s"],
                            version=meta["rubdiag_version"])


def _max(values: np.ndarray) -> float:
    return float(values.max()) if values.size else 0.0


def _jsonable(value):
    if isinstance(value, dict):
        return {k: _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, float) and not np.isfinite(value):
        return None if np.isnan(value) else str(value)
    return value
