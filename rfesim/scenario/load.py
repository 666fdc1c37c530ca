"""Reading and validating scenarios: JSON/YAML text or files, dicts, overrides.

Every problem becomes a :class:`rfesim.ScenarioError` whose ``errors`` list holds
``(dotted.field.path, reason)`` pairs.
"""
from __future__ import annotations

import copy
import difflib
import json
import math
import os
import re
import types
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Annotated, Any, Callable, Literal, Union

import yaml
from pydantic import BaseModel, TypeAdapter, ValidationError

from ..errors import ScenarioError
from .schema import FieldError, Scenario, bound_text, yaml_bool_hint

RESERVED_ATTACH = ("fixed", "free")


def _unwrap(tp):
    """Strip Annotated[...] and Optional[...] from a type annotation."""
    while True:
        origin = typing.get_origin(tp)
        if origin is Annotated:
            tp = typing.get_args(tp)[0]
            continue
        if origin in (Union, types.UnionType):
            args = [a for a in typing.get_args(tp) if a is not type(None)]
            if len(args) == 1:
                tp = args[0]
                continue
        return tp


def _type_tag(tp) -> str:
    """The name pydantic gives a type in an error location ("float", "list[list[float]]",
    "dict[str,float]"), without spaces."""
    tp = _unwrap(tp)
    origin = typing.get_origin(tp)
    if origin is not None and origin is not Literal:
        return f"{getattr(origin, '__name__', str(origin))}[{','.join(_type_tag(a) for a in typing.get_args(tp))}]"
    return getattr(tp, "__name__", str(tp))


def _union_member(tp, tag):
    """The member of a union that pydantic's location tag ``tag`` names, or None."""
    for member in typing.get_args(tp):
        m = _unwrap(member)
        if isinstance(tag, str) and typing.get_origin(m) in (list, dict, tuple) and \
                tag.replace(" ", "") == _type_tag(m):
            return m
        if isinstance(m, type) and issubclass(m, BaseModel):
            kind = m.model_fields.get("kind") or m.model_fields.get("method") or m.model_fields.get("type")
            if kind is not None and tag in typing.get_args(_unwrap(kind.annotation)):
                return m
            if tag == m.__name__:
                return m
        elif typing.get_origin(m) is Literal:
            if isinstance(tag, str) and tag.startswith("literal["):
                return m
        elif isinstance(m, type) and tag == m.__name__:
            return m
    return None


def _resolve(loc, root: type = Scenario) -> tuple[list[str], type | None, Any]:
    """Walk a pydantic error location through the Scenario schema (or the model ``root``).

    Returns the user's path (union tags that pydantic inserts are dropped, but only
    where the schema has a union, so a vessel called "harmonic" keeps its name) and
    the model class that owns the last path element (for "did you mean" hints), and
    the type expected at the path (None where unknown).
    """
    tp: Any = root
    owner = None
    out: list[str] = []
    items = list(loc)
    i = 0
    while i < len(items):
        p = items[i]
        if isinstance(p, str) and p.startswith("function-"):
            # a model with a validator, named by pydantic "function-after[_check(), Body]": in a
            # union (a crane's payload, a name or a Body) it is the member the path goes on in
            t = _unwrap(tp) if tp is not None else None
            if t is not None and typing.get_origin(t) in (Union, types.UnionType):
                member = _union_member(t, p.rstrip("]").rsplit(", ", 1)[-1])
                if member is not None:
                    tp = member
            i += 1
            continue
        if p == "[key]":                      # a dict key that is not a string
            i += 1
            continue
        t = _unwrap(tp) if tp is not None else None
        if t is not None and typing.get_origin(t) in (Union, types.UnionType):
            member = _union_member(t, p)
            if member is not None:
                tp = member
                i += 1
                continue
            tp = None
            continue
        out.append(str(p))
        i += 1
        if t is None:
            continue
        if isinstance(t, type) and issubclass(t, BaseModel):
            owner = t
            field = t.model_fields.get(p) if isinstance(p, str) else None
            tp = field.annotation if field is not None else None
        elif typing.get_origin(t) is dict:
            tp = typing.get_args(t)[1]
            owner = None
        elif typing.get_origin(t) is list:
            tp = typing.get_args(t)[0]
            owner = None
        else:
            tp = None
            owner = None
    return out, owner, tp


def _loc_to_path(loc) -> str:
    return ".".join(_resolve(loc)[0])


def _show(value: Any) -> str:
    """A short description of a user value for error messages."""
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)}"
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


_TYPE_REASONS = {
    "float_type": "must be a number",
    "float_parsing": "must be a number",
    "int_type": "must be a whole number",
    "int_parsing": "must be a whole number",
    "int_from_float": "must be a whole number",
    "string_type": "must be text (a string)",
    "bool_type": "must be true or false",
    "bool_parsing": "must be true or false",
    "dict_type": "must be a mapping of names to entries",
    "model_type": "must be a mapping (keys and values)",
    "model_attributes_type": "must be a mapping (keys and values)",
    "list_type": "must be a list",
}


def _kinds(tp) -> list[str]:
    """The ``kind`` values of the models in a discriminated union type."""
    out = []
    for member in typing.get_args(_unwrap(tp)) if tp is not None else ():
        m = _unwrap(member)
        if isinstance(m, type) and issubclass(m, BaseModel):
            for key in ("kind", "method", "type"):     # discriminators
                if key in m.model_fields:
                    out += [str(v) for v in typing.get_args(_unwrap(m.model_fields[key].annotation))]
                    break
    return out


def _reason(err: dict, owner: type | None = None, key: Any = None, tp: Any = None) -> tuple[str, str]:
    """(extra path, reason) for one pydantic error dict."""
    ctx = err.get("ctx") or {}
    exc = ctx.get("error")
    if isinstance(exc, FieldError):
        return exc.field, exc.reason
    typ = err.get("type", "")
    msg = err.get("msg", "invalid value")
    got = err.get("input")
    if msg.startswith("Value error, "):
        return "", msg[len("Value error, "):]
    if typ == "extra_forbidden":
        reason = "unknown key (not part of the schema; check the spelling)"
        if owner is not None:
            known = list(owner.model_fields)
            close = difflib.get_close_matches(str(key), known, n=1, cutoff=0.6)
            if close:
                reason = f"unknown key (did you mean '{close[0]}'?)"
            else:
                reason = f"unknown key (allowed here: {', '.join(known)})"
        return "", reason
    if typ == "missing":
        return "", "required field is missing"
    if typ == "finite_number":
        return "", f"must be a finite number, got {_show(got)}"
    if typ in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        bound = msg.lower().replace("input should be", "must be")
        limit = next((ctx[k] for k in ("le", "lt", "ge", "gt") if k in ctx), None)
        if isinstance(limit, (int, float)) and abs(limit) >= 1e12:       # 1e+20, not its 21 digits
            bound = f"{bound.rsplit(' ', 1)[0]} {bound_text(limit)}"
        why, unit = _limit_reason(owner, key, "limit" if typ.startswith("less") else "floor")
        if why and unit and unit != "1":
            bound += f" {unit}"
        return "", f"{bound} (got {_show(got)})" + (f": {why}" if why else "")
    if typ in ("union_tag_invalid", "union_tag_not_found"):
        field = str(ctx.get("discriminator", "'kind'")).strip("'\"")
        expected = ctx.get("expected_tags") or ", ".join(f"'{k}'" for k in _kinds(tp))
        if typ == "union_tag_not_found":
            return field, f"required field is missing (one of: {expected})"
        tag = "null" if isinstance(got, dict) and field in got and got[field] is None else f"'{ctx.get('tag')}'"
        return field, f"unknown {field} {tag} (use one of: {expected})"
    if typ == "literal_error":
        return "", f"must be {ctx.get('expected', 'one of the allowed values')} (got {_show(got)})"
    if typ in ("too_short", "too_long"):
        n = ctx.get("actual_length")
        lo, hi = ctx.get("min_length"), ctx.get("max_length")
        if typ == "too_short":
            return "", f"needs at least {lo} entries, got {n}"
        return "", f"allows at most {hi} entries, got {n}"
    if typ == "int_parsing_size":
        return "", f"must be a whole number of a usable size, got {_show(got)}"
    if typ == "string_too_long":
        return "", f"is too long (at most {ctx.get('max_length')} characters)"
    if typ in _TYPE_REASONS:
        hint = f" ({yaml_bool_hint(got)})" if isinstance(got, bool) and typ == "string_type" else ""
        if typ == "string_type" and "[key]" in err.get("loc", ()):
            if isinstance(got, bool):
                return "", f"names must be text (strings), got the boolean {_show(got)}{hint}"
            quoted = _show(got) if got is None else got
            return "", f"names must be text (strings), got {_show(got)} (quote it: '{quoted}')"
        if typ in ("int_parsing", "float_parsing") and isinstance(got, str) and SEXAGESIMAL.match(got.strip()):
            hint = (" (YAML 1.1 would read it as a base-60 number, rfesim does not: write the number itself, or "
                    "quote text)")
        return "", f"{_TYPE_REASONS[typ]}, got {_show(got)}{hint}"
    return "", msg


