"""MoorDyn reference runs of benchmark line H1, for work-precision comparisons.

Benchmark line H1 is a steel pipe (outer diameter 0.3 m, wall 0.02 m, empty) lying
partly on a flat seabed in 100 m of water: end A is pinned on the seabed at
(0, 0, -100) m, end B is a prescribed fairlead at (250, 0, -10) m, and the unstretched
length is 290 m. The fairlead heaves as ``z_B(t) = -10 + r(t) sin(2 pi t / 8)`` m with
the cosine ramp ``r(t) = 0.5 (1 - cos(pi t / 8))`` for ``t < 8`` s and 1 afterwards;
60 s are simulated. Two quantities are measured over the window 28-60 s:

1. the first-harmonic amplitude of the fairlead tension (N), from a least-squares fit
   of ``a0 + a cos(w t) + b sin(w t)`` at ``w = 2 pi / 8`` rad/s, amplitude
   ``sqrt(a^2 + b^2)``;
2. the largest sag-bend bending moment (N*m), the maximum over time and over the line
   nodes of ``EI * curvature`` with MoorDyn's node curvature.

This module runs the C++ MoorDyn v2 (PyPI package ``moordyn``) in-process on that line.

How the H1 data are written for MoorDyn
---------------------------------------
H1 is an *empty* (air-filled) pipe: its whole outer volume displaces water, so its
submerged weight is ``w = (rho_steel A_steel - rho_water pi/4 D_outer^2) g`` (about
644 N/m). MoorDyn describes a line by one diameter that sets the buoyancy, the drag and
the seabed contact areas; for this pipe that is simply the outer diameter:

* ``Diam = D_outer = 0.3 m``, ``Mass/m = rho_steel * A_steel`` (about 138.1 kg/m);
* drag coefficients 1.2 (normal, on ``Diam``) and 0.008 (axial, on ``pi Diam``), MoorDyn's
  own definitions; ``Ca = CaAx = 0``;
* ``EA = E * A_steel``, ``EI = E * pi/64 * (D_outer^4 - D_inner^4)``;
* seabed: MoorDyn's contact acts on the node (the pipe's centreline), rfesim's on the
  pipe's underside. So that both describe the same line, MoorDyn's seabed and anchor are
  at z = -99.85 m, where the centreline of the pipe resting on the real seabed at
  -100 m lies (rfesim's H1 scenario pins end A at -99.85 m on a seabed at -100 m).

Axial internal damping uses MoorDyn's negative-BA convention: ``BA = -0.8`` asks for
0.8 of the critical damping of one segment's axial mode (MoorDyn then sets
``BA = 0.8 * (L/N) * sqrt(EA * m)`` in N*s). Its effect is small: at 100 segments the
tension amplitude is 15549.1, 15549.7 and 15553.9 N for damping ratios 0.4, 0.8 and
1.6, and the moment does not change.

Coupling
--------
MoorDyn moves a coupled point with constant velocity within one ``moordyn.Step`` call.
The harness gives the fairlead its exact position at the start of each call and the
constant velocity that reaches the exact position at its end: a piecewise-linear path
whose velocity jumps by about ``a * dt`` at every call. Two errors follow (measured):

* the force MoorDyn returns at the end of a call uses the secant velocity, which lags
  the true one by about ``a * dt / 2``; through the large axial damping of the top
  segment this made the tension amplitude 0.6 % low with 1 ms calls (3.4 % low with
  5 ms, 6.7 % with 10 ms). Every ``OUTPUT_INTERVAL`` (0.01 s) a probe call of 1e-12 s
  with the exact fairlead velocity therefore makes MoorDyn re-evaluate the force at
  the exact fairlead position and velocity, without changing the state;
* the velocity jumps excite the short top segments: with 1 ms calls the probed
  amplitude was still 10, 16 and 20 N low at 100, 200 and 400 segments (60 N at 400
  with damping ratio 0.4). The fairlead is therefore updated at every internal step
  by default (coupling step = dtM, at most 1 ms); the remaining error (with the dtM
  error) is about 2 N at 100 segments and shrinks about as dtM^2.

Time integration
----------------
MoorDyn integrates explicitly with the internal step ``dtM``, which must stay below the
stability limit of the highest axial mode of the lumped-mass line, proportional to the
axial transit time of one segment ``(L / N) / sqrt(EA / m)`` = 0.05607 s / N (see
``segment_transit_time``). Measured on this line with ``BA = -0.8``: MoorDyn's default
RK2 is stable up to about 0.8 transit times, RK4 up to about 1.0 (unstable at 1.2).
RK4 is the default here because RK2 is also weakly unstable on the undamped bending
modes (highest bending frequency about ``4 sqrt(EI / m) / (L / N)^2``, amplified by
``1 + (w dt)^4 / 8`` per RK2 step): at 400 segments RK2 diverged at 0.48 transit times
and at 0.3 gave a spurious 20 % tension peak within 12 s, while RK4 ran stably at 0.9. The default dtM is
0.75 transit times for RK4 and 0.5 for RK2 (``default_internal_step``); there the
tension amplitude is within 4 N (RK4) or 7 N (RK2) of the half-step value at 50
segments, 2 N or 3.6 N at 100, 1 N or 1.8 N at 200.

Initial condition
-----------------
The initial condition comes from MoorDyn's dynamic relaxation (``ICgenDynamic 1``, drag
times 5, stopped when the fairlead tension changes by less than 1e-5 relative between
1 s checks). MoorDyn's default stationary solver is not used: earlier measurements on
this machine found it 36-42 % off on this stiff line (a check here at 50 segments left
the static tension 1.5 % low; by 28 s the dynamic amplitude no longer showed it). The
relaxed static state agrees with an independent elastica (inextensible rod with EI on
a rigid seabed, solved as a boundary-value problem): fairlead tension 184.2 kN,
horizontal tension 78.0 kN, largest moment 393 kN*m, touchdown 128 m from the anchor
(the elastic catenary without EI gives 194.7 kN and 142.8 m on the seabed).

Reference values
----------------
Convergence study (RK4, default steps, ``python -m rfesim.bench.moordyn_h1``): tension
amplitude 15282, 15521, 15550, 15581 and 15595 N and largest sag-bend moment 420.98,
419.53, 420.12, 420.02 and 419.90 kN*m for 25, 50, 100, 200 and 400 segments. The
amplitude still grows by 15-30 N per doubling at 400 segments; the estimated converged
values are 15.61 kN (+-0.01 kN) and 419.8 kN*m (+-0.2 kN*m).
"""
from __future__ import annotations

