"""Number formatting and pieces shared by the Markdown reports and terminal tables."""

from __future__ import annotations

import math
from typing import Any, Callable

__all__ = ["DASH", "number", "pct", "fmt", "checks_table", "figures_section"]

#: What a table cell shows for a missing value.
DASH = "—"


def number(value: Any) -> float | None:
    """``value`` as a finite float, or None (None, "", text that is not a number, NaN, inf)."""
    if value is None or value == "" or isinstance(value, bool):
        return None
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def pct(value: Any, digits: int = 1, *, signed: bool = True, unit: str = " %") -> str:
    """A fraction as a percentage: ``pct(-0.123)`` → ``"-12.3 %"``; ``pct(0.05, 0)`` → ``"+5 %"``;
    ``pct(0.0123, 2, signed=False, unit="")`` → ``"1.23"``; :data:`DASH` when there is no number."""
    x = number(value)
    if x is None:
        return DASH
    return f"{100 * x:{'+' if signed else ''}.{digits}f}{unit}"


def fmt(value: Any, spec: str = ".3g") -> str:
    """``format(value, spec)``, or :data:`DASH` when there is no number."""
    x = number(value)
    return DASH if x is None else format(x, spec)


def checks_table(checks: list[dict[str, Any]]) -> str:
    """A Markdown table of a case's checks: name, result (pass, **FAIL**, or "missed (aim)" for a
    check with ``required`` False) and detail."""
    lines = ["| check | result | detail |", "|---|---|---|"]
    for c in checks:
        result = "pass" if c["passed"] else ("**FAIL**" if c.get("required", True) else "missed (aim)")
        lines.append(f"| {c['name']} | {result} | {c.get('detail', '')} |")
    return "\n".join(lines)


def figures_section(results: Any, draw: Callable[[], str]) -> str:
    """A report's figures: ``draw()``, which plots them and returns their Markdown, unless the
    results' ``context`` turns figures off (``""``). A report without figures is still a report:
    a plotting error is written in their place."""
    if not getattr(results, "context", {}).get("figures", True):
        return ""
    try:
        return draw()
    except Exception as exc:  # noqa: BLE001 - a report without figures is still a report
        return f"(figures not written: {type(exc).__name__}: {exc})\n"
