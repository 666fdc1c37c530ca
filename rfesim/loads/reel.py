"""Reels: a drum that stores a line wrapped on it and pays it out (or reels it in) as it
turns (eq. 8.95's guiding structures: forces of the mechanism on the RFEs it holds).

Geometry: reel j has its centre C and unit axis a (attachment frame), the radius R of the
pipe axis on the drum (drum radius + pipe outer radius for one layer) and the payout
direction d at the take-off point, normal to a. The take-off point is P0 = C + R n0 with
n0 = a x d; the wrapped pipe runs back from it around the drum: the point at wrap angle
phi (0 at the take-off, growing against the payout) is

    P(phi) = C + R (cos(phi) n0 - sin(phi) d),    tangent (payout sense) cos(phi) d + sin(phi) n0,

and its material coordinate along the payout is sigma = -R phi. An RFE whose centre r,
projected on the drum plane, lies at 0 <= phi <= W (``wrap``, at most 270 deg) is

* pressed against the drum by a unilateral contact spring k_r l (R_c - rho) e_r when its
  distance rho from the axis is below R_c = R cos(l / (2 R)) (the centre of a chord of
  length l whose ends are on the circle of radius R: an element lying on the drum has no
  penetration), e_r the outward radial unit vector;
* held in the drum plane (flanges, the previous wrap) by a lateral spring -k_l l ((r - C).a) a;
* gripped tangentially by a spring-slider to a material anchor that turns with the drum:
  -k_g l (sigma - sigma_a - D) along the tangent, capped at its share F_max l w / sum(l w)
  of the drum's capacity (w the weight below, the sum over the RFEs on the wrap: the shares
  add up to F_max, the most the drum holds; the pipe slips on the drum beyond it);
  D = R * (drum rotation) is the paid-out length.

Every spring (and the cap) is weighted by min(1, R phi / l, R (W - phi) / l): the drum
takes hold of an RFE over one element length after the take-off and lets go over one
before the end of the window, so pipe passing the take-off sees no jump of force. The
payout D is the tensioner's (rfesim.loads.tensioner): a table of D(t), or driven by the
constant-tension characteristic, implicit in the step like a tensioner's. A driven reel
holds the back tension through a fixed offset: its characteristic acts on the drum's own
tangential grip force T_g less Delta_j (the workspace's ``reel_offset``), u(D) = T_g(D) -
Delta_j, and D = D_c + h v(u(D)), solved as a tensioner's (``solve_reel_payout``). T_g
also carries the moment of the pipe leaving the drum (M / R) and the wrap's share, so
statics (``settle_back_tension``, rfesim.solvers.reel_statics) sets Delta_j = T_g -
``back_tension`` once it has settled the tension just off the drum to the back tension:
the run starts in equilibrium, and the back tension is held in the mean (dynamically the
tension off the drum differs from it by the wrap's inertia and the change of M / R).
Without statics, or for a reel without a back tension, Delta_j = 0 and the set point is the
grip force. Why not the tension T_0 just off the drum (as before): it is measured beyond
the mass of the wrapped pipe from the drum (no inertia, on the soft grips), and a payout
proportional to it is a non-collocated integral feedback with no damping term (one mass
m, grips K_g, span K_s: g m s^3 + 0 s^2 + g (K_g + K_s) s + K_g K_s, unstable by
Routh-Hurwitz); the drum's own force gives g m s^3 + m K_g s^2 + ..., stable (a Maxwell
spring-dashpot, passive). The T_0 law also counted the drum's motion twice in the step
(gain + K_g h in effect). The grips and the driven payout are
committed by ``commit_tensioners`` on the reel's own arrays (the trial payout in the
workspace's ``reel_D_trial``). No RFE is created or
deleted: the stored pipe is part of the line.
"""
from __future__ import annotations

import math

from numba import njit

from .tensioner import MAX_PAYOUT_ITERATIONS, MODE_TENSION, payout_newton, payout_speed, tensioner_payout