import contextlib
import ctypes
import math
import os
import re
import sys
import tempfile
import time as time_module

import numpy as np

# --------------------------------------------------------------------------------------
# Benchmark line H1 (SI units throughout)
# --------------------------------------------------------------------------------------
OUTER_DIAMETER = 0.3  # m
WALL_THICKNESS = 0.02  # m
INNER_DIAMETER = OUTER_DIAMETER - 2.0 * WALL_THICKNESS  # m
STEEL_AREA = math.pi / 4.0 * (OUTER_DIAMETER**2 - INNER_DIAMETER**2)  # m^2
YOUNG_MODULUS = 2.1e11  # Pa
STEEL_DENSITY = 7850.0  # kg/m^3
WATER_DENSITY = 1025.0  # kg/m^3
GRAVITY = 9.81  # m/s^2
WATER_DEPTH = 100.0 - 0.5 * 0.3  # m: MoorDyn's node-centre seabed = centreline of the pipe resting on z = -100
AXIAL_STIFFNESS = YOUNG_MODULUS * STEEL_AREA  # EA, N
BENDING_STIFFNESS = YOUNG_MODULUS * math.pi / 64.0 * (OUTER_DIAMETER**4 - INNER_DIAMETER**4)  # EI, N*m^2
MASS_PER_LENGTH = STEEL_DENSITY * STEEL_AREA  # kg/m (empty pipe)
SUBMERGED_WEIGHT_PER_LENGTH = (MASS_PER_LENGTH - WATER_DENSITY * math.pi / 4.0 * OUTER_DIAMETER**2) * GRAVITY  # N/m
ANCHOR_POSITION = (0.0, 0.0, -WATER_DEPTH)  # m, end A, pinned on the seabed (pipe centreline)
FAIRLEAD_POSITION = (250.0, 0.0, -10.0)  # m, end B, prescribed
UNSTRETCHED_LENGTH = 290.0  # m
NORMAL_DRAG_COEFFICIENT = 1.2  # -, on the outer diameter
AXIAL_DRAG_COEFFICIENT = 0.008  # -, on the outer circumference pi * D_outer
NORMAL_ADDED_MASS_COEFFICIENT = 0.0  # -
AXIAL_ADDED_MASS_COEFFICIENT = 0.0  # -
# MoorDyn's default seabed model: a vertical contact pressure kBot * penetration
# + cBot * penetration rate, here taken to act over the outer diameter, i.e. per metre
# of pipe 9e5 N/m per m of penetration and 9e4 N*s/m per m/s.
SEABED_STIFFNESS = 3.0e6  # Pa/m
SEABED_DAMPING = 3.0e5  # Pa*s/m
SEABED_FRICTION_COEFFICIENT = 0.0  # - (MoorDyn's default: no seabed friction)
AXIAL_DAMPING_RATIO = 0.8  # fraction of the critical damping of a segment's axial mode

# Fairlead motion and measurement window
HEAVE_AMPLITUDE = 1.0  # m
HEAVE_PERIOD = 8.0  # s
RAMP_DURATION = 8.0  # s
ANALYSIS_START = 28.0  # s
HEAVE_ANGULAR_FREQUENCY = 2.0 * math.pi / HEAVE_PERIOD  # rad/s

# MoorDyn's line diameter: the outer diameter of the empty pipe (buoyancy, drag, seabed)
MOORDYN_DIAMETER = OUTER_DIAMETER  # m
OUTER_TO_MOORDYN_DIAMETER = OUTER_DIAMETER / MOORDYN_DIAMETER  # - (1: no rescaling needed)

# Axial wave speed sqrt(EA / m) that sets the explicit stability limit
AXIAL_WAVE_SPEED = math.sqrt(AXIAL_STIFFNESS / MASS_PER_LENGTH)  # m/s

# MoorDyn time integrator (option tScheme) and default dtM in segment transit times.
# Measured stability limits on this line with BA = -0.8: RK2 about 0.8, RK4 about 1.0.
DEFAULT_TIME_SCHEME = "RK4"
DEFAULT_TRANSIT_FRACTION = {"RK2": 0.5, "RK4": 0.75}

