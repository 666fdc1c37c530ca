"""Line-to-line joins: end A of a child line on end B of a parent line (``"attach":
"<parent>:end_b"``), so that a crane is one serial string of absolute-coordinate lines::

    "lines": {"pedestal": {"type": "column", "length": 10, "elements": 10,
                           "end_a": {"attach": "fixed", "position": [0, 0, 0],
                                     "direction": [0, 0, 1], "connection": "clamped"}},
              "boom": {"type": "boom", "length": 30, "elements": 15,
                       "end_a": {"attach": "pedestal:end_b", "connection": "clamped",
                                 "direction": [1, 0, 0.5],
                                 "drives": [{"name": "slewing", "axis": [0, 0, 1],
                                             "angle": [[0, 0], [20, 90]]}]}},
              "rope": {"type": "wire", "length": 20, "elements": 20,
                       "end_a": {"attach": "boom:end_b", "connection": "pinned"},
                       "end_b": {"attach": "payload", "position": [0, 0, 1]}}}

Rules (each broken one is an error naming the field): only end A of a child joins, only
end B of a parent is joined, a parent carries at most one child, no closed loops, end B of
the parent is attached to nothing else, both lines are in the absolute formulation and the
scene has no chains. The compile (rfesim.model.joins) numbers the RFEs of a string
consecutively and adds one joint SDE between them.

A *closing* join closes a loop (a portal's crossbeam onto the other half): end B of a line
on end B of another, ``"end_b": {"attach": "<target>:end_b", "connection": "clamped"}``.
It adds one SDE between the two end RFEs, which are not neighbours; the Jacobian is then
the band plus two off-band blocks (rfesim.solvers.banded.bt_factor_closed), formed from
the analytic tangent only. End B starts at the target's end B (give ``position`` when the
target comes later), the target's end B is free or carries a child, and a closing end
takes no drives, motor, reeving or hinge.
"""
from __future__ import annotations


def join_parent(end) -> str | None:
    """Name of the parent line of an end attached as "<parent>:end_b", else None."""
    attach = getattr(end, "attach", "")
    if not isinstance(attach, str) or ":" not in attach:
        return None
    return attach.partition(":")[0]


def join_strings(sc) -> list[list[str]]:
    """The lines of a validated scenario grouped in serial strings, each from its root (a
    line whose end A is not a join) to its last child; roots in the scenario's order."""
    child_of = {}
    for name, line in sc.lines.items():
        parent = join_parent(line.end_a)
        if parent is not None:
            child_of[parent] = name
    strings = []
    for name, line in sc.lines.items():
        if join_parent(line.end_a) is not None:
            continue
        string = [name]
        while string[-1] in child_of and len(string) <= len(sc.lines):
            string.append(child_of[string[-1]])
        strings.append(string)
    return strings


def check_join_formulations(sc) -> None:
    """Raise FieldError when a joined line (parent or child) is not in the absolute
    formulation (called first by the scenario's formulation checks)."""
    from .schema import FieldError
    for name, line in sc.lines.items():
        parent = join_parent(line.end_a)
        if parent is None or parent not in sc.lines:
            continue
        for who, ln in ((name, line), (parent, sc.lines[parent])):
            if ln.formulation != "absolute":
                raise FieldError(f"lines.{who}.formulation", f"joined lines ('{parent}' -> '{name}') must be in "
                                                             f"the absolute formulation, not {ln.formulation}")


def check_join_references(sc) -> list[tuple[str, str]]:
    """Cross-checks of the joins (see the module text)."""
    errors: list[tuple[str, str]] = []
    children: dict[str, list[str]] = {}
    for name, line, parent, base in _joined_ends(sc, "end_a", "joined to", errors):
        children.setdefault(parent, []).append(name)
        parent_line = sc.lines[parent]
        if parent_line.end_b.attach != "free":
            errors.append((f"lines.{parent}.end_b.attach",
                           f"end B of line '{parent}' carries line '{name}' (a join): it cannot also be attached "
                           f"to '{parent_line.end_b.attach}'"))
        if getattr(sc, "chains", None):
            errors.append((f"{base}.attach", "line-to-line joins are not available in a scene with chains (the "
                                             "mixed chain + line integrator does not know them); model the crane "
                                             "as a string of lines only"))
        if line.end_a.position is not None and parent_line.end_b.position is not None:
            d = sum((a - b) ** 2 for a, b in zip(line.end_a.position, parent_line.end_b.position)) ** 0.5
            if d > 1e-6:
                errors.append((f"{base}.position", f"{list(line.end_a.position)} is {d:.6g} m from end B of line "
                                                   f"'{parent}' {list(parent_line.end_b.position)}: leave it out "
                                                   f"(taken from the parent) or make them agree within 1e-6 m"))
    for parent, kids in children.items():
        if len(kids) > 1:
            errors.append((f"lines.{kids[1]}.end_a.attach",
                           f"line '{parent}' already carries line '{kids[0]}' at its end B: a string is serial, one "
                           f"child per parent"))
    # closed loops: follow the parents from every line
    reported: set[str] = set()
    for name in sc.lines:
        seen = [name]
        cur = name
        while True:
            parent = join_parent(sc.lines[cur].end_a)
            if parent is None or parent not in sc.lines:
                break
            if parent in seen:
                loop = seen[seen.index(parent):]
                if not reported.intersection(loop):
                    reported.update(loop)
                    errors.append((f"lines.{parent}.end_a.attach", "the joins form a closed loop ("
                                   + " -> ".join(list(reversed(loop)) + [loop[-1]]) + "): a string needs a first "
                                   "line whose end A is not a join"))
                break
            seen.append(parent)
            cur = parent
    errors.extend(_check_closures(sc))
    errors.extend(_check_line_leads(sc))
    return errors


