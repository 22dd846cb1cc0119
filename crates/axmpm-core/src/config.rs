//! Engine configuration: the resolved scenario, deserialised from the JSON the Python front end
//! produces (`Scenario.engine_json()`), or built directly in Rust tests.
//!
//! The key names are the scenario file's own (see `docs/architecture.md`); the front end has
//! already range-checked every value, but [`Config::validate`] repeats the checks that would
//! otherwise make the engine misbehave, so Rust callers get a clear error too.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FormulationKind {
    PlaneStrain,
    Axisymmetric,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShapeFunctionKind {
    Linear,
    Ugimp,
    Cpgimp,
    Cpdi2,
}

impl FormulationKind {
    pub const ALL: [Self; 2] = [Self::PlaneStrain, Self::Axisymmetric];

    /// The scenario's name (`simulation.formulation`), the formulation type's own.
    pub fn name(self) -> &'static str {
        use crate::formulation::{Axisymmetric, Formulation, PlaneStrain};
        match self {
            Self::PlaneStrain => PlaneStrain::NAME,
            Self::Axisymmetric => Axisymmetric::NAME,
        }
    }
}

impl ShapeFunctionKind {
    pub const ALL: [Self; 4] = [Self::Linear, Self::Ugimp, Self::Cpgimp, Self::Cpdi2];

    /// The scenario's name (`simulation.shape_function`), the scheme type's own.
    pub fn name(self) -> &'static str {
        use crate::interpolation::{CpGimp, Cpdi2, Linear, ShapeFunction, UGimp};
        match self {
            Self::Linear => Linear::NAME,
            Self::Ugimp => UGimp::NAME,
            Self::Cpgimp => CpGimp::NAME,
            Self::Cpdi2 => Cpdi2::NAME,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum UpdateScheme {
    /// Update stress last, with the momentum re-mapped to the grid first (Sulsky et al. 1995).
    Musl,
    /// Update stress last, with the grid velocities of the momentum update.
    Usl,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct SimulationConfig {
    pub formulation: FormulationKind,
    #[serde(default = "default_shape")]
    pub shape_function: ShapeFunctionKind,
    pub end_time: f64,
    pub output_interval: f64,
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 2],
    #[serde(default)]
    pub gravity_ramp_time: f64,
    /// Fixed time step in seconds; 0 selects `cfl * h / c_max`.
    #[serde(default)]
    pub time_step: f64,
    #[serde(default = "default_cfl")]
    pub cfl: f64,
    #[serde(default = "default_scheme")]
    pub update_scheme: UpdateScheme,
    #[serde(default = "default_flip")]
    pub flip_fraction: f64,
    /// Order m of the XPIC(m) filter that forms the non-FLIP share of the velocity update
    /// (`solver::xpic`): 1 is PIC.
    #[serde(default = "default_xpic_order")]
    pub xpic_order: u32,
    /// Allows the simulation's experimental options (`xpic_order` above 1).
    #[serde(default)]
    pub experimental: bool,
    #[serde(default)]
    pub damping: f64,
    /// Anti-locking: replace each particle's volumetric strain rate by the volume average of
    /// its background cell (mean dilatation / F-bar; see `solver`).
    #[serde(default)]
    pub volumetric_averaging: VolumetricAveraging,
    /// Front-end keys the engine does not need (checkpointing, stop criteria, ...).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

/// How the volumetric part of the velocity gradient is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumetricAveraging {
    /// Each particle's own velocity gradient (standard MPM).
    #[default]
    None,
    /// The volume-weighted mean over the particles of the background cell that contains the
    /// particle (Nagtegaal, Parks & Rice 1974; Coombs et al. 2018 for MPM).
    Cell,
}

fn default_shape() -> ShapeFunctionKind {
    ShapeFunctionKind::Linear
}
fn default_gravity() -> [f64; 2] {
    [0.0, -9.81]
}
fn default_cfl() -> f64 {
    0.4
}
fn default_scheme() -> UpdateScheme {
    UpdateScheme::Musl
}
fn default_flip() -> f64 {
    0.99
}

fn default_xpic_order() -> u32 {
    1
}

/// Why `xpic_order` above 1 needs `simulation.experimental = true` (the front end says the same).
pub const XPIC_IS_EXPERIMENTAL: &str = "orders above 1 are experimental (measured on the cone penetration case, not \
    adopted: docs/studies/cone-rate.md): set simulation.experimental = true to use them";

/// Why `xpic_order` above 1 is refused next to saturated bodies (the front end says the same).
pub const XPIC_WITH_SATURATED: &str = "orders above 1 are not available for saturated (two-phase) runs";

/// The highest XPIC order accepted (each order above 1 costs one more particle pass per step).
pub const MAX_XPIC_ORDER: u32 = 8;

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridConfig {
    #[serde(default)]
    pub origin: [f64; 2],
    pub extent: [f64; 2],
    pub cell_size: f64,
    /// A rigid body the grid follows along y (the moving grid, docs/physics.md §8): the nodes
    /// move with the body's axial displacement, modulo one cell, so the body keeps its place
    /// relative to the node rows and no row ever enters or leaves its contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub follow: Option<String>,
    /// Allows the grid's experimental options (`follow`).
    #[serde(default)]
    pub experimental: bool,
}

/// One material: the `model` (a name of [`crate::material::MODELS`]) and its parameters, which
/// the model reads itself (`crate::material::Parameters`): `density`, `youngs_modulus`,
/// `poisson_ratio`, and the model's own keys.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MaterialConfig {
    pub model: String,
    #[serde(flatten)]
    pub parameters: serde_json::Map<String, serde_json::Value>,
}

impl MaterialConfig {
    /// A material from its model and `(key, value)` parameters, for Rust callers.
    pub fn new(model: &str, parameters: &[(&str, serde_json::Value)]) -> Self {
        Self { model: model.into(), parameters: parameters.iter().map(|(k, v)| (k.to_string(), v.clone())).collect() }
    }

