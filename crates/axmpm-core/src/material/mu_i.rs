//! Mohr–Coulomb whose friction angle follows the inertial number: the μ(I) rheology of dense
//! granular flows (GDR MiDi 2004; Jop, Forterre & Pouliquen 2006, *A constitutive law for dense
//! granular flows*, Nature 441:727) inside the elasto-plastic Mohr–Coulomb model of
//! [`MohrCoulomb`].
//!
//! Selected by giving a `mohr_coulomb` material an `inertial_friction_angle` (φ₂); the other
//! Mohr–Coulomb keys keep their meaning and `friction_angle` is the static angle φ_s.
//!
//! # Law
//!
//! Inertial number of the particle over the step, from its stress at the start of the step and
//! the step's rate of deformation D:
//!
//! ```text
//! I = |γ̇| d / √(P / ρ_s),   |γ̇| = √(2 D′ : D′),   P = −tr σ / 3
//! μ(I) = μ_s + (μ₂ − μ_s) I / (I₀ + I)
//! ```
//!
//! with d the grain diameter, ρ_s the grain density, D′ = dev D (3D, with the hoop or
//! out-of-plane rate). |γ̇| is Jop et al.'s shear-rate norm √(½ γ̇ᵢⱼγ̇ᵢⱼ), γ̇ᵢⱼ = 2D′ᵢⱼ, so that a
//! simple shear u̇ = γ̇ y has |γ̇| = γ̇. Where P ≤ 0 (material at the apex or in tension) I is
//! unbounded and μ = μ₂.
//!
//! # Mapping to the Mohr–Coulomb friction angle
//!
//! Jop et al. write the stress as −P I + μ(I) P γ̇/|γ̇|: no normal-stress differences, so in the
//! plane of shearing the principal stresses are −P ± μP and the Mohr circle has centre P and
//! radius μP. Mohr–Coulomb at yield has radius/centre = sin φ, hence
//!
//! ```text
//! sin φ(I) = μ(I),   μ_s = sin φ_s,   μ₂ = sin φ₂.
//! ```
//!
//! (In a chute flow μ = tan θ of the slope; the Jop et al. glass-bead values μ_s = tan 20.9° =
//! 0.382 and μ₂ = tan 32.76° = 0.643, I₀ = 0.279, give φ_s = 22.45° and φ₂ = 40.05° here.)
//!
//! The friction angle is evaluated explicitly (from the start-of-step stress), then the step is
//! the Mohr–Coulomb update of [`MohrCoulomb`] with that angle, so every return (plane, edges,
//! apex, tension cut-off, re-compaction, disconnection) is exactly the rate-independent one at φ(I); ψ stays as
//! configured (ψ ≤ φ_s ≤ φ(I)). A particle that does not deform has I = 0 and the static angle.
//!
//! # State variables
//!
//! Those of [`MohrCoulomb`], then `inertial_number`: the I used in the particle's last step
//! (capped at [`INERTIAL_NUMBER_CAP`] where P ≤ 0, so that output files hold finite numbers).

use super::mohr_coulomb::MohrCoulomb;
use super::{rate_of_deformation, Kinematics, Material, Parameters};
use crate::particles::Stress;

/// Inertial number stored for material without pressure (P ≤ 0): μ = μ₂ there.
pub const INERTIAL_NUMBER_CAP: f64 = 1.0e6;

/// I₀ when a scenario does not give one (Jop, Forterre & Pouliquen 2006, glass beads).
pub const INERTIAL_NUMBER_SCALE_DEFAULT: f64 = 0.279;

const STATE_NAMES: [&str; 4] =
    ["plastic_shear_strain", "plastic_volumetric_strain", "plastic_work", "inertial_number"];
