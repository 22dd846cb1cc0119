//! One explicit MPM step (PHYSICS.md §1), generic over the formulation `F` and the
//! interpolation scheme `S`, so that each of the eight combinations is its own monomorphised
//! loop.
//!
//! Order of operations (MUSL, Sulsky, Zhou & Schreyer 1995; USL skips step 4):
//! 1. particle → grid: mass, momentum, internal force −Σ V_p σ_p·∇S_ip (with the hoop term
//!    −V_p σ_θθ S_ip/R_p in axisymmetry) and gravity Σ S_ip m_p g;
//! 2. grid: v = p/m, Cundall local damping f ← f − α|f| sign(v), v⁺ = v + Δt f/m, constraints;
//! 3. grid → particle: v_p ← FLIP·(v_p + Σ S (v⁺ − v)) + (1 − FLIP)·Σ S v⁺, Δx_p = Δt Σ S v⁺;
//! 4. MUSL: momentum re-mapped to the grid from the new particle velocities, constraints;
//! 5. strain update: L = Σ v_i ⊗ ∇S_ip (+ L_θθ = Σ v_r,i S_ip/R_p), F ← (I + Δt L) F,
//!    volume, stress by the material; then positions move by Δx_p and CPDI corners with v⁺.
//!
//! Race freedom and determinism: particle → grid scatters into a fixed number of lanes
//! ([`LANES`], independent of the thread count), each lane a contiguous range of particles
//! summed in particle order into its own nodal buffers; the lanes are then added node by node
//! in lane order. Every other pass writes only its own particle or node. Results are
//! therefore bit-for-bit identical for any number of threads.

use rayon::prelude::*;

use crate::boundary::Constraints;
use crate::config::{UpdateScheme, VolumetricAveraging};
use crate::formulation::Formulation;
use crate::grid::{GridFields, GridGeometry};
use crate::material::{Kinematics, Material};
use crate::particles::{DeformationGradient, Particles, Stress};
use crate::shape::{ParticleDomain, ShapeFunction, StencilBox};

/// Number of particle ranges scattered independently in particle → grid.
pub const LANES: usize = 8;

/// Particles per parallel work item of the update pass.
const UPDATE_CHUNK: usize = 512;

/// What particle → grid accumulates at one node. The fields of a node are kept together so
/// that scattering a particle touches one cache line per node instead of one per field.
#[derive(Clone, Copy, Debug, Default)]
pub struct NodalSums {
    pub mass: f64,
    pub momentum: [f64; 2],
    pub force: [f64; 2],
}

/// An inclusive box of grid nodes: columns `columns[0] ..= columns[1]`, rows
/// `rows[0] ..= rows[1]`; empty when a lower bound exceeds its upper bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeBox {
    pub columns: [usize; 2],
    pub rows: [usize; 2],
}

impl Default for NodeBox {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl NodeBox {
    pub const EMPTY: Self = Self { columns: [usize::MAX, 0], rows: [usize::MAX, 0] };

    /// The smallest box containing both.
    #[inline(always)]
    fn union(self, other: NodeBox) -> NodeBox {
        NodeBox {
            columns: [self.columns[0].min(other.columns[0]), self.columns[1].max(other.columns[1])],
            rows: [self.rows[0].min(other.rows[0]), self.rows[1].max(other.rows[1])],
        }
    }

    /// Rows of the box as (first row, number of rows), for `skip`/`take` over row chunks.
    #[inline(always)]
    fn row_span(&self) -> (usize, usize) {
        if self.is_empty() {
            (0, 0)
        } else {
            (self.rows[0], self.rows[1] - self.rows[0] + 1)
        }
    }

    /// Columns of the box, clipped to a grid row of `nodes_x` nodes.
    #[inline(always)]
    fn column_span(&self, nodes_x: usize) -> std::ops::RangeInclusive<usize> {
        self.columns[0]..=self.columns[1].min(nodes_x - 1)
    }

    #[inline(always)]
    fn is_empty(&self) -> bool {
        self.columns[0] > self.columns[1] || self.rows[0] > self.rows[1]
    }

    /// Grows the box to contain a stencil's node box.
    #[inline(always)]
    fn include(&mut self, st: StencilBox) {
        self.columns = [self.columns[0].min(st.columns[0] as usize), self.columns[1].max(st.columns[1] as usize)];
        self.rows = [self.rows[0].min(st.rows[0] as usize), self.rows[1].max(st.rows[1] as usize)];
    }
}

/// Nodal buffers of one lane. Only the nodes in the box `touched` can be non-zero, so clearing
/// and summing the lanes costs in proportion to the region the lane's particles cover, not to
/// the whole grid (nor to whole grid rows).
#[derive(Clone, Debug)]
pub struct Lane {
    pub nodes: Vec<NodalSums>,
    pub touched: NodeBox,
}

impl Lane {
    fn new(num_nodes: usize) -> Self {
        Self { nodes: vec![NodalSums::default(); num_nodes], touched: NodeBox::EMPTY }
    }

