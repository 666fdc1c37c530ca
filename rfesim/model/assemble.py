"""Equations of motion of the absolute-coordinate RFE model (section 8.4.1, eq. 8.92).

``evaluate`` computes, for a state (q, qdot) and the attachments' kinematics, every RFE's
generalised mass block ``Mgen`` (6x6) and generalised force ``fgen`` (applied forces minus
velocity terms), so that ``Mgen qddot = fgen`` RFE by RFE (the mass matrix A of eq. 8.92
is block diagonal).

Coordinates of RFE i (eq. 8.72): ``[x, y, z, psi, theta, phi]``, centre position and ZYX
angles measured from the RFE's reference rotation R0 (R = R0 Rzyx). For a pinned RFE only
the angles are coordinates (its end point follows the attachment); a clamped RFE has
none. Unused coordinates have identity mass and zero force, so they stay zero.

Projection of forces (the content of eq. 8.94): a resultant force F at the centre and a
moment M (global) give ``Q_r = F`` and ``Q_angles = E^T R^T M`` with E the Euler-rate
matrix (``omega_body = E d(angles)/dt``); the kinetic energy terms (eqs. 8.11-8.18) give
``E^T J E`` and the velocity terms ``E^T (omega x J omega + J dE/dt rates)``.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kinematics import (cross_into, euler_rate_derivative_into, euler_rate_matrix_into, matmul_into,
                          matTvec_into, matvec_into, rot_zyx_into, skew_into, solve3_sym_into)
from ..loads.bodies import body_hydro_forces
from ..loads.deck import deck_forces
from ..loads.tugger import tugger_forces
from ..loads.reeving import reeving_forces, slip_arms
from ..loads.gravity import gravity_forces
from ..loads.hydro import buoyancy_forces, morison_forces, submergence
from ..loads.point import point_loads
from ..loads.drives import drive_rest_into, motor_forces
from ..loads.sde import commit_plastic, plastic_sde_correction
from ..loads.sde_fused import sde_forces_rest_fused
from ..loads.rollers import commit_roller_friction, roller_forces
from ..loads.seabed import commit_friction, seabed_forces
from ..loads.tensioner import commit_tensioners, tensioner_forces
from ..loads.reel import reel_forces
from ..loads.tension_only import tension_only_correction_rest
from ..sea.kernel import sea_kinematics_into, sea_kinematics_reach


@njit(cache=True, _nrt=False)
def poses(km, att, q, qd, ref, ws):
    """Orientation, position, velocities of every RFE from the coordinates (eqs. 8.73-8.74):
    ``poses_fused``, the scalar form of ``poses_reference``."""
    poses_fused(km.rfe_kind, km.rfe_attach, km.rfe_attach_offset, km.rfe_pin_arm, km.rfe_clamp_R, att.R, att.p,
                att.v, att.w, q, qd, ref.R, ref.X, ws.R, ws.E, ws.Edot, ws.wb, ws.w, ws.r, ws.rbase, ws.roff, ws.v)


@njit(cache=True, inline="always")
def _pinned_point(i, a, R, att_R, att_p, rfe_attach_offset, rfe_pin_arm):
    """(P, m) of RFE i on attachment a: its attachment point P = p_a + R_a o (o the offset in
    the attachment frame) and its arm m = R_i x from the centre to the point (x the pin arm in
    the RFE frame); the centre is P - m. Scalar, for the fused pose kernel."""
    o0 = rfe_attach_offset[i, 0]; o1 = rfe_attach_offset[i, 1]; o2 = rfe_attach_offset[i, 2]
    P0 = att_R[a, 0, 0] * o0 + att_R[a, 0, 1] * o1 + att_R[a, 0, 2] * o2 + att_p[a, 0]
    P1 = att_R[a, 1, 0] * o0 + att_R[a, 1, 1] * o1 + att_R[a, 1, 2] * o2 + att_p[a, 1]
    P2 = att_R[a, 2, 0] * o0 + att_R[a, 2, 1] * o1 + att_R[a, 2, 2] * o2 + att_p[a, 2]
    x0 = rfe_pin_arm[i, 0]; x1 = rfe_pin_arm[i, 1]; x2 = rfe_pin_arm[i, 2]
    m0 = R[i, 0, 0] * x0 + R[i, 0, 1] * x1 + R[i, 0, 2] * x2
    m1 = R[i, 1, 0] * x0 + R[i, 1, 1] * x1 + R[i, 1, 2] * x2
    m2 = R[i, 2, 0] * x0 + R[i, 2, 1] * x1 + R[i, 2, 2] * x2
    return P0, P1, P2, m0, m1, m2


@njit(cache=True)
def poses_fused(rfe_kind, rfe_attach, rfe_attach_offset, rfe_pin_arm, rfe_clamp_R, att_R, att_p, att_v, att_w, q, qd,
                ref_R, ref_X, R, E, Edot, wb, w, r, rbase, roff, v):
    """``poses_reference`` (the same results to the bit) on the arrays themselves, with
    scalar locals and one sine and cosine per angle: the readable version's array views
    and helper calls per RFE cost more than its arithmetic."""
    for i in range(q.shape[0]):
        kind = rfe_kind[i]
        if kind == 2:
            a = rfe_attach[i]
            for j in range(3):
                for k in range(3):
                    R[i, j, k] = att_R[a, j, 0] * rfe_clamp_R[i, 0, k] + att_R[a, j, 1] * rfe_clamp_R[i, 1, k] \
                        + att_R[a, j, 2] * rfe_clamp_R[i, 2, k]
            P0, P1, P2, m0, m1, m2 = _pinned_point(i, a, R, att_R, att_p, rfe_attach_offset, rfe_pin_arm)
            r[i, 0] = P0 - m0
            r[i, 1] = P1 - m1
            r[i, 2] = P2 - m2
            rbase[i, 0] = P0
            rbase[i, 1] = P1
            rbase[i, 2] = P2
            roff[i, 0] = -m0
            roff[i, 1] = -m1
            roff[i, 2] = -m2
            w0 = att_w[a, 0]; w1 = att_w[a, 1]; w2 = att_w[a, 2]
            w[i, 0] = w0
            w[i, 1] = w1
            w[i, 2] = w2
            c0 = r[i, 0] - att_p[a, 0]
            c1 = r[i, 1] - att_p[a, 1]
            c2 = r[i, 2] - att_p[a, 2]
            v[i, 0] = att_v[a, 0] + (w1 * c2 - w2 * c1)
            v[i, 1] = att_v[a, 1] + (w2 * c0 - w0 * c2)
            v[i, 2] = att_v[a, 2] + (w0 * c1 - w1 * c0)
            wb[i, 0] = R[i, 0, 0] * w0 + R[i, 1, 0] * w1 + R[i, 2, 0] * w2
            wb[i, 1] = R[i, 0, 1] * w0 + R[i, 1, 1] * w1 + R[i, 2, 1] * w2
            wb[i, 2] = R[i, 0, 2] * w0 + R[i, 1, 2] * w1 + R[i, 2, 2] * w2
            for k in range(3):
                Edot[i, k] = 0.0
                for m in range(3):
                    E[i, k, m] = 0.0
            continue
        psi = q[i, 3]
        theta = q[i, 4]
        phi = q[i, 5]
        cz = math.cos(psi)
        sz = math.sin(psi)
        cy = math.cos(theta)
        sy = math.sin(theta)
        cx = math.cos(phi)
        sx = math.sin(phi)
        z00 = cz * cy
        z01 = cz * sy * sx - sz * cx
        z02 = cz * sy * cx + sz * sx
        z10 = sz * cy
        z11 = sz * sy * sx + cz * cx
        z12 = sz * sy * cx - cz * sx
        z20 = -sy
        z21 = cy * sx
        z22 = cy * cx
        for j in range(3):
            f0 = ref_R[i, j, 0]
            f1 = ref_R[i, j, 1]
            f2 = ref_R[i, j, 2]
            R[i, j, 0] = f0 * z00 + f1 * z10 + f2 * z20
            R[i, j, 1] = f0 * z01 + f1 * z11 + f2 * z21
            R[i, j, 2] = f0 * z02 + f1 * z12 + f2 * z22
        E00 = -sy
        E01 = 0.0
        E02 = 1.0
        E10 = cy * sx
        E11 = cx
        E12 = 0.0
        E20 = cy * cx
        E21 = -sx
        E22 = 0.0
        E[i, 0, 0] = E00
        E[i, 0, 1] = E01
        E[i, 0, 2] = E02
        E[i, 1, 0] = E10
        E[i, 1, 1] = E11
        E[i, 1, 2] = E12
        E[i, 2, 0] = E20
        E[i, 2, 1] = E21
        E[i, 2, 2] = E22
        dpsi = qd[i, 3]
        dtheta = qd[i, 4]
        dphi = qd[i, 5]
        b0 = E00 * dpsi + E01 * dtheta + E02 * dphi
        b1 = E10 * dpsi + E11 * dtheta + E12 * dphi
        b2 = E20 * dpsi + E21 * dtheta + E22 * dphi
        wb[i, 0] = b0
        wb[i, 1] = b1
        wb[i, 2] = b2
        w0 = R[i, 0, 0] * b0 + R[i, 0, 1] * b1 + R[i, 0, 2] * b2
        w1 = R[i, 1, 0] * b0 + R[i, 1, 1] * b1 + R[i, 1, 2] * b2
        w2 = R[i, 2, 0] * b0 + R[i, 2, 1] * b1 + R[i, 2, 2] * b2
        w[i, 0] = w0
        w[i, 1] = w1
        w[i, 2] = w2
        Edot[i, 0] = -dpsi * dtheta * cy
        Edot[i, 1] = -dtheta * dphi * sx + dpsi * (-dtheta * sy * sx + cy * cx * dphi)
        Edot[i, 2] = -dtheta * dphi * cx + dpsi * (-dtheta * sy * cx - cy * sx * dphi)
        if kind == 0:
            for k in range(3):
                rbase[i, k] = ref_X[i, k]
                roff[i, k] = q[i, k]
                r[i, k] = ref_X[i, k] + q[i, k]
                v[i, k] = qd[i, k]
        else:
            a = rfe_attach[i]
            P0, P1, P2, m0, m1, m2 = _pinned_point(i, a, R, att_R, att_p, rfe_attach_offset, rfe_pin_arm)
            r0 = P0 - m0
            r1 = P1 - m1
            r2 = P2 - m2
            r[i, 0] = r0
            r[i, 1] = r1
            r[i, 2] = r2
            rbase[i, 0] = P0
            rbase[i, 1] = P1
            rbase[i, 2] = P2
            roff[i, 0] = -m0
            roff[i, 1] = -m1
            roff[i, 2] = -m2
            c0 = P0 - att_p[a, 0]
            c1 = P1 - att_p[a, 1]
            c2 = P2 - att_p[a, 2]
            u0 = att_w[a, 0]; u1 = att_w[a, 1]; u2 = att_w[a, 2]
            v0 = att_v[a, 0] + (u1 * c2 - u2 * c1)
            v1 = att_v[a, 1] + (u2 * c0 - u0 * c2)
            v2 = att_v[a, 2] + (u0 * c1 - u1 * c0)
            c0 = r0 - P0
            c1 = r1 - P1
            c2 = r2 - P2
            v[i, 0] = v0 + (w1 * c2 - w2 * c1)
            v[i, 1] = v1 + (w2 * c0 - w0 * c2)
            v[i, 2] = v2 + (w0 * c1 - w1 * c0)


@njit(cache=True)
def poses_reference(km, att, q, qd, ref, ws):
    """Orientation, position, velocities of every RFE from the coordinates (eqs. 8.73-8.74);
    the readable reference of ``poses_fused`` (tests/unit/test_fused_kernels.py)."""
    Rz = ws.m33[0]
    P = ws.v3[0]
    tmp = ws.v3[1]
    c = ws.v3[2]
    for i in range(q.shape[0]):
        kind = km.rfe_kind[i]
        R = ws.R[i]
        if kind == 2:
            a = km.rfe_attach[i]
            matmul_into(att.R[a], km.rfe_clamp_R[i], R)
            matvec_into(att.R[a], km.rfe_attach_offset[i], P)
            matvec_into(R, km.rfe_pin_arm[i], tmp)
            for k in range(3):
                P[k] += att.p[a, k]
                ws.r[i, k] = P[k] - tmp[k]
                ws.rbase[i, k] = P[k]
                ws.roff[i, k] = -tmp[k]
                ws.w[i, k] = att.w[a, k]
                c[k] = ws.r[i, k] - att.p[a, k]
            cross_into(att.w[a], c, tmp)
            for k in range(3):
                ws.v[i, k] = att.v[a, k] + tmp[k]
            matTvec_into(R, ws.w[i], ws.wb[i])
            for k in range(3):
                ws.Edot[i, k] = 0.0
                for m in range(3):
                    ws.E[i, k, m] = 0.0
            continue
        rot_zyx_into(q[i, 3], q[i, 4], q[i, 5], Rz)
        matmul_into(ref.R[i], Rz, R)
        euler_rate_matrix_into(q[i, 3], q[i, 4], q[i, 5], ws.E[i])
        matvec_into(ws.E[i], qd[i, 3:6], ws.wb[i])
        matvec_into(R, ws.wb[i], ws.w[i])
        euler_rate_derivative_into(q[i, 3], q[i, 4], q[i, 5], qd[i, 3], qd[i, 4], qd[i, 5], ws.Edot[i])
        if kind == 0:
            for k in range(3):
                ws.rbase[i, k] = ref.X[i, k]
                ws.roff[i, k] = q[i, k]
                ws.r[i, k] = ref.X[i, k] + q[i, k]
                ws.v[i, k] = qd[i, k]
        else:
            a = km.rfe_attach[i]
            matvec_into(att.R[a], km.rfe_attach_offset[i], P)
            for k in range(3):
                P[k] += att.p[a, k]
            matvec_into(R, km.rfe_pin_arm[i], tmp)
            for k in range(3):
                ws.r[i, k] = P[k] - tmp[k]
                ws.rbase[i, k] = P[k]
                ws.roff[i, k] = -tmp[k]
                c[k] = P[k] - att.p[a, k]
            # velocity of the pin point, then of the centre
            cross_into(att.w[a], c, tmp)
            for k in range(3):
                ws.v[i, k] = att.v[a, k] + tmp[k]
                c[k] = ws.r[i, k] - P[k]
            cross_into(ws.w[i], c, tmp)
            for k in range(3):
                ws.v[i, k] += tmp[k]


@njit(cache=True, _nrt=False)
def accumulate_forces(km, att, ws, scale):
    """Zero the accumulators and add every load module the scene contains."""
    zero_forces(ws)
    sde_part(km, att, ws, ws.F, ws.M)
    local_loads(km, att, ws, scale)


@njit(cache=True, _nrt=False)
def zero_forces(ws):
    """ws.F = ws.M = 0."""
    for i in range(ws.F.shape[0]):
        for k in range(3):
            ws.F[i, k] = 0.0
            ws.M[i, k] = 0.0


@njit(cache=True, _nrt=False)
def sde_part(km, att, ws, F, M):
    """Every SDE force and moment added to F, M: elastic and damping (with rest rotations and
    drives), the elasto-plastic correction, slack ropes, servo motors, and the sheaves' pull
    toward the rope's lead (reeving: the tension of a join SDE, so it goes with them)."""
    if km.has_reeving:
        # a rope slipping over its sheave toward a vessel lead: the join's arm on the rope
        slip_arms(km.rv_sde, km.rv_slip, km.rv_att, km.rv_point, km.rv_len, km.rv_arm_written, km.rv_arm_offset,
                  km.sde_left, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness, km.sde_damping, ws.R, ws.rbase,
                  ws.roff, ws.v, ws.w, att.p, att.R, att.v, att.w, ws.rv_slip_out)
    sde_forces_all(km, att, ws, F, M)
    if km.has_plastic:
        plastic_forces(km, ws, M)
    if km.has_tension_only:
        tension_only_forces(km, ws, F, M)
    if km.has_motors:
        motor_moments(km, att, ws, -1, M)
    if km.has_reeving:
        reeving_forces(km.rv_sde, km.rv_kind, km.rv_att, km.rv_rfe, km.rv_point, km.sde_left, km.sde_right,
                       km.sde_arm_left, km.sde_arm_right, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R,
                       ws.rbase, ws.roff, ws.sigma, ws.sde_point, att.p, att.R, F, M, ws.rv_tension, ws.rv_dir,
                       ws.rv_fdir, ws.v3, ws.m33)


