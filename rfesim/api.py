"""The Python entry points: statics, simulate, modes (see CONTRACT.md)."""
from __future__ import annotations

import logging
import math
import time as _time

import numpy as np

from . import __version__
from .errors import CancelledError, SolverError
from .model.compile import compile_scenario
from .scenario import Scenario, load_scenario
from .solvers.buckling import buckling_warnings, crammed_rope_warnings, dynamic_crammed_warnings, \
    dynamic_shear_warnings, fold_warnings, shear_warnings, through_rope_warnings
from .solvers.dynamics import QUANTITY, Counters, Recorder, run_dynamics
from .solvers.kernels import Q_THROUGH
from .solvers.modal import (ModalResults, join_notes, locked_note, modal_analysis, statics_disabled_note,
                            statics_failed)
from .solvers.statics import solve_statics
from .solvers.system import System

log = logging.getLogger("rfesim")


# what a scene switches on (rfesim.model.compile: each term is a load module the kernels skip
# when its flag is off), for the -v log of the model
_TERMS = (("has_water", "buoyancy"), ("has_morison", "Morison loads"), ("has_sea", "waves / current"),
          ("has_seabed", "seabed"), ("has_friction", "seabed friction"), ("has_rollers", "rollers"),
          ("has_roller_friction", "roller friction"), ("has_tensioners", "tensioners"), ("has_reels", "reels"),
          ("has_plastic", "elasto-plastic SDEs"), ("has_tension_only", "tension-only SDEs"),
          ("has_bodies", "rigid bodies"), ("has_deck", "deck contact"), ("has_tuggers", "tugger lines"),
          ("has_reeving", "reeving"), ("has_closures", "closed chains"), ("has_loads", "point loads"))


def describe_model(model) -> str:
    """One line on the size of a compiled model and the load terms it switches on."""
    km = model.km
    n = int(km.rfe_mass.shape[0])
    terms = [name for flag, name in _TERMS if bool(getattr(km, flag, False))]
    if float(km.gravity) != 0.0:
        terms.insert(0, "gravity")
    if getattr(model, "winches", None):
        terms.append("winches")
    return (f"model: {len(model.lines)} line(s) ({', '.join(li.name for li in model.lines)}), {n} RFEs, "
            f"{int(np.count_nonzero(model.dof_mask))} degrees of freedom; terms: {', '.join(terms) or 'none'}")


def _compiled(sc: Scenario):
    model = compile_scenario(sc)
    log.info("%s", describe_model(model))
    return model


def _scenario(scenario) -> Scenario:
    # a Scenario instance too is validated again (rfesim.scenario.load.load_scenario): its
    # fields may have been assigned since it was validated
    return load_scenario(scenario)


def _other_formulations(sc: Scenario) -> bool:
    """Lines in the classical/modified/planar formulations or chains: rfesim.formulations.scene."""
    return bool(sc.chains) or any(line.formulation != "absolute" for line in sc.lines.values())


def _unsupported_lines(sc: Scenario) -> list[str]:
    """Lines free at both ends that no other line hangs from: without seabed, rollers or a
    balance of weight and buoyancy they have no static equilibrium."""
    used = set()
    for line in sc.lines.values():
        for end in (line.end_a, line.end_b):
            if ":" in end.attach:
                used.add(end.attach.split(":", 1)[0])
    return [name for name, line in sc.lines.items()
            if line.end_a.attach == "free" and line.end_b.attach == "free" and name not in used]


def _seabed_folds(model) -> list[str]:
    """What is wrong with heavy lines from the seabed longer than can hang and lie straight
    (LineInfo.seabed_fold): their slack folds on the seabed, which has no unique static shape
    (with no lateral stiffness it could snake either way), and the start shape bunches it up."""
    out = []
    for li in model.lines if model is not None else []:
        if li.seabed_fold is None:
            continue
        length, span, height, limit, drop = li.seabed_fold
        if drop > 0.0:
            out.append(f"line '{li.name}' hangs from two points {drop:.4g} m and {height:.4g} m above the seabed, "
                       f"{span:.4g} m apart, and is {length - limit:.4g} m longer ({length:.6g} m) than can hang "
                       f"vertically from both and lie straight on the seabed between them ({limit:.6g} m): the rest "
                       f"folds on the seabed, which has no unique static shape; shorten the line, move its ends "
                       f"apart, or set analysis.statics.enabled to false")
        elif height <= 1e-3 * length + 0.5 * li.section.outer_diameter:
            apart = f"{span:.6g} m apart" if abs(limit - span) <= 1e-6 * limit else \
                f"{limit:.6g} m apart along the seabed"
            out.append(f"line '{li.name}' has both ends on the seabed and {length - limit:.4g} m of slack "
                       f"({length:.6g} m between points {apart}): slack lying on the seabed has no "
                       f"unique static shape; make the line as long as the distance between its ends, lift an "
                       f"end off the seabed, or set analysis.statics.enabled to false")
        elif li.held_length > 0.0:
            # the pipe held on supports from end A (reel, rollers, tensioner) is not slack
            free = length - li.held_length
            out.append(f"line '{li.name}' runs from the seabed to its last support, a point {height:.4g} m up and "
                       f"{span:.4g} m away, {li.held_length:.6g} m from end A; beyond it its {free:.6g} m are "
                       f"{length - limit:.4g} m longer than can hang vertically and lie straight on the seabed "
                       f"({limit - li.held_length:.6g} m): the rest folds on the seabed, which has no unique static "
                       f"shape; shorten the line, move its ends apart, or set analysis.statics.enabled to false")
        else:
            out.append(f"line '{li.name}' runs from the seabed to a point {height:.4g} m up and {span:.4g} m away, "
                       f"and is {length - limit:.4g} m longer ({length:.6g} m) than can hang vertically and "
                       f"lie straight on the seabed ({limit:.6g} m): the rest folds on the seabed, which "
                       f"has no unique static shape; shorten the line, move its ends apart, or set "
                       f"analysis.statics.enabled to false")
    return out


