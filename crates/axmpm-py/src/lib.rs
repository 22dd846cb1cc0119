//! `axmpm._core`: thin PyO3 bindings of the engine. Arrays come out as numpy copies; the GIL
//! is released while the engine steps.

use numpy::{IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

use axmpm_core::config::MaterialConfig;
use axmpm_core::material::{self, Kinematics};
use axmpm_core::Simulation;

create_exception!(_core, SimulationFailure, PyRuntimeError, "The run produced an invalid state.");

#[pyclass(name = "Simulation", module = "axmpm._core")]
struct PySimulation {
    inner: Simulation,
}

fn rows<'py, const K: usize>(py: Python<'py>, data: impl Iterator<Item = [f64; K]>, n: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let mut flat = Vec::with_capacity(n * K);
    for row in data {
        flat.extend_from_slice(&row);
    }
    flat.into_pyarray(py).reshape([n, K])
}

#[pymethods]
impl PySimulation {
    /// Simulation(config_json, threads=0): builds a run from the resolved scenario JSON.
    #[new]
    #[pyo3(signature = (config_json, threads = 0))]
    fn new(py: Python<'_>, config_json: &str, threads: usize) -> PyResult<Self> {
        let inner = py.detach(|| Simulation::from_json(config_json, threads)).map_err(PyValueError::new_err)?;
        Ok(Self { inner })
    }

    /// Restores a checkpoint written by `to_bytes`.
    #[staticmethod]
    #[pyo3(signature = (data, threads = 0))]
    fn from_bytes(data: &[u8], threads: usize) -> PyResult<Self> {
        Simulation::from_bytes(data, threads).map(|inner| Self { inner }).map_err(PyValueError::new_err)
    }

