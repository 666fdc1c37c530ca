"""Generalised-alpha from a start out of equilibrium, against a readable reference and the
exact solution.

A bar clamped at end A, free at end B, starts straight and at rest with a constant axial
force P at end B (no statics): a step load. Along its axis the RFE line is exactly the
lumped chain of n springs EA/Delta and masses mu Delta (the last mu Delta / 2)
(tests/validation/test_bar_and_string_modes.py), a linear system M u'' + K u = F, so

* the readable reference below, generalised-alpha in the Arnold & Bruls (2007) form with
  the algorithmic acceleration started at a_0 = (M + c_q K)^-1 (F - K u_0) (the true start
  acceleration in the modes the step resolves, none in the stiff ones:
  rfesim.solvers.dynamics.start_acceleration), gives the tip displacement the solver must
  reproduce step by step (to its Newton tolerance);
* the exact solution, u = u_s - sum_k phi_k c_k cos(omega_k t) (u_s the static deflection),
  is approached as h^2: with a_0 = 0 (as the solver had it) the order fell to about 1.2
  for rho_inf < 1 (docs/theory.md, 'Starting generalised-alpha').
"""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.solvers.kernels import genalpha_parameters

L, MU, P = 10.0, 10.0, 1e5     # bending and shear as stiff as EA: not excited by the axial load


def bar(n, EA, h, rho_inf, duration):
    return {"environment": {"gravity": 0.0},
            "line_types": {"bar": {"EA": EA, "EIy": EA, "EIz": EA, "GA": EA, "GJ": 5e7,
                                   "mass_per_length": MU, "rotary_inertia": 1.0}},
            "lines": {"bar": {"type": "bar", "length": L, "elements": n,
                              "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                        "connection": "clamped"},
                              "end_b": {"attach": "free"}, "loads": [{"at": "end_b", "force": [P, 0, 0]}]}},
            "analysis": {"statics": {"enabled": False},
                         "dynamics": {"duration": duration, "output_interval": h,
                                      "integrator": {"kind": "generalized-alpha", "time_step": h,
                                                     "rho_inf": rho_inf, "tolerance": 1e-12}}}}


def tip_displacement(n, EA, h, rho_inf, duration):
    res = rfesim.simulate(bar(n, EA, h, rho_inf, duration))
    return res.time, res.line("bar").position[:, -1, 0] - L


def chain(n, EA):
    """Lumped masses and stiffness matrix of the axial chain (RFEs 1..n; RFE 0 is clamped)."""
    dx = L / n
    m = np.full(n, MU * dx)
    m[-1] *= 0.5
    K = np.zeros((n, n))
    for s in range(n):                  # SDE s joins RFE s (the clamp for s = 0) and RFE s + 1
        K[s, s] += EA / dx
        if s > 0:
            K[s - 1, s - 1] += EA / dx
            K[s - 1, s] -= EA / dx
            K[s, s - 1] -= EA / dx
    F = np.zeros(n)
    F[-1] = P
    return m, K, F


def reference_generalized_alpha(n, EA, h, rho_inf, nsteps):
    """Arnold & Bruls: equilibrium M acc_{n+1} + K u_{n+1} = F at t_{n+1}; algorithmic
    acceleration (1 - am) a_{n+1} + am a_n = (1 - af) acc_{n+1} + af acc_n;
    u_{n+1} = u_n + h v_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}),
    v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1});
    a_0 = (M + c_q K)^-1 M acc_0, c_q = h^2 beta (1 - af) / (1 - am)."""
    am, af, beta, gamma = genalpha_parameters(rho_inf)
    m, K, F = chain(n, EA)
    u, v = np.zeros(n), np.zeros(n)
    acc = (F - K @ u) / m
    c = h * h * beta * (1.0 - af) / (1.0 - am)
    a = np.linalg.solve(np.diag(m) + c * K, m * acc)
    out = [u[-1]]
    for _ in range(nsteps):
        # a_{n+1} = ab + (1 - af) / (1 - am) acc_{n+1}, ab the part known at t_n
        ab = (af * acc - am * a) / (1.0 - am)
        u_known = u + h * v + h * h * (0.5 - beta) * a + h * h * beta * ab
        acc_new = np.linalg.solve(np.diag(m) + c * K, F - K @ u_known)
        a_new = ab + (1.0 - af) / (1.0 - am) * acc_new
        u = u_known + c * acc_new
        v = v + h * ((1.0 - gamma) * a + gamma * a_new)
        a, acc = a_new, acc_new
        out.append(u[-1])
    return np.array(out)


def exact_tip(n, EA, t):
    """Modal superposition of the chain from rest: u = u_s - sum phi_k c_k cos(omega_k t)."""
    m, K, F = chain(n, EA)
    us = np.linalg.solve(K, F)
    Mh = np.diag(1.0 / np.sqrt(m))
    w2, Y = np.linalg.eigh(Mh @ K @ Mh)
    phi = Mh @ Y                           # M-orthonormal modes
    coef = phi.T @ (m * us)                # modal coordinates of u_s
    return us[-1] - np.cos(np.outer(t, np.sqrt(w2))) @ (phi[-1] * coef)


