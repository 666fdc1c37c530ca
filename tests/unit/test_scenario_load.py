"""Loading scenarios: JSON and YAML files, dicts, overrides, round trips, JSON Schema, defaults."""
from __future__ import annotations

import copy
import json

import pydantic
import pytest
import yaml

import rfesim
from rfesim import ScenarioError
from rfesim.model.compile import compile_scenario

SCENARIO = {
    "schema_version": 1,
    "name": "cantilever pipe",
    "environment": {"gravity": 9.81, "water": {"depth": 100.0}},
    "vessels": {
        "barge": {"position": [0.0, 0.0, 0.0],
                  "motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 8.0, "phase_deg": 0.0}}},
    },
    "line_types": {
        "pipe12": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 2.07e11,
                   "poisson_ratio": 0.3, "density": 7850.0, "drag_normal": 1.0, "drag_axial": 0.008,
                   "added_mass_normal": 1.0, "material": {"kind": "elastic"}},
    },
    "lines": {
        "pipe": {"type": "pipe12", "length": 10.0, "elements": 20, "formulation": "absolute",
                 "shear_stiffness": "fem",
                 "end_a": {"attach": "fixed", "position": [0, 0, -5.0], "direction": [1, 0, 0],
                           "connection": "clamped"},
                 "end_b": {"attach": "free"},
                 "loads": [{"at": "end_b", "force": [0, 0, -1000.0]}]},
    },
    "analysis": {
        "statics": {"enabled": True},
        "dynamics": {"duration": 60.0, "output_interval": 0.1,
                     "integrator": {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8}},
        "modal": {"modes": 10},
    },
}


@pytest.fixture
def data():
    return copy.deepcopy(SCENARIO)


@pytest.fixture
def json_file(tmp_path, data):
    path = tmp_path / "scenario.json"
    path.write_text(json.dumps(data, indent=2))
    return path


@pytest.fixture
def yaml_file(tmp_path, data):
    path = tmp_path / "scenario.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


# ----------------------------------------------------------------------------- JSON and YAML

def test_json_and_yaml_files_load_to_equal_models(json_file, yaml_file, data):
    from_json = rfesim.load_scenario(json_file)
    from_yaml = rfesim.load_scenario(yaml_file)
    from_dict = rfesim.Scenario.model_validate(data)
    assert isinstance(from_json, rfesim.Scenario)
    assert from_json == from_yaml == from_dict
    assert from_json.lines["pipe"].length == 10.0
    assert from_json.vessels["barge"].motion.heave.period == 8.0


def test_path_as_string_and_yml_suffix(tmp_path, json_file, data):
    path = tmp_path / "scenario.yml"
    path.write_text(yaml.safe_dump(data))
    assert rfesim.load_scenario(str(json_file)) == rfesim.load_scenario(str(path))


def test_text_sources(data):
    from_json_text = rfesim.load_scenario(json.dumps(data))
    from_yaml_text = rfesim.load_scenario(yaml.safe_dump(data))
    from_bytes = rfesim.load_scenario(json.dumps(data).encode())
    assert from_json_text == from_yaml_text == from_bytes


def test_json_content_in_a_yaml_file(tmp_path, data):
    path = tmp_path / "scenario.yaml"
    path.write_text(json.dumps(data, indent=2))
    assert rfesim.load_scenario(path) == rfesim.Scenario.model_validate(data)


def test_yaml_written_by_hand(tmp_path):
    path = tmp_path / "hand.yaml"
    path.write_text("""\
# a hand-written scenario
name: hand
line_types:
  cable: {EA: 1.0e8, EIy: 0.0, mass_per_length: 20.0}
lines:
  pipe:
    type: cable
    length: 100
    elements: 10
    end_a: {attach: fixed, position: [0, 0, 0]}
    end_b: {attach: fixed, position: [90, 0, 0]}
""")
    sc = rfesim.load_scenario(path)
    assert sc.lines["pipe"].end_b.position == [90.0, 0.0, 0.0]
    compile_scenario(sc)


