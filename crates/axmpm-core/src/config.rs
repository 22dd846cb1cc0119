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

#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridConfig {
    #[serde(default)]
    pub origin: [f64; 2],
    pub extent: [f64; 2],
    pub cell_size: f64,
}

/// One material, tagged by `model`. Each model reads the fields it needs.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct MaterialConfig {
    pub model: String,
    pub density: f64,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    #[serde(default)]
    pub friction_angle: Option<f64>,
    #[serde(default)]
    pub dilation_angle: Option<f64>,
    #[serde(default)]
    pub cohesion: Option<f64>,
    #[serde(default)]
    pub tension_cutoff: Option<f64>,
    /// Mohr–Coulomb: separated (apex / tension-cut-off) material re-compacts stress-free before
    /// it carries compression again (`None` = the model's default).
    #[serde(default)]
    pub recompaction: Option<bool>,
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialStress {
    Zero,
    Geostatic,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct BodyConfig {
    #[serde(default)]
    pub name: Option<String>,
    pub material: String,
    #[serde(default = "default_body_shape")]
    pub shape: String,
    pub min: [f64; 2],
    pub max: [f64; 2],
    #[serde(default = "default_ppc")]
    pub particles_per_cell: u32,
    #[serde(default)]
    pub velocity: [f64; 2],
    #[serde(default = "default_initial_stress")]
    pub initial_stress: InitialStress,
    /// Lateral earth-pressure ratio for geostatic stress; `None` = ν/(1−ν).
    #[serde(default)]
    pub k0: Option<f64>,
}

fn default_body_shape() -> String {
    "rectangle".into()
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
    /// Any other top-level sections the front end keeps (output, analysis, ...).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
}

impl Config {
    pub fn from_json(text: &str) -> Result<Self, String> {
        let config: Config = serde_json::from_str(text).map_err(|e| format!("invalid engine configuration: {e}"))?;
        config.validate()?;
        Ok(config)
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
            for d in 0..2 {
                if !(b.min[d] < b.max[d]) || b.min[d] < g.origin[d] - tol || b.max[d] > g.origin[d] + g.extent[d] + tol {
                    return Err(format!("bodies[{i}]: rectangle {:?}..{:?} must lie inside the grid", b.min, b.max));
                }
            }
        }
        if self.bodies.is_empty() {
            return Err("bodies: at least one body is needed".into());
        }
        Ok(())
    }
}
