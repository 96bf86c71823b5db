//! `flexmbd statespace` and `flexmbd sweep` through the binary: the state-space DC gain equals
//! the static compliance of `flexmbd static`, the Bode table starts at the DC gain, the sweep
//! equals `flexmbd modes --at-step` and `flexmbd static --compliance`, bad specs exit with 2.

use serde_json::Value;
use std::path::PathBuf;

mod common;
use common::run_json as run;

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
        // the same file again: replacing it needs --force
        &[
            "--force",
            "--bode",
            csv.to_str().unwrap(),
            "--bode-points",
            "3",
        ],
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

/// Point mass 0.5 kg on a truss (k = EA/L = 2000 N/m) whose base x is an `[inputs]`
/// coordinate.
const SPRING_MASS: &str = r#"
[model]
name = "spring-mass"

[nodes]
base = [0.0, 0.0, 0.0]
m = [0.1, 0.0, 0.0]

[fix]
base = ["y", "z"]
m = ["y", "z"]

[inputs]
base = "x"

[[truss]]
id = "t"
nodes = ["base", "m"]
EA = 200.0

[[mass]]
node = "m"
m = 0.5
"#;

/// `NODE:DIR:motion` through the binary: labels and units in JSON, .m and Bode; the Bode of
/// the mass displacement per base acceleration times (2πf)² is the base-excitation
/// transmissibility X/U = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²) (modal damping on the spring's
/// deformation, ωₙ² = k/m = 4000 s⁻²); the quasi-static column is 1 (the mass follows a slow base).
#[test]
fn motion_input_spring_mass_closed_form() {
    let p = tmp("spring_mass_motion.toml");
    std::fs::write(&p, SPRING_MASS).unwrap();
    let model = p.to_str().unwrap();
    let bode = tmp("spring_mass_motion.csv");
    let mfile = tmp("spring_mass_motion.m");
    let zeta = 0.05;
    let j = ok(&[
        "statespace",
        model,
        "--input",
        "m:x",
        "--input",
        "base:x:motion",
        "--output",
        "m:x",
        "--output",
        "m:x:acc",
        "--damping",
        "0.05",
        "--json",
        "--bode",
        bode.to_str().unwrap(),
        "--bode-points",
        "7",
        "--m",
        mfile.to_str().unwrap(),
    ]);
    let inp = &j["inputs"][1];
    assert_eq!(inp["name"], "base:x:motion");
    assert_eq!(inp["kind"], "motion");
    assert_eq!(inp["unit"], "m/s²");
    let states: Vec<&str> = j["states"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(states, ["eta_1", "deta_1", "u_2", "du_2"]);
    let dc = matrix(&j["dc_gain"]);
    // force column: compliance 1/k; motion column: quasi-static gain 1 (disp), 0 (acc)
    assert!((dc[0][0] - 1.0 / 2000.0).abs() < 1e-12);
    assert!((dc[0][1] - 1.0).abs() < 1e-12);
    assert!(dc[1][1].abs() < 1e-12);
    let m = std::fs::read_to_string(&mfile).unwrap();
    assert!(m.contains("'base:x:motion'") && m.contains("base:x:motion [m/s²]"));
    let csv = std::fs::read_to_string(&bode).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "mag(m:x:disp/base:x:motion)")
        .expect("motion column");
    let wn2: f64 = 4000.0;
    let wn = wn2.sqrt();
    let mut rows = 0;
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        let w = 2.0 * std::f64::consts::PI * v[0];
        // |X/U| = |ωₙ² + 2iζωₙω| / |ωₙ² − ω² + 2iζωₙω|
        let num = (wn2 * wn2 + (2.0 * zeta * wn * w).powi(2)).sqrt();
        let den = ((wn2 - w * w).powi(2) + (2.0 * zeta * wn * w).powi(2)).sqrt();
        let xu = v[col] * w * w;
        assert!(
            (xu - num / den).abs() < 1e-9 * num / den,
            "{}: {xu} vs {}",
            v[0],
            num / den
        );
        rows += 1;
    }
    assert_eq!(rows, 7);
}

