"""SDEs with a rest rotation and drives (rfesim.loads.drives, rfesim.loads.sde): joints
between lines.

* the kernel against a slow readable numpy SDE with rest rotation R0 and drive rate omega0
  (to round-off), whose elastic forces are checked to be minus the gradient of
  V = 1/2 eps^T C eps and whose deformation rate is the time derivative of eps along the
  rigid motions of the RFEs and the drive;
* the identity rest rotation reproduces the forces of the plain SDE bit for bit;
* the drive kernel's R0(t) equals the closed form with scipy's PCHIP, and its rate a
  central difference of R0(t);
* the analytic SDE tangent with rest rotations against finite differences.
"""
from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

import reference_impl as ref
from rfesim.loads.drives import axis_angle_into, drive_rest_into, drive_table, rest_at
from rfesim.loads.sde import sde_forces, sde_forces_rest
from rfesim.loads.sde_tangent import sde_tangent_rest
from rfesim.loads.tensioner import _table
from rfesim.model.arrays import joint_arrays

SEEDS = range(6)


# ----------------------------------------------------------------------------- readable reference

def rest_deformation(ra, Ra, arm_a, rb, Rb, arm_b, R0):
    """eps = [R'^T g, theta] with theta = log((R_a R0)^T R_b), R' = R_a R0 exp(theta/2); the
    gap g between the RFE ends uses the arms turned by R_a, R_b (eqs. 8.75-8.85)."""
    g = (rb + Rb @ arm_b) - (ra + Ra @ arm_a)
    Ras = Ra @ R0
    theta = ref.log_so3(Ras.T @ Rb)
    Rp = Ras @ ref.exp_so3(0.5 * theta)
    return np.concatenate([Rp.T @ g, theta])


def reference_rest_forces(p, C, D, R0, omega0):
    """Forces and moments (F_a, M_a, F_b, M_b, about the centres) and sigma of one SDE with
    rest rotation R0 and drive rate omega0 (left RFE's body frame, dR0/dt = [omega0]x R0),
    written out from the chapter's formulas (eqs. 8.85-8.90) with the exact J_r of
    reference_impl."""
    Ra, Rb = p["Ra"], p["Rb"]
    pa, pb = Ra @ p["arm_a"], Rb @ p["arm_b"]
    g = (p["rb"] + pb) - (p["ra"] + pa)
    Ras = Ra @ R0
    theta = ref.log_so3(Ras.T @ Rb)
    Rp = Ras @ ref.exp_so3(0.5 * theta)
    Jri = ref.right_jacobian_inverse(theta)
    Jrh = ref.right_jacobian(0.5 * theta)
    w0 = Ra @ omega0                                        # angular velocity of R0 (global)
    theta_dot = Jri @ Rb.T @ (p["wb"] - p["wa"] - w0)
    w_mean = p["wa"] + w0 + 0.5 * Rp @ Jrh @ theta_dot       # angular velocity of {i'}
    g_dot = p["vb"] + np.cross(p["wb"], pb) - p["va"] - np.cross(p["wa"], pa)
    delta = Rp.T @ g
    delta_dot = Rp.T @ (g_dot - np.cross(w_mean, g))
    Fp = C[:3] * delta + D[:3] * delta_dot
    Mp = C[3:] * theta + D[3:] * theta_dot
    Fg = Rp @ Fp
    mg = Rb @ Jri.T @ Mp
    h = np.cross(Fg, g)
    wth = Rb @ Jri.T @ Jrh.T @ Rp.T @ h
    F_a, F_b = Fg, -Fg
    M_a = np.cross(pa, Fg) + mg - h + 0.5 * wth
    M_b = -np.cross(pb, Fg) - mg - 0.5 * wth
    return np.concatenate([F_a, M_a, F_b, M_b]), np.concatenate([Fp, Mp]), np.concatenate([delta, theta])


