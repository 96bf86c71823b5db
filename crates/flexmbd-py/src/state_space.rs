//! `Model.state_space()`: the linear state-space model about a static equilibrium
//! (`dynamics::state_space_with_motions`, as `flexmbd statespace`), and its result
//! `flexmbd.StateSpace`: A, B, C, D with named inputs and outputs, the frequency response and
//! the conversion to python-control.

use crate::convert::{json, mat, vec1};
use crate::errors::{self, Failure};
use crate::model::{Loaded, PyModel};
use crate::statics::{solver, static_options, step_index};
use flexmbd_core::dynamics::state_space::{
    check_dense_size, state_space_with_motions, uses_sparse, StateSpace as Core, StateSpaceOptions,
    DENSE_STATE_SPACE_DOF,
};
use flexmbd_core::dynamics::{velocity_dof, EigenSolver};
use flexmbd_io::requests::{parse_input, parse_output, split_inputs};
use flexmbd_io::statespace_report::{statespace_json, Origin};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use std::sync::Arc;

/// A state-space model in modal coordinates with named inputs and outputs.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "StateSpace")]
pub struct StateSpace {
    model: Arc<Loaded>,
    step: usize,
    load_factor: f64,
    ss: Core,
}

/// The linear state-space model (A, B, C, D) about a static equilibrium.
#[pyfunction]
#[pyo3(signature = (model, inputs, outputs, damping=0.01, modes=None, static_correction=false, at_step=None, steps=None, solver="auto"))]
pub fn state_space(
    py: Python<'_>,
    model: &PyModel,
    inputs: Vec<String>,
    outputs: Vec<String>,
    damping: f64,
    modes: Option<usize>,
    static_correction: bool,
    at_step: Option<usize>,
    steps: Option<usize>,
    solver: &str,
) -> PyResult<StateSpace> {
    let loaded = model.inner.clone();
    let prepared = (|| {
        let file = loaded.static_file()?;
        let m = &file.model;
        let name = &loaded.file;
        if inputs.is_empty() || outputs.is_empty() {
            return Err(Failure::option(
                if inputs.is_empty() {
                    "inputs"
                } else {
                    "outputs"
                },
                "the state-space model needs at least one input and one output",
            ));
        }
        let specs = inputs
            .iter()
            .map(|s| parse_input(m, name, "input", s).map_err(|e| errors::request("inputs", e)))
            .collect::<Result<Vec<_>, _>>()?;
        let (loads, motions) = split_inputs(&specs);
        let outs = outputs
            .iter()
            .map(|s| parse_output(m, name, "output", s).map_err(|e| errors::request("outputs", e)))
            .collect::<Result<Vec<_>, _>>()?;
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(Failure::option(
                "damping",
                format!("damping must be a finite number >= 0, found {damping}"),
            ));
        }
        if modes == Some(0) {
            return Err(Failure::option("modes", "modes must be at least 1"));
        }
        let ss_opts = StateSpaceOptions {
            damping,
            modes,
            static_correction,
            solver: self::solver(solver)?,
            ..Default::default()
        };
        if uses_sparse(m, &ss_opts) && modes.is_none() {
            return Err(Failure::option(
                "modes",
                format!(
                    "{name} has {} degrees of freedom{}: the sparse state space keeps the lowest modes only; give modes=N (e.g. modes=20), with static_correction=True for the exact static gain",
                    velocity_dof(m),
                    if ss_opts.solver == EigenSolver::Sparse {
                        " and solver=\"sparse\" was given".to_string()
                    } else {
                        format!(", more than the dense state space takes ({DENSE_STATE_SPACE_DOF})")
                    }
                ),
            ));
        }
        Ok((
            static_options(file, steps, None)?,
            ss_opts,
            loads,
            motions,
            outs,
        ))
    })();
    let (opts, ss_opts, loads, motions, outs) = prepared.map_err(|f| f.into_py(py))?;
    let l = loaded.clone();
    let run = py.detach(move || {
        let m = &l.static_file()?.model;
        check_dense_size(m, &ss_opts)
            .map_err(|e| errors::state_space(&e).in_stage("state-space model refused"))?;
        let sol = flexmbd_core::statics::solve_path(m, &opts, |_, _| {}).map_err(|s| {
            errors::solve(&s.error)
                .in_stage("the static equilibrium to linearise about was not found")
        })?;
        let k = step_index(at_step, sol.steps.len(), false)?;
        let step = &sol.steps[k];
        let ss = state_space_with_motions(m, step, &loads, &motions, &outs, &ss_opts)
            .map_err(|e| errors::state_space(&e).in_stage("state-space model failed"))?;
        Ok::<_, Failure>((k, step.load_factor, ss))
    });
    let (step, load_factor, ss) = run.map_err(|f| f.into_py(py))?;
    Ok(StateSpace {
        model: loaded,
        step,
        load_factor,
        ss,
    })
}

