"""Two validation gaps closed, each a ScenarioError naming the field (dotted path), the value
and the reason:

* the sea floor without a seabed section: a fixed end, a vessel end at rest, or a point where a
  support holds its line (a tensioner's track, a straightener, a reel's take-off point) below
  surface_level - water.depth; the same points below a seabed (rfesim.scenario.load);
* huge finite numbers (1e200 Pa, 1e250 kg/m^3, a 1e300 kg payload): upper bounds with their
  reasons on moduli, section stiffnesses, densities, masses, inertias, stiffnesses, damping,
  forces, lengths and coefficients, generous enough for "rigid" stand-ins (1e15 Pa passes)
  (rfesim.scenario.schema MAX_*);
* the fields without a bound of their own (positions, headings, phases, times, speeds, volumes,
  gains) bounded by their unit (rfesim.scenario.schema.UNIT_BOUNDS), and a time step or output
  interval too short to count through the duration (rfesim.scenario.load.MAX_STEPS, MAX_OUTPUTS):
  before, a 1e-300 s step ended in an OverflowError from inside the dynamics driver.

Every bundled scenario, as JSON and as YAML, still passes ``rfesim check``.
"""
from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
import yaml

import rfesim
from rfesim import ScenarioError
from rfesim.cli import main
from rfesim.scenario.files import resolve_data_files
from rfesim.scenario.templates import expand

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
BUNDLED = sorted([*SCENARIOS.glob("*.json"), *SCENARIOS.glob("*.yaml"), *SCENARIOS.glob("*.yml")])


def example(name: str) -> dict:
    return json.loads((SCENARIOS / f"{name}.json").read_text())


def expanded(name: str) -> dict:
    """A bundled scenario with its templates expanded (its supports as plain entries)."""
    return expand(resolve_data_files(example(name), SCENARIOS))


def errors_of(data: dict | str, overrides: dict) -> dict[str, str]:
    with pytest.raises(ScenarioError) as info:
        load(data, overrides)
    return dict(info.value.errors)


def load(data: dict | str, overrides: dict):
    data = example(data) if isinstance(data, str) else data
    return rfesim.load_scenario(data, overrides=overrides, base_dir=SCENARIOS)


NO_SEABED = {"environment.seabed": None}          # catenary_riser: water 200 m deep, no seabed section

CABLE_SCENE = {
    "environment": {"water": {"depth": 100.0}},
    "line_types": {"cable": {"EA": 1.0e8, "EIy": 1.0e3, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "cable", "length": 10.0, "elements": 10,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, -50.0]}}},
    "analysis": {"dynamics": {"enabled": False}},
}


# ----------------------------------------------------------------------------- 1. the sea floor

def test_anchor_below_the_water_depth_without_a_seabed_is_refused():
    errors = errors_of("catenary_riser", {**NO_SEABED, "lines.riser.end_a.position": [-535.0, 0.0, -260.0]})
    reason = errors["lines.riser.end_a.position"]
    assert reason.startswith("z = -260 m is below the sea floor at the water depth 200 m (z = -200 m) by 60 m")
    assert "may lie at most 0.212 m below it (its radius 0.162 m + 0.05 m)" in reason


@pytest.mark.parametrize("z", [-199.838, -200.0, -200.2])
def test_anchor_on_the_sea_floor_without_a_seabed_is_fine(z):
    sc = load("catenary_riser", {**NO_SEABED, "lines.riser.end_a.position": [-535.0, 0.0, z]})
    assert sc.environment.seabed is None and sc.lines["riser"].end_a.position[2] == z


def test_anchor_just_beyond_the_radius_is_refused_without_a_seabed():
    errors = errors_of("catenary_riser", {**NO_SEABED, "lines.riser.end_a.position": [-535.0, 0.0, -200.3]})
    assert "by 0.3 m" in errors["lines.riser.end_a.position"]


def test_the_sea_floor_follows_the_surface_level():
    # still water at z = 10: the floor of 200 m deep water is at z = -190, above the anchor
    errors = errors_of("catenary_riser", {**NO_SEABED, "environment.water.surface_level": 10.0})
    assert "z = -199.838 m is below the sea floor at the water depth 200 m (z = -190 m) by 9.838 m" in \
        errors["lines.riser.end_a.position"]


