//! `Model.simulate()`: the nonlinear time simulation (`simulation::simulate`, as
//! `flexmbd simulate`), and its result `flexmbd.SimulationResult`. A run that stops before
//! its end time keeps its frames: the result is raised with `flexmbd.SimulationStoppedError`
//! as its `result`.

use crate::convert::{array, json, vec1};
use crate::errors::{self, Failure, Kind};
use crate::model::{Loaded, PyModel};
use crate::states::States;
use flexmbd_core::simulation::{simulate as run, SimFailure, Simulation, Stopped};
use flexmbd_io::requests::SimOverrides;
use flexmbd_io::sim_report::sim_json;
use pyo3::prelude::*;
use std::sync::Arc;

/// The result of a time simulation: the states at the output times, velocities, energies.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "SimulationResult")]
pub struct SimulationResult {
    model: Arc<Loaded>,
    sim: Simulation,
    stopped: Option<Stopped>,
    states: Py<States>,
}

/// Nonlinear time simulation (generalised-α) from t = 0 to the end time.
#[pyfunction]
#[pyo3(signature = (model, t_end=None, dt=None, fixed_step=false, rho_inf=None, tolerance=None, output_step=None))]
pub fn simulate(
    py: Python<'_>,
    model: &PyModel,
    t_end: Option<f64>,
    dt: Option<f64>,
    fixed_step: bool,
    rho_inf: Option<f64>,
    tolerance: Option<(f64, f64)>,
    output_step: Option<f64>,
) -> PyResult<Py<SimulationResult>> {
    let loaded = model.inner.clone();
    let over = SimOverrides {
        t_end,
        dt,
        fixed_step,
        rho_inf,
        tolerance: tolerance.map(|(a, r)| [a, r]),
        output_step,
    };
    let (file, warnings) = loaded.dynamic_file().map_err(|f| f.into_py(py))?;
    PyModel::warn(py, warnings)?;
    let opts = over
        .options(&loaded.file, &file.simulate, &|name| match name {
            "tolerance" => "tolerance=(abs, rel)".to_string(),
            n => format!("{n}="),
        })
        .map_err(|e| errors::request("simulate", e).into_py(py))?;
    let l = loaded.clone();
    let result = py.detach(move || {
        let file = l.dynamic_file()?.0;
        match run(&file.model, &file.simulate.excitation, &opts, &mut |_| {}) {
            Ok(sim) => Ok((sim, None)),
            Err(SimFailure::NotStarted(e)) => {
                Err(Failure::new(Kind::Numerical, e.to_string()).in_stage("simulation failed"))
            }
            Err(SimFailure::Stopped(s)) => Ok(((*s.partial).clone(), Some(s))),
        }
    });
    let (sim, stopped) = result.map_err(|f| f.into_py(py))?;
    let states = Py::new(
        py,
        States::new(
            &file.model,
            sim.frames
                .iter()
                .map(|f| f.as_step())
                .collect::<Vec<_>>()
                .iter(),
        ),
    )?;
    let failure = stopped.as_ref().map(|s| {
        let mut f = Failure::new(
            Kind::SimulationStopped,
            format!(
                "the simulation stopped at t = {:.6e} s: {}; the frames up to then are the exception's `result`",
                s.t, s.reason
            ),
        );
        f.hint = Some(s.hint.clone());
        f
    });
    let obj = Py::new(
        py,
        SimulationResult {
            model: loaded,
            sim,
            stopped,
            states,
        },
    )?;
    match failure {
        None => Ok(obj),
        Some(f) => Err(f.into_py_with(py, Some(obj.into_any()))),
    }
}

#[pymethods]
impl SimulationResult {
    fn __repr__(&self) -> String {
        format!(
            "<flexmbd.SimulationResult: {} frames to t = {:.4e} s{}>",
            self.sim.frames.len(),
            self.sim.frames.last().map_or(0.0, |f| f.t),
            if self.stopped.is_some() {
                ", stopped"
            } else {
                ""
            }
        )
    }

    /// Output times [s].
    #[getter]
    fn t(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.sim.frames.iter().map(|f| f.t).collect())
    }

    /// The states at the output times (positions, rotations, deformations, stresses, …).
    #[getter]
    fn states(&self, py: Python<'_>) -> Py<States> {
        self.states.clone_ref(py)
    }

    /// Node velocities [m/s], (frames, nodes, 3).
    #[getter]
    fn velocities(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_rates(py, |(v, _)| Some(*v))
    }

    /// Angular velocities [rad/s] (global axes), (frames, nodes, 3); NaN for nodes without
    /// rotation.
    #[getter]
    fn angular_velocities(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_rates(py, |(_, w)| *w)
    }

    /// Energies at the output times [J]: {"kinetic", "strain", "external_work",
    /// "prescribed_work", "dissipated", "balance_error"}, each an array over the frames.
    #[getter]
    fn energies(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let d = pyo3::types::PyDict::new(py);
        let e = |f: fn(&flexmbd_core::simulation::Energies) -> f64| {
            vec1(py, self.sim.frames.iter().map(|fr| f(&fr.energy)).collect())
        };
        d.set_item("kinetic", e(|x| x.kinetic))?;
        d.set_item("strain", e(|x| x.strain))?;
        d.set_item("external_work", e(|x| x.external_work))?;
        d.set_item("prescribed_work", e(|x| x.prescribed_work))?;
        d.set_item("dissipated", e(|x| x.dissipated))?;
        d.set_item("balance_error", e(|x| x.balance_error))?;
        Ok(d.into_any().unbind())
    }

    /// The counts of the run (steps, rejected steps, Newton iterations, …).
    #[getter]
    fn stats(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        json(
            py,
            &serde_json::to_value(self.sim.stats).unwrap_or_default(),
        )
    }

    /// Whether the run reached its end time.
    #[getter]
    fn complete(&self) -> bool {
        self.stopped.is_none()
    }

    /// The report as a dict: the structure of `flexmbd simulate --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let file = self.model.dynamic_file().map_err(|f| f.into_py(py))?.0;
        json(
            py,
            &sim_json(
                &file.model,
                &self.model.file,
                &self.sim,
                self.stopped.as_ref(),
            ),
        )
    }
}

/// A node's velocity and, for a rotational node, its angular velocity.
type NodeRate = ([f64; 3], Option<[f64; 3]>);

impl SimulationResult {
    fn node_rates(
        &self,
        py: Python<'_>,
        f: fn(&NodeRate) -> Option<[f64; 3]>,
    ) -> PyResult<Py<PyAny>> {
        let file = self.model.dynamic_file().map_err(|f| f.into_py(py))?.0;
        let nn = file.model.nodes.len();
        let data = self
            .sim
            .frames
            .iter()
            .flat_map(|fr| fr.node_velocities(&file.model))
            .flat_map(|r| f(&r).unwrap_or([f64::NAN; 3]))
            .collect();
        array(py, data, &[self.sim.frames.len(), nn, 3])
    }
}
