"""The km.rv_* arrays of the reevings (rfesim.loads.reeving, ``lines.<rope>.end_a.reeving``)."""
from __future__ import annotations

import numpy as np

from ..errors import ScenarioError
from ..loads.reeving import KIND_LINE_END, KIND_POINT


def reeving_arrays(sc, model) -> dict:
    """km fields of the scenario's reevings (one per line whose end A has ``reeving``)."""
    ropes = [(name, ln.end_a.reeving) for name, ln in (sc.lines or {}).items()
             if getattr(ln.end_a, "reeving", None) is not None]
    nv = len(ropes)
    out = dict(rv_sde=np.zeros(nv, np.int64), rv_kind=np.zeros(nv, np.int64), rv_att=np.zeros(nv, np.int64),
               rv_rfe=np.zeros(nv, np.int64), rv_point=np.zeros((nv, 3)), rv_slip=np.zeros(nv, np.int64),
               rv_len=np.zeros(nv), rv_arm_written=np.full(nv, np.nan), rv_arm_offset=np.zeros(nv),
               has_reeving=nv > 0)
    join_of = {ji.child: ji for ji in model.joins}
    lines = {li.name: li for li in model.lines}
    problems = []
    for j, (name, rv) in enumerate(ropes):
        field = f"lines.{name}.end_a.reeving.lead"
        ji = join_of.get(name)
        if ji is None:
            problems.append((f"lines.{name}.end_a.reeving", "reeving runs from a sheave: a pinned join of an "
                                                             "absolute line ('<line>:end_b')"))
            continue
        out["rv_sde"][j] = ji.sde
        if ":" in rv.lead:
            lname, _, end = rv.lead.partition(":")
            li = lines.get(lname)
            if li is None:
                known = ", ".join(sorted(lines)) or "none"
                problems.append((field, f"unknown line '{lname}' (absolute lines: {known})"))
                continue
            if lname == name:
                problems.append((field, "the rope cannot lead to its own end: name the line it runs along"))
                continue
            i = li.rfe_start if end == "end_a" else li.rfe_stop - 1
            half = 0.5 * float(model.km.rfe_length[i])
            out["rv_kind"][j] = KIND_LINE_END
            out["rv_rfe"][j] = i
            out["rv_point"][j] = [-half if end == "end_a" else half, 0.0, 0.0]
            if i == ji.parent_rfe and end == "end_b":
                problems.append((field, f"'{rv.lead}' is the sheave itself: lead the rope elsewhere"))
        else:
            if rv.lead not in model.attachment_names:
                known = ", ".join(n for n in model.attachment_names)
                problems.append((field, f"unknown vessel '{rv.lead}' (a vessel name, \"fixed\" or a line end; "
                                        f"attachments: {known})"))
                continue
            out["rv_kind"][j] = KIND_POINT
            out["rv_att"][j] = model.attachment_names.index(rv.lead)
            out["rv_point"][j] = rv.point
            # the rope slips over the sheave as the run changes length (rfesim.loads.reeving):
            # measured from the run at the initial positions (vessels at t = 0)
            out["rv_slip"][j] = 1
            out["rv_len"][j] = _run_length(model, ji, out["rv_att"][j], out["rv_point"][j])
    if problems:
        raise ScenarioError(problems)
    out.update(_offband_blocks(model, out))
    return out


def _offband_blocks(model, rv: dict) -> dict:
    """km.ob_row, ob_col, has_offband: the Jacobian blocks of the line-end leads' pulls whose
    RFEs are not neighbours (rfesim.loads.reeving.reeving_tangent: rows the sheave's RFE a and
    the lead's f, columns a, the rope's first b and f; a boom's foot against its tip)."""
    km = model.km
    pairs: list[tuple[int, int]] = []
    for j in range(rv["rv_sde"].shape[0]):
        if rv["rv_kind"][j] != KIND_LINE_END:
            continue
        s = int(rv["rv_sde"][j])
        a, b, f = int(km.sde_left[s]), int(km.sde_right[s]), int(rv["rv_rfe"][j])
        for i in (a, f):
            for k in (a, b, f):
                if abs(i - k) > 1 and (i, k) not in pairs:
                    pairs.append((i, k))
    return dict(ob_row=np.array([p[0] for p in pairs], np.int64), ob_col=np.array([p[1] for p in pairs], np.int64),
                has_offband=bool(pairs))


def _run_length(model, ji, att_index: int, point: np.ndarray) -> float:
    """Length (m) of the run from the sheave (the parent's end of the join SDE) to a lead
    on an attachment, at the model's initial state with the attachments at t = 0."""
    from ..kinematics import rot_zyx
    from ..vessel_kernel import attachment_kinematics, vessel_spec
    from .arrays import new_attachment_state
    att = new_attachment_state(len(model.attachment_names))
    attachment_kinematics(vessel_spec(model.motions), 0.0, att)
    q0, ref = model.initial.q, model.initial.ref
    a = ji.parent_rfe
    R = ref.R[a] @ rot_zyx(q0[a, 3], q0[a, 4], q0[a, 5])
    P = ref.X[a] + q0[a, :3] + R @ model.km.sde_arm_left[ji.sde]
    L = att.p[att_index] + att.R[att_index] @ np.asarray(point, float)
    return float(np.linalg.norm(L - P))
