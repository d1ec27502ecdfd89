"""What :func:`rubdiag.learn._predict` reads: its inputs as files, and each file's speed.

An input is a signal file, a dataset folder (one with a ``design.toml``: its stored rows), a
folder of signal files (every file in it with a signal suffix, :data:`SIGNAL_SUFFIXES`,
sorted by name; not its subfolders, not hidden files) or a glob pattern (``*``, ``?``,
``[…]``; ``**`` for subfolders), expanded here — not by a shell, so it works quoted and on
any system — into its sorted matches, each then read as if given by name. A folder without
a signal file, or a pattern that matches nothing, is refused.

Per-file speeds (:func:`read_speeds`: a CSV of ``file``, ``speed_rpm``; or a mapping) name a
file by its path as given, or by its file name alone (:func:`match_speeds`). Every input
file must be named; a name may leave its speed empty (the file then takes its speed from a
tacho or the estimate). An entry that names no input is ignored, so that one plant-wide
log serves any selection of its records; when an input is missing, the error lists a few
of them, since a misspelt name is the usual cause.
"""

from __future__ import annotations

import glob
import math
import os
from collections.abc import Mapping
from pathlib import Path

import pandas as pd

from rubdiag import _check
from rubdiag.signal._io import SUFFIXES

__all__ = ["SIGNAL_SUFFIXES", "Speeds", "expand_inputs", "is_dataset_folder", "match_speeds",
           "read_speeds", "speeds_per_file"]

#: File suffixes read as signal files in a folder (:func:`rubdiag.signal.read_signals`).
SIGNAL_SUFFIXES = SUFFIXES

_PATTERN = frozenset("*?[")


def is_dataset_folder(path: Path) -> bool:
    """Whether ``path`` is a rubdiag dataset folder (it holds a ``design.toml``)."""
    return (path / "design.toml").is_file()


def expand_inputs(inputs, exclude=()) -> list[tuple[Path, int]]:
    """The files (and dataset folders) of ``inputs``, in order, each with the position of
    the input it came from.

    Parameters
    ----------
    inputs : path, glob pattern, or a list of them
        Signal files, dataset folders, folders of signal files, glob patterns (module
        docstring).
    exclude : iterable of paths
        Files a folder or a pattern leaves out (the speeds file, the output table, when
        they lie among the records).

    Returns
    -------
    list of (Path, int)
        Every file or dataset folder, and the index of its input in ``inputs``.
    """
    given = [inputs] if isinstance(inputs, str | os.PathLike) else list(inputs)
    if not given:
        raise ValueError("inputs is empty (allowed: at least one file, folder or pattern)")
    skip = {os.path.realpath(p) for p in exclude}
    out = []
    for i, item in enumerate(given):
        text = os.fspath(item)
        if _PATTERN & set(text) and not os.path.exists(text):
            matches = sorted(glob.glob(text, recursive=True))
            matches = [Path(m) for m in matches if os.path.realpath(m) not in skip]
            if not matches:
                raise ValueError(f"{text}: the pattern matches no file")
            out += [(f, i) for m in matches for f in _files(m, skip)]
        else:
            out += [(f, i) for f in _files(Path(text), skip)]
    return out


def _files(path: Path, skip: set) -> list[Path]:
    """A folder's signal files (sorted), a dataset folder or a file as it is."""
    if not path.is_dir() or is_dataset_folder(path):
        return [path]
    found = sorted(p for p in path.iterdir()
                   if p.suffix.lower() in SIGNAL_SUFFIXES and not p.name.startswith(".")
                   and p.is_file() and os.path.realpath(p) not in skip)
    if not found:
        raise ValueError(f"{path}: no signal file in the folder (allowed: "
                         f"{', '.join(SIGNAL_SUFFIXES)}) and not a dataset folder (no "
                         "design.toml)")
    return found


class Speeds(dict):
    """Per-file speeds, file -> rpm (None: not given), and where they were read from
    (``source``, named in errors)."""

    def __init__(self, speeds, source: str):
        super().__init__(speeds)
        self.source = source


