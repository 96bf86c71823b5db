//! `flexmbd statespace` and `flexmbd sweep` through the binary: the state-space DC gain equals
//! the static compliance of `flexmbd static`, the Bode table starts at the DC gain, the sweep
//! equals `flexmbd modes --at-step` and `flexmbd static --compliance`, bad specs exit with 2.

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

fn run(args: &[&str]) -> (Output, Option<Value>) {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .output()
        .expect("run flexmbd");
    let json = serde_json::from_slice(&out.stdout).ok();
    (out, json)
}

fn ok(args: &[&str]) -> Value {
    let (out, json) = run(args);
    assert!(
        out.status.success(),
        "flexmbd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    json.expect("JSON on stdout")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmbd-statespace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Cantilever of 4 beam elements along x with a tip mass, a compressive and a lateral tip
/// load. `rotary`: steel strip with a section (rotary inertia); otherwise EA, GJ, EI, ρA given
/// directly, so the twist of every node carries no inertia and is condensed statically.
fn cantilever(rotary: bool, test: &str) -> PathBuf {
    let beam = if rotary {
        "section = \"strip\"\nmaterial = \"steel\""
    } else {
        "EA = 2.1e6\nGJ = 0.05\nEIy = 0.0175\nEIz = 1.75\nrho_a = 0.0785"
    };
    let text = format!(
        r#"
[model]
name = "cantilever"

[nodes]
g = [0.0, 0.0, 0.0]
t = [0.1, 0.0, 0.0]

[fix]
g = "all"

[[material]]
id = "steel"
E = 210e9
nu = 0.3
rho = 7850.0

[[section]]
id = "strip"
shape = "rectangle"
w = 0.01
t = 0.001

[[beam]]
id = "b"
nodes = ["g", "t"]
orient = [0.0, 1.0, 0.0]
{beam}
segments = 4

[[mass]]
node = "t"
m = 0.02

[[load]]
node = "t"
force = [-2.0, 0.0, 0.05]

[static]
steps = 3
"#
    );
    // one file per test: the tests run in parallel
    let p = tmp(&format!("cantilever_{rotary}_{test}.toml"));
    std::fs::write(&p, text).unwrap();
    p
}

const DIRS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

fn matrix(v: &Value) -> Vec<Vec<f64>> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect()
        })
        .collect()
}

/// max over entries of |a − b| / √(|b_ii b_jj|).
fn rel_err(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let mut e = 0.0f64;
    for i in 0..6 {
        for j in 0..6 {
            let s = (b[i][i].abs() * b[j][j].abs()).sqrt();
            e = e.max((a[i][j] - b[i][j]).abs() / s);
        }
    }
    e
}

fn statespace_tip(model: &str, extra: &[&str]) -> Value {
    let mut args: Vec<String> = vec!["statespace".into(), model.into(), "--json".into()];
    for d in DIRS {
        args.push("--input".into());
        args.push(format!("t:{d}"));
    }
    for d in DIRS {
        args.push("--output".into());
        args.push(format!("t:{d}:disp"));
    }
    args.extend(extra.iter().map(|s| s.to_string()));
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    ok(&refs)
}

#[test]
fn dc_gain_equals_static_compliance() {
    for rotary in [true, false] {
        let model = cantilever(rotary, "dc");
        let m = model.to_str().unwrap();
        let st = ok(&["static", m, "--compliance", "t", "--json", "--quiet"]);
        let steps = st["steps"].as_array().unwrap();
        let last = steps.len() - 1;
        let c = matrix(&steps[last]["compliance"][0]["global"]);
        // all modes, at the last step (the default) and at step 1
        let ss = statespace_tip(m, &[]);
        assert_eq!(ss["massless_directions"].as_u64().unwrap() > 0, !rotary);
        assert_eq!(ss["inputs"][3]["name"], "t:rx:moment");
        assert_eq!(ss["outputs"][1]["name"], "t:y:disp");
        let err = rel_err(&matrix(&ss["dc_gain"]), &c);
        assert!(err < 1e-6, "rotary {rotary}: {err}");
        let c1 = matrix(&steps[1]["compliance"][0]["global"]);
        let ss1 = statespace_tip(m, &["--at-step", "1"]);
        assert!(rel_err(&matrix(&ss1["dc_gain"]), &c1) < 1e-6);
        // truncated to 2 modes: exact static gain only with the static correction
        let tr = statespace_tip(m, &["--modes", "2", "--static-correction"]);
        assert_eq!(tr["A"].as_array().unwrap().len(), 4);
        assert!(rel_err(&matrix(&tr["dc_gain"]), &c) < 1e-6);
        let tr = statespace_tip(m, &["--modes", "2"]);
        assert!(rel_err(&matrix(&tr["dc_gain"]), &c) > 1e-3);
    }
}

