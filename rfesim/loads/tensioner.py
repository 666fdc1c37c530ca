"""Tensioners: a straight track on a vessel (or fixed) that holds a line laterally and grips
it axially, paying it out (or reeling it in) as the track moves (eq. 8.95's guiding
structures: forces of the mechanism on the RFEs it holds).

Geometry: track t has its entry point P (attachment frame), unit axis e pointing in the
payout direction (towards the sea) and length L. An RFE whose centre r lies within the
track, 0 <= xi = e.(r - P) <= L, is

* held on the axis by a lateral spring -k_l l (r - P - xi e) per unit length l of the
  RFE (a pad pressure), and
* gripped axially: the pads move with the track by D(t) (paid-out length) and grip the
  RFE at the material point it had when it entered, xi_a: the grip force
  -k_g l (xi - xi_a - D) is capped at the pads' capacity F_max l / L per RFE (the pipe slips
  through the pads beyond it, the anchor then slides: the same spring-slider as the seabed
  friction, rfesim.loads.seabed).

Both springs (and the capacity) are weighted by min(1, xi / l, (L - xi) / l): the pads take
hold of an RFE over one element length after the entry and let go over one before the
exit, so a line passing through sees no jump of force as RFEs come and go.

The paid-out length D is history: prescribed (a table of D against time, interpolated by a
monotone cubic: the payout speed is continuous), or driven by the tensioner's characteristic:
payout speed v(T) from the grip force T it carries, zero inside the dead band
|T - T_set| <= band and v = (T - T_set -+ band) / gain beyond it, limited to +-v_max;
D advances by v h at every accepted step (explicit in the step, exact for a prescribed
table). RFEs that enter the track are gripped where they are, RFEs that leave it are
released: no RFE is created or deleted, the line's length, mass and momentum stay those
of the material (the stored pipe upstream of the tensioner is part of the line).
"""
from __future__ import annotations


from numba import njit

from .drives import drive_table

MODE_TABLE = 0
MODE_TENSION = 1


@njit(cache=True)
def _table(ts, ds, vs, t):
    """Cubic Hermite through (ts, ds) with slopes vs (monotone PCHIP slopes from the compile
    step): the payout speed is continuous, so a payout that starts or stops gives no
    impulse; constant beyond the ends (``rfesim.loads.drives.drive_table``'s value)."""
    return drive_table(ts, ds, vs, t)[0]


@njit(cache=True)
def tensioner_payout(tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, j, t, D_committed):
    """Paid-out length of tensioner j at time t: the table, or the committed (driven) value."""
    if tens_mode[j] == MODE_TABLE:
        c = tens_count[j]
        return _table(tens_table_t[j, :c], tens_table_d[j, :c], tens_table_v[j, :c], t)
    return D_committed[j]


@njit(cache=True)
def tensioner_forces(tens_att, tens_point, tens_axis, tens_length, tens_kl, tens_kg, tens_cap, tens_line_lo,
                     tens_line_hi, tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, t, att_p, att_R,
                     rfe_length, r, F, grip_a, grip_on, grip_a_trial, grip_on_trial, D_committed, grip_force):
    """Add the forces of every tensioner on the RFEs in its track to F (at the centres: no
    moment). grip_a/grip_on (n,) committed grip anchors (material coordinate, m) and
    whether each RFE is gripped; the trial values are written. grip_force (ntens,) the
    axial force each tensioner carries (N, positive when it holds the line back)."""
    for j in range(tens_point.shape[0]):
        a = tens_att[j]
        R = att_R[a]
        # entry point and axis in the global frame
        px = att_p[a, 0] + R[0, 0] * tens_point[j, 0] + R[0, 1] * tens_point[j, 1] + R[0, 2] * tens_point[j, 2]
        py = att_p[a, 1] + R[1, 0] * tens_point[j, 0] + R[1, 1] * tens_point[j, 1] + R[1, 2] * tens_point[j, 2]
        pz = att_p[a, 2] + R[2, 0] * tens_point[j, 0] + R[2, 1] * tens_point[j, 1] + R[2, 2] * tens_point[j, 2]
        ex = R[0, 0] * tens_axis[j, 0] + R[0, 1] * tens_axis[j, 1] + R[0, 2] * tens_axis[j, 2]
        ey = R[1, 0] * tens_axis[j, 0] + R[1, 1] * tens_axis[j, 1] + R[1, 2] * tens_axis[j, 2]
        ez = R[2, 0] * tens_axis[j, 0] + R[2, 1] * tens_axis[j, 1] + R[2, 2] * tens_axis[j, 2]
        D = tensioner_payout(tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, j, t, D_committed)
        L = tens_length[j]
        total = 0.0
        for i in range(tens_line_lo[j], tens_line_hi[j]):
            dx = r[i, 0] - px
            dy = r[i, 1] - py
            dz = r[i, 2] - pz
            xi = dx * ex + dy * ey + dz * ez
            if xi < 0.0 or xi > L:
                grip_on_trial[i] = 0
                continue
            li = rfe_length[i]
            # the pads take hold over one element length at the entry and let go over one at
            # the exit: a line passing through sees no jump of force as RFEs come and go
            wgt = min(1.0, xi / li, (L - xi) / li)
            if wgt <= 0.0:
                grip_on_trial[i] = 0
                continue
            # lateral: back onto the axis
            kl = tens_kl[j] * li * wgt
            F[i, 0] -= kl * (dx - xi * ex)
            F[i, 1] -= kl * (dy - xi * ey)
            F[i, 2] -= kl * (dz - xi * ez)
            # axial grip, spring-slider against the moving pads
            kg = tens_kg[j] * li * wgt
            if grip_on[i] == 0:
                anchor = xi - D            # enters the track: gripped where it is
                f = 0.0
            else:
                anchor = grip_a[i]
                f = -kg * (xi - anchor - D)
                cap = tens_cap[j] * li * wgt / L
                if f > cap:
                    f = cap
                    anchor = xi - D + f / kg
                elif f < -cap:
                    f = -cap
                    anchor = xi - D + f / kg
            grip_a_trial[i] = anchor
            grip_on_trial[i] = 1
            F[i, 0] += f * ex
            F[i, 1] += f * ey
            F[i, 2] += f * ez
            total -= f
        grip_force[j] = total


@njit(cache=True)
def commit_tensioners(tens_mode, tens_set, tens_band, tens_gain, tens_vmax, grip_force, D_committed, h,
                      grip_a, grip_on, grip_a_trial, grip_on_trial, tens_line_lo, tens_line_hi):
    """Accept the trial grips and advance the driven tensioners by one step h: payout speed
    from the characteristic (dead band, gain, speed limit) at the grip force of the step."""
    for j in range(tens_mode.shape[0]):
        for i in range(tens_line_lo[j], tens_line_hi[j]):
            grip_a[i] = grip_a_trial[i]
            grip_on[i] = grip_on_trial[i]
        if tens_mode[j] == MODE_TENSION and h > 0.0:
            dT = grip_force[j] - tens_set[j]
            v = 0.0
            if dT > tens_band[j]:
                v = (dT - tens_band[j]) / tens_gain[j]
            elif dT < -tens_band[j]:
                v = (dT + tens_band[j]) / tens_gain[j]
            if v > tens_vmax[j]:
                v = tens_vmax[j]
            elif v < -tens_vmax[j]:
                v = -tens_vmax[j]
            D_committed[j] += v * h
