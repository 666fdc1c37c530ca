"""A body resting on a vessel's deck until it is lifted off (``bodies.<b>.deck``).

Unilateral contact of the body's footprint with the deck plane of a vessel, on the body's
RFE (a local load, like the seabed of the lines, eq. 8.95). The footprint is the rectangle
``footprint`` = [a, b] (body x and y) at the body's underside, h/2 below its centre (h the
body's vertical extent), and touches the deck at its four corners p_c = (+-a/2, +-b/2, -h/2)
(body frame), each carrying a quarter of the contact stiffness k and damping c. The corners
turn with the body, so the contact resists tilting (up to N a/2 before a corner lifts) and,
through friction, turning about the deck normal. With n = R_v e_z the deck normal and
P_d = p_v + R_v (0, 0, z_deck) a point of the deck, a corner B = r + R p_c penetrates by
delta = -(B - P_d) . n. Its normal force has the smooth onset of the roller contacts
(docs/theory.md, 'Implicit steps through roller contacts'):

    f_e = k' delta^2 / (2 delta_0)     (delta < delta_0),     k' (delta - delta_0 / 2) beyond,
    N = max(0, f_e + s c' d(delta)/dt),  s = min(1, delta / delta_0),   k' = k/4, c' = c/4,

and the friction in the deck plane is Coulomb's, regularised over DECK_SLIP_SPEED of the
slip velocity u_t of B relative to the deck: F_t = -mu N u_t / sqrt(|u_t|^2 + v_s^2) (the
body sits still within a few mm/s under a side load below mu N; a lifted body has no
friction). Each corner's force acts at the corner (with its moment about the centre); the
vessel's motion is prescribed, so the reaction on it is an output only (``deck_force``, the
sum of the corners' normal forces).

Statics (friction mode != 0, rfesim.solvers.statics): the slip velocity is zero there, so
Coulomb's regularised law would give no friction and a body resting on the deck with a
slack or slanted rope would have no lateral equilibrium. In statics the friction of each
corner is a stick spring instead, F_t = -k' (B - A)_t, returned onto the friction circle
|F_t| <= mu N: A is the corner's point at the model's initial state (the scenario's
position, kept in the vessel frame, ``anchor``), so the body is held where it was put on
the deck while the side load stays below mu N.
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment

DECK_ONSET = 0.002          # m, delta_0
DECK_SLIP_SPEED = 0.005     # m/s, v_s
DECK_CORNERS = 4


@njit(cache=True)
def deck_forces(body_rfe, deck_att, deck_z, deck_corner, deck_k, deck_c, deck_mu, att_p, att_R, att_v, att_w, R, r, v,
                w, F, M, normal_out, mode, anchor):
    """Add the deck contact forces and moments of every body with a deck (deck_att >= 0) to
    F, M (global, about the body centre); normal_out[j] = the sum of its corners' normal
    forces (N). deck_corner[j, c]: the footprint's corners in the body frame. mode[0]: 0
    dynamics (regularised Coulomb), otherwise statics (stick springs to anchor[j, c], the
    corners at the model's initial state, in the vessel frame)."""
    for j in range(body_rfe.shape[0]):
        normal_out[j] = 0.0
        a = deck_att[j]
        if a < 0:
            continue
        i = body_rfe[j]
        nx = att_R[a, 0, 2]
        ny = att_R[a, 1, 2]
        nz = att_R[a, 2, 2]
        # a point of the deck plane
        dx = att_p[a, 0] + nx * deck_z[j]
        dy = att_p[a, 1] + ny * deck_z[j]
        dz = att_p[a, 2] + nz * deck_z[j]
        k = 0.25 * deck_k[j]
        cd = 0.25 * deck_c[j]
        for c in range(DECK_CORNERS):
            px = deck_corner[j, c, 0]
            py = deck_corner[j, c, 1]
            pz = deck_corner[j, c, 2]
            ox = R[i, 0, 0] * px + R[i, 0, 1] * py + R[i, 0, 2] * pz
            oy = R[i, 1, 0] * px + R[i, 1, 1] * py + R[i, 1, 2] * pz
            oz = R[i, 2, 0] * px + R[i, 2, 1] * py + R[i, 2, 2] * pz
            bx = r[i, 0] + ox
            by = r[i, 1] + oy
            bz = r[i, 2] + oz
            delta = -((bx - dx) * nx + (by - dy) * ny + (bz - dz) * nz)
            if delta <= 0.0:
                continue
            # velocity of the corner relative to the deck point under it
            ex = bx - att_p[a, 0]
            ey = by - att_p[a, 1]
            ez = bz - att_p[a, 2]
            vdx = att_v[a, 0] + att_w[a, 1] * ez - att_w[a, 2] * ey
            vdy = att_v[a, 1] + att_w[a, 2] * ex - att_w[a, 0] * ez
            vdz = att_v[a, 2] + att_w[a, 0] * ey - att_w[a, 1] * ex
            ux = v[i, 0] + w[i, 1] * oz - w[i, 2] * oy - vdx
            uy = v[i, 1] + w[i, 2] * ox - w[i, 0] * oz - vdy
            uz = v[i, 2] + w[i, 0] * oy - w[i, 1] * ox - vdz
            un = ux * nx + uy * ny + uz * nz
            d0 = DECK_ONSET
            if delta < d0:
                fe = k * delta * delta / (2.0 * d0)
                s = delta / d0
            else:
                fe = k * (delta - 0.5 * d0)
                s = 1.0
            N = fe - s * cd * un          # penetrating (un < 0) adds to the force
            if N <= 0.0:
                continue
            normal_out[j] += N
            if mode[0] == 0:
                tx = ux - un * nx
                ty = uy - un * ny
                tz = uz - un * nz
                g = deck_mu[j] * N / math.sqrt(tx * tx + ty * ty + tz * tz + DECK_SLIP_SPEED * DECK_SLIP_SPEED)
                fx = N * nx - g * tx
                fy = N * ny - g * ty
                fz = N * nz - g * tz
            else:
                ax = (att_p[a, 0] + att_R[a, 0, 0] * anchor[j, c, 0] + att_R[a, 0, 1] * anchor[j, c, 1]
                      + att_R[a, 0, 2] * anchor[j, c, 2])
                ay = (att_p[a, 1] + att_R[a, 1, 0] * anchor[j, c, 0] + att_R[a, 1, 1] * anchor[j, c, 1]
                      + att_R[a, 1, 2] * anchor[j, c, 2])
                az = (att_p[a, 2] + att_R[a, 2, 0] * anchor[j, c, 0] + att_R[a, 2, 1] * anchor[j, c, 1]
                      + att_R[a, 2, 2] * anchor[j, c, 2])
                sx = bx - ax
                sy = by - ay
                sz = bz - az
                sn = sx * nx + sy * ny + sz * nz
                tx = -k * (sx - sn * nx)
                ty = -k * (sy - sn * ny)
                tz = -k * (sz - sn * nz)
                ft = math.sqrt(tx * tx + ty * ty + tz * tz)
                cap = deck_mu[j] * N
                if ft > cap:
                    tx *= cap / ft
                    ty *= cap / ft
                    tz *= cap / ft
                fx = N * nx + tx
                fy = N * ny + ty
                fz = N * nz + tz
            add_force_moment(F, M, i, ox, oy, oz, fx, fy, fz)
