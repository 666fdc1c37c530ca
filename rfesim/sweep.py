"""Parameter sweeps: one scenario, a grid of load cases, one table of summary results.

    rfesim sweep scenarios/catenary_riser.json \\
        --vary vessels.fpso.motion.heave.amplitude=1,2,3 \\
        --vary environment.water.density=1020,1030 -o table.csv

From Python (the local pool starts its worker processes with the ``spawn`` method, which
imports the main module again: a script needs the ``__main__`` guard)::

    from rfesim.sweep import run_sweep

    if __name__ == "__main__":
        rows = run_sweep("scenarios/catenary_riser.json", {"vessels.fpso.motion.heave.amplitude": [1, 2, 3]})

Cases run in parallel processes: a local process pool by default, or any executor with
``submit(fn, *args) -> future`` whose futures have ``.result()`` — a
``concurrent.futures`` executor or a ``distributed.Client`` (a Dask cluster, e.g. SLURM
through dask-jobqueue). Each process uses one numba/BLAS thread. A local worker process
that dies (killed, out of memory) fails only the case it was running: the pool is
started again for the others, and the cases it may have been running are run again,
alone (run_cases).

Summary columns (SI units): ``max_top_tension`` (N, largest over lines of the top tension:
the force at the end held on board, see :func:`line_top_tension`, for a crane template's
hoist rope the tension at its sheave; the lines of a crane's structure, its pedestal, boom,
legs, ..., are left out; the table's ``top_tension_at`` names the line and the end, e.g.
``riser end B``, ``lay tensioner`` or ``crane_rope sheave``),
``max_tension`` / ``min_tension`` (N, effective tension over the SDEs and times of the
lines outside a crane's structure: a crane's hoist rope, not its pedestal or boom in
compression), ``max_bend_moment`` (N*m, over all lines, a crane's boom and pedestal too: for a crane template
whose luffing cylinder or rope the case gives, the real frame's moments, with that actuator at its eye, at the
SDEs, the members' ends and the eye, rfesim.crane_results.structure_loads; the results file keeps the model's),
``touchdown_min`` / ``touchdown_max`` (m, range over time and
lines of the results' ``touchdown_arc_length``, the arc length from end A where seabed
contact begins; empty when no line touches the seabed), ``daf`` (dynamic amplification:
max top tension over the top tension at t = 0, the static one; for a crane's rope that of
rfesim.crane_results.crane_summary), ``wall_time`` (s),
``status`` (done / failed) and ``message``. The CSV file holds every number in full
precision; it gets each row as its case finishes, so an interrupted sweep (Ctrl-C,
SIGTERM: exit code 130) keeps the finished cases.
"""
from __future__ import annotations

import argparse
import contextlib
import copy
import csv
import itertools
import json
import logging
import math
import os
import sys
import threading
import time
from pathlib import Path
from typing import Any, Iterator

SUMMARY_COLUMNS = ("max_top_tension", "max_tension", "min_tension", "max_bend_moment", "touchdown_min",
                   "touchdown_max", "daf")
SUMMARY_UNITS = {"max_top_tension": "N", "max_tension": "N", "min_tension": "N", "max_bend_moment": "N*m",
                 "touchdown_min": "m", "touchdown_max": "m", "daf": "1", "wall_time": "s"}

# one numba / BLAS thread per worker process: parallelism comes from the load cases
WORKER_THREAD_ENV = {"NUMBA_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
                     "MKL_NUM_THREADS": "1"}


# --------------------------------------------------------------------------- summary of one run

