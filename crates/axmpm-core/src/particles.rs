//! Material points in structure-of-arrays layout.
//!
//! Volumes and masses are per unit thickness in plane strain and per radian in axisymmetry
//! (V_p = A_p R_p, m_p = ρ_p A_p R_p; Sulsky & Schreyer 1996).

use serde::{Deserialize, Serialize};

/// Deformation gradient stored as `[F11, F12, F21, F22, F33]`; F33 is the hoop stretch
/// (axisymmetric) or 1 (plane strain).
pub type DeformationGradient = [f64; 5];

/// Stress `[σ11, σ22, σ33, σ12]`: `[xx, yy, zz, xy]` in plane strain, `[rr, zz, θθ, rz]` in
/// axisymmetry. Tension positive, Pa.
pub type Stress = [f64; 4];

pub const IDENTITY_F: DeformationGradient = [1.0, 0.0, 0.0, 1.0, 1.0];

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Particles {
    pub position: Vec<[f64; 2]>,
    pub velocity: Vec<[f64; 2]>,
    pub mass: Vec<f64>,
    pub initial_volume: Vec<f64>,
    pub volume: Vec<f64>,
    pub initial_position: Vec<[f64; 2]>,
    pub deformation_gradient: Vec<DeformationGradient>,
    pub stress: Vec<Stress>,
    pub material: Vec<u32>,
    /// Initial half-widths of the particle domain (GIMP family; CPDI uses them to build corners).
    pub initial_half_width: Vec<[f64; 2]>,
    /// Corners of the particle domain, counter-clockwise (CPDI2 only; empty otherwise).
    pub corners: Vec<[[f64; 2]; 4]>,
    /// Per-material state variables, `state_stride` values per particle.
    pub state: Vec<f64>,
    pub state_stride: usize,
    /// Original number of each particle (its index when created). The solver keeps the
    /// particles sorted by grid tile (`solver::tiles`); what the user sees is put back in id
    /// order ([`Particles::in_id_order`]). Empty in checkpoints written before the sort
    /// existed (then the ids are the indices).
    #[serde(default)]
    pub id: Vec<u32>,
    /// Saturated runs only (`solver::saturated`; empty otherwise, and 0 / 0 for the
    /// particles of a dry body in a saturated run): pore pressure p (Pa, positive in
    /// compression; `stress` is then the effective stress σ′, the total being σ′ − p I) ...
    #[serde(default)]
    pub pore_pressure: Vec<f64>,
    /// ... porosity n (updated with the volume, the grains incompressible) ...
    #[serde(default)]
    pub porosity: Vec<f64>,
    /// ... the pore water's velocity w (m/s) ...
    #[serde(default)]
    pub water_velocity: Vec<[f64; 2]>,
    /// ... the hydraulic conductivity k (m/s) ...
    #[serde(default)]
    pub hydraulic_conductivity: Vec<f64>,
    /// ... and a prescribed external force on the particle (N per metre or per radian): a
    /// surface load carried by the body's top row of particles.
    #[serde(default)]
    pub external_force: Vec<[f64; 2]>,
}

