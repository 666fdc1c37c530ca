"""MoorDyn reference runs of benchmark line H2: line H1 with added mass, current and waves.

H2 is benchmark line H1 (see :mod:`rfesim.bench.moordyn_h1`: the pipe, the seabed, the
heaving fairlead, the coupling at every internal step with the exact-velocity probe,
RK4, ``ICgenDynamic`` and the measured quantities are all the same) with

* normal added-mass coefficient ``Ca = 1.0`` (axial ``CaAx = 0``): MoorDyn puts
  ``rho V Ca (I - q q^T)`` into each node's mass matrix and applies the fluid inertia
  ``rho V (1 + Ca) a_n + rho V (1 + CaAx) a_t`` of the water acceleration, which is
  rfesim's Froude-Krylov ``rho V a`` plus added-mass ``Ca rho V a_n`` term (same value);
* a uniform current of 0.5 m/s flowing toward +y, i.e. across the x-z plane of the
  line, ramped in linearly from 0 at t = 0 to full speed at t = 8 s (``Currents 2``, a
  dynamic current profile in ``current_profile_dynamic.txt``, which MoorDyn
  interpolates linearly in time, exactly rfesim's ``time_factor`` table
  ``[[0, 0], [8, 1]]``); the initial condition is the still-water equilibrium in both
  codes (MoorDyn switches water kinematics off during its dynamic relaxation; rfesim's
  statics at t = 0 sees a current factor of 0);
* a regular Airy wave of height 3 m and period 9 s travelling toward +x, with
  ``eta = 1.5 cos(omega t - k x)`` m at still water level 0, from t = 0 without a ramp
  (``WaveKin 7``: MoorDyn sums the wave components of ``wave_frequencies.txt`` at every
  node at every stage of its time integrator, with no ramp). MoorDyn writes the
  elevation as ``|A| sin(omega t - k x + arg A)``, so the complex amplitude is written
  as ``A = 0 + 1.5 i`` (``arg A = pi / 2``) to give the cosine above. Its kinematics use
  Wheeler stretching ``z_s = h (z - eta) / (h + eta)`` (depth ``h`` = the node-centre
  water depth 99.85 m) and are zero above the instantaneous surface (the line never
  reaches the surface here); rfesim's scenario uses ``stretching: wheeler`` with its
  depth of 100 m: the difference in the stretched height at the fairlead is 2e-4 m,
  1e-5 relative in the kinematics (checked by ``compare_kinematics``).

Drag is quadratic in the velocity of the water relative to the node, with the same
coefficients as H1 (``Cd`` 1.2 normal on ``Diam``, ``CdAx`` 0.008 on ``pi Diam``).
"""
from __future__ import annotations

import contextlib
import math
import os
import tempfile

from . import moordyn_h1 as h1

# --------------------------------------------------------------------------------------
# The sea of H2 (SI units)
# --------------------------------------------------------------------------------------
NORMAL_ADDED_MASS_COEFFICIENT = 1.0  # -
AXIAL_ADDED_MASS_COEFFICIENT = 0.0  # -
CURRENT_SPEED = 0.5  # m/s, uniform over depth
CURRENT_DIRECTION_DEG = 90.0  # deg, flowing toward +y (across the line's x-z plane)
CURRENT_RAMP_DURATION = 8.0  # s, linear ramp of the current speed from 0 at t = 0
WAVE_HEIGHT = 3.0  # m, crest to trough
WAVE_PERIOD = 9.0  # s
WAVE_DIRECTION_DEG = 0.0  # deg, travelling toward +x
WAVE_ANGULAR_FREQUENCY = 2.0 * math.pi / WAVE_PERIOD  # rad/s
# Last row of MoorDyn's dynamic current table: MoorDyn wraps its current time series
# around after the last row, so the table must reach past the end of every run.
CURRENT_TABLE_END = 1000.0  # s


