"""Winches: payout of a rope line by uniform growth of its elements, and the winch controllers.

A winch pays out (D > 0) or hauls in (D < 0) the line it acts on. The line keeps its n
elements; every element length becomes Delta(t) = (L0 + D(t)) / n (an ALE-like mesh whose
nodes stay at fixed fractions of the suspended length, docs/theory.md "Winches and rope
payout"). Before every time step ``set_payout`` rewrites, in place, every model array that
depends on Delta for the line's RFEs and SDEs:

* RFE length, mass (mu Delta), inertia (polar and rotary parts ~ Delta, the m Delta^2/12
  part ~ Delta^3), the pin arm of an attached end RFE, the arms of point loads on the line;
* SDE length, arms, stiffness (eq. 8.88: EA/Delta, GA/Delta, GJ/Delta, EI/Delta; eq. 8.89:
  12 EI/Delta^3 for shear) and damping (damping ratios: 2 zeta sqrt(c m_red) with the
  current c and m_red; explicit coefficients: / Delta);
* the arm on the line's side of any other SDE touching the line (a body connection, a
  joint to a parent line), and the solver's length scale of the line's RFEs.

Growing arms move the SDE ends apart from the RFE centres with no velocity of their own, so
the Kelvin-Voigt damping (eq. 8.86) would read the payout rate as a deformation rate and
pull with c_x * (rate the arms grow). That force is cancelled exactly by lengthening the
SDE's rest gap by c_x * rate / k_x (``damping_offset``). A shock absorber replaces the
first SDE of the line (at the winch) by the series spring k_r k_sa / (k_r + k_sa) with the
absorber's damping.

With ``payout_inertia`` the rope's free elements carry follower loads -m_i (1 - xi_i) d2D/dt2
along them: the inertia of the material, which runs at dD/dt while the node at xi moves at
xi dD/dt (docs/theory.md).

The controllers (one per winch) compute D(t_{n+1}) before each step from their mode (speed
table, drum dynamics, constant tension) plus the heave compensation, and read the rope
tension (first SDE of the line) and the end-A point after the step (explicit coupling).
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..scenario.winches import drum_radius, drum_rope_inertia
from .arrays import KIND_CLAMPED, KIND_FREE

MIN_FRACTION = 0.05      # haul-in stops (SolverError) below this fraction of the initial length

log = logging.getLogger(__name__)


@dataclass
class WinchInfo:
    """Where a winch's line sits in the model arrays, and the arrays at zero payout."""

    name: str
    line: str
    index: int
    rfe_lo: int
    rfe_hi: int
    sde_lo: int
    sde_hi: int
    length0: float                  # m, line length at zero payout
    mass_per_length: float          # kg/m
    stored: float                   # m on the drum at the start
    len0: np.ndarray                # (nr,) m, RFE lengths
    mass0: np.ndarray               # (nr,) kg
    inertia_lin0: np.ndarray        # (nr, 3) kg*m^2, part ~ Delta
    inertia_cub0: np.ndarray        # (nr, 3) kg*m^2, part ~ Delta^3
    pin_rfe: np.ndarray             # (np,) int64, attached end RFEs of the line
    pin_arm0: np.ndarray            # (np, 3) m
    arm_left0: np.ndarray           # (ns, 3) m
    arm_right0: np.ndarray          # (ns, 3) m
    stiffness0: np.ndarray          # (ns, 6)
    stiffness_power: np.ndarray     # (6,) stiffness ~ Delta^-power
    damping0: np.ndarray            # (ns, 6)
    damping_form: int               # 0 none, 1 ratios (2 zeta sqrt(c m_red)), 2 explicit (/ Delta)
    mred0: np.ndarray               # (ns, 6) reduced mass / inertia at zero payout (form 1)
    ext_sde: np.ndarray             # (ne,) int64, other SDEs touching the line
    ext_side: np.ndarray            # (ne,) int64, 0: their left RFE is on the line, 1: the right one
    ext_arm0: np.ndarray            # (ne, 3) m, that arm at zero payout
    load_idx: np.ndarray            # (nl,) int64, point loads on the line
    load_arm0: np.ndarray           # (nl, 3) m
    absorber_k: float = 0.0         # N/m, shock absorber in series with the first SDE (0: none)
    absorber_c: float = 0.0         # N*s/m
    material_idx: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # (nm,) point loads
    material_rfe: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))   # (nm,) their RFEs
    material_lag: np.ndarray = field(default_factory=lambda: np.zeros(0))             # (nm,) 1 - xi_i
    spec: object = None             # the scenario Winch
    payout: float = 0.0             # m, current payout (as last set)
    speed: float = 0.0              # m/s
    extra: dict = field(default_factory=dict)
    origins: dict = field(default_factory=dict)  # the scenario's template origins (rfesim.scenario.pipelay.Origin)

    def user_path(self, rest: str) -> str:
        """The dotted path of the winch's field ``rest`` as the user wrote it: a crane
        template's winch (``winches.<crane>_winch``) is its ``cranes.<crane>.winch``."""
        from ..scenario.pipelay import template_path
        return template_path(f"winches.{self.name}.{rest}", self.origins)

    @property
    def elements(self) -> int:
        return self.sde_hi - self.sde_lo

    @property
    def first_sde(self) -> int:
        return self.sde_lo


