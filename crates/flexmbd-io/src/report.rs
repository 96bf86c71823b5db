//! Reports of the kinematic analysis: JSON (`flexmbd check --json`) and aligned text tables.

use flexmbd_core::kinematics::advice::{Action, StateAdvice, WireAdvice};
use flexmbd_core::kinematics::classify::Classification;
use flexmbd_core::kinematics::freedom::FreedomCheck;
use flexmbd_core::kinematics::screw::ScrewAnalysis;
use flexmbd_core::kinematics::sparse::SparseDecision;
use flexmbd_core::kinematics::{
    ConstraintAnalysis, DeformationValue, Motion, NodalVelocity, SelfStress,
};
use flexmbd_core::model::{CoordKind, DefKind};
use flexmbd_core::Model;
use serde::Serialize;

/// Everything `flexmbd check` reports.
pub struct CheckReport<'a> {
    /// The model.
    pub model: &'a Model,
    /// The model file.
    pub file: &'a str,
    /// The relative rank tolerance used.
    pub rank_tol: f64,
    /// The analysis (after `--auto`, the analysis with the chosen generalised coordinates).
    pub analysis: &'a ConstraintAnalysis,
    /// Verified repair advice.
    pub advice: &'a [StateAdvice],
    /// `--auto`: the generalised coordinates chosen, and the analysis before the choice.
    pub auto: Option<(&'a [Action], &'a ConstraintAnalysis)>,
    /// The motions and self-stresses as twists and wrenches of the bodies.
    pub screws: Option<&'a ScrewAnalysis>,
    /// The comparison with the intended freedom, when the model states one.
    pub freedom: Option<&'a FreedomCheck>,
    /// Verified wires that remove each motion.
    pub wires: &'a [WireAdvice],
}

impl<'a> CheckReport<'a> {
    /// The report of a whole check ([`Classification`]) of `model` read from `file`.
    pub fn of(model: &'a Model, file: &'a str, rank_tol: f64, c: &'a Classification) -> Self {
        Self {
            model,
            file,
            rank_tol,
            analysis: &c.analysis,
            advice: &c.advice,
            auto: c.chosen.as_deref().zip(c.before.as_ref()),
            screws: Some(&c.screws),
            freedom: c.freedom.as_ref(),
            wires: &c.wires,
        }
    }
}

/// A value serialised through [`serde_json::Value`], whose objects have their keys sorted: the
/// key order of the document's small parts (one motion, one state, one suggestion).
struct Sorted<'a, T>(&'a T);

impl<T: Serialize> Serialize for Sorted<'_, T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serde_json::to_value(self.0)
            .map_err(serde::ser::Error::custom)?
            .serialize(s)
    }
}

/// A list serialised element by element ([`Sorted`]), never as a whole.
struct SortedList<'a, T>(&'a [T]);

impl<T: Serialize> Serialize for SortedList<'_, T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.0.iter().map(Sorted))
    }
}

/// Rows and columns of Dcc (the Euler-parameter form and the `--auto` counts before).
#[derive(Serialize)]
struct Shape {
    cols: usize,
    rows: usize,
}

/// The `--auto` object.
#[derive(Serialize)]
struct AutoDoc<'a> {
    before: AutoBefore,
    chosen: SortedList<'a, Action>,
}

#[derive(Serialize)]
struct AutoBefore {
    cols: usize,
    n_mechanisms: usize,
    n_self_stresses: usize,
    rank: usize,
    rows: usize,
}

/// The sparse path's rank decision and the defining row or column of every state.
#[derive(Serialize)]
struct SparseDoc {
    certain: bool,
    method: &'static str,
    /// The coordinate of each motion of the fundamental basis.
    motion_coordinates: Vec<String>,
    nnz: [usize; 3],
    s1: f64,
    s1_rel_residual: f64,
    s_r1_upper_bound: Option<f64>,
    s_r_lower_bound: Option<f64>,
    s_r_rel_residual: f64,
    /// The deformation of each self-stress state of the fundamental basis.
    self_stress_deformations: Vec<String>,
    states_listed: usize,
}

