"""The km.tug_* arrays of the tugger lines (rfesim.loads.tugger, rfesim.scenario.tuggers)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kinematics import rot_zyx
from ..loads.tugger import KIND_FORCE, KIND_TENSION


@dataclass
class TuggerInfo:
    name: str
    body: str           # "" for a line point
    vessel: str
    index: int          # row of the km.tug_* arrays
    line: str = ""      # the line of a line point, at arc length ``at`` (m) from end A
    at: float = float("nan")


def line_point(model, line: str, at: float) -> tuple[int, np.ndarray]:
    """(RFE, point in its body frame) of the point at arc length ``at`` on a line: the RFE
    whose span holds it (the end RFEs are half elements, rfesim.model.compile), on its axis."""
    li = model.line(line)
    dx = li.dx
    k = int(min(max(math.floor(at / dx + 0.5), 0), li.elements))
    centre = 0.25 * dx if k == 0 else (li.length - 0.25 * dx if k == li.elements else k * dx)
    return li.rfe_start + k, np.array([at - centre, 0.0, 0.0])


def tugger_arrays(sc, model) -> tuple[dict, list[TuggerInfo]]:
    """(km fields, infos) of the scenario's tuggers. An elastic tugger's unstretched length
    is its length at the model's initial state (vessels at t = 0) less pretension over
    stiffness, unless given."""
    tuggers = getattr(sc, "tuggers", {}) or {}
    ng = len(tuggers)
    K = max([len(t.mode.rows()) if t.mode.kind != "elastic" else 1 for t in tuggers.values()] + [1])
    out = dict(tug_rfe=np.zeros(ng, np.int64), tug_att=np.zeros(ng, np.int64), tug_deck=np.zeros((ng, 3)),
               tug_point=np.zeros((ng, 3)), tug_kind=np.zeros(ng, np.int64), tug_t=np.zeros((ng, K)),
               tug_v=np.zeros((ng, K)), tug_count=np.ones(ng, np.int64), tug_k=np.zeros(ng), tug_L0=np.zeros(ng),
               tug_c=np.zeros(ng), has_tuggers=ng > 0)
    if ng == 0:
        return out, []
    from ..model.arrays import new_attachment_state
    from ..vessel_kernel import attachment_kinematics, vessel_spec
    att = new_attachment_state(len(model.attachment_names))
    attachment_kinematics(vessel_spec(model.motions), 0.0, att)
    body_rfe = {b.name: b.rfe for b in model.bodies}
    q0, ref = model.initial.q, model.initial.ref
    infos = []
    for j, (name, tg) in enumerate(tuggers.items()):
        if tg.line is not None:
            i, point = line_point(model, tg.line, tg.at)
        else:
            i, point = body_rfe[tg.body], np.asarray(tg.body_point, float)
        a = model.attachment_names.index(tg.vessel)
        out["tug_rfe"][j] = i
        out["tug_att"][j] = a
        out["tug_deck"][j] = tg.deck_point
        out["tug_point"][j] = point
        if tg.mode.kind in ("tension", "force"):
            rows = np.asarray(tg.mode.rows(), float)
            m = rows.shape[0]
            out["tug_kind"][j] = KIND_TENSION if tg.mode.kind == "tension" else KIND_FORCE
            out["tug_t"][j, :m] = rows[:, 0]
            out["tug_v"][j, :m] = rows[:, 1]
            out["tug_t"][j, m:] = rows[-1, 0]
            out["tug_v"][j, m:] = rows[-1, 1]
            out["tug_count"][j] = m
            if tg.mode.kind == "force" and (tg.mode.length_min is not None or tg.mode.length_max is not None):
                out["tug_k"][j] = tg.mode.stop_stiffness
                out["tug_L0"][j] = tg.mode.length_min or 0.0
                out["tug_c"][j] = tg.mode.length_max or 0.0
        else:
            out["tug_kind"][j] = 1
            out["tug_k"][j] = tg.mode.stiffness
            out["tug_c"][j] = tg.mode.damping
            if tg.mode.length is not None:
                out["tug_L0"][j] = tg.mode.length
            else:
                R = ref.R[i] @ rot_zyx(q0[i, 3], q0[i, 4], q0[i, 5])
                P = ref.X[i] + q0[i, :3] + R @ point
                D = att.p[a] + att.R[a] @ np.asarray(tg.deck_point, float)
                L = float(np.linalg.norm(D - P))
                L0 = L - tg.mode.pretension / tg.mode.stiffness
                if L0 <= 0.0:
                    from ..errors import ScenarioError
                    raise ScenarioError([(f"tuggers.{name}.mode.pretension",
                                          f"{tg.mode.pretension} N stretches the {L:.4g} m line by more than its "
                                          f"length at stiffness {tg.mode.stiffness} N/m")])
                out["tug_L0"][j] = L0
        infos.append(TuggerInfo(name=name, body=tg.body or "", vessel=tg.vessel, index=j, line=tg.line or "",
                                at=float(tg.at) if tg.at is not None else float("nan")))
    return out, infos
