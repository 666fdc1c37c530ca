"""The command line and the load-case sweep: interrupted runs and sweeps keep what was
computed, the sweep's summary of pipelay lines, its checks of -o, --vary and --scheduler,
data files relative to the scenario, full precision in the CSV, names the results file
cannot hold (seconds: statics-only or 2 s runs, no worker processes)."""
from __future__ import annotations

import copy
import csv
import json
import shutil
import signal
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.cli import main
from test_cli import CANTILEVER      # the CLI tests' 10 m cantilever (pytest puts tests/ on sys.path)

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


@pytest.fixture
def good(tmp_path) -> Path:
    path = tmp_path / "cantilever.json"
    path.write_text(json.dumps(CANTILEVER), encoding="utf-8")
    return path


# --------------------------------------------------------------------------- rfesim run: Ctrl-C

class _InterruptAt:
    """A progress callback that presses Ctrl-C once the run passes ``t``."""

    def __init__(self, t):
        self.t = t

    def __call__(self, fraction, t):
        if t >= self.t:
            raise KeyboardInterrupt

    def close(self):
        pass


def test_run_interrupted_writes_the_results_so_far(good, tmp_path, monkeypatch, capsys):
    import rfesim.cli as cli

    monkeypatch.setattr(cli, "_progress_bar", lambda args: _InterruptAt(0.5))
    out = tmp_path / "interrupted.nc"
    assert main(["run", str(good), "-o", str(out)]) == 130
    err = capsys.readouterr().err
    assert "interrupted at t = " in err and "partial results" in err and str(out) in err
    res = rfesim.open_results(out)
    assert res.status == 2
    assert res.message.startswith(f"interrupted at t = {res.time[-1]:.6g} s")
    assert 0.5 <= res.time[-1] < 2.0 and res.time[0] == 0.0
    assert res.line("pipe").position.shape[0] == len(res.time)


def test_simulate_attaches_the_results_to_the_interruption(good):
    with pytest.raises(KeyboardInterrupt) as info:
        rfesim.simulate(good, progress=_InterruptAt(0.5))
    res = info.value.results
    assert res.status == 2 and 0.5 <= res.time[-1] < 2.0 and res.scenario_json


# --------------------------------------------------------------------------- results file

def test_write_failure_is_an_error_message_not_a_traceback(tmp_path):
    from rfesim.cli import CliError, _write

    class Res:
        def to_netcdf(self, path):
            raise ValueError("Unable to synchronously create group (name already exists)")

    with pytest.raises(CliError, match="could not write the results to .*ValueError.*lost"):
        _write(Res(), tmp_path / "x.nc")


@pytest.mark.parametrize("name", [".", ".."])
def test_dot_names_are_refused(good, tmp_path, capsys, name):
    data = copy.deepcopy(CANTILEVER)
    data["lines"][name] = data["lines"].pop("pipe")
    path = tmp_path / "dot.json"
    path.write_text(json.dumps(data))
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert f"lines.{name}: bad name '{name}'" in err
    data["vessels"] = {name: {"position": [0, 0, 0]}}
    data["lines"]["pipe"] = data["lines"].pop(name)
    with pytest.raises(rfesim.ScenarioError, match=f"vessels.{re_escape(name)}: bad name"):
        rfesim.load_scenario(data)


def re_escape(text):
    import re
    return re.escape(text)


# --------------------------------------------------------------------------- output paths