def _limit_reason(owner: type | None, key: Any, which: str = "limit") -> tuple[str | None, str | None]:
    """(the reason documented for a field's upper bound, or with ``which="floor"`` its lower
    bound, its unit): ``limit`` (``floor``) and ``units`` in its JSON Schema extra
    (rfesim.scenario.schema._units)."""
    field = owner.model_fields.get(key) if owner is not None and isinstance(key, str) else None
    extra = getattr(field, "json_schema_extra", None)
    if not isinstance(extra, dict):
        return None, None
    return extra.get(which), extra.get("units")


def validation_errors(exc: ValidationError, prefix: tuple = (), root: type = Scenario) -> list[tuple[str, str]]:
    """Convert a pydantic ValidationError into ``(field path, reason)`` pairs; ``prefix``
    is the location in the Scenario of what was validated (e.g. ``("pipelay",)``), or
    ``root`` the model validated on its own (a data file's RaoTable)."""
    by_path: dict[str, list[str]] = {}
    not_text: set[str] = set()         # a mapping (a list) given where a union takes a name (a number) or a model (a list)
    for err in exc.errors():
        loc = tuple(prefix) + tuple(err.get("loc", ()))
        parts, owner, tp = _resolve(loc, root)
        extra, reason = _reason(err, owner, parts[-1] if parts else None, tp)
        if parts and err.get("loc", ())[-1:] == ("[key]",) and (isinstance(err.get("input"), bool)
                                                                or err.get("input") is None):
            # pydantic reports a boolean key as its index 0/1 (a null one as None): name it by what
            # the user wrote
            parts = parts[:-1] + [_show(err["input"])]
        if extra:
            parts = parts + [extra]
        path = ".".join(parts)
        if err.get("type") == "string_type" and isinstance(err.get("input"), dict) or \
                err.get("type") in ("float_type", "float_parsing", "int_type", "int_parsing") and \
                isinstance(err.get("input"), (list, tuple)):
            not_text.add(path)
        reasons = by_path.setdefault(path, [])
        if reason not in reasons:
            reasons.append(reason)
    # a mapping that failed inside the model of a union (a crane's payload: a body name or a
    # body) is not also told it is no name, nor a list that failed inside the list member of a
    # union (an angle profile: a number or a table) that it is no number
    for path in not_text:
        if any(p.startswith(path + ".") for p in by_path) and len(by_path[path]) == 1:
            del by_path[path]
    # a value tried against several alternatives (a union) gives one error per
    # alternative: report them as one entry for the field
    return [(path, "; or ".join(reasons)) for path, reasons in by_path.items()]


def _rest_point(sc: Scenario, attach: str, local) -> list[float] | None:
    """Global position of a point given in the frame of ``attach`` ("fixed", "free": global; a
    vessel: its frame at rest), or None for any other attachment."""
    if attach in ("fixed", "free"):
        return list(local)
    vessel = sc.vessels.get(attach)
    if vessel is None:
        return None
    h = math.radians(vessel.heading_deg)
    x, y, z = local
    c, s = math.cos(h), math.sin(h)
    return [vessel.position[0] + c * x - s * y, vessel.position[1] + s * x + c * y, vessel.position[2] + z]


def _rest_position(sc: Scenario, end) -> list[float] | None:
    """Global position of a line end with its vessel at rest (None if not placed)."""
    if end.position is None:
        return None
    return _rest_point(sc, end.attach, end.position)


SEABED_TOLERANCE = 0.05     # m an end may lie in the seabed beyond its radius and its static sinkage


def seabed_contact(sc: Scenario, lt, p: list[float]) -> tuple[float, float, float, float, float] | None:
    """How a point ``p`` of a line of type ``lt`` sits on the seabed: (seabed z under it,
    depth of p below that z, the depth a resting line reaches, its contact radius, its static
    sinkage), or None without a seabed there. A line rests on the seabed in it by its contact
    radius (outer_diameter/2), the static sinkage of its submerged weight on the seabed spring
    (w/k, as a laid line rests, rfesim.model.compile) and SEABED_TOLERANCE; the seabed height
    is taken under the point (flat, sloped or profile seabed)."""
    env = sc.environment
    if env.seabed is None:
        return None
    zb = env.seabed_z_at(p[0], p[1])
    if zb is None or not math.isfinite(zb):
        return None
    from ..model.sections import section_from_type
    sec = section_from_type(lt)
    radius = 0.5 * sec.outer_diameter
    w = sec.mass_per_length * env.gravity
    if env.water is not None:
        w -= env.water.density * env.gravity * sec.displaced_area
    sink = max(w, 0.0) / env.seabed.normal_stiffness
    return zb, zb - p[2], radius + sink + SEABED_TOLERANCE, radius, sink


def _at_rest(attach: str) -> str:
    return "" if attach == "fixed" else f" (global, with vessel '{attach}' at rest)"


def _below_seabed(sc: Scenario, lt, attach: str, p: list[float], what: str = "an end") -> str | None:
    """Why a placed line end (global rest position ``p``) lies too deep in the seabed, or None
    (``seabed_contact``); without a seabed, too deep below the water depth
    (``_below_water_depth``). ``what`` names the point in the reason."""
    contact = seabed_contact(sc, lt, p)
    if contact is None:
        return _below_water_depth(sc, lt, attach, p, what)
    zb, depth, allowed, radius, sink = contact
    if not depth > allowed:
        return None
    under = "this end" if what == "an end" else "it"
    return (f"z = {p[2]:.6g} m{_at_rest(attach)} is {depth:.4g} m below the seabed (z = {zb:.6g} m under {under}): "
            f"{what} may rest on the seabed and lie at most {allowed:.3g} m in it (its radius {radius:.3g} m + the "
            f"sinkage of its weight {sink:.3g} m + {SEABED_TOLERANCE} m)")


