"""Bundled scenarios that read data files (scenarios/data/...) run by name, the path guard
still refuses everything else, and YAML alias bombs are refused before they expand."""
from __future__ import annotations

import json
import os
import time
from pathlib import Path

import pytest

from rfesim.scenario.load import yaml_expansion
from service import validate
from service.settings import Settings
from service_helpers import SCENARIOS, riser

# the bundled examples whose vessel motions are read from scenarios/data/
WITH_DATA_FILES = ("a_frame", "a_frame_deck_winch", "column_crane", "column_crane_liftoff",
                   "column_crane_slewing_motor", "reel_lay", "s_lay_template")
RAOS = Path(os.path.realpath(SCENARIOS / "data" / "barge_100m_raos.json"))
SHORT = {"analysis.dynamics.duration": 0.2, "analysis.dynamics.output_interval": 0.1}


def yaml_bomb() -> bytes:
    """The "billion laughs": 9 nested levels of 9 aliases, about 350 bytes, 9**9 strings."""
    names = "abcdefghi"
    lines = ["a: &a [" + ",".join(['"lol"'] * 9) + "]"]
    lines += [f"{n}: &{n} [" + ",".join([f"*{p}"] * 9) + "]" for p, n in zip(names, names[1:])]
    return ("\n".join(lines) + "\n").encode()


def _file_values(data) -> list[str]:
    if isinstance(data, dict):
        return [v for k, v in data.items() if k == "file"] + [x for v in data.values() for x in _file_values(v)]
    if isinstance(data, list):
        return [x for v in data for x in _file_values(v)]
    return []


def _is_copy_of(value: str, original: Path) -> bool:
    """A file value of a stored scenario names the copy made at submit of ``original``
    (``<data>/inputs/<sha256>/<name>``: a job runs on the files as they were submitted)."""
    copy = Path(value)
    return (copy.parent.parent.name == "inputs" and copy.name == original.name
            and copy.read_bytes() == original.read_bytes())


@pytest.fixture
def settings(tmp_path):
    (tmp_path / "data" / "files").mkdir(parents=True)
    return Settings(data_dir=tmp_path / "data")


def test_the_listed_bundled_scenarios_are_those_with_data_files():
    found = {p.stem for p in SCENARIOS.glob("*.json") if _file_values(json.loads(p.read_text()))}
    assert found == set(WITH_DATA_FILES)


@pytest.mark.parametrize("name", WITH_DATA_FILES)
def test_bundled_scenario_with_data_files_validates_by_name(name, settings):
    stored, sc = validate.prepare_job({"scenario": name, "overrides": SHORT}, settings, SCENARIOS)
    files = _file_values(stored)
    assert files and all(_is_copy_of(f, RAOS) for f in files)
    assert sc.analysis.dynamics.duration == pytest.approx(0.2)
    assert any(v.motion.kind == "rao" for v in sc.vessels.values())


def test_bundled_sweep_with_data_files_validates(settings):
    vary, cases, name = validate.prepare_sweep(
        {"scenario": "s_lay_template", "overrides": SHORT,
         "vary": {"analysis.dynamics.integrator.time_step": [0.05, 0.1]}}, settings, SCENARIOS)
    assert len(cases) == 2
    assert all(_is_copy_of(_file_values(case)[0], RAOS) for _, case in cases)


def test_file_fields_outside_the_data_directory_are_still_refused(settings):
    # overriding a bundled scenario's file: only that bundled file is accepted besides <data>/files
    for bad in ("/etc/passwd", "../../../../../etc/passwd", str(SCENARIOS / "cantilever_pipe.json")):
        with pytest.raises(validate.Invalid) as err:
            validate.prepare_job({"scenario": "a_frame", "overrides": {"vessels.barge.motion.file": bad}},
                                 settings, SCENARIOS)
        loc, msg = err.value.errors[0]
        assert loc == ["vessels", "barge", "motion", "file"]
        assert "must name a file inside the service's data directory" in msg
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_sweep({"scenario": "a_frame", "vary": {"vessels.barge.motion.file": ["/etc/passwd"]}},
                               settings, SCENARIOS)
    assert err.value.errors[0][0] == ["vessels", "barge", "motion", "file"]
    assert "data directory" in err.value.errors[0][1] and "load case" in err.value.errors[0][1]

    # a user's own scenario gets no exception, not even for the bundled data file
    for bad in ("/etc/passwd", "../../etc/passwd", str(RAOS)):
        user = riser()
        user["vessels"]["ship"]["motion"] = {"kind": "rao", "file": bad}
        with pytest.raises(validate.Invalid) as err:
            validate.prepare_job(user, settings, SCENARIOS)
        loc, msg = err.value.errors[0]
        assert loc == ["vessels", "ship", "motion", "file"] and "data directory" in msg, (bad, msg)

    # the same bundled scenario posted as a document: its relative file is read from <data>/files
    doc = json.loads((SCENARIOS / "column_crane.json").read_text())
    with pytest.raises(validate.Invalid) as err:
        validate.prepare_job(doc, settings, SCENARIOS)
    assert "file not found" in err.value.errors[0][1]
    target = settings.resolved_data_dir() / "files" / "data"
    target.mkdir()
    (target / RAOS.name).write_bytes(RAOS.read_bytes())
    stored, _ = validate.prepare_job(doc, settings, SCENARIOS)
    (value,) = _file_values(stored)
    assert _is_copy_of(value, target / RAOS.name)