def _floating_free_end(sc: Scenario) -> list[tuple[str, float, float]]:
    """Buoyant lines held at one end under water, the other end free, longer than the depth
    of the held end: (name, length, depth). Their floating part has no static shape."""
    from .model.compile import _submerged_weight
    from .model.sections import section_from_type
    from .scenario.load import _rest_point

    water = sc.environment.water
    if water is None or sc.environment.gravity <= 0.0:
        return []
    out = []
    for name, line in sc.lines.items():
        lt = sc.line_types.get(line.type)
        free = [e.attach == "free" for e in (line.end_a, line.end_b)]
        if lt is None or sum(free) != 1 or _submerged_weight(section_from_type(lt), sc) >= 0.0:
            continue
        held = line.end_b if free[0] else line.end_a
        point = _rest_point(sc, held.attach, held.position) if held.position is not None else None
        if point is not None and point[2] < water.surface_level and line.length > water.surface_level - point[2]:
            out.append((name, line.length, water.surface_level - point[2]))
    return out


def _shear_limited(model) -> list[tuple[str, float, float, float, int]]:
    """Lines in the fem shear stiffness (eq. 8.89) whose tension would exceed what it holds:
    (name, tension estimate, limit 12 EI / Delta^2, Delta, elements needed).

    The shear spring c = 12 EI / Delta^3 of an SDE holds a chain of rigid elements in line
    under a tension T only while T < c Delta = 12 EI / Delta^2: above it the straight chain is
    unstable (its elements shear apart sideways; a 20 m line, EI = 10 N m^2, 20 elements,
    pulled by 121 N has a negative eigenvalue in its static tangent, at 119 N it has none), so
    a hanging line carrying more has no stable equilibrium near its physical shape and Newton
    wanders (docs/theory.md, section 6, 'Soft fem shear under tension'). The tension is the
    one compile expected (rfesim.model.compile._tension_estimate)."""
    from .model.compile import shear_limit

    out = []
    for li in model.lines:
        tension, limit = li.tension_estimate, shear_limit(li.section, li.dx)
        if li.shear_model == "fem" and tension > limit:
            need = math.ceil(li.length / math.sqrt(12.0 * li.section.EI_min / tension))
            out.append((li.name, tension, limit, li.dx, need))
    return out


def _shear_hint(model) -> str | None:
    """The hint for lines whose fem shear cannot hold their tension (``_shear_limited``)."""
    limited = _shear_limited(model) if model is not None else []
    if not limited:
        return None
    name, tension, limit, dx, need = limited[0]
    more = f" (and {len(limited) - 1} more)" if len(limited) > 1 else ""
    return (f"line '{name}'{more} uses the fem shear stiffness 12 EI / Delta^3 (eq. 8.89), which holds its "
            f"elements in line only up to a tension of 12 EI / Delta^2 = {limit:.4g} N at Delta = {dx:.4g} m "
            f"(beyond it the chain of rigid elements shears apart sideways: no stable equilibrium), and it "
            f"carries about {tension:.4g} N: give lines.{name}.elements well above {need} (Delta below "
            f"sqrt(12 EI / T)), or set lines.{name}.shear_stiffness to kruszewski (eq. 8.88)")


def _statics_hint(sc: Scenario, model=None) -> str | None:
    """Why a statics that failed could not succeed, where the scene shows it: lines without
    support, slack lying on the seabed, lines whose fem shear cannot hold their tension,
    tuggers that out-pull their body's weight or a seabed too soft for a line's weight (with
    the compiled ``model``)."""
    free = _unsupported_lines(sc)
    if free:
        names = ", ".join(f"'{n}'" for n in free)
        return (f"line{'s' if len(free) > 1 else ''} {names} {'have' if len(free) > 1 else 'has'} no support "
                f"(both ends free): unless the seabed, rollers or buoyancy hold it there is no static "
                f"equilibrium; attach an end, or set analysis.statics.enabled to false and start the dynamics "
                f"from the given shape")
    shapeless = _no_static_shape(sc, model)
    if shapeless:
        return shapeless[0]
    shear = _shear_hint(model)
    if shear is not None:
        return shear
    start = _StartShape(model)          # the start shape evaluated once for the two checks below
    slack = _slack_ropes(model, start)
    if slack:
        name, length, chord, lower = slack[0]
        more = _and_more(slack)
        from .scenario.pipelay import user_field
        field = user_field(sc, f"lines.{name}.length")
        return (f"rope '{name}'{more} is {length - chord:.4g} m longer than the distance between its ends at the "
                f"start ({chord:.6g} m{lower}), one end nearly above the other: it starts slack along its whole "
                f"length, with no axial stiffness to guide Newton to its hanging shape (a loop below the lower "
                f"end); give {field} at most {chord:.6g} m for a taut rope, or set analysis.statics.enabled to "
                f"false and start the dynamics from the given shape")
    surfacing = _buoyant_at_surface(sc, model, start)
    if surfacing:
        name, w, rise = surfacing[0]
        more = _and_more(surfacing)
        return (f"line '{name}'{more} is buoyant (its submerged weight is {w:.4g} N/m: it floats up) and held at "
                f"both ends under the surface, and its arch between them reaches the surface (its start shape "
                f"rises {rise:.3g} m above it): there it floats, half submerged, and the length beyond what can "
                f"arch under the surface lies along it with no unique static shape; give the line weight (its line "
                f"type's density, contents_density or coating), shorten it, or set analysis.statics.enabled to false")
    stiff = _stiff_u_lines(model)
    if stiff:
        name, H, a, bend = stiff[0]
        more = _and_more(stiff)
        return (f"line '{name}'{more} sags onto the seabed in a U from two ends above it with a horizontal tension "
                f"of only {H / 1e3:.4g} kN, where its bending stiffness governs its shape: its bending length "
                f"sqrt(EI / H) = {bend:.4g} m against the catenary's radius {a:.4g} m at the touchdowns, so the "
                f"catenary it starts from is far from its shape; shorten the line (more tension), move its ends "
                f"apart, or set analysis.statics.enabled to false (the dynamics settle from the U)")
    neutral = _neutral_lines(sc)
    if neutral:
        name, w, dry = neutral[0]
        more = _and_more(neutral)
        return (f"line '{name}'{more} is nearly neutrally buoyant: its submerged weight is {w:.4g} N/m, "
                f"{100 * abs(w) / dry:.2g} % of its {dry:.4g} N/m in air, so it hardly settles anywhere (on the "
                f"seabed, on rollers or in a sag) and the contacts it barely touches switch Newton from step to "
                f"step; check the line type's density, contents_density and coating (the weight the water "
                f"does not carry), or set analysis.statics.enabled to false")
    tugged = _tugged_off(sc, model, start)
    if tugged:
        return tugged[0]
    from .seabed_check import soft_seabed_hint
    return soft_seabed_hint(model, sc)


