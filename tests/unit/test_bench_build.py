"""rfesim bench --only build: a row per bundled scenario, its own section (replaced, not
appended, the rest of the report kept) and its own benchmarks.json entry."""
import json
from pathlib import Path

from rfesim.bench.build import MARK_BEGIN, MARK_END, SWEEP_CASES
from rfesim.bench.run import main

SCENARIOS = sorted(p.name for p in (Path(__file__).resolve().parents[2] / "scenarios").glob("*.json"))


def test_build_section(tmp_path):
    out = tmp_path / "benchmarks.md"
    out.write_text("# Benchmarks\n\nkept text\n")
    (tmp_path / "benchmarks.json").write_text(json.dumps({"crane": {"kept": 1}}))
    for _ in range(2):
        assert main(["--only", "build", "--quick", "--output", str(out)]) == 0
    text = out.read_text()
    assert text.count(MARK_BEGIN) == 1 and text.count(MARK_END) == 1 and "kept text" in text
    rows = [ln for ln in text.splitlines() if ln.startswith("| `")]
    assert [ln.split("`")[1] for ln in rows] == SCENARIOS
    raw = json.loads((tmp_path / "benchmarks.json").read_text())
    assert raw["crane"] == {"kept": 1}
    b = raw["build"]
    assert [r["scenario"] for r in b["rows"]] == SCENARIOS and b["sweep_cases"] == SWEEP_CASES
    assert all(0.0 < r["validate"] < 10.0 and 0.0 < r["build"] < 10.0 for r in b["rows"])
    assert f"A sweep of {SWEEP_CASES} variants" in text
