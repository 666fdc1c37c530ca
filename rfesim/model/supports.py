"""Supports (rollers, stinger) of a scenario -> the roller arrays of the kernel model, and
the initial shape of a line that runs over them.

A stinger is an arc of roller axes in its attachment frame: from ``start`` with unit
tangent T, bending with radius R towards N0, the part of -z normal to T. At arc length s
(theta = s / R) the station is ``start + R sin(theta) T + R (1 - cos(theta)) N0``, its
tangent ``cos(theta) T + sin(theta) N0`` and the outward normal (towards the pipe)
``o = sin(theta) T - cos(theta) N0``. A flat station has one roller with axis
B = T x N0 across the arc; a V station has two with axes ``cos(v) (+-B) + sin(v) o``,
each starting at the V bottom. A pipe of radius a resting on a station has its axis at
the station + o (a + rho) / cos(v).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ScenarioError
from ..loads.rollers import CONTACT_ONSET


@dataclass
class SupportInfo:
    """Where a support's rollers sit in the model arrays."""

    name: str
    line: str
    attach: str
    roller_start: int
    roller_stop: int
    position: np.ndarray      # (nr, 3) m, roller contact-line centres in the attachment frame
    axis: np.ndarray          # (nr, 3) unit roller axes in the attachment frame

    @property
    def nroller(self) -> int:
        return self.roller_stop - self.roller_start


@dataclass
class RollerSet:
    """Rollers of one support in its attachment frame, with the resting points of the
    pipe axis (``guide + (a + rho) * lift * up``) used for the initial shape."""

    point: np.ndarray         # (m, 3)
    axis: np.ndarray          # (m, 3) unit
    half_width: np.ndarray    # (m,)
    radius: np.ndarray        # (m,)
    guide: np.ndarray         # (m, 3) station point (V bottom, or the roller centre)
    up: np.ndarray            # (m, 3) unit direction from the roller towards the pipe
    lift: np.ndarray          # (m,) 1 / cos(v)


def stinger_frame(direction) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """T (tangent), N0 (towards the centre of the arc, downwards), B = T x N0."""
    T = np.asarray(direction, float)
    T = T / np.linalg.norm(T)
    z = np.array([0.0, 0.0, 1.0])
    N0 = -(z - (z @ T) * T)
    N0 /= np.linalg.norm(N0)
    return T, N0, np.cross(T, N0)


def roller_set(sup, pipe_radius: float = 0.0) -> RollerSet:
    if sup.kind == "straightener":
        from .reels import straightener_roller_set
        return straightener_roller_set(sup, pipe_radius)
    if sup.kind == "rollers":
        pts, axes, hw, rad, up = [], [], [], [], []
        for r in sup.rollers:
            a = np.asarray(r.axis, float)
            a /= np.linalg.norm(a)
            u = np.array([0.0, 0.0, 1.0]) - a[2] * a
            nu = np.linalg.norm(u)
            u = u / nu if nu > 1e-9 else np.cross(a, [1.0, 0.0, 0.0]) / np.linalg.norm(np.cross(a, [1.0, 0.0, 0.0]))
            pts.append(r.position)
            axes.append(a)
            hw.append(0.5 * r.width)
            rad.append(r.radius)
            up.append(u)
        m = len(pts)
        P = np.asarray(pts, float)
        return RollerSet(P, np.asarray(axes), np.asarray(hw), np.asarray(rad), P.copy(), np.asarray(up),
                         np.ones(m))
    T, N0, B = stinger_frame(sup.direction)
    start = np.asarray(sup.start, float)
    nst = int(math.floor(sup.length / sup.spacing + 1e-9)) + 1
    v = math.radians(sup.v_angle_deg)
    pts, axes, guide, up = [], [], [], []
    for k in range(nst):
        th = k * sup.spacing / sup.radius
        p = start + sup.radius * math.sin(th) * T + sup.radius * (1.0 - math.cos(th)) * N0
        o = math.sin(th) * T - math.cos(th) * N0
        if v == 0.0:
            pts.append(p)
            axes.append(B)
            guide.append(p)
            up.append(o)
        else:
            for side in (1.0, -1.0):
                a = math.cos(v) * side * B + math.sin(v) * o
                pts.append(p + 0.5 * sup.roller_width * a)
                axes.append(a)
                guide.append(p)
                up.append(o)
    m = len(pts)
    return RollerSet(np.asarray(pts), np.asarray(axes), np.full(m, 0.5 * sup.roller_width),
                     np.full(m, sup.roller_radius), np.asarray(guide), np.asarray(up), np.full(m, 1.0 / math.cos(v)))