def _tugged_off(sc: Scenario, model, start: _StartShape | None = None) -> list[str]:
    """One hint per body whose constant-tension tuggers (rfesim.loads.tugger) pull it
    sideways at the start harder than its weight (less buoyancy, plus their own downward
    pull) presses it down: hanging from a rope it would lean past 45 degrees to hold them,
    on a deck its friction (at most that force times the friction coefficient) cannot, so
    there is no equilibrium near the start. A hint, not a proof: it is named only after a
    statics that failed."""
    if model is None or not getattr(model, "tuggers", None):
        return []
    from .loads.tugger import KIND_TENSION
    from .model.arrays import new_attachment_state
    from .scenario.pipelay import user_field
    from .vessel_kernel import attachment_kinematics, vessel_spec
    km = model.km
    start = start or _StartShape(model)
    ws = start.ws
    att = new_attachment_state(len(model.attachment_names))
    attachment_kinematics(vessel_spec(model.motions), 0.0, att)
    g = abs(float(sc.environment.gravity))
    water = sc.environment.water
    out = []
    for b in model.bodies:
        force = np.zeros(3)
        names = []
        for tg in model.tuggers:
            j = tg.index
            if tg.body != b.name or km.tug_kind[j] != KIND_TENSION:
                continue
            count = int(km.tug_count[j])
            tension = float(np.interp(0.0, km.tug_t[j, :count], km.tug_v[j, :count]))
            a = int(km.tug_att[j])
            deck = att.p[a] + att.R[a] @ km.tug_deck[j]
            point = ws.r[b.rfe] + ws.R[b.rfe] @ km.tug_point[j]
            span = deck - point
            length = float(np.linalg.norm(span))
            if tension > 0.0 and length > 0.0:
                force += tension * span / length
                names.append(tg.name)
        if not names:
            continue
        weight = b.mass * g
        if water is not None and float(ws.r[b.rfe][2]) < 0.0:
            weight -= float(water.density) * g * b.volume
        down = weight - float(force[2])
        side = float(math.hypot(force[0], force[1]))
        body = sc.bodies.get(b.name)
        deck = getattr(body, "deck", None)
        mu = float(deck.friction) if deck is not None else None
        if side <= (max(down, 0.0) if mu is None else mu * max(down, 0.0)):
            continue
        which = ", ".join(f"'{n}'" for n in names)
        field = user_field(sc, f"tuggers.{names[0]}.mode.tension")
        pull = (f"the tugger{'s' if len(names) > 1 else ''} {which} on body '{b.name}' pull it sideways with "
                f"{side / 1e3:.4g} kN at the start")
        press = (f"{down / 1e3:.4g} kN that its weight{' (less buoyancy)' if weight != b.mass * g else ''} and "
                 f"their downward pull press it down")
        if mu is None:
            why = (f"more than the {press}: hanging from a rope it would have to lean past 45 deg to hold them, so "
                   f"there is no equilibrium near the start")
        else:
            why = (f"more than the deck's friction holds: {mu:.3g} times the {press}, {mu * down / 1e3:.4g} kN at "
                   f"most (less what the rope carries), so it slides off its start and has no equilibrium there")
        out.append(f"{pull}, {why}; give the tuggers less tension ({field}) or the body more weight, or set "
                   f"analysis.statics.enabled to false")
    return out


STIFF_U = 3.0     # a U onto the seabed whose bending length exceeds this many touchdown radii is bending-governed


def _stiff_u_lines(model) -> list[tuple[str, float, float, float]]:
    """Lines that sag onto the seabed in a U from two ends above it (LineInfo.seabed_u) so
    slack that their bending stiffness, not their weight, shapes them: the bending length
    sqrt(EI / H) more than ``STIFF_U`` times the catenary's touchdown radius a = H / w. Their
    start shape, the U of two catenaries (rfesim.model.compile._two_touchdowns), bends them
    far beyond their shape at the touchdowns: the H1 riser pipe (EI 3.6e7 N m^2) between ends
    100 m and 190 m above the seabed converged at 480 m (4.5 radii) and failed at 500 m (12).
    (name, H N, a m, bending length m)."""
    out = []
    for li in model.lines if model is not None else []:
        if li.seabed_u is None:
            continue
        H, a, _top = li.seabed_u
        bend = math.sqrt(li.section.EI_min / H) if H > 0.0 else math.inf
        if bend > STIFF_U * a:
            out.append((li.name, H, a, bend))
    return out


def _and_more(found: list) -> str:
    """" (and N more)" after the first of several lines a hint names."""
    return f" (and {len(found) - 1} more)" if len(found) > 1 else ""


class _StartShape:
    """The model's start shape evaluated (RFE positions, SDE strains) on first use."""

    def __init__(self, model):
        self.model = model
        self._ws = None

    @property
    def ws(self):
        if self._ws is None:
            system = System(self.model)
            system.evaluate(self.model.initial)
            self._ws = system.ws
        return self._ws


VERTICAL = 0.1     # a rope's ends within this ratio of horizontal to vertical distance: one above the other


