//! Regression tests of the reliability findings (issue 15, docs/reliability.md): each input of
//! `tests/reliability/<finding>/` with the exit code and the words of the message (file, line,
//! item). Exit codes: 0 ok, 1 numerical failure, 2 invalid input, 3 not exact with
//! `--require-exact`, 4 a file that cannot be read or written; never a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The folder of a finding's inputs.
fn finding(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/reliability")
        .join(name)
}

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name)
}

/// A fresh folder for one test, removed by [`Temp::drop`].
struct Temp(PathBuf);
impl Temp {
    fn new(test: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let d = std::env::temp_dir().join(format!(
            "flexmbd-reliability-{}-{}-{test}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp dir");
        Temp(d)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    /// Copy `src` into the folder as `name`.
    fn copy(&self, src: &Path, name: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::copy(src, &p).expect("copy input");
        p
    }
    fn write(&self, name: &str, text: &[u8]) -> PathBuf {
        let p = self.path(name);
        std::fs::write(&p, text).expect("write input");
        p
    }
}
impl Drop for Temp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Run flexmbd in `dir` (default: the crate folder).
fn run_in(dir: Option<&Path>, args: &[&str]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexmbd"));
    if let Some(d) = dir {
        c.current_dir(d);
    }
    c.args(args).output().expect("run flexmbd")
}

fn run(args: &[&str]) -> Output {
    run_in(None, args)
}

fn s(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// Assert the exit code, no panic, and that stderr holds every one of `parts`; return stderr.
#[track_caller]
fn expect(out: &Output, code: i32, parts: &[&str]) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert_eq!(
        out.status.code(),
        Some(code),
        "exit code; stderr:\n{stderr}"
    );
    assert!(!stderr.contains("panicked"), "panic:\n{stderr}");
    for p in parts {
        assert!(stderr.contains(p), "`{p}` missing in:\n{stderr}");
    }
    stderr
}

// ---- output safety ----------------------------------------------------------------------------

/// manual_dataloss_convert_same_path: `convert a.dat a.dat` (also `./a.dat`, `../x/a.dat`, a
/// symbolic link, a hard link) is refused and the input is left as it was, with or without
/// `--force`.
#[test]
fn manual_dataloss_convert_same_path() {
    let t = Temp::new("same-path");
    let x = t.path("x");
    std::fs::create_dir_all(&x).unwrap();
    let src = finding("manual_dataloss_convert_same_path/in.dat");
    let a = t.copy(&src, "x/a.dat");
    let original = std::fs::read(&a).unwrap();
    let mut outs = vec!["a.dat", "./a.dat", "../x/a.dat"];
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("a.dat", x.join("link.dat")).unwrap();
        std::os::unix::fs::symlink("a.dat", x.join("link.toml")).unwrap();
        outs.extend(["link.dat", "link.toml"]);
    }
    std::fs::hard_link(&a, x.join("hard.toml")).unwrap();
    outs.push("hard.toml");
    for o in outs {
        for force in [false, true] {
            let mut args = vec!["convert", "a.dat", o];
            if force {
                args.insert(0, "--force");
            }
            let out = run_in(Some(&x), &args);
            expect(&out, 2, &[o, "input file", "never writes over an input"]);
            assert_eq!(std::fs::read(&a).unwrap(), original, "{o}: input changed");
        }
    }
    // the input itself, by another name, in the other commands that write files
    let model = t.copy(&example("strip_f01.toml"), "x/m.toml");
    let m = s(&model);
    for args in [
        vec!["static", m, "--steps", "1", "--csv", m],
        vec!["sweep", m, "--steps", "1", "--csv", m],
        vec!["view", m, "-o", m],
        vec![
            "statespace",
            m,
            "--input",
            "tip:z",
            "--output",
            "tip:z",
            "--m",
            m,
        ],
        vec![
            "statespace",
            m,
            "--input",
            "tip:z",
            "--output",
            "tip:z",
            "--bode",
            m,
        ],
        vec!["export", m, "--analysis", "check", "--vtk", m],
        vec!["export", m, "--analysis", "check", "--plots", m],
    ] {
        let mut forced = vec!["--force"];
        forced.extend(&args);
        for a in [&args, &forced] {
            let out = run(a);
            expect(&out, 2, &["m.toml", "never writes over an input"]);
        }
    }
    assert_eq!(
        std::fs::read(&model).unwrap(),
        std::fs::read(example("strip_f01.toml")).unwrap()
    );
}

/// An existing output file is refused without `--force` and replaced with it.
#[test]
fn existing_output_file_needs_force() {
    let t = Temp::new("force-file");
    let src = finding("manual_dataloss_convert_same_path/in.dat");
    let out_toml = t.path("out.toml");
    let o = s(&out_toml);
    expect(&run(&["convert", s(&src), o]), 0, &[]);
    std::fs::write(&out_toml, "user data\n").unwrap();
    expect(
        &run(&["convert", s(&src), o]),
        2,
        &[o, "exists; use --force to overwrite"],
    );
    assert_eq!(std::fs::read_to_string(&out_toml).unwrap(), "user data\n");
    expect(&run(&["--force", "convert", s(&src), o]), 0, &[]);
    assert!(std::fs::read_to_string(&out_toml)
        .unwrap()
        .contains("[nodes]"));
    // TOML into a file named .dat is refused
    let dat = t.path("out.dat");
    expect(
        &run(&["convert", s(&src), s(&dat)]),
        2,
        &["out.dat", ".toml"],
    );
    // view -o and sweep --csv
    let html = t.write("r.html", b"keep");
    let ex = example("twelve_truss.toml");
    expect(
        &run(&["view", s(&ex), "-o", s(&html)]),
        2,
        &["r.html", "exists; use --force to overwrite"],
    );
    assert_eq!(std::fs::read(&html).unwrap(), b"keep");
    expect(&run(&["--force", "view", s(&ex), "-o", s(&html)]), 0, &[]);
}

/// A shorter run into the same `--csv` / `--vtk` folder left the older step files beside the
/// new ones: the folder is refused without `--force`; with it, flexmbd's own files of the
/// earlier run are removed, and other files are kept.
#[test]
fn stale_output_folders() {
    let t = Temp::new("stale");
    let ex = example("strip_f01.toml");
    let csv = t.path("csv");
    let c = s(&csv);
    expect(
        &run(&["static", s(&ex), "--steps", "4", "--csv", c]),
        0,
        &[],
    );
    assert!(csv.join("step_004.csv").exists());
    std::fs::write(csv.join("notes.txt"), "mine").unwrap();
    std::fs::write(csv.join("step_x.csv"), "mine").unwrap();
    expect(
        &run(&["static", s(&ex), "--steps", "2", "--csv", c]),
        2,
        &[c, "earlier run", "--force"],
    );
    assert!(
        csv.join("step_004.csv").exists(),
        "nothing removed without --force"
    );
    expect(
        &run(&["--force", "static", s(&ex), "--steps", "2", "--csv", c]),
        0,
        &[],
    );
    assert!(csv.join("step_002.csv").exists());
    assert!(!csv.join("step_003.csv").exists(), "stale step file left");
    assert!(!csv.join("step_004.csv").exists(), "stale step file left");
    assert_eq!(
        std::fs::read_to_string(csv.join("notes.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_to_string(csv.join("step_x.csv")).unwrap(),
        "mine"
    );

    let vtk = t.path("vtk");
    let v = s(&vtk);
    let export = |steps: &str, force: bool| {
        let mut a = vec!["export", s(&ex), "--analysis", "static", "--steps", steps];
        a.extend(["--vtk", v]);
        if force {
            a.insert(0, "--force");
        }
        run(&a)
    };
    expect(&export("4", false), 0, &[]);
    assert!(vtk.join("static_0004.vtu").exists());
    expect(&export("2", false), 2, &[v, "earlier run", "--force"]);
    expect(&export("2", true), 0, &[]);
    assert!(vtk.join("static_0002.vtu").exists());
    assert!(
        !vtk.join("static_0003.vtu").exists(),
        "stale step file left"
    );
    // a folder with other files only is used as it is
    let other = t.path("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("README"), "mine").unwrap();
    expect(
        &run(&["static", s(&ex), "--steps", "1", "--csv", s(&other)]),
        0,
        &[],
    );
    assert!(other.join("README").exists() && other.join("summary.csv").exists());
}

/// An output that cannot be written is an I/O failure: exit 4 (1 is a numerical failure).
#[test]
fn io_failure_exits_4() {
    let t = Temp::new("io");
    let src = finding("manual_dataloss_convert_same_path/in.dat");
    let missing = t.path("no/such/folder/out.toml");
    expect(
        &run(&["convert", s(&src), s(&missing)]),
        4,
        &["cannot write", "out.toml"],
    );
    // a file where the CSV folder should be created
    let file = t.write("file", b"x");
    let below = file.join("csv");
    expect(
        &run(&[
            "static",
            s(&example("strip_f01.toml")),
            "--steps",
            "1",
            "--csv",
            s(&below),
        ]),
        4,
        &["file"],
    );
}

/// `flexmbd --help` documents the exit codes.
#[test]
fn help_lists_exit_codes() {
    let out = run(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for p in [
        "Exit codes",
        "1 numerical failure",
        "2 invalid input",
        "3 `check --require-exact`",
        "4 a file",
        "--force",
    ] {
        assert!(text.contains(p), "`{p}` missing in:\n{text}");
    }
}