# Dynamic-relaxation initial condition (MoorDyn options dtIC, TmaxIC, CdScaleIC, threshIC)
IC_CONVERGENCE_INTERVAL = 1.0  # s
IC_MAXIMUM_TIME = 200.0  # s
IC_DRAG_SCALE = 5.0  # -
IC_THRESHOLD = 1.0e-5  # - (relative fairlead tension change)

# Interval of the recorded fairlead tension and of the node-curvature samples
OUTPUT_INTERVAL = 0.01  # s
# Longest allowed coupling step (interval between moordyn.Step calls)
MAXIMUM_COUPLING_STEP = 1e-3  # s
# Length of the probe step that makes MoorDyn re-evaluate the fairlead force with the
# exact fairlead velocity at an output time (see ``run_moordyn_h1``)
PROBE_STEP = 1e-12  # s


def moordyn_available() -> bool:
    """Return True when the ``moordyn`` Python package (MoorDyn v2) can be imported."""
    try:
        import moordyn  # noqa: F401
    except Exception:
        return False
    return True


def fairlead_heave(time: float) -> float:
    """Prescribed fairlead height z_B (m) at ``time`` (s), ramped over the first 8 s."""
    if time < RAMP_DURATION:
        ramp = 0.5 * (1.0 - math.cos(math.pi * time / RAMP_DURATION))
    else:
        ramp = 1.0
    return FAIRLEAD_POSITION[2] + ramp * HEAVE_AMPLITUDE * math.sin(HEAVE_ANGULAR_FREQUENCY * time)


def fairlead_heave_velocity(time: float) -> float:
    """Prescribed fairlead vertical velocity dz_B/dt (m/s) at ``time`` (s)."""
    phase = HEAVE_ANGULAR_FREQUENCY * time
    if time < RAMP_DURATION:
        ramp = 0.5 * (1.0 - math.cos(math.pi * time / RAMP_DURATION))
        ramp_rate = 0.5 * math.pi / RAMP_DURATION * math.sin(math.pi * time / RAMP_DURATION)
    else:
        ramp, ramp_rate = 1.0, 0.0
    return HEAVE_AMPLITUDE * (ramp_rate * math.sin(phase) + ramp * HEAVE_ANGULAR_FREQUENCY * math.cos(phase))


def segment_transit_time(segments: int) -> float:
    """Time (s) an axial wave needs to cross one segment: ``(L / N) / sqrt(EA / m)``.

    Equal to 0.05607 s / N for H1. MoorDyn's "natural period" of a segment, used for its
    CFL factor, is ``2 pi`` times this value.
    """
    return UNSTRETCHED_LENGTH / segments / AXIAL_WAVE_SPEED


def default_internal_step(segments: int, coupling_step: float | None = None,
                          time_scheme: str = DEFAULT_TIME_SCHEME) -> float:
    """Default MoorDyn internal step dtM (s) for ``segments`` segments.

    ``DEFAULT_TRANSIT_FRACTION[time_scheme]`` times the axial transit time of one
    segment (RK4: 0.75 * 0.05607 s / N = 0.04205 s / N; RK2: 0.02804 s / N), lowered so
    that a whole number of steps fits in ``coupling_step`` or, when that is None (the
    fairlead is then updated at every internal step), capped at
    ``MAXIMUM_COUPLING_STEP`` and lowered so that a whole number of steps fits in
    ``OUTPUT_INTERVAL``. With RK4 and no coupling step this gives 1 ms for N = 25,
    0.833 ms for N = 50, 0.417 ms for N = 100, 0.208 ms for N = 200 and 0.104 ms for
    N = 400 (RK2: 1, 0.556, 0.278, 0.139 and 0.070 ms).
    """
    scheme = time_scheme.upper()
    if scheme not in DEFAULT_TRANSIT_FRACTION:
        raise ValueError(f"no default dtM for time scheme {time_scheme!r}; pass dt_internal "
                         f"(known: {', '.join(DEFAULT_TRANSIT_FRACTION)})")
    target = DEFAULT_TRANSIT_FRACTION[scheme] * segment_transit_time(segments)
    if coupling_step is None:
        return fit_to_coupling_step(min(target, MAXIMUM_COUPLING_STEP), OUTPUT_INTERVAL)
    return fit_to_coupling_step(target, coupling_step)


def fit_to_coupling_step(dt_internal: float, coupling_step: float) -> float:
    """Largest step (s) <= ``dt_internal`` that divides ``coupling_step`` into equal parts."""
    substeps = max(1, math.ceil(coupling_step / dt_internal - 1e-6))
    return coupling_step / substeps


