"""Prescribed motions that start or stop with a jolt inside the run.

Waves, a wave record that does not start calm and harmonic vessel motions with no ramp
(``ramp_duration`` 0) start at full height at t = 0 on a structure at rest (its statics in
still water, or its initial shape): the water's velocity and acceleration, and the vessels'
velocity, jump on at once (:func:`startup_warnings`).

Tables that stop a motion dead inside the run: a joint drive's or slewing motor's angle
table, a tensioner's or reel's payout table, a chain joint's prescribed table, whose last row
lies before the end of the run while the curve through the rows still moves there.

Beyond its last row every such table holds its last value: the drive (payout) stops at once
from the rate it had, a jolt in the structure and the lines it carries. The rate at the last
row is that of the curve the run follows (docs/theory.md, 'Drives'): the monotone cubic
(PCHIP) of drives, motors and payout tables of three rows or more, whose end slope comes from
the last two segments (a slewing table [[0, 80], [20, 80], [140, 1160]] deg ends at 16.7
deg/s, not at the 9 deg/s of its last segment); the straight line of a two-row payout table;
the natural cubic spline of a chain's table. A two-row drive table starts and stops at rest,
and a table whose last two rows hold one value ends at rest: neither is warned about. The
vessels' motion tables have their own warning (rfesim.scenario.schema.motion_table_warnings).
"""
from __future__ import annotations

import math
import re

import numpy as np

# a rate below this share of the table's largest step over its whole time span is rest
# (round-off of a cubic's slope at a flat last segment)
REST = 1e-9
# a wave record whose elevation over its first mean period reaches this share of its largest
# does not start calm
CALM_START = 0.1


def _ends_moving(t: np.ndarray, d: np.ndarray, v_end: float) -> bool:
    span = float(np.max(np.abs(np.diff(d)))) / float(t[-1] - t[0]) if len(t) > 1 else 0.0
    return abs(v_end) > REST * max(span, 1e-300)


def _source_template(sc, group: str, field: str):
    """(template name, its input dict) when ``field`` (as rfesim.scenario.pipelay.user_field
    gives it) lies in a ``group`` template (``cranes``, ``pipelay``) of the scenario's input,
    else None."""
    m = re.match(rf"{group}\.([^.\s]+)", field)
    source = getattr(sc, "_source", None)
    if m is None or not isinstance(source, dict):
        return None
    tpl = (source.get(group) or {}).get(m.group(1))
    return (m.group(1), tpl) if isinstance(tpl, dict) else None


def _crane_field(sc, path: str, drive: str) -> tuple[str, str, list | None]:
    """(field, what the table gives, the user's rows) of a drive's angle table at ``path`` of
    the expanded scenario: for a crane's drive the template's angle, stroke or rope-length
    table (``cranes.crane.slewing_deg``, "angle"; ``cranes.crane.cylinder.stroke``,
    "stroke"), else the path as rfesim.scenario.pipelay.user_field gives it (rows None)."""
    from .pipelay import user_field
    field = user_field(sc, path)
    found = _source_template(sc, "cranes", field)
    if found is None:
        return field, "angle", None
    crane, tpl = found
    keys = ["slewing_deg"] if drive == "slewing" else ["luffing_deg", "tilt_deg"]
    for key in keys:
        if isinstance(tpl.get(key), list):
            return f"cranes.{crane}.{key}", "angle", tpl[key]
    for key, what in (("cylinder", "stroke"), ("luffing_rope", "rope length")):
        rows = (tpl.get(key) or {}).get("stroke" if key == "cylinder" else "length") \
            if isinstance(tpl.get(key), dict) else None
        if drive != "slewing" and isinstance(rows, list):
            return f"cranes.{crane}.{key}.{'stroke' if key == 'cylinder' else 'length'}", what, rows
    return field, "angle", None


