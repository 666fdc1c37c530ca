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

Geometry: ``deck_point`` in the vessel frame, ``body_point`` in the body frame (default: the
body's centre). The line is straight and massless (a tugger weighs little against its
pull). Units SI.
"""
from __future__ import annotations

from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .schema import FieldError, Vector3, _fixed_length_numbers, _Strict, _units

TensionRow = Annotated[list[float], _fixed_length_numbers(2, "[t, tension]"), Field(min_length=2, max_length=2)]


class TuggerTension(_Strict):
    """A constant-tension tugger winch: tension T(t) at any line length."""

    kind: Literal["tension"]
    tension: Union[float, list[TensionRow]] = Field(..., description="Set tension (N), or rows [t (s), T (N)], "
                                                    "linear between rows, held beyond them",
                                                    json_schema_extra={"units": "N (s, N)"})

    @model_validator(mode="after")
    def _table(self):
        if isinstance(self.tension, (int, float)):
            if not self.tension >= 0.0:
                raise FieldError("tension", f"{self.tension} N: a tugger pulls (tension >= 0)")
            return self
        if not self.tension:
            raise FieldError("tension", "a table needs at least one row [t, T]")
        for i, (t, T) in enumerate(self.tension):
            if i and not t > self.tension[i - 1][0]:
                raise FieldError(f"tension.{i}.0", f"time {t} s does not increase")
            if not T >= 0.0:
                raise FieldError(f"tension.{i}.1", f"{T} N: a tugger pulls (tension >= 0)")
        return self

    def rows(self) -> list[list[float]]:
        if isinstance(self.tension, (int, float)):
            return [[0.0, float(self.tension)]]
        return [[float(t), float(T)] for t, T in self.tension]


class TuggerElastic(_Strict):
    """A braked tugger winch: a tension-only spring-damper line."""

    kind: Literal["elastic"]
    stiffness: float = _units("N/m", "Axial stiffness of the line (EA over its length)", gt=0.0)
    damping: float = _units("N*s/m", "Axial damping", default=0.0, ge=0.0)
    pretension: float = _units("N", "Tension at the scenario's initial positions (sets the unstretched length)",
                               default=0.0, ge=0.0)
    length: float | None = _units("m", "Unstretched length (instead of pretension)", default=None, gt=0.0)

    @model_validator(mode="after")
    def _one(self):
        if self.length is not None and self.pretension != 0.0:
            raise FieldError("length", "give either length or pretension, not both")
        return self


class Tugger(_Strict):
    """A tugger line from a vessel's deck to a body (see the module text)."""

    body: str = Field(..., min_length=1, description="The body (a name of `bodies`) the line pulls on")
    vessel: str = Field(..., min_length=1, description="The vessel (a name of `vessels`) whose deck carries the "
                        "tugger winch or fairlead")
    deck_point: Vector3 = _units("m", "The line's deck end (winch or fairlead) in the vessel frame")
    body_point: Vector3 = _units("m", "The line's end on the body, in the body frame (default: the centre)",
                                 default=[0.0, 0.0, 0.0])
    mode: Annotated[Union[TuggerTension, TuggerElastic], Field(discriminator="kind")] = Field(
        ..., description="constant tension (a table in time) or an elastic, braked line")


def check_tugger_references(sc) -> list[tuple[str, str]]:
    """A tugger pulls on an existing body from an existing vessel (its names are checked
    with the other groups' in rfesim.scenario.load)."""
    errors: list[tuple[str, str]] = []
    for name, tg in getattr(sc, "tuggers", {}).items():
        for field, value, group in (("body", tg.body, "bodies"), ("vessel", tg.vessel, "vessels")):
            if value not in getattr(sc, group):
                known = ", ".join(sorted(getattr(sc, group))) or "none defined"
                errors.append((f"tuggers.{name}.{field}", f"unknown {field} '{value}' ({group}: {known})"))
    return errors
