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
  -k_g l (xi - xi_a - D) is capped at its share of the pads' capacity F_max (below; the pipe slips
  through the pads beyond it, the anchor then slides: the same spring-slider as the seabed
  friction, rfesim.loads.seabed).

Both springs (and the capacity) are weighted by min(1, xi / l, (L - xi) / l): the pads take
hold of an RFE over one element length after the entry and let go over one before the
exit, so a line passing through sees no jump of force as RFEs come and go. Only RFEs whose
centre lies within ``TRACK_CAPTURE`` (1 m) of the axis are in the track: the pads hold a
pipe on the axis, not line that merely lies between the planes through the entry and the
exit (before, a reel-lay template's pipe stored on the lower half of a 12 m drum, 21 m
from the tensioner's axis but 0.3 m past its entry plane, was pulled towards the axis with
63 MN, and statics failed for reel radii 11 to 13 m).

The paid-out length D is history: prescribed (a table of D against time, see ``_table``), or
driven by the tensioner's characteristic: payout speed v(T) from the grip force T it
carries, zero inside the dead band |T - T_set| <= band and v = (T - T_set -+ band) / gain
beyond it, limited to +-v_max. A driven D is implicit in the step (backward Euler): at every
force evaluation at time t, h = t - t_c after the last commit at t_c,

    D = D_c + h v(T(D)),        T(D) = sum over the gripped RFEs of clip(k_g l w (xi - xi_a - D), +-cap_i),

