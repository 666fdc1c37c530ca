"""The command line: `rfesim check | statics | run | modes` on small scenarios (seconds)."""
from __future__ import annotations

import copy
import io
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from rfesim.cli import main
from rfesim.progress import ProgressBar, format_duration

# a 10 m cantilever of 10 elements, clamped at end A, tip load at end B, no gravity
CANTILEVER = {
    "schema_version": 1,
    "name": "cli cantilever",
    "environment": {"gravity": 0.0},
    "line_types": {"beam": {"EA": 1.0e8, "EIy": 1.0e5, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "beam", "length": 10.0, "elements": 10,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                 "connection": "clamped"},
                       "end_b": {"attach": "free"},
                       "loads": [{"at": "end_b", "force": [0.0, 0.0, -100.0]}]}},
    "analysis": {"statics": {"enabled": True},
                 "dynamics": {"duration": 2.0, "output_interval": 0.05,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.01, "rho_inf": 0.8}}},
}


def write_scenario(folder: Path, data: dict, name: str = "cantilever.json") -> Path:
    path = folder / name
    path.write_text(json.dumps(data), encoding="utf-8")
    return path


@pytest.fixture
def good(tmp_path) -> Path:
    return write_scenario(tmp_path, CANTILEVER)


@pytest.fixture
def bad(tmp_path) -> Path:
    data = copy.deepcopy(CANTILEVER)
    data["lines"]["pipe"]["elements"] = 0
    return write_scenario(tmp_path, data, "bad.json")


