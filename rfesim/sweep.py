"""Parameter sweeps: one scenario, a grid of load cases, one table of summary results.

    rfesim sweep scenarios/catenary_riser.json \\
        --vary vessels.fpso.motion.heave.amplitude=1,2,3 \\
        --vary environment.water.density=1020,1030 -o table.csv

From Python::

    from rfesim.sweep import run_sweep
    rows = run_sweep("scenarios/catenary_riser.json", {"vessels.fpso.motion.heave.amplitude": [1, 2, 3]})

Cases run in parallel processes: a local process pool by default, or any executor with
``submit(fn, *args) -> future`` whose futures have ``.result()`` — a
``concurrent.futures`` executor or a ``distributed.Client`` (a Dask cluster, e.g. SLURM
through dask-jobqueue). Each process uses one numba/BLAS thread.

Summary columns (SI units): ``max_top_tension`` (N, largest over lines of the force at end
B), ``max_tension`` / ``min_tension`` (N, effective tension over all SDEs and times),
``max_bend_moment`` (N*m), ``touchdown_min`` / ``touchdown_max`` (m, range over time of
the arc length where seabed contact ends, empty when no line touches the seabed),
``daf`` (dynamic amplification: max top tension over the top tension at t = 0, the
static one), ``wall_time`` (s), ``status`` (done / failed) and ``message``.
"""
from __future__ import annotations

import argparse
import contextlib
import csv
import itertools
import json
import math
import os
import sys
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
    """(min, max) over time of the touchdown arc length: per line and time, the largest
    arc length of an RFE in seabed contact (``seabed_force > 0``). (None, None) when no
    line touches the seabed."""
    import numpy as np

    lo, hi = math.inf, -math.inf
    for lr in res.lines.values():
        force = np.asarray(lr.seabed_force)
        if force.size == 0 or not np.any(force > 0.0):
            continue
        points = np.asarray(lr.arc_length)
        rfe_s = 0.5 * (points[:-1] + points[1:])        # RFE i spans points i .. i+1
        if rfe_s.shape[0] != force.shape[1]:
            rfe_s = np.linspace(points[0], points[-1], force.shape[1])
        contact = force > 0.0
        touching = np.any(contact, axis=1)
        last = force.shape[1] - 1 - np.argmax(contact[:, ::-1], axis=1)
        s = rfe_s[last[touching]]
        lo, hi = min(lo, float(s.min())), max(hi, float(s.max()))
    if lo > hi:
        return None, None
    return lo, hi


def summarize(res) -> dict[str, float | None]:
    """The summary columns of one run's Results (None where not defined)."""
    import numpy as np

    out: dict[str, float | None] = {c: None for c in SUMMARY_COLUMNS}
    if len(res.time) == 0 or not res.lines:
        return out
    top = {name: np.asarray(lr.top_tension) for name, lr in res.lines.items()}
    best = max(top, key=lambda n: np.nanmax(top[n]) if top[n].size else -np.inf)
    max_top = float(np.nanmax(top[best]))
    out["max_top_tension"] = _finite_or_none(max_top)
    out["max_tension"] = _finite_or_none(max(np.nanmax(lr.tension) for lr in res.lines.values()))
    out["min_tension"] = _finite_or_none(min(np.nanmin(lr.tension) for lr in res.lines.values()))
    out["max_bend_moment"] = _finite_or_none(max(np.nanmax(lr.bend_moment) for lr in res.lines.values()))
    out["touchdown_min"], out["touchdown_max"] = touchdown_range(res)
    static_top = float(top[best][0])
    if static_top > 1e-9 * max(1.0, abs(max_top)) and math.isfinite(static_top):
        out["daf"] = _finite_or_none(max_top / static_top)
    return out


# --------------------------------------------------------------------------- one load case

def run_case(case: dict, index: int = 0) -> dict[str, Any]:
    """Run one load case (a scenario dict) and summarise it; runs in a worker process.

    Returns ``{"case", "status", "message", "wall_time", **summary}``; a run that diverges
    is summarised from its partial results with status "failed".
    """
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
    row.update(summarize(res) if res is not None else {c: None for c in SUMMARY_COLUMNS})
    row["wall_time"] = time.perf_counter() - wall0
    return row


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
    """Every combination of the varied values, the last path varying fastest."""
    if not vary:
        return [{}]
    paths = list(vary)
    return [dict(zip(paths, combo)) for combo in itertools.product(*(vary[p] for p in paths))]


def _base_dict(scenario) -> dict:
    """The scenario as a plain dict (from a file path, JSON/YAML text, a dict or a Scenario)."""
    from .scenario import Scenario, validate_dict
    from .scenario.load import _read_file, parse_text

    if isinstance(scenario, Scenario):
        return scenario.model_dump(mode="json")
    if isinstance(scenario, dict):
        return scenario
    if isinstance(scenario, (str, os.PathLike)):
        text_like = isinstance(scenario, str) and ("\n" in scenario or scenario.lstrip().startswith(("{", "[")))
        data = parse_text(scenario) if text_like else parse_text(*_read_file(Path(scenario)))
        if not text_like:                        # data files are relative to the scenario file
            from .scenario.files import resolve_data_files
            data = resolve_data_files(data, Path(scenario).parent)
    else:
        data = scenario
    if not isinstance(data, dict):
        validate_dict(data)                      # raises the usual ScenarioError
    return data


