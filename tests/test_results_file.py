"""The results file (CONTRACT.md "Results file"): netCDF-4/HDF5, one group per object, a
`time` coordinate in s, `units` and `long_name` on every variable from one table, the
scenario JSON and the rfesim version as attributes, atomic writes, exact round trips."""
from __future__ import annotations

import json
import os

import h5py
import numpy as np
import pytest

import rfesim
import rfesim.results as results_module
from rfesim.results import CHANNELS, LINE_CHANNELS

xr = pytest.importorskip("xarray")

ELEMENTS = 10

# a 10-element cantilever clamped to a heaving barge, tip load, no gravity, 1 s of
# generalized-alpha dynamics (no statics: the test does not depend on the Newton solver)
SCENARIO = {
    "schema_version": 1,
    "name": "results-file cantilever",
    "environment": {"gravity": 0.0},
    "vessels": {"barge": {"position": [0.0, 0.0, 0.0],
                          "motion": {"kind": "harmonic", "heave": {"amplitude": 0.1, "period": 2.0}}}},
    "line_types": {"beam": {"EA": 1.0e8, "EIy": 1.0e5, "mass_per_length": 50.0}},
    "lines": {"pipe": {"type": "beam", "length": 10.0, "elements": ELEMENTS,
                       "end_a": {"attach": "barge", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                 "connection": "clamped"},
                       "end_b": {"attach": "free"},
                       "loads": [{"at": "end_b", "force": [0.0, 0.0, -100.0]}]}},
    "analysis": {"statics": {"enabled": False},
                 "dynamics": {"duration": 1.0, "output_interval": 0.05,
                              "integrator": {"kind": "generalized-alpha", "time_step": 0.01, "rho_inf": 0.8}}},
}

# a soft cable under gravity, RK4 with a step far above its stability limit: diverges
DIVERGING = {
    "name": "diverging cable",
    "environment": {"gravity": 9.81},
    "line_types": {"cable": {"EA": 1.0e7, "EIy": 1.0e3, "mass_per_length": 1.0}},
    "lines": {"pipe": {"type": "cable", "length": 10.0, "elements": ELEMENTS,
                       "end_a": {"attach": "fixed", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0],
                                 "connection": "clamped"},
                       "end_b": {"attach": "free"}}},
    "analysis": {"statics": {"enabled": False},
                 "dynamics": {"duration": 5.0, "output_interval": 0.05,
                              "integrator": {"kind": "rk4", "time_step": 0.05}}},
}

# group variable -> CHANNELS key (the vessel group reuses short names)
VESSEL_CHANNEL = {"position": "vessel_position", "rotation": "vessel_rotation"}


@pytest.fixture(scope="module")
def res():
    return rfesim.simulate(SCENARIO)


@pytest.fixture
def written(res, tmp_path):
    path = tmp_path / "run.nc"
    res.to_netcdf(path)
    return path


def test_run_shapes(res):
    nt = len(res.time)
    assert nt == 21
    lr = res.line("pipe")
    assert lr.position.shape == (nt, ELEMENTS + 2, 3)
    assert lr.tension.shape == (nt, ELEMENTS)


def test_xarray_line_group_units_and_values(res, written):
    lr = res.line("pipe")
    with xr.open_dataset(written, engine="h5netcdf", group="lines/pipe") as ds:
        assert set(LINE_CHANNELS) <= set(ds.data_vars)
        for name, var in ds.variables.items():
            assert name in CHANNELS, f"{name} is not in the CHANNELS table"
            units, long_name = CHANNELS[name]
            assert var.attrs.get("units") == units, name
            assert var.attrs.get("long_name") == long_name, name
        assert "time" in ds.coords
        assert ds["time"].attrs["units"] == "s"
        assert ds["time"].dtype == np.float64          # seconds, not decoded to datetimes
        np.testing.assert_array_equal(ds["time"].values, res.time)
        assert ds["position"].dims == ("time", "point", "xyz")
        assert ds["position"].shape == (len(res.time), ELEMENTS + 2, 3)
        for ch in LINE_CHANNELS:
            np.testing.assert_array_equal(ds[ch].values, getattr(lr, ch), err_msg=ch)
        np.testing.assert_array_equal(ds["arc_length"].values, lr.arc_length)
        np.testing.assert_array_equal(ds["sde_arc_length"].values, lr.sde_arc_length)


