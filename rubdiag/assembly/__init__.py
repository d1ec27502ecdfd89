"""Assembly layer: element matrices and the global sparse M, K, C, G of a rig."""

from rubdiag.assembly._assemble import BladeContactGeometry, Model, assemble, dof_map
from rubdiag.assembly._damping import rayleigh_coefficients
from rubdiag.assembly._dofs import DofMap

__all__ = ["BladeContactGeometry", "DofMap", "Model", "assemble", "dof_map",
           "rayleigh_coefficients"]