    /// An elastic material (`linear_elastic`, `neo_hookean`) or the elastic part of another.
    pub fn elastic(model: &str, density: f64, youngs_modulus: f64, poisson_ratio: f64) -> Self {
        Self::new(
            model,
            &[
                ("density", density.into()),
                ("youngs_modulus", youngs_modulus.into()),
                ("poisson_ratio", poisson_ratio.into()),
            ],
        )
    }

    /// Sets (or replaces) one parameter.
    pub fn set(&mut self, key: &str, value: impl Into<serde_json::Value>) -> &mut Self {
        self.parameters.insert(key.to_string(), value.into());
        self
    }
}

/// A body's stress at t = 0 (Pa, tension positive).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "InitialStressInput", into = "InitialStressInput")]
pub enum InitialStress {
    /// Stress free.
    Zero,
    /// σ_v from the weight of all material above (and the surcharges), σ_h = K0 σ_v.
    Geostatic,
    /// Uniform, the components [xx, yy, zz, xy] (axisymmetric: [rr, zz, θθ, rz]).
    Given([f64; 4]),
}

/// How a scenario writes [`InitialStress`]: `"zero"`, `"geostatic"`, a table
/// `{ vertical, horizontal }` (σ_yy and σ_xx = σ_zz, no shear) or `{ xx, yy, zz, xy }`.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(untagged)]
enum InitialStressInput {
    Named(InitialStressName),
    VerticalHorizontal { vertical: f64, horizontal: f64 },
    Components { xx: f64, yy: f64, zz: f64, #[serde(default)] xy: f64 },
}

#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum InitialStressName {
    Zero,
    Geostatic,
}

impl TryFrom<InitialStressInput> for InitialStress {
    type Error = String;
    fn try_from(input: InitialStressInput) -> Result<Self, String> {
        let stress = match input {
            InitialStressInput::Named(InitialStressName::Zero) => return Ok(InitialStress::Zero),
            InitialStressInput::Named(InitialStressName::Geostatic) => return Ok(InitialStress::Geostatic),
            InitialStressInput::VerticalHorizontal { vertical, horizontal } => [horizontal, vertical, horizontal, 0.0],
            InitialStressInput::Components { xx, yy, zz, xy } => [xx, yy, zz, xy],
        };
        if stress.iter().all(|c| c.is_finite()) {
            Ok(InitialStress::Given(stress))
        } else {
            Err(format!("initial_stress: the components must be finite numbers in Pa (got {stress:?})"))
        }
    }
}

impl From<InitialStress> for InitialStressInput {
    fn from(stress: InitialStress) -> Self {
        match stress {
            InitialStress::Zero => InitialStressInput::Named(InitialStressName::Zero),
            InitialStress::Geostatic => InitialStressInput::Named(InitialStressName::Geostatic),
            InitialStress::Given([xx, yy, zz, xy]) => InitialStressInput::Components { xx, yy, zz, xy },
        }
    }
}

/// A uniform pressure on a free surface of the material (`[[surcharges]]`): carried by the
/// particles whose upper edge lies on the line y = `level` within `range` of x (r), each
/// loaded with the pressure times its width (× its radius in axisymmetry, per radian) as a
/// dead load, ramped in with gravity (`gravity_ramp_time`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurchargeConfig {
    /// Names the history column NAME.applied_force_y; default `surcharge_<index>`.
    #[serde(default)]
    pub name: Option<String>,
    /// Pa, ≥ 0 (compressive on the surface).
    pub pressure: f64,
    /// Height of the loaded surface, m.
    pub level: f64,
    /// The x (r) range loaded, m; default the whole grid width.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
}