/// The JSON document of a check: keys in sorted order at every level, the order of the
/// `serde_json::Value` document this replaces (byte for byte; a test compares them), written
/// to the output as it is built (the lists element by element).
#[derive(Serialize)]
struct CheckDoc<'a> {
    #[serde(skip_serializing_if = "Option::is_none")]
    auto: Option<AutoDoc<'a>>,
    classification: &'static str,
    cols: usize,
    euler_parameter_form: Shape,
    exactly_constrained: bool,
    file: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    freedom: Option<Sorted<'a, FreedomCheck>>,
    generalised_coordinates: &'a [String],
    input_deformations: usize,
    kinematically_determinate: bool,
    mechanisms: SortedList<'a, Motion>,
    model: &'a str,
    n_mechanisms: usize,
    n_self_stresses: usize,
    rank: usize,
    rank_gap: Option<f64>,
    rank_threshold: f64,
    rank_tol: f64,
    rows: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    screws: Option<Sorted<'a, ScrewAnalysis>>,
    self_stresses: SortedList<'a, SelfStress>,
    singular_values: &'a [f64],
    #[serde(skip_serializing_if = "Option::is_none")]
    sparse: Option<SparseDoc>,
    statically_determinate: bool,
    suggestions: SortedList<'a, StateAdvice>,
    table1_row: usize,
    wire_suggestions: SortedList<'a, WireAdvice>,
}

/// "node.dof" of a column, "element.e<mode>" of a row (the names of `generalised_names`).
fn col_name(model: &Model, a: &ConstraintAnalysis, j: usize) -> String {
    let c = &a.cols[j];
    format!("{}.{}", model.nodes[c.node].name, c.dof.name())
}

fn row_name(model: &Model, a: &ConstraintAnalysis, i: usize) -> String {
    let r = &a.rows[i];
    format!("{}.e{}", model.elements[r.element].name, r.mode + 1)
}

/// Write the JSON document of a check (pretty, with a final newline) to `w`.
pub fn write_check_json(
    w: impl std::io::Write,
    r: &CheckReport<'_>,
    generalised: &[String],
) -> std::io::Result<()> {
    let a = r.analysis;
    let sparse = a.sparse.as_ref().map(|sp| SparseDoc {
        certain: sp.certain,
        method: "sparse rank-revealing LU",
        motion_coordinates: sp
            .motion_cols
            .iter()
            .map(|&j| col_name(r.model, a, j))
            .collect(),
        nnz: [sp.nnz.0, sp.nnz.1, sp.nnz.2],
        s1: sp.s1,
        s1_rel_residual: sp.s1_rel_residual,
        s_r1_upper_bound: sp.s_r1_upper,
        s_r_lower_bound: sp.s_r_lower,
        s_r_rel_residual: sp.s_r_rel_residual,
        self_stress_deformations: sp
            .self_stress_rows
            .iter()
            .map(|&i| row_name(r.model, a, i))
            .collect(),
        states_listed: a.motions.len().max(a.self_stresses.len()),
    });
    let doc = CheckDoc {
        auto: r.auto.map(|(chosen, before)| AutoDoc {
            before: AutoBefore {
                cols: before.n(),
                n_mechanisms: before.n_motions(),
                n_self_stresses: before.n_self_stresses(),
                rank: before.rank,
                rows: before.m(),
            },
            chosen: SortedList(chosen),
        }),
        classification: a.case.describe(),
        cols: a.n(),
        euler_parameter_form: Shape {
            cols: a.euler_shape.1,
            rows: a.euler_shape.0,
        },
        exactly_constrained: a.n_motions() == 0 && a.n_self_stresses() == 0,
        file: r.file,
        freedom: r.freedom.map(Sorted),
        generalised_coordinates: generalised,
        input_deformations: a.rows.iter().filter(|r| r.kind == DefKind::Input).count(),
        kinematically_determinate: a.n_motions() == 0,
        mechanisms: SortedList(&a.motions),
        model: &r.model.name,
        n_mechanisms: a.n_motions(),
        n_self_stresses: a.n_self_stresses(),
        rank: a.rank,
        rank_gap: a.rank_gap(),
        rank_threshold: a.tol,
        rank_tol: r.rank_tol,
        rows: a.m(),
        screws: r.screws.map(Sorted),
        self_stresses: SortedList(&a.self_stresses),
        singular_values: &a.singular_values,
        sparse,
        statically_determinate: a.n_self_stresses() == 0,
        suggestions: SortedList(r.advice),
        table1_row: a.case.row(),
        wire_suggestions: SortedList(r.wires),
    };
    let mut w = std::io::BufWriter::new(w);
    // an I/O error (a closed pipe) comes back as itself
    serde_json::to_writer_pretty(&mut w, &doc).map_err(std::io::Error::from)?;
    std::io::Write::write_all(&mut w, b"\n")?;
    std::io::Write::flush(&mut w)
}

