"""A compiled model with every work buffer allocated once (the ``data`` of model/data)."""
from __future__ import annotations

import numpy as np

from ..model.arrays import check_joint_arrays, new_attachment_state, new_workspace
from ..model.assemble import commit_history, evaluate, solve_accelerations
from ..model.compile import Model, State
from ..vessel_kernel import attachment_kinematics, vessel_spec
from .kernels import jacobian_fd, jacobian_fd_general, residual_q


class System:
    def __init__(self, model: Model):
        self.model = model
        km = model.km
        check_joint_arrays(km)              # rest rotations the kernels would skip: refuse
        n, nsde = model.n, model.nsde
        self.km = km
        self.n = n
        self.ws = new_workspace(n, nsde, model.plastic_history_width, km.roller_attach.shape[0],
                                km.tens_att.shape[0], km.reel_att.shape[0], km.motor_sde.shape[0],
                                km.body_rfe.shape[0], km.tug_rfe.shape[0], km.rv_sde.shape[0], km.cl_sde.shape[0],
                                km.ob_row.shape[0])
        if getattr(model, "initial_plastic_history", None) is not None:
            self.ws.plastic_hist[:] = model.initial_plastic_history     # pipe reeled on before t = 0
        self.vs = vessel_spec(model.motions)
        self.att = new_attachment_state(len(model.attachment_names))
        self.mask = model.dof_mask
        self.length_scale = km.rfe_length.copy()
        z = lambda *s: np.zeros(s)  # noqa: E731
        self.J = z(n, 3, 6, 6)
        self.Fac = z(n, 3, 6, 6)
        self.Q0, self.V0, self.r, self.dq = z(n, 6), z(n, 6), z(n, 6), z(n, 6)
        self.qd_buf, self.A_buf, self.qp, self.rp = z(n, 6), z(n, 6), z(n, 6), z(n, 6)
        self.hs = z(n)
        nsde = max(model.nsde, 1)
        self.Ks, self.Kds = z(nsde, 12, 12), z(nsde, 12, 12)
        self.T, self.Fsde, self.Msde = z(n, 6, 6), z(n, 3), z(n, 3)
        from ..model.winches import make_controllers
        self.controllers = make_controllers(self)     # winches: hooks around every dynamics step
        self.hung_bodies: set[str] = set()   # bodies statics turned to hang (rfesim.solvers.statics.hang_bodies)

    # ------------------------------------------------------------------ history
    def history(self) -> tuple:
        """A copy of the committed history (seabed friction anchors), to roll a step back."""
        ws = self.ws
        return (ws.fric_anchor.copy(), ws.fric_anchored.copy(), ws.plastic_hist.copy(), ws.roller_anchor.copy(),
                ws.roller_anchored.copy(), ws.grip_a.copy(), ws.grip_on.copy(), ws.tens_D.copy(),
                ws.tens_time.copy(), ws.reel_grip_a.copy(), ws.reel_grip_on.copy(), ws.reel_D.copy(),
                ws.reel_time.copy())

    def set_history(self, saved: tuple) -> None:
        ws = self.ws
        ws.fric_anchor[:] = saved[0]
        ws.fric_anchored[:] = saved[1]
        ws.plastic_hist[:] = saved[2]
        ws.roller_anchor[:] = saved[3]
        ws.roller_anchored[:] = saved[4]
        ws.grip_a[:] = saved[5]
        ws.grip_on[:] = saved[6]
        ws.tens_D[:] = saved[7]
        ws.tens_time[:] = saved[8]
        if len(saved) > 9:
            ws.reel_grip_a[:] = saved[9]
            ws.reel_grip_on[:] = saved[10]
            ws.reel_D[:] = saved[11]
            ws.reel_time[:] = saved[12]

    def commit_history(self) -> None:
        """Accept the trial history written by the last evaluation."""
        commit_history(self.km, self.ws)

    def set_friction_mode(self, mode: int) -> None:
        """Seabed friction: 0 stick/slip, 1 fully mobilised towards end A (statics), 2 off."""
        self.ws.fric_mode[0] = mode

    # ------------------------------------------------------------------ evaluations
    def set_time(self, t: float) -> None:
        attachment_kinematics(self.vs, float(t), self.att)

    def evaluate(self, state: State, scale: float = 1.0) -> None:
        self.set_time(state.t)
        self.ws.step_state[0] = 0
        evaluate(self.km, self.att, state.q, state.qd, state.ref, self.ws, float(scale))

    def accelerations(self, state: State) -> np.ndarray:
        """True accelerations of the state (also leaves the workspace evaluated)."""
        self.evaluate(state)
        qdd = np.zeros((self.n, 6))
        solve_accelerations(self.ws, qdd)
        return qdd

    def static_residual(self, q: np.ndarray, ref, scale: float, out: np.ndarray) -> None:
        residual_q(self.km, self.att, q, ref, self.ws, float(scale), 0, self.Q0, self.V0, 1.0, 0.0, self.mask,
                   self.qd_buf, self.A_buf, out)

    def static_jacobian(self, q: np.ndarray, ref, scale: float, r0: np.ndarray) -> np.ndarray:
        jacobian_fd(self.km, self.att, q, ref, self.ws, float(scale), 0, self.Q0, self.V0, 1.0, 0.0, self.mask,
                    self.qd_buf, self.A_buf, r0, self.qp, self.rp, self.hs, self.length_scale, self.J)
        return self.J

    def static_jacobian_analytic(self, q: np.ndarray, ref, scale: float = 1.0) -> np.ndarray:
        """Static Jacobian from the analytic SDE tangent (rfesim.solvers.jacobian)."""
        from .jacobian import jacobian_analytic
        work = np.zeros((self.n, 6))
        jacobian_analytic(self.km, self.att, q, ref, self.ws, float(scale), 0, self.Q0, self.V0, 1.0, 0.0, self.mask,
                          self.qd_buf, self.A_buf, work, self.qp, self.rp, self.hs, self.length_scale, self.J, self.Ks,
                          self.Kds, self.T, self.Fsde, self.Msde)
        return self.J

    @property
    def has_line_leads(self) -> bool:
        """A rope led along a line (reeving with a line-end lead, rfesim.loads.reeving): its pull
        on the lead couples RFEs that are not neighbours."""
        km = self.km
        return bool(km.has_reeving and np.any(km.rv_kind == 1))

    def static_jacobian_hybrid(self, q: np.ndarray, ref, scale: float = 1.0, ropes: bool = False) -> np.ndarray:
        """Static Jacobian from the central differences of ``static_jacobian_accurate`` with
        what the coloured differences cannot take switched off, plus the change of the
        analytic tangent (rfesim.solvers.jacobian) when it is switched on again:

        * closing joins (rfesim.model.joins): the closing SDEs couple RFEs that are not
          neighbours, which the colouring would mix into the band; their off-band blocks are
          left in ws.cl_J. The analytic tangent alone left the A-frame's statics stalling;
        * ropes led along a line (reeving to a line end, rfesim.loads.reeving): the pull on
          the lead (a boom's foot) follows the tension at the sheave (its tip), which the
          colouring mixed into the foot's band (the column crane scenario with the rope
          along the boom did not converge); its off-band blocks are left in ws.ob_J;
        * with ``ropes``, the tension-only SDEs (rfesim.loads.tension_only): the differences
          alone straddle the kink of max(0, C eps): their step (1e-5 of an element length) is
          larger than a light rope's whole stretch (1e-6 m for 100 N on EA = 1e8 N), so a
          rope element near the kink looks half as stiff, slack or taut (docs/theory.md,
          'Slack ropes in statics'); the differences take them elastic in compression too.

        The analytic tangent with everything on comes last, so that ws.cl_J and ws.ob_J hold
        the off-band blocks of the Jacobian returned."""
        km = self.km
        s = km.cl_sde
        saved_k = km.sde_stiffness[s].copy()
        saved_t = km.sde_tension_only.copy()
        km.sde_stiffness[s] = 0.0
        if ropes:
            km.sde_tension_only[:] = 0
        if self.has_line_leads:
            self.km = km._replace(has_reeving=False)
        try:
            off = self.static_jacobian_analytic(q, ref, scale).copy()
            J = self.static_jacobian_accurate(q, ref, scale).copy()
        finally:
            self.km = km
            km.sde_stiffness[s] = saved_k
            km.sde_tension_only[:] = saved_t
        J += self.static_jacobian_analytic(q, ref, scale) - off
        self.J[:] = J
        return self.J

    def static_jacobian_closed(self, q: np.ndarray, ref, scale: float = 1.0) -> np.ndarray:
        """``static_jacobian_hybrid`` of a scene with closing joins (or ropes led along a line)."""
        return self.static_jacobian_hybrid(q, ref, scale)

    def static_jacobian_ropes(self, q: np.ndarray, ref, scale: float = 1.0, closed: bool = False) -> np.ndarray:
        """``static_jacobian_hybrid`` of a scene with ropes (tension-only SDEs) on their exact
        tangent (with the closing joins and ropes led along a line, if any, whatever
        ``closed`` says)."""
        return self.static_jacobian_hybrid(q, ref, scale, ropes=True)

    def static_jacobian_accurate(self, q: np.ndarray, ref, scale: float = 1.0) -> np.ndarray:
        """Central-difference static Jacobian (statics and modal analysis). Central
        differences cancel the second-order change of stiff (axial) springs under lateral
        perturbations, which in forward differences swamps the geometric stiffness of
        nearly inextensible lines."""
        work = np.zeros((self.n, 6))
        jacobian_fd_general(self.km, self.att, q, ref, self.ws, float(scale), 0, self.Q0, self.V0, 1.0, 0.0, self.mask,
                            self.qd_buf, self.A_buf, work, self.qp, self.rp, self.hs, self.length_scale, self.J,
                            True, 1e-5)
        return self.J

    # ------------------------------------------------------------------ scales
    def roundoff_force(self, state: State) -> float:
        """The force resolution of the model (N): the stiffest SDE times the round-off of
        the positions it differences. No residual can be driven below this."""
        km = self.km
        if not self.model.nsde:
            return 0.0
        # SDE gaps difference reference positions and displacements apart (rfesim.loads.sde)
        size = float(np.abs(state.q[:, :3]).max()) + 2.0 * float(km.rfe_length.max())
        return 8.0 * np.finfo(float).eps * size * float(km.sde_stiffness[:, :3].max())

    def force_scale(self, state: State) -> float:
        """A typical force of the scene (N) to judge convergence against: the largest
        element weight or point load; the largest internal force if there are none."""
        km = self.km
        cand = [0.0]
        if km.gravity > 0:
            cand.append(float(km.rfe_mass.max() * km.gravity))
        if km.load_force.size:
            cand.append(float(np.abs(km.load_force).max()))
            cand.append(float(np.abs(km.load_moment).max() / max(km.rfe_length.min(), 1e-12)))
        ref = max(cand)
        if ref == 0.0 and self.model.nsde:
            self.evaluate(state)
            ref = float(np.abs(self.ws.sigma[:, :3]).max())
        return max(ref, 1e-9)
