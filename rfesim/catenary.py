"""Analytic elastic catenary of a single line hanging in a vertical plane.

This module gives the closed-form (quasi-static) solution of a uniform, elastic, perfectly
flexible line with no bending stiffness, under its own submerged weight, between two end
points in a vertical plane.  It is used

* by the statics solver, as a start shape for lines that partly lie on the seabed, and
* by the validation tests, as a reference solution.

It depends on numpy and scipy only.  All quantities are in SI units (m, N, N/m).

Conventions (the same as MoorPy's ``catenary`` function, our public validation reference):

* End A is the anchor (lower end) at ``(x, z) = (0, 0)``; end B is the fairlead at
  ``(span, height)``.  ``z`` is positive up.
* ``weight`` ``w`` is the submerged weight per unit *unstretched* length [N/m], ``w > 0``.
* ``EA`` is the axial stiffness [N]; the strain under tension ``T`` is ``T / EA``.
* ``H`` is the horizontal tension (constant along the suspended line), ``V`` the vertical
  tension component.  ``V_B`` is the vertical tension at the fairlead (positive: the line
  pulls the fairlead down).  ``V_A = V_B - w * L_s`` is the vertical tension component at
  the lower end of the suspended part of unstretched length ``L_s`` (positive: the line
  leaves that point going upwards).
* With ``seabed=True`` a rigid horizontal seabed passes through end A (``z = 0``); a part of
  the line of unstretched length ``L_b`` (the grounded length) may lie on it between the
  anchor and the touchdown point.  ``friction`` is the axial Coulomb friction coefficient
  ``C_B`` of that part: walking from the touchdown point toward the anchor the tension falls
  by ``C_B * w`` per unit length and is floored at zero (MoorPy's treatment).

Equations (Jonkman, "Dynamics modeling and loads analysis of an offshore floating wind
turbine", NREL/TP-500-41958, 2007, eqs. 2-35 to 2-40; Irvine, "Cable Structures", 1981,
ch. 1; identical to MoorPy's ``Catenary.py``).  For a suspended part of unstretched length
``L_s``, horizontal tension ``H``, vertical tension ``V`` at its top and
``V_A = V - w L_s`` at its bottom, the horizontal and vertical offsets top minus bottom are

    (E1)  x = H/w [asinh(V/H) - asinh(V_A/H)] + H L_s / EA
    (E2)  z = H/w [sqrt(1 + (V/H)^2) - sqrt(1 + (V_A/H)^2)] + (V^2 - V_A^2) / (2 EA w)

A grounded part of unstretched length ``L_b = L - V_B / w`` (when ``V_B < w L``) carries the
tension ``T(s) = max(H - C_B w (L_b - s), 0)`` at unstretched arc length ``s`` from the
anchor; its stretched horizontal length is

    (E3)  x_b = L_b + (1/EA) * integral_0^L_b T(s) ds
              = L_b + (H L_b - C_B w L_b^2 / 2) / EA     if H >= C_B w L_b (anchor tension > 0)
              = L_b + H^2 / (2 C_B w EA)                  otherwise (zero tension near anchor)

and the suspended part above it is (E1)-(E2) with ``V_A = 0`` and ``L_s = V_B / w``.  The two
closure equations ``x_total(H, V_B) = span`` and ``z_total(H, V_B) = height`` are solved for
``(H, V_B)`` by a damped Newton iteration with an analytic Jacobian, started from the
Peyrot-Goulois guess (Peyrot and Goulois, "Analysis of cable structures", Computers &
Structures 10, 1979, pp. 805-813) and from an elastic taut-line guess, with
``scipy.optimize.root`` as a fallback.

Numerically stable forms used throughout (they avoid the cancellation of (E1)-(E2) when the
line is nearly straight): with ``T_top = hypot(H, V)`` and ``T_bottom = hypot(H, V_A)``,

    (E2')  z = L_s (V + V_A) [1 / (T_top + T_bottom) + 1 / (2 EA)]
    (E1')  asinh(V/H) - asinh(V_A/H) = asinh(w L_s (V + V_A) / (V T_bottom + V_A T_top))
           when V and V_A have the same sign (otherwise the plain difference, which has no
           cancellation, is used).

(E2') follows from ``sqrt(1+a^2) - sqrt(1+b^2) = (a^2 - b^2) / (sqrt(1+a^2) + sqrt(1+b^2))``
and ``V - V_A = w L_s``; (E1') from ``asinh a - asinh b = asinh(a sqrt(1+b^2) - b sqrt(1+a^2))``.

Degenerate cases handled without iteration:

* ``span == 0``: vertical line (``H = 0``), taut or, without seabed, hanging in a U.
* ``seabed=True`` and ``height == 0``: the whole line lies on the seabed (tension from the
  stretch needed to reach ``span``, with friction as in MoorPy's profile type 0).
* ``seabed=True`` and ``length >= span + L_hanging``: the line is so slack that it would hang
  vertically from the fairlead onto the seabed (``H = 0``; MoorPy's profile type 4).  The
  grounded line is then laid straight from the anchor and the excess length, which a plane
  curve between the ends cannot hold, is bunched at the touchdown point below the fairlead.
  This is only a geometric placeholder, good enough as a start shape.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.optimize

__all__ = ["CatenarySolution", "solve_catenary", "natural_catenary", "hanging_length"]

# Names of the solution regimes (stored in CatenarySolution.regime).
REGIME_SUSPENDED = "suspended"          # no seabed contact (V_A may be < 0 without seabed)
REGIME_GROUNDED = "grounded"            # part of the line lies on the seabed, H > 0
REGIME_ON_SEABED = "on_seabed"          # height == 0: the whole line lies on the seabed
REGIME_SLACK_VERTICAL = "slack_vertical"  # H == 0: hangs vertically onto the seabed
REGIME_VERTICAL = "vertical"            # span == 0: vertical line, H == 0

_MACHINE_EPSILON = float(np.finfo(float).eps)


@dataclass(frozen=True)
class CatenarySolution:
    """Static solution of one line between the anchor (end A) and the fairlead (end B).

    Tensions are effective tensions in N; lengths are unstretched lengths in m.

    Attributes
    ----------
    horizontal_tension : H [N], at the fairlead (constant along the suspended part).
    vertical_tension_top : V_B [N], vertical tension at the fairlead; positive when the line
        pulls the fairlead downwards.
    vertical_tension_anchor : V_A [N] = V_B - w * suspended_length, vertical tension component
        at end A.  It is 0 when part of the line lies on the seabed, > 0 when the line
        leaves the anchor going up, and < 0 (only possible with ``seabed=False``) when the
        line leaves end A going down and sags below it (sign convention of MoorPy's ``fAV``).
    anchor_tension : |tension| at end A [N]; ``max(H - C_B w L_b, 0)`` on the seabed (may be
        smaller than H with friction), ``hypot(H, V_A)`` otherwise.
    top_tension : |tension| at the fairlead [N] = hypot(H, V_B).
    grounded_length : unstretched length lying on the seabed [m] (0 if none).
    suspended_length : unstretched suspended length [m].
    span, height : fairlead position relative to the anchor [m] (inputs).
    length : total unstretched length [m] (input).
    weight : submerged weight per unit unstretched length [N/m] (input).
    axial_stiffness : EA [N] (input).
    friction : axial seabed friction coefficient C_B [-] (input, 0 without seabed).
    seabed : whether a seabed through end A was modelled (input).
    regime : one of "suspended", "grounded", "on_seabed", "slack_vertical", "vertical".
    """

    horizontal_tension: float
    vertical_tension_top: float
    vertical_tension_anchor: float
    anchor_tension: float
    top_tension: float
    grounded_length: float
    suspended_length: float
    span: float
    height: float
    length: float
    weight: float
    axial_stiffness: float
    friction: float
    seabed: bool
    regime: str

    # ------------------------------------------------------------------ helpers
    def _arc_length(self, arc_length) -> np.ndarray:
        """Unstretched arc length(s) from end A as a float array, checked to lie in [0, L]."""
        values = np.asarray(arc_length, dtype=float)
        slack = 1e-9 * self.length
        if np.any(values < -slack) or np.any(values > self.length + slack) or np.any(~np.isfinite(values)):
            raise ValueError(
                f"s (arc length) must lie in [0, length={self.length}] m; "
                f"got values in [{np.min(values)}, {np.max(values)}]"
            )
        return np.clip(values, 0.0, self.length)

    @property
    def _touchdown_horizontal_position(self) -> float:
        """Stretched horizontal distance from the anchor to the touchdown point [m], eq. (E3)."""
        if self.regime == REGIME_SLACK_VERTICAL:
            return self.span
        if self.grounded_length <= 0.0:
            return 0.0
        return self.grounded_length + _grounded_stretch(
            self.horizontal_tension, self.grounded_length, self.grounded_length,
            self.weight, self.axial_stiffness, self.friction,
        )

    # ------------------------------------------------------------------ public API
    def profile(self, s) -> tuple[np.ndarray, np.ndarray]:
        """Line shape: horizontal ``x(s)`` and vertical ``z(s)`` [m] relative to end A.

        Parameters
        ----------
        s : float or array of unstretched arc length from end A [m], in ``[0, length]``.

        Returns
        -------
        (x, z) : arrays of the shape of ``s`` [m]; elastic stretch is included, so
        ``profile(length) == (span, height)`` to the solver tolerance.
        """
        arc = self._arc_length(s)
        H = self.horizontal_tension
        w = self.weight
        EA = self.axial_stiffness
        grounded = self.grounded_length

        if self.regime in (REGIME_SUSPENDED, REGIME_VERTICAL):
            # Eqs. (E1')-(E2') for the part [0, s], bottom vertical tension V_A, top V_A + w s.
            x, z = _suspended_offsets(H, self.vertical_tension_anchor + w * arc, arc, w, EA)
            return x, z

        x = np.empty_like(arc)
        z = np.zeros_like(arc)
        on_ground = arc <= grounded
        if self.regime == REGIME_SLACK_VERTICAL or (self.regime == REGIME_ON_SEABED and H == 0.0):
            # H = 0: zero tension, no stretch; excess length bunched below the fairlead.
            x[on_ground] = np.minimum(arc[on_ground], self.span)
        else:
            # Eq. (E3) evaluated up to s: s + (1/EA) * integral_0^s T(u) du.
            x[on_ground] = arc[on_ground] + _grounded_stretch(
                H, grounded, arc[on_ground], w, EA, self.friction
            )
        hanging = ~on_ground
        if np.any(hanging):
            from_touchdown = arc[hanging] - grounded
            # Eqs. (E1')-(E2') with V_A = 0 at the touchdown point.
            x_hanging, z_hanging = _suspended_offsets(H, w * from_touchdown, from_touchdown, w, EA)
            x[hanging] = self._touchdown_horizontal_position + x_hanging
            z[hanging] = z_hanging
        return x, z

    def tension(self, s) -> np.ndarray:
        """Effective tension magnitude [N] at unstretched arc length ``s`` [m] from end A."""
        arc = self._arc_length(s)
        H = self.horizontal_tension
        w = self.weight
        if self.regime in (REGIME_SUSPENDED, REGIME_VERTICAL):
            return np.hypot(H, self.vertical_tension_anchor + w * arc)
        grounded = self.grounded_length
        on_ground = arc <= grounded
        return np.where(
            on_ground,
            np.maximum(H - self.friction * w * (grounded - arc), 0.0),
            np.hypot(H, w * (arc - grounded)),
        )

    def slope(self, s) -> np.ndarray:
        """Slope dz/dx [-] of the line at unstretched arc length ``s`` [m] from end A.

        On the suspended part this is ``V(s) / H`` (tangent parallel to the tension); on the
        seabed it is 0; it is +-inf for a vertical part (H = 0).
        """
        arc = self._arc_length(s)
        H = self.horizontal_tension
        w = self.weight
        if self.regime in (REGIME_SUSPENDED, REGIME_VERTICAL):
            vertical = self.vertical_tension_anchor + w * arc
        else:
            vertical = np.where(arc <= self.grounded_length, 0.0, w * (arc - self.grounded_length))
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(vertical == 0.0, 0.0, vertical / H)


# ---------------------------------------------------------------------------- formulas
def hanging_length(weight: float, EA: float, height: float) -> float:
    """Unstretched length [m] of a line hanging vertically (H = 0) over ``height`` [m].

    Solves ``L + w L^2 / (2 EA) = height`` (stretch of a line under its own weight),
    written in a cancellation-free form: ``L = 2 h / (1 + sqrt(1 + 2 h w / EA))``.
    """
    return 2.0 * height / (1.0 + math.sqrt(1.0 + 2.0 * height * weight / EA))


def _suspended_offsets(H, V_top, suspended_length, weight, EA):
    """Offsets (x, z) [m] top minus bottom of a suspended part, eqs. (E1')-(E2').

    ``H`` [N] >= 0 scalar; ``V_top`` [N] and ``suspended_length`` [m] scalars or arrays.
    For ``H == 0`` the vertical-line limit is returned (x = 0).
    """
    V_top = np.asarray(V_top, dtype=float)
    length = np.asarray(suspended_length, dtype=float)
    V_bottom = V_top - weight * length
    tension_top = np.hypot(H, V_top)
    tension_bottom = np.hypot(H, V_bottom)
    tension_sum = tension_top + tension_bottom
    with np.errstate(divide="ignore", invalid="ignore"):
        # (E2'): z = L_s (V + V_A) [1/(T_top + T_bottom) + 1/(2 EA)]
        z = length * (V_top + V_bottom) * (np.where(tension_sum > 0.0, 1.0 / tension_sum, 0.0) + 0.5 / EA)
        if H == 0.0:
            x = np.zeros(np.broadcast(V_top, length).shape)
        else:
            x = H / weight * _asinh_difference(H, V_top, V_bottom, length, weight) + H * length / EA
    return x, z


def _asinh_difference(H, V_top, V_bottom, length, weight):
    """asinh(V_top/H) - asinh(V_bottom/H) [-], cancellation-free, eq. (E1')."""
    V_top = np.asarray(V_top, dtype=float)
    V_bottom = np.asarray(V_bottom, dtype=float)
    same_sign = V_top * V_bottom > 0.0
    tension_top = np.hypot(H, V_top)
    tension_bottom = np.hypot(H, V_bottom)
    denominator = V_top * tension_bottom + V_bottom * tension_top
    with np.errstate(divide="ignore", invalid="ignore"):
        stable = np.arcsinh(weight * length * (V_top + V_bottom) / denominator)
        plain = np.arcsinh(V_top / H) - np.arcsinh(V_bottom / H)
    return np.where(same_sign, stable, plain)


def _grounded_stretch(H, grounded_length, arc_length, weight, EA, friction):
    """Elastic elongation [m] of the grounded part between the anchor and ``arc_length``.

    ``(1/EA) * integral_0^s T(u) du`` with ``T(u) = max(H - C_B w (L_b - u), 0)`` (eq. E3),
    ``s = arc_length <= L_b = grounded_length``.  The tension is zero up to
    ``s_0 = L_b - H / (C_B w)`` (MoorPy's ``xB``); from ``m = max(s_0, 0)`` to ``s`` it gives
    ``[H (s - m) - C_B w ((L_b - m)^2 - (L_b - s)^2) / 2] / EA``.
    """
    arc = np.asarray(arc_length, dtype=float)
    if friction <= 0.0:
        return H * arc / EA
    zero_tension_end = max(grounded_length - H / (friction * weight), 0.0)
    start = np.minimum(arc, zero_tension_end)  # no stretch before the tension becomes positive
    return (
        H * (arc - start)
        - 0.5 * friction * weight * ((grounded_length - start) ** 2 - (grounded_length - arc) ** 2)
    ) / EA


class _ClosureEquations:
    """Closure residuals ``[x(H, V_B) - span, z(H, V_B) - height]`` [m] and their Jacobian.

    With a seabed, the grounded branch (E1)-(E3) is used when ``V_B < w L`` and the fully
    suspended branch (E1)-(E2) otherwise; the two are continuous with a continuous Jacobian
    at ``V_B = w L``.
    """

    def __init__(self, span, height, length, weight, EA, seabed, friction):
        self.span = span
        self.height = height
        self.length = length
        self.weight = weight
        self.EA = EA
        self.seabed = seabed
        self.friction = friction if seabed else 0.0

    def is_grounded(self, V_top: float) -> bool:
        return self.seabed and V_top < self.weight * self.length

    def evaluate(self, H: float, V_top: float):
        """Return (residual [2] in m, Jacobian [2x2] in m/N) at (H > 0, V_top)."""
        w, EA, L, friction = self.weight, self.EA, self.length, self.friction
        tension_top = math.hypot(H, V_top)
        cos_top = H / tension_top          # 1 / sqrt(1 + (V/H)^2)
        sin_top = V_top / tension_top      # (V/H) / sqrt(1 + (V/H)^2)
        if not self.is_grounded(V_top):
            # Fully suspended: eqs. (E1')-(E2') with L_s = L, V_A = V_B - w L.
            V_bottom = V_top - w * L
            tension_bottom = math.hypot(H, V_bottom)
            cos_bottom = H / tension_bottom
            sin_bottom = V_bottom / tension_bottom
            asinh_difference = float(_asinh_difference(H, V_top, V_bottom, L, w))
            x = H / w * asinh_difference + H * L / EA
            z = L * (V_top + V_bottom) * (1.0 / (tension_top + tension_bottom) + 0.5 / EA)
            dx_dH = (asinh_difference - (sin_top - sin_bottom)) / w + L / EA
            dx_dV = (cos_top - cos_bottom) / w
            dz_dH = dx_dV
            dz_dV = (sin_top - sin_bottom) / w + L / EA
        else:
            # Touchdown: suspended part L_s = V_B / w with V_A = 0, grounded L_b = L - L_s.
            suspended = max(V_top, 0.0) / w
            grounded = L - suspended
            stretch = float(_grounded_stretch(H, grounded, grounded, w, EA, friction))
            x = grounded + stretch + H / w * math.asinh(V_top / H) + H * suspended / EA
            z = V_top * V_top * (1.0 / (w * (tension_top + H)) + 0.5 / (w * EA))
            # Derivatives of the grounded stretch with respect to H and to L_b (eq. E3).
            if friction <= 0.0 or H >= friction * w * grounded:
                dstretch_dH = grounded / EA
                dstretch_dgrounded = (H - friction * w * grounded) / EA
            else:
                dstretch_dH = H / (friction * w * EA)
                dstretch_dgrounded = 0.0
            dx_dH = (math.asinh(V_top / H) - sin_top) / w + suspended / EA + dstretch_dH
            dx_dV = (cos_top - 1.0) / w + H / (w * EA) - dstretch_dgrounded / w
            dz_dH = (cos_top - 1.0) / w
            dz_dV = sin_top / w + V_top / (w * EA)
        residual = np.array([x - self.span, z - self.height])
        jacobian = np.array([[dx_dH, dx_dV], [dz_dH, dz_dV]])
        return residual, jacobian


# ---------------------------------------------------------------------------- solver
def _check_inputs(span, height, length, weight, EA, seabed, friction, tol) -> None:
    """Raise ValueError naming the offending field for impossible input."""
    values = dict(span=span, height=height, length=length, weight=weight, EA=EA, friction=friction, tol=tol)
    for name, value in values.items():
        if not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool):
            raise ValueError(f"{name} must be a real number, got {value!r}")
        if not math.isfinite(float(value)):
            raise ValueError(f"{name} must be finite, got {value!r}")
    if length <= 0.0:
        raise ValueError(f"length (unstretched line length) must be > 0 m, got {length!r}")
    if weight <= 0.0:
        raise ValueError(f"weight (submerged weight per unit length) must be > 0 N/m, got {weight!r}")
    if EA <= 0.0:
        raise ValueError(f"EA (axial stiffness) must be > 0 N, got {EA!r}")
    if span < 0.0:
        raise ValueError(f"span (horizontal distance anchor to fairlead) must be >= 0 m, got {span!r}")
    if seabed and height < 0.0:
        raise ValueError(
            f"height (fairlead above anchor) must be >= 0 m when seabed=True "
            f"(the seabed passes through the anchor), got {height!r}"
        )
    if friction < 0.0:
        raise ValueError(f"friction (seabed friction coefficient) must be >= 0, got {friction!r}")
    if not 0.0 < tol < 1e-2:
        raise ValueError(f"tol (relative tolerance) must be in (0, 0.01), got {tol!r}")


def _initial_guesses(span, height, length, weight, EA) -> list[tuple[float, float]]:
    """Start values (H [N], V_B [N]) for the Newton iteration.

    1. Peyrot-Goulois (1979), as in FAST v7 / MoorPy:
       lambda_0 = 0.2 if L <= chord, else sqrt(3 ((L^2 - h^2) / x^2 - 1));
       H_0 = |w x / (2 lambda_0)|, V_0 = w/2 (h / tanh(lambda_0) + L).
    2. Elastic taut line: straight chord stretched by T = EA (chord / L - 1), useful when the
       line is shorter than the chord and EA is large (H can be many orders above guess 1).
    """
    chord = math.hypot(span, height)
    if length <= chord:
        shape_parameter = 0.2
    else:
        shape_parameter = math.sqrt(3.0 * ((length ** 2 - height ** 2) / span ** 2 - 1.0))
    guesses = []
    H_guess = max(abs(0.5 * weight * span / shape_parameter), 1e-6 * weight * length)
    V_guess = 0.5 * weight * (height / math.tanh(shape_parameter) + length)
    guesses.append((H_guess, V_guess))
    # Elastic taut-line guess: axial tension of the stretched chord plus half the weight.
    taut_tension = EA * max(chord / length - 1.0, 0.0)
    if taut_tension > 0.0:
        guesses.append((taut_tension * span / chord, taut_tension * height / chord + 0.5 * weight * length))
    return guesses


def _newton(equations: _ClosureEquations, start, scale, tol, max_iterations=200):
    """Damped Newton iteration on the closure equations.

    Returns (H, V_B, residual norm [m], converged flag).  ``scale`` [m] turns the relative
    tolerance into distances.  Steps are limited so that H stays > 0 (and V_B > 0 on the
    grounded branch, where L_s = V_B / w), and halved until the residual decreases.
    """
    H, V_top = start
    residual, jacobian = equations.evaluate(H, V_top)
    norm = float(np.max(np.abs(residual)))
    # Residual floor set by rounding in the closure sums (terms of order 'scale').
    rounding_floor = 1e3 * _MACHINE_EPSILON * scale
    for _ in range(max_iterations):
        if norm <= tol * scale:
            return H, V_top, norm, True
        try:
            step = np.linalg.solve(jacobian, -residual)
        except np.linalg.LinAlgError:
            break
        if not np.all(np.isfinite(step)):
            break
        step_H, step_V = float(step[0]), float(step[1])
        # Keep H positive: never reduce it by more than a factor 10 in one step.
        factor = 1.0
        if H + step_H < 0.1 * H:
            factor = min(factor, 0.9 * H / -step_H)
        if equations.seabed and equations.height > 0.0 and V_top > 0.0 and V_top + step_V < 0.1 * V_top:
            factor = min(factor, 0.9 * V_top / -step_V)
        improved = False
        for _halving in range(40):
            trial_H = H + factor * step_H
            trial_V = V_top + factor * step_V
            trial_residual, trial_jacobian = equations.evaluate(trial_H, trial_V)
            trial_norm = float(np.max(np.abs(trial_residual)))
            if np.isfinite(trial_norm) and trial_norm < norm:
                improved = True
                break
            factor *= 0.5
        if not improved:
            # No decrease possible: either at the rounding floor (converged) or stuck.
            return H, V_top, norm, norm <= max(tol * scale, rounding_floor)
        relative_change = max(abs(trial_H - H) / trial_H, abs(trial_V - V_top) / max(abs(trial_V), trial_H))
        H, V_top, residual, jacobian, norm = trial_H, trial_V, trial_residual, trial_jacobian, trial_norm
        if relative_change <= 4.0 * _MACHINE_EPSILON and norm <= rounding_floor:
            return H, V_top, norm, True
    return H, V_top, norm, norm <= tol * scale


def _root_fallback(equations: _ClosureEquations, start, scale):
    """Fallback solve with scipy.optimize.root (MINPACK hybrd) in (ln H, V_B / (w L))."""
    force_scale = equations.weight * equations.length

    def residual_function(unknowns):
        H = math.exp(min(unknowns[0], 700.0))
        residual, _ = equations.evaluate(H, unknowns[1] * force_scale)
        return residual / scale

    start_vector = np.array([math.log(start[0]), start[1] / force_scale])
    result = scipy.optimize.root(residual_function, start_vector, method="hybr", options=dict(xtol=1e-14))
    H = math.exp(min(result.x[0], 700.0))
    V_top = float(result.x[1] * force_scale)
    residual, _ = equations.evaluate(H, V_top)
    return H, V_top, float(np.max(np.abs(residual)))


def _solve_vertical(height, length, weight, EA, seabed) -> CatenarySolution:
    """span == 0: vertical line with H = 0 (taut, or hanging in a U without seabed).

    With H = 0 eq. (E2') reduces to ``z = (|V_B| - |V_A|)/w + (V_B^2 - V_A^2)/(2 w EA)``,
    with ``V_A = V_B - w L``.  Three closed-form cases (MoorPy profile type 6):

    * taut, going up from A (V_A >= 0):   h = L + (V_A L + w L^2 / 2) / EA
    * taut, going down from A (V_B <= 0): h = -L + (V_A L + w L^2 / 2) / EA
    * hanging in a U (V_A < 0 < V_B): unstretched length from the lowest point up to B
      L_up = (h + L (1 + w L / (2 EA))) / (2 (1 + w L / (2 EA))), V_B = w L_up.
    """
    hanging_stretched = length + weight * length ** 2 / (2.0 * EA)  # = dz of a line hanging from one end
    if height >= hanging_stretched:
        V_bottom = (height - hanging_stretched) * EA / length
        V_top = V_bottom + weight * length
    elif height <= -hanging_stretched:
        V_top = (height + hanging_stretched) * EA / length
        V_bottom = V_top - weight * length
    else:
        stretch_factor = 1.0 + weight * length / (2.0 * EA)
        length_up = (height + length * stretch_factor) / (2.0 * stretch_factor)
        V_top = weight * length_up
        V_bottom = V_top - weight * length
    if seabed and V_bottom < 0.0:
        # Only rounding can get here (the caller handles lines long enough to reach the
        # seabed): the line just touches the seabed at the anchor.
        V_bottom = 0.0
        V_top = weight * length
    return CatenarySolution(
        horizontal_tension=0.0,
        vertical_tension_top=V_top,
        vertical_tension_anchor=V_bottom,
        anchor_tension=abs(V_bottom),
        top_tension=abs(V_top),
        grounded_length=0.0,
        suspended_length=length,
        span=0.0, height=height, length=length, weight=weight, axial_stiffness=EA,
        friction=0.0, seabed=seabed, regime=REGIME_VERTICAL,
    )


def _solve_on_seabed(span, length, weight, EA, friction) -> CatenarySolution:
    """height == 0 with seabed: the whole line lies on the seabed (MoorPy profile type 0).

    Eq. (E3) with L_b = L and x_b = span, solved for the fairlead tension H:
    no friction: H = EA (span/L - 1); with friction and anchor tension > 0:
    H = EA (span/L - 1) + C_B w L / 2 (valid while H >= C_B w L); otherwise
    H = sqrt(2 EA C_B w (span - L)).  A line longer than the span is slack (H = 0).
    """
    extension = span - length
    if extension <= 0.0:
        H = 0.0
    elif friction <= 0.0:
        H = EA * extension / length
    else:
        H = EA * extension / length + 0.5 * friction * weight * length
        if H < friction * weight * length:
            H = math.sqrt(2.0 * EA * friction * weight * extension)
    anchor_tension = max(H - friction * weight * length, 0.0)
    return CatenarySolution(
        horizontal_tension=H,
        vertical_tension_top=0.0,
        vertical_tension_anchor=0.0,
        anchor_tension=anchor_tension,
        top_tension=H,
        grounded_length=length,
        suspended_length=0.0,
        span=span, height=0.0, length=length, weight=weight, axial_stiffness=EA,
        friction=friction, seabed=True, regime=REGIME_ON_SEABED,
    )


def solve_catenary(span: float, height: float, length: float, weight: float, EA: float,
                   *, seabed: bool = True, friction: float = 0.0,
                   tol: float = 1e-12) -> CatenarySolution:
    """Solve the elastic catenary between the anchor (0, 0) and the fairlead (span, height).

    Parameters
    ----------
    span : horizontal distance from end A (anchor) to end B (fairlead) [m], >= 0.
    height : vertical distance from end A up to end B [m]; >= 0 with ``seabed=True``
        (may be negative without seabed).
    length : unstretched line length [m], > 0.  It may be shorter than the chord: the line
        is then stretched taut.
    weight : submerged weight per unit unstretched length w [N/m], > 0.
    EA : axial stiffness [N], > 0.
    seabed : if True, a rigid horizontal seabed passes through end A (z = 0) and part of the
        line may lie on it; if False the line hangs freely (it may sag below end A).
    friction : axial Coulomb friction coefficient C_B [-] of the grounded part (MoorPy's
        ``CB``); the tension falls by C_B w per unit length toward the anchor, floored at
        zero.  No effect without seabed contact.
    tol : relative tolerance; the closure errors in x and z are driven below
        ``tol * max(length, chord)`` metres (or to the rounding floor if that is larger).

    Returns
    -------
    CatenarySolution

    Raises
    ------
    ValueError : impossible input (the message names the field), or no convergence.
    """
    _check_inputs(span, height, length, weight, EA, seabed, friction, tol)
    span, height, length, weight, EA = map(float, (span, height, length, weight, EA))
    friction = float(friction) if seabed else 0.0

    if seabed and height == 0.0:
        return _solve_on_seabed(span, length, weight, EA, friction)

    if seabed:
        # A line longer than span + hanging length would hang vertically from the fairlead onto
        # the seabed: H = 0 (MoorPy profile type 4); the closure equations have no H > 0 root.
        hanging = hanging_length(weight, EA, height)
        if length >= span + hanging:
            V_top = weight * hanging
            return CatenarySolution(
                horizontal_tension=0.0,
                vertical_tension_top=V_top,
                vertical_tension_anchor=0.0,
                anchor_tension=0.0,
                top_tension=V_top,
                grounded_length=length - hanging,
                suspended_length=hanging,
                span=span, height=height, length=length, weight=weight, axial_stiffness=EA,
                friction=friction, seabed=True, regime=REGIME_SLACK_VERTICAL,
            )

    if span == 0.0:
        return _solve_vertical(height, length, weight, EA, seabed)

    equations = _ClosureEquations(span, height, length, weight, EA, seabed, friction)
    scale = max(length, math.hypot(span, height))
    best = None
    for start in _initial_guesses(span, height, length, weight, EA):
        H, V_top, norm, converged = _newton(equations, start, scale, tol)
        if best is None or norm < best[2]:
            best = (H, V_top, norm)
        if converged:
            break
    else:
        # Bracketing/trust-region fallback from a different start, then polish with Newton.
        for start in [best[:2]] + _initial_guesses(span, height, length, weight, EA):
            H, V_top, norm = _root_fallback(equations, start, scale)
            if np.isfinite(norm) and H > 0.0:
                H, V_top, norm, converged = _newton(equations, (H, V_top), scale, tol)
                if norm < best[2]:
                    best = (H, V_top, norm)
                if converged:
                    break
        else:
            raise ValueError(
                f"catenary did not converge: span={span}, height={height}, length={length}, "
                f"weight={weight}, EA={EA}, seabed={seabed}, friction={friction}; "
                f"best closure error {best[2]:.3e} m with H={best[0]:.6e} N, V_B={best[1]:.6e} N"
            )

    H, V_top = best[0], best[1]
    if equations.is_grounded(V_top):
        suspended = V_top / weight
        grounded = length - suspended
        return CatenarySolution(
            horizontal_tension=H,
            vertical_tension_top=V_top,
            vertical_tension_anchor=0.0,
            anchor_tension=max(H - friction * weight * grounded, 0.0),
            top_tension=math.hypot(H, V_top),
            grounded_length=grounded,
            suspended_length=suspended,
            span=span, height=height, length=length, weight=weight, axial_stiffness=EA,
            friction=friction, seabed=seabed, regime=REGIME_GROUNDED,
        )
    V_bottom = V_top - weight * length
    return CatenarySolution(
        horizontal_tension=H,
        vertical_tension_top=V_top,
        vertical_tension_anchor=V_bottom,
        anchor_tension=math.hypot(H, V_bottom),
        top_tension=math.hypot(H, V_top),
        grounded_length=0.0,
        suspended_length=length,
        span=span, height=height, length=length, weight=weight, axial_stiffness=EA,
        friction=friction, seabed=seabed, regime=REGIME_SUSPENDED,
    )


def natural_catenary(weight: float, height: float, horizontal_tension: float) -> dict:
    """Inextensible catenary touching down tangentially on a flat seabed ``height`` below the top.

    Used for S-lay sagbend checks.  With the catenary parameter ``a = H / w`` [m] and the
    origin at the touchdown point (zero slope there), the shape is
    ``z = a (cosh(x / a) - 1)`` (Irvine 1981, eq. 1.5), so at the top ``z = h``:

        horizontal span     X = a acosh(1 + h / a)
        suspended length    S = a sinh(X / a) = sqrt(h^2 + 2 a h)
        top tension         T = H + w h            (T = H cosh(X/a))
        top vertical force  V = w S
        top angle           atan(V / H) from horizontal
        touchdown curvature kappa = w / H          (= 1/a, the maximum curvature)

    Parameters
    ----------
    weight : submerged weight per unit length w [N/m], > 0.
    height : height of the top above the touchdown point h [m], >= 0.
    horizontal_tension : H [N], > 0.

    Returns
    -------
    dict with keys ``suspended_length`` [m], ``horizontal_span`` [m], ``top_tension`` [N],
    ``top_vertical_tension`` [N], ``top_angle_deg`` [deg from horizontal],
    ``touchdown_curvature`` [1/m], ``catenary_parameter`` [m].
    """
    for name, value in dict(weight=weight, height=height, horizontal_tension=horizontal_tension).items():
        if not isinstance(value, (int, float, np.integer, np.floating)) or isinstance(value, bool) \
                or not math.isfinite(float(value)):
            raise ValueError(f"{name} must be a finite real number, got {value!r}")
    if weight <= 0.0:
        raise ValueError(f"weight (submerged weight per unit length) must be > 0 N/m, got {weight!r}")
    if height < 0.0:
        raise ValueError(f"height (top above touchdown) must be >= 0 m, got {height!r}")
    if horizontal_tension <= 0.0:
        raise ValueError(f"horizontal_tension must be > 0 N, got {horizontal_tension!r}")
    parameter = horizontal_tension / weight
    suspended_length = math.sqrt(height * height + 2.0 * parameter * height)
    horizontal_span = parameter * math.asinh(suspended_length / parameter)  # = a acosh(1 + h/a)
    top_vertical_tension = weight * suspended_length
    return dict(
        suspended_length=suspended_length,
        horizontal_span=horizontal_span,
        top_tension=horizontal_tension + weight * height,
        top_vertical_tension=top_vertical_tension,
        top_angle_deg=math.degrees(math.atan2(top_vertical_tension, horizontal_tension)),
        touchdown_curvature=weight / horizontal_tension,
        catenary_parameter=parameter,
    )
