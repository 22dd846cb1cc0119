"""``model = "drucker_prager"``: rate-independent Drucker–Prager plasticity for dry, cohesionless
granular matter (docs/physics.md §6c; engine: crates/axmpm-core/src/material/drucker_prager.rs).

Yield cone τ = μ p with τ = √(½ s:s) (a layer on an incline flows at tan θ = μ), isochoric
plastic flow, stress-free in tension. Rousseau et al. (2023, JFM) reproduce granular collapses
with this constant-friction rheology when μ is the tangent of the material's avalanche angle
(tan 27.4° = 0.518 for Lajeunesse et al.'s glass beads). State variables written to every frame:
``plastic_shear_strain`` and ``plastic_work`` (J/m³ of reference volume). Optional: the
Mohr–Coulomb deviatoric section (``mohr_coulomb_section``: stronger in triaxial compression); and,
experimental (with ``experimental = true``), Dunatunga & Kamrin's disconnected state below
``critical_packing_fraction`` (as ``mohr_coulomb``) and Jop et al.'s μ(I) friction
(``inertial_friction`` = μ₂, with ``friction`` as μ_s; then the state holds ``inertial_number``
as well)."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..fields import Positive, bounded
from . import ElasticMaterial, critical_packing_errors, inertial_grain_errors, register_material


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
        None, description="kg/m³, solid density of the grains (>= density; > density with "
        "critical_packing_fraction); required with critical_packing_fraction or inertial_friction")

    # μ(I) friction (drucker_prager.rs, Jop, Forterre & Pouliquen 2006): friction is then μ_s.
    inertial_friction: Positive | None = Field(  # type: ignore[valid-type]
        None, description="mu_2, the friction coefficient at large inertial number I, >= friction "
        "(< 1 with mohr_coulomb_section): mu(I) = friction + (mu_2 - friction) I/(I_0 + I), "
        "I = |shear rate| d / sqrt(p / grain_density) (Jop et al. 2006 glass beads: 0.6435 with "
        "friction 0.3819); absent = constant friction")
    inertial_number_scale: Positive = Field(  # type: ignore[valid-type]
        0.279, description="I_0 of the mu(I) law (Jop et al. 2006 glass beads: 0.279)")
    grain_diameter: Positive | None = Field(  # type: ignore[valid-type]
        None, description="m, grain size d in I; required with inertial_friction")

    def cross_errors(self, prefix: str) -> list[tuple[str, str]]:
        """The disconnected state's keys, and μ(I)'s: μ₂ ≥ μ (< 1 with the section), grain size
        and density given, grain density ≥ bulk."""
        from ..fields import fmt

        errors: list[tuple[str, str]] = []
        if self.inertial_friction is not None:
            mu2, mu = self.inertial_friction, self.friction
            if mu2 < mu or (self.mohr_coulomb_section and mu2 >= 1.0):
                upper = "1 (it is sin phi_2 with mohr_coulomb_section)" if self.mohr_coulomb_section else "a finite number"
                errors.append((f"{prefix}inertial_friction",
                               f"must be >= friction = {fmt(mu)} and < {upper} (got {fmt(mu2)})"))
            errors += inertial_grain_errors(prefix, "inertial_friction", self.density,
                                            self.grain_diameter, self.grain_density)
        return errors + critical_packing_errors(prefix, self.density, self.grain_density,
                                                self.critical_packing_fraction)

    def default_k0(self) -> float:
        # Jaky's k0 = 1 − sin φ with sin φ = μ (the Mohr circle of a stress ratio τ/p = μ with
        # no normal-stress differences, as granular_fluidity.py).
        return 1.0 - self.friction
