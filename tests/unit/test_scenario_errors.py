"""Bad scenario input: every problem is a ScenarioError naming the field and the reason.

Each case takes a small valid scenario (a pipe line type, one line clamped at end A
and free at end B, statics only), breaks it one way, and checks that validation (and
``compile_scenario``, for the geometry-level problems) raises ``rfesim.ScenarioError``
with an entry for the expected dotted path whose reason says what is wrong. The same
cases go through a Python dict, JSON text and a YAML file.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path

import pydantic
import pytest
import yaml

import rfesim
from rfesim import ScenarioError
from rfesim.model.compile import compile_scenario

NAN = float("nan")
INF = float("inf")

BASE = {
    "schema_version": 1,
    "name": "cantilever pipe",
    "line_types": {
        "pipe12": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 2.07e11,
                   "poisson_ratio": 0.3, "density": 7850.0},
    },
    "lines": {
        "pipe": {"type": "pipe12", "length": 10.0, "elements": 20,
                 "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                           "connection": "clamped"},
                 "end_b": {"attach": "free"}},
    },
    "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}},
}

CABLE = {"EA": 1.0e8, "EIy": 1.0e3, "mass_per_length": 50.0}
HARMONIC = {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 8.0}}
ROWS = [[0.0, 0, 0, 0, 0, 0, 0], [1.0, 0, 0, 0.5, 0, 0, 0], [2.0, 0, 0, 1.0, 0, 0, 0]]


# ----------------------------------------------------------------------------- helpers

def _walk(data, keys):
    cur = data
    for k in keys:
        cur = cur[int(k)] if isinstance(cur, list) else cur[k]
    return cur


def put(**changes):
    """A mutation setting dotted paths (``__`` stands for ``.``) to values."""
    def mutate(data):
        for dotted, value in changes.items():
            keys = dotted.split("__")
            parent = data
            for k in keys[:-1]:
                if isinstance(parent, list):
                    parent = parent[int(k)]
                else:
                    parent = parent.setdefault(k, {})
            if isinstance(parent, list):
                parent[int(keys[-1])] = copy.deepcopy(value)
            else:
                parent[keys[-1]] = copy.deepcopy(value)
    return mutate


def drop(*dotted):
    """A mutation removing keys (``__`` for ``.``)."""
    def mutate(data):
        for path in dotted:
            keys = path.split("__")
            del _walk(data, keys[:-1])[keys[-1]]
    return mutate


def both(*mutations):
    def mutate(data):
        for m in mutations:
            m(data)
    return mutate


def rename_line(new):
    def mutate(data):
        data["lines"] = {new: data["lines"].pop("pipe")}
    return mutate


def mutated(mutation):
    data = copy.deepcopy(BASE)
    mutation(data)
    return data


def validate_and_compile(data):
    sc = rfesim.Scenario.model_validate(data)
    compile_scenario(sc)
    return sc


def via_dict(data, tmp_path):
    return validate_and_compile(data)


def via_json_text(data, tmp_path):
    sc = rfesim.load_scenario(json.dumps(data, indent=1))
    compile_scenario(sc)
    return sc


def via_yaml_file(data, tmp_path):
    path = tmp_path / "scenario.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    sc = rfesim.load_scenario(path)
    compile_scenario(sc)
    return sc


ROUTES = [pytest.param(via_dict, id="dict"), pytest.param(via_json_text, id="json"),
          pytest.param(via_yaml_file, id="yaml")]


def reasons_at(exc: ScenarioError, path: str) -> list[str]:
    return [r for p, r in exc.errors if p == path]


# ----------------------------------------------------------------------------- the cases
# (id, mutation, expected path, a word the reason must contain)

CASES = [
    # lengths and element counts
    ("length-negative", put(lines__pipe__length=-1.0), "lines.pipe.length", "greater than 0"),
    ("length-zero", put(lines__pipe__length=0.0), "lines.pipe.length", "greater than 0"),
    ("length-huge", put(lines__pipe__length=1e308), "lines.pipe.length", "less than"),
    ("length-tiny", put(lines__pipe__length=1e-300), "lines.pipe.length", "too short"),
    ("length-missing", drop("lines__pipe__length"), "lines.pipe.length", "missing"),
    ("length-null", put(lines__pipe__length=None), "lines.pipe.length", "number"),
    ("length-string", put(lines__pipe__length="ten"), "lines.pipe.length", "number"),
    ("length-boolean", put(lines__pipe__length=True), "lines.pipe.length", "boolean"),
    ("elements-zero", put(lines__pipe__elements=0), "lines.pipe.elements", "greater than or equal to 1"),
    ("elements-negative", put(lines__pipe__elements=-3), "lines.pipe.elements", "greater than or equal to 1"),
    ("elements-fraction", put(lines__pipe__elements=2.5), "lines.pipe.elements", "whole number"),
    ("elements-boolean", put(lines__pipe__elements=True), "lines.pipe.elements", "boolean"),
    ("elements-string", put(lines__pipe__elements="many"), "lines.pipe.elements", "whole number"),
    ("elements-too-many", put(lines__pipe__elements=200000), "lines.pipe.elements", "less than"),
    ("elements-too-fine", put(lines__pipe__length=0.01, lines__pipe__elements=100000),
     "lines.pipe.elements", "fewer elements"),
    # NaN and inf
    ("length-nan", put(lines__pipe__length=NAN), "lines.pipe.length", "finite"),
    ("length-inf", put(lines__pipe__length=INF), "lines.pipe.length", "finite"),
    ("youngs-inf", put(line_types__pipe12__youngs_modulus=INF), "line_types.pipe12.youngs_modulus", "finite"),
    ("youngs-nan", put(line_types__pipe12__youngs_modulus=NAN), "line_types.pipe12.youngs_modulus", "finite"),
    ("position-nan", put(lines__pipe__end_a__position=[0.0, NAN, 0.0]), "lines.pipe.end_a.position.1", "finite"),
    ("position-minus-inf", put(lines__pipe__end_a__position=[0.0, 0.0, -INF]), "lines.pipe.end_a.position.2",
     "finite"),
    ("direction-inf", put(lines__pipe__end_a__direction=[INF, 0.0, 0.0]), "lines.pipe.end_a.direction.0",
     "finite"),
    ("gravity-nan", put(environment={"gravity": NAN}), "environment.gravity", "finite"),
    ("gravity-inf", put(environment={"gravity": INF}), "environment.gravity", "finite"),
    ("water-density-nan", put(environment={"water": {"density": NAN}}), "environment.water.density", "finite"),
    ("load-force-inf", put(lines__pipe__loads=[{"at": "end_b", "force": [0.0, 0.0, -INF]}]),
     "lines.pipe.loads.0.force.2", "finite"),
    ("period-nan", put(vessels={"barge": {"motion": {"kind": "harmonic",
                                                     "heave": {"amplitude": 1.0, "period": NAN}}}}),
     "vessels.barge.motion.heave.period", "finite"),
    # unknown keys
    ("unknown-top-key", put(foo=1), "foo", "unknown key"),
    ("unknown-line-key", put(lines__pipe__foo=1), "lines.pipe.foo", "unknown key"),
    ("unknown-end-key", put(lines__pipe__end_a__bar=1), "lines.pipe.end_a.bar", "unknown key"),
    ("unknown-type-key", put(line_types__pipe12__colour="red"), "line_types.pipe12.colour", "unknown key"),
    ("misspelled-key", both(drop("lines__pipe__length"), put(lines__pipe__lenght=10.0)),
     "lines.pipe.lenght", "did you mean 'length'"),
    ("unknown-env-key", put(environment={"gravityy": 9.81}), "environment.gravityy", "did you mean 'gravity'"),
    ("unknown-motion-key", put(vessels={"barge": {"motion": {"kind": "harmonic",
                                                             "heav": {"amplitude": 1, "period": 2}}}}),
     "vessels.barge.motion.heav", "did you mean 'heave'"),
    ("unknown-integrator-key", put(analysis__dynamics__integrator={"kind": "rk4", "step": 0.1}),
     "analysis.dynamics.integrator.step", "unknown key"),
    # references
    ("unknown-attachment", put(lines__pipe__end_a__attach="ship"), "lines.pipe.end_a.attach",
     "unknown attachment 'ship'"),
    ("unknown-attachment-with-vessels", both(put(vessels={"barge": {}}), put(lines__pipe__end_a__attach="bardge")),
     "lines.pipe.end_a.attach", "barge"),
    ("unknown-line-type", put(lines__pipe__type="pipe13"), "lines.pipe.type", "unknown line type 'pipe13'"),
    ("line-type-missing", drop("lines__pipe__type"), "lines.pipe.type", "missing"),
    ("vessel-named-fixed", put(vessels={"fixed": {}}), "vessels.fixed", "reserved"),
    ("bad-line-name", rename_line("a:b"), "lines.a:b", "must not contain"),
    ("empty-line-name", rename_line(""), "lines", "empty"),
    # physically impossible sections
    ("wall-thicker-than-radius", put(line_types__pipe12__wall_thickness=0.2), "line_types.pipe12.wall_thickness",
     "radius"),
    ("wall-equal-radius", put(line_types__pipe12__wall_thickness=0.16195), "line_types.pipe12.wall_thickness",
     "radius"),
    ("wall-zero", put(line_types__pipe12__wall_thickness=0.0), "line_types.pipe12.wall_thickness",
     "greater than 0"),
    ("diameter-zero", put(line_types__pipe12__outer_diameter=0.0), "line_types.pipe12.outer_diameter",
     "greater than 0"),
    ("diameter-negative", put(line_types__pipe12__outer_diameter=-0.3), "line_types.pipe12.outer_diameter",
     "greater than 0"),
    ("density-zero", put(line_types__pipe12__density=0.0), "line_types.pipe12.density",
     "greater than or equal to 1 kg/m^3"),
    ("density-negative", put(line_types__pipe12__density=-7850.0), "line_types.pipe12.density",
     "greater than or equal to 1 kg/m^3"),
    ("water-density-zero", put(environment={"water": {"density": 0.0}}), "environment.water.density",
     "greater than 0"),
    ("water-density-negative", put(environment={"water": {"density": -1025.0}}), "environment.water.density",
     "greater than 0"),
    ("poisson-too-large", put(line_types__pipe12__poisson_ratio=0.5), "line_types.pipe12.poisson_ratio",
     "less than 0.5"),
    ("poisson-too-small", put(line_types__pipe12__poisson_ratio=-1.5), "line_types.pipe12.poisson_ratio",
     "greater than -1"),
    ("youngs-zero", put(line_types__pipe12__youngs_modulus=0.0), "line_types.pipe12.youngs_modulus",
     "greater than or equal to 100000 Pa"),
    ("youngs-absurd", put(line_types__pipe12__youngs_modulus=1e307, line_types__pipe12__outer_diameter=100.0,
                          line_types__pipe12__wall_thickness=10.0),
     "line_types.pipe12.youngs_modulus", "stiffness"),
    ("pipe-missing-youngs", drop("line_types__pipe12__youngs_modulus"), "line_types.pipe12.youngs_modulus",
     "needs"),
    ("pipe-missing-diameter", drop("line_types__pipe12__outer_diameter"), "line_types.pipe12.outer_diameter",
     "needs"),
    ("pipe-missing-wall", drop("line_types__pipe12__wall_thickness"), "line_types.pipe12.wall_thickness",
     "wall_thickness"),
    ("direct-missing-EA", put(line_types__pipe12={"EIy": 1e3, "mass_per_length": 50.0}),
     "line_types.pipe12.EA", "EA"),
    ("direct-missing-mass", put(line_types__pipe12={"EA": 1e8, "EIy": 1e3}),
     "line_types.pipe12.mass_per_length", "mass_per_length"),
    ("direct-missing-bending", put(line_types__pipe12={"EA": 1e8, "mass_per_length": 50.0}),
     "line_types.pipe12.EIy", "bending stiffness"),
    ("direct-negative-EA", put(line_types__pipe12={**CABLE, "EA": -1e8}), "line_types.pipe12.EA",
     "greater than 0"),
    ("pipe-and-direct", put(line_types__pipe12__EA=1e9), "line_types.pipe12.EA", "not both"),
    ("direct-with-contents", put(line_types__pipe12={**CABLE, "contents_density": 1000.0}),
     "line_types.pipe12.contents_density", "mass_per_length"),
    ("hydro-without-diameter", both(put(environment={"water": {}}),
                                    put(line_types__pipe12={**CABLE, "drag_normal": 1.2})),
     "line_types.pipe12.outer_diameter", "outer diameter"),
    # ends, directions, loads
    ("fixed-end-without-position", drop("lines__pipe__end_a__position"), "lines.pipe.end_a.position",
     "needs a position"),
    ("vessel-end-without-position", both(put(vessels={"barge": {}}),
                                         put(lines__pipe__end_b={"attach": "barge"})),
     "lines.pipe.end_b.position", "needs a position"),
    ("zero-direction", put(lines__pipe__end_a__direction=[0.0, 0.0, 0.0]), "lines.pipe.end_a.direction",
     "zero vector"),
    ("vector-two-components", put(lines__pipe__end_a__position=[0.0, 0.0]), "lines.pipe.end_a.position",
     "3 numbers"),
    ("vector-four-components", put(lines__pipe__end_a__direction=[1.0, 0.0, 0.0, 0.0]),
     "lines.pipe.end_a.direction", "3 numbers"),
    ("vector-boolean-component", put(lines__pipe__end_a__position=[0.0, True, 0.0]),
     "lines.pipe.end_a.position.1", "boolean"),
    ("vector-string", put(lines__pipe__end_a__direction="up"), "lines.pipe.end_a.direction", "list"),
    ("connection-unknown", put(lines__pipe__end_a__connection="welded"), "lines.pipe.end_a.connection",
     "'clamped' or 'pinned'"),
    ("free-end-clamped", put(lines__pipe__end_b__connection="clamped"), "lines.pipe.end_b.connection",
     "free end cannot be clamped"),
    ("two-free-ends", put(lines__pipe__end_a={"attach": "free"}), "lines.pipe.end_a.position", "two free ends"),
    ("load-beyond-end", put(lines__pipe__loads=[{"at": 12.0, "force": [0, 0, -1000.0]}]),
     "lines.pipe.loads.0.at", "outside the line"),
    ("load-negative-arc", put(lines__pipe__loads=[{"at": "end_b"}, {"at": -0.5}]), "lines.pipe.loads.1.at",
     "outside the line"),
    ("load-at-word", put(lines__pipe__loads=[{"at": "middle"}]), "lines.pipe.loads.0.at", "'end_a', 'end_b'"),
    ("load-at-boolean", put(lines__pipe__loads=[{"at": True}]), "lines.pipe.loads.0.at", "boolean"),
    ("loads-not-a-list", put(lines__pipe__loads={"at": "end_b"}), "lines.pipe.loads", "list"),
    # geometry (some found only when the model is compiled)
    ("chord-longer-than-line", put(lines__pipe__end_b={"attach": "fixed", "position": [20.0, 0.0, 0.0]}),
     "lines.pipe.length", "distance between its ends"),
    ("chord-to-vessel", both(put(vessels={"barge": {"position": [0.0, 30.0, 0.0], "heading_deg": 90.0}}),
                             put(lines__pipe__end_b={"attach": "barge", "position": [5.0, 0.0, 0.0]})),
     "lines.pipe.length", "distance between its ends"),
    ("ends-coincide", put(lines__pipe__end_b={"attach": "fixed", "position": [0.0, 0.0, 0.0]}),
     "lines.pipe.end_b.position", "coincides"),
    ("ends-coincide-via-vessel", both(put(vessels={"barge": {"position": [1.0, 2.0, 3.0]}}),
                                      put(lines__pipe__end_a__position=[1.0, 2.0, 3.0],
                                          lines__pipe__end_b={"attach": "barge", "position": [0.0, 0.0, 0.0]})),
     "lines.pipe.end_b.position", "coincides"),
    # environment
    ("gravity-negative", put(environment={"gravity": -9.81}), "environment.gravity", "greater than or equal"),
    ("gravity-string", put(environment={"gravity": "earth"}), "environment.gravity", "number"),
    ("seabed-without-level", put(environment={"seabed": {}}), "environment.seabed.z", "water depth"),
    ("seabed-above-water", put(environment={"water": {}, "seabed": {"z": 5.0}}), "environment.seabed.z",
     "below the water surface"),
    ("water-depth-zero", put(environment={"water": {"depth": 0.0}}), "environment.water.depth",
     "greater than 0"),
    ("environment-a-string", put(environment="sea"), "environment", "mapping"),
    # vessels and their motions
    ("harmonic-period-zero", put(vessels={"barge": {"motion": {"kind": "harmonic",
                                                               "heave": {"amplitude": 1.0, "period": 0.0}}}}),
     "vessels.barge.motion.heave.period", "greater than 0"),
    ("harmonic-amplitude-negative", put(vessels={"barge": {"motion": {"kind": "harmonic",
                                                                      "roll": {"amplitude": -2.0, "period": 9.0}}}}),
     "vessels.barge.motion.roll.amplitude", "greater than or equal to 0"),
    ("vessel-named-like-a-kind", put(vessels={"harmonic": {"motion": {"kind": "harmonic",
                                                                      "heave": {"amplitude": 1, "period": 0}}}}),
     "vessels.harmonic.motion.heave.period", "greater than 0"),
    ("table-time-not-increasing", put(vessels={"barge": {"motion": {
        "kind": "table", "interpolation": "linear", "rows": ROWS[:2] + [[1.0, 0, 0, 0, 0, 0, 0]]}}}),
     "vessels.barge.motion.rows.2", "does not increase"),
    ("table-time-decreasing", put(vessels={"barge": {"motion": {
        "kind": "table", "interpolation": "linear", "rows": [ROWS[0], ROWS[2], ROWS[1]]}}}),
     "vessels.barge.motion.rows.2", "does not increase"),
    ("table-row-too-short", put(vessels={"barge": {"motion": {
        "kind": "table", "interpolation": "linear", "rows": [ROWS[0], [1.0, 0, 0, 0, 0, 0]]}}}),
     "vessels.barge.motion.rows.1", "7 numbers"),
    ("table-row-too-long", put(vessels={"barge": {"motion": {
        "kind": "table", "interpolation": "linear", "rows": [ROWS[0], [1.0, 0, 0, 0, 0, 0, 0, 0]]}}}),
     "vessels.barge.motion.rows.1", "7 numbers"),
    ("table-cubic-few-rows", put(vessels={"barge": {"motion": {"kind": "table", "rows": ROWS}}}),
     "vessels.barge.motion.rows", "4 rows"),
    ("table-one-row", put(vessels={"barge": {"motion": {"kind": "table", "interpolation": "linear",
                                                        "rows": ROWS[:1]}}}),
     "vessels.barge.motion.rows", "at least 2"),
    ("motion-kind-unknown", put(vessels={"barge": {"motion": {"kind": "wobble"}}}), "vessels.barge.motion.kind",
     "unknown kind 'wobble'"),
    ("motion-kind-missing", put(vessels={"barge": {"motion": {"heave": {"amplitude": 1.0, "period": 8.0}}}}),
     "vessels.barge.motion.kind", "missing"),
    ("vessel-a-list", put(vessels={"barge": [0, 0, 0]}), "vessels.barge", "mapping"),
    # analysis settings
    ("integrator-unknown", put(analysis__dynamics__integrator={"kind": "euler"}),
     "analysis.dynamics.integrator.kind", "unknown kind 'euler'"),
    ("integrator-kind-missing", put(analysis__dynamics__integrator={"time_step": 0.1}),
     "analysis.dynamics.integrator.kind", "missing"),
    ("integrator-a-string", put(analysis__dynamics__integrator="rk4"), "analysis.dynamics.integrator", "mapping"),
    ("rho-inf-above-one", put(analysis__dynamics__integrator={"kind": "generalized-alpha", "rho_inf": 1.5}),
     "analysis.dynamics.integrator.rho_inf", "less than or equal to 1"),
    ("rho-inf-negative", put(analysis__dynamics__integrator={"kind": "generalized-alpha", "rho_inf": -0.1}),
     "analysis.dynamics.integrator.rho_inf", "greater than or equal to 0"),
    ("time-step-zero", put(analysis__dynamics__integrator={"kind": "generalized-alpha", "time_step": 0.0}),
     "analysis.dynamics.integrator.time_step", "greater than 0"),
    ("rtol-zero", put(analysis__dynamics__integrator={"kind": "adaptive", "rtol": 0.0}),
     "analysis.dynamics.integrator.rtol", "greater than or equal to 0.000000000001"),
    ("duration-negative", put(analysis__dynamics__duration=-1.0), "analysis.dynamics.duration",
     "greater than or equal to 0"),
    ("output-interval-too-long", put(analysis__dynamics={"enabled": True, "duration": 1.0, "output_interval": 5.0}),
     "analysis.dynamics.output_interval", "longer than the duration"),
    ("statics-enabled-a-number", put(analysis__statics__enabled="maybe"), "analysis.statics.enabled",
     "true or false"),
    ("modal-modes-zero", put(analysis__modal={"modes": 0}), "analysis.modal.modes", "greater than or equal to 1"),
    ("schema-version-2", put(schema_version=2), "schema_version", "must be 1"),
    ("lines-a-list", put(lines=[{"type": "pipe12"}]), "lines", "mapping"),
    ("line-null", put(lines__pipe=None), "lines.pipe", "mapping"),
]


@pytest.mark.parametrize("route", ROUTES)
@pytest.mark.parametrize("mutation, path, word", [pytest.param(*c[1:], id=c[0]) for c in CASES])
def test_bad_value_is_named(route, mutation, path, word, tmp_path):
    data = mutated(mutation)
    with pytest.raises(ScenarioError) as info:
        route(data, tmp_path)
    exc = info.value
    reasons = reasons_at(exc, path)
    assert reasons, f"no error at {path!r}; got {exc.errors}"
    assert any(word.lower() in r.lower() for r in reasons), f"{word!r} not in {reasons}"
    assert path in str(exc) if path else True
    assert not isinstance(exc, pydantic.ValidationError)


def test_base_scenario_is_valid():
    sc = validate_and_compile(copy.deepcopy(BASE))
    assert sc.lines["pipe"].elements == 20


@pytest.mark.parametrize("mutation", [
    pytest.param(put(lines__pipe__elements=20.0), id="elements-float-integral"),
    pytest.param(put(lines__pipe__length="10.5"), id="numeric-string"),
    pytest.param(put(line_types__pipe12__poisson_ratio=0.0), id="poisson-zero"),
    pytest.param(put(lines__pipe__end_b={"attach": "fixed", "position": [10.1, 0.0, 0.0]}),
                 id="taut-line-within-2-percent"),
    pytest.param(put(line_types__pipe12={**CABLE, "EIy": 0.0}), id="flexible-cable"),
    pytest.param(put(lines__pipe__loads=[{"at": 10.0}, {"at": 0.0}, {"at": "end_a"}]), id="loads-at-the-ends"),
    pytest.param(both(put(vessels={"barge": {"position": [0.0, 8.0, 0.0], "motion": HARMONIC}}),
                      put(lines__pipe__end_b={"attach": "barge", "position": [0.0, 0.0, 0.0]})), id="to-vessel"),
    pytest.param(put(vessels={"harmonic": {"motion": HARMONIC}}), id="vessel-named-like-a-kind"),
])
def test_edge_values_that_are_fine(mutation):
    validate_and_compile(mutated(mutation))


def test_boolean_is_not_read_as_one():
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(mutated(put(lines__pipe__elements=True)))
    assert info.value.errors == [("lines.pipe.elements", "must be a number, not the boolean true")]


# ----------------------------------------------------------------------------- the document itself

@pytest.mark.parametrize("obj", [[], [1, 2], "a scenario", None, 42, 3.5, True],
                         ids=["empty-list", "list", "string", "none", "int", "float", "bool"])
def test_scenario_must_be_a_mapping(obj):
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(obj)
    (path, reason), = info.value.errors
    assert path == ""
    assert "mapping" in reason


@pytest.mark.parametrize("text", ["[1, 2, 3]\n", '"just text"\n', "- a\n- b\n", "42\n"])
def test_scenario_text_must_be_a_mapping(text):
    with pytest.raises(ScenarioError, match="mapping"):
        rfesim.load_scenario(text)


@pytest.mark.parametrize("suffix", [".json", ".yaml"])
def test_scenario_file_must_be_a_mapping(tmp_path, suffix):
    path = tmp_path / f"s{suffix}"
    path.write_text("[1, 2]\n")
    with pytest.raises(ScenarioError, match="mapping"):
        rfesim.load_scenario(path)


INVALID_JSON = '{\n  "lines": {\n    "pipe": {"length": 10.0,, "elements": 20}\n  }\n}\n'
INVALID_YAML = "lines:\n  pipe:\n    length: 10.0\n   elements: 20\n"


def _line_column(exc: ScenarioError) -> str:
    (path, reason), = exc.errors
    assert path == ""
    assert "line" in reason and "column" in reason, reason
    return reason


def test_invalid_json_text():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(INVALID_JSON)
    reason = _line_column(info.value)
    assert "JSON" in reason and "line 3" in reason


def test_invalid_json_file(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(INVALID_JSON)
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(path)
    reason = _line_column(info.value)
    assert "JSON" in reason and "line 3 column" in reason


def test_yaml_content_in_a_json_file_is_invalid_json(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text(yaml.safe_dump(BASE))
    with pytest.raises(ScenarioError, match="invalid JSON at line 1 column 1"):
        rfesim.load_scenario(path)


def test_invalid_json_via_model_validate_json():
    with pytest.raises(ScenarioError, match="invalid JSON"):
        rfesim.Scenario.model_validate_json(INVALID_JSON)


def test_invalid_yaml_text():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(INVALID_YAML)
    reason = _line_column(info.value)
    assert "YAML" in reason and "line 4" in reason


@pytest.mark.parametrize("suffix", [".yaml", ".yml", ".txt"])
def test_invalid_yaml_file(tmp_path, suffix):
    path = tmp_path / f"bad{suffix}"
    path.write_text(INVALID_YAML)
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(path)
    assert "YAML" in _line_column(info.value)


def test_yaml_tab_indentation(tmp_path):
    path = tmp_path / "tabs.yaml"
    path.write_text("lines:\n\tpipe: {}\n")
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(path)
    assert "YAML" in _line_column(info.value)


def test_duplicate_key_in_yaml():
    text = "name: a\nlines: {}\nname: b\n"
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(text)
    reason = _line_column(info.value)
    assert "'name' appears twice" in reason and "line 3" in reason


def test_duplicate_key_in_json():
    text = '{"lines": {"pipe": {"length": 10.0, "length": 20.0}}}'
    with pytest.raises(ScenarioError, match="'length' appears twice"):
        rfesim.load_scenario(text)


@pytest.mark.parametrize("content", ["", "\n\n", "   \n  \n", "# only a comment\n"])
@pytest.mark.parametrize("suffix", [".json", ".yaml"])
def test_empty_file(tmp_path, content, suffix):
    path = tmp_path / f"empty{suffix}"
    path.write_text(content)
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(path)
    (field, reason), = info.value.errors
    assert field == ""
    if content.strip() and suffix == ".json":
        assert "invalid JSON" in reason          # a YAML comment is not JSON
    else:
        assert "empty" in reason


@pytest.mark.parametrize("text", ["", "   ", "\n"])
def test_empty_text(text):
    with pytest.raises(ScenarioError, match="empty"):
        rfesim.load_scenario(text)


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere" / "scenario.json"
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(path)
    (field, reason), = info.value.errors
    assert "not found" in reason and str(path) in reason
    with pytest.raises(ScenarioError, match="not found"):
        rfesim.load_scenario(str(path))


def test_directory_instead_of_file(tmp_path):
    with pytest.raises(ScenarioError, match="directory"):
        rfesim.load_scenario(tmp_path)


def test_binary_file(tmp_path):
    path = tmp_path / "scenario.json"
    path.write_bytes(b"\xff\xfe\x00\x81garbage")
    with pytest.raises(ScenarioError, match="UTF-8"):
        rfesim.load_scenario(path)


def test_wrong_source_type():
    with pytest.raises(ScenarioError, match="file path"):
        rfesim.load_scenario(12345)


# ----------------------------------------------------------------------------- many errors at once

def test_all_errors_are_reported_together():
    data = mutated(both(put(lines__pipe__length=-1.0, lines__pipe__elements=0),
                        put(line_types__pipe12__density=-5.0)))
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    exc = info.value
    paths = [p for p, _ in exc.errors]
    assert sorted(paths) == sorted(["lines.pipe.length", "lines.pipe.elements", "line_types.pipe12.density"])
    lines = str(exc).splitlines()
    assert lines[0].startswith("3 errors")
    for path, reason in exc.errors:
        assert sum(1 for ln in lines if ln.strip() == f"{path}: {reason}") == 1
    assert len(lines) == 1 + 3


def test_errors_in_several_objects_are_reported_together():
    data = mutated(both(put(lines__pipe__length=NAN, foo=1),
                        put(vessels={"barge": {"motion": {"kind": "harmonic",
                                                          "heave": {"amplitude": 1.0, "period": 0.0}}}}),
                        put(analysis__dynamics__integrator={"kind": "euler"})))
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    paths = {p for p, _ in info.value.errors}
    assert paths == {"lines.pipe.length", "foo", "vessels.barge.motion.heave.period",
                     "analysis.dynamics.integrator.kind"}


def test_reference_errors_are_reported_together():
    data = mutated(both(put(lines__pipe__end_a__attach="ship", lines__pipe__end_b__connection="clamped"),
                        put(lines__other={"type": "nope", "length": 5.0, "elements": 4})))
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(data)
    paths = {p for p, _ in info.value.errors}
    assert paths == {"lines.pipe.end_a.attach", "lines.pipe.end_b.connection", "lines.other.type"}
    assert len(str(info.value).splitlines()) == 4


def test_single_error_message_names_field_and_reason():
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate(mutated(put(lines__pipe__elements=0)))
    assert str(info.value) == "lines.pipe.elements: must be greater than or equal to 1 (got 0)"


def test_errors_through_overrides():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(copy.deepcopy(BASE), overrides={"lines.pipe.elements": 0,
                                                             "lines.pipe.length": math.inf})
    assert {p for p, _ in info.value.errors} == {"lines.pipe.elements", "lines.pipe.length"}


@pytest.mark.parametrize("path", ["lines.pipe.loads.3.force", "lines.pipe.loads.x.force",
                                  "lines.pipe.length.value"])
def test_bad_override_path(path):
    data = mutated(put(lines__pipe__loads=[{"at": "end_b"}]))
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data, overrides={path: [0.0, 0.0, 1.0]})
    assert info.value.errors[0][0] == path


def test_no_pydantic_error_leaks():
    with pytest.raises(ScenarioError) as info:
        rfesim.Scenario.model_validate({"lines": {"pipe": {"length": "x"}}})
    assert info.value.__cause__ is None and info.value.__suppress_context__
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("value, expected", [
    # a table row too short: the row is named by its index, not by pydantic's union tag
    # ("slewing_deg.list[list[float]].0"), and the number alternative is not also blamed
    ([[0.0], [10.0, 90.0]], [("cranes.crane.slewing_deg.0", "needs at least 2 entries, got 1")]),
    ([[0.0, 80.0], [10.0, "x"]], [("cranes.crane.slewing_deg.1.1", "must be a number, got 'x'")]),
    # neither alternative fits: both are named on the field
    ("x", [("cranes.crane.slewing_deg", "must be a number, got 'x'; or must be a list, got 'x'")]),
])
def test_angle_profile_errors_name_the_row(value, expected):
    folder = Path(__file__).resolve().parents[2] / "scenarios"
    data = json.loads((folder / "column_crane.json").read_text())
    data["cranes"]["crane"]["slewing_deg"] = value
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data, base_dir=folder)
    assert info.value.errors == expected


def test_oversized_integer_is_named():
    # pydantic's own words were "Unable to parse input string as an integer, exceeded maximum size"
    data = copy.deepcopy(BASE)
    data["lines"]["pipe"]["elements"] = 1e30
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    assert info.value.errors == [("lines.pipe.elements", "must be a whole number of a usable size, got 1e+30")]


def test_null_kind_is_called_null():
    # a null kind was reported as the text 'None'
    data = copy.deepcopy(BASE)
    data["vessels"] = {"ship": {"position": [0.0, 0.0, 0.0], "motion": {"kind": None}}}
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(data)
    assert info.value.errors == [("vessels.ship.motion.kind",
                                  "unknown kind null (use one of: 'fixed', 'harmonic', 'table', 'rao', 'csv')")]
