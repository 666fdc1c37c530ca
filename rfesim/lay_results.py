"""Pipelay outputs of a run (issue 3, item 8): top tension, departure angle, touchdown,
sagbend and overbend maxima (moment, curvature, strain), roller reactions, residual
curvature and range graphs, for a line laid from a vessel (end A on board, end B on the
seabed), as the pipelay templates make it (rfesim.scenario.pipelay), or any line with
supports.

    res = rfesim.simulate("scenarios/s_lay_template.json")
    out = lay_summary(res)                 # the line with supports, or lay_summary(res, "lay")
    out["top_tension"]                     # (nt,) N, axial: held by the tensioner / collar
    out["departure_angle"]                 # (nt,) deg below horizontal at the lift-off point

The lift-off point is the most downstream support exit along the line: the stinger tip
(last roller station), the exit of a tensioner / collar track, or a roller. It is a point
of the geometry, not where the pipe last touches: the pipe may leave the stinger a station
or two before its tip (``roller_reactions`` of the last stations 0), and the departure
angle is then the angle at which it passes above the tip. The scenario is read from the
results (``scenario_json``: the expanded scenario), so results read back from a file work
as well.

Range graphs and maxima are per material SDE (arc length from end A): with a payout a
material SDE moves from the tensioner and stinger into the span, so its range then mixes
places along the lay.
"""
from __future__ import annotations

import json
import math

import numpy as np


