//! The dense rectangular background grid: geometry and nodal fields.
//!
//! Nodes are numbered row by row, `node = j * nodes_x + i`, with node (i, j) at
//! `origin + (i h, j h)`. All nodal quantities are per unit thickness (plane strain) or per
//! radian (axisymmetric), so the nodal equation of motion a = f / m is the same in both.

/// Geometry of the grid; cheap to copy into the inner loops.
#[derive(Clone, Copy, Debug)]
pub struct GridGeometry {
    pub origin: [f64; 2],
    pub cell_size: f64,
    pub inverse_cell_size: f64,
    pub cells: [usize; 2],
    pub nodes: [usize; 2],
}

impl GridGeometry {
    pub fn new(origin: [f64; 2], extent: [f64; 2], cell_size: f64) -> Self {
        let cells = [(extent[0] / cell_size).round() as usize, (extent[1] / cell_size).round() as usize];
        Self { origin, cell_size, inverse_cell_size: 1.0 / cell_size, cells, nodes: [cells[0] + 1, cells[1] + 1] }
    }

    #[inline(always)]
    /// The same grid with one more row of cells on top (the moving grid of `grid.follow`).
    pub fn with_extra_row(&self) -> Self {
        let cells = [self.cells[0], self.cells[1] + 1];
        Self { cells, nodes: [cells[0] + 1, cells[1] + 1], ..*self }
    }

    pub fn num_nodes(&self) -> usize {
        self.nodes[0] * self.nodes[1]
    }

    #[inline(always)]
    pub fn node_index(&self, i: usize, j: usize) -> usize {
        j * self.nodes[0] + i
    }

    #[inline(always)]
    pub fn node_position(&self, node: usize) -> [f64; 2] {
        let i = node % self.nodes[0];
        let j = node / self.nodes[0];
        [self.origin[0] + i as f64 * self.cell_size, self.origin[1] + j as f64 * self.cell_size]
    }

    /// Upper corner of the grid.
    #[inline(always)]
    pub fn upper(&self) -> [f64; 2] {
        [
            self.origin[0] + self.cells[0] as f64 * self.cell_size,
            self.origin[1] + self.cells[1] as f64 * self.cell_size,
        ]
    }

    /// Whether a point lies inside the grid (closed box).
    #[inline(always)]
    pub fn contains(&self, x: [f64; 2]) -> bool {
        self.bounds().contains(x)
    }

    /// The grid's closed box with its upper corner computed once, for a loop that tests many
    /// points (the particle update tests every particle).
    #[inline(always)]
    pub fn bounds(&self) -> GridBounds {
        GridBounds { lower: self.origin, upper: self.upper() }
    }

    /// Position in cell units relative to the origin.
    #[inline(always)]
    pub fn local(&self, x: [f64; 2]) -> [f64; 2] {
        [(x[0] - self.origin[0]) * self.inverse_cell_size, (x[1] - self.origin[1]) * self.inverse_cell_size]
    }

    /// Row-major number of the cell containing a point (clamped to the grid),
    /// `j * cells_x + i`.
    #[inline(always)]
    pub fn cell_index(&self, x: [f64; 2]) -> usize {
        let [i, j] = self.cell_of(x);
        j * self.cells[0] + i
    }

    /// Per background cell, Σ_p w_p into `weight_sum` and Σ_p (w a)_p / Σ_p w_p into `mean` (0
    /// in empty cells), over the particles whose centre lies in the cell; `terms` gives
    /// (w_p, w_p a_p) in particle order. The sums run in that order on one thread, so they do
    /// not depend on the thread count.
    pub fn cell_weighted_mean(
        &self,
        positions: &[[f64; 2]],
        terms: impl Iterator<Item = (f64, f64)>,
        weight_sum: &mut [f64],
        mean: &mut [f64],
    ) {
        weight_sum.fill(0.0);
        mean.fill(0.0);
        for (x, (w, weighted)) in positions.iter().zip(terms) {
            let cell = self.cell_index(*x);
            weight_sum[cell] += w;
            mean[cell] += weighted;
        }
        for (m, &w) in mean.iter_mut().zip(weight_sum.iter()) {
            if w > 0.0 {
                *m /= w;
            }
        }
    }

