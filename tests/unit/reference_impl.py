"""Slow, readable numpy versions of the rfesim kernels, written straight from the
chapter's equations (rfe-method-chapter8.md, section 8.4, eqs. 8.72-8.96) and from the
kernels' docstrings. The tests in ``test_kernels_*.py`` check that every numba kernel
agrees with these to round-off on random states (STYLE.md, "Fast kernels checked against
readable ones").

Everything here favours the obvious formula over speed or robustness: rotations are built
from elementary matrices and scipy's rotation vectors, derivatives are taken by central
finite differences, integrals by quadrature, linear systems by ``numpy.linalg.solve``.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.spatial.transform import Rotation

UNIT_X = np.array([1.0, 0.0, 0.0])
UNIT_Y = np.array([0.0, 1.0, 0.0])
UNIT_Z = np.array([0.0, 0.0, 1.0])


# =============================================================================== rotations

def skew(vector):
    """The cross-product matrix [v]x, with [v]x u = v x u."""
    x, y, z = vector
    return np.array([[0.0, -z, y],
                     [z, 0.0, -x],
                     [-y, x, 0.0]])


def unskew(matrix):
    """The vector v of a skew-symmetric matrix [v]x (antisymmetric part only)."""
    antisymmetric = 0.5 * (matrix - matrix.T)
    return np.array([antisymmetric[2, 1], antisymmetric[0, 2], antisymmetric[1, 0]])


def rotation_about_x(angle):
    """Elementary rotation about x (third factor of eq. 8.73)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0],
                     [0.0, c, -s],
                     [0.0, s, c]])


def rotation_about_y(angle):
    """Elementary rotation about y (second factor of eq. 8.73)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s],
                     [0.0, 1.0, 0.0],
                     [-s, 0.0, c]])


def rotation_about_z(angle):
    """Elementary rotation about z (first factor of eq. 8.73)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0],
                     [s, c, 0.0],
                     [0.0, 0.0, 1.0]])


def rotation_about_x_derivative(angle):
    """d Rx / d angle."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[0.0, 0.0, 0.0],
                     [0.0, -s, -c],
                     [0.0, c, -s]])


def rotation_about_y_derivative(angle):
    """d Ry / d angle."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[-s, 0.0, c],
                     [0.0, 0.0, 0.0],
                     [-c, 0.0, -s]])


def rotation_zyx(psi, theta, phi):
    """eq. 8.73: R = Rz(psi) Ry(theta) Rx(phi), angles ordered as in eq. 8.72."""
    return rotation_about_z(psi) @ rotation_about_y(theta) @ rotation_about_x(phi)


def euler_rate_matrix(psi, theta, phi):
    """E with omega_body = E (psi', theta', phi') for R = Rz Ry Rx (eq. 8.73).

    omega_body = R^T (psi' e_z + theta' Rz e_y + phi' Rz Ry e_x)
               = psi' Rx^T Ry^T e_z + theta' Rx^T e_y + phi' e_x.
    """
    Rx = rotation_about_x(phi)
    Ry = rotation_about_y(theta)
    return np.column_stack([Rx.T @ Ry.T @ UNIT_Z, Rx.T @ UNIT_Y, UNIT_X])


def euler_rate_matrix_time_derivative(angles, rates):
    """dE/dt along a motion with the given angles and angle rates (product rule on the
    columns of ``euler_rate_matrix``)."""
    psi, theta, phi = angles
    dpsi, dtheta, dphi = rates
    Rx = rotation_about_x(phi)
    Ry = rotation_about_y(theta)
    dRx_dt = rotation_about_x_derivative(phi) * dphi
    dRy_dt = rotation_about_y_derivative(theta) * dtheta
    column_psi = dRx_dt.T @ Ry.T @ UNIT_Z + Rx.T @ dRy_dt.T @ UNIT_Z
    column_theta = dRx_dt.T @ UNIT_Y
    column_phi = np.zeros(3)
    return np.column_stack([column_psi, column_theta, column_phi])


