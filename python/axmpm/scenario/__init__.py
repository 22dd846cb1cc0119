"""Scenario files: TOML → validated, resolved pydantic models → JSON for the engine.

The structure, key names and defaults are the binding contract of ``docs/architecture.md``:
sections ``simulation``, ``grid``, ``materials`` (name → material, discriminated by
``model``), ``bodies`` (list, each a region by ``shape``), ``boundaries`` and ``walls`` (list).
Units are SI, angles in degrees, stresses tension positive.

The package, one concern per module:

* :mod:`.fields`: range-checked number types, the section base;
* :mod:`.sections`: ``[simulation]``, ``[grid]``;
* :mod:`.materials`: one module per material model, registered with ``@register_material``;
* :mod:`.bodies` and :mod:`.regions`: ``[[bodies]]``, one module per shape, ``@register_region``;
* :mod:`.boundaries`: ``[boundaries]`` and ``[[walls]]``;
* :mod:`.model`: :class:`Scenario`, the checks between sections and the resolved defaults;
* :mod:`.messages`: validation errors as ``dotted.key: message``;
* :mod:`.files`: reading TOML, ``--set`` overrides.
"""

from ..errors import ScenarioError
from .bodies import BodyHead, BodyKeys, Region
from .boundaries import Boundaries, BoundaryCondition, Wall
from .fields import GRID_TOLERANCE
from .files import apply_overrides, parse_value, read_toml
from .materials import MATERIAL_MODELS, ElasticMaterial, MaterialModel, register_material
from .materials.linear_elastic import LinearElastic
from .materials.mohr_coulomb import MohrCoulomb
from .materials.neo_hookean import NeoHookean
from .messages import convert_errors
from .model import Body, Material, Scenario, schema_json
from .regions import REGION_SHAPES, register_region
from .regions.rectangle import Rectangle
from .sections import Grid, Simulation

__all__ = [
    "Scenario",
    "Simulation",
    "Grid",
    "Material",
    "MaterialModel",
    "ElasticMaterial",
    "LinearElastic",
    "NeoHookean",
    "MohrCoulomb",
    "MATERIAL_MODELS",
    "register_material",
    "Body",
    "BodyHead",
    "BodyKeys",
    "Region",
    "Rectangle",
    "REGION_SHAPES",
    "register_region",
    "BoundaryCondition",
    "Boundaries",
    "Wall",
    "ScenarioError",
    "GRID_TOLERANCE",
    "apply_overrides",
    "parse_value",
    "read_toml",
    "schema_json",
    "convert_errors",
]
