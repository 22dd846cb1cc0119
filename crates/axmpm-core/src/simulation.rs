//! The public face of the engine: a [`Simulation`] built from a [`Config`], advanced in time,
//! inspected, checkpointed.

use serde::{Deserialize, Serialize};

use crate::constraint::Constraints;
use crate::config::{Config, FormulationKind, ShapeFunctionKind};
use crate::formulation::{Axisymmetric, Formulation, PlaneStrain};
use crate::grid::{GridFields, GridGeometry};
use crate::material::{self, Material};
use crate::particles::Particles;
use crate::setup::create_particles;
use crate::interpolation::{CpGimp, Cpdi2, Linear, ShapeFunction, UGimp};
use crate::solver::{self, Failure, Scratch, State, StepParameters, Tile, TileOrder};

type StepFn = fn(&mut State, f64, [f64; 2]) -> Result<(), Failure>;

/// Courant number c Δt/h at which the explicit step on a square grid of cell size h becomes
/// unstable in 2D: the grid's highest mode (the checkerboard) oscillates at ω = 2√2 c/h, and
/// central differences need ω Δt ≤ 2, i.e. c Δt/h ≤ 1/√2. `simulation.cfl` (default 0.4)
/// keeps the material as placed below it; [`Material::limit_wave_speed`] gets c = this × h/Δt.
pub const COURANT_LIMIT: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// A run that produced an invalid state (NaN, particle outside the grid, inverted element).
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationFailure {
    pub message: String,
    pub time: f64,
    pub steps: u64,
}

impl std::fmt::Display for SimulationFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "step {} (t = {:.6e} s): {}", self.steps, self.time, self.message)
    }
}

impl std::error::Error for SimulationFailure {}

/// Energies of the whole body: J for the body of revolution (axisymmetric, per-radian sums
/// × 2π) or J per metre thickness (plane strain).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Σ ½ m_p |v_p|².
    pub kinetic_energy: f64,
    /// Work done by the full gravity on the displacements, Σ m_p g·(x_p − X_p) (the potential
    /// energy released).
    pub gravity_work: f64,
    /// Stored elastic energy Σ V_p W(σ_p), W the isotropic linear elastic complementary
    /// energy density of each material's E and ν ([`crate::material::complementary_energy`]).
    pub elastic_energy: f64,
    /// Plastic (frictional) dissipation Σ V0_p w_p, w_p the state `plastic_work` (J per unit
    /// reference volume, accumulated by the stress returns; 0 for models without it).
    pub plastic_work: f64,
    /// Work of the faces' and walls' v⁺ corrections against the material since the start of
    /// the run, Σ J_i · v⁺_i,after (see [`crate::constraint`]): the normal component (zero for
    /// roller, friction and fixed walls: impact losses are in the residual) ...
    pub boundary_normal_dissipation: f64,
    /// ... and the tangential component (Coulomb friction; roller walls remove none), with
    /// the slip dissipation at the rigid bodies' interfaces, Σ j·(v⁺_after − w)
    /// (`constraint/rigid_body.rs`, "Energy").
    pub boundary_friction_dissipation: f64,
    /// Work the rigid bodies have done on the material since the start of the run,
    /// −Σ_steps J·w: each step's contact impulse J on the body times the body's velocity w
    /// over the step (`constraint/rigid_body.rs`, "Energy"; an energy input, like gravity's).
    pub rigid_body_work: f64,
    /// Saturated runs (0 otherwise): the pore water's kinetic energy Σ ½ n_p ρ_w V_p |w_p|² ...
    pub water_kinetic_energy: f64,
    /// ... and the work of the Darcy drag on the flow relative to the skeleton since the start
    /// of the run (`solver::saturated`, dissipated).
    pub drag_dissipation: f64,
}

impl Energies {
    /// What the scheme lost: gravity_work + rigid_body_work − (kinetic + elastic + plastic +
    /// boundary), J.
    pub fn residual(&self) -> f64 {
        self.gravity_work + self.rigid_body_work
            - self.kinetic_energy
            - self.elastic_energy
            - self.plastic_work
            - self.boundary_normal_dissipation
            - self.boundary_friction_dissipation
            - self.water_kinetic_energy
            - self.drag_dissipation
    }
}