    /// Zeroes the buffers where the previous scatter wrote (`nodes_x` nodes per grid row).
    /// Not inlined (one call per lane and pass): inlined, it changed the compiled scatter
    /// loops around it from one build to the next.
    #[inline(never)]
    fn clear(&mut self, nodes_x: usize) {
        let b = self.touched;
        if !b.is_empty() {
            for j in b.rows[0]..=b.rows[1] {
                let row = j * nodes_x;
                self.nodes[row + b.columns[0]..=row + b.columns[1]].fill(NodalSums::default());
            }
        }
        self.touched = NodeBox::EMPTY;
    }
}

/// Per-particle scratch arrays reused every step (no allocation in the step loop).
#[derive(Default)]
pub struct Scratch {
    /// `Vec<S::Cache>` of the scheme in use: each particle's stencil data, computed once per
    /// step in particle → grid and reused by grid → particle and the particle update.
    pub stencil_cache: Option<Box<dyn std::any::Any + Send + Sync>>,
    pub displacement: Vec<[f64; 2]>,
    /// Cell averaging only: each particle's velocity gradient, and per background cell the
    /// particle volume and the volume-weighted mean dilatation (see `update_particles`).
    pub velocity_gradient: Vec<[f64; 5]>,
    pub cell_volume: Vec<f64>,
    pub cell_dilatation: Vec<f64>,
    /// Nodes the particles reached in the last particle → grid: every grid field is +0
    /// outside this box (the grid passes write nothing else there, and constraints keep a
    /// zero velocity zero).
    pub grid_reached: NodeBox,
    /// Nodes the grid passes of this step work on: this step's reach together with the last
    /// step's, whose fields must be brought back to zero where the particles left.
    pub grid_region: NodeBox,
}

/// Parameters of the step that do not change during a run.
#[derive(Clone, Copy, Debug)]
pub struct StepParameters {
    pub flip_fraction: f64,
    pub damping: f64,
    pub scheme: UpdateScheme,
    /// Nodes lighter than this carry no velocity (avoids dividing by vanishing GIMP masses).
    pub mass_threshold: f64,
    pub volumetric_averaging: VolumetricAveraging,
}

/// Everything the step mutates or reads.
pub struct State {
    pub grid: GridGeometry,
    pub fields: GridFields,
    pub lanes: Vec<Lane>,
    pub scratch: Scratch,
    pub particles: Particles,
    pub materials: Vec<Box<dyn Material>>,
    /// `state_names().len()` of each material: the part of a particle's state slots its
    /// material uses (looked up per particle, so kept out of the virtual call).
    pub state_lengths: Vec<usize>,
    pub constraints: Constraints,
    pub parameters: StepParameters,
    pub time: f64,
    pub steps: u64,
    /// Wall seconds spent in each phase since the start of the run.
    pub timings: PhaseTimings,
}

/// Wall-clock seconds per phase of the step (for `axmpm bench`).
#[derive(Clone, Copy, Debug, Default)]
pub struct PhaseTimings {
    pub particle_to_grid: f64,
    pub grid_update: f64,
    pub grid_to_particle: f64,
    pub constitutive_update: f64,
}

/// Why a step produced an invalid state, for the first offending particle (lowest index).
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    NotFinite { particle: usize },
    LeftGrid { particle: usize, position: [f64; 2] },
    InvertedJacobian { particle: usize, jacobian: f64 },
}

impl Failure {
    fn particle(&self) -> usize {
        match self {
            Failure::NotFinite { particle }
            | Failure::LeftGrid { particle, .. }
            | Failure::InvertedJacobian { particle, .. } => *particle,
        }
    }

    pub fn message(&self) -> String {
        match self {
            Failure::NotFinite { particle } => {
                format!("particle {particle}: position, velocity or stress is not finite (NaN or infinite)")
            }
            Failure::LeftGrid { particle, position } => format!(
                "particle {particle} left the grid at ({:.6e}, {:.6e}): material flowed out or separated (enlarge grid.extent if the motion is real)",
                position[0], position[1]
            ),
            Failure::InvertedJacobian { particle, jacobian } => {
                format!("particle {particle}: deformation gradient inverted (J = {jacobian:.3e})")
            }
        }
    }
}

