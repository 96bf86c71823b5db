//! Design studies through the library: figures of merit against closed forms, a grid study
//! against the single runs, failing variants, the same records for any number of workers, a
//! stopped study resumed, and the errors of a study file.

use flexmbd_study::{evaluate_isolated, run, variants, Outputs, Record, Status, Study};
use std::path::{Path, PathBuf};

fn example(name: &str) -> (String, String) {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    (
        p.display().to_string(),
        std::fs::read_to_string(&p).expect("the example exists"),
    )
}

/// A study of `text` over the example model `model`.
fn study(text: &str, model: &str) -> Study {
    let m = example(model);
    Study::parse(text, "test-study.toml", move |_| Ok(m)).expect("a valid study")
}

fn all(study: &Study, jobs: usize) -> Vec<Record> {
    let vs = variants(study);
    let mut out = Vec::new();
    run(study, &vs, jobs, |r| {
        out.push(r);
        true
    });
    out.sort_by_key(|r| r.variant);
    out
}

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("flexmbd-study-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

const STRIP_STUDY: &str = r#"
[study]
model = "strip_f01.toml"
analyses = ["modes"]
modes = 3
[parameters]
"sections.strip.t" = { values = [0.2e-3, 0.5e-3, 1.0e-3] }
"nodes.tip.x" = { values = [0.08, 0.1] }
"#;

#[test]
fn the_first_frequency_of_every_strip_variant_is_euler_bernoulli() {
    // validation.md F01: f1 = (β1 L)² sqrt(E t² / (12 ρ L⁴)) / (2π), β1 L = 1.875104, for
    // E = 200 GPa, ρ = 7800 kg/m³; within 0.1 % (10 Hermite elements, lumped rotary inertia)
    let s = study(STRIP_STUDY, "strip_f01.toml");
    let records = all(&s, 2);
    assert_eq!(records.len(), 6);
    for r in &records {
        assert_eq!(r.status, Status::Ok, "{r:?}");
        let t = r.parameters["sections.strip.t"];
        let l = r.parameters["nodes.tip.x"];
        let exact = 1.875104f64.powi(2) * (200e9 * t * t / (12.0 * 7800.0 * l.powi(4))).sqrt()
            / (2.0 * std::f64::consts::PI);
        let f1 = r.merits["f1"].expect("f1");
        assert!(
            (f1 / exact - 1.0).abs() < 1e-3,
            "t {t} L {l}: {f1} vs {exact}"
        );
    }
}

#[test]
fn a_grid_study_equals_the_single_runs() {
    // each record's frequencies are those of `modes` on the member built by hand
    let s = study(STRIP_STUDY, "strip_f01.toml");
    let (file, text) = example("strip_f01.toml");
    for r in all(&s, 2) {
        let mut spec = flexmbd_io::model_toml::parse_spec(&text, &file).unwrap();
        for (k, v) in &r.parameters {
            spec.set(k, *v).unwrap();
        }
        let m = spec.build_file().unwrap().model;
        let sol = flexmbd_core::statics::solve(&m, &Default::default(), |_, _| {}).unwrap();
        let modal = flexmbd_core::dynamics::modes(&m, sol.steps.last().unwrap(), 3).unwrap();
        let single: Vec<Option<f64>> = modal.modes.iter().map(|m| Some(m.frequency)).collect();
        assert_eq!(r.frequencies, single, "variant {}", r.variant);
    }
}

#[test]
fn stroke_merits_of_the_parallel_leaf_guide_match_the_closed_forms() {
    // examples/parallel_leaf_stroke.toml: leaves L = 50 mm, w = 20 mm, t = 0.3 mm, E = 210 GPa,
    // ν = 0.3, the platform p driven in x. A small stroke x = 0.05 mm:
    // - support stiffness in z at the start: 2 EA / L (two straight leaves in tension), exact;
    // - in y at the start: each leaf a Timoshenko cantilever with its in-plane bending (the
    //   platform's tips lie on its x axis, so nothing holds their rotation about x):
    //   1/k = L³/(3 E I_w) + L/(κ G A), κ = 10(1+ν)/(12+11ν) (Cowper), two leaves;
    // - actuation force: 24 E I x / L³ (two clamped-guided leaves), 0.1 % at this stroke.
    let s = study(
        r#"
[study]
model = "parallel_leaf_stroke.toml"
analyses = ["stroke"]
support = ["p:z", "p:y"]
buckling = false
[parameters]
"prescribed.p.value" = { values = [0.05e-3] }
"#,
        "parallel_leaf_stroke.toml",
    );
    let r = &all(&s, 1)[0];
    assert_eq!(r.status, Status::Ok, "{r:?}");
    let (e, nu, l, w, t, x): (f64, f64, f64, f64, f64, f64) =
        (210e9, 0.3, 0.05, 0.02, 0.3e-3, 0.05e-3);
    let (a, g) = (w * t, e / (2.0 * (1.0 + nu)));
    let kz = 2.0 * e * a / l;
    let kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
    let ky = 2.0 / (l.powi(3) / (3.0 * e * t * w.powi(3) / 12.0) + l / (kappa * g * a));
    let force = 24.0 * e * (w * t.powi(3) / 12.0) * x / l.powi(3);
    let m = |k: &str| r.merits[k].unwrap_or_else(|| panic!("{k}"));
    assert!(
        (m("k_p_z_start") / kz - 1.0).abs() < 1e-9,
        "{} {kz}",
        m("k_p_z_start")
    );
    assert!(
        (m("k_p_y_start") / ky - 1.0).abs() < 1e-3,
        "{} {ky}",
        m("k_p_y_start")
    );
    assert!((m("max_actuation_force") / force - 1.0).abs() < 1e-3);
    assert_eq!(m("stroke_reached"), 1.0);
    // the drop is defined from the two ends
    let drop = 1.0 - m("k_p_z_end") / m("k_p_z_start");
    assert_eq!(m("k_p_z_drop"), drop);
    assert!(!r.merits.contains_key("buckling_margin"));
}

#[test]
fn a_study_with_failing_variants_completes_with_their_errors() {
    // a thickness of 0 is not a section; the other variants run
    let s = study(
        r#"
[study]
model = "strip_f01.toml"
analyses = ["check", "modes"]
modes = 2
[parameters]
"sections.strip.t" = { values = [0.5e-3, 0.0, -1e-3, 1e-3] }
"#,
        "strip_f01.toml",
    );
    let records = all(&s, 2);
    assert_eq!(records.len(), 4);
    let status: Vec<Status> = records.iter().map(|r| r.status).collect();
    assert_eq!(
        status,
        [Status::Ok, Status::Failed, Status::Failed, Status::Ok]
    );
    for r in &records[1..3] {
        let e = r.error.as_ref().unwrap();
        assert_eq!(e.stage, "model");
        assert!(e.message.contains("section `strip`"), "{}", e.message);
        assert!(r.merits.values().all(Option::is_none));
    }
    // the CSV row of a failed variant holds its error, quoted
    let row = records[1].to_csv_row();
    assert!(row.contains(",failed,") && row.contains(",model,"), "{row}");
}

#[test]
fn the_records_are_the_same_bit_for_bit_for_any_number_of_workers() {
    let s = study(
        r#"
[study]
model = "parallel_leaf_stroke.toml"
analyses = ["check", "stroke", "modes"]
support = ["p:z"]
modes = 4
sampling = "latin"
samples = 6
seed = 3
[parameters]
"prescribed.p.value" = { from = 1e-3, to = 4e-3 }
"sections.leaf.t" = { from = 0.2e-3, to = 0.4e-3 }
"#,
        "parallel_leaf_stroke.toml",
    );
    let one: Vec<String> = all(&s, 1).iter().map(Record::to_json_line).collect();
    let two: Vec<String> = all(&s, 2).iter().map(Record::to_json_line).collect();
    assert_eq!(one, two);
    let isolated: Vec<String> = variants(&s)
        .iter()
        .map(|v| evaluate_isolated(&s, v).to_json_line())
        .collect();
    assert_eq!(one, isolated);
    // a record reads back from its JSON line as the same record
    for line in &one {
        let r: Record = serde_json::from_str(line).unwrap();
        assert_eq!(&r.to_json_line(), line);
    }
}

#[test]
fn a_stopped_study_resumes_and_ends_with_the_records_of_an_uninterrupted_run() {
    let s = study(STRIP_STUDY, "strip_f01.toml");
    let vs = variants(&s);
    let n = vs.len();
    // the uninterrupted run
    let whole = temp("whole");
    let mut o = Outputs::open(&whole, &s, n, false).unwrap();
    run(&s, &vs, 2, |r| o.write(r).is_ok());
    o.finish(&s).unwrap();
    // a run stopped after its second record, with a line cut short by the stop
    let dir = temp("resumed");
    let mut o = Outputs::open(&dir, &s, n, false).unwrap();
    let mut k = 0;
    run(&s, &vs, 1, |r| {
        o.write(r).unwrap();
        k += 1;
        k < 2
    });
    drop(o);
    let jsonl = dir.join("records.jsonl");
    let before = std::fs::read_to_string(&jsonl).unwrap();
    std::fs::write(&jsonl, before.clone() + "{\"variant\":5,\"parame").unwrap();
    // resumed: the records kept, the cut line dropped, the rest run
    let mut o = Outputs::open(&dir, &s, n, false).unwrap();
    assert_eq!(o.records.len(), before.lines().count());
    assert!(o.records.len() >= 2 && o.records.len() < n);
    assert_eq!(std::fs::read_to_string(&jsonl).unwrap(), before);
    let todo: Vec<_> = vs
        .iter()
        .filter(|v| !o.records.contains_key(&v.index))
        .cloned()
        .collect();
    run(&s, &todo, 2, |r| o.write(r).is_ok());
    o.finish(&s).unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join("results.csv")).unwrap(),
        std::fs::read_to_string(whole.join("results.csv")).unwrap()
    );
    let sorted = |d: &Path| {
        let mut l: Vec<String> = std::fs::read_to_string(d.join("records.jsonl"))
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        l.sort();
        l
    };
    assert_eq!(sorted(&dir), sorted(&whole));
    // another study is refused in that folder, and replaced on request
    let other = study(
        &STRIP_STUDY.replace("modes = 3", "modes = 2"),
        "strip_f01.toml",
    );
    let e = Outputs::open(&dir, &other, n, false)
        .err()
        .expect("refused");
    assert!(e.to_string().contains("another study"), "{e}");
    let o = Outputs::open(&dir, &other, n, true).unwrap();
    assert!(o.records.is_empty());
    for d in [whole, dir] {
        let _ = std::fs::remove_dir_all(d);
    }
}

