//! Everything that corrects nodal velocities: the grid faces, the symmetry axis, straight rigid
//! walls (later rigid bodies and contact), behind one [`Constraint`] trait.
//!
//! The solver applies every constraint, in a fixed order (faces, axis, walls, then rigid
//! bodies), to the start-of-step velocities, to the velocities of the momentum update v⁺
//! (`record = true`: the correction of v⁺ is the physical one, and the momentum it removes
//! is the impulse the material exerts on the constraint) and, with MUSL, to the re-mapped
//! velocities (where faces and walls keep each node's contact state of v⁺:
//! [`ConstrainedNodes::correct_remapped`]). Each constraint that reports a reaction accumulates that impulse,
//! Σ_nodes m_i (v_before − v_after) per radian or per metre, until [`Constraint::take_impulse`].
//! With PIC velocities this is exactly the momentum the particles lose to the constraint; with
//! FLIP the particles also keep what the start-of-step correction removed from the grid, so
//! the two agree only on average (within 0.05 % for a body at rest with FLIP 0.99,
//! tests/reactions.rs; pure FLIP can keep a biased velocity pattern at a wall).
//! For the energy budget each constraint also accumulates the work that impulse does against the material,
//! Σ_nodes (J_i − m_i δ_i) · v⁺_i,after ([`Constraint::dissipated_energy`], accumulated over the whole run,
//! split into the normal and the tangential component): the impulse times the velocity the
//! node then moves with (the particles move with v⁺); m_i δ_i is the momentum the same
//! constraint removed from the node's start-of-step velocity in that step (the unrecorded call
//! before the recorded one), which the FLIP increment v⁺ − v gives back to the particles, so
//! J − m δ is the impulse the particles feel (without it a sliding block "dissipated" 35 %
//! more than its kinetic energy). For Coulomb sliding this is the friction
//! impulse times the slip velocity (≥ 0: the reduction never reverses the slip); the normal
//! component of a roller, friction or fixed wall is zero after the correction, so the energy
//! lost in an inelastic impact on a wall is not in this term (it is in the budget's residual).
//! Rejected measures: the kinetic energy the correction removes, ½ m (|v⁺_before|² −
//! |v⁺_after|²), is unbounded at nodes of vanishing mass (GIMP domains reaching past a wall,
//! v⁺ = v + Δt f/m); the impulse times the start-of-step velocity counts the velocity into
//! the base that pure FLIP particles keep at rest (the start-of-step correction, which they
//! never see), and grew without bound in a deposit at rest.
//!
//! Node conditions of faces and walls (docs/physics.md §1, §8; Bardenhagen et al. 2001 for friction):
//! - `roller`: normal velocity zero (bilateral), tangential free;
//! - `fixed`: both components zero;
//! - `friction`: no penetration (unilateral) with Coulomb friction: when the node moves into
//!   the wall with normal speed v_n > 0, v_n is removed and the tangential speed is reduced by
//!   μ v_n (never reversed); a node moving away is free.
//!
//! A face or wall acts on every node on its line and on the nodes beyond it (outside the
//! material side), so particle domains that reach past a wall (GIMP, CPDI) cannot drag
//! material through it. In axisymmetry the axis r = 0 is always a roller (v_r = 0).

use crate::config::{BoundariesConfig, Condition, Friction, WallConfig};
use crate::grid::GridGeometry;

pub mod axis;
pub mod line;
pub mod rigid_body;

pub use axis::SymmetryAxis;
pub use line::LineConstraint;
pub use rigid_body::RigidBody;

/// What a constraint may read when it corrects nodal velocities.
/// What a rigid body's penalty contact reads ([`RigidBody::add_contact_forces`]).
#[derive(Clone, Copy)]
pub struct ParticleContext<'a> {
    pub particles: &'a crate::particles::Particles,
    pub grid: &'a GridGeometry,
    /// Nodal mass (per radian or per metre) and the mass below which a node gets no force.
    pub mass: &'a [f64],
    pub light: f64,
    /// Time at the start of the step, s.
    pub time: f64,
    pub dt: f64,
    pub axisymmetric: bool,
}

pub struct NodalContext<'a> {
    pub grid: &'a GridGeometry,
    /// Nodal mass (per radian or per metre).
    pub mass: &'a [f64],
    /// Time at the start of the step, s.
    pub time: f64,
    pub dt: f64,
    pub axisymmetric: bool,
}

