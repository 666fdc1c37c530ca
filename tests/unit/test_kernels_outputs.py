"""rfesim.model.outputs (SDE channels, line points, end reactions) against direct numpy."""
from __future__ import annotations

import numpy as np
import pytest

import reference_impl as ref
from rfesim.model.arrays import KIND_CLAMPED, KIND_FREE, KIND_PINNED, new_workspace
from rfesim.model.compile import compile_scenario
from rfesim.model.outputs import line_points, reactions, sde_channels
from rfesim.scenario import load_scenario
from rfesim.solvers.system import System
from test_kernels_assemble import SCENARIO, accelerations, indices, random_state

SEEDS = [0, 1, 2, 3]
ROUNDOFF = 1e-12


@pytest.mark.parametrize("seed", SEEDS)
def test_sde_channels(seed):
    rng = np.random.default_rng(seed)
    n, nsde = 6, 5
    ws = new_workspace(n, nsde)
    ws.sigma[:] = rng.normal(scale=1e4, size=(nsde, 6))
    ws.eps[:] = rng.normal(scale=1e-2, size=(nsde, 6))
    ws.sigma[0, 1:3] = 0.0                          # no shear on this one
    length = rng.uniform(0.5, 3.0, size=nsde)
    channels = [np.full(nsde, np.nan) for _ in range(5)]
    sde_channels(ws, length, *channels)
    for value, expected in zip(channels, ref.sde_result_channels(ws.sigma, ws.eps, length)):
        np.testing.assert_allclose(value, expected, rtol=ROUNDOFF, atol=0)


@pytest.mark.parametrize("seed", SEEDS)
def test_line_points(seed):
    rng = np.random.default_rng(seed)
    n, nsde = 9, 8
    ws = new_workspace(n, nsde)
    ws.r[:] = rng.uniform(-50.0, 50.0, size=(n, 3))
    ws.R[:] = [ref.random_rotation(rng) for _ in range(n)]
    ws.sde_point[:] = rng.uniform(-50.0, 50.0, size=(nsde, 3))
    length = rng.uniform(0.5, 3.0, size=n)
    # two lines back to back: RFEs 0..3 with SDEs 0..2, RFEs 4..8 with SDEs 3..7
    for rfe_start, rfe_stop, sde_start, sde_stop in ((0, 4, 0, 3), (4, 9, 3, 8)):
        out = np.full((sde_stop - sde_start + 2, 3), np.nan)
        line_points(ws, rfe_start, rfe_stop, sde_start, sde_stop, length, out)
        end_a, end_b = ref.line_end_points(ws.r[rfe_start], ws.R[rfe_start], length[rfe_start],
                                           ws.r[rfe_stop - 1], ws.R[rfe_stop - 1], length[rfe_stop - 1])
        np.testing.assert_allclose(out[0], end_a, rtol=0, atol=ROUNDOFF * 50)
        np.testing.assert_allclose(out[-1], end_b, rtol=0, atol=ROUNDOFF * 50)
        np.testing.assert_array_equal(out[1:-1], ws.sde_point[sde_start:sde_stop])


@pytest.fixture(scope="module")
def system():
    return System(compile_scenario(load_scenario(SCENARIO)))


@pytest.mark.parametrize("seed", SEEDS)
def test_reactions(seed, system):
    """Pinned end: the pin force of the independent Newton-Euler solution (no moment).
    Clamped end: force and moment making the RFE follow its attachment (Newton-Euler with
    the attachment's angular velocity and acceleration)."""
    rng = np.random.default_rng(seed)
    state = random_state(system, rng)
    qdd = accelerations(system, state)
    ws, km, att = system.ws, system.km, system.att
    out = np.full((system.n, 6), np.nan)
    reactions(km, att, ws, qdd, out)
    for i in indices(system, KIND_FREE):
        np.testing.assert_array_equal(out[i], 0.0)
    for i in indices(system, KIND_PINNED):
        pin, _, pin_acceleration = ref.attachment_point_kinematics(att, km.rfe_attach[i], km.rfe_attach_offset[i])
        _, _, reaction = ref.pinned_rfe_newton_euler(km.rfe_mass[i], ws.Ma[i], km.rfe_inertia[i] + ws.Ja[i],
                                                     ws.R[i], ws.w[i], ws.r[i], pin, pin_acceleration, ws.F[i],
                                                     ws.M[i])
        scale = np.abs(ws.F[i]).max() + np.abs(reaction).max()
        np.testing.assert_allclose(out[i, :3], reaction, rtol=0, atol=1e-10 * scale)
        np.testing.assert_array_equal(out[i, 3:], 0.0)
    for i in indices(system, KIND_CLAMPED):
        a = km.rfe_attach[i]
        pin, _, pin_acceleration = ref.attachment_point_kinematics(att, a, km.rfe_attach_offset[i])
        w, alpha = att.w[a], att.alpha[a]
        centre_acceleration = ref.point_acceleration(pin_acceleration, alpha, w, ws.r[i] - pin)
        force = (km.rfe_mass[i] * np.eye(3) + ws.Ma[i]) @ centre_acceleration - ws.F[i]
        J_global = ws.R[i] @ np.diag(km.rfe_inertia[i] + ws.Ja[i]) @ ws.R[i].T
        moment = J_global @ alpha + np.cross(w, J_global @ w) - ws.M[i] - np.cross(pin - ws.r[i], force)
        scale = np.abs(ws.F[i]).max() + np.abs(force).max()
        np.testing.assert_allclose(out[i, :3], force, rtol=0, atol=ROUNDOFF * scale)
        np.testing.assert_allclose(out[i, 3:], moment, rtol=0,
                                   atol=ROUNDOFF * (np.abs(ws.M[i]).max() + scale * km.rfe_length[i]))
