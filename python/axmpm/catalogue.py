"""The one list of what the engine offers: formulations, interpolation schemes, material models
and region shapes, as the engine reports them (``axmpm._core.catalogue()``, from its registries).

The scenario schema (``axmpm.scenario``), ``axmpm bench``, the verification case and the tests
read these names from here; nothing in Python repeats them. The engine is loaded on first use
(``import axmpm`` stays light).
"""

from __future__ import annotations

from functools import lru_cache

from .engine import core

__all__ = ["catalogue", "formulations", "interpolation_schemes", "material_models", "region_shapes", "one_of"]

KEYS = ("formulations", "interpolation_schemes", "material_models", "region_shapes")


@lru_cache(maxsize=1)
def catalogue() -> dict[str, tuple[str, ...]]:
    """``{"formulations", "interpolation_schemes", "material_models", "region_shapes"}`` → names,
    in the engine's order."""
    lists = core().catalogue()
    return {key: tuple(lists[key]) for key in KEYS}


def formulations() -> tuple[str, ...]:
    return catalogue()["formulations"]


def interpolation_schemes() -> tuple[str, ...]:
    return catalogue()["interpolation_schemes"]


def material_models() -> tuple[str, ...]:
    return catalogue()["material_models"]


def region_shapes() -> tuple[str, ...]:
    return catalogue()["region_shapes"]


def one_of(names: tuple[str, ...] | list[str]) -> str:
    """``'a', 'b' or 'c'``: how messages list the choices."""
    quoted = [repr(n) for n in names]
    return quoted[0] if len(quoted) == 1 else ", ".join(quoted[:-1]) + " or " + quoted[-1]
