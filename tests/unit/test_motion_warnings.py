"""Tables that stop a motion dead inside the run (rfesim.scenario.motion_warnings): a drive's,
slewing motor's, payout or chain joint table whose last row lies inside the run while the
curve the run follows still moves there gets a dynamics warning naming the user's field, the
time and the rate at the last row, and the row that would hold it. The rate is the curve's
(the monotone cubic's end slope), not the last segment's mean."""
from __future__ import annotations

import copy
import math
import json
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import CubicSpline, PchipInterpolator

import rfesim
from rfesim.scenario.motion_warnings import startup_warnings, table_end_warnings

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
ROD = {"rigid": True, "length": 1.0, "mass": 1.0}


def scenario(name: str, **dynamics) -> dict:
    data = json.loads((SCENARIOS / name).read_text())
    data["analysis"]["dynamics"].update(dynamics)
    return data


def warnings_of(data: dict) -> list[str]:
    return table_end_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))


@pytest.mark.parametrize("name", sorted(p.name for p in SCENARIOS.glob("*.json")))
def test_the_shipped_scenarios_stop_their_tables_smoothly(name):
    assert warnings_of(scenario(name)) == []


def test_a_slewing_table_that_ends_moving_is_named_with_the_cubics_rate():
    data = scenario("column_crane.json", duration=160.0)
    rows = [[0.0, 80.0], [20.0, 80.0], [140.0, 1160.0]]
    data["cranes"]["crane"]["slewing_deg"] = rows
    (w,) = warnings_of(data)
    # PCHIP's end slope from the last two segments: ((2 h1 + h0) d1 - h1 d0) / (h0 + h1)
    rate = PchipInterpolator(*np.array(rows).T).derivative()(140.0)
    assert rate == pytest.approx((2 * 120 + 20) * 9.0 / 140.0)
    assert w.startswith(f"cranes.crane.slewing_deg: the angle table ends at t = 140 s with the slewing angle still "
                        f"turning at {rate:.3g} deg/s")
    assert "16.7 deg/s" in w and "9 deg/s" not in w
    assert "e.g. [145, 1160]" in w
    # held at its last angle: smooth; ending after the run: no stop inside it
    data["cranes"]["crane"]["slewing_deg"] = rows + [[145.0, 1160.0]]
    assert warnings_of(data) == []
    data["cranes"]["crane"]["slewing_deg"] = rows
    data["analysis"]["dynamics"]["duration"] = 140.0
    assert warnings_of(data) == []
    data["analysis"]["dynamics"].update(duration=160.0, enabled=False)
    assert warnings_of(data) == []


def test_a_two_row_drive_table_starts_and_stops_at_rest():
    data = scenario("column_crane.json", duration=30.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [10.0, 170.0]]
    assert warnings_of(data) == []


def test_the_portal_legs_share_one_warning_and_a_stroke_table_names_its_stroke():
    data = scenario("a_frame.json", duration=40.0)
    data["cranes"]["aframe"]["tilt_deg"] = [[0.0, -25.0], [5.0, -25.0], [35.0, 35.0]]
    (w,) = warnings_of(data)            # the two legs, one table
    assert w.startswith("cranes.aframe.tilt_deg: the angle table ends at t = 35 s with the luffing angle still "
                        "turning at 3.71 deg/s")
    data = scenario("column_crane.json", duration=30.0)
    crane = data["cranes"]["crane"]
    del crane["luffing_deg"]
    crane["cylinder"]["stroke"] = [[0.0, 11.98], [5.0, 11.98], [15.0, 11.63]]
    (w,) = warnings_of(data)
    assert w.startswith("cranes.crane.cylinder.stroke: the stroke table ends at t = 15 s with the luffing angle "
                        "still turning at -")
    assert "holds the last stroke, e.g. [20, 11.63]" in w


def test_a_slewing_motor_is_warned_that_its_set_angle_stops():
    data = scenario("column_crane_slewing_motor.json", duration=20.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 30.0], [5.0, 30.0], [15.0, 100.0]]
    (w,) = warnings_of(data)
    assert w.startswith("cranes.crane.slewing_deg: the angle table ends at t = 15 s")
    assert "the motor brakes the structure with up to its max_torque" in w