/// Clamped–guided beam under tension whose guided end `e` moves in y: the quasi-static gain of
/// the state-space model equals the response of `flexmbd static` to a small `[[prescribe]]`
/// stroke of e.y (central difference of two static runs, same tension); and a motion input on a
/// free coordinate is refused with exit code 2.
#[test]
fn motion_input_static_gain_equals_prescribed_statics() {
    let model_text = |prescribe: &str| {
        format!(
            r#"
[model]
name = "clamped-guided"

[nodes]
a = {{ x = [0.0, 0.0, 0.0], rot = true }}
e = {{ x = [0.2, 0.0, 0.0], rot = true }}

[fix]
a = "all"
e = ["z", "rx", "ry", "rz"]

{prescribe}

[[beam]]
id = "b"
nodes = ["a", "e"]
orient = [0.0, 1.0, 0.0]
EA = 2e5
GJ = 0.7
EIy = 1.0
EIz = 3.0
rho_a = 0.1
segments = 4

[[load]]
node = "e"
force = [30.0, 0.0, 0.0]

[static]
steps = 2
"#
        )
    };
    let h = 1e-5;
    let ss_model = tmp("guided_motion.toml");
    std::fs::write(&ss_model, model_text("[inputs]\ne = \"y\"")).unwrap();
    let nodes = ["b:1", "b:2", "b:3", "e"];
    let mut args: Vec<String> = vec![
        "statespace".into(),
        ss_model.to_str().unwrap().into(),
        "--json".into(),
        "--input".into(),
        "e:y:motion".into(),
    ];
    for n in nodes {
        for d in ["x", "y"] {
            args.push("--output".into());
            args.push(format!("{n}:{d}"));
        }
    }
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let j = ok(&refs);
    let dc = matrix(&j["dc_gain"]);
    let stat = |v: f64, name: &str| {
        let p = tmp(name);
        let pre = format!("[[prescribe]]\nnode = \"e\"\ndof = \"y\"\nvalue = {v:e}");
        std::fs::write(&p, model_text(&pre)).unwrap();
        let s = ok(&["static", p.to_str().unwrap(), "--json"]);
        let last = s["steps"].as_array().unwrap().last().unwrap().clone();
        last["nodes"].as_array().unwrap().clone()
    };
    let plus = stat(h, "guided_plus.toml");
    let minus = stat(-h, "guided_minus.toml");
    let pos = |list: &[Value], n: &str, k: usize| {
        let node = list.iter().find(|x| x["node"] == n).expect("node");
        node["position"][k].as_f64().unwrap()
    };
    let mut fd = Vec::new();
    for n in nodes {
        for k in 0..2 {
            fd.push((pos(&plus, n, k) - pos(&minus, n, k)) / (2.0 * h));
        }
    }
    let scale = fd.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    for (o, v) in fd.iter().enumerate() {
        assert!(
            (dc[o][0] - v).abs() < 1e-6 * scale,
            "output {o}: {} vs {v}",
            dc[o][0]
        );
    }
    assert!((dc[7][0] - 1.0).abs() < 1e-12);
    // a motion on a free coordinate is an input error
    let (out, _) = run(&[
        "statespace",
        ss_model.to_str().unwrap(),
        "--input",
        "b:2:y:motion",
        "--output",
        "e:y",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("b:2:y:motion") && err.contains("free"),
        "{err}"
    );
}

/// `NODE:rz:motion` through the binary: a cantilever (L = 0.2 m, no load) whose clamp rotation
/// about z is an input. Labels and the unit rad/s² in JSON and .m; the quasi-static column is
/// the rigid rotation of the whole beam (tip y = L per radian, tip and clamp rotation 1, tip
/// x 0), and the DC gain of the tip rotation per tip moment is the compliance L/EI = 0.1.
#[test]
fn rotation_motion_input_of_clamp_is_rigid_rotation() {
    let p = tmp("rotated_clamp.toml");
    std::fs::write(
        &p,
        r#"
[model]
name = "rotated-clamp"

[nodes]
a = { x = [0.0, 0.0, 0.0], rot = true }
t = [0.2, 0.0, 0.0]

[fix]
a = ["x", "y", "z", "rx", "ry"]

[inputs]
a = "rz"

[[beam]]
id = "b"
nodes = ["a", "t"]
orient = [0.0, 0.0, 1.0]
EA = 2e5
GJ = 0.7
EIy = 2.0
EIz = 2.0
rho_a = 0.1
segments = 4
"#,
    )
    .unwrap();
    let mfile = tmp("rotated_clamp.m");
    let j = ok(&[
        "statespace",
        p.to_str().unwrap(),
        "--input",
        "t:rz",
        "--input",
        "a:rz:motion",
        "--output",
        "t:y",
        "--output",
        "t:rz",
        "--output",
        "t:x",
        "--output",
        "a:rz",
        "--json",
        "--m",
        mfile.to_str().unwrap(),
    ]);
    let inp = &j["inputs"][1];
    assert_eq!(inp["name"], "a:rz:motion");
    assert_eq!(inp["kind"], "motion");
    assert_eq!(inp["unit"], "rad/s²");
    let m = std::fs::read_to_string(&mfile).unwrap();
    assert!(m.contains("'a:rz:motion'") && m.contains("a:rz:motion [rad/s²]"));
    let dc = matrix(&j["dc_gain"]);
    for (o, e) in [0.2, 1.0, 0.0, 1.0].iter().enumerate() {
        assert!(
            (dc[o][1] - e).abs() < 1e-9,
            "output {o}: {} vs {e}",
            dc[o][1]
        );
    }
    // the moment column: tip rotation per tip moment L/EI = 0.1 rad/(N·m)
    assert!((dc[1][0] - 0.1).abs() < 1e-9, "{}", dc[1][0]);
    // a free rotation (the beam's tip) cannot be moved: exit 2, pointing to a moment input
    let (out, _) = run(&[
        "statespace",
        p.to_str().unwrap(),
        "--input",
        "t:rz:motion",
        "--output",
        "t:y",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("t:rz:motion") && err.contains("free") && err.contains("t:rz:moment"),
        "{err}"
    );
}

const ACTUATOR_SPRING_MASS: &str = r#"
[model]
name = "actuator-spring-mass"

[nodes]
g = [0.0, 0.0, 0.0]
a = [0.05, 0.0, 0.0]
m = [0.15, 0.0, 0.0]

[fix]
g = "all"
a = ["y", "z"]
m = ["y", "z"]

[[truss]]
id = "act"
nodes = ["g", "a"]
input = [1]

[[truss]]
id = "spring"
nodes = ["a", "m"]
free = [1]
EA = 200.0

[[mass]]
node = "a"
m = 0.3

[[mass]]
node = "m"
m = 0.5
"#;

/// `ELEMENT:MODE:motion` through the binary: a linear actuator (truss elongation, an input
/// mode) drives a spring–mass. The actuator end follows the stroke exactly (quasi-static gain
/// 1), the mass sees the base-excitation transmissibility |X/E| = |ωₙ² + 2iζωₙω| /
/// |ωₙ² − ω² + 2iζωₙω| with ωₙ² = k/m = 2000/0.5 = 4000 s⁻²; labels name the element and mode.
/// A flexible mode, an unknown element and a mode out of range are input errors (exit 2).
#[test]
fn deformation_motion_input_actuator_closed_form() {
    let p = tmp("actuator_motion.toml");
    std::fs::write(&p, ACTUATOR_SPRING_MASS).unwrap();
    let model = p.to_str().unwrap();
    let bode = tmp("actuator_motion.csv");
    let zeta = 0.02;
    let j = ok(&[
        "statespace",
        model,
        "--input",
        "act:1:motion",
        "--output",
        "m:x",
        "--output",
        "a:x",
        "--damping",
        "0.02",
        "--json",
        "--bode",
        bode.to_str().unwrap(),
        "--bode-points",
        "9",
    ]);
    let inp = &j["inputs"][0];
    assert_eq!(inp["name"], "act:1:motion");
    assert_eq!(inp["kind"], "motion");
    assert_eq!(inp["unit"], "m/s²");
    assert_eq!(inp["element"], "act");
    assert_eq!(inp["mode"], 1);
    assert_eq!(inp["mode_name"], "elongation");
    let dc = matrix(&j["dc_gain"]);
    assert!((dc[0][0] - 1.0).abs() < 1e-12 && (dc[1][0] - 1.0).abs() < 1e-12);
    let csv = std::fs::read_to_string(&bode).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "mag(m:x:disp/act:1:motion)")
        .expect("motion column");
    let (wn2, mut rows) = (4000.0f64, 0);
    let wn = wn2.sqrt();
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        let w = 2.0 * std::f64::consts::PI * v[0];
        let num = (wn2 * wn2 + (2.0 * zeta * wn * w).powi(2)).sqrt();
        let den = ((wn2 - w * w).powi(2) + (2.0 * zeta * wn * w).powi(2)).sqrt();
        let xe = v[col] * w * w;
        assert!((xe - num / den).abs() < 1e-9 * num / den, "{}: {xe}", v[0]);
        rows += 1;
    }
    assert_eq!(rows, 9);
    for (spec, words) in [
        ("spring:1:motion", vec!["spring", "free", "input"]),
        ("nope:1:motion", vec!["nope", "not defined"]),
        ("act:2:motion", vec!["act", "1 to 1"]),
    ] {
        let (out, _) = run(&["statespace", model, "--input", spec, "--output", "m:x"]);
        assert_eq!(out.status.code(), Some(2), "{spec}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(spec), "{err}");
        for w in words {
            assert!(err.contains(w), "{spec}: {err}");
        }
    }
}

/// A model above the dense limit through the binary: the F01 strip (L = 0.1 m, b = 20 mm,
/// t = 0.5 mm, E = 200 GPa) in 600 elements (3600 degrees of freedom) takes the sparse path.
/// Without --modes it is refused with advice; a motion of the clamp moves the tip one to one;
/// with --modes 4 --static-correction the static
/// gain of the tip under a tip force along z is the Euler–Bernoulli L³/(3 E I), I = b t³/12,
/// and the first frequency the clamped–free 40.899 Hz (examples/strip_f01.toml).
#[test]
fn large_model_state_space_takes_the_sparse_path() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/strip_f01.toml"
    ))
    .unwrap()
    .replace("segments = 10", "segments = 600");
    let p = tmp("strip_600.toml");
    std::fs::write(&p, text).unwrap();
    let model = p.to_str().unwrap();
    let (out, _) = run(&["statespace", model, "--input", "tip:z", "--output", "tip:z"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--modes") && err.contains("3600"), "{err}");
    // a motion of the clamp moves the unloaded strip rigidly: the tip follows one to one
    let j = ok(&[
        "statespace",
        model,
        "--input",
        "root:z:motion",
        "--output",
        "tip:z",
        "--modes",
        "4",
        "--static-correction",
        "--json",
    ]);
    assert_eq!(j["solver"], "sparse");
    let g = matrix(&j["dc_gain"]);
    assert!((g[0][0] - 1.0).abs() < 1e-9, "{}", g[0][0]);
    let j = ok(&[
        "statespace",
        model,
        "--input",
        "tip:z",
        "--output",
        "tip:z",
        "--modes",
        "4",
        "--static-correction",
        "--json",
    ]);
    assert_eq!(j["solver"], "sparse");
    let (l, b, t, e): (f64, f64, f64, f64) = (0.1, 0.02, 0.0005, 200e9);
    let exact = l.powi(3) / (3.0 * e * b * t.powi(3) / 12.0);
    let dc = matrix(&j["dc_gain"]);
    assert!(
        (dc[0][0] - exact).abs() < 1e-9 * exact,
        "{} vs {exact}",
        dc[0][0]
    );
    let f1 = j["frequencies_hz"][0].as_f64().unwrap();
    assert!((f1 - 40.899).abs() < 1e-3 * 40.899, "{f1}");
}

/// Element outputs through the binary on the actuator–spring–mass: with the actuator held, a
/// force F on the mass is carried by the spring and by the actuator (σ/F = 1 at DC, spring
/// deformation F/k = F/2000); a slow actuator stroke moves the spring rigidly (σ = 0); the JSON
/// names element, mode and quantity. A force output on a free mode
/// without stiffness, an unknown element and a mode out of range are input errors (exit 2).
#[test]
fn element_outputs_through_the_binary() {
    let p = tmp("actuator_outputs.toml");
    std::fs::write(&p, ACTUATOR_SPRING_MASS).unwrap();
    let model = p.to_str().unwrap();
    let j = ok(&[
        "statespace",
        model,
        "--input",
        "m:x",
        "--input",
        "act:1:motion",
        "--output",
        "spring:1:force",
        "--output",
        "spring:1:def",
        "--output",
        "spring:1:def:vel",
        "--output",
        "act:1:force",
        "--output",
        "g:x:reaction",
        "--json",
    ]);
    let o = &j["outputs"][0];
    assert_eq!(o["name"], "spring:1:force");
    assert_eq!(o["unit"], "N");
    assert_eq!(o["element"], "spring");
    assert_eq!(o["quantity"], "force");
    assert_eq!(j["outputs"][2]["unit"], "m/s");
    let dc = matrix(&j["dc_gain"]);
    assert!((dc[0][0] - 1.0).abs() < 1e-12, "{:?}", dc);
    assert!((dc[1][0] - 1.0 / 2000.0).abs() < 1e-15, "{:?}", dc);
    assert!(dc[0][1].abs() < 1e-12 && dc[1][1].abs() < 1e-15, "{:?}", dc);
    // the actuator's reaction carries the load too, and nothing under a slow stroke
    assert!(
        (dc[3][0] - 1.0).abs() < 1e-9 && dc[3][1].abs() < 1e-9,
        "{:?}",
        dc
    );
    // the support at g holds the load: −F (the force it exerts, as `flexmbd static` reports)
    assert_eq!(j["outputs"][4]["quantity"], "reaction");
    assert!((dc[4][0] + 1.0).abs() < 1e-9, "{:?}", dc);
    let free_spring = ACTUATOR_SPRING_MASS.replace("EA = 200.0\n", "");
    let p0 = tmp("actuator_outputs_no_k.toml");
    std::fs::write(&p0, free_spring).unwrap();
    let (out, _) = run(&[
        "statespace",
        p0.to_str().unwrap(),
        "--input",
        "m:x",
        "--output",
        "spring:1:force",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no stiffness") && err.contains("spring:1:def"),
        "{err}"
    );
    for (spec, words) in [
        ("nope:1:force", vec!["nope", "not defined"]),
        ("spring:2:def", vec!["spring", "1 to 1"]),
        ("m:x:reaction", vec!["free", "reaction"]),
    ] {
        let (out, _) = run(&["statespace", model, "--input", "m:x", "--output", spec]);
        assert_eq!(out.status.code(), Some(2), "{spec}");
        let err = String::from_utf8_lossy(&out.stderr);
        for w in words {
            assert!(err.contains(spec) && err.contains(w), "{spec}: {err}");
        }
    }
}