def empty_roller_arrays() -> dict:
    z3 = np.zeros((0, 3))
    z = np.zeros(0)
    zi = np.zeros(0, np.int64)
    return dict(roller_attach=zi, roller_point=z3, roller_axis=z3.copy(), roller_half_width=z, roller_radius=z.copy(),
                roller_k=z.copy(), roller_c=z.copy(), roller_mu=z.copy(), roller_kt=z.copy(), roller_onset=z.copy(),
                roller_lo=zi.copy(),
                roller_hi=zi.copy())


def compile_supports(sc, attachment_names: list[str], lines) -> tuple[dict, list[SupportInfo]]:
    """Roller arrays of the kernel model and the supports' places in them."""
    supports = getattr(sc, "supports", None) or {}
    if not supports:
        return empty_roller_arrays(), []
    index = {li.name: li for li in lines}
    cols = {k: [] for k in empty_roller_arrays()}
    infos: list[SupportInfo] = []
    problems = []
    start = 0
    for name, sup in supports.items():
        li = index.get(sup.line)
        if li is None:
            problems.append((f"supports.{name}.line", f"unknown line '{sup.line}'"))
            continue
        if sup.kind in ("tensioner", "reel"):
            continue                       # compile_tensioners, rfesim.model.reels.compile_reels
        rs = roller_set(sup, 0.5 * li.section.outer_diameter)
        m = rs.point.shape[0]
        att = attachment_names.index(sup.attach)
        cols["roller_attach"].append(np.full(m, att, np.int64))
        cols["roller_point"].append(rs.point)
        cols["roller_axis"].append(rs.axis)
        cols["roller_half_width"].append(rs.half_width)
        cols["roller_radius"].append(rs.radius)
        cols["roller_k"].append(np.full(m, float(sup.stiffness)))
        cols["roller_c"].append(np.full(m, float(sup.damping)))
        cols["roller_mu"].append(np.full(m, float(sup.friction)))
        cols["roller_kt"].append(np.full(m, float(sup.friction_stiffness or sup.stiffness)))
        # smooth contact onset (rfesim.loads.rollers): given, or a fraction of pipe + roller radius
        cols["roller_onset"].append(np.full(m, float(sup.contact_onset)) if sup.contact_onset is not None
                                    else CONTACT_ONSET * (0.5 * li.section.outer_diameter + rs.radius))
        cols["roller_lo"].append(np.full(m, li.rfe_start, np.int64))
        cols["roller_hi"].append(np.full(m, li.rfe_stop, np.int64))
        infos.append(SupportInfo(name=name, line=sup.line, attach=sup.attach, roller_start=start,
                                 roller_stop=start + m, position=rs.point.copy(), axis=rs.axis.copy()))
        start += m
    if problems:
        raise ScenarioError(problems)
    arrays = {k: np.concatenate(v) if v else empty_roller_arrays()[k] for k, v in cols.items()}
    return arrays, infos


START_PENETRATION = 0.01     # the start shape presses into the rollers by this fraction of pipe + roller radius


