"""Scenes mixing absolute-coordinate lines with chains: scenario errors, the coupled Newton
solve (Schur complement = the dense solve), consistent initial accelerations, and the
Results of a run through the public API."""
from __future__ import annotations

import numpy as np
import pytest

import rfesim
from rfesim.formulations import mixed as M
from rfesim.scenario import Scenario
from rfesim.solvers.banded import bt_to_dense

G = 9.81


def scene(**line_end):
    end_a = {"attach": "c.arm"}
    end_a.update(line_end)
    return {"environment": {"gravity": G},
            "line_types": {"rope": {"EA": 1e5, "EIy": 1e-2, "GA": 1e5, "mass_per_length": 2.0}},
            "chains": {"c": {"links": {"arm": {"rigid": True, "length": 2.0, "mass": 10.0}},
                             "joints": {"j": {"kind": "revolute", "parent": "base", "child": "arm",
                                              "axis": [0, 1, 0], "stiffness": 5e3, "initial": 0.05}}}},
            "lines": {"rope": {"type": "rope", "length": 3.0, "elements": 4, "end_a": end_a,
                               "end_b": {"attach": "free"}}},
            "analysis": {"statics": {"enabled": True},
                         "dynamics": {"enabled": True, "duration": 0.2, "output_interval": 0.05,
                                      "integrator": {"kind": "generalized-alpha", "time_step": 0.01,
                                                     "rho_inf": 0.8}}}}


def errors_of(sc):
    with pytest.raises(rfesim.ScenarioError) as exc:
        Scenario.model_validate(sc)
    return dict(exc.value.errors)


@pytest.mark.parametrize("end, field, words", [
    ({"attach": "d.arm"}, "lines.rope.end_a.attach", "no chain 'd'"),
    ({"attach": "c.boom"}, "lines.rope.end_a.attach", "chain 'c' has no link 'boom'"),
    ({"attach": "c.arm", "at": 2.5}, "lines.rope.end_a.at", "beyond the tip of link 'arm'"),
    ({"attach": "fixed", "position": [0, 0, 0], "at": 1.0}, "lines.rope.end_a.at", "only for an end attached to a "
                                                                                     "chain link"),
])
def test_chain_attachment_errors_name_the_field(end, field, words):
    sc = scene()
    sc["lines"]["rope"]["end_a"] = end
    errs = errors_of(sc)
    assert field in errs, errs
    assert words in errs[field]


def test_mixed_scene_errors():
    sc = scene()
    sc["analysis"]["dynamics"]["integrator"] = {"kind": "rk4"}
    assert "use 'generalized-alpha'" in errors_of(sc)["analysis.dynamics.integrator.kind"]
    sc = scene()
    sc["lines"]["rope"]["formulation"] = "modified"
    sc["lines"]["rope"]["end_a"]["direction"] = [0, 0, -1]
    assert "only absolute-coordinate lines attach" in errors_of(sc)["lines.rope.end_a.attach"]
    sc = scene()
    sc["environment"]["seabed"] = {"z": -100.0}
    errs = errors_of(sc)
    assert any("seabed" in k for k in errs), errs
    with pytest.raises(rfesim.SolverError, match="modal analysis"):
        rfesim.modes(scene())


def coupled_step(h=0.01):
    sc = Scenario.model_validate(scene(at=1.5, position=[0.0, 0.1, 0.0]))
    ms = M.MixedScene(sc)
    st, c = M.initial_state(ms, sc)
    c["v"][:] = 0.3
    M.start_dynamics(ms, st, c)
    ig = M.make_integrator(ms, st, 0.8, 1e-10)
    cp = ig.cp
    am, af, beta, gamma = ig.am, ig.af, ig.beta, ig.gamma
    cq, cv = h * h * beta * (1 - af) / (1 - am), h * gamma * (1 - af) / (1 - am)
    Q0 = st.q + h * st.qd + h * h * 0.5 * st.qdd
    Q0c = c["x"] + h * c["v"] + h * h * 0.5 * c["a"]
    cp.setup(1, st.t + h, 1.0, Q0, st.qd.copy(), Q0c, c["v"].copy(), cq, cv)
    return ms, cp, st, Q0 + 1e-4, Q0c + 1e-3


def test_schur_complement_solve_equals_the_dense_solve():
    ms, cp, st, q, x = coupled_step()
    n = ms.system.n
    rL = np.zeros((n, 6))
    rC = cp.residual(q, st.ref, x, rL)
    assert cp.jacobian(q, st.ref, x, rL, rC, central=True) == -1
    rC = cp.residual(q, st.ref, x, rL)
    dL, dC = cp.solve(rL, rC)
    J = np.zeros((6 * n + ms.nc, 6 * n + ms.nc))
    J[:6 * n, :6 * n] = bt_to_dense(ms.system.J)
    J[:6 * n, 6 * n:] = cp.JLC.reshape(ms.nc, -1).T
    J[6 * n:, :6 * n] = cp.JCL.reshape(ms.nc, -1)
    J[6 * n:, 6 * n:] = cp.JCC
    d = np.linalg.solve(J, np.concatenate([rL.ravel(), rC]))
    np.testing.assert_allclose(dL.ravel(), d[:6 * n], rtol=0, atol=1e-9 * np.abs(d).max())
    np.testing.assert_allclose(dC, d[6 * n:], rtol=1e-7)


