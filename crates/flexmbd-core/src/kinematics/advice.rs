//! Repair advice (beyond SPACAR): how to remove each self-stress state and each motion, and an
//! automatic choice of generalised coordinates.
//!
//! - A self-stress state u (null column of U) involves the rows with uᵢ ≠ 0. Releasing such a
//!   fixed deformation (e^o → e^c) deletes a row that depends on the others, so m − r drops by
//!   one and n − r is unchanged. Input deformations in u are over-specified generalised
//!   coordinates; making them dependent has the same effect.
//! - A motion v (null column of V) involves the columns with vⱼ ≠ 0. Fixing such a coordinate or
//!   taking it as generalised deletes a column that depends on the others, so n − r drops by one.
//!   A free deformation whose rate along v is non-zero, fixed or taken as generalised, adds an
//!   independent row with the same effect.
//!
//! The candidates come from the null vectors, largest entry first; the counts each one leads to
//! are predicted from the null bases alone ([`super::update`]: a released row keeps the rank iff
//! a self-stress involves it, a fixed column iff a motion involves it), and candidates predicted
//! not to remove the state are skipped. Every suggestion shown is then **verified**: the counts
//! of the changed Dcc are recomputed exactly (the singular values above the changed matrix's own
//! threshold, by a rank-one update of the SVD), and a candidate whose verified counts differ is
//! dropped. [`counts`] is the full re-analysis of a changed partition. The wires that remove a
//! motion ([`WireSuggestion`]) are searched for and verified in `wires.rs` ([`wire_advice`],
//! re-exported here).

use super::update::{Change, Prediction, Updater};
use super::{
    check, columns, coordinate_constraint, rate_rows, CheckOptions, ConstraintAnalysis,
    KinematicsError, SparseRow,
};
use crate::elements::ElementKind;
use crate::linalg::{numerical_rank, pivot_columns};
use crate::model::{CoordKind, DefKind, Dof, Model, Partition};
use faer::Mat;
use serde::Serialize;

pub use super::wires::wire_advice;

/// A change of the model's partition.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "action", rename_all = "snake_case")]
pub enum Action {
    /// Release a fixed deformation (e^o → e^c): make it free.
    Release {
        /// Element name.
        element: String,
        /// Mode, 1-based.
        mode: usize,
        /// Mode name.
        mode_name: String,
    },
    /// Make an input deformation dependent (e^m → e^c).
    MakeDependent {
        /// Element name.
        element: String,
        /// Mode, 1-based.
        mode: usize,
        /// Mode name.
        mode_name: String,
    },
    /// Fix a nodal coordinate, or take it as a generalised coordinate (x^c → x^o or x^m).
    FixOrInputCoordinate {
        /// Node name.
        node: String,
        /// Degree of freedom.
        dof: Dof,
    },
    /// Fix a free deformation, or take it as a generalised coordinate (e^c → e^o or e^m).
    FixOrInputDeformation {
        /// Element name.
        element: String,
        /// Mode, 1-based.
        mode: usize,
        /// Mode name.
        mode_name: String,
    },
}