def resting_points(sc, line_name: str, pipe_radius: float, attachment_names: list[str], att0) -> np.ndarray | None:
    """Global points (at t = 0) where the axis of line ``line_name`` rests on its supports'
    roller stations, one per station, or None when no support carries the line. The
    points press into the rollers by ``START_PENETRATION``: statics then starts with the
    contacts closed, so Newton sees their stiffness (from a gap it would step through)."""
    pts = []
    for sup in (getattr(sc, "supports", None) or {}).values():
        if sup.line != line_name or sup.kind in ("tensioner", "reel"):
            continue
        rs = roller_set(sup, pipe_radius)
        a = attachment_names.index(sup.attach)
        R, p = att0.R[a], att0.p[a]
        reach = pipe_radius + rs.radius
        guide = p[None, :] + (rs.guide + (reach * rs.lift)[:, None] * rs.up) @ R.T
        centre = p[None, :] + rs.point @ R.T
        axis = rs.axis @ R.T
        up = rs.up @ R.T
        # stations: consecutive rollers whose resting points are closer than a pipe plus a
        # roller diameter hold the pipe together (the two halves of a V)
        groups = [[0]]
        for k in range(1, guide.shape[0]):
            if np.linalg.norm(guide[k] - guide[k - 1]) <= 2.0 * max(reach[k], reach[k - 1]):
                groups[-1].append(k)
            else:
                groups.append([k])
        for g in groups:
            X = guide[g].mean(axis=0)
            if len(g) > 1:
                # the point at distance pipe + roller radius from every axis of the station
                for _ in range(30):
                    J = np.zeros((len(g), 3))
                    res = np.zeros(len(g))
                    for row, k in enumerate(g):
                        e = X - centre[k]
                        e -= (e @ axis[k]) * axis[k]
                        d = np.linalg.norm(e)
                        res[row] = d - reach[k]
                        J[row] = e / max(d, 1e-300)
                    step = np.linalg.lstsq(J, -res, rcond=None)[0]
                    X = X + step
                    if np.abs(step).max() < 1e-12 * (1.0 + np.abs(X).max()):
                        break
            u = up[g].mean(axis=0)
            u /= np.linalg.norm(u)
            pts.append(X - START_PENETRATION * float(reach[g].mean()) * u)
    if not pts:
        return None
    return np.asarray(pts)


def supported_start(A: np.ndarray, B: np.ndarray | None, length: float, rest: np.ndarray, tail):
    """Polyline from end A through the resting points (ordered by distance from A), then
    ``tail(G, B, remaining_length)`` -> (s, X) from the last resting point G to end B
    (a catenary), or straight on along the last segment when B is free.
    Returns (s, X) of the whole curve."""
    order = np.argsort(np.linalg.norm(rest - A[None, :], axis=1))
    X = np.vstack([A[None, :], rest[order]])
    keep = np.ones(X.shape[0], bool)
    keep[1:] = np.linalg.norm(np.diff(X, axis=0), axis=1) > 1e-9
    X = X[keep]
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=1))])
    remaining = length - s[-1]
    if remaining <= 0.0:
        raise ScenarioError([("supports", f"the line is {length} m long but reaches the last roller only after "
                                          f"{s[-1]:.6g} m: make it longer")])
    tail_sx = tail(X[-1], B, remaining) if B is not None else None
    if tail_sx is None:
        d = X[-1] - X[-2] if X.shape[0] > 1 else np.array([0.0, 0.0, -1.0])
        d = d / np.linalg.norm(d)
        return np.append(s, s[-1] + remaining), np.vstack([X, X[-1] + remaining * d])
    ts, tX = tail_sx
    return np.concatenate([s, s[-1] + ts[1:]]), np.vstack([X, tX[1:]])


@dataclass
class TensionerInfo:
    name: str
    line: str
    index: int


