//! Numerical reliability through the binary (issue 15): inputs found by fuzzing that made an
//! analysis panic. Each input is kept in `tests/reliability/<finding>/` (the finding's name);
//! the command must end with exit 1 (numerical failure), a message that says what is not
//! finite, and no panic.

use std::path::PathBuf;
use std::process::Command;

fn input(finding: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reliability")
        .join(finding)
        .join("in.toml")
}

/// Runs flexmbd and returns (exit code, stderr).
fn run(args: &[&str], finding: &str) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .arg(input(finding))
        .arg("--quiet")
        .output()
        .expect("run flexmbd");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn huge_coordinates_are_a_numerical_failure_not_a_panic() {
    // a node at x = 1e200 m: the Jacobians overflow; before, `expect("finite")` panicked
    // (exit 101) in modes, sweep and statespace
    for finding in [
        "manual_panic_modes_huge_coordinate",
        "panic_modes_8243391383",
    ] {
        for args in [
            &["modes", "--count", "3"][..],
            &["sweep", "--count", "2"][..],
        ] {
            let (code, err) = run(args, finding);
            assert_eq!(code, Some(1), "{finding} {args:?}: {err}");
            assert!(!err.contains("panicked"), "{finding} {args:?}: {err}");
            assert!(
                err.contains("not finite") && err.contains("node positions"),
                "{finding} {args:?}: {err}"
            );
        }
    }
    let (code, err) = run(
        &["statespace", "--input", "tip:z", "--output", "tip:z"],
        "manual_panic_modes_huge_coordinate",
    );
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("not finite"), "{err}");
}
