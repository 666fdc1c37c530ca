"""The scenario schema: the user's words, one pydantic v2 model.

Every model forbids unknown keys and NaN/inf. SI units throughout (m, s, kg, N, Pa),
angles in degrees where the field name says ``_deg``, z up, still water at
``environment.water.surface_level`` (0 by default). Units are written into the JSON
Schema (``units`` key of each property, ``1`` for a dimensionless number or a count) and
at the end of each description in brackets (``[-]`` for ``1``), by :func:`_units`, so the
HTTP service and the docs show them; every number has one.

Cross-references (a line's ``type``, an end's ``attach``) are checked after the
field-level validation by :func:`rfesim.scenario.check_references`.
"""
from __future__ import annotations

import math
import types
import typing
from typing import Annotated, Any, Literal, Union

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field, PrivateAttr, field_validator, model_validator


class FieldError(ValueError):
    """A validation error raised inside a model validator that names a sub-field.

    The scenario loader appends ``field`` to the location pydantic reports, so the
    user sees ``line_types.pipe12.wall_thickness: ...`` rather than only the parent.
    """

    def __init__(self, field: str, reason: str):
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")


def unit_label(u: str) -> str:
    """A field's unit as its description shows it in brackets: the ``units`` of its JSON
    Schema, with ``1`` (dimensionless) written ``-``, also as a table's column ("s, 1" ->
    "s, -")."""
    return ", ".join("-" if c.strip() == "1" else c for c in u.split(", "))


def _units(u: str, description: str, limit: str | None = None, floor: str | None = None, **kw):
    """A pydantic Field with its SI unit in the JSON Schema (``units``) and at the end of its
    description in brackets (:func:`unit_label`): the description's text itself names no unit.
    ``u`` is ``1`` for a dimensionless number (a ratio, a coefficient, a direction of any
    length, a count, a seed), a table's column units "s, m" (rows [t, x]), or "N (s, N)" for
    a number or a table. ``limit`` is the reason for its upper bound (``le``/``lt``), added to
    the message when a value exceeds it, ``floor`` the reason for its lower bound
    (``ge``/``gt``), added when a value is below it (rfesim.scenario.load._reason)."""
    extra = {"units": u} if limit is None else {"units": u, "limit": limit}
    if floor is not None:
        extra["floor"] = floor
    return Field(description=f"{description} [{unit_label(u)}]", json_schema_extra=extra, **kw)


# Upper bounds of physical magnitudes, with the reasons given when a value exceeds them (the
# ``limit`` of _units): beyond any real engineering input, with room for "rigid" or "unlimited"
# stand-ins (a modulus of 1e15 Pa and a stiffness of 1e15 N/m pass), and far below the sizes at
# which the arithmetic with them overflows (float64 ends at 1.8e308; the SDE stiffness grows as
# E I / dx^3 with dx down to MIN_SEGMENT = 1e-6 m): a number past them has the wrong units.
MAX_MODULUS = 1.0e20                # Pa
MIN_MODULUS = 1.0e5                 # Pa
MODULUS_FLOOR = ("a tenth of the softest rubber (about 1e6 Pa), far below any pipe, rope, cable or member "
                 "(polyurethane 1e7 to 1e8 Pa, polyester rope fibre 1e10 Pa, steel 2.1e11 Pa): a line that soft "
                 "has no static shape to converge to (check the units, Pa)")
MODULUS_LIMIT = ("1e8 times the stiffest material (diamond, 1.2e12 Pa), room enough for a 'rigid' stand-in (1e15 Pa "
                 "passes), and the element stiffness E*I/dx^3 stays far from overflow (check the units, Pa)")
MAX_SECTION_STIFFNESS = 1.0e22      # N (EA, GA), N*m^2 (EI, GJ)
SECTION_STIFFNESS_LIMIT = ("a 60 in steel pipe has EA = 5e10 N and EI = 1.3e10 N*m^2, so this leaves room for a "
                           "'rigid' stand-in, and the element stiffness stays far from overflow (check the units)")
MAX_STIFFNESS = 1.0e20              # N/m, N/m/m, N*m/rad
STIFFNESS_LIMIT = ("real contacts, pads and springs are below 1e12, so this leaves room for a 'rigid' stand-in "
                   "(1e15 passes), and the forces stay far from overflow (check the units)")
MAX_DAMPING = 1.0e20                # N*s/m, N*s, N*m^2*s, N*m*s/rad
DAMPING_LIMIT = ("critical damping of 1e12 kg on a 1e15 N/m spring is 6e13 N*s/m, so this leaves room for any "
                 "damper or 'locked' stand-in, and the forces stay far from overflow (check the units)")
MAX_DENSITY = 1.0e6                 # kg/m^3
DENSITY_LIMIT = ("the densest material (osmium) has 22,600 kg/m^3, so this leaves room for equivalent densities "
                 "that lump coatings or attachments (check the units, kg/m^3)")
MAX_MASS = 1.0e12                   # kg
MASS_LIMIT = ("20,000 times the heaviest offshore lift (about 50,000 t, 5e7 kg), room enough for an immovable "
              "stand-in (check the units, kg)")
MAX_MASS_PER_LENGTH = 1.0e8         # kg/m
MASS_PER_LENGTH_LIMIT = ("a solid steel bar 10 m across has 6.2e5 kg/m, so this leaves room for any line or member "
                         "(check the units, kg/m)")
MAX_INERTIA = 1.0e18                # kg*m^2
INERTIA_LIMIT = ("the largest mass (1e12 kg) at a radius of gyration of 1 km, room enough for any body, drum or "
                 "stand-in (check the units, kg*m^2)")
MAX_ROTARY_INERTIA = 1.0e10          # kg*m (kg*m^2 per metre of line)
ROTARY_INERTIA_LIMIT = ("the largest mass per length (1e8 kg/m) at a radius of gyration of 10 m (check the "
                        "units, kg*m: kg*m^2 per metre of line)")
MAX_FORCE = 1.0e15                  # N, N*m
FORCE_LIMIT = ("a million times the weight of the heaviest offshore lift (5e8 N), room enough for any load, holding "
               "capacity or brake, and the forces stay far from overflow (check the units)")
MAX_LENGTH = 1.0e7                  # m
# Lower bounds of the magnitudes a scene divides by (a mass, a density, a gravity, a contact
# stiffness), with the reasons given when a value is below them (the ``floor`` of _units): far
# below any real input, and far above the sizes at which the arithmetic with them divides by
# zero or overflows (1e-300 kg/m^3 gave a ZeroDivisionError from inside the solver).
MIN_GRAVITY = 1.0e-3                # m/s^2, unless 0 (no gravity)
GRAVITY_FLOOR = "far below the gravity of any place a scene is in (the Moon has 1.62 m/s^2; check the units, m/s^2)"
MIN_DENSITY = 1.0                   # kg/m^3
DENSITY_FLOOR = ("about the density of air (1.2 kg/m^3): no pipe wall, rope or cable is lighter, and a line of "
                 "no mass cannot be integrated (check the units, kg/m^3)")
MIN_MASS_PER_LENGTH = 1.0e-4        # kg/m
MASS_PER_LENGTH_FLOOR = ("a tenth of a gram per metre, lighter than a thin fishing line: a line of no mass cannot "
                         "be integrated (check the units, kg/m)")
MIN_MASS = 1.0e-3                   # kg
MASS_FLOOR = ("a gram: no payload, link or body is lighter, and a body of no mass cannot be integrated (check the "
              "units, kg)")
MIN_RADIUS_OF_GYRATION = 1.0e-3     # m
MIN_INERTIA = 1.0e-9                # kg*m^2, a gram at a millimetre
INERTIA_FLOOR = ("a gram at a millimetre (1e-9 kg*m^2): a body that does not resist turning cannot be integrated "
                 "(check the units)")
MIN_SEABED_STIFFNESS = 1.0          # N/m/m
SEABED_STIFFNESS_FLOOR = ("soft clays give 1e4 to 1e6 N/m/m; on a softer seabed a line of 1 kN/m wet weight would sink "
                          "more than 1 km into it (check the units, N/m/m)")
LENGTH_LIMIT = "10,000 km, longer than any line, rope or structure (check the units, metres)"
MAX_COEFFICIENT = 10.0              # drag and added-mass coefficients of a line [-]
COEFFICIENT_LIMIT = ("the coefficients of slender and bluff shapes lie between 0 and about 2 (a coefficient, "
                     "not a force or a mass)")
MAX_ANGLE_DEG = 1.0e6               # deg
ANGLE_LIMIT = ("2,800 turns: no heading, phase or angle of a scene is larger, and the sine of a larger angle "
               "loses its digits (check the units, degrees)")
MAX_TIME = 1.0e7                    # s, the longest duration
TIME_LIMIT = "the longest simulated duration (116 days), so no time of a scene is later (check the units, seconds)"
MAX_SPEED = 1.0e4                   # m/s
SPEED_LIMIT = ("seven times the speed of sound in water: no current, vessel, winch or payout is faster "
               "(check the units, m/s)")
MAX_RATE = 1.0e5                    # rad/s
RATE_LIMIT = ("16,000 turns a second: no wave frequency, drum or joint turns faster (check the units, rad/s)")
MAX_AREA = 1.0e8                    # m^2
AREA_LIMIT = "a square 10 km on a side, larger than any body (check the units, m^2)"
MAX_VOLUME = 1.0e12                 # m^3
VOLUME_LIMIT = "a cube 10 km on a side, larger than any body (check the units, m^3)"
MAX_GAIN = 1.0e4                    # 1/s (its square for 1/s^2)
GAIN_LIMIT = ("a loop that closes in 0.1 ms, far faster than any winch drive can follow (check the units: "
              "a gain per second)")

# The bound of a field by its unit, for the fields that declare no bound of their own (no
# ``le``/``lt``): every number of a number, a vector or a list of them, checked by _Strict in
# size (a position -2e7 m is as wrong as +2e7 m). A number past it has the wrong units, or
# would make the arithmetic lose its digits (the sine of 1e20 degrees) or overflow.
UNIT_BOUNDS = {
    "m": (MAX_LENGTH, "10,000 km, farther than any point, line or structure of a scene reaches (check the units, "
                      "metres)"),
    "deg": (MAX_ANGLE_DEG, ANGLE_LIMIT),
    "s": (MAX_TIME, TIME_LIMIT),
    "m/s": (MAX_SPEED, SPEED_LIMIT),
    "rad/s": (MAX_RATE, RATE_LIMIT),
    "m/s or rad/s": (MAX_RATE, "the bound of both speeds (m/s) and turning rates (rad/s) (check the units)"),
    "rad/s or m/s": (MAX_RATE, "the bound of both speeds (m/s) and turning rates (rad/s) (check the units)"),
    "rad or m": (MAX_LENGTH, "10,000 km, or 1.6 million turns (check the units, metres or radians)"),
    "m or rad": (MAX_LENGTH, "10,000 km, or 1.6 million turns (check the units, metres or radians)"),
    "m^2": (MAX_AREA, AREA_LIMIT),
    "m^3": (MAX_VOLUME, VOLUME_LIMIT),
    "N": (MAX_FORCE, FORCE_LIMIT),
    "N*m": (MAX_FORCE, FORCE_LIMIT),
    "N or N*m": (MAX_FORCE, FORCE_LIMIT),
    "kg": (MAX_MASS, MASS_LIMIT),
    "kg*m^2": (MAX_INERTIA, INERTIA_LIMIT),
    "1/s": (MAX_GAIN, GAIN_LIMIT),
    "1/s^2": (MAX_GAIN ** 2, GAIN_LIMIT),
    "Pa": (MAX_MODULUS, MODULUS_LIMIT),
    "m/m or deg/m": (1.0e3, "a heave RAO is about 1 m/m at long waves and a roll RAO a few deg/m near its "
                            "resonance (check the units: motion per metre of wave amplitude)"),
}


def bound_text(limit: float) -> str:
    """A bound as the messages show it: integers and whole numbers below 1e12 in full, as
    pydantic writes them (100000), other numbers in exponent form (1e+20, not its 21 digits)."""
    if isinstance(limit, int) or (abs(limit) < 1e12 and float(limit).is_integer()):
        return str(int(limit))
    return f"{limit:.6g}"


def upper_bound(value: float, limit: float, unit: str, why: str, signed: bool = False) -> str | None:
    """The reason ``value`` exceeds ``limit`` (its size, if ``signed``), worded as for a field's
    ``le`` (rfesim.scenario.load._reason), or None: for the numbers of lists and of number-or-list
    fields, which cannot carry ``le``."""
    if (abs(value) if signed else value) <= limit:
        return None
    unit = f" {unit}" if unit != "1" else ""
    bound = f"lie between {bound_text(-limit)} and {bound_text(limit)}" if signed else \
        f"be less than or equal to {bound_text(limit)}"
    return f"must {bound}{unit} (got {value!r}): {why}"


def yaml_bool_hint(value: bool) -> str:
    """Why a boolean may stand where text was meant: YAML 1.1 (PyYAML) reads the unquoted
    words yes/no/on/off/true/false as booleans."""
    words = "yes, on and true" if value else "no, off and false"
    example = "on" if value else "off"
    return (f"YAML reads the unquoted words {words} as the boolean {'true' if value else 'false'}: "
            f"quote the word (e.g. \"{example}\") to give it as text")


WAVE_PERIODS = (0.1, 3600.0)      # s, ocean gravity waves: ripples of a few cm to tsunamis


def _wave_period(value: float, what: str) -> float:
    lo, hi = WAVE_PERIODS
    if not lo <= value <= hi:
        raise ValueError(f"{value:.6g} s is outside the periods of ocean gravity waves ({lo:g} s to {hi:g} s): "
                         f"check the units of the {what} (seconds)")
    return value