impl Action {
    /// The changed partition (coordinates and deformations are made inputs where the action
    /// allows both fixing and input: Dcc is the same either way).
    ///
    /// An action that names an element, mode, node or coordinate `model` does not have (an
    /// action of another model) is an error.
    pub fn apply(&self, model: &Model, p: &Partition) -> Result<Partition, KinematicsError> {
        let mut p = p.clone();
        let unknown = |what: String| KinematicsError::UnknownInAction(what);
        let def_index = |element: &str, mode: usize| {
            let e = model
                .elements
                .iter()
                .find(|e| e.name == element)
                .ok_or_else(|| unknown(format!("element `{element}`")))?;
            if mode == 0 || mode > e.element.ne() {
                return Err(unknown(format!("mode {mode} of element `{element}`")));
            }
            Ok(e.ie + mode - 1)
        };
        match self {
            Action::Release { element, mode, .. } | Action::MakeDependent { element, mode, .. } => {
                p.e[def_index(element, *mode)?] = DefKind::Free;
            }
            Action::FixOrInputDeformation { element, mode, .. } => {
                p.e[def_index(element, *mode)?] = DefKind::Input;
            }
            Action::FixOrInputCoordinate { node, dof } => {
                let id = model
                    .node_id(node)
                    .ok_or_else(|| unknown(format!("node `{node}`")))?;
                let i = model.nodes[id]
                    .x_index(*dof)
                    .ok_or_else(|| unknown(format!("coordinate {node}:{dof:?}")))?;
                p.x[i] = CoordKind::Input;
            }
        }
        Ok(p)
    }
    /// The action that takes a constraint row of Dcc out: release a fixed deformation, or make
    /// an input deformation dependent. `names` are the model's node names (for mode names).
    pub fn remove_row(model: &Model, names: &[String], r: &super::Row) -> Action {
        let entry = &model.elements[r.element];
        let (element, mode) = (entry.name.clone(), r.mode + 1);
        let mode_name = entry.element.mode_name(r.mode, names);
        if r.kind == DefKind::Input {
            Action::MakeDependent {
                element,
                mode,
                mode_name,
            }
        } else {
            Action::Release {
                element,
                mode,
                mode_name,
            }
        }
    }
    /// Human description.
    pub fn describe(&self) -> String {
        match self {
            Action::Release {
                element,
                mode,
                mode_name,
            } => {
                format!("release {element} mode {mode} ({mode_name})")
            }
            Action::MakeDependent {
                element,
                mode,
                mode_name,
            } => {
                format!("make input {element} mode {mode} ({mode_name}) dependent")
            }
            Action::FixOrInputCoordinate { node, dof } => {
                format!(
                    "fix {node}.{}, or take it as generalised coordinate",
                    dof.name()
                )
            }
            Action::FixOrInputDeformation {
                element,
                mode,
                mode_name,
            } => format!(
                "fix {element} mode {mode} ({mode_name}), or take it as generalised coordinate"
            ),
        }
    }
}

/// A verified suggestion.
#[derive(Clone, Debug, Serialize)]
pub struct Suggestion {
    /// What to change.
    #[serde(flatten)]
    pub action: Action,
    /// Magnitude of the candidate's entry in the state (ranking; 0..1).
    pub weight: f64,
    /// Motions after the change (verified).
    pub motions_after: usize,
    /// Self-stress states after the change (verified).
    pub self_stresses_after: usize,
    /// A release in the designer's words, when the action releases a deformation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub designer: Option<DesignerRelease>,
}

/// What a released deformation makes of its element, for a designer (docs/kinematic-analysis.md
/// "Repair in the designer's language").
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignerRelease {
    /// `remove`: the element constrains nothing after the release (leave it out, or make it
    /// compliant in every mode); `hinge` or `slide` ([`crate::elements::Release`]).
    pub kind: &'static str,
    /// The node a hinge sits at (`None` for a torsion hinge along the element, a slide or a
    /// removal).
    pub node: Option<String>,
    /// The unit axis of a hinge or slide, global, at the analysed configuration.
    pub axis: Option<[f64; 3]>,
}

/// The designer's words for every release in `advice` (a partition of `model` at x).
fn designer_releases(model: &Model, partition: &Partition, x: &[f64], advice: &mut [StateAdvice]) {
    use crate::elements::Release;
    for sg in advice.iter_mut().flat_map(|a| a.suggestions.iter_mut()) {
        let Action::Release { element, mode, .. } = &sg.action else {
            continue;
        };
        let Some(entry) = model.elements.iter().find(|e| &e.name == element) else {
            continue;
        };
        let ne = entry.element.ne();
        let rest_free = (0..ne)
            .filter(|&k| k + 1 != *mode)
            .all(|k| partition.e[entry.ie + k] == DefKind::Free);
        sg.designer = if rest_free {
            Some(DesignerRelease {
                kind: "remove",
                node: None,
                axis: None,
            })
        } else {
            let xk = crate::assembly::gather(entry, x);
            let uses = entry.element.node_uses();
            match entry.element.release(mode - 1, &xk) {
                Some(Release::Hinge { axis, at }) => Some(DesignerRelease {
                    kind: "hinge",
                    node: at.map(|i| model.nodes[uses[i].node].name.clone()),
                    axis: Some(axis),
                }),
                Some(Release::Slide { axis }) => Some(DesignerRelease {
                    kind: "slide",
                    node: None,
                    axis: Some(axis),
                }),
                None => None,
            }
        };
    }
}

/// Suggestions for one state.
#[derive(Clone, Debug, Serialize)]
pub struct StateAdvice {
    /// "self_stress" or "motion".
    pub kind: &'static str,
    /// Index of the state (0-based) in the analysis' list.
    pub state: usize,
    /// Verified suggestions, most significant first.
    pub suggestions: Vec<Suggestion>,
}

