"""A run with analysis.statics.enabled false starts from the scenario's start shape; when that
is far out of balance and the dynamics fail, the SolverError says so (rfesim.api._start_imbalance)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.api import START_IMBALANCE, _compiled, _start_imbalance
from rfesim.solvers.system import System

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _liftoff(statics: bool) -> rfesim.Scenario:
    # the module rests on the supply vessel's deck with the rope 0.22 m shorter than the
    # distance to the boom tip: the statics stretches it; the start shape is that short rope
    data = json.loads((SCENARIOS / "column_crane_liftoff.json").read_text())
    data["analysis"]["statics"]["enabled"] = statics
    data["analysis"]["dynamics"]["duration"] = 0.2
    # the failure itself is under test: no going back at half the step (Recovery), which passes it
    data["analysis"]["dynamics"]["integrator"]["recovery_halvings"] = 0
    data["environment"]["water"].pop("waves", None)
    for v in data["vessels"].values():
        v["motion"] = {"kind": "fixed"}
    return rfesim.load_scenario(data, base_dir=SCENARIOS)


def test_failed_run_from_an_unbalanced_start_says_so():
    sc = _liftoff(statics=False)
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(sc)
    err = info.value
    assert err.time < 0.05                       # within the first step
    assert "analysis.statics.enabled is false" in err.hint
    assert "at body 'crane_payload'" in err.hint
    # the out-of-balance force against a numpy sum of the start residual
    system = System(_compiled(sc))
    state = system.model.initial
    out = np.zeros_like(state.q)
    system.static_residual(state.q, state.ref, 1.0, out)
    peak = float(np.abs(out[:, :3]).max())
    assert peak > START_IMBALANCE * system.force_scale(state)
    assert f"{peak / 1e3:.4g} kN" in err.hint
    assert err.results is not None and err.hint.split("; ")[-1] in err.results.message


def test_balanced_start_gives_no_hint():
    sc = _liftoff(statics=True)
    system = System(_compiled(sc))
    state, _ = rfesim.api._static_state(system, sc)
    assert _start_imbalance(system, state) is None
