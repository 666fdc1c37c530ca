"""A submerged payload on a rope against closed forms: the added mass and buoyancy set the
pendulum and heave periods (per body axis, turned with the body), quadratic drag decays
the swing as 1/A grows linearly, and a current pulls the rope over by the drag per body
axis, and a regular wave swings it by its Froude-Krylov and added-mass forces
(rfesim.loads.bodies).

The payload: m = 10 t, V = 2 m^3, fully submerged 50 m down in water 200 m deep, on a
20 m rope (EA 1e8 N, 1 kg/m, no sea loads of its own) from a fixed point 30 m down. The
closed forms keep the small terms a 1e-5 check sees: the rope's static stretch, its mass
(m_r/3 in the inertia, m_r g L/2 in the pendulum's restoring moment) and the body
connection's compliance (100 EA / Delta_0, docs/theory.md 'Connection')."""
from __future__ import annotations

import math

import numpy as np
import pytest

import rfesim

G, RHO = 9.81, 1025.0
M, V, L, EA, MPL, TOP, N = 1.0e4, 2.0, 20.0, 1.0e8, 1.0, -30.0, 10
SUBMERGED_WEIGHT = (M - RHO * V) * G


def scene(ca, *, swing_deg=0.0, axis=0, yaw_deg=0.0, time_step=0.01, duration=40.0, drag=None, current=None,
          statics=False, attach_z=0.0, waves=None, start_static=False):
    a = math.radians(swing_deg)
    position = [0.0, 0.0, TOP - L * math.cos(a) - attach_z]
    position[axis] = L * math.sin(a)
    body = {"mass": M, "inertia": [1e4, 1.2e4, 1.4e4], "volume": V, "height": 2.0,
            "added_mass": {"ca": ca}, "orientation_deg": [0.0, 0.0, yaw_deg], "position": position}
    if drag:
        body["drag"] = drag
    water = {"density": RHO, "depth": 200.0}
    if current:
        water["current"] = current
    if waves:
        water["waves"] = waves
    analysis = ({"statics": {"enabled": True}, "dynamics": {"enabled": False}} if statics else
                {"statics": {"enabled": True} if start_static else {"enabled": False, "start": "straight"},
                 "dynamics": {"duration": duration, "output_interval": time_step,
                              "integrator": {"kind": "generalized-alpha", "time_step": time_step, "rho_inf": 0.9}}})
    return {"environment": {"gravity": G, "water": water},
            "line_types": {"rope": {"EA": EA, "EIy": 1.0, "mass_per_length": MPL, "tension_only": True}},
            "bodies": {"payload": body},
            "lines": {"hoist": {"type": "rope", "length": L, "elements": N,
                                "end_a": {"attach": "fixed", "position": [0.0, 0.0, TOP]},
                                "end_b": {"attach": "payload", "position": [0.0, 0.0, attach_z]}}},
            "analysis": analysis}


def mean_period(t, x) -> float:
    """Mean time between upward crossings of the mean (linear interpolation)."""
    x = x - x.mean()
    i = np.where((x[:-1] < 0.0) & (x[1:] >= 0.0))[0]
    crossings = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    assert len(crossings) >= 3
    return float(np.diff(crossings).mean())


def pendulum_period(ca: float, swing_deg: float) -> float:
    """T = 2 pi sqrt(I / K) (1 + theta0^2 / 16): I = (m + ca rho V) L'^2 + m_r L'^2 / 3,
    K = (m - rho V) g L' + m_r g L' / 2, L' the rope stretched by the submerged weight."""
    stretched = L * (1.0 + SUBMERGED_WEIGHT / EA)
    rope = MPL * L
    inertia = (M + ca * RHO * V) * stretched ** 2 + rope * stretched ** 2 / 3.0
    restoring = SUBMERGED_WEIGHT * stretched + rope * G * stretched / 2.0
    return 2.0 * math.pi * math.sqrt(inertia / restoring) * (1.0 + math.radians(swing_deg) ** 2 / 16.0)


@pytest.mark.parametrize("axis, yaw_deg, ca_along", [(0, 0.0, 0.5), (1, 0.0, 1.5), (0, 90.0, 1.5)])
def test_submerged_pendulum_period_takes_the_added_mass_of_the_body_axis_it_swings_along(axis, yaw_deg, ca_along):
    """ca = [0.5, 1.5, 1.0] in body axes: swinging along x the period is 10.565 s, along y
    11.505 s, and along x with the body yawed 90 deg (its y axis along global x) 11.505 s
    again; each within 5e-5 of the closed form (measured 1.4e-5 to 3.0e-5 at steps of 0.01,
    0.005 and 0.0025 s, not converging in h: the rope's heave bounce from the straight start,
    4 cm peak to peak, which the closed form leaves out, moves the crossings by that much).
    Without the added mass the period would be 5-13 % shorter, in air (no buoyancy either,
    2 pi sqrt(L/g)) 15-22 %."""
    swing = 2.0
    res = rfesim.simulate(scene([0.5, 1.5, 1.0], swing_deg=swing, axis=axis, yaw_deg=yaw_deg))
    period = mean_period(res.time, res.body("payload").position[:, axis])
    expected = pendulum_period(ca_along, swing)
    assert period == pytest.approx(expected, rel=5e-5)
    assert abs(pendulum_period(0.0, swing) / expected - 1.0) > 0.04


