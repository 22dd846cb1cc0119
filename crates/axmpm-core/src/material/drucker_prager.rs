//! Rate-independent Drucker–Prager plasticity for dry, cohesionless granular matter: the
//! constant-friction rheology τ ≤ μ p that Rousseau et al. (2023, *Revisiting the role of
//! friction coefficients in granular collapses: confrontation of 3-D non-smooth simulations
//! with experiments*, JFM) found to reproduce granular collapses with μ set to the tangent of
//! the material's *avalanche* (start) angle rather than its stop angle. docs/physics.md §6c.
//!
//! # Law
//!
//! With p = −tr σ / 3, the deviator s = σ + p I and τ = √(½ s:s) (3D, the hoop or out-of-plane
//! component included; in simple shear with equal normal stresses τ is the shear stress, so a
//! layer on an incline flows at tan θ = μ):
//!
//! ```text
//! yield surface     τ = μ p             (a cone about the hydrostatic axis, no Lode-angle term)
//! plastic flow      Dᵖ ∥ s              (isochoric: no dilatancy, the critical state)
//! tension           p ≤ 0 → σ = 0       (grains that separate carry no stress)
//! ```
//!
//! # Update (one step)
//!
//! 1. Elastic predictor: the linear-elastic Jaumann step of [`LinearElastic`].
//! 2. If p_tr ≤ 0 the material is stress-free. If τ_tr ≤ μ p_tr the step is elastic. Otherwise
//!    the deviator is scaled onto the cone at fixed pressure, s = s_tr μ p_tr / τ_tr: the
//!    backward-Euler (closest-point) return of an isochoric flow rule, exact in one step
//!    because the pressure does not change during the return. It is the rate-independent limit
//!    b → 0 of the granular fluidity model's local law (granular_fluidity.rs), solved
//!    implicitly instead of through a start-of-step fluidity.
//!
//! # Mohr–Coulomb deviatoric section (`mohr_coulomb_section = true`)
//!
//! Optional, off by default (the update is then the plain one, bit for bit). The circular
//! cone has the same strength whatever the Lode angle, so calibrated in shear (the inclined
//! flow where an avalanche angle is measured) it is weaker in triaxial compression than a
//! granular material: q/p = √3 μ against Mohr–Coulomb's 6 sin φ/(3 − sin φ). With the option
//! the radius of the section is that of the Mohr–Coulomb hexagon with sin φ = μ, so the
//! strength in plane-strain shear (ξ = 0) is unchanged and triaxial compression is stronger:
//!
//! ```text
//! τ = μ p g(ξ),   g(ξ) = 1 / [sin(α + π/3) + (μ/√3) cos(α + π/3)],   α = arccos(ξ)/3
//! ξ = (3√3/2) J₃/τ³     (−1 triaxial compression, 0 shear, +1 triaxial extension)
//! ```
//!
//! (from (σ₁ − σ₃) + (σ₁ + σ₃) sin φ = 0 with the principal deviator written in α; g(0) = 1,
//! g(−1) = 2√3/(3 − μ), g(+1) = 2√3/(3 + μ)). The return stays the radial one at fixed p,
//! which keeps the trial's Lode angle, so it lands on the section exactly in one step; the
//! flow remains isochoric and along the deviator (non-associated), unlike mohr_coulomb.rs,
//! whose returns to an edge of the pyramid change the Lode angle.
//!
//! # μ(I) friction (`inertial_friction`)
//!
//! Optional, off by default (the update is then the plain one, bit for bit): the friction
//! coefficient follows the inertial number, Jop, Forterre & Pouliquen's (2006) μ(I) rheology,
//! with `friction` as its static value μ_s and `inertial_friction` as μ₂:
//!
//! ```text
//! I = |γ̇| d / √(p / ρ_s),   μ(I) = μ_s + (μ₂ − μ_s) I / (I₀ + I)
//! ```
//!
//! (mu_i.rs, "Law": the same I and μ(I), from the start-of-step stress and the step's rate of
//! deformation, then the step is the rate-independent one at μ(I)). The cone needs no mapping:
//! Jop et al.'s stress −p I + μ p γ̇/|γ̇| has √J₂ = μ p exactly, so on the circle this is their
//! 3D law, and their glass-bead μ_s = tan 20.9°, μ₂ = tan 32.76° (measured as tan θ of steady
//! chute flows, simple shear) enter as they are. With the Mohr–Coulomb section, sin φ = μ(I).
//!
//! # Dilute material and the time step
//!
//! As in mohr_coulomb.rs ("Dilute material and the time step"): the moduli are those of the
//! material as placed, so a particle dilated stress-free to J ≫ 1 and then re-loaded has the
//! P-wave speed c0 √J, beyond what the explicit step keeps stable. Above
//! J_s = max(1, (c_max/c0)²) ([`Material::limit_wave_speed`]) the moduli of the trial are
//! scaled by J_s/J (a granular gas has no contact network, so any stiffness below the
//! material's as placed is admissible). Up to J_s the update is the plain one, bit for bit.
//!
//! # Disconnected material below the critical packing (`critical_packing_fraction`)
//!
//! Optional, off by default (the update is then the plain one, bit for bit): Dunatunga &
//! Kamrin's (2015) disconnected state, with the rule of mohr_coulomb.rs ("Disconnected
//! material below the critical packing") and its parameters (`critical_packing_fraction` φ_c,
//! `grain_density` ρ_s; J_c = ρ0/(φ_c ρ_s), [`Parameters::critical_jacobian`]). Granular
//! matter looser than φ_c has no enduring contacts: at J > J_c the particle is stress-free
//! whatever its strain increment, in compression as in tension (the plain model only frees it
//! in tension). A step that ends at J ≤ J_c after starting above it first takes out of the
//! strain increment the compaction done while still looser than φ_c, ln(J_n/J_c) with
//! ln J_n = ln J − tr Δε, so the material re-connects at φ_c with σ = 0 and stores nothing of
//! that compaction: the re-compaction of loose material is inelastic (no rebound), as in a
//! dilatable rigid-plastic continuum (Rousseau et al. 2023). With cell-averaged dilatation
//! (F-bar) J is the cell's, a packing of the continuum rather than of one particle.
//!
//! # State variables
//!
//! - `plastic_shear_strain`: Σ Δγᵖ, Δγᵖ = (τ_tr − τ)/G of each return (the shear strain the
//!   deviator gave up).
//! - `plastic_work`: per unit reference volume, J/m³: Σ J (σ_n : Δε − ΔW_e) over the steps that
//!   flow or separate, the start-of-step stress power less the change of the stored
//!   (complementary) elastic energy W_e, so that the model adds no residual of its own to the
//!   energy budget (as granular_fluidity.rs).