def test_output_folder_with_a_trailing_slash_and_plot_without_extension(good, tmp_path, capsys):
    missing = str(tmp_path / "newdir") + "/"
    assert main(["run", str(good), "-o", missing, "--no-progress"]) == 1
    assert f"the output folder does not exist: {missing}" in capsys.readouterr().err
    assert not (tmp_path / "newdir").exists()
    assert main(["run", str(good), "-o", str(tmp_path) + "/", "--no-progress"]) == 1
    assert "the output path is a folder" in capsys.readouterr().err
    out = tmp_path / "o.nc"
    assert main(["run", str(good), "-o", str(out), "--plot", str(tmp_path / "noext"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "--plot" in err and "give the image format as the file's extension" in err and ".png" in err
    assert not out.exists() and not (tmp_path / "noext.png").exists()


def test_sweep_output_cannot_overwrite_the_scenario(good, capsys):
    from rfesim.sweep import main as sweep_main

    before = good.read_bytes()
    assert sweep_main([str(good), "--vary", "lines.pipe.elements=10", "-o", str(good)]) == 1
    assert "would overwrite the scenario" in capsys.readouterr().err
    assert good.read_bytes() == before


def test_run_output_does_not_replace_another_scenario_or_a_foreign_file(good, tmp_path, capsys):
    """`rfesim run a.json -o b.json` used to turn the scenario b.json into HDF5 without a word;
    a results file replaces only an earlier results file, and no output replaces a JSON/YAML."""
    other = tmp_path / "b.json"
    other.write_text(good.read_text())
    notes = tmp_path / "notes.txt"
    notes.write_text("load case log\n")
    assert main(["run", str(good), "-o", str(other), "--no-progress"]) == 1
    assert "b.json exists and is a JSON file (a scenario?)" in capsys.readouterr().err
    assert other.read_text() == good.read_text()
    assert main(["statics", str(good), "-o", str(notes)]) == 1
    assert "notes.txt exists and is not a results file" in capsys.readouterr().err
    assert notes.read_text() == "load case log\n"
    from rfesim.sweep import main as sweep_main
    assert sweep_main([str(good), "--vary", "lines.pipe.elements=10", "-o", str(other)]) == 1
    assert other.read_text() == good.read_text()
    out = tmp_path / "r.nc"            # an earlier results file is replaced, as before
    assert main(["statics", str(good), "-o", str(out)]) == 0
    first = out.stat().st_mtime_ns
    assert main(["statics", str(good), "-o", str(out)]) == 0
    assert out.stat().st_mtime_ns >= first and out.read_bytes()[:8] == b"\x89HDF\r\n\x1a\n"


# --------------------------------------------------------------------------- sweep: interruption

def _statics_only(tmp_path) -> Path:
    data = copy.deepcopy(CANTILEVER)
    data["analysis"]["dynamics"]["enabled"] = False
    path = tmp_path / "statics.json"
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_interrupted_sweep_keeps_the_finished_rows(tmp_path, monkeypatch, capsys, how):
    import rfesim.sweep as sweep

    def interrupted_run(cases, executor=None, *, workers=None, on_row=None):
        # case 1 finishes, case 0 lost its worker (no wall time), then the sweep is stopped
        on_row({"case": 1, **cases[1][0], "max_top_tension": 1234.5678901234567, "wall_time": 0.25,
                "status": "done", "message": "finished"})
        on_row({"case": 0, **cases[0][0], "wall_time": None, "status": "failed",
                "message": sweep.LOST_WORKER})
        if how == "sigterm":
            signal.raise_signal(signal.SIGTERM)      # the batch system: sigterm_as_interrupt
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep, "run_cases", interrupted_run)
    before = signal.getsignal(signal.SIGTERM)
    out = tmp_path / "table.csv"
    scenario = _statics_only(tmp_path)
    assert sweep.main([str(scenario), "--vary", "lines.pipe.elements=10,12,14", "-o", str(out)]) == 130
    assert signal.getsignal(signal.SIGTERM) == before            # the caller's handler again
    err = capsys.readouterr().err
    assert "interrupted: 2 of 3 cases done" in err and str(out) in err
    assert "case 1: done (0.25 s)" in err
    assert f"case 0: failed: {sweep.LOST_WORKER}" in err and "( s)" not in err
    rows = list(csv.DictReader(out.open()))
    assert [(r["case"], r["lines.pipe.elements"], r["status"]) for r in rows] == [("1", "12", "done"),
                                                                                  ("0", "10", "failed")]
    assert float(rows[0]["max_top_tension"]) == 1234.5678901234567


# --------------------------------------------------------------------------- sweep: --vary checks

def test_a_misspelled_vary_name_is_refused_with_a_suggestion(tmp_path, capsys):
    from rfesim.sweep import main as sweep_main

    scenario = tmp_path / "riser.json"
    shutil.copy(SCENARIOS / "catenary_riser.json", scenario)
    vessel = next(iter(json.loads(scenario.read_text())["vessels"]))
    assert sweep_main([str(scenario), "--vary", f"vessels.{vessel}o.position=[0,0,0],[1,0,0]"]) == 1
    err = capsys.readouterr().err
    assert f"vessels.{vessel}o.position:" in err and f"did you mean 'vessels.{vessel}'?" in err
    assert "load cases on" not in err                  # refused before anything runs


def test_vary_paths_into_template_objects_are_allowed():
    from rfesim.errors import ScenarioError
    from rfesim.sweep import _base_dict, check_vary_paths

    lay = _base_dict(SCENARIOS / "j_lay.json")
    check_vary_paths(lay, {"pipelay.lay.tower_angle_deg": [80.0, 85.0],
                           "vessels.lay_vessel.motion.heave.amplitude": [1.0], "lines.lay.elements": [100]})
    crane = _base_dict(SCENARIOS / "column_crane.json")
    check_vary_paths(crane, {"cranes.crane.payload.mass": [5000.0], "bodies.crane_payload.mass": [5000.0]})
    check_vary_paths(crane, {"vessels.tug": [{"position": [0, 0, 0]}]})        # a whole new entry, on purpose
    with pytest.raises(ScenarioError, match=r"cranes.crane2.payload.mass: .*did you mean 'cranes.crane'"):
        check_vary_paths(crane, {"cranes.crane2.payload.mass": [5000.0]})


def test_varied_data_files_are_relative_to_the_scenario(tmp_path, monkeypatch, capsys):
    from rfesim.sweep import build_cases

    folder = tmp_path / "project"
    (folder / "data").mkdir(parents=True)
    shutil.copy(SCENARIOS / "s_lay_template.json", folder / "lay.json")
    shutil.copy(SCENARIOS / "data" / "barge_100m_raos.json", folder / "data" / "raos.json")
    shutil.copy(SCENARIOS / "data" / "barge_100m_raos.json", folder / "data" / "barge_100m_raos.json")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    cases = build_cases(str(folder / "lay.json"), {"vessels.barge.motion.file": ["data/raos.json"]})
    assert cases[0][1]["vessels"]["barge"]["motion"]["file"] == str((folder / "data" / "raos.json").resolve())
    # `rfesim check --expand` prints the data files as absolute paths: the output works saved anywhere
    assert main(["check", str(folder / "lay.json"), "--expand"]) == 0
    expanded = json.loads(capsys.readouterr().out)
    assert expanded["vessels"]["barge"]["motion"]["file"] == str((folder / "data" / "barge_100m_raos.json").resolve())
    saved = elsewhere / "expanded.json"
    saved.write_text(json.dumps(expanded))
    assert main(["check", str(saved)]) == 0


def test_bad_scheduler_address_names_the_option(good, capsys):
    pytest.importorskip("distributed")
    from rfesim.sweep import main as sweep_main

    for address in ("notanaddress", "foo://1.2.3.4:80"):
        assert sweep_main([str(good), "--vary", "lines.pipe.elements=10", "--scheduler", address]) == 2
        err = capsys.readouterr().err
        assert f"--scheduler '{address}' is not a Dask scheduler address" in err and "Traceback" not in err


# --------------------------------------------------------------------------- sweep: table

def test_csv_has_full_precision_and_the_console_tells_the_cases_apart(tmp_path):
    from rfesim.sweep import columns, format_table, write_csv

    vary = {"environment.water.density": [1025.0001, 1025.0004]}
    rows = [{"case": i, "environment.water.density": v, "max_top_tension": 178409.5044778198 + i,
             "wall_time": 1.5, "status": "done", "message": "finished"} for i, v in enumerate(vary[next(iter(vary))])]
    cols = columns(vary)
    write_csv(rows, cols, tmp_path / "t.csv")
    back = list(csv.DictReader((tmp_path / "t.csv").open()))
    assert [float(r["environment.water.density"]) for r in back] == [1025.0001, 1025.0004]
    assert float(back[0]["max_top_tension"]) == 178409.5044778198
    table = format_table(rows, cols)
    assert "1025.0001" in table and "1025.0004" in table
    assert "178410" in table                  # summary columns stay short on the console


# --------------------------------------------------------------------------- summary: pipelay lines

def test_pipelay_top_tension_is_the_tensioner_and_touchdown_the_results():
    from rfesim.cli import _line_extremes
    from rfesim.lay_results import lay_summary
    from rfesim.sweep import _summary, line_top_tension

    res = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "s_lay_template.json",
                                               overrides={"analysis.dynamics.enabled": False}))
    lay = res.line("lay")
    summary, where = _summary(res)
    held = float(np.max(lay_summary(res, "lay")["top_tension"]))
    assert where == "lay tensioner"
    assert summary["max_top_tension"] == pytest.approx(held)
    assert summary["max_top_tension"] > 1.2 * float(lay.top_tension.max())     # not the seabed pin at end B
    assert summary["touchdown_min"] == pytest.approx(float(np.nanmin(lay.touchdown_arc_length)))
    assert summary["touchdown_max"] < lay.arc_length[-1] - 10.0                  # not end B's element
    assert "tensioner" in "\n".join(_line_extremes(res))

    riser = rfesim.simulate(rfesim.load_scenario(SCENARIOS / "catenary_riser.json",
                                                 overrides={"analysis.dynamics.enabled": False}))
    top, end = line_top_tension(riser, "riser")
    assert end == "end B"
    np.testing.assert_array_equal(top, riser.line("riser").top_tension)
    summary, where = _summary(riser)
    assert where == "riser end B"
    assert summary["touchdown_max"] == pytest.approx(float(riser.line("riser").touchdown_arc_length[0]))


