//! Saturated soil (`solver::saturated`): Terzaghi's one-dimensional consolidation in plane
//! strain and in axisymmetry (a column off the axis between roller walls), against the series
//! solution, and the stable time step at low hydraulic conductivity.
mod common;

use axmpm_core::config::*;
use axmpm_core::solver::saturated::{SaturatedConfig, STANDARD_GRAVITY};
use axmpm_core::Simulation;

/// Skeleton: linear elastic, ν = 0 so that E_oed = E.
const E_OED: f64 = 1.0e7;
const POROSITY: f64 = 0.4;
const K_W: f64 = 2.2e9;
const RHO_W: f64 = 1000.0;
const LOAD: f64 = 1.0e4;
const HEIGHT: f64 = 1.0;

/// Terzaghi with compressible water: c_v = k / (γ_w (1/E_oed + n/K_w)).
fn consolidation_coefficient(k: f64) -> f64 {
    k / (RHO_W * STANDARD_GRAVITY * (1.0 / E_OED + POROSITY / K_W))
}

/// Initial (undrained) excess pressure q (K_w/n)/(K_w/n + E_oed).
fn undrained_pressure() -> f64 {
    LOAD * (K_W / POROSITY) / (K_W / POROSITY + E_OED)
}

/// Mean degree of consolidation U(T_v) = 1 − Σ 2/M² exp(−M² T_v), M = π(2m+1)/2.
fn terzaghi_degree(tv: f64) -> f64 {
    let mut sum = 0.0;
    for m in 0..2000 {
        let big_m = std::f64::consts::PI * (2 * m + 1) as f64 / 2.0;
        sum += 2.0 / (big_m * big_m) * (-big_m * big_m * tv).exp();
    }
    1.0 - sum
}

/// A column of `cells` cells over HEIGHT, one cell wide, base fixed and impermeable, sides
/// rollers (impermeable), top free and drained under LOAD. Axisymmetric: the column spans
/// r = 1 … 1 + h between roller walls.
fn column(formulation: FormulationKind, cells: usize, k: f64) -> Config {
    let h = HEIGHT / cells as f64;
    let axisymmetric = formulation == FormulationKind::Axisymmetric;
    let x0 = if axisymmetric { 1.0 } else { 0.0 };
    let mut cfg = common::block(formulation, ShapeFunctionKind::Linear, [0.0, 0.0], [0.0, 0.0]);
    cfg.materials.insert("m".into(), common::material("linear_elastic", 2650.0, E_OED, 0.0));
    cfg.grid = GridConfig { origin: [0.0, 0.0], extent: [x0 + 3.0 * h, HEIGHT + 2.0 * h], cell_size: h };
    cfg.simulation.flip_fraction = 0.99;
    let mut body = BodyConfig::rectangle("m", [x0, 0.0], [x0 + h, HEIGHT]);
    body.saturated = Some(SaturatedConfig {
        porosity: POROSITY,
        hydraulic_conductivity: k,
        water_bulk_modulus: K_W,
        water_density: RHO_W,
        water_table: None,
        pore_pressure: None,
        surface_load: LOAD,
    });
    cfg.bodies = vec![body];
    cfg.boundaries = BoundariesConfig {
        left: BoundaryCondition::ROLLER,
        right: BoundaryCondition::FREE,
        bottom: BoundaryCondition::FIXED,
        top: BoundaryCondition::FREE,
    };
    let wall = |position, material_side| WallConfig {
        axis: Axis::X,
        position,
        material_side,
        condition: Condition::Roller,
        coefficient: 0.0,
        removal_time: None,
    };
    cfg.walls = if axisymmetric {
        vec![wall(x0, Side::Positive), wall(x0 + h, Side::Negative)]
    } else {
        vec![wall(x0 + h, Side::Negative)]
    };
    cfg
}

/// The volume-weighted mean pore pressure of the particles.
fn mean_pressure(sim: &Simulation) -> f64 {
    let p = sim.particles();
    let volume: f64 = p.volume.iter().sum();
    p.pore_pressure.iter().zip(&p.volume).map(|(p, v)| p * v).sum::<f64>() / volume
}

/// U at each T_v of `tvs` (numerical, from the mean pressure) for a column of `cells` cells.
fn degrees(formulation: FormulationKind, cells: usize, tvs: &[f64]) -> Vec<f64> {
    let k = 1e-3;
    let cv = consolidation_coefficient(k);
    let mut sim = Simulation::new(column(formulation, cells, k), 1).unwrap();
    let u0 = undrained_pressure();
    tvs.iter()
        .map(|&tv| {
            sim.advance(tv * HEIGHT * HEIGHT / cv, u64::MAX).unwrap();
            1.0 - mean_pressure(&sim) / u0
        })
        .collect()
}

#[test]
fn terzaghi_degree_of_consolidation_in_both_formulations() {
    // U = 0.2, 0.4, 0.5, 0.6, 0.8, 0.9.
    let tvs = [0.0314, 0.1257, 0.1967, 0.2864, 0.5672, 0.8481];
    for formulation in [FormulationKind::PlaneStrain, FormulationKind::Axisymmetric] {
        let mut errors = Vec::new();
        for cells in [10, 20] {
            let u = degrees(formulation, cells, &tvs);
            let e = u.iter().zip(&tvs).map(|(u, &tv)| (u - terzaghi_degree(tv)).abs()).fold(0.0, f64::max);
            println!("{formulation:?} {cells} cells: U {u:?}, max |ΔU| {e:.4}");
            errors.push(e);
        }
        assert!(errors[1] < 0.02, "{formulation:?}: {errors:?}");
        assert!(errors[1] < errors[0], "{formulation:?}: the error shrinks with the mesh: {errors:?}");
    }
}