    fn to_bytes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let data = self.inner.to_bytes().map_err(PyRuntimeError::new_err)?;
        Ok(PyBytes::new(py, &data))
    }

    /// advance(until, max_steps) -> steps taken. Stops at `until` exactly or after `max_steps`.
    fn advance(&mut self, py: Python<'_>, until: f64, max_steps: u64) -> PyResult<u64> {
        let inner = &mut self.inner;
        py.detach(|| inner.advance(until, max_steps)).map_err(|f| SimulationFailure::new_err(f.to_string()))
    }

    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }
    #[getter]
    fn steps(&self) -> u64 {
        self.inner.steps()
    }
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt()
    }
    #[getter]
    fn threads(&self) -> usize {
        self.inner.threads()
    }
    #[getter]
    fn num_particles(&self) -> usize {
        self.inner.particles_in_solver_order().len()
    }
    #[getter]
    fn num_nodes(&self) -> usize {
        self.inner.grid().num_nodes()
    }
    #[getter]
    fn grid_shape(&self) -> (usize, usize) {
        let n = self.inner.grid().nodes;
        (n[0], n[1])
    }
    #[getter]
    fn bytes_per_particle(&self) -> usize {
        self.inner.bytes_per_particle()
    }

    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.position);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.velocity);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    fn initial_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.initial_position);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    /// (N, 4): [xx, yy, zz, xy] plane strain, [rr, zz, θθ, rz] axisymmetric.
    fn stresses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.stress);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    /// (N, 5): [F11, F12, F21, F22, F33].
    fn deformation_gradients<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.deformation_gradient);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    /// (N, 8): corners [x1, y1, ..., x4, y4] counter-clockwise (CPDI2; empty otherwise).
    fn corners<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.corners);
        let n = v.len();
        rows(py, v.iter().map(|c| [c[0][0], c[0][1], c[1][0], c[1][1], c[2][0], c[2][1], c[3][0], c[3][1]]), n)
    }
    /// (N,) pore pressure, Pa, positive in compression (saturated runs; empty otherwise).
    fn pore_pressures<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.particle_values(|p| &p.pore_pressure).into_pyarray(py)
    }
    /// (N,) porosity (saturated runs; empty otherwise).
    fn porosities<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.particle_values(|p| &p.porosity).into_pyarray(py)
    }
    /// (N, 2) pore water velocity, m/s (saturated runs; empty otherwise).
    fn water_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let v = self.inner.particle_values(|p| &p.water_velocity);
        let n = v.len();
        rows(py, v.into_iter(), n)
    }
    fn volumes<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.particle_values(|p| &p.volume).into_pyarray(py)
    }
    fn initial_volumes<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.particle_values(|p| &p.initial_volume).into_pyarray(py)
    }
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.inner.particle_values(|p| &p.mass).into_pyarray(py)
    }
    fn material_ids<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<i32>> {
        self.inner.particle_values(|p| &p.material).iter().map(|&m| m as i32).collect::<Vec<_>>().into_pyarray(py)
    }
    fn material_names(&self) -> Vec<String> {
        self.inner.material_names().to_vec()
    }
    fn state_names(&self) -> Vec<String> {
        self.inner.state_names().to_vec()
    }
    /// (N, len(state_names())).
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let n = self.inner.particles_in_solver_order().len();
        let k = self.inner.state_names().len();
        self.inner.state_table().into_pyarray(py).reshape([n, k])
    }
    /// The energy budget of the whole body (axisymmetric: × 2π), J: kinetic_energy,
    /// gravity_work (potential energy released), elastic_energy, plastic_work,
    /// boundary_normal_dissipation, boundary_friction_dissipation (with the slip at the rigid
    /// bodies' interfaces), rigid_body_work (the work the rigid bodies did on the material), in
    /// saturated runs water_kinetic_energy and drag_dissipation, and energy_residual
    /// (gravity_work plus rigid_body_work minus all the others: what the scheme lost).
    fn energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = self.inner.energies();
        let d = PyDict::new(py);
        d.set_item("kinetic_energy", e.kinetic_energy)?;
        d.set_item("gravity_work", e.gravity_work)?;
        d.set_item("elastic_energy", e.elastic_energy)?;
        d.set_item("plastic_work", e.plastic_work)?;
        d.set_item("boundary_normal_dissipation", e.boundary_normal_dissipation)?;
        d.set_item("boundary_friction_dissipation", e.boundary_friction_dissipation)?;
        d.set_item("rigid_body_work", e.rigid_body_work)?;
        if self.inner.water_outflow().is_some() {
            d.set_item("water_kinetic_energy", e.water_kinetic_energy)?;
            d.set_item("drag_dissipation", e.drag_dissipation)?;
        }
        d.set_item("energy_residual", e.residual())?;
        Ok(d)
    }
    /// Saturated runs: the water volume that left the saturated bodies since the start (m³ per
    /// metre in plane strain, per radian in axisymmetry: through the drained faces and free
    /// surfaces); None in a dry run.
    fn water_outflow(&self) -> Option<f64> {
        self.inner.water_outflow()
    }
    /// Per reporting constraint (faces that are not free: "left", "right", "bottom", "top";
    /// walls: "wall_0", ...), the mean force (N; axisymmetric: the whole body, × 2π; plane
    /// strain: per metre) the material exerted on it since the last call:
    /// [(name, force_x, force_y), ...]. Resets the accumulators.
    fn reactions(&mut self) -> Vec<(String, f64, f64)> {
        self.inner.reactions().into_iter().map(|(name, f)| (name, f[0], f[1])).collect()
    }
    /// Per surcharge, the force it applies to the material now (N; axisymmetric: the whole
    /// ring; plane strain: per metre; negative y: downward): [(name, force_x, force_y), ...].
    fn surcharge_forces(&self) -> Vec<(String, f64, f64)> {
        self.inner.surcharge_forces().into_iter().map(|(name, f)| (name, f[0], f[1])).collect()
    }
    /// Names `reactions()` reports, in order.
    fn reaction_names(&self) -> Vec<String> {
        self.inner.reaction_names()
    }
    /// Per rigid body, its outline at the current time: [(name, [(x, y), ...]), ...] (m,
    /// counter-clockwise, not closed).
    fn rigid_body_outlines(&self) -> Vec<(String, Vec<(f64, f64)>)> {
        self.inner
            .rigid_body_outlines()
            .into_iter()
            .map(|(name, vertices)| (name, vertices.into_iter().map(|v| (v[0], v[1])).collect()))
            .collect()
    }
    /// Per rigid body, its displacement (m) at the current time: [(name, dx, dy), ...].
    fn rigid_body_displacements(&self) -> Vec<(String, f64, f64)> {
        self.inner.rigid_body_displacements().into_iter().map(|(name, d)| (name, d[0], d[1])).collect()
    }
    /// Per rigid body, its velocity (m/s) at the current time: [(name, vx, vy), ...] (the
    /// prescribed one, or a force-driven body's).
    fn rigid_body_velocities(&self) -> Vec<(String, f64, f64)> {
        self.inner.rigid_body_velocities().into_iter().map(|(name, v)| (name, v[0], v[1])).collect()
    }
    /// Per rigid body, the mean force (N, whole body) since the last call split into parts:
    /// `base` (contact normals facing down), `shaft` (the rest), then the body's named parts by
    /// height and `rest` if it names any: [(name, [(part, fx, fy), ...]), ...]. Resets its own
    /// accumulators.
    fn rigid_body_parts(&mut self) -> Vec<(String, Vec<(String, f64, f64)>)> {
        self.inner
            .rigid_body_parts()
            .into_iter()
            .map(|(name, parts)| (name, parts.into_iter().map(|(part, f)| (part, f[0], f[1])).collect()))
            .collect()
    }
    /// Wall seconds spent in each phase of the step since construction:
    /// {"particle_to_grid", "grid_update", "grid_to_particle", "constitutive_update"}.
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let t = self.inner.timings();
        let d = PyDict::new(py);
        d.set_item("particle_to_grid", t.particle_to_grid)?;
        d.set_item("grid_update", t.grid_update)?;
        d.set_item("grid_to_particle", t.grid_to_particle)?;
        d.set_item("constitutive_update", t.constitutive_update)?;
        Ok(d)
    }
    /// The failure message once the run has failed, else None.
    fn failure(&self) -> Option<String> {
        self.inner.failure().map(|f| f.to_string())
    }
}