def _payout_field(sc, path: str) -> str:
    """The field of a payout table at ``path``: a pipelay template's tensioner table (its reel
    turns with the same table), else the path as user_field gives it."""
    from .pipelay import user_field
    field = user_field(sc, path)
    found = _source_template(sc, "pipelay", field)
    if found is not None and isinstance((found[1].get("tensioner") or {}).get("payout"), dict):
        return f"pipelay.{found[0]}.tensioner.payout.rows"
    return field


def _payout_tables(sc):
    """(support name, rows) of every payout table of at least two rows (tensioners, reels)."""
    for name, sup in (sc.supports or {}).items():
        payout = getattr(sup, "payout", None)
        if payout is not None and payout.kind == "table" and len(payout.rows) >= 2:
            yield name, payout.rows


def _hold_row(row) -> str:
    return f"[{float(row[0]) + 5.0:.6g}, {float(row[1]):.6g}]"


def _drive_tables(sc):
    """(path, drive name, rows) of every joint drive's and slewing motor's angle table of the
    scenario's lines (paths of the expanded scenario)."""
    for name, line in (sc.lines or {}).items():
        for end in ("end_a", "end_b"):
            spec = getattr(line, end)
            for i, d in enumerate(spec.drives):
                yield f"lines.{name}.{end}.drives.{i}.angle", d.name, d.angle
            if spec.motor is not None:
                yield f"lines.{name}.{end}.motor.angle", spec.motor.name, spec.motor.angle


def table_end_warnings(sc) -> list[str]:
    """One warning per table (per user field: the portal A-frame's two legs share theirs) whose
    motion stops dead inside the run, naming the field, the time of the last row and the rate
    there; [] without dynamics."""
    from ..model.supports import drive_slopes, table_slopes
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0.0):
        return []
    duration = float(dyn.duration)
    out, seen = [], set()

    def add(field: str, text: str) -> None:
        if field not in seen:
            seen.add(field)
            out.append(f"{field}: {text}")

    for path, drive, rows in _drive_tables(sc):
        if len(rows) < 3 or rows[-1][1] == rows[-2][1] or not 0.0 < rows[-1][0] < duration:
            continue        # two rows start and stop at rest; a flat last segment ends at rest
        rows = np.asarray(rows, float)
        rate = float(drive_slopes(rows[:, 0], rows[:, 1])[-1])
        if not _ends_moving(rows[:, 0], rows[:, 1], rate):
            continue
        motor = path.endswith("motor.angle")
        field, what, user_rows = _crane_field(sc, path, drive)
        stop = ("the motor's set angle stops dead there and the motor brakes the structure with up to its "
                "max_torque" if motor else f"the {drive} drive stops dead there (a jolt in the structure "
                                           "and the lines it carries)")
        add(field, f"the {what} table ends at t = {rows[-1, 0]:.6g} s with the {drive} angle still turning "
                   f"at {rate:.3g} deg/s (the slope of the drive's monotone cubic at the last row, from the "
                   f"last two segments), and holds its last {what} after it: {stop}; add a row that holds "
                   f"the last {what}, e.g. {_hold_row(user_rows[-1] if user_rows else rows[-1])}, for a "
                   f"smooth stop")
    for name, rows in _payout_tables(sc):
        if rows[-1][1] == rows[-2][1] or not 0.0 < rows[-1][0] < duration:
            continue
        rows = np.asarray(rows, float)
        speed = float(table_slopes(rows[:, 0], rows[:, 1])[-1])
        if not _ends_moving(rows[:, 0], rows[:, 1], speed):
            continue
        add(_payout_field(sc, f"supports.{name}.payout.rows"),
            f"the payout table ends at t = {rows[-1, 0]:.6g} s while paying out at {speed:.3g} m/s"
            f"{' (the straight line of two rows)' if len(rows) == 2 else ' (the slope of its monotone cubic at the last row)'}"
            f", and holds its last length after it: the payout stops dead there (a jolt through the grips into "
            f"the line); add a row that holds the last length, e.g. {_hold_row(rows[-1])}, "
            f"for a smooth stop")
    for cname, chain in (getattr(sc, "chains", None) or {}).items():
        for jname, joint in chain.joints.items():
            drive = joint.drive
            motion = getattr(drive, "motion", None)
            if drive.kind != "prescribed" or motion is None or motion.kind != "table":
                continue
            rows = np.asarray(motion.rows, float)
            if not 0.0 < rows[-1, 0] < duration:
                continue
            from scipy.interpolate import CubicSpline     # the chain scene's table (rfesim.formulations.scene)
            rate = float(CubicSpline(rows[:, 0], rows[:, 1], bc_type="natural")(rows[-1, 0], 1))
            if not _ends_moving(rows[:, 0], rows[:, 1], rate):
                continue
            unit = "m/s" if joint.kind == "prismatic" else "rad/s"
            add(f"chains.{cname}.joints.{jname}.drive.motion.rows",
                f"the table ends at t = {rows[-1, 0]:.6g} s while still moving at {rate:.3g} {unit} (the slope of "
                f"its natural cubic spline at the last row), and holds its last value after it: the joint stops "
                f"dead there; add rows that hold the last value for a smooth stop")
    return out


