"""Reels and straighteners of a scenario -> kernel arrays, roller sets, the initial shape
of a line stored on a reel and its reeled plastic state.

* ``compile_reels``: one row per reel of the reel kernel (rfesim.loads.reel), the payout
  in the tensioner's form (rfesim.model.supports.compile_tensioners).
* ``straightener_roller_set``: a straightener is n (odd) rollers over ``span`` along its
  axis: the even ones (both ends) hold the pipe axis on the straight line from ``entry``
  (they sit on the ``side`` of the pipe and push it back), the odd ones push it out by
  ``offset`` towards ``side`` (reverse bending). It compiles to ordinary rollers.
* ``reel_wrap_start``: the stored length of a line on a reel at t = 0, from end A along
  the wrap to the take-off point (a fine polyline on the circle of the pipe axis).
* ``reeled_history``: the plastic history of the SDEs on the wrap at t = 0: each bent
  from the straight virgin state to its curvature on the drum (the pipe was reeled on), so
  that pipe paid out carries the reeling residual curvature.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .supports import RollerSet, fill_payout


@dataclass
class ReelInfo:
    name: str
    line: str
    index: int


def reel_frame(sup, att0, attachment_names) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Global centre C, unit axis a, payout direction d and take-off radius n0 = a x d at t = 0."""
    at = attachment_names.index(sup.attach)
    R, p = att0.R[at], att0.p[at]
    a = np.asarray(sup.axis, float)
    a = a / np.linalg.norm(a)
    d = np.asarray(sup.direction, float)
    d = d - (d @ a) * a
    d = d / np.linalg.norm(d)
    return p + R @ np.asarray(sup.centre, float), R @ a, R @ d, R @ np.cross(a, d)


def compile_reels(sc, attachment_names: list[str], lines) -> tuple[dict, list[ReelInfo]]:
    """Reel arrays of the kernel model (rfesim.loads.reel), one row per reel."""
    supports = getattr(sc, "supports", None) or {}
    reels = [(name, sup) for name, sup in supports.items() if sup.kind == "reel"]
    index = {li.name: li for li in lines}
    K = max([len(sup.payout.rows) for _, sup in reels if sup.payout.kind == "table"] + [2])
    m = len(reels)
    out = {
        "reel_att": np.zeros(m, np.int64), "reel_centre": np.zeros((m, 3)), "reel_axis": np.zeros((m, 3)),
        "reel_dir": np.zeros((m, 3)), "reel_radius": np.zeros(m), "reel_wrap": np.zeros(m), "reel_kr": np.zeros(m),
        "reel_kl": np.zeros(m), "reel_kg": np.zeros(m), "reel_cap": np.zeros(m),
        "reel_line_lo": np.zeros(m, np.int64), "reel_line_hi": np.zeros(m, np.int64),
        "reel_mode": np.zeros(m, np.int64), "reel_table_t": np.zeros((m, K)), "reel_table_d": np.zeros((m, K)),
        "reel_table_v": np.zeros((m, K)), "reel_count": np.zeros(m, np.int64), "reel_set": np.zeros(m),
        "reel_band": np.zeros(m), "reel_gain": np.ones(m), "reel_vmax": np.zeros(m),
    }
    infos = []
    for j, (name, sup) in enumerate(reels):
        li = index[sup.line]
        out["reel_att"][j] = attachment_names.index(sup.attach)
        out["reel_centre"][j] = sup.centre
        a = np.asarray(sup.axis, float)
        a /= np.linalg.norm(a)
        d = np.asarray(sup.direction, float)
        d = d - (d @ a) * a
        out["reel_axis"][j] = a
        out["reel_dir"][j] = d / np.linalg.norm(d)
        out["reel_radius"][j] = sup.radius
        out["reel_wrap"][j] = math.radians(sup.wrap_deg)
        out["reel_kr"][j] = sup.contact_stiffness
        out["reel_kl"][j] = sup.lateral_stiffness
        out["reel_kg"][j] = sup.grip_stiffness
        out["reel_cap"][j] = sup.capacity
        out["reel_line_lo"][j] = li.rfe_start
        out["reel_line_hi"][j] = li.rfe_stop
        fill_payout(out, "reel", j, sup.payout)
        infos.append(ReelInfo(name=name, line=sup.line, index=j))
    return out, infos


def straightener_roller_set(sup, pipe_radius: float) -> RollerSet:
    """Rollers of a straightener in its attachment frame (see the module text)."""
    e = np.asarray(sup.axis, float)
    e /= np.linalg.norm(e)
    side = np.asarray(sup.side, float)
    side = side - (side @ e) * e
    side /= np.linalg.norm(side)
    across = np.cross(e, side)
    entry = np.asarray(sup.entry, float)
    reach = pipe_radius + sup.roller_radius
    pts, up = [], []
    n = sup.rollers
    for k in range(n):
        x = entry + (k * sup.span / (n - 1)) * e
        if k % 2 == 0:          # on the side of the pipe: pushes it back onto the straight line
            pts.append(x + reach * side)
            up.append(-side)
        else:                   # on the other side: pushes the pipe axis out to the offset
            pts.append(x + (sup.offset - reach) * side)
            up.append(side)
    P = np.asarray(pts)
    return RollerSet(P, np.tile(across, (n, 1)), np.full(n, 0.5 * sup.roller_width), np.full(n, sup.roller_radius),
                     P.copy(), np.asarray(up), np.ones(n))


