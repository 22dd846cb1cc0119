"""``model = "drucker_prager"``: rate-independent Drucker–Prager plasticity for dry, cohesionless
granular matter (docs/physics.md §6c; engine: crates/axmpm-core/src/material/drucker_prager.rs).

Yield cone τ = μ p with τ = √(½ s:s) (a layer on an incline flows at tan θ = μ), isochoric
plastic flow, stress-free in tension. Rousseau et al. (2023, JFM) reproduce granular collapses
with this constant-friction rheology when μ is the tangent of the material's avalanche angle
(tan 27.4° = 0.518 for Lajeunesse et al.'s glass beads). State variables written to every frame:
``plastic_shear_strain`` and ``plastic_work`` (J/m³ of reference volume). Optional: Dunatunga &
Kamrin's disconnected state below ``critical_packing_fraction`` (as ``mohr_coulomb``), and the
Mohr–Coulomb deviatoric section (``mohr_coulomb_section``: stronger in triaxial compression)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..fields import Positive, bounded
from . import ElasticMaterial, critical_packing_errors, register_material


@register_material("drucker_prager")
class DruckerPrager(ElasticMaterial):
    """Rate-independent Drucker–Prager cone, no dilatancy, no cohesion."""

    model: Literal["drucker_prager"]
    friction: bounded(0.0, 1.0, lo_open=True, hi_open=True) = Field(  # type: ignore[valid-type]
        description="μ, friction coefficient τ/p of the yield cone")

    mohr_coulomb_section: bool = Field(
        False, description="true: the yield surface's deviatoric section is the Mohr–Coulomb hexagon "
        "with sin phi = friction (same strength in plane-strain shear, q/p = 6 sin phi/(3 - sin phi) "
        "in triaxial compression instead of sqrt(3) friction), reached by the same radial, isochoric "
        "return; false: the circular cone")

    # Disconnected state (drucker_prager.rs, Dunatunga & Kamrin 2015), as mohr_coulomb's.
    critical_packing_fraction: bounded(0.0, 1.0, lo_open=True, hi_open=True) | None = Field(  # type: ignore[valid-type]
        None,
        description="critical (random-loose) packing fraction phi_c, in (0, density/grain_density]: "
        "material looser than it (J > (density/grain_density)/phi_c) is disconnected and "
        "stress-free, and re-compacts to it without elastic rebound; needs grain_density; absent = off",
    )
    grain_density: Positive | None = Field(  # type: ignore[valid-type]
        None, description="kg/m³, solid density of the grains (> density); required with "
        "critical_packing_fraction")

    def cross_errors(self, prefix: str) -> list[tuple[str, str]]:
        return critical_packing_errors(prefix, self.density, self.grain_density, self.critical_packing_fraction)

    def default_k0(self) -> float:
        # Jaky's k0 = 1 − sin φ with sin φ = μ (the Mohr circle of a stress ratio τ/p = μ with
        # no normal-stress differences, as granular_fluidity.py).
        return 1.0 - self.friction
