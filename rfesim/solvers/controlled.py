"""Generalized-alpha steps with controllers (winches): one compiled step at a time.

Scenes with controllers advance ``solvers.kernels.ga_advance`` ONE step per call, calling
``before_step(km, t_next, h)`` of every controller first (it rewrites model arrays for
t_{n+1}, e.g. the element lengths of a rope being paid out) and ``after_step(km, state,
t_next, h)`` after the step converged (it reads the new state: tension, sheave motion). A
failing step is retried in 2, 4, ... 64 sub-steps, with the state, the committed history
and every controller restored first. Scenes without controllers keep the multi-step
compiled loop of ``solvers.dynamics.run_dynamics``.
"""
from __future__ import annotations

from ..errors import SolverError

MAX_HALVINGS = 6          # a failing step is retried down to h / 2^6
COUPLING_ITERATIONS = 8   # steps redone while a drum winch moves its payout (WinchController.correct)


def advance_controlled(system, st, t_target: float, h: float, step, flags, counters):
    """Advance ``st`` to ``t_target`` in steps of h. ``step(state, t0, h)`` runs one
    compiled step in place and returns its status. Returns (state, status, t_failed):
    status 0 with the state at t_target, or the failing status with the state at the start
    of the step that failed."""
    km = system.km
    controllers = system.controllers
    nsteps = int(round((t_target - st.t) / h))
    t_start = st.t
    for j in range(nsteps):
        t0 = t_start + j * h
        saved = st.copy()
        saved_history = system.history()
        saved_ctrl = [c.save() for c in controllers]
        status = 0
        for level in range(MAX_HALVINGS + 1):
            unbalanced = None       # end of a sub-step whose drum coupling did not balance
            sub = 2 ** level
            hh = h / sub
            if level > 0:
                st = saved.copy()
                system.set_history(saved_history)
                for c, s in zip(controllers, saved_ctrl):
                    c.restore(s)
                flags[0] = 0           # the factorised Jacobian belongs to another step size
                flags[2] = 0           # the previous acceleration may come from the failed attempt
                if flags.shape[0] > 3:
                    flags[3] = 1       # a halved step: a third Newton attempt (kernels.ga_advance)
            for m in range(sub):
                ta = t0 + m * hh
                for c in controllers:
                    c.before_step(km, ta + hh, hh)
                start = st.copy()
                start_history = system.history()
                for _it in range(COUPLING_ITERATIONS):
                    status = step(st, ta, hh)
                    if status != 0:
                        break
                    # a drum winch balances its drum with the tension the step reached; if it
                    # moved its payout, the step is redone from its start (strong coupling)
                    redo = [c.correct(km, hh) for c in controllers if hasattr(c, "correct")]
                    if not any(redo):
                        break
                    counters["coupling_iterations"] = counters.get("coupling_iterations", 0) + 1
                    st = start.copy()
                    system.set_history(start_history)
                    flags[2] = 0
                    if _it == COUPLING_ITERATIONS - 1:
                        # still unbalanced after the last try: the step fails and is halved
                        # (it used to go on from its start, the state just restored)
                        status = 1
                        unbalanced = ta + hh
                        break
                if status != 0:
                    break
                st.t = ta + hh
                for c in controllers:
                    c.after_step(km, st, ta + hh, hh)
            if status == 0:
                if level > 0:
                    counters["step_halvings"] = counters.get("step_halvings", 0) + 1
                    flags[0] = 0
                break
        if flags.shape[0] > 3:
            flags[3] = 0
        if status != 0 and unbalanced is not None:
            # what to change, from the winches that did not settle (constant tension: gain, step, max_speed)
            notes = [n for n in (c.coupling_note(h / 2 ** MAX_HALVINGS) for c in controllers
                                 if hasattr(c, "coupling_note")) if n]
            raise SolverError(f"the winches' coupling to their ropes (drum balance, constant-tension "
                              f"speed) did not settle within {COUPLING_ITERATIONS} tries of a step at "
                              f"h/{2 ** MAX_HALVINGS}" + "".join(f"; {n}" for n in notes),
                              time=unbalanced, quantity="winch drum coupling")
        if status != 0:
            st = saved
            system.set_history(saved_history)
            for c, s in zip(controllers, saved_ctrl):
                c.restore(s)
            return st, status, t0
        st.t = t0 + h
    st.t = t_target
    return st, 0, t_target
