"""The runs whose numba kernels ``python -m rfesim._precompile --record`` lists: every shipped
scenario through statics and a few steps of dynamics, the example riser with each integrator
and Jacobian, its modes, and the results written and summarised (what ``rfesim run``,
``rfesim sweep`` and the service's workers call)."""
from __future__ import annotations

import os
import tempfile

SCENARIOS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scenarios")
STEPS = 3                      # time steps of dynamics per run: every kernel of a step is reached


def _short(sc, steps: int = STEPS):
    dyn = sc.analysis.dynamics
    dt = getattr(dyn.integrator, "time_step", None) or 0.01 / steps    # explicit: a few of their steps
    dyn.duration = steps * dt
    dyn.output_interval = dt
    return sc


def runs() -> list[tuple[str, object]]:
    """(label, callable) of each run."""
    import rfesim

    out = []
    names = sorted(n for n in os.listdir(SCENARIOS) if n.endswith(".json"))
    for name in names:
        path = os.path.join(SCENARIOS, name)
        out.append((f"simulate {name}", lambda path=path: rfesim.simulate(_short(rfesim.load_scenario(path)))))
    riser = os.path.join(SCENARIOS, "catenary_riser.json")
    integrators = [{"kind": "rk4"}, {"kind": "adaptive"},
                   {"kind": "generalized-alpha", "time_step": 0.05, "jacobian": "finite-difference"}]
    for integ in integrators:
        out.append((f"simulate catenary_riser.json {integ['kind']}",
                    lambda integ=integ: rfesim.simulate(_short(rfesim.load_scenario(
                        riser, overrides={"analysis.dynamics.integrator": integ})))))
    for name in ("catenary_riser.json", "column_crane.json", "s_lay.json"):
        path = os.path.join(SCENARIOS, name)
        out.append((f"modes {name}", lambda path=path: rfesim.modes(rfesim.load_scenario(path), n=3)))

    def write():
        from rfesim.sweep import summarize
        res = rfesim.simulate(_short(rfesim.load_scenario(riser)))
        summarize(res)
        with tempfile.TemporaryDirectory() as tmp:
            res.to_netcdf(os.path.join(tmp, "out.nc"))
    out.append(("results of catenary_riser.json", write))
    return out


def run_all(verbose: bool = True) -> list[str]:
    """Run every workload; returns the labels of those that failed (with the reason)."""
    import time
    failed = []
    for label, fn in runs():
        t0 = time.perf_counter()
        try:
            fn()
        except Exception as exc:   # recorded and reported: the record is then incomplete
            failed.append(f"{label}: {type(exc).__name__}: {exc}")
        if verbose:
            print(f"{time.perf_counter() - t0:8.1f} s  {label}", flush=True)
    return failed
