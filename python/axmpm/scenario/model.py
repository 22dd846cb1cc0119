"""The scenario: its sections put together, the checks between them, and the resolved defaults.

Validation happens in two phases: every field is checked at once (types, ranges, unknown keys
with a "did you mean" hint), then the cross checks run (grid lines, bodies inside the grid and
not overlapping, material references, axisymmetric axis, sizes). When some fields are invalid
the cross checks still run on every part that validated on its own (a section, a material, a
body, a wall), so ``axmpm check`` reports all problems at once. Either phase raises
:class:`~axmpm.errors.ScenarioError`; see docs/robustness.md.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import tomli_w
from pydantic import Field, TypeAdapter, ValidationError, model_validator

from ..engine import core
from ..errors import ScenarioError
from .bodies import GridFrame, overlaps
from .boundaries import Boundaries, Wall
from .fields import GRID_TOLERANCE, MAX_CELLS_PER_AXIS, MAX_OUTPUTS, Section, did_you_mean, fmt, on_grid_line
from .files import apply_overrides, drop_none, inline_short_arrays, read_toml
from .materials import engine_key_errors, material_type
from .messages import convert_errors
from .regions import body_type
from .rigid_bodies import RigidBody, reserved_names, rigid_body_errors
from .probes import Probe, probe_errors
from .saturated import Drainage, drainage_errors, saturated_errors
from .sections import Grid, Simulation
from .surcharges import Surcharge, surcharge_errors

__all__ = ["Scenario", "Material", "Body", "schema_json"]

#: The type of one ``[materials.NAME]`` table and of one ``[[bodies]]`` table (every registered
#: material model / region shape).
Material = material_type()
Body = body_type()


class Scenario(Section):
    """A complete, resolved scenario (see docs/architecture.md)."""

    simulation: Simulation
    grid: Grid
    materials: dict[str, Material]  # type: ignore[valid-type]
    bodies: list[Body]  # type: ignore[valid-type]
    boundaries: Boundaries = Field(default_factory=Boundaries)
    walls: list[Wall] = Field(default_factory=list)
    rigid_bodies: list[RigidBody] = Field(default_factory=list)  # type: ignore[valid-type]
    drainage: Drainage = Field(default_factory=Drainage)
    surcharges: list[Surcharge] = Field(default_factory=list)
    probes: list[Probe] = Field(default_factory=list)

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
            errors = convert_errors(exc, root=cls)
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
        return header + inline_short_arrays(tomli_w.dumps(drop_none(self.to_dict())))

    def engine_json(self) -> str:
        """The JSON the engine deserialises (``axmpm._core.Simulation(config_json)``)."""
        return self.model_dump_json()

    # -- derived quantities -------------------------------------------------------------

    def particle_count(self) -> int:
        """Number of particles the bodies will create (rigid bodies cut theirs out)."""
        if not self.rigid_bodies and all(body.shape == "rectangle" for body in self.bodies):
            return sum(body.particle_count(self.grid.cell_size) for body in self.bodies)
        return sum(len(p) for p in self.particle_positions())

    def particle_positions(self) -> list[Any]:
        """Per body, the initial particle positions (N × 2 arrays) the engine creates: the body's
        lattice points (sub-cell centres) inside its region and outside every rigid body."""
        out = []
        for body in self.bodies:
            points = body.lattice_points(self.grid.origin, self.grid.cell_size)
            for rigid in self.rigid_bodies:
                points = points[~rigid.contains(points)]
            out.append(points)
        return out

    def material_names(self) -> list[str]:
        """Material names in engine order (sorted), so ``material_id`` indexes this list."""
        return sorted(self.materials)


def schema_json(indent: int = 2) -> str:
    """JSON Schema of a scenario file."""
    return json.dumps(Scenario.model_json_schema(), indent=indent)


# --------------------------------------------------------------------------- cross checks


def _cross_check(s: Scenario) -> list[tuple[str, str]]:
    return cross_check_parts(
        s.simulation, s.grid, dict(s.materials), list(s.materials), list(s.bodies), s.boundaries, list(s.walls),
        list(s.rigid_bodies), list(s.surcharges), list(s.probes),
    ) + drainage_errors(s.drainage)


def _grid_cells_ok(grid: Grid, errors: list[tuple[str, str]]) -> bool:
    """Check the grid's extent against its cell size; False when the grid is unusable."""
    ok = True
    h = grid.cell_size
    for i, length in enumerate(grid.extent):
        n = length / h
        if not math.isfinite(n) or n > MAX_CELLS_PER_AXIS:
            errors.append((f"grid.extent.{i}", f"must be at most {MAX_CELLS_PER_AXIS:,} cells of {fmt(h)} m "
                           f"(got {fmt(length)} m = {n:.6g} cells)"))
            ok = False
        elif n < 1.0 - 1e-6:
            errors.append((f"grid.extent.{i}", f"must be at least one cell of {fmt(h)} m (got {fmt(length)} m)"))
        elif abs(n - round(n)) > 1e-6 * max(1.0, n):
            errors.append(
                (f"grid.extent.{i}", f"must be a whole number of cells of {fmt(h)} m "
                 f"(got {fmt(length)} m = {n:.6g} cells)")
            )
    if not all(math.isfinite(grid.origin[i] + grid.extent[i]) for i in (0, 1)):
        errors.append(("grid.extent", "origin + extent overflows"))
        ok = False
    return ok