#[test]
fn study_file_errors_name_the_line_and_the_item() {
    let cases: [(&str, usize, &str); 6] = [
        (
            "[study]\nmodel = \"strip_f01.toml\"\nsampling = \"random\"\n[parameters]\n\"sections.strip.t\" = { values = [1e-3] }\n",
            3,
            "unknown method `random`",
        ),
        (
            "[study]\nmodel = \"strip_f01.toml\"\n[parameters]\n\"sections.strip.t\" = { from = 1e-3, to = 2e-3 }\n",
            4,
            "a grid needs `count`",
        ),
        (
            "[study]\nmodel = \"strip_f01.toml\"\n[parameters]\n\"sections.strip.q\" = { values = [1e-3] }\n",
            4,
            "sections.strip.q",
        ),
        (
            "[study]\nmodel = \"strip_f01.toml\"\n[parameters]\nthickness = { values = [1e-3] }\n",
            4,
            "not declared in the model's [parameters]",
        ),
        (
            "[study]\nmodel = \"strip_f01.toml\"\nanalyses = [\"modes\", \"buckle\"]\n[parameters]\n\"sections.strip.t\" = { values = [1e-3] }\n",
            3,
            "unknown analysis `buckle`",
        ),
        (
            "[study]\nmodel = \"strip_f01.toml\"\nsupport = [\"tip:y\"]\n[parameters]\n\"sections.strip.t\" = { values = [1e-3] }\n",
            3,
            "add \"stroke\" to analyses",
        ),
    ];
    for (text, line, words) in cases {
        let m = example("strip_f01.toml");
        let e = Study::parse(text, "s.toml", move |_| Ok(m)).expect_err("an error");
        let msg = e.to_string();
        assert!(msg.starts_with(&format!("s.toml:{line}:")), "{msg}");
        assert!(msg.contains(words), "{msg}");
        assert!(e.is_input());
    }
}

