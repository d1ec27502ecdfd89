"""A static load on a rig: gravity along a chosen direction, and/or a side load at one node.

The Table 2 rig has none (its shaft is analysed about its static equilibrium); the faults
that look like rub need one: a crack breathes because gravity bends the shaft, a pedestal
lifts off against its weight, a journal bearing runs at a static eccentricity. A
:class:`StaticLoad` is opt-in (``Run(static_load=...)``, default None: the run, its bits
and its ids are those it had before the field existed).

* gravity: the body force of a uniform acceleration g along +y or +z on every mass of the
  model, ``f = M e g`` with ``e`` the rigid translation along that direction (1 on every
  translational DOF in it, 0 on the rotations): the consistent nodal loads of each
  element's weight (a shaft element gets its end moments too, a disc its weight);
* a side load: a force ``force_n`` (N) along +y or +z at one node (an int: that shaft
  node; or a label such as ``"casing 3"``).

Both act along the same ``direction``; signs follow the axes (gravity pulling towards -y:
``gravity_m_s2=-9.81``). The load is a "constant" load of order 0
(:mod:`rubdiag.simulation._loads`): it does not turn with the shaft, and a run starts from
its static deflection ``K⁻¹ f`` added to the harmonic steady state.

Where the blade–casing gaps are measured (``clearances``): ``"loaded"`` (the default) takes
the run's gap g0 as the clearance at the static equilibrium under this load — the casing is
aligned on the loaded rotor, as a machine's clearances are set and measured on the
assembled machine, where the rotor already sags. Each blade-tip contact's gap is then g0
plus its static approach ``n·(u_tip - u_casing)`` of ``K⁻¹ f``, so every blade sees g0 at
the static state and rubs only by its dynamic motion. ``"unloaded"``: g0 is the clearance
of the unloaded rig, so the load itself moves the rotor towards the casing (a side load
that closes a gap; gravity that sags the paper rig's discs by 0.41 mm closes a 0.3 mm gap
at the bottom blades). A rig's annular stator contacts (seals) follow the same rule:
``"loaded"`` centres each on the rotor's static state at its node (a seal aligned on the
loaded rotor), ``"unloaded"`` on the bearing line.

Units SI: m/s², N.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check

__all__ = ["StaticLoad"]

#: the directions a static load may act along (the model's translations)
DIRECTIONS = ("y", "z")
#: where the blade–casing gaps are measured: at the static equilibrium, or at rest
CLEARANCES = ("loaded", "unloaded")


@dataclass(frozen=True, kw_only=True)
class StaticLoad:
    """Gravity and/or a side load along one direction (module docstring).

    Parameters
    ----------
    direction : {"y", "z"}
        The direction both loads act along.
    gravity_m_s2 : float
        The acceleration of gravity along +direction (m/s², at most 1000 in size; -9.81 pulls
        towards -direction). Default 0: no gravity.
    force_n : float
        The side load along +direction (N, at most 1e6 in size). Default 0: none.
    node : int or str or None
        Where the side load acts: a shaft node number, or a DOF map node label such as
        ``"casing 3"``. Required exactly when ``force_n`` is nonzero.
    clearances : {"loaded", "unloaded"}
        Where the blade–casing gaps (and seal clearances) are measured: at the static
        equilibrium under this load (default), or on the unloaded rig (module docstring).

    Raises
    ------
    ValueError
        A field out of its range, or a node given without a side load (or the reverse).

    See Also
    --------
    Run : The run that carries it (``Run(static_load=...)``).

    Examples
    --------
    On a 2-kg point mass, gravity along -y is a 19.62 N load on the y DOF alone
    (:meth:`vector`; the rotations carry no weight):

    >>> import numpy as np
    >>> from rubdiag.assembly import DofMap
    >>> dofs = DofMap((("shaft 1", ("y", "z", "ry", "rz")),))
    >>> M = np.diag([2.0, 2.0, 0.01, 0.01])         # kg, kg·m²
    >>> StaticLoad(gravity_m_s2=-9.81).vector(M, dofs)
    array([-19.62,   0.  ,   0.  ,   0.  ])

    A side load of 50 N along +z at shaft node 1:

    >>> StaticLoad(direction="z", force_n=50.0, node=1).vector(M, dofs)
    array([ 0., 50.,  0.,  0.])
    """

    direction: str = "y"
    gravity_m_s2: float = 0.0
    force_n: float = 0.0
    node: int | str | None = None
    clearances: str = "loaded"

    def __post_init__(self):
        _check.choice("static_load.direction", self.direction, DIRECTIONS)
        _check.choice("static_load.clearances", self.clearances, CLEARANCES)
        object.__setattr__(self, "gravity_m_s2", _check.number(
            "static_load.gravity_m_s2", self.gravity_m_s2, lo=-1e3, hi=1e3, unit="m/s²"))
        object.__setattr__(self, "force_n", _check.number(
            "static_load.force_n", self.force_n, lo=-1e6, hi=1e6, unit="N"))
        if self.node is not None:
            if isinstance(self.node, str):
                if not self.node.strip():
                    raise ValueError("static_load.node = '' is out of range (allowed: a "
                                     "shaft node number or a node label such as "
                                     "'casing 3')")
            else:
                object.__setattr__(self, "node",
                                   _check.integer("static_load.node", self.node, lo=0))
        if (self.force_n != 0.0) != (self.node is not None):
            raise ValueError(f"static_load.node = {_check.plain(self.node)} with force_n = "
                             f"{_check.plain(self.force_n)} (allowed: a node exactly when "
                             "force_n is nonzero)")

    def vector(self, M, dofs) -> np.ndarray:
        """The load vector f (n,) (N) on a model with mass matrix ``M`` (n, n; sparse or
        dense) and DOF map ``dofs`` (:class:`~rubdiag.assembly._dofs.DofMap`)."""
        n = M.shape[0]
        f = np.zeros(n)
        if self.gravity_m_s2 != 0.0:
            e = np.zeros(n)
            e[[k for k, label in enumerate(dofs.labels)
               if label.rsplit(" ", 1)[1] == self.direction]] = 1.0
            f += self.gravity_m_s2 * np.asarray(M @ e).reshape(n)
        if self.force_n != 0.0:
            f[dofs.index(self.node, self.direction)] += self.force_n
        return f

    def check_model(self, dofs) -> None:
        """Refuse a side-load node the model lacks (ValueError naming it)."""
        if self.node is not None:
            try:
                dofs.index(self.node, self.direction)
            except ValueError:
                raise ValueError(f"static_load.node = {_check.plain(self.node)} is not a node "
                                 "of the rig's model (allowed: a shaft node number or a "
                                 "label such as 'casing 3')") from None