def _below_water_depth(sc: Scenario, lt, attach: str, p: list[float], what: str = "an end") -> str | None:
    """Why a placed line end (global rest position ``p``) lies below the sea floor of a scene
    with a water depth but no seabed section, or None. The water ends at surface_level -
    depth there (the wave kinematics below it are those at it, rfesim.sea.kernel): an end may
    lie on that floor by its radius and SEABED_TOLERANCE (no seabed spring: no sinkage).
    Without a water depth the sea has no floor and nothing is checked; with a seabed,
    ``seabed_contact``."""
    env = sc.environment
    water = env.water
    if env.seabed is not None or water is None or water.depth is None:
        return None
    from ..model.sections import section_from_type
    floor = water.surface_level - water.depth
    radius = 0.5 * section_from_type(lt).outer_diameter
    allowed = radius + SEABED_TOLERANCE
    depth = floor - p[2]
    if not depth > allowed:
        return None
    return (f"z = {p[2]:.6g} m{_at_rest(attach)} is below the sea floor at the water depth {water.depth:.6g} m "
            f"(z = {floor:.6g} m) by {depth:.4g} m: the water ends there, with or without a seabed section, and "
            f"{what} may lie at most {allowed:.3g} m below it (its radius {radius:.3g} m + {SEABED_TOLERANCE} m); "
            f"check its z and environment.water.depth")


def _unit(v) -> list[float]:
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def _held_points(sup) -> list[tuple[str, str, list[float]]]:
    """(field, point, position in the support's frame) of the points where a support holds
    its line on a prescribed path at the start: a tensioner's track (entry and exit), a
    straightener's straight line (first and last rollers) and a reel's take-off point.
    Rollers and stingers carry the line only where it touches them: none."""
    if sup.kind == "tensioner":
        e = _unit(sup.axis)
        return [("entry", "the track's entry", list(sup.entry)),
                ("length", "the track's exit (entry + length along the axis)",
                 [x + sup.length * u for x, u in zip(sup.entry, e)])]
    if sup.kind == "straightener":
        e = _unit(sup.axis)
        return [("entry", "the first roller's pipe axis", list(sup.entry)),
                ("span", "the last roller's pipe axis (entry + span along the axis)",
                 [x + sup.span * u for x, u in zip(sup.entry, e)])]
    if sup.kind == "reel":
        a, d = _unit(sup.axis), _unit(sup.direction)
        out = [a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2], a[0] * d[1] - a[1] * d[0]]
        return [("centre", "the take-off point (centre + radius * (axis x direction))",
                 [c + sup.radius * o for c, o in zip(sup.centre, out)])]
    return []


def _support_below_floor(sc: Scenario, sname: str, sup) -> list[tuple[str, str]]:
    """Errors for the points where a support holds its line (``_held_points``) below the
    seabed or the water depth, by the rule of a line end."""
    line = sc.lines.get(sup.line)
    lt = sc.line_types.get(line.type) if line is not None else None
    if lt is None:
        return []
    errors = []
    for field, point, local in _held_points(sup):
        p = _rest_point(sc, sup.attach, local)
        if p is None or not all(math.isfinite(c) for c in p):
            continue
        why = _below_seabed(sc, lt, sup.attach, p, f"the line '{sup.line}' held there")
        if why:
            errors.append((f"supports.{sname}.{field}", f"{point}: {why}"))
    return errors


NOTHING_TO_SIMULATE = ("lines", "the scenario has no lines to simulate")


def check_runnable(sc: Scenario) -> list[tuple[str, str]]:
    """What a run refuses in a scenario that is otherwise valid (shared by ``rfesim check``
    with rfesim.model.compile.compile_scenario): a scene with nothing to simulate."""
    if not sc.lines and not sc.chains:
        return [NOTHING_TO_SIMULATE]
    return []


def _on_chain(sc: Scenario, attach: str) -> bool:
    """A "<chain>.<link>" attachment (checked in detail by rfesim.scenario.chains)."""
    from .chains import chain_point
    return chain_point(sc, attach) is not None


def check_references(sc: Scenario) -> list[tuple[str, str]]:
    """Cross-field checks: names a scenario uses must exist and be consistent."""
    errors: list[tuple[str, str]] = []
    vessel_names = set(sc.vessels)
    for group, named in sc:
        if not isinstance(named, dict):
            continue
        # every named map (vessels, lines, bodies, supports, ...): names are references
        # ("<line>:end_b") and groups of the results file (/lines/<name>), where '.' and '..'
        # would be the group itself and its parent
        for name in named:
            if not name:
                errors.append((group, "a name is empty: give every entry a non-empty name"))
            elif any(c in name for c in "/:\\") or name.strip() != name or name in (".", ".."):
                errors.append((f"{group}.{name}", f"bad name {name!r}: names must be non-empty, must not "
                                                  f"contain '/', ':' or '\\' or outer spaces, and must not be "
                                                  f"'.' or '..'"))
    for name in vessel_names:
        if name in RESERVED_ATTACH:
            errors.append((f"vessels.{name}", f"'{name}' is a reserved attachment word; rename the vessel"))
    water = sc.environment.water
    for lname, line in sc.lines.items():
        base = f"lines.{lname}"
        if line.type not in sc.line_types:
            known = ", ".join(sorted(sc.line_types)) or "none defined"
            errors.append((f"{base}.type", f"unknown line type '{line.type}' (line_types: {known})"))
            continue
        lt = sc.line_types[line.type]
        for end_name in ("end_a", "end_b"):
            end = getattr(line, end_name)
            if end.attach not in RESERVED_ATTACH and end.attach not in vessel_names and end.attach not in sc.bodies \
                    and not _on_chain(sc, end.attach) and ":" not in end.attach:     # joins: scenario.joins
                known = ", ".join(["fixed", "free"] + sorted(vessel_names) + sorted(sc.bodies))
                errors.append((f"{base}.{end_name}.attach",
                               f"unknown attachment '{end.attach}' (use one of: {known})"))
            if end.attach == "free" and end.connection == "clamped":
                errors.append((f"{base}.{end_name}.connection", "a free end cannot be clamped"))
        if water is not None and lt.outer_diameter is None and (
                lt.drag_normal > 0 or lt.drag_axial > 0 or lt.added_mass_normal > 0 or lt.added_mass_axial > 0):
            errors.append((f"line_types.{line.type}.outer_diameter",
                           "hydrodynamic coefficients need an outer diameter"))
        pa, pb = _rest_position(sc, line.end_a), _rest_position(sc, line.end_b)
        if pa is not None and pb is not None:
            # vessels at rest; a taut line may be pre-stretched a little, not more than 2 %
            d = math.dist(pa, pb)
            if d < 1e-9 * line.length:
                errors.append((f"{base}.end_b.position", "end B coincides with end A"))
            elif d > 1.02 * line.length:
                errors.append((f"{base}.length", f"{line.length} m is shorter than the distance between its ends "
                                                 f"({d:.6g} m): the line would be stretched by "
                                                 f"{100 * (d / line.length - 1):.3g} %"))
        for end_name, p in (("end_a", pa), ("end_b", pb)):
            attach = getattr(line, end_name).attach
            if p is not None and attach != "free" and all(math.isfinite(c) for c in p):
                why = _below_seabed(sc, lt, attach, p)
                if why:
                    errors.append((f"{base}.{end_name}.position", why))
        on_reel = any(sup.kind == "reel" and sup.line == lname for sup in sc.supports.values())
        if line.end_a.attach == "free" and line.end_a.position is None and line.end_b.attach == "free" \
                and not on_reel:        # a reel places end A on its wrap (stored_length)
            errors.append((f"{base}.end_a.position", "a line with two free ends needs the position of end A"))
    for sname, sup in sc.supports.items():
        base = f"supports.{sname}"
        if sup.kind == "reel" and sup.line in sc.lines and sc.lines[sup.line].end_a.attach != "free":
            errors.append((f"{base}.line", f"end A of line '{sup.line}' must be free: it lies on the reel's wrap"))
        if sup.line not in sc.lines:
            known = ", ".join(sorted(sc.lines)) or "none defined"
            errors.append((f"{base}.line", f"unknown line '{sup.line}' (lines: {known})"))
        elif getattr(sup, "horizontal_tension", None) is not None:
            # rfesim.solvers.lay_statics: H is the horizontal force on the line's end B
            if sc.lines[sup.line].end_b.attach == "free" or ":" in sc.lines[sup.line].end_b.attach:
                errors.append((f"{base}.horizontal_tension", f"needs end B of line '{sup.line}' held (fixed or on "
                                                             f"a vessel): statics pays the line out until the "
                                                             f"horizontal force on its end B is this tension"))
            others = [n for n, o in sc.supports.items() if n < sname and o.kind == "tensioner"
                      and o.line == sup.line and getattr(o, "horizontal_tension", None) is not None]
            if others:
                errors.append((f"{base}.horizontal_tension", f"supports.{others[0]} sets the horizontal tension "
                                                             f"of line '{sup.line}' already: give it on one "
                                                             f"tensioner of the line"))
        elif sc.line_types.get(sc.lines[sup.line].type) is not None and \
                sc.line_types[sc.lines[sup.line].type].outer_diameter is None:
            errors.append((f"{base}.line", f"line '{sup.line}' has no outer_diameter (its type "
                                           f"'{sc.lines[sup.line].type}'): roller contact needs the pipe radius"))
        if sup.attach != "fixed" and sup.attach not in vessel_names:
            known = ", ".join(["fixed"] + sorted(vessel_names))
            errors.append((f"{base}.attach", f"unknown attachment '{sup.attach}' (use one of: {known})"))
        else:
            errors.extend(_support_below_floor(sc, sname, sup))
    from .bodies import check_body_references
    errors.extend(check_body_references(sc))
    from .winches import check_winch_references
    errors.extend(check_winch_references(sc))
    from .tuggers import check_tugger_references
    errors.extend(check_tugger_references(sc))
    from .joins import check_join_references
    errors.extend(check_join_references(sc))
    errors.extend(_step_counts(sc.analysis.dynamics))
    return list(dict.fromkeys(errors))


