//! The four faces of the grid: a condition on the nodes of one grid line.

use super::{ConstrainedNodes, Constraint, NodalContext, NodeCondition};
use crate::config::{BoundariesConfig, BoundaryCondition, Condition};
use crate::grid::GridGeometry;

/// One face of the grid with a roller, fixed or friction condition.
#[derive(Clone, Debug)]
pub struct GridFace {
    /// "left", "right", "bottom" or "top".
    pub name: &'static str,
    pub line: ConstrainedNodes,
}

impl GridFace {
    /// The faces that are not free, in the order left, right, bottom, top. In axisymmetry the
    /// left face is the axis ([`super::SymmetryAxis`]) whatever `faces.left` says.
    pub fn all(grid: &GridGeometry, faces: &BoundariesConfig, axisymmetric: bool) -> Vec<GridFace> {
        let [nx, ny] = grid.nodes;
        let column = |i: usize| (0..ny).map(|j| grid.node_index(i, j) as u32).collect::<Vec<_>>();
        let row = |j: usize| (0..nx).map(|i| grid.node_index(i, j) as u32).collect::<Vec<_>>();
        let left = if axisymmetric { BoundaryCondition::FREE } else { faces.left };
        [
            ("left", left, 0u8, -1.0, column(0)),
            ("right", faces.right, 0, 1.0, column(nx - 1)),
            ("bottom", faces.bottom, 1, -1.0, row(0)),
            ("top", faces.top, 1, 1.0, row(ny - 1)),
        ]
        .into_iter()
        .filter(|(_, bc, ..)| bc.condition != Condition::Free)
        .map(|(name, bc, axis, outward, nodes)| GridFace {
            name,
            line: ConstrainedNodes::new(
                nodes,
                NodeCondition { axis, outward, condition: bc.condition, coefficient: bc.coefficient },
            ),
        })
        .collect()
    }
}

impl Constraint for GridFace {
    fn name(&self) -> &str {
        self.name
    }

    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool) {
        self.line.correct(context, velocity, record);
    }

    fn apply_remapped(&mut self, _context: &NodalContext, velocity: &mut [[f64; 2]]) {
        self.line.correct_remapped(velocity);
    }

    fn take_impulse(&mut self) -> [f64; 2] {
        self.line.take_impulse()
    }

    fn dissipated_energy(&self) -> [f64; 2] {
        self.line.dissipated_energy()
    }
}
