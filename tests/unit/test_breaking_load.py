"""Line types (and crane ropes) may give a minimum breaking load: a statics or dynamics whose
effective tension exceeds it says so in its message and log, with the peak, where and when,
and its multiple of the breaking load (seconds: a 5 t payload on a column crane, the
tiny riser)."""
from __future__ import annotations

import copy
import logging

import pytest

import rfesim
from scenes import RISER

G = 9.81


def _crane(breaking_load, duration=None):
    crane = {"type": "column", "position": [0.0, 0.0, 2.0],
             "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04, "elements": 4},
             "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02, "elements": 10},
             "slewing_deg": 0.0, "luffing_deg": 40.0,
             "rope": {"length": 10.0, "elements": 10, "breaking_load": breaking_load},
             "payload": {"mass": 5000.0, "radius_of_gyration": 1.0}}
    dyn = ({"duration": duration, "output_interval": 0.1,
            "integrator": {"kind": "generalized-alpha", "time_step": 0.01}} if duration else {"enabled": False})
    return {"environment": {"gravity": G}, "cranes": {"c": crane},
            "analysis": {"statics": {"enabled": True}, "dynamics": dyn}}


def test_a_crane_rope_past_its_breaking_load_is_warned_about(caplog):
    with caplog.at_level(logging.WARNING, logger="rfesim"):
        res = rfesim.statics(_crane(40e3))
    tension = float(res.line("c_rope").tension[0].max())
    # the rope at the sheave carries the 5 t payload and the rope below it
    assert 5000.0 * G < tension < 5000.0 * G + 10.0 * 10 * 4000 * 0.04 ** 2 * G
    want = (f"; statics warning: line 'c_rope' reaches {tension / 1e3:.6g} kN of tension at t = 0 s, 0.5 m "
            f"from end A: {tension / 40e3:.3g} times the breaking_load of its line type 'c_rope_section' (40 kN)")
    assert res.message.endswith(want)
    assert any("c_rope" in r.getMessage() and "breaking_load" in r.getMessage() for r in caplog.records)


def test_below_the_breaking_load_nothing_is_said():
    res = rfesim.statics(_crane(60e3))
    assert "breaking_load" not in res.message


def test_dynamics_report_the_peak_over_the_run():
    res = rfesim.simulate(_crane(40e3, duration=0.5))
    assert "; dynamics warning: line 'c_rope' reaches" in res.message
    tension = res.line("c_rope").tension
    peak = float(max(row.max() for row in tension))
    assert f"{peak / 1e3:.6g} kN" in res.message


def test_a_line_type_breaking_load():
    sc = copy.deepcopy(RISER)
    sc["analysis"].pop("dynamics")
    top = float(rfesim.statics(copy.deepcopy(sc)).line("riser").tension[0].max())
    sc["line_types"]["pipe"]["breaking_load"] = 0.5 * top
    res = rfesim.statics(sc)
    assert "line 'riser' reaches" in res.message and "2 times the breaking_load of its line type 'pipe'" in res.message


@pytest.mark.parametrize("value", [0.0, -1.0])
def test_a_breaking_load_must_be_positive(value):
    sc = copy.deepcopy(RISER)
    sc["line_types"]["pipe"]["breaking_load"] = value
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario(sc)
    assert "line_types.pipe.breaking_load" in str(info.value)
