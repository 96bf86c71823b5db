//! Mode classes in `flexmbd modes` (issue 19 item 2, docs/dynamics.md "Mode classes") on the
//! paper's folded-sheet guides, through the binary (text and JSON), on both eigen solvers.
//!
//! The expected classes come from the paper (§5; theory.md §15) and from the physics of the
//! examples' geometry (their headers), not from flexmbd:
//!
//! - five sheets: mode 1 is the intended translation along x (paper: "the intended motion");
//!   modes 2 and 3 move the rigid part across the guide, resisted by the in-plane bending of
//!   the sheets (paper: "the rigid body moves as well ... in-plane bending"): support; the
//!   platform's rocking (a rotation, held by in-plane bending too) is support; then the five
//!   internal modes of the folds (paper: "internal modes of the folded sheets": a fold turns
//!   about its fold line and the platform stays still);
//! - six sheets: mode 1 intended ("same mode shape"), modes 2 and 3 the pair of transverse
//!   translations ("coincides with the third"): support; then the six internal modes of the
//!   folds, one per folded sheet; then the rotations of the platform (support).

use serde_json::Value;

mod common;
use common::{example, run, Temp};

fn modes(path: &std::path::Path, count: usize, solver: &str) -> Vec<Value> {
    let count = count.to_string();
    let args = [
        "modes",
        path.to_str().unwrap(),
        "--json",
        "--count",
        &count,
        "--solver",
        solver,
    ];
    let out = run(&args);
    assert!(
        out.status.success(),
        "flexmbd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    doc["modes"].as_array().expect("modes").clone()
}

fn classes(modes: &[Value]) -> Vec<&str> {
    modes
        .iter()
        .map(|m| m["class"].as_str().expect("class"))
        .collect()
}

/// The classes on both solvers, with the same fractions (within 1e-8).
fn both_solvers(name: &str, count: usize) -> Vec<Value> {
    let path = example(name);
    let dense = modes(&path, count, "dense");
    let sparse = modes(&path, count, "sparse");
    assert_eq!(classes(&dense), classes(&sparse), "{name}");
    for (k, (a, b)) in dense.iter().zip(&sparse).enumerate() {
        // an exactly degenerate pair is any orthonormal pair of its plane: its fractions are
        // not unique, its class is
        let pair = |j: usize| {
            dense.get(j).is_some_and(|o: &Value| {
                let (f, g) = (
                    a["eigenvalue"].as_f64().unwrap(),
                    o["eigenvalue"].as_f64().unwrap(),
                );
                (f - g).abs() < 1e-6 * f
            })
        };
        if (k > 0 && pair(k - 1)) || pair(k + 1) {
            continue;
        }
        for field in ["body_fraction", "released_fraction"] {
            let (p, q) = (a[field].as_f64().unwrap(), b[field].as_f64().unwrap());
            assert!(
                (p - q).abs() < 1e-8,
                "{name} mode {}: {field} {p} vs {q}",
                k + 1
            );
        }
    }
    dense
}

#[test]
fn five_sheet_guide_intended_support_and_internal() {
    let m = both_solvers("paper_dynamic_5_sheets.toml", 9);
    let mut want = vec!["intended", "support", "support", "support"];
    want.extend(["internal"; 5]);
    assert_eq!(classes(&m), want);
    // the decisive fractions on the right side of their thresholds (0.5)
    for mode in &m {
        let (beta, rho) = (
            mode["body_fraction"].as_f64().unwrap(),
            mode["released_fraction"].as_f64().unwrap(),
        );
        assert!(
            (0.0..=1.0).contains(&beta) && (0.0..=1.0).contains(&rho),
            "{mode}"
        );
    }
}

#[test]
fn six_sheet_guide_intended_support_pair_and_six_internal_modes() {
    let m = both_solvers("paper_dynamic_6_sheets.toml", 12);
    let mut want = vec!["intended", "support", "support"];
    want.extend(["internal"; 6]);
    want.extend(["support"; 3]);
    assert_eq!(classes(&m), want);
}

/// The text report of `flexmbd modes examples/NAME --count N`.
fn modes_text(name: &str, count: usize) -> String {
    let path = example(name);
    let out = run(&[
        "modes",
        path.to_str().unwrap(),
        "--count",
        &count.to_string(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn the_text_shows_the_class_with_its_fractions() {
    let text = modes_text("paper_dynamic_5_sheets.toml", 5);
    let row = |k: usize| {
        text.lines()
            .find(|l| l.trim_start().starts_with(&format!("{k} ")))
            .unwrap_or_else(|| panic!("row {k}:\n{text}"))
            .to_string()
    };
    assert!(text.contains("class"), "{text}");
    assert!(row(1).contains("intended  β 0."), "{}", row(1));
    assert!(row(1).contains("ρ 1.00"), "{}", row(1));
    assert!(row(2).contains("support"), "{}", row(2));
    assert!(row(5).contains("internal"), "{}", row(5));
    assert!(!text.contains("no bodies"), "{text}");
}

#[test]
fn a_model_without_bodies_says_that_every_mode_is_internal() {
    // the F01 strip has no point mass and no inertia: β = 0 for every mode
    let text = modes_text("strip_f01.toml", 3);
    assert!(
        text.contains("no bodies (masses/inertias on nodes): every mode counts as internal"),
        "{text}"
    );
    for m in modes(&example("strip_f01.toml"), 3, "auto") {
        assert_eq!(m["class"], "internal");
        assert_eq!(m["body_fraction"], 0.0);
    }
}

#[test]
fn rigid_body_modes_have_no_released_fraction() {
    // a free steel strip with a point mass: six rigid-body modes (nothing holds it), then
    // the elastic ones
    let dir = Temp::new("mode_classes_rigid");
    let file = dir.0.join("free.toml");
    std::fs::write(
        &file,
        r#"
[model]
name = "free strip"
[nodes]
p = [0.0, 0.0, 0.0]
q = [0.1, 0.0, 0.0]
[[material]]
id = "steel"
E = 200e9
nu = 0.3
rho = 7800.0
[[section]]
id = "strip"
shape = "rectangle"
w = 0.02
t = 0.0005
[[beam]]
id = "b"
nodes = ["p", "q"]
orient = [0.0, 0.0, 1.0]
section = "strip"
material = "steel"
segments = 4
free = [2, 3, 4]
[[mass]]
node = "q"
m = 0.01
"#,
    )
    .unwrap();
    let m = modes(&file, 8, "dense");
    for (k, mode) in m.iter().enumerate() {
        if k < 6 {
            assert_eq!(mode["rigid_body"], true, "{mode}");
            assert_eq!(mode["class"], "rigid_body");
            assert!(mode["released_fraction"].is_null(), "{mode}");
            assert!(mode["body_fraction"].is_f64(), "{mode}");
        } else {
            assert_ne!(mode["class"], "rigid_body");
            assert!(mode["released_fraction"].is_f64(), "{mode}");
        }
    }
}

#[test]
fn the_html_report_names_the_class_of_each_mode() {
    let dir = Temp::new("mode_classes_view");
    let out = dir.0.join("report.html");
    let path = example("paper_dynamic_5_sheets.toml");
    let r = run(&[
        "view",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--analysis",
        "modes",
        "--count",
        "5",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let html = std::fs::read_to_string(&out).expect("report written");
    let open = r#"<script type="application/json" id="flexmbd-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data");
    let data: Value = serde_json::from_str(&html[start..end]).expect("data is JSON");
    let class = |k: usize| {
        data["animations"][k]["class"]
            .as_str()
            .unwrap_or("")
            .to_string()
    };
    assert!(class(0).starts_with("intended β 0."), "{}", class(0));
    assert!(class(1).starts_with("support β"), "{}", class(1));
    assert!(class(4).starts_with("internal β"), "{}", class(4));
    // the selector and the heading show it
    assert!(html.contains("a.class ? ', ' + a.class"), "viewer script");
}
