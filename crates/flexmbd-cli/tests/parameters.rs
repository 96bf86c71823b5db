//! `--set NAME=VALUE` and models with `[parameters]` (docs/model-format.md, "Parameters and
//! expressions"): a parametric cantilever strip against the Euler–Bernoulli closed form, the
//! parameter values stated in the outputs, the errors (exit code 2, file, line and item), and
//! the parametric folded-sheet guide against the model it was written from.

mod common;
use common::{example, run, run_json, Temp};
use serde_json::Value;

/// A cantilever strip of length L, width 10 mm and thickness t (Euler–Bernoulli: no shear),
/// with the parameters `L` and `t`.
fn strip() -> String {
    std::fs::read_to_string(common::root().join("crates/flexmbd-cli/tests/models/param_strip.toml"))
        .expect("the strip model")
}

/// First bending frequency of a clamped-free Euler–Bernoulli beam bending across its
/// thickness: f1 = (β1 L)² / (2π) · sqrt(E I / (ρ A L⁴)), β1 L = 1.8751041 (Timoshenko &
/// Young), I/A = t²/12, so f1 = 1.8751041² / (2π) · t / L² · sqrt(E / (12 ρ)).
fn f1_closed_form(t: f64, l: f64) -> f64 {
    let (e, rho): (f64, f64) = (2.1e11, 7800.0);
    1.875_104_068_7_f64.powi(2) / (2.0 * std::f64::consts::PI) * t / (l * l)
        * (e / (12.0 * rho)).sqrt()
}

/// The first frequency of `flexmbd modes MODEL --json ARGS`, and the document.
fn first_frequency(model: &std::path::Path, args: &[&str]) -> (f64, Value) {
    let mut all = vec!["modes", model.to_str().expect("path"), "--json"];
    if !args.contains(&"--count") {
        all.extend(["--count", "2"]);
    }
    all.extend(args);
    let (out, json) = run_json(&all);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = json.expect("JSON on stdout");
    let f = json["modes"][0]["frequency_hz"]
        .as_f64()
        .expect("frequency");
    (f, json)
}

#[test]
fn the_first_frequency_of_a_strip_follows_t_and_l_under_set() {
    let dir = Temp::new("param-strip");
    let model = dir.write("strip.toml", strip().as_bytes());
    for (args, t, l) in [
        (vec![], 0.2e-3, 0.1),
        (vec!["--set", "t=0.4e-3"], 0.4e-3, 0.1),
        (vec!["--set", "t=0.1e-3", "--set", "L=0.2"], 0.1e-3, 0.2),
    ] {
        let (f, json) = first_frequency(&model, &args);
        let want = f1_closed_form(t, l);
        // ten elements and the rotary inertia of the section: within 0.1 %
        assert!(
            (f / want - 1.0).abs() < 1e-3,
            "t = {t}, L = {l}: {f} Hz, closed form {want} Hz"
        );
        // the values used are in the document
        assert_eq!(json["parameters"]["t"].as_f64(), Some(t));
        assert_eq!(json["parameters"]["L"].as_f64(), Some(l));
    }
    // f1 ∝ t: doubling t doubles f1 (the rotary inertia, ∝ t³, changes it by < 1e-5)
    let (f_a, _) = first_frequency(&model, &[]);
    let (f_b, _) = first_frequency(&model, &["--set", "t=0.4e-3"]);
    assert!((f_b / f_a - 2.0).abs() < 1e-4, "{f_b} / {f_a}");
    // a path of the document sets the same value on a model without parameters
    let plain = strip()
        .replace("[parameters]\nL = 0.1\nt = 0.2e-3\n", "")
        .replace("\"L\"", "0.1")
        .replace("t = \"t\"", "t = 0.2e-3");
    let plain = dir.write("plain.toml", plain.as_bytes());
    let (f_c, json) = first_frequency(&plain, &["--set", "sections.s.t=0.4e-3"]);
    assert!((f_c / f_b - 1.0).abs() < 1e-12, "{f_c} != {f_b}");
    assert_eq!(json["parameters"]["sections.s.t"].as_f64(), Some(0.4e-3));
    // without parameters and without --set, no `parameters` in the outputs
    let (_, json) = first_frequency(&plain, &[]);
    assert!(json.get("parameters").is_none());
    let out = run(&["check", plain.to_str().expect("path")]);
    assert!(!String::from_utf8_lossy(&out.stdout).contains("parameters"));
}

#[test]
fn text_outputs_state_the_parameters_under_their_title() {
    let dir = Temp::new("param-text");
    let model = dir.write("strip.toml", strip().as_bytes());
    for cmd in ["check", "static", "modes"] {
        let out = run(&[cmd, model.to_str().expect("path"), "--set", "t=3e-4"]);
        let text = String::from_utf8_lossy(&out.stdout);
        let lines: Vec<&str> = text.lines().collect();
        assert!(
            lines[0].starts_with(&format!("flexmbd {cmd}: strip")),
            "{text}"
        );
        assert_eq!(lines[1], "parameters: L = 0.1, t = 0.0003", "{text}");
    }
    let out = run(&["check", "--json", model.to_str().expect("path")]);
    let json: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(json["parameters"]["t"].as_f64(), Some(0.2e-3));
}

