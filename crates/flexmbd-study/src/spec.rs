//! The study file (docs/studies.md): the model, the parameters and how they vary, the analyses
//! whose figures of merit each variant reports.
//!
//! ```toml
//! [study]
//! name = "five folded sheets: thickness, length, angle"
//! model = "folded_sheet_guide_param.toml"   # relative to this file
//! analyses = ["check", "modes", "stroke"]   # default: check and modes
//! modes = 10                                # modes per variant
//! support = ["c:y", "c:z"]                  # support stiffness along the stroke (NODE:DIR)
//! sampling = "latin"                        # grid (default), list or latin
//! samples = 200                             # latin: the number of variants
//! seed = 1                                  # latin: the random seed
//!
//! [parameters]
//! t = { from = 0.15e-3, to = 0.3e-3, count = 4 }   # grid: count points; latin: the range
//! L = { values = [0.04, 0.05, 0.06] }              # grid: these values
//! "sections.sheet.w" = { from = 0.015, to = 0.025 } # a path into the model document
//!
//! [[variant]]                               # sampling = "list": one table per variant
//! t = 0.2e-3
//! ```

use crate::error::{InputError, StudyError};
use flexmbd_io::error::at;
use indexmap::IndexMap;
use serde::{Deserialize, Serialize};
use std::path::Path;
use toml::Spanned;

/// The most variants of one study (a guard against a grid that multiplies out of reach).
pub const MAX_VARIANTS: usize = 10_000_000;
/// The most modes per variant.
pub const MAX_MODES: usize = 1000;

/// A study, read and checked: everything a worker needs to evaluate a variant, the model's text
/// included (so that it can be sent to another process or machine as one JSON document).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Study {
    /// The study's name (the file stem when the file gives none).
    pub name: String,
    /// The study file, as given.
    pub file: String,
    /// The model file (relative paths resolved against the study file's folder).
    pub model_file: String,
    /// The model file's text.
    pub model_text: String,
    /// The parameters, in file order.
    pub parameters: Vec<Parameter>,
    /// How the variants are made.
    pub sampling: Sampling,
    /// What each variant computes.
    pub analyses: Analyses,
}

/// A parameter of the study: a parameter declared in the model's `[parameters]` table, or a
/// path into the model document (`sections.sheet.t`).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Parameter {
    /// Its name (or path).
    pub name: String,
    /// Its values or range.
    pub axis: Axis,
}

/// The values of one parameter.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// These values (grid), or none (list: the values come with each variant).
    Values(Vec<f64>),
    /// From `from` to `to`: `count` points in a grid (evenly, or evenly in the logarithm with
    /// `log`); any point of the interval in a Latin hypercube.
    Range {
        /// Lower end.
        from: f64,
        /// Upper end.
        to: f64,
        /// Number of grid points (grid only).
        count: Option<usize>,
        /// Spaced evenly in the logarithm.
        log: bool,
    },
}

/// How the variants are made from the parameters.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum Sampling {
    /// Every combination of the parameters' values (the first parameter varies slowest).
    Grid,
    /// The variants listed in the file, in file order (values in parameter order).
    List(Vec<Vec<f64>>),
    /// A Latin hypercube of `samples` points over the parameters' ranges.
    Latin {
        /// Number of variants.
        samples: usize,
        /// Random seed (the same seed gives the same variants on every machine).
        seed: u64,
    },
}

