//! `flexmbd study STUDY.toml`: the variants of a parametric model on all cores, their figures of
//! merit written as they arrive (docs/studies.md). Not to be confused with `sweep`, the
//! frequencies and stiffness along the load steps of ONE model.

use crate::{progress, BadInput};
use flexmbd_study::{Outputs, Status, Study, StudyError};
use std::path::PathBuf;
use std::process::ExitCode;

/// `flexmbd study`.
#[derive(clap::Args)]
pub struct StudyArgs {
    /// Study file (.toml): the model, its parameters and how they vary, the analyses.
    study: PathBuf,
    /// Output folder (default: STUDY_results in the current folder). A folder holding an
    /// unfinished run of the same study is resumed; with --force it is started over.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Worker threads (default: one per core); each variant runs on one thread.
    #[arg(long, value_name = "N")]
    jobs: Option<usize>,
    /// Print the variants (index and parameter values) and stop, without running them.
    #[arg(long)]
    list: bool,
    /// Do not draw the plots and the HTML page at the end.
    #[arg(long)]
    no_plots: bool,
}

fn study_err(e: StudyError) -> anyhow::Error {
    if e.is_input() {
        BadInput(e.to_string()).into()
    } else {
        anyhow::Error::new(crate::outputs::IoFailure(e.to_string()))
    }
}

/// Run `flexmbd study`.
pub fn run(args: StudyArgs) -> anyhow::Result<ExitCode> {
    if args.jobs == Some(0) {
        return Err(BadInput("--jobs must be at least 1".into()).into());
    }
    let study = Study::read(&args.study).map_err(study_err)?;
    let variants = flexmbd_study::variants(&study);
    if args.list {
        let mut t = format!("{} variants of {}\nvariant", variants.len(), study.file);
        for p in study.parameter_names() {
            t += &format!("  {p}");
        }
        t.push('\n');
        for v in &variants {
            t += &v.index.to_string();
            for x in &v.values {
                t += &format!("  {x}");
            }
            t.push('\n');
        }
        crate::emit(&t)?;
        return Ok(ExitCode::SUCCESS);
    }
    let dir = args.out.clone().unwrap_or_else(|| {
        let stem = args
            .study
            .file_stem()
            .map_or("study".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}_results"))
    });
    let mut out =
        Outputs::open(&dir, &study, variants.len(), crate::outputs::forced()).map_err(study_err)?;
    let resumed = out.records.len();
    let todo: Vec<_> = variants
        .iter()
        .filter(|v| !out.records.contains_key(&v.index))
        .cloned()
        .collect();
    let jobs = flexmbd_study::workers(args.jobs.unwrap_or(0), todo.len());
    if resumed > 0 {
        eprintln!(
            "resuming {}: {resumed} of {} variants done, {} to run",
            dir.display(),
            variants.len(),
            todo.len()
        );
    }
    let bar = progress::study_bar(todo.len());
    let mut failure: Option<StudyError> = None;
    flexmbd_study::run(&study, &todo, jobs, |r| {
        bar.inc(1);
        match out.write(r) {
            Ok(()) => true,
            Err(e) => {
                failure.get_or_insert(e);
                false
            }
        }
    });
    bar.finish_and_clear();
    if let Some(e) = failure {
        return Err(study_err(e));
    }
    out.finish(&study).map_err(study_err)?;
    let mut written = vec!["records.jsonl", "results.csv"];
    if !args.no_plots {
        let spinner = progress::spinner("plots");
        let n = flexmbd_study::plots::write_plots(&dir, &study, &out.records)
            .and_then(|n| {
                flexmbd_study::plots::write_html(&dir, &study, &out.records, variants.len())
                    .map(|()| n)
            })
            .map_err(crate::outputs::IoFailure)?;
        spinner.finish_and_clear();
        written.push("study.html");
        if n > 0 {
            written.push("plots/");
        }
    }
    crate::emit(&summary(&study, &out, variants.len(), &dir, &written, jobs))?;
    Ok(ExitCode::SUCCESS)
}

/// The text summary: counts, the range of every figure of merit, the failures, the files.
fn summary(
    study: &Study,
    out: &Outputs,
    total: usize,
    dir: &std::path::Path,
    written: &[&str],
    jobs: usize,
) -> String {
    let failed: Vec<_> = out
        .records
        .values()
        .filter(|r| r.status == Status::Failed)
        .collect();
    let mut s = format!(
        "Study {} ({}): {} variants, {} complete, {} failed ({} worker thread{})\n",
        study.name,
        study.file,
        total,
        out.records.len() - failed.len(),
        failed.len(),
        jobs,
        if jobs == 1 { "" } else { "s" }
    );
    s += &format!("Parameters: {}\n", study.parameter_names().join(", "));
    s += "\nFigure of merit            unit          min            max   variants\n";
    for m in flexmbd_study::merit_names(&study.analyses) {
        let range = flexmbd_study::plots::merit_range(&out.records, &m);
        let f = |x: Option<f64>| x.map_or("-".into(), |x| flexmbd_study::plots::cell(Some(x)));
        s += &format!(
            "{m:<26} {:<8} {:>14} {:>14} {:>10}\n",
            flexmbd_study::plots::merit_unit(&m),
            f(range.min),
            f(range.max),
            range.count
        );
    }
    if !failed.is_empty() {
        s += "\nFailed variants (first 10; every one is a row of results.csv with its error):\n";
        for r in failed.iter().take(10) {
            if let Some(e) = &r.error {
                s += &format!("  variant {}: {}: {}\n", r.variant, e.stage, e.message);
            }
        }
    }
    s += &format!("\nResults in {}: {}\n", dir.display(), written.join(", "));
    s
}
