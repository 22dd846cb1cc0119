//! One explicit MPM step (docs/physics.md §1), generic over the formulation `F` and the
//! interpolation scheme `S`, so that each of the eight combinations is its own monomorphised
//! loop. One file per pass, in the order of the step:
//!
//! 1. [`particle_to_grid`]: m_i, p_i and f_i = f_int + f_ext;
//! 2. [`grid_update`]: a_i = (f_int + f_ext)_i / m_i (Cundall damping), v⁺_i = v_i + Δt a_i,
//!    constraints;
//! 3. [`grid_to_particle`]: FLIP/PIC velocity blend (the PIC share filtered by [`xpic`] when
//!    its order is above 1), Δx_p = Δt Σ S v⁺; MUSL re-map of the momentum (Sulsky, Zhou &
//!    Schreyer 1995; USL skips it), constraints;
//! 4. [`particle_update`]: L, F, volume, stress by the material, positions and CPDI corners.
//!
//! Every [`tiles::SORT_INTERVAL`] steps the particles are first sorted by grid tile;
//! [`tiles`] makes the scatter of passes 1 and 3 race free and independent of the thread
//! count; every other pass writes only its own particle or node. Results are therefore
//! bit-for-bit identical for any number of threads.

use crate::config::{UpdateScheme, VolumetricAveraging};
use crate::constraint::Constraints;
use crate::formulation::Formulation;
use crate::grid::{GridFields, GridGeometry, NodeBox};
use crate::interpolation::ShapeFunction;
use crate::material::Material;
use crate::particles::Particles;

pub mod grid_to_particle;
pub mod grid_update;
pub mod isa;
pub mod particle_to_grid;
pub mod particle_update;
pub mod saturated;
pub mod surface_load;
pub mod tiles;
pub mod xpic;

pub use isa::Isa;
pub use tiles::{Tile, TileOrder};

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
    /// The cell field a material asks for ([`crate::material::Material::cell_field`]), with
    /// its arrays (set up with the run; `None`: no material asks).
    pub cell_laplacian: Option<crate::material::CellLaplacian>,
    /// Nodes the particles reached in the last particle → grid: every grid field is +0
    /// outside this box (the grid passes write nothing else there, and constraints keep a
    /// zero velocity zero).
    pub grid_reached: NodeBox,
    /// Nodes the grid passes of this step work on: this step's reach together with the last
    /// step's, whose fields must be brought back to zero where the particles left.
    pub grid_region: NodeBox,
    /// XPIC(m) with m > 1 only: the nodal fields of the filter ([`xpic`]).
    pub xpic: Option<xpic::XpicFields>,
}

/// Parameters of the step that do not change during a run.
#[derive(Clone, Copy, Debug)]
pub struct StepParameters {
    pub flip_fraction: f64,
    /// The order m of the XPIC(m) filter in the non-FLIP share of the velocity update
    /// ([`xpic`]; 1: PIC).
    pub xpic_order: u32,
    pub damping: f64,
    pub scheme: UpdateScheme,
    /// Nodes lighter than this get no force update (avoids dividing by vanishing GIMP masses);
    /// they keep the velocity p/m of their momentum.
    pub mass_threshold: f64,
    pub volumetric_averaging: VolumetricAveraging,
    /// The formulation is axisymmetric (for the constraints; the passes know it from `F`).
    pub axisymmetric: bool,
    /// Instruction set of the passes' loops ([`isa`]; results do not depend on it).
    pub isa: Isa,
}

/// Everything the step mutates or reads.
pub struct State {
    pub grid: GridGeometry,
    pub fields: GridFields,
    /// The particles' tiles since the last sort (empty: sort before the next step).
    pub tiles: TileOrder,
    /// The step count at the last sort, when this object made it (a sort at that count again
    /// would change nothing: the sort is stable and idempotent).
    pub sorted_at: Option<u64>,
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
    /// The pore water's nodal fields and scratch (saturated runs only, [`saturated`]).
    pub water: Option<Box<saturated::WaterState>>,
    /// The share of the surface loads applied in this step (the gravity ramp, 0..1).
    pub load_factor: f64,
}

