"""Benchmark H2 (rfesim.bench.h2, moordyn_h2, run_h2) without running MoorDyn: the
scenario builds with the sea of H2, the measurement recovers a known amplitude, the
MoorDyn input files describe the same sea, and the report keeps the other sections."""
import math

import numpy as np
import pytest

from rfesim.bench import h1, h2, moordyn_h1, moordyn_h2, run_h2
from rfesim.bench.h1 import H1Run


def test_h2_scenario_builds_with_the_sea_of_h2():
    sc = h2.h2_scenario(40, {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8})
    assert sc.lines["riser"].elements == 40
    assert sc.line_types["steel_pipe"].added_mass_normal == 1.0
    assert sc.line_types["steel_pipe"].added_mass_axial == 0.0
    water = sc.environment.water
    assert water.current.profile == [[0.0, 0.5]] and water.current.direction_deg == 90.0
    assert water.waves.kind == "airy" and water.waves.height == 3.0 and water.waves.period == 9.0
    assert water.waves.direction_deg == 0.0 and water.waves.stretching == "wheeler"
    # the rest is H1: same line, ends and heave
    base = h1.h1_scenario(40, {"kind": "generalized-alpha", "time_step": 0.05, "rho_inf": 0.8})
    assert sc.lines["riser"].length == base.lines["riser"].length == 290.0
    assert sc.lines["riser"].end_b.position == base.lines["riser"].end_b.position
    assert base.environment.water.current is None and base.environment.water.waves is None


def test_h2_sea_kinematics_are_the_stated_ones():
    """Current ramped linearly over 8 s toward +y; eta = 1.5 cos(omega t - k x)."""
    from rfesim.sea.kernel import sea_kinematics_into, sea_spec
    from rfesim.sea.waves import wave_number
    sc = h2.h2_scenario(10, {"kind": "generalized-alpha", "time_step": 0.05})
    spec = sea_spec(sc.environment)
    pts = np.array([[0.0, 0.0, -99.0], [37.0, 2.0, -60.0], [250.0, 0.0, -10.0]])
    eta, vel, acc = np.empty(3), np.empty((3, 3)), np.empty((3, 3))
    omega = 2.0 * math.pi / 9.0
    k = float(wave_number(np.array([omega]), 100.0, 9.81)[0])
    for t, factor in ((0.0, 0.0), (2.0, 0.25), (6.0, 0.75), (31.0, 1.0)):
        sea_kinematics_into(spec, t, pts, eta, vel, acc)
        np.testing.assert_allclose(eta, 1.5 * np.cos(omega * t - k * pts[:, 0]), atol=1e-12)
        # the wave moves water in the x-z plane only: y is the current alone
        np.testing.assert_allclose(vel[:, 1], 0.5 * factor, atol=1e-12)
        np.testing.assert_allclose(acc[:, 1], 0.0, atol=1e-12)


def test_first_harmonic_amplitude_recovers_a_known_amplitude():
    t = np.arange(0.0, 60.0 + 1e-9, 0.05)
    w = 2.0 * math.pi * h1.FREQUENCY
    amplitude, phase = 1234.5, 0.7
    signal = 9.6e4 + amplitude * np.cos(w * t + phase)
    # a transient before the 28-60 s window must not count
    early = t < 20.0
    signal[early] += 5e3 * np.exp(-t[early] / 3.0) * np.sin(1.7 * t[early])
    assert h1.first_harmonic_amplitude(t, signal) == pytest.approx(amplitude, rel=1e-12)
    assert h1.first_harmonic_amplitude(t, signal, window=(0.0, 60.0)) != pytest.approx(amplitude, rel=1e-3)
    # higher harmonics of the heave (4 periods in the window) are nearly orthogonal to it
    harmonics = signal + 300.0 * np.cos(2 * w * t - 0.2) + 50.0 * np.sin(3 * w * t)
    assert h1.first_harmonic_amplitude(t, harmonics) == pytest.approx(amplitude, rel=1e-3)
    # the same as MoorDyn's harness computes (its own copy of the fit)
    assert moordyn_h1.first_harmonic_amplitude(t, signal) == pytest.approx(amplitude, rel=1e-12)


