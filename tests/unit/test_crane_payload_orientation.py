"""A crane template's inline payload starts with its hook point straight under the sheave,
whatever its ``orientation_deg``: the body-frame ``payload_attachment`` is turned by the
body's ZYX rotation (rfesim.model.bodies.body_rotation) before the start position is set.
It used to be subtracted unturned, so a payload yawed 90 deg with the attachment [1, 0, 0.5]
started with its hook point 1.41 m off the sheave's vertical and statics failed."""
from __future__ import annotations

import math

import numpy as np

import rfesim
from rfesim.model.bodies import body_rotation
from rfesim.scenario import expand
from rfesim.scenario.bodies import Body

G = 9.81
LUFF = 40.0
TIP = np.array([20.0 * math.cos(math.radians(LUFF)), 0.0, 10.0 + 20.0 * math.sin(math.radians(LUFF))])


def column(orientation, attachment):
    tpl = {"type": "column", "position": [0.0, 0.0, 2.0],
           "pedestal": {"length": 8.0, "outer_diameter": 2.0, "wall_thickness": 0.04, "elements": 4},
           "boom": {"length": 20.0, "outer_diameter": 0.8, "wall_thickness": 0.02, "elements": 10},
           "slewing_deg": 0.0, "luffing_deg": LUFF, "rope": {"length": 10.0, "elements": 10},
           "payload": {"mass": 5000.0, "radius_of_gyration": 1.0, "orientation_deg": orientation},
           "payload_attachment": attachment}
    return {"environment": {"gravity": G}, "cranes": {"c": tpl},
            "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def hook_point(data):
    body = expand(data)["bodies"]["c_payload"]
    R = body_rotation(Body.model_validate(body))
    return np.asarray(body["position"]) + R @ np.asarray(data["cranes"]["c"]["payload_attachment"], float)


def test_rotated_payload_hook_point_starts_under_the_sheave():
    for orientation, attachment in (([0, 0, 90], [1.0, 0.0, 0.5]), ([0, 0, 30], [0.3, 0.0, 0.5]),
                                    ([10, -20, 45], [0.4, -0.2, 0.5])):
        hook = hook_point(column(orientation, attachment))
        np.testing.assert_allclose(hook, TIP - [0.0, 0.0, 10.0], atol=1e-9,
                                   err_msg=f"orientation {orientation}, attachment {attachment}")


def test_rotated_off_centre_payload_statics_converges():
    res = rfesim.statics(column([0, 0, 90], [1.0, 0.0, 0.5]))
    assert res.status == 0, res.message
    rope = np.asarray(res.line("c_rope").position)[0]
    # the rope hangs vertical from the sheave, the centre of mass under the hook point
    np.testing.assert_allclose(rope[-1, :2], rope[0, :2], atol=1e-4)
    np.testing.assert_allclose(np.asarray(res.bodies["c_payload"].position)[0, :2], rope[0, :2], atol=1e-4)
