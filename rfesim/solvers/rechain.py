"""Compiled re-chaining of a line's RFE centres for the statics' Newton update
(rfesim.solvers.statics._rechain).

Each RFE b = a + 1 of a line is placed from RFE a across their SDE s at its target
deformation eps_s (first three components, in the SDE's mean frame):

    r_b = r_a + R_a d_L + R' eps_s - R_b d_R,    R' = R_a* exp(log(R_a*^T R_b) / 2),

R_a* = R_a R0_s (R0_s the SDE's rest rotation, identity but at joints and drives), d_L and
d_R the SDE's arms in the frames of RFE a and b (chapter 8, eqs. 8.87-8.88: the SDE's
deformation measured in the mean frame of its two ends). The loop runs over every element of
the line on every Newton iteration; in Python it took 20 us an element (1.5 s an iteration
for a 67 604-element line), compiled it is a scalar loop. The readable reference is in
``tests/unit/test_rechain_kernel.py``.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..kinematics import exp_so3_into, log_so3_into


@njit(cache=True)
def chain_line_into(R, r, rest, arm_left, arm_right, eps_target, i0, s0, nsde, chain):
    """Re-chain RFEs i0 + 1 .. i0 + nsde from RFE i0 across SDEs s0 .. s0 + nsde - 1 (see the
    module): writes their centres into r (in place, each used by the next) and chain[0..nsde]
    (chain[0] = r[i0])."""
    ras = np.empty((3, 3))
    rel = np.empty((3, 3))
    half = np.empty((3, 3))
    rp = np.empty((3, 3))
    w = np.empty(3)
    for k in range(3):
        chain[0, k] = r[i0, k]
    for j in range(nsde):
        a = i0 + j
        b = a + 1
        s = s0 + j
        # R_a* = R_a R0
        for p in range(3):
            for q in range(3):
                ras[p, q] = R[a, p, 0] * rest[s, 0, q] + R[a, p, 1] * rest[s, 1, q] + R[a, p, 2] * rest[s, 2, q]
        # R_a*^T R_b
        for p in range(3):
            for q in range(3):
                rel[p, q] = ras[0, p] * R[b, 0, q] + ras[1, p] * R[b, 1, q] + ras[2, p] * R[b, 2, q]
        log_so3_into(rel, w)
        exp_so3_into(0.5 * w[0], 0.5 * w[1], 0.5 * w[2], half)
        for p in range(3):
            for q in range(3):
                rp[p, q] = ras[p, 0] * half[0, q] + ras[p, 1] * half[1, q] + ras[p, 2] * half[2, q]
        for p in range(3):
            x = r[a, p]
            for q in range(3):
                x += R[a, p, q] * arm_left[s, q] + rp[p, q] * eps_target[s, q] - R[b, p, q] * arm_right[s, q]
            r[b, p] = x
            chain[j + 1, p] = x
