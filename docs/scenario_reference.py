"""Writes docs/scenario.md, the key-by-key reference of scenario files, from the JSON Schema that
``axmpm schema`` prints (the pydantic models of ``axmpm.scenario``):

    python docs/scenario_reference.py > docs/scenario.md

``tests/test_docs.py`` fails when docs/scenario.md differs from this script's output."""

from __future__ import annotations

import json
import sys
from typing import Any

from axmpm.scenario import Scenario

HEADER = """# Scenario file reference

Generated from the scenario schema by `python docs/scenario_reference.py > docs/scenario.md`;
`axmpm schema` prints the same schema as JSON (for editors). A scenario is a TOML file with the
sections below. Units are SI (m, s, kg, Pa); angles are in degrees. Unknown keys are errors,
every error is reported at once (`axmpm check FILE`), and `axmpm check FILE --print` shows the
scenario with every default filled in. Any key can be overridden on the command line with
`--set dotted.key=value` (a TOML value), e.g. `--set materials.clay.cohesion=20e3` or
`--set bodies.0.max=[2.5,2.0]`. Examples: the README and `examples/`.
"""


def _type(prop: dict[str, Any], defs: dict[str, Any]) -> str:
    """A short description of the values a property accepts."""
    if "$ref" in prop:
        return f"table ({prop['$ref'].rsplit('/', 1)[-1]})"
    if "const" in prop:
        return json.dumps(prop["const"])
    if "enum" in prop:
        return " \\| ".join(json.dumps(v) for v in prop["enum"])
    if "anyOf" in prop:
        kinds = [_type(p, defs) for p in prop["anyOf"] if p.get("type") != "null"]
        text = " or ".join(kinds)
        return text + " (optional)" if any(p.get("type") == "null" for p in prop["anyOf"]) else text
    kind = prop.get("type", "any")
    if kind == "array":
        if "prefixItems" in prop:
            return "[" + ", ".join(_type(p, defs) for p in prop["prefixItems"]) + "]"
        return "list of " + _type(prop.get("items", {}), defs)
    bounds = []
    for key, sign in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<")):
        if key in prop:
            bounds.append(f"{sign} {prop[key]:g}")
    if "pattern" in prop:
        bounds.append(f"matching `{prop['pattern']}`")
    return kind + (" " + ", ".join(bounds) if bounds else "")


def _default(prop: dict[str, Any], required: bool) -> str:
    if required:
        return "required"
    if "default" not in prop:
        return ""
    value = prop["default"]
    return "absent" if value is None else f"`{json.dumps(value, ensure_ascii=False)}`"


def _clean(text: str) -> str:
    return " ".join(text.replace("``", "`").replace("|", "\\|").split())


def _table(definition: dict[str, Any], defs: dict[str, Any]) -> list[str]:
    lines = ["| key | values | default | meaning |", "|---|---|---|---|"]
    required = set(definition.get("required", []))
    for key, prop in definition.get("properties", {}).items():
        lines.append(f"| `{key}` | {_type(prop, defs)} | {_default(prop, key in required)} | "
                     f"{_clean(prop.get('description', ''))} |")
    return lines


def _union(prop: dict[str, Any]) -> list[str]:
    """The definitions a discriminated union (materials by model, bodies by shape) refers to."""
    holder = prop.get("additionalProperties") or prop.get("items") or prop
    return [ref["$ref"].rsplit("/", 1)[-1] for ref in holder.get("oneOf", [])]


def reference() -> str:
    schema = Scenario.model_json_schema()
    defs = schema["$defs"]
    out = [HEADER]
    required = set(schema.get("required", []))
    for section, prop in schema["properties"].items():
        brackets = f"[[{section}]]" if prop.get("type") == "array" else f"[{section}]"
        out.append(f"## `{brackets}`" + (" (required)" if section in required else ""))
        out.append("")
        names = _union(prop)
        if section == "materials":
            out += ["One table `[materials.NAME]` per material, any NAME; bodies refer to it by NAME. "
                    "The key `model` chooses the table's keys:", ""]
        if names:
            for name in names:
                definition = defs[name]
                tag = next(k for k in ("model", "shape") if k in definition["properties"])
                value = definition["properties"][tag].get("const")
                out += [f"### {tag} = \"{value}\"", "", _clean(definition.get("description", "")), ""]
                out += _table(definition, defs) + [""]
            continue
        name = (prop.get("items") or prop)["$ref"].rsplit("/", 1)[-1]
        definition = defs[name]
        out += [_clean(definition.get("description", "")), ""] + _table(definition, defs) + [""]
        if section == "boundaries":
            condition = defs["BoundaryCondition"]
            out += ["Each face takes a condition name (`left = \"roller\"`) or a table:", ""]
            out += _table(condition, defs) + [""]
    return "\n".join(out).rstrip() + "\n"


if __name__ == "__main__":
    sys.stdout.write(reference())