impl SurchargeConfig {
    /// Whether the surcharge covers the abscissa `x`.
    pub fn covers(&self, x: f64) -> bool {
        self.range.is_none_or(|[a, b]| a <= x && x <= b)
    }
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BodyConfig {
    #[serde(default)]
    pub name: Option<String>,
    pub material: String,
    #[serde(default = "default_ppc")]
    pub particles_per_cell: u32,
    #[serde(default)]
    pub velocity: [f64; 2],
    #[serde(default = "default_initial_stress")]
    pub initial_stress: InitialStress,
    /// Lateral earth-pressure ratio for geostatic stress; `None` = ν/(1−ν).
    #[serde(default)]
    pub k0: Option<f64>,
    /// Saturated with pore water (two-phase; `solver::saturated`); `None`: a dry or
    /// total-stress body, computed exactly as without this key.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub saturated: Option<SaturatedConfig>,
    /// The region the body fills: `shape` (default "rectangle") and the shape's own keys
    /// (rectangle: `min`, `max`), read by [`crate::geometry::build`].
    #[serde(flatten)]
    pub region: serde_json::Map<String, serde_json::Value>,
}

impl BodyConfig {
    /// A rectangular body of `material` (2 particles per cell and direction, at rest, stress
    /// free), for Rust callers.
    pub fn rectangle(material: &str, min: [f64; 2], max: [f64; 2]) -> Self {
        Self {
            name: None,
            material: material.into(),
            particles_per_cell: default_ppc(),
            velocity: [0.0; 2],
            initial_stress: default_initial_stress(),
            k0: None,
            saturated: None,
            region: crate::geometry::rectangle::table(min, max),
        }
    }