def elastic_catenary_estimate() -> dict:
    """Static estimate of H1 as an inextensible catenary on a rigid seabed (no EI).

    Returns a dict with ``horizontal_tension`` (N), ``fairlead_tension`` (N),
    ``suspended_length`` (m) and ``grounded_length`` (m). The submerged weight per metre
    is ``SUBMERGED_WEIGHT_PER_LENGTH``; axial strain (below 1e-4 here) would change
    these numbers by less than 0.1 %. Bending stiffness, ignored here, lowers the
    fairlead tension to about 184 kN and the grounded length to about 128 m.
    """
    span = FAIRLEAD_POSITION[0] - ANCHOR_POSITION[0]
    height = FAIRLEAD_POSITION[2] - ANCHOR_POSITION[2]

    def span_mismatch(catenary_parameter: float) -> float:
        suspended = math.sqrt(height**2 + 2.0 * height * catenary_parameter)
        return (UNSTRETCHED_LENGTH - suspended) + catenary_parameter * math.asinh(
            suspended / catenary_parameter) - span

    low, high = 1e-3, 1e5  # bisection on the catenary parameter H / w (m)
    for _ in range(200):
        middle = 0.5 * (low + high)
        if span_mismatch(middle) > 0.0:
            high = middle
        else:
            low = middle
    catenary_parameter = 0.5 * (low + high)
    suspended = math.sqrt(height**2 + 2.0 * height * catenary_parameter)
    horizontal = catenary_parameter * SUBMERGED_WEIGHT_PER_LENGTH
    return {
        "horizontal_tension": horizontal,
        "fairlead_tension": horizontal + SUBMERGED_WEIGHT_PER_LENGTH * height,
        "suspended_length": suspended,
        "grounded_length": UNSTRETCHED_LENGTH - suspended,
    }


def first_harmonic_amplitude(time: np.ndarray, signal: np.ndarray,
                             angular_frequency: float = HEAVE_ANGULAR_FREQUENCY,
                             start: float = ANALYSIS_START) -> float:
    """Amplitude of ``signal`` at ``angular_frequency`` (rad/s) over ``time >= start`` (s).

    Least-squares fit of ``a0 + a cos(w t) + b sin(w t)``; returns ``sqrt(a^2 + b^2)`` in
    the units of ``signal``.
    """
    time = np.asarray(time, dtype=float)
    signal = np.asarray(signal, dtype=float)
    window = time >= start - 1e-9
    phase = angular_frequency * time[window]
    basis = np.column_stack([np.ones_like(phase), np.cos(phase), np.sin(phase)])
    coefficients = np.linalg.lstsq(basis, signal[window], rcond=None)[0]
    return float(math.hypot(coefficients[1], coefficients[2]))


def moordyn_input_text(segments: int, dt_internal: float,
                       axial_damping_ratio: float = AXIAL_DAMPING_RATIO,
                       time_scheme: str = DEFAULT_TIME_SCHEME) -> str:
    """Text of a MoorDyn v2 input file for H1 with ``segments`` segments and step dtM (s).

    Point 1 is the anchor ("Fixed"), point 2 the fairlead ("Coupled"); the line runs
    from point 1 (end A) to point 2 (end B). ``axial_damping_ratio`` is written as a
    negative BA (fraction of critical damping of a segment's axial mode).
    """
    scale = OUTER_TO_MOORDYN_DIAMETER
    anchor_x, anchor_y, anchor_z = ANCHOR_POSITION
    fairlead_x, fairlead_y, fairlead_z = FAIRLEAD_POSITION
    return f"""--------------------- MoorDyn Input File ------------------------------------
Benchmark line H1 (rfesim.bench.moordyn_h1): steel pipe OD 0.3 m, wall 0.02 m, empty
(air inside): Diam is the outer diameter; seabed at the centreline of the resting pipe.
---------------------- LINE TYPES ----------------------------------------------------
TypeName  Diam  Mass/m  EA  BA/-zeta  EI  Cd  Ca  CdAx  CaAx
(name)  (m)  (kg/m)  (N)  (N-s/-)  (N-m^2)  (-)  (-)  (-)  (-)
pipe  {MOORDYN_DIAMETER:.12g}  {MASS_PER_LENGTH:.12g}  {AXIAL_STIFFNESS:.12g}  {-axial_damping_ratio:.6g}  {BENDING_STIFFNESS:.12g}  {NORMAL_DRAG_COEFFICIENT * scale:.12g}  {NORMAL_ADDED_MASS_COEFFICIENT:g}  {AXIAL_DRAG_COEFFICIENT * scale:.12g}  {AXIAL_ADDED_MASS_COEFFICIENT:g}
---------------------- POINTS --------------------------------------------------------
ID  Attachment  X  Y  Z  Mass  Volume  CdA  Ca
(#)  (word/ID)  (m)  (m)  (m)  (kg)  (m^3)  (m^2)  (-)
1  Fixed  {anchor_x:.12g}  {anchor_y:.12g}  {anchor_z:.12g}  0  0  0  0
2  Coupled  {fairlead_x:.12g}  {fairlead_y:.12g}  {fairlead_z:.12g}  0  0  0  0
---------------------- LINES ---------------------------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)  (ID)  (ID)  (m)  (-)  (-)
1  pipe  1  2  {UNSTRETCHED_LENGTH:.12g}  {int(segments)}  -
---------------------- OPTIONS -------------------------------------------------------
0  writeLog  no log file
{dt_internal:.12g}  dtM  internal time step (s)
{time_scheme}  tScheme  time integrator
{GRAVITY:.12g}  g  gravity (m/s^2)
{WATER_DENSITY:.12g}  rho  water density (kg/m^3)
{WATER_DEPTH:.12g}  WtrDpth  water depth (m)
{SEABED_STIFFNESS * scale:.12g}  kBot  seabed stiffness on Diam (Pa/m)
{SEABED_DAMPING * scale:.12g}  cBot  seabed damping on Diam (Pa-s/m)
{SEABED_FRICTION_COEFFICIENT:g}  FrictionCoefficient  seabed friction (-)
1  ICgenDynamic  dynamic-relaxation initial condition
{IC_CONVERGENCE_INTERVAL:.12g}  dtIC  convergence check interval (s)
{IC_MAXIMUM_TIME:.12g}  TmaxIC  longest relaxation (s)
{IC_DRAG_SCALE:.12g}  CdScaleIC  drag factor during relaxation (-)
{IC_THRESHOLD:.12g}  threshIC  relative tension change to stop (-)
1  disableOutput  no output files beyond headers
1  disableOutTime  no time printing
------------------------- need this line ---------------------------------------------
"""