def test_a_payout_table_names_the_tensioners_table_once():
    data = scenario("reel_lay.json", duration=70.0)      # its table ends at 60 s, the run's end
    rows = np.array(data["pipelay"]["lay"]["tensioner"]["payout"]["rows"])
    (w,) = warnings_of(data)                             # the reel turns with the same table
    speed = PchipInterpolator(rows[:, 0], rows[:, 1]).derivative()(60.0)
    assert w.startswith(f"pipelay.lay.tensioner.payout.rows: the payout table ends at t = 60 s while paying out at "
                        f"{speed:.3g} m/s")
    assert warnings_of(scenario("reel_lay.json")) == []


def test_a_chain_table_is_warned_with_its_spline_rate():
    rows = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.5], [3.0, 1.0]]
    data = {"environment": {"gravity": 9.81},
            "chains": {"c": {"links": {"a": dict(ROD)},
                             "joints": {"j1": {"kind": "revolute", "parent": "base", "child": "a", "axis": [0, 1, 0],
                                               "drive": {"kind": "prescribed",
                                                         "motion": {"kind": "table", "rows": rows}}}}}},
            "analysis": {"dynamics": {"duration": 4.0, "integrator": {"kind": "rk4"}}}}
    (w,) = table_end_warnings(rfesim.Scenario.model_validate(data))
    rate = CubicSpline(*np.array(rows).T, bc_type="natural")(3.0, 1)
    assert w.startswith(f"chains.c.joints.j1.drive.motion.rows: the table ends at t = 3 s while still moving at "
                        f"{rate:.3g} rad/s")
    data["analysis"]["dynamics"]["duration"] = 3.0
    assert table_end_warnings(rfesim.Scenario.model_validate(data)) == []


def test_check_and_the_services_submit_show_it_before_the_run(tmp_path, caplog):
    """``rfesim check`` logs the warning (and a vessel motion table ending early, which only
    the run's message had); the service answers it at submit (service.validate.load_warnings)."""
    import logging

    from rfesim.cli import main
    data = scenario("column_crane.json", duration=160.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [20.0, 80.0], [140.0, 1160.0]]
    data["vessels"]["barge"]["motion"]["file"] = str(SCENARIOS / data["vessels"]["barge"]["motion"]["file"])
    path = tmp_path / "slew.json"
    path.write_text(json.dumps(data))
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        assert main(["check", str(path)]) == 0
    logged = [r.getMessage() for r in caplog.records]
    assert any(m.startswith("dynamics: cranes.crane.slewing_deg: the angle table ends at t = 140 s") for m in logged)

    table = {"environment": {"gravity": 9.81},
             "vessels": {"ship": {"motion": {"kind": "table", "interpolation": "linear",
                                               "rows": [[0.0, 0, 0, 0, 0, 0, 0], [2.0, 1.0, 0, 0, 0, 0, 0]]}}},
             "line_types": {"rope": {"EA": 1.0e6, "EIy": 0.0, "mass_per_length": 1.0}},
             "lines": {"l": {"type": "rope", "length": 5.0, "elements": 5,
                             "end_a": {"attach": "ship", "position": [0.0, 0.0, 0.0]},
                             "end_b": {"attach": "free", "position": [0.0, 0.0, -5.0]}}},
             "analysis": {"dynamics": {"duration": 5.0}}}
    path.write_text(json.dumps(table))
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        assert main(["check", str(path)]) == 0
    assert any("(vessels.ship.motion.rows): the motion table ends at t = 2 s" in r.getMessage() for r in caplog.records)

    from service import validate
    from service.settings import Settings
    _, sc = validate.prepare_job({"scenario": "column_crane", "overrides": {
        "cranes.crane.slewing_deg": [[0.0, 80.0], [20.0, 80.0], [140.0, 1160.0]],
        "analysis.dynamics.duration": 160.0}}, Settings(data_dir=tmp_path), SCENARIOS)
    warnings = validate.load_warnings(sc)
    assert any(w.startswith("dynamics: cranes.crane.slewing_deg: the angle table ends at t = 140 s") for w in warnings)


