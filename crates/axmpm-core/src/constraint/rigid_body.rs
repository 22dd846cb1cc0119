//! Rigid bodies with a prescribed motion or driven by a force, in frictional, adhesive contact
//! with the material (`docs/physics.md` §8).
//!
//! # Scenario
//!
//! ```toml
//! [[rigid_bodies]]
//! name = "footing"
//! shape = "rectangle"            # or "polygon" with vertices = [[x, y], ...]
//! min = [0.0, 3.0]
//! max = [0.5, 3.2]
//! velocity = [0.0, -0.01]        # m/s, or a table: motion = [[t, vx, vy], ...]
//! friction = 0.0                 # Coulomb coefficient ≥ 0, or "rough" (no slip)
//! adhesion = 0.0                 # Pa ≥ 0; adhesion_limit = a_lim (Pa > 0) optional ("Adhesion")
//! contact = "nodes"              # or "penalty" ("Penalty contact" below)
//! parts = [{ name = "tip", below = 0.0309 }]   # optional ("Reaction")
//! ```
//!
//! The table is [`crate::config::RigidBodyConfig`]; [`RigidBody::from_config`] checks every
//! value, naming the key and the allowed range. The region is any shape of the region registry
//! ([`crate::geometry::SHAPES`]), used for the contact as its polygon ([`Region::outline`]).
//! The path is known in advance, so a body it carries out of the grid before the run's end is
//! refused ([`Motion::first_exit`]).
//!
//! `motion` is a velocity table linear between its rows (times strictly increasing, from
//! t ≥ 0), constant before the first and after the last row. The body's displacement is the exact
//! integral D(t) = ∫₀ᵗ v dt of that velocity ([`Motion::displacement`]): a pure function of time,
//! so a run resumed from a checkpoint moves the body bit for bit as an uninterrupted one. In
//! axisymmetry only axial motion is allowed (every vx = 0) and the region must lie at r ≥ 0.
//!
//! # Force-driven bodies
//!
//! A body with `mass` M (kg, whole body: per metre in plane strain, the whole ring in
//! axisymmetry), an optional `force = [[t, fx, fy], ...]` table F(t) (N, linear between rows,
//! constant outside) and an optional `initial_velocity` has no prescribed path: it moves under
//! F, gravity g (the material's of the step, with the ramp) and the contact impulse J the
//! material exerts on it ([`Dynamics`]). Its displacement X and velocity V are its state (in
//! the checkpoint). A step t → t + Δt:
//!
//! * [`RigidBody::begin_step`]: ΔV_ext = ∫ₜ^{t+Δt} F dt / M + g Δt (exact for the
//!   piecewise-linear F) and w₀ = V + ΔV_ext/2; the contact geometry is the body at X + Δt w₀;
//! * the recorded contact solves the body's velocity w with its reaction,
//!   M_b (w − w₀) = J(w) ([`RigidBody::contact_velocity`], M_b = M per metre or per radian):
//!   the velocity the body and its covered nodes reach together. With w₀ alone (the reaction a
//!   step late) a body lighter than the nodes it covers is thrown back faster than it came;
//! * [`RigidBody::end_step`]: X ← X + Δt w, V ← V + ΔV_ext + J/M.
//!
//! Without contact X(t + Δt) = X + Δt (V + ΔV_ext/2) = X + V Δt + a Δt²/2 for a constant
//! acceleration a: the trapezoid of a linear velocity is exact, so x(t) = x₀ + v₀ t + a t²/2 for
//! any sequence of steps. The body receives exactly the impulse the material loses (momentum
//! conserved between them). In axisymmetry only the axial components move the body.
//!
//! # Energy
//!
//! The work a body does on the material in a step is −J·w (J its contact impulse, w its
//! velocity over the step), summed in [`RigidBody::work`] (the budget's `rigid_body_work`);
//! the slip the contact leaves at a node, v_after − w, dissipates j·(v_after − w) ≥ 0
//! (j = m (v_before − v_after): Coulomb or adhesion reduce the slip without reversing it), the
//! tangential part of [`Constraint::dissipated_energy`].
//!
//! # Contact (Bardenhagen, Brackbill & Sulsky 2000; Bardenhagen et al. 2001)
//!
//! Over a step t → t + Δt the body moves with its mean velocity w = (D(t + Δt) − D(t))/Δt, so
//! that the nodes carrying it move it by exactly D(t + Δt) − D(t). The **covered nodes** are the
//! grid nodes carrying material mass that lie inside the body's region or on its boundary at the
//! end of the step (signed distance d ≤ 10⁻⁹ h), or outside it by less than the **reach** l_p =
//! h/(2n), the half-width of the material's particles (n per cell and direction; the largest
//! half-width when bodies differ). These are the nodes whose velocity a rigid body would own in
//! a two-field contact scheme (Bardenhagen et al. 2000): there the rigid body's nodal velocity is
//! its prescribed one, and the material's is corrected towards it. Why the reach: the material's
//! surface is the edge of its particles' domains, so the particle centres next to the body lie
//! l_p from it; when the body's surface is less than l_p above a row of nodes, those particles
//! have crossed below that row and no longer reach the nodes inside the body (linear shape
//! functions), so without the reach the body would lose its grip on them once per cell of travel
//! (a footing's load dropped by 30 % there and particles entered it). With it, contact starts at
//! most l_p early. At each covered node with material velocity v, relative velocity v_rel = v − w
//! and body outward normal n:
//!
//! * v_rel·n ≥ 0 (separating or sliding): untouched — separation is allowed;
//! * v_rel·n < 0 (approaching): the normal part is removed; the tangential part
//!   t = v_rel − (v_rel·n) n is reduced to max(0, |t| − μ |v_rel·n|) in its own direction
//!   (Coulomb: the tangential impulse is at most μ times the normal one, and never reverses the
//!   slip), or to 0 for `friction = "rough"` (no slip). v ← w + t'.
//!
//! The normal is the body's geometry (the outward normal of the nearest face of the body's
//! polygon), not the gradient of the material's mass: the rigid body's surface is known exactly,
//! whereas the mass gradient of the material is noisy and points the wrong way at corners and
//! near free surfaces (the known issue of Bardenhagen's normals that Nairn's later contact work
//! addresses with other normals). **Corners**: a node inside the body that is also within
//! h − l_p of a second face (e.g. on the side of a footing, less than h − l_p above its base)
//! is corrected for the nearest face and then for the other one, each as a unilateral frictional
//! contact, so the material there may neither enter through the base nor through the side — the
//! rigid-footing corner of a finite-element mesh, where the edge node carries the footing's
//! displacement. The distance h − l_p hands the base over without a gap: once the base is more
//! than h − l_p below such a node, the next row of nodes is within the reach l_p of the base
//! (below). Without it a footing's load dropped by a third every cell of settlement at B/h = 10
//! (the edge node, on the side face, went free while the base was between two rows). A larger
//! distance (h) made a plate drag a block's top edge along, a column away from its side face.
//! A body the grid follows (`grid.follow`) never moves between rows, so there is nothing to hand
//! over: its nodes see the nearest face only, and the node at a vertex is on the side face (at
//! the end of the step the base has moved off it). Counting the base there too drags the
//! material beside the body with it, the vertex node carrying the body's velocity for good
//! (a followed circular footing's N_c +18.5 % at B/h = 20 instead of −2.9 %;
//! docs/studies/contact-remedies.md).
//! A vertex bisector would instead push material sideways
//! out of the corner. **Symmetry**: a body resting on the grid's left edge (the axis of an
//! axisymmetric run or the symmetry plane of a half model) is mirrored about it for the contact,
//! so its own edge on that line is not a face: a node on the axis inside a pile sees the pile's
//! tip or top, not the axis.
//!
//! The other known issue, early contact a cell away (a two-field scheme sees contact as soon as
//! both bodies have mass at a node, up to one cell before the surfaces touch), is bounded here by
//! the reach: contact starts at most l_p = h/(2n) before the surfaces touch (a quarter cell with
//! 2 × 2 particles per cell). A larger reach (h/2, h) raised a footing's bearing load by 0.3 % and
//! 3 % (strip) and 5 % and 10 % (circle) at B/h = 20. The contact surface is still resolved to a
//! cell: the load transmitted varies with the position of the surface between two rows of nodes.
//! At a corner (outside, within the reach) the normal is the direction from the vertex.
//!
//! The Coulomb law at a node is [`super::coulomb_contact`], the one the grid faces and walls use
//! (with w = 0 and their axis as the normal).
//!
//! # Adhesion (a Tresca interface)
//!
//! `adhesion` a and `adhesion_limit` a_lim give the interface the shear strength
//! τ_max = min(μ σ_n + a, a_lim); with μ = 0 and a = α s_u it is the α-method of pile design
//! (shaft resistance α s_u whatever the normal stress). At a covered node of mass m the
//! correction removes the normal velocity |v_n| of an approaching node, a normal impulse
//! J_n = m |v_n|; if the node stands for the interface area A, the mean normal traction over
//! the step is σ_n = J_n/(A Δt), and the tangential impulse may be at most
//! τ_max A Δt = min(μ J_n + a A Δt, a_lim A Δt). Per unit mass, the slip is reduced by at most
//!
//!   min(μ |v_n| + a A Δt/m, a_lim A Δt/m),
//!
//! the Coulomb term μ|v_n| of the law plus the adhesion as a velocity. The adhesion holds
//! while the surfaces touch: at a covered node that does not approach (v_n ≥ 0: sliding along
//! a pile shaft in weightless soil, or leaving) the normal velocity is kept and only a A Δt/m
//! limits the slip (σ_n = 0: no friction). A is the node's share of the face: the face's
//! length within half the node spacing along it, h/(2 max(|n_x|, |n_y|)), of the node's
//! projection on it, clipped to the face's ends and to the grid's left edge (× ∫ r ds/length,
//! the radius, per radian in axisymmetry). Where the material ends along the face (a free
//! surface meeting a pile shaft) the last node's band stops at it: a half band is dropped
//! when the next node along the face carries less than a quarter of the node's mass (per unit
//! radius in axisymmetry). A node at the material's edge carries half the mass of a node
//! inside, so its inner neighbour has twice its mass and the edge node half its neighbour's:
//! a quarter separates the edge from the inside with a margin of two either way (the mass of
//! a node varies by some per cent as particles move). With material on one side of the node
//! only, its mass and its share of the face are both halved, so it slips as the others do.
//! Counting the whole band made a pile's shaft resistance h/L too high (L the length in
//! contact); dropping it only at a node without mass did the same once the soil dragged up
//! along the shaft gave the next node a little mass, and a threshold of a half dropped the
//! band of the node next to the edge whenever the edge node held slightly less than half. The node that stands for a face is the one in the band −(h − l_p) < d ≤ l_p of
//! signed distance d, one node per grid line across an axis-aligned face (nodes deeper inside
//! carry no adhesion, so a face between two nodes is not counted twice).
//!
//! With the penalty contact the adhesion acts per particle: its tangential force is at most
//! min(μ N + a A_p, a_lim A_p), A_p the tributary area of its corners inside the body; it
//! needs a corner inside the body (a gap), so it holds only where the normal pressure presses
//! the particles onto the body.
//!
//! # Penalty contact (`contact = "penalty"`)
//!
//! The alternative to the nodal correction imposes the contact where the surfaces are, not at
//! the nodes (the particle-level penalty of Bird, Pretti, Coombs, Augarde et al. 2024, who test
//! the corners of each GIMP domain against the surface): each particle's domain corners (GIMP:
//! x_p + F·(±l₀); CPDI: its own corners) are tested against the body's polygon at the start of
//! the step; a corner inside it by the gap g receives the pressure k·g along the nearest face's
//! outward normal, over a tributary length of half a domain side (× its radius in axisymmetry).
//! The particle's tangential force is the one that stops its slip relative to the body within
//! the step (m_p |v_t|/Δt), limited to μ times its normal force for Coulomb friction (not
//! limited for `"rough"`); it is shared among the particle's corners in contact by their
//! normal forces. Each corner force is added to the nodal forces f_i through the bilinear shape
//! functions of the grid at the corner (shared among the nodes of that cell that carry mass),
//! so a force under a footing never reaches a node beyond its edge. The force varies
//! continuously with the body's motion: no node row switches at once.
//!
//! Stiffness: k = ρ c_p²/h (Pa/m), the stiffness of one cell of the stiffest material in
//! uniaxial strain; the gap under a pressure p is g/h = p/(ρ c_p²) (10⁻³ for a footing on clay
//! at collapse), and the footing's N_c hardly depends on it (docs/studies/contact-remedies.md). It adds to a surface node at most the stiffness of the material's own
//! cell, so the highest frequency grows by at most √2 and the time step is kept at
//! c_p Δt/h ≤ 1/2 (the solver reduces it when `cfl` asks for more).
//!
//! Measured on the footing (docs/studies/contact-remedies.md): the load–settlement curve has
//! no steps, but N_c is 8 % (strip) and 15–20 % (circle) above the exact values at B/h = 20,
//! falling slowly with refinement; the nodal correction stays the default.
//!
//! # Reaction
//!
//! The force the material exerts on the body is the momentum the correction removes from the
//! material: Σ_covered m_i (v_before − v_after) per step (the MUSL re-map correction is not
//! counted: it only re-imposes the same condition on re-mapped velocities), accumulated and
//! handed out by [`Constraint::take_impulse`] (N·s per metre in plane strain, per radian in
//! axisymmetry). The impulse is also split into the part taken by nodes whose normal faces down
//! (n_y < −1/√2: the **base** of a pile or footing) and the rest (the **shaft**: sides, top).
//! With the penalty contact the impulse is minus the contact forces applied to the nodes × Δt,
//! split by each particle's mean normal; the material's momentum changes by exactly that.
//!
//! **Named parts by height** (`parts`, optional): a list of `{ name, below }` with `below`
//! increasing, heights in metres above the body's lowest point in its own frame (they move with
//! the body). Each face's correction at a covered node (both faces at a corner) acts where that
//! face is nearest the node, its foot; it goes to the first part whose `below` is at or above
//! the foot's height (a point at a part's upper end is that part's, with an allowance of 10⁻⁹
//! of the body's size for round-off), and above the last `below` to the part `rest`. So a part
//! ending at a vertex (a cone's shoulder) takes exactly the faces below it. With the penalty
//! contact a particle's force goes by the height of its centre. The split is by position, not
//! by normal, because the faces that carry a penetrometer's tip resistance are not horizontal:
//! a 60° cone's faces are 30° from vertical, and the normal split counts them as shaft. The
//! foot, not the node's own height, because a node inside the body near the shoulder is
//! corrected for the cone's face as well as the shaft's: by the node's height about 40 % of a
//! smooth cone's force went to the shaft above the shoulder (R/h = 2). The parts sum to the
//! body's total impulse.

