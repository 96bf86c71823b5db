//! The model as Python holds it: the source text (TOML or SPACAR `.dat`) and what the readers
//! the command line uses make of it (the model of the kinematic check, the model with its
//! analysis settings, and for a `.dat` file the model of the time simulation, built when first
//! asked for). Immutable and shared (`Arc`): safe from several threads.

use crate::errors::{self, Failure};
use flexmbd_io::{ModelFile, SpacarModel};
use pyo3::prelude::*;
use std::sync::{Arc, OnceLock};

/// The format of a model's source text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// The native TOML format (docs/model-format.md).
    Toml,
    /// A SPACAR input file (docs/spacar-import.md).
    Dat,
}

impl Format {
    fn name(self) -> &'static str {
        match self {
            Format::Toml => "toml",
            Format::Dat => "dat",
        }
    }

    /// The format of a file by its extension, as the command line reads it.
    fn of_path(path: &str) -> Result<Format, Failure> {
        let ext = std::path::Path::new(path)
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("toml") => Ok(Format::Toml),
            Some("dat") => Ok(Format::Dat),
            _ => {
                let mut f = Failure::option(
                    "path",
                    format!(
                        "{path}: unknown model format (expected a .toml file or a SPACAR .dat file)"
                    ),
                );
                f.file = Some(path.to_string());
                Err(f)
            }
        }
    }
}

/// A model read from its source, with everything the analyses need.
pub struct Loaded {
    /// The source text (empty for a model built from a document).
    pub text: String,
    /// The file name used in messages and reports.
    pub file: String,
    /// Its format.
    pub format: Format,
    /// The model of the kinematic check (for a `.dat` file: its `DYNE` deformations and `DYNX`
    /// coordinates as inputs, as SPACAR's kinematic analysis).
    pub check: flexmbd_core::Model,
    /// The model with its static data and settings (statics, modes, state space); an error for
    /// a `.dat` file whose static data cannot be mapped.
    static_file: Result<ModelFile, Failure>,
    /// A `.dat` file's parsed form, for the time-simulation model.
    spacar: Option<SpacarModel>,
    /// The time-simulation model of a `.dat` file, built when first asked for.
    dynamic: OnceLock<Result<(ModelFile, Vec<String>), Failure>>,
    /// The warnings of reading and mapping (`file:line: message`).
    pub warnings: Vec<String>,
}

fn warning_lines(m: &SpacarModel, w: &[flexmbd_io::spacar::Warning]) -> Vec<String> {
    w.iter()
        .map(|w| {
            format!(
                "{}:{}: {}",
                m.file,
                w.line,
                flexmbd_io::error::printable(&w.message)
            )
        })
        .collect()
}

impl Loaded {
    /// The intended freedom of the kinematic check (`[[freedom]]` of a TOML model; none for a
    /// `.dat` file).
    pub fn freedom(&self) -> Vec<flexmbd_core::kinematics::freedom::IntendedFreedom> {
        match (&self.format, &self.static_file) {
            (Format::Toml, Ok(f)) => f.freedom.clone(),
            _ => Vec::new(),
        }
    }

    /// Read `text` (named `file` in messages) in `format`.
    pub fn parse(text: String, file: String, format: Format) -> Result<Loaded, Failure> {
        match format {
            Format::Toml => {
                let mf = flexmbd_io::parse_model_file(&text, &file).map_err(errors::input)?;
                let mut l = Loaded::built(mf, file);
                l.text = text;
                Ok(l)
            }
            Format::Dat => {
                let sm = flexmbd_io::parse_dat(&text, &file).map_err(errors::input)?;
                let check = sm.to_model().map_err(errors::input)?;
                let mut warnings = warning_lines(&sm, &sm.warnings);
                let static_file = sm
                    .to_model_file()
                    .map(|(mf, w)| {
                        warnings.extend(warning_lines(&sm, &w));
                        mf
                    })
                    .map_err(errors::input);
                Ok(Loaded {
                    check,
                    static_file,
                    spacar: Some(sm),
                    dynamic: OnceLock::new(),
                    warnings,
                    text,
                    file,
                    format,
                })
            }
        }
    }

    /// A model built from a document (no source text: the document holds the model).
    pub fn built(mf: ModelFile, file: String) -> Loaded {
        Loaded {
            check: mf.model.clone(),
            static_file: Ok(mf),
            spacar: None,
            dynamic: OnceLock::new(),
            warnings: Vec::new(),
            text: String::new(),
            file,
            format: Format::Toml,
        }
    }

    /// The text of a model file and its format by its extension (`.toml` or `.dat`), as the
    /// command line reads it.
    pub fn read_text(path: &str) -> Result<(String, Format), Failure> {
        let format = Format::of_path(path)?;
        let bytes = std::fs::read(path).map_err(|source| {
            errors::input(flexmbd_io::InputError::Read {
                file: path.to_string(),
                source,
            })
        })?;
        let text = match format {
            // a .dat file's bytes that are not UTF-8 are replaced, as `read_dat` does
            Format::Dat => String::from_utf8_lossy(&bytes).into_owned(),
            Format::Toml => match String::from_utf8(bytes) {
                Ok(t) => t,
                // the reader's own message, with line and column
                Err(_) => {
                    return Err(errors::input(
                        flexmbd_io::read_model_file(std::path::Path::new(path))
                            .err()
                            .unwrap_or_else(|| flexmbd_io::InputError::File {
                                file: path.to_string(),
                                message: "the file is not UTF-8".into(),
                            }),
                    ))
                }
            },
        };
        Ok((text, format))
    }

