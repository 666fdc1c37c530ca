"""Scenario schema and loading (pydantic v2, JSON and YAML)."""
from .schema import Scenario
from .load import load_scenario, check_references, validate_dict, apply_overrides, parse_text
from .templates import expand

__all__ = ["Scenario", "load_scenario", "check_references", "validate_dict", "apply_overrides", "parse_text", "expand"]
