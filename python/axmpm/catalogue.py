"""The one list of what the engine offers: formulations, interpolation schemes, material models
and region shapes.

The scenario schema (``axmpm.scenario``), ``axmpm bench``, the plots and the tests read these
names from here and nowhere else. The engine reports them itself through
``axmpm._core.catalogue()``; until that binding is available, :data:`_BUILT_IN` mirrors it.
Switching over is the one line in :func:`catalogue`.
"""

from __future__ import annotations

from functools import lru_cache

__all__ = ["catalogue", "formulations", "interpolation_schemes", "material_models", "region_shapes"]

#: The engine's lists as of this commit (crates/axmpm-core: config.rs FormulationKind and
#: ShapeFunctionKind, material/mod.rs build, setup.rs rectangles), in the engine's order.
_BUILT_IN: dict[str, tuple[str, ...]] = {
    "formulations": ("plane_strain", "axisymmetric"),
    "interpolation_schemes": ("linear", "ugimp", "cpgimp", "cpdi2"),
    "material_models": ("linear_elastic", "neo_hookean", "mohr_coulomb"),
    "region_shapes": ("rectangle",),
}


@lru_cache(maxsize=1)
def catalogue() -> dict[str, tuple[str, ...]]:
    """``{"formulations", "interpolation_schemes", "material_models", "region_shapes"}`` → names."""
    lists = _BUILT_IN  # TODO(engine catalogue): lists = _core.catalogue() once the binding is on main
    return {key: tuple(lists[key]) for key in _BUILT_IN}


def formulations() -> tuple[str, ...]:
    return catalogue()["formulations"]


def interpolation_schemes() -> tuple[str, ...]:
    return catalogue()["interpolation_schemes"]


def material_models() -> tuple[str, ...]:
    return catalogue()["material_models"]


def region_shapes() -> tuple[str, ...]:
    return catalogue()["region_shapes"]
