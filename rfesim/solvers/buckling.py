"""Euler buckling check of a static equilibrium (called by rfesim.api after statics).

Statics finds equilibria, stable or not. A line with both ends placed and no gravity starts
straight, each element shortened to span the chord, and that straight column is already in
equilibrium (0 Newton iterations), however far it is compressed: the 600 m riser of
scenarios/catenary_riser.json without gravity sits at 180 MN of compression between ends
566 m apart, where its Euler load is 1.04 kN. The check finds such equilibria and says so.

A *free compressed stretch* is a run of consecutive SDEs of one line whose axial force
(the x component of eq. 8.86, the effective tension: buoyancy is a distributed load) is
compressive beyond the noise floor, with no supported RFE inside it. An RFE is supported
when the seabed pushes on it, a roller (or stinger, straightener) carries it, or a
tensioner or reel grips it; an SDE between two supported RFEs lies along its support and
belongs to no stretch. Tension-only SDEs (ropes) carry no compression and are skipped.
A stretch of length L (the sum of its SDE lengths) is compared with the Euler load

    N_E = pi^2 EI_min / L^2

of a pinned-pinned column (EI_min: the smaller bending stiffness of the section, eq. 8.88
with c = EI / Delta). Pins are the conservative choice for a stretch between supports or
tensioned neighbours, which hold its ends at least as well as pins (clamps: 4 N_E); a
stretch that ends at a free end of a line (a cantilever, N_E / 4) is not treated apart,
and a stretch is not followed across a join into the next line. The largest compression of
the stretch is compared (conservative where it varies along it). Compression below
``NOISE_FRACTION`` of the line's own force scale (its largest element weight or point load,
else its largest internal force: a heavy load elsewhere in the scene does not hide it), or
below ``NOISE_ROUNDOFF`` times the force resolution of the model, is numerical noise and
never warns.

Only a *straight* stretch is reported as unstable: one whose RFE centres lie within
``STRAIGHT`` of its length from the chord through its end centres. A pinned column past
its Euler load is unstable straight, but stable bent (the elastica, whose compression stays
a few per cent above N_E for deflections of a fifth of its length): a slack line that
statics has bent sideways under compression, such as a neutrally buoyant tether, is a
stable equilibrium and does not warn.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..model.compile import State
from .system import System

NOISE_FRACTION = 1e-3   # compression below this fraction of the force scale is noise
NOISE_ROUNDOFF = 1e3    # ... or below this multiple of the force resolution (System.roundoff_force)
STRAIGHT = 1e-2         # a stretch whose centres lie within this fraction of its length from its chord is straight


@dataclass(frozen=True)
class CompressedStretch:
    line: str
    start: float          # m, arc length from end A where the stretch begins
    length: float         # m, sum of its SDE lengths
    compression: float    # N, largest compressive axial force in it (positive)
    euler_load: float     # N, pi^2 EI_min / length^2 (pinned-pinned)
    bending_stiffness: float  # N*m^2, EI_min of the section
    deviation: float = 0.0    # m, largest distance of its RFE centres from the chord of its end centres

    @property
    def buckles(self) -> bool:
        """Straight and compressed beyond the Euler load: an unstable equilibrium."""
        return self.compression > self.euler_load and self.deviation <= STRAIGHT * self.length


def supported_rfes(system: System, state: State) -> np.ndarray:
    """(n,) bool: RFEs held along the line at the state (seabed contact, a roller in contact
    with the RFE or its neighbours, a tensioner's or a reel's grip). Evaluates the state."""
    km, ws = system.km, system.ws
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    n = km.rfe_mass.shape[0]
    held = ws.contact_force[:n] > 0.0
    if km.has_rollers:
        for j in range(km.roller_attach.shape[0]):
            i = int(ws.roller_hint[j])
            if ws.roller_normal[j] > 0.0 and i >= 0:
                lo, hi = max(i - 1, int(km.roller_lo[j])), min(i + 2, int(km.roller_hi[j]))
                held[lo:hi] = True
    if km.has_tensioners:
        held |= ws.grip_on[:n] == 1
    if km.has_reels:
        held |= ws.reel_grip_on[:n] == 1
    return held


def compressed_stretches(system: System, state: State) -> list[CompressedStretch]:
    """The free compressed stretches of every line at the state (module docstring), whether
    they buckle or not."""
    km, ws = system.km, system.ws
    held = supported_rfes(system, state)         # evaluates the state: ws.sigma is its SDE forces
    compression = -ws.sigma[:, 0]
    centres = ws.r[:km.rfe_mass.shape[0]].copy()
    roundoff = NOISE_ROUNDOFF * system.roundoff_force(state)
    out: list[CompressedStretch] = []
    for li in system.model.lines:
        EI = li.section.EI_min
        floor = max(NOISE_FRACTION * _line_force_scale(km, ws, li), roundoff)

        def close(run):
            if run:
                length = float(km.sde_length[run].sum())
                rfes = [int(km.sde_left[s]) for s in run] + [int(km.sde_right[run[-1]])]
                out.append(CompressedStretch(line=li.name, start=(run[0] - li.sde_start) * li.dx, length=length,
                                             compression=float(compression[run].max()),
                                             euler_load=math.pi ** 2 * EI / length ** 2, bending_stiffness=EI,
                                             deviation=_deviation(centres[rfes])))
            return []

        run: list[int] = []
        for s in range(li.sde_start, li.sde_stop):
            left, right = int(km.sde_left[s]), int(km.sde_right[s])
            if km.sde_tension_only[s] == 1 or compression[s] <= floor or (held[left] and held[right]):
                run = close(run)
                continue
            if held[left]:
                run = close(run)          # a support inside the run ends one stretch, begins the next
            run.append(s)
        close(run)
    return out


def _line_force_scale(km, ws, li) -> float:
    """A typical force of one line (N): its largest element weight or point load, else its
    largest internal force (as System.force_scale for the scene)."""
    lo, hi = li.rfe_start, li.rfe_stop
    cand = [0.0]
    if km.gravity > 0:
        cand.append(float(km.rfe_mass[lo:hi].max()) * km.gravity)
    if km.load_force.size:
        on = (km.load_rfe >= lo) & (km.load_rfe < hi)
        if on.any():
            cand.append(float(np.abs(km.load_force[on]).max()))
            cand.append(float(np.abs(km.load_moment[on]).max()) / max(float(km.rfe_length[lo:hi].min()), 1e-12))
    ref = max(cand)
    if ref == 0.0 and li.sde_stop > li.sde_start:
        ref = float(np.abs(ws.sigma[li.sde_start:li.sde_stop, :3]).max())
    return ref


def _deviation(points: np.ndarray) -> float:
    """Largest distance (m) of the points from the straight line through the first and last."""
    chord = points[-1] - points[0]
    d = points - points[0]
    size = float(np.linalg.norm(chord))
    if size == 0.0:
        return float(np.linalg.norm(d, axis=1).max())
    return float(np.linalg.norm(np.cross(d, chord / size), axis=1).max())


def buckling_warnings(system: System, state: State) -> list[str]:
    """One message per free compressed stretch beyond its Euler load: the line, where and how
    long the stretch is, its compression and Euler load, and what to do."""
    messages = []
    for c in compressed_stretches(system, state):
        if not c.buckles:
            continue
        messages.append(
            f"line '{c.line}' carries {c.compression / 1e3:.4g} kN of compression over a free stretch of "
            f"{c.length:.4g} m (arc length {c.start:.4g} to {c.start + c.length:.4g} m), above its Euler load "
            f"pi^2 EI / L^2 = {c.euler_load / 1e3:.4g} kN (pinned ends, EI = {c.bending_stiffness:.4g} N m^2): "
            f"this static equilibrium is unstable (buckling) and a dynamic run will leave it; give the line "
            f"tension (gravity, a shorter line or ends further apart, an end load) or support along the "
            f"stretch, or check the start shape (analysis.statics.start)")
    return messages
