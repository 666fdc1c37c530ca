"""Statics of a laid line at a given horizontal lay tension (``horizontal_tension`` of a
tensioner support; the pipelay templates set it to their ``tension``).

A tensioner (or J-lay collar) grips the line where it starts (rfesim.solvers.statics), so
the first static solution holds the *length* of line between the track and the pinned end
B on the seabed, not the tension: the horizontal tension H settles wherever that length
puts it. The templates build the line on the natural catenary of the given H, but the
bending stiffness (the stiffened catenary, the pipe leaving the stinger before its tip)
leaves a little more length in the span than the catenary has, and H settles a few per
cent low (the S-lay template: 143.6 kN for 150 kN; J-lay 1.7 % low). H is the horizontal
force on end B: the laid pipe carries it there when statics leaves out the seabed friction
(``analysis.statics.seabed_friction`` "none", the default).

``settle_lay_tension`` pays the line out through the track (or hauls it in) -- shifts the
tensioner's paid-out length by delta, which moves its grip anchors along the track -- and
solves statics again, by secant iterations on delta, until the horizontal force of the line
on its end B equals the given H to ``TOLERANCE`` (0.1 %; at most ``MAX_SHIFTS`` shifts, each
at most a quarter of an element length, ``MAX_STEP``, and rolled back and made smaller when
Newton lands on another equilibrium; more than ``ACCEPT``, 0.5 %, off fails).
The first slope is the natural catenary's, dH/dL = w / (dL/da) with a = H / w and
L = s - x the suspended length less its horizontal span from the track's exit height:
dL/da = h/s - acosh(1 + h/a) + sqrt((h/a) / (2 + h/a)). A reel on the same line turns
with the tensioner (its payout is shifted by the same delta), so the pipe between them,
and the reel's back tension, stay as they were. The shift stays in the payout for the run
(a prescribed table is shifted by delta at all times, a driven tensioner's committed
payout too; the results' ``payout`` starts at delta), so dynamics starts from that
equilibrium without a jump.

An elasto-plastic line (the reel-lay template's pipe through its straightener and over its
aligner) takes two more measures (docs/theory.md, "reel-lay given tension"):

* every shift solves from the plastic history the line had at t = 0 (the reeled pipe on the
  drum, virgin pipe elsewhere; ``Model.initial_plastic_history``), not from the last shift's:
  the settled state is the one a single statics solve at the settled payout gives, and a
  shift back and forth through the straightener adds no plastic cycle (hauling in would
  otherwise drag the pipe backwards through it, cycle by cycle);
* Newton starts from the last equilibrium with the line slid along itself by delta
  (``slide_line``): up to the track's exit every RFE takes the pose the line had delta
  further on (cubic Hermite along the centres with the RFE axes as tangents, rotations
  interpolated on SO(3)), so the pipe moves with the grips; over the suspended span the
  slide tapers linearly to 0 at end B. Started from the grips moved alone, the grips (1e7
  N/m per metre of track) sit at their capacity and the plastic hinges must be dragged
  through the rollers: a 0.5 m shift of the reel-lay template's payout took 400 iterations
  (8.5 s) and failed, four times in a row, before 0.3 m shifts went through.
"""
from __future__ import annotations

import math

import numpy as np

MAX_SHIFTS = 12
TOLERANCE = 1e-3        # relative: the shifts stop when H is this close
ACCEPT = 5e-3           # relative: beyond it after MAX_SHIFTS shifts, statics fails
# Largest shift of one solve, in element lengths of the line, and the retries of a shift.
# Newton starts each solve from the last equilibrium with the grips moved by the shift, and
# now and then lands on another equilibrium: in the S-lay template (2 m elements, V-rollers
# 6 m apart) shifts of -0.05 to -0.4 m from the first solution all converge next to it
# (H 144.4 to 148.8 kN, largest curvature 0.0108-0.0109 1/m) but for -0.2 m, where 28
# iterations end on a pipe pressed wavy into the rollers (curvature 0.0317 1/m, 560 kN on a
# station). A solve whose largest curvature grows by more than CURVATURE_JUMP (relative,
# plus 1e-4 1/m) or that fails is rolled back (history, payout) and tried again with 0.6
# times the shift, at most RETRIES times.
MAX_STEP = 0.25
CURVATURE_JUMP = 0.25
RETRIES = 4


def _end_b_horizontal(system, state, li) -> float:
    """Horizontal force (N) of line ``li`` on its end-B attachment at ``state`` (the
    results' end_b_force, rfesim.model.outputs.reactions, without the vertical part)."""
    from ..model.outputs import reactions
    system.evaluate(state)
    react = np.zeros((system.n, 6))
    reactions(system.km, system.att, system.ws, np.zeros((system.n, 6)), react)
    F = -react[li.rfe_stop - 1, :3]
    return float(math.hypot(F[0], F[1]))