use super::{coulomb_contact, Constraint, Interface, NodalContext};
pub use crate::config::Friction;
use crate::config::{ContactKind, RigidBodyConfig};
use crate::geometry::{self, Polygon, Region};
use serde_json::{Map, Value};

/// Why `contact = "penalty"` needs `experimental = true` (the same words in the front end).
pub const PENALTY_IS_EXPERIMENTAL: &str = "\"penalty\" is experimental (measured, not adopted: the footing's N_c comes out \
    8-20 % high; docs/studies/contact-remedies.md): set experimental = true in this rigid body to use it";

/// How the contact condition is imposed (module doc): `contact = "nodes" | "penalty"`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Enforcement {
    /// Velocity correction at the covered nodes (within the reach of the body).
    Nodes,
    /// Penalty pressure k·g on the particles' domain corners that lie inside the body (gap g),
    /// k in Pa/m (set by the solver, [`RigidBody::with_penalty_stiffness`]); each corner's
    /// force reaches the nodes through the grid's shape functions at that corner.
    Penalty(f64),
}

/// Prescribed motion: velocity linear between the rows of a table, constant outside it.
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    times: Vec<f64>,
    velocities: Vec<[f64; 2]>,
    /// D(t_k), the displacement at each row's time.
    displacements: Vec<[f64; 2]>,
}

impl Motion {
    /// A constant velocity.
    pub fn constant(velocity: [f64; 2]) -> Self {
        Self { times: vec![0.0], velocities: vec![velocity], displacements: vec![[0.0; 2]] }
    }

    /// Rows (t, vx, vy), times ≥ 0 and strictly increasing (checked by the caller's parser).
    pub fn table(rows: &[[f64; 3]]) -> Self {
        let times: Vec<f64> = rows.iter().map(|r| r[0]).collect();
        let velocities: Vec<[f64; 2]> = rows.iter().map(|r| [r[1], r[2]]).collect();
        let mut displacements = Vec::with_capacity(rows.len());
        // Constant v_0 from t = 0 to t_0, then trapezoids.
        let mut d = [velocities[0][0] * times[0], velocities[0][1] * times[0]];
        displacements.push(d);
        for k in 1..rows.len() {
            let dt = times[k] - times[k - 1];
            for c in 0..2 {
                d[c] += 0.5 * (velocities[k - 1][c] + velocities[k][c]) * dt;
            }
            displacements.push(d);
        }
        Self { times, velocities, displacements }
    }

    /// Index of the last row with t_k ≤ t, or `None` before the first row.
    #[inline]
    fn segment(&self, t: f64) -> Option<usize> {
        let k = self.times.partition_point(|&tk| tk <= t);
        k.checked_sub(1)
    }

    /// Prescribed velocity at time t.
    pub fn velocity(&self, t: f64) -> [f64; 2] {
        match self.segment(t) {
            None => self.velocities[0],
            Some(k) if k + 1 == self.times.len() => self.velocities[k],
            Some(k) => {
                let s = (t - self.times[k]) / (self.times[k + 1] - self.times[k]);
                let (a, b) = (self.velocities[k], self.velocities[k + 1]);
                [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])]
            }
        }
    }

    /// Displacement D(t) = ∫₀ᵗ v dt, exact for the piecewise-linear velocity.
    pub fn displacement(&self, t: f64) -> [f64; 2] {
        match self.segment(t) {
            None => [self.velocities[0][0] * t, self.velocities[0][1] * t],
            Some(k) => {
                let (d, v, tau) = (self.displacements[k], self.velocities[k], t - self.times[k]);
                if k + 1 == self.times.len() {
                    [d[0] + v[0] * tau, d[1] + v[1] * tau]
                } else {
                    let span = self.times[k + 1] - self.times[k];
                    let b = self.velocities[k + 1];
                    let q = 0.5 * tau * tau / span;
                    [d[0] + v[0] * tau + (b[0] - v[0]) * q, d[1] + v[1] * tau + (b[1] - v[1]) * q]
                }
            }
        }
    }

    /// The first time in [0, `end`] at which a box `lo..hi` moved by D(t) leaves the box
    /// `lower..upper`, if it does (to a relative 10⁻¹², found by bisection: each component of
    /// D is monotone between the table's times and the zeros of its velocity).
    pub fn first_exit(&self, lo: [f64; 2], hi: [f64; 2], lower: [f64; 2], upper: [f64; 2], end: f64) -> Option<f64> {
        let out = |t: f64| {
            let d = self.displacement(t);
            (0..2).any(|c| !(lo[c] + d[c] >= lower[c] && hi[c] + d[c] <= upper[c]))
        };
        let mut knots: Vec<f64> = std::iter::once(0.0).chain(self.times.iter().copied().filter(|&t| t > 0.0 && t < end)).collect();
        knots.push(end);
        let mut previous = 0.0;
        if out(previous) {
            return Some(0.0);
        }
        for piece in knots.windows(2) {
            let (a, b) = (piece[0], piece[1]);
            let (va, vb) = (self.velocity(a), self.velocity(b));
            let mut candidates: Vec<f64> = (0..2)
                .filter(|&c| (va[c] > 0.0) != (vb[c] > 0.0) && va[c] != vb[c])
                .map(|c| a + (b - a) * va[c] / (va[c] - vb[c]))
                .filter(|&t| t > a && t < b)
                .collect();
            candidates.sort_by(f64::total_cmp);
            candidates.push(b);
            for t in candidates {
                if out(t) {
                    let (mut inside, mut outside) = (previous, t);
                    while outside - inside > 1e-12 * outside.max(1e-300) {
                        let mid = 0.5 * (inside + outside);
                        if mid <= inside || mid >= outside {
                            break;
                        }
                        if out(mid) {
                            outside = mid;
                        } else {
                            inside = mid;
                        }
                    }
                    return Some(outside);
                }
                previous = t;
            }
        }
        None
    }

    /// Mean velocity over [t, t + dt]: (D(t + dt) − D(t))/dt.
    pub fn mean_velocity(&self, t: f64, dt: f64) -> [f64; 2] {
        let (a, b) = (self.displacement(t), self.displacement(t + dt));
        [(b[0] - a[0]) / dt, (b[1] - a[1]) / dt]
    }
}

/// A force-driven body's mass, load and state (module doc, "Force-driven bodies").
#[derive(Clone, Debug, PartialEq)]
pub struct Dynamics {
    /// M, kg: whole body (per metre in plane strain, the whole ring in axisymmetry).
    mass: f64,
    /// The applied force F(t) as a piecewise-linear table (its `velocity` is F, its
    /// `displacement` the exact impulse ∫₀ᵗ F dt); `None`: no applied force.
    force: Option<Motion>,
    /// Displacement X and velocity V at the simulation's current time.
    displacement: [f64; 2],
    velocity: [f64; 2],
    /// The velocity the body moved with over the last step, (X(t) − X(t − Δt))/Δt (the
    /// initial velocity before the first step): its rate of settlement, reported as its
    /// velocity. V differs from it by half the last step's ΔV_ext, which the contact resists in
    /// the next step: a body held at rest against a force F has w = 0 and V = F Δt/(2M).
    step_velocity: [f64; 2],
    /// Velocity change of the current step from the force and gravity, ΔV_ext
    /// ([`RigidBody::begin_step`]).
    kick: [f64; 2],
    /// The body's velocity over the current step with the contact, once solved
    /// ([`RigidBody::contact_velocity`]).
    contact: Option<[f64; 2]>,
    /// The body moves along y only: a body of revolution (axisymmetry), or a body resting on
    /// the grid's left edge, the symmetry plane of a half model (mirrored for the contact).
    axial_only: bool,
}

impl Dynamics {
    /// The body's mean velocity over a step of length `dt` from its current state:
    /// w = V + ΔV_ext/2, the trapezoid of the start and end velocities without the contact
    /// (exact for a constant acceleration, module doc).
    #[inline]
    fn mean_velocity(&self) -> [f64; 2] {
        [self.velocity[0] + 0.5 * self.kick[0], self.velocity[1] + 0.5 * self.kick[1]]
    }
}

/// How a rigid body moves: along a prescribed path, or under a force ([`Dynamics`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Kinematics {
    Prescribed(Motion),
    Driven(Dynamics),
}

/// What a checkpoint keeps of a rigid body (the rest is rebuilt from the scenario): a
/// force-driven body's displacement and velocity, and the work every body has done on the
/// material (per metre or per radian).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RigidBodyState {
    pub displacement: [f64; 2],
    pub velocity: [f64; 2],
    /// The velocity over the last step ([`Dynamics`]).
    pub step_velocity: [f64; 2],
    pub work: f64,
}

/// A rigid body: a region moved by a prescribed motion or by a force, in contact with the
/// material.
#[derive(Debug)]
pub struct RigidBody {
    name: String,
    /// The region at t = 0; at time t it is translated by the body's displacement.
    region: Box<dyn Region>,
    /// The same region as a polygon for the contact, united with its mirror image when it
    /// rests against the grid's left edge (symmetry plane or axis; module doc).
    contact: Polygon,
    kinematics: Kinematics,
    friction: Friction,
    /// Adhesion a and the interface's shear limit a_lim, Pa (module doc, "Adhesion").
    adhesion: f64,
    adhesion_limit: f64,
    enforcement: Enforcement,
    /// Distance outside the body within which a node still counts as covered (module doc).
    reach: f64,
    /// Whether the grid follows this body (`grid.follow`; module doc, "Corners").
    followed: bool,

    /// Impulse since the last `take_impulse`.
    impulse: [f64; 2],
    /// Impulse since the last `take_impulse_parts`: the base part and the rest (module doc).
    impulse_base: [f64; 2],
    impulse_shaft: [f64; 2],
    /// Impulse of the current step, J (per metre or per radian), for the body's own motion and
    /// its work ([`RigidBody::end_step`]).
    step_impulse: [f64; 2],
    /// Work the body has done on the material since the start, −Σ_steps J·w (module doc,
    /// "Energy"), per metre or per radian.
    work: f64,
    /// Of that work, the part lost to slip at the interface, Σ_nodes j·(v_after − w).
    interface_dissipation: f64,
    /// Named parts by height (module doc, "Reaction"): each part's upper end in the body's own
    /// frame (m, increasing), the names of the parts and then `rest`, and the impulse of each
    /// since the last [`RigidBody::take_named_parts`]. All empty when the body has no parts.
    part_tops: Vec<f64>,
    part_names: Vec<String>,
    impulse_named: Vec<[f64; 2]>,
}

/// The part above a body's named parts (module doc, "Reaction").
pub const REST: &str = "rest";

/// Names a body's part may not take: the normal split's parts and `rest`, whose columns the
/// history writes anyway.
const RESERVED_PART_NAMES: [&str; 3] = ["base", "shaft", REST];

/// Books an impulse at height `y` (a body's own frame) to the named part whose range holds it
/// (`tops`: the parts' upper ends, each with its round-off allowance; a point at a part's
/// upper end is that part's; `named`: their impulses, then `rest`'s), if there are any.
#[inline]
fn book_named(tops: &[f64], named: &mut [[f64; 2]], y: f64, impulse: [f64; 2]) {
    if named.is_empty() {
        return;
    }
    let k = tops.partition_point(|&top| y > top);
    named[k][0] += impulse[0];
    named[k][1] += impulse[1];
}

/// Newton iterations of a force-driven body's contact velocity at most
/// ([`RigidBody::contact_velocity`]; a frictionless contact in one direction has converged once
/// the set of nodes in contact stops changing; the last iterate is used otherwise, which keeps
/// the momentum balance, since the impulse booked is the one of that iterate).
const CONTACT_ITERATIONS: usize = 30;

/// Whether a normal faces down (the base of a pile or footing): n_y < −1/√2.
#[inline]
fn faces_down(n: [f64; 2]) -> bool {
    n[1] < -std::f64::consts::FRAC_1_SQRT_2
}

impl RigidBody {
    /// `contact`: the region as a polygon (mirrored about a symmetry line it rests on).
    pub fn new(
        name: impl Into<String>,
        region: Box<dyn Region>,
        contact: Polygon,
        kinematics: Kinematics,
        friction: Friction,
    ) -> Self {
        Self {
            name: name.into(),
            region,
            contact,
            kinematics,
            friction,
            adhesion: 0.0,
            adhesion_limit: f64::INFINITY,
            enforcement: Enforcement::Nodes,
            reach: 0.0,
            followed: false,

            impulse: [0.0; 2],
            impulse_base: [0.0; 2],
            impulse_shaft: [0.0; 2],
            step_impulse: [0.0; 2],
            work: 0.0,
            interface_dissipation: 0.0,
            part_tops: Vec::new(),
            part_names: Vec::new(),
            impulse_named: Vec::new(),
        }
    }

    /// Names the parts of the reaction by height (module doc, "Reaction"): `parts` as (name,
    /// upper end in m above the body's lowest point), the ends increasing (checked by
    /// [`RigidBody::from_config`]); above the last end, `rest`. No parts: no named split.
    pub fn with_parts(mut self, parts: &[(String, f64)]) -> Self {
        if parts.is_empty() {
            return self;
        }
        let (lo, hi) = self.region.bounding_box();
        // A vertex at a part's upper end given as the same sum in the scenario (tip + shoulder
        // height) may differ from lowest + below by round-off: allow 10⁻⁹ of the body's size.
        let allowance = 1e-9 * (hi[0] - lo[0]).max(hi[1] - lo[1]);
        self.part_tops = parts.iter().map(|(_, below)| lo[1] + below + allowance).collect();
        self.part_names = parts.iter().map(|(name, _)| name.clone()).chain(std::iter::once(REST.to_string())).collect();
        self.impulse_named = vec![[0.0; 2]; self.part_names.len()];
        self
    }


    /// Impulse of each named part since the last call (module doc, "Reaction"), in the order
    /// of `parts` and then `rest`; reset by the call. Empty when the body has no parts.
    pub fn take_named_parts(&mut self) -> Vec<(String, [f64; 2])> {
        let taken = self.part_names.iter().cloned().zip(self.impulse_named.iter().copied()).collect();
        self.impulse_named.iter_mut().for_each(|i| *i = [0.0; 2]);
        taken
    }

