"""Benchmark case "S-lay in irregular waves" (issue 3): a deep-water S-lay scenario.

The pipe: 12-inch X65, OD 0.3239 m, wall 0.0159 m, steel (E 207 GPa, 7850 kg/m^3), empty
(air inside) and bare (no coating): mass 120.8 kg/m, submerged weight w = 356.6 N/m,
EI = 3.79e7 N*m^2; C_dn 1.0, C_an 1.0. Water 1000 m deep.

The lay vessel (attachment ``barge``, heading 0, lay direction +x, the stinger over the
stern) moves by the illustrative barge RAOs of ``scenarios/data/barge_100m_raos.json`` in
a JONSWAP sea Hs 2.5 m, Tp 8 s, head seas (waves travel toward 180 deg: relative heading
180), seeded, ramped in over 20 s. The pipe is clamped horizontally at the tensioner
(TENSIONER_X behind the first roller), runs over a long steep stinger of V-rollers
(radius STINGER_RADIUS, curving down through DEPARTURE_DEG: a deep-water stinger whose
tip is about 60 m below the water line), hangs in the sagbend to the seabed and ends
pinned LAID_LENGTH beyond the touchdown point. The lay tension is the one whose natural
catenary (``rfesim.catenary.natural_catenary``) leaves the stinger tip at the stinger's
own tip angle and touches down tangentially on the seabed: H = w h / x with x from
x^2 + 2 x = tan^2(theta) (h the height of the tip above the seabed), so statics starts
from a shape through the lift-off and touchdown points that is already close.

The line has uniform elements: ``suspended_rfes`` elements on the natural catenary's
suspended length (200 in the benchmark), the same element length on the stinger and on
the laid pipe. Output: the largest |bending moment| in the sagbend (the SDEs in the lower
half of the water column) over the run after SETTLE seconds of start-up
(:func:`max_sagbend_moment`): the vessel and the sea start from rest and the first 100 s
carry a start-up transient at touchdown that is no part of the sea state's response.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ..catenary import natural_catenary

ROOT = Path(__file__).resolve().parents[2]
RAO_FILE = ROOT / "scenarios" / "data" / "barge_100m_raos.json"

OD, WT = 0.3239, 0.0159                 # m
E_STEEL, RHO_STEEL = 207e9, 7850.0      # Pa, kg/m^3
RHO_WATER, GRAVITY = 1025.0, 9.81
DEPTH = 1000.0                          # m
HS, TP, SEED = 2.5, 8.0, 3              # m, s, -
WAVE_DIRECTION_DEG = 180.0              # head seas for the vessel heading 0
WAVE_RAMP = 20.0                        # s
STINGER_RADIUS = 120.0                  # m, of the roller axes
DEPARTURE_DEG = 62.0                    # stinger tip angle from horizontal = departure angle
STINGER_START = (0.0, 0.0, 2.0)         # m, vessel frame: first roller station
TENSIONER_X = -12.0                     # m, vessel frame: end A (clamped, horizontal)
ROLLER_SPACING = 8.0                    # m
ROLLER_RADIUS, ROLLER_WIDTH, V_ANGLE = 0.15, 0.6, 30.0
ROLLER_STIFFNESS, ROLLER_DAMPING, ROLLER_FRICTION = 1e7, 1e4, 0.1
# stick spring of the rollers' spring-slider friction (rfesim.loads.rollers): 1e6 N/m, so friction
# is mobilised over mu N / k_t = 2.5 mm of sliding at a 25 kN roller load (the shear compliance of a
# roller cover) instead of 0.25 mm with the default k_t = k. With k_t = k, the contact points of a
# V-roller pair slide along the roller axes by half the change of the pipe's penetration into the
# V, so most rollers switched between stick and slip within every 0.1-0.2 s step and the Newton
# iteration's reused Jacobian went stale (docs/slay_speed_notes.md, branch slay-smooth). The
# largest sagbend moment over 300 s moves by -0.03 % (0.1 s) and -0.02 % (0.05 s).
ROLLER_FRICTION_STIFFNESS = 1e6
LAID_LENGTH = 150.0                     # m of pipe on the seabed beyond touchdown
SETTLE = 100.0                          # s of start-up (sea ramped in over WAVE_RAMP) left out of the maximum
SEABED_K = 1e5                          # N/m/m (soft clay)
# wave kinematics cut off where all components together are below 1e-6 of the sea's velocity
# bound (below about 370 m here; docs/theory.md 'Wave kinematics cut-off at depth'): 3e-5 m/s
KINEMATICS_CUTOFF = 1e-6
# Newton tolerance: largest residual force 1e-3 of an element weight (9.3 N on a 7.8 m RFE; the
# default 1e-6 asks for 9 mN, i.e. 2e-11 m of axial stretch at EA/L = 4e8 N/m). Over 300 s the
# largest sagbend moment is the same to 1 N*m at 0.1, 0.05 and 0.025 s as with 1e-6, with 28 %
# fewer residual evaluations at 0.1 s (docs/slay_speed_notes.md, branch slay-smooth)
NEWTON_TOLERANCE = 1e-3


def pipe_properties() -> dict:
    area = math.pi / 4.0 * (OD ** 2 - (OD - 2 * WT) ** 2)
    mass = RHO_STEEL * area
    w = (mass - RHO_WATER * math.pi / 4.0 * OD ** 2) * GRAVITY
    inertia = math.pi / 64.0 * (OD ** 4 - (OD - 2 * WT) ** 4)
    return {"mass": mass, "submerged_weight": w, "EI": E_STEEL * inertia, "EA": E_STEEL * area}


def geometry() -> dict:
    """Stinger tip, catenary (H, suspended length, span) and the line's length and end B."""
    p = pipe_properties()
    w = p["submerged_weight"]
    rp = OD / 2.0
    v = math.radians(V_ANGLE)
    lift = (rp + ROLLER_RADIUS) / math.cos(v)          # pipe axis above the V bottom
    theta = math.radians(DEPARTURE_DEG)
    Rp = STINGER_RADIUS + lift
    x0, _, z0 = STINGER_START
    zA = z0 + lift
    tip = np.array([x0 + Rp * math.sin(theta), 0.0, zA - Rp * (1.0 - math.cos(theta))])
    z_axis = -DEPTH + rp                               # pipe axis on the seabed
    h = tip[2] - z_axis
    x = -1.0 + math.sqrt(1.0 + math.tan(theta) ** 2)   # h / a for a top angle theta
    H = w * h / x
    nat = natural_catenary(w, h, H)
    on_vessel = (x0 - TENSIONER_X) + Rp * theta
    length = on_vessel + nat["suspended_length"] + LAID_LENGTH
    end_b = [float(tip[0] + nat["horizontal_span"] + LAID_LENGTH), 0.0, float(z_axis)]
    return {"tip": tip, "zA": zA, "h": h, "H": H, "natural": nat, "length": length, "end_b": end_b,
            "on_vessel": on_vessel, "z_axis": z_axis, **p}


