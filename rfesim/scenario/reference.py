"""The scenario reference for engineers: every section and field of the scenario JSON as
Markdown (``docs/scenario.md``), generated from the JSON Schema of :class:`rfesim.Scenario`.

    rfesim schema --markdown -o docs/scenario.md      (or: rfesim schema --markdown > docs/scenario.md)

:func:`scenario_reference_markdown` walks the schema: ``$ref`` into ``$defs``, ``anyOf``
alternatives, discriminated ``oneOf`` unions (one table per variant, under its
discriminator value), lists (``path[]``) and maps of named objects (``path.<name>``). Each
object gets one table with a row per field: path, type or allowed values, unit, default,
bounds, required, and the schema's description as it is. An object model met again at
another path (a vessel inside a crane template, ``end_b`` after ``end_a``) is not repeated:
its row links to the table where it was first listed. The output depends only on the
schema, so the page is regenerated, never edited (tests/unit/test_scenario_reference.py
fails when it is stale).

What the schema gives the page (rfesim.scenario.schema._units; the test checks it):

* every number (a number, a list or a table of numbers, a number-or-table) has a ``units``:
  an SI unit as the field is used (``m``, ``N*m``, ``deg`` for the ``_deg`` fields, ``rad``
  for joint coordinates ...), the column units of a table (``s, m``: rows [t, x]), ``N (s,
  N)`` for a number or a table, or ``1`` for a dimensionless number: a ratio, a
  coefficient, a direction of any length, and a count (elements, iterations, components,
  rollers) or a seed, which are integers of unit one. A fixed value (``schema_version``)
  has none;
* its description ends with that unit in brackets, ``1`` written ``[-]``, and names no unit
  in its text;
* every object (model) has a description, the introduction of its section;
* a bound that a validator checks and the JSON Schema cannot hold (times strictly
  increasing, a length less than another field's, a direction not zero) is written in the
  description.
"""
from __future__ import annotations

import json
import re
import typing
from typing import Any, Literal

from pydantic import BaseModel
from pydantic.json_schema import GenerateJsonSchema

REGENERATE = "rfesim schema --markdown -o docs/scenario.md"

COLUMNS = ["field", "type", "unit", "default", "bounds", "required", "description"]


# --------------------------------------------------------------------------- the schema

def _short_default(value: BaseModel) -> dict:
    """A model default as the smallest input that gives it: the fields that differ from
    their own defaults, after the fixed discriminator (``{"kind": "free"}``); ``{}`` for a
    model made of its fields' defaults."""
    out = {}
    for name, field in type(value).model_fields.items():
        args = typing.get_args(field.annotation)
        if typing.get_origin(field.annotation) is Literal and len(args) == 1:
            out[field.alias or name] = getattr(value, name)
    out.update(value.model_dump(mode="json", by_alias=True, exclude_defaults=True))
    return out


class _ReferenceJsonSchema(GenerateJsonSchema):
    """The JSON Schema with the defaults of the fields that have a default factory
    (``Field(default_factory=...)``), which pydantic leaves out: ``analysis.dynamics`` is
    ``{}`` (its fields' defaults), ``vessels.<name>.motion`` ``{"kind": "fixed"}``."""

    def get_default_value(self, schema):
        factory = schema.get("default_factory")
        if factory is None or schema.get("default_factory_takes_data"):
            return super().get_default_value(schema)
        value = factory()
        return _short_default(value) if isinstance(value, BaseModel) else value


def reference_schema() -> dict:
    """``rfesim.Scenario.model_json_schema()`` with the defaults of default factories."""
    from .schema import Scenario

    return Scenario.model_json_schema(schema_generator=_ReferenceJsonSchema)


# --------------------------------------------------------------------------- text

_CODE_SPAN = re.compile(r"(`+)(.+?)\1", re.S)


def _escape(text: str, cell: bool = True) -> str:
    """Schema text shown as written: ``|`` escaped in a table, ``*``, ``_`` and ``<`` outside
    code spans (``N*m ... kg*m^2`` is no emphasis, ``<name>`` no HTML tag), a cell on one line."""
    out, pos = [], 0
    for m in _CODE_SPAN.finditer(text):
        out.append(_escape_plain(text[pos:m.start()]))
        out.append(m.group(0))
        pos = m.end()
    out.append(_escape_plain(text[pos:]))
    text = "".join(out)
    if cell:
        text = " ".join(text.split("\n")).replace("|", "\\|")
    return text


