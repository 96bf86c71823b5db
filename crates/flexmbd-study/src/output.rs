//! The output folder of a study, written as the records arrive and resumable:
//!
//! - `study.json` — the manifest: the study's name, files, fingerprint, parameters, figures of
//!   merit and number of variants;
//! - `records.jsonl` — one JSON record per line, in the order the variants finished, each line
//!   flushed when written (a stopped run loses at most the line being written);
//! - `results.csv` — the same records as a table; rows appended as they arrive, rewritten in
//!   variant order when the run ends;
//! - `plots/` and `study.html` — written at the end ([`crate::plots`]).
//!
//! Opening a folder that holds the records of the same study (same fingerprint) resumes it:
//! the variants with a record are not run again. A folder of another study is refused unless
//! the caller asks to replace it.

use crate::error::StudyError;
use crate::record::{csv_header, merit_names, Record};
use crate::spec::Study;
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The names of the files a study writes (the only ones replacing an output folder removes).
pub const FILES: [&str; 4] = ["study.json", "records.jsonl", "results.csv", "study.html"];

/// An open output folder.
pub struct Outputs {
    dir: PathBuf,
    jsonl: File,
    csv: File,
    /// Every record so far (resumed and new), by variant.
    pub records: BTreeMap<usize, Record>,
}

fn io_err(dir: &Path, what: &str, e: std::io::Error) -> StudyError {
    StudyError::output(dir, format!("cannot write {what}: {e}"))
}

impl Outputs {
    /// Open `dir` for `study` with `total` variants: create it, resume it (same study), or,
    /// with `replace`, clear the study files of an earlier run in it. Returns the folder with
    /// the records it already holds.
    pub fn open(
        dir: &Path,
        study: &Study,
        total: usize,
        replace: bool,
    ) -> Result<Outputs, StudyError> {
        let manifest = dir.join("study.json");
        let fingerprint = study.fingerprint();
        let mut resumed = BTreeMap::new();
        if dir.exists() {
            if !dir.is_dir() {
                return Err(StudyError::output(dir, "exists and is not a folder"));
            }
            let same = std::fs::read_to_string(&manifest)
                .ok()
                .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
                .and_then(|m| {
                    m.get("fingerprint")
                        .and_then(|f| f.as_str())
                        .map(|f| f == fingerprint)
                });
            match same {
                Some(true) if !replace => resumed = read_records(dir, total)?,
                Some(_) if replace => clear(dir)?,
                Some(_) => {
                    return Err(StudyError::output(
                        dir,
                        "holds the results of another study (the study, its model or the program changed); write them elsewhere, or replace them",
                    ))
                }
                None => {
                    let foreign = std::fs::read_dir(dir)
                        .map_err(|e| io_err(dir, "the folder", e))?
                        .filter_map(Result::ok)
                        .any(|e| !FILES.contains(&e.file_name().to_string_lossy().as_ref()) && e.file_name() != "plots");
                    if foreign {
                        return Err(StudyError::output(
                            dir,
                            "exists and holds files that are not a study's results; give a new folder",
                        ));
                    }
                    clear(dir)?;
                }
            }
        } else {
            std::fs::create_dir_all(dir).map_err(|e| io_err(dir, "the folder", e))?;
        }
        let doc = serde_json::json!({
            "name": study.name,
            "study_file": study.file,
            "model_file": study.model_file,
            "fingerprint": fingerprint,
            "variants": total,
            "parameters": study.parameter_names(),
            "merits": merit_names(&study.analyses),
            "flexmbd": env!("CARGO_PKG_VERSION"),
        });
        let text = serde_json::to_string_pretty(&doc).unwrap_or_default() + "\n";
        std::fs::write(&manifest, text).map_err(|e| io_err(dir, "study.json", e))?;
        let jsonl = OpenOptions::new()
            .create(true)
            .append(true)
            .open(dir.join("records.jsonl"))
            .map_err(|e| io_err(dir, "records.jsonl", e))?;
        write_csv(dir, study, &resumed)?;
        let csv = OpenOptions::new()
            .append(true)
            .open(dir.join("results.csv"))
            .map_err(|e| io_err(dir, "results.csv", e))?;
        Ok(Outputs {
            dir: dir.to_path_buf(),
            jsonl,
            csv,
            records: resumed,
        })
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Write a record (JSON line and CSV row, both flushed).
    pub fn write(&mut self, r: Record) -> Result<(), StudyError> {
        let dir = &self.dir;
        writeln!(self.jsonl, "{}", r.to_json_line())
            .and_then(|()| self.jsonl.flush())
            .map_err(|e| io_err(dir, "records.jsonl", e))?;
        writeln!(self.csv, "{}", r.to_csv_row())
            .and_then(|()| self.csv.flush())
            .map_err(|e| io_err(dir, "results.csv", e))?;
        self.records.insert(r.variant, r);
        Ok(())
    }

    /// Rewrite `results.csv` in variant order.
    pub fn finish(&self, study: &Study) -> Result<(), StudyError> {
        write_csv(&self.dir, study, &self.records)
    }
}

/// `results.csv` with these records in variant order (written to a new file, then renamed).
fn write_csv(
    dir: &Path,
    study: &Study,
    records: &BTreeMap<usize, Record>,
) -> Result<(), StudyError> {
    let mut text = csv_header(study) + "\n";
    for r in records.values() {
        text += &r.to_csv_row();
        text.push('\n');
    }
    let tmp = dir.join("results.csv.part");
    std::fs::write(&tmp, text)
        .and_then(|()| std::fs::rename(&tmp, dir.join("results.csv")))
        .map_err(|e| io_err(dir, "results.csv", e))
}

/// The records of `records.jsonl` (the last one kept per variant); a last line cut short by a
/// stop is dropped and the file truncated to the lines before it.
fn read_records(dir: &Path, total: usize) -> Result<BTreeMap<usize, Record>, StudyError> {
    let path = dir.join("records.jsonl");
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(BTreeMap::new()),
        Err(e) => {
            return Err(StudyError::output(
                dir,
                format!("cannot read records.jsonl: {e}"),
            ))
        }
    };
    let mut out = BTreeMap::new();
    let mut good = 0;
    for line in text.split_inclusive('\n') {
        if !line.ends_with('\n') {
            break;
        }
        match serde_json::from_str::<Record>(line.trim_end()) {
            Ok(r) if r.variant < total => {
                out.insert(r.variant, r);
            }
            Ok(_) => {}
            Err(_) if good + line.len() == text.len() => break,
            Err(e) => {
                return Err(StudyError::output(
                    dir,
                    format!(
                    "records.jsonl line {}: not a record ({e}); replace the results to start over",
                    text[..good].matches('\n').count() + 1
                ),
                ))
            }
        }
        good += line.len();
    }
    if good < text.len() {
        let f = OpenOptions::new()
            .write(true)
            .open(&path)
            .map_err(|e| io_err(dir, "records.jsonl", e))?;
        f.set_len(good as u64)
            .map_err(|e| io_err(dir, "records.jsonl", e))?;
    }
    Ok(out)
}

/// Remove the files of a study's earlier run (only those: [`FILES`] and `plots/`).
fn clear(dir: &Path) -> Result<(), StudyError> {
    for f in FILES.iter().chain(&["results.csv.part"]) {
        match std::fs::remove_file(dir.join(f)) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                return Err(StudyError::output(dir, format!("cannot remove {f}: {e}")))
            }
            _ => {}
        }
    }
    crate::plots::clear(&dir.join("plots"))
        .map_err(|e| StudyError::output(dir, format!("cannot remove plots/: {e}")))
}
