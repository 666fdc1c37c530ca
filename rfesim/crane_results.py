"""Crane outputs of a run (issue 5, item 6), for a crane made by the ``cranes`` templates
(rfesim.scenario.cranes): rope tension and its dynamic amplification factor, slack events
and snap loads, hook and payload motion, pedestal base forces and moments, slewing and
luffing torques, bending moments along the boom / legs, cylinder forces, crane-tip
motion and acceleration.

    res = rfesim.simulate("scenarios/column_crane.json")
    out = crane_summary(res, "crane")
    out["daf"], out["slack_events"], out["base_moment"]

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


def slack_events(time: np.ndarray, tension: np.ndarray, threshold: float, snap_window: float = 2.0) -> list[dict]:
    """Intervals where ``tension`` < ``threshold`` and the snap load that follows each:
    ``[{"start", "end", "snap_load", "snap_time"}]`` (s, s, N, s); ``end`` and the snap load
    are NaN for a rope still slack at the end of the run. The snap load is the largest
    tension within ``snap_window`` s after the rope is taut again."""
    time = np.asarray(time, float)
    tension = np.asarray(tension, float)
    slack = tension < threshold
    events = []
    k = 0
    n = len(time)
    while k < n:
        if not slack[k]:
            k += 1
            continue
        start = k
        while k < n and slack[k]:
            k += 1
        if k >= n:
            events.append({"start": float(time[start]), "end": math.nan, "snap_load": math.nan,
                           "snap_time": math.nan})
            break
        window = (time >= time[k]) & (time <= time[k] + snap_window)
        j = int(np.flatnonzero(window)[np.argmax(tension[window])])
        events.append({"start": float(time[start]), "end": float(time[k]), "snap_load": float(tension[j]),
                       "snap_time": float(time[j])})
    return events


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
    payload's weight in air; see :func:`slack_events`) and ``snap_load_max`` N; ``payload_position``,
    ``payload_velocity``, ``payload_acceleration`` (nt, 3); ``base_force``,
    ``base_moment`` (nt, 3) N, N*m: the loads of the crane on the deck at the pedestal base
    (A-frame: the moment about the hinge, transferred from the deck stub's foot 1 m below
    it with the force; the portal A-frame: both legs', the moment about the point between
    their hinges, the template's ``position``, and ``base_force_legs`` (nt, 2, 3) per leg); ``drive_angle``/``drive_torque`` {name: (nt,)} (slewing,
    luffing); ``bend_moment_range`` {line: {arc_length, min, max, mean}} along the boom /
    legs and the pedestal; ``tip_position``, ``tip_acceleration`` (nt, 3): the sheave;
    ``cylinder_force`` (nt,) N per cylinder, pushing positive (with ``cylinder``, the
    template's cylinder dict; the portal A-frame: the mean of its legs', each leg carrying
    half the cylinders, and ``cylinder_force_legs`` (nt, 2); force-driven A-frame cylinders: their set force, with
    ``cylinder_length`` (nt,) m and the tilt ``drive_angle["luffing"]`` from that length); ``luffing_rope_tension`` (nt,) N per part of line (with
    ``luffing_rope``, the template's luffing_rope dict, and ``boom_length`` when its eye is
    not given)."""
    base_line, boom_line = _member(res, crane)
    time = np.asarray(res.time, float)
    loads = rope_tension(res, crane, static_tension)
    top, hook, body = loads["rope_tension"], loads["hook_tension"], loads["body"]
    static, static_hook = loads["static_tension"], loads["static_hook"]
    events = slack_events(time, hook, slack_fraction * static_hook)
    snaps = [e["snap_load"] for e in events if np.isfinite(e["snap_load"])]
    base = res.line(base_line)
    boom = res.line(boom_line)
    tip_line = res.line(f"{crane}_crossbeam") if f"{crane}_crossbeam" in res.lines else boom
    tip = np.asarray(tip_line.position, float)[:, -1, :]
    portal = f"{crane}_legs_2" in res.lines          # the closed-portal A-frame (rfesim.scenario.cranes)
    base_force = np.asarray(base.end_a_force, float)
    base_moment = np.asarray(base.end_a_moment, float)
    out = {}
    if base_line.endswith("_stub"):
        # A-frame: the loads reach the deck through the stub under each hinge (clamped 1 m below
        # it, rfesim.scenario.cranes._a_frame_leg); the moment is taken about the hinge (the
        # stub's end B), M_hinge = M_foot + (foot - hinge) x F, and for the portal about the
        # point between its hinges (the template's position): the stub's foot would add the
        # horizontal force times the stub's 1 m
        stubs = [base, res.line(f"{crane}_stub_2")] if portal else [base]
        feet = [np.asarray(st.position, float)[:, 0, :] for st in stubs]
        hinges = [np.asarray(st.position, float)[:, -1, :] for st in stubs]
        centre = sum(hinges) / len(hinges)
        forces = [np.asarray(st.end_a_force, float) for st in stubs]
        base_force = sum(forces)
        base_moment = sum(np.asarray(st.end_a_moment, float) + np.cross(f - centre, F)
                          for st, f, F in zip(stubs, feet, forces))
        if portal:
            out["base_force_legs"] = np.stack(forces, axis=1)
    out.update({
        "time": time, "rope_tension": top, "hook_tension": hook, "static_tension": static,
        "daf": loads["daf"],
        "slack_events": events, "snap_load_max": float(max(snaps)) if snaps else math.nan,
        "base_force": base_force, "base_moment": base_moment,
        "tip_position": tip, "tip_acceleration": _acceleration(time, tip),
        "bend_moment_range": {boom_line: boom.range_graph("bend_moment"),
                              base_line: base.range_graph("bend_moment")},
        "drive_angle": {}, "drive_torque": {},
    })
    if portal:
        for lname in (f"{crane}_legs_2", f"{crane}_stub_2", f"{crane}_crossbeam", f"{crane}_crossbeam_2"):
            out["bend_moment_range"][lname] = res.line(lname).range_graph("bend_moment")
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
    return out