pub trait Constraint: Send + Sync {
    /// Name used in output columns (`NAME.force_x`), e.g. "bottom", "wall_0", a rigid body's name.
    fn name(&self) -> &str;
    /// Corrects the nodal velocities in place. `record` is true for the momentum update
    /// (v⁺, the physical correction: its removed momentum counts towards the reaction) and
    /// false for the start-of-step velocities (the MUSL re-mapped ones go through
    /// [`Constraint::apply_remapped`]).
    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool);
    /// Corrects the MUSL re-mapped velocities of the step (after the recorded call on v⁺).
    /// By default the same correction as an unrecorded [`Constraint::apply`]; faces and walls
    /// keep the contact state of v⁺ ([`ConstrainedNodes::correct_remapped`]).
    fn apply_remapped(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]]) {
        self.apply(context, velocity, false);
    }
    /// Impulse the material exerted on the constraint since the last call (N·s, per radian
    /// or per metre: Σ_nodes m_i (v_before − v_after)), reset to zero by the call.
    fn take_impulse(&mut self) -> [f64; 2] {
        [0.0; 2]
    }
    /// Adds an impulse the material exerted on the constraint outside its velocity correction
    /// (N·s per radian or per metre): in a saturated run, the pore water's at an impermeable
    /// face or wall (`solver::saturated`, "Reactions"). Ignored by a constraint that reports
    /// no reaction.
    fn book_impulse(&mut self, _impulse: [f64; 2]) {}
    /// The fixed nodes whose velocity the constraint holds ([`HeldNodes`]). `None` for a
    /// constraint whose nodes move (a rigid body) or that holds nothing.
    fn held_nodes(&self) -> Option<HeldNodes<'_>> {
        None
    }
    /// Work of the recorded (v⁺) corrections against the material since the start of the run
    /// (J per radian or per metre; module doc): [normal component, tangential component].
    /// Not reset.
    fn dissipated_energy(&self) -> [f64; 2] {
        [0.0; 2]
    }
    /// Whether the constraint's reaction is reported in the history (faces/walls/rigid bodies).
    fn reports_reaction(&self) -> bool {
        true
    }
    /// Whether the constraint also corrects the start-of-step velocities (faces, axis, walls:
    /// yes; a rigid body's contact: no, see `rigid_body.rs`).
    fn applies_to_start_of_step(&self) -> bool {
        true
    }
    /// The rigid body behind this constraint, if it is one (displacements, base/shaft split).
    fn as_rigid_body(&self) -> Option<&RigidBody> {
        None
    }
    fn as_rigid_body_mut(&mut self) -> Option<&mut RigidBody> {
        None
    }
}

/// The fixed nodes a face or wall holds, in which directions ([x, y]: its normal, both for
/// `fixed`), and whether for good (`roller`, `fixed`: the held velocity is zero after every
/// correction) or only while pressed in (`friction`).
#[derive(Clone, Copy, Debug)]
pub struct HeldNodes<'a> {
    pub nodes: &'a [u32],
    pub directions: [bool; 2],
    pub bilateral: bool,
}

impl Friction {
    /// The largest tangential impulse (or force) the interface transmits with the normal one
    /// `normal` ≥ 0: μ·normal for Coulomb, unlimited for `"rough"`.
    #[inline(always)]
    pub fn shear_limit(self, normal: f64) -> f64 {
        match self {
            Friction::Coulomb(mu) => mu * normal,
            Friction::Rough => f64::INFINITY,
        }
    }
}

/// The tangential strength of a contact interface in velocity terms, for one node and step:
/// the Coulomb part comes from the normal velocity the contact removes, `adhesion` and `cap`
/// are the adhesion a and the limit a_lim times A Δt/m (A: the node's share of the interface,
/// m: its mass; constraint/rigid_body.rs, "Adhesion").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interface {
    pub friction: Friction,
    /// a A Δt / m, m/s (0: none).
    pub adhesion: f64,
    /// a_lim A Δt / m, m/s (∞: none).
    pub cap: f64,
}

impl Interface {
    /// Coulomb friction alone (walls, a rigid body without adhesion).
    #[inline(always)]
    pub fn coulomb(friction: Friction) -> Self {
        Self { friction, adhesion: 0.0, cap: f64::INFINITY }
    }
}

/// The unilateral contact of a node with a rigid surface, Coulomb friction (Bardenhagen et al.
/// 2001) plus adhesion: the corrected material velocity at a node moving with `v` against a
/// surface moving with `w` whose outward unit normal (out of the obstacle, into the material)
/// is `n`. With the relative velocity v − w split into v_n = (v − w)·n and v_t = (v − w)·τ,
/// τ = (−n_y, n_x):
/// - v_n < 0 (approaching): v_n is removed (the normal impulse per unit mass |v_n|), and v_t is
///   reduced by the interface's strength min(μ|v_n| + adhesion, cap), never reversed:
///   v_t ← sign(v_t) max(0, |v_t| − limit); `"rough"` removes v_t;
/// - v_n ≥ 0 (separating or sliding along): the normal part is kept (the contact is
///   unilateral) and the normal impulse is zero, so only the adhesion limits v_t; without
///   adhesion the velocity is untouched.
///
/// A wall is this law with w = 0, n = ±e_axis and no adhesion ([`NodeCondition::correct`]); a
/// rigid body passes its velocity, the normal of its nearest face and its adhesion.
#[inline(always)]
pub fn coulomb_contact(v: [f64; 2], w: [f64; 2], n: [f64; 2], interface: Interface) -> [f64; 2] {
    let rel = [v[0] - w[0], v[1] - w[1]];
    let vn = rel[0] * n[0] + rel[1] * n[1];
    let approaching = vn < 0.0;
    if !approaching && !(interface.adhesion > 0.0) {
        return v;
    }
    let tangent = [-n[1], n[0]];
    let vt = rel[0] * tangent[0] + rel[1] * tangent[1];
    let friction = if approaching { interface.friction.shear_limit(-vn) } else { 0.0 };
    let limit = (friction + interface.adhesion).min(interface.cap);
    let reduced = (vt.abs() - limit).max(0.0).copysign(vt);
    let mut out = [w[0] + reduced * tangent[0], w[1] + reduced * tangent[1]];
    if !approaching {
        out[0] += vn * n[0];
        out[1] += vn * n[1];
    }
    out
}

