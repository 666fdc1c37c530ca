"""Tugger lines (top-level ``tuggers``): a line from a deck point of a vessel to a point of a
body, holding the payload against swinging and turning (a local load on the body's RFE,
like the deck contact and the seabed of eq. 8.95).

The line is massless and straight: with D = p_v + R_v d the deck point (d in the vessel
frame) and P = r + R b the body point (b in the body frame), its length is L = |D - P| and
its unit direction from the body u = (D - P) / L. Its tension is

* ``tension`` (kind 0): the set tension T(t) of a constant-tension tugger winch (linear
  in a table of [t, T] rows, held beyond it): the winch pays out and hauls in so the line
  keeps T at any length;
* ``force`` (kind 2): a push-pull element, a hydraulic cylinder at a set force: the force
  P(t) pushes the point away from the deck point (P > 0) or pulls it toward it (P < 0), at
  any length between its end stops (the tension is -P); beyond the longest length L_max the
  stop pulls back with k_s (L - L_max), below the shortest L_min it pushes with
  k_s (L_min - L) (arrays: tug_k = k_s, tug_L0 = L_min, tug_c = L_max, 0: no stop);
* ``elastic`` (kind 1): a braked winch, T = max(0, k (L - L0) + c dL/dt) while L > L0 and
  0 when the line is slack (L <= L0), with dL/dt = u . (v_D - v_P).

The force T u acts on the body at P (with its moment about the centre). The vessel's
motion is prescribed, so the pull on the vessel is an output only (``tension``,
``length``).
"""
from __future__ import annotations

import math

from numba import njit

from ._common import add_force_moment

KIND_TENSION = 0
KIND_ELASTIC = 1
KIND_FORCE = 2


@njit(cache=True)
def table_value(ts, vs, count, t):
    """Linear interpolation in rows ts[:count], vs[:count], held constant beyond them."""
    if count <= 1 or t <= ts[0]:
        return vs[0]
    if t >= ts[count - 1]:
        return vs[count - 1]
    k = 0
    while k < count - 2 and t > ts[k + 1]:
        k += 1
    return vs[k] + (vs[k + 1] - vs[k]) * (t - ts[k]) / (ts[k + 1] - ts[k])


@njit(cache=True)
def tugger_forces(tug_rfe, tug_att, tug_deck, tug_point, tug_kind, tug_t, tug_v, tug_count, tug_k, tug_L0, tug_c,
                  time, att_p, att_R, att_v, att_w, R, r, v, w, F, M, tension_out, length_out):
    """Add the pull of every tugger line to its body's F, M (global, about the body centre);
    tension_out[j], length_out[j]: its tension (N) and length (m)."""
    for j in range(tug_rfe.shape[0]):
        i = tug_rfe[j]
        a = tug_att[j]
        # deck point and its velocity
        gx = att_R[a, 0, 0] * tug_deck[j, 0] + att_R[a, 0, 1] * tug_deck[j, 1] + att_R[a, 0, 2] * tug_deck[j, 2]
        gy = att_R[a, 1, 0] * tug_deck[j, 0] + att_R[a, 1, 1] * tug_deck[j, 1] + att_R[a, 1, 2] * tug_deck[j, 2]
        gz = att_R[a, 2, 0] * tug_deck[j, 0] + att_R[a, 2, 1] * tug_deck[j, 1] + att_R[a, 2, 2] * tug_deck[j, 2]
        dx = att_p[a, 0] + gx
        dy = att_p[a, 1] + gy
        dz = att_p[a, 2] + gz
        vdx = att_v[a, 0] + att_w[a, 1] * gz - att_w[a, 2] * gy
        vdy = att_v[a, 1] + att_w[a, 2] * gx - att_w[a, 0] * gz
        vdz = att_v[a, 2] + att_w[a, 0] * gy - att_w[a, 1] * gx
        # body point (arm o from the centre) and its velocity
        ox = R[i, 0, 0] * tug_point[j, 0] + R[i, 0, 1] * tug_point[j, 1] + R[i, 0, 2] * tug_point[j, 2]
        oy = R[i, 1, 0] * tug_point[j, 0] + R[i, 1, 1] * tug_point[j, 1] + R[i, 1, 2] * tug_point[j, 2]
        oz = R[i, 2, 0] * tug_point[j, 0] + R[i, 2, 1] * tug_point[j, 1] + R[i, 2, 2] * tug_point[j, 2]
        ex = dx - (r[i, 0] + ox)
        ey = dy - (r[i, 1] + oy)
        ez = dz - (r[i, 2] + oz)
        L = math.sqrt(ex * ex + ey * ey + ez * ez)
        length_out[j] = L
        tension_out[j] = 0.0
        if L < 1e-9:
            continue            # the body point on the deck point: no direction to pull in
        ux = ex / L
        uy = ey / L
        uz = ez / L
        if tug_kind[j] == KIND_TENSION:
            T = table_value(tug_t[j], tug_v[j], tug_count[j], time)
        elif tug_kind[j] == KIND_FORCE:
            # a push P > 0 (a cylinder) is a negative pull, of either sign; end stops (tug_k the
            # stops' stiffness, tug_L0 the shortest length, tug_c the longest, 0: none)
            T = -table_value(tug_t[j], tug_v[j], tug_count[j], time)
            if tug_k[j] > 0.0:
                if tug_c[j] > 0.0 and L > tug_c[j]:
                    T += tug_k[j] * (L - tug_c[j])
                elif L < tug_L0[j]:
                    T -= tug_k[j] * (tug_L0[j] - L)
            tension_out[j] = T
            add_force_moment(F, M, i, ox, oy, oz, T * ux, T * uy, T * uz)
            continue
        else:
            s = L - tug_L0[j]
            if s <= 0.0:
                continue        # slack
            vpx = v[i, 0] + w[i, 1] * oz - w[i, 2] * oy
            vpy = v[i, 1] + w[i, 2] * ox - w[i, 0] * oz
            vpz = v[i, 2] + w[i, 0] * oy - w[i, 1] * ox
            Ld = ux * (vdx - vpx) + uy * (vdy - vpy) + uz * (vdz - vpz)
            T = tug_k[j] * s + tug_c[j] * Ld
        if T <= 0.0:
            continue
        tension_out[j] = T
        add_force_moment(F, M, i, ox, oy, oz, T * ux, T * uy, T * uz)
