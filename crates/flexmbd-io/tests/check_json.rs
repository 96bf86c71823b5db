//! The streamed `check --json` document is the `serde_json::Value` document it replaced, byte
//! for byte (the reference below is the former writer, kept here as the test's oracle).

use flexmbd_core::kinematics::classify::{classify, ClassifyOptions};
use flexmbd_core::kinematics::{CheckMethod, CheckOptions};
use flexmbd_core::model::{DefKind, Dof, ElementSpec, ModelBuilder};
use flexmbd_core::Model;
use flexmbd_io::report::{generalised_names, write_check_json, CheckReport};
use serde_json::{json, Value};

/// The former `check_json`: the whole document as a `Value`.
fn reference(r: &CheckReport<'_>, generalised: &[String]) -> Value {
    let a = r.analysis;
    let mut doc = json!({
        "model": r.model.name,
        "file": r.file,
        "rows": a.m(),
        "cols": a.n(),
        "rank": a.rank,
        "euler_parameter_form": { "rows": a.euler_shape.0, "cols": a.euler_shape.1 },
        "rank_tol": r.rank_tol,
        "rank_threshold": a.tol,
        "rank_gap": a.rank_gap(),
        "singular_values": a.singular_values,
        "table1_row": a.case.row(),
        "classification": a.case.describe(),
        "kinematically_determinate": a.n_motions() == 0,
        "statically_determinate": a.n_self_stresses() == 0,
        "exactly_constrained": a.n_motions() == 0 && a.n_self_stresses() == 0,
        "n_mechanisms": a.n_motions(),
        "n_self_stresses": a.n_self_stresses(),
        "generalised_coordinates": generalised,
        "input_deformations": a.rows.iter().filter(|r| r.kind == DefKind::Input).count(),
        "mechanisms": a.motions,
        "self_stresses": a.self_stresses,
        "suggestions": r.advice,
    });
    if let Some((chosen, before)) = r.auto {
        doc["auto"] = json!({
            "chosen": chosen,
            "before": { "rows": before.m(), "cols": before.n(), "rank": before.rank,
                        "n_mechanisms": before.n_motions(), "n_self_stresses": before.n_self_stresses() },
        });
    }
    // the keys added with the designer's language (twists, wrenches, wires)
    if let Some(sc) = r.screws {
        doc["screws"] = json!(sc);
    }
    if let Some(f) = r.freedom {
        doc["freedom"] = json!(f);
    }
    doc["wire_suggestions"] = json!(r.wires);
    doc
}

/// A curved strip of beams, clamped, two modes of each free (motions), the tip's x and y as
/// generalised coordinates, and two equal rigid bars side by side (a self-stress).
fn model() -> Model {
    let mut b = ModelBuilder::new("strip");
    for i in 0..=6 {
        let t = i as f64 / 6.0;
        b.add_node(&format!("s{i}"), [t, 0.3 * t * t, 0.0], true)
            .unwrap();
    }
    for i in 0..6 {
        b.add_element(
            &format!("beam{i}"),
            &[&format!("s{i}"), &format!("s{}", i + 1)],
            ElementSpec::Beam {
                orient: Some([0.0, 0.0, 1.0]),
                ct: 0.0,
            },
            &[2, 4],
            &[],
        )
        .unwrap();
    }
    // two equal rigid bars side by side: their rows are equal, a self-stress for sure
    for t in ["t1", "t2"] {
        b.add_element(t, &["s1", "s5"], ElementSpec::Truss { ea: 0.0 }, &[], &[])
            .unwrap();
    }
    b.fix("s0", None).unwrap();
    b.input("s6", Some(&[Dof::X, Dof::Y])).unwrap();
    b.build().unwrap()
}

fn documents(m: &Model, auto: bool, method: CheckMethod) -> (Vec<u8>, Option<String>) {
    let opts = ClassifyOptions {
        check: CheckOptions {
            method,
            ..Default::default()
        },
        auto,
        max_suggestions: 6,
    };
    let c = classify(m, &opts).unwrap();
    let report = CheckReport::of(m, "strip.toml", opts.check.rank_tol, &c);
    let names = generalised_names(m, &c.partition.x, &c.partition.e);
    let mut out = Vec::new();
    write_check_json(&mut out, &report, &names).unwrap();
    let old = (method == CheckMethod::Dense)
        .then(|| serde_json::to_string_pretty(&reference(&report, &names)).unwrap() + "\n");
    (out, old)
}

