//! `flexmbd`: exact-constraint design of compliant mechanisms from the command line.
//!
//! Exit codes: 0 success; 1 numerical failure; 2 invalid input (file, line and item named);
//! 3 `check --require-exact` on a model that is not exactly constrained.

mod dynamics_cmd;
mod hints;
mod output_cmd;
mod progress;
mod view_cmd;

use anyhow::Context;
use clap::{Parser, Subcommand};
use flexmbd_core::kinematics::advice::{advise, auto_generalised};
use flexmbd_core::kinematics::{check, CheckOptions, KinematicsError};
use flexmbd_io::report::{check_json, check_text, generalised_names, CheckReport};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "flexmbd",
    version,
    about = "Exact-constraint design of compliant mechanisms (flexible multibody, SPACAR-style)"
)]
struct Cli {
    /// No progress bars (they are drawn on stderr only when it is a terminal).
    #[arg(long, global = true)]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Kinematic analysis: SVD of Dcc, Table 1 class, motions, self-stresses, repair advice.
    Check {
        /// Model file (.toml, or a SPACAR .dat file).
        model: PathBuf,
        /// Print JSON instead of tables.
        #[arg(long)]
        json: bool,
        /// Relative rank tolerance: s_i counts as zero when s_i <= tol * s_1 (default sqrt(eps)).
        #[arg(long, value_name = "TOL", allow_negative_numbers = true)]
        rank_tol: Option<f64>,
        /// Choose generalised coordinates automatically (one per motion) and report them.
        #[arg(long)]
        auto: bool,
        /// Maximum number of verified suggestions per motion or self-stress state.
        #[arg(long, default_value_t = 6, value_name = "N")]
        max_suggestions: usize,
        /// Exit with code 3 unless the model is exactly constrained.
        #[arg(long)]
        require_exact: bool,
    },
    /// Nonlinear statics: load steps, reactions, stress resultants, support stiffness, buckling.
    Static {
        /// Model file (.toml, or a SPACAR .dat file).
        model: PathBuf,
        /// Number of load steps (overrides [static] steps; default 10).
        #[arg(long, value_name = "N")]
        steps: Option<usize>,
        /// Report the 6 × 6 compliance and support stiffness of this node at every step
        /// (repeatable; adds to [static] compliance).
        #[arg(long, value_name = "NODE")]
        compliance: Vec<String>,
        /// Report this many buckling load multipliers at every step (0: none).
        #[arg(long, value_name = "N")]
        buckling: Option<usize>,
        /// Relative residual tolerance (default 1e-9).
        #[arg(long, value_name = "TOL")]
        tol_force: Option<f64>,
        /// Relative increment tolerance (default 1e-9).
        #[arg(long, value_name = "TOL")]
        tol_disp: Option<f64>,
        /// Print JSON instead of tables.
        #[arg(long)]
        json: bool,
        /// Also write summary.csv and step_K.csv into this directory.
        #[arg(long, value_name = "DIR")]
        csv: Option<PathBuf>,
        /// Backtracking line search in Newton (off by default; step halving is always on).
        #[arg(long)]
        line_search: bool,
    },
    /// Natural frequencies and mode shapes, linearised about a static equilibrium (with
    /// pre-stress) of the model's loads and strokes.
    Modes {
        /// Model file (.toml, or a SPACAR .dat file).
        model: PathBuf,
        /// Number of modes.
        #[arg(long, default_value_t = 10, value_name = "N")]
        count: usize,
        /// Linearise at this load step of the static solution (default: the last).
        #[arg(long, value_name = "K")]
        at_step: Option<usize>,
        /// Number of load steps of the static solution (overrides [static] steps).
        #[arg(long, value_name = "N")]
        steps: Option<usize>,
        /// Eigen solver: dense for small models, shift-invert Lanczos on the sparse matrices
        /// for large ones (auto), or either one.
        #[arg(long, value_enum, default_value_t = dynamics_cmd::SolverArg::Auto)]
        solver: dynamics_cmd::SolverArg,
        /// Print JSON instead of tables.
        #[arg(long)]
        json: bool,
    },
    /// Linear state-space model (A, B, C, D) about a static equilibrium with named inputs
    /// (forces, moments, prescribed motions of nodes and actuators) and outputs (node motions,
    /// element deformations and forces, actuator forces); JSON, MATLAB .m, Bode table.
    Statespace(dynamics_cmd::StatespaceArgs),
    /// Frequencies and support stiffness at every load step of the static solution.
    Sweep(dynamics_cmd::SweepArgs),
    /// Export results for ParaView (.vtu, .pvd) and as PNG/SVG plots (docs/visualisation.md).
    Export(output_cmd::ExportArgs),
    /// Write a self-contained HTML report with a 3D view: motions, modes, self-stress and
    /// stress colouring, load steps, classification (docs/visualisation.md).
    View(view_cmd::ViewArgs),
    /// Convert a SPACAR .dat model to the native TOML format (stiffness, masses, loads and
    /// strokes included; what TOML cannot express, e.g. shear columns, is written as comments).
    Convert {
        /// SPACAR model file (.dat).
        input: PathBuf,
        /// TOML file to write.
        output: PathBuf,
    },
}

