"""Model uncertainty as design factors: the rig a design point simulates.

A model is never the machine. The factors here vary the parameters of the rig that are
least known and most change the response, so that a classifier trained on a design meets
more than one rotor, and ``evaluate(split=<factor>)`` can ask how it does on a rotor it
never saw (train on the rest of the factor's range, test on a band of it):

``casing_stiffness_scale``
    times the casing support stiffnesses (k_y, k_z, and k_rx when the rig sets it; not the
    dampers).
``damping_ratio``
    the modal damping ratio ξ of both reference modes of the Rayleigh fit (the rig's
    ``Damping.xi_1`` and ``xi_2``; the study's is 0.04).
``disc_mass_scale``
    times each disc's mass and inertias (its dimensions stay; a disc given by dimensions is
    turned into mass and inertias first). On a rig with journal bearings each film's
    static load follows: the bearing reactions of the heavier rotor on rigid supports
    (:func:`bearing_loads_n`).
``oil_viscosity_scale``, ``bearing_clearance_scale``
    times each journal bearing's oil viscosity and radial clearance (rigs with journal
    bearings only: refused by name on others). The Sommerfeld number goes with μ/C², so the
    clearance moves the film's stiffness, the critical speeds and the threshold of
    instability the most.

``blade_count``
    the number of blades on the bladed disc (the rig's blade dimensions; the disc's
    rotating mass changes with it, and on journal bearings each film's static load
    follows, as for ``disc_mass_scale``). Each blade set that rubs keeps its pattern
    (:data:`BLADE_SETS`: every other blade, every blade, or one) at the new count. Whenever
    a design varies ``blade_count`` or ``rubbing_blades``, every run's casing ring has the
    smallest multiple of its blade count at least the rig's element count, so that a
    casing node faces every blade, whichever rubs (the paper rig's 16 blades: 48 elements
    instead of 40); the ring's mesh does not tell a rubbing run from another.

Which of them matter on the multi-fault rig is measured by ``scripts/uncertainty.py``
(documentation: "Model uncertainty"). A design's ``speed_ratio`` is relative to the critical
speed of each run's own rig, and a run with whirl turns at ``whirl_speed_ratio`` times its
own rig's threshold (:class:`rubdiag.dataset.Design`).
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Mapping

from rubdiag import _check
from rubdiag.dataset._fault_levels import BLADE_SETS

__all__ = ["BLADE_SETS", "CRITICAL_FACTORS", "JOURNAL_FACTORS", "RIG_FACTORS",
           "THRESHOLD_FACTORS", "bearing_loads_n", "blade_set", "blade_set_of",
           "check_rig_factors", "varied_rig", "with_rubbing_blades"]

#: the factors that change the rig, in the order they are applied
RIG_FACTORS = ("blade_count", "casing_stiffness_scale", "damping_ratio", "disc_mass_scale",
               "oil_viscosity_scale", "bearing_clearance_scale")
#: the factors that need journal bearings
JOURNAL_FACTORS = ("oil_viscosity_scale", "bearing_clearance_scale")
#: the factors that move the critical speeds (the casing meets the rotor only through
#: contact, and the critical speed map is undamped: neither casing_stiffness_scale nor
#: damping_ratio moves them)
CRITICAL_FACTORS = ("blade_count", "disc_mass_scale", *JOURNAL_FACTORS)
#: the factors that move the threshold of instability: those and the damping
THRESHOLD_FACTORS = ("damping_ratio", *CRITICAL_FACTORS)


def check_rig_factors(rig, names) -> None:
    """Refuse a journal-bearing factor on a rig without journal bearings."""
    if any(b.journal is not None for b in rig.bearings):
        return
    for name in JOURNAL_FACTORS:
        if name in names:
            raise ValueError(f"factors.{name} needs a rig with journal bearings (base.rig = "
                             f"{rig.name!r} has none; allowed: e.g. 'paper-journal')")


def varied_rig(rig, point: Mapping):
    """``rig`` with the rig factors of ``point`` applied (``rig`` itself when it has none).
    A point with ``rubbing_blades`` (whether its run rubs or not) gets the casing mesh
    that ``blade_count`` gives (module docstring)."""
    point = dict(point)
    if "rubbing_blades" in point and "blade_count" not in point:
        point["blade_count"] = rig.blades.count
    levels = tuple((name, point[name]) for name in RIG_FACTORS if name in point)
    return _varied(rig, levels) if levels else rig


def blade_set(count: int, pattern: str) -> tuple[int, ...]:
    """The blades (numbered from 1) of ``pattern`` (:data:`BLADE_SETS`) among ``count``."""
    _check.choice("rubbing_blades", pattern, BLADE_SETS)
    if pattern == "one":
        return (1,)
    return tuple(range(1, count + 1, 2 if pattern == "alternate" else 1))


def blade_set_of(rig) -> str:
    """The pattern of ``rig``'s contact blades (:data:`BLADE_SETS`), or a ValueError when
    they follow none."""
    for pattern in BLADE_SETS:
        if rig.contact.blades == blade_set(rig.blades.count, pattern):
            return pattern
    raise ValueError(f"factors.blade_count: the rig's contact blades {list(rig.contact.blades)}"
                     f" are none of the sets {', '.join(BLADE_SETS)} (allowed: a rig whose "
                     "contact blades are every other blade, every blade or blade 1)")


def with_rubbing_blades(rig, pattern: str):
    """``rig`` whose contact elements sit at the blades of ``pattern`` (its casing must
    have a node facing each: :func:`varied_rig` of a point with ``rubbing_blades``)."""
    blades = blade_set(rig.blades.count, pattern)
    if blades == rig.contact.blades:
        return rig
    return dataclasses.replace(rig, contact=dataclasses.replace(rig.contact, blades=blades))


@functools.lru_cache(maxsize=256)
def _varied(rig, levels: tuple):
    """:func:`varied_rig` of the rig factors ``levels`` ((name, value) pairs), kept: a
    design's points share a few levels of each."""
    point = dict(levels)
    if "blade_count" in point:
        rig = _with_blade_count(rig, point["blade_count"],
                                reload_films="disc_mass_scale" not in point)
    if "casing_stiffness_scale" in point:
        rig = _scaled_casing(rig, point["casing_stiffness_scale"])
    if "damping_ratio" in point:
        xi = point["damping_ratio"]
        rig = dataclasses.replace(rig, damping=dataclasses.replace(rig.damping, xi_1=xi,
                                                                   xi_2=xi))
    if "disc_mass_scale" in point:
        rig = _scaled_discs(rig, point["disc_mass_scale"])
    films = {"viscosity_pa_s": point.get("oil_viscosity_scale"),
             "clearance_m": point.get("bearing_clearance_scale")}
    films = {k: s for k, s in films.items() if s is not None}
    if films:
        rig = dataclasses.replace(rig, bearings=tuple(
            b if b.journal is None else dataclasses.replace(b, journal=dataclasses.replace(
                b.journal, **{k: getattr(b.journal, k) * s for k, s in films.items()}))
            for b in rig.bearings))
    return rig


