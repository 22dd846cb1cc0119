//! Saturated soil: the single-point two-phase formulation with the velocities of the solid
//! skeleton v and of the pore water w (Jassim, Stolle & Vermeer 2013, IJNAMG 37; the v–w
//! form of Anura3D), in plane strain and in axisymmetry (docs/physics.md, "Saturated soil").
//!
//! Grains incompressible, pore water compressible (bulk modulus K_w), effective stress
//! σ = σ′ − p I (tension positive, p positive in compression). Per unit volume of mixture, with
//! porosity n, grain density ρ_s, water density ρ_w and hydraulic conductivity k (m/s):
//!
//! - water:   ρ_w a_w = −∇p + ρ_w g − (n γ_w / k)(w − v),  γ_w = ρ_w g_n (g_n = [`STANDARD_GRAVITY`]);
//! - mixture: (1 − n) ρ_s a_s + n ρ_w a_w = ∇·(σ′ − p I) + ρ_sat g;
//! - storage: ṗ = −(K_w / n) [(1 − n) ∇·v + n ∇·w], each divergence with its hoop rate
//!   v_r / r in axisymmetry; the water's momentum balance carries the hoop term of p as the
//!   solid's carries σ_θθ.
//!
//! Lumped on the nodes (per metre or per radian) with M_s = Σ S m_s, M̄_w = Σ S ρ_w V (the water
//! equation's mass), M_w = Σ S n ρ_w V (the water in the mixture) and Q = Σ S n γ_w V / k:
//!
//!   M̄_w (w⁺ − w) = Δt F_w − Δt Q (w⁺ − v⁺),   M_s (v⁺ − v) + M_w (w⁺ − w) = Δt F.
//!
//! The drag is taken at the end of the step (implicit), node by node: two unknowns per node
//! and direction, solved in closed form ([`solve_node`]), no global system. The drag then sets
//! no time step (an explicit drag needs Δt < 2k/(n g): 5e-9 s at k = 1e-8 m/s); the step is the
//! undrained wave limit ([`wave_speed`]) for any k. As k → 0 the two velocities lock (w⁺ = v⁺,
//! the undrained mixture), as k → ∞ they decouple.
//!
//! A drained boundary (p = 0) is the natural condition of the water equation (no boundary
//! integral): free surfaces are drained. An impermeable face holds the water's normal velocity
//! to the solid's.
//!
//! Reactions: a constraint that changes the solid's velocity at a node by δv changes the
//! water's by β δv through the drag (β = Δt Q/(M̄_w + Δt Q), the water row), so it books the
//! mixture's impulse ([`reaction_mass`]) M_s δv + M_w β δv; an impermeable face or wall that
//! holds the solid also books the water's impulse M_w (w⁺ − v⁺) its impermeability removes.
//! The reported reaction is then the total force on the face, M_s Δv + M_w Δw against the
//! unconstrained update. The pore pressure is updated at the particles; its increment is averaged
//! over the particles of each background cell (the cell-centre volumetric rate, as the mean
//! dilatation does for the solid), which keeps the pressure field free of checkerboards.
//!
//! A loading plate (`loading_plate`: the surface load through a rigid, frictionless,
//! impermeable plate, as in Mandel's problem) makes the nodes of the grid row at the loaded
//! surface move vertically together, with the water's vertical velocity held to the solid's
//! there ([`move_plate`]).
//!
//! A run without a saturated body never enters this module (`Simulation` selects the dry
//! step), so dry results are unchanged bit for bit.

use rayon::prelude::*;

use super::grid_update::{constrain_velocities, damped};
use super::tiles::{inside, scatter_by_colour, zero_box, Shared, TileReach};
use super::{Failure, State};
use crate::config::{BoundariesConfig, Config, Drainage, DrainageConfig, FormulationKind, WallConfig};
use crate::constraint::Constraints;
use crate::formulation::Formulation;
use crate::grid::{GridGeometry, NodeBox};
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::material::Material;
use crate::particles::Particles;

/// g_n in γ_w = ρ_w g_n: the hydraulic conductivity k is defined under standard gravity,
/// whatever gravity the run itself applies (m/s²).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// The pore water of the run (K_w, ρ_w), from the first saturated body.
fn pore_water(config: &Config) -> Option<(f64, f64)> {
    config.bodies.iter().find_map(|b| b.saturated.as_ref().map(|s| (s.water_bulk_modulus, s.water_density)))
}

/// Undrained P-wave speed √((E_c + K_w/n)/ρ_sat) of a saturated skeleton of constrained
/// modulus `e_c` and grain density `rho_s`, or the faster of the two phases when the drag
/// decouples them (high k): the water alone √(K_w/ρ_w) and the skeleton alone
/// √(E_c/((1 − n)ρ_s)). The explicit step is bounded by this speed whatever k is (the drag is
/// implicit).
pub fn saturated_wave_speed(e_c: f64, rho_s: f64, n: f64, k_w: f64, rho_w: f64) -> f64 {
    let rho_sat = (1.0 - n) * rho_s + n * rho_w;
    let undrained = ((e_c + k_w / n) / rho_sat).sqrt();
    let water = (k_w / rho_w).sqrt();
    let skeleton = (e_c / ((1.0 - n) * rho_s)).sqrt();
    undrained.max(water).max(skeleton)
}

/// The largest wave speed of the saturated bodies (0 for a dry run); `materials` in the order
/// of `config.materials`.
pub fn wave_speed(config: &Config, materials: &[Box<dyn Material>]) -> f64 {
    let names: Vec<&String> = config.materials.keys().collect();
    config
        .bodies
        .iter()
        .filter_map(|b| {
            let s = b.saturated.as_ref()?;
            let m = &materials[names.iter().position(|n| **n == b.material)?];
            // The skeleton's constrained modulus from its own (dry) wave speed: E_c = ρ_s c².
            let e_c = m.density() * m.wave_speed() * m.wave_speed();
            Some(saturated_wave_speed(e_c, m.density(), s.porosity, s.water_bulk_modulus, s.water_density))
        })
        .fold(0.0, f64::max)
}

