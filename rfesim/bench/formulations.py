"""``rfesim bench --only formulations``: cost per time step vs number of RFEs of each RFE
formulation, and the modal analysis of a 1000-RFE classical linear line.

Case: a cantilever clamped at one end along x (steel-like section EA 1e9 N, EI 1e6 N*m^2,
10 kg/m, 10 m), under gravity, started straight. Every formulation is timed on the same
beam with its own time integrator as rfesim runs it from a scenario:

* absolute (section 8.4): generalized-alpha, 0.01 s, through compile_scenario / System /
  run_dynamics (the approach of `run_scaling`), best of two;
* classical (8.1, eq. 8.7), classical-linear (eq. 8.8), modified (8.2): fixed-step RK4 of
  `simulate_chain` (4 evaluations of A q'' = f per step), all six (classical) or three
  (modified) coordinates per RFE;
* planar (8.3): compiled RK4 and generalized-alpha of `planar_dynamics` (`planar_bench`).

The cost of a step does not depend on its length; the chain runs use a tiny step so that
every size stays stable over the timed steps.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

MARK_BEGIN = "<!-- formulations-bench -->"
MARK_END = "<!-- /formulations-bench -->"


def _cantilever(n: int, formulation: str, duration: float = 0.0, integrator=None) -> dict:
    from .cases import cantilever
    d = cantilever(n, [], EI=1e6, L=10.0, EA=1e9, mass=10.0, gravity=9.81)
    d["lines"]["beam"]["formulation"] = formulation
    d["analysis"]["statics"] = {"enabled": False}
    d["analysis"]["dynamics"] = {"duration": duration, "integrator": integrator or {"kind": "rk4"}}
    return d


def absolute_per_step(n_rfe: int, steps: int = 20) -> float:
    """Seconds per generalized-alpha step of the absolute formulation (best of two)."""
    import rfesim
    from ..model.compile import compile_scenario
    from ..solvers.dynamics import run_dynamics
    from ..solvers.system import System
    h = 0.01
    sc = rfesim.load_scenario(_cantilever(n_rfe - 1, "absolute", steps * h,
                                          {"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8}))
    sc.analysis.dynamics.output_interval = steps * h
    system = System(compile_scenario(sc))
    state = system.model.initial
    best = math.inf
    for _ in range(2):
        t0 = time.perf_counter()
        _, _, counters = run_dynamics(system, state, sc.analysis.dynamics)
        best = min(best, (time.perf_counter() - t0) / counters["steps"])
    return best


def chain_per_step(n_rfe: int, formulation: str, steps: int = 10) -> float:
    """Seconds per RK4 step of simulate_chain for a cantilever line in a chain formulation."""
    import rfesim
    from ..formulations.chain import simulate_chain
    from ..formulations.scene import compile_scene
    sc = rfesim.load_scenario(_cantilever(n_rfe - 1, formulation))
    unit = compile_scene(sc).chains[0]
    dt = 1e-8
    simulate_chain(unit.model, 2 * dt, dt, output_every=2)            # warm up
    best = math.inf
    for _ in range(2):
        t0 = time.perf_counter()
        res = simulate_chain(unit.model, steps * dt, dt, output_every=steps)
        best = min(best, (time.perf_counter() - t0) / steps)
        assert res.success, res.message
    return best


def modal_1000(repeats: int = 3) -> dict:
    """Wall time of rfesim.modes (10 modes) of a clamped 1000-element classical-linear line
    (best of `repeats`, after one warm-up) and its first frequency against 3.516^2 sqrt(EI/mu L^4)."""
    import rfesim
    from .cases import BETA_L, cantilever
    d = cantilever(1000, [], EI=1e6, L=100.0, EA=1e9, mass=10.0)
    d["lines"]["beam"]["formulation"] = "classical-linear"
    sc = rfesim.load_scenario(d)
    rfesim.modes(sc, n=10)
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        md = rfesim.modes(sc, n=10)
        best = min(best, time.perf_counter() - t0)
    f1 = BETA_L[0] ** 2 * math.sqrt(1e6 / (10.0 * 100.0 ** 4)) / (2 * math.pi)
    return {"wall_time": best, "coordinates": 6000, "f1": float(md.frequencies_hz[0]), "f1_exact": f1}


def run(quick: bool = False, log=print) -> dict:
    from ..formulations.planar_bench import cost_per_step
    big = (10, 30, 100, 300) if quick else (10, 30, 100, 300, 1000)
    small = (10, 30, 100) if quick else (10, 30, 100, 300)
    out = {"absolute": {}, "classical": {}, "classical-linear": {}, "modified": {}}
    for n in big:
        log(f"formulations: absolute {n} RFEs")
        out["absolute"][n] = absolute_per_step(n)
    for f in ("classical", "classical-linear", "modified"):
        for n in small:
            log(f"formulations: {f} {n} RFEs")
            out[f][n] = chain_per_step(n, f)
    log("formulations: planar")
    p = cost_per_step(n_list=big, rk4_steps=200, implicit_steps=20, repeats=2)
    out["planar rk4"] = dict(zip(p["rfes"].tolist(), p["rk4"].tolist()))
    out["planar generalized-alpha"] = dict(zip(p["rfes"].tolist(), p["generalized-alpha"].tolist()))
    log("formulations: modal analysis of a 1000-RFE classical linear line")
    out["modal_1000"] = modal_1000()
    out["slopes"] = {k: slope(v) for k, v in out.items() if k not in ("modal_1000", "slopes")}
    return out


def slope(rows: dict) -> float:
    """Least-squares slope of log(time per step) against log(RFEs), from 30 RFEs up."""
    n = np.array([k for k in rows if k >= 30], float)
    t = np.array([rows[k] for k in rows if k >= 30], float)
    return float(np.polyfit(np.log(n), np.log(t), 1)[0]) if len(n) >= 2 else float("nan")


LABELS = {"absolute": "absolute (8.4), generalized-alpha", "classical": "classical (8.1, eq. 8.7), RK4",
          "classical-linear": "classical linear (eq. 8.8), RK4", "modified": "modified (8.2), RK4",
          "planar rk4": "planar (8.3), RK4 (compiled loop)",
          "planar generalized-alpha": "planar (8.3), generalized-alpha"}


def plot(data: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 5))
    for key, label in LABELS.items():
        rows = data[key]
        n = np.array(list(rows), float)
        ax.loglog(n, 1e3 * np.array(list(rows.values())), "o-", label=f"{label}: slope {data['slopes'][key]:.2f}")
    ax.set_xlabel("number of RFEs")
    ax.set_ylabel("wall time per time step [ms]")
    ax.set_title("Cost per step of the RFE formulations (cantilever)")
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def report(data: dict, quick: bool) -> str:
    import os
    import platform
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    sizes = sorted({n for k in LABELS for n in data[k]})
    lines = [MARK_BEGIN, "## RFE formulations", "",
             f"`rfesim bench --only formulations{' --quick' if quick else ''}` on {platform.machine()}, "
             f"{os.cpu_count()} cores; load average at the end {load[0]:.2f} (shared machine: compare within "
             "this table).", "",
             "Cantilever, 10 m, EA 1e9 N, EI 1e6 N*m^2, 10 kg/m, under gravity, each formulation with the "
             "integrator rfesim uses for it (module docstring of `rfesim/bench/formulations.py`). Wall time per "
             "time step in ms; '-' not run (the dense modified chain and the classical chain's dense "
             "mass-matrix buffers grow as n^2).", "",
             "| formulation, integrator | " + " | ".join(f"{n} RFEs" for n in sizes) + " | slope (n >= 30) |",
             "|---|" + "---:|" * (len(sizes) + 1)]
    for key, label in LABELS.items():
        rows = data[key]
        cells = [f"{1e3 * rows[n]:.3g}" if n in rows else "-" for n in sizes]
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {data['slopes'][key]:.2f} |")
    m = data["modal_1000"]
    lines += ["", "![cost per step of the formulations](img/formulations_cost.png)", "",
              f"Modal analysis (`rfesim.modes`, 10 modes) of a clamped 1000-element classical linear line "
              f"({m['coordinates']} coordinates; sparse shift-invert Lanczos on the constant diagonal M and "
              f"block-tridiagonal K of eqs. 8.34-8.35): **{m['wall_time']:.3f} s** (target < 1 s); first "
              f"frequency {m['f1']:.6g} Hz against 3.516^2 sqrt(EI/(mu L^4)) = {m['f1_exact']:.6g} Hz "
              f"({100 * (m['f1'] / m['f1_exact'] - 1):+.3f} %).", "",
              "Reading: the absolute and planar formulations and the classical chain's evaluation are O(n) per "
              "step; `simulate_chain` copies its dense nq x nq mass-matrix buffers on every evaluation, so the "
              "classical chains grow faster than their O(n) factorisation; the modified formulation's mass "
              "matrix is dense (eq. 8.51): O(n^2) to assemble, O(n^3) to factor.", MARK_END]
    return "\n".join(lines)


def write(data: dict, path: Path, quick: bool) -> str:
    """Plot to img/formulations_cost.png next to the report `path`, replace the report's
    formulations section (between its markers) and store the numbers in
    benchmarks_formulations.json."""
    import json
    docs = path.parent
    (docs / "img").mkdir(parents=True, exist_ok=True)
    plot(data, docs / "img" / "formulations_cost.png")
    text = report(data, quick)
    raw = {k: ({str(n): t for n, t in v.items()} if k in LABELS else v) for k, v in data.items()}
    (docs / "benchmarks_formulations.json").write_text(json.dumps(raw, indent=1, default=float))
    old = path.read_text() if path.exists() else "# Benchmarks\n"
    if MARK_BEGIN in old and MARK_END in old:
        a, b = old.index(MARK_BEGIN), old.index(MARK_END) + len(MARK_END)
        new = old[:a] + text + old[b:]
    else:
        new = old.rstrip("\n") + "\n\n" + text + "\n"
    path.write_text(new)
    return text