def test_the_shipped_scenarios_ramp_their_waves_and_vessels_in():
    for path in sorted(SCENARIOS.glob("*.json")):
        assert startup_warnings(rfesim.load_scenario(path)) == [], path.name


def test_waves_without_a_ramp_are_named_with_their_period_and_the_rao_vessels():
    data = scenario("column_crane.json")
    data["environment"]["water"]["waves"]["ramp_duration"] = 0.0
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert w.startswith("environment.water.waves.ramp_duration: 0 s, so the jonswap waves start at full height at "
                        "t = 0 on the structure in its static equilibrium in still water")
    assert "and the motion of the RAO vessel barge," in w and "(ramp_duration 8 s)" in w
    data["environment"]["water"]["waves"] = {"kind": "airy", "height": 2.0, "period": 9.5}
    data["analysis"]["statics"]["enabled"] = False
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert "the airy waves start at full height at t = 0 on the structure in its initial shape at rest" in w
    assert "ramp them in over a period or more (ramp_duration 9.5 s)" in w
    data["analysis"]["dynamics"]["enabled"] = False
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []


def test_a_harmonic_vessel_without_a_ramp_is_named_in_the_template_field():
    data = scenario("h1_riser_heave.json")
    data["vessels"]["vessel"]["motion"]["ramp_duration"] = 0.0
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert w.startswith("vessels.vessel.motion.ramp_duration: 0 s, so vessel 'vessel' starts its harmonic motion")
    assert "(ramp_duration 8 s)" in w
    data["vessels"]["vessel"]["motion"]["heave"]["amplitude"] = 0.0     # still: nothing starts
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []
    data = scenario("j_lay.json")
    data["pipelay"]["lay"]["vessel"]["motion"]["ramp_duration"] = 0.0
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert w.startswith("pipelay.lay.vessel.motion.ramp_duration: 0 s, so vessel 'lay_vessel' starts")


def test_the_run_without_a_ramp_has_the_transient_the_warning_names():
    """The column crane of scenarios/column_crane.json, 20 s in a regular 3 m, 8 s beam sea:
    with no ramp the RAO barge starts rolling at full velocity under the payload hanging at
    rest, the payload snatches its rope (355 kN at the sheave against 138 kN ramped in over
    10 s) and the run needs 875 step halvings and 5 recoveries (ramped: none). The message
    says why."""
    data = scenario("column_crane.json", duration=20.0)
    data["environment"]["water"]["waves"] = {"kind": "airy", "height": 3.0, "period": 8.0, "direction_deg": 90.0}
    res = rfesim.simulate(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))
    assert "environment.water.waves.ramp_duration: 0 s" in res.message
    data["environment"]["water"]["waves"]["ramp_duration"] = 10.0
    ramped = rfesim.simulate(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert "ramp_duration" not in ramped.message
    assert res.counters["step_halvings"] > 20 * ramped.counters.get("step_halvings", 0) + 20
    assert np.max(res.line("crane_rope").tension) > 2.0 * np.max(ramped.line("crane_rope").tension)


def test_a_winch_or_payout_that_starts_at_speed_is_named():
    """A winch speed table not at 0 at t = 0 jumps the rope's speed from rest: the column crane
    hauling its 10 t in at 0.5 m/s from t = 0 in a calm sea peaks at 144 kN at the sheave
    against 104 kN with the speed reached over 2 s (static 99.7 kN; measured for this
    warning). A payout table whose straight line or cubic starts moving at once, the same."""
    data = scenario("column_crane.json", duration=10.0)
    data["cranes"]["crane"]["winch"]["mode"]["rows"] = [[0.0, -0.5]]
    (w,) = startup_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))
    assert w.startswith("cranes.crane.winch.mode.rows: the winch hauls in at 0.5 m/s at once at t = 0")
    assert "e.g. [[0, 0], [2, -0.5], ...]" in w
    data["cranes"]["crane"]["winch"]["mode"]["rows"] = [[0.0, 0.0], [2.0, -0.5]]
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []

    data = scenario("reel_lay.json")
    payout = data["pipelay"]["lay"]["tensioner"]["payout"]
    payout["rows"] = [[5.0, 0.0], [55.0, 7.5]]
    (w,) = startup_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))   # reel and tensioner
    assert w.startswith("pipelay.lay.tensioner.payout.rows: the payout table starts paying out at 0.15 m/s at once "
                        "at t = 5 s (the straight line of two rows)")
    payout["rows"] = [[-5.0, 0.0], [55.0, 7.5]]          # moving at t = 0 already
    (w,) = startup_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))
    assert "at 0.125 m/s at once at t = 0 s" in w
    payout["rows"] = [[0.0, 0.0], [5.0, 1.0], [55.0, 7.5]]
    rate = PchipInterpolator([0.0, 5.0, 55.0], [0.0, 1.0, 7.5]).derivative()(0.0)
    (w,) = startup_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))
    assert f"at {rate:.3g} m/s at once at t = 0 s (the slope of its monotone cubic at its first row)" in w
    payout["rows"] = [[0.0, 0.0], [5.0, 0.0], [6.0, 0.1], [55.0, 7.5]]        # held, then a ramp: from rest
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []


