//! `flexmbd`: exact-constraint design of compliant mechanisms from the command line.
//!
//! Exit codes: 0 success; 1 numerical failure; 2 invalid input (file, line and item named);
//! 3 `check --require-exact` on a model that is not exactly constrained; 4 a file or stream
//! could not be read or written (docs/reliability.md).

mod alloc;
mod dynamics_cmd;
mod hints;
mod output_cmd;
mod outputs;
mod params;
mod partial;
mod progress;
mod simulate_cmd;
mod study_cmd;
mod view_cmd;

/// mimalloc for small blocks, the operating system's pages for large ones ([`alloc`]).
#[global_allocator]
static GLOBAL: alloc::Allocator = alloc::Allocator;

use anyhow::Context;
use clap::{Parser, Subcommand};
use flexmbd_core::kinematics::classify::ClassifyOptions;
use flexmbd_core::kinematics::CheckOptions;
use flexmbd_io::report::{check_text, generalised_names, write_check_json, CheckReport};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "flexmbd",
    version,
    about = "Exact-constraint design of compliant mechanisms (flexible multibody, SPACAR-style)",
    after_help = AFTER_HELP
)]
struct Cli {
    /// No progress bars (they are drawn on stderr only when it is a terminal).
    #[arg(long, global = true)]
    quiet: bool,
    /// Replace existing output files, and remove the files of an earlier run (flexmbd's own
    /// file names only) from output folders. Without it, existing outputs are refused.
    #[arg(long, global = true)]
    force: bool,
    /// Evaluate the model with this value (repeatable): NAME a parameter of the TOML model's
    /// [parameters] (the values that use it follow), or a path of keys such as
    /// sections.sheet.t or nodes.c.x; VALUE a number or an expression of numbers, pi and deg.
    #[arg(long = "set", global = true, value_name = "NAME=VALUE", value_parser = params::parse_set)]
    set: Vec<(String, f64)>,
    #[command(subcommand)]
    command: Command,
}

/// The exit codes and output rules, printed by `flexmbd --help`.
const AFTER_HELP: &str = "Exit codes: 0 success; 1 numerical failure (no convergence, singular matrices); \
2 invalid input (the message names file, line and item); 3 `check --require-exact` on a model that \
is not exactly constrained; 4 a file or stream could not be read or written.

Outputs never replace an input file; an existing output file, or an output folder holding files of an \
earlier run, is refused unless --force is given (docs/reliability.md).";

/// Parse a number of load steps: 1 to the documented maximum.
fn parse_steps(s: &str) -> Result<usize, String> {
    let max = flexmbd_io::limits::MAX_STEPS;
    let n: u128 = s
        .trim()
        .parse()
        .map_err(|_| format!("expected a whole number from 1 to {max}, found `{s}`"))?;
    if n == 0 || n > max as u128 {
        return Err(format!(
            "the number of load steps must be from 1 to {max} (the limit, docs/reliability.md), found {s}"
        ));
    }
    Ok(n as usize)
}