@njit(cache=True, _nrt=False)
def drive_rests(km, att, ws):
    """Rest rotations R0(t) and their rates of the driven SDEs at the attachments' time
    (rfesim.loads.drives), into ws.sde_rest_eff and ws.sde_rest_rate."""
    if km.has_drives:
        drive_rest_into(km.drive_sde, km.drive_axis, km.drive_t, km.drive_angle, km.drive_slope, km.drive_count,
                        km.drive_phi0, km.sde_rest, att.time[0], ws.sde_rest_eff, ws.sde_rest_rate, ws.m33[8],
                        ws.m33[9], ws.m33[10])


@njit(cache=True, _nrt=False)
def sde_forces_all(km, att, ws, F, M):
    """The elastic and damping SDE forces (with rest rotations and drives) added to F, M;
    ws.eps, ws.sigma, ws.sde_point are written."""
    drive_rests(km, att, ws)
    # the scalar form of rfesim.loads.sde.sde_forces_rest_into (the same numbers, 4x faster)
    sde_forces_rest_fused(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                          km.sde_damping, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.sde_rest_rate, ws.R,
                          ws.rbase, ws.roff, ws.v, ws.w, F, M, ws.eps, ws.sigma, ws.sde_point)


@njit(cache=True, _nrt=False)
def plastic_forces(km, ws, M):
    """The elasto-plastic bending correction of the SDEs (after the elastic SDE forces)."""
    plastic_sde_correction(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                           km.sde_length, km.sde_plastic, km.plastic_params, ws.plastic_hist, ws.plastic_hist_trial,
                           ws.R, ws.rbase, ws.roff, ws.eps, ws.sigma, M, ws.k_tangent, ws.out5, ws.v3, ws.m33,
                           km.sde_has_rest, km.sde_rest, ws.sde_rest_eff)


