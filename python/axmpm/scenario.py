"""Scenario files: TOML → validated, resolved pydantic models → JSON for the engine.

The structure, key names and defaults are the binding contract of ``docs/architecture.md``:
sections ``simulation``, ``grid``, ``materials`` (name → material, discriminated by
``model``), ``bodies`` (list), ``boundaries`` and ``walls`` (list). Units are SI, angles in
degrees, stresses tension positive.

Validation happens in two phases: every field is checked at once (types, ranges, unknown
keys with a "did you mean" hint), then the cross checks run (grid lines, bodies inside the
grid and not overlapping, material references, axisymmetric axis, sizes). When some fields
are invalid the cross checks still run on every part that validated on its own (a section,
a material, a body, a wall), so ``axmpm check`` reports all problems at once. Either phase
raises :class:`~axmpm.errors.ScenarioError`; see docs/robustness.md.
"""

from __future__ import annotations

import copy
import difflib
import json
import math
import re
import sys
from pathlib import Path
from typing import Annotated, Any, Literal, Union

import tomli_w

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationError,
    model_validator,
)
from pydantic_core import PydanticCustomError

from .errors import ScenarioError

__all__ = [
    "Scenario",
    "Simulation",
    "Grid",
    "LinearElastic",
    "NeoHookean",
    "MohrCoulomb",
    "VonMises",
    "Body",
    "BoundaryCondition",
    "Boundaries",
    "Wall",
    "ScenarioError",
    "GRID_TOLERANCE",
]

#: Tolerance, as a fraction of a cell, for "on a grid line" checks.
GRID_TOLERANCE = 1e-6

#: Sanity limits: a dense grid with more cells than this along one axis, or a run with more
#: output frames than this, is certainly a unit mistake (and would overflow or exhaust memory).
MAX_CELLS_PER_AXIS = 10_000_000
MAX_OUTPUTS = 1_000_000


# --------------------------------------------------------------------------- range types


def _fmt(x: float) -> str:
    return f"{x:g}"


def _bounded(
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    kind: type = float,
) -> Any:
    """A number type with a range check whose message reads ``must be >= 0 and < 0.5 (got 0.7)``."""
    parts = []
    schema: dict[str, float] = {}
    if lo is not None:
        parts.append(f"{'>' if lo_open else '>='} {_fmt(lo)}")
        schema["exclusiveMinimum" if lo_open else "minimum"] = lo
    if hi is not None:
        parts.append(f"{'<' if hi_open else '<='} {_fmt(hi)}")
        schema["exclusiveMaximum" if hi_open else "maximum"] = hi
    text = "must be " + " and ".join(parts)

    def check(value: float) -> float:
        too_low = lo is not None and (value <= lo if lo_open else value < lo)
        too_high = hi is not None and (value >= hi if hi_open else value > hi)
        if too_low or too_high:
            raise PydanticCustomError("out_of_range", text + " (got {value})", {"value": value})
        return value

    return Annotated[kind, Field(json_schema_extra=schema), AfterValidator(check)]


Positive = _bounded(0.0, lo_open=True)
NonNegative = _bounded(0.0)
Vec2 = tuple[float, float]