def _work_directory(stack: contextlib.ExitStack, workdir, prefix: str) -> str:
    """``workdir`` (created if needed), or a temporary directory removed with ``stack``."""
    if workdir is None:
        return stack.enter_context(tempfile.TemporaryDirectory(prefix=prefix))
    directory = os.path.abspath(workdir)
    os.makedirs(directory, exist_ok=True)
    return directory


def _create_and_simulate(moordyn, input_path: str, console_path: str, segments: int, dt_internal: float,
                         coupling_step: float, duration: float, quiet: bool) -> dict:
    """Load the MoorDyn input, run ``_simulate`` and close the system, MoorDyn's console
    output going to ``console_path`` (echoed unless ``quiet``)."""
    with open(console_path, "w"):
        pass
    with _standard_output_to(console_path):
        system = moordyn.Create(input_path)
    if system is None:
        raise RuntimeError(f"MoorDyn could not load {input_path}")
    try:
        return _simulate(moordyn, system, segments, dt_internal, coupling_step, duration, console_path)
    finally:
        with _standard_output_to(console_path):
            moordyn.Close(system)
        if not quiet:
            with open(console_path) as handle:
                print(handle.read(), end="")


@contextlib.contextmanager
def _standard_output_to(path: str):
    """Send file descriptor 1 (MoorDyn's C++ console messages) to the file ``path``."""
    sys.stdout.flush()
    saved_descriptor = os.dup(1)
    file_descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    try:
        os.dup2(file_descriptor, 1)
        yield
    finally:
        with contextlib.suppress(Exception):
            ctypes.CDLL(None).fflush(None)
        os.dup2(saved_descriptor, 1)
        os.close(saved_descriptor)
        os.close(file_descriptor)


def _initial_condition_report(console_text: str) -> tuple[bool, float, float]:
    """(converged, relaxation time in s, remaining relative error) from MoorDyn's messages."""
    converged = "Fairlead tensions converged" in console_text
    match = re.search(r"Remaining error after\s+([-+0-9.eE]+)\s*s\s*=\s*([-+0-9.eE]+)\s*%", console_text)
    if match is None:
        return converged, float("nan"), float("nan")
    return converged, float(match.group(1)), float(match.group(2)) / 100.0


