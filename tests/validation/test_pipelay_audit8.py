"""S-lay / J-lay outputs after audit 8 (/tmp/audit8_lay/report.md), against hand calculations:

* C1: the S-lay template's default elements are a third of the roller-station spacing, so
  the stations along the stinger carry T s / R_p + w s cos(phi) (before: 4 m elements on 6 m
  spacing, every other station 0 and its neighbours twice that); a given element length
  above half the spacing gets a statics warning naming the template field;
* C2: ``top_tension`` of a line without a tensioner is the axial force at end A (before:
  |end_a_force|, the clamp's shear included, +3.3 %);
* C3: statics reaches the template's ``tension`` (before: H settled 4.3 % low for S-lay and
  1.7 % low for J-lay given the tension);
* S2: ``*_total_strain`` and the ``axial_strain`` / ``total_strain`` range graphs: the
  wall's axial strain from the true wall tension and the Lame stresses, plus kappa D / 2.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError
from rfesim.lay_results import lay_summary
from rfesim.scenario import expand

ROOT = Path(__file__).resolve().parents[2]
G, RHO_W = 9.81, 1025.0
D, T_WALL, E, RHO, NU = 0.3239, 0.0159, 2.07e11, 7850.0, 0.3
AREA = math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)
EA = E * AREA
W_AIR = RHO * AREA * G                                      # 376.6 N/m
W_SUB = W_AIR - RHO_W * math.pi / 4 * D ** 2 * G            # 356.25 N/m
H_GIVEN = 150e3
# the S-lay template's stinger (V-rollers at 30 deg, roller radius 0.15 m, radius 100 m,
# first station 2 m above the water line) and its laid pipe's axis
LIFT = (D / 2 + 0.15) / math.cos(math.radians(30.0))
RP = 100.0 + LIFT
Z_A = 2.0 + LIFT
Z_LAY = -130.0 + D / 2 - W_SUB / 1e6


def template(**lay):
    data = json.loads((ROOT / "scenarios" / "s_lay_template.json").read_text())
    data["analysis"]["dynamics"]["enabled"] = False
    data["pipelay"]["lay"].pop("element_length", None)
    data["pipelay"]["lay"].update(lay)
    return rfesim.load_scenario(data, base_dir=ROOT / "scenarios")


@pytest.fixture(scope="module")
def slay():
    sc = template()
    return sc, rfesim.statics(sc)


def test_s_lay_default_elements_are_a_third_of_the_station_spacing(slay):
    sc, _ = slay
    line, stinger = sc.lines["lay"], sc.supports["lay_stinger"]
    assert line.elements == math.ceil(line.length / (stinger.spacing / 3.0) - 1e-9)
    assert line.length / line.elements <= stinger.spacing / 3.0
    assert sc._template_warnings == []


def test_s_lay_station_reactions_follow_the_tension_over_the_arc(slay):
    """Away from the entry (stations 0-1, where the straight deck line turns onto the arc:
    tests/validation/test_slay_first_station.py) and the lift-off
    (stations 7-9), a station carries the tension turned over its spacing, T s / R_p, and
    the weight of a spacing normal to the arc, w s cos(phi): stations 3 (in air), 5 and 6
    (in water) within 5 %; the V-rollers' normals lean 30 deg, so the pair's normal forces
    times cos 30 deg. With 4 m elements station 3 carried 31.5 kN, station 5 25.5 kN and
    station 6 nothing."""
    sc, res = slay
    s = sc.supports["lay_stinger"].spacing
    rr = np.asarray(res.supports["lay_stinger"].roller_reaction[0])
    station = (rr[0::2] + rr[1::2]) * math.cos(math.radians(30.0))
    for i in (3, 5, 6):
        phi = i * s / 100.0
        z = Z_A - RP * (1.0 - math.cos(phi))
        T = H_GIVEN + W_SUB * (min(z, 0.0) - Z_LAY) + W_AIR * max(z, 0.0)   # frictionless: dT = w dz
        w = W_AIR if z > 0.0 else W_SUB
        assert station[i] == pytest.approx(T * s / RP + w * s * math.cos(phi), rel=0.05), i
    assert np.all(station[:10] > 0.0)                       # no station left out between the ends


def test_s_lay_statics_carries_the_template_tension(slay):
    """H (the pinned end B's horizontal force) within 0.5 % of the template's 150 kN, and the
    tensioner's grip force H + w_s (z_surface - z_lay) + w_air z_A (the string's effective
    tension over a frictionless path: dT = w dz) = 199.06 kN, within the bending's share of
    the axial force, EI / R_p^2 = 3.75 kN (over the arc dN/ds = -Q / R_p with Q = dM/ds, and
    M goes 0 -> EI / R_p -> 0 from the tensioner over the stinger into the span; measured
    -1.5 kN). Before: H 143.6 kN, grip 192.6 kN (6.4 kN low). Statics hauled the pipe in to
    get there: the payout starts negative."""
    _, res = slay
    H = -res.line("lay").end_b_force[0][0]
    assert H == pytest.approx(H_GIVEN, rel=0.005)
    top = lay_summary(res)["top_tension"][0]
    expected = H_GIVEN + W_SUB * (0.0 - Z_LAY) + W_AIR * Z_A
    assert expected == pytest.approx(199.06e3, abs=10.0)
    EI = E * math.pi / 64 * (D ** 4 - (D - 2 * T_WALL) ** 4)
    assert top == pytest.approx(expected, abs=EI / RP ** 2)
    assert res.tensioners["lay_tensioner"].payout[0] < 0.0
    assert "horizontal_tension" in json.loads(res.scenario_json)["supports"]["lay_tensioner"]


def test_j_lay_given_the_tension_carries_it():
    """J-lay given the tension of the 85 deg catenary, H = w h cos / (1 - cos) = 40.81 kN:
    statics pays the collar's pipe until end B carries it (before: 40.14 kN, -1.7 %)."""
    data = json.loads((ROOT / "scenarios" / "j_lay.json").read_text())
    data["analysis"]["dynamics"]["enabled"] = False
    lay = data["pipelay"]["lay"]
    lay.pop("tower_angle_deg")
    h = 0.0 - (-1200.0 + D / 2 - W_SUB / 1e6)
    c = math.cos(math.radians(85.0))
    lay["tension"] = W_SUB * h * c / (1 - c)
    assert lay["tension"] == pytest.approx(40.81e3, abs=10.0)
    res = rfesim.statics(rfesim.load_scenario(data, base_dir=ROOT / "scenarios"))
    assert -res.line("lay").end_b_force[0][0] == pytest.approx(lay["tension"], rel=0.005)
    assert lay_summary(res)["departure_angle"][0] == pytest.approx(85.0, abs=0.5)