def cross_check_parts(
    sim: Simulation | None,
    grid: Grid | None,
    materials: dict[str, Any] | None,
    material_names: list[str] | None,
    bodies: list[Any] | None,
    boundaries: Boundaries | None,
    walls: list[Wall | None] | None,
    rigid_bodies: list[Any | None] | None = None,
    surcharges: list[Surcharge | None] | None = None,
    probes: list[Probe | None] | None = None,
) -> list[tuple[str, str]]:
    """Cross checks between sections. ``None`` stands for a part that failed its own field
    checks (or a whole section that did): the checks needing it are skipped, so that this can
    run next to the field errors. ``materials`` maps names to validated materials (``None`` if
    invalid); ``material_names`` are all names (None if the section itself is invalid)."""
    errors: list[tuple[str, str]] = []

    if sim is not None:
        if sim.history_interval is not None and sim.history_interval > sim.output_interval * (1 + 1e-12):
            errors.append(("simulation.history_interval", f"must be <= output_interval = {fmt(sim.output_interval)} "
                           f"(got {fmt(sim.history_interval)})"))
        n_out = sim.end_time / sim.output_interval
        if not math.isfinite(n_out) or n_out > MAX_OUTPUTS:
            errors.append(("simulation.output_interval",
                           f"end_time / output_interval must be at most {MAX_OUTPUTS:,} output frames "
                           f"(got {n_out:.6g})"))

    grid_ok = grid is not None and _grid_cells_ok(grid, errors)
    frame: GridFrame | None = None
    if grid is not None:
        h = grid.cell_size
        lo = grid.origin
        hi = (grid.origin[0] + grid.extent[0], grid.origin[1] + grid.extent[1])
        tol = GRID_TOLERANCE * h
        frame = GridFrame(lo, hi, h) if grid_ok else None

    if materials is not None and material_names is not None:
        if not material_names:
            errors.append(("materials", "at least one material is required"))
        for name, mat in materials.items():
            if mat is not None:
                errors.extend(mat.cross_errors(f"materials.{name}."))
                errors.extend(engine_key_errors(name, mat.model_dump(mode="json")))

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
                               + did_you_mean(body.material, material_names)))
            if body.name is not None:
                if body.name in seen_names:
                    errors.append((f"{key}.name", f"duplicate body name {body.name!r}"))
                seen_names.add(body.name)
            errors.extend(body.region_errors(key, frame))
        if sim is not None:
            for i, body in enumerate(bodies):
                if body is not None and body.initial_stress == "geostatic" and not sim.gravity[1] < 0.0:
                    errors.append((f"bodies.{i}.initial_stress",
                                   f'"geostatic" needs gravity pointing down (simulation.gravity[1] < 0, got '
                                   f"{fmt(sim.gravity[1])}); for weightless soil give the stress: initial_stress = "
                                   "{ vertical = ..., horizontal = ... } (Pa, tension positive)"))
        errors.extend(overlaps(bodies, grid.cell_size if grid is not None else None))
        errors.extend(saturated_errors(bodies, grid if grid_ok else None))

    if sim is not None and sim.formulation == "axisymmetric":
        if grid is not None and abs(grid.origin[0]) > 1e-12 * grid.cell_size:  # the engine's own tolerance
            errors.append(("grid.origin.0", "axisymmetric grids start on the axis: must be 0 "
                           f"(got {fmt(grid.origin[0])})"))
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
                               f"must be inside the grid [{fmt(lo[axis])}, {fmt(hi[axis])}] "
                               f"(got {fmt(wall.position)})"))
            elif not on_grid_line(wall.position, lo[axis], h):
                errors.append((f"walls.{i}.position",
                               f"must lie on a grid line (multiples of {fmt(h)} m from the origin "
                               f"{fmt(lo[axis])}) (got {fmt(wall.position)})"))

    if rigid_bodies:
        axisymmetric = None if sim is None else sim.formulation == "axisymmetric"
        end_time = None if sim is None else sim.end_time
        errors.extend(rigid_body_errors(rigid_bodies, frame, axisymmetric, end_time, len(walls or [])))
    saturated = any(b is not None and b.saturated is not None for b in bodies or [])
    if sim is not None and sim.xpic_order > 1:
        if not sim.experimental:
            errors.append(("simulation.xpic_order", core().XPIC_IS_EXPERIMENTAL))
        if saturated:
            errors.append(("simulation.xpic_order", core().XPIC_WITH_SATURATED))
    if grid is not None and grid.follow is not None:
        errors.extend(_follow_errors(grid.follow, grid.experimental, materials, bodies, walls, rigid_bodies))
    if saturated:
        errors.extend((f"rigid_bodies.{i}.contact", core().PENALTY_WITH_SATURATED)
                      for i, b in enumerate(rigid_bodies or []) if b is not None and b.contact == "penalty")
    if surcharges:
        taken = set(reserved_names(len(walls or [])))
        taken |= {b.name for b in rigid_bodies or [] if b is not None and b.name is not None}
        errors.extend(surcharge_errors(surcharges, frame, taken))
    errors.extend(probe_errors(probes, grid if grid_ok else None))
    return errors