def run_moordyn_h1(segments: int, dt_internal: float | None = None, coupling_step: float | None = None,
                   duration: float = 60.0, workdir: str | None = None,
                   axial_damping_ratio: float = AXIAL_DAMPING_RATIO,
                   time_scheme: str = DEFAULT_TIME_SCHEME, quiet: bool = True) -> dict:
    """Run MoorDyn on line H1 and measure the fairlead tension amplitude and sag-bend moment.

    Parameters
    ----------
    segments:
        Number of line segments N (the line has N + 1 nodes).
    dt_internal:
        MoorDyn's internal step dtM (s); ``None`` picks ``default_internal_step``. It is
        lowered, if needed, so that it divides ``coupling_step`` (or, without a coupling
        step, ``OUTPUT_INTERVAL``) into equal parts.
    coupling_step:
        Interval (s) between ``moordyn.Step`` calls, i.e. between fairlead updates; at
        most 1 ms. ``None`` (the default) updates the fairlead at every internal step
        (coupling step = dtM, at most 1 ms), which removes most of the coupling error
        (see the module notes): a fixed 1 ms biased the amplitude by -10, -16 and -20 N
        at 100, 200 and 400 segments.
    duration:
        Simulated time (s) after the initial condition; the analysis window is
        ``ANALYSIS_START`` (28 s) to ``duration``.
    workdir:
        Directory for MoorDyn's input file and console log (kept); ``None`` uses a
        temporary directory that is removed afterwards.
    axial_damping_ratio:
        Axial internal damping as a fraction of a segment's critical damping (written as
        a negative BA).
    time_scheme:
        MoorDyn time integrator (option ``tScheme``), "RK4" (default) or e.g. "RK2".
    quiet:
        Keep MoorDyn's console messages out of the terminal (they are still captured to
        find the initial-condition result).

    Returns
    -------
    dict with
        ``tension_amplitude`` (N): first-harmonic amplitude over 28 s .. ``duration`` of
        the fairlead tension, the magnitude of the force the line applies to the coupled
        fairlead point (what ``moordyn.Step`` returns), evaluated at the exact fairlead
        position and velocity every ``OUTPUT_INTERVAL`` (0.01 s);
        ``max_sagbend_moment`` (N*m): largest ``EI * curvature`` over the line nodes and
        over the analysis window (MoorDyn's node curvatures, every ``OUTPUT_INTERVAL``);
        ``wall_time`` (s): wall-clock time of the dynamic run only (the coupling loop
        with its output probes and samples, without file writing and initial condition);
        ``ic_wall_time`` (s): wall-clock time of ``moordyn.Init`` (dynamic relaxation);
        ``segments``; ``dt_internal`` (s, the dtM used); ``coupling_step`` (s);
        ``time_scheme``; ``real_time_factor`` (simulated time / ``wall_time``);
        ``time`` (s) and ``fairlead_tension`` (N): arrays every ``OUTPUT_INTERVAL`` from 0
        (the first value is the static tension after the initial condition);
        ``line_fairlead_tension_amplitude`` (N): the same fit on
        ``moordyn.GetLineFairTen``, MoorDyn's line fairlead tension (it leaves out part
        of the top node's load: 1.8 % below the point force in the static state at 50
        segments, 0.2 % lower amplitude);
        ``max_sagbend_moment_time`` (s), ``max_sagbend_moment_node`` and
        ``max_sagbend_moment_node_position`` (m, xyz): when and where the largest moment
        occurred;
        ``ic_converged`` (bool), ``ic_relaxation_time`` (s of simulated relaxation) and
        ``ic_remaining_error`` (relative): the dynamic-relaxation result;
        ``static_fairlead_force`` (N, xyz), ``static_fairlead_tension`` (N),
        ``static_grounded_length`` (m, unstretched length of segments whose two nodes are
        within 1 cm of the seabed) and ``static_max_moment`` (N*m): the configuration
        after the initial condition.
    """
    import moordyn

    segments = int(segments)
    if segments < 2:
        raise ValueError(f"segments must be at least 2, got {segments}")
    if coupling_step is not None and not 0.0 < coupling_step <= MAXIMUM_COUPLING_STEP * (1.0 + 1e-9):
        raise ValueError(f"coupling_step must be in (0, {MAXIMUM_COUPLING_STEP}] s, got {coupling_step}")
    if duration <= ANALYSIS_START + HEAVE_PERIOD:
        raise ValueError(f"duration must exceed {ANALYSIS_START + HEAVE_PERIOD} s, got {duration}")
    if dt_internal is None:
        dt_internal = default_internal_step(segments, coupling_step, time_scheme)
    elif coupling_step is None:
        dt_internal = fit_to_coupling_step(min(float(dt_internal), MAXIMUM_COUPLING_STEP), OUTPUT_INTERVAL)
    else:
        dt_internal = fit_to_coupling_step(float(dt_internal), coupling_step)
    if coupling_step is None:
        coupling_step = dt_internal

    with contextlib.ExitStack() as stack:
        directory = _work_directory(stack, workdir, "moordyn_h1_")
        input_path = os.path.join(directory, f"h1_n{segments}.dat")
        console_path = os.path.join(directory, f"h1_n{segments}_console.txt")
        # MoorDyn subtracts dtM from the coupling step until nothing is left; written as
        # coupling_step / k exactly, rounding often leaves a ~1e-19 s remainder and thus
        # a (k+1)-th internal step. A dtM larger by 1e-9 (relative) gives exactly k steps.
        with open(input_path, "w") as handle:
            handle.write(moordyn_input_text(segments, dt_internal * (1.0 + 1e-9), axial_damping_ratio,
                                            time_scheme))
        result = _create_and_simulate(moordyn, input_path, console_path, segments, dt_internal, coupling_step,
                                      duration, quiet)
    result["time_scheme"] = time_scheme
    return result


