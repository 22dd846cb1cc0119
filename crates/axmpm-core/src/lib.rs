//! # axmpm-core
//!
//! Explicit material point method for large-deformation geomechanics, in plane strain and in
//! axisymmetry (Sulsky & Schreyer 1996), with the original MPM, uGIMP, cpGIMP and CPDI2
//! interpolation families. See `docs/architecture.md` and `PHYSICS.md` for the equations.

pub mod boundary;
pub mod config;
pub mod constraint;
pub mod formulation;
pub mod geometry;
pub mod grid;
pub mod material;
pub mod particles;
pub mod setup;
pub mod shape;
pub mod simulation;
pub mod solver;

pub use config::Config;
pub use simulation::{Simulation, SimulationFailure};
