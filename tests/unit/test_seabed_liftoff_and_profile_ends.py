"""Seabed contact at lift-off and beyond a profile's rows (audit 7, suspicions).

* An RFE lifting off faster than the seabed spring unloads has its normal force clipped to
  zero by the damper; it kept its geometric contact length, so the touchdown output was
  placed on it although the seabed no longer pushed it (H1, 100 elements: 4 of 81 output
  times in 8 s, up to 0.23 m past the contact). It is now out of contact (contact length 0).
* A seabed profile was continued with its end slopes without limit, so ``[[0, -100],
  [100, -50]]`` put the seabed 50 m above the water at x = 300 m. It now holds its end
  depths; a sloped plane, which does reach the surface somewhere, is refused where the scene
  lies over the part above the water.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError
from rfesim.loads.seabed import seabed_height
from rfesim.model.compile import compile_scenario
from rfesim.solvers import dynamics

PIPE = {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2.07e11, "density": 7850.0}


@pytest.mark.parametrize("in_kernel", [True, False])
def test_the_touchdown_point_is_on_an_rfe_the_seabed_pushes(monkeypatch, in_kernel):
    """H1 (a riser from the seabed to a heaving fairlead, seabed damping ratio 4): at every
    output time the touchdown arc length lies on an RFE with a positive seabed force, in the
    compiled recorder (rfesim.solvers.recording.touchdown_into) and the Python one
    (rfesim.solvers.dynamics.touchdown). Before, at t = 6.9, 7.0, 7.8 and 7.9 s it lay on the
    RFE next to the last one pushed, whose force the damper had clipped to zero."""
    from rfesim.bench.h1 import h1_scenario
    sc = h1_scenario(100, {"kind": "generalized-alpha", "time_step": 0.05}, output_interval=0.1)
    data = sc.model_dump(mode="json", exclude_none=True)
    data["analysis"]["dynamics"]["duration"] = 8.0
    monkeypatch.setattr(dynamics.Recorder, "IN_KERNEL", in_kernel)
    res = rfesim.simulate(data)
    riser = res.line("riser")
    force = np.asarray(riser.seabed_force)
    td = np.asarray(riser.touchdown_arc_length)
    n = force.shape[1]                          # 101 RFEs: the end ones half as long
    length = np.full(n, 290.0 / (n - 1))
    length[[0, -1]] *= 0.5
    edges = np.concatenate([[0.0], np.cumsum(length)])
    assert np.isfinite(td).all()
    for k in range(len(res.time)):
        on = np.nonzero((edges[:-1] - 1e-9 <= td[k]) & (td[k] <= edges[1:] + 1e-9))[0]
        assert force[k, on].max() > 0.0, (res.time[k], td[k], on)
        # and no RFE nearer the fairlead (end B) than the touchdown point is pushed
        assert not (force[k, on.max() + 1:] > 0.0).any(), res.time[k]


def profile_scene(profile, a=(150.0, 0.0), b=(250.0, 0.0), z=None):
    """A pipe laid out between two pinned ends at the heights ``z`` (default: resting on a
    seabed at -50 m: its radius and the static sinkage of its weight on the spring)."""
    sc = {"environment": {"water": {"density": 1025.0}, "seabed": {"profile": profile, "normal_stiffness": 1e6}},
          "line_types": {"p": PIPE},
          "lines": {"L": {"type": "p", "length": 100.0, "elements": 10,
                          "end_a": {"attach": "fixed", "position": [a[0], a[1], z if z is not None else -49.85],
                                    "connection": "pinned"},
                          "end_b": {"attach": "fixed", "position": [b[0], b[1], z if z is not None else -49.85],
                                    "connection": "pinned"}}},
          "analysis": {"statics": {"enabled": True}}}
    return sc


def test_a_profile_holds_its_end_depths():
    sc = rfesim.load_scenario(profile_scene([[0.0, -100.0], [100.0, -50.0]]))
    env = sc.environment
    # continued with its end slope (1/2) the seabed was at z = +50 m at x = 300 m
    assert [env.seabed_z_at(x, 7.0) for x in (-500.0, 0.0, 50.0, 100.0, 300.0, 1e6)] == \
        [-100.0, -100.0, -75.0, -50.0, -50.0, -50.0]
    # the compiled seabed, as the contact kernel sees it: flat (zero gradient) beyond the rows
    km = compile_scenario(sc).km
    out = np.zeros(3)
    for x, z, g in ((-500.0, -100.0, 0.0), (50.0, -75.0, 0.5), (300.0, -50.0, 0.0), (1e7, -50.0, 0.0)):
        seabed_height(km.bed_s, km.bed_z, km.bed_dir, x, 3.0, out)
        assert out[0] == pytest.approx(z, abs=1e-12) and out[1] == pytest.approx(g, abs=1e-15) and out[2] == 0.0


def test_a_pipe_beyond_the_profile_rests_on_its_held_end_depth():
    """A pipe laid from x = 150 to 250 m, past the last row at x = 100 m, rests on the seabed
    at -50 m: its axis at -50 + 0.15 (radius) - w / k (sinkage, w its submerged weight per
    length) everywhere. Before, the seabed there rose to 25 m above the water and the ends
    were refused as below it."""
    area = math.pi / 4.0 * (0.3 ** 2 - 0.26 ** 2)
    w = (7850.0 * area - 1025.0 * math.pi / 4.0 * 0.3 ** 2) * 9.81       # 644 N/m
    rest = -50.0 + 0.15 - w / 1e6
    res = rfesim.statics(profile_scene([[0.0, -100.0], [100.0, -50.0]], z=rest))
    line = res.lines["L"]
    z = np.asarray(line.position)[0][:, 2]
    np.testing.assert_allclose(z, rest, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(line.seabed_force)[0][1:-1] / 10.0, w, rtol=1e-6)


def test_a_sloped_plane_above_the_water_under_the_scene_is_refused():
    """A plane 100 m deep at the origin rising 10 deg along +x reaches the surface at
    x = 100 / tan 10 deg = 567.128 m; a pipe from (450, 0, -10) to (650, 0, 40) lies over it
    beyond (it would lie on a beach in the air)."""
    def sc(b, a=(450.0, 0.0, -10.0)):
        return {"environment": {"water": {"density": 1025.0}, "seabed": {"z": -100.0, "slope_deg": 10.0}},
                "line_types": {"p": PIPE},
                "lines": {"L": {"type": "p", "length": 210.0, "elements": 10,
                                "end_a": {"attach": "fixed", "position": list(a)},
                                "end_b": {"attach": "fixed", "position": b}}}}
    with pytest.raises(ScenarioError) as info:
        compile_scenario(rfesim.load_scenario(sc([650.0, 0.0, 40.0])))
    (field, reason), = info.value.errors
    assert field == "environment.seabed.slope_deg"
    assert reason.startswith("the plane seabed sloping 10 deg reaches the water surface (z = 0 m) 567.128 m from "
                             "the global origin along slope_direction_deg (0 deg) and continues above it, and the "
                             "start shape of line 'L' lies over it there")
    # a pipe short of the shore line (the seabed at -11.84 m under its far end) is fine
    compile_scenario(rfesim.load_scenario(sc([500.0, 0.0, -10.0], a=(300.0, 0.0, -10.0))))
    # and so is a profile of the same slope out to x = 500 m, flat beyond at -11.84 m
    g = math.tan(math.radians(10.0))
    prof = {"profile": [[0.0, -100.0], [500.0, -100.0 + 500.0 * g]]}
    data = sc([650.0, 0.0, 40.0])
    data["environment"]["seabed"] = prof
    compile_scenario(rfesim.load_scenario(data))