fn first_failure(a: Option<Failure>, b: Option<Failure>) -> Option<Failure> {
    match (a, b) {
        (Some(a), Some(b)) => Some(if a.particle() <= b.particle() { a } else { b }),
        (a, None) => a,
        (None, b) => b,
    }
}

impl State {
    pub fn allocate_scratch(&mut self) {
        let n = self.particles.len();
        self.scratch.displacement = vec![[0.0; 2]; n];
        if self.parameters.volumetric_averaging == VolumetricAveraging::Cell {
            let cells = self.grid.cells[0] * self.grid.cells[1];
            self.scratch.velocity_gradient = vec![[0.0; 5]; n];
            self.scratch.cell_volume = vec![0.0; cells];
            self.scratch.cell_dilatation = vec![0.0; cells];
        }
        self.lanes = (0..LANES).map(|_| Lane::new(self.grid.num_nodes())).collect();
    }
}

/// Particles per lane: lanes are equal contiguous chunks (the last may be shorter or empty).
#[inline(always)]
fn lane_length(n: usize) -> usize {
    n.div_ceil(LANES).max(1)
}

/// Advances the state by `dt` with body force `gravity`. Returns the first invalid particle, if
/// any (the state is then left as computed, for inspection).
pub fn step<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, gravity: [f64; 2]) -> Result<(), Failure> {
    let mut cache = take_stencil_cache::<S>(state);
    let t0 = std::time::Instant::now();
    particle_to_grid::<F, S>(state, gravity, &mut cache);
    let t1 = std::time::Instant::now();
    update_grid(state, dt);
    let t2 = std::time::Instant::now();
    grid_to_particle::<F, S>(state, dt, &cache);
    let t3 = std::time::Instant::now();
    let result = update_particles::<F, S>(state, dt, &cache);
    let t4 = std::time::Instant::now();
    state.scratch.stencil_cache = Some(Box::new(cache));
    state.timings.particle_to_grid += (t1 - t0).as_secs_f64();
    state.timings.grid_update += (t2 - t1).as_secs_f64();
    state.timings.grid_to_particle += (t3 - t2).as_secs_f64();
    state.timings.constitutive_update += (t4 - t3).as_secs_f64();
    state.time += dt;
    state.steps += 1;
    result
}

/// The scheme's per-particle stencil cache, kept in the scratch between steps (allocated on
/// the first step only).
fn take_stencil_cache<S: ShapeFunction>(state: &mut State) -> Vec<S::Cache> {
    let n = state.particles.len();
    match state.scratch.stencil_cache.take().map(|b| b.downcast::<Vec<S::Cache>>()) {
        Some(Ok(cache)) if cache.len() == n => *cache,
        _ => vec![S::Cache::default(); n],
    }
}

/// Scatters mass, momentum, internal and gravity forces to the nodes, lane by lane, then sums
/// the lanes in a fixed order. Computes each particle's stencil cache for the step.
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
fn particle_to_grid<F: Formulation, S: ShapeFunction>(state: &mut State, gravity: [f64; 2], cache: &mut [S::Cache]) {
    let particles = &state.particles;
    let grid = &state.grid;
    let len = lane_length(particles.len());
    let nodes_x = grid.nodes[0];
    cache.par_chunks_mut(len).zip(state.lanes.par_iter_mut()).enumerate().for_each(|(k, (lane_cache, lane))| {
        lane.clear(nodes_x);
        let mut touched = NodeBox::EMPTY;
        // Local copies of what the loop reads and slices of what it writes: the compiler then
        // keeps them in registers instead of reloading them after every nodal store (which it
        // cannot prove does not alias them).
        let (grid, gravity) = (*grid, gravity);
        let nodes = &mut lane.nodes[..];
        let corners = &particles.corners[..];
        // The lane's particles as slices of one length, so the loop indexes without bounds checks.
        let n = lane_cache.len();
        let first = k * len;
        let position = &particles.position[first..first + n];
        let initial_half_width = &particles.initial_half_width[first..first + n];
        let deformation_gradient = &particles.deformation_gradient[first..first + n];
        let mass = &particles.mass[first..first + n];
        let velocity = &particles.velocity[first..first + n];
        let volume = &particles.volume[first..first + n];
        let stress = &particles.stress[first..first + n];
        for (i, c) in lane_cache.iter_mut().enumerate() {
            let domain = ParticleDomain {
                position: position[i],
                initial_half_width: initial_half_width[i],
                deformation_gradient: &deformation_gradient[i],
                corners: corners.get(first + i),
            };
            S::prepare(&grid, &domain, F::AXISYMMETRIC, c);
            touched.include(S::node_box(&grid, c, &domain));
            let m = mass[i];
            let v = velocity[i];
            let vol = volume[i];
            let s = stress[i];
            let hoop = F::hoop_factor(position[i]);
            S::visit_entries(&grid, c, &domain, F::AXISYMMETRIC, |node, w, g| {
                let sums = &mut nodes[node];
                sums.mass += w * m;
                sums.momentum[0] += w * m * v[0];
                sums.momentum[1] += w * m * v[1];
                // Internal force (Sulsky & Schreyer 1996, PHYSICS.md §2) plus gravity.
                sums.force[0] += -vol * (s[0] * g[0] + s[3] * g[1] + s[2] * w * hoop) + w * m * gravity[0];
                sums.force[1] += -vol * (s[3] * g[0] + s[1] * g[1]) + w * m * gravity[1];
            });
        }
        lane.touched = touched;
    });
    let reached = state.lanes.iter().fold(NodeBox::EMPTY, |b, lane| b.union(lane.touched));
    state.scratch.grid_region = reached.union(state.scratch.grid_reached);
    state.scratch.grid_reached = reached;
    sum_lanes(&state.lanes, grid.nodes[0], state.scratch.grid_region, &mut state.fields, true);
}

