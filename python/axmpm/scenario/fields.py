"""Building blocks of the scenario sections: range-checked number types and the section base.

Every range check reads ``must be >= 0 and < 0.5 (got 0.7)``; every section forbids unknown keys
and rejects NaN and infinity.
"""

from __future__ import annotations

import difflib
from typing import Annotated, Any

from pydantic import AfterValidator, BaseModel, ConfigDict, Field
from pydantic_core import PydanticCustomError

__all__ = ["GRID_TOLERANCE", "MAX_CELLS_PER_AXIS", "MAX_OUTPUTS", "Positive", "NonNegative", "Vec2", "Section",
           "bounded", "fmt", "did_you_mean", "on_grid_line"]

#: Tolerance, as a fraction of a cell, for "on a grid line" checks.
GRID_TOLERANCE = 1e-6

#: Sanity limits: a dense grid with more cells than this along one axis, or a run with more
#: output frames than this, is certainly a unit mistake (and would overflow or exhaust memory).
MAX_CELLS_PER_AXIS = 10_000_000
MAX_OUTPUTS = 1_000_000


def fmt(x: float) -> str:
    return f"{x:g}"


def bounded(
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    kind: type = float,
) -> Any:
    """A number type with a range check whose message reads ``must be >= 0 and < 0.5 (got 0.7)``."""
    parts = []
    schema: dict[str, float] = {}
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {fmt(lo)}")
        schema["exclusiveMinimum" if lo_open else "minimum"] = lo
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {fmt(hi)}")
        schema["exclusiveMaximum" if hi_open else "maximum"] = hi
    text = "must be " + " and ".join(parts)

    def check(value: float) -> float:
        too_low = lo is not None and (value <= lo if lo_open else value < lo)
        too_high = hi is not None and (value >= hi if hi_open else value > hi)
        if too_low or too_high:
            raise PydanticCustomError("out_of_range", text + " (got {value})", {"value": value})
        return value

    return Annotated[kind, Field(json_schema_extra=schema), AfterValidator(check)]


Positive = bounded(0.0, lo_open=True)
NonNegative = bounded(0.0)
Vec2 = tuple[float, float]


class Section(BaseModel):
    """Base of every section: unknown keys are errors, NaN/inf are rejected."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


def did_you_mean(word: str, choices: Any) -> str:
    """``"; did you mean 'x'?"`` when ``word`` is close to one of ``choices``, else ``""``."""
    match = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1, cutoff=0.6)
    return f"; did you mean {match[0]!r}?" if match else ""


def on_grid_line(value: float, origin: float, h: float) -> bool:
    """``value`` lies on a grid line of cell size ``h`` from ``origin`` (within GRID_TOLERANCE)."""
    import math

    n = (value - origin) / h
    return math.isfinite(n) and abs(n - round(n)) <= GRID_TOLERANCE
