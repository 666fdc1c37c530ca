"""A driven (constant-tension) reel pays out stably (rfesim.loads.reel, docs/theory.md "Reel").

The reel's law acts on the drum's own grip force less the offset statics fixes (grip force
- back tension at the settled state), solved implicitly like a tensioner's. Before, it
acted on the tension just off the drum (beyond the wrapped pipe's mass from the drum: a
non-collocated feedback with negative damping) and counted the drum's motion twice in the
step: in the reel-lay template, with the tensioner on a 0.22 m/s table and the reel driven
at gain 2e4 (the first test), 10 s took 500 steps instead of 200 (187 halvings), the reel's
grip swung between -94 and +353 kN (std 139 kN after 4 s) and the tensioner's between -364
and +474 kN. Now: 200 steps, the reel's grip 70.7-76.0 kN (std 0.2 kN).
"""
from __future__ import annotations

from pathlib import Path

import math

import numpy as np
import pytest
from pydantic import TypeAdapter

import rfesim
from rfesim.loads.reel import reel_forces
from rfesim.loads.tensioner import MODE_TENSION

ROOT = Path(__file__).resolve().parents[2]
SCENARIOS = ROOT / "scenarios"

DURATION = 10.0
STEP = 0.05
SPEED = 0.22


def _ramp_rows(v: float, T: float) -> list[list[float]]:
    """D(t) of a half-cosine ramp from rest to v over 2 s, then v up to T + 1."""
    rows = [[0.0, 0.0]]
    for t in np.arange(0.25, 2.01, 0.25):
        rows.append([float(t), float(0.5 * v * (t - 2.0 / np.pi * np.sin(0.5 * np.pi * t)))])
    rows.append([T + 1.0, rows[-1][1] + v * (T - 1.0)])
    return rows


def test_driven_reel_under_a_prescribed_tensioner_pays_out_stably():
    over = {"environment.water.waves": None, "vessels.reeler.motion": {"kind": "fixed"},
            "analysis.dynamics.duration": DURATION, "analysis.dynamics.output_interval": 0.1,
            "analysis.dynamics.integrator.time_step": STEP,
            # a constant-tension tensioner makes the template drive the reel (gain, speed limit)
            "pipelay.lay.tensioner.payout": {"kind": "constant-tension", "tension": 5.0e4, "dead_band": 0.0,
                                             "gain": 2.0e4, "max_speed": 0.5}}
    sc = rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides=over)
    reel, tens = sc.supports["lay_reel"], sc.supports["lay_tensioner"]
    assert reel.payout.kind == "constant-tension" and reel.payout.gain == 2.0e4
    # the tensioner on a table: only the reel is driven
    tens.payout = TypeAdapter(type(tens).model_fields["payout"].annotation).validate_python(
        {"kind": "table", "rows": _ramp_rows(SPEED, DURATION)})
    res = rfesim.simulate(sc)
    planned = round(DURATION / STEP)
    assert res.counters["steps"] <= 1.05 * planned, res.counters
    t = np.asarray(res.time)
    Fr = np.asarray(res.reels["lay_reel"].grip_force)
    Ft = np.asarray(res.tensioners["lay_tensioner"].grip_force)
    assert Fr.min() > 0.0, Fr.min()                            # the drum never pushes the pipe
    assert Fr[t > 4.0].std() < 5.0e3, Fr[t > 4.0].std()        # it settles
    assert np.abs(Ft).max() < 3.0e5, np.abs(Ft).max()
    # it pays out with the tensioner (within the chord/grip kinematics of the wrap)
    D = np.asarray(res.reels["lay_reel"].payout)
    v = np.polyfit(t[t > 5.0], D[t > 5.0], 1)[0]
    assert 0.8 * SPEED < v < 1.3 * SPEED, v


@pytest.mark.parametrize("h", [0.05, 0.01])
def test_driven_reel_law_acts_on_its_grip_force_less_the_offset(h):
    """The kernel's implicit payout solves D = D_c + h (T_g(D) - offset - set) / gain with
    T_g the drum's own grip force at the solved D: the gain is the stated one at any step
    (before, gain + K_g h in effect, from the tension of an SDE past the take-off)."""
    R, W, l, kg = 4.0, math.radians(180.0), 0.5, 1.0e5
    a, d = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    C = np.array([0.0, 0.0, R])
    joints = np.arange(0.0, 6.0 + 1e-9, l) / R
    mid = 0.5 * (joints[:-1] + joints[1:])
    n0 = np.cross(a, d)
    pts = C + R * (np.cos(joints)[:, None] * n0 - np.sin(joints)[:, None] * d)
    r = 0.5 * (pts[:-1] + pts[1:])
    n = r.shape[0]
    weight = np.clip(np.minimum(R * mid / l, R * (W - mid) / l), 0.0, 1.0)
    on = (weight > 0.0).astype(np.int64)
    s0 = 0.2                                                  # the anchors 0.2 m ahead: the drum holds back
    anchor = -R * mid - s0
    K = kg * l * weight[on == 1].sum()
    offset, T_set, gain = 3.0e4, 1.0e4, 2.0e4
    D_trial, force = np.zeros(1), np.zeros(1)
    reel_forces(np.array([0]), np.array([C]), np.array([a]), np.array([d]), np.array([R]), np.array([W]),
                np.array([1e9]), np.array([1e9]), np.array([kg]), np.array([1e12]), np.array([0]), np.array([n]),
                np.array([MODE_TENSION]), np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)), np.array([2]), 0.0,
                np.zeros((1, 3)), np.eye(3)[None], np.full(n, l), r, np.zeros((n, 3)), anchor, on, np.zeros(n),
                np.zeros(n, np.int64), np.zeros(1), force, np.array([T_set]), np.zeros(1), np.array([gain]),
                np.array([100.0]), h, np.array([offset]), D_trial)
    D = D_trial[0]
    assert force[0] == pytest.approx(K * (s0 - D), rel=1e-9)     # the grip force at the solved D
    assert D == pytest.approx(h * (K * s0 - offset - T_set) / (gain + h * K), rel=1e-9)
    assert D / h == pytest.approx((force[0] - offset - T_set) / gain, rel=1e-9)
