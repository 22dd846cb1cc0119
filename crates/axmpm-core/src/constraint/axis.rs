//! The symmetry axis r = 0 of axisymmetric runs: a roller, v_r = 0 (no reaction reported: the
//! radial "force" on the axis is the hoop stress of the body of revolution, not a support).

use super::{Constraint, NodalContext, NodeCondition};
use crate::config::Condition;
use crate::grid::GridGeometry;

#[derive(Clone, Debug)]
pub struct SymmetryAxis {
    pub nodes: Vec<u32>,
}

const ROLLER_ON_AXIS: NodeCondition =
    NodeCondition { axis: 0, outward: -1.0, condition: Condition::Roller, coefficient: 0.0 };

impl SymmetryAxis {
    /// The nodes of the first grid column (the grid of an axisymmetric run starts at r = 0).
    pub fn new(grid: &GridGeometry) -> Self {
        Self { nodes: (0..grid.nodes[1]).map(|j| grid.node_index(0, j) as u32).collect() }
    }
}

impl Constraint for SymmetryAxis {
    fn name(&self) -> &str {
        "axis"
    }

    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], _record: bool) {
        ROLLER_ON_AXIS.correct_nodes(&self.nodes, context, velocity, false, &mut [0.0; 2]);
    }

    fn reports_reaction(&self) -> bool {
        false
    }
}