const STATE_NAMES_DISCONNECTION: [&str; 5] = [
    "plastic_shear_strain",
    "plastic_volumetric_strain",
    "disconnection_work",
    "plastic_work",
    "inertial_number",
];
const STATE_NAMES_RECOMPACTION: [&str; 5] = [
    "plastic_shear_strain",
    "plastic_volumetric_strain",
    "opening_volumetric_strain",
    "plastic_work",
    "inertial_number",
];

/// Inertial number I = |γ̇| d / √(P/ρ_s) of a stress and a rate of deformation
/// `[D11, D22, D33, D12]` (module doc, "Law"): 0 without shear, `f64::INFINITY` where P ≤ 0
/// and the material shears. Shared with drucker_prager.rs.
#[inline(always)]
pub fn inertial_number(stress: &Stress, d: &[f64; 4], grain_diameter: f64, grain_density: f64) -> f64 {
    let mean = (d[0] + d[1] + d[2]) / 3.0;
    let (e0, e1, e2) = (d[0] - mean, d[1] - mean, d[2] - mean);
    let shear_rate = (2.0 * (e0 * e0 + e1 * e1 + e2 * e2 + 2.0 * d[3] * d[3])).sqrt();
    if shear_rate == 0.0 {
        return 0.0;
    }
    let pressure = -(stress[0] + stress[1] + stress[2]) / 3.0;
    if !(pressure > 0.0) {
        return f64::INFINITY;
    }
    shear_rate * grain_diameter / (pressure / grain_density).sqrt()
}

/// The keys of a table that set the scale of I, `(I₀, d, ρ_s)`: `inertial_number_scale`
/// (default [`INERTIAL_NUMBER_SCALE_DEFAULT`]), and `grain_diameter` and `grain_density`, required
/// once the law is switched on by the key `switch`. Shared with drucker_prager.rs.
pub fn grain_scale_parameters(p: &Parameters, switch: &str) -> Result<(f64, f64, f64), String> {
    let i0 = p.f64_or("inertial_number_scale", INERTIAL_NUMBER_SCALE_DEFAULT)?;
    if !(i0 > 0.0 && i0.is_finite()) {
        return Err(p.error("inertial_number_scale", format!("must be > 0 (got {i0})")));
    }
    let required = |key: &str, unit: &str| -> Result<f64, String> {
        let v = p.optional_f64(key)?.ok_or_else(|| p.error(key, format!("is required with {switch}")))?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(p.error(key, format!("must be > 0{unit} (got {v})")))
        }
    };
    Ok((i0, required("grain_diameter", " m")?, required("grain_density", " kg/m³")?))
}

/// μ(I) = μ_s + (μ₂ − μ_s) I / (I₀ + I), μ₂ for I = ∞ (Jop, Forterre & Pouliquen 2006).
/// Shared with drucker_prager.rs.
#[inline(always)]
pub fn inertial_friction(static_friction: f64, dynamic_friction: f64, inertial_number_scale: f64, inertial_number: f64) -> f64 {
    let rise = dynamic_friction - static_friction;
    if inertial_number.is_infinite() {
        dynamic_friction
    } else {
        static_friction + rise * inertial_number / (inertial_number_scale + inertial_number)
    }
}

/// Mohr–Coulomb with μ(I) friction (module doc).
#[derive(Clone, Debug)]
pub struct InertialMohrCoulomb {
    /// The rate-independent model at the static angle φ_s; its other parameters are used at
    /// every φ(I).
    pub base: MohrCoulomb,
    /// μ_s = sin φ_s.
    pub static_friction: f64,
    /// μ₂ = sin φ₂.
    pub dynamic_friction: f64,
    /// I₀.
    pub inertial_number_scale: f64,
    /// d, m.
    pub grain_diameter: f64,
    /// ρ_s, kg/m³.
    pub grain_density: f64,
}