    /// The body's motion over the step [t, t + dt]: (displacement at t, displacement at
    /// t + dt, mean velocity w). Prescribed: D(t), D(t + dt) and (D(t + dt) − D(t))/dt;
    /// force-driven: X, X + dt w₀ with the predicted w₀ = V + ΔV_ext/2 of
    /// [`RigidBody::begin_step`], and w₀ or, once solved in the step, the contact's w (module doc).
    #[inline]
    fn step_motion(&self, time: f64, dt: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
        match &self.kinematics {
            Kinematics::Prescribed(motion) => {
                (motion.displacement(time), motion.displacement(time + dt), motion.mean_velocity(time, dt))
            }
            Kinematics::Driven(d) => {
                // The geometry of the step is the predicted one (without the contact), so the
                // solve and the re-map see the same covered nodes.
                let predicted = d.mean_velocity();
                let x = d.displacement;
                (x, [x[0] + dt * predicted[0], x[1] + dt * predicted[1]], d.contact.unwrap_or(predicted))
            }
        }
    }

    /// Before a step [t, t + dt] under `gravity` (the acceleration the material gets in that
    /// step): a force-driven body's velocity change without the contact,
    /// ΔV_ext = ∫ₜ^{t+dt} F dt / M + g dt (axial only for a body of revolution or on a symmetry
    /// plane). Nothing for a prescribed body.
    pub fn begin_step(&mut self, time: f64, dt: f64, gravity: [f64; 2]) {
        if let Kinematics::Driven(d) = &mut self.kinematics {
            let impulse = match &d.force {
                Some(f) => {
                    let (a, b) = (f.displacement(time), f.displacement(time + dt));
                    [b[0] - a[0], b[1] - a[1]]
                }
                None => [0.0; 2],
            };
            d.kick = [impulse[0] / d.mass + gravity[0] * dt, impulse[1] / d.mass + gravity[1] * dt];
            if d.axial_only {
                d.kick[0] = 0.0;
            }
            d.contact = None;
        }
    }

    /// After the step begun by [`RigidBody::begin_step`] (same `time`, `dt`): books the work
    /// the body did on the material, −J·w with J the step's contact impulse, and moves a
    /// force-driven body: X ← X + dt w, V ← V + ΔV_ext + J_body/M, J_body = `total_factor` × J
    /// (the whole body's impulse: 2π per radian in axisymmetry; only its axial part moves a
    /// body of revolution or one on a symmetry plane). The impulse the body receives is the
    /// momentum the material lost.
    pub fn end_step(&mut self, time: f64, dt: f64, total_factor: f64) {
        let (_, _, w) = self.step_motion(time, dt);
        let j = std::mem::take(&mut self.step_impulse);
        self.work -= j[0] * w[0] + j[1] * w[1];
        if let Kinematics::Driven(d) = &mut self.kinematics {
            let radial = if d.axial_only { 0.0 } else { 1.0 };
            d.displacement[0] += dt * w[0];
            d.displacement[1] += dt * w[1];
            d.step_velocity = w;
            d.velocity[0] += d.kick[0] + radial * total_factor * j[0] / d.mass;
            d.velocity[1] += d.kick[1] + total_factor * j[1] / d.mass;
        }
    }

    /// A force-driven body whose box has left the grid `lower..upper` (to 10⁻⁹ of the grid's
    /// span): why, naming the body, the time and its velocity. `None` for a prescribed body
    /// (its path is checked in advance, [`Motion::first_exit`]).
    pub fn left_grid(&self, time: f64, lower: [f64; 2], upper: [f64; 2]) -> Option<String> {
        let Kinematics::Driven(d) = &self.kinematics else { return None };
        let (lo, hi) = self.region.bounding_box();
        let x = d.displacement;
        let tol = 1e-9 * (upper[0] - lower[0]).max(upper[1] - lower[1]);
        let inside = (0..2).all(|c| lo[c] + x[c] >= lower[c] - tol && hi[c] + x[c] <= upper[c] + tol);
        if inside {
            return None;
        }
        let v = d.velocity;
        Some(format!(
            "rigid body '{}' left the grid at t = {time:.6e} s moving at ({:.3e}, {:.3e}) m/s (its box \
             ({:.6e}, {:.6e}) .. ({:.6e}, {:.6e}) m, the grid ({:.6e}, {:.6e}) .. ({:.6e}, {:.6e}) m): a force-driven \
             body moves under its force, gravity and the soil's reaction; check its mass and force, or \
             enlarge grid.extent if the motion is real",
            self.name,
            v[0],
            v[1],
            lo[0] + x[0],
            lo[1] + x[1],
            hi[0] + x[0],
            hi[1] + x[1],
            lower[0],
            lower[1],
            upper[0],
            upper[1]
        ))
    }

    /// One pass of the nodal contact (module doc) for the body at `offset` at the end of the
    /// step, moving with `w`: at each covered node with mass, `visit(m, before, after, steps, local)`
    /// with the node's mass, its velocity before and after the correction and the correction
    /// face by face (normal, from, to); with `write`, `after` is stored in `velocity`.
    fn sweep(
        &self,
        context: &NodalContext,
        velocity: &mut [[f64; 2]],
        offset: [f64; 2],
        w: [f64; 2],
        write: bool,
        mut visit: impl FnMut(f64, [f64; 2], [f64; 2], &[([f64; 2], [f64; 2], [f64; 2]); 2], [f64; 2]),
    ) {
        let grid = context.grid;
        let h = grid.cell_size;
        let (lo, hi) = self.region.bounding_box();
        let tolerance = 1e-9 * h;
        let reach = self.reach + tolerance;
        // A second face counts within h − l_p of a node (module doc, "Corners").
        // A body the grid follows keeps its place among the rows: nothing to hand over, and a
        // node at its vertex is on the nearest face only (module doc, "Corners").
        let corner = if self.followed { 0.0 } else { h - self.reach };
        let range = |d: usize| {
            let first = ((lo[d] + offset[d] - reach - grid.origin[d]) / h).ceil().max(0.0);
            let last = ((hi[d] + offset[d] + reach - grid.origin[d]) / h).floor();
            let last = last.min((grid.nodes[d] - 1) as f64);
            if last < first {
                1..0 // empty
            } else {
                first as usize..last as usize + 1
            }
        };
        // The interface at a node (module doc, "Adhesion"): Coulomb alone, or with the
        // adhesion and limit of the node's share A of the face, in velocity terms (× Δt/m).
        let adhesive = self.adhesion > 0.0 || self.adhesion_limit.is_finite();
        let (contact, friction, adhesion, adhesion_limit) = (&self.contact, self.friction, self.adhesion, self.adhesion_limit);
        let (dt, axisymmetric, reach_inside) = (context.dt, context.axisymmetric, h - self.reach);
        let mass = context.mass;
        let interface = |normal: [f64; 2], local: [f64; 2], distance: f64, m: f64, (i, j): (usize, usize)| {
            if !adhesive || distance <= -reach_inside {
                return Interface::coulomb(friction);
            }
            // One node per grid line crosses the face: the band between two nodes along it,
            // each half kept only if the next node along the face (on the grid line closest to
            // the face's direction) carries at least a quarter of this node's mass (per unit
            // radius in axisymmetry; module doc, "Adhesion").
            let half = 0.5 * h / normal[0].abs().max(normal[1].abs());
            let along = [-normal[1], normal[0]];
            let d = usize::from(along[1].abs() >= along[0].abs());
            let radius = |node: usize| grid.node_position(node)[0];
            let own = grid.node_index(i, j);
            let carries = |step: isize| {
                let mut ij = [i as isize, j as isize];
                ij[d] += step;
                if !(0..2).all(|c| ij[c] >= 0 && (ij[c] as usize) < grid.nodes[c]) {
                    return false;
                }
                let next = grid.node_index(ij[0] as usize, ij[1] as usize);
                let scale = if axisymmetric && radius(own) > 0.0 { radius(next) / radius(own) } else { 1.0 };
                mass[next] >= 0.25 * m * scale
            };
            let forward = if along[d] > 0.0 { 1 } else { -1 };
            let band = [if carries(-forward) { half } else { 0.0 }, if carries(forward) { half } else { 0.0 }];
            let (length, moment) = contact.face_band(local, normal, band, grid.origin[0] - offset[0]);
            let area = if axisymmetric { moment + length * offset[0] } else { length };
            let per_mass = area * dt / m;
            Interface { friction, adhesion: adhesion * per_mass, cap: adhesion_limit * per_mass }
        };
        let columns = range(0);
        for j in range(1) {
            for i in columns.clone() {
                let node = grid.node_index(i, j);
                let m = context.mass[node];
                if !(m > 0.0) {
                    continue;
                }
                let x = grid.node_position(node);
                let local = [x[0] - offset[0], x[1] - offset[1]];
                let (distance, mut normal, mut second) = self.contact.nearest_faces(local, corner);
                if distance > reach {
                    continue;
                }
                if distance > tolerance {
                    // Outside, within reach: one normal, from the nearest boundary point.
                    normal = self.contact.signed_distance(local).1;
                    second = None;
                }
                // Each face in turn (the nearest, then at a corner the other); the momentum each
                // removes goes to the base or the shaft part by that face's normal.
                let before = velocity[node];
                let mut after = coulomb_contact(before, w, normal, interface(normal, local, distance, m, (i, j)));
                let mut steps = [(normal, before, after), (normal, after, after)];
                if let Some(n2) = second {
                    let next = coulomb_contact(after, w, n2, interface(n2, local, distance, m, (i, j)));
                    steps[1] = (n2, after, next);
                    after = next;
                }
                if context.axisymmetric && i == 0 && grid.origin[0] == 0.0 {
                    // The axis stays a roller: its radial correction is the axis's, not the body's.
                    after[0] = before[0];
                    steps[0].2[0] = before[0];
                    steps[1].1[0] = before[0];
                    steps[1].2[0] = before[0];
                }
                if write {
                    velocity[node] = after;
                }
                visit(m, before, after, &steps, local);
            }
        }
    }

    /// A force-driven body's velocity over the step with the contact (module doc, "Force-driven
    /// bodies"): the w that solves M_b (w − w₀) = J(w), J(w) the impulse the material's
    /// covered nodes exert on the body when the contact makes them follow w, M_b the body's
    /// mass per metre or per radian (`mass`), w₀ its velocity without the contact. Semi-smooth
    /// Newton: each node that the contact corrects holds the body in the direction d of its
    /// correction, so ∂J/∂w ≈ −Σ m d dᵀ, and w ← w + (M_b I + Σ m d dᵀ)⁻¹ (M_b (w₀ − w) + J(w)),
    /// exact for a frictionless contact in one direction once the nodes in contact no longer
    /// change. Axial only (`axial_only`) for a body of revolution or on a symmetry plane.
    fn contact_velocity(
        &self,
        context: &NodalContext,
        velocity: &mut [[f64; 2]],
        offset: [f64; 2],
        w0: [f64; 2],
        mass: f64,
        axial_only: bool,
    ) -> [f64; 2] {
        let mut w = w0;
        for _ in 0..CONTACT_ITERATIONS {
            let (mut impulse, mut k) = ([0.0; 2], [0.0; 3]);
            self.sweep(context, velocity, offset, w, false, |m, before, after, _, _| {
                let d = [before[0] - after[0], before[1] - after[1]];
                let size = d[0] * d[0] + d[1] * d[1];
                impulse[0] += m * d[0];
                impulse[1] += m * d[1];
                if size > 0.0 {
                    k[0] += m * d[0] * d[0] / size;
                    k[1] += m * d[0] * d[1] / size;
                    k[2] += m * d[1] * d[1] / size;
                }
            });
            let r = [mass * (w0[0] - w[0]) + impulse[0], mass * (w0[1] - w[1]) + impulse[1]];
            let step = if axial_only {
                [0.0, r[1] / (mass + k[2])]
            } else {
                let (a, b, c) = (mass + k[0], k[1], mass + k[2]);
                let det = a * c - b * b;
                [(c * r[0] - b * r[1]) / det, (a * r[1] - b * r[0]) / det]
            };
            w = [w[0] + step[0], w[1] + step[1]];
            let scale = w[0].abs().max(w[1].abs()).max(w0[0].abs().max(w0[1].abs()));
            if step[0].abs().max(step[1].abs()) <= 1e-13 * scale {
                break;
            }
        }
        w
    }

    /// What a checkpoint keeps of the body ([`RigidBodyState`]).
    pub fn state(&self) -> RigidBodyState {
        let (displacement, velocity, step_velocity) = match &self.kinematics {
            Kinematics::Driven(d) => (d.displacement, d.velocity, d.step_velocity),
            Kinematics::Prescribed(_) => ([0.0; 2], [0.0; 2], [0.0; 2]),
        };
        RigidBodyState { displacement, velocity, step_velocity, work: self.work }
    }

    /// Restores what [`RigidBody::state`] kept (a prescribed body's displacement and velocity
    /// are functions of time: only its work is restored).
    pub fn restore(&mut self, state: &RigidBodyState) {
        self.work = state.work;
        if let Kinematics::Driven(d) = &mut self.kinematics {
            d.displacement = state.displacement;
            d.velocity = state.velocity;
            d.step_velocity = state.step_velocity;
        }
    }

    /// Work the body has done on the material since the start of the run, J per metre (plane
    /// strain) or per radian (axisymmetric): −Σ_steps J·w (module doc, "Energy").
    pub fn work(&self) -> f64 {
        self.work
    }

    pub fn kinematics(&self) -> &Kinematics {
        &self.kinematics
    }

    /// Sets the reach (m): nodes outside the body closer than this count as covered. The
    /// solver uses the material particles' half-width h/(2n) (module doc).
    pub fn with_reach(mut self, reach: f64) -> Self {
        self.reach = reach;
        self
    }

    /// Marks the body as the one the grid follows (`grid.follow`; module doc, "Corners").
    pub fn followed_by_the_grid(mut self, followed: bool) -> Self {
        self.followed = followed;
        self
    }

    /// Whether the grid follows this body (`grid.follow`).
    pub fn is_followed_by_the_grid(&self) -> bool {
        self.followed
    }

    /// Sets the stiffness k (Pa/m) of a penalty contact (no effect on a nodal one).
    pub fn with_penalty_stiffness(mut self, stiffness: f64) -> Self {
        if let Enforcement::Penalty(_) = self.enforcement {
            self.enforcement = Enforcement::Penalty(stiffness);
        }
        self
    }

    pub fn enforcement(&self) -> Enforcement {
        self.enforcement
    }