/// material_response(material_json, velocity_gradients (S, 5), dt, initial_stress=[0]*4)
/// -> (stresses (S, 4), states (S, k), state_names)
///
/// Drives one material point through a sequence of velocity gradients
/// [L11, L12, L21, L22, L33], each applied for `dt`; F is integrated as in the solver.
#[pyfunction]
#[pyo3(signature = (material_json, velocity_gradients, dt, initial_stress = [0.0; 4]))]
#[allow(clippy::type_complexity)]
fn material_response<'py>(
    py: Python<'py>,
    material_json: &str,
    velocity_gradients: PyReadonlyArray2<'py, f64>,
    dt: f64,
    initial_stress: [f64; 4],
) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>, Vec<String>)> {
    let config: MaterialConfig =
        serde_json::from_str(material_json).map_err(|e| PyValueError::new_err(format!("material: {e}")))?;
    let model = material::build("material", &config).map_err(PyValueError::new_err)?;
    let l = velocity_gradients.as_array();
    if l.ncols() != 5 {
        return Err(PyValueError::new_err("velocity_gradients must have 5 columns [L11, L12, L21, L22, L33]"));
    }
    let names: Vec<String> = model.state_names().iter().map(|s| s.to_string()).collect();
    let k = names.len();
    let steps = l.nrows();
    let mut stress = initial_stress;
    let mut state = vec![0.0; k];
    let mut f = [1.0, 0.0, 0.0, 1.0, 1.0];
    let mut stresses = Vec::with_capacity(steps * 4);
    let mut states = Vec::with_capacity(steps * k);
    for s in 0..steps {
        let g = [l[[s, 0]], l[[s, 1]], l[[s, 2]], l[[s, 3]], l[[s, 4]]];
        let a = [1.0 + dt * g[0], dt * g[1], dt * g[2], 1.0 + dt * g[3]];
        f = [
            a[0] * f[0] + a[1] * f[2],
            a[0] * f[1] + a[1] * f[3],
            a[2] * f[0] + a[3] * f[2],
            a[2] * f[1] + a[3] * f[3],
            (1.0 + dt * g[4]) * f[4],
        ];
        let jacobian = (f[0] * f[3] - f[1] * f[2]) * f[4];
        model.update_stress(&mut stress, &mut state, &Kinematics { velocity_gradient: g, deformation_gradient: f, jacobian, cell_field: [0.0; 2], dt });
        stresses.extend_from_slice(&stress);
        states.extend_from_slice(&state);
    }
    Ok((stresses.into_pyarray(py).reshape([steps, 4])?, states.into_pyarray(py).reshape([steps, k])?, names))
}

