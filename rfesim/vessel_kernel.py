"""Compiled attachment kinematics: the same motions as ``rfesim.vessel`` (the readable
reference, checked against this in the tests), evaluable inside numba time loops.

Every attachment is one of: fixed (0), a sum of harmonics per DOF (1; also what RAO
motions reduce to), or a piecewise-cubic table per DOF (2; a linear table is a cubic
with zero higher coefficients). A cosine ramp multiplies the displacements.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from .kinematics import matmul_into, matvec_into, rot_zyx_into
from .sea.trig import sincos
from .vessel import FixedVessel, HarmonicVessel, TableVessel


class VesselSpec(NamedTuple):
    kind: np.ndarray        # (natt,) int64: 0 fixed, 1 harmonic, 2 table
    position: np.ndarray    # (natt, 3) m, rest position of the origin
    R_heading: np.ndarray   # (natt, 3, 3)
    ramp: np.ndarray        # (natt,) s
    h_amp: np.ndarray       # (natt, K, 6) harmonic amplitudes (m, rad)
    h_omega: np.ndarray     # (natt, K, 6) rad/s
    h_phase: np.ndarray     # (natt, K, 6) rad
    t_knots: np.ndarray     # (natt, Nk) s, table times (padded)
    t_count: np.ndarray     # (natt,) int64, number of knots
    t_coef: np.ndarray      # (natt, Nk - 1, 4, 6) cubic coefficients, highest power first
    t_first: np.ndarray     # (natt, 6) values before the table
    t_last: np.ndarray      # (natt, 6) values after the table


def vessel_spec(motions) -> VesselSpec:
    """Pack the motion objects of a model (None: the fixed global frame) for the kernels."""
    natt = len(motions)
    K = 1
    Nk = 2
    for m in motions:
        if isinstance(m, HarmonicVessel):
            K = max(K, m.amplitude.reshape(-1, 6).shape[0])
        if isinstance(m, TableVessel):
            Nk = max(Nk, m.time.shape[0])
    kind = np.zeros(natt, np.int64)
    position = np.zeros((natt, 3))
    Rh = np.zeros((natt, 3, 3))
    Rh[:] = np.eye(3)
    ramp = np.zeros(natt)
    h_amp = np.zeros((natt, K, 6))
    h_omega = np.zeros((natt, K, 6))
    h_phase = np.zeros((natt, K, 6))
    t_knots = np.zeros((natt, Nk))
    t_count = np.zeros(natt, np.int64)
    t_coef = np.zeros((natt, Nk - 1, 4, 6))
    t_first = np.zeros((natt, 6))
    t_last = np.zeros((natt, 6))
    for j, m in enumerate(motions):
        if m is None:
            continue
        position[j] = m.position
        Rh[j] = m.R_heading
        ramp[j] = m.ramp_duration
        if isinstance(m, FixedVessel):
            kind[j] = 0
        elif isinstance(m, HarmonicVessel):
            kind[j] = 1
            a = m.amplitude.reshape(-1, 6)
            h_amp[j, :a.shape[0]] = a
            h_omega[j, :a.shape[0]] = m.omega.reshape(-1, 6)
            h_phase[j, :a.shape[0]] = m.phase.reshape(-1, 6)
        elif isinstance(m, TableVessel):
            kind[j] = 2
            nk = m.time.shape[0]
            t_knots[j, :nk] = m.time
            t_count[j] = nk
            if m.kind == "cubic":
                c = m.spline.c          # (4, nk - 1, 6), highest power first
                t_coef[j, :nk - 1] = np.transpose(c, (1, 0, 2))
            else:
                slope = np.diff(m.values, axis=0) / np.diff(m.time)[:, None]
                t_coef[j, :nk - 1, 2] = slope
                t_coef[j, :nk - 1, 3] = m.values[:-1]
            t_first[j] = m.values[0]
            t_last[j] = m.values[-1]
        else:
            raise TypeError(f"no compiled kinematics for {type(m).__name__}")
    return VesselSpec(kind, position, Rh, ramp, h_amp, h_omega, h_phase, t_knots, t_count, t_coef, t_first, t_last)


@njit(cache=True)
def _dofs(vs, j, t, d, dd, ddd):
    for k in range(6):
        d[k] = 0.0
        dd[k] = 0.0
        ddd[k] = 0.0
    kind = vs.kind[j]
    if kind == 1:
        for c in range(vs.h_amp.shape[1]):
            for k in range(6):
                a = vs.h_amp[j, c, k]
                if a == 0.0:
                    continue
                w = vs.h_omega[j, c, k]
                arg = w * t + vs.h_phase[j, c, k]
                s, co = sincos(arg)        # rfesim.sea.trig
                d[k] += a * s
                dd[k] += a * w * co
                ddd[k] -= a * w * w * s
    elif kind == 2:
        nk = vs.t_count[j]
        if t <= vs.t_knots[j, 0]:
            for k in range(6):
                d[k] = vs.t_first[j, k]
        elif t >= vs.t_knots[j, nk - 1]:
            for k in range(6):
                d[k] = vs.t_last[j, k]
        else:
            lo = 0
            hi = nk - 1
            while hi - lo > 1:
                mid = (lo + hi) // 2
                if vs.t_knots[j, mid] <= t:
                    lo = mid
                else:
                    hi = mid
            tau = t - vs.t_knots[j, lo]
            for k in range(6):
                c3 = vs.t_coef[j, lo, 0, k]
                c2 = vs.t_coef[j, lo, 1, k]
                c1 = vs.t_coef[j, lo, 2, k]
                c0 = vs.t_coef[j, lo, 3, k]
                d[k] = ((c3 * tau + c2) * tau + c1) * tau + c0
                dd[k] = (3.0 * c3 * tau + 2.0 * c2) * tau + c1
                ddd[k] = 6.0 * c3 * tau + 2.0 * c2
    T = vs.ramp[j]
    if T > 0.0 and t < T:
        if t <= 0.0:
            r = 0.0
            rd = 0.0
            rdd = 0.0
        else:
            a = math.pi / T
            r = 0.5 * (1.0 - math.cos(a * t))
            rd = 0.5 * a * math.sin(a * t)
            rdd = 0.5 * a * a * math.cos(a * t)
        for k in range(6):
            x = d[k]
            xd = dd[k]
            xdd = ddd[k]
            d[k] = r * x
            dd[k] = rd * x + r * xd
            ddd[k] = rdd * x + 2.0 * rd * xd + r * xdd


@njit(cache=True, _nrt=True)
def attachment_kinematics(vs, t, att):
    """Fill the AttachmentState ``att`` with every attachment's pose at time t."""
    att.time[0] = t
    sc = att.scratch
    d = sc[0:2].reshape(6)
    dd = sc[2:4].reshape(6)
    ddd = sc[4:6].reshape(6)
    Rl = sc[6:9]
    c1 = sc[9]
    c2 = sc[10]
    c3 = sc[11]
    wl = sc[12]
    al = sc[13]
    tmp = sc[14]
    for j in range(1, vs.kind.shape[0]):
        Rh = vs.R_heading[j]
        if vs.kind[j] == 0 and vs.ramp[j] == 0.0:
            for k in range(3):
                att.p[j, k] = vs.position[j, k]
                att.v[j, k] = 0.0
                att.w[j, k] = 0.0
                att.a[j, k] = 0.0
                att.alpha[j, k] = 0.0
                for m in range(3):
                    att.R[j, k, m] = Rh[k, m]
            continue
        _dofs(vs, j, t, d, dd, ddd)
        matvec_into(Rh, d[0:3], tmp)
        for k in range(3):
            att.p[j, k] = vs.position[j, k] + tmp[k]
        matvec_into(Rh, dd[0:3], att.v[j])
        matvec_into(Rh, ddd[0:3], att.a[j])
        roll = d[3]
        pitch = d[4]
        yaw = d[5]
        rot_zyx_into(yaw, pitch, roll, Rl)
        matmul_into(Rh, Rl, att.R[j])
        cz = math.cos(yaw)
        sz = math.sin(yaw)
        cy = math.cos(pitch)
        sy = math.sin(pitch)
        c1[0] = 0.0
        c1[1] = 0.0
        c1[2] = 1.0
        c2[0] = -sz
        c2[1] = cz
        c2[2] = 0.0
        c3[0] = cz * cy
        c3[1] = sz * cy
        c3[2] = -sy
        dr = dd[3]
        dp = dd[4]
        dy = dd[5]
        for k in range(3):
            wl[k] = c1[k] * dy + c2[k] * dp + c3[k] * dr
        # c2dot = (dy e_z) x c2 ; c3dot = (dy e_z + dp c2) x c3
        c2d0 = -dy * c2[1]
        c2d1 = dy * c2[0]
        w12_0 = dp * c2[0]
        w12_1 = dp * c2[1]
        w12_2 = dy
        c3d0 = w12_1 * c3[2] - w12_2 * c3[1]
        c3d1 = w12_2 * c3[0] - w12_0 * c3[2]
        c3d2 = w12_0 * c3[1] - w12_1 * c3[0]
        al[0] = c2[0] * ddd[4] + c3[0] * ddd[3] + c2d0 * dp + c3d0 * dr
        al[1] = c2[1] * ddd[4] + c3[1] * ddd[3] + c2d1 * dp + c3d1 * dr
        al[2] = ddd[5] + c3[2] * ddd[3] + c3d2 * dr
        matvec_into(Rh, wl, att.w[j])
        matvec_into(Rh, al, att.alpha[j])
