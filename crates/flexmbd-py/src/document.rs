//! The model document as Python holds it: a [`ModelSpec`] (the document every reader
//! produces, crates/flexmbd-io/src/spec) that Python builds and edits by names, and the core
//! model built from it when an analysis first asks ([`ModelSpec::build_file`], the one build
//! of the command line's readers), kept until the next edit.
//!
//! Edits arrive as the document's serialised items (serde JSON with the keys of the TOML
//! format, `{"id": "a", "x": 0.1, …}`): the Python package composes them from keyword
//! arguments, this module deserialises them into the spec's types and calls its edit methods.
//! A document is shared (`Mutex`): safe from several threads.

use crate::errors::{self, Failure, Kind};
use crate::model::{Format, Loaded, PyModel};
use flexmbd_io::spec::{
    DofEntry, EditError, ElementEntrySpec, FreedomEntry, InertiaEntry, LoadEntry, MassEntry,
    MaterialSpec, NodeSpec, PrescribeEntry, PrescribeTarget, SectionSpec, VelocityEntry,
};
use flexmbd_io::{ModelSpec, SpecError};
use pyo3::prelude::*;
use serde::de::DeserializeOwned;
use std::sync::{Arc, Mutex, MutexGuard};

/// A document and what is built from it.
#[derive(Clone)]
struct State {
    /// The document.
    spec: ModelSpec,
    /// The file name used in messages and reports.
    file: String,
    /// The text the document was read from (TOML), if it was read.
    source: Option<String>,
    /// The model built from the document since its last edit.
    built: Option<Arc<Loaded>>,
}

/// An editable model document (the Python class `flexmbd.Model` wraps it).
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "Document")]
pub struct Document {
    state: Mutex<State>,
}

/// A failed edit: `ModelError` naming the item (or path).
fn edit_error(e: EditError) -> Failure {
    let item = match &e {
        EditError::NotFound { name, .. } | EditError::Exists { name, .. } => name.clone(),
        EditError::Path { path, .. } => path.clone(),
    };
    let mut f = Failure::new(Kind::Model, e.to_string());
    f.item = Some(item);
    f
}

/// A value that is not of the item's form: `ModelError` naming the item.
fn form_error(what: &str, item: &str, e: serde_json::Error) -> Failure {
    let mut f = Failure::new(Kind::Model, format!("{what} `{item}`: {e}"));
    f.item = Some(item.to_string());
    f
}

/// The item of JSON `json` of type `T`; `what` and `item` name it in errors.
fn item<T: DeserializeOwned>(json: &str, what: &str, name: &str) -> Result<T, Failure> {
    serde_json::from_str(json).map_err(|e| form_error(what, name, e))
}

/// A build error of a document: `ModelError` with the item and, for an item read from a
/// file, its line (the core's neutral message: the document may have been made in Python).
fn build_error(e: SpecError, file: &str) -> Failure {
    let mut f = Failure::new(Kind::Model, format!("{file}: {}", e.message()));
    f.item = errors::first_quoted(&e.message());
    f.file = Some(file.to_string());
    f.line = e.at.map(|p| p.line);
    f.column = e.at.map(|p| p.column);
    f
}

impl Document {
    fn with(state: State) -> Self {
        Document {
            state: Mutex::new(state),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // a panic while holding the lock cannot leave the spec half-edited (edits replace
        // whole items), so a poisoned lock is still a valid document
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Apply `edit` to the spec; the built model is dropped.
    fn edit<R>(&self, edit: impl FnOnce(&mut ModelSpec) -> Result<R, Failure>) -> PyResult<R> {
        let mut s = self.lock();
        let r = edit(&mut s.spec)?;
        s.built = None;
        Ok(r)
    }

    /// A document read from TOML text with the overrides `set` (parameters or paths,
    /// [`flexmbd_io::parse_spec_with`]), built (its errors are the reader's, with line and
    /// column, as on the command line).
    pub fn parse_toml(
        text: String,
        file: String,
        set: &[(String, f64)],
    ) -> Result<Document, Failure> {
        let spec = flexmbd_io::parse_spec_with(&text, &file, set).map_err(errors::input)?;
        let mf = spec
            .build_file()
            .map_err(|e| errors::input(flexmbd_io::model_toml::spec_error(e, &file)))?;
        let built = Loaded::built(mf, file.clone());
        Ok(Document::with(State {
            spec,
            file,
            source: Some(text),
            built: Some(Arc::new(built)),
        }))
    }
}

#[pymethods]
impl Document {
    /// An empty document named `name`; `file` names it in messages.
    #[staticmethod]
    fn empty(name: &str, file: String) -> Self {
        Document::with(State {
            spec: ModelSpec::new(name),
            file,
            source: None,
            built: None,
        })
    }

    /// A document from its JSON form (`to_json()`), with the text it was read from.
    #[staticmethod]
    fn from_json(json: &str, file: String, source: Option<String>) -> PyResult<Self> {
        let spec: ModelSpec = item(json, "model", &file)?;
        Ok(Document::with(State {
            spec,
            file,
            source,
            built: None,
        }))
    }

    /// The document of a SPACAR `.dat` text: the TOML model file that `flexmbd convert` writes
    /// (its time-simulation settings too where they map to the same model), with the
    /// mapping's warnings.
    #[staticmethod]
    fn from_dat(py: Python<'_>, text: String, file: String) -> PyResult<(Self, Vec<String>)> {
        let r = py.detach(move || -> Result<(Self, Vec<String>), Failure> {
            let m = flexmbd_io::spacar::parse_dat(&text, &file).map_err(errors::input)?;
            let (toml, warnings) = m.to_toml_with_warnings().map_err(errors::input)?;
            // the document of the written file (what it cannot express, e.g. beam shear
            // flexibilities, is left out as in the file, and the warnings say so)
            let spec = flexmbd_io::parse_spec(&toml, &file).map_err(errors::input)?;
            let doc = Document::with(State {
                spec,
                file,
                source: None,
                built: None,
            });
            Ok((doc, warnings.iter().map(|w| w.to_string()).collect()))
        });
        r.map_err(|f| f.into_py(py))
    }

    /// The document as JSON (the keys of the TOML format).
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.lock().spec)
            .map_err(|e| Failure::new(Kind::Model, e.to_string()).into())
    }

