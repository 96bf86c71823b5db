//! Design studies from Python (`flexmbd.study`, docs/studies.md): the study as one JSON
//! document (the model's text inside, so it pickles and travels to Dask workers), its
//! variants, the evaluation of a batch of variants on one thread (a Dask task), the local run
//! on all cores, and the output folder written as records arrive. Every record is the JSON
//! line of `flexmbd_study::Record`, the same text the command line writes.

use crate::errors::{self, Failure};
use flexmbd_study::{Outputs, Record, Study, StudyError, Variant};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;

fn study_failure(e: StudyError) -> Failure {
    match e {
        StudyError::Input(e) => errors::input(e),
        StudyError::Output { .. } => Failure::option("out", e.to_string()),
    }
}

fn parse_doc(doc: &str) -> Result<Study, Failure> {
    serde_json::from_str(doc).map_err(|e| {
        Failure::option(
            "study",
            format!("not a study document of this flexmbd version: {e}"),
        )
    })
}

fn parse_lines(lines: &[String]) -> Result<Vec<Record>, Failure> {
    lines
        .iter()
        .map(|l| {
            serde_json::from_str(l)
                .map_err(|e| Failure::option("records", format!("not a study record: {e}")))
        })
        .collect()
}

/// Read a study file (and its model file): the study document as JSON.
#[pyfunction]
pub fn study_read(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    py.detach(move || {
        let s = Study::read(&path).map_err(study_failure)?;
        serde_json::to_string(&s).map_err(|e| Failure::option("study", e.to_string()))
    })
    .map_err(|f: Failure| f.into_py(py))
}

/// The variants of a study document: (index, parameter values) in index order.
#[pyfunction]
pub fn study_variants(py: Python<'_>, doc: &str) -> PyResult<Vec<(usize, Vec<f64>)>> {
    let s = parse_doc(doc).map_err(|f| f.into_py(py))?;
    Ok(flexmbd_study::variants(&s)
        .into_iter()
        .map(|v| (v.index, v.values))
        .collect())
}

/// Evaluate a batch of variants one after the other, each on one thread (the task of a Dask
/// worker): their records as JSON lines, in the batch's order.
#[pyfunction]
pub fn study_evaluate(
    py: Python<'_>,
    doc: &str,
    batch: Vec<(usize, Vec<f64>)>,
) -> PyResult<Vec<String>> {
    let s = parse_doc(doc).map_err(|f| f.into_py(py))?;
    for (i, values) in &batch {
        if values.len() != s.parameters.len() {
            return Err(Failure::option(
                "batch",
                format!(
                    "variant {i}: {} values for {} parameters",
                    values.len(),
                    s.parameters.len()
                ),
            )
            .into_py(py));
        }
    }
    Ok(py.detach(move || {
        batch
            .into_iter()
            .map(|(index, values)| {
                flexmbd_study::evaluate_isolated(&s, &Variant { index, values }).to_json_line()
            })
            .collect()
    }))
}

/// The output folder of a study, written as records arrive (`records.jsonl`, `results.csv`)
/// and finished with the plots and the HTML page; opening the folder of an unfinished run of
/// the same study resumes it.
#[pyclass(module = "flexmbd._flexmbd", name = "StudyOutputs")]
pub struct StudyOutputs {
    study: Study,
    total: usize,
    out: Mutex<Outputs>,
}

impl StudyOutputs {
    /// The folder, for one writer at a time (a writer that panicked leaves it unusable).
    fn lock(&self) -> Result<std::sync::MutexGuard<'_, Outputs>, Failure> {
        self.out
            .lock()
            .map_err(|_| Failure::new(errors::Kind::Numerical, "the output folder is unusable"))
    }
}

#[pymethods]
impl StudyOutputs {
    /// Open (create, resume, or with `replace` start over) the folder `out` of a study.
    #[new]
    fn new(py: Python<'_>, doc: &str, out: PathBuf, replace: bool) -> PyResult<Self> {
        let study = parse_doc(doc).map_err(|f| f.into_py(py))?;
        let total = flexmbd_study::variants(&study).len();
        let o = Outputs::open(&out, &study, total, replace)
            .map_err(|e| study_failure(e).into_py(py))?;
        Ok(StudyOutputs {
            study,
            total,
            out: Mutex::new(o),
        })
    }

    /// The indices of the variants the folder has records of.
    fn done(&self) -> Vec<usize> {
        self.out
            .lock()
            .map(|o| o.records.keys().copied().collect())
            .unwrap_or_default()
    }

    /// Write records (JSON lines) as they arrive.
    fn write(&self, py: Python<'_>, lines: Vec<String>) -> PyResult<()> {
        let records = parse_lines(&lines).map_err(|f| f.into_py(py))?;
        let mut o = self.lock().map_err(|f| f.into_py(py))?;
        for r in records {
            o.write(r).map_err(|e| study_failure(e).into_py(py))?;
        }
        Ok(())
    }

    /// Rewrite results.csv in variant order and, with `plots`, draw the plots and the page;
    /// returns every record of the folder (JSON lines, in variant order).
    fn finish(&self, py: Python<'_>, plots: bool) -> PyResult<Vec<String>> {
        let o = self.lock().map_err(|f| f.into_py(py))?;
        o.finish(&self.study)
            .map_err(|e| study_failure(e).into_py(py))?;
        if plots {
            flexmbd_study::plots::write_plots(o.dir(), &self.study, &o.records)
                .and_then(|_| {
                    flexmbd_study::plots::write_html(o.dir(), &self.study, &o.records, self.total)
                })
                .map_err(|m| Failure::new(errors::Kind::Read, m).into_py(py))?;
        }
        Ok(o.records.values().map(Record::to_json_line).collect())
    }
}

/// Run the variants not yet in `outputs` (or all, without outputs) on `jobs` threads (0: one
/// per core), each variant on one thread: the new records as JSON lines in the order they
/// finished; with `outputs`, each written as it arrives.
#[pyfunction]
#[pyo3(signature = (doc, jobs=0, outputs=None))]
pub fn study_run(
    py: Python<'_>,
    doc: &str,
    jobs: usize,
    outputs: Option<&StudyOutputs>,
) -> PyResult<Vec<String>> {
    let s = parse_doc(doc).map_err(|f| f.into_py(py))?;
    let done = outputs.map(|o| o.done()).unwrap_or_default();
    let todo: Vec<Variant> = flexmbd_study::variants(&s)
        .into_iter()
        .filter(|v| !done.contains(&v.index))
        .collect();
    let r = py.detach(|| -> Result<Vec<String>, Failure> {
        let mut lines = Vec::new();
        let mut failure = None;
        flexmbd_study::run(&s, &todo, jobs, |r| {
            if let Some(o) = outputs {
                let written = o
                    .lock()
                    .and_then(|mut o| o.write(r.clone()).map_err(study_failure));
                if let Err(f) = written {
                    failure.get_or_insert(f);
                    return false;
                }
            }
            lines.push(r.to_json_line());
            true
        });
        match failure {
            Some(f) => Err(f),
            None => Ok(lines),
        }
    });
    r.map_err(|f| f.into_py(py))
}
