"""Steady (or slowly varying) current: a horizontal velocity that depends on z and t.

    U(z, t) = f(t) s(z) (cos beta_c, sin beta_c, 0)

with s(z) the speed profile interpolated linearly between the given [z, speed] points
and held constant beyond its ends (above the top point up to the surface, below the
lowest down to the seabed), beta_c the direction the current flows TOWARD, from global x
toward global y (about z), and f(t) an optional time factor interpolated linearly in a
[t, factor] table (held constant beyond its ends; 1 without a table). z is the global
(absolute) height, like every position in a scenario. The profile is not stretched with
the waves: under a wave crest the current is that of the top point.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class CurrentProfile:
    z: np.ndarray            # (m,) m, ascending
    speed: np.ndarray        # (m,) m/s
    direction: float         # rad, direction of flow (toward) from global x about z
    time: np.ndarray         # (p,) s, ascending (empty: factor 1)
    factor: np.ndarray       # (p,) -

    def time_factor(self, t: float) -> float:
        if self.time.size == 0:
            return 1.0
        return float(np.interp(t, self.time, self.factor))

    def velocity(self, t: float, z) -> np.ndarray:
        """(n, 3) m/s current velocity at heights z (numpy)."""
        z = np.atleast_1d(np.asarray(z, dtype=float))
        s = np.interp(z, self.z, self.speed) * self.time_factor(t)
        return np.stack([s * math.cos(self.direction), s * math.sin(self.direction), 0.0 * s], axis=-1)


def no_current() -> CurrentProfile:
    e = np.zeros(0)
    return CurrentProfile(e, e, 0.0, e, e)


def current_profile(current) -> CurrentProfile:
    """The profile of a scenario's ``environment.water.current`` (schema object, or None)."""
    if current is None:
        return no_current()
    rows = np.asarray(current.profile, dtype=float).reshape(-1, 2)
    order = np.argsort(rows[:, 0], kind="stable")
    rows = rows[order]
    if current.time_factor:
        table = np.asarray(current.time_factor, dtype=float).reshape(-1, 2)
        time, factor = table[:, 0].copy(), table[:, 1].copy()
    else:
        time = factor = np.zeros(0)
    return CurrentProfile(z=rows[:, 0].copy(), speed=rows[:, 1].copy(),
                          direction=math.radians(current.direction_deg), time=time, factor=factor)
