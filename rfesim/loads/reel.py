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
holds the back tension: its characteristic acts on the tension T_0 of the line just off the
drum (the first SDE past the take-off point: the quantity statics settles to
``back_tension``, rfesim.solvers.reel_statics), not on the drum's tangential force (which
also carries the moment of the pipe leaving the drum, M / R). Inside the step that
tension follows the drum through the grips: u(D) = T_0 + T_g(D) - T_g(D_c), T_g the
tangential grip force, and D = D_c + h v(u(D)). The grips and the driven payout are
committed by ``commit_tensioners`` on the reel's own arrays. No RFE is created or
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
                D_committed, grip_force, reel_set, reel_band, reel_gain, reel_vmax, h_step, sde_left, sde_point,
                sde_sigma):
    """Add the forces of every reel on the RFEs on its wrap to F (at the centres: no
    moment). grip_a/grip_on (n,) committed grip anchors (material coordinate, m) and
    whether each RFE is gripped; the trial values are written. grip_force (nreel,) the
    tangential force each reel carries (N, positive when it holds the line back). h_step: time
    since the last commit (a driven reel's D is solved implicitly over it, from the tension
    sde_sigma[:, 0] of the SDE just past the take-off, and kept in reel_table_d[j, 1])."""
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
            if rho < 1e-9 * R or phi < 0.0 or phi > W:
                continue
            li = rfe_length[i]
            wgt = min(1.0, R * phi / li, R * (W - phi) / li)
            if wgt <= 0.0:
                continue
            held += li * wgt
            first = min(first, i)
            last = max(last, i + 1)
        cap_share = reel_cap[j] / held if held > 0.0 else 0.0
        D = tensioner_payout(reel_mode, reel_table_t, reel_table_d, reel_table_v, reel_count, j, t, D_committed)
        if reel_mode[j] == MODE_TENSION:
            if h_step > 0.0:
                # the tension just off the drum, and the grip force with the drum where it was
                P0x = cx + R * nx
                P0y = cy + R * ny
                P0z = cz + R * nz
                T0 = 0.0
                best = -1.0
                for q in range(sde_left.shape[0]):
                    if sde_left[q] < reel_line_lo[j] or sde_left[q] >= reel_line_hi[j]:
                        continue
                    qx = sde_point[q, 0] - P0x
                    qy = sde_point[q, 1] - P0y
                    qz = sde_point[q, 2] - P0z
                    if qx * dx_ + qy * dy_ + qz * dz_ <= 0.0:
                        continue
                    dist = qx * qx + qy * qy + qz * qz
                    if best < 0.0 or dist < best:
                        best = dist
                        T0 = sde_sigma[q, 0]
                Tg0, k0 = _reel_grip(D, first, last, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R, W,
                                     reel_kg[j], cap_share, rfe_length, r, grip_a, grip_on)
                offset = T0 - Tg0
                D0 = D
                a = D0 - h_step * reel_vmax[j] - 1e-12
                b = D0 + h_step * reel_vmax[j] + 1e-12
                Tg, k = Tg0, k0
                for _ in range(MAX_PAYOUT_ITERATIONS):
                    g, Dn, a, b = payout_newton(D, D0, h_step, offset + Tg, k, reel_set[j], reel_band[j], reel_gain[j],
                                                reel_vmax[j], a, b)
                    if abs(g) <= 1e-12 * (1.0 + abs(D)) or b - a <= 1e-14 * (1.0 + abs(D)):
                        break
                    D = Dn
                    Tg, k = _reel_grip(D, first, last, cx, cy, cz, ax, ay, az, dx_, dy_, dz_, nx, ny, nz, R, W,
                                       reel_kg[j], cap_share, rfe_length, r, grip_a, grip_on)
            reel_table_d[j, 1] = D
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
        if rho < 1e-9 * R or phi < 0.0 or phi > W:
            continue
        li = rfe_length[i]
        wgt = min(1.0, R * phi / li, R * (W - phi) / li)
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
