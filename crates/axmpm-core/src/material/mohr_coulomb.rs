//! Placeholder: Mohr–Coulomb is being implemented (issue #4); selecting it is an error for now.

use super::{Kinematics, Material};
use crate::config::MaterialConfig;
use crate::particles::Stress;

pub struct MohrCoulomb;

impl MohrCoulomb {
    pub fn from_config(_c: &MaterialConfig) -> Result<Self, String> {
        Err("mohr_coulomb is not available yet".into())
    }
}

impl Material for MohrCoulomb {
    fn model(&self) -> &'static str {
        "mohr_coulomb"
    }
    fn density(&self) -> f64 {
        0.0
    }
    fn wave_speed(&self) -> f64 {
        0.0
    }
    fn update_stress(&self, _stress: &mut Stress, _state: &mut [f64], _k: &Kinematics) {}
}
