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
//! dropped. [`counts`] is the full re-analysis of a changed partition.

use super::freedom::{intended_power, resolve_body, IntendedFreedom};
use super::screw::{position, ScrewAnalysis, VelocityField, PURE_TOL};
use super::update::{Change, Prediction, Updater};
use super::{
    check, columns, coordinate_constraint, rate_rows, CheckOptions, ConstraintAnalysis,
    KinematicsError, SparseRow,
};
use crate::elements::ElementKind;
use crate::linalg::{numerical_rank, pivot_columns};
use crate::math::{add, cross, dot, norm, normalize, sub};
use crate::model::{CoordKind, DefKind, Dof, Model, Partition};
use faer::Mat;
use serde::Serialize;

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
    let mut idx: Vec<(usize, f64)> = v
        .iter()
        .enumerate()
        .filter(|(_, a)| a.abs() > CANDIDATE_FLOOR * max)
        .map(|(i, a)| (i, a.abs()))
        .collect();
    // largest first; equal magnitudes (to 1e-6) keep their model order
    idx.sort_by_key(|&(i, a)| (std::cmp::Reverse((a / max * 1e6).round() as u64), i));
    idx
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

/// A candidate wire from node `na` to node `ng` along the unit `d`.
struct WireCandidate {
    /// The intended change ([`WireSuggestion::intended_change`]).
    change: f64,
    /// The reciprocal product per unit motion, made dimensionless (a rotation's over L).
    rel: f64,
    na: usize,
    ng: usize,
    d: [f64; 3],
    /// The reciprocal product ([`WireSuggestion::reciprocal`]).
    power: f64,
}

/// How a wire suggestion is verified: by a rank update of the dense SVD, or by the sparse
/// path's bound for an added row.
enum WireCheck<'a> {
    Dense(Updater<'a>),
    Sparse(super::sparse::AddedRowBound),
}

/// Candidate wires tried (verified) per motion, at most.
const MAX_WIRE_TRIES: usize = 200;

/// Node pairs (and body pairs) looked at per motion, at most (the first ones in the order of
/// bodies and nodes).
const MAX_WIRE_PAIRS: usize = 200_000;

/// The row of a rigid wire from node `a` to node `g` along the unit `d` over the columns:
/// ė = d · (u_g − u_a) (the elongation rate of a rigid truss, paper eq. (1)).
fn wire_row(model: &Model, cols: &[super::Column], a: usize, g: usize, d: [f64; 3]) -> SparseRow {
    let (pa, pg) = (
        model.nodes[a].host.unwrap_or(a),
        model.nodes[g].host.unwrap_or(g),
    );
    cols.iter()
        .enumerate()
        .filter(|(_, c)| !c.dof.is_rotation())
        .filter_map(|(j, c)| {
            let k = c.dof.index();
            if c.node == pg {
                Some((j, d[k]))
            } else if c.node == pa {
                Some((j, -d[k]))
            } else {
                None
            }
        })
        .filter(|e| e.1 != 0.0)
        .collect()
}