#[test]
fn streamed_check_json_equals_the_value_document_byte_for_byte() {
    let m = model();
    for auto in [false, true] {
        let (new, old) = documents(&m, auto, CheckMethod::Dense);
        let old = old.unwrap();
        let v: Value = serde_json::from_str(&old).unwrap();
        // the case exercises every part of the document
        assert!(v["n_mechanisms"].as_u64().unwrap() > 0 || auto);
        assert!(v["n_self_stresses"].as_u64().unwrap() > 0);
        assert!(!v["suggestions"].as_array().unwrap().is_empty());
        assert_eq!(v.get("auto").is_some(), auto);
        assert!(
            String::from_utf8(new).unwrap() == old,
            "auto = {auto}: the streamed document differs"
        );
    }
}

#[test]
fn sparse_check_json_holds_the_decision_and_every_defining_row() {
    let m = model();
    let (new, _) = documents(&m, false, CheckMethod::Sparse);
    let v: Value = serde_json::from_slice(&new).unwrap();
    let sp = &v["sparse"];
    assert_eq!(sp["certain"], Value::Bool(true));
    let ss = v["n_self_stresses"].as_u64().unwrap() as usize;
    let mo = v["n_mechanisms"].as_u64().unwrap() as usize;
    assert_eq!(sp["self_stress_deformations"].as_array().unwrap().len(), ss);
    assert_eq!(sp["motion_coordinates"].as_array().unwrap().len(), mo);
    assert!(v["singular_values"].as_array().unwrap().is_empty());
    // the same counts as the dense path
    let (dense, _) = documents(&m, false, CheckMethod::Dense);
    let d: Value = serde_json::from_slice(&dense).unwrap();
    assert_eq!(d["n_self_stresses"], v["n_self_stresses"]);
    assert_eq!(d["n_mechanisms"], v["n_mechanisms"]);
}

/// A flexure of many beams has six generalised coordinates (its deformations, as SPACAR's
/// `DYNE` modes are in the kinematic analysis) per beam: the text
/// report names the count, the first twenty and the last four, and `--json` lists all.
#[test]
fn a_long_list_of_generalised_coordinates_is_summarised_in_the_text_report() {
    let n = 10;
    let mut b = ModelBuilder::new("strip");
    for i in 0..=n {
        b.add_node(&format!("s{i}"), [i as f64, 0.0, 0.0], true)
            .unwrap();
    }
    for i in 0..n {
        b.add_element(
            &format!("b{i}"),
            &[&format!("s{i}"), &format!("s{}", i + 1)],
            ElementSpec::Beam {
                orient: Some([0.0, 1.0, 0.0]),
                ct: 0.0,
            },
            &[],
            &[1, 2, 3, 4, 5, 6],
        )
        .unwrap();
    }
    b.fix("s0", None).unwrap();
    let m = b.build().unwrap();
    let opts = ClassifyOptions {
        check: CheckOptions::default(),
        auto: false,
        max_suggestions: 0,
    };
    let c = classify(&m, &opts).unwrap();
    let report = CheckReport::of(&m, "strip.toml", opts.check.rank_tol, &c);
    let names = generalised_names(&m, &c.partition.x, &c.partition.e);
    assert_eq!(names.len(), 6 * n);
    let text = flexmbd_io::report::check_text(&report, &names);
    let line = text
        .lines()
        .find(|l| l.starts_with("generalised coordinates:"))
        .unwrap();
    let expected = format!(
        "generalised coordinates: 60 in all: {}, ..., {} (all in --json)",
        names[..20].join(", "),
        names[56..].join(", ")
    );
    assert_eq!(line, expected);
    let mut out = Vec::new();
    write_check_json(&mut out, &report, &names).unwrap();
    let v: Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(
        v["generalised_coordinates"].as_array().unwrap().len(),
        6 * n
    );
}
