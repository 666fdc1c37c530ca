"""Scenario schema of the sea environment: waves, current, RAO and CSV vessel motions.
Bad input raises ScenarioError naming the field; the CONTRACT.md example is valid."""
from __future__ import annotations

import copy
from pathlib import Path

import pytest

import rfesim
from rfesim import ScenarioError

DATA = Path(__file__).resolve().parents[2] / "scenarios" / "data"

RAOS = {"periods": [5.0, 10.0], "headings_deg": [0.0, 180.0],
        "heave": {"amplitude": [[0.2, 0.2], [0.9, 0.9]], "phase_deg": [[10.0, 10.0], [0.0, 0.0]]}}

BASE = {
    "environment": {"gravity": 9.81, "water": {
        "density": 1025.0, "depth": 100.0,
        "current": {"profile": [[0.0, 1.0], [-100.0, 0.2]], "direction_deg": 0.0},
        "waves": {"kind": "jonswap", "hs": 2.5, "tp": 8.0, "gamma": 3.3, "direction_deg": 180.0, "seed": 1}}},
    "vessels": {"barge": {"position": [0, 0, 0], "motion": {"kind": "rao", "raos": RAOS}}},
}


DELETE = object()


def changed(path: str, value, base=None):
    """A copy of ``base`` (default BASE) with the dotted ``path`` set to ``value`` (or deleted)."""
    data = copy.deepcopy(BASE if base is None else base)
    keys = path.split(".")
    cur = data
    for k in keys[:-1]:
        cur = cur[int(k)] if isinstance(cur, list) else cur[k]
    if value is DELETE:
        del cur[keys[-1]]
    elif isinstance(cur, list):
        cur[int(keys[-1])] = value
    else:
        cur[keys[-1]] = value
    return data


def changes(*pairs):
    data = BASE
    for path, value in pairs:
        data = changed(path, value, data)
    return data


W = "environment.water"
AIRY = {"kind": "airy", "height": 2.0, "period": 8.0}

CASES = [
    (changed(f"{W}.waves", {**AIRY, "height": 20.0}), f"{W}.waves.height", "breaking limit"),
    (changes((f"{W}.waves", {**AIRY, "height": 9.0, "period": 12.0}), (f"{W}.depth", 10.0),
             (f"{W}.current", DELETE)), f"{W}.waves.height", "tanh(kh)/7"),      # depth-limited breaking
    (changed(f"{W}.waves", {**AIRY, "period": -8.0}), f"{W}.waves.period", "greater than 0"),
    (changed(f"{W}.waves", {**AIRY, "stretching": "wheler"}), f"{W}.waves.stretching", "wheeler"),
    (changed(f"{W}.waves", {**AIRY, "phase": 3.0}), f"{W}.waves.phase", "phase_deg"),
    (changed(f"{W}.depth", DELETE), f"{W}.depth", "deep_water"),
    (changed(f"{W}.waves.kind", "jonswop"), f"{W}.waves.kind", "pierson-moskowitz"),
    (changed(f"{W}.waves.hs", 12.0), f"{W}.waves.hs", "steeper"),
    (changed(f"{W}.waves.hs", 0.0), f"{W}.waves.hs", "greater than 0"),
    (changed(f"{W}.waves.gamma", 0.5), f"{W}.waves.gamma", "greater than or equal to 1"),
    (changed(f"{W}.waves.seed", 1.5), f"{W}.waves.seed", "whole number"),
    (changed(f"{W}.waves.seed", True), f"{W}.waves.seed", "boolean"),
    (changed(f"{W}.waves.components", 0), f"{W}.waves.components", "greater than or equal to 1"),
    (changed(f"{W}.waves.discretisation", "random"), f"{W}.waves.discretisation", "geometric"),
    (changed(f"{W}.waves.omega_max", 0.5), f"{W}.waves.omega_max", "peak"),
    (changed(f"{W}.waves", {"kind": "time-series", "rows": [[0, 0], [1, 1], [2, 0], [3.5, 1]]}),
     f"{W}.waves.rows.3", "equal steps"),
    (changed(f"{W}.waves", {"kind": "time-series", "rows": [[0, 0], [1, 1], [2, 0]]}),
     f"{W}.waves.rows", "at least 4"),
    (changed(f"{W}.waves", {"kind": "time-series", "rows": [[0, 0], [1, 1, 2], [2, 0], [3, 1]]}),
     f"{W}.waves.rows.1", "[t, eta]"),
    (changed(f"{W}.current.profile", [[0.0, 1.0], [5.0, 0.2]]), f"{W}.current.profile.1", "above the still water"),
    (changed(f"{W}.current.profile", [[0.0, 1.0], [0.0, 0.2]]), f"{W}.current.profile.1", "given twice"),
    (changed(f"{W}.current.profile", []), f"{W}.current.profile", "at least 1"),
    (changed(f"{W}.current.profile", [[0.0, 1.0, 2.0]]), f"{W}.current.profile.0", "[z, speed]"),
    (changed(f"{W}.current.time_factor", [[0.0, 1.0], [0.0, 2.0]]), f"{W}.current.time_factor.1",
     "does not increase"),
    (changed(f"{W}.current.speed", 1.0), f"{W}.current.speed", "unknown key"),
    (changed(f"{W}.waves", DELETE), "vessels.barge.motion", "needs waves"),
    (changed("vessels.barge.motion.raos", DELETE), "vessels.barge.motion.raos",
     "give one of the RAO table inline (raos) or a file with it (file)"),
    (changed("vessels.barge.motion.file", "x.json"), "vessels.barge.motion.raos", "not both"),
    (changed("vessels.barge.motion.raos.periods", [5.0]), "vessels.barge.motion.raos.heave.amplitude",
     "one per period"),
    (changed("vessels.barge.motion.raos.periods", [10.0, 5.0, 6.0]), "vessels.barge.motion.raos.periods",
     "strictly"),
    (changed("vessels.barge.motion.raos.frequencies", [1.0, 2.0]), "vessels.barge.motion.raos.periods",
     "either periods or frequencies"),
    (changed("vessels.barge.motion.raos.headings_deg", [180.0, 0.0]), "vessels.barge.motion.raos.headings_deg.1",
     "does not increase"),
    (changed("vessels.barge.motion.raos.heave.amplitude", [[0.2, -0.2], [0.9, 0.9]]),
     "vessels.barge.motion.raos.heave.amplitude.0", "negative"),
    (changed("vessels.barge.motion.raos.heave.phase_deg", [[0.0], [0.0]]),
     "vessels.barge.motion.raos.heave.phase_deg.0", "one per heading"),
    (changed("vessels.barge.motion.raos.heave", DELETE), "vessels.barge.motion.raos.heave", "at least one"),
    (changed("vessels.barge.motion.raos.symmetric", True), None, None),
    (changed("vessels.barge.motion", {"kind": "rao", "file": "/no/such/raos.json"}), "vessels.barge.motion.file",
     "file not found"),
    (changed("vessels.barge.motion", {"kind": "csv"}), "vessels.barge.motion.file", "required"),
    (changed("vessels.barge.motion", {"kind": "csv", "file": "/no/such/motion.csv"}), "vessels.barge.motion.file",
     "file not found"),
    (changed("vessels.barge.motion", {"kind": "raos"}), "vessels.barge.motion.kind", "'csv'"),
]


