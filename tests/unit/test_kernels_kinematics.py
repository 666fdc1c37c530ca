"""rfesim.kinematics against the readable rotations of reference_impl (eqs. 8.72-8.73)."""
from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

import reference_impl as ref
from rfesim.kinematics import (euler_rate_derivative_into, euler_rate_matrix_into, exp_so3_into, log_so3_into,
                               relative_rotation_terms, right_jacobian_into, right_jacobian_inverse_into, rot_zyx,
                               rot_zyx_into, solve3_sym_into)

SEEDS = [0, 1, 2, 3, 4]
ROUNDOFF = 1e-12


def random_angles(rng):
    """ZYX angles (psi, theta, phi), theta away from +-pi/2."""
    return np.array([rng.uniform(-np.pi, np.pi), rng.uniform(-1.4, 1.4), rng.uniform(-np.pi, np.pi)])


def kernel_exp(w):
    out = np.empty((3, 3))
    exp_so3_into(w[0], w[1], w[2], out)
    return out


def kernel_log(R):
    out = np.empty(3)
    log_so3_into(np.ascontiguousarray(R), out)
    return out


def kernel_right_jacobian(w):
    out = np.empty((3, 3))
    right_jacobian_into(np.asarray(w, float), out)
    return out


def kernel_right_jacobian_inverse(w):
    out = np.empty((3, 3))
    right_jacobian_inverse_into(np.asarray(w, float), out)
    return out


def kernel_euler_rate_matrix(angles):
    out = np.empty((3, 3))
    euler_rate_matrix_into(angles[0], angles[1], angles[2], out)
    return out


def kernel_euler_rate_derivative(angles, rates):
    out = np.empty(3)
    euler_rate_derivative_into(angles[0], angles[1], angles[2], rates[0], rates[1], rates[2], out)
    return out


# ------------------------------------------------------------------ eq. 8.73

@pytest.mark.parametrize("seed", SEEDS)
def test_rot_zyx_is_product_of_elementary_rotations(seed):
    rng = np.random.default_rng(seed)
    for _ in range(20):
        psi, theta, phi = rng.uniform(-2 * np.pi, 2 * np.pi, size=3)
        expected = ref.rotation_zyx(psi, theta, phi)
        np.testing.assert_allclose(rot_zyx(psi, theta, phi), expected, rtol=0, atol=ROUNDOFF)
        out = np.empty((3, 3))
        rot_zyx_into(psi, theta, phi, out)
        np.testing.assert_array_equal(out, rot_zyx(psi, theta, phi))
        np.testing.assert_allclose(out.T @ out, np.eye(3), rtol=0, atol=ROUNDOFF)


# ------------------------------------------------------------------ Euler rates

@pytest.mark.parametrize("seed", SEEDS)
def test_euler_rate_matrix_is_the_analytic_E(seed):
    rng = np.random.default_rng(seed)
    for _ in range(20):
        angles = random_angles(rng)
        np.testing.assert_allclose(kernel_euler_rate_matrix(angles), ref.euler_rate_matrix(*angles),
                                   rtol=0, atol=ROUNDOFF)


@pytest.mark.parametrize("seed", SEEDS)
def test_euler_rate_matrix_gives_body_angular_velocity(seed):
    """[omega_body]x = R^T dR/dt with dR/dt by central differences along angles + rates t."""
    rng = np.random.default_rng(seed)
    step = 1e-6
    for _ in range(10):
        angles = random_angles(rng)
        rates = rng.normal(size=3)
        dR_dt = (ref.rotation_zyx(*(angles + step * rates)) - ref.rotation_zyx(*(angles - step * rates))) / (2 * step)
        omega_from_differences = ref.unskew(ref.rotation_zyx(*angles).T @ dR_dt)
        omega_kernel = kernel_euler_rate_matrix(angles) @ rates
        np.testing.assert_allclose(omega_kernel, omega_from_differences, rtol=0,
                                   atol=1e-8 * np.linalg.norm(rates))


def smooth_path(t, coefficients):
    """angles(t) = c0 + c1 t + c2 t^2 + c3 sin(t): a smooth path with varying rates."""
    c0, c1, c2, c3 = coefficients
    angles = c0 + c1 * t + c2 * t * t + c3 * np.sin(t)
    rates = c1 + 2 * c2 * t + c3 * np.cos(t)
    accelerations = 2 * c2 - c3 * np.sin(t)
    return angles, rates, accelerations


