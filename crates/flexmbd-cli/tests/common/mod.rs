//! Helpers shared by the command-line tests (each test file is its own crate and includes this
//! module): running the binary, the shipped examples, a fresh temporary folder per test.

#![allow(dead_code)]

use serde_json::Value;
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Run `flexmbd ARGS` in the current folder.
pub fn run<S: AsRef<OsStr>>(args: &[S]) -> Output {
    run_in(None, args)
}

/// Run `flexmbd ARGS` in `dir` (the current folder when `None`).
pub fn run_in<S: AsRef<OsStr>>(dir: Option<&Path>, args: &[S]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flexmbd"));
    if let Some(d) = dir {
        c.current_dir(d);
    }
    c.args(args).output().expect("run flexmbd")
}

/// Run `flexmbd ARGS`; the output and stdout parsed as JSON, when it is JSON.
pub fn run_json<S: AsRef<OsStr>>(args: &[S]) -> (Output, Option<Value>) {
    let out = run(args);
    let json = serde_json::from_slice(&out.stdout).ok();
    (out, json)
}

/// The repository's root folder.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A shipped example model, `examples/NAME`.
pub fn example(name: &str) -> PathBuf {
    root().join("examples").join(name)
}

/// A fresh, empty temporary folder, removed when dropped; its name holds the test's name, the
/// process id and a counter, so that tests running at once never share one.
pub struct Temp(pub PathBuf);

impl Temp {
    /// A new empty folder for `test`.
    pub fn new(test: &str) -> Self {
        static N: AtomicUsize = AtomicUsize::new(0);
        let d = std::env::temp_dir().join(format!(
            "flexmbd-test-{}-{}-{test}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("temp dir");
        Temp(d)
    }
    /// `NAME` in the folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
    /// Copy `src` into the folder as `name`.
    pub fn copy(&self, src: &Path, name: &str) -> PathBuf {
        let p = self.path(name);
        std::fs::copy(src, &p).expect("copy input");
        p
    }
    /// Write `text` into the folder as `name`.
    pub fn write(&self, name: &str, text: &[u8]) -> PathBuf {
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
