//! The cell pass of the nonlocal fluidity: the five-point Laplacian of the cell-averaged
//! fluidity, ∇²ḡ = S − D ḡ, which the model reads through [`super::super::Kinematics::cell_field`]
//! (the solver runs [`CellLaplacian::compute`] at the start of each step for a model whose
//! [`super::super::Material::cell_field`] asks for it).
//!
//! Finite-volume form over the background cells: ḡ = Σ V g / Σ V of the particles whose centre
//! lies in a cell, and across each face of a cell that holds material
//!
//! * to a cell that holds material: weight 1 on both (S gains w ḡ_neighbour, D gains w);
//! * to a cell behind a rough boundary (fixed or frictional face or wall): g = 0 on the face,
//!   the mirror value −ḡ (D gains 2w, S nothing) — grains at a rough wall cannot move
//!   cooperatively with the flow (Henann & Kamrin 2013);
//! * to anything else (an empty cell: the free surface; a smooth wall; the axis): no flux,
//!
//! all over h². In axisymmetry a radial face weighs its radius over the cell's,
//! (1/r) ∂/∂r (r ∂g/∂r), with r = x (the axis on x = 0).

use crate::config::{Axis, BoundariesConfig, Condition, Side, WallConfig};
use crate::formulation::Formulation;
use crate::grid::GridGeometry;
use crate::particles::Particles;

use super::super::{CellField, Material};

/// The boundary condition of the fluidity equation: g = 0 on rough boundaries, ∂g/∂n = 0
/// elsewhere (free surfaces, smooth walls, the axis).
#[derive(Clone, Debug, Default)]
pub struct FluidityBoundary {
    /// The grid's faces [left, right, bottom, top] that are rough.
    pub rough_faces: [bool; 4],
    /// Per background cell: the cell lies behind a rough wall (on its side away from the
    /// material); empty when no wall is rough.
    pub rough_wall_cells: Vec<bool>,
}

impl FluidityBoundary {
    /// The grid faces and the walls that are rough (fixed or frictional; walls removed during
    /// the run are left out, as are roller faces and walls, and the axis in axisymmetry).
    pub fn new(grid: &GridGeometry, faces: &BoundariesConfig, walls: &[WallConfig], axisymmetric: bool) -> Self {
        let rough = |c: Condition| matches!(c, Condition::Fixed | Condition::Friction);
        let rough_faces = [
            rough(faces.left.condition) && !axisymmetric,
            rough(faces.right.condition),
            rough(faces.bottom.condition),
            rough(faces.top.condition),
        ];
        let walls: Vec<_> = walls.iter().filter(|w| rough(w.condition) && w.removal_time.is_none()).collect();
        let mut rough_wall_cells = Vec::new();
        if !walls.is_empty() {
            let [nx, ny] = grid.cells;
            rough_wall_cells = vec![false; nx * ny];
            for j in 0..ny {
                for i in 0..nx {
                    let centre =
                        [grid.origin[0] + (i as f64 + 0.5) * grid.cell_size, grid.origin[1] + (j as f64 + 0.5) * grid.cell_size];
                    rough_wall_cells[j * nx + i] = walls.iter().any(|w| {
                        let x = centre[match w.axis {
                            Axis::X => 0,
                            Axis::Y => 1,
                        }];
                        match w.material_side {
                            Side::Positive => x < w.position,
                            Side::Negative => x > w.position,
                        }
                    });
                }
            }
        }
        Self { rough_faces, rough_wall_cells }
    }
}

/// The cell arrays of the Laplacian (allocated once with the run) and what they are taken of.
#[derive(Clone, Debug, Default)]
pub struct CellLaplacian {
    /// Per material, the state slot averaged per cell (`None`: the material takes no part).
    slots: Vec<Option<usize>>,
    boundary: FluidityBoundary,
    /// Per background cell: Σ V, the V-weighted mean ḡ, the neighbours' weighted sum S and the
    /// cell's own weight D (both over h²; 0 in empty cells).
    volume: Vec<f64>,
    mean: Vec<f64>,
    neighbour_sum: Vec<f64>,
    diagonal: Vec<f64>,
}

