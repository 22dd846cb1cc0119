//! Constitutive models behind one trait, registered by the name a scenario's `model` selects.
//!
//! Adding a model = one new file implementing [`Material`], with a `build` that reads the
//! model's parameters through [`Parameters`], plus one line in [`MODELS`].
//! Stress is Cauchy, `[σ11, σ22, σ33, σ12]` (σ33 = out-of-plane or hoop), tension positive.

use std::fmt::Display;

use serde_json::{Map, Value};

use crate::config::MaterialConfig;
use crate::particles::{DeformationGradient, Stress};

pub mod drucker_prager;
pub mod granular_fluidity;
pub mod linear_elastic;
pub mod mohr_coulomb;
pub mod mu_i;
pub mod neo_hookean;
pub mod status;
pub mod von_mises;
#[cfg(test)]
pub mod testing;

pub use drucker_prager::DruckerPrager;
pub use granular_fluidity::laplacian::{CellLaplacian, FluidityBoundary};
pub use granular_fluidity::GranularFluidity;
pub use linear_elastic::LinearElastic;
pub use mohr_coulomb::MohrCoulomb;
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
    /// The model's [`Material::cell_field`] at the particle's start-of-step background cell
    /// (zeros for a model that asks for none).
    pub cell_field: [f64; 2],
    pub dt: f64,
}

impl Kinematics {
    /// All zero (a placeholder for buffers that are filled before they are read).
    pub const ZERO: Kinematics = Kinematics {
        velocity_gradient: [0.0; 5],
        deformation_gradient: [0.0; 5],
        jacobian: 0.0,
        cell_field: [0.0; 2],
        dt: 0.0,
    };
}

/// A field the solver computes over the background cells for a model that asks for it
/// ([`Material::cell_field`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellField {
    /// The five-point Laplacian of the volume-weighted cell mean of state slot `slot`,
    /// ∇²ḡ = S − D ḡ, handed over as [S, D] ([`granular_fluidity::laplacian`]).
    Laplacian { slot: usize },
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

    /// Tells the model the fastest P-wave speed the run's time step keeps stable,
    /// [`crate::simulation::COURANT_LIMIT`] h/Δt (called once, when the run is built). A model
    /// whose wave speed grows with the deformation may bound it there; the default ignores
    /// it. Mohr–Coulomb: material dilated beyond J = (max_wave_speed/c0)² (a granular gas,
    /// stress-free but for re-loading) gets its moduli scaled by that J over its own
    /// (mohr_coulomb.rs, "Dilute material and the time step").
    fn limit_wave_speed(&mut self, _max_wave_speed: f64) {}

    /// The field over the background cells this model reads in [`Kinematics::cell_field`]
    /// (the solver computes it at the start of each step); `None` for a purely local model.
    fn cell_field(&self) -> Option<CellField> {
        None
    }

    /// Updates `stress` (and `state`, of length `state_names().len()`) over one step.
    fn update_stress(&self, stress: &mut Stress, state: &mut [f64], kinematics: &Kinematics);

    /// [`Material::update_stress`] of a run of particles of this model, in order: particle k
    /// has `stress[k]`, the state `state[k · stride..k · stride + state_length]` (`stride` ≥ 1,
    /// `state` holds `stress.len()` strides) and
    /// `kinematics[k]`. One call per run instead of one per particle: the solver's update pass
    /// uses it, and the model's `update_stress` is inlined into this loop.
    #[inline(always)]
    fn update_stress_batch(
        &self,
        stress: &mut [Stress],
        state: &mut [f64],
        stride: usize,
        state_length: usize,
        kinematics: &[Kinematics],
    ) {
        update_each(self, stress, state, stride, state_length, kinematics)
    }

    /// [`Material::update_stress_batch`] compiled with AVX2 (see `solver::isa`): the same
    /// operations in the same order, so the same result bit for bit.
    /// SAFETY: call only on a CPU with AVX2, FMA and BMI2 (`solver::Isa::Avx2`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    unsafe fn update_stress_batch_avx2(
        &self,
        stress: &mut [Stress],
        state: &mut [f64],
        stride: usize,
        state_length: usize,
        kinematics: &[Kinematics],
    ) {
        self.update_stress_batch(stress, state, stride, state_length, kinematics)
    }

    /// Stored elastic energy per unit current volume at `stress` (J/m³), for the energy
    /// budget: the complementary energy of isotropic linear elasticity with the model's E and
    /// ν ([`complementary_energy`]); 0 for a model without them.
    fn elastic_energy_density(&self, _stress: &Stress) -> f64 {
        0.0
    }
}

