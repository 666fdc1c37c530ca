"""What a straightener leaves in the pipe: the residual curvature of the elasto-plastic pipe
that went through a straightener support during a run, with its sense, and a warning when
it stays above ``STRAIGHTNESS_LIMIT`` (docs/theory.md, "Straightener offset").

The residual curvature is the curvature an SDE keeps when unloaded to zero moment from its
memory (rfesim.materials.residual_curvature, a magnitude); here it is a vector in the SDE's
frame (``signed_residual``), whose sense is measured against the bend the straightener
takes out: a straightener pushes its middle roller(s) towards ``side``, bending the pipe
about axis x (-side) there, so the bend it reverses, the reeling and aligner bend of a
reel-lay, is the one about ``axis x side``. Pipe left bent that way is under-straightened
(a larger offset bends it back further), pipe bent the other way over-straightened.
"""
from __future__ import annotations

import math

import numpy as np

# 1/m: pipe that leaves a straightener with more residual curvature than this (a bend radius
# of 200 m, a twentieth of the 0.105 1/m a 12.75 in X65 pipe keeps from an 8 m reel) is
# named in a run's warnings
STRAIGHTNESS_LIMIT = 0.005
CAPTURE = 1.0              # m: pipe within this of the straightener's line is on it


def signed_residual(params: np.ndarray, hist: np.ndarray, i: int) -> tuple[float, float]:
    """(kappa_y, kappa_z) 1/m: the residual curvature vector of elasto-plastic SDE i in its
    frame, the zero of the overlay law's moment from its committed memory: the elastic
    unloading point, then Newton with the consistent tangent (as
    ``rfesim.materials.residual_curvature.residual_curvature_into``, which gives its
    magnitude)."""
    from .materials.sde_plastic import plastic_bending_into
    p = params[i]
    n = int(p[0])
    ei = p[1] + float(np.sum(p[2:2 + n]))
    ky = float(np.sum(p[2:2 + n] * hist[i, 0:2 * n:2])) / ei
    kz = float(np.sum(p[2:2 + n] * hist[i, 1:2 * n:2])) / ei
    strength = float(np.sum(p[2 + n:2 + 2 * n]))
    out = np.zeros(5)
    work = hist.copy()
    for _ in range(50):
        plastic_bending_into(params, hist, i, ky, kz, out, work)
        if math.hypot(out[0], out[1]) <= 1e-12 * strength:
            break
        det = out[2] * out[4] - out[3] * out[3]
        if det <= 1e-14 * ei * ei:
            break
        ky -= (out[4] * out[0] - out[3] * out[1]) / det
        kz -= (out[2] * out[1] - out[3] * out[0]) / det
    return ky, kz