/// Nodal fields and per-particle scratch of the water, allocated with the run.
#[derive(Clone, Debug, Default)]
pub struct WaterState {
    /// K_w and ρ_w of the pore water.
    pub bulk_modulus: f64,
    pub density: f64,
    /// Nodes lighter than this (in M̄_w) carry no water.
    pub mass_threshold: f64,
    /// M̄_w = Σ S ρ_w V, the water equation's mass.
    pub equation_mass: Vec<f64>,
    /// M_w = Σ S n ρ_w V, the water in the mixture.
    pub mass: Vec<f64>,
    /// Σ S ρ_w V w.
    pub momentum: Vec<[f64; 2]>,
    /// Q = Σ S n γ_w V / k.
    pub drag: Vec<f64>,
    /// F_w = Σ V p ∇S (+ the hoop term V p S / R_p on r) + Σ S ρ_w V g.
    pub force: Vec<[f64; 2]>,
    /// w at the start of the step and w⁺.
    pub velocity: Vec<[f64; 2]>,
    pub velocity_new: Vec<[f64; 2]>,
    /// The nodes and directions whose water velocity follows the solid's (impermeable faces
    /// and walls, the axis, the loading plate).
    pub impermeable: Vec<ImpermeableNode>,
    /// Per node and direction, whether a `roller` or `fixed` face or wall holds the solid's
    /// velocity there (at zero, whatever the force): no damping there (`update_grid`).
    pub held: Vec<[bool; 2]>,
    /// Per node, the mass the constraints book their impulses with ([`reaction_mass`]).
    pub reaction_mass: Vec<f64>,
    /// Some particle carries a surface load ([`Particles::external_force`]).
    pub loaded: bool,
    /// Per particle: Δt ∇·w, then the storage increment; the volume at the start of the update.
    pub water_dilatation: Vec<f64>,
    pub volume_before: Vec<f64>,
    /// Per background cell: Σ V and Σ V e of the saturated particles (pressure averaging).
    pub cell_volume: Vec<f64>,
    pub cell_storage: Vec<f64>,
    /// Since the start of the run, per metre (plane strain) or per radian (axisymmetric): the
    /// water volume that left the saturated bodies ([`outflow_increment`]), m³, and the work
    /// of the drag on the relative flow ([`drag_work`]), J.
    pub outflow: f64,
    pub drag_work: f64,
    /// The grid row of the loading plate's nodes (`None`: no plate).
    pub plate_row: Option<usize>,
    /// Prescribed pore pressures of the faces [left, right, bottom, top] (`[drainage.pressure]`).
    pub face_pressures: [Option<f64>; 4],
}

/// A node and direction where no water crosses, and the constraint that books the water's
/// impulse there: the first that holds the solid's velocity in that direction at that node
/// ([`crate::constraint::Constraint::held_nodes`]; its index in [`Constraints::list`]), as it
/// books the solid's impulse there. `None`: no reporting constraint holds it (the axis, the
/// loading plate, an impermeable face that is free for the skeleton).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpermeableNode {
    pub node: u32,
    pub axis: u8,
    pub owner: Option<u32>,
}

impl WaterState {
    /// The water of a run (`None` for a dry one); `constraints`: the run's, to book the
    /// impermeable faces' and walls' water impulses to.
    pub fn new(config: &Config, grid: &GridGeometry, particles: &Particles, constraints: &Constraints) -> Option<Box<Self>> {
        let (bulk_modulus, density) = pore_water(config)?;
        let nodes = grid.num_nodes();
        let n = particles.len();
        let cells = grid.cells[0] * grid.cells[1];
        let saturated: Vec<f64> = (0..n).filter(|&p| particles.porosity[p] > 0.0).map(|p| density * particles.volume[p]).collect();
        let mean = saturated.iter().sum::<f64>() / saturated.len().max(1) as f64;
        let axisymmetric = config.simulation.formulation == FormulationKind::Axisymmetric;
        let plate = plate_row(config, grid, particles);
        // Per node and direction, the first reporting constraint that holds the solid there,
        // and whether some face or wall holds it for good.
        let mut holder = vec![[None; 2]; nodes];
        let mut held = vec![[false; 2]; nodes];
        for (index, c) in constraints.list.iter().enumerate() {
            let Some(h) = c.held_nodes() else { continue };
            for &node in h.nodes {
                for d in (0..2).filter(|&d| h.directions[d]) {
                    if c.reports_reaction() {
                        holder[node as usize][d] = holder[node as usize][d].or(Some(index as u32));
                    }
                    held[node as usize][d] |= h.bilateral;
                }
            }
        }
        let mut impermeable: Vec<ImpermeableNode> = impermeable_nodes(grid, &config.boundaries, &config.drainage, &config.walls, axisymmetric)
            .into_iter()
            .map(|(node, axis)| ImpermeableNode { node, axis, owner: holder[node as usize][axis as usize] })
            .collect();
        if let Some(row) = plate {
            impermeable.extend((0..grid.nodes[0]).map(|i| ImpermeableNode { node: grid.node_index(i, row) as u32, axis: 1, owner: None }));
        }
        Some(Box::new(Self {
            bulk_modulus,
            density,
            mass_threshold: 1e-12 * mean,
            equation_mass: vec![0.0; nodes],
            mass: vec![0.0; nodes],
            momentum: vec![[0.0; 2]; nodes],
            drag: vec![0.0; nodes],
            force: vec![[0.0; 2]; nodes],
            velocity: vec![[0.0; 2]; nodes],
            velocity_new: vec![[0.0; 2]; nodes],
            impermeable,
            held,
            reaction_mass: vec![0.0; nodes],
            loaded: particles.external_force.iter().any(|f| *f != [0.0; 2]),
            water_dilatation: vec![0.0; n],
            volume_before: vec![0.0; n],
            cell_volume: vec![0.0; cells],
            cell_storage: vec![0.0; cells],
            outflow: 0.0,
            drag_work: 0.0,
            plate_row: plate,
            face_pressures: config.drainage.pressure.faces(),
        }))
    }
}

/// The grid row of the loading plate: the row nearest the highest loaded surface (the upper
/// edges of the particles that carry a surface load), when some body asks for a plate.
fn plate_row(config: &Config, grid: &GridGeometry, particles: &Particles) -> Option<usize> {
    if !config.bodies.iter().any(|b| b.saturated.as_ref().is_some_and(|s| s.loading_plate)) {
        return None;
    }
    let top = (0..particles.len())
        .filter(|&p| particles.external_force[p] != [0.0; 2])
        .map(|p| particles.position[p][1] + particles.initial_half_width[p][1])
        .fold(f64::NEG_INFINITY, f64::max);
    if !top.is_finite() {
        return None;
    }
    let row = ((top - grid.origin[1]) / grid.cell_size).round();
    Some(row.clamp(0.0, (grid.nodes[1] - 1) as f64) as usize)
}

