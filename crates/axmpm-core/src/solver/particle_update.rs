//! Particle update: velocity gradient L = Σ_i v_i ⊗ ∇S_ip (+ the hoop rate
//! L_θθ = Σ_i v_r,i S_ip / R_p), deformation gradient F ← (I + Δt L) F, volume, stress by the
//! material, then position x_p ← x_p + Δx_p and the CPDI corners.

use rayon::prelude::*;

use super::{first_failure, Failure, Isa, Scratch, State};
use crate::config::{UpdateScheme, VolumetricAveraging};
use crate::formulation::Formulation;
use crate::grid::{GridBounds, GridGeometry};
use crate::interpolation::{ParticleDomain, ShapeFunction};
use crate::material::{CellLaplacian, Kinematics, Material};
use crate::particles::{DeformationGradient, Particles, Stress};

/// Particles per parallel work item of the update pass.
const UPDATE_CHUNK: usize = 512;

/// Particles per batch of the update pass's stress updates (their kinematics on the stack:
/// 32 × 112 B).
const STRESS_BATCH: usize = 32;

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
    isa: Isa,
    /// The cell pass a model asked for ([`Material::cell_field`]), computed for this step.
    cell_laplacian: Option<&'a CellLaplacian>,
}

/// The read-only per-particle inputs of one chunk of the update pass, as slices of the chunk's
/// length (indexed by the particle's place in its chunk without bounds checks).
struct ChunkInputs<'a> {
    initial_volume: &'a [f64],
    velocity: &'a [[f64; 2]],
    displacement: &'a [[f64; 2]],
}

/// The mutable state of one particle in the update pass.
struct ParticleUpdate<'a> {
    f: &'a mut [f64; 5],
    volume: &'a mut f64,
    position: &'a mut [f64; 2],
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
    let strain_velocity = inputs.strain_velocity;
    debug_assert_eq!(strain_velocity.len(), inputs.grid.num_nodes());
    S::visit_entries(&inputs.grid, cache, domain, F::AXISYMMETRIC, |node, w, dw| {
        debug_assert!(node < strain_velocity.len());
        // SAFETY: a stencil visits only nodes of the grid (`ShapeFunction::visit_entries`),
        // and the nodal velocities have one entry per node.
        let v = unsafe { *strain_velocity.get_unchecked(node) };
        l[0] += v[0] * dw[0];
        l[1] += v[0] * dw[1];
        l[2] += v[1] * dw[0];
        l[3] += v[1] * dw[1];
        vr += v[0] * w;
    });
    // Plane strain has no hoop rate: L33 = +0 without the sum (which the compiler then drops).
    l[4] = if F::AXISYMMETRIC { vr * F::hoop_factor(domain.position) } else { 0.0 };
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

/// Deformation gradient, CPDI corners, position and volume of one particle from its velocity
/// gradient `l` (and its stencil cache of the step, which the corner advection reuses);
/// returns what the material needs for its stress update. `i` is the particle's index in
/// `chunk` (the per-particle inputs of its chunk).
#[inline(always)]
fn move_particle<F: Formulation, S: ShapeFunction>(
    inputs: &UpdateInputs,
    chunk: &ChunkInputs,
    i: usize,
    u: ParticleUpdate,
    cache: &S::Cache,
    l: [f64; 5],
) -> Kinematics {
    let grid = &inputs.grid;
    // The cell field at the particle's start-of-step cell, when a model reads one.
    let cell_field = inputs.cell_laplacian.map_or([0.0; 2], |cells| cells.at(grid.cell_index(*u.position)));
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
    let d = chunk.displacement[i];
    x[0] += d[0];
    x[1] += d[1];
    *u.volume = match u.corners {
        Some(corners) => {
            S::advect_corners(grid, cache, inputs.advect_velocity, dt, corners, F::AXISYMMETRIC);
            S::domain_area(corners).unwrap_or(0.0) * F::volume_factor(*x)
        }
        None => chunk.initial_volume[i] * jacobian,
    };
    Kinematics { velocity_gradient: l, deformation_gradient: *f, jacobian, cell_field, dt }
}

/// Whether particle `p` (index `i` in `chunk`) is valid after its update: position, stress and
/// velocity finite, inside the grid (off the axis in axisymmetry), J > 0.
#[inline(always)]
fn check_particle<F: Formulation>(
    bounds: &GridBounds,
    chunk: &ChunkInputs,
    p: usize,
    i: usize,
    x: [f64; 2],
    s: &Stress,
    jacobian: f64,
) -> Option<Failure> {
    // All finite at once: x · 0 is ±0 for a finite x and NaN for ±∞ or NaN, so the sum of
    // the products is zero exactly when every value is finite (one test instead of eight),
    // whatever the order of the additions: summed as two groups of four, pairwise, so that
    // each group is one vector multiply and the sum a short tree.
    let v = chunk.velocity[i];
    let a = [x[0], x[1], s[0], s[1]].map(|c| c * 0.0);
    let b = [s[2], s[3], v[0], v[1]].map(|c| c * 0.0);
    let pairs = [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]];
    let finite = (pairs[0] + pairs[2]) + (pairs[1] + pairs[3]) == 0.0;
    if !finite {
        Some(Failure::NotFinite { particle: p })
    } else if !(bounds.contains(x) & (!F::AXISYMMETRIC | (x[0] > 0.0))) {
        Some(Failure::LeftGrid { particle: p, position: x, velocity: v })
    } else if !(jacobian > 0.0) {
        Some(Failure::InvertedJacobian { particle: p, jacobian })
    } else {
        None
    }
}