def test_vessel_end_below_the_water_depth_is_refused():
    errors = errors_of("catenary_riser", {**NO_SEABED, "vessels.fpso.position": [0.0, 0.0, -300.0]})
    assert errors["lines.riser.end_b.position"].startswith(
        "z = -315 m (global, with vessel 'fpso' at rest) is below the sea floor at the water depth 200 m")


def test_shallower_water_without_a_seabed_puts_the_anchor_below_its_floor():
    errors = errors_of("catenary_riser", {**NO_SEABED, "environment.water.depth": 100.0})
    assert "below the sea floor at the water depth 100 m (z = -100 m) by 99.84 m" in \
        errors["lines.riser.end_a.position"]


def test_no_water_depth_no_floor():
    # water without a depth (or no water at all) has no floor: a deep anchor is fine
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"]["pipe"]["end_a"]["position"] = [0.0, 0.0, -5000.0]
    assert load(data, {"environment.water.depth": None}).lines["pipe"].end_a.position[2] == -5000.0
    assert load(data, {"environment.water": None}).lines["pipe"].end_a.position[2] == -5000.0


def test_free_end_start_below_the_floor_is_not_refused():
    # a free end's position is where the line starts; statics and dynamics move it (without a
    # seabed it may hang below the floor): only ends held in place are checked
    data = copy.deepcopy(CABLE_SCENE)
    data["lines"]["pipe"]["end_a"]["position"] = [0.0, 0.0, -99.0]
    data["lines"]["pipe"]["end_b"] = {"attach": "free", "position": [0.0, 0.0, -109.0]}
    assert load(data, {}).lines["pipe"].end_b.position[2] == -109.0
    data["lines"]["pipe"]["end_b"]["attach"] = "fixed"
    assert "z = -109 m is below the sea floor" in errors_of(data, {})["lines.pipe.end_b.position"]


def test_seabed_check_unchanged_with_a_seabed():
    # with a seabed section its own rule applies (its sinkage allowance), not the water depth's
    errors = errors_of("catenary_riser", {"lines.riser.end_a.position": [-535.0, 0.0, -260.0]})
    assert "z = -260 m is 60 m below the seabed (z = -200 m under this end)" in errors["lines.riser.end_a.position"]


def test_tensioner_track_below_the_seabed_is_refused():
    data = expanded("j_lay")
    errors = errors_of(data, {"supports.lay_collar.entry": [0.0, 0.0, -1300.0]})
    assert errors["supports.lay_collar.entry"].startswith(
        "the track's entry: z = -1300 m (global, with vessel 'lay_vessel' at rest) is 100 m below the seabed "
        "(z = -1200 m under it): the line 'lay' held there may rest on the seabed")
    errors = errors_of(data, {"supports.lay_collar.length": 2000.0})
    assert list(errors) == ["supports.lay_collar.length"]
    assert errors["supports.lay_collar.length"].startswith("the track's exit (entry + length along the axis): "
                                                           "z = -1982.43 m")   # 10 m collar at 85 deg


def test_tensioner_track_below_the_water_depth_is_refused():
    errors = errors_of(expanded("j_lay"), {**NO_SEABED, "supports.lay_collar.entry": [0.0, 0.0, -1300.0]})
    assert "the track's entry: z = -1300 m (global, with vessel 'lay_vessel' at rest) is below the sea floor at " \
           "the water depth 1200 m (z = -1200 m) by 100 m" in errors["supports.lay_collar.entry"]


def test_reel_and_straightener_below_the_seabed_are_refused():
    data = expanded("reel_lay")
    errors = errors_of(data, {"supports.lay_reel.centre": [-17.59, 0.0, -1300.0]})
    assert errors["supports.lay_reel.centre"].startswith(
        "the take-off point (centre + radius * (axis x direction)): z = -1291.84 m")
    errors = errors_of(data, {"supports.lay_straightener.entry": [-6.15, 0.0, -1300.0]})
    assert "the first roller's pipe axis: z = -1300 m" in errors["supports.lay_straightener.entry"]
    assert "is 1000 m below the seabed" in errors["supports.lay_straightener.entry"]


def test_stinger_rollers_are_not_checked():
    # rollers carry the line only where it touches them: a stinger reaching into the seabed of
    # shallow water is left to the contact (the pipe leaves it before the tip)
    data = expanded("s_lay_template")
    assert load(data, {"supports.lay_stinger.start": [0.0, 0.0, -200.0]}).supports["lay_stinger"]