def _reduced(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        out = a * b / (a + b)
    out = np.where(np.isinf(a), b, out)
    return np.where(np.isinf(b), a, out)


def reduced_masses(km, lo: int, hi: int) -> np.ndarray:
    """(ns, 6) reduced masses (3 columns) and inertias (torsion, bend y, bend z) of the SDEs
    lo..hi with clamped RFEs counting as infinitely heavy (as rfesim.model.compile._sde_damping)."""
    a = km.sde_left[lo:hi]
    b = km.sde_right[lo:hi]
    m = km.rfe_mass.astype(float).copy()
    inertia = km.rfe_inertia.astype(float).copy()
    clamped = km.rfe_kind == KIND_CLAMPED
    m[clamped] = np.inf
    inertia[clamped] = np.inf
    out = np.empty((hi - lo, 6))
    out[:, :3] = _reduced(m[a], m[b])[:, None]
    out[:, 3:] = _reduced(inertia[a], inertia[b])
    return out


def compile_winches(sc, model) -> list[WinchInfo]:
    """WinchInfo of every winch (the arrays at zero payout), with the shock absorbers applied."""
    km = model.km
    infos = []
    for k, (name, w) in enumerate(sc.winches.items()):
        li = model.line(w.line)
        lo, hi, slo, shi = li.rfe_start, li.rfe_stop, li.sde_start, li.sde_stop
        lengths = km.rfe_length[lo:hi].copy()
        mass = km.rfe_mass[lo:hi].copy()
        cub = np.zeros((hi - lo, 3))
        cub[:, 1] = cub[:, 2] = mass * lengths ** 2 / 12.0
        lin = km.rfe_inertia[lo:hi] - cub
        pin = np.array([i for i in range(lo, hi) if km.rfe_kind[i] != KIND_FREE], np.int64)
        power = np.ones(6)
        if li.shear_model == "fem":
            power[1] = power[2] = 3.0
        lt = sc.line_types[sc.lines[w.line].type]
        spec = lt.damping
        form = 0
        if spec is not None:
            form = 1 if (spec.axial_ratio is not None or spec.bending_ratio is not None) else 2
        ext_sde, ext_side, ext_arm = [], [], []
        for s in range(km.sde_left.shape[0]):
            if slo <= s < shi:
                continue
            if lo <= km.sde_left[s] < hi:
                ext_sde.append(s), ext_side.append(0), ext_arm.append(km.sde_arm_left[s].copy())
            elif lo <= km.sde_right[s] < hi:
                ext_sde.append(s), ext_side.append(1), ext_arm.append(km.sde_arm_right[s].copy())
        loads = np.nonzero((km.load_rfe >= lo) & (km.load_rfe < hi))[0].astype(np.int64)
        sa = w.shock_absorber
        info = WinchInfo(
            name=name, line=w.line, index=k, rfe_lo=lo, rfe_hi=hi, sde_lo=slo, sde_hi=shi, length0=li.length,
            mass_per_length=li.section.mass_per_length, stored=float(w.stored), len0=lengths, mass0=mass,
            inertia_lin0=lin, inertia_cub0=cub, pin_rfe=pin, pin_arm0=km.rfe_pin_arm[pin].copy(),
            arm_left0=km.sde_arm_left[slo:shi].copy(), arm_right0=km.sde_arm_right[slo:shi].copy(),
            stiffness0=km.sde_stiffness[slo:shi].copy(), stiffness_power=power,
            damping0=km.sde_damping[slo:shi].copy(), damping_form=form, mred0=reduced_masses(km, slo, shi),
            ext_sde=np.asarray(ext_sde, np.int64), ext_side=np.asarray(ext_side, np.int64),
            ext_arm0=np.asarray(ext_arm, float).reshape(-1, 3), load_idx=loads, load_arm0=km.load_arm[loads].copy(),
            absorber_k=float(sa.stiffness) if sa is not None else 0.0,
            absorber_c=float(sa.damping) if sa is not None else 0.0, spec=w,
            origins=dict(getattr(sc, "_origins", None) or {}))
        if w.payout_inertia:
            # follower loads along the free elements (x axis: toward end B) for the material's
            # acceleration relative to the nodes (set_payout's accel; zero until a payout speeds up)
            rfes = np.array([i for i in range(lo, hi) if km.rfe_kind[i] == KIND_FREE], np.int64)
            first = km.load_rfe.shape[0]
            info.material_idx = np.arange(first, first + rfes.size, dtype=np.int64)
            info.material_rfe = rfes
            centre = np.cumsum(lengths) - 0.5 * lengths          # the end elements may be half ones
            info.material_lag = 1.0 - centre[rfes - lo] / lengths.sum()
            zeros = np.zeros((rfes.size, 3))
            model.km = km = model.km._replace(
                load_rfe=np.concatenate([km.load_rfe, rfes]), load_arm=np.concatenate([km.load_arm, zeros]),
                load_force=np.concatenate([km.load_force, zeros]),
                load_moment=np.concatenate([km.load_moment, zeros]),
                load_local=np.concatenate([km.load_local, np.ones(rfes.size, np.int64)]),
                has_loads=bool(km.has_loads or rfes.size > 0))
        set_payout(km, info, 0.0, 0.0)
        infos.append(info)
    return infos


def set_payout(km, info: WinchInfo, payout: float, speed: float, length_scale: np.ndarray | None = None,
               accel: float | None = None) -> None:
    """Rewrite in place every array of ``km`` that depends on the element length of the
    winch's line for the payout D (m) and payout speed (m/s) (see the module text); with
    ``accel`` (m/s^2, the payout's acceleration over the step) the follower loads of the
    material's inertia, -m_i (1 - xi_i) accel along each free element (``payout_inertia``)."""
    ratio = (info.length0 + payout) / info.length0
    rate = speed / info.length0                     # d(ratio)/dt
    lo, hi, slo, shi = info.rfe_lo, info.rfe_hi, info.sde_lo, info.sde_hi
    km.rfe_length[lo:hi] = info.len0 * ratio
    km.rfe_mass[lo:hi] = info.mass0 * ratio
    km.rfe_inertia[lo:hi] = info.inertia_lin0 * ratio + info.inertia_cub0 * ratio ** 3
    if info.pin_rfe.size:
        km.rfe_pin_arm[info.pin_rfe] = info.pin_arm0 * ratio
    if info.load_idx.size:
        km.load_arm[info.load_idx] = info.load_arm0 * ratio
    if length_scale is not None:
        length_scale[lo:hi] = km.rfe_length[lo:hi]
    km.sde_length[slo:shi] = (info.length0 + payout) / info.elements
    stiffness = info.stiffness0 / ratio ** info.stiffness_power[None, :]
    if info.damping_form == 1:
        mred = reduced_masses(km, slo, shi)
        with np.errstate(divide="ignore", invalid="ignore"):
            factor = np.sqrt(stiffness / info.stiffness0 * mred / info.mred0)
        damping = info.damping0 * np.where(np.isfinite(factor), factor, 0.0)
    elif info.damping_form == 2:
        damping = info.damping0 / ratio
    else:
        damping = info.damping0.copy()
    if info.absorber_k > 0.0:
        kr = stiffness[0, 0]
        stiffness[0, 0] = kr * info.absorber_k / (kr + info.absorber_k)
        damping[0, 0] = info.absorber_c
    km.sde_stiffness[slo:shi] = stiffness
    km.sde_damping[slo:shi] = damping
    # arms grow with the elements; the rest gap grows by c_x rate / k_x more (damping_offset)
    grow = (np.abs(info.arm_left0[:, 0]) + np.abs(info.arm_right0[:, 0])) * rate
    offset = damping_offset(damping[:, 0], stiffness[:, 0], grow)
    km.sde_arm_left[slo:shi] = info.arm_left0 * ratio
    km.sde_arm_left[slo:shi, 0] += offset
    km.sde_arm_right[slo:shi] = info.arm_right0 * ratio
    for j in range(info.ext_sde.shape[0]):
        s = info.ext_sde[j]
        arm0 = info.ext_arm0[j]
        size = float(np.linalg.norm(arm0))
        extra = 0.0
        if size > 0.0 and km.sde_stiffness[s, 0] > 0.0:
            extra = km.sde_damping[s, 0] * rate / km.sde_stiffness[s, 0]
        if info.ext_side[j] == 0:
            km.sde_arm_left[s] = arm0 * (ratio + extra)
        else:
            km.sde_arm_right[s] = arm0 * (ratio + extra)
    if accel is not None and info.material_idx.size:
        km.load_force[info.material_idx, 0] = -km.rfe_mass[info.material_rfe] * info.material_lag * accel
    info.payout = payout
    info.speed = speed


def damping_offset(damping: np.ndarray, stiffness: np.ndarray, grow_rate: np.ndarray) -> np.ndarray:
    """Rest-gap lengthening (m) that cancels the damping force c * grow_rate of arms growing
    at grow_rate (m/s): c * grow_rate / k (0 where k = 0)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        out = np.where(stiffness > 0.0, damping * grow_rate / stiffness, 0.0)
    return out


# ----------------------------------------------------------------------------- controllers

def _table(rows, t: float) -> float:
    ts = [r[0] for r in rows]
    vs = [r[1] for r in rows]
    return float(np.interp(t, ts, vs))


class WinchController:
    """The winch's payout in time: before_step sets D(t_{n+1}) into the model arrays,
    after_step reads the tension and the end-A point of the converged step.

    Heave compensation (``HeaveCompensation``): a PID on the error zeta - D_c, its speed
    clipped to max_speed, with anti-windup by conditional integration: while the speed is
    held at the limit, an error that would push it further into the limit is not integrated
    (docs/theory.md, 'Winches and rope payout')."""

    def __init__(self, info: WinchInfo, system):
        self.info = info
        self.system = system
        self.name = info.name
        self.spec = info.spec
        self.mode = info.spec.mode
        self.hc = info.spec.heave_compensation
        # state (saved and restored around a retried step)
        self.t = 0.0
        self.D = 0.0            # m, total payout
        self.v = 0.0            # m/s, total payout speed
        self.D_mode = 0.0       # m, payout of the mode (drum, tension)
        self.v_mode = 0.0
        self.D_c = 0.0          # m, payout of the heave compensation
        self.v_c = 0.0
        self.e_int = 0.0        # m*s, integral of the compensation error
        self.hc_sat = 0         # +1 / -1: the compensation speed of the step is held at +- max_speed
        self.e_prev = 0.0       # m, compensation error at the step before the last
        self.e_cur = 0.0        # m, compensation error at the last accepted step
        self.zeta = 0.0         # m, vertical motion of the end-A point since the start
        self.zeta_dot = 0.0
        self.zeta_dot_prev = 0.0
        self.z0 = None
        self.tension = 0.0
        self.accel = 0.0        # m/s^2, drum payout acceleration (drum mode)
        self.chord_rate = 0.0   # m/s, rate of the rope's chord (end A to end B) at the last accepted step
        self.chord_accel = 0.0  # m/s^2, its mean second derivative over that step (_measure_chord)
        # a rope led over its sheave to a vessel point slips over the sheave as the run changes
        # (rfesim.loads.reeving.slip_arms); the slip is handed to the hanging rope's length
        # whenever it passes half the rope's first RFE (``_hand_over``)
        self.lead = _slipping_reeving(system, info.line)
        self.slipped = 0.0      # m, slip handed over (the hanging rope is that much shorter)
        # m, the slip statics left (the run's reference length is taken at the compiled start
        # positions), handed to the hanging rope at the start of the dynamics (``start``): the
        # run's reference becomes the static run and the slip starts at 0
        self.slip0 = 0.0
        self.rv_len = float(system.km.rv_len[self.lead]) if self.lead is not None else 0.0

    # ------------------------------------------------------------------ state
    _FIELDS = ("t", "D", "v", "D_mode", "v_mode", "D_c", "v_c", "e_int", "e_prev", "e_cur", "zeta", "zeta_dot",
               "zeta_dot_prev", "tension", "accel", "slipped", "slip0", "rv_len", "chord_rate", "chord_accel")

    def save(self) -> tuple:
        return tuple(getattr(self, f) for f in self._FIELDS)

    def restore(self, saved: tuple) -> None:
        for f, v in zip(self._FIELDS, saved):
            setattr(self, f, v)
        if self.lead is not None:
            self.system.km.rv_len[self.lead] = self.rv_len
        set_payout(self.system.km, self.info, self._hanging(self.D), self.v, self.system.length_scale)

    def _hanging(self, D: float) -> float:
        """The hanging rope's length change (m, the payout set_payout takes) at the winch's
        payout D: D less the slip over the sheave handed to the hanging rope (``_hand_over``;
        with the static slip ``slip0``)."""
        return D - self.slipped - self.slip0

    # ------------------------------------------------------------------ measurements
    def _end_a(self):
        """(z, vertical velocity) of the line's end-A point from the evaluated workspace."""
        ws = self.system.ws
        i = self.info.rfe_lo
        arm = ws.R[i] @ np.array([-0.5 * self.system.km.rfe_length[i], 0.0, 0.0])
        return float(ws.r[i, 2] + arm[2]), float(ws.v[i, 2] + np.cross(ws.w[i], arm)[2])

    def measure(self) -> None:
        ws = self.system.ws
        self.tension = float(ws.sigma[self.info.first_sde, 0])
        z, vz = self._end_a()
        if self.z0 is None:
            self.z0 = z
        self.zeta = z - self.z0
        self.zeta_dot_prev = self.zeta_dot
        self.zeta_dot = vz

    def start(self, state) -> None:
        """At the start of the dynamics (workspace evaluated at ``state``). A rope slipping
        over its sheave to a vessel lead first takes the slip statics left into its hanging
        length (``_hand_over``; the state is re-evaluated): the run's reference is then the
        static run, and the slip (results ``reeving_slip``) starts at 0."""
        self.t = float(state.t)
        if self.lead is not None and self._hand_over(self.system.km, state, at_start=True):
            state.qdd[:] = self.system.accelerations(state)
        self.measure()
        self.zeta_dot_prev = self.zeta_dot
        self.e_prev = self.e_cur = self.zeta - self.D_c
        if self.mode.kind == "drum":
            self.accel = self._drum_accel(self.t, self.v_mode)
            self.chord_rate = 0.0
            self._measure_chord()
            note = self.release_note()
            if note:
                log.warning("dynamics: %s", note)
        elif self.mode.kind == "speed":
            self.v_mode = speed_at(self.mode.rows, self.t)

    # ------------------------------------------------------------------ modes
    def _radius(self, D: float | None = None) -> float:
        """Drum radius (m) with D m paid out (default: at the last accepted step), the rope on
        the drum being stored - D (rfesim.scenario.winches.drum_radius)."""
        m = self.mode
        return drum_radius(m.radius, m.layers, self._on_drum(D))

    def _on_drum(self, D: float | None = None) -> float:
        """Rope (m) on the drum with D m paid out (default: at the last accepted step)."""
        return self.info.stored - (self.D if D is None else D)

    def _accel(self, v: float, h: float) -> float:
        """The payout's mean acceleration (m/s^2) over a step of h s ending at the speed v."""
        return (v - self.v) / h if h > 0.0 else 0.0

    def _inertia(self, D: float | None = None) -> float:
        """Drum inertia (kg*m^2) with D m paid out (default: at the last accepted step): the
        drum's own and, with ``rope_inertia``, the rope's on it (drum_rope_inertia). The rope
        leaves at the drum's surface speed, so the angular momentum it takes away cancels
        J' omega: J omega' = r T - tau holds with the current J."""
        m = self.mode
        if not m.rope_inertia:
            return m.inertia
        return m.inertia + drum_rope_inertia(m.radius, m.layers, self._on_drum(D), self.info.mass_per_length)

    def _spool_term(self, v: float, r: float) -> float:
        """v^2 r'(L) / r (m/s^2): with v = omega r and dL/dt = -v for the rope L on the drum,
        dv/dt = r omega' - v^2 r'(L) / r; r' = growth / (2 r) on a layered drum, else 0."""
        lay = self.mode.layers
        if lay is None:
            return 0.0
        return 0.5 * v * v * lay.growth / (r * r)

    def _drum_accel(self, t: float, v: float, T: float | None = None, D: float | None = None) -> float:
        """Payout acceleration (m/s^2) of the drum at the rope tension T (default: the last
        measured), payout speed v and payout D (default: the last accepted; it sets the
        radius of a layered drum), the brake holding it at rest below its torque."""
        m = self.mode
        r = self._radius(D)
        net = r * (self.tension if T is None else T) - _table(m.torque, t)
        if m.brake_torque > 0.0:
            if abs(v) < 1e-12:
                if abs(net) <= m.brake_torque:
                    return 0.0
                net -= math.copysign(m.brake_torque, net)
            else:
                net -= math.copysign(m.brake_torque, v)
        return r * net / self._inertia(D) - self._spool_term(v, r)

    def _rope_axial(self) -> tuple[float, float]:
        """Axial stiffness (N/m) and damping (N*s/m) of the whole rope: its SDEs (and a shock
        absorber) in series."""
        km = self.system.km
        k = km.sde_stiffness[self.info.sde_lo:self.info.sde_hi, 0]
        c = km.sde_damping[self.info.sde_lo:self.info.sde_hi, 0]
        stiff = 1.0 / float(np.sum(1.0 / k)) if np.all(k > 0.0) else 0.0
        damp = 1.0 / float(np.sum(1.0 / c)) if np.all(c > 0.0) else 0.0
        return stiff, damp

    def _measure_chord(self, h: float = 0.0) -> None:
        """Rate of the rope's chord length (end A to end B) at an accepted step (the
        workspace evaluated there) and, over a step of h s, its mean second derivative, the
        change of that rate over the step / h (0 at the start). Kept with the controller's
        state: a retried step restores them (the workspace then holds the failed attempt's
        last iterate, from which the predictor of the retry once paid out 229 m to 82 km in
        25 ms). The end point of a free end RFE rides on its arm, which grows with the payout
        (the nodes stay at fixed fractions of the rope): its velocity includes arm v / L for
        the payout speed v and the hanging length L (without it the chord rate of a rope
        paying out at v read v Delta / (2 L) short: 0.17 m/s at 7 m/s in the free-drum check,
        h k times that, 42 kN, in the predicted tension). The mean over the step, not the
        end RFEs' accelerations: light end RFEs on a stiff rope ring (a start state moved by
        1e-8 m gave them 1000 m/s^2)."""
        ws, km, info = self.system.ws, self.system.km, self.info
        hang = info.length0 + info.payout
        grow = info.speed / hang if hang > 0.0 else 0.0
        pos, vel = [], []
        for i, sign in ((info.rfe_lo, -1.0), (info.rfe_hi - 1, 1.0)):
            arm = ws.R[i][:, 0] * (0.5 * sign * float(km.rfe_length[i]))
            pos.append(ws.r[i] + arm)
            v = ws.v[i] + np.cross(ws.w[i], arm)
            if km.rfe_kind[i] == KIND_FREE:
                v = v + grow * arm          # an attached end RFE ends at its attachment point
            vel.append(v)
        chord = pos[1] - pos[0]
        size = float(np.linalg.norm(chord))
        rate = float((vel[1] - vel[0]) @ chord) / size if size > 0.0 else 0.0
        self.chord_accel = (rate - self.chord_rate) / h if h > 0.0 else 0.0
        self.chord_rate = rate

    def _stretch_rate(self) -> float:
        """Rate (m/s) at which the rope's chord lengthens beyond its payout at the last
        accepted step: the chord's rate (_measure_chord) less the payout speed."""
        return self.chord_rate - self.v_mode

    def _drum_implicit(self, t: float, h: float) -> float:
        """Drum payout acceleration (m/s^2) at t = t_{n+1}, implicit in the rope's stretch.

        With m = J / r^2 the drum's inertia at the rope, k the rope's axial stiffness and
        the drum on the average-acceleration rule D_{n+1} = D_n + h v_n + h^2/4 (a_n + a),
        v_{n+1} = v_n + h/2 (a_n + a), and c the rope's axial damping, the tension at t_{n+1}
        is T_n + h dT/dt + 2 b A_n - b (a_n + a), b = k h^2/4 + c h/2, where dT/dt is k times
        the stretch rate at t_n and A_n the chord's mean acceleration over the last step
        (_measure_chord; the far end keeps it over this one: h^2/4 (A_n + A_{n+1}) of
        stretch, h/2 (A_n + A_{n+1}) of stretch rate), so m a = T_{n+1} - tau / r gives
        a = (T_n + h dT/dt + 2 b A_n - b a_n - tau / r) / (m + b): the drum-rope mode is
        integrated implicitly (stable at any step for a taut rope; a rope whose real damping
        of that mode is small, as with damping ratios, is slackened by a release from
        statics when T0 - T_eq > T_eq, see release_note), and a drum and payload accelerating together (A = a) are
        predicted to the linearised tension (6.85 against 6.96 m/s^2 at 50 ms steps).
        Without A_n (a payload held still over the step) the prediction in the free-drum
        check at 50 ms steps was -6 m/s^2 against +7, a trial payout 9 mm off a rope
        stretched 0.6 mm, which slackened or overloaded the rope in the step's Newton
        iterations (docs/theory.md, 'Winches and rope payout'). A slack rope (T <= 0) has no
        stiffness: the drum runs free. The brake acts as in _drum_accel on that net force."""
        m = self.mode
        r = self._radius()
        meq = self._inertia() / (r * r)
        k, c = self._rope_axial() if self.tension > 0.0 else (0.0, 0.0)
        kh = 0.25 * k * h * h + 0.5 * c * h
        net = self.tension + h * k * self._stretch_rate() + 2.0 * kh * self.chord_accel - kh * self.accel \
            - _table(m.torque, t) / r - meq * self._spool_term(self.v_mode, r)
        if m.brake_torque > 0.0:
            fb = m.brake_torque / r
            if abs(self.v_mode) < 1e-12:
                if abs(net) <= fb:
                    return 0.0
                net -= math.copysign(fb, net)
            else:
                net -= math.copysign(fb, self.v_mode)
        return net / (meq + kh)

    def release(self) -> dict | None:
        """The drum's release at the start of the run in closed form, or None when nothing is
        released (the drum balanced or held by its brake, or a slack rope). From statics the
        drum starts at rest with the rope at its static tension T0 while its motor gives
        F = tau(0) / r: a step load T0 - F on the drum (m = J / r^2) against the payload
        (M = T0 / g, the mass the rope carries) through the rope (k, c: its SDEs in series).
        The two accelerate together at (T0 - F) / (m + M) with the mean tension
        T_eq = F + m (T0 - F) / (m + M), and the relative mode (mass mu = m M / (m + M),
        omega = sqrt(k / mu), damping ratio zeta = c / (2 sqrt(k mu))) swings the tension about
        T_eq from T0: T = T_eq + (T0 - T_eq) e^(-zeta omega t) (cos omega_d t - zeta / sqrt(1 -
        zeta^2) sin omega_d t) for a rope that stays taut, least near omega_d t = pi:
        T_min = T_eq - (T0 - T_eq) exp(-zeta pi / sqrt(1 - zeta^2)). Returns {m, M, k, c, T0,
        T_eq, omega, zeta, T_min, t_slack} (t_slack: s, when the undamped tension reaches 0,
        NaN if T_min >= 0)."""
        m = self.mode
        km = self.system.km
        g = float(np.linalg.norm(km.gravity)) if np.ndim(km.gravity) else abs(float(km.gravity))
        T0 = self.tension
        r = self._radius()
        F = _table(m.torque, self.t) / r
        if T0 <= 0.0 or g <= 0.0 or abs(T0 - F) * r <= m.brake_torque:
            return None
        k, c = self._rope_axial()
        if k <= 0.0:
            return None
        meq = self._inertia() / (r * r)
        M = T0 / g
        mu = meq * M / (meq + M)
        T_eq = F + meq * (T0 - F) / (meq + M)
        omega = math.sqrt(k / mu)
        zeta = c / (2.0 * math.sqrt(k * mu))
        amp = T0 - T_eq
        T_min = T_eq - amp * math.exp(-zeta * math.pi / math.sqrt(1.0 - zeta * zeta)) if zeta < 1.0 else \
            min(T_eq, T0)
        t_slack = math.acos(max(-1.0, min(1.0, -T_eq / amp))) / omega if amp > 0.0 and T_eq < amp else math.nan
        return {"m": meq, "M": M, "k": k, "c": c, "T0": T0, "T_eq": T_eq, "omega": omega, "zeta": zeta,
                "T_min": T_min, "t_slack": t_slack}

    def release_note(self) -> str:
        """A warning (empty if none) when the drum's release at the start slackens the rope
        (``release``: T_min < 0). The run's own response then snatches the rope at every
        swing of the drum-rope mode, which a step longer than a small fraction of its period
        cannot follow: the drum's coupling is implicit, but the slack light rope's Newton
        fails (docs/theory.md, 'Winches and rope payout'; audit 7 D1: a 1 t payload on a 20 m
        rope of 0.05 kg/m, EA 1e8 N, damping ratio 0.2, free drum J = 100 kg m^2, r = 0.5 m:
        the rope's series damping 60 N s/m is 0.08 % of critical for that mode)."""
        rel = self.release()
        if rel is None or not rel["T_min"] < 0.0:
            return ""
        period = 2.0 * math.pi / rel["omega"]
        pull = _table(self.mode.torque, self.t) / self._radius()
        critical = 2.0 * math.sqrt(rel["k"] * rel["m"] * rel["M"] / (rel["m"] + rel["M"])) * self._hang_length()
        return (f"winch '{self.name}' (drum) is released at the start from the rope's static tension "
                f"{rel['T0'] / 1e3:.4g} kN against a motor pull of {pull / 1e3:.4g} kN: the drum ({rel['m']:.4g} kg "
                f"at the rope) and the load ({rel['M']:.4g} kg) swing against the rope (k = {rel['k']:.4g} N/m, "
                f"period {period * 1e3:.3g} ms, damping ratio {rel['zeta']:.2g} from the rope's SDE dampers in "
                f"series; damping ratios damp the elements' own modes, not this one) about {rel['T_eq'] / 1e3:.4g} "
                f"kN, down to about {rel['T_min'] / 1e3:.4g} kN: the rope goes slack {rel['t_slack'] * 1e3:.3g} ms "
                f"after the start and snatches taut at every swing. A time step of about {period / 50 * 1e3:.2g} ms "
                f"follows it (a slack light rope's Newton fails at longer ones); else damp the rope's axial mode "
                f"(line_types.<type>.damping.axial in N*s per unit length: {critical:.3g} is critical for it) or "
                f"release the drum smoothly (a motor torque table from r T0 down)")

    def _hang_length(self) -> float:
        return self.info.length0 + self.info.payout

    def _tension_speed(self, T: float | None = None) -> float:
        """Payout speed (m/s) of the constant-tension characteristic at the tension T (N;
        default: the last measured)."""
        m = self.mode
        T = self.tension if T is None else T
        if T > m.tension + m.dead_band:
            v = (T - m.tension - m.dead_band) / m.gain
        elif T < m.tension - m.dead_band:
            v = (T - m.tension + m.dead_band) / m.gain
        else:
            v = 0.0
        return max(-m.max_speed, min(m.max_speed, v))

    def before_step(self, km, t_next: float, h: float) -> None:
        m = self.mode
        if m.kind == "speed":
            from ..scenario.winches import speed_payout
            D_mode, v_mode = speed_payout(m.rows, t_next)
        elif m.kind == "drum":
            # the drum's acceleration at t_{n+1}, implicit in the rope's stretch (_drum_implicit):
            # with it the payout follows the average-acceleration Newmark rule, stable at any step
            # while the rope stays taut (a release that slackens the rope: release_note)
            v_star = self.v_mode + 0.5 * h * (self.accel + self._drum_implicit(t_next, h))
            if m.brake_torque > 0.0 and self.v_mode != 0.0 and v_star * self.v_mode < 0.0:
                v_star = 0.0                                 # the brake stops the drum, not reverses it
            D_mode = self.D_mode + 0.5 * h * (self.v_mode + v_star)
            v_mode = v_star
        else:
            v_mode = self._tension_speed()
            D_mode = self.D_mode + h * v_mode
        D_c, v_c = self.D_c, 0.0
        if self.hc is not None:
            hc = self.hc
            e = self.e_cur                                   # at t_n (after_step)
            de = (self.e_cur - self.e_prev) / h if h > 0 else 0.0
            v_c = hc.kp * e + hc.ki * self.e_int + hc.kd * de
            if hc.feedforward:
                # the sheave's speed at the middle of the step (linear extrapolation)
                v_c += self.zeta_dot + 0.5 * (self.zeta_dot - self.zeta_dot_prev)
            # saturated at max_speed: the side it is held on (anti-windup, after_step)
            self.hc_sat = 1 if v_c > hc.max_speed else (-1 if v_c < -hc.max_speed else 0)
            v_c = max(-hc.max_speed, min(hc.max_speed, v_c))
            D_c = self.D_c + h * v_c
        D = D_mode + D_c
        v = v_mode + v_c
        info = self.info
        if D > info.stored:
            raise SolverError(f"winch '{self.name}' ran out of rope: payout {D:.6g} m is more than the "
                              f"{info.stored:.6g} m stored on the drum ({info.user_path('stored')})",
                              time=t_next, quantity="winch payout")
        if info.length0 + self._hanging(D) < MIN_FRACTION * info.length0:
            what = f"hauled in {-D:.6g} m" if self.slipped + self.slip0 == 0.0 else \
                f"paid out {D:.6g} m while the run to the lead drew {self.slipped + self.slip0:.6g} m over the sheave"
            raise SolverError(f"winch '{self.name}' {what} of the {info.length0:.6g} m line: less than "
                              f"{100 * MIN_FRACTION:g} % of it is left hanging",
                              time=t_next, quantity="winch payout")
        self._next = (t_next, D, v, D_mode, v_mode, D_c, v_c)
        set_payout(km, info, self._hanging(D), v, self.system.length_scale, self._accel(v, h))

    COUPLING_TOLERANCE = 1e-5       # drum force balance, relative to the tension plus m g
    SPEED_TOLERANCE = 1e-3          # constant-tension speed against its characteristic, of max_speed

    def correct(self, km, h: float) -> bool:
        """After a converged step of a drum winch: the drum's equation with the tension the
        step reached, m a = T_{n+1} - tau / r (m = J / r^2), against the acceleration a the
        payout was set with (D_{n+1} = D_n + h v_n + h^2/4 (a_n + a)). When they disagree,
        one Newton update of a on the rope's axial stiffness k and damping c,
        da = -(m a - T + tau / r) / (m + k h^2/4 + c h/2) (or the last step's secant slope at
        this h, which sees the payload move within the step; then secants), resets the
        payout and returns True:
        the step is redone from its start (rfesim.solvers.controlled). Strongly coupled: the
        drum-rope mode is implicit at any step. A brake acts against the motion (a drum at
        rest at the step's end, held or stopped by its brake, is taken as it is). False when
        balanced."""
        m = self.mode
        if m.kind == "tension":
            return self._correct_tension(km, h)
        if m.kind != "drum":
            return False
        t_next, D, v, D_mode, v_mode, D_c, v_c = self._next
        if m.brake_torque > 0.0 and v_mode == 0.0:
            return False            # held by the brake, or stopped by it within the step (as staggered)
        r = self._radius(D)
        meq = self._inertia(D) / (r * r)
        T = float(self.system.ws.sigma[self.info.first_sde, 0])
        a = 2.0 * (v_mode - self.v_mode) / h - self.accel
        # the drum's acceleration with the tension reached (the brake against the motion)
        res = meq * (a - self._drum_accel(t_next, v_mode, T, D))
        if abs(res) <= self.COUPLING_TOLERANCE * (abs(T) + meq * max(float(km.gravity), 1.0)):
            return False
        k, c = self._rope_axial() if T > 0.0 else (0.0, 0.0)
        rigid = meq + 0.25 * k * h * h + 0.5 * c * h          # the far end held still over the step
        prev = getattr(self, "_secant", None)
        if prev is not None and prev[:2] == (t_next, h) and prev[2] != a and prev[3] != res:
            slope = (res - prev[3]) / (a - prev[2])           # the secant of the last two tries
            if meq <= slope <= rigid:
                self._slope = (h, slope)                      # the first guess of the next step
        else:
            # the last step's secant where it had one at this step size: the payload moves with
            # the rope within the step, so the tension yields less than the rigid k h^2/4 + c h/2
            # (about a quarter of it for the free-drum check at 50 ms steps)
            last = getattr(self, "_slope", None)
            slope = rigid
            if last is not None and last[0] == h and T > 0.0 and meq <= last[1] <= rigid:
                slope = last[1]
        self._secant = (t_next, h, a, res)
        a -= res / slope
        v_mode = self.v_mode + 0.5 * h * (self.accel + a)
        if m.brake_torque > 0.0 and self.v_mode != 0.0 and v_mode * self.v_mode < 0.0:
            v_mode = 0.0                                    # the brake stops the drum, not reverses it
        self._repay(km, t_next, self.D_mode + 0.5 * h * (self.v_mode + v_mode), v_mode, D_c, v_c)
        return True

    def _repay(self, km, t_next: float, D_mode: float, v_mode: float, D_c: float, v_c: float) -> None:
        """Set the mode's corrected payout and speed for the step to be redone."""
        D, v = D_mode + D_c, v_mode + v_c
        self._next = (t_next, D, v, D_mode, v_mode, D_c, v_c)
        set_payout(km, self.info, self._hanging(D), v, self.system.length_scale, self._accel(v, t_next - self.t))

    def _correct_tension(self, km, h: float) -> bool:
        """The constant-tension winch's speed against its characteristic at the tension the
        step reached (backward Euler on the payout): when v differs from v(T_{n+1}) by more
        than SPEED_TOLERANCE of max_speed, a new speed is set and True returned (the step is
        redone). The staggered rule (the speed from T_n) was stable only while k h / gain < 2.

        The residual r(v) = v - v_char(T(v)) is increasing in v (a faster payout slackens the
        rope) but kinked where the characteristic saturates at +-max_speed or enters the dead
        band: a Newton or secant step on r itself cycles over a kink when k h / gain is large
        (gain 1e3 N*s/m on a 7e6 N/m rope at 20 ms: slope 1 + k h / gain = 147 on the
        sloped part, 1 on the saturated one). So only the smooth part is linearised, the
        tension T(v) ~ T_i + S (v - v_i) (S = -k h, the far end held still over the step,
        then the secant of the tries), and the kinked characteristic is met exactly on that
        line (``_meet``); the new speed stays inside the bracket of the tries' signs of r
        (bisected when the line's root leaves it). On the sloped part this is the Newton
        step of slope 1 + k h / gain as before."""
        m = self.mode
        t_next, D, v, D_mode, v_mode, D_c, v_c = self._next
        T = float(self.system.ws.sigma[self.info.first_sde, 0])
        res = v_mode - self._tension_speed(T)
        tries = getattr(self, "_tries", None)
        if tries is None or tries[0] != (t_next, h):
            tries = self._tries = ((t_next, h), [])
        tries = tries[1]
        tries.append((v_mode, T, res))
        self._unsettled = (h, T, v_mode, res)
        if abs(res) <= self.SPEED_TOLERANCE * m.max_speed:
            return False
        lo = max((t[0] for t in tries if t[2] < 0.0), default=-m.max_speed)
        hi = min((t[0] for t in tries if t[2] > 0.0), default=m.max_speed)
        S = None
        if len(tries) > 1:
            v0, T0, _ = tries[-2]
            if v0 != v_mode:
                S = (T - T0) / (v_mode - v0)
        if S is None or not S <= 0.0:
            k = self._rope_axial()[0] if T > 0.0 else 0.0
            S = -k * h
        new = self._meet(T, v_mode, S)
        if not lo < new < hi and lo < hi:
            new = 0.5 * (lo + hi)          # the line's root left the bracket of the tries: bisect
        v_mode = new
        self._repay(km, t_next, self.D_mode + h * v_mode, v_mode, D_c, v_c)
        return True

    def _meet(self, T: float, v: float, S: float) -> float:
        """The speed u (m/s) at which the characteristic meets the tension line T + S (u - v)
        (S <= 0 N*s/m): the root of u - v_char(T + S (u - v)), increasing in u and in
        [-max_speed, max_speed]; each piece (saturated, sloped, dead band) solved exactly."""
        m = self.mode
        vmax, g, band = m.max_speed, m.gain, m.dead_band

        def tension(u):
            return T + S * (u - v)

        if tension(vmax) - m.tension - band >= g * vmax:
            return vmax                                   # saturated paying out at vmax
        if tension(-vmax) - m.tension + band <= -g * vmax:
            return -vmax                                  # saturated hauling in
        base = T - S * v - m.tension                      # T + S (u - v) - tension = base + S u
        if base - band > 0.0:                             # above the band at u = 0: pays out
            return min(vmax, max(0.0, (base - band) / (g - S)))
        if base + band < 0.0:                             # below it: hauls in
            return max(-vmax, min(0.0, (base + band) / (g - S)))
        return 0.0                                        # in the dead band at u = 0

    def coupling_note(self, h: float) -> str:
        """What to change when the constant-tension speed did not settle at the step h
        (rfesim.solvers.controlled), '' for other modes or a settled winch."""
        last = getattr(self, "_unsettled", None)
        if self.mode.kind != "tension" or last is None or last[0] != h:
            return ""
        m = self.mode
        hh, T, v, res = last
        k = self._rope_axial()[0] if T > 0.0 else 0.0
        return (f"winch '{self.name}' (constant tension): its speed {v:.4g} m/s missed the characteristic by "
                f"{abs(res):.3g} m/s at tension {T:.6g} N, with k h / gain = {k * hh / m.gain:.3g} (rope axial "
                f"stiffness k = {k:.3g} N/m); raise {self.info.user_path('mode.gain')} (N*s/m) toward k h = "
                f"{k * hh:.3g}, shorten the time step, or lower mode.max_speed ({m.max_speed:g} m/s)")

    def after_step(self, km, state, t: float, h: float) -> None:
        t_next, D, v, D_mode, v_mode, D_c, v_c = self._next
        self.measure()
        if self.mode.kind == "drum":
            a_new = self._drum_accel(t, v_mode, None, D)
            v_new = self.v_mode + 0.5 * h * (self.accel + a_new)
            if self.mode.brake_torque > 0.0 and self.v_mode != 0.0 and v_new * self.v_mode <= 0.0:
                v_new = 0.0
            if self.mode.brake_torque > 0.0 and self.v_mode == 0.0 and a_new == 0.0:
                v_new = 0.0
            v_mode = v_new
            self.accel = self._drum_accel(t, v_mode, None, D)
        if self.hc is not None:
            e = self.zeta - D_c
            # anti-windup by conditional integration: while the speed is held at max_speed,
            # an error that would push it further into the limit is not integrated (the
            # integral would wind up and overshoot once the sheave's motion can be followed)
            if not (self.hc_sat != 0 and e * self.hc_sat > 0.0):
                self.e_int += e * h
            self.e_prev, self.e_cur = self.e_cur, e
        self.t, self.D, self.v, self.D_mode, self.v_mode, self.D_c, self.v_c = t, D, v_mode + v_c, D_mode, v_mode, \
            D_c, v_c
        self.v = v_mode + v_c
        self.info.speed = self.v
        if self.mode.kind == "drum":
            self._measure_chord(h)
        if self.lead is not None:
            self._hand_over(km, state)

    def _hand_over(self, km, state, at_start: bool = False) -> bool:
        """Hand the rope's slip over the sheave to the hanging rope's length once it passes
        half the rope's first RFE: the rope shortens by the slip, the slip's reference run
        grows by it, and the rope's RFE centres move down the rope by slip (1 - f_k), f_k
        the fraction of the hanging length at centre k (its nodes stay at fixed fractions,
        as in a payout). For a straight rope this keeps every SDE's gap and the join's point
        on the rope exactly (docs/theory.md, 'Reeving'). ``at_start``: the slip statics left,
        whatever its size, kept apart (``slip0``) so that the recorded slip starts at 0.
        True when it handed a slip over."""
        info = self.info
        ws = self.system.ws
        delta = float(ws.rv_slip_out[self.lead])
        lo, hi = info.rfe_lo, info.rfe_hi
        if delta == 0.0 or (not at_start and abs(delta) <= 0.5 * float(km.rfe_length[lo])):
            return False
        hang = info.length0 + info.payout
        n = info.elements
        dx = hang / n
        centre = np.concatenate([[0.25 * dx], dx * np.arange(1, n), [hang - 0.25 * dx]])
        down = ws.R[lo:hi, :, 0]                       # each RFE's axis, down the rope
        state.q[lo:hi, :3] += (delta * (1.0 - centre / hang))[:, None] * down
        if at_start:
            self.slip0 += delta
        else:
            self.slipped += delta
        self.rv_len += delta
        km.rv_len[self.lead] = self.rv_len
        set_payout(km, info, self._hanging(self.D), self.v, self.system.length_scale)
        ws.step_state[0] = 0            # the workspace no longer holds this state's evaluation
        return True

    # ------------------------------------------------------------------ outputs
    def channels(self) -> dict:
        info = self.info
        km = self.system.km
        return {"payout": self.D, "speed": info.speed,
                "tension": float(self.system.ws.sigma[info.first_sde, 0]),
                "suspended_length": info.length0 + info.payout,
                "rope_mass_suspended": float(km.rfe_mass[info.rfe_lo:info.rfe_hi].sum()),
                "rope_mass_drum": info.mass_per_length * (info.stored - self.D),
                # the run from the sheave to a vessel lead (massless in the model): its reference
                # length, which the slip handed over lengthens as the hanging rope shortens, so
                # drum + run + hanging stays mu (stored + run + line length) (0 without a lead)
                "rope_mass_run": info.mass_per_length * self.rv_len if self.lead is not None else 0.0,
                "drum_radius": self._radius() if self.mode.kind == "drum" else math.nan}


def _slipping_reeving(system, line: str) -> int | None:
    """The reeving row of a rope that slips over its sheave toward a vessel lead
    (rfesim.loads.reeving), or None."""
    km = system.km
    if not getattr(km, "has_reeving", False):
        return None
    for j in range(km.rv_sde.shape[0]):
        if km.rv_slip[j] == 1 and int(km.sde_right[km.rv_sde[j]]) == system.model.line(line).rfe_start:
            return j
    return None


def speed_at(rows, t: float) -> float:
    from ..scenario.winches import speed_payout
    return speed_payout(rows, t)[1]


def make_controllers(system) -> list[WinchController]:
    return [WinchController(info, system) for info in getattr(system.model, "winches", [])]