def test_a_coarse_s_lay_mesh_is_warned_about_by_its_field():
    sc = template(element_length=4.0)
    assert len(sc._template_warnings) == 1
    warning = sc._template_warnings[0]
    assert warning.startswith("pipelay.lay.element_length: elements of 3.99")
    assert "half the stinger's roller-station spacing (5.985 m)" in warning
    assert template(elements=100)._template_warnings[0].startswith("pipelay.lay.elements: elements of 4.5")
    assert template(element_length=2.9)._template_warnings == []        # below half the spacing
    res = rfesim.statics(sc)
    assert "statics warning: pipelay.lay.element_length: elements of" in res.message


def test_horizontal_tension_needs_a_held_end_b_and_one_tensioner():
    data = json.loads((ROOT / "scenarios" / "s_lay_template.json").read_text())
    expanded = expand(data)
    expanded["lines"]["lay"]["end_b"] = {"attach": "free"}
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(expanded, base_dir=ROOT / "scenarios")
    assert "supports.lay_tensioner.horizontal_tension" in str(err.value)
    assert "needs end B of line 'lay' held" in str(err.value)
    expanded = expand(data)
    expanded["supports"]["lay_tensioner2"] = dict(expanded["supports"]["lay_tensioner"])
    with pytest.raises(ScenarioError) as err:
        rfesim.load_scenario(expanded, base_dir=ROOT / "scenarios")
    assert "supports.lay_tensioner2.horizontal_tension" in str(err.value)
    assert "supports.lay_tensioner sets the horizontal tension of line 'lay' already" in str(err.value)


