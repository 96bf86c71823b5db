//! `Model.static()` (`linearized::analyse`, as `flexmbd static`) and `Model.modes()`
//! (`dynamics::modes_with` about a static state, as `flexmbd modes`), with their results
//! `flexmbd.StaticResult` and `flexmbd.ModesResult`. A static path that stops part-way keeps
//! its converged steps: the result is built from them and raised with
//! `flexmbd.PathStoppedError` as its `result`.

use crate::convert::{array, json, vec1};
use crate::errors::{self, Failure, Kind};
use crate::model::{Loaded, PyModel};
use crate::states::States;
use flexmbd_core::dynamics::{check_dense_size, modes_with, EigenSolver, Modal, ModalOptions};
use flexmbd_core::statics::linear::{LinearRequest, StepLinear};
use flexmbd_core::statics::{PathMethod, SolveError, StaticAnalysis, StaticOptions, Stopped};
use flexmbd_io::modes_report::modes_json;
use flexmbd_io::static_report::static_json;
use flexmbd_io::stopped::StopNote;
use flexmbd_io::ModelFile;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// `path=`: `"load-steps"` or `"arc-length"`.
fn path_method(path: Option<&str>) -> Result<Option<PathMethod>, Failure> {
    match path {
        None => Ok(None),
        Some("load-steps") => Ok(Some(PathMethod::LoadSteps)),
        Some("arc-length") => Ok(Some(PathMethod::ArcLength)),
        Some(p) => Err(Failure::option(
            "path",
            format!("path must be \"load-steps\" or \"arc-length\", found {p:?}"),
        )),
    }
}

/// `solver=`: `"auto"`, `"dense"` or `"sparse"`.
pub fn solver(s: &str) -> Result<EigenSolver, Failure> {
    match s {
        "auto" => Ok(EigenSolver::Auto),
        "dense" => Ok(EigenSolver::Dense),
        "sparse" => Ok(EigenSolver::Sparse),
        s => Err(Failure::option(
            "solver",
            format!("solver must be \"auto\", \"dense\" or \"sparse\", found {s:?}"),
        )),
    }
}

/// The static options: the model file's `[static]` settings with `steps` and `path` over them.
pub fn static_options(
    file: &ModelFile,
    steps: Option<usize>,
    path: Option<&str>,
) -> Result<StaticOptions, Failure> {
    flexmbd_io::requests::static_options(&file.settings, steps, path_method(path)?)
        .map_err(|e| errors::request("steps", e))
}

/// The static state `at_step` of a solution with `n` steps (default the last).
pub fn step_index(at_step: Option<usize>, n: usize, stopped: bool) -> Result<usize, Failure> {
    let k = at_step.unwrap_or(n.saturating_sub(1));
    if k >= n {
        return Err(Failure::option(
            "at_step",
            format!(
                "at_step={k}: the static solution has steps 0 to {}{}",
                n.saturating_sub(1),
                if stopped { " (it stopped there)" } else { "" }
            ),
        ));
    }
    Ok(k)
}

/// The converged part of a static path, and why it stopped if it did; an error when no state
/// converged.
fn converged(
    r: Result<StaticAnalysis, Stopped>,
    what: &str,
) -> Result<(StaticAnalysis, Option<SolveError>), Failure> {
    match r {
        Ok(a) => Ok((a, None)),
        Err(s) if s.analysis.solution.steps.is_empty() => {
            Err(errors::solve(&s.error).in_stage(what))
        }
        Err(s) => {
            let (a, e) = s.into_parts();
            Ok((a, Some(e)))
        }
    }
}

/// The note of a path that stopped (the `stopped` field of the reports), with the Python hint.
fn note(a: &StaticAnalysis, stop: &Option<SolveError>) -> Option<StopNote> {
    stop.as_ref()
        .map(|e| StopNote::new(&a.solution, e, errors::solve_hint(e)))
}

