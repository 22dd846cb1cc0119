//! Simple polygons: `shape = "polygon"`, `vertices = [[x, y], ...]` (issue #13).
//!
//! Any orientation is accepted (the vertices are stored counter-clockwise); the polygon closes
//! itself (a last vertex repeating the first is dropped). Rejected, with a message naming
//! `{context}.vertices`: fewer than three vertices, non-finite coordinates, repeated consecutive
//! vertices, zero area, an edge folding back onto the previous one, and edges that cross or touch
//! anywhere but at their shared vertex (the polygon must be simple).
//!
//! Geometry (A = area, CCW vertices (x_i, y_i), c_i = x_i y_{i+1} − x_{i+1} y_i):
//! A = ½ Σ c_i, ∫ x dA = (1/6) Σ (x_i + x_{i+1}) c_i (the first moment; per radian the volume of
//! the body of revolution in axisymmetry). Inside test: crossing number (even–odd rule), closed
//! by a boundary tolerance of 1e-12 × the bounding-box diagonal. Signed distance: the nearest
//! point over all edges; the outward normal there is the edge's outward normal on an edge's
//! interior, and the direction from the nearest point to `x` (outside) or from `x` to it (inside)
//! at a vertex, so around a convex corner it turns continuously; on the boundary itself at a vertex
//! it is the normalised sum of the two edge normals.

use super::Region;

#[derive(Clone, Debug)]
pub struct Polygon {
    /// Vertices, counter-clockwise.
    vertices: Vec<[f64; 2]>,
    /// Outward unit normal of edge i (vertex i → vertex i + 1).
    normals: Vec<[f64; 2]>,
    bounding_box: ([f64; 2], [f64; 2]),
    area: f64,
    radial_moment: f64,
    /// Distance below which a point counts as on the boundary.
    tolerance: f64,
}

#[inline(always)]
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline(always)]
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline(always)]
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// (b − a) × (c − a): > 0 when c lies left of the line a → b.
#[inline(always)]
fn orientation(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    cross(sub(b, a), sub(c, a))
}

impl Polygon {
    /// Validates and builds a polygon; the error is the message after `{context}.vertices: `.
    pub fn new(mut vertices: Vec<[f64; 2]>) -> Result<Self, String> {
        if vertices.iter().any(|v| !(v[0].is_finite() && v[1].is_finite())) {
            return Err("every vertex must be a pair of finite numbers [x, y]".into());
        }
        if vertices.len() > 3 && vertices.first() == vertices.last() {
            vertices.pop();
        }
        let n = vertices.len();
        if n < 3 {
            return Err(format!("a polygon needs at least 3 vertices (got {n})"));
        }
        let (lo, hi) = bounds(&vertices);
        let diagonal = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
        // Orientation values are products of two lengths: compare them with the squared scale.
        let eps = 1e-12 * diagonal * diagonal;
        for i in 0..n {
            let j = (i + 1) % n;
            if vertices[i] == vertices[j] {
                return Err(format!("vertices {i} and {j} coincide at {:?} (degenerate edge)", vertices[i]));
            }
        }
        // Simple: adjacent edges must not fold back, others must not meet at all.
        for i in 0..n {
            let (a, b, c) = (vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
            if orientation(a, b, c).abs() <= eps && dot(sub(b, a), sub(c, b)) < 0.0 {
                return Err(format!(
                    "edges {i} and {} fold back onto each other at vertex {} {:?} (degenerate)",
                    (i + 1) % n,
                    (i + 1) % n,
                    b
                ));
            }
        }
        for i in 0..n {
            for j in i + 2..n {
                if i == 0 && j == n - 1 {
                    continue; // adjacent through the closing vertex
                }
                let (p1, p2) = (vertices[i], vertices[(i + 1) % n]);
                let (p3, p4) = (vertices[j], vertices[(j + 1) % n]);
                if segments_meet(p1, p2, p3, p4, eps) {
                    return Err(format!(
                        "edges {i} ({p1:?} → {p2:?}) and {j} ({p3:?} → {p4:?}) intersect: the polygon must be simple (not self-intersecting)"
                    ));
                }
            }
        }
        let twice_area: f64 = (0..n).map(|i| cross(vertices[i], vertices[(i + 1) % n])).sum();
        if !(twice_area.abs() > eps) {
            return Err("the polygon has zero area (degenerate: collinear vertices)".into());
        }
        if twice_area < 0.0 {
            vertices.reverse();
        }
        Ok(Self::from_counter_clockwise(vertices, diagonal))
    }

    /// Builds the derived data of already validated counter-clockwise vertices.
    fn from_counter_clockwise(vertices: Vec<[f64; 2]>, diagonal: f64) -> Self {
        let n = vertices.len();
        let mut twice_area = 0.0;
        let mut moment6 = 0.0;
        let mut normals = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (vertices[i], vertices[(i + 1) % n]);
            let c = cross(a, b);
            twice_area += c;
            moment6 += (a[0] + b[0]) * c;
            let e = sub(b, a);
            let length = e[0].hypot(e[1]);
            // Counter-clockwise: the interior is on the left, the outward normal on the right.
            normals.push([e[1] / length, -e[0] / length]);
        }
        Self {
            bounding_box: bounds(&vertices),
            vertices,
            normals,
            area: 0.5 * twice_area,
            radial_moment: moment6 / 6.0,
            tolerance: 1e-12 * diagonal,
        }
    }

