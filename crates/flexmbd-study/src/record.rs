//! The record of one variant: its parameters, its figures of merit, or where and why it failed.
//! One JSON line per record; the CSV table has one row per record with the same columns for
//! every variant of a study.

use crate::spec::{support_merit, Analyses, Study};
use crate::Variant;
use indexmap::IndexMap;
use serde::{Deserialize, Serialize};

/// Whether a variant was evaluated completely.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Every analysis of the study ran.
    Ok,
    /// An analysis failed: [`Record::error`] says which and why; the figures of merit of the
    /// analyses before it (and of the converged part of a stroke) are kept.
    Failed,
}

/// Where and why a variant failed.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Failure {
    /// The stage: `model` (the member could not be built), `check`, `stroke`, `modes`, or
    /// `internal` (a defect of flexmbd, reported instead of stopping the study).
    pub stage: String,
    /// The message.
    pub message: String,
}

impl Failure {
    pub(crate) fn new(stage: &str, message: impl std::fmt::Display) -> Self {
        Failure {
            stage: stage.into(),
            message: message.to_string(),
        }
    }
}

/// The results of one variant.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Record {
    /// The variant's index in the study.
    pub variant: usize,
    /// Its parameter values.
    pub parameters: IndexMap<String, f64>,
    /// Evaluated completely or not.
    pub status: Status,
    /// The figures of merit ([`merit_names`], in that order); null where not defined (a
    /// frequency of a class the variant has no mode of, a stiffness in a held direction) or
    /// not computed (after a failure).
    pub merits: IndexMap<String, Option<f64>>,
    /// The Table 1 class in words (with the check).
    pub table1: Option<String>,
    /// The frequencies [Hz] of the modes (null for an unstable mode).
    pub frequencies: Vec<Option<f64>>,
    /// The class of each mode: intended, support, internal, rigid_body.
    pub classes: Vec<String>,
    /// Where and why it failed.
    pub error: Option<Failure>,
}

impl Record {
    /// An empty record of `v`: every figure of merit null.
    pub(crate) fn empty(study: &Study, v: &Variant) -> Self {
        Record {
            variant: v.index,
            parameters: study
                .parameters
                .iter()
                .zip(&v.values)
                .map(|(p, &x)| (p.name.clone(), x))
                .collect(),
            status: Status::Ok,
            merits: merit_names(&study.analyses)
                .into_iter()
                .map(|n| (n, None))
                .collect(),
            table1: None,
            frequencies: Vec::new(),
            classes: Vec::new(),
            error: None,
        }
    }

    /// Set a figure of merit (non-finite values are null).
    pub(crate) fn set(&mut self, name: &str, value: f64) {
        if let Some(slot) = self.merits.get_mut(name) {
            *slot = value.is_finite().then_some(value);
        }
    }

    /// The record as one line of JSON (no newline).
    pub fn to_json_line(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// The record as a CSV row of [`csv_header`]'s columns.
    pub fn to_csv_row(&self) -> String {
        let mut cells: Vec<String> = vec![self.variant.to_string()];
        cells.extend(self.parameters.values().map(|v| num(Some(*v))));
        cells.push(
            match self.status {
                Status::Ok => "ok",
                Status::Failed => "failed",
            }
            .into(),
        );
        cells.extend(self.merits.values().map(|v| num(*v)));
        cells.push(csv_text(self.table1.as_deref().unwrap_or("")));
        cells.push(csv_text(
            self.error.as_ref().map_or("", |f| f.stage.as_str()),
        ));
        cells.push(csv_text(
            self.error.as_ref().map_or("", |f| f.message.as_str()),
        ));
        cells.join(",")
    }
}

/// A number as the shortest text that reads back to the same value; empty for null.
fn num(v: Option<f64>) -> String {
    match v {
        // counts and other whole numbers without a decimal point
        Some(v) if v.fract() == 0.0 && v.abs() < 1e15 => format!("{}", v as i64),
        Some(v) => serde_json::Number::from_f64(v).map_or(String::new(), |n| n.to_string()),
        None => String::new(),
    }
}

/// A CSV text cell: quoted when it holds a comma, quote or line break (RFC 4180).
fn csv_text(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The CSV header of a study's records.
pub fn csv_header(study: &Study) -> String {
    let mut cols: Vec<String> = vec!["variant".into()];
    cols.extend(study.parameters.iter().map(|p| csv_text(&p.name)));
    cols.push("status".into());
    cols.extend(merit_names(&study.analyses).iter().map(|n| csv_text(n)));
    cols.extend(["table1".into(), "failed_stage".into(), "error".into()]);
    cols.join(",")
}

/// The names of the figures of merit of a study's analyses, in record order (docs/studies.md
/// defines each):
/// - check: `table1_row`, `rank`, `motions`, `self_stresses`;
/// - stroke: `stroke_reached` (the load factor reached, 1 for the whole stroke),
///   `k_NODE_DIR_start`, `k_NODE_DIR_end`, `k_NODE_DIR_drop` per support direction,
///   `max_stress`, `max_actuation_force`, `buckling_margin`;
/// - modes: `f1`, `f_intended`, `f_support`, `f_internal`, `support_ratio`, `internal_ratio`.
pub fn merit_names(a: &Analyses) -> Vec<String> {
    let mut n: Vec<String> = Vec::new();
    if a.check {
        n.extend(["table1_row", "rank", "motions", "self_stresses"].map(String::from));
    }
    if a.stroke {
        n.push("stroke_reached".into());
        for s in &a.support {
            let name = support_merit(s);
            for end in ["start", "end", "drop"] {
                n.push(format!("{name}_{end}"));
            }
        }
        n.extend(["max_stress", "max_actuation_force"].map(String::from));
        if a.buckling {
            n.push("buckling_margin".into());
        }
    }
    if a.modes.is_some() {
        n.extend(
            [
                "f1",
                "f_intended",
                "f_support",
                "f_internal",
                "support_ratio",
                "internal_ratio",
            ]
            .map(String::from),
        );
    }
    n
}
