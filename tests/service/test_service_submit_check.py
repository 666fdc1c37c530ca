"""The submit builds the model, as `rfesim check` does: what the model compiler refuses (here
a line end that starts on the other, which validation accepts) is a 422 at POST /jobs and
POST /sweeps naming the field (and the load case), instead of a 202 and a job that fails in
the worker once the queue reaches it. The build is bounded by a time budget
(RFESIM_SUBMIT_MODEL_CHECK_SECONDS) and runs once per distinct model of a sweep."""
from __future__ import annotations

import copy
import threading

import httpx

from service import validate
from service.settings import Settings
from service_helpers import RISER, SCENARIOS, riser

# a 10 m riser from end A, fixed 1 m above the rest point of end B (5 m under the ship), to the
# ship, which heaves 1 m with a phase of 90 deg and no ramp: at t = 0 the ship is 1 m up and end
# B starts on end A. Validation places vessels at rest (the ends 1 m apart: accepted); the model
# compiler places them at t = 0 and refuses it
MOVING = {"vessels.ship.motion.ramp_duration": 0.0, "vessels.ship.motion.heave.phase_deg": 90.0,
          "lines.riser.end_a.position": [0.0, 0.0, -4.0], "lines.riser.length": 10.0, "lines.riser.elements": 40}
START_ON_END_A = {**MOVING, "vessels.ship.motion.heave.amplitude": 1.0}
RAMP = "dynamics: vessels.ship.motion.ramp_duration: 0 s, so vessel 'ship' starts its harmonic motion"
COINCIDE_DETAIL = {"loc": ["lines", "riser", "end_b", "position"], "msg": "end B coincides with end A",
                   "type": "value_error"}
# the bundled S-lay with its pipe cut to 40 m, end B free: shorter than the stinger's rollers
SHORT_PIPE = {"lines.pipe.length": 40.0, "lines.pipe.end_b": {"attach": "free"}, "lines.pipe.elements": 20}
SHORT_PIPE_DETAIL = {"loc": ["supports"], "msg": "the line is 40.0 m long but reaches the last roller only "
                                                 "after 65.2052 m: make it longer", "type": "value_error"}

# the 100 m riser made 130 m long: from end A on the seabed (z = -49.9) to end B 5 m under the
# ship at the origin, 70 m across and 44.9 m up, it can hang vertically and lie straight on the
# seabed over 70 + 44.9 = 114.9 m; the other 15.1 m fold on the seabed (no unique static shape),
# which only the built model tells (LineInfo.seabed_fold)
FOLD = ("statics: line 'riser' runs from the seabed to a point 44.9 m up and 70 m away, and is 15.1 m longer "
        "(130 m) than can hang vertically and lie straight on the seabed (114.9 m): the rest folds on the "
        "seabed, which has no unique static shape; shorten the line, move its ends apart, or set "
        "analysis.statics.enabled to false")

NOT_BUILT = "model check: the model was not built at submit: the checks took more than"


def _totals(api) -> tuple[int, int]:
    return api.client.get("/jobs").json()["total"], api.client.get("/sweeps").json()["total"]


def _cancel_all(api, job_ids) -> None:
    for j in job_ids:
        api.client.delete(f"/jobs/{j}")


def test_a_job_whose_model_the_compiler_refuses_is_a_422_naming_the_field(api):
    before = _totals(api)
    r = api.client.post("/jobs", json=riser(**START_ON_END_A))
    assert r.status_code == 422, r.text
    assert r.json()["detail"] == [COINCIDE_DETAIL]
    # a bundled scenario made wrong by overrides: a support past the line's end
    r = api.client.post("/jobs", json={"scenario": "s_lay", "overrides": SHORT_PIPE})
    assert r.status_code == 422, r.text
    assert r.json()["detail"] == [SHORT_PIPE_DETAIL]
    assert _totals(api) == before                      # no job was queued


def test_a_sweep_with_a_case_whose_model_fails_is_a_422_naming_the_load_case(api):
    before = _totals(api)
    # the heave amplitude moves the ship's start: the case of 1 m starts end B on end A
    body = {"scenario": riser(**MOVING), "vary": {"analysis.dynamics.duration": [1, 2],
                                                  "vessels.ship.motion.heave.amplitude": [0.5, 1.0]}}
    r = api.client.post("/sweeps", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"] == [{**COINCIDE_DETAIL, "msg": "end B coincides with end A (load case "
                                   "analysis.dynamics.duration=1, vessels.ship.motion.heave.amplitude=1.0)"}]
    # only a path the compiler does not read varied: one build, named by the first case
    body = {"scenario": "s_lay", "overrides": SHORT_PIPE, "vary": {"analysis.dynamics.duration": [1, 2]}}
    r = api.client.post("/sweeps", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"] == [{**SHORT_PIPE_DETAIL,
                                   "msg": SHORT_PIPE_DETAIL["msg"] + " (load case analysis.dynamics.duration=1)"}]
    assert _totals(api) == before


def test_valid_submits_are_accepted_with_the_warnings_of_their_built_model(api):
    off = {"analysis.dynamics.enabled": False}
    r = api.client.post("/jobs", json=riser(**off))
    assert r.status_code == 202 and r.json()["warnings"] == [], r.text
    jobs = [r.json()["id"]]
    r = api.client.post("/jobs", json=riser(**off, **{"lines.riser.length": 130.0}))
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == [FOLD]
    jobs.append(r.json()["id"])
    assert api.job(jobs[-1])["warnings"][0] == FOLD
    # a sweep: the warning of the case whose model has it, naming the case
    body = {"scenario": riser(**off), "vary": {"lines.riser.length": [100.0, 130.0]}}
    r = api.client.post("/sweeps", json=body)
    assert r.status_code == 202, r.text
    assert r.json()["warnings"] == [f"{FOLD} (load case lines.riser.length=130.0)"]
    first, second = r.json()["jobs"]
    jobs += [first, second]
    assert api.job(first)["warnings"] == [] and api.job(second)["warnings"] == [FOLD]
    _cancel_all(api, jobs)


