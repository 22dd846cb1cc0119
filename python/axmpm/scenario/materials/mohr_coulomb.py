"""``model = "mohr_coulomb"``: elastic–perfectly plastic Mohr–Coulomb, non-associated, with
optional tension cut-off, re-compaction, a disconnected state below the critical packing and
μ(I) friction (docs/physics.md §5); with
``friction_angle = 0`` and ``cohesion > 0`` it is Tresca (undrained clay, c = s_u; §8)."""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from ..fields import NonNegative, Positive, bounded, fmt
from . import ElasticMaterial, critical_packing_errors, inertial_grain_errors, register_material

#: Mohr–Coulomb ``recompaction`` when a scenario does not set it (same as the engine's
#: ``mohr_coulomb::RECOMPACTION_DEFAULT``).
RECOMPACTION_DEFAULT = False


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
    recompaction: bool = Field(
        RECOMPACTION_DEFAULT,
        strict=True,
        description="true: material separated by tension (apex / cut-off returns) re-compacts "
        "stress-free before it carries compression again (Dunatunga & Kamrin 2015); false: the "
        "opened volume is permanent",
    )
    # Disconnected state (mohr_coulomb.rs, Dunatunga & Kamrin 2015): present = material whose
    # packing density/grain_density / J falls below it carries no stress.
    critical_packing_fraction: bounded(0.0, 1.0, lo_open=True, hi_open=True) | None = Field(  # type: ignore[valid-type]
        None,
        description="critical (random-loose) packing fraction phi_c, in (0, density/grain_density]: "
        "material looser than it (J > (density/grain_density)/phi_c) is disconnected and "
        "stress-free, and re-compacts to it without elastic rebound; needs grain_density; "
        "excludes recompaction; absent = off",
    )
    cell_averaged_disconnection: bool = Field(
        False,
        strict=True,
        description="with critical_packing_fraction: true = the disconnection test uses the mean J "
        "of the particle's background cell (sum V / sum V0 at the start of the step: the cell's "
        "packing) instead of the particle's own J; false (default) = the particle's own",
    )
    # μ(I) friction (mu_i.rs): present = the friction angle follows the inertial number.
    inertial_friction_angle: bounded(0.0, 90.0, lo_open=True, hi_open=True) | None = Field(  # type: ignore[valid-type]
        None,
        description="degrees, in [friction_angle, 90): the friction angle at large inertial "
        "number I (mu(I) rheology, sin(phi) = mu_s + (mu_2 - mu_s) I/(I_0 + I), Jop et al. 2006); "
        "absent = rate-independent",
    )
    inertial_number_scale: Positive = Field(  # type: ignore[valid-type]
        0.279, description="I_0 of the mu(I) law (Jop et al. 2006 glass beads: 0.279)"
    )
    grain_diameter: Positive | None = Field(  # type: ignore[valid-type]
        None, description="m, grain size d in I = |shear rate| d / sqrt(P / grain_density); "
        "required with inertial_friction_angle"
    )
    grain_density: Positive | None = Field(  # type: ignore[valid-type]
        None, description="kg/m³, solid density of the grains (>= density; > density with "
        "critical_packing_fraction); required with inertial_friction_angle or "
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
        """ψ ≤ φ; the μ(I) keys: φ₂ ≥ φ, grain size and density given, grain density ≥ bulk."""
        errors: list[tuple[str, str]] = []
        if self.friction_angle == 0.0 and not self.cohesion > 0.0:
            errors.append((f"{prefix}friction_angle",
                           f"= 0 (Tresca) needs cohesion > 0 (got cohesion = {fmt(self.cohesion)})"))
        if self.friction_angle == 0.0 and self.inertial_friction_angle is not None:
            errors.append((f"{prefix}inertial_friction_angle",
                           "needs a static friction_angle > 0 (not Tresca, friction_angle = 0)"))
        if self.dilation_angle > self.friction_angle:
            errors.append((f"{prefix}dilation_angle",
                           f"must be <= friction_angle = {fmt(self.friction_angle)} (got {fmt(self.dilation_angle)})"))
        if self.inertial_friction_angle is not None:
            if self.inertial_friction_angle < self.friction_angle:
                errors.append((f"{prefix}inertial_friction_angle",
                               f"must be >= friction_angle = {fmt(self.friction_angle)} and < 90 "
                               f"(got {fmt(self.inertial_friction_angle)})"))
            errors += inertial_grain_errors(prefix, "inertial_friction_angle", self.density,
                                            self.grain_diameter, self.grain_density)
        if self.cell_averaged_disconnection and self.critical_packing_fraction is None:
            errors.append((f"{prefix}cell_averaged_disconnection",
                           "= true needs critical_packing_fraction (it changes how the disconnected "
                           "state is detected)"))
        if self.critical_packing_fraction is not None and self.recompaction:
            errors.append((f"{prefix}critical_packing_fraction",
                           "cannot be combined with recompaction = true (both model separated "
                           "material: choose one)"))
        errors += critical_packing_errors(prefix, self.density, self.grain_density, self.critical_packing_fraction)
        return errors
