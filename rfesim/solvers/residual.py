"""Residual of the static and implicit-step equations as a function of the coordinates."""
from __future__ import annotations

import numpy as np
from numba import njit

from ..model.assemble import evaluate, evaluate_frozen_sde, evaluate_keep_sde


def residual_q(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, out):
    """Residual as a function of the coordinates q.

    mode 0 (statics): out = -fgen(q, 0); mode 1 (implicit step): with A = (q - Q0)/cq and
    qdot = V0 + cv A, out = cq (Mgen A - fgen). Fixed coordinates give out = q (statics)
    or q - Q0, so their Jacobian rows are the identity.

    A Python function: ``residual_general`` with frozen 0 (compiled kernels call that
    directly). A compiled wrapper would be another entry point, and numba compiles every
    entry point with the whole tree of kernels it calls (2.6 MB of machine code here, about
    20 s of a cold start).
    """
    residual_general(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, out, 0, ws.F, ws.M)


@njit(cache=True, _nrt=False)
def residual_general(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, out, frozen, Fsde,
                     Msde):
    """residual_q; with ``frozen`` (1 or True) the SDE forces and moments are the given Fsde,
    Msde instead of being evaluated (the local part of the Jacobian,
    rfesim.solvers.jacobian); with ``frozen`` = 2 they are evaluated and also copied into
    Fsde, Msde (the implicit step's Newton iterate, whose Jacobian then reuses them)."""
    n = q.shape[0]
    if mode == 0:
        for i in range(n):
            for k in range(6):
                qd_buf[i, k] = 0.0
    else:
        inv = 1.0 / cq
        for i in range(n):
            for k in range(6):
                A = (q[i, k] - Q0[i, k]) * inv
                A_buf[i, k] = A
                qd_buf[i, k] = V0[i, k] + cv * A
    if frozen == 1:
        evaluate_frozen_sde(km, att, q, qd_buf, ref, ws, scale, Fsde, Msde)
    elif frozen == 2:
        evaluate_keep_sde(km, att, q, qd_buf, ref, ws, scale, Fsde, Msde)
    else:
        evaluate(km, att, q, qd_buf, ref, ws, scale)
    if mode == 0:
        for i in range(n):
            for k in range(6):
                out[i, k] = -ws.fgen[i, k] if mask[i, k] else q[i, k]
    else:
        for i in range(n):
            for a in range(6):
                s = -ws.fgen[i, a]
                for c in range(6):
                    s += ws.Mgen[i, a, c] * A_buf[i, c]
                out[i, a] = cq * s


@njit(cache=True, _nrt=False)
def residual_norm(r, cq, mask, length_scale, force_ref):
    """Largest residual force over the moving coordinates, relative to force_ref
    (moments are divided by the RFE length)."""
    m = 0.0
    inv = 1.0 / cq
    for i in range(r.shape[0]):
        for k in range(6):
            if not mask[i, k]:
                continue
            v = abs(r[i, k]) * inv
            if k >= 3:
                v /= length_scale[i]
            if v != v:
                return np.inf
            if v > m:
                m = v
    return m / force_ref