/// Parse a number of modes, frequencies or buckling multipliers: 0 to the documented maximum.
fn parse_count(s: &str) -> Result<usize, String> {
    let max = flexmbd_io::limits::MAX_MODES;
    match s.trim().parse::<u128>() {
        Ok(n) if n <= max as u128 => Ok(n as usize),
        Ok(_) => Err(format!(
            "the number must be from 0 to {max} (the limit, docs/reliability.md), found {s}"
        )),
        Err(_) => Err(format!(
            "expected a whole number from 0 to {max}, found `{s}`"
        )),
    }
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
        /// The rank-revealing method: dense SVD, sparse LU, or auto (sparse when Dcc has more
        /// than 2500 rows or columns).
        #[arg(long, value_enum, default_value_t = CheckMethodArg::Auto)]
        method: CheckMethodArg,
    },
    /// Nonlinear statics: load steps, reactions, stress resultants, support stiffness, buckling.
    Static {
        /// Model file (.toml, or a SPACAR .dat file).
        model: PathBuf,
        /// Number of load steps (overrides [static] steps; default 10).
        #[arg(long, value_name = "N", value_parser = parse_steps)]
        steps: Option<usize>,
        /// Report the 6 × 6 compliance and support stiffness of this node at every step
        /// (repeatable; adds to [static] compliance).
        #[arg(long, value_name = "NODE")]
        compliance: Vec<String>,
        /// Report this many buckling load multipliers at every step (0: none).
        #[arg(long, value_name = "N", value_parser = parse_count)]
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
        /// The smallest eigenvalues of the tangent stiffness at every step (column kappa1,
        /// JSON tangent_eigenvalues), for every path method; above 300 reduced coordinates the
        /// three nearest zero.
        #[arg(long)]
        tangent_eigenvalues: bool,
        /// How the path is followed: load-steps (equal steps of the load factor) or arc-length
        /// (passes limit points and snap-backs); overrides [static] path.
        #[arg(long, value_enum)]
        path: Option<dynamics_cmd::PathArg>,
    },
    /// Natural frequencies and mode shapes, linearised about a static equilibrium (with
    /// pre-stress) of the model's loads and strokes.
    Modes {
        /// Model file (.toml, or a SPACAR .dat file).
        model: PathBuf,
        /// Number of modes.
        #[arg(long, default_value_t = 10, value_name = "N", value_parser = parse_count)]
        count: usize,
        /// Linearise at this load step of the static solution (default: the last).
        #[arg(long, value_name = "K")]
        at_step: Option<usize>,
        /// Number of load steps of the static solution (overrides [static] steps).
        #[arg(long, value_name = "N", value_parser = parse_steps)]
        steps: Option<usize>,
        /// Eigen solver: dense for small models, shift-invert Lanczos on the sparse matrices
        /// for large ones (auto), or either one.
        #[arg(long, value_enum, default_value_t = dynamics_cmd::SolverArg::Auto)]
        solver: dynamics_cmd::SolverArg,
        /// Print JSON instead of tables.
        #[arg(long)]
        json: bool,
        /// How the static path is followed (overrides [static] path; default load-steps).
        #[arg(long, value_enum)]
        path: Option<dynamics_cmd::PathArg>,
    },
    /// Linear state-space model (A, B, C, D) about a static equilibrium with named inputs
    /// (forces, moments, prescribed motions of nodes and actuators) and outputs (node motions,
    /// element deformations and forces, actuator forces); JSON, MATLAB .m, Bode table.
    Statespace(dynamics_cmd::StatespaceArgs),
    /// Frequencies and support stiffness at every load step of the static solution.
    Sweep(dynamics_cmd::SweepArgs),
    /// Nonlinear time simulation (generalised-α): motions, forces and energies over time
    /// (docs/simulation.md).
    Simulate(simulate_cmd::SimulateArgs),
    /// A design study: the variants of a parametric model (grid, list or Latin hypercube) on
    /// all cores, with their figures of merit (Table 1, frequencies by mode class, support
    /// stiffness, stress, actuation force, buckling margin) in CSV, JSON lines, plots and an
    /// HTML page; resumable (docs/studies.md). `sweep` is the load steps of one model.
    Study(study_cmd::StudyArgs),
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
        Some("toml") => params::read_toml(path).map(|f| f.model),
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
    params::refuse_for_dat(path)?;
    let m = flexmbd_io::read_dat(path).map_err(|e| BadInput(e.to_string()))?;
    for w in &m.warnings {
        eprintln!(
            "warning: {}:{}: {}",
            m.file,
            w.line,
            flexmbd_io::error::printable(&w.message)
        );
    }
    Ok(m)
}

/// Read a model with its analysis settings: TOML with `[static]`, or a SPACAR `.dat` file with
/// its stiffness, masses, loads, prescribed values, gravity and `ITERSTEP` mapped
/// (docs/spacar-import.md §6; what the mapping approximates is printed as a warning).
fn load_with_settings(path: &Path) -> anyhow::Result<(flexmbd_core::Model, flexmbd_io::Settings)> {
    let f = load_file(path)?;
    Ok((f.model, f.settings))
}

/// Read a model file with its settings, whatever its format.
fn load_file(path: &Path) -> anyhow::Result<flexmbd_io::ModelFile> {
    match extension(path).as_deref() {
        Some("toml") => params::read_toml(path),
        Some("dat") => {
            let m = read_spacar(path)?;
            let (file, warnings) = m.to_model_file().map_err(|e| BadInput(e.to_string()))?;
            print_warnings(&m, &warnings);
            Ok(file)
        }
        _ => Err(BadInput(format!(
            "{}: unknown model format (expected a .toml file or a SPACAR .dat file)",
            path.display()
        ))
        .into()),
    }
}

