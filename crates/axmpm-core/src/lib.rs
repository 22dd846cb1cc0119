//! # axmpm-core
//!
//! Explicit material point method for large-deformation geomechanics, in plane strain and in
//! axisymmetry (Sulsky & Schreyer 1996), with the original MPM, uGIMP, cpGIMP and CPDI2
//! interpolation families. See `docs/architecture.md` for the layout and `docs/physics.md`
//! for the equations.

pub mod config;
pub mod constraint;
pub mod formulation;
pub mod geometry;
pub mod grid;
pub mod interpolation;
pub mod material;
pub mod particles;
pub mod setup;
pub mod simulation;
pub mod solver;

pub use config::Config;
pub use simulation::{Simulation, SimulationFailure};

/// What the engine offers, from its registries (each list exists once): `formulations`,
/// `interpolation_schemes`, `material_models` and `region_shapes`, each a list of the names
/// a scenario selects them by.
pub fn catalogue() -> std::collections::BTreeMap<&'static str, Vec<&'static str>> {
    use config::{FormulationKind, ShapeFunctionKind};
    [
        ("formulations", FormulationKind::ALL.iter().map(|f| f.name()).collect()),
        ("interpolation_schemes", ShapeFunctionKind::ALL.iter().map(|s| s.name()).collect()),
        ("material_models", material::model_names()),
        ("region_shapes", geometry::shape_names()),
    ]
    .into_iter()
    .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_lists_every_registry_under_the_names_scenarios_use() {
        let c = catalogue();
        assert_eq!(c["formulations"], ["plane_strain", "axisymmetric"]);
        assert_eq!(c["interpolation_schemes"], ["linear", "ugimp", "cpgimp", "cpdi2"]);
        assert_eq!(c["material_models"], ["linear_elastic", "neo_hookean", "mohr_coulomb", "von_mises", "granular_fluidity", "drucker_prager"]);
        assert_eq!(c["region_shapes"], ["rectangle", "polygon"]);
        // The names are the ones serde reads in a scenario.
        for f in config::FormulationKind::ALL {
            assert_eq!(serde_json::to_string(&f).unwrap(), format!("\"{}\"", f.name()));
        }
        for s in config::ShapeFunctionKind::ALL {
            assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{}\"", s.name()));
        }
    }
}