def test_modes_of_the_submerged_payload_are_its_pendulum_and_heave_closed_forms():
    """The modal analysis about the statics (rfesim.modes) linearises the same terms: with
    ca = [0.5, 1.5, 2] the two swings at 1 / T of the pendulum's closed form (0.08692 Hz
    along x, 0.09465 Hz along y) and the heave at sqrt(k / m_eff) / (2 pi) = 2.995 Hz, each
    within 1e-5 (measured 1e-6). Below them only zero modes (the free yaw and twist)."""
    md = rfesim.api.modes(scene([0.5, 1.5, 2.0], start_static=True), n=8)
    f = md.frequencies_hz
    stiffness = 1.0 / (L / EA + (L / N) / (100.0 * EA))
    heave = math.sqrt(stiffness / (M + 2.0 * RHO * V + MPL * L / 3.0)) / (2.0 * math.pi)
    expected = [1.0 / pendulum_period(1.5, 0.0), 1.0 / pendulum_period(0.5, 0.0), heave]
    swings = np.flatnonzero(f > 1e-3)[:3]
    np.testing.assert_allclose(f[swings], expected, rtol=1e-5)
    assert np.all(np.abs(f[:swings[0]]) < 1e-4) and md.unstable == 0


@pytest.mark.parametrize("ca_z", [2.0, 0.0])
def test_heave_period_on_the_rope_is_that_of_the_body_with_its_vertical_added_mass(ca_z):
    """Released on the unstretched rope the payload bounces on it: T = 2 pi sqrt(m_eff / k),
    m_eff = m + ca_z rho V + m_r / 3 and 1 / k = L / EA + Delta_0 / (100 EA) (the body
    connection). 0.3337 s with ca_z = 2, 0.2811 s with none: within 1e-4 at 1 ms steps
    (measured 4e-5, generalized-alpha's period error (omega h)^2 / 12). The bounce's height
    is twice the static stretch of the rope."""
    res = rfesim.simulate(scene([0.5, 1.5, ca_z], time_step=0.001, duration=2.0))
    z = res.body("payload").position[:, 2]
    stiffness = 1.0 / (L / EA + (L / N) / (100.0 * EA))
    expected = 2.0 * math.pi * math.sqrt((M + ca_z * RHO * V + MPL * L / 3.0) / stiffness)
    assert mean_period(res.time, z) == pytest.approx(expected, rel=1e-4)
    static_drop = SUBMERGED_WEIGHT / stiffness + MPL * L * G * L / (2.0 * EA)
    assert np.ptp(z) == pytest.approx(2.0 * static_drop, rel=1e-3)


def test_quadratic_drag_decays_the_swing_so_that_one_over_the_amplitude_grows_linearly():
    """x'' + c |x'| x' + omega^2 x = 0 loses energy (8/3) c A^3 omega^2 m per cycle, so
    1/A grows by (8/3) c per cycle, c = rho cd area / (2 (m + ca rho V)). Swinging from 5 deg
    with cd 1 on 0.1 m^2 for 80 s (7 cycles): the fitted slope within 1 % of (8/3) c
    (measured 0.09 %); without the added mass in c it would be 20 % off."""
    area, ca = 0.1, 1.0
    res = rfesim.simulate(scene([ca, ca, ca], swing_deg=5.0, duration=80.0, drag={"cd": 1.0, "area": area}))
    x = np.abs(res.body("payload").position[:, 0])
    k = np.where((x[1:-1] >= x[:-2]) & (x[1:-1] > x[2:]))[0] + 1
    # each half cycle's peak, refined by a parabola through the three samples about it
    y0, y1, y2 = x[k - 1], x[k], x[k + 1]
    peaks = y1 - (y0 - y2) ** 2 / (8.0 * (y0 - 2.0 * y1 + y2))
    assert len(peaks) >= 12
    slope = np.polyfit(np.arange(len(peaks)) / 2.0, 1.0 / peaks, 1)[0]
    c = RHO * 1.0 * area / (2.0 * (M + ca * RHO * V))
    assert slope == pytest.approx(8.0 / 3.0 * c, rel=0.01)
    assert peaks[-1] < 0.93 * peaks[0]