/// The (node, direction) pairs where no water crosses: impermeable faces (and the nodes of
/// the axis in axisymmetry), and every standing wall's line and the nodes beyond it.
pub fn impermeable_nodes(
    grid: &GridGeometry,
    faces: &BoundariesConfig,
    drainage: &DrainageConfig,
    walls: &[WallConfig],
    axisymmetric: bool,
) -> Vec<(u32, u8)> {
    let [nx, ny] = grid.nodes;
    let mut out = Vec::new();
    let [left, right, bottom, top] = drainage.resolve(faces);
    let mut face = |closed: bool, nodes: Vec<usize>, axis: u8| {
        if closed {
            out.extend(nodes.into_iter().map(|k| (k as u32, axis)));
        }
    };
    face(axisymmetric || left == Drainage::Impermeable, (0..ny).map(|j| grid.node_index(0, j)).collect(), 0);
    face(right == Drainage::Impermeable, (0..ny).map(|j| grid.node_index(nx - 1, j)).collect(), 0);
    face(bottom == Drainage::Impermeable, (0..nx).map(|i| grid.node_index(i, 0)).collect(), 1);
    face(top == Drainage::Impermeable, (0..nx).map(|i| grid.node_index(i, ny - 1)).collect(), 1);
    // A wall's nodes: its line and beyond, as the wall itself constrains them.
    for (index, w) in walls.iter().enumerate().filter(|(_, w)| w.removal_time.is_none()) {
        if let Some(wall) = crate::constraint::LineConstraint::wall(format!("wall_{index}"), grid, w) {
            let axis = wall.line.condition.axis;
            out.extend(wall.line.nodes.into_iter().map(|k| (k, axis)));
        }
    }
    out
}

/// One node and direction of the coupled update (module doc): the solid's velocity increment
/// Δv of
///
///   (M̄_w + Δt Q) Δw − Δt Q Δv = Δt F_w − Δt Q (w − v),   M_w Δw + M_s Δv = Δt F,
///
/// by Cramer's rule. `m_s`, `m_w`, `m_eq` are M_s, M_w, M̄_w; `impulse` = Δt F, `water_impulse`
/// = Δt F_w, `drag` = Δt Q, `relative` = w − v.
#[inline(always)]
pub fn solve_node(m_s: f64, m_w: f64, m_eq: f64, drag: f64, impulse: f64, water_impulse: f64, relative: f64) -> f64 {
    let water_rhs = water_impulse - drag * relative;
    let determinant = (m_eq + drag) * m_s + drag * m_w;
    ((m_eq + drag) * impulse - m_w * water_rhs) / determinant
}

/// The water row of the coupled update for a known v⁺: w⁺ = (M̄_w w + Δt F_w + Δt Q v⁺)/(M̄_w + Δt Q).
#[inline(always)]
pub fn water_velocity(m_eq: f64, drag: f64, w: f64, water_impulse: f64, v_new: f64) -> f64 {
    (m_eq * w + water_impulse + drag * v_new) / (m_eq + drag)
}

/// The mixture's momentum per unit change of the solid's velocity at a node: M_s + β M_w,
/// β = Δt Q/(M̄_w + Δt Q) the water row's response ∂w⁺/∂v⁺ ([`water_velocity`]). A constraint
/// that changes v⁺ by δv changes the mixture's momentum by this times δv: the impulse it
/// books. `drag` = Δt Q.
#[inline(always)]
pub fn reaction_mass(m_s: f64, m_w: f64, m_eq: f64, drag: f64) -> f64 {
    m_s + m_w * drag / (m_eq + drag)
}

/// The mixture's volumetric strain increment of the storage equation over one step,
/// e = (1 − n) Δε_s + n Δt ∇·w: Δε_s the solid's volumetric strain increment, `water_dilatation`
/// = Δt ∇·w (each with its hoop rate in axisymmetry).
#[inline(always)]
pub fn storage_strain(n: f64, solid_strain: f64, water_dilatation: f64) -> f64 {
    (1.0 - n) * solid_strain + n * water_dilatation
}

/// Pore pressure increment Δp = −(K_w/n) e of a storage strain e ([`storage_strain`]):
/// compression (e < 0) raises p.
#[inline(always)]
pub fn pressure_increment(k_w: f64, n: f64, storage_strain: f64) -> f64 {
    -k_w / n * storage_strain
}

/// The water volume that left a saturated particle over one step: its pore volume nV shrank
/// by ΔV (the grains are incompressible, so Δ(nV) = ΔV) and its water expanded by
/// −nV Δp/K_w = V e ([`pressure_increment`]), so −ΔV + V e of water went out. Summed over the
/// particles, only the flow across the bodies' surface remains (Gauss): the outflow through
/// the drained faces and free surfaces. `volume` is the particle's volume at the end of the
/// step, `storage_strain` its cell's e.
#[inline(always)]
pub fn outflow_increment(volume_before: f64, volume: f64, storage_strain: f64) -> f64 {
    volume * storage_strain - (volume - volume_before)
}

/// Porosity after the skeleton's volume went from `v_old` to `v_new` with incompressible
/// grains: the solid volume (1 − n) V is conserved.
#[inline(always)]
pub fn updated_porosity(n: f64, v_old: f64, v_new: f64) -> f64 {
    1.0 - (1.0 - n) * v_old / v_new
}

/// Advances a saturated run by `dt` (the dry step's passes, with the water added; see the
/// module doc and `solver::step`).
pub fn step<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, gravity: [f64; 2]) -> Result<(), Failure> {
    super::run_passes::<S>(
        state,
        dt,
        |state, cache| particle_to_grid::<F, S>(state, gravity, cache),
        |state| update_grid(state, dt),
        |state, cache| {
            super::grid_to_particle::grid_to_particle::<F, S>(state, dt, cache);
            water_to_particles::<F, S>(state, dt, cache);
        },
        |state, cache| {
            let water = state.water.as_mut().expect("a saturated run has its water");
            water.volume_before.copy_from_slice(&state.particles.volume);
            let result = super::particle_update::update_particles::<F, S>(state, dt, cache);
            let pressure = update_pore_pressure(state);
            super::first_failure(result.err(), pressure.err()).map_or(Ok(()), Err)
        },
    )
}

/// The nodal fields the saturated particle → grid adds to (shared by the tiles of one colour).
#[derive(Clone, Copy)]
struct Targets {
    mass: Shared<f64>,
    momentum: Shared<[f64; 2]>,
    force: Shared<[f64; 2]>,
    equation_mass: Shared<f64>,
    water_mass: Shared<f64>,
    water_momentum: Shared<[f64; 2]>,
    drag: Shared<f64>,
    water_force: Shared<[f64; 2]>,
}

