"""What an evaluation says against its model: the warnings ``rubdiag train`` prints, writes
into ``report.md``, ``metrics.json`` and ``model.json``, and ``predict`` repeats.

A model is saved whatever it scored — a poor model is still worth a report — but these
signs that it learnt little must not go unsaid:

* a class with fewer than :data:`MIN_RUNS_PER_CLASS` runs;
* a class of which no held-out run was recognised (recall 0);
* held-out macro-F1 no higher than the best baseline's (the same estimator on the 1×
  levels, the speed or the design factors alone): the features add nothing;
* held-out macro-F1 inside chance: at most the upper end of the shuffled-label control's
  permutation-null interval.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MIN_RUNS_PER_CLASS", "training_warnings"]

#: Fewest runs of a class for its held-out scores to mean much: two per fold of the
#: default 5-fold split. With fewer, a recall moves by 0.1 or more per run, and folds
#: without a run of the class test nothing of it.
MIN_RUNS_PER_CLASS = 10


def training_warnings(ev) -> list[str]:
    """The warnings of an :class:`~rubdiag.learn.evaluate.Evaluation` (module docstring),
    one sentence each; empty when none applies."""
    out = []
    for c, n in ev.class_counts.items():
        if n < MIN_RUNS_PER_CLASS:
            out.append(f"class {c} has {n} runs, fewer than the {MIN_RUNS_PER_CLASS} "
                       "(MIN_RUNS_PER_CLASS) its held-out scores need to mean much")
    for c, row in ev.per_class.iterrows():
        if row["support"] > 0 and row["recall"] == 0:
            out.append(f"class {c}: held-out recall 0 (none of its {int(row['support'])} "
                       "scored runs was recognised)")
    f1 = ev.scores["macro_f1"].value
    if ev.baselines is not None and not ev.baselines.empty:
        values = {name: s.value for name, s in ev.baselines["macro_f1"].items()
                  if np.isfinite(s.value)}
        if values:
            best = max(values, key=values.get)
            if f1 <= values[best]:
                out.append(f"held-out macro-F1 {f1:.3f} is no higher than the best "
                           f"baseline's ({best}: {values[best]:.3f}): on this data the "
                           "model does no better than that baseline alone")
    if ev.shuffled is not None and f1 <= ev.shuffled["null_hi"]:
        out.append(f"held-out macro-F1 {f1:.3f} is within chance (the shuffled-label "
                   f"control's null interval reaches {ev.shuffled['null_hi']:.3f})")
    return out
