"""Prescribed vessel motion: fixed, harmonic, or a table of the six displacements.

Convention: the vessel frame has its origin at ``position`` at rest, x forward, z up,
turned by ``heading_deg`` about z. The six displacements (surge, sway, heave in m along
the rest vessel axes; roll, pitch, yaw in deg) move the vessel origin and turn the
vessel as R = R_heading Rz(yaw) Ry(pitch) Rx(roll) (ZYX, eq. 8.73).

``kinematics(t)`` gives the pose and its first and second time derivatives:
origin position p, rotation R, velocity v, angular velocity w (global), acceleration a
and angular acceleration alpha (global).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from .kinematics import rot_zyx


def cosine_ramp(t: float, duration: float) -> tuple[float, float, float]:
    """r(t) = 0.5 (1 - cos(pi t / T)) for t < T, else 1; with its first two derivatives."""
    if duration <= 0.0 or t >= duration:
        return 1.0, 0.0, 0.0
    if t <= 0.0:
        return 0.0, 0.0, 0.0
    a = math.pi / duration
    return 0.5 * (1.0 - math.cos(a * t)), 0.5 * a * math.sin(a * t), 0.5 * a * a * math.cos(a * t)


@dataclass
class VesselKinematics:
    p: np.ndarray
    R: np.ndarray
    v: np.ndarray
    w: np.ndarray
    a: np.ndarray
    alpha: np.ndarray


class VesselMotion:
    """Base: displacement (6,), velocity (6,), acceleration (6,) of the six DOFs at t
    (rotations in rad), combined into the rigid-body pose by ``kinematics``."""

    ramp_duration = 0.0

    def __init__(self, position, heading_deg: float):
        self.position = np.asarray(position, dtype=float)
        h = math.radians(heading_deg)
        self.R_heading = rot_zyx(h, 0.0, 0.0)

    def dofs(self, t: float):  # pragma: no cover - overridden
        z = np.zeros(6)
        return z, z.copy(), z.copy()

    def ramped_dofs(self, t: float):
        d, dd, ddd = self.dofs(t)
        r, rd, rdd = cosine_ramp(t, self.ramp_duration)
        if r == 1.0 and rd == 0.0 and rdd == 0.0:
            return d, dd, ddd
        return r * d, rd * d + r * dd, rdd * d + 2.0 * rd * dd + r * ddd

    def kinematics(self, t: float) -> VesselKinematics:
        d, dd, ddd = self.ramped_dofs(t)
        Rh = self.R_heading
        p = self.position + Rh @ d[:3]
        v = Rh @ dd[:3]
        a = Rh @ ddd[:3]
        roll, pitch, yaw = d[3], d[4], d[5]
        droll, dpitch, dyaw = dd[3], dd[4], dd[5]
        R = Rh @ rot_zyx(yaw, pitch, roll)
        # spatial angular velocity of Rz(yaw) Ry(pitch) Rx(roll): columns e_z, Rz e_y, Rz Ry e_x
        cz, sz = math.cos(yaw), math.sin(yaw)
        cy, sy = math.cos(pitch), math.sin(pitch)
        c1 = np.array([0.0, 0.0, 1.0])
        c2 = np.array([-sz, cz, 0.0])
        c3 = np.array([cz * cy, sz * cy, -sy])
        w_loc = c1 * dyaw + c2 * dpitch + c3 * droll
        w12 = c1 * dyaw + c2 * dpitch
        c2dot = np.cross(c1 * dyaw, c2)
        c3dot = np.cross(w12, c3)
        al_loc = c1 * ddd[5] + c2 * ddd[4] + c3 * ddd[3] + c2dot * dpitch + c3dot * droll
        return VesselKinematics(p=p, R=R, v=v, w=Rh @ w_loc, a=a, alpha=Rh @ al_loc)


class FixedVessel(VesselMotion):
    def dofs(self, t):
        z = np.zeros(6)
        return z, z.copy(), z.copy()


class HarmonicVessel(VesselMotion):
    """displacement_k = amplitude_k sin(2 pi t / period_k + phase_k) per DOF."""

    def __init__(self, position, heading_deg, spec):
        super().__init__(position, heading_deg)
        self.ramp_duration = spec.ramp_duration
        amp = np.zeros(6)
        omega = np.zeros(6)
        phase = np.zeros(6)
        for k, name in enumerate(("surge", "sway", "heave", "roll", "pitch", "yaw")):
            dof = getattr(spec, name)
            if dof is None:
                continue
            amp[k] = dof.amplitude if k < 3 else math.radians(dof.amplitude)
            omega[k] = 2.0 * math.pi / dof.period
            phase[k] = math.radians(dof.phase_deg)
        self.amplitude, self.omega, self.phase = amp, omega, phase

    def dofs(self, t):
        arg = self.omega * t + self.phase
        s = np.sin(arg)
        c = np.cos(arg)
        return self.amplitude * s, self.amplitude * self.omega * c, -self.amplitude * self.omega ** 2 * s


class TableVessel(VesselMotion):
    """Interpolated table (cubic spline: continuous velocity and acceleration; or linear),
    its times shifted by the spec's start_time (the table's time at the run's t = 0).
    Outside the table the first/last row is held."""

    def __init__(self, position, heading_deg, spec):
        super().__init__(position, heading_deg)
        self.ramp_duration = spec.ramp_duration
        data = np.asarray(spec.rows, dtype=float)
        self.time = data[:, 0] - float(getattr(spec, "start_time", 0.0))    # run time of each row
        values = data[:, 1:].copy()
        values[:, 3:] = np.radians(values[:, 3:])
        self.values = values
        self.kind = spec.interpolation
        if self.kind == "cubic":
            from scipy.interpolate import CubicSpline      # imported here: 0.8 s of start-up otherwise
            self.spline = CubicSpline(self.time, values, axis=0, bc_type="natural")

    def dofs(self, t):
        t0, t1 = self.time[0], self.time[-1]
        if t <= t0 or t >= t1:
            d = self.values[0] if t <= t0 else self.values[-1]
            z = np.zeros(6)
            return d.copy(), z, z.copy()
        if self.kind == "cubic":
            return self.spline(t), self.spline(t, 1), self.spline(t, 2)
        j = int(np.searchsorted(self.time, t, side="right")) - 1
        dt = self.time[j + 1] - self.time[j]
        slope = (self.values[j + 1] - self.values[j]) / dt
        return self.values[j] + slope * (t - self.time[j]), slope, np.zeros(6)


def make_vessel_motion(vessel, environment=None) -> VesselMotion:
    """The motion object of a scenario vessel (an ``rao`` motion needs the scenario's
    ``environment``, whose waves drive it)."""
    m = vessel.motion
    if m.kind == "fixed":
        return FixedVessel(vessel.position, vessel.heading_deg)
    if m.kind == "harmonic":
        return HarmonicVessel(vessel.position, vessel.heading_deg, m)
    if m.kind == "table":
        return TableVessel(vessel.position, vessel.heading_deg, m)
    if m.kind == "csv":
        from .sea.motion_csv import csv_vessel
        return csv_vessel(vessel)
    if m.kind == "rao":
        from .sea.rao import rao_vessel
        return rao_vessel(vessel, environment)
    raise ValueError(f"unknown vessel motion kind {m.kind!r}")
