"""``model = "von_mises"``: J2 plasticity with linear isotropic hardening for metals
(docs/physics.md §7; engine: crates/axmpm-core/src/material/von_mises.rs).

σ_y(ε̄p) = yield_stress + hardening_modulus · ε̄p, hypoelastic (Jaumann) elastic part, radial
return. State variables written to every frame: ``plastic_strain`` (ε̄p) and ``plastic_work``
(J/m³ of reference volume)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..fields import NonNegative, Positive
from . import ElasticMaterial, register_material


@register_material("von_mises")
class VonMises(ElasticMaterial):
    """J2 (von Mises) plasticity with linear isotropic hardening."""

    model: Literal["von_mises"]
    yield_stress: Positive = Field(description="Pa, initial yield stress σ_y in uniaxial tension")  # type: ignore[valid-type]
    hardening_modulus: NonNegative = Field(  # type: ignore[valid-type]
        0.0, description="Pa, plastic modulus H = dσ_y/dε̄p (0 = perfectly plastic)"
    )