    /// Cell containing a point, clamped to the grid.
    #[inline(always)]
    pub fn cell_of(&self, x: [f64; 2]) -> [usize; 2] {
        let l = self.local(x);
        [
            (l[0].floor().max(0.0) as usize).min(self.cells[0] - 1),
            (l[1].floor().max(0.0) as usize).min(self.cells[1] - 1),
        ]
    }
}

/// The grid's closed box (see [`GridGeometry::bounds`]).
#[derive(Clone, Copy, Debug)]
pub struct GridBounds {
    pub lower: [f64; 2],
    pub upper: [f64; 2],
}

impl GridBounds {
    /// Whether `x` lies in the closed box. `&` instead of `&&`: four comparisons and no
    /// branches (the usual answer is true). A NaN coordinate is outside.
    #[inline(always)]
    pub fn contains(&self, x: [f64; 2]) -> bool {
        (x[0] >= self.lower[0]) & (x[1] >= self.lower[1]) & (x[0] <= self.upper[0]) & (x[1] <= self.upper[1])
    }
}

/// An inclusive box of grid nodes: columns `columns[0] ..= columns[1]`, rows
/// `rows[0] ..= rows[1]`; empty when a lower bound exceeds its upper bound ([`NodeBox::EMPTY`]).
/// A scheme reports the box of each particle's stencil (it may be larger than the entries
/// need); the solver grows the boxes of its lanes from them, so that clearing and summing the
/// nodal buffers costs in proportion to the region the particles reach.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeBox {
    pub columns: [u32; 2],
    pub rows: [u32; 2],
}

impl Default for NodeBox {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl NodeBox {
    pub const EMPTY: Self = Self { columns: [u32::MAX, 0], rows: [u32::MAX, 0] };

    /// The nodes of the cell with lower-left node `cell`, the cell clamped to the grid's cells.
    #[inline(always)]
    pub fn of_cell(grid: &GridGeometry, cell: [i32; 2]) -> Self {
        let i = cell[0].clamp(0, grid.cells[0] as i32 - 1) as u32;
        let j = cell[1].clamp(0, grid.cells[1] as i32 - 1) as u32;
        Self { columns: [i, (i + 1).min(grid.cells[0] as u32)], rows: [j, (j + 1).min(grid.cells[1] as u32)] }
    }

    /// The smallest box containing both.
    #[inline(always)]
    pub fn union(self, other: Self) -> Self {
        Self {
            columns: [self.columns[0].min(other.columns[0]), self.columns[1].max(other.columns[1])],
            rows: [self.rows[0].min(other.rows[0]), self.rows[1].max(other.rows[1])],
        }
    }

    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.columns[0] > self.columns[1] || self.rows[0] > self.rows[1]
    }

    /// Rows of the box as (first row, number of rows), for `skip`/`take` over row chunks.
    #[inline(always)]
    pub fn row_span(&self) -> (usize, usize) {
        if self.is_empty() {
            (0, 0)
        } else {
            (self.rows[0] as usize, (self.rows[1] - self.rows[0]) as usize + 1)
        }
    }

    /// Columns of the box, clipped to a grid row of `nodes_x` nodes.
    #[inline(always)]
    pub fn column_span(&self, nodes_x: usize) -> std::ops::RangeInclusive<usize> {
        self.columns[0] as usize..=(self.columns[1] as usize).min(nodes_x - 1)
    }
}

/// Nodal fields of one step.
#[derive(Clone, Debug)]
pub struct GridFields {
    pub mass: Vec<f64>,
    pub momentum: Vec<[f64; 2]>,
    /// Internal plus external force.
    pub force: Vec<[f64; 2]>,
    /// Velocity at the start of the step (momentum / mass, boundary conditions applied).
    pub velocity: Vec<[f64; 2]>,
    /// Velocity after the momentum update (and after the MUSL re-map, once done).
    pub velocity_new: Vec<[f64; 2]>,
}

impl GridFields {
    pub fn new(num_nodes: usize) -> Self {
        Self {
            mass: vec![0.0; num_nodes],
            momentum: vec![[0.0; 2]; num_nodes],
            force: vec![[0.0; 2]; num_nodes],
            velocity: vec![[0.0; 2]; num_nodes],
            velocity_new: vec![[0.0; 2]; num_nodes],
        }
    }
}