/// Counts (motions, self-stresses) of a partition by a full re-analysis (a new Dcc and its
/// singular values); the advice itself verifies by rank updates ([`super::update`]).
pub fn counts(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    opts: &CheckOptions,
) -> Result<(usize, usize), KinematicsError> {
    let cols = columns(model, partition, x);
    let rows = super::rows(model, partition);
    super::check_dense_size(rows.len(), cols.len(), opts.max_dense_bytes)?;
    let (rows, cols, dcc) = super::assemble_dcc(model, partition, x);
    let s = crate::linalg::singular_values(dcc.as_ref())?;
    let r = numerical_rank(&s, opts.rank_tol * s.first().copied().unwrap_or(0.0));
    Ok((cols.len() - r, rows.len() - r))
}

/// Candidates below this fraction of the largest entry are not tried.
const CANDIDATE_FLOOR: f64 = 1e-6;

/// Verified suggestions for every self-stress state and every motion, at most `max_per_state`
/// each: candidates in the order of their entries, skipped when the prediction from the null
/// bases says they do not remove the state, verified by an exact rank update before they are
/// kept (module docs).
pub fn advise(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    a: &ConstraintAnalysis,
    opts: &CheckOptions,
    max_per_state: usize,
) -> Result<Vec<StateAdvice>, KinematicsError> {
    let mut out = match &a.sparse {
        Some(sp) => super::sparse::advise_sparse(model, x, a, sp, max_per_state),
        None => advise_dense(model, partition, x, a, opts, max_per_state)?,
    };
    designer_releases(model, partition, x, &mut out);
    Ok(out)
}

/// [`advise`] on the dense path.
fn advise_dense(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    a: &ConstraintAnalysis,
    opts: &CheckOptions,
    max_per_state: usize,
) -> Result<Vec<StateAdvice>, KinematicsError> {
    let names = model.node_names();
    let before = (a.n_motions(), a.n_self_stresses());
    let mut out = Vec::new();
    if max_per_state == 0 || before == (0, 0) {
        let empty = |kind, state| StateAdvice {
            kind,
            state,
            suggestions: Vec::new(),
        };
        out.extend((0..before.1).map(|s| empty("self_stress", s)));
        out.extend((0..before.0).map(|k| empty("motion", k)));
        return Ok(out);
    }
    let upd = Updater::new(a, opts.rank_tol)?;
    // self-stress states: release rows with large entries
    for s in 0..a.n_self_stresses() {
        let u: Vec<f64> = (0..a.m()).map(|i| a.null_u[(i, s)]).collect();
        let cands = ranked(&u).into_iter().map(|(i, w)| {
            let action = Action::remove_row(model, &names, &a.rows[i]);
            (Change::RemoveRow(i), action, w)
        });
        let want = (before.0, before.1 - 1);
        let suggestions = verify(&upd, cands, want, max_per_state);
        out.push(StateAdvice {
            kind: "self_stress",
            state: s,
            suggestions,
        });
    }
    // motions: coordinates and free deformations that move
    let free = FreeRows::new(
        model,
        partition,
        x,
        a,
        max_per_state > 0 && a.n_motions() > 0,
    );
    for k in 0..a.n_motions() {
        let v: Vec<f64> = (0..a.n()).map(|j| a.null_v[(j, k)]).collect();
        // (column j, or free row f), weight
        let mut cands: Vec<(Result<usize, usize>, f64)> =
            ranked(&v).into_iter().map(|(j, w)| (Ok(j), w)).collect();
        cands.extend(free.candidates(&v).into_iter().map(|(f, w)| (Err(f), w)));
        // largest first (to 1e-6); stable: coordinates before deformations at equal weight
        cands.sort_by_key(|c| std::cmp::Reverse((c.1 * 1e6).round() as u64));
        let want = (before.0 - 1, before.1);
        let cands = cands.into_iter().map(|(c, w)| match c {
            Ok(j) => {
                let col = &a.cols[j];
                let row = coordinate_constraint(model, &a.cols, x, j);
                let change = if row.len() == 1 && row[0].0 == j {
                    Change::RemoveColumn(j)
                } else {
                    Change::AddRow(row)
                };
                (
                    change,
                    Action::FixOrInputCoordinate {
                        node: names[col.node].clone(),
                        dof: col.dof,
                    },
                    w,
                )
            }
            Err(f) => {
                let (el, mode) = model.deformation_owner(free.defs[f]);
                let entry = &model.elements[el];
                (
                    Change::AddRow(free.rows[f].clone()),
                    Action::FixOrInputDeformation {
                        element: entry.name.clone(),
                        mode: mode + 1,
                        mode_name: entry.element.mode_name(mode, &names),
                    },
                    w,
                )
            }
        });
        let suggestions = verify(&upd, cands, want, max_per_state);
        out.push(StateAdvice {
            kind: "motion",
            state: k,
            suggestions,
        });
    }
    Ok(out)
}