class _Section(BaseModel):
    """Base of every section: unknown keys are errors, NaN/inf are rejected."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


# --------------------------------------------------------------------------- sections


class Simulation(_Section):
    """``[simulation]``: formulation, interpolation, time integration."""

    formulation: Literal["plane_strain", "axisymmetric"]
    shape_function: Literal["linear", "ugimp", "cpgimp", "cpdi2"]
    end_time: Positive = Field(description="s, simulated time to reach")
    output_interval: Positive = Field(description="s, time between output frames")
    gravity: Vec2 = Field((0.0, -9.81), description="m/s², [x or r, y or z]")
    gravity_ramp_time: NonNegative = Field(
        0.0, description="s: gravity grows linearly from 0 over this time"
    )
    time_step: NonNegative = Field(
        0.0, description="s; 0 = from the CFL number and the fastest wave speed"
    )
    cfl: _bounded(0.0, 1.0, lo_open=True) = 0.4  # type: ignore[valid-type]
    update_scheme: Literal["musl", "usl"] = "musl"
    flip_fraction: _bounded(0.0, 1.0) = Field(  # type: ignore[valid-type]
        0.99, description="1 = pure FLIP, 0 = pure PIC"
    )
    damping: _bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
        0.0, description="Cundall local damping coefficient"
    )
    volumetric_averaging: Literal["none", "cell"] = Field(
        "none",
        description="anti-locking: 'cell' replaces each particle's volumetric strain rate by "
        "the volume-weighted mean of its background cell (mean dilatation / F-bar)",
    )
    stop_at_rest: _bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
        0.0,
        description="stop (status completed) at the first output time when the kinetic energy is "
        "below this fraction of the work done by gravity; 0 = run to end_time",
    )
    stop_when_settled: _bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
        0.0,
        description="stop (status completed) at the first output time when the work done by "
        "gravity over the last settle_window seconds is below this fraction of the total: the "
        "body no longer moves down (for undamped runs whose elastic vibration never dies out); "
        "0 = off",
    )
    settle_window: Positive = Field(  # type: ignore[valid-type]
        0.1, description="s: the time window of the stop_when_settled test"
    )
    stop_at_rest_after: NonNegative = Field(
        0.0, description="s: the at-rest and settled tests are applied only from this time on"
    )
    checkpoint_interval: Positive | None = Field(  # type: ignore[valid-type]
        None,
        description="s: write a restart checkpoint this often (rounded up to a whole number of "
        "output intervals); absent = only when the run stops (completed, failed, interrupted)",
    )


class Grid(_Section):
    """``[grid]``: a dense background grid of square cells."""

    origin: Vec2 = Field((0.0, 0.0), description="m; axisymmetric grids start at r = 0")
    extent: tuple[Positive, Positive] = Field(description="m, each a whole number of cells")  # type: ignore[valid-type]
    cell_size: Positive = Field(description="m")

    def cells(self) -> tuple[int, int]:
        """Number of cells in x (r) and y (z)."""
        return (
            int(round(self.extent[0] / self.cell_size)),
            int(round(self.extent[1] / self.cell_size)),
        )


class _Elastic(_Section):
    density: Positive = Field(description="kg/m³")
    youngs_modulus: Positive = Field(description="Pa")
    poisson_ratio: _bounded(0.0, 0.5, hi_open=True)  # type: ignore[valid-type]


class LinearElastic(_Elastic):
    """Small-strain isotropic elasticity (Hooke)."""

    model: Literal["linear_elastic"]


class NeoHookean(_Elastic):
    """Compressible neo-Hookean: σ = (1/J)[μ(b − I) + λ ln J I]."""

    model: Literal["neo_hookean"]


#: Mohr–Coulomb ``recompaction`` when a scenario does not set it (same as the engine's
#: ``mohr_coulomb::RECOMPACTION_DEFAULT``).
RECOMPACTION_DEFAULT = False


class MohrCoulomb(_Elastic):
    """Elastic–perfectly plastic Mohr–Coulomb, non-associated (dilation angle ψ ≤ φ)."""

    model: Literal["mohr_coulomb"]
    friction_angle: _bounded(0.0, 90.0, lo_open=True, hi_open=True) = Field(  # type: ignore[valid-type]
        description="degrees"
    )
    dilation_angle: NonNegative = Field(0.0, description="degrees, <= friction_angle")
    cohesion: NonNegative = Field(0.0, description="Pa")
    tension_cutoff: NonNegative = Field(0.0, description="Pa")
    recompaction: bool = Field(
        RECOMPACTION_DEFAULT,
        strict=True,
        description="true: material separated by tension (apex / cut-off returns) re-compacts "
        "stress-free before it carries compression again (Dunatunga & Kamrin 2015); false: the "
        "opened volume is permanent",
    )
    # μ(I) friction (mu_i.rs): present = the friction angle follows the inertial number.
    inertial_friction_angle: _bounded(0.0, 90.0, lo_open=True, hi_open=True) | None = Field(  # type: ignore[valid-type]
        None,
        description="degrees, in [friction_angle, 90): the friction angle at large inertial "
        "number I (mu(I) rheology, sin(phi) = mu_s + (mu_2 - mu_s) I/(I_0 + I), Jop et al. 2006); "
        "absent = rate-independent",
    )
    inertial_number_scale: Positive = Field(  # type: ignore[valid-type]
        0.279, description="I_0 of the mu(I) law (Jop et al. 2006 glass beads: 0.279)"
    )
    grain_diameter: Positive | None = Field(  # type: ignore[valid-type]
        None, description="m, grain size d in I = |shear rate| d / sqrt(P / grain_density); "
        "required with inertial_friction_angle"
    )
    grain_density: Positive | None = Field(  # type: ignore[valid-type]
        None, description="kg/m³, solid density of the grains (>= density); required with "
        "inertial_friction_angle"
    )


class VonMises(_Elastic):
    """J2 plasticity with linear isotropic hardening (docs/physics.md §7; engine
    material/von_mises.rs): σ_y(ε̄p) = yield_stress + hardening_modulus ε̄p."""

    model: Literal["von_mises"]
    yield_stress: Positive = Field(description="Pa, initial yield stress in uniaxial tension")  # type: ignore[valid-type]
    hardening_modulus: NonNegative = Field(  # type: ignore[valid-type]
        0.0, description="Pa, plastic modulus H = d(yield stress)/d(equivalent plastic strain); 0 = perfectly plastic"
    )


Material = Annotated[Union[LinearElastic, NeoHookean, MohrCoulomb, VonMises], Field(discriminator="model")]
MATERIAL_MODELS: dict[str, type[_Elastic]] = {
    "linear_elastic": LinearElastic,
    "neo_hookean": NeoHookean,
    "mohr_coulomb": MohrCoulomb,
    "von_mises": VonMises,
}


class Body(_Section):
    """``[[bodies]]``: a rectangle of material filled with particles on a regular lattice."""

    name: str | None = Field(None, description="resolved default: body_<index>")
    material: str
    shape: Literal["rectangle"] = "rectangle"
    min: Vec2 = Field(description="m, on grid lines")
    max: Vec2 = Field(description="m, on grid lines")
    particles_per_cell: _bounded(1, 8, kind=int) = Field(  # type: ignore[valid-type]
        2, description="per direction"
    )
    velocity: Vec2 = Field((0.0, 0.0), description="m/s")
    initial_stress: Literal["zero", "geostatic"] = "zero"
    k0: NonNegative | None = Field(  # type: ignore[valid-type]
        None,
        description="lateral earth pressure ratio; resolved default nu/(1-nu), "
        "or 1 - sin(phi) for mohr_coulomb",
    )
    allow_overlap: bool = Field(
        False,
        strict=True,
        description="true: this body may overlap other bodies (particles are then superposed, "
        "adding mass); false: an overlap with another body that does not allow it is an error",
    )


BoundaryName = Literal["free", "roller", "fixed", "friction"]


class BoundaryCondition(_Section):
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


class Boundaries(_Section):
    """``[boundaries]``: conditions on the four grid faces (r = 0 is the left face)."""

    left: Face = Field(default_factory=_free)
    right: Face = Field(default_factory=_free)
    bottom: Face = Field(default_factory=_free)
    top: Face = Field(default_factory=_free)


class Wall(_Section):
    """``[[walls]]``: a straight rigid wall on a grid line inside the grid."""

    axis: Literal["x", "y"] = Field(description='"x": the line x = position; "y": the line y = position')
    position: float = Field(description="m, on a grid line")
    material_side: Literal["negative", "positive"]
    condition: Literal["roller", "fixed", "friction"]
    coefficient: NonNegative = 0.0
    removal_time: NonNegative | None = Field(None, description="s; absent = never removed")  # type: ignore[valid-type]


# --------------------------------------------------------------------------- scenario


class Scenario(_Section):
    """A complete, resolved scenario (see docs/architecture.md)."""

    simulation: Simulation
    grid: Grid
    materials: dict[str, Material]
    bodies: list[Body]
    boundaries: Boundaries = Field(default_factory=Boundaries)
    walls: list[Wall] = Field(default_factory=list)

    @model_validator(mode="after")
    def _cross_check(self) -> "Scenario":
        errors = _cross_check(self)
        if errors:
            raise ScenarioError(errors)
        _resolve_defaults(self)
        return self

    # -- construction ------------------------------------------------------------------

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str | None = None) -> "Scenario":
        """Validate a plain dict (as read from TOML); raise :class:`ScenarioError`."""
        if not isinstance(data, dict):
            raise ScenarioError([("", "a scenario must be a table of sections")], source)
        try:
            return cls.model_validate(data)
        except ValidationError as exc:
            errors = _convert_errors(exc)
            try:
                errors = _merge_errors(errors, _partial_cross_check(data))
            except Exception:  # pragma: no cover - the field errors alone are still reported
                pass
            raise ScenarioError(errors, source) from None
        except ScenarioError as exc:
            exc.source = source
            raise

    @classmethod
    def from_toml(cls, path: str | Path, overrides: list[str] | None = None) -> "Scenario":
        """Read, override (``["a.b=1", ...]``, see :func:`apply_overrides`) and validate."""
        data = read_toml(path)
        if overrides:
            data = apply_overrides(data, overrides)
        return cls.from_dict(data, source=str(path))

    # -- output ------------------------------------------------------------------------

    def to_dict(self) -> dict[str, Any]:
        """The resolved scenario as plain JSON-compatible data (None values included)."""
        data = self.model_dump(mode="json")
        data["materials"] = {name: {"model": m["model"], **m} for name, m in data["materials"].items()}
        return data

    def to_toml(self) -> str:
        """The resolved scenario as TOML (keys whose value is None are omitted)."""
        header = "# Resolved axmpm scenario: every default filled in.\n"
        return header + _inline_short_arrays(tomli_w.dumps(_drop_none(self.to_dict())))

    def engine_json(self) -> str:
        """The JSON the engine deserialises (``axmpm._core.Simulation(config_json)``)."""
        return self.model_dump_json()

    # -- derived quantities -------------------------------------------------------------

    def particle_count(self) -> int:
        """Number of particles the bodies will create."""
        h = self.grid.cell_size
        total = 0
        for body in self.bodies:
            nx = int(round((body.max[0] - body.min[0]) / h))
            ny = int(round((body.max[1] - body.min[1]) / h))
            total += nx * ny * body.particles_per_cell**2
        return total

    def material_names(self) -> list[str]:
        """Material names in engine order (sorted), so ``material_id`` indexes this list."""
        return sorted(self.materials)


def schema_json(indent: int = 2) -> str:
    """JSON Schema of a scenario file."""
    return json.dumps(Scenario.model_json_schema(), indent=indent)


# --------------------------------------------------------------------------- cross checks


def _on_grid_line(value: float, origin: float, h: float) -> bool:
    n = (value - origin) / h
    return math.isfinite(n) and abs(n - round(n)) <= GRID_TOLERANCE


def _cross_check(s: Scenario) -> list[tuple[str, str]]:
    return _cross_check_parts(
        s.simulation, s.grid, dict(s.materials), list(s.materials), list(s.bodies), s.boundaries, list(s.walls)
    )


def _grid_cells_ok(grid: Grid, errors: list[tuple[str, str]]) -> bool:
    """Check the grid's extent against its cell size; False when the grid is unusable."""
    ok = True
    h = grid.cell_size
    for i, length in enumerate(grid.extent):
        n = length / h
        if not math.isfinite(n) or n > MAX_CELLS_PER_AXIS:
            errors.append((f"grid.extent.{i}", f"must be at most {MAX_CELLS_PER_AXIS:,} cells of {_fmt(h)} m "
                           f"(got {_fmt(length)} m = {n:.6g} cells)"))
            ok = False
        elif n < 1.0 - 1e-6:
            errors.append((f"grid.extent.{i}", f"must be at least one cell of {_fmt(h)} m (got {_fmt(length)} m)"))
        elif abs(n - round(n)) > 1e-6 * max(1.0, n):
            errors.append(
                (f"grid.extent.{i}", f"must be a whole number of cells of {_fmt(h)} m "
                 f"(got {_fmt(length)} m = {n:.6g} cells)")
            )
    if not all(math.isfinite(grid.origin[i] + grid.extent[i]) for i in (0, 1)):
        errors.append(("grid.extent", "origin + extent overflows"))
        ok = False
    return ok


