"""rfesim: Rigid Finite Element dynamics of offshore lines, pipelay and cranes.

    import rfesim
    sc = rfesim.load_scenario("scenarios/cantilever_pipe.json")
    res = rfesim.simulate(sc)
    res.line("pipe").tension
"""
__version__ = "0.1.0"


def _numba_cache_dir() -> None:
    """Keep numba's compiled kernels out of an installed package's folder.

    numba caches next to the source (``__pycache__``); for a package installed into
    site-packages those files outlive ``pip uninstall`` and leave a namespace package
    that shadows a later (editable) install. Unless the user chose a cache folder, use
    ``$XDG_CACHE_HOME/rfesim/numba`` (``~/.cache/...``) when it is writable; a source
    checkout keeps numba's default."""
    import os
    if "NUMBA_CACHE_DIR" in os.environ:
        return
    here = os.path.dirname(os.path.abspath(__file__))
    if "site-packages" not in here and "dist-packages" not in here:
        return
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = os.path.join(base, "rfesim", "numba")
    try:
        os.makedirs(folder, exist_ok=True)
        probe = os.path.join(folder, ".probe")
        with open(probe, "w"):
            pass
        os.unlink(probe)
    except OSError:
        return
    os.environ["NUMBA_CACHE_DIR"] = folder


_numba_cache_dir()


def _kernel_cache_guard() -> None:
    """Drop rfesim's cached kernels when the sources they were compiled from changed
    (rfesim._kernel_cache: numba alone would keep a kernel that inlined an edited one)."""
    import os

    from ._kernel_cache import guard
    guard(os.environ.get("NUMBA_CACHE_DIR") or None)


_kernel_cache_guard()

from .errors import CancelledError, RfesimError, ScenarioError, SolverError, UnsupportedError  # noqa: E402
from .scenario import Scenario, load_scenario  # noqa: E402
from .results import Results, open_results  # noqa: E402
from .api import modes, simulate, statics  # noqa: E402


def precompile(processes: int | None = None) -> int:
    """Compile the numba kernels the shipped scenarios use into numba's cache, in parallel
    processes (default: one per CPU, at most 4; RFESIM_PRECOMPILE sets it, 0: none), rather
    than one by one as a run first calls them: for a fresh install or cache. Returns how many
    kernels it compiled or loaded (docs/theory.md, 'Compiling in parallel')."""
    from ._precompile import precompile as run
    return run(processes)


__all__ = ["Scenario", "load_scenario", "statics", "simulate", "modes", "Results", "open_results",
           "precompile", "ScenarioError", "SolverError", "UnsupportedError", "CancelledError", "RfesimError", "__version__"]
