"""Reeving: the rope's run from a sheave back to its winch (``lines.<rope>.end_a.reeving``).

A hoist rope hangs from a sheave (a pinned line-to-line join, the rope's end A on the
boom's end B) and runs over it toward the winch. Over a frictionless sheave the tension is
the same on both sides, so the sheave carries the hanging rope's pull (the join SDE's force,
already in the model) and a second pull of the same tension toward the lead point: the next
guide sheave or the winch drum. This is the sheave's share of the guiding structures of
eq. 8.95; the run itself is taken straight and massless (its length is the winch's business,
rfesim.model.winches pays out at the sheave).

For reeving j on the join SDE s (RFE a: the parent's last, RFE b: the rope's first):

* tension at the sheave T = |f| with f = R' F'[0:3] the join's force on a (its mean frame
  times its force in {i'}, eqs. 8.86 and 8.90; the pinned join carries no moment);
* the lead L: a point of a vessel (or fixed), ``kind`` 0, L = p_v + R_v l; or an end of a
  line (a rope along a boom to the boom foot), ``kind`` 1, L = r_k + R_k l with l the arm
  from that RFE's centre;
* the pull T e, e = (L - P)/|L - P| with P the sheave (the join SDE's point), on RFE a at P
  (with its moment about a's centre); with a line-end lead the equal and opposite pull -T e
  acts on that RFE at L (the rope's run is inside the structure: no net force), with a
  vessel lead it goes to the vessel (prescribed motion: an output).

Jacobian (``reeving_tangent``, rv_K rows: the forces on a and on the lead's RFE f,
columns: the motions of a, b and f): the pull F = T e on a at P and -F on f at L, with

* dT = (f/T)^T df: the tension follows the join's deformation (its rows of the join
  tangent, with the slip's part of a slipping rope: ``slip_tangent``), of the order of the
  join's stiffness;
* de = (I - e e^T)(dL - dP)/|L - P|: the run turns with the sheave P = (r_a + p_a + r_b +
  p_b)/2 (and P moves with a slipping rope's arm, X_b d(delta)/2) and the lead L = r_f + l;
* the arms P - r_a and l turn with their RFEs.

A line-end lead couples f with a and b, which are not neighbours in the block-tridiagonal
Jacobian (the boom's foot and its tip): those blocks go off the band as the closing joins'
(``km.ob_row``, ``km.ob_col``, ws.ob_J; rfesim.solvers.banded.bt_factor_closed, Woodbury).
Before 2026-12 the lead's rows were left out of the analytic Jacobian, and the coloured
finite differences of statics mixed the foot's coupling with the tip into the band: the
column_crane scenario with the rope along the boom did not converge (docs/theory.md,
'Reeving').
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ._common import add_force_moment
from .sde import sde_geometry_rest

KIND_POINT = 0      # a point of a vessel (or fixed): the reaction goes to the attachment
KIND_LINE_END = 1   # an end of a line: the equal and opposite pull acts there


# ----------------------------------------------------------------------------- rope slip
#
# A rope led to a point of a vessel (a deck winch) runs over its sheave: when the sheave
# moves, the run to the lead changes length and the rope slips over the sheave by as much,
# so the hanging part changes length the other way (the winch holding the total). With the
# hanging rope's length fixed the pull T e is circulatory and a moving frame flutters
# (docs/theory.md, 'Reeving'). The SLIP of reeving j is the run's growth since the start,
#
#     delta = |L - P| - rv_len[j],     d(delta)/dt = e . (v_L - v_P),
#
# with P = r_a + R_a p_a the sheave (the parent's end of the join SDE s), L the lead, e the
# unit vector from P to L, rv_len the run's length at the initial positions. The rope is
# drawn through the sheave as through a ring: its end A sits delta up past the sheave, so
# the hanging length is the rope's less delta. In the model the join SDE's arm on the rope
# (its end A, (-l/2, 0, 0) in the rope's first RFE) becomes (-l/2 + delta + (c/k) d(delta)/dt,
# 0, 0): the join's spring and damper then act between the sheave and the point of the rope
# at the sheave, the damper on the joint's own rate and not on the slip (the rest-gap offset
# c/k d(delta)/dt, as a winch's growing arms, rfesim.model.winches). The arm is set before
# the SDE kernels at every evaluation, so the stiff coupling of the rope's length with the
# sheave's position is implicit in Newton; the SDE tangent sees the arm, ``slip_tangent``
# adds its dependence on the sheave's motion. The base arm (a winch rewrites it between
# steps) is kept by recording what was written: km.rv_arm_written, km.rv_arm_offset.


@njit(cache=True)
def _attached_point(att_p, att_R, at, rv_point, j):
    """The lead point of reeving j (rv_point, in the frame of attachment ``at``) in the
    global frame: p_at + R_at rv_point[j]."""
    x = att_p[at, 0] + att_R[at, 0, 0] * rv_point[j, 0] + att_R[at, 0, 1] * rv_point[j, 1] + \
        att_R[at, 0, 2] * rv_point[j, 2]
    y = att_p[at, 1] + att_R[at, 1, 0] * rv_point[j, 0] + att_R[at, 1, 1] * rv_point[j, 1] + \
        att_R[at, 1, 2] * rv_point[j, 2]
    z = att_p[at, 2] + att_R[at, 2, 0] * rv_point[j, 0] + att_R[at, 2, 1] * rv_point[j, 1] + \
        att_R[at, 2, 2] * rv_point[j, 2]
    return x, y, z


@njit(cache=True)
def slip_arms(rv_sde, rv_slip, rv_att, rv_point, rv_len, rv_arm_written, rv_arm_offset, sde_left, sde_arm_left,
              sde_arm_right, sde_stiffness, sde_damping, R, rbase, roff, v, w, att_p, att_R, att_v, att_w, slip_out):
    """Set the join SDE's arm on the rope of every slipping reeving for the slip of the
    current state (module text above); slip_out[j]: delta (m), 0 for reevings that do not
    slip."""
    for j in range(rv_sde.shape[0]):
        slip_out[j] = 0.0
        if rv_slip[j] == 0:
            continue
        s = rv_sde[j]
        a = sde_left[s]
        cur = sde_arm_right[s, 0]
        base = cur - rv_arm_offset[j] if cur == rv_arm_written[j] else cur     # else rewritten by a winch
        # the sheave P = r_a + R_a p_a and the lead L (arms about the centres in c, l)
        cx = R[a, 0, 0] * sde_arm_left[s, 0] + R[a, 0, 1] * sde_arm_left[s, 1] + R[a, 0, 2] * sde_arm_left[s, 2]
        cy = R[a, 1, 0] * sde_arm_left[s, 0] + R[a, 1, 1] * sde_arm_left[s, 1] + R[a, 1, 2] * sde_arm_left[s, 2]
        cz = R[a, 2, 0] * sde_arm_left[s, 0] + R[a, 2, 1] * sde_arm_left[s, 1] + R[a, 2, 2] * sde_arm_left[s, 2]
        at = rv_att[j]
        lx = att_R[at, 0, 0] * rv_point[j, 0] + att_R[at, 0, 1] * rv_point[j, 1] + att_R[at, 0, 2] * rv_point[j, 2]
        ly = att_R[at, 1, 0] * rv_point[j, 0] + att_R[at, 1, 1] * rv_point[j, 1] + att_R[at, 1, 2] * rv_point[j, 2]
        lz = att_R[at, 2, 0] * rv_point[j, 0] + att_R[at, 2, 1] * rv_point[j, 1] + att_R[at, 2, 2] * rv_point[j, 2]
        ex = att_p[at, 0] + lx - (rbase[a, 0] + roff[a, 0] + cx)
        ey = att_p[at, 1] + ly - (rbase[a, 1] + roff[a, 1] + cy)
        ez = att_p[at, 2] + lz - (rbase[a, 2] + roff[a, 2] + cz)
        d = math.sqrt(ex * ex + ey * ey + ez * ez)
        offset = 0.0
        if d >= 1e-9:
            ex /= d
            ey /= d
            ez /= d
            vLx = att_v[at, 0] + att_w[at, 1] * lz - att_w[at, 2] * ly
            vLy = att_v[at, 1] + att_w[at, 2] * lx - att_w[at, 0] * lz
            vLz = att_v[at, 2] + att_w[at, 0] * ly - att_w[at, 1] * lx
            vPx = v[a, 0] + w[a, 1] * cz - w[a, 2] * cy
            vPy = v[a, 1] + w[a, 2] * cx - w[a, 0] * cz
            vPz = v[a, 2] + w[a, 0] * cy - w[a, 1] * cx
            delta = d - rv_len[j]
            rate = ex * (vLx - vPx) + ey * (vLy - vPy) + ez * (vLz - vPz)
            slip_out[j] = delta
            offset = delta
            if sde_stiffness[s, 0] > 0.0:
                offset += sde_damping[s, 0] / sde_stiffness[s, 0] * rate
        new = base + offset
        sde_arm_right[s, 0] = new
        rv_arm_written[j] = new
        rv_arm_offset[j] = offset


@njit(cache=True)
def slip_tangent(rv_sde, rv_slip, sde_left, sde_right, sde_arm_left, R, e, K, Kd):
    """Add the slip's dependence on the sheave's motion to the join tangents K, Kd (nsde,
    12, 12; K = -df/dx, columns dr_a, da_a, dr_b, da_b): a longer arm moves the rope's
    end point like a translation of RFE b along X_b (its moment arm changes along the force,
    which gives no moment to first order), and d(delta) = -e . dr_a - (c_a x e) . da_a with
    c_a = R_a p_a, so K[:, a] += (K[:, r_b] X_b) (-e, -(c_a x e))^T, and Kd alike through
    d(delta)/dt. e: the reevings' unit directions to the lead (reeving_forces)."""
    for j in range(rv_sde.shape[0]):
        if rv_slip[j] == 0:
            continue
        s = rv_sde[j]
        a = sde_left[s]
        b = sde_right[s]
        ex = e[j, 0]
        ey = e[j, 1]
        ez = e[j, 2]
        if ex == 0.0 and ey == 0.0 and ez == 0.0:
            continue
        cx = R[a, 0, 0] * sde_arm_left[s, 0] + R[a, 0, 1] * sde_arm_left[s, 1] + R[a, 0, 2] * sde_arm_left[s, 2]
        cy = R[a, 1, 0] * sde_arm_left[s, 0] + R[a, 1, 1] * sde_arm_left[s, 1] + R[a, 1, 2] * sde_arm_left[s, 2]
        cz = R[a, 2, 0] * sde_arm_left[s, 0] + R[a, 2, 1] * sde_arm_left[s, 1] + R[a, 2, 2] * sde_arm_left[s, 2]
        d0 = -ex
        d1 = -ey
        d2 = -ez
        d3 = -(cy * ez - cz * ey)
        d4 = -(cz * ex - cx * ez)
        d5 = -(cx * ey - cy * ex)
        X0 = R[b, 0, 0]
        X1 = R[b, 1, 0]
        X2 = R[b, 2, 0]
        for which in range(2):
            A = K if which == 0 else Kd
            for row in range(12):
                u = A[s, row, 6] * X0 + A[s, row, 7] * X1 + A[s, row, 8] * X2
                A[s, row, 0] += u * d0
                A[s, row, 1] += u * d1
                A[s, row, 2] += u * d2
                A[s, row, 3] += u * d3
                A[s, row, 4] += u * d4
                A[s, row, 5] += u * d5