    /// Penalty contact (module doc): adds to the nodal forces `nodal_force` the force the body
    /// exerts on the material over the step starting at `time` (N per metre or per radian),
    /// each corner's force through the grid's bilinear shape functions at that corner, and
    /// books its opposite × dt as the body's impulse, split into base and shaft by the
    /// particle's mean normal. Serial, in particle order: independent of the thread count.
    pub fn add_contact_forces(&mut self, context: &super::ParticleContext, nodal_force: &mut [[f64; 2]]) {
        let Enforcement::Penalty(stiffness) = self.enforcement else { return };
        let super::ParticleContext { particles, grid, mass, light, time, dt, axisymmetric } = *context;
        let (offset, _, w) = self.step_motion(time, dt);
        let (lo, hi) = self.contact.bounding_box();
        let cpdi = !particles.corners.is_empty();
        for p in 0..particles.len() {
            let x = particles.position[p];
            let l = particles.initial_half_width[p];
            // Quick rejection: the domain lies within 2 max(l)·max|F| of the centre.
            let fg = &particles.deformation_gradient[p];
            let spread = 2.0 * l[0].max(l[1]) * (1.0 + fg[0].abs() + fg[1].abs() + fg[2].abs() + fg[3].abs());
            let c = [x[0] - offset[0], x[1] - offset[1]];
            if c[0] < lo[0] - spread || c[0] > hi[0] + spread || c[1] < lo[1] - spread || c[1] > hi[1] + spread {
                continue;
            }
            // Corners of the particle's domain (CPDI: its own; GIMP: F applied to ±l0).
            let corners: [[f64; 2]; 4] = if cpdi {
                particles.corners[p]
            } else {
                let mut q = [[0.0; 2]; 4];
                for (j, (sx, sy)) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].into_iter().enumerate() {
                    q[j] = [x[0] + fg[0] * sx * l[0] + fg[1] * sy * l[1], x[1] + fg[2] * sx * l[0] + fg[3] * sy * l[1]];
                }
                q
            };
            // Tributary length of a corner: half a side of the domain.
            let side = 0.5 * (l[0] + l[1]);
            let mut corner_force = [[0.0; 2]; 4];
            let mut normal_force = [0.0; 2];
            let mut total_magnitude = 0.0;
            let mut contact_area = 0.0;
            for (k, &q) in corners.iter().enumerate() {
                let (d, n) = geometry::Region::signed_distance(&self.contact, [q[0] - offset[0], q[1] - offset[1]]);
                if d < 0.0 {
                    let area = if axisymmetric { side * q[0].max(0.0) } else { side };
                    contact_area += area;
                    let magnitude = -stiffness * d * area;
                    corner_force[k] = [magnitude * n[0], magnitude * n[1]];
                    normal_force[0] += corner_force[k][0];
                    normal_force[1] += corner_force[k][1];
                    total_magnitude += magnitude;
                }
            }
            let fn_size = normal_force[0].hypot(normal_force[1]);
            if !(fn_size > 0.0) {
                continue;
            }
            let n = [normal_force[0] / fn_size, normal_force[1] / fn_size];
            let v = particles.velocity[p];
            let rel = [v[0] - w[0], v[1] - w[1]];
            let vn = rel[0] * n[0] + rel[1] * n[1];
            let t = [rel[0] - vn * n[0], rel[1] - vn * n[1]];
            let slip = t[0].hypot(t[1]);
            // Tangential force: the one that stops the particle's slip in this step, at most μ N.
            let stick = particles.mass[p] * slip / dt;
            // The interface's strength over the corners' area: min(μ N + a A, a_lim A).
            let mut strength = self.friction.shear_limit(fn_size) + self.adhesion * contact_area;
            if self.adhesion_limit.is_finite() {
                strength = strength.min(self.adhesion_limit * contact_area);
            }
            let limit = stick.min(strength);
            let tangential = if slip > 0.0 && limit > 0.0 { [-limit * t[0] / slip, -limit * t[1] / slip] } else { [0.0; 2] };
            let mut total = [0.0; 2];
            for (k, &q) in corners.iter().enumerate() {
                let f = corner_force[k];
                let magnitude = f[0].hypot(f[1]);
                if magnitude == 0.0 {
                    continue;
                }
                // The tangential force shared among the corners in contact by their normal force.
                let share = magnitude / total_magnitude;
                let f = [f[0] + share * tangential[0], f[1] + share * tangential[1]];
                if add_at_point(grid, mass, light, q, f, nodal_force) {
                    total[0] += f[0];
                    total[1] += f[1];
                }

            }
            let part = if faces_down(n) { &mut self.impulse_base } else { &mut self.impulse_shaft };
            // The material's impulse on the body is the opposite of the body's on the material.
            part[0] -= dt * total[0];
            part[1] -= dt * total[1];
            self.impulse[0] -= dt * total[0];
            self.impulse[1] -= dt * total[1];
            self.step_impulse[0] -= dt * total[0];
            self.step_impulse[1] -= dt * total[1];
            book_named(&self.part_tops, &mut self.impulse_named, c[1], [-dt * total[0], -dt * total[1]]);
        }
    }

    pub fn friction(&self) -> Friction {
        self.friction
    }

    /// The region at t = 0.
    pub fn region(&self) -> &dyn Region {
        self.region.as_ref()
    }

    /// Displacement of the body at time t, m: D(t) of a prescribed body; a force-driven
    /// body's is its state, that of the simulation's current time (t is then that time).
    pub fn displacement(&self, t: f64) -> [f64; 2] {
        match &self.kinematics {
            Kinematics::Prescribed(motion) => motion.displacement(t),
            Kinematics::Driven(d) => d.displacement,
        }
    }

    /// Velocity of the body at time t, m/s: the prescribed one, or the velocity a force-driven
    /// body moved with over the last step up to the current time t ([`Dynamics`]; its
    /// integration state V is in [`RigidBody::state`]).
    pub fn velocity(&self, t: f64) -> [f64; 2] {
        match &self.kinematics {
            Kinematics::Prescribed(motion) => motion.velocity(t),
            Kinematics::Driven(d) => d.step_velocity,
        }
    }

    /// Whether a point lies inside the body (closed) at time t ([`RigidBody::displacement`]).
    pub fn contains(&self, x: [f64; 2], t: f64) -> bool {
        let d = self.displacement(t);
        self.region.contains([x[0] - d[0], x[1] - d[1]])
    }

    /// Impulse since the last call of this function split into (base, shaft) (module doc), reset
    /// by the call (independently of [`Constraint::take_impulse`], which returns their sum over
    /// its own interval).
    pub fn take_impulse_parts(&mut self) -> ([f64; 2], [f64; 2]) {
        let parts = (self.impulse_base, self.impulse_shaft);
        self.impulse_base = [0.0; 2];
        self.impulse_shaft = [0.0; 2];
        parts
    }
}

impl Constraint for RigidBody {
    fn name(&self) -> &str {
        &self.name
    }

    fn apply(&mut self, context: &NodalContext, velocity: &mut [[f64; 2]], record: bool) {
        if matches!(self.enforcement, Enforcement::Penalty(_)) {
            return;
        }
        // Geometry at the end of the step, velocity the mean over the step (module doc); a
        // force-driven body's velocity is solved with the contact in the recorded call
        // ("Force-driven bodies") and kept for the re-map.
        let (_, offset, mut w) = self.step_motion(context.time, context.dt);
        if record {
            if let Kinematics::Driven(d) = &self.kinematics {
                // The body's mass per radian or per metre, as the nodes' and the impulse's.
                let mass = d.mass / if context.axisymmetric { std::f64::consts::TAU } else { 1.0 };
                w = self.contact_velocity(context, velocity, offset, w, mass, d.axial_only);
                if let Kinematics::Driven(d) = &mut self.kinematics {
                    d.contact = Some(w);
                }
            }
        }
        let (mut impulse, mut base, mut shaft, mut dissipation) = ([0.0; 2], [0.0; 2], [0.0; 2], 0.0);
        // The named parts' impulses, booked in place (taken out for the sweep, which reads `self`).
        let mut named = std::mem::take(&mut self.impulse_named);
        let (tops, contact) = (&self.part_tops, &self.contact);
        self.sweep(context, velocity, offset, w, true, |m, before, after, steps, local| {
            if !record {
                return;
            }
            impulse[0] += m * (before[0] - after[0]);
            impulse[1] += m * (before[1] - after[1]);
            // The slip left at the interface dissipates j·(v_after − w) ≥ 0 (module doc, "Energy").
            dissipation += m * ((before[0] - after[0]) * (after[0] - w[0]) + (before[1] - after[1]) * (after[1] - w[1]));
            for &(n, from, to) in steps {
                let removed = [m * (from[0] - to[0]), m * (from[1] - to[1])];
                let part = if faces_down(n) { &mut base } else { &mut shaft };
                part[0] += removed[0];
                part[1] += removed[1];
                if !named.is_empty() && removed != [0.0, 0.0] {
                    // By the height of the face's point nearest the node (module doc, "Reaction").
                    let foot = contact.foot_on_face(local, n);
                    book_named(tops, &mut named, foot[1], removed);
                }
            }
        });
        self.impulse_named = named;
        if record {
            for c in 0..2 {
                self.impulse[c] += impulse[c];
                self.step_impulse[c] += impulse[c];
                self.impulse_base[c] += base[c];
                self.impulse_shaft[c] += shaft[c];
            }
            self.interface_dissipation += dissipation;
        }
    }

    fn take_impulse(&mut self) -> [f64; 2] {
        std::mem::take(&mut self.impulse)
    }

    /// The interface's slip dissipation (module doc, "Energy"), as the tangential part.
    fn dissipated_energy(&self) -> [f64; 2] {
        [0.0, self.interface_dissipation]
    }

    /// The contact acts on the velocities of the momentum update (and the MUSL re-map), not on
    /// the start-of-step velocities: FLIP then carries the whole change v⁺ − v = Δt f/m plus the
    /// contact correction to the particles, so the material's momentum changes by exactly the
    /// impulse the body takes (module doc, "Reaction").
    fn applies_to_start_of_step(&self) -> bool {
        false
    }

    fn as_rigid_body(&self) -> Option<&RigidBody> {
        Some(self)
    }

    fn as_rigid_body_mut(&mut self) -> Option<&mut RigidBody> {
        Some(self)
    }
}

/// Adds the force `f` acting at the point `x` to the nodes of its grid cell with the bilinear
/// shape functions, shared among the nodes that carry more than `light` mass (a node without
/// mass has no momentum equation: its share would be lost, and with it the balance between the
/// material's momentum and the body's impulse). Returns whether the force was applied (no node
/// of the cell carries mass: not applied).
fn add_at_point(
    grid: &crate::grid::GridGeometry,
    mass: &[f64],
    light: f64,
    x: [f64; 2],
    f: [f64; 2],
    nodal_force: &mut [[f64; 2]],
) -> bool {
    let h = grid.cell_size;
    let mut cell = [0usize; 2];
    let mut s = [0.0; 2];
    for d in 0..2 {
        let u = ((x[d] - grid.origin[d]) / h).clamp(0.0, (grid.nodes[d] - 1) as f64);
        let i = (u.floor() as usize).min(grid.nodes[d] - 2);
        cell[d] = i;
        s[d] = u - i as f64;
    }
    let mut nodes = [(0usize, 0.0f64); 4];
    let mut carried = 0.0;
    for (k, (di, dj)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
        let node = grid.node_index(cell[0] + di, cell[1] + dj);
        let weight = (if di == 0 { 1.0 - s[0] } else { s[0] }) * (if dj == 0 { 1.0 - s[1] } else { s[1] });
        let weight = if mass[node] > light { weight } else { 0.0 };
        nodes[k] = (node, weight);
        carried += weight;
    }
    if !(carried > 0.0) {
        return false;
    }
    for (node, weight) in nodes {
        let w = weight / carried;
        nodal_force[node][0] += w * f[0];
        nodal_force[node][1] += w * f[1];
    }
    true
}

/// The names of the other constraints whose reactions share the history (grid faces, the
/// axis, `wall_i` for `walls[i]`): a rigid body may not take one.
pub fn reserved_names(wall_count: usize) -> Vec<String> {
    let faces = ["left", "right", "bottom", "top", "axis"].map(String::from);
    faces.into_iter().chain((0..wall_count).map(|i| format!("wall_{i}"))).collect()
}

/// Builds the rigid bodies of a scenario (errors name `rigid_bodies[i].key`): each by
/// [`RigidBody::from_config`], names unique and not in `reserved` ([`reserved_names`]).
/// `grid_lower`, `grid_upper`: the grid's corners (a body must lie inside the grid).
pub fn build_all(
    configs: &[RigidBodyConfig],
    grid_lower: [f64; 2],
    grid_upper: [f64; 2],
    axisymmetric: bool,
    end_time: f64,
    reserved: &[String],
) -> Result<Vec<RigidBody>, String> {
    let mut bodies: Vec<RigidBody> = Vec::with_capacity(configs.len());
    for (i, config) in configs.iter().enumerate() {
        let body = RigidBody::from_config(i, config, grid_lower, grid_upper, axisymmetric, end_time)?;
        check_name(i, &body.name, bodies.iter().map(|b| b.name.as_str()), reserved)?;
        bodies.push(body);
    }
    Ok(bodies)
}

/// `rigid_bodies[index].name` is not one of the `earlier` bodies' nor `reserved`.
pub fn check_name<'a>(
    index: usize,
    name: &str,
    mut earlier: impl Iterator<Item = &'a str>,
    reserved: &[String],
) -> Result<(), String> {
    if earlier.any(|n| n == name) {
        return Err(format!("rigid_bodies[{index}].name: '{name}' is used by another rigid body"));
    }
    if reserved.iter().any(|n| n == name) {
        return Err(format!(
            "rigid_bodies[{index}].name: '{name}' is the name of a grid face or wall (its reaction columns would clash): choose another"
        ));
    }
    Ok(())
}

