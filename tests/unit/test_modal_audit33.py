"""Modal analysis (audit 33): modes about the static equilibrium also with statics disabled,
winches held locked named, analysis.modal solved by a run, zero modes, unsupported scenes."""
from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim

G = 9.81
SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"

# the README's double pendulum: rods of 1 kg and 1 m (mass on the axis, centre at mid-length),
# started at 0.3 rad with statics disabled
README_PENDULUM = {
    "environment": {"gravity": G},
    "chains": {"pendulum": {
        "links": {"upper": {"rigid": True, "length": 1.0, "mass": 1.0},
                  "lower": {"rigid": True, "length": 1.0, "mass": 1.0}},
        "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper",
                           "direction": [0, 0, -1], "axis": [0, 1, 0], "initial": 0.3},
                   "middle": {"kind": "revolute", "parent": "upper", "child": "lower", "axis": [0, 1, 0]}}}},
    "analysis": {"statics": {"enabled": False},
                 "dynamics": {"duration": 5.0, "integrator": {"kind": "rk4", "time_step": 0.002}}},
}


def _pendulum_closed_form():
    """Lagrange about the hanging equilibrium: M = [[4/3, 1/2], [1/2, 1/3]], K = diag(1.5 g, 0.5 g)."""
    import scipy.linalg as sla
    M = np.array([[4 / 3, 1 / 2], [1 / 2, 1 / 3]])
    K = np.diag([1.5 * G, 0.5 * G])
    return np.sqrt(sla.eigh(K, M, eigvals_only=True)) / (2 * math.pi)


def test_readme_pendulum_modes_about_equilibrium_with_statics_disabled():
    """Was 0.41692 / 1.11827 Hz (about the 0.3 rad start); the equilibrium's 0.42655 / 1.14411 Hz."""
    md = rfesim.modes(copy.deepcopy(README_PENDULUM), n=2)
    assert md.frequencies_hz == pytest.approx(_pendulum_closed_form(), rel=1e-6)
    assert md.frequencies_hz == pytest.approx([0.42655, 1.14411], abs=1e-5)
    assert "analysis.statics.enabled is false" in md.message and "static equilibrium" in md.message
    on = copy.deepcopy(README_PENDULUM)
    on["analysis"]["statics"]["enabled"] = True
    md_on = rfesim.modes(on, n=2)
    assert md_on.frequencies_hz == pytest.approx(md.frequencies_hz, rel=1e-9)
    assert "statics.enabled" not in md_on.message


def test_column_crane_modes_with_statics_disabled():
    """Was six zero modes about the unloaded start; the equilibrium's 0.0861 / 0.0865 / 0.459 / 0.459 Hz."""
    sc = rfesim.load_scenario(SCENARIOS / "column_crane.json")
    sc.analysis.statics.enabled = False
    md = rfesim.modes(sc, n=6)
    f = np.asarray(md.frequencies_hz)
    assert f[2:] == pytest.approx([0.0861, 0.0865, 0.4592, 0.4592], abs=2e-4)
    assert "analysis.statics.enabled is false" in md.message


def test_cli_prints_rigid_body_round_off_as_zero(capsys):
    """The pinned catenary riser's spin computed 7.77e-7 Hz and printed so (period 1.29e6 s)
    while the negative round-off of other zero modes prints 0: now 0 / inf with a note, the
    first real mode 0.019874 Hz as before."""
    from rfesim.cli import main
    assert main(["modes", str(SCENARIOS / "catenary_riser.json"), "-n", "2"]) == 0
    out, err = capsys.readouterr()
    rows = [line.split() for line in out.splitlines()[2:]]
    assert rows[0] == ["1", "0", "inf"]
    assert rows[1][0] == "2" and float(rows[1][1]) == pytest.approx(0.0198741, rel=1e-5)
    assert "mode 1 printed as 0 (rigid-body): below 1e-08 of the stiffness-scale frequency" in err
    md = rfesim.modes(SCENARIOS / "catenary_riser.json", n=2)
    assert md.rigid_body.tolist() == [True, False]
    assert 0.0 < md.frequencies_hz[0] < 1e-8 * md.scale_hz


