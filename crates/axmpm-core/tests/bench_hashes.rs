//! The results of the `bench_step` scenario, pinned bit for bit for the four interpolation
//! schemes in both formulations: a change that is meant to leave the results alone (a refactor,
//! a speed-up, a new option that is off by default) must leave these eight hashes equal.
//!
//! These are regression pins, not verification: they prove "unchanged", not "correct".
//!
//! Re-pinning (only for a change that is meant to change results, e.g. a new summation order or
//! a physics fix): run, for each SCHEME in linear ugimp cpgimp cpdi2 and FORMULATION in
//! axisymmetric plane_strain,
//!
//! `cargo run --release --example bench_step -- SCHEME FORMULATION 1 20 2 0.001`
//!
//! copy the printed `hash=` values into `PINNED` below, and state in CHANGELOG.md why the results
//! changed, with the old and new hashes and the verification tables re-run.
#[path = "../examples/support/bench_case.rs"]
mod bench_case;
use axmpm_core::Simulation;

/// (scheme, formulation, hash of every particle array after 2 + 20 steps at 1 mm cells, 1 thread).
const PINNED: [(&str, &str, u64); 8] = [
    ("linear", "axisymmetric", 0xe5db34ea389811bd),
    ("linear", "plane_strain", 0x71f5833f2631b89d),
    ("ugimp", "axisymmetric", 0x6329aca7b13d17e1),
    ("ugimp", "plane_strain", 0xa92df5ab7107486d),
    ("cpgimp", "axisymmetric", 0x2df720a7664156a2),
    ("cpgimp", "plane_strain", 0x0118868c971430cb),
    ("cpdi2", "axisymmetric", 0xa8d7d58664adf856),
    ("cpdi2", "plane_strain", 0x57e46d5099cfcee1),
];

#[test]
fn the_bench_step_results_are_unchanged_bit_for_bit() {
    let mut changed = Vec::new();
    for (scheme, formulation, pinned) in PINNED {
        let json = bench_case::scenario(formulation, scheme, 0.001, "mohr_coulomb");
        let mut sim = Simulation::from_json(&json, 1).unwrap();
        // The benchmark's warm-up and timed steps.
        assert_eq!(sim.advance(1e9, 2).unwrap(), 2);
        assert_eq!(sim.advance(1e9, 20).unwrap(), 20);
        let h = bench_case::result_hash(&sim);
        if h != pinned {
            changed.push(format!("{scheme} {formulation}: pinned {pinned:016x}, now {h:016x}"));
        }
    }
    assert!(changed.is_empty(), "bench_step results changed (see the re-pin procedure in this file):\n{}", changed.join("\n"));
}
