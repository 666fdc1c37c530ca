"""The sea environment: linear waves (regular, irregular, from a record), current, and
vessel motion from RAOs or a CSV file.

* :mod:`rfesim.sea.waves` — dispersion, spectra, wave components (conventions there);
* :mod:`rfesim.sea.current` — current profile;
* :mod:`rfesim.sea.kernel` — ``SeaSpec``, ``sea_spec(environment)`` and the compiled
  ``sea_kinematics_into``;
* :mod:`rfesim.sea.rao` — vessel motion from displacement RAOs;
* :mod:`rfesim.sea.motion_csv` — vessel motion from a CSV time series.

Theory and conventions: ``docs/theory.md``, section "Sea environment". The submodules are
imported on first use (the scenario schema uses the light ones without numba).
"""
import importlib

_EXPORTS = {"SeaSpec": "kernel", "sea_spec": "kernel", "sea_kinematics_into": "kernel",
            "WaveComponents": "waves", "wave_components": "waves", "wave_number": "waves",
            "jonswap_spectrum": "waves", "pierson_moskowitz_spectrum": "waves",
            "CurrentProfile": "current", "current_profile": "current", "RaoVessel": "rao"}

__all__ = sorted(_EXPORTS)


def __getattr__(name):
    if name in _EXPORTS:
        return getattr(importlib.import_module(f".{_EXPORTS[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
