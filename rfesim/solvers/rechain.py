"""Compiled re-chaining of a line's RFE centres for the statics' Newton update
(rfesim.solvers.statics._rechain).

Each RFE b = a + 1 of a line is placed from RFE a across their SDE s at its target
deformation eps_s (first three components, in the SDE's mean frame):

    r_b = r_a + R_a d_L + R' eps_s - R_b d_R,    R' = R_a* exp(log(R_a*^T R_b) / 2),

R_a* = R_a R0_s (R0_s the SDE's rest rotation, identity but at joints and drives), d_L and
d_R the SDE's arms in the frames of RFE a and b (chapter 8, eqs. 8.87-8.88: the SDE's
deformation measured in the mean frame of its two ends). The loop runs over every element of
the line on every Newton iteration; for a 67 604-element line it took 0.93 s in Python and
74 ms compiled, timed in one process (12.6 times). Its 3 x 3 products are np.dot (BLAS, as numpy's
are), not scalar loops: with them the chain is bit for bit the Python loop's, where a scalar
loop's round-off (8 times faster still) moved static states in their last digits and with
them chaotic runs (docs/theory.md, 'Geometrically consistent update'). The readable
reference is in ``tests/unit/test_rechain_kernel.py``.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..kinematics import exp_so3_into, log_so3_into


@njit(cache=True)
def chain_line_into(R, r, rest, arm_left, arm_right, eps_target, i0, s0, nsde, chain):
    """Re-chain RFEs i0 + 1 .. i0 + nsde from RFE i0 across SDEs s0 .. s0 + nsde - 1 (see the
    module): writes their centres into r (in place, each used by the next) and chain[0..nsde]
    (chain[0] = r[i0]). The products are numpy's (np.dot, BLAS, as numba compiles it), in the
    order the Python loop took them, so the statics is bit for bit what it was."""
    w = np.empty(3)
    half = np.empty((3, 3))
    chain[0] = r[i0]
    for j in range(nsde):
        a = i0 + j
        b = a + 1
        s = s0 + j
        ras = np.dot(R[a], rest[s])
        log_so3_into(np.ascontiguousarray(np.dot(ras.T, R[b])), w)
        exp_so3_into(0.5 * w[0], 0.5 * w[1], 0.5 * w[2], half)
        rp = np.dot(ras, half)
        r[b] = r[a] + np.dot(R[a], arm_left[s]) + np.dot(rp, eps_target[s, :3]) - np.dot(R[b], arm_right[s])
        chain[j + 1] = r[b]