/// Sums the lanes node by node in lane order into the grid fields: momentum always, mass and
/// force when `all` (the MUSL re-map only scatters momentum).
/// Only `region` is zeroed first: outside it the fields are zero already (see
/// [`Scratch::grid_reached`]) and no lane reaches there.
fn sum_lanes(lanes: &[Lane], nodes_x: usize, region: NodeBox, fields: &mut GridFields, all: bool) {
    // Whole grid rows per parallel chunk, about 4096 nodes.
    let rows_per_chunk = (4096 / nodes_x).max(1);
    let chunk = rows_per_chunk * nodes_x;
    fields
        .mass
        .par_chunks_mut(chunk)
        .zip(fields.momentum.par_chunks_mut(chunk))
        .zip(fields.force.par_chunks_mut(chunk))
        .enumerate()
        .for_each(|(c, ((mass, momentum), force))| {
            // Start from zero and add each lane's touched part of this chunk, in lane order:
            // every node is summed as 0 + lane0 + lane1 + ..., independent of the threads.
            // (A lane adds nothing outside its box, where it holds +0, and adding +0 to a sum
            // that started at +0 never changes it, so skipping those nodes is exact.)
            let start = c * chunk;
            let first_row = c * rows_per_chunk;
            let last_row = first_row + mass.len() / nodes_x - 1;
            if !region.is_empty() {
                for j in region.rows[0].max(first_row)..=region.rows[1].min(last_row) {
                    let local = j * nodes_x - start + region.columns[0]..=j * nodes_x - start + region.columns[1];
                    momentum[local.clone()].fill([0.0; 2]);
                    if all {
                        mass[local.clone()].fill(0.0);
                        force[local].fill([0.0; 2]);
                    }
                }
            }
            for lane in lanes {
                let b = lane.touched;
                if b.is_empty() {
                    continue;
                }
                for j in b.rows[0].max(first_row)..=b.rows[1].min(last_row) {
                    let row = j * nodes_x;
                    let nodes = &lane.nodes[row + b.columns[0]..=row + b.columns[1]];
                    let local = row - start + b.columns[0]..=row - start + b.columns[1];
                    if all {
                        let out = mass[local.clone()]
                            .iter_mut()
                            .zip(&mut momentum[local.clone()])
                            .zip(&mut force[local]);
                        for (((m, p), f), sums) in out.zip(nodes) {
                            *m += sums.mass;
                            p[0] += sums.momentum[0];
                            p[1] += sums.momentum[1];
                            f[0] += sums.force[0];
                            f[1] += sums.force[1];
                        }
                    } else {
                        for (p, sums) in momentum[local].iter_mut().zip(nodes) {
                            p[0] += sums.momentum[0];
                            p[1] += sums.momentum[1];
                        }
                    }
                }
            }
        });
}