/// An error that is the user's input, reported with exit code 2.
#[derive(Debug)]
struct BadInput(String);
impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
impl std::error::Error for BadInput {}

fn load(path: &Path) -> anyhow::Result<flexmbd_core::Model> {
    match extension(path).as_deref() {
        Some("toml") => flexmbd_io::read_model(path).map_err(|e| BadInput(e.to_string()).into()),
        Some("dat") => read_spacar(path)?
            .to_model()
            .map_err(|e| BadInput(e.to_string()).into()),
        _ => Err(BadInput(format!(
            "{}: unknown model format (expected a .toml file or a SPACAR .dat file)",
            path.display()
        ))
        .into()),
    }
}

/// The lower-case file extension.
fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

/// Read a SPACAR file and print its warnings to stderr.
fn read_spacar(path: &Path) -> anyhow::Result<flexmbd_io::SpacarModel> {
    let m = flexmbd_io::read_dat(path).map_err(|e| BadInput(e.to_string()))?;
    for w in &m.warnings {
        eprintln!("warning: {}:{}: {}", m.file, w.line, w.message);
    }
    Ok(m)
}

/// Read a model with its analysis settings: TOML with `[static]`, or a SPACAR `.dat` file with
/// its stiffness, masses, loads, prescribed values, gravity and `ITERSTEP` mapped
/// (docs/spacar-import.md §6; what the mapping approximates is printed as a warning).
fn load_with_settings(path: &Path) -> anyhow::Result<(flexmbd_core::Model, flexmbd_io::Settings)> {
    match extension(path).as_deref() {
        Some("toml") => {
            let f = flexmbd_io::read_model_file(path).map_err(|e| BadInput(e.to_string()))?;
            Ok((f.model, f.settings))
        }
        Some("dat") => {
            let m = read_spacar(path)?;
            let (file, warnings) = m.to_model_file().map_err(|e| BadInput(e.to_string()))?;
            for w in &warnings {
                eprintln!("warning: {}:{}: {}", m.file, w.line, w.message);
            }
            Ok((file.model, file.settings))
        }
        _ => Err(BadInput(format!(
            "{}: unknown model format (expected a .toml file or a SPACAR .dat file)",
            path.display()
        ))
        .into()),
    }
}

/// Write to stdout; a closed pipe (`flexmbd check … | head`) is not an error.
fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("cannot write to standard output"))
        }
        _ => Ok(()),
    }
}