def _escape_plain(text: str) -> str:
    text = text.replace("\\", "\\\\").replace("*", "\\*")
    text = re.sub(r"(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])", r"\\_", text)     # end_a stays as it is
    return re.sub(r"<(?=[A-Za-z/!?])", "&lt;", text)                    # "<name>", not "< 0"


def _code(text: str) -> str:
    """``text`` as a code span (``|`` is escaped by the caller for tables)."""
    ticks = "``" if "`" in text else "`"
    pad = " " if "`" in text else ""
    return f"{ticks}{pad}{text}{pad}{ticks}"


def _json(value: Any) -> str:
    return json.dumps(value, separators=(", ", ": "), ensure_ascii=False)


def _number(value: float) -> str:
    """A bound: 0.001, 100000, 1e+07, 1.2e+12 (exact to 12 digits)."""
    x = float(value)
    if x == 0 or 1e-4 <= abs(x) < 1e6:
        return f"{x:.12g}"
    mantissa, exponent = f"{x:.11e}".split("e")
    return f"{mantissa.rstrip('0').rstrip('.')}e{exponent}"


def _number_bounds(node: dict) -> str:
    parts = []
    if "minimum" in node and "maximum" in node and node["minimum"] == -node["maximum"]:
        return f"±{_number(node['maximum'])}"
    if "minimum" in node:
        parts.append(f"≥ {_number(node['minimum'])}")
    if "exclusiveMinimum" in node:
        parts.append(f"> {_number(node['exclusiveMinimum'])}")
    if "maximum" in node:
        parts.append(f"≤ {_number(node['maximum'])}")
    if "exclusiveMaximum" in node:
        parts.append(f"< {_number(node['exclusiveMaximum'])}")
    return ", ".join(parts)


def _count(node: dict, one: str, many: str, listed: bool = True) -> str:
    """``3 numbers``, ``2 to 7 numbers``, ``at least 1 row`` ... of an array's item counts."""
    lo, hi = node.get("minItems"), node.get("maxItems")
    if lo is not None and lo == hi:
        return f"{lo} {one if lo == 1 else many}"
    if lo is not None and hi is not None:
        return f"{lo} to {hi} {many}"
    if lo:
        return f"at least {lo} {one if lo == 1 else many}"
    if hi is not None:
        return f"at most {hi} {one if hi == 1 else many}"
    return f"list of {many}" if listed else many


# --------------------------------------------------------------------------- the walk

class _Section:
    def __init__(self, path: str, definition: str, context: tuple, anchor: str):
        self.path = path
        self.definition = definition
        self.context = context          # ((path, discriminator, value), ...) of the unions on the way
        self.anchor = anchor

    def label(self) -> str:
        """``a.b`` (``kind: "x"``), and the variants of the objects it is in: `` — in `a`
        (`method: "s-lay"`)``."""
        label = _code(self.path)
        outer = [c for c in self.context if c[0] != self.path]
        own = [c for c in self.context if c[0] == self.path]
        if own:
            label += " (" + ", ".join(_code(f"{d}: {_json(v)}") for _, d, v in own) + ")"
        if outer:
            label += " — in " + ", ".join(f"{_code(p)} ({_code(f'{d}: {_json(v)}')})" for p, d, v in outer)
        return label