def _pchip_slopes(t: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Monotone cubic (Fritsch-Carlson / PCHIP) slopes: no overshoot between rows, zero
    slope at a flat row (a payout that stops, stops smoothly). Fewer than 3 rows: zeros
    (the drive and motor tables of rfesim.model.arrays use that)."""
    if len(t) < 3:
        return np.zeros(len(t))
    from scipy.interpolate import PchipInterpolator
    return PchipInterpolator(t, d).derivative()(t)


def drive_slopes(t: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Slopes at the rows of a drive's angle table (joint drives, servo motors; the cubic
    Hermite of ``rfesim.loads.drives.drive_table``): the monotone PCHIP slopes, but 0 at the
    first row when that is at t >= 0. The structure starts at rest (statics), and the drive
    holds its first angle before the table, so it starts from rest too: PCHIP's own end
    slope, extrapolated from the first two segments, made the rate jump at the first row, a
    shock (an A-frame tilt table starting at -4.16 deg/s failed at 0.106 s, its rope snatched
    slack and taut). A zero end slope keeps the Hermite monotone (Fritsch-Carlson: alpha = 0
    with a smaller alpha^2 + beta^2) and passes through every row. A table begun before t = 0 is moving at
    t = 0 whatever its first slope, and keeps PCHIP's. The last row keeps PCHIP's slope too: a
    table that ends while moving stops dead there, as it says (add a row to stop smoothly)."""
    v = _pchip_slopes(t, d)
    if len(v) and t[0] >= 0.0:
        v[0] = 0.0
    return v


def table_slopes(t: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Slopes (payout speeds) at the rows of a payout table for the cubic Hermite of
    ``rfesim.loads.tensioner._table``: the monotone PCHIP slopes for three rows or more;
    the secant for two rows (a straight line: constant speed between them, where zero end
    slopes made a cubic that started at rest and peaked at 1.5 times the speed)."""
    if len(t) == 2:
        return np.full(2, (d[1] - d[0]) / (t[1] - t[0]))
    return _pchip_slopes(t, d)


def fill_payout(out: dict, prefix: str, j: int, payout) -> None:
    """Pack a payout law (schema PayoutTable or PayoutConstantTension) into the arrays
    ``<prefix>_mode, _count, _table_t/d/v, _set, _band, _gain, _vmax`` at row j (a
    tensioner's or a reel's: the same kernels read them)."""
    from ..loads.tensioner import MODE_TABLE, MODE_TENSION
    if payout.kind == "table":
        rows = np.asarray(payout.rows, float)
        out[f"{prefix}_mode"][j] = MODE_TABLE
        out[f"{prefix}_count"][j] = max(2, len(rows))
        if len(rows) == 1:
            rows = np.vstack([rows, rows + [1.0, 0.0]])
        out[f"{prefix}_table_t"][j, :len(rows)] = rows[:, 0]
        out[f"{prefix}_table_d"][j, :len(rows)] = rows[:, 1]
        out[f"{prefix}_table_v"][j, :len(rows)] = table_slopes(rows[:, 0], rows[:, 1])
    else:
        out[f"{prefix}_mode"][j] = MODE_TENSION
        out[f"{prefix}_count"][j] = 2
        out[f"{prefix}_table_t"][j, :2] = [0.0, 1.0]
        out[f"{prefix}_set"][j] = payout.tension
        out[f"{prefix}_band"][j] = payout.dead_band
        out[f"{prefix}_gain"][j] = payout.gain
        out[f"{prefix}_vmax"][j] = payout.max_speed


def compile_tensioners(sc, attachment_names: list[str], lines) -> tuple[dict, list[TensionerInfo]]:
    """Tensioner arrays of the kernel model (rfesim.loads.tensioner), one row per tensioner."""
    supports = getattr(sc, "supports", None) or {}
    tens = [(name, sup) for name, sup in supports.items() if sup.kind == "tensioner"]
    index = {li.name: li for li in lines}
    K = max([len(sup.payout.rows) for _, sup in tens if sup.payout.kind == "table"] + [2])
    m = len(tens)
    out = {
        "tens_att": np.zeros(m, np.int64), "tens_point": np.zeros((m, 3)), "tens_axis": np.zeros((m, 3)),
        "tens_length": np.zeros(m), "tens_kl": np.zeros(m), "tens_kg": np.zeros(m), "tens_cap": np.zeros(m),
        "tens_line_lo": np.zeros(m, np.int64), "tens_line_hi": np.zeros(m, np.int64),
        "tens_mode": np.zeros(m, np.int64), "tens_table_t": np.zeros((m, K)), "tens_table_d": np.zeros((m, K)),
        "tens_table_v": np.zeros((m, K)),
        "tens_count": np.zeros(m, np.int64), "tens_set": np.zeros(m), "tens_band": np.zeros(m),
        "tens_gain": np.ones(m), "tens_vmax": np.zeros(m),
    }
    infos = []
    for j, (name, sup) in enumerate(tens):
        li = index[sup.line]
        out["tens_att"][j] = attachment_names.index(sup.attach)
        out["tens_point"][j] = sup.entry
        axis = np.asarray(sup.axis, float)
        out["tens_axis"][j] = axis / np.linalg.norm(axis)
        out["tens_length"][j] = sup.length
        out["tens_kl"][j] = sup.lateral_stiffness
        out["tens_kg"][j] = sup.grip_stiffness
        out["tens_cap"][j] = sup.capacity
        out["tens_line_lo"][j] = li.rfe_start
        out["tens_line_hi"][j] = li.rfe_stop
        fill_payout(out, "tens", j, sup.payout)
        infos.append(TensionerInfo(name=name, line=sup.line, index=j))
    return out, infos


def track_held_length(centres: np.ndarray, lengths: np.ndarray, P: np.ndarray, e: np.ndarray,
                      L: float) -> float | None:
    """Length of line (m) from its end A up to the exit of a track (entry ``P``, unit axis
    ``e``, length ``L``) along the line: the arc length to the centre of the last RFE of the
    first run, from end A, of RFEs whose centres lie in the track (0 <= xi <= L, within
    ``TRACK_CAPTURE`` of its axis, as rfesim.loads.tensioner holds them), plus what is left of
    the track beyond that centre. None when no RFE lies in the track. ``centres`` (n, 3) and
    ``lengths`` (n,) are one line's RFEs."""
    from ..loads.tensioner import TRACK_CAPTURE
    d = centres - P[None, :]
    xi = d @ e
    lateral = np.linalg.norm(d - xi[:, None] * e[None, :], axis=1)
    inside = (xi >= 0.0) & (xi <= L) & (lateral <= TRACK_CAPTURE)
    if not inside.any():
        return None
    k = int(np.argmax(inside))
    while k + 1 < len(inside) and inside[k + 1]:
        k += 1
    s_centre = np.cumsum(lengths) - 0.5 * lengths
    return float(s_centre[k] + (L - xi[k]))


def table_payout_problems(model) -> list[tuple[str, str]]:
    """(field, reason) for each tensioner whose payout table pays out more line than lies
    behind its track's exit in the start shape (``track_held_length``): the line's end A
    would leave the track and the line fly off or drop (a 15 m table through a 10 m track
    with end A at its entry ran 'finished', its line 494 m away). A reel's table is checked
    against its stored_length by the schema; a driven (constant-tension) payout, whose total
    is not known before the run, and what statics shifts the payout by, are checked during
    the run (rfesim.solvers.dynamics.payout_beyond)."""
    sc, km = model.scenario, model.km
    supports = getattr(sc, "supports", None) or {}
    out = []
    X = model.initial.positions()
    att = model.attachment_state(0.0)
    origins = getattr(sc, "_origins", None) or {}
    for ti in model.tensioners:
        sup = supports[ti.name]
        if sup.payout.kind != "table":
            continue
        reach = max(row[1] for row in sup.payout.rows)
        if reach <= 0.0:
            continue
        li = model.line(ti.line)
        a = int(km.tens_att[ti.index])
        P = att.p[a] + att.R[a] @ km.tens_point[ti.index]
        e = att.R[a] @ km.tens_axis[ti.index]
        lo, hi = li.rfe_start, li.rfe_stop
        held = track_held_length(X[lo:hi], km.rfe_length[lo:hi], P, e, float(km.tens_length[ti.index]))
        if held is None or reach <= held * (1.0 + 1e-9):
            continue
        field = f"supports.{ti.name}.payout"
        if origins:
            from ..scenario.pipelay import template_path
            field = template_path(field, origins)
        out.append((field,
                    f"the table pays out {reach:.6g} m, but the tensioner holds only {held:.6g} m of line "
                    f"'{ti.line}' from its end A up to the track's exit at the start: end A would leave the track "
                    f"and the line run free; pay out at most {held:.6g} m, or start with more line behind the "
                    f"track (end A further back, or a longer track)"))
    return out
