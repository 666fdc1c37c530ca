"""The column-crane benchmark of issue 5: the column crane of ``scenarios/column_crane.json``
(pedestal, boom, hoist rope, 10 t module) holding its payload 10 m under the surface on a
barge moving by its RAOs in a JONSWAP sea, 30 minutes simulated, about 100 RFEs in all.
Reported: wall time against real time, and the error of the largest rope tension against a
converged run (the same sea and seed with a smaller time step).
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCENARIO = ROOT / "scenarios" / "column_crane.json"
HS, TP, SEED = 2.0, 8.0, 11
DIRECTION = 0.0              # deg, following seas for the heading 0 (in beam seas the barge's roll slackens the rope: a harsher case)
DEPTH_OF_PAYLOAD = 10.0      # m, payload centre under the still water level
SETTLE = 60.0                # s, start-up left out of the maximum (waves ramp in over 20 s)


def crane_data(time_step: float = 0.1, duration: float = 1800.0, output_interval: float = 0.2,
               rope_elements: int = 45, boom_elements: int = 40, pedestal_elements: int = 12) -> dict:
    """The bench scenario (a dict): the template crane slewed over the side, boom at 45 deg,
    no slewing, luffing or winch motion; the rope long enough to hold the payload
    ``DEPTH_OF_PAYLOAD`` under the surface; RFEs: pedestal + boom + rope + 1 (payload)."""
    data = json.loads(SCENARIO.read_text())
    crane = data["cranes"]["crane"]
    crane["slewing_deg"] = 90.0
    crane.pop("winch", None)
    crane["pedestal"]["elements"] = pedestal_elements
    crane["boom"]["elements"] = boom_elements
    tip_z = crane["position"][2] + crane["pedestal"]["length"] + crane["boom"]["length"] * np.sin(np.radians(45.0))
    height = crane["payload"]["height"]
    crane["rope"] = dict(crane["rope"], length=float(tip_z + DEPTH_OF_PAYLOAD - 0.5 * height),
                         elements=rope_elements)
    data["vessels"]["barge"]["motion"]["file"] = str(ROOT / "scenarios" / "data" / "barge_100m_raos.json")
    data["environment"]["water"]["waves"].update(hs=HS, tp=TP, seed=SEED, direction_deg=DIRECTION)
    data["analysis"] = {"statics": {"enabled": True},
                        "dynamics": {"duration": duration, "output_interval": output_interval,
                                     "integrator": {"kind": "generalized-alpha", "time_step": time_step,
                                                    "rho_inf": 0.8}}}
    data["name"] = "column crane bench: 10 t payload 10 m under the surface, JONSWAP Hs 2 m, Tp 8 s"
    return data


def run_crane(time_step: float = 0.1, duration: float = 1800.0, output_interval: float = 0.2, log=None,
              **kw) -> dict:
    """Statics and dynamics of the bench scenario; returns the largest rope tension (at the
    sheave, after SETTLE), wall times, RFE count and solver counters."""
    from ..api import _static_state
    from ..model.compile import compile_scenario
    from ..scenario import Scenario
    from ..solvers.dynamics import Counters, run_dynamics
    from ..solvers.system import System
    sc = Scenario.model_validate(crane_data(time_step, duration, output_interval, **kw))
    t0 = time.perf_counter()
    system = System(compile_scenario(sc))
    state, info = _static_state(system, sc)
    t_static = time.perf_counter() - t0
    t1 = time.perf_counter()
    state, rec, counters = run_dynamics(system, state, sc.analysis.dynamics, counters=Counters())
    wall = time.perf_counter() - t1
    res = rec.results()
    rope = res.line("crane_rope")
    tension = np.asarray(rope.tension)[:, 0]
    keep = np.asarray(res.time) >= SETTLE - 1e-9
    hook = np.asarray(res.body("crane_payload").tension)
    if log is not None:
        log(f"  crane dt={time_step:g}: {duration:g} s simulated in {wall:.1f} s wall")
    return {"time_step": time_step, "duration": duration, "output_interval": output_interval,
            "rfes": int(system.km.rfe_length.shape[0]), "wall_time": wall, "statics_wall_time": t_static,
            "real_time_factor": duration / wall if wall > 0 else float("inf"),
            "steps": int(counters.get("steps", 0)), "step_halvings": int(counters.get("step_halvings", 0)),
            "newton_iterations": int(counters.get("newton_iterations", 0)),
            "jacobians": int(counters.get("jacobians", 0)),
            "static_tension": float(tension[0]), "max_tension": float(tension[keep].max()),
            "min_tension": float(tension[keep].min()), "max_hook_tension": float(hook[keep].max()),
            "statics_iterations": int(info.iterations)}

