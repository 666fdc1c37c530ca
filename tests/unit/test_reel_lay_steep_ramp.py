"""Reel-lay at a near-vertical ramp (the schema takes ramp_angle_deg in [20, 90)).

* The seabed-fold check (rfesim.model.compile._seabed_fold, the "folds on the seabed"
  warning of rfesim.api._seabed_folds) counts only the pipe free beyond the last support:
  the pipe on the reel, aligner, straightener and tensioner (60 m at 89.5 deg) is held, not
  slack. It counted it and warned of 21.8 m of slack at 89.5 deg.
* The start shape runs through the supports in path order (rfesim.model.reels.reel_tail):
  ordered by the distance along the take-off direction, the straightener's offset middle
  roller came out of order at 89.9 deg, the catenary lacked 6 m, its last element started
  stretched 391 % and statics failed (with the fold warning as its hint)."""
import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.api import _compiled
from rfesim.solvers.system import System

ROOT = Path(__file__).resolve().parents[2]


def _reel_lay(angle):
    sc = json.loads((ROOT / "scenarios" / "reel_lay.json").read_text())
    sc["vessels"]["reeler"]["motion"]["file"] = str(ROOT / "scenarios" / "data" / "barge_100m_raos.json")
    sc["analysis"].pop("dynamics", None)
    sc["pipelay"]["lay"]["ramp_angle_deg"] = angle
    return sc


@pytest.mark.parametrize("angle", [70.0, 89.0, 89.5, 89.9])
def test_held_pipe_is_not_slack(angle):
    line = _compiled(rfesim.load_scenario(_reel_lay(angle))).lines[0]
    assert line.seabed_fold is None
    # reel wrap, the 2 m to the aligner, the aligner arc, straightener and tensioner
    assert 55.0 < line.held_length < 62.0


def test_start_shape_runs_through_the_ramp_in_order():
    m = _compiled(rfesim.load_scenario(_reel_lay(89.9)))
    system = System(m)
    system.evaluate(m.initial)
    assert np.abs(system.ws.eps[:, 0]).max() < 1e-2        # was 3.91 (the last element)


def test_near_vertical_ramp_statics_without_a_fold_warning():
    for angle in (89.5, 89.9):                               # 89.9: SolverError before
        res = rfesim.statics(_reel_lay(angle))
        assert res.status == 0
        assert "folds on the seabed" not in res.message


def test_slack_beyond_the_supports_is_still_found():
    """40 m more pipe than the template's line: slack on the seabed beyond the last support,
    reported from that support (and its held length), not from the reel."""
    from rfesim.api import _seabed_folds
    from rfesim.scenario.pipelay import expand
    data = expand(_reel_lay(89.5))
    data["lines"]["lay"]["length"] += 40.0
    data["lines"]["lay"]["elements"] += 20
    model = _compiled(rfesim.load_scenario(data))
    length, span, height, limit, drop = model.lines[0].seabed_fold
    assert drop == 0.0                      # its lower end lies on the seabed
    held = model.lines[0].held_length
    # 40 m less the 12.3 m by which the template's catenary (317.7 m hanging 315 m over a
    # 15.0 m span) is shorter than hanging vertically and lying straight
    assert length - limit == pytest.approx(40.0 - 12.3, abs=1.0)
    text = _seabed_folds(model)[0]
    assert "its last support" in text and f"{held:.6g} m from end A" in text