#[test]
fn bode_table_and_matlab_file() {
    let model = cantilever(true, "bode");
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
    let ss = ok(&[&base[..], &["--json"]].concat());
    assert_eq!(ss["damping_ratio"], 0.02);
    assert_eq!(ss["inputs"][1]["name"], "t:ry:moment");
    assert_eq!(ss["outputs"][2]["unit"], "m/s²");
    let f1 = ss["frequencies_hz"][0].as_f64().unwrap();
    let dc = matrix(&ss["dc_gain"]);
    // a static force gives no velocity and no acceleration
    for j in 0..2 {
        assert!(dc[1][j].abs() < 1e-9 * dc[0][0].abs() && dc[2][j].abs() < 1e-9 * dc[0][0].abs());
    }
    let csv = tmp("bode.csv");
    let mfile = tmp("ss.m");
    let (lo, hi) = (format!("{}", 1e-5 * f1), format!("{}", 10.0 * f1));
    let (out, _) = run(&[
        &base[..],
        &[
            "--bode",
            csv.to_str().unwrap(),
            "--bode-points",
            "50",
            "--bode-min",
            &lo,
            "--bode-max",
            &hi,
            "--m",
            mfile.to_str().unwrap(),
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
    let header: Vec<&str> = lines[0].split(',').collect();
    assert_eq!(header.len(), 1 + 2 * 6);
    assert_eq!(header[1], "mag(t:z:disp/t:z:force)");
    assert_eq!(header[2], "phase_deg(t:z:disp/t:z:force)");
    // far below the first resonance: magnitude = DC gain, phase 0 (collocated force/disp)
    let row: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
    assert!((row[0] - 1e-5 * f1).abs() < 1e-9 * f1);
    assert!(
        (row[1] - dc[0][0].abs()).abs() < 1e-6 * dc[0][0].abs(),
        "{} vs {}",
        row[1],
        dc[0][0]
    );
    assert!(row[2].abs() < 1e-3, "{}", row[2]);
    // the MATLAB file
    let mtext = std::fs::read_to_string(&mfile).unwrap();
    assert!(
        mtext.contains("% inputs: 1 t:z:force [N]; 2 t:ry:moment [N·m]"),
        "{mtext}"
    );
    assert!(mtext.contains("% outputs: 1 t:z:disp [m]; 2 t:ry:vel [rad/s]; 3 t:z:acc [m/s²]"));
    assert!(mtext.contains("\nA = [\n") && mtext.contains("\nD = [\n"));
    assert!(mtext.contains("% sys = ss(A, B, C, D);"));
    // the default band: 0.1 f1 .. 10 f_max
    let (out, _) = run(&[
        &base[..],
        &["--bode", csv.to_str().unwrap(), "--bode-points", "3"],
    ]
    .concat());
    assert!(out.status.success());
    let text = std::fs::read_to_string(&csv).unwrap();
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
}

#[test]
fn sweep_equals_modes_and_static_compliance() {
    let ex = format!(
        "{}/../../examples/parallel_leaf_stroke.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let csv = tmp("sweep.csv");
    let sw = ok(&[
        "sweep",
        &ex,
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
    let steps = sw["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 5);
    let st = ok(&["static", &ex, "--steps", "4", "--json", "--quiet"]);
    let st_steps = st["steps"].as_array().unwrap();
    for k in [0usize, 4] {
        let md = ok(&[
            "modes",
            &ex,
            "--steps",
            "4",
            "--at-step",
            &k.to_string(),
            "--count",
            "5",
            "--json",
        ]);
        let f: Vec<f64> = md["modes"]
            .as_array()
            .unwrap()
            .iter()
            .map(|m| m["frequency_hz"].as_f64().unwrap())
            .collect();
        let g: Vec<f64> = steps[k]["frequencies_hz"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(f.len(), 5);
        for (a, b) in f.iter().zip(&g) {
            assert!((a - b).abs() < 1e-9 * a, "step {k}: {a} vs {b}");
        }
        // [static] compliance = ["p"] in the file: `static` reports it too
        let want = &st_steps[k]["compliance"][0];
        let got = &steps[k]["compliance"][0];
        assert_eq!(want["node"], "p");
        assert_eq!(got["node"], "p");
        for i in 0..6 {
            for key in ["stiffness_global", "stiffness_local"] {
                match (want[key][i].as_f64(), got[key][i].as_f64()) {
                    (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9 * a.abs(), "{key} {i}"),
                    (None, None) => {} // held (infinite)
                    (a, b) => panic!("step {k} {key}[{i}]: {a:?} vs {b:?}"),
                }
            }
        }
    }
    // the CSV: header and one row per step
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6);
    assert!(lines[0].starts_with("step,load_factor,f1_hz,"));
    assert!(lines[0].ends_with(",p:k_x,p:k_y,p:k_z,p:k_rx,p:k_ry,p:k_rz"));
    assert!(lines[1].contains(",inf,"), "x of p is prescribed: held");
    // the text table
    let (out, _) = run(&["sweep", &ex, "--steps", "2", "--count", "2", "--quiet"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("load factor") && text.contains("f2 [Hz]") && text.contains("p k_rz"));
}

#[test]
fn bad_specs_exit_with_2_and_name_the_argument() {
    let model = cantilever(true, "bad");
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
        let (out, _) = run(&[&["statespace", m][..], &args[..]].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(msg), "{args:?}: {err}");
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
