"""The reel-lay template scenario (scenarios/reel_lay.json) through statics and dynamics.

A 12.75 in x 0.625 in X65 pipe (elasto-plastic) comes off an 8 m reel, over the aligner,
through the straightener and the tensioner on a 70 deg ramp, down 300 m to the seabed.

* Statics against the natural catenary with the ramp's horizontal lay tension H: H at the
  seabed end, the touchdown point within the bending boundary layer sqrt(EI/H), the top
  tension (past the tensioner exit) within w sqrt(EI/H), the departure angle = ramp angle;
  the reel holds its back tension where the pipe leaves the drum.
* Dynamics with payout (reel and tensioner by one table): the recorded payouts follow the
  table; the material that left the reel and the material that went out past the tensioner
  exit both equal the payout (the pipe's mass on the reel + on the ramp + outboard is
  conserved, no RFE is made or lost); the top tension starts without a transient (the
  first second equals statics).
* Slow: a faster payout takes pipe that was bent plastically over the aligner through the
  straightener: what it keeps of its residual curvature is small.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

import rfesim
from rfesim.catenary import natural_catenary
from rfesim.lay_results import _rotation, lay_summary
from rfesim.scenario import expand, parse_text

PATH = "scenarios/reel_lay.json"
G, RHO_W = 9.81, 1025.0
D, T_WALL, E, RHO = 0.3239, 0.0159, 2.07e11, 7850.0
AREA = math.pi / 4 * (D ** 2 - (D - 2 * T_WALL) ** 2)
MASS = RHO * AREA                                           # 120.7 kg/m
W_AIR = MASS * G
W_SUB = W_AIR - RHO_W * math.pi / 4 * D ** 2 * G            # 356.25 N/m
EI = E * math.pi / 64 * (D ** 4 - (D - 2 * T_WALL) ** 4)
RAMP = 70.0
# the test's payout: held 0.5 s, then the speed rises on a half cosine to 0.3 m/s in 3 s
ROWS = [[0.0, 0.0]] + [[0.5 + 0.25 * i, 0.15 * (0.25 * i - 3.0 / math.pi * math.sin(math.pi * 0.25 * i / 3.0))]
                       for i in range(13)] + [[20.0, 0.45 + 0.3 * (20.0 - 3.5)]]     # 5.4 m: within the reel


def catenary_numbers():
    """(H, h, natural catenary) of the template: H from the ramp angle at the exit, the
    pipe's weight in air over the 2 m above the water (sec(angle) = 1 + W / H)."""
    z_bed = -300.0 + D / 2 - W_SUB / 1e6                    # the laid pipe's axis
    h = 2.0 - z_bed                                         # ramp exit at z = 2 m
    c = math.cos(math.radians(RAMP))
    W = W_SUB * (h - 2.0) + W_AIR * 2.0
    H = W * c / (1 - c)                                     # 56.76 kN (55.89 with w h)
    return H, h, z_bed, natural_catenary(W_SUB, h, H)


def run(duration, rows, overrides=None):
    o = {"analysis.dynamics.duration": duration, "analysis.dynamics.output_interval": 0.25,
         "pipelay.lay.tensioner": {"payout": {"kind": "table", "rows": rows}}}
    o.update(overrides or {})
    return rfesim.simulate(rfesim.load_scenario(PATH, overrides=o))


@pytest.fixture(scope="module")
def short():
    return run(5.0, ROWS)


def crossing(pos, s, point, normal):
    """Arc length where the polyline (pos, s) crosses the plane through point, normal to normal."""
    f = (pos - point) @ normal
    k = np.flatnonzero((f[:-1] < 0.0) & (f[1:] >= 0.0))
    assert len(k) == 1
    k = k[0]
    return s[k] + (s[k + 1] - s[k]) * (-f[k]) / (f[k + 1] - f[k])