def test_a_recorded_vessel_motion_begun_before_the_run_is_ramped_or_named():
    """A motion table (or file) whose run starts inside it (start_time) moves at t = 0: with no
    ramp its velocity there jumps on. The warning names the moving DOFs with their speeds,
    the spline's slope at t = 0 (the sines' own, 1.26 deg/s for the roll of 2 deg at 10 s at
    its zero crossing; at t = 0 of the table the natural spline's slope, 0.392 m/s of heave
    against the sine's 0.393)."""
    import math
    times = np.arange(0.0, 101.0)
    rows = [[t, 0.0, 0.0, 0.5 * math.sin(2 * math.pi * t / 8.0), 2.0 * math.sin(2 * math.pi * t / 10.0), 0.0, 0.0]
            for t in times]
    data = {"environment": {"gravity": 9.81},
            "vessels": {"ship": {"motion": {"kind": "table", "rows": rows, "start_time": 50.0}}},
            "line_types": {"rope": {"EA": 1.0e6, "EIy": 0.0, "mass_per_length": 1.0}},
            "lines": {"l": {"type": "rope", "length": 5.0, "elements": 5,
                            "end_a": {"attach": "ship", "position": [0.0, 0.0, 0.0]},
                            "end_b": {"attach": "free", "position": [0.0, 0.0, -5.0]}}},
            "analysis": {"dynamics": {"duration": 20.0}}}
    (w,) = startup_warnings(rfesim.Scenario.model_validate(data))
    # at 50 s the heave sine is at its crest (at rest) and the roll sine crosses zero
    assert w.startswith("vessels.ship.motion.ramp_duration: 0 s, so vessel 'ship' starts with the velocity its "
                        "motion table has at t = 0 (roll 1.26 deg/s)")
    data["vessels"]["ship"]["motion"]["start_time"] = 0.0
    (w,) = startup_warnings(rfesim.Scenario.model_validate(data))
    assert "(heave 0.392 m/s, roll 1.26 deg/s)" in w        # the natural spline's slope at its first row
    data["vessels"]["ship"]["motion"]["ramp_duration"] = 10.0
    assert startup_warnings(rfesim.Scenario.model_validate(data)) == []
    data["vessels"]["ship"]["motion"].update(ramp_duration=0.0, rows=[[t, 0, 0, 0.2, 0, 0, 0] for t in times])
    assert startup_warnings(rfesim.Scenario.model_validate(data)) == []          # held still