MAX_STEPS = 1.0e9       # time steps of one run
MAX_OUTPUTS = 1.0e8     # output times of one run


def _step_counts(dyn) -> list[tuple[str, str]]:
    """The time step and output interval against the duration: a step or interval too short
    to count its way through the run (a unit mistake: 1e-300 s, or ms for s)."""
    if not (dyn.enabled and dyn.duration > 0):
        return []
    T = float(dyn.duration)
    errors = []
    integ = dyn.integrator
    name = "max_step" if integ.kind == "adaptive" else "time_step"
    step = getattr(integ, name, None)
    if step is not None and T / step > MAX_STEPS:
        errors.append((f"analysis.dynamics.integrator.{name}",
                       f"{step:g} s takes {T / step:.3g} steps through the duration {T:g} s, more than the "
                       f"{MAX_STEPS:,.0f} a run can take (days of computing for the smallest scene): check the "
                       f"units (seconds)"))
    out = dyn.output_interval
    if out is not None and out > T:
        errors.append(("analysis.dynamics.output_interval", f"{out} s is longer than the duration {T} s"))
    elif out is not None and T / out > MAX_OUTPUTS:
        errors.append(("analysis.dynamics.output_interval",
                       f"{out:g} s stores {T / out:.3g} output times over the duration {T:g} s, more than the "
                       f"{MAX_OUTPUTS:,.0f} a run keeps: give a longer interval (seconds)"))
    return errors


def _extreme_number(data: Any, path: tuple = ()) -> tuple[float, tuple, Any] | None:
    """(|log10|v||, path, v) of the number in ``data`` farthest from 1 in magnitude."""
    best = None
    if isinstance(data, dict):
        items = ((str(k), v) for k, v in data.items())
    elif isinstance(data, list):
        items = ((str(i), v) for i, v in enumerate(data))
    else:
        if isinstance(data, (int, float)) and not isinstance(data, bool) and data != 0:
            try:
                return abs(math.log10(abs(data))), path, data
            except (ValueError, OverflowError):       # nan, inf
                return None
        return None
    for key, value in items:
        found = _extreme_number(value, path + (key,))
        if found is not None and (best is None or found[0] > best[0]):
            best = found
    return best


def arithmetic_error(exc: Exception, where: str, *sources: tuple[tuple, Any]) -> tuple[str, str]:
    """(field path, reason) for arithmetic that failed (overflow, division by zero, a solver
    that found no root) while checking ``where``: the number of ``sources`` ((path prefix,
    data) pairs) far out of range (beyond 1e30 or below 1e-30 in size) is named, else
    ``where``."""
    what = "overflows" if isinstance(exc, OverflowError) else \
        "divides by zero" if isinstance(exc, ZeroDivisionError) else "fails"
    best = None
    for prefix, data in sources:
        found = _extreme_number(data, tuple(prefix))
        if found is not None and (best is None or found[0] > best[0]):
            best = found
    if best is not None and best[0] >= 30.0:
        return ".".join(best[1]), (f"{_show(best[2])} is out of range: the computation with it {what} ({exc}); "
                                   f"give a value of a physical size (SI units)")
    return where, (f"these values cannot be computed with: the arithmetic {what} ({exc}); check their sizes "
                   f"and units")


def _arithmetic_site(obj: Any, tp: Any, path: tuple = ()) -> tuple | None:
    """The deepest path in ``obj`` (of schema type ``tp``) whose validation on its own raises
    an ArithmeticError, or None."""
    t = _unwrap(tp)
    members = [_unwrap(a) for a in typing.get_args(t)] if typing.get_origin(t) in (Union, types.UnionType) else [t]
    for m in members:
        children: list = []
        if isinstance(obj, dict) and isinstance(m, type) and issubclass(m, BaseModel):
            children = [(k, v, m.model_fields[k].annotation) for k, v in obj.items()
                        if isinstance(k, str) and k in m.model_fields]
        elif isinstance(obj, dict) and typing.get_origin(m) is dict:
            children = [(str(k), v, typing.get_args(m)[1]) for k, v in obj.items()]
        elif isinstance(obj, list) and typing.get_origin(m) is list:
            children = [(str(i), v, typing.get_args(m)[0]) for i, v in enumerate(obj)]
        for key, value, sub in children:
            found = _arithmetic_site(value, sub, path + (key,))
            if found is not None:
                return found
    if not isinstance(obj, (dict, list)):
        return None
    try:
        TypeAdapter(tp).validate_python(obj)
    except ArithmeticError:
        return path
    except Exception:  # noqa: BLE001 - only the arithmetic failure is looked for here
        return None
    return None


def _at(data: Any, path: tuple) -> Any:
    """The part of ``data`` at ``path`` (keys as text)."""
    for key in path:
        if isinstance(data, list):
            data = data[int(key)]
        else:
            data = next(v for k, v in data.items() if str(k) == key)
    return data