/// Wall-clock seconds per phase of the step (for `axmpm bench`).
#[derive(Clone, Copy, Debug, Default)]
pub struct PhaseTimings {
    pub particle_to_grid: f64,
    pub grid_update: f64,
    pub grid_to_particle: f64,
    pub constitutive_update: f64,
    /// Of the time above, the parts that run on one thread whatever the thread count: the
    /// sort's counting, the scatter's particles outside their tile's zone, the constraints,
    /// the cell averages' sums (for the serial fraction of `axmpm bench`'s notes).
    pub serial: f64,
}

/// Why a step produced an invalid state, for the first offending particle (lowest index).
#[derive(Clone, Debug, PartialEq)]
pub enum Failure {
    NotFinite { particle: usize },
    /// Outside the grid (or on/behind the axis in axisymmetry) with the velocity it had.
    LeftGrid { particle: usize, position: [f64; 2], velocity: [f64; 2] },
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

    /// The same failure naming the particle by its id instead of its index in the arrays.
    pub fn with_id(self, ids: &[u32]) -> Self {
        let id = |p: usize| ids.get(p).map_or(p, |&id| id as usize);
        match self {
            Failure::NotFinite { particle } => Failure::NotFinite { particle: id(particle) },
            Failure::LeftGrid { particle, position, velocity } => {
                Failure::LeftGrid { particle: id(particle), position, velocity }
            }
            Failure::InvertedJacobian { particle, jacobian } => {
                Failure::InvertedJacobian { particle: id(particle), jacobian }
            }
        }
    }

    pub fn message(&self) -> String {
        match self {
            Failure::NotFinite { particle } => {
                format!("particle {particle}: position, velocity or stress is not finite (NaN or infinite)")
            }
            Failure::LeftGrid { particle, position, velocity } => {
                // A real outflow moves at the problem's own speeds; a particle flung out at
                // many times them is the signature of an instability (time step, FLIP noise,
                // a contact or boundary that pulls material along), not of a small grid.
                let speed = velocity[0].hypot(velocity[1]);
                format!(
                    "particle {particle} left the grid at ({:.6e}, {:.6e}) m moving at {speed:.3e} m/s \
                     (v = ({:.3e}, {:.3e}) m/s). If that speed is far above the speeds of the \
                     problem (loading rates, wave or free-fall speeds), the run is unstable: \
                     lower simulation.cfl or simulation.flip_fraction, and check the contacts and \
                     boundary conditions near that point. If the motion is real (material \
                     flowing out), enlarge grid.extent.",
                    position[0], position[1], velocity[0], velocity[1]
                )
            }
            Failure::InvertedJacobian { particle, jacobian } => {
                format!("particle {particle}: deformation gradient inverted (J = {jacobian:.3e})")
            }
        }
    }
}

pub(super) fn first_failure(a: Option<Failure>, b: Option<Failure>) -> Option<Failure> {
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
        if self.parameters.xpic_order > 1 {
            self.scratch.xpic = Some(xpic::XpicFields::new(self.grid.num_nodes()));
        }
        if self.parameters.volumetric_averaging == VolumetricAveraging::Cell {
            let cells = self.grid.cells[0] * self.grid.cells[1];
            self.scratch.velocity_gradient = vec![[0.0; 5]; n];
            self.scratch.cell_volume = vec![0.0; cells];
            self.scratch.cell_dilatation = vec![0.0; cells];
        }
    }

    /// Sorts the particles by tile when due: every [`tiles::SORT_INTERVAL`] steps, and when
    /// no tiles are known (a new run, or a checkpoint written before the sort existed).
    /// The decision depends on the step count only, so a resumed run sorts where the
    /// uninterrupted one did.
    pub fn sort_if_due(&mut self) {
        let due = self.steps.is_multiple_of(tiles::SORT_INTERVAL) && self.sorted_at != Some(self.steps);
        if self.tiles.is_empty() || due {
            self.tiles = tiles::sort_particles(&self.grid, &mut self.particles, &mut self.timings.serial);
            self.sorted_at = Some(self.steps);
        }
    }
}

