//! Constitutive models behind one trait, registered by the name a scenario's `model` selects.
//!
//! Adding a model = one new file implementing [`Material`] plus one line in [`build`].
//! Stress is Cauchy, `[σ11, σ22, σ33, σ12]` (σ33 = out-of-plane or hoop), tension positive.

use crate::config::MaterialConfig;
use crate::particles::{DeformationGradient, Stress};

pub mod linear_elastic;
pub mod mohr_coulomb;
pub mod mu_i;
pub mod neo_hookean;
pub mod von_mises;

pub use linear_elastic::LinearElastic;
pub use mohr_coulomb::MohrCoulomb;
pub use mu_i::InertialMohrCoulomb;
pub use neo_hookean::NeoHookean;
pub use von_mises::VonMises;

/// What a material sees of one particle's motion over the step.
#[derive(Clone, Copy, Debug)]
pub struct Kinematics {
    /// Velocity gradient `[L11, L12, L21, L22, L33]`, L_ij = ∂v_i/∂x_j; L33 = v_r/R_p
    /// (axisymmetric hoop rate) or 0 (plane strain).
    pub velocity_gradient: [f64; 5],
    /// Deformation gradient at the end of the step.
    pub deformation_gradient: DeformationGradient,
    /// Jacobian det F at the end of the step (3D, including F33).
    pub jacobian: f64,
    pub dt: f64,
}

pub trait Material: Send + Sync {
    /// Registry name (`model = "..."`).
    fn model(&self) -> &'static str;

    /// Reference density ρ0, kg/m³.
    fn density(&self) -> f64;

    /// Fastest elastic (P-)wave speed, m/s, for the CFL time step.
    fn wave_speed(&self) -> f64;

    /// Names of the per-particle state variables this model keeps (e.g. plastic strain).
    fn state_names(&self) -> &'static [&'static str] {
        &[]
    }

    /// Updates `stress` (and `state`, of length `state_names().len()`) over one step.
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], kinematics: &Kinematics);
}

/// Lamé constants (λ, μ) from Young's modulus and Poisson's ratio.
pub fn lame(youngs_modulus: f64, poisson_ratio: f64) -> (f64, f64) {
    let mu = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
    let lambda = youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
    (lambda, mu)
}

/// P-wave speed √((λ + 2μ)/ρ).
pub fn p_wave_speed(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> f64 {
    let (lambda, mu) = lame(youngs_modulus, poisson_ratio);
    ((lambda + 2.0 * mu) / density).sqrt()
}

/// Rate of deformation D = sym(L) as `[D11, D22, D33, D12]` and the in-plane spin W12.
#[inline(always)]
pub fn rate_of_deformation(l: &[f64; 5]) -> ([f64; 4], f64) {
    ([l[0], l[3], l[4], 0.5 * (l[1] + l[2])], 0.5 * (l[1] - l[2]))
}

/// Jaumann co-rotational increment dt (W σ − σ W) for the in-plane spin W12
/// (W = [[0, W12], [−W12, 0]]); the out-of-plane component does not rotate.
#[inline(always)]
pub fn jaumann_rotation(stress: &Stress, spin12: f64, dt: f64) -> Stress {
    let w = spin12 * dt;
    [2.0 * w * stress[3], -2.0 * w * stress[3], 0.0, w * (stress[1] - stress[0])]
}

/// Builds a material from its configuration.
pub fn build(name: &str, config: &MaterialConfig) -> Result<Box<dyn Material>, String> {
    match config.model.as_str() {
        "linear_elastic" => Ok(Box::new(LinearElastic::from_config(config))),
        "neo_hookean" => Ok(Box::new(NeoHookean::from_config(config))),
        // An `inertial_friction_angle` makes the friction angle follow μ(I) (mu_i.rs).
        "mohr_coulomb" => {
            let base = MohrCoulomb::from_config(config)?;
            Ok(match InertialMohrCoulomb::from_config(config, &base)? {
                Some(m) => Box::new(m) as Box<dyn Material>,
                None => Box::new(base),
            })
        }
        // J2 plasticity (von_mises.rs); its errors already name `materials.NAME.KEY`.
        "von_mises" => Ok(Box::new(VonMises::from_config(name, config)?)),
        other => Err(format!(
            "materials.{name}.model: unknown model '{other}' (known: linear_elastic, neo_hookean, mohr_coulomb, von_mises)"
        )),
    }
}
