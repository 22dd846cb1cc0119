//! Hypoelastic isotropic linear elasticity with the Jaumann stress rate:
//! σ̇ = λ tr(D) I + 2μ D + W σ − σ W (objective for large rotations).

use super::{jaumann_rotation, lame, p_wave_speed, rate_of_deformation, Kinematics, Material, Parameters};
use crate::particles::Stress;

#[derive(Clone, Debug)]
pub struct LinearElastic {
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    lambda: f64,
    mu: f64,
}

impl LinearElastic {
    pub fn new(density: f64, youngs_modulus: f64, poisson_ratio: f64) -> Self {
        let (lambda, mu) = lame(youngs_modulus, poisson_ratio);
        Self { density, youngs_modulus, poisson_ratio, lambda, mu }
    }

    /// From the `density`, `youngs_modulus` and `poisson_ratio` of a material table.
    pub fn from_parameters(p: &Parameters) -> Result<Self, String> {
        Ok(Self::new(p.f64("density")?, p.f64("youngs_modulus")?, p.f64("poisson_ratio")?))
    }

    /// Elastic stress increment λ tr(dε) I + 2μ dε for a strain increment `[11, 22, 33, 12]`
    /// (tensor shear component).
    #[inline(always)]
    pub fn elastic_increment(&self, de: &[f64; 4]) -> Stress {
        let tr = de[0] + de[1] + de[2];
        [
            self.lambda * tr + 2.0 * self.mu * de[0],
            self.lambda * tr + 2.0 * self.mu * de[1],
            self.lambda * tr + 2.0 * self.mu * de[2],
            2.0 * self.mu * de[3],
        ]
    }
}

/// The registry's builder ([`super::MODELS`]).
pub fn build(p: &Parameters) -> Result<Box<dyn Material>, String> {
    Ok(Box::new(LinearElastic::from_parameters(p)?))
}

impl Material for LinearElastic {
    fn model(&self) -> &'static str {
        "linear_elastic"
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
        let (d, spin) = rate_of_deformation(&k.velocity_gradient);
        let de = [d[0] * k.dt, d[1] * k.dt, d[2] * k.dt, d[3] * k.dt];
        let rot = jaumann_rotation(stress, spin, k.dt);
        let inc = self.elastic_increment(&de);
        for c in 0..4 {
            stress[c] += inc[c] + rot[c];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kin(l: [f64; 5], dt: f64) -> Kinematics {
        Kinematics { velocity_gradient: l, deformation_gradient: [1.0, 0.0, 0.0, 1.0, 1.0], jacobian: 1.0, cell_field: [0.0; 2], dt }
    }

    #[test]
    fn uniaxial_strain_increment_by_hand() {
        // E = 10 MPa, ν = 0.25: λ = 4 MPa, μ = 4 MPa. dε11 = 1e-4 → σ11 = (λ+2μ)·1e-4 = 1200 Pa,
        // σ22 = σ33 = λ·1e-4 = 400 Pa.
        let m = LinearElastic::new(2000.0, 10e6, 0.25);
        let mut s = [0.0; 4];
        m.update_stress(&mut s, &mut [], &kin([1e-2, 0.0, 0.0, 0.0, 0.0], 1e-2));
        assert!((s[0] - 1200.0).abs() < 1e-9, "{s:?}");
        assert!((s[1] - 400.0).abs() < 1e-9);
        assert!((s[2] - 400.0).abs() < 1e-9);
        assert!(s[3].abs() < 1e-12);
    }

    #[test]
    fn simple_shear_increment_by_hand() {
        // L12 = γ̇: D12 = γ̇/2, σ12 = 2μ D12 dt = μ γ̇ dt.
        let m = LinearElastic::new(2000.0, 10e6, 0.25);
        let mut s = [0.0; 4];
        m.update_stress(&mut s, &mut [], &kin([0.0, 1.0, 0.0, 0.0, 0.0], 1e-5));
        assert!((s[3] - 4e6 * 1e-5).abs() < 1e-9, "{s:?}");
    }

    #[test]
    fn pure_spin_rotates_stress_without_changing_invariants() {
        let m = LinearElastic::new(2000.0, 10e6, 0.25);
        let mut s = [-100.0, -300.0, -50.0, 40.0];
        let (i1, det) = (s[0] + s[1], s[0] * s[1] - s[3] * s[3]);
        // Rigid spin ω: L = [[0, −ω], [ω, 0]]; many small steps through 90°.
        let steps = 20000;
        let omega = std::f64::consts::FRAC_PI_2;
        for _ in 0..steps {
            m.update_stress(&mut s, &mut [], &kin([0.0, -omega, omega, 0.0, 0.0], 1.0 / steps as f64));
        }
        assert!((s[0] + s[1] - i1).abs() < 1e-9);
        assert!(((s[0] * s[1] - s[3] * s[3]) - det).abs() / det.abs() < 1e-3);
        // After a quarter turn the normal components swap.
        assert!((s[0] + 300.0).abs() < 0.5 && (s[1] + 100.0).abs() < 0.5, "{s:?}");
        assert!((s[2] + 50.0).abs() < 1e-12);
    }
}
