"""Reading and validating scenarios: JSON/YAML text or files, dicts, overrides.

Every problem becomes a :class:`rfesim.ScenarioError` whose ``errors`` list holds
``(dotted.field.path, reason)`` pairs.
"""
from __future__ import annotations

import copy
import json
import math
import os
from pathlib import Path
from typing import Any, Callable

import yaml
from pydantic import ValidationError

from ..errors import ScenarioError
from .schema import FieldError, Scenario

RESERVED_ATTACH = ("fixed", "free")


def _loc_to_path(loc) -> str:
    parts = []
    for p in loc:
        if isinstance(p, int):
            parts.append(str(p))
        elif p in ("function-after", "function-before", "function-wrap", "function-plain"):
            continue
        elif isinstance(p, str) and p.startswith(("function-after[", "function-before[", "function-wrap[")):
            continue
        else:
            parts.append(str(p))
    return ".".join(parts)


_KIND_TAGS = {"fixed", "harmonic", "table", "elastic", "rk4", "adaptive", "generalized-alpha", "str", "float",
              "literal['end_a','end_b']", "literal['end_a', 'end_b']"}


def _reason(err: dict) -> tuple[str, str]:
    """(extra path, reason) for one pydantic error dict."""
    ctx = err.get("ctx") or {}
    exc = ctx.get("error")
    if isinstance(exc, FieldError):
        return exc.field, exc.reason
    typ = err.get("type", "")
    msg = err.get("msg", "invalid value")
    if msg.startswith("Value error, "):
        msg = msg[len("Value error, "):]
    if typ == "extra_forbidden":
        return "", "unknown key (not part of the schema; check the spelling)"
    if typ == "missing":
        return "", "required field is missing"
    if typ == "finite_number":
        return "", f"must be a finite number, got {err.get('input')!r}"
    if typ in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        return "", f"{msg.lower()} (got {err.get('input')!r})"
    return "", msg


def _clean_loc(loc) -> tuple:
    """Drop union-tag entries pydantic puts in locations of discriminated unions."""
    out = []
    for p in loc:
        if isinstance(p, str) and (p in _KIND_TAGS or p.startswith("literal[") or p.startswith("function-")):
            continue
        out.append(p)
    return tuple(out)


def validation_errors(exc: ValidationError) -> list[tuple[str, str]]:
    """Convert a pydantic ValidationError into ``(field path, reason)`` pairs."""
    out: list[tuple[str, str]] = []
    seen = set()
    for err in exc.errors():
        loc = _clean_loc(err.get("loc", ()))
        extra, reason = _reason(err)
        path = _loc_to_path(loc)
        if extra:
            path = f"{path}.{extra}" if path else extra
        key = (path, reason)
        if key not in seen:
            seen.add(key)
            out.append(key)
    # A union of "number or literal" reports one error per alternative; keep them, they
    # are short, but collapse exact duplicates (done above).
    return out


def check_references(sc: Scenario) -> list[tuple[str, str]]:
    """Cross-field checks: names a scenario uses must exist and be consistent."""
    errors: list[tuple[str, str]] = []
    vessel_names = set(sc.vessels)
    for name in list(sc.vessels) + list(sc.lines) + list(sc.line_types):
        if not name or any(c in name for c in "/:\\") or name.strip() != name:
            errors.append((name, "names must be non-empty and must not contain '/', ':' or '\\' or outer spaces"))
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
            if end.attach not in RESERVED_ATTACH and end.attach not in vessel_names:
                known = ", ".join(["fixed", "free"] + sorted(vessel_names))
                errors.append((f"{base}.{end_name}.attach",
                               f"unknown attachment '{end.attach}' (use one of: {known})"))
            if end.attach == "free" and end.connection == "clamped":
                errors.append((f"{base}.{end_name}.connection", "a free end cannot be clamped"))
        if water is not None and lt.outer_diameter is None and (
                lt.drag_normal > 0 or lt.drag_axial > 0 or lt.added_mass_normal > 0 or lt.added_mass_axial > 0):
            errors.append((f"line_types.{line.type}.outer_diameter",
                           "hydrodynamic coefficients need an outer diameter"))
        if line.end_a.position is not None and line.end_b.position is not None \
                and line.end_a.attach == line.end_b.attach:
            d = math.dist(line.end_a.position, line.end_b.position)
            if d > 1.02 * line.length:
                errors.append((f"{base}.length", f"{line.length} m is shorter than the distance between its ends "
                                                 f"({d:.6g} m): the line would be stretched by "
                                                 f"{100 * (d / line.length - 1):.3g} %"))
        if line.end_a.attach == "free" and line.end_a.position is None and line.end_b.attach == "free":
            errors.append((f"{base}.end_a.position", "a line with two free ends needs the position of end A"))
    an = sc.analysis
    if an.dynamics.enabled and an.dynamics.duration > 0 and an.dynamics.output_interval is not None:
        if an.dynamics.output_interval > an.dynamics.duration:
            errors.append(("analysis.dynamics.output_interval",
                           f"{an.dynamics.output_interval} s is longer than the duration {an.dynamics.duration} s"))
    return errors