/// The free deformations of a partition with their rates along the columns of an analysis
/// (sparse rows): the candidates that add a row to Dcc.
struct FreeRows {
    /// Global deformation indices.
    defs: Vec<usize>,
    /// Their rate rows over the columns.
    rows: Vec<SparseRow>,
    /// Their norms.
    norms: Vec<f64>,
}

impl FreeRows {
    fn new(
        model: &Model,
        partition: &Partition,
        x: &[f64],
        a: &ConstraintAnalysis,
        wanted: bool,
    ) -> Self {
        let defs: Vec<usize> = if wanted {
            (0..model.ne)
                .filter(|&i| partition.e[i] == DefKind::Free)
                .collect()
        } else {
            Vec::new()
        };
        let rows = rate_rows(model, x, &a.cols, &defs);
        let norms = rows
            .iter()
            .map(|r| r.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt())
            .collect();
        Self { defs, rows, norms }
    }

    /// Free deformations whose rate along v is significant, weighted by the cosine between
    /// their row and v, in model order.
    fn candidates(&self, v: &[f64]) -> Vec<(usize, f64)> {
        let mut out = Vec::new();
        for (f, row) in self.rows.iter().enumerate() {
            let norm = self.norms[f];
            if norm == 0.0 {
                continue;
            }
            // the dot product over all columns in order, as the dense row gave it
            let mut dot = 0.0;
            for &(j, r) in row {
                dot += r * v[j];
            }
            let w = dot.abs() / norm;
            if w > CANDIDATE_FLOOR {
                out.push((f, w));
            }
        }
        out
    }
}

/// Indices of significant entries with their magnitudes, largest first.
fn ranked(v: &[f64]) -> Vec<(usize, f64)> {
    let max = v.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    // largest first; equal magnitudes (to 1e-6) keep their model order (the key, made once
    // per entry, is unique with the index: an unstable sort gives that one order)
    let mut idx: Vec<(std::cmp::Reverse<u64>, usize, f64)> = v
        .iter()
        .enumerate()
        .filter(|(_, a)| a.abs() > CANDIDATE_FLOOR * max)
        .map(|(i, a)| {
            let a = a.abs();
            (std::cmp::Reverse((a / max * 1e6).round() as u64), i, a)
        })
        .collect();
    idx.sort_unstable_by_key(|&(key, i, _)| (key, i));
    idx.into_iter().map(|(_, i, a)| (i, a)).collect()
}

/// The first `max` candidates, in order, whose predicted counts may be `want` and whose
/// verified counts are `want`.
fn verify(
    upd: &Updater<'_>,
    cands: impl Iterator<Item = (Change, Action, f64)>,
    want: (usize, usize),
    max: usize,
) -> Vec<Suggestion> {
    let mut out = Vec::new();
    for (change, action, weight) in cands {
        if out.len() >= max {
            break;
        }
        if matches!(upd.predict(&change), Prediction::Certain(c) if c != want) {
            continue;
        }
        let (motions_after, self_stresses_after) = upd.counts_after(&change);
        if (motions_after, self_stresses_after) == want {
            out.push(Suggestion {
                action,
                weight,
                motions_after,
                self_stresses_after,
                designer: None,
            });
        }
    }
    out
}

/// The result of an automatic choice of generalised coordinates.
#[derive(Clone, Debug)]
pub struct AutoChoice {
    /// The changes made (coordinates or deformations taken as generalised).
    pub chosen: Vec<Action>,
    /// The changed partition.
    pub partition: Partition,
    /// The analysis with that partition (verification).
    pub analysis: ConstraintAnalysis,
}