/// Names of the generalised coordinates (x^m and e^m) of a partition.
pub fn generalised_names(model: &Model, px: &[CoordKind], pe: &[DefKind]) -> Vec<String> {
    let mut out = Vec::new();
    for n in &model.nodes {
        for d in flexmbd_core::model::Dof::ALL {
            // a hosted node's position is its host's: listed there
            if n.host.is_some() && !d.is_rotation() {
                continue;
            }
            if let Some(i) = n.x_index(d) {
                if px[i] == CoordKind::Input {
                    out.push(format!("{}.{}", n.name, d.name()));
                }
            }
        }
    }
    for (i, k) in pe.iter().enumerate() {
        if *k == DefKind::Input {
            let (el, mode) = model.deformation_owner(i);
            out.push(format!("{}.e{}", model.elements[el].name, mode + 1));
        }
    }
    out
}

/// A number for tables: fixed notation in [1e-3, 1e5), scientific otherwise (7 significant
/// digits).
pub fn fmt_num(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-3..1e5).contains(&a) {
        format!("{v:.6}")
    } else {
        format!("{v:.6e}")
    }
}

/// The first line of a text report and the blank line after it: `flexmbd COMMAND: MODEL  (FILE)`
/// (without `: MODEL` when the model has no name).
pub(crate) fn heading(command: &str, model: &Model, file: &str) -> String {
    format!("flexmbd {command}{}  ({file})\n\n", model_name(model))
}

/// `": name"` of a named model, empty for one without a name (the headings' model part).
pub(crate) fn model_name(model: &Model) -> String {
    if model.name.is_empty() {
        String::new()
    } else {
        format!(": {}", model.name)
    }
}