# deg/s: 5 rpm. Offshore cranes slew at about 1-3 rpm and luff, or tilt an A-frame, at a few
# deg/s; a drive table faster than this is a typing or units slip (minutes for seconds,
# radians for degrees) more often than a crane
DRIVE_RATE_LIMIT = 30.0


def _hermite_peak_rates(t: np.ndarray, d: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The largest |rate| on each segment of the cubic Hermite through rows (t, d) with slopes
    v at them (rfesim.loads.drives.drive_table), sampled at 65 points a segment: a two-row
    table's smooth start and stop peaks at 1.5 times its mean rate, in its middle."""
    s = np.linspace(0.0, 1.0, 65)[:, None]
    h = np.diff(t)[None, :]
    rate = ((6 * s ** 2 - 6 * s) * (d[:-1] - d[1:]) / h + (3 * s ** 2 - 4 * s + 1) * v[:-1]
            + (3 * s ** 2 - 2 * s) * v[1:])
    return np.abs(rate).max(axis=0)


def drive_rate_warnings(sc) -> list[str]:
    """One warning per joint drive's or slewing motor's angle table (per user field) whose
    curve turns faster than DRIVE_RATE_LIMIT inside the run: the field, the largest rate of
    the cubic Hermite the drive follows and the rows around it; [] without dynamics."""
    from ..model.supports import drive_slopes
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0.0):
        return []
    duration = float(dyn.duration)
    out, seen = [], set()
    for path, drive, rows in _drive_tables(sc):
        if len(rows) < 2:
            continue
        rows = np.asarray(rows, float)
        inside = rows[:-1, 0] < duration          # segments that start inside the run
        if not np.any(inside):
            continue
        seg = _hermite_peak_rates(rows[:, 0], rows[:, 1], drive_slopes(rows[:, 0], rows[:, 1]))
        seg[~inside] = 0.0
        k = int(np.argmax(seg))
        rate = float(seg[k])
        if rate <= DRIVE_RATE_LIMIT:
            continue
        field, what, _ = _crane_field(sc, path, drive)
        if field.endswith("tilt_deg"):
            drive = "tilt"             # an A-frame's legs, driven as a luffing joint
        if field in seen:
            continue
        seen.add(field)
        out.append(f"{field}: the {what} table turns the {drive} angle at up to {rate:.3g} deg/s "
                   f"({rate / 6.0:.3g} rpm) between t = {rows[k, 0]:.6g} s and {rows[k + 1, 0]:.6g} s, "
                   f"faster than an offshore crane's drives turn (slewing about 1-3 rpm, luffing and "
                   f"A-frame tilt a few deg/s; more than {DRIVE_RATE_LIMIT:.3g} deg/s is named): it whips "
                   f"the structure and what hangs from it; check the table's times (s) and angles (deg)")
    return out