def body_angular_acceleration(angles, rates, angle_accelerations):
    """d(omega_body)/dt = E qdd + (dE/dt) qd."""
    E = euler_rate_matrix(*angles)
    return E @ angle_accelerations + euler_rate_matrix_time_derivative(angles, rates) @ rates


def exp_so3(rotation_vector):
    """Rotation matrix of a rotation vector, exp([w]x) (scipy's quaternion form: the same
    as scipy.linalg.expm of the skew matrix to round-off, which the tests check, and
    ten times faster)."""
    return Rotation.from_rotvec(np.asarray(rotation_vector, dtype=float)).as_matrix()


def log_so3(rotation):
    """Rotation vector of a rotation matrix (angle in [0, pi]).

    The antisymmetric part of R is sin(angle) [n]x and its trace 1 + 2 cos(angle), so
    angle = atan2(|v|, (trace - 1)/2) and w = angle n, with v = vee((R - R^T)/2).
    Near pi the axis is lost in the antisymmetric part: there use scipy's quaternion."""
    rotation = np.asarray(rotation, dtype=float)
    v = unskew(rotation)
    sine = np.linalg.norm(v)
    cosine = 0.5 * (np.trace(rotation) - 1.0)
    angle = math.atan2(sine, cosine)
    if angle > 3.0:
        return Rotation.from_matrix(rotation).as_rotvec()
    if sine == 0.0:
        return np.zeros(3)
    return angle / sine * v


def gauss_legendre_on_unit_interval(count=20):
    nodes, weights = np.polynomial.legendre.leggauss(count)
    return 0.5 * (nodes + 1.0), 0.5 * weights


def right_jacobian(rotation_vector):
    """J_r(w) = integral_0^1 exp(-s [w]x) ds (Gauss-Legendre, exact to round-off for
    |w| <= pi), the matrix with exp(w + dw) = exp(w) exp(J_r(w) dw) to first order."""
    nodes, weights = gauss_legendre_on_unit_interval()
    w = np.asarray(rotation_vector, dtype=float)
    return sum(weight * exp_so3(-node * w) for node, weight in zip(nodes, weights))


def right_jacobian_inverse(rotation_vector):
    return np.linalg.inv(right_jacobian(rotation_vector))


def right_jacobian_by_finite_differences(rotation_vector, step=1e-6):
    """Column j: log(exp(w)^T exp(w + h e_j)) / h, central differences."""
    w = np.asarray(rotation_vector, dtype=float)
    base_transpose = exp_so3(w).T
    columns = []
    for j in range(3):
        dw = np.zeros(3)
        dw[j] = step
        plus = log_so3(base_transpose @ exp_so3(w + dw))
        minus = log_so3(base_transpose @ exp_so3(w - dw))
        columns.append((plus - minus) / (2.0 * step))
    return np.column_stack(columns)


def random_rotation(rng):
    """A uniformly distributed rotation (normalised Gaussian quaternion)."""
    quaternion = rng.normal(size=4)
    quaternion /= np.linalg.norm(quaternion)
    w, x, y, z = quaternion
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def random_rotation_vector(rng, angle):
    axis = rng.normal(size=3)
    return angle * axis / np.linalg.norm(axis)


def rigid_motion(position, rotation, velocity, angular_velocity, time_step):
    """Pose after a rigid motion with constant velocity and global angular velocity:
    r + v dt, expm([w]x dt) R."""
    return position + velocity * time_step, exp_so3(angular_velocity * time_step) @ rotation


# ===================================================================== spring-damping elements

def sde_end_points(position_a, rotation_a, arm_a, position_b, rotation_b, arm_b):
    """eqs. 8.78-8.79: right end of RFE a (r_L) and left end of RFE b (r_R), global."""
    return position_a + rotation_a @ arm_a, position_b + rotation_b @ arm_b


def sde_relative_rotation_vector(rotation_a, rotation_b):
    """eq. 8.75 in rotation-vector form: theta = log(R_a^T R_b)."""
    return log_so3(rotation_a.T @ rotation_b)