def test_yaml_alias_bomb_is_refused_before_it_expands():
    bomb = yaml_bomb()
    assert len(bomb) < 400
    start = time.process_time()
    with pytest.raises(validate.Invalid) as err:
        validate.parse_body(bomb, "application/yaml")
    assert time.process_time() - start < 0.5
    (loc, msg), = err.value.errors
    assert loc == ["body"]
    level, expanded = 10, 1 + 9                # the root and its 9 keys; level a: a list of 9 strings
    for _ in range(9):
        expanded += level
        level = 1 + 9 * level
    assert f"expand this document to {expanded} nodes" in msg and expanded > 4 * 10**8
    assert "at most 100000 nodes" in msg and "aliases" in msg

    # a recursive alias is refused too
    with pytest.raises(validate.Invalid, match="recursive structure"):
        validate.parse_body(b"a: &a [1, *a]\n", "application/yaml")
    # one long value repeated by aliases counts its characters
    long = b'a: &a "' + b"x" * 20_000 + b'"\nb: [' + b",".join([b"*a"] * 100) + b"]\n"
    with pytest.raises(validate.Invalid, match="1000000 characters"):
        validate.parse_body(long, "application/yaml")


def test_yaml_with_a_few_aliases_still_parses():
    doc = json.loads(json.dumps(riser()))
    text = ("line_types:\n  pipe: &pipe {outer_diameter: 0.2, wall_thickness: 0.012, youngs_modulus: 2.0e+11,"
            " density: 7850.0, drag_normal: 1.0, added_mass_normal: 1.0}\n  copy: *pipe\n")
    data = validate.parse_body(text.encode(), "application/yaml")
    assert data["line_types"]["copy"] == data["line_types"]["pipe"] == doc["line_types"]["pipe"]
    written_out = text.replace("*pipe", text.split("&pipe ")[1].split("\n")[0])
    assert "*" not in written_out
    assert yaml_expansion(text) == yaml_expansion(written_out)
    assert yaml_expansion(text)[0] == 31


# --------------------------------------------------------------------------- through a server

def test_post_bundled_scenarios_with_data_files_by_name(api):
    ids = {name: api.submit({"scenario": name, "overrides": SHORT}) for name in WITH_DATA_FILES}
    for name, job_id in ids.items():
        job = api.wait(job_id, timeout=300.0)
        assert job["status"] == "done", (name, job)
        stored = api.client.get(f"/jobs/{job_id}/scenario").json()
        assert all(_is_copy_of(f, RAOS) for f in _file_values(stored))

    # (a path both overridden and varied is refused: the varied values would replace the override)
    r = api.client.post("/sweeps", json={"scenario": "column_crane",
                                         "overrides": {"analysis.dynamics.output_interval": 0.1},
                                         "vary": {"analysis.dynamics.duration": [0.1, 0.2]}})
    assert r.status_code == 202, r.text
    assert len(r.json()["jobs"]) == 2

    r = api.client.post("/jobs", json={"scenario": "column_crane",
                                       "overrides": {"vessels.barge.motion.file": "/etc/passwd"}})
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["vessels", "barge", "motion", "file"]
    assert "data directory" in r.json()["detail"][0]["msg"]


def test_library_refuses_the_alias_bomb_in_a_local_file(tmp_path):
    """rfesim.load_scenario (and so `rfesim check|run`) of a local YAML file is capped too."""
    import rfesim

    path = tmp_path / "bomb.yaml"
    path.write_bytes(yaml_bomb())
    start = time.process_time()
    with pytest.raises(rfesim.ScenarioError, match="rfesim accepts at most 100000 nodes"):
        rfesim.load_scenario(path)
    assert time.process_time() - start < 0.5


def test_post_yaml_alias_bomb_is_answered_quickly(api):
    start = time.monotonic()
    r = api.client.post("/jobs", content=yaml_bomb(), headers={"content-type": "application/yaml"})
    elapsed = time.monotonic() - start
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["body"]
    assert "YAML aliases" in r.json()["detail"][0]["msg"] and "at most 100000 nodes" in r.json()["detail"][0]["msg"]
    assert elapsed < 5.0
    assert api.client.get("/health").status_code == 200


def test_a_wheel_installs_every_bundled_scenario_where_the_service_looks(tmp_path, monkeypatch):
    """A wheel used to carry no scenarios/: GET /scenarios of a pip-installed service gave []
    and every by-name example of docs/service.md failed. pyproject's data-files put them in
    <prefix>/share/rfesim/scenarios (and its data/), the last place find_scenarios_dir looks;
    every file of scenarios/ must be matched, so a new subfolder is not left out."""
    import shutil
    import sys
    import tomllib
    from pathlib import Path

    import rfesim
    from service.paths import find_scenarios_dir

    root = Path(__file__).resolve().parents[2]
    data_files = tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]["data-files"]
    installed = {f.relative_to(root).as_posix(): target for target, patterns in data_files.items()
                 for p in patterns for f in root.glob(p) if f.is_file()}
    bundled = {f.relative_to(root).as_posix() for f in (root / "scenarios").rglob("*") if f.is_file()
               and "__pycache__" not in f.parts}
    assert bundled and set(installed) == bundled
    prefix = tmp_path / "prefix"
    for rel, target in installed.items():      # install them as pip does, the layout kept
        (prefix / target).mkdir(parents=True, exist_ok=True)
        shutil.copy(root / rel, prefix / target)
    site = tmp_path / "site" / "rfesim"         # a package with no scenarios/ beside it
    site.mkdir(parents=True)
    monkeypatch.setattr(rfesim, "__file__", str(site / "__init__.py"))
    monkeypatch.setattr(sys, "prefix", str(prefix))
    monkeypatch.chdir(tmp_path)
    found = find_scenarios_dir()
    assert found == (prefix / "share" / "rfesim" / "scenarios").resolve()
    assert (found / "column_crane.json").is_file() and (found / "data" / "barge_100m_raos.json").is_file()
