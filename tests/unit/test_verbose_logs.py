"""What ``rfesim -v`` (info) and ``-vv`` (debug) add: the model's size and the load terms
the scene switches on, the statics' iterations, the dynamics' cost, and each step taken
in substeps (seconds: the CLI tests' cantilever and the kernel-recording tests' joined
crane scene)."""
from __future__ import annotations

import json
import logging
import re

import rfesim
from rfesim.cli import main
from test_cli import CANTILEVER      # pytest puts tests/ on sys.path
from test_kernel_recording import _joined
from scenes import RISER


def _run_cli(tmp_path, capsys, *flags):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(CANTILEVER), encoding="utf-8")
    assert main([*flags, "run", str(path), "-o", str(tmp_path / "r.nc")]) == 0
    return capsys.readouterr().err


def test_v_logs_the_model_the_statics_and_the_cost_of_the_run(tmp_path, capsys):
    err = _run_cli(tmp_path, capsys, "-v")
    assert ("INFO rfesim: model: 1 line(s) (pipe), 11 RFEs, 60 degrees of freedom; terms: point loads"
            in err), err                              # 10 free RFEs x 6, the clamped one none; no gravity
    assert re.search(r"INFO rfesim: statics: converged in \d+ Newton iterations", err), err
    m = re.search(r"INFO rfesim: dynamics: 2 s simulated in [\d.e+-]+ s, [\d.e+-]+x real time; 200 steps "
                  r"\(time step 0.01 s, 0 halvings\), (\d+) Newton iterations, (\d+) Jacobians", err)
    assert m, err
    res = rfesim.open_results(tmp_path / "r.nc")
    assert int(m.group(1)) == res.counters["newton_iterations"] and int(m.group(2)) == res.counters["jacobians"]


def test_without_v_the_run_logs_none_of_it(tmp_path, capsys):
    err = _run_cli(tmp_path, capsys)
    assert "INFO" not in err and "model:" not in err


def test_the_terms_are_those_of_the_scene(caplog):
    """A riser in waves over a seabed with friction switches on the sea's terms; the
    cantilever in air none of them."""
    with caplog.at_level(logging.INFO, logger="rfesim"):
        rfesim.api.check_model(RISER)
    line = next(r.getMessage() for r in caplog.records if r.getMessage().startswith("model:"))
    terms = line.split("terms: ")[1].split(", ")
    sc = rfesim.load_scenario(RISER)
    assert "gravity" in terms and "buoyancy" in terms and "seabed" in terms
    assert ("seabed friction" in terms) == (sc.environment.seabed.mu_axial > 0 or sc.environment.seabed.mu_lateral > 0)
    assert "rollers" not in terms and "reels" not in terms and "elasto-plastic SDEs" not in terms


def test_vv_logs_each_step_taken_in_substeps(caplog):
    # two Newton iterations a step: some steps fail and are taken again in substeps
    with caplog.at_level(logging.DEBUG, logger="rfesim"):
        res = rfesim.simulate(_joined(max_iterations=2, duration=1.5))
    halved = [r.getMessage() for r in caplog.records if "substeps of" in r.getMessage()]
    assert res.counters["step_halvings"] > 0
    assert len(halved) == res.counters["step_halvings"]
    assert all(r.levelno == logging.DEBUG for r in caplog.records if "substeps of" in r.getMessage())