def test_below_the_water_depth_through_rfesim_check(tmp_path, capsys):
    data = example("catenary_riser")
    del data["environment"]["seabed"]
    data["lines"]["riser"]["end_a"]["position"][2] = -260.0
    path = tmp_path / "deep.yaml"
    path.write_text(yaml.safe_dump(data))
    assert main(["check", str(path)]) == 1
    assert "lines.riser.end_a.position: z = -260 m is below the sea floor at the water depth 200 m" in \
        capsys.readouterr().err


@pytest.mark.parametrize("fmt", ["json", "yaml"])
@pytest.mark.parametrize("path", BUNDLED, ids=[p.name for p in BUNDLED])
def test_bundled_scenarios_pass_check(path, fmt, tmp_path, capsys):
    text = path.read_text()
    if fmt != path.suffix.lstrip("."):
        converted = tmp_path / f"{path.stem}.{fmt}"
        data = json.loads(text) if path.suffix == ".json" else yaml.safe_load(text)
        converted.write_text(json.dumps(data) if fmt == "json" else yaml.safe_dump(data))
        (tmp_path / "data").symlink_to(SCENARIOS / "data")      # relative data files (RAOs)
        path = converted
    assert main(["check", str(path)]) == 0, capsys.readouterr().err
    assert capsys.readouterr().out.startswith("OK")


# ----------------------------------------------------------------------------- 2. huge numbers

