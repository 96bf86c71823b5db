//! `flexmbd static` as a user runs it: JSON and CSV outputs, the text report, the path method
//! from the flag or the file, bad options. The numbers of these examples are checked at the io
//! level (`crates/flexmbd-io/tests/example_static.rs`).

use serde_json::Value;

mod common;
use common::run_json as run;

fn example() -> String {
    format!(
        "{}/../../examples/parallel_leaf_stroke.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn parallel_leaf_stroke_writes_json_and_csv() {
    // the smoke run of `flexmbd static` (the numbers: flexmbd-io/tests/example_static.rs)
    let dir = std::env::temp_dir().join(format!("flexmbd-static-{}", std::process::id()));
    let ex = example();
    let (out, json) = run(&[
        "static",
        &ex,
        "--json",
        "--quiet",
        "--csv",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json.expect("JSON");
    let steps = doc["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 21);

    // CSV: a summary row per step and a table per step
    let summary = std::fs::read_to_string(dir.join("summary.csv")).unwrap();
    assert_eq!(summary.lines().count(), 22);
    assert!(dir.join("step_020.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn static_text_report_and_bad_options() {
    let ex = example();
    let (out, _) = run(&["static", &ex, "--steps", "2", "--quiet"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("Reactions at supports and inputs") && text.contains("held"),
        "{text}"
    );
    let (out, _) = run(&["static", &ex, "--compliance", "nowhere"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nowhere"));
    let (out, _) = run(&["static", &ex, "--steps", "0"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn williams_toggle_path_method_from_the_flag_or_the_file() {
    // examples/williams_toggle.toml by arc length, asked for by `--path` or by the model's
    // [static] table: both limit points are passed (their loads against validation.md S05:
    // flexmbd-io/tests/example_static.rs); the text report names them; an unknown method is
    // an input error at its line
    let ex = format!(
        "{}/../../examples/williams_toggle.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let check = |out: &std::process::Output, doc: Option<Value>| {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc = doc.expect("JSON");
        let events = doc["events"].as_array().expect("events");
        assert_eq!(events.len(), 2, "{events:?}");
        for e in events {
            assert_eq!(e["kind"], "limit_point");
        }
        assert_eq!(doc["stopped"], Value::Null);
    };
    let (out, json) = run(&["static", &ex, "--path", "arc-length", "--json", "--quiet"]);
    check(&out, json);
    // the same from the model's [static] table
    let t = common::Temp::new("arc_toml");
    let text = std::fs::read_to_string(&ex).unwrap();
    let with = text.replace("[static]\n", "[static]\npath = \"arc-length\"\n");
    assert_ne!(with, text);
    let p = t.write("toggle.toml", with.as_bytes());
    let (out, json) = run(&["static", p.to_str().unwrap(), "--json", "--quiet"]);
    check(&out, json);
    // the text report names the limit points
    let (out, _) = run(&["static", p.to_str().unwrap(), "--quiet"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.matches("LIMIT POINT").count(), 2, "{text}");
    // an unknown method is an input error at its line
    let bad = t.write("bad.toml", text_with(&with, "path = \"arc\"").as_bytes());
    let (out, _) = run(&["static", bad.to_str().unwrap(), "--quiet"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml:") && err.contains("`path`"), "{err}");
}

/// `text` with its `path = …` line replaced by `line`.
fn text_with(text: &str, line: &str) -> String {
    text.replace("path = \"arc-length\"", line)
}

#[test]
fn tangent_eigenvalues_at_load_steps_only_when_asked_for() {
    // with load steps κ is off by default (`null` at every step); the flag, or the key in
    // [static], turns it on: three values per step of the parallel-leaf guide
    let ex = example();
    let count = |args: &[&str]| -> Vec<Option<usize>> {
        let (out, json) = run(args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        json.expect("JSON")["steps"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["tangent_eigenvalues"].as_array().map(Vec::len))
            .collect()
    };
    let off = count(&["static", &ex, "--steps", "3", "--json", "--quiet"]);
    assert!(off.iter().all(Option::is_none), "{off:?}");
    let on = count(&[
        "static",
        &ex,
        "--steps",
        "3",
        "--json",
        "--quiet",
        "--tangent-eigenvalues",
    ]);
    assert!(on.iter().all(|n| *n == Some(3)), "{on:?}");
    let text = std::fs::read_to_string(&ex).unwrap();
    let keyed = text.replacen("[static]", "[static]\ntangent_eigenvalues = true", 1);
    assert_ne!(keyed, text, "the example has a [static] table");
    let dir = common::Temp::new("static-kappa-key");
    let file = dir.write("keyed.toml", keyed.as_bytes());
    let from_key = count(&[
        "static",
        file.to_str().unwrap(),
        "--steps",
        "3",
        "--json",
        "--quiet",
    ]);
    assert_eq!(from_key, on);
}
