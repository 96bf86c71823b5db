//! The eigen solver options of the command line: `flexmbd modes --solver` and `flexmbd sweep
//! --solver` (the agreement of the two paths on the examples is tested at the io level,
//! `crates/flexmbd-io/tests/example_sparse_modes.rs`).

use std::process::Command;

mod common;
use common::example as example_path;

/// The library's error names the remedy in neutral words; the command line adds the option
/// that applies it (a `hint:` line).
#[test]
fn the_command_line_spells_the_remedy_as_an_option() {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["modes", "--solver", "sparse", "--quiet"])
        .arg(example_path("folded_sheet_guide_6.toml"))
        .output()
        .expect("run flexmbd");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("use the dense eigen solver"), "{err}");
    assert!(
        err.contains("\nhint: run `flexmbd check` on the model, or use --solver dense"),
        "{err}"
    );
}

fn sweep_frequencies(solver: &str) -> Vec<Vec<f64>> {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["sweep", "--count", "4", "--json", "--solver", solver])
        .arg(example_path("parallel_leaf_stroke.toml"))
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    v["steps"]
        .as_array()
        .expect("steps")
        .iter()
        .map(|s| {
            s["frequencies_hz"]
                .as_array()
                .expect("frequencies")
                .iter()
                .map(|f| f.as_f64().expect("a number"))
                .collect()
        })
        .collect()
}

#[test]
fn sweep_solver_option() {
    let (d, s) = (sweep_frequencies("dense"), sweep_frequencies("sparse"));
    assert_eq!(d.len(), s.len());
    for (a, b) in d.iter().zip(&s) {
        assert_eq!(a.len(), 4);
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() < 1e-8 * x, "{x} {y}");
        }
    }
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["sweep", "--solver", "fast"])
        .arg(example_path("parallel_leaf_stroke.toml"))
        .output()
        .expect("runs");
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("auto, dense, sparse"));
}
