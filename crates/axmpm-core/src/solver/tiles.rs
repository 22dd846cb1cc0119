//! Tiles: the race-free, thread-count-independent scatter of particle → grid, and the
//! particle order that makes it possible.
//!
//! Every [`SORT_INTERVAL`] steps the particles are sorted (stably) by tile of
//! [`TILE`] × [`TILE`] cells (the tile of the cell holding the particle's centre), the tiles
//! ordered by colour first: tile (a, b) has colour
//! (a mod 2) + 2 (b mod 2), so two tiles of one colour are at least one tile apart in x or in y.
//! After the sort each tile's particles are one contiguous range of the particle arrays, and the
//! colours follow each other in the arrays.
//!
//! A tile may write only inside its *zone*, its cells' nodes widened by [`HALO`] nodes on every
//! side; zones of tiles of one colour are disjoint (`TILE + 1 + 2 HALO ≤ 2 TILE`). The scatter
//! runs colour by colour: within a colour the tiles run in parallel, each adding its particles
//! in array order straight into the grid fields; a particle whose stencil leaves its tile's
//! zone (a CPDI2 domain stretched over several cells, or a particle that drifted since the last
//! sort) is skipped there and added after the colour's parallel part, on one thread, in array
//! order. Every node therefore receives its contributions in an order fixed by the particle
//! arrays alone (per colour: the one tile whose zone holds the node, then the overflowing
//! particles), whatever the number of threads: results are bit-for-bit identical for any
//! thread count. No nodal buffers besides the grid fields.
//!
//! The order between two sorts is part of the state: checkpoints store the particles in it,
//! with their original ids (`Particles::id`) and the tile ranges, so a resumed run continues
//! bit for bit.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::grid::{GridGeometry, NodeBox};
use crate::interpolation::fast_floor;
use crate::particles::Particles;

/// Cells per tile side. 8 × 8 cells hold 256 particles at 2 × 2 per cell: a tile's stencil
/// caches stay in the core's L2 cache, and a 200,000-particle body has about 800 tiles,
/// 200 per colour, enough for dozens of threads.
pub const TILE: u32 = 8;

/// Nodes a tile's zone extends past its cells on each side: a GIMP domain reaches one node
/// past its cell and a particle may drift a couple of cells between sorts. Zones of tiles of
/// one colour are disjoint as long as TILE + 1 + 2 HALO ≤ 2 TILE.
pub const HALO: u32 = 3;
const _: () = assert!(TILE + 1 + 2 * HALO <= 2 * TILE);

/// Steps between sorts (and a sort when a run starts or resumes from an older checkpoint).
pub const SORT_INTERVAL: u64 = 10;

/// Number of tile colours.
pub const COLOURS: usize = 4;

/// One tile's particles, `start..end` of the particle arrays, and its tile coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tile {
    pub coords: [u32; 2],
    pub start: u32,
    pub end: u32,
}

impl Tile {
    #[inline(always)]
    pub fn colour(&self) -> usize {
        ((self.coords[0] & 1) + 2 * (self.coords[1] & 1)) as usize
    }

    #[inline(always)]
    pub fn range(&self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }

    /// The nodes this tile may write to in the parallel part of the scatter.
    #[inline(always)]
    pub fn zone(&self) -> NodeBox {
        let [a, b] = self.coords;
        NodeBox {
            columns: [(a * TILE).saturating_sub(HALO), a * TILE + TILE + HALO],
            rows: [(b * TILE).saturating_sub(HALO), b * TILE + TILE + HALO],
        }
    }
}

/// Whether `inner` (non-empty) lies inside `outer`.
#[inline(always)]
pub fn inside(inner: NodeBox, outer: NodeBox) -> bool {
    inner.columns[0] >= outer.columns[0]
        && inner.columns[1] <= outer.columns[1]
        && inner.rows[0] >= outer.rows[0]
        && inner.rows[1] <= outer.rows[1]
}

/// What the scatter learned about one tile in this step's particle → grid.
#[derive(Clone, Copy, Debug, Default)]
pub struct TileReach {
    /// The nodes its particles reach.
    pub reached: NodeBox,
    /// Whether some particle's stencil left the tile's zone (it is then added on one thread).
    pub overflow: bool,
}

/// The tiles in array order (colour by colour), and where each colour starts.
#[derive(Clone, Debug, Default)]
pub struct TileOrder {
    pub tiles: Vec<Tile>,
    /// Tiles of colour c are `tiles[colour_start[c]..colour_start[c + 1]]`.
    pub colour_start: [usize; COLOURS + 1],
    pub reach: Vec<TileReach>,
}

