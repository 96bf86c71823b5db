//! `flexmbd.States`: a sequence of states (the load steps of a static path, the output times
//! of a simulation) as NumPy arrays by node and by element, from the core's shared result
//! tables (`flexmbd_core::results`, the numbers of the JSON reports).

use crate::convert::array;
use flexmbd_core::results::{element_results, node_results, ElementResult, NodeResult};
use flexmbd_core::statics::StepResult;
use flexmbd_core::Model;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// States by node and by element: arrays with the state (load step or output time) first.
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "States")]
pub struct States {
    /// Node names.
    nodes: Vec<String>,
    /// Element names.
    elements: Vec<String>,
    /// Load factor (statics) or time (simulation) of each state.
    param: Vec<f64>,
    /// Elastic energy of each state.
    energy: Vec<f64>,
    /// Per state, per node.
    node_rows: Vec<Vec<NodeResult>>,
    /// Per state, per element.
    element_rows: Vec<Vec<ElementResult>>,
}

impl States {
    /// The tables of `steps` of `model`.
    pub fn new<'a>(model: &Model, steps: impl Iterator<Item = &'a StepResult>) -> Self {
        let mut s = States {
            nodes: model.node_names(),
            elements: model.elements.iter().map(|e| e.name.clone()).collect(),
            param: Vec::new(),
            energy: Vec::new(),
            node_rows: Vec::new(),
            element_rows: Vec::new(),
        };
        for st in steps {
            s.param.push(st.load_factor);
            s.energy.push(st.energy);
            s.node_rows.push(node_results(model, st));
            s.element_rows.push(element_results(model, st));
        }
        s
    }

    /// Number of states.
    pub fn len(&self) -> usize {
        self.param.len()
    }

    /// (states, nodes, 3) of a per-node triple; NaN where a node has none.
    fn node_field(
        &self,
        py: Python<'_>,
        f: impl Fn(&NodeResult) -> Option<[f64; 3]>,
    ) -> PyResult<Py<PyAny>> {
        let data = self
            .node_rows
            .iter()
            .flatten()
            .flat_map(|n| f(n).unwrap_or([f64::NAN; 3]))
            .collect();
        array(py, data, &[self.len(), self.nodes.len(), 3])
    }

    /// {element: (states, modes)} of a per-element vector.
    fn element_field(
        &self,
        py: Python<'_>,
        f: impl Fn(&ElementResult) -> &[f64],
    ) -> PyResult<Py<PyAny>> {
        let d = PyDict::new(py);
        for (j, name) in self.elements.iter().enumerate() {
            let ne = self.element_rows.first().map_or(0, |r| f(&r[j]).len());
            let data = self
                .element_rows
                .iter()
                .flat_map(|r| f(&r[j]).iter().copied())
                .collect();
            d.set_item(name, array(py, data, &[self.len(), ne])?)?;
        }
        Ok(d.into_any().unbind())
    }
}

#[pymethods]
impl States {
    fn __len__(&self) -> usize {
        self.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<flexmbd.States: {} states of {} nodes and {} elements>",
            self.len(),
            self.nodes.len(),
            self.elements.len()
        )
    }

    /// Node names (the second axis of the nodal arrays).
    #[getter]
    fn node_names(&self) -> Vec<String> {
        self.nodes.clone()
    }

    /// Element names (the keys of the element dicts, the second axis of `max_stress`).
    #[getter]
    fn element_names(&self) -> Vec<String> {
        self.elements.clone()
    }

    /// Load factor of each state (statics) or its time [s] (simulation).
    #[getter]
    fn parameter<'py>(&self, py: Python<'py>) -> Py<PyAny> {
        crate::convert::vec1(py, self.param.clone())
    }

    /// Elastic (strain) energy of each state [J].
    #[getter]
    fn energy<'py>(&self, py: Python<'py>) -> Py<PyAny> {
        crate::convert::vec1(py, self.energy.clone())
    }

    /// Node positions [m], (states, nodes, 3).
    #[getter]
    fn positions(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_field(py, |n| Some(n.position))
    }

    /// Displacements from the reference [m], (states, nodes, 3).
    #[getter]
    fn displacements(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_field(py, |n| Some(n.displacement))
    }

    /// Rotation vectors (axis × angle, global axes) [rad], (states, nodes, 3); NaN for nodes
    /// without rotation.
    #[getter]
    fn rotations(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_field(py, |n| n.rotation)
    }

    /// Support reaction forces [N], (states, nodes, 3); NaN at nodes without a held position.
    #[getter]
    fn reaction_forces(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_field(py, |n| n.reaction_force)
    }

    /// Support reaction moments [N·m], (states, nodes, 3); NaN at nodes without a held
    /// rotation.
    #[getter]
    fn reaction_moments(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.node_field(py, |n| n.reaction_moment)
    }

    /// Deformations e by element: {name: (states, modes)}.
    #[getter]
    fn deformations(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.element_field(py, |e| &e.e)
    }

    /// Stress resultants σ by element: {name: (states, modes)} (beam: σ1 axial force [N], σ2
    /// torque/l0, σ3..σ6 bending end moments/l0 [N]).
    #[getter]
    fn stress_resultants(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        self.element_field(py, |e| &e.sigma)
    }

    /// Largest normal stress of each element with a section [Pa], (states, elements); NaN
    /// for elements without one.
    #[getter]
    fn max_stress(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let data = self
            .element_rows
            .iter()
            .flatten()
            .map(|e| e.max_stress.unwrap_or(f64::NAN))
            .collect();
        array(py, data, &[self.len(), self.elements.len()])
    }
}