def sde_mean_orientation(rotation_a, relative_rotation_vector):
    """eq. 8.77 as the geodesic midpoint: R' = R_a exp(theta / 2)."""
    return rotation_a @ exp_so3(0.5 * relative_rotation_vector)


def sde_deformation(position_a, rotation_a, arm_a, position_b, rotation_b, arm_b):
    """eq. 8.85: eps = [R'^T (r_R - r_L), theta]."""
    left_end, right_end = sde_end_points(position_a, rotation_a, arm_a, position_b, rotation_b, arm_b)
    gap = right_end - left_end
    theta = sde_relative_rotation_vector(rotation_a, rotation_b)
    mean_rotation = sde_mean_orientation(rotation_a, theta)
    return np.concatenate([mean_rotation.T @ gap, theta])


def sde_point(position_a, rotation_a, arm_a, position_b, rotation_b, arm_b):
    """The SDE position: midpoint of the gap between the two RFE ends."""
    left_end, right_end = sde_end_points(position_a, rotation_a, arm_a, position_b, rotation_b, arm_b)
    return 0.5 * (left_end + right_end)


def sde_deformation_rate(pair, time_step=1e-6):
    """d(eps)/dt by central differences along the rigid motions of both RFEs.

    ``pair`` is a dict with position_a, rotation_a, velocity_a, angular_velocity_a, arm_a
    and the same for b (angular velocities global)."""
    def deformation_at(dt):
        position_a, rotation_a = rigid_motion(pair["position_a"], pair["rotation_a"], pair["velocity_a"],
                                              pair["angular_velocity_a"], dt)
        position_b, rotation_b = rigid_motion(pair["position_b"], pair["rotation_b"], pair["velocity_b"],
                                              pair["angular_velocity_b"], dt)
        return sde_deformation(position_a, rotation_a, pair["arm_a"], position_b, rotation_b, pair["arm_b"])
    return (deformation_at(time_step) - deformation_at(-time_step)) / (2.0 * time_step)


def sde_section_forces(stiffness, damping, deformation, deformation_rate):
    """eqs. 8.86-8.87 with Kelvin-Voigt damping: sigma = C eps + D d(eps)/dt, in {i'}."""
    return stiffness * deformation + damping * deformation_rate


def sde_elastic_potential(stiffness, deformation):
    """V = 1/2 eps^T C eps (C diagonal)."""
    return 0.5 * float(np.sum(stiffness * deformation * deformation))


def rope_contact_potential(axial_stiffness, reach, gap, contact=0.5, ramp=0.1):
    """Energy of a rope SDE's axial contact (rfesim.loads.tension_only): none until the gap
    closes to -contact * reach; over the next ramp * reach its stiffness grows linearly from
    0 to C_x, then stays C_x. V = C d^3 / (6 w) on the ramp and C (d^2/2 - w d/2 + w^2/6)
    past it, with d the depth past the closing and w the ramp's width (C^1 at both joins)."""
    d = -contact * reach - gap
    w = ramp * reach
    if d <= 0.0:
        return 0.0
    if d < w:
        return axial_stiffness * d ** 3 / (6.0 * w)
    return axial_stiffness * (0.5 * d * d - 0.5 * w * d + w * w / 6.0)