    /// The document as a TOML model file.
    fn to_toml(&self) -> PyResult<String> {
        let s = self.lock();
        s.spec.to_toml().map_err(|m| {
            let mut f = Failure::new(Kind::Model, format!("{}: {m}", s.file));
            f.item = errors::first_quoted(&m);
            f.into()
        })
    }

    /// An independent copy (the built model is shared until either is edited).
    fn copy(&self) -> Self {
        Document::with(self.lock().clone())
    }

    /// The file name used in messages and reports.
    #[getter]
    fn file(&self) -> String {
        self.lock().file.clone()
    }

    /// The text the document was read from, if it was read.
    #[getter]
    fn source(&self) -> Option<String> {
        self.lock().source.clone()
    }

    /// The parameters the document was evaluated with (`[parameters]`), in file order.
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let d = pyo3::types::PyDict::new(py);
        for (k, v) in &self.lock().spec.parameters {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// The model's name and the numbers of nodes and elements the document states.
    fn summary(&self) -> (String, usize, usize) {
        let s = self.lock();
        (
            s.spec.name.clone(),
            s.spec.nodes.len(),
            s.spec.elements.len(),
        )
    }

    /// The core model, built from the document when first asked for after an edit.
    fn core(&self) -> PyResult<PyModel> {
        let mut s = self.lock();
        if let Some(b) = &s.built {
            return Ok(PyModel { inner: b.clone() });
        }
        let mf = s.spec.build_file().map_err(|e| build_error(e, &s.file))?;
        let built = Arc::new(Loaded::built(mf, s.file.clone()));
        s.built = Some(built.clone());
        Ok(PyModel { inner: built })
    }

    /// The value at `path` as JSON.
    fn get(&self, path: &str) -> PyResult<String> {
        let v = self.lock().spec.get(path).map_err(edit_error)?;
        Ok(v.to_string())
    }

    /// Set the value at `path` to the JSON `json`.
    fn set(&self, path: &str, json: &str) -> PyResult<()> {
        let v: serde_json::Value = item(json, "path", path)?;
        self.edit(|s| s.set(path, v).map_err(edit_error))
    }

    /// Add an item (`node`, `element`, `material`, `section`, `load`, `freedom`) given as JSON.
    fn add(&self, kind: &str, name: &str, json: &str) -> PyResult<()> {
        self.edit(|s| {
            match kind {
                "node" => s.add_node(item::<NodeSpec>(json, kind, name)?),
                "element" => s.add_element(item::<ElementEntrySpec>(json, kind, name)?),
                "material" => s.add_material(item::<MaterialSpec>(json, kind, name)?),
                "section" => s.add_section(item::<SectionSpec>(json, kind, name)?),
                "load" => {
                    s.add_load(item::<LoadEntry>(json, kind, name)?);
                    Ok(())
                }
                "freedom" => {
                    s.add_freedom(item::<FreedomEntry>(json, kind, name)?);
                    Ok(())
                }
                _ => return Err(Failure::option("kind", format!("no item kind `{kind}`"))),
            }
            .map_err(edit_error)
        })
    }

    /// Replace the item (`node`, `element`, `material`, `section`) of the same name.
    fn replace(&self, kind: &str, name: &str, json: &str) -> PyResult<()> {
        self.edit(|s| {
            match kind {
                "node" => s.replace_node(item(json, kind, name)?).map(drop),
                "element" => s.replace_element(item(json, kind, name)?).map(drop),
                "material" => s.replace_material(item(json, kind, name)?).map(drop),
                "section" => s.replace_section(item(json, kind, name)?).map(drop),
                _ => return Err(Failure::option("kind", format!("no item kind `{kind}`"))),
            }
            .map_err(edit_error)
        })
    }

    /// Set the entry of a node (`fix`, `input`, `mass`, `inertia`, `velocity`) or the stroke
    /// of an input (`stroke`), given as JSON, replacing the one it has.
    fn put(&self, kind: &str, name: &str, json: &str) -> PyResult<()> {
        self.edit(|s| {
            match kind {
                "fix" | "input" => {
                    let d: DofEntry = item(json, kind, name)?;
                    match kind {
                        "fix" => s.set_fix(&d.node, d.dofs.as_deref()),
                        _ => s.set_input(&d.node, d.dofs.as_deref()),
                    }
                }
                "mass" => {
                    let m: MassEntry = item(json, kind, name)?;
                    s.set_mass(&m.node, m.m);
                }
                "inertia" => {
                    let i: InertiaEntry = item(json, kind, name)?;
                    s.set_inertia(&i.node, i.i);
                }
                "velocity" => {
                    let v: VelocityEntry = item(json, kind, name)?;
                    s.set_velocity(&v.node, v.v, v.omega);
                }
                "stroke" => {
                    let p: PrescribeEntry = item(json, kind, name)?;
                    s.set_stroke(p.target, p.value);
                }
                _ => return Err(Failure::option("kind", format!("no entry kind `{kind}`"))),
            }
            Ok(())
        })
    }

    /// Remove an item or entry by its name (or node).
    fn remove(&self, kind: &str, name: &str) -> PyResult<()> {
        self.edit(|s| {
            match kind {
                "node" => s.remove_node(name).map(drop),
                "element" => s.remove_element(name).map(drop),
                "material" => s.remove_material(name).map(drop),
                "section" => s.remove_section(name).map(drop),
                "fix" => s.remove_fix(name).map(drop),
                "input" => s.remove_input(name).map(drop),
                "load" => s.remove_loads(name).map(drop),
                "mass" => s.remove_mass(name).map(drop),
                "inertia" => s.remove_inertia(name).map(drop),
                "velocity" => s.remove_velocity(name).map(drop),
                "freedom" => s.remove_freedoms(name).map(drop),
                _ => return Err(Failure::option("kind", format!("no item kind `{kind}`"))),
            }
            .map_err(edit_error)
        })
    }

    /// Remove the stroke of a target given as JSON (`{"node", "dof"}` or `{"element",
    /// "mode"}`).
    fn remove_stroke(&self, name: &str, json: &str) -> PyResult<()> {
        let t: PrescribeTarget = item(json, "stroke", name)?;
        self.edit(|s| s.remove_stroke(&t).map(drop).map_err(edit_error))
    }
}

/// Read a model file: a `Document` for TOML (with the overrides `set`), a `CoreModel` for a
/// SPACAR `.dat` file (which takes none).
#[pyfunction]
#[pyo3(signature = (path, set=Vec::new()))]
pub fn load(py: Python<'_>, path: &str, set: Vec<(String, f64)>) -> PyResult<Py<PyAny>> {
    let path = path.to_string();
    let read = py.detach(move || -> Result<Result<Document, Loaded>, Failure> {
        let (text, format) = Loaded::read_text(&path)?;
        match format {
            Format::Toml => Document::parse_toml(text, path, &set).map(Ok),
            Format::Dat if !set.is_empty() => Err(errors::input(flexmbd_io::InputError::File {
                file: path,
                message: "parameters and overrides (`set`) are a feature of TOML models; convert the SPACAR file first".into(),
            })),
            Format::Dat => Loaded::parse(text, path, Format::Dat).map(Err),
        }
    });
    match read.map_err(|f| f.into_py(py))? {
        Ok(d) => Ok(Py::new(py, d)?.into_any()),
        Err(l) => Ok(Py::new(py, PyModel::new(py, l)?)?.into_any()),
    }
}

/// A document from TOML text, named `file` in messages, with the overrides `set`.
#[pyfunction]
#[pyo3(signature = (text, file, set=Vec::new()))]
pub fn parse_toml(
    py: Python<'_>,
    text: String,
    file: String,
    set: Vec<(String, f64)>,
) -> PyResult<Document> {
    py.detach(move || Document::parse_toml(text, file, &set))
        .map_err(|f| f.into_py(py))
}