/// The velocity condition of a straight face or wall at one node.
#[derive(Clone, Copy, Debug)]
pub struct NodeCondition {
    /// Component normal to the wall (0: x/r, 1: y/z).
    pub axis: u8,
    /// +1 when the wall lies on the positive side of the material (outward normal +axis).
    pub outward: f64,
    pub condition: Condition,
    /// Coulomb friction coefficient μ (friction only).
    pub coefficient: f64,
}

impl NodeCondition {
    /// Whether a node moving with `v` is pressed into a unilateral (`friction`) wall.
    #[inline(always)]
    pub fn moves_into_wall(&self, v: [f64; 2]) -> bool {
        self.condition == Condition::Friction && v[self.axis as usize] * self.outward > 0.0
    }

    /// Corrects one nodal velocity (module doc).
    #[inline(always)]
    pub fn correct(&self, v: &mut [f64; 2]) {
        let a = self.axis as usize;
        match self.condition {
            Condition::Free => {}
            Condition::Roller => v[a] = 0.0,
            Condition::Fixed => *v = [0.0, 0.0],
            Condition::Friction => {
                // The wall's normal out of it, into the material: −outward along the axis.
                let mut n = [0.0; 2];
                n[a] = -self.outward;
                *v = coulomb_contact(*v, [0.0; 2], n, Interface::coulomb(Friction::Coulomb(self.coefficient)));
            }
        }
    }

    /// Corrects the velocities of `nodes`; with `record`, adds the momentum removed,
    /// Σ m_i (v_before − v_after), to `impulse` (it only reads: the velocities are the same).
    #[inline]
    pub fn correct_nodes(
        &self,
        nodes: &[u32],
        context: &NodalContext,
        velocity: &mut [[f64; 2]],
        record: bool,
        impulse: &mut [f64; 2],
    ) {
        if record {
            for &node in nodes {
                let v = &mut velocity[node as usize];
                let before = *v;
                self.correct(v);
                let m = context.mass[node as usize];
                impulse[0] += m * (before[0] - v[0]);
                impulse[1] += m * (before[1] - v[1]);
            }
        } else {
            for &node in nodes {
                self.correct(&mut velocity[node as usize]);
            }
        }
    }
}

/// A condition on a fixed set of nodes (a grid face or a wall) with its records: the
/// reaction impulse since it was last taken and the energy budget (module doc). Shared by
/// [`LineConstraint`]: the grid's faces and the walls.
#[derive(Clone, Debug)]
pub struct ConstrainedNodes {
    pub nodes: Vec<u32>,
    pub condition: NodeCondition,
    impulse: [f64; 2],
    /// Kinetic energy removed since the start ([normal, tangential], J per radian or metre).
    dissipated: [f64; 2],
    /// Per node, the correction of the last unrecorded call (start-of-step velocity).
    start_correction: Vec<[f64; 2]>,
    /// Per node, whether the last recorded call (v⁺) found it in contact: a `friction` node
    /// moving into the wall. Read by [`ConstrainedNodes::correct_remapped`].
    in_contact: Vec<bool>,
}

impl ConstrainedNodes {
    pub fn new(nodes: Vec<u32>, condition: NodeCondition) -> Self {
        Self {
            condition,
            impulse: [0.0; 2],
            dissipated: [0.0; 2],
            start_correction: Vec::new(),
            // No contact before the first recorded call: the re-map gets the plain correction.
            in_contact: vec![false; nodes.len()],
            nodes,
        }
    }

    /// [`NodeCondition::correct_nodes`] with the energy budget (module doc): a recorded call
    /// adds the impulse times the corrected velocity, per component, to the dissipated energy
    /// ([normal, tangential]); an unrecorded one (start-of-step velocities) keeps each node's
    /// correction for it.
    pub fn correct(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool) {
        let Self { nodes, condition, impulse, dissipated, start_correction, in_contact } = self;
        if start_correction.len() != nodes.len() {
            start_correction.clear();
            start_correction.resize(nodes.len(), [0.0; 2]);
        }
        if record {
            let a = condition.axis as usize;
            let t = 1 - a;
            for (k, &node) in nodes.iter().enumerate() {
                let v = &mut velocity[node as usize];
                let before = *v;
                in_contact[k] = condition.moves_into_wall(before);
                condition.correct(v);
                let m = context.mass[node as usize];
                let j = [m * (before[0] - v[0]), m * (before[1] - v[1])];
                impulse[0] += j[0];
                impulse[1] += j[1];
                let d = start_correction[k];
                dissipated[0] += (j[a] - m * d[a]) * v[a];
                dissipated[1] += (j[t] - m * d[t]) * v[t];
            }
        } else {
            for (k, &node) in nodes.iter().enumerate() {
                let v = &mut velocity[node as usize];
                let before = *v;
                condition.correct(v);
                start_correction[k] = [before[0] - v[0], before[1] - v[1]];
            }
        }
    }