@njit(cache=True)
def reel_forces(reel_att, reel_centre, reel_axis, reel_dir, reel_radius, reel_wrap, reel_kr, reel_kl, reel_kg,
                reel_cap, reel_line_lo, reel_line_hi, reel_mode, reel_table_t, reel_table_d, reel_table_v,
                reel_count, t, att_p, att_R, rfe_length, r, F, grip_a, grip_on, grip_a_trial, grip_on_trial,
                D_committed, grip_force, reel_set, reel_band, reel_gain, reel_vmax, h_step, reel_offset,
                D_trial):
    """Add the forces of every reel on the RFEs on its wrap to F (at the centres: no
    moment). grip_a/grip_on (n,) committed grip anchors (material coordinate, m) and
    whether each RFE is gripped; the trial values are written. grip_force (nreel,) the
    tangential force each reel carries (N, positive when it holds the line back). h_step: time
    since the last commit (a driven reel's D is solved implicitly over it, from its grip force
    less reel_offset[j] (nreel,), the workspace's reel_offset, and kept in D_trial[j] (nreel,),
    the workspace's reel_D_trial)."""
    for j in range(reel_centre.shape[0]):
        at = reel_att[j]
        Ra = att_R[at]
        # centre, axis, payout direction and take-off radius n0 = a x d in the global frame
        cx = att_p[at, 0] + Ra[0, 0] * reel_centre[j, 0] + Ra[0, 1] * reel_centre[j, 1] + Ra[0, 2] * reel_centre[j, 2]
        cy = att_p[at, 1] + Ra[1, 0] * reel_centre[j, 0] + Ra[1, 1] * reel_centre[j, 1] + Ra[1, 2] * reel_centre[j, 2]
        cz = att_p[at, 2] + Ra[2, 0] * reel_centre[j, 0] + Ra[2, 1] * reel_centre[j, 1] + Ra[2, 2] * reel_centre[j, 2]
        ax = Ra[0, 0] * reel_axis[j, 0] + Ra[0, 1] * reel_axis[j, 1] + Ra[0, 2] * reel_axis[j, 2]
        ay = Ra[1, 0] * reel_axis[j, 0] + Ra[1, 1] * reel_axis[j, 1] + Ra[1, 2] * reel_axis[j, 2]
        az = Ra[2, 0] * reel_axis[j, 0] + Ra[2, 1] * reel_axis[j, 1] + Ra[2, 2] * reel_axis[j, 2]
        dx_ = Ra[0, 0] * reel_dir[j, 0] + Ra[0, 1] * reel_dir[j, 1] + Ra[0, 2] * reel_dir[j, 2]
        dy_ = Ra[1, 0] * reel_dir[j, 0] + Ra[1, 1] * reel_dir[j, 1] + Ra[1, 2] * reel_dir[j, 2]
        dz_ = Ra[2, 0] * reel_dir[j, 0] + Ra[2, 1] * reel_dir[j, 1] + Ra[2, 2] * reel_dir[j, 2]
        nx = ay * dz_ - az * dy_
        ny = az * dx_ - ax * dz_
        nz = ax * dy_ - ay * dx_
        R = reel_radius[j]
        W = reel_wrap[j]
        # the RFEs on the wrap: their range and summed weighted length (the capacity's shares)
        first = reel_line_hi[j]
        last = reel_line_lo[j]
        held = 0.0
        for i in range(reel_line_lo[j], reel_line_hi[j]):
            phi, rho, h_, c, s, ex, ey, ez = _wrap_angle(r, i, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R)
            li = rfe_length[i]
            wgt = wrap_weight(phi, rho, R, W, li)
            if wgt <= 0.0:
                continue
            held += li * wgt
            first = min(first, i)
            last = max(last, i + 1)
        cap_share = reel_cap[j] / held if held > 0.0 else 0.0
        D = tensioner_payout(reel_mode, reel_table_t, reel_table_d, reel_table_v, reel_count, j, t, D_committed)
        if reel_mode[j] == MODE_TENSION:
            if h_step > 0.0 and first < last:
                # the law on the drum's own grip force less the offset statics fixed (module text)
                D = solve_reel_payout(D, h_step, -reel_offset[j], reel_set[j], reel_band[j], reel_gain[j],
                                      reel_vmax[j], first, last, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz,
                                      R, W, reel_kg[j], cap_share, rfe_length, r, grip_a, grip_on)
            elif h_step > 0.0:
                v, dv = payout_speed(0.0, reel_set[j], reel_band[j], reel_gain[j], reel_vmax[j])
                D += h_step * v
            D_trial[j] = D
        total = 0.0
        for i in range(reel_line_lo[j], reel_line_hi[j]):
            px = r[i, 0] - cx
            py = r[i, 1] - cy
            pz = r[i, 2] - cz
            h = px * ax + py * ay + pz * az             # out of the drum plane
            ex = px - h * ax
            ey = py - h * ay
            ez = pz - h * az
            rho = math.sqrt(ex * ex + ey * ey + ez * ez)
            if rho < 1e-9 * R:
                grip_on_trial[i] = 0
                continue
            ex /= rho
            ey /= rho
            ez /= rho
            c = ex * nx + ey * ny + ez * nz             # cos(phi)
            s = -(ex * dx_ + ey * dy_ + ez * dz_)       # sin(phi)
            phi = math.atan2(s, c)
            if phi < -0.5 * math.pi:
                phi += 2.0 * math.pi
            if phi < 0.0 or phi > W:
                grip_on_trial[i] = 0
                continue
            li = rfe_length[i]
            wgt = min(1.0, R * phi / li, R * (W - phi) / li)
            if wgt <= 0.0:
                grip_on_trial[i] = 0
                continue
            # radial: unilateral contact with the drum (a chord of length l on the circle)
            pen = R * math.cos(0.5 * li / R) - rho
            if pen > 0.0:
                kr = reel_kr[j] * li * wgt * pen
                F[i, 0] += kr * ex
                F[i, 1] += kr * ey
                F[i, 2] += kr * ez
            # lateral: back into the drum plane
            kl = reel_kl[j] * li * wgt * h
            F[i, 0] -= kl * ax
            F[i, 1] -= kl * ay
            F[i, 2] -= kl * az
            # tangential grip: spring-slider against the material anchor turning with the drum
            sigma = -R * phi
            kg = reel_kg[j] * li * wgt
            if grip_on[i] == 0:
                anchor = sigma - D                      # comes onto the wrap: gripped where it is
                f = 0.0
            else:
                anchor = grip_a[i]
                f = -kg * (sigma - anchor - D)
                cap = cap_share * li * wgt
                if f > cap:
                    f = cap
                    anchor = sigma - D + f / kg
                elif f < -cap:
                    f = -cap
                    anchor = sigma - D + f / kg
            grip_a_trial[i] = anchor
            grip_on_trial[i] = 1
            tx = c * dx_ + s * nx
            ty = c * dy_ + s * ny
            tz = c * dz_ + s * nz
            F[i, 0] += f * tx
            F[i, 1] += f * ty
            F[i, 2] += f * tz
            total -= f
        grip_force[j] = total


