"""Scenario schema of tugger lines (top-level ``tuggers``): a line from a deck point of a
vessel to a point of a body that steadies a payload against swinging and turning
(rfesim.loads.tugger, docs/theory.md "Tugger lines")::

    "tuggers": {"tug_ps": {"body": "module", "vessel": "barge",
                           "deck_point": [-6.0, 4.0, 4.0], "body_point": [-1.5, 0.0, 0.0],
                           "mode": {"kind": "tension", "tension": 5000.0}}}

Modes:

* ``tension``: a constant-tension tugger winch: the tension is ``tension`` (N), or a table
  of [t (s), T (N)] rows, linear between rows and held beyond them; the winch pays out and
  hauls in so the line keeps that tension at any length;
* ``elastic``: a braked tugger winch: the line is a tension-only spring of axial
  ``stiffness`` (N/m, EA over the line's length) and ``damping`` (N*s/m) that starts with
  ``pretension`` (N) at the scenario's initial positions (its unstretched length is the
  initial distance less pretension / stiffness), or with the given ``length``.

* ``force``: a push-pull element at a set force, a hydraulic cylinder at a set pressure:
  ``force`` (N, positive pushing the point away from the deck point), or a table of [t (s),
  P (N)] rows; its tension channel is -P (the crane templates' force-driven cylinders).

Instead of a body, a tugger may act on a point of a line: ``line`` and ``at`` (m from its
end A, on its axis).

Geometry: ``deck_point`` in the vessel frame, ``body_point`` in the body frame (default: the
body's centre). The line is straight and massless (a tugger weighs little against its
pull). Units SI.
"""
from __future__ import annotations

import math
from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .schema import (DAMPING_LIMIT, FORCE_LIMIT, LENGTH_LIMIT, MAX_DAMPING, MAX_FORCE, MAX_LENGTH, MAX_STIFFNESS,
                     STIFFNESS_LIMIT, FieldError, Vector3, _fixed_length_numbers, _Strict, _units)

TensionRow = Annotated[list[float], _fixed_length_numbers(2, "[t, tension]"), Field(min_length=2, max_length=2)]


def _check_table(value, field: str, symbol: str, ok, why: str) -> None:
    """A set value (N) or a table of [t (s), value (N)] rows with increasing times, every
    value passing ``ok`` (else FieldError ``why``)."""
    if isinstance(value, (int, float)):
        if not ok(value):
            raise FieldError(field, f"{value} N: {why}")
        return
    if not value:
        raise FieldError(field, f"a table needs at least one row [t, {symbol}]")
    for i, (t, v) in enumerate(value):
        if i and not t > value[i - 1][0]:
            raise FieldError(f"{field}.{i}.0", f"time {t} s does not increase")
        if not (math.isfinite(t) and ok(v)):
            raise FieldError(f"{field}.{i}.1", f"{v} N: {why}")


def _rows(value) -> list[list[float]]:
    """[[t, value], ...] of a set value (one row at t = 0) or a table."""
    if isinstance(value, (int, float)):
        return [[0.0, float(value)]]
    return [[float(t), float(v)] for t, v in value]


class TuggerTension(_Strict):
    """A constant-tension tugger winch: tension T(t) at any line length."""

    kind: Literal["tension"]
    tension: Union[float, list[TensionRow]] = _units("N (s, N)", "Set tension, not negative, or rows [t, T] with "
                                                                 "times strictly increasing and tensions not "
                                                                 "negative, linear between rows, held beyond them")

    @model_validator(mode="after")
    def _table(self):
        _check_table(self.tension, "tension", "T", lambda T: T >= 0.0, "a tugger pulls (tension >= 0)")
        return self

    def rows(self) -> list[list[float]]:
        return _rows(self.tension)


class TuggerForce(_Strict):
    """A push-pull element at a set force (a hydraulic cylinder at a set pressure): P(t)
    pushes the point away from the deck point when positive, pulls it when negative."""

    kind: Literal["force"]
    force: Union[float, list[TensionRow]] = _units("N (s, N)", "Set force (positive pushing), or rows [t, P] with "
                                                               "times strictly increasing, linear between rows, "
                                                               "held beyond them")

    length_min: float | None = _units("m", "End stop: the shortest length (default: none)", default=None, gt=0.0,
                                      le=MAX_LENGTH, limit=LENGTH_LIMIT)
    length_max: float | None = _units("m", "End stop: the longest length, longer than length_min (default: none)",
                                      default=None, gt=0.0,
                                      le=MAX_LENGTH, limit=LENGTH_LIMIT)
    stop_stiffness: float = _units("N/m", "Stiffness of the end stops", default=1.0e9, gt=0.0,
                                   le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)

    @model_validator(mode="after")
    def _table(self):
        _check_table(self.force, "force", "P", math.isfinite, "must be a finite force")
        if self.length_min is not None and self.length_max is not None and not self.length_min < self.length_max:
            raise FieldError("length_max", f"{self.length_max} m is not longer than length_min {self.length_min} m")
        return self

    def rows(self) -> list[list[float]]:
        return _rows(self.force)


