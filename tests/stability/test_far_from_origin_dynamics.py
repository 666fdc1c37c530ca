"""Dynamics of lines far from the origin (e.g. UTM coordinates): the round-off of absolute
positions in the generalised-alpha Newton iteration.

Within a step the RFE positions are ``ref.X + q``, ``ref.X`` fixed and ``q`` the displacement
since the last re-base: the SDE gaps difference the two parts apart (rfesim.loads.sde), so the
stiff SDE forces are continuous in q, unlike statics, which re-bases after every update
(rfesim.solvers.statics.position_resolution_force). Contact springs (tensioner pads, rollers,
seabed, reels, tuggers, deck) take the rounded sum r = ref.X + q and resolve forces only to
about k ulp(|r|): the J-lay template's collar (1e7 N/m/m pads on 1 m elements) 6.7e6 m from the
origin, 9.3e-3 N, 7.9 times the default tolerance (1e-6 x 1184 N). Newton stagnated there and
the run failed in its first step (0.1 s steps) or at 0.14 s (0.01 s). The Newton tolerance is
now floored at 4 times that resolution (rfesim.solvers.dynamics.newton_tolerance;
docs/theory.md, 'Resolution of absolute positions in dynamics')."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
import scenes
from rfesim.model.compile import compile_scenario
from rfesim.solvers.dynamics import contact_resolution_force, newton_tolerance
from rfesim.solvers.kernels import residual_q
from rfesim.solvers.statics import POSITION_FLOOR, position_resolution_force
from rfesim.solvers.system import System

FAR = 6.7e6          # m, a UTM northing: 2^22 <= x < 2^23, one ulp = 2^-30 m


def j_lay(x0: float, duration: float, time_step: float):
    """The bundled J-lay template (scenarios/j_lay.json as of this test) with 1 m elements,
    its vessel at (x0, 0, 0)."""
    return rfesim.load_scenario(scenes.j_lay_template(
        1.0, name="J-lay template, far from the origin",
        vessel={"position": [x0, 0.0, 0.0],
                "motion": {"kind": "harmonic", "heave": {"amplitude": 1.5, "period": 10.0},
                           "pitch": {"amplitude": 1.0, "period": 10.0, "phase_deg": 90.0},
                           "ramp_duration": 10.0}},
        analysis={"statics": {"enabled": True},
                  "dynamics": {"duration": duration, "output_interval": 0.1,
                               "integrator": {"kind": "generalized-alpha", "time_step": time_step}}}))


_RUNS = {}


def run(x0: float, duration: float, time_step: float):
    key = (x0, duration, time_step)
    if key not in _RUNS:
        _RUNS[key] = rfesim.simulate(j_lay(x0, duration, time_step))
    return _RUNS[key]


def test_contact_resolution_sets_the_newton_tolerance_far_from_the_origin():
    sc = j_lay(FAR, 1.0, 0.1)
    system = System(compile_scenario(sc))
    state = system.model.initial
    km = system.km
    # hand value: the collar's pad stiffness per length times the element length times one ulp
    # between 2^22 and 2^23 m
    pads = float(km.tens_kl.max()) * float(km.rfe_length.max())
    assert pads == pytest.approx(1.0e7, rel=1e-3)
    resolution = contact_resolution_force(system, state)
    assert resolution == pytest.approx(pads * 2.0 ** -30, rel=1e-12)                # 9.3e-3 N
    force_ref = system.force_scale(state)
    tol = newton_tolerance(system, state, 1e-6, force_ref)
    assert tol == pytest.approx(POSITION_FLOOR * pads * 2.0 ** -30 / force_ref, rel=1e-12)   # 3.1e-5
    assert tol > 30.0 * 1e-6
    # near the origin (|r| < 2048 m: one ulp 2^-42 m) the same pads are 2.3e-6 N, far below
    # the tolerance, which stays the scenario's
    near = System(compile_scenario(j_lay(0.0, 1.0, 0.1)))
    st0 = near.model.initial
    assert contact_resolution_force(near, st0) == pytest.approx(pads * 2.0 ** -42, rel=1e-12)
    assert newton_tolerance(near, st0, 1e-6, near.force_scale(st0)) == 1e-6


@pytest.mark.parametrize("time_step, duration", [(0.1, 2.0), (0.01, 0.5)])
def test_j_lay_far_from_the_origin_runs_as_near_it(time_step, duration):
    # failed before: 'Newton iteration did not converge' at t = 0.0047 s (0.1 s steps, after
    # halvings) and t = 0.14 s (0.01 s steps)
    far = run(FAR, duration, time_step)
    near = run(0.0, duration, time_step)
    steps = int(round(duration / time_step))
    assert far.counters["steps"] == steps
    assert far.counters.get("step_halvings", 0) == 0
    # Newton works no harder than near the origin (1.0-1.2 times its iterations measured)
    assert far.counters["newton_iterations"] <= 1.5 * near.counters["newton_iterations"]
    a, b = far.line("lay"), near.line("lay")
    shift = np.array([FAR, 0.0, 0.0])
    assert np.abs(a.position - shift - b.position).max() < 1e-6                  # m
    assert np.abs(a.tension - b.tension).max() < 1e-5 * np.abs(b.tension).max()  # 5.8e5 N
    assert np.abs(a.bend_moment - b.bend_moment).max() < 1.0                      # N m, of 2.8e5


def test_sde_forces_resolve_displacements_below_one_ulp_of_the_position():
    # the reason dynamics has no SDE blind spot: a displacement q of a fraction of an ulp of
    # the RFE's position moves the dynamic residual by the SDE stiffness times it, where the
    # same move of the reference position (statics' representation) is rounded away
    sc = j_lay(FAR, 1.0, 0.1)
    system = System(compile_scenario(sc))
    st = system.model.initial
    system.set_time(st.t)
    km, ws = system.km, system.ws
    n = system.n
    i = n // 2                                           # a free RFE of the hanging pipe
    assert km.rfe_kind[i] == 0
    ulp = float(np.spacing(abs(st.ref.X[i, 0])))
    assert ulp == 2.0 ** -30
    delta = ulp / 8.0
    zeros = np.zeros((n, 6))
    cq, cv = 1.0, 0.0

    def residual(q, ref):
        r = np.zeros((n, 6))
        residual_q(km, system.att, q, ref, ws, 1.0, 0, zeros, zeros, cq, cv, system.mask, system.qd_buf,
                   system.A_buf, r)
        return r

    q0 = st.q.copy()
    r0 = residual(q0, st.ref)
    q1 = q0.copy()
    q1[i, 0] += delta
    r1 = residual(q1, st.ref)
    k = float(km.sde_stiffness[:, 0].max())              # EA / l, 3.2e9 N/m
    change = float(np.abs(r1[i] - r0[i]).max())
    # the x stiffness of the two SDEs at RFE i: 0.34 k delta (1.3e-4 N; a move by one ulp, the
    # least a position takes, would change it by 2.7 k delta)
    assert 0.2 * k * delta < change < 2.0 * k * delta
    ref2 = type(st.ref)(st.ref.R.copy(), st.ref.X.copy())
    ref2.X[i, 0] += delta                                # rounds back to the same double
    assert ref2.X[i, 0] == st.ref.X[i, 0]
    assert np.array_equal(residual(q0, ref2), r0)
    # statics' force resolution at these positions: 3.0 N, 2500 times the tolerance's 1.2e-3 N
    assert position_resolution_force(system, st) == pytest.approx(k * ulp, rel=0.01)
    assert math.isfinite(change)
