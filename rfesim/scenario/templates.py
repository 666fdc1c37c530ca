"""Templates that expand into ordinary scenario sections before validation: ``pipelay``
(rfesim.scenario.pipelay) and ``cranes`` (rfesim.scenario.cranes)."""
from __future__ import annotations

from . import cranes, pipelay


def expand(data: dict) -> dict:
    """The scenario dict with its ``pipelay`` and ``cranes`` templates expanded (a new dict;
    the input itself when it has neither). Raises ScenarioError naming the template field."""
    return cranes.expand(pipelay.expand(data))