def _slack_ropes(model, start: _StartShape | None = None) -> list[tuple[str, float, float, str]]:
    """Ropes (lines of tension-only SDEs) longer than the distance between their ends at the
    start by more than EXCESS_LENGTH whose start shape compresses them (one end above the
    other: the catenary start degenerates and bows the rope sideways, every element slack):
    (name, length, distance, where end B is held). A slack rope between ends apart
    sideways starts from its catenary, taut, and is not listed."""
    if model is None:
        return []
    km = model.km
    candidates = [li for li in model.lines
                  if li.chord is not None and li.length > li.chord * (1.0 + EXCESS_LENGTH)
                  and li.sde_stop > li.sde_start and np.all(km.sde_tension_only[li.sde_start:li.sde_stop] == 1)]
    if not candidates:
        return []
    ws = (start or _StartShape(model)).ws
    eps, r = ws.eps[:, 0], ws.r
    bodies = {b.name for b in (getattr(model, "bodies", None) or [])}
    out = []
    for li in candidates:
        d = r[li.rfe_stop - 1] - r[li.rfe_start]          # the end RFEs' centres
        if not (np.all(eps[li.sde_start:li.sde_stop] < 0.0) and math.hypot(d[0], d[1]) < VERTICAL * abs(d[2])):
            continue
        held = li.end_b.attach if li.end_b is not None else None
        lower = f", end B at body '{held}'" if held in bodies else ""
        out.append((li.name, float(li.length), float(li.chord), lower))
    return out


def _buoyant_at_surface(sc: Scenario, model, start: _StartShape | None = None) -> list[tuple[str, float, float]]:
    """Buoyant lines with both ends placed under water whose start shape (the catenary of their
    net buoyancy, arched up) reaches the surface: (name, submerged weight N/m (< 0), the height
    of the start shape's top above the surface less the line's radius, m)."""
    from .model.compile import _submerged_weight
    from .model.sections import section_from_type

    water = sc.environment.water
    if model is None or water is None or sc.environment.gravity <= 0.0:
        return []
    candidates = []
    for li in model.lines:
        line = sc.lines.get(li.name)
        lt = sc.line_types.get(line.type) if line is not None else None
        if lt is None or li.chord is None:
            continue
        w = _submerged_weight(section_from_type(lt), sc)
        if w < 0.0:
            candidates.append((li, w))
    if not candidates:
        return []
    ws = (start or _StartShape(model)).ws
    out = []
    for li, w in candidates:
        r = ws.r[li.rfe_start:li.rfe_stop]
        rise = float(r[:, 2].max()) + 0.5 * li.section.outer_diameter - water.surface_level
        if rise >= 0.0 and float(r[0, 2]) < water.surface_level and float(r[-1, 2]) < water.surface_level:
            out.append((li.name, w, rise))
    return out


NEUTRAL_BUOYANCY = 0.02   # a line whose submerged weight is within this fraction of its dry weight


def _neutral_lines(sc: Scenario) -> list[tuple[str, float, float]]:
    """Lines in water whose submerged weight per length is within NEUTRAL_BUOYANCY of their
    weight in air: (name, submerged weight N/m, weight in air N/m)."""
    from .model.compile import _submerged_weight
    from .model.sections import section_from_type

    g = sc.environment.gravity
    if sc.environment.water is None or g <= 0.0:
        return []
    out = []
    for name, line in sc.lines.items():
        lt = sc.line_types.get(line.type)
        if lt is None:
            continue
        sec = section_from_type(lt)
        dry = sec.mass_per_length * g
        w = _submerged_weight(sec, sc)
        if dry > 0.0 and abs(w) < NEUTRAL_BUOYANCY * dry:
            out.append((name, w, dry))
    return out


def _no_static_shape(sc: Scenario, model) -> list[str]:
    """What makes lines of the scene have no unique static shape: a buoyant line floating
    free on the surface (_floating_free_end), slack folding on the seabed (_seabed_folds).
    The hint of a statics that fails, and a warning when Newton settles on some shape anyway
    (which one is a matter of round-off)."""
    out = [f"line '{name}' is buoyant, held at one end {depth:.4g} m under the surface with its other end free, "
           f"and {length:.6g} m long: the rest floats on the surface, where nothing holds it sideways, so it "
           f"has no unique static shape; hold its free end too (a position, a tether), or set "
           f"analysis.statics.enabled to false" for name, length, depth in _floating_free_end(sc)]
    return out + _seabed_folds(model)


EXCESS_LENGTH = 1e-3   # a line longer than the distance between its ends by this fraction has slack


def _excess_length(model) -> list[tuple[str, float, float]]:
    """Lines with both ends placed and longer than the distance between them: (name, length,
    distance). A straight start (analysis.statics.start) shortens each of their elements to
    span the chord: a column compressed by EA (1 - d / L), which buckles."""
    return [(li.name, li.length, li.chord) for li in model.lines
            if li.chord is not None and li.length > li.chord * (1.0 + EXCESS_LENGTH)]


def _straight_start_hint(excess: list[tuple[str, float, float]], why: str) -> str:
    name, length, span = excess[0]
    more = f" (and {len(excess) - 1} more)" if len(excess) > 1 else ""
    return (f"line '{name}'{more} is {length:.6g} m long between ends {span:.6g} m apart, and a straight start "
            f"compresses it into a straight column of that length, which buckles; {why}")


def _start_dependent(system: System, model) -> list[str]:
    """The kernel arrays of ``model`` (compiled from another start shape) that differ from
    the system's: what the start shape fixes in the model (the orientation of a clamped end
    given without a direction, the rest rotation of a join)."""
    a, b = system.km, model.km
    return [f for f in a._fields if isinstance(getattr(a, f), np.ndarray)
            and (getattr(a, f).shape != getattr(b, f).shape or not np.array_equal(getattr(a, f), getattr(b, f)))]