# a harmonic vessel motion beyond these is a units slip more often than a vessel: the motions
# of a vessel in waves stay below about 0.5 g (translations) at periods above about 3 s, and a
# 30 deg roll at 10 s turns at 0.2 rad/s^2
VESSEL_ACCELERATION_LIMIT = 9.81      # m/s^2 (1 g)
VESSEL_ANGULAR_LIMIT = 1.0            # rad/s^2


def harmonic_vessel_warnings(sc) -> list[str]:
    """One warning per degree of freedom of a harmonic vessel motion whose peak acceleration,
    amplitude (2 pi / period)^2, exceeds VESSEL_ACCELERATION_LIMIT (surge, sway, heave) or
    VESSEL_ANGULAR_LIMIT (roll, pitch, yaw): the field, the peak speed and acceleration;
    [] without dynamics."""
    from .pipelay import user_field
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0.0):
        return []
    out = []
    for name, vessel in (sc.vessels or {}).items():
        motion = vessel.motion
        if motion.kind != "harmonic":
            continue
        for dof in DOFS:
            spec = getattr(motion, dof)
            if spec is None or spec.amplitude <= 0.0:
                continue
            omega = 2.0 * math.pi / float(spec.period)
            field = user_field(sc, f"vessels.{name}.motion.{dof}")
            if dof in ("surge", "sway", "heave"):
                acc = spec.amplitude * omega ** 2
                if acc <= VESSEL_ACCELERATION_LIMIT:
                    continue
                what = (f"{spec.amplitude:.4g} m at a period of {spec.period:.4g} s moves vessel '{name}' at up to "
                        f"{spec.amplitude * omega:.4g} m/s with {acc:.4g} m/s^2 ({acc / 9.81:.3g} g)")
                units = "the amplitude (m) and the period (s)"
            else:
                acc = math.radians(spec.amplitude) * omega ** 2
                if acc <= VESSEL_ANGULAR_LIMIT:
                    continue
                what = (f"{spec.amplitude:.4g} deg at a period of {spec.period:.4g} s turns vessel '{name}' at up to "
                        f"{math.degrees(math.radians(spec.amplitude) * omega):.4g} deg/s with {acc:.3g} rad/s^2")
                units = "the amplitude (deg, not rad) and the period (s)"
            out.append(f"{field}: {what}: no vessel moves so in waves (its motions stay below about 0.5 g, "
                       f"at periods above about 3 s); check {units}")
    return out


SPECTRA = ("jonswap", "pierson-moskowitz")
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")
# a vessel table's speed at t = 0 below this (m/s or deg/s) is rest
MOVING = 1e-6