def validate_dict(obj: Any, _raw: Callable | None = None, _after: list | None = None) -> Scenario:
    """Validate a plain dict into a Scenario, raising ScenarioError on any problem.
    ``_after``: ``(path, value)`` assignments put onto sections the templates made, after
    their expansion (``revalidated``)."""
    if not isinstance(obj, dict):
        what = {type(None): "nothing (an empty document)", list: "a list", tuple: "a list", str: "a string",
                int: "a number", float: "a number", bool: "a boolean"}.get(type(obj), type(obj).__name__)
        raise ScenarioError([("", f"a scenario must be a JSON/YAML object (a mapping of keys to values), "
                                  f"got {what}")])
    raw = _raw or (lambda o: super(Scenario, Scenario).model_validate(o))
    from .pipelay import recording_origins, recording_warnings, template_path
    from .templates import expand
    given = obj                    # kept as the source: a revalidation expands the templates again
    with recording_origins() as origins, recording_warnings() as template_warnings:
        obj = expand(obj)          # pipelay and crane templates -> ordinary sections (rfesim.scenario.templates)
    if _after:
        obj = copy.deepcopy(obj)
        template_warnings += _put_after(obj, _after, origins)

    def user_fields(errors: list[tuple[str, str]]) -> ScenarioError:
        # an error in a section a template made names the template field the user wrote
        # (rfesim.scenario.pipelay.template_path); other scenarios' errors are unchanged
        return ScenarioError([(template_path(f, origins), r) for f, r in errors] if origins else errors)

    try:
        sc = raw(obj)
    except ValidationError as exc:
        raise user_fields(validation_errors(exc)) from None
    except ArithmeticError as exc:
        # a validator computing with an absurd number (1e300): name the section, and the number
        where = _arithmetic_site(obj, Scenario) or ()
        raise user_fields([arithmetic_error(exc, ".".join(where), (where, _at(obj, where)))]) from None
    try:
        errors = check_references(sc)
    except ArithmeticError as exc:
        raise user_fields([arithmetic_error(exc, "", ((), obj))]) from None
    if errors:
        raise user_fields(errors)
    sc._template_warnings = list(template_warnings)     # added to a run's statics warnings (rfesim.api)
    sc._source = copy.deepcopy(given)
    sc._origins = dict(origins)
    sc._after = copy.deepcopy(list(_after or []))
    sc._validated_dump = _plain(sc.model_dump(mode="python", warnings=False))
    return sc


