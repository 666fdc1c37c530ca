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
                _shift(km, ws, j, reels, delta)
                try:
                    new, new_info = solve(state)
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
