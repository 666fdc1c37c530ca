"""Generalised-alpha run with the recording inside the compiled loop (one call per chunk of
output intervals instead of one call and a Python recording per output interval).

``ga_run`` advances output interval after output interval with ``ga_advance`` and writes
the outputs of each reached time straight into the recorder's arrays
(rfesim.solvers.dynamics.Recorder): the line channels through the same output kernels
the Python recorder calls (rfesim.model.outputs.record_outputs), and the raw quantities the
recorder turns into body, joint and vessel channels afterwards, a chunk at a time with
numpy (Recorder.finish_rows). The Python recorder (Recorder.record) stays the readable
reference and the path of every scene this kernel does not record (controllers, motors,
tensioners, reels, rollers, tuggers, elasto-plastic pipe); the tests run both and compare.

A failed interval is rolled back (state, history and counters as they were at its start)
and handed to the Python driver, which redoes it in shorter steps (run_dynamics).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from ..loads.drives import drive_table
from ..loads.seabed import seabed_height
from ..model.assemble import evaluate
from ..model.outputs import record_outputs
from ..vessel_kernel import attachment_kinematics
from .kernels import ga_advance

# the order of the SDE channels in RecordArrays.sde and of the end channels in RecordArrays.ends
SDE_ORDER = ("tension", "shear_force", "bend_moment", "torque", "curvature")
END_ORDER = ("end_a_force", "end_b_force", "end_a_moment", "end_b_moment", "end_a_direction", "end_b_direction")
SEL_WIDTH = 21          # per kept RFE: r (3), v (3), acceleration (3), w (3), R row-major (9)
VESSEL_WIDTH = 12       # per vessel attachment: p (3), R row-major (9)


class RecordArrays(NamedTuple):
    """The recorder's arrays the kernel writes (rows = output times)."""
    time: np.ndarray            # (nt,)
    sde: np.ndarray             # (5, nt, nsde) SDE_ORDER
    pos: np.ndarray             # (nt, npts, 3) points of every line, line after line
    ends: np.ndarray            # (6, nt, nlines, 3) END_ORDER
    ia: np.ndarray              # (nlines,) int64: end-A RFE of each line
    ib: np.ndarray              # (nlines,) int64: end-B RFE
    line_ranges: np.ndarray     # (nlines, 5) int64 (rfesim.model.outputs.record_outputs)
    react: np.ndarray           # (n, 6) scratch: constraint reactions
    end_sdes: np.ndarray        # (m,) int64: SDEs whose end loads are kept (joins, then bodies)
    end_F: np.ndarray           # (n, 3) scratch
    end_M: np.ndarray           # (n, 3) scratch
    end_hist: np.ndarray        # (nt, m, 4, 3) sde_end_loads of end_sdes
    sel: np.ndarray             # (nsel,) int64: RFEs whose state is kept (bodies, joins' parent RFEs)
    sel_hist: np.ndarray        # (nt, nsel, SEL_WIDTH)
    body_rfe: np.ndarray        # (nb,) int64
    body_hist: np.ndarray       # (nt, nb, 2): submerged fraction, deck normal force
    vessel_hist: np.ndarray     # (nt, nv, VESSEL_WIDTH) of attachments 1..nv
    drive_hist: np.ndarray      # (nt, ndrive) prescribed drive angles (rad)
    seabed: np.ndarray          # (nt, n) seabed normal force on each RFE
    friction: np.ndarray        # (nt, n, 3) seabed friction force on each RFE
    td_pos: np.ndarray          # (nt, nlines, 3) touchdown point (NaN: none)
    td_arc: np.ndarray          # (nt, nlines) its arc length from end A


@njit(cache=True)
def _history_arrays(ws):
    """The committed history of ws, in the order of rfesim.solvers.system.System.history."""
    return (ws.fric_anchor, ws.fric_anchored, ws.plastic_hist, ws.roller_anchor, ws.roller_anchored, ws.grip_a,
            ws.grip_on, ws.tens_D, ws.tens_time, ws.reel_grip_a, ws.reel_grip_on, ws.reel_D, ws.reel_time)


