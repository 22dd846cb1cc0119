//! Scenario builders shared by the engine's integration tests.
#![allow(dead_code)]

use axmpm_core::config::*;
use axmpm_core::Simulation;
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
            xpic_order: 1,
            experimental: false,
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

/// A rigid body's table from JSON (the scenario's keys).
pub fn rigid_body_table(v: serde_json::Value) -> RigidBodyConfig {
    serde_json::from_value(v).unwrap()
}

/// Total momentum of the material (whole body: × 2π in axisymmetry), kg m/s.
pub fn material_momentum(sim: &axmpm_core::Simulation) -> [f64; 2] {
    let total = sim.total_factor();
    let p = sim.particles();
    let mut m = [0.0; 2];
    for i in 0..p.len() {
        m[0] += total * p.mass[i] * p.velocity[i][0];
        m[1] += total * p.mass[i] * p.velocity[i][1];
    }
    m
}

/// A Tresca clay layer (s_u = 10 kPa, E = 3 MPa, ν = 0.45) [0, 2] × [0, 1.2] m under gravity
/// −10 m/s², axisymmetric uGIMP, FLIP 0.99, roller at r = 2 m, fixed base: the ground of the
/// footing tests (add the footing).
pub fn clay_layer() -> Config {
    let mut cfg = block(FormulationKind::Axisymmetric, ShapeFunctionKind::Ugimp, [0.0, -10.0], [0.0, 0.0]);
    let mut clay = material("mohr_coulomb", 1800.0, 3e6, 0.45);
    clay.set("friction_angle", 0.0);
    clay.set("cohesion", 10e3);
    cfg.materials.insert("m".into(), clay);
    cfg.bodies[0].set_rectangle([0.0, 0.0], [2.0, 1.2]);
    cfg.boundaries.right = BoundaryCondition::ROLLER;
    cfg.boundaries.bottom = BoundaryCondition::FIXED;
    cfg.simulation.flip_fraction = 0.99;
    cfg
}

/// The in-situ stress of the cone penetration set-up, Pa (compression).
pub const S_V0: f64 = 66e3;

/// Tresca clay (s_u = 18 kPa, E = 5.4 MPa, ν = 0.49) of the given density.
pub fn tresca(density: f64) -> MaterialConfig {
    let mut m = material("mohr_coulomb", density, 5.4e6, 0.49);
    m.set("friction_angle", 0.0).set("cohesion", 18e3);
    m
}

/// A weightless Tresca layer 0.5 m × 0.5 m at σ_v = σ_h = −66 kPa (under a 66 kPa surcharge
/// `q` when `surcharge`), rollers on its sides and base, h = 0.05 m, a fixed Δt = 5e-5 s.
pub fn in_situ_layer(formulation: FormulationKind, surcharge: bool) -> Config {
    let mut cfg = block(formulation, ShapeFunctionKind::Cpgimp, [0.0, 0.0], [0.0, 0.0]);
    cfg.simulation.time_step = 5e-5;
    cfg.simulation.volumetric_averaging = VolumetricAveraging::Cell;
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [0.5, 0.75], cell_size: 0.05, follow: None, experimental: false };
    cfg.materials = BTreeMap::from([("clay".to_string(), tresca(1800.0))]);
    let mut body = BodyConfig::rectangle("clay", [0.0, 0.0], [0.5, 0.5]);
    body.initial_stress = InitialStress::Given([-S_V0, -S_V0, -S_V0, 0.0]);
    cfg.bodies = vec![body];
    cfg.boundaries.left = BoundaryCondition::ROLLER;
    cfg.boundaries.right = BoundaryCondition::ROLLER;
    cfg.boundaries.bottom = BoundaryCondition::ROLLER;
    if surcharge {
        cfg.surcharges = vec![SurchargeConfig { name: Some("q".into()), pressure: S_V0, level: 0.5, range: None }];
    }
    cfg
}

/// Largest |σ_ii + 66 kPa| / 66 kPa over the particles and the three normal components.
pub fn in_situ_stress_error(sim: &Simulation) -> f64 {
    sim.particles().stress.iter().flat_map(|s| s[..3].iter().map(|c| (c + S_V0).abs() / S_V0)).fold(0.0, f64::max)
}

/// Every per-particle array the run produces, as bits.
pub fn fingerprint(sim: &Simulation) -> Vec<u64> {
    let p = sim.particles();
    let mut bits: Vec<u64> = Vec::new();
    bits.extend(p.position.iter().flatten().map(|v| v.to_bits()));
    bits.extend(p.velocity.iter().flatten().map(|v| v.to_bits()));
    bits.extend(p.stress.iter().flatten().map(|v| v.to_bits()));
    bits.extend(p.deformation_gradient.iter().flatten().map(|v| v.to_bits()));
    bits.extend(p.volume.iter().map(|v| v.to_bits()));
    bits.extend(p.state.iter().map(|v| v.to_bits()));
    bits.extend(p.corners.iter().flatten().flatten().map(|v| v.to_bits()));
    bits.extend(sim.grid_fields().mass.iter().map(|v| v.to_bits()));
    bits.extend(sim.grid_fields().velocity.iter().flatten().map(|v| v.to_bits()));
    bits
}
