"""The tensioner kernel (rfesim.loads.tensioner) against a readable reference: lateral pads,
axial grip spring-slider against the moving track, capacity, entry and exit of RFEs, and
the characteristic of a driven tensioner."""
from __future__ import annotations

import numpy as np
import pytest

from rfesim.loads.tensioner import MODE_TABLE, MODE_TENSION, commit_tensioners, payout_speed, tensioner_forces


def reference_forces(P, e, L, kl, kg, cap, D, lengths, r, anchor, gripped):
    """Per RFE: force, trial anchor, gripped flag; and the tensioner's axial force. The
    capacity is the whole track's: each RFE's share is cap l w / sum(l w) over the RFEs in it."""
    n = r.shape[0]
    held = 0.0
    for i in range(n):
        xi = (r[i] - P) @ e
        weight = min(1.0, xi / lengths[i], (L - xi) / lengths[i])
        if 0.0 <= xi <= L and weight > 0.0:
            held += lengths[i] * weight
    F = np.zeros((n, 3))
    new_anchor = np.array(anchor, float)
    on = np.zeros(n, int)
    total = 0.0
    for i in range(n):
        rel = r[i] - P
        xi = rel @ e
        weight = min(1.0, xi / lengths[i], (L - xi) / lengths[i])     # taper at entry and exit
        if not 0.0 <= xi <= L or weight <= 0.0:
            continue
        F[i] -= kl * lengths[i] * weight * (rel - xi * e)
        if gripped[i]:
            limit = cap * lengths[i] * weight / held
            f = float(np.clip(-kg * lengths[i] * weight * (xi - anchor[i] - D), -limit, limit))
            new_anchor[i] = xi - D + f / (kg * lengths[i] * weight)
        else:
            f = 0.0
            new_anchor[i] = xi - D
        on[i] = 1
        F[i] += f * e
        total -= f
    return F, new_anchor, on, total