def test_a_wave_record_replayed_without_a_ramp_is_named_unless_it_starts_calm():
    """A recorded elevation (time-series waves) starts as the record has it at t = 0. A swell
    of 1 m amplitude at 10 s starts at full height: warned, with its mean period (10 s, the
    only component's) and 1 m. A focused group (Gaussian envelope of 10 s waves peaking
    at 150 s in a 300 s record) starts at 1e-10 of its crest: not warned; nor with a ramp."""
    import math
    t = np.arange(0.0, 300.0, 0.5)
    data = scenario("column_crane.json")
    swell = np.cos(2.0 * math.pi * t / 10.0)
    data["environment"]["water"]["waves"] = {"kind": "time-series", "rows": np.c_[t, swell].tolist()}
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert w.startswith("environment.water.waves.ramp_duration: 0 s, so the recorded waves (time-series) start as "
                        "the record has them at t = 0, up to 1 m over its first mean period (10 s; the record's "
                        "largest is 1 m), on the structure in its static equilibrium in still water")
    assert w.endswith("(ramp_duration 10 s), or start the record in calm water")
    data["environment"]["water"]["waves"]["ramp_duration"] = 10.0
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []
    group = np.exp(-((t - 150.0) / 30.0) ** 2) * np.cos(2.0 * math.pi * (t - 150.0) / 10.0)
    data["environment"]["water"]["waves"] = {"kind": "time-series", "rows": np.c_[t, group].tolist()}
    assert startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS)) == []
    # the same group shifted to peak at 10 s starts rough
    data["environment"]["water"]["waves"]["rows"] = np.c_[t, np.roll(group, -280)].tolist()
    (w,) = startup_warnings(rfesim.load_scenario(data, base_dir=SCENARIOS))
    assert "the recorded waves (time-series)" in w


# ---------------------------------------------------------------- drives faster than a crane's
def rate_warnings(data: dict) -> list[str]:
    from rfesim.scenario.motion_warnings import drive_rate_warnings
    return drive_rate_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))


@pytest.mark.parametrize("name", sorted(p.name for p in SCENARIOS.glob("*.json")))
def test_the_shipped_scenarios_drive_at_crane_rates(name):
    assert rate_warnings(scenario(name)) == []


def test_a_slewing_table_faster_than_a_crane_is_named_with_its_peak_rate():
    """Two rows, 360 deg in 2 s: the drive's cubic starts and stops at rest (zero end slopes),
    so it peaks in the middle at 1.5 times the mean 180 deg/s."""
    data = scenario("column_crane.json", duration=20.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [2.0, 440.0]]
    (w,) = rate_warnings(data)
    assert w.startswith("cranes.crane.slewing_deg: the angle table turns the slewing angle at up to 270 deg/s "
                        "(45 rpm) between t = 0 s and 2 s"), w
    assert "check the table's times (s) and angles (deg)" in w
    # a realistic slew, 180 deg in 90 s (peak 3 deg/s), and a fast one after the run's end: none
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [90.0, 260.0]]
    assert rate_warnings(data) == []
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [30.0, 80.0], [31.0, 440.0]]
    assert rate_warnings(data) == []
    data["analysis"]["dynamics"]["duration"] = 40.0
    assert len(rate_warnings(data)) == 1


def test_the_rate_is_the_largest_the_drive_kernel_gives():
    """Against the drive kernel (rfesim.loads.drives.drive_table) sampled finely through a
    table of five rows, with the compile step's slopes."""
    from rfesim.loads.drives import drive_table
    from rfesim.model.supports import drive_slopes
    rows = np.array([[0.0, 80.0], [3.0, 95.0], [4.0, 160.0], [4.5, 170.0], [10.0, 100.0]])
    data = scenario("column_crane.json", duration=20.0)
    data["cranes"]["crane"]["slewing_deg"] = rows.tolist()
    (w,) = rate_warnings(data)
    slopes = drive_slopes(rows[:, 0], rows[:, 1])
    ts = np.linspace(0.0, 10.0, 200001)
    rates = np.array([abs(drive_table(rows[:, 0], rows[:, 1], slopes, t)[1]) for t in ts])
    peak = float(rates.max())
    assert peak > 30.0
    named = float(w.split("at up to ")[1].split(" deg/s")[0])
    assert named == pytest.approx(peak, rel=2e-3), (named, peak)
    k = int(np.searchsorted(rows[:, 0], ts[int(rates.argmax())])) - 1
    assert f"between t = {rows[k, 0]:.6g} s and {rows[k + 1, 0]:.6g} s" in w


