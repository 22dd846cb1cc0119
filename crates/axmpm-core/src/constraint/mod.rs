//! Velocity constraints on grid nodes.
//!
//! LOCAL COPY of the trait fixed in INTERFACES.md (branch `ssi`, issue #13): the layout issue
//! (#12, branch rust-layout) owns this file; at the merge its version is taken and only the
//! `rigid_body` module line is added to it.

use crate::grid::GridGeometry;

pub mod rigid_body;

/// What a constraint may read when it corrects nodal velocities.
pub struct NodalContext<'a> {
    pub grid: &'a GridGeometry,
    pub mass: &'a [f64], // nodal mass (per radian or per metre)
    pub time: f64,       // time at the start of the step
    pub dt: f64,
    pub axisymmetric: bool,
}

pub trait Constraint: Send + Sync {
    /// Name used in output columns (`NAME.force_x`), e.g. "bottom", "wall_0", a rigid body's name.
    fn name(&self) -> &str;
    /// Corrects the nodal velocities in place. `record` is true for the momentum update
    /// (v⁺, the physical correction: its removed momentum counts towards the reaction) and
    /// false for the MUSL re-mapped velocities.
    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool);
    /// Impulse the material exerted on the constraint since the last call (N·s, per radian
    /// or per metre: Σ_nodes m_i (v_before − v_after)), reset to zero by the call.
    fn take_impulse(&mut self) -> [f64; 2] {
        [0.0; 2]
    }
    /// Whether the constraint's reaction is reported in the history (faces/walls/rigid bodies).
    fn reports_reaction(&self) -> bool {
        true
    }
}