/// The number of converged steps and the last load factor.
fn last_step(a: &StaticAnalysis) -> (usize, f64) {
    let s = &a.solution.steps;
    (s.len(), s.last().map_or(0.0, |s| s.load_factor))
}

/// Return `result`, or raise it with `PathStoppedError` when the path stopped.
fn finish<T: pyo3::PyClass + Into<pyo3::PyClassInitializer<T>>>(
    py: Python<'_>,
    result: T,
    (n, last): (usize, f64),
    stop: Option<SolveError>,
) -> PyResult<Py<T>> {
    let obj = Py::new(py, result)?;
    let Some(e) = stop else {
        return Ok(obj);
    };
    let mut f = errors::solve(&e);
    f.kind = Kind::PathStopped;
    f.message = format!(
        "the static path stopped after step {} (load factor {last:.6}); the results of the converged steps are the exception's `result`: {}",
        n.saturating_sub(1),
        f.message
    );
    Err(f.into_py_with(py, Some(obj.into_any())))
}

/// The result of a static analysis: the states of the load steps and the linearised results.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "StaticResult")]
pub struct StaticResult {
    model: Arc<Loaded>,
    analysis: StaticAnalysis,
    note: Option<StopNote>,
    states: Py<States>,
}

/// Nonlinear statics over load steps (or by arc length) with reactions, stress resultants,
/// compliance, buckling.
#[pyfunction]
#[pyo3(signature = (model, steps=None, compliance=Vec::new(), buckling=None, tol_force=None, tol_disp=None, line_search=false, path=None, tangent_eigenvalues=false))]
#[allow(clippy::too_many_arguments)]
pub fn static_(
    py: Python<'_>,
    model: &PyModel,
    steps: Option<usize>,
    compliance: Vec<String>,
    buckling: Option<usize>,
    tol_force: Option<f64>,
    tol_disp: Option<f64>,
    line_search: bool,
    path: Option<&str>,
    tangent_eigenvalues: bool,
) -> PyResult<Py<StaticResult>> {
    let loaded = model.inner.clone();
    let prepared = (|| {
        let file = loaded.static_file()?;
        let mut opts = static_options(file, steps, path)?;
        for (name, v, target) in [
            ("tol_force", tol_force, &mut opts.tol_force),
            ("tol_disp", tol_disp, &mut opts.tol_disp),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err(Failure::option(
                        name,
                        format!("{name} must be a positive number, found {v}"),
                    ));
                }
                *target = v;
            }
        }
        opts.line_search = line_search || file.settings.line_search;
        opts.tangent_eigenvalues = tangent_eigenvalues || file.settings.tangent_eigenvalues;
        let mut ids = Vec::new();
        for n in file.settings.compliance.iter().chain(&compliance) {
            ids.push(file.model.node_id(n).ok_or_else(|| {
                Failure::option(
                    "compliance",
                    format!("compliance: node `{n}` is not defined in {}", loaded.file),
                )
            })?);
        }
        let request = LinearRequest {
            compliance: ids,
            buckling: buckling.unwrap_or(file.settings.buckling),
            ..Default::default()
        };
        Ok((opts, request))
    })();
    let (opts, request) = prepared.map_err(|f| f.into_py(py))?;
    let l = loaded.clone();
    let run = py.detach(move || {
        let model = &l.static_file()?.model;
        if !request.is_empty() {
            flexmbd_core::linearized::check_dense_size(model, request.max_dense_bytes)
                .map_err(|e| errors::linear(&e).in_stage("compliance and buckling refused"))?;
        }
        converged(
            flexmbd_core::linearized::analyse(model, &opts, &request, |_, _| {}),
            "static analysis failed",
        )
    });
    let (analysis, stop) = run.map_err(|f| f.into_py(py))?;
    let states = Py::new(
        py,
        States::new(
            &loaded.static_file().map_err(|f| f.into_py(py))?.model,
            analysis.solution.steps.iter(),
        ),
    )?;
    let end = last_step(&analysis);
    let result = StaticResult {
        note: note(&analysis, &stop),
        model: loaded,
        analysis,
        states,
    };
    finish(py, result, end, stop)
}

