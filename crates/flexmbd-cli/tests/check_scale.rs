//! `flexmbd check` on large models (issue 14): the same bits for one and two threads, and the
//! size guard of the dense analysis.

use std::path::{Path, PathBuf};
use std::process::Command;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// `flexmbd check --json MODEL` with RAYON_NUM_THREADS = `threads`: stdout.
fn check_json_with_threads(model: &Path, threads: &str) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["check", "--json"])
        .arg(model)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("run flexmbd");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out.stdout
}

#[test]
fn check_json_is_bit_identical_for_one_and_two_threads() {
    for name in ["folded_sheet_guide_6.toml", "folded_sheet_guide_5.toml"] {
        let path = example(name);
        let one = check_json_with_threads(&path, "1");
        let two = check_json_with_threads(&path, "2");
        assert!(!one.is_empty());
        assert!(
            one == two,
            "{name}: check --json differs between 1 and 2 threads"
        );
    }
}

#[test]
fn check_of_a_model_too_large_for_the_dense_analysis_stops_with_the_limit_or_goes_sparse() {
    // 3,000 rigid beams in a chain: an 18,000 x 18,000 Dcc, about 13 GB dense with its factors
    let dir = std::env::temp_dir().join(format!("flexmbd-check-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("chain.toml");
    let n = 3000;
    let mut t = String::from("[model]\nname = \"chain of 3000 beams\"\n\n[nodes]\n");
    for i in 0..=n {
        t += &format!("n{i} = {{ x = [{}.0, 0.0, 0.0], rot = true }}\n", i);
    }
    t += "\n[fix]\nn0 = \"all\"\n\n";
    for i in 0..n {
        t += &format!(
            "[[beam]]\nid = \"b{i}\"\nnodes = [\"n{i}\", \"n{}\"]\norient = [0.0, 1.0, 0.0]\n",
            i + 1
        );
    }
    std::fs::write(&path, t).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["check", "--method", "dense"])
        .arg(&path)
        .output()
        .expect("run flexmbd");
    let stderr = String::from_utf8_lossy(&out.stderr);
    // the automatic choice takes the sparse path: a clamped chain of rigid beams is exactly
    // constrained (each beam's six rigid deformations hold the next node's six velocities)
    let auto = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["check", "--json"])
        .arg(&path)
        .output()
        .expect("run flexmbd");
    std::fs::remove_dir_all(&dir).ok();
    assert!(
        auto.status.success(),
        "{}",
        String::from_utf8_lossy(&auto.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&auto.stdout).unwrap();
    assert_eq!(v["rank"], 18000);
    assert_eq!(v["table1_row"], 1);
    assert_eq!(v["sparse"]["certain"], true);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        stderr.contains("18000 x 18000")
            && stderr.contains("limit of 4.0 GiB")
            && stderr.contains("sparse rank-revealing path")
            && stderr.contains("--method sparse"),
        "{stderr}"
    );
}
