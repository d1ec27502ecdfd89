"""Checks of the files a command reads and writes, done before any work.

A command checks its outputs first (a long simulation must not end in "no such folder"), then
its inputs. Every check raises an exception that :func:`rubdiag.cli.main` prints as one line
naming the option and the path.
"""

from __future__ import annotations

import os
from pathlib import Path

from rubdiag.cli._defaults import FromLibrary


def output_file(path, option: str = "--out") -> Path:
    """A file the command will write: its folder must exist and be writable, and the path
    must not be a folder. Missing folders are not created (a typo would make one)."""
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(f"{option} {path}: is a folder; give a file name")
    folder = path.parent
    if not folder.is_dir():
        what = "is not a folder" if folder.exists() else "does not exist (create it first)"
        raise FileNotFoundError(f"{option} {path}: the folder {folder} {what}")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise PermissionError(f"{option} {path}: the folder {folder} is not writable")
    return path


def output_folder(path, option: str = "--out") -> Path:
    """A folder the command will write into: created now (with its parents) if missing."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise NotADirectoryError(f"{option} {path}: is a file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OSError(f"{option} {path}: cannot create the folder ({exc.strerror})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise PermissionError(f"{option} {path}: the folder is not writable")
    return path


def add_rig_option(parser) -> None:
    """Add ``--rig FILE|PRESET`` (a path; :func:`load_rig` reads it), whose help names every
    preset of :data:`rubdiag.model.PRESETS`."""
    parser.add_argument("--rig", type=Path, action=FromLibrary,
                        shows={"presets": "rubdiag.model:PRESETS"},
                        help="rig TOML file or preset ({presets}; default: the study's paper "
                        "rig)")


def input_file(path, option: str | None, what: str) -> Path:
    """A file the command will read (``option`` None: a positional argument): it must exist
    and not be a folder."""
    path = Path(path)
    name = f"{path}" if option is None else f"{option} {path}"
    if not path.exists():
        raise FileNotFoundError(f"{name}: no such file")
    if path.is_dir():
        raise IsADirectoryError(f"{name}: is a folder, not {what}")
    return path


def load_rig(path):
    """The rig of a ``--rig FILE|PRESET`` option (None: the study's paper rig); a preset
    name (:data:`rubdiag.model.PRESETS`) that is not a file is the preset."""
    from rubdiag.model import PRESETS, load_rig, paper_rig, preset_rig

    if path is None:
        return paper_rig()
    if not Path(path).exists():
        if str(path) in PRESETS:
            return preset_rig(str(path))
        raise FileNotFoundError(f"--rig {path}: no such file or preset (presets: "
                                f"{', '.join(PRESETS)})")
    return load_rig(input_file(path, "--rig", "a rig TOML file"))


def load_result(path, option: str | None = None):
    """A saved simulation result; a truncated or corrupt archive is one clear error."""
    import zipfile
    import zlib

    from rubdiag.simulation import load_result

    path = input_file(path, option, "a result file")
    if not zipfile.is_zipfile(path):
        raise ValueError(f"{path}: not a rubdiag result file (not a complete .npz archive: "
                         "truncated, corrupt or another format)")
    try:
        return load_result(path)
    except (zipfile.BadZipFile, zlib.error, EOFError, KeyError) as exc:
        raise ValueError(f"{path}: corrupt result file ({exc})") from None