def slay_data(suspended_rfes: int = 200, time_step: float = 0.2, duration: float = 10800.0,
              output_interval: float | None = None, rho_inf: float = 0.8) -> dict:
    """The benchmark scenario as a dict (JSON-able)."""
    g = geometry()
    dx = g["natural"]["suspended_length"] / suspended_rfes
    elements = int(round(g["length"] / dx))
    raos = json.loads(RAO_FILE.read_text())
    return {
        "schema_version": 1,
        "name": "S-lay benchmark: 12-inch X65 in 1000 m, JONSWAP Hs 2.5 m Tp 8 s",
        "description": (f"Deep-water S-lay (rfesim.bench.slay): bare, empty 12-inch X65 pipe over a "
                        f"{STINGER_RADIUS:g} m radius stinger of V-rollers to {DEPARTURE_DEG:g} deg, lay tension "
                        f"H = {g['H'] / 1e3:.1f} kN (natural catenary from the tip), {elements} elements "
                        f"({suspended_rfes} on the suspended length), barge RAOs in JONSWAP Hs {HS} m Tp {TP} s, "
                        f"head seas, seed {SEED}."),
        "environment": {
            "gravity": GRAVITY,
            "water": {"density": RHO_WATER, "depth": DEPTH,
                      "waves": {"kind": "jonswap", "hs": HS, "tp": TP, "direction_deg": WAVE_DIRECTION_DEG,
                                "seed": SEED, "ramp_duration": WAVE_RAMP,
                                "kinematics_cutoff": KINEMATICS_CUTOFF}},
            "seabed": {"z": -DEPTH, "normal_stiffness": SEABED_K, "damping_ratio": 0.2, "friction": 0.5},
        },
        "vessels": {"barge": {"position": [0.0, 0.0, 0.0], "heading_deg": 0.0,
                              "motion": {"kind": "rao", "raos": raos}}},
        "line_types": {"x65": {"outer_diameter": OD, "wall_thickness": WT, "youngs_modulus": E_STEEL,
                               "density": RHO_STEEL, "drag_normal": 1.0, "added_mass_normal": 1.0,
                               "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {
            "type": "x65", "length": g["length"], "elements": elements,
            "end_a": {"attach": "barge", "position": [TENSIONER_X, 0.0, g["zA"]], "direction": [1, 0, 0],
                      "connection": "clamped"},
            "end_b": {"attach": "fixed", "position": g["end_b"], "connection": "pinned"}}},
        "supports": {"stinger": {
            "kind": "stinger", "attach": "barge", "line": "pipe", "start": list(STINGER_START),
            "direction": [1, 0, 0], "radius": STINGER_RADIUS,
            "length": STINGER_RADIUS * math.radians(DEPARTURE_DEG), "spacing": ROLLER_SPACING,
            "roller_width": ROLLER_WIDTH, "roller_radius": ROLLER_RADIUS, "v_angle_deg": V_ANGLE,
            "stiffness": ROLLER_STIFFNESS, "damping": ROLLER_DAMPING, "friction": ROLLER_FRICTION,
            "friction_stiffness": ROLLER_FRICTION_STIFFNESS}},
        "analysis": {
            "statics": {"enabled": True},
            "dynamics": {"duration": duration,
                         "integrator": {"kind": "generalized-alpha", "time_step": time_step, "rho_inf": rho_inf,
                                        "tolerance": NEWTON_TOLERANCE},
                         "output_interval": output_interval if output_interval is not None else time_step},
        },
    }