@njit(cache=True, _nrt=False)
def motor_moments(km, att, ws, only, M):
    """Servo motors of coaxial joins: the torque-limited torsional moment (after the elastic
    SDE forces; ``only`` >= 0: that SDE alone), rfesim.loads.drives.motor_forces."""
    motor_forces(km.motor_sde, km.motor_t, km.motor_angle, km.motor_slope, km.motor_count, km.motor_stiffness,
                 km.motor_damping, km.motor_torque, km.motor_shift, att.time[0], only, ws.motor_sat, km.sde_left,
                 km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase, ws.roff, ws.sigma,
                 M, ws.v3, ws.m33)


@njit(cache=True, _nrt=False)
def tension_only_forces(km, ws, F, M):
    """Ropes: no compressive axial SDE force (after the elastic and plastic SDE forces)."""
    tension_only_correction_rest(km.sde_left, km.sde_right, km.sde_arm_left, km.sde_arm_right, km.sde_stiffness,
                                 km.sde_tension_only, km.sde_has_rest, km.sde_rest, ws.sde_rest_eff, ws.R, ws.rbase,
                                 ws.roff, ws.sigma, F, M, ws.k_tangent, not km.has_plastic, ws.v3, ws.m33)


@njit(cache=True, _nrt=False)
def _scale_forces(F, M, c):
    for i in range(F.shape[0]):
        for k in range(3):
            F[i, k] *= c
            M[i, k] *= c


