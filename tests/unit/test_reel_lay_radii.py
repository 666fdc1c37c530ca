"""The reel-lay template starts (statics converges) for reel radii 8 to 13 m with its
default stored length. Before, statics failed at load factor 0 for radii 11 and 12 m (and
for stored lengths whose end A lay on the lower half of a larger drum): the stored pipe's
end lay between the planes through the tensioner's entry and exit, 21 m off its axis, and
the tensioner's pads pulled it towards the axis with 63 MN; the pads now hold only pipe
within 1 m of the axis (rfesim.loads.tensioner.TRACK_CAPTURE)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import rfesim

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def _statics(radius: float, stored: float | None = None):
    reel = {"radius": radius} if stored is None else {"radius": radius, "stored_length": stored}
    sc = rfesim.load_scenario(SCENARIOS / "reel_lay.json", overrides={
        "pipelay.lay.reel": reel, "analysis.dynamics.enabled": False,
        "vessels.reeler.motion": {"kind": "fixed"}})
    return sc, rfesim.statics(sc)


@pytest.mark.parametrize("radius", [8.0, 10.0, 11.0, 12.0, 13.0])
def test_reel_lay_statics_start_for_the_default_stored_length(radius):
    sc, res = _statics(radius)
    assert res.status == 0
    reel = sc.supports["lay_reel"]
    # the default: path (21.4 m) + the table's 7.5 m + two 2 m elements, at most half a turn less one element
    assert reel.stored_length == pytest.approx(min(32.88, math.pi * reel.radius - 2.0), abs=0.02)
    # the tensioner holds the catenary (about 170 kN), not pipe on the drum
    grip = float(np.asarray(res.tensioners["lay_tensioner"].grip_force)[0])
    assert 100e3 < grip < 250e3


def test_stored_end_on_the_lower_half_of_a_13_m_drum():
    """37.9 m on a 13 m drum: end A at 165 deg, 26 m below the tensioner's entry plane."""
    sc, res = _statics(13.0, 37.9)
    assert res.status == 0
