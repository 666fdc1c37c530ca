"""Seabed contact (eq. 8.95, forces F^d): a flat, sloped or profiled seabed with a normal
spring and damper per unit length, integrated in closed form along each RFE, and Coulomb
friction by a spring-slider (stick/slip) law.

Geometry. The seabed is a profile z_b(s) along a horizontal direction d (a plane is a
profile of two points; a flat seabed has equal heights), linear between its points and
continued with the end slopes (a scenario's profile is given flat end rows that hold its
end depths: rfesim.scenario.schema.Seabed.profile_table). Each RFE meets the tangent
plane of the seabed under its centre, with unit normal n. The penetration of the pipe's
underside, ``p(s) = a - n . (P(s) - P_b)`` with ``a`` the contact radius and ``P_b`` the
seabed point under the centre, is linear along a straight RFE; the spring force per unit length ``k p``
over the penetrated part is integrated exactly (a triangle or a trapezoid) and applied at
its centroid along n, so the force is continuously differentiable in the RFE's position as
contact spreads along it (smooth touchdown, good Newton convergence). The damper
``c (v . n)`` acts on the same length; the total normal force ``N`` is never tensile: an
RFE lifting off so fast that the damper would pull has N = 0 and is out of contact
(``contact_length`` 0, the touchdown output skips it; no friction).

Friction (stick/slip). Each RFE in contact carries an anchor point ``A`` (history: the
committed anchor is read, the trial one written; the integrators commit after every
accepted step). The tangential displacement ``u = (I - n n^T)(r - A)`` of the RFE centre
loads a stick spring ``-k_t l_c u`` with a damper ``-c_t l_c v_t`` in parallel (the
centre's velocity in the seabed plane; c_t per unit length from friction_damping_ratio,
``seabed_damping``: critically damped by default, so a load that comes on at once does not
swing the line past its static deflection and make it slip at half the limit, nor leave it
ringing; docs/theory.md, "Stick damper"); the force is split into axial (along the RFE axis
projected on the seabed, e_1) and lateral (e_2 = n x e_1) parts and returned radially onto
the friction ellipse ``(f_1/mu_1)^2 + (f_2/mu_2)^2 <= N^2`` when it lies outside (slip),
spring and damper shares alike; the trial anchor is ``A' = r + f_spring / (k_t l_c)``, so
in slip the anchor slides with the pipe (only ever towards it) and the force stays at the
friction limit. A sticking line holds still under any force below the limit (no creep),
unlike a viscous regularisation. Modes (``mode[0]``):

* 0 spring-slider (dynamics);
* 1 fully mobilised axial friction pointing towards end A (statics: the line was pulled
  towards end B while it was laid, MoorPy's assumption); the anchors are written so that
  a following dynamic run starts from the same friction forces;
* 2 no friction.
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment


def seabed_damping(seabed, mass_per_length: float) -> tuple[float, float]:
    """(normal, stick) damping per unit length of a line or body with this mass per length on
    the seabed, ``2 zeta sqrt(k m)`` with the seabed's damping_ratio and normal stiffness, and
    its friction_damping_ratio and stick stiffness (default 0.1 normal_stiffness); (0, 0)
    without a seabed."""
    if seabed is None:
        return 0.0, 0.0
    return (2.0 * seabed.damping_ratio * math.sqrt(seabed.normal_stiffness * mass_per_length),
            2.0 * seabed.friction_damping_ratio * math.sqrt(stick_stiffness(seabed) * mass_per_length))


def stick_stiffness(seabed) -> float:
    """The friction's stick stiffness per unit length in contact (N/m/m): friction_stiffness,
    by default a tenth of the normal stiffness; 0 without a seabed."""
    if seabed is None:
        return 0.0
    return float(seabed.friction_stiffness or 0.1 * seabed.normal_stiffness)


@njit(cache=True)
def seabed_height(bed_s, bed_z, bed_dir, x, y, out):
    """Seabed height and its gradient under (x, y): out = [z_b, dz/dx, dz/dy]."""
    s = x * bed_dir[0] + y * bed_dir[1]
    m = bed_s.shape[0]
    j = 0
    # profiles are short: a linear scan (segment j spans points j .. j+1)
    while j < m - 2 and s > bed_s[j + 1]:
        j += 1
    g = (bed_z[j + 1] - bed_z[j]) / (bed_s[j + 1] - bed_s[j])
    out[0] = bed_z[j] + g * (s - bed_s[j])
    out[1] = g * bed_dir[0]
    out[2] = g * bed_dir[1]


@njit(cache=True)
def seabed_forces(rfe_length, rfe_contact_radius, rfe_seabed_c, rfe_seabed_ct, bed_s, bed_z, bed_dir, seabed_k,
                  mu, kt,
                  R, r, v, w, F, M, contact_force, contact_length, anchor, anchored, anchor_trial,
                  anchored_trial, mode, friction_force, tmp):
    """Normal contact and friction of every RFE (see the module text). ``mu`` = [axial,
    lateral] coefficients; ``kt`` the stick stiffness and ``rfe_seabed_ct`` its damper per unit
    length; ``anchor``/``anchored``
    the committed friction anchors (read), ``anchor_trial``/``anchored_trial`` written;
    ``friction_force`` (n, 3) the friction force on each RFE; ``tmp`` a (3,) scratch."""
    fmode = mode[0]
    for i in range(rfe_length.shape[0]):
        contact_force[i] = 0.0
        contact_length[i] = 0.0
        anchored_trial[i] = 0
        for k in range(3):
            friction_force[i, k] = 0.0
            anchor_trial[i, k] = r[i, k]
        seabed_height(bed_s, bed_z, bed_dir, r[i, 0], r[i, 1], tmp)
        gx = tmp[1]
        gy = tmp[2]
        inv = 1.0 / math.sqrt(1.0 + gx * gx + gy * gy)
        nx = -gx * inv
        ny = -gy * inv
        nz = inv
        hl = 0.5 * rfe_length[i]
        tx = R[i, 0, 0]
        ty = R[i, 1, 0]
        tz = R[i, 2, 0]
        a = rfe_contact_radius[i]
        dc = (r[i, 2] - tmp[0]) * nz          # height of the centre above the seabed plane
        dt = nx * tx + ny * ty + nz * tz
        pl = a - (dc - hl * dt)
        pr = a - (dc + hl * dt)
        if pl <= 0.0 and pr <= 0.0:
            continue
        L = rfe_length[i]
        if pl > 0.0 and pr > 0.0:
            lc = L
            fk = seabed_k * L * 0.5 * (pl + pr)
            # centroid of the trapezoid, measured from the left end
            sc = L * (pl + 2.0 * pr) / (3.0 * (pl + pr))
        elif pl > 0.0:
            lc = L * pl / (pl - pr)
            fk = 0.5 * seabed_k * lc * pl
            sc = lc / 3.0
        else:
            lc = L * pr / (pr - pl)
            fk = 0.5 * seabed_k * lc * pr
            sc = L - lc / 3.0
        off = sc - hl
        dx = off * tx
        dy = off * ty
        dz = off * tz
        # normal velocity at the contact centroid: (v + w x d) . n
        vx = v[i, 0] + w[i, 1] * dz - w[i, 2] * dy
        vy = v[i, 1] + w[i, 2] * dx - w[i, 0] * dz
        vz = v[i, 2] + w[i, 0] * dy - w[i, 1] * dx
        fn = fk - rfe_seabed_c[i] * lc * (vx * nx + vy * ny + vz * nz)
        if fn <= 0.0:
            # lifting off faster than the spring unloads: the damper would pull, so the seabed
            # lets go (N = 0) and the RFE is out of contact: no contact length (the touchdown
            # point is never placed on it), no friction, its anchor released
            continue
        fx = fn * nx
        fy = fn * ny
        fz = fn * nz
        contact_force[i] = fn
        contact_length[i] = lc
        if fmode != 2 and (mu[0] > 0.0 or mu[1] > 0.0):
            # axial direction on the seabed e1 (the RFE axis projected), lateral e2 = n x e1
            e1x = tx - dt * nx
            e1y = ty - dt * ny
            e1z = tz - dt * nz
            ne = math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
            if ne < 1e-12:
                # a vertical RFE standing on the seabed: any tangent will do
                e1x = nz
                e1y = 0.0
                e1z = -nx
                ne = math.sqrt(e1x * e1x + e1z * e1z)
            e1x /= ne
            e1y /= ne
            e1z /= ne
            e2x = ny * e1z - nz * e1y
            e2y = nz * e1x - nx * e1z
            e2z = nx * e1y - ny * e1x
            klc = kt * lc
            # first touch (the anchor is where the RFE is now): no force
            f1 = 0.0
            f2 = 0.0
            if fmode == 1:
                f1 = -mu[0] * fn
            # the spring's share of the force (s1, s2) places the trial anchor
            s1 = f1
            s2 = f2
            if fmode == 0 and anchored[i] != 0:
                ux = r[i, 0] - anchor[i, 0]
                uy = r[i, 1] - anchor[i, 1]
                uz = r[i, 2] - anchor[i, 2]
                s1 = -klc * (ux * e1x + uy * e1y + uz * e1z)
                s2 = -klc * (ux * e2x + uy * e2y + uz * e2z)
                # the stick damper on the centre's sliding velocity (e1, e2 lie in the seabed plane)
                clc = rfe_seabed_ct[i] * lc
                f1 = s1 - clc * (v[i, 0] * e1x + v[i, 1] * e1y + v[i, 2] * e1z)
                f2 = s2 - clc * (v[i, 0] * e2x + v[i, 1] * e2y + v[i, 2] * e2z)
                if mu[0] <= 0.0:
                    f1 = 0.0
                    s1 = 0.0
                if mu[1] <= 0.0:
                    f2 = 0.0
                    s2 = 0.0
                q1 = f1 / mu[0] if mu[0] > 0.0 else 0.0
                q2 = f2 / mu[1] if mu[1] > 0.0 else 0.0
                phi = math.sqrt(q1 * q1 + q2 * q2)
                if phi > fn:
                    # slip: the force returned onto the ellipse, its spring and damper shares
                    # alike, so the anchor only moves towards the line (sliding with it); with
                    # no damper the spring holds the limit, as the classical spring-slider
                    lam = fn / phi
                    f1 *= lam
                    f2 *= lam
                    s1 *= lam
                    s2 *= lam
            ffx = f1 * e1x + f2 * e2x
            ffy = f1 * e1y + f2 * e2y
            ffz = f1 * e1z + f2 * e2z
            friction_force[i, 0] = ffx
            friction_force[i, 1] = ffy
            friction_force[i, 2] = ffz
            anchored_trial[i] = 1
            anchor_trial[i, 0] = r[i, 0] + (s1 * e1x + s2 * e2x) / klc
            anchor_trial[i, 1] = r[i, 1] + (s1 * e1y + s2 * e2y) / klc
            anchor_trial[i, 2] = r[i, 2] + (s1 * e1z + s2 * e2z) / klc
            fx += ffx
            fy += ffy
            fz += ffz
        # the contact force at the centroid d and its moment d x f
        add_force_moment(F, M, i, dx, dy, dz, fx, fy, fz)


@njit(cache=True)
def commit_friction(anchor, anchored, anchor_trial, anchored_trial):
    """Accept the trial friction anchors of the last evaluation (after an accepted step)."""
    for i in range(anchor.shape[0]):
        anchored[i] = anchored_trial[i]
        for k in range(3):
            anchor[i, k] = anchor_trial[i, k]