    /// Makes the body the rectangle `min..max`.
    pub fn set_rectangle(&mut self, min: [f64; 2], max: [f64; 2]) {
        self.region = crate::geometry::rectangle::table(min, max);
    }
}

fn default_ppc() -> u32 {
    2
}
fn default_initial_stress() -> InitialStress {
    InitialStress::Zero
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Condition {
    Free,
    Roller,
    Fixed,
    Friction,
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BoundaryCondition {
    pub condition: Condition,
    #[serde(default)]
    pub coefficient: f64,
}

impl BoundaryCondition {
    pub const FREE: Self = Self { condition: Condition::Free, coefficient: 0.0 };
    pub const ROLLER: Self = Self { condition: Condition::Roller, coefficient: 0.0 };
    pub const FIXED: Self = Self { condition: Condition::Fixed, coefficient: 0.0 };
    pub fn friction(mu: f64) -> Self {
        Self { condition: Condition::Friction, coefficient: mu }
    }
}

impl Default for BoundaryCondition {
    fn default() -> Self {
        Self::FREE
    }
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct BoundariesConfig {
    #[serde(default)]
    pub left: BoundaryCondition,
    #[serde(default)]
    pub right: BoundaryCondition,
    #[serde(default)]
    pub bottom: BoundaryCondition,
    #[serde(default)]
    pub top: BoundaryCondition,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    X,
    Y,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Negative,
    Positive,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct WallConfig {
    pub axis: Axis,
    pub position: f64,
    pub material_side: Side,
    pub condition: Condition,
    #[serde(default)]
    pub coefficient: f64,
    #[serde(default)]
    pub removal_time: Option<f64>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Config {
    pub simulation: SimulationConfig,
    pub grid: GridConfig,
    pub materials: std::collections::BTreeMap<String, MaterialConfig>,
    pub bodies: Vec<BodyConfig>,
    #[serde(default)]
    pub boundaries: BoundariesConfig,
    #[serde(default)]
    pub walls: Vec<WallConfig>,
    /// Rigid bodies with a prescribed motion (`constraint/rigid_body.rs`).
    #[serde(default)]
    pub rigid_bodies: Vec<RigidBodyConfig>,
    /// Uniform pressures on free surfaces ([`SurchargeConfig`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub surcharges: Vec<SurchargeConfig>,
    /// Which grid faces let the pore water out (saturated bodies only; `solver::saturated`).
    #[serde(default, skip_serializing_if = "DrainageConfig::is_default")]
    pub drainage: DrainageConfig,
    /// Any other top-level sections the front end keeps (output, analysis, ...).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

impl Config {
    /// Reads the engine JSON; an error names the key where it arose (`rigid_bodies[0].friction: ...`).
    pub fn from_json(text: &str) -> Result<Self, String> {
        let config: Config = from_json_named(text).map_err(|e| format!("invalid engine configuration: {e}"))?;
        config.validate()?;
        Ok(config)
    }

    /// Whether any body is saturated (pore water; the run then takes the two-phase step).
    pub fn has_saturated_bodies(&self) -> bool {
        self.bodies.iter().any(|b| b.saturated.is_some())
    }

    /// Checks that protect the engine itself; the front end reports the same problems with the
    /// scenario's dotted key names before the engine is ever built.
    pub fn validate(&self) -> Result<(), String> {
        let s = &self.simulation;
        let g = &self.grid;
        if !(g.cell_size > 0.0) {
            return Err(format!("grid.cell_size must be > 0 (got {})", g.cell_size));
        }
        for d in 0..2 {
            let cells = g.extent[d] / g.cell_size;
            if !(cells >= 1.0) || (cells - cells.round()).abs() > 1e-6 * cells.max(1.0) {
                return Err(format!("grid.extent[{d}] must be a whole number (>= 1) of cells (got {} cells)", cells));
            }
        }
        if s.formulation == FormulationKind::Axisymmetric && g.origin[0].abs() > 1e-12 * g.cell_size {
            return Err(format!("grid.origin[0] must be 0 in axisymmetric runs (got {})", g.origin[0]));
        }
        if !(s.end_time > 0.0) || !(s.output_interval > 0.0) {
            return Err("simulation.end_time and simulation.output_interval must be > 0".into());
        }
        if !(s.cfl > 0.0 && s.cfl <= 1.0) {
            return Err(format!("simulation.cfl must be in (0, 1] (got {})", s.cfl));
        }
        if !(s.time_step >= 0.0) {
            return Err(format!("simulation.time_step must be >= 0 (got {})", s.time_step));
        }
        if !(0.0..=1.0).contains(&s.flip_fraction) {
            return Err(format!("simulation.flip_fraction must be in [0, 1] (got {})", s.flip_fraction));
        }
        if !(1..=MAX_XPIC_ORDER).contains(&s.xpic_order) {
            return Err(format!("simulation.xpic_order must be an integer in [1, {MAX_XPIC_ORDER}] (got {})", s.xpic_order));
        }
        if s.xpic_order > 1 && !s.experimental {
            return Err(format!("simulation.xpic_order: {XPIC_IS_EXPERIMENTAL}"));
        }
        if s.xpic_order > 1 && self.has_saturated_bodies() {
            return Err(format!("simulation.xpic_order: {XPIC_WITH_SATURATED}"));
        }
        if !(0.0..1.0).contains(&s.damping) {
            return Err(format!("simulation.damping must be in [0, 1) (got {})", s.damping));
        }
        let tol = 1e-6 * g.cell_size;
        for (i, b) in self.bodies.iter().enumerate() {
            if !self.materials.contains_key(&b.material) {
                return Err(format!("bodies[{i}].material: no material named '{}'", b.material));
            }
            if !(1..=8).contains(&b.particles_per_cell) {
                return Err(format!("bodies[{i}].particles_per_cell must be 1..8 (got {})", b.particles_per_cell));
            }
            let region = crate::geometry::build(&format!("bodies[{i}]"), &b.region)?;
            let (lo, hi) = region.bounding_box();
            for d in 0..2 {
                if lo[d] < g.origin[d] - tol || hi[d] > g.origin[d] + g.extent[d] + tol {
                    return Err(format!("bodies[{i}]: {} {lo:?}..{hi:?} must lie inside the grid", region.shape()));
                }
            }
        }
        if self.bodies.is_empty() {
            return Err("bodies: at least one body is needed".into());
        }
        for (i, b) in self.bodies.iter().enumerate() {
            if b.initial_stress == InitialStress::Geostatic && !(s.gravity[1] < 0.0) {
                return Err(format!(
                    "bodies[{i}].initial_stress: \"geostatic\" needs gravity pointing down \
                     (simulation.gravity[1] < 0, got {}); for weightless soil give the stress, \
                     initial_stress = {{ vertical = ..., horizontal = ... }} (Pa, tension positive)",
                    s.gravity[1]
                ));
            }
        }
        for (i, c) in self.surcharges.iter().enumerate() {
            if !(c.pressure >= 0.0 && c.pressure.is_finite()) {
                return Err(format!("surcharges[{i}].pressure must be a finite number >= 0 Pa (got {})", c.pressure));
            }
            let (bottom, top) = (g.origin[1], g.origin[1] + g.extent[1]);
            if !(c.level >= bottom && c.level <= top) {
                return Err(format!("surcharges[{i}].level must lie in the grid, {bottom}..{top} m (got {})", c.level));
            }
            if let Some([a, b]) = c.range {
                let (left, right) = (g.origin[0], g.origin[0] + g.extent[0]);
                if !(a < b && a >= left - tol && b <= right + tol) {
                    return Err(format!(
                        "surcharges[{i}].range must be [x0, x1] with {left} <= x0 < x1 <= {right} m (got [{a}, {b}])"
                    ));
                }
            }
        }
        validate_saturated(self)?;
        if self.has_saturated_bodies() {
            if let Some(i) = self.rigid_bodies.iter().position(|b| b.contact == ContactKind::Penalty) {
                return Err(format!("rigid_bodies.{i}.contact: {PENALTY_WITH_SATURATED}"));
            }
        }
        if let Some(name) = &g.follow {
            validate_follow(self, name)?;
        }
        Ok(())
    }
}

/// Deserialises `text`; an error names the path of the value that failed (`a.b[2].c: ...`).
pub fn from_json_named<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    let mut reader = serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(&mut reader).map_err(|e| named_error(e.path().to_string(), e.inner()))
}

/// Converts a JSON value; an error names the path as [`from_json_named`] does.
pub fn from_value_named<T: serde::de::DeserializeOwned>(value: &serde_json::Value) -> Result<T, String> {
    serde_path_to_error::deserialize(value).map_err(|e| named_error(e.path().to_string(), e.inner()))
}

/// Converts a JSON value; an error is (the path of the value that failed, "" at the top; the message).
pub fn from_value_at<T: serde::de::DeserializeOwned>(value: &serde_json::Value) -> Result<T, (String, String)> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        (if path == "." { String::new() } else { path }, e.inner().to_string())
    })
}

fn named_error(path: String, inner: &serde_json::Error) -> String {
    if path == "." {
        inner.to_string()
    } else {
        format!("{path}: {inner}")
    }
}

// --------------------------------------------------------------------------- rigid bodies

/// The tangential law of a rigid body's contact (`friction`): Coulomb with coefficient μ ≥ 0
/// (0: smooth), or `"rough"` (no slip while in contact).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "serde_json::Value", into = "serde_json::Value")]
pub enum Friction {
    Coulomb(f64),
    Rough,
}

impl Default for Friction {
    fn default() -> Self {
        Self::Coulomb(0.0)
    }
}

impl TryFrom<serde_json::Value> for Friction {
    type Error = String;
    fn try_from(value: serde_json::Value) -> Result<Self, String> {
        match &value {
            serde_json::Value::String(s) if s == "rough" => Ok(Self::Rough),
            serde_json::Value::Number(n) if n.as_f64().is_some_and(|mu| mu >= 0.0 && mu.is_finite()) => {
                Ok(Self::Coulomb(n.as_f64().unwrap_or(0.0)))
            }
            _ => Err(format!("must be a number >= 0 or \"rough\" (got {value})")),
        }
    }
}

impl From<Friction> for serde_json::Value {
    fn from(f: Friction) -> Self {
        match f {
            Friction::Coulomb(mu) => mu.into(),
            Friction::Rough => "rough".into(),
        }
    }
}

/// How a rigid body's contact is imposed (`contact`; `constraint/rigid_body.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactKind {
    /// Velocity correction at the grid nodes the body covers.
    #[default]
    Nodes,
    /// Penalty pressure on the particles' domain corners inside the body (experimental).
    Penalty,
}

/// One `[[rigid_bodies]]` table. The region's keys (`shape` and the shape's own) are read by
/// [`crate::geometry::build`]; any other key is refused when the body is built
/// (`constraint::RigidBody::from_config`), which also checks the ranges.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RigidBodyConfig {
    /// Names the output columns (`NAME.force_x`).
    pub name: String,
    /// Constant velocity, m/s (or `motion`).
    #[serde(default)]
    pub velocity: Option<[f64; 2]>,
    /// Velocity table rows [t, vx, vy] (s, m/s), linear between rows.
    #[serde(default)]
    pub motion: Option<Vec<[f64; 3]>>,
    /// Mass of a force-driven body, kg (whole body: per metre in plane strain, the whole ring
    /// in axisymmetry; > 0). A body with a mass has no velocity or motion: it moves under
    /// `force`, gravity and the contact reaction.
    #[serde(default)]
    pub mass: Option<f64>,
    /// Force on a force-driven body, rows [t, fx, fy] (s, N in the units of `mass`), linear
    /// between rows, constant before the first and after the last.
    #[serde(default)]
    pub force: Option<Vec<[f64; 3]>>,
    /// Velocity of a force-driven body at t = 0, m/s (default 0).
    #[serde(default)]
    pub initial_velocity: Option<[f64; 2]>,
    #[serde(default)]
    pub friction: Friction,
    #[serde(default)]
    pub contact: ContactKind,
    /// Allows the experimental options (`contact = "penalty"`).
    #[serde(default)]
    pub experimental: bool,
    /// Adhesion a of the interface, Pa (≥ 0): its shear strength is min(μ σ_n + a, a_lim).
    #[serde(default)]
    pub adhesion: f64,
    /// Largest shear stress of the interface a_lim, Pa (> 0; none: unlimited).
    #[serde(default)]
    pub adhesion_limit: Option<f64>,
    /// Named parts of the body's reaction by height ([`RigidBodyPartConfig`]); empty: none
    /// (the base/shaft split by face normal is always reported).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<RigidBodyPartConfig>,
    /// `shape` and the shape's keys (rectangle: `min`, `max`; polygon: `vertices`).
    #[serde(flatten)]
    pub region: serde_json::Map<String, serde_json::Value>,
}

impl RigidBodyConfig {
    /// A body of `region` (its keys, e.g. [`crate::geometry::rectangle::table`]) moving at a
    /// constant `velocity`, smooth, nodal contact (for Rust callers).
    pub fn new(name: &str, region: serde_json::Map<String, serde_json::Value>, velocity: [f64; 2]) -> Self {
        Self {
            name: name.into(),
            velocity: Some(velocity),
            motion: None,
            mass: None,
            force: None,
            initial_velocity: None,
            friction: Friction::default(),
            contact: ContactKind::default(),
            experimental: false,
            adhesion: 0.0,
            adhesion_limit: None,
            parts: Vec::new(),
            region,
        }
    }
}

/// One entry of a rigid body's `parts`: the reaction taken by the covered nodes lower than
/// `below` (m, measured up from the body's lowest point, in the body's own frame: it moves
/// with the body) and not taken by an earlier part goes to the part `name`. What lies above
/// the last part is `rest`. E.g. a cone penetrometer's `tip` below its shoulder and a
/// `sleeve` above it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidBodyPartConfig {
    /// Names the history columns `BODY.NAME_force_x/y`.
    pub name: String,
    /// Upper end of the part, m above the body's lowest point (> 0, increasing along `parts`).
    pub below: f64,
}

