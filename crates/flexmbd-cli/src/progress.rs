//! Progress on stderr (indicatif), the same for every long command: a bar over the load steps
//! of a static solution and a spinner for a stage without steps (modes, sweeps, writing files).
//! Nothing is drawn with the global `--quiet`, or when stderr is not a terminal (a pipe, a file,
//! CI), so output that is captured never contains progress.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

static QUIET: AtomicBool = AtomicBool::new(false);

/// Set by the global `--quiet` flag.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether progress is drawn: not quiet, and stderr is a terminal.
pub fn shown() -> bool {
    !QUIET.load(Ordering::Relaxed) && std::io::stderr().is_terminal()
}

/// A bar over `len` steps, labelled `what`.
pub fn bar(len: usize, what: &str) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new(len as u64);
    b.set_style(
        ProgressStyle::with_template("{msg} {bar:30} {pos}/{len} {elapsed}")
            .expect("a valid constant template"),
    );
    b.set_message(what.to_string());
    b
}

/// A bar over the `len` variants of a study, with variants per second and the time left.
pub fn study_bar(len: usize) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new(len as u64);
    b.set_style(
        ProgressStyle::with_template(
            "variants {bar:30} {pos}/{len} {per_sec:.1} elapsed {elapsed} left {eta}",
        )
        .expect("a valid constant template"),
    );
    b
}

/// A spinner for a stage without steps, labelled `what`.
pub fn spinner(what: &str) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new_spinner();
    b.set_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
            .expect("a valid constant template"),
    );
    b.set_message(what.to_string());
    b.enable_steady_tick(Duration::from_millis(120));
    b
}

/// The static solution, with a bar over its load steps; a path that stops part-way keeps its
/// converged steps ([`flexmbd_core::statics::solve_path`]).
#[allow(clippy::result_large_err)]
pub fn solve_static(
    model: &flexmbd_core::Model,
    opts: &flexmbd_core::statics::StaticOptions,
) -> Result<flexmbd_core::statics::StaticSolution, flexmbd_core::statics::Stopped> {
    let b = bar(opts.steps, "load step");
    let sol = flexmbd_core::statics::solve_path(model, opts, |k, _| b.set_position(k as u64));
    b.finish_and_clear();
    sol
}

/// The static analysis (equilibrium path and linearised results per step), with a bar over
/// its load steps and a spinner for the linearised results.
#[allow(clippy::result_large_err)]
pub fn analyse_static(
    model: &flexmbd_core::Model,
    opts: &flexmbd_core::statics::StaticOptions,
    req: &flexmbd_core::linearized::LinearRequest,
) -> Result<flexmbd_core::statics::StaticAnalysis, flexmbd_core::statics::Stopped> {
    let b = bar(opts.steps, "load step");
    let s = std::cell::Cell::new(None);
    let r = flexmbd_core::linearized::analyse(model, opts, req, |k, n| {
        b.set_position(k as u64);
        if k == n && !req.is_empty() {
            b.finish_and_clear();
            s.set(Some(spinner("linearised results per step")));
        }
    });
    b.finish_and_clear();
    if let Some(s) = s.take() {
        s.finish_and_clear();
    }
    r
}

/// Run `f` with a spinner labelled `what`.
pub fn stage<T>(what: &str, f: impl FnOnce() -> T) -> T {
    let s = spinner(what);
    let r = f();
    s.finish_and_clear();
    r
}

/// A bar over simulated time [s] up to `t_end` (per mille of it), with steps per second.
pub fn time_bar(t_end: f64) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::new(1000);
    b.set_style(
        ProgressStyle::with_template("simulate {bar:30} {msg} {elapsed}")
            .expect("a valid constant template"),
    );
    b.set_message(format!("t = 0 / {t_end:.4e} s"));
    b
}

/// Advance a [`time_bar`] to the simulated time `t` of `t_end` after `steps` steps.
pub fn time_tick(b: &ProgressBar, t: f64, t_end: f64, steps: usize, started: std::time::Instant) {
    if b.is_hidden() {
        return;
    }
    let secs = started.elapsed().as_secs_f64().max(1e-9);
    b.set_position((1000.0 * (t / t_end).clamp(0.0, 1.0)) as u64);
    b.set_message(format!(
        "t = {t:.4e} / {t_end:.4e} s, {steps} steps, {:.0} steps/s",
        steps as f64 / secs
    ));
}
