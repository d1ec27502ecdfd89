"""The dataset format's constants, in one light module (no simulator behind it).

``SCHEMA_VERSION`` is hashed into every run id (:mod:`rubdiag.dataset._ids`) and written in
every ``dataset.json`` (:mod:`rubdiag.dataset._store`); it is raised when either meaning
changes, so that old ids and old folders are refused rather than silently mixed with new
ones. The column names are those of the rows (:mod:`rubdiag.dataset._rows`), which readers
of a stored dataset (:mod:`rubdiag.learn`) use without importing the simulator.
"""

SCHEMA_VERSION = 1

#: Between channel and feature in column names: ``shaft11_y_disp__amp_1x``.
SEPARATOR = "__"

ID_COLUMNS = ("run_id", "point_id", "replicate")
#: The ``model`` column: which model made the row (``Run.model_kind``). Metadata, never a
#: feature; a dataset made before the column existed is of the full model, and
#: :func:`rubdiag.dataset.load` fills it so.
MODEL_COLUMN = "model"
MODEL_KINDS = ("full", "reduced")
PROVENANCE = ("rubdiag_version", "status", "message", "wall_s", "simulate_s")
#: ``status`` of a row: finished; stopped by the simulator (no convergence, non-finite
#: state); over the per-run wall-time limit; anything else that raised.
STATUSES = ("ok", "diverged", "timeout", "error")

#: The mark of a probe pair's channel: ``shaft11_y_disp`` and ``shaft11_z_disp`` are the
#: pair ``shaft11_yz_disp`` (:func:`pair_channel`).
PAIR_MARK = "yz"


def pair_channel(y_name: str, z_name: str) -> str | None:
    """The channel name of the y/z probe pair ``y_name``, ``z_name``: the two names with
    their one differing ``_``-separated part (``y`` in one, ``z`` in the other) written
    ``yz``; None when the names do not differ so (a pair of freely named probes has no
    name that tells its probes back)."""
    a, b = str(y_name).split("_"), str(z_name).split("_")
    if len(a) != len(b):
        return None
    differ = [i for i, (p, q) in enumerate(zip(a, b, strict=True)) if p != q]
    if len(differ) != 1 or (a[differ[0]], b[differ[0]]) != ("y", "z"):
        return None
    a[differ[0]] = PAIR_MARK
    return "_".join(a)


def pair_probes(channel: str) -> tuple[str, str] | None:
    """The y and z probes of a pair channel (the inverse of :func:`pair_channel`), or None
    when ``channel`` is not named as a pair."""
    parts = str(channel).split("_")
    if parts.count(PAIR_MARK) != 1:
        return None
    i = parts.index(PAIR_MARK)
    return ("_".join([*parts[:i], "y", *parts[i + 1:]]),
            "_".join([*parts[:i], "z", *parts[i + 1:]]))


def _pair_features() -> tuple[str, ...]:
    from rubdiag.signal._fullspectrum import OrbitMeasures
    from rubdiag.signal._orders import HALF_ORDERS, THIRD_ORDERS, order_label

    lines = [f"{d}_{order_label(k)}" for k in sorted(HALF_ORDERS + THIRD_ORDERS)
             for d in ("fwd", "rev")]
    return (*lines, *OrbitMeasures.__dataclass_fields__)


def __getattr__(name: str):
    """``PAIR_FEATURES``, made on first use (PEP 562): the features of a pair channel, in
    their column order — those of :func:`rubdiag.signal._fullspectrum.orbit_features`
    (``fwd_<k>``, ``rev_<k>`` order by order, then the orbit measures). Their names come
    from the signal layer, which the run ids (:data:`SCHEMA_VERSION`) need not import."""
    if name == "PAIR_FEATURES":
        globals()[name] = value = _pair_features()
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
