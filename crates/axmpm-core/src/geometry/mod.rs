//! Body geometry: regions of the plane that a body fills with particles, behind one
//! [`Region`] trait, registered by the name a body's `shape = "..."` selects.
//!
//! Adding a shape = one new file implementing [`Region`] (with a `build` that parses the
//! shape's own keys) plus one line in [`SHAPES`].

use serde_json::{Map, Value};

pub mod fill;
pub mod polygon;
pub mod rectangle;

pub use fill::lattice_points;
pub use polygon::Polygon;
pub use rectangle::Rectangle;

pub trait Region: Send + Sync + std::fmt::Debug {
    /// Registry name, the scenario's `shape = "..."`.
    fn shape(&self) -> &'static str;
    /// Whether the point lies inside the region (closed set).
    fn contains(&self, x: [f64; 2]) -> bool;
    /// Axis-aligned bounding box (min, max).
    fn bounding_box(&self) -> ([f64; 2], [f64; 2]);
    /// In-plane area A, m².
    fn area(&self) -> f64;
    /// First moment about the axis, ∫ r dA, m³ (volume per radian in axisymmetry).
    fn radial_moment(&self) -> f64;
    /// Signed distance to the boundary (negative inside) and the outward unit normal of the
    /// boundary point closest to `x`.
    fn signed_distance(&self, x: [f64; 2]) -> (f64, [f64; 2]);
    /// Returns a copy moved by `offset` (rigid bodies move their region).
    fn translated(&self, offset: [f64; 2]) -> Box<dyn Region>;
    /// The region as a polygon (a rigid body's contact surface).
    fn outline(&self) -> Polygon;
}

/// Builds a region from the keys of a body table (`context` names the table in errors).
pub type RegionBuilder = fn(context: &str, table: &Map<String, Value>) -> Result<Box<dyn Region>, String>;

/// The shapes a body may have: name → builder and the shape's own keys. One line per shape.
pub const SHAPES: &[(&str, RegionBuilder, &[&str])] =
    &[("rectangle", rectangle::build, &["min", "max"]), ("polygon", polygon::build, &["vertices"])];

/// Shape of a body table without a `shape` key.
pub const DEFAULT_SHAPE: &str = "rectangle";

/// Names of the registered shapes, in registry order.
pub fn shape_names() -> Vec<&'static str> {
    SHAPES.iter().map(|(name, _, _)| *name).collect()
}

/// Builds a region from a body table (keys `shape` plus the shape's own keys, e.g.
/// rectangle: `min`, `max`; polygon: `vertices`); errors name `{context}.{key}`.
pub fn build(context: &str, table: &Map<String, Value>) -> Result<Box<dyn Region>, String> {
    let shape = match table.get("shape") {
        None | Some(Value::Null) => DEFAULT_SHAPE,
        Some(Value::String(s)) => s.as_str(),
        Some(other) => return Err(format!("{context}.shape: must be a string (got {other})")),
    };
    match SHAPES.iter().find(|(name, _, _)| *name == shape) {
        Some((_, builder, _)) => builder(context, table),
        None => Err(format!("{context}.shape: unknown shape '{shape}' (known: {})", shape_names().join(", "))),
    }
}

/// The keys of the region of a table (`shape` and the shape's own; an unknown shape has none).
pub fn region_keys(table: &Map<String, Value>) -> Vec<&'static str> {
    let shape = table.get("shape").and_then(Value::as_str).unwrap_or(DEFAULT_SHAPE);
    let own = SHAPES.iter().find(|(name, _, _)| *name == shape).map_or(&[][..], |(_, _, keys)| *keys);
    std::iter::once("shape").chain(own.iter().copied()).collect()
}

/// Reads a point `[x, y]` (m) under `key`.
pub fn point(context: &str, table: &Map<String, Value>, key: &str) -> Result<[f64; 2], String> {
    let value = table.get(key).ok_or_else(|| format!("{context}.{key}: required"))?;
    let coordinates = value.as_array().filter(|a| a.len() == 2).and_then(|a| Some([a[0].as_f64()?, a[1].as_f64()?]));
    match coordinates {
        Some(p) if p.iter().all(|c| c.is_finite()) => Ok(p),
        _ => Err(format!("{context}.{key}: must be a point [x, y] of finite numbers (got {value})")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn table(v: Value) -> Map<String, Value> {
        v.as_object().unwrap().clone()
    }

    #[test]
    fn build_selects_by_shape_and_names_keys_in_errors() {
        let r = build("bodies[0]", &table(json!({"min": [0.0, 0.1], "max": [0.2, 0.4]}))).unwrap();
        assert_eq!(r.shape(), "rectangle");
        assert_eq!(r.bounding_box(), ([0.0, 0.1], [0.2, 0.4]));
        let err = build("bodies[1]", &table(json!({"shape": "circle", "min": [0.0, 0.0]}))).unwrap_err();
        assert_eq!(err, "bodies[1].shape: unknown shape 'circle' (known: rectangle, polygon)");
        let err = build("bodies[0]", &table(json!({"shape": "rectangle", "min": [0.0], "max": [1.0, 1.0]}))).unwrap_err();
        assert!(err.starts_with("bodies[0].min: must be a point"), "{err}");
        let err = build("bodies[0]", &table(json!({"max": [1.0, 1.0]}))).unwrap_err();
        assert_eq!(err, "bodies[0].min: required");
    }
}
