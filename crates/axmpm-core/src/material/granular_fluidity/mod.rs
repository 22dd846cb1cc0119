//! The nonlocal granular fluidity (NGF) model of dense granular flow (Kamrin & Koval 2012,
//! *Nonlocal constitutive relation for steady granular flow*, PRL 108:178301; Henann & Kamrin
//! 2013, *A predictive, size-dependent continuum model for dense granular flows*, PNAS
//! 110:6730): an elasto-viscoplastic solid whose plastic shear rate is set by a *fluidity* g
//! that obeys a screened diffusion equation with a length proportional to the grain size d.
//! The grain size enters the flow rule itself: a layer a few grains thick flows less easily
//! than the local μ(I) law says (h_stop), and material next to a flowing zone creeps below
//! the static friction. docs/physics.md §6b.
//!
//! # Law
//!
//! With p = −tr σ / 3, the deviator s = σ + p I and τ = √(½ s:s) (3D, the hoop or out-of-plane
//! component included), μ = τ / p:
//!
//! ```text
//! plastic rate of deformation   Dᵖ = g s / (2 p)          (so γ̇ᵖ = √(2 Dᵖ:Dᵖ) = g μ)
//! local fluidity               g_loc = √(p / (ρ_s d²)) (μ − μ_s) / (b μ)   for μ > μ_s, else 0
//! cooperativity length          ξ² = A² d² / |μ − μ_s|
//! steady fluidity equation      g = g_loc + ξ² ∇²g
//! ```
//!
//! In homogeneous flow (∇²g = 0) this is the linearised local rheology μ = μ_s + b I,
//! I = γ̇ d / √(p/ρ_s). The glass-bead values of Henann & Kamrin 2013 (μ_s = 0.3819 from Jop
//! et al. 2006, b = 0.9377, A = 0.48) are the scenario front end's documented defaults
//! (docs/physics.md §6b gives where each comes from and its confidence).
//!
//! # Update (one step)
//!
//! 1. Elastic predictor: the linear-elastic Jaumann step of [`LinearElastic`], operation for
//!    operation.
//! 2. Fluidity: one Jacobi sweep of the steady equation per step (a pseudo-time relaxation),
//!    from μ and p of the start-of-step stress and the Laplacian of the cell-averaged fluidity
//!    at the particle's cell, ∇²g = S − D g ([`laplacian`], read in [`Kinematics::cell_field`]:
//!    S the neighbour cells' weighted sum, D the cell's own weight, both over h²), the diagonal
//!    taken at the particle's new g and the local term implicit:
//!    g ← (|Δμ| (g + g_loc) + A²d² S) / (2 |Δμ| + A²d² D),  Δμ = μ − μ_s,
//!    i.e. (g + g_loc + ξ² S)/(2 + ξ² D), written so that ξ → ∞ at μ = μ_s needs no division.
//!    Its fixed point is the steady equation |Δμ| (g − g_loc) = A²d² ∇²g; every term is ≥ 0,
//!    so g stays ≥ 0 (the steady solution's maximum principle), and no ratio of ξ to the cell
//!    size limits it. The equation relaxes in a few steps where ξ is a few cells, the flow in
//!    thousands: the fluidity is quasi-steady, as in the steady model.
//! 3. Viscoplastic return of the deviator, implicit in s at fixed g and p:
//!    s = s_tr / (1 + G Δt g / p_tr), p = p_tr. Material in tension (p_tr ≤ 0) carries no
//!    stress and has no local fluidity (separated grains).
//!
//! # State variables
//!
//! - `fluidity`: g, 1/s (averaged per cell for the Laplacian).
//! - `plastic_shear_strain`: Σ Δγᵖ, Δγᵖ = Δt g τ / p of each return.
//! - `plastic_work`: per unit reference volume, J/m³, in every step that flows or separates:
//!   Σ J (σ_n : Δε − ΔW_e), the stress power of the start-of-step stress less the change of the
//!   stored (complementary) elastic energy W_e, so that the model leaves no residual of its own
//!   in the energy budget (the frictional dissipation; separation releases the stored energy).

pub mod laplacian;

use super::{
    pressure_and_shear, rate_of_deformation, stress_power, CellField, Kinematics, LinearElastic, Material, Parameters,
};
use crate::particles::Stress;

