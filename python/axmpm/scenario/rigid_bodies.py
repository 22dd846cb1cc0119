"""``[[rigid_bodies]]``: rigid bodies moved by a prescribed velocity, in frictional contact with
the material (engine: ``constraint/rigid_body.rs``, docs/physics.md §8).

```toml
[[rigid_bodies]]
name = "footing"                 # names the history columns footing.force_x, ...
shape = "rectangle"              # or "polygon" with vertices = [[x, y], ...]
min = [0.0, 3.0]
max = [0.5, 3.2]
velocity = [0.0, -0.01]          # m/s, or motion = [[t, vx, vy], ...] (linear between rows)
friction = 0.0                   # Coulomb coefficient >= 0, or "rough" (no slip)
contact = "nodes"                # or "penalty", experimental (docs/studies/contact-remedies.md)
```

A rigid body cuts its region out of every body (no particle is created inside it), so a
pre-embedded pile is one rigid body inside a soil layer. Its displacement is the integral of its
velocity. In axisymmetric runs only axial motion is allowed (every vx = 0).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BeforeValidator, Field
from pydantic_core import PydanticCustomError

from .bodies import GridFrame
from .fields import Section, Vec2, fmt
from .regions.polygon import inside_polygon, polygon_problem

__all__ = ["RigidBody", "rigid_body_errors", "FACE_NAMES"]

#: Names the grid faces report their reactions under (a rigid body may not take them).
FACE_NAMES = ("left", "right", "bottom", "top", "axis")


def _friction(value: Any) -> Any:
    if isinstance(value, str) and value == "rough":
        return value
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value >= 0 and value == value \
            and value != float("inf"):
        return float(value)
    raise PydanticCustomError("friction", 'must be a number >= 0 or "rough" (got {value})', {"value": repr(value)})


Friction = Annotated[Any, BeforeValidator(_friction),
                     Field(json_schema_extra={"anyOf": [{"type": "number", "minimum": 0}, {"const": "rough"}]})]


class RigidBody(Section):
    """``[[rigid_bodies]]``: a rectangle or polygon moved by a prescribed velocity."""

    name: str = Field(pattern=r"^[A-Za-z_][A-Za-z0-9_-]*$",
                      description="names the history columns NAME.force_x, NAME.displacement_y, ...")
    shape: Literal["rectangle", "polygon"] = "rectangle"
    min: Vec2 | None = Field(None, description="m, rectangle")
    max: Vec2 | None = Field(None, description="m, rectangle")
    vertices: list[Vec2] | None = Field(None, description="m, polygon: [[x, y], ...], either orientation")
    velocity: Vec2 | None = Field(None, description="m/s, constant; or give motion")
    motion: list[tuple[float, float, float]] | None = Field(
        None, description="[[t, vx, vy], ...] (s, m/s): velocity linear between rows, constant "
        "before the first and after the last; times increasing")
    friction: Friction = Field(0.0, description='Coulomb coefficient >= 0 (0 = smooth), or "rough" (no slip)')
    contact: Literal["nodes", "penalty"] = Field(
        "nodes", description='"nodes": velocity correction at the grid nodes the body covers; "penalty": '
        "pressure on the particles' domain corners inside the body, stiffness rho c_p^2 / h "
        "(experimental: needs experimental = true)")
    experimental: bool = Field(False, description="allow the experimental options (contact = \"penalty\")")

    def outline(self) -> list[Vec2] | None:
        """The region as a polygon (a rectangle's four corners), or None when it is invalid."""
        if self.shape == "rectangle":
            if self.min is None or self.max is None:
                return None
            (x0, y0), (x1, y1) = self.min, self.max
            if not (x0 < x1 and y0 < y1):
                return None
            return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        if self.vertices is None or polygon_problem(self.vertices) is not None:
            return None
        return list(self.vertices)

    def contains(self, points: np.ndarray) -> np.ndarray:
        """Which points (N × 2) lie inside the body at t = 0 (boundary included)."""
        outline = self.outline()
        if outline is None:
            return np.zeros(len(points), dtype=bool)
        return inside_polygon(outline, points)


#: The engine's reason (constraint/rigid_body.rs, PENALTY_IS_EXPERIMENTAL).
PENALTY_IS_EXPERIMENTAL = ('"penalty" is experimental (measured, not adopted: the footing\'s N_c comes out 8-20 % '
                           'high; docs/studies/contact-remedies.md): set experimental = true in this rigid body '
                           'to use it')


def rigid_body_errors(bodies: list[RigidBody | None], grid: GridFrame | None, axisymmetric: bool | None,
                      taken: set[str]) -> list[tuple[str, str]]:
    """Checks of every rigid body: its shape's keys, a simple polygon, inside the grid, one
    motion (velocity or an increasing table), axial motion only in axisymmetry, unique names
    that are not those of other constraints (``taken``)."""
    errors: list[tuple[str, str]] = []
    seen: set[str] = set()
    for i, body in enumerate(bodies):
        if body is None:
            continue
        key = f"rigid_bodies.{i}"
        if body.name in seen:
            errors.append((f"{key}.name", f"duplicate rigid body name {body.name!r}"))
        elif body.name in taken:
            errors.append((f"{key}.name", f"{body.name!r} is the name of a grid face or wall (its reaction "
                           "columns would clash): choose another"))
        seen.add(body.name)
        if body.shape == "rectangle":
            for k in ("min", "max"):
                if getattr(body, k) is None:
                    errors.append((f"{key}.{k}", 'is required for shape = "rectangle"'))
            if body.vertices is not None:
                errors.append((f"{key}.vertices", 'is only valid for shape = "polygon"'))
            if body.min is not None and body.max is not None:
                for axis in (0, 1):
                    if not body.min[axis] < body.max[axis]:
                        errors.append((f"{key}.max.{axis}", f"must be > min.{axis} = {fmt(body.min[axis])} "
                                       f"(got {fmt(body.max[axis])})"))
        else:
            if body.vertices is None:
                errors.append((f"{key}.vertices", 'is required for shape = "polygon"'))
            else:
                problem = polygon_problem(body.vertices)
                if problem is not None:
                    errors.append((f"{key}.vertices", problem))
            for k in ("min", "max"):
                if getattr(body, k) is not None:
                    errors.append((f"{key}.{k}", 'is only valid for shape = "rectangle"'))
        outline = body.outline()
        if outline is not None and grid is not None:
            xs, ys = [p[0] for p in outline], [p[1] for p in outline]
            if min(xs) < grid.lo[0] - grid.tol or min(ys) < grid.lo[1] - grid.tol \
                    or max(xs) > grid.hi[0] + grid.tol or max(ys) > grid.hi[1] + grid.tol:
                errors.append((key, f"the rigid body [{fmt(min(xs))}, {fmt(max(xs))}] x [{fmt(min(ys))}, "
                               f"{fmt(max(ys))}] must lie inside the grid [{fmt(grid.lo[0])}, {fmt(grid.hi[0])}] x "
                               f"[{fmt(grid.lo[1])}, {fmt(grid.hi[1])}]"))
        if body.contact == "penalty" and not body.experimental:
            errors.append((f"{key}.contact", PENALTY_IS_EXPERIMENTAL))
        if body.velocity is None and body.motion is None:
            errors.append((f"{key}.velocity", "is required (or a motion table)"))
        elif body.velocity is not None and body.motion is not None:
            errors.append((f"{key}.motion", "give either velocity or motion, not both"))
        elif body.velocity is not None:
            if axisymmetric and body.velocity[0] != 0.0:
                errors.append((f"{key}.velocity.0", "must be 0 in axisymmetric runs (a body of revolution "
                               f"moves along the axis only) (got {fmt(body.velocity[0])})"))
        else:
            rows = body.motion or []
            if not rows:
                errors.append((f"{key}.motion", "must have at least one row [t, vx, vy]"))
            for k, row in enumerate(rows):
                if k == 0 and row[0] < 0.0:
                    errors.append((f"{key}.motion.0.0", f"the first time must be >= 0 (got {fmt(row[0])})"))
                if k > 0 and not row[0] > rows[k - 1][0]:
                    errors.append((f"{key}.motion.{k}.0", f"times must increase (got {fmt(row[0])} after "
                                   f"{fmt(rows[k - 1][0])})"))
                if axisymmetric and row[1] != 0.0:
                    errors.append((f"{key}.motion.{k}.1", "vx must be 0 in axisymmetric runs (a body of "
                                   f"revolution moves along the axis only) (got {fmt(row[1])})"))
    return errors
