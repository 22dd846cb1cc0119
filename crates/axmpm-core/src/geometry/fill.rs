//! Filling a region with particles: `n × n` lattice points per grid cell, each at the centre of
//! its sub-cell (spacing h/n), kept when the region contains it.

use super::Region;
use crate::grid::GridGeometry;

/// A bound within this fraction of a cell of a grid line counts as on it (the front end's
/// "on a grid line" tolerance).
const ON_GRID_LINE: f64 = 1e-6;

/// Visits the lattice points of `region`, `n` per direction and cell, row by row (cell rows,
/// then sub-rows, then cells, then sub-columns). Only the cells of the region's bounding box
/// (rounded outwards to grid lines, clipped to the grid) are walked; a point is kept when
/// `region.contains` it. A rectangle on grid lines thus fills exactly its cells.
pub fn lattice_points(region: &dyn Region, grid: &GridGeometry, n: usize, mut visit: impl FnMut([f64; 2])) {
    let h = grid.cell_size;
    let spacing = h / n as f64;
    let (lo, hi) = region.bounding_box();
    let cell_range = |d: usize| {
        let first = ((lo[d] - grid.origin[d]) / h + ON_GRID_LINE).floor() as i64;
        let end = ((hi[d] - grid.origin[d]) / h - ON_GRID_LINE).ceil() as i64;
        (first.max(0) as usize)..(end.max(0) as usize).min(grid.cells[d])
    };
    for cj in cell_range(1) {
        for b in 0..n {
            for ci in cell_range(0) {
                for a in 0..n {
                    let x = [
                        grid.origin[0] + ci as f64 * h + (a as f64 + 0.5) * spacing,
                        grid.origin[1] + cj as f64 * h + (b as f64 + 0.5) * spacing,
                    ];
                    if region.contains(x) {
                        visit(x);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Rectangle;

    #[test]
    fn a_rectangle_on_grid_lines_fills_its_cells_in_row_order() {
        let grid = GridGeometry::new([0.0, 0.0], [1.0, 1.0], 0.1);
        // Bounds a few ulps off the grid lines (0.1 · 3 ≠ 0.3) fill the same cells.
        for r in [
            Rectangle { min: [0.2, 0.1], max: [0.5, 0.3] },
            Rectangle { min: [0.1 * 2.0, 0.1 * 1.0], max: [0.1 * 5.0, 0.1 * 3.0] },
            Rectangle { min: [0.2 - 1e-9, 0.1 + 1e-9], max: [0.5 + 1e-9, 0.3 - 1e-9] },
        ] {
            let mut points = Vec::new();
            lattice_points(&r, &grid, 2, |x| points.push(x));
            assert_eq!(points.len(), 3 * 2 * 2 * 2);
            assert!((points[0][0] - 0.225).abs() < 1e-12 && (points[0][1] - 0.125).abs() < 1e-12);
            assert!((points[1][0] - 0.275).abs() < 1e-12 && (points[1][1] - 0.125).abs() < 1e-12);
            assert!((points[6][0] - 0.225).abs() < 1e-12 && (points[6][1] - 0.175).abs() < 1e-12);
        }
        // Clipped to the grid.
        let mut count = 0;
        lattice_points(&Rectangle { min: [0.8, 0.8], max: [1.2, 1.0] }, &grid, 1, |_| count += 1);
        assert_eq!(count, 4);
    }
}
