"""Scenario schema of winches (top-level ``winches``): a drum that pays out or hauls in a rope.

A winch acts on one absolute-coordinate line (usually a tension-only rope with a payload on
end B); its end A is the sheave or fairlead the rope leaves the winch over (attached to a
vessel, fixed, or joined to another line's end B). Payout grows every element of the line
uniformly (rfesim.model.winches, docs/theory.md "Winches and rope payout")::

    "winches": {"hoist": {"line": "rope", "stored": 500.0,
                          "mode": {"kind": "speed", "rows": [[0, 0], [5, 1.0], [45, 1.0], [50, 0]]},
                          "heave_compensation": {"kp": 0.5, "feedforward": true},
                          "shock_absorber": {"stiffness": 2.0e5, "damping": 1.0e4}}}

Modes (payout positive, haul-in negative):

* ``speed``: payout speed table rows [t (s), v (m/s)], linear between rows, the first and
  last speeds held beyond the table; payout D(t) is its exact integral from t = 0. The
  check against ``stored`` (and the haul-in limit) takes D at its exact extremes over the
  run: the rows' times, the run's ends and the zeros of the speed between rows.
* ``drum``: drum of radius r and inertia J driven by the rope tension T and the motor
  torque tau(t) (table, positive hauls in): J omega' = r T - tau, optionally held by a
  brake of torque ``brake_torque`` (the drum stands still while |r T - tau| stays below it).
  With ``layers`` the radius r grows with the rope on the drum (``drum_radius``) and
  v = omega r gives the payout acceleration r (r T - tau) / J - v^2 r'(L) / r. J holds the
  rope on the drum (``rope_inertia``, default on): J = inertia + mu * integral of r^2 dl.
* ``tension``: constant tension: it pays out at (T - tension - dead_band) / gain above the
  band, hauls in at (T - tension + dead_band) / gain below it, at most ``max_speed``.

``heave_compensation`` adds a PID speed v_c = kp e + ki int(e) + kd de/dt (+ zeta' with
feedforward) with e = zeta - D_c, zeta the vertical motion of the rope's end-A point
since the start and D_c the payout the compensation has made. ``shock_absorber`` puts a
spring k_sa with a damper c_sa beside it in series with the rope at the winch (both
required; ``"damping": 0`` for a plain spring). Units SI.
"""
from __future__ import annotations

import math
from typing import Annotated, Literal, Union

from pydantic import Field, model_validator

from .schema import (DAMPING_LIMIT, FORCE_LIMIT, INERTIA_LIMIT, LENGTH_LIMIT, MAX_DAMPING, MAX_FORCE, MAX_INERTIA,
                     MAX_LENGTH, MAX_STIFFNESS, STIFFNESS_LIMIT, FieldError, _fixed_length_numbers, _Strict, _units)

DEFAULT_STORED = 1000.0     # m of rope on the drum at the start

SpeedRow = Annotated[list[float], _fixed_length_numbers(2, "[t, speed]"), Field(min_length=2, max_length=2)]
TorqueRow = Annotated[list[float], _fixed_length_numbers(2, "[t, torque]"), Field(min_length=2, max_length=2)]


def _increasing(rows, name: str = "rows") -> None:
    for i in range(1, len(rows)):
        if not rows[i][0] > rows[i - 1][0]:
            raise FieldError(f"{name}.{i}", f"time {rows[i][0]} s does not increase")


class WinchSpeed(_Strict):
    """Prescribed payout speed: rows [t (s), v (m/s)], v > 0 pays out, linear between rows."""

    kind: Literal["speed"]
    rows: list[SpeedRow] = _units("s, m/s", "Payout speed rows [t, v], times strictly increasing, v > 0 pays out, "
                                            "linear between rows; the payout over the run at most `stored`, and at "
                                            "least 5 % of the line left out", min_length=1)

    @model_validator(mode="after")
    def _times(self):
        _increasing(self.rows)
        return self