def _finite_or_none(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def touchdown_range(res) -> tuple[float | None, float | None]:
    """(min, max) over time and lines of the touchdown arc length (the results'
    ``touchdown_arc_length``: arc length from end A of the point where seabed contact
    begins, seen from end B). (None, None) when no line touches the seabed."""
    import numpy as np

    values = [np.asarray(lr.touchdown_arc_length, dtype=float).ravel() for lr in res.lines.values()
              if lr.touchdown_arc_length is not None]
    values = np.concatenate(values) if values else np.zeros(0)
    if not np.any(np.isfinite(values)):
        return None, None
    return _finite_or_none(np.nanmin(values)), _finite_or_none(np.nanmax(values))


def line_top_tension(res, name: str):
    """``(top, where)``: the top tension of line ``name`` over time, (nt,) N, and which force
    it is (``"tensioner"``, ``"end A"`` or ``"end B"``).

    The top is the end held on board: for a line with supports (a pipelay line, end A on the
    vessel and end B pinned on the seabed) the force the tensioner (or collar) holds, or the
    axial force at end A without one (along the line's end tangent: rfesim.lay_results.lay_summary);
    otherwise the force at the
    end attached to a vessel, end B when both or neither are (a riser's top, as
    ``LineResults.top_tension``). The hoist rope of a crane template (``<crane>_rope``) is
    held at its sheave: the tension there (``"sheave"``), as
    rfesim.crane_results.crane_summary's ``rope_tension``."""
    import numpy as np

    from .crane_results import crane_names, rope_tension

    if len(res.time) and name.endswith("_rope") and name[:-len("_rope")] in crane_names(res):
        return rope_tension(res, name[:-len("_rope")])["rope_tension"], "sheave"
    lr = res.line(name)
    try:
        sc = json.loads(res.scenario_json) if res.scenario_json else {}
    except ValueError:
        sc = {}
    spec = (sc.get("lines") or {}).get(name) or {}
    supports = {s: v for s, v in (sc.get("supports") or {}).items() if isinstance(v, dict) and v.get("line") == name}
    if supports and len(res.time):
        from .lay_results import lay_summary

        try:
            top = np.asarray(lay_summary(res, name)["top_tension"], dtype=float)
        except Exception:   # a line type lay_summary cannot read: the force at the end on board below
            top = None
        if top is not None and top.shape == (len(res.time),):
            held = any(v.get("kind") == "tensioner" and s in res.tensioners for s, v in supports.items())
            return top, "tensioner" if held else "end A"
    vessels = sc.get("vessels") or {}
    on_vessel = [((spec.get(end) or {}).get("attach") in vessels) for end in ("end_a", "end_b")]
    if on_vessel[0] and not on_vessel[1]:
        return np.linalg.norm(np.asarray(lr.end_a_force), axis=-1), "end A"
    return np.asarray(lr.top_tension), "end B"


def _summary(res, scenario=None) -> tuple[dict[str, float | None], str | None]:
    """The summary columns and where the max top tension is (``"<line> <end>"``); a crane's
    structure lines with the real frame's bending moments where ``scenario`` (the case that
    ran) gives its luffing cylinder or rope (rfesim.crane_results.structure_loads)."""
    import numpy as np

    from .crane_results import crane_names, rope_tension, structure_lines, structure_loads

    out: dict[str, float | None] = {c: None for c in SUMMARY_COLUMNS}
    if len(res.time) == 0 or not res.lines:
        return out, None
    # a crane template's structure (pedestal, boom, legs, ...) is not a line held on board: its
    # top tension would be the pedestal's base force; the crane's hoist rope stands for it
    cranes = crane_names(res)
    structure = {line for c in cranes for line in structure_lines(res, c)}
    top = {name: line_top_tension(res, name) for name in res.lines if name not in structure}
    best = max(top, key=lambda n: np.nanmax(top[n][0]) if top[n][0].size else -np.inf)
    best_top, where = top[best]
    max_top = float(np.nanmax(best_top))
    out["max_top_tension"] = _finite_or_none(max_top)
    # tension over the lines that carry it (ropes, pipes, risers): a crane's pedestal and boom
    # are in compression, whose axial force would hide the rope going slack in min_tension
    carrying = [lr for name, lr in res.lines.items() if name not in structure]
    out["max_tension"] = _finite_or_none(max(np.nanmax(lr.tension) for lr in carrying))
    out["min_tension"] = _finite_or_none(min(np.nanmin(lr.tension) for lr in carrying))
    members = structure_loads(res, scenario)
    out["max_bend_moment"] = _finite_or_none(max(
        np.nanmax(members[name]["bend_moment"] if name in members else lr.bend_moment)
        for name, lr in res.lines.items()))
    out["touchdown_min"], out["touchdown_max"] = touchdown_range(res)
    static_top = float(best_top[0])
    if best.endswith("_rope") and best[:-len("_rope")] in cranes:
        # crane_summary's static reference: the hook load in air for a payload lifted off a deck
        static_top = rope_tension(res, best[:-len("_rope")])["static_tension"]
    if static_top > 1e-9 * max(1.0, abs(max_top)) and math.isfinite(static_top):
        out["daf"] = _finite_or_none(max_top / static_top)
    return out, f"{best} {where}"


def summarize(res, scenario=None) -> dict[str, float | None]:
    """The summary columns of one run's Results (None where not defined). The top tension
    is that of the end held on board (:func:`line_top_tension`); ``scenario``: the one that
    ran (a Scenario or its dict), whose crane templates give the real frame's bending moments
    of their structure (rfesim.crane_results.template_actuators)."""
    return _summary(res, scenario)[0]


# --------------------------------------------------------------------------- one load case

_case_tag = threading.local()       # the case a thread is running (run_case), for its log records
_plain_records = None               # the record factory before _tag_records put its own


def _tag_records() -> None:
    """Install, once per process, a log record factory that starts the message of every
    record logged while a thread runs a case with ``case N: `` (a sweep's warnings reach
    stderr from many worker processes; without the tag one cannot tell whose they are)."""
    global _plain_records
    if _plain_records is not None:
        return
    _plain_records = logging.getLogRecordFactory()

    def factory(*args, **kwargs):
        record = _plain_records(*args, **kwargs)
        index = getattr(_case_tag, "index", None)
        if index is not None and isinstance(record.msg, str):
            record.msg = f"case {index}: {record.msg}"
        return record

    logging.setLogRecordFactory(factory)


@contextlib.contextmanager
def _tagged(index: int) -> Iterator[None]:
    """Log records of this thread are tagged with the case ``index`` inside the block."""
    _tag_records()
    before = getattr(_case_tag, "index", None)
    _case_tag.index = index
    try:
        yield
    finally:
        _case_tag.index = before


def run_case(case: dict, index: int = 0) -> dict[str, Any]:
    """Run one load case (a scenario dict) and summarise it; runs in a worker process.

    Returns ``{"case", "status", "message", "wall_time", "top_tension_at", **summary}``; a
    run that diverges is summarised from its partial results with status "failed". What
    the run logs (warnings) starts with ``case <index>: ``.
    """
    with _tagged(index):
        return _run_case(case, index)


def _run_case(case: dict, index: int) -> dict[str, Any]:
    import rfesim

    wall0 = time.perf_counter()
    row: dict[str, Any] = {"case": index}
    try:
        res = rfesim.simulate(rfesim.load_scenario(case))
        row.update(status="done", message=res.message)
    except rfesim.SolverError as exc:
        res = exc.results
        row.update(status="failed", message=f"solver error: {exc}")
    except rfesim.ScenarioError as exc:
        res = None
        row.update(status="failed", message=f"scenario error: {exc}")
    summary, where = _summary(res, case) if res is not None else ({c: None for c in SUMMARY_COLUMNS}, None)
    row.update(summary)
    row["top_tension_at"] = where
    row["wall_time"] = time.perf_counter() - wall0
    return row


def _run_case_marked(case: dict, index: int, marker: str, fn=run_case) -> dict[str, Any]:
    """``fn(case, index)`` (:func:`run_case`) in a local worker process, first leaving the
    file ``marker``: the case had started when its worker died (run_cases)."""
    with open(marker, "w") as f:
        f.write(str(os.getpid()))
    return fn(case, index)


def _worker_init() -> None:
    """Local worker processes ignore Ctrl-C: the main process stops them (run_cases)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


# --------------------------------------------------------------------------- the grid

def parse_value(text: str) -> Any:
    """A value from the command line: JSON (numbers, true/false, null, lists, quoted
    text), else the text itself."""
    try:
        return json.loads(text)
    except ValueError:
        return text


def parse_vary(items: list[str]) -> dict[str, list]:
    """``["a.b=1,2,3", "c=[0,0,1],[0,0,2]"]`` -> ``{"a.b": [1, 2, 3], "c": [[0,0,1], [0,0,2]]}``.

    Values are split on commas outside brackets and quotes, each read as JSON when it is."""
    vary: dict[str, list] = {}
    for item in items:
        path, sep, values = item.partition("=")
        path = path.strip()
        if not sep or not path:
            raise ValueError(f"--vary {item!r}: expected PATH=V1,V2,...")
        if path in vary:
            raise ValueError(f"--vary {path} is given twice")
        parts = [p for p in _split_top_level(values) if p.strip() != ""]
        if not parts:
            raise ValueError(f"--vary {path}: no values")
        vary[path] = [parse_value(p.strip()) for p in parts]
    return vary


def _split_top_level(text: str) -> list[str]:
    parts, depth, quote, cur = [], 0, None, []
    for ch in text:
        if quote:
            cur.append(ch)
            if ch == quote:
                quote = None
            continue
        if ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append("".join(cur))
            cur = []
            continue
        cur.append(ch)
    parts.append("".join(cur))
    return parts


def grid(vary: dict[str, list]) -> list[dict[str, Any]]:
    """Every combination of the varied values, the last path varying fastest.

    Refused (ScenarioError naming both paths): a varied path inside another one, compared
    by dotted parts (``analysis.dynamics`` and ``analysis.dynamics.duration``, not
    ``lines.riser`` and ``lines.riser2``). The overrides of a case are applied one after
    the other, so one of the two would silently replace the other's values while the table
    still listed them."""
    from .errors import ScenarioError

    if not vary:
        return [{}]
    paths = list(vary)
    parts = [tuple(str(p).split(".")) for p in paths]
    overlaps = []
    for i, a in enumerate(parts):
        for j, b in enumerate(parts):
            if i != j and len(a) < len(b) and b[:len(a)] == a:
                overlaps.append((str(paths[j]), f"is inside the varied path '{paths[i]}': vary either "
                                                f"'{paths[i]}' or '{paths[j]}' (one would replace the other's "
                                                f"values in every load case)"))
    if overlaps:
        raise ScenarioError(overlaps)
    return [dict(zip(paths, combo)) for combo in itertools.product(*(vary[p] for p in paths))]


def _scenario_folder(scenario) -> Path | None:
    """The folder relative data-file paths are taken from: a scenario file's own folder
    (None for text, a dict or a Scenario: the current directory, as load_scenario does)."""
    if isinstance(scenario, os.PathLike) or (isinstance(scenario, str) and "\n" not in scenario
                                              and not scenario.lstrip().startswith(("{", "["))):
        return Path(scenario).parent
    return None


def _base_dict(scenario) -> dict:
    """The scenario as a plain dict (from a file path, JSON/YAML text, a dict or a Scenario)."""
    from .scenario import Scenario, validate_dict
    from .scenario.load import _read_file, parse_text

    if isinstance(scenario, Scenario):
        # the input it was validated from, with the fields assigned since: its pipelay and
        # crane templates are expanded again in every case (a varied water depth moves the
        # laid pipe's end; the expanded sections would keep the base's geometry)
        from .scenario.load import revalidated
        sc = revalidated(scenario)
        if sc._after:
            # assignments put onto sections a template made (no template field stands for
            # them): a case's input, with its templates, cannot carry them
            from .errors import ScenarioError
            raise ScenarioError([(".".join(str(k) for k in path),
                                  "was assigned in a section a template made, which a sweep makes again in every "
                                  "case from the template: give the template's fields (as overrides or varied "
                                  "values) instead") for path, _ in sc._after])
        if sc._source is not None:
            return copy.deepcopy(sc._source)
        return scenario.model_dump(mode="json", warnings=False)
    if isinstance(scenario, dict):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        folder = _scenario_folder(scenario)
        data = parse_text(scenario) if folder is None else parse_text(*_read_file(Path(scenario)))
        if folder is not None:                   # data files are relative to the scenario file
            from .scenario.files import resolve_data_files
            data = resolve_data_files(data, folder)
    else:
        data = scenario
    if not isinstance(data, dict):
        validate_dict(data)                      # raises the usual ScenarioError
    return data


def _named_maps() -> tuple[str, ...]:
    """The scenario's top-level maps of named objects (vessels, lines, line_types, ...)."""
    import typing

    from .scenario import Scenario

    return tuple(name for name, f in Scenario.model_fields.items() if typing.get_origin(f.annotation) is dict)


def check_vary_paths(base: dict, vary: dict[str, list]) -> None:
    """Refuse (ScenarioError naming the path) a varied path into an entry of a named map
    (``vessels.X.…``, ``lines.X.…``, ...) that the base scenario does not have, neither
    itself nor from its pipelay or crane templates: a misspelled name would add a new,
    unused object and run the base case unchanged. ``map.X`` alone, given whole objects as
    values, adds them on purpose and is allowed."""
    import difflib

    from .errors import ScenarioError

    errors = []
    expanded = None
    for path, values in vary.items():
        parts = str(path).split(".")
        if len(parts) < 2 or parts[0] not in _named_maps() or not parts[1]:
            continue                              # an empty part: set_path names it
        group, name = parts[0], parts[1]
        have = base.get(group) if isinstance(base.get(group), dict) else {}
        if name in have:
            continue
        if len(parts) == 2 and all(isinstance(v, dict) for v in values):
            continue                              # a whole new entry
        if expanded is None:                      # names the templates make (pipelay, cranes)
            try:
                from .scenario import expand
                expanded = expand(base)
            except Exception:   # a template that does not expand: validation says why, per case
                expanded = base
        made = expanded.get(group) if isinstance(expanded.get(group), dict) else {}
        if name in made:
            continue
        known = sorted(set(have) | set(made))
        close = difflib.get_close_matches(name, known, n=1)
        hint = f"; did you mean '{group}.{close[0]}'?" if close else ""
        errors.append((str(path), f"names {group} entry '{name}', which the scenario does not have "
                                  f"({group}: {', '.join(known) or 'none'}){hint}"))
    if errors:
        raise ScenarioError(errors)


def replaced_overrides(vary: dict, overrides: dict | None) -> list[tuple[str, str]]:
    """``(varied path, reason)`` for every override a varied path would replace: the varied
    values are applied after the overrides, so a varied path at or above an override's
    (``analysis.dynamics.duration`` or ``analysis.dynamics`` varied, ``analysis.dynamics.duration``
    overridden) silently replaced it in every load case. A varied path below an override's
    is fine: the varied value goes inside the override. Used by ``rfesim sweep`` and the
    service's ``POST /sweeps``."""
    return [(str(v), f"would replace the override '{o}' in every load case: vary '{o}' itself, or leave it "
                     f"out of the overrides") for v in vary for o in (overrides or {})
            if tuple(str(o).split("."))[:len(str(v).split("."))] == tuple(str(v).split("."))]


def build_cases(scenario, vary: dict[str, list], overrides: dict | None = None) -> list[tuple[dict, dict]]:
    """Validate every load case; ``[(case values, scenario dict), ...]``.

    Relative data-file paths among the varied values (``vessels.barge.motion.file``) are
    taken from the scenario file's folder, as the scenario's own. Raises ScenarioError
    naming the case and the field when a case is not valid, and naming the path when a
    varied path names an object the scenario does not have (:func:`check_vary_paths`)."""
    from .errors import ScenarioError
    from .scenario import load_scenario
    from .scenario.files import resolve_data_files
    from .scenario.load import apply_overrides

    base = _base_dict(scenario)
    folder = _scenario_folder(scenario)
    check_vary_paths(base, vary)
    lost = replaced_overrides(vary, overrides)
    if lost:
        raise ScenarioError(lost)
    cases = []
    for values in grid(vary):
        data = apply_overrides(base, {**(overrides or {}), **values})
        if folder is not None:
            data = resolve_data_files(data, folder)
        try:
            load_scenario(data)
        except ScenarioError as exc:
            where = ", ".join(f"{k}={json.dumps(v)}" for k, v in values.items())
            raise ScenarioError([(f, f"{r} (load case {where})") for f, r in exc.errors]) from None
        cases.append((values, data))
    return cases


@contextlib.contextmanager
def worker_environment() -> Iterator[None]:
    """Set the one-thread variables while worker processes are started (they inherit
    the environment), then restore the caller's."""
    saved = {k: os.environ.get(k) for k in WORKER_THREAD_ENV}
    os.environ.update(WORKER_THREAD_ENV)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def local_executor(workers: int | None = None):
    """A process pool (spawn start method) of ``workers`` processes (default: the cores);
    its processes ignore Ctrl-C (the main process stops them)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    n = max(1, workers or os.cpu_count() or 1)
    return ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context("spawn"),
                               initializer=_worker_init)


def run_sweep(scenario, vary: dict[str, list], executor=None, *, overrides: dict | None = None,
              workers: int | None = None, on_row=None) -> list[dict[str, Any]]:
    """Run every load case of ``vary`` (dotted path -> values, a grid) and return one row
    per case, in case order: ``case``, the varied values, the summary columns,
    ``top_tension_at``, ``wall_time``, ``status``, ``message``.

    ``executor``: None for a local process pool, or anything with ``submit(fn, *args)``
    returning a future with ``.result()`` (``concurrent.futures`` executors,
    ``distributed.Client``). ``on_row(row)`` is called as each case finishes (in the order
    they finish). Raises ScenarioError (naming the case and the field) before anything runs
    if a case is not valid. The local pool starts processes with ``spawn``: call it under
    ``if __name__ == "__main__":`` in a script.
    """
    return run_cases(build_cases(scenario, vary, overrides), executor, workers=workers, on_row=on_row)


LOST_WORKER = ("its worker process died (killed, or out of memory): it was run again alone, and its process "
               "died again")


def _failed(i: int, message: str) -> dict[str, Any]:
    return {"case": i, "status": "failed", "message": message, "wall_time": None, "top_tension_at": None,
            **{c: None for c in SUMMARY_COLUMNS}}


def run_cases(cases: list[tuple[dict, dict]], executor=None, *, workers: int | None = None,
              on_row=None) -> list[dict[str, Any]]:
    """Run validated cases from :func:`build_cases` on ``executor`` (see run_sweep); the
    rows in case order.

    A case whose run raises fails alone. On a local process pool (``executor`` None or a
    ``ProcessPoolExecutor``) a worker process that dies breaks the whole pool: the cases
    that had not started yet go to a new pool, and those that had (one of them was on the
    dead worker) are run again one at a time in a pool of their own; a case fails only if
    its process dies again there. A KeyboardInterrupt stops the workers and propagates
    (``on_row`` has had the finished rows)."""
    from concurrent.futures import ProcessPoolExecutor

    rows: dict[int, dict] = {}

    def finish(i: int, result: dict) -> None:
        row = {"case": i, **cases[i][0], **{k: v for k, v in result.items() if k != "case"}}
        rows[i] = row
        if on_row is not None:
            on_row(row)

    if executor is None or isinstance(executor, ProcessPoolExecutor):
        n = workers or getattr(executor, "_max_workers", None) or os.cpu_count() or 1
        _run_local(cases, executor, n, finish)
    else:
        _run_on(executor, cases, finish)
    return [rows[i] for i in sorted(rows)]


def _run_on(executor, cases, finish) -> None:
    """Any executor: each case's failure its own (a Dask cluster reschedules the cases of a
    lost worker itself)."""
    with worker_environment():
        futures = {_submit(executor, run_case, data, i): i for i, (_, data) in enumerate(cases)}
    for fut in _completed(executor, list(futures)):
        i = futures[fut]
        try:
            result = fut.result()
        except KeyboardInterrupt:
            raise
        except Exception as exc:   # this case fails, the others go on
            result = _failed(i, f"{type(exc).__name__}: {exc}")
        finish(i, result)


def _completed(executor, futures: list):
    """The futures as they finish (concurrent.futures, Dask), else in order."""
    from concurrent.futures import Future, as_completed

    if futures and all(isinstance(f, Future) for f in futures):
        return as_completed(futures)
    try:
        from distributed import Client
        from distributed import as_completed as dask_completed
    except ImportError:
        return futures
    return dask_completed(futures) if isinstance(executor, Client) else futures


def _stop(executor) -> None:
    """Shut a local pool down without waiting for the cases it runs (an interruption)."""
    processes = dict(getattr(executor, "_processes", None) or {})
    executor.shutdown(wait=False, cancel_futures=True)
    for p in processes.values():
        with contextlib.suppress(Exception):
            p.terminate()


def _run_local(cases, given, workers: int, finish, fn=run_case) -> None:
    """Run ``fn(case, index)`` (:func:`run_case`) for each case on local process pools,
    surviving dead worker processes (run_cases); ``finish(index, result)`` as each ends."""
    import shutil
    import tempfile
    from concurrent.futures import as_completed
    from concurrent.futures.process import BrokenProcessPool

    markers = Path(tempfile.mkdtemp(prefix="rfesim-sweep-"))
    pool = given
    try:
        pending, suspects, blind = list(range(len(cases))), [], 0
        while pending:
            if pool is None:
                with worker_environment():      # processes the pool starts now inherit one thread each
                    pool = local_executor(min(len(pending), workers))
            try:
                with worker_environment():
                    futures = {pool.submit(_run_case_marked, cases[i][1], i, str(markers / f"{i}"), fn): i
                               for i in pending}
            except BrokenProcessPool:           # a given pool broken before
                futures = {}
            broken = [i for i in pending if i not in futures.values()]
            for fut in as_completed(futures):
                i = futures[fut]
                try:
                    result = fut.result()
                except BrokenProcessPool:
                    broken.append(i)
                    continue
                except KeyboardInterrupt:
                    raise
                except Exception as exc:   # this case fails, the others go on
                    result = _failed(i, f"{type(exc).__name__}: {exc}")
                finish(i, result)
            if pool is not given:
                pool.shutdown(wait=True, cancel_futures=True)
            pool = None
            started = sorted(i for i in broken if (markers / f"{i}").exists())
            pending = sorted(i for i in broken if i not in started)
            suspects += started
            if broken and not started:
                blind += 1               # the pool broke with no case started: after 3 times, alone each
                if blind >= 3:
                    suspects += pending
                    pending = []
        for i in sorted(suspects):      # alone, so that a dead process names its case
            (markers / f"{i}").unlink(missing_ok=True)
            if pool is None:
                with worker_environment():
                    pool = local_executor(1)
            try:
                result = pool.submit(_run_case_marked, cases[i][1], i, str(markers / f"{i}"), fn).result()
            except BrokenProcessPool:
                pool.shutdown(wait=True, cancel_futures=True)
                pool = None
                result = _failed(i, LOST_WORKER)
            except KeyboardInterrupt:
                raise
            except Exception as exc:
                result = _failed(i, f"{type(exc).__name__}: {exc}")
            finish(i, result)
    except BaseException:
        if pool is not None and pool is not given:
            _stop(pool)
            pool = None
        raise
    finally:
        if pool is not None and pool is not given:
            pool.shutdown(wait=True, cancel_futures=True)
        shutil.rmtree(markers, ignore_errors=True)


def _submit(executor, fn, *args):
    try:
        from distributed import Client
    except ImportError:
        Client = None
    if Client is not None and isinstance(executor, Client):
        return executor.submit(fn, *args, pure=False)
    return executor.submit(fn, *args)


# --------------------------------------------------------------------------- table output

RESULT_COLUMNS = ("case", *SUMMARY_COLUMNS, "top_tension_at", "wall_time", "status", "message")


def columns(vary: dict[str, list]) -> list[str]:
    return ["case", *vary, *SUMMARY_COLUMNS, "top_tension_at", "wall_time", "status", "message"]


def _cell(value) -> str:
    """A value for the console table (6 significant digits)."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, dict, bool)):
        return json.dumps(value)
    return str(value)