TOO_LARGE = [
    # (scenario, overrides, field, the bound, a word of the reason)
    ("catenary_riser", {"line_types.pipe12.youngs_modulus": 1e200}, "line_types.pipe12.youngs_modulus",
     "must be less than or equal to 1e+20 Pa (got 1e+200)", "stiffest material (diamond"),
    ("catenary_riser", {"line_types.pipe12.density": 1e250}, "line_types.pipe12.density",
     "must be less than or equal to 1000000 kg/m^3 (got 1e+250)", "densest material (osmium)"),
    ("catenary_riser", {"line_types.pipe12.contents_density": 1e250}, "line_types.pipe12.contents_density",
     "less than or equal to 1000000 kg/m^3", "osmium"),
    ("catenary_riser", {"environment.water.density": 1e300}, "environment.water.density",
     "less than or equal to 1000000 kg/m^3", "osmium"),
    ("catenary_riser", {"environment.seabed.normal_stiffness": 1e300}, "environment.seabed.normal_stiffness",
     "less than or equal to 1e+20 N/m/m (got 1e+300)", "'rigid' stand-in"),
    ("catenary_riser", {"line_types.pipe12.drag_normal": 50.0}, "line_types.pipe12.drag_normal",
     "less than or equal to 10 (got 50.0)", "a coefficient, not a force or a mass"),
    ("catenary_riser", {"line_types.pipe12.damping": {"axial": 1e300}}, "line_types.pipe12.damping.axial",
     "less than or equal to 1e+20 N*s (got 1e+300)", "critical damping"),
    (CABLE_SCENE, {"line_types.cable.EA": 1e300}, "line_types.cable.EA",
     "less than or equal to 1e+22 N (got 1e+300)", "60 in steel pipe"),
    (CABLE_SCENE, {"line_types.cable.EIy": 1e300}, "line_types.cable.EIy",
     "less than or equal to 1e+22 N*m^2", "60 in steel pipe"),
    (CABLE_SCENE, {"line_types.cable.mass_per_length": 1e300}, "line_types.cable.mass_per_length",
     "less than or equal to 100000000 kg/m", "solid steel bar"),
    (CABLE_SCENE, {"lines.pipe.loads": [{"at": "end_b", "force": [0.0, 0.0, -1e300]}]}, "lines.pipe.loads.0.force.2",
     "must lie between -1e+15 and 1e+15 N (got -1e+300)", "heaviest offshore lift"),
    ("column_crane", {"cranes.crane.payload.mass": 1e300}, "cranes.crane.payload.mass",
     "must be less than or equal to 1e+12 kg (got 1e+300)", "heaviest offshore lift"),
    ("column_crane", {"cranes.crane.payload.added_mass.mass": 1e300}, "cranes.crane.payload.added_mass.mass",
     "less than or equal to 1e+12 kg", "heaviest offshore lift"),
    ("column_crane", {"cranes.crane.payload.drag.cd": [1.2, 50.0, 2.0]}, "cranes.crane.payload.drag.cd.1",
     "less than or equal to 10 (got 50.0)", "a coefficient"),
    ("column_crane", {"cranes.crane.payload.radius_of_gyration": None,
                      "cranes.crane.payload.inertia": [1e300, 1e300, 1e300]}, "cranes.crane.payload.inertia.0",
     "less than or equal to 1e+18 kg*m^2", "radius of gyration of 1 km"),
    ("column_crane", {"cranes.crane.rope.EA": 1e300}, "cranes.crane.rope.EA", "less than or equal to 1e+22 N",
     "'rigid' stand-in"),
    ("column_crane", {"cranes.crane.boom.youngs_modulus": 1e300}, "cranes.crane.boom.youngs_modulus",
     "less than or equal to 1e+20 Pa", "diamond"),
    # the template's winch is validated with the template (audit 7, D6): its errors name the field the user
    # wrote, cranes.crane.winch..., not the expanded winches.crane_winch...
    ("column_crane", {"cranes.crane.winch.stored": 1e300}, "cranes.crane.winch.stored",
     "less than or equal to 10000000 m", "longer than any line"),
    ("column_crane", {"cranes.crane.winch.mode": {"kind": "tension", "tension": 1e300, "gain": 1e4, "max_speed": 1.0}},
     "cranes.crane.winch.mode.tension", "less than or equal to 1e+15 N", "holding capacity"),
    ("column_crane", {"cranes.crane.tuggers": {"t1": {"deck_point": [0.0, 20.0, 2.0],
                                                      "mode": {"kind": "elastic", "stiffness": 1e300}}}},
     "cranes.crane.tuggers.t1.mode.stiffness", "less than or equal to 1e+20 N/m", "'rigid' stand-in"),
    ("s_lay_template", {"pipelay.lay.pipe.youngs_modulus": 1e300}, "pipelay.lay.pipe.youngs_modulus",
     "less than or equal to 1e+20 Pa", "diamond"),
    ("s_lay_template", {"pipelay.lay.pipe.density": 1e300}, "pipelay.lay.pipe.density",
     "less than or equal to 1000000 kg/m^3", "osmium"),
    ("s_lay_template", {"pipelay.lay.tensioner.capacity": 1e300}, "pipelay.lay.tensioner.capacity",
     "less than or equal to 1e+15 N", "holding capacity"),
    ("s_lay", {"supports.stinger.stiffness": 1e300}, "supports.stinger.stiffness",
     "less than or equal to 1e+20 N/m", "'rigid' stand-in"),
    ("s_lay", {"supports.stinger.damping": 1e300}, "supports.stinger.damping",
     "less than or equal to 1e+20 N*s/m", "critical damping"),
]


@pytest.mark.parametrize("data, overrides, field, bound, why", TOO_LARGE,
                         ids=[f"{c[0] if isinstance(c[0], str) else 'cable'}:{c[2]}" for c in TOO_LARGE])
def test_huge_number_is_refused_with_its_reason(data, overrides, field, bound, why):
    errors = errors_of(copy.deepcopy(data), overrides)
    assert field in errors, errors
    assert bound in errors[field] and why in errors[field]


RIGID_STAND_INS = [
    ("catenary_riser", {"line_types.pipe12.youngs_modulus": 1e15}),
    ("catenary_riser", {"environment.seabed.normal_stiffness": 1e15}),
    (CABLE_SCENE, {"line_types.cable.EA": 1e20, "line_types.cable.EIy": 1e18}),
    ("column_crane", {"cranes.crane.payload.mass": 5e7}),
    ("s_lay_template", {"pipelay.lay.tensioner.capacity": 1e14}),
    ("s_lay", {"supports.stinger.stiffness": 1e15, "supports.stinger.damping": 1e12}),
]


@pytest.mark.parametrize("data, overrides", RIGID_STAND_INS,
                         ids=[next(iter(c[1])) for c in RIGID_STAND_INS])
def test_rigid_stand_ins_and_the_heaviest_real_values_pass(data, overrides):
    assert load(copy.deepcopy(data), overrides) is not None


