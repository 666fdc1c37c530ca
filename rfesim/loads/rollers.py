"""Rollers and stingers (guiding structures of pipelay): unilateral contact between the
RFEs of a line and roller contact lines, with Coulomb friction along the roller axes.

A roller j is a segment of its axis in an attachment frame (0: the fixed global frame, or
a vessel): centre ``P_j``, unit axis ``a_j``, half width ``b_j`` (the pipe touches the
roller within ``+-b_j`` of the centre along the axis), roller radius ``rho_j``, normal
stiffness ``k_j`` (N/m) and damping ``c_j`` (N*s/m). An RFE i is the segment of the pipe
axis ``r_i + s t_i``, ``|s| <= L_i / 2`` (t_i the RFE's x axis), of outer radius
``a_i``. With ``X_p`` and ``X_r`` the closest points of the two segments (Ericson,
*Real-Time Collision Detection*, 5.1.9), ``d = |X_p - X_r|`` and the common normal
``n = (X_p - X_r) / d``, the penetration and the normal force on the RFE are

    delta = a_i + rho_j - d,    f_n = max(0, f_e(delta) - s(delta) c_j (v_p - v_r) . n)  (delta > 0)

with ``v_p`` the velocity of the pipe point ``X_p`` and ``v_r`` that of the roller
point ``X_r``. The contact comes in smoothly over a small onset depth ``delta_0``
(``roller_onset``; by default ``CONTACT_ONSET (a_i + rho_j)``, rfesim.model.supports):
``f_e = k_j delta^2 / (2 delta_0)`` and ``s = delta / delta_0`` below it,
``f_e = k_j (delta - delta_0 / 2)`` and ``s = 1`` beyond, so the force and its tangent ``k_j min(delta / delta_0, 1)`` are continuous at
first touch (a sharp onset, whose tangent jumps from 0 to k_j, makes the implicit step's
Newton iteration cycle between contact and no contact; docs/theory.md, "Roller contact
onset"). The force ``f_n n`` acts at ``X_p`` (the contact point on the surface,
``X_p - a_i n``, gives the same moment) and adds ``(X_p - r_i) x f`` to the RFE's moment
about its centre, like any load of eq. 8.93; the generalised forces follow by eq. 8.94.

Search (O(rollers), not O(rollers x RFEs)). Each roller belongs to one line (RFEs
``lo .. hi-1``) and keeps a hint, the RFE nearest to it at the last evaluation (``-1``:
unknown, then every RFE of the line is scanned once). From the hint the nearest RFE
(distance from the roller centre to the RFE axis segment) is found by walking along the
line while the distance falls; then the RFEs touching the roller are that one, its two
neighbours and any further neighbours for as long as they penetrate. A pipe passing over
a roller at an SDE touches it with both RFEs there; each contact is computed on its own,
so the force is continuous as the contact moves from one RFE to the next.

Friction (spring-slider, as on the seabed, ``rfesim.loads.seabed``). A roller turns
freely about its axis, so friction acts only along the axis. The roller's contacts have a
total normal force ``N = sum f_n`` and a contact coordinate along the axis
``u = sum f_n ((X_p - P) . a) / N``; the committed anchor ``u_0`` (history, in the
roller's frame) loads a stick spring ``f = -k_t (u - u_0)`` returned to ``|f| <= mu N``
when it slips, and the trial anchor is ``u_0' = u + f / k_t``. The friction force is
shared among the contacts in proportion to their normal force, each along the axis
projected normal to its contact normal. Mode (``mode[0]``, shared with the seabed):
0 stick/slip; 1 or 2 (statics) no friction -- anchors are then set at first touch.

Outputs per roller: ``roller_force`` (3,) the force of the pipe on the roller (global,
normal plus friction) and ``roller_normal`` the total normal force N.
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment

CONTACT_ONSET = 0.005    # default onset depth of a roller contact, as a fraction of pipe + roller radius


@njit(cache=True)
def segment_closest_points(cx, cy, cz, tx, ty, tz, h, px, py, pz, ax, ay, az, b, out):
    """Closest points of the segments c + s t, |s| <= h and p + u a, |u| <= b (t and a
    unit vectors): out = [s, u] (Ericson 5.1.9 on the centred parametrisation)."""
    # d1 = 2h t, d2 = 2b a, start points c - h t and p - b a; parameters in [0, 1]
    d1x = 2.0 * h * tx
    d1y = 2.0 * h * ty
    d1z = 2.0 * h * tz
    d2x = 2.0 * b * ax
    d2y = 2.0 * b * ay
    d2z = 2.0 * b * az
    rx = (cx - h * tx) - (px - b * ax)
    ry = (cy - h * ty) - (py - b * ay)
    rz = (cz - h * tz) - (pz - b * az)
    A = d1x * d1x + d1y * d1y + d1z * d1z
    E = d2x * d2x + d2y * d2y + d2z * d2z
    Fv = d2x * rx + d2y * ry + d2z * rz
    tiny = 1e-300
    if A <= tiny and E <= tiny:
        s1 = 0.0
        s2 = 0.0
    elif A <= tiny:
        s1 = 0.0
        s2 = min(max(Fv / E, 0.0), 1.0)
    else:
        C = d1x * rx + d1y * ry + d1z * rz
        if E <= tiny:
            s2 = 0.0
            s1 = min(max(-C / A, 0.0), 1.0)
        else:
            B = d1x * d2x + d1y * d2y + d1z * d2z
            den = A * E - B * B
            if den > 1e-14 * A * E:
                s1 = min(max((B * Fv - C * E) / den, 0.0), 1.0)
            else:
                s1 = 0.5          # parallel: any point of the overlap will do; take the middle
            s2 = (B * s1 + Fv) / E
            if s2 < 0.0:
                s2 = 0.0
                s1 = min(max(-C / A, 0.0), 1.0)
            elif s2 > 1.0:
                s2 = 1.0
                s1 = min(max((B - C) / A, 0.0), 1.0)
    out[0] = (2.0 * s1 - 1.0) * h
    out[1] = (2.0 * s2 - 1.0) * b


@njit(cache=True)
def _roller_frame(j, roller_attach, roller_point, roller_axis, att_p, att_R, g):
    """Global centre and axis of roller j: g[0:3] centre, g[3:6] axis."""
    at = roller_attach[j]
    for k in range(3):
        g[k] = att_p[at, k] + att_R[at, k, 0] * roller_point[j, 0] + att_R[at, k, 1] * roller_point[j, 1] \
            + att_R[at, k, 2] * roller_point[j, 2]
        g[3 + k] = att_R[at, k, 0] * roller_axis[j, 0] + att_R[at, k, 1] * roller_axis[j, 1] \
            + att_R[at, k, 2] * roller_axis[j, 2]


@njit(cache=True)
def _centre_distance2(i, g, R, r, rfe_length):
    """Squared distance from the roller centre g[0:3] to the axis segment of RFE i."""
    h = 0.5 * rfe_length[i]
    dx = g[0] - r[i, 0]
    dy = g[1] - r[i, 1]
    dz = g[2] - r[i, 2]
    s = dx * R[i, 0, 0] + dy * R[i, 1, 0] + dz * R[i, 2, 0]
    s = min(max(s, -h), h)
    ex = dx - s * R[i, 0, 0]
    ey = dy - s * R[i, 1, 0]
    ez = dz - s * R[i, 2, 0]
    return ex * ex + ey * ey + ez * ez


@njit(cache=True)
def _contact(i, g, b, rho, R, r, rfe_length, rfe_radius, sw, c):
    """Contact of RFE i with the roller g (centre, axis), half width b, radius rho.
    Returns the penetration (<= 0: none) and writes c = [X_p (3), X_r (3), n (3)]."""
    tx = R[i, 0, 0]
    ty = R[i, 1, 0]
    tz = R[i, 2, 0]
    h = 0.5 * rfe_length[i]
    segment_closest_points(r[i, 0], r[i, 1], r[i, 2], tx, ty, tz, h, g[0], g[1], g[2], g[3], g[4], g[5], b, sw)
    s = sw[0]
    u = sw[1]
    for k in range(3):
        c[k] = r[i, k] + s * R[i, k, 0]
        c[3 + k] = g[k] + u * g[3 + k]
    nx = c[0] - c[3]
    ny = c[1] - c[4]
    nz = c[2] - c[5]
    d = math.sqrt(nx * nx + ny * ny + nz * nz)
    reach = rfe_radius[i] + rho
    pen = reach - d
    if pen <= 0.0:
        return pen
    if d > 1e-12 * reach:
        nx /= d
        ny /= d
        nz /= d
    else:
        # the axes cross: push along t x a (towards the side the RFE centre is on)
        nx = ty * g[5] - tz * g[4]
        ny = tz * g[3] - tx * g[5]
        nz = tx * g[4] - ty * g[3]
        m = math.sqrt(nx * nx + ny * ny + nz * nz)
        if m < 1e-12:
            return 0.0
        sgn = 1.0 if nx * (r[i, 0] - g[0]) + ny * (r[i, 1] - g[1]) + nz * (r[i, 2] - g[2]) >= 0.0 else -1.0
        nx *= sgn / m
        ny *= sgn / m
        nz *= sgn / m
    c[6] = nx
    c[7] = ny
    c[8] = nz
    return pen


@njit(cache=True)
def contact_law(pen, vn, k, cdamp, onset):
    """Normal force (>= 0) at penetration pen > 0 and normal speed vn (> 0: separating):
    quadratic onset over the depth ``onset``, then linear (module text); onset 0: the
    sharp law max(0, k pen - c vn)."""
    if pen < onset:
        s = pen / onset
        fe = 0.5 * k * pen * s
    else:
        s = 1.0
        fe = k * (pen - 0.5 * onset)
    fn = fe - s * cdamp * vn
    return fn if fn > 0.0 else 0.0


@njit(cache=True)
def _normal_force(i, at, pen, c, k, cdamp, onset, r, v, w, att_p, att_v, att_w):
    """Normal force (>= 0) of a contact with penetration pen and geometry c."""
    # velocity of the pipe point X_p and of the roller point X_r, along n
    dx = c[0] - r[i, 0]
    dy = c[1] - r[i, 1]
    dz = c[2] - r[i, 2]
    vpx = v[i, 0] + w[i, 1] * dz - w[i, 2] * dy
    vpy = v[i, 1] + w[i, 2] * dx - w[i, 0] * dz
    vpz = v[i, 2] + w[i, 0] * dy - w[i, 1] * dx
    ex = c[3] - att_p[at, 0]
    ey = c[4] - att_p[at, 1]
    ez = c[5] - att_p[at, 2]
    vrx = att_v[at, 0] + att_w[at, 1] * ez - att_w[at, 2] * ey
    vry = att_v[at, 1] + att_w[at, 2] * ex - att_w[at, 0] * ez
    vrz = att_v[at, 2] + att_w[at, 0] * ey - att_w[at, 1] * ex
    vn = (vpx - vrx) * c[6] + (vpy - vry) * c[7] + (vpz - vrz) * c[8]
    return contact_law(pen, vn, k, cdamp, onset)


@njit(cache=True)
def _contact_normal_force(i, at, g, b, rho, R, r, rfe_length, rfe_radius, sw, c, k, cdamp, onset, v, w, att_p,
                          att_v, att_w):
    """Normal force of the roller on RFE i (``_normal_force``), 0 without contact; c as
    left by ``_contact``."""
    pen = _contact(i, g, b, rho, R, r, rfe_length, rfe_radius, sw, c)
    if pen <= 0.0:
        return 0.0
    return _normal_force(i, at, pen, c, k, cdamp, onset, r, v, w, att_p, att_v, att_w)


@njit(cache=True)
def roller_forces(roller_attach, roller_point, roller_axis, roller_half_width, roller_radius, roller_k, roller_c,
                  roller_mu, roller_kt, roller_onset, roller_lo, roller_hi, rfe_length, rfe_radius, att_p, att_R,
                  att_v, att_w, R, r, v, w, F, M, hint, roller_force, roller_normal, anchor, anchored, anchor_trial,
                  anchored_trial, mode, scratch):
    """Contact of every roller with the RFEs of its line (see the module text): adds the
    forces and moments on the RFEs to F, M (global); writes roller_force (nr, 3),
    roller_normal (nr,), the search hints and the trial friction anchors.
    ``scratch`` is a work array of at least 17 numbers."""
    g = scratch[0:6]
    c = scratch[6:15]
    sw2 = scratch[15:17]
    fmode = mode[0]
    for j in range(roller_attach.shape[0]):
        roller_force[j, 0] = 0.0
        roller_force[j, 1] = 0.0
        roller_force[j, 2] = 0.0
        roller_normal[j] = 0.0
        anchored_trial[j] = 0
        anchor_trial[j] = 0.0
        lo = roller_lo[j]
        hi = roller_hi[j]
        if hi <= lo:
            continue
        _roller_frame(j, roller_attach, roller_point, roller_axis, att_p, att_R, g)
        # nearest RFE: walk from the hint (a full scan when there is none)
        i0 = hint[j]
        if i0 < lo or i0 >= hi:
            best = 1e300
            i0 = lo
            for i in range(lo, hi):
                d2 = _centre_distance2(i, g, R, r, rfe_length)
                if d2 < best:
                    best = d2
                    i0 = i
        else:
            best = _centre_distance2(i0, g, R, r, rfe_length)
            while i0 > lo:
                d2 = _centre_distance2(i0 - 1, g, R, r, rfe_length)
                if d2 >= best:
                    break
                best = d2
                i0 -= 1
            while i0 < hi - 1:
                d2 = _centre_distance2(i0 + 1, g, R, r, rfe_length)
                if d2 >= best:
                    break
                best = d2
                i0 += 1
        hint[j] = i0
        b = roller_half_width[j]
        rho = roller_radius[j]
        # range of touching RFEs: i0 and its neighbours, extended while they penetrate
        ia = max(i0 - 1, lo)
        while ia > lo and _contact(ia, g, b, rho, R, r, rfe_length, rfe_radius, sw2, c) > 0.0:
            ia -= 1
        ib = min(i0 + 1, hi - 1)
        while ib < hi - 1 and _contact(ib, g, b, rho, R, r, rfe_length, rfe_radius, sw2, c) > 0.0:
            ib += 1
        at = roller_attach[j]
        friction = fmode == 0 and roller_mu[j] > 0.0
        # pass 1: normal forces; their sum and the force-weighted contact coordinate on the axis
        ntot = 0.0
        nu = 0.0
        for i in range(ia, ib + 1):
            fn = _contact_normal_force(i, at, g, b, rho, R, r, rfe_length, rfe_radius, sw2, c, roller_k[j],
                                       roller_c[j], roller_onset[j], v, w, att_p, att_v, att_w)
            if fn <= 0.0:
                continue
            ntot += fn
            nu += fn * ((c[0] - g[0]) * g[3] + (c[1] - g[1]) * g[4] + (c[2] - g[2]) * g[5])
        ffric = 0.0
        if friction and ntot > 0.0:
            u = nu / ntot
            kt = roller_kt[j]
            if anchored[j] != 0:
                ffric = -kt * (u - anchor[j])
                lim = roller_mu[j] * ntot
                if ffric > lim:
                    ffric = lim
                elif ffric < -lim:
                    ffric = -lim
            anchored_trial[j] = 1
            anchor_trial[j] = u + ffric / kt
        roller_normal[j] = ntot
        if ntot <= 0.0:
            continue
        # pass 2: apply the forces
        for i in range(ia, ib + 1):
            fn = _contact_normal_force(i, at, g, b, rho, R, r, rfe_length, rfe_radius, sw2, c, roller_k[j],
                                       roller_c[j], roller_onset[j], v, w, att_p, att_v, att_w)
            if fn <= 0.0:
                continue
            fx = fn * c[6]
            fy = fn * c[7]
            fz = fn * c[8]
            if ffric != 0.0:
                # the roller axis projected normal to this contact's normal
                an = g[3] * c[6] + g[4] * c[7] + g[5] * c[8]
                ex = g[3] - an * c[6]
                ey = g[4] - an * c[7]
                ez = g[5] - an * c[8]
                en = math.sqrt(ex * ex + ey * ey + ez * ez)
                if en > 1e-12:
                    share = ffric * fn / (ntot * en)
                    fx += share * ex
                    fy += share * ey
                    fz += share * ez
            dx = c[0] - r[i, 0]
            dy = c[1] - r[i, 1]
            dz = c[2] - r[i, 2]
            add_force_moment(F, M, i, dx, dy, dz, fx, fy, fz)
            roller_force[j, 0] -= fx
            roller_force[j, 1] -= fy
            roller_force[j, 2] -= fz


@njit(cache=True)
def commit_roller_friction(anchor, anchored, anchor_trial, anchored_trial):
    """Accept the trial roller friction anchors of the last evaluation (after an accepted step)."""
    for j in range(anchor.shape[0]):
        anchored[j] = anchored_trial[j]
        anchor[j] = anchor_trial[j]