@pytest.mark.parametrize("rho_inf", [1.0, 0.8, 0.5, 0.0])
def test_step_load_follows_the_reference_step_by_step(rho_inf):
    """10 elements, c = 1e4 m/s, h = 1 ms: omega_max h = 20, so the highest modes are
    dissipated as rho_inf says; every step's tip displacement equals the reference's."""
    t, tip = tip_displacement(10, 1e9, 1e-3, rho_inf, 0.04)
    ref = reference_generalized_alpha(10, 1e9, 1e-3, rho_inf, len(t) - 1)
    scale = P * L / 1e9
    assert np.abs(tip - ref).max() < 1e-7 * scale
    # the first step alone: a_0 = 0 left it 7 % short at rho_inf 0.8, 11 % at 0.5
    assert tip[1] == pytest.approx(ref[1], rel=1e-7)


@pytest.mark.parametrize("rho_inf, h0", [(0.8, 4e-4), (0.0, 2e-4)])
def test_step_load_converges_as_h_squared(rho_inf, h0):
    """5 elements, c = 1000 m/s (omega_max 984 rad/s), 0.05 s: the error of the tip
    displacement against the exact solution falls as h^2 over three halvings of h from h0
    (rho_inf 0 damps the highest mode hard: its asymptotic range starts at a shorter step)."""
    err = []
    for h in h0 / 2.0 ** np.arange(4):
        t, tip = tip_displacement(5, 1e7, h, rho_inf, 0.05)
        err.append(np.abs(tip - exact_tip(5, 1e7, t)).max() / (P * L / 1e7))
    err = np.array(err)
    orders = np.log2(err[:-1] / err[1:])
    assert np.all(np.abs(orders - 2.0) < 0.15), (err, orders)


def test_a_stiff_start_offset_makes_no_spurious_velocity():
    """The bar unloaded, its tip RFE moved 1 um along the axis, 50 ms steps (omega_max h =
    1000, rho_inf 0.8): the offset decays as the method damps the unresolved modes, the tip
    never moves beyond it nor faster than 1e-4 m/s. With a_0 equal to the true start
    acceleration (1.6e4 m/s^2 here) the method's overshoot put a velocity of about
    0.02 (omega h) omega x_0 into those modes: the energy check stopped the run at 0.2 s with
    the energy grown by 99.7 % of its scale."""
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import load_scenario
    from rfesim.solvers.dynamics import Counters, run_dynamics
    from rfesim.solvers.system import System
    doc = bar(10, 1e9, 0.05, 0.8, 1.0)
    doc["lines"]["bar"]["loads"] = []
    sc = load_scenario(doc)
    system = System(compile_scenario(sc))
    state = system.model.initial.copy()
    state.q[-1, 0] += 1e-6
    _, rec, _ = run_dynamics(system, state, sc.analysis.dynamics, counters=Counters())
    x = rec.results(status=0, message="", counters={}).line("bar").position[:, -1, 0] - L
    assert np.abs(x).max() <= 1e-6 * (1 + 1e-6)
    assert np.abs(np.diff(x)).max() / 0.05 < 1e-4


def test_a_run_in_two_parts_goes_on_with_its_own_algorithmic_acceleration():
    """The step-loaded bar (rho_inf 0.5, h = 1 ms) run for 20 ms and then on for 20 ms from the
    state the first part ended in, as the S-lay bench runs its 3 hours in parts: the second
    part keeps the first's algorithmic acceleration (it is started only once, on a fresh
    state) and ends where a 40 ms run ends, to the Newton tolerance."""
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import load_scenario
    from rfesim.solvers.dynamics import Counters, run_dynamics
    from rfesim.solvers.system import System

    def system_and_settings(duration):
        sc = load_scenario(bar(10, 1e9, 1e-3, 0.5, duration))
        return System(compile_scenario(sc)), sc.analysis.dynamics

    system, whole = system_and_settings(0.04)
    end_whole, _, _ = run_dynamics(system, system.model.initial, whole, counters=Counters())
    system, half = system_and_settings(0.02)
    middle, _, _ = run_dynamics(system, system.model.initial, half, counters=Counters())
    assert not middle.fresh and np.abs(middle.aux).max() > 0.0
    end, _, _ = run_dynamics(system, middle, half, counters=Counters())
    assert end.t == pytest.approx(0.04)
    scale = P * L / 1e9
    assert np.abs(end.positions() - end_whole.positions()).max() < 1e-7 * scale
    # velocities: 1e-10 m/s apart (the bar's speeds are up to P / sqrt(EA mu) = 1 m/s); with
    # the algorithmic acceleration started again at the middle, 0.011 m/s
    assert np.abs(end.qd[:, :3] - end_whole.qd[:, :3]).max() < 1e-6
