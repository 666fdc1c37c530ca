"""Vessel motion from RAOs (rfesim.sea.rao) and from a CSV file (rfesim.sea.motion_csv)."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
from rfesim.model.arrays import new_attachment_state
from rfesim.scenario.schema import RaoTable, TableMotion
from rfesim.sea.rao import rao_response
from rfesim.sea.waves import wave_components, water_depth
from rfesim.vessel import TableVessel, make_vessel_motion
from rfesim.vessel_kernel import attachment_kinematics, vessel_spec

DATA = Path(__file__).resolve().parents[2] / "scenarios" / "data"
DOFS = ("surge", "sway", "heave", "roll", "pitch", "yaw")


def constant_table(values: dict, frequencies=(0.2, 3.0), headings=(0.0, 90.0, 180.0, 270.0)):
    """An RAO table with the same (amplitude, phase lag) at every frequency and heading."""
    out = {"frequencies": list(frequencies), "headings_deg": list(headings)}
    for name, (amp, lag) in values.items():
        out[name] = {"amplitude": [[amp] * len(headings)] * len(frequencies),
                     "phase_deg": [[lag] * len(headings)] * len(frequencies)}
    return out


def scene(waves, motion, position=(0.0, 0.0, 0.0), heading=0.0, depth=150.0):
    return rfesim.load_scenario({"environment": {"water": {"depth": depth, "waves": waves}},
                                 "vessels": {"ship": {"position": list(position), "heading_deg": heading,
                                                      "motion": motion}}})


def test_regular_wave_gives_amplitude_times_rao_with_the_stated_phase_lag():
    H, T, phase, direction = 2.0, 9.0, 40.0, 30.0
    x_v = (20.0, -10.0, 0.0)
    raos = constant_table({"heave": (0.8, 30.0), "surge": (0.5, -75.0), "pitch": (2.0, 120.0)})
    sc = scene({"kind": "airy", "height": H, "period": T, "phase_deg": phase, "direction_deg": direction},
               {"kind": "rao", "raos": raos}, position=x_v, heading=0.0)
    motion = make_vessel_motion(sc.vessels["ship"], sc.environment)
    w = 2 * math.pi / T
    k = float(wave_components(sc.environment.water.waves, 150.0).wavenumber[0])
    kx = k * (x_v[0] * math.cos(math.radians(direction)) + x_v[1] * math.sin(math.radians(direction)))
    for t in np.linspace(0.0, 20.0, 41):
        d, dd, ddd = motion.dofs(t)
        arg = w * t - kx + math.radians(phase)
        expected = {0: 0.5 * (H / 2) * math.cos(arg - math.radians(-75.0)),
                    2: 0.8 * (H / 2) * math.cos(arg - math.radians(30.0)),
                    4: math.radians(2.0) * (H / 2) * math.cos(arg - math.radians(120.0))}
        for j in range(6):
            assert d[j] == pytest.approx(expected.get(j, 0.0), abs=1e-13)
        assert dd[2] == pytest.approx(-0.8 * (H / 2) * w * math.sin(arg - math.radians(30.0)), abs=1e-13)
        assert ddd[2] == pytest.approx(-w * w * d[2], abs=1e-13)


def test_unit_heave_rao_follows_the_irregular_wave_elevation_at_the_vessel():
    waves = {"kind": "jonswap", "hs": 3.0, "tp": 9.0, "seed": 11, "direction_deg": 200.0, "ramp_duration": 20.0}
    x_v = (35.0, 12.0, 0.0)
    sc = scene(waves, {"kind": "rao", "raos": constant_table({"heave": (1.0, 0.0)})}, position=x_v, heading=70.0)
    motion = make_vessel_motion(sc.vessels["ship"], sc.environment)
    wc = wave_components(sc.environment.water.waves, water_depth(sc.environment))
    for t in (0.0, 5.0, 19.0, 37.5, 300.0):
        assert motion.kinematics(t).p[2] == pytest.approx(wc.elevation(t, x_v[0], x_v[1]), abs=1e-12)


def test_rao_motion_runs_in_the_compiled_vessel_kinematics():
    sc = scene({"kind": "jonswap", "hs": 2.0, "tp": 8.0, "seed": 3, "direction_deg": 150.0, "ramp_duration": 10.0},
               {"kind": "rao", "file": str(DATA / "barge_100m_raos.json")}, position=(5.0, -3.0, 1.0), heading=20.0)
    motions = [None, make_vessel_motion(sc.vessels["ship"], sc.environment)]
    spec = vessel_spec(motions)
    assert spec.kind[1] == 1 and spec.h_amp.shape[1] == 200
    att = new_attachment_state(2)
    for t in (0.0, 4.0, 10.0, 63.3):
        attachment_kinematics(spec, t, att)
        k = motions[1].kinematics(t)
        for got, want in ((att.p[1], k.p), (att.R[1], k.R), (att.v[1], k.v), (att.w[1], k.w), (att.a[1], k.a),
                          (att.alpha[1], k.alpha)):
            assert np.max(np.abs(got - want)) < 1e-11


def test_interpolation_is_exact_for_a_bilinear_table():
    freqs, heads = [0.3, 0.6, 1.0, 1.6], [0.0, 60.0, 150.0, 240.0]

    def amp(w, b):
        return 0.2 + 0.5 * w + 0.002 * b + 0.001 * w * b

    def lag(w, b):
        return 10.0 + 20.0 * w - 0.1 * b

    table = RaoTable.model_validate({"frequencies": freqs, "headings_deg": heads, "heave": {
        "amplitude": [[amp(w, b) for b in heads] for w in freqs],
        "phase_deg": [[lag(w, b) for b in heads] for w in freqs]}})
    rng = np.random.default_rng(0)
    w = rng.uniform(0.3, 1.6, 50)
    b = rng.uniform(0.0, 240.0, 50)
    a, p = rao_response(table, w, b)
    assert np.allclose(a[:, 2], amp(w, b), rtol=1e-13) and np.allclose(np.degrees(p[:, 2]), lag(w, b), rtol=1e-13)
    assert not a[:, [0, 1, 3, 4, 5]].any()
    # beyond the frequencies the end rows are held
    a, _ = rao_response(table, np.array([0.1, 5.0]), np.array([60.0, 60.0]))
    assert a[:, 2] == pytest.approx([amp(0.3, 60.0), amp(1.6, 60.0)])
    # periodic in heading: 300 deg is halfway between 240 and 360 (= 0)
    a, _ = rao_response(table, np.array([0.6]), np.array([300.0]))
    assert a[0, 2] == pytest.approx(0.5 * (amp(0.6, 240.0) + amp(0.6, 0.0)))
    a2, _ = rao_response(table, np.array([0.6]), np.array([-60.0]))
    assert a2[0, 2] == pytest.approx(a[0, 2])


def test_periods_give_the_same_table_as_frequencies_and_phase_interpolates_the_short_way():
    w = [0.5, 1.0]
    by_w = RaoTable.model_validate({"frequencies": w, "headings_deg": [0.0],
                                    "roll": {"amplitude": [[1.0], [3.0]], "phase_deg": [[350.0], [10.0]]}})
    by_t = RaoTable.model_validate({"periods": [2 * math.pi / 1.0, 2 * math.pi / 0.5], "headings_deg": [0.0],
                                    "roll": {"amplitude": [[3.0], [1.0]], "phase_deg": [[10.0], [350.0]]}})
    for table in (by_w, by_t):
        a, p = rao_response(table, np.array([0.75]), np.array([123.0]))
        assert a[0, 3] == pytest.approx(math.radians(2.0))            # deg/m -> rad/m
        assert math.cos(p[0, 3]) == pytest.approx(1.0)                # 350 -> 10 through 0, not through 180


def test_symmetric_table_mirrors_sway_roll_yaw():
    table = RaoTable.model_validate(constant_table(
        {"sway": (0.7, 90.0), "roll": (3.0, 100.0), "heave": (0.9, 5.0), "yaw": (0.5, 45.0)},
        headings=(0.0, 90.0, 180.0)) | {"symmetric": True})
    a1, p1 = rao_response(table, np.array([1.0]), np.array([60.0]))
    a2, p2 = rao_response(table, np.array([1.0]), np.array([300.0]))
    assert np.allclose(a1, a2)
    for j in range(6):
        z1 = a1[0, j] * np.exp(-1j * p1[0, j])
        z2 = a2[0, j] * np.exp(-1j * p2[0, j])
        assert z2 == pytest.approx(-z1 if j in (1, 3, 5) else z1, abs=1e-14)


def test_example_barge_table_is_valid_and_physical():
    table = RaoTable.model_validate(json.loads((DATA / "barge_100m_raos.json").read_text()))
    # long waves: heave follows the surface (RAO -> 1, no lag)
    a, p = rao_response(table, np.array([2 * math.pi / 25.0]), np.array([90.0]))
    assert a[0, 2] == pytest.approx(1.0, abs=0.1) and abs(p[0, 2]) < math.radians(10.0)
    # short waves: no motion
    a, _ = rao_response(table, np.array([2 * math.pi / 4.0]), np.array([180.0]))
    assert np.all(a[0] < 0.08)


# --------------------------------------------------------------------------- CSV motion

CSV = """# vessel motion, generated for a test
time [s], heave [m], surge [m], sway, roll [deg], pitch, yaw
0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
1.0, 0.5, 0.1, 0.0, 1.0, 0.0, 0.0
2.0, 0.0, 0.2, 0.3, 0.0, -2.0, 0.0