@njit(cache=True)
def solve_reel_payout(D0, h, offset, T_set, band, gain, vmax, lo, hi, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny,
                      nz, R, W, kg_j, cap_share, rfe_length, r, grip_a, grip_on):
    """D = D0 + h v(offset + T_g(D)) for a driven reel (module text): the implicit payout, as
    ``solve_driven_payout`` for a tensioner's track."""
    a = D0 - h * vmax - 1e-12
    b = D0 + h * vmax + 1e-12
    D = D0
    for _ in range(MAX_PAYOUT_ITERATIONS):
        T, k = _reel_grip(D, lo, hi, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R, W, kg_j, cap_share,
                          rfe_length, r, grip_a, grip_on)
        g, Dn, a, b = payout_newton(D, D0, h, offset + T, k, T_set, band, gain, vmax, a, b)
        if abs(g) <= 1e-12 * (1.0 + abs(D)) or b - a <= 1e-14 * (1.0 + abs(D)):
            break
        D = Dn
    return D


@njit(cache=True)
def _wrap_angle(r, i, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R):
    """(phi, rho, h, cos phi, sin phi, e_r) of RFE i on the drum (the geometry of ``reel_forces``)."""
    px = r[i, 0] - cx
    py = r[i, 1] - cy
    pz = r[i, 2] - cz
    h = px * ax + py * ay + pz * az
    ex = px - h * ax
    ey = py - h * ay
    ez = pz - h * az
    rho = math.sqrt(ex * ex + ey * ey + ez * ez)
    if rho < 1e-9 * R:
        return 0.0, rho, h, 1.0, 0.0, 0.0, 0.0, 0.0
    ex /= rho
    ey /= rho
    ez /= rho
    c = ex * nx + ey * ny + ez * nz
    s = -(ex * dx_ + ey * dy_ + ez * dz_)
    phi = math.atan2(s, c)
    if phi < -0.5 * math.pi:
        phi += 2.0 * math.pi
    return phi, rho, h, c, s, ex, ey, ez


@njit(cache=True)
def wrap_weight(phi, rho, R, W, li):
    """The drum's hold on an RFE of length li at the wrap angle phi (distance rho from the
    axis) on a wrap of W rad: min(1, R phi / li, R (W - phi) / li), 0 off the wrap."""
    if rho < 1e-9 * R or phi < 0.0 or phi > W:
        return 0.0
    return max(0.0, min(1.0, R * phi / li, R * (W - phi) / li))


@njit(cache=True)
def _reel_grip(D, lo, hi, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R, W, kg_j, cap_share, rfe_length, r,
               grip_a, grip_on):
    """(T, k): the tangential force the gripped RFEs on the wrap carry with the drum at D
    (the grip law of ``reel_forces``) and -dT/dD."""
    T = 0.0
    k = 0.0
    for i in range(lo, hi):
        if grip_on[i] == 0:
            continue
        phi, rho, h, c, s, ex, ey, ez = _wrap_angle(r, i, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R)
        li = rfe_length[i]
        wgt = wrap_weight(phi, rho, R, W, li)
        if wgt <= 0.0:
            continue
        kg = kg_j * li * wgt
        cap = cap_share * li * wgt
        f = kg * (-R * phi - grip_a[i] - D)
        if f > cap:
            f = cap
        elif f < -cap:
            f = -cap
        else:
            k += kg
        T += f
    return T, k
