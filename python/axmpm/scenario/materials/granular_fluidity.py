"""``model = "granular_fluidity"`` (experimental: needs ``experimental = true``): the nonlocal
granular fluidity (NGF) model of dense granular flow (Kamrin & Koval 2012; Henann & Kamrin 2013; docs/physics.md §6b; engine:
crates/axmpm-core/src/material/granular_fluidity.rs).

An elasto-viscoplastic solid: plastic shear rate g μ with the fluidity g from
g = g_loc + ξ² ∇²g, g_loc = √(p/(ρ_s d²)) (μ − μ_s)/(b μ) above μ_s, ξ = A d / √|μ − μ_s|;
g = 0 on rough (fixed or frictional) walls and faces, zero flux elsewhere. The defaults are the
glass-bead values Henann & Kamrin (2013) used (μ_s = 0.3819 after Jop et al. 2006, b = 0.9377,
A = 0.48; quoted from Kamrin-group code, docs/physics.md §6b gives their confidence) and the
Lajeunesse et al. (2004) beads (d = 1.15 mm, ρ_s = 2500 kg/m³). State variables written to every
frame: ``fluidity`` (1/s), ``plastic_shear_strain`` and ``plastic_work`` (J/m³ of reference
volume)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..fields import NonNegative, Positive, bounded
from . import ElasticMaterial, register_material


@register_material("granular_fluidity")
class GranularFluidity(ElasticMaterial):
    """Nonlocal granular fluidity (Henann & Kamrin 2013)."""

    model: Literal["granular_fluidity"]
    static_friction: bounded(0.0, 1.0, lo_open=True, hi_open=True) = Field(  # type: ignore[valid-type]
        0.3819, description="μ_s, static friction coefficient τ/p")
    friction_rate: Positive = Field(  # type: ignore[valid-type]
        0.9377, description="b in the local law μ = μ_s + b I")
    nonlocal_amplitude: NonNegative = Field(  # type: ignore[valid-type]
        0.48, description="A, cooperativity length ξ = A d / √|μ − μ_s| (0 = the local law)")
    grain_diameter: Positive = Field(1.15e-3, description="m, d")  # type: ignore[valid-type]
    grain_density: Positive = Field(2500.0, description="kg/m³, ρ_s")  # type: ignore[valid-type]

    def default_k0(self) -> float:
        # Jaky's k0 = 1 − sin φ at the static friction, sin φ_s = μ_s (the Mohr circle of a
        # stress ratio τ/p = μ with no normal-stress differences: mu_i.rs).
        return 1.0 - self.static_friction
