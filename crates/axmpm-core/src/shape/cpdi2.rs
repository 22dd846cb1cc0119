//! Placeholder: being implemented (issue #3). Falls back to the linear hat so the crate builds.

use super::{ShapeFunction, Stencil};
use crate::grid::GridGeometry;
use crate::particles::Particles;

pub struct Cpdi2;

impl ShapeFunction for Cpdi2 {
    const NAME: &'static str = "cpdi2";

    fn stencil(grid: &GridGeometry, particles: &Particles, p: usize, axisymmetric: bool, out: &mut Stencil) {
        super::Linear::stencil(grid, particles, p, axisymmetric, out)
    }
}