def _exit_height(system, state, j: int, li) -> float:
    """Height (m) of tensioner j's exit above the line's end B at ``state``."""
    km, att = system.km, system.att
    system.evaluate(state)
    a = km.tens_att[j]
    exit_local = km.tens_point[j] + km.tens_length[j] * km.tens_axis[j]
    p = att.p[a] + att.R[a] @ exit_local
    return float(p[2] - system.ws.r[li.rfe_stop - 1, 2])


def catenary_slope(w: float, h: float, H: float) -> float:
    """dH/dL (N/m, negative) of the natural catenary of submerged weight w (N/m) from a
    point h above its tangent touchdown to a fixed far end on the seabed: paying out dL of
    line lowers H by this much per metre."""
    a = H / w
    s = math.sqrt(h * h + 2.0 * a * h)
    dLda = h / s - math.acosh(1.0 + h / a) + math.sqrt((h / a) / (2.0 + h / a))
    return w / dLda


def _largest_curvature(system, state, li) -> float:
    """Largest SDE curvature (1/m) of line ``li`` at ``state``."""
    from ..model.outputs import sde_channels
    system.evaluate(state)
    n = system.model.nsde
    ch = [np.zeros(n) for _ in range(5)]
    sde_channels(system.ws, system.km.sde_length, *ch)
    return float(ch[4][li.sde_start:li.sde_stop].max()) if li.sde_stop > li.sde_start else 0.0


def _exp(w: np.ndarray) -> np.ndarray:
    from ..kinematics import exp_so3_into
    out = np.zeros((3, 3))
    exp_so3_into(float(w[0]), float(w[1]), float(w[2]), out)
    return out


def _log(R: np.ndarray) -> np.ndarray:
    from ..kinematics import log_so3_into
    out = np.zeros(3)
    log_so3_into(np.ascontiguousarray(R), out)
    return out


def slide_line(system, state, li, j: int, delta: float):
    """A copy of ``state`` with line ``li`` slid along itself by ``delta`` (m, > 0 towards
    end B): Newton's start after tensioner j pays out delta. The RFE at arc length s (along
    the centres from end A) takes the pose the line had at s + delta f(s), f = 1 up to the
    track's exit and falling linearly to 0 at end B (the suspended span takes the change of
    length; end B stays). Between two centres the position is the cubic Hermite curve with
    the RFE axes (times the distance) as tangents -- a chord would cut the arc of the reel
    or aligner and press the pipe into the rollers -- and the rotation is interpolated on
    SO(3); before end A (hauling in) the pose continues at the first element's curvature.
    Only free RFEs move."""
    km, ws, att = system.km, system.ws, system.att
    system.evaluate(state)
    i0, i1 = li.rfe_start, li.rfe_stop
    r, R = ws.r[i0:i1].copy(), ws.R[i0:i1].copy()
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r, axis=0), axis=1))])
    a = km.tens_att[j]
    exit_p = att.p[a] + att.R[a] @ (km.tens_point[j] + km.tens_length[j] * km.tens_axis[j])
    s_exit = s[int(np.argmin(np.linalg.norm(r - exit_p, axis=1)))]
    s_b = s[-1]
    f = np.where(s <= s_exit, 1.0, (s_b - s) / max(s_b - s_exit, 1e-300))
    target = s + delta * f
    rate0 = _log(R[0].T @ R[1]) / s[1]               # curvature of the first element (body frame)
    new = state.copy()
    for k in range(len(s)):
        i = i0 + k
        if km.rfe_kind[i] != 0:
            continue
        t = target[k]
        if t < 0.0:
            Rn = R[0] @ _exp(t * rate0)
            pn = r[0] + t * (R[0] @ _exp(0.5 * t * rate0))[:, 0]
        else:
            t = min(t, s_b)
            m = min(int(np.searchsorted(s, t, side="right")) - 1, len(s) - 2)
            ln = s[m + 1] - s[m]
            u = (t - s[m]) / ln
            pn = ((2 * u ** 3 - 3 * u ** 2 + 1) * r[m] + (u ** 3 - 2 * u ** 2 + u) * ln * R[m][:, 0]
                  + (3 * u ** 2 - 2 * u ** 3) * r[m + 1] + (u ** 3 - u ** 2) * ln * R[m + 1][:, 0])
            Rn = R[m] @ _exp(u * _log(R[m].T @ R[m + 1]))
        new.ref.X[i] = pn
        new.ref.R[i] = Rn
        new.q[i] = 0.0
    system.evaluate(state)
    return new


