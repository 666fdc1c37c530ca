"""Crane outputs of a run (issue 5, item 6), for a crane made by the ``cranes`` templates
(rfesim.scenario.cranes): rope tension and its dynamic amplification factor, slack events
and snap loads, hook and payload motion, pedestal base forces and moments, slewing and
luffing torques, bending moments and axial forces along the boom / legs / pedestal /
crossbeam, cylinder forces, crane-tip motion and acceleration.

    sc = rfesim.load_scenario("scenarios/column_crane.json")
    res = rfesim.simulate(sc)
    out = crane_summary(res, "crane", **template_actuators(sc, "crane"))
    out["daf"], out["slack_events"], out["base_moment"], out["bend_moment_range"]

A table-driven luffing joint (angle, stroke or rope-length table) holds the boom or legs by
a moment at the hinge; with the template's cylinder (luffing rope) given, the member and base
loads are taken over to the real frame, the actuator pushing (pulling) at its eye
(:func:`crane_summary`, docs/theory.md 'Member loads of the real frame'); the results' own
line channels stay the model's.

The lines are found by the template's names (``<crane>_pedestal``, ``<crane>_boom``,
``<crane>_legs``, ``<crane>_rope``; the payload is the body on the rope's end B). The
static reference of the dynamic amplification factor is the first output sample (a run
starts from its statics) for a payload hanging from the rope; for a payload that starts on
a deck (``deck_force`` > 0 at the first sample: a lift-off), the first sample is the rope's
pull before the lift, part of the weight, and the reference is instead the static hook load
after lift-off, the weight in air of the payload and of the rope hanging below the first
rope SDE (:func:`hook_load_in_air`; the DAF of a lift applies to the static hook load, the
weight in air, as in DNV's lifting rules). ``static_tension`` overrides it.
"""
from __future__ import annotations

import math

import numpy as np


# the lines a crane template makes for its structure (rfesim.scenario.cranes), by the suffix
# of the crane's name; its hoist rope is ``<crane>_rope``
STRUCTURE_SUFFIXES = ("_pedestal", "_turret", "_boom", "_stub", "_stub_2", "_legs", "_legs_2", "_crossbeam",
                      "_crossbeam_2")


def crane_names(res) -> list[str]:
    """The cranes of a crane template in these results: ``<crane>`` with the lines
    ``<crane>_rope`` and ``<crane>_pedestal`` (column crane) or ``<crane>_legs`` (A-frame)."""
    return [line[:-len("_rope")] for line in res.lines
            if line.endswith("_rope") and any(line[:-len("_rope")] + s in res.lines for s in ("_pedestal", "_legs"))]


def structure_lines(res, crane: str) -> list[str]:
    """The lines of ``crane``'s structure (pedestal, turret, boom, A-frame stubs, legs and
    crossbeam) in these results: not the hoist rope."""
    return [crane + s for s in STRUCTURE_SUFFIXES if crane + s in res.lines]


def rope_tension(res, crane: str, static_tension: float | None = None) -> dict:
    """The hoist rope of ``crane``: ``rope_tension`` (nt,) N at the sheave (first rope SDE),
    ``hook_tension`` (nt,) N at the payload, ``static_tension`` N (the reference of the DAF,
    see :func:`crane_summary`), ``static_hook`` N (the payload's static load), ``daf`` and
    ``body`` (the payload's BodyResults, or None)."""
    rope = res.line(f"{crane}_rope")
    top = np.asarray(rope.tension, float)[:, 0]
    body = next((b for b in res.bodies.values() if getattr(b, "line", None) == f"{crane}_rope"), None)
    hook = np.asarray(body.tension, float) if body is not None else np.asarray(rope.tension, float)[:, -1]
    static, static_hook = float(top[0]), float(hook[0])
    deck = None if body is None else getattr(body, "deck_force", None)
    if body is not None and deck is not None and len(deck) and float(deck[0]) > 0.0 and res.scenario_json:
        # a lift-off: the first sample is the rope's pull with the deck carrying the rest of the
        # weight; the static reference is the hook load once the payload hangs in air
        static, static_hook = hook_load_in_air(res, f"{crane}_rope", body.name, int(np.argmax(top)))
    if static_tension is not None:
        static = float(static_tension)
    return {"rope_tension": top, "hook_tension": hook, "static_tension": static, "static_hook": static_hook,
            "daf": float(np.max(top) / static) if static > 0.0 else math.nan, "body": body}


def _member(res, crane: str) -> tuple[str, str]:
    """(structure line whose end A is the deck, the boom-like line carrying the drives)."""
    if f"{crane}_pedestal" in res.lines:
        return f"{crane}_pedestal", f"{crane}_boom"
    if f"{crane}_legs" in res.lines:
        return f"{crane}_stub", f"{crane}_legs"
    raise ValueError(f"no crane '{crane}' in these results (lines: {', '.join(sorted(res.lines))})")