def sde_elastic_forces_by_gradient(pair, stiffness, position_step=1e-6, rotation_step=1e-6, axial_contact=None):
    """Generalised elastic forces on RFEs a and b as minus the gradient of V:
    F = -dV/dr, M = -dV/d(delta) for a global virtual rotation R -> expm([delta]x) R
    (so M is the moment about the RFE centre). Central finite differences.
    ``axial_contact`` (C_x, reach) adds a rope's contact energy in the gap eps_x
    (``rope_contact_potential``). Returns (F_a, M_a, F_b, M_b)."""
    def potential(position_a, rotation_a, position_b, rotation_b):
        eps = sde_deformation(position_a, rotation_a, pair["arm_a"], position_b, rotation_b, pair["arm_b"])
        extra = 0.0 if axial_contact is None else rope_contact_potential(axial_contact[0], axial_contact[1], eps[0])
        return sde_elastic_potential(stiffness, eps) + extra

    base = dict(position_a=pair["position_a"], rotation_a=pair["rotation_a"],
                position_b=pair["position_b"], rotation_b=pair["rotation_b"])
    out = {}
    for side in ("a", "b"):
        force = np.zeros(3)
        moment = np.zeros(3)
        for k in range(3):
            step = np.zeros(3)
            step[k] = position_step
            plus = dict(base)
            minus = dict(base)
            plus["position_" + side] = base["position_" + side] + step
            minus["position_" + side] = base["position_" + side] - step
            force[k] = -(potential(**plus) - potential(**minus)) / (2.0 * position_step)
            step[k] = rotation_step
            plus = dict(base)
            minus = dict(base)
            plus["rotation_" + side] = exp_so3(step) @ base["rotation_" + side]
            minus["rotation_" + side] = exp_so3(-step) @ base["rotation_" + side]
            moment[k] = -(potential(**plus) - potential(**minus)) / (2.0 * rotation_step)
        out[side] = (force, moment)
    return out["a"][0], out["a"][1], out["b"][0], out["b"][1]