/// [`Material::update_stress`] particle by particle over a run (the default of
/// [`Material::update_stress_batch`], and the path of a model's variants that its own batch
/// update does not cover).
#[inline(always)]
pub fn update_each<M: Material + ?Sized>(
    material: &M,
    stress: &mut [Stress],
    state: &mut [f64],
    stride: usize,
    state_length: usize,
    kinematics: &[Kinematics],
) {
    for ((s, kin), slots) in stress.iter_mut().zip(kinematics).zip(state.chunks_exact_mut(stride)) {
        material.update_stress(s, &mut slots[..state_length], kin);
    }
}

/// Lamé constants (λ, μ) from Young's modulus and Poisson's ratio.
/// Complementary energy density of isotropic linear elasticity, J/m³:
/// W = [(1 + ν) σ:σ − ν (tr σ)²] / (2E), σ = [11, 22, 33, 12] (σ:σ counts the shear twice).
pub fn complementary_energy(stress: &Stress, youngs_modulus: f64, poisson_ratio: f64) -> f64 {
    let [a, b, c, s] = *stress;
    let tr = a + b + c;
    let ss = a * a + b * b + c * c + 2.0 * s * s;
    ((1.0 + poisson_ratio) * ss - poisson_ratio * tr * tr) / (2.0 * youngs_modulus)
}

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

/// p = −tr σ / 3 and τ = √(½ s:s) of a stress (3D: the hoop or out-of-plane deviator included),
/// the invariants of the pressure-dependent cone models (granular_fluidity.rs, drucker_prager.rs).
#[inline(always)]
pub fn pressure_and_shear(stress: &Stress) -> (f64, f64) {
    let p = -(stress[0] + stress[1] + stress[2]) / 3.0;
    let (s0, s1, s2) = (stress[0] + p, stress[1] + p, stress[2] + p);
    (p, (0.5 * (s0 * s0 + s1 * s1 + s2 * s2) + stress[3] * stress[3]).sqrt())
}

/// Stress power of one step per unit current volume, Δt σ : D, for the rate of deformation `d`
/// of [`rate_of_deformation`] (tensor shear component, hence the factor 2).
#[inline(always)]
pub fn stress_power(stress: &Stress, d: &[f64; 4], dt: f64) -> f64 {
    dt * (stress[0] * d[0] + stress[1] * d[1] + stress[2] * d[2] + 2.0 * stress[3] * d[3])
}

/// J up to which a hypoelastic model with P-wave speed `wave_speed` (as placed; c(J) = c0 √J at
/// density ρ0/J) stays within `max_wave_speed`: (c_max/c0)², never below 1; ∞ when unbounded
/// ([`Material::limit_wave_speed`]; mohr_coulomb.rs, "Dilute material and the time step").
pub fn stable_jacobian(max_wave_speed: f64, wave_speed: f64) -> f64 {
    let ratio = max_wave_speed / wave_speed;
    if ratio.is_finite() { (ratio * ratio).max(1.0) } else { f64::INFINITY }
}

/// The parameter table of one material (`materials.NAME`), read by its model. Absent keys and
/// JSON `null` both count as "not given"; keys a model does not read are ignored (the front
/// end has already rejected unknown keys).
#[derive(Clone, Copy, Debug)]
pub struct Parameters<'a> {
    name: &'a str,
    table: &'a Map<String, Value>,
}

impl<'a> Parameters<'a> {
    pub fn new(name: &'a str, table: &'a Map<String, Value>) -> Self {
        Self { name, table }
    }

    /// The material's name (`materials.NAME`).
    pub fn name(&self) -> &str {
        self.name
    }

    /// A required number.
    pub fn f64(&self, key: &str) -> Result<f64, String> {
        self.optional_f64(key)?.ok_or_else(|| self.error(key, "required"))
    }

