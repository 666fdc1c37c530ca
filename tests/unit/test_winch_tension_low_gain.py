"""Constant-tension winch with a low gain on a stiff rope (k h / gain up to ~150): the speed
is met on the kinked characteristic (saturated at max_speed, sloped, dead band) by
linearising only the tension (WinchController._correct_tension / _meet), inside the bracket
of the tries. A Newton or secant step on the kinked residual cycled over the kink at
max_speed, and a crane hoist with gain 1e3 N*s/m failed at its first step ("did not settle
within 8 tries of a step at h/64")."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import SolverError
from rfesim.model.winches import WinchController

G = 9.81
SET = 45000.0


def crane(gain, vmax, tension=SET, dt=0.02, duration=2.0):
    tpl = {"type": "column", "position": [0.0, 0.0, 2.0],
           "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04, "elements": 4},
           "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02, "elements": 10},
           "slewing_deg": 0.0, "luffing_deg": 40.0, "rope": {"length": 10.0, "elements": 10},
           "payload": {"mass": 5000.0, "radius_of_gyration": 1.0},
           "winch": {"stored": 100.0, "mode": {"kind": "tension", "tension": tension, "gain": gain,
                                               "max_speed": vmax}}}
    return {"environment": {"gravity": G}, "cranes": {"c": tpl},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"duration": duration, "output_interval": 0.02,
                                      "integrator": {"kind": "generalized-alpha", "time_step": dt, "rho_inf": 0.8}}}}


def characteristic(T, gain, vmax, tension=SET):
    return np.clip((T - tension) / gain, -vmax, vmax)


def test_low_gain_runs_and_pays_out_at_max_speed_when_saturated():
    gain, vmax = 1.0e3, 0.3
    res = rfesim.simulate(crane(gain, vmax))
    w = res.winch("c_winch")
    T, v = np.asarray(w.tension), np.asarray(w.speed)
    # every step meets the characteristic at its own end tension (backward Euler, 1e-3 of max_speed)
    np.testing.assert_allclose(v[1:], characteristic(T[1:], gain, vmax),
                               atol=WinchController.SPEED_TOLERANCE * vmax)
    saturated = (T - SET) / gain > vmax
    saturated[0] = False                                      # the static start, at rest
    assert saturated.sum() > 30                               # the run reaches the saturated part
    np.testing.assert_allclose(v[saturated], vmax, rtol=0, atol=WinchController.SPEED_TOLERANCE * vmax)
    assert res.counters.get("step_halvings", 0) == 0
    # it pays out; at most max_speed on average
    assert 0.0 < w.payout[-1] <= vmax * float(res.time[-1]) + 1e-9


def test_low_gain_unsaturated_set_point_settles_on_the_sloped_part():
    gain, vmax, tension = 1.0e3, 0.5, 49000.0
    res = rfesim.simulate(crane(gain, vmax, tension=tension, dt=0.05, duration=4.0))
    w = res.winch("c_winch")
    T, v = np.asarray(w.tension), np.asarray(w.speed)
    assert abs(v[-1] - (T[-1] - tension) / gain) < 1e-3 * vmax
    assert 0.0 < v[-1] < vmax                                # (0.37 m/s: on the slope, not clipped)


def test_unsettled_speed_names_what_to_change(monkeypatch):
    monkeypatch.setattr(WinchController, "SPEED_TOLERANCE", 0.0)        # never settles
    with pytest.raises(SolverError) as exc:
        rfesim.simulate(crane(1.0e3, 0.3, duration=0.02))
    msg = str(exc.value)
    for words in ("did not settle", "winch 'c_winch' (constant tension)", "k h / gain",
                  "cranes.c.winch.mode.gain", "time step", "max_speed"):
        assert words in msg, (words, msg)


def test_heaving_rope_at_half_second_steps_needs_no_halving():
    """The dead band's kinks cycled the secant at 0.5 s steps (16 halvings in 100 s)."""
    from tests.validation.test_winch_dynamics import hoist
    L0 = 20.0
    sc = hoist({"kind": "tension", "tension": 5000.0, "dead_band": 200.0, "gain": 500.0, "max_speed": 2.0},
               L0=L0, EA=2e5, m=10.0, mu=0.1, duration=30.0, h=0.5, output=0.5, damping=0.5)
    sc.pop("bodies")
    sc["vessels"] = {"tug": {"position": [0, 0, -L0 - 0.3], "motion": {"kind": "harmonic", "heave": {
        "amplitude": 0.5, "period": 20.0}, "ramp_duration": 10.0}}}
    sc["lines"]["hoist"]["end_b"] = {"attach": "tug", "position": [0, 0, 0]}
    res = rfesim.simulate(sc)
    assert res.counters.get("step_halvings", 0) == 0
    T = res.winch("w").tension
    assert np.abs(T[res.time > 10.0] - 5000.0).max() < 200.0 + 1.1 * 500.0 * 0.5 * 2 * math.pi / 20.0 + 20.0
