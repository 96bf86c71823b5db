//! The state-space models and the sweep of model files at the io level (docs/state-space.md):
//! the file read with `flexmbd_io`, the `--input`/`--output` specs parsed by its request parser,
//! the core's state space and sweep, and the documents of the io writers (the `statespace --json`
//! document, the MATLAB file, the Bode table, the sweep JSON), as `flexmbd statespace` and
//! `flexmbd sweep` make them; formerly run through the binary. The DC gain equals the static
//! compliance, the Bode table starts at the DC gain, the sweep equals the modes and the static
//! compliance, and motion inputs and element outputs against closed forms. The command line's
//! own concerns (arguments, exit codes, that every output is written) are tested in
//! `crates/flexmbd-cli/tests/statespace.rs`.
//!
//! The models are the command-line test models (`crates/flexmbd-cli/tests/models`), shared with
//! those tests, and the shipped examples.

use flexmbd_core::dynamics::state_space::{log_space, StateSpace, StateSpaceOptions};
use flexmbd_core::dynamics::sweep::sweep_with;
use flexmbd_core::dynamics::{modes_with, ModalOptions};
use flexmbd_io::statespace_report::{bode_csv, statespace_m, sweep_json, Origin};
use flexmbd_io::ModelFile;
use serde_json::Value;

mod common;
use common::{cli_model, example, statespace_doc, static_path};

/// A model file from its text (the test fails on an input error).
fn parse(text: &str, file: &str) -> ModelFile {
    flexmbd_io::parse_model_file(text, file).unwrap_or_else(|e| panic!("{e}"))
}

/// A JSON matrix (an array of rows) as rows of numbers.
fn matrix(v: &Value) -> Vec<Vec<f64>> {
    v.as_array()
        .expect("rows")
        .iter()
        .map(|r| {
            r.as_array()
                .expect("row")
                .iter()
                .map(|x| x.as_f64().expect("number"))
                .collect()
        })
        .collect()
}

/// One of the command-line test models, `crates/flexmbd-cli/tests/models/NAME`.
fn shared(name: &str) -> ModelFile {
    common::read(&cli_model(name))
}

/// The state space and the `statespace --json` document at the last step of the model's static
/// path, with the options `opts`.
fn last_step(
    f: &ModelFile,
    inputs: &[&str],
    outputs: &[&str],
    opts: &StateSpaceOptions,
) -> (StateSpace, Value) {
    let sol = static_path(f).unwrap_or_else(|s| panic!("{}", s.error));
    statespace_doc(
        f,
        "model.toml",
        &sol,
        sol.steps.len() - 1,
        inputs,
        outputs,
        opts,
    )
}

/// The `statespace --bode FILE --bode-points N` table over the command's default band (0.1 ×
/// the first to 10 × the highest kept frequency).
fn bode_default(f: &ModelFile, ss: &StateSpace, points: usize) -> String {
    let band = ss.default_band(2).expect("a positive frequency");
    bode_csv(&f.model, ss, &log_space(band[0], band[1], points), None)
}

/// The `statespace --m FILE` script of `ss`, whose `statespace --json` document is `doc`.
fn m_file(f: &ModelFile, ss: &StateSpace, doc: &Value) -> String {
    let origin = Origin {
        file: "model.toml",
        step: doc["step"].as_u64().expect("step") as usize,
        load_factor: doc["load_factor"].as_f64().expect("load factor"),
        stopped: None,
    };
    statespace_m(&f.model, origin, ss)
}

/// Cantilever of 4 beam elements along x with a tip mass, a compressive and a lateral tip
/// load (`cantilever_strip.toml`). `rotary`: steel strip with a section (rotary inertia);
/// otherwise EA, GJ, EI, ρA given directly, so the twist of every node carries no inertia and
/// is condensed statically.
fn cantilever(rotary: bool) -> ModelFile {
    let text = std::fs::read_to_string(cli_model("cantilever_strip.toml")).unwrap();
    if rotary {
        return parse(&text, "cantilever.toml");
    }
    let given = text.replace(
        "section = \"strip\"\nmaterial = \"steel\"",
        "EA = 2.1e6\nGJ = 0.05\nEIy = 0.0175\nEIz = 1.75\nrho_a = 0.0785",
    );
    assert_ne!(given, text);
    parse(&given, "cantilever.toml")
}

const DIRS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

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