@pytest.mark.parametrize("speed, toward_deg", [(1.0, 90.0), (2.0, 30.0)])
def test_current_pulls_the_payload_over_by_its_drag_per_body_axis(speed, toward_deg):
    """Statics in a uniform current: the rope's pull on the body balances its submerged
    weight and the drag 1/2 rho (cd area)_k |u_k| u_k per body axis k (cd [0.8, 1.2, 1.0] on
    [3, 2, 4.5] m^2), u the current in the axes of the body's attitude (its output ZYX
    angles), to 1e-6 of the weight. The drag is 1230 N across for 1 m/s toward +y; for 2 m/s
    toward 30 deg, with x and y coefficients that differ, the pull is not along the current.
    The rope hangs 1 m above the centre, so the body tilts by the rope's angle (0.9-3 deg).
    Its yaw has no stiffness (the rope's torsion is 1 N m^2 and the drag acts at the
    centre), so the statics may leave it anywhere: the drag is taken in whatever axes it left."""
    from scipy.spatial.transform import Rotation

    toward = math.radians(toward_deg)
    cd, area = np.array([0.8, 1.2, 1.0]), np.array([3.0, 2.0, 4.5])
    res = rfesim.statics(scene([1.0, 1.0, 1.0], statics=True, attach_z=1.0,
                               drag={"cd": cd.tolist(), "area": area.tolist()},
                               current={"profile": [[0.0, speed], [-200.0, speed]], "direction_deg": toward_deg}))
    body = res.body("payload")
    roll, pitch, yaw = body.rotation[0]
    axes = Rotation.from_euler("ZYX", [yaw, pitch, roll], degrees=True).as_matrix()   # columns: body axes
    u = axes.T @ (speed * np.array([math.cos(toward), math.sin(toward), 0.0]))
    drag = axes @ (0.5 * RHO * cd * area * np.abs(u) * u)
    force = body.connection_force[0]                   # the rope's pull on the body
    np.testing.assert_allclose(force, -drag + [0.0, 0.0, SUBMERGED_WEIGHT], rtol=0.0, atol=1e-6 * SUBMERGED_WEIGHT)
    tilt = math.degrees(math.atan2(math.hypot(*force[:2]), force[2]))
    assert 0.8 < tilt < 3.5 and math.hypot(roll, pitch) == pytest.approx(tilt, rel=0.02)
    if toward_deg == 90.0:
        assert math.hypot(*drag[:2]) == pytest.approx(1230.0, rel=1e-3)


def test_a_regular_wave_swings_the_payload_by_its_froude_krylov_and_added_mass_forces():
    """A 2 m, 14 s Airy wave along x (no stretching, no ramp) over the payload hanging in its
    statics, ca = [1, 0.5, 1]: the water's acceleration at the centre drives the swing by
    (1 + ca_x) rho V du/dt (Froude-Krylov and added mass), the pendulum

        x'' + omega0^2 (1 - F_z / W') x = (1 + ca_x) rho V (L'^2 / I) du/dt(x, t),

    omega0 = 0.5688 rad/s as above, F_z = (1 + ca_z) rho V dw/dt the vertical wave force the
    rope's tension W' = K / L' loses, du/dt = a omega^2 C(z) sin(k x - omega t), dw/dt =
    -a omega^2 S(z) cos(k x - omega t) (finite depth 200 m). From rest: a beat of the wave and
    the pendulum's own swing, up to 0.36 m. Over 80 s the payload's x follows this equation
    (integrated by scipy) to 1e-3 of its largest (measured 4.4e-4 at 0.02 s steps), and the
    linear closed form -X (sin omega t - (omega / omega0) sin omega0 t), X = A / (omega0^2 -
    omega^2), to 0.5 % (measured 0.16 %). Without the Froude-Krylov term the swing would be
    half."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    height, period, depth, ca = 2.0, 14.0, 200.0, [1.0, 0.5, 1.0]
    res = rfesim.simulate(scene(ca, time_step=0.02, duration=80.0, start_static=True,
                                waves={"kind": "airy", "height": height, "period": period, "stretching": "none"}))
    t, centre = res.time, res.body("payload").position
    x, z = centre[:, 0], centre[0, 2]
    omega = 2.0 * math.pi / period
    k = brentq(lambda k: omega ** 2 - G * k * math.tanh(k * depth), 1e-6, 10.0)
    accel = height / 2.0 * omega ** 2 / math.sinh(k * depth)
    du = accel * math.cosh(k * (z + depth))                  # amplitudes at the payload's depth
    dw = accel * math.sinh(k * (z + depth))
    stretched = L * (1.0 + SUBMERGED_WEIGHT / EA)
    inertia = (M + ca[0] * RHO * V) * stretched ** 2 + MPL * L * stretched ** 2 / 3.0
    restoring = SUBMERGED_WEIGHT * stretched + MPL * L * G * stretched / 2.0
    omega0 = math.sqrt(restoring / inertia)
    force = (1.0 + ca[0]) * RHO * V * stretched ** 2 / inertia

    def swing(time, y):
        phase = k * y[0] - omega * time
        lift = (1.0 + ca[2]) * RHO * V * -dw * math.cos(phase)
        return [y[1], -omega0 ** 2 * (1.0 - lift * stretched / restoring) * y[0] + force * du * math.sin(phase)]

    ode = solve_ivp(swing, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-10, atol=1e-12).y[0]
    largest = np.abs(ode).max()
    assert 0.3 < largest < 0.4
    assert np.abs(x - ode).max() < 1e-3 * largest
    amplitude = force * du / (omega0 ** 2 - omega ** 2)
    linear = -amplitude * (np.sin(omega * t) - omega / omega0 * np.sin(omega0 * t))
    assert np.abs(x - linear).max() < 5e-3 * largest
