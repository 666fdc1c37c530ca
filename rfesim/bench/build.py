"""``rfesim bench --only build``: what a scenario costs before its first step.

For every bundled scenario (``scenarios/*.json``): the validation (``rfesim.load_scenario``
of the file: reading it and its data files, template expansion included) and the model build (``rfesim.api.check_model``: the compiler's
arrays, start shape and initial state, no solve), each the median of ``repeats`` calls after
one warm-up call in this process (numba kernels loaded, memoised section fits kept, as in a
worker that has run a job). Then a load-case sweep: ``SWEEP_CASES`` variants of
``catenary_riser.json`` whose vessel sits 1 m further each, validated and built one after
another: the service builds each distinct model of a sweep at submit (docs/service.md), and a
design office script builds one per load case.

Writes its own section of docs/benchmarks.md (between ``<!-- build-bench -->`` and
``<!-- /build-bench -->``) and the ``build`` entry of docs/benchmarks.json.
"""
from __future__ import annotations

import copy
import json
import platform
import statistics
import time
from pathlib import Path

from .run import ROOT, log, write_part

MARK_BEGIN = "<!-- build-bench -->"
MARK_END = "<!-- /build-bench -->"
SWEEP_CASES = 30


def _timed(fn, repeats: int) -> float:
    """Median wall time of ``repeats`` calls (s)."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def run_build(quick: bool = False) -> dict:
    import rfesim
    from rfesim.api import check_model
    from rfesim.materials.sde_plastic import _fit_section_memo

    repeats = 3 if quick else 7
    rows = []
    for path in sorted((ROOT / "scenarios").glob("*.json")):
        log(f"build {path.name} ...")
        sc = rfesim.load_scenario(path)                  # from the file: its data files are relative to it
        check_model(sc)                                  # warm-up: kernels, memoised fits
        validate = _timed(lambda: rfesim.load_scenario(path), repeats)
        build = _timed(lambda: check_model(sc), repeats)
        fresh = _timed(lambda: (_fit_section_memo.cache_clear(), check_model(sc)), repeats)
        rows.append({"scenario": path.name, "validate": validate, "build": build, "build_fresh": fresh})
    base = json.loads((ROOT / "scenarios" / "catenary_riser.json").read_text())
    cases = []
    for i in range(SWEEP_CASES):
        case = copy.deepcopy(base)
        case["vessels"]["fpso"]["position"][0] = float(i)
        cases.append(case)

    def sweep():
        for case in cases:
            check_model(rfesim.load_scenario(case))

    sweep()
    sweep_time = _timed(sweep, 3 if quick else 5)
    return {"rows": rows, "sweep_cases": SWEEP_CASES, "sweep_time": sweep_time, "repeats": repeats,
            "machine": f"{platform.machine()}, Python {platform.python_version()}", "quick": quick}


def report(b: dict) -> str:
    lines = [MARK_BEGIN, "## Before the first step: validation and model build", "",
             "Each bundled scenario's validation (`rfesim.load_scenario` of the file: reading it and its data files, "
             "template expansion included) and model "
             "build (`rfesim.api.check_model`: arrays, start shape, initial state; no solve), median of "
             f"{b['repeats']} calls after a warm-up call in the same process (kernels loaded, section fits kept), "
             f"on {b['machine']}. The service does both at submit (docs/service.md); a sweep does both per load "
             "case.", "",
             "The last column is the build of a process that has not fitted the line's elasto-plastic section "
             "yet (rfesim.materials.sde_plastic.plastic_section keeps each fit).", "",
             "| scenario | validation [ms] | build [ms] | build, no section fit kept [ms] |", "|---|---:|---:|---:|"]
    for r in b["rows"]:
        fresh = r.get("build_fresh")
        fresh = "-" if fresh is None else f"{1e3 * fresh:.1f}"
        lines.append(f"| `{r['scenario']}` | {1e3 * r['validate']:.1f} | {1e3 * r['build']:.1f} | {fresh} |")
    lines += ["", f"A sweep of {b['sweep_cases']} variants of `catenary_riser.json` (the vessel 1 m further each), "
                  f"validated and built one after another: {b['sweep_time']:.3f} s "
                  f"({1e3 * b['sweep_time'] / b['sweep_cases']:.1f} ms a case).", "",
              "The longest builds are the lay templates': J-lay's 1.5 m elements (about 1000 RFEs) go through the "
              "start shape's march (a numba kernel, rfesim.model.march) and the per-SDE damping; reel-lay's first "
              "build also fits the elasto-plastic section's overlay model to the fibre model.", "", MARK_END]
    return "\n".join(lines)


def run_build_and_write(quick: bool, report_path: Path) -> str:
    b = run_build(quick)
    return write_part("build", b, report(b), report_path, MARK_BEGIN, MARK_END)