def slack_events(time: np.ndarray, tension: np.ndarray, threshold: float, snap_window: float = 2.0, *,
                 min_taut: float = 0.05, blip_level: float | None = None) -> list[dict]:
    """Intervals where ``tension`` < ``threshold`` and the snap load that follows each:
    ``[{"start", "end", "snap_load", "snap_time", "blips"}]`` (s, s, N, s, -); ``end`` and
    the snap load are NaN for a rope still slack at the end of the run.

    A slack rope chatters: between two slack spells the tension can rise for an output
    sample or two without the rope being taut again. Such a taut *blip* does not end the
    event (the two spells are one event, ``blips`` counts the taut blips inside it): a taut
    interval that is short (a single output sample, or shorter than ``min_taut`` s, from
    its first taut sample to the next slack one) and low (its largest tension below
    ``blip_level`` N, default 50 times ``threshold``: half the reference tension when the
    threshold is 1 % of it, so a short snap above it still ends the event). The snap load
    is the largest tension from the end of the event for ``snap_window`` s, but not past
    the start of the next slack event."""
    time = np.asarray(time, float)
    tension = np.asarray(tension, float)
    level = 50.0 * threshold if blip_level is None else float(blip_level)
    slack = tension < threshold
    n = len(time)
    # slack spells [start, stop) of consecutive slack samples
    spells = []
    k = 0
    while k < n:
        if not slack[k]:
            k += 1
            continue
        start = k
        while k < n and slack[k]:
            k += 1
        spells.append([start, k, 0])
    # merge spells separated by a taut blip
    merged = []
    for sp in spells:
        if merged:
            prev = merged[-1]
            gap = slice(prev[1], sp[0])                 # the taut samples between the two spells
            short = sp[0] - prev[1] == 1 or time[sp[0]] - time[prev[1]] < min_taut
            if short and float(np.max(tension[gap])) < level:
                prev[1] = sp[1]
                prev[2] += 1 + sp[2]
                continue
        merged.append(sp)
    events = []
    for i, (start, stop, blips) in enumerate(merged):
        if stop >= n:
            events.append({"start": float(time[start]), "end": math.nan, "snap_load": math.nan,
                           "snap_time": math.nan, "blips": blips})
            break
        last = merged[i + 1][0] if i + 1 < len(merged) else n        # the next slack event's start
        window = np.arange(stop, last)
        window = window[time[window] <= time[stop] + snap_window]
        j = int(window[np.argmax(tension[window])])
        events.append({"start": float(time[start]), "end": float(time[stop]), "snap_load": float(tension[j]),
                       "snap_time": float(time[j]), "blips": blips})
    return events


def template_actuators(scenario, crane: str) -> dict:
    """:func:`crane_summary`'s ``cylinder``, ``luffing_rope`` and ``boom_length`` of ``crane``
    from the scenario that ran: a Scenario loaded from its ``cranes`` templates (the input it
    keeps) or that input as a dict; {} when it has no such crane (its results alone do not
    keep the template: the expanded scenario has none)."""
    source = scenario if isinstance(scenario, dict) else getattr(scenario, "_source", None)
    tpl = ((source or {}).get("cranes") or {}).get(crane) if isinstance(source, dict) else None
    if not isinstance(tpl, dict):
        return {}
    if isinstance(tpl.get("luffing_rope"), dict):        # it luffs the boom (a cylinder then has no stroke)
        return {"luffing_rope": tpl["luffing_rope"], "boom_length": (tpl.get("boom") or {}).get("length")}
    return {"cylinder": tpl["cylinder"]} if isinstance(tpl.get("cylinder"), dict) else {}


def structure_loads(res, scenario=None) -> dict:
    """{line: crane_summary's ``member_loads`` entry, with ``crane`` and ``of`` (its
    ``member_loads_of``)} over the structure lines of every crane template in these results
    (:func:`crane_names`): the real frame's where the ``scenario``
    (:func:`template_actuators`) gives the crane's luffing cylinder or rope, else the
    model's. What ``rfesim run`` / ``statics`` print and a sweep's ``max_bend_moment`` take
    for the lines of a crane's structure. {} for results without output times."""
    if not len(res.time):
        return {}
    out = {}
    for crane in crane_names(res):
        kw = template_actuators(scenario, crane) if scenario is not None else {}
        summary = crane_summary(res, crane, **kw)
        for line, loads in summary["member_loads"].items():
            out[line] = dict(loads, crane=crane, of=summary["member_loads_of"])
    return out


def _line_mass_per_length(lt: dict) -> float:
    """kg/m of a line type dict of the expanded scenario (direct or from the pipe geometry,
    as rfesim.scenario.schema.LineType)."""
    if lt.get("mass_per_length") is not None:
        return float(lt["mass_per_length"])
    D = float(lt["outer_diameter"])
    d = D - 2.0 * float(lt["wall_thickness"])
    return float(lt["density"]) * math.pi / 4.0 * (D * D - d * d) \
        + float(lt.get("contents_density") or 0.0) * math.pi / 4.0 * d * d


def hook_load_in_air(res, rope: str, body: str, k: int = 0) -> tuple[float, float]:
    """(at the sheave, at the hook) N: the static loads of the payload ``body`` hanging in air
    at rest on the line ``rope``: g (m + mu (L - Delta / 2)) at the first SDE (Delta / 2 below
    the sheave, where ``rope_tension`` is read) and g m at the body, with L the rope's
    suspended length at output sample k (its winch's ``suspended_length``, else the line's
    length) and Delta = L / n. From the expanded scenario kept with the results
    (``scenario_json``)."""
    import json
    sc = json.loads(res.scenario_json)
    g = float(sc["environment"].get("gravity", 9.81))
    line = sc["lines"][rope]
    mu = _line_mass_per_length(sc["line_types"][line["type"]])
    length = float(line["length"])
    for w in (getattr(res, "winches", None) or {}).values():
        if getattr(w, "line", None) == rope:
            length = float(np.asarray(w.suspended_length, float)[k])
    n = int(np.asarray(res.line(rope).tension).shape[1])
    mass = float(sc["bodies"][body]["mass"])
    return g * (mass + mu * (length - 0.5 * length / n)), g * mass


