"""``[[surcharges]]``: a uniform pressure on a free surface of the material.

The particles whose upper edge lies on the line y = ``level`` (within half a particle) and
whose x (r) lies in ``range`` carry the pressure over their width as a dead load, ramped in
with gravity (``simulation.gravity_ramp_time``). A geostatic body under a surcharge starts with
σ_v = pressure + ρ g depth. The history reports ``NAME.applied_force_y``, the force the
surcharge applies to the material (N; per metre in plane strain, the whole ring in
axisymmetry; negative: downward).
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from .fields import NonNegative, Section, fmt

__all__ = ["Surcharge", "surcharge_errors"]


class Surcharge(Section):
    """One ``[[surcharges]]`` table."""

    name: str | None = Field(None, description="names the history column NAME.applied_force_y; "
                             "resolved default: surcharge_<index>")
    pressure: NonNegative = Field(description="Pa, compressive on the surface")  # type: ignore[valid-type]
    level: float = Field(description="m: the height of the loaded surface (the top of a body)")
    range: tuple[float, float] | None = Field(
        None, description="m: the x (r) range loaded, [x0, x1]; absent = the whole grid width")


def surcharge_errors(surcharges: list[Surcharge | None], frame: Any, taken: set[str]) -> list[tuple[str, str]]:
    """Cross checks: the level and range inside the grid (``frame``: a GridFrame, or None when
    the grid is invalid), x0 < x1, names unique and not those of other reporting constraints."""
    errors: list[tuple[str, str]] = []
    names = set(taken)
    for i, c in enumerate(surcharges):
        if c is None:
            continue
        key = f"surcharges.{i}"
        if c.name is not None:
            if c.name in names:
                errors.append((f"{key}.name", f"duplicate name {c.name!r} (faces, walls, rigid bodies and "
                               "surcharges name history columns)"))
            names.add(c.name)
        if frame is None:
            continue
        (x_lo, y_lo), (x_hi, y_hi) = frame.lo, frame.hi
        if not (y_lo - frame.tol <= c.level <= y_hi + frame.tol):
            errors.append((f"{key}.level", f"must lie in the grid, {fmt(y_lo)}..{fmt(y_hi)} m (got {fmt(c.level)})"))
        if c.range is not None:
            a, b = c.range
            if not (a < b):
                errors.append((f"{key}.range", f"must be [x0, x1] with x0 < x1 (got [{fmt(a)}, {fmt(b)}])"))
            elif a < x_lo - frame.tol or b > x_hi + frame.tol:
                errors.append((f"{key}.range", f"must lie in the grid, {fmt(x_lo)}..{fmt(x_hi)} m "
                               f"(got [{fmt(a)}, {fmt(b)}])"))
    return errors
