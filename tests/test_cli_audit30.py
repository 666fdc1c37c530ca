"""Audit 30, the command line: a second Ctrl-C while `rfesim run` writes the results of an
interrupted run, the plot of an interrupted run, `rfesim check` of a run whose output would
be too large, the sweep's top tension of a crane, `rfesim bench --help`."""
from __future__ import annotations

import copy
import json
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import rfesim
from rfesim.cli import main

import scenes

# `rfesim run` as the console script runs it (main() with sys.argv), with a results write
# that lasts a second (and says when it starts), so that a signal can be sent inside it
_SLOW_WRITE = """
import sys, time
import rfesim.results as r
_write = r._write_netcdf
def slow(res, path):
    sys.stderr.write("<writing>\\n"); sys.stderr.flush(); time.sleep(1.0); _write(res, path)
r._write_netcdf = slow
from rfesim.cli import main
sys.exit(main())
"""


class _Cli:
    """``rfesim run`` in a subprocess whose stderr is collected as it comes."""

    def __init__(self, args, code="from rfesim.cli import main; import sys; sys.exit(main())"):
        self.proc = subprocess.Popen([sys.executable, "-c", code, *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE)
        self.err = b""
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        while True:
            chunk = self.proc.stderr.read1(4096)
            if not chunk:
                return
            self.err += chunk

    def wait_for(self, text: bytes, timeout: float = 300.0):
        t0 = time.monotonic()
        while text not in self.err:
            assert self.proc.poll() is None or text in self.err, self.err.decode()[-2000:]
            assert time.monotonic() - t0 < timeout, f"no {text!r} in: {self.err.decode()[-2000:]}"
            time.sleep(0.01)

    def signal(self, sig):
        self.proc.send_signal(sig)      # nothing when it has ended

    def finish(self, timeout: float = 60.0) -> int:
        rc = self.proc.wait(timeout)
        self._reader.join(5)
        return rc


@pytest.fixture
def long_riser(tmp_path):
    """The tiny riser for a day of outputs every second: a run that lasts until interrupted."""
    sc = copy.deepcopy(scenes.RISER)
    sc["analysis"]["dynamics"].update(duration=86400.0, output_interval=1.0)
    path = tmp_path / "riser.json"
    path.write_text(json.dumps(sc), encoding="utf-8")
    return path


def test_second_ctrl_c_while_writing_the_partial_results_does_not_lose_them(long_riser, tmp_path):
    out = tmp_path / "part.nc"
    cli = _Cli(["run", str(long_riser), "-o", str(out), "--progress"], code=_SLOW_WRITE)
    cli.wait_for(b"%  t = ")                 # the progress bar: stepping
    cli.signal(signal.SIGINT)
    cli.wait_for(b"<writing>")
    cli.signal(signal.SIGINT)                # inside the write: used to remove the half-written file
    time.sleep(0.1)
    cli.signal(signal.SIGTERM)
    cli.wait_for(b"written to")
    cli.signal(signal.SIGINT)                # while the process ends: used to give exit code -2
    rc = cli.finish()
    err = cli.err.decode()
    assert rc == 130, err
    assert err.count(f"still writing the results to {out}, please wait") == 1, err
    assert "partial results (" in err
    res = rfesim.open_results(out)
    assert res.status == 2 and res.message.startswith("interrupted at t = ") and len(res.time) > 1
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []     # no temp file left


def test_ctrl_c_while_writing_the_results_of_a_finished_run_waits_for_them(tmp_path):
    path = tmp_path / "riser.json"
    path.write_text(json.dumps(scenes.RISER), encoding="utf-8")
    out = tmp_path / "full.nc"
    cli = _Cli(["run", str(path), "-o", str(out)], code=_SLOW_WRITE)
    cli.wait_for(b"<writing>")
    cli.signal(signal.SIGINT)
    rc = cli.finish()
    err = cli.err.decode()
    assert rc == 130, err
    assert f"still writing the results to {out}, please wait" in err
    assert f"interrupted after the run had ended: its results were written to {out} first" in err
    res = rfesim.open_results(out)
    assert res.status == 0 and res.time[-1] == pytest.approx(1.0)


def test_interrupted_run_writes_the_plot_of_the_partial_results(long_riser, tmp_path):
    out, png = tmp_path / "part.nc", tmp_path / "part.png"
    cli = _Cli(["run", str(long_riser), "-o", str(out), "--plot", str(png), "--progress"])
    cli.wait_for(b"%  t = ")
    cli.signal(signal.SIGINT)
    rc = cli.finish()
    err = cli.err.decode()
    assert rc == 130, err
    assert out.is_file() and png.is_file() and png.stat().st_size > 1000, err
    assert f"plot of the partial results written to {png}" in err


# --------------------------------------------------------------------------- rfesim check: output size

def test_check_refuses_what_run_refuses_for_its_output_size(tmp_path, monkeypatch, capsys):
    import rfesim.solvers.dynamics as dynamics

    # a machine of 1 GiB: 1e6 output times of the tiny riser (about 2.6 GB) do not fit
    monkeypatch.setattr(dynamics, "_memory_bytes", lambda: float(2**30))
    sc = copy.deepcopy(scenes.RISER)
    sc["analysis"]["dynamics"].update(duration=1.0e5, output_interval=0.1)
    path = tmp_path / "huge.json"
    path.write_text(json.dumps(sc), encoding="utf-8")
    assert main(["check", str(path)]) == 1
    out, err = capsys.readouterr()
    assert "OK" not in out
    assert "analysis.dynamics.output_interval: 1e+06 output times would store about" in err
    assert main(["run", str(path), "-o", str(tmp_path / "huge.nc")]) == 1
    assert capsys.readouterr().err.splitlines()[-1] == err.splitlines()[-1]     # the same message
    sc["analysis"]["dynamics"].update(output_interval=10.0)    # 1e4 output times: fine
    path.write_text(json.dumps(sc), encoding="utf-8")
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out.startswith("OK: tiny riser")


# --------------------------------------------------------------------------- sweep: a crane's top tension

def _short_crane() -> dict:
    """A column crane (template) on a heaving barge holding a 10 t module 3 m above the water:
    4 s, outputs every 0.1 s. Its pedestal's base force (about 0.7 MN) is the largest force
    at a line end, and the boom tip's end B force is just above the rope's."""
    return {
        "schema_version": 1, "name": "short crane",
        "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 100.0}},
        "vessels": {"barge": {"motion": {"kind": "harmonic", "heave": {"amplitude": 0.5, "period": 4.0},
                                         "ramp_duration": 1.0}}},
        "cranes": {"crane": {
            "type": "column", "vessel": "barge", "position": [0.0, 12.0, 4.0],
            "pedestal": {"length": 12.0, "outer_diameter": 2.5, "wall_thickness": 0.04, "elements": 2},
            "boom": {"length": 30.0, "outer_diameter": 1.0, "wall_thickness": 0.025, "elements": 4},
            "slewing_deg": 90.0, "luffing_deg": 45.0,
            "rope": {"length": 32.0, "diameter": 0.036, "elements": 8},
            "payload": {"mass": 10000.0, "radius_of_gyration": [1.1, 1.1, 1.2], "volume": 4.0, "height": 2.0,
                        "drag": {"cd": [1.2, 1.2, 2.0], "area": [6.0, 6.0, 9.0]},
                        "added_mass": {"mass": [4000.0, 4000.0, 12000.0]}}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": 4.0, "output_interval": 0.1,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8}}}}


def test_sweep_top_tension_of_a_crane_is_its_hoist_rope():
    from rfesim.crane_results import crane_summary
    from rfesim.sweep import run_case

    case = _short_crane()
    row = run_case(copy.deepcopy(case))
    assert row["status"] == "done", row["message"]
    assert row["top_tension_at"] == "crane_rope sheave"
    cs = crane_summary(rfesim.simulate(rfesim.load_scenario(case)), "crane")
    assert row["daf"] == pytest.approx(cs["daf"], rel=1e-12)
    assert row["max_top_tension"] == pytest.approx(float(np.max(cs["rope_tension"])), rel=1e-12)
    assert 1.0 < row["daf"] < 3.0
    # tension columns cover the rope, not the pedestal and boom in compression; the bending
    # moment covers the structure (the boom's root moment, not the rope's nothing)
    res = rfesim.simulate(rfesim.load_scenario(case))
    rope = np.asarray(res.line("crane_rope").tension)
    assert row["min_tension"] == pytest.approx(float(rope.min()), rel=1e-12) and row["min_tension"] > 0.0
    assert row["max_tension"] == pytest.approx(float(rope.max()), rel=1e-12)
    # (a crane's structure lines with their end moments, rfesim.crane_results.structure_loads: this
    # crane gives no cylinder, so the model's, the pedestal's foot moment above its first SDE's)
    from rfesim.crane_results import structure_loads
    members = structure_loads(res, case)
    assert row["max_bend_moment"] == pytest.approx(
        max(float(np.max(members[n]["bend_moment"] if n in members else lr.bend_moment))
            for n, lr in res.lines.items()), rel=1e-12)
    assert row["max_bend_moment"] >= max(float(np.max(lr.bend_moment)) for lr in res.lines.values()) > 1e5


# --------------------------------------------------------------------------- rfesim bench --help

def test_bench_help_shows_the_runner_options(capsys):
    with pytest.raises(SystemExit) as info:
        main(["bench", "--help"])
    assert info.value.code == 0
    out = capsys.readouterr().out
    assert "--only {h1,h2,scaling,startup,validation,formulations,slay,crane,build,compile}" in out
    assert "--quick" in out and "--no-moordyn" in out


def test_bench_outside_a_checkout_says_it_needs_one(tmp_path, monkeypatch, capsys):
    """From an installed wheel `rfesim bench` died with "internal error: FileNotFoundError
    .../site/scenarios/catenary_riser.json (a bug...)"; it now says it runs in a checkout."""
    import rfesim.bench.run as bench_run

    assert bench_run.checkout_problem() is None                 # this checkout has all three
    (tmp_path / "docs").mkdir()
    assert "has no scenarios/, no tests/" in bench_run.checkout_problem(tmp_path)
    monkeypatch.setattr(bench_run, "ROOT", tmp_path)
    monkeypatch.setattr(bench_run.checkout_problem, "__defaults__", (tmp_path,))
    assert main(["bench", "--only", "build"]) == 2
    err = capsys.readouterr().err
    assert "runs in a source checkout" in err and "internal error" not in err