impl CellLaplacian {
    /// The cell pass for `materials` on `grid`, or `None` when no material asks for it;
    /// `boundary` is built only then.
    pub fn of(materials: &[Box<dyn Material>], grid: &GridGeometry, boundary: impl FnOnce() -> FluidityBoundary)
              -> Option<Self> {
        let slots: Vec<Option<usize>> = materials
            .iter()
            .map(|m| match m.cell_field() {
                Some(CellField::Laplacian { slot }) => Some(slot),
                None => None,
            })
            .collect();
        slots.iter().any(Option::is_some).then(|| Self::new(slots, grid.cells[0] * grid.cells[1], boundary()))
    }

    fn new(slots: Vec<Option<usize>>, cells: usize, boundary: FluidityBoundary) -> Self {
        Self {
            slots,
            boundary,
            volume: vec![0.0; cells],
            mean: vec![0.0; cells],
            neighbour_sum: vec![0.0; cells],
            diagonal: vec![0.0; cells],
        }
    }

    /// [S, D] of background cell `cell`: ∇²ḡ = S − D ḡ there.
    #[inline(always)]
    pub fn at(&self, cell: usize) -> [f64; 2] {
        [self.neighbour_sum[cell], self.diagonal[cell]]
    }

    /// ḡ per cell from the particles' state, then S and D per cell (module doc). Sums in
    /// particle order on one thread: independent of the thread count.
    pub fn compute<F: Formulation>(&mut self, grid: &GridGeometry, particles: &Particles) {
        let Self { slots, boundary, volume, mean, neighbour_sum, diagonal } = self;
        let stride = particles.state_stride;
        let terms = particles.volume.iter().zip(&particles.material).enumerate().map(|(p, (&v, &id))| {
            match slots[id as usize] {
                Some(k) => (v, v * particles.state[p * stride + k]),
                None => (0.0, 0.0),
            }
        });
        grid.cell_weighted_mean(&particles.position, terms, volume, mean);
        let [nx, ny] = grid.cells;
        let h = grid.cell_size;
        let inverse_area = 1.0 / (h * h);
        let walls = &boundary.rough_wall_cells;
        for j in 0..ny {
            for i in 0..nx {
                let c = j * nx + i;
                if !(volume[c] > 0.0) {
                    neighbour_sum[c] = 0.0;
                    diagonal[c] = 0.0;
                    continue;
                }
                // One face of weight `w` to the neighbour `neighbour` inside the grid, or beyond
                // the grid's face `face`: (the neighbour's share of S, the share of D).
                let across = |neighbour: Option<usize>, face: usize, w: f64| -> (f64, f64) {
                    match neighbour {
                        Some(n) if volume[n] > 0.0 => (w * mean[n], w),
                        Some(n) if !walls.is_empty() && walls[n] => (0.0, 2.0 * w),
                        Some(_) => (0.0, 0.0),
                        None if boundary.rough_faces[face] => (0.0, 2.0 * w),
                        None => (0.0, 0.0),
                    }
                };
                // Face radii over the centre radius, (x_c ∓ h/2) / x_c, in axisymmetry.
                let (w_west, w_east) = if F::AXISYMMETRIC {
                    let r = grid.origin[0] + (i as f64 + 0.5) * h;
                    ((r - 0.5 * h) / r, (r + 0.5 * h) / r)
                } else {
                    (1.0, 1.0)
                };
                let faces = [
                    across((i > 0).then(|| c - 1), 0, w_west),
                    across((i + 1 < nx).then_some(c + 1), 1, w_east),
                    across((j > 0).then(|| c - nx), 2, 1.0),
                    across((j + 1 < ny).then_some(c + nx), 3, 1.0),
                ];
                neighbour_sum[c] = (faces[0].0 + faces[1].0 + faces[2].0 + faces[3].0) * inverse_area;
                diagonal[c] = (faces[0].1 + faces[1].1 + faces[2].1 + faces[3].1) * inverse_area;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::BoundaryCondition;
    use crate::formulation::{Axisymmetric, PlaneStrain};

    /// Particles at the centres of the cells `occupied` of `grid` (two per cell, volumes 1 and 3),
    /// material 0 with fluidity `g(centre)` in state slot 1 (of 3); a third particle of
    /// material 1 (no fluidity) in every occupied cell, with a fluidity slot value that must be
    /// ignored.
    fn fluidity_cloud(grid: &GridGeometry, occupied: impl Fn(usize, usize) -> bool, g: impl Fn([f64; 2]) -> f64) -> Particles {
        let mut particles = Particles { state_stride: 3, ..Default::default() };
        let h = grid.cell_size;
        for j in 0..grid.cells[1] {
            for i in 0..grid.cells[0] {
                if occupied(i, j) {
                    let x = [grid.origin[0] + (i as f64 + 0.5) * h, grid.origin[1] + (j as f64 + 0.5) * h];
                    for (volume, material) in [(1.0, 0), (3.0, 0), (5.0, 1)] {
                        particles.push(x, [0.0; 2], 1.0, volume, [0.25 * h; 2], [0.0; 4], material);
                        let n = particles.len();
                        particles.state[(n - 1) * 3 + 1] = if material == 0 { g(x) } else { 1e9 };
                    }
                }
            }
        }
        particles
    }

    /// ∇²ḡ = S − D ḡ per cell from [`CellLaplacian::compute`], with material 0 averaging slot 1
    /// and material 1 taking no part; the arrays start filled with garbage that must be
    /// overwritten.
    fn laplacian_of<F: Formulation>(grid: &GridGeometry, particles: &Particles, boundary: &FluidityBoundary) -> Vec<f64> {
        let cells = grid.cells[0] * grid.cells[1];
        let mut laplacian = CellLaplacian::new(vec![Some(1), None], cells, boundary.clone());
        for field in [&mut laplacian.volume, &mut laplacian.mean, &mut laplacian.neighbour_sum, &mut laplacian.diagonal] {
            field.fill(7.0);
        }
        laplacian.compute::<F>(grid, particles);
        assert!(laplacian.volume.iter().all(|&v| v == 0.0 || v == 4.0), "only the fluidity material's volume counts");
        (0..cells)
            .map(|c| {
                let [s, d] = laplacian.at(c);
                if laplacian.volume[c] > 0.0 {
                    s - d * laplacian.mean[c]
                } else {
                    assert_eq!((s, d), (0.0, 0.0));
                    0.0
                }
            })
            .collect()
    }

    #[test]
    fn fluidity_laplacian_is_exact_for_quadratics_in_both_formulations() {
        // Plane strain: g = x² + 2y² + xy has ∇²g = 6; axisymmetric: g = r² + 2z² has
        // (1/r)(r g_r)_r + g_zz = 4 + 4 = 8; both exact for the finite-volume five-point form.
        let grid = GridGeometry::new([0.0, 0.0], [0.8, 0.6], 0.1);
        let everywhere = |_: usize, _: usize| true;
        let boundary = FluidityBoundary::default();
        let plane = fluidity_cloud(&grid, everywhere, |x| x[0] * x[0] + 2.0 * x[1] * x[1] + x[0] * x[1]);
        let axi = fluidity_cloud(&grid, everywhere, |x| x[0] * x[0] + 2.0 * x[1] * x[1]);
        let l_plane = laplacian_of::<PlaneStrain>(&grid, &plane, &boundary);
        let l_axi = laplacian_of::<Axisymmetric>(&grid, &axi, &boundary);
        for j in 1..5 {
            for i in 1..7 {
                let c = j * 8 + i;
                assert!((l_plane[c] - 6.0).abs() < 1e-9, "plane ({i}, {j}): {}", l_plane[c]);
                assert!((l_axi[c] - 8.0).abs() < 1e-9, "axisymmetric ({i}, {j}): {}", l_axi[c]);
            }
        }
        // At the axis (i = 0) the face radius is 0: no flux through it, and the radial term is
        // still exact for r² ((r + h/2)(g_E − g_C) / (r h²) = (h)(2h²)/(h/2 · h²) = 4).
        for j in 1..5 {
            assert!((l_axi[j * 8] - 8.0).abs() < 1e-9, "axis cell row {j}: {}", l_axi[j * 8]);
        }
    }

    #[test]
    fn fluidity_boundaries_free_surface_rough_face_and_rough_wall() {
        // A uniform field has no Laplacian next to empty cells (free surface) or a smooth grid
        // face; a rough face or wall holds g = 0 on the face: the mirror value −ḡ, flux −2ḡ/h².
        let grid = GridGeometry::new([0.0, 0.0], [0.5, 0.4], 0.1); // 5 × 4 cells
        let h2 = 0.01;
        let block = |i: usize, j: usize| i < 3 && j < 2;
        let particles = fluidity_cloud(&grid, block, |_| 2.0);
        let free = laplacian_of::<PlaneStrain>(&grid, &particles, &FluidityBoundary::default());
        assert!(free.iter().all(|&l| l == 0.0), "{free:?}");
        // Rough bottom face: the bottom row of the block loses 2ḡ/h² = 400; empty cells stay 0.
        let bottom = FluidityBoundary { rough_faces: [false, false, true, false], ..Default::default() };
        let l = laplacian_of::<PlaneStrain>(&grid, &particles, &bottom);
        for c in 0..20 {
            let expected = if c < 3 { -2.0 * 2.0 / h2 } else { 0.0 };
            assert!((l[c] - expected).abs() < 1e-9, "cell {c}: {} vs {expected}", l[c]);
        }
        // Left face rough too (plane strain), and a rough wall behind the block's right side
        // (cells i ≥ 3 of rows 0–1 marked): the corner cell (0, 0) loses two faces' worth.
        let mut wall_cells = vec![false; 20];
        for c in [3, 4, 8, 9] {
            wall_cells[c] = true;
        }
        let sides = FluidityBoundary { rough_faces: [true, false, false, false], rough_wall_cells: wall_cells };
        let l = laplacian_of::<PlaneStrain>(&grid, &particles, &sides);
        let face = -2.0 * 2.0 / h2;
        for (c, expected) in [(0, face), (1, 0.0), (2, face), (5, face), (6, 0.0), (7, face), (10, 0.0), (12, 0.0)] {
            assert!((l[c] - expected).abs() < 1e-9, "cell {c}: {} vs {expected}", l[c]);
        }
        // A neighbour with material carries its own mean: raise cell (1, 0) to 5 → cells (0, 0)
        // and (2, 0) gain (5 − 2)/h², and (1, 0) loses that to each of its three neighbours.
        let particles = fluidity_cloud(&grid, block, |x| if x[0] > 0.1 && x[0] < 0.2 && x[1] < 0.1 { 5.0 } else { 2.0 });
        let l = laplacian_of::<PlaneStrain>(&grid, &particles, &FluidityBoundary::default());
        assert!((l[0] - 3.0 / h2).abs() < 1e-9 && (l[1] + 3.0 * 3.0 / h2).abs() < 1e-9 && (l[2] - 3.0 / h2).abs() < 1e-9, "{:?}", &l[..3]);
    }

    #[test]
    fn axisymmetric_rough_boundaries_weigh_the_face_by_its_radius() {
        // In axisymmetry a radial face of radius r_f counts r_f / r_c: a rough wall or grid face
        // to the east of a cell centred at r_c removes 2ḡ (r_c + h/2)/(r_c h²).
        let grid = GridGeometry::new([0.0, 0.0], [0.5, 0.2], 0.1); // 5 × 2 cells
        let h2 = 0.01;
        let east = |i: f64| (i + 1.0) / (i + 0.5); // (r_c + h/2) / r_c at r_c = (i + ½) h
        // The block fills cells i ≤ 1 behind a rough wall over i ≥ 2.
        let particles = fluidity_cloud(&grid, |i, _| i < 2, |_| 2.0);
        let mut wall_cells = vec![false; 10];
        for c in [2, 3, 4, 7, 8, 9] {
            wall_cells[c] = true;
        }
        let wall = FluidityBoundary { rough_faces: [false; 4], rough_wall_cells: wall_cells };
        let l = laplacian_of::<Axisymmetric>(&grid, &particles, &wall);
        for (c, expected) in [(0, 0.0), (1, -2.0 * 2.0 * east(1.0) / h2), (5, 0.0), (6, -2.0 * 2.0 * east(1.0) / h2)] {
            assert!((l[c] - expected).abs() < 1e-9, "wall, cell {c}: {} vs {expected}", l[c]);
        }
        // The whole grid filled, its right face rough: the last column (i = 4) loses 2ḡ r_f/r_c.
        let particles = fluidity_cloud(&grid, |_, _| true, |_| 2.0);
        let right = FluidityBoundary { rough_faces: [false, true, false, false], ..Default::default() };
        let l = laplacian_of::<Axisymmetric>(&grid, &particles, &right);
        for (c, expected) in [(3, 0.0), (4, -2.0 * 2.0 * east(4.0) / h2), (9, -2.0 * 2.0 * east(4.0) / h2)] {
            assert!((l[c] - expected).abs() < 1e-9, "face, cell {c}: {} vs {expected}", l[c]);
        }
    }

    fn wall(axis: Axis, position: f64, material_side: Side, condition: Condition, removal_time: Option<f64>) -> WallConfig {
        WallConfig { axis, position, material_side, condition, coefficient: 0.3, removal_time }
    }

    #[test]
    fn fluidity_boundary_marks_rough_faces_and_the_cells_behind_rough_walls() {
        // 8 × 5 cells of 0.25 m from (0.5, 1.0): cell centres x = 0.625 + 0.25 i, y = 1.125 +
        // 0.25 j, exact in binary, so a wall through a centre tests the strict comparisons.
        let grid = GridGeometry::new([0.5, 1.0], [2.0, 1.25], 0.25);
        assert_eq!(grid.cells, [8, 5]);
        let faces = BoundariesConfig {
            left: BoundaryCondition::FIXED,
            right: BoundaryCondition::ROLLER,
            bottom: BoundaryCondition::friction(0.4),
            top: BoundaryCondition::FREE,
        };
        let walls = [
            // Material on the positive side of x = 1.125 (the centre of column i = 2): columns
            // 0 and 1 lie behind it.
            wall(Axis::X, 1.125, Side::Positive, Condition::Fixed, None),
            // Material below y = 1.875 (the centre of row j = 3): row 4 lies behind it.
            wall(Axis::Y, 1.875, Side::Negative, Condition::Friction, None),
            // Smooth, or removed during the run: not rough.
            wall(Axis::X, 2.0, Side::Negative, Condition::Roller, None),
            wall(Axis::Y, 1.3, Side::Positive, Condition::Fixed, Some(0.0)),
        ];
        let plane = FluidityBoundary::new(&grid, &faces, &walls, false);
        assert_eq!(plane.rough_faces, [true, false, true, false]);
        let behind: Vec<bool> = (0..5).flat_map(|j| (0..8).map(move |i| i < 2 || j == 4)).collect();
        assert_eq!(plane.rough_wall_cells, behind);
        // In axisymmetry the left face is the axis, never rough.
        let axisymmetric = FluidityBoundary::new(&grid, &faces, &walls, true);
        assert_eq!(axisymmetric.rough_faces, [false, false, true, false]);
        assert_eq!(axisymmetric.rough_wall_cells, behind);
        // Without a rough wall the cell list stays empty; the faces alone.
        let smooth =
            FluidityBoundary::new(&grid, &BoundariesConfig { right: BoundaryCondition::FIXED, ..faces.clone() }, &walls[2..], false);
        assert_eq!(smooth.rough_faces, [true, true, true, false]);
        assert!(smooth.rough_wall_cells.is_empty());
        let top = BoundariesConfig { top: BoundaryCondition::friction(0.2), left: BoundaryCondition::FREE, ..faces.clone() };
        assert_eq!(FluidityBoundary::new(&grid, &top, &[], false).rough_faces, [false, false, true, true]);
    }

    #[test]
    fn only_a_model_that_asks_gets_the_cell_pass() {
        use crate::material::{GranularFluidity, LinearElastic};
        let grid = GridGeometry::new([0.0, 0.0], [0.5, 0.4], 0.1);
        let elastic: Vec<Box<dyn Material>> = vec![Box::new(LinearElastic::new(1000.0, 1e6, 0.3))];
        assert!(CellLaplacian::of(&elastic, &grid, || panic!("no boundary without the pass")).is_none());
        let mixed: Vec<Box<dyn Material>> = vec![
            Box::new(LinearElastic::new(1000.0, 1e6, 0.3)),
            Box::new(GranularFluidity::new(1550.0, 1e6, 0.3, 0.38, 0.94, 0.48, 1e-3, 2500.0)),
        ];
        let pass = CellLaplacian::of(&mixed, &grid, FluidityBoundary::default).unwrap();
        assert_eq!(pass.slots, [None, Some(super::super::FLUIDITY_SLOT)]);
        assert_eq!(pass.volume.len(), 20);
        assert_eq!(pass.at(19), [0.0, 0.0]);
    }
}
