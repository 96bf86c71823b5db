//! The pictures of a study: each figure of merit against each parameter (PNG and SVG, a point
//! per variant that has the value) and `study.html`, one page with every plot, a summary and
//! the table of all records.

use crate::record::{merit_names, Record, Status};
use crate::spec::Study;
use flexmbd_io::plots::{Plot, Series};
use std::collections::BTreeMap;
use std::path::Path;

/// The unit of a figure of merit, for axis labels.
pub fn merit_unit(name: &str) -> &'static str {
    let rot = name.contains("_rx_") || name.contains("_ry_") || name.contains("_rz_");
    match name {
        n if n.ends_with("_drop") || n.ends_with("_ratio") => "-",
        n if n.starts_with("f") && !n.ends_with("_ratio") => "Hz",
        n if n.starts_with("k_") && rot => "N·m/rad",
        n if n.starts_with("k_") => "N/m",
        "max_stress" => "Pa",
        "max_actuation_force" => "N or N·m",
        _ => "-",
    }
}

/// Remove the plots of an earlier run (flexmbd's own file names only).
pub(crate) fn clear(dir: &Path) -> std::io::Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for e in entries.filter_map(Result::ok) {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.contains("_vs_") && (name.ends_with(".png") || name.ends_with(".svg")) {
            std::fs::remove_file(e.path())?;
        }
    }
    Ok(())
}

/// The smallest and largest value of a figure of merit over a study's records, and how many
/// records have a value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeritRange {
    /// The smallest value (none without a value).
    pub min: Option<f64>,
    /// The largest value.
    pub max: Option<f64>,
    /// The number of records with a value.
    pub count: usize,
}

/// The [`MeritRange`] of `merit` over `records`.
pub fn merit_range(records: &BTreeMap<usize, Record>, merit: &str) -> MeritRange {
    let mut r = MeritRange {
        min: None,
        max: None,
        count: 0,
    };
    for v in records
        .values()
        .filter_map(|r| r.merits.get(merit).copied().flatten())
    {
        r.min = Some(r.min.map_or(v, |m| m.min(v)));
        r.max = Some(r.max.map_or(v, |m| m.max(v)));
        r.count += 1;
    }
    r
}

/// Whether a figure of merit whose values span `lo..=hi` varies by more than round-off: by more
/// than 1e-9 of its magnitude, and, for a stiffness drop 1 − k_end/k_start (a ratio of order
/// one), by more than 1e-9 at all (the two ends of a path without a stroke give a drop of a
/// few 1e-11, which is no drop).
fn varies(merit: &str, lo: f64, hi: f64) -> bool {
    let size = lo.abs().max(hi.abs());
    let floor = if merit.ends_with("_drop") {
        1e-9f64.max(1e-9 * size)
    } else {
        1e-9 * size
    };
    hi - lo > floor
}

/// The (merit, parameter) pairs worth a plot: merits whose values vary ([`varies`]).
fn plotted(study: &Study, records: &BTreeMap<usize, Record>) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for m in merit_names(&study.analyses) {
        let MeritRange {
            min: Some(lo),
            max: Some(hi),
            ..
        } = merit_range(records, &m)
        else {
            continue;
        };
        if varies(&m, lo, hi) {
            for p in study.parameter_names() {
                out.push((m.clone(), p.to_string()));
            }
        }
    }
    out
}

fn file_stem(merit: &str, param: &str) -> String {
    let clean = |s: &str| -> String {
        s.chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    c
                } else {
                    '_'
                }
            })
            .collect()
    };
    format!("{}_vs_{}", clean(merit), clean(param))
}

/// Write `plots/MERIT_vs_PARAMETER.{png,svg}` for every figure of merit that varies.
pub fn write_plots(
    dir: &Path,
    study: &Study,
    records: &BTreeMap<usize, Record>,
) -> Result<usize, String> {
    let plots = dir.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| format!("{}: {e}", plots.display()))?;
    clear(&plots).map_err(|e| format!("{}: {e}", plots.display()))?;
    let pairs = plotted(study, records);
    for (m, p) in &pairs {
        let points: Vec<(f64, f64)> = records
            .values()
            .filter_map(|r| Some((*r.parameters.get(p)?, r.merits.get(m).copied().flatten()?)))
            .collect();
        let plot = Plot {
            title: format!("{m} against {p}"),
            x_label: p.clone(),
            y_label: format!("{m} [{}]", merit_unit(m)),
            log_y: false,
            series: vec![Series {
                label: format!("{} variants", points.len()),
                points,
            }],
            hlines: Vec::new(),
            markers: true,
            lines: false,
        };
        plot.write(&plots.join(file_stem(m, p)), (640, 420))
            .map_err(|e| e.to_string())?;
    }
    Ok(pairs.len())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number for a page or a summary: 6 significant digits; empty for none.