/// Particle → grid of both phases, tile by tile and colour by colour as the dry pass
/// (`particle_to_grid`; race free, the same sums for any thread count).
fn particle_to_grid<F: Formulation, S: ShapeFunction>(state: &mut State, gravity: [f64; 2], cache: &mut [S::Cache]) {
    let grid = state.grid;
    let nodes_x = grid.nodes[0];
    let previous = state.scratch.grid_reached;
    let water = state.water.as_mut().expect("a saturated run has its water");
    zero_box(&mut state.fields.mass, nodes_x, previous);
    zero_box(&mut state.fields.momentum, nodes_x, previous);
    zero_box(&mut state.fields.force, nodes_x, previous);
    zero_box(&mut water.equation_mass, nodes_x, previous);
    zero_box(&mut water.mass, nodes_x, previous);
    zero_box(&mut water.momentum, nodes_x, previous);
    zero_box(&mut water.drag, nodes_x, previous);
    zero_box(&mut water.force, nodes_x, previous);
    let targets = Targets {
        mass: Shared::new(&mut state.fields.mass),
        momentum: Shared::new(&mut state.fields.momentum),
        force: Shared::new(&mut state.fields.force),
        equation_mass: Shared::new(&mut water.equation_mass),
        water_mass: Shared::new(&mut water.mass),
        water_momentum: Shared::new(&mut water.momentum),
        drag: Shared::new(&mut water.drag),
        water_force: Shared::new(&mut water.force),
    };
    let rho_w = water.density;
    let particles = &state.particles;
    let order = &mut state.tiles;
    let caches = Shared::new(cache);
    let isa = state.parameters.isa;
    let (mut reached, mut serial) = scatter_by_colour(order, |tile, overflow| {
        // SAFETY: as in the dry `particle_to_grid` (disjoint tiles and zones of one colour).
        let cache = unsafe { caches.slice(tile.range()) };
        // `overflow` a constant at each call site, as in the dry scatter.
        if overflow {
            isa.run(
                #[inline(always)]
                || unsafe { scatter::<F, S>(&grid, gravity, rho_w, particles, tile.range(), tile.zone(), cache, targets, true) },
            )
        } else {
            isa.run(
                #[inline(always)]
                || unsafe { scatter::<F, S>(&grid, gravity, rho_w, particles, tile.range(), tile.zone(), cache, targets, false) },
            )
        }
    });
    if water.loaded {
        let serial_start = std::time::Instant::now();
        reached = reached.union(super::surface_load::add_surface_loads(&grid, particles, state.load_factor, &mut state.fields.force));
        serial += serial_start.elapsed();
    }
    if water.face_pressures.iter().any(Option::is_some) {
        let serial_start = std::time::Instant::now();
        add_face_pressures::<F>(&grid, water, &mut state.fields.force);
        serial += serial_start.elapsed();
    }
    state.scratch.grid_region = reached.union(previous);
    state.scratch.grid_reached = reached;
    state.timings.serial += serial.as_secs_f64();
}

/// Adds the particles `range` of one tile to both phases' nodal fields (see the dry
/// `particle_to_grid::scatter` for `zone` and `overflow`).
/// SAFETY: no other thread writes to the nodes this call writes to.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
unsafe fn scatter<F: Formulation, S: ShapeFunction>(
    grid: &GridGeometry,
    gravity: [f64; 2],
    rho_w: f64,
    particles: &Particles,
    range: std::ops::Range<usize>,
    zone: NodeBox,
    cache: &mut [S::Cache],
    targets: Targets,
    overflow: bool,
) -> TileReach {
    let mut reach = TileReach::default();
    let grid = *grid;
    let first = range.start;
    for (i, c) in cache.iter_mut().enumerate() {
        let p = first + i;
        let x = particles.position[p];
        let domain = ParticleDomain {
            position: x,
            initial_half_width: particles.initial_half_width[p],
            deformation_gradient: &particles.deformation_gradient[p],
            corners: particles.corners.get(p),
        };
        if !overflow {
            S::prepare(&grid, &domain, F::AXISYMMETRIC, c);
        }
        let c = &*c;
        let node_box = S::node_box(&grid, c, &domain);
        let in_zone = inside(node_box, zone);
        if !overflow {
            reach.reached = reach.reached.union(node_box);
            reach.overflow |= !in_zone;
        }
        if in_zone == overflow {
            continue;
        }
        let m = particles.mass[p];
        let v = particles.velocity[p];
        let vol = particles.volume[p];
        let s = particles.stress[p];
        let n = particles.porosity[p];
        let pressure = particles.pore_pressure[p];
        let w = particles.water_velocity[p];
        // The water's masses and drag (zero for a dry particle, n = 0).
        let equation_mass = if n > 0.0 { rho_w * vol } else { 0.0 };
        let water_mass = n * equation_mass;
        let drag = if n > 0.0 { water_mass * STANDARD_GRAVITY / particles.hydraulic_conductivity[p] } else { 0.0 };
        // Total stress σ′ − p I on the mixture.
        let minus_vs = [-vol * (s[0] - pressure), -vol * (s[1] - pressure), -vol * s[3]];
        let hoop_factor = if F::AXISYMMETRIC { F::hoop_factor(x) } else { 0.0 };
        let hoop = vol * (s[2] - pressure) * hoop_factor;
        let body = [(m + water_mass) * gravity[0] - hoop, (m + water_mass) * gravity[1]];
        // Water: −∇p integrated by parts, V p ∇S, with V p S / R_p on r in axisymmetry.
        let vp = vol * pressure;
        let water_body = [equation_mass * gravity[0] + vp * hoop_factor, equation_mass * gravity[1]];
        let momentum = [m * v[0], m * v[1]];
        let water_momentum = [equation_mass * w[0], equation_mass * w[1]];
        S::visit_entries(&grid, c, &domain, F::AXISYMMETRIC, move |node, s, g| {
            *targets.mass.at(node) += s * m;
            let pm = targets.momentum.at(node);
            pm[0] += s * momentum[0];
            pm[1] += s * momentum[1];
            let f = targets.force.at(node);
            f[0] += minus_vs[0] * g[0] + minus_vs[2] * g[1] + s * body[0];
            f[1] += minus_vs[2] * g[0] + minus_vs[1] * g[1] + s * body[1];
            *targets.equation_mass.at(node) += s * equation_mass;
            *targets.water_mass.at(node) += s * water_mass;
            *targets.drag.at(node) += s * drag;
            let wm = targets.water_momentum.at(node);
            wm[0] += s * water_momentum[0];
            wm[1] += s * water_momentum[1];
            let fw = targets.water_force.at(node);
            fw[0] += vp * g[0] + s * water_body[0];
            fw[1] += vp * g[1] + s * water_body[1];
        });
    }
    reach
}

