"""``model = "neo_hookean"``: compressible neo-Hookean hyperelasticity."""

from __future__ import annotations

from typing import Literal

from . import ElasticMaterial, register_material



@register_material("neo_hookean")
class NeoHookean(ElasticMaterial):
    """Compressible neo-Hookean: σ = (1/J)[μ(b − I) + λ ln J I]."""

    model: Literal["neo_hookean"]