def test_a_varied_path_that_would_replace_an_override_is_refused(good):
    """The varied values go on top of the overrides: varying analysis.dynamics (or the very
    path) would silently drop an override of analysis.dynamics.duration in every case; an
    override above a varied path is fine (the varied value goes inside it, in each case's own
    copy: before, every case shared the override's object and all got the last value)."""
    from rfesim.sweep import build_cases

    for vary in ({"analysis.dynamics": [{"duration": 0.3}]}, {"analysis.dynamics.duration": [0.3, 0.4]}):
        with pytest.raises(rfesim.ScenarioError) as err:
            build_cases(good, vary, overrides={"analysis.dynamics.duration": 0.5})
        ((field, reason),) = err.value.errors
        assert field == next(iter(vary)) and "the override 'analysis.dynamics.duration'" in reason
    cases = build_cases(good, {"analysis.dynamics.duration": [0.3, 0.4]},
                        overrides={"analysis.dynamics": {"duration": 1.0, "output_interval": 0.1}})
    assert [c[1]["analysis"]["dynamics"]["duration"] for c in cases] == [0.3, 0.4]
    assert all(c[1]["analysis"]["dynamics"]["output_interval"] == 0.1 for c in cases)


def test_load_scenario_overrides_refuse_a_misspelled_entry():
    # rfesim.load_scenario(overrides=...) and apply_overrides: the same check as --vary
    import rfesim
    from rfesim.errors import ScenarioError

    path = SCENARIOS / "catenary_riser.json"
    vessel = next(iter(json.loads(path.read_text())["vessels"]))
    with pytest.raises(ScenarioError, match=rf"vessels.{vessel}o.position: .*did you mean 'vessels.{vessel}'\?"):
        rfesim.load_scenario(path, overrides={f"vessels.{vessel}o.position": [20.0, 0.0, 0.0]})
    sc = rfesim.load_scenario(path, overrides={f"vessels.{vessel}.position": [20.0, 0.0, 0.0]})
    assert list(sc.vessels[vessel].position) == [20.0, 0.0, 0.0]
    # a whole new entry is added on purpose
    sc = rfesim.load_scenario(path, overrides={"vessels.tug": {"position": [0.0, 50.0, 0.0]}})
    assert set(sc.vessels) == {vessel, "tug"}