def moordyn_h2_input_text(segments: int, dt_internal: float,
                          axial_damping_ratio: float = h1.AXIAL_DAMPING_RATIO,
                          time_scheme: str = h1.DEFAULT_TIME_SCHEME) -> str:
    """Text of a MoorDyn v2 input file for H2: the H1 file with ``Ca = 1`` and the
    options ``WaveKin 7`` (wave components summed at the nodes) and ``Currents 2``
    (dynamic current profile)."""
    text = h1.moordyn_input_text(segments, dt_internal, axial_damping_ratio, time_scheme)
    lines = text.splitlines()
    type_rows = [i for i, line in enumerate(lines) if line.startswith("pipe ")]
    option_rows = [i for i, line in enumerate(lines) if line.split()[1:2] == ["ICgenDynamic"]]
    if len(type_rows) != 1 or len(option_rows) != 1:
        raise RuntimeError("unexpected layout of the H1 MoorDyn input file")
    # columns: TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
    fields = lines[type_rows[0]].split()
    fields[7] = f"{NORMAL_ADDED_MASS_COEFFICIENT:g}"
    fields[9] = f"{AXIAL_ADDED_MASS_COEFFICIENT:g}"
    lines[type_rows[0]] = "  ".join(fields)
    lines[1] = "Benchmark line H2 (rfesim.bench.moordyn_h2): line H1 with Ca 1, a 0.5 m/s current toward +y"
    lines[2] = "and a regular Airy wave H 3 m, T 9 s toward +x (wave_frequencies.txt, current_profile_dynamic.txt)."
    lines.insert(option_rows[0], "7  WaveKin  wave components summed at the nodes (wave_frequencies.txt)")
    lines.insert(option_rows[0] + 1, "2  Currents  dynamic current profile (current_profile_dynamic.txt)")
    return "\n".join(lines) + "\n"


def wave_frequencies_text() -> str:
    """``wave_frequencies.txt``: rows ``omega (rad/s)  Re(A)  Im(A)  direction (rad)``.

    MoorDyn's elevation is ``sum |A| sin(omega t - k (x cos b + y sin b) + arg A)``; the
    first row must be omega = 0. ``A = 1.5 i`` gives ``eta = 1.5 cos(omega t - k x)``.
    """
    direction = math.radians(WAVE_DIRECTION_DEG)
    return (f"0 0 0 {direction!r}\n"
            f"{WAVE_ANGULAR_FREQUENCY!r} 0 {0.5 * WAVE_HEIGHT!r} {direction!r}\n")


def current_profile_dynamic_text() -> str:
    """``current_profile_dynamic.txt``: 4 ignored lines, the depths, 1 ignored line, then
    rows ``t  ux(z_1..z_n)  uy(z_1..z_n)``. Two depths far below and at the surface (the
    profile is held beyond them) make the current uniform; rows at 0 and
    ``CURRENT_RAMP_DURATION`` give the linear ramp (MoorDyn resamples the table at its
    smallest time interval and interpolates linearly)."""
    direction = math.radians(CURRENT_DIRECTION_DEG)
    ux = CURRENT_SPEED * math.cos(direction)
    uy = CURRENT_SPEED * math.sin(direction)
    if abs(ux) < 1e-12:
        ux = 0.0
    rows = [(0.0, 0.0, 0.0), (CURRENT_RAMP_DURATION, ux, uy), (CURRENT_TABLE_END, ux, uy)]
    body = "".join(f"{t!r} {vx!r} {vx!r} {vy!r} {vy!r}\n" for t, vx, vy in rows)
    return ("--------------------- MoorDyn dynamic current (rfesim.bench.moordyn_h2) ------------\n"
            "uniform current ramped in linearly\n"
            "rows: t, ux at each depth, uy at each depth\n"
            "depths (m):\n"
            "-1000.0 0.0\n"
            "t (s)  ux(-1000)  ux(0)  uy(-1000)  uy(0)  (m/s)\n" + body)


