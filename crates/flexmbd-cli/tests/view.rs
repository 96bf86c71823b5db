//! `flexmbd view`: the HTML report (its data and self-containedness; the page itself in a
//! browser is checked by html_chromium.py), bad input, and the global `--quiet`.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;
use std::sync::atomic::{AtomicUsize, Ordering};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn temp_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "flexmbd-view-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

mod common;

fn run(args: &[&str]) -> Output {
    common::run_in(Some(&root()), args)
}

/// `flexmbd view examples/MODEL.toml ARGS -o OUT`: the page and its data.
fn view(model: &str, args: &[&str]) -> (String, Value) {
    let out = temp_dir().join("report.html");
    let ex = format!("examples/{model}.toml");
    let mut all = vec!["view", ex.as_str(), "-o", out.to_str().unwrap()];
    all.extend(args);
    let r = run(&all);
    assert!(
        r.status.success(),
        "flexmbd view {model} {args:?}: {}",
        String::from_utf8_lossy(&r.stderr)
    );
    let stdout = String::from_utf8_lossy(&r.stdout);
    assert!(
        stdout.starts_with(&format!("wrote {}", out.display())),
        "{stdout}"
    );
    let html = std::fs::read_to_string(&out).expect("report written");
    assert!(
        stdout.contains(&format!("({} bytes)", html.len())),
        "{stdout}"
    );
    let open = r#"<script type="application/json" id="flexmbd-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data");
    let data: Value = serde_json::from_str(&html[start..end]).expect("data is JSON");
    (html, data)
}

#[test]
fn check_report_of_the_twelve_truss() {
    let (html, d) = view("twelve_truss", &[]);
    assert!(html.starts_with("<!DOCTYPE html>"));
    assert_eq!(d["analysis"], "check");
    assert_eq!(d["summary"]["table1_row"], 2);
    assert_eq!(d["summary"]["n_motions"], 1);
    assert_eq!(d["animations"].as_array().unwrap().len(), 1);
    assert_eq!(d["fields"][0]["key"], "self_stress_1");
    assert_eq!(d["elements"].as_array().unwrap().len(), 12);
    // self-contained: the three.js sources are inlined, nothing is loaded
    assert!(html.contains(r#"<script type="text/plain" id="three-module">"#));
    assert!(!html.to_ascii_lowercase().contains("<script src"));
}

#[test]
fn check_report_of_the_six_folded_sheets() {
    let (_, d) = view("folded_sheet_guide_6", &[]);
    assert_eq!(d["summary"]["table1_row"], 3);
    assert_eq!(d["summary"]["n_self_stresses"], 1);
    assert!(d["animations"].as_array().unwrap().is_empty());
    let sheets = d["elements"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "beam" && e["section"]["shape"] == "rectangle")
        .count();
    assert_eq!(sheets, 12);
    assert!(!d["summary"]["advice"].as_array().unwrap().is_empty());
}

#[test]
fn static_report_has_every_load_step() {
    let (_, d) = view(
        "parallel_leaf_stroke",
        &["--analysis", "static", "--steps", "3"],
    );
    assert_eq!(d["analysis"], "static");
    let frames = d["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 4);
    assert_eq!(frames[3]["load_factor"], 1.0);
    let keys: Vec<&str> = d["fields"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["key"].as_str().unwrap())
        .collect();
    assert!(keys.contains(&"max_stress"), "{keys:?}");
    // the classification of the kinematic model is shown too
    assert_eq!(d["summary"]["table1_row"], 6);
}

#[test]
fn modes_report_lists_frequencies() {
    let (_, d) = view("strip_f01", &["--analysis", "modes", "--count", "3"]);
    let a = d["animations"].as_array().unwrap();
    assert_eq!(a.len(), 3);
    let f1 = a[0]["value"].as_f64().unwrap();
    assert!((f1 - 40.9).abs() < 0.1, "{f1}");
    assert_eq!(a[0]["detail"], "40.90 Hz");
    assert_eq!(d["fields"][0]["key"], "strain_energy");
}

#[track_caller]
fn fails(args: &[&str], code: i32, parts: &[&str]) {
    let r = run(args);
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(code), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for p in parts {
        assert!(stderr.contains(p), "`{p}` missing in: {stderr}");
    }
}

#[test]
fn bad_input_is_named() {
    let dir = temp_dir();
    let out = dir.join("r.html");
    let out = out.to_str().unwrap();
    // a model error names file, line and item
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "[nodes]\na = [0.0, 0.0, 0.0]\n\n[[truss]]\nid = \"t\"\nnodes = [\"a\", \"zz\"]\n",
    )
    .unwrap();
    let bad_s = bad.to_str().unwrap();
    fails(
        &["view", bad_s, "-o", out],
        2,
        &[&format!("{bad_s}:4:"), "element `t`", "`zz`"],
    );
    assert!(!Path::new(out).exists(), "no report for a bad model");
    fails(
        &["view", "examples/missing.toml", "-o", out],
        2,
        &["examples/missing.toml"],
    );
    fails(
        &[
            "view",
            "examples/strip_f01.toml",
            "--analysis",
            "modes",
            "--at-step",
            "99",
            "-o",
            out,
        ],
        2,
        &["--at-step 99"],
    );
    fails(
        &[
            "view",
            "examples/strip_f01.toml",
            "--analysis",
            "modes",
            "--count",
            "0",
            "-o",
            out,
        ],
        2,
        &["--count"],
    );
    fails(
        &[
            "view",
            "examples/twelve_truss.toml",
            "--rank-tol",
            "-1",
            "-o",
            out,
        ],
        2,
        &["--rank-tol"],
    );
    // -o is required
    fails(&["view", "examples/twelve_truss.toml"], 2, &["--output"]);
    // an output that cannot be written: a directory (an I/O failure, exit 4)
    let d = dir.to_str().unwrap();
    fails(
        &["view", "examples/twelve_truss.toml", "-o", d],
        4,
        &["cannot write", d],
    );
}

#[test]
fn quiet_is_global_and_no_progress_goes_to_a_pipe() {
    for args in [
        &[
            "--quiet",
            "static",
            "examples/parallel_leaf_stroke.toml",
            "--steps",
            "2",
        ][..],
        &[
            "static",
            "examples/parallel_leaf_stroke.toml",
            "--steps",
            "2",
            "--quiet",
        ],
        &[
            "static",
            "examples/parallel_leaf_stroke.toml",
            "--steps",
            "2",
        ],
        &[
            "sweep",
            "examples/strip_f01.toml",
            "--steps",
            "1",
            "--count",
            "1",
        ],
        &["modes", "examples/strip_f01.toml", "--count", "1"],
    ] {
        let r = run(args);
        let stderr = String::from_utf8_lossy(&r.stderr);
        assert!(r.status.success(), "{args:?}: {stderr}");
        // stderr is a pipe here: no bar, spinner or terminal control sequence
        assert!(
            !stderr.contains("load step") && !stderr.contains('\u{1b}'),
            "{args:?}: {stderr}"
        );
    }
}
