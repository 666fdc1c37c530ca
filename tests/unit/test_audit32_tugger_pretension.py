"""An elastic tugger's pretension sets its unstretched length at the scenario's initial
positions; statics that moves the body changes its tension. The run says so (audit of
2026-12-06: a 10 kN tugger held 469 N after statics, with no word)."""
from __future__ import annotations

import rfesim


def crane_hook(pretension: float, stiffness: float, dynamics: bool = False) -> dict:
    """A 10 t load on a 20 m rope from a fixed ship, a tugger to a deck point 50 m off."""
    return {"environment": {"gravity": 9.81},
            "vessels": {"ship": {"motion": {"kind": "fixed"}}},
            "line_types": {"rope": {"outer_diameter": 0.036, "EA": 1e8, "EIy": 10.0, "EIz": 10.0, "GJ": 10.0,
                                    "mass_per_length": 5.0, "tension_only": True}},
            "lines": {"rope": {"type": "rope", "length": 20.0, "elements": 4,
                               "end_a": {"attach": "ship", "position": [0, 0, 10]},
                               "end_b": {"attach": "load", "position": [0, 0, 0]}}},
            "bodies": {"load": {"mass": 10000.0, "radius_of_gyration": 1.0}},
            "tuggers": {"tg": {"body": "load", "vessel": "ship", "deck_point": [50, 0, -10],
                               "mode": {"kind": "elastic", "stiffness": stiffness, "pretension": pretension}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": dynamics, "duration": 0.2 if dynamics else 0.0,
                                      "output_interval": 0.1,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}}}


def test_a_pretension_statics_undoes_is_warned():
    res = rfesim.statics(crane_hook(10_000.0, 1e5))
    held = float(res.tugger("tg").tension[0])
    assert held < 2_000.0                                  # the body swung toward the tugger: most is gone
    assert "tuggers.tg.mode.pretension" in res.message and "not its pretension 10 kN" in res.message
    res = rfesim.simulate(crane_hook(10_000.0, 1e5, dynamics=True))
    assert "tuggers.tg.mode.pretension" in res.message


def test_a_soft_tugger_keeps_its_pretension_unwarned():
    res = rfesim.statics(crane_hook(10_000.0, 1e3))      # 1e3 N/m: the swing changes it by < 20 %
    held = float(res.tugger("tg").tension[0])
    assert abs(held - 10_000.0) < 2_000.0
    assert "pretension" not in res.message
