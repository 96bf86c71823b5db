//! flexmbd's errors as Python exceptions (the classes live in `flexmbd/_errors.py`): one class
//! per kind, with the file, line and item of invalid input, and what to try of a numerical
//! failure spelled as Python keyword arguments (core's messages are neutral; the CLI adds its
//! flags in `flexmbd-cli/src/hints.rs`, this module adds the keywords).

use flexmbd_core::dynamics::state_space::StateSpaceError;
use flexmbd_core::dynamics::ModalError;
use flexmbd_core::kinematics::classify::{ClassifyError, Stage};
use flexmbd_core::kinematics::KinematicsError;
use flexmbd_core::statics::linear::LinearError;
use flexmbd_core::statics::SolveError;
use flexmbd_io::InputError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyModule;

/// The kind of a failure: one Python exception class each.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Invalid model data (`flexmbd.ModelError`, a `ValueError`).
    Model,
    /// An argument of an analysis that does not fit the model (`flexmbd.OptionError`, a
    /// `ValueError`).
    Option,
    /// A numerical failure (`flexmbd.NumericalError`, a `RuntimeError`).
    Numerical,
    /// A static path that stopped part-way, with the converged steps
    /// (`flexmbd.PathStoppedError`, a `NumericalError`).
    PathStopped,
    /// A time simulation that stopped before its end time, with the frames up to then
    /// (`flexmbd.SimulationStoppedError`, a `NumericalError`).
    SimulationStopped,
    /// A dense analysis above its memory limit (`flexmbd.TooLargeError`, a `MemoryError`).
    TooLarge,
    /// A file that cannot be read (`flexmbd.ReadError`, an `OSError`).
    Read,
}

impl Kind {
    fn class(self) -> &'static str {
        match self {
            Kind::Model => "ModelError",
            Kind::Option => "OptionError",
            Kind::Numerical => "NumericalError",
            Kind::PathStopped => "PathStoppedError",
            Kind::SimulationStopped => "SimulationStoppedError",
            Kind::TooLarge => "TooLargeError",
            Kind::Read => "ReadError",
        }
    }
}

/// A failure, free of Python objects (it crosses the release of the GIL); [`Failure::into_py`]
/// makes the exception. Boxed: it travels in `Result`s.
#[derive(Clone, Debug)]
pub struct Failure(Box<Details>);

impl std::ops::Deref for Failure {
    type Target = Details;
    fn deref(&self) -> &Details {
        &self.0
    }
}

impl std::ops::DerefMut for Failure {
    fn deref_mut(&mut self) -> &mut Details {
        &mut self.0
    }
}

/// What a [`Failure`] says.
#[derive(Clone, Debug)]
pub struct Details {
    /// Which exception class.
    pub kind: Kind,
    /// What is wrong.
    pub message: String,
    /// Model file.
    pub file: Option<String>,
    /// 1-based line in the file.
    pub line: Option<usize>,
    /// 1-based column in the file.
    pub column: Option<usize>,
    /// The node, element or option concerned.
    pub item: Option<String>,
    /// Which analysis or stage failed.
    pub stage: Option<String>,
    /// What to try, in Python words.
    pub hint: Option<String>,
}

impl Failure {
    /// A failure of `kind` with a message and nothing else known.
    pub fn new(kind: Kind, message: impl Into<String>) -> Self {
        Failure(Box::new(Details {
            kind,
            message: message.into(),
            file: None,
            line: None,
            column: None,
            item: None,
            stage: None,
            hint: None,
        }))
    }

    /// An argument that does not fit: `OptionError` naming the keyword `item`.
    pub fn option(item: &str, message: impl Into<String>) -> Self {
        let mut f = Failure::new(Kind::Option, message);
        f.item = Some(item.to_string());
        f
    }

    /// The same failure with a stage ("modal analysis") in front of its message.
    pub fn in_stage(mut self, stage: &str) -> Self {
        self.message = format!("{stage}: {}", self.message);
        self.stage = Some(stage.to_string());
        self
    }

    /// The Python exception.
    pub fn into_py(self, py: Python<'_>) -> PyErr {
        self.into_py_with(py, None)
    }

    /// The Python exception, carrying the results up to the failure as its `result`.
    pub fn into_py_with(self, py: Python<'_>, result: Option<Py<PyAny>>) -> PyErr {
        match self.build(py, result) {
            Ok(e) => e,
            Err(e) => e,
        }
    }

    fn build(self, py: Python<'_>, result: Option<Py<PyAny>>) -> PyResult<PyErr> {
        let d = *self.0;
        let text = match &d.hint {
            Some(h) => format!("{}\nhint: {h}", d.message),
            None => d.message.clone(),
        };
        let exc = errors_module(py)?.getattr(d.kind.class())?.call1((text,))?;
        exc.setattr("file", d.file)?;
        exc.setattr("line", d.line)?;
        exc.setattr("column", d.column)?;
        exc.setattr("item", d.item)?;
        exc.setattr("stage", d.stage)?;
        exc.setattr("hint", d.hint)?;
        exc.setattr("result", result)?;
        Ok(PyErr::from_value(exc))
    }
}

impl From<Failure> for PyErr {
    fn from(f: Failure) -> PyErr {
        Python::attach(|py| f.into_py(py))
    }
}

static ERRORS: PyOnceLock<Py<PyModule>> = PyOnceLock::new();