    /// A required finite number > 0; the message names the key, the range and `unit`.
    pub fn positive(&self, key: &str, unit: &str) -> Result<f64, String> {
        let v = self.f64(key)?;
        if v > 0.0 && v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(key, format!("must be > 0{unit} (got {v})")))
        }
    }

    /// The required `poisson_ratio`, in (−1, 0.5).
    pub fn poisson_ratio(&self) -> Result<f64, String> {
        let v = self.f64("poisson_ratio")?;
        if v > -1.0 && v < 0.5 {
            Ok(v)
        } else {
            Err(self.error("poisson_ratio", format!("must be in (-1, 0.5) (got {v})")))
        }
    }

    /// The disconnection threshold J_c = ρ0/(φ_c ρ_s) of Dunatunga & Kamrin's disconnected
    /// state (mohr_coulomb.rs, "Disconnected material"; drucker_prager.rs) from
    /// `critical_packing_fraction` (φ_c) and `grain_density` (ρ_s), or `None` without a
    /// `critical_packing_fraction`. The packing as placed, φ0 = ρ0/ρ_s (ρ0 = `density`), must be
    /// < 1 and φ_c in (0, φ0] (a material placed looser than φ_c would start disconnected).
    pub fn critical_jacobian(&self, density: f64) -> Result<Option<f64>, String> {
        let Some(phi_c) = self.optional_f64("critical_packing_fraction")? else {
            return Ok(None);
        };
        let rho_s = self
            .optional_f64("grain_density")?
            .ok_or_else(|| self.error("grain_density", "is required with critical_packing_fraction"))?;
        if !(rho_s > density && rho_s.is_finite()) {
            return Err(self.error(
                "grain_density",
                format!("must be > density = {density} kg/m³ (packing as placed density/grain_density < 1; got {rho_s})"),
            ));
        }
        let phi0 = density / rho_s;
        if !(phi_c > 0.0 && phi_c <= phi0) {
            return Err(self.error(
                "critical_packing_fraction",
                format!("must be in (0, density/grain_density] = (0, {phi0}] (got {phi_c})"),
            ));
        }
        Ok(Some(phi0 / phi_c))
    }

    /// The key is in the table with a value other than `null`.
    pub fn is_given(&self, key: &str) -> bool {
        !matches!(self.table.get(key), None | Some(Value::Null))
    }

    /// A number, `default` when not given.
    pub fn f64_or(&self, key: &str, default: f64) -> Result<f64, String> {
        Ok(self.optional_f64(key)?.unwrap_or(default))
    }

    /// A number, `None` when not given.
    pub fn optional_f64(&self, key: &str) -> Result<Option<f64>, String> {
        match self.table.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v.as_f64().map(Some).ok_or_else(|| self.error(key, format!("must be a number (got {v})"))),
        }
    }

    /// A boolean, `default` when not given.
    pub fn bool_or(&self, key: &str, default: bool) -> Result<bool, String> {
        match self.table.get(key) {
            None | Some(Value::Null) => Ok(default),
            Some(v) => v.as_bool().ok_or_else(|| self.error(key, format!("must be true or false (got {v})"))),
        }
    }

    /// An error message naming the key: `materials.NAME.KEY: message`.
    pub fn error(&self, key: &str, message: impl Display) -> String {
        format!("materials.{}.{key}: {message}", self.name)
    }
}

/// Re-connection of Dunatunga & Kamrin's disconnected state (mohr_coulomb.rs, "Disconnected
/// material", rule 2; drucker_prager.rs): the part of a compressive strain increment `strain`
/// done while J was still above J_c, ln(J_n/J_c) with ln J_n = ln J − tr Δε (`jacobian` the
/// end-of-step J), is taken out of it isotropically, so that it is stored nowhere. Returns the
/// compaction taken out (0 when the step started at or below J_c, or extends).
#[inline(always)]
pub fn take_out_disconnected_compaction(strain: &mut [f64; 4], jacobian: f64, critical_jacobian: f64) -> f64 {
    let dv = strain[0] + strain[1] + strain[2];
    if dv < 0.0 {
        let excess = jacobian.ln() - dv - critical_jacobian.ln();
        if excess > 0.0 {
            let closed = excess.min(-dv);
            let third = closed / 3.0;
            strain[0] += third;
            strain[1] += third;
            strain[2] += third;
            return closed;
        }
    }
    0.0
}

/// Builds a model from its parameters.
pub type ModelBuilder = fn(&Parameters) -> Result<Box<dyn Material>, String>;

/// The constitutive models: `model` name → builder. One line per model.
pub const MODELS: &[(&str, ModelBuilder)] = &[
    ("linear_elastic", linear_elastic::build),
    ("neo_hookean", neo_hookean::build),
    ("mohr_coulomb", mohr_coulomb::build),
    ("von_mises", von_mises::build),
    // Nonlocal granular fluidity (Henann & Kamrin 2013).
    ("granular_fluidity", granular_fluidity::build),
    // Rate-independent Drucker–Prager (Rousseau et al. 2023's constant-friction rheology).
    ("drucker_prager", drucker_prager::build),
];

/// The models that ask the solver for a cell field (`Material::cell_field`): their cell
/// boundaries are fixed, so a moving grid (`grid.follow`) is refused with them.
pub const NONLOCAL_MODELS: &[&str] = &["granular_fluidity"];

