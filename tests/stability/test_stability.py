"""Numerical stability under stress: long undamped runs, large implicit steps, stiff short
elements, rotations through 360 degrees, and divergence caught as SolverError."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.model.compile import compile_scenario
from rfesim.model.energy import mechanical_energy
from rfesim.scenario import load_scenario
from rfesim.solvers.dynamics import run_dynamics, stable_rk4_step
from rfesim.solvers.statics import solve_statics
from rfesim.solvers.system import System


def beam_scenario(loads=(), n=8, L=1.0, EI=100.0, EA=1e5, mu=1.0, gravity=0.0, integrator=None, duration=0.0,
                  output_interval=None):
    sc = {
        "environment": {"gravity": gravity},
        "line_types": {"beam": {"EA": EA, "EIy": EI, "GA": EA, "mass_per_length": mu, "rotary_inertia": 0.0}},
        "lines": {"beam": {"type": "beam", "length": L, "elements": n,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}, "loads": list(loads)}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": duration, "output_interval": output_interval,
                                  "integrator": integrator or {"kind": "generalized-alpha"}}},
    }
    return load_scenario(sc)


LONG_RUN = dict(n=4, EA=1e4)      # highest / first frequency ~ 20: 1000 periods stay cheap for RK4


def released_beam(integrator, periods, output_interval=None, n=4, EA=1e4):
    """A clamped beam bent by a tip load, released at t = 0, undamped, no gravity."""
    loaded = beam_scenario([{"at": "end_b", "force": [0, 0, -5.0]}], n=n, EA=EA)
    state, _ = solve_statics(System(compile_scenario(loaded)))
    T1 = 2 * math.pi / (1.875104 ** 2 * math.sqrt(100.0 / 1.0))     # first period of the beam
    sc = beam_scenario(n=n, EA=EA, integrator=integrator, duration=periods * T1,
                       output_interval=output_interval or T1)
    system = System(compile_scenario(sc))
    e0 = mechanical_energy(system, state).total
    final, rec, counters = run_dynamics(system, state, sc.analysis.dynamics)
    return system, e0, final, rec, counters, T1


def test_energy_conserved_implicit_rho_inf_1_over_1000_periods():
    T1 = 2 * math.pi / (1.875104 ** 2 * 10.0)
    system, e0, final, rec, counters, T1 = released_beam(
        {"kind": "generalized-alpha", "time_step": T1 / 40, "rho_inf": 1.0}, periods=1000, output_interval=T1 / 16)
    e1 = mechanical_energy(system, final).total
    assert abs(e1 - e0) / e0 < 0.01
    # the tip still swings with the initial amplitude over the last period (no numerical
    # damping at rho_inf = 1)
    tip_z = rec.line_data["beam"]["position"][:rec.k, -1, 2]
    assert np.abs(tip_z[-16:]).max() > 0.9 * np.abs(tip_z[:16]).max()


def test_energy_conserved_rk4_below_stability_limit_over_1000_periods():
    loaded = beam_scenario(**LONG_RUN)
    h = stable_rk4_step(System(compile_scenario(loaded)), compile_scenario(loaded).initial, 0.8)
    system, e0, final, rec, counters, T1 = released_beam({"kind": "rk4", "time_step": h}, periods=1000)
    e1 = mechanical_energy(system, final).total
    assert abs(e1 - e0) / e0 < 0.01


def test_implicit_steps_100x_the_explicit_limit_stay_stable():
    loaded = beam_scenario()
    model = compile_scenario(loaded)
    h_explicit = stable_rk4_step(System(model), model.initial, 1.0)
    system, e0, final, rec, counters, T1 = released_beam(
        {"kind": "generalized-alpha", "time_step": 100 * h_explicit, "rho_inf": 0.8}, periods=50,
        output_interval=400 * h_explicit)
    assert counters["time_step"] >= 100 * h_explicit
    e1 = mechanical_energy(system, final).total
    assert np.isfinite(e1) and e1 <= e0 * 1.001          # numerical damping may only remove energy
    assert np.all(np.isfinite(rec.line_data["beam"]["position"][:rec.k]))


def test_stiff_short_element_steel_pipe_runs():
    """12-inch steel pipe, 0.1 m elements, hanging from a heaving vessel in water (the heave
    is ramped in: an impulsive start would launch an axial stress wave rho c v A ~ 6e5 N)."""
    sc = {
        "environment": {"gravity": 9.81, "water": {"density": 1025.0, "depth": 50.0}},
        "vessels": {"ship": {"motion": {"kind": "harmonic", "heave": {"amplitude": 1.0, "period": 6.0},
                                        "ramp_duration": 6.0}}},
        "line_types": {"pipe": {"outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 2.07e11,
                                "density": 7850.0, "drag_normal": 1.0, "added_mass_normal": 1.0}},
        "lines": {"pipe": {"type": "pipe", "length": 10.0, "elements": 100,
                           "end_a": {"attach": "ship", "position": [0, 0, -2.0], "direction": [0, 0, -1],
                                     "connection": "clamped"},
                           "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": 12.0, "output_interval": 0.05,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.01, "rho_inf": 0.8}}},
    }
    res = rfesim.simulate(sc)
    line = res.line("pipe")
    assert res.success
    assert np.all(np.isfinite(line.position)) and np.all(np.isfinite(line.tension))
    # the hang-off force follows the heave: weight in water +- mass * acceleration, bounded
    steel = math.pi / 4 * (0.3239 ** 2 - (0.3239 - 2 * 0.0159) ** 2)
    weight = 10.0 * 9.81 * (7850.0 * steel - 1025.0 * math.pi / 4 * 0.3239 ** 2)
    hang_off = -line.end_a_force[:, 2]
    assert hang_off[0] == pytest.approx(weight, rel=1e-3)           # static: the weight in water
    assert 0.0 < hang_off.min() and hang_off.max() < 3.0 * weight


def test_rod_rotating_through_360_degrees():
    """A stiff rod spinning about its pinned end in zero gravity turns through several full
    revolutions; its reference rotations are re-based, energy and angular momentum stay."""
    omega = 2.0 * math.pi        # one revolution per second
    L = 1.0
    sc = {
        "environment": {"gravity": 0.0},
        "line_types": {"rod": {"EA": 1e7, "EIy": 1e4, "GA": 1e7, "GJ": 1e4, "mass_per_length": 1.0,
                               "rotary_inertia": 0.0}},
        "lines": {"rod": {"type": "rod", "length": L, "elements": 4,
                          "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [1, 0, 0],
                                    "connection": "pinned"},
                          "end_b": {"attach": "free"}}},
        "analysis": {"statics": {"enabled": False},
                     "dynamics": {"duration": 3.0, "output_interval": 0.01,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.002, "rho_inf": 1.0}}},
    }
    model = compile_scenario(load_scenario(sc))
    system = System(model)
    state = model.initial.copy()
    # rigid rotation about the z axis through the pin: v = omega x r, angular rates about body z
    for i in range(model.n):
        r = state.ref.X[i] + state.q[i, :3]
        if model.km.rfe_kind[i] == 0:
            state.qd[i, :3] = np.cross([0, 0, omega], r)
        state.qd[i, 3] = omega            # psi rate = rotation about z at zero angles
    e0 = mechanical_energy(system, state).total
    final, rec, counters = run_dynamics(system, state, load_scenario(sc).analysis.dynamics)
    assert counters["rebases"] > 0
    tip = rec.line_data["rod"]["position"][:rec.k, -1, :2]
    angle = np.unwrap(np.arctan2(tip[:, 1], tip[:, 0]))
    assert angle[-1] - angle[0] == pytest.approx(3 * 2 * math.pi, rel=1e-3)
    assert mechanical_energy(system, final).total == pytest.approx(e0, rel=1e-3)


def test_vertical_line_is_an_ordinary_case():
    """A line hanging straight down (Euler angle theta = 90 deg in a global chart) swings
    like any other: compare the first period with the hanging-chain value."""
    L, g = 10.0, 9.81
    sc = {
        "environment": {"gravity": g},
        "line_types": {"c": {"EA": 1e8, "EIy": 1e-2, "GA": 1e8, "GJ": 1e-2, "mass_per_length": 1.0,
                             "rotary_inertia": 0.0}},
        "lines": {"c": {"type": "c", "length": L, "elements": 20, "shear_stiffness": "kruszewski",
                        "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, -1],
                                  "connection": "pinned"},
                        "end_b": {"attach": "free"}}},
    }
    md = rfesim.modes(sc, n=4)
    f = np.sort(md.frequencies_hz[md.frequencies_hz > 1e-6])[0]
    assert 2 * math.pi * f / math.sqrt(g / L) == pytest.approx(1.20241, rel=1e-3)


def test_divergence_is_a_solver_error_with_clean_partial_results():
    """RK4 far above its stability limit blows up: SolverError says when and where, the
    results computed before the failure are kept and contain no NaN."""
    model = compile_scenario(beam_scenario())
    h = stable_rk4_step(System(model), model.initial, 1.0)
    sc = beam_scenario([{"at": "end_b", "force": [0, 0, -5.0]}], integrator={"kind": "rk4", "time_step": 20 * h},
                       duration=2000 * h, output_interval=20 * h)
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(sc)
    exc = info.value
    assert exc.time is not None and 0 < exc.time < 2000 * h
    assert exc.element is not None and "line 'beam'" in exc.element
    assert "diverged" in str(exc)
    partial = exc.results
    assert partial is not None and partial.status == 1
    assert len(partial.time) >= 1 and partial.time[-1] < exc.time + 1e-12
    for name in ("position", "tension", "bend_moment"):
        assert np.all(np.isfinite(getattr(partial.line("beam"), name)))
