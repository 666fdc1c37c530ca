"""Synchronous checks of what a client submits: the scenario (rfesim.load_scenario), its
file references (inside the data directory only), the service's limits and, within a time
budget, the model the run would build (:class:`ModelCheck`, as ``rfesim check``).

Every problem is a :class:`Invalid` holding ``(loc, msg)`` pairs, answered as 422
``{"detail": [{"loc": [...], "msg": ...}]}``.
"""
from __future__ import annotations

import functools
import json
import logging
import math
import os
import queue
import re
import threading
import time
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from pathlib import Path
from typing import Any

from .paths import SAFE_NAME, check_scenario_paths, files_dir, snapshot_data_files

WRAPPER_KEYS = ("scenario", "overrides")


class Invalid(Exception):
    def __init__(self, errors: list[tuple[list, str]]):
        self.errors = errors
        super().__init__("; ".join(f"{'.'.join(map(str, loc))}: {msg}" for loc, msg in errors))

    def detail(self) -> list[dict]:
        return [{"loc": list(loc), "msg": msg, "type": "value_error"} for loc, msg in self.errors]


def _loc(dotted: str) -> list[str]:
    return dotted.split(".") if dotted else ["body"]


def _scenario_errors(exc, suffix: str = "") -> Invalid:
    return Invalid([(_loc(f), r + suffix) for f, r in exc.errors])


def parse_body(body: bytes, content_type: str | None) -> Any:
    """JSON (or YAML when the content type says so) -> plain data; Invalid if not.

    YAML alias expansion is capped by :func:`rfesim.scenario.parse_text` itself."""
    from rfesim import ScenarioError
    from rfesim.scenario import parse_text

    fmt = "yaml" if content_type and "yaml" in content_type.lower() else "json"
    try:
        return parse_text(body, fmt)
    except ScenarioError as exc:
        raise Invalid([(["body"], r) for _, r in exc.errors]) from None


def bundled(name: str, scenarios_dir: Path | None) -> tuple[dict, frozenset[Path]]:
    """A bundled example scenario by name (``cantilever_pipe``), as a dict, and the data
    files it may read.

    The example's relative data files (``"file": "data/barge_100m_raos.json"``) are
    taken from the bundled scenarios folder, as ``rfesim run scenarios/<name>.json``
    does, and made absolute; those that lie inside that folder are returned as the only
    files outside ``<data>/files`` that the path guard accepts for this submission."""
    from rfesim.scenario import parse_text
    from rfesim.scenario.files import resolve_data_files

    if scenarios_dir is None:
        raise Invalid([(["scenario"], "this installation has no bundled scenarios")])
    stem = name[:-5] if name.endswith(".json") else name
    path = scenarios_dir / f"{stem}.json"
    if not SAFE_NAME.match(stem) or not path.is_file():
        known = ", ".join(sorted(p.stem for p in scenarios_dir.glob("*.json")))
        raise Invalid([(["scenario"], f"no bundled scenario {name!r} (available: {known})")])
    data = parse_text(path.read_bytes(), "json")
    root = Path(os.path.realpath(scenarios_dir))
    allowed = set()
    for value in _file_values(data):
        resolved = Path(os.path.realpath(root / value))       # an absolute value stays itself
        if root in resolved.parents:
            allowed.add(resolved)
    return resolve_data_files(data, root), frozenset(allowed)


def _file_values(data: Any) -> list[str]:
    """The string values of every ``file`` key of a raw scenario (csv and rao motions)."""
    out = []
    if isinstance(data, dict):
        for key, value in data.items():
            if key == "file" and isinstance(value, str) and value.strip() and "\x00" not in value:
                out.append(value)
            else:
                out += _file_values(value)
    elif isinstance(data, list):
        for value in data:
            out += _file_values(value)
    return out