3.0, -0.5, 0.3, 0.0, 0.0, 0.0, 5.0
4.0, 0.0, 0.4, 0.0, -1.0, 0.0, 0.0
"""
ROWS = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [1.0, 0.1, 0.0, 0.5, 1.0, 0.0, 0.0],
        [2.0, 0.2, 0.3, 0.0, 0.0, -2.0, 0.0], [3.0, 0.3, 0.0, -0.5, 0.0, 0.0, 5.0],
        [4.0, 0.4, 0.0, 0.0, -1.0, 0.0, 0.0]]


def write_scene(tmp_path, motion, csv_text=CSV):
    (tmp_path / "data").mkdir(exist_ok=True)
    (tmp_path / "data" / "motion.csv").write_text(csv_text)
    path = tmp_path / "scene.json"
    path.write_text(json.dumps({"vessels": {"ship": {"position": [1.0, 2.0, 3.0], "heading_deg": 30.0,
                                                     "motion": motion}}}))
    return path


@pytest.mark.parametrize("interpolation", ["cubic", "linear"])
def test_csv_motion_is_the_table_motion_of_its_rows(tmp_path, interpolation):
    path = write_scene(tmp_path, {"kind": "csv", "file": "data/motion.csv", "interpolation": interpolation,
                                  "ramp_duration": 1.5})
    sc = rfesim.load_scenario(path)                      # the file is found next to the scenario
    got = make_vessel_motion(sc.vessels["ship"])
    want = TableVessel([1.0, 2.0, 3.0], 30.0, TableMotion(kind="table", rows=ROWS, interpolation=interpolation,
                                                          ramp_duration=1.5))
    for t in (-1.0, 0.3, 1.0, 2.7, 3.99, 9.0):
        kg, kw = got.kinematics(t), want.kinematics(t)
        for a, b in ((kg.p, kw.p), (kg.R, kw.R), (kg.v, kw.v), (kg.a, kw.a), (kg.w, kw.w)):
            assert np.max(np.abs(a - b)) < 1e-14


def test_csv_without_header_and_whitespace_separated(tmp_path):
    text = "\n".join(" ".join(str(v) for v in r) for r in ROWS)
    path = write_scene(tmp_path, {"kind": "csv", "file": "data/motion.csv", "interpolation": "linear"}, text)
    sc = rfesim.load_scenario(path)
    assert np.array_equal(sc.vessels["ship"].motion.rows(), ROWS)


def errors_of(path):
    with pytest.raises(rfesim.ScenarioError) as info:
        rfesim.load_scenario(path)
    return dict(info.value.errors)


@pytest.mark.parametrize("text, word", [
    ("t, surge, sway, heave, roll, pitch\n0,0,0,0,0,0\n1,0,0,0,0,0\n", "missing yaw"),
    ("t, surge, sway, heave, roll, pitch, yawn\n", "unknown column 'yawn'"),
    ("0,0,0,0,0,0,0\n1,0,0,0,0,0\n", "line 2: 6 columns, expected 7"),
    ("0,0,0,0,0,0,0\n1,0,0,x,0,0,0\n", "line 2: 'x' is not a number"),
    ("0,0,0,0,0,0,0\n0,0,0,1,0,0,0\n1,0,0,0,0,0,0\n2,0,0,0,0,0,0\n", "does not increase"),
    ("0,0,0,0,0,0,0\n1,0,0,1,0,0,0\n2,0,0,0,0,0,0\n", "at least 4 rows"),
])
def test_bad_csv_names_the_file_field_and_the_problem(tmp_path, text, word):
    path = write_scene(tmp_path, {"kind": "csv", "file": "data/motion.csv"}, text)
    errors = errors_of(path)
    assert word in errors["vessels.ship.motion.file"] and "motion.csv" in errors["vessels.ship.motion.file"]


def test_missing_csv_file(tmp_path):
    path = write_scene(tmp_path, {"kind": "csv", "file": "data/nothere.csv"})
    assert "file not found" in errors_of(path)["vessels.ship.motion.file"]


def test_relative_paths_resolve_against_the_scenario_folder_not_the_working_directory(tmp_path, monkeypatch):
    path = write_scene(tmp_path, {"kind": "csv", "file": "data/motion.csv"})
    monkeypatch.chdir(tmp_path / "data")
    sc = rfesim.load_scenario(path)
    assert Path(sc.vessels["ship"].motion.file) == (tmp_path / "data" / "motion.csv").resolve()
    # a dict has no folder: a base_dir may be given; without it the working directory is used
    data = json.loads(path.read_text())
    assert rfesim.load_scenario(data, base_dir=tmp_path).vessels["ship"].motion.rows().shape == (5, 7)
    with pytest.raises(rfesim.ScenarioError):
        rfesim.load_scenario(data)
    data["vessels"]["ship"]["motion"]["file"] = "motion.csv"
    assert rfesim.load_scenario(data).vessels["ship"].motion.rows().shape == (5, 7)
    assert data["vessels"]["ship"]["motion"]["file"] == "motion.csv"        # the input is not modified


def test_rao_file_errors_name_the_file_and_the_table_field(tmp_path):
    bad = json.loads((DATA / "barge_100m_raos.json").read_text())
    bad["heave"]["amplitude"] = bad["heave"]["amplitude"][:-1]
    (tmp_path / "raos.json").write_text(json.dumps(bad))
    waves = {"kind": "airy", "height": 1.0, "period": 8.0}
    with pytest.raises(rfesim.ScenarioError) as info:
        scene(waves, {"kind": "rao", "file": str(tmp_path / "raos.json")})
    reason = dict(info.value.errors)["vessels.ship.motion.file"]
    assert "raos.json" in reason and "heave.amplitude" in reason and "expected one per period" in reason
