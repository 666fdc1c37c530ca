"""A statics that fails says why where the scene shows it, found by varying the shipped
scenarios by factors 0.5-2:

* a nearly neutrally buoyant line (rfesim.api._neutral_lines): the S-lay pipe at 5495 kg/m^3
  (0.7 x steel) weighs 0.1 % of its weight in air under water, and its statics used up its
  Newton iterations with no word on why;
* a slack rope (rfesim.api._slack_ropes): the column crane of the lift-off scenario set 0.5 m
  lower leaves its rope 0.28 m longer than the distance from the boom tip to the module on the
  supply vessel's deck, and its statics failed the same way."""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import pytest

import rfesim
from rfesim.api import NEUTRAL_BUOYANCY, _buoyant_at_surface, _compiled, _neutral_lines, _slack_ropes, _statics_hint

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
    # the residual is the failed increment's, not that of the load factor reached (converged
    # there: the message used to quote 6.07e-08 of the force scale, at load factor 0.5)
    got = re.search(r"load factor ([\d.]+) reached, at load factor ([\d.]+) the residual stayed at ([\d.e+-]+) x",
                    info.value.message)
    assert got is not None, info.value.message
    reached, tried, residual = (float(x) for x in got.groups())
    assert tried > reached and residual > 1e-8        # above the statics' tolerance
    arc = float(re.search(r"arc length ([\d.]+) m", info.value.element).group(1))
    assert 326.0 <= arc <= 435.0                       # on the laid part near the seabed end
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


def liftoff(crane_z: float, rope: float | None = None) -> dict:
    data = json.loads((SCENARIOS / "column_crane_liftoff.json").read_text())
    data["analysis"]["dynamics"]["enabled"] = False
    data["cranes"]["crane"]["position"][2] = crane_z
    if rope is not None:
        data["cranes"]["crane"]["rope"]["length"] = rope
    return data


def test_failed_statics_names_the_slack_rope_and_the_length_that_holds():
    sc = rfesim.load_scenario(liftoff(3.5), base_dir=SCENARIOS)
    (name, length, chord, lower), = _slack_ropes(_compiled(sc))
    assert (name, length, lower) == ("crane_rope", 35.35, ", end B at body 'crane_payload'")
    assert 0.27 < length - chord < 0.28           # the crane 0.5 m lower, the rope 0.22 m short before
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.statics(sc)
    hint = info.value.hint
    assert hint.startswith(f"rope 'crane_rope' is {length - chord:.4g} m longer than the distance between its ends")
    assert f"give cranes.crane.rope.length at most {chord:.6g} m" in hint
    # the advice holds: the rope at that length converges, taut
    res = rfesim.statics(rfesim.load_scenario(liftoff(3.5, rope=round(chord, 4)), base_dir=SCENARIOS))
    assert res.line("crane_rope").tension.max() > 0.0


def test_taut_rope_is_not_slack():
    sc = rfesim.load_scenario(liftoff(4.0), base_dir=SCENARIOS)      # the shipped geometry
    assert _slack_ropes(_compiled(sc)) == []


def riser(water_density: float) -> dict:
    data = json.loads((SCENARIOS / "catenary_riser.json").read_text())
    data["environment"]["water"]["density"] = water_density
    data["analysis"]["dynamics"]["enabled"] = False
    return data


def test_a_buoyant_riser_whose_arch_reaches_the_surface_floats_there():
    # water 1.5 x as dense: the 12 in riser floats up (-58 N/m) between its anchor 200 m down
    # and the FPSO's 15 m down, and its 600 m arch over 535 m reaches the surface. With the
    # steel's E at 0.7 x its statics failed while an RFE lying at the surface was wet or dry by
    # its axis alone (its buoyancy jumped there); with the immersed section counted
    # (rfesim.loads.hydro.submergence) it converges, its crest cut by the surface. Should it
    # fail, the hint names the cause.
    data = riser(1537.5)
    data["line_types"]["pipe12"]["youngs_modulus"] = 1.449e11
    lt = data["line_types"]["pipe12"]
    D, t = lt["outer_diameter"], lt["wall_thickness"]
    w = (lt["density"] * math.pi * (D - t) * t - 1537.5 * math.pi * D * D / 4.0) * G
    sc = rfesim.load_scenario(data, base_dir=SCENARIOS)
    (name, weight, rise), = _buoyant_at_surface(sc, _compiled(sc))
    assert name == "riser" and weight == pytest.approx(w, rel=1e-9) and rise > 0.0
    res = rfesim.statics(sc)
    crest = float(res.line("riser").position[0][:, 2].max())
    assert -0.5 * D < crest < 0.5 * D                  # floating, its section cut by the surface
    hint = _statics_hint(sc, _compiled(sc))
    assert hint.startswith(f"line 'riser' is buoyant (its submerged weight is {w:.4g} N/m")


def test_heavy_riser_does_not_reach_the_surface():
    sc = rfesim.load_scenario(riser(1025.0), base_dir=SCENARIOS)
    assert _buoyant_at_surface(sc, _compiled(sc)) == []