def test_json_schema_states_the_new_bounds():
    defs = rfesim.Scenario.model_json_schema()["$defs"]
    modulus = defs["LineType"]["properties"]["youngs_modulus"]
    assert 1e20 in [modulus.get("maximum")] + [a.get("maximum") for a in modulus.get("anyOf", [])]
    assert "diamond" in modulus["limit"]
    assert defs["Body"]["properties"]["mass"]["maximum"] == 1e12


# ----------------------------------------------------------------------------- 3. bounds by unit

LINEAR = {"kind": "table", "interpolation": "linear"}

BY_UNIT = [
    ("catenary_riser", {"vessels.fpso.position": [1e30, 0.0, 0.0]}, "vessels.fpso.position.0",
     "must lie between -10000000 and 10000000 m (got 1e+30)", "check the units, metres"),
    ("catenary_riser", {"lines.riser.end_a.position": [-535.0, -2e7, -199.0]}, "lines.riser.end_a.position.1",
     "must lie between -10000000 and 10000000 m (got -20000000.0)", "farther than any point"),
    ("catenary_riser", {"vessels.fpso.heading_deg": 1e300}, "vessels.fpso.heading_deg",
     "must lie between -1000000 and 1000000 deg (got 1e+300)", "check the units, degrees"),
    ("catenary_riser", {"vessels.fpso.motion.heave.phase_deg": -2e6}, "vessels.fpso.motion.heave.phase_deg",
     "must lie between -1000000 and 1000000 deg", "2,800 turns"),
    ("catenary_riser", {"vessels.fpso.motion.heave.amplitude": 1e4}, "vessels.fpso.motion.heave.amplitude",
     "must be less than or equal to 1000 m or deg (got 10000.0)", "15 m of heave"),
    ("catenary_riser", {"vessels.fpso.motion.ramp_duration": 1e300}, "vessels.fpso.motion.ramp_duration",
     "must be less than or equal to 10000000 s (got 1e+300)", "check the units, seconds"),
    ("column_crane", {"cranes.crane.payload.volume": 1e300}, "cranes.crane.payload.volume",
     "must be less than or equal to 1e+12 m^3 (got 1e+300)", "a cube 10 km on a side"),
    ("column_crane", {"cranes.crane.winch.heave_compensation": {"kp": 1e300}},   # named as written (audit 7, D6)
     "cranes.crane.winch.heave_compensation.kp", "must be less than or equal to 10000 1/s (got 1e+300)",
     "a loop that closes in 0.1 ms"),
    ("s_lay_template", {"pipelay.lay.tensioner.payout": {"kind": "constant-tension", "tension": 1.5e5,
                                                          "gain": 1e5, "max_speed": 1e300}},
     "pipelay.lay.tensioner.payout.max_speed", "must be less than or equal to 10000 m/s (got 1e+300)",
     "speed of sound in water"),
]