/// Whether [`check_particle`] finds every particle `batch` of the chunk valid (`kinematics`
/// holds the batch's kinematics from its first entry on): the same tests, combined with `&`
/// into one flag, so that the loop has no branch and the compiler vectorises it.
#[inline(always)]
fn batch_is_valid<F: Formulation>(
    bounds: &GridBounds,
    chunk: &ChunkInputs,
    batch: std::ops::Range<usize>,
    position: &[[f64; 2]],
    stress: &[Stress],
    kinematics: &[Kinematics],
) -> bool {
    let (position, stress, velocity) = (&position[batch.clone()], &stress[batch.clone()], &chunk.velocity[batch]);
    let mut valid = true;
    for (((x, s), v), kin) in position.iter().zip(stress).zip(velocity).zip(kinematics) {
        // As `check_particle`: the products with 0 sum to zero exactly when all are finite.
        let a = [x[0], x[1], s[0], s[1]].map(|c| c * 0.0);
        let b = [s[2], s[3], v[0], v[1]].map(|c| c * 0.0);
        let pairs = [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]];
        let finite = (pairs[0] + pairs[2]) + (pairs[1] + pairs[3]) == 0.0;
        valid &= finite & bounds.contains(*x) & (!F::AXISYMMETRIC | (x[0] > 0.0)) & (kin.jacobian > 0.0);
    }
    valid
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
pub(super) fn update_particles<F: Formulation, S: ShapeFunction>(
    state: &mut State,
    dt: f64,
    cache: &[S::Cache],
) -> Result<(), Failure> {
    let averaging = state.parameters.volumetric_averaging == VolumetricAveraging::Cell;
    let Scratch {
        displacement,
        velocity_gradient: gradients,
        cell_volume,
        cell_dilatation,
        cell_laplacian,
        ..
    } = &mut state.scratch;
    let particles = &mut state.particles;
    if let Some(cells) = cell_laplacian.as_mut() {
        let serial_start = std::time::Instant::now();
        cells.compute::<F>(&state.grid, particles);
        state.timings.serial += serial_start.elapsed().as_secs_f64();
    }
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
        isa: state.parameters.isa,
        cell_laplacian: cell_laplacian.as_ref(),
    };
    let source = if averaging {
        let serial = &mut state.timings.serial;
        cell_averaged_gradients::<F, S>(&inputs, particles, cache, gradients, cell_volume, cell_dilatation, serial);
        GradientSource::CellAveraged { gradients, cell_mean_dilatation: cell_dilatation }
    } else {
        GradientSource::Stencil
    };
    // One chunk of particles per work item, compiled for the instruction set in use.
    // The batch's kinematics live in a buffer made once per rayon job (`map_init`), not once
    // per chunk: every batch writes its entries before reading them.
    let batch_buffer = || [Kinematics::ZERO; STRESS_BATCH];
    let update_chunk = |kinematics: &mut [Kinematics; STRESS_BATCH], k: usize, chunk: ChunkArrays<S>| {
        inputs.isa.run(
            #[inline(always)]
            || update_chunk::<F, S>(&inputs, source, stride, k, chunk, kinematics),
        )
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
            .map_init(batch_buffer, |kinematics, (k, ((((((f, stress), volume), position), state), cache), corners))| {
                update_chunk(kinematics, k, ChunkArrays { f, stress, volume, position, state, cache, corners: Some(corners) })
            })
            .reduce(|| None, first_failure)
    } else {
        chunks
            .enumerate()
            .map_init(batch_buffer, |kinematics, (k, (((((f, stress), volume), position), state), cache))| {
                update_chunk(kinematics, k, ChunkArrays { f, stress, volume, position, state, cache, corners: None })
            })
            .reduce(|| None, first_failure)
    };
    failure.map_or(Ok(()), Err)
}

/// The arrays of one chunk of particles in the update pass (each of the chunk's length; the
/// state holds `stride` slots per particle).
struct ChunkArrays<'a, S: ShapeFunction> {
    f: &'a mut [DeformationGradient],
    stress: &'a mut [Stress],
    volume: &'a mut [f64],
    position: &'a mut [[f64; 2]],
    state: &'a mut [f64],
    cache: &'a [S::Cache],
    corners: Option<&'a mut [[[f64; 2]; 4]]>,
}