impl Particles {
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.position.len()
    }

    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// Appends one particle with zero state and identity deformation.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        position: [f64; 2],
        velocity: [f64; 2],
        mass: f64,
        volume: f64,
        half_width: [f64; 2],
        stress: Stress,
        material: u32,
    ) {
        self.position.push(position);
        self.velocity.push(velocity);
        self.mass.push(mass);
        self.initial_volume.push(volume);
        self.volume.push(volume);
        self.initial_position.push(position);
        self.deformation_gradient.push(IDENTITY_F);
        self.stress.push(stress);
        self.material.push(material);
        self.initial_half_width.push(half_width);
        self.id.push(self.id.len() as u32);
        self.state.extend(std::iter::repeat(0.0).take(self.state_stride));
    }

    /// Rectangular domain corners from the centre and half-widths, counter-clockwise from the
    /// lower left.
    pub fn rectangle_corners(x: [f64; 2], half: [f64; 2]) -> [[f64; 2]; 4] {
        [
            [x[0] - half[0], x[1] - half[1]],
            [x[0] + half[0], x[1] - half[1]],
            [x[0] + half[0], x[1] + half[1]],
            [x[0] - half[0], x[1] + half[1]],
        ]
    }

    /// Releases the spare capacity that growing the arrays particle by particle left (up to
    /// twice the particle count per array): the particle count is fixed for the whole run.
    pub fn shrink_to_fit(&mut self) {
        self.position.shrink_to_fit();
        self.velocity.shrink_to_fit();
        self.mass.shrink_to_fit();
        self.initial_volume.shrink_to_fit();
        self.volume.shrink_to_fit();
        self.initial_position.shrink_to_fit();
        self.deformation_gradient.shrink_to_fit();
        self.stress.shrink_to_fit();
        self.material.shrink_to_fit();
        self.initial_half_width.shrink_to_fit();
        self.corners.shrink_to_fit();
        self.state.shrink_to_fit();
        self.id.shrink_to_fit();
        self.pore_pressure.shrink_to_fit();
        self.porosity.shrink_to_fit();
        self.water_velocity.shrink_to_fit();
        self.hydraulic_conductivity.shrink_to_fit();
        self.external_force.shrink_to_fit();
    }

    /// Gives particles without ids (an older checkpoint) the ids 0, 1, 2, ...
    pub fn ensure_ids(&mut self) {
        if self.id.len() != self.len() {
            self.id = (0..self.len() as u32).collect();
        }
    }

    /// Whether every particle is at the index of its id.
    pub fn in_id_order_already(&self) -> bool {
        self.id.iter().enumerate().all(|(k, &id)| id as usize == k)
    }

    /// Reorders every per-particle array: the particle at `order[k]` moves to `k`. With
    /// `parallel`, on the current rayon pool: the solver calls it inside the simulation's own
    /// pool; copies for output run serially, so that they never start rayon's global pool (a
    /// process forked after that, e.g. by a process pool, would wait forever for its threads).
    pub fn permute(&mut self, order: &[u32], parallel: bool) {
        use rayon::prelude::*;
        fn gather<T: Copy + Send + Sync>(v: &mut Vec<T>, order: &[u32], parallel: bool) {
            if v.len() == order.len() {
                *v = if parallel {
                    order.par_iter().map(|&k| v[k as usize]).collect()
                } else {
                    order.iter().map(|&k| v[k as usize]).collect()
                };
            }
        }
        gather(&mut self.position, order, parallel);
        gather(&mut self.velocity, order, parallel);
        gather(&mut self.mass, order, parallel);
        gather(&mut self.initial_volume, order, parallel);
        gather(&mut self.volume, order, parallel);
        gather(&mut self.initial_position, order, parallel);
        gather(&mut self.deformation_gradient, order, parallel);
        gather(&mut self.stress, order, parallel);
        gather(&mut self.material, order, parallel);
        gather(&mut self.initial_half_width, order, parallel);
        gather(&mut self.corners, order, parallel);
        gather(&mut self.id, order, parallel);
        gather(&mut self.pore_pressure, order, parallel);
        gather(&mut self.porosity, order, parallel);
        gather(&mut self.water_velocity, order, parallel);
        gather(&mut self.hydraulic_conductivity, order, parallel);
        gather(&mut self.external_force, order, parallel);
        let stride = self.state_stride;
        if stride > 0 && self.state.len() == order.len() * stride {
            let mut state = vec![0.0; self.state.len()];
            let copy = |(slots, &k): (&mut [f64], &u32)| {
                slots.copy_from_slice(&self.state[k as usize * stride..(k as usize + 1) * stride]);
            };
            if parallel {
                state.par_chunks_mut(stride).zip(order.par_iter()).for_each(copy);
            } else {
                state.chunks_mut(stride).zip(order.iter()).for_each(copy);
            }
            self.state = state;
        }
    }

    /// `values`, one per particle in array order, put in id order (a copy either way).
    pub fn by_id<T: Copy + Default>(&self, values: &[T]) -> Vec<T> {
        if self.id.len() != values.len() || self.in_id_order_already() {
            return values.to_vec();
        }
        let mut out = vec![T::default(); values.len()];
        for (&id, &v) in self.id.iter().zip(values) {
            out[id as usize] = v;
        }
        out
    }

    /// For each id, the particle's index in the arrays.
    pub fn index_of_ids(&self) -> Vec<u32> {
        let mut index: Vec<u32> = (0..self.len() as u32).collect();
        if self.id.len() == self.len() {
            for (k, &id) in self.id.iter().enumerate() {
                index[id as usize] = k as u32;
            }
        }
        index
    }

    /// A copy with the particles in id order (as created), the order of everything the user
    /// sees; borrowed when they are in that order already.
    pub fn in_id_order(&self) -> std::borrow::Cow<'_, Particles> {
        if self.id.len() != self.len() || self.in_id_order_already() {
            return std::borrow::Cow::Borrowed(self);
        }
        let mut order = vec![0u32; self.len()];
        for (k, &id) in self.id.iter().enumerate() {
            order[id as usize] = k as u32;
        }
        let mut copy = self.clone();
        copy.permute(&order, false);
        std::borrow::Cow::Owned(copy)
    }

    /// Bytes held per particle by the arrays above (for the benchmark's memory figure).
    pub fn bytes_per_particle(&self) -> usize {
        let n = self.len().max(1);
        let f = std::mem::size_of::<f64>();
        let total = self.position.capacity() * 2 * f
            + self.velocity.capacity() * 2 * f
            + self.mass.capacity() * f
            + self.initial_volume.capacity() * f
            + self.volume.capacity() * f
            + self.initial_position.capacity() * 2 * f
            + self.deformation_gradient.capacity() * 5 * f
            + self.stress.capacity() * 4 * f
            + self.material.capacity() * 4
            + self.initial_half_width.capacity() * 2 * f
            + self.corners.capacity() * 8 * f
            + self.state.capacity() * f
            + self.id.capacity() * 4
            + (self.pore_pressure.capacity() + self.porosity.capacity() + self.hydraulic_conductivity.capacity()) * f
            + (self.water_velocity.capacity() + self.external_force.capacity()) * 2 * f;
        total / n
    }
}
