"""``shape = "polygon"``: a simple polygon ``vertices = [[x, y], ...]`` (any orientation).

The engine's ``geometry/polygon.rs`` builds the same polygon from the same key. A polygon body
gets the particles of its n × n-per-cell lattice (sub-cell centres, as every body) whose centres
lie inside the polygon (boundary included); cells cut by the boundary get fewer particles, each
of the full sub-cell volume (particle volumes are not trimmed to the boundary).

The checks here repeat the engine's (degenerate or self-intersecting polygons are reported with
the key) so that ``axmpm check`` names the problem before the engine is built; a rigid body of
this shape (:mod:`..rigid_bodies`) is checked by the engine alone.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from pydantic import Field

from ..bodies import GridFrame, Region
from ..fields import Vec2, fmt
from . import register_region

__all__ = ["Polygon", "polygon_problem", "inside_polygon", "lattice_centres"]


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def _orientation(a: Vec2, b: Vec2, c: Vec2) -> float:
    return _cross(b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1])


def _segments_meet(p1: Vec2, p2: Vec2, p3: Vec2, p4: Vec2, eps: float) -> bool:
    """The closed segments p1p2 and p3p4 share a point (orientation tolerance ``eps``)."""
    d1, d2 = _orientation(p3, p4, p1), _orientation(p3, p4, p2)
    d3, d4 = _orientation(p1, p2, p3), _orientation(p1, p2, p4)

    def opposite(a: float, b: float) -> bool:
        return (a > eps and b < -eps) or (a < -eps and b > eps)

    if opposite(d1, d2) and opposite(d3, d4):
        return True

    def on(a: Vec2, b: Vec2, p: Vec2, d: float) -> bool:
        return (abs(d) <= eps
                and min(a[0], b[0]) - 1e-12 <= p[0] <= max(a[0], b[0]) + 1e-12
                and min(a[1], b[1]) - 1e-12 <= p[1] <= max(a[1], b[1]) + 1e-12)

    return on(p3, p4, p1, d1) or on(p3, p4, p2, d2) or on(p1, p2, p3, d3) or on(p1, p2, p4, d4)


def closed_vertices(vertices: list[Vec2]) -> list[Vec2]:
    """The vertices without a last one repeating the first (the polygon closes itself)."""
    v = [tuple(map(float, p)) for p in vertices]
    if len(v) > 3 and v[0] == v[-1]:
        v = v[:-1]
    return v  # type: ignore[return-value]


def polygon_problem(vertices: list[Vec2]) -> str | None:
    """Why ``vertices`` do not make a simple polygon with an area, or None (the engine's checks)."""
    v = closed_vertices(vertices)
    n = len(v)
    if n < 3:
        return f"a polygon needs at least 3 vertices (got {n})"
    xs, ys = [p[0] for p in v], [p[1] for p in v]
    diagonal = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    eps = 1e-12 * diagonal * diagonal
    for i in range(n):
        j = (i + 1) % n
        if v[i] == v[j]:
            return f"vertices {i} and {j} coincide at ({fmt(v[i][0])}, {fmt(v[i][1])}) (degenerate edge)"
    for i in range(n):
        a, b, c = v[i], v[(i + 1) % n], v[(i + 2) % n]
        turn = _orientation(a, b, c)
        back = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1])
        if abs(turn) <= eps and back < 0.0:
            k = (i + 1) % n
            return f"edges {i} and {k} fold back onto each other at vertex {k} (degenerate)"
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            if _segments_meet(v[i], v[(i + 1) % n], v[j], v[(j + 1) % n], eps):
                return (f"edges {i} and {j} intersect: the polygon must be simple (not self-intersecting)")
    area2 = sum(_cross(v[i][0], v[i][1], v[(i + 1) % n][0], v[(i + 1) % n][1]) for i in range(n))
    if not abs(area2) > eps:
        return "the polygon has zero area (degenerate: collinear vertices)"
    return None


