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

/// Runs `flexmbd ARGS FINDING/in.toml --quiet`: (exit code, stdout, stderr).
fn run_out(args: &[&str], finding: &str) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(args)
        .arg(input(finding))
        .arg("--quiet")
        .output()
        .expect("run flexmbd");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// [`run_out`] without stdout: (exit code, stderr).
fn run(args: &[&str], finding: &str) -> (Option<i32>, String) {
    let (code, _, err) = run_out(args, finding);
    (code, err)
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

#[test]
fn manual_nan_modes_massless_mechanism() {
    // trusses a-b-c along x, a fixed, a mass on c only: b's transverse directions have neither
    // stiffness nor inertia. Before, the dense path printed NaN frequencies with exit 0; now
    // both paths say what the sparse one said
    let f = "manual_nan_modes_massless_mechanism";
    for args in [
        &["modes"][..],
        &["modes", "--solver", "dense"][..],
        &["modes", "--solver", "sparse"][..],
        &["sweep"][..],
        &["statespace", "--input", "c:x", "--output", "c:x"][..],
    ] {
        let (code, out, err) = run_out(args, f);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(
            err.contains("massless coordinates form a mechanism") && err.contains(": b."),
            "{args:?}: {err}"
        );
        assert!(
            !out.contains("NaN") && !err.contains("panicked"),
            "{args:?}: {out}"
        );
    }
}

#[test]
fn manual_nan_static_huge_coordinate() {
    // a node at x = 1e200 m: every energy was NaN (null in JSON) with exit 0
    for f in ["manual_nan_static_huge_coordinate", "nan_static_d89c023de4"] {
        for args in [&["static"][..], &["static", "--json"][..]] {
            let (code, out, err) = run_out(args, f);
            assert_eq!(code, Some(1), "{f} {args:?}: {err}");
            assert!(
                err.contains("is not finite")
                    && err.contains("step 0")
                    && err.contains("overflow double precision")
                    && err.contains("no state of the path is finite"),
                "{f} {args:?}: {err}"
            );
            assert!(!out.contains("NaN") && !out.contains("null"), "{f}: {out}");
        }
    }
}

#[test]
fn manual_wrong_modes_free_floating() {
    // an unloaded free–free strip (L = 0.1 m, t = 0.5 mm, steel): six rigid-body modes, then the
    // first bending mode, βL = 4.730041: f = (βL)² sqrt(E t² / (12 ρ L⁴)) / (2π) = 260.25 Hz
    // (3 elements: within 1 %); no instability warning
    let f = "manual_wrong_modes_free_floating";
    let (code, out, err) = run_out(&["modes", "--count", "8"], f);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(out.matches("rigid-body mode").count(), 6, "{out}");
    assert!(
        !out.contains("complex") && !out.contains("warning"),
        "{out}"
    );
    let (code, out, err) = run_out(&["modes", "--count", "8", "--json"], f);
    assert_eq!(code, Some(0), "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    let modes = v["modes"].as_array().expect("modes");
    for (k, m) in modes.iter().enumerate() {
        assert_eq!(m["rigid_body"], serde_json::json!(k < 6), "mode {k}: {m}");
    }
    for m in &modes[..6] {
        assert_eq!(m["frequency_hz"], serde_json::json!(0.0));
    }
    let c = (200e9 * 0.0005f64.powi(2) / (12.0 * 7800.0 * 0.1f64.powi(4))).sqrt();
    let want = 4.730041f64.powi(2) * c / (2.0 * std::f64::consts::PI);
    let got = modes[6]["frequency_hz"].as_f64().expect("frequency");
    assert!((got - want).abs() < 1e-2 * want, "{got} vs {want}");
    // six modes or fewer, all of them rigid-body modes: the sparse solver sees no elastic mode
    // to compare with (before, it printed six tiny frequencies), and a sweep of six frequencies
    // (before, the dense solver's six were judged without the seventh: 'complex', a warning)
    for args in [
        &["modes", "--count", "6", "--solver", "sparse"][..],
        &["modes", "--count", "3", "--solver", "sparse"][..],
    ] {
        let (code, out, err) = run_out(args, f);
        assert_eq!(code, Some(0), "{err}");
        let n: usize = args[2].parse().expect("count");
        assert_eq!(out.matches("rigid-body mode").count(), n, "{args:?}: {out}");
    }
    for solver in ["dense", "sparse"] {
        let (code, out, err) = run_out(&["sweep", "--count", "6", "--solver", solver], f);
        assert_eq!(code, Some(0), "{err}");
        assert!(
            !out.contains("complex") && !out.contains("warning"),
            "{solver}: {out}"
        );
        let row = out
            .lines()
            .find(|l| l.starts_with("  10 "))
            .expect("step 10");
        assert_eq!(row.matches(" 0.000000").count(), 6, "{solver}: {row}");
    }
}

#[test]
fn manual_wrong_static_inverted_column() {
    // a 0.1 m steel strip under a 1e7 N compressive tip load (Euler load about 10 N): before, the
    // tip passed through the root to z = -0.6 m and the state was reported stable in tension
    let f = "manual_wrong_static_inverted_column";
    for args in [
        &["static", "--buckling", "1", "--steps", "4"][..],
        &["static"][..],
    ] {
        let (code, out, err) = run_out(args, f);
        assert_eq!(code, Some(1), "{args:?}: {err}\n{out}");
        assert!(
            err.contains("inverted")
                && err.contains("element `b")
                && err.contains("load factor")
                && err.contains("displacement control"),
            "{args:?}: {err}"
        );
        assert!(err.contains("--steps"), "{err}");
    }
}

#[test]
fn manual_wrong_compliance_stiffness_ratio() {
    // E = 0.2 Pa in series with 200 GPa (ratio 1e12): the support stiffness came out with the
    // wrong sign and 'UNSTABLE' under a 1e-14 N load, without a word on the conditioning
    let f = "manual_wrong_compliance_stiffness_ratio";
    let (code, out, err) = run_out(&["static", "--compliance", "tip", "--buckling", "1"], f);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.contains("ill-conditioned"), "{out}");
    let (code, out, _) = run_out(
        &["static", "--compliance", "tip", "--buckling", "1", "--json"],
        f,
    );
    assert_eq!(code, Some(0));
    let v: serde_json::Value = serde_json::from_str(&out).expect("JSON");
    assert!(v.to_string().contains("ill-conditioned"), "{v}");
    // the same strip of one material is well conditioned: no warning
    let text = std::fs::read_to_string(input(f)).expect("read");
    let same = text.replace("E = 0.2\n", "E = 200e9\n");
    assert_ne!(same, text);
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("one_material.toml");
    std::fs::write(&p, same).expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args([
            "static",
            "--compliance",
            "tip",
            "--buckling",
            "1",
            "--quiet",
        ])
        .arg(&p)
        .output()
        .expect("run flexmbd");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        !text.contains("ill-conditioned") && !text.contains("UNSTABLE"),
        "{text}"
    );
}

