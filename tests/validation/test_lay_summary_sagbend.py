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