impl TileOrder {
    /// Rebuilds the colour index from `tiles` (restored from a checkpoint or just sorted).
    pub fn from_tiles(tiles: Vec<Tile>) -> Self {
        let mut colour_start = [tiles.len(); COLOURS + 1];
        for c in (0..COLOURS).rev() {
            colour_start[c] = tiles.iter().position(|t| t.colour() >= c).unwrap_or(colour_start[c + 1]);
        }
        let reach = vec![TileReach::default(); tiles.len()];
        Self { tiles, colour_start, reach }
    }

    pub fn is_empty(&self) -> bool {
        self.tiles.is_empty()
    }

    /// Tile indices of colour `c`.
    #[inline(always)]
    pub fn colour(&self, c: usize) -> std::ops::Range<usize> {
        self.colour_start[c]..self.colour_start[c + 1]
    }
}

/// Tiles of the grid along x and y.
fn tile_counts(grid: &GridGeometry) -> [u32; 2] {
    [(grid.cells[0] as u32).div_ceil(TILE), (grid.cells[1] as u32).div_ceil(TILE)]
}

/// Sort key of a particle at `x`: its tile, numbered colour by colour, row by row within a
/// colour (with gaps: the numbers run over all tiles for every colour).
#[inline(always)]
fn tile_key(grid: &GridGeometry, tiles: [u32; 2], x: [f64; 2]) -> u32 {
    // The cell, clamped to the grid (particles outside it have failed the step already).
    let l = grid.local(x);
    let cell = |l: f64, n: usize| (fast_floor(l).max(0.0) as u32).min(n as u32 - 1);
    let (a, b) = (cell(l[0], grid.cells[0]) / TILE, cell(l[1], grid.cells[1]) / TILE);
    let colour = (a & 1) + 2 * (b & 1);
    (colour * tiles[1] + b) * tiles[0] + a
}

/// The tile coordinates of a key of [`tile_key`].
fn tile_of_key(tiles: [u32; 2], key: u32) -> [u32; 2] {
    [key % tiles[0], key / tiles[0] % tiles[1]]
}

/// Sorts the particles by tile, colour by colour (a stable counting sort: particles of one
/// tile keep their order), and returns the tiles. Not in the step's hot loops: once every
/// [`SORT_INTERVAL`] steps, allocating the permuted arrays.
/// `serial_seconds` accumulates the time of the one-thread part.
pub fn sort_particles(grid: &GridGeometry, particles: &mut Particles, serial_seconds: &mut f64) -> TileOrder {
    let n = particles.len();
    assert!(n < u32::MAX as usize, "more than 2³² − 1 particles");
    let tiles = tile_counts(grid);
    let keys: Vec<u32> = particles.position.par_iter().map(|&x| tile_key(grid, tiles, x)).collect();
    // Counting sort: bucket sizes, their starts, then each particle to the next place of its
    // bucket in array order (stable, one thread: the same order on any number of threads).
    let serial_start = std::time::Instant::now();
    let buckets = COLOURS * (tiles[0] * tiles[1]) as usize;
    let mut start = vec![0u32; buckets + 1];
    for &k in &keys {
        start[k as usize + 1] += 1;
    }
    for b in 0..buckets {
        start[b + 1] += start[b];
    }
    let mut next = start.clone();
    let mut order = vec![0u32; n];
    for (p, &k) in keys.iter().enumerate() {
        order[next[k as usize] as usize] = p as u32;
        next[k as usize] += 1;
    }
    let identity = order.iter().enumerate().all(|(k, &p)| k as u32 == p);
    *serial_seconds += serial_start.elapsed().as_secs_f64();
    if !identity {
        particles.permute(&order, true);
    }
    let tiles = (0..buckets)
        .filter(|&b| start[b + 1] > start[b])
        .map(|b| Tile { coords: tile_of_key(tiles, b as u32), start: start[b], end: start[b + 1] })
        .collect();
    TileOrder::from_tiles(tiles)
}

/// A slice shared by the tasks of one colour, which write disjoint parts of it: disjoint
/// particle ranges (tiles), or disjoint node zones (tiles of one colour).
#[derive(Clone, Copy)]
pub(super) struct Shared<T> {
    pointer: *mut T,
    len: usize,
}

// SAFETY: `Shared` only hands out access through the unsafe methods below, whose callers
// guarantee that no two threads touch the same element.
unsafe impl<T: Send> Send for Shared<T> {}
unsafe impl<T: Send> Sync for Shared<T> {}

impl<T> Shared<T> {
    pub(super) fn new(slice: &mut [T]) -> Self {
        Self { pointer: slice.as_mut_ptr(), len: slice.len() }
    }