def unwrap(data: Any, scenarios_dir: Path | None) -> tuple[Any, dict, frozenset[Path]]:
    """The body of POST /jobs: a scenario, or ``{"scenario": <scenario or bundled name>,
    "overrides": {dotted.path: value}}``. Returns (scenario data, overrides, the data
    files of a bundled scenario that the path guard accepts: none for a given scenario)."""
    if not (isinstance(data, dict) and "scenario" in data):
        return data, {}, frozenset()
    extra = [k for k in data if k not in WRAPPER_KEYS]
    if extra:
        raise Invalid([([str(k)], f"unknown key (allowed with 'scenario': {', '.join(WRAPPER_KEYS)})")
                       for k in extra])
    scenario = data["scenario"]
    allowed: frozenset[Path] = frozenset()
    if isinstance(scenario, str):
        scenario, allowed = bundled(scenario, scenarios_dir)
    elif not isinstance(scenario, dict):
        raise Invalid([(["scenario"], "must be a scenario (a mapping) or the name of a bundled scenario")])
    return scenario, check_overrides(data.get("overrides")), allowed


def check_overrides(overrides: Any) -> dict:
    if overrides is None:
        return {}
    if not isinstance(overrides, dict):
        raise Invalid([(["overrides"], "must be a mapping of dotted scenario paths to values")])
    bad = [k for k in overrides if not isinstance(k, str) or not k.strip() or len(k) > 500]
    if bad:
        raise Invalid([(["overrides"], f"bad path {k!r}: use a dotted path such as 'lines.pipe.elements'")
                       for k in bad])
    return overrides


def to_json(value: Any, loc: list) -> str:
    """Compact JSON text of plain data (Invalid if it has values JSON cannot hold)."""
    try:
        return json.dumps(value, separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise Invalid([(loc, f"cannot be stored as JSON: {exc}")]) from None


def output_times(sc) -> int:
    """The output times a run stores, as the dynamics driver picks them: its own
    :func:`rfesim.solvers.dynamics.output_schedule` (an output interval shorter than the
    step keeps the interval and shortens the step), plus the output at the start."""
    from rfesim.solvers.dynamics import output_schedule

    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0):
        return 1
    T = float(dyn.duration)
    integ = dyn.integrator
    adaptive = integ.kind == "adaptive"
    step = getattr(integ, "time_step", None)
    if dyn.output_interval is None and not adaptive and not step:
        # RK4 with its step estimated from the stiffest SDE at run time: without an output
        # interval the driver stores every step up to 10000 outputs, then every few steps
        return 10_002
    # the step only matters without an output interval (then it is the given fixed step);
    # the adaptive driver ignores it
    _, n_out, _ = output_schedule(T, float(step or T), dyn.output_interval, adaptive)
    return n_out + 1


def rfe_count(sc) -> tuple[int, dict[str, int]]:
    """RFEs of a validated Scenario, and per group (``lines``, ``chains``): what its
    results hold per output time. A line or a flexible chain link of n elements has n + 1
    RFEs; a rigid chain link is output as a line of one element (2 RFEs)."""
    groups = {"lines": sum(line.elements + 1 for line in sc.lines.values())}
    chains = 0
    for chain in (getattr(sc, "chains", None) or {}).values():
        for link in chain.links.values():
            chains += 2 if link.rigid else int(link.elements) + 1
    if chains:
        groups["chains"] = chains
    return sum(groups.values()), groups


def check_limits(sc, settings, prefix: list | None = None) -> None:
    """The service's limits on one validated Scenario (Invalid naming the field)."""
    prefix = prefix or []
    errors = []
    from rfesim.scenario.load import check_runnable

    for field, reason in check_runnable(sc):        # what a run refuses (rfesim.scenario.load)
        errors.append((prefix + [field], reason))
    nrfe, groups = rfe_count(sc)
    if nrfe > settings.max_rfes:
        # name the group holding most of them (the field to make smaller)
        field = max(groups, key=groups.get)
        parts = [f"{n} in {g}" for g, n in groups.items() if n]
        where = f" ({', '.join(parts)})" if len(parts) > 1 else ""
        errors.append((prefix + [field], f"the scenario has {nrfe} RFEs{where}: sum over "
                                         f"lines and flexible chain links of elements + 1, 2 per rigid chain link; "
                                         f"this service takes at most {settings.max_rfes} (RFESIM_MAX_RFES)"))
    dyn = sc.analysis.dynamics
    if dyn.enabled and dyn.duration > settings.max_duration:
        errors.append((prefix + ["analysis", "dynamics", "duration"],
                       f"{dyn.duration:g} s is longer than this service simulates ({settings.max_duration:g} s; "
                       f"RFESIM_MAX_DURATION)"))
    ntimes = output_times(sc)
    values = ntimes * max(1, nrfe)
    if not errors and values > settings.max_output_values:
        errors.append((prefix + ["analysis", "dynamics", "output_interval"],
                       f"{ntimes} output times x {nrfe} RFEs = {values} stored values, more than this "
                       f"service keeps for one job ({settings.max_output_values}; RFESIM_MAX_OUTPUT_VALUES): "
                       f"give a longer output_interval"))
    if errors:
        raise Invalid(errors)


