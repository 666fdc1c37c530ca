"""The SDE kernel of every evaluation in scalar form (``sde_forces_rest_fused``); the
readable reference is ``rfesim.loads.sde.sde_forces_rest_into``."""
from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def sde_forces_rest_fused(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                     rest_static, rest_eff, rest_rate, R, rbase, roff, v, w, F, M, eps_out, sigma_out, point_out):
    """``rfesim.loads.sde.sde_forces_rest_into`` (same arguments but the scratch, same
    results to the bit) written with scalar locals: no array views, no calls per SDE. The
    readable kernel creates a dozen array views and calls five helpers per SDE, and their
    reference counting cost three times the arithmetic (0.061 against 0.016 ms for the
    100 SDEs of the crane benchmark). Checked against it in tests/unit/test_fused_kernels.py."""
    has_flags = rest_flag.shape[0] > 0
    for s in range(sde_left.shape[0]):
        a = sde_left[s]
        b = sde_right[s]
        fl = 0
        if has_flags:
            fl = rest_flag[s]
        # R_a, R_b
        a00 = R[a, 0, 0]; a01 = R[a, 0, 1]; a02 = R[a, 0, 2]
        a10 = R[a, 1, 0]; a11 = R[a, 1, 1]; a12 = R[a, 1, 2]
        a20 = R[a, 2, 0]; a21 = R[a, 2, 1]; a22 = R[a, 2, 2]
        b00 = R[b, 0, 0]; b01 = R[b, 0, 1]; b02 = R[b, 0, 2]
        b10 = R[b, 1, 0]; b11 = R[b, 1, 1]; b12 = R[b, 1, 2]
        b20 = R[b, 2, 0]; b21 = R[b, 2, 1]; b22 = R[b, 2, 2]
        # arms pa = R_a arm_a, pb = R_b arm_b
        x0 = sde_arm_left[s, 0]; x1 = sde_arm_left[s, 1]; x2 = sde_arm_left[s, 2]
        pa0 = a00 * x0 + a01 * x1 + a02 * x2
        pa1 = a10 * x0 + a11 * x1 + a12 * x2
        pa2 = a20 * x0 + a21 * x1 + a22 * x2
        x0 = sde_arm_right[s, 0]; x1 = sde_arm_right[s, 1]; x2 = sde_arm_right[s, 2]
        pb0 = b00 * x0 + b01 * x1 + b02 * x2
        pb1 = b10 * x0 + b11 * x1 + b12 * x2
        pb2 = b20 * x0 + b21 * x1 + b22 * x2
        g0 = (rbase[b, 0] - rbase[a, 0]) + (roff[b, 0] - roff[a, 0]) + (pb0 - pa0)
        g1 = (rbase[b, 1] - rbase[a, 1]) + (roff[b, 1] - roff[a, 1]) + (pb1 - pa1)
        g2 = (rbase[b, 2] - rbase[a, 2]) + (roff[b, 2] - roff[a, 2]) + (pb2 - pa2)
        # R_a* = R_a R0 (rest rotation) or R_a
        if fl == 0:
            c00 = a00; c01 = a01; c02 = a02
            c10 = a10; c11 = a11; c12 = a12
            c20 = a20; c21 = a21; c22 = a22
        else:
            if fl == 1:
                r00 = rest_static[s, 0, 0]; r01 = rest_static[s, 0, 1]; r02 = rest_static[s, 0, 2]
                r10 = rest_static[s, 1, 0]; r11 = rest_static[s, 1, 1]; r12 = rest_static[s, 1, 2]
                r20 = rest_static[s, 2, 0]; r21 = rest_static[s, 2, 1]; r22 = rest_static[s, 2, 2]
            else:
                r00 = rest_eff[s, 0, 0]; r01 = rest_eff[s, 0, 1]; r02 = rest_eff[s, 0, 2]
                r10 = rest_eff[s, 1, 0]; r11 = rest_eff[s, 1, 1]; r12 = rest_eff[s, 1, 2]
                r20 = rest_eff[s, 2, 0]; r21 = rest_eff[s, 2, 1]; r22 = rest_eff[s, 2, 2]
            c00 = a00 * r00 + a01 * r10 + a02 * r20
            c01 = a00 * r01 + a01 * r11 + a02 * r21
            c02 = a00 * r02 + a01 * r12 + a02 * r22
            c10 = a10 * r00 + a11 * r10 + a12 * r20
            c11 = a10 * r01 + a11 * r11 + a12 * r21
            c12 = a10 * r02 + a11 * r12 + a12 * r22
            c20 = a20 * r00 + a21 * r10 + a22 * r20
            c21 = a20 * r01 + a21 * r11 + a22 * r21
            c22 = a20 * r02 + a21 * r12 + a22 * r22
        # Rrel = R_a*^T R_b
        e00 = c00 * b00 + c10 * b10 + c20 * b20
        e01 = c00 * b01 + c10 * b11 + c20 * b21
        e02 = c00 * b02 + c10 * b12 + c20 * b22
        e10 = c01 * b00 + c11 * b10 + c21 * b20
        e11 = c01 * b01 + c11 * b11 + c21 * b21
        e12 = c01 * b02 + c11 * b12 + c21 * b22
        e20 = c02 * b00 + c12 * b10 + c22 * b20
        e21 = c02 * b01 + c12 * b11 + c22 * b21
        e22 = c02 * b02 + c12 * b12 + c22 * b22
        # quaternion (Shepperd), w >= 0
        tr = e00 + e11 + e22
        if tr >= e00 and tr >= e11 and tr >= e22:
            sq = math.sqrt(1.0 + tr) * 2.0
            qw = 0.25 * sq
            qx = (e21 - e12) / sq
            qy = (e02 - e20) / sq
            qz = (e10 - e01) / sq
        elif e00 >= e11 and e00 >= e22:
            sq = math.sqrt(1.0 + e00 - e11 - e22) * 2.0
            qw = (e21 - e12) / sq
            qx = 0.25 * sq
            qy = (e01 + e10) / sq
            qz = (e02 + e20) / sq
        elif e11 >= e22:
            sq = math.sqrt(1.0 + e11 - e00 - e22) * 2.0
            qw = (e02 - e20) / sq
            qx = (e01 + e10) / sq
            qy = 0.25 * sq
            qz = (e12 + e21) / sq
        else:
            sq = math.sqrt(1.0 + e22 - e00 - e11) * 2.0
            qw = (e10 - e01) / sq
            qx = (e02 + e20) / sq
            qy = (e12 + e21) / sq
            qz = 0.25 * sq
        if qw < 0.0:
            qw = -qw
            qx = -qx
            qy = -qy
            qz = -qz
        nq = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
        qw = qw / nq
        qx = qx / nq
        qy = qy / nq
        qz = qz / nq
        s2 = qx * qx + qy * qy + qz * qz
        sn = math.sqrt(s2)
        angle = 2.0 * math.atan2(sn, qw)
        if sn > 1e-300:
            f = angle / sn
        else:
            f = 2.0
        t0 = f * qx
        t1 = f * qy
        t2 = f * qz
        th2 = angle * angle
        nh = math.sqrt(2.0 * (1.0 + qw))
        hw = (1.0 + qw) / nh
        hx = qx / nh
        hy = qy / nh
        hz = qz / nh
        h00 = 1.0 - 2.0 * (hy * hy + hz * hz)
        h11 = 1.0 - 2.0 * (hx * hx + hz * hz)
        h22 = 1.0 - 2.0 * (hx * hx + hy * hy)
        h01 = 2.0 * (hx * hy - hz * hw)
        h10 = 2.0 * (hx * hy + hz * hw)
        h02 = 2.0 * (hx * hz + hy * hw)
        h20 = 2.0 * (hx * hz - hy * hw)
        h12 = 2.0 * (hy * hz - hx * hw)
        h21 = 2.0 * (hy * hz + hx * hw)
        if angle < 2e-2:
            cc = 1.0 / 12.0 + th2 / 720.0 + th2 * th2 / 30240.0
        else:
            cc = 1.0 / th2 - qw / (2.0 * angle * sn)
        ph = 0.5 * angle
        ph2 = ph * ph
        if ph < 1e-2:
            ca = 0.5 - ph2 / 24.0 + ph2 * ph2 / 720.0
            cb = 1.0 / 6.0 - ph2 / 120.0 + ph2 * ph2 / 5040.0
        else:
            ca = s2 / ((1.0 + qw) * ph2)
            cb = (ph - sn) / (ph2 * ph)
        # J_r^-1(theta)
        dg = 1.0 - cc * th2
        i00 = cc * t0 * t0 + dg
        i11 = cc * t1 * t1 + dg
        i22 = cc * t2 * t2 + dg
        i01 = cc * t0 * t1 - 0.5 * t2
        i10 = cc * t1 * t0 + 0.5 * t2
        i02 = cc * t0 * t2 + 0.5 * t1
        i20 = cc * t2 * t0 - 0.5 * t1
        i12 = cc * t1 * t2 - 0.5 * t0
        i21 = cc * t2 * t1 + 0.5 * t0
        # J_r(theta/2)
        u0 = 0.5 * t0
        u1 = 0.5 * t1
        u2 = 0.5 * t2
        dh = 1.0 - cb * ph2
        j00 = cb * u0 * u0 + dh
        j11 = cb * u1 * u1 + dh
        j22 = cb * u2 * u2 + dh
        j01 = cb * u0 * u1 + ca * u2
        j10 = cb * u1 * u0 - ca * u2
        j02 = cb * u0 * u2 - ca * u1
        j20 = cb * u2 * u0 + ca * u1
        j12 = cb * u1 * u2 + ca * u0
        j21 = cb * u2 * u1 - ca * u0
        # mean frame Rp = R_a* Rh
        p00 = c00 * h00 + c01 * h10 + c02 * h20
        p01 = c00 * h01 + c01 * h11 + c02 * h21
        p02 = c00 * h02 + c01 * h12 + c02 * h22
        p10 = c10 * h00 + c11 * h10 + c12 * h20
        p11 = c10 * h01 + c11 * h11 + c12 * h21
        p12 = c10 * h02 + c11 * h12 + c12 * h22
        p20 = c20 * h00 + c21 * h10 + c22 * h20
        p21 = c20 * h01 + c21 * h11 + c22 * h21
        p22 = c20 * h02 + c21 * h12 + c22 * h22
        # dlt = Rp^T g
        d0 = p00 * g0 + p10 * g1 + p20 * g2
        d1 = p01 * g0 + p11 * g1 + p21 * g2
        d2 = p02 * g0 + p12 * g1 + p22 * g2
        # rates
        wa0 = w[a, 0]; wa1 = w[a, 1]; wa2 = w[a, 2]
        wb0 = w[b, 0]; wb1 = w[b, 1]; wb2 = w[b, 2]
        if fl == 2:
            x0 = rest_rate[s, 0]; x1 = rest_rate[s, 1]; x2 = rest_rate[s, 2]
            wr0 = a00 * x0 + a01 * x1 + a02 * x2
            wr1 = a10 * x0 + a11 * x1 + a12 * x2
            wr2 = a20 * x0 + a21 * x1 + a22 * x2
        else:
            wr0 = 0.0
            wr1 = 0.0
            wr2 = 0.0
        gd0 = v[b, 0] + (wb1 * pb2 - wb2 * pb1) - v[a, 0] - (wa1 * pa2 - wa2 * pa1)
        gd1 = v[b, 1] + (wb2 * pb0 - wb0 * pb2) - v[a, 1] - (wa2 * pa0 - wa0 * pa2)
        gd2 = v[b, 2] + (wb0 * pb1 - wb1 * pb0) - v[a, 2] - (wa0 * pa1 - wa1 * pa0)
        dw0 = wb0 - wa0 - wr0
        dw1 = wb1 - wa1 - wr1
        dw2 = wb2 - wa2 - wr2
        # thdot = Jri Rb^T dw
        x0 = b00 * dw0 + b10 * dw1 + b20 * dw2
        x1 = b01 * dw0 + b11 * dw1 + b21 * dw2
        x2 = b02 * dw0 + b12 * dw1 + b22 * dw2
        td0 = i00 * x0 + i01 * x1 + i02 * x2
        td1 = i10 * x0 + i11 * x1 + i12 * x2
        td2 = i20 * x0 + i21 * x1 + i22 * x2
        # wp = w_a + wr + 1/2 Rp Jrh thdot
        x0 = j00 * td0 + j01 * td1 + j02 * td2
        x1 = j10 * td0 + j11 * td1 + j12 * td2
        x2 = j20 * td0 + j21 * td1 + j22 * td2
        wp0 = wa0 + wr0 + 0.5 * (p00 * x0 + p01 * x1 + p02 * x2)
        wp1 = wa1 + wr1 + 0.5 * (p10 * x0 + p11 * x1 + p12 * x2)
        wp2 = wa2 + wr2 + 0.5 * (p20 * x0 + p21 * x1 + p22 * x2)
        # dltdot = Rp^T (gdot + g x wp)
        x0 = (g1 * wp2 - g2 * wp1) + gd0
        x1 = (g2 * wp0 - g0 * wp2) + gd1
        x2 = (g0 * wp1 - g1 * wp0) + gd2
        dd0 = p00 * x0 + p10 * x1 + p20 * x2
        dd1 = p01 * x0 + p11 * x1 + p21 * x2
        dd2 = p02 * x0 + p12 * x1 + p22 * x2
        Fp0 = sde_stiffness[s, 0] * d0 + sde_damping[s, 0] * dd0
        Fp1 = sde_stiffness[s, 1] * d1 + sde_damping[s, 1] * dd1
        Fp2 = sde_stiffness[s, 2] * d2 + sde_damping[s, 2] * dd2
        Mp0 = sde_stiffness[s, 3] * t0 + sde_damping[s, 3] * td0
        Mp1 = sde_stiffness[s, 4] * t1 + sde_damping[s, 4] * td1
        Mp2 = sde_stiffness[s, 5] * t2 + sde_damping[s, 5] * td2
        eps_out[s, 0] = d0
        eps_out[s, 1] = d1
        eps_out[s, 2] = d2
        eps_out[s, 3] = t0
        eps_out[s, 4] = t1
        eps_out[s, 5] = t2
        sigma_out[s, 0] = Fp0
        sigma_out[s, 1] = Fp1
        sigma_out[s, 2] = Fp2
        sigma_out[s, 3] = Mp0
        sigma_out[s, 4] = Mp1
        sigma_out[s, 5] = Mp2
        point_out[s, 0] = rbase[a, 0] + roff[a, 0] + pa0 + 0.5 * g0
        point_out[s, 1] = rbase[a, 1] + roff[a, 1] + pa1 + 0.5 * g1
        point_out[s, 2] = rbase[a, 2] + roff[a, 2] + pa2 + 0.5 * g2
        # mg = Rb Jri^T Mp
        x0 = i00 * Mp0 + i10 * Mp1 + i20 * Mp2
        x1 = i01 * Mp0 + i11 * Mp1 + i21 * Mp2
        x2 = i02 * Mp0 + i12 * Mp1 + i22 * Mp2
        mg0 = b00 * x0 + b01 * x1 + b02 * x2
        mg1 = b10 * x0 + b11 * x1 + b12 * x2
        mg2 = b20 * x0 + b21 * x1 + b22 * x2
        # Fg = Rp Fp ; h = Fg x g
        Fg0 = p00 * Fp0 + p01 * Fp1 + p02 * Fp2
        Fg1 = p10 * Fp0 + p11 * Fp1 + p12 * Fp2
        Fg2 = p20 * Fp0 + p21 * Fp1 + p22 * Fp2
        hh0 = Fg1 * g2 - Fg2 * g1
        hh1 = Fg2 * g0 - Fg0 * g2
        hh2 = Fg0 * g1 - Fg1 * g0
        # wth = Rb Jri^T Jrh^T Rp^T h
        x0 = p00 * hh0 + p10 * hh1 + p20 * hh2
        x1 = p01 * hh0 + p11 * hh1 + p21 * hh2
        x2 = p02 * hh0 + p12 * hh1 + p22 * hh2
        y0 = j00 * x0 + j10 * x1 + j20 * x2
        y1 = j01 * x0 + j11 * x1 + j21 * x2
        y2 = j02 * x0 + j12 * x1 + j22 * x2
        x0 = i00 * y0 + i10 * y1 + i20 * y2
        x1 = i01 * y0 + i11 * y1 + i21 * y2
        x2 = i02 * y0 + i12 * y1 + i22 * y2
        wt0 = b00 * x0 + b01 * x1 + b02 * x2
        wt1 = b10 * x0 + b11 * x1 + b12 * x2
        wt2 = b20 * x0 + b21 * x1 + b22 * x2
        # pb x Fg, pa x Fg
        cb0 = pb1 * Fg2 - pb2 * Fg1
        cb1 = pb2 * Fg0 - pb0 * Fg2
        cb2 = pb0 * Fg1 - pb1 * Fg0
        ca0 = pa1 * Fg2 - pa2 * Fg1
        ca1 = pa2 * Fg0 - pa0 * Fg2
        ca2 = pa0 * Fg1 - pa1 * Fg0
        F[b, 0] -= Fg0
        F[b, 1] -= Fg1
        F[b, 2] -= Fg2
        F[a, 0] += Fg0
        F[a, 1] += Fg1
        F[a, 2] += Fg2
        M[b, 0] += -cb0 - mg0 - 0.5 * wt0
        M[b, 1] += -cb1 - mg1 - 0.5 * wt1
        M[b, 2] += -cb2 - mg2 - 0.5 * wt2
        M[a, 0] += ca0 + mg0 - hh0 + 0.5 * wt0
        M[a, 1] += ca1 + mg1 - hh1 + 0.5 * wt1
        M[a, 2] += ca2 + mg2 - hh2 + 0.5 * wt2
