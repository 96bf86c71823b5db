//! Output safety (docs/reliability.md): no output path may be an input file, an existing output
//! file is replaced only with `--force`, and an output folder that holds files of an earlier run
//! (flexmbd's own file-name patterns) is cleared of them only with `--force`.

use crate::BadInput;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

static FORCE: AtomicBool = AtomicBool::new(false);

/// Set by the global `--force` flag.
pub fn set_force(force: bool) {
    FORCE.store(force, Ordering::Relaxed);
}

fn force() -> bool {
    FORCE.load(Ordering::Relaxed)
}

/// Whether the global `--force` was given.
pub fn forced() -> bool {
    force()
}

/// A failure to read or write a file or stream that is not the user's input: exit code 4.
#[derive(Debug)]
pub struct IoFailure(pub String);
impl std::fmt::Display for IoFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for IoFailure {}

/// Whether `a` and `b` name the same existing file (through `.`/`..`, symbolic links or hard
/// links).
pub fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if (ma.dev(), ma.ino()) == (mb.dev(), mb.ino()) {
            return true;
        }
    }
    let _ = (ma, mb);
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(ca), Ok(cb)) => ca == cb,
        _ => false,
    }
}

/// Refuse an output path that is one of the input files.
fn not_an_input(out: &Path, what: &str, inputs: &[&Path]) -> Result<(), BadInput> {
    for input in inputs {
        if same_file(out, input) {
            return Err(BadInput(format!(
                "{what} {}: this is the input file {}; flexmbd never writes over an input",
                out.display(),
                input.display()
            )));
        }
    }
    Ok(())
}

/// Check an output FILE before the analysis runs: not an input, and not existing unless
/// `--force` is given. `what` names the option (`--bode`, `-o`, `OUTPUT`).
pub fn check_file(out: &Path, what: &str, inputs: &[&Path]) -> Result<(), BadInput> {
    not_an_input(out, what, inputs)?;
    // a folder is left to the write, which fails with an I/O error (exit 4)
    match std::fs::metadata(out) {
        Ok(m) if !m.is_dir() && !force() => Err(BadInput(format!(
            "{what} {}: the file exists; use --force to overwrite",
            out.display()
        ))),
        _ => Ok(()),
    }
}

/// A file name flexmbd writes into an output folder: `prefix` + digits + `suffix`
/// (`digits: true`), or `prefix` + anything + `suffix` (a plot stem).
#[derive(Clone, Copy, Debug)]
pub struct Pattern {
    /// Start of the name.
    pub prefix: &'static str,
    /// What comes between: digits only, or anything.
    pub digits: bool,
    /// End of the name.
    pub suffix: &'static str,
}

impl Pattern {
    /// A fixed name.
    pub const fn exact(name: &'static str) -> Self {
        Pattern {
            prefix: name,
            digits: true,
            suffix: "",
        }
    }
    /// `prefix` + digits + `suffix`.
    pub const fn numbered(prefix: &'static str, suffix: &'static str) -> Self {
        Pattern {
            prefix,
            digits: true,
            suffix,
        }
    }
    /// `prefix` + any text + `suffix`.
    pub const fn any(prefix: &'static str, suffix: &'static str) -> Self {
        Pattern {
            prefix,
            digits: false,
            suffix,
        }
    }

    fn matches(&self, name: &str) -> bool {
        let Some(mid) = name
            .strip_prefix(self.prefix)
            .and_then(|r| r.strip_suffix(self.suffix))
        else {
            return false;
        };
        if self.digits {
            mid.bytes().all(|b| b.is_ascii_digit())
        } else {
            !mid.is_empty()
        }
    }
}

/// The files of `static --csv DIR`.
pub const STATIC_CSV: &[Pattern] = &[
    Pattern::exact("summary.csv"),
    Pattern::numbered("step_", ".csv"),
];
/// The files of `export --vtk DIR`.
pub const EXPORT_VTK: &[Pattern] = &[
    Pattern::exact("check.vtu"),
    Pattern::numbered("static_", ".vtu"),
    Pattern::exact("static.pvd"),
    Pattern::numbered("mode_", ".vtu"),
    Pattern::exact("modes.pvd"),
];
/// The files of `export --plots DIR`.
pub const EXPORT_PLOTS: &[Pattern] = &[
    Pattern::exact("singular_values.png"),
    Pattern::exact("singular_values.svg"),
    Pattern::exact("force_stroke.png"),
    Pattern::exact("force_stroke.svg"),
    Pattern::exact("frequency_stroke.png"),
    Pattern::exact("frequency_stroke.svg"),
    Pattern::any("stiffness_", ".png"),
    Pattern::any("stiffness_", ".svg"),
];