def test_xarray_vessel_group(res, written):
    vr = res.vessel("barge")
    with xr.open_dataset(written, engine="h5netcdf", group="vessels/barge") as ds:
        for name, var in ds.variables.items():
            units, long_name = CHANNELS[VESSEL_CHANNEL.get(name, name)]
            assert (var.attrs.get("units"), var.attrs.get("long_name")) == (units, long_name), name
        np.testing.assert_array_equal(ds["position"].values, vr.position)
        np.testing.assert_array_equal(ds["rotation"].values, vr.rotation)
        # the heave motion is in the file: 0.1 m amplitude at 2 s period
        assert np.max(np.abs(ds["position"].values[:, 2])) == pytest.approx(0.1, rel=1e-3)


def test_plain_h5py(res, written):
    with h5py.File(written, "r") as f:
        assert "lines/pipe" in f and "vessels/barge" in f
        g = f["lines/pipe"]
        for name in LINE_CHANNELS + ("time", "arc_length", "sde_arc_length"):
            units, long_name = CHANNELS[name]
            attr = g[name].attrs
            assert _text(attr["units"]) == units and _text(attr["long_name"]) == long_name
        np.testing.assert_array_equal(g["position"][()], res.line("pipe").position)
        np.testing.assert_array_equal(g["time"][()], res.time)
        assert _text(f.attrs["rfesim_version"]) == rfesim.__version__


def test_scenario_and_version_attributes(written):
    with h5py.File(written, "r") as f:
        scenario_json = _text(f.attrs["scenario"])
        version = _text(f.attrs["rfesim_version"])
    assert version == rfesim.__version__
    sc = rfesim.load_scenario(json.loads(scenario_json))
    assert sc.name == SCENARIO["name"]
    assert sc.lines["pipe"].elements == ELEMENTS
    assert sc == rfesim.load_scenario(SCENARIO)


def test_open_results_round_trip(res, written):
    back = rfesim.open_results(written)
    assert_same_results(back, res)


def test_write_is_atomic_and_leaves_no_temp_file(res, tmp_path):
    path = tmp_path / "a.nc"
    res.to_netcdf(path)
    res.to_netcdf(path)          # overwrite in place
    assert sorted(os.listdir(tmp_path)) == ["a.nc"]
    assert os.stat(path).st_mode & 0o777 == 0o666 & ~_umask()


def test_failed_write_leaves_no_partial_file(res, tmp_path, monkeypatch):
    real_writer = results_module._write_netcdf

    def failing_writer(results, path):
        real_writer(results, path)  # the whole file is written to the temporary path...
        raise RuntimeError("disk full")  # ...and then the write fails

    monkeypatch.setattr(results_module, "_write_netcdf", failing_writer)
    target = tmp_path / "out.nc"
    with pytest.raises(RuntimeError, match="disk full"):
        res.to_netcdf(target)
    assert os.listdir(tmp_path) == []

    # an existing file at the target is left as it was
    monkeypatch.setattr(results_module, "_write_netcdf", real_writer)
    res.to_netcdf(target)
    before = target.read_bytes()
    monkeypatch.setattr(results_module, "_write_netcdf", failing_writer)
    with pytest.raises(RuntimeError):
        res.to_netcdf(target)
    assert target.read_bytes() == before
    assert os.listdir(tmp_path) == ["out.nc"]


def test_solver_error_results_can_be_written(tmp_path):
    with pytest.raises(rfesim.SolverError) as info:
        rfesim.simulate(DIVERGING)
    exc = info.value
    assert exc.time is not None and exc.time < 5.0
    partial = exc.results
    assert partial is not None and partial.status == 1 and not partial.success
    assert len(partial.time) > 0 and partial.time[-1] < 5.0
    assert np.all(np.isfinite(partial.line("pipe").position))
    assert partial.version == rfesim.__version__ and partial.scenario_json
    path = tmp_path / "partial.nc"
    partial.to_netcdf(path)
    back = rfesim.open_results(path)
    assert_same_results(back, partial)
    with xr.open_dataset(path, engine="h5netcdf", group="lines/pipe") as ds:
        assert ds.sizes["time"] == len(partial.time)


