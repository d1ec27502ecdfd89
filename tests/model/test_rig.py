"""Rig description: the preset against Table 1, TOML round trip and edge units, and a
clear one-line error for every kind of bad input."""

import dataclasses
import math
import pickle
import tomllib
from pathlib import Path

import pytest

import rubdiag
from rubdiag.model import (
    Bearing,
    BladeContact,
    Blades,
    Casing,
    Disc,
    Material,
    Rig,
    Shaft,
    load_rig,
    rig_to_dict,
    save_rig,
)

DATA = Path(__file__).resolve().parents[2] / "data"


def test_paper_rig_matches_table1(paper_rig):
    t1 = tomllib.loads((DATA / "paper_table1.toml").read_text())
    assert paper_rig.material == Material(t1["material"]["youngs_modulus_pa"],
                                          t1["material"]["poisson_ratio"],
                                          t1["material"]["density_kg_m3"])
    assert [b.node for b in paper_rig.bearings] == [4, 26]
    for b in paper_rig.bearings:
        assert (b.k_y_n_m, b.k_z_n_m) == (t1["bearings"]["k_y_n_m"], t1["bearings"]["k_z_n_m"])
        assert (b.c_y_ns_m, b.c_z_ns_m) == (t1["bearings"]["c_y_ns_m"], t1["bearings"]["c_z_ns_m"])
    blades = paper_rig.blades
    assert (blades.count, blades.length_m, blades.width_m, blades.thickness_m) == (
        t1["blades"]["count"], t1["blades"]["length_m"], t1["blades"]["width_m"],
        t1["blades"]["thickness_m"])
    casing = paper_rig.casing
    assert (casing.axial_width_m, casing.radial_height_m) == (t1["casing"]["width_m"],
                                                              t1["casing"]["height_m"])
    assert casing.support_k_y_n_m == t1["casing"]["support_k_y_n_m"]
    assert len(paper_rig.contact.blades) == t1["contact"]["count"]
    assert paper_rig.contact.normal_stiffness_n_m == t1["contact"]["normal_stiffness_n_m"]
    assert paper_rig.loading.unbalance_kg_m == (t1["loading"]["unbalance_kg_m"],) * 2
    assert [d.node for d in paper_rig.discs] == [11, 19]
    assert paper_rig.shaft.n_elements == t1["elements"]["shaft_beam188"]
    assert paper_rig.shaft.nodes.start == 3
    assert paper_rig.nominal_gap_m() == pytest.approx(2.3e-3)
    assert paper_rig.unbalance(2).phases_rad == (0.0, math.pi)


def test_contact_pairs_blade_and_casing_at_the_same_angle(paper_rig, paper_model):
    geo = paper_model.blade_contacts
    assert geo.tip_dofs.shape == (8, 2)
    for k in range(1, 9):
        blade = paper_rig.contact.blades[k - 1]
        casing_node = paper_rig.contact_casing_node(k)
        assert paper_rig.blades.angle_rad(blade) == pytest.approx(
            paper_rig.casing.angle_rad(casing_node))
        assert geo.angle_rad[k - 1] == pytest.approx((k - 1) * math.pi / 4)
    assert paper_rig.contact_casing_node(1) == 1
    assert paper_model.dofs.labels[geo.casing_dofs[0, 0]] == "casing 1 y"
    assert paper_model.dofs.labels[geo.tip_dofs[0, 0]] == "blade 1.4 y"


def test_toml_round_trip_and_pickle(tmp_path, paper_rig):
    path = save_rig(paper_rig, tmp_path / "rig.toml")
    assert load_rig(path) == paper_rig
    assert pickle.loads(pickle.dumps(paper_rig)) == paper_rig


def test_edge_units_in_toml(tmp_path):
    text = """
[shaft]
element_lengths_mm = [100.0, 100.0]
outer_diameters_mm = 10.0
first_node = 1
[[bearings]]
node = 1
k_y_n_m = 1e6
k_z_n_m = 1e6
[[bearings]]
node = 3
k_y_n_m = 1e6
k_z_n_m = 1e6
[damping]
reference_speeds_rpm = [600.0, 1200.0]
"""
    (tmp_path / "r.toml").write_text(text)
    rig = load_rig(tmp_path / "r.toml")
    assert rig.shaft.element_lengths_m == pytest.approx((0.1, 0.1))
    assert rig.shaft.outer_diameters_m == pytest.approx((0.01, 0.01))
    assert rig.damping.reference_speeds_rad_s == pytest.approx((20 * math.pi, 40 * math.pi))
    assert rig.blades is None and rig.casing is None   # a plain rotor is a valid rig
    assert rig_to_dict(rig)["shaft"]["element_lengths_m"] == pytest.approx([0.1, 0.1])