def _plain(value: Any) -> Any:
    """A dump's values as plain Python: numpy scalars and arrays (assigned by a script) as
    numbers and lists, tuples as lists."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if type(value).__module__ == "numpy":
        tolist = getattr(value, "tolist", None)
        return _plain(tolist()) if tolist is not None else value
    return value


def _assignments(before: Any, now: Any, path: tuple = ()) -> list[tuple[tuple, Any]]:
    """(path, value) of every place where ``now`` differs from ``before`` (two dumps); a
    removed entry has the value ``_REMOVED``; lists are compared whole."""
    if isinstance(before, dict) and isinstance(now, dict):
        out = []
        for key in now:
            if key not in before:
                out.append((path + (key,), now[key]))
            else:
                out += _assignments(before[key], now[key], path + (key,))
        out += [(path + (key,), _REMOVED) for key in before if key not in now]
        return out
    return [] if _same(before, now) else [(path, now)]


class _Removed:
    """The value of a removed entry among assignments: one object, also when copied or
    pickled (a Scenario keeps such assignments, ``_after``)."""

    def __repr__(self) -> str:
        return "<removed>"

    def __reduce__(self) -> str:
        return "_REMOVED"

    def __deepcopy__(self, memo) -> "_Removed":
        return self

    def __copy__(self) -> "_Removed":
        return self


_REMOVED = _Removed()


def _same(a: Any, b: Any) -> bool:
    # a type change counts (60.0 assigned to an int field is validated again, to 60)
    try:
        return type(a) is type(b) and bool(a == b)
    except Exception:
        return False


def _assign(data: dict, path: tuple, value: Any, now: dict) -> None:
    """Put an assignment into the input dict: ``data`` at ``path`` becomes ``value``. A section
    the input left out (its defaults) is started empty, so it gets only the assigned field;
    where the input gave something else than a mapping on the way (a shorthand the validators
    expanded) the whole section is taken from the dump ``now``."""
    cur, dump = data, now
    for key in path[:-1]:
        dump = dump[key]
        if key not in cur:
            cur[key] = {}
        elif not isinstance(cur[key], dict):
            cur[key] = copy.deepcopy(dump)       # the section as the Scenario has it now
            return
        cur = cur[key]
    if value is _REMOVED:
        cur.pop(path[-1], None)
    else:
        cur[path[-1]] = copy.deepcopy(value)


def _made_section(path: str, origins: dict) -> str | None:
    """The section a template made (``bodies.crane_payload``) that ``path`` lies in, or None."""
    return max((p for p in origins if path == p or path.startswith(p + ".")), key=len, default=None)


def template_route(path: str, origins: dict) -> tuple[str | None, str | None]:
    """Where a value for ``path`` of the expanded scenario goes in the input with its
    templates: ``(path, None)`` outside the sections the templates made; in a made section,
    ``(template field, None)`` when the field is a copy of a template field
    (``bodies.crane_payload.mass`` -> ``cranes.crane.payload.mass``), else ``(None, reason)``:
    the template makes the section again at every validation, so a value set in it would
    not hold (or would clash with the name the template makes)."""
    best = _made_section(path, origins)
    if best is None:
        return path, None
    o = origins[best]
    rest = path[len(best) + 1:]
    first = rest.split(".", 1)[0]
    if first and first in o.keys:
        return f"{o.template}.{o.keys[first]}{rest[len(first):]}", None
    if o.copy_of is not None and first and first not in o.generated:
        return f"{o.template}.{o.copy_of}.{rest}", None
    where = f"{o.template}.{o.field}" if o.field else o.template
    return None, (f"{best} is made by the template {o.template}" + (f" from its field {where}" if o.field else "")
                  + f", again each time the scenario is validated: a value given in it would not hold; give "
                  f"it through the template's fields ({where}.…) instead")


def onto_templates(data: dict, overrides: dict[str, Any]) -> dict[str, Any]:
    """``overrides`` (dotted path -> value) with the paths into entries that the ``data``'s
    templates make (``bodies.crane_payload.mass``) put onto the template fields they copy
    (``cranes.crane.payload.mass``); a path into a made entry that no template field stands
    for is a ScenarioError naming it and the template field to give instead."""
    maps = set(_named_maps())

    def own(group: str) -> dict:
        return data.get(group) if isinstance(data.get(group), dict) else {}

    made = [str(p) for p in overrides if len(str(p).split(".")) >= 2 and str(p).split(".")[0] in maps
            and str(p).split(".")[1] not in own(str(p).split(".")[0])]
    if not made or not any(data.get(k) for k in ("pipelay", "cranes")):
        return overrides
    from .pipelay import recording_origins
    from .templates import expand
    try:
        with recording_origins() as origins:
            expand(data)
    except Exception:   # noqa: BLE001 - a template that does not expand: the validation says why
        return overrides
    out, errors = {}, []
    for path, value in overrides.items():
        field, reason = template_route(str(path), origins) if str(path) in made else (path, None)
        if reason is not None:
            errors.append((str(path), reason))
        else:
            out[field] = value
    if errors:
        raise ScenarioError(errors)
    return out


def _put_after(data: dict, after: list, origins: dict) -> list[str]:
    """Put assignments (``(path, value)``, a value ``_REMOVED`` to remove) onto the sections
    the templates made in the expanded ``data``; the warnings that say so, naming the
    template. A ScenarioError for a section the templates no longer make."""
    errors, warnings = [], []
    for path, value in after:
        dotted = ".".join(str(k) for k in path)
        best = _made_section(dotted, origins)
        if best is None:
            errors.append((dotted, "was assigned in a section a template made, which the templates no longer "
                                   "make: assign it again on the scenario as loaded now"))
            continue
        cur = data
        for key in path[:-1]:
            if not isinstance(cur.get(key), dict):
                cur[key] = {}
            cur = cur[key]
        if value is _REMOVED:
            cur.pop(path[-1], None)
        else:
            cur[path[-1]] = copy.deepcopy(value)
        o = origins[best]
        where = f"{o.template}.{o.field}" if o.field else o.template
        text = (f"{best} was changed after the template {o.template} made it ({dotted}): kept over what {where} "
                f"makes, but what the template computes from it elsewhere is not made again; give the "
                f"template's fields for a consistent scenario")
        if text not in warnings:
            warnings.append(text)
    if errors:
        raise ScenarioError(errors)
    return warnings


def _named_maps() -> tuple[str, ...]:
    return tuple(name for name, f in Scenario.model_fields.items() if typing.get_origin(f.annotation) is dict)


def _assign_template(data: dict, tpath: tuple, npath: tuple, value: Any, now: dict) -> None:
    """Put an assignment at ``npath`` of the expanded scenario into the input at its template
    field ``tpath`` (the two share their last parts after the template's and the made
    section's own)."""
    k = 0
    while k < min(len(tpath), len(npath)) - 1 and tpath[-1 - k] == npath[-1 - k]:
        k += 1
    cur = data
    for key in tpath[:len(tpath) - max(k, 1)]:
        if not isinstance(cur.get(key), dict):
            cur[key] = {}
        cur = cur[key]
    if k == 0:
        cur[tpath[-1]] = copy.deepcopy(value)
        return
    dump = now
    for key in npath[:len(npath) - k]:
        dump = dump[key]
    _assign(cur, tpath[len(tpath) - k:], value, dump)


def revalidated(sc: Scenario, overrides: dict[str, Any] | None = None) -> Scenario:
    """``sc`` validated again with the fields assigned since it was validated (pydantic does
    not check an assignment: ``sc.environment.water.density = -1025`` ran, with wrong
    numbers). The assignments are put into the input it was validated from, so what a
    validator filled in or what a field's default left unset stays so (a tugger's body_point,
    a bilinear law's hardening_ratio); unchanged and without overrides: ``sc`` itself.
    The input keeps its pipelay and crane templates, so they are expanded again (a changed
    water depth moves a laid pipe's end B); an assignment in a section a template made goes
    onto the template field it copies (``template_route``), or where none does, onto the
    made section after the expansion, with a warning naming the template (``_after``)."""
    now = _plain(sc.model_dump(mode="python", warnings=False))
    source, before = sc._source, sc._validated_dump
    if source is None or before is None:
        data = now      # not made by validate_dict (model_construct): its whole dump
    else:
        changes = _assignments(before, now)
        if not changes and not overrides:
            return sc
        data = copy.deepcopy(source)
        origins, after = sc._origins or {}, list(sc._after or [])
        for path, value in changes:
            dotted = ".".join(str(k) for k in path)
            if not origins or _made_section(dotted, origins) is None:
                _assign(data, path, value, now)
                continue
            # in a section a pipelay or crane template made: onto the template field it
            # copies (the templates are expanded again from the input)
            field, reason = template_route(dotted, origins)
            if reason is None and value is not _REMOVED:
                _assign_template(data, tuple(field.split(".")), path, value, now)
            else:
                # no template field stands for it (a line type, a support the template
                # computes): put onto the made section after the expansion, with a warning
                after = [a for a in after if a[0] != path] + [(path, value)]
    # the templates' warnings: made again when the input has templates (they are expanded
    # again), else those of the first expansion are kept
    kept = [] if source is not None and sc._origins else list(sc._template_warnings or [])
    if source is None or before is None or not (sc._origins and after):
        out = load_scenario(data, overrides)
    else:        # as load_scenario(data, overrides) does with a dict, then the assignments after
        out = validate_dict(apply_overrides(data, overrides) if overrides else data, _after=after)
    out._template_warnings = kept + [w for w in out._template_warnings if w not in kept]
    return out


class _UniqueKeyLoader(yaml.SafeLoader):
    """A safe YAML loader that refuses a key given twice in one mapping."""


def _construct_unique_mapping(loader, node, deep=False):
    seen = {}
    for key_node, _ in node.value:
        if key_node.tag == "tag:yaml.org,2002:merge":
            continue              # "<<: *base": merged by construct_mapping, the keys written here win
        key = loader.construct_object(key_node, deep=deep)
        try:
            hash(key)
        except TypeError:
            continue              # the default constructor reports unhashable keys
        if key in seen:
            mark = key_node.start_mark
            raise ScenarioError([("", f"invalid YAML at line {mark.line + 1} column {mark.column + 1}: "
                                      f"key '{key}' appears twice in the same mapping (first at line "
                                      f"{seen[key].line + 1})")])
        seen[key] = key_node.start_mark
    mapping = loader.construct_mapping(node, deep=deep)
    for key_node, _ in node.value:
        # an unquoted yes/no/on/off/true/false key is a boolean in YAML 1.1: keep the word to
        # report it (_bool_keys) instead of a name "false"
        if isinstance(key_node, yaml.ScalarNode) and key_node.tag == "tag:yaml.org,2002:bool" \
                and key_node.style is None:
            value = loader.construct_object(key_node, deep=deep)
            if isinstance(value, bool) and value in mapping:
                mapping[_YamlBoolKey(key_node.value, value, key_node.start_mark)] = mapping.pop(value)
    return mapping


class _YamlBoolKey:
    """A mapping key that YAML read as a boolean (``no:``), with the word the user wrote."""

    def __init__(self, word: str, value: bool, mark):
        self.word, self.value, self.mark = word, value, mark

    def __repr__(self) -> str:
        return self.word


def _bool_keys(data: Any, path: tuple = ()) -> list[tuple[str, str]]:
    """Errors for the keys YAML read as booleans, with their dotted paths."""
    out = []
    if isinstance(data, dict):
        for key, value in data.items():
            if isinstance(key, _YamlBoolKey):
                where = ".".join(path + (key.word,))
                out.append((where, f"YAML reads the unquoted key {key.word} (line {key.mark.line + 1}) as the "
                                   f"boolean {'true' if key.value else 'false'}, not a name: quote it "
                                   f"(\"{key.word}\": ...) (YAML 1.1 reads yes, no, on, off, true and false "
                                   f"as booleans)"))
                out.extend(_bool_keys(value, path + (key.word,)))
            else:
                out.extend(_bool_keys(value, path + (str(key),)))
    elif isinstance(data, list):
        for i, value in enumerate(data):
            out.extend(_bool_keys(value, path + (str(i),)))
    return out


_UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_unique_mapping)
# numbers in exponent form as YAML 1.2 (and JSON, and every engineer) writes them: 2.1e11, 1e5,
# 3E-2 -- YAML 1.1, and so PyYAML, reads them as text unless they have a dot and a signed exponent
_UniqueKeyLoader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^(?:[-+]?(?:[0-9][0-9_]*)(?:\.[0-9_]*)?[eE][-+]?[0-9]+|[-+]?\.[0-9_]+[eE][-+]?[0-9]+)$"),
    list("-+0123456789."))
