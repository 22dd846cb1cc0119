"""The ``[simulation]`` and ``[grid]`` sections."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import AfterValidator, Field
from pydantic_core import PydanticCustomError

from ..catalogue import catalogue, one_of
from .fields import NonNegative, Positive, Section, Vec2, bounded

__all__ = ["Simulation", "Grid", "engine_choice"]


def engine_choice(key: str) -> Any:
    """A name from the engine's catalogue list ``key`` (:mod:`axmpm.catalogue`), checked when a
    scenario is validated (the engine is loaded then, not at import) with the message of a
    literal choice; the JSON Schema lists the names."""

    def check(value: Any) -> str:
        names = catalogue()[key]
        if not isinstance(value, str) or value not in names:
            raise PydanticCustomError("literal_error", "Input should be {expected}", {"expected": one_of(names)})
        return value

    def schema(s: dict[str, Any]) -> None:
        s.update(type="string", enum=list(catalogue()[key]))

    return Annotated[Any, AfterValidator(check), Field(json_schema_extra=schema)]


Formulation = engine_choice("formulations")
InterpolationScheme = engine_choice("interpolation_schemes")


class Simulation(Section):
    """``[simulation]``: formulation, interpolation, time integration."""

    formulation: Formulation
    shape_function: InterpolationScheme
    end_time: Positive = Field(description="s, simulated time to reach")
    output_interval: Positive = Field(description="s, time between output frames")
    history_interval: Positive | None = Field(  # type: ignore[valid-type]
        None, description="s: a history.csv row (energies, reactions, rigid bodies) this often between "
        "output frames, <= output_interval; absent = rows at the output times only")
    gravity: Vec2 = Field((0.0, -9.81), description="m/s², [x or r, y or z]")
    gravity_ramp_time: NonNegative = Field(
        0.0, description="s: gravity grows linearly from 0 over this time"
    )
    time_step: NonNegative = Field(
        0.0, description="s; 0 = from the CFL number and the fastest wave speed"
    )
    cfl: bounded(0.0, 1.0, lo_open=True) = 0.4  # type: ignore[valid-type]
    update_scheme: Literal["musl", "usl"] = "musl"
    flip_fraction: bounded(0.0, 1.0) = Field(  # type: ignore[valid-type]
        0.99, description="1 = pure FLIP, 0 = pure PIC"
    )
    xpic_order: bounded(1, 8, kind=int) = Field(  # type: ignore[valid-type]
        1,
        description="order m of the XPIC(m) filter that forms the non-FLIP share of the velocity update: "
        "1 = PIC (damps smooth motion at the rate (1 - flip_fraction)/dt); m > 1 removes the grid's "
        "null-space noise as PIC does and damps smooth motion to order m (Hammerquist & Nairn 2017), "
        "at the cost of m - 1 more particle passes per step. Experimental above 1: needs experimental = true",
    )
    experimental: bool = Field(False, description="allow the experimental options (xpic_order above 1)")
    damping: bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
        0.0, description="Cundall local damping coefficient"
    )
    volumetric_averaging: Literal["none", "cell"] = Field(
        "none",
        description="anti-locking: 'cell' replaces each particle's volumetric strain rate by "
        "the volume-weighted mean of its background cell (mean dilatation / F-bar)",
    )
    stop_at_rest: bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
        0.0,
        description="stop (status completed) at the first output time when the kinetic energy is "
        "below this fraction of the work done by gravity; 0 = run to end_time",
    )
    stop_when_settled: bounded(0.0, 1.0, hi_open=True) = Field(  # type: ignore[valid-type]
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


class Grid(Section):
    """``[grid]``: a dense background grid of square cells."""

    origin: Vec2 = Field((0.0, 0.0), description="m; axisymmetric grids start at r = 0")
    extent: tuple[Positive, Positive] = Field(description="m, each a whole number of cells")  # type: ignore[valid-type]
    cell_size: Positive = Field(description="m")
    follow: str | None = Field(
        None,
        description="name of a rigid body the grid moves with along y (modulo one cell), so that the "
        "body keeps its place relative to the node rows: no node row enters or leaves its contact as "
        "it penetrates (a pile, a cone, a footing pushed deep). Not with walls, saturated bodies or "
        "granular_fluidity materials; the bottom and top faces then act on the node row at most one "
        "cell outside the grid's extent. Experimental: needs experimental = true",
    )
    experimental: bool = Field(False, description="allow the experimental options (follow)")

    def cells(self) -> tuple[int, int]:
        """Number of cells in x (r) and y (z)."""
        return (
            int(round(self.extent[0] / self.cell_size)),
            int(round(self.extent[1] / self.cell_size)),
        )
