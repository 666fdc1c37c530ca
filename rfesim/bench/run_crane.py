"""``rfesim bench --only crane``: the column-crane benchmark of issue 5 (rfesim.bench.crane):
30 minutes of a column crane holding a payload in irregular waves; wall time against real
time (target: at least 200x faster than real time) and the error of the largest rope
tension against a converged run (target < 1 %). The reference is the same scene with a
quarter of the production time step; the run at half the step shows how far the
reference itself is converged. Writes its own section of docs/benchmarks.md (between
``<!-- crane-bench -->`` and ``<!-- /crane-bench -->``) and the ``crane`` entry of
docs/benchmarks.json.
"""
from __future__ import annotations

import os
import platform
from pathlib import Path

from .crane import DEPTH_OF_PAYLOAD, DIRECTION, HS, SEED, SETTLE, TP, run_crane
from .run import log, store_entry, write_marked_section

MARK_BEGIN = "<!-- crane-bench -->"
MARK_END = "<!-- /crane-bench -->"
PRODUCTION_STEP = 0.1
DURATION = 1800.0
QUICK_DURATION = 300.0
OUTPUT_INTERVAL = 0.2
LIMITS = (
    "What limits it. The cost of a step at 0.1 s: about 4 residual evaluations and 0.2-0.35 Jacobians, and an "
    "output every other step. The evaluation's largest part, the SDE pass, and the poses now run in scalar form "
    "(docs/theory.md, 'Scalar hot kernels and one-call recording'; timed inside numba, 0.061 -> 0.016 ms for the "
    "100 SDEs, 0.014 -> 0.006 ms for the poses), with the same results to the bit (the same counts and maximum as "
    "before them). Run at the same time as the code before them on this shared machine (load 4-5), the production "
    "run took 26.5 s of CPU against 36.1 s (1.36x less; wall 124 s against 155 s); the 19.7 s the code before "
    "them took on a quiet machine (91x) then scales to about 14.5 s (about 120x); measured on the quiet machine "
    "(load 0.8) the production run then took 15.6 s (116x). On 2026-11-25 the machine was faster: the same code "
    "took 10.84 s (166x, load 0.1), so most of the step from 116x is the machine, not the code; this run's "
    "production time varies by 5-8 % between repeats. "
    "The recording then cost 2.9 s of those 10.84 s: with it replaced by a no-op the run took 7.96 s (226x, the "
    "ceiling without outputs). Each line channel is now kept in one array over all lines (the lines' arrays are "
    "views), copied once per output instead of once per line; the joint-drive rotation is written out, the drive "
    "tables' row slices are kept between outputs and the output imports are at module level. Old and new code "
    "run alternately three times each (the same results to the bit): 11.60 s against 10.94 s on average "
    "(1.06x). Per output now (timed on the quiet machine): 105 us in all, of which the output kernel 41 us (12 us "
    "of it numba unboxing the model, attachment and workspace tuples, 244 arrays; the rest the SDE channels and "
    "points of 100 RFEs), the joint outputs 18.5 us, the body outputs 4.7 us, and small numpy copies. Next: the "
    "recording inside the stepping kernel (one call per run instead of one per output interval): with the Python "
    "of an output gone (about 64 us) and one unboxing instead of two, about 0.7 s less, near 180-190x; the stepping "
    "itself must then come down as well for 200x (without outputs it ran at 226x). The sea's per-component constants are now packed "
    "once instead of at every call (docs/theory.md, 'Sea kinematics at depth'): run alternately with the code "
    "before, three times each, 10.58 s against 10.41 s (1.016x, the same results to the bit). CPU "
    "per call measured before the scalar kernels, before -> after: an evaluation 0.134 -> 0.085 ms, the first of a step with "
    "the sea kinematics 0.353 -> 0.280 ms, a Jacobian 0.57 -> 0.53 ms, a recorded output 0.40 -> 0.31 ms. What "
    "remains per step: the sea kinematics (about 0.2 ms: 200 components at each of the dozen wet RFEs, a cosine, "
    "a sine and an exponential each), the further "
    "evaluations, the Jacobians, whose SDE tangent, maps and assembly are not in scalar form (one costs about six "
    "evaluations), and the recording (above). Tried and not kept: a Jacobian refresh after 3 "
    "evaluations instead of 4 (3.16 evaluations and 0.383 Jacobians a step instead of 3.64 and 0.281 over 300 s, "
    "the same wall time); a predictor that carries the vessel's rigid motion to the pedestal and boom (the first "
    "residual grows from about 3 to 40-150 payload weights, at the boom tip: the boom's vibration is not rigid); "
    "the analytic SDE part of the Jacobian refreshed at every step (2.83 instead of 3.53 evaluations and 0.17 "
    "instead of 0.29 Jacobians a step over 15 s, but the refresh, about 0.25 ms, costs what it saves); accepting "
    "a step on the estimated contraction without the confirming evaluation (0.3 evaluations a step, on the steps "
    "between outputs only). A longer step does not pay: at 0.2 s the error grows to about 0.7 % and every step "
    "forms a new Jacobian (the rope's axial springs, EA/T about 1000, turn with the swinging payload and the "
    "structure turns with the vessel; the spectral radius of J0^-1 J4 - I after four 0.2 s steps: 0.83).")