@njit(cache=True, _nrt=False)
def local_loads(km, att, ws, scale):
    """Every load that acts on one RFE alone (all but the SDEs), added to ws.F, ws.M."""
    if km.gravity != 0.0:
        gravity_forces(km.rfe_mass, km.rfe_kind, km.gravity, scale, ws.F)
    frozen = km.has_sea and ws.sea_frozen[0] != 0
    if km.has_water:
        if frozen:
            pass                    # the kinematics of this step's first evaluation (see ga_advance)
        elif km.has_sea:
            water_kinematics(km, att, ws)
        else:
            for i in range(ws.surface_z.shape[0]):
                ws.surface_z[i] = km.water_level
        submergence(km.rfe_length, km.rfe_disp_area, ws.R, ws.r, ws.surface_z, ws.sub_frac, ws.sub_point)
        if km.has_sea and not frozen:
            # an RFE cut by the surface: water kinematics at the centroid of its wet part
            for i in range(ws.sub_frac.shape[0]):
                if 0.0 < ws.sub_frac[i] < 1.0:
                    for k in range(3):
                        ws.point1[0, k] = ws.sub_point[i, k]
                    if ws.waves_off[0] == 0:
                        sea_kinematics_into(km.sea, att.time[0], ws.point1, ws.tmp3[0, 0:1],
                                            ws.water_vel[i:i + 1], ws.water_acc[i:i + 1])
                    else:
                        sea_kinematics_into(km.sea_still, 0.0, ws.point1, ws.tmp3[0, 0:1],
                                            ws.water_vel[i:i + 1], ws.water_acc[i:i + 1])
        buoyancy_forces(km.rfe_length, km.rfe_disp_area, km.rfe_kind, km.water_density, km.gravity, scale,
                        ws.r, ws.sub_frac, ws.sub_point, ws.F, ws.M)
        if km.has_morison and scale > 0.0:
            # statics' load steps (scale < 1) ramp the current's drag with the weights: F + scale
            # * morison as scale * (F / scale + morison), with no buffer. Held at its full value,
            # it made a short load step harder, not easier (a line in a strong current whose
            # statics needed load steps could not take any). Dynamics: scale 1, untouched.
            if scale != 1.0:
                _scale_forces(ws.F, ws.M, 1.0 / scale)
            morison_forces(km.rfe_length, km.rfe_diameter, km.rfe_disp_area, km.rfe_cdn, km.rfe_cdt, km.rfe_can,
                           km.rfe_cat, km.water_density, ws.R, ws.r, ws.v, ws.w, ws.sub_frac, ws.sub_point,
                           ws.water_vel, ws.water_acc, ws.F, ws.M, ws.Ma, ws.Ja)
            if scale != 1.0:
                _scale_forces(ws.F, ws.M, scale)
        if km.has_bodies:
            body_hydro_forces(km.body_rfe, km.body_volume, km.body_height, km.body_box, km.body_cob, km.body_drag,
                              km.body_added_mass, km.body_added_inertia, km.body_slam, km.water_density, km.gravity,
                              scale, ws.R, ws.r, ws.v, ws.w, ws.surface_z, ws.water_vel, ws.water_acc, ws.F, ws.M,
                              ws.Ma, ws.Ja, ws.sub_frac, ws.sub_point)
    if km.has_deck:
        deck_forces(km.body_rfe, km.body_deck_att, km.body_deck_z, km.body_deck_corner, km.body_deck_k,
                    km.body_deck_c, km.body_deck_mu, att.p, att.R, att.v, att.w, ws.R, ws.r, ws.v, ws.w, ws.F, ws.M,
                    ws.deck_normal, ws.fric_mode, km.body_deck_anchor)
    if km.has_tuggers:
        tugger_forces(km.tug_rfe, km.tug_att, km.tug_deck, km.tug_point, km.tug_kind, km.tug_t, km.tug_v,
                      km.tug_count, km.tug_k, km.tug_L0, km.tug_c, att.time[0], att.p, att.R, att.v, att.w, ws.R,
                      ws.r, ws.v, ws.w, ws.F, ws.M, ws.tug_tension, ws.tug_length)
    if km.has_seabed:
        seabed_forces(km.rfe_length, km.rfe_contact_radius, km.rfe_seabed_c, km.rfe_seabed_ct, km.bed_s, km.bed_z,
                      km.bed_dir,
                      km.seabed_k, km.seabed_mu, km.seabed_kt, ws.R, ws.r, ws.v, ws.w, ws.F, ws.M,
                      ws.contact_force, ws.contact_length, ws.fric_anchor, ws.fric_anchored, ws.fric_anchor_trial,
                      ws.fric_anchored_trial, ws.fric_mode, ws.friction_force, ws.v3[31])
    if km.has_loads:
        point_loads(km.load_rfe, km.load_arm, km.load_force, km.load_moment, km.load_local, scale,
                    ws.R, ws.F, ws.M, ws.tmp3)
    if km.has_rollers:
        roller_forces(km.roller_attach, km.roller_point, km.roller_axis, km.roller_half_width, km.roller_radius,
                      km.roller_k, km.roller_c, km.roller_mu, km.roller_kt, km.roller_onset, km.roller_lo,
                      km.roller_hi, km.rfe_length, km.rfe_contact_radius, att.p, att.R, att.v, att.w, ws.R, ws.r,
                      ws.v, ws.w, ws.F, ws.M, ws.roller_hint, ws.roller_force, ws.roller_normal, ws.roller_anchor,
                      ws.roller_anchored, ws.roller_anchor_trial, ws.roller_anchored_trial, ws.fric_mode,
                      ws.roller_scratch)
    if km.has_tensioners:
        # a driven tensioner pays out implicitly over the time since the last commit
        ws.tens_time[1] = att.time[0]
        tensioner_forces(km.tens_att, km.tens_point, km.tens_axis, km.tens_length, km.tens_kl, km.tens_kg,
                         km.tens_cap, km.tens_line_lo, km.tens_line_hi, km.tens_mode, km.tens_table_t,
                         km.tens_table_d, km.tens_table_v, km.tens_count, att.time[0], att.p, att.R, km.rfe_length, ws.r, ws.F,
                         ws.grip_a, ws.grip_on, ws.grip_a_trial, ws.grip_on_trial, ws.tens_D, ws.tens_force,
                         km.tens_set, km.tens_band, km.tens_gain, km.tens_vmax, ws.tens_time[1] - ws.tens_time[0],
                         ws.tens_D_trial)
    if km.has_reels:
        ws.reel_time[1] = att.time[0]
        reel_forces(km.reel_att, km.reel_centre, km.reel_axis, km.reel_dir, km.reel_radius, km.reel_wrap, km.reel_kr,
                    km.reel_kl, km.reel_kg, km.reel_cap, km.reel_line_lo, km.reel_line_hi, km.reel_mode,
                    km.reel_table_t, km.reel_table_d, km.reel_table_v, km.reel_count, att.time[0], att.p, att.R,
                    km.rfe_length, ws.r, ws.F, ws.reel_grip_a, ws.reel_grip_on, ws.reel_grip_a_trial,
                    ws.reel_grip_on_trial, ws.reel_D, ws.reel_force, km.reel_set, km.reel_band, km.reel_gain,
                    km.reel_vmax, ws.reel_time[1] - ws.reel_time[0], ws.reel_offset, ws.reel_D_trial)