use super::mu_i::{grain_scale_parameters, inertial_friction, inertial_number, INERTIAL_NUMBER_CAP};
use super::{
    jaumann_rotation, pressure_and_shear, rate_of_deformation, stable_jacobian, stress_power, take_out_disconnected_compaction,
    Kinematics,
    LinearElastic, Material, Parameters,
};
use crate::particles::Stress;

const STATE_NAMES: [&str; 2] = ["plastic_shear_strain", "plastic_work"];
/// With μ(I): the inertial number of the particle's last step as well (capped at
/// [`INERTIAL_NUMBER_CAP`] where p ≤ 0, as mu_i.rs).
const STATE_NAMES_INERTIAL: [&str; 3] = ["plastic_shear_strain", "plastic_work", "inertial_number"];
const SHEAR_STRAIN_SLOT: usize = 0;
const WORK_SLOT: usize = 1;
const INERTIAL_NUMBER_SLOT: usize = 2;

/// The μ(I) law of the cone (module doc, "μ(I) friction"); μ_s is [`DruckerPrager::friction`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InertialFriction {
    /// μ₂, the friction at I → ∞ (≥ μ_s).
    pub dynamic_friction: f64,
    /// I₀.
    pub inertial_number_scale: f64,
    /// d, m.
    pub grain_diameter: f64,
    /// ρ_s, kg/m³.
    pub grain_density: f64,
}

/// The Drucker–Prager model (module doc).
#[derive(Clone, Debug)]
pub struct DruckerPrager {
    /// The elastic part (the predictor is its step).
    pub elastic: LinearElastic,
    /// μ, the friction coefficient τ/p of the yield cone.
    pub friction: f64,
    /// G, Pa.
    shear_modulus: f64,
    /// J above which the moduli are scaled by `stable_jacobian / J` (module doc, "Dilute
    /// material"); ∞ = never (set by [`Material::limit_wave_speed`]).
    pub stable_jacobian: f64,
    /// J_c = φ0/φ_c above which the material is disconnected (module doc); `None` = off.
    pub critical_jacobian: Option<f64>,
    /// Whether the deviatoric section is Mohr–Coulomb's hexagon with sin φ = μ (module doc);
    /// false = the circular cone.
    pub mohr_coulomb_section: bool,
    /// μ(I) friction with `friction` as μ_s (module doc); `None` = constant friction.
    pub inertial: Option<InertialFriction>,
}

/// ξ = (3√3/2) J₃/τ³ of `stress` with pressure p (compression positive) and τ = √J₂ > 0: the
/// cosine of three times the Lode angle (σ₃₃, the hoop or out-of-plane stress, is principal).
#[inline(always)]
pub fn lode_parameter(stress: &Stress, p: f64, tau: f64) -> f64 {
    let (s11, s22, s33) = (stress[0] + p, stress[1] + p, stress[2] + p);
    let j3 = s33 * (s11 * s22 - stress[3] * stress[3]);
    1.5 * 3f64.sqrt() * j3 / (tau * tau * tau)
}

/// g(ξ), the radius of the Mohr–Coulomb section with sin φ = `sin_phi` at Lode parameter ξ,
/// relative to its radius in plane-strain shear (module doc, "Mohr–Coulomb deviatoric
/// section"). ξ is clamped to [−1, 1] against round-off.
#[inline(always)]
pub fn mohr_coulomb_section_radius(xi: f64, sin_phi: f64) -> f64 {
    let angle = xi.clamp(-1.0, 1.0).acos() / 3.0 + std::f64::consts::FRAC_PI_3;
    1.0 / (angle.sin() + sin_phi / 3f64.sqrt() * angle.cos())
}

impl DruckerPrager {
    pub fn new(density: f64, youngs_modulus: f64, poisson_ratio: f64, friction: f64) -> Self {
        Self {
            elastic: LinearElastic::new(density, youngs_modulus, poisson_ratio),
            friction,
            shear_modulus: youngs_modulus / (2.0 * (1.0 + poisson_ratio)),
            stable_jacobian: f64::INFINITY,
            critical_jacobian: None,
            mohr_coulomb_section: false,
            inertial: None,
        }
    }

    /// Makes the friction follow μ(I) with `friction` as μ_s (module doc); `None` leaves it
    /// constant.
    pub fn with_inertial_friction(mut self, law: Option<InertialFriction>) -> Self {
        self.inertial = law;
        self
    }

    /// The friction coefficient of a step from the start-of-step `stress` and the step's rate
    /// of deformation `d`, with the inertial number it used (0 without μ(I)).
    #[inline(always)]
    fn friction_of_step(&self, stress: &Stress, d: &[f64; 4]) -> (f64, f64) {
        match &self.inertial {
            None => (self.friction, 0.0),
            Some(law) => {
                let i = inertial_number(stress, d, law.grain_diameter, law.grain_density);
                (inertial_friction(self.friction, law.dynamic_friction, law.inertial_number_scale, i), i)
            }
        }
    }

    /// Gives the yield surface Mohr–Coulomb's deviatoric section with sin φ = μ (module doc).
    pub fn with_mohr_coulomb_section(mut self, on: bool) -> Self {
        self.mohr_coulomb_section = on;
        self
    }

    /// Switches the disconnected state on above J = `critical_jacobian` (module doc); `None`
    /// leaves the plain model.
    pub fn with_disconnection(mut self, critical_jacobian: Option<f64>) -> Self {
        self.critical_jacobian = critical_jacobian;
        self
    }