def build_cases(scenario, vary: dict[str, list], overrides: dict | None = None) -> list[tuple[dict, dict]]:
    """Validate every load case; ``[(case values, scenario dict), ...]``.

    Raises ScenarioError naming the case and the field when a case is not valid."""
    from .errors import ScenarioError
    from .scenario import load_scenario
    from .scenario.load import apply_overrides

    base = _base_dict(scenario)
    cases = []
    for values in grid(vary):
        data = apply_overrides(base, {**(overrides or {}), **values})
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
    """A process pool (spawn start method) of ``workers`` processes (default: the cores)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    n = max(1, workers or os.cpu_count() or 1)
    return ProcessPoolExecutor(max_workers=n, mp_context=multiprocessing.get_context("spawn"))


def run_sweep(scenario, vary: dict[str, list], executor=None, *, overrides: dict | None = None,
              workers: int | None = None, on_row=None) -> list[dict[str, Any]]:
    """Run every load case of ``vary`` (dotted path -> values, a grid) and return one row
    per case: ``case``, the varied values, the summary columns, ``wall_time``, ``status``.

    ``executor``: None for a local process pool, or anything with ``submit(fn, *args)``
    returning a future with ``.result()`` (``concurrent.futures`` executors,
    ``distributed.Client``). ``on_row(row)`` is called as each row arrives, in case order.
    Raises ScenarioError (naming the case and the field) before anything runs if a case
    is not valid.
    """
    return run_cases(build_cases(scenario, vary, overrides), executor, workers=workers, on_row=on_row)


def run_cases(cases: list[tuple[dict, dict]], executor=None, *, workers: int | None = None,
              on_row=None) -> list[dict[str, Any]]:
    """Run validated cases from :func:`build_cases` on ``executor`` (see run_sweep)."""
    own = executor is None
    if own:
        executor = local_executor(min(len(cases), workers or os.cpu_count() or 1))
    try:
        with worker_environment():     # processes the pool starts now inherit one thread each
            futures = [_submit(executor, run_case, data, i) for i, (_, data) in enumerate(cases)]
        rows = []
        for i, ((values, _), fut) in enumerate(zip(cases, futures)):
            try:
                result = fut.result()
            except Exception as exc:   # a lost worker, a broken pool: this case fails, the others go on
                result = {"case": i, "status": "failed", "message": f"{type(exc).__name__}: {exc}",
                          "wall_time": None, **{c: None for c in SUMMARY_COLUMNS}}
            row = {"case": i, **values, **{k: v for k, v in result.items() if k != "case"}}
            rows.append(row)
            if on_row is not None:
                on_row(row)
        return rows
    finally:
        if own:
            executor.shutdown(wait=True, cancel_futures=True)


def _submit(executor, fn, *args):
    try:
        from distributed import Client
    except ImportError:
        Client = None
    if Client is not None and isinstance(executor, Client):
        return executor.submit(fn, *args, pure=False)
    return executor.submit(fn, *args)


# --------------------------------------------------------------------------- table output

def columns(vary: dict[str, list]) -> list[str]:
    return ["case", *vary, *SUMMARY_COLUMNS, "wall_time", "status", "message"]


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, (list, dict, bool)):
        return json.dumps(value)
    return str(value)


def write_csv(rows: list[dict], cols: list[str], path: str | os.PathLike) -> None:
    tmp = Path(f"{os.fspath(path)}.tmp")
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(cols)
        for row in rows:
            writer.writerow([_cell(row.get(c)) for c in cols])
    os.replace(tmp, path)


def format_table(rows: list[dict], cols: list[str]) -> str:
    header = [c + (f" [{SUMMARY_UNITS[c]}]" if c in SUMMARY_UNITS else "") for c in cols if c != "message"]
    keys = [c for c in cols if c != "message"]
    body = [[_cell(r.get(c)) for c in keys] for r in rows]
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


def main(argv: list[str] | None = None) -> int:
    """``rfesim sweep``; returns 0 when every case finished, 3 when some failed, 1 on bad
    input, 2 on a usage error."""
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
    if args.output:
        folder = Path(args.output).resolve().parent
        if not folder.is_dir():
            print(f"error: the output folder does not exist: {folder}", file=sys.stderr)
            return 1
        if Path(args.output).is_dir():
            print(f"error: the output path is a folder: {args.output} (give a file, e.g. {args.output}/table.csv)",
                  file=sys.stderr)
            return 1
        from .cli import CliError, check_writable

        try:
            check_writable(Path(args.output))
        except CliError as exc:
            print(str(exc), file=sys.stderr)
            return 1
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

    def report(row):
        print(f"  case {row['case']}: {row['status']} ({_cell(row.get('wall_time'))} s)", file=sys.stderr)

    with contextlib.ExitStack() as stack:
        executor = None
        if args.scheduler or args.local_cluster:
            try:
                from distributed import Client, LocalCluster
            except ImportError:
                print("error: Dask is not installed: pip install 'rfesim[service]' (dask[distributed])",
                      file=sys.stderr)
                return 2
            if args.scheduler:
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
        rows = run_cases(cases, executor, workers=args.workers, on_row=report)
    cols = columns(vary)
    print(format_table(rows, cols))
    print(f"{len(rows)} cases, wall time {time.perf_counter() - wall0:.3g} s", file=sys.stderr)
    if args.output:
        write_csv(rows, cols, args.output)
        print(f"table written to {args.output}", file=sys.stderr)
    return 0 if all(r["status"] == "done" for r in rows) else 3


if __name__ == "__main__":
    raise SystemExit(main())
