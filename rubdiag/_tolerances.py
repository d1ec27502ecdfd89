"""Tolerances that decide when a computed float stands for an exact value, shared by the
modules that compare or snap one: a value on a level, a bound reached, a root that is real,
a whirl that is neither forward nor backward. Each is far above what float rounding of a
few operations leaves (about 1e-15 relative) and far below any real difference the
comparison is meant to see.
"""

from __future__ import annotations

__all__ = ["BOUND_SLACK", "ON_LEVEL", "PLANAR_WHIRL", "REAL_ROOT"]

#: How far (absolute, or relative for values above 1) a value computed in a few float
#: operations may lie from the whole number or grid level it stands for and still be on it
#: (an order on a bin, a blade on a casing node, revolutions in a record): values truly
#: between levels lie 1e-6 or more away.
ON_LEVEL = 1e-9
#: Relative slack of an inclusive bound: a value computed to equal the bound (the highest
#: order kept, a window's start, the revolutions a window must hold) may land a few ulps
#: past it and still counts as reaching it.
BOUND_SLACK = 1e-12
#: The share of its modulus under which an eigenvalue's imaginary part is rounding and the
#: eigenvalue is real (Ω² of a synchronous critical speed): spurious roots of an indefinite
#: M − iG have an imaginary part of the order of their modulus.
REAL_ROOT = 1e-6
#: A whirl ratio (+1 circular forward, -1 backward) within this of 0 is planar: neither
#: forward nor backward (a mode of the casing ring, or one without shaft motion).
PLANAR_WHIRL = 1e-3