def load_warnings(sc) -> list[str]:
    """The warnings of a validated Scenario that need no model and no solve, answered at
    submit (a few milliseconds): the templates' warnings (a stinger mesh too coarse for its
    rollers: what ``rfesim check`` shows), a duration the output interval does not divide,
    the RAO vessels whose table leaves out a noticeable part of the sea
    (rfesim.sea.rao.rao_range_warnings) and the prescribed motions that start or stop with a
    jolt (rfesim.scenario.motion_warnings.input_motion_warnings: no ramp, a table that ends
    moving). Those that need the built model (no unique static
    shape) are :func:`model_warnings`, found by :class:`ModelCheck`; those that need the
    solution (statics: buckling, fem shear; dynamics: shear limit passed, slack ropes...) are
    found by the worker when the job runs and added to the job's record then
    (``service.worker.execute``)."""
    from rfesim.scenario.motion_warnings import input_motion_warnings
    from rfesim.sea.rao import rao_range_warnings
    from rfesim.solvers.dynamics import output_interval_warning

    out = [f"statics: {w}" for w in getattr(sc, "_template_warnings", [])]
    dyn = sc.analysis.dynamics
    if dyn.enabled and dyn.duration > 0:
        if dyn.output_interval:
            note = output_interval_warning(float(dyn.duration), float(dyn.output_interval))
            if note:
                out.append(f"dynamics: {note}")
        out += [f"dynamics: {w}" for w in input_motion_warnings(sc) + rao_range_warnings(sc)]
    return out


def prepare_job(data: Any, settings, scenarios_dir: Path | None, model_check: "ModelCheck | None" = None,
                warnings: list | None = None):
    """(scenario dict to store, validated Scenario) for POST /jobs. With a :class:`ModelCheck`,
    the scenario's model is built too (Invalid with what the model compiler refuses); with a
    list as ``warnings``, the scenario's :func:`load_warnings` and those of its built model are
    appended to it."""
    from rfesim import ScenarioError, load_scenario
    from rfesim.scenario import apply_overrides
    from rfesim.scenario.files import resolve_data_files

    scenario, overrides, allowed = unwrap(data, scenarios_dir)
    if not isinstance(scenario, dict):
        # never a string: rfesim.load_scenario would read a string as a file path
        raise Invalid([(["body"], "must be a scenario (a JSON object), or {\"scenario\": <scenario or bundled "
                                  "name>, \"overrides\": {dotted.path: value}}")])
    try:
        if overrides:
            scenario = apply_overrides(scenario, overrides)
        path_errors = check_scenario_paths(scenario, settings.resolved_data_dir(), allowed=allowed)
        if path_errors:
            raise Invalid([(_loc(f), r) for f, r in path_errors])
        # relative data files are the service's <data_dir>/files, never its working directory:
        # made absolute, then copied as they are now (the job runs on the files it was
        # submitted with, not on what a later upload put in their place), and checked as copied
        scenario = resolve_data_files(scenario, files_dir(settings.resolved_data_dir()))
        scenario = snapshot_data_files(scenario, settings.resolved_data_dir())
        sc = load_scenario(scenario, base_dir=files_dir(settings.resolved_data_dir()))
    except ScenarioError as exc:
        raise _scenario_errors(exc) from None
    check_limits(sc, settings)
    if warnings is not None:
        warnings += load_warnings(sc)
    if model_check is not None:
        built, notes = model_check.build_cases([sc])
        if warnings is not None:
            warnings += [w for found in built for w in found] + notes
    return scenario, sc


