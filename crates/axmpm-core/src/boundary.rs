//! Velocity constraints on grid nodes: the four grid faces and straight rigid walls.
//!
//! A constraint acts on every node on its line and on the nodes beyond it (outside the
//! material side), so particle domains that reach past a wall (GIMP, CPDI) cannot drag
//! material through it. Conditions (PHYSICS.md; Bardenhagen et al. 2001 for friction):
//! - `roller`: normal velocity zero (bilateral), tangential free;
//! - `fixed`: both components zero;
//! - `friction`: no penetration (unilateral) with Coulomb friction: when the node moves into
//!   the wall with normal speed v_n > 0, v_n is removed and the tangential speed is reduced by
//!   μ v_n (never reversed); a node moving away is free.
//! In axisymmetry the axis r = 0 is always a roller (v_r = 0).

use crate::config::{Axis, BoundariesConfig, BoundaryCondition, Condition, Side, WallConfig};
use crate::grid::GridGeometry;

#[derive(Clone, Copy, Debug)]
pub struct NodeConstraint {
    pub node: u32,
    /// Component normal to the wall (0: x/r, 1: y/z).
    pub axis: u8,
    /// +1 when the wall lies on the positive side of the material (outward normal +axis).
    pub outward: f64,
    pub condition: Condition,
    pub coefficient: f64,
    /// Time at which the wall disappears (`f64::INFINITY` = never).
    pub removal_time: f64,
}

impl NodeConstraint {
    #[inline(always)]
    pub fn apply(&self, v: &mut [f64; 2]) {
        let a = self.axis as usize;
        let t = 1 - a;
        match self.condition {
            Condition::Free => {}
            Condition::Roller => v[a] = 0.0,
            Condition::Fixed => *v = [0.0, 0.0],
            Condition::Friction => {
                let vn = v[a] * self.outward;
                if vn > 0.0 {
                    v[a] = 0.0;
                    let vt = v[t];
                    let reduced = (vt.abs() - self.coefficient * vn).max(0.0);
                    v[t] = reduced.copysign(vt);
                }
            }
        }
    }
}

/// All node constraints of a run, in a fixed order (faces left, right, bottom, top, then walls).
#[derive(Clone, Debug, Default)]
pub struct Constraints {
    pub list: Vec<NodeConstraint>,
}

impl Constraints {
    pub fn new(grid: &GridGeometry, faces: &BoundariesConfig, walls: &[WallConfig], axisymmetric: bool) -> Self {
        let mut list = Vec::new();
        let [nx, ny] = grid.nodes;
        let left = if axisymmetric { BoundaryCondition::ROLLER } else { faces.left };
        let mut face = |bc: BoundaryCondition, axis: u8, outward: f64, nodes: &mut dyn Iterator<Item = usize>| {
            if bc.condition == Condition::Free {
                return;
            }
            for node in nodes {
                list.push(NodeConstraint {
                    node: node as u32,
                    axis,
                    outward,
                    condition: bc.condition,
                    coefficient: bc.coefficient,
                    removal_time: f64::INFINITY,
                });
            }
        };
        face(left, 0, -1.0, &mut (0..ny).map(|j| grid.node_index(0, j)));
        face(faces.right, 0, 1.0, &mut (0..ny).map(|j| grid.node_index(nx - 1, j)));
        face(faces.bottom, 1, -1.0, &mut (0..nx).map(|i| grid.node_index(i, 0)));
        face(faces.top, 1, 1.0, &mut (0..nx).map(|i| grid.node_index(i, ny - 1)));

        let tol = 1e-6 * grid.cell_size;
        for wall in walls {
            if wall.condition == Condition::Free {
                continue;
            }
            let a = match wall.axis {
                Axis::X => 0usize,
                Axis::Y => 1usize,
            };
            let outward = match wall.material_side {
                Side::Negative => 1.0,
                Side::Positive => -1.0,
            };
            for node in 0..grid.num_nodes() {
                let x = grid.node_position(node)[a];
                let beyond = match wall.material_side {
                    Side::Negative => x >= wall.position - tol,
                    Side::Positive => x <= wall.position + tol,
                };
                if beyond {
                    list.push(NodeConstraint {
                        node: node as u32,
                        axis: a as u8,
                        outward,
                        condition: wall.condition,
                        coefficient: wall.coefficient,
                        removal_time: wall.removal_time.unwrap_or(f64::INFINITY),
                    });
                }
            }
        }
        Self { list }
    }

    /// Applies every constraint still in place at `time` to a nodal velocity field.
    pub fn apply(&self, time: f64, velocity: &mut [[f64; 2]]) {
        for c in &self.list {
            if time < c.removal_time {
                c.apply(&mut velocity[c.node as usize]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(condition: Condition, mu: f64) -> NodeConstraint {
        NodeConstraint { node: 0, axis: 1, outward: -1.0, condition, coefficient: mu, removal_time: f64::INFINITY }
    }

    #[test]
    fn friction_base_by_hand() {
        // Base (outward normal −y). Moving down at 1 m/s and sideways at 2 m/s with μ = 0.5:
        // normal removed, tangential 2 − 0.5·1 = 1.5.
        let mut v = [2.0, -1.0];
        c(Condition::Friction, 0.5).apply(&mut v);
        assert_eq!(v, [1.5, 0.0]);
        // Sliding stops, never reverses.
        let mut v = [-0.2, -1.0];
        c(Condition::Friction, 0.5).apply(&mut v);
        assert_eq!(v, [0.0, 0.0]);
        // Leaving the wall: untouched.
        let mut v = [2.0, 1.0];
        c(Condition::Friction, 0.5).apply(&mut v);
        assert_eq!(v, [2.0, 1.0]);
    }

    #[test]
    fn roller_and_fixed() {
        let mut v = [2.0, -1.0];
        c(Condition::Roller, 0.0).apply(&mut v);
        assert_eq!(v, [2.0, 0.0]);
        c(Condition::Fixed, 0.0).apply(&mut v);
        assert_eq!(v, [0.0, 0.0]);
    }

    #[test]
    fn axis_is_a_roller_and_walls_reach_beyond_their_line() {
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let faces = BoundariesConfig::default();
        let wall = WallConfig {
            axis: Axis::X,
            position: 0.5,
            material_side: Side::Negative,
            condition: Condition::Roller,
            coefficient: 0.0,
            removal_time: Some(0.1),
        };
        let cs = Constraints::new(&g, &faces, &[wall], true);
        // 5 axis nodes + 3 columns (x = 0.5, 0.75, 1.0) of 5 nodes.
        assert_eq!(cs.list.len(), 5 + 15);
        let mut v = vec![[1.0, 1.0]; g.num_nodes()];
        cs.apply(0.0, &mut v);
        assert_eq!(v[g.node_index(0, 2)], [0.0, 1.0]);
        assert_eq!(v[g.node_index(1, 2)], [1.0, 1.0]);
        assert_eq!(v[g.node_index(2, 2)], [0.0, 1.0]);
        let mut v = vec![[1.0, 1.0]; g.num_nodes()];
        cs.apply(0.2, &mut v); // wall removed, axis stays
        assert_eq!(v[g.node_index(2, 2)], [1.0, 1.0]);
        assert_eq!(v[g.node_index(0, 2)], [0.0, 1.0]);
    }
}