    /// From a `drucker_prager` table; every key is required (the scenario front end fills the
    /// documented defaults) but the optional `critical_packing_fraction`, `grain_density`,
    /// `mohr_coulomb_section` (false when absent) and `inertial_friction` (μ₂; with it
    /// `grain_diameter` and `grain_density` are required, `inertial_number_scale` defaults to
    /// Jop et al.'s 0.279).
    /// Errors name `materials.NAME.KEY` and the allowed range.
    pub fn from_parameters(p: &Parameters) -> Result<Self, String> {
        let density = p.positive("density", " kg/m³")?;
        let youngs_modulus = p.positive("youngs_modulus", " Pa")?;
        let poisson_ratio = p.poisson_ratio()?;
        let friction = p.positive("friction", "")?;
        let critical_jacobian = p.critical_jacobian(density)?;
        let mohr_coulomb_section = p.bool_or("mohr_coulomb_section", false)?;
        if mohr_coulomb_section && friction >= 1.0 {
            return Err(p.error("friction", format!("must be < 1 with mohr_coulomb_section (it is sin φ; got {friction})")));
        }
        let inertial = Self::inertial_from_parameters(p, friction, mohr_coulomb_section)?;
        Ok(Self::new(density, youngs_modulus, poisson_ratio, friction)
            .with_disconnection(critical_jacobian)
            .with_mohr_coulomb_section(mohr_coulomb_section)
            .with_inertial_friction(inertial))
    }

    /// The μ(I) keys of a table, `None` without `inertial_friction`.
    fn inertial_from_parameters(p: &Parameters, friction: f64, mohr_coulomb_section: bool)
                                -> Result<Option<InertialFriction>, String> {
        let Some(mu2) = p.optional_f64("inertial_friction")? else {
            return Ok(None);
        };
        if mohr_coulomb_section && !(mu2 >= friction && mu2 < 1.0) {
            return Err(p.error("inertial_friction", format!(
                "must be in [friction, 1) = [{friction}, 1) with mohr_coulomb_section (it is sin φ₂; got {mu2})")));
        }
        if !(mu2 >= friction && mu2.is_finite()) {
            return Err(p.error("inertial_friction", format!("must be finite and >= friction = {friction} (got {mu2})")));
        }
        let (inertial_number_scale, grain_diameter, grain_density) = grain_scale_parameters(p, "inertial_friction")?;
        Ok(Some(InertialFriction { dynamic_friction: mu2, inertial_number_scale, grain_diameter, grain_density }))
    }
}

/// The registry's builder ([`super::MODELS`]).
pub fn build(p: &Parameters) -> Result<Box<dyn Material>, String> {
    Ok(Box::new(DruckerPrager::from_parameters(p)?))
}

