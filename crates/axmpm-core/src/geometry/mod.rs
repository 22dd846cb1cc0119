//! Regions of the (x, y) / (r, z) plane that bodies and rigid bodies occupy.
//!
//! LOCAL COPY of the trait fixed in INTERFACES.md (branch `ssi`, issue #13): the layout issue
//! (#12, branch rust-layout) owns this file; at the merge its version is taken and only the
//! polygon's registry line is added to it.

pub mod polygon;

pub use polygon::Polygon;

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
}

type Builder = fn(&str, &serde_json::Map<String, serde_json::Value>) -> Result<Box<dyn Region>, String>;

/// One line per shape.
const SHAPES: &[(&str, Builder)] = &[("polygon", polygon::build)];

/// Builds a region from a body table (keys `shape` plus the shape's own keys, e.g.
/// rectangle: `min`, `max`; polygon: `vertices`); errors name `{context}.{key}`.
pub fn build(context: &str, table: &serde_json::Map<String, serde_json::Value>) -> Result<Box<dyn Region>, String> {
    let shape = match table.get("shape") {
        Some(serde_json::Value::String(s)) => s.as_str(),
        Some(other) => return Err(format!("{context}.shape: must be a string (got {other})")),
        None => return Err(format!("{context}.shape: is required")),
    };
    match SHAPES.iter().find(|(name, _)| *name == shape) {
        Some((_, builder)) => builder(context, table),
        None => {
            let known: Vec<&str> = SHAPES.iter().map(|(n, _)| *n).collect();
            Err(format!("{context}.shape: unknown shape '{shape}' (known: {})", known.join(", ")))
        }
    }
}