/// Checkpoint contents; everything else is rebuilt from the configuration.
#[derive(Serialize, Deserialize)]
struct Checkpoint {
    format: u32,
    config: Config,
    particles: Particles,
    time: f64,
    steps: u64,
    /// Kinetic energy removed by the constraints so far ([normal, tangential], per radian or
    /// metre); absent in older checkpoints (then 0).
    #[serde(default)]
    boundary_dissipation: [f64; 2],
    /// Saturated runs: the water's outflow and drag work so far (per radian or metre); absent
    /// in dry runs' and older checkpoints (then 0).
    #[serde(default)]
    water_totals: [f64; 2],
    /// The particles' tiles since the last sort (`particles` are stored in that order, with
    /// their ids); absent in older checkpoints (then the particles are sorted on resume).
    #[serde(default)]
    tiles: Vec<Tile>,
    /// Per rigid body in scenario order, its state (a force-driven body's displacement and
    /// velocities, every body's work); absent in older checkpoints (then each body restarts from
    /// its initial state).
    #[serde(default)]
    rigid_bodies: Vec<crate::constraint::rigid_body::RigidBodyState>,
}

const CHECKPOINT_FORMAT: u32 = 1;

pub struct Simulation {
    config: Config,
    state: State,
    material_names: Vec<String>,
    state_names: Vec<String>,
    dt: f64,
    scheme: Scheme,
    pool: rayon::ThreadPool,
    failure: Option<SimulationFailure>,
    /// Time of the last [`Simulation::reactions`] call (or of the start of this object).
    reactions_since: f64,
    /// Time of the last [`Simulation::rigid_body_parts`] call.
    parts_since: f64,
    /// Each surcharge's force at full load, N per metre or per radian ([`crate::setup::surcharge_forces`]).
    surcharge_totals: Vec<[f64; 2]>,
    /// `grid.follow`: the index, among the rigid bodies, of the body the grid moves with.
    follow: Option<usize>,
}

/// What a run needs of its interpolation scheme, resolved once from the scenario's names:
/// the one place that maps a `ShapeFunctionKind` to its type.
#[derive(Clone, Copy)]
struct Scheme {
    /// The step, monomorphised for the formulation and the scheme.
    step: StepFn,
    /// Sets up the scheme's stencil cache ([`solver::allocate_stencil_cache`]).
    allocate_cache: fn(&mut State),
    /// Whether particles carry CPDI2 corners.
    uses_corners: bool,
    /// Bytes of the stencil cache per particle.
    cache_bytes: usize,
}

impl Scheme {
    fn of<F: Formulation, S: ShapeFunction>(saturated: bool) -> Self {
        Self {
            step: if saturated { solver::saturated::step::<F, S> } else { solver::step::<F, S> },
            allocate_cache: solver::allocate_stencil_cache::<S>,
            uses_corners: S::USES_CORNERS,
            cache_bytes: std::mem::size_of::<S::Cache>(),
        }
    }

    /// `saturated`: the two-phase step ([`solver::saturated`]) instead of the dry one.
    fn select(formulation: FormulationKind, shape: ShapeFunctionKind, saturated: bool) -> Self {
        fn pick<F: Formulation>(shape: ShapeFunctionKind, saturated: bool) -> Scheme {
            match shape {
                ShapeFunctionKind::Linear => Scheme::of::<F, Linear>(saturated),
                ShapeFunctionKind::Ugimp => Scheme::of::<F, UGimp>(saturated),
                ShapeFunctionKind::Cpgimp => Scheme::of::<F, CpGimp>(saturated),
                ShapeFunctionKind::Cpdi2 => Scheme::of::<F, Cpdi2>(saturated),
            }
        }
        match formulation {
            FormulationKind::PlaneStrain => pick::<PlaneStrain>(shape, saturated),
            FormulationKind::Axisymmetric => pick::<Axisymmetric>(shape, saturated),
        }
    }
}


/// Whether `tiles` cover the particle arrays `0..n` in order, each tile non-empty.
fn tiles_cover(tiles: &[Tile], n: usize) -> bool {
    let mut next = 0;
    for t in tiles {
        if t.start != next || t.end <= t.start {
            return false;
        }
        next = t.end;
    }
    !tiles.is_empty() && next as usize == n
}

