//! The largest stable time step of the saturated (two-phase) step against the hydraulic
//! conductivity k: a saturated column (H = 1 m, 10 cells, E_oed = 10 MPa, n = 0.4,
//! K_w = 2.2 GPa) under a step load, run for `steps` steps at Courant numbers c_u Δt/h
//! (c_u the undrained P-wave speed) found by bisection; stable = no failure and the pore
//! pressure stays below 5 q. Prints one row per k with the explicit-drag limit for comparison
//! (docs/physics.md, "Saturated soil").
//!
//! `cargo run --release --example saturated_time_step -- [STEPS]` (default 3000).

use axmpm_core::solver::saturated::STANDARD_GRAVITY;
use axmpm_core::Simulation;

const CELLS: usize = 10;
const LOAD: f64 = 1.0e4;
const E_OED: f64 = 1.0e7;
const N: f64 = 0.4;
const K_W: f64 = 2.2e9;
const RHO_W: f64 = 1000.0;
const RHO_S: f64 = 2650.0;

fn scenario(k: f64, dt: f64) -> String {
    let h = 1.0 / CELLS as f64;
    format!(
        r#"{{
  "simulation": {{"formulation": "plane_strain", "shape_function": "linear", "end_time": 1.0, "output_interval": 1.0,
                 "gravity": [0.0, 0.0], "time_step": {dt:e}, "flip_fraction": 0.99}},
  "grid": {{"origin": [0.0, 0.0], "extent": [{gx}, {gy}], "cell_size": {h}}},
  "materials": {{"m": {{"model": "linear_elastic", "density": {RHO_S}, "youngs_modulus": {E_OED}, "poisson_ratio": 0.0}}}},
  "bodies": [{{"material": "m", "min": [0.0, 0.0], "max": [{h}, 1.0],
              "saturated": {{"porosity": {N}, "hydraulic_conductivity": {k:e}, "water_bulk_modulus": {K_W}, "surface_load": {LOAD}}}}}],
  "boundaries": {{"left": {{"condition": "roller"}}, "bottom": {{"condition": "fixed"}}}},
  "walls": [{{"axis": "x", "position": {h}, "material_side": "negative", "condition": "roller"}}]
}}"#,
        gx = 3.0 * h,
        gy = 1.2,
    )
}

fn stable(k: f64, dt: f64, steps: u64) -> bool {
    let mut sim = Simulation::from_json(&scenario(k, dt), 1).expect("valid scenario");
    if sim.advance(f64::INFINITY, steps).is_err() {
        return false;
    }
    sim.particles().pore_pressure.iter().all(|p| p.abs() < 5.0 * LOAD)
}

fn main() {
    let steps: u64 = std::env::args().nth(1).map_or(3000, |s| s.parse().expect("STEPS"));
    let h = 1.0 / CELLS as f64;
    let rho_sat = (1.0 - N) * RHO_S + N * RHO_W;
    let c_u = ((E_OED + K_W / N) / rho_sat).sqrt();
    let auto = Simulation::from_json(&scenario(1e-3, 0.0), 1).unwrap().dt();
    println!("undrained wave speed c_u = {c_u:.1} m/s; default step (cfl 0.4) = {auto:.3e} s, Courant {:.3}", auto * c_u / h);
    println!("| k (m/s) | largest stable Courant c_u Δt/h | Δt (s) | explicit drag limit (s) |");
    println!("|---|---|---|---|");
    for e in 2..=9 {
        let k = 10f64.powi(-e);
        let (mut lo, mut hi) = (0.05, 2.0);
        assert!(stable(k, lo * h / c_u, steps), "k = {k}: unstable at Courant {lo}");
        while hi - lo > 0.005 {
            let mid = 0.5 * (lo + hi);
            if stable(k, mid * h / c_u, steps) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // The explicit drag's limit (Δt_l = (2/ω)(√(ξ² + 1) − ξ), ω = (2/h)√(K_w/ρ_w),
        // ξ = n g/(2 k ω)).
        let omega = 2.0 / h * (K_W / RHO_W).sqrt();
        let xi = N * STANDARD_GRAVITY / (2.0 * k * omega);
        let explicit = 2.0 / omega * ((xi * xi + 1.0).sqrt() - xi);
        println!("| 1e-{e} | {lo:.3} | {:.3e} | {explicit:.2e} |", lo * h / c_u);
    }
}