#[test]
fn parameters_and_listed_variants_keep_the_file_order() {
    // TOML tables come back sorted by key; the study keeps the order the user wrote
    let s = study(
        r#"
[study]
model = "strip_f01.toml"
analyses = ["modes"]
sampling = "list"
[[variant]]
"sections.strip.t" = 0.5e-3
"nodes.tip.x" = 0.1
[[variant]]
"nodes.tip.x" = 0.05
"sections.strip.t" = 0.3e-3
"#,
        "strip_f01.toml",
    );
    assert_eq!(s.parameter_names(), ["sections.strip.t", "nodes.tip.x"]);
    let v = variants(&s);
    assert_eq!(v[0].values, [0.5e-3, 0.1]);
    assert_eq!(v[1].values, [0.3e-3, 0.05]);
    let g = study(STRIP_STUDY, "strip_f01.toml");
    assert_eq!(g.parameter_names(), ["sections.strip.t", "nodes.tip.x"]);
    // the grid: the last parameter fastest
    let gv: Vec<Vec<f64>> = variants(&g).into_iter().map(|v| v.values).collect();
    assert_eq!(gv[0], [0.2e-3, 0.08]);
    assert_eq!(gv[1], [0.2e-3, 0.1]);
    assert_eq!(gv[2], [0.5e-3, 0.08]);
}

#[test]
fn the_paper_guide_study_reports_the_intended_and_support_frequencies() {
    // examples/folded_sheet_guide_param.toml at the paper's t = 0.2 mm, L = 50 mm: mode 1 the
    // intended x translation at 8.2 Hz (paper §5), then support modes (the paper: "about
    // 20 x" higher), the fold modes internal; f_intended scales as t^1.5 (the model's header)
    let s = study(
        r#"
[study]
model = "folded_sheet_guide_param.toml"
analyses = ["modes"]
modes = 10
[parameters]
t = { values = [0.2e-3, 0.3e-3] }
"#,
        "folded_sheet_guide_param.toml",
    );
    let r = all(&s, 2);
    let f = |k: usize, m: &str| r[k].merits[m].unwrap_or_else(|| panic!("{m}"));
    assert!((f(0, "f_intended") / 8.2 - 1.0).abs() < 0.01);
    assert_eq!(r[0].classes[0], "intended");
    assert!(f(0, "support_ratio") > 15.0 && f(0, "f_internal") > f(0, "f_support"));
    assert!((f(1, "f_intended") / f(0, "f_intended") / 1.5f64.powf(1.5) - 1.0).abs() < 0.01);
}