impl Material for DruckerPrager {
    fn model(&self) -> &'static str {
        "drucker_prager"
    }
    fn density(&self) -> f64 {
        self.elastic.density
    }
    fn wave_speed(&self) -> f64 {
        self.elastic.wave_speed()
    }
    fn state_names(&self) -> &'static [&'static str] {
        if self.inertial.is_some() {
            &STATE_NAMES_INERTIAL
        } else {
            &STATE_NAMES
        }
    }
    fn elastic_energy_density(&self, stress: &Stress) -> f64 {
        self.elastic.elastic_energy_density(stress)
    }

    fn limit_wave_speed(&mut self, max_wave_speed: f64) {
        self.stable_jacobian = stable_jacobian(max_wave_speed, self.wave_speed());
    }

    #[inline(always)]
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], k: &Kinematics) {
        let start = *stress;
        // Elastic predictor: the linear-elastic Jaumann step, with the moduli scaled by
        // s = J_s/J for dilute material (module doc).
        let (d, spin) = rate_of_deformation(&k.velocity_gradient);
        let mut strain = [d[0] * k.dt, d[1] * k.dt, d[2] * k.dt, d[3] * k.dt];
        let mut disconnected = false;
        if let Some(jc) = self.critical_jacobian {
            if k.jacobian > jc {
                disconnected = true;
            } else {
                take_out_disconnected_compaction(&mut strain, k.jacobian, jc);
            }
        }
        let stiffness = if k.jacobian > self.stable_jacobian { self.stable_jacobian / k.jacobian } else { 1.0 };
        let de = [strain[0] * stiffness, strain[1] * stiffness, strain[2] * stiffness, strain[3] * stiffness];
        let rot = jaumann_rotation(stress, spin, k.dt);
        let inc = self.elastic.elastic_increment(&de);
        for c in 0..4 {
            stress[c] += inc[c] + rot[c];
        }
        // μ, or μ(I) from the start-of-step stress (module doc, "μ(I) friction").
        let (friction, inertial_number) = self.friction_of_step(&start, &d);
        if let Some(slot) = state.get_mut(INERTIAL_NUMBER_SLOT) {
            *slot = inertial_number.min(INERTIAL_NUMBER_CAP);
        }
        let (p, tau) = pressure_and_shear(stress);
        if p > 0.0 && !disconnected {
            let strength = if self.mohr_coulomb_section && tau > 0.0 {
                friction * p * mohr_coulomb_section_radius(lode_parameter(stress, p, tau), friction)
            } else {
                friction * p
            };
            if tau <= strength {
                return; // elastic
            }
            // Return at fixed p along the trial deviator, s = s_tr μ p g / τ_tr: the closest point
            // on the circle (g = 1); on the hexagon the radial, non-associated return (module doc).
            let scale = strength / tau;
            for c in 0..3 {
                stress[c] = -p + scale * (stress[c] + p);
            }
            stress[3] *= scale;
            state[SHEAR_STRAIN_SLOT] += (tau - strength) / (stiffness * self.shear_modulus);
        } else {
            // Tension, or looser than the critical packing: the grains separate, stress-free.
            *stress = [0.0; 4];
        }
        let power = stress_power(&start, &d, k.dt);
        let stored = self.elastic_energy_density(stress) - self.elastic_energy_density(&start);
        state[WORK_SLOT] += k.jacobian * (power - stored);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::testing::{kinematics, MaterialPoint};

    /// Glass beads at the avalanche angle of Lajeunesse et al.'s beads, tan 27.4°.
    fn beads() -> DruckerPrager {
        DruckerPrager::new(1550.0, 1e6, 0.3, 27.4f64.to_radians().tan())
    }

    fn power(start: &Stress, k: &Kinematics) -> f64 {
        stress_power(start, &rate_of_deformation(&k.velocity_gradient).0, k.dt)
    }

    #[test]
    fn pressure_and_shear_of_simple_and_triaxial_stress() {
        let (p, tau) = pressure_and_shear(&[-100.0, -100.0, -100.0, 30.0]);
        assert_eq!((p, tau), (100.0, 30.0));
        // σ = diag(−1, −1, −4): p = 2, s = (1, 1, −2), ½ s:s = 3; and with the order changed.
        for stress in [[-1.0, -1.0, -4.0, 0.0], [-4.0, -1.0, -1.0, 0.0], [-1.0, -4.0, -1.0, 0.0]] {
            let (p, tau) = pressure_and_shear(&stress);
            assert!((p - 2.0).abs() < 1e-15 && (tau - 3f64.sqrt()).abs() < 1e-15, "{stress:?}: {p}, {tau}");
        }
    }

    #[test]
    fn below_the_cone_the_step_is_the_elastic_one() {
        let m = beads();
        let elastic = LinearElastic::new(1550.0, 1e6, 0.3);
        let (mut s_dp, mut s_elastic) = ([-500.0, -400.0, -450.0, 100.0], [-500.0, -400.0, -450.0, 100.0]);
        let mut state = [0.0; 2];
        let k = kinematics([1e-3, 2e-3, 0.0, -1e-3, 0.0], 1e-3);
        for _ in 0..10 {
            m.update_stress(&mut s_dp, &mut state, &k);
            elastic.update_stress(&mut s_elastic, &mut [], &k);
        }
        assert_eq!(s_dp, s_elastic);
        assert_eq!(state, [0.0; 2]);
    }

    #[test]
    fn a_return_lands_on_the_cone_at_the_trial_pressure_along_the_trial_deviator() {
        let m = beads();
        let elastic = LinearElastic::new(1550.0, 1e6, 0.3);
        let start = [-480.0, -530.0, -490.0, 260.0];
        let (mut stress, mut trial) = (start, start);
        let mut state = [0.1, 2.0];
        let k = Kinematics { jacobian: 0.97, ..kinematics([2.0, 30.0, -5.0, -1.0, 0.5], 2e-5) };
        m.update_stress(&mut stress, &mut state, &k);
        elastic.update_stress(&mut trial, &mut [], &k);
        let (p_trial, tau_trial) = pressure_and_shear(&trial);
        let (p, tau) = pressure_and_shear(&stress);
        assert!(tau_trial > m.friction * p_trial, "the trial must be outside the cone");
        assert!((p - p_trial).abs() < 1e-12 * p);
        assert!((tau - m.friction * p).abs() < 1e-12 * tau, "τ/p = {} vs μ = {}", tau / p, m.friction);
        let scale = tau / tau_trial;
        for c in 0..3 {
            assert!(((stress[c] + p) - scale * (trial[c] + p)).abs() < 1e-9, "component {c}");
        }
        assert!((stress[3] - scale * trial[3]).abs() < 1e-12);
        let g_modulus = 1e6 / 2.6;
        assert!((state[0] - 0.1 - (tau_trial - tau) / g_modulus).abs() < 1e-15);
        let w = |s: &Stress| crate::material::complementary_energy(s, 1e6, 0.3);
        let expected = 0.97 * (power(&start, &k) - (w(&stress) - w(&start)));
        let dissipated = state[1] - 2.0;
        assert!(dissipated > 0.0 && (dissipated - expected).abs() < 1e-12 * dissipated, "{dissipated} vs {expected}");
    }

    #[test]
    fn steady_simple_shear_flows_at_the_friction_coefficient_whatever_the_rate() {
        // Homogeneous simple shear at constant pressure: the shear stress rises elastically to
        // μ p and stays there at any rate (rate independence), dissipating τ γ̇ per unit volume.
        let m = beads();
        let p = 500.0;
        for (rate, dt) in [(0.5, 1e-5), (50.0, 1e-6)] {
            let mut point = MaterialPoint::new(&m, [-p, -p, -p, 0.0]);
            let steps = 200_000;
            point.drive(&m, [0.0, rate, 0.0, 0.0, 0.0], dt, steps);
            let (pressure, tau) = pressure_and_shear(&point.stress);
            assert!((pressure - p).abs() < 1e-9 * p, "{pressure}");
            assert!((tau - m.friction * p).abs() < 1e-9 * tau, "rate {rate}: μ = {} vs {}", tau / p, m.friction);
            // Past the elastic rise (γ = μ p / G ≈ 7e-4), the work is τ (γ − γ_elastic).
            let strain = rate * dt * steps as f64;
            let plastic = strain - tau / (1e6 / 2.6);
            let work = point.state[1];
            assert!((work - tau * plastic).abs() < 0.01 * tau * plastic, "rate {rate}: {work} vs {}", tau * plastic);
            assert!((point.state[0] - plastic).abs() < 0.01 * plastic, "{} vs {plastic}", point.state[0]);
        }
    }

    #[test]
    fn tension_and_zero_pressure_leave_the_material_stress_free() {
        let m = beads();
        for start in [[1.0, 1.0, 1.0, 0.3], [0.0, 0.0, 0.0, 25.0]] {
            let mut stress = start;
            let mut state = [0.0; 2];
            let k = Kinematics { jacobian: 1.25, ..kinematics([0.0; 5], 1e-3) };
            m.update_stress(&mut stress, &mut state, &k);
            assert_eq!(stress, [0.0; 4]);
            assert_eq!(state[0], 0.0);
            let released = 1.25 * crate::material::complementary_energy(&start, 1e6, 0.3);
            assert!(released > 0.0 && (state[1] - released).abs() < 1e-15 * released, "{} vs {released}", state[1]);
        }
    }

    #[test]
    fn wave_speed_is_the_elastic_p_wave_speed() {
        let c = (1e6f64 * 0.7 / (1.3 * 0.4 * 1550.0)).sqrt();
        assert!((beads().wave_speed() - c).abs() < 1e-12 * c);
    }

    #[test]
    fn dilute_material_reloads_no_faster_than_the_time_step_allows() {
        let plain = beads();
        let c0 = plain.wave_speed();
        let mut limited = beads();
        limited.limit_wave_speed(2.0 * c0); // stable up to J = 4
        assert!((limited.stable_jacobian - 4.0).abs() < 1e-12, "{}", limited.stable_jacobian);
        let mut faster = beads();
        faster.limit_wave_speed(3.0 * c0); // J_s = (c_max/c0)² = 9
        assert!((faster.stable_jacobian - 9.0).abs() < 1e-12, "{}", faster.stable_jacobian);
        let mut slow = beads();
        slow.limit_wave_speed(0.5 * c0);
        assert_eq!(slow.stable_jacobian, 1.0);
        // A compressive, sheared increment from rest, elastic (inside the cone).
        let l = [-2.0, 0.3, 0.1, -1.0, -1.0];
        for (jacobian, s) in [(0.98, 1.0), (4.0, 1.0), (10.0, 0.4), (100.0, 0.04)] {
            let k = Kinematics { jacobian, ..kinematics(l, 1e-4) };
            let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
            limited.update_stress(&mut a, &mut [0.0; 2], &k);
            plain.update_stress(&mut b, &mut [0.0; 2], &k);
            let (p, tau) = pressure_and_shear(&b);
            assert!(p > 0.0 && tau < plain.friction * p, "the increment must be elastic");
            for c in 0..4 {
                assert!((a[c] - s * b[c]).abs() <= 1e-12 * b[c].abs(), "J = {jacobian}, component {c}: {} vs {}", a[c], s * b[c]);
            }
        }
        // Plastic shear strain of a return at J > J_s is that of the softer moduli.
        let k = Kinematics { jacobian: 10.0, ..kinematics([0.0, 40.0, 0.0, 0.0, 0.0], 1e-4) };
        let (mut stress, mut state) = ([-100.0, -100.0, -100.0, 50.0], [0.0; 2]);
        limited.update_stress(&mut stress, &mut state, &k);
        // The trial of the softer moduli: linear elasticity with E × 0.4 (λ and G scale with E).
        let mut trial = [-100.0, -100.0, -100.0, 50.0];
        LinearElastic::new(1550.0, 0.4e6, 0.3).update_stress(&mut trial, &mut [], &k);
        let (p_trial, tau_trial) = pressure_and_shear(&trial);
        assert!(tau_trial > limited.friction * p_trial, "the step must return");
        let expected = (tau_trial - limited.friction * p_trial) / (0.4 * 1e6 / 2.6);
        assert!((state[0] - expected).abs() < 1e-9 * expected, "{} vs {expected}", state[0]);
    }

    /// Bulk modulus of `beads()`, Pa.
    const BULK: f64 = 1e6 / (3.0 * (1.0 - 2.0 * 0.3));

    /// Compression by `compaction` (−tr Δε) over one step, at end-of-step J `jacobian`: radial
    /// and hoop rates equal, the axial one twice as large (every component in the trace).
    fn compress(compaction: f64, jacobian: f64) -> Kinematics {
        let rate = -compaction / 4.0 / 1e-4; // tr Δε = (1 + 2 + 1) × rate × dt
        Kinematics { jacobian, ..kinematics([rate, 0.0, 0.0, 2.0 * rate, rate], 1e-4) }
    }

    #[test]
    fn looser_than_the_critical_packing_the_material_carries_no_stress() {
        let jc = 0.62 / 0.55;
        let m = beads().with_disconnection(Some(jc));
        // Compressed and sheared, but at J above J_c: stress-free, its elastic energy dissipated.
        let start = [-300.0, -280.0, -290.0, 40.0];
        for jacobian in [jc * 1.0001, 1.3, 4.0] {
            let (mut stress, mut state) = (start, [0.0; 2]);
            let k = compress(1e-3, jacobian);
            m.update_stress(&mut stress, &mut state, &k);
            assert_eq!(stress, [0.0; 4], "J = {jacobian}");
            let released = jacobian * (power(&start, &k) + crate::material::complementary_energy(&start, 1e6, 0.3));
            assert!((state[1] - released).abs() < 1e-12 * released.abs(), "{} vs {released}", state[1]);
        }
        // At J_c itself it is connected: a shearing step is the plain model's.
        let shear = Kinematics { jacobian: jc, ..kinematics([0.0, 2.0, 0.0, 0.0, 0.0], 1e-4) };
        let (mut a, mut b) = (start, start);
        m.update_stress(&mut a, &mut [0.0; 2], &shear);
        beads().update_stress(&mut b, &mut [0.0; 2], &shear);
        assert_eq!(a, b);
        assert!(pressure_and_shear(&a).0 > 280.0);
    }

    #[test]
    fn recompaction_stores_only_the_compaction_beyond_the_critical_packing() {
        // From J_n = 1.2 (stress-free) to J = 1.1 across J_c = 1.127 in one step: only
        // ln(J_c/J) of the compaction is elastic; the plain model stores all of ln(J_n/J).
        let jc = 0.62 / 0.55;
        let (j_start, j_end) = (1.2f64, 1.1f64);
        let compaction = (j_start / j_end).ln();
        let k = compress(compaction, j_end);
        let mut stress = [0.0; 4];
        beads().with_disconnection(Some(jc)).update_stress(&mut stress, &mut [0.0; 2], &k);
        let (p, _) = pressure_and_shear(&stress);
        let expected = BULK * (jc / j_end).ln();
        assert!((p - expected).abs() < 1e-9 * expected, "{p} vs {expected}");
        let mut plain = [0.0; 4];
        beads().update_stress(&mut plain, &mut [0.0; 2], &k);
        let (p_plain, _) = pressure_and_shear(&plain);
        assert!((p_plain - BULK * compaction).abs() < 1e-9 * p_plain, "{p_plain}");
        // A step that starts at or below J_c, or extends, is the plain one, bit for bit.
        for k in [compress(0.01, 1.05), compress(-0.01, 1.05), compress((jc / 1.1).ln() - 1e-9, 1.1)] {
            let (mut a, mut b) = ([-100.0, -90.0, -95.0, 10.0], [-100.0, -90.0, -95.0, 10.0]);
            beads().with_disconnection(Some(jc)).update_stress(&mut a, &mut [0.0; 2], &k);
            beads().update_stress(&mut b, &mut [0.0; 2], &k);
            assert_eq!(a, b);
        }
    }

    /// Principal stresses (tension positive) at pressure p, τ = √J₂ and Lode parameter ξ:
    /// s_k = (2/√3) τ cos(α − 2πk/3), α = arccos(ξ)/3 (so that ξ = (3√3/2) J₃/τ³).
    fn principal(p: f64, tau: f64, xi: f64) -> Stress {
        let alpha = xi.acos() / 3.0;
        let s = |k: f64| 2.0 / 3f64.sqrt() * tau * (alpha - 2.0 * std::f64::consts::PI * k / 3.0).cos();
        [-p + s(0.0), -p + s(1.0), -p + s(2.0), 0.0]
    }

    #[test]
    fn the_mohr_coulomb_section_meets_the_principal_stress_criterion() {
        let mu = 27.4f64.to_radians().tan();
        // Reference states: shear g = 1, compression 2√3/(3 − μ), extension 2√3/(3 + μ).
        assert!((mohr_coulomb_section_radius(0.0, mu) - 1.0).abs() < 1e-15);
        assert!((mohr_coulomb_section_radius(-1.0, mu) - 2.0 * 3f64.sqrt() / (3.0 - mu)).abs() < 1e-15);
        assert!((mohr_coulomb_section_radius(1.0, mu) - 2.0 * 3f64.sqrt() / (3.0 + mu)).abs() < 1e-15);
        // Round-off beyond ±1 is clamped.
        assert_eq!(mohr_coulomb_section_radius(-1.0 - 1e-12, mu), mohr_coulomb_section_radius(-1.0, mu));
        assert_eq!(mohr_coulomb_section_radius(1.0 + 1e-12, mu), mohr_coulomb_section_radius(1.0, mu));
        // On the section, (σ_max − σ_min) + (σ_max + σ_min) sin φ = 0 with sin φ = μ, at every ξ,
        // and the Lode parameter of the principal state is the one it was built with.
        for xi in [-1.0, -0.9, -0.5, -0.2, 0.0, 0.3, 0.7, 1.0] {
            let p = 800.0;
            let tau = mu * p * mohr_coulomb_section_radius(xi, mu);
            let sigma = principal(p, tau, xi);
            let (max, min) = (sigma[..3].iter().cloned().fold(f64::MIN, f64::max), sigma[..3].iter().cloned().fold(f64::MAX, f64::min));
            assert!(((max - min) + (max + min) * mu).abs() < 1e-12 * p, "ξ = {xi}");
            let (pp, tt) = pressure_and_shear(&sigma);
            assert!((pp - p).abs() < 1e-12 * p && (tt - tau).abs() < 1e-12 * tau);
            assert!((lode_parameter(&sigma, pp, tt) - xi).abs() < 1e-12, "ξ = {xi}");
        }
        // The Lode parameter with an in-plane shear component: a compression along an axis
        // rotated in the 1–2 plane is still ξ = −1.
        let (c, s) = (0.6f64.cos(), 0.6f64.sin());
        let (a, b) = (-3.0, -1.0); // principal in-plane values, hoop −1
        let rotated = [c * c * a + s * s * b, s * s * a + c * c * b, -1.0, c * s * (a - b)];
        let (p, tau) = pressure_and_shear(&rotated);
        assert!((lode_parameter(&rotated, p, tau) + 1.0).abs() < 1e-12);
    }

    #[test]
    fn with_the_mohr_coulomb_section_compression_returns_to_the_mohr_coulomb_strength() {
        let plain = beads();
        let hexagon = beads().with_mohr_coulomb_section(true);
        let mu = plain.friction;
        // Trials beyond both surfaces: q/p of the return is 6 sin φ/(3 − sin φ) in triaxial
        // compression and 6 sin φ/(3 + sin φ) in extension with the section, √3 μ without.
        let zero = kinematics([0.0; 5], 1e-6);
        for (xi, ratio) in [(-1.0, 6.0 * mu / (3.0 - mu)), (1.0, 6.0 * mu / (3.0 + mu)), (0.0, 3f64.sqrt() * mu)] {
            let start = principal(1000.0, 2.0 * mu * 1000.0, xi);
            let (mut a, mut b) = (start, start);
            let (mut state_a, mut state_b) = ([0.0; 2], [0.0; 2]);
            hexagon.update_stress(&mut a, &mut state_a, &zero);
            plain.update_stress(&mut b, &mut state_b, &zero);
            let (p, tau) = pressure_and_shear(&a);
            assert!((p - 1000.0).abs() < 1e-9, "the return keeps p");
            assert!((3f64.sqrt() * tau / p - ratio).abs() < 1e-12, "ξ = {xi}: q/p = {}", 3f64.sqrt() * tau / p);
            assert!((lode_parameter(&a, p, tau) - xi).abs() < 1e-9, "the return keeps the Lode angle");
            let (pb, taub) = pressure_and_shear(&b);
            assert!((taub / pb - mu).abs() < 1e-12);
            // The plastic shear strain is what the deviator gave up: (τ_tr − τ)/G.
            assert!((state_a[0] - (2.0 * mu * 1000.0 - tau) / (1e6 / 2.6)).abs() < 1e-12, "ξ = {xi}");
        }
        // Inside the hexagon but outside the circle (compression at 1.2 μ p): elastic with the
        // section, a return without.
        let start = principal(1000.0, 1.2 * mu * 1000.0, -1.0);
        let (mut a, mut b) = (start, start);
        hexagon.update_stress(&mut a, &mut [0.0; 2], &zero);
        plain.update_stress(&mut b, &mut [0.0; 2], &zero);
        assert_eq!(a, start);
        assert!((pressure_and_shear(&b).1 - mu * 1000.0).abs() < 1e-9);
        // An isotropic state has no Lode angle (τ = 0): it stays elastic, with no NaN.
        let mut isotropic = [-500.0, -500.0, -500.0, 0.0];
        let mut state = [0.0; 2];
        hexagon.update_stress(&mut isotropic, &mut state, &zero);
        assert_eq!(isotropic, [-500.0, -500.0, -500.0, 0.0]);
        assert_eq!(state, [0.0; 2]);
        // Simple shear from an isotropic state is pure shear (ξ = 0): the same flow stress.
        let mut point = MaterialPoint::new(&hexagon, [-500.0, -500.0, -500.0, 0.0]);
        point.drive(&hexagon, [0.0, 0.5, 0.0, 0.0, 0.0], 1e-5, 20_000);
        let (p, tau) = pressure_and_shear(&point.stress);
        assert!((tau - mu * p).abs() < 1e-9 * tau, "τ/p = {}", tau / p);
    }

    /// Jop et al.'s glass-bead μ(I) (μ_s = tan 20.9°, μ₂ = tan 32.76°, I₀ = 0.279) with the
    /// Lajeunesse et al. beads' d = 1.15 mm and ρ_s = 2500 kg/m³.
    fn flowing_beads(section: bool) -> DruckerPrager {
        DruckerPrager::new(1550.0, 1e6, 0.3, 20.9f64.to_radians().tan())
            .with_mohr_coulomb_section(section)
            .with_inertial_friction(Some(InertialFriction {
                dynamic_friction: 32.76f64.to_radians().tan(),
                inertial_number_scale: 0.279,
                grain_diameter: 1.15e-3,
                grain_density: 2500.0,
            }))
    }

    #[test]
    fn steady_simple_shear_flows_at_the_friction_of_its_inertial_number() {
        // Simple shear at constant p: τ/p settles on μ(I), I = γ̇ d/√(p/ρ_s), and the state
        // holds that I; a faster shear is stronger (the constant cone is the same at any rate).
        let m = flowing_beads(false);
        let law = m.inertial.unwrap();
        let p = 500.0;
        let mut ratios = vec![];
        for (rate, dt) in [(5.0, 1e-6), (50.0, 1e-7), (400.0, 2e-8)] {
            let mut point = MaterialPoint::new(&m, [-p, -p, -p, 0.0]);
            point.drive(&m, [0.0, rate, 0.0, 0.0, 0.0], dt, 100_000);
            let (pressure, tau) = pressure_and_shear(&point.stress);
            let i = rate * 1.15e-3 / (p / 2500.0f64).sqrt();
            let mu = m.friction + (law.dynamic_friction - m.friction) * i / (0.279 + i);
            assert!((pressure - p).abs() < 1e-9 * p, "{pressure}");
            assert!((tau / pressure - mu).abs() < 1e-6 * mu, "rate {rate}: τ/p = {} vs μ(I) = {mu}", tau / pressure);
            assert!((point.state[2] - i).abs() < 1e-6 * i, "I = {} vs {i}", point.state[2]);
            ratios.push(tau / pressure);
        }
        assert!(ratios[0] < ratios[1] && ratios[1] < ratios[2], "{ratios:?}");
        assert!(ratios[0] > m.friction && ratios[2] < law.dynamic_friction);
    }

    #[test]
    fn a_mu_of_i_step_is_the_constant_cone_step_at_the_friction_of_its_inertial_number() {
        // Any step, circle or hexagon: the same as the rate-independent model at μ = μ(I) of the
        // start-of-step stress, and the same plastic strain and work.
        let mut rng = crate::material::testing::Lcg(7);
        for section in [false, true] {
            let m = flowing_beads(section);
            let law = m.inertial.unwrap();
            for _ in 0..200 {
                let start = crate::material::testing::random_stress(&mut rng, -900.0, -50.0, 300.0);
                let l = [rng.uniform(-40.0, 40.0), rng.uniform(-40.0, 40.0), rng.uniform(-40.0, 40.0),
                         rng.uniform(-40.0, 40.0), rng.uniform(-20.0, 20.0)];
                let k = Kinematics { jacobian: rng.uniform(0.9, 1.1), ..kinematics(l, 1e-4) };
                let d = rate_of_deformation(&l).0;
                let i = inertial_number(&start, &d, 1.15e-3, 2500.0);
                let mu = inertial_friction(m.friction, law.dynamic_friction, 0.279, i);
                let constant = DruckerPrager::new(1550.0, 1e6, 0.3, mu).with_mohr_coulomb_section(section);
                let (mut a, mut b) = (start, start);
                let (mut state_a, mut state_b) = ([0.5, 3.0, 0.0], [0.5, 3.0]);
                m.update_stress(&mut a, &mut state_a, &k);
                constant.update_stress(&mut b, &mut state_b, &k);
                assert_eq!(a, b, "section {section}, I = {i}");
                assert_eq!(state_a[..2], state_b);
                assert_eq!(state_a[2], i);
            }
        }
        // No shear: μ_s, I = 0. No pressure at the start while shearing: μ₂, I stored capped.
        let m = flowing_beads(true);
        let (mut stress, mut state) = ([-200.0, -200.0, -200.0, 0.0], [0.0; 3]);
        m.update_stress(&mut stress, &mut state, &kinematics([-1.0, 0.0, 0.0, -1.0, -1.0], 1e-4));
        assert_eq!(state[2], 0.0);
        assert_eq!(m.friction_of_step(&[-200.0; 4], &[-1.0, -1.0, -1.0, 0.0]).0, m.friction);
        let (mut stress, mut state) = ([0.0; 4], [0.0; 3]);
        m.update_stress(&mut stress, &mut state, &kinematics([-30.0, 20.0, 0.0, -30.0, -30.0], 1e-4));
        assert_eq!(state[2], INERTIAL_NUMBER_CAP);
        assert_eq!(m.friction_of_step(&[0.0; 4], &[-30.0, -30.0, -30.0, 10.0]).0, m.inertial.unwrap().dynamic_friction);
    }

    #[test]
    fn registry_builds_it_by_name_and_names_bad_keys() {
        use serde_json::json;
        let table = json!({"density": 1550.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3, "friction": 0.5184});
        let p = Parameters::new("beads", table.as_object().unwrap());
        let m = build(&p).unwrap();
        assert_eq!(m.model(), "drucker_prager");
        assert_eq!(m.state_names(), &STATE_NAMES);
        for (key, value, message) in [
            ("friction", 0.0, "must be > 0 (got 0)"),
            ("density", -1.0, "must be > 0 kg/m³ (got -1)"),
            ("poisson_ratio", 0.5, "must be in (-1, 0.5) (got 0.5)"),
            ("poisson_ratio", -1.0, "must be in (-1, 0.5) (got -1)"),
        ] {
            let mut bad = table.clone();
            bad[key] = json!(value);
            let p = Parameters::new("beads", bad.as_object().unwrap());
            assert_eq!(build(&p).err().unwrap(), format!("materials.beads.{key}: {message}"));
        }
        // The disconnected state: J_c = ρ0/(φ_c ρ_s), and its keys checked.
        let mut with = table.clone();
        with["critical_packing_fraction"] = json!(0.55);
        with["grain_density"] = json!(2500.0);
        let m = DruckerPrager::from_parameters(&Parameters::new("beads", with.as_object().unwrap())).unwrap();
        assert!((m.critical_jacobian.unwrap() - 0.62 / 0.55).abs() < 1e-12);
        assert_eq!(DruckerPrager::from_parameters(&p).unwrap().critical_jacobian, None);
        // The Mohr–Coulomb section: off when absent, on by key; a non-boolean or μ ≥ 1 named.
        assert!(!DruckerPrager::from_parameters(&p).unwrap().mohr_coulomb_section);
        let mut hexagon = table.clone();
        hexagon["mohr_coulomb_section"] = json!(true);
        assert!(DruckerPrager::from_parameters(&Parameters::new("beads", hexagon.as_object().unwrap())).unwrap().mohr_coulomb_section);
        hexagon["friction"] = json!(1.0);
        assert_eq!(build(&Parameters::new("beads", hexagon.as_object().unwrap())).err().unwrap(),
                   "materials.beads.friction: must be < 1 with mohr_coulomb_section (it is sin φ; got 1)");
        hexagon["friction"] = json!(0.9);
        assert!(build(&Parameters::new("beads", hexagon.as_object().unwrap())).is_ok());
        // μ(I): off when absent; with it three state variables, its keys checked.
        assert_eq!(DruckerPrager::from_parameters(&p).unwrap().inertial, None);
        let mut flowing = table.clone();
        flowing["friction"] = json!(0.3819);
        flowing["inertial_friction"] = json!(0.6435);
        flowing["grain_diameter"] = json!(1.15e-3);
        flowing["grain_density"] = json!(2500.0);
        let m = build(&Parameters::new("beads", flowing.as_object().unwrap())).unwrap();
        assert_eq!(m.state_names(), &STATE_NAMES_INERTIAL);
        let law = DruckerPrager::from_parameters(&Parameters::new("beads", flowing.as_object().unwrap())).unwrap().inertial;
        assert_eq!(law, Some(InertialFriction { dynamic_friction: 0.6435, inertial_number_scale: 0.279,
                                                grain_diameter: 1.15e-3, grain_density: 2500.0 }));
        flowing["inertial_number_scale"] = json!(0.5);
        flowing["inertial_friction"] = json!(0.3819);
        let law = DruckerPrager::from_parameters(&Parameters::new("beads", flowing.as_object().unwrap())).unwrap().inertial;
        assert_eq!(law.unwrap().inertial_number_scale, 0.5);
        assert_eq!(law.unwrap().dynamic_friction, 0.3819);
        flowing["inertial_friction"] = json!(1.5);
        assert!(build(&Parameters::new("beads", flowing.as_object().unwrap())).is_ok());
        for (key, value, message) in [
            ("inertial_friction", json!(0.38), "must be finite and >= friction = 0.3819 (got 0.38)"),
            ("inertial_number_scale", json!(0.0), "must be > 0 (got 0)"),
            ("grain_diameter", json!(null), "is required with inertial_friction"),
            ("grain_diameter", json!(0.0), "must be > 0 m (got 0)"),
            ("grain_density", json!(null), "is required with inertial_friction"),
            ("grain_density", json!(-1.0), "must be > 0 kg/m³ (got -1)"),
        ] {
            let mut bad = flowing.clone();
            bad[key] = value;
            assert_eq!(build(&Parameters::new("beads", bad.as_object().unwrap())).err().unwrap(),
                       format!("materials.beads.{key}: {message}"));
        }
        flowing["mohr_coulomb_section"] = json!(true);
        assert_eq!(build(&Parameters::new("beads", flowing.as_object().unwrap())).err().unwrap(),
                   "materials.beads.inertial_friction: must be in [friction, 1) = [0.3819, 1) with mohr_coulomb_section (it is sin φ₂; got 1.5)");
        flowing["inertial_friction"] = json!(0.999);
        assert!(build(&Parameters::new("beads", flowing.as_object().unwrap())).is_ok());
        flowing["inertial_friction"] = json!(1.0);
        assert!(build(&Parameters::new("beads", flowing.as_object().unwrap())).is_err());
        flowing["inertial_friction"] = json!(0.3);
        assert!(build(&Parameters::new("beads", flowing.as_object().unwrap())).is_err());
        hexagon["mohr_coulomb_section"] = json!(1);
        assert_eq!(build(&Parameters::new("beads", hexagon.as_object().unwrap())).err().unwrap(),
                   "materials.beads.mohr_coulomb_section: must be true or false (got 1)");
        for (key, value, message) in [
            ("grain_density", json!(null), "is required with critical_packing_fraction".to_string()),
            ("grain_density", json!(1550.0), "must be > density = 1550 kg/m³ (packing as placed density/grain_density < 1; got 1550)".to_string()),
            ("critical_packing_fraction", json!(0.63), "must be in (0, density/grain_density] = (0, 0.62] (got 0.63)".to_string()),
            ("critical_packing_fraction", json!(0.0), "must be in (0, density/grain_density] = (0, 0.62] (got 0)".to_string()),
        ] {
            let mut bad = with.clone();
            bad[key] = value;
            let p = Parameters::new("beads", bad.as_object().unwrap());
            assert_eq!(build(&p).err().unwrap(), format!("materials.beads.{key}: {message}"));
        }
    }
}
