//! Compressible neo-Hookean hyperelasticity (docs/physics.md §4):
//! σ = (1/J) [μ (b − I) + λ ln J I], b = F Fᵀ, J = det F.
//! Stress depends on F alone, so it is objective and path independent.

use super::{lame, p_wave_speed, Kinematics, Material, Parameters};
use crate::particles::{DeformationGradient, Stress};

#[derive(Clone, Debug)]
pub struct NeoHookean {
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    lambda: f64,
    mu: f64,
}

impl NeoHookean {
    pub fn new(density: f64, youngs_modulus: f64, poisson_ratio: f64) -> Self {
        let (lambda, mu) = lame(youngs_modulus, poisson_ratio);
        Self { density, youngs_modulus, poisson_ratio, lambda, mu }
    }

    /// From the `density`, `youngs_modulus` and `poisson_ratio` of a material table.
    pub fn from_parameters(p: &Parameters) -> Result<Self, String> {
        Ok(Self::new(p.f64("density")?, p.f64("youngs_modulus")?, p.f64("poisson_ratio")?))
    }

    /// Cauchy stress `[σ11, σ22, σ33, σ12]` for the deformation gradient `[F11, F12, F21, F22, F33]`.
    pub fn cauchy_stress(&self, f: &DeformationGradient) -> Stress {
        let j = (f[0] * f[3] - f[1] * f[2]) * f[4];
        let b11 = f[0] * f[0] + f[1] * f[1];
        let b22 = f[2] * f[2] + f[3] * f[3];
        let b12 = f[0] * f[2] + f[1] * f[3];
        let b33 = f[4] * f[4];
        let p = self.lambda * j.ln();
        [
            (self.mu * (b11 - 1.0) + p) / j,
            (self.mu * (b22 - 1.0) + p) / j,
            (self.mu * (b33 - 1.0) + p) / j,
            self.mu * b12 / j,
        ]
    }
}

/// The registry's builder ([`super::MODELS`]).
pub fn build(p: &Parameters) -> Result<Box<dyn Material>, String> {
    Ok(Box::new(NeoHookean::from_parameters(p)?))
}

impl Material for NeoHookean {
    fn model(&self) -> &'static str {
        "neo_hookean"
    }
    fn density(&self) -> f64 {
        self.density
    }
    fn elastic_energy_density(&self, stress: &Stress) -> f64 {
        super::complementary_energy(stress, self.youngs_modulus, self.poisson_ratio)
    }
    fn wave_speed(&self) -> f64 {
        p_wave_speed(self.youngs_modulus, self.poisson_ratio, self.density)
    }

    // Inlined into the trait's `update_stress_batch` and its AVX2 copy (solver::isa).
    #[inline(always)]
    fn update_stress(&self, stress: &mut Stress, _state: &mut [f64], k: &Kinematics) {
        *stress = self.cauchy_stress(&k.deformation_gradient);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniaxial_stretch_with_zero_poisson_gives_the_1d_law() {
        // ν = 0: λ = 0, μ = E/2; F = diag(1, λs, 1): σ22 = (E/2)(λs² − 1)/λs = (E/2)(λs − 1/λs).
        let e = 20e3;
        let m = NeoHookean::new(1000.0, e, 0.0);
        for ls in [0.6, 0.9, 1.0, 1.3, 1.62] {
            let s = m.cauchy_stress(&[1.0, 0.0, 0.0, ls, 1.0]);
            assert!((s[1] - 0.5 * e * (ls - 1.0 / ls)).abs() < 1e-9 * e, "λs = {ls}: {s:?}");
            assert!(s[0].abs() < 1e-12 && s[2].abs() < 1e-12 && s[3].abs() < 1e-12);
        }
    }

    #[test]
    fn simple_shear_by_hand() {
        // F = [[1, γ], [0, 1]], J = 1: b = [[1+γ², γ], [γ, 1]], σ = μ (b − I).
        let m = NeoHookean::new(1000.0, 2.6e6, 0.3); // μ = 1 MPa
        let g = 0.2;
        let s = m.cauchy_stress(&[1.0, g, 0.0, 1.0, 1.0]);
        assert!((s[0] - 1e6 * g * g).abs() < 1e-6);
        assert!(s[1].abs() < 1e-6 && s[2].abs() < 1e-6);
        assert!((s[3] - 1e6 * g).abs() < 1e-6);
    }

    #[test]
    fn volumetric_compression_by_hand() {
        // F = a I (3D): J = a³, σ = (μ(a² − 1) + λ 3 ln a)/a³ on each normal component.
        let m = NeoHookean::new(1000.0, 1e6, 0.3);
        let (lambda, mu) = lame(1e6, 0.3);
        let a: f64 = 0.9;
        let s = m.cauchy_stress(&[a, 0.0, 0.0, a, a]);
        let expect = (mu * (a * a - 1.0) + lambda * 3.0 * a.ln()) / a.powi(3);
        for c in 0..3 {
            assert!((s[c] - expect).abs() < 1e-8 * expect.abs());
        }
    }

    #[test]
    fn rotation_leaves_stress_invariants_unchanged() {
        let m = NeoHookean::new(1000.0, 1e6, 0.3);
        let u = [1.1, 0.05, 0.05, 0.9, 1.02];
        let s0 = m.cauchy_stress(&u);
        let th: f64 = 0.7;
        let (c, s) = (th.cos(), th.sin());
        // F = R U
        let f = [c * u[0] - s * u[2], c * u[1] - s * u[3], s * u[0] + c * u[2], s * u[1] + c * u[3], u[4]];
        let s1 = m.cauchy_stress(&f);
        assert!(((s0[0] + s0[1]) - (s1[0] + s1[1])).abs() < 1e-6);
        assert!(((s0[0] * s0[1] - s0[3] * s0[3]) - (s1[0] * s1[1] - s1[3] * s1[3])).abs() < 1e-3);
        assert!((s0[2] - s1[2]).abs() < 1e-9);
    }
}
