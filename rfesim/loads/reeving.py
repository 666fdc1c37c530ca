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

Jacobian (``reeving_tangent``): T depends on the join's deformation through the same SDE,
so dT = f^T df / T and the pull's rows of the join tangent are e (f/T)^T times its force rows
(and P - r_a cross that for the moment): the coupling between the parent's last RFE and the
rope's first, which sit next to each other in the block-tridiagonal Jacobian. Left out of
the Jacobian: the turning of e with P and L (of order T/|L - P|, small against the rope's
axial stiffness) and, for a line-end lead, the pull on the lead RFE (its RFE is not a
neighbour of the join's; it is a boom foot held by a stiff joint, so Newton stays fast).
"""
from __future__ import annotations

import math

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
            at = rv_att[j]
            L0 = att_p[at, 0] + att_R[at, 0, 0] * rv_point[j, 0] + att_R[at, 0, 1] * rv_point[j, 1] + \
                att_R[at, 0, 2] * rv_point[j, 2]
            L1 = att_p[at, 1] + att_R[at, 1, 0] * rv_point[j, 0] + att_R[at, 1, 1] * rv_point[j, 1] + \
                att_R[at, 1, 2] * rv_point[j, 2]
            L2 = att_p[at, 2] + att_R[at, 2, 0] * rv_point[j, 0] + att_R[at, 2, 1] * rv_point[j, 1] + \
                att_R[at, 2, 2] * rv_point[j, 2]
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
def reeving_tangent(rv_sde, sde_left, rbase, roff, sde_point, tension, e, fdir, K, Kd):
    """Add the pull's dependence on the join's deformation to the join tangents K, Kd
    (nsde, 12, 12; K = -df/dx of ``rfesim.loads.sde_tangent``): the parent's rows (0-5)
    get e (f/T)^T times its force rows 0-2, and the arm P - r_a cross that."""
    for j in range(rv_sde.shape[0]):
        if tension[j] <= 0.0:
            continue
        s = rv_sde[j]
        a = sde_left[s]
        cx = sde_point[s, 0] - (rbase[a, 0] + roff[a, 0])
        cy = sde_point[s, 1] - (rbase[a, 1] + roff[a, 1])
        cz = sde_point[s, 2] - (rbase[a, 2] + roff[a, 2])
        ex = e[j, 0]
        ey = e[j, 1]
        ez = e[j, 2]
        mx = cy * ez - cz * ey       # c x e
        my = cz * ex - cx * ez
        mz = cx * ey - cy * ex
        for which in range(2):
            A = K if which == 0 else Kd
            for col in range(12):
                u = fdir[j, 0] * A[s, 0, col] + fdir[j, 1] * A[s, 1, col] + fdir[j, 2] * A[s, 2, col]
                A[s, 0, col] += ex * u
                A[s, 1, col] += ey * u
                A[s, 2, col] += ez * u
                A[s, 3, col] += mx * u
                A[s, 4, col] += my * u
                A[s, 5, col] += mz * u
