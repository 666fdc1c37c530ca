"""The validation cases of VALIDATION.md as scenario builders and measurements, shared by
the tests (tests/validation) and the validation report (``rfesim bench --validation``,
docs/validation.md)."""
from __future__ import annotations

import math

import numpy as np

G = 9.81

# --------------------------------------------------------------------------- references
MATTIASSON = {1.0: (0.30172, 0.05643, 0.46135), 10.0: (0.81061, 0.55500, 1.43029)}
BETA_L = np.array([1.875104, 4.694091, 7.854757, 10.995541])
B4_RATIOS = {10: [1.00230, 1.00802, 1.01303, 1.01760], 20: [1.00057, 1.00199, 1.00327, 1.00454]}
CHAIN_C = np.array([1.20241, 2.76004, 4.32686])
PENDULUM = {30.0: 1.017409, 90.0: 1.180341, 150.0: 1.762204}
P1_SEABED = {"H": 96643.4, "V": 237751.8, "grounded": 202.810}
P1_SUSPENDED = {"H": 43694.6, "V": 77634.4, "V_anchor": 22365.6}


# --------------------------------------------------------------------------- beams
def cantilever(n, loads, *, EI=1.0, L=1.0, EA=1e7, GA=None, shear="fem", EIz=None, mass=1.0, rotary=0.0,
               gravity=0.0, load_steps=1):
    """A cantilever clamped at the origin along +x, free at end B (a scenario dict)."""
    lt = {"EA": EA, "EIy": EI, "GA": GA if GA is not None else EA, "mass_per_length": mass,
          "rotary_inertia": rotary}
    if EIz is not None:
        lt["EIz"] = EIz
    return {
        "name": "cantilever",
        "environment": {"gravity": gravity},
        "line_types": {"beam": lt},
        "lines": {"beam": {"type": "beam", "length": L, "elements": n, "shear_stiffness": shear,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}, "loads": loads}},
        "analysis": {"statics": {"enabled": True, "tolerance": 1e-12, "load_steps": load_steps},
                     "dynamics": {"enabled": False}},
    }


def r1_tip_force(n, shear, L=10.0, EI=1e6, GA=1e9):
    """R1: (deflection, rotation) per unit tip force, with the O(P^3) geometric
    nonlinearity removed by Richardson extrapolation from P and 2P; and the references."""
    import rfesim

    def run(P):
        line = rfesim.statics(cantilever(n, [{"at": "end_b", "force": [0, 0, -P]}], EI=EI, L=L, EA=1e12, GA=GA,
                                         shear=shear)).line("beam")
        d = line.end_b_direction[0]
        return -line.position[0, -1, 2] / P, math.atan2(-d[2], d[0]) / P

    P = 1e-3 * EI / L ** 2
    w1, r1 = run(P)
    w2, r2 = run(2 * P)
    bending = L ** 3 / (3 * EI) * (1 - 1 / (4 * n ** 2))
    shear_part = L / GA if shear == "kruszewski" else L ** 3 / (12 * EI * n ** 2)
    return ((4 * w1 - w2) / 3, (4 * r1 - r2) / 3), (bending + shear_part, L ** 2 / (2 * EI))


def r1_tip_moment(n, L=10.0, EI=1e6):
    """R1 with a tip moment: (deflection, rotation) per unit moment, Richardson-extrapolated."""
    import rfesim

    def run(Mi):
        line = rfesim.statics(cantilever(n, [{"at": "end_b", "moment": [0, -Mi, 0]}], EI=EI, L=L,
                                         EA=1e12)).line("beam")
        d = line.end_b_direction[0]
        return line.position[0, -1, 2] / Mi, math.atan2(d[2], d[0]) / Mi

    M = 1e-3 * EI / L
    w1, r1 = run(M)
    w2, r2 = run(2 * M)
    return ((4 * w1 - w2) / 3, (4 * r1 - r2) / 3), (L ** 2 / (2 * EI), L / EI)


def mattiasson(n, alpha):
    """B1: (w/L, u/L, tip rotation) of a cantilever under a dead tip load alpha EI/L^2."""
    import rfesim
    line = rfesim.statics(cantilever(n, [{"at": "end_b", "force": [0, 0, -alpha]}])).line("beam")
    tip = line.position[0, -1]
    d = line.end_b_direction[0]
    return -tip[2], 1.0 - tip[0], -math.atan2(d[2], d[0])


def end_moment(n, fraction, L=1.0, EI=1.0):
    """B2: line results under a tip moment fraction * 2 pi EI/L, the moment, and the tip
    position error relative to the exact circle (over L)."""
    import rfesim
    M = fraction * 2 * math.pi * EI / L
    line = rfesim.statics(cantilever(n, [{"at": "end_b", "moment": [0, M, 0]}], EI=EI, L=L)).line("beam")
    kappa = M / EI
    expected = np.array([math.sin(kappa * L), 0.0, -(1 - math.cos(kappa * L))]) / kappa
    return line, M, float(np.linalg.norm(line.position[0, -1] - expected) / L)


