"""compile(scenario) -> Model: discretisation, connectivity and the loads a scene needs.

Primary and secondary division (Fig. 8.2): a line of length L with ``elements`` = n SDEs
is cut into n equal segments of length Delta = L/n; an SDE sits at the middle of each
segment; the n + 1 RFEs between them are RFE 0 (length Delta/2, at end A), RFEs 1..n-1
(length Delta) and RFE n (Delta/2, at end B). SDE stiffness by eq. 8.88 (kruszewski) or
eq. 8.89 (fem).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import ScenarioError
from ..kinematics import frame_from_tangent, minimal_rotation
from ..vessel import VesselMotion, make_vessel_motion
from ..sea.kernel import sea_spec
from ..loads.seabed import seabed_damping, stick_stiffness
from .arrays import (KIND_CLAMPED, KIND_FREE, KIND_PINNED, AttachmentState, KernelModel, Reference,
                     new_attachment_state)
from .sections import Section, section_from_type
from .supports import compile_supports, compile_tensioners, resting_points, supported_start
from .reels import compile_reels, reel_tail, reel_wrap_start, reeled_history, track_points
from .bodies import append_body, body_arrays, body_pose, deck_arrays
from .joins import JoinInfo, drive_rows, hinge_frame, joint_rows
from .arrays import append_sde, joint_arrays
from .march import march_joints
from ..scenario.joins import join_parent, join_strings
from ..scenario.load import NOTHING_TO_SIMULATE

log = logging.getLogger("rfesim")

LEAD_SHARE = 0.1          # clamped ends' straight leads longer than this share of the line: no leads
LEAD_CHORD = 1e-3         # ... nor when the chord between their inner ends is shorter than this share
BUILT_STRETCH = 1.1       # a line whose ends, placed when the model is built, lie further apart than this x its length
SHEAR_MARGIN = 1.0        # a line expected above this share of its fem shear limit defaults to kruszewski
NEARLY_FLEXIBLE = 1e-6     # 12 EI / Delta^3 below this fraction of GA / Delta: default to kruszewski


@dataclass
class LineInfo:
    """Where a line sits in the model arrays, and what it is."""

    name: str
    rfe_start: int
    rfe_stop: int
    sde_start: int
    sde_stop: int
    length: float
    elements: int
    dx: float
    section: Section
    shear_model: str
    end_a: object      # the scenario LineEnd
    end_b: object
    chord: float | None = None   # m, distance between the ends at t = 0 when both are placed
    tension_estimate: float = 0.0   # N, its largest static tension expected before statics (fem lines:
                                    #   _tension_estimate), against its fem shear limit (shear_limit)
    seabed_fold: tuple | None = None   # (length, horizontal span, height, limit, lower end's height) m of a heavy
                                       #   line longer than can hang onto the seabed and lie straight (_seabed_fold)
    held_length: float = 0.0   # m from end A to the last support point of its start shape (reel, rollers,
                               #   tensioner track): the pipe there cannot fold on the seabed (_held_end)
    seabed_u: tuple | None = None   # (H N, a = H / w m, top tension N) of a heavy line sagging onto the seabed
                                    #   from two ends above it (_seabed_u)

    @property
    def nrfe(self) -> int:
        return self.rfe_stop - self.rfe_start

    @property
    def sde_arc_length(self) -> np.ndarray:
        """Arc length of each SDE from end A (m)."""
        return (np.arange(self.elements) + 0.5) * self.dx

    @property
    def point_arc_length(self) -> np.ndarray:
        """Arc length of the output points: end A, every SDE, end B (m)."""
        return np.concatenate([[0.0], self.sde_arc_length, [self.length]])


@dataclass
class State:
    """Mutable state of a run: time, coordinates, rates, accelerations and the reference
    pose the coordinates are measured from."""

    t: float
    q: np.ndarray          # (n, 6) [displacement from ref.X (m), ZYX angles from ref.R (rad)]
    qd: np.ndarray         # (n, 6)
    qdd: np.ndarray        # (n, 6)
    ref: Reference         # per-RFE reference rotation and position
    aux: np.ndarray        # (n, 6) generalised-alpha algorithmic acceleration
    static: bool = False   # a static equilibrium (rfesim.solvers.statics.solve_statics): a dynamic
                           #   run starts from it at rest, aux 0 (dynamics.start_acceleration)
    fresh: bool = True     # no dynamic run has set aux yet: run_dynamics starts it
                           #   (dynamics.start_acceleration); a run's end state goes on with its own

    def copy(self) -> "State":
        return State(self.t, self.q.copy(), self.qd.copy(), self.qdd.copy(),
                     Reference(self.ref.R.copy(), self.ref.X.copy()), self.aux.copy(), self.static, self.fresh)

    def positions(self) -> np.ndarray:
        """Centres of the free RFEs (m); others are computed from their attachments."""
        return self.ref.X + self.q[:, :3]


@dataclass
class Model:
    scenario: object
    km: KernelModel
    lines: list[LineInfo]
    attachment_names: list[str]
    motions: list[VesselMotion | None]
    dof_mask: np.ndarray                    # (n, 6) bool, True for coordinates that move
    initial: State
    line_index: dict[str, int] = field(default_factory=dict)
    plastic_history_width: int = 1          # columns of the SDEs' plastic history
    supports: list = field(default_factory=list)   # rfesim.model.supports.SupportInfo, one per support
    tensioners: list = field(default_factory=list)  # rfesim.model.supports.TensionerInfo, one per tensioner
    bodies: list = field(default_factory=list)     # rfesim.model.bodies.BodyInfo, one per body
    reels: list = field(default_factory=list)      # rfesim.model.reels.ReelInfo, one per reel
    initial_plastic_history: np.ndarray | None = None   # (nsde, nh) plastic history at t = 0 (reeled pipe)
    winches: list = field(default_factory=list)    # rfesim.model.winches.WinchInfo, one per winch
    tuggers: list = field(default_factory=list)    # rfesim.model.tuggers.TuggerInfo, one per tugger line
    joins: list = field(default_factory=list)      # rfesim.model.joins.JoinInfo, one per line-to-line join
    closures: list = field(default_factory=list)   # rfesim.model.joins.JoinInfo, one per closing join (end B)

    @property
    def n(self) -> int:
        return self.km.rfe_mass.shape[0]

    @property
    def nsde(self) -> int:
        return self.km.sde_left.shape[0]

    def line(self, name: str) -> LineInfo:
        return self.lines[self.line_index[name]]

    def attachment_state(self, t: float, out: AttachmentState | None = None) -> AttachmentState:
        """Kinematics of every attachment at time t."""
        natt = len(self.attachment_names)
        if out is None:
            out = new_attachment_state(natt)
        for j, motion in enumerate(self.motions):
            if motion is None:
                continue
            k = motion.kinematics(t)
            out.p[j] = k.p
            out.R[j] = k.R
            out.v[j] = k.v
            out.w[j] = k.w
            out.a[j] = k.a
            out.alpha[j] = k.alpha
        return out

    @property
    def has_moving_attachments(self) -> bool:
        return any(m is not None and not type(m).__name__.startswith("Fixed") for m in self.motions)

    def describe_rfe(self, i: int) -> str:
        """'line pipe, RFE 12 (arc length 30.5 m)' for error messages."""
        for li in self.lines:
            if li.rfe_start <= i < li.rfe_stop:
                j = i - li.rfe_start
                s = 0.0 if j == 0 else min(li.length, j * li.dx)
                return f"line '{li.name}', RFE {j} (arc length {s:.4g} m)"
        for b in self.bodies:
            if b.rfe == i:
                return f"body '{b.name}'"
        return f"RFE {i}"


# ----------------------------------------------------------------------------- helpers

def _sde_coefficients(sec: Section, dx: float, shear_model: str) -> np.ndarray:
    """eq. 8.88 / 8.89: [c_x, c_y, c_z, c_torsion, c_bend_y, c_bend_z]."""
    cx = sec.EA / dx
    if shear_model == "fem":                      # eq. 8.89: shear in y pairs with bending about z
        cy = 12.0 * sec.EIz / dx ** 3
        cz = 12.0 * sec.EIy / dx ** 3
    else:                                         # eq. 8.88
        cy = cz = sec.GA / dx
    return np.array([cx, cy, cz, sec.GJ / dx, sec.EIy / dx, sec.EIz / dx])


def _choose_shear_model(line, sec: Section, dx: float) -> str:
    if line.shear_stiffness is not None:
        return line.shear_stiffness
    if 12.0 * sec.EI_min / dx ** 3 < NEARLY_FLEXIBLE * sec.GA / dx:
        log.info("line is nearly flexible (EI = %.3g N*m^2): using kruszewski shear stiffness (eq. 8.88)", sec.EI_min)
        return "kruszewski"
    return "fem"


def shear_limit(sec: Section, dx: float) -> float:
    """N, the tension up to which the fem shear springs (eq. 8.89, c = 12 EI / Delta^3) hold a
    chain of rigid elements in line: c Delta = 12 EI / Delta^2 (docs/theory.md, section 6,
    'Soft fem shear under tension'); beyond it the chain shears apart sideways."""
    return 12.0 * sec.EI_min / dx ** 2


def _hung_below(sc, lname: str, seen: frozenset = frozenset()) -> float:
    """N, what hangs from end B of line ``lname`` besides the line itself: the weight of a
    body there (dry, the most it pulls) and of the lines joined below it, each with its wet
    weight, point loads and what hangs below it in turn."""
    line = sc.lines[lname]
    g = sc.environment.gravity
    body = sc.bodies.get(line.end_b.attach) if isinstance(line.end_b.attach, str) else None
    weight = body.mass * g if body is not None else 0.0
    for name, child in sc.lines.items():
        if name not in seen and join_parent(child.end_a) == lname:
            sec = section_from_type(sc.line_types[child.type])
            weight += abs(_submerged_weight(sec, sc)) * child.length + _point_loads(child)
            weight += _hung_below(sc, name, seen | {lname})
    return weight


def _point_loads(line) -> float:
    return sum(float(np.linalg.norm(ld.force)) for ld in line.loads)


def _tension_estimate(lname: str, line, sec: Section, sc, A, B) -> float:
    """N, the largest static tension of a line expected before statics: the elastic
    catenary's between its ends when both are placed (the U of ``_two_touchdowns`` when it
    sags onto the seabed from two ends above it), or the stretch between ends farther
    apart than its length, else its wet weight; with its point loads and what hangs from its
    end B (a body, joined lines: ``_hung_below``)."""
    from ..catenary import solve_catenary
    w = abs(_submerged_weight(sec, sc))
    extra = _point_loads(line) + _hung_below(sc, lname)
    tension = w * line.length
    if A is not None and B is not None:
        d = float(np.linalg.norm(B - A))
        lo, hi = (A, B) if A[2] <= B[2] else (B, A)
        span = float(np.hypot(*(hi - lo)[:2]))
        if d >= line.length:
            tension = sec.EA * (d / line.length - 1.0)
        elif w > 0.0 and span > 1e-6 * line.length:
            # a heavy line whose lower end rests on the seabed lies on it in part, as its start
            # shape does (_catenary_curve): the catenary without seabed would sag through it
            # and overstate the tension
            on_seabed = _submerged_weight(sec, sc) > 0.0 and _grounded(lo, sec, sc, line.length)
            try:
                cat = solve_catenary(span, float(hi[2] - lo[2]), line.length, w, sec.EA, seabed=bool(on_seabed))
                tension = max(cat.top_tension, cat.anchor_tension)
            except (ValueError, ArithmeticError):
                pass                # no catenary for these sizes: the wet weight stands
            u = None if on_seabed else _seabed_u(line, sec, sc, A, B)
            if u is not None:
                tension = u[2]          # both ends above the seabed, sagging onto it: the U
    return tension + extra


def _seabed_u(line, sec: Section, sc, A, B) -> tuple[float, float, float] | None:
    """(H N, a = H / w m, top tension N) of a heavy line between placed ends above the seabed
    that sags onto it in a U (``_two_touchdowns``, on the seabed under its lower end, as its
    start shape takes it); None otherwise."""
    w = _submerged_weight(sec, sc)
    if A is None or B is None or w <= 0.0:
        return None
    lo, hi = (A, B) if A[2] <= B[2] else (B, A)
    zb = sc.environment.seabed_z_at(float(lo[0]), float(lo[1]))
    if zb is None or _grounded(lo, sec, sc, line.length):
        return None
    level = zb + 0.5 * sec.outer_diameter
    span = float(np.hypot(*(hi - lo)[:2]))
    u = _two_touchdowns(float(lo[2] - level), float(hi[2] - level), span, line.length, w, n=3)
    if u is None:
        return None
    H = float(u[3].min())
    return H, H / w, float(u[3].max())


def _grounded(p: np.ndarray, sec: Section, sc, length: float) -> bool:
    """Whether the point ``p`` of a line rests on the seabed (as _catenary_curve takes it)."""
    z = sc.environment.seabed_z_at(float(p[0]), float(p[1]))
    return z is not None and (p[2] - 0.5 * sec.outer_diameter - z) < 1e-3 * length


def _held_end(curve: _Curve, held: list) -> tuple[float, np.ndarray] | None:
    """(arc length, point) of the last vertex of the start curve that is a support point (a
    reel's take-off point, a roller's resting point, a tensioner track's entry or exit): the
    line is held there and up to there, and hangs free only beyond it. None without any."""
    pts = [np.asarray(p, float).reshape(-1, 3) for p in held if p is not None and len(p)]
    if not pts:
        return None
    P = np.vstack(pts)
    scale = 1e-9 * max(1.0, float(np.abs(curve.X).max()))
    hit = [k for k in range(curve.X.shape[0]) if np.min(np.linalg.norm(P - curve.X[k], axis=1)) <= scale]
    if not hit:
        return None
    k = max(hit)
    return float(curve.s[k]), curve.X[k].copy()


def _seabed_fold(line, sec: Section, sc, A, B, held: tuple[float, np.ndarray] | None = None) -> tuple | None:
    """(length, horizontal span, height, limit, lower end's height) of a heavy line between
    placed ends that is longer than ``limit``: what can hang vertically from the upper end
    down to the seabed under it and lie straight along the seabed to the lower end (on a flat
    seabed the horizontal span plus the height; on a slope or a profile the drop to the
    seabed under the upper end plus the length along the seabed). When the lower end is above
    the seabed too, the line can also hang vertically from it (a U whose bottom lies on the
    seabed: _two_touchdowns), and the limit adds that drop, the fifth entry (0 for a lower
    end on the seabed). The rest would fold back on the seabed, which has no unique static
    shape (its start shape bunches it up). None otherwise.

    ``held`` (``_held_end``: arc length from end A and point of the last support of the start
    shape, end A upper): the line hangs free only from there, so span and height are taken
    from that point and the limit adds the held length (the pipe on a reel-lay vessel's reel,
    aligner, straightener and tensioner, 38 m at a 89.5 deg ramp, is not slack)."""
    if A is None or B is None or _submerged_weight(sec, sc) <= 0.0:
        return None
    s_held = 0.0
    if held is not None and B[2] <= A[2]:
        s_held, A = held
    lo, hi = (A, B) if A[2] <= B[2] else (B, A)
    env = sc.environment
    if env.seabed is None:
        return None
    span = float(np.hypot(*(hi - lo)[:2]))
    height = float(hi[2] - lo[2])
    # the seabed path from under the lower end to under the upper end (profiles are piecewise
    # linear: sample finely enough for their kinks)
    n = 1 if env.seabed.profile is None else max(64, 8 * len(env.seabed.profile))
    f = np.linspace(0.0, 1.0, n + 1)
    x = lo[0] + f * (hi[0] - lo[0])
    y = lo[1] + f * (hi[1] - lo[1])
    zb = np.array([env.seabed_z_at(float(a), float(b)) for a, b in zip(x, y)])
    along = float(np.sum(np.sqrt(np.diff(x) ** 2 + np.diff(y) ** 2 + np.diff(zb) ** 2)))
    contact = 0.5 * sec.outer_diameter
    if _grounded(lo, sec, sc, line.length):
        # from the lower end's height above the seabed
        drop_lo, hang = 0.0, height - float(zb[-1] - zb[0])
    else:
        # both ends above the seabed: the line may hang down from each onto it (a U)
        drop_lo, hang = float(lo[2] - contact - zb[0]), float(hi[2] - contact - zb[-1])
    limit = s_held + drop_lo + max(hang, 0.0) + along
    if line.length <= limit * (1.0 + 1e-3):
        return None
    return line.length, span, max(hang, 0.0), limit, drop_lo


def _plane_above_water(sc, centres: np.ndarray, lines) -> tuple[str, str] | None:
    """A sloped plane seabed rises through the water surface somewhere; the (field, reason)
    error when it does under the scene: under an RFE centre of the start shape or a vessel
    at rest. (A profile holds its end depths beyond its rows, all below the surface, so it
    never does: Seabed.profile_table.) None otherwise."""
    env = sc.environment
    sb, water = env.seabed, env.water
    if sb is None or water is None or sb.profile is not None or sb.slope_deg == 0.0:
        return None
    where = [(f"the start shape of line '{li.name}'", centres[k])
             for li in lines for k in range(li.rfe_start, li.rfe_stop)]
    where += [(f"vessel '{name}'", np.asarray(v.position, float)) for name, v in sc.vessels.items()]
    surface = water.surface_level
    for what, p in where:
        zb = env.seabed_z_at(float(p[0]), float(p[1]))
        if zb >= surface:
            g = math.tan(math.radians(sb.slope_deg))
            shore = (surface - env.seabed_z_at(0.0, 0.0)) / g
            return ("environment.seabed.slope_deg",
                    f"the plane seabed sloping {sb.slope_deg:g} deg reaches the water surface (z = {surface:g} m) "
                    f"{shore:.6g} m from the global origin along slope_direction_deg "
                    f"({sb.slope_direction_deg:g} deg) and continues above it, and {what} lies over it there "
                    f"(at x = {p[0]:.6g} m, y = {p[1]:.6g} m the seabed is {zb - surface:.4g} m above the "
                    f"water): give a gentler slope, or the seabed as a profile (flat beyond its last row)")
    return None


def _submerged_weight(sec: Section, sc) -> float:
    g = sc.environment.gravity
    w = sec.mass_per_length * g
    if sc.environment.water is not None:
        w -= sc.environment.water.density * g * sec.displaced_area
    return w


class _Curve:
    """Initial shape of a line: a polyline through points at given arc lengths."""

    def __init__(self, s: np.ndarray, X: np.ndarray, strain=None):
        self.s = s
        self.X = X
        self.strain = strain          # callable: axial strain at arc length s (e.g. T(s) / EA), or None

    def __call__(self, s):
        return np.column_stack([np.interp(s, self.s, self.X[:, k]) for k in range(3)])

    def _march(self, start: np.ndarray, lengths: np.ndarray, direction: np.ndarray | None = None) -> np.ndarray:
        """Joint points from ``start`` along the polyline, each at the given straight
        distance from the previous one (sphere-polyline intersections, moving forward),
        straight on along ``direction`` (default: the last direction) past its end; the
        compiled loop rfesim.model.march.march_joints."""
        if direction is None:
            direction = self._last_direction()
        f64 = np.float64
        return march_joints(np.ascontiguousarray(self.X, dtype=f64), np.ascontiguousarray(start, dtype=f64),
                            np.ascontiguousarray(lengths, dtype=f64), np.ascontiguousarray(direction, dtype=f64))

    def _last_direction(self) -> np.ndarray:
        """Unit direction of the curve's last segment of nonzero length."""
        d = np.diff(self.X, axis=0)
        n = np.linalg.norm(d, axis=1)
        k = np.nonzero(n > 0.0)[0]
        return d[k[-1]] / n[k[-1]] if k.size else np.array([1.0, 0.0, 0.0])

    def joints(self, lengths: np.ndarray, end_b: np.ndarray | None) -> np.ndarray:
        """Points A = J0, J1, ..., J_{n+1} with |J_{i+1} - J_i| = lengths_i (1 + e_i + e),
        e_i the curve's own strain at the element (the catenary's T/EA) and e a common
        correction chosen (secant) so the chain closes at end_b when given: the RFEs then
        meet at every SDE with the tension of the curve, without spurious initial forces."""
        start = self.X[0]
        if self.strain is not None:
            mid = np.concatenate([[0.0], np.cumsum(lengths)])
            lengths = lengths * (1.0 + self.strain(0.5 * (mid[:-1] + mid[1:])))
        direction = self._last_direction()
        if end_b is None:
            return self._march(start, lengths, direction)
        def miss(e):
            pts = self._march(start, lengths * (1.0 + e), direction)
            return float(np.linalg.norm(pts[-1] - end_b)) * (1.0 if self._short(pts, end_b) else -1.0), pts
        m0, pts = miss(0.0)
        if abs(m0) < 1e-12 * lengths.sum():
            return pts
        e1 = 1e-6
        m1, pts = miss(e1)
        e0 = 0.0
        for _ in range(40):
            if m1 == m0:
                break
            e2 = e1 - m1 * (e1 - e0) / (m1 - m0)
            e0, m0 = e1, m1
            e1 = e2
            m1, pts = miss(e1)
            if abs(m1) < 1e-13 * lengths.sum():
                break
        pts[-1] = end_b
        return pts

    @staticmethod
    def _short(pts: np.ndarray, end_b: np.ndarray) -> bool:
        """True when the marched chain stops before end_b (needs stretching)."""
        last = pts[-1] - pts[-2]
        return float((end_b - pts[-1]) @ last) > 0.0


def _straight(start: np.ndarray, direction: np.ndarray, length: float, stretch: float = 1.0) -> _Curve:
    d = direction / np.max(np.abs(direction))     # scaled first: the squares of 1e200 overflow in the norm
    d = d / np.linalg.norm(d)
    s = np.array([0.0, length])
    return _Curve(s, np.vstack([start, start + stretch * length * d]))


class _TwoTouchdownTension:
    """Tension along a ``_two_touchdowns`` shape, as CatenarySolution.tension gives it."""

    def __init__(self, s: np.ndarray, tension: np.ndarray):
        self.s, self.T = s, tension

    def tension(self, arc):
        return np.interp(arc, self.s, self.T)


def _two_touchdowns(h_lo: float, h_hi: float, span: float, length: float, weight: float,
                    n: int = 2001) -> tuple | None:
    """A heavy line between two ends ``h_lo`` and ``h_hi`` above a flat seabed, ``span`` apart
    horizontally, that hangs down to the seabed on both sides and lies on it in between: two
    touchdown catenaries of the same horizontal tension H = w a (no friction along the laid
    part), each from a height h with suspended length sqrt(h^2 + 2 h a) and horizontal reach
    a acosh(1 + h / a) (the catenary z = a (cosh(x / a) - 1) from its touchdown), and the laid
    length span - reach_lo - reach_hi between them; a is the root of

        sum_i [sqrt(h_i^2 + 2 h_i a) - a acosh(1 + h_i / a)] + span = length,

    between a -> 0 (left side: h_lo + h_hi + span, the longest line that can hang vertically
    and lie straight, _seabed_fold) and the a at which the laid part vanishes (the free
    catenary touching the seabed at one point). Inextensible; the start shape's joints add
    the strain T / EA (_Curve.joints).

    Returns (arc s from the lower end, horizontal distance x, height z above the seabed,
    tension T) on ``n`` points, or None when no such shape exists (the line is too long, so
    its slack folds, or too short to reach the seabed)."""
    import scipy.optimize

    if min(h_lo, h_hi) <= 0.0 or weight <= 0.0:
        return None

    def reach(a):
        return a * math.acosh(1.0 + h_lo / a) + a * math.acosh(1.0 + h_hi / a)

    def excess(a):
        hang = math.sqrt(h_lo * h_lo + 2.0 * h_lo * a) + math.sqrt(h_hi * h_hi + 2.0 * h_hi * a)
        return hang + span - reach(a) - length

    tiny = 1e-9 * max(h_lo, h_hi, span)
    if reach(tiny) >= span or excess(tiny) <= 0.0:
        return None
    big = max(h_lo, h_hi, span)
    while reach(big) < span:
        big *= 2.0
    a_touch = scipy.optimize.brentq(lambda a: reach(a) - span, tiny, big, xtol=1e-12 * big)
    if excess(a_touch) >= 0.0:
        return None
    a = scipy.optimize.brentq(excess, tiny, a_touch, xtol=1e-13 * a_touch)
    s_lo = math.sqrt(h_lo * h_lo + 2.0 * h_lo * a)
    x_lo = a * math.acosh(1.0 + h_lo / a)
    laid = span - reach(a)
    s = np.linspace(0.0, length, n)
    # arc from each touchdown (negative on the laid part), and the catenary there
    sig = np.where(s < s_lo, s_lo - s, np.maximum(s - s_lo - laid, 0.0))
    u = a * np.arcsinh(sig / a)
    x = np.where(s < s_lo, x_lo - u, np.where(s <= s_lo + laid, x_lo + (s - s_lo), x_lo + laid + u))
    z = np.sqrt(a * a + sig * sig) - a
    tension = weight * (a + z)
    x[-1], z[-1] = span, h_hi
    return s, x, z, tension


def _catenary_curve(A: np.ndarray, B: np.ndarray, length: float, weight: float, EA: float,
                    seabed_z: float | None, contact_radius: float, seabed_k: float = 0.0) -> _Curve | None:
    """Elastic catenary in the vertical plane through A and B (None if not applicable).
    The part on the seabed is placed at its static penetration weight / k, where the
    contact already has its stiffness (at zero penetration it has none, and Newton would
    see no seabed under the grounded elements)."""
    from ..catenary import solve_catenary
    if weight < 0.0:
        # a buoyant line floats up: the catenary of its net buoyancy -w hangs the other way up,
        # the hanging catenary of weight -w mirrored in a horizontal plane (the same tensions).
        # The seabed cannot hold it up; the free surface is not a support either.
        flip = np.array([1.0, 1.0, -1.0])
        c = _catenary_curve(A * flip, B * flip, length, -weight, EA, None, contact_radius)
        return None if c is None else _Curve(c.s, c.X * flip[None, :], c.strain)
    swap = B[2] < A[2]
    lo, hi = (B, A) if swap else (A, B)
    dh = hi[:2] - lo[:2]
    span = float(np.hypot(dh[0], dh[1]))
    height = float(hi[2] - lo[2])
    if weight <= 0.0 or span < 1e-6 * length:
        return None
    on_seabed = seabed_z is not None and (lo[2] - contact_radius - seabed_z) < 1e-3 * length
    try:
        sol = solve_catenary(span, height, length, weight, EA, seabed=bool(on_seabed))
    except Exception as exc:  # noqa: BLE001 - fall back to another start shape
        log.info("catenary start failed (%s); using a straight start", exc)
        return None
    s = np.linspace(0.0, length, 2001)
    x, z = sol.profile(s)
    eh = np.array([dh[0], dh[1], 0.0]) / span
    X = lo[None, :] + x[:, None] * eh[None, :] + z[:, None] * np.array([0.0, 0.0, 1.0])[None, :]
    if seabed_z is not None and not on_seabed and float(X[:, 2].min()) < seabed_z + contact_radius - 1e-6 * length:
        # both ends above the seabed and the free catenary sags through it: it lies on the
        # seabed between two touchdowns (clipping the free sag to the seabed would bunch it up)
        u = _two_touchdowns(float(lo[2] - seabed_z - contact_radius), float(hi[2] - seabed_z - contact_radius),
                            span, length, weight)
        if u is not None:
            s, x, z, tension = u
            X = np.column_stack([lo[0] + x * eh[0], lo[1] + x * eh[1], seabed_z + contact_radius + z])
            sol = _TwoTouchdownTension(s, tension)
    if seabed_z is not None:
        rest = seabed_z + contact_radius - (weight / seabed_k if seabed_k > 0 else 0.0)
        # grounded: at the level of the lower end (the catenary's seabed), which may sit a
        # little above or below the contact level given by the pipe radius
        level = max(seabed_z + contact_radius, lo[2]) if on_seabed else seabed_z + contact_radius
        on = X[:, 2] <= level + 1e-6 * length
        X[on, 2] = rest
        X[:, 2] = np.maximum(X[:, 2], rest)
    strain = (lambda arc: sol.tension(arc) / EA)
    if swap:
        X = X[::-1].copy()
        return _Curve(s, X, lambda arc: sol.tension(length - arc) / EA)
    return _Curve(s, X, strain)


# ----------------------------------------------------------------------------- compile

def compile_scenario(sc, start: str | None = None) -> Model:
    """Build the frozen model arrays and the initial state of a validated scenario."""
    env = sc.environment
    attachment_names = ["fixed"] + list(sc.vessels)
    motions: list[VesselMotion | None] = [None] + [make_vessel_motion(v, env) for v in sc.vessels.values()]
    att0 = new_attachment_state(len(attachment_names))
    for j, motion in enumerate(motions):
        if motion is not None:
            k = motion.kinematics(0.0)
            att0.p[j], att0.R[j] = k.p, k.R

    water = env.water
    seabed_z = env.seabed_z()
    seabed = env.seabed
    start = start or sc.analysis.statics.start

    rfe = {k: [] for k in ("mass", "inertia", "length", "kind", "attach", "attach_offset", "pin_arm", "clamp_R",
                           "diameter", "disp_area", "cdn", "cdt", "can", "cat", "contact_radius", "seabed_c",
                           "seabed_ct")}
    sde = {k: [] for k in ("left", "right", "arm_left", "arm_right", "stiffness", "damping", "length")}
    loads = {k: [] for k in ("rfe", "arm", "force", "moment", "local")}
    q0_blocks, R0_blocks, X0_blocks = [], [], []
    lines: list[LineInfo] = []
    plastic_rows: list[np.ndarray] = []
    plastic_flags: list[int] = []
    n_total = 0
    nsde_total = 0
    problems: list[tuple[str, str]] = []
    tension_flags: list[int] = []          # per SDE: 1 for a tension-only line type (a rope)
    body_infos: list = []                  # rfesim.model.bodies.BodyInfo
    join_infos: list[JoinInfo] = []        # line-to-line joins (rfesim.model.joins)
    motors: list[dict] = []                # servo motors of coaxial joins (rfesim.loads.drives.motor_forces)
    join_drives: list = []                 # (joint SDE, parent end rotation at t = 0, schema drives)
    end_b_of: dict[str, dict] = {}         # per line: its end-B RFE, point, frame and SDE data (joins)

    # the lines of a joined string get consecutive RFEs, parent then child; a string with a
    # closing join (end B on another line's end B, rfesim.model.joins) after the strings it
    # closes onto, so that its end B can be taken from theirs
    closing = {name: join_parent(ln.end_b) for name, ln in sc.lines.items() if join_parent(ln.end_b) is not None}
    strings = join_strings(sc)
    strings = [st for st in strings if not closing.keys() & set(st)] + \
        [st for st in strings if closing.keys() & set(st)]
    closures: list[tuple[str, str]] = []   # (closing line, target line)
    for lname in [name for string in strings for name in string]:
        line = sc.lines[lname]
        base = f"lines.{lname}"
        parent = join_parent(line.end_a)
        if parent is not None and parent not in end_b_of:
            continue                       # the parent failed (its problem is reported)
        lt = sc.line_types[line.type]
        sec = section_from_type(lt)
        nseg = line.elements
        L = line.length
        dx = L / nseg
        shear_model = _choose_shear_model(line, sec, dx)
        if getattr(lt, "tension_only", False) and line.shear_stiffness is None:
            shear_model = "kruszewski"       # a rope: its elements stay joined whatever its (small) EI
        lengths = np.full(nseg + 1, dx)
        lengths[0] = lengths[-1] = 0.5 * dx
        s_lo = np.concatenate([[0.0], (np.arange(1, nseg + 1) - 0.5) * dx])
        s_hi = np.concatenate([(np.arange(1, nseg + 1) - 0.5) * dx, [L]])
        masses = sec.mass_per_length * lengths
        # Torsion inertia: the section's polar mass moment, but at least that of a
        # homogeneous section with the same GJ/EA, 2 (1 + nu) mu GJ / EA, so that a section
        # given without inertia has no torsion mode above its axial one.
        nu = lt.poisson_ratio
        polar = max(sec.polar_inertia, 2.0 * (1.0 + nu) * sec.mass_per_length * sec.GJ / sec.EA)
        if polar <= 0.0:
            # no torsion stiffness either (a cable): any positive inertia will do
            radius = 0.5 * sec.outer_diameter if sec.outer_diameter > 0 else 1e-3 * dx
            polar = sec.mass_per_length * radius * radius
        inertia = np.column_stack([polar * lengths,
                                   masses * lengths ** 2 / 12.0 + sec.rotary_inertia * lengths,
                                   masses * lengths ** 2 / 12.0 + sec.rotary_inertia * lengths])
        # --- ends
        ends = {}
        for end_name, end, j in (("end_a", line.end_a, 0), ("end_b", line.end_b, nseg)):
            if end.attach == "free" or end.attach in sc.bodies or join_parent(end) is not None:
                # a body: its own RFE (model.bodies); a join: an SDE to the parent (model.joins)
                ends[end_name] = dict(kind=KIND_FREE, att=-1, offset=np.zeros(3))
            else:
                att = attachment_names.index(end.attach)
                kind = KIND_CLAMPED if end.connection == "clamped" else KIND_PINNED
                ends[end_name] = dict(kind=kind, att=att, offset=np.asarray(end.position, float))
        # global end positions and directions at t = 0
        def _glob_point(end_name, end):
            if end.position is None:
                return None
            e = ends[end_name]
            p = np.asarray(end.position, float)
            if e["att"] <= 0:
                return p
            return att0.p[e["att"]] + att0.R[e["att"]] @ p

        def _glob_dir(end_name, end):
            if end.direction is None:
                return None
            d = np.asarray(end.direction, float)
            d = d / np.max(np.abs(d))       # any size (rfesim.scenario.schema._nonzero): scaled before the norm
            d = d / np.linalg.norm(d)
            e = ends[end_name]
            if e["att"] <= 0:
                return d
            return att0.R[e["att"]] @ d

        A = _glob_point("end_a", line.end_a)
        B = _glob_point("end_b", line.end_b)
        target = closing.get(lname)
        if target is not None and B is None:
            if target not in end_b_of:
                problems.append((f"{base}.end_b.position", f"line '{target}' comes later in the scenario: give the "
                                                           f"position of this closing end (global)"))
                continue
            B = end_b_of[target]["point"].copy()     # a closing join: end B starts at the target's end B
        dA = _glob_dir("end_a", line.end_a)
        dB = _glob_dir("end_b", line.end_b)
        down = np.array([0.0, 0.0, -1.0]) if env.gravity > 0 else np.array([1.0, 0.0, 0.0])
        # a line with one end placed hangs from it, or floats up from it when buoyant and that
        # end is under water (up to the surface, then along it: _floating_curve)
        surface = env.water.surface_level if env.water is not None else None
        placed = A if A is not None else B
        floats = (env.gravity > 0 and _submerged_weight(sec, sc) < 0.0 and surface is not None
                  and placed is not None and placed[2] < surface)
        if parent is not None:
            # a join: end A starts at the parent's end B
            PB = end_b_of[parent]["point"]
            if A is not None and float(np.linalg.norm(A - PB)) > 1e-6:
                problems.append((f"{base}.end_a.position", f"{np.round(A, 9).tolist()} is "
                                 f"{float(np.linalg.norm(A - PB)):.6g} m from end B of line '{parent}' at the start "
                                 f"{np.round(PB, 9).tolist()}: leave it out or make them agree within 1e-6 m"))
                continue
            A = PB.copy()
        wrap = reel_wrap_start(sc, lname, attachment_names, att0)
        if wrap is not None:
            A = wrap[1][0]          # stored on a reel: end A lies on the wrap (rfesim.model.reels)
        body_pose_b = None
        if line.end_b.attach in sc.bodies:
            body_pose_b = body_pose(sc.bodies[line.end_b.attach], line, A, down)
            if body_pose_b is None:
                problems.append((f"bodies.{line.end_b.attach}.position", "give the body's position or the "
                                                                        f"position of end A of line '{lname}'"))
                continue
            B, dB = body_pose_b[2], None
        if parent is not None and dA is None:
            # toward end B when it is placed, else along the parent's end tangent
            chord = None if B is None else B - A
            if chord is not None and float(np.linalg.norm(chord)) > 1e-9 * L:
                dA = chord / np.linalg.norm(chord)
            else:
                dA = end_b_of[parent]["frame"][:, 0].copy()
        tension = _tension_estimate(lname, line, sec, sc, A, B) if shear_model == "fem" else 0.0
        if shear_model == "fem" and line.shear_stiffness is None:
            if tension > SHEAR_MARGIN * shear_limit(sec, dx):
                # the fem shear would not hold this line's tension in line (docs/theory.md, section 6)
                log.info("line %s: its tension, about %.4g N, is beyond %g of the fem shear limit 12 EI / "
                         "Delta^2 = %.4g N: using the kruszewski shear stiffness (eq. 8.88)", lname, tension,
                         SHEAR_MARGIN, shear_limit(sec, dx))
                shear_model = "kruszewski"
        curve = None
        end_distance = None
        if A is not None and B is not None:
            chord = B - A
            d = end_distance = float(np.linalg.norm(chord))
            if d < 1e-9 * L:
                problems.append((f"{base}.end_b.position", "end B coincides with end A"))
                continue
            if d > BUILT_STRETCH * L:
                # ends placed only here (a join's parent end, a body): a line that cannot reach
                # between them, in the user's field (validation refuses placed ends past 2 %,
                # rfesim.scenario.load; a soft line from a chain point may be pre-stretched more)
                from ..scenario.pipelay import user_field
                field = user_field(sc, f"{base}.length")
                problems.append((field, f"{L:.6g} m is shorter than the distance between its ends at the start "
                                        f"({d:.6g} m): the line would be stretched by {100 * (d / L - 1):.3g} %"))
                continue
            if d >= L * (1.0 - 1e-9) or start == "straight" or env.gravity == 0.0:
                curve = _straight(A, chord, L, stretch=d / L)
            else:
                # a clamped end with a direction holds its end RFE along it (its pose is the
                # clamp's, docs/theory.md section 5): the catenary spans between the end RFEs'
                # inner ends, so that SDE 0 starts without a gap (eq. 8.85), only bent (eq. 8.87)
                lead_a = lengths[0] if (ends["end_a"]["kind"] == KIND_CLAMPED and dA is not None) else 0.0
                lead_b = lengths[-1] if (ends["end_b"]["kind"] == KIND_CLAMPED and dB is not None) else 0.0
                A1 = A + lead_a * dA if lead_a > 0.0 else A
                B1 = B - lead_b * dB if lead_b > 0.0 else B
                L1 = L - lead_a - lead_b
                inner = float(np.linalg.norm(B1 - A1))
                if inner >= L1 * (1.0 - 1e-9) or inner < LEAD_CHORD * L1 or lead_a + lead_b > LEAD_SHARE * L:
                    # no slack between the clamps' leads, or so few elements that the leads are
                    # much of the line or end at (or past) the other end: the catenary end to end
                    A1, B1, L1, lead_a, lead_b = A, B, L, 0.0, 0.0
                low = A1 if A1[2] <= B1[2] else B1
                curve = _catenary_curve(A1, B1, L1, _submerged_weight(sec, sc), sec.EA,
                                        env.seabed_z_at(float(low[0]), float(low[1])),
                                        0.5 * sec.outer_diameter, seabed.normal_stiffness if seabed else 0.0)
                if curve is None:
                    curve = _sagged_curve(A1, B1, L1, up=_submerged_weight(sec, sc) < 0.0)
                if lead_a > 0.0 or lead_b > 0.0:
                    curve = _with_leads(curve, A, B, lead_a, lead_b)
        elif A is not None:
            curve = _straight(A, dA, L) if dA is not None else \
                _floating_curve(A, L, surface - 0.5 * sec.outer_diameter) if floats else _straight(A, down, L)
        elif B is not None:
            if dB is None and floats:
                up = _floating_curve(B, L, surface - 0.5 * sec.outer_diameter)
                curve = _Curve(L - up.s[::-1], up.X[::-1].copy())
            else:
                dirB = dB if dB is not None else -down
                curve = _straight(B - L * dirB / np.linalg.norm(dirB), dirB, L)
        else:
            problems.append((f"{base}.end_a.position", "give the position of at least one end"))
            continue
        rest = resting_points(sc, lname, 0.5 * sec.outer_diameter, attachment_names, att0) \
            if (A is not None and start != "straight") else None
        if rest is not None:
            # over rollers: through their resting points, then a catenary to end B
            curve = _supported_curve(A, B, L, rest, sec, sc)
        held_points = [rest]
        if wrap is not None:
            # from end A along the wrap to the take-off point, then over the rollers
            track = track_points(sc, lname, attachment_names, att0) if B is not None else None
            ts, tX = reel_tail(wrap[1][-1], wrap[2], L - wrap[0][-1], rest, B, tail=_catenary_tail(sec, sc),
                               track=track)
            curve = _Curve(np.concatenate([wrap[0], wrap[0][-1] + ts[1:]]), np.vstack([wrap[1], tX[1:]]))
            held_points += [wrap[1][-1:], track]
        held = _held_end(curve, held_points) if (rest is not None or wrap is not None) else None
        joints = curve.joints(lengths, B if (A is not None and B is not None) else None)
        if A is None:
            # only end B is placed: the curve was built ending at B; march from its start
            joints = curve.joints(lengths, None)
        e0, e1 = joints[:-1], joints[1:]
        tang = e1 - e0
        norms = np.linalg.norm(tang, axis=1)
        if not (np.all(np.isfinite(joints)) and np.all(np.isfinite(norms))):
            # an overflow in the start shape (a catenary or a seabed sinkage of absurd size): more
            # elements would not help, the sizes would
            problems.append((base, f"the start shape of this line of {L:.6g} m has joints at non-finite positions "
                                   f"(its catenary or its sinkage into the seabed overflowed): check the sizes and "
                                   f"units of its end positions, of its line type's weight and EA, and of "
                                   f"environment.gravity and environment.seabed.normal_stiffness"))
            continue
        if not np.all(norms > 1e-9 * L):
            # the chain of so few, long elements does not close along the start curve
            problems.append((f"{base}.elements", f"{nseg} elements of {dx:.4g} m are too few to start this line "
                                                 f"of {L:.6g} m from its start shape (two of its joints coincide): "
                                                 f"give more elements (e.g. {max(2 * nseg, 10)})"))
            continue
        tang /= norms[:, None]
        centres = 0.5 * (e0 + e1)
        # frames: clamped end A sets the first frame, then parallel transport along the line
        frames = np.empty((nseg + 1, 3, 3))
        if line.end_a.connection == "clamped" and dA is not None:
            frames[0] = frame_from_tangent(dA)
        else:
            frames[0] = frame_from_tangent(tang[0])
        hinge = -1
        if getattr(line.end_a, "hinge_axis", None) is not None and parent is not None:
            # a hinged join (rfesim.model.joins): its axis is the child's first torsion or bending axis
            hinge, frame = hinge_frame(frames[0][:, 0], np.asarray(line.end_a.hinge_axis, float))
            if hinge < 0:
                problems.append((f"{base}.end_a.hinge_axis", frame))
                continue
            frames[0] = frame
        for i in range(1, nseg + 1):
            frames[i] = minimal_rotation(frames[i - 1][:, 0] if i == 1 else tang[i - 1], tang[i]) @ frames[i - 1]
        if line.end_b.connection == "clamped" and dB is not None:
            frames[-1] = minimal_rotation(frames[-1][:, 0], dB) @ frames[-1]
        if body_pose_b is not None and line.end_b.connection == "clamped":
            # the connection's rotation springs measure from equal frames (rfesim.model.bodies)
            if float(frames[-1][:, 0] @ body_pose_b[1][:, 0]) < 1.0 - 1e-6:
                problems.append((f"bodies.{line.end_b.attach}.orientation_deg", f"a clamped body continues the "
                                 f"line: its x axis must point along line '{lname}' at end B, "
                                 f"{np.round(frames[-1][:, 0], 6).tolist()}"))
                continue
            frames[-1] = body_pose_b[1]
        if body_pose_b is not None:
            # the end RFE ends exactly at the attachment point: the stiff connection starts unloaded
            centres[-1] = B - 0.5 * lengths[-1] * frames[-1][:, 0]
        # --- RFE arrays
        for i in range(nseg + 1):
            rfe["mass"].append(masses[i])
            rfe["inertia"].append(inertia[i])
            rfe["length"].append(lengths[i])
            kind, att, offset, arm = KIND_FREE, -1, np.zeros(3), np.zeros(3)
            clamp = np.eye(3)
            if i == 0 and ends["end_a"]["kind"] != KIND_FREE:
                e = ends["end_a"]
                kind, att, offset = e["kind"], e["att"], e["offset"]
                arm = np.array([-0.5 * lengths[i], 0.0, 0.0])
            elif i == nseg and ends["end_b"]["kind"] != KIND_FREE:
                e = ends["end_b"]
                kind, att, offset = e["kind"], e["att"], e["offset"]
                arm = np.array([0.5 * lengths[i], 0.0, 0.0])
            if kind == KIND_CLAMPED:
                clamp = att0.R[att].T @ frames[i]
            rfe["kind"].append(kind)
            rfe["attach"].append(att)
            rfe["attach_offset"].append(offset)
            rfe["pin_arm"].append(arm)
            rfe["clamp_R"].append(clamp)
            in_water = water is not None and sec.outer_diameter > 0
            rfe["diameter"].append(sec.outer_diameter if in_water else 0.0)
            rfe["disp_area"].append(sec.displaced_area if in_water else 0.0)
            rfe["cdn"].append(sec.drag_normal)
            rfe["cdt"].append(sec.drag_axial)
            rfe["can"].append(sec.added_mass_normal)
            rfe["cat"].append(sec.added_mass_axial)
            rfe["contact_radius"].append(0.5 * sec.outer_diameter)
            c_len, ct_len = seabed_damping(seabed, sec.mass_per_length)
            rfe["seabed_c"].append(c_len)
            rfe["seabed_ct"].append(ct_len)
        # --- the joint SDE to the parent (rfesim.model.joins), numbered before the line's own SDEs
        if parent is not None:
            pe = end_b_of[parent]
            dxm = 0.5 * (pe["dx"] + dx)
            free_ends = {"end_a": {"kind": KIND_FREE}, "end_b": {"kind": KIND_FREE}}
            rows_k, rows_c = [], []
            for sec_j, shear_j, damping_j in ((pe["section"], pe["shear_model"], pe["damping"]),
                                              (sec, shear_model, lt.damping)):
                cj = _sde_coefficients(sec_j, dxm, shear_j)
                rows_k.append(cj)
                rows_c.append(_sde_damping(damping_j, sec_j, dxm, cj, np.array([pe["mass"], masses[0]]),
                                           np.vstack([pe["inertia"], inertia[0]]), free_ends)[0])
            stiffness_j, damping_j = joint_rows(line.end_a.connection, rows_k, rows_c)
            if hinge >= 0:
                stiffness_j[hinge] = 0.0
                damping_j[hinge] = 0.0
            motor = getattr(line.end_a, "motor", None)
            if motor is not None:
                # a servo motor about the joint's axis (rfesim.loads.drives): the join must be coaxial
                cosang = float(pe["frame"][:, 0] @ frames[0][:, 0])
                if cosang < 1.0 - 1e-9:
                    problems_motor = [(f"lines.{lname}.end_a.direction",
                                       f"a motor turns the join about its axis: end A of '{lname}' must continue "
                                       f"the direction of end B of '{parent}' (they are "
                                       f"{math.degrees(math.acos(max(-1.0, min(1.0, cosang)))):.3g} deg apart)")]
                    raise ScenarioError(problems_motor)
                stiffness_j[3] = motor.stiffness
                damping_j[3] = motor.damping
                motors.append({"sde": nsde_total, "stiffness": motor.stiffness, "damping": motor.damping,
                               "max_torque": motor.max_torque,
                               "table": [[r[0], math.radians(r[1])] for r in motor.angle], "name": motor.name})
            append_sde(sde, plastic_rows, plastic_flags, tension_flags, pe["rfe"], n_total,
                       [0.5 * pe["length"], 0.0, 0.0], [-0.5 * lengths[0], 0.0, 0.0], stiffness_j, damping_j, dxm)
            rest = pe["frame"].T @ frames[0]
            join_infos.append(JoinInfo(parent=parent, child=lname, connection=line.end_a.connection, sde=nsde_total,
                                       parent_rfe=pe["rfe"], child_rfe=n_total, rest=rest, hinge=hinge))
            if line.end_a.drives:
                join_drives.append((nsde_total, pe["frame"], list(line.end_a.drives)))
            nsde_total += 1
        # --- SDEs
        coef = _sde_coefficients(sec, dx, shear_model)
        material = getattr(lt, "material", None)
        if material is not None and getattr(material, "kind", "elastic") == "elastoplastic":
            from ..materials.sde_plastic import plastic_params
            prow = plastic_params(material, sec).params
            plastic_rows.extend([prow] * nseg)
            plastic_flags.extend([1] * nseg)
        else:
            plastic_rows.extend([np.zeros(2)] * nseg)
            plastic_flags.extend([0] * nseg)
        damp = _sde_damping(lt.damping, sec, dx, coef, masses, inertia, ends)
        for j in range(nseg):
            sde["left"].append(n_total + j)
            sde["right"].append(n_total + j + 1)
            sde["arm_left"].append([0.5 * lengths[j], 0.0, 0.0])
            sde["arm_right"].append([-0.5 * lengths[j + 1], 0.0, 0.0])
            sde["stiffness"].append(coef)
            sde["damping"].append(damp[j])
            sde["length"].append(dx)
        # --- point loads
        for k, ld in enumerate(line.loads):
            if ld.at == "end_a":
                i, arm = 0, [-0.5 * lengths[0], 0.0, 0.0]
            elif ld.at == "end_b":
                i, arm = nseg, [0.5 * lengths[-1], 0.0, 0.0]
            else:
                s = float(ld.at)
                i = int(np.clip(np.searchsorted(s_hi, s, side="left"), 0, nseg))
                arm = [s - 0.5 * (s_lo[i] + s_hi[i]), 0.0, 0.0]
            loads["rfe"].append(n_total + i)
            loads["arm"].append(arm)
            loads["force"].append(ld.force)
            loads["moment"].append(ld.moment)
            loads["local"].append(1 if ld.frame == "local" else 0)
        # --- initial coordinates
        q0_blocks.append(np.zeros((nseg + 1, 6)))
        X0_blocks.append(centres)
        R0_blocks.append(frames)
        lines.append(LineInfo(name=lname, rfe_start=n_total, rfe_stop=n_total + nseg + 1, sde_start=nsde_total,
                              sde_stop=nsde_total + nseg, length=L, elements=nseg, dx=dx, section=sec,
                              shear_model=shear_model, end_a=line.end_a, end_b=line.end_b, chord=end_distance,
                              tension_estimate=tension, seabed_fold=_seabed_fold(line, sec, sc, A, B, held),
                              held_length=held[0] if held is not None else 0.0,
                              seabed_u=_seabed_u(line, sec, sc, A, B) if held is None else None))
        end_b_of[lname] = dict(rfe=n_total + nseg, point=centres[-1] + 0.5 * lengths[-1] * frames[-1][:, 0],
                               frame=frames[-1].copy(), dx=dx, length=lengths[-1], section=sec,
                               shear_model=shear_model, damping=lt.damping, mass=masses[-1], inertia=inertia[-1])
        n_total += nseg + 1
        nsde_total += nseg
        tension_flags.extend([1 if getattr(lt, "tension_only", False) else 0] * nseg)
        if target is not None:
            closures.append((lname, target))
        if body_pose_b is not None:
            body_infos.append(append_body(sc, line.end_b.attach, len(body_infos), line, body_pose_b, coef,
                                          lengths[-1], masses[-1], inertia[-1], n_total, nsde_total, rfe, sde,
                                          plastic_rows, plastic_flags, tension_flags, q0_blocks, X0_blocks,
                                          R0_blocks, (KIND_FREE,)))
            n_total += 1
            nsde_total += 1

    # closing joins (rfesim.model.joins): one SDE each, after all the lines' own
    closure_infos: list[JoinInfo] = []
    for lname, target in closures:
        if target not in end_b_of:
            continue                       # the target failed (its problem is reported)
        pe, ce = end_b_of[target], end_b_of[lname]
        gap = float(np.linalg.norm(ce["point"] - pe["point"]))
        if gap > 1e-6:
            problems.append((f"lines.{lname}.end_b.position", f"end B of '{lname}' starts {gap:.6g} m from end B of "
                                                              f"line '{target}' it is joined to: they must agree "
                                                              f"within 1e-6 m"))
            continue
        connection = sc.lines[lname].end_b.connection
        dxm = 0.5 * (pe["dx"] + ce["dx"])
        free_ends = {"end_a": {"kind": KIND_FREE}, "end_b": {"kind": KIND_FREE}}
        rows_k, rows_c = [], []
        for e in (pe, ce):
            cj = _sde_coefficients(e["section"], dxm, e["shear_model"])
            rows_k.append(cj)
            rows_c.append(_sde_damping(e["damping"], e["section"], dxm, cj, np.array([pe["mass"], ce["mass"]]),
                                       np.vstack([pe["inertia"], ce["inertia"]]), free_ends)[0])
        stiffness_c, damping_c = joint_rows(connection, rows_k, rows_c)
        append_sde(sde, plastic_rows, plastic_flags, tension_flags, pe["rfe"], ce["rfe"],
                   [0.5 * pe["length"], 0.0, 0.0], [0.5 * ce["length"], 0.0, 0.0], stiffness_c, damping_c, dxm)
        closure_infos.append(JoinInfo(parent=target, child=lname, connection=connection, sde=nsde_total,
                                      parent_rfe=pe["rfe"], child_rfe=ce["rfe"], rest=pe["frame"].T @ ce["frame"]))
        nsde_total += 1

    if problems:
        raise ScenarioError(problems)
    if n_total == 0:
        raise ScenarioError([NOTHING_TO_SIMULATE])

    f = lambda key, shape, dt=float: (np.asarray(rfe[key], dtype=dt).reshape(shape))  # noqa: E731
    n = n_total
    has_water = water is not None and (any(li.section.outer_diameter > 0 for li in lines) or bool(body_infos))
    sea = sea_spec(env)
    sea_still = sea._replace(has_waves=False, amplitude=sea.amplitude[:0].copy(), velocity=sea.velocity[:0].copy(),
                             omega=sea.omega[:0].copy(),
                             wavenumber=sea.wavenumber[:0].copy(), phase=sea.phase[:0].copy(),
                             cos_direction=sea.cos_direction[:0].copy(), sin_direction=sea.sin_direction[:0].copy(),
                             ramp=0.0)
    # waves act through Froude-Krylov inertia even without drag or added mass
    has_morison = has_water and (sea.has_waves or any(
        li.section.drag_normal > 0 or li.section.drag_axial > 0 or li.section.added_mass_normal > 0
        or li.section.added_mass_axial > 0 for li in lines))
    if seabed is not None:
        ps, pz, pdir = seabed.profile_table(seabed_z)
        bed_s, bed_z = np.asarray(ps, float), np.asarray(pz, float)
        bed_dir = np.array([math.cos(math.radians(pdir)), math.sin(math.radians(pdir))])
    else:
        bed_s, bed_z, bed_dir = np.array([-1.0, 1.0]), np.array([-1e30, -1e30]), np.array([1.0, 0.0])
    if any(plastic_flags):
        from ..materials.sde_plastic import pack_params
        plastic_params_arr, hist0 = pack_params(plastic_rows)
        plastic_width = hist0.shape[1]
    else:
        plastic_params_arr, plastic_width = np.zeros((len(plastic_flags), 2)), 1
    roller_arrays, support_infos = compile_supports(sc, attachment_names, lines)
    tens_arrays, tens_infos = compile_tensioners(sc, attachment_names, lines)
    reel_arrays, reel_infos = compile_reels(sc, attachment_names, lines)
    join_arrays = {}
    if join_infos or closure_infos:                 # rest rotations and drives of the joints (model.joins)
        join_arrays = joint_arrays(nsde_total, {ji.sde: ji.rest for ji in join_infos + closure_infos},
                                   drive_rows(join_drives))
    if closure_infos:
        join_arrays["cl_sde"] = np.array([ci.sde for ci in closure_infos], np.int64)
        join_arrays["has_closures"] = True
    row = 0
    for ji in join_infos:
        count = sum(len(d) for s, _, d in join_drives if s == ji.sde)
        ji.drive_start, ji.drive_stop = row, row + count
        ji.drive_names = [d.name for s, _, ds in join_drives if s == ji.sde for d in ds]
        row += count
        for j, m in enumerate(motors):
            if m["sde"] == ji.sde:
                ji.motor = j
                ji.drive_names.append(m["name"])
    if motors:
        from .arrays import motor_arrays
        join_arrays.update(motor_arrays(motors))
    km = KernelModel(
        **join_arrays,
        **roller_arrays,
        **tens_arrays,
        has_tensioners=bool(tens_arrays["tens_att"].shape[0] > 0),
        **reel_arrays,
        has_reels=bool(reel_arrays["reel_att"].shape[0] > 0),
        has_rollers=bool(roller_arrays["roller_attach"].shape[0] > 0),
        has_roller_friction=bool(roller_arrays["roller_attach"].shape[0] > 0
                                 and float(roller_arrays["roller_mu"].max()) > 0.0),
        rfe_mass=f("mass", (n,)), rfe_inertia=f("inertia", (n, 3)), rfe_length=f("length", (n,)),
        rfe_kind=f("kind", (n,), np.int64), rfe_attach=f("attach", (n,), np.int64),
        rfe_attach_offset=f("attach_offset", (n, 3)), rfe_pin_arm=f("pin_arm", (n, 3)),
        rfe_clamp_R=f("clamp_R", (n, 3, 3)), rfe_diameter=f("diameter", (n,)), rfe_disp_area=f("disp_area", (n,)),
        rfe_cdn=f("cdn", (n,)), rfe_cdt=f("cdt", (n,)), rfe_can=f("can", (n,)), rfe_cat=f("cat", (n,)),
        rfe_contact_radius=f("contact_radius", (n,)), rfe_seabed_c=f("seabed_c", (n,)),
        rfe_seabed_ct=f("seabed_ct", (n,)),
        sde_left=np.asarray(sde["left"], np.int64), sde_right=np.asarray(sde["right"], np.int64),
        sde_arm_left=np.asarray(sde["arm_left"], float).reshape(-1, 3),
        sde_arm_right=np.asarray(sde["arm_right"], float).reshape(-1, 3),
        sde_stiffness=np.asarray(sde["stiffness"], float).reshape(-1, 6),
        sde_damping=np.asarray(sde["damping"], float).reshape(-1, 6),
        sde_length=np.asarray(sde["length"], float),
        load_rfe=np.asarray(loads["rfe"], np.int64), load_arm=np.asarray(loads["arm"], float).reshape(-1, 3),
        load_force=np.asarray(loads["force"], float).reshape(-1, 3),
        load_moment=np.asarray(loads["moment"], float).reshape(-1, 3),
        load_local=np.asarray(loads["local"], np.int64),
        gravity=float(env.gravity),
        water_density=float(water.density) if water is not None else 0.0,
        water_level=float(water.surface_level) if water is not None else 0.0,
        seabed_z=float(seabed_z) if seabed_z is not None else -1e30,
        seabed_k=float(seabed.normal_stiffness) if seabed is not None else 0.0,
        bed_s=bed_s, bed_z=bed_z, bed_dir=bed_dir,
        seabed_mu=np.array([seabed.mu_axial, seabed.mu_lateral] if seabed is not None else [0.0, 0.0]),
        seabed_kt=stick_stiffness(seabed),
        has_water=bool(has_water), has_morison=bool(has_morison), has_seabed=seabed is not None,
        has_loads=len(loads["rfe"]) > 0,
        has_friction=seabed is not None and (seabed.mu_axial > 0.0 or seabed.mu_lateral > 0.0),
        sde_plastic=np.asarray(plastic_flags, np.int64), plastic_params=plastic_params_arr,
        has_plastic=bool(any(plastic_flags)),
        has_sea=bool(has_water and (sea.has_waves or sea.has_current)), sea=sea, sea_still=sea_still,
        sde_tension_only=np.asarray(tension_flags, np.int64), has_tension_only=bool(any(tension_flags)),
        **body_arrays(sc, body_infos),
        **deck_arrays(sc, body_infos, attachment_names),
    )
    from .arrays import complete_joint_arrays
    km = complete_joint_arrays(km)          # sde_has_rest: which SDEs the kernels give a rest rotation
    dof_mask = np.ones((n, 6), dtype=bool)
    dof_mask[km.rfe_kind == KIND_PINNED, :3] = False
    dof_mask[km.rfe_kind == KIND_CLAMPED, :] = False
    q0 = np.vstack(q0_blocks)
    ref = Reference(R=np.concatenate(R0_blocks, axis=0), X=np.concatenate(X0_blocks, axis=0))
    initial = State(t=0.0, q=q0, qd=np.zeros((n, 6)), qdd=np.zeros((n, 6)), ref=ref, aux=np.zeros((n, 6)))
    beach = _plane_above_water(sc, initial.positions(), lines)
    if beach is not None:
        raise ScenarioError([beach])
    model = Model(scenario=sc, km=km, lines=lines, attachment_names=attachment_names, motions=motions,
                  plastic_history_width=int(plastic_width), supports=support_infos, tensioners=tens_infos,
                  dof_mask=dof_mask, initial=initial, line_index={li.name: k for k, li in enumerate(lines)},
                  bodies=body_infos, reels=reel_infos, joins=join_infos, closures=closure_infos)
    if tens_infos:
        from .supports import table_payout_problems
        problems = table_payout_problems(model)     # a payout table beyond the line behind the track
        if problems:
            raise ScenarioError(problems)
    if reel_infos and km.has_plastic:
        model.initial_plastic_history = reeled_history(sc, lines, ref.R, km.plastic_params, int(plastic_width))
    if getattr(sc, "winches", None):
        from .winches import compile_winches
        model.winches = compile_winches(sc, model)
    if km.has_deck:
        from .bodies import deck_anchors
        model.km = model.km._replace(body_deck_anchor=deck_anchors(model, float(env.gravity), sc))
    if getattr(sc, "tuggers", None):
        from .tuggers import tugger_arrays
        arrays, model.tuggers = tugger_arrays(sc, model)
        model.km = model.km._replace(**arrays)
    if any(getattr(ln.end_a, "reeving", None) is not None for ln in (sc.lines or {}).values()):
        from .reeving import reeving_arrays
        model.km = model.km._replace(**reeving_arrays(sc, model))
    return model


def _supported_curve(A: np.ndarray, B: np.ndarray | None, L: float, rest: np.ndarray, sec: Section, sc) -> _Curve:
    """Initial shape of a line over rollers: A, the resting points on the rollers, then
    the catenary to end B with the remaining length (rfesim.model.supports)."""
    s, X = supported_start(A, B, L, rest, _catenary_tail(sec, sc))
    return _Curve(s, X)


def _catenary_tail(sec: Section, sc):
    """tail(G, B, remaining) -> (s, X): the catenary (or the straight line when taut) from a
    support's last point G to end B with the remaining length."""
    env = sc.environment
    seabed = env.seabed

    def tail(G, Bp, remaining):
        d = float(np.linalg.norm(Bp - G))
        if d >= remaining * (1.0 - 1e-9):
            c = _straight(G, Bp - G, remaining, stretch=d / remaining)
        else:
            low = G if G[2] <= Bp[2] else Bp
            c = _catenary_curve(G, Bp, remaining, _submerged_weight(sec, sc), sec.EA,
                                env.seabed_z_at(float(low[0]), float(low[1])), 0.5 * sec.outer_diameter,
                                seabed.normal_stiffness if seabed else 0.0)
            if c is None:
                c = _sagged_curve(G, Bp, remaining)
        return c.s, c.X

    return tail


def _with_leads(curve: _Curve, A: np.ndarray, B: np.ndarray, lead_a: float, lead_b: float) -> _Curve:
    """``curve`` (between the inner ends of clamped end RFEs) with the straight leads from end
    A and to end B along the clamps' directions prepended and appended (a lead of 0: none).
    The strain of a lead is the curve's at its end."""
    s = curve.s + lead_a
    X = curve.X
    if lead_a > 0.0:
        s, X = np.concatenate([[0.0], s]), np.vstack([A, X])
    if lead_b > 0.0:
        s, X = np.concatenate([s, [s[-1] + lead_b]]), np.vstack([X, B])
    strain = None
    if curve.strain is not None:
        inner, length = curve.strain, float(curve.s[-1])
        strain = (lambda arc: inner(np.clip(np.asarray(arc, float) - lead_a, 0.0, length)))
    return _Curve(s, X, strain)


def _floating_curve(P: np.ndarray, L: float, top: float) -> _Curve:
    """A buoyant line from the point P under water: straight up, and along global x at the
    height ``top`` (the surface less its radius) for the length that does not fit below it
    (a start shape; statics floats it where its buoyancy carries it)."""
    rise = min(L, max(top - float(P[2]), 0.0))
    pts, s = [P], [0.0]
    if rise > 0.0:
        pts.append(P + np.array([0.0, 0.0, rise]))
        s.append(rise)
    if L - rise > 0.0:
        pts.append(pts[-1] + np.array([L - rise, 0.0, 0.0]))
        s.append(L)
    return _Curve(np.array(s), np.vstack(pts))


def _sagged_curve(A: np.ndarray, B: np.ndarray, L: float, up: bool = False) -> _Curve:
    """A parabola-like sag below the chord (above it for a buoyant line, ``up``) with the
    right arc length (fallback start)."""
    chord = B - A
    d = np.linalg.norm(chord)
    u = np.linspace(0.0, 1.0, 201)
    sag_dir = np.array([0.0, 0.0, 1.0 if up else -1.0])
    if d > 1e-12 * L:
        sag_dir = sag_dir - chord * (sag_dir @ chord) / (d * d)
    if np.linalg.norm(sag_dir) < 1e-9:
        sag_dir = np.cross(chord, [0.0, 1.0, 0.0])
    sag_dir /= np.linalg.norm(sag_dir)
    lo, hi = 0.0, L
    for _ in range(80):     # bisection on the sag depth for the arc length
        h = 0.5 * (lo + hi)
        X = A[None, :] + u[:, None] * chord[None, :] + (4 * h * u * (1 - u))[:, None] * sag_dir[None, :]
        arc = np.linalg.norm(np.diff(X, axis=0), axis=1).sum()
        if arc > L:
            hi = h
        else:
            lo = h
    seg = np.linalg.norm(np.diff(X, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    s *= L / s[-1]
    return _Curve(s, X)


def _sde_damping(spec, sec: Section, dx: float, coef: np.ndarray, masses: np.ndarray, inertia: np.ndarray,
                 ends: dict) -> np.ndarray:
    """Kelvin-Voigt damping of each SDE (nseg, 6)."""
    nseg = masses.shape[0] - 1
    out = np.zeros((nseg, 6))
    if spec is None:
        return out
    if spec.axial_ratio is not None or spec.bending_ratio is not None:
        za = spec.axial_ratio or 0.0
        zb = spec.bending_ratio or 0.0
        for j in range(nseg):
            ml, mr = masses[j], masses[j + 1]
            if j == 0 and ends["end_a"]["kind"] == KIND_CLAMPED:
                ml = np.inf
            if j == nseg - 1 and ends["end_b"]["kind"] == KIND_CLAMPED:
                mr = np.inf
            mred = _reduced(ml, mr)
            for k in range(3):
                out[j, k] = 2.0 * za * math.sqrt(coef[k] * mred)
            for k, ax in ((3, 0), (4, 1), (5, 2)):
                jl, jr = inertia[j, ax], inertia[j + 1, ax]
                if np.isinf(ml):
                    jl = np.inf
                if np.isinf(mr):
                    jr = np.inf
                out[j, k] = 2.0 * zb * math.sqrt(coef[k] * _reduced(jl, jr))
        return out
    vals = [spec.axial or 0.0, spec.shear or 0.0, spec.shear or 0.0, spec.torsion or 0.0, spec.bending or 0.0,
            spec.bending or 0.0]
    out[:] = np.asarray(vals) / dx
    return out


def _reduced(a: float, b: float) -> float:
    if np.isinf(a):
        return b
    if np.isinf(b):
        return a
    return a * b / (a + b)