/// Run `flexmbd ARGS`, expect exit code 2; stderr.
#[track_caller]
fn fails(args: &[&str]) -> String {
    let out = run(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

#[test]
fn set_errors_exit_with_code_2_naming_file_line_and_item() {
    let dir = Temp::new("param-errors");
    let model = dir.write("strip.toml", strip().as_bytes());
    let m = model.to_str().expect("path");
    // a parameter the model does not declare: the declared ones are listed
    let e = fails(&["modes", m, "--set", "thickness=1e-4"]);
    assert!(
        e.contains("strip.toml") && e.contains("`thickness`") && e.contains("are: L, t"),
        "{e}"
    );
    // a value that is not a number
    let e = fails(&["check", m, "--set", "t=thin"]);
    assert!(
        e.contains("--set") && e.contains("unknown name `thin`"),
        "{e}"
    );
    let e = fails(&["check", m, "--set", "t"]);
    assert!(e.contains("NAME=VALUE"), "{e}");
    // a path that does not exist
    let e = fails(&["static", m, "--set", "sections.s.q=1"]);
    assert!(
        e.contains("sections.s.q") && e.contains("no key `q`"),
        "{e}"
    );
    // a value that makes an expression of the file fail: line 27 `t = "t"` of the section,
    // column 10 the `/`
    let bad = strip().replace("t = \"t\"", "t = \"0.01/(t - 2e-4)\"");
    let model = dir.write("bad.toml", bad.as_bytes());
    let e = fails(&["modes", model.to_str().expect("path")]);
    assert!(
        e.contains("bad.toml:27:10") && e.contains("section `s`") && e.contains("division by zero"),
        "{e}"
    );
    // a SPACAR file has no parameters
    let dat = dir.write("m.dat", b"BEAM 1 1 2 3 4 0 1 0\nEND\n");
    let e = fails(&["check", dat.to_str().expect("path"), "--set", "t=1"]);
    assert!(e.contains("TOML"), "{e}");
}

/// Every number of two JSON documents within 1e-12 relative (1e-15 absolute for values that
/// are zero in one: cos 90° evaluates to 6e-17, the file writes 0.0).
fn same_numbers(a: &Value, b: &Value, path: &str) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().expect("f64"), y.as_f64().expect("f64"));
            let tol = (1e-12 * x.abs().max(y.abs())).max(1e-15);
            assert!((x - y).abs() <= tol, "{path}: {x} != {y}");
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{path}");
            for (i, (x, y)) in x.iter().zip(y).enumerate() {
                same_numbers(x, y, &format!("{path}.{i}"));
            }
        }
        (Value::Object(x), Value::Object(y)) => {
            let keys = |m: &serde_json::Map<String, Value>| m.keys().cloned().collect::<Vec<_>>();
            assert_eq!(keys(x), keys(y), "{path}");
            for (k, v) in x {
                same_numbers(v, &y[k], &format!("{path}.{k}"));
            }
        }
        _ => assert_eq!(a, b, "{path}"),
    }
}

#[test]
fn the_parametric_guide_is_the_paper_guide_at_its_defaults() {
    let param = example("folded_sheet_guide_param.toml");
    let plain = example("paper_dynamic_5_sheets.toml");
    let doc = |p: &std::path::Path| {
        let mut v = serde_json::to_value(flexmbd_io::read_spec(p).expect("spec")).expect("json");
        let o = v.as_object_mut().expect("object");
        o.remove("name");
        o.remove("parameters");
        v
    };
    same_numbers(&doc(&param), &doc(&plain), "spec");
    // the same frequencies
    let (_, a) = first_frequency(&param, &["--count", "10"]);
    let (_, b) = first_frequency(&plain, &["--count", "10"]);
    let freqs = |v: &Value| -> Vec<f64> {
        v["modes"]
            .as_array()
            .expect("modes")
            .iter()
            .map(|m| m["frequency_hz"].as_f64().expect("f"))
            .collect()
    };
    let (fa, fb) = (freqs(&a), freqs(&b));
    assert_eq!(fa.len(), 10);
    for (x, y) in fa.iter().zip(&fb) {
        assert!((x / y - 1.0).abs() < 1e-12, "{x} != {y}");
    }
    // the paper's 8.2 Hz and 282 Hz (paper §5; the file's header gives the comparison)
    assert!(
        (fa[0] - 8.2).abs() < 0.05 && (fa[2] - 282.0).abs() < 1.0,
        "{fa:?}"
    );
    // another member: t = 0.3 mm stiffens the intended motion as t^1.5 (the header's
    // estimate, 8.21 * 1.5^1.5 = 15.08 Hz, less the sheets' own mass)
    let (f1, _) = first_frequency(&param, &["--set", "t=0.3e-3"]);
    assert!((f1 / (fa[0] * 1.5f64.powf(1.5)) - 1.0).abs() < 0.01, "{f1}");
}
