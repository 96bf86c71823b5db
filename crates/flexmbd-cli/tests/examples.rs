//! Every shipped example model runs through the built `flexmbd check` (the smoke run of the
//! command on the examples; what the examples give is tested at the io level,
//! `crates/flexmbd-io/tests/examples.rs`).

use std::path::{Path, PathBuf};
use std::process::Command;

fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

#[test]
fn every_example_checks() {
    let mut n = 0;
    for entry in std::fs::read_dir(examples_dir()).expect("examples/ exists") {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
            .arg("check")
            .arg(&path)
            .output()
            .expect("flexmbd runs");
        assert!(
            out.status.success(),
            "flexmbd check {} exited with {}:\n{}",
            path.display(),
            out.status,
            String::from_utf8_lossy(&out.stderr)
        );
        n += 1;
    }
    assert!(n >= 8, "found only {n} example models");
}
