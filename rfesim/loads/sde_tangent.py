"""Tangent stiffness and damping of the SDEs (for the implicit solver's Jacobian).

For SDE s between RFEs a and b, with spatial virtual displacements
x = (dr_a, da_a, dr_b, da_b) (da: small rotation, dR = [da]x R), the deformation rate map
B of ``rfesim.loads.sde`` gives d(eps) = B dx and the generalised forces f = -B^T sigma.
The tangent K = -df/dx is

* material: B^T C B (exact), and B^T D B for the velocity dependence of the damping (both
  symmetric: formed on and above the diagonal);
* geometric: d(B^T sigma)/dx at fixed sigma, from the rotation of F = R' F' with the mean
  frame (angular velocity omega' = (I - W/2) da_a + (W/2) da_b), the arms p x F, the moment
  m = R_b J_r^-T M' (which turns with R_b and changes with theta through J_r^-T,
  ``jr_inv_t_derivative``) and the gap moment h = F x g (in M_a with I - W^T/2, in M_b with
  W^T/2). The one term left out is the change of W in W^T h: h is O(|F| |g|), the force
  times the gap of a stiff spring, so the tangent is exact to that order at any relative
  rotation theta. (Taking W = J_r = I, as it was until 2026-11, is an error of order theta:
  harmless between neighbouring RFEs of a line, but a pin between a rope's end and a
  payload turned 90 deg from it gave the payload's free yaw a false stiffness coupling of
  O(|F|), docs/theory.md, 'The SDE tangent'.)

Rest rotations (``rfesim.loads.sde.sde_geometry_rest``): the spatial variation of
R_a* = R_a R0 is that of R_a (d R_a* = [da_a]x R_a*, i.e. R_a* [R0^T R_a^T da_a]x), so B
and the geometric terms keep their form with the geometry (R', J_r, W) of R_a*; the
tangent is as exact with rest rotations as without. The position dependence of the drive
rate R_a omega0 in the damping (a velocity-level term) is left out, like the position
dependence of the other damping terms.

Tested against finite differences of ``sde_forces`` in tests/unit/test_sde_tangent.py
(and with rest rotations in tests/unit/test_sde_rest_rotation.py).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kinematics import matmul_into, matvec_into, skew_into
from .sde import sde_geometry_rest


@njit(cache=True, _nrt=True)
def sde_tangent(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, R, rbase, roff,
                sigma, K, Kd):
    """``sde_tangent_rest`` for SDEs straight at rest."""
    sde_tangent_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping,
                     np.zeros(0, np.int64), np.zeros((0, 3, 3)), np.zeros((0, 3, 3)), R, rbase, roff, sigma, K, Kd)


@njit(cache=True, _nrt=True)
def sde_tangent_rest(sde_left, sde_right, sde_arm_left, sde_arm_right, sde_stiffness, sde_damping, rest_flag,
                     rest_static, rest_eff, R, rbase, roff, sigma, K, Kd):
    """K (nsde, 12, 12): tangent stiffness -df/dx; Kd (nsde, 12, 12): B^T D B.
    ``sigma`` (nsde, 6) are the SDE forces of the evaluated state (F', M' in {i'});
    rest rotations as in ``rfesim.loads.sde.sde_geometry_rest``."""
    B = np.zeros((6, 12))
    Ras = np.empty((3, 3))
    Rrel = np.empty((3, 3))
    Rh = np.empty((3, 3))
    Rp = np.empty((3, 3))
    Jri = np.empty((3, 3))
    Jrh = np.empty((3, 3))
    W = np.empty((3, 3))
    T1 = np.empty((3, 3))
    T2 = np.empty((3, 3))
    Pa = np.empty((3, 3))
    Pb = np.empty((3, 3))
    Gx = np.empty((3, 3))
    Fx = np.empty((3, 3))
    mx = np.empty((3, 3))
    th = np.empty(3)
    pa = np.empty(3)
    pb = np.empty(3)
    g = np.empty(3)
    F = np.empty(3)
    m = np.empty(3)
    tmp = np.empty(3)
    CB = np.empty((6, 12))
    DB = np.empty((6, 12))
    FPa = np.empty((3, 3))
    PaF = np.empty((3, 3))
    FPb = np.empty((3, 3))
    PbF = np.empty((3, 3))
    GF = np.empty((3, 3))
    Wh = np.empty((3, 3))
    FW = np.empty((3, 3))
    PaW = np.empty((3, 3))
    PbW = np.empty((3, 3))
    GW = np.empty((3, 3))
    dh = np.empty((4, 3, 3))
    WTdh = np.empty((4, 3, 3))
    E = np.empty((3, 3))
    Mp = np.empty(3)
    for s in range(sde_left.shape[0]):
        b = sde_right[s]
        Rb = R[b]
        sde_geometry_rest(s, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff, R,
                          rbase, roff, pa, pb, g, Rrel, th, Rh, Rp, Jri, Jrh, Ras)
        # W = Rp Jrh Jri Rb^T
        matmul_into(Jrh, Jri, T1)
        matmul_into(Rp, T1, T2)
        for i in range(3):
            for j in range(3):
                W[i, j] = T2[i, 0] * Rb[j, 0] + T2[i, 1] * Rb[j, 1] + T2[i, 2] * Rb[j, 2]
        skew_into(pa, Pa)
        skew_into(pb, Pb)
        skew_into(g, Gx)
        # ---- B (6 x 12): rows delta' then theta; columns dr_a, da_a, dr_b, da_b
        for i in range(6):
            for j in range(12):
                B[i, j] = 0.0
        for i in range(3):
            for j in range(3):
                G_ij = Rp[j, i]                       # G = Rp^T
                B[i, j] = -G_ij                       # d/dr_a
                B[i, 6 + j] = G_ij                    # d/dr_b
        # d/da_a: G ([pa]x + [g]x (I - W/2)) ; d/da_b: G (-[pb]x + [g]x W / 2)
        for i in range(3):
            for j in range(3):
                ga = Pa[i, j]
                gb = -Pb[i, j]
                for k in range(3):
                    ga += Gx[i, k] * ((1.0 if k == j else 0.0) - 0.5 * W[k, j])
                    gb += Gx[i, k] * 0.5 * W[k, j]
                T1[i, j] = ga
                T2[i, j] = gb
        for i in range(3):
            for j in range(3):
                sa = 0.0
                sb = 0.0
                for k in range(3):
                    sa += Rp[k, i] * T1[k, j]
                    sb += Rp[k, i] * T2[k, j]
                B[i, 3 + j] = sa
                B[i, 9 + j] = sb
        # theta rows: Jri Rb^T (da_b - da_a)
        for i in range(3):
            for j in range(3):
                v = Jri[i, 0] * Rb[j, 0] + Jri[i, 1] * Rb[j, 1] + Jri[i, 2] * Rb[j, 2]
                B[3 + i, 3 + j] = -v
                B[3 + i, 9 + j] = v
        # ---- material parts: B^T C B and B^T D B
        # (C and D diagonal: B^T C B and B^T D B in one pass, each term as C B then B^T (C B);
        # both symmetric, so formed on and above the diagonal and mirrored)
        st = sde_stiffness[s]
        sd = sde_damping[s]
        for i in range(6):
            for j in range(12):
                CB[i, j] = st[i] * B[i, j]
                DB[i, j] = sd[i] * B[i, j]
        for i in range(12):
            for j in range(i, 12):
                acc = 0.0
                accd = 0.0
                for k in range(6):
                    acc += B[k, i] * CB[k, j]
                    accd += B[k, i] * DB[k, j]
                K[s, i, j] = acc
                K[s, j, i] = acc
                Kd[s, i, j] = accd
                Kd[s, j, i] = accd
        # ---- geometric part (sigma fixed), spatial; see the module docstring
        # The mean frame {i'} turns with omega' = (I - W/2) da_a + (W/2) da_b (the angular
        # velocity of sde_forces_rest_into), the gap moment h = F x g enters M_a with
        # I - W^T/2 and M_b with W^T/2 (apply_section_force), and the section moment
        # m = R_b J_r^-T M' turns with R_b and changes with theta through J_r^-T. Taking
        # W = J_r = I here (an error of order theta) left O(theta |F|) in directions with
        # no stiffness of their own: a rope's end pinned to a payload at 90 deg
        # (docs/theory.md, 'The SDE tangent').
        for k in range(3):
            tmp[k] = sigma[s, k]
        matvec_into(Rp, tmp, F)
        for k in range(3):
            Mp[k] = sigma[s, 3 + k]
        for k in range(3):
            tmp[k] = Jri[0, k] * Mp[0] + Jri[1, k] * Mp[1] + Jri[2, k] * Mp[2]
        matvec_into(Rb, tmp, m)                       # m = R_b J_r^-T M' (eq. 8.90.2)
        skew_into(F, Fx)
        skew_into(m, mx)
        # E = R_b d(J_r^-T M')/d(theta) J_r^-1 R_b^T: d m = [da_b]x m + E (da_b - da_a)
        jr_inv_t_derivative(th, Mp, T1)
        matmul_into(T1, Jri, T2)
        matmul_into(Rb, T2, T1)
        for i in range(3):
            for j in range(3):
                E[i, j] = T1[i, 0] * Rb[j, 0] + T1[i, 1] * Rb[j, 1] + T1[i, 2] * Rb[j, 2]
        # helper products: [F]x[pa]x, [pa]x[F]x, [F]x[pb]x, [pb]x[F]x, [g]x[F]x
        matmul_into(Fx, Pa, FPa)
        matmul_into(Pa, Fx, PaF)
        matmul_into(Fx, Pb, FPb)
        matmul_into(Pb, Fx, PbF)
        matmul_into(Gx, Fx, GF)
        for i in range(3):
            for j in range(3):
                Wh[i, j] = 0.5 * W[i, j]
        # omega' maps: X omega' = X (I - W/2) da_a + X (W/2) da_b
        matmul_into(Fx, Wh, FW)
        matmul_into(PaF, Wh, PaW)
        matmul_into(PbF, Wh, PbW)
        matmul_into(GF, Wh, GW)
        # dh = [g]x[F]x omega' + [F]x dg, dg = dr_b - dr_a + [pa]x da_a - [pb]x da_b
        for i in range(3):
            for j in range(3):
                dh[0, i, j] = -Fx[i, j]                            # dr_a
                dh[1, i, j] = GF[i, j] - GW[i, j] + FPa[i, j]      # da_a
                dh[2, i, j] = Fx[i, j]                             # dr_b
                dh[3, i, j] = GW[i, j] - FPb[i, j]                 # da_b
        # W^T/2 dh: the part of dh in M_b (M_a takes the rest, dh - W^T/2 dh)
        for c in range(4):
            for i in range(3):
                for j in range(3):
                    WTdh[c, i, j] = Wh[0, i] * dh[c, 0, j] + Wh[1, i] * dh[c, 1, j] + Wh[2, i] * dh[c, 2, j]
        # rows [-F_a; -M_a; -F_b; -M_b] of d(B^T sigma); columns dr_a, da_a, dr_b, da_b
        for i in range(3):
            for j in range(3):
                fa = Fx[i, j] - FW[i, j]
                fb = FW[i, j]
                # -F_a = -F: d = [F]x omega'
                K[s, i, 3 + j] += fa
                K[s, i, 9 + j] += fb
                # -F_b = +F: d = -[F]x omega'
                K[s, 6 + i, 3 + j] -= fa
                K[s, 6 + i, 9 + j] -= fb
                # -M_a = -pa x F - m + (I - W^T/2) h
                K[s, 3 + i, 3 + j] += -FPa[i, j] + PaF[i, j] - PaW[i, j] + E[i, j]
                K[s, 3 + i, 9 + j] += PaW[i, j] + mx[i, j] - E[i, j]
                # -M_b = pb x F + m + W^T/2 h
                K[s, 9 + i, 9 + j] += FPb[i, j] - PbW[i, j] - mx[i, j] + E[i, j]
                K[s, 9 + i, 3 + j] += -PbF[i, j] + PbW[i, j] - E[i, j]
                for c in range(4):
                    K[s, 3 + i, 3 * c + j] += dh[c, i, j] - WTdh[c, i, j]
                    K[s, 9 + i, 3 * c + j] += WTdh[c, i, j]


@njit(cache=True)
def jr_inv_t_derivative(th, Mp, D):
    """D = d(J_r(theta)^-T M')/d(theta) at fixed M', with J_r^-T = I - [th]x/2 + c [th]x^2,
    c(phi) = 1/phi^2 - cot(phi/2)/(2 phi) (rfesim.kinematics.relative_rotation_terms):
    J_r^-T M' = M' - th x M'/2 + c (th (th.M') - phi^2 M'), so
    D = [M']x/2 + c'/phi u th^T + c ((th.M') I + th M'^T - 2 M' th^T), u = th (th.M') - phi^2 M'."""
    phi2 = th[0] * th[0] + th[1] * th[1] + th[2] * th[2]
    phi = math.sqrt(phi2)
    if phi < 0.1:
        # series: c = 1/12 + phi^2/720 + phi^4/30240 + phi^6/1209600, c'/phi from its derivative
        c = 1.0 / 12.0 + phi2 / 720.0 + phi2 * phi2 / 30240.0 + phi2 * phi2 * phi2 / 1209600.0
        dc = 1.0 / 360.0 + phi2 / 7560.0 + phi2 * phi2 / 201600.0
    else:
        sh = math.sin(0.5 * phi)
        ch = math.cos(0.5 * phi)
        c = 1.0 / phi2 - ch / (2.0 * phi * sh)
        dc = (-2.0 / (phi2 * phi) + 1.0 / (4.0 * phi * sh * sh) + ch / (2.0 * phi2 * sh)) / phi
    tm = th[0] * Mp[0] + th[1] * Mp[1] + th[2] * Mp[2]
    for i in range(3):
        u = th[i] * tm - phi2 * Mp[i]
        for j in range(3):
            D[i, j] = dc * u * th[j] + c * ((tm if i == j else 0.0) + th[i] * Mp[j] - 2.0 * Mp[i] * th[j])
    D[0, 1] += -0.5 * Mp[2]
    D[0, 2] += 0.5 * Mp[1]
    D[1, 0] += 0.5 * Mp[2]
    D[1, 2] += -0.5 * Mp[0]
    D[2, 0] += -0.5 * Mp[1]
    D[2, 1] += 0.5 * Mp[0]
