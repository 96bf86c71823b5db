//! `flexmbd study` through the binary: the output folder, the list of variants, a run resumed,
//! the folder of another study refused, and the exit codes of bad input. The figures of merit
//! are tested in the library (crates/flexmbd-study/tests/study.rs).

mod common;
use common::{example, run, run_in, Temp};

const STUDY: &str = r#"
[study]
name = "strip thickness"
model = "strip.toml"
analyses = ["check", "modes"]
modes = 3
[parameters]
"sections.strip.t" = { from = 0.2e-3, to = 0.6e-3, count = 3 }
"#;

fn setup(t: &Temp) -> std::path::PathBuf {
    t.copy(&example("strip_f01.toml"), "strip.toml");
    t.write("strip_study.toml", STUDY.as_bytes())
}

#[test]
fn a_study_writes_its_records_table_plots_and_page() {
    let t = Temp::new("study-run");
    let s = setup(&t);
    let out = run_in(
        Some(&t.0),
        &["--quiet".as_ref(), "study".as_ref(), s.as_os_str()],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("3 variants, 3 complete, 0 failed"), "{text}");
    let dir = t.path("strip_study_results");
    for f in ["study.json", "records.jsonl", "results.csv", "study.html"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("results.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 4);
    assert!(lines[0].starts_with("variant,sections.strip.t,status,table1_row"));
    assert!(lines[1].starts_with("0,0.0002,ok,"), "{}", lines[1]);
    assert_eq!(
        std::fs::read_to_string(dir.join("records.jsonl"))
            .unwrap()
            .lines()
            .count(),
        3
    );
    assert!(dir.join("plots/f1_vs_sections_strip_t.png").is_file());
    assert!(dir.join("plots/f1_vs_sections_strip_t.svg").is_file());
    let html = std::fs::read_to_string(dir.join("study.html")).unwrap();
    assert!(html.contains("<svg") && html.contains("strip thickness"));

    // run again: nothing left to run, the same records
    let again = run_in(Some(&t.0), &["study".as_ref(), s.as_os_str()]);
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stderr).contains("3 of 3 variants done, 0 to run"));
    assert_eq!(
        std::fs::read_to_string(dir.join("results.csv")).unwrap(),
        csv
    );
    // another study in the same folder is refused (exit 4), and replaced with --force
    let other = t.write(
        "strip_study2.toml",
        STUDY.replace("modes = 3", "modes = 2").as_bytes(),
    );
    let args = |force: bool| {
        let mut a: Vec<std::ffi::OsString> = vec!["study".into(), other.clone().into()];
        a.extend(["--out".into(), dir.clone().into_os_string()]);
        if force {
            a.insert(0, "--force".into());
        }
        a
    };
    let refused = run(&args(false));
    assert_eq!(refused.status.code(), Some(4));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("another study"));
    let replaced = run(&args(true));
    assert!(
        replaced.status.success(),
        "{}",
        String::from_utf8_lossy(&replaced.stderr)
    );
}

#[test]
fn list_prints_the_variants_without_running_them() {
    let t = Temp::new("study-list");
    let s = setup(&t);
    let out = run_in(
        Some(&t.0),
        &["study".as_ref(), s.as_os_str(), "--list".as_ref()],
    );
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with("3 variants of"), "{text}");
    assert!(text.contains("\n2  0.0006\n"), "{text}");
    assert!(!t.path("strip_study_results").exists());
}

#[test]
fn a_bad_study_file_is_invalid_input_with_its_line() {
    let t = Temp::new("study-bad");
    t.copy(&example("strip_f01.toml"), "strip.toml");
    let s = t.write(
        "bad.toml",
        STUDY.replace("count = 3", "count = 3, step = 1").as_bytes(),
    );
    let out = run(&["study".as_ref(), s.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml:8:"), "{err}");
    assert!(err.contains("step"), "{err}");
    let zero = run(&[
        "study".as_ref(),
        s.as_os_str(),
        "--jobs".as_ref(),
        "0".as_ref(),
    ]);
    assert_eq!(zero.status.code(), Some(2));
}
