"""A statics that fails on a nearly neutrally buoyant line says so (rfesim.api._neutral_lines):
found by varying the shipped S-lay scenario, whose pipe at 5495 kg/m^3 (0.7 x steel) weighs
0.1 % of its weight in air under water and whose statics then used up its Newton iterations
with no word on why."""
from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

import rfesim
from rfesim.api import NEUTRAL_BUOYANCY, _neutral_lines

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
G, RHO_W = 9.81, 1025.0


def s_lay(density: float) -> dict:
    data = json.loads((SCENARIOS / "s_lay.json").read_text())
    data["line_types"]["x65"]["density"] = density
    data["analysis"]["dynamics"]["enabled"] = False
    return data


def weights(data: dict) -> tuple[float, float]:
    lt = data["line_types"]["x65"]
    D, t = lt["outer_diameter"], lt["wall_thickness"]
    dry = lt["density"] * math.pi * (D - t) * t * G          # thin-walled: pi (D - t) t = pi/4 (D^2 - (D - 2t)^2)
    return dry - RHO_W * G * math.pi * D * D / 4.0, dry


def test_failed_statics_names_the_neutral_line():
    data = s_lay(5495.0)
    w, dry = weights(data)
    assert abs(w) < 1e-3 * dry
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.statics(rfesim.load_scenario(data, base_dir=SCENARIOS))
    hint = info.value.hint
    assert hint.startswith("line 'pipe' is nearly neutrally buoyant")
    assert f"submerged weight is {w:.4g} N/m" in hint and f"{dry:.4g} N/m in air" in hint


@pytest.mark.parametrize("density, neutral", [(5495.0, True), (7850.0, False), (5450.0, True), (4000.0, False)])
def test_neutral_lines(density, neutral):
    data = s_lay(density)
    w, dry = weights(data)
    assert (abs(w) < NEUTRAL_BUOYANCY * dry) == neutral
    found = _neutral_lines(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert [name for name, _, _ in found] == (["pipe"] if neutral else [])
    if neutral:
        assert found[0][1] == pytest.approx(w, rel=1e-9) and found[0][2] == pytest.approx(dry, rel=1e-9)