def test_yaml_merge_keys_share_properties(tmp_path):
    """``<<: *base`` merges a mapping (YAML's merge key); the keys written beside it win. It
    failed with "could not determine a constructor for the tag ...merge" before."""
    path = tmp_path / "merge.yaml"
    path.write_text("""\
name: merge
line_types:
  cable: &cable {EA: 1.0e8, EIy: 0.0, mass_per_length: 20.0}
  heavy:
    <<: *cable
    mass_per_length: 40.0
lines:
  pipe:
    type: heavy
    length: 100
    elements: 10
    end_a: &end {attach: fixed, position: [0, 0, 0]}
    end_b:
      <<: [*end, {connection: pinned}]
      position: [90, 0, 0]
""")
    sc = rfesim.load_scenario(path)
    heavy = sc.line_types["heavy"]
    assert (heavy.EA, heavy.EIy, heavy.mass_per_length) == (1.0e8, 0.0, 40.0)
    assert sc.lines["pipe"].end_b.position == [90.0, 0.0, 0.0] and sc.lines["pipe"].end_b.attach == "fixed"
    path.write_text(path.read_text().replace("    mass_per_length: 40.0\n", "    mass_per_length: 40.0\n"
                                             "    mass_per_length: 41.0\n"))
    with pytest.raises(rfesim.ScenarioError, match="key 'mass_per_length' appears twice"):
        rfesim.load_scenario(path)


def test_utf8_bom_is_accepted(tmp_path, data):
    path = tmp_path / "bom.json"
    path.write_bytes(b"\xef\xbb\xbf" + json.dumps(data).encode())
    assert rfesim.load_scenario(path).name == "cantilever pipe"


# ----------------------------------------------------------------------------- overrides

def test_overrides(json_file):
    sc = rfesim.load_scenario(json_file, overrides={"lines.pipe.elements": 40})
    assert sc.lines["pipe"].elements == 40
    assert rfesim.load_scenario(json_file).lines["pipe"].elements == 20


def test_override_into_a_list(yaml_file):
    sc = rfesim.load_scenario(yaml_file, overrides={"lines.pipe.loads.0.force": [0.0, 0.0, -2000.0]})
    assert sc.lines["pipe"].loads[0].force == [0.0, 0.0, -2000.0]


def test_overrides_do_not_change_the_input(data):
    before = copy.deepcopy(data)
    sc = rfesim.load_scenario(data, overrides={"lines.pipe.length": 12.0, "environment.water.density": 1030.0})
    assert sc.lines["pipe"].length == 12.0
    assert sc.environment.water.density == 1030.0
    assert data == before


def test_override_creates_missing_mappings(data):
    sc = rfesim.load_scenario(data, overrides={"environment.seabed.normal_stiffness": 2.0e5})
    assert sc.environment.seabed.normal_stiffness == 2.0e5
    assert sc.environment.seabed_z() == -100.0


def test_overrides_on_a_scenario(data):
    sc = rfesim.Scenario.model_validate(data)
    sc2 = rfesim.load_scenario(sc, overrides={"analysis.dynamics.integrator.rho_inf": 0.5})
    assert sc2.analysis.dynamics.integrator.rho_inf == 0.5
    assert sc.analysis.dynamics.integrator.rho_inf == 0.8
    assert rfesim.load_scenario(sc) is sc     # unchanged since validated: taken as it is


def test_override_with_a_bad_value_names_the_path(json_file):
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(json_file, overrides={"lines.pipe.loads.0.force": [0.0, 1.0]})
    assert info.value.errors[0][0] == "lines.pipe.loads.0.force"


# ----------------------------------------------------------------------------- model_validate

def test_model_validate_dict(data):
    sc = rfesim.Scenario.model_validate(data)
    assert sc.lines["pipe"].type == "pipe12"
    assert rfesim.Scenario.model_validate(sc) is sc


def test_model_validate_raises_scenario_error(data):
    data["lines"]["pipe"]["elements"] = 0
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    assert not isinstance(info.value, pydantic.ValidationError)
    assert info.value.errors[0][0] == "lines.pipe.elements"


def test_model_validate_checks_references(data):
    data["lines"]["pipe"]["end_a"]["attach"] = "ship"
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    assert info.value.errors[0][0] == "lines.pipe.end_a.attach"