@pytest.mark.parametrize("seed", SEEDS)
def test_euler_rate_derivative_is_dE_dt_times_rates(seed):
    """d/dt [E(angles(t)) rates(t)] = Edot rates + E rates' along a smooth path, the
    derivative by central differences; and exactly the product-rule dE/dt of the reference."""
    rng = np.random.default_rng(seed)
    step = 1e-5
    for _ in range(10):
        coefficients = [random_angles(rng), rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)]
        t = rng.uniform(-0.5, 0.5)
        angles, rates, accelerations = smooth_path(t, coefficients)

        def omega(time):
            a, r, _ = smooth_path(time, coefficients)
            return ref.euler_rate_matrix(*a) @ r

        omega_dot = (omega(t + step) - omega(t - step)) / (2 * step)
        velocity_part = omega_dot - ref.euler_rate_matrix(*angles) @ accelerations
        kernel = kernel_euler_rate_derivative(angles, rates)
        scale = np.linalg.norm(rates) ** 2 + np.linalg.norm(accelerations)
        np.testing.assert_allclose(kernel, velocity_part, rtol=0, atol=1e-8 * scale)
        exact = ref.euler_rate_matrix_time_derivative(angles, rates) @ rates
        np.testing.assert_allclose(kernel, exact, rtol=0, atol=ROUNDOFF * np.linalg.norm(rates) ** 2)


# ------------------------------------------------------------------ exp / log

ANGLES = [0.0, 1e-12, 1e-9, 1e-6, 9.99e-5, 1.0e-4, 1.01e-4, 1e-3, 1e-2, 0.1, 0.5, 1.0, 2.0, 3.0,
          np.pi - 1e-3]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", ANGLES)
def test_exp_so3_matches_expm(seed, angle):
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    np.testing.assert_allclose(kernel_exp(w), scipy.linalg.expm(ref.skew(w)), rtol=0, atol=ROUNDOFF)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", ANGLES)
def test_log_so3_inverts_exp(seed, angle):
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    R = ref.exp_so3(w)
    recovered = kernel_log(R)
    # round-off of R (1e-16 absolute) moves the rotation vector by about as much
    np.testing.assert_allclose(recovered, w, rtol=0, atol=max(ROUNDOFF * angle, 1e-15))
    np.testing.assert_allclose(recovered, ref.log_so3(R), rtol=0, atol=max(ROUNDOFF * angle, 1e-15))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", ANGLES)
def test_reference_exp_and_log(seed, angle):
    """The reference itself: exp is scipy.linalg.expm of [w]x, log is scipy's rotation vector."""
    from scipy.spatial.transform import Rotation
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    R = scipy.linalg.expm(ref.skew(w))
    np.testing.assert_allclose(ref.exp_so3(w), R, rtol=0, atol=ROUNDOFF)
    np.testing.assert_allclose(ref.log_so3(R), Rotation.from_matrix(R).as_rotvec(), rtol=0,
                               atol=max(ROUNDOFF * angle, 1e-15))