class _Writer:
    def __init__(self, schema: dict):
        self.schema = schema
        self.defs = schema.get("$defs", {})
        self.sections: dict[str, _Section] = {}   # by definition: where it was first listed
        self.anchors: set[str] = set()
        self.rows = 0
        self.out: list[str] = []

    # ------------------------------------------------------------------ helpers
    def _definition(self, ref: str) -> str:
        prefix = "#/$defs/"
        if not ref.startswith(prefix):
            raise ValueError(f"unsupported $ref {ref!r}")
        name = ref[len(prefix):]
        if name not in self.defs:
            raise ValueError(f"$ref {ref!r} names no definition")
        return name

    def _anchor(self, path: str, context: tuple) -> str:
        words = [path] + [str(v) for _, _, v in context]
        base = re.sub(r"[^a-z0-9]+", "-", " ".join(words).lower()).strip("-") or "section"
        anchor, k = base, 2
        while anchor in self.anchors:
            anchor, k = f"{base}-{k}", k + 1
        self.anchors.add(anchor)
        return anchor

    def _target(self, path: str, definition: str, context: tuple, queue: list) -> _Section:
        """The section of ``definition``: where it was first listed, or a new one at ``path``."""
        section = self.sections.get(definition)
        if section is None:
            section = _Section(path, definition, context, self._anchor(path, context))
            self.sections[definition] = section
            queue.append(section)
        return section

    @staticmethod
    def _link(text: str, section: _Section) -> str:
        return f"[{text}](#{section.anchor})"

    # ------------------------------------------------------------------ types
    def describe(self, node: dict, path: str, context: tuple, queue: list) -> tuple[str, list[str]]:
        """(type text, bounds) of a property's schema ``node``; the objects it holds are
        queued as sections."""
        if "$ref" in node:
            section = self._target(path, self._definition(node["$ref"]), context, queue)
            text = "object"
            if section.path != path or section.context != context:
                text += ", as " + section.label()
            return self._link(text, section), []
        if "oneOf" in node:
            return self._union(node, path, context, queue), []
        if "anyOf" in node:
            texts, bounds = [], []
            for alt in node["anyOf"]:
                t, b = self.describe(alt, path, context, queue)
                texts.append(t)
                bounds += [x for x in b if x not in bounds]
            return " or ".join(texts), bounds
        if "const" in node:
            return _code(_json(node["const"])), []
        if "enum" in node:
            values = [_code(_json(v)) for v in node["enum"]]
            return ("one of " + ", ".join(values)) if len(values) > 1 else values[0], []
        kind = node.get("type")
        if kind == "array":
            return self._array(node, path, context, queue)
        if kind == "object":
            extra = node.get("additionalProperties")
            if isinstance(extra, dict) and extra:
                t, b = self.describe(extra, f"{path}.<name>", context, queue)
                lo = node.get("minProperties")
                if lo:
                    b = [f"at least {lo} {'entry' if lo == 1 else 'entries'}"] + b
                return f"map: name → {t}", b
            return "object", []
        if kind in ("number", "integer"):
            b = _number_bounds(node)
            return kind, [b] if b else []
        if kind == "string":
            b = []
            if "minLength" in node:
                b.append(f"length ≥ {node['minLength']}")
            if "maxLength" in node:
                b.append(f"length ≤ {node['maxLength']}")
            return "string", [", ".join(b)] if b else []
        if kind in ("boolean", "null"):
            return kind, []
        if kind is None and not node:
            return "any", []
        raise ValueError(f"{path}: unsupported schema {_json(node)[:200]}")

    def _union(self, node: dict, path: str, context: tuple, queue: list) -> str:
        discriminator = node.get("discriminator", {})
        key = discriminator.get("propertyName")
        if key is None:
            raise ValueError(f"{path}: a oneOf without a discriminator")
        by_definition = {self._definition(ref): value for value, ref in discriminator.get("mapping", {}).items()}
        links = []
        for alt in node["oneOf"]:
            definition = self._definition(alt["$ref"])
            value = by_definition[definition]
            section = self._target(path, definition, context + ((path, key, value),), queue)
            links.append(self._link(_code(_json(value)), section))
        return f"object by {_code(key)}: " + ", ".join(links)

    def _array(self, node: dict, path: str, context: tuple, queue: list) -> tuple[str, list[str]]:
        items = node.get("items", {})
        if items.get("type") in ("number", "integer", "string", "boolean") \
                and not {"anyOf", "oneOf", "$ref", "enum", "const"} & set(items):
            _, b = self.describe(items, f"{path}[]", context, queue)
            return _count(node, items["type"], items["type"] + "s"), b
        if items.get("type") == "array" and items.get("items", {}).get("type") in ("number", "integer"):
            cells = items["items"]
            row = _count(items, cells["type"], cells["type"] + "s", listed=False)
            b = _number_bounds(cells)
            return _count(node, "row", "rows", listed=False) + f" of {row}", [b] if b else []
        t, b = self.describe(items, f"{path}[]", context, queue)
        return f"{_count(node, 'item', 'items')}: {t}" if ("minItems" in node or "maxItems" in node) \
            else f"list of {t}", b

    # ------------------------------------------------------------------ output
    def table(self, obj: dict, prefix: str, context: tuple) -> list[_Section]:
        """The table of an object's fields; returns the sections of the objects it holds."""
        queue: list[_Section] = []
        required = set(obj.get("required", []))
        rows = []
        props = list(obj.get("properties", {}).items())
        if context and context[-1][0] == prefix:      # a variant: its discriminator first
            props.sort(key=lambda item: item[0] != context[-1][1])
        for name, prop in props:
            path = f"{prefix}.{name}" if prefix else name
            type_text, bounds = self.describe(prop, path, context, queue)
            if name in required:
                default = "—"
            elif "default" in prop:
                default = _code(_json(prop["default"]))
            else:
                default = ""
            cells = [_code(path), type_text, _code(prop["units"]) if "units" in prop else "", default,
                     "; ".join(bounds), "yes" if name in required else "no",
                     _escape(prop.get("description", ""))]
            rows.append("| " + " | ".join(c if i == 6 else c.replace("|", "\\|") for i, c in enumerate(cells)) + " |")
        self.rows += len(rows)
        if rows:
            self.out += ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS), *rows, ""]
        else:
            self.out += ["No fields.", ""]
        return queue

    def section(self, section: _Section) -> None:
        definition = self.defs[section.definition]
        self.out += [f'<a id="{section.anchor}"></a>', "", f"### {section.label()}", ""]
        if definition.get("description"):
            self.out += [_escape(definition["description"], cell=False), ""]
        if definition.get("type") != "object" or "properties" not in definition:
            raise ValueError(f"{section.path}: definition {section.definition} is not an object")
        for child in self.table(definition, section.path, section.context):
            self.section(child)

    def write(self) -> str:
        props = self.schema.get("properties", {})
        self.out += [
            "# Scenario reference",
            "",
            "<!-- Generated from the JSON Schema of rfesim.Scenario by rfesim.scenario.reference: do not edit. -->",
            "",
            "Generated from the scenario's JSON Schema (`rfesim.Scenario.model_json_schema()`); do not edit it "
            f"by hand. After a change to the schema, regenerate it with `{REGENERATE}` "
            "(tests/unit/test_scenario_reference.py fails while it is stale).",
            "",
            "A scenario is a JSON or YAML file; `rfesim check SCENARIO` validates it and names the field of "
            "every error, `rfesim check --expand SCENARIO` prints it with its pipelay and crane templates "
            "expanded. SI units, angles in degrees where the name ends in `_deg`, z up, the still water "
            "surface at `environment.water.surface_level` (0).",
            "",
            "How to read the tables:",
            "",
            "* **field**: the path of the field in the scenario. `<name>` is a key you choose (a map of "
            "named objects: `lines.<name>`), `[]` an item of a list (`lines.<name>.loads[]`).",
            "* **type**: `number`, `integer`, `string`, `boolean`; a quoted value is the only one allowed; "
            "`or null`: null is accepted too (mostly the default: not set). `rows of 2 numbers` is a table, e.g. "
            "`[[0.0, 1.0], [10.0, 2.0]]`. An object links to its table; `object by kind` lists the variants "
            "of a choice (the value of `kind`, `method`, `type` ... selects which fields apply), each with its "
            "own table. An object that appears in several places is listed once, where it first appears.",
            "* **unit**: the SI unit; `1`: dimensionless (a ratio, a coefficient, a direction of any length, a "
            "count or a seed). A table lists the units of its columns (`s, m`: rows "
            "[t, eta]); a field that takes a number or a table has both: `deg (s, deg)` is an angle in deg or "
            "rows [t in s, angle in deg].",
            "* **default**: the value taken when the field is left out; `{}` for an object: the defaults of "
            "its fields. `—`: required, no default.",
            "* **bounds**: the allowed range (`±1e+07`: between -1e+07 and 1e+07), of every number of a list "
            "or table; a number without bounds of its own is bounded by its unit (`UNIT_BOUNDS` in "
            "`rfesim/scenario/schema.py`, also each column of a table), and the error for a value outside says "
            "why.",
            "* **description**: as written in the schema, ending with the unit in brackets (`[-]`: "
            "dimensionless), with the conditions the bounds column cannot show (times strictly increasing, a "
            "length less than another field's, a direction not zero).",
            "",
            "## Top level",
            "",
        ]
        top = self.table(self.schema, "", ())
        sections_by_key: dict[str, list[_Section]] = {}
        for s in top:
            sections_by_key.setdefault(s.path.split(".")[0].split("[")[0], []).append(s)
        for key, prop in props.items():
            if key not in sections_by_key:
                continue
            self.out += [f"## {_code(key)}", ""]
            if prop.get("description"):
                self.out += [_escape(prop["description"], cell=False), ""]
            for s in sections_by_key[key]:
                self.section(s)
        while self.out and self.out[-1] == "":
            self.out.pop()
        return "\n".join(self.out) + "\n"


def scenario_reference_markdown(schema: dict | None = None) -> str:
    """The scenario reference page (docs/scenario.md) as Markdown: one section per top-level
    key, a table per object, the variants of a choice under its discriminator value."""
    return _Writer(reference_schema() if schema is None else schema).write()


def scenario_reference_rows(schema: dict | None = None) -> int:
    """The number of field rows of the reference page."""
    w = _Writer(reference_schema() if schema is None else schema)
    w.write()
    return w.rows