// --------------------------------------------------------------------------- saturated soil

fn default_water_bulk_modulus() -> f64 {
    2.2e9
}
fn default_water_density() -> f64 {
    1000.0
}

/// A body's `saturated` table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SaturatedConfig {
    /// Initial porosity n, in (0, 1).
    pub porosity: f64,
    /// Hydraulic conductivity k, m/s (> 0).
    pub hydraulic_conductivity: f64,
    /// Bulk modulus of the pore water K_w, Pa (> 0).
    #[serde(default = "default_water_bulk_modulus")]
    pub water_bulk_modulus: f64,
    /// Density of the pore water ρ_w, kg/m³ (> 0).
    #[serde(default = "default_water_density")]
    pub water_density: f64,
    /// Initial pore pressure hydrostatic below this height (m): p = ρ_w |g_y| (z_w − y), 0 above.
    #[serde(default)]
    pub water_table: Option<f64>,
    /// Initial pore pressure, uniform (Pa); used when `water_table` is not given (default 0).
    #[serde(default)]
    pub pore_pressure: Option<f64>,
    /// A uniform pressure (Pa, ≥ 0) on the body's top surface, carried by its top row of
    /// particles from t = 0 on (the load of a consolidation test).
    #[serde(default)]
    pub surface_load: f64,
    /// The surface load acts through a rigid, frictionless, impermeable plate: the nodes of the
    /// grid row at the loaded surface move vertically together (`solver::saturated`).
    #[serde(default)]
    pub loading_plate: bool,
}