/// Read a model file for `flexmbd simulate`: a SPACAR file with its time-simulation data
/// (mode 1: `TIMESTEP`, `ERROR`, loads and inputs as functions of time; docs/spacar-import.md
/// §7), a TOML file as for every command.
fn load_sim_file(path: &Path) -> anyhow::Result<flexmbd_io::ModelFile> {
    if extension(path).as_deref() != Some("dat") {
        return load_file(path);
    }
    let m = read_spacar(path)?;
    let (file, warnings) = m
        .to_dynamic_model_file()
        .map_err(|e| BadInput(e.to_string()))?;
    print_warnings(&m, &warnings);
    Ok(file)
}

/// The warnings of a SPACAR mapping on stderr, `warning: file:line: …`.
fn print_warnings(m: &flexmbd_io::SpacarModel, warnings: &[flexmbd_io::spacar::Warning]) {
    for w in warnings {
        eprintln!(
            "warning: {}:{}: {}",
            m.file,
            w.line,
            flexmbd_io::error::printable(&w.message)
        );
    }
}

/// `check --method`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum CheckMethodArg {
    /// Sparse above 2500 rows or columns of Dcc, dense below.
    Auto,
    /// Dense SVD: all singular values, orthonormal null bases.
    Dense,
    /// Sparse rank-revealing LU: rank with bounds, fundamental null bases.
    Sparse,
}

impl From<CheckMethodArg> for flexmbd_core::kinematics::CheckMethod {
    fn from(m: CheckMethodArg) -> Self {
        use flexmbd_core::kinematics::CheckMethod;
        match m {
            CheckMethodArg::Auto => CheckMethod::Auto,
            CheckMethodArg::Dense => CheckMethod::Dense,
            CheckMethodArg::Sparse => CheckMethod::Sparse,
        }
    }
}

/// Write to stdout; a closed pipe (`flexmbd check … | head`) is not an error.
fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let text = params::mark(text);
    let mut out = std::io::stdout().lock();
    written(out.write_all(text.as_bytes()).and_then(|()| out.flush()))
}

/// The outcome of writing to stdout: a closed pipe is not an error.
fn written(r: std::io::Result<()>) -> anyhow::Result<()> {
    match r {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("cannot write to standard output"))
        }
        _ => Ok(()),
    }
}

/// Writes a JSON document to standard output as it is serialised, marked with the parameters
/// a study set ([`params::Marked`]): the text of a large model's results is never held whole.
fn emit_json<T: serde::Serialize>(doc: &T) -> anyhow::Result<()> {
    use std::io::Write;
    let out = std::io::stdout().lock();
    let mut w = params::Marked::new(std::io::BufWriter::with_capacity(1 << 16, out));
    written(
        serde_json::to_writer_pretty(&mut w, doc)
            .map_err(std::io::Error::from)
            .and_then(|()| w.write_all(b"\n"))
            .and_then(|()| w.flush()),
    )
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
    outputs::check_file(output, "OUTPUT", &[input])?;
    if extension(output).as_deref() != Some("toml") {
        return Err(BadInput(format!(
            "OUTPUT {}: convert writes a TOML model; give a file name ending in .toml",
            output.display()
        ))
        .into());
    }
    let m = read_spacar(input)?;
    // the document is built before it is written, so that a file flexmbd cannot use is
    // reported, not written
    let text = m.to_toml().map_err(|e| BadInput(e.to_string()))?;
    outputs::write_file(output, &text)?;
    Ok(ExitCode::SUCCESS)
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    progress::set_quiet(cli.quiet);
    outputs::set_force(cli.force);
    params::set_overrides(cli.set);
    match cli.command {
        Command::Convert { input, output } => convert(&input, &output),
        Command::Statespace(args) => dynamics_cmd::run_statespace(args),
        Command::Sweep(args) => dynamics_cmd::run_sweep(args),
        Command::Simulate(args) => simulate_cmd::run(args),
        Command::Study(args) => study_cmd::run(args),
        Command::Export(args) => output_cmd::run_export(args),
        Command::View(args) => view_cmd::run_view(args),
        Command::Modes {
            model,
            count,
            at_step,
            steps,
            solver,
            json,
            path,
        } => run_modes(&model, count, at_step, (steps, path), solver, json),
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
            tangent_eigenvalues,
            path,
        } => run_static(
            &model,
            (steps, path),
            compliance,
            buckling,
            tol_force,
            tol_disp,
            json,
            csv,
            (line_search, tangent_eigenvalues),
        ),
        Command::Check {
            model,
            json,
            rank_tol,
            auto,
            max_suggestions,
            require_exact,
            method,
        } => {
            // the intended freedom is a part of the TOML format
            let (m, freedom) = match extension(&model).as_deref() {
                Some("toml") => {
                    let f = params::read_toml(&model)?;
                    (f.model, f.freedom)
                }
                _ => (load(&model)?, Vec::new()),
            };
            let opts = CheckOptions {
                rank_tol: rank_tol.unwrap_or(CheckOptions::default().rank_tol),
                method: method.into(),
                ..Default::default()
            };
            if !(opts.rank_tol.is_finite() && opts.rank_tol >= 0.0) {
                return Err(BadInput(format!(
                    "--rank-tol must be a finite number >= 0, found {}",
                    opts.rank_tol
                ))
                .into());
            }
            let c = classify_cli(
                &m,
                &model,
                &ClassifyOptions {
                    check: opts,
                    auto,
                    max_suggestions,
                },
                &freedom,
            )?;
            let file = model.display().to_string();
            let report = CheckReport::of(&m, &file, opts.rank_tol, &c);
            let names = generalised_names(&m, &c.partition.x, &c.partition.e);
            if json {
                let mut out = Vec::new();
                write_check_json(&mut out, &report, &names)?;
                emit(&String::from_utf8_lossy(&out))?;
            } else {
                emit(&check_text(&report, &names))?;
            }
            Ok(if require_exact && !c.is_exact() {
                ExitCode::from(3)
            } else {
                ExitCode::SUCCESS
            })
        }
    }
}

