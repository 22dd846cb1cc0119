"""``[[rigid_bodies]]``: rigid bodies moved by a prescribed velocity or driven by a force, in
frictional contact with the material (engine: ``constraint/rigid_body.rs``, docs/physics.md §8).

```toml
[[rigid_bodies]]
name = "footing"                 # names the history columns footing.force_x, ...
shape = "rectangle"              # any region shape of [[bodies]] (polygon: vertices = [[x, y], ...])
min = [0.0, 3.0]
max = [0.5, 3.2]
velocity = [0.0, -0.01]          # m/s, or motion = [[t, vx, vy], ...] (linear between rows)
friction = 0.0                   # Coulomb coefficient >= 0, or "rough" (no slip)
adhesion = 0.0                   # Pa: shear strength min(friction sigma_n + adhesion, adhesion_limit)
contact = "nodes"                # or "penalty", experimental (docs/studies/contact-remedies.md)
parts = [{ name = "tip", below = 0.0309 }, { name = "sleeve", below = 0.1646 }]  # optional
```

A force-driven body gives ``mass`` (kg, the whole body: per metre in plane strain, the whole
ring in axisymmetry) instead of ``velocity``/``motion``, with an optional ``force = [[t, fx,
fy], ...]`` (N, linear between rows) and ``initial_velocity``: it moves under that force,
gravity and the material's reaction (a maintained load, a free-falling penetrometer).

``parts`` names pieces of the body's reaction by height: the contact's correction along a face
goes to the first part whose ``below`` (m above the body's lowest point, in its own frame: the
heights move with the body) is at or above the point of the face where it acts, and above the
last ``below`` to ``rest``; a part ending at a vertex (a cone's shoulder) takes exactly the faces
below it. The history then has
``NAME.PART_force_y`` (and ``_x`` in plane strain) for each part and ``rest``, besides the
``base``/``shaft`` split by face normal; each split sums to ``NAME.force_y``. E.g. a cone
penetrometer: the cone below its shoulder is the tip, the 150 cm² friction sleeve above it.

A rigid body cuts its region out of every body (no particle is created inside it), so a
pre-embedded pile is one rigid body inside a soil layer. Its displacement is the integral of its
velocity. In axisymmetric runs only axial motion is allowed (every vx = 0). The path must keep
the body inside the grid until ``simulation.end_time``; a force-driven body that leaves the
grid ends the run as failed.

The region is one of the registered shapes (:mod:`.regions`), the same as a body's. The types
here give the schema; the engine checks the values and words the messages
(``axmpm._core.rigid_body_errors``), the front end only reports them under its dotted keys.
"""

from __future__ import annotations

import json
import math
import re
from typing import Annotated, Any, Literal, Union

from pydantic import BeforeValidator, Field

from ..engine import core
from .bodies import GridFrame, Region
from .fields import Section, Vec2
from .regions import REGIONS, default_shape

__all__ = ["RigidBody", "rigid_body_class", "rigid_body_errors", "reserved_names", "RIGID_BODY_SHAPES"]

Friction = Annotated[Any, Field(json_schema_extra={"anyOf": [{"type": "number", "minimum": 0},
                                                             {"const": "rough"}]})]


class RigidBodyHead(Section):
    """The first key of every rigid body."""

    name: str = Field(description="names the history columns NAME.force_x, NAME.displacement_y, ...; "
                      "no dots, commas or spaces, not the name of a grid face or wall")


class RigidBodyPart(Section):
    """One entry of a rigid body's ``parts``."""

    name: str = Field(description="names the history columns BODY.NAME_force_x/y; no dots, commas or spaces, "
                      "not base, shaft or rest")
    below: float = Field(description="m: the part's upper end above the body's lowest point (in the body's "
                         "own frame); > 0 and increasing along parts")