impl Simulation {
    /// Builds a run from the resolved scenario JSON (see `docs/architecture.md`).
    pub fn from_json(json: &str, threads: usize) -> Result<Self, String> {
        Self::new(Config::from_json(json)?, threads)
    }

    /// Builds a run. `threads` = 0 uses every core the problem can use (one per 10,000
    /// particles, at most all of them); results do not depend on it.
    pub fn new(config: Config, threads: usize) -> Result<Self, String> {
        Self::build(config, threads, None)
    }

    fn build(config: Config, threads: usize, restored: Option<(Particles, f64, u64, Vec<Tile>)>) -> Result<Self, String> {
        config.validate()?;
        let material_names: Vec<String> = config.materials.keys().cloned().collect();
        let mut materials: Vec<Box<dyn Material>> = config
            .materials
            .iter()
            .map(|(name, m)| material::build(name, m))
            .collect::<Result<_, _>>()?;
        let mut state_names: Vec<String> = Vec::new();
        for m in &materials {
            for n in m.state_names() {
                if !state_names.iter().any(|s| s == n) {
                    state_names.push((*n).to_string());
                }
            }
        }
        let stride = materials.iter().map(|m| m.state_names().len()).max().unwrap_or(0).max(1);
        let g = &config.grid;
        let grid = GridGeometry::new(g.origin, g.extent, g.cell_size);
        let s = &config.simulation;
        let axisymmetric = s.formulation == FormulationKind::Axisymmetric;
        let saturated = config.has_saturated_bodies();
        let scheme = Scheme::select(s.formulation, s.shape_function, saturated);
        let with_corners = scheme.uses_corners;
        let (mut particles, time, steps, tiles) = match restored {
            Some(r) => r,
            None => {
                let particles = match s.formulation {
                    FormulationKind::PlaneStrain => {
                        create_particles::<PlaneStrain>(&config, &grid, &materials, &material_names, stride, with_corners)?
                    }
                    FormulationKind::Axisymmetric => {
                        create_particles::<Axisymmetric>(&config, &grid, &materials, &material_names, stride, with_corners)?
                    }
                };
                (particles, 0.0, 0, Vec::new())
            }
        };
        // Tiles belong to the order they were sorted into: without the ids, sort again.
        let tiles = if particles.id.len() == particles.len() && tiles_cover(&tiles, particles.len()) {
            TileOrder::from_tiles(tiles)
        } else {
            TileOrder::default()
        };
        particles.ensure_ids();
        particles.shrink_to_fit();
        if particles.is_empty() {
            return Err("bodies: no particle was created (is every body at least one cell in size?)".into());
        }
        let used: Vec<bool> =
            (0..materials.len()).map(|m| particles.material.iter().any(|&id| id as usize == m)).collect();
        let wave_speed = materials
            .iter()
            .zip(&used)
            .filter(|(_, &u)| u)
            .map(|(m, _)| m.wave_speed())
            .fold(0.0_f64, f64::max);
        // A saturated body's undrained wave (0 in a dry run: the step is the dry one).
        let wave_speed = wave_speed.max(solver::saturated::wave_speed(&config, &materials));
        let dt = if s.time_step > 0.0 { s.time_step } else { s.cfl * g.cell_size / wave_speed };
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(format!("time step {dt} is not positive; check the materials' stiffness and density"));
        }
        // The step is computed for the materials as placed; a model whose wave speed grows
        // with the deformation (hypoelastic moduli in dilated material) may bound it here.
        let max_wave_speed = COURANT_LIMIT * g.cell_size / dt;
        for m in materials.iter_mut() {
            m.limit_wave_speed(max_wave_speed);
        }
        let mean_mass = particles.mass.iter().sum::<f64>() / particles.len() as f64;
        let parameters = StepParameters {
            flip_fraction: s.flip_fraction,
            xpic_order: s.xpic_order,
            damping: s.damping,
            scheme: s.update_scheme,
            mass_threshold: 1e-12 * mean_mass,
            volumetric_averaging: s.volumetric_averaging,
            axisymmetric,
            isa: crate::solver::Isa::detect(),
        };
        // The grid the solver steps on. With `grid.follow` it has one more row of cells and moves
        // along y with the body (`Simulation::place_grid`): it always covers the scenario's grid.
        let step_grid = if g.follow.is_some() { grid.with_extra_row() } else { grid };
        let mut constraints = Constraints::new(&step_grid, &config.boundaries, &config.walls, axisymmetric, g.follow.is_some());
        // Rigid bodies last. Their reach is the largest particle half-width h/(2n) of the bodies.
        let finest = config.bodies.iter().map(|b| b.particles_per_cell).min().unwrap_or(1).max(1);
        let reach = g.cell_size / (2.0 * finest as f64);
        // Penalty contact: k = ρ c_p² / h, the stiffness of one cell of the stiffest material in
        // uniaxial strain (constraint/rigid_body.rs, "Penalty"); the step keeps c_p Δt/h ≤ 1/2.
        let constrained_modulus = materials
            .iter()
            .zip(&used)
            .filter(|(_, &u)| u)
            .map(|(m, _)| m.density() * m.wave_speed() * m.wave_speed())
            .fold(0.0_f64, f64::max);
        for body in crate::setup::rigid_bodies(&config)? {
            let followed = g.follow.as_deref() == Some(crate::constraint::Constraint::name(&body));
            let body = body
                .with_reach(reach)
                .with_penalty_stiffness(constrained_modulus / g.cell_size)
                .followed_by_the_grid(followed);
            constraints.push(Box::new(body));
        }
        // A penalty contact adds to a surface node at most the stiffness of the soil's own cell
        // (k h = ρ c_p²), so its highest frequency is at most √2 times the soil's: the Courant
        // number is kept below COURANT_LIMIT/√2 = 1/2 (constraint/rigid_body.rs, "Penalty").
        let dt = if constraints.has_particle_contact() {
            dt.min(0.5 * g.cell_size / wave_speed)
        } else {
            dt
        };
        // The followed body's index among the rigid bodies (`validate_follow` made sure it exists).
        let follow = constraints.rigid_bodies().position(crate::constraint::RigidBody::is_followed_by_the_grid);
        let water = solver::saturated::WaterState::new(&config, &step_grid, &particles, &constraints);
        let surcharge_totals = match s.formulation {
            FormulationKind::PlaneStrain => crate::setup::surcharge_forces::<PlaneStrain>(&config, &particles),
            FormulationKind::Axisymmetric => crate::setup::surcharge_forces::<Axisymmetric>(&config, &particles),
        };
        let mut state = State {
            water,
            grid: step_grid,
            fields: GridFields::new(step_grid.num_nodes()),
            tiles,
            sorted_at: None,
            scratch: Scratch::default(),
            particles,
            state_lengths: materials.iter().map(|m| m.state_names().len()).collect(),
            materials,
            constraints,
            parameters,
            time,
            steps,
            timings: Default::default(),
            load_factor: 1.0,
        };
        state.allocate_scratch();
        state.scratch.cell_laplacian = crate::material::CellLaplacian::of(&state.materials, &step_grid, || {
            crate::material::FluidityBoundary::new(&step_grid, &config.boundaries, &config.walls, axisymmetric)
        });
        if follow.is_some() && state.scratch.cell_laplacian.is_some() {
            return Err(format!("grid.follow: {}", crate::material::FOLLOW_WITH_NONLOCAL));
        }
        // threads = 0: as many cores as the problem can use. Below ~10,000 particles per thread
        // the fork/join of each pass costs more than it saves. Results do not depend on it.
        let threads = if threads == 0 {
            let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
            (state.particles.len() / 10_000).clamp(1, cores)
        } else {
            threads
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| format!("could not start {threads} threads: {e}"))?;
        // A new run (or an older checkpoint) is sorted at the end of the set-up, once the grid is
        // placed, on the run's own threads (never rayon's global pool: see `Particles::permute`).
        let reactions_since = state.time;
        let mut simulation = Self {
            config,
            state,
            material_names,
            state_names,
            dt,
            scheme,
            pool,
            failure: None,
            reactions_since,
            parts_since: reactions_since,
            surcharge_totals,
            follow,
        };
        simulation.place_grid();
        if simulation.state.tiles.is_empty() {
            let Self { pool, state, .. } = &mut simulation;
            pool.install(|| state.sort_if_due());
        }
        (simulation.scheme.allocate_cache)(&mut simulation.state);
        Ok(simulation)
    }

    /// With `grid.follow`, places the grid for the step that starts now: its rows move with the
    /// followed body's axial displacement u_y, modulo one cell h, origin_y = y_0 − ((−u_y) mod h),
    /// so every node row keeps its distance to the body, and the grid (one row taller than the
    /// scenario's) covers the scenario's grid y_0 … y_0 + H at every step. Particles carry the
    /// whole state, so only the nodes move (the moving mesh of Beuth 2012 and Ceccato et al. 2016,
    /// without their compressed zone: the faces' node rows move with the grid, at most one cell
    /// outside the scenario's faces; docs/physics.md §8).
    fn place_grid(&mut self) {
        let Some(k) = self.follow else { return };
        let body = self.state.constraints.rigid_bodies().nth(k).expect("followed body");
        let uy = body.displacement(self.state.time)[1];
        let h = self.state.grid.cell_size;
        self.state.grid.origin[1] = self.config.grid.origin[1] - (-uy).rem_euclid(h);
    }

    /// Gravity at the current time: ramped linearly from zero over `gravity_ramp_time`.
    pub fn gravity(&self) -> [f64; 2] {
        let s = &self.config.simulation;
        let factor = self.load_factor();
        [s.gravity[0] * factor, s.gravity[1] * factor]
    }

    /// The share of gravity and of the surcharges applied at the current time: ramped
    /// linearly from zero over `gravity_ramp_time`, 1 without a ramp.
    pub fn load_factor(&self) -> f64 {
        let s = &self.config.simulation;
        if s.gravity_ramp_time > 0.0 { (self.state.time / s.gravity_ramp_time).min(1.0) } else { 1.0 }
    }

    /// Each surcharge's name and the force it applies to the material now (N per metre in
    /// plane strain, whole ring in axisymmetry; negative: downward).
    pub fn surcharge_forces(&self) -> Vec<(String, [f64; 2])> {
        let factor = self.load_factor() * if self.state.parameters.axisymmetric { std::f64::consts::TAU } else { 1.0 };
        self.config
            .surcharges
            .iter()
            .zip(&self.surcharge_totals)
            .enumerate()
            .map(|(i, (c, total))| {
                let name = c.name.clone().unwrap_or_else(|| format!("surcharge_{i}"));
                (name, [factor * total[0], factor * total[1]])
            })
            .collect()
    }

    /// Advances to time `until` (the last step shortened to land on it exactly) or by
    /// `max_steps` steps, whichever comes first. Returns the number of steps taken.
    pub fn advance(&mut self, until: f64, max_steps: u64) -> Result<u64, SimulationFailure> {
        if let Some(f) = &self.failure {
            return Err(f.clone());
        }
        let mut taken = 0;
        while taken < max_steps {
            let remaining = until - self.state.time;
            if remaining <= 0.0 {
                break;
            }
            // Land on `until` without a sliver step: the last one or two steps share the rest.
            let (dt, lands) = if remaining <= self.dt {
                (remaining, true)
            } else if remaining < 2.0 * self.dt {
                (0.5 * remaining, false)
            } else {
                (self.dt, false)
            };
            let gravity = self.gravity();
            self.state.load_factor = self.load_factor();
            self.place_grid();
            let start = self.state.time;
            // The force-driven bodies' velocity change of the step without the contact, for
            // the contact's body velocity (constraint/rigid_body.rs, "Force-driven bodies").
            self.state.constraints.begin_rigid_body_step(start, dt, gravity);
            let step_fn = self.scheme.step;
            let state = &mut self.state;
            let result = self.pool.install(|| step_fn(state, dt, gravity));
            let g = &self.config.grid;
            let upper = [g.origin[0] + g.extent[0], g.origin[1] + g.extent[1]];
            let (total, origin) = (self.total_factor(), g.origin);
            let bodies = self.state.constraints.end_rigid_body_step(start, dt, total, origin, upper);
            if lands {
                self.state.time = until;
            }
            taken += 1;
            let message = match (result, bodies) {
                (Err(failure), _) => Some(failure.with_id(&self.state.particles.id).message()),
                (Ok(()), Err(message)) => Some(message),
                (Ok(()), Ok(())) => None,
            };
            if let Some(message) = message {
                let f = SimulationFailure { message, time: self.state.time, steps: self.state.steps };
                self.failure = Some(f.clone());
                return Err(f);
            }
        }
        Ok(taken)
    }

    pub fn config(&self) -> &Config {
        &self.config
    }
    /// The particles in id order (the order they were created in), whatever order the
    /// solver keeps them in (a copy when that differs).
    pub fn particles(&self) -> std::borrow::Cow<'_, Particles> {
        self.state.particles.in_id_order()
    }
    /// One per-particle array (`field` of the particles in the solver's order), in id order:
    /// a copy of that array only, for output.
    pub fn particle_values<T: Copy + Default>(&self, field: impl FnOnce(&Particles) -> &[T]) -> Vec<T> {
        let p = &self.state.particles;
        p.by_id(field(p))
    }

    /// The particles in the order the solver keeps them (sorted by grid tile; `id` gives
    /// each one's place in [`Simulation::particles`]).
    pub fn particles_in_solver_order(&self) -> &Particles {
        &self.state.particles
    }
    pub fn grid(&self) -> &GridGeometry {
        &self.state.grid
    }
    pub fn grid_fields(&self) -> &GridFields {
        &self.state.fields
    }
    pub fn time(&self) -> f64 {
        self.state.time
    }
    pub fn steps(&self) -> u64 {
        self.state.steps
    }
    /// Nominal time step (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Bytes held per particle: the particle arrays plus the per-particle scratch of the step
    /// (position increments, the scheme's stencil cache and, with cell averaging, the velocity
    /// gradients; the grid is counted separately, per node; the scatter needs no nodal buffers of its own).
    pub fn bytes_per_particle(&self) -> usize {
        let n = self.state.particles.len().max(1);
        let sc = &self.state.scratch;
        let cache = self.scheme.cache_bytes;
        let scratch = sc.displacement.capacity() * std::mem::size_of::<[f64; 2]>()
            + sc.velocity_gradient.capacity() * std::mem::size_of::<[f64; 5]>();
        self.state.particles.bytes_per_particle() + scratch / n + cache
    }
    pub fn threads(&self) -> usize {
        self.pool.current_num_threads()
    }
    /// The instruction set the step's loops run with (`solver::isa`; it changes no result).
    pub fn isa(&self) -> solver::Isa {
        self.state.parameters.isa
    }
    /// Runs the step's loops with `isa` from now on; an error if this CPU does not have it.
    pub fn set_isa(&mut self, isa: solver::Isa) -> Result<(), String> {
        if isa == solver::Isa::Avx2 && solver::Isa::best_supported() != solver::Isa::Avx2 {
            return Err("this CPU does not support AVX2, FMA and BMI2".into());
        }
        self.state.parameters.isa = isa;
        Ok(())
    }
    pub fn material_names(&self) -> &[String] {
        &self.material_names
    }
    pub fn state_names(&self) -> &[String] {
        &self.state_names
    }
    /// Wall seconds spent in each phase of the step since this object was built.
    pub fn timings(&self) -> solver::PhaseTimings {
        self.state.timings
    }
    pub fn failure(&self) -> Option<&SimulationFailure> {
        self.failure.as_ref()
    }

    /// Per-particle state as rows of `state_names()` values (0 where a particle's material
    /// does not have that variable).
    pub fn state_table(&self) -> Vec<f64> {
        let p = &self.state.particles;
        let cols = self.state_names.len();
        let mut out = vec![0.0; p.len() * cols];
        let columns: Vec<Vec<usize>> = self
            .state
            .materials
            .iter()
            .map(|m| m.state_names().iter().map(|n| self.state_names.iter().position(|s| s == n).unwrap()).collect())
            .collect();
        let stride = p.state_stride;
        // Row `id` of the table is the particle with that id.
        let ids = if p.id.len() == p.len() { Some(&p.id) } else { None };
        for i in 0..p.len() {
            let row = ids.map_or(i, |ids| ids[i] as usize);
            for (k, &c) in columns[p.material[i] as usize].iter().enumerate() {
                out[row * cols + c] = p.state[i * stride + k];
            }
        }
        out
    }

    /// Multiplier from per-radian (axisymmetric) or per-metre (plane strain) sums to the
    /// reported totals: 2π for the body of revolution, 1 per metre thickness.
    pub fn total_factor(&self) -> f64 {
        match self.config.simulation.formulation {
            FormulationKind::PlaneStrain => PlaneStrain::TOTAL_FACTOR,
            FormulationKind::Axisymmetric => Axisymmetric::TOTAL_FACTOR,
        }
    }

    /// Names of the constraints whose reactions [`Simulation::reactions`] reports, in order:
    /// the faces that are not free ("left", "right", "bottom", "top"), then the walls
    /// ("wall_0", "wall_1", ... by their index in the scenario).
    pub fn reaction_names(&self) -> Vec<String> {
        self.state.constraints.reaction_names()
    }

    /// Per reporting constraint, the mean force (N; whole body: × 2π in axisymmetry, per metre
    /// in plane strain) the material exerted on it since the last call: the impulse of the
    /// momentum-update corrections, Σ m_i (v⁺_before − v⁺_after), over the elapsed time.
    /// Resets the accumulators; zero forces when no time has elapsed.
    pub fn reactions(&mut self) -> Vec<(String, [f64; 2])> {
        let elapsed = self.state.time - self.reactions_since;
        self.reactions_since = self.state.time;
        let scale = if elapsed > 0.0 { self.total_factor() / elapsed } else { 0.0 };
        self.state
            .constraints
            .take_impulses()
            .into_iter()
            .map(|(name, impulse)| (name, [impulse[0] * scale, impulse[1] * scale]))
            .collect()
    }

    /// Displacement of each rigid body at the current time, m: the integral of its prescribed
    /// velocity (a function of time only), or a force-driven body's current displacement.
    pub fn rigid_body_displacements(&self) -> Vec<(String, [f64; 2])> {
        use crate::constraint::Constraint;
        let t = self.state.time;
        self.state.constraints.rigid_bodies().map(|b| (b.name().to_string(), b.displacement(t))).collect()
    }

    /// Velocity of each rigid body at the current time, m/s: the prescribed one, or the one a
    /// force-driven body moved with over the last step.
    pub fn rigid_body_velocities(&self) -> Vec<(String, [f64; 2])> {
        use crate::constraint::Constraint;
        let t = self.state.time;
        self.state.constraints.rigid_bodies().map(|b| (b.name().to_string(), b.velocity(t))).collect()
    }

    /// Per rigid body, what a checkpoint keeps of it (a force-driven body's displacement X and
    /// integration velocity V, its velocity over the last step, the work it has done on the
    /// material per metre or radian; `constraint::rigid_body::RigidBodyState`).
    pub fn rigid_body_states(&self) -> Vec<(String, crate::constraint::rigid_body::RigidBodyState)> {
        use crate::constraint::Constraint;
        self.state.constraints.rigid_bodies().map(|b| (b.name().to_string(), b.state())).collect()
    }

    /// Per rigid body, its outline (counter-clockwise vertices, m) at the current time.
    pub fn rigid_body_outlines(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        use crate::constraint::Constraint;
        let t = self.state.time;
        self.state
            .constraints
            .rigid_bodies()
            .map(|b| {
                let d = b.displacement(t);
                let outline = b.region().outline();
                (b.name().to_string(), outline.vertices().iter().map(|v| [v[0] + d[0], v[1] + d[1]]).collect())
            })
            .collect()
    }

    /// Per rigid body, the mean force (N, whole body) the material exerted on it since the last
    /// call, split into parts: `base` (contact normals facing down) and `shaft` (the rest), then
    /// the body's named parts by height and `rest` if it names any
    /// (`constraint::rigid_body`, "Reaction"). Each split sums to the body's force in
    /// [`Simulation::reactions`], which keeps its own interval.
    pub fn rigid_body_parts(&mut self) -> Vec<(String, Vec<(String, [f64; 2])>)> {
        use crate::constraint::Constraint;
        let elapsed = self.state.time - self.parts_since;
        self.parts_since = self.state.time;
        let scale = if elapsed > 0.0 { self.total_factor() / elapsed } else { 0.0 };
        let force = |impulse: [f64; 2]| [impulse[0] * scale, impulse[1] * scale];
        self.state
            .constraints
            .rigid_bodies_mut()
            .map(|b| {
                let (base, shaft) = b.take_impulse_parts();
                let mut parts = vec![("base".to_string(), force(base)), ("shaft".to_string(), force(shaft))];
                parts.extend(b.take_named_parts().into_iter().map(|(name, impulse)| (name, force(impulse))));
                (b.name().to_string(), parts)
            })
            .collect()
    }

    /// The water volume that left the saturated bodies since the start of the run, m³ per
    /// metre (plane strain) or per radian (axisymmetric) (`solver::saturated::outflow_increment`);
    /// `None` in a dry run.
    pub fn water_outflow(&self) -> Option<f64> {
        self.state.water.as_ref().map(|w| w.outflow)
    }

    /// The energy budget ([`Energies`]), summed in particle order (deterministic).
    pub fn energies(&self) -> Energies {
        let p = &self.state.particles;
        // Summed in id order, so the budget does not depend on the solver's particle order.
        let index = p.index_of_ids();
        let g = self.config.simulation.gravity;
        let materials = &self.state.materials;
        let work_slot: Vec<Option<usize>> =
            materials.iter().map(|m| m.state_names().iter().position(|n| *n == "plastic_work")).collect();
        let mut e = Energies::default();
        for &i in &index {
            let i = i as usize;
            let v = p.velocity[i];
            e.kinetic_energy += 0.5 * p.mass[i] * (v[0] * v[0] + v[1] * v[1]);
            let x = p.position[i];
            let x0 = p.initial_position[i];
            e.gravity_work += p.mass[i] * (g[0] * (x[0] - x0[0]) + g[1] * (x[1] - x0[1]));
            let m = p.material[i] as usize;
            e.elastic_energy += p.volume[i] * materials[m].elastic_energy_density(&p.stress[i]);
            if let Some(k) = work_slot[m] {
                e.plastic_work += p.initial_volume[i] * p.state[i * p.state_stride + k];
            }
        }
        if let Some(water) = &self.state.water {
            for &i in &index {
                let i = i as usize;
                let w = p.water_velocity[i];
                e.water_kinetic_energy += 0.5 * p.porosity[i] * water.density * p.volume[i] * (w[0] * w[0] + w[1] * w[1]);
            }
            e.drag_dissipation = water.drag_work;
        }
        let [normal, tangential] = self.state.constraints.dissipated_energy();
        let total = self.total_factor();
        e.water_kinetic_energy *= total;
        e.drag_dissipation *= total;
        e.kinetic_energy *= total;
        e.gravity_work *= total;
        e.elastic_energy *= total;
        e.plastic_work *= total;
        e.boundary_normal_dissipation = normal * total;
        e.boundary_friction_dissipation = tangential * total;
        e.rigid_body_work = self.state.constraints.rigid_body_work() * total;
        e
    }

    /// Serialises everything needed to continue the run bit for bit.
    pub fn to_bytes(&self) -> Result<Vec<u8>, String> {
        let checkpoint = Checkpoint {
            format: CHECKPOINT_FORMAT,
            config: self.config.clone(),
            particles: self.state.particles.clone(),
            time: self.state.time,
            steps: self.state.steps,
            boundary_dissipation: self.state.constraints.dissipated_energy(),
            water_totals: self.state.water.as_ref().map_or([0.0; 2], |w| [w.outflow, w.drag_work]),
            tiles: self.state.tiles.tiles.clone(),
            rigid_bodies: self.state.constraints.rigid_bodies().map(|b| b.state()).collect(),
        };
        serde_json::to_vec(&checkpoint).map_err(|e| format!("checkpoint: {e}"))
    }

    /// Restores a run written by [`Simulation::to_bytes`].
    pub fn from_bytes(data: &[u8], threads: usize) -> Result<Self, String> {
        let c: Checkpoint = serde_json::from_slice(data).map_err(|e| format!("not a readable axmpm checkpoint: {e}"))?;
        if c.format != CHECKPOINT_FORMAT {
            return Err(format!("checkpoint format {} is not supported (expected {CHECKPOINT_FORMAT})", c.format));
        }
        let mut sim = Self::build(c.config, threads, Some((c.particles, c.time, c.steps, c.tiles)))?;
        sim.state.constraints.restored_dissipation = c.boundary_dissipation;
        for (body, state) in sim.state.constraints.rigid_bodies_mut().zip(&c.rigid_bodies) {
            body.restore(state);
        }
        if let Some(water) = sim.state.water.as_mut() {
            [water.outflow, water.drag_work] = c.water_totals;
        }
        Ok(sim)
    }
}