def test_model_validate_json(data):
    assert rfesim.Scenario.model_validate_json(json.dumps(data)) == rfesim.Scenario.model_validate(data)
    data["lines"]["pipe"]["length"] = -1
    with pytest.raises(ScenarioError, match="lines.pipe.length"):
        rfesim.Scenario.model_validate_json(json.dumps(data))


# ----------------------------------------------------------------------------- round trips

def test_model_dump_json_round_trips(data):
    sc = rfesim.Scenario.model_validate(data)
    text = sc.model_dump_json()
    again = rfesim.load_scenario(text)
    assert again == sc
    assert again.model_dump_json() == text


def test_model_dump_json_round_trips_through_a_file(tmp_path, data):
    sc = rfesim.Scenario.model_validate(data)
    path = tmp_path / "dumped.json"
    path.write_text(sc.model_dump_json(indent=2))
    assert rfesim.load_scenario(path) == sc


def test_model_dump_round_trips_as_yaml(tmp_path, data):
    sc = rfesim.Scenario.model_validate(data)
    path = tmp_path / "dumped.yaml"
    path.write_text(yaml.safe_dump(sc.model_dump(mode="json")))
    assert rfesim.load_scenario(path) == sc


def test_round_trip_of_every_motion_and_integrator(data):
    data["vessels"]["table"] = {"motion": {"kind": "table", "interpolation": "linear",
                                           "rows": [[0, 0, 0, 0, 0, 0, 0], [1, 0, 0, 1, 0, 0, 0]]}}
    data["vessels"]["still"] = {"motion": {"kind": "fixed"}}
    data["lines"]["pipe"]["loads"].append({"at": 5.0, "moment": [0, 100.0, 0], "frame": "local"})
    for integrator in ({"kind": "rk4"}, {"kind": "adaptive", "rtol": 1e-5},
                       {"kind": "generalized-alpha", "rho_inf": 0.6}):
        data["analysis"]["dynamics"]["integrator"] = integrator
        sc = rfesim.Scenario.model_validate(data)
        assert rfesim.load_scenario(sc.model_dump_json()) == sc


# ----------------------------------------------------------------------------- JSON Schema

def _properties(schema: dict, model: str) -> dict:
    return schema["$defs"][model]["properties"]


def test_json_schema_has_units():
    schema = rfesim.Scenario.model_json_schema()
    assert _properties(schema, "Line")["length"]["units"] == "m"
    assert _properties(schema, "LineType")["youngs_modulus"]["units"] == "Pa"
    assert _properties(schema, "LineType")["density"]["units"] == "kg/m^3"
    assert _properties(schema, "Environment")["gravity"]["units"] == "m/s^2"
    assert _properties(schema, "HarmonicDof")["period"]["units"] == "s"
    assert _properties(schema, "LineEnd")["position"]["units"] == "m"
    assert _properties(schema, "Water")["density"]["units"] == "kg/m^3"


def test_json_schema_states_the_limits():
    schema = rfesim.Scenario.model_json_schema()
    line = _properties(schema, "Line")
    assert line["length"]["exclusiveMinimum"] == 0.0
    assert line["elements"]["minimum"] == 1
    assert schema["additionalProperties"] is False
    assert schema["$defs"]["Line"]["additionalProperties"] is False
    json.dumps(schema)           # plain JSON


# ----------------------------------------------------------------------------- defaults

def test_defaults_are_filled():
    sc = rfesim.Scenario.model_validate({
        "line_types": {"pipe12": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.1e11,
                                  "density": 7850.0}},
        "lines": {"pipe": {"type": "pipe12", "length": 10.0, "elements": 10,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0]}}},
        "environment": {"water": {}},
    })
    assert sc.schema_version == 1
    assert sc.environment.gravity == 9.81
    assert sc.environment.water.density == 1025.0
    assert sc.environment.water.surface_level == 0.0
    assert sc.environment.seabed is None
    line = sc.lines["pipe"]
    assert line.end_a.connection == "pinned"
    assert line.end_b.attach == "free"
    assert line.end_b.connection == "pinned"
    assert line.formulation == "absolute"
    assert line.loads == []
    lt = sc.line_types["pipe12"]
    assert lt.poisson_ratio == 0.3
    assert lt.material.kind == "elastic"
    assert sc.analysis.statics.enabled is True
    assert sc.analysis.dynamics.integrator.kind == "generalized-alpha"
    assert sc.analysis.dynamics.integrator.rho_inf == 0.8
    assert sc.vessels == {}


