"""Cold-cache compile (``rfesim bench --only compile``): the recorded kernels
(rfesim/data/kernel_signatures.json) compiled into an empty numba cache by one process, one
after the other as runs compile them when first called, against ``rfesim.precompile`` in two
processes into another empty cache, one after the other in one run; then the recorded
workload (rfesim._kernel_workload) on the parallel-filled cache, which should compile nothing
(docs/theory.md, 'Compiling in parallel')."""
from __future__ import annotations

import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from .run import ROOT, log, write_part

MARK_BEGIN = "<!-- compile-bench -->"
MARK_END = "<!-- /compile-bench -->"
QUICK_KERNELS = ("rfesim.loads.tensioner:payout_speed", "rfesim.loads.tensioner:payout_newton",
                 "rfesim.loads.tensioner:solve_driven_payout", "rfesim.loads.tensioner:tensioner_forces")


def _timed(cmd: list[str], env: dict) -> tuple[float, float, str]:
    """(wall s, CPU s of the process and its children, stdout) of one command."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(cmd, env=env, cwd=str(ROOT), capture_output=True, text=True, check=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out.stdout


def _cached(cache: str) -> int:
    return sum(name.endswith(".nbc") for _, _, files in os.walk(cache) for name in files)


def run_bench(quick: bool) -> dict:
    only = ["--only", ",".join(QUICK_KERNELS)] if quick else []
    runs = {}
    with tempfile.TemporaryDirectory(prefix="rfesim-bench-compile-") as tmp:
        for processes in (1, 2):
            cache = os.path.join(tmp, f"cache{processes}")
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
            log(f"compile: {processes} process(es) into an empty cache ...")
            wall, cpu, out = _timed([sys.executable, "-m", "rfesim._precompile", str(processes)] + only, env)
            runs[processes] = {"wall_time": wall, "cpu_time": cpu, "kernels": int(out.split()[0]),
                               "compiled_files": _cached(cache)}
        workload = None
        if not quick:
            env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "cache2"), PYTHONPATH=str(ROOT),
                       RFESIM_PRECOMPILE="0")
            before = _cached(env["NUMBA_CACHE_DIR"])
            log("compile: the recorded workload on the parallel-filled cache ...")
            wall, cpu, _ = _timed([sys.executable, "-c", "from rfesim._kernel_workload import run_all; "
                                   "import sys; sys.exit(1 if run_all(False) else 0)"], env)
            workload = {"wall_time": wall, "new_files": _cached(env["NUMBA_CACHE_DIR"]) - before}
    return {"quick": quick, "runs": {str(k): v for k, v in runs.items()}, "workload": workload,
            "speedup": runs[1]["wall_time"] / runs[2]["wall_time"]}


def report(b: dict) -> str:
    la = os.getloadavg() if hasattr(os, "getloadavg") else None
    lines = [MARK_BEGIN, "## Cold-cache compile (rfesim.precompile)", "",
             f"`rfesim bench --only compile` on {platform.machine()}, {os.cpu_count()} cores"
             + (f"; load average at the end {la[0]:.2f}, {la[1]:.2f}, {la[2]:.2f} (shared machine)" if la else "")
             + ". The kernels of `rfesim/data/kernel_signatures.json` compiled into an empty numba cache, by one "
             "process (as runs compile them when first called, one after the other) and by two "
             "(`python -m rfesim._precompile N`), measured one after the other in one run.", "",
             "| processes | kernels | cache files written | wall time [s] | CPU time [s] |",
             "|---:|---:|---:|---:|---:|"]
    for n, x in b["runs"].items():
        lines.append(f"| {n} | {x['kernels']} | {x['compiled_files']} | {x['wall_time']:.1f} | {x['cpu_time']:.1f} |")
    lines += ["", f"Two processes: {b['speedup']:.2f}x faster than one."]
    if b["workload"] is not None:
        w = b["workload"]
        lines.append(f"The recorded workload (every shipped scenario through statics and three steps, each integrator, "
                     f"modes, a results file) then ran on the cache the two processes filled in "
                     f"{w['wall_time']:.1f} s, writing {w['new_files']} more compiled files (0: nothing left to "
                     f"compile).")
    if b["quick"]:
        lines.append(f"This was a --quick run: {len(QUICK_KERNELS)} small kernels, not the record.")
    lines += ["", MARK_END]
    return "\n".join(lines)


def run_compile_and_write(quick: bool, report_path: Path) -> str:
    b = run_bench(quick)
    return write_part("compile", b, report(b), report_path, MARK_BEGIN, MARK_END)