    /// Vertices, counter-clockwise.
    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices
    }

    /// The union of this polygon and its mirror image about the vertical line x = `axis`, when
    /// the polygon lies at x ≥ axis and has an edge on that line (a body against a symmetry
    /// plane or the axis of revolution): the half model's own edge on the axis is not a surface.
    /// `None` when there is no such edge or the union is not a simple polygon.
    pub fn mirrored_about(&self, axis: f64) -> Option<Polygon> {
        let n = self.vertices.len();
        let tol = self.tolerance;
        let on_axis = |k: usize| (self.vertices[k % n][0] - axis).abs() <= tol;
        if self.bounding_box.0[0] < axis - tol {
            return None;
        }
        // An edge k → k + 1 on the axis whose next edge leaves it: the chain starts at k + 1.
        let start = (0..n).find(|&k| on_axis(k) && on_axis(k + 1) && !on_axis(k + 2))? + 1;
        // Walk forward to the first vertex back on the axis: the chain off the axis.
        let mut chain = vec![[axis, self.vertices[start % n][1]]];
        let mut k = start + 1;
        while !on_axis(k) {
            chain.push(self.vertices[k % n]);
            k += 1;
        }
        let end = [axis, self.vertices[k % n][1]];
        // Every other vertex must lie on the axis run, else the polygon meets the axis twice.
        if (k - start) + 1 < n && (k + 1..start + n).any(|j| !on_axis(j)) {
            return None;
        }
        let interior: Vec<[f64; 2]> = chain[1..].to_vec();
        chain.push(end);
        chain.extend(interior.iter().rev().map(|v| [2.0 * axis - v[0], v[1]]));
        Polygon::new(chain).ok()
    }

    /// The faces a point inside (or on) the polygon is nearest to, for contact: the signed
    /// distance, the outward normal of the nearest edge (an edge normal, also on a vertex), and
    /// the outward normal of the nearest other edge (with another normal) if that edge is
    /// within the distance `within` of the point (at a corner, the other face).
    pub fn nearest_faces(&self, x: [f64; 2], within: f64) -> (f64, [f64; 2], Option<[f64; 2]>) {
        let n = self.vertices.len();
        let mut nearest = (f64::INFINITY, 0usize);
        let mut second: Option<(f64, usize)> = None;
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let e = sub(b, a);
            let t = (dot(sub(x, a), e) / dot(e, e)).clamp(0.0, 1.0);
            let d = sub(x, [a[0] + t * e[0], a[1] + t * e[1]]);
            let distance = dot(d, d).sqrt();
            if distance < nearest.0 {
                if nearest.0 <= within && dot(self.normals[nearest.1], self.normals[i]) < 1.0 - 1e-12 {
                    second = Some(nearest);
                }
                nearest = (distance, i);
            } else if distance <= within
                && second.is_none_or(|(sd, _)| distance < sd)
                && dot(self.normals[nearest.1], self.normals[i]) < 1.0 - 1e-12
            {
                second = Some((distance, i));
            }
        }
        let inside = self.crossing_inside(x);
        let signed = if inside { -nearest.0 } else { nearest.0 };
        let first = self.normals[nearest.1];
        let other = second
            .filter(|&(d, i)| d <= within && dot(self.normals[i], first) < 1.0 - 1e-12)
            .map(|(_, i)| self.normals[i]);
        (signed, first, other)
    }

    /// The stretch of a face that a point `x` represents, for the tractions of a contact: on
    /// the edge with outward normal `normal` nearest to `x` (the nearest edge when none has
    /// it), the part from `band[0]` before to `band[1]` after the projection of `x` along the
    /// edge (its direction is (−n_y, n_x), counter-clockwise) and at first coordinate ≥ `min_x`.
    /// Returns (its length, ∫ x₀ ds over it): the area per metre, and per radian in axisymmetry.
    pub fn face_band(&self, x: [f64; 2], normal: [f64; 2], band: [f64; 2], min_x: f64) -> (f64, f64) {
        let n = self.vertices.len();
        let Some((i, _)) = self.face_with_normal(x, normal) else { return (0.0, 0.0) };
        let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
        let e = sub(b, a);
        let length = dot(e, e).sqrt();
        let u = [e[0] / length, e[1] / length];
        let s = dot(sub(x, a), u);
        let (mut lo, mut hi) = ((s - band[0]).max(0.0), (s + band[1]).min(length));
        // Keep the part at x₀ ≥ min_x (x₀ is linear in the arc length s).
        if u[0] != 0.0 {
            let s_min = (min_x - a[0]) / u[0];
            if u[0] > 0.0 {
                lo = lo.max(s_min);
            } else {
                hi = hi.min(s_min);
            }
        } else if a[0] < min_x {
            return (0.0, 0.0);
        }
        if !(hi > lo) {
            return (0.0, 0.0);
        }
        let mid = a[0] + 0.5 * (lo + hi) * u[0];
        (hi - lo, (hi - lo) * mid)
    }

    /// The point of a face nearest to `x`, on the edge with outward normal `normal` nearest to
    /// `x` (the nearest edge when none has it): where a contact correction along `normal` at `x`
    /// acts on the body.
    pub fn foot_on_face(&self, x: [f64; 2], normal: [f64; 2]) -> [f64; 2] {
        self.face_with_normal(x, normal).map_or(x, |(_, foot)| foot)
    }

    /// The edge with outward normal `normal` nearest to `x` (the nearest edge when none has it)
    /// and the point of it nearest to `x`; `None` for a polygon without edges.
    fn face_with_normal(&self, x: [f64; 2], normal: [f64; 2]) -> Option<(usize, [f64; 2])> {
        let n = self.vertices.len();
        let mut best: Option<(bool, f64, usize, [f64; 2])> = None;
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let e = sub(b, a);
            let t = (dot(sub(x, a), e) / dot(e, e)).clamp(0.0, 1.0);
            let foot = [a[0] + t * e[0], a[1] + t * e[1]];
            let d = sub(x, foot);
            let key = (dot(self.normals[i], normal) > 1.0 - 1e-9, dot(d, d));
            let better = match best {
                None => true,
                Some((matches, distance, _, _)) => (key.0 && !matches) || (key.0 == matches && key.1 < distance),
            };
            if better {
                best = Some((key.0, key.1, i, foot));
            }
        }
        best.map(|(_, _, i, foot)| (i, foot))
    }

    /// Crossing-number test (even–odd rule), boundary not included reliably.
    #[inline]
    fn crossing_inside(&self, x: [f64; 2]) -> bool {
        let n = self.vertices.len();
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            if (a[1] > x[1]) != (b[1] > x[1]) {
                let crossing = a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if x[0] < crossing {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Nearest boundary point: (distance, the point, edge index, parameter along the edge in [0, 1]).
    #[inline]
    fn nearest(&self, x: [f64; 2]) -> (f64, [f64; 2], usize, f64) {
        let n = self.vertices.len();
        let mut best = (f64::INFINITY, [0.0; 2], 0, 0.0);
        let mut best_sq = f64::INFINITY;
        for i in 0..n {
            let (a, b) = (self.vertices[i], self.vertices[(i + 1) % n]);
            let e = sub(b, a);
            let t = (dot(sub(x, a), e) / dot(e, e)).clamp(0.0, 1.0);
            let p = [a[0] + t * e[0], a[1] + t * e[1]];
            let d = sub(x, p);
            let sq = dot(d, d);
            if sq < best_sq {
                best_sq = sq;
                best = (0.0, p, i, t);
            }
        }
        best.0 = best_sq.sqrt();
        best
    }
}

fn bounds(vertices: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for v in vertices {
        for d in 0..2 {
            lo[d] = lo[d].min(v[d]);
            hi[d] = hi[d].max(v[d]);
        }
    }
    (lo, hi)
}

/// Whether the closed segments p1p2 and p3p4 share a point (orientation tolerance `eps`).
fn segments_meet(p1: [f64; 2], p2: [f64; 2], p3: [f64; 2], p4: [f64; 2], eps: f64) -> bool {
    let d1 = orientation(p3, p4, p1);
    let d2 = orientation(p3, p4, p2);
    let d3 = orientation(p1, p2, p3);
    let d4 = orientation(p1, p2, p4);
    let opposite = |a: f64, b: f64| (a > eps && b < -eps) || (a < -eps && b > eps);
    if opposite(d1, d2) && opposite(d3, d4) {
        return true;
    }
    // Touching or collinear overlap: an end point on the other segment.
    let on = |a: [f64; 2], b: [f64; 2], p: [f64; 2], d: f64| {
        d.abs() <= eps
            && p[0] >= a[0].min(b[0]) - 1e-12 * (a[0] - b[0]).abs().max(1.0)
            && p[0] <= a[0].max(b[0]) + 1e-12 * (a[0] - b[0]).abs().max(1.0)
            && p[1] >= a[1].min(b[1]) - 1e-12 * (a[1] - b[1]).abs().max(1.0)
            && p[1] <= a[1].max(b[1]) + 1e-12 * (a[1] - b[1]).abs().max(1.0)
    };
    on(p3, p4, p1, d1) || on(p3, p4, p2, d2) || on(p1, p2, p3, d3) || on(p1, p2, p4, d4)
}

impl Region for Polygon {
    fn shape(&self) -> &'static str {
        "polygon"
    }

    fn contains(&self, x: [f64; 2]) -> bool {
        let (lo, hi) = self.bounding_box;
        let tol = self.tolerance;
        if x[0] < lo[0] - tol || x[0] > hi[0] + tol || x[1] < lo[1] - tol || x[1] > hi[1] + tol {
            return false;
        }
        self.crossing_inside(x) || self.nearest(x).0 <= tol
    }

    fn bounding_box(&self) -> ([f64; 2], [f64; 2]) {
        self.bounding_box
    }

    fn area(&self) -> f64 {
        self.area
    }

    fn radial_moment(&self) -> f64 {
        self.radial_moment
    }

    fn signed_distance(&self, x: [f64; 2]) -> (f64, [f64; 2]) {
        let (distance, p, edge, t) = self.nearest(x);
        let inside = self.crossing_inside(x);
        let signed = if inside { -distance } else { distance };
        let n = self.vertices.len();
        let at_vertex = t == 0.0 || t == 1.0;
        let normal = if !at_vertex {
            self.normals[edge]
        } else if distance > self.tolerance {
            let d = sub(x, p);
            let s = if inside { -1.0 } else { 1.0 } / distance;
            [s * d[0], s * d[1]]
        } else {
            // On a vertex: the bisector of its two edges' outward normals.
            let (before, after) = if t == 0.0 { ((edge + n - 1) % n, edge) } else { (edge, (edge + 1) % n) };
            let (a, b) = (self.normals[before], self.normals[after]);
            let s = [a[0] + b[0], a[1] + b[1]];
            let length = s[0].hypot(s[1]);
            if length > 0.0 {
                [s[0] / length, s[1] / length]
            } else {
                a
            }
        };
        (signed, normal)
    }

    fn outline(&self) -> Polygon {
        self.clone()
    }

    fn translated(&self, offset: [f64; 2]) -> Box<dyn Region> {
        let vertices: Vec<[f64; 2]> = self.vertices.iter().map(|v| [v[0] + offset[0], v[1] + offset[1]]).collect();
        Box::new(Self::from_counter_clockwise(vertices, self.tolerance * 1e12))
    }
}

/// `shape = "polygon"`: reads `vertices`.
pub fn build(
    context: &str,
    table: &serde_json::Map<String, serde_json::Value>,
) -> Result<Box<dyn Region>, String> {
    from_table(context, table).map(|p| Box::new(p) as Box<dyn Region>)
}

/// The polygon of a table's `vertices` (errors name `{context}.vertices`).
pub fn from_table(context: &str, table: &serde_json::Map<String, serde_json::Value>) -> Result<Polygon, String> {
    let key = format!("{context}.vertices");
    let list = match table.get("vertices") {
        Some(serde_json::Value::Array(list)) => list,
        Some(other) => return Err(format!("{key}: must be a list of [x, y] pairs (got {other})")),
        None => return Err(format!("{key}: is required for shape = \"polygon\"")),
    };
    let mut vertices = Vec::with_capacity(list.len());
    for (i, v) in list.iter().enumerate() {
        let pair = v.as_array().filter(|a| a.len() == 2).and_then(|a| Some([a[0].as_f64()?, a[1].as_f64()?]));
        match pair {
            Some(p) => vertices.push(p),
            None => return Err(format!("{key}[{i}]: must be a pair of numbers [x, y] (got {v})")),
        }
    }
    Polygon::new(vertices).map_err(|e| format!("{key}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(vertices: serde_json::Value) -> serde_json::Map<String, serde_json::Value> {
        let serde_json::Value::Object(m) = serde_json::json!({"shape": "polygon", "vertices": vertices}) else {
            unreachable!()
        };
        m
    }

    /// An L-shaped hexagon (non-convex), clockwise as given: area 3, ∫x dA = 2.5.
    fn ell() -> Polygon {
        Polygon::new(vec![[0.0, 0.0], [0.0, 2.0], [1.0, 2.0], [1.0, 1.0], [2.0, 1.0], [2.0, 0.0]]).unwrap()
    }

    #[test]
    fn area_moment_and_box_of_an_l_shape_in_either_orientation() {
        let cw = ell();
        let mut v = cw.vertices().to_vec();
        v.reverse();
        for p in [cw, Polygon::new(v).unwrap()] {
            assert_eq!(p.shape(), "polygon");
            assert!((p.area() - 3.0).abs() < 1e-14);
            // [0, 1] × [0, 2] (area 2, centroid x = 0.5) plus [1, 2] × [0, 1] (area 1, x = 1.5).
            assert!((p.radial_moment() - (2.0 * 0.5 + 1.0 * 1.5)).abs() < 1e-14);
            assert_eq!(p.bounding_box(), ([0.0, 0.0], [2.0, 2.0]));
        }
    }

    #[test]
    fn contains_is_closed_and_respects_the_notch() {
        let p = ell();
        for x in [[0.5, 0.5], [0.5, 1.5], [1.5, 0.5], [0.0, 0.0], [1.0, 1.5], [2.0, 0.5], [1.5, 1.0], [1.0, 1.0]] {
            assert!(p.contains(x), "{x:?} inside or on the boundary");
        }
        for x in [[1.5, 1.5], [1.0 + 1e-9, 1.0 + 1e-9], [-1e-9, 0.5], [2.5, 0.5], [0.5, 2.0 + 1e-9]] {
            assert!(!p.contains(x), "{x:?} outside");
        }
    }

    #[test]
    fn signed_distance_and_outward_normal() {
        let p = ell();
        let check = |x: [f64; 2], d: f64, n: [f64; 2]| {
            let (gd, gn) = p.signed_distance(x);
            assert!((gd - d).abs() < 1e-14 && (gn[0] - n[0]).abs() < 1e-14 && (gn[1] - n[1]).abs() < 1e-14,
                    "{x:?}: got ({gd}, {gn:?}), want ({d}, {n:?})");
        };
        check([0.5, 0.25], -0.25, [0.0, -1.0]); // nearest the base
        check([0.5, -0.5], 0.5, [0.0, -1.0]);
        check([1.75, 0.5], -0.25, [1.0, 0.0]);
        check([1.5, 1.25], 0.25, [0.0, 1.0]); // above the notch floor
        check([1.25, 1.5], 0.25, [1.0, 0.0]); // right of the notch wall
        // Outside a convex corner: the normal points from the corner to the point.
        let s = 0.5f64.sqrt();
        check([2.0 + 0.3, -0.3], 0.3 * 2f64.sqrt(), [s, -s]);
        // Inside near the re-entrant corner (1, 1): nearest is the corner, normal towards it.
        check([0.9, 0.9], -0.1 * 2f64.sqrt(), [s, s]);
        // On a vertex: the bisector.
        check([2.0, 0.0], 0.0, [s, -s]);
        // |∇d| = 1 away from the medial axis (finite differences of the distance).
        let h = 1e-6;
        for x in [[0.3, 0.7], [2.4, 1.6], [-0.3, 2.2], [1.3, 1.8]] {
            let (d, n) = p.signed_distance(x);
            let gx = (p.signed_distance([x[0] + h, x[1]]).0 - d) / h;
            let gy = (p.signed_distance([x[0], x[1] + h]).0 - d) / h;
            assert!((gx - n[0]).abs() < 1e-5 && (gy - n[1]).abs() < 1e-5, "{x:?}: ∇d = ({gx}, {gy}), n = {n:?}");
        }
    }

    /// The particle lattice (points at sub-cell centres, kept when `contains`) fills the
    /// polygon's area up to the cells its boundary cuts: |N s² − A| ≤ perimeter × s.
    #[test]
    fn lattice_points_inside_fill_the_area() {
        let p = Polygon::new(vec![[0.1, 0.2], [2.3, 0.4], [1.1, 1.9], [0.7, 0.9]]).unwrap();
        let perimeter: f64 = (0..4)
            .map(|i| {
                let (a, b) = (p.vertices()[i], p.vertices()[(i + 1) % 4]);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .sum();
        for s in [0.1, 0.02, 0.004] {
            let n = (2.5 / s) as usize;
            let count = (0..n * n)
                .filter(|k| p.contains([((k % n) as f64 + 0.5) * s, ((k / n) as f64 + 0.5) * s]))
                .count();
            let error = (count as f64 * s * s - p.area()).abs();
            assert!(error <= perimeter * s, "spacing {s}: {} vs {}", count as f64 * s * s, p.area());
        }
    }

    #[test]
    fn mirroring_about_the_axis_removes_the_axis_edge() {
        // Pile with a conical tip, against the axis x = 0 (clockwise as given).
        let pile = Polygon::new(vec![[0.0, 1.0], [0.25, 1.0], [0.25, 0.4], [0.0, 0.2]]).unwrap();
        let both = pile.mirrored_about(0.0).expect("has an axis edge");
        assert!((both.area() - 2.0 * pile.area()).abs() < 1e-14);
        assert!(both.radial_moment().abs() < 1e-14);
        // On the axis inside the pile the nearest surface is the tip or the top, not the axis.
        let (d, n) = both.signed_distance([0.0, 0.3]);
        assert!(d < -0.05 && n[1] < -0.5, "({d}, {n:?})");
        assert!(pile.signed_distance([0.0, 0.3]).0.abs() < 1e-14, "the half model puts the axis at distance 0");
        // Off the axis nothing changes.
        for x in [[0.2, 0.5], [0.3, 0.9], [0.1, 0.1]] {
            let (a, b) = (pile.signed_distance(x), both.signed_distance(x));
            assert!((a.0 - b.0).abs() < 1e-14 && (a.1[0] - b.1[0]).abs() < 1e-14, "{x:?}");
        }
        // A rectangle with three vertices on the axis (collinear run) mirrors too.
        let r = Polygon::new(vec![[0.0, 0.0], [0.5, 0.0], [0.5, 1.0], [0.0, 1.0], [0.0, 0.5]]).unwrap();
        let m = r.mirrored_about(0.0).unwrap();
        assert_eq!(m.bounding_box(), ([-0.5, 0.0], [0.5, 1.0]));
        // Not touching the axis, or crossing it: no mirror.
        assert!(ell().mirrored_about(-1.0).is_none());
        assert!(ell().mirrored_about(1.0).is_none());
    }

    #[test]
    fn nearest_faces_reports_both_faces_at_a_corner() {
        let p = Polygon::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]).unwrap();
        let (_, n, second) = p.nearest_faces([0.999, 0.0005], 1.5e-3);
        assert_eq!(n, [0.0, -1.0]);
        assert_eq!(second, Some([1.0, 0.0]));
        let (_, n, second) = p.nearest_faces([0.9, 0.0005], 1.5e-3);
        assert_eq!((n, second), ([0.0, -1.0], None));
    }

    /// The foot of a point on the nearest edge with a given normal, clamped to the edge: on the
    /// L-shape the two upward faces y = 2 (x in [0, 1]) and y = 1 (x in [1, 2]) are chosen by
    /// distance; a normal no edge has falls back to the nearest edge.
    #[test]
    fn foot_on_face_by_hand() {
        let p = ell();
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
        let cases = [
            ([1.8, 1.5], [0.0, 1.0], [1.8, 1.0]),  // y = 1 face 0.5 away, y = 2 face 0.94
            ([0.5, 2.3], [0.0, 1.0], [0.5, 2.0]),
            ([0.9, 0.8], [0.0, -1.0], [0.9, 0.0]), // inside: the base, though the corner (1, 1) is nearer
            ([2.5, -0.5], [0.0, -1.0], [2.0, 0.0]), // clamped to the base's end
            ([2.3, 1.4], [0.6, 0.8], [2.0, 1.0]),  // no such normal: the nearest edge (the corner)
        ];
        for (x, normal, want) in cases {
            let got = p.foot_on_face(x, normal);
            assert!(close(got, want), "{x:?} {normal:?}: {got:?}");
        }
    }

    #[test]
    fn translated_moves_everything() {
        let p = ell();
        let q = p.translated([3.0, -1.0]);
        assert_eq!(q.bounding_box(), ([3.0, -1.0], [5.0, 1.0]));
        assert!((q.area() - 3.0).abs() < 1e-14);
        assert!((q.radial_moment() - (p.radial_moment() + 3.0 * 3.0)).abs() < 1e-12);
        for x in [[0.5, 0.5], [1.5, 1.5], [2.3, -0.3]] {
            let (a, b) = (p.signed_distance(x), q.signed_distance([x[0] + 3.0, x[1] - 1.0]));
            assert!((a.0 - b.0).abs() < 1e-14 && (a.1[0] - b.1[0]).abs() < 1e-14 && (a.1[1] - b.1[1]).abs() < 1e-14);
            assert_eq!(p.contains(x), q.contains([x[0] + 3.0, x[1] - 1.0]));
        }
    }

    #[test]
    fn bad_polygons_are_rejected_naming_the_key() {
        let err = |v: serde_json::Value| build("rigid_bodies[0]", &table(v)).err().expect("must be rejected");
        let bow_tie = err(serde_json::json!([[0, 0], [1, 1], [1, 0], [0, 1]]));
        assert!(bow_tie.starts_with("rigid_bodies[0].vertices: ") && bow_tie.contains("simple"), "{bow_tie}");
        assert!(err(serde_json::json!([[0, 0], [1, 0]])).contains("at least 3"));
        assert!(err(serde_json::json!([[0, 0], [1, 0], [2, 0]])).contains("degenerate"));
        assert!(err(serde_json::json!([[0, 0], [1, 0], [1, 0], [0, 1]])).contains("coincide"));
        // Spike: an edge going back along the previous one.
        assert!(err(serde_json::json!([[0, 0], [2, 0], [1, 0], [1, 1]])).contains("fold back"));
        // A vertex touching a non-adjacent edge.
        assert!(err(serde_json::json!([[0, 0], [2, 0], [2, 2], [1, 0], [0, 2]])).contains("simple"));
        assert!(err(serde_json::json!([[0, 0], [1, "a"], [0, 1]])).contains("vertices[1]"));
        assert!(err(serde_json::json!("square")).contains("list of [x, y]"));
        let missing = build("bodies[2]", &serde_json::Map::from_iter([("shape".into(), "polygon".into())]));
        assert!(missing.err().unwrap().starts_with("bodies[2].vertices"));
        assert!(super::super::build("b", &serde_json::Map::from_iter([("shape".into(), "blob".into())]))
            .err()
            .unwrap()
            .contains("b.shape"));
        // A closing vertex repeating the first is accepted (dropped).
        let closed = build("b", &table(serde_json::json!([[0, 0], [1, 0], [1, 1], [0, 0]]))).unwrap();
        assert!((closed.area() - 0.5).abs() < 1e-15);
    }
}