@njit(cache=True)
def reeving_forces(rv_sde, rv_kind, rv_att, rv_rfe, rv_point, sde_left, sde_right, sde_arm_left, sde_arm_right,
                   rest_flag, rest_static, rest_eff, R, rbase, roff, sigma, sde_point, att_p, att_R, F, M,
                   tension_out, dir_out, fdir_out, v3, m33):
    """Add every reeving's pull to F, M (global, about the RFE centres). tension_out[j]: the
    tension at the sheave (N); dir_out[j]: the unit direction e from the sheave to the lead;
    fdir_out[j]: the unit direction of the join's force on the parent (for the Jacobian).
    v3 (>= 4, 3), m33 (>= 6, 3, 3): scratch (the workspace's, as the other SDE corrections)."""
    pa, pb, g, th = v3[0], v3[1], v3[2], v3[3]
    Rrel, Rh, Rp, Jri, Jrh, Ras = m33[0], m33[1], m33[2], m33[3], m33[4], m33[5]
    for j in range(rv_sde.shape[0]):
        s = rv_sde[j]
        a = sde_left[s]
        tension_out[j] = 0.0
        for k in range(3):
            dir_out[j, k] = 0.0
            fdir_out[j, k] = 0.0
        # the join's force on the parent, global: f = R' F' (eq. 8.90 with the pinned join's M' = 0)
        sde_geometry_rest(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff, R,
                          rbase, roff, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh, Ras)
        f0 = Rp[0, 0] * sigma[s, 0] + Rp[0, 1] * sigma[s, 1] + Rp[0, 2] * sigma[s, 2]
        f1 = Rp[1, 0] * sigma[s, 0] + Rp[1, 1] * sigma[s, 1] + Rp[1, 2] * sigma[s, 2]
        f2 = Rp[2, 0] * sigma[s, 0] + Rp[2, 1] * sigma[s, 1] + Rp[2, 2] * sigma[s, 2]
        T = math.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
        if T <= 0.0:
            continue
        # the lead point
        if rv_kind[j] == KIND_POINT:
            L0, L1, L2 = _attached_point(att_p, att_R, rv_att[j], rv_point, j)
            lx = ly = lz = 0.0
        else:
            k = rv_rfe[j]
            lx = R[k, 0, 0] * rv_point[j, 0] + R[k, 0, 1] * rv_point[j, 1] + R[k, 0, 2] * rv_point[j, 2]
            ly = R[k, 1, 0] * rv_point[j, 0] + R[k, 1, 1] * rv_point[j, 1] + R[k, 1, 2] * rv_point[j, 2]
            lz = R[k, 2, 0] * rv_point[j, 0] + R[k, 2, 1] * rv_point[j, 1] + R[k, 2, 2] * rv_point[j, 2]
            L0 = rbase[k, 0] + roff[k, 0] + lx
            L1 = rbase[k, 1] + roff[k, 1] + ly
            L2 = rbase[k, 2] + roff[k, 2] + lz
        ex = L0 - sde_point[s, 0]
        ey = L1 - sde_point[s, 1]
        ez = L2 - sde_point[s, 2]
        d = math.sqrt(ex * ex + ey * ey + ez * ez)
        if d < 1e-9:
            continue            # the lead on the sheave: no direction to pull in
        ex /= d
        ey /= d
        ez /= d
        tension_out[j] = T
        dir_out[j, 0] = ex
        dir_out[j, 1] = ey
        dir_out[j, 2] = ez
        fdir_out[j, 0] = f0 / T
        fdir_out[j, 1] = f1 / T
        fdir_out[j, 2] = f2 / T
        ox = sde_point[s, 0] - (rbase[a, 0] + roff[a, 0])
        oy = sde_point[s, 1] - (rbase[a, 1] + roff[a, 1])
        oz = sde_point[s, 2] - (rbase[a, 2] + roff[a, 2])
        add_force_moment(F, M, a, ox, oy, oz, T * ex, T * ey, T * ez)
        if rv_kind[j] == KIND_LINE_END:
            add_force_moment(F, M, rv_rfe[j], lx, ly, lz, -T * ex, -T * ey, -T * ez)


