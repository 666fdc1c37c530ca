"""The compiled re-chaining of the statics' Newton update (rfesim.solvers.rechain) against
its readable reference, the per-element loop the statics ran before (one SDE at a time:
the mean frame of its two ends from the matrix log and exp, then the centre of the next
RFE across the SDE at its target deformation)."""
from __future__ import annotations

import numpy as np
from scipy.linalg import expm, logm

from rfesim.solvers.rechain import chain_line_into


def _hat(w):
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _rotation(rng, angle):
    w = rng.normal(size=3)
    return expm(_hat(angle * w / np.linalg.norm(w)))


def reference(R, r, rest, arm_left, arm_right, eps_target, i0, s0, nsde):
    """r_b = r_a + R_a d_L + R' eps - R_b d_R with R' = R_a* exp(log(R_a*^T R_b) / 2),
    R_a* = R_a R0: scipy's matrix log and exp, one element after the other."""
    r = r.copy()
    chain = [r[i0].copy()]
    for j in range(nsde):
        a, b, s = i0 + j, i0 + j + 1, s0 + j
        ras = R[a] @ rest[s]
        mean = ras @ expm(0.5 * np.real(logm(ras.T @ R[b])))
        r[b] = r[a] + R[a] @ arm_left[s] + mean @ eps_target[s, :3] - R[b] @ arm_right[s]
        chain.append(r[b].copy())
    return r, np.array(chain)


def test_chain_line_kernel_equals_the_reference():
    """A 12-element line (RFEs 3..15 of 20, SDEs 5..16) with frames turned up to 2.5 rad from
    each other, rest rotations on some SDEs, arms of half an element and deformations of
    1e-3 m: the kernel's centres equal the reference's to 1e-12 m, and RFEs outside the line
    are untouched."""
    rng = np.random.default_rng(7)
    n, nsde_all, i0, s0, nsde = 20, 20, 3, 5, 12
    R = np.array([_rotation(rng, rng.uniform(0.0, 2.5)) for _ in range(n)])
    rest = np.array([np.eye(3) if k % 3 else _rotation(rng, 0.8) for k in range(nsde_all)])
    arm_left = np.tile([0.5, 0.0, 0.0], (nsde_all, 1)) + 0.01 * rng.normal(size=(nsde_all, 3))
    arm_right = -np.tile([0.5, 0.0, 0.0], (nsde_all, 1)) + 0.01 * rng.normal(size=(nsde_all, 3))
    eps = 1e-3 * rng.normal(size=(nsde_all, 6))
    r0 = rng.normal(size=(n, 3))
    expected_r, expected_chain = reference(R, r0, rest, arm_left, arm_right, eps, i0, s0, nsde)
    r = r0.copy()
    chain = np.empty((nsde + 1, 3))
    chain_line_into(R, r, rest, arm_left, arm_right, eps, i0, s0, nsde, chain)
    np.testing.assert_allclose(chain, expected_chain, rtol=0.0, atol=1e-12)
    np.testing.assert_allclose(r, expected_r, rtol=0.0, atol=1e-12)
    np.testing.assert_array_equal(r[:i0 + 1], r0[:i0 + 1])
    np.testing.assert_array_equal(r[i0 + nsde + 1:], r0[i0 + nsde + 1:])
    # the chain moved: the centres are not where they started
    assert np.abs(r[i0 + 1:i0 + nsde + 1] - r0[i0 + 1:i0 + nsde + 1]).min() > 1e-3


def test_chain_line_kernel_is_bit_for_bit_the_python_loop():
    """With numpy's 3 x 3 products (np.dot in the kernel) the chain equals the Python loop the
    statics ran before, numpy's @ with the same log and exp, to the last bit: a static state
    does not move in its last digits (docs/theory.md, 'Geometrically consistent update')."""
    from rfesim.solvers.statics import _exp, _log
    rng = np.random.default_rng(3)
    n = 40
    R = np.array([_rotation(rng, rng.uniform(0.0, 2.5)) for _ in range(n)])
    rest = np.array([np.eye(3) if k % 3 else _rotation(rng, 0.8) for k in range(n)])
    arm_left, arm_right, r0 = rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    eps = 1e-3 * rng.normal(size=(n, 6))
    r = r0.copy()
    for a in range(n - 1):
        ras = R[a] @ rest[a]
        mean = ras @ _exp(0.5 * _log(ras.T @ R[a + 1]))
        r[a + 1] = r[a] + R[a] @ arm_left[a] + mean @ eps[a, :3] - R[a + 1] @ arm_right[a]
    got = r0.copy()
    chain = np.empty((n, 3))
    chain_line_into(R, got, rest, arm_left, arm_right, eps, 0, 0, n - 1, chain)
    assert np.array_equal(got, r) and np.array_equal(chain, r)
