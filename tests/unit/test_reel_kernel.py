"""The reel kernel (rfesim.loads.reel) against a readable reference: unilateral radial
contact with the drum, lateral hold in the drum plane, tangential grip spring-slider
against anchors turning with the drum, capacity, the taper over the wrap window; the
residual-curvature kernel (rfesim.materials.residual_curvature) against the fibre model;
the straightener's roller geometry and schema errors."""
from __future__ import annotations

import math

import numpy as np
import pytest

from rfesim.loads.reel import reel_forces
from rfesim.loads.tensioner import MODE_TABLE


def reference_reel(C, a, d, R, W, kr, kl, kg, cap, D, lengths, r, anchor, gripped):
    """Per RFE: force, trial anchor, gripped flag; and the reel's tangential force (module text)."""
    n0 = np.cross(a, d)
    n = r.shape[0]
    held = 0.0                     # the capacity is the drum's: shared by l w / sum(l w) on the wrap
    for i in range(n):
        rel = r[i] - C
        radial = rel - (rel @ a) * a
        e_r = radial / np.linalg.norm(radial)
        phi = math.atan2(-(e_r @ d), e_r @ n0)
        if phi < -math.pi / 2:
            phi += 2 * math.pi
        weight = min(1.0, R * phi / lengths[i], R * (W - phi) / lengths[i])
        if 0.0 <= phi <= W and weight > 0.0:
            held += lengths[i] * weight
    F = np.zeros((n, 3))
    new_anchor = np.array(anchor, float)
    on = np.zeros(n, int)
    total = 0.0
    for i in range(n):
        rel = r[i] - C
        h = rel @ a
        radial = rel - h * a
        rho = np.linalg.norm(radial)
        e_r = radial / rho
        phi = math.atan2(-(e_r @ d), e_r @ n0)           # wrap angle, back from the take-off
        if phi < -math.pi / 2:
            phi += 2 * math.pi
        l = lengths[i]
        weight = min(1.0, R * phi / l, R * (W - phi) / l)
        if not 0.0 <= phi <= W or weight <= 0.0:
            continue
        penetration = R * math.cos(l / (2 * R)) - rho    # the centre of a chord of length l on the drum
        if penetration > 0:
            F[i] += kr * l * weight * penetration * e_r
        F[i] -= kl * l * weight * h * a
        sigma = -R * phi                                  # material coordinate along the payout
        tangent = math.cos(phi) * d + math.sin(phi) * n0
        if gripped[i]:
            limit = cap * l * weight / held
            f = float(np.clip(-kg * l * weight * (sigma - anchor[i] - D), -limit, limit))
            new_anchor[i] = sigma - D + f / (kg * l * weight)
        else:
            f = 0.0
            new_anchor[i] = sigma - D
        on[i] = 1
        F[i] += f * tangent
        total -= f
    return F, new_anchor, on, total


def run_kernel(C, a, d, R, W, kr, kl, kg, cap, table_t, table_d, t, lengths, r, anchor, gripped, att_R, att_p,
               att=0):
    n = r.shape[0]
    F = np.zeros((n, 3))
    at = np.full(n, np.nan)
    ont = np.full(n, -1, np.int64)
    force = np.zeros(1)
    reel_forces(np.array([att]), np.array([C]), np.array([a]), np.array([d]), np.array([R]), np.array([W]),
                np.array([kr]), np.array([kl]), np.array([kg]), np.array([cap]), np.array([0]), np.array([n]),
                np.array([MODE_TABLE]), np.array([table_t]), np.array([table_d]),
                np.array([np.gradient(table_d, table_t)]), np.array([len(table_t)]), t, att_p, att_R, lengths, r, F,
                np.asarray(anchor, float), np.asarray(gripped, np.int64), at, ont, np.zeros(1), force, np.zeros(1),
                np.zeros(1), np.ones(1), np.zeros(1), 0.0, np.zeros(1), np.zeros(1))
    return F, at, ont, force[0]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_reel_kernel_against_reference(seed):
    rng = np.random.default_rng(seed)
    n = 40
    a = rng.normal(size=3)
    a /= np.linalg.norm(a)
    d = rng.normal(size=3)
    d -= (d @ a) * a
    d /= np.linalg.norm(d)
    n0 = np.cross(a, d)
    C = rng.normal(size=3)
    R, W = 5.0, math.radians(200.0)
    # RFE centres around the whole circle (some off the window), in and out of contact, off the plane
    phi = np.linspace(-0.6, W + 0.6, n)
    rho = R * (1.0 + rng.normal(scale=0.003, size=n))
    h = rng.normal(scale=0.01, size=n)
    r = C + rho[:, None] * (np.cos(phi)[:, None] * n0 - np.sin(phi)[:, None] * d) + h[:, None] * a
    lengths = rng.uniform(0.3, 0.7, size=n)
    table_t, table_d = np.array([0.0, 10.0, 20.0]), np.array([0.0, 4.0, 4.0])
    D = 4.0
    gripped = rng.integers(0, 2, size=n)
    anchor = -R * phi - D + rng.normal(scale=0.002, size=n)
    anchor[::4] += rng.normal(scale=1.0, size=anchor[::4].shape)    # these slip
    kr, kl, kg, cap = 3e7, 2e6, 5e6, 4e5
    # the drum on a vessel: turned and shifted; the kernel takes the attachment-frame data
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    Q *= np.sign(np.linalg.det(Q))
    p = rng.normal(size=3)
    att_R = np.stack([np.eye(3), Q])
    att_p = np.stack([np.zeros(3), p])
    F, at, ont, force = run_kernel(Q.T @ (C - p), Q.T @ a, Q.T @ d, R, W, kr, kl, kg, cap, table_t, table_d, 25.0,
                                   lengths, r, anchor, gripped, att_R, att_p, att=1)
    Fr, ar, onr, total = reference_reel(C, a, d, R, W, kr, kl, kg, cap, D, lengths, r, anchor, gripped)
    np.testing.assert_allclose(F, Fr, rtol=1e-9, atol=1e-6)
    np.testing.assert_array_equal(ont, onr)
    inside = onr == 1
    np.testing.assert_allclose(at[inside], ar[inside], rtol=0, atol=1e-10)
    assert force == pytest.approx(total, rel=1e-9, abs=1e-6 * cap)
    assert 0 < inside.sum() < n                                        # some on the window, some off it
    # unilateral: RFEs pressed into the drum are pushed out, those off it are not pulled in
    rel = r - C
    radial = rel - (rel @ a)[:, None] * a
    rho_c = np.linalg.norm(radial, axis=1)
    pressed = inside & (rho_c < R * np.cos(lengths / (2 * R)))
    assert pressed.any() and (inside & ~pressed).any()