def _allows_bool(annotation) -> bool:
    """True when a field's type accepts a boolean (bool itself, or a union with bool)."""
    if annotation is bool:
        return True
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _allows_bool(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return any(_allows_bool(a) for a in typing.get_args(annotation))
    return annotation is Any


def _alternatives(annotation) -> list:
    """The types a field's type accepts: the members of a union, Annotated unwrapped."""
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _alternatives(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return [t for a in typing.get_args(annotation) for t in _alternatives(a)]
    return [annotation]


def _bool_in_numbers(value, annotation, where: str) -> tuple[str, bool] | None:
    """(path, value) of the first boolean in the list ``value`` where ``annotation`` takes a
    number in a (nested) list, or None: pydantic's lax mode would read it as 1 or 0."""
    for member in _alternatives(annotation):
        if typing.get_origin(member) not in (list, tuple):
            continue
        args = [a for a in typing.get_args(member) if a is not Ellipsis] or [Any]
        for i, v in enumerate(value):
            item = args[min(i, len(args) - 1)]
            if _allows_bool(item):
                continue
            if isinstance(v, bool):
                if _is_numeric(item):
                    return f"{where}.{i}", v
            elif isinstance(v, (list, tuple)):
                found = _bool_in_numbers(v, item, f"{where}.{i}")
                if found is not None:
                    return found
    return None


def _show(value: Any) -> str:
    """A short repr of a user value for error messages."""
    if isinstance(value, dict):
        return "a mapping"
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, validate_default=True,
                              populate_by_name=True, json_schema_extra=lambda schema, cls: _schema_unit_bounds(schema))

    @model_validator(mode="before")
    @classmethod
    def _no_bool_for_numbers(cls, data):
        # pydantic's lax mode reads true/false as 1/0 for numbers: that is silent garbage
        # in a scenario (``elements: true``), so a boolean is accepted only where the
        # field is a boolean.
        if isinstance(data, dict):
            for name, value in data.items():
                field = cls.model_fields.get(name) if isinstance(name, str) else None
                if field is None or not isinstance(value, bool) or _allows_bool(field.annotation):
                    continue
                word = "true" if value else "false"
                if _is_numeric(field.annotation):
                    raise FieldError(name, f"must be a number, not the boolean {word}")
                raise FieldError(name, f"the boolean {word} is not allowed here ({yaml_bool_hint(value)})")
            # the same inside lists and tables of numbers (``rows: [[0, 80], [true, 90]]``)
            for name, value in data.items():
                field = cls.model_fields.get(name) if isinstance(name, str) else None
                if field is None or not isinstance(value, (list, tuple)):
                    continue
                found = _bool_in_numbers(value, field.annotation, name)
                if found is not None:
                    raise FieldError(found[0], f"must be a number, not the boolean {'true' if found[1] else 'false'}")
        return data

    @model_validator(mode="after")
    def _unit_bounds(self):
        # the fields without a bound of their own get the bound of their unit (UNIT_BOUNDS),
        # the cells of a table the bound of their column's unit
        for name, field in type(self).model_fields.items():
            extra = field.json_schema_extra
            if not isinstance(extra, dict) or "limit" in extra or "units" not in extra:
                continue
            scalar, columns = table_units(extra["units"])
            value = getattr(self, name)
            if columns is not None and isinstance(value, list) and value and all(isinstance(r, list) for r in value):
                _check_table(value, name, columns)
                continue
            if any(hasattr(m, "le") or hasattr(m, "lt") for m in field.metadata):
                continue
            lower = [v for m in field.metadata for v in (getattr(m, "ge", None), getattr(m, "gt", None))
                     if v is not None]
            positive = any(v > 0 for v in lower) or any(getattr(m, "gt", None) == 0 for m in field.metadata)
            for where, v in _numbers(value, name):
                _check_number(v, where, scalar, signed=not any(v >= 0 for v in lower))
                if scalar == "s" and positive and 0.0 < v < MIN_TIME:
                    raise FieldError(where, f"{v:g} s is shorter than {MIN_TIME:g} s, {MIN_TIME_LIMIT}")
        return self


MIN_TIME = 1.0e-6                   # s, the shortest period, ramp, step or table interval
MIN_TIME_LIMIT = ("a microsecond: no period, ramp, time step or table interval of a scene is shorter "
                  "(check the units, seconds)")


def table_units(units: str) -> tuple[str | None, list[str] | None]:
    """(unit of a single number, units of a table's columns) of a field's ``units``: "N (s, N)"
    (a number in N or rows [t, N]), "s, m/s" or "[1, Pa]" (rows only), "m" (numbers only)."""
    text = units.strip()
    if text.endswith(")") and " (" in text:
        scalar, rest = text[:-1].split(" (", 1)
        return scalar.strip(), [c.strip() for c in rest.split(",")]
    if text.startswith("[") and text.endswith("]"):
        return None, [c.strip() for c in text[1:-1].split(",")]
    if "," in text:
        return None, [c.strip() for c in text.split(",")]
    return text, None


def _check_number(v: float, where: str, unit: str | None, signed: bool) -> None:
    bound = UNIT_BOUNDS.get(unit) if unit is not None else None
    why = upper_bound(v, bound[0], unit, bound[1], signed=signed) if bound is not None else None
    if why:
        raise FieldError(where, why)


def _check_table(rows: list, name: str, columns: list[str]) -> None:
    """Every cell of a table within the bound of its column's unit (the last unit for the
    columns beyond the list), and the rows of a time column at least MIN_TIME apart."""
    for i, row in enumerate(rows):
        for j, v in enumerate(row):
            if isinstance(v, (int, float)) and not isinstance(v, bool):
                _check_number(float(v), f"{name}.{i}.{j}", columns[min(j, len(columns) - 1)], signed=True)
        if columns[0] == "s" and i and row and rows[i - 1]:
            dt = row[0] - rows[i - 1][0]
            if 0.0 < dt < MIN_TIME * (1.0 - 1e-6):          # 10.000001 - 10 is 1e-6 s within rounding
                raise FieldError(f"{name}.{i}.0", f"{row[0]:.17g} s is {dt:.3g} s after the row before: rows closer "
                                                  f"than {MIN_TIME:g} s, {MIN_TIME_LIMIT}")


def _schema_unit_bounds(schema: dict) -> None:
    """The bounds of UNIT_BOUNDS in the JSON Schema: ``maximum`` (and ``minimum`` for signed
    numbers) on the numbers of every property bounded by its unit, and its ``limit`` text."""
    for prop in schema.get("properties", {}).values():
        bound = UNIT_BOUNDS.get(prop.get("units"))
        if bound is None or "limit" in prop or _has_maximum(prop):
            continue
        prop["limit"] = bound[1]
        _bound_numbers(prop, bound[0])


def _has_maximum(node) -> bool:
    if isinstance(node, dict):
        return "maximum" in node or "exclusiveMaximum" in node or any(_has_maximum(v) for v in node.values())
    if isinstance(node, list):
        return any(_has_maximum(v) for v in node)
    return False


def _bound_numbers(node, limit: float) -> None:
    if isinstance(node, list):
        for v in node:
            _bound_numbers(v, limit)
    elif isinstance(node, dict):
        if node.get("type") in ("number", "integer"):
            node["maximum"] = limit
            if "minimum" not in node and "exclusiveMinimum" not in node:
                node["minimum"] = -limit
        for key in ("anyOf", "oneOf", "items", "prefixItems"):
            if key in node:
                _bound_numbers(node[key], limit)


def _numbers(value, where: str):
    """(path, number) of every number in a number or a (nested) list of them."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        yield where, float(value)
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            yield from _numbers(v, f"{where}.{i}")


def _is_numeric(annotation) -> bool:
    """True when a field's type is (optionally) int or float."""
    if annotation in (int, float):
        return True
    origin = typing.get_origin(annotation)
    if origin is Annotated:
        return _is_numeric(typing.get_args(annotation)[0])
    if origin in (Union, types.UnionType):
        return any(_is_numeric(a) for a in typing.get_args(annotation))
    return False


def _fixed_length_numbers(n: int, what: str):
    """A before-validator for a list of exactly ``n`` numbers (clear message, no booleans)."""

    def check(value):
        if isinstance(value, (list, tuple)):
            if len(value) != n:
                raise ValueError(f"must have exactly {n} numbers {what}, got {len(value)}")
            for i, v in enumerate(value):
                if isinstance(v, bool):
                    raise FieldError(str(i), f"must be a number, not the boolean {'true' if v else 'false'}")
        return value

    return BeforeValidator(check)


Vector3 = Annotated[list[float], _fixed_length_numbers(3, "[x, y, z]"), Field(min_length=3, max_length=3)]
TableRow = Annotated[list[float], _fixed_length_numbers(7, "[t, surge, sway, heave, roll, pitch, yaw]"),
                     Field(min_length=7, max_length=7)]

PositiveFloat = Annotated[float, Field(gt=0.0)]
NonNegativeFloat = Annotated[float, Field(ge=0.0)]


# --------------------------------------------------------------------------- environment

CurrentRow = Annotated[list[float], _fixed_length_numbers(2, "[z, speed]"), Field(min_length=2, max_length=2)]
FactorRow = Annotated[list[float], _fixed_length_numbers(2, "[t, factor]"), Field(min_length=2, max_length=2)]
ElevationRow = Annotated[list[float], _fixed_length_numbers(2, "[t, eta]"), Field(min_length=2, max_length=2)]
Vector2 = Annotated[list[float], _fixed_length_numbers(2, "[x, y]"), Field(min_length=2, max_length=2)]

_TOWARD = "from global x toward global y (about z): 0 = along +x, 90 = along +y, 180 = along -x"


class Current(_Strict):
    """Current: a horizontal speed profile over z flowing toward ``direction_deg``
    (rfesim.sea.current)."""

    profile: list[CurrentRow] = _units(
        "m, m/s", "Rows [z, speed]: z absolute, at or below the still water surface, each z once, rows in any "
                  "order; linear in z between rows, constant above the highest and below the lowest row",
        min_length=1)
    direction_deg: float = _units("deg", f"Direction the current flows TOWARD, {_TOWARD}", default=0.0)
    time_factor: list[FactorRow] | None = _units(
        "s, 1", "Optional rows [t, factor] multiplying the profile, times strictly increasing, linear in t, "
                "constant beyond the ends; a factor times the fastest speed of the profile at most 1e4 m/s. "
                "The factor is a slow modulation (a start-up ramp, a tide): the current's own dU/dt is not "
                "part of the water acceleration (no Morison inertia from it), as in MoorDyn and most codes",
        default=None, min_length=1)

    @model_validator(mode="after")
    def _tables(self):
        seen: dict[float, int] = {}
        for i, (z, _) in enumerate(self.profile):
            if z in seen:
                raise FieldError(f"profile.{i}", f"z = {z} m is given twice (rows {seen[z]} and {i})")
            seen[z] = i
        rows = self.time_factor or []
        for i in range(1, len(rows)):
            if not rows[i][0] > rows[i - 1][0]:
                raise FieldError(f"time_factor.{i}", f"time {rows[i][0]} s does not increase "
                                                     f"(previous {rows[i - 1][0]} s)")
        fastest = max(abs(v) for _, v in self.profile)
        for i, (_, f) in enumerate(rows):
            if abs(f) * fastest > MAX_SPEED:
                raise FieldError(f"time_factor.{i}.1", f"{f:g} times the fastest row of the profile ({fastest:g} m/s) "
                                                       f"is faster than {MAX_SPEED:g} m/s: {SPEED_LIMIT}")
        return self


class _Waves(_Strict):
    """Settings shared by every wave kind (rfesim.sea.waves)."""

    direction_deg: float = _units("deg", f"Direction the waves travel TOWARD, {_TOWARD}", default=0.0)
    stretching: Literal["wheeler", "none", "vertical", "linear"] = Field(
        "wheeler", description="Kinematics up to the instantaneous surface: wheeler (Airy profile stretched "
                               "over [-h, eta]), none (Airy expressions at the actual z), vertical (constant "
                               "above still water), linear (Taylor extrapolation above still water)")
    ramp_duration: float = _units("s", "The waves are ramped in with 0.5*(1-cos(pi*t/T)) over this time "
                                  "(an RAO vessel motion follows the same ramp)", default=0.0, ge=0.0)
    deep_water: bool = Field(False, description="Deep-water dispersion and kinematics (k = omega^2/g, exp(k z)) "
                                                "even with a finite depth; needed when no depth is given")
    kinematics_cutoff: float = _units(
        "1", "Deep points skip the waves: where the bound of every component's velocity and acceleration "
             "together, whatever the surface elevation, is below this fraction of the sea's bound sum "
             "|u_j| (1 + omega_j), the wave kinematics are zero and the elevation is not summed "
             "(docs/theory.md, 'Wave kinematics cut-off at depth'); 0: every point is summed",
        default=0.0, ge=0.0, le=1e-3)


class _RegularWaves(_Waves):
    """What the regular waves (airy, stokes5) share: a period within ocean gravity waves."""

    period: float = _units("s", "Wave period, 0.1 to 3600 (ocean gravity waves)", gt=0.0)

    @field_validator("period")
    @classmethod
    def _period(cls, value):
        return _wave_period(value, "wave period")


class AiryWaves(_RegularWaves):
    """A regular linear wave: eta = H/2 cos(omega t - k (x cos b + y sin b) + phase)."""

    kind: Literal["airy"]
    height: float = _units("m", "Wave height H, crest to trough (amplitude H/2); at most the breaking limit "
                                "H/L = tanh(kh)/7 of its wave length L", gt=0.0)
    phase_deg: float = _units("deg", "Phase: eta = H/2*cos(2*pi*t/period - k*(x*cos(b) + y*sin(b)) + phase)",
                              default=0.0)


class Stokes5Waves(_RegularWaves):
    """A regular Stokes 5th-order wave (Fenton 1985): height crest to trough, period, zero
    Eulerian mean current; five harmonics (rfesim.sea.stokes5). Refused beyond the breaking
    limit and in shallow water (Ursell number > 40)."""

    kind: Literal["stokes5"]
    height: float = _units("m", "Wave height H, crest to trough; below the breaking limit of the wave, and "
                                "refused in shallow water (Ursell number above 40)", gt=0.0)
    phase_deg: float = _units("deg", "Phase of the fundamental (harmonic j has j times it)", default=0.0)
    stretching: Literal["wheeler", "none", "vertical", "linear"] = Field(
        "none", description="Stokes kinematics hold up to the actual surface: none (default) evaluates them "
                            "there; the other methods as for airy")


class _SpectrumWaves(_Waves):
    hs: float = _units("m", "Significant wave height (4 sqrt(m0)); the sea's steepness 2*pi*hs/(g*tp^2) at "
                            "most the DNV-RP-C205 limit for its tp", gt=0.0)
    tp: float = _units("s", "Spectral peak period, 0.1 to 3600 (ocean gravity waves)", gt=0.0)
    seed: int = _units("1", "Seed of the random frequencies and phases (numpy default_rng): the same seed, the "
                            "same sea", default=0, ge=0, le=2 ** 63 - 1)
    components: int = _units("1", "Number of wave components", default=200, ge=1, le=20000)
    discretisation: Literal["geometric", "equal-spacing", "equal-energy"] = Field(
        "geometric", description="Frequency bins: geometric (constant d_omega/omega), equal-spacing or "
                                 "equal-energy; each component has the energy of its bin and a random "
                                 "frequency inside it")
    omega_min: float | None = _units("rad/s", "Lowest frequency (default 0.5*2*pi/tp), 0.000873 to 628.3 (ocean "
                                              "gravity waves), below the peak 2*pi/tp and omega_max",
                                     default=None, gt=0.0)
    omega_max: float | None = _units("rad/s", "Highest frequency (default 10*2*pi/tp), 0.000873 to 628.3 (ocean "
                                              "gravity waves), above the peak 2*pi/tp and omega_min",
                                     default=None, gt=0.0)

    @field_validator("tp")
    @classmethod
    def _tp(cls, value):
        return _wave_period(value, "peak period")

    @field_validator("omega_min", "omega_max")
    @classmethod
    def _omega(cls, value):
        # the default range, 0.5 to 10 times the peak frequency, at the longest and shortest tp
        lo, hi = 0.5 * 2.0 * math.pi / WAVE_PERIODS[1], 10.0 * 2.0 * math.pi / WAVE_PERIODS[0]
        if value is not None and not lo <= value <= hi:
            raise ValueError(f"{value:.6g} rad/s is outside the frequencies of ocean gravity waves ({lo:.3g} to "
                             f"{hi:.3g} rad/s: periods of {2.0 * math.pi / hi:.3g} s to {2.0 * math.pi / lo:.4g} s): "
                             f"check the units (rad/s)")
        return value

    @model_validator(mode="after")
    def _range(self):
        wp = 2.0 * math.pi / self.tp
        lo = self.omega_min if self.omega_min is not None else 0.5 * wp
        hi = self.omega_max if self.omega_max is not None else 10.0 * wp
        if not hi > lo:
            raise FieldError("omega_max", f"{hi:.6g} rad/s must exceed omega_min {lo:.6g} rad/s")
        if not lo < wp < hi:
            raise FieldError("omega_min" if lo >= wp else "omega_max",
                             f"the range [{lo:.6g}, {hi:.6g}] rad/s must contain the peak 2*pi/tp = {wp:.6g} rad/s")
        return self


class JonswapWaves(_SpectrumWaves):
    """JONSWAP spectrum (DNV-RP-C205 form), random phases; normalised to the area Hs^2/16
    exactly where DNV's A_gamma misses it by more than 1 % (gamma above 6.3, other sigmas)."""

    kind: Literal["jonswap"]
    gamma: float | None = _units("1", "Peak enhancement factor (default: the DNV-RP-C205 rule from "
                                      "tp/sqrt(hs))", default=None, ge=1.0, le=10.0)
    sigma_a: float = _units("1", "Spectral width below the peak", default=0.07, gt=0.0, le=1.0)
    sigma_b: float = _units("1", "Spectral width above the peak", default=0.09, gt=0.0, le=1.0)


class PiersonMoskowitzWaves(_SpectrumWaves):
    """Pierson-Moskowitz spectrum (JONSWAP with gamma = 1), random phases."""

    kind: Literal["pierson-moskowitz"]


class TimeSeriesWaves(_Waves):
    """A recorded (or designed) elevation time series at one point, split into its Fourier
    components, which then travel as long-crested linear waves."""

    kind: Literal["time-series"]
    rows: list[ElevationRow] = _units("s, m", "Rows [t, eta], times strictly increasing at equal steps: the "
                                              "elevation above still water at origin (repeats with the record "
                                              "length)", min_length=4)
    origin: Vector2 = _units("m", "Point [x, y] where the record was taken", default=[0.0, 0.0])
    omega_max: float | None = _units("rad/s", "Drop the components above this frequency", default=None, gt=0.0)

    @model_validator(mode="after")
    def _steps(self):
        t = [r[0] for r in self.rows]
        dt = t[1] - t[0]
        for i in range(1, len(t)):
            if not t[i] > t[i - 1]:
                raise FieldError(f"rows.{i}", f"time {t[i]} s does not increase (previous {t[i - 1]} s)")
            if abs((t[i] - t[i - 1]) - dt) > 1e-6 * dt:
                raise FieldError(f"rows.{i}", f"time step {t[i] - t[i - 1]:.9g} s differs from the first step "
                                              f"{dt:.9g} s: the record must be sampled at equal steps")
        return self


Waves = Annotated[Union[AiryWaves, Stokes5Waves, JonswapWaves, PiersonMoskowitzWaves, TimeSeriesWaves], Field(discriminator="kind")]


class Water(_Strict):
    """Sea water: density, depth, still-water level, current and waves."""

    density: float = _units("kg/m^3", "Mass density of sea water", default=1025.0, gt=0.0,
                            le=MAX_DENSITY, limit=DENSITY_LIMIT)
    depth: float | None = _units("m", "Water depth below the still surface (seabed at surface_level - depth); "
                                      "with a seabed, it must match the seabed's z (a profile's at the global "
                                      "origin)",
                                 default=None, gt=0.0, le=1.0e5,
                                 limit="no sea is deeper than about 11 km (check the units, metres)")
    surface_level: float = _units("m", "z of the still water surface", default=0.0)
    current: Current | None = Field(None, description="Current profile; omit for none")
    waves: Waves | None = Field(None, description="Waves: kind airy, stokes5, jonswap, pierson-moskowitz or time-series; "
                                                  "omit for still water")

    @model_validator(mode="after")
    def _current_in_water(self):
        if self.current is not None:
            for i, (z, _) in enumerate(self.current.profile):
                if z > self.surface_level + 1e-9 * max(1.0, abs(self.surface_level)):
                    raise FieldError(f"current.profile.{i}", f"z = {z} m is above the still water surface "
                                                             f"(z = {self.surface_level} m): profile heights are "
                                                             f"absolute z, negative below the surface")
        return self


ProfilePoint = Annotated[list[float], _fixed_length_numbers(2, "[distance, z]"), Field(min_length=2, max_length=2)]


PROFILE_HOLD = 1000.0   # m, length of the flat rows that hold a seabed profile's end depths (any > 0 will do)


class Seabed(_Strict):
    """Seabed: a flat plane, a sloped plane or a 2-D profile, with a normal spring-damper and
    Coulomb friction (spring-slider stick/slip) per unit length of line in contact."""

    z: float | None = _units("m", "z of the seabed at the global origin (default: surface_level - water.depth), "
                                  "below the still water surface; not with a profile, and with water.depth "
                                  "given it must match it", default=None)
    slope_deg: float = _units("deg", "Inclination of a plane seabed (0: horizontal)", default=0.0, gt=-60.0, lt=60.0)
    slope_direction_deg: float = _units("deg", "Direction (from global x, about z) in which a sloped seabed rises",
                                        default=0.0)
    profile: list[ProfilePoint] | None = _units(
        "m", "2-D seabed profile: rows [horizontal distance along profile_direction_deg from the global origin, "
             "seabed z], distances strictly increasing, no segment steeper than 60 degrees; linear between rows, "
             "flat beyond the table at the depth of its first and last rows (every row must lie below the water "
             "surface, so the seabed does everywhere); not with slope_deg or z", default=None, min_length=2)
    profile_direction_deg: float = _units("deg", "Direction of the profile's distance axis (from global x); "
                                                 "only with a profile", default=0.0)
    normal_stiffness: float = _units("N/m/m", "Normal contact stiffness per unit length of line",
                                     default=1.0e5, ge=MIN_SEABED_STIFFNESS, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT,
                                     floor=SEABED_STIFFNESS_FLOOR)
    damping_ratio: float = _units("1", "Normal contact damping as a fraction of critical for the line's mass per "
                                       "length on the seabed spring", default=0.2, ge=0.0, le=10.0)
    friction: float = _units("1", "Coulomb friction coefficient, axial and lateral", default=0.0, ge=0.0, le=5.0)
    friction_axial: float | None = _units("1", "Axial friction coefficient (default: friction)", default=None,
                                          ge=0.0, le=5.0)
    friction_lateral: float | None = _units("1", "Lateral friction coefficient (default: friction)", default=None,
                                            ge=0.0, le=5.0)
    friction_stiffness: float | None = _units(
        "N/m/m", "Tangential stiffness of the stick spring per unit length in contact: a sticking line moves "
                 "friction_force / (stiffness * length) before it slides, its mobilisation displacement "
                 "(default: 0.1 * normal_stiffness; a stiffer spring holds the line closer but makes the "
                 "implicit integrator's Newton iterations work harder at stick/slip changes)",
        default=None, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    friction_damping_ratio: float = _units(
        "1", "Damping of the stick spring as a fraction of critical for the line's mass per length on it "
             "(dynamics). At 1 a load that comes on at once (a pipe set down on a slope) takes the line to its "
             "mobilisation displacement without ringing; the friction then peaks e^-2 = 13.5 % above the load "
             "while it settles. 0 leaves the spring undamped: it overshoots to twice the load (slipping "
             "at half the friction limit) and rings",
        default=1.0, ge=0.0, le=10.0)

    @model_validator(mode="after")
    def _geometry(self):
        if self.profile is not None:
            if self.slope_deg != 0.0:
                raise FieldError("profile", "give either a slope or a profile, not both")
            if self.z is not None:
                raise FieldError("z", "a profile gives the seabed z itself; leave z out")
            if self.slope_direction_deg != 0.0:
                raise FieldError("slope_direction_deg", "a profile has no slope direction: its distance axis is "
                                                        "profile_direction_deg")
        elif self.profile_direction_deg != 0.0:
            raise FieldError("profile_direction_deg", "applies to a seabed profile only: a sloped plane rises "
                                                      "along slope_direction_deg")
        if self.profile is not None:
            for i in range(1, len(self.profile)):
                if not self.profile[i][0] > self.profile[i - 1][0]:
                    raise FieldError(f"profile.{i}", f"distance {self.profile[i][0]} m does not increase "
                                                     f"(previous {self.profile[i - 1][0]} m)")
            for i in range(1, len(self.profile)):
                d = self.profile[i][0] - self.profile[i - 1][0]
                if abs(self.profile[i][1] - self.profile[i - 1][1]) > math.tan(math.radians(60.0)) * d:
                    raise FieldError(f"profile.{i}", "the profile is steeper than 60 degrees here")
        return self

    @property
    def mu_axial(self) -> float:
        return self.friction if self.friction_axial is None else self.friction_axial

    @property
    def mu_lateral(self) -> float:
        return self.friction if self.friction_lateral is None else self.friction_lateral

    def profile_table(self, z_origin: float | None) -> tuple[list[float], list[float], float]:
        """The seabed as (distances, z values, direction_deg), continued beyond its ends with
        the end slopes (rfesim.loads.seabed.seabed_height): a profile, with a flat row
        PROFILE_HOLD m beyond each end so that it holds its end depths (the user's profile may
        end on a slope that would rise through the water surface); or the plane through
        z_origin with the given slope (two points; the plane continues)."""
        if self.profile is not None:
            ds, zs = [p[0] for p in self.profile], [p[1] for p in self.profile]
            return ([ds[0] - PROFILE_HOLD] + ds + [ds[-1] + PROFILE_HOLD], [zs[0]] + zs + [zs[-1]],
                    self.profile_direction_deg)
        g = math.tan(math.radians(self.slope_deg))
        return [-1.0, 1.0], [z_origin - g, z_origin + g], self.slope_direction_deg


class Environment(_Strict):
    """The surroundings of the scene: gravity, the sea water (depth, current, waves) and the
    seabed the lines can rest on."""

    gravity: float = _units("m/s^2", f"Acceleration of gravity (acts along -z); 0 for none, else at least "
                            f"{MIN_GRAVITY:g} (waves need at least 0.1)", default=9.81, ge=0.0, le=100.0,
                            floor=GRAVITY_FLOOR)
    water: Water | None = Field(None, description="Sea water; omit for a scene in air")
    seabed: Seabed | None = Field(None, description="Seabed contact; omit for no seabed")

    @field_validator("gravity")
    @classmethod
    def _real_gravity(cls, value: float) -> float:
        if 0.0 < value < MIN_GRAVITY:
            raise ValueError(f"{value:.6g} m/s^2 is not a gravity: give 0 for none, or at least {MIN_GRAVITY:g} m/s^2, "
                             f"{GRAVITY_FLOOR}")
        return value

    @model_validator(mode="after")
    def _seabed_level(self):
        if self.seabed is not None and self.seabed.profile is not None:
            if self.water is not None:
                for i, (_, zp) in enumerate(self.seabed.profile):
                    if zp >= self.water.surface_level:
                        raise FieldError(f"seabed.profile.{i}", f"z = {zp} m is not below the water surface")
                if self.water.depth is not None:
                    # the waves take the depth at the global origin, where the profile has its own
                    expected = self.water.surface_level - self.seabed_z_at(0.0, 0.0)
                    if abs(self.water.depth - expected) > 1e-6 * max(1.0, expected):
                        raise FieldError("water.depth", f"{self.water.depth:.6g} m does not match the seabed profile, "
                                                        f"{expected:.6g} m deep at the global origin (where the "
                                                        f"waves take the depth); leave water.depth out")
            return self
        if self.seabed is not None and self.seabed.z is None:
            if self.water is None or self.water.depth is None:
                raise FieldError("seabed.z", "give the seabed level z or a water depth")
        if self.seabed is not None and self.seabed.z is not None and self.water is not None \
                and self.water.depth is not None:
            expected = self.water.surface_level - self.water.depth
            if abs(self.seabed.z - expected) > 1e-6 * max(1.0, self.water.depth):
                raise FieldError("seabed.z", f"{self.seabed.z} m does not match the water depth "
                                             f"{self.water.depth} m (seabed at z = {expected} m); give one of them")
        if self.seabed is not None and self.water is not None and self.seabed_z() >= self.water.surface_level:
            raise FieldError("seabed.z", "the seabed must lie below the water surface")
        return self

    @model_validator(mode="after")
    def _waves_fit_the_water(self):
        waves = self.water.waves if self.water is not None else None
        if waves is None:
            return self
        depth = self.water.depth
        if depth is None and self.seabed is not None:
            depth = self.water.surface_level - self.seabed_z()
        if depth is None and not waves.deep_water:
            raise FieldError("water.depth", "waves need the water depth (give water.depth or a seabed), or set "
                                            "water.waves.deep_water: true for deep-water waves")
        if self.gravity < 0.1:
            raise FieldError("gravity", f"waves need gravity: at least 0.1 m/s^2, got {self.gravity:.6g} m/s^2")
        try:
            self._check_wave_steepness(waves, None if waves.deep_water else depth)
        except (ArithmeticError, RuntimeError) as exc:
            # e.g. a dispersion relation that does not converge: the field, not a traceback
            raise FieldError("water.waves", f"the waves cannot be computed for this period, depth and gravity "
                                            f"({exc}): check their sizes and units") from None
        return self

    def _check_wave_steepness(self, waves, h: float | None) -> None:
        from ..sea.waves import breaking_steepness, sea_state_steepness_limit, wavelength
        if waves.kind == "airy":
            length = wavelength(waves.period, h, self.gravity)
            limit = breaking_steepness(waves.period, h, self.gravity)
            if waves.height / length > limit:
                raise FieldError("water.waves.height",
                                 f"{waves.height} m on a {length:.4g} m long wave (H/L = {waves.height / length:.4g}) "
                                 f"is steeper than the breaking limit H/L = tanh(kh)/7 = {limit:.4g}")
        elif waves.kind == "stokes5":
            from ..sea.stokes5 import stokes5
            try:
                stokes5(waves.height, waves.period, h, self.gravity)
            except ValueError as e:
                raise FieldError("water.waves.height", str(e)) from None
        elif waves.kind == "time-series":
            self._check_record(waves, h)
        elif waves.kind in ("jonswap", "pierson-moskowitz"):
            steepness = 2.0 * math.pi * waves.hs / (self.gravity * waves.tp ** 2)
            limit = sea_state_steepness_limit(waves.tp)
            if steepness > limit:
                raise FieldError("water.waves.hs",
                                 f"{waves.hs} m at tp = {waves.tp} s is steeper (2*pi*hs/(g*tp^2) = {steepness:.4g}) "
                                 f"than a sea state can be (DNV-RP-C205 limit {limit:.4g}): lower hs or raise tp")

    def _check_record(self, waves, h: float | None) -> None:
        """A wave elevation record: its elevation within the water depth and each of its
        Fourier components below Miche's breaking steepness H/L = tanh(kh)/7 (a record in
        millimetres, say, passes every other check and moves the water at km/s)."""
        import numpy as np
        from ..sea.waves import wave_components
        eta = np.array([r[1] for r in waves.rows], dtype=float)
        peak = int(np.argmax(np.abs(eta)))
        units = "check the units (metres) and the record"
        if h is not None and abs(eta[peak]) >= h:
            raise FieldError(f"water.waves.rows.{peak}",
                             f"elevation {eta[peak]:.6g} m is as large as the water depth {h:.6g} m: {units}")
        comp = wave_components(waves, h, self.gravity)
        if comp.amplitude.size == 0:
            return
        depth = math.inf if h is None else h
        steep = 2.0 * comp.amplitude * comp.wavenumber / (2.0 * math.pi)
        limit = np.tanh(comp.wavenumber * depth) / 7.0
        j = int(np.argmax(steep / limit))
        if steep[j] > limit[j]:
            raise FieldError("water.waves.rows",
                             f"the record's component of period {2.0 * math.pi / comp.omega[j]:.4g} s has a height of "
                             f"{2.0 * comp.amplitude[j]:.4g} m (H/L = {steep[j]:.4g}), steeper than the breaking limit "
                             f"H/L = tanh(kh)/7 = {limit[j]:.4g}: {units}, or drop the short components with "
                             f"omega_max")

    def seabed_z(self) -> float | None:
        """The z of the seabed plane, or None without a seabed."""
        if self.seabed is None:
            return None
        if self.seabed.profile is not None:
            return self.seabed_z_at(0.0, 0.0)
        if self.seabed.z is not None:
            return self.seabed.z
        return self.water.surface_level - self.water.depth

    def seabed_z_at(self, x: float, y: float) -> float | None:
        """The z of the seabed under the horizontal position (x, y), or None without a seabed."""
        if self.seabed is None:
            return None
        sb = self.seabed
        z0 = None if sb.profile is not None else (sb.z if sb.z is not None
                                                   else self.water.surface_level - self.water.depth)
        ds, zs, direction = sb.profile_table(z0)
        s = x * math.cos(math.radians(direction)) + y * math.sin(math.radians(direction))
        j = 0
        while j < len(ds) - 2 and s > ds[j + 1]:
            j += 1
        return zs[j] + (zs[j + 1] - zs[j]) / (ds[j + 1] - ds[j]) * (s - ds[j])


# --------------------------------------------------------------------------- vessels

DOF_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")


class HarmonicDof(_Strict):
    """One degree of freedom of a harmonic vessel motion: a sine of the given amplitude,
    period and phase about the rest position."""

    amplitude: float = _units("m or deg", "Amplitude: a length for surge, sway and heave, an angle for roll, "
                                          "pitch and yaw",
                              ge=0.0, le=1000.0, limit=("a vessel's largest motions in a storm are about 15 m of "
                                                        "heave and 30 deg of roll (check the units)"))
    period: float = _units("s", "Period", gt=0.0)
    phase_deg: float = _units("deg", "Phase: displacement = amplitude*sin(2*pi*t/period + phase)", default=0.0)


class FixedMotion(_Strict):
    """No motion: the vessel stays at its rest position and heading (a fixed frame, a quay
    or a platform)."""

    kind: Literal["fixed"] = "fixed"


class HarmonicMotion(_Strict):
    """Sum of sines per degree of freedom about the vessel's rest position."""

    kind: Literal["harmonic"]
    surge: HarmonicDof | None = None
    sway: HarmonicDof | None = None
    heave: HarmonicDof | None = None
    roll: HarmonicDof | None = None
    pitch: HarmonicDof | None = None
    yaw: HarmonicDof | None = None
    ramp_duration: float = _units("s", "The motion is ramped in with 0.5*(1-cos(pi*t/T)) over this time",
                                  default=0.0, ge=0.0)


START_TIME_DOC = ("Time of the table (file) at which the run starts: the vessel is at the row of time "
                  "start_time + t at the run's time t (a recorded file with times 1000 to 1100 s: 1000). Before "
                  "the first row and after the last the vessel is held still at that row: a table that starts "
                  "after the run's start or ends before its duration is warned about, one outside the run is "
                  "refused")


class TableMotion(_Strict):
    """A table of time vs the six displacements [t, surge, sway, heave, roll, pitch, yaw]."""

    kind: Literal["table"]
    rows: list[TableRow] = _units(
        "s, m, m, m, deg, deg, deg", "Rows [t, surge, sway, heave, roll, pitch, yaw], times strictly increasing "
                                     "(at least 4 rows for cubic interpolation)", min_length=2)
    interpolation: Literal["cubic", "linear"] = "cubic"
    ramp_duration: float = _units("s", "Ramp-in time of the motion", default=0.0, ge=0.0)
    start_time: float = _units("s", START_TIME_DOC, default=0.0, ge=-1.0e9, le=1.0e9)

    @model_validator(mode="after")
    def _times_increase(self):
        times = [r[0] for r in self.rows]
        for i in range(1, len(times)):
            if not times[i] > times[i - 1]:
                raise FieldError(f"rows.{i}", f"time {times[i]} s does not increase (previous {times[i - 1]} s)")
        if self.interpolation == "cubic" and len(times) < 4:
            raise FieldError("rows", "cubic interpolation needs at least 4 rows (or use interpolation 'linear')")
        return self


class RaoDof(_Strict):
    """Displacement RAO of one degree of freedom: one row per frequency (or period), one
    value per heading."""

    amplitude: list[list[float]] = _units("m/m or deg/m", "RAO amplitude, not negative: m/m for surge, sway and "
                                                          "heave, deg/m for roll, pitch and yaw; a row per "
                                                          "frequency (or period) of the table, a value per heading",
                                          min_length=1)
    phase_deg: list[list[float]] = _units("deg", "Phase LAG of the motion behind the wave elevation at the vessel "
                                                 "origin, same layout as amplitude", min_length=1)


class RaoTable(_Strict):
    """Displacement RAOs: motion_k(t) = sum_j a_j |RAO_k(omega_j, beta_j)| cos(omega_j t - k_j.x_v + phi_j -
    phase_k), relative to the wave elevation a_j cos(omega_j t - k_j.x_v + phi_j) at the vessel origin x_v."""

    description: str = Field("", max_length=10000, description="Free text: the vessel, loading condition, source")
    periods: list[float] | None = _units("s", "Wave periods of the table rows, greater than 0, strictly "
                                              "increasing or strictly decreasing (or give frequencies)", default=None)
    frequencies: list[float] | None = _units("rad/s", "Wave frequencies of the table rows, greater than 0, "
                                                      "strictly increasing or strictly decreasing (or give periods)",
                                             default=None)
    headings_deg: list[float] = _units("deg", "Relative wave headings of the columns, strictly increasing, over at "
                                              "most 360 (a symmetric table: within [0, 180]): wave direction "
                                              "(toward) minus vessel heading; 0 = waves travel along the vessel x "
                                              "axis (following seas), 90 = toward port (from starboard), 180 = "
                                              "head seas", min_length=1)
    symmetric: bool = Field(False, description="Port-starboard symmetric vessel: headings only in [0, 180]; "
                                               "heading b > 180 uses 360 - b with sway, roll and yaw reversed")
    surge: RaoDof | None = None
    sway: RaoDof | None = None
    heave: RaoDof | None = None
    roll: RaoDof | None = None
    pitch: RaoDof | None = None
    yaw: RaoDof | None = None

    @model_validator(mode="after")
    def _layout(self):
        if (self.periods is None) == (self.frequencies is None):
            raise FieldError("periods", "give either periods or frequencies (one per table row)")
        name = "periods" if self.periods is not None else "frequencies"
        rows = self.periods if self.periods is not None else self.frequencies
        if not rows:
            raise FieldError(name, "needs at least one value")
        for i, v in enumerate(rows):
            if not v > 0.0:
                raise FieldError(f"{name}.{i}", f"must be positive, got {v}")
        if len(rows) > 1:
            step = [rows[i] - rows[i - 1] for i in range(1, len(rows))]
            if not (all(s > 0 for s in step) or all(s < 0 for s in step)):
                raise FieldError(name, "must be strictly increasing or strictly decreasing")
        h = self.headings_deg
        for i in range(1, len(h)):
            if not h[i] > h[i - 1]:
                raise FieldError(f"headings_deg.{i}", f"{h[i]} deg does not increase (previous {h[i - 1]} deg)")
        if h[-1] - h[0] > 360.0:
            raise FieldError("headings_deg", "must span at most 360 deg")
        if self.symmetric and (h[0] < 0.0 or h[-1] > 180.0):
            raise FieldError("headings_deg", "a symmetric table has headings in [0, 180] deg")
        given = [d for d in DOF_NAMES if getattr(self, d) is not None]
        if not given:
            raise FieldError("heave", "give the RAOs of at least one degree of freedom (surge ... yaw)")
        for d in given:
            dof = getattr(self, d)
            for part in ("amplitude", "phase_deg"):
                table = getattr(dof, part)
                if len(table) != len(rows):
                    raise FieldError(f"{d}.{part}", f"has {len(table)} rows, expected one per {name[:-1]} "
                                                    f"({len(rows)})")
                for i, row in enumerate(table):
                    if len(row) != len(h):
                        raise FieldError(f"{d}.{part}.{i}", f"has {len(row)} values, expected one per heading "
                                                            f"({len(h)})")
                    if part == "amplitude" and any(v < 0.0 for v in row):
                        raise FieldError(f"{d}.{part}.{i}", "amplitudes must not be negative (use the phase)")
        return self


class RaoMotion(_Strict):
    """Vessel motion from displacement RAOs and the scene's waves (rfesim.sea.rao)."""

    kind: Literal["rao"]
    raos: RaoTable | None = Field(None, description="The RAO table inline (or give file)")
    file: str | None = Field(None, description="A JSON or YAML file with the RAO table (instead of raos); "
                                               "relative paths are taken from the scenario file's folder")
    _table: Any = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _source(self):
        if self.raos is None and self.file is None:
            raise FieldError("raos", "give one of the RAO table inline (raos) or a file with it (file)")
        if self.raos is not None and self.file is not None:
            raise FieldError("raos", "give the RAO table inline (raos) or a file, not both")
        if self.file is not None:
            from ..sea.rao import read_rao_file
            try:
                self._table = read_rao_file(self.file)
            except ValueError as exc:
                raise FieldError("file", str(exc)) from None
        return self

    def table(self) -> RaoTable:
        return self.raos if self.raos is not None else self._table


class CsvMotion(_Strict):
    """A CSV file of time vs the six displacements: columns t (s), surge, sway, heave (m),
    roll, pitch, yaw (deg); an optional header row names them (in any order); '#' starts
    a comment line."""

    kind: Literal["csv"]
    file: str = Field(..., description="The CSV file; relative paths are taken from the scenario file's folder")
    interpolation: Literal["cubic", "linear"] = "cubic"
    ramp_duration: float = _units("s", "Ramp-in time of the motion", default=0.0, ge=0.0)
    start_time: float = _units("s", START_TIME_DOC, default=0.0, ge=-1.0e9, le=1.0e9)
    _rows: Any = PrivateAttr(default=None)

    @model_validator(mode="after")
    def _read(self):
        from ..sea.motion_csv import read_motion_csv
        try:
            rows = read_motion_csv(self.file)
        except ValueError as exc:
            raise FieldError("file", str(exc)) from None
        if self.interpolation == "cubic" and rows.shape[0] < 4:
            raise FieldError("file", f"{self.file}: cubic interpolation needs at least 4 rows, got "
                                     f"{rows.shape[0]} (or use interpolation 'linear')")
        self._rows = rows
        return self

    def rows(self):
        """(n, 7) array: t, surge, sway, heave (m), roll, pitch, yaw (deg)."""
        return self._rows


def motion_table_span(motion) -> tuple[float, float] | None:
    """The run times (s) of the first and last rows of a ``table`` or ``csv`` vessel motion
    (its times less start_time), or None for other motions."""
    if motion.kind == "table":
        times = [motion.rows[0][0], motion.rows[-1][0]]
    elif motion.kind == "csv":
        rows = motion.rows()
        times = [float(rows[0, 0]), float(rows[-1, 0])]
    else:
        return None
    return times[0] - motion.start_time, times[1] - motion.start_time


def motion_table_warnings(sc) -> list[str]:
    """The ``table`` and ``csv`` vessel motions that do not cover the whole run: before the
    first row and after the last the vessel is held still at that row (after the last, the
    vessel stops dead: a shock in the lines it carries). One warning per vessel and end,
    naming the field; [] without dynamics."""
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0.0):
        return []
    out = []
    for name, vessel in sc.vessels.items():
        span = motion_table_span(vessel.motion)
        if span is None:
            continue
        first, last = span
        field = f"vessels.{name}.motion." + ("file" if vessel.motion.kind == "csv" else "rows")
        what = "file" if vessel.motion.kind == "csv" else "table"
        if first > 0.0:
            out.append(f"vessel '{name}' ({field}): the motion {what} starts at t = {first:.6g} s of the run "
                       f"(its time {first + vessel.motion.start_time:.6g} s, start_time "
                       f"{vessel.motion.start_time:.6g} s); before it the vessel stands still at the first row "
                       f"and then starts with the table's velocity at once")
        if last < float(dyn.duration):
            out.append(f"vessel '{name}' ({field}): the motion {what} ends at t = {last:.6g} s of the run "
                       f"(its time {last + vessel.motion.start_time:.6g} s), before the run's duration "
                       f"{float(dyn.duration):.6g} s; after it the vessel stops dead at the last row (a shock "
                       f"in the lines it carries): give rows up to the end of the run or a shorter duration")
    return out


VesselMotion = Annotated[Union[FixedMotion, HarmonicMotion, TableMotion, RaoMotion, CsvMotion],
                         Field(discriminator="kind")]


class Vessel(_Strict):
    """A vessel with prescribed motion. Its frame has its origin at `position` at rest,
    x forward, z up, turned by `heading_deg` about z. Motions are displacements of the
    vessel origin; rotations are ZYX (yaw, pitch, roll) about the vessel origin."""

    position: Vector3 = _units("m", "Rest position of the vessel origin", default=[0.0, 0.0, 0.0])
    heading_deg: float = _units("deg", "Heading of the vessel x axis from global x, about z", default=0.0)
    motion: VesselMotion = Field(default_factory=FixedMotion)


# --------------------------------------------------------------------------- line types

class ElasticMaterial(_Strict):
    """Linear elastic section: the SDE forces and moments are the section stiffnesses (EA,
    EI, GJ, GA) times the strains and curvatures, whatever their size."""

    kind: Literal["elastic"] = "elastic"


StrainStressRow = Annotated[list[float], _fixed_length_numbers(2, "[strain, stress]"),
                            Field(min_length=2, max_length=2)]


class ElastoplasticMaterial(_Strict):
    """Elasto-plastic pipe steel (section 8.4.2, rfesim.materials): the SDE bending moment
    follows the fibre-integrated moment-curvature of the pipe wall with kinematic
    hardening. Needs a pipe geometry and a line in the absolute formulation (the classical,
    modified and planar SDEs and chain links are elastic only: refused there). Laws: ``bilinear`` (yield_stress, hardening_ratio;
    0 is elastic-perfectly plastic), ``ramberg-osgood`` (eps = sigma/E + ro_offset *
    (sigma/yield_stress)^ro_n), ``table`` (rows [strain, stress], the first row the
    yield point on the elastic line, slopes not increasing; the last slope continues)."""

    kind: Literal["elastoplastic"]
    law: Literal["bilinear", "ramberg-osgood", "table"] = Field("bilinear", description="Stress-strain law")
    yield_stress: float | None = _units("Pa", "Yield stress (ramberg-osgood: stress at the plastic strain "
                                        "ro_offset; table: the first row's stress), greater than 0; bilinear and "
                                        "ramberg-osgood: below a tenth of the line type's youngs_modulus",
                                        default=None)
    hardening_ratio: float | None = _units("1", "Tangent modulus after yield over Young's modulus E_t/E of the "
                                                "bilinear law, in [0, 1); default 0", default=None)
    ro_n: float | None = _units("1", "Ramberg-Osgood exponent n, greater than 1", default=None)
    ro_offset: float | None = _units("1", "Ramberg-Osgood plastic strain at the yield stress, in (0, 0.1); "
                                          "default 0.002", default=None)
    table: list[StrainStressRow] | None = _units(
        "1, Pa", "Rows [strain, stress] of the monotonic curve: the first row the yield point (strain and stress "
                 "greater than 0, stress/strain within 1 % of youngs_modulus), strains strictly increasing, "
                 "stresses not decreasing, slopes not increasing (concave)", default=None)

    @model_validator(mode="after")
    def _law(self):
        used = {"bilinear": ("yield_stress", "hardening_ratio"),
                "ramberg-osgood": ("yield_stress", "ro_n", "ro_offset"),
                "table": ("table", "yield_stress")}[self.law]
        for name in ("hardening_ratio", "ro_n", "ro_offset", "table"):
            if getattr(self, name) is not None and name not in used:
                raise FieldError(name, f"is not used by law '{self.law}' (give law: "
                                       f"{'bilinear' if name == 'hardening_ratio' else 'ramberg-osgood' if name.startswith('ro_') else 'table'})")
        if self.law == "table":
            self._check_table()
        elif self.yield_stress is None:
            raise FieldError("yield_stress", f"law '{self.law}' needs a yield stress (Pa)")
        if self.yield_stress is not None and not self.yield_stress > 0.0:
            raise FieldError("yield_stress", f"must be greater than 0 Pa, got {self.yield_stress}")
        if self.law == "bilinear":
            if self.hardening_ratio is None:
                self.hardening_ratio = 0.0
            if not 0.0 <= self.hardening_ratio < 1.0:
                raise FieldError("hardening_ratio", f"must be in [0, 1) (E_t/E; 0: perfectly plastic), "
                                                    f"got {self.hardening_ratio}")
        if self.law == "ramberg-osgood":
            if self.ro_n is None:
                raise FieldError("ro_n", "law 'ramberg-osgood' needs the exponent ro_n (> 1)")
            if not self.ro_n > 1.0:
                raise FieldError("ro_n", f"must be greater than 1, got {self.ro_n}")
            if self.ro_offset is None:
                self.ro_offset = 0.002
            if not 0.0 < self.ro_offset < 0.1:
                raise FieldError("ro_offset", f"must be in (0, 0.1), got {self.ro_offset}")
        return self

    def _check_table(self):
        rows = self.table
        if not rows:
            raise FieldError("table", "law 'table' needs at least one row [strain, stress]")
        if rows[0][0] <= 0.0 or rows[0][1] <= 0.0:
            raise FieldError("table.0", "the first row is the yield point: strain and stress must be greater than 0")
        if self.yield_stress is not None and abs(self.yield_stress - rows[0][1]) > 1e-9 * rows[0][1]:
            raise FieldError("yield_stress", f"{self.yield_stress} Pa differs from the first table row's stress "
                                             f"{rows[0][1]} Pa (the yield point); give one of them")
        slope = rows[0][1] / rows[0][0]
        for j in range(1, len(rows)):
            (e0, s0), (e1, s1) = rows[j - 1], rows[j]
            if not e1 > e0:
                raise FieldError(f"table.{j}", f"strain {e1} does not increase (previous {e0})")
            if s1 < s0:
                raise FieldError(f"table.{j}", f"stress {s1} Pa decreases (previous {s0} Pa): softening is not "
                                               f"supported")
            new = (s1 - s0) / (e1 - e0)
            if new > slope * (1.0 + 1e-9):
                raise FieldError(f"table.{j}", f"slope {new:.6g} Pa is steeper than the previous segment's "
                                               f"{slope:.6g} Pa: the curve must be concave")
            slope = new
        self.yield_stress = rows[0][1]


Material = Annotated[Union[ElasticMaterial, ElastoplasticMaterial], Field(discriminator="kind")]


class StructuralDamping(_Strict):
    """Kelvin-Voigt damping of the SDEs: either damping ratios of the element-level
    axial/bending modes, or explicit coefficients (per unit length, like EA and EI)."""

    axial_ratio: float | None = _units("1", "Damping ratio of the axial and shear element modes", default=None,
                                       ge=0.0, le=2.0)
    bending_ratio: float | None = _units("1", "Damping ratio of the bending and torsion element modes",
                                         default=None, ge=0.0, le=2.0)
    axial: float | None = _units("N*s", "Axial damping coefficient (stress-rate analogue of EA)", default=None, ge=0.0,
                                 le=MAX_DAMPING, limit=DAMPING_LIMIT)
    shear: float | None = _units("N*s", "Shear damping coefficient", default=None, ge=0.0,
                                 le=MAX_DAMPING, limit=DAMPING_LIMIT)
    bending: float | None = _units("N*m^2*s", "Bending damping coefficient (analogue of EI)", default=None, ge=0.0,
                                   le=MAX_DAMPING, limit=DAMPING_LIMIT)
    torsion: float | None = _units("N*m^2*s", "Torsion damping coefficient (analogue of GJ)", default=None, ge=0.0,
                                   le=MAX_DAMPING, limit=DAMPING_LIMIT)

    @model_validator(mode="after")
    def _one_way(self):
        ratios = self.axial_ratio is not None or self.bending_ratio is not None
        explicit = any(v is not None for v in (self.axial, self.shear, self.bending, self.torsion))
        if ratios and explicit:
            raise FieldError("axial_ratio", "give damping either as ratios or as explicit coefficients, not both")
        return self


class LineType(_Strict):
    """Section of a line: a pipe geometry (outer_diameter, wall_thickness, youngs_modulus,
    density) or direct section properties (EA, EIy, EIz, GJ, mass_per_length, GA)."""

    outer_diameter: float | None = _units("m", "Outer diameter (hydrodynamic, buoyancy and contact diameter)",
                                          default=None, gt=0.0, le=100.0,
                                          limit="a line is a slender rod, pipe or cable: 100 m across is not "
                                                "slender (check the units, metres)")
    wall_thickness: float | None = _units("m", "Wall thickness of a pipe, less than outer_diameter/2",
                                          default=None, gt=0.0)
    youngs_modulus: float | None = _units("Pa", "Young's modulus", default=None, ge=MIN_MODULUS,
                                          le=MAX_MODULUS, limit=MODULUS_LIMIT, floor=MODULUS_FLOOR)
    poisson_ratio: float = _units("1", "Poisson's ratio", default=0.3, gt=-1.0, lt=0.5)
    density: float | None = _units("kg/m^3", "Material density of the pipe wall", default=None, ge=MIN_DENSITY,
                                   le=MAX_DENSITY, limit=DENSITY_LIMIT, floor=DENSITY_FLOOR)
    contents_density: float = _units("kg/m^3", "Density of the pipe contents (internal fluid)", default=0.0, ge=0.0,
                                     le=MAX_DENSITY, limit=DENSITY_LIMIT)

    EA: float | None = _units("N", "Axial stiffness", default=None, gt=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    EIy: float | None = _units("N*m^2", "Bending stiffness about the local y axis", default=None, ge=0.0,
                               le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    EIz: float | None = _units("N*m^2", "Bending stiffness about the local z axis", default=None, ge=0.0,
                               le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    GJ: float | None = _units("N*m^2", "Torsional stiffness", default=None, ge=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    GA: float | None = _units("N", "Effective shear stiffness (kappa already applied)", default=None, gt=0.0,
                              le=MAX_SECTION_STIFFNESS, limit=SECTION_STIFFNESS_LIMIT)
    mass_per_length: float | None = _units("kg/m", "Mass per unit length (structure and contents)",
                                           default=None, ge=MIN_MASS_PER_LENGTH, le=MAX_MASS_PER_LENGTH,
                                           limit=MASS_PER_LENGTH_LIMIT, floor=MASS_PER_LENGTH_FLOOR)
    rotary_inertia: float | None = _units("kg*m", "Mass moment of inertia of the section about a transverse "
                                          "axis per unit length (polar: twice this)", default=None, ge=0.0,
                                          le=MAX_ROTARY_INERTIA, limit=ROTARY_INERTIA_LIMIT)

    drag_normal: float = _units("1", "Normal drag coefficient (on outer_diameter)", default=0.0, ge=0.0,
                                le=MAX_COEFFICIENT, limit=COEFFICIENT_LIMIT)
    drag_axial: float = _units("1", "Axial drag coefficient (on pi*outer_diameter)", default=0.0, ge=0.0,
                               le=MAX_COEFFICIENT, limit=COEFFICIENT_LIMIT)
    added_mass_normal: float = _units("1", "Normal added-mass coefficient", default=0.0, ge=0.0,
                                      le=MAX_COEFFICIENT, limit=COEFFICIENT_LIMIT)
    added_mass_axial: float = _units("1", "Axial added-mass coefficient", default=0.0, ge=0.0,
                                     le=MAX_COEFFICIENT, limit=COEFFICIENT_LIMIT)
    material: Material = Field(default_factory=ElasticMaterial)
    tension_only: bool = Field(False, description="A rope: the axial SDE force is max(0, EA eps + damping), "
                                                  "never compressive (slack) until two elements overlap by half "
                                                  "their length, where their axial contact pushes back; keep the "
                                                  "bending stiffness small")
    breaking_load: float | None = _units(
        "N", "Minimum breaking load (MBL) of the line: a run whose effective tension exceeds it says so "
             "(a warning with the peak, where and when, and its multiple of the MBL); omit for no check",
        default=None, gt=0.0, le=1e12)
    steel_outer_diameter: float | None = _units(
        "m", "Outer diameter of the steel of a coated pipe given by direct section properties (outer_diameter "
             "is then the coated one): bending strains are taken at it (rfesim.lay_results); default "
             "outer_diameter", default=None, gt=0.0, le=100.0)
    damping: StructuralDamping | None = None

    @model_validator(mode="after")
    def _section(self):
        if self.steel_outer_diameter is not None and self.outer_diameter is not None \
                and self.steel_outer_diameter > self.outer_diameter:
            raise FieldError("steel_outer_diameter", f"{self.steel_outer_diameter} m is larger than outer_diameter "
                                                     f"{self.outer_diameter} m: the steel lies inside the coating")
        pipe = self.wall_thickness is not None
        if not pipe and self.EA is None and (self.youngs_modulus is not None or self.density is not None):
            raise FieldError("wall_thickness", "a pipe geometry needs wall_thickness (with outer_diameter, "
                                               "youngs_modulus and density); or give direct section properties "
                                               "EA, EIy and mass_per_length")
        if pipe:
            for name in ("outer_diameter", "youngs_modulus", "density"):
                if getattr(self, name) is None:
                    raise FieldError(name, "a pipe geometry (wall_thickness given) needs outer_diameter, "
                                           "wall_thickness, youngs_modulus and density")
            if self.wall_thickness >= 0.5 * self.outer_diameter:
                raise FieldError("wall_thickness", f"{self.wall_thickness} m is not less than the outer radius "
                                                   f"{0.5 * self.outer_diameter} m (outer_diameter/2): impossible "
                                                   f"pipe section (for a solid rod give direct section properties)")
            for name in ("EA", "EIy", "EIz", "GJ", "mass_per_length"):
                if getattr(self, name) is not None:
                    raise FieldError(name, "give either a pipe geometry or direct section properties, not both")
            D = self.outer_diameter
            d = D - 2.0 * self.wall_thickness
            area = math.pi / 4.0 * (D * D - d * d)
            inertia = math.pi / 64.0 * (D ** 4 - d ** 4)
            for name, value in (("EA", self.youngs_modulus * area), ("EI", self.youngs_modulus * inertia)):
                if not (math.isfinite(value) and value > 0.0):
                    raise FieldError("youngs_modulus", f"{self.youngs_modulus} Pa with this pipe geometry gives "
                                                       f"{name} = {value:.6g}: not a usable section stiffness")
            mass = self.density * area + self.contents_density * math.pi / 4.0 * d * d
            if not (math.isfinite(mass) and mass > 0.0):
                raise FieldError("density", f"{self.density} kg/m^3 with this pipe geometry gives a mass per "
                                            f"length of {mass:.6g} kg/m: not a usable section")
        else:
            missing = [n for n in ("EA", "mass_per_length") if getattr(self, n) is None]
            if missing:
                raise FieldError(missing[0], "direct section properties need EA and mass_per_length "
                                             "(or give a pipe geometry: outer_diameter, wall_thickness, "
                                             "youngs_modulus, density)")
            if self.EIy is None and self.EIz is None:
                raise FieldError("EIy", "direct section properties need a bending stiffness EIy (and EIz, "
                                        "which defaults to EIy); use 0 for a flexible cable")
            if self.contents_density > 0.0:
                raise FieldError("contents_density", "only used with a pipe geometry; with direct section "
                                                     "properties include the contents in mass_per_length")
        if self.damping is not None and (self.damping.axial_ratio or self.damping.bending_ratio) is not None:
            pass
        if self.material.kind == "elastoplastic":
            self._check_elastoplastic()
        return self

    def _check_elastoplastic(self):
        """An elastoplastic material needs a pipe wall; a table's yield point lies on the elastic line."""
        if self.wall_thickness is None:
            raise FieldError("material", "an elastoplastic material needs a pipe geometry (outer_diameter, "
                                         "wall_thickness, youngs_modulus), not direct section properties")
        mat = self.material
        if mat.law == "table":
            strain, stress = mat.table[0]
            if abs(stress / strain - self.youngs_modulus) > 0.01 * self.youngs_modulus:
                raise FieldError("material.table.0", f"the first row is the yield point and must lie on the elastic "
                                                     f"line: stress/strain = {stress / strain:.6g} Pa but "
                                                     f"youngs_modulus = {self.youngs_modulus:.6g} Pa (> 1 % apart)")
        elif mat.yield_stress >= 0.1 * self.youngs_modulus:
            raise FieldError("material.yield_stress", f"{mat.yield_stress} Pa is not below a tenth of youngs_modulus "
                                                      f"{self.youngs_modulus} Pa: not a metal (check the units, Pa)")


# --------------------------------------------------------------------------- lines

DriveAngleRow = Annotated[list[float], _fixed_length_numbers(2, "[t, angle]"), Field(min_length=2, max_length=2)]


class Drive(_Strict):
    """A prescribed rotation of a clamped line-to-line join (slewing, luffing): the joint's
    rest rotation turns by angle(t) - angle(0) about ``axis`` (rfesim.model.joins)."""

    name: str = Field(..., min_length=1, max_length=100, description="Name of the drive (output column)")
    axis: Vector3 = _units("1", "Rotation axis, global at t = 0 (any length, not zero); it turns with the parent "
                                "line's end")
    angle: list[DriveAngleRow] = _units("s, deg", "Rows [t, angle], times strictly increasing: monotone cubic "
                                                  "(PCHIP) between rows, from rest at a first row at t >= 0, held "
                                                  "beyond the ends", min_length=1)

    @model_validator(mode="after")
    def _check(self):
        _nonzero(self.axis, "axis")
        for i in range(1, len(self.angle)):
            if not self.angle[i][0] > self.angle[i - 1][0]:
                raise FieldError(f"angle.{i}", f"time {self.angle[i][0]} s does not increase (previous "
                                               f"{self.angle[i - 1][0]} s)")
        return self


class Motor(_Strict):
    """A torque-limited servo motor turning a clamped, coaxial line-to-line join about its own
    axis (a slewing ring): it follows the angle table through the servo gains and never
    exceeds ``max_torque`` (rfesim.loads.drives.motor_forces)."""

    name: str = Field("slewing", min_length=1, max_length=100, description="Name of the drive (output column)")
    angle: list[DriveAngleRow] = _units("s, deg", "Set angle rows [t, angle], times strictly increasing, angles "
                                                  "within +-36000 (100 turns): monotone cubic (PCHIP) between "
                                                  "rows, from rest at a first row at t >= 0, held beyond the "
                                                  "ends; the join turns by angle(t) - angle(0)", min_length=1)
    max_torque: float = _units("N*m", "Largest torque the motor gives (both directions)", gt=0.0,
                               le=MAX_FORCE, limit=FORCE_LIMIT)
    stiffness: float = _units("N*m/rad", "Servo gain on the angle error (the joint's torsional stiffness)", gt=0.0,
                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float = _units("N*m*s/rad", "Servo gain on the rate error (the joint's torsional damping)",
                            default=0.0, ge=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)

    @model_validator(mode="after")
    def _check(self):
        for i in range(1, len(self.angle)):
            if not self.angle[i][0] > self.angle[i - 1][0]:
                raise FieldError(f"angle.{i}", f"time {self.angle[i][0]} s does not increase (previous "
                                               f"{self.angle[i - 1][0]} s)")
        for i, row in enumerate(self.angle):
            if not abs(row[1]) <= 36000.0:
                raise FieldError(f"angle.{i}", f"{row[1]} deg is beyond 100 turns")
        return self


class Reeving(_Strict):
    """The rope's run from a pinned join (a sheave) back toward its winch: a frictionless
    sheave carries the rope's tension on both sides, so the join's parent is also pulled
    toward the lead by the tension at the sheave (rfesim.loads.reeving)."""

    lead: str = Field(..., min_length=1, description='Where the rope runs to from the sheave: a vessel name or '
                      '"fixed" (a deck winch or guide sheave at point), or an end of a line, "<line>:end_a" or '
                      '"<line>:end_b" (a rope running along a boom to its foot; the equal pull acts there; dynamics '
                      'then needs the analytic Jacobian, the default)')
    point: Vector3 | None = _units("m", "The lead point: in the vessel frame for a vessel, global for fixed "
                                   "(not for a line end)", default=None)

    @model_validator(mode="after")
    def _check(self):
        if ":" in self.lead:
            line, _, end = self.lead.partition(":")
            if not line or end not in ("end_a", "end_b"):
                raise FieldError("lead", f"a line end is '<line>:end_a' or '<line>:end_b' (got {self.lead!r})")
            if self.point is not None:
                raise FieldError("point", "a line-end lead is that end's point: leave out point")
        elif self.point is None:
            raise FieldError("point", f"give the lead point on '{self.lead}' (the deck winch or guide sheave)")
        return self


class LineEnd(_Strict):
    """One end of a line (end A at arc length 0, end B at its length): what it is attached
    to (the global frame, a vessel, a body, a chain link or another line's end), where, and
    whether its rotation follows the attachment (clamped) or is free (pinned)."""

    attach: str = Field("free", description='"fixed" (global frame), "free", a vessel name, (end B) a body '
                                            'name (position: the attachment point in the body frame), or (end '
                                            'A) "<line>:end_b": joined to end B of another absolute line '
                                            '(rfesim.model.joins; position optional), or (end B) '
                                            '"<line>:end_b": a closing join onto end B of another line (a '
                                            'portal\'s crossbeam, rfesim.scenario.joins)')
    position: Vector3 | None = _units("m", "Position of the end: global for fixed and free ends, in the vessel "
                                      "frame for a vessel (required for a fixed end and an end on a vessel or a "
                                      "body)", default=None)
    direction: Vector3 | None = _units("1", "Tangent of the line at this end (any length, not zero), pointing "
                                            "from end A toward end B (global, or vessel frame for a vessel)",
                                       default=None)
    connection: Literal["clamped", "pinned"] = Field("pinned", description="clamped: position and orientation "
                                                     "follow the attachment; pinned: position only")
    at: float | None = _units("m", 'Attached to a chain link ("attach": "<chain>.<link>"): arc length of the '
                              "point on the link (default: its tip); position is then the offset from that point "
                              "in the link's axes (default: none) and direction is in the link's axes",
                              default=None, ge=0.0)
    drives: list[Drive] = Field(default_factory=list, description='Prescribed rotations of a clamped join '
                                '("<line>:end_b"), applied in the listed order (slewing before luffing)')
    motor: Motor | None = Field(None, description='A torque-limited servo motor turning a clamped, coaxial '
                                'join ("<line>:end_b") about its own axis (a slewing ring); not with drives')
    reeving: Reeving | None = Field(None, description='The rope of a pinned join ("<line>:end_b", the sheave) '
                                    'runs on to a lead (its winch): the parent is pulled toward the lead by '
                                    'the tension at the sheave (rfesim.loads.reeving)')
    hinge_axis: Vector3 | None = _units("1", 'A clamped join ("<line>:end_b") that turns freely about this axis '
                                             '(global at t = 0; any length, not zero), normal to end A\'s direction '
                                             '(a luffing pin) or along it (a free slewing bearing): the joint\'s '
                                             'stiffness and damping about it are 0 (rfesim.model.joins); no drives '
                                             'or motor with it', default=None)

    @model_validator(mode="after")
    def _direction(self):
        if self.direction is not None:
            _nonzero(self.direction, "direction")
        if ":" in self.attach:
            parent, _, point = self.attach.partition(":")
            if not parent or point != "end_b":
                raise FieldError("attach", f"a join names end B of another line, '<line>:end_b' (got "
                                           f"{self.attach!r})")
        if self.reeving is not None and (":" not in self.attach or self.connection != "pinned"):
            raise FieldError("reeving", 'reeving runs from a sheave, a pinned join ("attach": "<line>:end_b", '
                                        '"connection": "pinned")')
        if self.motor is not None and (":" not in self.attach or self.connection != "clamped"):
            raise FieldError("motor", 'a motor acts only on a clamped join ("attach": "<line>:end_b", '
                                      '"connection": "clamped")')
        if self.hinge_axis is not None:
            if ":" not in self.attach or self.connection != "clamped":
                raise FieldError("hinge_axis", 'a hinge releases one rotation of a clamped join ("attach": '
                                               '"<line>:end_b", "connection": "clamped")')
            _nonzero(self.hinge_axis, "hinge_axis")
            if self.drives or self.motor is not None:
                raise FieldError("hinge_axis", "a hinged join turns freely: no drives or motor on it")
        if self.drives:
            if ":" not in self.attach or self.connection != "clamped":
                raise FieldError("drives", 'drives act only on a clamped join ("attach": "<line>:end_b", '
                                           '"connection": "clamped")')
            if self.motor is not None:
                raise FieldError("motor", "a join has either drives (angle tables) or a motor, not both")
            names = [d.name for d in self.drives]
            for i, nm in enumerate(names):
                if nm in names[:i]:
                    raise FieldError(f"drives.{i}.name", f"drive '{nm}' is given twice")
        return self


class PointLoad(_Strict):
    """A concentrated force and moment on a line (or a chain link) at an arc length from its
    end A: a dead load in the global frame, or a follower load turning with the element."""

    at: Union[Literal["end_a", "end_b"], float] = _units("m", '"end_a", "end_b", or the arc length from end A, '
                                                              'from 0 to the length of the line (or link)')
    force: Vector3 = _units("N", "Force", default=[0.0, 0.0, 0.0])         # bounded by its unit (UNIT_BOUNDS)
    moment: Vector3 = _units("N*m", "Moment", default=[0.0, 0.0, 0.0])
    frame: Literal["global", "local"] = Field("global", description="global: dead load; local: follows the "
                                              "element (x along the line)")

    @field_validator("at", mode="before")
    @classmethod
    def _at(cls, value):
        if isinstance(value, str):
            if value in ("end_a", "end_b"):
                return value
            try:
                return float(value)
            except ValueError:
                pass
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            return value
        raise ValueError(f"must be 'end_a', 'end_b' or an arc length from end A in m, got {_show(value)}")


MIN_SEGMENT = 1.0e-6      # m, shortest SDE spacing length/elements (the SDE stiffness goes as 1/dx^3)


class Line(_Strict):
    """A flexible line (pipe, riser, rope, boom) of one line type, cut into rigid finite
    elements joined by spring-damper elements (SDEs), with its two ends and point loads."""

    type: str = Field(..., description="Name of a line type")
    length: float = _units("m", "Unstretched length", gt=0.0, le=MAX_LENGTH, limit=LENGTH_LIMIT)
    elements: int = _units("1", "Number of SDEs (primary division into equal segments), each segment "
                                "length/elements at least 1e-6 m", ge=1, le=100000)
    formulation: Literal["absolute", "classical", "classical-linear", "modified", "planar"] = Field(
        "absolute", description="RFE formulation: absolute coordinates (section 8.4, sea loads, seabed), "
                                "classical (8.1, eq. 8.7), classical-linear (eq. 8.8), modified (8.2, joint "
                                "coordinates, no axial/shear flexibility) or planar (8.3, vertical plane)")
    dofs: list[str] | None = Field(None, description="classical/modified only: the free RFE coordinates "
                                   "(classical: x, y, z, rx, ry, rz; modified: rx, ry, rz); default all")
    shear_stiffness: Literal["fem", "kruszewski"] | None = Field(
        None, description='"fem" (eq. 8.89, default) or "kruszewski" (eq. 8.88). By default a nearly flexible '
                          'line (12EI/dx^3 < 1e-6 GA/dx) uses kruszewski so its elements stay connected, and so does '
                          'a line whose expected static tension (its elastic catenary, or its wet weight and point '
                          'loads) exceeds 12EI/dx^2, beyond which the fem shear does not hold its elements in line')
    end_a: LineEnd = Field(default_factory=LineEnd)
    end_b: LineEnd = Field(default_factory=LineEnd)
    loads: list[PointLoad] = Field(default_factory=list)

    @model_validator(mode="after")
    def _ends(self):
        dx = self.length / self.elements
        if dx < MIN_SEGMENT:
            if self.length < MIN_SEGMENT:
                raise FieldError("length", f"{self.length} m is too short (at least {MIN_SEGMENT} m)")
            raise FieldError("elements", f"{self.elements} elements on {self.length} m make segments of "
                                         f"{dx:.3g} m, shorter than {MIN_SEGMENT} m: use fewer elements")
        if self.dofs is not None and self.formulation == "absolute":
            raise FieldError("dofs", "is for the classical and modified formulations only: every coordinate of "
                                     "an absolute-formulation line is free (drop dofs, or set formulation)")
        if self.end_a.attach == "free" and self.end_b.attach == "free":
            pass  # a free-floating line is allowed in dynamics (statics will be singular and says so)
        # an end on a chain link ("<chain>.<link>", checked by scenario.chains) may omit its position
        # end B on "<line>:end_b" is a closing join (rfesim.scenario.joins); its position is optional
        if self.end_a.position is None and self.end_a.attach != "free" and "." not in self.end_a.attach \
                and ":" not in self.end_a.attach:
            raise FieldError("end_a.position", f"an end attached to '{self.end_a.attach}' needs a position")
        if self.end_b.position is None and self.end_b.attach != "free" and "." not in self.end_b.attach \
                and ":" not in self.end_b.attach:
            raise FieldError("end_b.position", f"an end attached to '{self.end_b.attach}' needs a position")
        for i, load in enumerate(self.loads):
            if not isinstance(load.at, str) and not (0.0 <= load.at <= self.length):
                raise FieldError(f"loads.{i}.at", f"arc length {load.at} m is outside the line [0, {self.length}] m")
        return self


# --------------------------------------------------------------------------- supports

def _nonzero(vector: list[float], field: str) -> None:
    """A direction or axis (normalised where it is used, so of any length): refused only when it
    is zero. One of extreme size (its largest component beyond 1e3 or below 1e-3) is scaled in
    place by its largest component, keeping its direction: the sum of the squares of 1e200 (or
    of 1e-200) overflows (underflows) in a norm."""
    big = max((abs(c) for c in vector), default=0.0)
    if big == 0.0:
        raise FieldError(field, "must not be the zero vector")
    if not 1.0e-3 <= big <= 1.0e3:
        vector[:] = [c / big for c in vector]


class Roller(_Strict):
    """One roller: a segment of its axis in the support's frame, on which the pipe rests
    (penetration = pipe outer radius + roller radius - distance between the pipe axis and
    this segment, rfesim.loads.rollers)."""

    position: Vector3 = _units("m", "Centre of the roller's contact line (a point on the roller axis), in the "
                               "frame of the support's attachment")
    axis: Vector3 = _units("1", "Direction of the roller axis (any length, not zero), in the frame of the "
                                "support's attachment")
    width: float = _units("m", "Length of the contact line along the axis (the pipe touches within +-width/2 of "
                          "position)", ge=0.0)
    radius: float = _units("m", "Roller radius (0: the contact line itself)", default=0.0, ge=0.0)

    @model_validator(mode="after")
    def _axis(self):
        _nonzero(self.axis, "axis")
        return self


class _Support(_Strict):
    attach: str = Field("fixed", description='"fixed" (global frame) or a vessel name: the rollers move with it')
    line: str = Field(..., description="Name of the line that runs over the rollers")
    stiffness: float = _units("N/m", "Contact stiffness of each roller", gt=0.0,
                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float = _units("N*s/m", "Contact damping of each roller (acts only while pressed)", default=0.0,
                            ge=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)
    friction: float = _units("1", "Coulomb friction coefficient along the roller axes (the rollers turn freely "
                                  "along the pipe); dynamics only", default=0.0, ge=0.0, le=10.0)
    friction_stiffness: float | None = _units("N/m", "Stick-spring stiffness of the friction (default: the "
                                              "contact stiffness)", default=None, gt=0.0,
                                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    contact_onset: float | None = _units("m", "Penetration over which the contact force comes in smoothly "
                                         "(quadratic, then linear with the stiffness; rfesim.loads.rollers). "
                                         "Default 0.005 x (pipe + roller radius); 0: a sharp onset",
                                         default=None, ge=0.0)


class RollerSupport(_Support):
    """Rollers listed one by one (a V-roller is two rollers with inclined axes)."""

    kind: Literal["rollers"]
    rollers: list[Roller] = Field(..., min_length=1, max_length=100000)


class StingerSupport(_Support):
    """Rollers along a rigid arc: the arc is the line of the roller axes (the bottoms of
    V-rollers), starting at ``start`` with tangent ``direction`` and curving towards -z of
    the attachment frame with ``radius``; a roller station every ``spacing`` along it,
    from ``start`` to ``length``. Each station has one roller across the arc (axis
    horizontal, normal to the arc plane) or, with ``v_angle_deg`` > 0, two rollers whose
    axes rise by that angle on either side (a V)."""

    kind: Literal["stinger"]
    start: Vector3 = _units("m", "First roller station (attachment frame)")
    direction: Vector3 = _units("1", "Tangent of the arc at start, pointing along the lay direction (attachment "
                                     "frame; any length, not zero, not vertical)")
    radius: float = _units("m", "Radius of the arc of roller axes", gt=0.0)
    length: float = _units("m", "Arc length of the stinger from start, at most half the circle (pi * radius)",
                           gt=0.0, le=1.0e4)
    spacing: float = _units("m", "Distance between roller stations along the arc, at most the length, and at "
                                 "most 10000 stations (length / spacing)", gt=0.0)
    roller_width: float = _units("m", "Contact length of each roller", gt=0.0)
    roller_radius: float = _units("m", "Roller radius", default=0.0, ge=0.0)
    v_angle_deg: float = _units("deg", "Rise of each half of a V-roller from horizontal (0: one flat roller per "
                                "station)", default=0.0, ge=0.0, lt=80.0)

    @model_validator(mode="after")
    def _geometry(self):
        _nonzero(self.direction, "direction")
        n = math.sqrt(sum(c * c for c in self.direction))
        if abs(self.direction[2]) / n > 1.0 - 1e-9:
            raise FieldError("direction", "must not be vertical: the arc bends towards -z in the plane of the "
                                          "direction and z")
        if self.spacing > self.length:
            raise FieldError("spacing", f"{self.spacing} m is longer than the stinger ({self.length} m)")
        if self.length / self.spacing > 10000:
            raise FieldError("spacing", f"{self.spacing} m on {self.length} m makes more than 10000 stations")
        if self.length > math.pi * self.radius:
            raise FieldError("length", f"{self.length} m is more than half the circle of radius {self.radius} m")
        return self


PayoutRow = Annotated[list[float], _fixed_length_numbers(2, "[t, paid-out length]"), Field(min_length=2, max_length=2)]


class PayoutTable(_Strict):
    """Prescribed payout: rows [t (s), paid-out length (m)], constant beyond the ends;
    negative lengths reel the line in. Two rows: a straight line (constant speed between
    them). Three rows or more: the monotone cubic (PCHIP) through the rows, so that the
    payout speed is continuous at every row (a speed that jumped would jolt the pipe through
    the stiff grips): it passes every row exactly and never overshoots, is flat at a row
    where the payout stops, and between two rows whose neighbours are flat (a start and a
    stop) peaks at 1.5 times their mean speed -- add rows (a short ramp at each end) for a
    speed that is constant in between (rfesim.loads.tensioner)."""

    kind: Literal["table"]
    rows: list[PayoutRow] = _units("s, m", "Rows [t, paid-out length], times strictly increasing; negative "
                                           "lengths reel the line in", min_length=1)

    @model_validator(mode="after")
    def _times(self):
        for i in range(1, len(self.rows)):
            if not self.rows[i][0] > self.rows[i - 1][0]:
                raise FieldError(f"rows.{i}", f"time {self.rows[i][0]} s does not increase")
        return self


class PayoutConstantTension(_Strict):
    """The tensioner's characteristic: it pays out when it holds more than tension +
    dead_band, reels in below tension - dead_band, at (excess beyond the band) / gain,
    at most max_speed."""

    kind: Literal["constant-tension"]
    tension: float = _units("N", "Set tension", gt=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    dead_band: float = _units("N", "Dead band around the set tension", default=0.0, ge=0.0,
                              le=MAX_FORCE, limit=FORCE_LIMIT)
    gain: float = _units("N*s/m", "Tension excess per unit payout speed", gt=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)
    max_speed: float = _units("m/s", "Largest payout or reel-in speed", gt=0.0)


class TensionerSupport(_Strict):
    """A straight track (a tensioner, or a J-lay collar/clamp) that holds a line on its
    axis with lateral pads and grips it axially; the pads move with the payout
    (rfesim.loads.tensioner). The line's material passes through: pipe stored upstream of
    the track (on deck, on a ramp) is part of the line."""

    kind: Literal["tensioner"]
    attach: str = Field("fixed", description='"fixed" (global frame) or a vessel name: the track moves with it')
    line: str = Field(..., description="Name of the line the tensioner holds")
    entry: Vector3 = _units("m", "Entry point of the track (attachment frame)")
    axis: Vector3 = _units("1", "Direction of payout along the track (attachment frame; any length, not zero)")
    length: float = _units("m", "Track length", gt=0.0, le=MAX_LENGTH, limit=LENGTH_LIMIT)
    lateral_stiffness: float = _units("N/m/m", "Pad stiffness holding the line on the axis, per unit length",
                                      default=1.0e7, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    grip_stiffness: float = _units("N/m/m", "Axial grip stiffness per unit length", default=1.0e7, gt=0.0,
                                   le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    capacity: float = _units("N", "Largest axial force the whole track holds before the line slips (shared "
                             "among the elements in it by their gripped length)", gt=0.0,
                             le=MAX_FORCE, limit=FORCE_LIMIT)
    payout: Annotated[Union[PayoutTable, PayoutConstantTension], Field(discriminator="kind")] = Field(
        default_factory=lambda: PayoutTable(kind="table", rows=[[0.0, 0.0]]),
        description="Prescribed payout, or driven by the tension characteristic (default: holds the line); a "
                    "table may pay out at most the line behind the track's exit at the start (from end A up to "
                    "the exit along the line): more is refused, and a payout that runs end A out of the track "
                    "stops the run")
    horizontal_tension: float | None = _units(
        "N", "Horizontal lay tension H that statics sets: it pays the line out (or hauls it in) through the "
             "track until the horizontal force of the line on its end B (a laid pipe's pinned end on the "
             "seabed) equals H to 0.5 %; the shift stays in the payout for the run (default: the track holds "
             "the line where it starts)", default=None, gt=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)

    @model_validator(mode="after")
    def _axis(self):
        _nonzero(self.axis, "axis")
        return self


class ReelSupport(_Strict):
    """A reel (drum) storing a line wrapped on it: the RFEs on the wrap window are pressed
    against the drum (unilateral radial contact), held in its plane and gripped
    tangentially by anchors that turn with the drum; the payout is the drum's rotation
    times ``radius`` (rfesim.loads.reel). End A of the line lies on the wrap at the start,
    ``stored_length`` back from the take-off point, and the stored pipe starts plastically
    bent to the drum (rfesim.model.reels)."""

    kind: Literal["reel"]
    attach: str = Field("fixed", description='"fixed" (global frame) or a vessel name: the reel moves with it')
    line: str = Field(..., description="Name of the line stored on the reel (from its end A)")
    centre: Vector3 = _units("m", "Centre of the drum (attachment frame)")
    axis: Vector3 = _units("1", "Drum axis (attachment frame; any length, not zero); the take-off point is at "
                                "centre + radius * (axis x direction)")
    direction: Vector3 = _units("1", "Direction in which the pipe leaves the drum at the take-off point, normal "
                                     "to the axis (attachment frame; any length, not zero)")
    radius: float = _units("m", "Radius of the pipe axis on the drum (drum radius + pipe outer radius)", gt=0.0,
                           le=MAX_LENGTH, limit=LENGTH_LIMIT)
    wrap_deg: float = _units("deg", "Wrap window: the angle back from the take-off point over which the drum "
                             "holds the pipe", default=180.0, gt=0.0, le=270.0)
    stored_length: float = _units("m", "Length of the line from end A wrapped on the drum at the start, at most "
                                       "the wrap window radius * wrap_deg (in radians)", ge=0.0)
    contact_stiffness: float = _units("N/m/m", "Radial contact stiffness of the drum per unit length",
                                      default=1.0e7, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    lateral_stiffness: float = _units("N/m/m", "Stiffness holding the pipe in the drum plane, per unit length",
                                      default=1.0e7, gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    grip_stiffness: float = _units("N/m/m", "Tangential grip stiffness per unit length", default=1.0e7, gt=0.0,
                                   le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    capacity: float = _units("N", "Largest tangential force the drum holds before the pipe slips (shared among "
                             "the elements on the wrap by their gripped length)", gt=0.0,
                             le=MAX_FORCE, limit=FORCE_LIMIT)
    back_tension: float | None = _units("N", "Back tension the drum holds on the line at the start: statics turns "
                                        "the drum (shifts its payout) until the tension of the line just off the "
                                        "drum (the first element past the take-off point) equals it; the drum's "
                                        "tangential force also carries the moment of the pipe leaving the drum "
                                        "(default: the drum grips the line where it starts); below capacity",
                                        default=None, gt=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    payout: Annotated[Union[PayoutTable, PayoutConstantTension], Field(discriminator="kind")] = Field(
        default_factory=lambda: PayoutTable(kind="table", rows=[[0.0, 0.0]]),
        description="Paid-out length (radius times the drum rotation) prescribed, or driven by the tension "
                    "characteristic acting on the drum's tangential force less the offset statics fixes "
                    "with back_tension (its force then less the back tension; 0 without back_tension) "
                    "(default: the drum holds still); a table may pay out at most stored_length")

    @model_validator(mode="after")
    def _geometry(self):
        _nonzero(self.axis, "axis")
        _nonzero(self.direction, "direction")
        a = [c / math.sqrt(sum(x * x for x in self.axis)) for c in self.axis]
        d = [c / math.sqrt(sum(x * x for x in self.direction)) for c in self.direction]
        if abs(sum(x * y for x, y in zip(a, d))) > 1e-6:
            raise FieldError("direction", "must be normal to the drum axis (the pipe leaves the drum tangentially)")
        wrap = self.radius * math.radians(self.wrap_deg)
        if self.stored_length > wrap * (1.0 + 1e-12):
            raise FieldError("stored_length", f"{self.stored_length} m is longer than the wrap window "
                                              f"({wrap:.6g} m = radius x wrap_deg): widen wrap_deg or store less")
        if self.payout.kind == "table":
            reach = max(row[1] for row in self.payout.rows)
            if reach > self.stored_length:
                raise FieldError("payout", f"the table pays out {reach:.6g} m, more than the {self.stored_length:.6g} m "
                                           f"stored on the reel (stored_length): the reel would empty and the "
                                           f"line's end run free; pay out less or store more")
        if self.back_tension is not None and self.back_tension >= self.capacity:
            raise FieldError("back_tension", f"{self.back_tension} N is not below the drum's capacity "
                                             f"{self.capacity} N")
        return self


class StraightenerSupport(_Support):
    """A straightener (aligner): ``rollers`` rollers (odd, 3 for a three-point bender) over
    ``span`` along ``axis`` from ``entry``, their axes across. The even rollers (both ends)
    hold the pipe axis on the straight line from ``entry``; the odd ones push it out by
    ``offset`` towards ``side``, bending the pipe the other way (reverse bending). Compiles to
    ordinary rollers (rfesim.loads.rollers, rfesim.model.reels.straightener_roller_set)."""

    kind: Literal["straightener"]
    entry: Vector3 = _units("m", "Pipe axis at the first roller (attachment frame)")
    axis: Vector3 = _units("1", "Direction of the pipe's travel through the straightener (attachment frame; any "
                                "length, not zero)")
    side: Vector3 = _units("1", "Bending side: the direction, normal to axis, in which the middle roller(s) push "
                                "the pipe (attachment frame; any length, not zero)")
    span: float = _units("m", "Distance between the first and the last roller", gt=0.0)
    offset: float = _units("m", "How far the middle roller(s) push the pipe axis out of the straight line, at "
                                "most half the roller pitch, span / (rollers - 1)", ge=0.0)
    rollers: int = _units("1", "Number of rollers, odd", default=3, ge=3, le=99)
    roller_radius: float = _units("m", "Roller radius", default=0.2, ge=0.0)
    roller_width: float = _units("m", "Length of each roller's contact line", default=1.0, gt=0.0)

    @model_validator(mode="after")
    def _geometry(self):
        _nonzero(self.axis, "axis")
        _nonzero(self.side, "side")
        if self.rollers % 2 == 0:
            raise FieldError("rollers", f"must be odd (rollers alternate sides, both ends on one), got {self.rollers}")
        e = [c / math.sqrt(sum(x * x for x in self.axis)) for c in self.axis]
        n = [c / math.sqrt(sum(x * x for x in self.side)) for c in self.side]
        if abs(sum(x * y for x, y in zip(e, n))) > 1e-6:
            raise FieldError("side", "must be normal to the axis")
        pitch = self.span / (self.rollers - 1)
        if self.offset > 0.5 * pitch:
            raise FieldError("offset", f"{self.offset} m is more than half the roller pitch ({pitch:.6g} m): "
                                       f"steeper than 1 in 2")
        return self


Support = Annotated[Union[RollerSupport, StingerSupport, TensionerSupport, ReelSupport, StraightenerSupport],
                    Field(discriminator="kind")]


# --------------------------------------------------------------------------- analysis

class StaticsSettings(_Strict):
    """Static equilibrium (Newton with load steps), solved before dynamics and modal analysis."""

    enabled: bool = Field(True, description="Solve statics; false starts dynamics from the lines' initial shape "
                                            "at rest (a modal analysis solves the statics all the same: its modes "
                                            "are about the static equilibrium)")
    tolerance: float = _units("1", "Convergence: largest residual force relative to the largest applied force",
                              default=1e-8, gt=0.0, lt=1.0)
    max_iterations: int = _units("1", "Newton iterations over all load steps", default=400, ge=1, le=100000)
    load_steps: int = _units("1", "Initial number of load steps (halved adaptively when Newton fails)", default=1,
                             ge=1, le=1000)
    seabed_friction: Literal["none", "mobilised"] = Field(
        "none", description="Seabed friction in statics: none, or fully mobilised axial friction on the grounded "
                            "length pointing towards end A (the line was pulled towards end B as it was laid)")
    start: Literal["auto", "straight", "catenary"] = Field(
        "auto", description="Initial shape: auto = catenary for lines with both ends placed and slack, "
                            "straight otherwise; a straight start that fails on lines with slack goes on from "
                            "the catenary (and says so)")


class RK4Settings(_Strict):
    """Explicit fourth-order Runge-Kutta at a fixed step, by default a safe fraction of the
    stability limit of the stiffest SDE."""

    kind: Literal["rk4"]
    time_step: float | None = _units("s", "Fixed step (default: estimated from the stiffest SDE)",
                                     default=None, gt=0.0)
    safety: float = _units("1", "Fraction of the estimated stability limit used for the default step",
                           default=0.8, gt=0.0, le=1.0)


ADAPTIVE_RTOL_FLOOR = 1e-12
ADAPTIVE_ATOL_FLOOR = 1e-15


class AdaptiveSettings(_Strict):
    """Explicit Dormand-Prince 5(4) with an adaptive step that keeps the estimated error of
    each step within rtol and atol."""

    kind: Literal["adaptive"]
    rtol: float = _units("1", "Relative error allowed per step of the embedded Dormand-Prince pair, of each "
                              "coordinate (a position against its size plus the element length)", default=1e-6,
                         ge=ADAPTIVE_RTOL_FLOOR, lt=1.0,
                         floor="below it the error estimate is round-off (a double resolves 2.2e-16 of a number) and "
                               "the adaptive step collapses")
    atol: float = _units("m or rad; m/s or rad/s", "Absolute error allowed per step, added to rtol's share, in the "
                                                   "unit of each coordinate: m for positions, rad for rotations, "
                                                   "m/s and rad/s for velocities", default=1e-8,
                         ge=ADAPTIVE_ATOL_FLOOR, le=1.0,
                         floor="below it a coordinate near zero needs an error below its round-off: the step "
                               "collapses or the run takes millions of steps (1e-20: 1.3 million steps for 0.05 s)",
                         limit="an error of 1 m or 1 rad per step controls nothing")
    max_step: float | None = _units("s", "Largest step", default=None, gt=0.0)
    first_step: float | None = _units("s", "First step (default: estimated)", default=None, gt=0.0)


class GeneralizedAlphaSettings(_Strict):
    """Implicit generalized-alpha (Chung-Hulbert) at a fixed step with Newton iterations: the
    default integrator, second-order accurate with numerical damping of the highest
    frequencies set by rho_inf."""

    kind: Literal["generalized-alpha"]
    time_step: float = _units("s", "Time step", default=0.01, gt=0.0)
    rho_inf: float = _units("1", "Spectral radius at infinite frequency (1: no numerical damping)", default=0.8,
                            ge=0.0, le=1.0)
    tolerance: float = _units("1", "Newton tolerance: largest residual force relative to the largest element "
                                   "weight or point load", default=1e-6, gt=0.0, lt=1.0)
    max_iterations: int = _units("1", "Newton iterations of one try of a step (a step that fails is retried from "
                                      "another predictor, then halved)", default=12, ge=1, le=200)
    jacobian_reuse: bool = Field(True, description="Modified Newton: keep the factorised Jacobian while "
                                                   "Newton converges fast")
    jacobian: Literal["analytic", "finite-difference"] = Field(
        "analytic", description="Jacobian of the SDEs: analytic tangent (fast) or coloured finite differences "
                                "(the reference)")
    recovery_halvings: int = _units("1", "A step that fails even in 64 substeps (a slack rope snatched taut): the "
                                         "run goes back to its last checkpoint 0.5 to 2.5 s before the failure and "
                                         "takes the stretch to 2 s past it at half the step, halving again on a "
                                         "further failure down to time_step / 2^recovery_halvings, and says so in "
                                         "the results' message; 0 stops the run at the failure",
                                    default=3, ge=0, le=6)


Integrator = Annotated[Union[RK4Settings, AdaptiveSettings, GeneralizedAlphaSettings], Field(discriminator="kind")]


class DynamicsSettings(_Strict):
    """Time-domain simulation from the static equilibrium (or the initial shape)."""

    enabled: bool = Field(True, description="Run dynamics (with a duration above 0)")
    duration: float = _units("s", "Simulated time", default=0.0, ge=0.0, le=1.0e7)
    integrator: Integrator = Field(default_factory=lambda: GeneralizedAlphaSettings(kind="generalized-alpha"))
    output_interval: float | None = _units("s", "Interval between stored results (default: every step for "
                                           "fixed-step integrators, every few steps beyond 10000 outputs, "
                                           "duration/1000 for adaptive; made to divide the duration). A fixed "
                                           "step is shortened to divide it; an interval that does not divide "
                                           "the duration runs on to the next output time after it",
                                           default=None, gt=0.0)


class ModalSettings(_Strict):
    """Natural frequencies and mode shapes of the structure linearised about its static
    equilibrium (solved for it also when analysis.statics.enabled is false): computed by
    `rfesim modes` / rfesim.modes, and by a run (`rfesim run`, rfesim.simulate, the HTTP
    service) after its statics and dynamics, into results.modes and the group /modes of the
    results file."""

    modes: int = _units("1", "Number of modes (lowest frequencies)", default=10, ge=1, le=10000)


class Analysis(_Strict):
    """What to solve: statics, then dynamics and/or modal analysis about the static equilibrium."""

    statics: StaticsSettings = Field(default_factory=StaticsSettings)
    dynamics: DynamicsSettings = Field(default_factory=DynamicsSettings)
    modal: ModalSettings | None = None


# --------------------------------------------------------------------------- scenario

from .chains import ChainSpec, check_formulations  # noqa: E402 - chains.py builds on the models above
from .bodies import Body  # noqa: E402 - bodies.py builds on the models above
from .winches import Winch  # noqa: E402 - winches.py builds on the models above
from .tuggers import Tugger  # noqa: E402 - tuggers.py builds on the models above
from .pipelay import PipelayTemplate  # noqa: E402 - pipelay.py builds on the models above
from .cranes import CraneTemplate  # noqa: E402 - cranes.py builds on the models above


class Scenario(_Strict):
    """A complete scene: environment, vessels, line types, lines and analysis settings."""

    schema_version: Literal[1] = Field(1, description="Version of this scenario format")
    name: str = Field("unnamed", max_length=200, description="Name of the scene (results files, job lists)")
    description: str = Field("", max_length=10000, description="Free text: the scene, its data and sources")
    environment: Environment = Field(default_factory=Environment, description="Gravity, sea water, current, "
                                     "waves and seabed")
    vessels: dict[str, Vessel] = Field(default_factory=dict, description="Vessels (or fixed frames) that lines, "
                                       "supports and cranes are attached to, and their motion")
    line_types: dict[str, LineType] = Field(default_factory=dict, description="Cross-section properties of "
                                            "pipes, risers and ropes, used by lines")
    lines: dict[str, Line] = Field(default_factory=dict, description="Flexible lines cut into rigid finite "
                                   "elements: type, length, elements, ends")
    supports: dict[str, Support] = Field(default_factory=dict, description="Guiding structures "
                                         "that lines rest on or pass through (rollers, stinger, tensioner, reel, "
                                         "straightener)")
    analysis: Analysis = Field(default_factory=Analysis, description="Statics, dynamics and modal settings")
    chains: dict[str, ChainSpec] = Field(default_factory=dict, description="Kinematic chains of rigid and "
                                         "flexible links (rfesim.scenario.chains)")
    bodies: dict[str, Body] = Field(default_factory=dict, description="Rigid bodies (payloads, buoys) on the "
                                    "end B of a line (rfesim.scenario.bodies)")
    winches: dict[str, Winch] = Field(default_factory=dict, description="Winches paying out or hauling in a "
                                      "rope line (rfesim.scenario.winches)")
    tuggers: dict[str, Tugger] = Field(default_factory=dict, description="Tugger lines from a vessel's deck "
                                       "to a body, steadying a payload (rfesim.scenario.tuggers)")
    pipelay: dict[str, PipelayTemplate] = Field(default_factory=dict, description="Pipelay templates (s-lay, "
                                                "j-lay, reel-lay), expanded into vessels, line_types, lines and "
                                                "supports before validation (rfesim.scenario.expand); empty after")
    cranes: dict[str, CraneTemplate] = Field(default_factory=dict, description="Crane templates (column, "
                                             "a-frame), expanded into vessels, line_types, lines, bodies and "
                                             "winches before validation (rfesim.scenario.expand); empty after")
    # what the templates' expansion found worth a warning (rfesim.scenario.pipelay.template_warning),
    # each naming the template field; added to the statics warnings of a run (rfesim.api)
    _template_warnings: list = PrivateAttr(default_factory=list)
    # the input this Scenario was validated from (its pipelay and cranes templates not
    # expanded), and its dump then (plain values): rfesim.scenario.load.revalidated compares
    # the dump now with it and validates the input with the fields assigned since (pydantic
    # does not check an assignment), expanding the templates again; ``_origins`` maps the
    # sections the templates made to the template fields (rfesim.scenario.pipelay.Origin)
    _source: dict | None = PrivateAttr(default=None)
    _validated_dump: dict | None = PrivateAttr(default=None)
    _origins: dict = PrivateAttr(default_factory=dict)
    # assignments in made sections that no template field stands for, put onto them after
    # every expansion ((path, value) pairs; rfesim.scenario.load.revalidated)
    _after: list = PrivateAttr(default_factory=list)

    def __eq__(self, other):
        # two scenarios are equal when their fields are: not by how they were made (their
        # private input, dump and template warnings, which pydantic would compare too)
        if not isinstance(other, Scenario):
            return NotImplemented
        return self.__dict__ == other.__dict__

    __hash__ = None

    @model_validator(mode="after")
    def _formulations(self):
        check_formulations(self)
        return self

    @model_validator(mode="after")
    def _motion_tables_meet_the_run(self):
        # only a run: statics alone takes the vessel where the table has it at t = 0
        dyn = self.analysis.dynamics
        duration = float(dyn.duration) if dyn.enabled else 0.0
        for name, vessel in self.vessels.items():
            span = motion_table_span(vessel.motion) if duration > 0.0 else None
            if span is None:
                continue
            first, last = span
            field = f"vessels.{name}.motion.start_time"
            what = "file" if vessel.motion.kind == "csv" else "table"
            if last <= 0.0:
                raise FieldError(field, f"the motion {what} ends before the run starts: its rows run from "
                                        f"{first + vessel.motion.start_time:.6g} to "
                                        f"{last + vessel.motion.start_time:.6g} s and the run starts at its time "
                                        f"start_time = {vessel.motion.start_time:.6g} s, so the vessel would "
                                        f"stand still at its last row (set start_time to the table's time of "
                                        f"the run's start)")
            if first >= duration:
                raise FieldError(field, f"the motion {what} starts after the run ends: its rows run from "
                                        f"{first + vessel.motion.start_time:.6g} to "
                                        f"{last + vessel.motion.start_time:.6g} s, the run covers its times "
                                        f"{vessel.motion.start_time:.6g} to "
                                        f"{vessel.motion.start_time + duration:.6g} s, so the vessel would "
                                        f"stand still at its first row (set start_time to the table's time of "
                                        f"the run's start)")
        return self

    @model_validator(mode="after")
    def _rao_needs_waves(self):
        water = self.environment.water
        for name, vessel in self.vessels.items():
            if vessel.motion.kind == "rao" and (water is None or water.waves is None):
                raise FieldError(f"vessels.{name}.motion", "an RAO motion needs waves in the scene "
                                                           "(environment.water.waves)")
        return self

    @classmethod
    def model_validate(cls, obj, *args, **kwargs):  # noqa: D102 - converts errors to ScenarioError
        from .load import validate_dict
        if isinstance(obj, cls):
            return obj
        return validate_dict(obj, _raw=lambda o: super(Scenario, cls).model_validate(o, *args, **kwargs))

    @classmethod
    def model_validate_json(cls, data, *args, **kwargs):  # noqa: D102
        from .load import parse_text
        return cls.model_validate(parse_text(data, "json"))