def _simulate(moordyn, system, segments: int, dt_internal: float, coupling_step: float,
              duration: float, console_path: str) -> dict:
    """Initial condition and coupled time loop of ``run_moordyn_h1``."""
    fairlead_x, fairlead_y, fairlead_z = FAIRLEAD_POSITION
    start_clock = time_module.perf_counter()
    with _standard_output_to(console_path):
        error_code = moordyn.Init(system, [fairlead_x, fairlead_y, fairlead_z], [0.0, 0.0, 0.0])
    ic_wall_time = time_module.perf_counter() - start_clock
    with open(console_path) as handle:
        ic_converged, ic_relaxation_time, ic_remaining_error = _initial_condition_report(handle.read())
    if error_code != 0:
        raise RuntimeError(f"moordyn.Init failed with error code {error_code} "
                           f"(segments={segments}, dtM={dt_internal:g} s)")

    line = moordyn.GetLine(system, 1)
    fairlead_point = moordyn.GetPoint(system, 2)
    node_count = segments + 1

    static_force = np.array(moordyn.GetPointForce(fairlead_point), dtype=float)
    static_positions = np.array([moordyn.GetLineNodePos(line, node) for node in range(node_count)])
    static_curvatures = np.array([moordyn.GetLineNodeCurv(line, node) for node in range(node_count)])
    touching = static_positions[:, 2] <= -WATER_DEPTH + 0.01
    static_grounded_length = float(np.sum(touching[:-1] & touching[1:])) * UNSTRETCHED_LENGTH / segments

    step_count = int(round(duration / coupling_step))
    sample_every = max(1, int(round(OUTPUT_INTERVAL / coupling_step)))
    sample_count = step_count // sample_every + 1
    times = np.arange(sample_count) * (sample_every * coupling_step)
    fairlead_tension = np.empty(sample_count)
    line_fairlead_tension = np.empty(sample_count)
    fairlead_tension[0] = float(np.linalg.norm(static_force))
    line_fairlead_tension[0] = moordyn.GetLineFairTen(line)

    largest_curvature = -1.0
    largest_curvature_time = float("nan")
    largest_curvature_node = -1
    largest_curvature_position = (float("nan"),) * 3
    nodes = range(node_count)
    step = moordyn.Step
    get_curvature = moordyn.GetLineNodeCurv

    height_now = fairlead_heave(0.0)
    start_clock = time_module.perf_counter()
    for index in range(step_count):
        time_now = index * coupling_step
        time_next = (index + 1) * coupling_step
        height_next = fairlead_heave(time_next)
        try:
            # exact position at the start of the step and the secant velocity that
            # reaches the exact position at its end
            step(system, [fairlead_x, fairlead_y, height_now],
                 [0.0, 0.0, (height_next - height_now) / coupling_step], time_now, coupling_step)
            height_now = height_next
            if (index + 1) % sample_every:
                continue
            # Output time: MoorDyn's force at the end of a step uses the step's secant
            # velocity, a velocity error of about a * dt / 2 that the line's axial damping
            # turns into a force error (about -0.6 % on the tension amplitude at 1 ms).
            # A probe step of 1e-12 s with the exact velocity re-evaluates the force at
            # the exact fairlead position and velocity without changing the state.
            force = step(system, [fairlead_x, fairlead_y, height_now],
                         [0.0, 0.0, fairlead_heave_velocity(time_next)], time_next, PROBE_STEP)
        except Exception as error:
            raise RuntimeError(f"MoorDyn failed at t = {time_now:.3f} s (segments={segments}, "
                               f"dtM={dt_internal:g} s)") from error
        sample = (index + 1) // sample_every
        fairlead_tension[sample] = math.sqrt(force[0] ** 2 + force[1] ** 2 + force[2] ** 2)
        line_fairlead_tension[sample] = moordyn.GetLineFairTen(line)
        if times[sample] >= ANALYSIS_START - 1e-9:
            curvatures = [get_curvature(line, node) for node in nodes]
            node = int(np.argmax(curvatures))
            if curvatures[node] > largest_curvature:
                largest_curvature = curvatures[node]
                largest_curvature_time = float(times[sample])
                largest_curvature_node = node
                largest_curvature_position = moordyn.GetLineNodePos(line, node)
    wall_time = time_module.perf_counter() - start_clock

    if not (np.all(np.isfinite(fairlead_tension)) and math.isfinite(largest_curvature)):
        raise RuntimeError(f"MoorDyn diverged (segments={segments}, dtM={dt_internal:g} s)")

    return {
        "tension_amplitude": first_harmonic_amplitude(times, fairlead_tension),
        "max_sagbend_moment": BENDING_STIFFNESS * largest_curvature,
        "wall_time": wall_time,
        "ic_wall_time": ic_wall_time,
        "segments": segments,
        "dt_internal": dt_internal,
        "coupling_step": coupling_step,
        "real_time_factor": duration / wall_time,
        "time": times,
        "fairlead_tension": fairlead_tension,
        "line_fairlead_tension_amplitude": first_harmonic_amplitude(times, line_fairlead_tension),
        "max_sagbend_moment_time": largest_curvature_time,
        "max_sagbend_moment_node": largest_curvature_node,
        "max_sagbend_moment_node_position": tuple(float(value) for value in largest_curvature_position),
        "ic_converged": ic_converged,
        "ic_relaxation_time": ic_relaxation_time,
        "ic_remaining_error": ic_remaining_error,
        "static_fairlead_force": tuple(float(value) for value in static_force),
        "static_fairlead_tension": float(np.linalg.norm(static_force)),
        "static_grounded_length": static_grounded_length,
        "static_max_moment": BENDING_STIFFNESS * float(static_curvatures.max()),
    }


def convergence_study(segment_counts=(25, 50, 100, 200, 400), step_factors=(1.0, 0.5),
                      time_scheme: str = DEFAULT_TIME_SCHEME, time_budget: float = 600.0,
                      damping_check_segments: int | None = 100, report=print) -> list[dict]:
    """Run ``run_moordyn_h1`` over segment counts and internal steps, printing a table.

    ``step_factors`` multiply ``default_internal_step(N)``. A run is skipped when the
    predicted wall time (initial condition plus dynamic run, scaled from the previous
    segment count's default-step run by the node count and the step ratio) would bring
    the time spent on its segment count above ``time_budget`` (s). When
    ``damping_check_segments`` is set, that segment count is also run with axial damping
    ratios 0.4 and 1.6 at the smallest step factor. Returns the result dicts without
    their time series.
    """
    results: list[dict] = []
    header = (f"{'N':>5} {'dtM (s)':>10} {'dtM/transit':>11} {'zeta':>5} {'T amp (N)':>10} "
              f"{'M max (kN*m)':>12} {'wall (s)':>9} {'x real':>7} {'IC (s)':>7} {'relax (s)':>9} "
              f"{'T static (N)':>12}")
    report(f"MoorDyn {time_scheme}, fairlead updated every internal step (coupling step = dtM), "
           f"60 s simulated, analysis 28-60 s")
    report(header)
    report("-" * len(header))

    def run_and_report(segments: int, dt_internal: float, damping_ratio: float) -> dict:
        result = run_moordyn_h1(segments, dt_internal, axial_damping_ratio=damping_ratio,
                                time_scheme=time_scheme)
        summary = {key: value for key, value in result.items() if key not in ("time", "fairlead_tension")}
        summary["axial_damping_ratio"] = damping_ratio
        results.append(summary)
        report(f"{segments:>5} {result['dt_internal']:>10.4g} "
               f"{result['dt_internal'] / segment_transit_time(segments):>11.3f} {damping_ratio:>5.2f} "
               f"{result['tension_amplitude']:>10.1f} {result['max_sagbend_moment'] / 1e3:>12.2f} "
               f"{result['wall_time']:>9.1f} {result['real_time_factor']:>7.2f} "
               f"{result['ic_wall_time']:>7.1f} {result['ic_relaxation_time']:>9.1f} "
               f"{result['static_fairlead_tension']:>12.0f}"
               + ("" if result["ic_converged"] else "  (initial condition not converged)"))
        return summary

    reference = None  # (segments, dtM, seconds) of the last default-step run
    for segments in segment_counts:
        spent = 0.0
        for index, factor in enumerate(step_factors):
            step = default_internal_step(segments, None, time_scheme) * factor
            if reference is not None:
                predicted = reference[2] * (segments / reference[0]) * (reference[1] / step)
                if spent + predicted > time_budget:
                    report(f"{segments:>5} {step:>10.4g}  skipped: about {predicted:.0f} s predicted, "
                           f"budget {time_budget:.0f} s per N")
                    continue
            summary = run_and_report(segments, step, AXIAL_DAMPING_RATIO)
            seconds = summary["wall_time"] + summary["ic_wall_time"]
            spent += seconds
            if index == 0:
                reference = (segments, step, seconds)

    if damping_check_segments:
        step = default_internal_step(damping_check_segments, None, time_scheme) * min(step_factors)
        for damping_ratio in (0.4, 1.6):
            run_and_report(damping_check_segments, step, damping_ratio)

    _report_summary(results, report)
    return results