/// What a grid face does to the pore water.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Drainage {
    /// p = 0: the water leaves freely.
    Drained,
    /// No flow through the face: the water's normal velocity is the solid's.
    Impermeable,
}

/// The `drainage` table: one [`Drainage`] per grid face. A face not given is impermeable when
/// it supports the solid (roller, fixed, friction) and drained when free. The symmetry axis
/// and the walls are always impermeable.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrainageConfig {
    #[serde(default)]
    pub left: Option<Drainage>,
    #[serde(default)]
    pub right: Option<Drainage>,
    #[serde(default)]
    pub bottom: Option<Drainage>,
    #[serde(default)]
    pub top: Option<Drainage>,
    /// Faces where the water outside stands at a given pressure (Pa, compression positive):
    /// drained faces with p = this instead of 0.
    #[serde(default)]
    pub pressure: FacePressures,
}

/// A prescribed pore pressure per grid face (`None`: p = 0 where the face is drained).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FacePressures {
    #[serde(default)]
    pub left: Option<f64>,
    #[serde(default)]
    pub right: Option<f64>,
    #[serde(default)]
    pub bottom: Option<f64>,
    #[serde(default)]
    pub top: Option<f64>,
}

impl FacePressures {
    /// [left, right, bottom, top].
    pub fn faces(&self) -> [Option<f64>; 4] {
        [self.left, self.right, self.bottom, self.top]
    }
}