class DrumLayers(_Strict):
    """Level-wound layers on the drum: the radius at which the rope leaves the drum grows
    with the rope on it (``drum_radius``)."""

    width: float = _units("m", "Drum width between the flanges", gt=0.0)
    rope_diameter: float = _units("m", "Rope diameter (the pitch of the turns and of the layers), at most the "
                                       "width and less than twice the drum's radius", gt=0.0)

    @property
    def growth(self) -> float:
        """d(r^2)/dL = d^2 / (pi w) (m^2 per m of rope on the drum), see ``drum_radius``."""
        return self.rope_diameter ** 2 / (math.pi * self.width)


def drum_radius(radius: float, layers: DrumLayers | None, on_drum: float) -> float:
    """Radius (m) at which the rope leaves a drum holding ``on_drum`` m of rope.

    Without layers, ``radius``. With them, ``radius`` is the centre of the first layer's
    turns (core radius plus half a rope diameter) and the rope fills the drum's cross-section
    (width w, turns of pitch d in layers of pitch d): the rope holds the annulus
    pi w (r^2 - r_1^2) = d^2 L, so r = sqrt(r_1^2 + L d^2 / (pi w)). At k full layers this
    lies between the k-th and the (k + 1)-th layer's turn centres (which jump by d at each
    crossover): the mean radius of a level-wound drum, continuous in L."""
    if layers is None:
        return float(radius)
    L = max(float(on_drum), 0.0)
    return math.sqrt(radius * radius + L * layers.growth)


def drum_rope_inertia(radius: float, layers: DrumLayers | None, on_drum: float, mass_per_length: float) -> float:
    """Rotational inertia (kg*m^2) of the ``on_drum`` m of rope (``mass_per_length`` kg/m) on
    the drum about its axis, mu * integral of r(l)^2 dl over the rope on it, r(l) as in
    ``drum_radius``: mu r^2 L on one radius, mu (r_1^2 L + L^2 d^2 / (2 pi w)) in layers."""
    L = max(float(on_drum), 0.0)
    if layers is None:
        return mass_per_length * radius * radius * L
    return mass_per_length * (radius * radius * L + 0.5 * L * L * layers.growth)