def _csv_cell(value) -> str:
    """A value for the CSV file: numbers in full precision (repr: read back exactly)."""
    if isinstance(value, float):
        return repr(value)
    return _cell(value)


def _distinct_cells(values: list) -> list[str]:
    """Console cells of a varied column: 6 significant digits, more where two different
    numbers would otherwise look the same (1025.0001 and 1025.0004)."""
    numbers = {v for v in values if isinstance(v, float) and math.isfinite(v)}
    digits = 6
    while digits < 17 and len({f"{v:.{digits}g}" for v in numbers}) < len(numbers):
        digits += 1
    return [f"{v:.{digits}g}" if isinstance(v, float) else _cell(v) for v in values]


def write_csv(rows: list[dict], cols: list[str], path: str | os.PathLike) -> None:
    """The table as CSV, written atomically (a temporary file beside it, then renamed)."""
    tmp = Path(f"{os.fspath(path)}.tmp")
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(cols)
        for row in rows:
            writer.writerow([_csv_cell(row.get(c)) for c in cols])
    os.replace(tmp, path)


class RowWriter:
    """A CSV file that gets each row as its case finishes (flushed at once): an interrupted
    sweep keeps the finished cases. ``finish(rows)`` rewrites it in case order."""

    def __init__(self, path: str | os.PathLike, cols: list[str]):
        self.path, self.cols = path, cols
        self.file = open(path, "w", newline="", encoding="utf-8")
        self.writer = csv.writer(self.file)
        self.writer.writerow(cols)
        self.file.flush()

    def add(self, row: dict) -> None:
        self.writer.writerow([_csv_cell(row.get(c)) for c in self.cols])
        self.file.flush()

    def close(self) -> None:
        if not self.file.closed:
            self.file.close()

    def finish(self, rows: list[dict]) -> None:
        self.close()
        write_csv(rows, self.cols, self.path)


