"""``rfesim bench --only slay``: the S-lay benchmark of issue 3 (rfesim.bench.slay): wall
time for 3 hours simulated with 200 RFEs on the suspended pipe, and the error of the
largest sagbend moment against a converged run (same sea, same seed, half the time step;
see REFERENCE). Writes its own section of docs/benchmarks.md (between the markers
``<!-- slay-bench -->`` and ``<!-- /slay-bench -->``) and the ``slay`` entry of
docs/benchmarks.json (other entries kept).
"""
from __future__ import annotations

import os
import platform
from pathlib import Path

from .run import log, store_entry, write_marked_section
from .slay import DEPARTURE_DEG, DEPTH, HS, SEED, STINGER_RADIUS, TP, geometry, run_slay

MARK_BEGIN = "<!-- slay-bench -->"
MARK_END = "<!-- /slay-bench -->"

# The production step is 0.1 s, not 0.2 s: at 0.2 s the seabed touchdown makes steps fail and
# halve, so a 0.2 s run costs about as much wall time as a 0.1 s run (measured: 120 s simulated,
# 40.5 s against 38.7 s wall, 64 against 15 halvings) and is 3 times less accurate.
PRODUCTION = {"suspended_rfes": 200, "time_step": 0.1}
REFERENCE = {"suspended_rfes": 200, "time_step": 0.05}    # same RFEs, half the step
DURATION = 3 * 3600.0
QUICK_DURATION = 300.0
# convergence of the largest sagbend moment in the time step (same sea and seed): each step
# run over CONVERGENCE_DURATION; the reference step is converged when halving it changes the
# maximum by less than CONVERGED
CONVERGENCE_STEPS = (0.2, 0.1, 0.05, 0.025)
CONVERGENCE_DURATION = 300.0
CONVERGED = 0.002
OUTPUT_INTERVAL = 0.4            # s, a multiple of both time steps (the driver shortens a step that does not divide it)
TARGET_WALL = 180.0
LIMITS = (
    "Since the table before this one (141.8 s, an earlier session; its 212 halvings came from code before the "
    "Newton change for slack ropes, which also settles this scene's steps: 40 now): the wave phases' sine and "
    "cosine with one argument reduction, on vector instructions (rfesim.sea.trig; docs/theory.md, 'Sine and "
    "cosine of the wave phases'). The water kinematics of the step at the line's static state: 518 us -> 123 us "
    "a call (CPU time, best of 7 x 2000 calls). 300 s at 0.1 s, the code before and after run alternately in one "
    "session, twice each: 5.82-6.10 s against 3.97-4.02 s (1.5x), with the same steps (3000, no halvings), "
    "Newton iterations (11934), Jacobians (2132) and largest sagbend moment to the printed digit. The machine is "
    "slower today than on the day of the 141.8 s table: the code before would have taken about 36 x 6 s, over "
    "the 180 s target. "
    "Before that (270.2 s, an earlier session): the evaluation chain is compiled without reference "
    "counting (docs/theory.md, 'Reference counting off in the evaluation chain'). Timed against the code before "
    "it, the two run alternately in one session (300 s at 0.1 s, three runs each after a warm-up): 5.92-6.08 s "
    "against 4.11-4.25 s (1.43x), with the same steps, Newton iterations, Jacobians and largest sagbend moment to "
    "every digit; the rest of the step from 270 s is the machine, quieter today. The per-call costs below were "
    "measured before that change. "
    "What limits it (docs/slay_speed_notes.md, measured on the shared machine). Per call: the residual with the "
    "water kinematics frozen 0.35-0.41 ms, the analytic Jacobian as the Newton iteration forms it 1.35 ms (6 local "
    "evaluations of 0.18 ms and the SDE tangent 0.34 ms), its banded factorisation 0.1 ms, the water kinematics of "
    "the step 0.73 ms. 3 hours at 0.1 s are 108000 steps: 180 s leaves 1.7 ms per step. Measured over 300 s at "
    "0.1 s: 4.05 evaluations, 0.75 Jacobians and 8 halvings per 3014 steps, about 3.5 ms per step by the per-call "
    "costs (5.2 ms before branch slay-smooth: Jacobian refresh at the predictor only after a step of more than 8 "
    "evaluations, Newton tolerance 1e-3 of an element weight, roller friction stick spring 1e6 N/m). The residual "
    "is smooth enough at the solution (full Newton converges quadratically once the contact states settle); the "
    "iterations are lost to contact states that change within a step: roller stick/slip above all (in a V station "
    "the contact points slide along the roller axes as the penetration changes), the lift-off roller (clear of "
    "the pipe at the predictor, overrun by the first Newton step), onset crossings and seabed contact. Even full "
    "Newton needs 4-5 evaluations per 0.2 s step from the predictor, and 0.2 s is not accurate enough (its "
    "maximum moves by 1.5 % with which steps are halved). Accuracy: the largest sagbend moment is set by "
    "touchdown events and converges slowly in the step: see the convergence table. Next: an analytic local "
    "Jacobian (mass, gravity, buoyancy, Morison; finite differences only for the contacts) and a cheaper "
    "evaluation; a contact-aware first Newton step at the lift-off roller.")
