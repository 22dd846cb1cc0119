//! Scenario builders shared by the engine's integration tests.
#![allow(dead_code)]

use axmpm_core::config::*;
use std::collections::BTreeMap;

pub fn material(model: &str, density: f64, e: f64, nu: f64) -> MaterialConfig {
    MaterialConfig {
        model: model.into(),
        density,
        youngs_modulus: e,
        poisson_ratio: nu,
        friction_angle: None,
        dilation_angle: None,
        cohesion: None,
        tension_cutoff: None,
        recompaction: None,
        extra: Default::default(),
    }
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
        grid: GridConfig { origin: [0.0, 0.0], extent: [2.0, 2.0], cell_size: 0.1 },
        materials,
        bodies: vec![BodyConfig {
            name: None,
            material: "m".into(),
            shape: "rectangle".into(),
            min: [0.6, 0.6],
            max: [1.0, 1.2],
            particles_per_cell: 2,
            velocity,
            initial_stress: InitialStress::Zero,
            k0: None,
        }],
        boundaries: BoundariesConfig::default(),
        walls: vec![],
        extra: Default::default(),
    }
}

pub const ALL_SHAPES: [ShapeFunctionKind; 4] =
    [ShapeFunctionKind::Linear, ShapeFunctionKind::Ugimp, ShapeFunctionKind::Cpgimp, ShapeFunctionKind::Cpdi2];
pub const ALL_FORMULATIONS: [FormulationKind; 2] = [FormulationKind::PlaneStrain, FormulationKind::Axisymmetric];