@pytest.mark.parametrize("seed", SEEDS)
def test_log_so3_of_random_rotations(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        R = ref.random_rotation(rng)
        w = kernel_log(R)
        assert np.linalg.norm(w) <= np.pi + 1e-12
        np.testing.assert_allclose(ref.exp_so3(w), R, rtol=0, atol=ROUNDOFF)


# ------------------------------------------------------------------ right Jacobians

@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", ANGLES[:-1] + [3.1])
def test_right_jacobian_matches_definition(seed, angle):
    """J_r(w) = integral_0^1 exp(-s [w]x) ds, and J_r^-1 its matrix inverse."""
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    expected = ref.right_jacobian(w)
    np.testing.assert_allclose(kernel_right_jacobian(w), expected, rtol=0, atol=ROUNDOFF)
    np.testing.assert_allclose(kernel_right_jacobian_inverse(w), np.linalg.inv(expected), rtol=0,
                               atol=ROUNDOFF * np.linalg.norm(np.linalg.inv(expected)))
    np.testing.assert_allclose(kernel_right_jacobian_inverse(w) @ kernel_right_jacobian(w), np.eye(3), rtol=0,
                               atol=ROUNDOFF * np.linalg.norm(np.linalg.inv(expected)))


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", [1e-3, 0.1, 1.0, 2.5])
def test_right_jacobian_by_finite_differences(seed, angle):
    """exp(w + dw) = exp(w) exp(J_r(w) dw) to first order."""
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    np.testing.assert_allclose(kernel_right_jacobian(w), ref.right_jacobian_by_finite_differences(w), rtol=0,
                               atol=1e-8)


# ------------------------------------------------------------------ relative rotation terms

RELATIVE_ANGLES = [0.0, 1e-12, 1e-8, 1e-6, 1e-4,
                   0.99e-2, 1e-2, 1.01e-2, 1.99e-2, 2e-2, 2.01e-2,
                   0.05, 0.1, 0.5, 1.0, 2.0, 3.0]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("angle", RELATIVE_ANGLES)
def test_relative_rotation_terms_equal_the_plain_functions(seed, angle):
    rng = np.random.default_rng(seed)
    w = ref.random_rotation_vector(rng, angle)
    R = ref.exp_so3(w)
    theta = np.empty(3)
    half = np.empty((3, 3))
    jacobian_inverse = np.empty((3, 3))
    half_jacobian = np.empty((3, 3))
    relative_rotation_terms(R, theta, half, jacobian_inverse, half_jacobian)
    # the plain kernels on the same R
    plain_theta = kernel_log(R)
    np.testing.assert_allclose(theta, plain_theta, rtol=0, atol=max(ROUNDOFF * angle, 1e-15))
    np.testing.assert_allclose(theta, w, rtol=0, atol=max(ROUNDOFF * angle, 1e-15))
    np.testing.assert_allclose(half, kernel_exp(0.5 * plain_theta), rtol=0, atol=ROUNDOFF)
    np.testing.assert_allclose(jacobian_inverse, kernel_right_jacobian_inverse(plain_theta), rtol=0,
                               atol=ROUNDOFF * max(1.0, np.linalg.norm(jacobian_inverse)))
    np.testing.assert_allclose(half_jacobian, kernel_right_jacobian(0.5 * plain_theta), rtol=0, atol=ROUNDOFF)
    # and the readable references
    np.testing.assert_allclose(half, ref.exp_so3(0.5 * w), rtol=0, atol=ROUNDOFF)
    np.testing.assert_allclose(half @ half, R, rtol=0, atol=ROUNDOFF)
    np.testing.assert_allclose(jacobian_inverse, ref.right_jacobian_inverse(w), rtol=0,
                               atol=ROUNDOFF * max(1.0, np.linalg.norm(jacobian_inverse)))
    np.testing.assert_allclose(half_jacobian, ref.right_jacobian(0.5 * w), rtol=0, atol=ROUNDOFF)


@pytest.mark.parametrize("seed", SEEDS)
def test_relative_rotation_terms_of_products_of_random_rotations(seed):
    """As used by the SDEs: R = R_a^T R_b for two random nearby or far rotations."""
    rng = np.random.default_rng(seed)
    for angle in (1e-8, 1e-3, 0.015, 0.3, 2.0):
        Ra = ref.random_rotation(rng)
        Rb = Ra @ ref.exp_so3(ref.random_rotation_vector(rng, angle))
        R = np.ascontiguousarray(Ra.T @ Rb)
        theta = np.empty(3)
        half = np.empty((3, 3))
        jacobian_inverse = np.empty((3, 3))
        half_jacobian = np.empty((3, 3))
        relative_rotation_terms(R, theta, half, jacobian_inverse, half_jacobian)
        np.testing.assert_allclose(theta, ref.log_so3(R), rtol=0, atol=1e-15 + ROUNDOFF * angle)
        np.testing.assert_allclose(half, ref.exp_so3(0.5 * ref.log_so3(R)), rtol=0, atol=ROUNDOFF)
        np.testing.assert_allclose(jacobian_inverse, ref.right_jacobian_inverse(theta), rtol=0, atol=ROUNDOFF)
        np.testing.assert_allclose(half_jacobian, ref.right_jacobian(0.5 * theta), rtol=0, atol=ROUNDOFF)


# ------------------------------------------------------------------ 3x3 solve

@pytest.mark.parametrize("seed", SEEDS)
def test_solve3_matches_numpy(seed):
    rng = np.random.default_rng(seed)
    for symmetric in (True, False):
        for _ in range(20):
            A = rng.normal(size=(3, 3)) + 4.0 * np.eye(3)
            if symmetric:
                A = A + A.T
            b = rng.normal(size=3)
            out = np.empty(3)
            solve3_sym_into(A, b, out)
            expected = np.linalg.solve(A, b)
            np.testing.assert_allclose(out, expected, rtol=0,
                                       atol=ROUNDOFF * np.linalg.cond(A) * np.linalg.norm(expected))
