"""A drive table from t >= 0 starts at rest (rfesim.model.supports.drive_slopes): the angle's
rate is 0 at its first row, as before it and as the structure's at the start of the run, so a
table whose first segment already moves does not start the structure with a rate jump. Its
last row keeps PCHIP's slope (a table ending while moving stops dead, as it says)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

import rfesim
from rfesim.loads.drives import drive_table
from rfesim.model.supports import drive_slopes
from rfesim.scenario.cranes import _initial

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
TILT = [[0.0, -25.0], [3.5, -37.5], [35.0, 35.0], [40.0, 35.0]]


def test_end_slopes_are_zero_and_the_inside_is_pchip():
    t, d = np.array(TILT).T
    v = drive_slopes(t, d)
    pchip = PchipInterpolator(t, d).derivative()(t)
    assert pchip[0] == pytest.approx(-4.15873, rel=1e-5)      # PCHIP's own: a rate jump at t = 0
    assert v[0] == 0.0
    np.testing.assert_array_equal(v[1:], pchip[1:])
    # a table begun before t = 0 keeps PCHIP's first slope: it is moving at t = 0 anyway
    early = drive_slopes(t - 1.0, d)
    np.testing.assert_array_equal(early, pchip)


@pytest.mark.parametrize("rows", [TILT, [[0.0, 0.0], [10.0, 90.0], [20.0, 180.0]],
                                  [[-5.0, 10.0], [0.0, 20.0], [5.0, 25.0], [7.0, 60.0], [9.0, 61.0]]])
def test_the_hermite_passes_the_rows_stays_monotone_and_its_rate_is_continuous(rows):
    t, d = np.array(rows, float).T
    v = drive_slopes(t, d)
    for ti, di in zip(t, d):
        assert drive_table(t, d, v, ti)[0] == pytest.approx(di, abs=1e-12)
    # no overshoot between rows
    ts = np.linspace(t[0], t[-1], 4001)
    vals = np.array([drive_table(t, d, v, x)[0] for x in ts])
    for k in range(len(t) - 1):
        seg = vals[(ts >= t[k]) & (ts <= t[k + 1])]
        assert seg.min() >= min(d[k], d[k + 1]) - 1e-9 and seg.max() <= max(d[k], d[k + 1]) + 1e-9
    # from t >= 0, the rate is 0 just inside the first row, as before it
    if t[0] >= 0.0:
        x = t[0] + 1e-7 * (t[-1] - t[0])
        assert abs(drive_table(t, d, v, x)[1]) < 1e-4 * np.abs(np.diff(d) / np.diff(t)).max()


def test_the_start_angle_of_a_crane_table_begun_before_t0_is_the_drives():
    rows = [[-5.0, 10.0], [0.0, 20.0], [5.0, 25.0], [7.0, 60.0], [9.0, 61.0]]
    rows_mid = [[-5.0, 10.0], [2.0, 20.0], [5.0, 25.0], [7.0, 60.0]]
    rows_late = [[1.0, 10.0], [2.0, 20.0], [5.0, 25.0], [7.0, 60.0]]
    assert _initial(rows_late) == 10.0
    for r in (rows, rows_mid):
        t, d = np.array(r).T
        assert _initial(r) == pytest.approx(float(drive_table(t, d, drive_slopes(t, d), 0.0)[0]), abs=1e-12)
    assert _initial(rows) == 20.0


def test_an_a_frame_tilt_table_that_moves_from_t0_runs():
    """The A-frame's tilt from -25 deg at t = 0 to -37.5 deg at 3.5 s: with PCHIP's end slope
    (-4.16 deg/s at once) its rope went slack and the run failed at 0.106 s."""
    d = json.loads((SCENARIOS / "a_frame.json").read_text())
    d["cranes"]["aframe"]["tilt_deg"] = TILT
    d["analysis"]["dynamics"]["duration"] = 6.0
    d["analysis"]["dynamics"]["integrator"]["recovery_halvings"] = 0
    res = rfesim.simulate(rfesim.load_scenario(d, base_dir=SCENARIOS))
    assert res.message.startswith("finished")
    assert float(res.time[-1]) == pytest.approx(6.0)
