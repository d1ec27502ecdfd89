"""What an evaluation says against its model: one list of warnings, made once at training.

A model is saved whatever it scored — a poor model is still worth a report — but these
signs that it learnt little must not go unsaid:

* a class with fewer than :data:`MIN_RUNS_PER_CLASS` runs;
* a class of which no held-out run was recognised (recall 0);
* held-out macro-F1 no higher than the best baseline's (the same estimator on the 1×
  levels, the speed or the design factors alone): the features add nothing;
* held-out macro-F1 inside chance: at most the upper end of the shuffled-label control's
  permutation-null interval;
* the shuffled-label control itself above chance: more shuffles outside their null
  interval than chance allows, which a leak through the split causes.

:func:`training_warnings` makes the list; ``rubdiag train`` prints it (stderr),
``report.md`` renders it under "Warnings", ``metrics.json`` and ``model.json`` store it
(``warnings``) — the same sentences everywhere. A prediction repeats, once per call, only
those that concern it (:func:`prediction_warnings`): a class's run count says how far its
held-out scores can be trusted, which the training told once.
"""

from __future__ import annotations

import numpy as np

__all__ = ["MIN_RUNS_PER_CLASS", "prediction_warnings", "small_class_warnings",
           "training_warnings"]

#: Fewest runs of a class for its held-out scores to mean much: two per fold of the
#: default 5-fold split. With fewer, a recall moves by 0.1 or more per run, and folds
#: without a run of the class test nothing of it.
MIN_RUNS_PER_CLASS = 10


def small_class_warnings(class_counts: dict) -> list[str]:
    """The warnings of the classes with fewer than :data:`MIN_RUNS_PER_CLASS` runs
    (``class_counts``: class -> runs), one sentence each."""
    return [f"class {c} has {n} runs, fewer than the {MIN_RUNS_PER_CLASS} "
            "(MIN_RUNS_PER_CLASS) its held-out scores need to mean much"
            for c, n in class_counts.items() if n < MIN_RUNS_PER_CLASS]


def training_warnings(ev) -> list[str]:
    """The warnings of an :class:`~rubdiag.learn._evaluate.Evaluation` (module docstring),
    one sentence each; empty when none applies.

    Parameters
    ----------
    ev : Evaluation
        An evaluation.

    Returns
    -------
    list of str
        The warnings.
    """
    out = small_class_warnings(ev.class_counts)
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
    shuffled = ev.shuffled
    if shuffled is not None and f1 <= shuffled["null_hi"]:
        out.append(f"held-out macro-F1 {f1:.3f} is within chance (the shuffled-label "
                   f"control's null interval reaches {shuffled['null_hi']:.3f})")
    if shuffled is not None and not shuffled.get("inside", True):
        out.append(f"the shuffled-label control scored above chance: "
                   f"{shuffled['n_outside']} of {shuffled['n_shuffles']} shuffles outside "
                   f"their null interval (chance allows {shuffled['allowed_outside']}); look "
                   "for a leak through the split (runs of one design point on both sides)")
    return out


def prediction_warnings(meta: dict) -> list[str]:
    """The training warnings of a model description (``model.json``) that concern its
    predictions: every one but the small-class counts (:func:`small_class_warnings` of
    its ``class_counts``), in their order."""
    told = set(small_class_warnings(meta.get("class_counts", {})))
    return [w for w in meta.get("warnings", []) if w not in told]