def _check_line_leads(sc) -> list[tuple[str, str]]:
    """A rope led along a line (``end_a.reeving.lead`` "<line>:end_a|end_b") pulls that line's
    end with the tension at the sheave: RFEs that are not neighbours, whose coupling only the
    analytic Jacobian carries (rfesim.loads.reeving; the coloured differences mix it into the
    band: 82 of 100 steps of a column crane halved)."""
    errors: list[tuple[str, str]] = []
    integ = sc.analysis.dynamics.integrator
    if getattr(integ, "jacobian", "analytic") == "analytic":
        return errors
    for name, line in sc.lines.items():
        rv = getattr(line.end_a, "reeving", None)
        if rv is not None and ":" in rv.lead:
            errors.append(("analysis.dynamics.integrator.jacobian", f"line '{name}' is led along '{rv.lead}' "
                           f"(lines.{name}.end_a.reeving.lead): the pull there couples RFEs that are not "
                           f"neighbours, which needs the analytic Jacobian"))
    return errors


def _joined_ends(sc, end: str, verb: str, errors: list):
    """(name, line, other line, field path of the end) of every line whose ``end`` joins
    another line that exists and is not itself; the others' errors go to ``errors``."""
    for name, line in sc.lines.items():
        other = join_parent(getattr(line, end))
        if other is None:
            continue
        base = f"lines.{name}.{end}"
        bad = _named_line(sc, name, other, base, verb)
        if bad:
            errors.append(bad)
            continue
        yield name, line, other, base


def _named_line(sc, name: str, other: str, base: str, verb: str) -> tuple[str, str] | None:
    """The error of an end naming an unknown line or its own line's end B, else None."""
    if other not in sc.lines:
        known = ", ".join(n for n in sc.lines if n != name) or "none"
        return f"{base}.attach", f"unknown line '{other}' (other lines: {known})"
    if other == name:
        return f"{base}.attach", f"a line cannot be {verb} its own end B"
    return None


def _check_closures(sc) -> list[tuple[str, str]]:
    """Cross-checks of the closing joins (end B on another line's end B, see the module text)."""
    errors: list[tuple[str, str]] = []
    for name, line, target, base in _joined_ends(sc, "end_b", "closed onto", errors):
        for field in ("drives", "motor", "reeving", "hinge_axis"):
            if getattr(line.end_b, field, None):
                errors.append((f"{base}.{field}", f"a closing join (end B on '{target}:end_b') takes no {field}"))
        if sc.lines[target].end_b.attach != "free" and join_parent(sc.lines[target].end_b) is None:
            errors.append((f"{base}.attach", f"end B of line '{target}' is attached to "
                                             f"'{sc.lines[target].end_b.attach}': close onto a free end B"))
        if getattr(sc, "chains", None):
            errors.append((f"{base}.attach", "line-to-line joins are not available in a scene with chains"))
        for who in (name, target):
            if sc.lines[who].formulation != "absolute":
                errors.append((f"lines.{who}.formulation", f"a closing join ('{name}' -> '{target}') needs both "
                                                           f"lines in the absolute formulation"))
        integ = sc.analysis.dynamics.integrator
        if getattr(integ, "jacobian", "analytic") != "analytic":
            errors.append(("analysis.dynamics.integrator.jacobian", f"line '{name}' closes a loop (end B on "
                           f"'{target}:end_b'): its off-band coupling needs the analytic Jacobian"))
    return errors
