"""The rotor of a rig: its material, the shaft's beam elements and the rigid discs on it.

Shaft nodes are numbered from ``Shaft.first_node`` (3 when the coupling is left out, as in
the study), so that the paper rig's discs sit at nodes 11 and 19.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rubdiag import _check
from rubdiag.model._frozen import set_field as _set

__all__ = ["Disc", "Material", "Shaft"]


@dataclass(frozen=True)
class Material:
    """Isotropic linear-elastic material shared by shaft, discs, blades and casing.

    Parameters
    ----------
    youngs_modulus_pa : float
        Young's modulus E (Pa, > 0).
    poisson_ratio : float
        Poisson's ratio ν (-1 < ν < 0.5).
    density_kg_m3 : float
        Density ρ (kg/m³, > 0).
    """

    youngs_modulus_pa: float = 210e9
    poisson_ratio: float = 0.3
    density_kg_m3: float = 7850.0

    def __post_init__(self):
        _check.positive("Material.youngs_modulus_pa", self.youngs_modulus_pa)
        _check.number("Material.poisson_ratio", self.poisson_ratio, lo=-1.0, hi=0.5,
                      lo_open=True, hi_open=True)
        _check.positive("Material.density_kg_m3", self.density_kg_m3)

    @property
    def shear_modulus_pa(self) -> float:
        return self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))


@dataclass(frozen=True)
class Shaft:
    """Shaft of Timoshenko beam elements; element i joins nodes first_node+i and +i+1.

    ``outer_diameters_m`` and ``inner_diameters_m`` are per element; a single number applies
    to every element (inner 0 means a solid shaft).

    Parameters
    ----------
    element_lengths_m : tuple of float
        Length of each beam element (m, > 0), in axial order.
    outer_diameters_m : tuple of float or float
        Outer diameter of each element (m, > 0), or one for all.
    inner_diameters_m : tuple of float or float
        Bore of each element (m, >= 0 and below its outer diameter), or one for all.
    first_node : int
        Node number of the shaft's first node (>= 0).
    """

    element_lengths_m: tuple[float, ...]
    outer_diameters_m: tuple[float, ...] | float
    inner_diameters_m: tuple[float, ...] | float = 0.0
    first_node: int = 3

    def __post_init__(self):
        lengths = _check.numbers("Shaft.element_lengths_m", self.element_lengths_m)
        n = len(lengths)
        outer = _check.numbers("Shaft.outer_diameters_m", self.outer_diameters_m, length=n)
        inner = _check.numbers("Shaft.inner_diameters_m", self.inner_diameters_m,
                               check=_check.non_negative, length=n)
        for i, (do, di) in enumerate(zip(outer, inner, strict=True)):
            if di >= do:
                raise _check.out_of_range(f"Shaft.inner_diameters_m[{i}]", di,
                                          f"< outer diameter {do:g} m")
        _check.integer("Shaft.first_node", self.first_node, lo=0)
        _set(self, "element_lengths_m", lengths)
        _set(self, "outer_diameters_m", outer)
        _set(self, "inner_diameters_m", inner)

    @property
    def n_elements(self) -> int:
        return len(self.element_lengths_m)

    @property
    def nodes(self) -> range:
        """Paper node numbers of the shaft nodes, in axial order."""
        return range(self.first_node, self.first_node + self.n_elements + 1)

    @property
    def node_positions_m(self) -> tuple[float, ...]:
        """Axial position x of every shaft node, the first node at x = 0."""
        x = [0.0]
        for length in self.element_lengths_m:
            x.append(x[-1] + length)
        return tuple(x)


@dataclass(frozen=True)
class Disc:
    """Rigid disc on a shaft node, given by its geometry or by its mass and inertias.

    Give either ``outer_radius_m`` and ``thickness_m`` (a uniform disc of the rig's material,
    optional bore ``inner_radius_m``) or all three of ``mass_kg``, ``polar_inertia_kg_m2``
    and ``diametral_inertia_kg_m2``.

    Parameters
    ----------
    node : int
        Shaft node the disc sits on.
    outer_radius_m : float or None
        Outer radius (m) of a uniform disc.
    thickness_m : float or None
        Axial thickness (m) of a uniform disc.
    inner_radius_m : float
        Bore radius (m) of a uniform disc, 0 <= bore < outer radius.
    mass_kg : float or None
        Mass (kg) of a disc given by its inertia.
    polar_inertia_kg_m2 : float or None
        Polar moment of inertia about the shaft axis (kg·m²).
    diametral_inertia_kg_m2 : float or None
        Diametral moment of inertia (kg·m²).
    """

    node: int
    outer_radius_m: float | None = None
    thickness_m: float | None = None
    inner_radius_m: float = 0.0
    mass_kg: float | None = None
    polar_inertia_kg_m2: float | None = None
    diametral_inertia_kg_m2: float | None = None

    def __post_init__(self):
        _check.integer("Disc.node", self.node, lo=0)
        geometry = (self.outer_radius_m, self.thickness_m)
        inertia = (self.mass_kg, self.polar_inertia_kg_m2, self.diametral_inertia_kg_m2)
        has_geometry = all(v is not None for v in geometry)
        has_inertia = all(v is not None for v in inertia)
        if has_geometry == has_inertia:
            raise ValueError(
                f"Disc at node {self.node}: give either outer_radius_m and thickness_m, or "
                "mass_kg, polar_inertia_kg_m2 and diametral_inertia_kg_m2 (exactly one set)")
        if has_geometry:
            _check.positive("Disc.outer_radius_m", self.outer_radius_m)
            _check.positive("Disc.thickness_m", self.thickness_m)
            _check.number("Disc.inner_radius_m", self.inner_radius_m, lo=0.0,
                          hi=self.outer_radius_m, hi_open=True)
        else:
            _check.positive("Disc.mass_kg", self.mass_kg)
            _check.positive("Disc.polar_inertia_kg_m2", self.polar_inertia_kg_m2)
            _check.positive("Disc.diametral_inertia_kg_m2", self.diametral_inertia_kg_m2)

    def inertia(self, density_kg_m3: float) -> tuple[float, float, float]:
        """(mass kg, polar inertia kg·m², diametral inertia kg·m²)."""
        if self.mass_kg is not None:
            return self.mass_kg, self.polar_inertia_kg_m2, self.diametral_inertia_kg_m2
        ro, ri, t = self.outer_radius_m, self.inner_radius_m, self.thickness_m
        m = density_kg_m3 * math.pi * (ro**2 - ri**2) * t
        ip = 0.5 * m * (ro**2 + ri**2)
        idiam = m * (3.0 * (ro**2 + ri**2) + t**2) / 12.0
        return m, ip, idiam