def write_inputs(directory: str, segments: int, dt_internal: float,
                 axial_damping_ratio: float = h1.AXIAL_DAMPING_RATIO,
                 time_scheme: str = h1.DEFAULT_TIME_SCHEME) -> str:
    """Write the H2 input file and its wave and current files into ``directory`` (MoorDyn
    reads them from the input file's folder); return the input file's path."""
    input_path = os.path.join(directory, f"h2_n{segments}.dat")
    with open(input_path, "w") as handle:
        handle.write(moordyn_h2_input_text(segments, dt_internal, axial_damping_ratio, time_scheme))
    with open(os.path.join(directory, "wave_frequencies.txt"), "w") as handle:
        handle.write(wave_frequencies_text())
    with open(os.path.join(directory, "current_profile_dynamic.txt"), "w") as handle:
        handle.write(current_profile_dynamic_text())
    return input_path


def run_moordyn_h2(segments: int, dt_internal: float | None = None, duration: float = 60.0,
                   workdir: str | None = None, axial_damping_ratio: float = h1.AXIAL_DAMPING_RATIO,
                   time_scheme: str = h1.DEFAULT_TIME_SCHEME, quiet: bool = True) -> dict:
    """Run MoorDyn on line H2 and measure the fairlead tension amplitude and the largest
    bending moment over 28 s .. ``duration``.

    The fairlead is updated at every internal step (coupling step = dtM, at most 1 ms);
    ``dt_internal`` None picks ``moordyn_h1.default_internal_step``. Returns the dict of
    :func:`moordyn_h1.run_moordyn_h1` (tension amplitude, largest moment, wall times,
    initial-condition report, ...).
    """
    import moordyn

    segments = int(segments)
    if segments < 2:
        raise ValueError(f"segments must be at least 2, got {segments}")
    if duration <= h1.ANALYSIS_START + h1.HEAVE_PERIOD:
        raise ValueError(f"duration must exceed {h1.ANALYSIS_START + h1.HEAVE_PERIOD} s, got {duration}")
    if dt_internal is None:
        dt_internal = h1.default_internal_step(segments, None, time_scheme)
    else:
        dt_internal = h1.fit_to_coupling_step(min(float(dt_internal), h1.MAXIMUM_COUPLING_STEP),
                                              h1.OUTPUT_INTERVAL)
    coupling_step = dt_internal

    with contextlib.ExitStack() as stack:
        directory = h1._work_directory(stack, workdir, "moordyn_h2_")
        # dtM larger by 1e-9 (relative) so that MoorDyn takes exactly one step per call
        # (see run_moordyn_h1)
        input_path = write_inputs(directory, segments, dt_internal * (1.0 + 1e-9), axial_damping_ratio,
                                  time_scheme)
        console_path = os.path.join(directory, f"h2_n{segments}_console.txt")
        result = h1._create_and_simulate(moordyn, input_path, console_path, segments, dt_internal, coupling_step,
                                         duration, quiet)
    result["time_scheme"] = time_scheme
    return result


def moordyn_kinematics(points, times, workdir: str | None = None) -> list:
    """MoorDyn's water velocity, acceleration and elevation at ``points`` (m, xyz) and
    ``times`` (s, ascending, from 0), read with ``moordyn.GetWavesKin`` from an H2 model
    with 10 segments stepped in time: a list over times of lists over points of
    ``(velocity, acceleration, elevation)``."""
    import moordyn

    segments = 10
    dt = 1e-3
    out = []
    with contextlib.ExitStack() as stack:
        directory = (stack.enter_context(tempfile.TemporaryDirectory(prefix="moordyn_h2_kin_"))
                     if workdir is None else workdir)
        input_path = write_inputs(directory, segments, dt)
        console_path = os.path.join(directory, "console.txt")
        with h1._standard_output_to(console_path):
            system = moordyn.Create(input_path)
            moordyn.Init(system, list(h1.FAIRLEAD_POSITION), [0.0, 0.0, 0.0])
        try:
            waves = moordyn.GetWaves(system)
            now = 0.0
            for t in times:
                while now < t - 1e-12:
                    step = min(dt, t - now)
                    moordyn.Step(system, list(h1.FAIRLEAD_POSITION), [0.0, 0.0, 0.0], now, step)
                    now += step
                row = []
                for point in points:
                    velocity, acceleration, elevation, _ = moordyn.GetWavesKin(waves, *map(float, point))
                    row.append((tuple(velocity), tuple(acceleration), float(elevation)))
                out.append(row)
        finally:
            with h1._standard_output_to(console_path):
                moordyn.Close(system)
    return out


