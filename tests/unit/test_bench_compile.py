"""rfesim bench --only compile (--quick: four small kernels): one process against two into
empty caches, its own section (replaced, the rest of the report kept) and its own
benchmarks.json entry."""
import json

from rfesim.bench.run import main
from rfesim.bench.run_compile import MARK_BEGIN, MARK_END, QUICK_KERNELS


def test_compile_section(tmp_path):
    out = tmp_path / "benchmarks.md"
    out.write_text("# Benchmarks\n\nkept text\n")
    (tmp_path / "benchmarks.json").write_text(json.dumps({"crane": {"kept": 1}}))
    assert main(["--only", "compile", "--quick", "--output", str(out)]) == 0
    text = out.read_text()
    assert text.count(MARK_BEGIN) == 1 and text.count(MARK_END) == 1 and "kept text" in text
    raw = json.loads((tmp_path / "benchmarks.json").read_text())
    assert raw["crane"] == {"kept": 1}
    b = raw["compile"]
    one, two = b["runs"]["1"], b["runs"]["2"]
    # the same kernels compiled, into the same number of cache files, either way
    assert one["kernels"] == two["kernels"] == len(QUICK_KERNELS)
    assert one["compiled_files"] == two["compiled_files"] >= len(QUICK_KERNELS)
    assert b["speedup"] == one["wall_time"] / two["wall_time"] > 0.0 and b["workload"] is None
    assert f"| 1 | {len(QUICK_KERNELS)} | {one['compiled_files']} |" in text
    assert "This was a --quick run" in text