def b4_frequencies(n, shear="kruszewski", L=10.0, EI=1e6, mu=10.0):
    """B4: the first four in-plane bending frequencies over the continuum ones."""
    import rfesim
    sc = cantilever(n, [], EI=EI, L=L, EA=1e12, GA=1e13 if shear == "kruszewski" else None, shear=shear,
                    EIz=100 * EI, mass=mu)
    md = rfesim.modes(sc, n=12)
    shapes = md.line_shapes["beam"]
    inplane = [k for k in range(len(md.frequencies_hz))
               if np.abs(shapes[k][:, 2]).max() > 0.9 * np.abs(shapes[k]).max()]
    f = md.frequencies_hz[inplane][:4]
    exact = BETA_L[:len(f)] ** 2 * math.sqrt(EI / (mu * L ** 4)) / (2 * math.pi)
    return f / exact


def hanging_chain(n, L=10.0):
    return {
        "environment": {"gravity": G},
        "line_types": {"chain": {"EA": 1e9, "EIy": 1e-3, "GA": 1e9, "GJ": 1e-3, "mass_per_length": 1.0,
                                 "rotary_inertia": 0.0}},
        "lines": {"chain": {"type": "chain", "length": L, "elements": n, "shear_stiffness": "kruszewski",
                            "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, -1],
                                      "connection": "pinned"},
                            "end_b": {"attach": "free"}}},
    }


def chain_frequencies(n, L=10.0, modes=12):
    """B5: distinct swinging frequencies as c_n = omega / sqrt(g/L) (each comes as a pair in
    x and y; the free rotation about the vertical has zero frequency)."""
    import rfesim
    md = rfesim.modes(hanging_chain(n, L), n=modes)
    f = np.sort(md.frequencies_hz[md.frequencies_hz > 1e-6])
    distinct = [f[0]]
    for x in f[1:]:
        if x > distinct[-1] * (1 + 1e-6):
            distinct.append(x)
    return 2 * math.pi * np.array(distinct) / math.sqrt(G / L)


def pendulum_period_ratio(theta0_deg, integrator, n=4, L=2.0, periods=2.2):
    """B9: a stiff rod pinned at the top released from rest at theta0; measured period over
    the small-amplitude period of the same physical pendulum, T0 = 2 pi sqrt(2L / 3g)."""
    import rfesim
    th = math.radians(theta0_deg)
    T0 = 2 * math.pi * math.sqrt(2 * L / (3 * G))
    sc = {"environment": {"gravity": G},
          "line_types": {"rod": {"EA": 1e9, "EIy": 1e7, "GA": 1e9, "GJ": 1e7, "mass_per_length": 1.0,
                                 "rotary_inertia": 0.0}},
          "lines": {"rod": {"type": "rod", "length": L, "elements": n,
                            "end_a": {"attach": "fixed", "position": [0, 0, 0],
                                      "direction": [math.sin(th), 0, -math.cos(th)], "connection": "pinned"},
                            "end_b": {"attach": "free"}}},
          "analysis": {"statics": {"enabled": False},
                       "dynamics": {"duration": periods * T0 * PENDULUM[theta0_deg], "output_interval": T0 / 400,
                                    "integrator": integrator(T0)}}}
    res = rfesim.simulate(sc)
    x = res.line("rod").position[:, -1, 0]
    t = res.time
    idx = np.flatnonzero(np.sign(x[:-1]) != np.sign(x[1:]))
    crossings = [t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i]) for i in idx]
    return (crossings[2] - crossings[0]) / T0


# --------------------------------------------------------------------------- lines
def catenary_line(n, weight, seabed=True, EA=7.51e12, friction=0.0):
    """P1: span 400 m, height 200 m, length 500 m, EI -> 0; with axial seabed friction
    fully mobilised in statics when ``friction`` > 0."""
    env = {"gravity": G}
    if seabed:
        env["seabed"] = {"z": 0.0, "normal_stiffness": 1e9, "damping_ratio": 0.0, "friction_axial": friction}
    return {
        "name": "P1 catenary",
        "environment": env,
        "line_types": {"chain": {"EA": EA, "EIy": 1.0, "GJ": 1.0, "GA": EA / 3, "mass_per_length": weight / G}},
        "lines": {"line": {"type": "chain", "length": 500.0, "elements": n, "shear_stiffness": "kruszewski",
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "connection": "pinned"},
                           "end_b": {"attach": "fixed", "position": [400, 0, 200], "connection": "pinned"}}},
        "analysis": {"dynamics": {"enabled": False},
                     "statics": {"seabed_friction": "mobilised" if friction > 0 else "none"}},
    }