def test_cli_mixed_scene_modes_is_a_missing_component(tmp_path, capsys):
    """Modal analysis of a chain with an absolute line hanging from it is not provided: exit 2
    (a missing component), was 3 (a solver failure); the API still raises a SolverError."""
    import json

    from rfesim.cli import main
    data = copy.deepcopy(README_PENDULUM)
    data["analysis"] = {"statics": {"enabled": True},
                        "dynamics": {"duration": 1.0, "integrator": {"kind": "generalized-alpha", "time_step": 0.01}}}
    data["line_types"] = {"rope": {"EA": 1e6, "EIy": 1e-2, "GJ": 1e-2, "mass_per_length": 1.0}}
    data["lines"] = {"hoist": {"type": "rope", "length": 5.0, "elements": 5, "end_a": {"attach": "pendulum.lower"},
                               "end_b": {"attach": "free"}}}
    path = tmp_path / "mixed.json"
    path.write_text(json.dumps(data))
    assert main(["modes", str(path)]) == 2
    err = capsys.readouterr().err
    assert "error: modal analysis of a scene mixing chains with absolute-coordinate lines is not supported" in err
    with pytest.raises(rfesim.UnsupportedError):
        rfesim.modes(data)
    with pytest.raises(rfesim.SolverError):
        rfesim.modes(data)


# a 10 m cantilever of 10 elements clamped at end A, no gravity: statics only, with analysis.modal
CANTILEVER = {
    "name": "modal cantilever",
    "environment": {"gravity": 0.0},
    "line_types": {"beam": {"EA": 1.0e8, "EIy": 1.0e5, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "beam", "length": 10.0, "elements": 10,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                 "connection": "clamped"},
                       "end_b": {"attach": "free"}}},
    "analysis": {"statics": {"enabled": True}, "dynamics": {"enabled": False}, "modal": {"modes": 3}},
}


def test_simulate_solves_analysis_modal_and_the_file_keeps_it(tmp_path):
    """analysis.modal was never solved by a run ('statics only', no modes in the results or the
    file); now results.modes as rfesim.modes gives them, and /modes round-trips."""
    import h5py

    from service.results_json import list_channels
    res = rfesim.simulate(copy.deepcopy(CANTILEVER))
    md = rfesim.modes(copy.deepcopy(CANTILEVER))
    assert res.modes is not None and len(res.modes.frequencies_hz) == 3
    assert res.modes.frequencies_hz == pytest.approx(md.frequencies_hz, rel=1e-9)
    assert "modal analysis: 3 modes about the static equilibrium" in res.message
    path = tmp_path / "r.nc"
    res.to_netcdf(path)
    with h5py.File(path, "r") as f:
        assert f["modes/frequency"].attrs["units"] in (b"Hz", "Hz")
        assert f["modes/period"].attrs["units"] in (b"s", "s")
        assert f["modes/lines/pipe/shape"].shape == (3, 12, 3)
    back = rfesim.open_results(path)
    assert back.modes.frequencies_hz == pytest.approx(res.modes.frequencies_hz, rel=0, abs=0)
    assert back.modes.shapes.shape == res.modes.shapes.shape == (3, 11, 6)      # 11 RFEs
    assert np.array_equal(back.modes.shapes, res.modes.shapes)
    assert np.array_equal(back.modes.line_shapes["pipe"], res.modes.line_shapes["pipe"])
    assert back.modes.scale_hz == res.modes.scale_hz
    channels = list_channels(path)
    assert "modes/frequency" in channels and "modes/period" in channels
    # without analysis.modal: no modes, no group
    plain = copy.deepcopy(CANTILEVER)
    del plain["analysis"]["modal"]
    res2 = rfesim.simulate(plain)
    assert res2.modes is None and "modal" not in res2.message
    res2.to_netcdf(tmp_path / "p.nc")
    assert rfesim.open_results(tmp_path / "p.nc").modes is None