def prepare_sweep(data: Any, settings, scenarios_dir: Path | None,
                  warnings: list | None = None, model_check: "ModelCheck | None" = None,
                  notes: list | None = None) -> tuple[dict, list[tuple[dict, dict]], str]:
    """(vary, [(case values, scenario dict)], name) for POST /sweeps. With a list as
    ``warnings``, each case's :func:`load_warnings` (and with a :class:`ModelCheck` the warnings
    of its built model) are appended to it, one list per case. With a :class:`ModelCheck`, the
    cases' models are built once per distinct structure (:func:`structure_key`), first case
    first, within the check's time budget; a build error is Invalid naming the load case, and
    what the check has to say about the sweep as a whole (cases left unbuilt) is appended to
    ``notes``."""
    from rfesim import ScenarioError, load_scenario
    from rfesim.scenario import apply_overrides
    from rfesim.scenario.files import resolve_data_files
    from rfesim.sweep import grid

    if not isinstance(data, dict):
        raise Invalid([(["body"], "must be a mapping: {\"scenario\": ..., \"vary\": {path: [values]}}")])
    keys = ("scenario", "vary", "overrides")
    extra = [k for k in data if k not in keys]
    missing = [k for k in ("scenario", "vary") if k not in data]
    if extra or missing:
        raise Invalid([([str(k)], f"unknown key (allowed: {', '.join(keys)})") for k in extra]
                      + [([k], "required field is missing") for k in missing])
    scenario, overrides, allowed = unwrap({"scenario": data["scenario"], "overrides": data.get("overrides")}, scenarios_dir)
    vary = data["vary"]
    if not isinstance(vary, dict) or not vary:
        raise Invalid([(["vary"], "must be a non-empty mapping of dotted scenario paths to lists of values")])
    errors = []
    for path, values in vary.items():
        # a YAML body can have keys that are not text (``1:``, ``2.5:``, ``~:``)
        if not isinstance(path, str):
            errors.append((["vary", str(path)], f"must be a dotted scenario path such as 'lines.pipe.elements' "
                                                f"(text), got {type(path).__name__} {path!r}"))
        elif not path.strip() or len(path) > 500:
            errors.append((["vary", path], "must be a dotted scenario path such as 'lines.pipe.elements'"))
        elif not isinstance(values, list) or not values:
            errors.append((["vary", path], "must be a non-empty list of values"))
    if errors:
        raise Invalid(errors)
    # a path both overridden and varied: the varied values replaced the override, silently (and
    # an override inside a varied path, lines.pipe.end_b.position under a varied lines.pipe.end_b,
    # was lost the same way); refused as rfesim sweep refuses it
    from rfesim.sweep import replaced_overrides

    errors = [(["vary", path], reason) for path, reason in replaced_overrides(vary, overrides)]
    if errors:
        raise Invalid(errors)
    to_json(vary, ["vary"])
    ncases = math.prod(len(v) for v in vary.values())
    limit = settings.max_queued_jobs
    if ncases > limit:
        raise Invalid([(["vary"], f"{ncases} load cases; this service takes at most {limit} at once "
                                  f"(RFESIM_MAX_QUEUED_JOBS)")])
    try:
        points = grid(vary)               # refuses a varied path inside another one
    except ScenarioError as exc:
        raise Invalid([(["vary", f], r) for f, r in exc.errors]) from None
    name = scenario.get("name", "") if isinstance(scenario, dict) else ""
    cases = []
    # structure -> (load case, its case indices): the Scenario objects are not kept (one can hold
    # megabytes, its RAO tables), the build loads its first case again
    builds: dict[Any, tuple[str, list[int]]] = {}
    copies: dict[str, str] = {}          # each data file read and copied once for all the cases
    for i, values in enumerate(points):
        where = ", ".join(f"{k}={json.dumps(v)}" for k, v in values.items())
        try:
            case = apply_overrides(scenario, {**overrides, **values})
            path_errors = check_scenario_paths(case, settings.resolved_data_dir(), allowed=allowed)
            if path_errors:
                raise Invalid([(_loc(f), f"{r} (load case {where})") for f, r in path_errors])
            case = resolve_data_files(case, files_dir(settings.resolved_data_dir()))
            case = snapshot_data_files(case, settings.resolved_data_dir(), copies)
            sc = load_scenario(case, base_dir=files_dir(settings.resolved_data_dir()))
        except ScenarioError as exc:
            raise _scenario_errors(exc, f" (load case {where})") from None
        try:
            check_limits(sc, settings)
        except Invalid as exc:
            raise Invalid([(loc, f"{msg} (load case {where})") for loc, msg in exc.errors]) from None
        cases.append((values, case))
        if warnings is not None:
            warnings.append(load_warnings(sc))
        if model_check is not None:
            key = structure_key(values, sc, i)
            if key in builds:
                builds[key][1].append(i)
            else:
                builds[key] = (where, [i])
    if model_check is not None and builds:
        groups = list(builds.values())
        base_dir = files_dir(settings.resolved_data_dir())
        loaders = [functools.partial(load_scenario, cases[members[0]][1], base_dir=base_dir) for _, members in groups]
        built, more = model_check.build_cases(loaders, [where for where, _ in groups])
        for (_, members), found in zip(groups, built):
            if warnings is not None:
                for i in members:
                    warnings[i] = warnings[i] + found
        if more and notes is not None:
            unbuilt = sum(len(members) for _, members in groups[len(built):])
            notes += [f"{m} ({unbuilt} of {len(cases)} load cases, {len(groups) - len(built)} of {len(groups)} "
                      f"distinct models, were not built)" for m in more]
    return vary, cases, str(name)


