//! The μ(I) rheology of dense granular flows (GDR MiDi 2004; Jop, Forterre & Pouliquen 2006,
//! *A constitutive law for dense granular flows*, Nature 441:727): the inertial number of a
//! particle's step and the friction coefficient it gives. drucker_prager.rs uses it as its
//! `inertial_friction` option.
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
//! simple shear u̇ = γ̇ y has |γ̇| = γ̇. Where P ≤ 0 (material without contact pressure) I is
//! unbounded and μ = μ₂. A particle that does not deform has I = 0 and the static friction μ_s.

use super::Parameters;
use crate::particles::Stress;

/// Inertial number stored for material without pressure (P ≤ 0): μ = μ₂ there.
pub const INERTIAL_NUMBER_CAP: f64 = 1.0e6;

/// I₀ when a scenario does not give one (Jop, Forterre & Pouliquen 2006, glass beads).
pub const INERTIAL_NUMBER_SCALE_DEFAULT: f64 = 0.279;

/// Inertial number I = |γ̇| d / √(P/ρ_s) of a stress and a rate of deformation
/// `[D11, D22, D33, D12]` (module doc, "Law"): 0 without shear, `f64::INFINITY` where P ≤ 0
/// and the material shears.
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
/// once the law is switched on by the key `switch`.
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
#[inline(always)]
pub fn inertial_friction(static_friction: f64, dynamic_friction: f64, inertial_number_scale: f64, inertial_number: f64) -> f64 {
    let rise = dynamic_friction - static_friction;
    if inertial_number.is_infinite() {
        dynamic_friction
    } else {
        static_friction + rise * inertial_number / (inertial_number_scale + inertial_number)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::rate_of_deformation;

    const GRAIN_DIAMETER: f64 = 1.15e-3;
    const GRAIN_DENSITY: f64 = 2500.0;

    #[test]
    fn inertial_number_of_a_simple_shear() {
        // u̇ = γ̇ y: L12 = γ̇, D12 = γ̇/2, |γ̇| = γ̇; I = γ̇ d / √(P/ρ_s).
        let (gamma, p) = (40.0, 250.0);
        let stress = [-p, -p, -p, 0.0];
        let i = |d: &[f64; 4], stress: &Stress| inertial_number(stress, d, GRAIN_DIAMETER, GRAIN_DENSITY);
        let (d, _) = rate_of_deformation(&[0.0, gamma, 0.0, 0.0, 0.0]);
        let expected = gamma * GRAIN_DIAMETER / (p / GRAIN_DENSITY).sqrt();
        assert!((i(&d, &stress) - expected).abs() < 1e-12 * expected);
        // A pure volume change does not shear.
        let (d, _) = rate_of_deformation(&[1.0, 0.0, 0.0, 1.0, 1.0]);
        assert_eq!(i(&d, &stress), 0.0);
        // No pressure: unbounded.
        let (d, _) = rate_of_deformation(&[0.0, gamma, 0.0, 0.0, 0.0]);
        assert!(i(&d, &[0.0; 4]).is_infinite());
        assert!(i(&d, &[1.0, 1.0, 1.0, 0.0]).is_infinite());
    }

    #[test]
    fn inertial_number_of_a_general_rate_uses_the_whole_deviator() {
        // |γ̇|² = 2 D′:D′ = 2 [tr(D²) − (tr D)²/3], with every component of D different (the
        // hoop rate D33 included), against the invariant form; and pure shear in the plane,
        // D = diag(γ̇/2, −γ̇/2, 0), which is simple shear rotated by 45°: |γ̇| = γ̇.
        let p: f64 = 250.0;
        let stress = [-p, -p, -p, 0.0];
        let d: [f64; 4] = [3.0, -1.0, 0.5, 0.7];
        let trace = d[0] + d[1] + d[2];
        let tr_d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 2.0 * d[3] * d[3];
        let rate = (2.0 * (tr_d2 - trace * trace / 3.0)).sqrt();
        let expected = rate * GRAIN_DIAMETER / (p / GRAIN_DENSITY).sqrt();
        let got = inertial_number(&stress, &d, GRAIN_DIAMETER, GRAIN_DENSITY);
        assert!((got - expected).abs() < 1e-12 * expected, "{got} vs {expected}");
        let gamma = 40.0;
        let got = inertial_number(&stress, &[0.5 * gamma, -0.5 * gamma, 0.0, 0.0], GRAIN_DIAMETER, GRAIN_DENSITY);
        let simple = inertial_number(&stress, &[0.0, 0.0, 0.0, 0.5 * gamma], GRAIN_DIAMETER, GRAIN_DENSITY);
        assert!((got - simple).abs() < 1e-12 * simple, "{got} vs {simple}");
    }

    #[test]
    fn friction_rises_from_static_to_dynamic() {
        // Jop et al.'s glass beads: μ_s = tan 20.9°, μ₂ = tan 32.76°, I₀ = 0.279.
        let (mu_s, mu_2, i0) = (20.9f64.to_radians().tan(), 32.76f64.to_radians().tan(), 0.279);
        let mu = |i: f64| inertial_friction(mu_s, mu_2, i0, i);
        assert_eq!(mu(0.0), mu_s);
        assert_eq!(mu(f64::INFINITY), mu_2);
        assert!((mu(i0) - 0.5 * (mu_s + mu_2)).abs() < 1e-15, "half way at I = I₀");
        let mut last = mu(0.0);
        for k in 1..60 {
            let m = mu(1e-4 * 1.3f64.powi(k));
            assert!(m > last && m < mu_2);
            last = m;
        }
    }

    #[test]
    fn grain_scale_keys_are_checked_with_their_names() {
        use serde_json::json;
        let read = |table: serde_json::Value| {
            grain_scale_parameters(&Parameters::new("sand", table.as_object().unwrap()), "inertial_friction")
        };
        assert_eq!(read(json!({"grain_diameter": 1e-3, "grain_density": 2500.0})),
                   Ok((INERTIAL_NUMBER_SCALE_DEFAULT, 1e-3, 2500.0)));
        assert_eq!(read(json!({"inertial_number_scale": 0.5, "grain_diameter": 1e-3, "grain_density": 2500.0})),
                   Ok((0.5, 1e-3, 2500.0)));
        assert_eq!(read(json!({"grain_density": 2500.0})).unwrap_err(),
                   "materials.sand.grain_diameter: is required with inertial_friction");
        assert_eq!(read(json!({"grain_diameter": 1e-3})).unwrap_err(),
                   "materials.sand.grain_density: is required with inertial_friction");
        assert_eq!(read(json!({"grain_diameter": 0.0, "grain_density": 2500.0})).unwrap_err(),
                   "materials.sand.grain_diameter: must be > 0 m (got 0)");
        assert_eq!(read(json!({"grain_diameter": 1e-3, "grain_density": -1.0})).unwrap_err(),
                   "materials.sand.grain_density: must be > 0 kg/m³ (got -1)");
        assert_eq!(read(json!({"inertial_number_scale": 0.0, "grain_diameter": 1e-3, "grain_density": 2500.0}))
                       .unwrap_err(), "materials.sand.inertial_number_scale: must be > 0 (got 0)");
    }
}