def test_check_good(good, capsys):
    assert main(["check", str(good)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("OK: cli cantilever: 1 lines, 0 vessels")


def test_check_bad_names_the_field(bad, capsys):
    assert main(["check", str(bad)]) == 1
    captured = capsys.readouterr()
    assert "scenario error:" in captured.err
    assert "lines.pipe.elements:" in captured.err
    assert "Traceback" not in captured.err


def test_check_several_errors_one_per_line(tmp_path, capsys):
    data = copy.deepcopy(CANTILEVER)
    data["lines"]["pipe"]["elements"] = 0
    data["lines"]["pipe"]["lenght"] = 3.0
    path = write_scenario(tmp_path, data, "two.json")
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "scenario error:"
    assert any(line.strip().startswith("lines.pipe.elements:") for line in err)
    assert any(line.strip().startswith("lines.pipe.lenght:") for line in err)


def test_check_refuses_what_compiling_the_model_refuses(tmp_path, capsys):
    # both ends at one point: validation refuses it now (it once passed validation and only
    # the model compiler refused it)
    data = copy.deepcopy(CANTILEVER)
    data["lines"]["pipe"]["end_b"] = {"attach": "fixed", "position": [0.0, 0.0, 0.0]}
    path = write_scenario(tmp_path, data, "coincide.json")
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "lines.pipe.end_b.position: end B coincides with end A" in err
    assert "Traceback" not in err
    # a pipe shorter than its stinger passes validation; only building the model finds it:
    # `check` used to say OK and only `run` failed
    root = Path(__file__).resolve().parents[1]
    data = json.loads((root / "scenarios" / "s_lay.json").read_text())
    data["lines"]["pipe"].update(length=40.0, elements=20, end_b={"attach": "free"})
    path = write_scenario(tmp_path, data, "short.json")
    assert main(["check", str(path)]) == 1
    err = capsys.readouterr().err
    assert "supports: the line is 40.0 m long but reaches the last roller only after 65.2052 m" in err
    assert "Traceback" not in err


def test_check_builds_a_scene_of_the_other_formulations(tmp_path, capsys):
    # `check` builds the chain model of a modified-formulation line (rfesim.api.check_model)
    # instead of the absolute-coordinate compiler, which would refuse it
    data = copy.deepcopy(CANTILEVER)
    data["lines"]["pipe"]["formulation"] = "modified"
    data["analysis"]["dynamics"]["integrator"] = {"kind": "rk4", "time_step": 1.0e-4}
    path = write_scenario(tmp_path, data, "modified.json")
    assert main(["check", str(path)]) == 0
    assert capsys.readouterr().out.startswith("OK: cli cantilever")


def test_check_shows_a_template_warning(tmp_path, capsys):
    # the S-lay template with elements longer than half the roller spacing: `check` says so
    # (the warning a run puts among its statics warnings), and still passes
    root = Path(__file__).resolve().parents[1]
    data = json.loads((root / "scenarios" / "s_lay_template.json").read_text())
    data["pipelay"]["lay"]["element_length"] = 4.0
    shutil.copytree(root / "scenarios" / "data", tmp_path / "data")       # its RAO file
    path = write_scenario(tmp_path, data, "coarse.json")
    assert main(["check", str(path)]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("OK: ")
    assert "scenario: pipelay.lay.element_length: elements of 3.99" in captured.err


def test_check_shows_the_built_models_warning(tmp_path, capsys):
    # the service's tiny riser made 130 m long: 15.1 m more than can hang vertically and lie
    # straight on the seabed, so it folds there (no unique static shape); only the built model
    # tells, and `check` says so as a run's statics would (it printed nothing before)
    sys.path.insert(0, str(Path(__file__).resolve().parent / "service"))
    from service_helpers import riser

    path = write_scenario(tmp_path, riser(**{"lines.riser.length": 130.0}), "fold.json")
    assert main(["check", str(path)]) == 0
    captured = capsys.readouterr()
    assert captured.out.startswith("OK: ")
    assert ("statics: line 'riser' runs from the seabed to a point 44.9 m up and 70 m away, and is 15.1 m "
            "longer (130 m)") in captured.err


def test_verbose_logs_library_messages(tmp_path, capsys):
    data = copy.deepcopy(CANTILEVER)
    data["line_types"]["beam"]["EIy"] = 0.0      # a flexible line: the model compiler says so at INFO
    data["lines"]["pipe"]["loads"] = []
    path = write_scenario(tmp_path, data, "flexible.json")
    out = tmp_path / "flexible.nc"
    assert main(["statics", str(path), "-o", str(out)]) == 0
    assert "INFO" not in capsys.readouterr().err
    assert main(["statics", str(path), "-v", "-o", str(out)]) == 0
    assert "INFO rfesim" in capsys.readouterr().err


def test_statics_warning_is_shown_once(tmp_path, capsys):
    """The cantilever pushed along its axis by ten times its Euler load, weightless: statics
    converges straight and warns (rfesim.solvers.buckling). The warning is logged on stderr
    once; the summary line counts it; the results file keeps it in full."""
    import rfesim
    data = copy.deepcopy(CANTILEVER)
    euler = 3.141592653589793 ** 2 * 1.0e5 / 10.0 ** 2
    data["lines"]["pipe"]["loads"] = [{"at": "end_b", "force": [-10.0 * euler, 0.0, 0.0]}]
    path = write_scenario(tmp_path, data, "pushed.json")
    out = tmp_path / "pushed.nc"
    assert main(["statics", str(path), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert captured.err.count("compression over a free stretch of 10 m") == 1
    assert "compression over" not in captured.out and "(1 statics warning, above)" in captured.out
    assert "statics warning: line 'pipe' carries" in rfesim.open_results(out).message


def test_missing_file(tmp_path, capsys):
    assert main(["check", str(tmp_path / "nope.json")]) == 1
    err = capsys.readouterr().err
    assert "not found" in err and "nope.json" in err


def test_invalid_json(tmp_path, capsys):
    path = tmp_path / "broken.json"
    path.write_text('{"name": "x",', encoding="utf-8")
    assert main(["check", str(path)]) == 1
    assert "invalid JSON" in capsys.readouterr().err


def test_statics_writes_file(good, tmp_path, capsys):
    import rfesim

    out = tmp_path / "st.nc"
    assert main(["statics", str(good), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "pipe" in text and "end A force" in text and "max tension" in text
    assert out.is_file() and out.stat().st_size > 0
    res = rfesim.open_results(out)
    assert res.kind == "statics" and len(res.time) == 1
    # the clamp carries the tip load: 100 N downwards on the line -> the line pulls the clamp down
    assert res.line("pipe").end_a_force[0, 2] == pytest.approx(-100.0, rel=1e-6)


def test_statics_missing_output_folder(good, tmp_path, capsys):
    assert main(["statics", str(good), "-o", str(tmp_path / "no" / "st.nc")]) == 1
    assert "output folder does not exist" in capsys.readouterr().err


def test_run_writes_results_and_plot(good, tmp_path, capsys):
    import rfesim

    out, png = tmp_path / "run.nc", tmp_path / "run.png"
    assert main(["run", str(good), "-o", str(out), "--plot", str(png), "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "simulated 2 s" in text and "steps" in text and "max top tension" in text
    assert out.is_file() and out.stat().st_size > 0
    assert png.is_file() and png.stat().st_size > 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    res = rfesim.open_results(out)
    assert res.time[-1] == pytest.approx(2.0)


def test_run_default_output_in_cwd(good, tmp_path, monkeypatch, capsys):
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)
    assert main(["run", str(good), "--no-progress"]) == 0
    assert (work / "cantilever.nc").is_file()


def test_run_progress_bar(good, tmp_path, capsys):
    assert main(["run", str(good), "-o", str(tmp_path / "p.nc"), "--progress"]) == 0
    err = capsys.readouterr().err
    assert "100.0%" in err and "ETA" in err


def test_cold_numba_cache_is_announced(good, tmp_path, monkeypatch, capsys):
    # a run compiles (or loads) the kernels into the cache: the next run says nothing about it
    assert main(["run", str(good), "-o", str(tmp_path / "a.nc"), "--no-progress"]) == 0
    capsys.readouterr()
    assert main(["run", str(good), "-o", str(tmp_path / "b.nc"), "--no-progress"]) == 0
    assert "compiling" not in capsys.readouterr().err
    # an empty cache directory is cold
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "empty_cache"))
    cold = subprocess.run([sys.executable, "-c", "from rfesim.cli import numba_cache_is_cold as f; print(f())"],
                          capture_output=True, text=True, env=env, timeout=120)
    assert cold.stdout.strip() == "True", cold.stderr
    # and then run, statics and modes say why the first run is slow, on stderr
    # and compile them ahead in parallel processes (rfesim.precompile, tests/test_precompile.py)
    monkeypatch.setattr("rfesim.cli.numba_cache_is_cold", lambda: True)
    calls = []
    monkeypatch.setattr("rfesim._precompile.precompile", lambda n, progress=None: calls.append(n) or 0)
    monkeypatch.setenv("RFESIM_PRECOMPILE", "2")
    for argv in (["run", str(good), "-o", str(tmp_path / "c.nc"), "--no-progress"], ["statics", str(good)],
                 ["modes", str(good), "-n", "2"]):
        assert main(argv) == 0
        captured = capsys.readouterr()
        assert "compiling the numba kernels in 2 processes" in captured.err, argv
        assert "compiling" not in captured.out
    assert calls == [2, 2, 2]
    # with one process the run compiles what it calls (no more than it needs)
    monkeypatch.setenv("RFESIM_PRECOMPILE", "1")
    assert main(["statics", str(good)]) == 0
    assert "compiling the numba kernels: the first run" in capsys.readouterr().err and calls == [2, 2, 2]
    monkeypatch.setenv("RFESIM_PRECOMPILE", "2")
    # a failure there is a note, and the run compiles as it goes
    monkeypatch.setattr("rfesim._precompile.precompile", lambda n, progress=None: 1 / 0)
    assert main(["statics", str(good)]) == 0
    assert "compiling the kernels ahead failed (ZeroDivisionError" in capsys.readouterr().err


def test_run_solver_error_writes_partial_results(tmp_path, capsys):
    import rfesim

    path = write_scenario(tmp_path, diverging_scenario(), "diverge.json")
    out, png = tmp_path / "diverge.nc", tmp_path / "diverge.png"
    assert main(["run", str(path), "-o", str(out), "--plot", str(png), "--no-progress"]) == 3
    err = capsys.readouterr().err
    assert "solver error:" in err and "partial results" in err and str(out) in err
    # the step is named against the RK4 stability limit, in the warning and in the error
    assert "longer than its stability limit" in err and "analysis.dynamics.integrator.time_step" in err
    assert png.is_file() and png.stat().st_size > 0
    res = rfesim.open_results(out)
    assert res.status == 1 and 0 < len(res.time) and res.time[-1] < 5.0


def test_plot_path_checked_before_the_run(good, tmp_path, capsys):
    same = tmp_path / "same.png"
    assert main(["run", str(good), "-o", str(same), "--plot", str(same), "--no-progress"]) == 2
    assert "--plot and -o name the same file" in capsys.readouterr().err
    assert not same.exists()
    out = tmp_path / "o.nc"
    assert main(["run", str(good), "-o", str(out), "--plot", str(tmp_path / "o.xyz"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "cannot write '.xyz' files" in err and ".png" in err and "Traceback" not in err
    assert not out.exists()                     # refused before the run, nothing written


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs a Linux /proc (not writable, even for root)")
def test_unwritable_output_refused_before_the_run(good, capsys):
    assert main(["run", str(good), "-o", "/proc/rfesim_results.nc", "--no-progress"]) == 1
    err = capsys.readouterr().err
    assert "cannot write /proc/rfesim_results.nc" in err
    assert "simulated" not in err


def test_summary_counts_halved_steps():
    import numpy as np

    from rfesim.cli import _run_summary

    class Res:
        kind = "dynamics"
        time = np.linspace(0.0, 6.0, 4)
        lines = {}
        counters = {"steps": 31, "time_step": 2.0, "step_halvings": 3}

    text = _run_summary(Res(), 1.0)[0]
    assert text.startswith("simulated 6 s: 31 steps (time step 2 s, 3 step halvings where Newton needed")
    Res.counters = {"steps": 3, "time_step": 2.0}
    assert _run_summary(Res(), 1.0)[0].startswith("simulated 6 s: 3 steps of 2 s, 4 output times")


def test_sweep_output_folder_refused_before_the_cases(good, tmp_path, capsys):
    from rfesim.sweep import main as sweep_main

    folder = tmp_path / "outdir"
    folder.mkdir()
    assert sweep_main([str(good), "--vary", "analysis.dynamics.duration=0.05", "-o", str(folder)]) == 1
    err = capsys.readouterr().err
    assert "the output path is a folder" in err
    assert not (tmp_path / "outdir.tmp").exists()


def diverging_scenario() -> dict:
    """A soft cable under gravity integrated by RK4 with a step far above its stability limit."""
    return {
        "name": "diverging cable",
        "environment": {"gravity": 9.81},
        "line_types": {"cable": {"EA": 1.0e7, "EIy": 1.0e3, "mass_per_length": 1.0}},
        "lines": {"pipe": {"type": "cable", "length": 10.0, "elements": 10,
                           "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": 5.0, "output_interval": 0.05,
                                  "integrator": {"kind": "rk4", "time_step": 0.05}}},
    }


def test_modes_table(good, capsys):
    assert main(["modes", str(good), "-n", "3"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header = next(i for i, line in enumerate(lines) if "frequency [Hz]" in line)
    rows = [line.split() for line in lines[header + 1:] if line.strip()]
    assert len(rows) == 3
    assert [int(r[0]) for r in rows] == [1, 2, 3]
    freqs = [float(r[1]) for r in rows]
    periods = [float(r[2]) for r in rows]
    assert all(f > 0 for f in freqs)
    assert freqs == sorted(freqs)
    assert periods == pytest.approx([1.0 / f for f in freqs], rel=1e-4)


def test_usage_errors(capsys):
    with pytest.raises(SystemExit) as exc:
        main([])
    assert exc.value.code == 2
    with pytest.raises(SystemExit) as exc:
        main(["check", "x.json", "--bogus"])
    assert exc.value.code == 2


def test_optional_components_missing_say_so(capsys, monkeypatch):
    import rfesim.cli as cli

    monkeypatch.setattr(cli, "_module_exists", lambda name: False)
    assert main(["bench", "--quick"]) == 2
    assert "rfesim.bench.run" in capsys.readouterr().err
    assert main(["serve"]) == 2
    assert "service.app" in capsys.readouterr().err
    assert main(["sweep", "x.json", "--vary", "lines.pipe.elements=10,20"]) == 2
    assert "rfesim.sweep" in capsys.readouterr().err


def test_bench_and_sweep_dispatch(monkeypatch):
    import types

    import rfesim.cli as cli

    calls = {}
    bench = types.ModuleType("rfesim.bench.run")
    bench.main = lambda argv: calls.setdefault("bench", argv) and 0
    sweep = types.ModuleType("rfesim.sweep")
    sweep.main = lambda argv: calls.setdefault("sweep", argv) and 0
    monkeypatch.setitem(sys.modules, "rfesim.bench.run", bench)
    monkeypatch.setitem(sys.modules, "rfesim.sweep", sweep)
    monkeypatch.setattr(cli, "_module_exists", lambda name: True)
    assert main(["bench", "--quick", "--extra-flag"]) == 0
    assert calls["bench"] == ["--quick", "--extra-flag"]
    assert main(["sweep", "s.json", "--vary", "a.b=1,2", "--vary", "c=3", "--scheduler", "tcp://h:8786"]) == 0
    assert calls["sweep"] == ["s.json", "--vary", "a.b=1,2", "--vary", "c=3", "--scheduler", "tcp://h:8786"]


def test_keyboard_interrupt_exits_130(good, tmp_path, monkeypatch, capsys):
    import rfesim

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(rfesim, "simulate", interrupted)
    out = tmp_path / "interrupted.nc"
    assert main(["run", str(good), "--no-progress", "-o", str(out)]) == 130
    assert "interrupted" in capsys.readouterr().err
    assert not out.exists()


def test_subprocess_check_and_statics(good, bad, tmp_path):
    env = dict(os.environ, PYTHONIOENCODING="utf-8")
    ok = subprocess.run([sys.executable, "-m", "rfesim.cli", "check", str(good)], capture_output=True, text=True,
                        env=env, timeout=120)
    assert ok.returncode == 0, ok.stderr
    assert ok.stdout.startswith("OK: cli cantilever")
    ko = subprocess.run([sys.executable, "-m", "rfesim.cli", "check", str(bad)], capture_output=True, text=True,
                        env=env, timeout=120)
    assert ko.returncode == 1
    assert "lines.pipe.elements" in ko.stderr and "Traceback" not in ko.stderr
    out = tmp_path / "sub.nc"
    st = subprocess.run([sys.executable, "-m", "rfesim.cli", "statics", str(good), "-o", str(out)],
                        capture_output=True, text=True, env=env, timeout=300)
    assert st.returncode == 0, st.stderr
    assert out.is_file() and out.stat().st_size > 0


# --------------------------------------------------------------------------- progress bar

class FakeClock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def test_progress_bar_throttles_and_estimates():
    clock, stream = FakeClock(), io.StringIO()
    bar = ProgressBar(stream, clock=clock, max_rate=10.0)
    for k in range(1, 101):
        clock.now = 0.01 * k          # 100 updates over 1 s
        bar(k / 100.0, 0.6 * k)
    assert bar.updates == 100
    assert 5 <= bar.draws <= 12       # ~10 draws/s, the final 100 % always drawn
    assert "100.0%" in stream.getvalue() and "t = 60 s" in stream.getvalue()
    # the ETA uses the rate since the first update (start-up time before it does not count)
    clock2 = FakeClock()
    bar2 = ProgressBar(io.StringIO(), clock=clock2)
    clock2.now = 5.0                  # statics and compilation took 5 s
    bar2(0.0, 0.0)
    assert bar2.eta() != bar2.eta()   # NaN: no rate yet
    clock2.now = 6.0
    bar2(0.25, 15.0)
    assert bar2.eta() == pytest.approx(3.0)
    bar.close()
    assert stream.getvalue().endswith("\n")


def test_progress_bar_delay_keeps_quick_runs_silent():
    clock, stream = FakeClock(), io.StringIO()
    bar = ProgressBar(stream, clock=clock, delay=1.0)
    for k in range(1, 11):
        clock.now = 0.05 * k
        bar(k / 10.0, float(k))
    bar.close()
    assert stream.getvalue() == ""


def test_format_duration():
    assert format_duration(3.21) == "3.2 s"
    assert format_duration(125.0) == "2 min 05 s"
    assert format_duration(7380.0) == "2 h 03 min"
    assert format_duration(float("nan")) == "?"