#[test]
fn dc_gain_equals_static_compliance() {
    let inputs: Vec<String> = DIRS.iter().map(|d| format!("t:{d}")).collect();
    let outputs: Vec<String> = DIRS.iter().map(|d| format!("t:{d}:disp")).collect();
    let inputs: Vec<&str> = inputs.iter().map(String::as_str).collect();
    let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    for rotary in [true, false] {
        let mut f = cantilever(rotary);
        let sol = static_path(&f).unwrap_or_else(|s| panic!("{}", s.error));
        let tip = |k: usize, opts: &StateSpaceOptions| {
            statespace_doc(&f, "cantilever.toml", &sol, k, &inputs, &outputs, opts).1
        };
        // all modes, at the last step (the default) and at step 1
        let all = StateSpaceOptions::default();
        let last = sol.steps.len() - 1;
        let ss = tip(last, &all);
        let ss1 = tip(1, &all);
        // truncated to 2 modes: exact static gain only with the static correction
        let two = StateSpaceOptions {
            modes: Some(2),
            ..Default::default()
        };
        let tr_corrected = tip(
            last,
            &StateSpaceOptions {
                static_correction: true,
                ..two
            },
        );
        let tr = tip(last, &two);
        // `static --compliance t`
        f.settings.compliance.push("t".into());
        let st = common::static_doc(&f, "cantilever.toml", None);
        let steps = st["steps"].as_array().unwrap();
        assert_eq!(steps.len() - 1, last);
        let c = matrix(&steps[last]["compliance"][0]["global"]);
        assert_eq!(ss["massless_directions"].as_u64().unwrap() > 0, !rotary);
        assert_eq!(ss["inputs"][3]["name"], "t:rx:moment");
        assert_eq!(ss["outputs"][1]["name"], "t:y:disp");
        let err = rel_err(&matrix(&ss["dc_gain"]), &c);
        assert!(err < 1e-6, "rotary {rotary}: {err}");
        let c1 = matrix(&steps[1]["compliance"][0]["global"]);
        assert!(rel_err(&matrix(&ss1["dc_gain"]), &c1) < 1e-6);
        assert_eq!(tr_corrected["A"].as_array().unwrap().len(), 4);
        assert!(rel_err(&matrix(&tr_corrected["dc_gain"]), &c) < 1e-6);
        assert!(rel_err(&matrix(&tr["dc_gain"]), &c) > 1e-3);
    }
}

#[test]
fn bode_table_and_matlab_file() {
    let f = cantilever(true);
    let opts = StateSpaceOptions {
        damping: 0.02,
        ..Default::default()
    };
    let (ss, doc) = last_step(
        &f,
        &["t:z", "t:y:moment"],
        &["t:z", "t:ry:vel", "t:z:acc"],
        &opts,
    );
    assert_eq!(doc["damping_ratio"], 0.02);
    assert_eq!(doc["inputs"][1]["name"], "t:ry:moment");
    assert_eq!(doc["outputs"][2]["unit"], "m/s²");
    let f1 = doc["frequencies_hz"][0].as_f64().unwrap();
    let dc = matrix(&doc["dc_gain"]);
    // a static force gives no velocity and no acceleration
    for j in 0..2 {
        assert!(dc[1][j].abs() < 1e-9 * dc[0][0].abs() && dc[2][j].abs() < 1e-9 * dc[0][0].abs());
    }
    // `--bode FILE --bode-points 50 --bode-min 1e-5 f1 --bode-max 10 f1`
    let text = bode_csv(&f.model, &ss, &log_space(1e-5 * f1, 10.0 * f1, 50), None);
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
    let mtext = m_file(&f, &ss, &doc);
    assert!(
        mtext.contains("% inputs: 1 t:z:force [N]; 2 t:ry:moment [N·m]"),
        "{mtext}"
    );
    assert!(mtext.contains("% outputs: 1 t:z:disp [m]; 2 t:ry:vel [rad/s]; 3 t:z:acc [m/s²]"));
    assert!(mtext.contains("\nA = [\n") && mtext.contains("\nD = [\n"));
    assert!(mtext.contains("% sys = ss(A, B, C, D);"));
}

