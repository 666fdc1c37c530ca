"""Starting generalised-alpha in the mixed chain + line integrator
(rfesim.formulations.mixed.filter_start) and the planar one of section 8.3
(rfesim.formulations.planar.start_acceleration), as for a scene of lines
(tests/validation/test_generalized_alpha_start.py; docs/theory.md, 'Starting
generalised-alpha').

Both started the algorithmic acceleration at the true one, a_0 = qdd_0. That keeps the
method second order, but in a mode the step does not resolve (omega h >> 1) it starts the
method's overshoot: from a start offset x_0 the mode gets a velocity of about
0.02 (omega h) omega x_0, beyond the omega x_0 the exact motion ever reaches, and an
undamped model gains energy. The start is now a_0 = (M + cq K + cv C)^-1 M qdd_0: qdd_0 to
O(h^2) in the resolved modes, about 0 in the stiff ones.

(a) mixed, statics off: a rigid arm on a stiff revolute spring (k = 1e9 N m/rad) carrying
    a stiff hanging rope (EA = 1e9 N) starts straight, out of equilibrium in both stiff
    modes; at 50 ms steps (omega h ~ 400) the undamped model must not gain energy, which the
    old start did;
(b) planar: a cantilever in its static equilibrium under a tip load, its last joint turned
    1e-6 rad (a local mode at omega h ~ 100): no energy gained, joint rates below the
    exact motion's bound;
(c) in the resolved modes a_0 - qdd_0 = O(h^2) (order 2), in both integrators;
(d) a start from statics keeps qdd_0 bit for bit (round-off there), so the runs from statics
    are what they were.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.formulations import mixed as M
from rfesim.formulations import planar as P
from rfesim.scenario import Scenario

G = 9.81


def arm_scene(h, k=1e9, EA=1e9, rho=0.8, duration=0.5, statics=False):
    """A rigid arm (L 2 m, 10 kg) on a revolute joint with a rotational spring k, carrying
    a 5 m rope (2 kg/m) hanging from its tip; statics off, so it starts straight along the
    arm's initial direction and unstretched."""
    return {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": EA, "EIy": 1e-2, "GA": EA, "mass_per_length": 2.0}},
            "chains": {"c": {"links": {"arm": {"rigid": True, "length": 2.0, "mass": 10.0}},
                             "joints": {"j": {"kind": "revolute", "parent": "base", "child": "arm",
                                              "axis": [0, 1, 0], "stiffness": k}}}},
            "lines": {"rope": {"type": "rope", "length": 5.0, "elements": 10, "end_a": {"attach": "c.arm"},
                               "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": statics},
                         "dynamics": {"duration": duration, "output_interval": h,
                                      "integrator": {"kind": "generalized-alpha", "time_step": h,
                                                     "rho_inf": rho}}}}


def mixed_start(d, filtered=True):
    """The mixed scene set up as rfesim.formulations.mixed.simulate sets it up: (ms, st, c,
    integrator, h, force_ref), the start filtered or not (the old start: a_0 = qdd_0)."""
    sc = Scenario.model_validate(d)
    integ = sc.analysis.dynamics.integrator
    ms = M.MixedScene(sc)
    st, c = M.initial_state(ms, sc)
    M.start_dynamics(ms, st, c)
    h = float(integ.time_step)
    force_ref = ms.system.force_scale(st)
    ig = M.make_integrator(ms, st, integ.rho_inf, integ.tolerance, integ.max_iterations, integ.jacobian_reuse)
    if filtered:
        M.filter_start(ms, st, c, ig, h, force_ref)
    return ms, st, c, ig, h, force_ref


def mixed_energy_gain(filtered):
    ms, st, c, ig, h, force_ref = mixed_start(arm_scene(0.05), filtered)
    e0 = M.mixed_energy(ms, st, c["x"], c["v"])["total"]
    gain, rate = -np.inf, 0.0
    for _ in range(10):
        ig.advance(st, c, h, force_ref)
        gain = max(gain, M.mixed_energy(ms, st, c["x"], c["v"])["total"] - e0)
        rate = max(rate, abs(float(c["v"][0])))
    return gain, rate


def test_mixed_start_out_of_equilibrium_gains_no_energy():
    gain, rate = mixed_energy_gain(True)
    # the joint's exact motion about its equilibrium theta_s (k theta_s = (m g L / 2 + W L),
    # W the rope's weight) has rates up to omega theta_s, omega^2 = k / (the arm and rope's
    # inertia about the joint, at least m L^2 / 3)
    theta_s = (10.0 * G * 1.0 + 2.0 * 5.0 * G * 2.0) / 1e9
    omega_max = math.sqrt(1e9 / (10.0 * 4.0 / 3.0))
    assert gain <= 1e-9, gain                      # (1e-9 J: round-off of the energy sums)
    assert rate < omega_max * theta_s, (rate, omega_max * theta_s)
    # the old start, a_0 = qdd_0: the method's overshoot, energy gained from a start at rest
    old_gain, old_rate = mixed_energy_gain(False)
    assert old_gain > 1e-4, old_gain
    assert old_rate > omega_max * theta_s, (old_rate, omega_max * theta_s)


def test_mixed_simulate_starts_filtered():
    d = arm_scene(0.05, duration=0.2)
    res = rfesim.simulate(d)
    assert res.status == 0, res.message
    ms, st, c, ig, h, force_ref = mixed_start(d, True)
    for _ in range(4):
        ig.advance(st, c, h, force_ref)
    assert float(res.joint("c.j").coordinate[-1, 0]) == pytest.approx(float(c["x"][0]), rel=1e-12, abs=1e-15)


