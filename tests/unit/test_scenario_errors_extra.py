"""Bad scenario input found by an audit: each case must become a ScenarioError naming the
field (dotted path) and the reason, never a traceback and never silently accepted.

* line ends below the seabed (flat, sloped and profile seabeds; fixed and vessel ends);
* absurd numbers (1e300, 1e-300) that overflowed or divided by zero in validation and
  template expansion, and the safety net that names the field when arithmetic fails;
* ``rfesim check`` refuses a scenario without lines, as ``run`` does;
* ``dofs`` on an absolute-formulation line;
* YAML 1.1 booleans (``no:``, ``off``) where a name or a word was meant;
* dotted override paths with empty parts or negative list positions.
"""
from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

import rfesim
from rfesim import ScenarioError
from rfesim.cli import main
from rfesim.model.compile import compile_scenario
from rfesim.scenario.load import apply_overrides, check_runnable, parse_text

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def example(name: str) -> dict:
    return json.loads((SCENARIOS / f"{name}.json").read_text())


def load_example(name: str, overrides: dict):
    return rfesim.load_scenario(example(name), overrides=overrides, base_dir=SCENARIOS)


def errors_of(name: str, overrides: dict) -> dict[str, str]:
    with pytest.raises(ScenarioError) as info:
        load_example(name, overrides)
    return dict(info.value.errors)


CABLE_SCENE = {
    "line_types": {"cable": {"EA": 1.0e8, "EIy": 1.0e3, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "cable", "length": 10.0, "elements": 10,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0]}}},
    "analysis": {"dynamics": {"enabled": False}},
}


# ----------------------------------------------------------------------------- 1. below the seabed

def test_anchor_below_a_flat_seabed_is_refused():
    errors = errors_of("catenary_riser", {"lines.riser.end_a.position": [-535.0, 0.0, -260.0]})
    reason = errors["lines.riser.end_a.position"]
    assert "z = -260 m is 60 m below the seabed (z = -200 m" in reason


def test_shallower_water_puts_the_anchor_below_the_seabed():
    errors = errors_of("catenary_riser", {"environment.water.depth": 100.0})
    reason = errors["lines.riser.end_a.position"]
    assert "below the seabed (z = -100 m" in reason and "99.84 m" in reason


@pytest.mark.parametrize("z", [-199.838, -200.0, -200.2])
def test_anchor_resting_on_or_slightly_in_the_seabed_is_fine(z):
    # the example rests its anchor's axis one pipe radius (0.162 m) above the seabed; an axis
    # on the seabed or a little in it (radius + sinkage + 5 cm = 0.212 m) is fine too
    sc = load_example("catenary_riser", {"lines.riser.end_a.position": [-535.0, 0.0, z]})
    assert sc.lines["riser"].end_a.position[2] == z


def test_anchor_just_beyond_the_tolerance_is_refused():
    errors = errors_of("catenary_riser", {"lines.riser.end_a.position": [-535.0, 0.0, -200.3]})
    assert "0.3 m below the seabed" in errors["lines.riser.end_a.position"]
    assert "at most 0.212 m" in errors["lines.riser.end_a.position"]


def test_sloped_seabed_is_taken_under_the_end():
    # the seabed rises toward -x (slope_direction 0, negative slope): 94 m above the anchor there
    errors = errors_of("catenary_riser", {"environment.seabed.slope_deg": -10.0})
    assert "94.17 m below the seabed (z = -105.665 m under this end)" in errors["lines.riser.end_a.position"]
    # sloping down toward -x, the anchor is above the seabed
    assert load_example("catenary_riser", {"environment.seabed.slope_deg": 10.0}).lines["riser"]


def test_profile_seabed_is_taken_under_the_end():
    profile = {"environment.water.depth": None, "environment.seabed.profile": [[-1000.0, -150.0], [0.0, -200.0]]}
    errors = errors_of("catenary_riser", profile)
    assert "below the seabed (z = -173.25 m under this end)" in errors["lines.riser.end_a.position"]


