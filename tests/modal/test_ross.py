"""Cross-check of rubdiag against ROSS (ross-rotordynamics): forward critical speeds (within
1 %, and to 1e-6), plus undamped natural frequencies at speed and the unbalance response.

Skipped when ROSS is not installed (the project venv does not have it); run with an
interpreter that has both, e.g. ``/tmp/rossenv/bin/python -m pytest tests/modal/test_ross.py``.
See benchmarks/compare_ross.py for the same comparison as a script, with timings.

The rotor is the paper rig without blades and casing (24 Timoshenko elements with the
paper.toml lengths, rigid discs r = 35 mm, t = 15 mm at nodes 11 and 19, bearings
k_y = 500e6, k_z = 200e6 N/m at nodes 4 and 26), with its solid 10 mm shaft and with a
thick hollow 40/20 mm shaft on which shear deformation and rotary inertia move the critical
speeds by several per cent (so that the 1 % bar can tell a model without them apart).
Axes: rubdiag (x axial; y, z lateral) -> ROSS (z axial; x, y lateral), y -> x, z -> y.
"""

import dataclasses
import math
import warnings

import numpy as np
import pytest

rs = pytest.importorskip("ross")

from rubdiag.assembly import assemble  # noqa: E402
from rubdiag.modal import critical_speeds, modes, unbalance_response  # noqa: E402
from rubdiag.model import Bearing, Damping, Disc, Material, Rig, Shaft, Unbalance  # noqa: E402
from rubdiag.model import paper_rig as load_paper_rig  # noqa: E402

RPM = math.pi / 30
N_CRITICAL = 2


def rotor_rig(outer_m: float, inner_m: float) -> Rig:
    paper = load_paper_rig()
    shaft = Shaft(paper.shaft.element_lengths_m, outer_m, inner_m, paper.shaft.first_node)
    return Rig(
        shaft=shaft,
        bearings=(Bearing(4, 500e6, 200e6), Bearing(26, 500e6, 200e6)),
        discs=(Disc(11, outer_radius_m=0.035, thickness_m=0.015),
               Disc(19, outer_radius_m=0.035, thickness_m=0.015)),
        material=Material(210e9, 0.3, 7850.0),
    )


def ross_rotor(rig: Rig, **physics):
    """The same rotor in ROSS; ``physics`` overrides ShaftElement's switches."""
    mat = rig.material
    steel = rs.Material(name="rubdiag_steel", rho=mat.density_kg_m3,
                        E=mat.youngs_modulus_pa, Poisson=mat.poisson_ratio)
    options = {"shear_effects": True, "rotary_inertia": True, "gyroscopic": True,
               "shear_method_calc": "cowper", **physics}
    first = rig.shaft.first_node
    shaft = [rs.ShaftElement(L=length, idl=di, odl=do, material=steel, **options)
             for length, do, di in zip(rig.shaft.element_lengths_m,
                                       rig.shaft.outer_diameters_m,
                                       rig.shaft.inner_diameters_m, strict=True)]
    discs = []
    for disc in rig.discs:
        m, ip, idiam = disc.inertia(mat.density_kg_m3)   # the same inertias, explicitly
        discs.append(rs.DiskElement(n=disc.node - first, m=m, Id=idiam, Ip=ip))
    bearings = [rs.BearingElement(n=b.node - first, kxx=b.k_y_n_m, kyy=b.k_z_n_m,
                                  cxx=b.c_y_ns_m, cyy=b.c_z_ns_m) for b in rig.bearings]
    return rs.Rotor(shaft, discs, bearings)


