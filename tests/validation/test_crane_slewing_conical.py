"""A column crane slewing steadily carries its payload round on a conical pendulum: large
rotations of the slewing drive (four turns) with the centripetal dynamics of the rope and
payload.

scenarios/column_crane.json on a still deck in air (no waves, the barge fixed, the winch
held, the payload without drag or added mass), slewed up to Omega = 6 deg/s over 50 s
(angle Omega (t - 10)^2 / 100 from t = 10 s, then linear) and on at that rate to 300 s. Once
the spin-up's swing has settled into a small oscillation, the payload's centre of gravity,
a distance l below the sheave, circles at the radius r where the rope leans out by theta,

    tan(theta) = Omega^2 r / g,   r = r_tip + l sin(theta),

(the conical pendulum: the horizontal pull of the rope gives the centripetal force m Omega^2
r, the vertical one the weight), and the tension at the hook is m g / cos(theta). The
measured means over the last 150 s (13 pendulum periods) meet both to 0.1 % and 5e-6."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.crane_results import crane_summary

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
G = 9.81
OMEGA_DEG = 6.0


def slewing_crane() -> dict:
    data = json.loads((SCENARIOS / "column_crane.json").read_text())
    data["environment"] = {"gravity": G}
    data["vessels"]["barge"]["motion"] = {"kind": "fixed"}
    crane = data["cranes"]["crane"]
    rows = [[0.0, 0.0], [10.0, 0.0]]
    rows += [[t, OMEGA_DEG * (t - 10.0) ** 2 / 100.0] for t in np.arange(15.0, 60.1, 5.0)]
    rows += [[t, OMEGA_DEG * 25.0 + OMEGA_DEG * (t - 60.0)] for t in np.arange(70.0, 300.1, 10.0)]
    crane["slewing_deg"] = [[float(t), float(a)] for t, a in rows]
    crane["winch"] = {"mode": {"kind": "speed", "rows": [[0.0, 0.0]]}}
    del crane["payload"]["drag"], crane["payload"]["added_mass"]
    data["analysis"]["dynamics"].update(duration=300.0, output_interval=0.1)
    return data


def test_the_slewed_payload_circles_on_the_conical_pendulum():
    data = slewing_crane()
    res = rfesim.simulate(data)
    assert res.status == 0 and "warning" not in res.message
    out = crane_summary(res, "crane")
    t = out["time"]
    late = t > 150.0
    rate = np.gradient(out["drive_angle"]["slewing"], t)
    assert np.max(np.abs(rate[late] - OMEGA_DEG)) < 1e-6                 # steady slewing
    assert out["drive_angle"]["slewing"][-1] == pytest.approx(1590.0)    # over four turns
    axis = np.asarray(res.line("crane_pedestal").position)[0, 0, :2]    # the pedestal's foot
    tip, payload = out["tip_position"], out["payload_position"]
    r_tip = np.linalg.norm(tip[late, :2] - axis, axis=1)
    r = np.linalg.norm(payload[late, :2] - axis, axis=1)
    length = np.linalg.norm(tip[late] - payload[late], axis=1)           # sheave to the centre of gravity
    omega = math.radians(OMEGA_DEG)
    theta = math.atan(omega ** 2 * r.mean() / G)
    # the spin-up leaves a swing of about 0.16 m about the circle
    assert np.ptp(r) < 0.5
    assert r.mean() - r_tip.mean() == pytest.approx(length.mean() * math.sin(theta), rel=0.01)   # 0.830 m
    mass = data["cranes"]["crane"]["payload"]["mass"]
    assert out["hook_tension"][late].mean() == pytest.approx(mass * G / math.cos(theta), rel=1e-4)
