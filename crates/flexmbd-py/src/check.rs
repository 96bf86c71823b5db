//! `Model.check()`: the kinematic analysis (`kinematics::classify`, as `flexmbd check`) and its
//! result `flexmbd.CheckResult`.

use crate::convert::{json, mat, vec1};
use crate::errors::{self, Failure};
use crate::model::{Loaded, PyModel};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::kinematics::classify::{classify_intended, Classification, ClassifyOptions};
use flexmbd_core::kinematics::{CheckMethod, CheckOptions, ConstraintAnalysis};
use flexmbd_io::report::{generalised_names, write_check_json, CheckReport};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

/// The result of a kinematic check.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "CheckResult")]
pub struct CheckResult {
    model: Arc<Loaded>,
    rank_tol: f64,
    c: Classification,
}

/// The kinematic check: SVD of Dcc, Table 1 class, motions, self-stresses, verified advice.
#[pyfunction]
#[pyo3(signature = (model, rank_tol=None, auto=false, max_suggestions=6, method="auto"))]
pub fn check(
    py: Python<'_>,
    model: &PyModel,
    rank_tol: Option<f64>,
    auto: bool,
    max_suggestions: usize,
    method: &str,
) -> PyResult<CheckResult> {
    let loaded = model.inner.clone();
    let method = match method {
        "auto" => CheckMethod::Auto,
        "dense" => CheckMethod::Dense,
        "sparse" => CheckMethod::Sparse,
        other => {
            return Err(Failure::option(
                "method",
                format!("method must be \"auto\", \"dense\" or \"sparse\", found {other:?}"),
            )
            .into_py(py))
        }
    };
    let opts = CheckOptions {
        rank_tol: rank_tol.unwrap_or(CheckOptions::default().rank_tol),
        method,
        ..Default::default()
    };
    if !(opts.rank_tol.is_finite() && opts.rank_tol >= 0.0) {
        return Err(Failure::option(
            "rank_tol",
            format!(
                "rank_tol must be a finite number >= 0, found {}",
                opts.rank_tol
            ),
        )
        .into_py(py));
    }
    let rank_tol = opts.rank_tol;
    let classify_opts = ClassifyOptions {
        check: opts,
        auto,
        max_suggestions,
    };
    let l = loaded.clone();
    let c = py
        .detach(move || classify_intended(&l.check, &classify_opts, &l.freedom(), |_| {}))
        .map_err(|e| errors::classify(&e).into_py(py))?;
    Ok(CheckResult {
        model: loaded,
        rank_tol,
        c,
    })
}

impl CheckResult {
    fn a(&self) -> &ConstraintAnalysis {
        &self.c.analysis
    }
}

#[pymethods]
impl CheckResult {
    fn __repr__(&self) -> String {
        let a = self.a();
        format!(
            "<flexmbd.CheckResult: Dcc {} x {}, rank {}, {} motion(s), {} self-stress(es): {}>",
            a.m(),
            a.n(),
            a.rank,
            a.n_motions(),
            a.n_self_stresses(),
            a.case.describe()
        )
    }

