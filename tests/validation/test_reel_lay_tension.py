"""Reel-lay template given the lay tension (rfesim.solvers.lay_statics, docs/theory.md,
"Pipelay templates", statics and the lay tension).

The template given `tension` sets it as the tensioner's `horizontal_tension`: statics pays
the elasto-plastic pipe through the tensioner (the reel turning with it) until the pipe
carries H to its pinned end B. Before, the reel-lay template held the catenary's length
and H settled 3 % low (53.27 kN for 54.9 kN).

* H at end B is the given tension to 0.1 %; the payout hauls in about the catenary's
  estimate (H - H0) / (dH/dL).
* The settled plastic state is one step from the t = 0 history (reeled pipe on the drum,
  virgin pipe elsewhere): the shifts and drum turns add no plastic cycle. Exact identity:
  the committed history equals the return mapping of the t = 0 history to the settled
  state's curvatures.
* Newton starts each shift from the line slid along itself (``slide_line``): up to the
  tensioner's exit the centres stay on the path (distances between neighbours kept to
  2 mm, the largest change 1.7 mm at the half element of end A; sliding along the chords
  between the centres changes them by 11-15 mm on the 9 m aligner and the 8 m drum with
  2 m elements: 0.01 x EA / l = 8 MN in the axial springs).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.api import _static_state
from rfesim.catenary import natural_catenary
from rfesim.model.compile import compile_scenario
from rfesim.scenario import expand, parse_text
from rfesim.solvers.system import System

PATH = "scenarios/reel_lay.json"
G, RHO_W = 9.81, 1025.0
D, T_WALL = 0.3239, 0.0159
AREA = math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)
W_SUB = 7850.0 * AREA * G - RHO_W * math.pi / 4 * D ** 2 * G            # 356.25 N/m
TENSION = 54.9e3
GIVEN = {"pipelay.lay.ramp_angle_deg": None, "pipelay.lay.tension": TENSION}


def _scenario(overrides=None):
    o = dict(GIVEN)
    o.update(overrides or {})
    return rfesim.load_scenario(PATH, overrides=o)


@pytest.fixture(scope="module")
def settled():
    return rfesim.statics(_scenario())


def test_reel_lay_given_tension_sets_the_tensioners_horizontal_tension():
    data = expand(parse_text(open(PATH).read(), "json"))
    assert "horizontal_tension" not in data["supports"]["lay_tensioner"]        # given the ramp angle
    raw = parse_text(open(PATH).read(), "json")
    raw["pipelay"]["lay"].pop("ramp_angle_deg")
    raw["pipelay"]["lay"]["tension"] = TENSION
    data = expand(raw)
    assert data["supports"]["lay_tensioner"]["horizontal_tension"] == TENSION


def test_reel_lay_given_tension_carries_it_to_end_b(settled):
    line = settled.line("lay")
    H = -line.end_b_force[0][0]                       # the laid pipe carries H to end B
    assert H == pytest.approx(TENSION, rel=1e-3)      # before: 53.27 kN (-3 %)
    # the payout hauls in about what the natural catenary's slope says: the pipe held at the
    # catenary's length carried 53.27 kN (the stiffened catenary); dH/dL = w / (dL/da)
    z_bed = -300.0 + D / 2 - W_SUB / 1e6
    h = 2.0 - z_bed
    a = TENSION / W_SUB
    s = math.sqrt(h * h + 2 * a * h)
    slope = W_SUB / (h / s - math.acosh(1 + h / a) + math.sqrt((h / a) / (2 + h / a)))   # -1044 N/m
    payout = float(settled.tensioners["lay_tensioner"].payout[0])
    assert payout == pytest.approx(-(53.27e3 - TENSION) / slope, rel=0.15)            # -1.45 m
    reel = float(settled.reels["lay_reel"].payout[0])
    assert reel < payout + 0.3                        # the reel turned with it (and to its back tension)
    # the touchdown point of the catenary with the given H, within sqrt(EI/H)
    EI = 2.07e11 * math.pi / 64 * (D ** 4 - (D - 2 * T_WALL) ** 4)
    nat = natural_catenary(W_SUB, h, TENSION)
    assert line.touchdown_position[0][0] == pytest.approx(nat["horizontal_span"], abs=math.sqrt(EI / TENSION))


def test_settled_plastic_state_is_one_step_from_the_reeled_start():
    sc = _scenario()
    system = System(compile_scenario(sc))
    state, _info = _static_state(system, sc)
    li = system.model.lines[0]
    ws = system.ws
    lo, hi = li.sde_start, li.sde_stop
    got = ws.plastic_hist[lo:hi].copy()
    hist0 = system.model.initial_plastic_history
    assert np.abs(hist0[lo:hi]).max() > 0.0                       # reeled pipe on the drum
    # one return mapping from the t = 0 history to the settled curvatures
    ws.plastic_hist[:] = hist0
    system.evaluate(state)
    one_step = ws.plastic_hist_trial[lo:hi]
    assert np.abs(got - one_step).max() <= 1e-9 * np.abs(one_step).max()
    assert np.abs(got - hist0[lo:hi]).max() > 0.0                # the pipe off the drum did yield


def test_slide_keeps_the_pipe_on_its_path():
    from rfesim.solvers.lay_statics import slide_line
    sc = rfesim.load_scenario(PATH)                               # ramp angle: no shifts
    system = System(compile_scenario(sc))
    state, _info = _static_state(system, sc)
    li = system.model.lines[0]
    j = system.model.tensioners[0].index
    km, att = system.km, system.att

    def centres(st):
        system.evaluate(st)
        return system.ws.r[li.rfe_start:li.rfe_stop].copy()

    r0 = centres(state)
    a = km.tens_att[j]
    exit_p = att.p[a] + att.R[a] @ (km.tens_point[j] + km.tens_length[j] * km.tens_axis[j])
    kx = int(np.argmin(np.linalg.norm(r0 - exit_p, axis=1)))
    gaps0 = np.linalg.norm(np.diff(r0[:kx + 1], axis=0), axis=1)
    for delta in (0.5, -0.5, 1.0):
        r1 = centres(slide_line(system, state, li, j, delta))
        gaps1 = np.linalg.norm(np.diff(r1[:kx + 1], axis=0), axis=1)
        np.testing.assert_allclose(gaps1, gaps0, atol=2e-3)
        moved = np.linalg.norm(r1[1:kx] - r0[1:kx], axis=1)      # each centre moved by about delta
        np.testing.assert_allclose(moved, abs(delta), rtol=0.02)
        assert np.array_equal(r1[-1], r0[-1])                     # end B stays
