"""Dynamics against closed forms: the inertial effects of a moving base, the three
integrators against each other, point loads along a line."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

G = 9.81


def hanging_rod(motion, integrator, duration=12.0, elements=4, length=2.0, mass=10.0):
    """A very stiff rod clamped vertically under a vessel, in air."""
    return {
        "environment": {"gravity": G},
        "vessels": {"ship": {"position": [0.0, 0.0, 5.0], "motion": motion}},
        # stiff enough to move rigidly: axial and bending frequencies > 100 rad/s >> 2 rad/s
        "line_types": {"rod": {"EA": 1e7, "EIy": 1e6, "GA": 1e7, "GJ": 1e6, "mass_per_length": mass}},
        "lines": {"rod": {"type": "rod", "length": length, "elements": elements,
                          "end_a": {"attach": "ship", "position": [0, 0, 0], "direction": [0, 0, -1],
                                    "connection": "clamped"},
                          "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": duration, "output_interval": 0.02, "integrator": integrator}},
    }


@pytest.mark.parametrize("integrator", [
    {"kind": "generalized-alpha", "time_step": 0.002, "rho_inf": 0.8},
    {"kind": "rk4"},
])
def test_heaving_vessel_top_force_is_m_g_plus_a(integrator):
    """A rigid rod clamped to a heaving vessel: the force at the top is m (g + a_z(t))."""
    amplitude, period = 0.5, 3.0
    motion = {"kind": "harmonic", "heave": {"amplitude": amplitude, "period": period}, "ramp_duration": 3.0}
    duration = 9.0 if integrator["kind"] == "rk4" else 12.0
    res = rfesim.simulate(hanging_rod(motion, integrator, duration=duration))
    t = res.time
    w = 2 * math.pi / period
    # the ramped heave z = r(t) A sin(wt): its acceleration after the ramp is -A w^2 sin(wt)
    after = t >= 4.0
    a_z = -amplitude * w * w * np.sin(w * t[after])
    m = 10.0 * 2.0
    top = -res.line("rod").end_a_force[after, 2]          # force of the rod on the vessel, downwards
    assert top == pytest.approx(m * (G + a_z), rel=2e-3, abs=2e-3 * m * G)


def test_pitching_vessel_inertial_forces():
    """A rigid rod clamped under a pitching vessel (pitch about the vessel origin): the
    horizontal force at the top is the mass times the acceleration of the rod's centre,
    -m (alpha x r_c + w x (w x r_c)) plus gravity, with r_c the centre below the origin."""
    amplitude_deg, period = 5.0, 4.0
    motion = {"kind": "harmonic", "pitch": {"amplitude": amplitude_deg, "period": period}, "ramp_duration": 4.0}
    res = rfesim.simulate(hanging_rod(motion, {"kind": "generalized-alpha", "time_step": 0.002, "rho_inf": 0.8},
                                      duration=14.0))
    t = res.time
    after = t >= 6.0
    w = 2 * math.pi / period
    A = math.radians(amplitude_deg)
    theta = A * np.sin(w * t[after])
    thetad = A * w * np.cos(w * t[after])
    thetadd = -A * w * w * np.sin(w * t[after])
    m, L = 20.0, 2.0
    # centre of the rod at distance L/2 below the pitch axis, along the rotated -z axis
    d = L / 2
    # position of the centre: (-d sin(theta), 0, -d cos(theta)) relative to the origin (pitch about y)
    ax = -d * (thetadd * np.cos(theta) - thetad ** 2 * np.sin(theta))
    az = d * (thetadd * np.sin(theta) + thetad ** 2 * np.cos(theta))
    force = -res.line("rod").end_a_force[after]            # force of the vessel on the rod
    assert force[:, 0] == pytest.approx(m * ax, abs=2e-3 * m * G)
    assert force[:, 2] == pytest.approx(m * (G + az), abs=2e-3 * m * G)


def test_integrators_agree_on_a_swinging_line():
    """A soft hanging chain released from an inclined straight shape: RK4, adaptive
    Dormand-Prince and generalized-alpha (rho_inf = 1) give the same motion."""
    def run(integrator):
        sc = {"environment": {"gravity": G},
              "line_types": {"c": {"EA": 2e4, "EIy": 5.0, "GA": 2e4, "GJ": 5.0, "mass_per_length": 1.0}},
              "lines": {"c": {"type": "c", "length": 2.0, "elements": 6,
                              "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0.6, 0, -0.8],
                                        "connection": "pinned"},
                              "end_b": {"attach": "free"}}},
              "analysis": {"statics": {"enabled": False},
                           "dynamics": {"duration": 2.0, "output_interval": 0.05, "integrator": integrator}}}
        return rfesim.simulate(sc).line("c").position[:, -1]
    rk4 = run({"kind": "rk4"})
    dp = run({"kind": "adaptive", "rtol": 1e-9, "atol": 1e-11})
    ga = run({"kind": "generalized-alpha", "time_step": 2e-4, "rho_inf": 1.0, "tolerance": 1e-10})
    scale = np.abs(rk4).max()
    assert np.abs(dp - rk4).max() < 1e-4 * scale     # RK4 at its default (stability-limited) step
    assert np.abs(ga - rk4).max() < 1e-3 * scale


def test_point_force_at_a_distance_along_the_line():
    """A transverse force P at arc length a (mid-span, at the centre of an RFE) on a
    cantilever in the linear range: tip deflection P a^2 (3L - a) / (6 EI)."""
    L, EI, n = 10.0, 1e6, 20
    a = 5.0
    P = 1e-3 * EI / L ** 2

    def deflection(force):
        sc = {"environment": {"gravity": 0.0},
              "line_types": {"b": {"EA": 1e12, "EIy": EI, "mass_per_length": 1.0}},
              "lines": {"b": {"type": "b", "length": L, "elements": n,
                              "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                        "connection": "clamped"},
                              "end_b": {"attach": "free"},
                              "loads": [{"at": a, "force": [0, 0, -force]}]}},
              "analysis": {"statics": {"tolerance": 1e-12}}}
        return -rfesim.statics(sc).line("b").position[0, -1, 2] / force

    w = (4 * deflection(P) - deflection(2 * P)) / 3         # remove the O(P^3) nonlinearity
    exact = a ** 2 * (3 * L - a) / (6 * EI)
    # the RFE model is exact for a load at an SDE and O(1/n^2) in between
    assert w == pytest.approx(exact, rel=1.0 / n ** 2)
