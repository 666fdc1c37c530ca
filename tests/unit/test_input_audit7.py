"""Regression tests of the bad-input audit 7 (scenario files): each bad input gives a clear
error naming the field and the reason, never a traceback from deep inside, silent garbage or
lost results.

* D1 a tiny gravity (1e-300 m/s^2): a ZeroDivisionError from the catenary of the tension
  estimate; now refused below schema.MIN_GRAVITY (0 stays valid: a scene without gravity), and
  the estimate survives an ArithmeticError;
* D2 a tiny density, mass, radius of gyration or inertia: a ZeroDivisionError from the kernels
  that lost the statics; now floors in the schema, and an ArithmeticError from the kernels is
  a SolverError that carries the results so far;
* D3 directions and axes of huge or tiny size: overflow in a sum of squares, or "the zero
  vector" for [1e-200, 0, 0]; now only zero is refused and extreme sizes are rescaled;
* D4 booleans inside lists and tables of numbers, silently read as 1 or 0;
* D5 YAML 1.1 base-60 numbers (``1:20`` read as 80);
* D7 a CSV vessel-motion file skipped the bounds of the inline table motion;
* D8 a tiny seabed stiffness: a floor, and non-finite start joints not blamed on ``elements``;
* D9 the RAO-file and override messages;
* the command line's last-resort handler of an unexpected exception (exit code 4).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim import ScenarioError, SolverError
from rfesim.cli import build_parser, main

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
RAO_FILE = SCENARIOS / "data" / "barge_100m_raos.json"


def example(name: str) -> dict:
    return json.loads((SCENARIOS / f"{name}.json").read_text())


def load(data: dict | str, overrides: dict | None = None, base_dir=SCENARIOS):
    data = example(data) if isinstance(data, str) else data
    return rfesim.load_scenario(data, overrides=overrides, base_dir=base_dir)


def errors_of(data: dict | str, overrides: dict | None = None, base_dir=SCENARIOS) -> dict[str, str]:
    with pytest.raises(ScenarioError) as info:
        load(data, overrides, base_dir)
    return dict(info.value.errors)


PENDULUM = {
    "environment": {"gravity": 9.81},
    "chains": {"pendulum": {
        "links": {"upper": {"rigid": True, "length": 1.0, "mass": 1.0}},
        "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper", "direction": [0, 0, -1],
                           "axis": [0, 1, 0], "initial": 0.3}}}},
    "analysis": {"statics": {"enabled": False},
                 "dynamics": {"duration": 0.1, "integrator": {"kind": "rk4", "time_step": 0.002}}},
}


# ----------------------------------------------------------------------------- D1 gravity

@pytest.mark.parametrize("g", [1e-300, 5e-324, 1e-12, 9.99e-4])
def test_tiny_gravity_is_refused_with_its_floor(g):
    reason = errors_of("catenary_riser", {"environment.gravity": g})["environment.gravity"]
    assert "m/s^2 is not a gravity: give 0 for none, or at least 0.001 m/s^2" in reason
    assert "check the units" in reason


@pytest.mark.parametrize("g", [0.0, 1e-3, 1.62])
def test_no_gravity_and_small_gravity_stay_valid(g):
    assert load("cantilever_pipe", {"environment.gravity": g}).environment.gravity == g


def test_tension_estimate_survives_an_arithmetic_error():
    # past the schema (an API user's model): the catenary of the tension estimate divides by
    # zero; the estimate falls back to the wet weight instead of a ZeroDivisionError traceback
    from rfesim.model.compile import compile_scenario
    sc = load("catenary_riser")
    sc.environment.gravity = 1e-300
    try:
        compile_scenario(sc)
    except ScenarioError:
        pass                       # a field-named refusal is fine; a ZeroDivisionError is not


# ----------------------------------------------------------------------------- D2 masses

FLOORS = [
    ("h1_riser_heave", "line_types.steel_pipe.density", 1e-300,
     "must be greater than or equal to 1 kg/m^3 (got 1e-300)"),
    ("h1_riser_heave", "line_types.steel_pipe.density", 0.5, "must be greater than or equal to 1 kg/m^3 (got 0.5)"),
    ("column_crane", "cranes.crane.payload.mass", 1e-300, "must be greater than or equal to 0.001 kg (got 1e-300)"),
    ("column_crane", "cranes.crane.payload.radius_of_gyration", 1e-300, "must be at least 0.001 m (a millimetre)"),
    ("column_crane", "cranes.crane.payload.radius_of_gyration.1", 1e-300, "must be at least 0.001 m (a millimetre)"),
]


@pytest.mark.parametrize("name, path, value, words", FLOORS, ids=[f"{c[1]}={c[2]:g}" for c in FLOORS])
def test_tiny_mass_like_values_are_refused(name, path, value, words):
    errors = errors_of(name, {path: value})
    assert path in errors, errors
    assert words in errors[path] and "check the units" in errors[path]


def test_tiny_mass_per_length_and_inertia_are_refused():
    data = example("column_crane")
    payload = data["cranes"]["crane"]["payload"]
    del payload["radius_of_gyration"]
    payload["inertia"] = [1e4, 1e-300, 1e4]
    assert "must be at least 1e-09 kg*m^2" in errors_of(data)["cranes.crane.payload.inertia.1"]
    cable = {"EA": 1.0e8, "EIy": 1.0e3, "mass_per_length": 1e-300}
    reason = errors_of("cantilever_pipe", {"line_types.pipe12": cable})["line_types.pipe12.mass_per_length"]
    assert "must be greater than or equal to 0.0001 kg/m (got 1e-300)" in reason


def test_tiny_chain_link_mass_is_refused():
    reason = errors_of(PENDULUM, {"chains.pendulum.links.upper.mass": 1e-300})["chains.pendulum.links.upper.mass"]
    assert "must be greater than or equal to 0.001 kg" in reason


def test_arithmetic_error_in_the_kernels_is_a_solver_error_with_the_statics(monkeypatch):
    # past the schema's floor: the kernels divide by zero at the first acceleration; the
    # converged statics go with the SolverError (before: a ZeroDivisionError, nothing kept).
    # The entry points validate an assigned value again (rfesim.api._scenario), so the value
    # gets past the floor only with that step skipped
    sc = load("h1_riser_heave", {"analysis.dynamics.duration": 0.1})
    sc.line_types["steel_pipe"].density = 1e-300
    monkeypatch.setattr(rfesim.api, "_scenario", lambda scenario: scenario)
    with pytest.raises(SolverError) as info:
        rfesim.simulate(sc)
    exc = info.value
    assert "arithmetic error in the solver (ZeroDivisionError" in str(exc)
    assert "check the scenario's values and their units" in str(exc)
    assert exc.results is not None and len(exc.results.time) == 1 and exc.results.status == 1
    assert exc.results.scenario_json


def test_arithmetic_error_during_the_run_keeps_the_results_so_far(monkeypatch):
    import rfesim.solvers.dynamics as dyn
    real = dyn.rk4_advance
    calls = []

    def failing(*args):
        calls.append(1)
        if len(calls) > 2:
            raise ZeroDivisionError("division by zero")
        return real(*args)

    monkeypatch.setattr(dyn, "rk4_advance", failing)
    sc = load("cantilever_pipe", {"analysis.statics.enabled": False, "analysis.modal": None,
                                  "analysis.dynamics": {"duration": 0.05, "output_interval": 0.01,
                                                        "integrator": {"kind": "rk4", "time_step": 1e-4}}})
    with pytest.raises(SolverError) as info:
        rfesim.simulate(sc)
    res = info.value.results
    assert "arithmetic error in the solver" in str(info.value)
    assert res is not None and res.status == 1 and len(res.time) == 3      # t = 0, 0.01, 0.02 s


# ----------------------------------------------------------------------------- D3 vectors

@pytest.mark.parametrize("vector, unit", [
    ([1e300, 0.0, 0.0], [1.0, 0.0, 0.0]),
    ([1e200, 0.0, -1e200], [1.0, 0.0, -1.0]),
    ([1e-200, 0.0, 0.0], [1.0, 0.0, 0.0]),
    ([0.0, 5e-324, 0.0], [0.0, 1.0, 0.0]),
])
def test_direction_of_extreme_size_is_rescaled(vector, unit):
    data = example("cantilever_pipe")
    data["lines"]["pipe"]["end_a"]["direction"] = vector
    sc = load(data)
    assert sc.lines["pipe"].end_a.direction == unit
    assert data["lines"]["pipe"]["end_a"]["direction"] == vector          # the caller's data untouched


def test_ordinary_directions_are_kept_as_given():
    data = example("cantilever_pipe")
    data["lines"]["pipe"]["end_a"]["direction"] = [3.0, 0.0, -4.0]
    assert load(data).lines["pipe"].end_a.direction == [3.0, 0.0, -4.0]


def test_chain_joint_direction_and_axis_of_extreme_size():
    sc = load(PENDULUM, {"chains.pendulum.joints.top.direction": [0, 0, -1e300],
                         "chains.pendulum.joints.top.axis": [0, 1e-300, 0]})
    joint = sc.chains["pendulum"].joints["top"]
    assert joint.direction == [0.0, 0.0, -1.0] and joint.axis == [0.0, 1.0, 0.0]


@pytest.mark.parametrize("path", ["lines.pipe.end_a.direction"])
def test_the_zero_vector_is_still_refused(path):
    assert "must not be the zero vector" in errors_of("cantilever_pipe", {path: [0, 0, 0]})[path]
    reason = errors_of(PENDULUM, {"chains.pendulum.joints.top.axis": [0, 0, 0]})["chains.pendulum.joints.top.axis"]
    assert "must not be the zero vector" in reason


def test_straight_start_of_a_huge_direction():
    from rfesim.model.compile import _straight
    curve = _straight(np.zeros(3), np.array([1e300, 0.0, 0.0]), 10.0)
    assert np.allclose(curve.X[-1], [10.0, 0.0, 0.0])


# ----------------------------------------------------------------------------- D4 booleans

def _rao_file_with_a_boolean(tmp_path: Path) -> dict:
    table = json.loads(RAO_FILE.read_text())
    table["heave"]["amplitude"][3][2] = True
    (tmp_path / "raos.json").write_text(json.dumps(table))
    return {"vessels.fpso.motion": {"kind": "rao", "file": str(tmp_path / "raos.json")}}


BOOLEANS = [
    ("column_crane", {"cranes.crane.slewing_deg": [[0, 80], [True, 90]]}, "cranes.crane.slewing_deg.1.0", "true"),
    ("column_crane", {"cranes.crane.luffing_deg": [[0, 45], [10, False]]}, "cranes.crane.luffing_deg.1.1", "false"),
    ("a_frame", {"cranes.aframe.cylinder.base": [True, False]}, "cranes.aframe.cylinder.base.0", "true"),
    ("a_frame", {"cranes.aframe.tilt_deg": [[0, -25], [True, 35]]}, "cranes.aframe.tilt_deg.1.0", "true"),
    ("riser_irregular_sea", {"vessels.fpso.motion.raos.periods.2": True}, "vessels.fpso.motion.raos.periods.2",
     "true"),
    ("riser_irregular_sea", {"vessels.fpso.motion.raos.headings_deg.0": False},
     "vessels.fpso.motion.raos.headings_deg.0", "false"),
    ("riser_irregular_sea", {"vessels.fpso.motion.raos.heave.amplitude.3.2": True},
     "vessels.fpso.motion.raos.heave.amplitude.3.2", "true"),
    ("riser_irregular_sea", {"vessels.fpso.motion.raos.heave.phase_deg.0.0": True},
     "vessels.fpso.motion.raos.heave.phase_deg.0.0", "true"),
    ("catenary_riser", {"vessels.fpso.motion": {"kind": "table", "interpolation": "linear",
                                                "rows": [[0, 0, 0, 0, 0, 0, 0], [1, 0, 0, True, 0, 0, 0]]}},
     "vessels.fpso.motion.rows.1.3", "true"),
    (PENDULUM, {"chains.pendulum.joints.top.initial": [True]}, "chains.pendulum.joints.top.initial.0", "true"),
    (PENDULUM, {"chains.pendulum.joints.top.initial_rate": [False]}, "chains.pendulum.joints.top.initial_rate.0",
     "false"),
    (PENDULUM, {"chains.pendulum.joints.top.drive": {"kind": "prescribed", "motion": {
        "kind": "table", "rows": [[0, 0], [1, 0.1], [2, True], [3, 0.3]]}}},
     "chains.pendulum.joints.top.drive.motion.rows.2.1", "true"),
]


@pytest.mark.parametrize("name, overrides, path, word", BOOLEANS, ids=[c[2] for c in BOOLEANS])
def test_boolean_in_a_list_of_numbers_is_refused(name, overrides, path, word):
    errors = errors_of(name, overrides)
    assert errors.get(path) == f"must be a number, not the boolean {word}", errors


def test_boolean_in_an_rao_file_is_refused(tmp_path):
    reason = errors_of("riser_irregular_sea", _rao_file_with_a_boolean(tmp_path))["vessels.fpso.motion.file"]
    assert reason == f"{tmp_path / 'raos.json'}: heave.amplitude.3.2: must be a number, not the boolean true"


def test_booleans_stay_valid_where_the_field_is_a_boolean():
    sc = load("riser_irregular_sea", {"vessels.fpso.motion.raos.symmetric": True})
    assert sc.vessels["fpso"].motion.raos.symmetric is True


# ----------------------------------------------------------------------------- D5 YAML base 60

def _yaml_riser(elements: str, length: str = "600.0") -> str:
    data = example("catenary_riser")
    data["lines"]["riser"]["elements"] = "@E"
    data["lines"]["riser"]["length"] = "@L"
    import yaml
    return yaml.safe_dump(data, sort_keys=False).replace("'@E'", elements).replace("'@L'", length)


@pytest.mark.parametrize("elements, length, path, got", [
    ("1:20", "600.0", "lines.riser.elements", "'1:20'"),
    ("120", "10:00.0", "lines.riser.length", "'10:00.0'"),
])
def test_yaml_base_60_numbers_are_not_numbers(elements, length, path, got):
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(_yaml_riser(elements, length))
    reason = dict(info.value.errors)[path]
    assert got in reason and "base-60" in reason


def test_yaml_numbers_still_read():
    from rfesim.scenario.load import parse_text
    assert parse_text("a: 120\nb: 2.1e11\nc: -3.5\nd: 1_000\ne: 0x10\nf: '1:20'\n", "yaml") == \
        {"a": 120, "b": 2.1e11, "c": -3.5, "d": 1000, "e": 16, "f": "1:20"}
    assert rfesim.load_scenario(_yaml_riser("120")).lines["riser"].elements == 120


# ----------------------------------------------------------------------------- D7 CSV motion

CSV_HEADER = "t,surge,sway,heave,roll,pitch,yaw\n"


def _csv(tmp_path: Path, rows: list[str]) -> dict:
    (tmp_path / "motion.csv").write_text(CSV_HEADER + "\n".join(rows) + "\n")
    return {"vessels.fpso.motion": {"kind": "csv", "file": "motion.csv", "interpolation": "linear"}}


@pytest.mark.parametrize("rows, words", [
    (["0,0,0,0,0,0,0", "1,0,0,0.5,0,0,0", "1e300,0,0,1,0,0,0"],
     "line 4, column t: must lie between -10000000 and 10000000 s (got 1e+300)"),
    (["0,0,0,0,0,0,0", "1,0,0,1e300,0,0,0"], "line 3, column heave: must lie between -10000000 and 10000000 m"),
    (["0,0,0,0,0,0,2e6", "1,0,0,0,0,0,0"], "line 2, column yaw: must lie between -1000000 and 1000000 deg"),
    (["0,0,0,0,0,0,0", "4,0,0,0,0,0,0", "4.0000000001,0,0,0,0,0,0"],
     "line 4, column t: 4.0000000001 s is 1e-10 s after the row before: rows closer than 1e-06 s"),
])
def test_csv_motion_has_the_bounds_of_the_inline_table(tmp_path, rows, words):
    reason = errors_of("catenary_riser", _csv(tmp_path, rows), base_dir=tmp_path)["vessels.fpso.motion.file"]
    assert reason.startswith(f"{tmp_path / 'motion.csv'}, ") and words in reason, reason


def test_csv_motion_within_the_bounds_is_read(tmp_path):
    sc = load("catenary_riser", _csv(tmp_path, ["0,0,0,0,0,0,0", "1,0,0,0.5,0,0,0"]), base_dir=tmp_path)
    assert sc.vessels["fpso"].motion.rows().shape == (2, 7)


# ----------------------------------------------------------------------------- D8 seabed stiffness

@pytest.mark.parametrize("k", [1e-300, 1e-20, 0.5])
def test_tiny_seabed_stiffness_is_refused(k):
    reason = errors_of("catenary_riser", {"environment.seabed.normal_stiffness": k})
    reason = reason["environment.seabed.normal_stiffness"]
    assert "must be greater than or equal to 1 N/m/m" in reason and "sink" in reason


@pytest.mark.filterwarnings("ignore::RuntimeWarning")         # the overflows this test provokes
def test_non_finite_start_joints_are_not_blamed_on_the_elements():
    from rfesim.model.compile import compile_scenario
    sc = load("catenary_riser")
    sc.environment.seabed.normal_stiffness = 1e-300       # past the schema (an API user's model)
    with pytest.raises(ScenarioError) as info:
        compile_scenario(sc)
    errors = dict(info.value.errors)
    assert "lines.riser.elements" not in errors, errors
    assert "joints at non-finite positions" in errors["lines.riser"]
    assert "environment.seabed.normal_stiffness" in errors["lines.riser"]


# ----------------------------------------------------------------------------- D9 messages

def _rao_file(tmp_path: Path, content: str | bytes) -> dict:
    path = tmp_path / "raos.json"
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    return {"vessels.fpso.motion": {"kind": "rao", "file": str(path)}}


@pytest.mark.parametrize("content, words", [
    ("[1, 2, 3]", "raos.json: the RAO table must be a mapping (keys and values), got a list of 3"),
    ("@typo", "raos.json: heavee: unknown key (did you mean 'heave'?)"),
    ("@nan", "raos.json: heave.amplitude.0.0: must be a finite number, got nan"),
    ("", "raos.json: the RAO table file is empty"),
    (b"\xff\xfe\x00garbage", "raos.json is not UTF-8 text (byte 0): an RAO table is a JSON or YAML text file"),
])
def test_rao_file_errors_are_worded_as_the_scenario_errors(tmp_path, content, words):
    if content in ("@typo", "@nan"):
        table = json.loads(RAO_FILE.read_text())
        if content == "@typo":
            table["heavee"] = table.pop("heave")
        else:
            table["heave"]["amplitude"][0][0] = float("nan")        # json writes NaN
        content = json.dumps(table)
    reason = errors_of("riser_irregular_sea", _rao_file(tmp_path, content))["vessels.fpso.motion.file"]
    assert words in reason, reason
    assert "Input should" not in reason and "RaoTable" not in reason and "scenario" not in reason


@pytest.mark.parametrize("kind, what", [("rao", "the RAO table"), ("csv", "the CSV file of the vessel motion")])
def test_empty_file_name_is_named(kind, what):
    motion = {"kind": kind, "file": ""} if kind == "rao" else {"kind": "csv", "file": "", "interpolation": "linear"}
    reason = errors_of("riser_irregular_sea", {"vessels.fpso.motion": motion})["vessels.fpso.motion.file"]
    assert reason == f"the file name is empty: give the path of {what}" + (" (a JSON or YAML file)" if kind == "rao"
                                                                             else "")


def test_overrides_as_a_list_are_refused():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(str(SCENARIOS / "cantilever_pipe.json"), overrides=[("lines.pipe.elements", 10)])
    assert info.value.errors == [("", "overrides must be a mapping of dotted field paths to values, such as "
                                      "{'lines.pipe.elements': 40}, got a list of 1 (list)")]


def test_override_key_that_is_not_text_is_named():
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(str(SCENARIOS / "cantilever_pipe.json"), overrides={1: 1})
    (path, reason), = info.value.errors
    assert path == "1" and reason.startswith("an override's key must be text, a dotted field path") \
        and "got 1 (int)" in reason


def test_yaml_null_as_a_name_is_named_null():
    text = _yaml_riser("120").replace("\n  riser:\n", "\n  null:\n", 1)
    with pytest.raises(ScenarioError) as info:
        rfesim.load_scenario(text)
    assert dict(info.value.errors)["lines.null"] == "names must be text (strings), got null (quote it: 'null')"


# ----------------------------------------------------------------------------- the command line

def test_unexpected_exception_is_one_line_and_exit_code_4(monkeypatch, capsys):
    import rfesim.cli as cli

    def broken(args):
        raise RuntimeError("boom")

    monkeypatch.delenv("RFESIM_DEBUG", raising=False)
    monkeypatch.setattr(cli, "cmd_check", broken)
    assert main(["check", str(SCENARIOS / "cantilever_pipe.json")]) == cli.EXIT_INTERNAL == 4
    err = capsys.readouterr().err
    assert err == ("rfesim: internal error: RuntimeError: boom (a bug; please report it with the scenario; set "
                   "RFESIM_DEBUG=1 for the traceback)\n")


def test_rfesim_debug_shows_the_traceback(monkeypatch):
    import rfesim.cli as cli

    def broken(args):
        raise RuntimeError("boom")

    monkeypatch.setenv("RFESIM_DEBUG", "1")
    monkeypatch.setattr(cli, "cmd_check", broken)
    with pytest.raises(RuntimeError, match="boom"):
        main(["check", str(SCENARIOS / "cantilever_pipe.json")])


@pytest.mark.parametrize("exc, code", [(KeyboardInterrupt(), 130), (SystemExit(7), None)])
def test_interrupts_and_exits_are_not_internal_errors(monkeypatch, capsys, exc, code):
    import rfesim.cli as cli

    def stop(args):
        raise exc

    monkeypatch.delenv("RFESIM_DEBUG", raising=False)
    monkeypatch.setattr(cli, "cmd_check", stop)
    if code is None:
        with pytest.raises(SystemExit):
            main(["check", str(SCENARIOS / "cantilever_pipe.json")])
    else:
        assert main(["check", str(SCENARIOS / "cantilever_pipe.json")]) == code
    assert "internal error" not in capsys.readouterr().err


def test_exit_code_4_is_documented():
    assert "4 internal error" in build_parser().epilog
    readme = (SCENARIOS.parent / "README.md").read_text()
    assert "4 internal\nerror" in readme or "4 internal error" in readme