def test_an_a_frame_tilt_and_a_slewing_motor_are_named_in_their_fields():
    data = scenario("a_frame.json", duration=20.0)
    data["cranes"]["aframe"]["tilt_deg"] = [[0.0, -25.0], [1.0, 35.0]]
    (w,) = rate_warnings(data)
    assert w.startswith("cranes.aframe.tilt_deg: the angle table turns the tilt angle at up to 90 deg/s"), w
    data = scenario("column_crane_slewing_motor.json", duration=20.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [1.0, 20.0]]
    (w,) = rate_warnings(data)
    assert w.startswith("cranes.crane.slewing_deg: the angle table turns the slewing angle at up to 90 deg/s"), w


def test_check_shows_a_fast_drive_before_the_run(tmp_path, capsys):
    from rfesim.cli import main
    data = scenario("column_crane.json", duration=20.0)
    data["cranes"]["crane"]["slewing_deg"] = [[0.0, 80.0], [2.0, 440.0]]
    (tmp_path / "data").symlink_to(SCENARIOS / "data")
    path = tmp_path / "fast.json"
    path.write_text(json.dumps(data))
    main(["check", str(path)])
    out = capsys.readouterr()
    assert "cranes.crane.slewing_deg: the angle table turns the slewing angle at up to 270 deg/s" in out.out + out.err


# ---------------------------------------------------------------- harmonic motions no vessel makes
def vessel_warnings(data: dict) -> list[str]:
    from rfesim.scenario.motion_warnings import harmonic_vessel_warnings
    return harmonic_vessel_warnings(rfesim.load_scenario(copy.deepcopy(data), base_dir=SCENARIOS))


@pytest.mark.parametrize("name", sorted(p.name for p in SCENARIOS.glob("*.json")))
def test_the_shipped_vessels_move_as_vessels(name):
    assert vessel_warnings(scenario(name)) == []


def test_a_harmonic_motion_beyond_one_g_is_named_with_its_speed_and_acceleration():
    """20 m of sway at 0.5 s (a harness variant; the riser then ran at 235 m/s): 20 (4 pi)^2
    = 3158 m/s^2, speed 20 x 4 pi = 251.3 m/s."""
    data = scenario("catenary_riser.json")
    data["vessels"]["fpso"]["motion"] = {"kind": "harmonic", "sway": {"amplitude": 20.0, "period": 0.5},
                                         "heave": {"amplitude": 2.0, "period": 10.0}, "ramp_duration": 10.0}
    (w,) = vessel_warnings(data)
    assert w.startswith("vessels.fpso.motion.sway: 20 m at a period of 0.5 s moves vessel 'fpso' at up to 251.3 m/s "
                        "with 3158 m/s^2 (322 g)"), w
    # 1 g is the limit: at pi s (omega 2 rad/s) 2.45 m gives 9.80 m/s^2, 2.46 m 9.84
    data["vessels"]["fpso"]["motion"]["sway"] = {"amplitude": 2.45, "period": math.pi}
    assert vessel_warnings(data) == []
    data["vessels"]["fpso"]["motion"]["sway"] = {"amplitude": 2.46, "period": math.pi}
    assert len(vessel_warnings(data)) == 1


def test_a_roll_given_in_radians_at_a_short_period_is_named():
    data = scenario("catenary_riser.json")
    data["vessels"]["fpso"]["motion"] = {"kind": "harmonic", "roll": {"amplitude": 30.0, "period": 2.0},
                                         "ramp_duration": 10.0}
    (w,) = vessel_warnings(data)
    # 30 deg = 0.5236 rad; (pi)^2 x 0.5236 = 5.17 rad/s^2; 30 x pi = 94.25 deg/s
    assert w.startswith("vessels.fpso.motion.roll: 30 deg at a period of 2 s turns vessel 'fpso' at up to 94.25 deg/s "
                        "with 5.17 rad/s^2"), w
    assert "check the amplitude (deg, not rad)" in w
    data["vessels"]["fpso"]["motion"]["roll"] = {"amplitude": 30.0, "period": 10.0}    # 0.21 rad/s^2
    assert vessel_warnings(data) == []
