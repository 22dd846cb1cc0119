"""``model = "mohr_coulomb"``: elastic–perfectly plastic Mohr–Coulomb, non-associated, with
an optional tension cut-off and (experimental) a disconnected state below the critical packing
(docs/physics.md §5); with ``friction_angle = 0`` and ``cohesion > 0`` it is Tresca (undrained
clay, c = s_u; §8)."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from ..fields import NonNegative, Positive, bounded, fmt
from . import ElasticMaterial, critical_packing_errors, register_material

@register_material("mohr_coulomb")
class MohrCoulomb(ElasticMaterial):
    """Elastic–perfectly plastic Mohr–Coulomb, non-associated (dilation angle ψ ≤ φ); Tresca
    for friction_angle = 0 (then cohesion > 0, dilation_angle 0, no tension cut-off unless given)."""

    model: Literal["mohr_coulomb"]
    friction_angle: bounded(0.0, 90.0, hi_open=True) = Field(  # type: ignore[valid-type]
        description="degrees; 0 = Tresca (undrained, total stress: needs cohesion > 0)"
    )
    dilation_angle: NonNegative = Field(0.0, description="degrees, <= friction_angle")
    cohesion: NonNegative = Field(0.0, description="Pa (s_u for Tresca)")
    tension_cutoff: NonNegative | None = Field(  # type: ignore[valid-type]
        None, description="Pa; absent: 0 (no tension) for friction_angle > 0, no cut-off for Tresca "
        "(friction_angle = 0)")
    # Disconnected state (mohr_coulomb.rs, Dunatunga & Kamrin 2015): present = material whose
    # packing density/grain_density / J falls below it carries no stress.
    critical_packing_fraction: bounded(0.0, 1.0, lo_open=True, hi_open=True) | None = Field(  # type: ignore[valid-type]
        None,
        description="critical (random-loose) packing fraction phi_c, in (0, density/grain_density]: "
        "material looser than it (J > (density/grain_density)/phi_c) is disconnected and "
        "stress-free, and re-compacts to it without elastic rebound; needs grain_density; "
        "absent = off",
    )
    grain_density: Positive | None = Field(  # type: ignore[valid-type]
        None, description="kg/m³, solid density of the grains (> density); required with "
        "critical_packing_fraction"
    )

    @model_validator(mode="after")
    def _resolve_tension_cutoff(self) -> "MohrCoulomb":
        """The resolved default: 0 for φ > 0; none (absent) for Tresca."""
        if self.tension_cutoff is None and self.friction_angle > 0.0:
            self.tension_cutoff = 0.0
        return self

    def default_k0(self) -> float:
        """Jaky's 1 − sin φ."""
        return 1.0 - math.sin(math.radians(self.friction_angle))

    def cross_errors(self, prefix: str) -> list[tuple[str, str]]:
        """Tresca needs c > 0; ψ ≤ φ; the disconnected state's keys."""
        errors: list[tuple[str, str]] = []
        if self.friction_angle == 0.0 and not self.cohesion > 0.0:
            errors.append((f"{prefix}friction_angle",
                           f"= 0 (Tresca) needs cohesion > 0 (got cohesion = {fmt(self.cohesion)})"))
        if self.dilation_angle > self.friction_angle:
            errors.append((f"{prefix}dilation_angle",
                           f"must be <= friction_angle = {fmt(self.friction_angle)} (got {fmt(self.dilation_angle)})"))
        errors += critical_packing_errors(prefix, self.density, self.grain_density, self.critical_packing_fraction)
        return errors