def random_joint(rng, kink=np.pi / 2, bend=0.3, gap=0.05):
    """Two RFEs joined at a kink: R_b = R_a R0 exp(~bend), a random rest rotation R0 of
    angle ``kink``, a gap of ~gap, random velocities."""
    R0 = ref.exp_so3(ref.random_rotation_vector(rng, kink))
    Ra = ref.random_rotation(rng)
    Rb = Ra @ R0 @ ref.exp_so3(ref.random_rotation_vector(rng, bend * rng.uniform(0.1, 1.0)))
    arm_a = np.array([rng.uniform(0.3, 2.0), 0, 0]) + rng.normal(scale=0.05, size=3)
    arm_b = np.array([-rng.uniform(0.3, 2.0), 0, 0]) + rng.normal(scale=0.05, size=3)
    ra = rng.uniform(-50, 50, size=3)
    rb = ra + Ra @ arm_a - Rb @ arm_b + rng.normal(scale=gap, size=3)
    p = dict(Ra=Ra, Rb=Rb, ra=ra, rb=rb, arm_a=arm_a, arm_b=arm_b, va=rng.normal(size=3), vb=rng.normal(size=3),
             wa=rng.normal(size=3), wb=rng.normal(size=3))
    C = rng.uniform(0.5, 2.0, size=6) * np.array([1e5, 3e4, 3e4, 2e3, 5e3, 5e3])
    D = rng.uniform(0.5, 2.0, size=6) * np.array([1e3, 3e2, 3e2, 20.0, 50.0, 50.0])
    return p, C, D, R0, rng.normal(size=3)


def kernel_rest_forces(p, C, D, R0, omega0, flag):
    """sde_forces_rest on the pair; flag 1: R0 as a constant rest rotation (omega0 unused),
    2: as the driven one with rate omega0."""
    F = np.zeros((2, 3))
    M = np.zeros((2, 3))
    eps, sigma, point = np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3))
    R0s = np.ascontiguousarray(R0[None])
    sde_forces_rest(np.array([0]), np.array([1]), p["arm_a"][None], p["arm_b"][None], C[None], D[None],
                    np.array([flag], np.int64), R0s, R0s.copy(), np.ascontiguousarray(omega0[None]),
                    np.stack([p["Ra"], p["Rb"]]), np.stack([p["ra"], p["rb"]]), np.zeros((2, 3)),
                    np.stack([p["va"], p["vb"]]), np.stack([p["wa"], p["wb"]]), F, M, eps, sigma, point)
    return np.concatenate([F[0], M[0], F[1], M[1]]), sigma[0], eps[0]


@pytest.mark.parametrize("seed", SEEDS)
def test_kernel_equals_readable_reference_with_rest_rotation_and_drive(seed):
    rng = np.random.default_rng(seed)
    p, C, D, R0, omega0 = random_joint(rng)
    for flag, w0 in ((2, omega0), (1, np.zeros(3))):
        f, sigma, eps = kernel_rest_forces(p, C, D, R0, omega0, flag)
        f_ref, sigma_ref, eps_ref = reference_rest_forces(p, C, D, R0, w0)
        assert np.abs(eps - eps_ref).max() <= 1e-12 * max(1.0, np.abs(eps_ref).max())
        assert np.abs(sigma - sigma_ref).max() <= 1e-11 * np.abs(sigma_ref).max()
        assert np.abs(f - f_ref).max() <= 1e-11 * np.abs(f_ref).max()
    # the kink matters: without the rest rotation the forces are different
    f_plain, _, _ = kernel_rest_forces(p, C, D, np.eye(3), omega0, 1)
    assert np.abs(f_plain - f_ref).max() > 1e-2 * np.abs(f_ref).max()


@pytest.mark.parametrize("seed", SEEDS)
def test_elastic_forces_are_minus_the_gradient_of_the_energy_with_rest_rotation(seed):
    """F = -dV/dr and M = -dV/d(delta) (global virtual rotations R -> exp([delta]x) R) with
    eps measured from R_a R0: the force application of the plain SDE is exact for R_a*."""
    rng = np.random.default_rng(seed)
    p, C, _, R0, _ = random_joint(rng)
    f, _, _ = kernel_rest_forces(p, C, np.zeros(6), R0, np.zeros(3), 1)

    def V(x):
        Ra = ref.exp_so3(x[3:6]) @ p["Ra"]
        Rb = ref.exp_so3(x[9:12]) @ p["Rb"]
        e = rest_deformation(p["ra"] + x[0:3], Ra, p["arm_a"], p["rb"] + x[6:9], Rb, p["arm_b"], R0)
        return 0.5 * float(np.sum(C * e * e))

    h = 1e-6
    grad = np.zeros(12)
    for j in range(12):
        d = np.zeros(12)
        d[j] = h
        grad[j] = (V(d) - V(-d)) / (2 * h)
    assert np.abs(f + grad).max() <= 1e-6 * np.abs(f).max()


