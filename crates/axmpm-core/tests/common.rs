//! Scenario builders shared by the engine's integration tests.
#![allow(dead_code)]

use axmpm_core::config::*;
use std::collections::BTreeMap;

pub fn material(model: &str, density: f64, e: f64, nu: f64) -> MaterialConfig {
    MaterialConfig::elastic(model, density, e, nu)
}

/// A block of `material` in a grid of `cells` × `cells` cells of size 0.1, no boundary conditions.
pub fn block(
    formulation: FormulationKind,
    shape: ShapeFunctionKind,
    gravity: [f64; 2],
    velocity: [f64; 2],
) -> Config {
    let mut materials = BTreeMap::new();
    materials.insert("m".to_string(), material("linear_elastic", 1000.0, 1e6, 0.3));
    Config {
        simulation: SimulationConfig {
            formulation,
            shape_function: shape,
            end_time: 1.0,
            output_interval: 0.1,
            gravity,
            gravity_ramp_time: 0.0,
            time_step: 0.0,
            cfl: 0.4,
            update_scheme: UpdateScheme::Musl,
            flip_fraction: 1.0,
            damping: 0.0,
            volumetric_averaging: VolumetricAveraging::None,
            extra: Default::default(),
        },
        grid: GridConfig { origin: [0.0, 0.0], extent: [2.0, 2.0], cell_size: 0.1, follow: None, experimental: false },
        materials,
        bodies: vec![BodyConfig { velocity, ..BodyConfig::rectangle("m", [0.6, 0.6], [1.0, 1.2]) }],
        boundaries: BoundariesConfig::default(),
        walls: vec![],
        rigid_bodies: vec![],
        drainage: Default::default(),
        surcharges: Vec::new(),
        extra: Default::default(),
    }
}

pub const ALL_SHAPES: [ShapeFunctionKind; 4] =
    [ShapeFunctionKind::Linear, ShapeFunctionKind::Ugimp, ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2];
pub const ALL_FORMULATIONS: [FormulationKind; 2] = [FormulationKind::PlaneStrain, FormulationKind::Axisymmetric];
