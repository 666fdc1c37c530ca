"""Vessel motion from displacement RAOs (response amplitude operators) and the scene's waves.

Convention. The wave elevation at the vessel's rest origin x_v = (x_v, y_v) is
eta_v(t) = r(t) sum_j a_j cos(omega_j t - k_j (x_v cos beta_j + y_v sin beta_j) + phi_j)
(:mod:`rfesim.sea.waves`). Each degree of freedom k (surge, sway, heave along the vessel
axes at rest [m]; roll, pitch, yaw [rad]) responds to each component as

    x_k(t) = r(t) sum_j a_j A_k(omega_j, b_j) cos(omega_j t - k_j . x_v + phi_j - eps_k(omega_j, b_j)),

with A_k the RAO amplitude (m/m, or deg/m in the table) and eps_k the phase LAG [deg]: a
positive eps_k means the motion reaches its maximum eps_k/omega seconds after the wave
crest passes the vessel origin. b_j = beta_j - vessel heading is the relative heading
(0: waves travel along the vessel x axis, following seas; 180: head seas; 90: waves
travel toward the vessel's port side, i.e. come from starboard).

Interpolation: linear in circular frequency (the table rows may be given as periods),
amplitude and phase separately (the phase difference taken in (-180, 180]); beyond the
table's frequencies the end rows are held. In heading: linear, periodic over 360 deg
(between the last heading and the first + 360); with ``symmetric`` the table covers
[0, 180] and heading b > 180 uses 360 - b with sway, roll and yaw reversed (mirror in the
vessel's x-z plane). The motion is a sum of harmonics per DOF, so it runs in the compiled
vessel kinematics as a harmonic motion (kind 1) without any kernel change.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..vessel import HarmonicVessel, VesselMotion
from .waves import WaveComponents, wave_components, water_depth

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
MIRROR_SIGN = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0])   # x-z plane mirror: sway, roll, yaw reverse


def read_input_file(path: Path, what: str, encoding: str | None = None):
    """The bytes of ``path`` (its text when ``encoding`` is given), ValueError naming the
    file for a missing file, a directory (``what``: what the file should be), text that
    does not decode, or any other read error."""
    try:
        return path.read_bytes() if encoding is None else path.read_text(encoding=encoding)
    except FileNotFoundError:
        raise ValueError(f"file not found: {path}") from None
    except IsADirectoryError:
        raise ValueError(f"{path} is a directory, not {what}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path} is not UTF-8 text") from None
    except OSError as exc:
        raise ValueError(f"cannot read {path}: {exc.strerror or exc}") from None


def read_rao_file(path):
    """The :class:`rfesim.scenario.schema.RaoTable` in a JSON or YAML file (ValueError naming
    the file and the field for anything wrong)."""
    from pydantic import ValidationError

    from ..errors import ScenarioError
    from ..scenario.load import parse_text, validation_errors
    from ..scenario.schema import RaoTable
    if not str(path).strip():
        raise ValueError("the file name is empty: give the path of the RAO table (a JSON or YAML file)")
    path = Path(path)
    raw = read_input_file(path, "an RAO table")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path} is not UTF-8 text (byte {exc.start}): an RAO table is a JSON or YAML "
                         f"text file") from None
    if not text.strip():
        raise ValueError(f"{path}: the RAO table file is empty")
    try:
        data = parse_text(text, "json" if path.suffix.lower() == ".json" else "auto")
    except ScenarioError as exc:
        raise ValueError(f"{path}: {exc}") from None
    try:
        return RaoTable.model_validate(data)
    except ValidationError as exc:
        # the field-named wording of the scenario's own errors (rfesim.scenario.load)
        errors = validation_errors(exc, root=RaoTable)
        raise ValueError(f"{path}: " + "; ".join(f"{where}: {reason}" if where else f"the RAO table {reason}"
                                                 for where, reason in errors)) from None


def _table_arrays(table):
    """(omega (nw,) ascending rad/s, headings (nh,) deg, amplitude (6, nw, nh), phase lag (6, nw, nh) deg)."""
    if table.frequencies is not None:
        omega = np.asarray(table.frequencies, dtype=float)
    else:
        omega = 2.0 * math.pi / np.asarray(table.periods, dtype=float)
    order = np.argsort(omega)
    omega = omega[order]
    headings = np.asarray(table.headings_deg, dtype=float)
    amp = np.zeros((6, omega.size, headings.size))
    lag = np.zeros((6, omega.size, headings.size))
    for k, name in enumerate(DOF_NAMES):
        dof = getattr(table, name)
        if dof is not None:
            amp[k] = np.asarray(dof.amplitude, dtype=float)[order]
            lag[k] = np.asarray(dof.phase_deg, dtype=float)[order]
    return omega, headings, amp, lag


def _bracket(xs, x):
    """Indices i0, i1 and weights f of linear interpolation in ascending xs (clamped)."""
    x = np.clip(x, xs[0], xs[-1])
    if xs.size == 1:
        z = np.zeros(x.shape, dtype=np.int64)
        return z, z, np.zeros(x.shape)
    i0 = np.clip(np.searchsorted(xs, x, side="right") - 1, 0, xs.size - 2)
    f = (x - xs[i0]) / (xs[i0 + 1] - xs[i0])
    return i0, i0 + 1, f


def _wrap180(deg):
    return (np.asarray(deg) + 180.0) % 360.0 - 180.0


def rao_response(table, omega, relative_heading_deg):
    """RAO amplitudes (K, 6) [m/m; rad/m for rotations] and phase lags (K, 6) [rad] at the
    component frequencies ``omega`` (K,) [rad/s] and relative headings (K,) [deg]."""
    w_tab, h_tab, amp, lag = _table_arrays(table)
    omega = np.asarray(omega, dtype=float)
    beta = np.asarray(relative_heading_deg, dtype=float) % 360.0
    sign = np.ones((omega.size, 6))
    if table.symmetric:
        mirror = beta > 180.0
        beta = np.where(mirror, 360.0 - beta, beta)
        sign[mirror] = MIRROR_SIGN
    elif h_tab[-1] - h_tab[0] < 360.0:
        # periodic: close the table with the first column at heading + 360
        h_tab = np.append(h_tab, h_tab[0] + 360.0)
        amp = np.concatenate([amp, amp[:, :, :1]], axis=2)
        lag = np.concatenate([lag, lag[:, :, :1]], axis=2)
        beta = h_tab[0] + (beta - h_tab[0]) % 360.0
    else:
        beta = h_tab[0] + (beta - h_tab[0]) % 360.0
    i0, i1, fw = _bracket(w_tab, omega)
    c0, c1, fh = _bracket(h_tab, beta)

    def in_frequency(c):
        a = (1.0 - fw) * amp[:, i0, c] + fw * amp[:, i1, c]
        p0 = lag[:, i0, c]
        p = p0 + fw * _wrap180(lag[:, i1, c] - p0)
        return a, p

    a0, p0 = in_frequency(c0)
    a1, p1 = in_frequency(c1)
    amplitude = ((1.0 - fh) * a0 + fh * a1).T
    phase = (p0 + fh * _wrap180(p1 - p0)).T
    phase = np.where(sign < 0.0, phase + 180.0, phase)
    amplitude[:, 3:] *= math.pi / 180.0
    return amplitude, np.radians(phase)


class RaoVessel(HarmonicVessel):
    """A vessel moving with its RAOs in the scene's waves: displacement_k = sum over the wave
    components of amplitude sin(omega t + phase), the harmonic motion of
    :class:`rfesim.vessel.HarmonicVessel` with K components per DOF (arrays (K, 6))."""

    def __init__(self, position, heading_deg: float, table, waves: WaveComponents):
        VesselMotion.__init__(self, position, heading_deg)
        self.ramp_duration = waves.ramp_duration
        relative = np.degrees(waves.direction) - heading_deg
        rao_amp, rao_lag = rao_response(table, waves.omega, relative)
        x, y = float(self.position[0]), float(self.position[1])
        # eta at the vessel origin: a cos(omega t + psi), psi = phi - k.x_v
        psi = waves.phase - waves.wavenumber * (x * np.cos(waves.direction) + y * np.sin(waves.direction))
        # a A cos(omega t + psi - eps) = a A sin(omega t + psi - eps + pi/2)
        self.amplitude = waves.amplitude[:, None] * rao_amp
        self.omega = np.repeat(waves.omega[:, None], 6, axis=1)
        self.phase = psi[:, None] - rao_lag + 0.5 * math.pi

    def dofs(self, t):
        arg = self.omega * t + self.phase
        s = np.sin(arg)
        c = np.cos(arg)
        a = self.amplitude
        return (a * s).sum(axis=0), (a * self.omega * c).sum(axis=0), -(a * self.omega ** 2 * s).sum(axis=0)


RAO_RANGE_ENERGY = 0.01    # share of the sea's m0 beyond an RAO table's frequencies that is warned about


def _period_text(omega: float) -> str:
    return f"{omega:.4g} rad/s ({2.0 * math.pi / omega:.3g} s)"


def rao_range_warnings(sc) -> list[str]:
    """The RAO vessels of a scenario whose table leaves out a noticeable part of the sea:
    more than RAO_RANGE_ENERGY of the wave components' energy (m0 = sum a_j^2 / 2) lies above
    the table's highest frequency (or below its lowest) on components that the held end row
    moves the vessel with (a row of zeros held beyond the table is the RAO tapering to zero,
    so those components are not counted). One warning per vessel and side, naming the
    vessel's motion field, the table's end frequency and the share; [] without waves."""
    env = sc.environment
    water = getattr(env, "water", None)
    rao = [(name, v) for name, v in sc.vessels.items() if v.motion.kind == "rao"]
    if not rao or water is None or water.waves is None:
        return []
    waves = wave_components(water.waves, water_depth(env), env.gravity)
    energy = 0.5 * np.asarray(waves.amplitude, float) ** 2
    m0 = float(energy.sum())
    if not m0 > 0.0:
        return []
    out = []
    for name, vessel in rao:
        table = vessel.motion.table()
        field = f"vessels.{name}.motion." + ("raos" if vessel.motion.raos is not None else "file")
        w_tab = _table_arrays(table)[0]
        amp, _ = rao_response(table, waves.omega, np.degrees(waves.direction) - vessel.heading_deg)
        moves = amp.max(axis=1) > 0.0
        for side, outside, end, more, knob in (
                ("above", waves.omega > w_tab[-1], w_tab[-1], "shorter", "omega_max"),
                ("below", waves.omega < w_tab[0], w_tab[0], "longer", "omega_min")):
            share = float(energy[outside & moves].sum()) / m0
            if not share > RAO_RANGE_ENERGY:
                continue
            held = amp[outside & moves].max(axis=0)
            held[3:] = np.degrees(held[3:])
            largest = ", ".join(f"{DOF_NAMES[k]} {held[k]:.3g} {'m/m' if k < 3 else 'deg/m'}"
                                for k in np.argsort(-held) if held[k] > 0.0)
            far = waves.omega[outside].max() if side == "above" else waves.omega[outside].min()
            remedy = f"extend the table to {more} periods"
            if hasattr(water.waves, knob):
                remedy += f", or set environment.water.waves.{knob} to {end:.4g} rad/s"
            out.append(f"vessel '{name}' ({field}): {100.0 * share:.3g} % of the sea's energy (m0) lies {side} the "
                       f"RAO table's {'highest' if side == 'above' else 'lowest'} frequency, {_period_text(end)}, "
                       f"out to {_period_text(far)}; there the vessel moves with the table's end row held "
                       f"(up to {largest}) instead of its real RAOs: {remedy}")
    return out


def rao_vessel(vessel, environment) -> RaoVessel:
    """The motion of a scenario vessel with an ``rao`` motion in the environment's waves."""
    water = getattr(environment, "water", None)
    if water is None or water.waves is None:
        raise ValueError("an RAO motion needs waves in the scene (environment.water.waves)")
    waves = wave_components(water.waves, water_depth(environment), environment.gravity)
    return RaoVessel(vessel.position, vessel.heading_deg, vessel.motion.table(), waves)