/// Advances the state by `dt` with body force `gravity`. Returns the first invalid particle, if
/// any (the state is then left as computed, for inspection).
pub fn step<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, gravity: [f64; 2]) -> Result<(), Failure> {
    run_passes::<S>(
        state,
        dt,
        // m_i, p_i and f_i = f_int + f_ext from the particles.
        |state, cache| particle_to_grid::particle_to_grid::<F, S>(state, gravity, cache),
        // a_i = (f_int + f_ext)_i / m_i, v⁺_i = v_i + Δt a_i, constrained.
        |state| grid_update::update_grid(state, dt),
        // v_p and Δx_p from v⁺ (FLIP/PIC); MUSL: momentum re-mapped, velocities constrained.
        |state, cache| grid_to_particle::grid_to_particle::<F, S>(state, dt, cache),
        // L_p, F_p, V_p, σ_p, x_p.
        |state, cache| particle_update::update_particles::<F, S>(state, dt, cache),
    )
}

/// The four passes of one step (the dry ones of [`step`] or the saturated ones), with what
/// every step shares: the sort when due, the stencil cache, the time of each phase, the clock.
#[inline(always)]
pub(super) fn run_passes<S: ShapeFunction>(
    state: &mut State,
    dt: f64,
    scatter: impl FnOnce(&mut State, &mut [S::Cache]),
    grid: impl FnOnce(&mut State),
    gather: impl FnOnce(&mut State, &[S::Cache]),
    update: impl FnOnce(&mut State, &[S::Cache]) -> Result<(), Failure>,
) -> Result<(), Failure> {
    let t0 = std::time::Instant::now();
    // Counted in particle → grid's time: the sort is there for the scatter.
    state.sort_if_due();
    let mut cache = take_stencil_cache::<S>(state);
    scatter(state, &mut cache);
    let t1 = std::time::Instant::now();
    grid(state);
    let t2 = std::time::Instant::now();
    gather(state, &cache);
    let t3 = std::time::Instant::now();
    let result = update(state, &cache);
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

/// Allocates the scheme's per-particle stencil cache in the scratch at set-up, so that no step
/// allocates it (`step` would on its first call otherwise).
pub fn allocate_stencil_cache<S: ShapeFunction>(state: &mut State) {
    let cache = take_stencil_cache::<S>(state);
    state.scratch.stencil_cache = Some(Box::new(cache));
}

/// The scheme's per-particle stencil cache, kept in the scratch between steps (allocated at
/// set-up by [`allocate_stencil_cache`], or here if the particle count changed).
fn take_stencil_cache<S: ShapeFunction>(state: &mut State) -> Vec<S::Cache> {
    let n = state.particles.len();
    match state.scratch.stencil_cache.take().map(|b| b.downcast::<Vec<S::Cache>>()) {
        Some(Ok(cache)) if cache.len() == n => *cache,
        _ => vec![S::Cache::default(); n],
    }
}


#[cfg(test)]
mod tests {
    use super::Failure;

    /// The left-grid message names the particle's id, where it left, its speed and velocity,
    /// and both causes (an instability: the time step and FLIP keys; a real outflow: the extent).
    #[test]
    fn the_left_grid_message_names_the_speed_and_the_likely_causes() {
        let failure = Failure::LeftGrid { particle: 3, position: [1.5, -0.25], velocity: [3.0, -4.0] };
        let message = failure.with_id(&[10, 11, 12, 42]).message();
        for part in [
            "particle 42 left the grid at (1.500000e0, -2.500000e-1) m",
            "moving at 5.000e0 m/s",
            "v = (3.000e0, -4.000e0) m/s",
            "simulation.cfl",
            "simulation.flip_fraction",
            "grid.extent",
        ] {
            assert!(message.contains(part), "{part:?} not in {message}");
        }
    }
}