def inside_polygon(vertices: list[Vec2], points: np.ndarray) -> np.ndarray:
    """Which of ``points`` (N × 2) lie inside the polygon (crossing number, boundary included
    within 1e-12 of the bounding-box diagonal, as the engine's ``contains``)."""
    v = np.asarray(closed_vertices(vertices), dtype=float)
    x, y = points[:, 0], points[:, 1]
    inside = np.zeros(len(points), dtype=bool)
    nearest = np.full(len(points), np.inf)
    n = len(v)
    for i in range(n):
        a, b = v[i], v[(i + 1) % n]
        crosses = (a[1] > y) != (b[1] > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            at = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
        inside ^= crosses & (x < at)
        e = b - a
        t = np.clip(((x - a[0]) * e[0] + (y - a[1]) * e[1]) / (e @ e), 0.0, 1.0)
        nearest = np.minimum(nearest, np.hypot(x - (a[0] + t * e[0]), y - (a[1] + t * e[1])))
    diagonal = float(np.hypot(*(v.max(axis=0) - v.min(axis=0))))
    return inside | (nearest <= 1e-12 * diagonal)


def lattice_centres(lo: Vec2, hi: Vec2, origin: Vec2, cell_size: float, n: int) -> np.ndarray:
    """The n × n-per-cell lattice points (sub-cell centres) of the cells covering [lo, hi]
    (rounded outwards to grid lines, as the engine's ``geometry::lattice_points``)."""
    spacing = cell_size / n
    axes = []
    for d in (0, 1):
        first = math.floor((lo[d] - origin[d]) / cell_size + 1e-6)
        end = math.ceil((hi[d] - origin[d]) / cell_size - 1e-6)
        cells = np.arange(max(first, 0), max(end, 0))
        sub = (np.arange(n) + 0.5) * spacing
        axes.append((origin[d] + cells[:, None] * cell_size + sub[None, :]).ravel())
    xx, yy = np.meshgrid(axes[0], axes[1])
    return np.column_stack([xx.ravel(), yy.ravel()])


@register_region("polygon")
class Polygon(Region):
    """a simple polygon (``shape = "polygon"``): ``vertices`` in either orientation, not
    self-intersecting; particles where the lattice points fall inside."""

    shape: Literal["polygon"]
    vertices: list[Vec2] = Field(description="m, [[x, y], ...], either orientation, the polygon closes itself",
                                 min_length=3)

    def bounding_box(self) -> tuple[Vec2, Vec2] | None:
        if polygon_problem(self.vertices) is not None:
            return None
        xs, ys = [p[0] for p in self.vertices], [p[1] for p in self.vertices]
        return (min(xs), min(ys)), (max(xs), max(ys))

    def region_errors(self, key: str, grid: GridFrame | None) -> list[tuple[str, str]]:
        problem = polygon_problem(self.vertices)
        if problem is not None:
            return [(f"{key}.vertices", problem)]
        if grid is None:
            return []
        (x0, y0), (x1, y1) = self.bounding_box()  # type: ignore[misc]
        if x0 < grid.lo[0] - grid.tol or y0 < grid.lo[1] - grid.tol or x1 > grid.hi[0] + grid.tol \
                or y1 > grid.hi[1] + grid.tol:
            return [(f"{key}.vertices",
                     f"must lie inside the grid [{fmt(grid.lo[0])}, {fmt(grid.hi[0])}] x "
                     f"[{fmt(grid.lo[1])}, {fmt(grid.hi[1])}] (the polygon spans [{fmt(x0)}, {fmt(x1)}] x "
                     f"[{fmt(y0)}, {fmt(y1)}])")]
        return []

    def contains(self, points: np.ndarray) -> np.ndarray:
        if polygon_problem(self.vertices) is not None:
            return np.zeros(len(points), dtype=bool)
        return inside_polygon(self.vertices, points)

    def lattice_points(self, origin: Vec2, cell_size: float) -> np.ndarray:
        """The body's particle positions (N × 2)."""
        box = self.bounding_box()
        if box is None:
            return np.zeros((0, 2))
        points = lattice_centres(box[0], box[1], origin, cell_size, self.particles_per_cell)
        return points[inside_polygon(self.vertices, points)]

    def particle_count(self, cell_size: float) -> int:
        # The lattice is anchored on the grid; without the grid's origin, anchor on 0 (the
        # scenario passes the origin through lattice_points when it has it).
        return int(len(self.lattice_points((0.0, 0.0), cell_size)))