BY_COLUMN = [
    # tables: each cell within the bound of its column's unit, time rows at least 1e-6 s apart
    ("catenary_riser", {"vessels.fpso.motion": {**LINEAR, "rows": [[0, 0, 0, 0, 0, 0, 0], [10, 1e300, 0, 0, 0, 0, 0]]}},
     "vessels.fpso.motion.rows.1.1", "must lie between -10000000 and 10000000 m (got 1e+300)", "metres"),
    ("catenary_riser", {"vessels.fpso.motion": {**LINEAR, "rows": [[0, 0, 0, 0, 0, 0, 0], [10, 0, 0, 0, 1e300, 0, 0]]}},
     "vessels.fpso.motion.rows.1.4", "must lie between -1000000 and 1000000 deg (got 1e+300)", "degrees"),
    ("catenary_riser", {"vessels.fpso.motion": {**LINEAR, "rows": [[0, 0, 0, 0, 0, 0, 0],
                                                                   [1e300, 0, 0, 0, 0, 0, 0]]}},
     "vessels.fpso.motion.rows.1.0", "must lie between -10000000 and 10000000 s (got 1e+300)", "seconds"),
    ("catenary_riser", {"vessels.fpso.motion": {"kind": "table", "rows": [[0, 0, 0, 0, 0, 0, 0],
                                                                          [1e-300, 0, 0, 0, 0, 0, 0],
                                                                          [1, 0, 0, 0, 0, 0, 0],
                                                                          [2, 0, 0, 0, 0, 0, 0]]}},
     "vessels.fpso.motion.rows.1.0", "is 1e-300 s after the row before: rows closer than 1e-06 s", "a microsecond"),
    ("catenary_riser", {"environment.water.current": {"profile": [[0, 1e300], [-200, 0]]}},
     "environment.water.current.profile.0.1", "must lie between -10000 and 10000 m/s (got 1e+300)", "speed of sound"),
    ("catenary_riser", {"environment.water.current": {"profile": [[0, 1], [-200, 0]],
                                                      "time_factor": [[0, 0], [1, 1e300]]}},
     "environment.water.current.time_factor.1.1", "1e+300 times the fastest row of the profile (1 m/s)",
     "speed of sound"),
    ("catenary_riser", {"vessels.fpso.motion.heave.period": 1e-300}, "vessels.fpso.motion.heave.period",
     "1e-300 s is shorter than 1e-06 s", "a microsecond"),
    ("column_crane", {"cranes.crane.winch.mode": {"kind": "speed", "rows": [[-1e300, 0], [12, 0.3]]}},
     # named as written (audit 7, D6), not winches.crane_winch.mode.rows.0.0
     "cranes.crane.winch.mode.rows.0.0", "must lie between -10000000 and 10000000 s (got -1e+300)", "seconds"),
    ("column_crane", {"cranes.crane.tuggers": {"t1": {"deck_point": [0.0, 20.0, 2.0], "mode": {
        "kind": "tension", "tension": [[0, 1e3], [5, -1e300]]}}}}, "cranes.crane.tuggers.t1.mode.tension.1.1",
     "must lie between -1e+15 and 1e+15 N (got -1e+300)", "heaviest offshore lift"),
    ("column_crane", {"cranes.crane.slewing_deg": [[0, 80], [2e7, 90]]}, "cranes.crane.slewing_deg.1.0",
     "must lie between -10000000 and 10000000 s (got 20000000.0)", "seconds"),
]
BY_UNIT += BY_COLUMN


@pytest.mark.parametrize("data, overrides, field, bound, why", BY_UNIT, ids=[c[2] for c in BY_UNIT])
def test_unbounded_field_takes_the_bound_of_its_unit(data, overrides, field, bound, why):
    errors = errors_of(copy.deepcopy(data), overrides)
    assert field in errors, errors
    assert bound in errors[field] and why in errors[field]


@pytest.mark.parametrize("overrides", [
    {"vessels.fpso.heading_deg": 720.0, "vessels.fpso.motion.heave.phase_deg": -9.0e5},
    {"vessels.fpso.motion.heave.amplitude": 1000.0},
    {"vessels.fpso.motion.ramp_duration": 1.0e7},
])
def test_values_up_to_the_unit_bounds_pass(overrides):
    assert load("catenary_riser", overrides) is not None


@pytest.mark.parametrize("t", [10.0, 1000.0, 3e-6])
def test_table_rows_a_microsecond_apart_pass(t):
    # 10.000001 - 10 is 9.9999999925e-07 in floating point: within rounding of 1e-6 s
    rows = [[t, 0, 0, 0, 0, 0, 0], [t + 1e-6, 1, 0, 0, 0, 0, 0], [t + 1, 1, 0, 0, 0, 0, 0]]
    sc = load("catenary_riser", {"vessels.fpso.motion": {**LINEAR, "rows": rows, "start_time": t}})
    assert sc.vessels["fpso"].motion.rows[1][0] == t + 1e-6


def test_a_scene_far_from_the_origin_passes():
    # every position of the riser moved 9,000 km east: inside the bound of 10,000 km
    data = example("catenary_riser")
    data["vessels"]["fpso"]["position"][0] += 9.0e6
    data["lines"]["riser"]["end_a"]["position"][0] += 9.0e6
    assert load(data, {}).lines["riser"].end_a.position[0] == 9.0e6 - 535.0