/// material_key_errors(name, material_json) -> [(key, message)]: the engine's refusals of the
/// retired and experimental keys of one material table (`material::status`), for the
/// scenario front end to report next to its own checks; empty for an unknown model.
#[pyfunction]
fn material_key_errors(name: &str, material_json: &str) -> PyResult<Vec<(String, String)>> {
    let config: MaterialConfig =
        serde_json::from_str(material_json).map_err(|e| PyValueError::new_err(format!("material: {e}")))?;
    Ok(material::status::key_errors(&material::Parameters::new(name, &config.parameters), &config.model))
}

/// rigid_body_errors(tables_json, grid_lower, grid_upper, axisymmetric, end_time, wall_count) -> [(key, message)]:
/// the engine's refusals of the `rigid_bodies` tables (a JSON list; null: a table left out), at
/// most one per body, keys as `rigid_bodies[0].motion[2][0]`, for the scenario front end
/// (an infinite grid or `end_time`: not checked against).
#[pyfunction]
fn rigid_body_errors(
    tables_json: &str,
    grid_lower: [f64; 2],
    grid_upper: [f64; 2],
    axisymmetric: bool,
    end_time: f64,
    wall_count: usize,
) -> PyResult<Vec<(String, String)>> {
    use axmpm_core::constraint::rigid_body;
    let tables: Vec<Option<serde_json::Value>> =
        serde_json::from_str(tables_json).map_err(|e| PyValueError::new_err(format!("rigid_bodies: {e}")))?;
    let reserved = rigid_body::reserved_names(wall_count);
    Ok(rigid_body::errors(&tables, grid_lower, grid_upper, axisymmetric, end_time, &reserved))
}

/// follow_errors(follow, experimental, rigid_body_names, wall_count, saturated, material_models)
/// -> [message]: the engine's refusals of `grid.follow` (config and material registry), every
/// one, for the scenario front end.
#[pyfunction]
fn follow_errors(
    follow: &str,
    experimental: bool,
    rigid_body_names: Vec<String>,
    wall_count: usize,
    saturated: bool,
    material_models: Vec<String>,
) -> Vec<String> {
    let names: Vec<&str> = rigid_body_names.iter().map(String::as_str).collect();
    let mut errors = axmpm_core::config::follow_errors(follow, experimental, &names, wall_count, saturated);
    if material_models.iter().any(|m| axmpm_core::material::NONLOCAL_MODELS.contains(&m.as_str())) {
        errors.push(axmpm_core::material::FOLLOW_WITH_NONLOCAL.to_string());
    }
    errors
}

/// reserved_names(wall_count) -> [name]: the names the grid faces, the axis and the walls
/// report their reactions under (a rigid body may not take one).
#[pyfunction]
fn reserved_names(wall_count: usize) -> Vec<String> {
    axmpm_core::constraint::rigid_body::reserved_names(wall_count)
}

/// catalogue() -> {"formulations", "interpolation_schemes", "material_models", "region_shapes"}:
/// the names the engine accepts, each a list, from the engine's registries.
#[pyfunction]
fn catalogue(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    for (key, names) in axmpm_core::catalogue() {
        d.set_item(key, names)?;
    }
    Ok(d)
}

/// instruction_set() -> "avx2" or "baseline": the instruction set the step's loops run with on
/// this CPU (`AXMPM_ISA=baseline` asks for the baseline); both give bit-identical results.
#[pyfunction]
fn instruction_set() -> &'static str {
    axmpm_core::solver::Isa::detect().name()
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PySimulation>()?;
    m.add("SimulationFailure", m.py().get_type::<SimulationFailure>())?;
    m.add_function(wrap_pyfunction!(material_response, m)?)?;
    m.add_function(wrap_pyfunction!(catalogue, m)?)?;
    m.add_function(wrap_pyfunction!(instruction_set, m)?)?;
    m.add_function(wrap_pyfunction!(material_key_errors, m)?)?;
    m.add_function(wrap_pyfunction!(rigid_body_errors, m)?)?;
    m.add_function(wrap_pyfunction!(reserved_names, m)?)?;
    m.add_function(wrap_pyfunction!(follow_errors, m)?)?;
    m.add("PENALTY_WITH_SATURATED", axmpm_core::config::PENALTY_WITH_SATURATED)?;
    m.add("XPIC_IS_EXPERIMENTAL", axmpm_core::config::XPIC_IS_EXPERIMENTAL)?;
    m.add("XPIC_WITH_SATURATED", axmpm_core::config::XPIC_WITH_SATURATED)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
