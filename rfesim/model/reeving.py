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
               rv_rfe=np.zeros(nv, np.int64), rv_point=np.zeros((nv, 3)), has_reeving=nv > 0)
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
    if problems:
        raise ScenarioError(problems)
    return out


def check_dynamics(model) -> None:
    """Refuse a dynamic run with a reeving led to a point of a vessel (or fixed): the run's
    length change as the sheave moves is not given to the hanging rope, so that pull is not
    conservative and a moving frame can flutter (docs/theory.md, 'Reeving'). Statics and a
    lead at a line end (along the boom) are fine."""
    km = model.km
    if not getattr(km, "has_reeving", False) or not np.any(km.rv_kind == KIND_POINT):
        return
    sc = model.scenario
    names = [name for name, ln in (sc.lines or {}).items() if getattr(ln.end_a, "reeving", None) is not None]
    problems = [(f"lines.{name}.end_a.reeving.lead",
                 f"a lead at a point of '{ln.end_a.reeving.lead}' is for statics only: in dynamics the rope's run "
                 f"to it changes length as the sheave moves and that length is not yet given to the hanging "
                 f"rope; lead it along the boom ('<line>:end_a', a crane template's \"reeving\": \"boom\") or "
                 f"run statics alone")
                for name in names for ln in [sc.lines[name]] if ":" not in ln.end_a.reeving.lead]
    raise ScenarioError(problems)