/// Nodal velocities before and after the momentum update, with damping and constraints.
fn update_grid(state: &mut State, dt: f64) {
    let params = state.parameters;
    let fields = &mut state.fields;
    // Row by row over the region of this step (elsewhere every field is zero and stays so).
    let region = state.scratch.grid_region;
    let nx = state.grid.nodes[0];
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    fields
        .velocity
        .par_chunks_mut(nx)
        .zip(fields.velocity_new.par_chunks_mut(nx))
        .zip(fields.mass.par_chunks(nx))
        .zip(fields.momentum.par_chunks(nx))
        .zip(fields.force.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .with_min_len(4)
        .flat_map_iter(|((((v, v_new), m), p), f)| {
            let c = columns.clone();
            v[c.clone()].iter_mut().zip(&mut v_new[c.clone()]).zip(&m[c.clone()]).zip(&p[c.clone()]).zip(&f[c])
        })
        .for_each(|((((v, v_new), &m), p), f)| {
            if m > params.mass_threshold {
                let v0 = [p[0] / m, p[1] / m];
                let mut a = [0.0; 2];
                for d in 0..2 {
                    // Cundall local damping: the unbalanced force is reduced by α|f| against the motion.
                    let damped = f[d] - params.damping * f[d].abs() * sign(v0[d]);
                    a[d] = damped / m;
                }
                *v = v0;
                *v_new = [v0[0] + dt * a[0], v0[1] + dt * a[1]];
            } else {
                *v = [0.0; 2];
                *v_new = [0.0; 2];
            }
        });
    state.constraints.apply(state.time, &mut fields.velocity);
    state.constraints.apply(state.time, &mut fields.velocity_new);
}

#[inline(always)]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// New particle velocities (PIC/FLIP blend) and position increments; with MUSL the new
/// momentum is scattered back to the grid in the same pass (same stencil, same lanes).
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
fn grid_to_particle<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, cache: &[S::Cache]) {
    let grid = &state.grid;
    let fields = &state.fields;
    let flip = state.parameters.flip_fraction;
    let musl = state.parameters.scheme == UpdateScheme::Musl;
    // Velocities are updated in place (each particle reads only its own); the rest is read only.
    let Particles { velocity, position, initial_half_width, deformation_gradient, corners, mass, .. } =
        &mut state.particles;
    let (position, initial_half_width, deformation_gradient, corners, mass) =
        (&*position, &*initial_half_width, &*deformation_gradient, &*corners, &*mass);
    let len = lane_length(velocity.len());
    velocity
        .par_chunks_mut(len)
        .zip(state.scratch.displacement.par_chunks_mut(len))
        .zip(state.lanes.par_iter_mut())
        .enumerate()
        .for_each(|(k, ((velocity_io, displacement_out), lane))| {
            // The MUSL re-map scatters the same stencils as particle → grid, so it reaches the
            // same node box: kept instead of grown again particle by particle.
            let reached = lane.touched;
            if musl {
                lane.clear(grid.nodes[0]);
            }
            // Local copies and slices, kept in registers across the nodal stores (see P2G).
            let (grid, flip, dt, musl) = (*grid, flip, dt, musl);
            let (velocity_new, velocity_old) = (&fields.velocity_new[..], &fields.velocity[..]);
            let nodes = &mut lane.nodes[..];
            let corners: &[[[f64; 2]; 4]] = corners;
            // The lane's particles as slices of one length (no bounds checks in the loop).
            let n = velocity_io.len();
            let first = k * len;
            let position = &position[first..first + n];
            let initial_half_width = &initial_half_width[first..first + n];
            let deformation_gradient = &deformation_gradient[first..first + n];
            let mass = &mass[first..first + n];
            let cache = &cache[first..first + n];
            for (i, (v_io, dx)) in velocity_io.iter_mut().zip(displacement_out.iter_mut()).enumerate() {
                let domain = ParticleDomain {
                    position: position[i],
                    initial_half_width: initial_half_width[i],
                    deformation_gradient: &deformation_gradient[i],
                    corners: corners.get(first + i),
                };
                let mut v_grid = [0.0; 2];
                let mut dv = [0.0; 2];
                S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                    let vn = velocity_new[node];
                    let vo = velocity_old[node];
                    v_grid[0] += w * vn[0];
                    v_grid[1] += w * vn[1];
                    dv[0] += w * (vn[0] - vo[0]);
                    dv[1] += w * (vn[1] - vo[1]);
                });
                let v = *v_io;
                let v_new = [
                    flip * (v[0] + dv[0]) + (1.0 - flip) * v_grid[0],
                    flip * (v[1] + dv[1]) + (1.0 - flip) * v_grid[1],
                ];
                *v_io = v_new;
                *dx = [dt * v_grid[0], dt * v_grid[1]];
                if musl {
                    let m = mass[i];
                    S::visit_entries(&grid, &cache[i], &domain, F::AXISYMMETRIC, |node, w, _| {
                        let sums = &mut nodes[node];
                        let wm = w * m;
                        sums.momentum[0] += wm * v_new[0];
                        sums.momentum[1] += wm * v_new[1];
                    });
                }
            }
            if musl {
                lane.touched = reached;
            }
        });
    if musl {
        sum_lanes(&state.lanes, grid.nodes[0], state.scratch.grid_region, &mut state.fields, false);
        remap_velocity(state);
    }
}