/// What each variant computes, and so which figures of merit it reports.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Analyses {
    /// The kinematic check: Table 1 class and counts.
    pub check: bool,
    /// The modal analysis with this many modes: frequencies by class.
    pub modes: Option<usize>,
    /// The static path of the model's loads and strokes: support stiffness at its ends, the
    /// largest stress and actuation force, the buckling margin.
    pub stroke: bool,
    /// Support stiffness directions `NODE:DIR` (global axes) along the stroke.
    pub support: Vec<String>,
    /// The buckling margin along the stroke.
    pub buckling: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDoc {
    study: Spanned<StudySection>,
    #[serde(default)]
    parameters: IndexMap<String, Spanned<AxisDoc>>,
    #[serde(default)]
    variant: Vec<Spanned<IndexMap<String, Spanned<f64>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StudySection {
    name: Option<String>,
    model: Spanned<String>,
    analyses: Option<Spanned<Vec<String>>>,
    modes: Option<Spanned<usize>>,
    support: Option<Spanned<Vec<String>>>,
    buckling: Option<bool>,
    sampling: Option<Spanned<String>>,
    samples: Option<Spanned<usize>>,
    seed: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AxisDoc {
    values: Option<Vec<f64>>,
    from: Option<f64>,
    to: Option<f64>,
    count: Option<usize>,
    #[serde(default)]
    log: bool,
}

impl Study {
    /// Read a study file and its model file.
    pub fn read(path: &Path) -> Result<Study, StudyError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| InputError::Read {
            file: file.clone(),
            source,
        })?;
        let dir = path.parent().unwrap_or(Path::new(""));
        Study::parse(&text, &file, |model| {
            let p = dir.join(model);
            let name = p.display().to_string();
            std::fs::read_to_string(&p)
                .map(|t| (name.clone(), t))
                .map_err(|source| InputError::Read { file: name, source })
        })
    }

    /// Parse study text; `file` names it in messages, `read_model` reads the model file the
    /// study names (returning its name for messages and its text).
    pub fn parse(
        text: &str,
        file: &str,
        read_model: impl FnOnce(&str) -> Result<(String, String), InputError>,
    ) -> Result<Study, StudyError> {
        let mut doc: FileDoc = toml::from_str(text).map_err(|e| {
            let message = e.message().trim().to_string();
            match e.span() {
                Some(s) => at(file, text, s.start, message),
                None => InputError::File {
                    file: file.into(),
                    message,
                },
            }
        })?;
        // the toml crate hands tables over in key order; the file's order is the user's
        doc.parameters.sort_by_key(|_, a| a.span().start);
        for v in &mut doc.variant {
            v.get_mut().sort_by_key(|_, x| x.span().start);
        }
        let err = |offset: usize, message: String| -> StudyError {
            at(file, text, offset, message).into()
        };
        let s = doc.study.get_ref();
        let start = doc.study.span().start;

        // analyses
        let mut analyses = Analyses {
            check: true,
            modes: Some(10),
            stroke: false,
            support: Vec::new(),
            buckling: true,
        };
        if let Some(a) = &s.analyses {
            analyses.check = false;
            analyses.modes = None;
            for name in a.get_ref() {
                match name.as_str() {
                    "check" => analyses.check = true,
                    "modes" => analyses.modes = Some(10),
                    "stroke" => analyses.stroke = true,
                    other => {
                        return Err(err(
                            a.span().start,
                            format!("[study] analyses: unknown analysis `{other}` (expected check, modes or stroke)"),
                        ))
                    }
                }
            }
            if a.get_ref().is_empty() {
                return Err(err(
                    a.span().start,
                    "[study] analyses: give at least one of check, modes, stroke".into(),
                ));
            }
        }
        if let Some(m) = &s.modes {
            let n = *m.get_ref();
            if !(1..=MAX_MODES).contains(&n) {
                return Err(err(
                    m.span().start,
                    format!("[study] modes: from 1 to {MAX_MODES}, found {n}"),
                ));
            }
            if analyses.modes.is_none() {
                return Err(err(
                    m.span().start,
                    "[study] modes: the analyses do not include `modes`".into(),
                ));
            }
            analyses.modes = Some(n);
        }
        if let Some(sup) = &s.support {
            if !analyses.stroke {
                return Err(err(
                    sup.span().start,
                    "[study] support: the support stiffness is computed along the stroke; add \"stroke\" to analyses".into(),
                ));
            }
            for d in sup.get_ref() {
                support_dir(d)
                    .map_err(|m| err(sup.span().start, format!("[study] support: {m}")))?;
            }
            analyses.support = sup.get_ref().clone();
        }
        if let Some(b) = s.buckling {
            analyses.buckling = b;
        }

        // parameters
        let mut parameters = Vec::new();
        let mut places: Vec<usize> = doc.parameters.values().map(|a| a.span().start).collect();
        for (name, a) in &doc.parameters {
            let d = a.get_ref();
            let here = a.span().start;
            let axis = match (&d.values, d.from, d.to) {
                (Some(v), None, None) => {
                    if d.count.is_some() || d.log {
                        return Err(err(here, format!("parameter `{name}`: `count` and `log` go with `from` and `to`, not with `values`")));
                    }
                    if v.is_empty() {
                        return Err(err(here, format!("parameter `{name}`: `values` is empty")));
                    }
                    Axis::Values(v.clone())
                }
                (None, Some(from), Some(to)) => {
                    if !(from.is_finite() && to.is_finite() && from < to) {
                        return Err(err(here, format!("parameter `{name}`: give finite `from` < `to`, found {from} and {to}")));
                    }
                    if d.log && from <= 0.0 {
                        return Err(err(here, format!("parameter `{name}`: a logarithmic range needs `from` > 0, found {from}")));
                    }
                    if d.count == Some(0) {
                        return Err(err(here, format!("parameter `{name}`: `count` must be at least 1")));
                    }
                    Axis::Range { from, to, count: d.count, log: d.log }
                }
                _ => {
                    return Err(err(here, format!("parameter `{name}`: give either `values = [...]` or `from` and `to` (with `count` in a grid)")))
                }
            };
            if let Axis::Values(v) = &axis {
                if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
                    return Err(err(
                        here,
                        format!("parameter `{name}`: the value {bad} is not finite"),
                    ));
                }
            }
            parameters.push(Parameter {
                name: name.clone(),
                axis,
            });
        }

        // sampling
        let method = s.sampling.as_ref().map_or("grid", |m| m.get_ref().as_str());
        let method_at = s.sampling.as_ref().map_or(start, |m| m.span().start);
        let sampling = match method {
            "grid" => {
                for (p, (_, a)) in parameters.iter().zip(&doc.parameters) {
                    if let Axis::Range { count: None, .. } = p.axis {
                        return Err(err(a.span().start, format!("parameter `{}`: a grid needs `count` (the number of points from `from` to `to`)", p.name)));
                    }
                }
                if parameters.is_empty() {
                    return Err(err(start, "the study has no [parameters]".into()));
                }
                Sampling::Grid
            }
            "latin" => {
                let Some(n) = &s.samples else {
                    return Err(err(
                        method_at,
                        "sampling = \"latin\" needs `samples` (the number of variants)".into(),
                    ));
                };
                if !(1..=MAX_VARIANTS).contains(n.get_ref()) {
                    return Err(err(
                        n.span().start,
                        format!("samples: from 1 to {MAX_VARIANTS}, found {}", n.get_ref()),
                    ));
                }
                for (p, (_, a)) in parameters.iter().zip(&doc.parameters) {
                    if !matches!(p.axis, Axis::Range { .. }) {
                        return Err(err(
                            a.span().start,
                            format!(
                                "parameter `{}`: a Latin hypercube needs a range (`from`, `to`)",
                                p.name
                            ),
                        ));
                    }
                }
                if parameters.is_empty() {
                    return Err(err(start, "the study has no [parameters]".into()));
                }
                Sampling::Latin {
                    samples: *n.get_ref(),
                    seed: s.seed.unwrap_or(1),
                }
            }
            "list" => {
                if doc.variant.is_empty() {
                    return Err(err(
                        method_at,
                        "sampling = \"list\" needs [[variant]] tables".into(),
                    ));
                }
                // the parameters are those of the variants (in the order of the first one); a
                // [parameters] table may declare them (without values) or be left out
                let mut names: Vec<String> = parameters.iter().map(|p| p.name.clone()).collect();
                if names.is_empty() {
                    names = doc.variant[0].get_ref().keys().cloned().collect();
                    places = vec![doc.variant[0].span().start; names.len()];
                    parameters = names
                        .iter()
                        .map(|n| Parameter {
                            name: n.clone(),
                            axis: Axis::Values(Vec::new()),
                        })
                        .collect();
                }
                let mut rows = Vec::new();
                for (k, v) in doc.variant.iter().enumerate() {
                    let here = v.span().start;
                    let mut row = Vec::new();
                    for n in &names {
                        match v.get_ref().get(n).map(|x| *x.get_ref()) {
                            Some(x) if x.is_finite() => row.push(x),
                            Some(x) => {
                                return Err(err(
                                    here,
                                    format!("variant {k}: `{n}` = {x} is not finite"),
                                ))
                            }
                            None => {
                                return Err(err(
                                    here,
                                    format!(
                                        "variant {k}: no value for `{n}` (every variant gives {})",
                                        names.join(", ")
                                    ),
                                ))
                            }
                        }
                    }
                    if let Some(extra) = v.get_ref().keys().find(|key| !names.contains(key)) {
                        return Err(err(
                            here,
                            format!(
                                "variant {k}: `{extra}` is not a parameter of the study ({})",
                                names.join(", ")
                            ),
                        ));
                    }
                    rows.push(row);
                }
                Sampling::List(rows)
            }
            other => {
                return Err(err(
                    method_at,
                    format!("sampling: unknown method `{other}` (expected grid, list or latin)"),
                ))
            }
        };
        if !matches!(sampling, Sampling::List(_)) && !doc.variant.is_empty() {
            return Err(err(
                doc.variant[0].span().start,
                "[[variant]] tables go with sampling = \"list\"".into(),
            ));
        }
        if matches!(sampling, Sampling::Grid) {
            let n = crate::sampling::grid_size(&parameters);
            if n > MAX_VARIANTS {
                return Err(err(
                    start,
                    format!("the grid has {n} variants, more than the limit {MAX_VARIANTS}"),
                ));
            }
        }

        let (model_file, model_text) = read_model(s.model.get_ref()).map_err(|e| match e {
            InputError::Read { file: f, source } => err(
                s.model.span().start,
                format!("[study] model: cannot read {f}: {source}"),
            ),
            other => other.into(),
        })?;
        let name = s.name.clone().unwrap_or_else(|| {
            Path::new(file)
                .file_stem()
                .map_or("study".into(), |s| s.to_string_lossy().into_owned())
        });
        let study = Study {
            name,
            file: file.to_string(),
            model_file,
            model_text,
            parameters,
            sampling,
            analyses,
        };
        if let Err((i, message)) = crate::evaluate::check_parameters(&study)? {
            return Err(err(places.get(i).copied().unwrap_or(start), message));
        }
        Ok(study)
    }

    /// The parameters' names, in order.
    pub fn parameter_names(&self) -> Vec<&str> {
        self.parameters.iter().map(|p| p.name.as_str()).collect()
    }

    /// A fingerprint of everything that decides the records (the study, the model's text and
    /// the program's version): a resumed run continues only the records of the same study.
    pub fn fingerprint(&self) -> String {
        let doc = serde_json::json!({
            "parameters": self.parameters,
            "sampling": self.sampling,
            "analyses": self.analyses,
            "model_text": self.model_text,
            "version": env!("CARGO_PKG_VERSION"),
        });
        format!("{:016x}", fnv1a(doc.to_string().as_bytes()))
    }
}

/// The support directions, in the order of a compliance's rows.
const DIRS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// The name stem of the figures of merit of a support direction `NODE:DIR`: `k_NODE_DIR`
/// (followed by `_start`, `_end`, `_drop`); `s` is one the study reader accepted.
pub fn support_merit(s: &str) -> String {
    let (node, dir) = support_dir(s).unwrap_or_default();
    format!("k_{node}_{}", DIRS[dir])
}

/// `NODE:DIR` → (node, index of the direction in x, y, z, rx, ry, rz). Node names may hold
/// `:`, so the direction is read from the right.
pub fn support_dir(s: &str) -> Result<(String, usize), String> {
    let usage = || format!("`{s}`: expected NODE:DIR with DIR one of x, y, z, rx, ry, rz");
    let (node, dir) = s.rsplit_once(':').ok_or_else(usage)?;
    let k = DIRS.iter().position(|d| *d == dir).ok_or_else(usage)?;
    if node.is_empty() {
        return Err(usage());
    }
    Ok((node.to_string(), k))
}

/// FNV-1a, 64 bits: a hash that is the same in every build (the standard library's is not
/// promised to be).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}