impl StateSpace {
    fn core_model(&self) -> &flexmbd_core::Model {
        // a StateSpace exists only for a model whose static file was read
        match self.model.static_file() {
            Ok(f) => &f.model,
            Err(_) => &self.model.check,
        }
    }
}

#[pymethods]
impl StateSpace {
    fn __repr__(&self) -> String {
        format!(
            "<flexmbd.StateSpace: {} states, {} inputs, {} outputs, {} modes>",
            self.ss.n_states(),
            self.ss.n_inputs(),
            self.ss.outputs.len(),
            self.ss.n_modes()
        )
    }

    /// A (states × states).
    #[getter]
    #[allow(non_snake_case)]
    fn A(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.ss.a)
    }

    /// B (states × inputs).
    #[getter]
    #[allow(non_snake_case)]
    fn B(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.ss.b)
    }

    /// C (outputs × states).
    #[getter]
    #[allow(non_snake_case)]
    fn C(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.ss.c)
    }

    /// D (outputs × inputs).
    #[getter]
    #[allow(non_snake_case)]
    fn D(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.ss.d)
    }

    /// Input names, in the order of the columns of B and D.
    #[getter]
    fn input_names(&self) -> Vec<String> {
        let m = self.core_model();
        self.ss.input_info(m).into_iter().map(|i| i.name).collect()
    }

    /// Output names, in the order of the rows of C and D.
    #[getter]
    fn output_names(&self) -> Vec<String> {
        let m = self.core_model();
        self.ss.outputs.iter().map(|o| o.name(m)).collect()
    }

    /// State names.
    #[getter]
    fn state_names(&self) -> Vec<String> {
        self.ss.state_names()
    }

    /// Frequencies of the kept modes [Hz].
    #[getter]
    fn frequencies(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.ss.frequencies())
    }

    /// ω² of the kept modes [rad²/s²].
    #[getter]
    fn eigenvalues(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.ss.eigenvalues.clone())
    }

    /// The modal damping ratio ζ.
    #[getter]
    fn damping(&self) -> f64 {
        self.ss.damping
    }

    /// The static gain −C A⁻¹ B + D (outputs × inputs); None when A is singular.
    #[getter]
    fn dc_gain(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        match self.ss.dc_gain() {
            Ok(g) => mat(py, &g),
            Err(_) => Ok(py.None()),
        }
    }

    /// Notes on the inputs and outputs.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.ss.warnings.clone()
    }

    /// The load step linearised about, and its load factor.
    #[getter]
    fn step(&self) -> (usize, f64) {
        (self.step, self.load_factor)
    }

    /// The frequency response G(j 2π f) at the frequencies `f_hz` [Hz] (any array-like): a
    /// complex array (frequencies, outputs, inputs).
    fn frequency_response(&self, py: Python<'_>, f_hz: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let f = crate::convert::f64_vector(f_hz)?;
        let (no, ni) = (self.ss.outputs.len(), self.ss.n_inputs());
        let g = py.detach(|| {
            f.iter()
                .flat_map(|&fk| {
                    self.ss
                        .frequency_response(fk)
                        .into_iter()
                        .flatten()
                        .map(|c| num_complex_of(c.re, c.im))
                })
                .collect::<Vec<_>>()
        });
        Ok(PyArray1::from_vec(py, g)
            .reshape(vec![f.len(), no, ni])?
            .into_any()
            .unbind())
    }

    /// The report as a dict: the structure of `flexmbd statespace --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let origin = Origin {
            file: &self.model.file,
            step: self.step,
            load_factor: self.load_factor,
            stopped: None,
        };
        json(py, &statespace_json(self.core_model(), origin, &self.ss))
    }

    /// A python-control `StateSpace` (needs the package `control`).
    fn to_control(slf: &Bound<'_, Self>) -> PyResult<Py<PyAny>> {
        let py = slf.py();
        Ok(py
            .import("flexmbd._control")?
            .call_method1("to_control", (slf,))?
            .unbind())
    }
}

fn num_complex_of(re: f64, im: f64) -> numpy::Complex64 {
    numpy::Complex64::new(re, im)
}