/// MUSL: nodal velocities from the re-mapped momentum, constrained; stored in `fields.velocity`.
fn remap_velocity(state: &mut State) {
    let threshold = state.parameters.mass_threshold;
    let fields = &mut state.fields;
    let region = state.scratch.grid_region;
    let nx = state.grid.nodes[0];
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    fields
        .velocity
        .par_chunks_mut(nx)
        .zip(fields.mass.par_chunks(nx))
        .zip(fields.momentum.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .with_min_len(4)
        .for_each(|((v, m), p)| {
            let c = columns.clone();
            for ((v, &m), p) in v[c.clone()].iter_mut().zip(&m[c.clone()]).zip(&p[c]) {
                *v = if m > threshold { [p[0] / m, p[1] / m] } else { [0.0; 2] };
            }
        });
    state.constraints.apply(state.time, &mut fields.velocity);
}

/// Read-only inputs of the per-particle update.
#[derive(Clone, Copy)]
struct UpdateInputs<'a> {
    grid: GridGeometry,
    dt: f64,
    strain_velocity: &'a [[f64; 2]],
    advect_velocity: &'a [[f64; 2]],
    materials: &'a [Box<dyn Material>],
    state_lengths: &'a [usize],
    material_ids: &'a [u32],
    initial_volume: &'a [f64],
    initial_half_width: &'a [[f64; 2]],
    velocity: &'a [[f64; 2]],
    displacement: &'a [[f64; 2]],
}

/// The mutable state of one particle in the update pass.
struct ParticleUpdate<'a> {
    f: &'a mut [f64; 5],
    stress: &'a mut [f64; 4],
    volume: &'a mut f64,
    position: &'a mut [f64; 2],
    state: &'a mut [f64],
    corners: Option<&'a mut [[f64; 2]; 4]>,
}

/// Velocity gradient of one particle from the stencil at its start-of-step position and
/// domain: L_ij = Σ_i v_i ∂S_ip/∂x_j, and the hoop rate L_θθ = Σ v_r,i S_ip / R_p (0 in plane
/// strain). Stored as [L11, L12, L21, L22, L33].
#[inline(always)]
fn velocity_gradient<F: Formulation, S: ShapeFunction>(
    inputs: &UpdateInputs,
    domain: &ParticleDomain,
    cache: &S::Cache,
) -> [f64; 5] {
    let mut l = [0.0; 5];
    let mut vr = 0.0;
    S::visit_entries(&inputs.grid, cache, domain, F::AXISYMMETRIC, |node, w, dw| {
        let v = inputs.strain_velocity[node];
        l[0] += v[0] * dw[0];
        l[1] += v[0] * dw[1];
        l[2] += v[1] * dw[0];
        l[3] += v[1] * dw[1];
        vr += v[0] * w;
    });
    l[4] = vr * F::hoop_factor(domain.position);
    l
}

/// Volumetric strain rate tr L (the hoop rate included; it is zero in plane strain).
#[inline(always)]
fn dilatation(l: &[f64; 5]) -> f64 {
    l[0] + l[3] + l[4]
}

/// Replaces the volumetric part of L by `mean_dilatation`, spread equally over the normal
/// components that can stretch: the two in-plane ones in plane strain (L33 = 0 is kept), and
/// the in-plane and hoop ones in axisymmetry. The rate form of F-bar (mean dilatation,
/// Nagtegaal, Parks & Rice 1974; for MPM with the background cell as the averaging domain,
/// Coombs, Charlton, Cortis & Augarde 2018, CMAME 333): the isochoric part stays the
/// particle's own, so plastic flow with zero dilation (ψ = 0) is not over-constrained by the
/// one-velocity-field-per-cell kinematics (volumetric locking).
#[inline(always)]
fn with_mean_dilatation<F: Formulation>(mut l: [f64; 5], mean_dilatation: f64) -> [f64; 5] {
    let components = if F::AXISYMMETRIC { 3.0 } else { 2.0 };
    let correction = (mean_dilatation - dilatation(&l)) / components;
    l[0] += correction;
    l[3] += correction;
    if F::AXISYMMETRIC {
        l[4] += correction;
    }
    l
}