/// The kinematic check ([`kinematics::classify`]) with a spinner per stage; a model without
/// constraint rows is invalid input (exit 2), the other failures say what to try.
pub(crate) fn classify_cli(
    model: &flexmbd_core::Model,
    path: &Path,
    opts: &ClassifyOptions,
    intended: &[flexmbd_core::kinematics::freedom::IntendedFreedom],
) -> anyhow::Result<flexmbd_core::kinematics::classify::Classification> {
    use flexmbd_core::kinematics::classify::{classify_intended, Stage};
    use flexmbd_core::kinematics::KinematicsError;
    let mut spinner: Option<indicatif::ProgressBar> = None;
    let r = classify_intended(model, opts, intended, |stage| {
        if let Some(s) = spinner.take() {
            s.finish_and_clear();
        }
        spinner = Some(progress::spinner(match stage {
            Stage::Check => "kinematic analysis",
            Stage::Auto => "automatic generalised coordinates",
            Stage::Advice => "repair advice",
        }));
    });
    if let Some(s) = spinner {
        s.finish_and_clear();
    }
    r.map_err(|e| match &e.source {
        KinematicsError::NoConstraintRows => BadInput(format!(
            "{}: {} (leave it out of `free`)",
            path.display(),
            e.source
        ))
        .into(),
        KinematicsError::UnknownBody(_) | KinematicsError::BadFreedom(_) => {
            BadInput(format!("{}: [[freedom]]: {}", path.display(), e.source)).into()
        }
        _ => anyhow::Error::new(e),
    })
}