def startup_warnings(sc) -> list[str]:
    """The waves (regular or a spectrum) and harmonic vessel motions of a dynamic run that
    start with no ramp: at full height at t = 0 on a structure at rest, so the water's velocity
    and acceleration (and the RAO vessels' motion, which follows the waves' ramp) or the
    vessel's velocity jump on at once, a start-up transient over the first periods. One
    warning each, naming the ``ramp_duration`` field and a period to ramp over; a wave
    elevation record likewise, unless it starts calm (:func:`_record_start_warning`).
    A vessel's motion table or file begun before t = 0 with no ramp: its velocity at t = 0
    jumps on. Also the winch speed tables whose speed at t = 0 is not 0, and the payout tables that
    start moving at once (at their first row, or at t = 0 for a table begun before): the
    line's speed jumps from rest."""
    from .pipelay import user_field
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0.0):
        return []
    rest = "its static equilibrium in still water" if sc.analysis.statics.enabled else "its initial shape at rest"
    still = "at rest in its statics" if sc.analysis.statics.enabled else "at rest in its initial shape"
    out = []
    water = sc.environment.water
    waves = water.waves if water is not None else None
    if waves is not None and waves.kind in ("airy", "stokes5") + SPECTRA and waves.ramp_duration == 0.0:
        period, which = (waves.tp, "peak period") if waves.kind in SPECTRA else (waves.period, "period")
        rao = sorted(n for n, v in (sc.vessels or {}).items() if v.motion.kind == "rao")
        vessels = f", and the motion of the RAO vessel{'s' * (len(rao) > 1)} {', '.join(rao)}," if rao else ""
        out.append(f"{user_field(sc, 'environment.water.waves.ramp_duration')}: 0 s, so the {waves.kind} waves "
                   f"start at full height at t = 0 on the structure in {rest}: the water's velocity and "
                   f"acceleration{vessels} jump on at once, a start-up transient over the first wave periods; "
                   f"ramp them in over a {which} or more (ramp_duration {period:.6g} s), or leave the first "
                   f"periods out of the results")
    elif waves is not None and waves.kind == "time-series" and waves.ramp_duration == 0.0:
        out += _record_start_warning(sc, waves, rest)
    for name, vessel in (sc.vessels or {}).items():
        motion = vessel.motion
        if motion.kind not in ("harmonic", "table", "csv") or motion.ramp_duration != 0.0:
            continue
        field = user_field(sc, f"vessels.{name}.motion.ramp_duration")
        if motion.kind == "harmonic":
            dofs = [d for d in (motion.surge, motion.sway, motion.heave, motion.roll, motion.pitch, motion.yaw)
                    if d is not None and d.amplitude > 0.0]
            if dofs:
                out.append(f"{field}: 0 s, so vessel '{name}' starts its harmonic motion at full amplitude at t = 0 "
                           f"with the structure in {rest}: the vessel's velocity jumps on at once, a jolt in the "
                           f"lines it carries; ramp it in over a period or more (ramp_duration "
                           f"{max(d.period for d in dofs):.6g} s)")
            continue
        # a motion table or file begun before t = 0 moves at the run's start (one that begins
        # after it has its own warning, rfesim.scenario.schema.motion_table_warnings)
        from ..vessel import make_vessel_motion
        from .schema import motion_table_span
        first, last = motion_table_span(motion)
        if not first <= 0.0 < last:
            continue
        _, rate, _ = make_vessel_motion(vessel).dofs(1e-9)
        speeds = [(dof, abs(float(v)) if k < 3 else math.degrees(abs(float(v))), "m/s" if k < 3 else "deg/s")
                  for k, (dof, v) in enumerate(zip(DOFS, rate))]
        top = max(v for _, v, _ in speeds)
        if top >= MOVING:
            moving = ", ".join(f"{dof} {v:.3g} {unit}" for dof, v, unit in speeds if v >= 0.01 * top)
            out.append(f"{field}: 0 s, so vessel '{name}' starts with the velocity its motion "
                       f"{'file' if motion.kind == 'csv' else 'table'} has at t = 0 ({moving}) while the structure "
                       f"starts {still}: the velocity jumps on at once, a jolt in the lines it carries; give "
                       f"ramp_duration (a wave period or more) to ramp the motion in")
    for name, winch in (sc.winches or {}).items():
        mode = winch.mode
        if mode.kind != "speed":
            continue
        rows = np.asarray(mode.rows, float)
        speed = float(np.interp(0.0, rows[:, 0], rows[:, 1]))      # linear between rows, held beyond
        if speed == 0.0:
            continue
        what = "pays out" if speed > 0.0 else "hauls in"
        out.append(f"{user_field(sc, f'winches.{name}.mode.rows')}: the winch {what} at {abs(speed):.6g} m/s at once at "
                   f"t = 0 with the rope {still}: its speed jumps from 0, a jolt in the rope ("
                   f"{'the payload drops and its tension dips' if speed > 0.0 else 'the payload is snatched'}); "
                   f"start the table at 0 m/s and reach the speed over a second or more, e.g. [[0, 0], "
                   f"[2, {speed:.6g}], ...]")
    for name, rows in _payout_tables(sc):
        rows = np.asarray(rows, float)
        t0 = max(float(rows[0, 0]), 0.0)
        if t0 >= float(dyn.duration):
            continue
        if len(rows) == 2:
            speed = float(np.diff(rows[:, 1])[0] / np.diff(rows[:, 0])[0]) if rows[0, 0] <= t0 < rows[1, 0] else 0.0
        elif rows[0, 0] >= 0.0:
            from ..model.supports import table_slopes
            speed = float(table_slopes(rows[:, 0], rows[:, 1])[0])
        else:
            from scipy.interpolate import PchipInterpolator
            speed = float(PchipInterpolator(rows[:, 0], rows[:, 1]).derivative()(t0)) if t0 < rows[-1, 0] else 0.0
        if not _ends_moving(rows[:, 0], rows[:, 1], speed):
            continue
        text = (f"{_payout_field(sc, f'supports.{name}.payout.rows')}: the payout table starts paying out at "
                f"{speed:.3g} m/s at once at t = {t0:.6g} s"
                f"{' (the straight line of two rows)' if len(rows) == 2 else ' (the slope of its monotone cubic at its first row)'}"
                f" with the line {still}: a jolt through the grips into the line; add a row that holds the first "
                f"length before it and a short ramp (the cubic through them starts from rest)")
        if text not in out:             # a pipelay template's reel turns with its tensioner's table
            out.append(text)
    return out