def _report_summary(results: list[dict], report=print) -> None:
    """Print, per segment count, the finest-step values and their changes."""
    nominal = [result for result in results if result["axial_damping_ratio"] == AXIAL_DAMPING_RATIO]
    finest: dict[int, dict] = {}
    coarsest: dict[int, dict] = {}
    for result in nominal:
        segments = result["segments"]
        if segments not in finest or result["dt_internal"] < finest[segments]["dt_internal"]:
            finest[segments] = result
        if segments not in coarsest or result["dt_internal"] > coarsest[segments]["dt_internal"]:
            coarsest[segments] = result
    report("")
    report("Finest step per N (change from the coarser step; change from the previous N):")
    previous = None
    for segments in sorted(finest):
        fine, coarse = finest[segments], coarsest[segments]
        step_change = (f"{fine['tension_amplitude'] - coarse['tension_amplitude']:+8.1f} N, "
                       f"{(fine['max_sagbend_moment'] - coarse['max_sagbend_moment']) / 1e3:+6.2f} kN*m"
                       if fine is not coarse else "  single step       ")
        n_change = (f"{fine['tension_amplitude'] - previous['tension_amplitude']:+8.1f} N, "
                    f"{(fine['max_sagbend_moment'] - previous['max_sagbend_moment']) / 1e3:+6.2f} kN*m"
                    if previous is not None else "")
        report(f"  N = {segments:>4}: {fine['tension_amplitude']:9.1f} N, {fine['max_sagbend_moment'] / 1e3:7.2f} kN*m"
               f"  (dtM: {step_change}; N: {n_change})")
        previous = fine
    damping = [result for result in results if result["axial_damping_ratio"] != AXIAL_DAMPING_RATIO]
    if damping:
        same = [result for result in nominal if result["segments"] == damping[0]["segments"]
                and math.isclose(result["dt_internal"], damping[0]["dt_internal"])]
        report("Axial damping ratio (same N and dtM):")
        for result in sorted(same + damping, key=lambda run: run["axial_damping_ratio"]):
            report(f"  zeta = {result['axial_damping_ratio']:.2f}: {result['tension_amplitude']:9.1f} N, "
                   f"{result['max_sagbend_moment'] / 1e3:7.2f} kN*m  (N = {result['segments']}, "
                   f"dtM = {result['dt_internal']:.4g} s)")


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description="MoorDyn convergence study on benchmark line H1.")
    parser.add_argument("--segments", type=int, nargs="+", default=[25, 50, 100, 200, 400])
    parser.add_argument("--step-factors", type=float, nargs="+", default=[1.0, 0.5],
                        help="multiples of the default dtM")
    parser.add_argument("--time-scheme", default=DEFAULT_TIME_SCHEME, help="MoorDyn tScheme (RK4 or RK2)")
    parser.add_argument("--time-budget", type=float, default=600.0,
                        help="largest predicted wall time (s) spent on one N")
    parser.add_argument("--damping-check-segments", type=int, default=100,
                        help="N for the axial-damping sensitivity runs (0 to skip)")
    arguments = parser.parse_args()
    if not moordyn_available():
        raise SystemExit("the moordyn package is not installed (pip install moordyn)")
    estimate = elastic_catenary_estimate()
    print(f"Elastic catenary without EI: fairlead tension {estimate['fairlead_tension']:.0f} N, "
          f"horizontal {estimate['horizontal_tension']:.0f} N, on the seabed {estimate['grounded_length']:.1f} m")
    convergence_study(arguments.segments, arguments.step_factors, arguments.time_scheme,
                      arguments.time_budget, arguments.damping_check_segments or None)