    /// Corrects the MUSL re-mapped velocities with the contact state of the step's v⁺
    /// correction: a `friction` node that was pressed into the wall in v⁺ keeps zero normal
    /// velocity even when its re-mapped velocity points away from the wall (the other nodes,
    /// and the other conditions, as in [`NodeCondition::correct`]).
    ///
    /// Why: the strain rate is taken from the re-mapped velocities. A particle pressed against
    /// the wall is pushed off it by the wall's correction of v⁺ (the half of its internal
    /// force pointing into the wall is removed); if its nodes on the wall were then let go
    /// because the re-mapped velocity — the particle's own, now moving away — points away, all
    /// its nodes carry one velocity, its strain rate is zero, and its stress never relaxes: a
    /// compressed spring leaving a wall without lengthening, a source of energy (a lone dilute
    /// particle at a base was measured accelerating at J σ/(ρ0 h) ≈ 4.7·10⁴ m/s² until it left
    /// the grid; docs/validation.md). With the contact kept for the re-map, the particle
    /// lengthens as it leaves and its stress relaxes (docs/physics.md §8, "The contact state
    /// of the step").
    pub fn correct_remapped(&mut self, velocity: &mut [[f64; 2]]) {
        let Self { nodes, condition, in_contact, .. } = self;
        let a = condition.axis as usize;
        for (&node, &contact) in nodes.iter().zip(in_contact.iter()) {
            let v = &mut velocity[node as usize];
            condition.correct(v);
            if contact {
                v[a] = 0.0;
            }
        }
    }

    /// The impulse recorded since the last call (see [`Constraint::take_impulse`]).
    pub fn take_impulse(&mut self) -> [f64; 2] {
        std::mem::take(&mut self.impulse)
    }

    /// See [`Constraint::book_impulse`].
    pub fn book_impulse(&mut self, impulse: [f64; 2]) {
        self.impulse[0] += impulse[0];
        self.impulse[1] += impulse[1];
    }

    /// See [`Constraint::dissipated_energy`].
    pub fn dissipated_energy(&self) -> [f64; 2] {
        self.dissipated
    }
}

/// All constraints of a run, in the order the solver applies them.
#[derive(Default)]
pub struct Constraints {
    pub list: Vec<Box<dyn Constraint>>,
    /// Dissipated energy carried over from a checkpoint ([normal, tangential]).
    pub restored_dissipation: [f64; 2],
}

impl Constraints {
    /// Faces (left, right, bottom, top; only those that are not free, and in axisymmetry no
    /// left face), the axis (axisymmetric runs), then the walls in scenario order (`wall_i`
    /// for `walls[i]`; free walls are left out).
    /// `moving_grid`: the grid follows a body along y (`LineConstraint::faces`).
    pub fn new(grid: &GridGeometry, faces: &BoundariesConfig, walls: &[WallConfig], axisymmetric: bool, moving_grid: bool) -> Self {
        let mut list: Vec<Box<dyn Constraint>> = Vec::new();
        for face in LineConstraint::faces(grid, faces, axisymmetric, moving_grid) {
            list.push(Box::new(face));
        }
        if axisymmetric {
            list.push(Box::new(SymmetryAxis::new(grid)));
        }
        for (i, wall) in walls.iter().enumerate() {
            if let Some(w) = LineConstraint::wall(format!("wall_{i}"), grid, wall) {
                list.push(Box::new(w));
            }
        }
        Self { list, restored_dissipation: [0.0; 2] }
    }

    /// Adds a constraint after the others (rigid bodies come last).
    pub fn push(&mut self, constraint: Box<dyn Constraint>) {
        self.list.push(constraint);
    }