def _acceleration(time: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Second derivative of x(t) (nt, 3) by central differences (one-sided at the ends)."""
    if len(time) < 3:
        return np.full_like(x, np.nan)
    v = np.gradient(x, time, axis=0)
    return np.gradient(v, time, axis=0)


def cylinder_forces(torque: np.ndarray, angle_deg: np.ndarray, cylinder: dict, a_frame: bool) -> np.ndarray:
    """Force per cylinder (N, positive pushing) from the luffing drive torque (N*m, the joint's
    moment on the boom / legs about the drive axis, positive toward larger angles) and the
    drive angle history; ``cylinder``: the template's cylinder (base [x, z], eye, count)."""
    from .scenario.cranes import CylinderSpec, cylinder_lever
    cyl = CylinderSpec.model_validate(cylinder)
    out = np.empty(len(torque))
    for k, (m, a) in enumerate(zip(torque, angle_deg)):
        plane = math.radians(a)
        if a_frame:                       # template angle: tilt from vertical; plane angle 90 - tilt
            plane = 0.5 * math.pi - plane
            m = -m                        # the drive turns toward larger tilt = smaller plane angle
        _, lever = cylinder_lever(cyl, plane)
        # the cylinders put on the boom / legs the moment the driven joint does: F * lever * count = m
        out[k] = m / (lever * cyl.count) if abs(lever) > 1e-9 else math.nan
    return out


def luffing_rope_tensions(torque: np.ndarray, angle_deg: np.ndarray, luffing_rope: dict,
                          boom_length: float) -> np.ndarray:
    """Tension of the luffing rope (N, per part of line) from the luffing drive torque (N*m,
    the joint's moment on the boom about the drive axis, positive toward larger angles) and
    the boom angle history; ``luffing_rope``: the template's luffing_rope (gantry, eye,
    falls)."""
    from .scenario.cranes import LuffingRopeSpec, luffing_rope_lever
    spec = LuffingRopeSpec.model_validate({"length": [[0.0, 1.0]]} | dict(luffing_rope))
    eye = spec.eye if spec.eye is not None else boom_length
    out = np.empty(len(torque))
    for k, (m, a) in enumerate(zip(torque, angle_deg)):
        _, lever = luffing_rope_lever(spec, eye, math.radians(a))
        # the falls pulling toward the gantry put on the boom the moment the driven joint does
        out[k] = m / (lever * spec.falls) if abs(lever) > 1e-9 else math.nan
    return out


def _scenario(res) -> dict:
    """The expanded scenario kept with the results (``scenario_json``)."""
    import json
    return json.loads(res.scenario_json) if res.scenario_json else {}


def _unit(v: np.ndarray) -> np.ndarray:
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0.0, n, 1.0)


def _perpendicular(m: np.ndarray, t: np.ndarray) -> np.ndarray:
    """|m - (m . t) t|: the bending part of the moments m (..., 3) about the unit axes t."""
    return np.linalg.norm(m - np.sum(m * t, axis=-1, keepdims=True) * t, axis=-1)


def _point_at(line, s: float) -> np.ndarray:
    """(nt, 3) the point at arc length ``s`` from end A of a line's results (linear between
    its points: end A, the SDEs, end B)."""
    arc = np.asarray(line.arc_length, float)
    pos = np.asarray(line.position, float)
    k = int(np.clip(np.searchsorted(arc, s) - 1, 0, len(arc) - 2))
    w = (s - arc[k]) / (arc[k + 1] - arc[k])
    return (1.0 - w) * pos[:, k] + w * pos[:, k + 1]


def section_loads(res, line: str, point_loads=(), at=()) -> dict:
    """Internal loads at every SDE of ``line`` of a run's results, rebuilt from the line's
    end-A loads (``end_a_force``, ``end_a_moment``: what the line beyond puts on its end-A
    attachment) and the weight and inertia of its RFEs between end A and the SDE (their
    centres' accelerations from second differences of the output samples; zero for one
    sample, statics). Returns ``point``, ``tangent``, ``force``, ``moment`` (nt, nsde, 3): the
    SDE point, the line's unit tangent there, and the force and moment (about the SDE point,
    global) of the part beyond the SDE (toward end B) on the part before it, so that the
    axial force (tension positive) is force . tangent and the bending moment is the moment's
    part normal to the tangent; with ``at`` (arc lengths from end A), also ``at_point``,
    ``at_tangent``, ``at_moment`` (nt, len(at), 3) at those points of the line (the RFEs whose
    centres lie before each counted before it). ``point_loads``: further loads on RFEs, (rfe
    index, point (nt, 3), force (nt, 3)). Left out: the RFEs' rotary inertia and any sea load
    on them (the crane's members are in air); :func:`crane_summary` checks the rebuilt
    moments against the model's own (``member_loads_residual``)."""
    sc = _scenario(res)
    g = float((sc.get("environment") or {}).get("gravity", 9.81))
    lr = res.line(line)
    mu = _line_mass_per_length(sc["line_types"][sc["lines"][line]["type"]])
    time = np.asarray(res.time, float)
    arc = np.asarray(lr.arc_length, float)
    pts = np.asarray(lr.position, float)                 # (nt, nsde + 2, 3): end A, the SDEs, end B
    mass = mu * np.diff(arc)                             # the RFEs between consecutive points
    centre = 0.5 * (pts[:, :-1] + pts[:, 1:])
    if len(time) >= 3:
        acc = np.gradient(np.gradient(centre, time, axis=0), time, axis=0)
    else:
        acc = np.zeros_like(centre)
    f = mass[None, :, None] * (np.array([0.0, 0.0, -g]) - acc)     # weight and d'Alembert force per RFE
    mo = np.cross(centre, f)                                         # their moments about the origin
    for rfe, point, force in point_loads:
        f[:, rfe] += force
        mo[:, rfe] += np.cross(point, force)
    sum_f = np.concatenate([np.zeros_like(f[:, :1]), np.cumsum(f, axis=1)], axis=1)   # over the first k RFEs
    sum_m = np.concatenate([np.zeros_like(mo[:, :1]), np.cumsum(mo, axis=1)], axis=1)
    FA = np.asarray(lr.end_a_force, float)[:, None, :]
    MA = np.asarray(lr.end_a_moment, float)[:, None, :]
    rA = pts[:, :1]

    def loads(r, k):
        # at the points r (nt, m, 3), past the first k (m,) RFEs
        sf, sm = sum_f[:, k], sum_m[:, k]
        return FA - sf, MA + np.cross(rA - r, FA) - (sm - np.cross(r, sf))

    n = pts.shape[1] - 2
    r = pts[:, 1:-1]
    force, moment = loads(r, np.arange(1, n + 1))
    rfe = _unit(np.diff(pts, axis=1))                    # the RFEs' axes; an SDE's, their mean
    out = {"point": r, "tangent": _unit(rfe[:, :-1] + rfe[:, 1:]), "force": force, "moment": moment}
    if len(at):
        at = np.asarray(at, float)
        mid = 0.5 * (arc[:-1] + arc[1:])
        k = np.searchsorted(mid, at)                     # RFEs whose centres lie before
        seg = np.clip(np.searchsorted(arc, at) - 1, 0, len(arc) - 2)
        w = ((at - arc[seg]) / (arc[seg + 1] - arc[seg]))[None, :, None]
        p = (1.0 - w) * pts[:, seg] + w * pts[:, seg + 1]
        out["at_point"] = p
        out["at_tangent"] = _unit(pts[:, seg + 1] - pts[:, seg])
        out["at_moment"] = loads(p, k)[1]
    return out