def test_vessel_end_below_the_seabed_is_refused():
    errors = errors_of("catenary_riser", {"vessels.fpso.position": [0.0, 0.0, -300.0]})
    reason = errors["lines.riser.end_b.position"]
    assert "z = -315 m (global, with vessel 'fpso' at rest) is 115 m below the seabed" in reason


def test_sinkage_of_a_heavy_line_on_a_soft_seabed_is_allowed():
    # a 50 kg/m cable in air on a 1e3 N/m/m seabed sinks 0.49 m: an anchor there is where it rests
    data = copy.deepcopy(CABLE_SCENE)
    data["environment"] = {"seabed": {"z": 0.0, "normal_stiffness": 1.0e3}}
    data["lines"]["pipe"]["end_a"]["position"] = [0.0, 0.0, -0.5]
    assert rfesim.load_scenario(data).lines["pipe"].end_a.position[2] == -0.5
    data["lines"]["pipe"]["end_a"]["position"] = [0.0, 0.0, -0.6]
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    assert "0.6 m below the seabed" in dict(info.value.errors)["lines.pipe.end_a.position"]


def test_below_the_seabed_through_rfesim_check(tmp_path, capsys):
    data = example("catenary_riser")
    data["lines"]["riser"]["end_a"]["position"][2] = -260.0
    path = tmp_path / "deep.json"
    path.write_text(json.dumps(data))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "lines.riser.end_a.position: z = -260 m is 60 m below the seabed" in err


# ----------------------------------------------------------------------------- 2. absurd numbers

OVERFLOWS = [
    ("catenary_riser", "line_types.pipe12.outer_diameter", 1e300, "less than or equal to 100 m", "slender"),
    ("riser_irregular_sea", "environment.water.waves.tp", 1e300, "1e+300 s is outside", "gravity waves"),
    ("riser_irregular_sea", "environment.water.waves.tp", 1e-300, "1e-300 s is outside", "gravity waves"),
    ("riser_irregular_sea", "environment.water.waves.omega_max", 1e300, "rad/s is outside", "gravity waves"),
    ("a_frame", "cranes.aframe.legs.outer_diameter", 1e300, "less than or equal to 50 m", "slender tube"),
    ("a_frame", "cranes.aframe.crossbeam.outer_diameter", 1e300, "less than or equal to 50 m", "slender tube"),
    ("s_lay_template", "pipelay.lay.pipe.outer_diameter", 1e300, "less than or equal to 10 m", "pipelines"),
    ("j_lay", "environment.water.depth", 1e300, "less than or equal to 100000 m", "deeper than"),
    ("s_lay_template", "pipelay.lay.tension", 1e300, "less than or equal to 1000000000 N", "tensioners"),
    ("s_lay_template", "pipelay.lay.stinger.radius", 1e300, "less than or equal to 10000 m", "stinger"),
    # below the floor of a seabed stiffness (schema.MIN_SEABED_STIFFNESS), named before the template expands
    ("j_lay", "environment.seabed.normal_stiffness", 1e-300, "must be greater than or equal to 1 N/m/m (got 1e-300)",
     "sink more than 1 km"),
    # positions, angles and times are bounded by their unit (schema.UNIT_BOUNDS)
    ("j_lay", "pipelay.lay.exit.2", 1e300, "must lie between -10000000 and 10000000 m (got 1e+300)",
     "check the units, metres"),
    ("catenary_riser", "vessels.fpso.heading_deg", 1e300, "must lie between -1000000 and 1000000 deg",
     "loses its digits"),
    ("catenary_riser", "vessels.fpso.motion.heave.amplitude", 1e300, "less than or equal to 1000 m or deg",
     "30 deg of roll"),
    ("catenary_riser", "vessels.fpso.motion.ramp_duration", 1e300, "less than or equal to 10000000 s",
     "longest simulated duration"),
]


@pytest.mark.parametrize("name, path, value, words, why", OVERFLOWS,
                         ids=[f"{c[0]}:{c[1]}={c[2]:g}" for c in OVERFLOWS])
def test_absurd_number_is_a_field_error(name, path, value, words, why):
    errors = errors_of(name, {path: value})
    assert path in errors, errors
    assert words in errors[path] and why in errors[path]