pub fn cell(v: Option<f64>) -> String {
    match v {
        None => String::new(),
        Some(v) if v == 0.0 || (1e-3..1e6).contains(&v.abs()) => {
            let digits = (5 - v.abs().log10().floor().max(-1.0) as i32).max(0) as usize;
            let s = format!("{v:.digits$}");
            if s.contains('.') {
                s.trim_end_matches('0').trim_end_matches('.').to_string()
            } else {
                s
            }
        }
        Some(v) => format!("{v:.5e}"),
    }
}

/// `study.html`: a self-contained page (the SVG plots inlined) with the study, the number of
/// variants that ran and failed, the range of every figure of merit, every plot, and the table
/// of the records in variant order.
pub fn write_html(
    dir: &Path,
    study: &Study,
    records: &BTreeMap<usize, Record>,
    total: usize,
) -> Result<(), String> {
    let ok = records.values().filter(|r| r.status == Status::Ok).count();
    let merits = merit_names(&study.analyses);
    let mut h = String::new();
    h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
    h += &format!("<title>{} — flexmbd study</title>\n", esc(&study.name));
    h += "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;font-size:13px}\
td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}th{background:#eee}tr.failed td{background:#fde8e8}td.err{text-align:left;min-width:32em}\
.plots{display:flex;flex-wrap:wrap;gap:8px}.plots svg{width:480px;height:315px;border:1px solid #ddd}</style>\n";
    h += "</head><body>\n";
    h += &format!("<h1>{}</h1>\n", esc(&study.name));
    h += &format!(
        "<p>Study <code>{}</code>, model <code>{}</code>: {} of {} variants evaluated, {} complete, {} failed.</p>\n",
        esc(&study.file),
        esc(&study.model_file),
        records.len(),
        total,
        ok,
        records.len() - ok
    );
    h += "<h2>Figures of merit</h2>\n<table><tr><th>figure of merit</th><th>unit</th><th>min</th><th>max</th><th>variants with a value</th></tr>\n";
    for m in &merits {
        let range = merit_range(records, m);
        h += &format!(
            "<tr><td style=\"text-align:left\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(m),
            esc(merit_unit(m)),
            cell(range.min),
            cell(range.max),
            range.count
        );
    }
    h += "</table>\n<h2>Plots</h2>\n";
    let pairs = plotted(study, records);
    let mut last = String::new();
    for (m, p) in &pairs {
        if *m != last {
            if !last.is_empty() {
                h += "</div>\n";
            }
            h += &format!("<h3>{}</h3>\n<div class=\"plots\">\n", esc(m));
            last = m.clone();
        }
        let svg = dir
            .join("plots")
            .join(file_stem(m, p))
            .with_extension("svg");
        let text = std::fs::read_to_string(&svg).map_err(|e| format!("{}: {e}", svg.display()))?;
        let start = text.find("<svg").unwrap_or(0);
        h += &text[start..];
        h += "\n";
    }
    if !last.is_empty() {
        h += "</div>\n";
    }
    h += "<h2>Records</h2>\n<table><tr><th>variant</th>";
    for p in study.parameter_names() {
        h += &format!("<th>{}</th>", esc(p));
    }
    h += "<th>status</th>";
    for m in &merits {
        h += &format!("<th>{}</th>", esc(m));
    }
    h += "<th>error</th></tr>\n";
    for r in records.values() {
        let failed = r.status == Status::Failed;
        h += &format!(
            "<tr{}><td>{}</td>",
            if failed { " class=\"failed\"" } else { "" },
            r.variant
        );
        for v in r.parameters.values() {
            h += &format!("<td>{}</td>", cell(Some(*v)));
        }
        h += &format!("<td>{}</td>", if failed { "failed" } else { "ok" });
        for m in &merits {
            h += &format!("<td>{}</td>", cell(r.merits.get(m).copied().flatten()));
        }
        let err = r
            .error
            .as_ref()
            .map_or(String::new(), |f| format!("{}: {}", f.stage, f.message));
        h += &format!("<td class=\"err\">{}</td></tr>\n", esc(&err));
    }
    h += "</table>\n</body></html>\n";
    let path = dir.join("study.html");
    std::fs::write(&path, h).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::varies;

    #[test]
    fn round_off_is_not_a_variation() {
        // a frequency from 8.2 to 11.5 Hz varies; the same stiffness up to the last digits
        // does not; a drop of ±5e-11 between two identical states does not; a drop of 1 % does
        assert!(varies("f1", 8.2, 11.5));
        assert!(!varies("k_c_y_start", 249_390.0, 249_390.0 * (1.0 + 1e-13)));
        assert!(!varies("k_c_y_drop", -5.9e-11, 3.4e-11));
        assert!(varies("k_c_y_drop", 0.0, 0.01));
    }
}