def test_no_water_by_default():
    sc = rfesim.Scenario.model_validate({})
    assert sc.environment.water is None
    assert sc.environment.gravity == 9.81


def test_vessel_defaults(data):
    data["vessels"]["still"] = {}
    sc = rfesim.Scenario.model_validate(data)
    assert sc.vessels["still"].motion.kind == "fixed"
    assert sc.vessels["still"].position == [0.0, 0.0, 0.0]
    assert sc.vessels["still"].heading_deg == 0.0


def test_seabed_level_from_water_depth(data):
    data["environment"]["seabed"] = {}
    sc = rfesim.Scenario.model_validate(data)
    assert sc.environment.seabed_z() == -100.0
    assert sc.environment.seabed.normal_stiffness == 1.0e5


def test_loaded_scenario_compiles(json_file):
    model = compile_scenario(rfesim.load_scenario(json_file))
    assert model.line("pipe").elements == 20


def test_numba_cache_folder_only_moves_for_installed_packages(monkeypatch, tmp_path):
    """An installed package caches its kernels in the user cache (numba's __pycache__ files
    would outlive pip uninstall in site-packages); a source checkout and a user choice stay."""
    import rfesim
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    rfesim._numba_cache_dir()                      # this checkout is not in site-packages
    assert "NUMBA_CACHE_DIR" not in __import__("os").environ
    monkeypatch.setattr(rfesim, "__file__", "/x/lib/python3.11/site-packages/rfesim/__init__.py")
    import os
    real_abspath = os.path.abspath
    monkeypatch.setattr(os.path, "abspath", lambda p: p if "site-packages" in str(p) else real_abspath(p))
    rfesim._numba_cache_dir.__globals__["__file__"] = "/x/lib/python3.11/site-packages/rfesim/__init__.py"
    try:
        rfesim._numba_cache_dir()
        assert os.environ["NUMBA_CACHE_DIR"] == str(tmp_path / "rfesim" / "numba")
        monkeypatch.setenv("NUMBA_CACHE_DIR", "/mine")
        rfesim._numba_cache_dir()
        assert os.environ["NUMBA_CACHE_DIR"] == "/mine"
    finally:
        rfesim._numba_cache_dir.__globals__["__file__"] = real_abspath(rfesim.__path__[0] + "/__init__.py")


def test_yaml_numbers_in_exponent_form_are_numbers():
    # YAML 1.1 (PyYAML's safe loader) reads 2.1e11 and 1e5 as text; a scenario reads them as
    # numbers, as JSON and YAML 1.2 do; quoted they stay text
    from rfesim.scenario import parse_text

    text = "a: 2.1e11\nb: 1e5\nc: -3E-2\nd: '2e5'\ne: .5e3\nf: 2.5\ng: 12\nh: e5\n"
    assert yaml.safe_load(text)["a"] == "2.1e11"
    assert parse_text(text, "yaml") == {"a": 2.1e11, "b": 1e5, "c": -0.03, "d": "2e5", "e": 500.0, "f": 2.5,
                                        "g": 12, "h": "e5"}
    doc = ("name: exponent\nline_types:\n  steel:\n    EA: 2.1e9\n    EIy: 1e5\n    mass_per_length: 5e1\n"
           "lines:\n  pipe:\n    type: steel\n    length: 1e1\n    elements: 10\n"
           "    end_a: {attach: fixed, position: [0, 0, 0], direction: [1, 0, 0], connection: clamped}\n"
           "    end_b: {attach: free}\n")
    sc = rfesim.load_scenario(doc)
    assert sc.line_types["steel"].EA == 2.1e9 and sc.lines["pipe"].length == 10.0