/// For every listed motion of a dense analysis: wires between existing nodes of a moving body
/// and of another body or the ground whose reciprocal product with the bodies' relative twist
/// is not zero (the wire stops the motion), each verified to remove exactly that motion and
/// add no self-stress (its row raises the rank of Dcc), ranked by how little they act on the
/// intended freedoms, then by their reciprocal product (docs/kinematic-analysis.md "Repair
/// in the designer's language"). On the sparse path a wire is verified by the bound of
/// [`super::sparse::AddedRowBound`] (no new factorisation), and only when the rank decision is
/// certain.
pub fn wire_advice(
    model: &Model,
    x: &[f64],
    a: &ConstraintAnalysis,
    screws: &ScrewAnalysis,
    intended: &[IntendedFreedom],
    opts: &CheckOptions,
    max_per_state: usize,
) -> Result<Vec<WireAdvice>, KinematicsError> {
    if max_per_state == 0 || a.n_motions() == 0 {
        return Ok(Vec::new());
    }
    let verify = match &a.sparse {
        None => WireCheck::Dense(Updater::new(a, opts.rank_tol)?),
        Some(sp) => match super::sparse::AddedRowBound::new(a, sp, opts.rank_tol) {
            Some(b) => WireCheck::Sparse(b),
            None => return Ok(Vec::new()),
        },
    };
    let bodies = &screws.bodies;
    let l = screws.length_scale;
    let resolved: Vec<(usize, &IntendedFreedom)> = intended
        .iter()
        .filter_map(|f| resolve_body(model, bodies, &f.body).map(|b| (b, f)))
        .collect();
    let want = (a.n_motions() - 1, a.n_self_stresses());
    // each node's body, and the nodes in none
    let mut node_body: Vec<Option<usize>> = vec![None; model.nodes.len()];
    for (i, b) in bodies.iter().enumerate() {
        for &id in &b.node_ids {
            node_body[id] = Some(i);
        }
    }
    let loose: Vec<usize> = (0..model.nodes.len())
        .filter(|&id| node_body[id].is_none())
        .collect();
    let anchor = |id: usize| {
        node_body[id].map_or_else(|| model.nodes[id].name.clone(), |i| bodies[i].name.clone())
    };
    let mut out = Vec::new();
    for (k, ms) in screws.motions.iter().enumerate() {
        let mut v: Vec<f64> = (0..a.n()).map(|j| a.null_v[(j, k)]).collect();
        super::normalize_signed(&mut v);
        let field = VelocityField::new(model, &a.cols, &v);
        // the moving bodies' twists by body index (linear in the bodies, for large models)
        let by_name: std::collections::HashMap<&str, &super::screw::BodyTwist> =
            ms.bodies.iter().map(|t| (t.body.as_str(), t)).collect();
        let moving: Vec<Option<&super::screw::BodyTwist>> = bodies
            .iter()
            .map(|b| by_name.get(b.name.as_str()).copied())
            .collect();
        // the twist of body i at the point p (zero for a body at rest)
        let twist = |i: usize, p: [f64; 3]| {
            moving[i].map_or(([0.0; 3], [0.0; 3]), |t| {
                let w = t.angular_velocity;
                (w, add(t.velocity, cross(w, sub(p, t.screw.point))))
            })
        };
        let mut cands: Vec<WireCandidate> = Vec::new();
        let mut pairs = 0usize;
        // a candidate from node na (of body ia, or none) to node ng, `unit` the size of the
        // relative motion it is measured against, `rotation` whether that is a rotation
        let mut consider = |na: usize, ng: usize, unit: f64, rotation: bool| {
            let (pa, pg) = (position(model, x, na), position(model, x, ng));
            let dv = sub(pg, pa);
            if norm(dv) <= 1e-9 * l {
                return;
            }
            let d = normalize(dv);
            let power = dot(d, sub(field.u[na], field.u[ng])).abs() / unit;
            let rel = if rotation { power / l } else { power };
            if rel <= 1e-6 {
                return;
            }
            let (ia, ig) = (node_body[na], node_body[ng]);
            let change = intended_power(
                &resolved,
                bodies,
                (ia.unwrap_or(usize::MAX), pa),
                (ig.unwrap_or(usize::MAX), pg),
                d,
                l,
            );
            cands.push(WireCandidate {
                change,
                rel,
                na,
                ng,
                d,
                power,
            });
        };
        'bodies: for (ia, ba) in bodies.iter().enumerate() {
            if ba.ground || moving[ia].is_none() {
                continue;
            }
            for (ig, bg) in bodies.iter().enumerate() {
                // a body pair counts like a node pair (bodies in one twist give none)
                pairs += 1;
                if pairs > MAX_WIRE_PAIRS {
                    break 'bodies;
                }
                if ig == ia {
                    continue;
                }
                let (wa, va) = twist(ia, ba.centre);
                let (wg, vg) = twist(ig, ba.centre);
                let (wr, vr) = (sub(wa, wg), sub(va, vg));
                let rotation = norm(wr) * l > PURE_TOL * (norm(wr) * l + norm(vr));
                let unit = if rotation { norm(wr) } else { norm(vr) };
                if unit == 0.0 {
                    continue;
                }
                for &na in &ba.node_ids {
                    for &ng in &bg.node_ids {
                        pairs += 1;
                        if pairs > MAX_WIRE_PAIRS {
                            break 'bodies;
                        }
                        consider(na, ng, unit, rotation);
                    }
                }
            }
            // to a node in no body, measured against the body's own twist
            let (wa, va) = twist(ia, ba.centre);
            let rotation = norm(wa) * l > PURE_TOL * (norm(wa) * l + norm(va));
            let unit = if rotation { norm(wa) } else { norm(va) };
            for &na in &ba.node_ids {
                for &ng in &loose {
                    pairs += 1;
                    if pairs > MAX_WIRE_PAIRS {
                        break 'bodies;
                    }
                    consider(na, ng, unit, rotation);
                }
            }
        }
        // a moving node in no body (a joint of trusses or wires): a wire to any other node,
        // measured against their relative velocity (a translation)
        let umax = field.u.iter().map(|&u| norm(u)).fold(0.0, f64::max);
        'nodes: for &na in &loose {
            if norm(field.u[na]) <= 1e-6 * umax {
                continue;
            }
            for ng in 0..model.nodes.len() {
                pairs += 1;
                if pairs > MAX_WIRE_PAIRS {
                    break 'nodes;
                }
                let unit = norm(sub(field.u[na], field.u[ng]));
                if ng != na && unit > 0.0 {
                    consider(na, ng, unit, false);
                }
            }
        }
        cands.sort_by_key(|c| {
            (
                (c.change * 1e6).round() as u64,
                std::cmp::Reverse((c.rel * 1e9).round() as u64),
            )
        });
        let mut wires: Vec<WireSuggestion> = Vec::new();
        for c in cands.into_iter().take(MAX_WIRE_TRIES) {
            let (na, ng, d) = (c.na, c.ng, c.d);
            if wires.len() >= max_per_state {
                break;
            }
            let pa = position(model, x, na);
            // one wire per line
            let same_line = |w: &WireSuggestion| {
                norm(cross(w.direction, d)) <= 1e-9
                    && norm(cross(sub(pa, w.point), w.direction)) <= 1e-9 * l
            };
            if wires.iter().any(same_line) {
                continue;
            }
            let row = wire_row(model, &a.cols, na, ng, d);
            let (motions_after, self_stresses_after) = match &verify {
                WireCheck::Dense(upd) => {
                    let change_row = Change::AddRow(row);
                    if matches!(upd.predict(&change_row), Prediction::Certain(c) if c != want) {
                        continue;
                    }
                    upd.counts_after(&change_row)
                }
                WireCheck::Sparse(bound) if bound.raises_rank(&row) => want,
                WireCheck::Sparse(_) => continue,
            };
            if (motions_after, self_stresses_after) != want {
                continue;
            }
            wires.push(WireSuggestion {
                from: model.nodes[na].name.clone(),
                to: model.nodes[ng].name.clone(),
                body: anchor(na),
                other: anchor(ng),
                point: pa,
                direction: d,
                length: norm(sub(position(model, x, ng), pa)),
                reciprocal: c.power,
                intended_change: c.change,
                motions_after,
                self_stresses_after,
            });
        }
        out.push(WireAdvice { motion: k, wires });
    }
    Ok(out)
}