def _rotation(roll_pitch_yaw_deg) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll) (eq. 8.73), angles in degrees."""
    phi, theta, psi = np.radians(roll_pitch_yaw_deg)
    cz, sz, cy, sy, cx, sx = math.cos(psi), math.sin(psi), math.cos(theta), math.sin(theta), math.cos(phi), \
        math.sin(phi)
    return np.array([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
                     [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
                     [-sy, cy * sx, cy * cx]])


def _vessel_rotation(sc: dict, res, vessel: str, k: int) -> np.ndarray:
    """The rotation of ``vessel`` at output k: its heading (the scenario's heading_deg) and
    its motion (the results' roll, pitch and yaw, taken about the heading's axes:
    R = R_heading Rz(yaw) Ry(pitch) Rx(roll), rfesim.vessel)."""
    heading = float(((sc.get("vessels") or {}).get(vessel) or {}).get("heading_deg", 0.0))
    return _rotation([0.0, 0.0, heading]) @ _rotation(res.vessels[vessel].rotation[k])


def _exit_points(sup: dict) -> np.ndarray:
    """Points (attachment frame) where the line leaves a support."""
    kind = sup.get("kind")
    if kind == "tensioner":
        axis = np.asarray(sup["axis"], float)
        return (np.asarray(sup["entry"], float) + sup["length"] * axis / np.linalg.norm(axis))[None, :]
    if kind == "stinger":
        from .model.supports import stinger_frame
        T, N0, _ = stinger_frame(sup["direction"])
        R = sup["radius"]
        th = math.floor(sup["length"] / sup["spacing"] + 1e-9) * sup["spacing"] / R
        return (np.asarray(sup["start"], float) + R * math.sin(th) * T + R * (1.0 - math.cos(th)) * N0)[None, :]
    if kind == "rollers":
        return np.asarray([r["position"] for r in sup["rollers"]], float)
    for key in ("exit", "end"):               # other guiding structures that name their exit
        if isinstance(sup.get(key), list) and len(sup[key]) == 3:
            return np.asarray(sup[key], float)[None, :]
    return np.zeros((0, 3))


def _tension_past(sc: dict, res, lr, sup: dict, pos: np.ndarray) -> np.ndarray:
    """(nt,) tension of the line at the exit of tensioner ``sup`` (followed with its vessel):
    the free span's tension, from the first two SDEs past the exit extrapolated linearly
    back to it (before, the first SDE's, up to an element below the exit: 161.4 kN against
    163.6 kN at the exit of the reel-lay template's 2 m elements, the pipe's weight in air
    over that length). pos (nt, npoints, 3): end A, the SDEs, end B."""
    tension = np.asarray(lr.tension)
    s = np.asarray(lr.sde_arc_length)
    p0 = _exit_points(sup)[0]
    e0 = np.asarray(sup["axis"], float)
    e0 = e0 / np.linalg.norm(e0)
    att = sup.get("attach", "fixed")
    out = np.zeros(pos.shape[0])
    n = tension.shape[1]
    for k in range(pos.shape[0]):
        p, e = p0, e0
        if att in res.vessels:
            vr = res.vessels[att]
            Rv = _vessel_rotation(sc, res, att, k)
            p, e = np.asarray(vr.position[k]) + Rv @ p0, Rv @ e0
        pts = pos[k, 1:-1]
        j = int(np.linalg.norm(pts - p[None, :], axis=1).argmin())   # nearest SDE
        past = j + np.flatnonzero((pts[j:] - p[None, :]) @ e > 0.0)   # downstream of the exit
        if len(past) < 2 or past[1] != past[0] + 1:
            out[k] = tension[k, min(j + 1, n - 1)]
            continue
        a, b = past[0], past[1]
        s_exit = s[a] - float((pts[a] - p) @ e)              # the pipe runs along the axis there
        out[k] = tension[k, a] + (tension[k, b] - tension[k, a]) * (s_exit - s[a]) / (s[b] - s[a])
    return out


def _axial_strain(sc: dict, lt: dict, pos: np.ndarray, tension: np.ndarray) -> np.ndarray:
    """(nt, nsde) axial strain of the pipe wall: the true wall tension
    T_w = T_e + p_i A_i - p_e A_e (T_e the effective tension of the SDEs) with the Lame
    stresses' Poisson contraction, eps_a = (T_w - 2 nu (p_i A_i - p_e A_e)) / EA (thick
    wall: sigma_h + sigma_r = 2 (p_i A_i - p_e A_e) / A through the wall). Hydrostatic
    pressures as the von Mises channel (rfesim.solvers.dynamics, docs/theory.md "Stresses"):
    p_e = rho_w g (surface - z) below the still-water surface, p_i = rho_c g (z_top - z) from
    the contents at rest, open at the line's highest point (a line type without a wall
    thickness: no internal pressure). A_e is the displaced (outer) area, A_i the bore.
    Elastic: the SDEs yield in bending only (rfesim.materials.sde_plastic), so for a
    yielded section this is the elastic part of the axial strain (the fibre section's
    axial strain at the same tension and curvature is larger)."""
    from .model.sections import section_from_type
    from .scenario.schema import LineType
    from .solvers.dynamics import hydrostatic_pressures
    ltm = LineType.model_validate(lt)
    sec = section_from_type(ltm)
    env = sc.get("environment") or {}
    water = env.get("water") or {}
    z = pos[:, 1:-1, 2]
    A_e = sec.displaced_area
    A_i = 0.0
    rho_c = 0.0
    if ltm.wall_thickness is not None and ltm.outer_diameter is not None:
        A_i = math.pi / 4.0 * (ltm.outer_diameter - 2.0 * ltm.wall_thickness) ** 2
        rho_c = ltm.contents_density
    p_e, p_i = hydrostatic_pressures(z, pos[:, :, 2].max(axis=1)[:, None], float(env.get("gravity", 9.81)),
                                     float(water.get("density", 1025.0)) if env.get("water") else 0.0,
                                     float(water.get("surface_level", 0.0)), rho_c)
    nu = ltm.poisson_ratio
    wall = tension + p_i * A_i - p_e * A_e
    return (wall - 2.0 * nu * (p_i * A_i - p_e * A_e)) / sec.EA


def _pick_line(sc: dict, res, line: str | None) -> str:
    if line is not None:
        res.line(line)
        return line
    laid = sorted({s.get("line") for s in (sc.get("supports") or {}).values() if s.get("line") in res.lines})
    if len(laid) != 1:
        raise ValueError(f"give the line: lines with supports: {laid or 'none'}")
    return laid[0]


def lay_summary(res, line: str | None = None, *, outer_diameter: float | None = None,
                t_from: float | None = None) -> dict:
    """Pipelay outputs of ``line`` (default: the one line with supports).

    ``outer_diameter``: steel diameter for the strains (default: the line type's
    steel_outer_diameter, which the pipelay templates set for a coated pipe, else its
    outer_diameter; give it for a coated pipe of your own line type without it).
    ``t_from``: range graphs and maxima from this time on (default: the whole run).

    Returns a dict: ``time`` (nt,); ``top_tension`` (nt,) N, the axial force at the top of
    the line: the force the most downstream tensioner (or collar) holds along its track (its
    grip force), or without one the component of the end-A force along the line's tangent
    there, ``end_a_force . end_a_direction`` (the axial tension; the clamp's shear is left
    out); a line stored on a reel: the line's tension at that tensioner's exit (the free
    span's, from the first two SDEs past the exit), which the reel's back tension and the
    tensioner hold together;
    ``departure_angle`` (nt,) deg below horizontal of the line just past the lift-off
    point, ``departure_arc_length`` (nt,) m; ``touchdown_position`` (nt, 3) m,
    ``touchdown_arc_length`` (nt,) m; ``sagbend_moment``, ``sagbend_curvature``,
    ``sagbend_strain``, ``overbend_moment``, ``overbend_curvature``, ``overbend_strain``
    (maxima over the run; sagbend: concave-up part between the lift-off point and the
    touchdown, overbend: concave down above the touchdown, on the stinger/aligner; the
    ``*_strain`` are bending only, kappa D / 2);
    ``sagbend_total_strain``, ``overbend_total_strain``: the largest outer-fibre strain
    magnitude, axial + bending, |eps_a| + kappa D / 2 (eps_a the wall's axial strain,
    ``_axial_strain``): the fibre on the tension side where the wall is in tension (eps_a >
    0, as on the overbend), the fibre on the compression side where it is compressed (eps_a <
    0: the deep sag bend, where the external pressure's Poisson term and the low effective
    tension put the wall in axial compression), which strain criteria such as DNV-ST-F101's
    (the overbend strain of its simplified laying criteria, the displacement-controlled
    local-buckling check on the compressive strain) take; ``sagbend_tensile_strain``,
    ``overbend_tensile_strain``: the tension-side fibre's largest strain, eps_a + kappa D / 2;
    ``sagbend_compressive_strain``, ``overbend_compressive_strain``: the compression-side
    fibre's largest compressive strain, kappa D / 2 - eps_a (a positive number; 0 when no
    fibre is in compression); ``roller_reactions`` {support: (nt, nroller) N};
    ``roller_reaction_max`` {support: (nroller,) N}; ``range_graphs`` {channel: {arc_length,
    min, max, mean}} for tension, bend_moment, curvature, bending_strain (kappa D / 2),
    axial_strain (eps_a), total_strain (|eps_a| + kappa D / 2), tensile_strain (eps_a + kappa
    D / 2), compressive_strain (kappa D / 2 - eps_a), position_z;
    ``residual_curvature`` (nsde,) 1/m at the last time, curvature - M/EI (the curvature
    left after elastic unloading; 0 for an elastic pipe up to round-off; for an elasto-plastic
    pipe the ``residual_curvature`` channel, from the plastic memory), and
    ``residual_curvature_max`` beyond the lift-off point."""
    sc = json.loads(res.scenario_json) if res.scenario_json else {}
    name = _pick_line(sc, res, line)
    lr = res.line(name)
    lt = sc["line_types"][sc["lines"][name]["type"]]
    D = float(outer_diameter or lt.get("steel_outer_diameter") or lt.get("outer_diameter") or 0.0)
    if lt.get("EIy") is not None:
        EI = float(lt["EIy"])
    else:
        Do, t = lt["outer_diameter"], lt["wall_thickness"]
        EI = lt["youngs_modulus"] * math.pi / 64.0 * (Do ** 4 - (Do - 2.0 * t) ** 4)
    time = np.asarray(res.time)
    nt = len(time)
    pos = np.asarray(lr.position)
    s_pts = np.asarray(lr.arc_length)
    s_sde = np.asarray(lr.sde_arc_length)
    keep = np.ones(nt, bool) if t_from is None else time >= t_from
    # lift-off: the most downstream support exit, followed with its vessel
    supports = {k: v for k, v in (sc.get("supports") or {}).items() if v.get("line") == name}
    dep_index = np.zeros(nt, int)
    for k in range(nt):
        best = 0
        for sup in supports.values():
            pts = _exit_points(sup)
            if pts.shape[0] == 0:
                continue
            att = sup.get("attach", "fixed")
            if att in res.vessels:
                vr = res.vessels[att]
                pts = np.asarray(vr.position[k]) + pts @ _vessel_rotation(sc, res, att, k).T
            d = np.linalg.norm(pos[k][None, :, :] - pts[:, None, :], axis=2)
            best = max(best, int(d.argmin(axis=1).max()))
        dep_index[k] = min(best, pos.shape[1] - 2)
    tangent = pos[np.arange(nt), dep_index + 1] - pos[np.arange(nt), dep_index]
    departure = np.degrees(np.arctan2(-tangent[:, 2], np.hypot(tangent[:, 0], tangent[:, 1])))
    # top tension: the most downstream tensioner's grip force; without one the axial force
    # at end A (along the end's tangent: a clamp's shear is not tension)
    top = np.einsum("ij,ij->i", np.asarray(lr.end_a_force, float), np.asarray(lr.end_a_direction, float))
    tens = [(n, s) for n, s in supports.items() if s.get("kind") == "tensioner" and n in res.tensioners]
    if tens:
        def exit_arc(item):
            p = _exit_points(item[1])[0]
            att = item[1].get("attach", "fixed")
            if att in res.vessels:
                vr = res.vessels[att]
                p = np.asarray(vr.position[0]) + _vessel_rotation(sc, res, att, 0) @ p
            return int(np.linalg.norm(pos[0] - p[None, :], axis=1).argmin())
        last = max(tens, key=exit_arc)
        top = np.asarray(res.tensioners[last[0]].grip_force, float)
        if any(s.get("kind") == "reel" for s in supports.values()):
            # reel-lay: the reel holds a back tension too; the top tension is the line's
            # tension at the tensioner's exit (the catenary's top)
            top = _tension_past(sc, res, lr, last[1], pos)
    # sagbend / overbend: sign of z'' along the line above the touchdown point
    moment = np.asarray(lr.bend_moment)
    curv = np.asarray(lr.curvature)
    td = np.asarray(lr.touchdown_arc_length) if lr.touchdown_arc_length is not None else np.full(nt, np.nan)
    try:
        axial = np.asarray(_axial_strain(sc, lt, pos, np.asarray(lr.tension, float)))
    except (ValueError, TypeError, KeyError, ZeroDivisionError):        # a section without EA: no axial strain
        axial = np.full(curv.shape, np.nan)
    bending = curv * 0.5 * D                     # curvature is a magnitude: the outer fibres at +-kappa D / 2
    fibres = {"total": np.abs(axial) + bending, "tensile": axial + bending, "compressive": bending - axial}
    out = {"sagbend_moment": 0.0, "sagbend_curvature": 0.0, "overbend_moment": 0.0, "overbend_curvature": 0.0,
           **{f"{part}_{f}_strain": 0.0 for part in ("sagbend", "overbend") for f in fibres}}
    for k in np.flatnonzero(keep):
        zpp = np.gradient(np.gradient(pos[k, :, 2], s_pts), s_pts)
        zpp_sde = np.interp(s_sde, s_pts, zpp)
        above = s_sde <= (td[k] if np.isfinite(td[k]) else s_sde[-1])
        # the sag bend hangs beyond the lift-off point: a pipe bent concave up on the reel,
        # ramp or straightener (reel-lay's plastic bends) is not the sag bend
        free = s_sde > s_pts[dep_index[k]]
        for part, mask in (("sagbend", above & free & (zpp_sde > 0.0)), ("overbend", above & (zpp_sde < 0.0))):
            if mask.any():
                out[f"{part}_moment"] = max(out[f"{part}_moment"], float(moment[k][mask].max()))
                out[f"{part}_curvature"] = max(out[f"{part}_curvature"], float(curv[k][mask].max()))
                for f, data in fibres.items():
                    key = f"{part}_{f}_strain"
                    out[key] = max(out[key], float(np.nanmax(data[k][mask], initial=0.0)))
    out["sagbend_strain"] = out["sagbend_curvature"] * 0.5 * D
    out["overbend_strain"] = out["overbend_curvature"] * 0.5 * D
    graphs = {ch: lr.range_graph(ch, t_from, time) for ch in ("tension", "bend_moment", "curvature", "position_z")}
    graphs["bending_strain"] = {"arc_length": graphs["curvature"]["arc_length"],
                                **{q: graphs["curvature"][q] * 0.5 * D for q in ("min", "max", "mean")}}
    rows = np.flatnonzero(keep)
    for name_, data in (("axial_strain", axial), *((f"{f}_strain", v) for f, v in fibres.items())):
        graphs[name_] = {"arc_length": graphs["curvature"]["arc_length"], "min": data[rows].min(axis=0),
                         "max": data[rows].max(axis=0), "mean": data[rows].mean(axis=0)}
    residual = curv[-1] - moment[-1] / EI
    if lr.residual_curvature is not None and (lt.get("material") or {}).get("kind") == "elastoplastic":
        residual = np.asarray(lr.residual_curvature)[-1]        # from the plastic memory (reverse yield too)
    beyond = s_sde > s_pts[dep_index[-1]]
    sup_res = {n: res.supports[n] for n in supports if n in res.supports}
    out.update(
        line=name, time=time, top_tension=top, departure_angle=departure, departure_arc_length=s_pts[dep_index],
        touchdown_position=np.asarray(lr.touchdown_position), touchdown_arc_length=td,
        roller_reactions={n: np.asarray(r.roller_reaction) for n, r in sup_res.items()},
        roller_reaction_max={n: np.asarray(r.roller_reaction)[keep].max(axis=0) for n, r in sup_res.items()},
        range_graphs=graphs, residual_curvature=residual,
        residual_curvature_max=float(np.abs(residual[beyond]).max()) if beyond.any() else 0.0)
    return out
