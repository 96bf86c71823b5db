//! The native TOML model format (docs/model-format.md).
//!
//! ```toml
//! [model]
//! name = "12-truss of the paper, Fig. 2"
//! [nodes]                       # id = position [m], or { x = [...], rot = true }, or { at = "s1" }
//! s1 = [1.0, 1.0, 0.0]
//! [fix]
//! s1 = "all"                    # or a list: ["x", "y", "z", "rx", "ry", "rz"]
//! [[truss]]
//! id = "b1"
//! nodes = ["s1", "t2"]
//! [[beam]]
//! id = "w1"
//! nodes = ["g1", "r1"]
//! orient = [0.0, 0.0, 1.0]      # local y axis
//! free = [2, 3, 4, 5, 6]        # deformation modes, numbered as in the paper
//! input = []
//! [[hinge]]
//! id = "h1"
//! nodes = ["a", "b"]
//! axis = [0.0, 0.0, 1.0]
//! free = [1]
//! [[rigid]]
//! id = "platform"
//! nodes = ["r1", "r2", "r3"]
//! [inputs]                      # nodal coordinates that are generalised coordinates
//! r1 = ["x"]
//! ```
//!
//! Units are SI. Unknown keys, missing fields, non-finite numbers, unknown nodes, duplicate ids
//! and degenerate elements are errors naming file, line and item.
//!
//! Reading is: serde reads the file ([`schema`]) → a [`ModelSpec`] with the place of every item
//! (`read.rs`; `spans.rs` names the item of a TOML syntax error) → [`ModelSpec::build_file`],
//! the build every reader uses. Writing ([`write_toml`], `write.rs`) is the reverse: a spec as
//! a TOML file that reads back to the same spec.

pub mod expr;
mod params;
mod pieces;
mod read;
mod schema;
mod spans;
mod write;

pub use crate::spec::{ModelFile, Settings};
pub use write::write_toml;

use crate::error::{at, InputError};
use crate::spec::{ModelSpec, SpecError, SpecErrorKind};
use flexmbd_core::Model;

/// `[simulate]` settings as the readers return them (the former home of
/// [`crate::spec::SimulateSettings`]).
pub mod simulate {
    pub use crate::spec::SimulateSettings;
}

/// Read and compile a TOML model file.
pub fn read_model(path: &std::path::Path) -> Result<Model, InputError> {
    read_model_file(path).map(|f| f.model)
}

/// Parse and compile TOML model text; `file` names it in messages.
pub fn parse_model(text: &str, file: &str) -> Result<Model, InputError> {
    parse_model_file(text, file).map(|f| f.model)
}

/// Read a TOML model file with its analysis settings.
pub fn read_model_file(path: &std::path::Path) -> Result<ModelFile, InputError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    parse_model_file(&text, &file)
}

/// Parse TOML model text with its analysis settings.
pub fn parse_model_file(text: &str, file: &str) -> Result<ModelFile, InputError> {
    parse_spec(text, file)?
        .build_file()
        .map_err(|e| spec_error(e, file))
}

/// Read a TOML model file as a [`ModelSpec`] (not built: edit it, then build or write it).
pub fn read_spec(path: &std::path::Path) -> Result<ModelSpec, InputError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    parse_spec(&text, &file)
}

/// Parse TOML model text as a [`ModelSpec`]; `file` names it in messages. Errors of the file's
/// form (syntax, unknown keys, types, names of degrees of freedom, shapes, settings) are
/// reported here, errors of values and references by [`ModelSpec::build_file`].
pub fn parse_spec(text: &str, file: &str) -> Result<ModelSpec, InputError> {
    read::parse_spec(text, file, &[])
}

