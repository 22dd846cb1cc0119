"""Material models of ``[materials.NAME]``, one module per model, each registered by name.

Adding a model = one module here with a section class registered by the decorator::

    @register_material("von_mises")
    class VonMises(ElasticMaterial):
        model: Literal["von_mises"]
        yield_stress: Positive = Field(description="Pa")

        def default_k0(self) -> float: ...              # optional: k0 of geostatic bodies
        def cross_errors(self, prefix) -> list: ...     # optional: checks between its keys

Every module of this package is imported when the package is (so nothing else changes), and
the scenario's ``materials`` table accepts every registered model (discriminated by ``model``).
The engine's models must each have one (tests/test_scenario.py compares with
:func:`axmpm.catalogue.material_models`).
"""

from __future__ import annotations

import importlib
import json
import pkgutil
from collections.abc import Callable
from typing import Annotated, Any, Union

from pydantic import Field

from ...engine import core
from ..fields import Positive, Section, bounded

__all__ = ["MaterialModel", "ElasticMaterial", "register_material", "MATERIAL_MODELS", "material_type",
           "model_names", "critical_packing_errors", "engine_key_errors"]

#: model name → section class, in registration order (see :func:`model_names` for the order used).
MATERIAL_MODELS: dict[str, type["MaterialModel"]] = {}


class MaterialModel(Section):
    """Base of every material section: the ``model`` tag and ``density``; the defaults and
    checks the scenario asks each model for."""

    density: Positive = Field(description="kg/m³")  # type: ignore[valid-type]
    experimental: bool = Field(
        False, strict=True,
        description="true: accept this material's experimental options (measured, not validated; "
        "docs/studies/granular-variants.md): drucker_prager inertial_friction, the "
        "critical_packing_fraction of drucker_prager and mohr_coulomb, the granular_fluidity model")

    def default_k0(self) -> float:
        """Lateral earth pressure ratio of a geostatic body of this material when it sets no k0."""
        return 1.0

    def cross_errors(self, prefix: str) -> list[tuple[str, str]]:
        """Problems between this model's own keys, as (``prefix + key``, message)."""
        return []


class ElasticMaterial(MaterialModel):
    """Isotropic elasticity: Young's modulus and Poisson's ratio (k0 = ν/(1 − ν))."""

    youngs_modulus: Positive = Field(description="Pa")  # type: ignore[valid-type]
    poisson_ratio: bounded(0.0, 0.5, hi_open=True)  # type: ignore[valid-type]

    def default_k0(self) -> float:
        return self.poisson_ratio / (1.0 - self.poisson_ratio)


def critical_packing_errors(prefix: str, density: float, grain_density: float | None,
                            critical_packing_fraction: float | None) -> list[tuple[str, str]]:
    """The checks of a ``critical_packing_fraction`` (the disconnected state of mohr_coulomb and
    drucker_prager): ``grain_density`` given and > ``density``, and φ_c ≤ φ0 = density /
    grain_density (material placed looser than φ_c would start disconnected)."""
    from ..fields import fmt

    if critical_packing_fraction is None:
        return []
    if grain_density is None:
        return [(f"{prefix}grain_density", "is required with critical_packing_fraction")]
    if not grain_density > density:
        return [(f"{prefix}grain_density",
                 f"must be > density = {fmt(density)} with critical_packing_fraction "
                 f"(packing as placed density/grain_density < 1; got {fmt(grain_density)})")]
    packing = density / grain_density
    if critical_packing_fraction > packing:
        return [(f"{prefix}critical_packing_fraction",
                 f"must be in (0, density/grain_density] = (0, {fmt(packing)}] "
                 f"(got {fmt(critical_packing_fraction)})")]
    return []


def inertial_grain_errors(prefix: str, switch: str, density: float, grain_diameter: float | None,
                          grain_density: float | None) -> list[tuple[str, str]]:
    """The grain keys μ(I) needs (drucker_prager's ``inertial_friction``, named by ``switch``):
    ``grain_diameter`` and ``grain_density`` given, the grain density at least the bulk
    ``density``."""
    from ..fields import fmt

    errors = [(f"{prefix}{key}", f"is required with {switch}")
              for key, value in (("grain_diameter", grain_diameter), ("grain_density", grain_density))
              if value is None]
    if grain_density is not None and grain_density < density:
        errors.append((f"{prefix}grain_density",
                       f"must be >= density = {fmt(density)} (the bulk density of the grains) "
                       f"(got {fmt(grain_density)})"))
    return errors


def engine_key_errors(name: str, table: dict[str, Any]) -> list[tuple[str, str]]:
    """The engine's refusals of the retired and experimental keys of material ``name`` (its
    table, ``model`` included), as (``materials.NAME.KEY``, message): the engine holds the rule
    and the wording (``axmpm._core.material_key_errors``), the front end only reports them."""
    found = core().material_key_errors(name, json.dumps(table, default=str))
    return [(f"materials.{name}.{key}", message) for key, message in found]


def register_material(name: str) -> Callable[[type[MaterialModel]], type[MaterialModel]]:
    """Class decorator: register a material section under its ``model`` name."""

    def decorate(cls: type[MaterialModel]) -> type[MaterialModel]:
        if name in MATERIAL_MODELS and MATERIAL_MODELS[name] is not cls:
            raise ValueError(f"material model {name!r} is registered twice")
        MATERIAL_MODELS[name] = cls
        return cls

    return decorate


for _info in pkgutil.iter_modules(__path__):
    if not _info.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_info.name}")


def model_names() -> list[str]:
    """The registered models: the engine's catalogue order first, then any others by name
    (loads the engine: for messages and reports, not at import)."""
    from ...catalogue import material_models

    engine = [m for m in material_models() if m in MATERIAL_MODELS]
    return engine + sorted(set(MATERIAL_MODELS) - set(engine))


def material_type() -> Any:
    """The type of one ``[materials.NAME]`` table: the registered models discriminated by ``model``
    (in registration order; messages list them in the engine's, :func:`model_names`)."""
    classes = tuple(MATERIAL_MODELS.values())
    if len(classes) == 1:
        return classes[0]
    return Annotated[Union[classes], Field(discriminator="model")]  # type: ignore[valid-type]
