"""A sweep's log records name their load case: warnings from worker processes reach
stderr interleaved, and without the tag one cannot tell whose they are (seconds: the CLI
tests' 2 s cantilever)."""
from __future__ import annotations

import copy
import json
import logging
import threading

from rfesim.cli import main
from rfesim.sweep import run_case
from test_cli import CANTILEVER      # pytest puts tests/ on sys.path

WARNING = "is not a whole number of output intervals"


def _uneven(duration=2.03):
    case = copy.deepcopy(CANTILEVER)
    case["analysis"]["dynamics"]["duration"] = duration
    return case


def test_run_case_tags_its_warnings_with_the_case_number(caplog):
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        row = run_case(_uneven(), 7)
        logging.getLogger("rfesim.api").warning("after the case")
    assert row["status"] == "done"
    msgs = [r.getMessage() for r in caplog.records]
    tagged = [m for m in msgs if WARNING in m]
    assert tagged and all(m.startswith("case 7: analysis.dynamics.duration") for m in tagged), msgs
    assert "after the case" in msgs            # outside the case: no tag


def test_the_tag_is_per_thread(caplog):
    """Cases run on a thread pool: each thread's records carry its own case number."""
    seen = {}
    barrier = threading.Barrier(2)

    def log_in_case(i):
        from rfesim.sweep import _tagged
        with _tagged(i):
            barrier.wait()
            logging.getLogger("rfesim.x").warning("thread %d", i)

    with caplog.at_level(logging.WARNING, logger="rfesim"):
        threads = [threading.Thread(target=log_in_case, args=(i,)) for i in (3, 4)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    for r in caplog.records:
        seen[r.getMessage()] = True
    assert set(seen) == {"case 3: thread 3", "case 4: thread 4"}


def test_cli_sweep_warnings_on_stderr_name_the_case(tmp_path, capfd):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(CANTILEVER), encoding="utf-8")
    assert main(["sweep", str(path), "--vary", "analysis.dynamics.duration=2,2.03",
                 "-o", str(tmp_path / "s.csv"), "--workers", "2"]) == 0
    err = capfd.readouterr().err
    lines = [ln for ln in err.splitlines() if WARNING in ln]
    assert len(lines) == 1 and lines[0].startswith("case 1: analysis.dynamics.duration (2.03 s)"), err