/// The boundary term of a face where the water outside stands at a prescribed pressure p̄:
/// −∮ N_k p̄ n dS (× r in axisymmetry, per radian) on both the water's force (the weak form of
/// −∇p, whose boundary term vanishes where p = 0) and the mixture's (the water outside pushes
/// on the total stress; on a supported face the constraint takes the normal part). Only the
/// face's segments whose two nodes carry water count: ∫ N_a r dr = h (2 r_a + r_b)/6 over a
/// segment [r_a, r_b] (h/2 in plane strain). Exact for linear shape functions, whose nodal
/// support ends at the body's edge. One thread, in node order; adds to nodes the particles
/// reached (nodes with water).
fn add_face_pressures<F: Formulation>(grid: &GridGeometry, water: &mut WaterState, force: &mut [[f64; 2]]) {
    let [nx, ny] = grid.nodes;
    let h = grid.cell_size;
    // Per face [left, right, bottom, top]: its outward normal, its node count, its t-th node.
    let normals = [[-1.0, 0.0], [1.0, 0.0], [0.0, -1.0], [0.0, 1.0]];
    let node = |face: usize, t: usize| match face {
        0 => grid.node_index(0, t),
        1 => grid.node_index(nx - 1, t),
        2 => grid.node_index(t, 0),
        _ => grid.node_index(t, ny - 1),
    };
    for (face, pressure) in water.face_pressures.into_iter().enumerate() {
        let Some(pressure) = pressure else { continue };
        let (normal, count) = (normals[face], if face < 2 { ny } else { nx });
        for t in 0..count - 1 {
            let (a, b) = (node(face, t), node(face, t + 1));
            if water.equation_mass[a] <= water.mass_threshold || water.equation_mass[b] <= water.mass_threshold {
                continue;
            }
            let radius = |k: usize| if F::AXISYMMETRIC { grid.node_position(k)[0] } else { 1.0 };
            let (ra, rb) = (radius(a), radius(b));
            for (k, length) in [(a, h * (2.0 * ra + rb) / 6.0), (b, h * (ra + 2.0 * rb) / 6.0)] {
                for d in 0..2 {
                    let push = -pressure * normal[d] * length;
                    water.force[k][d] += push;
                    force[k][d] += push;
                }
            }
        }
    }
}

/// Nodal velocities of both phases before and after the coupled momentum update, with the
/// solid's constraints, then the water row re-solved for the constrained v⁺ and the
/// impermeable boundaries.
fn update_grid(state: &mut State, dt: f64) {
    let params = state.parameters;
    let fields = &mut state.fields;
    let water = state.water.as_mut().expect("a saturated run has its water");
    let region = state.scratch.grid_region;
    let nx = state.grid.nodes[0];
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nx);
    let water_threshold = water.mass_threshold;
    fields
        .velocity
        .par_chunks_mut(nx)
        .zip(fields.velocity_new.par_chunks_mut(nx))
        .zip(water.velocity.par_chunks_mut(nx))
        .zip(fields.mass.par_chunks(nx))
        .zip(fields.momentum.par_chunks(nx))
        .zip(fields.force.par_chunks(nx))
        .zip(water.equation_mass.par_chunks(nx))
        .zip(water.mass.par_chunks(nx))
        .zip(water.momentum.par_chunks(nx))
        .zip(water.drag.par_chunks(nx))
        .zip(water.force.par_chunks(nx))
        .zip(water.reaction_mass.par_chunks_mut(nx))
        .zip(water.held.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .for_each(|((((((((((((v, v_new), w), m), p), f), m_eq), m_w), p_w), q), f_w), m_r), held)| {
            for k in columns.clone() {
                let (m, m_eq) = (m[k], m_eq[k]);
                // The water row is re-solved for the constrained v⁺ only at nodes with force
                // updates and water (below): elsewhere a constraint moves the solid alone.
                m_r[k] = if m > params.mass_threshold && m_eq > water_threshold { reaction_mass(m, m_w[k], m_eq, dt * q[k]) } else { m };
                if m > params.mass_threshold {
                    let v0 = [p[k][0] / m, p[k][1] / m];
                    let has_water = m_eq > water_threshold;
                    let w0 = if has_water { [p_w[k][0] / m_eq, p_w[k][1] / m_eq] } else { v0 };
                    let mut vn = [0.0; 2];
                    for d in 0..2 {
                        // Cundall local damping of the mixture's unbalanced force, except where
                        // a face or wall holds the velocity: there the force is balanced by the
                        // support (which books it as the reaction), and v⁺ is zero whatever it is.
                        let force = if held[k][d] { f[k][d] } else { damped(f[k][d], params.damping, v0[d]) };
                        vn[d] = if has_water {
                            v0[d] + solve_node(m, m_w[k], m_eq, dt * q[k], dt * force, dt * f_w[k][d], w0[d] - v0[d])
                        } else {
                            v0[d] + dt * force / m
                        };
                    }
                    v[k] = v0;
                    v_new[k] = vn;
                    w[k] = w0;
                } else if m > 0.0 {
                    // A light node: no force update (see the dry `update_node`).
                    v[k] = [p[k][0] / m, p[k][1] / m];
                    v_new[k] = v[k];
                    w[k] = if m_eq > water_threshold { [p_w[k][0] / m_eq, p_w[k][1] / m_eq] } else { v[k] };
                } else {
                    v[k] = [0.0; 2];
                    v_new[k] = [0.0; 2];
                    w[k] = [0.0; 2];
                }
            }
        });
    if let Some(row) = water.plate_row {
        move_plate(fields, water, row, nx, dt, &params);
    }
    constrain_velocities(state, dt);
    let fields = &state.fields;
    let water = state.water.as_mut().expect("a saturated run has its water");
    // w⁺ from the water row with the constrained v⁺ (where no constraint acted, the value of
    // the coupled solve).
    let light = params.mass_threshold;
    water
        .velocity_new
        .par_chunks_mut(nx)
        .zip(water.velocity.par_chunks(nx))
        .zip(fields.velocity_new.par_chunks(nx))
        .zip(fields.mass.par_chunks(nx))
        .zip(water.equation_mass.par_chunks(nx))
        .zip(water.drag.par_chunks(nx))
        .zip(water.force.par_chunks(nx))
        .skip(first_row)
        .take(rows)
        .for_each(|((((((w_new, w), v_new), m), m_eq), q), f_w)| {
            for k in columns.clone() {
                w_new[k] = if m[k] > light && m_eq[k] > water_threshold {
                    let water = |d: usize| water_velocity(m_eq[k], dt * q[k], w[k][d], dt * f_w[k][d], v_new[k][d]);
                    [water(0), water(1)]
                } else {
                    w[k]
                };
            }
        });
    // Impermeable: the water's normal velocity is held to the solid's; the face or wall that
    // holds the solid there takes the water's impulse M_w (w⁺ − v⁺) too (module doc,
    // "Reactions"). One thread, in list order: deterministic.
    for &ImpermeableNode { node, axis, owner } in &water.impermeable {
        let (node, d) = (node as usize, axis as usize);
        let held = fields.velocity_new[node][d];
        if let Some(owner) = owner {
            if fields.mass[node] > light && water.equation_mass[node] > water_threshold {
                let mut impulse = [0.0; 2];
                impulse[d] = water.mass[node] * (water.velocity_new[node][d] - held);
                state.constraints.list[owner as usize].book_impulse(impulse);
            }
        }
        water.velocity_new[node][d] = held;
        water.velocity[node][d] = fields.velocity[node][d];
    }
    water.drag_work += drag_work(water, &fields.velocity_new, dt, first_row..first_row + rows, columns, nx);
}