#[test]
fn sweep_equals_modes_and_static_compliance() {
    // `--steps 4` over the file's [static] steps; [static] compliance = ["p"] in the file
    let mut f = common::read(&example("parallel_leaf_stroke.toml"));
    f.settings.steps = Some(4);
    let sol = static_path(&f).unwrap_or_else(|s| panic!("{}", s.error));
    let p = f.model.node_id("p").expect("node p");
    let points = sweep_with(&f.model, &sol.steps, 5, &[p], &ModalOptions::default());
    let sw = sweep_json(&f.model, "stroke.toml", &points, &["p".to_string()], None);
    let steps = sw["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 5);
    let st = common::static_doc(&f, "stroke.toml", None);
    let st_steps = st["steps"].as_array().unwrap();
    for k in [0usize, 4] {
        let modal = modes_with(&f.model, &sol.steps[k], 5, &ModalOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let md = flexmbd_io::modes_report::modes_json(
            &f.model,
            "stroke.toml",
            sol.steps[k].load_factor,
            &modal,
            None,
        );
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

/// |X/U| = |ωₙ² + 2iζωₙω| / |ωₙ² − ω² + 2iζωₙω| of every row of a Bode table in column `col`,
/// times ω²: the base-excitation transmissibility from the displacement per base acceleration,
/// with ωₙ² = 4000 s⁻² (both spring–mass models: k/m = 2000/0.5); the number of rows.
fn transmissibility_rows(csv: &str, col: &str, zeta: f64) -> usize {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == col)
        .expect("motion column");
    let (wn2, mut rows) = (4000.0f64, 0);
    let wn = wn2.sqrt();
    for l in lines {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        let w = 2.0 * std::f64::consts::PI * v[0];
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
    rows
}

/// `NODE:DIR:motion`: labels and units in JSON, .m and Bode; the Bode of the mass displacement
/// per base acceleration times (2πf)² is the base-excitation transmissibility
/// X/U = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²) (modal damping on the spring's deformation,
/// ωₙ² = k/m = 4000 s⁻²); the quasi-static column is 1 (the mass follows a slow base).
#[test]
fn motion_input_spring_mass_closed_form() {
    let f = parse(SPRING_MASS, "spring_mass.toml");
    let zeta = 0.05;
    let opts = StateSpaceOptions {
        damping: zeta,
        ..Default::default()
    };
    let (ss, j) = last_step(&f, &["m:x", "base:x:motion"], &["m:x", "m:x:acc"], &opts);
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
    let m = m_file(&f, &ss, &j);
    assert!(m.contains("'base:x:motion'") && m.contains("base:x:motion [m/s²]"));
    let csv = bode_default(&f, &ss, 7);
    let rows = transmissibility_rows(&csv, "mag(m:x:disp/base:x:motion)", zeta);
    assert_eq!(rows, 7);
}

/// Clamped–guided beam under tension whose guided end `e` moves in y (`clamped_guided.toml`):
/// the quasi-static gain of the state-space model equals the static response to a small
/// `[[prescribe]]` stroke of e.y (central difference of two static solutions, same tension).
#[test]
fn motion_input_static_gain_equals_prescribed_statics() {
    let h = 1e-5;
    let text = std::fs::read_to_string(cli_model("clamped_guided.toml")).unwrap();
    let f = parse(&text, "guided_motion.toml");
    let nodes = ["b:1", "b:2", "b:3", "e"];
    let outputs: Vec<String> = nodes
        .iter()
        .flat_map(|n| ["x", "y"].map(|d| format!("{n}:{d}")))
        .collect();
    let outputs: Vec<&str> = outputs.iter().map(String::as_str).collect();
    let (_, j) = last_step(&f, &["e:y:motion"], &outputs, &StateSpaceOptions::default());
    let dc = matrix(&j["dc_gain"]);
    let stat = |v: f64| {
        let pre = format!("[[prescribe]]\nnode = \"e\"\ndof = \"y\"\nvalue = {v:e}");
        let held = text.replace("[inputs]\ne = \"y\"", &pre);
        assert_ne!(held, text);
        let s = common::static_doc(&parse(&held, "guided.toml"), "guided.toml", None);
        let last = s["steps"].as_array().unwrap().last().unwrap().clone();
        last["nodes"].as_array().unwrap().clone()
    };
    let plus = stat(h);
    let minus = stat(-h);
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
}

/// `NODE:rz:motion`: a cantilever (L = 0.2 m, no load) whose clamp rotation about z is an input
/// (`rotated_clamp.toml`). Labels and the unit rad/s² in JSON and .m; the quasi-static column is
/// the rigid rotation of the whole beam (tip y = L per radian, tip and clamp rotation 1, tip
/// x 0), and the DC gain of the tip rotation per tip moment is the compliance L/EI = 0.1.
#[test]
fn rotation_motion_input_of_clamp_is_rigid_rotation() {
    let f = shared("rotated_clamp.toml");
    let (ss, j) = last_step(
        &f,
        &["t:rz", "a:rz:motion"],
        &["t:y", "t:rz", "t:x", "a:rz"],
        &StateSpaceOptions::default(),
    );
    let inp = &j["inputs"][1];
    assert_eq!(inp["name"], "a:rz:motion");
    assert_eq!(inp["kind"], "motion");
    assert_eq!(inp["unit"], "rad/s²");
    let m = m_file(&f, &ss, &j);
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
}

/// `ELEMENT:MODE:motion` (`actuator_spring_mass.toml`): a linear actuator (truss elongation, an
/// input mode) drives a spring–mass. The actuator end follows the stroke exactly (quasi-static
/// gain 1), the mass sees the base-excitation transmissibility |X/E| = |ωₙ² + 2iζωₙω| /
/// |ωₙ² − ω² + 2iζωₙω| with ωₙ² = k/m = 2000/0.5 = 4000 s⁻²; labels name the element and mode.
#[test]
fn deformation_motion_input_actuator_closed_form() {
    let f = shared("actuator_spring_mass.toml");
    let zeta = 0.02;
    let opts = StateSpaceOptions {
        damping: zeta,
        ..Default::default()
    };
    let (ss, j) = last_step(&f, &["act:1:motion"], &["m:x", "a:x"], &opts);
    let inp = &j["inputs"][0];
    assert_eq!(inp["name"], "act:1:motion");
    assert_eq!(inp["kind"], "motion");
    assert_eq!(inp["unit"], "m/s²");
    assert_eq!(inp["element"], "act");
    assert_eq!(inp["mode"], 1);
    assert_eq!(inp["mode_name"], "elongation");
    let dc = matrix(&j["dc_gain"]);
    assert!((dc[0][0] - 1.0).abs() < 1e-12 && (dc[1][0] - 1.0).abs() < 1e-12);
    let csv = bode_default(&f, &ss, 9);
    let rows = transmissibility_rows(&csv, "mag(m:x:disp/act:1:motion)", zeta);
    assert_eq!(rows, 9);
}

/// Element outputs on the actuator–spring–mass: with the actuator held, a force F on the mass
/// is carried by the spring and by the actuator (σ/F = 1 at DC, spring deformation
/// F/k = F/2000); a slow actuator stroke moves the spring rigidly (σ = 0); the JSON names
/// element, mode and quantity.
#[test]
fn element_outputs_of_the_actuator_spring_mass() {
    let f = shared("actuator_spring_mass.toml");
    let (_, j) = last_step(
        &f,
        &["m:x", "act:1:motion"],
        &[
            "spring:1:force",
            "spring:1:def",
            "spring:1:def:vel",
            "act:1:force",
            "g:x:reaction",
        ],
        &StateSpaceOptions::default(),
    );
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
}

/// A model above the dense limit: the F01 strip (L = 0.1 m, b = 20 mm, t = 0.5 mm,
/// E = 200 GPa) in 600 elements (3600 degrees of freedom) takes the sparse path. A motion of
/// the clamp moves the tip one to one; with 4 modes and the static correction the static gain
/// of the tip under a tip force along z is the Euler–Bernoulli L³/(3 E I), I = b t³/12, and the
/// first frequency the clamped–free 40.899 Hz (examples/strip_f01.toml). The path is solved
/// once for both state spaces (the command solves it for each).
#[test]
fn large_model_state_space_takes_the_sparse_path() {
    let text = std::fs::read_to_string(example("strip_f01.toml"))
        .unwrap()
        .replace("segments = 10", "segments = 600");
    let f = parse(&text, "strip_600.toml");
    let sol = static_path(&f).unwrap_or_else(|s| panic!("{}", s.error));
    let last = sol.steps.len() - 1;
    let opts = StateSpaceOptions {
        modes: Some(4),
        static_correction: true,
        ..Default::default()
    };
    // a motion of the clamp moves the unloaded strip rigidly: the tip follows one to one
    let (_, j) = statespace_doc(
        &f,
        "strip_600.toml",
        &sol,
        last,
        &["root:z:motion"],
        &["tip:z"],
        &opts,
    );
    assert_eq!(j["solver"], "sparse");
    let g = matrix(&j["dc_gain"]);
    assert!((g[0][0] - 1.0).abs() < 1e-9, "{}", g[0][0]);
    let (_, j) = statespace_doc(
        &f,
        "strip_600.toml",
        &sol,
        last,
        &["tip:z"],
        &["tip:z"],
        &opts,
    );
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
