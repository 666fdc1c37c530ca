"""Torque-limited slewing motor on a coaxial join (rfesim.loads.drives.motor_forces,
docs/theory.md "Slewing motor with a torque limit"): a pedestal, a turret on the motor and a
horizontal boom clamped to the turret, no gravity moment about the axis.

* at the torque limit the boom accelerates at T_max / I_z, I_z its inertia about the
  pedestal axis summed from the model's RFEs;
* below the limit the servo follows the angle table;
* the motor's torque never exceeds its limit;
* the motor-corrected loads equal the SDE kernel's with the torsional law replaced by a
  spring giving the same moment (an identity, at a random pose);
* the template's slewing motor: the crane turns by its table and the slewing torque is an
  output.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError

ROOT = Path(__file__).resolve().parents[2]
TUBE = {"EA": 2e10, "EIy": 5e9, "EIz": 5e9, "GJ": 4e9, "mass_per_length": 500.0}


def scene(max_torque, table, stiffness=2e8, damping=4e7, duration=3.0, h=0.02, boom_direction=(1, 0, 0)):
    motor = {"angle": table, "max_torque": max_torque, "stiffness": stiffness, "damping": damping}
    return {"environment": {"gravity": 9.81},
            "line_types": {"tube": TUBE, "boomt": dict(TUBE, mass_per_length=300.0)},
            "lines": {
                "ped": {"type": "tube", "length": 9.5, "elements": 5,
                        "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                                  "connection": "clamped"}},
                "turret": {"type": "tube", "length": 0.5, "elements": 1,
                           "end_a": {"attach": "ped:end_b", "connection": "clamped", "direction": [0, 0, 1],
                                     "motor": motor}},
                "boom": {"type": "boomt", "length": 20.0, "elements": 10,
                         "end_a": {"attach": "turret:end_b", "connection": "clamped",
                                   "direction": list(boom_direction)}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"duration": duration, "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": h, "rho_inf": 0.8}}}}


def inertia_about_axis(data) -> float:
    """I_z of the turret and boom RFEs about the vertical axis through the origin (parallel
    axes plus each RFE's own inertia about the global z)."""
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import Scenario
    from rfesim.solvers.system import System
    sc = Scenario.model_validate(data)
    system = System(compile_scenario(sc))
    system.evaluate(system.model.initial)
    km, ws = system.km, system.ws
    total = 0.0
    for li in system.model.lines:
        if li.name == "ped":
            continue
        for i in range(li.rfe_start, li.rfe_stop):
            x, y = ws.r[i, 0], ws.r[i, 1]
            ez = ws.R[i].T @ np.array([0.0, 0.0, 1.0])     # global z in the RFE's axes
            total += km.rfe_mass[i] * (x * x + y * y) + float(np.sum(km.rfe_inertia[i] * ez * ez))
    return total


def test_saturated_motor_accelerates_at_torque_over_inertia():
    T = 2e4
    data = scene(T, [[0.0, 0.0], [1.0, 60.0]])
    res = rfesim.simulate(data)
    turret = res.line("turret")
    assert turret.drive_names == ("slewing",)
    t = np.asarray(res.time)
    angle = np.radians(np.asarray(turret.drive_angle)[:, 0])
    torque = np.asarray(turret.drive_torque)[:, 0]
    keep = t >= 0.3
    alpha = 2.0 * np.polyfit(t[keep], angle[keep], 2)[0]
    expected = T / inertia_about_axis(data)
    assert alpha == pytest.approx(expected, rel=0.005)
    assert np.all(np.abs(torque) <= T * (1.0 + 1e-6))
    assert np.abs(torque[keep]).min() > 0.99 * T            # at the limit throughout


def test_servo_follows_the_table_below_the_limit():
    res = rfesim.simulate(scene(1e9, [[0.0, 0.0], [1.0, 0.0], [5.0, 30.0]], duration=8.0))
    turret = res.line("turret")
    t = np.asarray(res.time)
    angle = np.asarray(turret.drive_angle)[:, 0]
    torque = np.asarray(turret.drive_torque)[:, 0]
    assert angle[t <= 1.0] == pytest.approx(0.0, abs=1e-6)
    assert angle[-1] == pytest.approx(30.0, abs=0.05)
    assert np.abs(torque).max() > 1e5                        # it did drive the boom
    assert abs(torque[-1]) < 0.2 * np.abs(torque).max()      # and holds it at rest afterwards


def test_motor_loads_equal_the_sde_kernel_with_the_same_moment():
    from rfesim.model.assemble import motor_moments, poses, sde_forces_all
    from rfesim.model.compile import compile_scenario
    from rfesim.scenario import Scenario
    from rfesim.solvers.system import System
    from rfesim.vessel_kernel import attachment_kinematics
    system = System(compile_scenario(Scenario.model_validate(scene(2e4, [[0.0, 0.0], [1.0, 60.0]]))))
    km, ws, att = system.km, system.ws, system.att
    st = system.model.initial.copy()
    rng = np.random.default_rng(1)
    st.q[:, 3:] += 0.02 * rng.standard_normal((system.n, 3)) * system.mask[:, 3:]
    st.qd[:] = 0.1 * rng.standard_normal((system.n, 6)) * system.mask
    attachment_kinematics(system.vs, 0.5, att)
    poses(km, att, st.q, st.qd, st.ref, ws)
    F, M = np.zeros((system.n, 3)), np.zeros((system.n, 3))
    sde_forces_all(km, att, ws, F, M)
    m = int(km.motor_sde[0])
    theta, elastic = float(ws.eps[m, 3]), float(ws.sigma[m, 3])
    # the servo law by hand: set angle and rate of the two-row table at t = 0.5 (a straight line)
    rate = np.radians(60.0)
    raw = elastic - 2e8 * rate * 0.5 - 4e7 * rate
    motor_moments(km, att, ws, -1, M)
    assert float(ws.sigma[m, 3]) == pytest.approx(float(np.clip(raw, -2e4, 2e4)), rel=1e-12)
    assert ws.motor_sat[0] == (1 if abs(raw) > 2e4 else 0)
    # reference: the plain SDE kernel with a torsional spring that gives the same moment
    k2, c2 = km.sde_stiffness.copy(), km.sde_damping.copy()
    k2[m, 3] = float(ws.sigma[m, 3]) / theta
    c2[m, 3] = 0.0
    F2, M2 = np.zeros((system.n, 3)), np.zeros((system.n, 3))
    sde_forces_all(km._replace(sde_stiffness=k2, sde_damping=c2), att, ws, F2, M2)
    np.testing.assert_allclose(F, F2, rtol=0, atol=1e-9 * np.abs(F).max())
    np.testing.assert_allclose(M, M2, rtol=0, atol=1e-12 * np.abs(M).max())


@pytest.mark.parametrize("edit, field, words", [
    (lambda d: d["lines"]["turret"]["end_a"].update(connection="pinned"), "lines.turret.end_a.motor",
     "clamped join"),
    (lambda d: d["lines"]["turret"]["end_a"].update(drives=[{"name": "x", "axis": [0, 0, 1],
                                                            "angle": [[0, 0], [1, 1]]}]),
     "lines.turret.end_a.motor", "not both"),
    (lambda d: d["analysis"]["dynamics"].update(output_interval=1.0),
     "analysis.dynamics.output_interval", "less than 90 deg in one"),
    (lambda d: d["lines"]["turret"]["end_a"]["motor"].update(max_torque=-1.0),
     "lines.turret.end_a.motor.max_torque", ""),
    (lambda d: d["lines"]["turret"]["end_a"].update(direction=[0, 1, 1]), "lines.turret.end_a.direction",
     "must continue the direction"),
])
def test_motor_input_errors_name_the_field(edit, field, words):
    data = scene(2e4, [[0.0, 0.0], [1.0, 60.0]])
    edit(data)
    with pytest.raises(ScenarioError) as err:
        rfesim.simulate(data)
    text = str(err.value)
    assert field in text and words in text


def crane_data(max_torque):
    data = json.loads((ROOT / "scenarios" / "column_crane.json").read_text())
    data["environment"]["water"].pop("waves")
    data["vessels"]["barge"]["motion"] = {"kind": "fixed"}
    crane = data["cranes"]["crane"]
    crane.pop("winch")
    crane["slewing_motor"] = {"max_torque": max_torque}
    data["analysis"]["dynamics"].update(duration=14.0, output_interval=0.1)
    data["analysis"]["dynamics"]["integrator"]["time_step"] = 0.05
    return data


def test_column_crane_template_with_a_slewing_motor():
    from rfesim.crane_results import crane_summary
    from rfesim.scenario import expand
    data = crane_data(3e5)
    out = expand(data)
    ped, turret = out["lines"]["crane_pedestal"], out["lines"]["crane_turret"]
    assert ped["length"] + turret["length"] == pytest.approx(12.0)            # the pedestal's height kept
    assert turret["end_a"]["motor"]["max_torque"] == 3e5
    assert [d["name"] for d in out["lines"]["crane_boom"]["end_a"]["drives"]] == ["luffing"]
    res = rfesim.simulate(data)
    s = crane_summary(res, "crane")
    slew, torque = s["drive_angle"]["slewing"], s["drive_torque"]["slewing"]
    assert slew[0] == pytest.approx(80.0, abs=1e-6)
    assert slew[-1] == pytest.approx(90.0, abs=0.5)
    assert np.abs(torque).max() <= 3e5 * (1.0 + 1e-6)
    assert s["drive_angle"]["luffing"][-1] == pytest.approx(45.0, abs=1e-6)


def test_servo_slews_past_half_a_turn_by_rebasing_its_joint(monkeypatch):
    """A motor joint's angle is a rotation vector component, unique within +-180 deg; the
    twist is moved into the joint's rest rotation between outputs (rfesim.model.joins.
    rebase_motors), so the servo slews the boom 270 deg: the drive angle reaches 270 deg,
    the boom tip lies on its circle at 270 deg, and the run is the same (to the Newton
    tolerance) whether the joint is rebased beyond 60 or beyond 30 deg."""
    import rfesim.model.joins as joins
    data = scene(1e9, [[0.0, 0.0], [1.0, 0.0], [9.0, 270.0]], duration=11.0)
    res = rfesim.simulate(data)
    angle = np.asarray(res.line("turret").drive_angle)[:, 0]
    assert angle.max() > 269.0 and angle[-1] == pytest.approx(270.0, abs=0.05)
    tip = np.asarray(res.line("boom").position)[-1, -1]
    reach = 20.0 + 0.0                                          # the boom from the pedestal axis
    assert tip[:2] == pytest.approx([0.0, -reach], abs=0.05)   # 270 deg from +x about +z
    monkeypatch.setattr(joins, "REBASE_TWIST", np.pi / 6.0)
    res2 = rfesim.simulate(data)
    tips, tips2 = np.asarray(res.line("boom").position)[:, -1], np.asarray(res2.line("boom").position)[:, -1]
    assert np.abs(tips - tips2).max() < 1e-4
    assert np.abs(np.asarray(res2.line("turret").drive_angle)[:, 0] - angle).max() < 1e-4


def test_template_slewing_motor_turns_the_crane_half_a_turn():
    """The column crane template on a 3 MN*m motor slews 180 deg in 12 s."""
    data = crane_data(3e6)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [12.0, 260.0]]
    from rfesim.crane_results import crane_summary
    s = crane_summary(rfesim.simulate(data), "crane")
    slew = s["drive_angle"]["slewing"]
    # through 180 deg from the start without a jump (0.1 s outputs, at most 15 deg/s); the
    # swinging payload drives the 0.5 Hz servo a little past its end (measured 1.9 deg at 14 s)
    assert np.abs(np.diff(slew)).max() < 3.0
    assert slew[-1] == pytest.approx(260.0, abs=3.0)


def test_the_slewing_motor_example_scenario_loads():
    sc = rfesim.load_scenario(ROOT / "scenarios" / "column_crane_slewing_motor.json")
    motor = sc.lines["crane_turret"].end_a.motor
    assert motor.max_torque == 250000.0 and motor.angle[-1] == [15.0, 100.0]