impl DrainageConfig {
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The drainage of each face [left, right, bottom, top], the defaults resolved: a face with
    /// a prescribed pressure is drained.
    pub fn resolve(&self, faces: &BoundariesConfig) -> [Drainage; 4] {
        let default = |c: Condition, p: Option<f64>| {
            if c == Condition::Free || p.is_some() {
                Drainage::Drained
            } else {
                Drainage::Impermeable
            }
        };
        let [pl, pr, pb, pt] = self.pressure.faces();
        [
            self.left.unwrap_or(default(faces.left.condition, pl)),
            self.right.unwrap_or(default(faces.right.condition, pr)),
            self.bottom.unwrap_or(default(faces.bottom.condition, pb)),
            self.top.unwrap_or(default(faces.top.condition, pt)),
        ]
    }
}

/// Range checks of the `saturated` tables, naming the key; one pore water per run; prescribed
/// face pressures finite and on drained faces.
/// Why `grid.follow` needs `grid.experimental = true` (the same words in the front end).
pub const FOLLOW_IS_EXPERIMENTAL: &str = "the moving grid is experimental (measured, not adopted: no load steps and \
    smooth footings converge, but rough bodies and FLIP 0.999 became unstable at B/h = 40; \
    docs/studies/contact-remedies.md): set grid.experimental = true to use it";

/// Why a rigid body's `contact = "penalty"` is refused next to a saturated body (the same words
/// in the front end).
pub const PENALTY_WITH_SATURATED: &str = "\"penalty\" cannot be combined with saturated bodies (the saturated step \
    imposes a rigid body's contact at the nodes): use \"nodes\"";