@pytest.mark.parametrize("waves", [
    {"kind": "airy", "height": 1.0, "period": 1e-300},
    {"kind": "stokes5", "height": 1.0, "period": 1e300},
])
def test_regular_wave_period_out_of_range(waves):
    errors = errors_of("catenary_riser", {"environment.water.waves": waves})
    assert "s is outside the periods of ocean gravity waves" in errors["environment.water.waves.period"]


def test_waves_need_real_gravity():
    # (below 1e-3 m/s^2 a gravity is refused in any scene: test_input_audit7)
    errors = errors_of("riser_irregular_sea", {"environment.gravity": 0.01})
    assert "waves need gravity: at least 0.1 m/s^2" in errors["environment.gravity"]


def test_tension_too_large_for_a_stinger_catenary():
    # a nearly neutral pipe under the largest tension: the catenary leaves the stinger flat, no
    # tip angle matches it; the tension is named, not scipy's "f(a) and f(b) must have different signs"
    D, d = 0.3239, 0.3239 - 2 * 0.0159
    neutral = 1025.0 * D * D / (D * D - d * d)       # steel density at which the pipe floats
    # (since the catenary carries the pipe's weight in air above the water, 2026-12, the dry
    # stretch below the deck gives a tip angle of 0.113 deg: too short a stinger for its spacing)
    errors = errors_of("s_lay_template", {"pipelay.lay.tension": 1e9, "pipelay.lay.pipe.density": neutral + 1e-11})
    assert errors == {"pipelay.lay.stinger.spacing": "6.0 m is longer than the stinger (0.1978 m to the tip "
                                                     "angle 0.113 deg)"}


def test_arithmetic_safety_net_in_validation(monkeypatch):
    # arithmetic that fails inside a validator names the section it was checking ...
    import rfesim.scenario.schema as schema

    def overflow(value, what):
        raise OverflowError("math range error")

    monkeypatch.setattr(schema, "_wave_period", overflow)
    errors = errors_of("riser_irregular_sea", {})
    assert "the arithmetic overflows (math range error)" in errors["environment.water.waves"]
    # ... or the number far out of range in it
    errors = errors_of("riser_irregular_sea", {"environment.water.waves.ramp_duration": 1e200})
    assert "1e+200 is out of range: the computation with it overflows" in \
        errors["environment.water.waves.ramp_duration"]


