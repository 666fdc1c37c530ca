"""lay_summary's sag bend lies beyond the lift-off point: a reel-lay pipe, bent plastic on
the drum, over the aligner and through the straightener, must not lend those moments to the
sag bend (before: 283 kN m from the ramp, above the 249 kN m a natural catenary's touchdown
curvature allows)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.lay_results import lay_summary

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def reel_run():
    sc = rfesim.load_scenario(ROOT / "scenarios" / "reel_lay.json",
                              overrides={"analysis.dynamics.duration": 1.0})
    return rfesim.simulate(sc)


def test_reel_lay_sagbend_moment_is_the_suspended_pipes(reel_run):
    res = reel_run
    out = lay_summary(res)
    sc = json.loads(res.scenario_json)
    lt = sc["line_types"][sc["lines"][out["line"]]["type"]]
    D, t, E = lt["outer_diameter"], lt["wall_thickness"], lt["youngs_modulus"]
    EI = E * math.pi / 64.0 * (D ** 4 - (D - 2.0 * t) ** 4)
    rho_w = sc["environment"]["water"]["density"]
    w = (lt["density"] * math.pi / 4.0 * (D ** 2 - (D - 2.0 * t) ** 2)
         + (lt.get("contents_density") or 0.0) * math.pi / 4.0 * (D - 2.0 * t) ** 2
         - rho_w * math.pi / 4.0 * D ** 2) * 9.80665            # submerged weight, N/m
    lr = res.line(out["line"])
    H = float(np.abs(np.asarray(lr.end_b_force)[:, 0]).max())
    # the natural catenary's touchdown curvature w/H bounds the stiffened sag bend's
    # (the bending boundary layer lowers the peak); the ramp's plastic bends reach far beyond
    bound = EI * w / H
    assert 0.7 * bound < out["sagbend_moment"] <= bound
    # and the largest moment of the suspended span (lift-off to touchdown) is the one reported
    s = np.asarray(lr.sde_arc_length)
    m = np.asarray(lr.bend_moment)
    k = len(res.time) - 1
    span = (s > out["departure_arc_length"][k]) & (s < np.asarray(lr.touchdown_arc_length)[k])
    assert out["sagbend_moment"] >= float(m[k][span].max()) - 1e-6
    # the pipe on the ramp carries much more (plastic), and it is the overbend's
    assert out["overbend_moment"] > 2.0 * bound


def test_deep_sagbend_total_strain_is_the_compressive_fibre():
    """scenarios/j_lay.json, 1200 m of water: at the sag bend's peak (z -1191.5 m, T 42.3 kN,
    p_e 11.98 MPa) the wall is in axial compression, eps_a = (T - p_e A_e + 2 nu p_e A_e) / EA
    = -1.107e-4, against the bending strain kappa D / 2 = 1.079e-3. Before,
    sagbend_total_strain was the tension-side fibre eps_a + kappa D / 2 = 0.000968, 19 % below
    the compressive outer fibre's |eps_a - kappa D / 2| = 0.001190 that DNV-ST-F101's
    displacement-controlled check takes; now it is |eps_a| + kappa D / 2, with the
    tension- and compression-side fibres beside it."""
    res = rfesim.statics(rfesim.load_scenario(ROOT / "scenarios" / "j_lay.json"))
    out = lay_summary(res)
    lr = res.line(out["line"])
    sc = json.loads(res.scenario_json)
    lt = sc["line_types"][sc["lines"][out["line"]]["type"]]
    D, t, E, nu = lt["outer_diameter"], lt["wall_thickness"], lt["youngs_modulus"], 0.3
    A, A_e = math.pi / 4 * (D ** 2 - (D - 2 * t) ** 2), math.pi / 4 * D ** 2
    kappa = np.asarray(lr.curvature)[0]
    s = np.asarray(lr.sde_arc_length)
    td = float(np.asarray(lr.touchdown_arc_length)[0])
    span = (s > out["departure_arc_length"][0]) & (s < td)
    i = int(np.flatnonzero(span)[np.argmax(kappa[span])])           # the sag bend's peak
    z = float(np.asarray(lr.position)[0, i + 1, 2])
    T = float(np.asarray(lr.tension)[0, i])
    p_e = sc["environment"]["water"]["density"] * sc["environment"]["gravity"] * -z
    eps_a = (T - p_e * A_e + 2.0 * nu * p_e * A_e) / (E * A)
    bend = kappa[i] * D / 2
    assert z == pytest.approx(-1191.5, abs=1.0)
    assert eps_a == pytest.approx(-1.107e-4, rel=5e-3)
    assert bend == pytest.approx(1.079e-3, rel=2e-3)
    assert out["sagbend_strain"] == pytest.approx(bend, rel=1e-9)
    assert out["sagbend_total_strain"] == pytest.approx(bend - eps_a, rel=1e-6)          # 0.001190
    assert out["sagbend_total_strain"] == pytest.approx(0.001190, abs=2e-6)
    assert out["sagbend_compressive_strain"] == pytest.approx(out["sagbend_total_strain"], rel=1e-12)
    assert out["sagbend_tensile_strain"] == pytest.approx(bend + eps_a, rel=1e-3)        # 0.000968, before
    assert out["sagbend_total_strain"] > 1.2 * out["sagbend_tensile_strain"]
    g = out["range_graphs"]
    np.testing.assert_allclose(g["total_strain"]["max"], np.abs(g["axial_strain"]["max"]) + kappa * D / 2,
                               rtol=1e-12)
    np.testing.assert_allclose(g["compressive_strain"]["max"] - g["tensile_strain"]["max"],
                               -2.0 * g["axial_strain"]["max"], rtol=1e-9, atol=1e-15)
    # the overbend in air is in tension: its largest fibre is the tension side's
    assert out["overbend_total_strain"] == pytest.approx(out["overbend_tensile_strain"], rel=1e-12)
