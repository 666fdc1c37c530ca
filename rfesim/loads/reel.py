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
  -k_g l (sigma - sigma_a - D) along the tangent, capped at F_max l / (R W) (the pipe slips
  on the drum beyond it); D = R * (drum rotation) is the paid-out length.

Every spring (and the cap) is weighted by min(1, R phi / l, R (W - phi) / l): the drum
takes hold of an RFE over one element length after the take-off and lets go over one
before the end of the window, so pipe passing the take-off sees no jump of force. The
payout D is the tensioner's (rfesim.loads.tensioner): a monotone cubic table of D(t), or
driven by the constant-tension characteristic; the grips and the driven payout are
committed by ``commit_tensioners`` on the reel's own arrays. No RFE is created or
deleted: the stored pipe is part of the line.
"""
from __future__ import annotations

import math

from numba import njit

from .tensioner import tensioner_payout


@njit(cache=True)
def reel_forces(reel_att, reel_centre, reel_axis, reel_dir, reel_radius, reel_wrap, reel_kr, reel_kl, reel_kg,
                reel_cap, reel_line_lo, reel_line_hi, reel_mode, reel_table_t, reel_table_d, reel_table_v,
                reel_count, t, att_p, att_R, rfe_length, r, F, grip_a, grip_on, grip_a_trial, grip_on_trial,
                D_committed, grip_force):
    """Add the forces of every reel on the RFEs on its wrap to F (at the centres: no
    moment). grip_a/grip_on (n,) committed grip anchors (material coordinate, m) and
    whether each RFE is gripped; the trial values are written. grip_force (nreel,) the
    tangential force each reel carries (N, positive when it holds the line back)."""
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
        D = tensioner_payout(reel_mode, reel_table_t, reel_table_d, reel_table_v, reel_count, j, t, D_committed)
        R = reel_radius[j]
        W = reel_wrap[j]
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
                cap = reel_cap[j] * li * wgt / (R * W)
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
