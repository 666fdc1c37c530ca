"""Euler buckling check of a static equilibrium (called by rfesim.api after statics).

Statics finds equilibria, stable or not. A line with both ends placed and no gravity starts
straight, each element shortened to span the chord, and that straight column is already in
equilibrium (0 Newton iterations), however far it is compressed: the 600 m riser of
scenarios/catenary_riser.json without gravity sits at 180 MN of compression between ends
566 m apart, where its Euler load is 1.04 kN. The check finds such equilibria and says so.

A *free compressed stretch* is a run of consecutive SDEs of one line, or of lines joined end
to end, whose axial force (the x component of eq. 8.86, the effective tension: buoyancy is a
distributed load) is compressive beyond the noise floor, with no supported RFE inside it. An
RFE is supported when the seabed pushes on it, a roller (or stinger, straightener) carries
it, or a tensioner or reel grips it; an SDE between two supported RFEs lies along its support
and belongs to no stretch. Tension-only SDEs (ropes) carry no compression and are skipped.

*Joins.* A stretch goes on across a join (rfesim.model.joins: end A of a child on end B of
its parent, or a closing join of two ends B) into the next line: every join transmits the
axial force (clamped, hinged and pinned alike), and a column built of four lines joined end
to end, each short enough to pass alone, is one column of their summed length. The joint SDE
counts as any SDE of the run (its compression, its two RFEs supported or not) but has no
length: it joins the two end points of the lines. A join is crossed only where the two lines
continue each other: their outward end tangents opposite within ``KINK`` (4 ``STRAIGHT``: a
kink theta at a join moves the middle of the stretch by up to theta L / 4 off its chord, so
a stretch bent more than that at a join would not count as straight anyway). A join bent
more (a boom on its pedestal, A-frame legs on their deck stubs) is a corner of a frame, not a
column going on: the walk ends there and each line is checked alone, as where more than one
straight join meets at a line end. EI_min is the smallest of the joined lines' sections
(conservative where they differ). A clamped join is as stiff as its lines (100 times one of
their elements); a pinned or hinged join in the middle of a stretch is a hinge, which lowers
the load further (a pinned-ended column with a hinge inside is a mechanism): the check does
not go that far and treats the joined stretch as one continuous column, which is still
lower than the pieces' loads it replaces.

*End conditions.* A stretch of length L (the sum of its SDE lengths) is compared with the
Euler load

    N_E = pi^2 EI_min / L_eff^2

with L_eff = L, pinned-pinned (EI_min: the smaller bending stiffness of the section, eq. 8.88
with c = EI / Delta). Pins are the conservative choice for a stretch between supports or
tensioned neighbours, which hold its ends at least as well as pins (clamps: 4 N_E). A
stretch one of whose ends is a *free line end* is a cantilever, L_eff = 2 L (N_E / 4): the
line end is attached to nothing (no fixed point, vessel, body or join), no tugger line,
reeving lead or follower load (a follower-loaded cantilever is Beck's column, not Euler's)
acts on its RFE, and no RFE from the stretch out to that end is supported. 2 L is exact for
a clamped other end; a rotationally softer one (the line going on over a support or into a
tensioned part, a corner join) lowers the load further and a pinned one makes it a
mechanism, not told apart. Its compression grows from its free end to its held end, each
rise a load P_j at its height a_j above the held end, which alone buckles it at
pi^2 EI / (2 a_j)^2 (the part above the load is unloaded and stays straight): the cantilever
buckles when sum_j P_j / (pi^2 EI / (2 a_j)^2) reaches 1 (Dunkerley's sum, a lower bound,
exact for one load anywhere, 5.6 % low for a uniform weight against Greenhill's
q L^3 = 7.837 EI: ``cantilever_load``). A steel pipe standing clamped in air under its own
weight buckles at 63 m (12-inch X65, EI = 3.79e7 N m^2, 1185 N/m); the tip-load rule alone
would warn from 43 m. A stretch with two free ends (a
free-free column compressed by loads along it) keeps the pinned L_eff = L: Euler's end
conditions do not describe it.

The largest compression of a pinned stretch is compared (conservative where it varies along it).
Compression below ``NOISE_FRACTION`` of the line's own force scale (its largest element
weight or point load, else its largest internal force: a heavy load elsewhere in the scene
does not hide it; a joint SDE takes the smaller floor of its two lines), or below
``NOISE_ROUNDOFF`` times the force resolution of the model, is numerical noise and never
warns.

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
from typing import NamedTuple

import numpy as np

from ..model.compile import State
from .system import System

NOISE_FRACTION = 1e-3   # compression below this fraction of the force scale is noise
NOISE_ROUNDOFF = 1e3    # ... or below this multiple of the force resolution (System.roundoff_force)
STRAIGHT = 1e-2         # a stretch whose centres lie within this fraction of its length from its chord is straight
KINK = 4.0 * STRAIGHT   # rad: two joined lines whose ends turn by more than this are a corner, not one column
FOLD = 0.5 * math.pi    # rad: an SDE of a line bent more than this is folded back (fold_warnings)


@dataclass(frozen=True)
class CompressedStretch:
    line: str             # the (first) line of the stretch
    start: float          # m, arc length from end A of ``line`` where the stretch begins (on one line: its end
                          #   nearer end A)
    length: float         # m, sum of its SDE lengths (the joints between lines have none)
    compression: float    # N, largest compressive axial force in it (positive)
    euler_load: float     # N, pi^2 EI_min / effective_length^2
    bending_stiffness: float  # N*m^2, EI_min: the smallest bending stiffness of the sections along it
    deviation: float = 0.0    # m, largest distance of its RFE centres from the chord of its end centres
    lines: tuple[str, ...] = ()     # the lines it runs over, in order across their joins (default: (line,))
    stop: float = math.nan          # m, arc length from end A of the last line where it ends (default start + length)
    free_ends: int = 0              # how many of its two ends are free line ends (nothing attached, nothing holds them)
    effective_length: float = math.nan  # m, pi sqrt(EI_min / euler_load): the length (pinned ends), twice it (a
                                        #   cantilever with its load at the free end), 1.12 times it (its own weight)
    free_end_compression: float = 0.0   # N, a cantilever's compression at its free end (its tip load)

    def __post_init__(self):
        if not self.lines:
            object.__setattr__(self, "lines", (self.line,))
        if math.isnan(self.stop):
            object.__setattr__(self, "stop", self.start + self.length)
        if math.isnan(self.effective_length):
            object.__setattr__(self, "effective_length", self.length)

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


class _Step(NamedTuple):
    """One SDE of a walk along joined lines, oriented along the walk."""
    sde: int
    left: int             # RFE behind it
    right: int            # RFE ahead of it
    length: float         # m (0 for the joint between two lines)
    line: int             # index of its line in model.lines (a joint: the line ahead)
    arc_left: float       # m, arc length of its left end on its line (a joint: NaN)
    arc_right: float
    floor: float          # N, compression at or below this is noise
    joint: bool


def _walks(system: System, floors: list[float]) -> list[tuple[list[_Step], tuple, tuple]]:
    """Every line once, in walks that go on across the joins that continue a line straight:
    (steps, first line end, last line end), a line end being (line index, "a" | "b"). A join
    (end A of a child on end B of its parent, or a closing join of two ends B) is crossed when
    it transmits force (every join does: clamped, hinged or pinned; none is a rope) and the
    two lines continue each other there: their outward end tangents are opposite within KINK
    rad. A join bent more than that (a boom on its pedestal, a leg on its stub) is a corner,
    not a column going on; there, and where more than one straight join meets a line end,
    the walk ends. Uses the orientations of the last evaluation (system.ws)."""
    model, km, ws = system.model, system.km, system.ws
    lines = model.lines
    index = {li.name: k for k, li in enumerate(lines)}

    def end_rfe(end) -> int:
        k, side = end
        return lines[k].rfe_start if side == "a" else lines[k].rfe_stop - 1

    def outward(end) -> np.ndarray:
        x = ws.R[end_rfe(end)][:, 0]
        return x if end[1] == "b" else -x

    straight: dict[tuple, list] = {}
    for info, sides in [(j, ("b", "a")) for j in model.joins] + [(c, ("b", "b")) for c in model.closures]:
        if info.parent not in index or info.child not in index or km.sde_tension_only[info.sde] == 1:
            continue
        p, c = (index[info.parent], sides[0]), (index[info.child], sides[1])
        if float(outward(p) @ outward(c)) <= -math.cos(KINK):
            straight.setdefault(p, []).append((c, info.sde))
            straight.setdefault(c, []).append((p, info.sde))
    partner = {end: links[0] for end, links in straight.items()
               if len(links) == 1 and len(straight[links[0][0]]) == 1}

    def steps_of(k: int, forward: bool) -> list[_Step]:
        li = lines[k]
        out = []
        order = range(li.sde_start, li.sde_stop) if forward else range(li.sde_stop - 1, li.sde_start - 1, -1)
        for s in order:
            j = s - li.sde_start
            a, b = j * li.dx, (j + 1) * li.dx
            left, right = int(km.sde_left[s]), int(km.sde_right[s])
            if not forward:
                left, right, a, b = right, left, b, a
            out.append(_Step(s, left, right, float(km.sde_length[s]), k, a, b, floors[k], False))
        return out

    visited = [False] * len(lines)
    walks = []

    def walk_from(end):
        steps, first = [], end
        while True:
            k = end[0]
            visited[k] = True
            steps.extend(steps_of(k, end[1] == "a"))
            out = (k, "b" if end[1] == "a" else "a")
            nxt = partner.get(out)
            if nxt is None or visited[nxt[0][0]]:
                return steps, first, out          # a free, held or attached end, a corner; or a loop closed
            end, s = nxt
            steps.append(_Step(s, end_rfe(out), end_rfe(end), 0.0, end[0], math.nan, math.nan,
                               min(floors[k], floors[end[0]]), True))

    for k in range(len(lines)):
        if visited[k]:
            continue
        start = next((e for e in ((k, "a"), (k, "b")) if e not in partner), (k, "a"))
        walks.append(walk_from(start))
    return walks


def _free_line_ends(system: System) -> set:
    """Line ends (line index, "a" | "b") that nothing holds: attached to nothing (no fixed
    point, vessel, body or join), no tugger or reeving lead on their RFE, no follower load
    on it (a follower-loaded cantilever is not Euler's column)."""
    model, km = system.model, system.km
    index = {li.name: k for k, li in enumerate(model.lines)}
    joined = set()
    for j in model.joins:
        joined |= {(index.get(j.parent), "b"), (index.get(j.child), "a")}
    for c in model.closures:
        joined |= {(index.get(c.parent), "b"), (index.get(c.child), "b")}
    restrained = set(int(i) for i in km.tug_rfe)
    restrained |= set(int(i) for i, kind in zip(km.rv_rfe, km.rv_kind) if kind == 1)
    restrained |= set(int(i) for i, local in zip(km.load_rfe, km.load_local) if local == 1)
    out = set()
    for k, li in enumerate(model.lines):
        for side, end, rfe in (("a", li.end_a, li.rfe_start), ("b", li.end_b, li.rfe_stop - 1)):
            if getattr(end, "attach", None) == "free" and (k, side) not in joined and rfe not in restrained:
                out.add((k, side))
    return out


def compressed_stretches(system: System, state: State) -> list[CompressedStretch]:
    """The free compressed stretches of every line at the state (module docstring), whether
    they buckle or not, followed across the straight joins between lines."""
    km, ws = system.km, system.ws
    held = supported_rfes(system, state)         # evaluates the state: ws.sigma is its SDE forces
    compression = -ws.sigma[:, 0]
    for c in system.model.closures:
        # a closing join's frame is the closing line's (rest rotation R_target^T R_closing, a
        # half turn for two ends B meeting head on), whose x points back into the target:
        # its axial force is compressive when positive
        compression[c.sde] = ws.sigma[c.sde, 0]
    centres = ws.r[:km.rfe_mass.shape[0]].copy()
    roundoff = NOISE_ROUNDOFF * system.roundoff_force(state)
    lines = system.model.lines
    floors = [max(NOISE_FRACTION * _line_force_scale(km, ws, li), roundoff) for li in lines]
    free = _free_line_ends(system)
    out: list[CompressedStretch] = []
    for steps, first_end, last_end in _walks(system, floors):

        def loose(rfes, end) -> bool:
            """The walk's end ``end`` is a free line end and nothing holds the RFEs from the
            stretch's end out to it."""
            return end in free and not any(held[i] for i in rfes)

        def close(lo: int, hi: int) -> None:
            """The stretch of steps[lo:hi] (joints at its ends, of no length, left out)."""
            while lo < hi and steps[lo].joint:
                lo += 1
            while hi > lo and steps[hi - 1].joint:
                hi -= 1
            if lo >= hi:
                return
            run = steps[lo:hi]
            sdes = [st.sde for st in run]
            length = float(sum(st.length for st in run))
            names = []
            for st in run:
                if not st.joint and lines[st.line].name not in names:
                    names.append(lines[st.line].name)
            EI = min(system.model.line(n).section.EI_min for n in names)
            before = [steps[lo].left] + [i for st in steps[:lo] for i in (st.left, st.right)]
            after = [steps[hi - 1].right] + [i for st in steps[hi:] for i in (st.left, st.right)]
            free_a, free_b = loose(before, first_end), loose(after, last_end)
            free_ends = int(free_a) + int(free_b)
            peak = float(compression[sdes].max())
            load, tip = math.pi ** 2 * EI / length ** 2, 0.0
            if free_ends == 1:
                outward = run if free_a else run[::-1]          # from the free end to the held end
                profile = [float(compression[st.sde]) for st in outward]
                tip = max(profile[0], 0.0)
                load = cantilever_load(EI, [st.length for st in outward], profile)
            a, b = run[0].arc_left, run[-1].arc_right
            if len(names) == 1:
                a, b = min(a, b), max(a, b)
            rfes = [st.left for st in run] + [run[-1].right]
            out.append(CompressedStretch(line=names[0], start=a, length=length, compression=peak,
                                         euler_load=load, bending_stiffness=EI,
                                         deviation=_deviation(centres[rfes]), lines=tuple(names), stop=b,
                                         free_ends=free_ends, effective_length=math.pi * math.sqrt(EI / load),
                                         free_end_compression=tip))

        lo = None
        for i, st in enumerate(steps):
            if km.sde_tension_only[st.sde] == 1 or compression[st.sde] <= st.floor or (held[st.left]
                                                                                       and held[st.right]):
                if lo is not None:
                    close(lo, i)
                lo = None
                continue
            if held[st.left] and lo is not None:
                close(lo, i)              # a support inside the run ends one stretch, begins the next
                lo = None
            if lo is None:
                lo = i
        if lo is not None:
            close(lo, len(steps))
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


def shear_warnings(system: System, state: State) -> list[str]:
    """One message per line in the fem shear stiffness (eq. 8.89) whose tension at the state
    exceeds what that shear holds in line, 12 EI / Delta^2 (rfesim.model.compile.shear_limit;
    docs/theory.md, section 6): its elements shear apart sideways, and an equilibrium statics
    found there is spurious (a 100 m line of EI = 1e4 N m^2 on 20 elements hangs 18 m too deep
    at half its tension). By default a line whose expected tension shows it before statics
    takes the kruszewski shear (rfesim.model.compile._tension_estimate); a line given
    ``shear_stiffness: fem``, or pulled harder than expected, keeps fem and is warned."""
    from ..model.compile import shear_limit
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    out = []
    for li in system.model.lines:
        if li.shear_model != "fem" or li.sde_stop <= li.sde_start:
            continue
        limit = shear_limit(li.section, li.dx)
        tension = float(system.ws.sigma[li.sde_start:li.sde_stop, 0].max())
        if tension > limit:
            out.append(f"line '{li.name}' carries {tension / 1e3:.4g} kN of tension, above the "
                       f"{limit / 1e3:.4g} kN that its fem shear stiffness 12 EI / Delta^3 (eq. 8.89) holds in line "
                       f"(12 EI / Delta^2 at Delta = {li.dx:.4g} m): its elements shear apart sideways and this "
                       f"equilibrium is spurious; set lines.{li.name}.shear_stiffness to kruszewski (eq. 8.88), or "
                       f"give many more elements (Delta well below sqrt(12 EI / T), with T the line's true tension, "
                       f"which this equilibrium understates)")
    return out


def fold_warnings(system: System, state: State) -> list[str]:
    """One message per line that statics left folded back on itself: an SDE of the line (not
    a joint between lines) bent by more than ``FOLD`` (its two RFEs turned more than a right
    angle against each other, eq. 8.75). No line of any stiffness takes that shape over one
    element in a static equilibrium; it is slack bunched up where the start shape put more
    line than the path holds (elements overlapping, some in compression), and its tensions
    are not the line's: 300 m of chain sagging onto the seabed from two ends, started from
    the free catenary clipped to the seabed, converged folded at 173 deg in two places with
    four times the horizontal tension of its U (docs/theory.md, section 6, 'A U onto the
    seabed')."""
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    eps = system.ws.eps
    out = []
    for li in system.model.lines:
        if li.sde_stop <= li.sde_start:
            continue
        bend = np.hypot(eps[li.sde_start:li.sde_stop, 4], eps[li.sde_start:li.sde_stop, 5])
        folds = np.nonzero(bend > FOLD)[0]
        if folds.size == 0:
            continue
        arcs = li.sde_arc_length[folds]
        k = int(np.argmax(bend[folds]))
        where = (f"at arc length {arcs[0]:.4g} m" if folds.size == 1 else
                 f"at {folds.size} SDEs between arc length {arcs.min():.4g} and {arcs.max():.4g} m")
        out.append(f"line '{li.name}' lies folded back on itself {where} (its elements meet at up to "
                   f"{math.degrees(float(bend[folds][k])):.4g} deg, at arc length {arcs[k]:.4g} m): this equilibrium "
                   f"has slack bunched up, and its tensions are not the line's; check that the line is not longer "
                   f"than its path can hold (on the seabed: than can hang down onto it and lie straight), or "
                   f"start statics from another shape (analysis.statics.start)")
    return out


def _rope_lines(system: System, state: State):
    """(line, rows of its tension-only SDEs) for each line with any, after evaluating the
    state at rest (the workspace then holds its eps and sigma)."""
    km = system.km
    if not km.has_tension_only:
        return []
    st = state.copy()
    st.qd[:] = 0.0
    system.evaluate(st)
    out = []
    for li in system.model.lines:
        rows = np.arange(li.sde_start, li.sde_stop)
        rows = rows[km.sde_tension_only[rows] == 1]
        if rows.size:
            out.append((li, rows))
    return out


def _longer_than_chord(li, chord: float, sc) -> str:
    """'; it is .. m longer than the distance between its ends (..): give <field> nearer that'
    for a line longer than ``chord`` (the length field as the user wrote it), else ''."""
    if li.length <= chord * 1.001:
        return ""
    field = f"lines.{li.name}.length"
    if sc is not None:
        from ..scenario.pipelay import user_field
        field = user_field(sc, field)
    return (f"; it is {li.length - chord:.4g} m longer than the distance between its ends ({chord:.4g} m): "
            f"give {field} nearer that")


def _in_contact(compression: float, where: str, weight: float) -> str:
    return (f"in axial contact (overlapping by half their length or more) with {compression / 1e3:.4g} kN of "
            f"compression{where}, more than the rope's weight ({weight / 1e3:.4g} kN)")


def through_rope_warnings(system: System, state: State, sc=None) -> list[str]:
    """One message per rope (tension-only SDEs) that statics left with elements pushed through
    one another: the axial gap of an SDE (eps_x, eq. 8.85) below -ROPE_THROUGH times its arms'
    sum, the state the dynamics stop on (rfesim.solvers.kernels.check_ropes). Before the
    rope's axial contact (rfesim.loads.tension_only) a slack rope SDE carried no force, so
    Newton could leave one inverted at the bottom of a slack bight: a column crane's 35.35 m
    rope from a 21 m boom's tip to a payload on a deck 4.7 m aside converged with two 1.18 m
    elements overlapping by 1.66 m at arc length 31.2 m, and its dynamics stopped in their
    first substep, blaming a whipping drive. Now a guard. ``sc`` (the scenario) names the
    length field as the user wrote it."""
    from ..loads.tension_only import arm_sums
    from .kernels import ROPE_THROUGH
    km, ws = system.km, system.ws
    out = []
    for li, rows in _rope_lines(system, state):
        bad = rows[ws.eps[rows, 0] < -ROPE_THROUGH * arm_sums(km.sde_arm_left, km.sde_arm_right, rows)]
        if bad.size == 0:
            continue
        k = int(bad[np.argmin(ws.eps[bad, 0])])
        a = ws.r[li.rfe_start] - 0.5 * li.dx * ws.R[li.rfe_start, :, 0]
        b = ws.r[li.rfe_stop - 1] + 0.5 * li.dx * ws.R[li.rfe_stop - 1, :, 0]
        slack = _longer_than_chord(li, float(np.linalg.norm(b - a)), sc)
        out.append(f"rope '{li.name}' lies with elements pushed through one another at arc length "
                   f"{li.sde_arc_length[k - li.sde_start]:.4g} m (overlapping by {-float(ws.eps[k, 0]):.4g} m, its "
                   f"elements being {li.dx:.4g} m long"
                   f"{f', and {bad.size - 1} more SDEs' if bad.size > 1 else ''}): its slack part is folded inside "
                   f"an element, no shape of the rope, and a dynamic run from here stops at once{slack}, or "
                   f"set analysis.statics.enabled to false")
    return out


def crammed_rope_warnings(system: System, state: State, sc=None) -> list[str]:
    """One message per rope (tension-only SDEs) that statics left compressed on its axial
    contact (rfesim.loads.tension_only) harder than its own weight: its elements crammed
    together in a straight column, which a rope does not carry (it buckles sideways), so the
    equilibrium is unstable and its end forces are no rope's. A slack bight resting on the
    contact carries a fraction of its weight (the lift-off with a 21 m boom: under 20 N on a
    1.8 kN rope); a weightless 20 m rope between points 5 m apart, started straight, converged
    with 21.4 MN of compression in every element and at both ends. ``sc`` (the scenario)
    names the length field as the user wrote it (the distance is the one between the line's
    ends at the start: the end elements are crammed past them)."""
    km, ws = system.km, system.ws
    out = []
    lines = _rope_lines(system, state)
    floor = system.roundoff_force(state) if lines else 0.0
    for li, rows in lines:
        weight = abs(km.gravity) * float(km.rfe_mass[li.rfe_start:li.rfe_stop].sum())
        k = int(rows[np.argmin(ws.sigma[rows, 0])])
        compression = -float(ws.sigma[k, 0])
        if compression <= weight + floor:
            continue
        many = int(np.count_nonzero(ws.sigma[rows, 0] < -(weight + floor)))
        slack = _longer_than_chord(li, li.chord, sc) if li.chord is not None else ""
        where = f" at arc length {li.sde_arc_length[k - li.sde_start]:.4g} m"
        out.append(f"rope '{li.name}' is crammed into itself: {many} of its {rows.size} SDEs hold their elements "
                   f"{_in_contact(compression, where, weight)}; a rope buckles sideways instead, so this "
                   f"equilibrium is unstable and its end forces are no rope's{slack}, or set "
                   f"analysis.statics.enabled to false")
    return out


def dynamic_crammed_warnings(model, results) -> list[str]:
    """One message per rope (tension-only SDEs) whose elements, at any output time of a run,
    were pushed into their axial contact (rfesim.loads.tension_only) harder than the rope's
    own weight (``crammed_rope_warnings`` after statics, for the dynamics): a rope driven into
    itself faster than it can fold. A bight bunching as it settles stays far below (the
    lift-off luffed to 38.5 deg: 91 N on a 1.8 kN rope); a 1 kg payload whipped into its 2 m
    rope by a near-rigid crane reached 35 kN: the motion there is no rope's."""
    out = []
    km = model.km
    if not km.has_tension_only:
        return out
    g = abs(km.gravity)
    for li in model.lines:
        if li.sde_stop <= li.sde_start or km.sde_tension_only[li.sde_start] != 1 or li.name not in results.lines:
            continue
        tension = np.asarray(results.line(li.name).tension)
        if tension.size == 0:
            continue
        weight = g * float(km.rfe_mass[li.rfe_start:li.rfe_stop].sum())
        k = int(np.argmin(tension.min(axis=1)))
        j = int(np.argmin(tension[k]))
        compression = -float(tension[k, j])
        if compression > max(weight, 1e-9):
            arc = np.asarray(results.line(li.name).sde_arc_length)
            where = f" at arc length {float(arc[j]):.4g} m" if arc.size == tension.shape[1] else ""
            out.append(f"rope '{li.name}' was driven into itself: at t = {results.time[k]:.6g} s its elements met "
                       f"{_in_contact(compression, where, weight)}; a rope folds instead, so the motion there is "
                       f"no rope's: damp the rope, lower analysis.dynamics.integrator.rho_inf, shorten the time "
                       f"step or slow the drive that whips it")
    return out


def dynamic_shear_warnings(model, results) -> list[str]:
    """One message per line in the fem shear stiffness whose tension, at any output time of a
    run, exceeds the limit 12 EI / Delta^2 that shear holds in line (``shear_warnings`` after
    statics, for the peaks of the dynamics: a snap load): the run from then on may be spurious."""
    from ..model.compile import shear_limit
    out = []
    for li in model.lines:
        if li.shear_model != "fem" or li.name not in results.lines:
            continue
        tension = np.asarray(results.line(li.name).tension)
        if tension.size == 0:
            continue
        k = int(np.argmax(tension.max(axis=1)))
        peak, limit = float(tension[k].max()), shear_limit(li.section, li.dx)
        if peak > limit:
            out.append(f"line '{li.name}' reaches {peak / 1e3:.4g} kN of tension at t = {results.time[k]:.6g} s, above "
                       f"the {limit / 1e3:.4g} kN that its fem shear stiffness 12 EI / Delta^3 (eq. 8.89) holds in "
                       f"line (12 EI / Delta^2 at Delta = {li.dx:.4g} m): from then on its elements may shear apart "
                       f"sideways and the run be spurious; set lines.{li.name}.shear_stiffness to kruszewski "
                       f"(eq. 8.88) or give more elements")
    return out


GREENHILL = 7.837   # (q L^3 / EI) at which a cantilever buckles under its own weight q per length


def cantilever_load(EI: float, lengths, compressions) -> float:
    """The largest compression of a cantilever at which it buckles, its load growing in the
    proportions of ``compressions``: the axial forces of its SDEs (positive compressive) from
    the free end to the held end, ``lengths`` their lengths. Each rise of the compression
    along it is a load P_j at its distance a_j from the held end, which alone buckles it at
    pi^2 EI / (2 a_j)^2 (the part above a load is unloaded and stays straight); together they
    buckle it when sum_j P_j (2 a_j)^2 / (pi^2 EI) reaches 1 (Dunkerley's sum, a lower bound:
    exact for one load anywhere, 5.6 % low for a uniform weight, whose exact limit is
    q L^3 = GREENHILL EI). Falls in compression toward the held end are left out (safe side)."""
    a = float(np.sum(lengths))
    usage, before, peak = 0.0, 0.0, 0.0
    for length, n in zip(lengths, compressions):
        rise = n - before
        if rise > 0.0:
            usage += rise * (2.0 * a) ** 2 / (math.pi ** 2 * EI)
        before, peak, a = n, max(peak, n), a - length
    return peak / usage if usage > 0.0 else math.pi ** 2 * EI / (2.0 * float(np.sum(lengths))) ** 2


def buckling_warnings(system: System, state: State) -> list[str]:
    """One message per free compressed stretch beyond its Euler load: the line (or the joined
    lines), where and how long the stretch is, its compression and Euler load with the end
    condition taken, and what to do."""
    messages = []
    for c in compressed_stretches(system, state):
        if not c.buckles:
            continue
        if len(c.lines) == 1:
            where = (f"line '{c.line}' carries {c.compression / 1e3:.4g} kN of compression over a free stretch of "
                     f"{c.length:.4g} m (arc length {c.start:.4g} to {c.stop:.4g} m)")
            stiffness = f"EI = {c.bending_stiffness:.4g} N m^2"
        else:
            names = ", ".join(f"'{n}'" for n in c.lines)
            where = (f"lines {names}, joined end to end, carry {c.compression / 1e3:.4g} kN of compression over a "
                     f"free stretch of {c.length:.4g} m (from arc length {c.start:.4g} m of '{c.lines[0]}' to "
                     f"arc length {c.stop:.4g} m of '{c.lines[-1]}')")
            stiffness = f"EI = {c.bending_stiffness:.4g} N m^2, the smallest along the stretch"
        if c.free_ends == 1:
            n_tip = math.pi ** 2 * c.bending_stiffness / (2.0 * c.length) ** 2
            euler = (f"{c.euler_load / 1e3:.4g} kN (one end free, a cantilever of {c.length:.4g} m: "
                     f"{c.free_end_compression / 1e3:.4g} kN of it at the free end, whose load alone buckles it at "
                     f"pi^2 EI / (2 L)^2 = {n_tip / 1e3:.4g} kN, the rest loaded along it, each load P at its "
                     f"height a above the held end buckling it alone at pi^2 EI / (2 a)^2, combined by Dunkerley's "
                     f"sum; {stiffness})")
        else:
            euler = f"pi^2 EI / L^2 = {c.euler_load / 1e3:.4g} kN (pinned ends, {stiffness})"
        messages.append(
            f"{where}, above its Euler load {euler}: this static equilibrium is unstable (buckling) and a dynamic "
            f"run will leave it; give the line tension (gravity, a shorter line or ends further apart, an end "
            f"load) or support along the stretch, or check the start shape (analysis.statics.start)")
    return messages