impl InertialMohrCoulomb {
    /// φ₂ in degrees, φ_s = `base.friction_angle` ≤ φ₂ < 90.
    pub fn new(base: MohrCoulomb, inertial_friction_angle: f64, inertial_number_scale: f64,
               grain_diameter: f64, grain_density: f64) -> Self {
        Self {
            static_friction: base.friction_angle.to_radians().sin(),
            dynamic_friction: inertial_friction_angle.to_radians().sin(),
            base,
            inertial_number_scale,
            grain_diameter,
            grain_density,
        }
    }

    /// The μ(I) variant of a `mohr_coulomb` table, or `None` when it has no
    /// `inertial_friction_angle` (rate-independent Mohr–Coulomb).
    pub fn from_parameters(p: &Parameters, base: &MohrCoulomb) -> Result<Option<Self>, String> {
        let Some(phi2) = p.optional_f64("inertial_friction_angle")? else {
            return Ok(None);
        };
        let phi = base.friction_angle;
        if phi == 0.0 {
            return Err(p.error("inertial_friction_angle", "needs a static friction_angle > 0 (not Tresca, friction_angle = 0)"));
        }
        if !(phi2 >= phi && phi2 < 90.0) {
            return Err(p.error(
                "inertial_friction_angle",
                format!("must be in [friction_angle, 90) = [{phi}, 90) degrees (got {phi2})"),
            ));
        }
        let (i0, d, rho_s) = grain_scale_parameters(p, "inertial_friction_angle")?;
        Ok(Some(Self::new(base.clone(), phi2, i0, d, rho_s)))
    }

    /// Inertial number I of a stress and a rate of deformation `[D11, D22, D33, D12]`
    /// (module doc); `f64::INFINITY` where P ≤ 0 and the material shears.
    #[inline]
    pub fn inertial_number(&self, stress: &Stress, d: &[f64; 4]) -> f64 {
        inertial_number(stress, d, self.grain_diameter, self.grain_density)
    }

    /// μ(I) = μ_s + (μ₂ − μ_s) I / (I₀ + I); μ₂ for I = ∞.
    #[inline]
    pub fn friction(&self, inertial_number: f64) -> f64 {
        inertial_friction(self.static_friction, self.dynamic_friction, self.inertial_number_scale, inertial_number)
    }

    /// The rate-independent model at friction angle asin μ (degrees), other parameters as `base`.
    fn at_friction(&self, mu: f64) -> MohrCoulomb {
        let b = &self.base;
        MohrCoulomb::new(b.density, b.youngs_modulus, b.poisson_ratio, mu.asin().to_degrees(), b.dilation_angle,
                         b.cohesion, b.tension_cutoff)
            .with_recompaction(b.recompaction)
            .with_disconnection(b.critical_jacobian)
            .with_stable_jacobian(b.stable_jacobian)
            .with_cell_averaged_disconnection(b.cell_averaged_disconnection)
    }
}

