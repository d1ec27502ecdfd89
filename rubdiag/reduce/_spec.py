"""What a reduced model is asked to keep: :class:`Reduction`, part of a run's description.

The reduction keeps physical only what is nonlinear — the blade-tip and casing DOFs of the
contact elements, and the tip rotations of the contact blades (see ``tip_rotations``) — and
represents everything linear by fixed-interface (Craig–Bampton) modes below a cutoff
frequency. The cutoff follows from what the features look at: the
highest order (8×) at the highest speed a design uses, with a margin for the modes' own
dynamics, so one reduction serves every speed of a rig.
"""

from __future__ import annotations

from dataclasses import dataclass

from rubdiag import _check

__all__ = ["DEFAULT_CUTOFF_HZ", "MARGIN", "Reduction"]

#: The default cutoff (Hz): 2 × (8 × 6840 rpm / 60) = 1824 Hz, rounded up. 6840 rpm is the
#: paper rig's second critical speed + 20 %, the top of the speed ranges the shipped dataset
#: designs sample; 8× is the highest order of the feature layer, 2 the margin (the usual
#: Craig–Bampton rule: modes up to 1.5-2 × the highest frequency of interest). On the paper
#: rig no fixed-interface mode lies between 1442 and 2589 Hz, so any cutoff in that band
#: gives the same model.
DEFAULT_CUTOFF_HZ = 2000.0
#: The cutoff over the band the reduced model answers for (the Craig–Bampton rule's margin):
#: :func:`rubdiag.reduce._check` holds frequencies below ``cutoff_hz / MARGIN`` to 0.5 %.
MARGIN = 2.0


@dataclass(frozen=True)
class Reduction:
    """A Craig–Bampton reduction of the rig: the contact DOFs stay physical, every
    fixed-interface mode below ``cutoff_hz`` (Hz) is kept.

    ``tip_rotations`` also keeps the in-plane rotation of each contact blade's tip physical.
    With the tip translations alone, the static shape a tip load gives is the only shape of
    a blade's first bending below the cutoff, and its frequency comes out 1.5 % high (a
    static load shape's Rayleigh quotient); the stick-slip at the tip is sensitive to it:
    without the rotations the sticking share of the study's cells is 20-45 % low at 2 kHz
    (documentation: The reduced model). Results saved before the option existed were made without.

    ``shaft_nodes`` keeps every DOF of those shaft nodes physical too: where another
    nonlinear element acts (a breathing crack's element, a misaligned coupling's node).
    A run with faults adds its fault elements' nodes itself
    (:func:`rubdiag.simulation._rig_system.rig_system`).

    A run whose blade contacts cannot close — their gap at least
    :data:`~rubdiag.simulation._idle_contacts.IDLE_GAP_RATIO` times the linear approach, a
    fault dataset's healthy and lone-fault runs with the casing out of reach — is simulated
    on the reduction without them: their tips and casing nodes are left to the modes like
    any linear DOF (43 instead of 66 coordinates on the journal-bearing rig), and the result
    reports them open throughout (:mod:`rubdiag.simulation._idle_contacts`).
    ``keep_idle_contacts`` keeps them physical all the same (the comparison of the two).

    Use :meth:`for_features` to derive the cutoff from a speed range.

    Parameters
    ----------
    cutoff_hz : float
        Fixed-interface modes below this frequency are kept (Hz).
    tip_rotations : bool
        Keep each contact blade tip's in-plane rotation physical.
    shaft_nodes : tuple of int
        Shaft nodes whose every DOF stays physical.
    keep_idle_contacts : bool
        Keep the DOFs of blade contacts that cannot close physical.
    """

    cutoff_hz: float = DEFAULT_CUTOFF_HZ
    tip_rotations: bool = True
    shaft_nodes: tuple[int, ...] = ()
    keep_idle_contacts: bool = False

    def __post_init__(self):
        _check.number("cutoff_hz", self.cutoff_hz, lo=1.0, hi=1e6)
        if not isinstance(self.tip_rotations, bool):
            raise _check.wrong_type("tip_rotations", self.tip_rotations, "True or False")
        if not isinstance(self.keep_idle_contacts, bool):
            raise _check.wrong_type("keep_idle_contacts", self.keep_idle_contacts,
                                    "True or False")
        nodes = tuple(sorted({int(n) for n in _check.indices("shaft_nodes", self.shaft_nodes)}))
        object.__setattr__(self, "shaft_nodes", nodes)

    def description(self) -> dict:
        """The reduction as JSON-ready data: ``shaft_nodes`` only when there are some and
        ``keep_idle_contacts`` only when set, so that a reduction without them has the
        description (and the runs their ids and the disk cache its keys) it had before the
        fields existed."""
        out = {"cutoff_hz": float(self.cutoff_hz), "tip_rotations": bool(self.tip_rotations)}
        if self.shaft_nodes:
            out["shaft_nodes"] = list(self.shaft_nodes)
        if self.keep_idle_contacts:
            out["keep_idle_contacts"] = True
        return out

    @property
    def band_hz(self) -> float:
        """The band the reduced model answers for (Hz): ``cutoff_hz / MARGIN``."""
        return self.cutoff_hz / MARGIN

    @classmethod
    def for_features(cls, max_speed_rpm: float, max_order: float = 8.0,
                     margin: float = MARGIN) -> Reduction:
        """The reduction whose cutoff is ``margin × max_order × max_speed_rpm / 60`` Hz:
        every feature line up to order ``max_order`` at up to ``max_speed_rpm`` lies below
        the cutoff with that margin."""
        speed = _check.positive("max_speed_rpm", max_speed_rpm)
        order = _check.positive("max_order", max_order)
        margin = _check.number("margin", margin, lo=1.0, hi=100.0)
        return cls(cutoff_hz=margin * order * speed / 60.0)
