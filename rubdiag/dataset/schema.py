"""The dataset format's constants, in one light module (no simulator behind it).

``SCHEMA_VERSION`` is hashed into every run id (:mod:`rubdiag.dataset.ids`) and written in
every ``dataset.json`` (:mod:`rubdiag.dataset.store`); it is raised when either meaning
changes, so that old ids and old folders are refused rather than silently mixed with new
ones. The column names are those of the rows (:mod:`rubdiag.dataset.rows`), which readers
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
