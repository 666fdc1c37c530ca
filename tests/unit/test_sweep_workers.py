"""A local sweep survives dead worker processes (rfesim.sweep.run_cases / _run_local): only
the case whose process dies (again, when run alone) fails; the others finish.

The worker function here stands in for rfesim.sweep.run_case (no simulation): spawned
workers import this module by name (pytest puts its folder on sys.path, which spawn
passes on), so keep its imports light."""
from __future__ import annotations

import os
import signal
from pathlib import Path


def _row(case: dict, index: int) -> dict:
    return {"case": index, "status": "done", "message": f"ran in {os.getpid()}", "wall_time": 0.01,
            "max_top_tension": float(case["value"])}


def die_always(case: dict, index: int) -> dict:
    """Kills its own worker process (kill -9, as the OOM killer does) for the case marked so."""
    if case.get("die"):
        os.kill(os.getpid(), signal.SIGKILL)
    return _row(case, index)


def die_once(case: dict, index: int) -> dict:
    """Kills its worker the first time only (out of memory beside other cases, fine alone)."""
    flag = case.get("flag")
    if flag and not os.path.exists(flag):
        Path(flag).write_text("died once")
        os.kill(os.getpid(), signal.SIGKILL)
    return _row(case, index)


def _run(cases, fn, workers=2):
    from rfesim.sweep import _run_local

    out = {}
    _run_local(cases, None, workers, lambda i, r: out.__setitem__(i, r), fn)
    return out


def test_a_dead_worker_fails_only_its_own_case():
    from rfesim.sweep import LOST_WORKER

    cases = [({"v": i}, {"value": i, "die": i == 1}) for i in range(5)]
    out = _run(cases, die_always)
    assert sorted(out) == [0, 1, 2, 3, 4]
    assert out[1]["status"] == "failed" and out[1]["message"] == LOST_WORKER and out[1]["wall_time"] is None
    for i in (0, 2, 3, 4):
        assert out[i]["status"] == "done", out[i]
        assert out[i]["max_top_tension"] == float(i)


def test_a_case_whose_worker_died_once_is_run_again(tmp_path):
    cases = [({"v": i}, {"value": i, "flag": str(tmp_path / "died") if i == 2 else None}) for i in range(4)]
    out = _run(cases, die_once)
    assert (tmp_path / "died").read_text() == "died once"          # it did kill a worker
    assert [out[i]["status"] for i in range(4)] == ["done"] * 4
    assert [out[i]["max_top_tension"] for i in range(4)] == [0.0, 1.0, 2.0, 3.0]