def test_statics_match_the_natural_catenary(short):
    H_given, h, z_bed, nat = catenary_numbers()
    layer = math.sqrt(EI / H_given)                         # 26 m
    line = short.line("lay")
    H = -line.end_b_force[0][0]                             # the grounded pipe carries H to end B
    assert H == pytest.approx(H_given, rel=0.05)
    assert line.touchdown_position[0][0] == pytest.approx(nat["horizontal_span"], abs=layer)
    out = lay_summary(short)
    # top tension just past the tensioner exit: H, the submerged weight up to the surface and
    # the weight in air above it, within w sqrt(EI/H) of the catenary with the settled H
    expected = H + W_SUB * (0.0 - z_bed) + W_AIR * 2.0
    assert out["top_tension"][0] == pytest.approx(expected, abs=W_SUB * layer)
    assert out["top_tension"][0] == pytest.approx(expected - H + H_given, rel=0.05)
    assert out["departure_angle"][0] == pytest.approx(RAMP, abs=1.0)
    # the reel holds its back tension (10 % of the catenary's top tension) where the pipe
    # leaves the drum: the pipe is pulled over the aligner, not pushed
    data = expand(parse_text(open(PATH).read(), "json"))
    reel = data["supports"]["lay_reel"]
    assert reel["back_tension"] == pytest.approx(0.1 * (H_given + W_SUB * (h - 2.0) + W_AIR * 2.0))
    take_off = np.asarray(reel["centre"]) + [0.0, 0.0, reel["radius"]]
    pts = np.asarray(line.position[0])[1:-1]
    past = np.flatnonzero(pts[:, 0] > take_off[0])
    first = past[np.argmin(np.linalg.norm(pts[past] - take_off, axis=1))]
    assert line.tension[0][first] == pytest.approx(reel["back_tension"], rel=0.011)
    tension_ramp = np.asarray(line.tension[0])[first:first + 18]       # aligner, straightener, tensioner
    # down the ramp the pipe's weight takes the back tension off (1.1 kN/m), to about zero at
    # the tensioner, which holds the catenary: no compression to speak of
    assert tension_ramp.min() > -0.05 * reel["back_tension"]


def test_top_tension_is_read_at_the_tensioner_exit(short):
    """The top tension of the reel-lay line is the free span's tension at the tensioner's
    exit, H + w (0 - z_bed) + w_air 2 m with the settled H (163.6 kN in the auditor's run),
    to 0.3 kN; before, the first SDE past the exit's, an element (2 m of pipe in air at 70
    deg, 2.2 kN) below it: 161.4 kN."""
    _, _, z_bed, _ = catenary_numbers()
    line = short.line("lay")
    H = -line.end_b_force[0][0]
    top = lay_summary(short)["top_tension"]
    assert top[0] == pytest.approx(H + W_SUB * (0.0 - z_bed) + W_AIR * 2.0, abs=300.0)