def test_coupling_blocks_against_central_differences_of_the_whole_residual():
    ms, cp, st, q, x = coupled_step()
    n = ms.system.n
    rL = np.zeros((n, 6))
    rC = cp.residual(q, st.ref, x, rL)
    cp.jacobian(q, st.ref, x, rL, rC)                 # forward differences, as in the step loop

    def whole(z):
        r = np.zeros((n, 6))
        c = cp.residual(z[:6 * n].reshape(n, 6), st.ref, z[6 * n:], r)
        return np.concatenate([r.ravel(), c])
    z0 = np.concatenate([q.ravel(), x])
    cols = [6 * n + j for j in range(ms.nc)] + [6 * i + a for i, a in ms.coupled_cols]
    for j in cols:
        hj = 1e-6 * max(1.0, abs(z0[j]))
        zp, zm = z0.copy(), z0.copy()
        zp[j] += hj
        zm[j] -= hj
        col = (whole(zp) - whole(zm)) / (2 * hj)
        if j >= 6 * n:
            mine = np.concatenate([cp.JLC[j - 6 * n].ravel(), cp.JCC[:, j - 6 * n]])
        else:
            mine = np.concatenate([np.zeros(6 * n), cp.JCL[:, j // 6, j % 6]])
            col[:6 * n] = 0.0                           # J_LL: checked by the line's own tests
        np.testing.assert_allclose(mine, col, rtol=0, atol=1e-5 * max(np.abs(col).max(), 1.0))
    # the coupling loads depend on no other line coordinates
    far = [6 * i + a for i in range(n) for a in range(6)
           if ms.system.mask[i, a] and (i, a) not in set(ms.coupled_cols)]
    for j in far[:6]:
        zp, zm = z0.copy(), z0.copy()
        zp[j] += 1e-6
        zm[j] -= 1e-6
        assert np.all(whole(zp)[6 * n:] == whole(zm)[6 * n:])


def test_initial_accelerations_solve_the_coupled_equations():
    sc = Scenario.model_validate(scene(at=1.0))
    ms = M.MixedScene(sc)
    st, c = M.initial_state(ms, sc)
    c["v"][:] = 0.5
    a, qdd = M.initial_accelerations(ms, st, c["x"], c["v"])
    # the residual of one implicit step with the accelerations given is consistent: with
    # cq -> A = (q - Q0) / cq equal to the accelerations the residual vanishes (mode 1)
    ig = M.make_integrator(ms, st, 0.8, 1e-10)
    cp = ig.cp
    cq = 1e-6
    Q0, Q0c = st.q - cq * qdd, c["x"] - cq * a
    cp.setup(1, st.t, 1.0, Q0, st.qd - 0.0 * qdd, Q0c, c["v"].copy(), cq, 0.0)
    rL = np.zeros_like(st.q)
    rC = cp.residual(st.q, st.ref, c["x"], rL)
    assert np.abs(rC / cq).max() < 1e-8 * ms.chain_ref
    assert np.abs((rL / cq)[ms.system.mask]).max() < 1e-8 * ms.total_weight


def test_simulate_through_the_api_gives_line_and_chain_results():
    sc = scene(at=1.5, position=[0.0, 0.0, -0.1])
    res = rfesim.simulate(sc)
    assert set(res.lines) == {"rope", "c.arm"}
    assert res.time[-1] == pytest.approx(0.2) and len(res.time) == 5
    theta = res.joints["c.j"].coordinate[:, 0]
    rope = res.line("rope")
    # the rope hangs from the arm point at s = 1.5 m, 0.1 m below the arm axis (link axes)
    for k, th in enumerate(theta):
        x_axis = np.array([np.cos(th), 0.0, -np.sin(th)])
        z_axis = np.array([np.sin(th), 0.0, np.cos(th)])
        np.testing.assert_allclose(rope.position[k, 0], 1.5 * x_axis - 0.1 * z_axis, atol=1e-9)
    assert res.counters["steps"] == 20
    # starting from the statics with the arm at rest, it stays at rest: theta constant
    np.testing.assert_allclose(theta, theta[0], atol=1e-8)
    assert rope.end_a_force[:, 2] == pytest.approx(-2.0 * 3.0 * G, rel=1e-6)


@pytest.mark.parametrize("end_x, warns", [(4.9, True), (5.1, False)])
def test_lines_of_a_mixed_scene_get_the_buckling_check(end_x, warns):
    # without gravity, the 3 m line from the arm's tip (2, 0, 0) to a fixed point on the arm's
    # axis starts straight: 2.9 m away it is a column at EA * 0.1 / 3 = 3.3 kN, far above its
    # Euler load pi^2 EI / L^2 = 0.011 N (rfesim.solvers.buckling); 3.1 m away it is in tension
    sc = scene()
    sc["environment"]["gravity"] = 0.0
    sc["chains"]["c"]["joints"]["j"]["initial"] = 0.0
    sc["lines"]["rope"]["end_b"] = {"attach": "fixed", "position": [end_x, 0.0, 0.0]}
    sc["analysis"]["dynamics"]["enabled"] = False
    st = rfesim.statics(sc)
    assert st.line("rope").tension[0] == pytest.approx(np.full(4, 1e5 * (end_x - 5.0) / 3.0), rel=1e-6)
    for message in (st.message, rfesim.simulate(sc).message):
        assert ("line 'rope' carries 3.333 kN of compression" in message) is warns, message
        assert ("above its Euler load pi^2 EI / L^2 = 1.097e-05 kN" in message) is warns, message
