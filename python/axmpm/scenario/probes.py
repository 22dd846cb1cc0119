"""``[[probes]]``: points of the grid at which every history row records the pore pressure
(saturated runs), the stress and the displacement, interpolated from the particles
(:mod:`axmpm.run.probes`).
"""

from __future__ import annotations

from typing import Any

from pydantic import Field

from .fields import Section, Vec2, fmt

__all__ = ["Probe", "probe_errors"]


class Probe(Section):
    """A point whose pore pressure (saturated runs), stress and displacement every history row
    records, interpolated from the particles within one cell of it (a linear moving
    least-squares fit, exact for a linear field, also at a free surface)."""

    name: str = Field(pattern=r"^[A-Za-z_][A-Za-z0-9_-]*$",
                      description="names the history columns NAME.pore_pressure, NAME.stress_yy, "
                                  "NAME.displacement_x, ...")
    point: Vec2 = Field(description="m, a fixed point of the grid (the particles near it at each row are used)")


def probe_errors(probes: list[Any] | None, grid: Any) -> list[tuple[str, str]]:
    """Cross checks of the probes: each point inside the grid, each name used once."""
    errors: list[tuple[str, str]] = []
    seen: set[str] = set()
    for i, probe in enumerate(probes or []):
        if probe is None:
            continue
        if probe.name in seen:
            errors.append((f"probes.{i}.name", f"duplicate probe name {probe.name!r}: each probe needs its own"))
        seen.add(probe.name)
        if grid is None:
            continue
        for d in (0, 1):
            lo, hi = grid.origin[d], grid.origin[d] + grid.extent[d]
            if not lo <= probe.point[d] <= hi:
                errors.append((f"probes.{i}.point.{d}",
                               f"must lie inside the grid, in [{fmt(lo)}, {fmt(hi)}] (got {fmt(probe.point[d])})"))
    return errors
