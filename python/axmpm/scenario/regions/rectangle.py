"""``shape = "rectangle"``: an axis-aligned rectangle [min, max] with its corners on grid lines."""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

from pydantic import Field

from ..bodies import GridFrame, Region
from ..fields import Vec2, fmt, on_grid_line
from . import register_region
from .polygon import lattice_centres

if TYPE_CHECKING:
    import numpy as np


@register_region("rectangle")
class Rectangle(Region):
    """an axis-aligned rectangle (``shape = "rectangle"``, the default): ``min`` and ``max``
    corners, on grid lines."""

    shape: Literal["rectangle"] = "rectangle"
    min: Vec2 = Field(description="m (a body's: on grid lines)")
    max: Vec2 = Field(description="m (a body's: on grid lines)")

    def bounding_box(self) -> tuple[Vec2, Vec2] | None:
        if self.min[0] < self.max[0] and self.min[1] < self.max[1]:
            return self.min, self.max
        return None

    def region_errors(self, key: str, grid: GridFrame | None) -> list[tuple[str, str]]:
        errors: list[tuple[str, str]] = []
        for axis in (0, 1):
            bmin, bmax = self.min[axis], self.max[axis]
            if not bmin < bmax:
                errors.append((f"{key}.max.{axis}", f"must be > min.{axis} = {fmt(bmin)} (got {fmt(bmax)})"))
            if grid is None:
                continue
            lo, hi = grid.lo[axis], grid.hi[axis]
            for which, value in (("min", bmin), ("max", bmax)):
                if value < lo - grid.tol or value > hi + grid.tol:
                    errors.append((f"{key}.{which}.{axis}",
                                   f"must be inside the grid [{fmt(lo)}, {fmt(hi)}] (got {fmt(value)})"))
                elif not on_grid_line(value, lo, grid.h):
                    errors.append((f"{key}.{which}.{axis}",
                                   f"must lie on a grid line (multiples of {fmt(grid.h)} m from the "
                                   f"origin {fmt(lo)}) (got {fmt(value)})"))
        return errors

    def contains(self, points: "np.ndarray") -> "np.ndarray":
        (x0, y0), (x1, y1) = self.min, self.max
        return (points[:, 0] >= x0) & (points[:, 0] <= x1) & (points[:, 1] >= y0) & (points[:, 1] <= y1)

    def lattice_points(self, origin: Vec2, cell_size: float) -> "np.ndarray":
        """The body's particle positions (N × 2): every lattice point of its cells."""
        if self.bounding_box() is None:
            import numpy as np

            return np.zeros((0, 2))
        return lattice_centres(self.min, self.max, origin, cell_size, self.particles_per_cell)

    def particle_count(self, cell_size: float) -> int:
        nx = int(round((self.max[0] - self.min[0]) / cell_size))
        ny = int(round((self.max[1] - self.min[1]) / cell_size))
        return nx * ny * self.particles_per_cell**2