@njit(cache=True)
def _skew_into(v, out, rows, cols, scale):
    """out[rows:rows+3, cols:cols+3] += scale [v]x (the cross-product matrix of v)."""
    out[rows + 0, cols + 1] -= scale * v[2]
    out[rows + 0, cols + 2] += scale * v[1]
    out[rows + 1, cols + 0] += scale * v[2]
    out[rows + 1, cols + 2] -= scale * v[0]
    out[rows + 2, cols + 0] -= scale * v[1]
    out[rows + 2, cols + 1] += scale * v[0]


@njit(cache=True)
def _cross_rows(v, G, out, row0, scale):
    """out[row0:row0+3, :] += scale [v]x G (G (3, m), out (>= row0 + 3, m), both 2-d)."""
    for col in range(G.shape[1]):
        out[row0 + 0, col] += scale * (v[1] * G[2, col] - v[2] * G[1, col])
        out[row0 + 1, col] += scale * (v[2] * G[0, col] - v[0] * G[2, col])
        out[row0 + 2, col] += scale * (v[0] * G[1, col] - v[1] * G[0, col])


@njit(cache=True)
def reeving_tangent(rv_sde, rv_kind, rv_att, rv_rfe, rv_point, rv_slip, sde_left, sde_right, sde_arm_left,
                    sde_arm_right, R, rbase, roff, sde_point, att_p, att_R, tension, e, fdir, K, Kd, rv_K, rv_Kd):
    """The pulls' tangent (module text): rv_K, rv_Kd (nv, 12, 18) = -d(force)/dx, -d(force)/dv
    of reeving j, rows: the force and moment on the sheave's RFE a (0-5) and on the lead's
    RFE f (6-11, a line-end lead), columns: the spatial (dr, da) of RFE a (0-5), of the
    rope's first RFE b (6-11) and of f (12-17). K, Kd: the join tangents (nsde, 12, 12,
    ``rfesim.loads.sde_tangent`` and ``slip_tangent``), read for the tension's dependence on
    the join. Zero for a reeving without tension (its pull is zero)."""
    GP = np.zeros((3, 18))          # dP/dx, the sheave P (the join SDE's point)
    GL = np.zeros((3, 18))          # dL/dx, the lead
    GF = np.zeros((3, 18))          # dF_a/dx, the pull on a
    Gc = np.zeros((3, 18))          # d(P - r_a)/dx
    Gl = np.zeros((3, 18))          # d(l)/dx, the lead's arm from its RFE's centre
    pa = np.zeros(3)
    pb = np.zeros(3)
    lv = np.zeros(3)
    c = np.zeros(3)
    Fa = np.zeros(3)
    for j in range(rv_sde.shape[0]):
        for r in range(12):
            for col in range(18):
                rv_K[j, r, col] = 0.0
                rv_Kd[j, r, col] = 0.0
        T = tension[j]
        if T <= 0.0:
            continue
        s = rv_sde[j]
        a = sde_left[s]
        b = sde_right[s]
        for k in range(3):
            pa[k] = R[a, k, 0] * sde_arm_left[s, 0] + R[a, k, 1] * sde_arm_left[s, 1] + R[a, k, 2] * sde_arm_left[s, 2]
            pb[k] = (R[b, k, 0] * sde_arm_right[s, 0] + R[b, k, 1] * sde_arm_right[s, 1]
                     + R[b, k, 2] * sde_arm_right[s, 2])
            c[k] = sde_point[s, k] - (rbase[a, k] + roff[a, k])
            Fa[k] = T * e[j, k]
        GP[:, :] = 0.0
        GL[:, :] = 0.0
        Gl[:, :] = 0.0
        # P = (r_a + p_a + r_b + p_b) / 2, dp = da x p = -[p]x da
        for k in range(3):
            GP[k, k] += 0.5
            GP[k, 6 + k] += 0.5
        _skew_into(pa, GP, 0, 3, -0.5)
        _skew_into(pb, GP, 0, 9, -0.5)
        if rv_slip[j] == 1:
            # the slip lengthens the join's arm on the rope along X_b by d(delta) = -e . dP_a
            # (a fixed lead; rfesim.loads.reeving.slip_arms), which moves P by X_b d(delta) / 2
            for col in range(6):
                if col < 3:
                    dd = -e[j, col]
                else:
                    m = col - 3             # -e . (da x p_a) = -(p_a x e) . da
                    m1 = (m + 1) % 3
                    m2 = (m + 2) % 3
                    dd = -(pa[m1] * e[j, m2] - pa[m2] * e[j, m1])
                for k in range(3):
                    GP[k, col] += 0.5 * R[b, k, 0] * dd
        lead = rv_kind[j] == KIND_LINE_END
        f = rv_rfe[j]
        if lead:
            for k in range(3):
                lv[k] = R[f, k, 0] * rv_point[j, 0] + R[f, k, 1] * rv_point[j, 1] + R[f, k, 2] * rv_point[j, 2]
                GL[k, 12 + k] = 1.0
            _skew_into(lv, GL, 0, 15, -1.0)
            _skew_into(lv, Gl, 0, 15, -1.0)
        # the run's length d = |L - P|
        if lead:
            L0 = rbase[f, 0] + roff[f, 0] + lv[0]
            L1 = rbase[f, 1] + roff[f, 1] + lv[1]
            L2 = rbase[f, 2] + roff[f, 2] + lv[2]
        else:
            L0, L1, L2 = _attached_point(att_p, att_R, rv_att[j], rv_point, j)
        d = math.sqrt((L0 - sde_point[s, 0]) ** 2 + (L1 - sde_point[s, 1]) ** 2 + (L2 - sde_point[s, 2]) ** 2)
        # dT = (f/T) . df = -(f/T)^T K[s, 0:3] dx over the join's columns (a, b)
        for col in range(18):
            # dF_a = e dT + T (I - e e^T)/d (dL - dP)
            w0 = GL[0, col] - GP[0, col]
            w1 = GL[1, col] - GP[1, col]
            w2 = GL[2, col] - GP[2, col]
            ew = e[j, 0] * w0 + e[j, 1] * w1 + e[j, 2] * w2
            dT = 0.0
            if col < 12:
                dT = -(fdir[j, 0] * K[s, 0, col] + fdir[j, 1] * K[s, 1, col] + fdir[j, 2] * K[s, 2, col])
            for k in range(3):
                w = w0 if k == 0 else (w1 if k == 1 else w2)
                GF[k, col] = e[j, k] * dT + T / d * (w - e[j, k] * ew)
                Gc[k, col] = GP[k, col] - (1.0 if col == k else 0.0)
        # K = -d(force)/dx: on a, F_a = T e and M_a = c x F_a
        for k in range(3):
            for col in range(18):
                rv_K[j, k, col] = -GF[k, col]
        _cross_rows(c, GF, rv_K[j], 3, -1.0)
        _cross_rows(Fa, Gc, rv_K[j], 3, 1.0)        # -(dc x F_a) = F_a x dc
        if lead:
            # on f: -F_a at L, M_f = l x (-F_a)
            for k in range(3):
                for col in range(18):
                    rv_K[j, 6 + k, col] = GF[k, col]
            _cross_rows(lv, GF, rv_K[j], 9, 1.0)
            _cross_rows(Fa, Gl, rv_K[j], 9, -1.0)   # -(dl x (-F_a)) = -(F_a x dl)
        # damping: the tension's dependence on the join's rates (the direction has none)
        for col in range(12):
            u = fdir[j, 0] * Kd[s, 0, col] + fdir[j, 1] * Kd[s, 1, col] + fdir[j, 2] * Kd[s, 2, col]
            if u == 0.0:
                continue
            for k in range(3):
                k1 = (k + 1) % 3
                k2 = (k + 2) % 3
                rv_Kd[j, k, col] = e[j, k] * u
                rv_Kd[j, 3 + k, col] = (c[k1] * e[j, k2] - c[k2] * e[j, k1]) * u
                if lead:
                    rv_Kd[j, 6 + k, col] = -e[j, k] * u
                    rv_Kd[j, 9 + k, col] = -(lv[k1] * e[j, k2] - lv[k2] * e[j, k1]) * u
