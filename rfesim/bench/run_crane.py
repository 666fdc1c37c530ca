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
    "What limits it. The cost of a step, about 1.1 ms at 0.1 s (measured separately on this scene: a residual "
    "evaluation 0.28 ms, the first of each step with the sea kinematics 0.54 ms, an analytic Jacobian 0.8 ms before "
    "it reused the Newton iterate's evaluation and SDE forces (docs/slay_speed_notes.md), its factorisation "
    "0.04 ms, a recorded output 0.3 ms), with about 3.8 evaluations and 0.35 Jacobians a step. The "
    "sea and the recording no longer dominate: the kinematics of dry RFEs are skipped and an output reuses the "
    "step's evaluation (docs/theory.md, 'Sea kinematics of dry RFEs; output recording'; before them a step cost "
    "about 3.6 ms in the same conditions). A longer step does not pay: at 0.2 s the error grows to about 0.7 % and "
    "every step forms a new Jacobian (2.9 ms a step): the rope's axial springs (EA/T about 1000) turn with the "
    "swinging payload and the whole structure turns with the vessel, so a Jacobian two or three steps old makes "
    "modified Newton diverge (the spectral radius of J0^-1 J4 - I after four 0.2 s steps: 0.83). The 200x target "
    "needs about 0.5 ms a step at 0.1 s: a cheaper SDE kernel (0.15 ms of the 0.28 ms evaluation for 100 SDEs), a "
    "Jacobian refresh of the analytic SDE part alone between full ones, and a predictor that carries the vessel's "
    "rigid motion to the structure on it (the first residual of a step is 100 to 200 times the payload's weight, "
    "at the pedestal, whose axial stiffness reads the predictor's error).")
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