def test_simulate_modal_of_a_chain_with_statics_disabled_and_dynamics():
    """The README pendulum (statics disabled, 5 s of dynamics) with analysis.modal: the run's
    results.modes are the equilibrium's 0.42655 / 1.14411 Hz."""
    data = copy.deepcopy(README_PENDULUM)
    data["analysis"]["dynamics"]["duration"] = 0.1
    data["analysis"]["modal"] = {"modes": 2}
    res = rfesim.simulate(data)
    assert res.kind == "dynamics" and res.time[-1] == pytest.approx(0.1)
    assert res.modes.frequencies_hz == pytest.approx(_pendulum_closed_form(), rel=1e-6)
    assert "analysis.statics.enabled is false" in res.message


def test_simulate_modal_not_provided_keeps_the_run():
    """A mixed chain + absolute-line scene: the run's results stand, results.modes is None and
    the message says the modal analysis was not done and why."""
    data = copy.deepcopy(README_PENDULUM)
    data["analysis"] = {"statics": {"enabled": True}, "dynamics": {"enabled": False}, "modal": {"modes": 2}}
    data["line_types"] = {"rope": {"EA": 1e6, "EIy": 1e-2, "GJ": 1e-2, "mass_per_length": 1.0}}
    data["lines"] = {"hoist": {"type": "rope", "length": 5.0, "elements": 5, "end_a": {"attach": "pendulum.lower"},
                               "end_b": {"attach": "free"}}}
    res = rfesim.simulate(data)
    assert res.modes is None
    assert "modal analysis: not done (analysis.modal): modal analysis of a scene mixing chains" in res.message


def _winch_scene(mode, heave=None):
    """A 10 t payload on a 20 m rope (EA = 1e8 N, EA/l = 5e6 N/m) from a fixed sheave, winch 'w'."""
    data = {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": 1e8, "EIy": 1e-2, "GJ": 1e-2, "mass_per_length": 0.1, "tension_only": True,
                                    "outer_diameter": 0.036}},
            "lines": {"rope": {"type": "rope", "length": 20.0, "elements": 10,
                               "end_a": {"attach": "fixed", "position": [0, 0, 50.0], "connection": "pinned"},
                               "end_b": {"attach": "load", "position": [0, 0, 1.0], "connection": "pinned"}}},
            "bodies": {"load": {"mass": 1e4, "radius_of_gyration": 1.0}},
            "winches": {"w": {"line": "rope", "mode": mode}}}
    if heave is not None:
        data["winches"]["w"]["heave_compensation"] = heave
    return data


def test_modes_name_winches_held_locked():
    """The modal analysis holds a constant-tension winch locked (its bounce sqrt(k/M)/2pi =
    3.559 Hz stays, the time domain has none), unsaid before; now the message names it. A
    speed winch (prescribed: locked is right) and heave compensation on a fixed sheave are not named."""
    tension = rfesim.modes(_winch_scene({"kind": "tension", "tension": 1e4 * G, "gain": 1e5, "max_speed": 1.0}), n=7)
    assert tension.frequencies_hz[6] == pytest.approx(math.sqrt(5e6 / 1e4) / (2 * math.pi), rel=2e-3)
    assert "holds every winch and payout locked" in tension.message
    assert "winch 'w' (mode tension: it pays out at the set tension)" in tension.message
    drum = rfesim.modes(_winch_scene({"kind": "drum", "radius": 0.5, "inertia": 100.0,
                                      "torque": [[0, 0.5 * 1e4 * G]]}), n=2)
    assert "winch 'w' (mode drum without a brake" in drum.message
    speed = rfesim.modes(_winch_scene({"kind": "speed", "rows": [[0, 0]]}, heave={"kp": 1.0}), n=2)
    assert "locked" not in speed.message