def test_pipe_lying_on_the_drum_feels_nothing_and_the_grip_follows_the_rotation():
    """RFEs of length l on the chords of the pipe-axis circle: no contact force; the grip
    anchors move with the payout (a drum turned by D / R carries them along)."""
    R, W = 4.0, math.radians(180.0)
    a, d = np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
    C = np.array([0.0, 0.0, R])
    l = 0.5
    joints = np.arange(0.0, 6.0 + 1e-9, l) / R
    mid = 0.5 * (joints[:-1] + joints[1:])
    n0 = np.cross(a, d)
    pts = C + R * (np.cos(joints)[:, None] * n0 - np.sin(joints)[:, None] * d)
    r = 0.5 * (pts[:-1] + pts[1:])
    lengths = np.full(r.shape[0], l)
    att_R, att_p = np.eye(3)[None], np.zeros((1, 3))
    table_t, table_d = np.array([0.0, 1.0]), np.array([0.0, 0.0])
    F, at, ont, force = run_kernel(C, a, d, R, W, 1e9, 1e9, 1e7, 1e9, table_t, table_d, 0.0, lengths, r,
                                   np.zeros(len(r)), np.zeros(len(r), np.int64), att_R, att_p)
    assert np.abs(F).max() < 1e-9 * 1e9 * l                          # exactly on the drum: no force
    np.testing.assert_allclose(at[ont == 1], -R * mid[ont == 1], atol=1e-12)
    # the drum turns by D / R: the same pipe, gripped at those anchors, is pulled along the payout
    D = 0.01
    F2, _, _, force2 = run_kernel(C, a, d, R, W, 1e9, 1e9, 1e7, 1e9, np.array([0.0, 1.0]), np.array([D, D]), 0.0,
                                  lengths, r, at, ont, att_R, att_p)
    tangent = np.cos(mid)[:, None] * d + np.sin(mid)[:, None] * n0
    weight = np.minimum(1.0, np.minimum(R * mid / l, R * (W - mid) / l))
    np.testing.assert_allclose(np.sum(F2 * tangent, axis=1)[ont == 1], (1e7 * l * weight * D)[ont == 1],
                               rtol=1e-9)
    assert force2 == pytest.approx(-1e7 * l * D * weight[ont == 1].sum(), rel=1e-9)


