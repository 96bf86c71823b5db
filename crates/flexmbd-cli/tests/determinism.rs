//! Bit-identical results for any number of threads (issue 15): every analysis command's output
//! on the shipped examples is byte for byte the same with RAYON_NUM_THREADS = 1 and 2, and the
//! same on a second run. (`check` has its own test in `check_scale.rs`.)

mod common;

use common::example;
use std::process::Command;

/// stdout of `flexmbd ARGS` with `threads` rayon threads; the command must succeed.
fn stdout_with_threads(args: &[&str], threads: &str) -> Vec<u8> {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .arg("--quiet")
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("run flexmbd");
    assert!(
        out.status.success(),
        "flexmbd {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!out.stdout.is_empty(), "flexmbd {args:?}: no output");
    out.stdout
}

#[test]
fn every_command_gives_the_same_bytes_on_one_and_two_threads() {
    let stroke = example("parallel_leaf_stroke.toml");
    let blade = example("rotating_blade.toml");
    let guide = example("paper_dynamic_5_sheets.toml");
    let (stroke, blade, guide) = (
        stroke.to_str().unwrap(),
        blade.to_str().unwrap(),
        guide.to_str().unwrap(),
    );
    let runs: [&[&str]; 6] = [
        &[
            "static",
            stroke,
            "--json",
            "--buckling",
            "2",
            "--compliance",
            "p",
        ],
        &["modes", stroke, "--json", "--count", "6"],
        &["modes", blade, "--json", "--count", "6"],
        &[
            "modes", guide, "--json", "--count", "6", "--solver", "dense",
        ],
        &["sweep", stroke, "--count", "3", "--compliance", "p"],
        &[
            "statespace",
            stroke,
            "--input",
            "p:x",
            "--output",
            "p:x",
            "--json",
        ],
    ];
    for args in runs {
        let one = stdout_with_threads(args, "1");
        let two = stdout_with_threads(args, "2");
        assert!(one == two, "flexmbd {args:?}: 1 and 2 threads differ");
        assert!(
            stdout_with_threads(args, "2") == two,
            "flexmbd {args:?}: two runs differ"
        );
    }
}

/// `simulate` on a chain long enough for the parallel assembly (more than 256 elements).
#[test]
fn simulate_gives_the_same_bytes_on_one_and_two_threads() {
    let dir = common::Temp::new("sim_threads");
    let text = std::fs::read_to_string(example("pendulum.toml"))
        .unwrap()
        .replace("segments = 2", "segments = 300");
    let model = dir.write("chain.toml", text.as_bytes());
    let model = model.to_str().unwrap();
    let args = [
        "simulate",
        model,
        "--json",
        "--t-end",
        "0.02",
        "--dt",
        "1e-3",
        "--output-step",
        "0.01",
    ];
    let one = stdout_with_threads(&args, "1");
    assert_eq!(one, stdout_with_threads(&args, "2"), "1 vs 2 threads");
    assert_eq!(one, stdout_with_threads(&args, "1"), "second run");
}