def lateral_share(rotor, evector) -> float:
    """Fraction of |q|² of a ROSS eigenvector in its lateral DOFs (x, y, α, β)."""
    q = evector[: evector.size // 2].reshape(-1, rotor.number_dof)   # [x, y, z, α, β, θ]
    return float(np.sum(np.abs(q[:, [0, 1, 3, 4]]) ** 2) / np.sum(np.abs(q) ** 2))


def ross_forward_critical_speeds(rig: Rig, n: int = N_CRITICAL, **physics) -> np.ndarray:
    """ROSS's run_critical_speed crossings whose eigenvector whirls forward (rad/s).

    The whirl is the net whirl of ROSS's own eigenvector at the crossing (as rubdiag
    measures it) rather than ROSS's label, which says "Mixed" for some forward modes.
    """
    rotor = ross_rotor(rig, **physics)
    num_modes = 4 * n + 8
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_critical_speed(num_modes=num_modes, rtol=1e-8)
        forward = []
        for i, (wn, wd) in enumerate(zip(result.wn(), result.wd(), strict=True)):
            evector = rotor.run_modal(wd, num_modes).evectors[:, i]
            q = evector[: evector.size // 2].reshape(-1, rotor.number_dof)
            x, y = q[:, 0], q[:, 1]
            if lateral_share(rotor, evector) > 0.5 and np.sum((x * y.conj()).imag) > 0:
                forward.append(wn)
    return np.sort(forward)[:n]


ROTORS = {"paper-solid-10mm": (0.010, 0.0), "hollow-40-20mm": (0.040, 0.020)}


@pytest.fixture(scope="module", params=list(ROTORS))
def compared(request):
    rig = rotor_rig(*ROTORS[request.param])
    ours = critical_speeds(assemble(rig), n=N_CRITICAL)
    theirs = ross_forward_critical_speeds(rig)
    return request.param, rig, ours, theirs


def test_forward_critical_speeds_match_ross_within_1_percent(compared):
    name, _, ours, theirs = compared
    assert len(ours) == N_CRITICAL, ours
    assert len(theirs) == N_CRITICAL, theirs
    np.testing.assert_allclose(ours, theirs, rtol=0.01,
                               err_msg=f"{name}: rubdiag vs ROSS forward critical speeds")


def test_same_element_formulation_as_ross(compared):
    """Both use the Timoshenko element of interdependent interpolation with Cowper's κ, so
    the speeds agree to solver precision (measured ~1e-10); 1e-6 still catches a change
    of κ formula (Hutchinson's moves them by ≥ 7e-5)."""
    name, _, ours, theirs = compared
    np.testing.assert_allclose(ours, theirs, rtol=1e-6, err_msg=name)


def test_ross_without_shear_misses_the_hollow_rotor_by_more_than_1_percent():
    """The 1 % bar is discriminating: leaving out shear in ROSS moves mode 2 of the thick
    hollow rotor by ~2.7 %. (On the slender paper shaft it moves it by only ~0.12 %.)"""
    rig = rotor_rig(*ROTORS["hollow-40-20mm"])
    ours = critical_speeds(assemble(rig), n=N_CRITICAL)
    no_shear = ross_forward_critical_speeds(rig, shear_effects=False)
    assert np.max(np.abs(no_shear / ours - 1.0)) > 0.01


def test_paper_shaft_matches_the_preset():
    """The compared rotor really is the paper rig's shaft, discs and bearings."""
    paper = load_paper_rig()
    rig = rotor_rig(*ROTORS["paper-solid-10mm"])
    assert rig.shaft == paper.shaft
    assert [(b.node, b.k_y_n_m, b.k_z_n_m) for b in rig.bearings] == [
        (b.node, b.k_y_n_m, b.k_z_n_m) for b in paper.bearings]
    assert rig.discs == paper.discs
    assert rig.material == paper.material


@pytest.mark.parametrize("speed_rpm", [0.0, 8000.0])
def test_undamped_natural_frequencies_match_ross(speed_rpm):
    """modes(..., damped=False) against ROSS's run_modal: the 6 lowest lateral modes
    (ROSS's torsional mode, which rubdiag does not model, is left out)."""
    rig = rotor_rig(*ROTORS["paper-solid-10mm"])
    ours = modes(assemble(rig), speed_rpm * RPM, n_modes=6, damped=False).damped_frequencies
    rotor = ross_rotor(rig)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        modal = rotor.run_modal(speed_rpm * RPM, num_modes=20)
    lateral = [w for i, w in enumerate(modal.wd)
               if w > 1.0 and lateral_share(rotor, modal.evectors[:, i]) > 0.5]
    np.testing.assert_allclose(ours, lateral[:6], rtol=1e-6)


def test_unbalance_response_matches_ross():
    """Complex unbalance response (amplitude and phase) with bearing damping only, out-of-
    phase unbalances on both discs, against ROSS's run_unbalance_response: same force
    convention (F_y = uΩ²e^{iφ}, F_z = −iF_y) and same solution."""
    rig = dataclasses.replace(
        rotor_rig(*ROTORS["paper-solid-10mm"]),
        damping=Damping(0.0, 0.0, (1.0, 2.0)),        # no Rayleigh damping
        bearings=(Bearing(4, 500e6, 200e6, 2e3, 1e3), Bearing(26, 500e6, 200e6, 2e3, 1e3)))
    unbalance = Unbalance((1.56e-4, 1.56e-4), (0.3, math.pi + 0.3))
    speeds = np.array([500.0, 1500.0, 1596.0, 3000.0, 6030.0, 8000.0]) * RPM
    points = ((11, "y"), (11, "z"), (19, "y"), (19, "z"), (4, "z"))
    ours = unbalance_response(assemble(rig), speeds, unbalance, points=points).amplitudes
    rotor = ross_rotor(rig)
    first = rig.shaft.first_node
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = rotor.run_unbalance_response(
            node=[d.node - first for d in rig.discs],
            unbalance_magnitude=list(unbalance.magnitudes_kg_m),
            unbalance_phase=list(unbalance.phases_rad), frequency=speeds)
    rows = [rotor.number_dof * (node - first) + (0 if d == "y" else 1) for node, d in points]
    theirs = np.asarray(result.forced_resp)[rows, :].T
    np.testing.assert_allclose(ours, theirs, rtol=1e-6)