    /// Dcc: the Jacobian of the rigid and input deformations with respect to the dependent
    /// coordinates (velocity form), rows × cols (paper eq. 9).
    #[getter]
    #[allow(non_snake_case)]
    fn Dcc(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.a().Dcc)
    }

    /// Singular values of Dcc, descending.
    #[getter]
    fn singular_values(&self, py: Python<'_>) -> Py<PyAny> {
        vec1(py, self.a().singular_values.clone())
    }

    /// Numerical rank of Dcc.
    #[getter]
    fn rank(&self) -> usize {
        self.a().rank
    }

    /// The relative rank tolerance used (s_i counts as zero when s_i <= rank_tol * s_1).
    #[getter]
    fn rank_tol(&self) -> f64 {
        self.rank_tol
    }

    /// The absolute threshold of the rank decision.
    #[getter]
    fn rank_threshold(&self) -> f64 {
        self.a().tol
    }

    /// Number of rows (rigid and input deformations) and columns (dependent velocity
    /// coordinates) of Dcc.
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.a().m(), self.a().n())
    }

    /// Names of the rows of Dcc (`element.eK`, K 1-based).
    #[getter]
    fn row_names(&self) -> Vec<String> {
        let m = &self.model.check;
        self.a()
            .rows
            .iter()
            .map(|r| format!("{}.e{}", m.elements[r.element].name, r.mode + 1))
            .collect()
    }

    /// Names of the columns of Dcc (`node.x` … `node.rz`).
    #[getter]
    fn column_names(&self) -> Vec<String> {
        let m = &self.model.check;
        self.a()
            .cols
            .iter()
            .map(|c| format!("{}.{}", m.nodes[c.node].name, c.dof.name()))
            .collect()
    }

    /// Null vectors of Dcc (columns): the kinematically indeterminate motions, cols × motions.
    #[getter]
    #[allow(non_snake_case)]
    fn V(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.a().null_v)
    }

    /// Null vectors of Dccᵀ (columns): the self-stress states, rows × self-stresses.
    #[getter]
    #[allow(non_snake_case)]
    fn U(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        mat(py, &self.a().null_u)
    }

    /// The row of the paper's Table 1 (1 to 4).
    #[getter]
    fn table1_row(&self) -> usize {
        self.a().case.row()
    }

    /// The Table 1 class in words.
    #[getter]
    fn classification(&self) -> &'static str {
        self.a().case.describe()
    }

    /// Number of kinematically indeterminate motions.
    #[getter]
    fn n_motions(&self) -> usize {
        self.a().n_motions()
    }

    /// Number of self-stress states.
    #[getter]
    fn n_self_stresses(&self) -> usize {
        self.a().n_self_stresses()
    }

    /// No motion and no self-stress.
    #[getter]
    fn exactly_constrained(&self) -> bool {
        self.c.is_exact()
    }

    /// The motions by node: per motion {node: [vx, vy, vz, wx, wy, wz]} (nodes that move).
    #[getter]
    fn motions(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let out = pyo3::types::PyList::empty(py);
        for m in &self.a().motions {
            let mut by_node: Vec<(String, [f64; 6])> = Vec::new();
            for v in &m.coordinates {
                let k = match by_node.iter().position(|(n, _)| *n == v.node) {
                    Some(k) => k,
                    None => {
                        by_node.push((v.node.clone(), [0.0; 6]));
                        by_node.len() - 1
                    }
                };
                by_node[k].1[v.dof.index()] = v.value;
            }
            let d = PyDict::new(py);
            for (n, v) in by_node {
                d.set_item(n, vec1(py, v.to_vec()))?;
            }
            out.append(d)?;
        }
        Ok(out.into_any().unbind())
    }

    /// The self-stress states by element: per state {element: stress values of its modes}.
    #[getter]
    fn self_stresses(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let model = &self.model.check;
        let out = pyo3::types::PyList::empty(py);
        for s in &self.a().self_stresses {
            let mut by_el: Vec<(String, Vec<f64>)> = Vec::new();
            for v in &s.deformations {
                let k = match by_el.iter().position(|(n, _)| *n == v.element) {
                    Some(k) => k,
                    None => {
                        let ne = model
                            .elements
                            .iter()
                            .find(|e| e.name == v.element)
                            .map_or(v.mode, |e| e.element.ne());
                        by_el.push((v.element.clone(), vec![0.0; ne.max(v.mode)]));
                        by_el.len() - 1
                    }
                };
                if let Some(slot) = by_el[k].1.get_mut(v.mode.wrapping_sub(1)) {
                    *slot = v.value;
                }
            }
            let d = PyDict::new(py);
            for (n, v) in by_el {
                d.set_item(n, vec1(py, v))?;
            }
            out.append(d)?;
        }
        Ok(out.into_any().unbind())
    }

    /// The names of the generalised coordinates (inputs) of the analysed partition.
    #[getter]
    fn generalised_coordinates(&self) -> Vec<String> {
        let p = &self.c.partition;
        generalised_names(&self.model.check, &p.x, &p.e)
    }

    /// The verified repair advice: per motion or self-stress state, the suggestions (as in
    /// `to_dict()["suggestions"]`).
    #[getter]
    fn advice(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        json(
            py,
            &serde_json::to_value(&self.c.advice).unwrap_or_default(),
        )
    }

    /// The generalised coordinates chosen with `auto=True` (None otherwise).
    #[getter]
    fn auto_chosen(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        match &self.c.chosen {
            Some(c) => json(py, &serde_json::to_value(c).unwrap_or_default()),
            None => Ok(py.None()),
        }
    }

    /// The report as a dict: the structure of `flexmbd check --json`.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let l = &self.model;
        let report = CheckReport::of(&l.check, &l.file, self.rank_tol, &self.c);
        let p = &self.c.partition;
        let names = generalised_names(&l.check, &p.x, &p.e);
        let mut buf = Vec::new();
        write_check_json(&mut buf, &report, &names)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        let doc: serde_json::Value = serde_json::from_slice(&buf)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        json(py, &doc)
    }
}
