"""Synchronous checks of what a client submits: the scenario (rfesim.load_scenario), its
file references (inside the data directory only) and the service's limits.

Every problem is a :class:`Invalid` holding ``(loc, msg)`` pairs, answered as 422
``{"detail": [{"loc": [...], "msg": ...}]}``.
"""
from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

from .paths import SAFE_NAME, check_scenario_paths, files_dir

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
    and the RAO vessels whose table leaves out a noticeable part of the sea
    (rfesim.sea.rao.rao_range_warnings). The warnings that need the compiled model or the
    solution (statics: no unique static shape, buckling, fem shear; dynamics: shear limit
    passed, slack ropes...) are found by the worker when the job runs and added to the job's
    record then (``service.worker.execute``)."""
    from rfesim.sea.rao import rao_range_warnings
    from rfesim.solvers.dynamics import output_interval_warning

    out = [f"statics: {w}" for w in getattr(sc, "_template_warnings", [])]
    dyn = sc.analysis.dynamics
    if dyn.enabled and dyn.duration > 0:
        if dyn.output_interval:
            note = output_interval_warning(float(dyn.duration), float(dyn.output_interval))
            if note:
                out.append(f"dynamics: {note}")
        out += [f"dynamics: {w}" for w in rao_range_warnings(sc)]
    return out


def prepare_job(data: Any, settings, scenarios_dir: Path | None):
    """(scenario dict to store, validated Scenario) for POST /jobs."""
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
        # store them absolute so the worker reads the same files
        scenario = resolve_data_files(scenario, files_dir(settings.resolved_data_dir()))
        sc = load_scenario(scenario, base_dir=files_dir(settings.resolved_data_dir()))
    except ScenarioError as exc:
        raise _scenario_errors(exc) from None
    check_limits(sc, settings)
    return scenario, sc


def prepare_sweep(data: Any, settings, scenarios_dir: Path | None,
                  warnings: list | None = None) -> tuple[dict, list[tuple[dict, dict]], str]:
    """(vary, [(case values, scenario dict)], name) for POST /sweeps. With a list as
    ``warnings``, each case's :func:`load_warnings` are appended to it, one list per case."""
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
    for values in points:
        where = ", ".join(f"{k}={json.dumps(v)}" for k, v in values.items())
        try:
            case = apply_overrides(scenario, {**overrides, **values})
            path_errors = check_scenario_paths(case, settings.resolved_data_dir(), allowed=allowed)
            if path_errors:
                raise Invalid([(_loc(f), f"{r} (load case {where})") for f, r in path_errors])
            case = resolve_data_files(case, files_dir(settings.resolved_data_dir()))
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
    return vary, cases, str(name)


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