TARGET_FACTOR = 200.0
TARGET_ERROR = 0.01


def run_bench(quick: bool) -> dict:
    duration = QUICK_DURATION if quick else DURATION
    runs = {}
    for name, div in (("production", 1), ("half step", 2), ("reference", 4)):
        dt = PRODUCTION_STEP / div
        log(f"crane {name} run (dt {dt:g} s, {duration:g} s) ...")
        runs[name] = run_crane(time_step=dt, duration=duration, output_interval=OUTPUT_INTERVAL, log=log)
    ref = runs["reference"]["max_tension"]
    return {"runs": runs, "quick": quick,
            "error": abs(runs["production"]["max_tension"] - ref) / ref,
            "reference_error": abs(runs["half step"]["max_tension"] - ref) / ref,
            "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None}


def report(b: dict) -> str:
    p = b["runs"]["production"]
    la = b.get("load_average")
    ok_speed = p["real_time_factor"] >= TARGET_FACTOR
    ok_err = b["error"] < TARGET_ERROR
    lines = [MARK_BEGIN, "## Column crane in irregular waves (issue 5)", "",
             f"`rfesim bench --only crane` on {platform.machine()}, {os.cpu_count()} cores"
             + (f"; load average at the end {la[0]:.2f}, {la[1]:.2f}, {la[2]:.2f} (shared machine)" if la else "")
             + ".", "",
             f"Scenario `rfesim.bench.crane`: the column crane of `scenarios/column_crane.json` (12 m pedestal, 30 m "
             f"boom at 45 deg slewed over the side, 36 mm hoist rope, 10 t module of 4 m3) holding the payload "
             f"{DEPTH_OF_PAYLOAD:g} m under the surface, the rope through the splash zone; {p['rfes']} RFEs in all "
             f"(pedestal, boom, rope and the payload); barge RAOs in a JONSWAP sea Hs {HS:g} m, Tp {TP:g} s, "
             f"toward {DIRECTION:g} deg (head seas), seed {SEED}; generalized-alpha (rho_inf 0.8). Output: the largest rope tension at the sheave "
             f"after the first {SETTLE:g} s, sampled every {p['output_interval']:g} s in every run.", "",
             "| run | time step [s] | simulated [s] | wall time [s] | faster than real time | steps | step halvings "
             "| residual evaluations / step | Jacobians / step | static tension [kN] | max tension [kN] |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, x in b["runs"].items():
        steps = max(x["steps"], 1)
        lines.append(f"| {name} | {x['time_step']:g} | {x['duration']:g} | {x['wall_time']:.2f} | "
                     f"{x['real_time_factor']:.0f}x | {x['steps']} | {x['step_halvings']} | "
                     f"{x['newton_iterations'] / steps:.2f} | {x['jacobians'] / steps:.3f} | "
                     f"{x['static_tension'] / 1e3:.2f} | {x['max_tension'] / 1e3:.3f} |")
    lines += ["",
              f"Production run: {p['real_time_factor']:.0f}x faster than real time (target >= {TARGET_FACTOR:g}x: "
              f"{'met' if ok_speed else 'missed'}); error of its largest rope tension against the reference "
              f"{100 * b['error']:.3f} % (target < {100 * TARGET_ERROR:g} %: {'met' if ok_err else 'missed'}). The "
              f"half-step run differs from the reference by {100 * b['reference_error']:.3f} %: the reference is "
              f"converged to about that."
              + (f" This was a --quick run ({p['duration']:g} s simulated, not 30 minutes)." if b["quick"] else ""),
              "", LIMITS, "", MARK_END]
    return "\n".join(lines)


def write_section(text: str, path: Path) -> None:
    write_marked_section(text, path, MARK_BEGIN, MARK_END)


def run_crane_and_write(quick: bool, report_path: Path) -> str:
    b = run_bench(quick)
    text = report(b)
    write_section(text, report_path)
    store_entry(report_path, "crane", b)
    return text
