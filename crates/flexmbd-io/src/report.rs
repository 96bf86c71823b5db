//! Reports of the kinematic analysis: JSON (`flexmbd check --json`) and aligned text tables.

use flexmbd_core::kinematics::advice::{Action, StateAdvice};
use flexmbd_core::kinematics::ConstraintAnalysis;
use flexmbd_core::model::{CoordKind, DefKind};
use flexmbd_core::Model;
use serde_json::{json, Value};

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
}

/// JSON document of a check.
pub fn check_json(r: &CheckReport<'_>, generalised: &[String]) -> Value {
    let a = r.analysis;
    let mut doc = json!({
        "model": r.model.name,
        "file": r.file,
        "rows": a.m(),
        "cols": a.n(),
        "rank": a.rank,
        "euler_parameter_form": { "rows": a.euler_shape.0, "cols": a.euler_shape.1 },
        "rank_tol": r.rank_tol,
        "rank_threshold": a.tol,
        "rank_gap": a.rank_gap(),
        "singular_values": a.singular_values,
        "table1_row": a.case.row(),
        "classification": a.case.describe(),
        "kinematically_determinate": a.n_motions() == 0,
        "statically_determinate": a.n_self_stresses() == 0,
        "exactly_constrained": a.n_motions() == 0 && a.n_self_stresses() == 0,
        "n_mechanisms": a.n_motions(),
        "n_self_stresses": a.n_self_stresses(),
        "generalised_coordinates": generalised,
        "input_deformations": a.rows.iter().filter(|r| r.kind == DefKind::Input).count(),
        "mechanisms": a.motions,
        "self_stresses": a.self_stresses,
        "suggestions": r.advice,
    });
    if let Some((chosen, before)) = r.auto {
        doc["auto"] = json!({
            "chosen": chosen,
            "before": { "rows": before.m(), "cols": before.n(), "rank": before.rank,
                        "n_mechanisms": before.n_motions(), "n_self_stresses": before.n_self_stresses() },
        });
    }
    doc
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
            "  ... and {rest} more entries of magnitude {} or less (all in --json)\n",
            fmt_num(below)
        )),
    )
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

/// Human report of a check, as aligned tables.
pub fn check_text(r: &CheckReport<'_>, generalised: &[String]) -> String {
    let a = r.analysis;
    let mut s = String::new();
    let title = if r.model.name.is_empty() {
        String::new()
    } else {
        format!(": {}", r.model.name)
    };
    s += &format!("flexmbd check{title}  ({})\n\n", r.file);
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
    let gs = if generalised.is_empty() {
        "none".to_string()
    } else {
        generalised.join(", ")
    };
    s += &format!("generalised coordinates: {gs}\n");
    s += &format!(
        "rank {} (threshold {:.3e} = {:.3e} x s1)",
        a.rank, a.tol, r.rank_tol
    );
    if let Some(g) = a.rank_gap() {
        s += &format!(", gap s{}/s{} = {:.3e}", a.rank, a.rank + 1, g);
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
    s += &singular_value_text(a);
    for (k, m) in a.motions.iter().enumerate() {
        let values: Vec<f64> = m.coordinates.iter().map(|c| c.value).collect();
        let (shown, rest) = top_entries(&values);
        let what = if rest.is_some() {
            format!(", the {TEXT_TOP_ENTRIES} largest of {}", values.len())
        } else {
            String::new()
        };
        s += &format!(
            "\nMotion {} (kinematically indeterminate; nodal velocities, unit length{what})\n",
            k + 1
        );
        let rows: Vec<Vec<String>> = shown
            .iter()
            .map(|&i| &m.coordinates[i])
            .map(|c| {
                vec![
                    c.node.clone(),
                    c.dof.name().to_string(),
                    format!("{:+.6}", c.value),
                ]
            })
            .collect();
        s += &table(&["node", "dof", "velocity"], &rows);
        s += rest.as_deref().unwrap_or("");
    }
    for (k, st) in a.self_stresses.iter().enumerate() {
        let values: Vec<f64> = st.deformations.iter().map(|d| d.value).collect();
        let (shown, rest) = top_entries(&values);
        let what = if rest.is_some() {
            format!(", the {TEXT_TOP_ENTRIES} largest of {}", values.len())
        } else {
            String::new()
        };
        s += &format!(
            "\nSelf-stress state {} (statically indeterminate; stress resultants, unit length{what})\n",
            k + 1
        );
        let rows: Vec<Vec<String>> = shown
            .iter()
            .map(|&i| &st.deformations[i])
            .map(|d| {
                vec![
                    d.element.clone(),
                    d.mode.to_string(),
                    d.mode_name.clone(),
                    format!("{:+.6}", d.value),
                ]
            })
            .collect();
        s += &table(&["element", "mode", "name", "value"], &rows);
        s += rest.as_deref().unwrap_or("");
    }
    if !r.advice.is_empty() {
        s += "\nRepair advice (each verified: the counts after the change recomputed from the SVD)\n";
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
                    "    - {}  -> {} motion(s), {} self-stress(es)\n",
                    sg.action.describe(),
                    sg.motions_after,
                    sg.self_stresses_after
                );
            }
        }
    }
    s
}