def _static_state(system: System, sc: Scenario, progress=None):
    """Statics of the scene -> (state, info). A straight start (analysis.statics.start) that
    fails on lines with slack is retried from the catenary start shape; info.warnings says
    so, and holds the free compressed stretches beyond their Euler load
    (rfesim.solvers.buckling); each is logged too."""
    s = sc.analysis.statics

    def solve(start=None):
        # a start shape of the model (its own or the catenary's): bodies hang first (hang_bodies)
        return solve_statics(system, start, tolerance=s.tolerance, max_iterations=s.max_iterations,
                             load_steps=s.load_steps, progress=progress, seabed_friction=s.seabed_friction,
                             hang=True)

    saved = system.history()
    wall0 = _time.perf_counter()
    try:
        state, info = solve()
    except SolverError as exc:
        excess = _excess_length(system.model) if s.start == "straight" else []
        if excess:
            state, info = _catenary_retry(system, sc, exc, excess, saved, solve)
        else:
            hint = None if exc.hint else _statics_hint(sc, system.model)
            if hint is None:
                raise
            raise SolverError(exc.message, time=exc.time,
                              element=exc.element, quantity=exc.quantity, results=exc.results, hint=hint) from None

    def resolve(st):
        return solve_statics(system, st, tolerance=s.tolerance, max_iterations=s.max_iterations,
                             seabed_friction=s.seabed_friction)

    if system.km.has_reels:
        # reels that hold a back tension: turn the drums until they do (rfesim.solvers.reel_statics)
        from .solvers.reel_statics import settle_back_tension
        state, info = settle_back_tension(system, sc, state, info, resolve)
    if system.km.has_tensioners and any(getattr(sup, "horizontal_tension", None) is not None
                                        for sup in sc.supports.values()):
        # tensioners that set the horizontal lay tension: pay out until the line carries it
        # (rfesim.solvers.lay_statics); a reel on that line turns with them, and settles again
        from .solvers.lay_statics import settle_lay_tension
        state, info = settle_lay_tension(system, sc, state, info, resolve)
        if system.km.has_reels:
            state, info = settle_back_tension(system, sc, state, info, resolve)
    info.warnings = (list(getattr(sc, "_template_warnings", [])) + _no_static_shape(sc, system.model)
                     + list(info.warnings) + buckling_warnings(system, state) + shear_warnings(system, state)
                     + fold_warnings(system, state))
    info.through = through_rope_warnings(system, state, sc)
    info.warnings += info.through + crammed_rope_warnings(system, state, sc)
    for w in info.warnings:
        log.warning("statics: %s", w)
    log.info("statics: %s, %.3g s", info.message, _time.perf_counter() - wall0)
    return state, info


def describe_run(counters, t_end: float) -> str:
    """One line on the cost of a dynamic run from its counters (rfesim.solvers.dynamics)."""
    wall = float(counters.get("wall_time", 0.0) or 0.0)
    speed = f", {t_end / wall:.3g}x real time" if wall > 0 and t_end > 0 else ""
    return (f"dynamics: {t_end:g} s simulated in {wall:.3g} s{speed}; {counters.get('steps', 0)} steps "
            f"(time step {counters.get('time_step', float('nan')):.3g} s, {counters.get('step_halvings', 0)} halvings)"
            + (f", {counters['newton_iterations']} Newton iterations, {counters.get('jacobians', 0)} Jacobians"
               if counters.get("newton_iterations") else ""))


def _catenary_retry(system: System, sc: Scenario, exc: SolverError, excess, saved, solve):
    """Statics from the catenary start shape after the straight start failed on lines with
    slack: another first iterate of the same model (docs/theory.md, section 6). Only when
    the catenary start compiles to the same model: where the start shape fixes something in
    it (a clamped end without a direction), the error keeps the straight start's failure
    with a hint."""
    def failed(why: str):
        return SolverError(exc.message, time=exc.time, element=exc.element, quantity=exc.quantity,
                           results=exc.results, hint=_straight_start_hint(excess, why))

    catenary = compile_scenario(sc, start="catenary")
    differ = _start_dependent(system, catenary)
    if differ:
        raise failed("a catenary start would set the model differently (the orientation of a clamped end "
                     "given without a direction, or of a join: " + ", ".join(differ) + "), so it is not "
                     "tried in its place: give those ends a direction, or set analysis.statics.start to "
                     "catenary (or auto)") from None
    system.set_history(saved)       # the failed solve's tensioner, reel and friction anchors
    try:
        state, info = solve(catenary.initial)
    except SolverError:
        shear = _shear_hint(system.model)
        raise failed("statics from the catenary start failed too: " + (
            shear if shear is not None else "look at the scene (are the ends where you meant them?), or give "
                                            "more load steps (analysis.statics.load_steps)")) from None
    name, length, span = excess[0]
    note = (f"the straight start failed (it compresses the {length:.6g} m of line '{name}' between ends "
            f"{span:.6g} m apart into a column, which buckles), so statics started from the catenary")
    info.warnings = [note]
    return state, info


START_IMBALANCE = 10.0     # a start shape out of balance by more than this x the force scale is named on a failure


def _start_imbalance(system: System, state) -> str | None:
    """With analysis.statics.enabled false the dynamics start from the scenario's start shape:
    when that is out of balance by more than START_IMBALANCE x the scene's force scale (its
    largest weight or point load), what a failed run's SolverError adds as a hint (None
    otherwise): the largest out-of-balance force, where, and what to do. Evaluated before the
    run (a winch's payout rewrites the model as it runs)."""
    out = np.zeros_like(state.q)
    system.static_residual(state.q, state.ref, 1.0, out)
    force = np.abs(out[:, :3]).max(axis=1) if out.size else np.zeros(0)
    if force.size == 0 or not np.isfinite(force).all():
        return None
    i = int(np.argmax(force))
    scale = system.force_scale(state)
    if force[i] <= START_IMBALANCE * scale:
        return None
    return (f"analysis.statics.enabled is false, so the dynamics started from the scenario's start shape, which is "
            f"out of balance by up to {force[i] / 1e3:.4g} kN ({force[i] / scale:.3g} times the largest weight or "
            f"load, {scale / 1e3:.4g} kN) at {system.model.describe_rfe(i)}: enable the statics "
            f"(analysis.statics.enabled: true) to start from the equilibrium")


STATICS_WARNING = "; statics warning: "     # what precedes each statics warning in a results' message


def _with_warnings(message: str, info) -> str:
    """The results' message with the statics warnings (rfesim.solvers.buckling) after it."""
    warnings = info.warnings if info is not None else []
    return "".join([message] + [f"{STATICS_WARNING}{w}" for w in warnings])