def _shift(km, ws, j: int, reels: list[int], delta: float) -> None:
    """Pay out ``delta`` more through tensioner j and the reels that turn with it."""
    if km.tens_mode[j] == 0:
        km.tens_table_d[j, :km.tens_count[j]] += delta
    else:
        ws.tens_D[j] += delta
    for r in reels:
        if km.reel_mode[r] == 0:
            km.reel_table_d[r, :km.reel_count[r]] += delta
        else:
            ws.reel_D[r] += delta


def settle_lay_tension(system, sc, state, info, solve):
    """(state, info) with the line of every tensioner that has a ``horizontal_tension``
    carrying it to its end B. ``solve(state)`` -> (state, info) solves statics from a state
    (the committed grips kept). Raises SolverError when H is not reached to 0.5 %."""
    from ..errors import SolverError
    from ..model.compile import _submerged_weight
    model = system.model
    held = [(ti, sc.supports[ti.name].horizontal_tension) for ti in getattr(model, "tensioners", [])
            if getattr(sc.supports[ti.name], "horizontal_tension", None) is not None]
    if not held:
        return state, info
    km, ws = system.km, system.ws
    lines = {li.name: li for li in model.lines}
    iterations = info.iterations
    warnings = list(info.warnings)              # the first solve's (a catenary retry's note)
    for ti, target in held:
        j, li = ti.index, lines[ti.line]
        reels = [ri.index for ri in getattr(model, "reels", []) if ri.line == ti.line]
        w = _submerged_weight(li.section, sc)
        h = _exit_height(system, state, j, li)
        slope = catenary_slope(w, h, target) if w > 0.0 and h > 0.0 else -w
        cap = min(MAX_STEP * li.dx, 0.5 * km.tens_length[j])
        # an elasto-plastic line: each shift from the t = 0 plastic history, Newton from the
        # line slid with the grips (module docstring)
        plastic = bool(km.has_plastic and np.any(km.sde_plastic[li.sde_start:li.sde_stop] == 1))
        if plastic:
            hist0 = (model.initial_plastic_history if getattr(model, "initial_plastic_history", None) is not None
                     else np.zeros_like(ws.plastic_hist))[li.sde_start:li.sde_stop].copy()
        prev = None
        H = _end_b_horizontal(system, state, li)
        kappa = _largest_curvature(system, state, li)
        for _ in range(MAX_SHIFTS):
            err = H - target
            if abs(err) <= TOLERANCE * target:
                break
            if prev is not None and abs(H - prev[1]) > 1e-9 * target:
                slope = min((H - prev[1]) / prev[0], -1e-6 * abs(slope))
            delta = max(-cap, min(cap, -err / slope))          # H too high: pay out (delta > 0)
            for _attempt in range(RETRIES + 1):
                saved = system.history()
                start = state
                if plastic:
                    ws.plastic_hist[li.sde_start:li.sde_stop] = hist0
                    start = slide_line(system, state, li, j, delta)
                _shift(km, ws, j, reels, delta)
                try:
                    new, new_info = solve(start)
                    k_new = _largest_curvature(system, new, li)
                    ok = k_new <= (1.0 + CURVATURE_JUMP) * kappa + 1e-4
                except SolverError:
                    ok = False
                if ok:
                    break
                system.set_history(saved)                         # roll back: history and payout
                if km.tens_mode[j] == 0:
                    km.tens_table_d[j, :km.tens_count[j]] -= delta
                for r in reels:
                    if km.reel_mode[r] == 0:
                        km.reel_table_d[r, :km.reel_count[r]] -= delta
                system.evaluate(state)                            # the grips' trial values of that state
                delta *= 0.6
            else:
                raise SolverError(f"statics: line '{ti.line}' does not settle at the horizontal tension "
                                  f"{target:.6g} N of supports.{ti.name}.horizontal_tension: paying out "
                                  f"{delta / 0.6:.4g} m from {H:.6g} N finds no equilibrium next to the last one")
            iterations += new_info.iterations
            prev = (delta, H)
            state, info, kappa = new, new_info, k_new
            H = _end_b_horizontal(system, state, li)
        if abs(H - target) > ACCEPT * target:
            raise SolverError(f"statics: line '{ti.line}' does not settle at the horizontal tension "
                              f"{target:.6g} N of supports.{ti.name}.horizontal_tension (it carries {H:.6g} N to "
                              f"its end B after {MAX_SHIFTS} shifts of the payout)")
    info.iterations = iterations
    info.warnings = warnings + [w for w in info.warnings if w not in warnings]
    return state, info