/// The files in `dir` that match one of `patterns` (regular files only), sorted.
fn own_files(dir: &Path, patterns: &[Pattern]) -> std::io::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        if entry.file_type()?.is_file() && patterns.iter().any(|p| p.matches(name)) {
            out.push(entry.path());
        }
    }
    out.sort();
    Ok(out)
}

/// Check an output FOLDER before the analysis runs: not an input, not a file, and without
/// files of an earlier run unless `--force` is given.
pub fn check_dir(
    dir: &Path,
    what: &str,
    patterns: &[Pattern],
    inputs: &[&Path],
) -> Result<(), anyhow::Error> {
    not_an_input(dir, what, inputs)?;
    match std::fs::metadata(dir) {
        Err(_) => return Ok(()),
        Ok(m) if !m.is_dir() => {
            return Err(
                BadInput(format!("{what} {}: is a file, not a folder", dir.display())).into(),
            )
        }
        Ok(_) => {}
    }
    let old = own_files(dir, patterns).map_err(|e| {
        IoFailure(format!(
            "{what} {}: cannot list the folder: {e}",
            dir.display()
        ))
    })?;
    if let (Some(first), false) = (old.first(), force()) {
        return Err(BadInput(format!(
            "{what} {}: the folder holds {} file(s) of an earlier run (e.g. {}); use --force to replace them",
            dir.display(),
            old.len(),
            first.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        ))
        .into());
    }
    Ok(())
}

/// Create an output folder and, with `--force`, remove the files of an earlier run (only names
/// of `patterns`, never an input file), right before the new files are written.
pub fn prepare_dir(
    dir: &Path,
    what: &str,
    patterns: &[Pattern],
    inputs: &[&Path],
) -> Result<(), anyhow::Error> {
    check_dir(dir, what, patterns, inputs)?;
    std::fs::create_dir_all(dir)
        .map_err(|e| IoFailure(format!("cannot create folder {}: {e}", dir.display())))?;
    let old = own_files(dir, patterns).map_err(|e| {
        IoFailure(format!(
            "{what} {}: cannot list the folder: {e}",
            dir.display()
        ))
    })?;
    for f in old {
        not_an_input(&f, what, inputs)?;
        std::fs::remove_file(&f).map_err(|e| {
            IoFailure(format!(
                "cannot remove the earlier output {}: {e}",
                f.display()
            ))
        })?;
    }
    Ok(())
}

/// Write an output file (checked before by [`check_file`]); a failure is an [`IoFailure`].
///
/// The text goes to a temporary file beside the target first, which then replaces it: a write
/// that fails (a full disk) leaves an existing file as it was. A symbolic link is written
/// through (its target is replaced).
pub fn write_file(path: &Path, text: &str) -> Result<(), IoFailure> {
    let fail = |e: std::io::Error| IoFailure(format!("cannot write {}: {e}", path.display()));
    let target = match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path).map_err(fail)?,
        _ => path.to_path_buf(),
    };
    let Some(name) = target.file_name() else {
        return std::fs::write(path, text).map_err(fail);
    };
    let tmp = target.with_file_name(format!(
        ".{}.flexmbd-{}.tmp",
        name.to_string_lossy(),
        std::process::id()
    ));
    let written = std::fs::write(&tmp, text).and_then(|()| std::fs::rename(&tmp, &target));
    if let Err(e) = written {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(e));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns() {
        assert!(Pattern::numbered("step_", ".csv").matches("step_003.csv"));
        assert!(!Pattern::numbered("step_", ".csv").matches("step_x.csv"));
        assert!(Pattern::exact("summary.csv").matches("summary.csv"));
        assert!(!Pattern::exact("summary.csv").matches("summary.csv.bak"));
        assert!(Pattern::any("stiffness_", ".png").matches("stiffness_tip.png"));
        assert!(!Pattern::any("stiffness_", ".png").matches("stiffness_.png"));
    }
}
