"""Paying out pipe through a tensioner (rfesim.loads.tensioner): the pipe stored upstream
passes the track, the suspended length grows by the paid-out length, mass is that of the
material throughout, and the line's tension shows no start-up transient."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim

MASS_PER_LENGTH = 100.0
PULL = 5.0e4


def payout_rows():
    """50 m paid out between 10 s and 70 s, at 1 m/s between 20 s and 60 s (the monotone
    cubic through the rows eases the speed in and out)."""
    return [[0.0, 0.0], [10.0, 0.0], [20.0, 5.0], [60.0, 45.0], [70.0, 50.0], [90.0, 50.0]]


def payout_scene(duration=90.0):
    return rfesim.Scenario.model_validate({
        "environment": {"gravity": 0.0},
        "line_types": {"pipe": {"EA": 2e9, "EIy": 1e6, "GJ": 1e6, "mass_per_length": MASS_PER_LENGTH,
                                "outer_diameter": 0.3, "damping": {"axial_ratio": 0.05, "bending_ratio": 0.05}}},
        "lines": {"pipe": {"type": "pipe", "length": 150.0, "elements": 75,
                           "end_a": {"attach": "free", "position": [-70.0, 0.0, 0.0], "direction": [1, 0, 0]},
                           "end_b": {"attach": "free"},
                           "loads": [{"at": "end_b", "force": [PULL, 0.0, 0.0]}]}},
        "supports": {"tensioner": {"kind": "tensioner", "line": "pipe", "entry": [0.0, 0.0, 0.0],
                                   "axis": [1.0, 0.0, 0.0], "length": 10.0, "capacity": 1e6,
                                   "payout": {"kind": "table", "rows": payout_rows()}}},
        "analysis": {"dynamics": {"duration": duration, "output_interval": 0.5,
                                  "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}},
    })


def test_payout_of_50_m_conserves_mass_and_has_no_transient():
    res = rfesim.simulate(payout_scene())
    line = res.line("pipe")
    tens = res.tensioners["tensioner"]
    t = res.time
    assert tens.payout[-1] == pytest.approx(50.0)
    # the line moved out by the paid-out length (+ its stretch under the pull, constant)
    end_b = line.position[:, -1, 0]
    np.testing.assert_allclose(end_b - end_b[0], tens.payout, atol=0.02)
    # the length beyond the track exit grew by 50 m: arc length of the first point past x = 10 m
    def outboard(k):
        x = line.position[k, :, 0]
        return line.arc_length[-1] - np.interp(10.0, x, line.arc_length)
    assert outboard(-1) - outboard(0) == pytest.approx(50.0, abs=0.05)
    # the tensioner holds the pull less what accelerates the line (its whole mass, material
    # upstream included): no start-up transient, no jolt as RFEs enter and leave the track
    accel = np.gradient(np.gradient(tens.payout, t), t)
    expected = PULL - MASS_PER_LENGTH * 150.0 * accel
    assert np.abs(tens.grip_force - expected).max() < 0.04 * PULL     # axial ringing after jerks of the cubic
    assert np.abs(tens.grip_force - PULL).max() < 0.06 * PULL
    # momentum: the whole line moves with the payout speed, its mass the material's
    v = np.gradient(line.position[:, :, 0], t, axis=0)
    speed = np.gradient(tens.payout, t)
    moving = speed > 0.5
    momentum = MASS_PER_LENGTH * np.trapezoid(v[moving], line.arc_length, axis=1)
    assert momentum == pytest.approx(MASS_PER_LENGTH * 150.0 * speed[moving], rel=0.01)