TARGET_ERROR = 0.02


def run_bench(quick: bool) -> dict:
    duration = QUICK_DURATION if quick else DURATION
    conv = []
    for dt in CONVERGENCE_STEPS:
        log(f"S-lay convergence run (dt {dt:g} s, {CONVERGENCE_DURATION:g} s) ...")
        conv.append(run_slay(duration=CONVERGENCE_DURATION, output_interval=OUTPUT_INTERVAL, log=log,
                             suspended_rfes=PRODUCTION["suspended_rfes"], time_step=dt))
    log(f"S-lay production run ({PRODUCTION}, {duration:g} s) ...")
    prod = run_slay(duration=duration, output_interval=OUTPUT_INTERVAL, log=log, **PRODUCTION)
    log(f"S-lay reference run ({REFERENCE}, {duration:g} s) ...")
    ref = run_slay(duration=duration, output_interval=OUTPUT_INTERVAL, log=log, **REFERENCE)
    error = abs(prod["max_sagbend_moment"] - ref["max_sagbend_moment"]) / ref["max_sagbend_moment"]
    return {"production": prod, "reference": ref, "error": error, "quick": quick, "convergence": conv,
            "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None}


def convergence_lines(conv: list) -> list:
    """Table of the largest sagbend moment against the time step, each row's change from
    the row above (the step halved)."""
    if not conv:
        return []
    lines = [f"Convergence in the time step (same sea and seed, {conv[0]['duration']:g} s simulated, maximum "
             f"after {conv[0]['settle']:g} s):", "",
             "| time step [s] | wall time [s] | steps | step halvings | residual evaluations / step | "
             "Jacobians / step | max sagbend moment [kN*m] | change from the step above |",
             "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    prev = None
    for x in conv:
        steps = max(x["steps"], 1)
        m = x["max_sagbend_moment"]
        change = "" if prev is None else f"{100 * abs(m - prev) / m:.2f} %"
        lines.append(f"| {x['time_step']:g} | {x['wall_time']:.1f} | {x['steps']} | {x['step_halvings']} | "
                     f"{x['newton_iterations'] / steps:.2f} | {x['jacobians'] / steps:.3f} | {m / 1e3:.3f} | {change} |")
        prev = m
    by_dt = {x["time_step"]: x["max_sagbend_moment"] for x in conv}
    ref_dt = REFERENCE["time_step"]
    half = [dt for dt in by_dt if abs(dt - ref_dt / 2) < 1e-12]
    if ref_dt in by_dt and half:
        c = abs(by_dt[ref_dt] - by_dt[half[0]]) / by_dt[half[0]]
        lines += ["", f"Halving the reference step {ref_dt:g} s changes this maximum by {100 * c:.2f} % "
                      f"(converged when < {100 * CONVERGED:g} %: {'yes' if c < CONVERGED else 'no'})."]
    return lines + [""]


def report(b: dict) -> str:
    p, r = b["production"], b["reference"]
    g = geometry()
    wall_3h = p["wall_time"] * DURATION / p["duration"]        # extrapolated for a --quick run
    ok_wall = wall_3h < TARGET_WALL
    ok_err = b["error"] < TARGET_ERROR
    la = b.get("load_average")
    lines = [MARK_BEGIN, "## S-lay in irregular waves (issue 3)", "",
             f"`rfesim bench --only slay` on {platform.machine()}, {os.cpu_count()} cores"
             + (f"; load average at the end {la[0]:.2f}, {la[1]:.2f}, {la[2]:.2f} (shared machine)" if la else "")
             + ".", "",
             f"Scenario `rfesim.bench.slay`: bare, empty 12-inch X65 pipe (0.3239 x 0.0159 m, steel, no coating, "
             f"submerged weight {g['submerged_weight']:.1f} N/m) in {DEPTH:g} m of water, clamped at the tensioner "
             f"of a lay barge, over a {STINGER_RADIUS:g} m radius stinger of V-rollers curving to "
             f"{DEPARTURE_DEG:g} deg (tip {-g['tip'][2]:.0f} m below the water line), lay tension "
             f"H = {g['H'] / 1e3:.1f} kN from the natural catenary that leaves the tip at that angle "
             f"(top tension {g['natural']['top_tension'] / 1e3:.0f} kN, suspended length "
             f"{g['natural']['suspended_length']:.0f} m), pinned 150 m beyond touchdown; barge RAOs "
             f"(scenarios/data/barge_100m_raos.json) in a JONSWAP sea Hs {HS:g} m, Tp {TP:g} s, head seas, seed "
             f"{SEED}; generalized-alpha (rho_inf 0.8). Output: the largest |bending moment| in the sagbend (SDEs "
             f"below {DEPTH / 2:g} m depth) over the run after the first {p['settle']:g} s (start-up), sampled every "
             f"{p['output_interval']:g} s in both runs. "
             f"Static sagbend moment {p['static_sagbend_moment'] / 1e3:.1f} kN*m (natural catenary EI w / H = "
             f"{g['EI'] * g['submerged_weight'] / g['H'] / 1e3:.1f} kN*m).", "",
             "| run | elements (suspended RFEs) | time step [s] | simulated [s] | wall time [s] | statics [s] | steps "
             "| step halvings | residual evaluations / step | Jacobians / step | max sagbend moment [kN*m] |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    runs = [("production", p), ("reference", r)]
    if b.get("production_3h"):
        runs.append(("production, 3 hours", b["production_3h"]))
    for name, x in runs:
        steps = max(x["steps"], 1)
        lines.append(f"| {name} | {x['elements']} ({x['suspended_rfes']}) | {x['time_step']:g} | {x['duration']:g} | "
                     f"{x['wall_time']:.1f} | {x['statics_wall_time']:.1f} | {x['steps']} | {x['step_halvings']} | "
                     f"{x['newton_iterations'] / steps:.2f} | {x['jacobians'] / steps:.3f} | "
                     f"{x['max_sagbend_moment'] / 1e3:.3f} |")
    lines += ["",
              f"Error of the production run's largest sagbend moment against the reference: "
              f"{100 * b['error']:.3f} % (target < {100 * TARGET_ERROR:g} %: {'met' if ok_err else 'missed'}). "
              f"Wall time of the dynamics for {p['duration']:g} s simulated: {p['wall_time']:.1f} s "
              f"(target < {TARGET_WALL:g} s for 3 hours: {'met' if ok_wall else 'missed'}"
              + (f", extrapolated {wall_3h:.0f} s" if b["quick"] else "") + ").", "",
              *convergence_lines(b.get("convergence", [])),
              "The reference is the same scenario, sea and seed with half the time step, run once by the bench; "
              "both runs sample the moment at the same output "
              "times." + (" This was a --quick run: "
                          f"{p['duration']:g} s simulated, not 3 hours; the 3-hour wall time extrapolates "
                          f"to about {wall_3h:.0f} s; the error over a short run says little about 3 hours."
                          if b["quick"] else ""),
              "", LIMITS]
    if b.get("production_3h"):
        x = b["production_3h"]
        lines += ["", f"3 hours with the production settings (run once, without a 3-hour reference): "
                      f"{x['wall_time']:.0f} s wall, {x['steps']} steps, {x['step_halvings']} halvings, largest "
                      f"sagbend moment {x['max_sagbend_moment'] / 1e3:.1f} kN*m."]
    lines += ["", MARK_END]
    return "\n".join(lines)


def write_section(text: str, path: Path) -> None:
    write_marked_section(text, path, MARK_BEGIN, MARK_END)


def run_slay_and_write(quick: bool, report_path: Path) -> str:
    b = run_bench(quick)
    text = report(b)
    write_section(text, report_path)
    store_entry(report_path, "slay", b)
    return text