impl Material for InertialMohrCoulomb {
    fn model(&self) -> &'static str {
        "mohr_coulomb"
    }
    fn density(&self) -> f64 {
        self.base.density()
    }
    fn elastic_energy_density(&self, stress: &Stress) -> f64 {
        self.base.elastic_energy_density(stress)
    }
    fn wave_speed(&self) -> f64 {
        self.base.wave_speed()
    }
    fn state_names(&self) -> &'static [&'static str] {
        if self.base.recompaction {
            &STATE_NAMES_RECOMPACTION
        } else if self.base.critical_jacobian.is_some() {
            &STATE_NAMES_DISCONNECTION
        } else {
            &STATE_NAMES
        }
    }

    fn limit_wave_speed(&mut self, max_wave_speed: f64) {
        self.base.limit_wave_speed(max_wave_speed);
    }
    fn needs_cell_jacobian(&self) -> bool {
        self.base.needs_cell_jacobian()
    }

    // Inlined into the trait's `update_stress_batch` and its AVX2 copy (solver::isa).
    #[inline(always)]
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], k: &Kinematics) {
        let (d, _) = rate_of_deformation(&k.velocity_gradient);
        let inertial_number = self.inertial_number(stress, &d);
        let mu = self.friction(inertial_number);
        let n = self.base.state_names().len();
        if mu == self.static_friction {
            self.base.update_stress(stress, &mut state[..n], k);
        } else {
            self.at_friction(mu).update_stress(stress, &mut state[..n], k);
        }
        if let Some(slot) = state.get_mut(n) {
            *slot = inertial_number.min(INERTIAL_NUMBER_CAP);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model() -> InertialMohrCoulomb {
        // Glass beads (Jop et al. 2006): μ_s = tan 20.9°, μ₂ = tan 32.76°, I₀ = 0.279, here as sin φ.
        let phi_s = (20.9f64).to_radians().tan().asin().to_degrees();
        let phi_2 = (32.76f64).to_radians().tan().asin().to_degrees();
        let base = MohrCoulomb::new(1550.0, 1.0e6, 0.3, phi_s, 0.0, 0.0, 0.0);
        InertialMohrCoulomb::new(base, phi_2, 0.279, 1.15e-3, 2500.0)
    }

    fn kinematics(l: [f64; 5], dt: f64) -> Kinematics {
        Kinematics { velocity_gradient: l, deformation_gradient: [1.0, 0.0, 0.0, 1.0, 1.0], jacobian: 1.0, cell_jacobian: 1.0, dt }
    }

    #[test]
    fn inertial_number_of_a_simple_shear() {
        // u̇ = γ̇ y: L12 = γ̇, D12 = γ̇/2, |γ̇| = γ̇; I = γ̇ d / √(P/ρ_s).
        let m = model();
        let (gamma, p) = (40.0, 250.0);
        let stress = [-p, -p, -p, 0.0];
        let (d, _) = rate_of_deformation(&[0.0, gamma, 0.0, 0.0, 0.0]);
        let expected = gamma * 1.15e-3 / (p / 2500.0f64).sqrt();
        assert!((m.inertial_number(&stress, &d) - expected).abs() < 1e-12 * expected);
        // a pure volume change does not shear
        let (d, _) = rate_of_deformation(&[1.0, 0.0, 0.0, 1.0, 1.0]);
        assert_eq!(m.inertial_number(&stress, &d), 0.0);
        // no pressure: unbounded
        let (d, _) = rate_of_deformation(&[0.0, gamma, 0.0, 0.0, 0.0]);
        assert!(m.inertial_number(&[0.0; 4], &d).is_infinite());
    }

    #[test]
    fn inertial_number_of_a_general_rate_uses_the_whole_deviator() {
        // |γ̇|² = 2 D′:D′ = 2 [tr(D²) − (tr D)²/3], with every component of D different (the
        // hoop rate D33 included), against the invariant form; and pure shear in the plane,
        // D = diag(γ̇/2, −γ̇/2, 0), which is simple shear rotated by 45°: |γ̇| = γ̇.
        let (p, d_grain, rho): (f64, f64, f64) = (250.0, 1.15e-3, 2500.0);
        let stress = [-p, -p, -p, 0.0];
        let d: [f64; 4] = [3.0, -1.0, 0.5, 0.7];
        let trace = d[0] + d[1] + d[2];
        let tr_d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * d[3] * d[3];
        let rate = (2.0 * (tr_d2 - trace * trace / 3.0)).sqrt();
        let expected = rate * d_grain / (p / rho).sqrt();
        let got = inertial_number(&stress, &d, d_grain, rho);
        assert!((got - expected).abs() < 1e-12 * expected, "{got} vs {expected}");
        let gamma = 40.0;
        let got = inertial_number(&stress, &[0.5 * gamma, -0.5 * gamma, 0.0, 0.0], d_grain, rho);
        let simple = inertial_number(&stress, &[0.0, 0.0, 0.0, 0.5 * gamma], d_grain, rho);
        assert!((got - simple).abs() < 1e-12 * simple, "{got} vs {simple}");
    }

    #[test]
    fn friction_rises_from_static_to_dynamic() {
        let m = model();
        assert_eq!(m.friction(0.0), m.static_friction);
        assert_eq!(m.friction(f64::INFINITY), m.dynamic_friction);
        let half = m.friction(0.279);
        assert!((half - 0.5 * (m.static_friction + m.dynamic_friction)).abs() < 1e-15);
        let mut last = m.friction(0.0);
        for k in 1..60 {
            let mu = m.friction(1e-4 * 1.3f64.powi(k));
            assert!(mu > last && mu < m.dynamic_friction);
            last = mu;
        }
        // glass beads: φ_s = 22.45°, φ₂ = 40.05° in the sin φ = μ mapping
        assert!((m.base.friction_angle - 22.449).abs() < 0.001, "{}", m.base.friction_angle);
        assert!((m.dynamic_friction.asin().to_degrees() - 40.051).abs() < 0.001);
    }

    /// A fast simple shear of a confined sample ends on the Mohr–Coulomb surface of φ(I), not
    /// of φ_s: the in-plane Mohr circle radius / centre is μ(I) (sin φ); a slow one at φ_s.
    #[test]
    fn shearing_sample_sits_on_the_surface_of_its_inertial_number() {
        let m = model();
        let p = 200.0;
        for gamma in [1e-3, 5.0, 50.0, 500.0] {
            let mut stress = [-p, -p, -p, 0.0];
            let mut state = [0.0; 4];
            let dt = 2e-4 / gamma; // total shear strain 0.2 in 1000 steps
            for _ in 0..1000 {
                m.update_stress(&mut stress, &mut state, &kinematics([0.0, gamma, 0.0, 0.0, 0.0], dt));
            }
            let centre = -(stress[0] + stress[1]) / 2.0;
            let radius = (((stress[0] - stress[1]) / 2.0).powi(2) + stress[3] * stress[3]).sqrt();
            let (d, _) = rate_of_deformation(&[0.0, gamma, 0.0, 0.0, 0.0]);
            let i = m.inertial_number(&stress, &d);
            let mu = m.friction(i);
            assert!((radius / centre - mu).abs() < 2e-3 * mu, "γ̇ = {gamma}: R/c = {}, μ(I) = {mu}", radius / centre);
            assert!((state[3] - i.min(INERTIAL_NUMBER_CAP)).abs() <= 0.05 * i, "stored I {} vs {i}", state[3]);
            // Plastic work of steady shear at yield: ≈ τ γ_p = (radius) × (0.2 − elastic), > 0.
            assert!(state[2] > 0.5 * radius * 0.2 && state[2] < radius * 0.2 * 1.01, "plastic work {}", state[2]);
            if gamma < 0.01 {
                assert!((mu - m.static_friction).abs() < 1e-4);
            }
            if gamma > 100.0 {
                assert!(mu > m.static_friction + 0.6 * (m.dynamic_friction - m.static_friction));
            }
        }
    }

    /// The wave-speed limit of the run (mohr_coulomb.rs, "Dilute material and the time
    /// step") reaches the model at every friction μ(I) picks, not only the static one.
    #[test]
    fn the_wave_speed_limit_holds_at_every_friction() {
        let mut m = model();
        let c0 = m.wave_speed();
        m.limit_wave_speed(3.0 * c0); // J_s = 9
        assert!((m.base.stable_jacobian - 9.0).abs() < 1e-9);
        assert_eq!(m.at_friction(0.5).stable_jacobian, m.base.stable_jacobian);
        // A dilute particle (J = 900) sheared fast (μ > μ_s) while compressed: its re-loading
        // stiffness is s = 9/900 of the material's.
        let dt = 1e-5;
        let k = Kinematics { jacobian: 900.0, cell_jacobian: 900.0, ..kinematics([-1e-6 / dt, 5e-6 / dt, 0.0, 0.0, 0.0], dt) };
        let (mut a, mut b) = ([-10.0, -10.0, -10.0, 0.0], [-10.0, -10.0, -10.0, 0.0]);
        let (mut sa, mut sb) = ([0.0; 4], [0.0; 4]);
        m.update_stress(&mut a, &mut sa, &k);
        model().update_stress(&mut b, &mut sb, &k);
        assert!(sa[3] > 0.0, "the inertial number is recorded: μ(I) path");
        let (da, db) = (a[0] + 10.0, b[0] + 10.0);
        assert!(db < 0.0 && (da - 0.01 * db).abs() < 1e-9 * db.abs(), "limited {da} vs plain {db}");
    }

    /// The solver computes the cells' mean J only for a model that reads it: μ(I) asks exactly
    /// when its Mohr–Coulomb base does (`cell_averaged_disconnection`).
    #[test]
    fn needs_the_cell_jacobian_exactly_when_its_base_does() {
        let plain = model();
        assert!(!plain.needs_cell_jacobian());
        let base = plain.base.clone().with_disconnection(Some(1.2)).with_cell_averaged_disconnection(true);
        let phi_2 = (32.76f64).to_radians().tan().asin().to_degrees();
        let cell = InertialMohrCoulomb::new(base, phi_2, 0.279, 1.15e-3, 2500.0);
        assert!(cell.needs_cell_jacobian());
        assert!(cell.at_friction(0.5).needs_cell_jacobian(), "kept at every friction μ(I) picks");
    }

    /// Without shearing the update is the rate-independent one, bit for bit.
    #[test]
    fn no_shear_is_plain_mohr_coulomb() {
        let m = model();
        let k = kinematics([-1e-3, 0.0, 0.0, -1e-3, -1e-3], 1e-3); // isotropic compression
        let (mut s1, mut s2) = ([-100.0, -150.0, -120.0, 0.0], [-100.0, -150.0, -120.0, 0.0]);
        let (mut st1, mut st2) = ([0.0; 3], [0.0; 2]);
        m.update_stress(&mut s1, &mut st1, &k);
        m.base.update_stress(&mut s2, &mut st2, &k);
        assert_eq!(s1, s2);
        assert_eq!(&st1[..2], &st2[..]);
        assert_eq!(st1[2], 0.0);
    }

    #[test]
    fn config_selects_and_checks_the_law() {
        use crate::config::MaterialConfig;
        let mut c = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
        c.set("friction_angle", 22.0);
        let params = |c: &MaterialConfig| c.parameters.clone();
        let table = params(&c);
        let base = MohrCoulomb::from_parameters(&Parameters::new("sand", &table)).unwrap();
        let select = |c: &MaterialConfig| {
            let table = params(c);
            InertialMohrCoulomb::from_parameters(&Parameters::new("sand", &table), &base)
        };
        assert!(select(&c).unwrap().is_none());
        c.set("inertial_friction_angle", 38.0);
        let err = select(&c).unwrap_err();
        assert_eq!(err, "materials.sand.grain_diameter: is required with inertial_friction_angle");
        c.set("grain_diameter", 1e-3).set("grain_density", 2500.0);
        let m = select(&c).unwrap().unwrap();
        assert_eq!(m.inertial_number_scale, INERTIAL_NUMBER_SCALE_DEFAULT);
        assert_eq!(m.state_names(), &STATE_NAMES[..]);
        // The registry builds the μ(I) variant under the `mohr_coulomb` name.
        assert_eq!(crate::material::build("sand", &c).unwrap().state_names(), &STATE_NAMES[..]);
        c.set("inertial_friction_angle", 20.0);
        let err = select(&c).unwrap_err();
        assert!(err.starts_with("materials.sand.inertial_friction_angle: ") && err.contains("[22, 90)"), "{err}");
    }
}
