"""rfesim: Rigid Finite Element dynamics of offshore lines, pipelay and cranes.

    import rfesim
    sc = rfesim.load_scenario("scenarios/cantilever.json")
    res = rfesim.simulate(sc)
    res.line("pipe").tension
"""
__version__ = "0.1.0"

from .errors import CancelledError, RfesimError, ScenarioError, SolverError  # noqa: E402
from .scenario import Scenario, load_scenario  # noqa: E402
from .results import Results, open_results  # noqa: E402
from .api import modes, simulate, statics  # noqa: E402

__all__ = ["Scenario", "load_scenario", "statics", "simulate", "modes", "Results", "open_results",
           "ScenarioError", "SolverError", "CancelledError", "RfesimError", "__version__"]
