//! An axis-aligned rectangle `min ≤ x ≤ max` (keys `min`, `max`).

use serde_json::{Map, Value};

use super::{point, Region};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    pub min: [f64; 2],
    pub max: [f64; 2],
}

/// Builds a rectangle from the `min` and `max` keys of a body table.
pub fn build(context: &str, table: &Map<String, Value>) -> Result<Box<dyn Region>, String> {
    let min = point(context, table, "min")?;
    let max = point(context, table, "max")?;
    for d in 0..2 {
        if !(min[d] < max[d]) {
            return Err(format!("{context}.max: must exceed min in both directions (got min {min:?}, max {max:?})"));
        }
    }
    Ok(Box::new(Rectangle { min, max }))
}

/// The body-table keys of a rectangle (`shape`, `min`, `max`), for Rust callers building a
/// configuration.
pub fn table(min: [f64; 2], max: [f64; 2]) -> Map<String, Value> {
    let mut t = Map::new();
    t.insert("shape".into(), Value::from("rectangle"));
    t.insert("min".into(), Value::from(min.to_vec()));
    t.insert("max".into(), Value::from(max.to_vec()));
    t
}

impl Region for Rectangle {
    fn shape(&self) -> &'static str {
        "rectangle"
    }

    fn contains(&self, x: [f64; 2]) -> bool {
        x[0] >= self.min[0] && x[0] <= self.max[0] && x[1] >= self.min[1] && x[1] <= self.max[1]
    }

    fn bounding_box(&self) -> ([f64; 2], [f64; 2]) {
        (self.min, self.max)
    }

    fn area(&self) -> f64 {
        (self.max[0] - self.min[0]) * (self.max[1] - self.min[1])
    }

    /// ∫ r dA = (r₁² − r₀²)/2 · (z₁ − z₀).
    fn radial_moment(&self) -> f64 {
        0.5 * (self.max[0] * self.max[0] - self.min[0] * self.min[0]) * (self.max[1] - self.min[1])
    }

    fn signed_distance(&self, x: [f64; 2]) -> (f64, [f64; 2]) {
        // Distances past each face (positive outside that face).
        let beyond = [self.min[0] - x[0], x[0] - self.max[0], self.min[1] - x[1], x[1] - self.max[1]];
        let normals = [[-1.0, 0.0], [1.0, 0.0], [0.0, -1.0], [0.0, 1.0]];
        let outside = [beyond[0].max(beyond[1]).max(0.0), beyond[2].max(beyond[3]).max(0.0)];
        if outside[0] > 0.0 || outside[1] > 0.0 {
            // Outside: the nearest boundary point is on a face or a corner.
            let q = [
                if beyond[0] > 0.0 { -outside[0] } else { outside[0] },
                if beyond[2] > 0.0 { -outside[1] } else { outside[1] },
            ];
            let d = q[0].hypot(q[1]);
            return (d, [q[0] / d, q[1] / d]);
        }
        // Inside or on the boundary: the nearest face.
        let k = (0..4).fold(0, |k, i| if beyond[i] > beyond[k] { i } else { k });
        (beyond[k], normals[k])
    }

    fn outline(&self) -> super::Polygon {
        let (lo, hi) = (self.min, self.max);
        super::Polygon::new(vec![lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]]).expect("a rectangle with min < max is a simple polygon")
    }

    fn translated(&self, offset: [f64; 2]) -> Box<dyn Region> {
        Box::new(Rectangle {
            min: [self.min[0] + offset[0], self.min[1] + offset[1]],
            max: [self.max[0] + offset[0], self.max[1] + offset[1]],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_by_hand() {
        let r = Rectangle { min: [0.1, 0.0], max: [0.3, 0.5] };
        assert!((r.area() - 0.1).abs() < 1e-15);
        // (0.09 − 0.01)/2 · 0.5 = 0.02
        assert!((r.radial_moment() - 0.02).abs() < 1e-15);
        assert!(r.contains([0.1, 0.5]) && r.contains([0.2, 0.2]) && !r.contains([0.31, 0.2]));
        let moved = r.translated([0.1, -0.2]);
        assert_eq!(moved.bounding_box(), ([0.2, -0.2], [0.4, 0.3]));
    }

    #[test]
    fn signed_distance_and_normal() {
        let r = Rectangle { min: [0.0, 0.0], max: [2.0, 1.0] };
        assert_eq!(r.signed_distance([1.0, 0.2]), (-0.2, [0.0, -1.0]));
        assert_eq!(r.signed_distance([1.9, 0.5]), (-0.10000000000000009, [1.0, 0.0]));
        assert_eq!(r.signed_distance([1.0, 1.5]), (0.5, [0.0, 1.0]));
        assert_eq!(r.signed_distance([-0.5, 0.5]), (0.5, [-1.0, 0.0]));
        let (d, n) = r.signed_distance([3.0, 2.0]);
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
        assert!((n[0] - 0.5f64.sqrt()).abs() < 1e-15 && (n[1] - 0.5f64.sqrt()).abs() < 1e-15);
        let (d, n) = r.signed_distance([-1.0, -1.0]);
        assert!((d - 2f64.sqrt()).abs() < 1e-15 && n[0] < 0.0 && n[1] < 0.0);
    }
}