def read_speeds(path) -> Speeds:
    """The per-file speeds of a CSV file: columns ``file`` (a path, or a file name) and
    ``speed_rpm`` (rpm, > 0; empty: no speed for that file); other columns are ignored.

    Returns
    -------
    Speeds
        A dict ``file`` -> speed in rpm, or None where the cell is empty.
    """
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(f"{path}: is a folder, not a speeds CSV file")
    try:
        table = pd.read_csv(path, dtype={"file": str}, skipinitialspace=True)
    except FileNotFoundError:
        raise FileNotFoundError(f"{path}: no such file") from None
    except (pd.errors.EmptyDataError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: not a CSV table of file, speed_rpm "
                         f"({str(exc).splitlines()[0]})") from None
    missing = [c for c in ("file", "speed_rpm") if c not in table.columns]
    if missing:
        raise ValueError(f"{path}: no column {missing[0]!r} (a speeds file has the columns "
                         f"file, speed_rpm; this one has {', '.join(map(str, table.columns))})")
    speeds = {}
    for line, (name, value) in enumerate(zip(table["file"], table["speed_rpm"], strict=True),
                                         start=2):
        if not isinstance(name, str) or not name.strip():
            raise ValueError(f"{path}, line {line}: the file name is empty")
        name = name.strip()
        if name in speeds:
            raise ValueError(f"{path}: {name!r} is listed twice (allowed: one speed per file)")
        speeds[name] = _speed(value, f"{path}: speed_rpm of {name!r}")
    if not speeds:
        raise ValueError(f"{path}: the speeds file lists no file")
    return Speeds(speeds, str(path))


def _speed(value, name: str) -> float | None:
    """A per-file speed in rpm (> 0), or None for an empty one."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise _check.wrong_type(name, value, "a number of rpm, or empty") from None
    return _check.positive(name, value, "rpm")


def match_speeds(files, speeds: Mapping) -> list[float | None]:
    """The speed of each of ``files`` from ``speeds`` (file -> rpm or None; a
    :class:`Speeds` names its source in errors), where an entry names a file by its path as
    given (the same file once resolved) or, without a folder part, by its file name.

    Every file must be named (by path before by name; by two paths is refused); an entry
    naming no file is ignored; a name shared by several files must be given as paths.
    """
    source = getattr(speeds, "source", "speed_rpm")
    entries = {os.fspath(k): _speed(v, f"{source}: speed_rpm of {os.fspath(k)!r}")
               for k, v in speeds.items()}
    by_path, by_name = {}, {}
    for key in entries:
        if os.path.basename(key) == key:
            by_name[key] = key
        else:
            resolved = os.path.realpath(key)
            if resolved in by_path:
                raise ValueError(f"{source}: {key!r} and {by_path[resolved]!r} name the same "
                                 "file (allowed: one speed per file)")
            by_path[resolved] = key
    files = [Path(f) for f in files]
    real = [os.path.realpath(f) for f in files]
    holders: dict[str, set] = {}
    for f, r in zip(files, real, strict=True):
        holders.setdefault(f.name, set()).add(r)
    keys = []
    for f, r in zip(files, real, strict=True):
        key = by_path.get(r) or by_name.get(f.name)
        if key is None:
            used = {by_path.get(x) for x in real} | {by_name.get(g.name) for g in files}
            unused = [k for k in entries if k not in used]
            hint = (f"; entries that name no input: {', '.join(unused[:3])}"
                    f"{' …' if len(unused) > 3 else ''}" if unused else "")
            raise ValueError(f"{source}: no speed for {f} (every input file needs an entry, "
                             f"by its path or its file name{hint})")
        if key == f.name and len(holders[f.name]) > 1:
            raise ValueError(f"{source}: {key!r} names {len(holders[key])} input files; "
                             "name them by their paths")
        keys.append(key)
    return [entries[k] for k in keys]


def speeds_per_file(speed_rpm, n_inputs: int, files: list[tuple[Path, int]]
                    ) -> list[float | None]:
    """The given speed of each file of ``files`` (:func:`expand_inputs`) from a per-input
    ``speed_rpm``: a sequence aligned with the ``n_inputs`` inputs (a folder's or a
    pattern's files share its speed) or a mapping (:func:`match_speeds`)."""
    if isinstance(speed_rpm, Mapping):
        return match_speeds([f for f, _ in files], speed_rpm)
    given = list(speed_rpm)
    if len(given) != n_inputs:
        raise ValueError(f"speed_rpm has {len(given)} speeds for {n_inputs} inputs (allowed: "
                         "one number, one per input, or a mapping file -> rpm)")
    speeds = [_speed(v, f"speed_rpm[{i}]") for i, v in enumerate(given)]
    return [speeds[i] for _, i in files]