/// What `grid.follow = follow` is refused for, from what the configuration says: it must name
/// one of `rigid_bodies`, need `experimental`, and nothing else may be tied to fixed node rows
/// (`walls`: a wall's nodes; `saturated`: the drainage faces of saturated soil). A non-local
/// material's fixed cell boundaries are the material registry's to refuse
/// (`crate::material::NONLOCAL_MODELS`). One message per refusal, without the key; the front
/// end shows them all (`axmpm check`), the engine the first.
pub fn follow_errors(follow: &str, experimental: bool, rigid_bodies: &[&str], walls: usize, saturated: bool) -> Vec<String> {
    let mut errors = Vec::new();
    if !experimental {
        errors.push(FOLLOW_IS_EXPERIMENTAL.to_string());
    }
    if !rigid_bodies.contains(&follow) {
        let names: Vec<String> = rigid_bodies.iter().map(|n| format!("'{n}'")).collect();
        let names = if names.is_empty() { "there is none".to_string() } else { names.join(", ") };
        errors.push(format!("must name a rigid body ({names}) (got '{follow}')"));
    }
    if walls > 0 {
        errors.push("cannot be combined with walls (a wall's nodes are fixed): use the grid's faces".into());
    }
    if saturated {
        errors.push("cannot be combined with saturated bodies (their drainage faces are fixed rows)".into());
    }
    errors
}

fn validate_follow(config: &Config, name: &str) -> Result<(), String> {
    let names: Vec<&str> = config.rigid_bodies.iter().map(|b| b.name.as_str()).collect();
    match follow_errors(name, config.grid.experimental, &names, config.walls.len(), config.has_saturated_bodies()).first() {
        Some(error) => Err(format!("grid.follow: {error}")),
        None => Ok(()),
    }
}

fn validate_saturated(config: &Config) -> Result<(), String> {
    let d = &config.drainage;
    let names = ["left", "right", "bottom", "top"];
    let explicit = [d.left, d.right, d.bottom, d.top];
    for ((name, p), given) in names.iter().zip(d.pressure.faces()).zip(explicit) {
        if let Some(p) = p {
            if !p.is_finite() {
                return Err(format!("drainage.pressure.{name} must be finite (got {p})"));
            }
            if given == Some(Drainage::Impermeable) {
                return Err(format!("drainage.pressure.{name}: the face is impermeable; a prescribed pressure needs a drained face"));
            }
        }
    }
    let mut water: Option<(f64, f64)> = None;
    let g = &config.grid;
    for (i, b) in config.bodies.iter().enumerate() {
        let Some(s) = &b.saturated else { continue };
        let key = |k: &str| format!("bodies[{i}].saturated.{k}");
        if !(s.porosity > 0.0 && s.porosity < 1.0) {
            return Err(format!("{} must be in (0, 1) (got {})", key("porosity"), s.porosity));
        }
        if !(s.hydraulic_conductivity > 0.0 && s.hydraulic_conductivity.is_finite()) {
            return Err(format!("{} must be > 0 m/s (got {})", key("hydraulic_conductivity"), s.hydraulic_conductivity));
        }
        if !(s.water_bulk_modulus > 0.0 && s.water_bulk_modulus.is_finite()) {
            return Err(format!("{} must be > 0 Pa (got {})", key("water_bulk_modulus"), s.water_bulk_modulus));
        }
        if !(s.water_density > 0.0 && s.water_density.is_finite()) {
            return Err(format!("{} must be > 0 kg/m³ (got {})", key("water_density"), s.water_density));
        }
        if let Some(z) = s.water_table {
            let (lo, hi) = (g.origin[1], g.origin[1] + g.extent[1]);
            if !(z >= lo && z <= hi) {
                return Err(format!("{} must lie inside the grid, in [{lo}, {hi}] (got {z})", key("water_table")));
            }
            if s.pore_pressure.is_some() {
                return Err(format!("{}: give either water_table or pore_pressure, not both", key("pore_pressure")));
            }
        }
        if let Some(p) = s.pore_pressure {
            if !p.is_finite() {
                return Err(format!("{} must be finite (got {p})", key("pore_pressure")));
            }
        }
        if !(s.surface_load >= 0.0 && s.surface_load.is_finite()) {
            return Err(format!("{} must be >= 0 Pa (got {})", key("surface_load"), s.surface_load));
        }
        match water {
            None => water = Some((s.water_bulk_modulus, s.water_density)),
            Some(w) if w != (s.water_bulk_modulus, s.water_density) => {
                return Err(format!(
                    "{}, {}: every saturated body holds the same pore water (got K_w, ρ_w = {:?} and {:?})",
                    key("water_bulk_modulus"),
                    key("water_density"),
                    w,
                    (s.water_bulk_modulus, s.water_density)
                ))
            }
            Some(_) => {}
        }
    }
    Ok(())
}

