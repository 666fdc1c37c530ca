"""A body resting on a vessel's deck until it is lifted off (``bodies.<b>.deck``).

Unilateral contact of the body's underside with the deck plane of a vessel, on the body's
RFE (a local load, like the seabed of the lines, eq. 8.95). With n = R_v e_z the deck
normal and P_d = p_v + R_v (0, 0, z_deck) a point of the deck, the underside point is
B = r - (h/2) n (h the body's vertical extent: the body is taken upright on the deck) and
its penetration delta = -(B - P_d) . n. The normal force has the smooth onset of the
roller contacts (docs/theory.md, 'Implicit steps through roller contacts'):

    f_e = k delta^2 / (2 delta_0)     (delta < delta_0),     k (delta - delta_0 / 2) beyond,
    N = max(0, f_e + s c d(delta)/dt),  s = min(1, delta / delta_0),

and the friction in the deck plane is Coulomb's, regularised over DECK_SLIP_SPEED of the
slip velocity u_t of B relative to the deck: F_t = -mu N u_t / sqrt(|u_t|^2 + v_s^2) (the
body sits still within a few mm/s under a side load below mu N; a lifted body has no
friction). The force acts at B (with its moment about the centre); the vessel's motion is
prescribed, so the reaction on it is an output only (``deck_force``).
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment

DECK_ONSET = 0.002          # m, delta_0
DECK_SLIP_SPEED = 0.005     # m/s, v_s


@njit(cache=True)
def deck_forces(body_rfe, deck_att, deck_z, deck_half, deck_k, deck_c, deck_mu, att_p, att_R, att_v, att_w, r, v, w,
                F, M, normal_out):
    """Add the deck contact force and moment of every body with a deck (deck_att >= 0) to
    F, M (global, about the body centre); normal_out[j] = the normal force N (N)."""
    for j in range(body_rfe.shape[0]):
        normal_out[j] = 0.0
        a = deck_att[j]
        if a < 0:
            continue
        i = body_rfe[j]
        nx = att_R[a, 0, 2]
        ny = att_R[a, 1, 2]
        nz = att_R[a, 2, 2]
        # a point of the deck plane and the underside point B
        dx = att_p[a, 0] + att_R[a, 0, 2] * deck_z[j]
        dy = att_p[a, 1] + att_R[a, 1, 2] * deck_z[j]
        dz = att_p[a, 2] + att_R[a, 2, 2] * deck_z[j]
        h = deck_half[j]
        bx = r[i, 0] - h * nx
        by = r[i, 1] - h * ny
        bz = r[i, 2] - h * nz
        delta = -((bx - dx) * nx + (by - dy) * ny + (bz - dz) * nz)
        if delta <= 0.0:
            continue
        # velocity of B relative to the deck point under it
        cx = bx - att_p[a, 0]
        cy = by - att_p[a, 1]
        cz = bz - att_p[a, 2]
        vdx = att_v[a, 0] + att_w[a, 1] * cz - att_w[a, 2] * cy
        vdy = att_v[a, 1] + att_w[a, 2] * cx - att_w[a, 0] * cz
        vdz = att_v[a, 2] + att_w[a, 0] * cy - att_w[a, 1] * cx
        ox = -h * nx
        oy = -h * ny
        oz = -h * nz
        ux = v[i, 0] + w[i, 1] * oz - w[i, 2] * oy - vdx
        uy = v[i, 1] + w[i, 2] * ox - w[i, 0] * oz - vdy
        uz = v[i, 2] + w[i, 0] * oy - w[i, 1] * ox - vdz
        un = ux * nx + uy * ny + uz * nz
        d0 = DECK_ONSET
        k = deck_k[j]
        if delta < d0:
            fe = k * delta * delta / (2.0 * d0)
            s = delta / d0
        else:
            fe = k * (delta - 0.5 * d0)
            s = 1.0
        N = fe - s * deck_c[j] * un          # penetrating (un < 0) adds to the force
        if N <= 0.0:
            continue
        normal_out[j] = N
        tx = ux - un * nx
        ty = uy - un * ny
        tz = uz - un * nz
        g = deck_mu[j] * N / math.sqrt(tx * tx + ty * ty + tz * tz + DECK_SLIP_SPEED * DECK_SLIP_SPEED)
        fx = N * nx - g * tx
        fy = N * ny - g * ty
        fz = N * nz - g * tz
        add_force_moment(F, M, i, ox, oy, oz, fx, fy, fz)