def sde_deformation_rate_matrix(pair, time_step=1e-6):
    """B with d(eps)/dt = B [v_a, w_a, v_b, w_b] (6 x 12): d(eps)/dt is linear in the
    velocities, so column j is the deformation rate for the unit velocity j (finite
    differences in the velocities with a unit step, exact for a linear map)."""
    names = ("velocity_a", "angular_velocity_a", "velocity_b", "angular_velocity_b")
    columns = []
    for j in range(12):
        unit_pair = dict(pair)
        for name in names:
            unit_pair[name] = np.zeros(3)
        unit_pair[names[j // 3]] = np.eye(3)[j % 3]
        columns.append(sde_deformation_rate(unit_pair, time_step))
    return np.column_stack(columns)


def sde_damping_forces_by_dissipation(pair, damping, time_step=1e-6):
    """Damping forces as minus the velocity gradient of the dissipation function
    1/2 eps_dot^T D eps_dot: -(d eps_dot / d velocities)^T D eps_dot.
    Returns (F_a, M_a, F_b, M_b)."""
    B = sde_deformation_rate_matrix(pair, time_step)
    velocities = np.concatenate([pair["velocity_a"], pair["angular_velocity_a"],
                                 pair["velocity_b"], pair["angular_velocity_b"]])
    generalised = -B.T @ (damping * (B @ velocities))
    return generalised[0:3], generalised[3:6], generalised[6:9], generalised[9:12]


# =============================================================================== loads

def gravity_force(mass, gravity, scale):
    """eq. 8.19: weight -m g e_z at the centre of mass."""
    return -scale * mass * gravity * UNIT_Z


def submerged_part(length, displaced_area, rotation, centre, surface_z):
    """Fraction of a straight RFE (axis = local x, centred at ``centre``) below the
    surface and the centroid of that part, on the axis.

    The RFE is a cylinder of radius a = sqrt(A_d / pi): each cross-section (a disc normal to
    the axis tangent t, its centre at centre + s t, s in [-l/2, l/2]) reaches c = a sqrt(1 -
    t_z^2) above and below its centre, and the part of it below the surface is a circular
    segment, the fraction phi(h / c) of its area with h the centre's height above the surface
    (phi(u) = (acos u - u sqrt(1 - u^2)) / pi between -1 and 1). The fraction is the mean of
    phi along the axis and the centroid the phi-weighted mean of s, both by adaptive
    quadrature (scipy.integrate.quad) with the points where the disc touches the surface as
    breakpoints. A vertical RFE (c = 0) is wet along its axis below the surface."""
    from scipy.integrate import quad

    if displaced_area <= 0.0:
        return 0.0, centre.copy()
    tangent = rotation[:, 0]
    half = 0.5 * length
    c = math.sqrt(displaced_area / math.pi) * math.sqrt(max(0.0, 1.0 - tangent[2] ** 2))

    def phi(s):
        h = centre[2] + s * tangent[2] - surface_z
        if c == 0.0:
            return 1.0 if h <= 0.0 else 0.0
        u = h / c
        if u >= 1.0:
            return 0.0
        if u <= -1.0:
            return 1.0
        return (math.acos(u) - u * math.sqrt(1.0 - u * u)) / math.pi

    breaks = []
    if tangent[2] != 0.0:
        for level in (-c, 0.0, c):
            s = (surface_z + level - centre[2]) / tangent[2]
            if -half < s < half:
                breaks.append(s)
    opts = dict(points=breaks or None, epsabs=1e-13, epsrel=1e-12, limit=200)
    wet = quad(phi, -half, half, **opts)[0]
    fraction = wet / length
    if fraction <= 0.0:
        return 0.0, centre.copy()
    if fraction >= 1.0 - 1e-15:
        return 1.0, centre.copy()
    centroid_s = quad(lambda s: s * phi(s), -half, half, **opts)[0] / wet
    return fraction, centre + centroid_s * tangent


def buoyancy_force_and_moment(length, displaced_area, water_density, gravity, scale, centre, fraction,
                              centroid):
    """Archimedes: rho g A l f upward at the submerged centroid; moment about the centre."""
    force = scale * water_density * gravity * displaced_area * length * fraction * UNIT_Z
    return force, np.cross(centroid - centre, force)


def morison_force_and_moment(length, diameter, displaced_area, drag_normal, drag_axial, added_mass_normal,
                             added_mass_axial, water_density, rotation, centre, velocity, angular_velocity,
                             fraction, centroid, water_velocity, water_acceleration):
    """Morison loads of the submerged part, from the docstring of rfesim.loads.hydro:

    drag 1/2 rho C_dn D l_sub |u_n| u_n + 1/2 rho C_dt pi D l_sub |u_t| u_t t, with u the
    water velocity relative to the element at the submerged centroid (v + w x d);
    Froude-Krylov rho V a plus added-mass inertia m_an a_n + m_at a_t of the water
    acceleration; added-mass matrix m_an (I - t t^T) + m_at t t^T; added rotational
    inertia m_an l_sub^2 / 12 about the transverse body axes. Returns
    (force, moment about the centre, added mass matrix (global), added inertia (body))."""
    if fraction <= 0.0 or diameter <= 0.0:
        return np.zeros(3), np.zeros(3), np.zeros((3, 3)), np.zeros(3)
    submerged_length = fraction * length
    tangent = rotation[:, 0]
    arm = centroid - centre
    element_velocity = velocity + np.cross(angular_velocity, arm)
    relative_velocity = water_velocity - element_velocity
    axial_velocity = relative_velocity @ tangent
    normal_velocity = relative_velocity - axial_velocity * tangent
    normal_drag = 0.5 * water_density * drag_normal * diameter * submerged_length \
        * np.linalg.norm(normal_velocity) * normal_velocity
    axial_drag = 0.5 * water_density * drag_axial * math.pi * diameter * submerged_length \
        * abs(axial_velocity) * axial_velocity * tangent
    displaced_mass = water_density * displaced_area * submerged_length
    normal_added_mass = added_mass_normal * displaced_mass
    axial_added_mass = added_mass_axial * displaced_mass
    axial_acceleration = water_acceleration @ tangent
    normal_acceleration = water_acceleration - axial_acceleration * tangent
    inertia = displaced_mass * water_acceleration + normal_added_mass * normal_acceleration \
        + axial_added_mass * axial_acceleration * tangent
    force = normal_drag + axial_drag + inertia
    tangent_projector = np.outer(tangent, tangent)
    added_mass_matrix = normal_added_mass * (np.eye(3) - tangent_projector) + axial_added_mass * tangent_projector
    transverse = normal_added_mass * submerged_length ** 2 / 12.0
    added_inertia = np.array([0.0, transverse, transverse])
    return force, np.cross(arm, force), added_mass_matrix, added_inertia


def seabed_contact_by_quadrature(length, contact_radius, seabed_damping, seabed_z, seabed_stiffness, rotation,
                                 centre, velocity, angular_velocity, points=20001):
    """Seabed reaction of a straight RFE by numerical integration along its axis:
    penetration p(s) = z_seabed - (z(s) - a); spring force integral of k max(0, p) ds
    (trapezoid rule) applied at its centroid (first moment / force); the damper
    c l_contact v_z(centroid); the total is never tensile, and an element the damper would
    pull is out of contact (contact length 0).
    Returns (force, moment about the centre, normal force, contact length)."""
    tangent = rotation[:, 0]
    s = np.linspace(-0.5 * length, 0.5 * length, points)
    penetration = seabed_z - (centre[2] + s * tangent[2] - contact_radius)
    spring = seabed_stiffness * np.maximum(penetration, 0.0)
    spring_force = np.trapezoid(spring, s)
    if spring_force <= 0.0:
        return np.zeros(3), np.zeros(3), 0.0, 0.0
    centroid_s = np.trapezoid(spring * s, s) / spring_force
    # contact length: the part of the axis where the (linear) penetration is positive
    left = seabed_z - (centre[2] - 0.5 * length * tangent[2] - contact_radius)
    right = seabed_z - (centre[2] + 0.5 * length * tangent[2] - contact_radius)
    if left > 0.0 and right > 0.0:
        contact_length = length
    else:
        contact_length = length * max(left, right) / abs(left - right)
    arm = centroid_s * tangent
    vertical_velocity = (velocity + np.cross(angular_velocity, arm))[2]
    normal_force = max(0.0, spring_force - seabed_damping * contact_length * vertical_velocity)
    if normal_force == 0.0:
        # lifting off faster than the spring unloads: out of contact (no contact length)
        return np.zeros(3), np.zeros(3), 0.0, 0.0
    force = normal_force * UNIT_Z
    return force, np.cross(arm, force), normal_force, contact_length


def point_load(rotation, arm, force, moment, local, scale):
    """eq. 8.93: a force at the body point ``arm`` and a moment; ``local`` loads are given
    in the RFE frame. Returns (resultant force, moment about the centre), global."""
    if local:
        force = rotation @ force
        moment = rotation @ moment
    return scale * force, scale * (moment + np.cross(rotation @ arm, force))


# =============================================================================== dynamics

def free_rfe_generalised_mass(mass, added_mass, body_inertia, euler_matrix):
    """eq. 8.92 block of a free RFE: diag(m I + M_a, E^T J E)."""
    out = np.zeros((6, 6))
    out[:3, :3] = mass * np.eye(3) + added_mass
    out[3:, 3:] = euler_matrix.T @ np.diag(body_inertia) @ euler_matrix
    return out


def free_rfe_newton_euler_residuals(mass, added_mass, body_inertia, rotation, force, moment, angles, rates,
                                    acceleration, angle_accelerations):
    """Newton-Euler for a free RFE: (m I + M_a) a - F and
    J dw/dt + w x J w - R^T M (body frame), with w = E qd, dw/dt = E qdd + Edot qd."""
    J = np.diag(body_inertia)
    omega = euler_rate_matrix(*angles) @ rates
    omega_dot = body_angular_acceleration(angles, rates, angle_accelerations)
    translational = (mass * np.eye(3) + added_mass) @ acceleration - force
    rotational = J @ omega_dot + np.cross(omega, J @ omega) - rotation.T @ moment
    return translational, rotational


def point_acceleration(origin_acceleration, angular_acceleration, angular_velocity, offset):
    """Acceleration of a point of a rigid body at ``offset`` from a reference point."""
    return origin_acceleration + np.cross(angular_acceleration, offset) \
        + np.cross(angular_velocity, np.cross(angular_velocity, offset))


def pinned_rfe_newton_euler(mass, added_mass, body_inertia, rotation, angular_velocity, centre, pin_point,
                            pin_acceleration, force, moment):
    """A pinned RFE as a free rigid body plus an unknown reaction F_r at the pin:

        (m I + M_a) a_c = F + F_r
        J_g alpha + w x J_g w = M + (P - r) x F_r
        a_c + alpha x (P - r) + w x (w x (P - r)) = a_P   (the end stays on the attachment)

    solved as one 9 x 9 linear system. Returns (a_c, alpha, F_r), global."""
    J_global = rotation @ np.diag(body_inertia) @ rotation.T
    translational_mass = mass * np.eye(3) + added_mass
    to_pin = pin_point - centre
    w = angular_velocity
    system = np.zeros((9, 9))
    rhs = np.zeros(9)
    # unknowns: [a_c, alpha, F_r]
    system[0:3, 0:3] = translational_mass
    system[0:3, 6:9] = -np.eye(3)
    rhs[0:3] = force
    system[3:6, 3:6] = J_global
    system[3:6, 6:9] = -skew(to_pin)
    rhs[3:6] = moment - np.cross(w, J_global @ w)
    system[6:9, 0:3] = np.eye(3)
    system[6:9, 3:6] = -skew(to_pin)             # alpha x d = -d x alpha
    rhs[6:9] = pin_acceleration - np.cross(w, np.cross(w, to_pin))
    solution = np.linalg.solve(system, rhs)
    return solution[0:3], solution[3:6], solution[6:9]


def attachment_point_kinematics(attachment, index, offset):
    """Position, velocity and acceleration of the attachment point with the given offset
    (attachment frame) on attachment ``index``."""
    lever = attachment.R[index] @ offset
    position = attachment.p[index] + lever
    velocity = attachment.v[index] + np.cross(attachment.w[index], lever)
    acceleration = point_acceleration(attachment.a[index], attachment.alpha[index], attachment.w[index], lever)
    return position, velocity, acceleration


# =============================================================================== outputs

def line_end_points(centre_a, rotation_a, length_a, centre_b, rotation_b, length_b):
    """End A: centre of the first RFE minus half its length along its axis; end B: plus."""
    return centre_a - 0.5 * length_a * rotation_a[:, 0], centre_b + 0.5 * length_b * rotation_b[:, 0]


def sde_result_channels(section_forces, deformation, element_length):
    """Effective tension (axial force), shear and bending magnitudes, torque, curvature."""
    tension = section_forces[:, 0]
    shear = np.hypot(section_forces[:, 1], section_forces[:, 2])
    torque = section_forces[:, 3]
    bending_moment = np.hypot(section_forces[:, 4], section_forces[:, 5])
    curvature = np.hypot(deformation[:, 4], deformation[:, 5]) / element_length
    return tension, shear, bending_moment, torque, curvature


# =============================================================================== block tridiagonal

def block_tridiagonal_dense(blocks):
    """Dense matrix of (n, 3, 6, 6) blocks [sub, diagonal, super] (first sub and last
    super ignored)."""
    n = blocks.shape[0]
    dense = np.zeros((6 * n, 6 * n))
    for i in range(n):
        rows = slice(6 * i, 6 * i + 6)
        dense[rows, 6 * i:6 * i + 6] = blocks[i, 1]
        if i > 0:
            dense[rows, 6 * (i - 1):6 * i] = blocks[i, 0]
        if i < n - 1:
            dense[rows, 6 * (i + 1):6 * (i + 2)] = blocks[i, 2]
    return dense


# =============================================================================== seabed (general)

def seabed_plane_under(profile_s, profile_z, direction, x, y):
    """Height and unit normal of the tangent plane of a piecewise-linear seabed profile
    under (x, y): linear interpolation, end slopes continued (np.interp clamps, so the
    segment is chosen by hand)."""
    s = x * direction[0] + y * direction[1]
    j = int(np.clip(np.searchsorted(profile_s, s) - 1, 0, len(profile_s) - 2))
    slope = (profile_z[j + 1] - profile_z[j]) / (profile_s[j + 1] - profile_s[j])
    z = profile_z[j] + slope * (s - profile_s[j])
    gradient = slope * np.asarray(direction)
    normal = np.array([-gradient[0], -gradient[1], 1.0])
    return z, normal / np.linalg.norm(normal)


def seabed_on_plane_by_quadrature(length, contact_radius, seabed_damping, plane_point, normal, stiffness, rotation,
                                  centre, velocity, angular_velocity, points=20001):
    """Normal seabed reaction of a straight RFE on a plane (point, unit normal) by numerical
    integration: penetration p(s) = a - n.(P(s) - P0); spring integral at its centroid; the
    damper on the contact length; never tensile (an element the damper would pull is out of
    contact: contact length 0). Returns (force, moment, normal force, contact length)."""
    tangent = rotation[:, 0]
    s = np.linspace(-0.5 * length, 0.5 * length, points)
    P = centre[None, :] + s[:, None] * tangent[None, :]
    penetration = contact_radius - (P - plane_point) @ normal
    spring = stiffness * np.maximum(penetration, 0.0)
    spring_force = np.trapezoid(spring, s)
    if spring_force <= 0.0:
        return np.zeros(3), np.zeros(3), 0.0, 0.0
    centroid_s = np.trapezoid(spring * s, s) / spring_force
    left, right = penetration[0], penetration[-1]
    contact_length = length if (left > 0 and right > 0) else length * max(left, right) / abs(left - right)
    arm = centroid_s * tangent
    normal_velocity = (velocity + np.cross(angular_velocity, arm)) @ normal
    normal_force = max(0.0, spring_force - seabed_damping * contact_length * normal_velocity)
    if normal_force == 0.0:
        # lifting off faster than the spring unloads: out of contact (no contact length)
        return np.zeros(3), np.zeros(3), 0.0, 0.0
    force = normal_force * normal
    return force, np.cross(arm, force), normal_force, contact_length


def seabed_friction_spring_slider(normal, tangent, centre, anchor, stick_stiffness, contact_length, normal_force,
                                  mu_axial, mu_lateral, velocity=None, stick_damping=0.0):
    """Coulomb friction by a spring-slider: stick spring -k l (I - n n^T)(r - anchor) and its
    damper -c l (I - n n^T) v (Kelvin-Voigt), split into axial (tangent projected on the seabed)
    and lateral parts, scaled back onto the ellipse (f_a/mu_a)^2 + (f_l/mu_l)^2 = N^2 when
    outside (slip: spring and damper shares scaled alike); returns (force, new anchor), the
    anchor where the spring's share of the force puts it."""
    P = np.eye(3) - np.outer(normal, normal)
    axial = P @ tangent
    axial /= np.linalg.norm(axial)
    lateral = np.cross(normal, axial)
    spring = -stick_stiffness * contact_length * (P @ (centre - anchor))
    damper = np.zeros(3) if velocity is None else -stick_damping * contact_length * (P @ velocity)
    keep = np.array([mu_axial > 0, mu_lateral > 0], float)
    spring_al = keep * np.array([spring @ axial, spring @ lateral])
    total_al = spring_al + keep * np.array([damper @ axial, damper @ lateral])
    ratio = np.hypot(total_al[0] / mu_axial if mu_axial > 0 else 0.0,
                     total_al[1] / mu_lateral if mu_lateral > 0 else 0.0)
    if ratio > normal_force:
        total_al = total_al * normal_force / ratio
        spring_al = spring_al * normal_force / ratio
    force = total_al[0] * axial + total_al[1] * lateral
    spring_force = spring_al[0] * axial + spring_al[1] * lateral
    return force, centre + spring_force / (stick_stiffness * contact_length)


def spatial_central_differences(fun, Ra, Rb, ra, rb, step):
    """d fun / dx by central differences in the spatial virtual displacements of a pair of
    RFEs, x = (dr_a, da_a, dr_b, da_b) with R -> exp(da) R: column j of the result is
    (fun at +step e_j - fun at -step e_j) / (2 step); fun(Ra, Rb, ra, rb) returns a vector."""
    columns = []
    for j in range(12):
        values = []
        for sign in (1.0, -1.0):
            d = np.zeros(12)
            d[j] = sign * step
            values.append(np.asarray(fun(exp_so3(d[3:6]) @ Ra, exp_so3(d[9:12]) @ Rb, ra + d[0:3], rb + d[6:9])))
        columns.append((values[0] - values[1]) / (2.0 * step))
    return np.stack(columns, axis=1)
