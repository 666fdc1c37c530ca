"""Statics of reels that hold a given back tension (``back_tension`` of a reel support).

The reel's grips hold the line where it starts (rfesim.solvers.statics), so the tension
in the line where it leaves the drum after the first static solution is whatever the start
shape left between the reel and the tensioner: the line there is gripped at both ends, and
its tension is statically indeterminate. A real reel drive holds a set back tension.
``settle_back_tension`` turns each such drum -- shifts its paid-out length D by delta,
which moves its grip anchors along the wrap -- and solves statics again, by secant
iterations on delta, until the tension of the line just off the drum (the first SDE past
the take-off point) equals the back tension (to 1 % or 100 N). The shift stays in
the payout for the run (a prescribed table is shifted by delta at all times; a driven
drum's committed D is shifted), so dynamics starts from that equilibrium without a jump.
Each turn of the drum of an elasto-plastic line solves from the line's t = 0 plastic
history (``Model.initial_plastic_history``: the reeled pipe on the drum, virgin pipe
elsewhere), not from the last turn's, as the lay-tension shifts do
(rfesim.solvers.lay_statics): the settled pipe carries one step from it, and turning the
drum back and forth adds no plastic cycle. Then each such reel's offset ``ws.reel_offset[j]`` = grip force - back tension is stored:
a driven reel's law acts on its own grip force less it (rfesim.loads.reel), so it starts
at its set point (the back tension) and holds it in the mean.
"""
from __future__ import annotations

import numpy as np

MAX_SHIFTS = 12


def _take_off_tension(system, state, j: int) -> float:
    """Tension (N) of the first SDE past the take-off point of reel j."""
    from ..model.outputs import sde_channels
    km, ws, att = system.km, system.ws, system.att
    system.evaluate(state)
    at = km.reel_att[j]
    R, p = att.R[at], att.p[at]
    a, d = R @ km.reel_axis[j], R @ km.reel_dir[j]
    P0 = p + R @ km.reel_centre[j] + km.reel_radius[j] * np.cross(a, d)
    nsde = system.model.nsde
    ch = [np.zeros(nsde) for _ in range(5)]
    sde_channels(ws, km.sde_length, *ch)
    mine = (km.sde_left >= km.reel_line_lo[j]) & (km.sde_left < km.reel_line_hi[j])      # the reel's line
    past = np.flatnonzero(mine & ((ws.sde_point[:nsde] - P0) @ d > 0.0))
    i = past[np.argmin(np.linalg.norm(ws.sde_point[past] - P0, axis=1))]
    return float(ch[0][i])


def _sde_range(model, j: int) -> tuple[int, int]:
    """SDE range of the line stored on reel j."""
    ri = next(r for r in model.reels if r.index == j)
    li = next(li for li in model.lines if li.name == ri.line)
    return li.sde_start, li.sde_stop


def settle_back_tension(system, sc, state, info, solve):
    """(state, info) with every reel that has a back tension holding it. ``solve(state)``
    -> (state, info) solves statics from a state (the committed grips kept)."""
    model = system.model
    reels = [(ri.index, sc.supports[ri.name].back_tension) for ri in getattr(model, "reels", [])
             if getattr(sc.supports[ri.name], "back_tension", None) is not None]
    if not reels:
        return state, info
    km, ws = system.km, system.ws
    iterations = info.iterations
    for j, B in reels:
        # first secant slope: the grips on the wrap in series with 50 m of the line's axial stiffness
        kg = km.reel_kg[j] * km.reel_radius[j] * km.reel_wrap[j]
        ea = float(np.max(model.km.sde_stiffness[:, 0] * model.km.sde_length)) if model.nsde else kg
        slope = 1.0 / (1.0 / kg + 50.0 / ea)
        # an elasto-plastic line turns from its t = 0 plastic history each time
        lo, hi = _sde_range(model, j)
        hist0 = None
        if km.has_plastic and hi > lo and np.any(km.sde_plastic[lo:hi] == 1):
            init = getattr(model, "initial_plastic_history", None)
            hist0 = (init if init is not None else np.zeros_like(ws.plastic_hist))[lo:hi].copy()
        prev = None
        for _ in range(MAX_SHIFTS):
            F = _take_off_tension(system, state, j)
            err = F - B
            if abs(err) <= max(0.01 * B, 100.0):
                break
            if prev is not None and abs(F - prev[1]) > 1e-9 * B:
                slope = max(-(F - prev[1]) / prev[0], 1e-6 * slope)
            delta = err / slope                   # pay out (delta > 0) to hold less
            if km.reel_mode[j] == 0:
                km.reel_table_d[j, :km.reel_count[j]] += delta
            else:
                ws.reel_D[j] += delta
            prev = (delta, F)
            if hist0 is not None:
                ws.plastic_hist[lo:hi] = hist0          # from the t = 0 plastic history (module docstring)
            state, info = solve(state)
            iterations += info.iterations
        else:
            from ..errors import SolverError
            raise SolverError(f"statics: the reel does not settle at its back tension {B:.6g} N "
                              f"(holds {F:.6g} N after {MAX_SHIFTS} turns of the drum)")
    # the offset of each settled reel's law (rfesim.loads.reel): its grip force less the back
    # tension at the settled state, so a driven reel starts in equilibrium
    system.evaluate(state)
    for j, B in reels:
        ws.reel_offset[j] = float(ws.reel_force[j]) - B
    info.iterations = iterations
    return state, info