    /// Applies every constraint, in order, to a nodal velocity field.
    pub fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool) {
        for c in &mut self.list {
            c.apply(context, velocity, record);
        }
    }

    /// Applies every constraint, in order, to the MUSL re-mapped velocities
    /// ([`Constraint::apply_remapped`]).
    pub fn apply_remapped(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]]) {
        for c in &mut self.list {
            c.apply_remapped(context, velocity);
        }
    }

    /// Applies, in order, the constraints that correct start-of-step velocities (not recorded).
    pub fn apply_start_of_step(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]]) {
        for c in &mut self.list {
            if c.applies_to_start_of_step() {
                c.apply(context, velocity, false);
            }
        }
    }

    /// Whether some rigid body imposes its contact by particle forces
    /// ([`rigid_body::Enforcement::Penalty`]).
    pub fn has_particle_contact(&self) -> bool {
        self.rigid_bodies().any(|b| matches!(b.enforcement(), rigid_body::Enforcement::Penalty(_)))
    }

    /// The rigid bodies' penalty contact forces, added to the nodal forces
    /// ([`RigidBody::add_contact_forces`]).
    pub fn add_contact_forces(&mut self, context: &ParticleContext, nodal_force: &mut [[f64; 2]]) {
        for body in self.rigid_bodies_mut() {
            body.add_contact_forces(context, nodal_force);
        }
    }

    /// The rigid bodies among the constraints, in order.
    pub fn rigid_bodies(&self) -> impl Iterator<Item = &RigidBody> {
        self.list.iter().filter_map(|c| c.as_rigid_body())
    }

    pub fn rigid_bodies_mut(&mut self) -> impl Iterator<Item = &mut RigidBody> {
        self.list.iter_mut().filter_map(|c| c.as_rigid_body_mut())
    }

    /// Before a step [t, t + dt] under `gravity`: [`RigidBody::begin_step`] of every body.
    pub fn begin_rigid_body_step(&mut self, time: f64, dt: f64, gravity: [f64; 2]) {
        for body in self.rigid_bodies_mut() {
            body.begin_step(time, dt, gravity);
        }
    }

    /// After that step: [`RigidBody::end_step`] of every body, then the first force-driven
    /// body outside the grid `lower..upper` at the step's end `time + dt`, if any
    /// ([`RigidBody::left_grid`]).
    pub fn end_rigid_body_step(
        &mut self,
        time: f64,
        dt: f64,
        total_factor: f64,
        lower: [f64; 2],
        upper: [f64; 2],
    ) -> Result<(), String> {
        let mut failure = None;
        for body in self.rigid_bodies_mut() {
            body.end_step(time, dt, total_factor);
            if failure.is_none() {
                failure = body.left_grid(time + dt, lower, upper);
            }
        }
        failure.map_or(Ok(()), Err)
    }

    /// Work the rigid bodies have done on the material since the start of the run (J per
    /// radian or per metre; [`RigidBody::work`]).
    pub fn rigid_body_work(&self) -> f64 {
        self.rigid_bodies().map(RigidBody::work).sum()
    }

    /// Names of the constraints that report a reaction, in order.
    pub fn reaction_names(&self) -> Vec<String> {
        self.list.iter().filter(|c| c.reports_reaction()).map(|c| c.name().to_string()).collect()
    }

    /// Kinetic energy removed by all constraints since the start of the run (J per radian or
    /// per metre): [normal, tangential] (see [`Constraint::dissipated_energy`]).
    pub fn dissipated_energy(&self) -> [f64; 2] {
        let mut total = self.restored_dissipation;
        for c in &self.list {
            let e = c.dissipated_energy();
            total[0] += e[0];
            total[1] += e[1];
        }
        total
    }

    /// Per reporting constraint, the impulse since the last call (N·s per radian or per
    /// metre), resetting the accumulators.
    pub fn take_impulses(&mut self) -> Vec<(String, [f64; 2])> {
        self.list
            .iter_mut()
            .filter(|c| c.reports_reaction())
            .map(|c| (c.name().to_string(), c.take_impulse()))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{Axis, BoundaryCondition, Side};

    const SMOOTH: Friction = Friction::Coulomb(0.0);

    /// The law without adhesion.
    fn law(v: [f64; 2], w: [f64; 2], n: [f64; 2], friction: Friction) -> [f64; 2] {
        coulomb_contact(v, w, n, Interface::coulomb(friction))
    }

    #[test]
    fn contact_law_by_hand() {
        let down = [0.0, -1.0]; // base of a body: outward normal −y
        let w = [0.0, -0.5]; // body moving down at 0.5 m/s
        // Material at rest below the base: approaching at 0.5; smooth keeps the tangential part.
        assert_eq!(law([0.3, 0.0], w, down, SMOOTH), [0.3, -0.5]);
        // Coulomb μ = 0.4: tangential 0.3 reduced by 0.4 × 0.5 = 0.2 → 0.1.
        let v = law([0.3, 0.0], w, down, Friction::Coulomb(0.4));
        assert!((v[0] - 0.1).abs() < 1e-15 && v[1] == -0.5, "{v:?}");
        // μ large enough: sticks, never reverses.
        assert_eq!(law([0.3, 0.0], w, down, Friction::Coulomb(1.0)), [0.0, -0.5]);
        assert_eq!(law([0.3, 0.0], w, down, Friction::Rough), [0.0, -0.5]);
        // Separating (material moving down faster than the body): untouched, whatever the friction.
        assert_eq!(law([0.3, -0.7], w, down, Friction::Rough), [0.3, -0.7]);
        // Exactly matched normal velocity (sliding along): untouched.
        assert_eq!(law([0.3, -0.5], w, down, Friction::Rough), [0.3, -0.5]);
        // Oblique normal: the result never moves into the body, and the removed part is along n.
        let s = 0.5f64.sqrt();
        let n = [s, -s];
        let v = law([-1.0, 0.2], [0.0, 0.0], n, SMOOTH);
        assert!((v[0] * n[0] + v[1] * n[1]).abs() < 1e-15);
        let d = [v[0] + 1.0, v[1] - 0.2];
        assert!((d[0] * n[1] - d[1] * n[0]).abs() < 1e-15, "correction not along n");
        // A body moving sideways (a pile pushed laterally in plane strain): its right face
        // (outward normal +x) moving at 0.4 m/s meets material at rest, which is pushed along
        // at the body's speed and keeps its own tangential velocity when smooth.
        assert_eq!(law([0.0, 0.2], [0.4, 0.0], [1.0, 0.0], SMOOTH), [0.4, 0.2]);
        // Material already moving away faster than the face: untouched.
        assert_eq!(law([0.5, 0.2], [0.4, 0.0], [1.0, 0.0], Friction::Rough), [0.5, 0.2]);
        // A wall is the law with w = 0 and n = ±e_axis: a right wall (outward +x, normal −x)
        // stops a node moving into it and slows its tangential speed 0.5 by μ × 0.4 = 0.1.
        let wall = NodeCondition { axis: 0, outward: 1.0, condition: Condition::Friction, coefficient: 0.25 };
        let mut v = [0.4, -0.5];
        wall.correct(&mut v);
        assert_eq!(v, law([0.4, -0.5], [0.0, 0.0], [-1.0, 0.0], Friction::Coulomb(0.25)));
        assert!(v[0] == 0.0 && (v[1] + 0.4).abs() < 1e-15, "{v:?}");
    }

    /// Adhesion by hand: a base (normal −y, tangent +x) moving down at 0.5 m/s over material
    /// sliding at 0.3 m/s. Approaching: the normal part goes, the slip is reduced by
    /// μ|v_n| + adhesion = 0.2 × 0.5 + 0.05 = 0.15, or by the cap 0.12 when smaller.
    /// Separating (material moving down at 0.7): the normal part stays, and only the adhesion
    /// holds the slip back (0.3 → 0.2), whatever the friction; without adhesion: untouched.
    #[test]
    fn adhesion_by_hand() {
        let (down, w) = ([0.0, -1.0], [0.0, -0.5]);
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15;
        let glue = |adhesion: f64, cap: f64| Interface { friction: Friction::Coulomb(0.2), adhesion, cap };
        let v = coulomb_contact([0.3, 0.0], w, down, glue(0.05, f64::INFINITY));
        assert!(close(v, [0.15, -0.5]), "{v:?}");
        let v = coulomb_contact([0.3, 0.0], w, down, glue(0.05, 0.12));
        assert!(close(v, [0.18, -0.5]), "{v:?}");
        // Enough adhesion: the node sticks, never reverses (the α-method with μ = 0).
        let alpha = Interface { friction: Friction::Coulomb(0.0), adhesion: 1.0, cap: f64::INFINITY };
        assert_eq!(coulomb_contact([0.3, 0.0], w, down, alpha), [0.0, -0.5]);
        let v = coulomb_contact([0.3, -0.7], w, down, glue(0.1, f64::INFINITY));
        assert!(close(v, [0.2, -0.7]), "{v:?}");
        let rough = Interface { friction: Friction::Rough, adhesion: 0.1, cap: f64::INFINITY };
        assert!(close(coulomb_contact([0.3, -0.7], w, down, rough), [0.2, -0.7]));
        assert_eq!(coulomb_contact([0.3, -0.7], w, down, glue(0.0, f64::INFINITY)), [0.3, -0.7]);
        // The same on a shaft (normal +x, tangent +y): material at rest beside a body rising
        // at 1 m/s is dragged up by the adhesion alone.
        let shaft = Interface { friction: Friction::Coulomb(0.0), adhesion: 0.0125, cap: f64::INFINITY };
        assert!(close(coulomb_contact([0.0, 0.0], [0.0, 1.0], [1.0, 0.0], shaft), [0.0, 0.0125]));
    }

    fn base(condition: Condition, mu: f64) -> NodeCondition {
        NodeCondition { axis: 1, outward: -1.0, condition, coefficient: mu }
    }

    fn context<'a>(grid: &'a GridGeometry, mass: &'a [f64], time: f64) -> NodalContext<'a> {
        NodalContext { grid, mass, time, dt: 1e-3, axisymmetric: false }
    }

    #[test]
    fn friction_base_by_hand() {
        // Base (outward normal −y). Moving down at 1 m/s and sideways at 2 m/s with μ = 0.5:
        // normal removed, tangential 2 − 0.5·1 = 1.5.
        let mut v = [2.0, -1.0];
        base(Condition::Friction, 0.5).correct(&mut v);
        assert_eq!(v, [1.5, 0.0]);
        // Sliding stops, never reverses.
        let mut v = [-0.2, -1.0];
        base(Condition::Friction, 0.5).correct(&mut v);
        assert_eq!(v, [0.0, 0.0]);
        // Leaving the wall: untouched.
        let mut v = [2.0, 1.0];
        base(Condition::Friction, 0.5).correct(&mut v);
        assert_eq!(v, [2.0, 1.0]);
    }

    #[test]
    fn friction_reduction_is_mu_times_the_normal_speed() {
        // v_n ≠ 1 tells μ v_n from μ / v_n: down at 4 m/s, sideways at −3 m/s, μ = 0.25:
        // tangential −(3 − 0.25·4) = −2 (a reduction of μ/v_n = 0.0625 would leave −2.9375).
        let mut v = [-3.0, -4.0];
        base(Condition::Friction, 0.25).correct(&mut v);
        assert_eq!(v, [-2.0, 0.0]);
        // Slow approach, v_n = 0.5 (μ/v_n = 1 would stop the node): 1 − 0.5·0.5 = 0.75.
        let mut v = [1.0, -0.5];
        base(Condition::Friction, 0.5).correct(&mut v);
        assert_eq!(v, [0.75, 0.0]);
        // A right wall (outward +x): v_n = 2 into it, tangential 1.5 − 0.5·2 = 0.5.
        let mut v = [2.0, 1.5];
        NodeCondition { axis: 0, outward: 1.0, condition: Condition::Friction, coefficient: 0.5 }.correct(&mut v);
        assert_eq!(v, [0.0, 0.5]);
    }

    #[test]
    fn remapped_velocities_keep_the_contact_of_v_plus() {
        // A friction base (outward −y) on nodes 0, 1, 2, μ = 0.5.
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.5);
        let mass = vec![1.0; g.num_nodes()];
        let mut line = ConstrainedNodes::new(vec![0, 1, 2], base(Condition::Friction, 0.5));
        // Before any recorded call there is no contact state: the plain correction.
        let mut v = vec![[1.0, 2.0]; g.num_nodes()];
        v[1] = [1.0, -2.0];
        line.correct_remapped(&mut v);
        assert_eq!(&v[..3], &[[1.0, 2.0], [0.0, 0.0], [1.0, 2.0]]);
        // v⁺: node 0 pressed into the base, node 1 leaving it, node 2 at rest on it.
        let mut v_plus = vec![[0.0; 2]; g.num_nodes()];
        v_plus[0] = [3.0, -1.0];
        v_plus[1] = [3.0, 1.0];
        line.correct(&context(&g, &mass, 0.0), &mut v_plus, true);
        assert_eq!(&v_plus[..3], &[[2.5, 0.0], [3.0, 1.0], [0.0, 0.0]]);
        // Re-mapped: every node moving away, at 0.5 m/s. Node 0 keeps its contact (normal
        // velocity 0, tangential free: nothing presses it in), the others leave.
        let mut remapped = vec![[2.0, 0.5]; g.num_nodes()];
        line.correct_remapped(&mut remapped);
        assert_eq!(&remapped[..4], &[[2.0, 0.0], [2.0, 0.5], [2.0, 0.5], [2.0, 0.5]]);
        // Re-mapped velocities into the base get the full friction correction on every node.
        let mut remapped = vec![[2.0, -1.0]; g.num_nodes()];
        line.correct_remapped(&mut remapped);
        assert_eq!(&remapped[..3], &[[1.5, 0.0], [1.5, 0.0], [1.5, 0.0]]);
        // The impulse is the recorded call's alone (node 0: m (v_before − v_after)).
        assert_eq!(line.take_impulse(), [0.5, -1.0]);
        // A roller (bilateral) is a roller whatever the contact state.
        let mut roller = ConstrainedNodes::new(vec![0], base(Condition::Roller, 0.0));
        let mut v_plus = vec![[1.0, -1.0]];
        roller.correct(&context(&g, &mass, 0.0), &mut v_plus, true);
        let mut remapped = vec![[1.0, 1.0]];
        roller.correct_remapped(&mut remapped);
        assert_eq!(remapped[0], [1.0, 0.0]);
    }

    #[test]
    fn the_axis_holds_remapped_velocities_too() {
        // Axisymmetric, no faces: the axis (a roller, v_r = 0 at r = 0) corrects the
        // re-mapped velocities like every other field (the trait's default `apply_remapped`).
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.5);
        let mut cs = Constraints::new(&g, &BoundariesConfig::default(), &[], true, false);
        let mass = vec![1.0; g.num_nodes()];
        let mut remapped = vec![[1.0, 2.0]; g.num_nodes()];
        cs.apply_remapped(&context(&g, &mass, 0.0), &mut remapped);
        for j in 0..3 {
            assert_eq!(remapped[g.node_index(0, j)], [0.0, 2.0]);
            assert_eq!(remapped[g.node_index(1, j)], [1.0, 2.0]);
        }
    }

    #[test]
    fn a_removed_wall_lets_remapped_velocities_go() {
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.5);
        let wall = WallConfig {
            axis: Axis::X,
            position: 0.5,
            material_side: Side::Negative,
            condition: Condition::Friction,
            coefficient: 0.0,
            removal_time: Some(0.1),
        };
        let mut cs = Constraints::new(&g, &BoundariesConfig::default(), &[wall], false, false);
        let mass = vec![1.0; g.num_nodes()];
        let node = g.node_index(1, 1);
        // Removed at its removal time exactly, as in `apply`.
        for (time, kept) in [(0.0, true), (0.1, false), (0.2, false)] {
            let mut v_plus = vec![[1.0, 0.0]; g.num_nodes()];
            cs.apply(&context(&g, &mass, time), &mut v_plus, true);
            let mut remapped = vec![[-1.0, 0.0]; g.num_nodes()];
            cs.apply_remapped(&context(&g, &mass, time), &mut remapped);
            let expected = if kept { [0.0, 0.0] } else { [-1.0, 0.0] };
            assert_eq!(remapped[node], expected, "t = {time}");
        }
    }

    #[test]
    fn faces_and_walls_tell_the_nodes_and_directions_they_hold() {
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.5);
        let faces = BoundariesConfig {
            left: BoundaryCondition::ROLLER,
            bottom: BoundaryCondition::FIXED,
            right: BoundaryCondition::friction(0.3),
            ..Default::default()
        };
        let wall = |removal_time| WallConfig {
            axis: Axis::Y,
            position: 0.5,
            material_side: Side::Positive,
            condition: Condition::Roller,
            coefficient: 0.0,
            removal_time,
        };
        let cs = Constraints::new(&g, &faces, &[wall(None), wall(Some(1.0))], true, false);
        let held: Vec<_> = cs.list.iter().map(|c| c.held_nodes().map(|h| (c.name().to_string(), h.nodes.to_vec(), h.directions, h.bilateral))).collect();
        assert_eq!(
            held,
            vec![
                // Axisymmetric: no left face; the axis holds nothing it books.
                Some(("right".into(), vec![2, 5, 8], [true, false], false)),
                Some(("bottom".into(), vec![0, 1, 2], [true, true], true)),
                None,
                // The standing wall: its line y = 0.5 and the row below it.
                Some(("wall_0".into(), vec![0, 1, 2, 3, 4, 5], [false, true], true)),
                // A wall lifted during the run holds nothing for good.
                None,
            ]
        );
        let free = Constraints::new(&g, &BoundariesConfig::default(), &[WallConfig { condition: Condition::Free, ..wall(None) }], false, false);
        assert!(free.list.is_empty());
    }

    #[test]
    fn roller_and_fixed() {
        let mut v = [2.0, -1.0];
        base(Condition::Roller, 0.0).correct(&mut v);
        assert_eq!(v, [2.0, 0.0]);
        base(Condition::Fixed, 0.0).correct(&mut v);
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
        let mut cs = Constraints::new(&g, &faces, &[wall], true, false);
        assert_eq!(cs.list.len(), 2);
        assert_eq!(cs.reaction_names(), vec!["wall_0".to_string()]);
        let mass = vec![1.0; g.num_nodes()];
        let mut v = vec![[1.0, 1.0]; g.num_nodes()];
        cs.apply(&context(&g, &mass, 0.0), &mut v, false);
        assert_eq!(v[g.node_index(0, 2)], [0.0, 1.0]);
        assert_eq!(v[g.node_index(1, 2)], [1.0, 1.0]);
        // 3 columns (x = 0.5, 0.75, 1.0) of 5 nodes.
        for i in 2..5 {
            for j in 0..5 {
                assert_eq!(v[g.node_index(i, j)], [0.0, 1.0]);
            }
        }
        let mut v = vec![[1.0, 1.0]; g.num_nodes()];
        cs.apply(&context(&g, &mass, 0.2), &mut v, false); // wall removed, axis stays
        assert_eq!(v[g.node_index(2, 2)], [1.0, 1.0]);
        assert_eq!(v[g.node_index(0, 2)], [0.0, 1.0]);
    }

    #[test]
    fn faces_report_the_momentum_they_remove_only_when_recording() {
        let g = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.5);
        let faces = BoundariesConfig {
            left: BoundaryCondition::ROLLER,
            bottom: BoundaryCondition::friction(0.5),
            ..Default::default()
        };
        let mut cs = Constraints::new(&g, &faces, &[], false, false);
        assert_eq!(cs.reaction_names(), vec!["left".to_string(), "bottom".to_string()]);
        let mass: Vec<f64> = (0..g.num_nodes()).map(|n| 1.0 + n as f64).collect();
        let mut v = vec![[2.0, -1.0]; g.num_nodes()];
        cs.apply(&context(&g, &mass, 0.0), &mut v, false);
        assert!(cs.take_impulses().iter().all(|(_, j)| *j == [0.0; 2]));
        let mut v = vec![[2.0, -1.0]; g.num_nodes()];
        cs.apply(&context(&g, &mass, 0.0), &mut v, true);
        let reactions = cs.take_impulses();
        // Left face, nodes 0, 3, 6 (masses 1, 4, 7): v_x 2 → 0, except node 0, which the left
        // face corrects first: 2 m/s of each.
        assert_eq!(reactions[0], ("left".to_string(), [2.0 * (1.0 + 4.0 + 7.0), 0.0]));
        // Bottom nodes 0, 1, 2 (masses 1, 2, 3): v_y −1 → 0, v_x 2 → 1.5 (nodes 1, 2) and 0 → 0
        // (node 0, already stopped by the left face).
        assert_eq!(reactions[1], ("bottom".to_string(), [0.5 * (2.0 + 3.0), -(1.0 + 2.0 + 3.0)]));
        // Taken: zero until the next recording.
        assert!(cs.take_impulses().iter().all(|(_, j)| *j == [0.0; 2]));
    }
}
