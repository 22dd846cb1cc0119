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
use crate::interpolation::clamped_floor;
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
    let cell = |l: f64, n: usize| clamped_floor(l, (n - 1) as f64);
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

/// Runs a scatter over the tiles of `order`, colour by colour: first every tile of a colour in
/// parallel (`scatter(tile, false)`, its reach recorded), then, on this thread in array order,
/// the tiles whose particles left their zone (`scatter(tile, true)`). Within a colour the tiles'
/// zones are disjoint, so the parallel part is race free and the sums do not depend on the
/// thread count. Returns the nodes the tiles reached and the time spent on one thread.
#[inline(always)]
pub(super) fn scatter_by_colour(
    order: &mut TileOrder,
    scatter: impl Fn(&Tile, bool) -> TileReach + Sync,
) -> (NodeBox, std::time::Duration) {
    let mut serial = std::time::Duration::ZERO;
    for c in 0..COLOURS {
        let range = order.colour(c);
        order.tiles[range.clone()].par_iter().zip(order.reach[range.clone()].par_iter_mut()).for_each(|(tile, reach)| {
            *reach = scatter(tile, false);
        });
        let serial_start = std::time::Instant::now();
        for (tile, reach) in order.tiles[range.clone()].iter().zip(&order.reach[range]) {
            if reach.overflow {
                scatter(tile, true);
            }
        }
        serial += serial_start.elapsed();
    }
    (order.reach.iter().fold(NodeBox::EMPTY, |b, r| b.union(r.reached)), serial)
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

    /// A tile's zone is exactly its cells' nodes widened by HALO nodes on every side, clipped
    /// at node 0: no narrower (its particles' stencils must fit) and no wider (the zones of one
    /// colour's tiles, 2 TILE nodes apart, leave a gap of one node only).
    #[test]
    fn zone_is_the_tiles_cell_nodes_widened_by_halo_clipped_at_node_zero() {
        let span = |k: u32| {
            let first = k as i64 * TILE as i64 - HALO as i64;
            [first.max(0) as u32, (k + 1) * TILE + HALO]
        };
        for a in 0..7 {
            for b in 0..7 {
                let z = Tile { coords: [a, b], start: 0, end: 1 }.zone();
                assert_eq!(z, NodeBox { columns: span(a), rows: span(b) }, "tile ({a}, {b})");
            }
        }
        // Spelled out for the first tiles: nodes 0..=11, 5..=19, 13..=27 (TILE 8, HALO 3).
        assert_eq!(Tile { coords: [0, 1], start: 0, end: 1 }.zone(), NodeBox { columns: [0, 11], rows: [5, 19] });
        assert_eq!(Tile { coords: [2, 0], start: 0, end: 1 }.zone(), NodeBox { columns: [13, 27], rows: [0, 11] });
    }

    /// `inside` holds for a box equal to the outer box or within it, and fails as soon as the
    /// inner box sticks out by one node on any single side (the case of a particle whose
    /// stencil leaves its tile's zone by one node: it must go to the one-thread part).
    #[test]
    fn inside_fails_when_the_box_sticks_out_by_one_node_on_any_one_side() {
        let outer = NodeBox { columns: [4, 10], rows: [20, 30] };
        assert!(inside(outer, outer));
        assert!(inside(NodeBox { columns: [5, 9], rows: [21, 29] }, outer));
        assert!(inside(NodeBox { columns: [4, 4], rows: [30, 30] }, outer));
        assert!(inside(NodeBox { columns: [10, 10], rows: [20, 20] }, outer));
        let sticking_out = [
            ("left", NodeBox { columns: [3, 10], rows: [20, 30] }),
            ("right", NodeBox { columns: [4, 11], rows: [20, 30] }),
            ("bottom", NodeBox { columns: [4, 10], rows: [19, 30] }),
            ("top", NodeBox { columns: [4, 10], rows: [20, 31] }),
            ("left, within the rows", NodeBox { columns: [3, 5], rows: [22, 23] }),
            ("top, within the columns", NodeBox { columns: [6, 7], rows: [29, 31] }),
            ("all four sides", NodeBox { columns: [3, 11], rows: [19, 31] }),
            ("beside it", NodeBox { columns: [11, 12], rows: [20, 30] }),
        ];
        for (side, inner) in sticking_out {
            assert!(!inside(inner, outer), "{side}: {inner:?}");
        }
    }

    /// A particle on the grid's upper edge or outside the grid (it has failed the step, but is
    /// sorted first) goes to the tile of the nearest cell: the last cell holds x = upper, and the
    /// tile numbers stay within the tile counts.
    #[test]
    fn particles_on_or_outside_the_grids_edges_go_to_the_nearest_edge_tile() {
        let grid = GridGeometry::new([0.0, 0.0], [4.0, 3.0], 0.1); // 40 × 30 cells, 5 × 4 tiles
        let tiles = tile_counts(&grid);
        assert_eq!(tiles, [5, 4]);
        let cases = [
            ([4.0, 3.0], [4, 3]),   // the upper corner: cell (39, 29)
            ([4.25, 3.5], [4, 3]),  // past it
            ([4.0, 1.25], [4, 1]),  // on the right edge, cell row 12
            ([1.65, 3.0], [2, 3]),  // on the top edge, cell column 16
            ([-0.3, -0.2], [0, 0]), // below the origin
            ([-1.0, 2.05], [0, 2]), // left of it, cell row 20
            ([0.05, 0.05], [0, 0]),
        ];
        let mut particles = Particles { state_stride: 1, ..Default::default() };
        for (x, t) in cases {
            assert_eq!(tile_of_key(tiles, tile_key(&grid, tiles, x)), t, "{x:?}");
            particles.push(x, [0.0; 2], 1.0, 1.0, [0.05; 2], [0.0; 4], 0);
        }
        let order = sort_particles(&grid, &mut particles, &mut 0.0);
        for t in &order.tiles {
            for p in t.range() {
                assert_eq!(t.coords, cases[particles.id[p] as usize].1, "particle {}", particles.id[p]);
            }
        }
        assert_eq!(order.tiles.iter().map(|t| t.range().len()).sum::<usize>(), cases.len());
    }

    /// A sort in which no particle keeps its index is applied (the permutation is not taken
    /// for the identity), every array following its particle.
    #[test]
    fn sort_moves_the_particles_when_none_keeps_its_place() {
        let grid = GridGeometry::new([0.0, 0.0], [4.0, 3.0], 0.1); // 5 × 4 tiles
        let mut particles = Particles { state_stride: 1, ..Default::default() };
        // Tiles (1, 0) (colour 1), (0, 1) (colour 2), (0, 0) (colour 0): sorted 2, 0, 1.
        for (k, x) in [[1.05, 0.05], [0.05, 1.05], [0.05, 0.05]].into_iter().enumerate() {
            particles.push(x, [k as f64, 0.0], 1.0, 1.0, [0.05; 2], [0.0; 4], 0);
        }
        let order = sort_particles(&grid, &mut particles, &mut 0.0);
        assert_eq!(particles.id, [2, 0, 1]);
        assert_eq!(particles.position, [[0.05, 0.05], [1.05, 0.05], [0.05, 1.05]]);
        assert_eq!(particles.velocity, [[2.0, 0.0], [0.0, 0.0], [1.0, 0.0]]);
        let tile = |a, b, k| Tile { coords: [a, b], start: k, end: k + 1 };
        assert_eq!(order.tiles, [tile(0, 0, 0), tile(1, 0, 1), tile(0, 1, 2)]);
        assert_eq!([order.colour(0), order.colour(1), order.colour(2), order.colour(3)], [0..1, 1..2, 2..3, 3..3]);
    }

    /// The colour ranges partition the tile list in order: colour c's range holds exactly the
    /// tiles of colour c, the ranges follow each other from 0 to the number of tiles, a colour
    /// without tiles has an empty range; the order is empty exactly when it has no tiles.
    #[test]
    fn colour_ranges_partition_the_tiles_colour_by_colour() {
        let tile = |a, b| Tile { coords: [a, b], start: 0, end: 1 };
        assert!(TileOrder::default().is_empty());
        let lists = [
            vec![],
            vec![tile(0, 0), tile(2, 0), tile(1, 0), tile(0, 1), tile(4, 3), tile(1, 1), tile(3, 1)],
            vec![tile(1, 0), tile(1, 2)],             // colour 1 only
            vec![tile(0, 0), tile(1, 1)],             // colours 0 and 3
            vec![tile(0, 1), tile(2, 1), tile(1, 1)], // colours 2 and 3
            vec![tile(0, 2), tile(1, 0), tile(3, 0)], // colours 0 and 1
        ];
        for tiles in lists {
            let order = TileOrder::from_tiles(tiles.clone());
            assert_eq!(order.is_empty(), tiles.is_empty(), "{tiles:?}");
            assert_eq!(order.reach.len(), tiles.len());
            let mut next = 0;
            for c in 0..COLOURS {
                let range = order.colour(c);
                assert_eq!(range.start, next, "colour {c} of {tiles:?}");
                assert_eq!(range.len(), tiles.iter().filter(|t| t.colour() == c).count(), "colour {c} of {tiles:?}");
                assert!(tiles[range.clone()].iter().all(|t| t.colour() == c), "colour {c} of {tiles:?}");
                next = range.end;
            }
            assert_eq!(next, tiles.len());
        }
    }

    /// For grids of 1 to 40 cells a side (whole and partial tiles) with one particle at the
    /// centre of every cell, created in reverse order: every particle lands in exactly one tile,
    /// its cell's, in creation order within it; each tile's cells' nodes lie in its zone; the
    /// zones of one colour's tiles are pairwise disjoint.
    #[test]
    fn every_cell_lands_in_its_tile_and_one_colours_zones_are_disjoint_for_many_grid_sizes() {
        for nx in [1usize, 2, 7, 8, 9, 16, 17, 24, 33] {
            for ny in [1usize, 5, 8, 9, 23, 40] {
                let grid = GridGeometry::new([-1.0, 2.0], [nx as f64 * 0.5, ny as f64 * 0.5], 0.5);
                let mut particles = Particles { state_stride: 1, ..Default::default() };
                for j in (0..ny).rev() {
                    for i in (0..nx).rev() {
                        let x = [-1.0 + (i as f64 + 0.5) * 0.5, 2.0 + (j as f64 + 0.5) * 0.5];
                        particles.push(x, [0.0; 2], 1.0, 1.0, [0.125; 2], [0.0; 4], 0);
                    }
                }
                let order = sort_particles(&grid, &mut particles, &mut 0.0);
                let size = format!("{nx} × {ny} cells");
                assert_eq!(order.tiles.len(), nx.div_ceil(TILE as usize) * ny.div_ceil(TILE as usize), "{size}");
                let mut next = 0;
                for t in &order.tiles {
                    assert_eq!(t.start, next, "{size}");
                    assert!(t.end > t.start, "{size}");
                    next = t.end;
                    for p in t.range() {
                        let [i, j] = grid.cell_of(particles.position[p]);
                        assert_eq!(t.coords, [i as u32 / TILE, j as u32 / TILE], "{size}");
                        let cell = NodeBox { columns: [i as u32, i as u32 + 1], rows: [j as u32, j as u32 + 1] };
                        assert!(inside(cell, t.zone()), "{size}");
                        if p > t.start as usize {
                            assert!(particles.id[p] > particles.id[p - 1], "{size}: stable within a tile");
                        }
                    }
                }
                assert_eq!(next as usize, nx * ny, "{size}");
                for c in 0..COLOURS {
                    let same = &order.tiles[order.colour(c)];
                    for (k, t) in same.iter().enumerate() {
                        assert_eq!(t.colour(), c, "{size}");
                        for u in &same[k + 1..] {
                            assert!(!boxes_overlap(t.zone(), u.zone()), "{size}: {:?} {:?}", t.coords, u.coords);
                        }
                    }
                }
            }
        }
    }

    /// `zero_box` zeroes exactly the box's nodes (its columns clipped to the row), and nothing
    /// for an empty box.
    #[test]
    fn zero_box_zeroes_the_boxs_nodes_and_no_other() {
        let (nx, ny) = (7, 6);
        let mut field = vec![1.0f64; nx * ny];
        zero_box(&mut field, nx, NodeBox::EMPTY);
        assert!(field.iter().all(|&v| v == 1.0));
        zero_box(&mut field, nx, NodeBox { columns: [2, 4], rows: [1, 3] });
        zero_box(&mut field, nx, NodeBox { columns: [5, 20], rows: [5, 5] });
        for j in 0..ny {
            for i in 0..nx {
                let zeroed = ((2..=4).contains(&i) && (1..=3).contains(&j)) || (i >= 5 && j == 5);
                assert_eq!(field[j * nx + i], if zeroed { 0.0 } else { 1.0 }, "node ({i}, {j})");
            }
        }
    }

    /// The sort adds the time of its one-thread part to `serial_seconds` (the step's serial
    /// time in the timings): it accumulates, it does not reset or subtract.
    #[test]
    fn sort_adds_its_one_thread_time_to_serial_seconds() {
        let grid = GridGeometry::new([0.0, 0.0], [4.0, 3.0], 0.1);
        let mut particles = Particles { state_stride: 1, ..Default::default() };
        for k in 0..2000u32 {
            let x = [(k as f64 * 0.618_034).fract() * 3.999, (k as f64 * 0.414_214).fract() * 2.999];
            particles.push(x, [0.0; 2], 1.0, 1.0, [0.05; 2], [0.0; 4], 0);
        }
        let mut serial = 1.0;
        sort_particles(&grid, &mut particles, &mut serial);
        let first = serial;
        assert!(first > 1.0 && first < 61.0, "{first}");
        sort_particles(&grid, &mut particles, &mut serial);
        assert!(serial > first && serial < first + 60.0, "{first} then {serial}");
    }
}
