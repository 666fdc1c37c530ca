"""Sea and vessel inputs the shipped scenarios do not use (audit of 2026-12-06): a vessel
motion table or CSV file that does not cover the run (start_time, warnings, errors), CSV
files written by spreadsheets, wave records in the wrong units, and what the time factor of a
current does not do."""
from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

import rfesim
from rfesim.scenario.schema import motion_table_warnings
from rfesim.vessel import make_vessel_motion
from scenes import RISER

CSV_ROWS = [[1000.0 + t, 0.05 * t, 0.0, 0.2 * math.sin(t), 0.0, 0.0, 0.0] for t in range(11)]


def csv_text(rows, sep=", "):
    return "t, surge, sway, heave, roll, pitch, yaw\n" + "\n".join(sep.join(f"{v:.12g}" for v in r) for r in rows)


def riser_with_csv(tmp_path, text, duration=1.0, **motion):
    (tmp_path / "motion.csv").write_text(text)
    data = copy.deepcopy(RISER)
    data["vessels"]["ship"]["motion"] = {"kind": "csv", "file": str(tmp_path / "motion.csv"),
                                         "interpolation": "linear", **motion}
    data["analysis"]["dynamics"]["duration"] = duration
    return data


def errors_of(data):
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario(data)
    return dict(info.value.errors)


# ----------------------------------------------------------------- motion tables and the run

def test_start_time_maps_the_files_times_onto_the_run(tmp_path):
    sc = rfesim.load_scenario(riser_with_csv(tmp_path, csv_text(CSV_ROWS), start_time=1000.0))
    motion = make_vessel_motion(sc.vessels["ship"])
    for t in (0.5, 2.5, 7.0):
        d, v, _ = motion.dofs(t)
        assert d[0] == pytest.approx(0.05 * t, abs=1e-12)                   # the row of time 1000 + t
        assert v[0] == pytest.approx(0.05, abs=1e-12)
    assert motion_table_warnings(sc) == []


def test_a_file_outside_the_run_is_refused_naming_start_time(tmp_path):
    errors = errors_of(riser_with_csv(tmp_path, csv_text(CSV_ROWS)))        # 1000-1010 s, run 0-1 s
    msg = errors["vessels.ship.motion.start_time"]
    assert "starts after the run ends" in msg and "1000" in msg
    errors = errors_of(riser_with_csv(tmp_path, csv_text(CSV_ROWS), start_time=2000.0))
    assert "ends before the run starts" in errors["vessels.ship.motion.start_time"]
    # statics alone takes the vessel where the table has it at t = 0: no check
    data = riser_with_csv(tmp_path, csv_text(CSV_ROWS))
    data["analysis"]["dynamics"]["enabled"] = False
    rfesim.load_scenario(data)


def test_a_table_ending_before_the_run_is_warned_in_the_results(tmp_path):
    rows = [[t, 0.0, 0.0, 0.1 * t, 0.0, 0.0, 0.0] for t in (10.0, 10.25, 10.5, 10.75)]
    data = copy.deepcopy(RISER)
    data["vessels"]["ship"]["motion"] = {"kind": "table", "rows": rows, "interpolation": "linear",
                                         "start_time": 10.0}
    sc = rfesim.load_scenario(data)
    (warning,) = motion_table_warnings(sc)
    assert "vessels.ship.motion.rows" in warning and "ends at t = 0.75 s" in warning and "stops dead" in warning
    res = rfesim.simulate(sc)
    assert "ends at t = 0.75 s" in res.message


def test_a_table_starting_late_is_warned(tmp_path):
    rows = [[t, 0.0, 0.0, 0.1 * t, 0.0, 0.0, 0.0] for t in (0.5, 1.0, 1.5)]
    data = copy.deepcopy(RISER)
    data["vessels"]["ship"]["motion"] = {"kind": "table", "rows": rows, "interpolation": "linear"}
    (warning,) = motion_table_warnings(rfesim.load_scenario(data))
    assert "starts at t = 0.5 s" in warning and "stands still at the first row" in warning


# ----------------------------------------------------------------- spreadsheet CSV files

def test_semicolons_and_trailing_separators_are_read(tmp_path):
    rows = [[float(t), 0.0, 0.25 * t, 0.0, 0.0, 0.0, 0.0] for t in range(4)]
    for text in (csv_text(rows, "; "), csv_text(rows).replace("\n", ",\n") + ","):
        sc = rfesim.load_scenario(riser_with_csv(tmp_path, text))
        assert np.array_equal(sc.vessels["ship"].motion.rows(), rows)


def test_a_decimal_comma_is_named(tmp_path):
    text = "t;surge;sway;heave;roll;pitch;yaw\n0;0;0;0;0;0;0\n1;0,5;0;0;0;0;0\n2;0;0;0;0;0;0\n3;0;0;0;0;0;0\n"
    msg = errors_of(riser_with_csv(tmp_path, text))["vessels.ship.motion.file"]
    assert "line 3" in msg and "decimal comma" in msg


# ----------------------------------------------------------------- wave records

def record(amplitude, period=12.6, dt=0.5, n=256):
    return [[i * dt, amplitude * math.sin(2.0 * math.pi * i * dt / period)] for i in range(n)]


def env_with_record(rows, depth=1000.0):
    return {"water": {"depth": depth, "waves": {"kind": "time-series", "rows": rows}}}


def record_errors(rows, depth=1000.0):
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario({"environment": env_with_record(rows, depth)})
    return dict(info.value.errors)


def test_a_record_in_millimetres_is_refused():
    errors = record_errors(record(750.0))                               # 1.5 m written in mm
    (field,) = errors
    assert field == "environment.water.waves.rows" and "breaking limit" in errors[field] and "units" in errors[field]
    rfesim.load_scenario({"environment": env_with_record(record(0.75))})      # in metres: fine


def test_a_record_deeper_than_the_water_is_refused():
    rows = [[i * 0.5, 0.0] for i in range(64)]
    rows[10][1] = -25.0
    errors = record_errors(rows, depth=20.0)
    assert "as large as the water depth" in errors["environment.water.waves.rows.10"]


# ----------------------------------------------------------------- current time factor

def test_schema_says_the_current_time_factor_is_not_differentiated():
    text = json.dumps(rfesim.scenario.schema.Current.model_json_schema())
    assert "dU/dt is not part of the water acceleration" in text