@pytest.mark.parametrize("data, path, word", CASES)
def test_bad_sea_input_is_named(data, path, word):
    if path is None:
        rfesim.load_scenario(data)       # a variation that is fine
        return
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    errors = dict(info.value.errors)
    assert path in errors, info.value.errors
    assert word in errors[path], errors[path]


def test_contract_example_environment_is_valid():
    sc = rfesim.load_scenario(BASE)
    water = sc.environment.water
    assert water.waves.kind == "jonswap" and water.waves.gamma == 3.3 and water.current.direction_deg == 0.0


def test_symmetric_table_refuses_headings_above_180():
    data = changed("vessels.barge.motion.raos.symmetric", True)
    data["vessels"]["barge"]["motion"]["raos"]["headings_deg"] = [0.0, 270.0]
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    assert "[0, 180]" in dict(info.value.errors)["vessels.barge.motion.raos.headings_deg"]


def test_deep_water_needs_no_depth_and_a_seabed_gives_one():
    data = changed(f"{W}.depth", DELETE)
    data["environment"]["water"]["waves"]["deep_water"] = True
    rfesim.load_scenario(data)
    data = changed(f"{W}.depth", DELETE)
    data["environment"]["seabed"] = {"z": -60.0}
    rfesim.load_scenario(data)


def test_units_and_directions_are_in_the_json_schema():
    schema = rfesim.Scenario.model_json_schema()
    defs = schema["$defs"]
    assert defs["JonswapWaves"]["properties"]["hs"]["units"] == "m"
    assert "TOWARD" in defs["JonswapWaves"]["properties"]["direction_deg"]["description"]
    assert "TOWARD" in defs["Current"]["properties"]["direction_deg"]["description"]
    assert defs["AiryWaves"]["properties"]["period"]["units"] == "s"
    assert "LAG" in defs["RaoDof"]["properties"]["phase_deg"]["description"]


def test_example_rao_file_loads_through_a_scenario():
    data = changed("vessels.barge.motion", {"kind": "rao", "file": str(DATA / "barge_100m_raos.json")})
    sc = rfesim.load_scenario(data)
    table = sc.vessels["barge"].motion.table()
    assert table.symmetric and len(table.periods) == len(table.heave.amplitude)
    # the model dumps to the same scenario (the table is re-read from the file)
    again = rfesim.load_scenario(sc.model_dump(mode="json"))
    assert again.vessels["barge"].motion.table() == table
