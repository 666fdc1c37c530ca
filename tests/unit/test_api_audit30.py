"""Audit 30, the Python API: rfesim.api.check_model refuses a run whose output would be too
large, Results.to_netcdf's error names the user's path, LineResults.range_graph's error for
an unknown quantity, a diverging run's message."""
from __future__ import annotations

import copy

import pytest

import rfesim
from rfesim import ScenarioError
from rfesim.api import check_model

import scenes


def test_check_model_refuses_too_many_output_times(monkeypatch):
    import rfesim.solvers.dynamics as dynamics

    monkeypatch.setattr(dynamics, "_memory_bytes", lambda: float(2**30))     # a machine of 1 GiB
    sc = copy.deepcopy(scenes.RISER)
    sc["analysis"]["dynamics"].update(duration=1.0e5, output_interval=0.1)
    with pytest.raises(ScenarioError) as info:
        check_model(rfesim.Scenario.model_validate(sc))
    (field, reason), = info.value.errors
    assert field == "analysis.dynamics.output_interval"
    assert reason.startswith("1e+06 output times would store about 2.")
    # without an output interval a fixed step records at most about 10000 output times: fine
    del sc["analysis"]["dynamics"]["output_interval"]
    assert check_model(rfesim.Scenario.model_validate(sc)) == []
    # dynamics off: nothing recorded
    sc["analysis"]["dynamics"].update(output_interval=0.1, enabled=False)
    assert check_model(rfesim.Scenario.model_validate(sc)) == []


# --------------------------------------------------------------------------- Results.to_netcdf

@pytest.fixture(scope="module")
def statics_results():
    return rfesim.statics(rfesim.Scenario.model_validate(scenes.RISER))


def test_to_netcdf_names_the_path_given_when_its_folder_does_not_exist(statics_results, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(FileNotFoundError) as info:
        statics_results.to_netcdf("nodir/x.nc")
    assert info.value.filename == "nodir/x.nc"
    assert str(info.value) == ("[Errno 2] cannot write the results, the folder 'nodir' does not exist: "
                               "'nodir/x.nc'")
    with pytest.raises(IsADirectoryError, match="the path is a folder: 'sub'"):
        (tmp_path / "sub").mkdir()
        statics_results.to_netcdf("sub")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sub"]       # no temporary file left


def test_to_netcdf_names_the_path_given_when_the_folder_is_not_writable(statics_results, tmp_path, monkeypatch):
    import errno
    import os

    import rfesim.results as results

    real_open = os.open

    def refuse(name, *args, **kw):      # a read-only folder (the tests may run as root)
        if str(name).endswith(".tmp"):
            raise PermissionError(errno.EACCES, "Permission denied", name)
        return real_open(name, *args, **kw)

    monkeypatch.setattr(results.os, "open", refuse)
    path = str(tmp_path / "x.nc")
    with pytest.raises(PermissionError) as info:
        statics_results.to_netcdf(path)
    assert info.value.filename == path and ".tmp" not in str(info.value)
    assert f"cannot write the results in the folder '{tmp_path}': Permission denied" in str(info.value)
    monkeypatch.setattr(results.os, "open", real_open)

    def full(res, name):                # the disk filling up in the write
        with open(name, "wb") as f:
            f.write(b"partial")
        raise OSError(errno.ENOSPC, "No space left on device", name)

    monkeypatch.setattr(results, "_write_netcdf", full)
    with pytest.raises(OSError) as info:
        statics_results.to_netcdf(path)
    assert info.value.filename == path and ".tmp" not in str(info.value)
    assert "cannot write the results: No space left on device" in str(info.value)
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------- range_graph, divergence

def test_range_graph_of_an_unknown_quantity_lists_the_ones_it_takes(statics_results):
    line = statics_results.line("riser")
    for bad in ("position_q", "position_xy", "end_b_force", "tensoin"):
        with pytest.raises(ValueError) as info:
            line.range_graph(bad)
        assert str(info.value) == (
            f"range_graph: '{bad}' is not a channel along the line; it takes position_x, position_y, "
            "position_z, tension, shear_force, bend_moment, torque, curvature, seabed_force, von_mises_stress, "
            "utilisation, residual_curvature")
    assert line.range_graph("position_y")["min"].shape == line.arc_length.shape
    assert line.range_graph("seabed_force")["max"].shape == (line.seabed_force.shape[1],)


def test_a_diverging_run_names_what_diverged_once():
    sc = copy.deepcopy(scenes.RISER)     # RK4 at 5x its stability limit (about 0.002 s)
    sc["analysis"]["dynamics"].update(duration=1.0, integrator={"kind": "rk4", "time_step": 0.01})
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(rfesim.Scenario.model_validate(sc))
    text = str(info.value)
    assert text.startswith("the run diverged at t = ")
    assert info.value.quantity == "velocity not finite or runaway"
    assert text.count("not finite or runaway") == 1, text
    assert info.value.results.message.count("not finite or runaway") == 1


def test_ctrl_c_while_the_finished_run_is_put_together_keeps_its_results(monkeypatch):
    """A Ctrl-C after the last step, while simulate builds the results and their warnings,
    used to go out with no results ("nothing written"); the run is complete: they go with it."""
    import rfesim.api as api

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(api, "_dynamic_warnings", interrupted)
    with pytest.raises(KeyboardInterrupt) as info:
        rfesim.simulate(copy.deepcopy(scenes.RISER))
    res = info.value.results
    assert res is not None and res.status == 0
    assert res.time[-1] == pytest.approx(scenes.RISER["analysis"]["dynamics"]["duration"])
    assert len(res.time) == 11
