//! Nothing lost (issue 17, item 3): a static path that stops part-way writes every converged
//! step in every format asked for, marks where and why it stopped, and exits 1. The numbers of
//! the converged part (the stop at the limit point, the buckling multiplier and the lowest
//! frequencies there, the inverted column's last valid step) are checked in process in
//! `crates/flexmbd-io/tests/stopped_path_files.rs`.
//!
//! Input: examples/williams_toggle.toml (validation S05, the Williams toggle frame: a dead load
//! of 180 N on the whole frame, beyond its limit load P_max = 150.66 N) with at most 6 Newton
//! iterations per step, so that Newton cannot jump to the far branch and the path stops at the
//! limit point, after step 17 (load factor 0.8…).

mod common;
use common::{example, run, Temp};
use serde_json::Value;

/// The toggle of the example, written into `t`, with 6 Newton iterations per step.
fn toggle(t: &Temp) -> String {
    let text = std::fs::read_to_string(example("williams_toggle.toml")).expect("example");
    let stiff = text.replace("steps = 20\n", "steps = 20\nmax_iterations = 6\n");
    assert_ne!(stiff, text);
    t.write("toggle.toml", stiff.as_bytes())
        .to_string_lossy()
        .into_owned()
}

/// `v` is `want` as printed with six decimals.
fn near(v: &Value, want: f64) -> bool {
    v.as_f64().is_some_and(|v| (v - want).abs() <= 5e-7)
}