impl StaticResult {
    fn linear(&self) -> &[StepLinear] {
        &self.analysis.linear
    }
}

#[pymethods]
impl StaticResult {
    fn __repr__(&self) -> String {
        format!(
            "<flexmbd.StaticResult: {} load steps{}>",
            self.analysis.solution.steps.len(),
            if self.note.is_some() {
                ", stopped part-way"
            } else {
                ""
            }
        )
    }

    /// The states of the load steps (step 0 is the unloaded state).
    #[getter]
    fn states(&self, py: Python<'_>) -> Py<States> {
        self.states.clone_ref(py)
    }

    /// Load factor of each step.
    #[getter]
    fn load_factors(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(
            py,
            self.analysis
                .solution
                .steps
                .iter()
                .map(|s| s.load_factor)
                .collect(),
        )
    }

    /// Newton iterations of each step.
    #[getter]
    fn iterations(&self) -> Vec<usize> {
        self.analysis
            .solution
            .steps
            .iter()
            .map(|s| s.iterations)
            .collect()
    }

    /// The 6 × 6 compliance of each requested node at every step, global axes:
    /// {node: (steps, 6, 6)}; rows and columns x, y, z, rx, ry, rz.
    #[getter]
    fn compliance(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.compliance_in(py, |c| c.global)
    }

    /// The same in each node's current local axes.
    #[getter]
    fn compliance_local(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.compliance_in(py, |c| c.local)
    }

    /// Positive buckling load multipliers of each step, (steps, count), NaN-padded; None
    /// when buckling was not asked for.
    #[getter]
    fn buckling(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let rows: Vec<Vec<f64>> = self
            .linear()
            .iter()
            .map(|x| {
                x.buckling
                    .as_ref()
                    .map_or(Vec::new(), |b| b.multipliers.clone())
            })
            .collect();
        if self.linear().iter().all(|x| x.buckling.is_none()) {
            return Ok(py.None());
        }
        let width = rows.iter().map(Vec::len).max().unwrap_or(0);
        let data = rows
            .iter()
            .flat_map(|r| (0..width).map(|k| r.get(k).copied().unwrap_or(f64::NAN)))
            .collect();
        array(py, data, &[rows.len(), width])
    }

    /// The smallest eigenvalues of the tangent stiffness on the constraints at each step,
    /// (steps, 3), ascending, NaN where not computed or where the model has fewer free
    /// directions (docs/statics.md, "Smallest eigenvalues of the tangent").
    #[getter]
    fn tangent_eigenvalues(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let steps = &self.analysis.solution.steps;
        let width = flexmbd_core::statics::TANGENT_EIGENVALUES;
        let data = steps
            .iter()
            .flat_map(|st| {
                let k = st.tangent_eigenvalues.as_deref().unwrap_or(&[]);
                (0..width).map(|i| k.get(i).copied().unwrap_or(f64::NAN))
            })
            .collect();
        array(py, data, &[steps.len(), width])
    }

    /// Negative directions of the tangent stiffness at each step (0: stable); None where not
    /// computed.
    #[getter]
    fn unstable_directions(&self) -> Vec<Option<usize>> {
        self.linear()
            .iter()
            .map(|x| x.unstable_directions)
            .collect()
    }

    /// Where and why the path stopped (None for a complete path).
    #[getter]
    fn stopped(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        json(py, &flexmbd_io::stopped::json_field(self.note.as_ref()))
    }

    /// The report as a dict: the structure of `flexmbd static --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let l = &self.model;
        let file = l.static_file().map_err(|f| f.into_py(py))?;
        json(
            py,
            &static_json(
                &file.model,
                &l.file,
                &self.analysis.solution,
                &self.analysis.linear,
                self.note.as_ref(),
            ),
        )
    }
}