@njit(cache=True)
def _copy_all(dst, src):
    """dst[k][:] = src[k] for two tuples shaped as _history_arrays (constant indices: the
    members differ in type)."""
    dst[0][:] = src[0]
    dst[1][:] = src[1]
    dst[2][:] = src[2]
    dst[3][:] = src[3]
    dst[4][:] = src[4]
    dst[5][:] = src[5]
    dst[6][:] = src[6]
    dst[7][:] = src[7]
    dst[8][:] = src[8]
    dst[9][:] = src[9]
    dst[10][:] = src[10]
    dst[11][:] = src[11]
    dst[12][:] = src[12]


@njit(cache=True)
def copy_history(ws, hist, save):
    """The committed history of ws (rfesim.solvers.system.System.history) into hist (save
    True) or back from it."""
    live = _history_arrays(ws)
    if save:
        _copy_all(hist, live)
    else:
        _copy_all(live, hist)


@njit(cache=True)
def touchdown_into(km, ws, start, stop, pos, arc):
    """rfesim.solvers.dynamics.touchdown of the line of RFEs start..stop-1: its arc length
    from end A into arc[0] and its position into pos; both left as they are (NaN) when no
    RFE of the line touches the seabed."""
    first = -1
    last = -1
    for j in range(stop - start):
        if ws.contact_length[start + j] > 0.0:
            if first < 0:
                first = j
            last = j
    if first < 0:
        return
    # a line hanging from end A (a pipe laid from a vessel) is searched from end A
    from_a = ws.r[start, 2] > ws.r[stop - 1, 2]
    j = first if from_a else last
    i = start + j
    s_lo = 0.0
    for m in range(j):
        s_lo += km.rfe_length[start + m]
    L = km.rfe_length[i]
    lc = min(ws.contact_length[i], L)
    # the contact part of an RFE starts at its lower end against the seabed plane under its
    # centre (the sign of n . t, n unnormalised: -dz/dx, -dz/dy, 1)
    g = np.zeros(3)
    seabed_height(km.bed_s, km.bed_z, km.bed_dir, ws.r[i, 0], ws.r[i, 1], g)
    dt = ws.R[i, 2, 0] - g[1] * ws.R[i, 0, 0] - g[2] * ws.R[i, 1, 0]
    if from_a:
        off = (0.5 * L - lc) if (dt < 0.0 and lc < L) else -0.5 * L
    else:
        off = (lc - 0.5 * L) if (dt > 0.0 and lc < L) else 0.5 * L
    arc[0] = s_lo + 0.5 * L + off
    for c in range(3):
        pos[c] = ws.r[i, c] + off * ws.R[i, c, 0]


@njit(cache=True)
def record_row(km, att, ws, qdd, k, t, rec):
    """Row k of the recorder at time t from an evaluated workspace: what Recorder.record
    writes for the line channels, and the raw body, joint and vessel quantities."""
    rec.time[k] = t
    s = rec.sde
    record_outputs(km, att, ws, qdd, rec.react, km.sde_length, s[0, k], s[1, k], s[2, k], s[3, k], s[4, k],
                   rec.line_ranges, rec.pos[k], rec.end_sdes, rec.end_F, rec.end_M, rec.end_hist[k])
    # force and moment of a line on its attachment = - constraint force on the end RFE
    E = rec.ends
    for j in range(rec.ia.shape[0]):
        a = rec.ia[j]
        b = rec.ib[j]
        for c in range(3):
            E[0, k, j, c] = -rec.react[a, c]
            E[1, k, j, c] = -rec.react[b, c]
            E[2, k, j, c] = -rec.react[a, 3 + c]
            E[3, k, j, c] = -rec.react[b, 3 + c]
            E[4, k, j, c] = ws.R[a, c, 0]
            E[5, k, j, c] = ws.R[b, c, 0]
    for j in range(rec.sel.shape[0]):
        i = rec.sel[j]
        row = rec.sel_hist[k, j]
        for c in range(3):
            row[c] = ws.r[i, c]
            row[3 + c] = ws.v[i, c]
            row[6 + c] = qdd[i, c]
            row[9 + c] = ws.w[i, c]
            for d in range(3):
                row[12 + 3 * c + d] = ws.R[i, c, d]
    for j in range(rec.body_rfe.shape[0]):
        rec.body_hist[k, j, 0] = ws.sub_frac[rec.body_rfe[j]] if km.has_bodies else 0.0
        rec.body_hist[k, j, 1] = ws.deck_normal[j] if km.has_deck else 0.0
    for j in range(rec.vessel_hist.shape[1]):
        row = rec.vessel_hist[k, j]
        for c in range(3):
            row[c] = att.p[1 + j, c]
            for d in range(3):
                row[3 + 3 * c + d] = att.R[1 + j, c, d]
    if km.has_seabed:
        for i in range(ws.contact_force.shape[0]):
            rec.seabed[k, i] = ws.contact_force[i]
            for c in range(3):
                rec.friction[k, i, c] = ws.friction_force[i, c]
        for j in range(rec.line_ranges.shape[0]):
            touchdown_into(km, ws, rec.line_ranges[j, 0], rec.line_ranges[j, 1], rec.td_pos[k, j],
                           rec.td_arc[k, j:j + 1])
    for j in range(rec.drive_hist.shape[1]):
        cnt = km.drive_count[j]
        rec.drive_hist[k, j] = drive_table(km.drive_t[j, :cnt], km.drive_angle[j, :cnt], km.drive_slope[j, :cnt],
                                           t)[0]


