"""Statics of slack lines whose start shape used to be wrong (rfesim.model.compile; docs/theory.md,
section 6, 'Start shapes of clamped and buoyant slack lines' and 'Soft fem shear under tension').

* A flexible line clamped horizontally at end A and pinned 5 m away (20 m long, lots of slack)
  failed from the straight and the catenary start: the catenary leaves A steeply, the clamped
  end RFE points along the clamp, and the frames of all the other RFEs were transported from the
  clamp's frame along the chord tangents, so every element was turned away from its own chord
  by the angle between them (residual 9.6e5 x force scale at the start).
* A slightly buoyant slack tether started from a downward sag (the catenary start needs a
  positive weight), which is the inverted, compressed arch: statics found that unstable
  equilibrium or failed.
* With the fem shear (eq. 8.89) a chain of rigid elements under a tension above 12 EI / Delta^2
  shears apart: then statics says so and what to do.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim
from rfesim.catenary import solve_catenary
from rfesim.model.compile import compile_scenario

G = 9.81
RHO = 1025.0
LENGTH = 20.0
MASS = 10.0                # kg/m, a small steel pipe
D = 0.05                   # m
Z0 = -10.0                 # m, height of both ends


def clamped_line(EI: float, water: bool, *, start: str = "auto", elements: int = 20, span: float = 5.0) -> dict:
    """20 m clamped horizontally at end A, pinned at end B ``span`` away at the same height."""
    env = {"gravity": G}
    if water:
        env["water"] = {"density": RHO, "depth": 100.0}
    return {"name": "clamped slack line", "environment": env,
            "line_types": {"flex": {"EA": 1.0e8, "EIy": EI, "mass_per_length": MASS, "outer_diameter": D}},
            "lines": {"l": {"type": "flex", "length": LENGTH, "elements": elements,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, Z0], "direction": [1.0, 0.0, 0.0],
                                      "connection": "clamped"},
                            "end_b": {"attach": "fixed", "position": [span, 0.0, Z0], "connection": "pinned"}}},
            "analysis": {"statics": {"enabled": True, "start": start}}}


def wet_weight(water: bool) -> float:
    """N/m"""
    return MASS * G - (RHO * G * math.pi / 4.0 * D * D if water else 0.0)


def end_forces(res, name: str = "l"):
    line = res.line(name)
    return tuple(np.asarray(getattr(line, a)[0]) for a in ("end_a_force", "end_b_force", "end_a_moment"))


@pytest.mark.parametrize("EI, water", [(100.0, False), (1000.0, False), (100.0, True), (1000.0, True)])
def test_clamped_slack_line_hangs(EI, water):
    """It converges from the catenary start to a line hanging in a U: the ends carry its whole
    wet weight, and the clamp, which holds it horizontal where the catenary leaves at 85.6 deg
    below the horizontal, takes the moment of the tensioned elastica's boundary layer,
    M = 2 sqrt(EI T) sin(theta / 2) (from EI theta'^2 / 2 = T (1 - cos theta)), the way a
    cantilever hanging down loads its wall."""
    res = rfesim.statics(rfesim.load_scenario(clamped_line(EI, water, start="catenary")))
    assert res.status == 0 and res.counters["newton_iterations"] < 100
    fa, fb, ma = end_forces(res)
    w = wet_weight(water)
    assert fa[2] + fb[2] == pytest.approx(-w * LENGTH, rel=1e-6)
    assert abs(fa[0] + fb[0]) <= 1e-6 * w * LENGTH
    z = np.asarray(res.line("l").position[0])[:, 2]
    assert z.min() < Z0 - 8.0                                  # hangs (the catenary's sag is 9.1 m)
    cat = solve_catenary(5.0, 0.0, LENGTH, w, 1.0e8, seabed=False)
    theta = math.atan2(-cat.vertical_tension_anchor, cat.horizontal_tension)
    estimate = 2.0 * math.sqrt(EI * cat.anchor_tension) * math.sin(theta / 2.0)
    assert ma[1] > 0.0 and abs(ma[0]) + abs(ma[2]) <= 1e-9 * ma[1]      # the line pulls the clamp's tip down
    assert 0.8 * estimate < ma[1] < 1.25 * estimate


def test_clamped_slack_line_from_the_straight_start():
    """The straight start (a column compressed to the 5 m chord) fails, and statics goes on from
    the catenary start of the same model (the clamp's direction is given) to its equilibrium."""
    res = rfesim.statics(rfesim.load_scenario(clamped_line(1000.0, True, start="straight")))
    assert "so statics started from the catenary" in res.message
    ref = rfesim.statics(rfesim.load_scenario(clamped_line(1000.0, True, start="catenary")))
    for got, want in zip(end_forces(res), end_forces(ref)):
        assert np.abs(got - want).max() <= 1e-6 * np.abs(want).max()


def test_clamped_start_shape_follows_the_clamp():
    """The start: the clamped end RFE along the clamp's direction, the chain of the others on the
    catenary from its inner end, each RFE's axis along its own chord (no element turned away
    from it), and no gap at the SDE next to the clamp."""
    model = compile_scenario(rfesim.load_scenario(clamped_line(100.0, False, start="catenary")))
    R, X, ell = model.initial.ref.R, model.initial.ref.X, model.km.rfe_length
    left = X - 0.5 * ell[:, None] * R[:, :, 0]
    right = X + 0.5 * ell[:, None] * R[:, :, 0]
    assert np.allclose(R[0][:, 0], [1.0, 0.0, 0.0], atol=1e-12)
    gap = left[1:] - right[:-1]
    along = np.einsum("ij,ij->i", gap, R[:-1, :, 0])
    lateral = gap - along[:, None] * R[:-1, :, 0]
    # no element turned away from its chord: the gaps are the chord chain's closure error only
    # (compressed by 0.5 %, section 6), where a frame turned by the catenary's 86 deg at the
    # clamp opened gaps of half an element
    assert np.abs(lateral).max() < 0.01 * ell.max() and np.abs(along).max() < 0.01 * ell.max()
    assert R[1][2, 0] < -0.5                                          # the chain turns down right after the clamp


@pytest.mark.parametrize("EI", [1.0, 100.0])
def test_buoyant_slack_tether_floats_up(EI):
    """A tether 0.1 % lighter than the water it displaces, 20 m between anchors 15 m apart at
    50 m depth, floats up in the mirror image of the same tether 0.1 % heavier (the same net
    force per length the other way), pulling both anchors up by its net buoyancy. With
    EI = 1 N m^2 it is a catenary in tension; with EI = 100 N m^2 (Euler load 2.5 N against a net
    buoyancy of 1.6 N) a bent elastica a little in compression, either way up."""
    shapes = {}
    for ratio in (0.999, 1.001):
        m = ratio * RHO * math.pi / 4.0 * 0.1 ** 2
        data = {"name": "tether", "environment": {"gravity": G, "water": {"density": RHO, "depth": 100.0}},
                "line_types": {"t": {"EA": 1.0e7, "EIy": EI, "mass_per_length": m, "outer_diameter": 0.1}},
                "lines": {"t": {"type": "t", "length": 20.0, "elements": 20,
                                "end_a": {"attach": "fixed", "position": [0.0, 0.0, -50.0]},
                                "end_b": {"attach": "fixed", "position": [15.0, 0.0, -50.0]}}},
                "analysis": {"statics": {"enabled": True}}}
        res = rfesim.statics(rfesim.load_scenario(data))
        assert res.status == 0
        fa, fb, _ = end_forces(res, "t")
        net = (m - RHO * math.pi / 4.0 * 0.1 ** 2) * G * 20.0          # N, < 0 when buoyant
        assert fa[2] + fb[2] == pytest.approx(-net, rel=1e-6)            # the line pulls its anchors up
        assert fa[0] == pytest.approx(-fb[0], rel=1e-6)
        if EI == 1.0:
            assert fa[0] > 0.0                                         # a catenary: it pulls its anchors together
        shapes[ratio] = np.asarray(res.line("t").position[0])
    up, down = shapes[0.999], shapes[1.001]
    assert up[:, 2].min() >= -50.0 - 1e-9 and up[:, 2].max() > -50.0 + 5.0
    mirrored = down.copy()
    mirrored[:, 2] = -100.0 - down[:, 2]
    assert np.abs(up - mirrored).max() < 1e-6


def test_soft_fem_shear_under_tension_is_named():
    """EI = 10 N m^2 on 20 elements: the fem shear 12 EI / Delta^3 holds the chain in line up
    to 120 N only, and the hanging line carries ~980 N, so there is no stable equilibrium near
    its shape. Given the fem shear, the failure says so and what to do; by default the line
    takes the kruszewski shear (eq. 8.88) it suggests, and converges."""
    data = clamped_line(10.0, False, start="catenary")
    data["lines"]["l"]["shear_stiffness"] = "fem"
    with pytest.raises(rfesim.SolverError) as err:
        rfesim.statics(rfesim.load_scenario(data))
    hint = err.value.hint or ""
    assert "line 'l' uses the fem shear stiffness" in hint
    assert "12 EI / Delta^2 = 120 N" in hint
    assert "lines.l.elements" in hint and "lines.l.shear_stiffness to kruszewski" in hint
    sc = rfesim.load_scenario(clamped_line(10.0, False, start="catenary"))
    assert compile_scenario(sc).lines[0].shear_model == "kruszewski"
    res = rfesim.statics(sc)
    fa, fb, ma = end_forces(res)
    assert fa[2] + fb[2] == pytest.approx(-wet_weight(False) * LENGTH, rel=1e-6)
    assert ma[1] > 0.0


def hanging_line(EI: float, shear: str | None = None) -> dict:
    """100 m of 20 kg/m in air hanging between points 60 m apart on 20 elements (9.85 kN)."""
    line = {"type": "u", "length": 100.0, "elements": 20,
            "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0]},
            "end_b": {"attach": "fixed", "position": [60.0, 0.0, 0.0]}}
    if shear:
        line["shear_stiffness"] = shear
    return {"environment": {"gravity": G},
            "line_types": {"u": {"EA": 1e8, "EIy": EI, "mass_per_length": 20.0, "outer_diameter": 0.1}},
            "lines": {"u": line}, "analysis": {"statics": {"enabled": True}}}


@pytest.mark.parametrize("shear", [None, "kruszewski"])
def test_a_hanging_line_past_its_fem_shear_limit_takes_kruszewski(shear):
    """With EI = 1e4 N m^2 the fem shear holds 4.8 kN only (12 EI / Delta^2), and the line
    carries 9.85 kN. Given the fem shear, statics found a spurious equilibrium (hanging 18 m
    too deep at half the tension); by default the line takes the kruszewski shear and hangs
    as the elastic catenary does (its EI stiffens it by 0.6 %)."""
    sc = rfesim.load_scenario(hanging_line(1.0e4, shear))
    assert compile_scenario(sc).lines[0].shear_model == "kruszewski"
    res = rfesim.statics(sc)
    cat = solve_catenary(60.0, 0.0, 100.0, 20.0 * G, 1e8, seabed=False)
    fa, _, _ = end_forces(res, "u")
    assert abs(fa[0]) == pytest.approx(cat.horizontal_tension, rel=0.01)
    assert np.asarray(res.line("u").position[0])[:, 2].min() == pytest.approx(-36.15, abs=0.1)
    assert "warning" not in res.message


def test_a_line_within_its_fem_shear_limit_keeps_it():
    """With EI = 1e5 N m^2 the fem shear holds 48 kN: it stays the default, and both shears
    agree (EI bends the line 5 % off the catenary's horizontal tension)."""
    sc = rfesim.load_scenario(hanging_line(1.0e5))
    assert compile_scenario(sc).lines[0].shear_model == "fem"
    fem = end_forces(rfesim.statics(sc), "u")[0]
    kru = end_forces(rfesim.statics(hanging_line(1.0e5, "kruszewski")), "u")[0]
    assert fem[0] == pytest.approx(kru[0], rel=2e-3) and fem[2] == pytest.approx(kru[2], rel=1e-9)


def test_an_explicit_fem_shear_past_its_limit_warns():
    res = rfesim.statics(hanging_line(1.0e4, "fem"))
    assert "statics warning: line 'u' carries" in res.message
    assert "above the 4.8 kN that its fem shear stiffness 12 EI / Delta^3 (eq. 8.89) holds in line" in res.message
    assert "this equilibrium is spurious" in res.message


def test_a_coarse_clamped_line_starts_without_the_leads():
    """With 4 elements the clamp's lead is an eighth of the line: the catenary then runs end
    to end, as before the leads (they made the start degenerate, NaN frames). Statics
    converges and the ends carry the line's weight."""
    data = clamped_line(1.0e6, False, elements=4)
    model = compile_scenario(rfesim.load_scenario(data), start="catenary")
    assert np.all(np.isfinite(model.initial.ref.R)) and np.all(np.isfinite(model.initial.ref.X))
    fa, fb, _ = end_forces(rfesim.statics(data))
    assert fa[2] + fb[2] == pytest.approx(-wet_weight(False) * LENGTH, rel=1e-9)


def test_too_few_elements_for_the_start_shape_name_the_field():
    """2 elements (10 m each) of a 20 m line over 5 m: two joints of the start chain coincide.
    Before, statics failed with a residual NaN naming no field."""
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.statics(clamped_line(1.0e6, False, elements=2))
    reason = dict(info.value.errors)["lines.l.elements"]
    assert reason.startswith("2 elements of 10 m are too few to start this line of 20 m") and "give more" in reason


def test_a_buoyant_line_with_a_free_end_floats_up():
    """Held at its foot, a buoyant riser (10 kg/m in a 0.3 m tube: 62 kg/m of water) starts
    straight up and stays there in tension; before it started hanging down, compressed."""
    data = {"environment": {"gravity": G, "water": {"density": RHO, "depth": 200.0}},
            "line_types": {"b": {"EA": 1e9, "EIy": 1e4, "mass_per_length": 10.0, "outer_diameter": 0.3}},
            "lines": {"l": {"type": "b", "length": 50.0, "elements": 20,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, -100.0]},
                            "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True}}}
    res = rfesim.statics(data)
    line = res.line("l")
    assert line.position[0][-1, 2] == pytest.approx(-50.0, abs=1e-3)          # end B 50 m up
    net = RHO * G * math.pi / 4.0 * 0.3 ** 2 - 10.0 * G                          # N/m upward
    assert line.tension[0].max() == pytest.approx(net * 50.0 * (1 - 0.5 / 20), rel=1e-6)
    assert "warning" not in res.message


def test_a_run_past_the_fem_shear_limit_warns_in_its_message():
    """The dynamics keeps the spurious equilibrium's 4.9 kN, above the 4.8 kN the fem shear
    holds: the run's message and the log say so after the statics warning, at the peak's time."""
    from rfesim.cli import _summary_message
    data = hanging_line(1.0e4, "fem")
    data["analysis"]["dynamics"] = {"duration": 0.5, "output_interval": 0.1,
                                    "integrator": {"kind": "generalized-alpha", "time_step": 0.05}}
    res = rfesim.simulate(data)
    head, _, dynamics = res.message.partition("; dynamics warning: ")
    assert "statics warning: line 'u' carries" in head
    assert dynamics.startswith("line 'u' reaches 4.9") and "above the 4.8 kN that its fem shear" in dynamics
    assert _summary_message(res.message).endswith("(1 statics warning, 1 dynamics warning, above)")


def test_dynamic_shear_warnings_name_the_time_of_the_peak():
    from types import SimpleNamespace
    from rfesim.solvers.buckling import dynamic_shear_warnings
    model = compile_scenario(rfesim.load_scenario(hanging_line(1.0e5)))       # fem, limit 48 kN
    tension = np.full((3, 20), 1.0e4)
    tension[2, 7] = 5.0e4
    results = SimpleNamespace(lines={"u": None}, time=np.array([0.0, 0.5, 1.0]),
                              line=lambda name: SimpleNamespace(tension=tension))
    warning, = dynamic_shear_warnings(model, results)
    assert warning.startswith("line 'u' reaches 50 kN of tension at t = 1 s, above the 48 kN")
    tension[2, 7] = 4.7e4
    assert dynamic_shear_warnings(model, results) == []


def test_what_hangs_below_a_line_counts_in_its_expected_tension():
    """The 100 m line of EI = 1e4 N m^2 (fem limit 4.8 kN) carrying a 2000 kg body, or a
    50 m, 50 kg/m line joined below it, takes the kruszewski shear; before, only its own
    2 kg/m counted and it kept fem at 21.5 kN (a spurious equilibrium, warned)."""
    data = {"environment": {"gravity": G},
            "line_types": {"u": {"EA": 1e8, "EIy": 1e4, "mass_per_length": 2.0, "outer_diameter": 0.1},
                           "h": {"EA": 1e8, "EIy": 1e6, "mass_per_length": 50.0, "outer_diameter": 0.1}},
            "lines": {"u": {"type": "u", "length": 100.0, "elements": 20,
                            "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0]},
                            "end_b": {"attach": "w", "position": [0.0, 0.0, 0.0]}}},
            "bodies": {"w": {"mass": 2000.0, "radius_of_gyration": 0.5}},
            "analysis": {"statics": {"enabled": True}}}
    sc = rfesim.load_scenario(data)
    assert compile_scenario(sc).lines[0].shear_model == "kruszewski"
    assert "warning" not in rfesim.statics(sc).message
    del data["bodies"]
    data["lines"]["u"]["end_b"] = {"attach": "free"}
    data["lines"]["c"] = {"type": "h", "length": 50.0, "elements": 10, "end_a": {"attach": "u:end_b"},
                          "end_b": {"attach": "free"}}
    model = compile_scenario(rfesim.load_scenario(data))
    assert [(li.name, li.shear_model) for li in model.lines] == [("u", "kruszewski"), ("c", "fem")]



def test_a_line_resting_on_the_seabed_expects_the_grounded_catenary():
    """150 m of 20 kg/m (117 N/m wet) from an anchor on the seabed at 50 m depth to a point
    100 m away at the surface: part of it lies on the seabed, and its expected tension is the
    grounded catenary's (5.86 kN), under the fem limit of 8.53 kN (EI = 4e4 N m^2, 7.5 m
    elements), so it keeps the fem shear. Before, the catenary without seabed (12.7 kN, sagging
    through the seabed) switched it to kruszewski. Both shears give the same top force."""
    def anchored(shear=None):
        line = {"type": "p", "length": 150.0, "elements": 20,
                "end_a": {"attach": "fixed", "position": [0.0, 0.0, -50.0]},
                "end_b": {"attach": "fixed", "position": [100.0, 0.0, 0.0]}}
        if shear:
            line["shear_stiffness"] = shear
        return {"environment": {"gravity": G, "water": {"density": RHO, "depth": 50.0},
                                "seabed": {"normal_stiffness": 1e5, "friction": 0.0}},
                "line_types": {"p": {"EA": 1e8, "EIy": 4e4, "mass_per_length": 20.0, "outer_diameter": 0.1}},
                "lines": {"l": line}, "analysis": {"statics": {"enabled": True}}}
    sc = rfesim.load_scenario(anchored())
    w = 20.0 * G - RHO * G * math.pi / 4.0 * 0.1 ** 2
    grounded = solve_catenary(100.0, 50.0, 150.0, w, 1e8, seabed=True)
    hanging = solve_catenary(100.0, 50.0, 150.0, w, 1e8, seabed=False)
    limit = 12.0 * 4e4 / 7.5 ** 2
    assert grounded.top_tension < limit < hanging.top_tension
    info = compile_scenario(sc).lines[0]
    assert info.shear_model == "fem"
    assert info.tension_estimate == pytest.approx(grounded.top_tension, rel=1e-9)
    fem = end_forces(rfesim.statics(sc))[1]
    kru = end_forces(rfesim.statics(anchored("kruszewski")))[1]
    assert fem[2] == pytest.approx(kru[2], rel=3e-3) and fem[0] == pytest.approx(kru[0], rel=0.05)


def buoyant(z0: float, length: float, end: str = "end_a") -> dict:
    line = {"type": "b", "length": length, "elements": 20, "end_a": {"attach": "free"}, "end_b": {"attach": "free"}}
    line[end] = {"attach": "fixed", "position": [0.0, 0.0, z0]}
    return {"environment": {"gravity": G, "water": {"density": RHO, "depth": 150.0}},
            "line_types": {"b": {"EA": 1e8, "EIy": 1e4, "mass_per_length": 5.0, "outer_diameter": 0.2}},
            "lines": {"l": line}, "analysis": {"statics": {"enabled": True}}}


@pytest.mark.parametrize("end", ["end_a", "end_b"])
def test_a_buoyant_line_held_in_air_hangs_down(end):
    """Held 30 m above the water, the line is not buoyant where it is: it hangs (from z = 30
    to 10 m), not standing up as an inverted pendulum."""
    z = np.asarray(rfesim.statics(buoyant(30.0, 20.0, end)).line("l").position[0])[:, 2]
    assert z.min() == pytest.approx(10.0, abs=1e-3) and z.max() == pytest.approx(30.0, abs=1e-9)


@pytest.mark.parametrize("end", ["end_a", "end_b"])
def test_a_buoyant_line_longer_than_its_depth_says_why_statics_fails(end):
    """Held 100 m down, 200 m long, its free end free: the rest floats on the surface with
    nothing holding it sideways, so it has no unique static shape; the failure says so, or a
    warning does where Newton settles on some shape anyway (one standing in the air, 20 m
    above the surface)."""
    try:
        text = rfesim.statics(buoyant(-100.0, 200.0, end)).message
    except rfesim.SolverError as exc:
        text = exc.hint or ""
    assert "line 'l' is buoyant, held at one end 100 m under the surface" in text
    assert "no unique static shape" in text
