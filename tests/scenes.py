"""Small scenes the tests share (plain dicts, a few seconds of work each): a tiny steel riser
to a heaving ship (absolute coordinates; also the service tests' riser), double pendulums
of rigid links, a cantilever as a planar line or a chain of modified links, and a rope
hanging from a sprung arm (a chain mixed with a line)."""
from __future__ import annotations

import copy

from rfesim.bench.cases import cantilever

G = 9.81

# a 12-element steel riser from the seabed to a heaving ship: absolute coordinates, seabed
# contact (touchdown), a top tension at end B (DAF); statics then 1 s of generalized-alpha,
# outputs every 0.1 s, about 0.1-0.2 s of work per second simulated
RISER: dict = {
    "schema_version": 1, "name": "tiny riser",
    "environment": {"gravity": G, "water": {"density": 1025.0, "depth": 50.0},
                    "seabed": {"normal_stiffness": 1.0e5, "damping_ratio": 0.5}},
    "vessels": {"ship": {"motion": {"kind": "harmonic", "heave": {"amplitude": 0.5, "period": 8.0},
                                    "ramp_duration": 2.0}}},
    "line_types": {"pipe": {"outer_diameter": 0.2, "wall_thickness": 0.012, "youngs_modulus": 2.0e11,
                            "density": 7850.0, "drag_normal": 1.0, "added_mass_normal": 1.0}},
    "lines": {"riser": {"type": "pipe", "length": 100.0, "elements": 12,
                        "end_a": {"attach": "fixed", "position": [-70.0, 0.0, -49.9]},
                        "end_b": {"attach": "ship", "position": [0.0, 0.0, -5.0]}}},
    "analysis": {"statics": {"enabled": True},
                 "dynamics": {"duration": 1.0, "output_interval": 0.1,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}},
}


def pendulum(kind="rk4", chains=("pendulum",)):
    """Double pendulums of rigid links (one chain unit each), 0.3 rad off the vertical from
    rest, statics off: 1 s, outputs every 0.1 s."""
    integ = {"kind": kind}
    if kind == "rk4":
        integ["time_step"] = 0.002
    chain = {"links": {"upper": {"rigid": True, "length": 1.0, "mass": 1.0},
                       "lower": {"rigid": True, "length": 1.0, "mass": 1.0}},
             "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper",
                                "direction": [0, 0, -1], "axis": [0, 1, 0], "initial": 0.3},
                        "middle": {"kind": "revolute", "parent": "upper", "child": "lower", "axis": [0, 1, 0]}}}
    return {"environment": {"gravity": G},
            "chains": {name: copy.deepcopy(chain) for name in chains},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": 1.0, "output_interval": 0.1, "integrator": integ}}}



def cantilever_line(formulation, kind):
    """A 10 m cantilever with a 10 kN tip load dropped from straight, as a planar line or a
    chain of modified links: 0.2 s, outputs every 0.01 s."""
    sc = cantilever(10, [{"at": "end_b", "force": [0, 0, -1e4]}], EI=2.2e8, L=10.0, EA=3.2e10, GA=1e10,
                    mass=120.0, gravity=G)
    sc["lines"]["beam"]["formulation"] = formulation
    sc["analysis"]["statics"]["enabled"] = False
    integ = {"kind": kind}
    if kind != "adaptive":
        integ["time_step"] = 1e-4
    sc["analysis"]["dynamics"] = {"duration": 0.2, "output_interval": 0.01, "integrator": integ}
    return sc



def mixed_rope():
    """A 3 m rope hanging from a sprung 2 m arm: statics, then 0.2 s of generalized-alpha with
    0.01 s steps, outputs every 0.05 s."""
    return {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": 1e5, "EIy": 1e-2, "GA": 1e5, "mass_per_length": 2.0}},
            "chains": {"c": {"links": {"arm": {"rigid": True, "length": 2.0, "mass": 10.0}},
                             "joints": {"j": {"kind": "revolute", "parent": "base", "child": "arm",
                                              "axis": [0, 1, 0], "stiffness": 5e3, "initial": 0.05}}}},
            "lines": {"rope": {"type": "rope", "length": 3.0, "elements": 4, "end_a": {"attach": "c.arm"},
                               "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": True, "duration": 0.2, "output_interval": 0.05,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01,
                                                     "rho_inf": 0.8}}}}



def j_lay_template(element_length: float, *, vessel: dict | None = None, analysis: dict | None = None,
                   name: str = "J-lay template") -> dict:
    """The bundled J-lay template (scenarios/j_lay.json as of these tests): a 12-inch X65 pipe
    from an 85 deg tower into 1200 m of water, 50 m laid; ``vessel`` is the template's vessel
    section (at the origin, still by default), ``analysis`` the scenario's (statics only by
    default)."""
    return {
        "schema_version": 1, "name": name,
        "environment": {"gravity": G, "water": {"density": 1025.0, "depth": 1200.0},
                        "seabed": {"normal_stiffness": 1.0e6, "damping_ratio": 0.2, "friction": 0.5}},
        "pipelay": {"lay": {
            "method": "j-lay", "tower_angle_deg": 85.0, "exit": [0.0, 0.0, 0.0],
            "vessel": vessel if vessel is not None else {"position": [0.0, 0.0, 0.0]},
            "pipe": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "grade": "X65"},
            "laid_length": 50.0, "element_length": element_length}},
        "analysis": analysis if analysis is not None else {"statics": {"enabled": True},
                                                           "dynamics": {"enabled": False}},
    }
