"""The test rotor on plain journal bearings shared by the modal and the run tests: a
practically rigid shaft (d = 200 mm, 0.3 m, nearly massless; ``stiff=False``: d = 12 mm)
with a 20 kg disc at mid-span on two identical short bearings (R = 20 mm, L = 10 mm,
c = 50 um, 0.02 Pa s), each carrying half the weight, 98.1 N, along -y."""

from __future__ import annotations

from rubdiag.model import Bearing, Damping, Disc, JournalFilm, Loading, Material, Rig, Shaft

MASS, G = 20.0, 9.81
FILM = dict(viscosity_pa_s=0.02, radius_m=0.02, length_m=0.01, clearance_m=50e-6)
LOAD = MASS * G / 2
NO_DAMPING = Damping(0.0, 0.0, (100.0, 200.0))


def rig(stiff: bool = True) -> Rig:
    film = JournalFilm(**FILM, load_n=LOAD)
    n_el = 6
    d = 0.2 if stiff else 0.012
    shaft = Shaft((0.3 / n_el,) * n_el, d, first_node=0)
    disc = Disc(n_el // 2, mass_kg=MASS, polar_inertia_kg_m2=0.05, diametral_inertia_kg_m2=0.03)
    return Rig(shaft=shaft, bearings=(Bearing(0, 0.0, 0.0, journal=film),
                                      Bearing(n_el, 0.0, 0.0, journal=film)),
               discs=(disc,), material=Material(210e9, 0.3, 1e-3), damping=NO_DAMPING,
               loading=Loading((1e-5,)))


def whip_rig() -> Rig:
    """The same disc and films on a steel shaft of 25 mm, whose bending stiffness (48 E I /
    L³ = 7.2 MN/m) is of the films' order: the first mode moves the journals, and well above
    its threshold it whips."""
    import dataclasses

    return dataclasses.replace(rig(stiff=False), shaft=Shaft((0.05,) * 6, 0.025, first_node=0),
                               material=Material(210e9, 0.3, 7850.0))