def test_moordyn_input_describes_the_same_line_and_sea():
    text = moordyn_h2.moordyn_h2_input_text(50, 5e-4)
    h1_text = moordyn_h1.moordyn_input_text(50, 5e-4)
    row = [line.split() for line in text.splitlines() if line.startswith("pipe ")][0]
    h1_row = [line.split() for line in h1_text.splitlines() if line.startswith("pipe ")][0]
    # TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx: only Ca differs from H1
    assert float(row[7]) == 1.0 and float(row[9]) == 0.0
    assert row[:7] == h1_row[:7] and row[8] == h1_row[8]
    options = {line.split()[1]: line.split()[0] for line in text.splitlines()
               if len(line.split()) > 1 and line.split()[1] in ("WaveKin", "Currents", "dtM", "ICgenDynamic")}
    assert options == {"WaveKin": "7", "Currents": "2", "dtM": "0.0005", "ICgenDynamic": "1"}

    # wave_frequencies.txt: MoorDyn's eta = |A| sin(omega t - k x + arg A) must be
    # rfesim's 1.5 cos(omega t - k x)
    rows = [list(map(float, line.split())) for line in moordyn_h2.wave_frequencies_text().splitlines()]
    assert rows[0][0] == 0.0 and rows[0][1:3] == [0.0, 0.0]
    omega, re, im, beta = rows[1]
    assert omega == pytest.approx(2.0 * math.pi / 9.0) and beta == 0.0
    theta = np.linspace(-10.0, 10.0, 41)
    np.testing.assert_allclose(abs(complex(re, im)) * np.sin(theta + math.atan2(im, re)), 1.5 * np.cos(theta),
                               atol=1e-14)

    # current_profile_dynamic.txt: depths row, then t, ux(z1, z2), uy(z1, z2)
    lines = moordyn_h2.current_profile_dynamic_text().splitlines()
    assert [float(z) for z in lines[4].split()] == [-1000.0, 0.0]
    table = np.array([list(map(float, line.split())) for line in lines[6:]])
    np.testing.assert_allclose(table[:, 0], [0.0, 8.0, moordyn_h2.CURRENT_TABLE_END])
    np.testing.assert_allclose(table[:, 1:3], 0.0, atol=1e-15)             # no x component
    np.testing.assert_allclose(table[:, 3:5], [[0.0, 0.0], [0.5, 0.5], [0.5, 0.5]])
    assert moordyn_h2.CURRENT_TABLE_END > 60.0                           # MoorDyn wraps the table around


def _runs(code, pairs, wall):
    return [H1Run(code, n, "s", w, w, 1e4 * (1 + e), 4e5, e) for (n, e), w in zip(pairs, wall)]


def test_h2_report_keeps_the_other_sections(tmp_path):
    h2_results = {
        "rfesim": _runs("rfesim", [(25, 2e-2), (50, 5e-3), (100, 8e-4), (200, 2e-4)], [0.5, 1.0, 2.0, 4.0]),
        "moordyn": _runs("moordyn", [(25, 3e-2), (50, 1e-2), (100, 4e-3), (200, 1e-3)], [10.0, 20.0, 60.0, 200.0]),
        "quick": False,
        "bench_wall_time": 600.0,
    }
    h2_results["rfesim_reference"] = H1Run("rfesim", 400, "ref", 9.0, 9.0, 1e4, 4e5, 0.0)
    h2_results["moordyn_reference"] = H1Run("moordyn", 400, "ref", 500.0, 700.0, 1.001e4, 4.002e5, 0.0)
    summary = run_h2.summarise(h2_results)
    at_1 = summary["targets"][0]
    assert at_1["error"] == 1e-2 and at_1["moordyn"] == pytest.approx(20.0)
    # rfesim passes 1e-2 between 0.5 s (2e-2) and 1 s (5e-3): log-log interpolation
    assert at_1["rfesim"] == pytest.approx(math.exp(math.log(0.5) + 0.5 * math.log(2.0)))
    at_100 = summary["at_rfes"][0]
    assert at_100["elements"] == 100 and at_100["rfesim"] == 2.0
    assert at_100["moordyn"] == math.inf          # 8e-4 is below MoorDyn's best (1e-3)
    assert at_100["moordyn_same_segments"] == 60.0

    path = tmp_path / "benchmarks.md"
    core = "<!-- core-bench -->\n## Core solver\nunchanged text\n<!-- /core-bench -->"
    path.write_text("# Benchmarks\n\n" + core + "\n\n<!-- service-bench -->\nservice\n<!-- /service-bench -->\n")
    run_h2.write_section(run_h2.report(h2_results), path)
    first = path.read_text()
    assert core in first and "<!-- service-bench -->\nservice" in first
    assert first.index("<!-- /core-bench -->") < first.index(run_h2.MARK_BEGIN) < first.index("<!-- service-bench")
    assert "+0.10 %" in first                     # converged tension amplitudes 1.001e4 vs 1e4
    # a second write replaces the H2 section in place
    h2_results["bench_wall_time"] = 1200.0
    run_h2.write_section(run_h2.report(h2_results), path)
    second = path.read_text()
    assert second.count(run_h2.MARK_BEGIN) == 1 and core in second and "took 20.0 min" in second