def run_kernel(P, e, L, kl, kg, cap, table_t, table_d, t, lengths, r, anchor, gripped, att_R=None, att_p=None,
               mode=MODE_TABLE, D_committed=0.0):
    n = r.shape[0]
    att_R = np.eye(3)[None] if att_R is None else att_R
    att_p = np.zeros((1, 3)) if att_p is None else att_p
    F = np.zeros((n, 3))
    at = np.full(n, np.nan)
    ont = np.full(n, -1, np.int64)
    force = np.zeros(1)
    tensioner_forces(np.array([0]), np.array([P]), np.array([e]), np.array([L]), np.array([kl]), np.array([kg]),
                     np.array([cap]), np.array([0]), np.array([n]), np.array([mode]), np.array([table_t]),
                     np.array([table_d]), np.array([np.gradient(table_d, table_t)]), np.array([len(table_t)]), t,
                     att_p, att_R, lengths, r, F,
                     np.asarray(anchor, float), np.asarray(gripped, np.int64), at, ont, np.array([D_committed]),
                     force, np.zeros(1), np.zeros(1), np.ones(1), np.zeros(1), 0.0, np.zeros(1))
    return F, at, ont, force[0]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_kernel_against_reference(seed):
    rng = np.random.default_rng(seed)
    n = 30
    e = rng.normal(size=3)
    e /= np.linalg.norm(e)
    P = rng.normal(size=3)
    L = 10.0
    xi = np.linspace(-3.0, 13.0, n)
    lateral = rng.normal(scale=0.01, size=(n, 3))
    lateral -= (lateral @ e)[:, None] * e
    r = P + xi[:, None] * e + lateral
    lengths = rng.uniform(0.3, 0.7, size=n)
    table_t, table_d = np.array([0.0, 10.0, 20.0]), np.array([0.0, 5.0, 5.0])
    t = 25.0
    D = 5.0
    gripped = rng.integers(0, 2, size=n)
    anchor = xi - D + rng.normal(scale=0.002, size=n)
    anchor[::4] += rng.normal(scale=1.0, size=anchor[::4].shape)    # these slip
    kl, kg, cap = 1e6, 5e6, 2e5
    F, at, ont, force = run_kernel(P, e, L, kl, kg, cap, table_t, table_d, t, lengths, r, anchor, gripped)
    Fr, ar, onr, total = reference_forces(P, e, L, kl, kg, cap, D, lengths, r, anchor, gripped)
    np.testing.assert_allclose(F, Fr, rtol=1e-10, atol=1e-9)
    inside = onr == 1
    np.testing.assert_allclose(at[inside], ar[inside], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(ont, onr)
    assert force == pytest.approx(total, rel=1e-9, abs=1e-6 * cap)
    # at the capacity somewhere, and the axial force never exceeds its share of it
    axial = F @ e
    xi_in = (r[inside] - P) @ e
    w_in = np.minimum(1.0, np.minimum(xi_in / lengths[inside], (L - xi_in) / lengths[inside]))
    share = cap * lengths[inside] * w_in / np.sum(lengths[inside] * w_in)
    assert np.all(np.abs(axial[inside]) <= share * (1 + 1e-12) + 1e-9)


def test_track_on_a_moving_vessel_and_the_characteristic():
    """Track defined in a vessel frame turned 90 deg about z and shifted: the pads push the
    RFE back to the axis in the global frame; a driven tensioner pays out when its force is
    above set + band, reels in below set - band, at (dT -+ band)/gain, limited to v_max."""
    Rz = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    att_R = np.stack([np.eye(3), Rz])
    att_p = np.array([[0.0, 0.0, 0.0], [5.0, 0.0, 1.0]])
    r = np.array([[5.0 + 0.01, 3.0, 1.0]])           # on the global y axis line, 1 cm off, mid-track
    F = np.zeros((1, 3))
    at = np.zeros(1)
    ont = np.zeros(1, np.int64)
    force = np.zeros(1)
    tensioner_forces(np.array([1]), np.array([[0.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]), np.array([8.0]),
                     np.array([1e5]), np.array([1e6]), np.array([1e9]), np.array([0]), np.array([1]),
                     np.array([MODE_TENSION]), np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2)), np.array([2]),
                     0.0, att_p,
                     att_R, np.array([2.0]), r, F, np.zeros(1), np.zeros(1, np.int64), at, ont, np.array([0.0]),
                     force, np.array([1.0e5]), np.array([0.2e5]), np.array([4e4]), np.array([1.0]), 0.0, np.zeros(1))
    np.testing.assert_allclose(F[0], [-1e5 * 2.0 * 0.01, 0.0, 0.0], atol=1e-9)
    assert ont[0] == 1 and at[0] == pytest.approx(3.0)
    for grip, expected in [(1.2e5, 0.0), (1.6e5, (1.6e5 - 1.0e5 - 0.2e5) / 4e4),
                           (0.5e5, (0.5e5 - 1.0e5 + 0.2e5) / 4e4), (9e5, 1.0)]:
        assert payout_speed(grip, 1.0e5, 0.2e5, 4e4, 1.0)[0] == pytest.approx(expected)
    # the commit takes the paid-out length solved in the step's last evaluation
    D = np.array([0.0])
    D_trial = np.array([0.37])
    commit_tensioners(np.array([MODE_TENSION]), D_trial, D, 0.5, np.zeros(1), np.zeros(1, np.int64),
                      np.zeros(1), np.zeros(1, np.int64), np.array([0]), np.array([1]))
    assert D[0] == 0.37
    commit_tensioners(np.array([MODE_TENSION]), D_trial, D, 0.0, np.zeros(1), np.zeros(1, np.int64),
                      np.zeros(1), np.zeros(1, np.int64), np.array([0]), np.array([1]))
    assert D[0] == 0.37                   # statics (h = 0) does not move it


def test_line_beside_the_track_is_not_held():
    """Only RFEs within TRACK_CAPTURE (1 m) of the axis are in the track. Before, any RFE
    between the entry and exit planes was pulled onto the axis: a reel-lay pipe stored on the
    lower half of a 12 m drum, 21 m from the tensioner's axis and 0.3 m past its entry plane,
    took 63 MN (statics failed for reel radii 11-13 m)."""
    from rfesim.loads.tensioner import TRACK_CAPTURE
    e = np.array([np.cos(np.radians(70.0)), 0.0, -np.sin(np.radians(70.0))])
    P = np.zeros(3)
    side = np.array([np.sin(np.radians(70.0)), 0.0, np.cos(np.radians(70.0))])      # normal to e
    # on the axis, just within the capture, just beyond it, and 21 m away, all 5 m into the track
    offsets = [0.0, 0.9 * TRACK_CAPTURE, 1.1 * TRACK_CAPTURE, 21.0]
    r = np.array([P + 5.0 * e + d * side for d in offsets])
    lengths = np.full(4, 1.0)
    F, at, on, force = run_kernel(P, e, 10.0, 1e7, 1e7, 1e6, np.array([0.0, 1.0]), np.array([0.0, 0.0]), 0.0,
                                  lengths, r, np.zeros(4), np.zeros(4, np.int64))
    np.testing.assert_array_equal(on, [1, 1, 0, 0])
    assert np.linalg.norm(F[1]) == pytest.approx(1e7 * 0.9 * TRACK_CAPTURE, rel=1e-12)     # pulled onto the axis
    np.testing.assert_array_equal(F[2:], 0.0)
