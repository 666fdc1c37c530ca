"""Lines at the water surface: an RFE is wet in proportion to its immersed section
(rfesim.loads.hydro.submergence, docs/theory.md 'Wet fraction of an RFE at the surface').

Before, an RFE was wet along its axis only: a horizontal one lying at the surface was wholly
dry or wholly wet as its axis crossed it, so a floating line's buoyancy jumped and Newton could
not follow it (the H1 riser in water 2050 kg/m^3 floats; its run stopped at 9.09 s at every
step down to 0.01 s)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim

G = 9.81
RHO = 1025.0
D = 0.4                      # m, outer diameter
MASS = 90.0                  # kg/m: floats (it displaces 128.8 kg/m)
L = 10.0
SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def segment_fraction(u: float) -> float:
    """Share of a disc below a line u radii above its centre."""
    if u >= 1.0:
        return 0.0
    if u <= -1.0:
        return 1.0
    return (math.acos(u) - u * math.sqrt(1.0 - u * u)) / math.pi


def beam_at(h: float) -> dict:
    """A stiff 10 m beam pinned at both ends at its axis height h above the still surface."""
    return {"environment": {"gravity": G, "water": {"density": RHO, "depth": 50.0}},
            "line_types": {"beam": {"EA": 1e11, "EIy": 1e11, "mass_per_length": MASS, "outer_diameter": D}},
            "lines": {"b": {"type": "beam", "length": L, "elements": 10,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, h], "connection": "pinned"},
                            "end_b": {"attach": "fixed", "position": [L, 0.0, h], "connection": "pinned"}}},
            "analysis": {"statics": {"enabled": True}}}


@pytest.mark.parametrize("u", [-1.2, -0.6, -0.25, 0.0, 0.4, 0.9, 1.1])
def test_a_horizontal_beam_at_the_surface_is_carried_by_its_immersed_section(u):
    """The ends carry its weight less the buoyancy of the circular segment under the surface:
    (m - rho A phi(u)) g L, phi the segment's share (to 1e-5: the beam's deflection under the
    rest, 4e-7 m on average, moves its section against the surface)."""
    res = rfesim.statics(beam_at(u * 0.5 * D))
    line = res.line("b")
    lift = -(np.asarray(line.end_a_force[0])[2] + np.asarray(line.end_b_force[0])[2])
    expected = (MASS - RHO * math.pi * D * D / 4.0 * segment_fraction(u)) * G * L
    assert lift == pytest.approx(expected, rel=1e-5, abs=1e-5 * MASS * G * L)


def test_a_floating_riser_in_dense_water_runs_on():
    """scenarios/h1_riser_heave.json with its pipe at 5495 kg/m^3 in water of 2050 kg/m^3 (it
    floats at the surface over part of its length) and its heave at 0.7 m: 12 s at 0.02 s
    steps with no step halved."""
    d = json.loads((SCENARIOS / "h1_riser_heave.json").read_text())
    d["vessels"]["vessel"]["motion"]["heave"]["amplitude"] = 0.7
    d["line_types"]["steel_pipe"]["density"] = 5495.0
    d["environment"]["water"]["density"] = 2050.0
    d["analysis"]["dynamics"]["duration"] = 12.0
    d["analysis"]["dynamics"]["integrator"]["recovery_halvings"] = 0
    res = rfesim.simulate(rfesim.load_scenario(d, base_dir=SCENARIOS))
    assert res.message.startswith("finished")
    assert res.counters.get("step_halvings", 0) == 0
    z = np.asarray(res.line("riser").position)[:, :, 2]
    assert z.max() > -0.15 and z.max() < 0.15              # afloat, cut by the surface