@njit(cache=True, _nrt=False)
def water_kinematics(km, att, ws):
    """Free surface, water velocity and acceleration at every RFE centre (waves and
    current, rfesim.sea); with ``ws.waves_off`` (statics) still water plus current."""
    sea_reach(km, ws)
    if ws.waves_off[0] == 0:
        sea_kinematics_reach(km.sea, att.time[0], ws.r, ws.sea_reach, True, ws.surface_z, ws.water_vel, ws.water_acc)
    else:
        sea_kinematics_reach(km.sea_still, 0.0, ws.r, ws.sea_reach, True, ws.surface_z, ws.water_vel,
                             ws.water_acc)


SEA_MARGIN = 1.0        # m added to every reach: the kinematics stay frozen over a step's Newton iterations


@njit(cache=True, _nrt=False)
def sea_reach(km, ws):
    """ws.sea_reach: how far below its centre each RFE can be wet -- half its length times
    the vertical component of its axis plus its radius, a body's centre of buoyancy offset
    plus half its height (a box body: half its diagonal) -- plus SEA_MARGIN; an RFE without
    displaced area or diameter (no sea loads) is never wet."""
    for i in range(ws.r.shape[0]):
        if km.rfe_disp_area[i] <= 0.0 and km.rfe_diameter[i] <= 0.0:
            ws.sea_reach[i] = -1e300
        else:
            ws.sea_reach[i] = 0.5 * km.rfe_length[i] * abs(ws.R[i, 2, 0]) + 0.5 * km.rfe_diameter[i] + SEA_MARGIN
    if km.has_bodies:
        for j in range(km.body_rfe.shape[0]):
            i = km.body_rfe[j]
            c = km.body_cob[j]
            b = km.body_box[j]
            ext = 0.5 * km.body_height[j]
            if b[0] > 0.0:
                ext = max(ext, math.sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]))
            ws.sea_reach[i] = max(ws.sea_reach[i], math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
                                  + ext + SEA_MARGIN)


