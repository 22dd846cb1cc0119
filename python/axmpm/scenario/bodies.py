"""``[[bodies]]``: a region of material filled with particles on a regular lattice.

The keys every body has are here (:class:`BodyHead`, :class:`BodyKeys`); the region's own keys
(``shape`` and, for a rectangle, ``min`` and ``max``) come from the shape's module in
:mod:`.regions`, which registers a :class:`Region` per shape.
:func:`~.regions.body_type` is the type of one ``[[bodies]]`` table.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, ValidationError
from pydantic_core import PydanticCustomError

from .fields import GRID_TOLERANCE, NonNegative, Section, Vec2, bounded, fmt
from .saturated import Saturated

__all__ = ["BodyHead", "BodyKeys", "Region", "GridFrame", "body_class", "overlaps"]


class GridFrame:
    """What a region checks itself against: the grid's lower and upper corners and cell size."""

    def __init__(self, lo: Vec2, hi: Vec2, cell_size: float):
        self.lo, self.hi, self.h = lo, hi, cell_size
        self.tol = GRID_TOLERANCE * cell_size


class BodyHead(Section):
    """The first keys of every body."""

    name: str | None = Field(None, description="resolved default: body_<index>")
    material: str


class VerticalHorizontalStress(Section):
    """``initial_stress = { vertical = ..., horizontal = ... }``: a uniform stress, Pa, tension
    positive (compression negative): σ_yy = vertical, σ_xx = σ_zz (σ_θθ) = horizontal, no shear."""

    vertical: float = Field(description="Pa, tension positive: sigma_yy")
    horizontal: float = Field(description="Pa, tension positive: sigma_xx and the out-of-plane (hoop) component")


class StressComponents(Section):
    """``initial_stress = { xx = ..., yy = ..., zz = ..., xy = ... }``: a uniform stress, Pa,
    tension positive; axisymmetric: xx = rr, yy = zz (axial), zz = θθ (hoop), xy = rz."""

    xx: float = Field(description="Pa, tension positive")
    yy: float = Field(description="Pa, tension positive")
    zz: float = Field(description="Pa, tension positive: out of plane (hoop in axisymmetry)")
    xy: float = Field(0.0, description="Pa")


_STRESS_FORMS = '"zero", "geostatic", { vertical = ..., horizontal = ... } or { xx = ..., yy = ..., zz = ..., xy = ... } (Pa)'


def _initial_stress(value: Any) -> Any:
    """One message for every wrong form, instead of one per member of the union."""
    if value in ("zero", "geostatic") or isinstance(value, (VerticalHorizontalStress, StressComponents)):
        return value
    if isinstance(value, dict):
        form = VerticalHorizontalStress if {"vertical", "horizontal"} & set(value) else StressComponents
        try:
            return form.model_validate(value)
        except ValidationError as e:
            problem = "; ".join(f"{'.'.join(map(str, err['loc']))}: {err['msg']}" for err in e.errors())
            raise PydanticCustomError("initial_stress", "must be {forms}: {problem} (got {value})",
                                      {"forms": _STRESS_FORMS, "problem": problem, "value": repr(value)}) from None
    raise PydanticCustomError("initial_stress", "must be {forms} (got {value})",
                              {"forms": _STRESS_FORMS, "value": repr(value)})


InitialStress = Annotated[Any, BeforeValidator(_initial_stress), Field(json_schema_extra={"anyOf": [
    {"enum": ["zero", "geostatic"]},
    {"type": "object", "properties": {"vertical": {"type": "number"}, "horizontal": {"type": "number"}},
     "required": ["vertical", "horizontal"], "additionalProperties": False},
    {"type": "object", "properties": {k: {"type": "number"} for k in ("xx", "yy", "zz", "xy")},
     "required": ["xx", "yy", "zz"], "additionalProperties": False}]})]