STEPS = [
    ({"analysis.dynamics.integrator.time_step": 1e-300}, "analysis.dynamics.integrator.time_step",
     "1e-300 s is shorter than 1e-06 s, a microsecond"),
    ({"analysis.dynamics.integrator": {"kind": "rk4", "time_step": 2e-6}, "analysis.dynamics.duration": 1e4},
     "analysis.dynamics.integrator.time_step", "2e-06 s takes 5e+09 steps through the duration 10000 s, more than "
                                               "the 1,000,000,000"),
    ({"analysis.dynamics.integrator": {"kind": "adaptive", "max_step": 2e-6}, "analysis.dynamics.duration": 1e4},
     "analysis.dynamics.integrator.max_step", "2e-06 s takes 5e+09 steps"),
    ({"analysis.dynamics.output_interval": 2e-6, "analysis.dynamics.duration": 1e3},
     "analysis.dynamics.output_interval", "2e-06 s stores 5e+08 output times over the duration 1000 s, more than "
                                          "the 100,000,000"),
    ({"analysis.dynamics.output_interval": 1e-300}, "analysis.dynamics.output_interval",
     "1e-300 s is shorter than 1e-06 s"),
]


@pytest.mark.parametrize("overrides, field, words", STEPS, ids=[f"{c[1].rsplit('.', 1)[1]}-{i}"
                                                                 for i, c in enumerate(STEPS)])
def test_a_step_too_short_for_the_duration_is_refused(overrides, field, words):
    errors = errors_of("catenary_riser", overrides)
    assert field in errors, errors
    assert words in errors[field]


def test_short_steps_within_the_count_pass():
    # 6e7 steps of 1 microsecond: a long run, not a unit mistake
    sc = load("catenary_riser", {"analysis.dynamics.integrator.time_step": 1e-6})
    assert sc.analysis.dynamics.integrator.time_step == 1e-6


def test_json_schema_states_the_unit_bounds():
    defs = rfesim.Scenario.model_json_schema()["$defs"]
    position = defs["Vessel"]["properties"]["position"]
    assert (position["items"]["minimum"], position["items"]["maximum"]) == (-1e7, 1e7)
    assert "check the units, metres" in position["limit"]
    heading = defs["Vessel"]["properties"]["heading_deg"]
    assert (heading["minimum"], heading["maximum"]) == (-1e6, 1e6)
    ramp = defs["HarmonicMotion"]["properties"]["ramp_duration"]        # its own minimum stays
    assert (ramp["minimum"], ramp["maximum"]) == (0.0, 1e7)
    modulus = defs["LineType"]["properties"]["youngs_modulus"]          # its own bounds stay
    assert "diamond" in modulus["limit"] and "rubber" in modulus["floor"]
    assert modulus["anyOf"][0]["minimum"] == 1e5 and modulus["anyOf"][0]["maximum"] == 1e20



def test_a_mapping_given_for_a_name_or_a_body_is_not_told_to_be_text():
    # a crane's payload is a body name or a body: an error inside the body is the only one
    errors = errors_of("column_crane", {"cranes.crane.payload.volume": 1e13})
    assert list(errors) == ["cranes.crane.payload.volume"], errors
    errors = errors_of("column_crane", {"cranes.crane.payload": 5})
    assert "must be text" in errors["cranes.crane.payload"], errors


def test_table_units_read_numbers_and_tables():
    from rfesim.scenario.schema import table_units
    assert table_units("N (s, N)") == ("N", ["s", "N"])
    assert table_units("s, m/s") == (None, ["s", "m/s"])
    assert table_units("[1, Pa]") == (None, ["1", "Pa"])
    assert table_units("m") == ("m", None)


@pytest.mark.parametrize("name, path", [
    ("s_lay", "line_types.x65.youngs_modulus"),
    ("column_crane", "cranes.crane.boom.youngs_modulus"),
    ("j_lay", "pipelay.lay.pipe.youngs_modulus"),
])
def test_youngs_modulus_floor(name, path):
    # 1e-12 Pa used to reach the statics, which failed with "Newton did not converge"
    reason = errors_of(name, {path: 1e-12})[path]
    assert reason.startswith("must be greater than or equal to 100000 Pa (got 1e-12): a tenth of the softest rubber")
    load(name, {path: 1e9})                      # a soft polymer passes


@pytest.mark.parametrize("name, path", [("column_crane", "cranes.crane.boom.density"),
                                        ("j_lay", "pipelay.lay.pipe.density")])
def test_template_steel_density_floor(name, path):
    reason = errors_of(name, {path: 1e-3})[path]
    assert reason.startswith("must be greater than or equal to 1 kg/m^3 (got 0.001): about the density of air")