def test_arithmetic_safety_net_in_templates(monkeypatch):
    import rfesim.catenary
    import rfesim.scenario.pipelay as pipelay

    def divide(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(rfesim.catenary, "natural_catenary", divide)     # the stinger tip under water
    errors = errors_of("s_lay_template", {})
    assert "the arithmetic divides by zero (float division by zero)" in errors["pipelay.lay"]
    monkeypatch.undo()
    monkeypatch.setattr(pipelay, "lay_catenary", divide)                  # the two-piece catenary
    errors = errors_of("j_lay", {})
    assert "the arithmetic divides by zero (float division by zero)" in errors["pipelay.lay"]


@pytest.mark.parametrize("override", [{"environment.water.waves.tp": 1e-300},
                                      {"environment.water.waves.tp": 1e300}])
def test_no_traceback_from_rfesim_check(tmp_path, capsys, override):
    path = tmp_path / "sea.json"
    path.write_text(json.dumps(apply_overrides(example("riser_irregular_sea"), override)))
    (tmp_path / "data").symlink_to(SCENARIOS / "data")
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "environment.water.waves.tp:" in err and "Traceback" not in err


# ----------------------------------------------------------------------------- 3. check = run

def test_check_refuses_a_scenario_without_lines(tmp_path, capsys):
    path = tmp_path / "empty.json"
    path.write_text("{}")
    assert main(["check", str(path)]) == 1
    captured = capsys.readouterr()
    assert "lines: the scenario has no lines to simulate" in captured.err
    assert "OK" not in captured.out


def test_check_and_run_share_the_rule():
    sc = rfesim.load_scenario({"vessels": {"ship": {}}})       # loading alone is fine (vessel-only scenes)
    with pytest.raises(ScenarioError) as info:
        compile_scenario(sc)
    assert check_runnable(sc) == info.value.errors == [("lines", "the scenario has no lines to simulate")]
    assert check_runnable(rfesim.load_scenario(copy.deepcopy(CABLE_SCENE))) == []


# ----------------------------------------------------------------------------- 4. dofs

def test_dofs_on_an_absolute_line_is_refused():
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"]["pipe"]["dofs"] = ["x", "rz"]
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    reason = dict(info.value.errors)["lines.pipe.dofs"]
    assert "classical and modified formulations only" in reason


# ----------------------------------------------------------------------------- 5. YAML booleans

YAML_SCENE = """\
line_types:
  cable: {EA: 1.0e8, EIy: 1.0e3, mass_per_length: 50.0}
lines:
  NAME:
    type: cable
    length: 10.0
    elements: 10
    end_a: {attach: fixed, position: [0, 0, 0], connection: CONNECTION}
"""


@pytest.mark.parametrize("word, value", [("no", "false"), ("off", "false"), ("yes", "true"), ("On", "true")])
def test_yaml_boolean_line_name(word, value):
    text = YAML_SCENE.replace("NAME", word).replace("CONNECTION", "pinned")
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(text)
    reason = dict(info.value.errors)[f"lines.{word}"]
    assert f"YAML reads the unquoted key {word} (line 4) as the boolean {value}" in reason
    assert f'quote it ("{word}": ...)' in reason


def test_quoted_yaml_name_is_fine():
    sc = rfesim.load_scenario(YAML_SCENE.replace("NAME", '"no"').replace("CONNECTION", "pinned"))
    assert list(sc.lines) == ["no"]


def test_yaml_boolean_value_where_a_word_is_meant():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(YAML_SCENE.replace("NAME", "pipe").replace("CONNECTION", "off"))
    reason = dict(info.value.errors)["lines.pipe.end_a.connection"]
    assert "the boolean false is not allowed here" in reason
    assert "YAML reads the unquoted words no, off and false as the boolean false" in reason
    assert "quote the word" in reason


def test_yaml_boolean_keys_are_found_at_any_depth():
    with pytest.raises(ScenarioError) as info:
        parse_text("a:\n  - b:\n      yes: 1\n")
    assert [p for p, _ in info.value.errors] == ["a.0.b.yes"]


def test_boolean_name_in_a_python_dict():
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"] = {False: data["lines"]["pipe"]}
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    reason = dict(info.value.errors)["lines.false"]
    assert "names must be text (strings), got the boolean false" in reason and "quote" in reason


# ----------------------------------------------------------------------------- 6. override paths

@pytest.mark.parametrize("path, words", [
    ("lines..pipe", "part 2 of the dotted path is empty (after 'lines'"),
    (".lines.pipe.length", "part 1 of the dotted path is empty (at the start"),
    ("lines.pipe.length.", "part 4 of the dotted path is empty (at the end"),
    ("lines.pipe.loads.-1.at", "'-1' is a negative list position"),
    ("lines.pipe.loads.-1", "'-1' is a negative list position"),
    ("lines.pipe.loads.1.at", "beyond the end of the list (its only position is 0)"),
])
def test_bad_dotted_override_path(path, words):
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"]["pipe"]["loads"] = [{"at": "end_b", "force": [0.0, 0.0, -1.0]}]
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data, overrides={path: 5.0})
    assert info.value.errors == [(path, info.value.errors[0][1])]      # one error, at the path given
    assert words in info.value.errors[0][1]
    assert "" not in data["lines"]                                     # nothing made on the way


def test_empty_override_path():
    with pytest.raises(ScenarioError) as info:
        apply_overrides(copy.deepcopy(CABLE_SCENE), {"": 1})
    assert "an override needs a dotted field path" in str(info.value)


def test_good_list_override_still_works():
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"]["pipe"]["loads"] = [{"at": "end_b"}]
    sc = rfesim.load_scenario(data, overrides={"lines.pipe.loads.0.at": 5.0})
    assert sc.lines["pipe"].loads[0].at == 5.0
