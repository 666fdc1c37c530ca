"""Rest rotations and drives of SDEs: joints between lines (docs/theory.md, "Joints between
lines: rest rotation and drives").

The SDEs of section 8.4 are straight at rest: their deformation theta = log(R_a^T R_b)
(eq. 8.75 in rotation-vector form) vanishes when the two RFEs are aligned. A joint between
two lines (a crane's boom on its pedestal, a kinked connection) is stress-free at a given
relative rotation R0, its REST ROTATION: the deformation is measured from R_a* = R_a R0
instead of R_a (``rfesim.loads.sde``). A DRIVE (a slewing ring, a luffing cylinder) makes
the rest rotation a prescribed function of time,

    R0(t) = Rot(a_1, dphi_1(t)) Rot(a_2, dphi_2(t)) ... Rot(a_m, dphi_m(t)) sde_rest[s],

with a_k the drive axes in the body frame of the SDE's left RFE (the parent line's end)
and dphi_k(t) = phi_k(t) - phi_k(0) the drive angles relative to the start, phi_k a
monotone cubic (PCHIP) through an angle table, so the drive rate is continuous (from rest at
a first row at t >= 0: rfesim.model.supports.drive_slopes). The angular
velocity of R0 relative to RFE a (in a's body frame) is

    omega0 = sum_k (Rot(a_1, dphi_1) ... Rot(a_{k-1}, dphi_{k-1})) a_k dphi_k/dt

(dR0/dt = [omega0]x R0): the kernel subtracts it from the relative angular velocity of
the RFEs, so the damping of a driven joint acts on the deformation rate alone.

Kernel arrays (rfesim.model.arrays.KernelModel): ``sde_rest`` (nsde, 3, 3),
``sde_has_rest`` (nsde,) 0 identity / 1 constant rest / 2 driven, and the drive rows
``drive_sde, drive_axis, drive_t, drive_angle, drive_slope, drive_count, drive_phi0``
(rows of one SDE consecutive, in the order the rotations are composed); the effective rest
rotation and rate of the driven SDEs at the evaluation time go to the workspace arrays
``sde_rest_eff`` (nsde, 3, 3) and ``sde_rest_rate`` (nsde, 3) (``drive_rest_into``, called
at every evaluation of the equations of motion, rfesim.model.assemble).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..interp import bracket
from .sde import sde_moment_change_into


@njit(cache=True)
def drive_table(ts, ps, vs, t):
    """(value, slope) at t of the cubic Hermite through (ts, ps) with slopes vs (monotone
    PCHIP slopes from the compile step, rfesim.model.supports.drive_slopes), constant beyond the ends (slope 0 there). Also the
    payout curve of tensioners and reels (``rfesim.loads.tensioner._table``)."""
    n = ts.shape[0]
    if t <= ts[0]:
        return ps[0], 0.0
    if t >= ts[n - 1]:
        return ps[n - 1], 0.0
    lo = bracket(ts, t)
    hi = lo + 1
    h = ts[hi] - ts[lo]
    u = (t - ts[lo]) / h
    h00 = (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u)
    h10 = u * (1.0 - u) * (1.0 - u)
    h01 = u * u * (3.0 - 2.0 * u)
    h11 = u * u * (u - 1.0)
    val = h00 * ps[lo] + h10 * h * vs[lo] + h01 * ps[hi] + h11 * h * vs[hi]
    d00 = 6.0 * u * (u - 1.0)
    d10 = (1.0 - u) * (1.0 - 3.0 * u)
    d01 = -d00
    d11 = u * (3.0 * u - 2.0)
    slope = (d00 * ps[lo] + d01 * ps[hi]) / h + d10 * vs[lo] + d11 * vs[hi]
    return val, slope


@njit(cache=True)
def axis_angle_into(ax, angle, out):
    """Rotation by ``angle`` (rad) about the unit axis ``ax`` (Rodrigues), into out (3, 3)."""
    c = math.cos(angle)
    s = math.sin(angle)
    C = 1.0 - c
    x = ax[0]
    y = ax[1]
    z = ax[2]
    out[0, 0] = c + x * x * C
    out[0, 1] = x * y * C - z * s
    out[0, 2] = x * z * C + y * s
    out[1, 0] = y * x * C + z * s
    out[1, 1] = c + y * y * C
    out[1, 2] = y * z * C - x * s
    out[2, 0] = z * x * C - y * s
    out[2, 1] = z * y * C + x * s
    out[2, 2] = c + z * z * C


@njit(cache=True)
def drive_rest_into(drive_sde, drive_axis, drive_t, drive_angle, drive_slope, drive_count, drive_phi0, sde_rest, t,
                    rest_eff, rest_rate, P, Rk, T):
    """Effective rest rotation R0(t) (into rest_eff[s]) and its angular velocity omega0 in
    the left RFE's body frame (into rest_rate[s]) of every driven SDE s at time t.
    P, Rk, T are (3, 3) scratch."""
    nd = drive_sde.shape[0]
    j = 0
    while j < nd:
        s = drive_sde[j]
        w = rest_rate[s]
        for a in range(3):
            w[a] = 0.0
            for b in range(3):
                P[a, b] = 1.0 if a == b else 0.0
        while j < nd and drive_sde[j] == s:
            c = drive_count[j]
            phi, rate = drive_table(drive_t[j, :c], drive_angle[j, :c], drive_slope[j, :c], t)
            ax = drive_axis[j]
            # omega0 += (R_1 ... R_{k-1}) a_k dphi_k/dt
            for a in range(3):
                w[a] += rate * (P[a, 0] * ax[0] + P[a, 1] * ax[1] + P[a, 2] * ax[2])
            axis_angle_into(ax, phi - drive_phi0[j], Rk)
            for a in range(3):
                for b in range(3):
                    T[a, b] = P[a, 0] * Rk[0, b] + P[a, 1] * Rk[1, b] + P[a, 2] * Rk[2, b]
            for a in range(3):
                for b in range(3):
                    P[a, b] = T[a, b]
            j += 1
        S = sde_rest[s]
        out = rest_eff[s]
        for a in range(3):
            for b in range(3):
                out[a, b] = P[a, 0] * S[0, b] + P[a, 1] * S[1, b] + P[a, 2] * S[2, b]


# ----------------------------------------------------------------------------- Python helpers

def drive_angles(km, t: float) -> np.ndarray:
    """Drive angles relative to the start, dphi_k(t) = phi_k(t) - phi_k(0) (rad), one per row."""
    out = np.zeros(km.drive_sde.shape[0])
    for j in range(out.shape[0]):
        c = int(km.drive_count[j])
        phi, _ = drive_table(km.drive_t[j, :c], km.drive_angle[j, :c], km.drive_slope[j, :c], float(t))
        out[j] = phi - km.drive_phi0[j]
    return out


def drive_rates(km, t: float) -> np.ndarray:
    """Drive rates dphi_k/dt (rad/s), one per row."""
    out = np.zeros(km.drive_sde.shape[0])
    for j in range(out.shape[0]):
        c = int(km.drive_count[j])
        out[j] = drive_table(km.drive_t[j, :c], km.drive_angle[j, :c], km.drive_slope[j, :c], float(t))[1]
    return out


def rest_of_workspace(km, ws) -> np.ndarray:
    """Rest rotations (nsde, 3, 3) the SDE kernels used in the last evaluation of ws."""
    nsde = km.sde_left.shape[0]
    rest = np.zeros((nsde, 3, 3))
    rest[:] = np.eye(3)
    if km.sde_has_rest.shape[0] == nsde:
        one = km.sde_has_rest == 1
        two = km.sde_has_rest == 2
        rest[one] = km.sde_rest[one]
        rest[two] = ws.sde_rest_eff[two]
    return rest


def rest_at(km, t: float) -> tuple[np.ndarray, np.ndarray]:
    """Effective rest rotations (nsde, 3, 3) and rates omega0 (nsde, 3; left RFE's body
    frame, rad/s) of every SDE at time t (identity and 0 for SDEs without a rest rotation)."""
    nsde = km.sde_left.shape[0]
    rest = np.zeros((nsde, 3, 3))
    rest[:] = np.eye(3)
    rate = np.zeros((nsde, 3))
    if km.sde_rest.shape[0] == nsde:
        rest[:] = km.sde_rest
    if km.has_drives:
        drive_rest_into(km.drive_sde, km.drive_axis, km.drive_t, km.drive_angle, km.drive_slope, km.drive_count,
                        km.drive_phi0, np.ascontiguousarray(rest.copy()), float(t), rest, rate, np.zeros((3, 3)),
                        np.zeros((3, 3)), np.zeros((3, 3)))
    return rest, rate


# ----------------------------------------------------------------------------- torque-limited servo motors
#
# A MOTOR turns a clamped, coaxial join about its own axis (the joint SDE's torsion axis x,
# eq. 8.75): a slewing ring with a hydraulic or electric drive. It is a position servo with a
# torque limit (docs/theory.md, "Slewing motor with a torque limit"): the joint's torsional
# stiffness and damping are the servo gains k_p, k_d (set in sde_stiffness[s, 3] and
# sde_damping[s, 3] by the compile step, so the elastic law and its analytic tangent give
# k_p theta_x + k_d dtheta_x/dt), and ``motor_forces`` turns that moment into
#
#     M_x = clip(k_p (theta_x - theta_set(t)) + k_d (dtheta_x/dt - dtheta_set/dt), -T_max, T_max)
#
# with theta_set(t) = phi(t) - phi(0) from the angle table (monotone cubic, ``drive_table``).
# The joint's other five components stay those of a clamped joint. Below the limit the
# tangent is exact; at the limit the Jacobian keeps the servo gains (Newton converges
# linearly there).


@njit(cache=True)
def motor_forces(motor_sde, motor_t, motor_angle, motor_slope, motor_count, motor_stiffness, motor_damping,
                 motor_torque, motor_shift, t, only, sat, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                 rest_eff, R, rbase, roff, sigma, M, v3, m33):
    """Correct the torsional moment of every motor SDE (``only`` >= 0: that SDE alone) from
    the elastic law already applied (sigma[s, 3] = k_p theta_x + k_d dtheta_x/dt) to the
    torque-limited servo law above; the difference is applied like the SDE moment itself
    (eq. 8.90.2 through the exact J_r^-T), sigma is corrected too. sat[j] = 1 for a motor at
    its limit (its tangent is then 0: rfesim.solvers.jacobian), else 0. motor_shift[j]: the
    twist already moved into the joint's rest rotation (rfesim.model.joins.rebase_motors)."""
    for j in range(motor_sde.shape[0]):
        s = motor_sde[j]
        if only >= 0 and s != only:
            continue
        c = motor_count[j]
        phi, rate = drive_table(motor_t[j, :c], motor_angle[j, :c], motor_slope[j, :c], t)
        phi0 = drive_table(motor_t[j, :c], motor_angle[j, :c], motor_slope[j, :c], 0.0)[0]
        # theta_x is measured from the rest rotation, which has taken motor_shift of the twist
        raw = sigma[s, 3] - motor_stiffness[j] * (phi - phi0 - motor_shift[j]) - motor_damping[j] * rate
        lim = motor_torque[j]
        new = min(max(raw, -lim), lim)
        sat[j] = 1 if abs(raw) > lim else 0
        dm0 = new - sigma[s, 3]
        sigma[s, 3] = new
        torsion_moment_into(s, dm0, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                            rest_eff, R, rbase, roff, M, v3, m33)


@njit(cache=True)
def torsion_moment_into(s, dm0, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static, rest_eff,
                        R, rbase, roff, M, v3, m33):
    """Add a change dm0 of SDE s's torsional moment (in {i'}) to M as the SDE kernel
    applies its moments (rfesim.loads.sde.sde_moment_change_into)."""
    dm = v3[20]
    dm[0] = dm0
    dm[1] = 0.0
    dm[2] = 0.0
    sde_moment_change_into(s, dm, sde_left, sde_right, sde_arm_left, sde_arm_right, rest_flag, rest_static,
                           rest_eff, R, rbase, roff, M, v3[21], v3[22], v3, m33)
