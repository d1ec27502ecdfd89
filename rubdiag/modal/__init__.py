"""Linear analysis: modes at speed, Campbell diagram, critical speeds, harmonic and
unbalance responses, the threshold of instability on journal bearings, and calibration of
unknown geometry to target critical speeds.

Examples
--------
A Jeffcott rotor: a 10-kg disc at the middle of a 1-m, 20-mm steel shaft of negligible mass
on stiff bearings. Its first critical speed is sqrt(k/m), with the shaft's midspan
stiffness k = 48 E I / L³:

>>> import math
>>> from rubdiag.assembly import assemble
>>> from rubdiag.model import (Bearing, Damping, Disc, Material, Rig,
...                            Shaft, Unbalance)
>>> stiff = dict(k_y_n_m=1e12, k_z_n_m=1e12)
>>> rig = Rig(
...     shaft=Shaft(element_lengths_m=(0.125,) * 8, outer_diameters_m=0.02,
...                 first_node=1),
...     bearings=(Bearing(node=1, **stiff), Bearing(node=9, **stiff)),
...     discs=(Disc(node=5, mass_kg=10.0, polar_inertia_kg_m2=0.05,
...                 diametral_inertia_kg_m2=0.025),),
...     material=Material(density_kg_m3=1.0),
...     damping=Damping(xi_1=0.01, xi_2=0.01,
...                     reference_speeds_rad_s=(50.0, 200.0)))
>>> model = assemble(rig)
>>> m = 10.0                                              # kg
>>> k = 48 * 210e9 * (math.pi * 0.02**4 / 64) / 1.0**3    # N/m
>>> w = critical_speeds(model, n=1)[0]
>>> print(f"{w:.2f} rad/s, sqrt(k/m) = {math.sqrt(k / m):.2f}")
88.94 rad/s, sqrt(k/m) = 88.98

An unbalance u = 1e-4 kg·m on the disc: well below the critical speed the disc's orbit
has the radius u Ω² / (k − m Ω²); at the critical speed, u / (2 ξ m), with ξ the Rayleigh
damping ratio there:

>>> u = Unbalance(magnitudes_kg_m=(1e-4,), phases_rad=(0.0,))
>>> r = harmonic_response(model, 30.0, u).orbit_semi_major(5)
>>> formula = 1e-4 * 30.0**2 / (k - m * 30.0**2)
>>> print(f"{r * 1e6:.3f} um, formula {formula * 1e6:.3f} um")
1.284 um, formula 1.283 um
>>> alpha, beta = model.rayleigh
>>> xi = alpha / (2 * w) + beta * w / 2
>>> r = harmonic_response(model, w, u).orbit_semi_major(5)
>>> print(f"{r * 1e3:.4f} mm, formula {1e-4 / (2 * xi * m) * 1e3:.4f} mm")
0.6207 mm, formula 0.6207 mm
"""

from rubdiag.modal._calibrate import KNOBS, Calibration, calibrate
from rubdiag.modal._campbell import Campbell, campbell
from rubdiag.modal._critical import (
    CriticalSpeeds,
    critical_speeds,
    direct_film_stiffness,
    synchronous_modes,
    with_rayleigh,
)
from rubdiag.modal._eigen import Modes, modes
from rubdiag.modal._harmonic import (
    HarmonicResponse,
    UnbalanceResponse,
    harmonic_response,
    unbalance_response,
)
from rubdiag.modal._stability import StabilityThreshold, stability_threshold, whirl_threshold

__all__ = [
    "KNOBS",
    "Calibration",
    "Campbell",
    "CriticalSpeeds",
    "HarmonicResponse",
    "Modes",
    "StabilityThreshold",
    "UnbalanceResponse",
    "calibrate",
    "campbell",
    "critical_speeds",
    "direct_film_stiffness",
    "harmonic_response",
    "modes",
    "stability_threshold",
    "synchronous_modes",
    "unbalance_response",
    "whirl_threshold",
    "with_rayleigh",
]