@pytest.mark.parametrize("seed", SEEDS)
def test_deformation_rate_follows_the_rigid_motions_and_the_drive(seed):
    """With C = 0, sigma = D d(eps)/dt: the kernel's deformation rate equals the central
    difference of eps along the rigid motions of both RFEs and R0(t) = exp(t [omega0]x) R0."""
    rng = np.random.default_rng(seed)
    p, _, D, R0, omega0 = random_joint(rng)
    _, sigma, _ = kernel_rest_forces(p, np.zeros(6), D, R0, omega0, 2)

    def eps_at(dt):
        ra, Ra = ref.rigid_motion(p["ra"], p["Ra"], p["va"], p["wa"], dt)
        rb, Rb = ref.rigid_motion(p["rb"], p["Rb"], p["vb"], p["wb"], dt)
        return rest_deformation(ra, Ra, p["arm_a"], rb, Rb, p["arm_b"], ref.exp_so3(dt * omega0) @ R0)

    h = 1e-6
    rate = (eps_at(h) - eps_at(-h)) / (2 * h)
    assert np.abs(sigma - D * rate).max() <= 1e-6 * np.abs(D * rate).max()
    # RFE b rigidly following the drive (w_b = w_a + R_a omega0, same point velocity at the
    # joint): no relative rotation rate, so no damping moment from the drive rate
    q = dict(p)
    q["wb"] = p["wa"] + p["Ra"] @ omega0
    _, sigma_follow, _ = kernel_rest_forces(q, np.zeros(6), D, R0, omega0, 2)
    assert np.abs(sigma_follow[3:]).max() <= 1e-12 * np.abs(D[3:]).max() * np.abs(omega0).max()


@pytest.mark.parametrize("seed", SEEDS)
def test_identity_rest_rotation_gives_exactly_the_plain_forces(seed):
    rng = np.random.default_rng(seed)
    p, C, D, _, _ = random_joint(rng, kink=0.0)
    F = np.zeros((2, 3))
    M = np.zeros((2, 3))
    eps, sigma, point = np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3))
    sde_forces(np.array([0]), np.array([1]), p["arm_a"][None], p["arm_b"][None], C[None], D[None],
               np.stack([p["Ra"], p["Rb"]]), np.stack([p["ra"], p["rb"]]), np.zeros((2, 3)),
               np.stack([p["va"], p["vb"]]), np.stack([p["wa"], p["wb"]]), F, M, eps, sigma, point)
    plain = np.concatenate([F[0], M[0], F[1], M[1]])
    for flag in (1, 2):
        f, s, e = kernel_rest_forces(p, C, D, np.eye(3), np.zeros(3), flag)
        assert np.array_equal(f, plain)
        assert np.array_equal(s, sigma[0])
        assert np.array_equal(e, eps[0])


# ----------------------------------------------------------------------------- drives

def drive_closed_form(rows, rest, t):
    """R0(t) = Rot(a1, dphi1(t)) Rot(a2, dphi2(t)) rest with scipy's PCHIP angles (constant
    beyond the table; from rest at a first row at t >= 0), dphi = phi(t) - phi(0); a two-row table is a cubic with zero end
    slopes (a move that starts and stops smoothly, like the tensioner's payout table)."""
    out = np.eye(3)
    for d in rows:
        tab = np.asarray(d["table"], float)
        if len(tab) >= 3:
            # PCHIP's slopes, but a table from t >= 0 starts at rest (rfesim.model.supports.drive_slopes)
            v = PchipInterpolator(tab[:, 0], tab[:, 1]).derivative()(tab[:, 0])
            if tab[0, 0] >= 0.0:
                v[0] = 0.0
            f = CubicHermiteSpline(tab[:, 0], tab[:, 1], v)
        else:
            f = CubicHermiteSpline(tab[:, 0], tab[:, 1], np.zeros(len(tab)))
        phi = lambda x: float(f(np.clip(x, tab[0, 0], tab[-1, 0])))  # noqa: E731
        a = np.asarray(d["axis"], float) / np.linalg.norm(d["axis"])
        out = out @ ref.exp_so3(a * (phi(t) - phi(0.0)))
    return out @ rest