/// Left-aligned text table with a header row.
pub fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut w: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for r in rows {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let line = |cells: Vec<String>| {
        let mut s = String::from("  ");
        for (i, c) in cells.iter().enumerate() {
            let pad = w[i] - c.chars().count();
            s.push_str(c);
            if i + 1 < cells.len() {
                s.push_str(&" ".repeat(pad + 2));
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(header.iter().map(|h| h.to_string()).collect());
    out += &line(w.iter().map(|&n| "-".repeat(n)).collect());
    for r in rows {
        out += &line(r.clone());
    }
    out
}

/// Up to this many singular values the text report lists them all; above, the largest, those
/// around the rank decision and the smallest (`--json` has them all).
pub const TEXT_ALL_SINGULAR_VALUES: usize = 200;
/// Motions and self-stress states with up to this many non-zero entries are listed in full in
/// the text report; longer ones by their largest entries.
pub const TEXT_ALL_ENTRIES: usize = 40;
/// The entries shown of a long motion or self-stress state.
pub const TEXT_TOP_ENTRIES: usize = 10;
/// Singular values shown on each side of the rank decision, and at each end, of a long list.
const TEXT_NEAR_RANK: usize = 5;

/// The rows of a long vector shown in text: the `TEXT_TOP_ENTRIES` largest by magnitude,
/// largest first, and a closing line for the rest.
fn top_entries(values: &[f64]) -> (Vec<usize>, Option<String>) {
    top_of(values, "entries", "  ")
}

/// [`top_entries`] for a list of `what` (the closing line indented by `indent`): all of them
/// up to `TEXT_ALL_ENTRIES`, else the `TEXT_TOP_ENTRIES` largest by magnitude.
pub(crate) fn top_of(values: &[f64], what: &str, indent: &str) -> (Vec<usize>, Option<String>) {
    if values.len() <= TEXT_ALL_ENTRIES {
        return ((0..values.len()).collect(), None);
    }
    let mut order: Vec<usize> = (0..values.len()).collect();
    // largest magnitude first; equal magnitudes in vector order (stable)
    order.sort_by(|&a, &b| values[b].abs().total_cmp(&values[a].abs()));
    let rest = values.len() - TEXT_TOP_ENTRIES;
    let below = values[order[TEXT_TOP_ENTRIES]].abs();
    let top = order[..TEXT_TOP_ENTRIES].to_vec();
    (
        top,
        Some(format!(
            "{indent}... and {rest} more {what} of magnitude {} or less (all in --json)\n",
            fmt_num(below)
        )),
    )
}

/// What the entries of a motion and of a self-stress state are, in the text report.
const MOTION_KIND: &str = "kinematically indeterminate; nodal velocities";
const SELF_STRESS_KIND: &str = "statically indeterminate; stress resultants";

/// A motion or self-stress state in text: the heading `title (kind, unit length)` (for a long
/// vector with how many of its entries are shown), then a table of the entries shown
/// ([`top_entries`]), each its `cells` and its `value`, and the line for the rest.
fn null_vector_text<T>(
    (title, kind): (&str, &str),
    (entries, value, cells): (&[T], impl Fn(&T) -> f64, impl Fn(&T) -> Vec<String>),
    header: &[&str],
) -> String {
    let values: Vec<f64> = entries.iter().map(value).collect();
    let (shown, rest) = top_entries(&values);
    let of = if rest.is_some() {
        format!(", the {TEXT_TOP_ENTRIES} largest of {}", values.len())
    } else {
        String::new()
    };
    let rows: Vec<Vec<String>> = shown
        .iter()
        .map(|&i| {
            let mut row = cells(&entries[i]);
            row.push(format!("{:+.6}", values[i]));
            row
        })
        .collect();
    let heading = format!("\n{title} ({kind}, unit length{of})\n");
    heading + &table(header, &rows) + rest.as_deref().unwrap_or("")
}

/// The singular-value table of the text report: all of them for small models; else the
/// largest, those around the rank decision and the smallest, with "..." where some are left out.
fn singular_value_text(a: &ConstraintAnalysis) -> String {
    let sv = &a.singular_values;
    let row = |i: usize| {
        let v = sv[i];
        let mark = if v <= a.tol { "zero" } else { "" };
        vec![format!("{}", i + 1), fmt_num(v), mark.to_string()]
    };
    if sv.len() <= TEXT_ALL_SINGULAR_VALUES {
        let rows: Vec<Vec<String>> = (0..sv.len()).map(row).collect();
        return "\nSingular values of Dcc\n".to_string() + &table(&["#", "value", ""], &rows);
    }
    let k = TEXT_NEAR_RANK;
    let mut shown: Vec<usize> = (0..3).collect();
    shown.extend(a.rank.saturating_sub(k)..(a.rank + k).min(sv.len()));
    shown.extend(sv.len().saturating_sub(k)..sv.len());
    shown.sort_unstable();
    shown.dedup();
    let mut rows = Vec::new();
    let mut next = 0;
    for &i in &shown {
        if i > next {
            rows.push(vec!["...".to_string(), String::new(), String::new()]);
        }
        rows.push(row(i));
        next = i + 1;
    }
    let mut s = format!(
        "\nSingular values of Dcc: {} in all; the largest, the {k} on each side of the rank \
         decision and the smallest (all in --json)\n",
        sv.len()
    );
    if a.rank > 0 {
        s += &format!(
            "  rank decision: s{} = {} is {} x the threshold {}",
            a.rank,
            fmt_num(sv[a.rank - 1]),
            fmt_num(sv[a.rank - 1] / a.tol.max(f64::MIN_POSITIVE)),
            fmt_num(a.tol)
        );
        match sv.get(a.rank) {
            Some(z) => {
                s += &format!(
                    "; s{} = {} is the largest counted as zero (gap s{}/s{} = {})\n",
                    a.rank + 1,
                    fmt_num(*z),
                    a.rank,
                    a.rank + 1,
                    fmt_num(sv[a.rank - 1] / z.max(1e-300))
                )
            }
            None => s += "; no singular value is counted as zero\n",
        }
    }
    s + &table(&["#", "value", ""], &rows)
}

/// The rank decision of the sparse path: s₁, the threshold, the bounds on the two sides of it,
/// and what the bases are.
fn sparse_decision_text(a: &ConstraintAnalysis, sp: &SparseDecision) -> String {
    let mut s = format!(
        "\nRank decision (sparse rank-revealing LU of Dcc; {} nonzeros, {} in L, {} in U)\n",
        sp.nnz.0, sp.nnz.1, sp.nnz.2
    );
    s += &format!(
        "  s1 = {} (Lanczos, relative residual {:.1e}); threshold {} = {:.3e} x s1\n",
        fmt_num(sp.s1),
        sp.s1_rel_residual,
        fmt_num(a.tol),
        a.tol / sp.s1.max(f64::MIN_POSITIVE)
    );
    let tol = a.tol.max(f64::MIN_POSITIVE);
    match sp.s_r_lower {
        Some(lo) => {
            s += &format!(
                "  kept: s{} >= {} (smallest singular value of the {r} x {r} block of pivot rows \
                 and basic columns, Lanczos estimate), {} x the threshold\n",
                a.rank,
                fmt_num(lo),
                fmt_num(lo / tol),
                r = a.rank
            )
        }
        None => s += "  kept: none (rank 0)\n",
    }
    match sp.s_r1_upper {
        Some(up) => {
            s += &format!(
                "  counted as zero: s{} <= {} (Frobenius norm of the dropped entries), {} x the \
                 threshold\n",
                a.rank + 1,
                fmt_num(up),
                fmt_num(up / tol)
            )
        }
        None => s += "  counted as zero: none (full rank)\n",
    }
    s += if sp.certain {
        "  decision certain: both bounds clear the threshold by a factor 2 or more\n"
    } else {
        "  decision UNCERTAIN: a bound is within a factor 2 of the threshold; compare with the \
         dense SVD or set the rank tolerance explicitly\n"
    };
    s += &format!(
        "  bases: one motion per dependent coordinate, one self-stress state per redundant \
         constraint (fundamental bases); {} of {} motions and {} of {} self-stress states listed \
         (every defining coordinate and constraint in --json)\n",
        a.motions.len(),
        a.n_motions(),
        a.self_stresses.len(),
        a.n_self_stresses()
    );
    s
}

/// Human report of a check, as aligned tables.
pub fn check_text(r: &CheckReport<'_>, generalised: &[String]) -> String {
    let a = r.analysis;
    let mut s = heading("check", r.model, r.file);
    if let Some((chosen, before)) = r.auto {
        s += &format!(
            "--auto: {} motion(s) found without extra generalised coordinates; chose {}:\n",
            before.n_motions(),
            chosen.len()
        );
        for c in chosen {
            s += &format!("  - {}\n", c.describe());
        }
        s += "verified by repeating the analysis:\n\n";
    }
    s += &format!(
        "Dcc: {} rows (fixed and input deformations) x {} columns (dependent velocities)\n",
        a.m(),
        a.n()
    );
    s += &format!(
        "     SPACAR Euler-parameter form: {} x {} (same counts, see docs/rotations.md)\n",
        a.euler_shape.0, a.euler_shape.1
    );
    // a long list (a flexure of many beams: six deformations each) by its ends
    const LISTED: usize = 24;
    let gs = if generalised.is_empty() {
        "none".to_string()
    } else if generalised.len() <= LISTED {
        generalised.join(", ")
    } else {
        let k = generalised.len();
        format!(
            "{k} in all: {}, ..., {} (all in --json)",
            generalised[..LISTED - 4].join(", "),
            generalised[k - 4..].join(", ")
        )
    };
    s += &format!("generalised coordinates: {gs}\n");
    s += &format!(
        "rank {} (threshold {:.3e} = {:.3e} x s1)",
        a.rank, a.tol, r.rank_tol
    );
    if let Some(g) = a.rank_gap() {
        let rel = if a.sparse.is_some() { ">=" } else { "=" };
        s += &format!(", gap s{}/s{} {rel} {:.3e}", a.rank, a.rank + 1, g);
    }
    if a.sparse.is_some() {
        s += ", sparse rank-revealing LU";
    }
    s += "\n\n";
    s += &format!("Table 1, row {}: {}\n", a.case.row(), a.case.describe());
    s += &format!(
        "  kinematically indeterminate motions (n - r): {}\n",
        a.n_motions()
    );
    s += &format!(
        "  self-stress states (m - r):                  {}\n",
        a.n_self_stresses()
    );
    if a.n_motions() == 0 && a.n_self_stresses() == 0 {
        s += "  => exactly constrained\n";
    }
    s += &match &a.sparse {
        Some(sp) => sparse_decision_text(a, sp),
        None => singular_value_text(a),
    };
    for (k, m) in a.motions.iter().enumerate() {
        let cells = |c: &NodalVelocity| vec![c.node.clone(), c.dof.name().to_string()];
        s += &null_vector_text(
            (&format!("Motion {}", k + 1), MOTION_KIND),
            (&m.coordinates, |c| c.value, cells),
            &["node", "dof", "velocity"],
        );
    }
    for (k, st) in a.self_stresses.iter().enumerate() {
        let cells =
            |d: &DeformationValue| vec![d.element.clone(), d.mode.to_string(), d.mode_name.clone()];
        s += &null_vector_text(
            (&format!("Self-stress state {}", k + 1), SELF_STRESS_KIND),
            (&st.deformations, |d| d.value, cells),
            &["element", "mode", "name", "value"],
        );
    }
    if let Some(sc) = r.screws {
        s += &crate::screw_report::screws_text(sc);
    }
    if let Some(f) = r.freedom {
        s += &crate::screw_report::freedom_text(f);
    }
    if !r.advice.is_empty() {
        s += if a.sparse.is_some() {
            "\nRepair advice (each verified: the change keeps the pivot rows and basic columns, so \
             the bounds of the rank decision hold)\n"
        } else {
            "\nRepair advice (each verified: the counts after the change recomputed from the SVD)\n"
        };
        for st in r.advice {
            let what = if st.kind == "motion" {
                "motion"
            } else {
                "self-stress state"
            };
            s += &format!("  {} {}: any one of\n", what, st.state + 1);
            if st.suggestions.is_empty() {
                s += "    (no single change removes it; see the state above)\n";
            }
            for sg in &st.suggestions {
                s += &format!(
                    "    - {}{}  -> {} motion(s), {} self-stress(es)\n",
                    sg.action.describe(),
                    crate::screw_report::designer_release(sg),
                    sg.motions_after,
                    sg.self_stresses_after
                );
            }
        }
    }
    s += &crate::screw_report::wires_text(r.wires);
    s
}
