"""Three defects of the service: warnings found at submit reached only the server log,
a cold numba cache left a job "running" for minutes with no word of why, and a worker
outlived its SIGKILLed server for as long as its run had left between two output times."""
from __future__ import annotations

import os
import shutil
import sqlite3
import time
from pathlib import Path

import httpx
import pytest

import rfesim
from service import validate
from service.settings import Settings
from service.worker import COMPILING_NOTE, merge_warnings
from service_helpers import SCENARIOS, Api, alive, riser

# 1.0 s is not a whole number of output intervals of 0.3 s: the run goes on to 1.2 s
OUTPUT_NOTE = ("dynamics: analysis.dynamics.duration (1 s) is not a whole number of output intervals (0.3 s): the "
               "run goes on to the next output time, t = 1.2 s")

# a clamped steel column (OD 0.2 m, wall 10 mm, 10 m) pushed down by 500 kN at its free top:
# EI = 2e11 * pi/64 * (0.2^4 - 0.18^4) = 5.402e6 N m^2, a cantilever buckles under its tip load at
# pi^2 EI / (2 L)^2 = 133.3 kN, so statics ends on an unstable straight shape and warns; a
# warning only a solve finds
COLUMN = {
    "schema_version": 1, "name": "column",
    "environment": {"gravity": 9.81},
    "line_types": {"p": {"outer_diameter": 0.2, "wall_thickness": 0.01, "youngs_modulus": 2.0e11,
                         "density": 7850.0}},
    "lines": {"col": {"type": "p", "length": 10.0, "elements": 10,
                      "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                "connection": "clamped"},
                      "end_b": {"attach": "free"},
                      "loads": [{"at": "end_b", "force": [0.0, 0.0, -5.0e5]}]}},
    "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}},
}


# --------------------------------------------------------------------------- 1. warnings

def test_submit_answers_the_warnings_that_need_no_solve(api):
    r = api.client.post("/jobs", json=riser(**{"analysis.dynamics.output_interval": 0.3}))
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == [OUTPUT_NOTE]
    job_id = r.json()["id"]
    assert api.job(job_id)["warnings"] == [OUTPUT_NOTE]
    job = api.wait(job_id)
    assert job["status"] == "done" and job["simulated_time"] == pytest.approx(1.2)
    # the run logs the same warning again: kept once
    assert job["warnings"] == [OUTPUT_NOTE]
    # a scenario without any: an empty list
    r = api.client.post("/jobs", json=riser())
    assert r.status_code == 202 and r.json()["warnings"] == []


def test_the_warnings_of_the_run_are_added_to_the_job(api):
    r = api.client.post("/jobs", json=COLUMN)
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == []                 # buckling needs the static solution
    job = api.wait(r.json()["id"])
    assert job["status"] == "done", job
    (warning,) = job["warnings"]
    assert warning.startswith("statics: line 'col' carries ")
    assert "pi^2 EI / (2 L)^2 = 133.3 kN" in warning and "EI = 5.402e+06 N m^2" in warning


def test_sweep_submit_answers_the_cases_warnings(api):
    body = {"scenario": riser(), "vary": {"analysis.dynamics.output_interval": [0.3, 0.25]}}
    r = api.client.post("/sweeps", json=body)
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == [f"{OUTPUT_NOTE} (load case analysis.dynamics.output_interval=0.3)"]
    first, second = r.json()["jobs"]
    assert api.job(first)["warnings"] == [OUTPUT_NOTE] and api.job(second)["warnings"] == []
    # the same warning in every case: once
    body = {"scenario": riser(**{"analysis.dynamics.output_interval": 0.3}),
            "vary": {"vessels.ship.motion.heave.amplitude": [0.2, 0.4]}}
    r = api.client.post("/sweeps", json=body)
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == [f"{OUTPUT_NOTE} (all 2 load cases)"]
    api.client.delete(f"/sweeps/{r.json()['id']}")


def test_load_warnings_of_a_template_and_an_rao_table(tmp_path):
    from rfesim.sea.rao import rao_range_warnings

    settings = Settings(data_dir=tmp_path)
    _, sc = validate.prepare_job({"scenario": "s_lay_template", "overrides": {"pipelay.lay.element_length": 4.0}},
                                 settings, SCENARIOS)
    (warning,) = validate.load_warnings(sc)
    assert warning.startswith("statics: pipelay.lay.element_length: elements of 3.99")
    _, sc = validate.prepare_job({"scenario": "column_crane"}, settings, SCENARIOS)
    warnings = validate.load_warnings(sc)
    assert warnings == [f"dynamics: {w}" for w in rao_range_warnings(sc)] and len(warnings) == 1
    assert "RAO table's highest frequency" in warnings[0]