def check_model(scenario) -> list[str]:
    """Build the model of a scenario without solving anything: what ``rfesim check`` runs
    after validation. It raises the ScenarioError a run would raise while compiling (a line
    whose ends coincide, a reeving to an unknown line, a support past the line's end, ...),
    naming the field; statics and dynamics are not started (their failures need a solve).
    Returns the warnings that need the built model but no solve, as a run's statics logs
    them: lines with no unique static shape (slack folding on the seabed, a buoyant line
    floating free; ``_no_static_shape``), for absolute-coordinate scenes with statics."""
    sc = _scenario(scenario)
    if _other_formulations(sc):
        from .formulations import mixed, scene
        if mixed.is_mixed(sc):
            mixed.MixedScene(sc)
        else:
            scene.compile_scene(sc)
        return []
    model = _compiled(sc)
    _check_output_times(sc, model)
    return _no_static_shape(sc, model) if sc.analysis.statics.enabled else []


def _check_output_times(sc, model) -> None:
    """The ScenarioError the dynamics of a run raise before their first step when the output
    times would store more results than this machine's memory takes
    (rfesim.solvers.dynamics._check_output_size, for the output times of its output schedule).
    Unknown without a solve only for the default RK4 step (its stability limit) without an
    output interval, which records at most about 10000 output times: not checked then."""
    from .solvers.dynamics import _check_output_size, _whole_intervals, output_schedule
    dyn = sc.analysis.dynamics
    if not (dyn.enabled and dyn.duration > 0):
        return
    T, integ = float(dyn.duration), dyn.integrator
    adaptive = integ.kind == "adaptive"
    step = getattr(integ, "time_step", None)
    if dyn.output_interval:
        n_out = _whole_intervals(T, float(dyn.output_interval))
    elif adaptive or step:
        n_out = output_schedule(T, float(step or T), None, adaptive)[1]
    else:
        return
    _check_output_size(System(model), n_out + 2)


_COMPILE_CHECKED = False


def _compile_ahead() -> None:
    """Once per process: a cold numba cache (the first run after an install) is filled by
    ``rfesim.precompile`` in parallel processes before the run, rather than kernel by kernel
    as the run first calls them (docs/theory.md, 'Compiling in parallel'). Only with two
    processes or more (RFESIM_PRECOMPILE, default the CPUs): one process would compile more
    than the run needs."""
    global _COMPILE_CHECKED
    if _COMPILE_CHECKED:
        return
    _COMPILE_CHECKED = True
    from . import _precompile

    n = _precompile.processes_default()
    if n < 2 or not _precompile.cache_is_cold():
        return
    log.info("compiling the numba kernels in %d processes (the first run after an install: a few minutes)", n)
    try:
        _precompile.precompile(n)
    except Exception as exc:   # the run compiles what it calls, as without it
        log.info("compiling the kernels ahead failed (%s: %s); the run compiles them as it calls them",
                 type(exc).__name__, exc)


def statics(scenario, *, progress=None):
    """Static equilibrium of a scenario -> Results with one time point."""
    sc = _scenario(scenario)
    _compile_ahead()
    if _other_formulations(sc):
        from .formulations import scene
        res = scene.statics(sc, progress)
        res.message += _breaking_load_message(sc, res)
        return res
    system = System(_compiled(sc))
    wall0 = _time.perf_counter()
    state, info = _static_state(system, sc, progress)
    rec = Recorder(system, 1)
    rec.record(state, state.qdd)
    counters = {"newton_iterations": info.iterations, "load_steps": info.load_steps,
                "wall_time": _time.perf_counter() - wall0}
    res = rec.results(status=0, message=_with_warnings(info.message, info), counters=counters,
                      scenario_json=sc.model_dump_json(), version=__version__, kind="statics")
    res.message += _breaking_load_message(sc, res, system.model)
    return res