def test_top_tension_without_a_tensioner_is_the_axial_force():
    """scenarios/s_lay.json: end A clamped on the barge (no tensioner). The axial force there
    is H + w_s (0 - z_B) + w_air z_A (effective tension over a frictionless path), 187.5 kN;
    the force's magnitude, 193.8 kN, includes the clamp's shear (48.9 kN) and was reported
    before."""
    res = rfesim.statics(rfesim.load_scenario(ROOT / "scenarios" / "s_lay.json"))
    lr = res.line("pipe")
    top = lay_summary(res)["top_tension"][0]
    H = -lr.end_b_force[0][0]
    z_a, z_b = 2.3602088329474076, -116.80688549512683       # the scenario's ends
    assert top == pytest.approx(H + W_SUB * (0.0 - z_b) + W_AIR * z_a, rel=1e-3)
    assert top == pytest.approx(float(np.dot(lr.end_a_force[0], lr.end_a_direction[0])), rel=1e-12)
    assert top == pytest.approx(lr.tension[0][0], rel=1e-3)                 # the first SDE's tension
    assert np.linalg.norm(lr.end_a_force[0]) > 1.03 * top


def test_total_strain_adds_the_wall_axial_strain(slay):
    """axial strain of the wall eps_a = (T_w + 2 nu p_e A_e) / EA with T_w = T_e - p_e A_e
    (empty pipe: no internal pressure), p_e = rho_w g (0 - z) under water, 0 in air;
    total = eps_a + kappa D / 2 (statics: one time, so min = max = mean)."""
    _, res = slay
    out = lay_summary(res)
    lr = res.line("lay")
    T = lr.tension[0]
    z = lr.position[0][1:-1, 2]
    p_e = RHO_W * G * np.maximum(-z, 0.0)
    A_e = math.pi / 4 * D ** 2
    eps_a = (T - (1.0 - 2.0 * NU) * p_e * A_e) / EA
    graphs = out["range_graphs"]
    np.testing.assert_allclose(graphs["axial_strain"]["max"], eps_a, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(graphs["total_strain"]["mean"], eps_a + lr.curvature[0] * D / 2, rtol=1e-9)
    # in air at the overbend: T / EA, 6e-5 on a bending strain of 1.7e-3; in the sagbend the
    # external pressure takes 0.4 p_e A_e (41 kN at 125 m) off the effective tension
    air = z > 0.0
    assert eps_a[air] == pytest.approx(T[air] / EA, rel=1e-12)
    assert out["overbend_total_strain"] > out["overbend_strain"] + 0.9 * T[air].min() / EA
    assert out["overbend_total_strain"] < out["overbend_strain"] + 1.1 * T.max() / EA
    deep = z < -100.0
    lo, hi = eps_a[deep].min(), eps_a[deep].max()
    assert out["sagbend_strain"] + lo <= out["sagbend_total_strain"] <= out["sagbend_strain"] + hi


def test_a_spacing_whose_default_elements_are_too_many_is_named():
    """The default elements follow the station spacing: a 1 cm spacing makes elements of
    3.3 mm, 136000 on the line, more than a line may have; the error names the spacing (the
    user wrote no element_length)."""
    with pytest.raises(ScenarioError) as err:
        template(stinger={"radius": 100.0, "spacing": 0.01})
    assert "pipelay.lay.stinger.spacing: the default elements, a third of the station spacing" in str(err.value)