    /// The model and settings of statics, modes and state spaces.
    pub fn static_file(&self) -> Result<&ModelFile, Failure> {
        self.static_file.as_ref().map_err(Clone::clone)
    }

    /// The model and settings of the time simulation, with the warnings of its mapping.
    pub fn dynamic_file(&self) -> Result<(&ModelFile, &[String]), Failure> {
        let Some(sm) = &self.spacar else {
            return self.static_file().map(|f| (f, &[][..]));
        };
        self.dynamic
            .get_or_init(|| {
                sm.to_dynamic_model_file()
                    .map(|(mf, w)| (mf, warning_lines(sm, &w)))
                    .map_err(errors::input)
            })
            .as_ref()
            .map(|(f, w)| (f, &w[..]))
            .map_err(Clone::clone)
    }
}

/// The compiled model (the Python class `flexmbd.Model` wraps it).
#[pyclass(frozen, module = "flexmbd._flexmbd", name = "CoreModel")]
pub struct PyModel {
    /// The shared, immutable model.
    pub inner: Arc<Loaded>,
}

fn warn_all(py: Python<'_>, lines: &[String]) -> PyResult<()> {
    if lines.is_empty() {
        return Ok(());
    }
    let category = py.import("flexmbd._errors")?.getattr("FlexmbdWarning")?;
    let warnings = py.import("warnings")?;
    for l in lines {
        warnings.call_method1("warn", (l, &category, 2))?;
    }
    Ok(())
}

impl PyModel {
    /// Wrap a loaded model, issuing its warnings.
    pub fn new(py: Python<'_>, loaded: Loaded) -> PyResult<Self> {
        warn_all(py, &loaded.warnings)?;
        Ok(PyModel {
            inner: Arc::new(loaded),
        })
    }

    /// The warnings of the simulation model's mapping, issued as Python warnings.
    pub fn warn(py: Python<'_>, lines: &[String]) -> PyResult<()> {
        warn_all(py, lines)
    }
}

/// Read model text in a format (`"toml"` or `"dat"`), named `file` in messages.
#[pyfunction]
pub fn parse(py: Python<'_>, text: String, file: String, format: &str) -> PyResult<PyModel> {
    let format = match format {
        "toml" => Format::Toml,
        "dat" => Format::Dat,
        other => {
            return Err(Failure::option(
                "format",
                format!("unknown model format `{other}` (expected \"toml\" or \"dat\")"),
            )
            .into_py(py))
        }
    };
    let loaded = py
        .detach(move || Loaded::parse(text, file, format))
        .map_err(|f| f.into_py(py))?;
    PyModel::new(py, loaded)
}

#[pymethods]
impl PyModel {
    /// The source text, its file name and format: what a pickle carries.
    fn source(&self) -> (String, String, &'static str) {
        let l = &self.inner;
        (l.text.clone(), l.file.clone(), l.format.name())
    }

    /// The model's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.check.name.clone()
    }

    /// The file name used in messages and reports.
    #[getter]
    fn file(&self) -> String {
        self.inner.file.clone()
    }

    /// `"toml"` or `"dat"`.
    #[getter]
    fn format(&self) -> &'static str {
        self.inner.format.name()
    }

    /// Node names in model order.
    #[getter]
    fn node_names(&self) -> Vec<String> {
        self.inner.check.node_names()
    }

    /// Element names in model order.
    #[getter]
    fn element_names(&self) -> Vec<String> {
        let m = &self.inner.check;
        m.elements.iter().map(|e| e.name.clone()).collect()
    }

    /// Element types in model order (`truss`, `beam`, `hinge`, `rigid`).
    #[getter]
    fn element_types(&self) -> Vec<String> {
        let m = &self.inner.check;
        m.elements
            .iter()
            .map(|e| e.element.type_name().to_string())
            .collect()
    }

    /// Number of nodal coordinates x (positions and Euler parameters).
    #[getter]
    fn n_coordinates(&self) -> usize {
        self.inner.check.x0().len()
    }

    /// Number of deformations e.
    #[getter]
    fn n_deformations(&self) -> usize {
        self.inner.check.partition.e.len()
    }

    /// Names of the nodal coordinates (`node.x`, …, `node.l0` … `node.l3`).
    #[getter]
    fn coordinate_names(&self) -> Vec<String> {
        let m = &self.inner.check;
        let mut names = vec![String::new(); m.x0().len()];
        for n in &m.nodes {
            for (k, c) in ["x", "y", "z"].iter().enumerate() {
                if let Some(s) = names.get_mut(n.ix_pos + k) {
                    if s.is_empty() {
                        *s = format!("{}.{c}", n.name);
                    }
                }
            }
            if let Some(r) = n.ix_rot {
                for k in 0..4 {
                    if let Some(s) = names.get_mut(r + k) {
                        *s = format!("{}.l{k}", n.name);
                    }
                }
            }
        }
        names
    }

    /// The warnings of reading the file (`file:line: message`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
}
