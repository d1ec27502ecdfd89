"""Reduced-order models of a rig: Craig–Bampton with the contact DOFs kept physical.

:class:`Reduction` says what to keep (it is part of a :class:`~rubdiag.simulation.Run`);
:func:`reduced_model` builds (and caches, once per rig and process) the reduced matrices;
:func:`check` measures how far the reduced model is from the full one.
"""

from rubdiag.reduce._check import FREQUENCY_TOLERANCE, ReductionCheck, check
from rubdiag.reduce._craig_bampton import CraigBampton, craig_bampton
from rubdiag.reduce._reduced import ReducedModel, boundary_dofs, contact_dofs, reduced_model
from rubdiag.reduce._spec import DEFAULT_CUTOFF_HZ, MARGIN, Reduction

__all__ = ["DEFAULT_CUTOFF_HZ", "FREQUENCY_TOLERANCE", "MARGIN", "CraigBampton", "ReducedModel",
           "Reduction", "ReductionCheck", "boundary_dofs", "check", "contact_dofs",
           "craig_bampton", "reduced_model"]