/// `flexmbd._errors`, imported once.
fn errors_module(py: Python<'_>) -> PyResult<&Bound<'_, PyModule>> {
    ERRORS
        .get_or_try_init(py, || py.import("flexmbd._errors").map(|m| m.unbind()))
        .map(|m| m.bind(py))
}

/// The first name in backticks of a message (the item that messages of the readers and the
/// core name: "element `b1`: node `n9` is not defined" → `b1`).
pub fn first_quoted(message: &str) -> Option<String> {
    let start = message.find('`')? + 1;
    let len = message[start..].find('`')?;
    Some(message[start..start + len].to_string())
}

/// A model file error: `ModelError` with file, line, column and item (`ReadError` for a file
/// that cannot be read).
pub fn input(e: InputError) -> Failure {
    let text = e.to_string();
    match e {
        InputError::Read { file, .. } => {
            let mut f = Failure::new(Kind::Read, text);
            f.file = Some(file);
            f
        }
        InputError::At {
            file,
            line,
            column,
            message,
        } => {
            let mut f = Failure::new(Kind::Model, text);
            f.item = first_quoted(&message);
            f.file = Some(file);
            f.line = Some(line);
            f.column = Some(column);
            f
        }
        InputError::File { file, message } => {
            let mut f = Failure::new(Kind::Model, text);
            f.item = first_quoted(&message);
            f.file = Some(file);
            f
        }
    }
}

/// The kind of a core error: too large, or numerical.
fn kind_of(too_large: bool) -> Kind {
    if too_large {
        Kind::TooLarge
    } else {
        Kind::Numerical
    }
}

/// A failed static path.
pub fn solve(e: &SolveError) -> Failure {
    let mut f = Failure::new(Kind::Numerical, e.to_string());
    f.hint = solve_hint(e).map(str::to_string);
    f
}

/// What to try after a static path failed with `e`, as keyword arguments.
pub fn solve_hint(e: &SolveError) -> Option<&'static str> {
    match e {
        SolveError::NoConvergence { .. } => Some(
            "more load steps: steps=N (or `steps` in the model's [static] table); at a limit point (snap-through) follow the path by arc length: path=\"arc-length\" (or `path = \"arc-length\"` in [static])",
        ),
        SolveError::Inverted { .. } => {
            Some("more load steps: steps=N (or `steps` in the model's [static] table)")
        }
        _ => None,
    }
}

/// A failed modal analysis.
pub fn modal(e: &ModalError) -> Failure {
    let mut f = Failure::new(kind_of(matches!(e, ModalError::TooLarge(_))), e.to_string());
    f.hint = modal_hint(e).map(str::to_string);
    f
}

fn modal_hint(m: &ModalError) -> Option<&'static str> {
    match m {
        ModalError::NoMass => Some(
            "in a TOML model: a [[material]] with `rho` for the beams, or [[mass]] / [[inertia]] entries",
        ),
        ModalError::DenseInaccurate { .. } => Some("use solver=\"sparse\""),
        ModalError::TooLarge(_) => Some(
            "use solver=\"sparse\" (or \"auto\"), which computes the lowest count=N modes only",
        ),
        ModalError::TooManyModes { .. } => Some(
            "ask for fewer modes (count=N, at most a third of the degrees of freedom), or choose the solver explicitly: solver=\"sparse\" (slow for many modes) or solver=\"dense\"",
        ),
        ModalError::SparseSingular => {
            Some("run model.check() on the model, or use solver=\"dense\"")
        }
        ModalError::NotConverged { .. } => {
            Some("ask for fewer modes (count=N), or use solver=\"dense\"")
        }
        _ => None,
    }
}

/// A failed state-space model.
pub fn state_space(e: &StateSpaceError) -> Failure {
    if let StateSpaceError::Modal(m) = e {
        let mut f = modal(m);
        if let ModalError::TooLarge(_) = m {
            f.hint = Some(
                "use solver=\"sparse\" (or \"auto\") with modes=N (e.g. modes=20), and static_correction=True for the exact static gain".into(),
            );
        }
        return f;
    }
    let mut f = Failure::new(Kind::Numerical, e.to_string());
    f.hint = match e {
        StateSpaceError::SparseNeedsModes { .. } => Some(
            "give modes=N (e.g. modes=20), with static_correction=True for the exact static gain",
        ),
        StateSpaceError::NoRotation { .. } => {
            Some("in a TOML model, `rot = true` gives a node rotation coordinates")
        }
        _ => None,
    }
    .map(str::to_string);
    f
}

/// A failed kinematic check.
pub fn classify(e: &ClassifyError) -> Failure {
    let too_large = matches!(e.source, KinematicsError::TooLarge { .. });
    let mut f = Failure::new(kind_of(too_large), format!("{e}: {}", e.source));
    if let KinematicsError::NoConstraintRows = e.source {
        f.kind = Kind::Model;
        f.hint = Some("leave a deformation mode out of an element's `free` list".into());
    } else if e.stage == Stage::Check && !too_large {
        f.hint = Some("check the model for NaN coordinates, or try another rank_tol".into());
    }
    f
}

/// A refused linearised static result (compliance, buckling).
pub fn linear(e: &LinearError) -> Failure {
    let mut f = Failure::new(
        kind_of(matches!(e, LinearError::TooLarge(_))),
        e.to_string(),
    );
    if let LinearError::TooLarge(_) = e {
        f.hint = Some(
            "leave out compliance=… and buckling=… (and `compliance`, `buckling` in the model's [static] table), or use a model with fewer elements".into(),
        );
    }
    f
}

/// An argument of an analysis that does not fit the model (the io parser's messages).
pub fn request(item: &str, e: flexmbd_io::requests::RequestError) -> Failure {
    Failure::option(item, e.0)
}
