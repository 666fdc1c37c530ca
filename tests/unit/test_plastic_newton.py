"""Newton of the generalised-alpha step with elasto-plastic SDEs (rfesim.solvers.kernels.
ga_advance; docs/theory.md, 'Plastic SDEs and Newton').

The reel-lay template with 0.5 m elements starts its dynamics with hundreds of plastic SDEs
on the aligner at their yield surface. A Newton iterate that moves them switches their
tangent between elastic and plastic (EI against a hundredth of it): a Jacobian kept from one
iterate is of the wrong branch at the next, so modified Newton cycled. The first step failed
at the full step in both attempts and was retried in substeps; 29 % of the 60 s run's steps
were. Once a step is in trouble (an iteration that does not cut the residual 4 times) the
kernel now forms a Jacobian at every iterate when the model has plastic SDEs.

The test takes the arguments of the run's first call of the kernel and runs that step:
- with the kernel;
- with a readable replica of its Newton loop (the same residual, Jacobian and banded
  solver kernels, the control flow written out), once with the new rule and once with
  the old one.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import rfesim
import rfesim.solvers.fastcall as fastcall
from rfesim.solvers import kernels as K
from rfesim.solvers.banded import bt_factor_closed, bt_solve_closed
from rfesim.solvers.jacobian import jacobian_analytic_at
from rfesim.solvers.residual import residual_general, residual_norm
from rfesim.vessel_kernel import attachment_kinematics

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"


def replica_step(a, full_when_slow: bool, log: list):
    """One generalised-alpha step of ga_advance from a fresh start (no Jacobian kept, no
    previous acceleration: the constant-acceleration predictor), its Newton loop written
    out: a Jacobian at the first iterate; an iteration that cuts the residual by less than
    SLOW_RATE forms a new one (unless it still contracts fast enough); after MAX_FRESH
    Jacobians such an iteration gives the attempt up unless it halved the residual; a second
    attempt restarts from the predictor. ``full_when_slow``: once an attempt is in trouble,
    a Jacobian at every iterate (the rule for plastic SDEs). Returns (q or None, residual
    evaluations, Jacobians); ``log`` gets (attempt, iteration, residual / tolerance)."""
    km, vs, att, ws, q, qd, qdd, aux, ref = a[:9]
    t0, h, am, af, beta, gamma, tol, maxit = a[9], a[10], a[12], a[13], a[14], a[15], a[16], a[17]
    mask, ls, force_ref, J, Fac, Q0, V0, r, dq, qd_buf, A_buf, qp, rp, hs = a[19:33]
    Ks, Kds, T, Fsde, Msde = a[37:42]
    ref = type(ref)(*(x.copy() for x in ref))
    cq = h * h * beta * (1 - af) / (1 - am)
    cv = h * gamma * (1 - af) / (1 - am)
    attachment_kinematics(vs, t0 + h, att)
    ab = (af * qdd - am * aux) / (1 - am)
    Q0[:] = q + h * qd + h * h * (0.5 - beta) * aux + h * h * beta * ab
    V0[:] = qd + h * (1 - gamma) * aux + h * gamma * ab
    evals = jacobians = 0
    for attempt in range(2):
        x = Q0 + cq * qdd
        need, full, nfresh, rn_prev = True, False, 0, math.inf
        for it in range(maxit):
            residual_general(km, att, x, ref, ws, 1.0, np.int64(1), Q0, V0, cq, cv, mask, qd_buf, A_buf, r,
                             np.int64(2), Fsde, Msde)
            if km.has_sea and attempt == 0 and it == 0:
                ws.sea_frozen[0] = 1          # the water kinematics of the predictor, kept for the step
            rn = residual_norm(r, cq, mask, ls, force_ref)
            evals += 1
            log.append((attempt, it, rn / tol))
            if rn <= tol:
                ws.sea_frozen[0] = 0
                return x, evals, jacobians
            stale = min(K.STALE_ITERATIONS, maxit - 3.0 - it)
            slow = it > 0 and rn > K.SLOW_RATE * rn_prev and not (
                rn < K.CONTRACTS * rn_prev and stale > 0 and math.log(rn / tol) <= stale * math.log(rn_prev / rn))
            if slow:
                if nfresh >= K.MAX_FRESH and rn > K.PROGRESS * rn_prev:
                    break
                need = True
                full = full_when_slow
            if need or full:
                jacobian_analytic_at(km, att, x, ref, ws, 1.0, np.int64(1), Q0, V0, cq, cv, mask, qd_buf, A_buf, r,
                                     qp, rp, hs, ls, J, Ks, Kds, T, Fsde, Msde, np.bool_(True))
                assert bt_factor_closed(J, Fac, km, ws) < 0
                nfresh += 1
                jacobians += 1
                need = False
            bt_solve_closed(Fac, r, dq, km, ws)
            x = x - dq
            rn_prev = rn
    ws.sea_frozen[0] = 0
    return None, evals, jacobians


@pytest.fixture(scope="module")
def first_step():
    """The reel-lay at 0.5 m elements run for one step; the arguments of its first
    ga_advance call (copied before the call) and of its workspace."""
    captured = {}
    original = fastcall.FastCall

    class Capture(original):
        def __call__(self, *a):
            if getattr(self, "kernel", None) is K.ga_advance and "args" not in captured:
                captured["args"] = [x.copy() if isinstance(x, np.ndarray) else x for x in a]
                captured["args"][8] = type(a[8])(*(x.copy() for x in a[8]))
                captured["ws"] = [x.copy() for x in a[3]]
            return super().__call__(*a)

    d = json.loads((SCENARIOS / "reel_lay.json").read_text())
    d["pipelay"]["lay"]["element_length"] = 0.5
    d["analysis"]["dynamics"].update(duration=0.05, output_interval=0.05)
    mp = pytest.MonkeyPatch()
    mp.setattr(fastcall, "FastCall", Capture)
    try:
        rfesim.simulate(rfesim.load_scenario(d, base_dir=SCENARIOS))
    finally:
        mp.undo()
    a = captured["args"]
    assert a[9] == 0.0 and a[10] == 0.05 and a[3].plastic_hist.shape[0] > 0 and a[0].has_plastic

    def fresh():
        """The arguments as they were before the call (the workspace too)."""
        for dst, src in zip(a[3], captured["ws"]):
            dst[...] = src
        b = [x.copy() if isinstance(x, np.ndarray) else x for x in a]
        b[8] = type(a[8])(*(x.copy() for x in a[8]))
        b[11] = 1                 # one step
        b[33][:] = 0              # flags: no Jacobian kept, no previous acceleration
        b[34][:] = 0              # stats
        return b

    return fresh


def test_the_kernel_converges_the_step_modified_newton_cycled_on(first_step):
    b = first_step()
    assert K.ga_advance(*b) == 0
    steps, evals, jacobians, _ = b[34]
    assert steps == 1
    log = []
    q, r_evals, r_jacobians = replica_step(first_step(), True, log)
    assert q is not None, log
    assert (evals, jacobians) == (r_evals, r_jacobians), (b[34], r_evals, r_jacobians, log)
    # the same iterates to round-off, within the Newton tolerance's reach (a converged iterate
    # moves by about 1e-6 m where the tolerance is met)
    assert np.abs(b[4][:, :3] - q[:, :3]).max() < 1e-5
    # the old rule: a Jacobian kept from the iterate before a branch switch, and the
    # residual grows back; both attempts give up and the step went to substeps
    old = []
    q_old, _, _ = replica_step(first_step(), False, old)
    assert q_old is None
    assert any(o[2] > 10 * p[2] for p, o in zip(old, old[1:]) if p[0] == o[0]), old