def _cross_check_parts(
    sim: Simulation | None,
    grid: Grid | None,
    materials: dict[str, Any] | None,
    material_names: list[str] | None,
    bodies: list[Body | None] | None,
    boundaries: Boundaries | None,
    walls: list[Wall | None] | None,
) -> list[tuple[str, str]]:
    """Cross checks between sections. ``None`` stands for a part that failed its own field
    checks (or a whole section that did): the checks needing it are skipped, so that this can
    run next to the field errors. ``materials`` maps names to validated materials (``None`` if
    invalid); ``material_names`` are all names (None if the section itself is invalid)."""
    errors: list[tuple[str, str]] = []

    if sim is not None:
        n_out = sim.end_time / sim.output_interval
        if not math.isfinite(n_out) or n_out > MAX_OUTPUTS:
            errors.append(("simulation.output_interval",
                           f"end_time / output_interval must be at most {MAX_OUTPUTS:,} output frames "
                           f"(got {n_out:.6g})"))

    grid_ok = grid is not None and _grid_cells_ok(grid, errors)
    if grid is not None:
        h = grid.cell_size
        lo = grid.origin
        hi = (grid.origin[0] + grid.extent[0], grid.origin[1] + grid.extent[1])
        tol = GRID_TOLERANCE * h

    if materials is not None and material_names is not None:
        if not material_names:
            errors.append(("materials", "at least one material is required"))
        for name, mat in materials.items():
            if isinstance(mat, MohrCoulomb) and mat.dilation_angle > mat.friction_angle:
                errors.append(
                    (f"materials.{name}.dilation_angle",
                     f"must be <= friction_angle = {_fmt(mat.friction_angle)} "
                     f"(got {_fmt(mat.dilation_angle)})")
                )
            if isinstance(mat, MohrCoulomb) and mat.inertial_friction_angle is not None:
                if mat.inertial_friction_angle < mat.friction_angle:
                    errors.append(
                        (f"materials.{name}.inertial_friction_angle",
                         f"must be >= friction_angle = {_fmt(mat.friction_angle)} and < 90 "
                         f"(got {_fmt(mat.inertial_friction_angle)})")
                    )
                for key in ("grain_diameter", "grain_density"):
                    if getattr(mat, key) is None:
                        errors.append((f"materials.{name}.{key}", "is required with inertial_friction_angle"))
                if mat.grain_density is not None and mat.grain_density < mat.density:
                    errors.append(
                        (f"materials.{name}.grain_density",
                         f"must be >= density = {_fmt(mat.density)} (the bulk density of the grains) "
                         f"(got {_fmt(mat.grain_density)})")
                    )

    if bodies is not None:
        if not bodies:
            errors.append(("bodies", "at least one body is required"))
        seen_names: set[str] = set()
        for i, body in enumerate(bodies):
            if body is None:
                continue
            key = f"bodies.{i}"
            if material_names is not None and body.material not in material_names:
                errors.append((f"{key}.material", f"unknown material {body.material!r}"
                               + _did_you_mean(body.material, material_names)))
            if body.name is not None:
                if body.name in seen_names:
                    errors.append((f"{key}.name", f"duplicate body name {body.name!r}"))
                seen_names.add(body.name)
            for axis in (0, 1):
                bmin, bmax = body.min[axis], body.max[axis]
                if not bmin < bmax:
                    errors.append((f"{key}.max.{axis}",
                                   f"must be > min.{axis} = {_fmt(bmin)} (got {_fmt(bmax)})"))
                if not grid_ok:
                    continue
                for which, value in (("min", bmin), ("max", bmax)):
                    if value < lo[axis] - tol or value > hi[axis] + tol:
                        errors.append((f"{key}.{which}.{axis}",
                                       f"must be inside the grid [{_fmt(lo[axis])}, {_fmt(hi[axis])}] "
                                       f"(got {_fmt(value)})"))
                    elif not _on_grid_line(value, lo[axis], h):
                        errors.append((f"{key}.{which}.{axis}",
                                       f"must lie on a grid line (multiples of {_fmt(h)} m from the "
                                       f"origin {_fmt(lo[axis])}) (got {_fmt(value)})"))
        errors.extend(_overlaps(bodies, grid.cell_size if grid is not None else None))

    if sim is not None and sim.formulation == "axisymmetric":
        if grid is not None and abs(grid.origin[0]) > 1e-12 * grid.cell_size:  # the engine's own tolerance
            errors.append(("grid.origin.0", "axisymmetric grids start on the axis: must be 0 "
                           f"(got {_fmt(grid.origin[0])})"))
        if boundaries is not None and boundaries.left.condition != "roller":
            errors.append(("boundaries.left",
                           "in axisymmetric runs the left face is the axis, which is always a "
                           f'roller: must be "roller" (got "{boundaries.left.condition}")'))

    if grid_ok and walls is not None:
        for i, wall in enumerate(walls):
            if wall is None:
                continue
            axis = 0 if wall.axis == "x" else 1
            if wall.position < lo[axis] - tol or wall.position > hi[axis] + tol:
                errors.append((f"walls.{i}.position",
                               f"must be inside the grid [{_fmt(lo[axis])}, {_fmt(hi[axis])}] "
                               f"(got {_fmt(wall.position)})"))
            elif not _on_grid_line(wall.position, lo[axis], h):
                errors.append((f"walls.{i}.position",
                               f"must lie on a grid line (multiples of {_fmt(h)} m from the origin "
                               f"{_fmt(lo[axis])}) (got {_fmt(wall.position)})"))
    return errors