def _follow_errors(
    follow: str,
    experimental: bool,
    materials: dict[str, Any] | None,
    bodies: list[Any] | None,
    walls: list[Wall | None] | None,
    rigid_bodies: list[Any | None] | None,
) -> list[tuple[str, str]]:
    """``grid.follow``: the engine's refusals (a rigid body's name, ``experimental``, nothing tied
    to fixed node rows), every one."""
    names = [b.name for b in rigid_bodies or [] if b is not None]
    if rigid_bodies is None or None in rigid_bodies:
        names.append(follow)  # a rigid body left out by its own error: not refused twice
    saturated = any(b is not None and b.saturated is not None for b in bodies or [])
    used = {b.material for b in bodies or [] if b is not None}
    models = [m.model for name, m in (materials or {}).items() if m is not None and name in used]
    messages = core().follow_errors(follow, experimental, names, len(walls or []), saturated, models)
    return [("grid.follow", message) for message in messages]


def _validate_part(adapter: Any, value: Any) -> Any:
    """``adapter`` (a model class or TypeAdapter) applied to ``value``, or None if invalid."""
    try:
        if isinstance(adapter, TypeAdapter):
            return adapter.validate_python(value)
        return adapter.model_validate(value)
    except Exception:  # ValidationError, ScenarioError, anything odd in fuzzed input
        return None


_ADAPTERS: dict[str, TypeAdapter[Any]] = {}


def _adapter(name: str) -> TypeAdapter[Any]:
    if name not in _ADAPTERS:
        _ADAPTERS[name] = TypeAdapter({"material": Material, "body": Body, "rigid_body": RigidBody}[name])
    return _ADAPTERS[name]


def _partial_cross_check(data: dict[str, Any]) -> list[tuple[str, str]]:
    """The cross checks on the parts of a scenario that are valid on their own."""
    sim = _validate_part(Simulation, data.get("simulation"))
    grid = _validate_part(Grid, data.get("grid"))
    raw_materials = data.get("materials")
    materials: dict[str, Any] | None = None
    names: list[str] | None = None
    if isinstance(raw_materials, dict):
        names = [str(n) for n in raw_materials]
        materials = {str(n): _validate_part(_adapter("material"), m) for n, m in raw_materials.items()}
    raw_bodies = data.get("bodies")
    bodies = [_validate_part(_adapter("body"), b) for b in raw_bodies] if isinstance(raw_bodies, list) else None
    boundaries = _validate_part(Boundaries, data.get("boundaries", {}))
    raw_walls = data.get("walls", [])
    walls = [_validate_part(Wall, w) for w in raw_walls] if isinstance(raw_walls, list) else None
    raw_rigid = data.get("rigid_bodies", [])
    rigid = [_validate_part(_adapter("rigid_body"), b) for b in raw_rigid] if isinstance(raw_rigid, list) else None
    raw_surcharges = data.get("surcharges", [])
    surcharges = ([_validate_part(Surcharge, c) for c in raw_surcharges] if isinstance(raw_surcharges, list)
                  else None)
    raw_probes = data.get("probes", [])
    probes = [_validate_part(Probe, p) for p in raw_probes] if isinstance(raw_probes, list) else None
    drainage = _validate_part(Drainage, data.get("drainage", {}))
    return cross_check_parts(sim, grid, materials, names, bodies, boundaries, walls, rigid, surcharges,
                             probes) + drainage_errors(drainage)


def _merge_errors(field: list[tuple[str, str]], cross: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Field errors, then the cross errors on keys that have no field error (nor a parent
    or child key with one)."""
    keys = [k for k, _ in field]

    def related(key: str) -> bool:
        return any(key == k or key.startswith(k + ".") or k.startswith(key + ".") for k in keys)

    return field + [(k, m) for k, m in cross if not related(k)]


def _resolve_defaults(s: Scenario) -> None:
    """Fill in defaults that depend on other sections: body names, and k0 (the material model's)."""
    for i, surcharge in enumerate(s.surcharges):
        if surcharge.name is None:
            surcharge.name = f"surcharge_{i}"
    for i, body in enumerate(s.bodies):
        if body.name is None:
            body.name = f"body_{i}"
        if body.k0 is None:
            body.k0 = s.materials[body.material].default_k0()