def slay_scenario(**kw):
    import rfesim
    return rfesim.load_scenario(slay_data(**kw))


def sagbend_mask(position: np.ndarray) -> np.ndarray:
    """SDEs in the sagbend: the lower half of the water column (position: (npts, 3) of one
    record, end A, the SDEs, end B)."""
    return position[1:-1, 2] < -0.5 * DEPTH


def max_sagbend_moment(bend_moment: np.ndarray, position: np.ndarray) -> float:
    """Largest |bending moment| over the records and the sagbend SDEs of each record."""
    m = 0.0
    for k in range(bend_moment.shape[0]):
        sel = sagbend_mask(position[k])
        if sel.any():
            m = max(m, float(np.abs(bend_moment[k][sel]).max()))
    return m


def run_slay(suspended_rfes: int = 200, time_step: float = 0.2, duration: float = 10800.0,
             output_interval: float = 0.4, chunk: float = 900.0, log=None) -> dict:
    """Statics, then ``duration`` of dynamics in chunks of ``chunk`` seconds (the records of
    one chunk are reduced to the sagbend maximum and dropped, so 3 hours fit in memory);
    returns the largest sagbend moment, wall times and the solver counters."""
    import time
    from ..api import _static_state
    from ..model.compile import compile_scenario
    from ..solvers.dynamics import Counters, run_dynamics
    from ..solvers.system import System
    sc = slay_scenario(suspended_rfes=suspended_rfes, time_step=time_step, duration=duration,
                       output_interval=output_interval)
    t0 = time.perf_counter()
    system = System(compile_scenario(sc))
    state, info = _static_state(system, sc)
    t_static = time.perf_counter() - t0
    rec0 = None
    counters = Counters()
    m_max = 0.0
    static_moment = None
    dyn = sc.analysis.dynamics
    done = 0.0
    t1 = time.perf_counter()
    while done < duration - 1e-9:
        part = min(chunk, duration - done)
        settings = dyn.model_copy(update={"duration": part})
        state, rec, counters = run_dynamics(system, state, settings, counters=counters)
        line = rec.line_data["pipe"]
        k = rec.k
        if static_moment is None:
            static_moment = max_sagbend_moment(line["bend_moment"][:1], line["position"][:1])
            rec0 = line["position"][0].copy()
        keep = rec.time[:k] >= SETTLE - 1e-9
        if keep.any():
            m_max = max(m_max, max_sagbend_moment(line["bend_moment"][:k][keep], line["position"][:k][keep]))
        done += part
        if log is not None:
            log(f"  S-lay {suspended_rfes} RFEs dt={time_step:g}: {done:g} s simulated, "
                f"{time.perf_counter() - t1:.1f} s wall, halvings {counters.get('step_halvings', 0)}")
    wall = time.perf_counter() - t1
    km = system.km
    return {"suspended_rfes": suspended_rfes, "elements": int(sc.lines["pipe"].elements),
            "rfes": int(km.rfe_length.shape[0]), "time_step": time_step, "duration": duration,
            "output_interval": output_interval, "settle": SETTLE,
            "step_used": float(counters.get("time_step", time_step)),
            "wall_time": wall, "statics_wall_time": t_static,
            "statics_iterations": int(info.iterations), "steps": int(counters.get("steps", 0)),
            "step_halvings": int(counters.get("step_halvings", 0)),
            "newton_iterations": int(counters.get("newton_iterations", 0)),
            "jacobians": int(counters.get("jacobians", 0)),
            "max_sagbend_moment": m_max, "static_sagbend_moment": static_moment,
            "static_touchdown_x": float(_touchdown_x(rec0)), "H": float(geometry()["H"])}


def _touchdown_x(position: np.ndarray) -> float:
    """x of the first SDE point within 1 cm of the seabed (pipe axis), from end A."""
    z_axis = -DEPTH + OD / 2.0
    near = np.nonzero(position[:, 2] < z_axis + 0.01)[0]
    return float(position[near[0], 0]) if near.size else float("nan")
