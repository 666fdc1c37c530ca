"""Block-tridiagonal Jacobian of the residual from the analytic SDE tangent.

J = (local part) + (SDE part):

* the SDE part couples neighbours: T_i^T (cK K_s + cD Kd_s) T_j for the RFE pair (i, j) of
  every SDE s, with K_s, Kd_s the spatial tangent stiffness and damping of
  ``rfesim.loads.sde_tangent`` and T_i the map from RFE i's coordinates to its spatial
  virtual displacement (dr, da): diag(I, R E) for a free RFE, (-[c]x R E, R E) on the angles
  of a pinned one (c from its pin to its centre), zero for a clamped one;
* the local part is everything that acts on one RFE alone -- its mass and velocity terms,
  gravity, buoyancy, Morison drag and added mass, seabed contact, point loads, and the
  change of the projection T^T with the RFE's own coordinates under the (frozen) SDE
  forces -- formed by forward differences with every RFE perturbed at once (6 evaluations
  of the local terms, whatever the number of RFEs).

The reevings' pulls (rfesim.loads.reeving.reeving_tangent) add blocks of the sheave's RFE and
of a line-end lead's RFE; those between RFEs that are not neighbours (a boom's foot and its
tip) go to ws.ob_J, solved with the closing joins' (rfesim.solvers.banded.bt_factor_closed).

In statics (mode 0) cK = 1, cD = 0; in an implicit step (mode 1) cK = cq, cD = cv
(``rfesim.solvers.kernels.residual_q``). This costs about a fifth of the coloured
finite-difference Jacobian (18 full evaluations) and is checked against it in the tests.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..kinematics import matmul_into, matvec_into
from ..loads.reeving import reeving_tangent, slip_tangent
from ..loads.sde_tangent import sde_tangent_rest
from ..model.assemble import sde_part
from .residual import residual_general


@njit(cache=True, _nrt=True)
def _maps(km, att, ws, T):
    """T (n, 6, 6): coordinates -> spatial virtual displacement (dr, da) of each RFE centre."""
    RE = np.empty((3, 3))
    P = np.empty(3)
    c = np.empty(3)
    for i in range(T.shape[0]):
        for a in range(6):
            for b in range(6):
                T[i, a, b] = 0.0
        kind = km.rfe_kind[i]
        if kind == 2:
            continue
        matmul_into(ws.R[i], ws.E[i], RE)
        for a in range(3):
            for b in range(3):
                T[i, 3 + a, 3 + b] = RE[a, b]
        if kind == 0:
            for a in range(3):
                T[i, a, a] = 1.0
        else:
            at = km.rfe_attach[i]
            matvec_into(att.R[at], km.rfe_attach_offset[i], P)
            for k in range(3):
                c[k] = ws.r[i, k] - (P[k] + att.p[at, k])
            # dr = da x c = -[c]x RE dphi
            for b in range(3):
                col0 = RE[0, b]
                col1 = RE[1, b]
                col2 = RE[2, b]
                T[i, 0, 3 + b] = col1 * c[2] - col2 * c[1]
                T[i, 1, 3 + b] = col2 * c[0] - col0 * c[2]
                T[i, 2, 3 + b] = col0 * c[1] - col1 * c[0]


@njit(cache=True)
def _congruence_into(T, i, j, KK, KT):
    """KK <- T_i^T KK T_j (6 x 6; KT is scratch): a block of the spatial tangent mapped to
    the columns of RFE j and the rows of RFE i."""
    for a in range(6):
        for b in range(6):
            acc = 0.0
            for k in range(6):
                acc += KK[a, k] * T[j, k, b]
            KT[a, b] = acc
    for a in range(6):
        for b in range(6):
            acc = 0.0
            for k in range(6):
                acc += T[i, k, a] * KT[k, b]
            KK[a, b] = acc


@njit(cache=True)
def _reeving_blocks(km, ws, T, cK, cD, J, KK, KT):
    """Add the pulls' tangent (ws.rv_K, rv_Kd of rfesim.loads.reeving.reeving_tangent) to J:
    the block of rows RFE i (the sheave's a, a line-end lead's f) and columns RFE j (a, the
    rope's first b, f) is T_i^T (cK K + cD Kd) T_j, in the band when i and j are neighbours,
    else in ws.ob_J at the slot of (i, j) (km.ob_row, km.ob_col)."""
    for rv in range(km.rv_sde.shape[0]):
        s = km.rv_sde[rv]
        lead = km.rv_kind[rv] == 1
        for bi in range(2 if lead else 1):
            i = km.sde_left[s] if bi == 0 else km.rv_rfe[rv]
            for bj in range(3 if lead else 2):
                j = km.sde_left[s] if bj == 0 else (km.sde_right[s] if bj == 1 else km.rv_rfe[rv])
                for a in range(6):
                    for b in range(6):
                        KK[a, b] = cK * ws.rv_K[rv, 6 * bi + a, 6 * bj + b] + cD * ws.rv_Kd[rv, 6 * bi + a, 6 * bj + b]
                _congruence_into(T, i, j, KK, KT)
                slot = j - i + 1
                if 0 <= slot <= 2:
                    for a in range(6):
                        for b in range(6):
                            J[i, slot, a, b] += KK[a, b]
                    continue
                for c in range(km.ob_row.shape[0]):
                    if km.ob_row[c] == i and km.ob_col[c] == j:
                        for a in range(6):
                            for b in range(6):
                                ws.ob_J[c, a, b] += KK[a, b]
                        break


def jacobian_analytic(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                      length_scale, J, Ks, Kds, T, Fsde, Msde):
    """Fill J (n, 3, 6, 6) at q; r0 receives the residual at q. Work arrays: Ks, Kds
    (nsde, 12, 12), T (n, 6, 6), Fsde, Msde (n, 3). A Python function: a compiled wrapper
    of ``jacobian_analytic_at`` would be another entry point, compiled with its whole tree
    of kernels (4 MB of machine code, about 30 s of a cold start)."""
    jacobian_analytic_at(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                         length_scale, J, Ks, Kds, T, Fsde, Msde, False)


@njit(cache=True, _nrt=True)
def jacobian_analytic_at(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                         length_scale, J, Ks, Kds, T, Fsde, Msde, evaluated):
    """``jacobian_analytic``; with ``evaluated`` the caller has just evaluated the residual
    at q into r0 with ``residual_general(..., 2, Fsde, Msde)`` (ws holds the poses and SDE
    state of q, Fsde and Msde the SDE forces alone) and neither is evaluated again (the
    implicit step's Newton iteration: one residual and one SDE evaluation less per
    Jacobian, the same numbers)."""
    n = q.shape[0]
    if not evaluated:
        residual_general(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, np.int64(0),
                         ws.F, ws.M)
        # SDE forces alone, spatial, at the base state (ws holds the base poses and velocities)
        for i in range(n):
            for k in range(3):
                Fsde[i, k] = 0.0
                Msde[i, k] = 0.0
        sde_part(km, att, ws, Fsde, Msde)
    if km.has_motors:
        # a motor at its torque limit has no torsional tangent (rfesim.loads.drives.motor_forces)
        if not (km.has_plastic or km.has_tension_only):
            for s in range(km.sde_left.shape[0]):
                for k in range(6):
                    ws.k_tangent[s, k] = km.sde_stiffness[s, k]
        for s in range(km.sde_left.shape[0]):
            for k in range(6):
                ws.c_tangent[s, k] = km.sde_damping[s, k]
        for j in range(km.motor_sde.shape[0]):
            if ws.motor_sat[j] == 1:
                ws.k_tangent[km.motor_sde[j], 3] = 0.0
                ws.c_tangent[km.motor_sde[j], 3] = 0.0
        sde_tangent_rest(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, ws.k_tangent, ws.c_tangent,
                         km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase, ws.roff, ws.sigma, Ks, Kds)
    elif km.has_plastic or km.has_tension_only:
        # a slack rope element (rfesim.loads.tension_only) keeps its axial damping here although
        # its force is 0: the exact tangent (no damping) was tried and took a snap load's peak
        # 1.3 % lower at 2 ms steps (docs/theory.md, 'Slack ropes and Newton')
        sde_tangent_rest(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, ws.k_tangent, km.sde_damping,
                         km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase, ws.roff, ws.sigma, Ks, Kds)
    else:
        sde_tangent_rest(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                         km.sde_damping, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase, ws.roff,
                         ws.sigma, Ks, Kds)
    if km.has_reeving:
        # the rope's slip over the sheave (into the join's tangent), then the pulls toward the
        # leads: their tangent in ws.rv_K, rv_Kd, placed below (rfesim.loads.reeving)
        slip_tangent(km.rv_sde, km.rv_slip, km.sde_left, km.sde_right, km.sde_arm_left, ws.R, ws.rv_dir, Ks, Kds)
        reeving_tangent(km.rv_sde, km.rv_kind, km.rv_att, km.rv_rfe, km.rv_point, km.rv_slip, km.sde_left,
                        km.sde_right, km.sde_arm_left, km.sde_arm_right, ws.R, ws.rbase, ws.roff, ws.sde_point,
                        att.p, att.R, ws.rv_tension, ws.rv_dir, ws.rv_fdir, Ks, Kds, ws.rv_K, ws.rv_Kd)
    _maps(km, att, ws, T)
    cK = 1.0 if mode == 0 else cq
    cD = 0.0 if mode == 0 else cv
    for i in range(n):
        for sl in range(3):
            for a in range(6):
                for b in range(6):
                    J[i, sl, a, b] = 0.0
    if km.has_closures:
        for c in range(ws.cl_J.shape[0]):
            for blk in range(2):
                for a in range(6):
                    for b in range(6):
                        ws.cl_J[c, blk, a, b] = 0.0
    for c in range(ws.ob_J.shape[0]):
        for a in range(6):
            for b in range(6):
                ws.ob_J[c, a, b] = 0.0
    KK = np.empty((6, 6))
    KT = np.empty((6, 6))
    if km.has_reeving:
        _reeving_blocks(km, ws, T, cK, cD, J, KK, KT)
    for s in range(km.sde_left.shape[0]):
        ia = km.sde_left[s]
        ib = km.sde_right[s]
        for bi in range(2):
            i = ia if bi == 0 else ib
            for bj in range(2):
                j = ia if bj == 0 else ib
                slot = j - i + 1
                cl = -1
                if slot < 0 or slot > 2:
                    # a closing join's RFEs are not neighbours: its off-band blocks go to
                    # ws.cl_J (rfesim.solvers.banded.bt_factor_closed)
                    for c in range(km.cl_sde.shape[0]):
                        if km.cl_sde[c] == s:
                            cl = c
                # the block T_i^T (cK K + cD Kd)[bi, bj] T_j (6 x 6)
                for a in range(6):
                    for b in range(6):
                        KK[a, b] = cK * Ks[s, 6 * bi + a, 6 * bj + b] + cD * Kds[s, 6 * bi + a, 6 * bj + b]
                if km.rfe_kind[i] == 0 and km.rfe_kind[j] == 0:
                    # free RFEs: T = diag(I, R E) (_maps), so only the rotation columns of KK
                    # and the rotation rows of KK T_j are mapped (the same numbers, 4x fewer
                    # multiplications than the general product below)
                    for a in range(6):
                        for b in range(3):
                            KT[a, b] = KK[a, b]
                            KT[a, 3 + b] = (KK[a, 3] * T[j, 3, 3 + b] + KK[a, 4] * T[j, 4, 3 + b]
                                            + KK[a, 5] * T[j, 5, 3 + b])
                    for a in range(3):
                        for b in range(6):
                            KK[a, b] = KT[a, b]
                            KK[3 + a, b] = (T[i, 3, 3 + a] * KT[3, b] + T[i, 4, 3 + a] * KT[4, b]
                                            + T[i, 5, 3 + a] * KT[5, b])
                else:
                    _congruence_into(T, i, j, KK, KT)
                if cl >= 0:
                    for a in range(6):
                        for b in range(6):
                            ws.cl_J[cl, bi, a, b] += KK[a, b]
                else:
                    for a in range(6):
                        for b in range(6):
                            J[i, slot, a, b] += KK[a, b]
    # local part: every RFE perturbed at once, SDE forces frozen
    eps = 1.5e-8
    for k in range(6):
        for i in range(n):
            for a in range(6):
                qp[i, a] = q[i, a]
            typical = length_scale[i] if k < 3 else 1.0
            h = eps * max(abs(q[i, k]), typical)
            tmp = q[i, k] + h
            hs[i] = tmp - q[i, k]
            qp[i, k] = tmp
        residual_general(km, att, qp, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, rp, np.int64(1), Fsde,
                         Msde)
        for i in range(n):
            inv = 1.0 / hs[i]
            for a in range(6):
                J[i, 1, a, k] += (rp[i, a] - r0[i, a]) * inv