#[test]
fn dense_paths_refuse_models_above_the_memory_limit() {
    // the F01 strip in 1200 beams: 1200 free nodes of 6 velocity components, 7200 degrees of
    // freedom, whose dense modal analysis, state space and linearisation need more than the
    // default 4 GiB; each is refused before the static solve (exit 1), and the hint names the
    // sparse solver where there is one. (The automatic choice takes the sparse path for a few
    // lowest modes, the dense one for more than a third of them: dynamics::auto_solver; its
    // refusal is `automatic_choice_refuses_most_modes_of_a_large_model`.)
    let p = strip_1200("strip_1200.toml");
    for (args, what, hint) in [
        (
            &["modes", "--solver", "dense"][..],
            "dense modal analysis (all modes) of this model (7200 degrees of freedom)",
            "--solver sparse",
        ),
        (
            &["sweep", "--solver", "dense"][..],
            "dense modal analysis",
            "--solver sparse",
        ),
        (
            &[
                "statespace",
                "--solver",
                "dense",
                "--input",
                "tip:z",
                "--output",
                "tip:z",
            ][..],
            "dense state space (all modes) of this model (7200 degrees of freedom)",
            "--solver sparse (or auto) with --modes N",
        ),
        (
            &["static", "--compliance", "tip"][..],
            "dense linearisation (compliance, buckling, stability)",
            "leave out --compliance and --buckling",
        ),
        (
            &["sweep", "--compliance", "tip"][..],
            "dense linearisation",
            "leave out --compliance",
        ),
    ] {
        let t = std::time::Instant::now();
        let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
            .args(args)
            .arg(&p)
            .arg("--quiet")
            .output()
            .expect("run flexmbd");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(what) && err.contains("above the limit of 4.0 GiB"),
            "{args:?}: {err}"
        );
        assert!(
            err.lines()
                .any(|l| l.starts_with("hint: ") && l.contains(hint)),
            "{args:?}: {err}"
        );
        assert!(out.stdout.is_empty(), "{args:?}");
        // refused before the static solve and before any dense matrix
        assert!(
            t.elapsed().as_secs_f64() < 10.0,
            "{args:?}: {:?}",
            t.elapsed()
        );
    }
}

#[test]
fn automatic_choice_refuses_most_modes_of_a_large_model() {
    // the F01 strip in 1200 beams (7200 degrees of freedom): 5000 modes are more than a third
    // of them, which the automatic choice computes densely, but the dense matrices exceed the
    // default 4 GiB; refused at once (exit 1) with the remedy: fewer modes or an explicit solver
    let p = strip_1200("strip_1200_many.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_flexmbd"))
        .args(["modes", "--count", "5000"])
        .arg(&p)
        .arg("--quiet")
        .output()
        .expect("run flexmbd");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("5000 modes of a model with 7200 degrees of freedom"),
        "{err}"
    );
    assert!(
        err.lines()
            .any(|l| l.starts_with("hint: ") && l.contains("--count") && l.contains("--solver")),
        "{err}"
    );
    assert!(out.stdout.is_empty());
}

/// The F01 strip in 1200 beams (7200 degrees of freedom), written as `name` in the test's
/// temporary folder.
fn strip_1200(name: &str) -> PathBuf {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/strip_f01.toml"),
    )
    .expect("read");
    let big = text.replace("segments = 10\n", "segments = 1200\n");
    assert_ne!(big, text);
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&p, big).expect("write");
    p
}