@njit(cache=True)
def ga_run(km, vs, att, ws, q, qd, qdd, aux, ref, t_start, out_dt, k_first, n_out, h, per_out, alpha_m, alpha_f,
           beta, gamma, tol, maxit, reuse, mask, length_scale, force_ref, J, Fac, Q0, V0, r, dq, qd_buf, A_buf, qp,
           rp, hs, flags, stats, fail, analytic, Ks, Kds, T, Fsde, Msde, qdd_prev, save, hist, rec, row0, done):
    """Output intervals k_first .. k_first + n_out - 1 of a generalised-alpha run, each of
    per_out steps of h from t_start + (k - 1) out_dt (as run_dynamics steps them), each
    reached time recorded into row row0 + m of rec. Returns 0, or the status of the interval
    that failed, rolled back: q, qd, qdd, aux, ref, the history and stats as at its start.
    done[0] = intervals completed and recorded. save: (q, qd, qdd, aux, ref.R, ref.X, stats)
    buffers; hist: buffers shaped as System.history()."""
    done[0] = 0
    for m in range(n_out):
        k_out = k_first + m
        t0 = t_start + (k_out - 1) * out_dt
        save[0][:] = q
        save[1][:] = qd
        save[2][:] = qdd
        save[3][:] = aux
        save[4][:] = ref.R
        save[5][:] = ref.X
        save[6][:] = stats
        copy_history(ws, hist, True)
        status = ga_advance(km, vs, att, ws, q, qd, qdd, aux, ref, t0, h, per_out, alpha_m, alpha_f, beta, gamma,
                            tol, maxit, reuse, mask, length_scale, force_ref, J, Fac, Q0, V0, r, dq, qd_buf, A_buf,
                            qp, rp, hs, flags, stats, fail, analytic, Ks, Kds, T, Fsde, Msde, qdd_prev)
        if status != 0:
            q[:] = save[0]
            qd[:] = save[1]
            qdd[:] = save[2]
            aux[:] = save[3]
            ref.R[:] = save[4]
            ref.X[:] = save[5]
            stats[:] = save[6]
            copy_history(ws, hist, False)
            return status
        t = t_start + k_out * out_dt
        # the last step left the evaluation of this very state (Recorder.record)
        if ws.step_state[0] == 1 and abs(att.time[0] - t) <= 1e-9 * max(1.0, abs(t)):
            ws.step_state[0] = 0
        else:
            attachment_kinematics(vs, t, att)
            ws.step_state[0] = 0
            evaluate(km, att, q, qd, ref, ws, 1.0)
        record_row(km, att, ws, qdd, row0 + m, t, rec)
        done[0] = m + 1
    return 0
