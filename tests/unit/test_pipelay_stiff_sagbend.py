"""The pipelay templates warn when the natural catenary cannot describe the sagbend: its
radius at the touchdown H/w is shorter than the bending boundary layer sqrt(EI/H) (a reel-lay
ramp at 89.3 deg in 300 m failed statics; at 89.5 deg the tensioner carried 996 kN, with no
word on why)."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
G, RHO_W, RHO_S = 9.81, 1025.0, 7850.0
D, T = 0.3239, 0.0159          # the templates' 12.75 in X65 pipe, empty
E = 2.07e11


def _load(name, **changes):
    sc = json.loads((SCENARIOS / name).read_text())
    for v in (sc.get("vessels") or {}).values():
        if "file" in v.get("motion", {}):
            v["motion"]["file"] = str(SCENARIOS / v["motion"]["file"])
    sc["pipelay"]["lay"].update(changes)
    return [w for w in rfesim.load_scenario(sc)._template_warnings if "boundary layer" in w]


def _numbers(w):
    H, radius, layer = (float(x) for x in re.search(
        r"H = ([\d.]+) kN makes a sagbend radius H/w of ([\d.]+) m, shorter than the pipe's bending "
        r"boundary layer sqrt\(EI/H\) = ([\d.]+) m", w).groups())
    return 1e3 * H, radius, layer


def test_a_steep_reel_lay_ramp_is_warned_about_with_consistent_numbers():
    (w,) = _load("reel_lay.json", ramp_angle_deg=85.0)
    assert w.startswith("pipelay.lay.ramp_angle_deg: at 85 deg, the natural catenary's lay tension")
    H, radius, layer = _numbers(w)
    area = math.pi / 4 * (D ** 2 - (D - 2 * T) ** 2)
    weight = (RHO_S * area - RHO_W * math.pi / 4 * D ** 2) * G
    EI = E * math.pi / 64 * (D ** 4 - (D - 2 * T) ** 4)
    assert radius == pytest.approx(H / weight, rel=2e-3)
    assert layer == pytest.approx(math.sqrt(EI / H), rel=2e-3)
    assert layer > radius


@pytest.mark.parametrize("name, changes", [("reel_lay.json", {}), ("reel_lay.json", {"ramp_angle_deg": 80.0}),
                                           ("j_lay.json", {}), ("s_lay_template.json", {})])
def test_the_shipped_and_moderate_layouts_are_not_warned_about(name, changes):
    assert _load(name, **changes) == []


def test_a_slack_s_lay_tension_is_warned_about_on_its_field():
    (w,) = _load("s_lay_template.json", tension=3000.0)
    assert w.startswith("pipelay.lay.tension: the lay tension H = 3 kN") and "give a larger tension" in w