# YAML 1.1 reads 1:20 as the base-60 (sexagesimal) number 80 and 1:30.5 as 90.5: no engineer
# means that, so those are text (refused where a number is due, the field named) -- YAML 1.2
# dropped them too. PyYAML's int and float resolvers without their sexagesimal alternative:
_NOT_SEXAGESIMAL = {
    "tag:yaml.org,2002:int": re.compile(
        r"^(?:[-+]?0b[0-1_]+|[-+]?0[0-7_]+|[-+]?(?:0|[1-9][0-9_]*)|[-+]?0x[0-9a-fA-F_]+)$"),
    "tag:yaml.org,2002:float": re.compile(
        r"^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+][0-9]+)?|\.[0-9][0-9_]*(?:[eE][-+][0-9]+)?"
        r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"),
}
_UniqueKeyLoader.yaml_implicit_resolvers = {
    first: [(tag, _NOT_SEXAGESIMAL[tag] if tag in _NOT_SEXAGESIMAL and ":[0-5]?[0-9]" in regexp.pattern else regexp)
            for tag, regexp in resolvers]
    for first, resolvers in _UniqueKeyLoader.yaml_implicit_resolvers.items()}
SEXAGESIMAL = re.compile(r"^[-+]?[0-9][0-9_]*(?::[0-5]?[0-9])+(?:\.[0-9_]*)?$")


def _unique_json_object(pairs):
    out = {}
    for key, value in pairs:
        if key in out:
            raise ScenarioError([("", f"invalid JSON: key '{key}' appears twice in the same object")])
        out[key] = value
    return out


def _parse_json(text: str) -> Any:
    try:
        return json.loads(text, parse_constant=float, object_pairs_hook=_unique_json_object)
    except json.JSONDecodeError as exc:
        raise ScenarioError([("", f"invalid JSON at line {exc.lineno} column {exc.colno}: {exc.msg}")]) from None
    except ScenarioError:
        raise                                     # a key given twice (ScenarioError is a ValueError too)
    except RecursionError:
        raise ScenarioError([("", "invalid JSON: nested too deeply")]) from None
    except ValueError as exc:
        # Python refuses to convert an integer literal of more than sys.get_int_max_str_digits()
        # digits (4300 by default, a guard against quadratic-time conversion) with a message
        # about set_int_max_str_digits that means nothing to the author of a scenario
        import sys

        what = (f"a number with more than {sys.get_int_max_str_digits()} digits (write it in exponent form, "
                f"e.g. 1.5e300)" if "integer string conversion" in str(exc) else str(exc))
        raise ScenarioError([("", f"invalid JSON: {what}")]) from None


# YAML anchors and aliases (&name, *name) make a document a graph: a 400-byte "billion
# laughs" document expands to 9**8 nodes when constructed. What aliases may add, beyond what
# the document writes out, is capped (checked on the composed graph, before any construction).
YAML_ALIAS_MAX_NODES = 100_000
YAML_ALIAS_MAX_CHARS = 1_000_000
_SATURATE = 10**15


def yaml_expansion(text: str) -> tuple[int, int]:
    """(nodes, scalar characters) of the YAML document once its aliases are expanded;
    ScenarioError when aliases add more than YAML_ALIAS_MAX_NODES nodes or
    YAML_ALIAS_MAX_CHARS characters to what is written out, or make it recursive.

    Only composes the document (a graph where an alias is the node it names, linear in the
    text) and sums the sizes bottom-up, each node once. A document that does not compose
    gives (0, 0): the parser reports its error."""
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)   # pure Python: no C-stack overflow when deep
    except (yaml.YAMLError, RecursionError):
        return 0, 0
    if root is None:
        return 0, 0
    size: dict[int, tuple[int, int]] = {}      # id(node) -> (nodes, characters) once expanded
    open_: set[int] = set()                    # nodes whose children are being summed (the DFS path)
    stack: list[tuple[Any, bool]] = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        key = id(node)
        kids = _yaml_children(node)
        if children_done:
            nodes, chars = 1, 0
            for kid in kids:
                n, c = size[id(kid)]
                nodes, chars = nodes + n, chars + c
            size[key] = (min(nodes, _SATURATE), min(chars, _SATURATE))
            open_.discard(key)
        elif key in open_:
            mark = node.start_mark
            raise ScenarioError([("", f"invalid YAML at line {mark.line + 1} column {mark.column + 1}: an alias "
                                      f"refers to a node that contains it (a recursive structure)")])
        elif key not in size:
            if isinstance(node, yaml.ScalarNode):
                size[key] = (1, len(node.value))
                continue
            open_.add(key)
            stack.append((node, True))
            stack.extend((kid, False) for kid in kids if id(kid) not in size)
    written_nodes = len(size)
    written_chars = sum(len(n.value) for n in _yaml_scalars(root))
    nodes, chars = size[id(root)]
    if nodes - written_nodes > YAML_ALIAS_MAX_NODES or chars - written_chars > YAML_ALIAS_MAX_CHARS:
        def shown(n: int) -> str:
            return f"{n}" if n < _SATURATE else f"more than {_SATURATE:.0e}"

        raise ScenarioError([("", f"YAML aliases (*name) expand this document to {shown(nodes)} nodes and "
                                  f"{shown(chars)} characters of values, from {written_nodes} nodes written out; "
                                  f"rfesim accepts at most {YAML_ALIAS_MAX_NODES} nodes and {YAML_ALIAS_MAX_CHARS} "
                                  f"characters added by aliases: write the repeated parts out instead")])
    return nodes, chars


def _yaml_children(node) -> list:
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    if isinstance(node, yaml.MappingNode):
        return [n for pair in node.value for n in pair]
    return []


def _yaml_scalars(root):
    """Every distinct scalar node of a composed YAML graph, once."""
    seen, stack = set(), [root]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.ScalarNode):
            yield node
        else:
            stack.extend(_yaml_children(node))


def _parse_yaml(text: str) -> Any:
    if "&" in text and "*" in text:        # no anchor, no alias: nothing to expand
        yaml_expansion(text)
    try:
        data = yaml.load(text, Loader=_UniqueKeyLoader)  # noqa: S506 - a SafeLoader subclass
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1} column {mark.column + 1}" if mark is not None else ""
        raise ScenarioError([("", f"invalid YAML{where}: {getattr(exc, 'problem', None) or exc}")]) from None
    except ScenarioError:
        raise                                     # refused by our loader (ScenarioError is a ValueError too)
    except RecursionError:
        raise ScenarioError([("", "invalid YAML: nested too deeply")]) from None
    except ValueError as exc:
        # Python's cap on the digits of an integer literal (see _parse_json)
        import sys

        what = (f"a number with more than {sys.get_int_max_str_digits()} digits (write it in exponent form, "
                f"e.g. 1.5e300)" if "integer string conversion" in str(exc) else str(exc))
        raise ScenarioError([("", f"invalid YAML: {what}")]) from None
    errors = _bool_keys(data)
    if errors:
        raise ScenarioError(errors)
    return data


