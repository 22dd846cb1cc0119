"""``[boundaries]`` (the four grid faces) and ``[[walls]]`` (straight rigid walls on grid lines)."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field
from pydantic_core import PydanticCustomError

from .fields import NonNegative, Section

__all__ = ["BoundaryCondition", "Boundaries", "Wall", "Face"]


BoundaryName = Literal["free", "roller", "fixed", "friction"]


class BoundaryCondition(Section):
    """A face or wall condition; ``coefficient`` is the Coulomb friction μ (friction only)."""

    condition: BoundaryName
    coefficient: NonNegative = 0.0


def _condition_from_string(value: Any) -> Any:
    """Accept ``"roller"`` as shorthand for ``{condition = "roller", coefficient = 0}``."""
    if isinstance(value, str):
        return {"condition": value}
    if isinstance(value, (dict, BoundaryCondition)):
        return value
    raise PydanticCustomError(
        "boundary_type",
        'must be a condition name ("free", "roller", "fixed", "friction") or a table '
        "with keys condition and coefficient (got {value})",
        {"value": repr(value)},
    )


Face = Annotated[BoundaryCondition, BeforeValidator(_condition_from_string)]


def _free() -> BoundaryCondition:
    return BoundaryCondition(condition="free")


class Boundaries(Section):
    """``[boundaries]``: conditions on the four grid faces (r = 0 is the left face)."""

    left: Face = Field(default_factory=_free)
    right: Face = Field(default_factory=_free)
    bottom: Face = Field(default_factory=_free)
    top: Face = Field(default_factory=_free)


class Wall(Section):
    """``[[walls]]``: a straight rigid wall on a grid line inside the grid."""

    axis: Literal["x", "y"] = Field(description='"x": the line x = position; "y": the line y = position')
    position: float = Field(description="m, on a grid line")
    material_side: Literal["negative", "positive"]
    condition: Literal["roller", "fixed", "friction"]
    coefficient: NonNegative = 0.0
    removal_time: NonNegative | None = Field(None, description="s; absent = never removed")  # type: ignore[valid-type]
