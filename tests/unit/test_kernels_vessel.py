"""rfesim.vessel_kernel.attachment_kinematics against the readable rfesim.vessel classes,
and both against finite differences of the pose."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.model.arrays import new_attachment_state
from rfesim.scenario.schema import HarmonicMotion, TableMotion
from rfesim.vessel import FixedVessel, HarmonicVessel, TableVessel
from rfesim.vessel_kernel import attachment_kinematics, vessel_spec

ROUNDOFF = 1e-12
RAMP = 3.0
TABLE_START = 1.0
TABLE_END = 13.0

HARMONIC = HarmonicMotion(kind="harmonic",
                          surge={"amplitude": 1.5, "period": 9.0, "phase_deg": 15.0},
                          sway={"amplitude": 0.7, "period": 11.0, "phase_deg": -40.0},
                          heave={"amplitude": 2.0, "period": 7.0, "phase_deg": 80.0},
                          roll={"amplitude": 8.0, "period": 8.5, "phase_deg": 120.0},
                          pitch={"amplitude": 5.0, "period": 6.0, "phase_deg": 200.0},
                          yaw={"amplitude": 10.0, "period": 14.0, "phase_deg": 300.0},
                          ramp_duration=RAMP)


def table_rows(seed):
    rng = np.random.default_rng(seed)
    times = np.sort(np.concatenate([[TABLE_START, TABLE_END], rng.uniform(TABLE_START + 0.5, TABLE_END - 0.5, 5)]))
    values = np.column_stack([rng.normal(scale=1.0, size=(times.size, 3)), rng.normal(scale=6.0, size=(times.size, 3))])
    return np.column_stack([times, values]).tolist()


def motions(seed):
    """The motions of a model: index 0 is the fixed global frame (None)."""
    rows = table_rows(seed)
    return [None,
            FixedVessel([10.0, -5.0, 1.0], 25.0),
            HarmonicVessel([-3.0, 4.0, 0.5], 135.0, HARMONIC),
            HarmonicVessel([0.0, 0.0, 0.0], 0.0, HarmonicMotion(kind="harmonic", heave={"amplitude": 1.0,
                                                                                          "period": 8.0})),
            TableVessel([1.0, 2.0, 3.0], -60.0, TableMotion(kind="table", rows=rows, interpolation="cubic",
                                                              ramp_duration=RAMP)),
            TableVessel([4.0, 0.0, -1.0], 200.0, TableMotion(kind="table", rows=rows, interpolation="linear")),
            TableVessel([0.0, 0.0, 0.0], 90.0, TableMotion(kind="table", rows=rows, interpolation="cubic"))]


TIMES = [-1.0, 0.0, 0.4, 1.5, RAMP - 1e-9, RAMP, RAMP + 0.3, 6.1, 9.7, TABLE_END - 1e-3, TABLE_END, 20.0, 123.4]


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("time", TIMES)
def test_compiled_kinematics_equal_the_python_classes(seed, time):
    models = motions(seed)
    spec = vessel_spec(models)
    att = new_attachment_state(len(models))
    attachment_kinematics(spec, float(time), att)
    # the fixed global frame is left alone
    np.testing.assert_array_equal(att.R[0], np.eye(3))
    np.testing.assert_array_equal(att.p[0], 0.0)
    for j, motion in enumerate(models):
        if motion is None:
            continue
        expected = motion.kinematics(float(time))
        for name in ("p", "R", "v", "w", "a", "alpha"):
            kernel_value = getattr(att, name)[j]
            reference_value = getattr(expected, name)
            scale = max(1.0, np.abs(reference_value).max())
            np.testing.assert_allclose(kernel_value, reference_value, rtol=0, atol=ROUNDOFF * scale,
                                       err_msg=f"attachment {j} ({type(motion).__name__}), {name} at t = {time}")


def pose(motion, time):
    k = motion.kinematics(time)
    return k.p, k.R, k.v, k.w


# times away from the knots of the tables and from the ends of the ramp, where a
# derivative of the motion jumps
SMOOTH_TIMES = [0.4, 1.5, 2.2, RAMP + 0.3, 6.1, 9.7, 20.0]


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("time", SMOOTH_TIMES)
def test_velocities_are_derivatives_of_the_pose(seed, time):
    """v = dp/dt, [w]x = dR/dt R^T, a = dv/dt, alpha = dw/dt (central differences) for the
    Python classes and the compiled kernel alike (they agree to round-off above)."""
    models = motions(seed)
    spec = vessel_spec(models)
    att = new_attachment_state(len(models))
    step = 1e-6
    for j, motion in enumerate(models):
        if motion is None:
            continue
        if isinstance(motion, TableVessel):
            knots = motion.time
            if np.min(np.abs(knots - time)) < 10 * step:
                continue
        p_plus, R_plus, v_plus, w_plus = pose(motion, time + step)
        p_minus, R_minus, v_minus, w_minus = pose(motion, time - step)
        attachment_kinematics(spec, float(time), att)
        velocity_scale = 1.0 + np.abs(att.v[j]).max()
        np.testing.assert_allclose(att.v[j], (p_plus - p_minus) / (2 * step), rtol=0, atol=1e-8 * velocity_scale)
        w_fd = ref.unskew((R_plus - R_minus) / (2 * step) @ att.R[j].T)
        np.testing.assert_allclose(att.w[j], w_fd, rtol=0, atol=1e-8)
        acceleration_scale = 1.0 + np.abs(att.a[j]).max()
        np.testing.assert_allclose(att.a[j], (v_plus - v_minus) / (2 * step), rtol=0,
                                   atol=1e-7 * acceleration_scale)
        np.testing.assert_allclose(att.alpha[j], (w_plus - w_minus) / (2 * step), rtol=0, atol=1e-7)


@pytest.mark.parametrize("seed", [0, 1])
def test_ramp_and_table_limits(seed):
    """Before the ramp the displacements are zero; outside the table the first/last row is
    held with zero rates."""
    models = motions(seed)
    spec = vessel_spec(models)
    att = new_attachment_state(len(models))
    attachment_kinematics(spec, -0.5, att)
    for j in (2, 4):                                 # ramped motions at rest before t = 0
        np.testing.assert_allclose(att.p[j], models[j].position, rtol=0, atol=ROUNDOFF * 10)
        np.testing.assert_allclose(att.R[j], models[j].R_heading, rtol=0, atol=ROUNDOFF)
        for name in ("v", "w", "a", "alpha"):
            np.testing.assert_array_equal(getattr(att, name)[j], 0.0)
    for time, row in ((0.5, 0), (TABLE_END + 5.0, -1)):
        attachment_kinematics(spec, time, att)
        motion = models[5]                            # linear table, no ramp
        displacement = motion.values[row]
        np.testing.assert_allclose(att.p[5], motion.position + motion.R_heading @ displacement[:3], rtol=0,
                                   atol=ROUNDOFF * 10)
        np.testing.assert_allclose(att.R[5], motion.R_heading @ ref.rotation_zyx(displacement[5], displacement[4],
                                                                                 displacement[3]),
                                   rtol=0, atol=ROUNDOFF)
        for name in ("v", "w", "a", "alpha"):
            np.testing.assert_array_equal(getattr(att, name)[5], 0.0)
