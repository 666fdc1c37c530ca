"""Benchmark line H1 (docs/benchmarks.md): a steel catenary riser on a heaving fairlead.

Measured quantities over 28-60 s: the first-harmonic amplitude of the fairlead tension (a
least-squares fit of a0 + a cos(wt) + b sin(wt) at 0.125 Hz) and the largest bending
moment along the line (the sag bend). The error of a run is the larger of their relative
errors against a converged solution.
"""
from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

SCENARIO = Path(__file__).resolve().parents[2] / "scenarios" / "h1_riser_heave.json"
WINDOW = (28.0, 60.0)
FREQUENCY = 0.125          # Hz


def first_harmonic_amplitude(time_s: np.ndarray, signal: np.ndarray, frequency: float = FREQUENCY,
                             window: tuple[float, float] = WINDOW) -> float:
    """Amplitude of the least-squares fit a0 + a cos(wt) + b sin(wt) over the window."""
    sel = (time_s >= window[0] - 1e-9) & (time_s <= window[1] + 1e-9)
    w = 2.0 * math.pi * frequency
    t = time_s[sel]
    A = np.column_stack([np.ones_like(t), np.cos(w * t), np.sin(w * t)])
    coef, *_ = np.linalg.lstsq(A, signal[sel], rcond=None)
    return float(math.hypot(coef[1], coef[2]))


@dataclass
class H1Run:
    code: str                 # "rfesim" | "moordyn"
    segments: int
    setting: str              # time step / tolerance description
    wall_time: float          # s, the dynamic run only
    total_time: float         # s, including statics / initial conditions
    tension_amplitude: float  # N
    max_moment: float         # N*m
    error: float = float("nan")

    def as_row(self) -> dict:
        return {k: getattr(self, k) for k in ("code", "segments", "setting", "wall_time", "total_time",
                                              "tension_amplitude", "max_moment", "error")}


def h1_scenario(elements: int, integrator: dict, output_interval: float = 0.05):
    import rfesim
    data = json.loads(SCENARIO.read_text())
    data["lines"]["riser"]["elements"] = int(elements)
    data["analysis"]["dynamics"]["integrator"] = integrator
    data["analysis"]["dynamics"]["output_interval"] = output_interval
    return rfesim.load_scenario(data)


def run_rfesim_h1(elements: int, integrator: dict, label: str, repeats: int = 1, scenario=h1_scenario) -> H1Run:
    """One H1 run: statics, then 60 s of dynamics (timed alone, best of ``repeats``).
    ``scenario(elements, integrator)`` builds the scenario (H2 passes its own)."""
    from ..model.compile import compile_scenario
    from ..solvers.dynamics import run_dynamics
    from ..solvers.statics import solve_statics
    from ..solvers.system import System
    sc = scenario(elements, integrator)
    t0 = time.perf_counter()
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system)
    t_static = time.perf_counter() - t0
    best = math.inf
    rec = None
    for _ in range(max(1, repeats)):
        t1 = time.perf_counter()
        _, rec, _ = run_dynamics(system, state, sc.analysis.dynamics)
        best = min(best, time.perf_counter() - t1)
    line = rec.results().line("riser")
    t = rec.time[:rec.k]
    amplitude = first_harmonic_amplitude(t, line.top_tension)
    sel = (t >= WINDOW[0] - 1e-9) & (t <= WINDOW[1] + 1e-9)
    moment = float(line.bend_moment[sel].max())
    return H1Run("rfesim", elements, label, best, best + t_static, amplitude, moment)


def assign_errors(runs: list[H1Run], reference: H1Run) -> None:
    for r in runs:
        r.error = max(abs(r.tension_amplitude / reference.tension_amplitude - 1.0),
                      abs(r.max_moment / reference.max_moment - 1.0))


def time_to_reach(runs: list[H1Run], target: float) -> float:
    """Smallest wall time among runs whose error is at most target (inf if none);
    interpolated in log-log between the fastest run above and the cheapest run below the
    target along the work-precision front."""
    pts = sorted((r.wall_time, r.error) for r in runs if np.isfinite(r.error) and r.error > 0)
    ok = [w for w, e in pts if e <= target]
    if not ok:
        return math.inf
    w_ok = min(ok)
    # the front: for each wall time, the best error achieved at or below it
    front = []
    best = math.inf
    for w, e in pts:
        if e < best:
            best = e
            front.append((w, e))
    for (w0, e0), (w1, e1) in zip(front, front[1:]):
        if e0 > target >= e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return float(math.exp(math.log(w0) + f * (math.log(w1) - math.log(w0))))
    return w_ok