solved for D by safeguarded Newton (T(D) is piecewise linear and non-increasing, so the
root is unique and lies within h v_max of D_c; ``solve_driven_payout``). The pads thus move
with the pipe inside the step: the loop of grip stiffness k = sum k_g l w (1e8 N/m for a
10 m track) and gain is stable at any step, where the explicit update D_c + h v(T(D_c))
(used before) needed h < 2 gain / k (2 ms at gain 1e5 N s/m) and chattered beyond it
(docs/theory.md, 'Driven payout'). The trial D is kept in the workspace (``D_trial``,
``Workspace.tens_D_trial``; the model's arrays stay constant) and committed with the grips.
RFEs that enter the track are gripped where they
are, RFEs that leave it are released: no RFE is created or deleted, the line's length, mass
and momentum stay those of the material (the stored pipe upstream of the tensioner is part
of the line).

Capacity: F_max is what the whole track holds: each gripped RFE's share is
F_max l w / sum(l w) over the RFEs in the track (w the taper weight), so the shares add up
to F_max whatever the element length and the taper (before: F_max l w / L, which with the
taper and a half-length end element summed to about 0.75 F_max).
"""
from __future__ import annotations


from numba import njit

from .drives import drive_table

MODE_TABLE = 0
MODE_TENSION = 1
TRACK_CAPTURE = 1.0         # m: an RFE whose centre is farther from a track's axis is not in the track


@njit(cache=True)
def _table(ts, ds, vs, t):
    """Cubic Hermite through (ts, ds) with slopes vs (from the compile step,
    ``rfesim.model.supports.table_slopes``: monotone PCHIP slopes for three rows or more, the
    secant for two, so a two-row table is a straight line at constant speed); constant
    beyond the ends (``rfesim.loads.drives.drive_table``'s value)."""
    return drive_table(ts, ds, vs, t)[0]


@njit(cache=True)
def tensioner_payout(tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, j, t, D_committed):
    """Paid-out length of tensioner j at time t: the table, or the committed (driven) value."""
    if tens_mode[j] == MODE_TABLE:
        c = tens_count[j]
        return _table(tens_table_t[j, :c], tens_table_d[j, :c], tens_table_v[j, :c], t)
    return D_committed[j]


@njit(cache=True)
def payout_speed(T, T_set, band, gain, vmax):
    """(v, dv/dT) of the characteristic: dead band, gain, speed limit."""
    dT = T - T_set
    v = 0.0
    dv = 0.0
    if dT > band:
        v = (dT - band) / gain
        dv = 1.0 / gain
    elif dT < -band:
        v = (dT + band) / gain
        dv = 1.0 / gain
    if v > vmax:
        v = vmax
        dv = 0.0
    elif v < -vmax:
        v = -vmax
        dv = 0.0
    return v, dv


@njit(cache=True)
def payout_newton(D, D0, h, u, k, T_set, band, gain, vmax, lo, hi):
    """One safeguarded Newton step on g(D) = D - D0 - h v(u(D)), du/dD = -k <= 0 (g rises
    with slope >= 1: one root, bracketed by [lo, hi]). Returns (g, next D, lo, hi)."""
    v, dv = payout_speed(u, T_set, band, gain, vmax)
    g = D - D0 - h * v
    if g > 0.0:
        hi = D
    else:
        lo = D
    Dn = D - g / (1.0 + h * dv * k)
    if not lo < Dn < hi:
        Dn = 0.5 * (lo + hi)
    return g, Dn, lo, hi


@njit(cache=True)
def track_weight(xi, L, li):
    """The pads' hold on an RFE of length li at xi along a track of length L (module text):
    min(1, xi / li, (L - xi) / li), 0 outside the track."""
    if xi < 0.0 or xi > L:
        return 0.0
    return max(0.0, min(1.0, xi / li, (L - xi) / li))


@njit(cache=True)
def off_axis(dx, dy, dz, xi, ex, ey, ez):
    """True when the point (dx, dy, dz) from a track's entry, xi along its unit axis e, lies
    farther than TRACK_CAPTURE from the axis: not in the track (module text)."""
    lx = dx - xi * ex
    ly = dy - xi * ey
    lz = dz - xi * ez
    return lx * lx + ly * ly + lz * lz > TRACK_CAPTURE * TRACK_CAPTURE


@njit(cache=True)
def _track_grip(D, lo, hi, px, py, pz, ex, ey, ez, L, kg_j, cap_share, rfe_length, r, grip_a, grip_on):
    """(T, k): the axial force T(D) the gripped RFEs in the track carry with the pads at D
    (the grip law of ``tensioner_forces``) and -dT/dD (the grip stiffness of the RFEs below
    their capacity)."""
    T = 0.0
    k = 0.0
    for i in range(lo, hi):
        if grip_on[i] == 0:
            continue
        dx = r[i, 0] - px
        dy = r[i, 1] - py
        dz = r[i, 2] - pz
        xi = dx * ex + dy * ey + dz * ez
        li = rfe_length[i]
        wgt = track_weight(xi, L, li)
        if wgt <= 0.0 or off_axis(dx, dy, dz, xi, ex, ey, ez):
            continue
        kg = kg_j * li * wgt
        cap = cap_share * li * wgt
        f = kg * (xi - grip_a[i] - D)
        if f > cap:
            f = cap
        elif f < -cap:
            f = -cap
        else:
            k += kg
        T += f
    return T, k


MAX_PAYOUT_ITERATIONS = 60


@njit(cache=True)
def tensioner_forces(tens_att, tens_point, tens_axis, tens_length, tens_kl, tens_kg, tens_cap, tens_line_lo,
                     tens_line_hi, tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, t, att_p, att_R,
                     rfe_length, r, F, grip_a, grip_on, grip_a_trial, grip_on_trial, D_committed, grip_force,
                     tens_set, tens_band, tens_gain, tens_vmax, h, D_trial):
    """Add the forces of every tensioner on the RFEs in its track to F (at the centres: no
    moment). grip_a/grip_on (n,) committed grip anchors (material coordinate, m) and
    whether each RFE is gripped; the trial values are written. grip_force (ntens,) the
    axial force each tensioner carries (N, positive when it holds the line back). h: time
    since the last commit (a driven tensioner's D is solved implicitly over it and kept in
    D_trial[j] (ntens,), the workspace's tens_D_trial; 0 in statics)."""
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
        L = tens_length[j]
        # the RFEs in the track: their range and summed weighted length (the capacity's shares)
        first = tens_line_hi[j]
        last = tens_line_lo[j]
        held = 0.0
        for i in range(tens_line_lo[j], tens_line_hi[j]):
            dx = r[i, 0] - px
            dy = r[i, 1] - py
            dz = r[i, 2] - pz
            xi = dx * ex + dy * ey + dz * ez
            li = rfe_length[i]
            wgt = track_weight(xi, L, li)
            if wgt <= 0.0 or off_axis(dx, dy, dz, xi, ex, ey, ez):
                continue
            held += li * wgt
            first = min(first, i)
            last = max(last, i + 1)
        cap_share = tens_cap[j] / held if held > 0.0 else 0.0
        D = tensioner_payout(tens_mode, tens_table_t, tens_table_d, tens_table_v, tens_count, j, t, D_committed)
        if tens_mode[j] == MODE_TENSION:
            if h > 0.0 and first < last:
                D = solve_driven_payout(D, h, 0.0, tens_set[j], tens_band[j], tens_gain[j], tens_vmax[j], first, last,
                                        px, py, pz, ex, ey, ez, L, tens_kg[j], cap_share, rfe_length, r, grip_a,
                                        grip_on)
            elif h > 0.0:
                v, dv = payout_speed(0.0, tens_set[j], tens_band[j], tens_gain[j], tens_vmax[j])
                D += h * v
            D_trial[j] = D
        total = 0.0
        for i in range(tens_line_lo[j], tens_line_hi[j]):
            dx = r[i, 0] - px
            dy = r[i, 1] - py
            dz = r[i, 2] - pz
            xi = dx * ex + dy * ey + dz * ez
            if xi < 0.0 or xi > L or off_axis(dx, dy, dz, xi, ex, ey, ez):
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
                cap = cap_share * li * wgt
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
def solve_driven_payout(D0, h, offset, T_set, band, gain, vmax, lo, hi, px, py, pz, ex, ey, ez, L, kg_j, cap_share,
                        rfe_length, r, grip_a, grip_on):
    """D = D0 + h v(offset + T(D)) for a driven track (module text): the implicit payout."""
    a = D0 - h * vmax - 1e-12
    b = D0 + h * vmax + 1e-12
    D = D0
    for _ in range(MAX_PAYOUT_ITERATIONS):
        T, k = _track_grip(D, lo, hi, px, py, pz, ex, ey, ez, L, kg_j, cap_share, rfe_length, r, grip_a, grip_on)
        g, Dn, a, b = payout_newton(D, D0, h, offset + T, k, T_set, band, gain, vmax, a, b)
        if abs(g) <= 1e-12 * (1.0 + abs(D)) or b - a <= 1e-14 * (1.0 + abs(D)):
            break
        D = Dn
    return D


@njit(cache=True)
def commit_tensioners(tens_mode, D_trial, D_committed, h, grip_a, grip_on, grip_a_trial, grip_on_trial,
                      tens_line_lo, tens_line_hi):
    """Accept the trial grips and, after a step (h > 0), the driven tensioners' paid-out
    length solved implicitly in the step's last force evaluation (kept in D_trial[j])."""
    for j in range(tens_mode.shape[0]):
        for i in range(tens_line_lo[j], tens_line_hi[j]):
            grip_a[i] = grip_a_trial[i]
            grip_on[i] = grip_on_trial[i]
        if tens_mode[j] == MODE_TENSION and h > 0.0:
            D_committed[j] = D_trial[j]