def compare_kinematics(points=((0.0, 0.0, -10.0), (125.0, 0.0, -40.0), (250.0, 0.0, -11.0),
                               (60.0, 0.0, -99.85)),
                       times=(0.0, 2.3, 5.0, 9.7, 31.4)) -> dict:
    """Largest difference between MoorDyn's and rfesim's water kinematics for H2 at
    ``points`` and ``times``: ``{"velocity": m/s, "acceleration": m/s^2, "elevation": m,
    "velocity_scale": m/s, "acceleration_scale": m/s^2}`` (scales: the largest values
    seen), rfesim's from :func:`rfesim.sea.kernel.sea_kinematics_into` on the H2 scenario."""
    import numpy as np

    from ..sea.kernel import sea_kinematics_into, sea_spec
    from .h2 import h2_scenario

    scenario = h2_scenario(10, {"kind": "generalized-alpha", "time_step": 0.05})
    spec = sea_spec(scenario.environment)
    md = moordyn_kinematics(points, times)
    pts = np.asarray(points, dtype=float)
    eta = np.empty(len(pts))
    vel = np.empty((len(pts), 3))
    acc = np.empty((len(pts), 3))
    worst = {"velocity": 0.0, "acceleration": 0.0, "elevation": 0.0,
             "velocity_scale": 0.0, "acceleration_scale": 0.0}
    for t, row in zip(times, md):
        sea_kinematics_into(spec, float(t), pts, eta, vel, acc)
        for i, (u, a, e) in enumerate(row):
            worst["velocity"] = max(worst["velocity"], float(np.max(np.abs(np.asarray(u) - vel[i]))))
            worst["acceleration"] = max(worst["acceleration"], float(np.max(np.abs(np.asarray(a) - acc[i]))))
            worst["elevation"] = max(worst["elevation"], float(abs(e - eta[i])))
            worst["velocity_scale"] = max(worst["velocity_scale"], float(np.max(np.abs(vel[i]))))
            worst["acceleration_scale"] = max(worst["acceleration_scale"], float(np.max(np.abs(acc[i]))))
    return worst


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description="MoorDyn runs of benchmark line H2.")
    parser.add_argument("--segments", type=int, nargs="+", default=[25, 50, 100])
    parser.add_argument("--step-factor", type=float, default=1.0, help="multiple of the default dtM")
    parser.add_argument("--kinematics", action="store_true", help="compare the water kinematics with rfesim's")
    arguments = parser.parse_args()
    if not h1.moordyn_available():
        raise SystemExit("the moordyn package is not installed (pip install moordyn)")
    if arguments.kinematics:
        print(compare_kinematics())
    for n in arguments.segments:
        step = h1.default_internal_step(n) * arguments.step_factor
        r = run_moordyn_h2(n, step)
        print(f"N = {n:4d}  dtM = {1e3 * r['dt_internal']:.4g} ms  T amp = {r['tension_amplitude']:.1f} N  "
              f"M max = {r['max_sagbend_moment']:.0f} N*m  wall {r['wall_time']:.1f} s  IC {r['ic_wall_time']:.1f} s  "
              f"static T {r['static_fairlead_tension']:.0f} N", flush=True)