SHAFT = Shaft((0.1, 0.1), 0.01)
BEARINGS = (Bearing(3, 1e6, 1e6),)


@pytest.mark.parametrize("make,match", [
    (lambda: Shaft((0.1, -0.01), 0.01), r"Shaft.element_lengths_m\[1\] = -0.01 .*> 0"),
    (lambda: Shaft((0.1,), 0.01, 0.02), r"Shaft.inner_diameters_m\[0\]"),
    (lambda: Material(density_kg_m3=0.0), r"Material.density_kg_m3 = 0.0 .*> 0"),
    (lambda: Material(poisson_ratio=0.7), r"Material.poisson_ratio = 0.7"),
    (lambda: Rig(SHAFT, (Bearing(99, 1e6, 1e6),)), r"Bearing.node = 99 is not a shaft node "
                                                  r"\(allowed: shaft nodes 3..5\)"),
    (lambda: Rig(SHAFT, BEARINGS, discs=(Disc(4, 0.035, 0.015),),
                 blades=Blades(16, 0.04, 0.015, 0.002, 0.035, 4),
                 casing=Casing(0.07, 0.015, 0.005)), r"Blades do not fit inside the casing"),
    (lambda: Rig(SHAFT, BEARINGS, discs=(Disc(4, 0.035, 0.015),),
                 blades=Blades(16, 0.04, 0.015, 0.002, 0.035, 4),
                 casing=Casing(0.0798, 0.015, 0.005, n_elements=40),
                 contact=BladeContact(blades=(2,))), r"no casing node at the blade's angle"),
    (lambda: BladeContact(friction_coefficient=-0.1), r"friction_coefficient = -0.1"),
    (lambda: Disc(4), r"Disc at node 4: give either"),
    (lambda: Casing(0.08, 0.015, 0.005, support="glued"), r"Casing.support = 'glued'"),
    (lambda: Rig(SHAFT, ()), r"Rig.bearings is empty"),
    (lambda: Shaft((0.1, float("nan")), 0.01), r"element_lengths_m\[1\] = nan"),
])
def test_bad_values_name_the_field_and_range(make, match):
    with pytest.raises(ValueError, match=match):
        make()


@pytest.mark.parametrize("mutate,match", [
    (lambda d: d["shaft"].update(colour="red"), r"unknown key 'shaft.colour' \(allowed: "),
    (lambda d: d.update(pump={}), r"unknown key 'pump'"),
    (lambda d: d["shaft"].update(first_node=3.5), r"shaft.first_node = 3.5 has the wrong type "
                                                   r"\(expected integer\)"),
    (lambda d: d["blades"].update(count="sixteen"), r"blades.count = 'sixteen' has the wrong"),
    (lambda d: d["bearings"][1].update(node=40), r"Bearing.node = 40 is not a shaft node"),
    (lambda d: d["contact"].update(augmented="yes"), r"contact.augmented = 'yes'"),
    (lambda d: d["shaft"].update(element_lengths_m=[0.1, -1.0]),
     r"Shaft.element_lengths_m\[1\] = -1.0"),
])
def test_bad_toml_gives_one_line_error(tmp_path, paper_rig, mutate, match):
    import tomli_w

    data = rig_to_dict(paper_rig)
    mutate(data)
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    with pytest.raises(ValueError, match=match) as info:
        load_rig(path)
    assert "\n" not in str(info.value)


def test_not_toml_and_missing_field(tmp_path):
    (tmp_path / "x.toml").write_text("[shaft\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_rig(tmp_path / "x.toml")
    (tmp_path / "y.toml").write_text("[[bearings]]\nnode = 3\nk_y_n_m = 1.0\nk_z_n_m = 1.0\n")
    with pytest.raises(ValueError, match="shaft"):
        load_rig(tmp_path / "y.toml")


def test_variants_come_from_replace(paper_rig):
    stiffer = dataclasses.replace(paper_rig, contact=dataclasses.replace(
        paper_rig.contact, friction_coefficient=0.5))
    assert stiffer.contact.friction_coefficient == 0.5
    assert paper_rig.contact.friction_coefficient == 0.4
    with pytest.raises(dataclasses.FrozenInstanceError):
        paper_rig.name = "x"


def test_import_is_light():
    import subprocess
    import sys

    code = ("import sys, rubdiag; heavy = [m for m in ('numpy', 'scipy', 'pandas', 'numba', "
            "'matplotlib') if m in sys.modules]; print(','.join(heavy))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == ""
    assert rubdiag.paper_rig is rubdiag.model.paper_rig


def test_every_public_name_resolves():
    for name in rubdiag.__all__:
        assert getattr(rubdiag, name) is not None, name
    with pytest.raises(AttributeError, match="no attribute 'nonesuch'"):
        rubdiag.nonesuch