def test_residual_curvature_kernel_matches_the_fibre_model():
    """P4 pipe reeled on the 8.162 m reel: 0.10470 1/m (elastic unloading); a pipe
    reverse-bent far enough to yield again: the kernel's Newton iterations find the zero of
    the moment, equal to the overlay law unloaded to zero moment (brentq) and to the fibre
    model within its polyline error; an elastic SDE keeps no curvature."""
    from scipy.optimize import brentq

    import rfesim
    from rfesim.materials.residual_curvature import residual_curvature_into
    from rfesim.materials.sde_plastic import N_OUT, pack_params, plastic_bending_into, plastic_params
    from rfesim.materials.section import FibreSection, PipeWall
    from rfesim.materials.stress_strain import Bilinear
    from rfesim.model.sections import section_from_type

    lt = rfesim.Scenario.model_validate({"line_types": {"x65": {
        "outer_diameter": 0.3239, "wall_thickness": 0.0159, "youngs_modulus": 207e9, "density": 7850.0,
        "material": {"kind": "elastoplastic", "yield_stress": 448e6, "hardening_ratio": 0.02}}}}).line_types["x65"]
    ps = plastic_params(lt.material, section_from_type(lt))
    params, hist = pack_params([ps.params, ps.params, ps.params])
    out = np.zeros(N_OUT)
    trial = hist.copy()
    kr = 1.0 / 8.162
    path = {0: [kr], 1: [kr, -0.3 * kr]}          # reeled; reeled then reverse-bent past reverse yield
    for i, kappas in path.items():
        for k in kappas:
            plastic_bending_into(params, hist, i, k, 0.0, out, trial)
            hist[i] = trial[i]
    res = np.zeros(3)
    residual_curvature_into(params, hist, np.array([1, 1, 0]), np.zeros_like(hist), np.zeros(N_OUT), res)
    for i in (0, 1):
        zero = brentq(lambda k: plastic_bending_into(params, hist, i, k, 0.0, out, trial) or out[0], -kr, kr,
                      xtol=1e-15)
        assert res[i] == pytest.approx(abs(zero), rel=1e-9)
    fibres = FibreSection(Bilinear(207e9, 448e6, 0.02), PipeWall(0.3239, 0.0159, 207e9))
    fibres.update(kr)
    assert res[0] == pytest.approx(abs(fibres.unload()[0]), rel=5e-3)
    fibres.update(-0.3 * kr)
    assert res[1] == pytest.approx(abs(fibres.unload()[0]), rel=2e-2)
    assert res[2] == 0.0


def test_straightener_rollers_and_schema_errors():
    import rfesim
    from rfesim.errors import ScenarioError
    from rfesim.model.reels import straightener_roller_set

    base = {"line_types": {"p": {"EA": 1e9, "EIy": 1e6, "GJ": 1e6, "mass_per_length": 100.0, "outer_diameter": 0.3}},
            "lines": {"pipe": {"type": "p", "length": 20.0, "elements": 10,
                               "end_a": {"attach": "fixed", "position": [0, 0, 0]}}}}
    st = {"kind": "straightener", "line": "pipe", "entry": [1.0, 0, 0], "axis": [2, 0, 0], "side": [0, 0, 3],
          "span": 4.0, "offset": 0.1, "stiffness": 1e8, "roller_radius": 0.2, "rollers": 5}
    sc = rfesim.Scenario.model_validate({**base, "supports": {"s": st}})
    rs = straightener_roller_set(sc.supports["s"], 0.15)
    # rollers every span / 4; even ones above the pipe line, odd ones below the offset line
    np.testing.assert_allclose(rs.point[:, 0], 1.0 + np.arange(5.0))
    np.testing.assert_allclose(rs.point[:, 2], [0.35, 0.1 - 0.35, 0.35, 0.1 - 0.35, 0.35])
    np.testing.assert_allclose(rs.axis, np.tile([0.0, -1.0, 0.0], (5, 1)))
    # the pipe axis rests at roller + reach * up: on the straight line and at the offset
    np.testing.assert_allclose((rs.guide + 0.35 * rs.up)[:, 2], [0.0, 0.1, 0.0, 0.1, 0.0], atol=1e-15)
    for change, field in [({"rollers": 4}, "rollers"), ({"side": [1, 0, 1]}, "side"), ({"offset": 0.6}, "offset"),
                          ({"axis": [0, 0, 0]}, "axis")]:
        with pytest.raises(ScenarioError, match=f"supports.s.{field}"):
            rfesim.Scenario.model_validate({**base, "supports": {"s": {**st, **change}}})
    reel = {"kind": "reel", "line": "pipe", "centre": [0, 0, 5], "axis": [0, 1, 0], "direction": [1, 0, 0],
            "radius": 5.0, "wrap_deg": 90.0, "stored_length": 5.0, "capacity": 1e6}
    base_free = {**base, "lines": {"pipe": {**base["lines"]["pipe"], "end_a": {"attach": "free"}}}}
    rfesim.Scenario.model_validate({**base_free, "supports": {"r": reel}})
    for change, field in [({"direction": [1, 0.1, 0]}, "direction"), ({"stored_length": 8.0}, "stored_length"),
                          ({"wrap_deg": 300.0}, "wrap_deg"), ({"radius": 0.0}, "radius")]:
        with pytest.raises(ScenarioError, match=f"supports.r.{field}"):
            rfesim.Scenario.model_validate({**base_free, "supports": {"r": {**reel, **change}}})
    with pytest.raises(ScenarioError, match="supports.r.line"):
        rfesim.Scenario.model_validate({**base, "supports": {"r": reel}})     # end A fixed: not on the reel
