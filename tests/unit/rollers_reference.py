"""Slow, readable numpy version of rfesim.loads.rollers (roller contact and friction),
written from the kernel's module text: every RFE of the roller's line is tested (no
search), and the closest points of two segments come from enumerating the candidates of a
convex quadratic on a rectangle (the interior stationary point and the optimum on each of
the four edges), not from Ericson's clamping sequence the kernel uses."""
from __future__ import annotations

import numpy as np

from rfesim.loads.rollers import CONTACT_ONSET


def closest_points(centre, tangent, half_length, point, axis, half_width):
    """(s, u) minimising |centre + s tangent - point - u axis| over |s| <= h, |u| <= b."""
    def dist(s, u):
        return float(np.linalg.norm(centre + s * tangent - point - u * axis))

    candidates = []
    c = float(tangent @ axis)
    w = centre - point
    det = 1.0 - c * c
    if det > 1e-12:
        # grad = 0: s + c' ... solve [[1, -c], [c, -1]] [s, u] = [-w.t, -w.a]
        s, u = np.linalg.solve(np.array([[1.0, -c], [c, -1.0]]), np.array([-w @ tangent, -w @ axis]))
        if abs(s) <= half_length and abs(u) <= half_width:
            candidates.append((s, u))
    for s in (-half_length, half_length):
        u = float(np.clip((w + s * tangent) @ axis, -half_width, half_width))
        candidates.append((s, u))
    for u in (-half_width, half_width):
        s = float(np.clip(-(w - u * axis) @ tangent, -half_length, half_length))
        candidates.append((s, u))
    return min(candidates, key=lambda su: dist(*su))


def roller_forces(roller_attach, roller_point, roller_axis, roller_half_width, roller_radius, roller_k, roller_c,
                  roller_mu, roller_kt, roller_lo, roller_hi, rfe_length, rfe_radius, att_p, att_R, att_v, att_w,
                  R, r, v, w, anchor, anchored, mode, roller_onset=None):
    """``roller_onset`` (nr,): contact onset depths (default CONTACT_ONSET (a + rho)).
    Returns F, M (n, 3) on the RFEs, roller_force (nr, 3), roller_normal (nr,),
    anchor_trial (nr,), anchored_trial (nr,)."""
    n = r.shape[0]
    nr = roller_attach.shape[0]
    F = np.zeros((n, 3))
    M = np.zeros((n, 3))
    force = np.zeros((nr, 3))
    normal = np.zeros(nr)
    anchor_trial = np.zeros(nr)
    anchored_trial = np.zeros(nr, np.int64)
    for j in range(nr):
        a_idx = roller_attach[j]
        P = att_p[a_idx] + att_R[a_idx] @ roller_point[j]
        a = att_R[a_idx] @ roller_axis[j]
        contacts = []      # (i, X_p, n, f_n)
        for i in range(roller_lo[j], roller_hi[j]):
            t = R[i][:, 0]
            s, u = closest_points(r[i], t, 0.5 * rfe_length[i], P, a, roller_half_width[j])
            Xp = r[i] + s * t
            Xr = P + u * a
            d = np.linalg.norm(Xp - Xr)
            penetration = rfe_radius[i] + roller_radius[j] - d
            if penetration <= 0.0:
                continue
            nrm = (Xp - Xr) / d
            v_pipe = v[i] + np.cross(w[i], Xp - r[i])
            v_roller = att_v[a_idx] + np.cross(att_w[a_idx], Xr - att_p[a_idx])
            # smooth onset over delta_0 = CONTACT_ONSET (a + rho): quadratic, then linear
            onset = CONTACT_ONSET * (rfe_radius[i] + roller_radius[j]) if roller_onset is None else roller_onset[j]
            if penetration < onset:
                elastic = roller_k[j] * penetration ** 2 / (2.0 * onset)
                ramp = penetration / onset
            else:
                elastic = roller_k[j] * (penetration - onset / 2.0)
                ramp = 1.0
            fn = elastic - ramp * roller_c[j] * (v_pipe - v_roller) @ nrm
            if fn > 0.0:
                contacts.append((i, Xp, nrm, fn))
        total = sum(cn[3] for cn in contacts)
        normal[j] = total
        friction = 0.0
        if mode == 0 and roller_mu[j] > 0.0 and total > 0.0:
            u = sum(fn * (Xp - P) @ a for _, Xp, _, fn in contacts) / total
            if anchored[j]:
                friction = float(np.clip(-roller_kt[j] * (u - anchor[j]), -roller_mu[j] * total,
                                         roller_mu[j] * total))
            anchored_trial[j] = 1
            anchor_trial[j] = u + friction / roller_kt[j]
        for i, Xp, nrm, fn in contacts:
            f = fn * nrm
            if friction != 0.0:
                e = a - (a @ nrm) * nrm
                f = f + friction * fn / total * e / np.linalg.norm(e)
            F[i] += f
            M[i] += np.cross(Xp - r[i], f)
            force[j] -= f
    return F, M, force, normal, anchor_trial, anchored_trial