@njit(cache=True, _nrt=False)
def evaluate_keep_sde(km, att, q, qd, ref, ws, scale, Fsde, Msde):
    """``evaluate``, also copying the SDE forces and moments alone (``sde_part``, before the
    local loads are added) into Fsde, Msde: the frozen SDE part
    that the analytic Jacobian at this state needs (rfesim.solvers.jacobian), so that it
    does not evaluate the SDEs again."""
    poses(km, att, q, qd, ref, ws)
    zero_forces(ws)
    sde_part(km, att, ws, ws.F, ws.M)
    n = ws.F.shape[0]
    for i in range(n):
        for k in range(3):
            Fsde[i, k] = ws.F[i, k]
            Msde[i, k] = ws.M[i, k]
    local_loads(km, att, ws, scale)
    project(km, att, ws)


@njit(cache=True, _nrt=False)
def evaluate_frozen_sde(km, att, q, qd, ref, ws, scale, Fsde, Msde):
    """Like evaluate, but with the SDE forces and moments given (held fixed): the local part
    of the equations, whose Jacobian is block diagonal (rfesim.solvers.jacobian)."""
    poses(km, att, q, qd, ref, ws)
    for i in range(ws.F.shape[0]):
        for k in range(3):
            ws.F[i, k] = Fsde[i, k]
            ws.M[i, k] = Msde[i, k]
    local_loads(km, att, ws, scale)
    project(km, att, ws)


@njit(cache=True, inline="always")
def _project_free(i, m, inertia, Ja, Ma, R, E, wb, Edot, F, M, Mgen, fgen):
    """The free-RFE (kind 0) branch of ``project`` in scalar form (the same numbers to the
    bit: the zero entries of the diagonal inertia are multiplied as the 3x3 helpers do)."""
    for a in range(6):
        fgen[i, a] = 0.0
        for b in range(6):
            Mgen[i, a, b] = 0.0
    j0 = inertia[i, 0] + Ja[i, 0]
    j1 = inertia[i, 1] + Ja[i, 1]
    j2 = inertia[i, 2] + Ja[i, 2]
    for a in range(3):
        for b in range(3):
            Mgen[i, a, b] = Ma[i, a, b]
        Mgen[i, a, a] += m
        fgen[i, a] = F[i, a]
    m0 = M[i, 0]
    m1 = M[i, 1]
    m2 = M[i, 2]
    rh0 = R[i, 0, 0] * m0 + R[i, 1, 0] * m1 + R[i, 2, 0] * m2
    rh1 = R[i, 0, 1] * m0 + R[i, 1, 1] * m1 + R[i, 2, 1] * m2
    rh2 = R[i, 0, 2] * m0 + R[i, 1, 2] * m1 + R[i, 2, 2] * m2
    w0 = wb[i, 0]
    w1 = wb[i, 1]
    w2 = wb[i, 2]
    t0 = j0 * w0 + 0.0 * w1 + 0.0 * w2
    t1 = 0.0 * w0 + j1 * w1 + 0.0 * w2
    t2 = 0.0 * w0 + 0.0 * w1 + j2 * w2
    c0 = w1 * t2 - w2 * t1
    c1 = w2 * t0 - w0 * t2
    c2 = w0 * t1 - w1 * t0
    d0 = Edot[i, 0]
    d1 = Edot[i, 1]
    d2 = Edot[i, 2]
    u0 = j0 * d0 + 0.0 * d1 + 0.0 * d2
    u1 = 0.0 * d0 + j1 * d1 + 0.0 * d2
    u2 = 0.0 * d0 + 0.0 * d1 + j2 * d2
    rh0 -= c0 + u0
    rh1 -= c1 + u1
    rh2 -= c2 + u2
    for b in range(3):
        e0 = E[i, 0, b]
        e1 = E[i, 1, b]
        e2 = E[i, 2, b]
        # column b of T1 = Jb E
        s0 = j0 * e0 + 0.0 * e1 + 0.0 * e2
        s1 = 0.0 * e0 + j1 * e1 + 0.0 * e2
        s2 = 0.0 * e0 + 0.0 * e1 + j2 * e2
        for a in range(3):
            Mgen[i, 3 + a, 3 + b] = E[i, 0, a] * s0 + E[i, 1, a] * s1 + E[i, 2, a] * s2
        fgen[i, 3 + b] = e0 * rh0 + e1 * rh1 + e2 * rh2