class WinchDrum(_Strict):
    """Drum dynamics J omega' = r T - tau (omega > 0 pays out), motor torque table, brake."""

    kind: Literal["drum"]
    radius: float = _units("m", "Drum radius (rope layer; with layers: the first layer's turn centres)", gt=0.0,
                           le=MAX_LENGTH, limit=LENGTH_LIMIT)
    layers: DrumLayers | None = Field(None, description="Level-wound layers: the radius grows with the rope on "
                                      "the drum, r = sqrt(radius^2 + L d^2 / (pi width)) (default: one radius)")
    inertia: float = _units("kg*m^2", "Rotational inertia of the drum and the drive about the drum axis", gt=0.0,
                            le=MAX_INERTIA, limit=INERTIA_LIMIT)
    torque: list[TorqueRow] = _units("s, N*m", "Motor torque rows [t, torque], times strictly increasing, "
                                               "positive hauls in, linear between rows", default=[[0.0, 0.0]],
                                     min_length=1)
    brake_torque: float = _units("N*m", "Brake: holds the drum while the net torque stays below it (0: none)",
                                 default=0.0, ge=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    rope_inertia: bool = Field(True, description="Add the inertia of the rope on the drum, mass_per_length times "
                               "the integral of r^2 over it, to ``inertia`` (it falls as the rope pays out); false "
                               "when ``inertia`` already holds it")

    @model_validator(mode="after")
    def _times(self):
        _increasing(self.torque, "torque")
        if self.layers is not None and self.layers.rope_diameter >= 2.0 * self.radius:
            raise FieldError("layers.rope_diameter", f"{self.layers.rope_diameter} m does not fit a first layer "
                                                     f"whose turns' centres are at radius {self.radius} m")
        if self.layers is not None and self.layers.rope_diameter > self.layers.width:
            raise FieldError("layers.rope_diameter", f"{self.layers.rope_diameter} m is wider than the drum "
                                                     f"({self.layers.width} m between the flanges)")
        return self


class WinchTension(_Strict):
    """Constant tension: payout speed (T - tension -+ dead_band) / gain outside the band."""

    kind: Literal["tension"]
    tension: float = _units("N", "Set tension", gt=0.0, le=MAX_FORCE, limit=FORCE_LIMIT)
    dead_band: float = _units("N", "Dead band around the set tension", default=0.0, ge=0.0,
                              le=MAX_FORCE, limit=FORCE_LIMIT)
    gain: float = _units("N*s/m", "Tension excess per unit payout speed", gt=0.0, le=MAX_DAMPING, limit=DAMPING_LIMIT)
    max_speed: float = _units("m/s", "Largest payout or haul-in speed", gt=0.0)


class HeaveCompensation(_Strict):
    """Active heave compensation: a PID on winch speed cancelling the vertical motion of the
    rope's end-A point (the sheave) since the start."""

    kp: float = _units("1/s", "Proportional gain", default=1.0, ge=0.0)
    ki: float = _units("1/s^2", "Integral gain", default=0.0, ge=0.0)
    kd: float = _units("1", "Derivative gain", default=0.0, ge=0.0)
    max_speed: float = _units("m/s", "Largest compensation speed", default=10.0, gt=0.0)
    feedforward: bool = Field(False, description="Add the sheave's vertical velocity to the speed")


class ShockAbsorber(_Strict):
    """A spring k_sa with a damper c_sa beside it (Kelvin-Voigt), in series with the rope at
    the winch. The damping has no default: an absorber's damping is what makes it one (an
    undamped spring under the payload rings at its bounce frequency with nothing to stop it);
    give 0 for a plain spring."""

    stiffness: float = _units("N/m", "Spring stiffness k_sa", gt=0.0, le=MAX_STIFFNESS, limit=STIFFNESS_LIMIT)
    damping: float | None = _units("N*s/m", "Damping c_sa of the damper beside the spring (required; 0: a plain "
                                   "spring; critical on a payload of mass m: 2 sqrt(k_sa m))", default=None, ge=0.0,
                                   le=MAX_DAMPING, limit=DAMPING_LIMIT)

    @model_validator(mode="after")
    def _damping_given(self):
        if self.damping is None:
            raise FieldError("damping", "give the absorber's damping c_sa (N*s/m), e.g. a fraction of critical "
                                        "2 sqrt(k_sa m) on the payload's mass m: an undamped spring in series with "
                                        "the rope rings for ever at the payload's bounce frequency (0 for a plain "
                                        "spring)")
        return self


class Winch(_Strict):
    """A winch paying out or hauling in one rope line from its end A: a prescribed speed,
    drum dynamics under the rope tension and a motor torque, or constant tension; with
    optional heave compensation and a shock absorber."""

    line: str = Field(..., description="Name of the (absolute-coordinate) line the winch pays out")
    stored: float = _units("m", "Rope on the drum at the start (payout beyond it is refused)",
                           default=DEFAULT_STORED, gt=0.0, le=MAX_LENGTH, limit=LENGTH_LIMIT)
    mode: Annotated[Union[WinchSpeed, WinchDrum, WinchTension], Field(discriminator="kind")] = Field(
        default_factory=lambda: WinchSpeed(kind="speed", rows=[[0.0, 0.0]]),
        description="speed profile, drum dynamics or constant tension (default: holds the rope)")
    heave_compensation: HeaveCompensation | None = None
    shock_absorber: ShockAbsorber | None = None
    payout_inertia: bool = Field(True, description="Inertia of the rope's material running down the hanging "
                                 "rope as the payout speeds up or slows down: the elements' nodes move at "
                                 "xi dD/dt, the material at dD/dt, so each element i gets the follower load "
                                 "-m_i (1 - xi_i) d2D/dt2 along it (docs/theory.md, 'Winches and rope payout')")


class TemplateWinch(Winch):
    """The winch of a crane template (``cranes.<name>.winch``): a ``winches`` entry without
    ``line`` -- it acts on the crane's own rope. Validated with the template, so its errors
    name ``cranes.<name>.winch....``, the field the user wrote."""

    line: str | None = Field(None, description="Leave out: the template's winch acts on its own rope")

    @model_validator(mode="after")
    def _own_rope(self):
        if self.line is not None:
            raise FieldError("line", "the template's winch acts on its own rope: leave out line")
        return self


def speed_payout(rows, t: float) -> tuple[float, float]:
    """(payout D(t) in m, speed v(t) in m/s) of a speed table: the exact integral from 0 of
    the piecewise-linear speed, held constant before the first and after the last row."""
    ts = [float(r[0]) for r in rows]
    vs = [float(r[1]) for r in rows]

    def v_at(x: float) -> float:
        if x <= ts[0]:
            return vs[0]
        if x >= ts[-1]:
            return vs[-1]
        for i in range(1, len(ts)):
            if x <= ts[i]:
                u = (x - ts[i - 1]) / (ts[i] - ts[i - 1])
                return vs[i - 1] + u * (vs[i] - vs[i - 1])
        return vs[-1]

    def integral(a: float, b: float) -> float:
        """Integral of v over [a, b] (a <= b): trapezoids between the breakpoints (exact)."""
        pts = [a] + [x for x in ts if a < x < b] + [b]
        return sum(0.5 * (v_at(pts[k]) + v_at(pts[k + 1])) * (pts[k + 1] - pts[k]) for k in range(len(pts) - 1))

    D = integral(0.0, t) if t >= 0.0 else -integral(t, 0.0)
    return D, v_at(t)


def payout_extreme_times(rows, duration: float) -> list[float]:
    """The times in [0, duration] at which the payout D(t) of a speed table (``speed_payout``:
    the integral of the piecewise-linear speed, constant beyond the rows) can be largest or
    least: the ends 0 and ``duration``, the rows' times (kinks of D' = v) and every zero of
    v inside a row interval, t* = t_i - v_i (t_{i+1} - t_i) / (v_{i+1} - v_i) where v changes
    sign (D' = 0: a peak or trough of the payout between rows). Elsewhere D is monotone."""
    ts = [0.0, float(duration)] + [float(r[0]) for r in rows if 0.0 < r[0] < duration]
    for (t0, v0), (t1, v1) in zip(rows[:-1], rows[1:]):
        if v0 * v1 < 0.0:
            t = t0 - v0 * (t1 - t0) / (v1 - v0)
            if 0.0 < t < duration:
                ts.append(float(t))
    return sorted(ts)


def check_winch_references(sc) -> list[tuple[str, str]]:
    """A winch acts on one existing absolute-coordinate line, one winch per line, in a
    generalized-alpha run; a speed table must not pay out more than the stored rope."""
    errors: list[tuple[str, str]] = []
    owner: dict[str, str] = {}
    dyn = sc.analysis.dynamics
    for name, w in sc.winches.items():
        base = f"winches.{name}"
        if w.line not in sc.lines:
            known = ", ".join(sorted(sc.lines)) or "none defined"
            errors.append((f"{base}.line", f"unknown line '{w.line}' (lines: {known})"))
            continue
        line = sc.lines[w.line]
        if line.formulation != "absolute":
            errors.append((f"{base}.line", f"line '{w.line}' is in the {line.formulation} formulation: a winch "
                                           f"pays out an absolute-coordinate line"))
        if w.line in owner:
            errors.append((f"{base}.line", f"line '{w.line}' already has winch '{owner[w.line]}': one winch per "
                                           f"line"))
        owner.setdefault(w.line, name)
        if any(sup.line == w.line for sup in sc.supports.values() if getattr(sup, "line", None) is not None
               and sup.kind in ("tensioner", "reel")):
            errors.append((f"{base}.line", f"line '{w.line}' is already paid out by a tensioner or reel"))
        if dyn.enabled and dyn.duration > 0 and dyn.integrator.kind != "generalized-alpha":
            errors.append(("analysis.dynamics.integrator.kind", f"winch '{name}' needs the generalized-alpha "
                                                                f"integrator (got {dyn.integrator.kind})"))
        if w.mode.kind == "speed" and dyn.enabled:
            ts = payout_extreme_times(w.mode.rows, float(dyn.duration))
            worst = max(speed_payout(w.mode.rows, t)[0] for t in ts)
            if worst > w.stored:
                errors.append((f"{base}.mode.rows", f"pays out {worst:.6g} m within the run's {dyn.duration} s, "
                                                    f"more than the {w.stored:.6g} m stored on the drum"))
            least = min(speed_payout(w.mode.rows, t)[0] for t in ts)
            if line.length + least < 0.05 * line.length:
                errors.append((f"{base}.mode.rows", f"hauls in {-least:.6g} m of the line's {line.length} m: at "
                                                    f"least 5 % of it must stay out"))
    return errors
