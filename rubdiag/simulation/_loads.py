"""External loads by order: harmonic terms locked to the shaft's angle, with an amplitude law.

A term j of a :class:`HarmonicForce` acts at DOF ``dofs[j]`` with complex amplitude F_j (N),
on a shaft turning at ``omega[j]`` = Ω (rad/s), with order k_j (it turns k times per
revolution; negative: backward) and an amplitude law. At constant speed it is the harmonic

    f_j(t) = Re(F_j A_j e^{i k Ω t}),   a load at frequency kΩ,

with A = 1 for the laws ``"unbalance"`` and ``"constant"`` (F_j is the load at the speed
Ω) and A = a(Ω) for ``"table"``: a factor linear in a table of (speed_rad_s, factor) knots,
held constant outside it. Along a speed profile Ω(t), φ(t) = ∫Ω dt (the run starts at
Ω₀ = ``omega``) every term follows the shaft's angle, f_j = Re(F_j z_j(t)):

* ``"unbalance"``: ``z = (Ω² - iΩ'/k) / Ω₀² e^{ikφ}``, the inertia force of a mass
  eccentricity turning at kφ, ``-m e d²/dt² e^{ikφ} = m e (k²Ω² - ikΩ') e^{ikφ}``, scaled
  to F at Ω₀. For k = 1 it is the unbalance load of the shaft,
  ``(Ω² - iΩ') / Ω₀² e^{iφ}`` (f_y = u(Ω² cos φ + Ω' sin φ) for F_y = u Ω₀², F_z = -i F_y),
  bit for bit as before orders existed;
* ``"constant"``: ``z = e^{ikφ}``, a load of fixed magnitude (a magnetic pull, a
  misalignment preload turning with the shaft); with k = 0, z = 1: a static load
  f = Re(F) that does not turn (gravity, a side load, a coupling's preload), the only
  law order 0 is allowed with;
* ``"table"``: ``z = a(Ω) e^{ikφ}``.

The kernel evaluates z once per group of terms with the same order, law and table
(:mod:`rubdiag._kernels.load`); :func:`kernel_force` packs those groups and
:func:`load_vector` evaluates the same load in Python (the initial acceleration).

Units SI: N, rad/s, s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rubdiag import _check
from rubdiag._kernels.interface import Force
from rubdiag._kernels.load import (
    LAW_CONSTANT,
    LAW_TABLE,
    LAW_UNBALANCE,
    LW_CODE,
    LW_OMEGA,
    LW_ORDER,
)
from rubdiag.simulation._speed_profile import SpeedProfile

__all__ = ["LAWS", "HarmonicForce", "kernel_force", "load_vector"]

#: the amplitude laws by name, as the kernel codes them
LAWS = {"unbalance": LAW_UNBALANCE, "constant": LAW_CONSTANT, "table": LAW_TABLE}
#: the largest |order| accepted (a harmonic of a few hundred per revolution is not a load
#: this integrator resolves at its usual steps)
MAX_ORDER = 100.0


@dataclass(frozen=True)
class HarmonicForce:
    """A sparse load of harmonic terms by shaft order (module docstring).

    ``dofs`` (m,) int, ``amplitudes`` (m,) complex (N), ``omega`` (m,) the shaft speed Ω
    (rad/s; at constant speed, order 1, the term's angular frequency). ``order`` (m,) k,
    ``|k| <= 100`` (default 1: once per revolution), nonzero but for the law ``"constant"``,
    where k = 0 is a static load f = Re(F). ``law`` one of ``"unbalance"``
    (default), ``"constant"``, ``"table"``, for all terms or one per term. ``table``: the
    (speed_rad_s, factor) knots (K, 2) of the ``"table"`` terms, speeds >= 0 increasing,
    one table for all of them or one per term (None for the other laws). Scalars broadcast;
    a DOF may appear several times (the terms add up).

    Parameters
    ----------
    dofs : numpy.ndarray
        (m,) DOF of each term.
    amplitudes : numpy.ndarray
        (m,) complex amplitude of each term (N).
    omega : numpy.ndarray
        (m,) shaft speed Ω of each term (rad/s).
    order : numpy.ndarray or float
        Shaft order k of each term.
    law : str or tuple of str
        ``"unbalance"``, ``"constant"`` or ``"table"``, for all terms or one per term.
    table : tuple or None
        The (speed_rad_s, factor) knots of the ``"table"`` terms.
    """

    dofs: np.ndarray
    amplitudes: np.ndarray
    omega: np.ndarray
    order: np.ndarray | float = 1.0
    law: tuple[str, ...] | str = "unbalance"
    table: tuple | None = None

    def __post_init__(self):
        dofs = _check.indices("force.dofs", np.atleast_1d(self.dofs))
        amp = np.atleast_1d(np.asarray(self.amplitudes, dtype=np.complex128))
        om = np.broadcast_to(np.asarray(self.omega, dtype=np.float64), dofs.shape).copy()
        if not (dofs.ndim == amp.ndim == 1 and dofs.shape == amp.shape):
            raise ValueError(
                f"force: dofs {dofs.shape} and amplitudes {amp.shape} must be 1-D of equal length"
            )
        m = dofs.size
        laws = _laws(self.law, m)
        object.__setattr__(self, "dofs", dofs)
        object.__setattr__(self, "amplitudes", amp)
        object.__setattr__(self, "omega", om)
        object.__setattr__(self, "order", _orders(self.order, m, laws))
        object.__setattr__(self, "law", laws)
        object.__setattr__(self, "table", _tables(self.table, laws))

    @classmethod
    def zero(cls) -> HarmonicForce:
        """No external load."""
        return cls(np.zeros(0, np.int64), np.zeros(0, np.complex128), np.zeros(0))

    @classmethod
    def unbalance(cls, dof_y: int, dof_z: int, unbalance: float, speed: float) -> HarmonicForce:
        """Rotating unbalance ``u = m e`` (kg m) at speed Ω (rad/s), forward whirl y → z:
        F̂_y = uΩ², F̂_z = -i uΩ² (f_y = uΩ² cos Ωt, f_z = uΩ² sin Ωt)."""
        f = unbalance * speed**2
        return cls([dof_y, dof_z], [f, -1j * f], [speed, speed])

    def __add__(self, other: HarmonicForce) -> HarmonicForce:
        return HarmonicForce(
            np.concatenate([self.dofs, other.dofs]),
            np.concatenate([self.amplitudes, other.amplitudes]),
            np.concatenate([self.omega, other.omega]),
            np.concatenate([self.order, other.order]),
            self.law + other.law,
            self.table + other.table,
        )

    @property
    def frequencies(self) -> np.ndarray:
        """Each term's angular frequency at constant speed, kΩ (rad/s)."""
        return self.order * self.omega

    def steady_amplitudes(self) -> np.ndarray:
        """Each term's complex amplitude at constant speed Ω = ``omega``: F, or F a(Ω) for
        a ``"table"`` term (N)."""
        amp = self.amplitudes.copy()
        for j, tab in enumerate(self.table):
            if tab is not None:     # only table terms are scaled: the others keep their bits
                amp[j] = amp[j] * np.interp(self.omega[j], tab[:, 0], tab[:, 1])
        return amp

    def evaluate(self, t: float, n: int) -> np.ndarray:
        """Dense load vector f(t) (length n) at constant speed."""
        f = np.zeros(n)
        np.add.at(f, self.dofs,
                  (self.steady_amplitudes() * np.exp(1j * self.frequencies * t)).real)
        return f


def _orders(order, m: int, laws: tuple[str, ...]) -> np.ndarray:
    """Each term's order k; k = 0 (a static load) only with the law "constant": the
    unbalance law divides by k, and a table of speeds scaling a load that does not turn
    is a load the caller should scale itself."""
    k = np.broadcast_to(np.asarray(order, dtype=np.float64), (m,)).copy()
    static = np.array([law == "constant" for law in laws], dtype=bool) & (k == 0)
    bad = ~np.isfinite(k) | ((k == 0) & ~static) | (np.abs(k) > MAX_ORDER)
    if bad.any():
        j = int(np.argmax(bad))
        zero = f" for the law '{laws[j]}' (0, a static load, only with 'constant')" \
            if k[j] == 0 else ""
        raise _check.out_of_range(f"force.order[{j}]", float(k[j]),
                                  f"nonzero{zero}, -{MAX_ORDER:g} <= order <= "
                                  f"{MAX_ORDER:g}; negative: backward")
    return k


def _laws(law, m: int) -> tuple[str, ...]:
    laws = (law,) * m if isinstance(law, str) else tuple(law)
    if len(laws) != m:
        raise ValueError(f"force.law has {len(laws)} entries (allowed: one law, or one per "
                         f"term: {m})")
    for j, name in enumerate(laws):
        _check.choice(f"force.law[{j}]", name, LAWS)
    return laws


def _tables(table, laws: tuple[str, ...]) -> tuple:
    """One (K, 2) read-only array per term (None where the law is not "table")."""
    m = len(laws)
    if table is None:
        per_term = (None,) * m
    elif _is_one_table(table):
        if "table" not in laws:
            raise ValueError("force.table is given, but no term has the law 'table' "
                             "(allowed: None)")
        per_term = tuple(table if law == "table" else None for law in laws)
    else:
        per_term = tuple(table)
        if len(per_term) != m:
            raise ValueError(f"force.table has {len(per_term)} entries (allowed: one table, "
                             f"or one per term: {m})")
    out = []
    for j, (tab, law) in enumerate(zip(per_term, laws, strict=True)):
        if (tab is None) != (law != "table"):
            raise ValueError(f"force.table[{j}] is {'missing' if tab is None else 'given'} "
                             f"(allowed: a table exactly for the law 'table'; law[{j}] = "
                             f"'{law}')")
        out.append(None if tab is None else _checked_table(f"force.table[{j}]", tab))
    return tuple(out)


def _is_one_table(table) -> bool:
    try:
        arr = np.asarray(table, dtype=np.float64)
    except (TypeError, ValueError):     # ragged: one table per term
        return False
    return arr.ndim == 2


def _checked_table(name: str, table) -> np.ndarray:
    tab = np.array(table, dtype=np.float64, ndmin=2)
    if tab.ndim != 2 or tab.shape[1] != 2 or tab.shape[0] < 1:
        raise ValueError(f"{name} has shape {tab.shape} (allowed: (K, 2) rows of "
                         "(speed_rad_s, factor), K >= 1)")
    for i, (w, a) in enumerate(tab):
        _check.number(f"{name}[{i}, 0] (speed_rad_s)", w, lo=0.0, hi=1e5, unit="rad/s")
        _check.number(f"{name}[{i}, 1] (factor)", a)
    if np.any(np.diff(tab[:, 0]) <= 0):
        raise ValueError(f"{name}: speeds must increase strictly (allowed: a table of "
                         "(speed_rad_s, factor) rows by increasing speed)")
    tab.setflags(write=False)
    return tab


def _groups(force: HarmonicForce, rotating: bool):
    """``(group, keys)``: each term's group index and each group's (ω, k, law, table)."""
    keys, index, group = [], {}, np.zeros(force.dofs.size, np.int64)
    for j in range(force.dofs.size):
        tab = force.table[j]
        om = 0.0 if rotating else float(force.frequencies[j])
        key = (om, float(force.order[j]), LAWS[force.law[j]],
               None if tab is None else tab.tobytes())
        if key not in index:
            index[key] = len(keys)
            keys.append((om, key[1], key[2], tab))
        group[j] = index[key]
    return group, keys


def kernel_force(force: HarmonicForce, rot: np.ndarray) -> Force:
    """The kernel's load (:data:`rubdiag._kernels.interface.Force`) for a speed profile's knots
    ``rot`` (empty: constant speed, given to the kernel as one knot): at constant speed the
    amplitudes at the speed and a group per frequency; along a profile the amplitudes at Ω₀
    and a group per order, law and table."""
    rotating = rot.shape[0] > 0
    amp = force.amplitudes if rotating else force.steady_amplitudes()
    group, keys = _groups(force, rotating)
    n_knots = max([2] + [len(k[3]) for k in keys if k[3] is not None])
    law = np.zeros((len(keys), 3))
    table = np.zeros((len(keys), n_knots, 2))
    for g, (om, k, code, tab) in enumerate(keys):
        law[g, LW_OMEGA], law[g, LW_ORDER], law[g, LW_CODE] = om, k, code
        table[g] = _padded(np.array([[0.0, 1.0]]) if tab is None else tab, n_knots)
    return Force(np.ascontiguousarray(force.dofs), np.ascontiguousarray(amp.real),
                 np.ascontiguousarray(amp.imag), group, law, table,
                 rot if rotating else np.zeros((1, 3)), np.zeros((len(keys), 4)))


def _padded(tab: np.ndarray, n_knots: int) -> np.ndarray:
    """``tab`` extended to ``n_knots`` rows by knots of its last factor at 1, 2, … rad/s
    above its last speed: the kernel interpolates in strictly increasing knots, and the
    factor holds beyond the table."""
    extra = np.arange(1, n_knots - len(tab) + 1, dtype=np.float64)
    pad = np.column_stack([tab[-1, 0] + extra, np.full(extra.size, tab[-1, 1])])
    return np.vstack([tab, pad])


def load_vector(force: HarmonicForce, profile: SpeedProfile | None, t: float,
                n: int) -> np.ndarray:
    """The load vector f(t) (n,): harmonic, or following the speed ``profile``; the same
    formulas as the kernel (module docstring), group by group."""
    if profile is None:
        return force.evaluate(t, n)
    w, alpha = float(profile.speed(t)), float(profile.acceleration(t))
    phi = float(profile.angle(t))
    group, keys = _groups(force, True)
    f = np.zeros(n)
    for g, (_, k, code, tab) in enumerate(keys):
        if code == LAW_UNBALANCE:   # k = 1: (Ω² - iΩ') / Ω₀² e^{iφ}, the bits of before
            gain = (w * w - 1j * (alpha / k)) / profile.start_rad_s**2 * np.exp(1j * (k * phi))
        else:
            a = 1.0 if code == LAW_CONSTANT else float(np.interp(w, tab[:, 0], tab[:, 1]))
            gain = a * np.exp(1j * (k * phi))
        terms = group == g
        np.add.at(f, force.dofs[terms], (force.amplitudes[terms] * gain).real)
    return f