@njit(cache=True, _nrt=False)
def project(km, att, ws):
    """Generalised mass blocks and forces of every RFE (eqs. 8.92, 8.94); free RFEs through
    the scalar ``_project_free``, the others as written in ``project_reference``."""
    for i in range(ws.F.shape[0]):
        if km.rfe_kind[i] == 0:
            _project_free(i, km.rfe_mass[i], km.rfe_inertia, ws.Ja, ws.Ma, ws.R, ws.E, ws.wb, ws.Edot, ws.F, ws.M,
                          ws.Mgen, ws.fgen)
        else:
            _project_one(km, att, ws, i)


@njit(cache=True)
def project_reference(km, att, ws):
    """Generalised mass blocks and forces of every RFE (eqs. 8.92, 8.94), readable; the
    reference of ``project`` (tests/unit/test_fused_kernels.py)."""
    for i in range(ws.F.shape[0]):
        _project_one(km, att, ws, i)


@njit(cache=True, _nrt=False)
def _project_one(km, att, ws, i):
    """Generalised mass block and force of RFE i (eqs. 8.92, 8.94)."""
    Jb = ws.m33[0]
    Jg = ws.m33[1]
    Mt = ws.m33[2]
    JP = ws.m33[3]
    B = ws.m33[4]
    T1 = ws.m33[5]
    Cx = ws.m33[6]
    rhs = ws.v3[0]
    tmp = ws.v3[1]
    tmp2 = ws.v3[2]
    c = ws.v3[3]
    P = ws.v3[4]
    Mg = ws.Mgen[i]
    f = ws.fgen[i]
    for a in range(6):
        f[a] = 0.0
        for b in range(6):
            Mg[a, b] = 0.0
    kind = km.rfe_kind[i]
    if kind == 2:
        for a in range(6):
            Mg[a, a] = 1.0
        return
    m = km.rfe_mass[i]
    for a in range(3):
        for b in range(3):
            Jb[a, b] = 0.0
        Jb[a, a] = km.rfe_inertia[i, a] + ws.Ja[i, a]
    E = ws.E[i]
    wb = ws.wb[i]
    if kind == 0:
        for a in range(3):
            for b in range(3):
                Mg[a, b] = ws.Ma[i, a, b]
            Mg[a, a] += m
            f[a] = ws.F[i, a]
        # body-frame moment minus gyroscopic and Euler-rate terms
        matTvec_into(ws.R[i], ws.M[i], rhs)
        matvec_into(Jb, wb, tmp)
        cross_into(wb, tmp, tmp2)
        matvec_into(Jb, ws.Edot[i], tmp)
        for a in range(3):
            rhs[a] -= tmp2[a] + tmp[a]
        # E^T J E and E^T rhs
        matmul_into(Jb, E, T1)
        for a in range(3):
            for b in range(3):
                Mg[3 + a, 3 + b] = E[0, a] * T1[0, b] + E[1, a] * T1[1, b] + E[2, a] * T1[2, b]
            f[3 + a] = E[0, a] * rhs[0] + E[1, a] * rhs[1] + E[2, a] * rhs[2]
    else:
        for a in range(3):
            Mg[a, a] = 1.0
        at = km.rfe_attach[i]
        R = ws.R[i]
        matvec_into(att.R[at], km.rfe_attach_offset[i], P)
        for k in range(3):
            P[k] += att.p[at, k]
            c[k] = ws.r[i, k] - P[k]
        # Jg = R Jb R^T ; Mt = m I + Ma ; JP = Jg - [c]x Mt [c]x
        for a in range(3):
            for b in range(3):
                s = 0.0
                for k in range(3):
                    s += R[a, k] * Jb[k, k] * R[b, k]
                Jg[a, b] = s
                Mt[a, b] = ws.Ma[i, a, b]
            Mt[a, a] += m
        skew_into(c, Cx)
        matmul_into(Mt, Cx, T1)
        for a in range(3):
            for b in range(3):
                JP[a, b] = Jg[a, b] - (Cx[a, 0] * T1[0, b] + Cx[a, 1] * T1[1, b] + Cx[a, 2] * T1[2, b])
        # acceleration of the pin point: a + alpha x d + w x (w x d), d = P - p_att
        for k in range(3):
            tmp2[k] = P[k] - att.p[at, k]
        cross_into(att.alpha[at], tmp2, tmp)
        cross_into(att.w[at], tmp2, rhs)
        cross_into(att.w[at], rhs, tmp2)
        w = ws.w[i]
        for k in range(3):
            tmp2[k] += att.a[at, k] + tmp[k]          # a_P
        cross_into(w, c, tmp)
        cross_into(w, tmp, rhs)                        # w x (w x c)
        for k in range(3):
            tmp2[k] += rhs[k]                          # a_P + w x (w x c)
        matvec_into(Mt, tmp2, tmp)
        cross_into(c, tmp, rhs)                        # c x Mt(...)
        # rhs_g = M + c x F - w x (Jg w) - c x Mt(...) - JP R Edot
        cross_into(c, ws.F[i], tmp)
        for k in range(3):
            rhs[k] = ws.M[i, k] + tmp[k] - rhs[k]
        matvec_into(Jg, w, tmp)
        cross_into(w, tmp, tmp2)
        matvec_into(R, ws.Edot[i], tmp)
        for k in range(3):
            rhs[k] -= tmp2[k]
        matvec_into(JP, tmp, tmp2)
        for k in range(3):
            rhs[k] -= tmp2[k]
        # B = R E (angle rates -> global angular velocity)
        matmul_into(R, E, B)
        matmul_into(JP, B, T1)
        for a in range(3):
            for b in range(3):
                Mg[3 + a, 3 + b] = B[0, a] * T1[0, b] + B[1, a] * T1[1, b] + B[2, a] * T1[2, b]
            f[3 + a] = B[0, a] * rhs[0] + B[1, a] * rhs[1] + B[2, a] * rhs[2]


