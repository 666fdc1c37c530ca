"""Statics' load steps ramp the current's drag with the weights (rfesim.model.assemble.
local_loads): the residual's current part at load factor lambda is lambda times its full
value. Held at its full value, it made a short load step harder, not easier: the reel-lay
template in a 1.5 m/s current could take no load step and failed at load factor 0."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np

import rfesim
from rfesim.model.compile import compile_scenario
from rfesim.solvers.system import System
from scenes import RISER

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _residual(sc, lam):
    system = System(compile_scenario(rfesim.load_scenario(sc)))
    st = system.model.initial
    r = np.zeros_like(st.q)
    system.static_residual(st.q, st.ref, lam, r)
    return r


def test_the_current_part_of_the_static_residual_scales_with_the_load_factor():
    still = copy.deepcopy(RISER)
    current = copy.deepcopy(RISER)
    current["environment"]["water"]["current"] = {"profile": [[0.0, 1.5], [-50.0, 1.0]], "direction_deg": 90.0}
    full = _residual(current, 1.0) - _residual(still, 1.0)
    assert np.abs(full).max() > 100.0                  # the drag of a 1-1.5 m/s cross current, N
    for lam in (0.5, 0.125, 1e-3):
        part = _residual(current, lam) - _residual(still, lam)
        np.testing.assert_allclose(part, lam * full, rtol=0, atol=1e-9 * np.abs(full).max())


def test_reel_lay_statics_in_a_strong_current():
    """The reel-lay template in a 1.5 m/s uniform current along the lay (it needs load
    steps): statics converges (it failed at load factor 0)."""
    sc = json.loads((SCENARIOS / "reel_lay.json").read_text())
    sc["vessels"]["reeler"]["motion"]["file"] = str(SCENARIOS / "data" / "barge_100m_raos.json")
    sc["analysis"].pop("dynamics")
    still = rfesim.statics(copy.deepcopy(sc))
    sc["environment"]["water"]["current"] = {"profile": [[0.0, 1.5], [-300.0, 1.5]], "direction_deg": 0.0}
    res = rfesim.statics(sc)
    assert res.status == 0
    top = np.asarray(res.line("lay").tension)[0]
    assert np.all(np.isfinite(top))
    assert still.status == 0