def _overlaps(bodies: list[Body | None], h: float | None) -> list[tuple[str, str]]:
    """Pairs of bodies whose rectangles share an area (touching edges are fine), unless one
    of the two has ``allow_overlap = true``. Reported on the later body."""
    errors: list[tuple[str, str]] = []
    valid = [(i, b) for i, b in enumerate(bodies)
             if b is not None and b.min[0] < b.max[0] and b.min[1] < b.max[1]]
    for jj, (j, b) in enumerate(valid):
        for i, a in valid[:jj]:
            if a.allow_overlap or b.allow_overlap:
                continue
            x0, x1 = max(a.min[0], b.min[0]), min(a.max[0], b.max[0])
            y0, y1 = max(a.min[1], b.min[1]), min(a.max[1], b.max[1])
            tol = GRID_TOLERANCE * h if h is not None else 0.0
            if x1 - x0 > tol and y1 - y0 > tol:
                other = f"bodies.{i}" + (f" ({a.name!r})" if a.name else "")
                errors.append((f"bodies.{j}",
                               f"overlaps {other} over [{_fmt(x0)}, {_fmt(x1)}] x [{_fmt(y0)}, {_fmt(y1)}]; "
                               "overlapping particles add their mass. Set allow_overlap = true on "
                               "one of the two bodies if this is intended"))
                break
    return errors