class TuggerElastic(_Strict):
    """A braked tugger winch: a tension-only spring-damper line."""

    kind: Literal["elastic"]
    stiffness: float = _units("N/m", "Axial stiffness of the line (EA over its length)", gt=0.0,
                              le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float = _units("N*s/m", "Axial damping", default=0.0, ge=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)
    pretension: float = _units("N", "Tension at the scenario's initial positions (sets the unstretched length)",
                               default=0.0, ge=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    length: float | None = _units("m", "Unstretched length (instead of pretension)", default=None, gt=0.0,
                                  le=MAX_LENGTH, limit=LENGTH_LIMIT)

    @model_validator(mode="after")
    def _one(self):
        if self.length is not None and self.pretension != 0.0:
            raise FieldError("length", "give either length or pretension, not both")
        return self


class Tugger(_Strict):
    """A tugger line from a winch or fairlead on a vessel's deck to a body (or a point of a
    line), steadying a payload against swinging and turning: constant tension, an elastic
    braked line, or a set push-pull force."""

    body: str | None = Field(None, min_length=1, description="The body (a name of `bodies`) the line pulls on")
    line: str | None = Field(None, min_length=1, description="Or the line (a name of `lines`) it acts on, at "
                             "arc length `at` on the line's axis")
    at: float | None = _units("m", "Arc length from the line's end A of the point the tugger acts on, at most "
                                   "the line's length (with `line`)", default=None, ge=0.0)
    vessel: str = Field(..., min_length=1, description="The vessel (a name of `vessels`) whose deck carries the "
                        "tugger winch or fairlead")
    deck_point: Vector3 = _units("m", "The line's deck end (winch or fairlead) in the vessel frame")
    body_point: Vector3 = _units("m", "The line's end on the body, in the body frame (default: the centre)",
                                 default=[0.0, 0.0, 0.0])
    mode: Annotated[Union[TuggerTension, TuggerElastic, TuggerForce], Field(discriminator="kind")] = Field(
        ..., description="constant tension (a table in time), an elastic, braked line, or a set push-pull force "
        "(a cylinder)")

    @model_validator(mode="after")
    def _target(self):
        if (self.body is None) == (self.line is None):
            raise FieldError("body", "give the body the tugger acts on, or a line and the arc length at")
        if self.line is not None:
            if self.at is None:
                raise FieldError("at", f"give the arc length on line '{self.line}' (m from end A)")
            if "body_point" in self.model_fields_set:
                raise FieldError("body_point", "a line point is on the line's axis at `at`: leave out body_point")
        elif self.at is not None:
            raise FieldError("at", "at goes with line, not with body")
        return self


def check_tugger_references(sc) -> list[tuple[str, str]]:
    """A tugger pulls on an existing body from an existing vessel (its names are checked
    with the other groups' in rfesim.scenario.load)."""
    errors: list[tuple[str, str]] = []
    for name, tg in getattr(sc, "tuggers", {}).items():
        for field, value, group in (("body", tg.body, "bodies"), ("line", tg.line, "lines"),
                                    ("vessel", tg.vessel, "vessels")):
            if value is None:
                continue
            if value not in getattr(sc, group):
                known = ", ".join(sorted(getattr(sc, group))) or "none defined"
                errors.append((f"tuggers.{name}.{field}", f"unknown {field} '{value}' ({group}: {known})"))
        if tg.line is not None and tg.line in sc.lines and sc.lines[tg.line].formulation != "absolute":
            errors.append((f"tuggers.{name}.line", f"line '{tg.line}' has the {sc.lines[tg.line].formulation} "
                                                   "formulation: a tugger acts on an absolute-coordinate line"))
        elif tg.line is not None and tg.line in sc.lines and tg.at > sc.lines[tg.line].length:
            errors.append((f"tuggers.{name}.at", f"{tg.at} m is beyond the {sc.lines[tg.line].length} m of line "
                                                 f"'{tg.line}'"))
    return errors