/// Deformation gradient, CPDI corners, position, volume and stress of one particle from its
/// velocity gradient `l` (and its stencil cache of the step, which the corner advection
/// reuses); returns a failure if its new state is invalid.
#[inline(always)]
fn update_particle<F: Formulation, S: ShapeFunction>(
    inputs: &UpdateInputs,
    p: usize,
    u: ParticleUpdate,
    cache: &S::Cache,
    l: [f64; 5],
) -> Option<Failure> {
    let grid = &inputs.grid;
    let dt = inputs.dt;
    // F ← (I + Δt L) F in-plane; F33 ← (1 + Δt L33) F33.
    let f = u.f;
    let f_old = *f;
    let a = [1.0 + dt * l[0], dt * l[1], dt * l[2], 1.0 + dt * l[3]];
    f[0] = a[0] * f_old[0] + a[1] * f_old[2];
    f[1] = a[0] * f_old[1] + a[1] * f_old[3];
    f[2] = a[2] * f_old[0] + a[3] * f_old[2];
    f[3] = a[2] * f_old[1] + a[3] * f_old[3];
    f[4] = (1.0 + dt * l[4]) * f_old[4];
    let jacobian = (f[0] * f[3] - f[1] * f[2]) * f[4];

    let x = u.position;
    let d = inputs.displacement[p];
    x[0] += d[0];
    x[1] += d[1];
    *u.volume = match u.corners {
        Some(corners) => {
            S::advect_corners(grid, cache, inputs.advect_velocity, dt, corners, F::AXISYMMETRIC);
            S::domain_area(corners).unwrap_or(0.0) * F::volume_factor(*x)
        }
        None => inputs.initial_volume[p] * jacobian,
    };
    let kinematics = Kinematics { velocity_gradient: l, deformation_gradient: *f, jacobian, dt };
    let material = &inputs.materials[inputs.material_ids[p] as usize];
    material.update_stress(u.stress, u.state, &kinematics);

    let finite = x[0].is_finite()
        && x[1].is_finite()
        && u.stress.iter().all(|s| s.is_finite())
        && inputs.velocity[p].iter().all(|v| v.is_finite());
    if !finite {
        Some(Failure::NotFinite { particle: p })
    } else if !grid.contains(*x) || (F::AXISYMMETRIC && x[0] <= 0.0) {
        Some(Failure::LeftGrid { particle: p, position: *x })
    } else if !(jacobian > 0.0) {
        Some(Failure::InvertedJacobian { particle: p, jacobian })
    } else {
        None
    }
}

/// Where the velocity gradient of each particle comes from in the update pass.
#[derive(Clone, Copy)]
enum GradientSource<'a> {
    /// Computed from the stencil in the same pass (no averaging).
    Stencil,
    /// Precomputed per particle, with the volumetric part replaced by the mean dilatation of
    /// the particle's cell.
    CellAveraged { gradients: &'a [[f64; 5]], cell_mean_dilatation: &'a [f64] },
}