def _validate_part(adapter: Any, value: Any) -> Any:
    """``adapter`` (a model class or TypeAdapter) applied to ``value``, or None if invalid."""
    try:
        if isinstance(adapter, TypeAdapter):
            return adapter.validate_python(value)
        return adapter.model_validate(value)
    except Exception:  # ValidationError, ScenarioError, anything odd in fuzzed input
        return None


_MATERIAL_ADAPTER: TypeAdapter[Any] | None = None


def _partial_cross_check(data: dict[str, Any]) -> list[tuple[str, str]]:
    """The cross checks on the parts of a scenario that are valid on their own."""
    global _MATERIAL_ADAPTER
    if _MATERIAL_ADAPTER is None:
        _MATERIAL_ADAPTER = TypeAdapter(Material)
    sim = _validate_part(Simulation, data.get("simulation"))
    grid = _validate_part(Grid, data.get("grid"))
    raw_materials = data.get("materials")
    materials: dict[str, Any] | None = None
    names: list[str] | None = None
    if isinstance(raw_materials, dict):
        names = [str(n) for n in raw_materials]
        materials = {str(n): _validate_part(_MATERIAL_ADAPTER, m) for n, m in raw_materials.items()}
    raw_bodies = data.get("bodies")
    bodies = [_validate_part(Body, b) for b in raw_bodies] if isinstance(raw_bodies, list) else None
    boundaries = _validate_part(Boundaries, data.get("boundaries", {}))
    raw_walls = data.get("walls", [])
    walls = [_validate_part(Wall, w) for w in raw_walls] if isinstance(raw_walls, list) else None
    return _cross_check_parts(sim, grid, materials, names, bodies, boundaries, walls)