DRIVES = [{"sde": 1, "axis": [0.0, 0.0, 1.0], "table": [[0.0, 0.1], [2.0, 0.5], [5.0, 1.5], [8.0, 1.0]]},
          {"sde": 1, "axis": [0.3, 1.0, 0.0], "table": [[1.0, 0.0], [4.0, -0.6], [6.0, -0.2], [7.0, 0.4]]},
          {"sde": 3, "axis": [1.0, 0.0, 0.0], "table": [[0.0, 0.0], [3.0, 2.0]]}]


def drive_model(rest):
    arrays = joint_arrays(4, {1: rest, 2: rest.T}, DRIVES)
    return arrays


def test_joint_arrays_flags_and_table():
    rest = ref.exp_so3(np.array([0.2, -0.4, 0.9]))
    a = drive_model(rest)
    assert a["sde_has_rest"].tolist() == [0, 2, 1, 2]
    assert a["has_drives"] and a["drive_sde"].tolist() == [1, 1, 3]
    assert np.allclose(np.linalg.norm(a["drive_axis"], axis=1), 1.0)
    # phi0 is the table value at t = 0 (second drive: its first row, the table starts at 1 s)
    assert a["drive_phi0"].tolist() == [0.1, 0.0, 0.0]
    # the value is the tensioner's monotone cubic, and the slope its derivative
    for j, t in ((0, 3.3), (1, 4.5), (2, 1.0)):
        c = a["drive_count"][j]
        args = (a["drive_t"][j, :c], a["drive_angle"][j, :c], a["drive_slope"][j, :c])
        v, s = drive_table(*args, t)
        assert v == _table(*args, t)
        assert abs(s - (_table(*args, t + 1e-6) - _table(*args, t - 1e-6)) / 2e-6) < 1e-8
    with pytest.raises(ValueError, match="times must increase"):
        joint_arrays(2, None, [{"sde": 0, "axis": [0, 0, 1], "table": [[0, 0], [0, 1]]}])
    with pytest.raises(ValueError, match="SDE index 5"):
        joint_arrays(2, None, [{"sde": 5, "axis": [0, 0, 1], "table": [[0, 0], [1, 1]]}])


@pytest.mark.parametrize("t", [0.0, 0.7, 2.0, 3.3, 4.5, 5.5, 6.9, 9.0])
def test_drive_rest_rotation_equals_closed_form_and_rate_its_derivative(t):
    rest = ref.exp_so3(np.array([0.2, -0.4, 0.9]))
    a = drive_model(rest)
    km_rest = a["sde_rest"]

    def kernel(time):
        eff = np.zeros((4, 3, 3))
        rate = np.zeros((4, 3))
        drive_rest_into(a["drive_sde"], a["drive_axis"], a["drive_t"], a["drive_angle"], a["drive_slope"],
                        a["drive_count"], a["drive_phi0"], km_rest, time, eff, rate, np.zeros((3, 3)),
                        np.zeros((3, 3)), np.zeros((3, 3)))
        return eff, rate

    eff, rate = kernel(t)
    assert np.abs(eff[1] - drive_closed_form(DRIVES[:2], rest, t)).max() < 1e-13
    assert np.abs(eff[3] - drive_closed_form(DRIVES[2:], np.eye(3), t)).max() < 1e-13
    assert np.abs(eff[[0, 2]]).max() == 0.0                 # only driven SDEs are written
    # omega0: dR0/dt = [omega0]x R0, at t = 0 too: a table from t >= 0 starts from rest
    # (rfesim.model.supports.drive_slopes; with PCHIP's own first slope the rate jumped there).
    # The step is small for the differences across a row, where the second derivative jumps
    h = 1e-7
    for s in (1, 3):
        dR = (kernel(t + h)[0][s] - kernel(t - h)[0][s]) / (2 * h)
        omega_fd = ref.unskew(dR @ eff[s].T)
        assert np.abs(rate[s] - omega_fd).max() < 1e-7 * max(1.0, np.abs(omega_fd).max())
    if t >= 8.0:
        assert np.abs(rate).max() == 0.0                    # beyond every table: at rest
    if t == 0.0:
        assert np.abs(eff[1] - rest).max() < 1e-15          # the start is the stress-free state