/// The loading plate: the nodes of grid row `row` take one vertical velocity V⁺. The plate is
/// rigid, massless and impermeable, so on its nodes the water moves with the solid (w⁺ = v⁺ = V⁺
/// vertically) and the vertical momentum balance of the row, with the plate's reactions summing
/// to zero, gives Σ (M_s + M_w) V⁺ = Σ (M_s v + M_w w) + Δt Σ F over the row's nodes (the surface
/// load is in F). Frictionless: the horizontal velocities are left as they are. One thread, in
/// node order.
fn move_plate(
    fields: &mut crate::grid::GridFields,
    water: &WaterState,
    row: usize,
    nx: usize,
    dt: f64,
    params: &super::StepParameters,
) {
    let nodes = row * nx..(row + 1) * nx;
    let (mut inertia, mut momentum, mut force) = (0.0, 0.0, 0.0);
    for k in nodes.clone() {
        let m = fields.mass[k];
        if m <= params.mass_threshold {
            continue;
        }
        let m_w = if water.equation_mass[k] > water.mass_threshold { water.mass[k] } else { 0.0 };
        inertia += m + m_w;
        momentum += m * fields.velocity[k][1] + m_w * water.velocity[k][1];
        force += fields.force[k][1];
    }
    if inertia > 0.0 {
        // The damping acts on the plate's unbalanced force as a whole: its nodes' forces need
        // not vanish one by one (the plate redistributes them), and damping each would push the
        // plate up by α Σ |F_k|.
        let plate = (momentum + dt * damped(force, params.damping, momentum / inertia)) / inertia;
        for k in nodes.filter(|&k| fields.mass[k] > 0.0) {
            fields.velocity_new[k][1] = plate;
        }
    }
}

/// The work of the implicit drag over one step over the nodes of `rows` × `columns` (one
/// thread, row by row: deterministic). The water row is the water's momentum balance per unit
/// volume of water (its mass M̄_w = Σ S ρ_w V), so its drag Q (w − v) is the force on the water
/// of a unit volume of mixture divided by n; the force itself is n Q (w − v), with the nodal
/// porosity n = M_w / M̄_w, and its work Σ Δt n Q |w⁺ − v⁺|² (per unit volume of mixture,
/// (γ_w/k) |q|² with the Darcy flux q = n (w − v)).
fn drag_work(
    water: &WaterState,
    v_new: &[[f64; 2]],
    dt: f64,
    rows: std::ops::Range<usize>,
    columns: std::ops::RangeInclusive<usize>,
    nx: usize,
) -> f64 {
    let mut work = 0.0;
    for j in rows {
        for k in columns.clone().map(|i| j * nx + i) {
            if water.equation_mass[k] <= water.mass_threshold {
                continue;
            }
            let porosity = water.mass[k] / water.equation_mass[k];
            let (w, v) = (water.velocity_new[k], v_new[k]);
            let r = [w[0] - v[0], w[1] - v[1]];
            work += dt * porosity * water.drag[k] * (r[0] * r[0] + r[1] * r[1]);
        }
    }
    work
}


/// Particles per parallel work item of the water passes.
const WATER_CHUNK: usize = 512;

/// The particles' water velocities (the FLIP/PIC blend of the solid's) and Δt ∇·w (hoop rate
/// included) from the nodal w⁺, at the start-of-step stencils. Each particle writes only its
/// own entries.
fn water_to_particles<F: Formulation, S: ShapeFunction>(state: &mut State, dt: f64, cache: &[S::Cache]) {
    let grid = state.grid;
    let flip = state.parameters.flip_fraction;
    let isa = state.parameters.isa;
    let water = state.water.as_mut().expect("a saturated run has its water");
    let (w_new, w_old) = (&water.velocity_new, &water.velocity);
    let particles = &mut state.particles;
    let (position, half, f, corners, porosity) = (
        &particles.position,
        &particles.initial_half_width,
        &particles.deformation_gradient,
        &particles.corners,
        &particles.porosity,
    );
    particles
        .water_velocity
        .par_chunks_mut(WATER_CHUNK)
        .zip(water.water_dilatation.par_chunks_mut(WATER_CHUNK))
        .enumerate()
        .for_each(|(chunk, (velocity, dilatation))| {
            // The chunk's loop compiled for the instruction set chosen (`solver::isa`).
            isa.run(
                #[inline(always)]
                || {
                    for (i, (w_p, div)) in velocity.iter_mut().zip(dilatation.iter_mut()).enumerate() {
                        let p = chunk * WATER_CHUNK + i;
                        if porosity[p] <= 0.0 {
                            *div = 0.0;
                            continue;
                        }
                        let domain = ParticleDomain {
                            position: position[p],
                            initial_half_width: half[p],
                            deformation_gradient: &f[p],
                            corners: corners.get(p),
                        };
                        let mut w_grid = [0.0; 2];
                        let mut dw = [0.0; 2];
                        let mut divergence = 0.0;
                        let mut radial = 0.0;
                        S::visit_entries(&grid, &cache[p], &domain, F::AXISYMMETRIC, |node, s, g| {
                            let (wn, wo) = (w_new[node], w_old[node]);
                            w_grid[0] += s * wn[0];
                            w_grid[1] += s * wn[1];
                            dw[0] += s * (wn[0] - wo[0]);
                            dw[1] += s * (wn[1] - wo[1]);
                            divergence += wn[0] * g[0] + wn[1] * g[1];
                            radial += s * wn[0];
                        });
                        if F::AXISYMMETRIC {
                            divergence += radial * F::hoop_factor(domain.position);
                        }
                        *w_p = [
                            flip * (w_p[0] + dw[0]) + (1.0 - flip) * w_grid[0],
                            flip * (w_p[1] + dw[1]) + (1.0 - flip) * w_grid[1],
                        ];
                        *div = dt * divergence;
                    }
                },
            )
        });
}