/// Why `grid.follow` is refused with a material of [`NONLOCAL_MODELS`].
pub const FOLLOW_WITH_NONLOCAL: &str = "cannot be combined with a non-local material (its cell boundaries are fixed)";

/// Names of the registered models, in registry order.
pub fn model_names() -> Vec<&'static str> {
    MODELS.iter().map(|(name, _)| *name).collect()
}

/// Builds material `name` from its configuration.
pub fn build(name: &str, config: &MaterialConfig) -> Result<Box<dyn Material>, String> {
    let parameters = Parameters::new(name, &config.parameters);
    match MODELS.iter().find(|(model, _)| *model == config.model) {
        Some((model, builder)) => {
            status::check(&parameters, model)?;
            builder(&parameters)
        }
        None => Err(parameters.error(
            "model",
            format!("unknown model '{}' (known: {})", config.model, model_names().join(", ")),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn parameters_read_numbers_defaults_and_name_the_key_in_errors() {
        let table = json!({"density": 1550, "poisson_ratio": 0.3, "cohesion": null, "flag": true, "bad": "x"});
        let p = Parameters::new("sand", table.as_object().unwrap());
        assert_eq!(p.f64("density"), Ok(1550.0));
        assert_eq!(p.f64("youngs_modulus"), Err("materials.sand.youngs_modulus: required".to_string()));
        assert_eq!(p.f64_or("cohesion", 5.0), Ok(5.0));
        assert_eq!(p.optional_f64("cohesion"), Ok(None));
        assert_eq!(p.optional_f64("poisson_ratio"), Ok(Some(0.3)));
        assert_eq!(p.bool_or("flag", false), Ok(true));
        assert_eq!(p.bool_or("other", false), Ok(false));
        assert_eq!(p.f64("bad"), Err("materials.sand.bad: must be a number (got \"x\")".to_string()));
        assert!(p.bool_or("density", false).unwrap_err().starts_with("materials.sand.density: must be true or false"));
    }

    #[test]
    fn every_model_is_built_by_its_registered_name_and_unknown_ones_list_the_known() {
        let mut config = MaterialConfig::elastic("x", 1550.0, 1e6, 0.3);
        config.set("friction_angle", 30.0);
        config.set("yield_stress", 1e4);
        config.set("friction", 0.52);
        for (key, value) in [("static_friction", 0.38), ("friction_rate", 0.94), ("nonlocal_amplitude", 0.48),
                             ("grain_diameter", 1e-3), ("grain_density", 2500.0)] {
            config.set(key, value);
        }
        // The registry refuses an experimental model or option without the opt-in, and a retired key.
        config.model = "granular_fluidity".into();
        assert!(build("sand", &config).err().unwrap().starts_with("materials.sand.model: granular_fluidity is experimental"));
        config.model = "mohr_coulomb".into();
        config.set("recompaction", false);
        assert!(build("sand", &config).err().unwrap().starts_with("materials.sand.recompaction: is not a mohr_coulomb parameter"));
        config.parameters.remove("recompaction");
        config.set("experimental", true);
        for name in model_names() {
            config.model = name.into();
            let m = build("sand", &config).unwrap();
            assert_eq!(m.model(), name);
            assert_eq!(m.density(), 1550.0);
            // Only the nonlocal model asks the solver for a cell field.
            assert_eq!(m.cell_field().is_some(), NONLOCAL_MODELS.contains(&name), "{name}");
        }
        config.model = "cam_clay".into();
        assert_eq!(
            build("sand", &config).err().unwrap(),
            "materials.sand.model: unknown model 'cam_clay' (known: linear_elastic, neo_hookean, mohr_coulomb, von_mises, granular_fluidity, drucker_prager)"
        );
    }

    #[test]
    fn material_config_keeps_the_json_shape() {
        let text = r#"{"model": "mohr_coulomb", "density": 1550.0, "youngs_modulus": 1e6, "poisson_ratio": 0.3,
            "friction_angle": 30.0, "dilation_angle": null, "tension_cutoff": 5.0}"#;
        let config: MaterialConfig = serde_json::from_str(text).unwrap();
        assert_eq!(config.model, "mohr_coulomb");
        assert_eq!(config.parameters["friction_angle"], json!(30.0));
        assert!(!config.parameters.contains_key("model"));
        let again: MaterialConfig = serde_json::from_str(&serde_json::to_string(&config).unwrap()).unwrap();
        assert_eq!(again.parameters, config.parameters);
        assert_eq!(build("sand", &config).unwrap().state_names().len(), 3); // plastic shear, plastic volumetric, plastic work
    }
}
