//! `flexmbd statespace` and `flexmbd sweep` through the binary: the command-line concerns. One
//! run of each writes every output (JSON, the MATLAB file, the Bode table over the default and
//! a given band; sweep JSON, CSV and text), an existing output is replaced with `--force`, and
//! bad specs and models exit with 2 naming the argument. The numbers (the DC gain against the
//! static compliance, the Bode table, the sweep against modes and statics, motion inputs and
//! element outputs against closed forms, the large model's sparse path) are checked in process
//! in `crates/flexmbd-io/tests/statespace_files.rs`, on the same models
//! (`tests/models/*.toml`).

use serde_json::Value;
use std::path::PathBuf;

mod common;
use common::{example, run_json as run, Temp};

fn ok(args: &[&str]) -> Value {
    let (out, json) = run(args);
    assert!(
        out.status.success(),
        "flexmbd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    json.expect("JSON on stdout")
}

/// A test model, `tests/models/NAME` (shared with the io tests).
fn model(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/models")
        .join(name)
}

/// `flexmbd statespace … ARGS` exits with 2 and names `words` on stderr.
fn refused(args: &[&str], words: &[&str]) {
    let (out, _) = run(&[&["statespace"][..], args].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    for w in words {
        assert!(err.contains(w), "{args:?}: {err}");
    }
}

#[test]
fn bode_table_and_matlab_file() {
    let t = Temp::new("statespace_bode");
    let model = model("cantilever_strip.toml");
    let m = model.to_str().unwrap();
    let base = [
        "statespace",
        m,
        "--input",
        "t:z",
        "--input",
        "t:y:moment",
        "--output",
        "t:z",
        "--output",
        "t:ry:vel",
        "--output",
        "t:z:acc",
        "--damping",
        "0.02",
    ];
    let (csv, mfile) = (t.path("bode.csv"), t.path("ss.m"));
    // JSON on stdout, the MATLAB file and the Bode table over the default band: 0.1 f1 .. 10 f_max;
    // the step and the modes asked for
    let ss = ok(&[
        &base[..],
        &[
            "--at-step",
            "1",
            "--modes",
            "2",
            "--static-correction",
            "--json",
            "--m",
            mfile.to_str().unwrap(),
            "--bode",
            csv.to_str().unwrap(),
            "--bode-points",
            "3",
        ],
    ]
    .concat());
    for key in ["A", "B", "C", "D", "dc_gain"] {
        assert!(ss[key].is_array(), "{key}");
    }
    assert_eq!(ss["step"], 1);
    assert_eq!(ss["A"].as_array().unwrap().len(), 4);
    assert_eq!(ss["static_correction"], true);
    let f1 = ss["frequencies_hz"][0].as_f64().unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 4);
    let first: f64 = text
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((first - 0.1 * f1).abs() < 1e-9 * f1);
    let mtext = std::fs::read_to_string(&mfile).unwrap();
    assert!(mtext.contains("\nA = [\n") && mtext.contains("\nD = [\n"));
    // the same file again, over a given band: replacing it needs --force
    let (lo, hi) = (format!("{}", 1e-5 * f1), format!("{}", 10.0 * f1));
    let (out, _) = run(&[
        &base[..],
        &[
            "--force",
            "--bode",
            csv.to_str().unwrap(),
            "--bode-points",
            "50",
            "--bode-min",
            &lo,
            "--bode-max",
            &hi,
        ],
    ]
    .concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 51);
    assert_eq!(lines[0].split(',').count(), 1 + 2 * 6);
    let row: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
    assert!((row[0] - 1e-5 * f1).abs() < 1e-9 * f1);
}

#[test]
fn sweep_writes_json_csv_and_text() {
    let t = Temp::new("statespace_sweep");
    let ex = example("parallel_leaf_stroke.toml");
    let ex = ex.to_str().unwrap();
    let csv = t.path("sweep.csv");
    let sw = ok(&[
        "sweep",
        ex,
        "--steps",
        "4",
        "--count",
        "5",
        "--compliance",
        "p",
        "--json",
        "--quiet",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(sw["steps"].as_array().unwrap().len(), 5);
    // the CSV: header and one row per step
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6);
    assert!(lines[0].starts_with("step,load_factor,f1_hz,"));
    assert!(lines[0].ends_with(",p:k_x,p:k_y,p:k_z,p:k_rx,p:k_ry,p:k_rz"));
    assert!(lines[1].contains(",inf,"), "x of p is prescribed: held");
    // the text table
    let (out, _) = run(&["sweep", ex, "--steps", "2", "--count", "2", "--quiet"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("load factor") && text.contains("f2 [Hz]") && text.contains("p k_rz"));
}

#[test]
fn bad_specs_exit_with_2_and_name_the_argument() {
    let model = model("cantilever_strip.toml");
    let m = model.to_str().unwrap();
    for (args, msg) in [
        (
            vec!["--input", "t:w", "--output", "t:y"],
            "--input `t:w`: unknown direction `w`",
        ),
        (
            vec!["--input", "q:y", "--output", "t:y"],
            "--input `q:y`: node `q` is not defined",
        ),
        (
            vec!["--input", "t:y:torque", "--output", "t:y"],
            "unknown input kind `torque`",
        ),
        (
            vec!["--input", "t:rx:force", "--output", "t:y"],
            "a force acts along x, y or z",
        ),
        (
            vec!["--input", "t:y", "--output", "t:y:jerk"],
            "--output `t:y:jerk`: unknown output kind",
        ),
        (
            vec!["--input", "t", "--output", "t:y"],
            "--input `t`: expected NODE:DIR",
        ),
        (
            vec!["--input", "t:y", "--output", "t:y", "--damping", "-1"],
            "--damping must be",
        ),
        (
            vec!["--input", "t:y", "--output", "t:y", "--modes", "0"],
            "--modes must be at least 1",
        ),
        (
            vec!["--input", "t:y", "--output", "t:y", "--at-step", "9"],
            "--at-step 9",
        ),
    ] {
        refused(&[&[m][..], &args[..]].concat(), &[msg]);
    }
    let (out, _) = run(&["sweep", m, "--compliance", "nope"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--compliance: node `nope`"));
    // a node whose name contains ':' (segment nodes b:1 … b:3)
    let ss = ok(&[
        "statespace",
        m,
        "--input",
        "b:2:x:moment",
        "--output",
        "b:2:rx",
        "--json",
    ]);
    assert_eq!(ss["inputs"][0]["name"], "b:2:rx:moment");
    assert_eq!(ss["outputs"][0]["name"], "b:2:rx:disp");
}

/// Motion inputs that cannot be: a motion on a free coordinate (a free translation; a free
/// rotation, pointing to a moment input), a flexible mode, an unknown element, a mode out of
/// range: input errors (exit 2) that name the spec.
#[test]
fn bad_motion_inputs_exit_with_2() {
    let guided = model("clamped_guided.toml");
    let guided = guided.to_str().unwrap();
    refused(
        &[guided, "--input", "b:2:y:motion", "--output", "e:y"],
        &["b:2:y:motion", "free"],
    );
    let clamp = model("rotated_clamp.toml");
    let clamp = clamp.to_str().unwrap();
    refused(
        &[clamp, "--input", "t:rz:motion", "--output", "t:y"],
        &["t:rz:motion", "free", "t:rz:moment"],
    );
    let act = model("actuator_spring_mass.toml");
    let act = act.to_str().unwrap();
    for (spec, words) in [
        ("spring:1:motion", vec!["spring", "free", "input"]),
        ("nope:1:motion", vec!["nope", "not defined"]),
        ("act:2:motion", vec!["act", "1 to 1"]),
    ] {
        refused(
            &[act, "--input", spec, "--output", "m:x"],
            &[&[spec][..], &words[..]].concat(),
        );
    }
}

/// Element outputs that cannot be: a force output on a free mode without stiffness, an unknown
/// element, a mode out of range, a reaction on a free coordinate: input errors (exit 2) that
/// name the spec.
#[test]
fn bad_element_outputs_exit_with_2() {
    let t = Temp::new("statespace_outputs");
    let act = model("actuator_spring_mass.toml");
    let text = std::fs::read_to_string(&act).unwrap();
    let free_spring = text.replace("EA = 200.0\n", "");
    assert_ne!(free_spring, text);
    let p0 = t.write("actuator_outputs_no_k.toml", free_spring.as_bytes());
    refused(
        &[
            p0.to_str().unwrap(),
            "--input",
            "m:x",
            "--output",
            "spring:1:force",
        ],
        &["no stiffness", "spring:1:def"],
    );
    for (spec, words) in [
        ("nope:1:force", vec!["nope", "not defined"]),
        ("spring:2:def", vec!["spring", "1 to 1"]),
        ("m:x:reaction", vec!["free", "reaction"]),
    ] {
        refused(
            &[act.to_str().unwrap(), "--input", "m:x", "--output", spec],
            &[&[spec][..], &words[..]].concat(),
        );
    }
}

/// A model above the dense limit (the F01 strip in 600 elements, 3600 degrees of freedom) takes
/// the sparse path, which keeps the lowest modes only: without --modes it is refused with
/// advice (exit 2), before the static solve.
#[test]
fn a_large_model_needs_modes() {
    let t = Temp::new("statespace_large");
    let text = std::fs::read_to_string(example("strip_f01.toml"))
        .unwrap()
        .replace("segments = 10", "segments = 600");
    let p = t.write("strip_600.toml", text.as_bytes());
    refused(
        &[p.to_str().unwrap(), "--input", "tip:z", "--output", "tip:z"],
        &["--modes", "3600"],
    );
}