/// Exit code, stdout, stderr of `flexmbd ARGS --quiet`.
fn go(args: &[&str]) -> (Option<i32>, String, String) {
    let mut a = args.to_vec();
    a.push("--quiet");
    let out = run(&a);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The stop is reported on stderr with the last converged load factor; that load factor.
fn assert_stop_message(err: &str) -> f64 {
    assert!(
        err.contains("the static path stopped after step 17 (load factor 0.8")
            && err.contains("the results of the converged steps are written")
            && err.contains("no equilibrium found"),
        "{err}"
    );
    assert!(
        err.contains("hint: ") && err.contains("--path arc-length"),
        "{err}"
    );
    err.split("(load factor ")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .and_then(|s| s.parse().ok())
        .expect("load factor in the message")
}

#[test]
fn static_writes_every_converged_step_in_every_format() {
    let t = Temp::new("stopped_static");
    let model = toggle(&t);
    let csv = t.path("csv");
    let (code, out, err) = go(&[
        "static",
        &model,
        "--buckling",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    let last = assert_stop_message(&err);
    // text: steps 0 … 16 on the grid, 17 the last converged sub-step, then the mark
    assert!(out.contains("\n  16    0.8000"), "{out}");
    assert!(out.contains("\n  17    0.8"), "{out}");
    assert!(
        out.contains("\nSTOPPED after step 17 (load factor 0.8"),
        "{out}"
    );
    assert!(out.contains("  what to try: more load steps"), "{out}");
    assert!(out.contains("Last step (load factor 0.8"), "{out}");
    // CSV: every converged step, the summary ends with the mark as a comment
    for k in 0..=17 {
        assert!(csv.join(format!("step_{k:03}.csv")).is_file(), "step {k}");
    }
    assert!(!csv.join("step_018.csv").exists());
    let summary = std::fs::read_to_string(csv.join("summary.csv")).expect("summary");
    let lines: Vec<&str> = summary.lines().collect();
    assert_eq!(lines.len(), 1 + 18 + 1, "{summary}");
    assert!(lines[18].starts_with("17,0.8"), "{summary}");
    assert!(
        lines[19].starts_with("# stopped after step 17 (load factor 0.8"),
        "{summary}"
    );
    // JSON: the steps and the `stopped` object (the buckling multiplier of the last state, near
    // 1 at the limit point, is checked in process: crates/flexmbd-io/tests/stopped_path_files.rs)
    let (code, out, _) = go(&["static", &model, "--json"]);
    assert_eq!(code, Some(1));
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    let steps = doc["steps"].as_array().expect("steps");
    assert_eq!(steps.len(), 18);
    assert!(near(&steps[17]["load_factor"], last));
    let stop = &doc["stopped"];
    assert_eq!(stop["after_step"], 17);
    assert!(near(&stop["load_factor"], last));
    assert!(stop["reason"]
        .as_str()
        .unwrap()
        .contains("no equilibrium found"));
    assert!(stop["what_to_try"].as_str().unwrap().contains("--steps"));
    // a complete path has `stopped: null` and exits 0
    let complete = example("williams_toggle.toml");
    let (code, out, err) = go(&["static", complete.to_str().unwrap(), "--json"]);
    assert_eq!(code, Some(0), "{err}");
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(doc["stopped"], Value::Null);
}

#[test]
fn export_and_view_write_every_converged_step() {
    let t = Temp::new("stopped_export");
    let model = toggle(&t);
    let vtk = t.path("vtk");
    let (code, out, err) = go(&[
        "export",
        &model,
        "--analysis",
        "static",
        "--vtk",
        vtk.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert_stop_message(&err);
    for k in 0..=17 {
        let f = vtk.join(format!("static_{k:04}.vtu"));
        assert!(
            f.is_file() && out.contains(&*f.to_string_lossy()),
            "step {k}"
        );
    }
    assert!(!vtk.join("static_0018.vtu").exists());
    let pvd = std::fs::read_to_string(vtk.join("static.pvd")).expect("pvd");
    assert_eq!(pvd.matches("<DataSet ").count(), 18, "{pvd}");
    assert!(
        pvd.contains("<!-- stopped after step 17 (load factor 0.8"),
        "{pvd}"
    );
    let html = t.path("view.html");
    let (code, _, err) = go(&[
        "view",
        &model,
        "--analysis",
        "static",
        "-o",
        html.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert_stop_message(&err);
    let page = std::fs::read_to_string(&html).expect("page");
    assert!(page.contains("stopped after step 17 (load factor 0.8"));
}

#[test]
fn modes_and_sweep_use_the_converged_steps() {
    let t = Temp::new("stopped_modes");
    let model = toggle(&t);
    // modes at the last converged state
    let (code, out, err) = go(&["modes", &model, "--json", "--count", "2"]);
    assert_eq!(code, Some(1), "{err}");
    let last = assert_stop_message(&err);
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    assert!(near(&doc["load_factor"], last));
    assert_eq!(doc["stopped"]["after_step"], 17);
    assert!(doc["modes"][0]["frequency_hz"].as_f64().is_some());
    // another converged step asked for: its modes, and still exit 1
    let (code, out0, _) = go(&["modes", &model, "--json", "--count", "2", "--at-step", "0"]);
    assert_eq!(code, Some(1));
    let doc0: Value = serde_json::from_str(&out0).expect("JSON");
    assert!(doc0["modes"][0]["frequency_hz"].as_f64().is_some());
    // sweep: a row per converged step, and the mark in text, JSON and CSV
    let csv = t.path("sweep.csv");
    let (code, out, err) = go(&[
        "sweep",
        &model,
        "--count",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, Some(1), "{err}");
    assert_stop_message(&err);
    assert!(out.contains("\n  17    0.8"), "{out}");
    assert!(out.contains("\nSTOPPED after step 17"), "{out}");
    let text = std::fs::read_to_string(&csv).expect("csv");
    assert_eq!(text.lines().count(), 1 + 18 + 1, "{text}");
    assert!(text.ends_with('\n') && text.lines().last().unwrap().starts_with("# stopped"));
    let (code, out, _) = go(&["sweep", &model, "--count", "1", "--json"]);
    assert_eq!(code, Some(1));
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(doc["steps"].as_array().unwrap().len(), 18);
    assert_eq!(doc["stopped"]["after_step"], 17);
}

#[test]
fn an_inverted_column_keeps_its_valid_steps() {
    // tests/reliability/manual_wrong_static_inverted_column: a column crushed through its root
    // in 4 steps; the unloaded state and the last valid sub-step are kept
    let model = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reliability/manual_wrong_static_inverted_column/in.toml");
    let (code, out, err) = go(&["static", model.to_str().unwrap(), "--steps", "4", "--json"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("inverted"), "{err}");
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    let steps = doc["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 2, "{out}");
    assert!(steps[1]["load_factor"].as_f64().is_some());
    assert!(doc["stopped"]["reason"]
        .as_str()
        .unwrap()
        .contains("inverted"));
}

#[test]
fn statespace_linearises_the_last_converged_state() {
    let t = Temp::new("stopped_statespace");
    let model = toggle(&t);
    let io = ["--input", "apex:y", "--output", "apex:y"];
    // JSON: the state of the last converged step, with the mark
    let mut args = vec!["statespace", &model, "--json"];
    args.extend(io);
    let (code, out, err) = go(&args);
    assert_eq!(code, Some(1), "{err}");
    let last = assert_stop_message(&err);
    let doc: Value = serde_json::from_str(&out).expect("JSON");
    assert_eq!(doc["step"], 17);
    assert!(near(&doc["load_factor"], last));
    assert_eq!(doc["stopped"]["after_step"], 17);
    assert!(doc["frequencies_hz"][0].as_f64().is_some());
    let mut args0 = args.clone();
    args0.extend(["--at-step", "0"]);
    let (code, out0, _) = go(&args0);
    assert_eq!(code, Some(1));
    let doc0: Value = serde_json::from_str(&out0).expect("JSON");
    assert!(doc0["frequencies_hz"][0].as_f64().is_some());
    // text, the .m file and the Bode table carry the mark too
    let (m, bode) = (t.path("ss.m"), t.path("bode.csv"));
    let mut args = vec!["statespace", &model];
    args.extend(io);
    args.extend(["--m", m.to_str().unwrap(), "--bode", bode.to_str().unwrap()]);
    let (code, out, err) = go(&args);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        out.contains("\nSTOPPED after step 17 (load factor 0.8"),
        "{out}"
    );
    let mfile = std::fs::read_to_string(&m).expect(".m");
    assert!(
        mfile.contains("\n% stopped after step 17 (load factor 0.8"),
        "{mfile}"
    );
    let table = std::fs::read_to_string(&bode).expect("bode");
    assert!(
        table
            .lines()
            .last()
            .unwrap()
            .starts_with("# stopped after step 17"),
        "{table}"
    );
    // a step beyond the converged ones: an error that says where the path stopped
    let mut args = vec!["statespace", &model, "--at-step", "19"];
    args.extend(io);
    let (code, out, err) = go(&args);
    assert_eq!(code, Some(1), "{err}");
    assert!(out.is_empty(), "{out}");
    assert!(
        err.contains("--at-step 19: the static solution has steps 0 to 17")
            && err.contains("stopped after step 17"),
        "{err}"
    );
}