def simulate(scenario, *, progress=None):
    """Statics (if enabled) then dynamics (if enabled and duration > 0) -> Results; with
    analysis.modal also the modes about the static equilibrium in ``results.modes`` (a
    ModalResults, as ``modes`` gives them; None and a note in the message when the modal
    analysis failed or is not provided for the scene).

    ``progress(fraction, time)`` is called as the run advances; if it raises, the run stops
    with ``rfesim.CancelledError``, whose ``results`` hold what the dynamics recorded up to
    the last output step (status 3, rfesim.solvers.dynamics.CANCELLED, "cancelled at t =
    ..."; None when nothing was recorded yet, or for a cancel in the statics), in every
    formulation as for an interruption below. A diverging run raises ``rfesim.SolverError`` whose
    ``results`` hold everything computed before; a KeyboardInterrupt in the dynamics (Ctrl-C,
    or a SIGTERM the command line turns into it; a BaseException, so a progress callback that
    raises it is not turned into CancelledError) carries them the same way (``results``,
    status 2, "interrupted at t = ...", or None when nothing was recorded yet), in every
    formulation: absolute-coordinate lines, mixed chain and line scenes
    (rfesim.formulations.mixed.simulate), and scenes of chains and classical / modified /
    planar lines (rfesim.formulations.scene.simulate), whose uncoupled units are integrated
    one after another: their results keep the time span every unit reached (t = 0 only
    while some unit had not started). Interrupted statics carry nothing.
    """
    sc = _scenario(scenario)
    _compile_ahead()
    if _other_formulations(sc):
        from .formulations import scene
        try:
            res = scene.simulate(sc, progress)
        except SolverError as exc:
            if exc.results is not None:
                exc.results.message += _dynamic_warnings(None, exc.results, sc)
            raise
        if res.kind == "dynamics":
            res.message += _dynamic_warnings(None, res, sc)
            log.info("%s", describe_run(res.counters, float(res.time[-1])))
        else:
            res.message += _breaking_load_message(sc, res)
        return _with_modes(sc, res)
    model = _compiled(sc)
    system = System(model)
    an = sc.analysis
    meta = dict(scenario_json=sc.model_dump_json(), version=__version__)
    counters = Counters()
    state = model.initial
    info = None
    if an.statics.enabled:
        state, info = _static_state(system, sc)
        counters["statics_iterations"] = info.iterations
    dyn = an.dynamics
    if not (dyn.enabled and dyn.duration > 0):
        rec = Recorder(system, 1)
        rec.record(state, state.qdd)
        res = rec.results(status=0, message=_with_warnings("statics only", info), counters=dict(counters),
                          kind="statics", **meta)
        res.message += _breaking_load_message(sc, res, model)
        return _with_modes(sc, res)
    unbalanced = None if an.statics.enabled else _start_imbalance(system, state)
    try:
        state, rec, counters = run_dynamics(system, state, dyn, progress=progress, counters=counters)
    except SolverError as exc:
        if exc.results is not None:
            exc.results.scenario_json = meta["scenario_json"]
            exc.results.version = __version__
            exc.results.message = _with_warnings(exc.results.message, info) + _dynamic_warnings(model, exc.results, sc)
        if info is not None and info.through and exc.quantity == QUANTITY[Q_THROUGH]:
            # the statics left the rope so: say that, not what drives one through in a run
            hint = f"the static equilibrium it started from had them: {info.through[0]}"
            raise SolverError(exc.message, time=exc.time, element=exc.element, quantity=exc.quantity,
                              results=exc.results, hint=hint) from None
        if unbalanced is not None and exc.results is not None:
            exc.results.message += f"; {unbalanced}"
        # the jolts the input was warned about (waves with no ramp, tables that start at speed
        # or stop dead) are often the cause: the error names them too, not only the results
        from .scenario.motion_warnings import input_motion_warnings
        warned = input_motion_warnings(sc)
        before = (f"before the run the scenario was warned: {warned[0]}"
                  + (f" (and {len(warned) - 1} more in the results' message)" if len(warned) > 1 else "")
                  if warned else None)
        if unbalanced is not None or before is not None:
            hint = "; ".join(h for h in (exc.hint, unbalanced, before) if h)
            raise SolverError(exc.message, time=exc.time, element=exc.element, quantity=exc.quantity,
                              results=exc.results, hint=hint) from None
        raise
    except (CancelledError, KeyboardInterrupt) as exc:
        # a progress callback that raised (CancelledError, status CANCELLED) or Ctrl-C (or
        # SIGTERM turned into it by the command line; status INTERRUPTED): run_dynamics
        # attached the results so far, as to a SolverError
        part = getattr(exc, "results", None)
        if part is not None:
            part.scenario_json, part.version = meta["scenario_json"], __version__
            part.message = _with_warnings(part.message, info)
        raise
    message = _with_warnings(f"finished: {counters.get('steps', 0)} steps", info)
    log.info("%s", describe_run(counters, float(state.t)))
    try:
        res = rec.results(status=0, message=message, counters=dict(counters), **meta)
        res.message += _dynamic_warnings(model, res, sc, rec)
        res.message += "".join(f"{DYNAMICS_WARNING}{w}" for w in _straightener_warnings(system, state, res, sc))
    except KeyboardInterrupt as exc:
        # Ctrl-C after the last step, while the results were put together: the run is complete,
        # and they go with the interruption as those of a run stopped early do (the command
        # line's handler lets no second signal through while it writes them)
        if getattr(exc, "results", None) is None:
            exc.results = rec.results(status=0, message=message, counters=dict(counters), **meta)
        raise
    return _with_modes(sc, res)


MODAL_NOTE = "; modal analysis: "   # what precedes the modal analysis' summary in a results' message


def _with_modes(sc: Scenario, res):
    """A run's Results with the modes of analysis.modal (when given) about the static
    equilibrium, as ``modes`` computes them (results.modes, a ModalResults; the statics
    solved for them also when analysis.statics.enabled is false), and a note in the message.
    A modal analysis that fails or is not provided for the scene leaves results.modes None
    and says why in the message: the run's own results stand."""
    if sc.analysis.modal is None:
        return res
    wall0 = _time.perf_counter()
    try:
        md = modes(sc)
    except SolverError as exc:
        log.warning("modal analysis: not done: %s", exc)
        res.message += f"{MODAL_NOTE}not done (analysis.modal): {exc}"
        return res
    res.modes = md
    f = np.asarray(md.frequencies_hz, float)
    lowest = f[~md.rigid_body] if f.size else f
    first = f", lowest {lowest[0]:.6g} Hz" if lowest.size else ""
    res.message += (f"{MODAL_NOTE}{f.size} modes about the static equilibrium{first} (results.modes; /modes in the results file)"
                    + (f": {md.message}" if md.message else ""))
    res.counters["modal_wall_time"] = _time.perf_counter() - wall0
    return res


DYNAMICS_WARNING = "; dynamics warning: "   # what precedes each dynamics warning in a results' message


def breaking_load_warnings(sc: Scenario, results) -> list[str]:
    """One message per line whose line type gives a ``breaking_load`` and whose effective
    tension in ``results`` exceeds it: the peak, its time and place, and its multiple of the
    breaking load."""
    out = []
    for name, line in (sc.lines or {}).items():
        lt = (sc.line_types or {}).get(line.type)
        mbl = getattr(lt, "breaking_load", None)
        if not mbl or name not in results.lines:
            continue
        lr = results.line(name)
        tension = np.asarray(lr.tension, float)
        if tension.size == 0 or not np.isfinite(tension).any():
            continue
        k, j = np.unravel_index(int(np.nanargmax(tension)), tension.shape)
        peak = float(tension[k, j])
        if peak > mbl:
            s = float(np.asarray(lr.sde_arc_length)[j])
            out.append(f"line '{name}' reaches {peak / 1e3:.6g} kN of tension at t = {float(results.time[k]):.6g} s, "
                       f"{s:.4g} m from end A: {peak / mbl:.3g} times the breaking_load of its line type "
                       f"'{line.type}' ({mbl / 1e3:.6g} kN)")
    return out


PRETENSION_SLACK = 0.2      # share of its pretension an elastic tugger may lose or gain in statics unwarned