/// Every problem of the `rigid_bodies` tables (`None`: a table the caller left out), at most
/// one per body, as (key, message) with the key in the engine's form
/// (`rigid_bodies[0].motion[2][0]`): for a front end, which reports them next to its own.
pub fn errors(
    tables: &[Option<Value>],
    grid_lower: [f64; 2],
    grid_upper: [f64; 2],
    axisymmetric: bool,
    end_time: f64,
    reserved: &[String],
) -> Vec<(String, String)> {
    let mut found = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for (i, table) in tables.iter().enumerate() {
        let Some(table) = table else { continue };
        let config = match crate::config::from_value_at::<RigidBodyConfig>(table) {
            Ok(config) => config,
            Err((path, message)) => {
                let dot = if path.is_empty() || path.starts_with('[') { "" } else { "." };
                found.push((format!("rigid_bodies[{i}]{dot}{path}"), message));
                continue;
            }
        };
        let checked = RigidBody::from_config(i, &config, grid_lower, grid_upper, axisymmetric, end_time)
            .and_then(|_| check_name(i, &config.name, names.iter().map(String::as_str), reserved));
        names.push(config.name);
        if let Err(e) = checked {
            // The engine's errors read "KEY: message" (keys have no ": ").
            let (key, message) = e.split_once(": ").unwrap_or((e.as_str(), ""));
            found.push((key.to_string(), message.to_string()));
        }
    }
    found
}

impl RigidBody {
    /// The body of `rigid_bodies[index]`, every value range-checked (errors name the key and
    /// the allowed range); its path must keep it inside the grid until `end_time` (not
    /// checked when it is not finite).
    pub fn from_config(
        index: usize,
        config: &RigidBodyConfig,
        grid_lower: [f64; 2],
        grid_upper: [f64; 2],
        axisymmetric: bool,
        end_time: f64,
    ) -> Result<Self, String> {
        let context = format!("rigid_bodies[{index}]");
        let name = &config.name;
        if name.is_empty() || name.contains(['.', ',']) || name.contains(char::is_whitespace) {
            return Err(format!(
                "{context}.name: must be a non-empty string without dots, commas or spaces (it names output columns; got {name:?})"
            ));
        }
        // Keys given as null (a front end may write every key of its schema) count as absent.
        let table: Map<String, Value> =
            config.region.iter().filter(|(_, v)| !v.is_null()).map(|(k, v)| (k.clone(), v.clone())).collect();
        let region = geometry::build(&context, &table)?;
        let region_keys = geometry::region_keys(&table);
        if let Some(key) = table.keys().find(|k| !region_keys.contains(&k.as_str())) {
            return Err(format!(
                "{context}.{key}: unknown key (a rigid body has name, velocity or motion (or mass, force and \
                 initial_velocity), friction, adhesion, adhesion_limit, contact, experimental, parts and its region's keys: {})",
                region_keys.join(", ")
            ));
        }
        let (lo, hi) = region.bounding_box();
        let polygon = region.outline();
        let mirror = polygon.mirrored_about(grid_lower[0]);
        let on_symmetry_plane = mirror.is_some();
        let contact = mirror.unwrap_or(polygon);
        let span = (grid_upper[0] - grid_lower[0]).max(grid_upper[1] - grid_lower[1]);
        let tol = 1e-9 * span;
        if lo[0] < grid_lower[0] - tol
            || lo[1] < grid_lower[1] - tol
            || hi[0] > grid_upper[0] + tol
            || hi[1] > grid_upper[1] + tol
        {
            return Err(format!(
                "{context}: the rigid body ({lo:?} .. {hi:?}) must lie inside the grid ({grid_lower:?} .. {grid_upper:?})"
            ));
        }
        let axial_only = "must be 0 in axisymmetric runs (only axial motion of a body of revolution";
        if config.mass.is_some() {
            // A body of revolution, or a body on the half model's symmetry plane (the grid's
            // left edge, where it is mirrored for the contact), moves along y only.
            let reason = if axisymmetric {
                axial_only.to_string()
            } else {
                format!(
                    "must be 0 for a body resting on the grid's left edge x = {} (the symmetry plane of a half model: \
                     it moves along y only",
                    grid_lower[0]
                )
            };
            let along_y = axisymmetric || on_symmetry_plane;
            let kinematics = driven(&context, config, along_y.then_some(reason.as_str()))?;
            return finish(context, config, region, contact, kinematics, lo, tol, axisymmetric);
        }
        for (key, given) in [("force", config.force.is_some()), ("initial_velocity", config.initial_velocity.is_some())] {
            if given {
                return Err(format!("{context}.{key}: belongs to a force-driven body: give its mass (kg > 0) too"));
            }
        }
        let motion = match (&config.velocity, &config.motion) {
            (Some(_), Some(_)) => return Err(format!("{context}.motion: give either velocity or motion, not both")),
            (None, None) => {
                return Err(format!("{context}.velocity: is required (or a motion table, or a mass for a force-driven body)"))
            }
            (Some(velocity), None) => {
                if velocity.iter().any(|v| !v.is_finite()) {
                    return Err(format!("{context}.velocity: must be finite (got {velocity:?})"));
                }
                if axisymmetric && velocity[0] != 0.0 {
                    return Err(format!("{context}.velocity[0]: {axial_only}; got {})", velocity[0]));
                }
                Motion::constant(*velocity)
            }
            (None, Some(rows)) => {
                let reason = axial_only.to_string();
                checked_table(&format!("{context}.motion"), rows, "[t, vx, vy]", "vx", axisymmetric.then_some(reason.as_str()))?
            }
        };
        // The path is known in advance: it must keep the body inside the grid until the end.
        if end_time.is_finite() {
            let slack = |c: [f64; 2], s: f64| [c[0] + s * tol, c[1] + s * tol];
            if let Some(t) = motion.first_exit(lo, hi, slack(grid_lower, -1.0), slack(grid_upper, 1.0), end_time) {
                let key = if config.velocity.is_some() { "velocity" } else { "motion" };
                return Err(format!(
                    "{context}.{key}: the prescribed path carries the body out of the grid at t = {t:.6e} s, \
                     before simulation.end_time = {end_time} s (the body must stay inside the grid)"
                ));
            }
        }
        finish(context, config, region, contact, Kinematics::Prescribed(motion), lo, tol, axisymmetric)
    }
}

/// A table's `mass`, `force` and `initial_velocity` as a force-driven body's [`Dynamics`]
/// (errors name the key and the allowed range).
/// `axial_only`: why the body moves along y only (None: it moves freely).
fn driven(context: &str, config: &RigidBodyConfig, axial_only: Option<&str>) -> Result<Kinematics, String> {
    for (key, given) in [("velocity", config.velocity.is_some()), ("motion", config.motion.is_some())] {
        if given {
            return Err(format!(
                "{context}.{key}: a body with a mass is driven by its force: give either mass (with force, \
                 initial_velocity) or {key}, not both"
            ));
        }
    }
    let mass = config.mass.unwrap_or(f64::NAN);
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(format!(
            "{context}.mass: must be a finite number > 0 kg (the whole body: per metre in plane strain, the whole \
             ring in axisymmetry; got {mass})"
        ));
    }
    let velocity = config.initial_velocity.unwrap_or([0.0; 2]);
    if velocity.iter().any(|v| !v.is_finite()) {
        return Err(format!("{context}.initial_velocity: must be finite m/s (got {velocity:?})"));
    }
    if let Some(reason) = axial_only.filter(|_| velocity[0] != 0.0) {
        return Err(format!("{context}.initial_velocity[0]: {reason}; got {})", velocity[0]));
    }
    let force = match &config.force {
        None => None,
        Some(rows) => Some(checked_table(&format!("{context}.force"), rows, "[t, fx, fy] (s, N)", "fx", axial_only)?),
    };
    Ok(Kinematics::Driven(Dynamics { mass, force, displacement: [0.0; 2], velocity, step_velocity: velocity, kick: [0.0; 2], contact: None,
        axial_only: axial_only.is_some() }))
}

/// A table of rows [t, a_x, a_y] linear in time (a `motion` or a `force`) checked, naming
/// `key`: non-empty, finite, times from ≥ 0 strictly increasing, and the x column `x_name` 0
/// when `axial_only` gives why.
fn checked_table(key: &str, rows: &[[f64; 3]], row_form: &str, x_name: &str, axial_only: Option<&str>) -> Result<Motion, String> {
    if rows.is_empty() {
        return Err(format!("{key}: must be a non-empty list of rows {row_form}"));
    }
    for (k, row) in rows.iter().enumerate() {
        let rk = format!("{key}[{k}]");
        if row.iter().any(|v| !v.is_finite()) {
            return Err(format!("{rk}: must be finite (got {row:?})"));
        }
        if k == 0 && row[0] < 0.0 {
            return Err(format!("{rk}[0]: the first time must be >= 0 s (got {})", row[0]));
        }
        if k > 0 && !(row[0] > rows[k - 1][0]) {
            return Err(format!("{rk}[0]: times must increase strictly (got {} after {})", row[0], rows[k - 1][0]));
        }
        if let Some(reason) = axial_only.filter(|_| row[1] != 0.0) {
            return Err(format!("{rk}[1]: {x_name} {reason}; got {})", row[1]));
        }
    }
    Ok(Motion::table(rows))
}