def test_merge_warnings_keeps_each_once_and_bounds_the_list():
    assert merge_warnings(["dynamics: a"], ["a", "statics: b", "b", "c"]) == ["dynamics: a", "statics: b", "c"]
    merged = merge_warnings([], [f"w{i}" for i in range(60)], limit=50)
    assert merged[:50] == [f"w{i}" for i in range(50)]
    assert merged[50:] == ["... and 10 more warnings (see the service's log)"]


def test_sweep_warnings_are_bounded():
    """A 900-case sweep whose cases each warn differently answers at most 50 of them."""
    cases = [({"x": i}, [f"w{i}"]) for i in range(60)]
    out = validate.sweep_warnings(cases)
    assert out[:2] == ['w0 (load case x=0)', 'w1 (load case x=1)'] and len(out) == 51
    assert out[-1] == "... and 10 more warnings (each load case's job lists its own)"
    assert validate.sweep_warnings(cases[:50]) == [f"w{i} (load case x={i})" for i in range(50)]


def test_an_older_job_database_gets_the_new_columns(tmp_path):
    from service.store import Store

    con = sqlite3.connect(tmp_path / "jobs.sqlite")
    # the jobs table as the service created it before the warnings and compile_time columns
    con.execute("CREATE TABLE jobs (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT UNIQUE NOT NULL, "
                "status TEXT NOT NULL, name TEXT NOT NULL DEFAULT '', scenario TEXT NOT NULL, "
                "progress REAL NOT NULL DEFAULT 0, sim_time REAL, message TEXT NOT NULL DEFAULT '', "
                "created REAL NOT NULL, started REAL, finished REAL, attempts INTEGER NOT NULL DEFAULT 0, "
                "cancel_requested INTEGER NOT NULL DEFAULT 0, worker TEXT, worker_pid INTEGER, sweep_id TEXT, "
                "case_index INTEGER, case_values TEXT, summary TEXT, wall_time REAL, "
                "has_results INTEGER NOT NULL DEFAULT 0)")
    con.execute("INSERT INTO jobs (id, status, scenario, created) VALUES ('oldjob0001', 'done', '{}', 1.0)")
    con.commit()
    con.close()
    job = Store(tmp_path / "jobs.sqlite").get("oldjob0001")
    assert job["warnings"] == [] and job["compile_time"] is None


# --------------------------------------------------------------------------- 2. cold numba cache

EVICTED = "assemble.rebase-"     # a kernel the warm-up and a riser call from Python, compiled in ~1 s


def numba_cache_without(folder: Path, evicted: str) -> Path:
    """A NUMBA_CACHE_DIR holding the package's numba cache (hard links) but one kernel: a worker
    using it loads every kernel and compiles that one, as on a machine where the cache is cold."""
    from numba.core.caching import UserProvidedCacheLocator

    from service.worker import warm_up

    # the kernels a worker's warm-up and the riser job load, compiled into this process's
    # cache first: on a fresh checkout (CI) the cache is cold when this test runs
    warm_up()
    rfesim.simulate(riser())
    removed = 0
    given = os.environ.get("NUMBA_CACHE_DIR")
    if given:                                   # this process's cache is a NUMBA_CACHE_DIR: mirror it
        pairs = [(src, folder / src.relative_to(given)) for src in Path(given).rglob("*.nb[ic]")]
    else:                                       # next to the sources, in __pycache__
        root = Path(rfesim.__file__).parent
        pairs = [(src, folder / UserProvidedCacheLocator.get_suitable_cache_subpath(str(src.parent.parent / "x.py"))
                  / src.name) for src in root.rglob("__pycache__/*.nb[ic]")]
    for src, dst in pairs:
        if src.name.startswith(evicted):
            removed += 1
            continue
        dst.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(src, dst)
        except OSError:
            shutil.copy2(src, dst)
    assert removed, f"no cached kernel {evicted!r}"
    # compiled from these sources: else the worker's import drops the copied cache as one of
    # unknown sources (rfesim._kernel_cache) and compiles everything, minutes
    from rfesim._kernel_cache import mark_current
    mark_current(str(folder))
    return folder


def _watch(api: Api, job_id: str, timeout: float = 120.0) -> tuple[dict, list[dict], list[dict]]:
    """Poll a job and /health until the job is over: (the job, the job answers, the health answers)."""
    jobs, healths = [], []
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        healths.append(api.client.get("/health").json())
        job = api.job(job_id)
        jobs.append(job)
        if job["status"] in ("done", "failed", "cancelled"):
            return job, jobs, healths
        time.sleep(0.03)
    raise AssertionError(f"job {job_id} not over after {timeout} s: {jobs[-1]}")