def _frame(model, sup, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(entry, unit axis, unit side) of a straightener support in the global frame at time t."""
    att = model.attachment_state(t)
    a = model.attachment_names.index(sup.attach)
    R, p = att.R[a], att.p[a]
    e = R @ np.asarray(sup.axis, float)
    s = R @ np.asarray(sup.side, float)
    return p + R @ np.asarray(sup.entry, float), e / np.linalg.norm(e), s / np.linalg.norm(s)


def straightened(system, state, results, name: str) -> dict | None:
    """The pipe that went through straightener support ``name`` during the run of ``results``
    (upstream of its first middle roller at the first output, past its last roller and
    within two spans of it at ``state``, the last): {"sde": line SDE indices, "residual": (m,)
    1/m magnitudes, "signed": (m,) 1/m, positive bent as the pipe coming in (the bend the
    straightener takes out: the residual curvature of the elasto-plastic pipe on the three
    elements before its entry, or without one there the bend about axis x side), negative
    the other way, "arc_length": (m,) m from end A, "against": +1 when the middle roller(s)
    push against the incoming bend (``side`` as meant), -1 when with it}; None when no such
    elasto-plastic pipe."""
    model = system.model
    sc = model.scenario
    sup = sc.supports[name]
    li = model.line(sup.line)
    km = model.km
    lo, hi = li.sde_start, li.sde_stop
    if not np.any(km.sde_plastic[lo:hi] == 1) or sup.line not in results.lines:
        return None
    pos = np.asarray(results.line(sup.line).position)
    # upstream of the first middle roller (one pitch in) at the start: the SDEs from end A
    # before the first one on the straightener's line past it
    pitch = sup.span / (sup.rollers - 1)
    P0, e0, _ = _frame(model, sup, float(results.time[0]))
    d0 = pos[0, 1:-1] - P0
    xi0 = d0 @ e0
    on0 = np.flatnonzero((xi0 >= pitch) & (np.linalg.norm(d0 - xi0[:, None] * e0, axis=1) <= CAPTURE))
    first = int(on0[0]) if len(on0) else int(np.argmin(np.linalg.norm(d0 - pitch * e0, axis=1)))
    P, e, side = _frame(model, sup, float(state.t))
    system.evaluate(state)
    ws = system.ws
    d = ws.sde_point[lo:hi] - P
    xi = d @ e
    near = np.linalg.norm(d - xi[:, None] * e, axis=1) <= CAPTURE
    plastic = km.sde_plastic[lo:hi] == 1
    k = np.flatnonzero((np.arange(hi - lo) < first) & near & (xi > sup.span) & (xi <= 3.0 * sup.span) & plastic)
    if not len(k):
        return None

    def vector(j: int) -> np.ndarray:
        ky, kz = signed_residual(km.plastic_params, ws.plastic_hist, lo + j)
        return ws.R[li.rfe_start + j] @ np.array([0.0, ky, kz])      # the SDE's left RFE's frame

    # the bend coming in: the pipe about to enter (the three elements before the first on the line)
    normal = np.cross(e, side)
    entering = np.flatnonzero(near & (xi >= 0.0))
    if len(entering):
        j0 = int(entering[0])
        ref = sum((vector(j) for j in range(max(0, j0 - 3), j0) if plastic[j]), np.zeros(3))
        if np.linalg.norm(ref) > STRAIGHTNESS_LIMIT:
            ref = ref - (ref @ e) * e
    else:
        ref = np.zeros(3)
    against = 1.0
    if np.linalg.norm(ref) > STRAIGHTNESS_LIMIT:
        against = 1.0 if float(ref @ normal) >= 0.0 else -1.0
        normal = ref / np.linalg.norm(ref)
    signed = np.array([float(vector(j) @ normal) for j in k])
    return {"sde": k, "residual": np.array([float(np.linalg.norm(vector(j))) for j in k]), "signed": signed,
            "arc_length": np.asarray(li.sde_arc_length)[k], "against": against, "pitch": pitch}


def suggested_offset(offset: float, residual: float, pitch: float) -> float:
    """The offset (m, positive pushing against the incoming bend) that would leave the
    residual curvature ``residual`` (1/m, positive as the pipe came in) of the pipe through a
    straightener set at ``offset`` at zero: the middle roller of a three-roller bender moved
    by d bends the pipe under it by 3 d / p^2 more (a beam on two supports p either side of
    a load: deflection F (2p)^3 / 48 EI, curvature F 2p / 4 EI), and near the cancelling
    reverse curvature the residual changes one for one with it (docs/theory.md,
    "Straightener offset")."""
    return offset + residual * pitch * pitch / 3.0


def straightener_warnings(system, state, results, sc) -> list[str]:
    """One message per straightener support whose pipe, gone through it during the run,
    keeps a residual curvature above STRAIGHTNESS_LIMIT: the largest, its bend radius, its
    sense, the mean, and the offset that would cancel the mean (``suggested_offset``) in the
    field to set (the template's ``straightener_offset`` for a reel-lay template's
    straightener, negative there when set away from the centres)."""
    out = []
    origins = getattr(sc, "_origins", None) or {}
    for name, sup in (sc.supports or {}).items():
        if sup.kind != "straightener":
            continue
        got = straightened(system, state, results, name)
        if got is None:
            continue
        m = int(np.argmax(got["residual"]))
        k = float(got["residual"][m])
        if k <= STRAIGHTNESS_LIMIT:
            continue
        field = f"supports.{name}.offset"
        if origins:
            from .scenario.pipelay import template_path
            field = template_path(field, origins)
        mean = float(np.mean(got["signed"]))
        now = got["against"] * sup.offset
        new = suggested_offset(now, mean, got["pitch"])
        sense = "bent as it came in" if got["signed"][m] > 0.0 else "bent the other way (reversed)"
        state_ = "under-straightened" if mean > 0.0 else "over-straightened"
        if field.endswith(".straightener_offset"):
            advice = f"give {field} {new:.3g} m (now {now:.4g} m; negative: the middle roller away from the centres)"
        elif new >= 0.0:
            advice = f"give {field} {new:.3g} m (now {sup.offset:.4g} m)"
        else:
            advice = (f"give {field} {-new:.3g} m with supports.{name}.side the other way (the middle roller "
                      f"pushing {'with' if got['against'] > 0 else 'against'} the incoming bend; now "
                      f"{sup.offset:.4g} m)")
        over = int(np.count_nonzero(got["residual"] > STRAIGHTNESS_LIMIT))
        out.append(f"the pipe that left straightener '{name}' during the run keeps a residual curvature of up to "
                   f"{k:.4g} 1/m (bend radius {1.0 / k:.4g} m, {sense}; {over} of its {len(got['residual'])} "
                   f"elements there above {STRAIGHTNESS_LIMIT:g} 1/m, the largest {got['arc_length'][m]:.4g} m "
                   f"from end A of line '{sup.line}'; mean {mean:+.3g} 1/m, {state_}): {advice}, which the mean "
                   f"says cancels it (a residual curvature changes by -3 / pitch^2 per m of offset; docs/theory.md, "
                   f"'Straightener offset')")
    return out