class RigidBodyKeys(Section):
    """The keys of every rigid body after its region's."""

    velocity: Vec2 | None = Field(None, description="m/s, constant; or give motion")
    motion: list[tuple[float, float, float]] | None = Field(
        None, description="[[t, vx, vy], ...] (s, m/s): velocity linear between rows, constant "
        "before the first and after the last; times increasing")
    mass: float | None = Field(None, description="kg, > 0: a body driven by its force, gravity and the "
                               "material's reaction instead of a velocity (the whole body: per metre in plane "
                               "strain, the whole ring in axisymmetry); no velocity or motion then")
    force: list[tuple[float, float, float]] | None = Field(
        None, description="[[t, fx, fy], ...] (s, N in the units of mass) on a body with a mass: linear between "
        "rows, constant before the first and after the last; times increasing (default: no force)")
    initial_velocity: Vec2 | None = Field(None, description="m/s at t = 0 of a body with a mass (default [0, 0])")
    friction: Friction = Field(0.0, description='Coulomb coefficient >= 0 (0 = smooth), or "rough" (no slip)')
    contact: Literal["nodes", "penalty"] = Field(
        "nodes", description='"nodes": velocity correction at the grid nodes the body covers; "penalty": '
        "pressure on the particles' domain corners inside the body, stiffness rho c_p^2 / h "
        "(experimental: needs experimental = true)")
    experimental: bool = Field(False, description="allow the experimental options (contact = \"penalty\")")
    adhesion: float = Field(0.0, description="Pa, >= 0: the interface's shear strength is "
                            "min(friction sigma_n + adhesion, adhesion_limit); alpha s_u with friction = 0 "
                            "is the alpha-method of pile design")
    adhesion_limit: float | None = Field(None, description="Pa, > 0: the largest shear stress of the "
                                         "interface (none: unlimited)")
    parts: list[RigidBodyPart] = Field(
        default_factory=list, description="named parts of the reaction by height, [{ name, below }, ...]: "
        "the contact force on a face goes to the first part whose below (m above the body's lowest point, "
        "in its own frame) is at or above where it acts, above the last to rest; history columns "
        "NAME.PART_force_y (and _x in plane strain) per part and rest")


def rigid_body_class(region: type[Region]) -> type[Section]:
    """The ``[[rigid_bodies]]`` class of a region shape: the rigid-body keys around the region's."""
    doc = f"``[[rigid_bodies]]`` whose region is {region.__doc__ or region.__name__}"
    return type(region.__name__ + "RigidBody", (RigidBodyKeys, region, RigidBodyHead),
                {"__doc__": doc, "__module__": __name__})


#: shape name → rigid-body class, for every registered region shape.
RIGID_BODY_SHAPES: dict[str, type[Any]] = {name: rigid_body_class(region) for name, region in REGIONS.items()}

#: The type of one ``[[rigid_bodies]]`` table: the shapes discriminated by ``shape`` (a rectangle
#: when it is absent).
RigidBody: Any = (next(iter(RIGID_BODY_SHAPES.values())) if len(RIGID_BODY_SHAPES) == 1 else
                  Annotated[Union[tuple(RIGID_BODY_SHAPES.values())],  # type: ignore[misc]
                            Field(discriminator="shape"), BeforeValidator(default_shape)])


def _dotted(key: str) -> str:
    """The engine's key (``rigid_bodies[0].motion[2][0]``) as the front end's (``rigid_bodies.0.motion.2.0``)."""
    return re.sub(r"\[(\d+)\]", r".\1", key)


def reserved_names(wall_count: int) -> list[str]:
    """The names the grid faces, the axis and the ``wall_count`` walls report their reactions
    under (the engine's list; a rigid body or a surcharge may not take one)."""
    return list(core().reserved_names(wall_count))


def rigid_body_errors(bodies: list[Any | None], grid: GridFrame | None, axisymmetric: bool | None,
                      end_time: float | None, wall_count: int) -> list[tuple[str, str]]:
    """The engine's refusals of the rigid bodies (``None``: a table that failed its own field
    checks, left out): its region, inside the grid and kept there by its path until
    ``end_time`` (``grid`` or ``end_time`` None: not checked), one motion, axial motion only in
    axisymmetry, the contact and its adhesion, unique names that are not those of the grid
    faces or of the ``wall_count`` walls. At most one problem per body."""
    lo, hi = (grid.lo, grid.hi) if grid is not None else ((-math.inf, -math.inf), (math.inf, math.inf))
    end = math.inf if end_time is None or grid is None else end_time
    tables = [None if b is None else b.model_dump(mode="json", exclude_none=True) for b in bodies]
    found = core().rigid_body_errors(json.dumps(tables), tuple(lo), tuple(hi), bool(axisymmetric), end, wall_count)
    return [(_dotted(key), message) for key, message in found]