/// `flexmbd convert IN.dat OUT.toml`.
fn convert(input: &Path, output: &Path) -> anyhow::Result<ExitCode> {
    if extension(input).as_deref() != Some("dat") {
        return Err(BadInput(format!(
            "{}: convert reads SPACAR .dat files",
            input.display()
        ))
        .into());
    }
    let m = read_spacar(input)?;
    // build the model first, so that a file flexmbd cannot use is reported, not written
    m.to_model().map_err(|e| BadInput(e.to_string()))?;
    let text = m.to_toml().map_err(|e| BadInput(e.to_string()))?;
    std::fs::write(output, text).with_context(|| format!("cannot write {}", output.display()))?;
    Ok(ExitCode::SUCCESS)
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    progress::set_quiet(cli.quiet);
    match cli.command {
        Command::Convert { input, output } => convert(&input, &output),
        Command::Statespace(args) => dynamics_cmd::run_statespace(args),
        Command::Sweep(args) => dynamics_cmd::run_sweep(args),
        Command::Export(args) => output_cmd::run_export(args),
        Command::View(args) => view_cmd::run_view(args),
        Command::Modes {
            model,
            count,
            at_step,
            steps,
            solver,
            json,
        } => run_modes(&model, count, at_step, steps, solver, json),
        Command::Static {
            model,
            steps,
            compliance,
            buckling,
            tol_force,
            tol_disp,
            json,
            csv,
            line_search,
        } => run_static(
            &model,
            steps,
            compliance,
            buckling,
            tol_force,
            tol_disp,
            json,
            csv,
            line_search,
        ),
        Command::Check {
            model,
            json,
            rank_tol,
            auto,
            max_suggestions,
            require_exact,
        } => {
            let m = load(&model)?;
            let opts = CheckOptions {
                rank_tol: rank_tol.unwrap_or(CheckOptions::default().rank_tol),
                ..Default::default()
            };
            if !(opts.rank_tol.is_finite() && opts.rank_tol >= 0.0) {
                return Err(BadInput(format!(
                    "--rank-tol must be a finite number >= 0, found {}",
                    opts.rank_tol
                ))
                .into());
            }
            let x = m.x0();
            let before = progress::stage("kinematic analysis", || check(&m, &m.partition, &x, &opts)).map_err(|e| match e {
                // a size limit, not a numerical failure: its message says what the limit is
                e @ KinematicsError::TooLarge { .. } => anyhow::Error::new(e),
                e => anyhow::Error::new(e).context("kinematic analysis failed (check the model for NaN coordinates, or try another --rank-tol)"),
            })?;
            let (partition, analysis, chosen) = if auto {
                let c = auto_generalised(&m, &m.partition, &x, &opts)
                    .context("automatic choice of generalised coordinates failed")?;
                (c.partition, c.analysis, Some(c.chosen))
            } else {
                (m.partition.clone(), before.clone(), None)
            };
            let advice = progress::stage("repair advice", || {
                advise(&m, &partition, &x, &analysis, &opts, max_suggestions)
            })
            .context("repair advice failed")?;
            let file = model.display().to_string();
            let report = CheckReport {
                model: &m,
                file: &file,
                rank_tol: opts.rank_tol,
                analysis: &analysis,
                advice: &advice,
                auto: chosen.as_deref().map(|c| (c, &before)),
            };
            let names = generalised_names(&m, &partition.x, &partition.e);
            if json {
                let mut text = serde_json::to_string_pretty(&check_json(&report, &names))?;
                text.push('\n');
                emit(&text)?;
            } else {
                emit(&check_text(&report, &names))?;
            }
            let exact = analysis.n_motions() == 0 && analysis.n_self_stresses() == 0;
            Ok(if require_exact && !exact {
                ExitCode::from(3)
            } else {
                ExitCode::SUCCESS
            })
        }
    }
}