@njit(cache=True, _nrt=False)
def evaluate(km, att, q, qd, ref, ws, scale):
    """One evaluation of the equations of motion: fills ws (poses, forces, Mgen, fgen)."""
    poses(km, att, q, qd, ref, ws)
    accumulate_forces(km, att, ws, scale)
    project(km, att, ws)


@njit(cache=True, _nrt=False)
def commit_history(km, ws):
    """Accept the trial history of the last evaluation (seabed friction anchors) as the
    state after an accepted step: called by every integrator once per step."""
    if km.has_friction:
        commit_friction(ws.fric_anchor, ws.fric_anchored, ws.fric_anchor_trial, ws.fric_anchored_trial)
    if km.has_plastic:
        commit_plastic(ws.plastic_hist, ws.plastic_hist_trial)
    if km.has_roller_friction:
        commit_roller_friction(ws.roller_anchor, ws.roller_anchored, ws.roller_anchor_trial, ws.roller_anchored_trial)
    if km.has_tensioners:
        # driven tensioners: the paid-out length solved implicitly in this step's last evaluation
        h = ws.tens_time[1] - ws.tens_time[0]
        commit_tensioners(km.tens_mode, ws.tens_D_trial, ws.tens_D, h, ws.grip_a, ws.grip_on, ws.grip_a_trial,
                          ws.grip_on_trial, km.tens_line_lo, km.tens_line_hi)
        ws.tens_time[0] = ws.tens_time[1]
    if km.has_reels:
        # the same spring-sliders and payout law as the tensioners, on the reels' arrays
        h = ws.reel_time[1] - ws.reel_time[0]
        commit_tensioners(km.reel_mode, ws.reel_D_trial, ws.reel_D, h, ws.reel_grip_a, ws.reel_grip_on,
                          ws.reel_grip_a_trial, ws.reel_grip_on_trial, km.reel_line_lo, km.reel_line_hi)
        ws.reel_time[0] = ws.reel_time[1]


@njit(cache=True, _nrt=False)
def solve_accelerations(ws, qdd):
    """qdd = Mgen^-1 fgen, RFE by RFE (3x3 translational and rotational blocks)."""
    A = ws.m33[0]
    b = ws.v3[0]
    x = ws.v3[1]
    for i in range(qdd.shape[0]):
        for blk in range(2):
            o = 3 * blk
            for a in range(3):
                b[a] = ws.fgen[i, o + a]
                for c in range(3):
                    A[a, c] = ws.Mgen[i, o + a, o + c]
            solve3_sym_into(A, b, x)
            for a in range(3):
                qdd[i, o + a] = x[a]


@njit(cache=True)
def residual_into(ws, qdd, out):
    """out = Mgen qdd - fgen (the implicit residual of eq. 8.92)."""
    for i in range(qdd.shape[0]):
        for a in range(6):
            s = -ws.fgen[i, a]
            for c in range(6):
                s += ws.Mgen[i, a, c] * qdd[i, c]
            out[i, a] = s


@njit(cache=True, _nrt=True)
def rebase(q, qd, ref, kind, threshold, qdd, aux, map_aux):
    """Move every free RFE's reference position to its current position (exact: rates and
    accelerations of the displacement do not change), and each RFE's reference rotation to
    its current orientation when its angles exceed ``threshold`` (rad), mapping angle rates
    and accelerations to the new chart exactly
    (omega_body and d(omega_body)/dt are unchanged). ``aux`` is a second acceleration-like
    array mapped the same way (the generalised-alpha algorithmic acceleration). Returns the
    number of RFEs re-based."""
    Rz = np.empty((3, 3))
    Rn = np.empty((3, 3))
    E = np.empty((3, 3))
    wb = np.empty(3)
    ed = np.empty(3)
    ed0 = np.empty(3)
    wd = np.empty(3)
    count = 0
    for i in range(q.shape[0]):
        if kind[i] == 2:
            continue
        if kind[i] == 0:
            for k in range(3):
                ref.X[i, k] += q[i, k]
                q[i, k] = 0.0
        if abs(q[i, 3]) <= threshold and abs(q[i, 4]) <= threshold and abs(q[i, 5]) <= threshold:
            continue
        count += 1
        rot_zyx_into(q[i, 3], q[i, 4], q[i, 5], Rz)
        matmul_into(ref.R[i], Rz, Rn)
        for a in range(3):
            for b in range(3):
                ref.R[i, a, b] = Rn[a, b]
        euler_rate_matrix_into(q[i, 3], q[i, 4], q[i, 5], E)
        matvec_into(E, qd[i, 3:6], wb)
        euler_rate_derivative_into(q[i, 3], q[i, 4], q[i, 5], qd[i, 3], qd[i, 4], qd[i, 5], ed)
        # new chart at zero angles: E0 maps (psi', theta', phi') -> (phi', theta', psi')
        q[i, 3] = 0.0
        q[i, 4] = 0.0
        q[i, 5] = 0.0
        qd[i, 3] = wb[2]
        qd[i, 4] = wb[1]
        qd[i, 5] = wb[0]
        euler_rate_derivative_into(0.0, 0.0, 0.0, qd[i, 3], qd[i, 4], qd[i, 5], ed0)
        for arr_id in range(2 if map_aux else 1):
            acc = qdd if arr_id == 0 else aux
            matvec_into(E, acc[i, 3:6], wd)
            for k in range(3):
                wd[k] += ed[k] - ed0[k]
            acc[i, 3] = wd[2]
            acc[i, 4] = wd[1]
            acc[i, 5] = wd[0]
    return count