/// Choose as many generalised coordinates as there are motions, by QR with column pivoting
/// on the null space of Dcc: nodal coordinates first (rows of the null basis V₀), then free
/// deformations (their rates along V₀) if the coordinates cannot remove every motion. Taking
/// the chosen set as x^m (or e^m) makes the remaining Dcc full column rank because the chosen
/// k × k block of the null basis is non-singular. Verified by repeating the analysis.
pub fn auto_generalised(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    opts: &CheckOptions,
) -> Result<AutoChoice, KinematicsError> {
    let a = check(model, partition, x, opts)?;
    let k = a.n_motions();
    let names = model.node_names();
    let mut chosen: Vec<Action> = Vec::new();
    if let Some(sp) = a.sparse.as_ref().filter(|_| k > 0) {
        // the sparse path: the dependent columns (fixing them all leaves the basic columns, of
        // full column rank)
        for &j in &sp.motion_cols {
            let c = &a.cols[j];
            chosen.push(Action::FixOrInputCoordinate {
                node: names[c.node].clone(),
                dof: c.dof,
            });
        }
    } else if k > 0 {
        // candidate matrix: k × n, column j = row j of the null basis
        let cand = Mat::from_fn(k, a.n(), |i, j| a.null_v[(j, i)]);
        for j in pivot_columns(cand.as_ref(), k, 1e-8) {
            let c = &a.cols[j];
            chosen.push(Action::FixOrInputCoordinate {
                node: names[c.node].clone(),
                dof: c.dof,
            });
        }
    }
    let mut p = partition.clone();
    for c in &chosen {
        p = c.apply(model, &p)?;
    }
    // coordinates could not remove every motion: add free deformations
    let mut analysis = check(model, &p, x, opts)?;
    if analysis.n_motions() > 0 {
        let cols = columns(model, &p, x);
        let free: Vec<usize> = (0..model.ne).filter(|&i| p.e[i] == DefKind::Free).collect();
        let rates = rate_rows(model, x, &cols, &free);
        let kk = analysis.n_motions().min(analysis.null_v.ncols());
        let cand = Mat::from_fn(kk, free.len(), |r, c| {
            rates[c]
                .iter()
                .map(|&(j, d)| d * analysis.null_v[(j, r)])
                .sum()
        });
        for c in pivot_columns(cand.as_ref(), kk, 1e-8) {
            let (el, mode) = model.deformation_owner(free[c]);
            let entry = &model.elements[el];
            chosen.push(Action::FixOrInputDeformation {
                element: entry.name.clone(),
                mode: mode + 1,
                mode_name: entry.element.mode_name(mode, &names),
            });
        }
        p = partition.clone();
        for c in &chosen {
            p = c.apply(model, &p)?;
        }
        analysis = check(model, &p, x, opts)?;
    }
    Ok(AutoChoice {
        chosen,
        partition: p,
        analysis,
    })
}

/// A wire (a rigid constraint line between a node of a moving body and a node of another body
/// or of the ground, Blanding's constraint line) that removes a motion without adding a
/// self-stress: verified like every suggestion ([`Updater::counts_after`] of its row).
#[derive(Clone, Debug, Serialize)]
pub struct WireSuggestion {
    /// The node on the moving body.
    pub from: String,
    /// The node on the other body or the ground.
    pub to: String,
    /// The moving body (the node `from` itself when it belongs to no body: a joint of
    /// trusses or wires).
    pub body: String,
    /// The other body ("ground" for the ground; the node `to` when it belongs to no body).
    pub other: String,
    /// A point of the wire's line: the node `from`.
    pub point: [f64; 3],
    /// The unit direction of the line, from `from` to `to`.
    pub direction: [f64; 3],
    /// The wire's length, the distance between the nodes [m].
    pub length: f64,
    /// |reciprocal product| of the unit wire with the relative twist of the two bodies in the
    /// motion, the twist of unit |ω| (a rotation: the wire's moment arm about the axis [m]) or
    /// of unit |v| (a translation: the cosine between wire and motion).
    pub reciprocal: f64,
    /// The largest reciprocal product of the unit wire with an intended freedom of unit |ω|
    /// (times L) or unit |v| ([`super::freedom::intended_power`]); 0 when the wire leaves every
    /// intended freedom alone, or when none is stated.
    pub intended_change: f64,
    /// Motions after adding the wire (verified).
    pub motions_after: usize,
    /// Self-stress states after adding the wire (verified).
    pub self_stresses_after: usize,
}

/// The wires that remove one motion.
#[derive(Clone, Debug, Serialize)]
pub struct WireAdvice {
    /// Index of the motion (0-based) in the analysis' list.
    pub motion: usize,
    /// Verified wires, least change of the intended freedom first, then the largest
    /// reciprocal product.
    pub wires: Vec<WireSuggestion>,
}