def parse_text(text: str | bytes, fmt: str = "auto") -> Any:
    """Parse JSON or YAML text into plain Python data (ScenarioError if it is not).

    ``fmt`` is "json", "yaml" or "auto" (JSON when the text starts with ``{`` or ``[``
    and parses as JSON, YAML otherwise). Keys given twice are refused.
    """
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            raise ScenarioError([("", f"the scenario is not UTF-8 text (byte {exc.start})")]) from None
    text = text.lstrip("\ufeff")
    if not text.strip():
        raise ScenarioError([("", "the scenario is empty")])
    if fmt == "json":
        return _parse_json(text)
    if fmt == "yaml":
        return _parse_yaml(text)
    if text.lstrip().startswith(("{", "[")):
        try:
            return _parse_json(text)
        except ScenarioError as json_error:
            try:                   # YAML flow style, e.g. {a: 1}
                return _parse_yaml(text)
            except ScenarioError:
                raise json_error from None
    return _parse_yaml(text)


def _list_index(path: str, key: str, items: list) -> int:
    """The list position ``key`` names in a dotted override path (ScenarioError if none)."""
    if key.startswith("-") and key[1:].isdigit():
        raise ScenarioError([(path, f"'{key}' is a negative list position: positions count from 0 at the "
                                    f"start of the list ({_span(items)})")])
    if not (key.isascii() and key.isdigit()):
        raise ScenarioError([(path, f"'{key}' is not a valid index: a list position is a whole number from 0")])
    i = int(key)
    if i >= len(items):
        raise ScenarioError([(path, f"'{key}' is not a valid index: beyond the end of the list ({_span(items)})")])
    return i


def _span(items: list) -> str:
    n = len(items)
    return "the list is empty" if n == 0 else "its only position is 0" if n == 1 else f"positions 0 to {n - 1}"


def set_path(data: dict, path: str, value: Any) -> None:
    """Set ``data[a][b][c] = value`` for a dotted path ``a.b.c`` (list positions from 0 allowed).

    Refused with a ScenarioError naming the path: an empty path or an empty part (``lines..pipe``,
    a leading or trailing dot), a negative or missing list position, a part under a value that
    is not a mapping or a list."""
    if not isinstance(path, str):
        raise ScenarioError([(str(path), f"an override's key must be text, a dotted field path such as "
                                         f"lines.pipe.elements, got {_show(path)} ({type(path).__name__})")])
    if not path.strip():
        raise ScenarioError([(str(path), "an override needs a dotted field path such as lines.pipe.elements, "
                                         "got an empty one")])
    keys = path.split(".")
    for i, k in enumerate(keys):
        if not k.strip():
            where = "at the start" if i == 0 else "at the end" if i == len(keys) - 1 else f"after '{keys[i - 1]}'"
            raise ScenarioError([(path, f"part {i + 1} of the dotted path is empty ({where}: a stray or doubled "
                                        f"dot): each part must name a field, an entry or a list position")])
    cur: Any = data
    for i, k in enumerate(keys[:-1]):
        if isinstance(cur, list):
            cur = cur[_list_index(path, k, cur)]
            continue
        if not isinstance(cur, dict):
            raise ScenarioError([(path, f"'{'.'.join(keys[:i])}' is not a mapping")])
        if k not in cur or cur[k] is None:
            cur[k] = {}
        cur = cur[k]
    last = keys[-1]
    if isinstance(cur, list):
        cur[_list_index(path, last, cur)] = value
    elif isinstance(cur, dict):
        cur[last] = value
    else:
        raise ScenarioError([(path, "parent is not a mapping")])


def apply_overrides(data: dict, overrides: dict[str, Any] | None) -> dict:
    """A deep copy of ``data`` with dotted-path overrides applied (copies of their values: a
    later path inside one, such as a sweep's varied value, must not change the caller's).
    A path into an entry of a named map that ``data`` (or its templates) does not have is a
    ScenarioError naming the path (rfesim.sweep.check_vary_paths); ``map.X`` given a whole
    object adds entry X on purpose. A path into an entry its templates make goes onto the
    template field it copies, or is refused naming the template field (``onto_templates``)."""
    if overrides is not None and not isinstance(overrides, Mapping):
        raise ScenarioError([("", f"overrides must be a mapping of dotted field paths to values, such as "
                                  f"{{'lines.pipe.elements': 40}}, got {_show(overrides)} "
                                  f"({type(overrides).__name__})")])
    if overrides and isinstance(data, Mapping):
        # a misspelled entry name (``vessels.fpsoo.position``) would add a new, unused entry and
        # leave the case unchanged: refused, naming the path (as for `rfesim sweep --vary`)
        from ..sweep import check_vary_paths
        check_vary_paths(data, {str(path): [value] for path, value in overrides.items()})
        overrides = onto_templates(data, overrides)
    out = copy.deepcopy(data)
    for path, value in (overrides or {}).items():
        set_path(out, path, copy.deepcopy(value))
    return out


def _read_file(path: Path) -> tuple[str, str]:
    """The text of a scenario file and its format ("json" for .json, else "auto")."""
    if not str(path).strip():
        raise ScenarioError([("", "no scenario file given (empty path)")])
    try:
        if not path.exists():
            raise ScenarioError([("", f"scenario file not found: {path}")])
        if path.is_dir():
            raise ScenarioError([("", f"{path} is a directory, not a scenario file")])
        raw = path.read_bytes()
    except OSError as exc:
        raise ScenarioError([("", f"cannot read the scenario file {path}: {exc.strerror or exc}")]) from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ScenarioError([("", f"{path} is not UTF-8 text (byte {exc.start})")]) from None
    if not text.strip():
        raise ScenarioError([("", f"the scenario file {path} is empty")])
    return text, "json" if path.suffix.lower() == ".json" else "auto"


def load_scenario(source: str | os.PathLike | dict | Scenario, overrides: dict[str, Any] | None = None,
                  base_dir: str | os.PathLike | None = None) -> Scenario:
    """Load a scenario from a JSON/YAML file path, JSON/YAML text, a dict or a Scenario.

    ``overrides`` maps dotted paths to values (``{"lines.pipe.elements": 40}``) applied
    before validation, as a base file + load case. Relative data-file paths in the
    scenario (``file`` of a csv or rao vessel motion) are taken from ``base_dir``: by
    default the scenario file's folder, or the current directory for text and dicts.
    A Scenario is validated again with the fields assigned since it was validated (pydantic
    does not check an assignment; ``revalidated``); ``rfesim.statics``, ``simulate`` and
    ``modes`` do the same. Unchanged and without overrides it is returned as it is.
    """
    if isinstance(source, Scenario):
        return revalidated(source, overrides)
    if isinstance(source, dict):
        data = source
    elif isinstance(source, bytes):
        data = parse_text(source)
    elif isinstance(source, str) and not source.strip():
        raise ScenarioError([("", "the scenario is empty (no file path or text given)")])
    elif isinstance(source, (str, os.PathLike)):
        text_like = isinstance(source, str) and ("\n" in source or source.lstrip().startswith(("{", "[")))
        if text_like:
            data = parse_text(source)
        else:
            data = parse_text(*_read_file(Path(source)))
            if base_dir is None:
                base_dir = Path(source).parent
    else:
        raise ScenarioError([("", f"a scenario must be a file path, JSON/YAML text or a mapping, "
                                  f"got {type(source).__name__}")])
    if overrides:
        if not isinstance(data, dict):
            raise ScenarioError([("", "a scenario must be a mapping")])
        data = apply_overrides(data, overrides)
    if base_dir is not None:
        from .files import resolve_data_files
        data = resolve_data_files(data, base_dir)
    return validate_dict(data)
