"""Per-mode quantities of complex shapes: whirl direction and where the energy lies.

At every node the lateral motion (u_y, u_z) = Re((a, b) e^{λt}) traces an ellipse, run
forwards (from +y to +z, like the rotor) when Im(a·conj(b)) > 0. The whirl ratio sums
2·Im(a·conj(b)) over the shaft's nodes, normalised by Σ(|a|² + |b|²): +1 is a circular
forward orbit, −1 backward.
"""

from __future__ import annotations

import numpy as np

__all__ = ["energy_shares", "whirl_ratio"]


def whirl_ratio(model, shapes: np.ndarray) -> np.ndarray:
    """Whirl ratio in [−1, 1] of each column of ``shapes`` over the shaft nodes."""
    dofs = model.dofs
    y = model.dofs.component("shaft", ("y",))
    z = model.dofs.component("shaft", ("z",))
    if not y:   # no shaft in the model (e.g. a lone ring): use every lateral pair
        y, z = _all_pairs(dofs)
    a, b = shapes[y], shapes[z]
    num = 2.0 * np.sum((a * b.conj()).imag, axis=0)
    den = np.sum(np.abs(a) ** 2 + np.abs(b) ** 2, axis=0)
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0)


def _all_pairs(dofs):
    labels = dofs.labels
    y = [i for i, s in enumerate(labels) if s.endswith(" y")]
    return y, [i + 1 for i in y]


def energy_shares(model, shapes: np.ndarray) -> dict[str, np.ndarray]:
    """Fraction of each mode's kinetic energy q^H M q carried by shaft, blades and casing."""
    Mq = model.M @ shapes
    total = np.real(np.sum(shapes.conj() * Mq, axis=0))
    out = {}
    for name in ("shaft", "blade", "casing"):
        idx = model.dofs.component(name)
        part = np.real(np.sum(shapes[idx].conj() * Mq[idx], axis=0)) if idx else 0 * total
        out[f"{name}_share"] = part / total
    return out