const STATE_NAMES: [&str; 3] = ["fluidity", "plastic_shear_strain", "plastic_work"];

/// Index of `fluidity` in the state (averaged per cell for the Laplacian).
pub const FLUIDITY_SLOT: usize = 0;
const SHEAR_STRAIN_SLOT: usize = 1;
const WORK_SLOT: usize = 2;

/// The NGF model (module doc).
#[derive(Clone, Debug)]
pub struct GranularFluidity {
    /// The elastic part (the predictor is its step).
    pub elastic: LinearElastic,
    /// μ_s, static friction coefficient (τ/p).
    pub static_friction: f64,
    /// b, the slope of the local law μ = μ_s + b I.
    pub friction_rate: f64,
    /// A, the nonlocal amplitude (0: the local law).
    pub nonlocal_amplitude: f64,
    /// d, m.
    pub grain_diameter: f64,
    /// ρ_s, kg/m³.
    pub grain_density: f64,
    /// G, Pa.
    shear_modulus: f64,
}

impl GranularFluidity {
    pub fn new(density: f64, youngs_modulus: f64, poisson_ratio: f64, static_friction: f64, friction_rate: f64,
               nonlocal_amplitude: f64, grain_diameter: f64, grain_density: f64) -> Self {
        Self {
            elastic: LinearElastic::new(density, youngs_modulus, poisson_ratio),
            static_friction,
            friction_rate,
            nonlocal_amplitude,
            grain_diameter,
            grain_density,
            shear_modulus: youngs_modulus / (2.0 * (1.0 + poisson_ratio)),
        }
    }

    /// From a `granular_fluidity` table; every key is required (the scenario front end fills
    /// the documented defaults). Errors name `materials.NAME.KEY` and the allowed range.
    pub fn from_parameters(p: &Parameters) -> Result<Self, String> {
        let density = p.positive("density", " kg/m³")?;
        let youngs_modulus = p.positive("youngs_modulus", " Pa")?;
        let poisson_ratio = p.poisson_ratio()?;
        let static_friction = p.positive("static_friction", "")?;
        let friction_rate = p.positive("friction_rate", "")?;
        let amplitude = p.f64("nonlocal_amplitude")?;
        if !(amplitude >= 0.0 && amplitude.is_finite()) {
            return Err(p.error("nonlocal_amplitude", format!("must be >= 0 (got {amplitude})")));
        }
        let grain_diameter = p.positive("grain_diameter", " m")?;
        let grain_density = p.positive("grain_density", " kg/m³")?;
        Ok(Self::new(density, youngs_modulus, poisson_ratio, static_friction, friction_rate, amplitude, grain_diameter,
                     grain_density))
    }

    /// g_loc at pressure `p` > 0 and stress ratio `mu` (0 at or below μ_s).
    #[inline(always)]
    pub fn local_fluidity(&self, p: f64, mu: f64) -> f64 {
        if mu > self.static_friction {
            (p / self.grain_density).sqrt() / self.grain_diameter * (mu - self.static_friction) / (self.friction_rate * mu)
        } else {
            0.0
        }
    }

    /// One relaxation sweep of the steady fluidity equation (module doc, step 2) from fluidity
    /// `g`, with the cell's Laplacian ∇²g = `neighbour_sum` − `diagonal` g, at the
    /// start-of-step stress `stress`.
    #[inline(always)]
    pub fn relax_fluidity(&self, g: f64, neighbour_sum: f64, diagonal: f64, stress: &Stress) -> f64 {
        let (p, tau) = pressure_and_shear(stress);
        if !(p > 0.0) {
            // Separated grains: no local fluidity, no cooperativity; g decays.
            return 0.5 * g;
        }
        let mu = tau / p;
        let excess = (mu - self.static_friction).abs();
        let ad2 = self.nonlocal_amplitude * self.nonlocal_amplitude * self.grain_diameter * self.grain_diameter;
        let g_loc = self.local_fluidity(p, mu);
        let denominator = 2.0 * excess + ad2 * diagonal;
        if denominator > 0.0 {
            (excess * (g + g_loc) + ad2 * neighbour_sum) / denominator
        } else {
            // μ = μ_s exactly in a cell without neighbours: nothing drives g.
            g
        }
    }
}