def test_statics_only_results_round_trip(tmp_path):
    data = json.loads(json.dumps(SCENARIO))
    data["analysis"]["dynamics"]["duration"] = 0.0
    res = rfesim.simulate(data)          # statics disabled, no dynamics: the initial state
    assert res.kind == "statics" and len(res.time) == 1
    path = tmp_path / "s.nc"
    res.to_netcdf(path)
    assert_same_results(rfesim.open_results(path), res)


# --------------------------------------------------------------------------- helpers

def _text(x) -> str:
    return x.decode() if isinstance(x, bytes) else str(x)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def assert_same_results(back, res) -> None:
    np.testing.assert_array_equal(back.time, res.time)
    assert back.time.dtype == res.time.dtype
    assert list(back.lines) == list(res.lines)
    for name, lr in res.lines.items():
        lb = back.line(name)
        for ch in LINE_CHANNELS + ("arc_length", "sde_arc_length"):
            a, b = getattr(lb, ch), getattr(lr, ch)
            assert a.shape == b.shape, ch
            np.testing.assert_array_equal(a, b, err_msg=f"{name}.{ch}")
        np.testing.assert_array_equal(lb.top_tension, lr.top_tension)
    assert list(back.vessels) == list(res.vessels)
    for name, vr in res.vessels.items():
        np.testing.assert_array_equal(back.vessel(name).position, vr.position)
        np.testing.assert_array_equal(back.vessel(name).rotation, vr.rotation)
    assert back.status == res.status and isinstance(back.status, int)
    assert back.message == res.message
    assert back.kind == res.kind
    assert back.version == res.version
    assert back.scenario_json == res.scenario_json
    assert back.counters == json.loads(json.dumps(res.counters))


def test_chain_joints_round_trip(tmp_path):
    """The README's double pendulum (0.2 s): /joints/<chain>.<joint> with units by the joint's
    kind (rad for revolute, m for prismatic) and long_name, read back by open_results."""
    pendulum = {"environment": {"gravity": 9.81},
                "chains": {"pendulum": {
                    "links": {"upper": {"rigid": True, "length": 1.0, "mass": 1.0},
                              "lower": {"rigid": True, "length": 1.0, "mass": 1.0},
                              "slider": {"rigid": True, "length": 0.5, "mass": 1.0}},
                    "joints": {"top": {"kind": "revolute", "parent": "base", "child": "upper",
                                       "direction": [0, 0, -1], "axis": [0, 1, 0], "initial": 0.3},
                               "middle": {"kind": "revolute", "parent": "upper", "child": "lower",
                                          "axis": [0, 1, 0]},
                               "slide": {"kind": "prismatic", "parent": "lower", "child": "slider",
                                         "axis": [1, 0, 0], "stiffness": 100.0}}}},
                "analysis": {"statics": {"enabled": False},
                             "dynamics": {"duration": 0.2, "integrator": {"kind": "rk4", "time_step": 0.002}}}}
    res = rfesim.simulate(pendulum)
    top = res.joints["pendulum.top"]
    assert top.kind == "revolute" and top.coordinate[0, 0] == pytest.approx(0.3)
    assert top.coordinate.shape == top.velocity.shape == (len(res.time), 1)
    path = tmp_path / "pendulum.nc"
    res.to_netcdf(path)
    back = rfesim.open_results(path)
    assert sorted(back.joints) == ["pendulum.middle", "pendulum.slide", "pendulum.top"]
    for name, jr in res.joints.items():
        jb = back.joint(name)
        assert jb.kind == jr.kind
        np.testing.assert_array_equal(jb.coordinate, jr.coordinate)
        np.testing.assert_array_equal(jb.rate, jr.rate)
    ds = xr.open_dataset(path, engine="h5netcdf", group="joints/pendulum.top")
    assert ds["coordinate"].attrs["units"] == "rad" and ds["rate"].attrs["units"] == "rad/s"
    assert "revolute" in ds["coordinate"].attrs["long_name"]
    np.testing.assert_array_equal(ds["time"].values, res.time)
    slide = xr.open_dataset(path, engine="h5netcdf", group="joints/pendulum.slide")
    assert slide["coordinate"].attrs["units"] == "m" and slide["rate"].attrs["units"] == "m/s"
    with h5py.File(path, "r") as f:
        assert f["joints/pendulum.middle/coordinate"].shape == (len(res.time), 1)
