"""Statics of a crane payload whose rope is attached off its centre line: the payload has to
turn to hang its centre of mass under the attachment point (rfesim.solvers.statics.hang_bodies).

Closed form: a rigid body on a pinned (shackle) connection hangs with its centre of mass
straight under the attachment point a (body axes), so the turn is the angle between a and
the vertical: atan(|a_horizontal| / a_z), 63.43 degrees for a = [0, 1, 0.5] (a roll about the
body's x axis) and [1, 0, 0.5] (a pitch). The yaw about the rope is free: it stays at the
given orientation (the smallest rotation that hangs the body)."""
import math

import numpy as np
import pytest

import rfesim

G = 9.81
TURN = math.degrees(math.atan2(1.0, 0.5))        # 63.435 deg


def _crane(attachment, orientation=(0.0, 0.0, 0.0)):
    payload = {"mass": 5000.0, "radius_of_gyration": 1.0, "orientation_deg": list(orientation)}
    return {"environment": {"gravity": G},
            "cranes": {"c": {"type": "column", "position": [0.0, 0.0, 2.0],
                             "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04,
                                          "elements": 4},
                             "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02,
                                      "elements": 10},
                             "slewing_deg": 0.0, "luffing_deg": 40.0, "rope": {"length": 10.0, "elements": 10},
                             "payload": payload, "payload_attachment": list(attachment)}},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def _hung(attachment, orientation=(0.0, 0.0, 0.0)):
    res = rfesim.statics(_crane(attachment, orientation))
    b = res.bodies["c_payload"]
    return np.asarray(b.rotation[0], float), np.asarray(b.position[0], float), res


@pytest.mark.parametrize("attachment, expected", [
    ([0.0, 1.0, 0.5], [TURN, 0.0, 0.0]),          # roll: failed at load factor 0 before
    ([1.0, 0.0, 0.5], [0.0, -TURN, 0.0]),         # pitch: in the crane's symmetry plane
    ([0.0, 0.3, 0.5], [math.degrees(math.atan2(0.3, 0.5)), 0.0, 0.0]),   # was yaw -115.8 deg
    ([0.0, 0.3, -0.5], [180.0 - math.degrees(math.atan2(0.3, 0.5)), 0.0, 0.0]),  # attachment below: upturned
])
def test_payload_hangs_at_the_closed_form_angle(attachment, expected):
    rot, _, _ = _hung(attachment)
    assert rot == pytest.approx(expected, abs=0.01)


def test_attachment_point_is_over_the_centre_of_mass():
    """The rope's end (the attachment point) is straight above the centre of mass."""
    rot, cog, res = _hung([0.0, 1.0, 0.5])
    from rfesim.kinematics import rot_zyx
    roll, pitch, yaw = np.radians(rot)
    P = cog + rot_zyx(yaw, pitch, roll) @ np.array([0.0, 1.0, 0.5])
    assert P[:2] == pytest.approx(cog[:2], abs=1e-6)
    assert P[2] - cog[2] == pytest.approx(math.hypot(1.0, 0.5), abs=1e-6)


def test_given_yaw_is_kept():
    """A payload turned 90 degrees about the vertical and attached along its x axis pitches
    to hang and keeps its yaw (was 89.66 deg with the template's position)."""
    rot, _, _ = _hung([1.0, 0.0, 0.5], orientation=(0.0, 0.0, 90.0))
    assert rot == pytest.approx([0.0, -TURN, 90.0], abs=0.01)