/// The storage equation at the particles (after the solid's update): the increment of each
/// saturated particle, averaged over the saturated particles of its background cell, then the
/// pressure and the porosity. Returns the lowest particle whose pressure is not finite.
fn update_pore_pressure(state: &mut State) -> Result<(), Failure> {
    let grid = state.grid;
    let water = state.water.as_mut().expect("a saturated run has its water");
    let particles = &mut state.particles;
    let k_w = water.bulk_modulus;
    // Storage rate e = (1 − n) Δε_s + n Δt ∇·w per particle (in `water_dilatation`), then its
    // V-weighted mean per cell (one thread, in array order: deterministic).
    let serial_start = std::time::Instant::now();
    let isa = state.parameters.isa;
    water.cell_volume.fill(0.0);
    water.cell_storage.fill(0.0);
    // Both loops compiled for the instruction set chosen (`solver::isa`: the cell index's floor
    // is then one instruction, not a library call).
    let outflow = isa.run(
        #[inline(always)]
        || {
            for p in 0..particles.len() {
                let n = particles.porosity[p];
                if n <= 0.0 {
                    continue;
                }
                let solid_strain = (particles.volume[p] / water.volume_before[p]).ln();
                let e = storage_strain(n, solid_strain, water.water_dilatation[p]);
                water.water_dilatation[p] = e;
                let cell = grid.cell_index(particles.position[p]);
                water.cell_volume[cell] += particles.volume[p];
                water.cell_storage[cell] += particles.volume[p] * e;
            }
            let mut outflow = 0.0;
            for p in 0..particles.len() {
                let n = particles.porosity[p];
                if n <= 0.0 {
                    continue;
                }
                let cell = grid.cell_index(particles.position[p]);
                let e = water.cell_storage[cell] / water.cell_volume[cell];
                particles.pore_pressure[p] += pressure_increment(k_w, n, e);
                particles.porosity[p] = updated_porosity(n, water.volume_before[p], particles.volume[p]);
                outflow += outflow_increment(water.volume_before[p], particles.volume[p], e);
            }
            outflow
        },
    );
    water.outflow += outflow;
    state.timings.serial += serial_start.elapsed().as_secs_f64();
    match particles.pore_pressure.iter().position(|p| !p.is_finite()) {
        Some(p) => Err(Failure::NotFinite { particle: p }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coupled_node_update_conserves_the_mixture_momentum_and_locks_at_low_conductivity() {
        // Masses and impulses of no special value.
        let (m_s, n, rho_w, v) = (3.0, 0.4, 1000.0, 2.0e-3);
        let m_eq = rho_w * v;
        let m_w = n * m_eq;
        let (impulse, water_impulse, relative) = (0.7, -0.3, 0.05);
        for k in [1e-2, 1e-5, 1e-9] {
            let drag = 1e-4 * m_w * STANDARD_GRAVITY / k;
            let dv = solve_node(m_s, m_w, m_eq, drag, impulse, water_impulse, relative);
            let w0 = 0.1 + relative;
            let dw = water_velocity(m_eq, drag, w0, water_impulse, 0.1 + dv) - w0;
            // Mixture: M_s Δv + M_w Δw = Δt F.
            assert!((m_s * dv + m_w * dw - impulse).abs() < 1e-12 * impulse.abs().max(1.0), "k = {k}");
            // Water: M̄_w Δw = Δt F_w − Δt Q (w⁺ − v⁺).
            let r_new = relative + dw - dv;
            assert!((m_eq * dw - (water_impulse - drag * r_new)).abs() < 1e-9 * (drag * r_new.abs()).max(1.0), "k = {k}");
            if k < 1e-6 {
                // Locked: the relative velocity is gone (to O(M/(Δt Q)) = O(1e-5) of it here),
                // the mixture moves as one mass.
                assert!(r_new.abs() < 1e-4 * relative, "k = {k}: {r_new}");
                assert!((dv - (impulse + m_w * relative) / (m_s + m_w)).abs() < 1e-4 * dv.abs(), "k = {k}: {dv}");
            }
        }
        // Without drag the phases are independent.
        let dv = solve_node(m_s, m_w, m_eq, 0.0, impulse, water_impulse, relative);
        let dw = water_velocity(m_eq, 0.0, 0.0, water_impulse, dv) - 0.0;
        assert!((dw - water_impulse / m_eq).abs() < 1e-15);
        assert!((dv - (impulse - m_w * water_impulse / m_eq) / m_s).abs() < 1e-12);
    }

    #[test]
    fn reaction_mass_is_the_mixtures_response_to_the_solids_velocity() {
        // M_s = 3, M_w = 0.8, M̄_w = 2: no drag, the water stays (β = 0); Δt Q = 6, β = 6/8.
        assert_eq!(reaction_mass(3.0, 0.8, 2.0, 0.0), 3.0);
        assert!((reaction_mass(3.0, 0.8, 2.0, 6.0) - (3.0 + 0.8 * 0.75)).abs() < 1e-15);
        // It is M_s + M_w ∂w⁺/∂v⁺ of the water row.
        let (m_eq, drag, w, impulse) = (2.0, 6.0, 0.1, 0.3);
        let slope = (water_velocity(m_eq, drag, w, impulse, 1.5) - water_velocity(m_eq, drag, w, impulse, 0.5)) / 1.0;
        assert!((reaction_mass(3.0, 0.8, m_eq, drag) - (3.0 + 0.8 * slope)).abs() < 1e-14);
        // Locked (Δt Q ≫ M̄_w): the whole mixture.
        assert!((reaction_mass(3.0, 0.8, 2.0, 1e12) - 3.8).abs() < 1e-11);
    }

    #[test]
    fn storage_and_porosity_follow_the_volume() {
        let (k_w, n) = (2.2e9, 0.3);
        let dp = |solid: f64, water: f64| pressure_increment(k_w, n, storage_strain(n, solid, water));
        // Compression of the skeleton alone raises p by (K_w/n)(1 − n)|Δε|.
        assert!((dp(-1e-6, 0.0) - k_w / n * (1.0 - n) * 1e-6).abs() < 1e-6);
        // Water flowing out (∇·w > 0) lowers p by K_w Δt ∇·w.
        assert!((dp(0.0, 2e-6) + k_w * 2e-6).abs() < 1e-6);
        // Undrained (w = v): Δp = −K_w/n Δε.
        assert!((dp(-1e-6, -1e-6) - k_w / n * 1e-6).abs() < 1e-6);
        // The solid volume (1 − n)V is conserved.
        let n1 = updated_porosity(n, 1.0, 0.9);
        assert!(((1.0 - n1) * 0.9 - (1.0 - n) * 1.0).abs() < 1e-15);
        assert!((updated_porosity(n, 2.0, 2.0) - n).abs() < 1e-15);
    }

    #[test]
    fn outflow_is_the_pore_volume_lost_plus_the_water_expansion() {
        // The pore volume shrank by 0.1 with the water's pressure unchanged (e = 0): 0.1 left.
        assert!((outflow_increment(2.0, 1.9, 0.0) - 0.1).abs() < 1e-15);
        // No volume change, the pressure fell (e > 0): the water's expansion e V left.
        assert!((outflow_increment(1.0, 1.0, 3e-6) - 3e-6).abs() < 1e-18);
        // Both: the new volume weights the storage strain.
        assert!((outflow_increment(1.0, 0.5, 1e-3) - (0.5e-3 + 0.5)).abs() < 1e-15);
    }

    /// A 3 × 2 node water state with the given nodal masses, drags and velocities.
    fn water_on(nodes: usize, m_eq: f64, n: f64, q: f64, w: [f64; 2]) -> WaterState {
        WaterState {
            mass_threshold: 1e-9,
            equation_mass: vec![m_eq; nodes],
            mass: vec![n * m_eq; nodes],
            drag: vec![q; nodes],
            velocity: vec![w; nodes],
            velocity_new: vec![w; nodes],
            ..Default::default()
        }
    }

    #[test]
    fn drag_work_is_n_q_relative_speed_squared_over_the_region() {
        let (nx, ny) = (3, 2);
        let mut water = water_on(nx * ny, 2.0, 0.25, 8.0, [0.3, -0.4]);
        let v = vec![[0.0; 2]; nx * ny];
        // |w − v|² = 0.25, n Q = 2 per node, Δt = 0.5: 0.25 per node.
        let all = drag_work(&water, &v, 0.5, 0..ny, 0..=nx - 1, nx);
        assert!((all - 6.0 * 0.25).abs() < 1e-12, "{all}");
        // Only the region's nodes, and none without water.
        let one_row = drag_work(&water, &v, 0.5, 1..2, 1..=2, nx);
        assert!((one_row - 2.0 * 0.25).abs() < 1e-12, "{one_row}");
        water.equation_mass[nx + 1] = 0.0;
        assert!((drag_work(&water, &v, 0.5, 1..2, 1..=2, nx) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn plate_moves_its_row_together_under_the_total_force() {
        let (nx, ny) = (3, 2);
        let params = crate::solver::StepParameters {
            flip_fraction: 1.0,
            xpic_order: 1,
            damping: 0.0,
            scheme: crate::config::UpdateScheme::Musl,
            mass_threshold: 1e-9,
            volumetric_averaging: crate::config::VolumetricAveraging::None,
            axisymmetric: false,
            isa: crate::solver::Isa::Baseline,
        };
        let mut fields = crate::grid::GridFields::new(nx * ny);
        let water = water_on(nx * ny, 1.0, 0.5, 3.0, [0.0, -0.1]);
        for (i, (m, f)) in [(1.0, -4.0), (2.0, 1.0), (0.0, 7.0)].into_iter().enumerate() {
            let k = nx + i;
            fields.mass[k] = m;
            fields.velocity[k] = [0.2 * i as f64, -0.1];
            fields.velocity_new[k] = [0.5, 9.0];
            fields.force[k] = [1.0, f];
        }
        let dt = 0.1;
        move_plate(&mut fields, &water, 1, nx, dt, &params);
        // Σ (M_s + M_w) V⁺ = Σ (M_s v + M_w w) + Δt Σ F over the nodes with mass (the third has none).
        let expected = ((1.0 + 2.0) * -0.1 + 2.0 * 0.5 * -0.1 + dt * (-4.0 + 1.0)) / (1.0 + 2.0 + 2.0 * 0.5);
        for k in [nx, nx + 1] {
            assert!((fields.velocity_new[k][1] - expected).abs() < 1e-15, "{:?}", fields.velocity_new[k]);
            assert_eq!(fields.velocity_new[k][0], 0.5, "frictionless: the horizontal velocity is left");
        }
        assert_eq!(fields.velocity_new[nx + 2], [0.5, 9.0], "a node without mass is left");
        assert_eq!(fields.velocity_new[0], [0.0; 2], "the other rows are left");
        // Damping acts on the total: with the plate moving down and Σ F = −3 N, the force becomes
        // −3 + α·3 (against the motion), not Σ (F_k + α |F_k|).
        let damped_params = crate::solver::StepParameters { damping: 0.5, ..params };
        move_plate(&mut fields, &water, 1, nx, dt, &damped_params);
        let damped_expected = ((1.0 + 2.0) * -0.1 + 2.0 * 0.5 * -0.1 + dt * (-3.0 + 1.5)) / 4.0;
        assert!((fields.velocity_new[nx][1] - damped_expected).abs() < 1e-15, "{:?}", fields.velocity_new[nx]);
    }

    #[test]
    fn wave_speed_is_the_undrained_one_or_the_faster_phase() {
        // E_c = 1e7, ρ_s = 2650, n = 0.4, K_w = 2.2e9, ρ_w = 1000: undrained
        // √((1e7 + 5.5e9)/(1590 + 400)) = 1663.9 m/s, above the water's 1483.2 m/s.
        let c = saturated_wave_speed(1e7, 2650.0, 0.4, 2.2e9, 1000.0);
        assert!((c - ((1e7 + 2.2e9 / 0.4) / 1990.0_f64).sqrt()).abs() < 1e-9);
        // Soft water: the skeleton alone is fastest.
        let c = saturated_wave_speed(1e9, 2650.0, 0.4, 1e5, 1000.0);
        assert!((c - (1e9 / (0.6 * 2650.0_f64)).sqrt()).abs() < 1e-9);
        // Light water: the water alone.
        let c = saturated_wave_speed(1e5, 2650.0, 0.4, 2.2e9, 10.0);
        assert!((c - (2.2e9 / 10.0_f64).sqrt()).abs() < 1e-6);
    }
}
