"""Closing joins (rfesim.model.joins, rfesim.scenario.joins): end B of a line joined to end B of
another closes a loop -- a portal frame of two columns and a crossbeam in two halves. The
closing SDE couples two RFEs that are not neighbours; the Newton matrix is the band plus two
off-band blocks, solved by the Woodbury identity (rfesim.solvers.banded.bt_factor_closed).

Checked: the portal's sway under a side load against slope-deflection theory, its base
reactions against the load (an exact identity), the Woodbury solve against a dense solve,
energy conservation of the undamped portal in dynamics, its sway period (modal analysis and
a free vibration) against the rigid-beam closed form, and the errors of bad closures."""
from __future__ import annotations

import copy
import math

import numpy as np
import pytest

import rfesim
from rfesim.errors import ScenarioError
from rfesim.model.compile import compile_scenario
from rfesim.model.energy import mechanical_energy
from rfesim.solvers.banded import bt_factor_closed, bt_solve_closed, bt_to_dense
from rfesim.solvers.dynamics import run_dynamics
from rfesim.solvers.statics import solve_statics
from rfesim.solvers.system import System

HEIGHT, SPAN, EI_COLUMN, EI_BEAM, PUSH = 6.0, 8.0, 2.0e7, 3.0e7, 1000.0


def beam(EI, EA=1.0e11, GJ=1.0e7, mass=50.0):
    return {"EA": EA, "EIy": EI, "EIz": EI, "GJ": GJ, "mass_per_length": mass}