impl StaticResult {
    fn compliance_in(
        &self,
        py: Python<'_>,
        f: fn(&flexmbd_core::statics::linear::Compliance) -> [[f64; 6]; 6],
    ) -> PyResult<Py<PyAny>> {
        let d = PyDict::new(py);
        let Some(first) = self.linear().first() else {
            return Ok(d.into_any().unbind());
        };
        for (k, (name, _)) in first.compliance.iter().enumerate() {
            let data: Vec<f64> = self
                .linear()
                .iter()
                .flat_map(|x| {
                    x.compliance
                        .get(k)
                        .map_or([[f64::NAN; 6]; 6], |(_, c)| f(c))
                        .into_iter()
                        .flatten()
                })
                .collect();
            d.set_item(name, array(py, data, &[self.linear().len(), 6, 6])?)?;
        }
        Ok(d.into_any().unbind())
    }
}

/// The result of a modal analysis about a static state.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "ModesResult")]
pub struct ModesResult {
    model: Arc<Loaded>,
    load_factor: f64,
    modal: Modal,
    note: Option<StopNote>,
}

/// Natural frequencies and mode shapes, linearised about a static equilibrium.
#[pyfunction]
#[pyo3(signature = (model, count=10, at_step=None, steps=None, solver="auto", path=None))]
pub fn modes(
    py: Python<'_>,
    model: &PyModel,
    count: usize,
    at_step: Option<usize>,
    steps: Option<usize>,
    solver: &str,
    path: Option<&str>,
) -> PyResult<Py<ModesResult>> {
    let loaded = model.inner.clone();
    let prepared = (|| {
        let file = loaded.static_file()?;
        let max = flexmbd_io::limits::MAX_MODES;
        if count > max {
            return Err(Failure::option(
                "count",
                format!(
                    "count must be from 0 to {max} (the limit, docs/reliability.md), found {count}"
                ),
            ));
        }
        Ok((
            static_options(file, steps, path)?,
            ModalOptions::with_solver(self::solver(solver)?),
        ))
    })();
    let (opts, modal_opts) = prepared.map_err(|f| f.into_py(py))?;
    let l = loaded.clone();
    let run = py.detach(move || {
        let model = &l.static_file()?.model;
        check_dense_size(model, count, &modal_opts)
            .map_err(|e| errors::modal(&e).in_stage("modal analysis refused"))?;
        let (a, stop) = converged(
            flexmbd_core::statics::solve_path(model, &opts, |_, _| {}).map(|solution| {
                StaticAnalysis {
                    solution,
                    linear: Vec::new(),
                }
            }),
            "the static equilibrium to linearise about was not found",
        )?;
        let steps = &a.solution.steps;
        let step = &steps[step_index(at_step, steps.len(), stop.is_some())?];
        let load_factor = step.load_factor;
        let modal = modes_with(model, step, count, &modal_opts)
            .map_err(|e| errors::modal(&e).in_stage("modal analysis failed"))?;
        Ok::<_, Failure>((a, load_factor, modal, stop))
    });
    let (a, load_factor, modal, stop) = run.map_err(|f| f.into_py(py))?;
    let end = last_step(&a);
    let result = ModesResult {
        note: note(&a, &stop),
        model: loaded,
        load_factor,
        modal,
    };
    finish(py, result, end, stop)
}

#[pymethods]
impl ModesResult {
    fn __repr__(&self) -> String {
        let f: Vec<String> = self
            .modal
            .modes
            .iter()
            .take(4)
            .map(|m| format!("{:.4}", m.frequency))
            .collect();
        format!(
            "<flexmbd.ModesResult: {} modes, {} Hz{}>",
            self.modal.modes.len(),
            f.join(", "),
            if self.modal.modes.len() > 4 {
                ", …"
            } else {
                ""
            }
        )
    }