def test_axis_angle_is_the_exponential_map():
    out = np.zeros((3, 3))
    ax = np.array([0.3, -0.5, 0.8])
    ax /= np.linalg.norm(ax)
    axis_angle_into(ax, 1.234, out)
    assert np.abs(out - ref.exp_so3(1.234 * ax)).max() < 1e-15


# ----------------------------------------------------------------------------- tangent

def spatial_forces(Ra, Rb, ra, rb, arm_a, arm_b, C, R0):
    R0s = np.ascontiguousarray(R0[None])
    F = np.zeros((2, 3))
    M = np.zeros((2, 3))
    eps, sigma, point = np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 3))
    sde_forces_rest(np.array([0]), np.array([1]), arm_a[None], arm_b[None], C[None], np.zeros((1, 6)),
                    np.array([1], np.int64), R0s, R0s, np.zeros((1, 3)), np.stack([Ra, Rb]), np.stack([ra, rb]),
                    np.zeros((2, 3)), np.zeros((2, 3)), np.zeros((2, 3)), F, M, eps, sigma, point)
    return np.concatenate([F[0], M[0], F[1], M[1]]), sigma


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("bend", [1e-3, 0.03])
def test_tangent_with_rest_rotation_matches_finite_differences(seed, bend):
    rng = np.random.default_rng(seed)
    p, _, _, R0, _ = random_joint(rng, bend=bend, gap=1e-3)
    C = np.array([1e6, 3e5, 2e5, 1e4, 2e4, 3e4])
    args = (p["arm_a"], p["arm_b"], C, R0)
    _, sigma = spatial_forces(p["Ra"], p["Rb"], p["ra"], p["rb"], *args)
    K = np.zeros((1, 12, 12))
    Kd = np.zeros((1, 12, 12))
    R0s = np.ascontiguousarray(R0[None])
    sde_tangent_rest(np.array([0]), np.array([1]), p["arm_a"][None], p["arm_b"][None], C[None], np.zeros((1, 6)),
                     np.array([1], np.int64), R0s, R0s, np.stack([p["Ra"], p["Rb"]]), np.stack([p["ra"], p["rb"]]),
                     np.zeros((2, 3)), sigma, K, Kd)
    Kfd = -ref.spatial_central_differences(
        lambda Ra, Rb, ra, rb: spatial_forces(Ra, Rb, ra, rb, *args)[0], p["Ra"], p["Rb"], p["ra"], p["rb"], 1e-7)
    scale = np.abs(Kfd).max()
    # as for the plain SDE (tests/unit/test_sde_tangent.py): exact but for the change of W in
    # W^T h (h = F x g, O(|F| |g|))
    assert np.abs(K[0] - Kfd).max() <= 1e-5 * scale
    # and the rest rotation matters: the tangent of the plain SDE at this kinked pose differs
    K0 = np.zeros((1, 12, 12))
    eye = np.ascontiguousarray(np.eye(3)[None])
    sde_tangent_rest(np.array([0]), np.array([1]), p["arm_a"][None], p["arm_b"][None], C[None], np.zeros((1, 6)),
                     np.array([1], np.int64), eye, eye, np.stack([p["Ra"], p["Rb"]]), np.stack([p["ra"], p["rb"]]),
                     np.zeros((2, 3)), sigma, K0, Kd)
    assert np.abs(K0[0] - Kfd).max() > 0.1 * scale


def test_rest_at_python_helper_matches_kernel_arrays():
    rest = ref.exp_so3(np.array([0.2, -0.4, 0.9]))
    a = drive_model(rest)

    class KM:
        pass
    km = KM()
    for k, v in a.items():
        setattr(km, k, v)
    km.sde_left = np.arange(4)
    R, w = rest_at(km, 3.3)
    assert np.abs(R[1] - drive_closed_form(DRIVES[:2], rest, 3.3)).max() < 1e-13
    assert np.abs(R[2] - rest.T).max() == 0.0 and np.abs(R[0] - np.eye(3)).max() == 0.0
    assert np.abs(w[[0, 2]]).max() == 0.0 and np.abs(w[1]).max() > 0.0