/// Updates the particles of chunk `k` (particles from `k · UPDATE_CHUNK` on), its arrays as
/// slices of one length: a plain loop per chunk instead of rayon's per-item plumbing (zipped
/// producers, a reduction per particle). Returns the chunk's lowest failing particle.
#[inline(always)]
fn update_chunk<F: Formulation, S: ShapeFunction>(
    inputs: &UpdateInputs,
    source: GradientSource,
    stride: usize,
    k: usize,
    chunk: ChunkArrays<S>,
    kinematics: &mut [Kinematics; STRESS_BATCH],
) -> Option<Failure> {
    // A local copy, kept in registers across the particle's stores (see P2G).
    let inputs = *inputs;
    let ChunkArrays { f, stress, volume, position, state, cache, mut corners } = chunk;
    let first = k * UPDATE_CHUNK;
    let n = f.len();
    let (stress, volume, position, cache) = (&mut stress[..n], &mut volume[..n], &mut position[..n], &cache[..n]);
    let initial_half_width = &inputs.initial_half_width[first..first + n];
    let material_ids = &inputs.material_ids[first..first + n];
    let chunk_inputs = ChunkInputs {
        initial_volume: &inputs.initial_volume[first..first + n],
        velocity: &inputs.velocity[first..first + n],
        displacement: &inputs.displacement[first..first + n],
    };
    let bounds = inputs.grid.bounds();
    let mut failure = None;
    // In batches: the kinematics of a batch, then the stress update of each run of particles
    // of one material in one call (the model's parameters stay in registers, and there is one
    // dynamic dispatch per run instead of per particle), then the checks.
    for start in (0..n).step_by(STRESS_BATCH) {
        let end = (start + STRESS_BATCH).min(n);
        for (i, kin) in (start..end).zip(kinematics.iter_mut()) {
            let p = first + i;
            let corners = corners.as_mut().map(|c| &mut c[i]);
            let domain = ParticleDomain {
                position: position[i],
                initial_half_width: initial_half_width[i],
                deformation_gradient: &f[i],
                corners: corners.as_deref(),
            };
            let l = match source {
                GradientSource::Stencil => velocity_gradient::<F, S>(&inputs, &domain, &cache[i]),
                GradientSource::CellAveraged { gradients, cell_mean_dilatation } => with_mean_dilatation::<F>(
                    gradients[p],
                    cell_mean_dilatation[inputs.grid.cell_index(domain.position)],
                ),
            };
            let u = ParticleUpdate { f: &mut f[i], volume: &mut volume[i], position: &mut position[i], corners };
            *kin = move_particle::<F, S>(&inputs, &chunk_inputs, i, u, &cache[i], l);
        }
        let mut run_start = start;
        while run_start < end {
            let id = material_ids[run_start];
            let run_end = (run_start + 1..end).find(|&j| material_ids[j] != id).unwrap_or(end);
            let material = &inputs.materials[id as usize];
            let state_length = inputs.state_lengths[id as usize];
            let stress_run = &mut stress[run_start..run_end];
            let state_run = &mut state[run_start * stride..run_end * stride];
            let kinematics_run = &kinematics[run_start - start..run_end - start];
            match inputs.isa {
                // SAFETY: `Avx2` is only chosen on a CPU that has it (`Isa::detect`).
                #[cfg(target_arch = "x86_64")]
                Isa::Avx2 => unsafe {
                    material.update_stress_batch_avx2(stress_run, state_run, stride, state_length, kinematics_run)
                },
                _ => material.update_stress_batch(stress_run, state_run, stride, state_length, kinematics_run),
            }
            run_start = run_end;
        }
        // The lowest failing index of the chunk (chunks are then reduced the same way): the
        // whole batch in one branch-free pass, particle by particle only if it has a failure.
        let batch = start..end;
        if failure.is_none() && !batch_is_valid::<F>(&bounds, &chunk_inputs, batch.clone(), position, stress, &kinematics[..]) {
            for (i, kin) in batch.zip(kinematics.iter()) {
                let result = check_particle::<F>(&bounds, &chunk_inputs, first + i, i, position[i], &stress[i], kin.jacobian);
                if result.is_some() {
                    failure = result;
                    break;
                }
            }
        }
    }
    failure
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
    serial_seconds: &mut f64,
) {
    gradients.par_chunks_mut(UPDATE_CHUNK).zip(cache.par_chunks(UPDATE_CHUNK)).enumerate().for_each(|(k, (ls, cs))| {
        inputs.isa.run(
            #[inline(always)]
            || {
                for (i, (l, c)) in ls.iter_mut().zip(cs).enumerate() {
                    let domain = ParticleDomain::of(particles, k * UPDATE_CHUNK + i);
                    *l = velocity_gradient::<F, S>(inputs, &domain, c);
                }
            },
        )
    });
    let serial_start = std::time::Instant::now();
    let terms = particles.volume.iter().zip(gradients.iter()).map(|(&v, l)| (v, v * dilatation(l)));
    inputs.grid.cell_weighted_mean(&particles.position, terms, cell_volume, cell_dilatation);
    *serial_seconds += serial_start.elapsed().as_secs_f64();
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::formulation::{Axisymmetric, PlaneStrain};
    use crate::interpolation::linear::LinearCache;
    use crate::interpolation::Linear;
    use crate::material::{LinearElastic, VonMises};

    /// A deterministic scatter in [0, 1) (golden-ratio sequence).
    fn unit(k: usize) -> f64 {
        (0.1 + k as f64 * 0.618_033_988_749_895).fract()
    }

    /// Grid x ∈ [0, 2], y ∈ [−1, 1]; a valid particle state (index 1 of the chunk inputs).
    /// `check_particle` of one particle (index 1 of its chunk, 7 overall), after checking that
    /// the batch test agrees with it: a batch of that particle alone is valid exactly when the
    /// particle is.
    fn check<F: Formulation>(grid: &GridGeometry, x: [f64; 2], s: Stress, v: [f64; 2], j: f64) -> Option<Failure> {
        let velocity = [[0.0, 0.0], v];
        let chunk = ChunkInputs { initial_volume: &[1.0; 2], velocity: &velocity, displacement: &[[0.0; 2]; 2] };
        let result = check_particle::<F>(&grid.bounds(), &chunk, 7, 1, x, &s, j);
        let kinematics = [Kinematics { jacobian: j, ..Kinematics::ZERO }];
        let alone = batch_is_valid::<F>(&grid.bounds(), &chunk, 1..2, &[[0.0; 2], x], &[[0.0; 4], s], &kinematics);
        assert_eq!(alone, result.is_none(), "batch test vs check_particle at x = {x:?}, s = {s:?}, v = {v:?}, J = {j}");
        result
    }

    /// The batch test over several particles: valid when all are, invalid when any one is
    /// (first, middle or last), whatever the others.
    #[test]
    fn a_batch_is_valid_exactly_when_every_particle_is() {
        let grid = GridGeometry::new([0.0, -1.0], [2.0, 2.0], 0.5);
        let n = 5;
        let position = vec![[1.0, 0.3]; n];
        let stress = vec![[1e5, -2e5, 3e4, -1e4]; n];
        let velocity = vec![[1.0, -2.0]; n];
        let kinematics = vec![Kinematics { jacobian: 0.9, ..Kinematics::ZERO }; n];
        let volume = vec![1.0; n];
        let displacement = vec![[0.0; 2]; n];
        let chunk = ChunkInputs { initial_volume: &volume, velocity: &velocity, displacement: &displacement };
        let valid = |p: &[[f64; 2]], s: &[Stress], k: &[Kinematics]| {
            (batch_is_valid::<Axisymmetric>(&grid.bounds(), &chunk, 0..n, p, s, k),
             batch_is_valid::<PlaneStrain>(&grid.bounds(), &chunk, 0..n, p, s, k))
        };
        assert_eq!(valid(&position, &stress, &kinematics), (true, true));
        for bad in [0, 2, n - 1] {
            let mut p = position.clone();
            p[bad] = [3.0, 0.3];
            assert_eq!(valid(&p, &stress, &kinematics), (false, false), "off the grid at {bad}");
            let mut s = stress.clone();
            s[bad][3] = f64::NAN;
            assert_eq!(valid(&position, &s, &kinematics), (false, false), "NaN stress at {bad}");
            let mut k = kinematics.clone();
            k[bad].jacobian = -1.0;
            assert_eq!(valid(&position, &stress, &k), (false, false), "inverted at {bad}");
            let mut p = position.clone();
            p[bad] = [0.0, 0.3];
            assert_eq!(valid(&p, &stress, &kinematics), (false, true), "on the axis at {bad}");
        }
    }

    /// The particle check, against its definition: any of position, stress and velocity not
    /// finite → NotFinite; outside the closed grid box (or on/behind the axis in axisymmetry)
    /// → LeftGrid; J ≤ 0 or NaN → InvertedJacobian; in that order of precedence, and naming
    /// the particle's global index (7), not its place in the chunk inputs (1).
    #[test]
    fn check_particle_flags_non_finite_values_points_off_the_grid_and_inverted_jacobians() {
        let grid = GridGeometry::new([0.0, -1.0], [2.0, 2.0], 0.5);
        let (x, s, v, j) = ([1.0, 0.3], [1e5, -2e5, 3e4, -1e4], [1.0, -2.0], 0.9);
        assert_eq!(check::<PlaneStrain>(&grid, x, s, v, j), None);
        assert_eq!(check::<Axisymmetric>(&grid, x, s, v, j), None);
        let (tiny, huge) = ([1e-300, -1e-300], [1e300, -1e300, 0.0, -0.0]);
        assert_eq!(check::<PlaneStrain>(&grid, tiny, huge, [-0.0, 1e300], 1e-300), None);
        // Each of the eight values alone, NaN or ±∞.
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for k in 0..8 {
                let mut values = [x[0], x[1], s[0], s[1], s[2], s[3], v[0], v[1]];
                values[k] = bad;
                let [x0, x1, s0, s1, s2, s3, v0, v1] = values;
                let got = check::<PlaneStrain>(&grid, [x0, x1], [s0, s1, s2, s3], [v0, v1], j);
                assert_eq!(got, Some(Failure::NotFinite { particle: 7 }), "value {k} = {bad}");
            }
        }
        // Not finite first, then off the grid, then inverted.
        let nan_stress = [f64::NAN, 0.0, 0.0, 0.0];
        let not_finite = Some(Failure::NotFinite { particle: 7 });
        assert_eq!(check::<PlaneStrain>(&grid, [3.0, 0.0], nan_stress, v, -1.0), not_finite);
        let off = Some(Failure::LeftGrid { particle: 7, position: [3.0, 0.0], velocity: v });
        assert_eq!(check::<PlaneStrain>(&grid, [3.0, 0.0], s, v, -1.0), off);
        // The closed box: every edge and corner is inside, one ulp beyond is not.
        let (up, down) = (f64::next_up, f64::next_down);
        for p in [[0.0, -1.0], [2.0, 1.0], [0.0, 1.0], [2.0, -1.0], [1.0, -1.0], [1.0, 1.0], [0.0, 0.5], [2.0, 0.5]] {
            assert_eq!(check::<PlaneStrain>(&grid, p, s, v, j), None, "{p:?}");
        }
        for p in [[down(0.0), 0.0], [up(2.0), 0.0], [1.0, down(-1.0)], [1.0, up(1.0)], [-5.0, 5.0], [5.0, -5.0]] {
            assert_eq!(check::<PlaneStrain>(&grid, p, s, v, j), Some(Failure::LeftGrid { particle: 7, position: p, velocity: v }));
        }
        // Axisymmetry: r = 0 (on the axis) is off the grid, r > 0 inside is not.
        let left_at = |position| Some(Failure::LeftGrid { particle: 7, position, velocity: v });
        assert_eq!(check::<Axisymmetric>(&grid, [0.0, 0.5], s, v, j), left_at([0.0, 0.5]));
        assert_eq!(check::<Axisymmetric>(&grid, [1e-12, 0.5], s, v, j), None);
        assert_eq!(check::<Axisymmetric>(&grid, [2.0, 0.5], s, v, j), None);
        assert_eq!(check::<Axisymmetric>(&grid, [up(2.0), 0.5], s, v, j), left_at([up(2.0), 0.5]));
        // Plane strain has no axis: x ≤ 0 inside a grid that extends there is fine.
        let left = GridGeometry::new([-1.0, -1.0], [2.0, 2.0], 0.5);
        assert_eq!(check::<PlaneStrain>(&left, [-0.5, 0.0], s, v, j), None);
        assert_eq!(check::<PlaneStrain>(&left, [0.0, 0.0], s, v, j), None);
        assert_eq!(check::<PlaneStrain>(&left, [0.5, 0.0], s, v, j), None);
        for bad in [0.0, -0.0, -0.5, f64::NAN, f64::NEG_INFINITY] {
            let got = check::<PlaneStrain>(&grid, x, s, v, bad);
            let inverted =
                matches!(got, Some(Failure::InvertedJacobian { particle: 7, jacobian }) if jacobian.to_bits() == bad.to_bits());
            assert!(inverted, "J = {bad}: {got:?}");
        }
    }

    /// `GridBounds::contains` (which `GridGeometry::contains` calls) is the closed box
    /// origin ≤ x ≤ upper, on the edges, one ulp either side of them, and on a lattice across
    /// and around the grid.
    #[test]
    fn grid_bounds_contain_the_points_the_grid_contains() {
        let grid = GridGeometry::new([-0.3, 0.2], [1.2, 0.8], 0.1);
        let bounds = grid.bounds();
        let u = grid.upper();
        let o = grid.origin;
        let closed_box = |p: [f64; 2]| p[0] >= o[0] && p[1] >= o[1] && p[0] <= u[0] && p[1] <= u[1];
        let near = |a: f64| [a.next_down(), a, a.next_up()];
        let mut xs: Vec<f64> = [grid.origin[0], u[0]].iter().flat_map(|&a| near(a)).collect();
        let mut ys: Vec<f64> = [grid.origin[1], u[1]].iter().flat_map(|&a| near(a)).collect();
        xs.extend((0..40).map(|k| -0.6 + k as f64 * 0.05));
        ys.extend((0..40).map(|k| -0.1 + k as f64 * 0.05));
        let (mut inside, mut outside) = (0, 0);
        for &x in &xs {
            for &y in &ys {
                let want = closed_box([x, y]);
                assert_eq!(grid.contains([x, y]), want, "({x}, {y})");
                assert_eq!(bounds.contains([x, y]), want, "({x}, {y})");
                if want { inside += 1 } else { outside += 1 }
            }
        }
        assert!(inside > 100 && outside > 100);
        assert!(bounds.contains(grid.origin) && bounds.contains(u));
        assert!(!bounds.contains([f64::NAN, 0.5]) && !bounds.contains([0.0, f64::NAN]));
    }

    /// Particles of one chunk of the update pass, after `first` particles of other chunks: the
    /// per-particle inputs cover all of them, the arrays the pass writes only the chunk's.
    #[derive(Clone)]
    struct Chunk {
        material_ids: Vec<u32>,
        initial_volume: Vec<f64>,
        initial_half_width: Vec<[f64; 2]>,
        velocity: Vec<[f64; 2]>,
        displacement: Vec<[f64; 2]>,
        gradients: Vec<[f64; 5]>,
        f: Vec<[f64; 5]>,
        stress: Vec<Stress>,
        volume: Vec<f64>,
        position: Vec<[f64; 2]>,
        state: Vec<f64>,
    }

    const STRIDE: usize = 3;
    const DT: f64 = 0.01;
    /// The nodal velocity field v = B + A x: linear, so every stencil gives L = A exactly
    /// (up to rounding).
    const A: [[f64; 2]; 2] = [[0.3, -0.2], [0.5, -0.1]];
    const B: [f64; 2] = [0.05, -0.02];

    fn grid() -> GridGeometry {
        GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.125)
    }

    /// Material 0 elastic, material 1 von Mises with a yield stress the particles' stresses
    /// exceed (so its two state slots change every step), 3 state slots per particle.
    fn materials() -> (Vec<Box<dyn Material>>, Vec<usize>) {
        let m: Vec<Box<dyn Material>> =
            vec![Box::new(LinearElastic::new(1000.0, 1e6, 0.3)), Box::new(VonMises::new(1000.0, 5e6, 0.25, 2e3, 1e4))];
        let lengths = m.iter().map(|m| m.state_names().len()).collect();
        (m, lengths)
    }

    /// `first + n` particles spread over the grid, each with its own F, stress and state; the
    /// materials interleaved in runs of 1 to 6 that cross the batches' boundaries (32, 64).
    fn chunk(first: usize, n: usize) -> Chunk {
        let total = first + n;
        let pattern = [0, 0, 1, 0, 1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 1];
        let u = |p: usize, k: usize| unit(7 * p + k);
        Chunk {
            material_ids: (0..total).map(|p| pattern[(p + 3) % pattern.len()]).collect(),
            initial_volume: (0..total).map(|p| 0.01 * (1.0 + u(p, 0))).collect(),
            initial_half_width: vec![[0.03, 0.03]; total],
            velocity: (0..total).map(|p| [u(p, 1) - 0.5, u(p, 2)]).collect(),
            displacement: (0..total).map(|p| [1e-3 * (u(p, 3) - 0.5), 1e-3 * u(p, 4)]).collect(),
            gradients: (0..total).map(|p| [u(p, 0) - 0.5, u(p, 1), -u(p, 2), u(p, 3) - 0.5, 0.1 * u(p, 4)]).collect(),
            f: (first..total)
                .map(|p| [1.0 + 0.1 * u(p, 5), 0.05 * u(p, 6), -0.03 * u(p, 1), 0.95, 1.0 + 0.02 * u(p, 2)])
                .collect(),
            stress: (first..total)
                .map(|p| [-1e4 * u(p, 1), 2e4 * (u(p, 2) - 0.5), -3e3 * u(p, 3), 5e3 * u(p, 4)])
                .collect(),
            volume: vec![0.0; n],
            position: (first..total).map(|p| [0.05 + 0.9 * u(p, 3), 0.05 + 0.9 * u(p, 6)]).collect(),
            state: (first * STRIDE..total * STRIDE).map(|k| 1e-3 * unit(k)).collect(),
        }
    }

    /// Runs `update_chunk` on chunk `k` of `c` with the input arrays of `c` from particle
    /// `offset` on, with the nodal field v = B + A x.
    fn run_chunk<F: Formulation>(c: &mut Chunk, k: usize, offset: usize, averaged: bool, isa: Isa) -> Option<Failure> {
        let grid = grid();
        let nodal: Vec<[f64; 2]> = (0..grid.num_nodes())
            .map(|node| {
                let x = grid.node_position(node);
                [B[0] + A[0][0] * x[0] + A[0][1] * x[1], B[1] + A[1][0] * x[0] + A[1][1] * x[1]]
            })
            .collect();
        let cells = grid.cells[0] * grid.cells[1];
        let cell_mean_dilatation: Vec<f64> = (0..cells).map(|cell| 0.2 * unit(cell) - 0.1).collect();
        let (materials, state_lengths) = materials();
        let start = offset;
        let inputs = UpdateInputs {
            grid,
            dt: DT,
            strain_velocity: &nodal,
            advect_velocity: &nodal,
            materials: &materials,
            state_lengths: &state_lengths,
            material_ids: &c.material_ids[start..],
            initial_volume: &c.initial_volume[start..],
            initial_half_width: &c.initial_half_width[start..],
            velocity: &c.velocity[start..],
            displacement: &c.displacement[start..],
            isa,
            cell_laplacian: None,
        };
        let cache: Vec<LinearCache> = (0..c.f.len())
            .map(|i| {
                let mut cache = LinearCache::default();
                let domain = ParticleDomain {
                    position: c.position[i],
                    initial_half_width: c.initial_half_width[start + k * UPDATE_CHUNK + i],
                    deformation_gradient: &c.f[i],
                    corners: None,
                };
                Linear::prepare(&grid, &domain, F::AXISYMMETRIC, &mut cache);
                cache
            })
            .collect();
        let source = if averaged {
            let gradients = &c.gradients[start..];
            GradientSource::CellAveraged { gradients, cell_mean_dilatation: &cell_mean_dilatation }
        } else {
            GradientSource::Stencil
        };
        let arrays = ChunkArrays::<Linear> {
            f: &mut c.f,
            stress: &mut c.stress,
            volume: &mut c.volume,
            position: &mut c.position,
            state: &mut c.state,
            cache: &cache,
            corners: None,
        };
        update_chunk::<F, Linear>(&inputs, source, STRIDE, k, arrays, &mut [Kinematics::ZERO; STRESS_BATCH])
    }

    /// The velocity gradient particle `p` at `x` should get: A (and v_r / r in axisymmetry)
    /// from the linear field, or with cell averaging its stored gradient with tr L replaced
    /// by the cell's mean dilatation, spread over the 2 (3) normal components.
    fn expected_l<F: Formulation>(c: &Chunk, p: usize, x: [f64; 2], averaged: bool) -> [f64; 5] {
        if averaged {
            let grid = grid();
            let cells = grid.cells[0];
            let cell = (x[1] / grid.cell_size).floor() as usize * cells + (x[0] / grid.cell_size).floor() as usize;
            let mean = 0.2 * unit(cell) - 0.1;
            let g = c.gradients[p];
            let normal = if F::AXISYMMETRIC { 3.0 } else { 2.0 };
            let corr = (mean - (g[0] + g[3] + g[4])) / normal;
            [g[0] + corr, g[1], g[2], g[3] + corr, if F::AXISYMMETRIC { g[4] + corr } else { g[4] }]
        } else {
            let hoop = if F::AXISYMMETRIC { (B[0] + A[0][0] * x[0] + A[0][1] * x[1]) / x[0] } else { 0.0 };
            [A[0][0], A[0][1], A[1][0], A[1][1], hoop]
        }
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-9 * scale.max(b.abs())
    }

    /// The batched update pass (kinematics in batches of 32, one stress call per run of one
    /// material, chunk 1 of the particles) against its definition particle by particle: F ←
    /// (I + Δt L) F with L from the closed form, x ← x + Δx, V = V0 J, the stress and state
    /// of each particle's own material called on its own kinematics; and bit for bit against
    /// the same pass run on each particle alone (a chunk of one, one run of one).
    fn batched_update_is_the_particle_by_particle_update<F: Formulation>(averaged: bool, isa: Isa) {
        let n = 70;
        let first = UPDATE_CHUNK;
        let c0 = chunk(first, n);
        let mut c = c0.clone();
        assert_eq!(run_chunk::<F>(&mut c, 1, 0, averaged, isa), None);
        let (materials, state_lengths) = materials();
        let mut yielded = 0;
        for i in 0..n {
            let p = first + i;
            let what = format!("{} averaged {averaged} {isa:?}: particle {i}", F::NAME);
            // Closed forms.
            let l = expected_l::<F>(&c0, p, c0.position[i], averaged);
            let f0 = c0.f[i];
            let a = [1.0 + DT * l[0], DT * l[1], DT * l[2], 1.0 + DT * l[3]];
            let f = [
                a[0] * f0[0] + a[1] * f0[2],
                a[0] * f0[1] + a[1] * f0[3],
                a[2] * f0[0] + a[3] * f0[2],
                a[2] * f0[1] + a[3] * f0[3],
                (1.0 + DT * l[4]) * f0[4],
            ];
            for k in 0..5 {
                assert!(close(c.f[i][k], f[k], 1.0), "{what}: F {:?} vs {f:?}", c.f[i]);
            }
            let jacobian = (f[0] * f[3] - f[1] * f[2]) * f[4];
            let d = c0.displacement[p];
            assert_eq!(c.position[i], [c0.position[i][0] + d[0], c0.position[i][1] + d[1]], "{what}");
            let volume = c0.initial_volume[p] * jacobian;
            assert!(close(c.volume[i], volume, 0.0), "{what}: V {} vs {volume}", c.volume[i]);
            let id = c0.material_ids[p] as usize;
            let mut stress = c0.stress[i];
            let mut state = c0.state[i * STRIDE..(i + 1) * STRIDE].to_vec();
            let kinematics =
                Kinematics { velocity_gradient: l, deformation_gradient: f, jacobian, cell_field: [0.0; 2], dt: DT };
            materials[id].update_stress(&mut stress, &mut state[..state_lengths[id]], &kinematics);
            for k in 0..4 {
                assert!(close(c.stress[i][k], stress[k], 1e4), "{what}: stress {:?} vs {stress:?}", c.stress[i]);
            }
            for k in 0..STRIDE {
                let got = &c.state[i * STRIDE..(i + 1) * STRIDE];
                assert!(close(got[k], state[k], 1e-3), "{what}: state {got:?} vs {state:?}");
            }
            if id == 1 && c.state[i * STRIDE] != c0.state[i * STRIDE] {
                yielded += 1;
            }
            // One particle alone, bit for bit.
            let mut one = c0.clone();
            one.f = vec![c0.f[i]];
            one.stress = vec![c0.stress[i]];
            one.volume = vec![0.0];
            one.position = vec![c0.position[i]];
            one.state = c0.state[i * STRIDE..(i + 1) * STRIDE].to_vec();
            assert_eq!(run_chunk::<F>(&mut one, 0, p, averaged, isa), None);
            assert_eq!(one.f[0].map(f64::to_bits), c.f[i].map(f64::to_bits), "{what}");
            assert_eq!(one.stress[0].map(f64::to_bits), c.stress[i].map(f64::to_bits), "{what}");
            assert_eq!(one.volume[0].to_bits(), c.volume[i].to_bits(), "{what}");
            assert_eq!(one.position[0], c.position[i], "{what}");
            let bits = |s: &[f64]| s.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&one.state), bits(&c.state[i * STRIDE..(i + 1) * STRIDE]), "{what}");
        }
        // Both materials present, von Mises yielding (its state moves).
        let ones = c0.material_ids[first..].iter().filter(|&&id| id == 1).count();
        assert!(ones > 20 && ones < n - 20 && yielded == ones, "{ones} von Mises particles, {yielded} yielded");
    }

    #[test]
    fn batched_update_pass_is_the_particle_by_particle_update() {
        for isa in [Isa::Baseline, Isa::detect()] {
            for averaged in [false, true] {
                batched_update_is_the_particle_by_particle_update::<PlaneStrain>(averaged, isa);
                batched_update_is_the_particle_by_particle_update::<Axisymmetric>(averaged, isa);
            }
        }
    }

    /// The update pass reports the lowest-index failing particle of the chunk, by its global
    /// index, wherever it lies in the chunk's batches (first, middle, last partial one).
    #[test]
    fn update_chunk_reports_its_lowest_failing_particle() {
        let (first, n) = (UPDATE_CHUNK, 70);
        let run = |c: &Chunk| run_chunk::<PlaneStrain>(&mut c.clone(), 1, 0, false, Isa::Baseline);
        let c0 = chunk(first, n);
        assert_eq!(run(&c0), None);
        // Particle 40: NaN velocity; 45: displaced off the grid; 66: inverted F.
        let mut c = c0.clone();
        c.velocity[first + 40][1] = f64::NAN;
        c.displacement[first + 45] = [2.0, 0.0];
        c.f[66] = [-1.0, 0.0, 0.0, 1.0, 1.0];
        assert_eq!(run(&c), Some(Failure::NotFinite { particle: first + 40 }));
        c.velocity[first + 40] = c0.velocity[first + 40];
        let x = [c0.position[45][0] + 2.0, c0.position[45][1] + 0.0];
        assert_eq!(run(&c), Some(Failure::LeftGrid { particle: first + 45, position: x, velocity: c.velocity[first + 45] }));
        c.displacement[first + 45] = c0.displacement[first + 45];
        let got = run(&c);
        let inverted_at = |got: Option<Failure>, p: usize| {
            matches!(got, Some(Failure::InvertedJacobian { particle, jacobian }) if particle == p && jacobian < 0.0)
        };
        assert!(inverted_at(got.clone(), first + 66), "{got:?}");
        // One more in the first batch comes first.
        c.f[3] = [0.0, 1.0, 1.0, 0.0, 1.0];
        let got = run(&c);
        assert!(inverted_at(got.clone(), first + 3), "{got:?}");
        // Only the last particle of the chunk.
        let mut c = c0.clone();
        c.velocity[first + n - 1][0] = f64::INFINITY;
        assert_eq!(run(&c), Some(Failure::NotFinite { particle: first + n - 1 }));
    }
}
