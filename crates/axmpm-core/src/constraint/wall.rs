//! A straight rigid wall on a grid line inside the grid, acting on the nodes of its line and
//! beyond (away from the material side), optionally removed at a given time (column collapse:
//! the gate is lifted).

use super::{ConstrainedNodes, Constraint, NodalContext, NodeCondition};
use crate::config::{Axis, Condition, Side, WallConfig};
use crate::grid::GridGeometry;

#[derive(Clone, Debug)]
pub struct Wall {
    pub name: String,
    pub line: ConstrainedNodes,
    /// Time at which the wall disappears (`f64::INFINITY` = never).
    pub removal_time: f64,
}

impl Wall {
    /// The wall of `config`, or `None` for a free wall (it constrains nothing).
    pub fn new(name: String, grid: &GridGeometry, config: &WallConfig) -> Option<Self> {
        if config.condition == Condition::Free {
            return None;
        }
        let axis = match config.axis {
            Axis::X => 0usize,
            Axis::Y => 1usize,
        };
        let outward = match config.material_side {
            Side::Negative => 1.0,
            Side::Positive => -1.0,
        };
        // Nodes within 1e-6 h of the wall line count as on it.
        let tol = 1e-6 * grid.cell_size;
        let nodes = (0..grid.num_nodes())
            .filter(|&node| {
                let x = grid.node_position(node)[axis];
                match config.material_side {
                    Side::Negative => x >= config.position - tol,
                    Side::Positive => x <= config.position + tol,
                }
            })
            .map(|node| node as u32)
            .collect();
        let condition =
            NodeCondition { axis: axis as u8, outward, condition: config.condition, coefficient: config.coefficient };
        Some(Self {
            name,
            line: ConstrainedNodes::new(nodes, condition),
            removal_time: config.removal_time.unwrap_or(f64::INFINITY),
        })
    }
}

impl Wall {
    /// Whether the wall still acts: before its removal time (removed at that time exactly).
    fn stands(&self, context: &NodalContext) -> bool {
        context.time < self.removal_time
    }
}

impl Constraint for Wall {
    fn name(&self) -> &str {
        &self.name
    }

    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool) {
        if self.stands(context) {
            self.line.correct(context, velocity, record);
        }
    }

    fn apply_remapped(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]]) {
        if self.stands(context) {
            self.line.correct_remapped(velocity);
        }
    }

    fn take_impulse(&mut self) -> [f64; 2] {
        self.line.take_impulse()
    }

    fn dissipated_energy(&self) -> [f64; 2] {
        self.line.dissipated_energy()
    }
}