def tugger_pretension_warnings(sc: Scenario, results) -> list[str]:
    """One message per elastic tugger with a pretension whose tension at the first time of
    ``results`` (the static equilibrium, when statics ran) differs from it by more than
    PRETENSION_SLACK of it: the pretension sets the unstretched length at the scenario's
    initial positions, and statics moves the body (a 10 kN tugger on a stiff line held 469 N
    after the body settled 0.095 m)."""
    out = []
    if not sc.analysis.statics.enabled:
        return out
    for name, tug in (sc.tuggers or {}).items():
        mode = tug.mode
        if mode.kind != "elastic" or not mode.pretension > 0.0 or name not in results.tuggers:
            continue
        tension = np.asarray(results.tugger(name).tension, float)
        if tension.size == 0 or not np.isfinite(tension[0]):
            continue
        held = float(tension[0])
        if abs(held - mode.pretension) > PRETENSION_SLACK * mode.pretension:
            out.append(f"tugger '{name}' (tuggers.{name}.mode.pretension) holds {held / 1e3:.4g} kN at static "
                       f"equilibrium, not its pretension {mode.pretension / 1e3:.4g} kN: the pretension sets the "
                       f"line's unstretched length at the scenario's initial positions, and statics moved the "
                       f"body; start the body where it hangs with the tugger pulling, or give the line's length")
    return out


def _breaking_load_message(sc: Scenario, results, model=None) -> str:
    """The breaking-load and tugger-pretension warnings of a statics result, and with the
    compiled ``model`` the lines sunk into the seabed (rfesim.seabed_check), logged and as
    text for its message."""
    from .seabed_check import below_bottom_warnings, seabed_penetration_warnings
    warnings = (breaking_load_warnings(sc, results) + tugger_pretension_warnings(sc, results)
                + seabed_penetration_warnings(model, sc, results) + below_bottom_warnings(sc, results))
    for w in warnings:
        log.warning("statics: %s", w)
    return "".join(f"{STATICS_WARNING}{w}" for w in warnings)


def _dynamic_warnings(model, results, sc=None, recorder=None) -> str:
    """A duration the output interval does not divide, the prescribed motions that start or
    stop with a jolt (rfesim.scenario.motion_warnings.input_motion_warnings: waves and vessel
    motions with no ramp, vessel motion tables that end before the run does or start after
    it, drive, motor, winch and payout tables that start at speed or stop dead inside it),
    the RAO vessels whose table leaves
    out a noticeable part of the sea (rfesim.sea.rao.rao_range_warnings) and the lines whose tension in the run went past
    their fem shear limit and the ropes driven into themselves (rfesim.solvers.buckling.
    dynamic_shear_warnings, dynamic_crammed_warnings; ``model`` None:
    a scene of other formulations), logged and as text for the message; with the run's
    ``recorder`` (a run that finished) also the growth of a closed scene's energy below the
    stop (rfesim.solvers.dynamics.EnergyCheck) and more than a tenth of the steps halved."""
    from .scenario.motion_warnings import input_motion_warnings
    from .sea.rao import rao_range_warnings
    from .solvers.dynamics import halving_warning, output_interval_warning
    from .seabed_check import below_bottom_warnings, seabed_penetration_warnings
    warnings = (input_motion_warnings(sc) + rao_range_warnings(sc) + below_bottom_warnings(sc, results)
                if sc is not None else []) + (
        dynamic_shear_warnings(model, results) + dynamic_crammed_warnings(model, results)
        + seabed_penetration_warnings(model, sc, results) if model is not None else []) + (
        breaking_load_warnings(sc, results) + tugger_pretension_warnings(sc, results) if sc is not None else [])
    if recorder is not None:
        check = getattr(recorder, "energy_check", None)
        duration = float(results.time[-1] - results.time[0]) if len(results.time) else 0.0
        warnings += [w for w in (check.warning() if check is not None else None,
                                 halving_warning(results.counters or {}, duration)) if w]
        recovery = getattr(recorder, "recovery", None)
        warnings += recovery.warnings() if recovery is not None else []
    for w in warnings:
        log.warning("dynamics: %s", w)
    # a duration the output interval does not divide: logged when the run was scheduled
    # (rfesim.solvers.dynamics.output_schedule); the results' message keeps it too
    dyn = sc.analysis.dynamics if sc is not None else None
    schedule = (output_interval_warning(float(dyn.duration), float(dyn.output_interval))
                if dyn is not None and dyn.output_interval else None)
    return "".join(f"{DYNAMICS_WARNING}{w}" for w in [schedule] * bool(schedule) + warnings)


def _straightener_warnings(system, state, results, sc) -> list[str]:
    """The straightener supports whose elasto-plastic pipe, gone through them during the run,
    keeps a residual curvature above rfesim.straightening.STRAIGHTNESS_LIMIT (its value, bend
    radius and sense, and the offset field to set), logged."""
    if not system.km.has_plastic or not any(s.kind == "straightener" for s in (sc.supports or {}).values()):
        return []
    from .straightening import straightener_warnings
    warnings = straightener_warnings(system, state, results, sc)
    for w in warnings:
        log.warning("dynamics: %s", w)
    return warnings


def modes(scenario, n: int | None = None) -> ModalResults:
    """Natural frequencies (Hz) and mode shapes about the static equilibrium.

    The statics is solved for them also when analysis.statics.enabled is false (which only
    skips the statics before a run's dynamics); ModalResults.message then says so.

    n: the number of lowest modes, a positive integer (default analysis.modal.modes, else
    10; ScenarioError naming n otherwise); above the number of moving coordinates all modes
    are given and ModalResults.message says so. Unstable modes have negative frequencies
    (see ModalResults)."""
    sc = _scenario(scenario)
    from .solvers.modal import checked_mode_count
    nmodes = checked_mode_count(n, default=sc.analysis.modal.modes if sc.analysis.modal else 10)
    _compile_ahead()
    if _other_formulations(sc):
        from .formulations import scene
        return scene.modes(sc, nmodes)
    system = System(compile_scenario(sc))
    # about the static equilibrium also when analysis.statics.enabled is false (the note says so)
    try:
        state, _ = _static_state(system, sc)
    except SolverError as exc:
        raise statics_failed(exc, sc) from None
    md = modal_analysis(system, state, nmodes)
    md.message = join_notes(statics_disabled_note(sc), locked_note(sc), md.message)
    return md