def _with_blade_count(rig, count: int, reload_films: bool):
    """``rig`` with ``count`` blades, its contact blades in their pattern at that count and
    its casing ring meshed at the smallest multiple of ``count`` at least its own (on
    journal bearings the films carry the new weight unless the disc masses are scaled
    next, which reloads them)."""
    pattern = blade_set_of(rig)
    casing = rig.casing
    n = -(-casing.n_elements // count) * count
    default_support = casing.n_elements // 2 + 1
    casing = dataclasses.replace(
        casing, n_elements=n,
        support_node=None if casing.support_node == default_support else casing.support_node)
    varied = dataclasses.replace(
        rig, blades=dataclasses.replace(rig.blades, count=count), casing=casing,
        contact=dataclasses.replace(rig.contact, blades=blade_set(count, pattern)))
    return _reloaded_films(varied) if reload_films else varied


def _reloaded_films(rig):
    """``rig`` whose journal films carry its rotor's weight (:func:`bearing_loads_n`)."""
    if not any(b.journal is not None for b in rig.bearings):
        return rig
    loads = bearing_loads_n(rig)
    return dataclasses.replace(rig, bearings=tuple(
        b if b.journal is None else dataclasses.replace(
            b, journal=dataclasses.replace(b.journal, load_n=load))
        for b, load in zip(rig.bearings, loads, strict=True)))


def _scaled_casing(rig, s: float):
    casing = rig.casing
    k_rx = casing.support_k_rx_nm_rad
    casing = dataclasses.replace(casing, support_k_y_n_m=casing.support_k_y_n_m * s,
                                 support_k_z_n_m=casing.support_k_z_n_m * s,
                                 support_k_rx_nm_rad=None if k_rx is None else k_rx * s)
    return dataclasses.replace(rig, casing=casing)


def _scaled_discs(rig, s: float):
    density = rig.material.density_kg_m3
    discs = []
    for disc in rig.discs:
        mass, polar, diametral = disc.inertia(density)
        discs.append(dataclasses.replace(
            disc, outer_radius_m=None, thickness_m=None, inner_radius_m=0.0, mass_kg=mass * s,
            polar_inertia_kg_m2=polar * s, diametral_inertia_kg_m2=diametral * s))
    return _reloaded_films(dataclasses.replace(rig, discs=tuple(discs)))


@functools.lru_cache(maxsize=64)
def bearing_loads_n(rig, gravity_m_s2: float = 9.81) -> tuple[float, ...]:
    """The share of the rotor's weight each bearing carries (N, along gravity -y): the
    static reactions of ``rig``'s rotor with every bearing made rigid (1e12 N/m, no
    pedestal; the casing's weight rests on its own supports). For the two bearings of the
    presets the rotor is statically determinate, so the answer is the lever rule's,
    whatever the real bearings' stiffness."""
    import scipy.sparse.linalg as spla

    from rubdiag.assembly import assemble
    from rubdiag.model import Bearing
    from rubdiag.simulation import StaticLoad

    rigid = dataclasses.replace(rig, bearings=tuple(
        Bearing(b.node, 1e12, 1e12) for b in rig.bearings))
    model = assemble(rigid)
    weight = StaticLoad(gravity_m_s2=-gravity_m_s2).vector(model.M, model.dofs)
    x = spla.spsolve(model.K.tocsc(), weight)
    return tuple(round(-1e12 * float(x[model.dofs.index(b.node, "y")]), 9)
                 for b in rigid.bearings)
