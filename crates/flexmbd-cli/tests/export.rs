//! `flexmbd export`: ParaView files and plots (docs/visualisation.md).

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("flexmbd-export-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn export(model: &str, args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .current_dir(root())
        .arg("export")
        .arg(format!("examples/{model}.toml"))
        .args(args)
        .output()
        .expect("run flexmbd");
    assert!(
        out.status.success(),
        "flexmbd export {model} {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn model(name: &str) -> flexmbd_core::Model {
    flexmbd_io::read_model(&root().join(format!("examples/{name}.toml"))).expect("model")
}

/// The number in `attr="N"` of a .vtu file.
fn xml_count(text: &str, attr: &str) -> usize {
    let i = text.find(&format!("{attr}=\"")).expect(attr) + attr.len() + 2;
    text[i..].split('"').next().unwrap().parse().unwrap()
}

/// Point and cell counts written in a .vtu equal the model's nodes and line cells, and the
/// named arrays are there.
fn assert_vtu(path: &Path, m: &flexmbd_core::Model, fields: &[&str]) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        xml_count(&text, "NumberOfPoints"),
        m.nodes.len(),
        "{}",
        path.display()
    );
    assert_eq!(
        xml_count(&text, "NumberOfCells"),
        flexmbd_io::vtk::cell_count(m),
        "{}",
        path.display()
    );
    for f in fields {
        assert!(
            text.contains(&format!("Name=\"{f}\"")),
            "{}: no field {f}",
            path.display()
        );
    }
}