/// The checks and settings every rigid body shares after its motion: the contact, the region
/// at r ≥ 0 in axisymmetry, the adhesion.
#[allow(clippy::too_many_arguments)]
fn finish(
    context: String,
    config: &RigidBodyConfig,
    region: Box<dyn Region>,
    contact: Polygon,
    kinematics: Kinematics,
    lo: [f64; 2],
    tol: f64,
    axisymmetric: bool,
) -> Result<RigidBody, String> {
    let enforcement = match config.contact {
        ContactKind::Nodes => Enforcement::Nodes,
        // The stiffness follows from the material and the grid (the solver sets it).
        ContactKind::Penalty => Enforcement::Penalty(0.0),
    };
    // The penalty contact was measured and not adopted (its footing N_c is 8–20 % high,
    // docs/studies/contact-remedies.md): it is run only when asked for explicitly.
    if config.contact == ContactKind::Penalty && !config.experimental {
        return Err(format!("{context}.contact: {PENALTY_IS_EXPERIMENTAL}"));
    }
    if config.mass.is_some() && config.contact == ContactKind::Penalty {
        return Err(format!(
            "{context}.contact: a force-driven body (with a mass) uses the nodal contact, \"nodes\" (its velocity is \
             solved with the contact's impulse there)"
        ));
    }
    if axisymmetric && lo[0] < -tol {
        return Err(format!("{context}: an axisymmetric rigid body must lie at r >= 0 (its region reaches r = {})", lo[0]));
    }
    if !(config.adhesion >= 0.0 && config.adhesion.is_finite()) {
        return Err(format!("{context}.adhesion: must be a finite number >= 0 Pa (got {})", config.adhesion));
    }
    if let Some(limit) = config.adhesion_limit {
        if !(limit > 0.0 && limit.is_finite()) {
            return Err(format!("{context}.adhesion_limit: must be a finite number > 0 Pa (got {limit})"));
        }
    }
    let mut parts: Vec<(String, f64)> = Vec::with_capacity(config.parts.len());
    for (k, part) in config.parts.iter().enumerate() {
        let key = format!("{context}.parts[{k}]");
        let part_name = &part.name;
        if part_name.is_empty() || part_name.contains(['.', ',']) || part_name.contains(char::is_whitespace) {
            return Err(format!(
                "{key}.name: must be a non-empty string without dots, commas or spaces (it names output columns; got {part_name:?})"
            ));
        }
        if RESERVED_PART_NAMES.contains(&part_name.as_str()) || parts.iter().any(|(n, _)| n == part_name) {
            return Err(format!(
                "{key}.name: '{part_name}' is taken (parts are named once, and not {}: their columns are written anyway)",
                RESERVED_PART_NAMES.join(", ")
            ));
        }
        let below = part.below;
        let floor = parts.last().map_or(0.0, |(_, b)| *b);
        if !(below.is_finite() && below > floor) {
            return Err(format!(
                "{key}.below: must be a finite height > {floor} m (above the body's lowest point and the previous part's; got {below})"
            ));
        }
        parts.push((part_name.clone(), below));
    }
    let mut body = RigidBody::new(config.name.clone(), region, contact, kinematics, config.friction).with_parts(&parts);
    body.enforcement = enforcement;
    body.adhesion = config.adhesion;
    body.adhesion_limit = config.adhesion_limit.unwrap_or(f64::INFINITY);
    Ok(body)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::GridGeometry;
    use serde_json::json;

    /// The base/shaft split: a face steeper than 45° from horizontal is shaft; a 45° face (a
    /// cone tip of 90°) is shaft too, by the strict inequality; a flat base is base.
    #[test]
    fn faces_down_splits_base_from_shaft_at_45_degrees() {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        assert!(faces_down([0.0, -1.0]));
        assert!(faces_down([0.5, -0.9]));
        assert!(!faces_down([s, -s]), "a 45° face counts as shaft");
        assert!(!faces_down([1.0, 0.0]) && !faces_down([0.0, 1.0]));
    }

    #[test]
    fn motion_table_velocity_and_exact_displacement() {
        let m = Motion::table(&[[0.5, 0.0, 0.0], [1.5, 0.0, -2.0], [2.0, 1.0, -2.0]]);
        assert_eq!(m.velocity(0.2), [0.0, 0.0]);
        assert_eq!(m.velocity(1.0), [0.0, -1.0]);
        assert_eq!(m.velocity(1.75), [0.5, -2.0]);
        assert_eq!(m.velocity(9.0), [1.0, -2.0]);
        // D(t) against a fine midpoint quadrature of the velocity.
        for t in [0.3, 0.5, 0.9, 1.5, 1.8, 2.0, 3.25] {
            let n = 200_000;
            let mut q = [0.0; 2];
            for k in 0..n {
                let v = m.velocity((k as f64 + 0.5) * t / n as f64);
                q[0] += v[0] * t / n as f64;
                q[1] += v[1] * t / n as f64;
            }
            let d = m.displacement(t);
            assert!((d[0] - q[0]).abs() < 1e-8 && (d[1] - q[1]).abs() < 1e-8, "t {t}: {d:?} vs {q:?}");
        }
        // By hand: ramp 0 → −2 over [0.5, 1.5] moves −1; then 0.5 s at −2 → −2 (+ x: ½·1·0.5).
        let d = m.displacement(2.0);
        assert!((d[0] - 0.25).abs() < 1e-15 && (d[1] + 2.0).abs() < 1e-15, "{d:?}");
        let c = Motion::constant([0.1, -0.2]);
        assert_eq!(c.displacement(2.0), [0.2, -0.4]);
        let w = c.mean_velocity(1.0, 1e-3);
        assert!((w[0] - 0.1).abs() < 1e-12 && (w[1] + 0.2).abs() < 1e-12);
    }

    /// The first exit from the grid [0, 1]² of the box [0.4, 0.6]² by hand: at 1 m/s up it
    /// leaves at t = 0.4; with v = 1 − 2t its displacement t − t² peaks at 0.25 (t = 0.5), so
    /// a box reaching 0.8 leaves where 0.8 + t − t² = 1, t = (1 − √0.2)/2, unless the run ends
    /// before.
    #[test]
    fn first_exit_from_the_grid_by_hand() {
        let (lo, hi, lower, upper) = ([0.4, 0.4], [0.6, 0.6], [0.0, 0.0], [1.0, 1.0]);
        let t = Motion::constant([0.0, 1.0]).first_exit(lo, hi, lower, upper, 1.0).unwrap();
        assert!((t - 0.4).abs() < 1e-11, "{t}");
        assert_eq!(Motion::constant([0.0, 1.0]).first_exit(lo, hi, lower, upper, 0.39), None);
        let up_and_down = Motion::table(&[[0.0, 0.0, 1.0], [1.0, 0.0, -1.0]]);
        let tall = [0.6, 0.8];
        let t = up_and_down.first_exit(lo, tall, lower, upper, 2.0).unwrap();
        assert!((t - 0.5 * (1.0 - 0.2f64.sqrt())).abs() < 1e-11, "{t}");
        assert_eq!(up_and_down.first_exit(lo, tall, lower, upper, 0.2), None);
        // Lower, it turns back inside and leaves through the bottom once D = −0.4 (t = 1.4).
        let t = up_and_down.first_exit(lo, hi, lower, upper, 2.0).unwrap();
        assert!((t - 1.4).abs() < 1e-11, "{t}");
        // Sideways (x) and downwards too; a table that starts late stays until its first row.
        let t = Motion::table(&[[0.5, -2.0, 0.0], [1.0, -2.0, 0.0]]).first_exit(lo, hi, lower, upper, 9.0).unwrap();
        assert!((t - 0.2).abs() < 1e-11, "{t}");
        let t = Motion::table(&[[0.5, 0.0, 0.0], [0.5 + 1e-9, 0.0, -1.0]]).first_exit(lo, hi, lower, upper, 9.0).unwrap();
        assert!((t - 0.9).abs() < 1e-8, "{t}");
        // The path of the user report: out at once.
        let t = Motion::table(&[[0.0, 0.0, 1e308], [1.0, 0.0, 1e308]]).first_exit(lo, hi, lower, upper, 1.0).unwrap();
        assert!(t < 1e-300, "{t}");
    }

    #[test]
    fn a_path_that_leaves_the_grid_is_refused_naming_the_key_and_the_time() {
        let configs: Vec<RigidBodyConfig> = serde_json::from_value(json!([{"name": "pile", "min": [0.4, 0.4],
            "max": [0.6, 0.6], "motion": [[0, 0, 1e308], [1, 0, 1e308]]}])).unwrap();
        let e = build_all(&configs, [0.0; 2], [1.0; 2], false, 1.0, &[]).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].motion: the prescribed path carries the body out of the grid at t = "), "{e}");
        let configs: Vec<RigidBodyConfig> = serde_json::from_value(json!([{"name": "pile", "min": [0.4, 0.4],
            "max": [0.6, 0.6], "velocity": [0.0, -0.5]}])).unwrap();
        let e = build_all(&configs, [0.0; 2], [1.0; 2], false, 1.0, &[]).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].velocity:") && e.contains("t = 8.000000e-1 s"), "{e}");
        assert!(build_all(&configs, [0.0; 2], [1.0; 2], false, 0.79, &[]).is_ok());
    }

    /// Adhesion at the nodes by hand: a pile [0, 0.25] × [0, 1] against the grid's left edge,
    /// rising at 1 m/s past material at rest (h = 0.25, m = 2 per node, Δt = 10⁻³, a = 100
    /// Pa). The node (1, 2) on its side face (normal +x, the material neither approaching nor
    /// leaving) represents the face's length h = 0.25 (× its radius 0.25 per radian in
    /// axisymmetry): it is dragged up by a A Δt/m = 0.0125 m/s (0.003125), or by the limit's
    /// when a_lim = 50 Pa; the node (0, 2) inside the pile, a whole cell from the face, is not.
    #[test]
    fn adhesion_drags_the_nodes_of_a_face_by_its_area() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let pile = |extra: Value| {
            let mut t = table(json!({"name": "pile", "min": [0.0, 0.0], "max": [0.25, 1.0], "velocity": [0.0, 1.0]}));
            t.extend(table(extra));
            Value::Object(t)
        };
        let mass = vec![2.0; grid.num_nodes()];
        for (axisymmetric, extra, drag) in [
            (false, json!({"adhesion": 100.0}), 0.0125),
            (false, json!({"adhesion": 100.0, "adhesion_limit": 50.0}), 0.00625),
            (true, json!({"adhesion": 100.0}), 0.003125),
            (false, json!({}), 0.0),
        ] {
            let mut b = build(json!([pile(extra)]), axisymmetric).unwrap().pop().unwrap();
            let mut v = vec![[0.0, 0.0]; grid.num_nodes()];
            let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-3, axisymmetric };
            b.apply(&context, &mut v, true);
            let got = v[grid.node_index(1, 2)];
            assert!(got[0] == 0.0 && (got[1] - drag).abs() < 1e-15, "axisymmetric {axisymmetric}: {got:?} vs {drag}");
            assert_eq!(v[grid.node_index(0, 2)], [0.0, 0.0]);
            // The impulse on the pile is the momentum given to the material (shaft part).
            let (_, shaft) = b.take_impulse_parts();
            assert!(shaft[1] <= -2.0 * drag + 1e-15, "{shaft:?}");
        }
        // Where the material ends along the face (no mass at the node above) the node stands
        // for the half band below it only.
        let mut ended = mass.clone();
        ended[grid.node_index(1, 3)] = 0.0;
        let mut b = build(json!([pile(json!({"adhesion": 100.0}))]), false).unwrap().pop().unwrap();
        let mut v = vec![[0.0, 0.0]; grid.num_nodes()];
        b.apply(&NodalContext { grid: &grid, mass: &ended, time: 0.0, dt: 1e-3, axisymmetric: false }, &mut v, true);
        assert!((v[grid.node_index(1, 2)][1] - 0.00625).abs() < 1e-15, "{:?}", v[grid.node_index(1, 2)]);
        let e = build(json!([pile(json!({"adhesion": -1.0}))]), false).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].adhesion: must be a finite number >= 0 Pa"), "{e}");
        let e = build(json!([pile(json!({"adhesion_limit": 0.0}))]), false).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].adhesion_limit: must be a finite number > 0 Pa"), "{e}");
    }

    fn table(v: Value) -> Map<String, Value> {
        let Value::Object(m) = v else { unreachable!() };
        m
    }

    fn square_body(extra: Value) -> Value {
        let mut t = table(json!({"name": "plate", "shape": "polygon",
                                  "vertices": [[0.25, 0.5], [0.75, 0.5], [0.75, 0.75], [0.25, 0.75]]}));
        t.extend(table(extra));
        Value::Object(t)
    }

    fn build(bodies: Value, axisymmetric: bool) -> Result<Vec<RigidBody>, String> {
        let configs: Vec<RigidBodyConfig> =
            crate::config::from_value_named(&bodies).map_err(|e| format!("rigid_bodies{e}"))?;
        build_all(&configs, [0.0, 0.0], [1.0, 1.0], axisymmetric, f64::INFINITY, &reserved_names(1))
    }

    #[test]
    fn bad_rigid_bodies_are_rejected_naming_the_key() {
        let err = |b: Value, axi: bool| build(json!([b]), axi).err().expect("must be rejected");
        let e = err(square_body(json!({"motion": [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0], [1.0, 0.0, 0.0]]})), false);
        assert!(e.starts_with("rigid_bodies[0].motion[2][0]") && e.contains("increase"), "{e}");
        let e = err(square_body(json!({"velocity": [0.0, -1.0], "friction": -0.1})), false);
        assert!(e.starts_with("rigid_bodies[0].friction"), "{e}");
        assert!(err(square_body(json!({"velocity": [0.0, -1.0], "friction": "sticky"})), false).contains("rough"));
        let e = err(square_body(json!({"velocity": [0.1, -1.0]})), true);
        assert!(e.starts_with("rigid_bodies[0].velocity[0]") && e.contains("axisymmetric"), "{e}");
        let e = err(square_body(json!({"motion": [[0.0, 0.0, -1.0], [1.0, 0.2, -1.0]]})), true);
        assert!(e.starts_with("rigid_bodies[0].motion[1][1]"), "{e}");
        let outside = json!({"name": "p", "shape": "polygon", "vertices": [[0.5, 0.5], [1.5, 0.5], [1.0, 0.9]],
                             "velocity": [0.0, 0.0]});
        assert!(err(outside, false).contains("inside the grid"));
        let bow_tie = json!({"name": "p", "shape": "polygon", "vertices": [[0, 0], [1, 1], [1, 0], [0, 1]],
                             "velocity": [0.0, 0.0]});
        assert!(err(bow_tie, false).starts_with("rigid_bodies[0].vertices"));
        assert!(err(square_body(json!({})), false).contains("velocity"));
        assert!(err(square_body(json!({"velocity": [0, 0], "motion": [[0, 0, 0]]})), false).contains("not both"));
        assert!(err(square_body(json!({"velocity": [0, 0], "name": "a.b"})), false).starts_with("rigid_bodies[0].name"));
        let e = build(json!([square_body(json!({"velocity": [0, 0]})), square_body(json!({"velocity": [0, 0]}))]), false);
        assert!(e.err().unwrap().starts_with("rigid_bodies[1].name"));
        let ok = build(json!([square_body(json!({"motion": [[0.0, 0.0, 0.0], [1.0, 0.0, -1.0]], "friction": "rough"}))]), true)
            .unwrap();
        assert_eq!(ok[0].friction(), Friction::Rough);
        assert!(build_all(&[], [0.0; 2], [1.0; 2], false, 1.0, &[]).unwrap().is_empty());
        // Names of the faces and walls are taken; a key no rigid body has is refused.
        let e = err(square_body(json!({"velocity": [0, 0], "name": "wall_0"})), false);
        assert!(e.starts_with("rigid_bodies[0].name") && e.contains("grid face or wall"), "{e}");
        let e = err(square_body(json!({"velocity": [0, 0], "min": [0.0, 0.0]})), false);
        assert!(e.starts_with("rigid_bodies[0].min: unknown key") && e.contains("vertices"), "{e}");
        let e = err(square_body(json!({"velocity": [0, 0], "frcition": 0.2})), false);
        assert!(e.starts_with("rigid_bodies[0].frcition: unknown key"), "{e}");
        // The type errors name the key too.
        let e = err(square_body(json!({"velocity": [0, 0, 1]})), false);
        assert!(e.starts_with("rigid_bodies[0].velocity:"), "{e}");
        let e = err(square_body(json!({"velocity": [0, 0], "friction": true})), false);
        assert!(e.starts_with("rigid_bodies[0].friction: must be a number >= 0"), "{e}");
        // Named parts: names once, not those of the normal split or rest; heights > 0, increasing.
        let parts = |p: Value| err(square_body(json!({"velocity": [0, 0], "parts": p})), false);
        let e = parts(json!([{"name": "rest", "below": 0.1}]));
        assert!(e.starts_with("rigid_bodies[0].parts[0].name: 'rest' is taken"), "{e}");
        let e = parts(json!([{"name": "tip", "below": 0.1}, {"name": "base", "below": 0.2}]));
        assert!(e.starts_with("rigid_bodies[0].parts[1].name"), "{e}");
        let e = parts(json!([{"name": "tip", "below": 0.1}, {"name": "tip", "below": 0.2}]));
        assert!(e.starts_with("rigid_bodies[0].parts[1].name: 'tip' is taken"), "{e}");
        let e = parts(json!([{"name": "a b", "below": 0.1}]));
        assert!(e.starts_with("rigid_bodies[0].parts[0].name: must be a non-empty string"), "{e}");
        let e = parts(json!([{"name": "tip", "below": 0.0}]));
        assert!(e.starts_with("rigid_bodies[0].parts[0].below: must be a finite height > 0 m"), "{e}");
        let e = parts(json!([{"name": "tip", "below": 0.2}, {"name": "sleeve", "below": 0.2}]));
        assert!(e.starts_with("rigid_bodies[0].parts[1].below: must be a finite height > 0.2 m"), "{e}");
        let e = parts(json!([{"name": "tip", "above": 0.2}]));
        assert!(e.starts_with("rigid_bodies[0].parts[0]") && e.contains("above"), "{e}");
    }

    /// The keys of a force-driven body: refused values name the key and the allowed range.
    #[test]
    fn bad_force_driven_bodies_are_rejected_naming_the_key() {
        let err = |b: Value, axi: bool| build(json!([b]), axi).err().expect("must be rejected");
        let e = err(square_body(json!({"mass": 0.0})), false);
        assert!(e.starts_with("rigid_bodies[0].mass: must be a finite number > 0 kg"), "{e}");
        assert!(err(square_body(json!({"mass": -1.0})), false).starts_with("rigid_bodies[0].mass:"));
        // NaN (TOML nan) arrives as a non-number in JSON: the type error names the key.
        let e = err(square_body(json!({"mass": "nan"})), false);
        assert!(e.starts_with("rigid_bodies[0].mass"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "velocity": [0.0, -1.0]})), false);
        assert!(e.starts_with("rigid_bodies[0].velocity: a body with a mass") && e.contains("not both"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "motion": [[0.0, 0.0, -1.0]]})), false);
        assert!(e.starts_with("rigid_bodies[0].motion: a body with a mass"), "{e}");
        let e = err(square_body(json!({"velocity": [0.0, -1.0], "force": [[0.0, 0.0, -1.0]]})), false);
        assert!(e.starts_with("rigid_bodies[0].force: belongs to a force-driven body"), "{e}");
        let e = err(square_body(json!({"velocity": [0.0, -1.0], "initial_velocity": [0.0, 1.0]})), false);
        assert!(e.starts_with("rigid_bodies[0].initial_velocity: belongs to a force-driven body"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "force": [[0.0, 0.0, -1.0], [0.0, 0.0, -2.0]]})), false);
        assert!(e.starts_with("rigid_bodies[0].force[1][0]: times must increase strictly"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "force": [[-1.0, 0.0, -1.0]]})), false);
        assert!(e.starts_with("rigid_bodies[0].force[0][0]: the first time must be >= 0"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "force": []})), false);
        assert!(e.starts_with("rigid_bodies[0].force: must be a non-empty list"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "force": [[0.0, 1.0, -1.0]]})), true);
        assert!(e.starts_with("rigid_bodies[0].force[0][1]: fx must be 0 in axisymmetric runs"), "{e}");
        let e = err(square_body(json!({"mass": 1.0, "initial_velocity": [0.5, 0.0]})), true);
        assert!(e.starts_with("rigid_bodies[0].initial_velocity[0]: must be 0 in axisymmetric runs"), "{e}");
        // On the half model's symmetry plane (the grid's left edge) a body moves along y only.
        let half = json!({"name": "footing", "min": [0.0, 0.5], "max": [0.25, 0.75], "mass": 1.0,
                          "force": [[0.0, 0.5, -1.0]]});
        let e = err(half, false);
        assert!(e.starts_with("rigid_bodies[0].force[0][1]: fx must be 0 for a body resting on the grid's left edge"), "{e}");
        let half = json!({"name": "footing", "min": [0.0, 0.5], "max": [0.25, 0.75], "mass": 1.0, "initial_velocity": [0.1, 0.0]});
        assert!(err(half, false).starts_with("rigid_bodies[0].initial_velocity[0]: must be 0 for a body resting"));
        let e = err(square_body(json!({"mass": 1.0, "contact": "penalty", "experimental": true})), false);
        assert!(e.starts_with("rigid_bodies[0].contact: a force-driven body"), "{e}");
        let ok = build(json!([square_body(json!({"mass": 2.0, "force": [[0.0, 0.0, -1.0], [1.0, 0.0, -3.0]],
                                                  "initial_velocity": [0.0, -0.5]}))]), true)
            .unwrap();
        assert!(matches!(ok[0].kinematics(), Kinematics::Driven(_)));
        assert_eq!(ok[0].velocity(0.0), [0.0, -0.5]);
        assert_eq!(ok[0].displacement(0.0), [0.0, 0.0]);
    }

    /// One step of a force-driven body by hand: M = 2 kg per metre at V = (0.5, −1), force
    /// ramping from (2, −4) N at t = 0 to (4, −8) N at t = 1, gravity (0, −10), dt = 0.1 from
    /// t = 0.5: the force's impulse is ∫ F = 0.1 × (3.1, −6.2) = (0.31, −0.62) N s (F at the
    /// step's middle), so ΔV_ext = (0.155, −0.31 − 1) = (0.155, −1.31); without contact w = V + ΔV_ext/2,
    /// X = dt w and V ← V + ΔV_ext. In axisymmetry the radial parts stay 0. A contact impulse J
    /// (per metre) adds J/M to V; the body's work is −J·w.
    #[test]
    fn a_force_driven_step_by_hand() {
        let body = square_body(json!({"mass": 2.0, "initial_velocity": [0.5, -1.0],
                                      "force": [[0.0, 2.0, -4.0], [1.0, 4.0, -8.0]]}));
        let mut b = build(json!([body]), false).unwrap().pop().unwrap();
        b.begin_step(0.5, 0.1, [0.0, -10.0]);
        let close = |a: [f64; 2], e: [f64; 2]| (a[0] - e[0]).abs() < 1e-14 && (a[1] - e[1]).abs() < 1e-14;
        let kick = [0.155, -1.31];
        let w = [0.5 + 0.5 * kick[0], -1.0 + 0.5 * kick[1]];
        let (start, end, mean) = b.step_motion(0.5, 0.1);
        assert!(start == [0.0; 2] && close(mean, w) && close(end, [0.1 * w[0], 0.1 * w[1]]), "{end:?} {mean:?}");
        b.step_impulse = [0.3, 0.8];
        b.end_step(0.5, 0.1, 1.0);
        assert!(close(b.displacement(0.6), [0.1 * w[0], 0.1 * w[1]]), "{:?}", b.displacement(0.6));
        let v = [0.5 + kick[0] + 0.3 / 2.0, -1.0 + kick[1] + 0.8 / 2.0];
        assert!(close(b.state().velocity, v), "{:?} vs {v:?}", b.state().velocity);
        // Reported: the velocity it moved with over the step.
        assert!(close(b.velocity(0.6), w), "{:?} vs {w:?}", b.velocity(0.6));
        assert!((b.work() + 0.3 * w[0] + 0.8 * w[1]).abs() < 1e-15, "{}", b.work());
        assert_eq!(b.step_impulse, [0.0; 2], "taken by the step");
        // The state round-trips through a checkpoint's record.
        let state = b.state();
        let mut c = build(json!([square_body(json!({"mass": 2.0}))]), false).unwrap().pop().unwrap();
        c.restore(&state);
        assert_eq!(c.state(), b.state());
        // Axisymmetric: the whole ring's impulse is 2π times the per-radian one, axial only.
        let body = square_body(json!({"mass": 2.0, "initial_velocity": [0.0, -1.0], "force": [[0.0, 0.0, -4.0]]}));
        let mut b = build(json!([body]), true).unwrap().pop().unwrap();
        b.begin_step(0.0, 0.1, [1.0, -10.0]);
        b.step_impulse = [0.3, 0.8];
        b.end_step(0.0, 0.1, std::f64::consts::TAU);
        let v = b.state().velocity;
        assert!(v[0] == 0.0 && (v[1] - (-1.0 - 0.2 - 1.0 + std::f64::consts::TAU * 0.8 / 2.0)).abs() < 1e-14, "{v:?}");
        assert!((b.displacement(0.1)[1] - 0.1 * (-1.0 - 0.6)).abs() < 1e-15);
        // A body on the symmetry plane (plane strain) keeps vx = 0 whatever the impulse.
        let half = json!({"name": "footing", "min": [0.0, 0.5], "max": [0.25, 0.75], "mass": 2.0});
        let mut b = build(json!([half]), false).unwrap().pop().unwrap();
        b.begin_step(0.0, 0.1, [1.0, 0.0]);
        b.step_impulse = [0.3, 0.8];
        b.end_step(0.0, 0.1, 1.0);
        assert_eq!(b.state().velocity, [0.0, 0.4]);
        // A prescribed body books its work too, and does not move by it.
        let mut p = build(json!([square_body(json!({"velocity": [0.0, -2.0]}))]), false).unwrap().pop().unwrap();
        p.step_impulse = [1.0, 3.0];
        p.end_step(0.0, 0.1, 1.0);
        assert!((p.work() - 6.0).abs() < 1e-15, "{}", p.work());
        assert!((p.displacement(0.1)[1] + 0.2).abs() < 1e-15);
    }

    /// On a 4 × 4-cell grid (h = 0.25) the plate [0.25, 0.75] × [0.5, 0.75] (moving down, by
    /// less than the boundary tolerance over the step) covers the nodes i = 1..3, j = 2..3.
    /// Material moving at (0.5, 0) everywhere: only the covered nodes with mass change, by the
    /// contact law with the face normals (both faces at the corners), and the impulse is
    /// Σ m (v − v') split into the base (corrections along a normal facing down) and the rest.
    /// By hand (smooth, m = 2):
    /// base interior (2, 2) → (0.5, −1); bottom-left corner (1, 2) → (0, −1) (base, then left
    /// side); bottom-right (3, 2) → (0.5, −1) (moving away from the right side); top-left
    /// (1, 3) → (0, 0) (leaving the top, into the left side); (2, 3) has no mass; top-right
    /// (3, 3) unchanged. Base impulse (0, 6), shaft (2, 0).
    #[test]
    fn covered_nodes_are_corrected_and_the_impulse_is_the_removed_momentum() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let body = square_body(json!({"velocity": [0.0, -1.0]}));
        let mut bodies = build(json!([body]), false).unwrap();
        let b = &mut bodies[0];
        let n = grid.num_nodes();
        let mut mass = vec![2.0; n];
        mass[grid.node_index(2, 3)] = 0.0;
        let mut v = vec![[0.5, 0.0]; n];
        let dt = 1e-13;
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt, axisymmetric: false };
        b.apply(&context, &mut v, true);
        let want = [((2, 2), [0.5, -1.0]), ((1, 2), [0.0, -1.0]), ((3, 2), [0.5, -1.0]), ((1, 3), [0.0, 0.0])];
        for j in 0..5 {
            for i in 0..5 {
                let got = v[grid.node_index(i, j)];
                let expect = want.iter().find(|(ij, _)| *ij == (i, j)).map_or([0.5, 0.0], |w| w.1);
                assert!((got[0] - expect[0]).abs() < 1e-9 && (got[1] - expect[1]).abs() < 1e-9, "({i}, {j}): {got:?}");
            }
        }
        let (base, shaft) = b.take_impulse_parts();
        assert!(base[0].abs() < 1e-9 && (base[1] - 6.0).abs() < 1e-9, "base {base:?}");
        assert!((shaft[0] - 2.0).abs() < 1e-9 && shaft[1].abs() < 1e-9, "shaft {shaft:?}");
        // The total has its own accumulator: base + shaft, then reset.
        let total = b.take_impulse();
        assert!((total[0] - 2.0).abs() < 1e-9 && (total[1] - 6.0).abs() < 1e-9, "{total:?}");
        assert_eq!(b.take_impulse(), [0.0, 0.0], "reset by the call");
        assert_eq!(b.take_impulse_parts(), ([0.0; 2], [0.0; 2]), "reset by the call");
        // Not recorded: the same correction, no impulse.
        let mut v = vec![[0.5, 0.0]; n];
        b.apply(&context, &mut v, false);
        assert_eq!(v[grid.node_index(1, 2)], [0.0, -1.0]);
        assert_eq!(b.take_impulse(), [0.0, 0.0]);
        // At the end of a longer step the plate has left the top row: those nodes are free.
        let mut v = vec![[0.5, 0.0]; n];
        let later = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 0.01, axisymmetric: false };
        b.apply(&later, &mut v, true);
        assert_eq!(v[grid.node_index(1, 3)], [0.5, 0.0]);
        assert!((v[grid.node_index(2, 2)][1] + 1.0).abs() < 1e-12);
        let total = b.take_impulse();
        // Base interior and bottom-right: (0, 2) each; bottom-left (left face, then the base
        // within the tie): (1, 2).
        assert!((total[0] - 1.0).abs() < 1e-9 && (total[1] - 6.0).abs() < 1e-9, "{total:?}");
    }

    /// The energy of the contact by hand: the plate's base (normal −y) moving down at 1 m/s
    /// over one node of mass 2 sliding at 0.5 m/s, Coulomb 0.2: the node approaches at 1 m/s,
    /// keeps 0.5 − 0.2 × 1 = 0.3 m/s of slip, so j = 2 (0.2, 1) = (0.4, 2); the slip left
    /// dissipates j·(v_after − w) = 0.4 × 0.3 = 0.12 J, and the step's work on the material is
    /// −J·w = 2 J. Unrecorded calls book nothing.
    #[test]
    fn the_contact_books_the_slip_dissipation_and_the_work() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let mut b = build(json!([square_body(json!({"velocity": [0.0, -1.0], "friction": 0.2}))]), false).unwrap().pop().unwrap();
        let mut mass = vec![0.0; grid.num_nodes()];
        let node = grid.node_index(2, 2);
        mass[node] = 2.0;
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-13, axisymmetric: false };
        let mut v = vec![[0.0; 2]; grid.num_nodes()];
        v[node] = [0.5, 0.0];
        b.apply(&context, &mut v, false);
        assert_eq!(b.dissipated_energy(), [0.0, 0.0]);
        v[node] = [0.5, 0.0];
        b.apply(&context, &mut v, true);
        assert!((v[node][0] - 0.3).abs() < 1e-12 && (v[node][1] + 1.0).abs() < 1e-12, "{:?}", v[node]);
        let [normal, slip] = b.dissipated_energy();
        assert!(normal == 0.0 && (slip - 0.12).abs() < 1e-12, "{slip}");
        b.end_step(0.0, 1e-13, 1.0);
        assert!((b.work() - 2.0).abs() < 1e-9, "{}", b.work());
    }

    /// A force-driven plate (2 kg per metre, no force, no gravity) meets material at rest: the
    /// three base nodes of the 4 × 4 grid (mass 1 each) and the plate end the step with one
    /// velocity, the centre of mass one: moving down at 1 m/s, smooth: 2 × (−1)/(2 + 3) = −0.4
    /// m/s; moving at (1, −1) m/s, rough: (0.4, −0.4). The nodes take the impulse −J, the
    /// plate +J (J = 3 × 0.4 per component), so the momentum 2 × w₀ is kept; the re-map of the
    /// step uses the same velocity.
    #[test]
    fn a_force_driven_body_and_the_nodes_it_hits_share_one_velocity() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let mut mass = vec![0.0; grid.num_nodes()];
        let base = [grid.node_index(1, 2), grid.node_index(2, 2), grid.node_index(3, 2)];
        for &n in &base {
            mass[n] = 1.0;
        }
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-13, axisymmetric: false };
        for (v0, friction, w) in [([0.0, -1.0], json!(0.0), [0.0, -0.4]), ([1.0, -1.0], json!("rough"), [0.4, -0.4])] {
            let body = square_body(json!({"mass": 2.0, "initial_velocity": v0, "friction": friction}));
            let mut b = build(json!([body]), false).unwrap().pop().unwrap();
            b.begin_step(0.0, 1e-13, [0.0, 0.0]);
            let mut v = vec![[0.0; 2]; grid.num_nodes()];
            b.apply(&context, &mut v, true);
            for &n in &base {
                assert!((v[n][0] - w[0]).abs() < 1e-12 && (v[n][1] - w[1]).abs() < 1e-12, "{friction}: {:?}", v[n]);
            }
            let mut remapped = vec![[0.0; 2]; grid.num_nodes()];
            b.apply(&context, &mut remapped, false);
            assert_eq!(remapped[base[1]], v[base[1]], "{friction}: the re-map uses the solved velocity");
            let j = b.step_impulse;
            assert!((j[0] + 3.0 * w[0]).abs() < 1e-12 && (j[1] + 3.0 * w[1]).abs() < 1e-12, "{friction}: {j:?}");
            b.end_step(0.0, 1e-13, 1.0);
            let v_body = b.state().velocity;
            for c in 0..2 {
                assert!((2.0 * v_body[c] + 3.0 * w[c] - 2.0 * v0[c]).abs() < 1e-12, "{friction}: momentum {v_body:?}");
                assert!((b.velocity(0.0)[c] - w[c]).abs() < 1e-12);
            }
        }
        // Axisymmetric: the same per radian with the ring's mass 2π × 2 kg, axial only.
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-13, axisymmetric: true };
        let body = square_body(json!({"mass": 2.0 * std::f64::consts::TAU, "initial_velocity": [0.0, -1.0]}));
        let mut b = build(json!([body]), true).unwrap().pop().unwrap();
        b.begin_step(0.0, 1e-13, [0.0, 0.0]);
        let mut v = vec![[0.0; 2]; grid.num_nodes()];
        b.apply(&context, &mut v, true);
        assert!((v[base[1]][1] + 0.4).abs() < 1e-12 && v[base[1]][0] == 0.0, "{:?}", v[base[1]]);
    }

    /// Named parts by height, on the plate and material of the test above (smooth, m = 2,
    /// lowest point y = 0.5): with `tip` below 0.1 the whole base row (y = 0.5, height 0) goes
    /// to the tip, the bottom-left corner's side correction included (its foot on the side face
    /// is the corner): (1, 2) + (0, 2) + (0, 2) = (1, 6), where the normal split gives that
    /// corner's x part to the shaft; the top-left node (1, 3) is corrected by the top and the
    /// left faces with feet at its own place (height 0.25): (1, 0) to `rest` with a sleeve
    /// below 0.24, to the sleeve with a sleeve below 0.25 (a part's upper end is its own).
    /// Each split sums to the total.
    #[test]
    fn named_parts_take_the_reaction_of_the_nodes_at_their_height() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let n = grid.num_nodes();
        let mut mass = vec![2.0; n];
        mass[grid.node_index(2, 3)] = 0.0;
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-13, axisymmetric: false };
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9;
        for (sleeve_top, sleeve, rest) in [(0.24, [0.0, 0.0], [1.0, 0.0]), (0.25, [1.0, 0.0], [0.0, 0.0])] {
            let parts = json!([{"name": "tip", "below": 0.1}, {"name": "sleeve", "below": sleeve_top}]);
            let mut b = build(json!([square_body(json!({"velocity": [0.0, -1.0], "parts": parts}))]), false)
                .unwrap()
                .pop()
                .unwrap();
            let mut v = vec![[0.5, 0.0]; n];
            b.apply(&context, &mut v, true);
            let named = b.take_named_parts();
            let names: Vec<&str> = named.iter().map(|(name, _)| name.as_str()).collect();
            assert_eq!(names, ["tip", "sleeve", "rest"]);
            assert!(close(named[0].1, [1.0, 6.0]), "tip {named:?}");
            assert!(close(named[1].1, sleeve) && close(named[2].1, rest), "below {sleeve_top}: {named:?}");
            let total = b.take_impulse();
            let sum = named.iter().fold([0.0; 2], |a, (_, i)| [a[0] + i[0], a[1] + i[1]]);
            assert!(close(sum, total), "{sum:?} vs {total:?}");
            assert!(b.take_named_parts().iter().all(|(_, i)| *i == [0.0, 0.0]), "reset by the call");
            // Not recorded: nothing booked.
            b.apply(&context, &mut vec![[0.5, 0.0]; n], false);
            assert!(b.take_named_parts().iter().all(|(_, i)| *i == [0.0, 0.0]));
        }
        // The round-off allowance is 10⁻⁹ of the body's size (0.5 m here: 5·10⁻¹⁰ m): the top
        // row's feet (height 0.25) are the tip's when it ends 3·10⁻¹⁰ m below them, the rest's
        // when it ends 7·10⁻¹⁰ m below.
        for (gap, top_row_is_tip) in [(3e-10, true), (7e-10, false)] {
            let parts = json!([{"name": "tip", "below": 0.25 - gap}]);
            let mut b = build(json!([square_body(json!({"velocity": [0.0, -1.0], "parts": parts}))]), false)
                .unwrap()
                .pop()
                .unwrap();
            b.apply(&context, &mut vec![[0.5, 0.0]; n], true);
            let named = b.take_named_parts();
            let (tip, rest) = if top_row_is_tip { ([2.0, 6.0], [0.0, 0.0]) } else { ([1.0, 6.0], [1.0, 0.0]) };
            assert!(close(named[0].1, tip) && close(named[1].1, rest), "gap {gap}: {named:?}");
        }
        // Each face's correction goes by its foot, not by the node's height: the plate's base
        // 0.05 below the row j = 2, mass at the corner node (1, 2) only (0.05 above the base).
        // Its left face (foot (0.25, 0.5), height 0.05) stops the rightward 0.5: (1, 0); then
        // the base (foot (0.25, 0.45), height 0) the upward 1 relative to the plate: (0, 2).
        // With the tip below 0.02 the base's share is the tip's and the side's the rest's (by
        // the node's height both would be the rest's).
        let low = json!({"name": "plate", "shape": "polygon", "vertices": [[0.25, 0.45], [0.75, 0.45], [0.75, 0.75], [0.25, 0.75]],
                         "velocity": [0.0, -1.0], "parts": [{"name": "tip", "below": 0.02}]});
        let mut b = build(json!([low]), false).unwrap().pop().unwrap();
        let mut corner_mass = vec![0.0; n];
        corner_mass[grid.node_index(1, 2)] = 2.0;
        let corner = NodalContext { grid: &grid, mass: &corner_mass, time: 0.0, dt: 1e-13, axisymmetric: false };
        let mut v = vec![[0.5, 0.0]; n];
        b.apply(&corner, &mut v, true);
        assert!(close(v[grid.node_index(1, 2)], [0.0, -1.0]), "{:?}", v[grid.node_index(1, 2)]);
        let named = b.take_named_parts();
        assert!(close(named[0].1, [0.0, 2.0]) && close(named[1].1, [1.0, 0.0]), "{named:?}");
        // A body without parts has no named split.
        let mut plain = build(json!([square_body(json!({"velocity": [0.0, -1.0]}))]), false).unwrap().pop().unwrap();
        plain.apply(&context, &mut vec![[0.5, 0.0]; n], true);
        assert!(plain.take_named_parts().is_empty());
    }

    /// Nodes outside the body count as covered up to the reach: with the plate's base at
    /// y = 0.5 and the node row j = 1 at y = 0.25, a reach of 0.3 takes in row 1 under the base
    /// (normal −y), a reach of 0.2 leaves it free; nodes beside the plate stay free either way.
    #[test]
    fn the_reach_takes_in_nodes_just_outside() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let mass = vec![1.0; grid.num_nodes()];
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-13, axisymmetric: false };
        for (reach, covered) in [(0.3, true), (0.2, false)] {
            let body = square_body(json!({"velocity": [0.0, -1.0]}));
            let b = build(json!([body]), false).unwrap().pop().unwrap();
            let mut b = b.with_reach(reach);
            let mut v = vec![[0.0, 0.0]; grid.num_nodes()];
            b.apply(&context, &mut v, true);
            assert_eq!(v[grid.node_index(2, 1)], if covered { [0.0, -1.0] } else { [0.0, 0.0] }, "reach {reach}");
            // Beside the plate (0.25 from its side) and below its corners (diagonal 0.354): free.
            assert_eq!(v[grid.node_index(4, 2)], [0.0, 0.0]);
            assert_eq!(v[grid.node_index(0, 1)], [0.0, 0.0]);
        }
    }

    fn penalty_context<'a>(
        particles: &'a crate::particles::Particles,
        grid: &'a GridGeometry,
        mass: &'a [f64],
        dt: f64,
    ) -> crate::constraint::ParticleContext<'a> {
        crate::constraint::ParticleContext { particles, grid, mass, light: 0.0, time: 0.0, dt, axisymmetric: false }
    }

    /// Penalty contact by hand: the plate [0.25, 0.75] × [0.5, 0.75] (moving down at 1 m/s) and
    /// one particle at (0.5, 0.45), half-width 0.0625, sliding at 0.3 m/s relative to the plate:
    /// its two top corners are 0.0125 inside the base, each pressed by k g l = 1000 × 0.0125 ×
    /// 0.0625 = 0.78125 N down; Coulomb μ = 0.4 limits the tangential force to 0.4 × 1.5625 =
    /// 0.625 N against the slip. Each corner's force goes to the nodes of its cell with the
    /// bilinear weights (corner (0.4375, 0.5125): cell (1, 2), s = (0.75, 0.05)), shared among
    /// the nodes with mass; the body books minus the total × Δt as base impulse.
    #[test]
    fn penalty_forces_by_hand() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let body = square_body(json!({"velocity": [0.0, -1.0], "friction": 0.4, "contact": "penalty", "experimental": true}));
        let mut b = build(json!([body]), false).unwrap().pop().unwrap().with_penalty_stiffness(1000.0);
        assert_eq!(b.enforcement(), Enforcement::Penalty(1000.0));
        let mut particles = crate::particles::Particles::default();
        particles.push([0.5, 0.45], [0.3, -1.0], 2.0, 0.0156, [0.0625, 0.0625], [0.0; 4], 0);
        // A particle well below the plate: no force.
        particles.push([0.5, 0.2], [0.0, 0.0], 2.0, 0.0156, [0.0625, 0.0625], [0.0; 4], 0);
        let mut mass = vec![1.0; grid.num_nodes()];
        let dt = 1e-3;
        let mut force = vec![[0.0; 2]; grid.num_nodes()];
        b.add_contact_forces(&penalty_context(&particles, &grid, &mass, dt), &mut force);
        let total = force.iter().fold([0.0; 2], |a, f| [a[0] + f[0], a[1] + f[1]]);
        assert!((total[0] + 0.625).abs() < 1e-12 && (total[1] + 1.5625).abs() < 1e-12, "{total:?}");
        // Node (2, 2) takes 0.75 × 0.95 of each corner's force (the tangential one shared
        // half and half): 2 × 0.7125 × (−0.3125, −0.78125).
        let f = force[grid.node_index(2, 2)];
        assert!((f[0] + 2.0 * 0.7125 * 0.3125).abs() < 1e-12 && (f[1] + 2.0 * 0.7125 * 0.78125).abs() < 1e-12, "{f:?}");
        let (base, shaft) = b.take_impulse_parts();
        assert!((base[0] - 0.625 * dt).abs() < 1e-15 && (base[1] - 1.5625 * dt).abs() < 1e-15, "{base:?}");
        assert_eq!(shaft, [0.0, 0.0]);
        assert!((b.take_impulse()[1] - 1.5625 * dt).abs() < 1e-15);
        // Named parts go by the particle centre's height: y = 0.45, below the plate's lowest
        // point, is the first part's; a particle centre 0.3 above it is the rest's.
        let parts = json!([{"name": "tip", "below": 0.1}]);
        let body = square_body(json!({"velocity": [0.0, -1.0], "friction": 0.4, "contact": "penalty",
                                      "experimental": true, "parts": parts}));
        let mut named = build(json!([body]), false).unwrap().pop().unwrap().with_penalty_stiffness(1000.0);
        named.add_contact_forces(&penalty_context(&particles, &grid, &mass, dt), &mut vec![[0.0; 2]; grid.num_nodes()]);
        let split = named.take_named_parts();
        assert!((split[0].1[0] - 0.625 * dt).abs() < 1e-15 && (split[0].1[1] - 1.5625 * dt).abs() < 1e-15, "{split:?}");
        assert_eq!(split[1], (REST.to_string(), [0.0, 0.0]));
        let mut above = crate::particles::Particles::default();
        above.push([0.5, 0.8], [0.3, -1.0], 2.0, 0.0156, [0.0625, 0.0625], [0.0; 4], 0);
        named.add_contact_forces(&penalty_context(&above, &grid, &mass, dt), &mut vec![[0.0; 2]; grid.num_nodes()]);
        let split = named.take_named_parts();
        assert_eq!(split[0].1, [0.0, 0.0]);
        assert!(split[1].1[1] < 0.0, "pressed down by the top face: {split:?}");
        // Rough: the tangential force stops the slip in the step, m |v_t| / Δt = 600 N.
        let body = square_body(json!({"velocity": [0.0, -1.0], "friction": "rough", "contact": "penalty", "experimental": true}));
        let mut rough = build(json!([body]), false).unwrap().pop().unwrap().with_penalty_stiffness(1000.0);
        let mut force = vec![[0.0; 2]; grid.num_nodes()];
        rough.add_contact_forces(&penalty_context(&particles, &grid, &mass, dt), &mut force);
        let total = force.iter().fold([0.0; 2], |a, f| [a[0] + f[0], a[1] + f[1]]);
        assert!((total[0] + 600.0).abs() < 1e-9 && (total[1] + 1.5625).abs() < 1e-12, "{total:?}");
        // A node of the corner's cell without mass: its share goes to the others, the total stays.
        mass[grid.node_index(2, 2)] = 0.0;
        let mut force = vec![[0.0; 2]; grid.num_nodes()];
        b.add_contact_forces(&penalty_context(&particles, &grid, &mass, dt), &mut force);
        assert_eq!(force[grid.node_index(2, 2)], [0.0, 0.0]);
        let total = force.iter().fold([0.0; 2], |a, f| [a[0] + f[0], a[1] + f[1]]);
        assert!((total[0] + 0.625).abs() < 1e-12 && (total[1] + 1.5625).abs() < 1e-12, "{total:?}");
        // The nodal enforcement leaves the velocities alone under a penalty contact.
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt, axisymmetric: false };
        let mut v = vec![[0.5, 0.0]; grid.num_nodes()];
        b.apply(&context, &mut v, true);
        assert!(v.iter().all(|&x| x == [0.5, 0.0]));
        // An unknown enforcement is refused, naming the key.
        let e = build(json!([square_body(json!({"velocity": [0, 0], "contact": "penalty"}))]), false).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].contact") && e.contains("experimental = true"), "{e}");
        let e = build(json!([square_body(json!({"velocity": [0, 0], "contact": "glue"}))]), false).err().unwrap();
        assert!(e.starts_with("rigid_bodies[0].contact") && e.contains("penalty"), "{e}");
    }

    #[test]
    fn axis_nodes_keep_zero_radial_velocity() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.25);
        let body = json!({"name": "pile", "shape": "polygon", "vertices": [[0.0, 0.5], [0.5, 0.25], [0.5, 1.0], [0.0, 1.0]],
                          "velocity": [0.0, -1.0]});
        let mut bodies = build(json!([body]), true).unwrap();
        let mass = vec![1.0; grid.num_nodes()];
        let mut v = vec![[0.0, 0.0]; grid.num_nodes()];
        let context = NodalContext { grid: &grid, mass: &mass, time: 0.0, dt: 1e-6, axisymmetric: true };
        bodies[0].apply(&context, &mut v, true);
        // The axis node on the sloping tip (0, 0.5): oblique normal, but v_r stays 0.
        let tip = v[grid.node_index(0, 2)];
        assert_eq!(tip[0], 0.0);
        assert!(tip[1] < 0.0);
    }
}