def format_table(rows: list[dict], cols: list[str]) -> str:
    header = [c + (f" [{SUMMARY_UNITS[c]}]" if c in SUMMARY_UNITS else "") for c in cols if c != "message"]
    keys = [c for c in cols if c != "message"]
    by_column = [_distinct_cells([r.get(c) for r in rows]) if c not in RESULT_COLUMNS
                 else [_cell(r.get(c)) for r in rows] for c in keys]
    body = [list(cells) for cells in zip(*by_column)] if rows else []
    widths = [max(len(h), *(len(b[i]) for b in body)) if body else len(h) for i, h in enumerate(header)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(b, widths)) for b in body]
    failed = [r for r in rows if r.get("status") != "done"]
    lines += [f"case {r['case']}: {r.get('message', '')}" for r in failed]
    return "\n".join(lines)


# --------------------------------------------------------------------------- command line

def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="rfesim sweep", description="Run a scenario over a grid of parameter values "
                                "and print one table of summary results per load case.")
    p.add_argument("scenario", metavar="SCENARIO", help="base scenario file (JSON or YAML)")
    p.add_argument("--vary", action="append", required=True, metavar="PATH=V1,V2,...",
                   help="dotted scenario path and its values; several --vary make a grid")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster of this scheduler")
    where.add_argument("--local-cluster", type=int, metavar="N",
                       help="start a Dask LocalCluster of N worker processes and run on it")
    where.add_argument("--workers", type=int, metavar="N",
                       help="size of the local process pool (default: number of cores)")
    p.add_argument("-o", "--output", metavar="TABLE.csv", help="also write the table as CSV")
    return p


