//! Lanes: the race-free, thread-count-independent scatter of particle → grid.
//!
//! Particles are split into a fixed number of contiguous ranges ([`LANES`], independent of
//! the thread count); each lane sums its particles in particle order into its own nodal
//! buffers, and the lanes are then added node by node in lane order. Every node is therefore
//! summed as 0 + lane0 + lane1 + ... whatever the number of threads: results are bit-for-bit
//! identical for any thread count.

use rayon::prelude::*;

use crate::grid::{GridFields, NodeBox};

/// Number of particle ranges scattered independently in particle → grid.
pub const LANES: usize = 8;

/// What particle → grid accumulates at one node. The fields of a node are kept together so
/// that scattering a particle touches one cache line per node instead of one per field.
#[derive(Clone, Copy, Debug, Default)]
pub struct NodalSums {
    pub mass: f64,
    pub momentum: [f64; 2],
    pub force: [f64; 2],
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
    pub(super) fn new(num_nodes: usize) -> Self {
        Self { nodes: vec![NodalSums::default(); num_nodes], touched: NodeBox::EMPTY }
    }

    /// Zeroes the buffers where the previous scatter wrote (`nodes_x` nodes per grid row).
    /// Not inlined (one call per lane and pass): inlined, it makes the compiled scatter loops
    /// around it depend on unrelated code changes (unstable instruction counts).
    #[inline(never)]
    pub(super) fn clear(&mut self, nodes_x: usize) {
        let b = self.touched;
        if !b.is_empty() {
            let (first, last) = (b.columns[0] as usize, b.columns[1] as usize);
            for j in b.row_range() {
                let row = j * nodes_x;
                self.nodes[row + first..=row + last].fill(NodalSums::default());
            }
        }
        self.touched = NodeBox::EMPTY;
    }
}

/// Particles per lane: lanes are equal contiguous chunks (the last may be shorter or empty).
#[inline(always)]
pub(super) fn lane_length(n: usize) -> usize {
    n.div_ceil(LANES).max(1)
}

/// Sums the lanes node by node in lane order into the grid fields: momentum always, mass and
/// force when `all` (the MUSL re-map only scatters momentum).
/// Only `region` is zeroed first: outside it the fields are zero already (see
/// [`super::Scratch::grid_reached`]) and no lane reaches there.
pub(super) fn sum_lanes(lanes: &[Lane], nodes_x: usize, region: NodeBox, fields: &mut GridFields, all: bool) {
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
                let (first_column, last_column) = (region.columns[0] as usize, region.columns[1] as usize);
                for j in (region.rows[0] as usize).max(first_row)..=(region.rows[1] as usize).min(last_row) {
                    let local = j * nodes_x - start + first_column..=j * nodes_x - start + last_column;
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
                let (first_column, last_column) = (b.columns[0] as usize, b.columns[1] as usize);
                for j in (b.rows[0] as usize).max(first_row)..=(b.rows[1] as usize).min(last_row) {
                    let row = j * nodes_x;
                    let nodes = &lane.nodes[row + first_column..=row + last_column];
                    let local = row - start + first_column..=row - start + last_column;
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

