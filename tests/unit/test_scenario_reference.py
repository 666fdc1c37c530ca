"""The scenario reference page docs/scenario.md (rfesim.scenario.reference, `rfesim schema`):
up to date with the schema, every field of every object and variant listed once, with its
unit, default, bounds and the schema's own description; every number of the schema with a
unit, written once in its metadata and at the end of its description, every object with a
description, and the times of every time table said to increase."""
from __future__ import annotations

import difflib
import json
import re
from collections import Counter
from pathlib import Path

import pytest

import rfesim
from rfesim.cli import main
from rfesim.scenario.reference import REGENERATE, scenario_reference_markdown

PAGE = Path(__file__).resolve().parents[2] / "docs" / "scenario.md"
COLUMNS = ["field", "type", "unit", "default", "bounds", "required", "description"]


@pytest.fixture(scope="module")
def generated() -> str:
    return scenario_reference_markdown()


@pytest.fixture(scope="module")
def schema() -> dict:
    return rfesim.Scenario.model_json_schema()


def cells(line: str) -> list[str]:
    """The cells of a Markdown table row, split at the pipes that are not escaped."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]


def unescape(text: str) -> str:
    """The text a reader sees of a cell: Markdown escapes and &lt; undone."""
    return re.sub(r"\\([\\*_|])", r"\1", text).replace("&lt;", "<")


def tables(page: str) -> list[tuple[str, str, list[dict]]]:
    """(heading, heading's path, rows as dicts by column) of every table, in page order."""
    out, heading, path = [], None, None
    for line in page.splitlines():
        if line.startswith("#"):
            heading = line
            m = re.match(r"#+ `([^`]*)`", line)
            path = m.group(1) if m else ""
            continue
        if line.startswith("| field |"):
            assert cells(line) == COLUMNS
            out.append((heading, path, []))
        elif line.startswith("| `"):
            row = cells(line)
            assert len(row) == len(COLUMNS), f"a row of {len(row)} cells (an unescaped '|'?): {line}"
            out[-1][2].append(dict(zip(COLUMNS, row)))
    return out


def table(page: str, path: str, variant: str | None = None) -> dict[str, dict]:
    """The rows (by field path) of the one table of ``path`` (and ``variant``, e.g. 'kind: "jonswap"')."""
    found = [rows for heading, p, rows in tables(page)
             if p == path and (variant is None or f"(`{variant}`)" in heading)]
    assert len(found) == 1, f"{len(found)} tables of {path} {variant or ''}"
    return {r["field"].strip("`"): r for r in found[0]}


def unit_label(units: str) -> str:
    """A unit as a description ends with it in brackets: ``1`` (dimensionless) as ``-``."""
    return ", ".join("-" if c.strip() == "1" else c for c in units.split(", "))


def holds_numbers(node) -> bool:
    """True when a property's schema takes a number somewhere (a number, a list or table of
    numbers, a number-or-table, a map of numbers); a fixed value (``const``) is no quantity."""
    if not isinstance(node, dict) or "const" in node:
        return False
    if node.get("type") in ("number", "integer"):
        return True
    alternatives = [a for key in ("anyOf", "oneOf", "prefixItems") for a in node.get(key, [])]
    inner = [node[key] for key in ("items", "additionalProperties") if isinstance(node.get(key), dict)]
    return any(holds_numbers(a) for a in alternatives + inner)


def properties(schema: dict):
    """(model name, field name, property schema) of the top level and of every definition."""
    for model, definition in [("Scenario", schema)] + list(schema["$defs"].items()):
        for name, prop in definition.get("properties", {}).items():
            yield model, name, prop


# a unit written in a description's text: "(m)", "(deg)", "(-)", "[t s, ...", "t s" ("(s)" after a
# word is a plural)
UNIT_IN_TEXT = re.compile(r"(?<![A-Za-z])\((?:s|m|N|deg|rad|Pa|kg|m/s|rad/s|N\*m|-)\)|\[\[t s|\bt s\b|\[-\]")


def reachable_definitions(schema: dict) -> list[str]:
    """The $defs a scenario can hold, found by following every $ref from the top."""
    defs, seen = schema["$defs"], []

    def visit(node):
        if isinstance(node, dict):
            ref = node.get("$ref")
            if ref is not None:
                name = ref.rsplit("/", 1)[-1]
                if name not in seen:
                    seen.append(name)
                    visit(defs[name])
            for key, value in node.items():
                if key != "$defs":
                    visit(value)
        elif isinstance(node, list):
            for value in node:
                visit(value)

    visit(schema)
    return seen


# --------------------------------------------------------------------------- the page

def test_docs_page_is_the_generated_reference(generated):
    page = PAGE.read_text(encoding="utf-8")
    if page != generated:
        diff = "\n".join(list(difflib.unified_diff(page.splitlines(), generated.splitlines(), "docs/scenario.md",
                                                   "generated", lineterm=""))[:40])
        pytest.fail(f"docs/scenario.md is stale: it differs from the reference generated from the scenario schema "
                    f"(the schema changed without regenerating the page, or the page was edited by hand). "
                    f"Run `{REGENERATE}` and commit the result.\n{diff}")
    assert REGENERATE in page


def test_every_field_of_every_object_and_variant_once(generated, schema):
    # counted from the plain JSON Schema: the top level and each object model it can hold
    defs = reachable_definitions(schema)
    expected = [tuple(sorted(schema["properties"]))] + [tuple(sorted(schema["$defs"][d]["properties"]))
                                                        for d in defs]
    listed = []
    for heading, path, rows in tables(generated):
        names = []
        for row in rows:
            field = row["field"].strip("`")
            prefix = f"{path}." if path else ""
            assert field.startswith(prefix), f"{field} under {heading}"
            name = field[len(prefix):]
            assert "." not in name and "[" not in name, f"{field} under {heading}"
            names.append(name)
        duplicated = [n for n, k in Counter(names).items() if k > 1]
        assert not duplicated, f"{heading}: {duplicated} listed twice"
        listed.append(tuple(sorted(names)))
    assert sorted(listed) == sorted(expected)
    assert sum(len(t) for t in listed) == sum(len(t) for t in expected)
    assert len(defs) > 70 and sum(len(t) for t in expected) > 500       # the walk reached the whole schema


def test_jonswap_fields_under_their_variant(generated, schema):
    jonswap = table(generated, "environment.water.waves", 'kind: "jonswap"')
    hs = jonswap["environment.water.waves.hs"]
    assert hs["unit"] == "`m`"
    assert hs["required"] == "yes" and hs["default"] == "—"
    assert hs["bounds"] == "> 0, ≤ 1e+07"
    assert unescape(hs["description"]) == schema["$defs"]["JonswapWaves"]["properties"]["hs"]["description"]
    assert jonswap["environment.water.waves.kind"]["type"] == '`"jonswap"`'
    # gamma and the spectral widths are JONSWAP's own: not under Pierson-Moskowitz nor Airy
    for field in ("gamma", "sigma_a", "sigma_b"):
        assert f"environment.water.waves.{field}" in jonswap
        assert f"environment.water.waves.{field}" not in table(generated, "environment.water.waves",
                                                               'kind: "pierson-moskowitz"')
        assert f"environment.water.waves.{field}" not in table(generated, "environment.water.waves", 'kind: "airy"')
    airy = table(generated, "environment.water.waves", 'kind: "airy"')
    assert "environment.water.waves.hs" not in airy and airy["environment.water.waves.height"]["unit"] == "`m`"
    assert jonswap["environment.water.waves.components"]["default"] == "`200`"
    assert jonswap["environment.water.waves.components"]["bounds"] == "≥ 1, ≤ 20000"


def test_required_and_optional_fields(generated):
    current = table(generated, "environment.water.current")
    assert current["environment.water.current.profile"]["required"] == "yes"
    assert current["environment.water.current.profile"]["default"] == "—"
    assert current["environment.water.current.profile"]["type"] == "at least 1 row of 2 numbers"
    assert current["environment.water.current.profile"]["unit"] == "`m, m/s`"
    assert current["environment.water.current.direction_deg"]["required"] == "no"
    assert current["environment.water.current.direction_deg"]["default"] == "`0.0`"
    line = table(generated, "lines.<name>")
    assert line["lines.<name>.type"]["required"] == "yes"
    assert line["lines.<name>.length"]["required"] == "yes"


def test_pipelay_method_lists_the_three_templates(generated):
    top = table(generated, "")
    methods = re.findall(r'\[`"([a-z-]+)"`\]', top["pipelay"]["type"])
    assert methods == ["s-lay", "j-lay", "reel-lay"]
    assert top["pipelay"]["type"].startswith("map: name → object by `method`")
    for method in methods:
        rows = table(generated, "pipelay.<name>", f'method: "{method}"')
        assert rows["pipelay.<name>.method"]["type"] == f'`"{method}"`'
        assert rows["pipelay.<name>.method"]["required"] == "yes"
    # the stinger belongs to S-lay, the reel to reel-lay, the tower angle to J-lay
    assert "pipelay.<name>.stinger" in table(generated, "pipelay.<name>", 'method: "s-lay"')
    assert "pipelay.<name>.stinger" not in table(generated, "pipelay.<name>", 'method: "j-lay"')
    assert "pipelay.<name>.reel" in table(generated, "pipelay.<name>", 'method: "reel-lay"')
    assert "pipelay.<name>.tower_angle_deg" in table(generated, "pipelay.<name>", 'method: "j-lay"')


def test_default_factories_are_shown_as_the_input_they_stand_for(generated):
    # pydantic leaves default factories out of the JSON Schema; the page shows them as the
    # smallest input that gives the same default
    vessel = table(generated, "vessels.<name>")
    assert vessel["vessels.<name>.motion"]["default"] == '`{"kind": "fixed"}`'
    assert rfesim.Scenario.model_validate({"vessels": {"v": {}}}).vessels["v"].motion.kind == "fixed"
    line_type = table(generated, "line_types.<name>")
    assert line_type["line_types.<name>.material"]["default"] == '`{"kind": "elastic"}`'
    dynamics = table(generated, "analysis.dynamics")
    assert dynamics["analysis.dynamics.integrator"]["default"] == '`{"kind": "generalized-alpha"}`'
    assert rfesim.Scenario.model_validate({}).analysis.dynamics.integrator.kind == "generalized-alpha"
    assert table(generated, "")["lines"]["default"] == "`{}`"


def test_descriptions_are_the_schemas_own(generated, schema):
    # every description cell reads as the schema's text (escapes undone, lines joined)
    defs = schema["$defs"]
    by_props = {}
    for d in reachable_definitions(schema):
        by_props.setdefault(tuple(sorted(defs[d]["properties"])), []).append(defs[d])
    by_props.setdefault(tuple(sorted(schema["properties"])), []).append(schema)
    checked = 0
    for heading, path, rows in tables(generated):
        prefix = f"{path}." if path else ""
        names = tuple(sorted(r["field"].strip("`")[len(prefix):] for r in rows))
        candidates = by_props[names]
        for row in rows:
            name = row["field"].strip("`")[len(prefix):]
            texts = {" ".join(c["properties"][name].get("description", "").split("\n")) for c in candidates}
            assert unescape(row["description"]) in texts, (heading, name)
            checked += 1
    assert checked > 500
    # a unit with '*' is not read as emphasis
    eiy = table(generated, "line_types.<name>")["line_types.<name>.EIy"]
    assert eiy["description"].endswith("[N\\*m^2]") and eiy["unit"] == "`N*m^2`"


def test_links_lead_to_anchors(generated):
    anchors = re.findall(r'<a id="([^"]+)"></a>', generated)
    assert len(anchors) == len(set(anchors))
    targets = set(re.findall(r"\]\(#([^)]+)\)", generated))
    assert targets and targets <= set(anchors)
    # a model met again links to where it is listed: a crane's vessel to vessels.<name>
    crane = table(generated, "cranes.<name>", 'type: "column"')
    assert "[object, as `vessels.<name>`](#vessels-name)" in crane["cranes.<name>.vessel"]["type"]


def test_deterministic(generated):
    assert scenario_reference_markdown() == generated


# --------------------------------------------------------------------------- the command

def test_cli_schema_markdown_prints_the_page(generated, capsys):
    assert main(["schema", "--markdown"]) == 0
    assert capsys.readouterr().out == generated


def test_cli_schema_json_prints_the_json_schema(schema, capsys):
    assert main(["schema"]) == 0
    assert json.loads(capsys.readouterr().out) == schema
    assert main(["schema", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == schema


def test_cli_schema_output_file(generated, tmp_path, capsys):
    out = tmp_path / "scenario.md"
    assert main(["schema", "--markdown", "-o", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == generated
    assert capsys.readouterr().err.strip() == f"scenario reference written to {out}"
    assert main(["schema", "--markdown", "-o", str(tmp_path / "no" / "scenario.md")]) == 1
    assert "error: could not write" in capsys.readouterr().err
    assert main(["schema", "-o", str(tmp_path)]) == 1
    assert f"error: the output path is a folder: {tmp_path}" in capsys.readouterr().err


def test_cli_help_lists_schema(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert re.search(r"^\s+schema\s+print the scenario's JSON Schema", capsys.readouterr().out, re.M)


# --------------------------------------------------------------------------- units, descriptions, bounds

def test_every_number_has_its_unit_once(schema):
    # every number an engineer types has a unit in the schema's ``units``, and its description
    # ends with that unit in brackets ("1", dimensionless, as "[-]") and names no unit in its text
    missing, suffix, inner, numbers = [], [], [], 0
    for model, name, prop in properties(schema):
        if not holds_numbers(prop):
            continue
        numbers += 1
        units = prop.get("units")
        if not units:
            missing.append(f"{model}.{name}")
            continue
        text = prop.get("description", "")
        end = f" [{unit_label(units)}]"
        if not text.endswith(end):
            suffix.append(f"{model}.{name}: {text[-40:]!r} does not end with {end!r}")
        elif UNIT_IN_TEXT.search(text[:-len(end)]):
            inner.append(f"{model}.{name}: {text!r}")
    assert not missing, f"{len(missing)} numeric fields without a unit: {missing}"
    assert not suffix, f"{len(suffix)} descriptions without their unit at the end: {suffix}"
    assert not inner, f"{len(inner)} descriptions with a unit in their text: {inner}"
    assert numbers > 350          # the walk reached the schema's numbers
    # dimensionless numbers and counts are "1", angles of the _deg fields deg
    defs = schema["$defs"]
    assert defs["LineType"]["properties"]["poisson_ratio"]["units"] == "1"
    assert defs["Line"]["properties"]["elements"]["units"] == "1"
    assert defs["JonswapWaves"]["properties"]["seed"]["units"] == "1"
    assert defs["Current"]["properties"]["time_factor"]["description"].endswith("[s, -]")
    assert all(prop["units"].startswith("deg") for _, name, prop in properties(schema) if name.endswith("_deg"))


def test_every_number_has_a_unit_on_the_page(generated):
    rows = [row for _, _, rows in tables(generated) for row in rows
            if "number" in row["type"] or "integer" in row["type"]]
    assert len(rows) > 350
    assert [row["field"] for row in rows if not row["unit"]] == []
    poisson = table(generated, "line_types.<name>")["line_types.<name>.poisson_ratio"]
    assert poisson["unit"] == "`1`" and poisson["description"] == "Poisson's ratio [-]"


def test_every_object_has_a_description(schema, generated):
    defs = schema["$defs"]
    undescribed = [d for d in reachable_definitions(schema) if not defs[d].get("description", "").strip()]
    assert not undescribed, f"models without a docstring: {undescribed}"
    # so every section of the page opens with its introduction, not with its table
    lines = generated.splitlines()
    headings = [i for i, line in enumerate(lines) if line.startswith("### ")]
    assert len(headings) > 70
    bare = [lines[i] for i in headings if lines[i + 2].startswith("| field |")]
    assert not bare, f"sections without an introduction: {bare}"


def test_time_tables_say_that_their_times_increase(schema):
    # every table with a time column has its times strictly increasing (its model's validator);
    # the JSON Schema cannot hold it, so the description says it
    time_tables = [f"{model}.{name}" for model, name, prop in properties(schema)
                   if re.match(r"^(?:[^(]*\()?s,", prop.get("units", ""))]
    assert len(time_tables) >= 15
    silent = [f for f in time_tables if "strictly increasing" not in
              schema["$defs"][f.split(".")[0]]["properties"][f.split(".")[1]]["description"]]
    assert not silent, f"time tables that do not say their times increase: {silent}"


@pytest.mark.parametrize("section, rows, where", [
    ({"environment": {"water": {"depth": 50.0, "current": {"profile": [[0.0, 1.0]],
                                                           "time_factor": [[0.0, 1.0], [0.0, 2.0]]}}}},
     None, "environment.water.current.time_factor.1"),
    ({"vessels": {"v": {"motion": {"kind": "table", "rows": [[0, 0, 0, 0, 0, 0, 0], [5, 0, 0, 0, 0, 0, 0],
                                                              [4, 0, 0, 0, 0, 0, 0]],
                                   "interpolation": "linear"}}}}, None, "vessels.v.motion.rows.2"),
])
def test_a_time_table_that_does_not_increase_is_refused(section, rows, where):
    # what the descriptions say is what the validators check
    with pytest.raises(rfesim.ScenarioError) as err:
        rfesim.load_scenario(section)
    assert where in str(err.value) and "does not increase" in str(err.value)