def validate_dict(obj: Any, _raw: Callable | None = None) -> Scenario:
    """Validate a plain dict into a Scenario, raising ScenarioError on any problem."""
    if not isinstance(obj, dict):
        raise ScenarioError([("", f"a scenario must be a JSON/YAML object (mapping), got {type(obj).__name__}")])
    raw = _raw or (lambda o: super(Scenario, Scenario).model_validate(o))
    try:
        sc = raw(obj)
    except ValidationError as exc:
        raise ScenarioError(validation_errors(exc)) from None
    errors = check_references(sc)
    if errors:
        raise ScenarioError(errors)
    return sc


def parse_text(text: str | bytes, fmt: str = "auto") -> Any:
    """Parse JSON or YAML text into plain Python data (ScenarioError if it is not)."""
    if isinstance(text, bytes):
        text = text.decode("utf-8")
    if fmt == "json" or (fmt == "auto" and text.lstrip().startswith(("{", "["))):
        try:
            return json.loads(text, parse_constant=lambda c: float("nan"))
        except json.JSONDecodeError as exc:
            raise ScenarioError([("", f"invalid JSON at line {exc.lineno} column {exc.colno}: {exc.msg}")]) from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1} column {mark.column + 1}" if mark is not None else ""
        raise ScenarioError([("", f"invalid YAML{where}: {getattr(exc, 'problem', exc)}")]) from None


def set_path(data: dict, path: str, value: Any) -> None:
    """Set ``data[a][b][c] = value`` for a dotted path ``a.b.c`` (list indices allowed)."""
    keys = path.split(".")
    cur: Any = data
    for i, k in enumerate(keys[:-1]):
        if isinstance(cur, list):
            try:
                cur = cur[int(k)]
            except (ValueError, IndexError):
                raise ScenarioError([(path, f"'{k}' is not a valid index")]) from None
            continue
        if not isinstance(cur, dict):
            raise ScenarioError([(path, f"'{'.'.join(keys[:i])}' is not a mapping")])
        if k not in cur or cur[k] is None:
            cur[k] = {}
        cur = cur[k]
    last = keys[-1]
    if isinstance(cur, list):
        try:
            cur[int(last)] = value
        except (ValueError, IndexError):
            raise ScenarioError([(path, f"'{last}' is not a valid index")]) from None
    elif isinstance(cur, dict):
        cur[last] = value
    else:
        raise ScenarioError([(path, "parent is not a mapping")])


def apply_overrides(data: dict, overrides: dict[str, Any] | None) -> dict:
    """A deep copy of ``data`` with dotted-path overrides applied."""
    out = copy.deepcopy(data)
    for path, value in (overrides or {}).items():
        set_path(out, path, value)
    return out


def load_scenario(source: str | os.PathLike | dict | Scenario, overrides: dict[str, Any] | None = None) -> Scenario:
    """Load a scenario from a JSON/YAML file path, JSON/YAML text, a dict or a Scenario.

    ``overrides`` maps dotted paths to values (``{"lines.pipe.elements": 40}``) applied
    before validation, as a base file + load case.
    """
    if isinstance(source, Scenario):
        if not overrides:
            return source
        source = source.model_dump(mode="json")
    if isinstance(source, dict):
        data = source
    else:
        text_like = isinstance(source, str) and ("\n" in source or source.lstrip().startswith("{"))
        if text_like:
            data = parse_text(source)
        else:
            path = Path(source)
            if not path.exists():
                raise ScenarioError([("", f"scenario file not found: {path}")])
            fmt = "json" if path.suffix.lower() == ".json" else "auto"
            data = parse_text(path.read_text(encoding="utf-8"), fmt)
    if overrides:
        if not isinstance(data, dict):
            raise ScenarioError([("", "a scenario must be a mapping")])
        data = apply_overrides(data, overrides)
    return validate_dict(data)
