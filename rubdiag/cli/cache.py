"""The ``cache`` command: where the disk cache of rig-only results is, what it holds, clear it."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser(
        "cache", help="show or clear the disk cache of rig-only results",
        description="Runs keep what depends only on the rig (the assembled and reduced "
        "models, the critical speeds, the threshold of instability on journal bearings) in "
        "a disk cache, keyed by the rig's content, the "
        "rubdiag version and the BLAS kernels, so that the next run of the rig starts at "
        "once. The folder is $RUBDIAG_CACHE_DIR (empty: no disk cache), else the platform's "
        "cache folder (~/.cache/rubdiag on Linux). Deleting it is safe at any time.")
    p.add_argument("--clear", action="store_true", help="delete the cache's files")
    p.set_defaults(func=_cache_command)


def _cache_command(args) -> int:
    from rubdiag import _cache

    where = _cache.folder()
    if where is None:
        print(f"disk cache off ({_cache.ENV} is empty)")
        return 0
    if where.exists() and not where.is_dir():       # runs then cache nothing, silently
        raise ValueError(f"{where}: not a folder, so nothing is cached (allowed: {_cache.ENV} "
                         "naming a folder, or empty to switch the disk cache off)")
    if args.clear:
        print(f"removed {_cache.clear()} files from {where}")
        return 0
    files = _cache.entries()
    size = sum(f.stat().st_size for f in files if f.exists())
    print(f"{where} ({_cache.ENV} to move it; empty to switch the cache off)")
    print(f"{len(files)} files, {size / 1e6:.1f} MB")
    return 0
