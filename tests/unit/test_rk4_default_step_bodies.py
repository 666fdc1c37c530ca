"""The default RK4 step of a scene with a body on a line end (rfesim.solvers.dynamics.stable_rk4_step).

The body connection (rfesim.model.bodies) is damped critically on the translational mass of
the line's end RFE, but it also acts on that RFE's rotation through the half-length arm,
where the RFE carries a quarter of its mass: that mode is damped twice critically and has a
real eigenvalue -(2 + sqrt 3) omega, 3.7 times the highest natural frequency. The step from
omega_max alone (9.6e-6 s on the rope below) then lay beyond the true limit (7.8e-6 s) and
every run diverged after about 60 steps; the limit now also honours the largest damping rate
(2.785 / the largest eigenvalue of M^-1 C, the negative real axis of RK4's region).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
import rfesim.solvers.dynamics as dynamics
from rfesim.api import _static_state
from rfesim.model.compile import compile_scenario
from rfesim.scenario import load_scenario
from rfesim.solvers.dynamics import highest_frequency, stable_rk4_step, _max_damping_ratio
from rfesim.solvers.system import System


def rope_scene(body=True, duration=0.01, mass=5000.0, time_step=None):
    """A 20 m rope (EA 5.9e7 N, 20 elements) hanging from a fixed point, a 5 t body on end B."""
    integrator = {"kind": "rk4"}
    if time_step:
        integrator["time_step"] = time_step
    d = {
        "environment": {"gravity": 9.81},
        "line_types": {"rope": {"EA": 5.9e7, "EIy": 1000.0, "mass_per_length": 5.2, "outer_diameter": 0.036,
                                "tension_only": True, "drag_normal": 1.2, "added_mass_normal": 1.0,
                                "damping": {"axial_ratio": 0.2, "bending_ratio": 0.2}}},
        "lines": {"rope": {"type": "rope", "length": 20.0, "elements": 20,
                           "end_a": {"attach": "fixed", "position": [0, 0, 30.0], "connection": "pinned"},
                           "end_b": {"attach": "payload", "position": [0, 0, 1.0]}}},
        "bodies": {"payload": {"mass": mass, "radius_of_gyration": [1.0, 1.0, 1.0], "volume": 2.0, "height": 2.0,
                               "drag": {"cd": [1.2, 1.2, 2.0], "area": [4, 4, 4]},
                               "position": [0, 0, 9.0]}},
        "analysis": {"statics": {"enabled": True},
                     "dynamics": {"duration": duration, "output_interval": 0.001, "integrator": integrator}},
    }
    if not body:
        d.pop("bodies")
        d["lines"]["rope"]["end_b"] = {"attach": "free"}
    return d


def static_system(d):
    sc = load_scenario(d)
    system = System(compile_scenario(sc))
    state, _ = _static_state(system, sc)
    return system, state


def first_order_eigenvalues(system, state):
    """Eigenvalues of the linearised first-order system [[0, I], [-M^-1 K, -M^-1 C]] about the
    state: central differences of the true accelerations in every moving coordinate and
    velocity, dense numpy (129 coordinates here)."""
    mask = system.mask
    idx = np.argwhere(mask)
    N = len(idx)
    A = np.zeros((2 * N, 2 * N))
    A[:N, N:] = np.eye(N)
    for c, (i, j) in enumerate(idx):
        for part, eps in ((0, 1e-7), (1, 1e-5)):      # (position m or rad, velocity m/s or rad/s)
            cols = []
            for sign in (1.0, -1.0):
                s = state.copy()
                (s.q if part == 0 else s.qd)[i, j] += sign * eps
                cols.append(system.accelerations(s)[mask])
            A[N:, part * N + c] = (cols[0] - cols[1]) / (2.0 * eps)
    K = -A[N:, :N]                                     # M^-1 K
    return np.linalg.eigvals(A), np.linalg.eigvals(K)


def rk4_limit(lam):
    """Longest step h with |R(h lambda)| <= 1 for all the given eigenvalues, R the RK4
    amplification 1 + z + z^2/2 + z^3/6 + z^4/24 (bisection)."""
    def stable(h):
        z = h * lam
        return np.all(np.abs(1 + z + z * z / 2 + z ** 3 / 6 + z ** 4 / 24) <= 1.0 + 1e-9)
    lo, hi = 0.0, 1e-3
    while stable(hi):
        hi *= 2.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


@pytest.fixture(scope="module")
def body_scene():
    system, state = static_system(rope_scene())
    lam, lam_k = first_order_eigenvalues(system, state)
    return system, state, lam, lam_k


def test_default_step_within_the_true_limit(body_scene):
    system, state, lam, lam_k = body_scene
    # only the fast modes set the limit: the slow ones (pendulum, round-off near 0) are left out
    fast = lam[np.abs(lam) > 0.01 * np.abs(lam).max()]
    assert fast.real.max() < 0.0
    true_limit = rk4_limit(fast)
    assert 7.0e-6 < true_limit < 8.5e-6                # measured 7.8e-6 s
    # the cause: the largest |lambda| is real, far beyond the highest natural frequency
    omega_max = math.sqrt(np.abs(lam_k).max())          # 9.5e4 rad/s
    top = lam[np.argmax(np.abs(lam))]                   # -3.56e5 1/s
    assert abs(top.imag) < 1e-6 * abs(top) and top.real < -3.0 * omega_max
    # the estimate honours it: the limit itself and the default (0.8 x) stay inside
    limit = stable_rk4_step(system, state, 1.0)
    default = stable_rk4_step(system, state, 0.8)
    assert limit < true_limit
    assert default == pytest.approx(0.8 * limit, rel=1e-12)
    assert default > 0.5 * true_limit                   # and not needlessly short (5.3e-6 s)
    # the omega_max bound alone (the default before) lay beyond the true limit
    zeta = _max_damping_ratio(system)
    old = 0.8 * 2.8 / (highest_frequency(system, state) * math.sqrt(1.0 + 4.0 * zeta * zeta))
    assert old > true_limit


@pytest.mark.parametrize("mass", [5000.0, 50.0])
def test_default_step_runs_with_a_body(mass):
    res = rfesim.simulate(rope_scene(mass=mass, duration=0.01))
    assert res.status == 0
    h = res.counters["time_step"]
    assert 4e-6 < h < 7.8e-6
    # the body hangs still on the rope: its connection carries its weight
    tension = res.bodies["payload"].connection_tension
    assert np.all(np.isfinite(tension))
    assert tension[-1] == pytest.approx(mass * 9.81, rel=0.02)


def test_default_step_without_body_unchanged():
    """No body: the damping rate does not bind, the step is 0.8 x 2.8 / (omega_max sqrt(1 + 4 zeta^2))
    as before (2.81e-4 s; the run then steps 2.5e-4 s to meet the output times)."""
    system, state = static_system(rope_scene(body=False))
    zeta = _max_damping_ratio(system)
    old = 0.8 * 2.8 / (highest_frequency(system, state) * math.sqrt(1.0 + 4.0 * zeta * zeta))
    assert stable_rk4_step(system, state, 0.8) == old
    assert old == pytest.approx(2.81e-4, rel=0.01)
    assert 2.785 / dynamics.highest_damping_rate(system, state) > old / 0.8
    res = rfesim.simulate(rope_scene(body=False, duration=0.01))
    assert res.status == 0 and res.counters["time_step"] == pytest.approx(2.5e-4)


def test_default_step_divergence_names_step_and_limit(monkeypatch):
    """Should a default step diverge all the same (here: the damping rate left out, the old
    estimate), the error names the step and the estimated limit as for an explicit step."""
    monkeypatch.setattr(dynamics, "highest_damping_rate", lambda system, state, iterations=60: 0.0)
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(rope_scene(duration=0.002))
    for msg in (info.value.results.message, str(info.value)):
        assert "velocity not finite or runaway" in msg
        assert "the default RK4 step 9.52e-06 s is within 0.8 x its estimated stability limit, about 1.19e-05 s" in msg
        assert "analysis.dynamics.integrator.time_step" in msg