def test_payout_follows_the_law_and_conserves_the_pipe(short):
    t = np.asarray(short.time)
    law = PchipInterpolator(*np.asarray(ROWS).T)(t)
    tens = np.asarray(short.tensioners["lay_tensioner"].payout)
    reel = np.asarray(short.reels["lay_reel"].payout)
    np.testing.assert_allclose(tens, law, atol=1e-12)
    np.testing.assert_allclose(reel - reel[0], law, atol=1e-12)    # statics turned the drum by reel[0]
    assert 0.0 < reel[0] < 0.25 and law[-1] > 0.85                  # (10 cm for 16 kN back tension)
    data = expand(parse_text(open(PATH).read(), "json"))
    sup = data["supports"]
    take_off = np.asarray(sup["lay_reel"]["centre"]) + [0.0, 0.0, sup["lay_reel"]["radius"]]
    e = np.asarray(sup["lay_tensioner"]["axis"])
    exit_ = np.asarray(sup["lay_tensioner"]["entry"]) + sup["lay_tensioner"]["length"] * e
    line = short.line("lay")
    vessel = short.vessels["reeler"]
    s = np.asarray(line.arc_length)
    off_reel, outboard = [], []
    for k in range(len(t)):
        p = np.asarray(line.position[k])
        Rv, pv = _rotation(vessel.rotation[k]), np.asarray(vessel.position[k])     # the vessel's pose
        off_reel.append(crossing(p, s, pv + Rv @ take_off, Rv @ np.array([1.0, 0.0, 0.0])))
        outboard.append(crossing(p, s, pv + Rv @ exit_, Rv @ e))
    ramp = np.asarray(outboard) - np.asarray(off_reel)       # material arc length between drum and exit
    # material moves out: the points at the take-off and at the exit are material that was
    # further up the line (smaller arc length from end A on the reel)
    off_reel = off_reel[0] - np.asarray(off_reel)
    outboard = outboard[0] - np.asarray(outboard)
    # pipe leaves the reel and goes out past the tensioner as the payout says (elastic
    # stretch and the grip springs: within 2 cm)
    np.testing.assert_allclose(off_reel, law, atol=0.02)
    np.testing.assert_allclose(outboard, law, atol=0.02)
    # mass: what the reel loses goes outboard; the pipe on the ramp keeps its mass; the
    # line keeps every RFE (mass on reel + ramp + outboard = MASS * length at all times)
    assert MASS * np.abs(ramp - ramp[0]).max() < MASS * 0.02
    assert np.asarray(line.position).shape == (len(t), len(s), 3)
    assert MASS * float(s[-1]) == pytest.approx(MASS * data["lines"]["lay"]["length"], rel=1e-12)


def test_top_tension_starts_without_a_transient(short):
    t = np.asarray(short.time)
    top = lay_summary(short)["top_tension"]
    held = t <= 0.5                                          # before the payout starts
    assert np.abs(top[held] / top[0] - 1.0).max() < 2e-3
    # paying out: the catenary eases as pipe goes in and accelerates down (a smooth dip of
    # about 10 %); no ringing (a payout that starts with a jump of acceleration, 0.5 m/s^2,
    # swings it by +-40 % every 0.3 s)
    assert np.abs(np.diff(top)).max() < 0.04 * top[0]
    assert np.abs(top / top[0] - 1.0).max() < 0.15
    # the reel keeps a back tension: the pipe is pulled, not pushed, over the aligner
    line = short.line("lay")
    stored = expand(parse_text(open(PATH).read(), "json"))["supports"]["lay_reel"]["stored_length"]
    first = int(np.argmin(np.abs(np.asarray(line.sde_arc_length) - (stored + 0.2))))   # just off the drum
    assert np.asarray(line.tension)[:, first].min() > 0.2 * np.asarray(line.tension)[0, first] > 0.0


@pytest.mark.slow
def test_straightener_takes_out_the_aligner_bend():
    """0.5 m/s for 30 s: pipe bent plastically over the aligner at the start (virgin pipe in
    the start shape) goes through the straightener (offset 0: held straight)."""
    rows = [[0.0, 0.0], [1.0, 0.0], [3.0, 0.5], [5.0, 1.5], [31.0, 1.5 + 26.0 * 0.5]]     # within the reel
    res = run(30.0, rows)
    assert res.success
    line = res.line("lay")
    rc = np.asarray(line.residual_curvature)
    s_sde = np.asarray(line.sde_arc_length)
    pts = np.asarray(line.position)[:, 1:-1]
    data = expand(parse_text(open(PATH).read(), "json"))
    st = data["supports"]["lay_straightener"]
    e = np.asarray(st["axis"])
    last_roller = np.asarray(st["entry"]) + st["span"] * e
    bent = rc[0] > 0.02                                      # over the aligner at the start
    through = bent & ((pts[-1] - last_roller) @ e > 0.2)     # and now behind the straightener
    assert through.sum() >= 2, s_sde[bent]
    assert rc[-1, through].max() < 0.25 * rc[0, through].min()
    out = lay_summary(res)
    assert np.all(np.isfinite(out["top_tension"])) and out["departure_angle"][-1] == pytest.approx(RAMP, abs=1.5)