/// `flexmbd modes`.
fn run_modes(
    path: &Path,
    count: usize,
    at_step: Option<usize>,
    steps: Option<usize>,
    solver: dynamics_cmd::SolverArg,
    json: bool,
) -> anyhow::Result<ExitCode> {
    use flexmbd_core::dynamics::modes_with;
    let (model, settings) = load_with_settings(path)?;
    let opts = dynamics_cmd::static_options(&settings, steps)?;
    let sol = progress::solve_static(&model, &opts)
        .context("the static equilibrium to linearise about was not found")?;
    let k = at_step.unwrap_or(sol.steps.len() - 1);
    let Some(step) = sol.steps.get(k) else {
        return Err(BadInput(format!(
            "--at-step {k}: the static solution has steps 0 to {}",
            sol.steps.len() - 1
        ))
        .into());
    };
    let modal = progress::stage("modal analysis", || {
        modes_with(&model, step, count, &solver.options())
    })
    .context("modal analysis failed")?;
    let fname = path.display().to_string();
    if json {
        emit(
            &(serde_json::to_string_pretty(&flexmbd_io::modes_report::modes_json(
                &model,
                &fname,
                step.load_factor,
                &modal,
            ))? + "\n"),
        )?;
    } else {
        emit(&flexmbd_io::modes_report::modes_text(
            &model,
            &fname,
            step.load_factor,
            &modal,
        ))?;
    }
    Ok(ExitCode::SUCCESS)
}

/// `flexmbd static`.
fn run_static(
    path: &Path,
    steps: Option<usize>,
    compliance: Vec<String>,
    buckling: Option<usize>,
    tol_force: Option<f64>,
    tol_disp: Option<f64>,
    json: bool,
    csv: Option<PathBuf>,
    line_search: bool,
) -> anyhow::Result<ExitCode> {
    use flexmbd_core::statics::linear::{
        buckling as buckle, compliance as comply, linearize, unstable_directions,
    };
    use flexmbd_io::static_report::{static_json, static_text, write_csv, StepExtras};
    let (model, settings) = load_with_settings(path)?;
    let mut opts = dynamics_cmd::static_options(&settings, steps)?;
    for (name, v, target) in [
        ("--tol-force", tol_force, &mut opts.tol_force),
        ("--tol-disp", tol_disp, &mut opts.tol_disp),
    ] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(
                    BadInput(format!("{name} must be a positive number, found {v}")).into(),
                );
            }
            *target = v;
        }
    }
    opts.line_search = line_search || settings.line_search;
    let mut nodes = settings.compliance.clone();
    nodes.extend(compliance);
    let node_ids = nodes
        .iter()
        .map(|n| {
            model.node_id(n).ok_or_else(|| {
                BadInput(format!(
                    "--compliance: node `{n}` is not defined in {}",
                    path.display()
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let n_buckling = buckling.unwrap_or(settings.buckling);

    let sol = progress::solve_static(&model, &opts).context("static analysis failed")?;

    // linearised results per step
    let linear_wanted = !node_ids.is_empty() || n_buckling > 0;
    let extras: Vec<StepExtras> = sol
        .steps
        .iter()
        .map(|st| {
            let mut x = StepExtras::default();
            if !linear_wanted {
                return x;
            }
            let lin = linearize(&model, st);
            for (name, &id) in nodes.iter().zip(&node_ids) {
                match comply(&model, &lin, st, id) {
                    Ok(c) => x.compliance.push((name.clone(), c)),
                    Err(e) => x.warnings.push(format!("compliance of `{name}`: {e}")),
                }
            }
            if n_buckling > 0 {
                match buckle(&model, &lin, n_buckling) {
                    Ok(b) => x.buckling = Some(b),
                    Err(e) => x.warnings.push(format!("buckling: {e}")),
                }
                match unstable_directions(&model, &lin) {
                    Ok(n) => x.unstable_directions = Some(n),
                    Err(e) => x.warnings.push(format!("stability: {e}")),
                }
            }
            x
        })
        .collect();
    let fname = path.display().to_string();
    if let Some(dir) = &csv {
        write_csv(dir, &model, &sol, &extras)
            .with_context(|| format!("cannot write CSV files into {}", dir.display()))?;
    }
    if json {
        emit(&(serde_json::to_string_pretty(&static_json(&model, &fname, &sol, &extras))? + "\n"))?;
    } else {
        emit(&static_text(&model, &fname, &sol, &extras))?;
    }
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            let bad_input = e.downcast_ref::<BadInput>().is_some();
            eprintln!("error: {e:#}");
            if let Some(hint) = hints::cli_hint(&e) {
                eprintln!("hint: {hint}");
            }
            ExitCode::from(if bad_input { 2 } else { 1 })
        }
    }
}