    /// Natural frequencies [Hz], ascending (NaN for ω² < 0: an unstable state).
    #[getter]
    fn frequencies(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.modal.modes.iter().map(|m| m.frequency).collect())
    }

    /// Eigenvalues ω² [rad²/s²].
    #[getter]
    fn eigenvalues(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.modal.modes.iter().map(|m| m.eigenvalue).collect())
    }

    /// Which modes are rigid-body modes.
    #[getter]
    fn rigid_body(&self) -> Vec<bool> {
        self.modal.modes.iter().map(|m| m.rigid_body).collect()
    }

    /// The class of each mode: `intended`, `support`, `internal` or `rigid_body`
    /// (docs/dynamics.md "Mode classes").
    #[getter]
    fn classes(&self) -> Vec<&'static str> {
        self.modal.modes.iter().map(|m| m.class.name()).collect()
    }

    /// Body fraction β of each mode: the share of its kinetic energy in the point masses and
    /// inertias on nodes.
    #[getter]
    fn body_fractions(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(
            py,
            self.modal.modes.iter().map(|m| m.fractions.body).collect(),
        )
    }

    /// Released fraction ρ of each mode: the share of its strain energy in the deformations the
    /// kinematic analysis releases (`free`, `input`); NaN for a rigid-body mode.
    #[getter]
    fn released_fractions(&self, py: Python<'_>) -> Py<PyAny> {
        let r = self.modal.modes.iter();
        vec1(
            py,
            r.map(|m| m.fractions.released.unwrap_or(f64::NAN))
                .collect(),
        )
    }

    /// Mode shapes by node: (modes, nodes, 6): translation x, y, z and rotation x, y, z of
    /// each node (mass-normalised).
    #[getter]
    fn shapes(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let n = self.model.static_file().map_or(0, |f| f.model.nodes.len());
        let data = self
            .modal
            .modes
            .iter()
            .flat_map(|m| m.nodal.iter().flat_map(|(u, w)| u.iter().chain(w).copied()))
            .collect();
        array(py, data, &[self.modal.modes.len(), n, 6])
    }

    /// Strain energy fraction of each element in each mode, (modes, elements).
    #[getter]
    fn strain_energy(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let ne = self
            .model
            .static_file()
            .map_or(0, |f| f.model.elements.len());
        let mut data = vec![0.0; self.modal.modes.len() * ne];
        for (k, m) in self.modal.modes.iter().enumerate() {
            for &(el, _, f) in &m.strain {
                data[k * ne + el] += f;
            }
        }
        array(py, data, &[self.modal.modes.len(), ne])
    }

    /// Kinetic energy fraction of each node in each mode, (modes, nodes, 2): translation and
    /// rotation.
    #[getter]
    fn kinetic_energy(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let nn = self.model.static_file().map_or(0, |f| f.model.nodes.len());
        let mut data = vec![0.0; self.modal.modes.len() * nn * 2];
        for (k, m) in self.modal.modes.iter().enumerate() {
            for &(n, t, r) in &m.kinetic {
                data[(k * nn + n) * 2] = t;
                data[(k * nn + n) * 2 + 1] = r;
            }
        }
        array(py, data, &[self.modal.modes.len(), nn, 2])
    }

    /// Load factor of the static state the modes are about.
    #[getter]
    fn load_factor(&self) -> f64 {
        self.load_factor
    }

    /// Number of degrees of freedom of the linearised model.
    #[getter]
    fn ndof(&self) -> usize {
        self.modal.ndof
    }

    /// The report as a dict: the structure of `flexmbd modes --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let l = &self.model;
        let file = l.static_file().map_err(|f| f.into_py(py))?;
        json(
            py,
            &modes_json(
                &file.model,
                &l.file,
                self.load_factor,
                &self.modal,
                self.note.as_ref(),
            ),
        )
    }
}