    /// The element at `k`.
    /// SAFETY: no other thread accesses element `k` while the reference lives.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn at(&self, k: usize) -> &mut T {
        debug_assert!(k < self.len);
        &mut *self.pointer.add(k)
    }

    /// The elements `range`.
    /// SAFETY: no other thread accesses them while the slice lives.
    #[inline(always)]
    #[allow(clippy::mut_from_ref)]
    pub(super) unsafe fn slice(&self, range: std::ops::Range<usize>) -> &mut [T] {
        assert!(range.start <= range.end && range.end <= self.len);
        std::slice::from_raw_parts_mut(self.pointer.add(range.start), range.end - range.start)
    }
}

/// Zeroes `box_` (rows of `nodes_x` nodes) in each of `fields`, rows in parallel.
pub(super) fn zero_box<T: Copy + Default + Send + Sync>(field: &mut [T], nodes_x: usize, region: NodeBox) {
    if region.is_empty() {
        return;
    }
    let (first_row, rows) = region.row_span();
    let columns = region.column_span(nodes_x);
    field.par_chunks_mut(nodes_x).skip(first_row).take(rows).with_min_len(8).for_each(|row| {
        row[columns.clone()].fill(T::default());
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes_overlap(a: NodeBox, b: NodeBox) -> bool {
        a.columns[0] <= b.columns[1] && b.columns[0] <= a.columns[1] && a.rows[0] <= b.rows[1] && b.rows[0] <= a.rows[1]
    }

    #[test]
    fn zones_of_one_colour_are_disjoint_and_zones_hold_their_tiles_nodes() {
        let tile = |a, b| Tile { coords: [a, b], start: 0, end: 1 };
        for a in 0..6 {
            for b in 0..6 {
                let t = tile(a, b);
                let z = t.zone();
                // The tile's own cells' nodes plus HALO on every side (clipped at 0).
                assert!(inside(NodeBox { columns: [a * TILE, a * TILE + TILE], rows: [b * TILE, b * TILE + TILE] }, z));
                for c in 0..6 {
                    for d in 0..6 {
                        let u = tile(c, d);
                        if (c, d) != (a, b) && u.colour() == t.colour() {
                            assert!(!boxes_overlap(z, u.zone()), "{:?} {:?}", t.coords, u.coords);
                        }
                    }
                }
            }
        }
        // Neighbouring tiles (other colours) do share nodes: the colours are needed.
        assert!(boxes_overlap(tile(1, 1).zone(), tile(2, 1).zone()));
    }

    #[test]
    fn sort_groups_particles_by_tile_colour_by_colour_keeping_their_order() {
        let grid = GridGeometry::new([0.0, 0.0], [4.0, 3.0], 0.1); // 40 × 30 cells, 5 × 4 tiles
        let mut particles = Particles { state_stride: 1, ..Default::default() };
        // A scattered, deterministic cloud; a few particles share a cell.
        for k in 0..700u32 {
            let x = [(k as f64 * 0.618_034).fract() * 3.999, (k as f64 * 0.414_214).fract() * 2.999];
            particles.push(x, [k as f64, 0.0], 1.0, 1.0, [0.05; 2], [0.0; 4], 0);
            particles.state[k as usize] = k as f64;
        }
        let mut serial = 0.0;
        let order = sort_particles(&grid, &mut particles, &mut serial);
        let tiles = tile_counts(&grid);
        let mut next = 0;
        let mut previous_colour = 0;
        for t in &order.tiles {
            assert_eq!(t.start, next, "tiles cover the arrays in order");
            assert!(t.end > t.start);
            next = t.end;
            assert!(t.colour() >= previous_colour, "colour by colour");
            previous_colour = t.colour();
            for p in t.range() {
                assert_eq!(tile_of_key(tiles, tile_key(&grid, tiles, particles.position[p])), t.coords);
                if p > t.range().start {
                    assert!(particles.id[p] > particles.id[p - 1], "stable within a tile");
                }
            }
        }
        assert_eq!(next as usize, particles.len());
        for c in 0..COLOURS {
            assert!(order.tiles[order.colour(c)].iter().all(|t| t.colour() == c));
        }
        // Every array moved with its particle.
        for p in 0..particles.len() {
            let id = particles.id[p] as f64;
            assert_eq!(particles.velocity[p][0], id);
            assert_eq!(particles.state[p], id);
        }
        // Sorting again changes nothing.
        let before = particles.position.clone();
        let again = sort_particles(&grid, &mut particles, &mut serial);
        assert_eq!(particles.position, before);
        assert_eq!(again.tiles, order.tiles);
    }
}