def line_reel(sc, line_name: str):
    """(name, reel) of the reel that stores line ``line_name``, or None."""
    for name, sup in (getattr(sc, "supports", None) or {}).items():
        if sup.kind == "reel" and sup.line == line_name:
            return name, sup
    return None


def reel_wrap_start(sc, line_name: str, attachment_names, att0, points_per_radian: int = 2000):
    """(s, X, d) of the stored part of a line on its reel at t = 0: arc length from end A,
    points on the circle of the pipe axis from end A (wrap angle stored_length / R) to the
    take-off point, and the payout direction there; None when no reel stores the line."""
    found = line_reel(sc, line_name)
    if found is None:
        return None
    sup = found[1]
    C, a, d, n0 = reel_frame(sup, att0, attachment_names)
    R = sup.radius
    phi_a = sup.stored_length / R
    m = max(2, int(math.ceil(phi_a * points_per_radian)) + 1)
    phi = np.linspace(phi_a, 0.0, m)
    X = C[None, :] + R * (np.cos(phi)[:, None] * n0[None, :] - np.sin(phi)[:, None] * d[None, :])
    return R * (phi_a - phi), X, d


def track_points(sc, line_name: str, attachment_names, att0) -> np.ndarray | None:
    """Global points (t = 0) of the entry and exit of every tensioner track that holds line
    ``line_name`` (its axis), or None: the start shape of a reeled line passes through them."""
    pts = []
    for sup in (getattr(sc, "supports", None) or {}).values():
        if sup.kind != "tensioner" or sup.line != line_name:
            continue
        at = attachment_names.index(sup.attach)
        R, p = att0.R[at], att0.p[at]
        e = np.asarray(sup.axis, float)
        e = e / np.linalg.norm(e)
        entry = np.asarray(sup.entry, float)
        pts.extend([p + R @ entry, p + R @ (entry + sup.length * e)])
    return np.asarray(pts) if pts else None


def reel_tail(P0: np.ndarray, d: np.ndarray, length: float, rest: np.ndarray | None, B: np.ndarray | None,
              tail=None, track: np.ndarray | None = None):
    """(s, X) from the take-off point P0: through the resting points on rollers and the
    tensioner track points ahead of it along d (each next the nearest), then, when end B is
    placed, ``tail(G, B, remaining) -> (s, X)`` from the last of them G to B (the catenary
    with the remaining length; without ``tail``: straight to B), else straight on."""
    pts = [P0]
    cand = [c for c in (rest, track) if c is not None and len(c)]
    if cand:
        allp = np.vstack(cand)
        ahead = list(allp[(allp - P0) @ d > 0.0])
        # chained nearest first, not sorted by the distance along d: a ramp near 90 deg runs
        # almost across d, and there the straightener's offset middle roller came before the
        # roller 3 m above it (89.9 deg: 20 -> 14 -> 17 -> 12 m up the ramp, 6 m of detour,
        # so the start shape's catenary lacked 6 m and its last element started stretched
        # 391 %, and statics failed)
        while ahead:
            k = int(np.argmin([np.linalg.norm(p - pts[-1]) for p in ahead]))
            pts.append(ahead.pop(k))
    X = np.asarray(pts)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(X, axis=0), axis=1))])
    remaining = length - s[-1]
    if remaining <= 0.0:
        from ..errors import ScenarioError
        raise ScenarioError([("supports", f"the line leaves the reel with {length:.6g} m but reaches the last "
                                          f"roller only after {s[-1]:.6g} m: make it longer")])
    if B is not None and tail is not None:
        ts, tX = tail(X[-1], np.asarray(B, float), remaining)
        return np.concatenate([s, s[-1] + ts[1:]]), np.vstack([X, tX[1:]])
    if B is not None:
        end = np.asarray(B, float)
    else:
        u = X[-1] - X[-2] if X.shape[0] > 1 else d
        end = X[-1] + remaining * u / np.linalg.norm(u)
    return np.append(s, s[-1] + remaining), np.vstack([X, end])


def reeled_history(sc, lines, ref_R: np.ndarray, params: np.ndarray, width: int) -> np.ndarray | None:
    """Plastic history (nsde, width) at t = 0: the SDEs of a line stored on a reel that lie
    on the wrap (arc length <= stored_length) bent from the virgin state to their initial
    curvature (the relative rotation of their two RFEs over the spacing, which the start
    shape puts on the circle of radius R); zero elsewhere. None without reels."""
    from ..kinematics import log_so3_into
    from ..materials.sde_plastic import N_OUT, plastic_bending_into
    hist = None
    out = np.zeros(N_OUT)
    w = np.zeros(3)
    for li in lines:
        found = line_reel(sc, li.name)
        if found is None:
            continue
        if hist is None:
            hist = np.zeros((params.shape[0], width))
        zero = np.zeros_like(hist)
        stored = found[1].stored_length
        for k, s in enumerate(li.sde_arc_length):
            if s > stored:
                break
            i = li.sde_start + k
            if params[i, 0] <= 0.0:
                continue              # an elastic line: no memory
            left = li.rfe_start + k
            log_so3_into(ref_R[left].T @ ref_R[left + 1], w)
            plastic_bending_into(params, zero, i, w[1] / li.dx, w[2] / li.dx, out, hist)
    return hist