def _record_start_warning(sc, waves, rest: str) -> list[str]:
    """A wave elevation record replayed with no ramp starts as the record has it at t = 0
    (rfesim.sea.waves.components_from_time_series: the record's own times, repeated with its
    length). It is warned about when the elevation over the first mean period Tz = 2 pi
    sqrt(m0 / m2) of the run reaches CALM_START of the record's largest: a record that starts
    in calm water (a focused group, a designed start) is not."""
    from ..sea.waves import components_from_time_series
    from .pipelay import user_field
    rows = np.asarray(waves.rows, float)
    a, w, phase = components_from_time_series(rows[:, 0], rows[:, 1], waves.omega_max)
    if a.size == 0:
        return []
    tz = 2.0 * math.pi * math.sqrt(float(np.sum(a * a)) / float(np.sum((a * w) ** 2)))
    t = np.linspace(0.0, tz, 65)
    eta = np.cos(np.outer(t, w) + phase) @ a
    largest = float(np.max(np.abs(rows[:, 1] - rows[:, 1].mean())))
    start = float(np.max(np.abs(eta)))
    if not start >= CALM_START * largest:
        return []
    return [f"{user_field(sc, 'environment.water.waves.ramp_duration')}: 0 s, so the recorded waves (time-series) "
            f"start as the record has them at t = 0, up to {start:.3g} m over its first mean period ({tz:.3g} s; "
            f"the record's largest is {largest:.3g} m), on the structure in {rest}: the water's velocity and "
            f"acceleration jump on at once, a start-up transient; ramp them in over a mean period or more "
            f"(ramp_duration {tz:.3g} s), or start the record in calm water"]


def input_motion_warnings(sc) -> list[str]:
    """The motion warnings a scenario's input gives before it runs: waves and harmonic vessel
    motions with no ramp (:func:`startup_warnings`), the vessels' motion tables that do not
    cover the run (rfesim.scenario.schema.motion_table_warnings), the tables that stop
    dead inside it (:func:`table_end_warnings`), the drives faster than a crane's
    (:func:`drive_rate_warnings`) and harmonic vessel motions no vessel makes
    (:func:`harmonic_vessel_warnings`); what ``rfesim check`` and the service's
    submit show, and a run's message repeats."""
    from .schema import motion_table_warnings
    return (startup_warnings(sc) + motion_table_warnings(sc) + table_end_warnings(sc) + drive_rate_warnings(sc)
            + harmonic_vessel_warnings(sc))