/// Velocity gradient, deformation gradient, volume, stress and position of every particle, in
/// one pass (each particle reads its start-of-step position and domain before moving them).
/// With cell averaging a first pass stores every velocity gradient and sums the cells.
#[inline(never)] // one call per step; a symbol of its own for profiles (callgrind --toggle-collect)
fn update_particles<F: Formulation, S: ShapeFunction>(
    state: &mut State,
    dt: f64,
    cache: &[S::Cache],
) -> Result<(), Failure> {
    let averaging = state.parameters.volumetric_averaging == VolumetricAveraging::Cell;
    let Scratch { displacement, velocity_gradient: gradients, cell_volume, cell_dilatation, .. } = &mut state.scratch;
    let particles = &mut state.particles;
    // At least one state slot per particle (set up in `Simulation::build`), so the zipped
    // state chunks below stay aligned with the particles.
    let stride = particles.state_stride;
    debug_assert!(stride >= 1 && particles.state.len() == particles.len() * stride);
    let inputs = UpdateInputs {
        grid: state.grid,
        dt,
        // Strain rate from the re-mapped (MUSL) or updated (USL) velocities; corners move with
        // the updated velocities, like the particle positions.
        strain_velocity: if state.parameters.scheme == UpdateScheme::Musl {
            &state.fields.velocity
        } else {
            &state.fields.velocity_new
        },
        advect_velocity: &state.fields.velocity_new,
        materials: &state.materials,
        state_lengths: &state.state_lengths,
        material_ids: &particles.material,
        initial_volume: &particles.initial_volume,
        initial_half_width: &particles.initial_half_width,
        velocity: &particles.velocity,
        displacement,
    };
    let source = if averaging {
        cell_averaged_gradients::<F, S>(&inputs, particles, cache, gradients, cell_volume, cell_dilatation);
        GradientSource::CellAveraged { gradients, cell_mean_dilatation: cell_dilatation }
    } else {
        GradientSource::Stencil
    };
    let gradient = |inputs: &UpdateInputs, p: usize, domain: &ParticleDomain, c: &S::Cache| match source {
        GradientSource::Stencil => velocity_gradient::<F, S>(inputs, domain, c),
        GradientSource::CellAveraged { gradients, cell_mean_dilatation } => {
            with_mean_dilatation::<F>(gradients[p], cell_mean_dilatation[inputs.grid.cell_index(domain.position)])
        }
    };
    // One chunk of particles, its arrays as slices of one length: a plain loop per chunk
    // instead of rayon's per-item plumbing (zipped producers, a reduction per particle).
    #[allow(clippy::too_many_arguments)]
    let update_chunk = |k: usize,
                        f: &mut [DeformationGradient],
                        stress: &mut [Stress],
                        volume: &mut [f64],
                        position: &mut [[f64; 2]],
                        state: &mut [f64],
                        cache: &[S::Cache],
                        mut corners: Option<&mut [[[f64; 2]; 4]]>|
     -> Option<Failure> {
        // A local copy, kept in registers across the particle's stores (see P2G); not redundant.
        #[allow(clippy::redundant_locals)]
        let inputs = inputs;
        let first = k * UPDATE_CHUNK;
        let n = f.len();
        let (stress, volume, position, cache) = (&mut stress[..n], &mut volume[..n], &mut position[..n], &cache[..n]);
        let initial_half_width = &inputs.initial_half_width[first..first + n];
        let material_ids = &inputs.material_ids[first..first + n];
        let mut failure = None;
        for i in 0..n {
            let p = first + i;
            let corners = corners.as_mut().map(|c| &mut c[i]);
            let domain = ParticleDomain {
                position: position[i],
                initial_half_width: initial_half_width[i],
                deformation_gradient: &f[i],
                corners: corners.as_deref(),
            };
            let l = gradient(&inputs, p, &domain, &cache[i]);
            let slots = i * stride..i * stride + inputs.state_lengths[material_ids[i] as usize];
            let u = ParticleUpdate {
                f: &mut f[i],
                stress: &mut stress[i],
                volume: &mut volume[i],
                position: &mut position[i],
                state: &mut state[slots],
                corners,
            };
            let result = update_particle::<F, S>(&inputs, p, u, &cache[i], l);
            // The lowest failing index of the chunk (chunks are then reduced the same way).
            if failure.is_none() {
                failure = result;
            }
        }
        failure
    };
    let chunks = particles
        .deformation_gradient
        .par_chunks_mut(UPDATE_CHUNK)
        .zip(particles.stress.par_chunks_mut(UPDATE_CHUNK))
        .zip(particles.volume.par_chunks_mut(UPDATE_CHUNK))
        .zip(particles.position.par_chunks_mut(UPDATE_CHUNK))
        .zip(particles.state.par_chunks_mut(UPDATE_CHUNK * stride))
        .zip(cache.par_chunks(UPDATE_CHUNK));
    let failure = if S::USES_CORNERS {
        chunks
            .zip(particles.corners.par_chunks_mut(UPDATE_CHUNK))
            .enumerate()
            .map(|(k, ((((((f, stress), volume), position), s), c), corners))| {
                update_chunk(k, f, stress, volume, position, s, c, Some(corners))
            })
            .reduce(|| None, first_failure)
    } else {
        chunks
            .enumerate()
            .map(|(k, (((((f, stress), volume), position), s), c))| update_chunk(k, f, stress, volume, position, s, c, None))
            .reduce(|| None, first_failure)
    };
    failure.map_or(Ok(()), Err)
}

/// First pass of the cell-averaged update: every particle's velocity gradient into
/// `gradients`, then the volume-weighted mean dilatation of each background cell,
/// Σ_p V_p tr L_p / Σ_p V_p over the particles whose centre lies in the cell, into
/// `cell_dilatation`. The cell sums run in particle order on one thread, so they do not
/// depend on the thread count (one add per particle; cheap next to the stencil work).
fn cell_averaged_gradients<F: Formulation, S: ShapeFunction>(
    inputs: &UpdateInputs,
    particles: &Particles,
    cache: &[S::Cache],
    gradients: &mut [[f64; 5]],
    cell_volume: &mut [f64],
    cell_dilatation: &mut [f64],
) {
    gradients
        .par_iter_mut()
        .zip(cache.par_iter())
        .enumerate()
        .with_min_len(256)
        .for_each(|(p, (l, c))| {
            let domain = ParticleDomain::of(particles, p);
            *l = velocity_gradient::<F, S>(inputs, &domain, c);
        });
    let grid = &inputs.grid;
    cell_volume.fill(0.0);
    cell_dilatation.fill(0.0);
    for ((x, &v), l) in particles.position.iter().zip(&particles.volume).zip(gradients.iter()) {
        let cell = grid.cell_index(*x);
        cell_volume[cell] += v;
        cell_dilatation[cell] += v * dilatation(l);
    }
    for (d, &v) in cell_dilatation.iter_mut().zip(cell_volume.iter()) {
        if v > 0.0 {
            *d /= v;
        }
    }
}
