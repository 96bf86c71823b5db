//! Bad input to `flexmbd check`: every case exits with code 2, names file, line and item on
//! stderr, and never panics.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// A fresh directory for this test process.
fn temp_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "flexmbd-bad-input-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

/// Write `text` to `dir/name`.
fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write model");
    p
}

mod common;
use common::run;

/// Run `flexmbd check <path> <extra>` and return stderr, asserting exit code 2 and no panic.
#[track_caller]
fn check_fails(path: &Path, extra: &[&str]) -> String {
    let mut args = vec![std::ffi::OsStr::new("check"), path.as_os_str()];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    let out = run(&args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(2),
        "exit code for {}: stderr:\n{stderr}",
        path.display()
    );
    assert!(!stderr.contains("panicked"), "panic:\n{stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    assert!(out.stdout.is_empty(), "nothing on stdout for bad input");
    stderr
}

/// Write the model, run `check`, assert `file:line:` and every one of `parts` are on stderr.
#[track_caller]
fn bad_model(name: &str, text: &str, line: usize, parts: &[&str]) {
    let dir = temp_dir();
    let path = write(&dir, &format!("{name}.toml"), text);
    let stderr = check_fails(&path, &[]);
    let at = format!("{}:{line}:", path.display());
    assert!(stderr.contains(&at), "`{at}` missing in:\n{stderr}");
    for p in parts {
        assert!(stderr.contains(p), "`{p}` missing in:\n{stderr}");
    }
    std::fs::remove_dir_all(dir).ok();
}

const NODES: &str = "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [0.1, 0.0, 0.0]\n";

#[test]
fn unknown_node() {
    bad_model(
        "unknown_node",
        &format!("{NODES}[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tpi\"]\n"),
        4,
        &["element `bar`", "node `tpi` is not defined"],
    );
}

#[test]
fn duplicate_ids() {
    bad_model(
        "duplicate_node",
        &format!("{NODES}tip = [0.2, 0.0, 0.0]\n"),
        4,
        &["node `tip`", "defined twice"],
    );
    bad_model(
        "duplicate_element",
        &format!(
            "{NODES}[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\n\
             [[beam]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\n"
        ),
        7,
        &["element `bar`", "defined twice"],
    );
}

#[test]
fn zero_length_element() {
    bad_model(
        "zero_length",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [0.0, 0.0, 0.0]\n\
         [[beam]]\nid = \"leaf\"\nnodes = [\"base\", \"tip\"]\n",
        4,
        &["element `leaf`", "zero length"],
    );
}

#[test]
fn orientation_parallel_to_axis() {
    bad_model(
        "parallel",
        &format!(
            "{NODES}[[beam]]\nid = \"leaf\"\nnodes = [\"base\", \"tip\"]\norient = [1.0, 0.0, 0.0]\n"
        ),
        4,
        &["element `leaf`", "parallel"],
    );
}

#[test]
fn nan_and_inf() {
    bad_model(
        "nan_node",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [nan, 0.0, 0.0]\n",
        3,
        &["node `tip`", "not finite"],
    );
    bad_model(
        "inf_node",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = { x = [0.0, inf, 0.0] }\n",
        3,
        &["node `tip`", "not finite"],
    );
    bad_model(
        "nan_orient",
        &format!(
            "{NODES}[[beam]]\nid = \"leaf\"\nnodes = [\"base\", \"tip\"]\norient = [0.0, nan, 1.0]\n"
        ),
        4,
        &["element `leaf`", "`orient` must be finite"],
    );
    bad_model(
        "inf_ea",
        &format!("{NODES}[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\nEA = -inf\n"),
        4,
        &["element `bar`", "`EA` must be finite"],
    );
}

#[test]
fn huge_number() {
    // 1e400 is not a TOML float: a parse error, still naming the node
    bad_model(
        "huge",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [1e400, 0.0, 0.0]\n",
        3,
        &["node `tip`", "overflow"],
    );
    bad_model(
        "huge_int",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [99999999999999999999, 0, 0]\n",
        3,
        &["node `tip`"],
    );
}

#[test]
fn unknown_keys() {
    bad_model(
        "unknown_element_key",
        &format!("{NODES}[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\nE = 2.1e11\n"),
        7,
        &["element `bar`", "unknown field `E`"],
    );
    bad_model(
        "unknown_node_key",
        &format!("{NODES}hub = {{ x = [0.0, 0.0, 1.0], rotation = true }}\n"),
        4,
        &["node `hub`", "unknown key `rotation`"],
    );
    bad_model(
        "unknown_section",
        &format!("{NODES}[materials]\nsteel = 2.1e11\n"),
        4,
        &["unknown section `materials`"],
    );
}

#[test]
fn missing_fields() {
    bad_model(
        "missing_nodes",
        &format!("{NODES}[[truss]]\nid = \"bar\"\n"),
        4,
        &["element `bar`", "missing field `nodes`"],
    );
    bad_model(
        "missing_axis",
        &format!("{NODES}[[hinge]]\nid = \"pivot\"\nnodes = [\"base\", \"tip\"]\n"),
        4,
        &["element `pivot`", "missing field `axis`"],
    );
    bad_model(
        "missing_id",
        &format!("{NODES}[[rigid]]\nnodes = [\"base\", \"tip\"]\n"),
        4,
        &["[[rigid]]", "missing field `id`"],
    );
}

#[test]
fn dofs() {
    let truss = format!("{NODES}[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\n");
    bad_model(
        "unknown_dof",
        &format!("{truss}[fix]\nbase = [\"x\", \"phi\"]\n"),
        8,
        &["fix entry `base`", "unknown degree of freedom `phi`"],
    );
    bad_model(
        "rotation_without_rotation",
        &format!("{truss}[inputs]\ntip = [\"rz\"]\n"),
        8,
        &["inputs entry `tip`", "`rz` is a rotation", "rot = true"],
    );
    bad_model(
        "fix_unknown_node",
        &format!("{truss}[fix]\nbsae = \"all\"\n"),
        8,
        &["fix entry `bsae`", "not defined"],
    );
    bad_model(
        "fixed_and_input",
        &format!("{truss}[fix]\nbase = \"all\"\n[inputs]\nbase = [\"x\"]\n"),
        10,
        &["node `base`", "both fixed and an input"],
    );
}

#[test]
fn modes() {
    let beam = format!("{NODES}[[beam]]\nid = \"leaf\"\nnodes = [\"base\", \"tip\"]\n");
    bad_model(
        "mode_out_of_range",
        &format!("{beam}free = [2, 3, 4, 7]\n"),
        4,
        &["element `leaf`", "mode 7 does not exist", "1 to 6"],
    );
    bad_model(
        "mode_zero",
        &format!("{beam}input = [0]\n"),
        4,
        &["element `leaf`", "mode 0 does not exist"],
    );
    bad_model(
        "mode_free_and_input",
        &format!("{beam}free = [2, 3, 4]\ninput = [4]\n"),
        4,
        &["element `leaf`", "mode 4", "both as free and as input"],
    );
}

#[test]
fn wrong_node_count() {
    bad_model(
        "node_count",
        &format!(
            "{NODES}mid = [0.05, 0.0, 0.0]\n[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"mid\", \"tip\"]\n"
        ),
        5,
        &["element `bar`", "a truss needs 2 nodes, found 3"],
    );
    bad_model(
        "rigid_one_node",
        &format!("{NODES}[[rigid]]\nid = \"body\"\nnodes = [\"tip\"]\n"),
        4,
        &["element `body`", "at least 2 nodes, found 1"],
    );
}

#[test]
fn at_unknown_host() {
    bad_model(
        "at_unknown",
        &format!("{NODES}pin = {{ at = \"tipp\" }}\n"),
        4,
        &["node `pin`", "`tipp`", "not defined before it"],
    );
}

#[test]
fn malformed_toml() {
    bad_model(
        "malformed",
        &format!("{NODES}[[truss]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\n"),
        4,
        &["element `bar`", "expected `]`"],
    );
    bad_model(
        "unclosed_array",
        "[nodes]\nbase = [0.0, 0.0, 0.0]\ntip = [0.1, 0.0\n",
        3,
        &["node `tip`"],
    );
}

#[test]
fn missing_file() {
    let dir = temp_dir();
    let path = dir.join("does_not_exist.toml");
    let stderr = check_fails(&path, &[]);
    assert!(stderr.contains("does_not_exist.toml"), "{stderr}");
    assert!(stderr.contains("cannot read the file"), "{stderr}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn wrong_extension() {
    let dir = temp_dir();
    let path = write(&dir, "model.txt", NODES);
    let stderr = check_fails(&path, &[]);
    assert!(stderr.contains("model.txt"), "{stderr}");
    assert!(stderr.contains("expected a .toml file"), "{stderr}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn no_nodes_section() {
    let dir = temp_dir();
    let path = write(&dir, "empty.toml", "[model]\nname = \"nothing\"\n");
    let stderr = check_fails(&path, &[]);
    assert!(stderr.contains("empty.toml: "), "{stderr}");
    assert!(stderr.contains("[nodes]"), "{stderr}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_rank_tol() {
    let dir = temp_dir();
    let path = write(
        &dir,
        "ok.toml",
        &format!(
            "{NODES}[fix]\nbase = \"all\"\n[[truss]]\nid = \"bar\"\nnodes = [\"base\", \"tip\"]\n"
        ),
    );
    // the good model itself passes
    let out = run(&["check".as_ref(), path.as_os_str()]);
    assert_eq!(out.status.code(), Some(0));
    // `--rank-tol -1` (clap usage error) and `--rank-tol=-1` (rejected value) both exit 2
    check_fails(&path, &["--rank-tol", "-1"]);
    for bad in ["--rank-tol=-1", "--rank-tol=nan", "--rank-tol=inf"] {
        let stderr = check_fails(&path, &[bad]);
        assert!(stderr.contains("--rank-tol must be"), "{stderr}");
    }
    std::fs::remove_dir_all(dir).ok();
}