def test_a_job_that_compiles_numba_kernels_says_so(make_server, tmp_path):
    cache = numba_cache_without(tmp_path / "numba", EVICTED)
    server = make_server(env={"NUMBA_CACHE_DIR": str(cache), "RFESIM_WORKERS": "1", "RFESIM_WARMUP": "false"})
    api = Api(server)
    job_id = api.submit(riser())
    job, jobs, healths = _watch(api, job_id)
    assert job["status"] == "done", job
    assert any(j["status"] == "running" and j["message"].endswith(f": {COMPILING_NOTE}") for j in jobs), \
        [j["message"] for j in jobs]
    assert any(h["executor"]["compiling"] == 1 and COMPILING_NOTE in h["message"] for h in healths)
    assert job["compile_time"] > 0.0
    # the kernel is in the cache now: the next job compiles nothing
    again = api.wait(api.submit(riser()))
    assert again["status"] == "done" and again["compile_time"] == 0.0
    api.close()


def test_workers_compiling_in_their_warm_up_show_in_health_and_queued_jobs(make_server, tmp_path):
    cache = numba_cache_without(tmp_path / "numba", EVICTED)
    server = make_server(env={"NUMBA_CACHE_DIR": str(cache), "RFESIM_WORKERS": "1"}, wait_workers=False)
    api = Api(server)
    job_id = api.submit(riser())
    job, jobs, healths = _watch(api, job_id)
    assert job["status"] == "done", job
    waiting = f"queued (waiting for the workers' warm-up: {COMPILING_NOTE})"
    assert any(j["status"] == "queued" and j["message"] == waiting for j in jobs), [j["message"] for j in jobs]
    assert any(h["executor"]["compiling"] == 1 and h["executor"]["ready"] == 0
               and h["message"] == f"1 of 1 workers {COMPILING_NOTE}; jobs wait in the queue until a worker is ready"
               for h in healths), [h["message"] for h in healths]
    assert healths[-1]["message"] == "1 of 1 workers ready" and job["compile_time"] == 0.0
    api.close()


# --------------------------------------------------------------------------- 3. orphan workers

def test_a_worker_exits_within_a_second_or_two_of_its_server_being_killed(make_server):
    server = make_server(env={"RFESIM_WORKERS": "1"})
    api = Api(server)
    # one output at the end of 600 s simulated (tens of seconds of wall time): no progress
    # callback, where the old worker looked for its parent, between t = 0 and the end
    job_id = api.submit({"scenario": "cantilever_pipe",
                         "overrides": {"analysis.dynamics.duration": 600.0, "analysis.dynamics.output_interval": 600.0,
                                       "analysis.dynamics.integrator.time_step": 0.0005}})
    pid = api.wait(job_id, until=("running",), predicate=lambda j: j["worker_pid"])["worker_pid"]
    time.sleep(1.0)                        # inside the time steps
    assert alive(pid)
    api.close()
    server.kill()
    killed = time.monotonic()
    while alive(pid) and time.monotonic() - killed < 10.0:
        time.sleep(0.05)
    lived = time.monotonic() - killed
    assert not alive(pid) and lived < 3.0, f"the worker lived {lived:.3g} s after its server was killed"

    # the job it was running is re-queued at the next start, as after any SIGKILL
    restarted = make_server(data_dir=server.data_dir, env={"RFESIM_WORKERS": "1"}, wait_workers=False)
    api = Api(restarted)
    job = api.job(job_id)
    assert job["status"] in ("queued", "running"), job
    if job["status"] == "queued":
        assert job["message"].startswith("re-queued after a service restart")
    else:
        assert job["message"].startswith("running on local process") and "(attempt 2)" in job["message"]
    api.close()
    try:
        httpx.delete(f"{restarted.url}/jobs/{job_id}", timeout=10.0)
    except httpx.HTTPError:
        pass


def test_the_worker_warm_up_run_is_clean():
    """The warm-up run logged "dynamics warning: 1 of the 2 time steps (50 %) failed Newton's
    iteration ... the results may be inaccurate" at every service start (and in the docker
    build): it runs without a warning now, with the same kernels (statics, dynamics, sea)."""
    import copy

    import rfesim
    from service.worker import WARMUP_SCENARIO

    res = rfesim.simulate(copy.deepcopy(WARMUP_SCENARIO))
    assert res.status == 0 and res.message.startswith("finished") and "warning" not in res.message