def _address_problem(address: str) -> str | None:
    """Why ``address`` is not a Dask scheduler address (unknown scheme, no port), or None.
    Checked before connecting: what Client raises for a bad address depends on the state of
    the process's event loop."""
    from distributed.comm.addressing import parse_address, parse_host_port
    from distributed.comm.registry import get_backend

    try:
        scheme, loc = parse_address(address, strict=False)
        get_backend(scheme)
        if scheme in ("tcp", "tls", "ws", "wss"):
            parse_host_port(loc)
    except (ValueError, TypeError) as exc:
        return str(exc)
    return None


def main(argv: list[str] | None = None) -> int:
    """``rfesim sweep``; returns 0 when every case finished, 3 when some failed, 1 on bad
    input, 2 on a usage error, 130 when interrupted (Ctrl-C, SIGTERM): the CSV file then
    holds the cases that had finished."""
    from .cli import CliError, _output_path, sigterm_as_interrupt
    from .errors import ScenarioError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    try:
        vary = parse_vary(args.vary)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    output = None
    if args.output:
        try:       # the checks of `rfesim run -o`: the folder exists, not a folder, not the scenario, writable
            output = _output_path(args.output, Path(args.scenario), None)
        except CliError as exc:
            print(str(exc), file=sys.stderr)
            return exc.code
    for n, flag in ((args.local_cluster, "--local-cluster"), (args.workers, "--workers")):
        if n is not None and n < 1:
            print(f"error: {flag} must be at least 1", file=sys.stderr)
            return 2
    try:
        cases = build_cases(args.scenario, vary)
    except ScenarioError as exc:
        print("scenario error:", file=sys.stderr)
        for f, r in exc.errors:
            print(f"  {f}: {r}" if f else f"  {r}", file=sys.stderr)
        return 1
    where = (f"Dask scheduler {args.scheduler}" if args.scheduler else
             f"a Dask LocalCluster of {args.local_cluster} processes" if args.local_cluster else
             f"a local pool of {min(len(cases), args.workers or os.cpu_count() or 1)} processes")
    print(f"{len(cases)} load cases on {where}", file=sys.stderr)
    wall0 = time.perf_counter()
    cols = columns(vary)
    finished: list[dict] = []
    writer: RowWriter | None = None

    def report(row):
        finished.append(row)
        if writer is not None:
            writer.add(row)
        t = row.get("wall_time")
        detail = f" ({_cell(t)} s)" if t is not None else f": {row.get('message', '')}"
        print(f"  case {row['case']}: {row['status']}{detail}", file=sys.stderr)

    try:
        with sigterm_as_interrupt(), contextlib.ExitStack() as stack:
            executor = None
            if args.scheduler or args.local_cluster:
                try:
                    from distributed import Client, LocalCluster
                except ImportError:
                    print("error: Dask is not installed: pip install 'rfesim[service]' (dask[distributed])",
                          file=sys.stderr)
                    return 2
                if args.scheduler:
                    bad = _address_problem(args.scheduler)
                    if bad:                                 # not an address: "notanaddress", "foo://..."
                        print(f"error: --scheduler {args.scheduler!r} is not a Dask scheduler address ({bad}); "
                              f"give one such as tcp://head-node:8786", file=sys.stderr)
                        return 2
                    try:
                        executor = stack.enter_context(Client(args.scheduler, timeout=30))
                    except (OSError, TimeoutError) as exc:
                        print(f"error: cannot reach the Dask scheduler {args.scheduler}: {exc}", file=sys.stderr)
                        return 2
                else:
                    with worker_environment():
                        cluster = stack.enter_context(LocalCluster(
                            n_workers=args.local_cluster, threads_per_worker=1, processes=True,
                            host="127.0.0.1", dashboard_address=None))
                    executor = stack.enter_context(Client(cluster))
            if output is not None:
                writer = RowWriter(output, cols)
                stack.callback(writer.close)
            rows = run_cases(cases, executor, workers=args.workers, on_row=report)
    except KeyboardInterrupt:
        if writer is not None:
            writer.close()
        done = sorted(finished, key=lambda r: r["case"])
        if done:
            print(format_table(done, cols))
        print(f"interrupted: {len(done)} of {len(cases)} cases done"
              + (f", their rows are in {output}" if output is not None else ""), file=sys.stderr)
        return 130
    print(format_table(rows, cols))
    print(f"{len(rows)} cases, wall time {time.perf_counter() - wall0:.3g} s", file=sys.stderr)
    if writer is not None:
        writer.finish(rows)             # the whole table again, in case order
        print(f"table written to {output}", file=sys.stderr)
    return 0 if all(r["status"] == "done" for r in rows) else 3


if __name__ == "__main__":
    raise SystemExit(main())