def _merge_errors(field: list[tuple[str, str]], cross: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Field errors, then the cross errors on keys that have no field error (nor a parent
    or child key with one)."""
    keys = [k for k, _ in field]

    def related(key: str) -> bool:
        return any(key == k or key.startswith(k + ".") or k.startswith(key + ".") for k in keys)

    return field + [(k, m) for k, m in cross if not related(k)]


def _resolve_defaults(s: Scenario) -> None:
    """Fill in defaults that depend on other sections (body names, k0)."""
    for i, body in enumerate(s.bodies):
        if body.name is None:
            body.name = f"body_{i}"
        if body.k0 is None:
            mat = s.materials[body.material]
            if isinstance(mat, MohrCoulomb):
                body.k0 = 1.0 - math.sin(math.radians(mat.friction_angle))
            else:
                body.k0 = mat.poisson_ratio / (1.0 - mat.poisson_ratio)


# --------------------------------------------------------------------------- error messages


def _did_you_mean(word: str, choices: Any) -> str:
    match = difflib.get_close_matches(str(word), [str(c) for c in choices], n=1, cutoff=0.6)
    return f"; did you mean {match[0]!r}?" if match else ""


_SECTION_MODELS: dict[str, type[BaseModel]] = {
    "simulation": Simulation,
    "grid": Grid,
    "boundaries": Boundaries,
    "bodies": Body,
    "walls": Wall,
}


def _model_at(loc: tuple[Any, ...]) -> type[BaseModel] | None:
    """The model class validating the table at ``loc`` (pydantic location, tags included)."""
    if not loc:
        return Scenario
    section = loc[0]
    if section == "materials":
        if len(loc) == 3:
            return MATERIAL_MODELS.get(str(loc[2]))
        return None
    if section in ("bodies", "walls"):
        return _SECTION_MODELS[section] if len(loc) == 2 else None
    if section == "boundaries":
        return Boundaries if len(loc) == 1 else BoundaryCondition
    if len(loc) == 1:
        return _SECTION_MODELS.get(str(section))
    return None


def _dotted(loc: tuple[Any, ...]) -> str:
    """Pydantic location → dotted key, dropping the discriminator tag of materials."""
    parts = list(loc)
    if len(parts) >= 3 and parts[0] == "materials" and str(parts[2]) in MATERIAL_MODELS:
        del parts[2]
    return ".".join(str(p) for p in parts)


def _convert_errors(exc: ValidationError) -> list[tuple[str, str]]:
    out: list[tuple[str, str]] = []
    for err in exc.errors(include_url=False):
        loc = tuple(err["loc"])
        kind = err["type"]
        ctx = err.get("ctx") or {}
        value = err.get("input")
        msg = err["msg"]
        if kind == "extra_forbidden":
            model = _model_at(loc[:-1])
            fields = list(model.model_fields) if model else []
            msg = "unknown key" + _did_you_mean(loc[-1], fields)
            if model is not None and issubclass(model, _Elastic):
                owners = [n for n, m in MATERIAL_MODELS.items() if loc[-1] in m.model_fields]
                if owners and "did you mean" not in msg:
                    msg += f" (only valid for model = {' or '.join(repr(o) for o in owners)})"
        elif kind == "missing" and loc and isinstance(loc[-1], int):
            loc = loc[:-1]  # a too-short tuple reports its first missing index
            msg = f"must have exactly 2 entries (got {len(value) if isinstance(value, (list, tuple)) else value!r})"
        elif kind == "missing":
            msg = "required key is missing"
        elif kind == "literal_error":
            msg = f"must be {ctx.get('expected', '')} (got {value!r})"
            if isinstance(value, str):
                choices = [c.strip(" '") for c in str(ctx.get("expected", "")).replace(" or ", ",").split(",")]
                msg += _did_you_mean(value, choices)
        elif kind == "union_tag_invalid":
            loc = loc + ("model",)
            expected = ctx.get("expected_tags", "")
            msg = f"unknown material model {ctx.get('tag')!r}; expected one of {expected}"
            msg += _did_you_mean(ctx.get("tag", ""), MATERIAL_MODELS)
        elif kind == "union_tag_not_found":
            loc = loc + ("model",)
            msg = "required key is missing (one of " + ", ".join(repr(m) for m in MATERIAL_MODELS) + ")"
        elif kind in ("too_long", "too_short") and isinstance(value, (list, tuple)):
            msg = f"must have exactly 2 entries (got {len(value)})" if "tuple" in msg.lower() else msg
        elif kind in ("float_parsing", "float_type", "int_parsing", "int_type", "int_from_float"):
            msg = f"{msg.rstrip('.')} (got {value!r})"
        elif kind in ("finite_number",):
            msg = f"must be a finite number (got {value!r})"
        out.append((_dotted(loc), msg))
    return out


# --------------------------------------------------------------------------- TOML and overrides


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file; missing files and syntax errors become :class:`ScenarioError`."""
    p = Path(path)
    try:
        text = p.read_bytes()
    except FileNotFoundError:
        raise ScenarioError([("", f"scenario file not found: {p}")], str(p)) from None
    except IsADirectoryError:
        raise ScenarioError([("", f"scenario path is a folder, not a file: {p}")], str(p)) from None
    except OSError as exc:
        raise ScenarioError([("", f"cannot read {p}: {exc.strerror}")], str(p)) from None
    try:
        return tomllib.loads(text.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise ScenarioError([("", f"{p}: not UTF-8 text ({exc.reason})")], str(p)) from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError([("", f"{p}: invalid TOML: {exc}")], str(p)) from None
    except RecursionError:
        raise ScenarioError([("", f"{p}: invalid TOML: arrays or tables nested too deeply")], str(p)) from None


def parse_value(text: str) -> Any:
    """Parse an override value as a TOML value (``1``, ``[0.1, 0.2]``, ``"a"``, ``{...}``);
    anything that is not valid TOML is taken as a bare string (``roller``)."""
    try:
        return tomllib.loads("v = " + text)["v"]
    except tomllib.TOMLDecodeError:
        return text.strip()


def apply_overrides(data: dict[str, Any], overrides: list[str]) -> dict[str, Any]:
    """Return a deep copy of ``data`` with ``key.path=value`` overrides applied.

    Keys are dotted; integer parts index arrays of tables (``bodies.0.max=[0.1,0.2]``); an
    index equal to the array length appends a new table. Missing tables are created.
    Problems are collected and raised together as :class:`ScenarioError`.
    """
    result = copy.deepcopy(data)  # plain TOML data (may hold dates, which JSON cannot)
    errors: list[tuple[str, str]] = []
    for item in overrides:
        key, sep, raw = item.partition("=")
        key = key.strip()
        if not sep or not key:
            errors.append((key or item, f"override must look like key.path=value (got {item!r})"))
            continue
        parts = key.split(".")
        if any(not p for p in parts):
            errors.append((key, "empty part in the dotted key"))
            continue
        try:
            _set_path(result, parts, parse_value(raw))
        except _OverrideError as exc:
            errors.append((key, str(exc)))
    if errors:
        raise ScenarioError(errors, "--set")
    return result


class _OverrideError(Exception):
    pass


def _set_path(node: Any, parts: list[str], value: Any) -> None:
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        where = ".".join(parts[:depth]) or "the scenario"
        if isinstance(node, list):
            if not part.isdigit():
                raise _OverrideError(f"{where} is an array: expected an index, got {part!r}")
            index = int(part)
            if index > len(node):
                raise _OverrideError(f"index {index} out of range ({where} has {len(node)} entries)")
            if index == len(node):
                node.append({})
            if last:
                node[index] = value
            else:
                node = node[index]
        elif isinstance(node, dict):
            if last:
                node[part] = value
            else:
                if part not in node:
                    node[part] = [] if parts[depth + 1].isdigit() else {}
                elif isinstance(node[part], str) and depth == 1 and parts[0] == "boundaries":
                    node[part] = {"condition": node[part]}  # shorthand face → table form
                node = node[part]
        else:
            raise _OverrideError(f"{where} is a value ({node!r}), not a table")


_MULTILINE_ARRAY = re.compile(r"\[\n((?:[ \t]+[^\[\]{}\n\"]+,\n)+)\]")


def _inline_short_arrays(text: str) -> str:
    """tomli-w writes every array over several lines; put short numeric ones on one line."""

    def join(match: re.Match[str]) -> str:
        items = [line.strip().rstrip(",") for line in match.group(1).splitlines()]
        return "[" + ", ".join(items) + "]"

    return _MULTILINE_ARRAY.sub(join, text)


def _drop_none(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _drop_none(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, list):
        return [_drop_none(v) for v in obj]
    return obj
