"""Cost per time step of the planar formulation vs the number of RFEs (for ``rfesim bench``).

Case: a clamped cantilever (L = 10 m, EI = 1e5 N*m^2, 10 kg/m) under gravity, base heaving
harmonically, started straight. RK4: the whole loop compiled, step 0.3 sqrt(J_min / c_max)
(inside the stability limit; the cost per step does not depend on it). Generalised-alpha: step 1e-3 s, Newton on the banded KKT system
(Python driver around the kernels)."""
from __future__ import annotations

import math
import time

import numpy as np

from .planar import BaseMotion, planar_beam, planar_dynamics


def _model(n_rfe: int):
    motion = BaseMotion(y=lambda t: (0.1 * math.sin(2.0 * t), 0.2 * math.cos(2.0 * t), -0.4 * math.sin(2.0 * t)))
    return planar_beam(10.0, 1e5, 10.0, max(n_rfe - 1, 0), gravity=9.81, base_motion=motion)


def _per_step(model, method, step, steps, repeats):
    planar_dynamics(model, 2 * step, step, method=method)        # compile / warm up
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        planar_dynamics(model, steps * step, step, method=method, record_every=steps)
        best = min(best, time.perf_counter() - t0)
    return best / steps


def cost_per_step(n_list=(10, 30, 100, 300, 1000), rk4_steps: int = 200, implicit_steps: int = 20,
                  repeats: int = 3) -> dict:
    """Seconds per time step vs number of RFEs: {'rfes': (k,), 'rk4': (k,),
    'generalized-alpha': (k,)} (best of ``repeats``). RK4 time includes sampling the base
    motion at the stage times in Python."""
    rk4, implicit = [], []
    for n in n_list:
        model = _model(int(n))
        h = 0.3 * math.sqrt(model.inertia.min() / max(model.sde_stiffness.max(initial=0.0), 1e-30))
        rk4.append(_per_step(model, "rk4", min(h, 1e-3), rk4_steps, repeats))
        implicit.append(_per_step(model, "generalized-alpha", 1e-3, implicit_steps, repeats))
    return {"rfes": np.asarray(n_list, dtype=int), "rk4": np.array(rk4), "generalized-alpha": np.array(implicit)}


if __name__ == "__main__":   # pragma: no cover
    out = cost_per_step()
    for n, a, b in zip(out["rfes"], out["rk4"], out["generalized-alpha"]):
        print(f"{n:6d} RFEs  rk4 {a * 1e6:9.1f} us/step   generalized-alpha {b * 1e6:9.1f} us/step")