class BodyKeys(Section):
    """The keys of every body after its region's."""

    particles_per_cell: bounded(1, 8, kind=int) = Field(  # type: ignore[valid-type]
        2, description="per direction"
    )
    velocity: Vec2 = Field((0.0, 0.0), description="m/s")
    initial_stress: InitialStress = Field(
        "zero",
        description='"zero"; "geostatic" (sigma_v from the weight of all material above and the '
        "surcharges, sigma_h = k0 sigma_v; needs gravity); or a uniform stress in Pa, tension positive: "
        "{ vertical = ..., horizontal = ... } or { xx = ..., yy = ..., zz = ..., xy = ... }",
    )
    k0: NonNegative | None = Field(  # type: ignore[valid-type]
        None,
        description="lateral earth pressure ratio; resolved default: the material model's "
        "(nu/(1-nu) for elastic models, 1 - sin(phi) for mohr_coulomb)",
    )
    allow_overlap: bool = Field(
        False,
        strict=True,
        description="true: this body may overlap other bodies (particles are then superposed, "
        "adding mass); false: an overlap with another body that does not allow it is an error",
    )
    saturated: Saturated | None = Field(
        None, description="pore water (two-phase saturated soil); absent: a dry or total-stress body"
    )


class Region(Section):
    """A body's region: the ``shape`` tag, the shape's own keys, and the geometry the checks
    need. Each shape module (:mod:`.regions`) subclasses it and registers it; the body class of
    a shape is ``BodyHead`` keys, then the region's, then ``BodyKeys`` (:func:`body_class`)."""

    def bounding_box(self) -> tuple[Vec2, Vec2] | None:
        """(min, max) corners, or None when the region is degenerate (its own error reports it)."""
        raise NotImplementedError

    def region_errors(self, key: str, grid: GridFrame | None) -> list[tuple[str, str]]:
        """Problems of the region alone (``grid`` None: the grid is invalid), keys under ``key``."""
        raise NotImplementedError

    def particle_count(self, cell_size: float) -> int:
        """Number of particles the engine creates for this body (``self.particles_per_cell`` per
        direction and cell)."""
        raise NotImplementedError

    def lattice_points(self, origin: Vec2, cell_size: float) -> Any:
        """The positions (N × 2 numpy array) of the particles the engine creates for this body
        alone (before rigid bodies cut theirs out), on the grid anchored at ``origin``."""
        raise NotImplementedError


def body_class(region: type[Region]) -> type[Section]:
    """The ``[[bodies]]`` class of a shape: the common keys around the region's keys (in the
    order the resolved scenario lists them: name, material, shape, region keys, the rest)."""
    name = region.__name__ + "Body"
    doc = f"``[[bodies]]`` whose region is {region.__doc__ or region.__name__}"
    return type(name, (BodyKeys, region, BodyHead), {"__doc__": doc, "__module__": region.__module__})


def overlaps(bodies: list[Any], h: float | None) -> list[tuple[str, str]]:
    """Pairs of bodies whose bounding boxes share an area (touching edges are fine; exact for
    rectangles), unless one of the two has ``allow_overlap = true``. Reported on the later body."""
    errors: list[tuple[str, str]] = []
    boxes = [(i, b, b.bounding_box()) for i, b in enumerate(bodies) if b is not None]
    valid = [(i, b, box) for i, b, box in boxes if box is not None]
    for jj, (j, b, (b_lo, b_hi)) in enumerate(valid):
        for i, a, (a_lo, a_hi) in valid[:jj]:
            if a.allow_overlap or b.allow_overlap:
                continue
            x0, x1 = max(a_lo[0], b_lo[0]), min(a_hi[0], b_hi[0])
            y0, y1 = max(a_lo[1], b_lo[1]), min(a_hi[1], b_hi[1])
            tol = GRID_TOLERANCE * h if h is not None else 0.0
            if x1 - x0 > tol and y1 - y0 > tol:
                other = f"bodies.{i}" + (f" ({a.name!r})" if a.name else "")
                errors.append((f"bodies.{j}",
                               f"overlaps {other} over [{fmt(x0)}, {fmt(x1)}] x [{fmt(y0)}, {fmt(y1)}]; "
                               "overlapping particles add their mass. Set allow_overlap = true on "
                               "one of the two bodies if this is intended"))
                break
    return errors
