"""Exceptions raised by rfesim.

`ScenarioError` is raised for bad input and always names the field and the reason.
`SolverError` is raised when a run cannot go on; it says when and where, and it carries
the results computed so far in `.results`; so does `CancelledError` (a progress callback
that raised) when the dynamics had recorded outputs.
"""
from __future__ import annotations


class RfesimError(Exception):
    """Base class of every error rfesim raises on purpose."""


class ScenarioError(RfesimError, ValueError):
    """Bad scenario input.

    `errors` is a list of ``(field_path, reason)`` pairs, where ``field_path`` is a
    dotted path such as ``lines.pipe.elements``.
    """

    def __init__(self, errors, message: str | None = None):
        if isinstance(errors, str):
            errors = [("", errors)]
        self.errors = [(str(f), str(r)) for f, r in errors]
        if message is None:
            message = "; ".join(f"{f}: {r}" if f else r for f, r in self.errors)
        super().__init__(message)

    def __str__(self) -> str:  # one line per error, field first
        if len(self.errors) == 1:
            return super().__str__()
        lines = [f"{len(self.errors)} errors in the scenario:"]
        lines += [f"  {f}: {r}" if f else f"  {r}" for f, r in self.errors]
        return "\n".join(lines)


class SolverError(RfesimError, RuntimeError):
    """A run that could not go on (divergence, NaN, Newton failure).

    Attributes: ``message`` (what failed, without the rest), ``time`` (s), ``element`` (description of where), ``quantity``
    (what went wrong), ``results`` (the Results computed up to the failure, or None),
    ``hint`` (what the state at the failure suggests, or None).
    """

    def __init__(self, message: str, *, time: float | None = None, element: str | None = None,
                 quantity: str | None = None, results=None, hint: str | None = None):
        self.message = message
        self.time = time
        self.element = element
        self.quantity = quantity
        self.results = results
        self.hint = hint
        parts = [message]
        if time is not None:
            parts.append(f"at t = {time:.6g} s")
        if element:
            parts.append(f"in {element}")
        if quantity:
            parts.append(f"({quantity})")
        text = " ".join(parts)
        if hint:
            text += f"; {hint}"
        super().__init__(text)


class UnsupportedError(SolverError):
    """An analysis this installation does not provide for the scene (the modal analysis of a
    scene mixing chains with absolute-coordinate lines): not a failure of the solver. A
    SolverError for callers that catch those; the command line exits with 2 (a missing
    component), not 3."""


class CancelledError(RfesimError):
    """Raised when a progress callback asks a run to stop (it raised an exception, the
    ``__cause__`` of this one).

    Attributes: ``message`` (the text), ``time`` (s, the last output time recorded, or
    None), ``results`` (a cancel during the dynamics: the Results recorded up to the last
    output step, status 3 (CANCELLED), message "cancelled at t = ... s", in every formulation;
    None when nothing was recorded yet, and for a cancel during statics)."""

    def __init__(self, message: str = "cancelled", *, time: float | None = None, results=None):
        self.message = message
        self.time = time
        self.results = results
        super().__init__(message)
