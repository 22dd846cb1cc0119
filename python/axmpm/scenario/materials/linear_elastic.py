"""``model = "linear_elastic"``: small-strain isotropic elasticity (Hooke)."""

from __future__ import annotations

from typing import Literal

from . import ElasticMaterial, register_material



@register_material("linear_elastic")
class LinearElastic(ElasticMaterial):
    """Small-strain isotropic elasticity (Hooke)."""

    model: Literal["linear_elastic"]
