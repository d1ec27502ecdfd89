"""Names for every degree of freedom, so results can be addressed as ("shaft 11", "y").

Node labels: ``"shaft N"`` (paper node number N), ``"blade B.S"`` (blade B, station S from
root to tip, both 1-based; the root station 0 is tied to the disc and has no DOFs of its
own), ``"casing K"`` (1-based, node 1 on +y, counter-clockwise towards +z) and
``"pedestal K"`` (the pedestal of bearing K, 0-based in ``Rig.bearings``; y and z only),
numbered after every other node so a rig without pedestals keeps its numbering.

Directions: ``y``, ``z`` (translations), ``ry``, ``rz`` (shaft rotations about y and z),
``rx`` (in-plane rotation of blade and casing nodes about x).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PEDESTAL_DIRECTIONS", "PLANAR_DIRECTIONS", "SHAFT_DIRECTIONS", "DofMap"]

SHAFT_DIRECTIONS = ("y", "z", "ry", "rz")
PLANAR_DIRECTIONS = ("y", "z", "rx")
PEDESTAL_DIRECTIONS = ("y", "z")


@dataclass(frozen=True)
class DofMap:
    """Ordered DOF names; ``index(node, direction)`` gives the global DOF number.

    Parameters
    ----------
    nodes : tuple of (str, tuple of str)
        Every node's label (``"shaft 11"``) and its directions, in DOF order.
    """

    nodes: tuple[tuple[str, tuple[str, ...]], ...]
    _index: dict = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        index, k = {}, 0
        for label, directions in self.nodes:
            for direction in directions:
                index[(label, direction)] = k
                k += 1
        object.__setattr__(self, "_index", index)

    @classmethod
    def build(cls, shaft_nodes, n_blades: int, n_blade_stations: int, n_casing: int,
              pedestals: tuple[int, ...] = ()):
        """``pedestals``: the indices of the bearings that have a pedestal."""
        nodes = [(f"shaft {n}", SHAFT_DIRECTIONS) for n in shaft_nodes]
        nodes += [(f"blade {b}.{s}", PLANAR_DIRECTIONS) for b in range(1, n_blades + 1)
                  for s in range(1, n_blade_stations + 1)]
        nodes += [(f"casing {k}", PLANAR_DIRECTIONS) for k in range(1, n_casing + 1)]
        nodes += [(f"pedestal {k}", PEDESTAL_DIRECTIONS) for k in pedestals]
        return cls(tuple(nodes))

    @property
    def n_dof(self) -> int:
        return len(self._index)

    @property
    def labels(self) -> list[str]:
        """``"shaft 11 y"``-style name of every DOF, in order."""
        return [f"{node} {d}" for node, dirs in self.nodes for d in dirs]

    @functools.cached_property
    def directions(self) -> np.ndarray:
        """The direction (``"y"``, ``"rx"``, …) of every DOF, in order (read-only)."""
        out = np.array([d for _, dirs in self.nodes for d in dirs])
        out.flags.writeable = False
        return out

    def index(self, node: str | int, direction: str) -> int:
        """Global DOF number; an int ``node`` means that shaft node."""
        label = f"shaft {node}" if isinstance(node, int) else node
        try:
            return self._index[(label, direction)]
        except KeyError:
            raise ValueError(f"no DOF ({label!r}, {direction!r}) in this model") from None

    def component(self, name: str, directions: tuple[str, ...] | None = None) -> list[int]:
        """DOF numbers of a component ("shaft", "blade", "casing" or "pedestal"), optionally
        only the given directions, in order."""
        return list(self._component(name, None if directions is None else tuple(directions)))

    @functools.lru_cache(maxsize=256)  # noqa: B019  (a few maps, each kept with its model)
    def _component(self, name: str, directions: tuple[str, ...] | None) -> tuple[int, ...]:
        return tuple(k for (label, d), k in self._index.items()
                     if label.split(" ", 1)[0] == name and (directions is None or d in directions))

    def __contains__(self, key) -> bool:
        return key in self._index