# --------------------------------------------------------------------------- the model at submit

log = logging.getLogger("rfesim.service")

# Varied paths the model compiler does not read (rfesim.model.compile reads neither the dynamics
# nor the modal settings, and the sea's waves and current only become load arrays), and the
# vessels' motions, which it reads only through the vessels' poses at t = 0 (those go into the key
# instead: a motion that moves the vessel's start, a harmonic one without a ramp, is built again).
LOAD_ONLY = ("analysis.dynamics", "analysis.modal", "environment.water.waves", "environment.water.current")
_MOTION = re.compile(r"^vessels\.[^.]+\.motion(\.|$)")


def load_only(path: str) -> bool:
    """True for a dotted scenario path whose values cannot change the built model but through
    the vessels' start poses: under ``analysis.dynamics``, ``analysis.modal``,
    ``environment.water.waves``, ``environment.water.current`` or ``vessels.<name>.motion``."""
    return bool(_MOTION.match(path)) or any(path == p or path.startswith(p + ".") for p in LOAD_ONLY)


def structure_key(values: dict, sc, index: int) -> Any:
    """What a sweep's load case builds its model from, among what the sweep varies: the values
    of its varied paths but the :func:`load_only` ones, and, when some of those are varied, the
    poses of the vessels at t = 0 (what the compiler takes of a motion). Cases of one key build
    the same model: it is built once, for the first of them."""
    from rfesim.vessel import make_vessel_motion

    key = [(p, json.dumps(v, sort_keys=True)) for p, v in values.items() if not load_only(p)]
    if len(key) < len(values):
        try:
            for name, vessel in sc.vessels.items():
                k = make_vessel_motion(vessel, sc.environment).kinematics(0.0)
                pose = [round(float(x), 9) + 0.0 for x in [*k.p, *k.R.ravel()]]
                key.append((f"vessels.{name}@t=0", tuple(pose)))
        except Exception:       # noqa: BLE001 - the build says what is wrong: build this case itself
            key.append(("case", index))
    return tuple(key)


def model_warnings(sc) -> list[str]:
    """Build the model of a validated Scenario as a run does (``rfesim.api.check_model``:
    ScenarioError naming the field when the compiler refuses it), and return the warnings that
    need the built model but no solve: lines with no unique static shape (slack folding on the
    seabed, a buoyant line floating free; what a run's statics logs, ``rfesim.api._static_state``)."""
    from rfesim.api import check_model

    return [f"statics: {w}" for w in check_model(sc)]