def test_mixed_filtered_start_is_the_true_acceleration_to_order_h2():
    """A soft joint (k = 5e3 N m/rad) and rope (EA = 1e7 N): every mode resolved at these
    steps, so a_0 -> qdd_0 as (cq omega^2), i.e. h^2."""
    errors = []
    for h in (1e-4, 5e-5, 2.5e-5):
        ms, st, c, ig, h, force_ref = mixed_start(arm_scene(h, k=5e3, EA=1e7), False)
        a, qdd = c["a"].copy(), st.qdd.copy()
        assert M.filter_start(ms, st, c, ig, h, force_ref)
        errors.append((abs(c["aux"][0] / a[0] - 1.0), np.abs(st.aux - qdd).max() / np.abs(qdd).max()))
    errors = np.array(errors)
    assert errors[0, 0] < 0.01 and errors[0, 1] < 0.05, errors
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(orders - 2.0) < 0.2), orders


def test_mixed_start_from_statics_keeps_qdd():
    ms, st, c, ig, h, force_ref = mixed_start(arm_scene(0.05, k=5e3, EA=1e7, statics=True), False)
    aux, caux = st.aux.copy(), c["aux"].copy()
    assert st.static
    assert not M.filter_start(ms, st, c, ig, h, force_ref)
    assert np.array_equal(st.aux, aux) and np.array_equal(c["aux"], caux)


# ---------------------------------------------------------------------------- planar (8.3)
L, EI, MU, TIP = 10.0, 1e6, 50.0, 5e3


def planar_run(h, filtered, monkeypatch, n=20, rho=0.8, kick=1e-6):
    model = P.planar_beam(L, EI, MU, n, tip_force=(0.0, -TIP))
    st = P.planar_statics(model)
    q0 = st.q.copy()
    q0[-1] += kick
    with monkeypatch.context() as mp:
        if not filtered:
            mp.setattr(P, "start_acceleration", lambda model, w, q, qd, qdd, *a: qdd.copy())
        r = P.planar_dynamics(model, 1.0, h, q0=q0, method="generalized-alpha", rho_inf=rho, tolerance=1e-12)
    assert r.success, r.message
    energy = np.array([P.kinetic_energy(model, q, v) + P.potential_energy(model, q) for q, v in zip(r.q, r.qd)])
    return model, r, energy


def test_planar_start_off_equilibrium_in_a_stiff_mode(monkeypatch):
    model, r, energy = planar_run(0.05, True, monkeypatch)
    # the kicked end RFE (d/2 = 0.25 m, 12.5 kg) on its joint spring EI/d: omega ~ 2800 rad/s,
    # so the exact motion's joint rates stay below about omega * 1e-6 = 2.8e-3 rad/s
    d = L / 20
    m_end = MU * d / 2
    omega = math.sqrt((EI / d) / (m_end * (d / 2) ** 2 / 3))
    assert omega * 0.05 > 100
    bound = omega * 1e-6
    assert energy.max() - energy[0] <= 1e-12 * abs(energy[0]), energy.max() - energy[0]
    assert np.abs(r.qd).max() < 0.2 * bound, (np.abs(r.qd).max(), bound)
    # the old start: 6 times past the bound, energy gained
    model, r_old, energy_old = planar_run(0.05, False, monkeypatch)
    assert np.abs(r_old.qd).max() > 2 * bound, (np.abs(r_old.qd).max(), bound)
    assert energy_old.max() - energy_old[0] > 1e-6


def test_planar_filtered_start_is_the_true_acceleration_to_order_h2():
    """A cantilever of 4 elements released straight under gravity (every mode resolved at
    these steps): a_0 - qdd_0 = O(h^2)."""
    model = P.planar_beam(L, EI, MU, 4, gravity=G)
    w = P.PlanarWork(model)
    q = np.array(model.q_initial, float)
    qd = np.zeros_like(q)
    qdd, reac = P.accelerations(model, q, qd, 0.0, w)
    am, af, beta, gamma = P.genalpha_parameters(0.8)
    errors = []
    for h in (4e-4, 2e-4, 1e-4):
        cq = h * h * beta * (1 - af) / (1 - am)
        cv = h * gamma * (1 - af) / (1 - am)
        a0 = P.start_acceleration(model, w, q, qd, qdd, reac[-1], cq, cv, 1e-12)
        assert np.array_equal(a0[~model.free_mask()], qdd[~model.free_mask()])
        errors.append(np.abs(a0 - qdd).max() / np.abs(qdd).max())
    errors = np.array(errors)
    assert 0 < errors[0] < 0.05, errors
    orders = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(orders - 2.0) < 0.1), orders


def test_planar_start_from_statics_keeps_qdd():
    model = P.planar_beam(L, EI, MU, 20, tip_force=(0.0, -TIP), gravity=G)
    st = P.planar_statics(model)
    w = P.PlanarWork(model)
    qd = np.zeros_like(st.q)
    qdd, reac = P.accelerations(model, st.q, qd, 0.0, w)
    am, af, beta, gamma = P.genalpha_parameters(0.8)
    h = 0.05
    cq = h * h * beta * (1 - af) / (1 - am)
    cv = h * gamma * (1 - af) / (1 - am)
    a0 = P.start_acceleration(model, w, st.q, qd, qdd, reac[-1], cq, cv, 1e-9)
    assert np.array_equal(a0, qdd)