def portal(n: int, ei_beam: float = EI_BEAM, beam_mass: float = 50.0, push: float = PUSH,
           connection: str = "clamped") -> dict:
    """Columns clamped at x = 0 and x = SPAN, crossbeam halves from their tops to mid-span,
    the second closing onto the first; a side push at mid-span, no gravity."""
    return {
        "environment": {"gravity": 0.0},
        "line_types": {"column": beam(EI_COLUMN), "crossbeam": beam(ei_beam, mass=beam_mass)},
        "lines": {
            "left": {"type": "column", "length": HEIGHT, "elements": n,
                     "end_a": {"attach": "fixed", "position": [0, 0, 0], "direction": [0, 0, 1],
                               "connection": "clamped"}},
            "beam_l": {"type": "crossbeam", "length": SPAN / 2, "elements": n,
                       "end_a": {"attach": "left:end_b", "connection": "clamped", "direction": [1, 0, 0]},
                       "loads": [{"at": "end_b", "force": [push, 0, 0]}]},
            "right": {"type": "column", "length": HEIGHT, "elements": n,
                      "end_a": {"attach": "fixed", "position": [SPAN, 0, 0], "direction": [0, 0, 1],
                                "connection": "clamped"}},
            "beam_r": {"type": "crossbeam", "length": SPAN / 2, "elements": n,
                       "end_a": {"attach": "right:end_b", "connection": "clamped", "direction": [-1, 0, 0]},
                       "end_b": {"attach": "beam_l:end_b", "connection": connection}}},
        "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}}}


def sway_exact(ei_beam: float = EI_BEAM) -> float:
    """Sway of a fixed-base portal under a side load H at the beam (slope deflection, rigid
    joints, no axial or shear strain): H h^3 (2 + 3k) / (EI_c (12 + 72 k)), k = (EI_b/L)/(EI_c/h)."""
    k = (ei_beam / SPAN) / (EI_COLUMN / HEIGHT)
    return PUSH * HEIGHT ** 3 * (2.0 + 3.0 * k) / (EI_COLUMN * (12.0 + 72.0 * k))


def test_portal_sway_and_base_reactions_against_slope_deflection():
    """Sway within 0.2 % of slope-deflection theory at 8 and 16 elements per member (measured
    +0.18 % and +0.09 %: first order, the joints' finite stiffness); the closure carries the
    load across (the columns' horizontal base reactions add up to the push, exactly) and the
    joints turn by theta = 3 psi / (2 + 3 k)."""
    errors = []
    for n in (8, 16):
        res = rfesim.statics(portal(n))
        tip = res.line("beam_l").position[0, -1]
        errors.append((tip[0] - SPAN / 2) / sway_exact() - 1.0)
        left, right = res.line("left"), res.line("right")
        # both columns sway alike (the beam is axially rigid): their tops move together
        assert left.position[0, -1][0] == pytest.approx(right.position[0, -1][0] - SPAN, rel=1e-3)
        # base reactions: the pushes of the columns on the ground add up to the push
        fx = left.end_a_force[0][0] + right.end_a_force[0][0]
        assert fx == pytest.approx(PUSH, rel=1e-6)
        assert abs(left.end_a_force[0][2] + right.end_a_force[0][2]) < 1e-6 * PUSH
        # the closing end reports the closure's load: the right half pushes the left half's
        # end with the share of the push the right column takes (half of it, by antisymmetry)
        cl = res.line("beam_r").end_b_force[0]
        assert cl[0] == pytest.approx(-right.end_a_force[0][0], rel=1e-3)
    assert abs(errors[0]) < 2e-3 and abs(errors[1]) < 2e-3
    assert abs(errors[1]) < abs(errors[0])


def test_pinned_closure_is_a_portal_with_a_hinge_at_mid_span():
    """A pinned closure carries no moment: under antisymmetric sway the crossbeam's moment is
    zero at mid-span anyway, so the sway is the same (within 1e-4), but a symmetric vertical
    load at mid-span now bends each half as a cantilever from its column's top."""
    clamped = rfesim.statics(portal(8))
    pinned = rfesim.statics(portal(8, connection="pinned"))
    dc = clamped.line("beam_l").position[0, -1][0] - SPAN / 2
    dp = pinned.line("beam_l").position[0, -1][0] - SPAN / 2
    assert dp == pytest.approx(dc, rel=1e-4)
    assert np.linalg.norm(pinned.line("beam_r").end_b_moment[0]) < 1e-6 * PUSH * SPAN
    assert np.linalg.norm(clamped.line("beam_r").end_b_moment[0]) < 1e-5 * PUSH * SPAN   # measured 1.7e-6
    down = portal(8)
    down["lines"]["beam_l"]["loads"] = [{"at": "end_b", "force": [0, 0, -PUSH]}]
    m_clamped = rfesim.statics(down).line("beam_r").end_b_moment[0]
    down["lines"]["beam_r"]["end_b"]["connection"] = "pinned"
    m_pinned = rfesim.statics(down).line("beam_r").end_b_moment[0]
    assert abs(m_clamped[1]) > 0.05 * PUSH * SPAN / 2 and np.linalg.norm(m_pinned) < 1e-6 * PUSH * SPAN


def test_woodbury_solve_against_a_dense_solve():
    """bt_factor_closed / bt_solve_closed against numpy's dense solve of the same matrix (the
    band of the analytic static Jacobian plus the closure's off-band blocks)."""
    sc = rfesim.Scenario.model_validate(portal(4))
    system = System(compile_scenario(sc))
    km, ws = system.km, system.ws
    J = system.static_jacobian_analytic(system.model.initial.q, system.model.initial.ref).copy()
    mask = system.mask
    for i in range(system.n):                       # clamped bases: identity rows, as statics does
        for a in range(6):
            if not mask[i, a]:
                J[i, :, a, :] = 0.0
                J[i, :, :, a] = 0.0
                J[i, 1, a, a] = 1.0
    A = bt_to_dense(J)
    s = int(km.cl_sde[0])
    a, b = int(km.sde_left[s]), int(km.sde_right[s])
    assert abs(b - a) > 1
    A[6 * a:6 * a + 6, 6 * b:6 * b + 6] += ws.cl_J[0, 0]
    A[6 * b:6 * b + 6, 6 * a:6 * a + 6] += ws.cl_J[0, 1]
    assert np.abs(ws.cl_J[0]).max() > 1e6
    rng = np.random.default_rng(7)
    rhs = rng.standard_normal((system.n, 6)) * mask          # forces on the moving coordinates
    Fac = np.zeros_like(J)
    assert bt_factor_closed(J, Fac, km, ws) == -1
    x = np.zeros_like(rhs)
    bt_solve_closed(Fac, rhs, x, km, ws)
    ref = np.linalg.solve(A, rhs.ravel()).reshape(-1, 6)
    # the matrix is ill-conditioned (EA 1e11 against the rotations): compare the backward
    # errors (measured 2.4e-14 for Woodbury on the block LU, 3.7e-17 for the dense LU with
    # pivoting; a Newton step needs far less) and the solutions to the conditioning
    def backward(z):
        return np.abs(A @ z.ravel() - rhs.ravel()).max() / (np.abs(A).sum(axis=1).max() * np.abs(z).max()
                                                             + np.abs(rhs).max())
    assert backward(x) <= 1e-12
    assert np.abs(x - ref).max() <= 1e-5 * np.abs(ref).max()
    # the band alone is a different matrix: the closure matters
    y = np.linalg.solve(bt_to_dense(J), rhs.ravel()).reshape(-1, 6)
    assert np.abs(y - ref).max() > 0.1 * np.abs(ref).max()


def _dynamic(data: dict, duration: float, dt: float, rho_inf: float = 1.0) -> dict:
    data = copy.deepcopy(data)
    data["analysis"] = {"statics": {"enabled": False},
                        "dynamics": {"enabled": True, "duration": duration, "output_interval": dt,
                                     "integrator": {"kind": "generalized-alpha", "time_step": dt,
                                                    "rho_inf": rho_inf, "tolerance": 1e-10}}}
    return data


def test_undamped_portal_conserves_energy_released_under_a_push():
    """The unloaded portal released under a dead side push (rho_inf = 1, no damping): kinetic
    + strain - work of the push stays within 1e-4 of the largest strain energy over 2 s
    (several sway periods), while the sway swings between 0 and twice the static one."""
    sc = rfesim.Scenario.model_validate(_dynamic(portal(6), 2.0, 0.002))
    system = System(compile_scenario(sc))
    start = system.model.initial.copy()
    e0 = mechanical_energy(system, start).total
    end, rec, _ = run_dynamics(system, start, sc.analysis.dynamics)
    e1 = mechanical_energy(system, end)
    sway = rec.results().line("beam_l").position[:, -1, 0] - SPAN / 2
    static = sway_exact()
    assert sway.max() == pytest.approx(2.0 * static, rel=0.03)
    strain_max = PUSH * 2.0 * static                   # the push's work at the largest sway
    assert abs(e1.total - e0) < 1e-4 * strain_max
    assert e1.kinetic > 0.0


def test_portal_sway_period_modal_and_free_vibration():
    """A heavy, nearly rigid crossbeam (16 t, EI_b = 1e4 EI_c) on light columns: the sway period
    is 2 pi sqrt(M / K) with K = 24 EI_c / h^3 and M the beam plus 13/35 of each column (the
    consistent mass of a guided column). Modal analysis within 0.5 % (measured +0.16 %), and a
    free vibration's period within 1 % of the modal one."""
    data = portal(8, ei_beam=1.0e4 * EI_COLUMN, beam_mass=2000.0, push=0.0)
    mass = 2000.0 * SPAN + 2.0 * 13.0 / 35.0 * 50.0 * HEIGHT
    period = 2.0 * math.pi * math.sqrt(mass * HEIGHT ** 3 / (24.0 * EI_COLUMN))
    modes = rfesim.modes(data, 4)
    # the in-plane sway: the mode that moves mid-span along x (the first is out of plane)
    tip = modes.line_shapes["beam_l"][:, -1]
    k = int(np.argmax(np.abs(tip[:, 0]) / (np.linalg.norm(tip, axis=1) + 1e-300)))
    assert abs(tip[k, 0]) > 0.99 * np.linalg.norm(tip[k])
    modal = float(modes.periods_s[k])
    assert modal == pytest.approx(period, rel=5e-3)
    # free vibration from the static sway under the push, released at t = 0
    sc = rfesim.Scenario.model_validate(_dynamic(portal(8, ei_beam=1.0e4 * EI_COLUMN, beam_mass=2000.0),
                                                 3.0 * period, period / 200.0))
    system = System(compile_scenario(sc))
    state, _ = solve_statics(system)
    sc2 = rfesim.Scenario.model_validate(_dynamic(data, 3.0 * period, period / 200.0))
    system2 = System(compile_scenario(sc2))
    _, rec, _ = run_dynamics(system2, state, sc2.analysis.dynamics)
    r = rec.results()
    x = r.line("beam_l").position[:, -1, 0] - SPAN / 2
    t = r.time
    up = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    crossings = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    assert len(crossings) >= 2
    measured = float(np.mean(np.diff(crossings)))
    assert measured == pytest.approx(modal, rel=1e-2)


@pytest.mark.parametrize("change, field, words", [
    (lambda d: d["lines"]["beam_r"]["end_b"].update(attach="nowhere:end_b"), "lines.beam_r.end_b.attach",
     "unknown line 'nowhere'"),
    (lambda d: d["lines"]["beam_r"]["end_b"].update(attach="beam_r:end_b"), "lines.beam_r.end_b.attach",
     "its own end B"),
    (lambda d: d["lines"]["beam_r"]["end_b"].update(position=[4.0, 0.0, 6.5]), "lines.beam_r.end_b.position",
     "m from end B of line 'beam_l' it is joined to"),
    (lambda d: d["analysis"].update(dynamics={"enabled": True, "duration": 1.0, "integrator": {
        "kind": "generalized-alpha", "jacobian": "finite-difference"}}),
     "analysis.dynamics.integrator.jacobian", "analytic Jacobian"),
    (lambda d: d["lines"]["beam_r"]["end_b"].update(drives=[{"name": "x", "axis": [0, 0, 1], "angle": [[0, 0], [1, 5]]}]),
     "lines.beam_r.end_b.drives", "takes no drives"),
])
def test_bad_closures_are_refused_naming_the_field(change, field, words):
    data = portal(4)
    change(data)
    with pytest.raises(ScenarioError) as err:
        rfesim.statics(data)
    assert field in str(err.value) and words in str(err.value)