class ModelCheck:
    """Builds scenarios' models at submit, in one thread of its own, within a time budget per
    submit (``RFESIM_SUBMIT_MODEL_CHECK_SECONDS``).

    The request thread waits for each build at most until the budget is spent. A build that
    has not finished by then cannot be stopped (it is Python): it finishes in the check thread
    and its outcome is dropped; the submit is accepted with a warning saying the model was not
    built (a build error then fails the job when it runs, as before). One thread keeps the
    web process's building to one core at a time, whatever the number of submits: a submit whose
    budget runs out while others' builds hold the thread is answered the same way, and its
    build, not started, is dropped."""

    def __init__(self, seconds: float = 3.0, build=None):
        self.seconds = float(seconds)
        self._build = build or model_warnings
        self._queue: queue.SimpleQueue = queue.SimpleQueue()
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    def _run(self) -> None:
        while True:
            fut, fn, args = self._queue.get()
            if not fut.set_running_or_notify_cancel():
                continue
            try:
                fut.set_result(fn(*args))
            except BaseException as exc:        # noqa: BLE001 - handed to the waiting request
                fut.set_exception(exc)

    def submit(self, fn, *args) -> Future:
        """Run ``fn(*args)`` in the check thread (a daemon: a build left running does not hold
        the service's exit)."""
        with self._lock:
            if self._thread is None or not self._thread.is_alive():
                self._thread = threading.Thread(target=self._run, name="rfesim-model-check", daemon=True)
                self._thread.start()
        fut: Future = Future()
        self._queue.put((fut, fn, args))
        return fut

    def _build_one(self, item) -> list[str]:
        return self._build(item() if callable(item) else item)

    def build_cases(self, scs: list, wheres: list[str] | None = None) -> tuple[list[list[str]], list[str]]:
        """Build each validated Scenario's model in turn (an item may be a function returning
        it, called in the check thread): ([warnings of each built one], notes).
        Invalid (naming the field, and the load case ``wheres[i]`` when given) at the first one
        the compiler refuses. Once the budget is spent the rest are not built: the lists of
        warnings stop there and ``notes`` says so."""
        from rfesim import ScenarioError

        deadline = time.monotonic() + self.seconds
        out: list[list[str]] = []
        for i, sc in enumerate(scs):
            suffix = f" (load case {wheres[i]})" if wheres else ""
            fut = self.submit(self._build_one, sc)
            try:
                found = fut.result(timeout=max(0.0, deadline - time.monotonic()))
            except FutureTimeout:
                fut.cancel()            # not started yet (another submit's build holds the thread): dropped
                return out, [f"model check: the model was not built at submit: the checks took more than "
                             f"{self.seconds:g} s (RFESIM_SUBMIT_MODEL_CHECK_SECONDS); what the model compiler "
                             f"refuses (ends that coincide, a support past the line's end, ...) fails the job "
                             f"when it runs"]
            except ScenarioError as exc:
                raise _scenario_errors(exc, suffix) from None
            except Exception as exc:    # noqa: BLE001 - no field to name: the run reports it
                log.warning("building the model at submit failed%s", suffix, exc_info=True)
                found = [f"model check: the model could not be built at submit ({type(exc).__name__}: {exc}); "
                         f"the job's run reports what it finds"]
            out.append(found)
        return out, []


def sweep_warnings(cases: list[tuple[dict, list[str]]], limit: int = 50) -> list[str]:
    """The load-time warnings of a sweep's cases ``[(case values, warnings)]``, for its submit
    answer: a warning every case has once, with "(all n load cases)"; the others once per case
    with the case's values, as its errors name them; at most ``limit`` (a last entry says how
    many more the cases' own jobs carry)."""
    n = len(cases)
    seen: dict[str, list[dict]] = {}
    for values, warnings in cases:
        for w in dict.fromkeys(warnings):
            seen.setdefault(w, []).append(values)
    out = []
    for w, where in seen.items():
        if len(where) == n:
            out.append(w if n == 1 else f"{w} (all {n} load cases)")
        else:
            out += [f"{w} (load case {', '.join(f'{k}={json.dumps(v)}' for k, v in values.items())})"
                    for values in where]
    if len(out) > limit:
        out = out[:limit] + [f"... and {len(out) - limit} more warnings (each load case's job lists its own)"]
    return out