def _vessel_rotation(res, sc: dict, vessel: str) -> np.ndarray:
    """(nt, 3, 3) the vessel's rotation R = R_heading Rz(yaw) Ry(pitch) Rx(roll) at the output
    samples (rfesim.vessel; identity motion for a vessel without results)."""
    from .kinematics import rot_zyx
    nt = len(res.time)
    h = math.radians(float(((sc.get("vessels") or {}).get(vessel) or {}).get("heading_deg") or 0.0))
    v = (getattr(res, "vessels", None) or {}).get(vessel)
    rot = np.radians(np.asarray(v.rotation, float)) if v is not None else np.zeros((nt, 3))
    Rh = rot_zyx(h, 0.0, 0.0)
    return np.stack([Rh @ rot_zyx(y, p, r) for r, p, y in rot])


def _luffing_plane(res, sc: dict, crane: str, member: str, a_frame: bool) -> tuple:
    """(hinge, x, z) (nt, 3) each: the luffing joint of ``member`` (boom or leg) and the unit
    axes of its luffing plane, in which cylinder.base and luffing_rope.gantry are given: z the
    column's axis at its top (column crane: the pedestal's or turret's end-B direction) or the
    deck's normal (A-frame), x toward the outreach (column: the boom's foot direction with its
    z part taken out; A-frame: outboard, the luffing axis turned with the deck, cross z)."""
    line = res.line(member)
    hinge = np.asarray(line.position, float)[:, 0]
    if not a_frame:
        parent = res.line(f"{crane}_turret" if f"{crane}_turret" in res.lines else f"{crane}_pedestal")
        z = _unit(np.asarray(parent.end_b_direction, float))
        d = np.asarray(line.end_a_direction, float)
        return hinge, _unit(d - np.sum(d * z, axis=-1, keepdims=True) * z), z
    spec = sc["lines"][member]["end_a"]
    drive = next(d for d in spec.get("drives") or [] if d["name"] == "luffing")
    stub = sc["lines"][spec["attach"].split(":")[0]]
    R = _vessel_rotation(res, sc, stub["end_a"]["attach"])
    # the drive's axis is global at t = 0 (the first output sample), fixed in the deck
    axis = R @ (R[0].T @ np.asarray(drive["axis"], float))
    z = R[:, :, 2]
    return hinge, _unit(np.cross(axis, z)), z