def test_a_sweep_builds_each_distinct_model_once(tmp_path):
    settings = Settings(data_dir=tmp_path / "data")
    built = []
    check = validate.ModelCheck(5.0, build=lambda sc: built.append(sc) or [])
    # the ship's heave is ramped in: it starts at rest whatever its amplitude, so amplitude and
    # duration do not change the model; the elements do: 2 models for 12 cases
    vary = {"vessels.ship.motion.heave.amplitude": [0.5, 1.0, 2.0], "analysis.dynamics.duration": [1, 2],
            "lines.riser.elements": [12, 14]}
    _, cases, _ = validate.prepare_sweep({"scenario": riser(), "vary": vary}, settings, SCENARIOS,
                                         warnings=[], model_check=check, notes=[])
    assert len(cases) == 12
    assert [sc.lines["riser"].elements for sc in built] == [12, 14]
    # without a ramp and with a phase of 90 deg the ship starts displaced by the amplitude: each
    # amplitude is a model of its own (the compiler places the vessel at t = 0)
    built.clear()
    moving = riser(**{"vessels.ship.motion.ramp_duration": 0.0, "vessels.ship.motion.heave.phase_deg": 90.0})
    validate.prepare_sweep({"scenario": moving, "vary": {"vessels.ship.motion.heave.amplitude": [0.5, 1.0],
                                                         "analysis.dynamics.duration": [1, 2]}},
                           settings, SCENARIOS, warnings=[], model_check=check, notes=[])
    assert [sc.vessels["ship"].motion.heave.amplitude for sc in built] == [0.5, 1.0]
    assert validate.load_only("analysis.dynamics") and validate.load_only("vessels.ship.motion.heave.period")
    assert validate.load_only("environment.water.waves.hs")
    assert not validate.load_only("analysis.statics.start") and not validate.load_only("vessels.ship.position")
    assert not validate.load_only("analysis") and not validate.load_only("analysis.dynamicsx")


def test_a_build_that_does_not_finish_within_the_budget_is_not_waited_for(tmp_path):
    settings = Settings(data_dir=tmp_path / "data")
    built = []
    check = validate.ModelCheck(0.05, build=lambda sc: built.append(sc) or validate.model_warnings(sc))
    # another submit's build holds the check thread: this one's budget runs out first
    release = threading.Event()
    check.submit(release.wait, 30.0)
    warnings: list[str] = []
    validate.prepare_job(riser(**START_ON_END_A), settings, SCENARIOS, model_check=check, warnings=warnings)
    ramp, note = warnings               # the load warning of its unramped heave (no model needed), then the note
    assert ramp.startswith(RAMP)
    assert note.startswith(NOT_BUILT) and "0.05 s (RFESIM_SUBMIT_MODEL_CHECK_SECONDS)" in note
    notes: list[str] = []
    validate.prepare_sweep({"scenario": riser(**START_ON_END_A), "vary": {"analysis.dynamics.duration": [1, 2, 3]}},
                           settings, SCENARIOS, warnings=[], model_check=check, notes=notes)
    assert notes == [note + " (3 of 3 load cases, 1 of 1 distinct models, were not built)"]
    release.set()
    # the dropped builds never run; the thread builds the next submit's model
    check.seconds = 30.0
    try:
        validate.prepare_job(riser(**START_ON_END_A), settings, SCENARIOS, model_check=check, warnings=[])
        raise AssertionError("the coincident ends were accepted")
    except validate.Invalid as exc:
        assert exc.detail() == [COINCIDE_DETAIL]
    assert len(built) == 1


def test_the_budget_and_the_switch_are_service_settings(make_server):
    # a 20000-RFE riser (the service's limit) takes seconds to build (its catenary start shape):
    # with a budget of 0.2 s the submit answers 202 at once, saying the model was not built
    big = copy.deepcopy(RISER)
    big["lines"]["riser"]["elements"] = 19999
    big["analysis"] = {"statics": {"enabled": False}, "dynamics": {"duration": 1.0, "output_interval": 0.5,
                                                                     "integrator": {"kind": "generalized-alpha",
                                                                                    "time_step": 0.05}}}
    env = {"RFESIM_WORKERS": "1", "RFESIM_WARMUP": "false"}
    server = make_server(env={**env, "RFESIM_SUBMIT_MODEL_CHECK_SECONDS": "0.2"}, wait_workers=False)
    with httpx.Client(base_url=server.url, timeout=60.0) as c:
        r = c.post("/jobs", json=big)
        assert r.status_code == 202, r.text
        (note,) = r.json()["warnings"]
        assert note.startswith(NOT_BUILT) and "0.2 s" in note
        c.delete(f"/jobs/{r.json()['id']}")
    # switched off: the scenario is only validated, as before (the worker finds the error)
    server = make_server(env={**env, "RFESIM_SUBMIT_MODEL_CHECK": "false"}, wait_workers=False)
    with httpx.Client(base_url=server.url, timeout=60.0) as c:
        r = c.post("/jobs", json=riser(**START_ON_END_A))
        assert r.status_code == 202, r.text
        (ramp,) = r.json()["warnings"]     # the validation's own (no model): the heave without a ramp
        assert ramp.startswith(RAMP), r.text
        c.delete(f"/jobs/{r.json()['id']}")
