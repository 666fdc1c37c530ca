"""Compiled time-stepping kernels: residuals, Jacobians, and the integrators' step loops.

Whole runs of steps happen inside these functions (no Python per step): the attachment
(vessel) kinematics is compiled too (``rfesim.vessel_kernel``). Each advance function
returns a status code: 0 ok, 1 Newton did not converge, 2 non-finite or runaway state,
3 singular Jacobian; ``fail`` holds (time, RFE index, quantity code) of a failure.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..model.assemble import commit_history, evaluate, rebase, solve_accelerations
from .jacobian import jacobian_analytic_at
from .residual import residual_general, residual_norm, residual_q  # noqa: F401  (re-exported)
from ..vessel_kernel import attachment_kinematics
from ..loads.tension_only import rope_reach
from .banded import bt_factor_closed, bt_solve_closed

SLOW_STEP = 8                   # residual evaluations after which the next step refreshes its Jacobian
REBASE_THRESHOLD = 0.5          # rad: re-base an RFE's reference rotation beyond this angle
RUNAWAY_SPEED = 1.0e5           # m/s or rad/s: a state faster than this has diverged
RUNAWAY_DISTANCE = 1.0e7        # m
MAX_FRESH = 3                   # Jacobians formed within one Newton attempt before the step is given up
PROGRESS = 0.5                  # ... unless each iteration still cuts the residual to this fraction
SLOW_RATE = 0.25                # an iteration that cuts the residual by less than this fraction forms a new Jacobian
STALE_ITERATIONS = 6.0          # ... unless it still contracts (below CONTRACTS) and, at the rate seen, reaches the
CONTRACTS = 0.9                 # tolerance within this many more iterations (a Jacobian costs 6-10 residuals)

# quantity codes in ``fail[2]``
Q_POSITION, Q_VELOCITY, Q_NEWTON, Q_JACOBIAN, Q_THROUGH = 0, 1, 2, 3, 4
ROPE_THROUGH = 1.0              # a rope SDE's gap past -ROPE_THROUGH (|arm_L| + |arm_R|): elements passed through


FD_REL_STEP = 1.5e-8      # relative step of the forward-difference Jacobian


def jacobian_fd(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                length_scale, J):
    """Block-tridiagonal Jacobian d(residual)/dq by forward differences, RFEs coloured by
    index mod 3 (RFEs of one colour are three apart, so their effects never overlap).
    A Python function (``jacobian_fd_general`` forward, as compiled kernels call it): a
    compiled wrapper would be another entry point compiled with its whole tree of kernels."""
    jacobian_fd_general(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                        length_scale, J, False, FD_REL_STEP)


@njit(cache=True)
def jacobian_fd_general(km, att, q, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0, qp, rp, hs,
                        length_scale, J, central, rel_step):
    """Coloured finite-difference Jacobian; ``central`` uses (r(q+h) - r(q-h)) / 2h with r0
    as a second buffer (overwritten), for the accuracy modal analysis needs."""
    n = q.shape[0]
    not_frozen = np.int64(0)       # int64, not a literal: one specialization of residual_general
    for c in range(3):
        for k in range(6):
            for i in range(n):
                for a in range(6):
                    qp[i, a] = q[i, a]
            for i in range(c, n, 3):
                typical = length_scale[i] if k < 3 else 1.0
                h = rel_step * max(abs(q[i, k]), typical)
                tmp = q[i, k] + h
                hs[i] = tmp - q[i, k]
                qp[i, k] = tmp
            residual_general(km, att, qp, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, rp, not_frozen,
                             ws.F, ws.M)
            if central:
                for i in range(c, n, 3):
                    qp[i, k] = q[i, k] - hs[i]
                residual_general(km, att, qp, ref, ws, scale, mode, Q0, V0, cq, cv, mask, qd_buf, A_buf, r0,
                                 not_frozen, ws.F, ws.M)
            for i in range(c, n, 3):
                inv = 1.0 / (2.0 * hs[i]) if central else 1.0 / hs[i]
                for j in range(i - 1, i + 2):
                    if j < 0 or j >= n:
                        continue
                    slot = i - j + 1
                    for a in range(6):
                        J[j, slot, a, k] = (rp[j, a] - r0[j, a]) * inv
    # blocks across the ends of the matrix must be zero
    for a in range(6):
        for b in range(6):
            J[0, 0, a, b] = 0.0
            J[n - 1, 2, a, b] = 0.0


@njit(cache=True, _nrt=False)
def check_state(q, qd, mask, fail, t):
    """Non-finite or runaway coordinates: fill fail and return 2, else 0."""
    for i in range(q.shape[0]):
        for k in range(6):
            x = q[i, k]
            v = qd[i, k]
            if not (math.isfinite(x) and math.isfinite(v)):
                fail[0] = t
                fail[1] = i
                fail[2] = Q_POSITION if not math.isfinite(x) else Q_VELOCITY
                return 2
            if mask[i, k] and (abs(v) > RUNAWAY_SPEED or (k < 3 and abs(x) > RUNAWAY_DISTANCE)):
                fail[0] = t
                fail[1] = i
                fail[2] = Q_VELOCITY if abs(v) > RUNAWAY_SPEED else Q_POSITION
                return 2
    return 0


@njit(cache=True, _nrt=False)
def check_ropes(km, ws, fail, t):
    """A tension-only SDE (rope) whose axial gap ws.eps[s, 0] (eq. 8.85) of the last
    evaluation is below -ROPE_THROUGH times its arms' sum (for two elements of a line: their
    centres have met): its two elements were pushed through one another, past the axial
    contact that should have held them (rfesim.loads.tension_only). From there a joint
    pulled apart reads as compression, so the rope would come apart with no tension and the
    run go on as if nothing happened (before the contact: a payload flung 200 m from the
    sheave on a 2 m rope). A diverged state: fill fail (the SDE's left RFE) and return 2
    (the driver retries the interval in shorter steps), else 0."""
    if not km.has_tension_only:
        return 0
    for s in range(km.sde_tension_only.shape[0]):
        if km.sde_tension_only[s] != 0 and ws.eps[s, 0] < 0.0 and \
                ws.eps[s, 0] < -ROPE_THROUGH * rope_reach(km.sde_arm_left, km.sde_arm_right, s):
            fail[0] = t
            fail[1] = km.sde_left[s]
            fail[2] = Q_THROUGH
            return 2
    return 0


@njit(cache=True)
def explicit_acceleration(km, vs, att, ws, t, q, qd, ref, qdd):
    attachment_kinematics(vs, t, att)
    evaluate(km, att, q, qd, ref, ws, 1.0)
    solve_accelerations(ws, qdd)


# ----------------------------------------------------------------------------- generalised-alpha

@njit(cache=True, _nrt=False)
def ga_advance(km, vs, att, ws, q, qd, qdd, aux, ref, t0, h, nsteps, alpha_m, alpha_f, beta, gamma, tol,
               maxit, reuse, mask, length_scale, force_ref, J, Fac, Q0, V0, r, dq, qd_buf, A_buf, qp, rp, hs,
               flags, stats, fail, analytic, Ks, Kds, T, Fsde, Msde, qdd_prev):
    """Advance nsteps generalised-alpha steps of size h from t0 (Chung & Hulbert 1993 in the
    form of Arnold & Bruls 2007: equilibrium at t_{n+1}, algorithmic acceleration ``aux``).

    flags[0] = 1 when Fac holds a factorised Jacobian valid for this h (kept between calls:
    modified Newton); flags[1] = residual evaluations of the last step: a step that needed
    more than SLOW_STEP of them refreshes the Jacobian at the start of the next (a reused
    Jacobian goes stale as the line turns). Within a step, an iteration that reduces the
    residual by less than 4x forms a new Jacobian (so a step in trouble becomes full
    Newton), unless the iteration still contracts and, at the rate it shows, reaches the
    tolerance within STALE_ITERATIONS more and within the iterations left in the step less 3
    (a Jacobian and its factorisation cost as much as 6-10 residual evaluations; without the
    second limit steps ran out of iterations and were halved: docs/theory.md, 'When Newton
    forms a new Jacobian'); a step
    that still fails restarts once from the constant-acceleration predictor with a fresh
    Jacobian, and, in a step already halved by the driver (flags[3] = 1), once more from the
    step's start state (docs/theory.md, 'Slack ropes and Newton'). stats += [steps, newton
    iterations, jacobians,
    rebases]. ``analytic``: Jacobian from the SDE tangent (rfesim.solvers.jacobian) instead
    of coloured finite differences; Ks, Kds, T, Fsde, Msde are its work arrays. The Newton
    predictor extrapolates the acceleration linearly from the last two steps (qdd_prev holds
    the previous one; flags[2] = 1 once it is valid).
    """
    n = q.shape[0]
    cq = h * h * beta * (1.0 - alpha_f) / (1.0 - alpha_m)
    cv = h * gamma * (1.0 - alpha_f) / (1.0 - alpha_m)
    attempts = 3 if flags.shape[0] > 3 and flags[3] == 1 else 2
    # mode 1 (dynamics) and frozen 2 as int64, not literals: a literal argument makes numba
    # compile another specialization of the whole residual and Jacobian kernels for it
    mode_dyn = np.int64(1)
    keep_sde = np.int64(2)
    not_frozen = np.int64(0)
    for step in range(nsteps):
        t1 = t0 + (step + 1) * h
        attachment_kinematics(vs, t1, att)
        for i in range(n):
            for k in range(6):
                ab = (alpha_f * qdd[i, k] - alpha_m * aux[i, k]) / (1.0 - alpha_m)
                Q0[i, k] = q[i, k] + h * qd[i, k] + h * h * (0.5 - beta) * aux[i, k] + h * h * beta * ab
                V0[i, k] = qd[i, k] + h * (1.0 - gamma) * aux[i, k] + h * gamma * ab
                if flags[2] == 1:
                    qp[i, k] = Q0[i, k] + cq * (2.0 * qdd[i, k] - qdd_prev[i, k])   # predictor: linear in time
                else:
                    qp[i, k] = Q0[i, k] + cq * qdd[i, k]      # predictor: A = qdd_n
        for i in range(n):
            for k in range(6):
                q[i, k] = qp[i, k]
        converged = False
        evals = 0
        ws.step_state[0] = 0
        for attempt in range(attempts):
            need_new = flags[0] == 0 or (not reuse) or attempt > 0 or flags[1] > SLOW_STEP
            rn_prev = np.inf
            nfresh = 0
            full = False
            for it in range(maxit):
                if analytic:
                    # the SDE forces alone are kept in Fsde, Msde for a Jacobian at this iterate
                    residual_general(km, att, q, ref, ws, 1.0, mode_dyn, Q0, V0, cq, cv, mask, qd_buf, A_buf, r,
                                     keep_sde, Fsde, Msde)
                else:
                    residual_general(km, att, q, ref, ws, 1.0, mode_dyn, Q0, V0, cq, cv, mask, qd_buf, A_buf, r,
                                     not_frozen, ws.F, ws.M)
                if km.has_sea and attempt == 0 and it == 0:
                    # water kinematics at the predictor, kept for this step's Newton iterations
                    # and Jacobian (the predictor is within O(h^3) of the solution)
                    ws.sea_frozen[0] = 1
                rn = residual_norm(r, cq, mask, length_scale, force_ref)
                stats[1] += 1
                evals += 1
                if not math.isfinite(rn):
                    break
                if rn <= tol:
                    converged = True
                    ws.step_state[0] = 1      # ws holds the evaluation of the converged state
                    break
                stale = min(STALE_ITERATIONS, maxit - 3.0 - it)
                if it > 0 and rn > SLOW_RATE * rn_prev and not (tol > 0.0 and rn < CONTRACTS * rn_prev and
                        stale > 0.0 and math.log(rn / tol) <= stale * math.log(rn_prev / rn)):
                    # slow: a new Jacobian at this iterate, also when this attempt already formed
                    # one (a contact or friction state that changed since makes it wrong; a
                    # stale tangent then cycles where full Newton converges in a few steps);
                    # after MAX_FRESH of them the step is in real trouble unless the residual
                    # still halves every iteration: give up and let the driver halve it (a snap
                    # load or a contact shock needs the smaller step). A slack rope whose
                    # elements go taut and slack again within the step needs 5-6 fresh tangents
                    # at any step size; halving does not help it (docs/theory.md, 'Slack ropes
                    # and Newton')
                    if nfresh >= MAX_FRESH and rn > PROGRESS * rn_prev:
                        break
                    need_new = True
                    # elasto-plastic SDEs (section 8.4.2) at their yield surface switch between
                    # the elastic and the plastic tangent as the iterates move: a Jacobian kept
                    # from one iterate is of the wrong branch at the next, and modified Newton
                    # cycles where full Newton converges in a few iterations; so once in trouble
                    # the attempt forms one at every iterate (docs/theory.md, 'Plastic SDEs and
                    # Newton')
                    if km.has_plastic:
                        full = True
                if full:
                    need_new = True
                if need_new:
                    if analytic:
                        # r, ws, Fsde and Msde hold the evaluation at q (residual_general above)
                        jacobian_analytic_at(km, att, q, ref, ws, 1.0, mode_dyn, Q0, V0, cq, cv, mask, qd_buf, A_buf, r,
                                             qp, rp, hs, length_scale, J, Ks, Kds, T, Fsde, Msde, np.bool_(True))
                    else:
                        jacobian_fd_general(km, att, q, ref, ws, 1.0, mode_dyn, Q0, V0, cq, cv, mask, qd_buf, A_buf,
                                            r, qp, rp, hs, length_scale, J, np.bool_(False), FD_REL_STEP)
                    stats[2] += 1
                    bad = bt_factor_closed(J, Fac, km, ws)
                    if bad >= 0:
                        ws.sea_frozen[0] = 0
                        fail[0] = t1
                        fail[1] = bad
                        fail[2] = Q_JACOBIAN
                        flags[0] = 0
                        return 3
                    flags[0] = 1
                    nfresh += 1
                    need_new = False
                    # the residual is unchanged by forming J; solve with it
                bt_solve_closed(Fac, r, dq, km, ws)
                small = True
                for i in range(n):
                    for k in range(6):
                        q[i, k] -= dq[i, k]
                        typical = length_scale[i] if k < 3 else 1.0
                        if abs(dq[i, k]) > 1e-13 * max(abs(q[i, k]), typical):
                            small = False
                rn_prev = rn
                if small:
                    converged = True
                    break
            if converged:
                break
            if attempt + 1 == attempts:
                break
            if attempt == 0:
                # restart from the (constant-acceleration) predictor with a fresh Jacobian
                for i in range(n):
                    for k in range(6):
                        q[i, k] = Q0[i, k] + cq * qdd[i, k]
            else:
                # then, in a halved step, from the step's start state q_n: both predictors
                # carry the accelerations of a stiff mode (omega h >> 1), large but harmless,
                # over the step into a far iterate. Not at the driver's own step: there it can
                # converge to a far root of the step's equations where the halved step finds
                # the right one (docs/theory.md, 'Slack ropes and Newton')
                for i in range(n):
                    for k in range(6):
                        ab = (alpha_f * qdd[i, k] - alpha_m * aux[i, k]) / (1.0 - alpha_m)
                        q[i, k] = Q0[i, k] - (h * qd[i, k] + h * h * (0.5 - beta) * aux[i, k] + h * h * beta * ab)
        flags[1] = evals
        ws.sea_frozen[0] = 0
        if not converged:
            fail[0] = t1
            fail[1] = -1
            fail[2] = Q_NEWTON
            flags[0] = 0
            return 1
        commit_history(km, ws)
        inv = 1.0 / cq
        for i in range(n):
            for k in range(6):
                A = (q[i, k] - Q0[i, k]) * inv
                anew = (alpha_f * qdd[i, k] + (1.0 - alpha_f) * A - alpha_m * aux[i, k]) / (1.0 - alpha_m)
                qd[i, k] = V0[i, k] + cv * A
                qdd_prev[i, k] = qdd[i, k]
                qdd[i, k] = A
                aux[i, k] = anew
        status = check_state(q, qd, mask, fail, t1)
        if status == 0:
            status = check_ropes(km, ws, fail, t1)      # ws: the converged iterate's evaluation
        if status != 0:
            return status
        nre = rebase(q, qd, ref, km.rfe_kind, REBASE_THRESHOLD, qdd, aux, True)
        if nre > 0:
            flags[2] = 0           # the previous acceleration is in an old chart: skip one extrapolation
        else:
            flags[2] = 1
        stats[3] += nre
        stats[0] += 1
    return 0


def genalpha_parameters(rho_inf: float) -> tuple[float, float, float, float]:
    """Chung-Hulbert parameters (alpha_m, alpha_f, beta, gamma) for a spectral radius rho_inf."""
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, beta, gamma


# ----------------------------------------------------------------------------- explicit

@njit(cache=True)
def rk4_advance(km, vs, att, ws, q, qd, qdd, ref, t0, h, nsteps, mask, k_q, k_v, qs, vs_buf, acc, stats, fail):
    """Classical fixed-step RK4 on (q, qdot); k_q, k_v (4, n, 6) stage buffers."""
    n = q.shape[0]
    for step in range(nsteps):
        t = t0 + step * h
        for st in range(4):
            if st == 0:
                ts = t
                for i in range(n):
                    for k in range(6):
                        qs[i, k] = q[i, k]
                        vs_buf[i, k] = qd[i, k]
            else:
                c = 0.5 * h if st < 3 else h
                ts = t + c
                for i in range(n):
                    for k in range(6):
                        qs[i, k] = q[i, k] + c * k_q[st - 1, i, k]
                        vs_buf[i, k] = qd[i, k] + c * k_v[st - 1, i, k]
            explicit_acceleration(km, vs, att, ws, ts, qs, vs_buf, ref, acc)
            if st == 0:
                # the friction force of the accepted state equals that of its return-mapped anchors
                commit_history(km, ws)
            for i in range(n):
                for k in range(6):
                    k_q[st, i, k] = vs_buf[i, k]
                    k_v[st, i, k] = acc[i, k]
        for i in range(n):
            for k in range(6):
                q[i, k] += h / 6.0 * (k_q[0, i, k] + 2.0 * k_q[1, i, k] + 2.0 * k_q[2, i, k] + k_q[3, i, k])
                qd[i, k] += h / 6.0 * (k_v[0, i, k] + 2.0 * k_v[1, i, k] + 2.0 * k_v[2, i, k] + k_v[3, i, k])
        status = check_state(q, qd, mask, fail, t + h)
        if status == 0:
            status = check_ropes(km, ws, fail, t + h)   # ws: the last stage, at t + h
        if status != 0:
            return status
        stats[3] += rebase(q, qd, ref, km.rfe_kind, REBASE_THRESHOLD, qdd, qdd, False)
        stats[0] += 1
        stats[1] += 4
    explicit_acceleration(km, vs, att, ws, t0 + nsteps * h, q, qd, ref, qdd)
    commit_history(km, ws)
    return 0


# Dormand-Prince 5(4) tableau
_DP_C = np.array([0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0])
_DP_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
])
_DP_B = np.array([35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0])
_DP_E = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
                  -1.0 / 40.0])


@njit(cache=True)
def dp_advance(km, vs, att, ws, q, qd, qdd, ref, t0, t_end, h_in, h_max, rtol, atol, mask, k_q, k_v, qs, vs_buf,
               acc, cA, cB, cC, cE, stats, fail, hout):
    """Adaptive Dormand-Prince 5(4) from t0 to exactly t_end; qdd holds the derivative at
    t0 on entry (FSAL) and at t_end on exit. hout[0] returns the next step size."""
    n = q.shape[0]
    t = t0
    h = min(h_in, t_end - t0)
    for i in range(n):
        for k in range(6):
            k_q[0, i, k] = qd[i, k]
            k_v[0, i, k] = qdd[i, k]
    rejects = 0
    while t < t_end - 1e-14 * max(1.0, abs(t_end)):
        if t + h > t_end:
            h = t_end - t
        for st in range(1, 7):
            for i in range(n):
                for k in range(6):
                    sq = 0.0
                    sv = 0.0
                    for j in range(st):
                        sq += cA[st, j] * k_q[j, i, k]
                        sv += cA[st, j] * k_v[j, i, k]
                    qs[i, k] = q[i, k] + h * sq
                    vs_buf[i, k] = qd[i, k] + h * sv
            explicit_acceleration(km, vs, att, ws, t + cC[st] * h, qs, vs_buf, ref, acc)
            for i in range(n):
                for k in range(6):
                    k_q[st, i, k] = vs_buf[i, k]
                    k_v[st, i, k] = acc[i, k]
        stats[1] += 6
        # the 5th-order solution is the last stage's argument (FSAL): qs, vs_buf
        err = 0.0
        cnt = 0
        for i in range(n):
            for k in range(6):
                if not mask[i, k]:
                    continue
                eq = 0.0
                ev = 0.0
                for j in range(7):
                    eq += cE[j] * k_q[j, i, k]
                    ev += cE[j] * k_v[j, i, k]
                # translations: relative to the element length; angles: to 1 rad
                sq = atol + rtol * (max(abs(q[i, k]), abs(qs[i, k])) + (km.rfe_length[i] if k < 3 else 1.0))
                sv = atol + rtol * max(abs(qd[i, k]), abs(vs_buf[i, k]))
                err += (h * eq / sq) ** 2 + (h * ev / sv) ** 2
                cnt += 2
        err = math.sqrt(err / max(cnt, 1))
        if not math.isfinite(err):
            err = 1e10
        if err <= 1.0:
            commit_history(km, ws)      # the last stage was evaluated at the accepted state
            t += h
            for i in range(n):
                for k in range(6):
                    q[i, k] = qs[i, k]
                    qd[i, k] = vs_buf[i, k]
                    k_q[0, i, k] = k_q[6, i, k]
                    k_v[0, i, k] = k_v[6, i, k]
            status = check_state(q, qd, mask, fail, t)
            if status == 0:
                status = check_ropes(km, ws, fail, t)     # ws: the last stage, the accepted state
            if status != 0:
                return status
            nre = rebase(q, qd, ref, km.rfe_kind, REBASE_THRESHOLD, k_v[0], k_v[0], False)
            if nre > 0:
                stats[3] += nre
                explicit_acceleration(km, vs, att, ws, t, q, qd, ref, acc)
                for i in range(n):
                    for k in range(6):
                        k_q[0, i, k] = qd[i, k]
                        k_v[0, i, k] = acc[i, k]
            stats[0] += 1
            fac = 5.0 if err == 0.0 else min(5.0, max(0.2, 0.9 * err ** -0.2))
            h = min(h * fac, h_max)
            rejects = 0
        else:
            stats[2] += 1
            rejects += 1
            h *= max(0.1, 0.9 * err ** -0.2)
            if h < 1e-14 * max(1.0, abs(t)) or rejects > 50:
                fail[0] = t
                fail[1] = -1
                fail[2] = Q_VELOCITY
                return 2
    for i in range(n):
        for k in range(6):
            qdd[i, k] = k_v[0, i, k]
    hout[0] = h
    return 0