/// [`parse_spec`] of one member of a parametric model (docs/model-format.md, "Parameters and
/// expressions"): every `(name, value)` of `set` overrides a value of the file.
///
/// - A plain name (`t`) is a parameter of `[parameters]`: it takes `value` instead of the
///   file's value or expression before anything is evaluated, so the parameters and values
///   that depend on it follow. A name the file does not declare is an error listing the
///   declared ones.
/// - A name with a dot (`sections.sheet.t`, `nodes.c.x`, `loads.tip.force.1`) is a path of
///   the document, set with [`ModelSpec::set`] after the file is evaluated (also in a file
///   without parameters; nothing depends on it).
///
/// The evaluated parameters (the overrides included) are [`ModelSpec::parameters`].
pub fn parse_spec_with(
    text: &str,
    file: &str,
    set: &[(String, f64)],
) -> Result<ModelSpec, InputError> {
    let (paths, names): (Vec<_>, Vec<_>) = set.iter().cloned().partition(|(k, _)| k.contains('.'));
    let mut spec = read::parse_spec(text, file, &names)?;
    for (path, value) in &paths {
        // a whole number is set as one, so that it also fits an integer key (`static.steps`)
        let v = if value.fract() == 0.0 && value.abs() < 9.0e15 {
            serde_json::Value::from(*value as i64)
        } else {
            serde_json::Value::from(*value)
        };
        spec.set(path, v).map_err(|e| InputError::File {
            file: file.into(),
            message: format!("cannot set `{path}` = {value}: {e}"),
        })?;
    }
    Ok(spec)
}

/// [`read_spec`] of one member of a parametric model: see [`parse_spec_with`].
pub fn read_spec_with(
    path: &std::path::Path,
    set: &[(String, f64)],
) -> Result<ModelSpec, InputError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    parse_spec_with(&text, &file, set)
}

/// [`read_model_file`] of one member of a parametric model: see [`parse_spec_with`].
pub fn read_model_file_with(
    path: &std::path::Path,
    set: &[(String, f64)],
) -> Result<ModelFile, InputError> {
    let file = path.display().to_string();
    read_spec_with(path, set)?
        .build_file()
        .map_err(|e| spec_error(e, &file))
}

/// A build error of a spec read from `file`, at its item's line and column, in this format's
/// words.
pub fn spec_error(e: SpecError, file: &str) -> InputError {
    let message = match &e.kind {
        SpecErrorKind::Model(m) => toml_message(m),
        _ => e.message(),
    };
    match e.at {
        Some(p) => InputError::At {
            file: file.into(),
            line: p.line,
            column: p.column,
            message,
        },
        None => InputError::File {
            file: file.into(),
            message,
        },
    }
}

/// A model error in this format's words: the core's neutral message plus the TOML spelling of
/// its remedy where it has one.
fn toml_message(e: &flexmbd_core::ModelError) -> String {
    use flexmbd_core::ModelError::{MomentWithoutRotation, NoRotation};
    match e {
        NoRotation { .. } | MomentWithoutRotation { .. } => {
            format!("{e}; in a TOML model: `rot = true` on the node")
        }
        _ => e.to_string(),
    }
}

/// Read a file as UTF-8 text; bytes that are not UTF-8 are an error at their line and column.
fn read_text(path: &std::path::Path, file: &str) -> Result<String, InputError> {
    let bytes = std::fs::read(path).map_err(|source| InputError::Read {
        file: file.to_string(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let start = e.utf8_error().valid_up_to();
        let len = e.utf8_error().error_len().unwrap_or(bytes.len() - start);
        let bad: Vec<String> = bytes[start..start + len]
            .iter()
            .map(|b| format!("0x{b:02X}"))
            .collect();
        // the valid text before the bad bytes gives the line and column
        let before = String::from_utf8_lossy(&bytes[..start]);
        at(
            file,
            &before,
            before.len(),
            format!(
                "the file is not UTF-8: invalid byte {} at byte offset {start}; TOML files are UTF-8 (save the file as UTF-8)",
                bad.join(" ")
            ),
        )
    })
}

#[cfg(test)]
mod param_tests;
#[cfg(test)]
mod round_trip;
#[cfg(test)]
mod tests;