/// The registry's builder ([`super::MODELS`]).
pub fn build(p: &Parameters) -> Result<Box<dyn Material>, String> {
    Ok(Box::new(GranularFluidity::from_parameters(p)?))
}

impl Material for GranularFluidity {
    fn model(&self) -> &'static str {
        "granular_fluidity"
    }
    fn density(&self) -> f64 {
        self.elastic.density
    }
    fn wave_speed(&self) -> f64 {
        self.elastic.wave_speed()
    }
    fn state_names(&self) -> &'static [&'static str] {
        &STATE_NAMES
    }
    fn cell_field(&self) -> Option<CellField> {
        Some(CellField::Laplacian { slot: FLUIDITY_SLOT })
    }
    fn elastic_energy_density(&self, stress: &Stress) -> f64 {
        self.elastic.elastic_energy_density(stress)
    }

    #[inline(always)]
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], k: &Kinematics) {
        let [neighbour_sum, diagonal] = k.cell_field;
        let g = self.relax_fluidity(state[FLUIDITY_SLOT], neighbour_sum, diagonal, stress);
        state[FLUIDITY_SLOT] = g;
        let start = *stress;
        // Elastic predictor: the linear-elastic Jaumann step itself.
        self.elastic.update_stress(stress, &mut [], k);
        let p = -(stress[0] + stress[1] + stress[2]) / 3.0;
        if p > 0.0 && !(g > 0.0) {
            return; // elastic
        }
        if p > 0.0 {
            // s = s_tr / (1 + G Δt g / p): Δs = −2G Δt Dᵖ with Dᵖ = g s / (2p) at the end of the step.
            let scale = 1.0 / (1.0 + self.shear_modulus * k.dt * g / p);
            for c in 0..3 {
                stress[c] = -p + scale * (stress[c] + p);
            }
            stress[3] *= scale;
            // Δγᵖ = Δt g μ = Δt g τ / p.
            let (_, tau) = pressure_and_shear(stress);
            state[SHEAR_STRAIN_SLOT] += k.dt * g * tau / p;
        } else {
            // Tension: the grains separate, stress-free.
            *stress = [0.0; 4];
        }
        // Dissipated: the stress power of the start-of-step stress (the stress the step's
        // internal forces came from) less the change of stored elastic energy, so that the
        // model adds no residual of its own to the energy budget. (The end-point rule
        // τ Δγᵖ and the mid-point rule (τ_tr² − τ²)/(2G) are the two limits of this: G Δt g/p
        // ≫ 1, where the elastic strain of one step is larger than the material keeps, and ≪ 1.)
        let (d, _) = rate_of_deformation(&k.velocity_gradient);
        let power = stress_power(&start, &d, k.dt);
        let stored = self.elastic_energy_density(stress) - self.elastic_energy_density(&start);
        state[WORK_SLOT] += k.jacobian * (power - stored);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::testing::{kinematics, MaterialPoint};

    // Glass beads (Henann & Kamrin 2013): μ_s = 0.3819, b = 0.9377, A = 0.48, d = 1.15 mm.
    fn beads(amplitude: f64) -> GranularFluidity {
        GranularFluidity::new(1550.0, 1e6, 0.3, 0.3819, 0.9377, amplitude, 1.15e-3, 2500.0)
    }

    /// A stress with pressure p and τ = μ p in simple shear (σ12 = τ, normal stresses −p).
    fn sheared(p: f64, mu: f64) -> Stress {
        [-p, -p, -p, mu * p]
    }

    #[test]
    fn pressure_and_shear_of_simple_and_triaxial_stress() {
        let (p, tau) = pressure_and_shear(&[-100.0, -100.0, -100.0, 30.0]);
        assert_eq!((p, tau), (100.0, 30.0));
        // Triaxial: σ = diag(−1, −1, −4): p = 2, s = (1, 1, −2), ½ s:s = 3.
        let (p, tau) = pressure_and_shear(&[-1.0, -1.0, -4.0, 0.0]);
        assert!((p - 2.0).abs() < 1e-15 && (tau - 3f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn local_fluidity_is_the_linear_mu_of_i_law() {
        let m = beads(0.48);
        let (p, mu) = (500.0, 0.45);
        let g = m.local_fluidity(p, mu);
        // γ̇ = g μ, I = γ̇ d / √(p/ρ_s) must satisfy μ = μ_s + b I.
        let inertial_number = g * mu * m.grain_diameter / (p / m.grain_density).sqrt();
        assert!((m.static_friction + m.friction_rate * inertial_number - mu).abs() < 1e-14);
        assert_eq!(m.local_fluidity(p, 0.3819), 0.0);
        assert_eq!(m.local_fluidity(p, 0.2), 0.0);
    }

    #[test]
    fn relaxation_converges_to_the_steady_equation() {
        // With the neighbours fixed (S, D), the fixed point solves |Δμ| (g − g_loc) = A²d² (S − D g),
        // above and below μ_s, and at μ_s (pure diffusion: g = S/D, the neighbours' weighted mean).
        let m = beads(0.48);
        let ad2 = (0.48f64 * 1.15e-3).powi(2);
        let h2 = 1e-6;
        for (mu, sum, diagonal) in [(0.45, 900.0 / h2, 4.0 / h2), (0.45, 0.0, 5.0 / h2), (0.35, 120.0 / h2, 3.0 / h2),
                                    (0.3819, 40.0 / h2, 4.0 / h2), (0.6, 0.0, 0.0)] {
            let stress = sheared(500.0, mu);
            let excess = (mu - 0.3819f64).abs();
            let expected = (excess * m.local_fluidity(500.0, mu) + ad2 * sum) / (excess + ad2 * diagonal);
            let mut g = 0.0;
            for _ in 0..400 {
                g = m.relax_fluidity(g, sum, diagonal, &stress);
            }
            assert!((g - expected).abs() <= 1e-12 * expected.abs(), "μ = {mu}: {g} vs {expected}");
            let laplacian = sum - diagonal * g;
            assert!((excess * (g - m.local_fluidity(500.0, mu)) - ad2 * laplacian).abs() <= 1e-9 * excess.max(1e-3) * g.max(1.0));
        }
        // μ = μ_s next to a cell of g = 40 on one face: g → 40 (S/D = 40).
        let mut g = 0.0;
        for _ in 0..400 {
            g = m.relax_fluidity(g, 40.0 / h2, 1.0 / h2, &sheared(500.0, 0.3819));
        }
        assert!((g - 40.0).abs() < 1e-9, "{g}");
    }

    #[test]
    fn one_sweep_by_hand_and_the_fluidity_stays_non_negative() {
        let m = beads(0.48);
        let ad2 = (0.48f64 * 1.15e-3).powi(2);
        let (g0, sum, diagonal) = (30.0, 2.0e7, 6.0e6);
        let stress = sheared(500.0, 0.3319); // Δμ = −0.05: below μ_s, g_loc = 0
        let g = m.relax_fluidity(g0, sum, diagonal, &stress);
        let by_hand = (0.05 * g0 + ad2 * sum) / (2.0 * 0.05 + ad2 * diagonal);
        assert!((g - by_hand).abs() < 1e-12 * by_hand, "{g} vs {by_hand}");
        // A particle whose cell lies on a rough base with empty neighbours (S = 0, large D) and
        // a strongly negative Laplacian stays ≥ 0 (the explicit sweep went negative here).
        for diagonal in [1e3, 1e6, 1e9] {
            let g = m.relax_fluidity(5.0, 0.0, diagonal, &stress);
            assert!(g > 0.0 && g < 5.0, "{g}");
        }
        // Tension: no local fluidity, g halves; a cell without neighbours at μ = μ_s keeps g.
        assert_eq!(m.relax_fluidity(2.0, 1e9, 1e6, &[1.0, 1.0, 1.0, 0.0]), 1.0);
        assert_eq!(m.relax_fluidity(2.0, 0.0, 0.0, &sheared(500.0, 0.3819)), 2.0);
    }

    #[test]
    fn without_amplitude_the_update_is_local() {
        let m = beads(0.0);
        let s = sheared(500.0, 0.45);
        let g_loc = m.local_fluidity(500.0, 0.45);
        assert_eq!(m.relax_fluidity(2.0, 1e9, 1e7, &s), 0.5 * (2.0 + g_loc));
        let mut g = 0.0;
        for _ in 0..60 {
            g = m.relax_fluidity(g, 1e9, 1e7, &s);
        }
        assert!((g - g_loc).abs() < 1e-12 * g_loc);
    }

    #[test]
    fn steady_simple_shear_follows_the_local_law() {
        // Homogeneous simple shear at constant pressure (the normal stresses are kept by the
        // zero normal rates, the elastic predictor adds no pressure): the shear stress settles
        // where the plastic rate g μ equals the imposed rate, at μ = μ_s + b I.
        let m = beads(0.48);
        let (p, rate, dt) = (500.0, 20.0, 1e-6);
        let mut point = MaterialPoint::new(&m, sheared(p, 0.2));
        point.drive(&m, [0.0, rate, 0.0, 0.0, 0.0], dt, 400_000);
        let (pressure, tau) = pressure_and_shear(&point.stress);
        assert!((pressure - p).abs() < 1e-9 * p, "{pressure}");
        let inertial_number = rate * m.grain_diameter / (p / m.grain_density).sqrt();
        let expected = m.static_friction + m.friction_rate * inertial_number;
        assert!((tau / p - expected).abs() < 2e-3 * expected, "μ = {} vs {expected}", tau / p);
        // The dissipation rate is τ γ̇ (per reference volume, J = 1): W = τ γ̇ t at steady state,
        // within the elastic transient.
        let work = point.state[2];
        assert!(work > 0.0 && (work - tau * rate * 0.4).abs() < 0.02 * tau * rate * 0.4, "{work}");
    }

    #[test]
    fn below_static_friction_without_neighbours_the_material_is_elastic() {
        let m = beads(0.48);
        let elastic = LinearElastic::new(1550.0, 1e6, 0.3);
        let (mut s_fluid, mut s_elastic) = (sheared(500.0, 0.1), sheared(500.0, 0.1));
        let mut state = [0.0; 3];
        let k = kinematics([1e-3, 2e-3, 0.0, -1e-3, 0.0], 1e-3);
        for _ in 0..10 {
            m.update_stress(&mut s_fluid, &mut state, &k);
            elastic.update_stress(&mut s_elastic, &mut [], &k);
        }
        assert_eq!(s_fluid, s_elastic);
        assert_eq!(state, [0.0; 3]);
    }

    /// The start-of-step stress power σ_n : Δε of a step (tensor shear component).
    fn power(start: &Stress, k: &Kinematics) -> f64 {
        stress_power(start, &rate_of_deformation(&k.velocity_gradient).0, k.dt)
    }

    #[test]
    fn tension_leaves_the_material_stress_free_and_dissipates_its_elastic_energy() {
        let m = beads(0.48);
        let start = sheared(10.0, 0.3);
        let mut stress = start;
        let mut state = [5.0, 0.0, 0.0];
        let k = Kinematics { jacobian: 1.25, ..kinematics([1.0, 0.0, 0.0, 1.0, 1.0], 1e-3) };
        m.update_stress(&mut stress, &mut state, &k);
        assert_eq!(stress, [0.0; 4]);
        let w0 = crate::material::complementary_energy(&start, 1e6, 0.3);
        let released = 1.25 * (power(&start, &k) + w0);
        assert!(w0 > 0.0 && (state[2] - released).abs() < 1e-15 * w0, "{} vs {released}", state[2]);
        assert_eq!(state[1], 0.0);
    }

    #[test]
    fn a_flowing_step_dissipates_the_power_less_the_stored_energy_change() {
        // From a flowing state (g > 0), one step: Δw = J [σ_n : Δε − (W(σ) − W(σ_n))],
        // Δγᵖ = Δt g τ / p, and the return keeps p and the direction of the trial deviator.
        let m = beads(0.48);
        let elastic = LinearElastic::new(1550.0, 1e6, 0.3);
        let start = [-480.0, -530.0, -490.0, 260.0];
        let (mut stress, mut trial) = (start, start);
        let mut state = [800.0, 0.1, 2.0];
        let k = Kinematics { jacobian: 0.97, ..kinematics([2.0, 30.0, -5.0, -1.0, 0.5], 2e-5) };
        m.update_stress(&mut stress, &mut state, &k);
        elastic.update_stress(&mut trial, &mut [], &k);
        let g = state[0];
        assert!(g > 0.0 && g != 800.0);
        let w = |s: &Stress| crate::material::complementary_energy(s, 1e6, 0.3);
        let dissipated = state[2] - 2.0;
        let expected = 0.97 * (power(&start, &k) - (w(&stress) - w(&start)));
        assert!(dissipated > 0.0 && (dissipated - expected).abs() < 1e-12 * dissipated, "{dissipated} vs {expected}");
        let (p_trial, tau_trial) = pressure_and_shear(&trial);
        let (p, tau) = pressure_and_shear(&stress);
        assert!((p - p_trial).abs() < 1e-12 * p);
        let g_modulus = 1e6 / 2.6;
        let scale = 1.0 / (1.0 + g_modulus * 2e-5 * g / p);
        assert!(scale < 0.9 && (tau - scale * tau_trial).abs() < 1e-12 * tau);
        assert!((state[1] - 0.1 - 2e-5 * g * tau / p).abs() < 1e-15);
        for c in 0..3 {
            assert!(((stress[c] + p) - scale * (trial[c] + p)).abs() < 1e-9, "component {c}");
        }
        assert!((stress[3] - scale * trial[3]).abs() < 1e-12);
    }

    #[test]
    fn zero_pressure_is_separated_material() {
        // p = 0 exactly counts as separated, not as flowing: the fluidity halves (μ = τ/p is
        // undefined there), the deviator is released whether g is 0 or not, and no shear strain
        // is booked.
        let m = beads(0.48);
        assert_eq!(m.relax_fluidity(2.0, 1e9, 1e6, &[0.0; 4]), 1.0);
        let k = kinematics([0.0; 5], 1e-3);
        for g in [0.0, 40.0] {
            let mut stress = [0.0, 0.0, 0.0, 25.0];
            let mut state = [2.0 * g, 0.0, 0.0];
            m.update_stress(&mut stress, &mut state, &k);
            assert_eq!(state[0], g);
            assert_eq!(stress, [0.0; 4], "g = {g}");
            assert_eq!(state[1], 0.0, "g = {g}");
            assert!(state[2] > 0.0, "the released elastic energy is dissipated (g = {g})");
        }
    }

    #[test]
    fn wave_speed_is_the_elastic_p_wave_speed() {
        // c = √((λ + 2G)/ρ) = √(E (1 − ν) / ((1 + ν)(1 − 2ν) ρ)).
        let c = (1e6f64 * 0.7 / (1.3 * 0.4 * 1550.0)).sqrt();
        assert!((beads(0.48).wave_speed() - c).abs() < 1e-12 * c);
    }

    #[test]
    fn registry_builds_it_by_name_and_names_bad_keys() {
        use serde_json::json;
        let table = json!({"density": 1550.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3, "static_friction": 0.3819,
                           "friction_rate": 0.9377, "nonlocal_amplitude": 0.48, "grain_diameter": 1.15e-3,
                           "grain_density": 2500.0});
        let p = Parameters::new("beads", table.as_object().unwrap());
        let m = build(&p).unwrap();
        assert_eq!(m.model(), "granular_fluidity");
        assert_eq!(m.state_names(), &STATE_NAMES);
        assert_eq!(m.cell_field(), Some(CellField::Laplacian { slot: FLUIDITY_SLOT }));
        for (key, value, message) in [
            ("nonlocal_amplitude", -1.0, "must be >= 0 (got -1)"),
            ("static_friction", 0.0, "must be > 0 (got 0)"),
            ("grain_diameter", -1e-3, "must be > 0 m (got -0.001)"),
            ("poisson_ratio", 0.5, "must be in (-1, 0.5) (got 0.5)"),
            ("poisson_ratio", -1.0, "must be in (-1, 0.5) (got -1)"),
        ] {
            let mut bad = table.clone();
            bad[key] = json!(value);
            let p = Parameters::new("beads", bad.as_object().unwrap());
            assert_eq!(build(&p).err().unwrap(), format!("materials.beads.{key}: {message}"));
        }
    }
}
