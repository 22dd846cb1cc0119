//! A condition on the nodes of a grid line: the four faces of the grid, and straight rigid walls
//! on a grid line inside it (acting on the nodes of their line and beyond, away from the material
//! side, so particle domains that reach past a wall cannot drag material through it), optionally
//! removed at a given time (column collapse: the gate is lifted). The two differ only in the
//! nodes they pick and in when they act.

use super::{ConstrainedNodes, Constraint, HeldNodes, NodalContext, NodeCondition};
use crate::config::{Axis, BoundariesConfig, BoundaryCondition, Condition, Side, WallConfig};
use crate::grid::GridGeometry;

#[derive(Clone, Debug)]
pub struct LineConstraint {
    /// "left", "right", "bottom", "top" for the faces; `wall_i` for `walls[i]`.
    pub name: String,
    pub line: ConstrainedNodes,
    /// Time at which the line stops acting (`f64::INFINITY` = never).
    pub removal_time: f64,
}

impl LineConstraint {
    /// The faces that are not free, in the order left, right, bottom, top. In axisymmetry the
    /// left face is the axis ([`super::SymmetryAxis`]) whatever `faces.left` says.
    ///
    /// On a grid that moves along y (`moving_grid`, `grid.follow`) the scenario's bottom face
    /// y_0 lies between the grid's first two node rows (y_0 − s and y_0 − s + h, 0 ≤ s < h), and
    /// the bottom and top faces act on both: a condition on the outer row alone would let the
    /// material over the face go (the lowest particles lose the outer row's support as s grows,
    /// and a nearly incompressible layer on rollers then sinks as a block), whereas the two rows
    /// hold it and constrain at most one cell of material that a fixed or roller face keeps
    /// nearly at rest anyway.
    pub fn faces(grid: &GridGeometry, faces: &BoundariesConfig, axisymmetric: bool, moving_grid: bool) -> Vec<Self> {
        let [nx, ny] = grid.nodes;
        let column = |i: usize| (0..ny).map(|j| grid.node_index(i, j) as u32).collect::<Vec<_>>();
        let rows = |js: &[usize]| js.iter().flat_map(|&j| (0..nx).map(move |i| grid.node_index(i, j) as u32)).collect::<Vec<_>>();
        let (bottom, top) = if moving_grid { (rows(&[0, 1]), rows(&[ny - 2, ny - 1])) } else { (rows(&[0]), rows(&[ny - 1])) };
        let left = if axisymmetric { BoundaryCondition::FREE } else { faces.left };
        [
            ("left", left, 0u8, -1.0, column(0)),
            ("right", faces.right, 0, 1.0, column(nx - 1)),
            ("bottom", faces.bottom, 1, -1.0, bottom),
            ("top", faces.top, 1, 1.0, top),
        ]
        .into_iter()
        .filter(|(_, bc, ..)| bc.condition != Condition::Free)
        .map(|(name, bc, axis, outward, nodes)| Self {
            name: name.to_string(),
            line: ConstrainedNodes::new(
                nodes,
                NodeCondition { axis, outward, condition: bc.condition, coefficient: bc.coefficient },
            ),
            removal_time: f64::INFINITY,
        })
        .collect()
    }

    /// The wall of `config`, or `None` for a free wall (it constrains nothing).
    pub fn wall(name: String, grid: &GridGeometry, config: &WallConfig) -> Option<Self> {
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

    /// Whether the line still acts: before its removal time (removed at that time exactly).
    fn stands(&self, context: &NodalContext) -> bool {
        context.time < self.removal_time
    }
}

impl Constraint for LineConstraint {
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

    fn book_impulse(&mut self, impulse: [f64; 2]) {
        self.line.book_impulse(impulse);
    }

    fn held_nodes(&self) -> Option<HeldNodes<'_>> {
        // A wall that is lifted during the run is not impermeable (saturated soil) and would
        // take over bookings it no longer makes.
        if self.removal_time.is_finite() {
            return None;
        }
        let c = self.line.condition;
        let directions = match c.condition {
            Condition::Free => return None,
            Condition::Fixed => [true; 2],
            Condition::Roller | Condition::Friction => [c.axis == 0, c.axis == 1],
        };
        Some(HeldNodes { nodes: &self.line.nodes, directions, bilateral: c.condition != Condition::Friction })
    }

    fn dissipated_energy(&self) -> [f64; 2] {
        self.line.dissipated_energy()
    }
}
