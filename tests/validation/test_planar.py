"""Validation of the planar RFE formulation (chapter section 8.3) against VALIDATION.md
(R1, B1, B2, B4, B5, B9) and closed forms: the catenary between two pins (end-B
reactions, eq. 8.67), energy conservation of a free vibration, and geometric stiffening of a
beam on a base spun up with a prescribed angle (eq. 8.69)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rfesim.formulations.planar import (BaseMotion, kinetic_energy, joint_positions, planar_beam, planar_dynamics,
                                        planar_modes, planar_statics, potential_energy, smooth_spin_up,
                                        tip_position)

EI, MU, L = 1.0, 1.0, 1.0


# ---------------------------------------------------------------- R1 linear cantilever

@pytest.mark.parametrize("n", [1, 5, 20])
def test_r1_linear_cantilever_exact_for_any_n(n):
    P = 1e-7 * EI / L ** 2        # small: nonlinear corrections ~ (PL^2/EI)^2 = 1e-14
    st = planar_statics(planar_beam(L, EI, MU, n, tip_force=(0.0, -P)))
    tip = tip_position(planar_beam(L, EI, MU, n), st.q)
    assert -st.q[-1] == pytest.approx(P * L ** 2 / (2 * EI), rel=1e-8)
    assert -tip[1] == pytest.approx(P * L ** 3 / (3 * EI) * (1 - 1 / (4 * n * n)), rel=1e-8)
    M = 1e-7 * EI / L
    st = planar_statics(planar_beam(L, EI, MU, n, tip_moment=M))
    assert st.q[-1] == pytest.approx(M * L / EI, rel=1e-8)
    assert tip_position(planar_beam(L, EI, MU, n), st.q)[1] == pytest.approx(M * L ** 2 / (2 * EI), rel=1e-8)
    # base reaction (eq. 8.70): the clamp carries the tip moment
    assert st.base_reaction[2] == pytest.approx(-M, rel=1e-8)


# ---------------------------------------------------------------- B1 large deflection (Mattiasson)

B1 = {1.0: (0.30172, 0.05643, 0.46135), 10.0: (0.81061, 0.55500, 1.43029)}


def _b1(alpha, n):
    model = planar_beam(L, EI, MU, n, tip_force=(0.0, -alpha * EI / L ** 2))
    st = planar_statics(model)
    tip = tip_position(model, st.q)
    return np.array([-tip[1] / L, 1.0 - tip[0] / L, -st.q[-1]])


@pytest.mark.parametrize("alpha", [1.0, 10.0])
def test_b1_mattiasson_at_20_elements(alpha):
    got = _b1(alpha, 20)
    assert np.all(np.abs(got / np.array(B1[alpha]) - 1.0) < 3e-3)


def test_b1_error_falls_as_one_over_n_squared():
    """Observed order from n = 10, 20, 40 (deflection and rotation; the 5-digit shortening
    reference is too coarse for the n = 40 error). Errors against the n = 160 solution."""
    fine = _b1(10.0, 160)
    e = np.array([np.abs(_b1(10.0, n) - fine)[[0, 2]] for n in (10, 20, 40)])
    order = np.log2(e[:-1] / e[1:])
    assert np.all((order > 1.9) & (order < 2.1)), order
    # and the Richardson extrapolation of n = 80, 160 agrees with Mattiasson to his 5 digits
    extrapolated = fine + (fine - _b1(10.0, 80)) / 3.0
    assert np.all(np.abs(extrapolated - np.array(B1[10.0])) <= 6e-6)


# ---------------------------------------------------------------- B2 pure end moment

def _b2_tip_error(turns, n):
    M = 2 * math.pi * turns * EI / L
    model = planar_beam(L, EI, MU, n, tip_moment=M)
    st = planar_statics(model)
    theta = M * L / EI
    assert st.q[-1] == pytest.approx(theta, abs=1e-8)            # tip rotation exact
    radius = EI / M
    exact = np.array([radius * math.sin(theta), radius * (1 - math.cos(theta))])
    return np.linalg.norm(tip_position(model, st.q) - exact)


def test_b2_pure_moment_closes_into_a_full_circle():
    assert _b2_tip_error(1.0, 20) < 1e-3 * L
    assert _b2_tip_error(0.25, 20) < 1e-3 * L


def test_b2_half_circle_tip_converges_as_one_over_n_squared():
    errors = [_b2_tip_error(0.5, n) for n in (10, 20, 40)]
    order = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(np.abs(order - 2.0) < 0.05), order


# ---------------------------------------------------------------- B4 cantilever frequencies

B4_BETA = np.array([1.875104, 4.694091, 7.854757, 10.995541])
B4_RATIO = {10: np.array([1.00230, 1.00802, 1.01303, 1.01760]), 20: np.array([1.00057, 1.00199, 1.00327, 1.00454])}


@pytest.mark.parametrize("n", [10, 20])
def test_b4_cantilever_frequencies(n):
    model = planar_beam(L, EI, MU, n)
    f = planar_modes(model, model.q_initial, count=4).frequencies_hz
    exact = B4_BETA ** 2 * math.sqrt(EI / (MU * L ** 4)) / (2 * math.pi)
    assert np.allclose(f / exact, B4_RATIO[n], atol=6e-6)


# ---------------------------------------------------------------- B5 hanging chain

def test_b5_hanging_chain_frequencies():
    g = 9.81
    c = np.array([1.20241, 2.76004, 4.32686])
    errors = []
    for n in (10, 20):
        model = planar_beam(L, 0.0, MU, n, end_a="pinned", angle=-math.pi / 2, gravity=g)
        st = planar_statics(model)
        assert np.allclose(st.q[2:], -math.pi / 2, atol=1e-12)          # hangs straight down
        f = planar_modes(model, st.q, count=3).frequencies_hz * 2 * math.pi / math.sqrt(g / L)
        errors.append(np.abs(f / c - 1.0))
    assert errors[0][0] < 1e-3                       # mode 1 within 0.1 % at n = 10
    assert np.all(errors[1] < errors[0] / 3.0)       # every mode converges (~1/n^2)


# ---------------------------------------------------------------- B9 large-amplitude pendulum

@pytest.mark.parametrize("method", ["rk4", "generalized-alpha"])
def test_b9_pendulum_90_degrees(method):
    """One rigid RFE (n_k = 0) pinned at A_0, released horizontal: T/T0 = 1.180341."""
    g = 9.81
    model = planar_beam(L, 0.0, MU, 0, end_a="pinned", angle=0.0, gravity=g)
    T0 = 2 * math.pi * math.sqrt(2 * L / (3 * g))    # rod about its end: I/(m g L/2) = 2L/(3g)
    res = planar_dynamics(model, 0.7 * T0, T0 / 2000, method=method, rho_inf=1.0)
    rate = res.qd[:, 2]
    k = np.nonzero((rate[1:] >= 0) & (rate[:-1] < 0) & (np.arange(1, rate.size) > 5))[0][0]
    t_half = res.t[k] + (res.t[k + 1] - res.t[k]) * (-rate[k]) / (rate[k + 1] - rate[k])
    assert 2 * t_half / T0 == pytest.approx(1.180341, abs=2e-6)


# ---------------------------------------------------------------- catenary between two pins (end B)

@pytest.mark.parametrize("n", [10, 20])
def test_chain_between_two_pins_is_a_catenary(n):
    half_span, half_length, g = 0.8, 1.0, 9.81
    c = brentq(lambda c: c * math.sinh(half_span / c) - half_length, 0.05, 100.0)
    sag = c * (math.cosh(half_span / c) - 1.0)
    model = planar_beam(2 * half_length, 0.0, MU, n, end_a="pinned", end_b="pinned", gravity=g)
    model = dataclasses.replace(model, end_b_position=np.array([2 * half_span, 0.0]))
    mid = np.concatenate([[0.0], np.cumsum(np.r_[0.5, np.ones(n - 1)] * 2 * half_length / n)])
    start = model.q_initial.copy()
    start[2:] = -0.8 * np.cos(np.pi * mid / (2 * half_length))
    st = planar_statics(model, q_start=start)
    assert np.linalg.norm(tip_position(model, st.q) - model.end_b_position) < 1e-12
    assert st.end_reaction[1] == pytest.approx(MU * g * half_length, rel=1e-10)    # half the weight
    assert st.base_reaction[0] == pytest.approx(-st.end_reaction[0], rel=1e-10)
    # horizontal tension and sag converge to the catenary as 1/n^2
    # (measured: H -0.29 %, sag -0.87 % at n = 10; -0.069 %, -0.22 % at n = 20)
    assert st.end_reaction[0] == pytest.approx(MU * g * c, rel=0.32 / n ** 2)
    assert -joint_positions(model, st.q)[:, 1].min() == pytest.approx(sag, rel=0.95 / n ** 2)


# ---------------------------------------------------------------- energy of a free vibration

def test_energy_conserved_in_undamped_free_vibration():
    loaded = planar_beam(L, EI, MU, 20, tip_force=(0.0, -5.0))
    start = planar_statics(loaded).q
    model = planar_beam(L, EI, MU, 20)
    e0 = potential_energy(model, start)
    drift = []
    for h in (2e-4, 1e-4):
        res = planar_dynamics(model, 1.0, h, q0=start, method="rk4", record_every=int(round(0.01 / h)))
        energy = np.array([kinetic_energy(model, q, v) + potential_energy(model, q) for q, v in zip(res.q, res.qd)])
        assert np.max(np.abs(res.q[:, -1] - start[-1])) > 0.5    # it really swings (tip rotation 0.9 rad)
        drift.append(np.max(np.abs(energy / e0 - 1.0)))
    # measured 8.9e-6 and 1.8e-6: RK4's dissipation of the stiffest modes (h omega_max ~ 0.3-0.6)
    assert drift[1] < 2.5e-6
    assert drift[0] / drift[1] > 4.0


# ---------------------------------------------------------------- geometric stiffening under spin-up

def test_spin_up_tip_stays_bounded_geometric_stiffening():
    """Kane, Ryan & Banerjee (1987) beam: L = 10 m, EI = 14 kN m^2, 1.2 kg/m, base spun up to
    6 rad/s in 15 s. 6 rad/s exceeds the first bending frequency 3.8 rad/s, so a model without
    geometric stiffening diverges; the planar formulation stays bounded and settles."""
    length = 10.0
    model = planar_beam(length, 14000.0, 1.2, 10, base_motion=BaseMotion(phi=smooth_spin_up(6.0, 15.0)))
    omega1 = 1.875104 ** 2 * math.sqrt(14000.0 / (1.2 * length ** 4))
    assert omega1 < 6.0
    deflection = {}
    for method, h in (("generalized-alpha", 0.005), ("rk4", 0.001)):
        res = planar_dynamics(model, 20.0, h, method=method, record_every=int(round(0.05 / h)))
        tip = res.tip(model)
        base = res.q[:, 2]
        assert base[-1] == pytest.approx(smooth_spin_up(6.0, 15.0)(20.0)[0], abs=1e-9)
        deflection[method] = -np.sin(base) * tip[:, 0] + np.cos(base) * tip[:, 1]   # in the rotating frame
        after = deflection[method][res.t >= 15.0]
        assert np.max(np.abs(deflection[method])) < 0.06 * length
        assert np.max(np.abs(after)) < 5e-4 * length
    diff = np.max(np.abs(deflection["rk4"] - deflection["generalized-alpha"]))
    assert diff < 0.01 * np.max(np.abs(deflection["rk4"]))