def _actuators(res, crane: str, out: dict, cylinder: dict | None, luffing_rope: dict | None,
               boom_length: float | None) -> list[dict]:
    """The luffing cylinders or rope of a table-driven crane as the real frame has them, per
    boom or leg: ``member`` (its line), ``eye`` (its arc length from the hinge), ``eye_point``
    (nt, 3: where the drive angle puts it on the straight member, as the template's triangle
    hinge - base - eye has it), ``force`` (nt, 3) on the member at the eye (all its
    cylinders' push along base -> eye, or the falls' pull toward the gantry, of the size that
    leaves the hinge no moment about the luffing axis: the joint's moment over the lever, count
    times ``cylinder_force`` or falls times ``luffing_rope_tension``), ``hinge`` (nt, 3),
    ``low`` (m below the hinge, along the column, of its other end: cylinder.base or
    luffing_rope.gantry z, negated), ``on_deck`` (that end on the deck: an A-frame's cylinder
    base, a column crane's at or below its pedestal's foot) and ``leg`` (0, or 1 for the
    portal's second leg). Empty for a force-driven crane, one without a luffing drive, or
    one without the actuator given."""
    if "luffing" not in out["drive_torque"] or (cylinder is None and luffing_rope is None):
        return []
    if cylinder is not None and luffing_rope is not None:
        raise ValueError("give the luffing cylinder or the luffing rope, not both")
    sc = _scenario(res)
    a_frame = f"{crane}_legs" in res.lines
    portal = f"{crane}_legs_2" in res.lines
    members = [f"{crane}_legs", f"{crane}_legs_2"] if portal else [f"{crane}_legs" if a_frame else f"{crane}_boom"]
    acts = []
    for j, member in enumerate(members):
        hinge, x, z = _luffing_plane(res, sc, crane, member, a_frame)
        line = res.line(member)
        if cylinder is not None:
            from .scenario.cranes import CylinderSpec
            spec = CylinderSpec.model_validate({k: v for k, v in cylinder.items() if k != "force"})
            (bx, bz), eye = spec.base, spec.eye
        else:
            from .scenario.cranes import LuffingRopeSpec
            spec = LuffingRopeSpec.model_validate({"length": [[0.0, 1.0]]} | dict(luffing_rope))
            (bx, bz), eye = spec.gantry, (spec.eye if spec.eye is not None else float(boom_length))
        # the eye where the drive's angle puts it on the straight member: the real frame's, whose
        # cylinder (rope) length sets the triangle hinge - base - eye (the model's member bends
        # under the joint's moment between the hinge and the eye, the real one far less)
        angle = np.radians(np.asarray(line.drive_angle, float)[:, list(line.drive_names).index("luffing")])
        if a_frame:                     # the template's angle is the tilt from the vertical
            angle = 0.5 * math.pi - angle
        eye_point = hinge + eye * (np.cos(angle)[:, None] * x + np.sin(angle)[:, None] * z)
        u = _unit(eye_point - (hinge + bx * x + bz * z))        # along the actuator, toward the eye
        # its size: the real hinge carries no moment about the luffing axis, F l = M with l the
        # lever of that line about the hinge and M the joint's moment (the drive torque)
        axis = _unit(np.cross(z, x))
        lever = np.sum(np.cross(eye_point - hinge, u) * axis, axis=-1)
        held = np.sum(np.asarray(line.end_a_moment, float) * axis, axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            size = np.where(np.abs(lever) > 1e-9 * eye, -held / lever, np.nan)
        column_top = 0.0 if a_frame else sum(float(np.asarray(res.line(n).arc_length)[-1])
                                             for n in (f"{crane}_pedestal", f"{crane}_turret") if n in res.lines)
        force = size[:, None] * u
        acts.append({"member": member, "eye": eye, "eye_point": eye_point, "force": force, "hinge": hinge,
                     "low": -bz, "on_deck": a_frame or -bz >= column_top, "leg": j})
    return acts


def _member_loads(res, crane: str, acts: list[dict]) -> tuple[dict, float]:
    """{line: {arc_length (n,), bend_moment (nt, n), sde_arc_length (nsde,), axial_force,
    shear_force, torque (nt, nsde), end_a_force, end_b_force (nt, 3)}} of every line of the
    crane's structure: the bending moment at end A, every SDE, an actuator's eye on the line
    and end B (the ends from the line's end moments, a closing line's onto its end B
    included), the axial force (tension positive), the shear force's size and the torque at
    the SDEs and the line's end forces (as LineResults'); with the actuators
    (:func:`_actuators`) those of the real frame: where a section lies between the
    actuator's two ends (a boom's or leg's section below the eye; a deck stub's, or a
    pedestal's above the cylinder base), its force F at the eye acts on the part beyond the
    section, adding F and (eye - section) x F to the internal loads the model has (the
    moment-driven joint carries them instead), the boom's or leg's sections taken on the
    straight line from the hinge to the eye, F's part along the member along it and its
    normal part added to the model's shear vector (the real frame's member does not bend there
    as the model's does under the joint's moment). Also
    the largest difference between the model's bending moment and the one rebuilt from the
    end-A loads (section_loads) over the corrected SDEs, relative to the model's largest on
    that line (0 when nothing is corrected)."""
    sc = _scenario(res)
    lines = structure_lines(res, crane)
    # the sections each actuator spans, by line: (actuator, first and last arc length of the
    # span on the line, the arc length from the hinge of the line's end A for a boom's or leg's
    # sections below the eye, else None)
    spans: dict[str, list] = {name: [] for name in lines}
    for act in acts:
        member = act["member"]
        suffix = "_2" if member.endswith("_2") else ""
        length = float(np.asarray(res.line(member).arc_length)[-1])
        spans[member].append((act, -np.inf, act["eye"], 0.0))
        beam = f"{crane}_crossbeam"
        if act["eye"] > length and beam in spans and not suffix and f"{crane}_legs_2" not in res.lines:
            spans[beam].append((act, -np.inf, act["eye"] - length, length))
        if act.get("eye_only"):
            continue
        if member.endswith(("_legs", "_legs_2")):
            spans[f"{crane}_stub{suffix}"].append((act, -np.inf, np.inf, None))
        else:
            top = 0.0
            for name in (f"{crane}_pedestal", f"{crane}_turret"):
                if name in spans:
                    top += float(np.asarray(res.line(name).arc_length)[-1])
            below = 0.0
            for name in (f"{crane}_pedestal", f"{crane}_turret"):
                if name in spans:
                    if act["low"] > 0.0:            # the cylinder base / gantry on the column below the hinge
                        spans[name].append((act, top - act["low"] - below, np.inf, None))
                    below += float(np.asarray(res.line(name).arc_length)[-1])

    def on_chord(act, chord, arcs, points):
        # sections of a boom or leg below its eye taken on the straight line from the hinge to
        # the eye (``chord``: the arc length from the hinge of this line's end A; arcs: theirs on
        # this line); ``points`` (the deformed ones) elsewhere
        if chord is None:
            return points
        hinge, eye = act["hinge"], act["eye_point"]
        return hinge[:, None] + ((chord + np.asarray(arcs, float)) / act["eye"])[None, :, None] * (eye - hinge)[:, None]

    closing = {name: [n for n, spec in (sc.get("lines") or {}).items()
                      if (spec.get("end_b") or {}).get("attach") == f"{name}:end_b"] for name in lines}
    out, residual = {}, 0.0
    for name in lines:
        lr = res.line(name)
        arc = np.asarray(lr.arc_length, float)
        s = np.asarray(lr.sde_arc_length, float)
        pts = np.asarray(lr.position, float)
        bend = np.asarray(lr.bend_moment, float)
        axial = np.asarray(lr.tension, float).copy()
        end_a = np.asarray(lr.end_a_moment, float).copy()
        end_b = -np.asarray(lr.end_b_moment, float) + sum(np.asarray(res.line(c).end_b_moment, float)
                                                          for c in closing[name])
        inner, sections = bend.copy(), s
        shear = np.asarray(lr.shear_force, float).copy()
        torque = np.asarray(lr.torque, float).copy()
        force_a = np.asarray(lr.end_a_force, float).copy()
        force_b = np.asarray(lr.end_b_force, float).copy()
        if spans[name]:
            # an actuator's eye on this line: a section there, where the real frame's moment peaks
            eyes = [hi for _, _, hi, _ in spans[name] if arc[0] < hi < arc[-1]]
            rebuilt = section_loads(res, name, _reeving_loads(res, sc, name), at=eyes)
            M = rebuilt["moment"]
            model = _perpendicular(M, rebuilt["tangent"])
            # the model's shear vector, normal to its SDE's tangent; F's part normal to the member
            # is added to it below
            T = rebuilt["tangent"]
            V = rebuilt["force"] - np.sum(rebuilt["force"] * T, axis=-1)[..., None] * T
            touched = np.zeros(len(s), bool)
            for act, lo, hi, chord in spans[name]:
                if act.get("eye_only"):
                    continue
                F, eye = act["force"], act["eye_point"]
                sel = (s >= lo) & (s < hi)
                touched |= sel
                arm = eye[:, None] - on_chord(act, chord, s[sel], rebuilt["point"][:, sel])
                moment = np.cross(arm, F[:, None])
                M[:, sel] += moment
                along = rebuilt["tangent"][:, sel] if chord is None else \
                    _unit(act["eye_point"] - act["hinge"])[:, None]
                part = np.sum(F[:, None] * along, axis=-1)
                axial[:, sel] += part
                V[:, sel] += F[:, None] - part[..., None] * along
                # about the member's axis (on the chord, the arm lies along it: nothing)
                torque[:, sel] += np.sum(moment * along, axis=-1)
                if lo <= arc[0] < hi:
                    end_a += np.cross(eye - on_chord(act, chord, arc[:1], pts[:, :1])[:, 0], F)
                    force_a += F
                if lo <= arc[-1] < hi:
                    end_b += np.cross(eye - on_chord(act, chord, arc[-1:], pts[:, -1:])[:, 0], F)
                    force_b -= F
            inner[:, touched] = _perpendicular(M[:, touched], rebuilt["tangent"][:, touched])
            shear[:, touched] = np.linalg.norm(V[:, touched], axis=-1)
            if touched.any():
                scale = max(float(np.max(np.abs(bend))), 1e-300)
                residual = max(residual, float(np.max(np.abs(model[:, touched] - bend[:, touched]))) / scale)
            if eyes:
                # the moment at the eye itself: the force there has no arm about it
                k = np.searchsorted(s, eyes)
                sections = np.insert(s, k, eyes)
                inner = np.insert(inner, k, _perpendicular(rebuilt["at_moment"], rebuilt["at_tangent"]), axis=1)
        moment = np.concatenate([_perpendicular(end_a, np.asarray(lr.end_a_direction, float))[:, None], inner,
                                 _perpendicular(end_b, np.asarray(lr.end_b_direction, float))[:, None]], axis=1)
        out[name] = {"arc_length": np.concatenate([[arc[0]], sections, [arc[-1]]]), "bend_moment": moment,
                     "sde_arc_length": s, "axial_force": axial, "shear_force": shear, "torque": torque,
                     "end_a_force": force_a, "end_b_force": force_b}
    return out, residual


def _reeving_loads(res, sc: dict, name: str) -> list:
    """The pull of a hoist rope led along ``name`` to its foot (``reeving: "boom"``,
    rfesim.loads.reeving): the rope tension at the sheave along the run from the lead (the
    line's end A) to the sheave, on the line's first RFE at its end A; [] otherwise."""
    loads = []
    for rope, spec in (sc.get("lines") or {}).items():
        lead = ((spec.get("end_a") or {}).get("reeving") or {}).get("lead")
        if lead == f"{name}:end_a" and rope in res.lines:
            rl = res.line(rope)
            tension = np.linalg.norm(np.asarray(rl.end_a_force, float), axis=-1)
            foot = np.asarray(res.line(name).position, float)[:, 0]
            sheave = np.asarray(rl.position, float)[:, 0]
            loads.append((0, foot, tension[:, None] * _unit(sheave - foot)))
    return loads


def _range(arc: np.ndarray, data: np.ndarray) -> dict:
    return {"arc_length": arc, "min": np.nanmin(data, axis=0), "max": np.nanmax(data, axis=0),
            "mean": np.nanmean(data, axis=0)}


def crane_summary(res, crane: str, *, static_tension: float | None = None, slack_fraction: float = 0.01,
                  cylinder: dict | None = None, luffing_rope: dict | None = None,
                  boom_length: float | None = None) -> dict:
    """Crane outputs of ``crane`` (the name of its template). Returns a dict:

    ``time``; ``rope_tension`` (nt,) N at the sheave (first rope SDE) and ``hook_tension``
    (nt,) N at the payload; ``static_tension`` N and ``daf`` = max / static of the tension
    at the sheave (the static tension: the first sample, a run starting from its statics with
    the payload hanging; for a payload that starts on a deck, ``deck_force`` > 0 at the first
    sample, the hook load in air once lifted, :func:`hook_load_in_air` at the sample of the
    largest tension; ``static_tension`` overrides both); ``slack_events`` (tension at the
    payload below ``slack_fraction`` of its static one, the first sample or, from a deck, the
    payload's weight in air; a taut blip shorter than 0.05 s or one sample and below half that
    static tension does not end an event; see :func:`slack_events`) and ``snap_load_max`` N;
    ``payload_position``, ``payload_velocity``, ``payload_acceleration`` (nt, 3);
    ``tip_position``, ``tip_acceleration`` (nt, 3): the sheave; ``drive_angle``/``drive_torque``
    {name: (nt,)} (slewing, luffing); ``cylinder_force`` (nt,) N per cylinder, pushing positive
    (with ``cylinder``, the template's cylinder dict; the portal A-frame: the mean of its legs',
    each leg carrying half the cylinders, and ``cylinder_force_legs`` (nt, 2); force-driven
    A-frame cylinders: their set force, with ``cylinder_length`` (nt,) m and the tilt
    ``drive_angle["luffing"]`` from that length); ``luffing_rope_tension`` (nt,) N per part of
    line (with ``luffing_rope``, the template's luffing_rope dict, and ``boom_length`` when its
    eye is not given).

    Member and base loads, of the real frame (``member_loads_of`` "real frame") when the
    luffing is force-driven (``cylinder.force``: the model is the real frame) or a table
    drives it (angle, stroke or rope length) and ``cylinder`` or ``luffing_rope`` is given:
    the model's luffing joint carries the drive's moment at the hinge, the real frame's
    cylinders (rope) push (pull) at their eye, so the loads between the hinge and the eye,
    and those the deck takes, are taken over to the real frame (:func:`template_actuators`
    reads the actuator from the scenario; docs/theory.md, 'Member loads of the real frame').
    Without the actuator (``member_loads_of`` "model") they are the model's, whose luffing
    joint carries the moment. ``member_loads`` {line: {arc_length (n,), bend_moment (nt, n),
    sde_arc_length (nsde,), axial_force, shear_force, torque (nt, nsde), end_a_force,
    end_b_force (nt, 3)}} for every line of the structure (pedestal, turret, boom, A-frame
    stubs, legs, crossbeam): the bending moment N*m at end A, the SDEs, the actuator's eye
    (boom, legs) and end B, the axial force N (tension positive), the shear force N (its
    size) and the torque N*m (the moment about the member's axis, as the results' ``torque``)
    at the SDEs; ``bend_moment_range``, ``axial_force_range``, ``shear_force_range`` and
    ``torque_range`` {line: {arc_length, min, max, mean}} of them over time;
    ``member_loads_residual``: the largest difference, relative to the line's largest, between
    the model's bending moment and the one rebuilt from the line's end loads, weights and
    inertia that the correction adds to (section_loads; a check: 1e-8 in statics, 3e-3 in
    the column crane's waves at 0.1 s output samples); ``legs_per_line``: 2 for the
    equivalent A-frame (no ``crossbeam``), whose ``<c>_legs``, ``<c>_stub`` and
    ``<c>_crossbeam`` stand for both legs (their moments and forces are the sums of the two),
    else 1. ``base_force``, ``base_moment`` (nt, 3) N, N*m: the loads of the crane on the deck
    through its pedestal's foot (column crane; the moment about it), or its hinges (A-frame:
    the moment about the hinge, transferred from the deck stub's foot 1 m below it with the
    force; the portal A-frame: both legs', the moment about the point between their hinges,
    the template's ``position``, and ``base_force_legs`` (nt, 2, 3) per leg), without what an
    actuator with its other end on the deck puts there itself: ``cylinder_deck_force``,
    ``cylinder_deck_moment`` (nt, 3) N, N*m, the force of all the A-frame's cylinders on the
    deck at their bases and its moment about the point ``base_moment`` is taken about (a
    column crane's only when its cylinder base is at or below the pedestal's foot; on the
    pedestal it is inside the crane), so that base and cylinders together are all the crane
    puts on the deck."""
    base_line, boom_line = _member(res, crane)
    time = np.asarray(res.time, float)
    loads = rope_tension(res, crane, static_tension)
    top, hook, body = loads["rope_tension"], loads["hook_tension"], loads["body"]
    static, static_hook = loads["static_tension"], loads["static_hook"]
    events = slack_events(time, hook, slack_fraction * static_hook, blip_level=0.5 * static_hook)
    snaps = [e["snap_load"] for e in events if np.isfinite(e["snap_load"])]
    base = res.line(base_line)
    boom = res.line(boom_line)
    tip_line = res.line(f"{crane}_crossbeam") if f"{crane}_crossbeam" in res.lines else boom
    tip = np.asarray(tip_line.position, float)[:, -1, :]
    portal = f"{crane}_legs_2" in res.lines          # the closed-portal A-frame (rfesim.scenario.cranes)
    out = {
        "time": time, "rope_tension": top, "hook_tension": hook, "static_tension": static,
        "daf": loads["daf"],
        "slack_events": events, "snap_load_max": float(max(snaps)) if snaps else math.nan,
        "tip_position": tip, "tip_acceleration": _acceleration(time, tip),
        "drive_angle": {}, "drive_torque": {},
        "legs_per_line": 2 if boom_line.endswith("_legs") and not portal else 1,
    }
    if body is not None:
        out.update(payload_position=np.asarray(body.position, float),
                   payload_velocity=np.asarray(body.velocity, float),
                   payload_acceleration=np.asarray(body.acceleration, float))
    # the boom's joint drives, and a slewing motor's turret (rfesim.scenario.cranes.SlewingMotor)
    for lname in (f"{crane}_turret", boom_line):
        if lname not in res.lines:
            continue
        line = res.line(lname)
        angle = getattr(line, "drive_angle", None)
        torque = getattr(line, "drive_torque", None)
        if angle is None or torque is None:
            continue
        for j, dname in enumerate(line.drive_names):
            out["drive_angle"][dname] = np.asarray(angle, float)[:, j]
            out["drive_torque"][dname] = np.asarray(torque, float)[:, j]
    cyl_tugger = res.tuggers.get(f"{crane}_cylinder") if getattr(res, "tuggers", None) else None
    if cylinder is not None and cylinder.get("force") is not None and cyl_tugger is not None:
        # force-driven A-frame cylinders (rfesim.scenario.cranes): their set force, their length,
        # and the tilt that length gives through the triangle hinge - base - eye
        from .scenario.cranes import CylinderSpec, cylinder_angle
        cyl = CylinderSpec.model_validate({k: v for k, v in cylinder.items() if k != "force"})
        length = np.asarray(cyl_tugger.length, float)
        push = -np.asarray(cyl_tugger.tension, float)
        if portal:                       # each leg's tugger carries half the cylinders
            push_2 = -np.asarray(res.tuggers[f"{crane}_cylinder_2"].tension, float)
            out["cylinder_force_legs"] = np.stack([2.0 * push, 2.0 * push_2], axis=1) / cyl.count
            push = push + push_2
        out["cylinder_force"] = push / cyl.count
        out["cylinder_length"] = length
        tilt = np.full(len(length), math.nan)
        for k, L in enumerate(length):
            try:
                tilt[k] = 90.0 - math.degrees(cylinder_angle(cyl, float(L), (math.radians(10.0),
                                                                            math.radians(170.0))))
            except ValueError:
                pass                    # beyond the triangle: left NaN
        out["drive_angle"]["luffing"] = tilt
    elif cylinder is not None and "luffing" in out["drive_torque"]:
        a_frame = boom_line.endswith("_legs")
        ang = out["drive_angle"]["luffing"]
        torque = out["drive_torque"]["luffing"]
        if portal:                       # each leg's drive stands for half the cylinders
            leg2 = res.line(f"{crane}_legs_2")
            torque_2 = np.asarray(leg2.drive_torque, float)[:, list(leg2.drive_names).index("luffing")]
            out["cylinder_force_legs"] = np.stack([2.0 * cylinder_forces(torque, ang, cylinder, a_frame),
                                                   2.0 * cylinder_forces(torque_2, ang, cylinder, a_frame)], axis=1)
            torque = torque + torque_2
        out["cylinder_force"] = cylinder_forces(torque, ang, cylinder, a_frame)
    if luffing_rope is not None and "luffing" in out["drive_torque"]:
        if luffing_rope.get("eye") is None and boom_length is None:
            raise ValueError("luffing_rope without an eye needs boom_length (the eye is at the tip)")
        out["luffing_rope_tension"] = luffing_rope_tensions(out["drive_torque"]["luffing"],
                                                            out["drive_angle"]["luffing"], luffing_rope,
                                                            float(boom_length or 0.0))
    # the member loads of the real frame: the luffing cylinders (rope) at their eye, not the
    # moment-driven joint of the model (docs/theory.md, 'Member loads of the real frame')
    acts = _actuators(res, crane, out, None if cyl_tugger is not None else cylinder, luffing_rope, boom_length)
    if cyl_tugger is not None:
        # force-driven cylinders: the model is the real frame; a section at their eye
        legs_length = float(np.asarray(boom.arc_length)[-1])
        for suffix in ("", "_2") if portal else ("",):
            tug = res.tuggers[f"{crane}_cylinder{suffix}"]
            member = f"{crane}_legs{suffix}"
            acts.append({"member": member, "eye": tug.at + (0.0 if tug.line == member else legs_length),
                         "eye_only": True, "on_deck": False})
    members, residual = _member_loads(res, crane, acts)
    out["member_loads"] = members
    out["member_loads_of"] = "real frame" if acts else "model"
    out["member_loads_residual"] = residual
    out["bend_moment_range"] = {n: _range(m["arc_length"], m["bend_moment"]) for n, m in members.items()}
    for key in ("axial_force", "shear_force", "torque"):
        out[f"{key}_range"] = {n: _range(m["sde_arc_length"], m[key]) for n, m in members.items()}
    # base loads: through the pedestal's foot, or an A-frame's hinges (the deck stubs' feet, the
    # moment about the hinge, or the point between the portal's hinges); an actuator whose other
    # end is on the deck puts its own reaction there (``cylinder_deck_force``), not through them
    base_force = np.asarray(base.end_a_force, float).copy()
    base_moment = np.asarray(base.end_a_moment, float).copy()
    reference = np.asarray(base.position, float)[:, 0]           # the pedestal's foot
    deck = [(a["leg"], a["eye_point"], a["force"]) for a in acts if a["on_deck"]]
    if cyl_tugger is not None:
        # force-driven cylinders: the model's hinges are the real ones already; their deck ends
        for j, suffix in enumerate(("", "_2") if portal else ("",)):
            tug = res.tuggers[f"{crane}_cylinder{suffix}"]
            deck.append((j, _point_at(res.line(tug.line), tug.at), np.asarray(tug.force, float)))
    if base_line.endswith("_stub"):
        # the stub under each hinge is clamped 1 m below it (rfesim.scenario.cranes._a_frame_leg):
        # M_hinge = M_foot + (foot - hinge) x F, the stub's foot would add the horizontal force
        # times the stub's 1 m
        stubs = [base, res.line(f"{crane}_stub_2")] if portal else [base]
        feet = [np.asarray(st.position, float)[:, 0, :] for st in stubs]
        hinges = [np.asarray(st.position, float)[:, -1, :] for st in stubs]
        reference = sum(hinges) / len(hinges)
        forces = [np.asarray(st.end_a_force, float).copy() for st in stubs]
        moments = [np.asarray(st.end_a_moment, float) + np.cross(f - reference, F)
                   for st, f, F in zip(stubs, feet, forces)]
        for j, eye, force in deck:
            if cyl_tugger is None:          # the model's deck stub took the cylinders' reaction too
                forces[j] = forces[j] + force
                moments[j] = moments[j] + np.cross(eye - reference, force)
        base_force, base_moment = sum(forces), sum(moments)
        if portal:
            out["base_force_legs"] = np.stack(forces, axis=1)
    else:
        for _, eye, force in deck:
            base_force += force
            base_moment += np.cross(eye - reference, force)
    if deck:
        # the cylinders' push on the deck at their bases (along their line: its moment is the
        # eye's), about the point the base moment is taken about
        out["cylinder_deck_force"] = -sum(force for _, _, force in deck)
        out["cylinder_deck_moment"] = -sum(np.cross(eye - reference, force) for _, eye, force in deck)
    out["base_force"], out["base_moment"] = base_force, base_moment
    return out
