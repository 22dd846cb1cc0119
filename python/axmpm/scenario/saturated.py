"""Saturated soil: a body's ``saturated`` table (its pore water) and the run's ``[drainage]``
(which grid faces let the water out). The engine's two-phase step runs only when some body has
a ``saturated`` table; a body's material is then its effective-stress skeleton and its
``density`` the density of the grains (docs/physics.md, "Saturated soil").
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field

from .fields import NonNegative, Positive, Section, bounded, fmt, on_grid_line

__all__ = ["Saturated", "Drainage", "saturated_errors"]


class Saturated(Section):
    """``[bodies.saturated]``: the pore water of a saturated body."""

    porosity: bounded(0.0, 1.0, lo_open=True, hi_open=True) = Field(  # type: ignore[valid-type]
        description="initial porosity n (updated with the volume; the grains are incompressible)"
    )
    hydraulic_conductivity: Positive = Field(  # type: ignore[valid-type]
        description="k, m/s (Darcy; defined under standard gravity 9.81 m/s²)"
    )
    water_bulk_modulus: Positive = Field(2.2e9, description="K_w, Pa")  # type: ignore[valid-type]
    water_density: Positive = Field(1000.0, description="ρ_w, kg/m³")  # type: ignore[valid-type]
    water_table: float | None = Field(
        None, description="m: initial pore pressure hydrostatic below this height, 0 above"
    )
    pore_pressure: float | None = Field(
        None, description="Pa, initial uniform pore pressure (compression positive) when no water_table"
    )
    surface_load: NonNegative = Field(  # type: ignore[valid-type]
        0.0, description="Pa, a uniform pressure on the body's top surface from t = 0 on"
    )
    loading_plate: bool = Field(
        False, description="the surface_load acts through a rigid, frictionless, impermeable plate: the nodes "
                           "of the grid row at the body's top (which must lie on a grid line) move down together"
    )


DrainageName = Literal["drained", "impermeable"]


class Drainage(Section):
    """``[drainage]``: what each grid face does to the pore water. A face not given is
    impermeable when its boundary condition supports the solid and drained when it is free;
    the axis and the walls are impermeable."""

    left: DrainageName | None = None
    right: DrainageName | None = None
    bottom: DrainageName | None = None
    top: DrainageName | None = None


def saturated_errors(bodies: list[Any] | None, grid: Any) -> list[tuple[str, str]]:
    """Cross checks of the ``saturated`` tables: the water table inside the grid, one way to
    give the initial pressure, one pore water for the whole run."""
    errors: list[tuple[str, str]] = []
    water: tuple[float, float] | None = None
    for i, body in enumerate(bodies or []):
        s = getattr(body, "saturated", None)
        if s is None:
            continue
        key = f"bodies.{i}.saturated"
        if s.water_table is not None and grid is not None:
            lo, hi = grid.origin[1], grid.origin[1] + grid.extent[1]
            if not lo <= s.water_table <= hi:
                errors.append((f"{key}.water_table",
                               f"must lie inside the grid, in [{fmt(lo)}, {fmt(hi)}] (got {fmt(s.water_table)})"))
        if s.loading_plate and s.surface_load <= 0.0:
            errors.append((f"{key}.loading_plate", "the plate carries the surface_load: give a surface_load > 0"))
        if s.loading_plate and grid is not None:
            box = body.bounding_box()
            if box is not None and not on_grid_line(box[1][1], grid.origin[1], grid.cell_size):
                errors.append((f"{key}.loading_plate",
                               f"the body's top ({fmt(box[1][1])}) must lie on a grid line (multiples of "
                               f"{fmt(grid.cell_size)} m from {fmt(grid.origin[1])})"))
        if s.water_table is not None and s.pore_pressure is not None:
            errors.append((f"{key}.pore_pressure", "give either water_table or pore_pressure, not both"))
        this = (s.water_bulk_modulus, s.water_density)
        if water is None:
            water = this
        elif this != water:
            errors.append((f"{key}.water_bulk_modulus",
                           "every saturated body holds the same pore water: water_bulk_modulus and "
                           f"water_density must equal the first saturated body's ({fmt(water[0])}, {fmt(water[1])})"))
    return errors
