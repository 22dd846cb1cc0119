"""Scenario files: reading TOML, ``--set`` overrides, writing the resolved scenario as TOML."""

from __future__ import annotations

import copy
import re
import sys
from pathlib import Path
from typing import Any

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from ..errors import ScenarioError

__all__ = ["read_toml", "parse_value", "apply_overrides", "inline_short_arrays", "drop_none"]


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; missing files and syntax errors become :class:`ScenarioError`."""
    p = Path(path)
    try:
        text = p.read_bytes()
    except FileNotFoundError:
        raise ScenarioError([("", f"scenario file not found: {p}")], str(p)) from None
    except IsADirectoryError:
        raise ScenarioError([("", f"scenario path is a folder, not a file: {p}")], str(p)) from None
    except OSError as exc:
        raise ScenarioError([("", f"cannot read {p}: {exc.strerror}")], str(p)) from None
    try:
        return tomllib.loads(text.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise ScenarioError([("", f"{p}: not UTF-8 text ({exc.reason})")], str(p)) from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError([("", f"{p}: invalid TOML: {exc}")], str(p)) from None
    except RecursionError:
        raise ScenarioError([("", f"{p}: invalid TOML: arrays or tables nested too deeply")], str(p)) from None


def parse_value(text: str) -> Any:
    """Parse an override value as a TOML value (``1``, ``[0.1, 0.2]``, ``"a"``, ``{...}``);
    anything that is not valid TOML is taken as a bare string (``roller``)."""
    try:
        return tomllib.loads("v = " + text)["v"]
    except tomllib.TOMLDecodeError:
        return text.strip()


def apply_overrides(data: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
    """Return a deep copy of ``data`` with ``key.path=value`` overrides applied.

    Keys are dotted; integer parts index arrays of tables (``bodies.0.max=[0.1,0.2]``); an
    index equal to the array length appends a new table. Missing tables are created.
    Problems are collected and raised together as :class:`ScenarioError`.
    """
    result = copy.deepcopy(data)  # plain TOML data (may hold dates, which JSON cannot)
    errors: list[tuple[str, str]] = []
    for item in overrides:
        key, sep, raw = item.partition("=")
        key = key.strip()
        if not sep or not key:
            errors.append((key or item, f"override must look like key.path=value (got {item!r})"))
            continue
        parts = key.split(".")
        if any(not p for p in parts):
            errors.append((key, "empty part in the dotted key"))
            continue
        try:
            _set_path(result, parts, parse_value(raw))
        except _OverrideError as exc:
            errors.append((key, str(exc)))
    if errors:
        raise ScenarioError(errors, "--set")
    return result


class _OverrideError(Exception):
    pass


def _set_path(node: Any, parts: list[str], value: Any) -> None:
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[:depth]) or "the scenario"
        if isinstance(node, list):
            if not part.isdigit():
                raise _OverrideError(f"{where} is an array: expected an index, got {part!r}")
            index = int(part)
            if index > len(node):
                raise _OverrideError(f"index {index} out of range ({where} has {len(node)} entries)")
            if index == len(node):
                node.append({})
            if last:
                node[index] = value
            else:
                node = node[index]
        elif isinstance(node, dict):
            if last:
                node[part] = value
            else:
                if part not in node:
                    node[part] = [] if parts[depth + 1].isdigit() else {}
                elif isinstance(node[part], str) and depth == 1 and parts[0] == "boundaries":
                    node[part] = {"condition": node[part]}  # shorthand face → table form
                node = node[part]
        else:
            raise _OverrideError(f"{where} is a value ({node!r}), not a table")


_MULTILINE_ARRAY = re.compile(r"\[\n((?:[ \t]+[^\[\]{}\n\"]+,\n)+)\]")


def inline_short_arrays(text: str) -> str:
    """tomli-w writes every array over several lines; put short numeric ones on one line."""

    def join(match: re.Match[str]) -> str:
        items = [line.strip().rstrip(",") for line in match.group(1).splitlines()]
        return "[" + ", ".join(items) + "]"

    return _MULTILINE_ARRAY.sub(join, text)


def drop_none(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: drop_none(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, list):
        return [drop_none(v) for v in obj]
    return obj
