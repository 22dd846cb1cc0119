//! Bytes held per particle (`Simulation::bytes_per_particle`, printed by `bench_step` and
//! `axmpm bench`): the schemes differ exactly by their stencil caches and CPDI2's corners, and
//! every scheme stays within issue 16's 400 B per particle (plus the grid).

mod common;
use axmpm_core::config::*;
use axmpm_core::interpolation::{CpGimp, Cpdi2, Linear, ShapeFunction, UGimp};
use axmpm_core::Simulation;
use common::*;
use std::mem::size_of;

fn bytes(shape: ShapeFunctionKind) -> usize {
    let mut cfg = block(FormulationKind::Axisymmetric, shape, [0.0, -9.81], [0.0, 0.0]);
    let mut sand = MaterialConfig::elastic("mohr_coulomb", 1550.0, 1e6, 0.3);
    sand.set("friction_angle", 25.0).set("dilation_angle", 0.0).set("cohesion", 0.0);
    cfg.materials.clear();
    cfg.materials.insert("m".into(), sand);
    Simulation::new(cfg, 1).unwrap().bytes_per_particle()
}

#[test]
fn schemes_differ_by_their_caches_and_corners_and_stay_within_400_bytes() {
    let linear = bytes(ShapeFunctionKind::Linear);
    let ugimp = bytes(ShapeFunctionKind::Ugimp);
    let cpgimp = bytes(ShapeFunctionKind::Cpgimp);
    let cpdi2 = bytes(ShapeFunctionKind::Cpdi2);
    let cache = |n: usize| n as isize;
    let diff = |a: usize, b: usize| a as isize - b as isize;
    assert_eq!(
        diff(ugimp, linear),
        cache(size_of::<<UGimp as ShapeFunction>::Cache>()) - cache(size_of::<<Linear as ShapeFunction>::Cache>())
    );
    assert_eq!(
        diff(cpgimp, linear),
        cache(size_of::<<CpGimp as ShapeFunction>::Cache>()) - cache(size_of::<<Linear as ShapeFunction>::Cache>())
    );
    // CPDI2 also carries its four corners (4 × 2 f64).
    assert_eq!(
        diff(cpdi2, linear),
        64 + cache(size_of::<<Cpdi2 as ShapeFunction>::Cache>()) - cache(size_of::<<Linear as ShapeFunction>::Cache>())
    );
    // The linear scheme: at least position, velocity, F, stress, the step's displacement and
    // its cache (2 + 2 + 5 + 4 + 2 f64).
    assert!(linear >= 15 * 8 + size_of::<<Linear as ShapeFunction>::Cache>(), "{linear}");
    for (name, b) in [("linear", linear), ("uGIMP", ugimp), ("cpGIMP", cpgimp), ("CPDI2", cpdi2)] {
        assert!(b <= 400, "{name}: {b} B per particle");
    }
}
