"""Body regions (``shape = "..."`` of a ``[[bodies]]`` table), one module per shape, each
registered by name.

Adding a shape = one module here with a region registered by the decorator::

    @register_region("polygon")
    class Polygon(Region):
        # docstring: "a polygon of ..." (completes "[[bodies]] whose region is ...")

        shape: Literal["polygon"]
        vertices: list[Vec2] = Field(description="m, counter-clockwise")

        def bounding_box(self): ...
        def region_errors(self, key, grid): ...
        def particle_count(self, cell_size): ...

The body class of the shape (``REGION_SHAPES["polygon"]``) has the common body keys around
the region's (:func:`~axmpm.scenario.bodies.body_class`).
Every module of this package is imported with it; the engine builds the same shape from the
same keys (``geometry/`` in the engine, docs/architecture.md). ``shape`` may be omitted for a
rectangle (the default).
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable
from typing import Annotated, Any, Union

from pydantic import BeforeValidator, Field

from ...catalogue import region_shapes
from ..bodies import Region, body_class

__all__ = ["register_region", "REGION_SHAPES", "REGIONS", "DEFAULT_SHAPE", "body_type", "shape_names",
           "default_shape"]

#: shape name → body class (the common body keys around the region's).
REGION_SHAPES: dict[str, type[Any]] = {}
#: shape name → the region alone (its keys and geometry), e.g. for ``[[rigid_bodies]]``.
REGIONS: dict[str, type[Region]] = {}
#: The shape of a body table without ``shape``.
DEFAULT_SHAPE = "rectangle"


def register_region(name: str) -> Callable[[type[Region]], type[Region]]:
    """Class decorator: register a region under its ``shape`` name (the body class is built
    from it, :func:`~axmpm.scenario.bodies.body_class`); returns the region unchanged."""

    def decorate(region: type[Region]) -> type[Region]:
        if name in REGION_SHAPES:
            raise ValueError(f"region shape {name!r} is registered twice")
        REGION_SHAPES[name] = body_class(region)
        REGIONS[name] = region
        return region

    return decorate


for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")


def shape_names() -> list[str]:
    """The registered shapes: the engine's catalogue order first, then any others by name
    (loads the engine: for messages, not at import)."""
    engine = [s for s in region_shapes() if s in REGION_SHAPES]
    return engine + sorted(set(REGION_SHAPES) - set(engine))


def default_shape(value: Any) -> Any:
    if isinstance(value, dict) and "shape" not in value:
        return {**value, "shape": DEFAULT_SHAPE}
    return value


def body_type() -> Any:
    """The type of one ``[[bodies]]`` table: the registered shapes discriminated by ``shape``
    (a rectangle when it is absent)."""
    classes = tuple(REGION_SHAPES.values())
    if len(classes) == 1:
        return classes[0]
    return Annotated[Union[classes], Field(discriminator="shape"),  # type: ignore[valid-type]
                     BeforeValidator(default_shape)]
