"""Scenes mixing absolute-coordinate lines with chains (rfesim.formulations.mixed): one
Newton over both in statics, one generalised-alpha integrator in dynamics.

(a) a rigid arm on a revolute joint with a rotational spring carrying a hanging line:
    joint angle from k theta = (m g L / 2 + W L) cos theta, line top force = its weight W;
(b) a flexible cantilever as a chain link carrying a hanging line vs the same cantilever as
    an absolute line with the line's weight at its tip, and beam theory;
(c) an undamped rigid pendulum carrying a stiff rod (a clamped absolute line) with
    rho_inf = 1: total energy conserved, small-oscillation period of the compound pendulum;
(d) the time-step convergence order of the coupled integrator is 2.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import rfesim
from rfesim.formulations import mixed as M
from rfesim.scenario import Scenario

G = 9.81


def hanging_on_arm(k=5e3, L=2.0, m=10.0, mu=2.0, ell=5.0):
    return {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": 1e7, "EIy": 1e-2, "GA": 1e7, "mass_per_length": mu}},
            "chains": {"c": {"links": {"arm": {"rigid": True, "length": L, "mass": m}},
                             "joints": {"j": {"kind": "revolute", "parent": "base", "child": "arm",
                                              "axis": [0, 1, 0], "stiffness": k}}}},
            "lines": {"rope": {"type": "rope", "length": ell, "elements": 10, "end_a": {"attach": "c.arm"},
                               "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def test_statics_arm_with_spring_carrying_a_hanging_line():
    k, L, m, mu, ell = 5e3, 2.0, 10.0, 2.0, 5.0
    res = rfesim.statics(hanging_on_arm(k, L, m, mu, ell))
    W = mu * ell * G
    theta = brentq(lambda th: k * th - (m * G * L / 2 + W * L) * math.cos(th), 0.0, 1.5)
    assert res.joints["c.j"].coordinate[0, 0] == pytest.approx(theta, rel=1e-7)
    rope = res.line("rope")
    np.testing.assert_allclose(rope.end_a_force[0], [0.0, 0.0, -W], atol=1e-6 * W)
    # top SDE (half an element below the top) carries the weight below it
    assert rope.tension[0, 0] == pytest.approx(mu * G * (ell - ell / 20), rel=1e-6)
    # the line hangs from the arm tip
    np.testing.assert_allclose(rope.position[0, 0], [L * math.cos(theta), 0.0, -L * math.sin(theta)], atol=1e-9)
    # the chain's own outputs: the joint section of the arm carries the arm and the line
    arm = res.line("c.arm")
    assert arm.end_a_force[0, 2] == pytest.approx(-(m * G + W), rel=1e-7)


def cantilever_scene(as_chain, n=10, L=4.0, EI=2e5, mu_beam=5.0, mu=1.0, ell=3.0, formulation="modified"):
    beam = {"EA": 1e10, "EIy": EI, "EIz": EI, "GJ": EI, "GA": 1e10, "mass_per_length": mu_beam}
    sc = {"environment": {"gravity": G},
          "line_types": {"beam": beam, "rope": {"EA": 1e7, "EIy": 1e-2, "GA": 1e7, "mass_per_length": mu}},
          "analysis": {"statics": {"enabled": True, "tolerance": 1e-10}, "dynamics": {"enabled": False}}}
    if as_chain:
        sc["chains"] = {"c": {"links": {"beam": {"type": "beam", "length": L, "elements": n,
                                                 "formulation": formulation}},
                              "joints": {"root": {"kind": "fixed", "parent": "base", "child": "beam"}}}}
        sc["lines"] = {"rope": {"type": "rope", "length": ell, "elements": 6, "end_a": {"attach": "c.beam"},
                                "end_b": {"attach": "free"}}}
    else:
        sc["lines"] = {"beam": {"type": "beam", "length": L, "elements": n, "shear_stiffness": "fem",
                                "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                          "connection": "clamped"}, "end_b": {"attach": "free"},
                                "loads": [{"at": "end_b", "force": [0, 0, -mu * ell * G]}]}}
    return sc


@pytest.mark.parametrize("formulation", ["modified", "classical"])
def test_flexible_cantilever_as_chain_link_and_as_absolute_line(formulation):
    n, L, EI, mu_beam, mu, ell = 10, 4.0, 2e5, 5.0, 1.0, 3.0
    chain = rfesim.statics(cantilever_scene(True, n, L, EI, mu_beam, mu, ell, formulation))
    absolute = rfesim.statics(cantilever_scene(False, n, L, EI, mu_beam, mu, ell))
    P, w = mu * ell * G, mu_beam * G
    beam_theory = P * L ** 3 / (3 * EI) + w * L ** 4 / (8 * EI)
    tip_chain = -chain.line("c.beam").position[0, -1, 2]
    tip_abs = -absolute.line("beam").position[0, -1, 2]
    # the rope hangs from the chain link's tip and pulls it down by its weight
    np.testing.assert_allclose(chain.line("rope").position[0, 0], chain.line("c.beam").position[0, -1], atol=1e-9)
    assert chain.line("rope").end_a_force[0, 2] == pytest.approx(-P, rel=2e-5)
    # both discretisations within theirs (O(1/n^2), here < 1 %) of beam theory and of each other
    assert tip_chain == pytest.approx(beam_theory, rel=1e-2)
    assert tip_abs == pytest.approx(beam_theory, rel=1e-2)
    assert tip_chain == pytest.approx(tip_abs, rel=1e-2)
    if formulation == "classical":      # the same SDEs as the absolute line (eq. 8.89): the same deflection
        assert tip_chain == pytest.approx(tip_abs, rel=1e-6)


# ----------------------------------------------------------------------------- dynamics
L_ARM, M_ARM, MU_ROD, L_ROD = 1.0, 5.0, 2.0, 0.5


def pendulum_scene(h, rho):
    return {"environment": {"gravity": G},
            "line_types": {"rod": {"EA": 1e6, "EIy": 1e3, "GA": 1e6, "mass_per_length": MU_ROD,
                                   "rotary_inertia": 0.0}},
            "chains": {"c": {"links": {"arm": {"rigid": True, "length": L_ARM, "mass": M_ARM}},
                             "joints": {"j": {"kind": "revolute", "parent": "base", "child": "arm",
                                              "axis": [0, 1, 0], "direction": [0, 0, -1]}}}},
            "lines": {"rod": {"type": "rod", "length": L_ROD, "elements": 2,
                              "end_a": {"attach": "c.arm", "connection": "clamped", "direction": [1, 0, 0]},
                              "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True, "tolerance": 1e-10},
                         "dynamics": {"enabled": True, "duration": 1.0,
                                      "integrator": {"kind": "generalized-alpha", "time_step": h, "rho_inf": rho,
                                                     "tolerance": 1e-10}}}}


def compound_pendulum():
    """(I about the pivot, m g d): the arm (slender rod) and the rod continuing it."""
    inertia = M_ARM * L_ARM ** 2 / 3 + MU_ROD * ((L_ARM + L_ROD) ** 3 - L_ARM ** 3) / 3
    moment = G * (M_ARM * L_ARM / 2 + MU_ROD * L_ROD * (L_ARM + L_ROD / 2))
    return inertia, moment


def swing(h, rho, t_end, omega0, every=1):
    """Start at the static equilibrium (hanging) with the joint rate omega0 and the rod
    moving with the arm as one rigid body; returns (t, theta, total energy) per output."""
    sc = Scenario.model_validate(pendulum_scene(h, rho))
    ms = M.MixedScene(sc)
    st, c = M.initial_state(ms, sc)
    c["v"][:] = omega0
    sysm = ms.system
    ms.set_points(0.0, ms.chain_full(0.0, c["x"], c["v"], np.zeros(ms.nc)))
    sysm.evaluate(st)
    w = np.array([0.0, omega0, 0.0])
    ws = sysm.ws
    for i in range(sysm.n):
        if sysm.km.rfe_kind[i] == 0:
            st.qd[i, :3] = np.cross(w, ws.r[i])
            st.qd[i, 3:] = np.linalg.solve(ws.E[i], ws.R[i].T @ w)
    M.start_dynamics(ms, st, c)
    ig = M.make_integrator(ms, st, rho, 1e-10)
    force_ref = sysm.force_scale(st)
    out = [(0.0, c["x"][0], M.mixed_energy(ms, st, c["x"], c["v"])["total"])]
    nsteps = round(t_end / h)
    for k in range(1, nsteps + 1):
        ig.advance(st, c, h, force_ref)
        if k % every == 0 or k == nsteps:
            out.append((st.t, c["x"][0], M.mixed_energy(ms, st, c["x"], c["v"])["total"]))
    return np.array(out).T, ig.stats


def test_pendulum_energy_and_period():
    inertia, moment = compound_pendulum()
    period = 2 * math.pi * math.sqrt(inertia / moment)
    amplitude = 0.2
    omega0 = amplitude * math.sqrt(moment / inertia)          # small-oscillation amplitude ~ 0.2 rad
    h = period / 100
    (t, theta, energy), stats = swing(h, 1.0, 6 * period, omega0)
    swing_energy = 0.5 * inertia * omega0 ** 2
    drift = (energy.max() - energy.min()) / swing_energy
    assert drift < 1e-3, drift
    s = np.sign(theta[1:])
    k = np.nonzero(s[1:] != s[:-1])[0] + 1
    tc = t[k] - theta[k] * (t[k + 1] - t[k]) / (theta[k + 1] - theta[k])
    measured = 2 * np.mean(np.diff(tc))
    # finite amplitude (1 + theta0^2 / 16) and the trapezoidal rule's (1 + (w h)^2 / 12)
    expected = period * (1 + amplitude ** 2 / 16) * (1 + (2 * math.pi / 100) ** 2 / 12)
    assert measured == pytest.approx(expected, rel=1e-3)
    assert measured == pytest.approx(period, rel=5e-3)


def test_time_step_convergence_order():
    inertia, moment = compound_pendulum()
    omega0 = 0.3 * math.sqrt(moment / inertia)
    ends = [swing(h, 0.9, 1.0, omega0, every=10 ** 6)[0][1][-1] for h in (0.04, 0.02, 0.01)]
    e1, e2 = abs(ends[0] - ends[1]), abs(ends[1] - ends[2])
    order = math.log2(e1 / e2)
    assert 1.7 < order < 2.3, (ends, order)