/// A PNG of the requested size (IHDR width and height) and its SVG.
fn assert_plot(stem: &Path, size: (u32, u32)) {
    let png = std::fs::read(stem.with_extension("png"))
        .unwrap_or_else(|e| panic!("{}.png: {e}", stem.display()));
    assert!(png.len() > 1000, "{}.png is nearly empty", stem.display());
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&png[12..16], b"IHDR");
    let w = u32::from_be_bytes(png[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(png[20..24].try_into().unwrap());
    assert_eq!((w, h), size, "{}.png", stem.display());
    let svg = std::fs::read_to_string(stem.with_extension("svg")).unwrap();
    assert!(svg.contains("<svg"), "{}.svg", stem.display());
    assert!(svg.contains("<text"), "{}.svg has no text", stem.display());
}

/// Run the independent meshio reader on `dir` if meshio is installed.
fn meshio_check(dir: &Path, expect: serde_json::Value) {
    let have = Command::new("python3")
        .args(["-c", "import meshio"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !have {
        println!("skipped: meshio not installed (python3 -m pip install --user meshio)");
        return;
    }
    let json = dir.join("expect.json");
    std::fs::write(&json, expect.to_string()).unwrap();
    let out = Command::new("python3")
        .arg(root().join("crates/flexmbd-cli/tests/vtk_meshio.py"))
        .arg(dir)
        .arg(&json)
        .output()
        .expect("python3");
    assert!(
        out.status.success(),
        "meshio check failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn expect(
    m: &flexmbd_core::Model,
    point: &[(&str, usize)],
    cell: &[(&str, usize)],
) -> serde_json::Value {
    serde_json::json!({
        "points": m.nodes.len(),
        "cells": flexmbd_io::vtk::cell_count(m),
        "point_data": point.iter().map(|(n, c)| (n.to_string(), serde_json::Value::from(*c))).collect::<serde_json::Map<_, _>>(),
        "cell_data": cell.iter().map(|(n, c)| (n.to_string(), serde_json::Value::from(*c))).collect::<serde_json::Map<_, _>>(),
    })
}

const BASE: [(&str, usize); 3] = [("element", 1), ("element_type", 1), ("section", 2)];
const STEP_CELLS: [(&str, usize); 6] = [
    ("element", 1),
    ("element_type", 1),
    ("section", 2),
    ("e", 6),
    ("sigma", 6),
    ("max_stress", 1),
];

#[test]
fn check_export_twelve_truss() {
    let d = out_dir("check");
    let (vtk, plots) = (d.join("vtk"), d.join("plots"));
    export(
        "twelve_truss",
        &[
            "--analysis",
            "check",
            "--vtk",
            vtk.to_str().unwrap(),
            "--plots",
            plots.to_str().unwrap(),
            "--plot-size",
            "700x450",
        ],
    );
    let m = model("twelve_truss");
    assert_vtu(
        &vtk.join("check.vtu"),
        &m,
        &["motion_1", "motion_1_angular", "self_stress_1"],
    );
    assert_plot(&plots.join("singular_values"), (700, 450));
    let mut cells = BASE.to_vec();
    cells.push(("self_stress_1", 1));
    meshio_check(
        &vtk,
        serde_json::json!({"check.vtu": expect(&m, &[("motion_1", 3), ("motion_1_angular", 3)], &cells)}),
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn static_export_parallel_leaf_stroke() {
    let d = out_dir("static");
    let (vtk, plots) = (d.join("vtk"), d.join("plots"));
    export(
        "parallel_leaf_stroke",
        &[
            "--analysis",
            "static",
            "--vtk",
            vtk.to_str().unwrap(),
            "--plots",
            plots.to_str().unwrap(),
            "--plot-size",
            "640x400",
            "--count",
            "3",
        ],
    );
    let m = model("parallel_leaf_stroke");
    // 20 steps and the unloaded state
    for k in 0..=20 {
        assert_vtu(
            &vtk.join(format!("static_{k:04}.vtu")),
            &m,
            &[
                "displacement",
                "rotation",
                "e",
                "sigma",
                "max_stress",
                "section",
            ],
        );
    }
    let pvd = std::fs::read_to_string(vtk.join("static.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 21);
    assert!(pvd.contains("timestep=\"1e0\" group=\"\" part=\"0\" file=\"static_0020.vtu\""));
    // the deformed platform node moved by the 5 mm stroke
    let last = std::fs::read_to_string(vtk.join("static_0020.vtu")).unwrap();
    assert!(
        last.contains("5e-3") || last.contains("4.99999"),
        "stroke not in the last step"
    );
    for p in ["force_stroke", "stiffness_p", "frequency_stroke"] {
        assert_plot(&plots.join(p), (640, 400));
    }
    let e = expect(&m, &[("displacement", 3), ("rotation", 3)], &STEP_CELLS);
    meshio_check(
        &vtk,
        serde_json::json!({"static_0000.vtu": e, "static_0020.vtu": e}),
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn modes_export_strip() {
    let d = out_dir("modes");
    let (vtk, plots) = (d.join("vtk"), d.join("plots"));
    export(
        "strip_f01",
        &[
            "--analysis",
            "modes",
            "--count",
            "4",
            "--vtk",
            vtk.to_str().unwrap(),
            "--plots",
            plots.to_str().unwrap(),
        ],
    );
    let m = model("strip_f01");
    for k in 1..=4 {
        assert_vtu(
            &vtk.join(format!("mode_{k:03}.vtu")),
            &m,
            &["mode", "mode_rotation"],
        );
    }
    assert!(!vtk.join("mode_005.vtu").exists());
    let pvd = std::fs::read_to_string(vtk.join("modes.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 4);
    assert_plot(&plots.join("frequency_stroke"), (800, 500));
    // the first mode's largest translation is 10 % of the strip length (0.1 m)
    let text = std::fs::read_to_string(vtk.join("mode_001.vtu")).unwrap();
    let i = text.find("Name=\"mode\"").unwrap();
    let body = text[i..]
        .split('>')
        .nth(1)
        .unwrap()
        .split('<')
        .next()
        .unwrap();
    let v: Vec<f64> = body
        .split_whitespace()
        .map(|s| s.parse().unwrap())
        .collect();
    let max = v
        .chunks(3)
        .map(|c| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt())
        .fold(0.0, f64::max);
    assert!((max - 0.01).abs() < 1e-9, "largest mode translation {max}");
    let e = expect(
        &m,
        &[
            ("displacement", 3),
            ("rotation", 3),
            ("mode", 3),
            ("mode_rotation", 3),
        ],
        &STEP_CELLS,
    );
    meshio_check(&vtk, serde_json::json!({"mode_001.vtu": e}));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn export_needs_an_output() {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .current_dir(root())
        .args([
            "export",
            "examples/twelve_truss.toml",
            "--analysis",
            "check",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}
