"""Roller contact kernel (rfesim.loads.rollers) against the readable reference on random
geometries, the search from hints, friction stick/slip, and the closest points of two
segments against a brute-force grid."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
import rollers_reference as rref
from rfesim.loads.rollers import CONTACT_ONSET, commit_roller_friction, roller_forces, segment_closest_points

SEEDS = [0, 1, 2, 3, 4, 5]


def frame_from_tangent(t, rng):
    t = t / np.linalg.norm(t)
    y = np.cross(rng.normal(size=3), t)
    y /= np.linalg.norm(y)
    return np.column_stack([t, y, np.cross(t, y)])


def random_chain(rng, n):
    """RFEs along a smooth random space curve (a line of n RFEs), with random velocities."""
    s = np.linspace(0.0, 1.0, 4001)
    k = rng.uniform(0.2, 0.6, size=3)
    ph = rng.uniform(0, 2 * np.pi, size=3)
    curve = np.column_stack([20.0 * s, 3.0 * np.sin(2 * np.pi * k[0] * s + ph[0]),
                             4.0 * np.sin(2 * np.pi * k[1] * s + ph[1]) + 2.0 * s * s])
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(curve, axis=0), axis=1))])
    joints = np.column_stack([np.interp(np.linspace(0, arc[-1], n + 1), arc, curve[:, m]) for m in range(3)])
    # small gaps and kinks at the joints, like RFEs meeting at SDEs
    joints += rng.normal(scale=1e-3, size=joints.shape)
    e = np.diff(joints, axis=0)
    length = np.linalg.norm(e, axis=1)
    R = np.array([frame_from_tangent(ei, rng) for ei in e])
    r = 0.5 * (joints[:-1] + joints[1:])
    v = rng.normal(scale=0.5, size=(n, 3))
    w = rng.normal(scale=0.3, size=(n, 3))
    return length, R, r, v, w


def random_attachments(rng):
    p = np.vstack([np.zeros(3), rng.normal(scale=5.0, size=3)])
    R = np.stack([np.eye(3), ref.random_rotation(rng)])
    v = np.vstack([np.zeros(3), rng.normal(size=3)])
    w = np.vstack([np.zeros(3), rng.normal(scale=0.1, size=3)])
    return p, R, v, w


def random_rollers(rng, length, R, r, radius, att, nr):
    """Rollers near random points of the chain, axes across it, some penetrating and some
    clear; given in the frame of a random attachment."""
    n = length.shape[0]
    out = {k: [] for k in ("attach", "point", "axis", "half_width", "radius")}
    for _ in range(nr):
        i = int(rng.integers(1, n - 1))
        s = rng.uniform(-0.5, 0.5) * length[i]
        t = R[i][:, 0]
        normal = R[i] @ np.array([0.0, np.cos(th := rng.uniform(0, 2 * np.pi)), np.sin(th)])
        axis = np.cross(t, normal) + rng.normal(scale=0.3) * t
        axis /= np.linalg.norm(axis)
        rho = rng.uniform(0.05, 0.3)
        gap = rng.uniform(-0.05, 0.02)            # < 0: penetration
        centre = r[i] + s * t - (radius[i] + rho + gap) * normal + rng.uniform(-0.2, 0.2) * axis
        a_idx = int(rng.integers(0, 2))
        out["attach"].append(a_idx)
        out["point"].append(att[1][a_idx].T @ (centre - att[0][a_idx]))
        out["axis"].append(att[1][a_idx].T @ axis)
        out["half_width"].append(rng.uniform(0.1, 0.4))
        out["radius"].append(rho)
    return (np.array(out["attach"], np.int64), np.array(out["point"]), np.array(out["axis"]),
            np.array(out["half_width"]), np.array(out["radius"]))


def run_kernel(args, hint, anchor, anchored, mode, onset=None):
    """The kernel on a case; ``onset`` (nr,) the contact onset depths, by default
    CONTACT_ONSET (pipe + roller radius) as rfesim.model.supports sets them."""
    (attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, att, R, r, v, w) = args
    n = r.shape[0]
    nr = attach.shape[0]
    if onset is None:
        onset = CONTACT_ONSET * (radius[0] + rho)      # the cases have one pipe radius
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    force = np.zeros((nr, 3))
    normal = np.zeros(nr)
    at = np.zeros(nr)
    adt = np.zeros(nr, np.int64)
    roller_forces(attach, point, axis, hw, rho, k, c, mu, kt, onset, lo, hi, length, radius, att[0], att[1], att[2],
                  att[3], R, r, v, w, F, M, hint, force, normal, anchor, anchored, at, adt,
                  np.array([mode], np.int64), np.zeros(32))
    return F, M, force, normal, at, adt


def make_case(seed, nr=12, n=30):
    rng = np.random.default_rng(seed)
    length, R, r, v, w = random_chain(rng, n)
    radius = np.full(n, rng.uniform(0.1, 0.3))
    att = random_attachments(rng)
    attach, point, axis, hw, rho = random_rollers(rng, length, R, r, radius, att, nr)
    k = rng.uniform(1e4, 1e6, size=nr)
    c = rng.uniform(0.0, 1e3, size=nr)
    mu = rng.uniform(0.0, 0.5, size=nr)
    mu[0] = 0.0
    kt = rng.uniform(1e4, 1e6, size=nr)
    lo = np.zeros(nr, np.int64)
    hi = np.full(nr, n, np.int64)
    return rng, (attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, att, R, r, v, w)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("mode", [0, 2])
def test_kernel_matches_reference(seed, mode):
    rng, args = make_case(seed)
    nr = args[0].shape[0]
    anchor = rng.uniform(-0.3, 0.3, size=nr)
    anchored = rng.integers(0, 2, size=nr).astype(np.int64)
    hint = np.full(nr, -1, np.int64)
    F, M, force, normal, at, adt = run_kernel(args, hint, anchor, anchored, mode)
    (attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, att, R, r, v, w) = args
    Fr, Mr, force_r, normal_r, at_r, adt_r = rref.roller_forces(
        attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, *att, R, r, v, w, anchor, anchored, mode)
    assert (normal_r > 0).sum() >= 3, "the random case should have several contacts"
    scale = max(np.abs(Fr).max(), 1.0)
    np.testing.assert_allclose(F, Fr, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(M, Mr, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(force, force_r, rtol=0, atol=1e-11 * scale)
    np.testing.assert_allclose(normal, normal_r, rtol=0, atol=1e-11 * scale)
    np.testing.assert_array_equal(adt, adt_r)
    np.testing.assert_allclose(at[adt == 1], at_r[adt_r == 1], rtol=0, atol=1e-12)
    # action and reaction: the rollers feel exactly minus what the RFEs feel
    np.testing.assert_allclose(F.sum(axis=0), -force.sum(axis=0), rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("seed", SEEDS[:3])
def test_search_from_any_hint_finds_the_same_contacts(seed):
    rng, args = make_case(seed)
    nr = args[0].shape[0]
    n = args[15].shape[0]
    anchor = np.zeros(nr)
    anchored = np.zeros(nr, np.int64)
    hint = np.full(nr, -1, np.int64)
    F0, M0, *_ = run_kernel(args, hint, anchor, anchored, 2)
    nearest = hint.copy()
    for _ in range(3):
        # a stale hint a few RFEs off, as after the pipe slid along the rollers
        hint = np.clip(nearest + rng.integers(-3, 4, size=nr), 0, n - 1).astype(np.int64)
        F1, M1, *_ = run_kernel(args, hint, anchor, anchored, 2)
        np.testing.assert_array_equal(F1, F0)
        np.testing.assert_array_equal(M1, M0)
        np.testing.assert_array_equal(hint, nearest)


def test_rollers_only_see_their_own_line():
    rng, args = make_case(7, nr=6, n=30)
    args = list(args)
    args[9] = np.full(6, 15, np.int64)       # rollers belong to RFEs 15..29 only
    hint = np.full(6, -1, np.int64)
    F, M, force, normal, *_ = run_kernel(tuple(args), hint, np.zeros(6), np.zeros(6, np.int64), 2)
    assert np.all(F[:15] == 0.0)
    assert np.all(hint >= 15)
    (attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, att, R, r, v, w) = args
    Fr, *_ = rref.roller_forces(attach, point, axis, hw, rho, k, c, mu, kt, lo, hi, length, radius, *att, R, r,
                                v, w, np.zeros(6), np.zeros(6, np.int64), 2)
    np.testing.assert_allclose(F, Fr, rtol=0, atol=1e-11 * max(np.abs(Fr).max(), 1.0))


@pytest.mark.parametrize("seed", SEEDS)
def test_segment_closest_points_against_a_grid(seed):
    rng = np.random.default_rng(seed)
    out = np.zeros(2)
    for _ in range(20):
        c, p = rng.normal(size=3), rng.normal(size=3)
        t, a = rng.normal(size=3), rng.normal(size=3)
        t /= np.linalg.norm(t)
        a /= np.linalg.norm(a)
        h, b = rng.uniform(0.1, 2.0, size=2)
        segment_closest_points(*c, *t, h, *p, *a, b, out)
        d_kernel = np.linalg.norm(c + out[0] * t - p - out[1] * a)
        ss, uu = np.meshgrid(np.linspace(-h, h, 401), np.linspace(-b, b, 401), indexing="ij")
        pts = c + ss[..., None] * t - p - uu[..., None] * a
        d_grid = np.linalg.norm(pts, axis=-1).min()
        assert d_kernel <= d_grid + 1e-12
        assert d_kernel >= d_grid - 2.0 * (h + b) / 400.0
        s_ref, u_ref = rref.closest_points(c, t, h, p, a, b)
        assert out[0] == pytest.approx(s_ref, abs=1e-9) and out[1] == pytest.approx(u_ref, abs=1e-9)


# normal force of flat_roller_case: k (penetration - onset / 2), beyond the smooth onset
FLAT_PRESS = 1e6 * (0.01 - 0.5 * CONTACT_ONSET * (0.15 + 0.1))


def flat_roller_case(mu, k=1e6, kt=1e6):
    """One RFE lying across one fixed roller (axis along y), pressed by 1 cm."""
    att = (np.zeros((1, 3)), np.eye(3)[None], np.zeros((1, 3)), np.zeros((1, 3)))
    length = np.array([2.0])
    radius = np.array([0.15])
    R = np.eye(3)[None].copy()
    r = np.array([[0.0, 0.0, 0.15 + 0.1 - 0.01]])
    args = [np.zeros(1, np.int64), np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.array([0.5]),
            np.array([0.1]), np.array([k]), np.array([0.0]), np.array([mu]), np.array([kt]),
            np.zeros(1, np.int64), np.ones(1, np.int64), length, radius, att, R, r, np.zeros((1, 3)),
            np.zeros((1, 3))]
    return args


def test_friction_sticks_then_slips_along_the_axis_only():
    args = flat_roller_case(mu=0.3)
    hint = np.full(1, -1, np.int64)
    anchor = np.zeros(1)
    anchored = np.zeros(1, np.int64)
    F, M, force, normal, at, adt = run_kernel(tuple(args), hint, anchor, anchored, 0)
    assert normal[0] == pytest.approx(FLAT_PRESS, rel=1e-12)       # k (penetration - onset / 2)
    assert F[0] == pytest.approx([0.0, 0.0, FLAT_PRESS], abs=1e-9)   # first touch: no friction yet
    commit_roller_friction(anchor, anchored, at, adt)
    assert anchored[0] == 1 and anchor[0] == pytest.approx(0.0, abs=1e-15)
    # slide 1 mm sideways (along the roller axis): stick spring kt * 1e-3 = 1000 N < mu N = 2812.5 N
    args[15] = args[15] + np.array([[0.0, 1e-3, 0.0]])
    F, M, force, normal, at, adt = run_kernel(tuple(args), hint, anchor, anchored, 0)
    assert F[0, 1] == pytest.approx(-1000.0, rel=1e-9)
    assert at[0] == pytest.approx(0.0, abs=1e-15)                    # sticking: the anchor stays
    # slide 1 cm: the force is capped at mu N and the anchor follows the pipe
    args[15] = args[15] + np.array([[0.0, 9e-3, 0.0]])
    F, M, force, normal, at, adt = run_kernel(tuple(args), hint, anchor, anchored, 0)
    assert F[0, 1] == pytest.approx(-0.3 * FLAT_PRESS, rel=1e-12)
    assert at[0] == pytest.approx(0.01 - 0.3 * FLAT_PRESS / 1e6, rel=1e-12)
    # moving along the pipe (the roller turns): no friction at all
    args[15] = args[15] + np.array([[0.5, 0.0, 0.0]])
    F2, *_ = run_kernel(tuple(args), hint, anchor, anchored, 0)
    assert F2[0, 0] == 0.0
    # statics (mode 2): no friction, anchors unset
    F3, M3, force3, normal3, at3, adt3 = run_kernel(tuple(args), hint, anchor, anchored, 2)
    assert abs(F3[0, 1]) < 1e-9 and adt3[0] == 0


def test_damping_acts_only_while_pressed_and_never_pulls():
    args = flat_roller_case(mu=0.0)
    args[6] = np.array([2e5])
    hint = np.full(1, -1, np.int64)
    z = (np.zeros(1), np.zeros(1, np.int64))
    args[16] = np.array([[0.0, 0.0, -0.02]])     # moving into the roller: stiffer
    F, *_ = run_kernel(tuple(args), hint, *z, 2)
    assert F[0, 2] == pytest.approx(FLAT_PRESS + 2e5 * 0.02, rel=1e-12)
    args[16] = np.array([[0.0, 0.0, 0.2]])       # leaving fast: the force would be tensile, it is zero
    F, M, force, normal, *_ = run_kernel(tuple(args), hint, *z, 2)
    assert F[0, 2] == 0.0 and normal[0] == 0.0


def _support_errors(support, lines=True):
    import rfesim
    sc = {"line_types": {"p": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2e11,
                               "density": 7850}},
          "lines": {"pipe": {"type": "p", "length": 10, "elements": 5,
                             "end_a": {"attach": "fixed", "position": [0, 0, 0]}}} if lines else {},
          "supports": {"s": support}}
    with pytest.raises(rfesim.ScenarioError) as err:
        rfesim.Scenario.model_validate(sc)
    return str(err.value)


@pytest.mark.parametrize("support, field, words", [
    ({"kind": "rollers", "line": "nope", "stiffness": 1e6,
      "rollers": [{"position": [0, 0, 0], "axis": [0, 1, 0], "width": 0.5}]}, "supports.s.line", "unknown line"),
    ({"kind": "rollers", "line": "pipe", "attach": "boat", "stiffness": 1e6,
      "rollers": [{"position": [0, 0, 0], "axis": [0, 1, 0], "width": 0.5}]}, "supports.s.attach",
     "unknown attachment"),
    ({"kind": "rollers", "line": "pipe", "stiffness": 1e6,
      "rollers": [{"position": [0, 0, 0], "axis": [0, 0, 0], "width": 0.5}]}, "supports.s.rollers.0.axis",
     "zero vector"),
    ({"kind": "rollers", "line": "pipe", "stiffness": 0.0,
      "rollers": [{"position": [0, 0, 0], "axis": [0, 1, 0], "width": 0.5}]}, "supports.s.stiffness", ""),
    ({"kind": "stinger", "line": "pipe", "stiffness": 1e6, "start": [0, 0, 0], "direction": [0, 0, -1],
      "radius": 50, "length": 20, "spacing": 4, "roller_width": 0.5}, "supports.s.direction", "vertical"),
    ({"kind": "stinger", "line": "pipe", "stiffness": 1e6, "start": [0, 0, 0], "direction": [1, 0, 0],
      "radius": 50, "length": 20, "spacing": 40, "roller_width": 0.5}, "supports.s.spacing", "longer"),
])
def test_support_errors_name_the_field(support, field, words):
    text = _support_errors(support)
    assert field in text and words in text


def test_stinger_stations_lie_on_the_arc():
    from rfesim.model.supports import roller_set
    import rfesim
    sc = rfesim.Scenario.model_validate({
        "line_types": {"p": {"outer_diameter": 0.3, "wall_thickness": 0.02, "youngs_modulus": 2e11, "density": 7850}},
        "lines": {"pipe": {"type": "p", "length": 10, "elements": 5, "end_a": {"attach": "fixed",
                                                                                "position": [0, 0, 0]}}},
        "supports": {"s": {"kind": "stinger", "line": "pipe", "stiffness": 1e6, "start": [1, 2, 3],
                           "direction": [0, 2, 0], "radius": 40, "length": 30, "spacing": 5, "roller_width": 0.6,
                           "v_angle_deg": 30}}})
    rs = roller_set(sc.supports["s"])
    assert rs.point.shape == (14, 3)                        # 7 stations x 2 halves of a V
    centre = np.array([1.0, 2.0, 3.0 - 40.0])               # the arc bends down from +y
    np.testing.assert_allclose(np.linalg.norm(rs.guide - centre, axis=1), 40.0, rtol=1e-12)
    np.testing.assert_allclose(rs.guide[-1], [1.0, 2.0 + 40 * np.sin(0.75), 3.0 - 40 * (1 - np.cos(0.75))],
                               rtol=1e-12)
    # V halves rise 30 deg from the cross direction (x), start at the V bottom
    np.testing.assert_allclose(np.abs(rs.axis[0]), [np.cos(np.radians(30)), 0.0, np.sin(np.radians(30))],
                               atol=1e-12)
    np.testing.assert_allclose(rs.point[0] - 0.3 * rs.axis[0], rs.guide[0], atol=1e-12)
