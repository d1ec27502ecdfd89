"""Calibrate unknown geometry so that the forward critical speeds hit targets.

The study gives its critical speeds (1500 and 5700 rpm) but not the shaft and disc
geometry. :func:`calibrate` scales chosen geometry *knobs* of a starting rig until its first
forward critical speeds match the targets (least squares on log(speed/target), so one knob
per target gives an exact match).

Knobs (each a positive scale factor applied to the starting rig):

``outer_spans``   shaft elements between a bearing and the nearest disc;
``inner_span``    shaft elements between the first and the last disc;
``overhangs``     shaft elements outside the bearings;
``shaft_diameter`` every shaft element's outer and inner diameter;
``disc_radius``   the outer radius of every disc given by geometry;
``disc_thickness`` the thickness of every disc given by geometry.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass

import numpy as np

from rubdiag.model import Rig

__all__ = ["KNOBS", "Calibration", "calibrate"]


def _element_groups(rig: Rig) -> dict[str, list[int]]:
    """Shaft element indices of the span groups, from the bearing and disc nodes."""
    nodes = list(rig.shaft.nodes)
    bearings = sorted(b.node for b in rig.bearings)
    discs = sorted(d.node for d in rig.discs)
    first, last = bearings[0], bearings[-1]

    def elements(a, b):  # elements between nodes a < b
        return list(range(nodes.index(a), nodes.index(b)))

    groups = {"overhangs": elements(nodes[0], first) + elements(last, nodes[-1])}
    if discs:
        groups["outer_spans"] = elements(first, discs[0]) + elements(discs[-1], last)
        groups["inner_span"] = elements(discs[0], discs[-1])
    return groups


def _scale_lengths(group: str):
    def apply(rig: Rig, s: float) -> Rig:
        idx = _element_groups(rig).get(group, [])
        if not idx:
            raise ValueError(f"knob {group!r} selects no shaft element in this rig")
        lengths = list(rig.shaft.element_lengths_m)
        for i in idx:
            lengths[i] *= s
        return dataclasses.replace(rig, shaft=dataclasses.replace(
            rig.shaft, element_lengths_m=tuple(lengths)))
    return apply


def _scale_diameter(rig: Rig, s: float) -> Rig:
    shaft = rig.shaft
    return dataclasses.replace(rig, shaft=dataclasses.replace(
        shaft, outer_diameters_m=tuple(d * s for d in shaft.outer_diameters_m),
        inner_diameters_m=tuple(d * s for d in shaft.inner_diameters_m)))


def _scale_discs(field: str):
    def apply(rig: Rig, s: float) -> Rig:
        discs = tuple(dataclasses.replace(d, **{field: getattr(d, field) * s})
                      if getattr(d, field) is not None else d for d in rig.discs)
        return dataclasses.replace(rig, discs=discs)
    return apply


#: The fit's gradient tolerance, small enough that the steps' and residuals' tolerances
#: (``rtol / 100``) stop it; and the step of its finite-difference Jacobian in log-scale
#: (0.01 %: far above the critical speeds' rounding).
_GTOL = 1e-12
_DIFF_STEP = 1e-4
KNOBS = {
    "outer_spans": _scale_lengths("outer_spans"),
    "inner_span": _scale_lengths("inner_span"),
    "overhangs": _scale_lengths("overhangs"),
    "shaft_diameter": _scale_diameter,
    "disc_radius": _scale_discs("outer_radius_m"),
    "disc_thickness": _scale_discs("thickness_m"),
}


@dataclass(frozen=True)
class Calibration:
    """The calibrated rig, the scale of each knob, and the speeds reached (rad/s).

    Parameters
    ----------
    rig : Rig
        The calibrated rig.
    knobs : tuple of str
        The knobs scaled (:data:`KNOBS`).
    scales : tuple of float
        The factor applied to each knob (1: unchanged).
    targets : tuple of float
        The target forward critical speeds (rad/s).
    speeds : tuple of float
        The forward critical speeds of the calibrated rig (rad/s).
    n_evaluations : int
        How many rigs the search assembled and solved.
    """

    rig: Rig
    knobs: tuple[str, ...]
    scales: tuple[float, ...]
    targets: tuple[float, ...]
    speeds: tuple[float, ...]
    n_evaluations: int

    @property
    def relative_errors(self) -> tuple[float, ...]:
        return tuple(s / t - 1.0 for s, t in zip(self.speeds, self.targets, strict=True))


def calibrate(rig: Rig, targets, knobs=("outer_spans", "inner_span"),
              rtol: float = 1e-6) -> Calibration:
    """Scale ``knobs`` of ``rig`` so that its first forward critical speeds equal ``targets``.

    Parameters
    ----------
    rig : Rig
        The rig to calibrate.
    targets : sequence of float
        Target forward critical speeds (rad/s), ascending.
    knobs : sequence of str
        Names from :data:`KNOBS`; as many as targets for an exact match.
    rtol : float
        Relative tolerance on the speeds.

    Returns
    -------
    Calibration
        The calibrated rig, the knobs' scales and the speeds reached.
    """
    from scipy.optimize import least_squares

    from rubdiag.assembly import assemble
    from rubdiag.modal._critical import critical_speeds

    targets = tuple(float(t) for t in targets)
    if not targets or any(not np.isfinite(t) or t <= 0 for t in targets):
        raise ValueError(f"targets = {targets!r} is out of range (allowed: speeds > 0 rad/s)")
    if any(b <= a for a, b in itertools.pairwise(targets)):
        raise ValueError(f"targets = {targets!r} must be strictly ascending")
    knobs = tuple(knobs)
    for name in knobs:
        if name not in KNOBS:
            raise ValueError(f"knob {name!r} is not allowed (allowed: {', '.join(KNOBS)})")
    if not knobs:
        raise ValueError("knobs is empty (allowed: at least one of " + ", ".join(KNOBS) + ")")

    def build(log_scales) -> Rig:
        out = rig
        for name, ls in zip(knobs, log_scales, strict=True):
            out = KNOBS[name](out, float(np.exp(ls)))
        return out

    def residual(log_scales):
        speeds = critical_speeds(assemble(build(log_scales)), n=len(targets))
        if len(speeds) < len(targets):
            return np.full(len(targets), 10.0)
        return np.log(speeds / np.array(targets))

    fit = least_squares(residual, np.zeros(len(knobs)), bounds=(np.log(0.2), np.log(5.0)),
                        xtol=rtol * 1e-2, ftol=rtol * 1e-2, gtol=_GTOL, diff_step=_DIFF_STEP)
    result = build(fit.x)
    speeds = critical_speeds(assemble(result), n=len(targets))
    return Calibration(rig=result, knobs=knobs, scales=tuple(np.exp(fit.x).tolist()),
                       targets=targets, speeds=tuple(speeds.tolist()),
                       n_evaluations=int(fit.nfev))