/// `flexmbd modes`.
fn run_modes(
    path: &Path,
    count: usize,
    at_step: Option<usize>,
    (steps, path_arg): (Option<usize>, Option<dynamics_cmd::PathArg>),
    solver: dynamics_cmd::SolverArg,
    json: bool,
) -> anyhow::Result<ExitCode> {
    use flexmbd_core::dynamics::modes_with;
    let (model, settings) = load_with_settings(path)?;
    let modal_opts = solver.options();
    // the size guard of the dense path, before the static solve
    flexmbd_core::dynamics::check_dense_size(&model, count, &modal_opts)
        .context("modal analysis refused")?;
    let mut opts = dynamics_cmd::static_options(&settings, steps, path_arg)?;
    // nothing depends on the load factor: every load step is the first one's equilibrium, so
    // one step gives the state to linearise about (without solving and keeping the others)
    if at_step.is_none()
        && opts.path == flexmbd_core::statics::PathMethod::LoadSteps
        && !model.loads.scale_with_load_factor()
    {
        opts.steps = opts.steps.min(1);
    }
    let mut run = partial::Path::of_solution(
        progress::solve_static(&model, &opts),
        "the static equilibrium to linearise about was not found",
    )?;
    let sol = run.solution();
    // a path that stopped part-way: its last converged step, unless another one is asked for
    let k = at_step.unwrap_or(sol.steps.len() - 1);
    if k >= sol.steps.len() {
        return Err(BadInput(format!(
            "--at-step {k}: the static solution has steps 0 to {}{}",
            sol.steps.len() - 1,
            if run.stop.is_some() {
                " (it stopped there)"
            } else {
                ""
            }
        ))
        .into());
    }
    let note = run.note();
    run.keep_only_linearised_state(k);
    let step = &run.solution().steps[k];
    let modal = progress::stage("modal analysis", || {
        modes_with(&model, step, count, &modal_opts)
    })
    .context("modal analysis failed")?;
    let fname = path.display().to_string();
    if json {
        emit_json(&flexmbd_io::modes_report::ModesDoc {
            model: &model,
            file: &fname,
            load_factor: step.load_factor,
            modal: &modal,
            stop: note.as_ref(),
        })?;
    } else {
        emit(&flexmbd_io::modes_report::modes_text(
            &model,
            &fname,
            step.load_factor,
            &modal,
            note.as_ref(),
        ))?;
    }
    run.finish()
}

/// `flexmbd static`.
fn run_static(
    path: &Path,
    (steps, path_arg): (Option<usize>, Option<dynamics_cmd::PathArg>),
    compliance: Vec<String>,
    buckling: Option<usize>,
    tol_force: Option<f64>,
    tol_disp: Option<f64>,
    json: bool,
    csv: Option<PathBuf>,
    (line_search, tangent_eigenvalues): (bool, bool),
) -> anyhow::Result<ExitCode> {
    use flexmbd_core::linearized::LinearRequest;
    use flexmbd_io::static_report::{static_text, write_csv};
    if let Some(dir) = &csv {
        outputs::check_dir(dir, "--csv", outputs::STATIC_CSV, &[path])?;
    }
    let (model, settings) = load_with_settings(path)?;
    let mut opts = dynamics_cmd::static_options(&settings, steps, path_arg)?;
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
    opts.tangent_eigenvalues = tangent_eigenvalues || settings.tangent_eigenvalues;
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
    let request = LinearRequest {
        compliance: node_ids,
        buckling: buckling.unwrap_or(settings.buckling),
        ..Default::default()
    };
    if !request.is_empty() {
        // the size guard of the dense linearised results, before the static solve
        flexmbd_core::linearized::check_dense_size(&model, request.max_dense_bytes)
            .context("compliance and buckling refused")?;
    }
    let run = partial::Path::of_analysis(
        progress::analyse_static(&model, &opts, &request),
        "static analysis failed",
    )?;
    let (sol, extras) = (&run.analysis.solution, &run.analysis.linear);
    let note = run.note();
    let fname = path.display().to_string();
    if let Some(dir) = &csv {
        outputs::prepare_dir(dir, "--csv", outputs::STATIC_CSV, &[path])?;
        write_csv(dir, &model, sol, extras, note.as_ref()).map_err(|e| {
            outputs::IoFailure(format!(
                "cannot write CSV files into {}: {e}",
                dir.display()
            ))
        })?;
    }
    if json {
        let doc = flexmbd_io::static_report::StaticDoc {
            model: &model,
            file: &fname,
            sol,
            extras,
            stop: note.as_ref(),
        };
        emit_json(&doc)?;
    } else {
        emit(&static_text(&model, &fname, sol, extras, note.as_ref()))?;
    }
    run.finish()
}

/// 2 for the user's input, 4 for a file or stream that cannot be read or written, 1 otherwise
/// (a numerical failure).
fn exit_code(e: &anyhow::Error) -> u8 {
    if e.downcast_ref::<BadInput>().is_some() {
        2
    } else if e
        .chain()
        .any(|c| c.is::<outputs::IoFailure>() || c.is::<std::io::Error>())
    {
        4
    } else {
        1
    }
}

fn main() -> ExitCode {
    alloc::purge_at_once();
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            // control characters copied from an input are shown escaped, not sent to the terminal
            eprintln!("error: {}", flexmbd_io::error::printable(&format!("{e:#}")));
            if let Some(hint) = hints::cli_hint(&e) {
                eprintln!("hint: {hint}");
            }
            ExitCode::from(exit_code(&e))
        }
    }
}
