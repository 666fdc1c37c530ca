"""The J-lay template's default mesh resolves the hang-off: below the collar the pipe bends
within the boundary layer lambda = sqrt(EI/T_top) (9 m in scenarios/j_lay.json, T_top the
catenary's top tension), so the default elements are lambda/6 (1.5 m). The old default of
10 m, longer than lambda, gave under a 1 deg turn of the collar 29.7 kN m against 55.1 kN m
converged (and in the 60 s run with 1 deg of pitch 32.0 against 59.6 kN m)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.scenario import expand

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def tilted(element_length=None, tilt_deg=1.0, tolerance=None):
    """The J-lay template's statics with the collar turned tilt_deg steeper about its exit
    (the catenary below still leaves at the tower angle): the hang-off bends."""
    d = json.loads((SCENARIOS / "j_lay.json").read_text())
    d["analysis"]["dynamics"]["enabled"] = False
    if element_length is not None:
        d["pipelay"]["lay"]["element_length"] = element_length
    if tolerance is not None:
        d["analysis"]["statics"]["tolerance"] = tolerance
    e = expand(d)
    line, col = e["lines"]["lay"], e["supports"]["lay_collar"]
    exit_p = np.array(col["entry"]) + col["length"] * np.array(col["axis"])
    ax = np.array(col["axis"])
    th = math.atan2(-ax[2], ax[0]) + math.radians(tilt_deg)
    ax = np.array([math.cos(th), 0.0, -math.sin(th)])
    col["axis"] = ax.tolist()
    col["entry"] = (exit_p - col["length"] * ax).tolist()
    line["end_a"]["position"], line["end_a"]["direction"] = col["entry"], col["axis"]
    res = rfesim.statics(rfesim.load_scenario(e, base_dir=SCENARIOS))
    lr = res.line("lay")
    s = np.asarray(lr.sde_arc_length)
    top = s < col["length"] + 60.0                       # the collar and 60 m below its exit
    moment = float(np.abs(np.asarray(lr.bend_moment)[0][top]).max())
    t_exit = float(np.interp(col["length"], s, np.asarray(lr.tension)[0]))
    return e, moment, t_exit


def bending_stiffness(e) -> float:
    lt = e["line_types"][e["lines"]["lay"]["type"]]
    D, t = lt["outer_diameter"], lt["wall_thickness"]
    return lt["youngs_modulus"] * math.pi / 64.0 * (D ** 4 - (D - 2.0 * t) ** 4)


@pytest.fixture(scope="module")
def default_mesh():
    return tilted()


def test_default_elements_are_a_sixth_of_the_hang_off_layer(default_mesh):
    e, _, t_exit = default_mesh
    line = e["lines"]["lay"]
    EI = bending_stiffness(e)
    lam = math.sqrt(EI / t_exit)                        # from the solved tension at the collar's exit
    assert 8.5 < lam < 9.5
    assert line["length"] / line["elements"] == pytest.approx(lam / 6.0, rel=0.01)


def test_hang_off_moment_converges_at_the_default_mesh(default_mesh):
    e, moment, t_exit = default_mesh
    _, fine, _ = tilted(element_length=0.75, tolerance=1e-5)
    _, coarse, _ = tilted(element_length=10.0)
    assert moment == pytest.approx(fine, rel=0.03)
    assert coarse < 0.6 * fine                          # the old default: about half
    # below a rigid clamp's EI dtheta / lambda (the collar's pads give a little)
    EI = bending_stiffness(e)
    clamp = EI * math.radians(1.0) / math.sqrt(EI / t_exit)
    assert 0.6 * clamp < fine < clamp


def test_coarse_given_elements_are_warned_about_by_their_field():
    d = json.loads((SCENARIOS / "j_lay.json").read_text())
    d["pipelay"]["lay"]["element_length"] = 10.0
    sc = rfesim.load_scenario(d, base_dir=SCENARIOS)
    (warning,) = sc._template_warnings
    assert "element_length" in warning and "sqrt(EI/T_top)" in warning and "1.499 m" in warning
    d["pipelay"]["lay"]["element_length"] = 4.0          # below half the layer: no warning
    assert rfesim.load_scenario(d, base_dir=SCENARIOS)._template_warnings == []
