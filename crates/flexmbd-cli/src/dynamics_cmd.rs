//! `flexmbd statespace` and `flexmbd sweep` (docs/state-space.md).

use crate::{emit, outputs, BadInput};
use anyhow::Context;
use flexmbd_core::dynamics::state_space::{
    check_dense_size, log_space, state_space_with_motions, uses_sparse, Output, StateSpaceOptions,
    DENSE_STATE_SPACE_DOF,
};
use flexmbd_core::dynamics::sweep::sweep_with;
use flexmbd_core::dynamics::{velocity_dof, EigenSolver, ModalOptions};
use flexmbd_core::statics::{PathMethod, StaticOptions};
use flexmbd_core::Model;
use flexmbd_io::requests::{self, InputSpec};
use flexmbd_io::statespace_report as report;
use flexmbd_io::Settings;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `flexmbd statespace`.
#[derive(clap::Args)]
pub struct StatespaceArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    /// An input: a force along (x, y, z) or a moment about (rx, ry, rz) a global axis on a node.
    /// `NODE:x:moment` is the moment about x. `NODE:x:motion` is a prescribed motion of a held
    /// translation (support, [inputs] or [[prescribe]]); its input is the acceleration [m/s²].
    /// `NODE:rz:motion` is an enforced small rotation about z of a held rotation; its input is
    /// the angular acceleration [rad/s²]. `ELEMENT:MODE:motion` drives deformation MODE
    /// (1-based) of an element, an `input` mode such as an actuator's elongation or a driven
    /// hinge's angle; its input is the deformation's acceleration [m/s², rad/s² for hinges].
    /// Repeatable; forces and moments come first in the columns of B, in command-line order,
    /// then the motions.
    #[arg(
        long = "input",
        value_name = "NODE:DIR[:force|moment|motion] | ELEMENT:MODE:motion",
        required = true
    )]
    inputs: Vec<String>,
    /// An output: displacement (default), velocity or acceleration of a node along x, y, z or
    /// its rotation about rx, ry, rz. `ELEMENT:MODE:def` is deformation MODE (1-based) of an
    /// element, `ELEMENT:MODE:force` its force: σ = S e of a flexible mode, the constraint
    /// reaction of a rigid or `input` mode (an actuator's force, a driven hinge's torque; value
    /// only, dense state space). Both may be followed by `:vel` or `:acc` for their rates.
    /// `NODE:DIR:reaction` is the reaction force (moment) at a held coordinate (a support).
    /// Repeatable; the order is the row order of C.
    #[arg(
        long = "output",
        value_name = "NODE:DIR[:disp|vel|acc] | ELEMENT:MODE:def|force[:vel|acc]",
        required = true
    )]
    outputs: Vec<String>,
    /// Modal damping ratio ζ of every mode.
    #[arg(
        long,
        default_value_t = 0.01,
        value_name = "ZETA",
        allow_negative_numbers = true
    )]
    damping: f64,
    /// Keep only the lowest N modes (default: all modes that carry mass).
    #[arg(long, value_name = "N", value_parser = crate::parse_count)]
    modes: Option<usize>,
    /// Add the static flexibility of the dropped modes to D (displacement outputs), so a
    /// truncated model keeps the exact static gain.
    #[arg(long)]
    static_correction: bool,
    /// Linearise at this load step of the static solution (default: the last).
    #[arg(long, value_name = "K")]
    at_step: Option<usize>,
    /// Number of load steps of the static solution (overrides [static] steps).
    #[arg(long, value_name = "N", value_parser = crate::parse_steps)]
    steps: Option<usize>,
    /// How the static path is followed (overrides [static] path; default load-steps).
    #[arg(long, value_enum)]
    path: Option<PathArg>,
    /// Eigen solver: auto (dense up to 3000 degrees of freedom, sparse above), dense (all
    /// modes, prescribed-motion inputs) or sparse (the lowest --modes N by shift-invert
    /// Lanczos, force and moment inputs; for large models).
    #[arg(long, value_enum, default_value_t = SolverArg::Auto)]
    solver: SolverArg,
    /// Print the model as JSON (A, B, C, D as arrays of rows, names, frequencies, ζ).
    #[arg(long)]
    json: bool,
    /// Write the model as a MATLAB/Octave script.
    #[arg(long = "m", value_name = "FILE.m")]
    m_file: Option<PathBuf>,
    /// Write a Bode table (magnitude in output/input units, phase in degrees) as CSV.
    #[arg(long, value_name = "FILE.csv")]
    bode: Option<PathBuf>,
    /// Number of log-spaced frequencies of the Bode table.
    #[arg(long, default_value_t = 200, value_name = "N")]
    bode_points: usize,
    /// Lowest Bode frequency [Hz] (default: 0.1 × the first kept frequency).
    #[arg(long, value_name = "HZ")]
    bode_min: Option<f64>,
    /// Highest Bode frequency [Hz] (default: 10 × the highest kept frequency).
    #[arg(long, value_name = "HZ")]
    bode_max: Option<f64>,
}

/// Arguments of `flexmbd sweep`.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    /// Number of frequencies per step.
    #[arg(long, default_value_t = 6, value_name = "N", value_parser = crate::parse_count)]
    count: usize,
    /// Report the support stiffness of this node at every step (repeatable; adds to
    /// [static] compliance).
    #[arg(long, value_name = "NODE")]
    compliance: Vec<String>,
    /// Support stiffness in the node's local axes in the table and CSV (default: global).
    #[arg(long)]
    local: bool,
    /// Number of load steps (overrides [static] steps).
    #[arg(long, value_name = "N", value_parser = crate::parse_steps)]
    steps: Option<usize>,
    /// Print JSON instead of the table.
    #[arg(long)]
    json: bool,
    /// Also write the table as CSV.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    /// Eigen solver: auto (sparse above 48 degrees of freedom), dense (all modes) or sparse
    /// (shift-invert Lanczos, for large models).
    #[arg(long, value_enum, default_value_t = SolverArg::Auto)]
    solver: SolverArg,
    /// How the static path is followed (overrides [static] path; default load-steps).
    #[arg(long, value_enum)]
    path: Option<PathArg>,
}

/// `--solver` of `flexmbd modes` and `flexmbd sweep` (docs/dynamics.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum SolverArg {
    /// Dense for small models, sparse for large ones.
    Auto,
    /// All eigenpairs of the dense reduced matrices.
    Dense,
    /// The lowest modes by shift-invert Lanczos on the sparse matrices.
    Sparse,
}

impl SolverArg {
    /// The modal-analysis settings.
    pub(crate) fn options(self) -> ModalOptions {
        ModalOptions::with_solver(match self {
            SolverArg::Auto => EigenSolver::Auto,
            SolverArg::Dense => EigenSolver::Dense,
            SolverArg::Sparse => EigenSolver::Sparse,
        })
    }
}

/// `--path` of `flexmbd static`, `modes` and `sweep` (docs/statics.md, "Path following").
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum PathArg {
    /// Equal load steps, halved where Newton fails (cannot pass a limit point of the load).
    LoadSteps,
    /// Arc length: passes limit points and snap-backs; steps adapt to Newton.
    ArcLength,
}

impl PathArg {
    /// The core's setting.
    pub(crate) fn method(self) -> PathMethod {
        match self {
            PathArg::LoadSteps => PathMethod::LoadSteps,
            PathArg::ArcLength => PathMethod::ArcLength,
        }
    }
}

/// Static options from the file's settings, `--steps` and `--path` (as `flexmbd static` does).
pub(crate) fn static_options(
    settings: &Settings,
    steps: Option<usize>,
    path: Option<PathArg>,
) -> anyhow::Result<StaticOptions> {
    flexmbd_io::requests::static_options(settings, steps, path.map(PathArg::method))
        .map_err(|e| BadInput(e.0).into())
}

/// Parse `--input NODE:DIR[:force|moment|motion]` or `ELEMENT:MODE:motion`.
pub fn parse_input(model: &Model, path: &Path, spec: &str) -> Result<InputSpec, BadInput> {
    requests::parse_input(model, &path.display().to_string(), "--input", spec)
        .map_err(|e| BadInput(e.0))
}

/// Parse `--output NODE:DIR[:disp|vel|acc]` or `ELEMENT:MODE:def|force[:disp|vel|acc]`.
pub fn parse_output(model: &Model, path: &Path, spec: &str) -> Result<Output, BadInput> {
    requests::parse_output(model, &path.display().to_string(), "--output", spec)
        .map_err(|e| BadInput(e.0))
}

/// Most points of a Bode table (`--bode-points`).
const MAX_BODE_POINTS: usize = 100_000;

/// `flexmbd statespace`.
pub fn run_statespace(a: StatespaceArgs) -> anyhow::Result<ExitCode> {
    for (flag, p) in [("--m", &a.m_file), ("--bode", &a.bode)] {
        if let Some(p) = p {
            outputs::check_file(p, flag, &[&a.model])?;
        }
    }
    if let (Some(m), Some(b)) = (&a.m_file, &a.bode) {
        if m == b || outputs::same_file(m, b) {
            return Err(
                BadInput(format!("--m and --bode name the same file {}", m.display())).into(),
            );
        }
    }
    let (model, settings) = crate::load_with_settings(&a.model)?;
    let specs = a
        .inputs
        .iter()
        .map(|s| parse_input(&model, &a.model, s))
        .collect::<Result<Vec<_>, _>>()?;
    let (inputs, motions) = requests::split_inputs(&specs);
    let outputs = a
        .outputs
        .iter()
        .map(|s| parse_output(&model, &a.model, s))
        .collect::<Result<Vec<_>, _>>()?;
    if !(a.damping.is_finite() && a.damping >= 0.0) {
        return Err(BadInput(format!(
            "--damping must be a finite number >= 0, found {}",
            a.damping
        ))
        .into());
    }
    if a.modes == Some(0) {
        return Err(BadInput("--modes must be at least 1".into()).into());
    }
    if a.bode.is_some() && !(2..=MAX_BODE_POINTS).contains(&a.bode_points) {
        return Err(BadInput(format!(
            "--bode-points must be from 2 to {MAX_BODE_POINTS}, found {}",
            a.bode_points
        ))
        .into());
    }
    for (flag, v) in [("--bode-min", a.bode_min), ("--bode-max", a.bode_max)] {
        if let Some(v) = v {
            if !(v.is_finite() && v > 0.0) {
                return Err(BadInput(format!(
                    "{flag} must be a positive frequency in Hz, found {v}"
                ))
                .into());
            }
        }
    }
    if let (Some(lo), Some(hi)) = (a.bode_min, a.bode_max) {
        if lo >= hi {
            return Err(
                BadInput(format!("--bode-min ({lo}) must be below --bode-max ({hi})")).into(),
            );
        }
    }
    let ss_opts = StateSpaceOptions {
        damping: a.damping,
        modes: a.modes,
        static_correction: a.static_correction,
        solver: a.solver.options().solver,
        ..Default::default()
    };
    // the sparse path's requirement (the number of modes) is an input error, found before the
    // static solve
    if uses_sparse(&model, &ss_opts) {
        let ndof = velocity_dof(&model);
        if a.modes.is_none() {
            return Err(BadInput(format!(
                "{} has {ndof} degrees of freedom{}: the sparse state space keeps the lowest modes only; give --modes N (e.g. --modes 20), with --static-correction for the exact static gain",
                a.model.display(),
                if a.solver == SolverArg::Sparse {
                    " and --solver sparse was given".to_string()
                } else {
                    format!(", more than the dense state space takes ({DENSE_STATE_SPACE_DOF})")
                }
            ))
            .into());
        }
    }
    // the size guard of the dense path, before the static solve
    check_dense_size(&model, &ss_opts).context("state-space model refused")?;
    let opts = static_options(&settings, a.steps, a.path)?;
    // a path that stops part-way: the state space of its last converged state (or of the
    // step asked for), marked as such, then exit 1
    let path = crate::partial::Path::of_solution(
        crate::progress::solve_static(&model, &opts),
        "the static equilibrium to linearise about was not found",
    )?;
    let (sol, note) = (path.solution(), path.note());
    let k = a.at_step.unwrap_or(sol.steps.len() - 1);
    let Some(step) = sol.steps.get(k) else {
        let msg = format!(
            "--at-step {k}: the static solution has steps 0 to {}",
            sol.steps.len() - 1
        );
        return match &note {
            Some(n) => Err(anyhow::anyhow!("{msg}: the path {}", n.line())),
            None => Err(BadInput(msg).into()),
        };
    };
    let ss = state_space_with_motions(&model, step, &inputs, &motions, &outputs, &ss_opts)
        .context("state-space model failed")?;
    let file = a.model.display().to_string();
    let origin = report::Origin {
        file: &file,
        step: k,
        load_factor: step.load_factor,
        stopped: note.as_ref(),
    };
    let mut written = Vec::new();
    if let Some(p) = &a.m_file {
        outputs::write_file(p, &report::statespace_m(&model, origin, &ss))?;
        written.push(p.display().to_string());
    }
    if let Some(p) = &a.bode {
        let band = ss.default_band(2);
        let lo = a.bode_min.or(band.as_ref().map(|b| b[0]));
        let hi = a.bode_max.or(band.as_ref().map(|b| b[1]));
        let (Some(lo), Some(hi)) = (lo, hi) else {
            return Err(BadInput(
                "--bode: no kept mode has a positive frequency; give --bode-min and --bode-max"
                    .into(),
            )
            .into());
        };
        if lo >= hi {
            return Err(BadInput(format!(
                "--bode: the frequency range {lo} to {hi} Hz is empty; give --bode-min below --bode-max"
            ))
            .into());
        }
        let freqs = log_space(lo, hi, a.bode_points);
        outputs::write_file(p, &report::bode_csv(&model, &ss, &freqs, note.as_ref()))?;
        written.push(p.display().to_string());
    }
    if a.json {
        let mut text = serde_json::to_string_pretty(&report::statespace_json(&model, origin, &ss))?;
        text.push('\n');
        emit(&text)?;
    } else {
        let mut text = report::statespace_text(&model, origin, &ss);
        for w in written {
            text += &format!("\nwritten: {w}");
        }
        if !text.ends_with('\n') {
            text.push('\n');
        }
        emit(&text)?;
    }
    path.finish()
}

/// `flexmbd sweep`.
pub fn run_sweep(a: SweepArgs) -> anyhow::Result<ExitCode> {
    if let Some(p) = &a.csv {
        outputs::check_file(p, "--csv", &[&a.model])?;
    }
    let (model, settings) = crate::load_with_settings(&a.model)?;
    let mut nodes: Vec<String> = Vec::new();
    for n in settings.compliance.iter().chain(&a.compliance) {
        if !nodes.contains(n) {
            nodes.push(n.clone());
        }
    }
    let ids = nodes
        .iter()
        .map(|n| {
            model.node_id(n).ok_or_else(|| {
                BadInput(format!(
                    "--compliance: node `{n}` is not defined in {}",
                    a.model.display()
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    // the size guards of the dense paths, before the static solve
    let modal = a.solver.options();
    if a.count > 0 {
        flexmbd_core::dynamics::check_dense_size(&model, a.count, &modal)
            .context("modal analysis refused")?;
    }
    if !ids.is_empty() {
        flexmbd_core::linearized::check_dense_size(&model, modal.max_dense_bytes)
            .context("support stiffness refused")?;
    }
    let opts = static_options(&settings, a.steps, a.path)?;
    let path = crate::partial::Path::of_solution(
        crate::progress::solve_static(&model, &opts),
        "the static equilibrium to linearise about was not found",
    )?;
    let (sol, note) = (path.solution(), path.note());
    let points = crate::progress::stage("frequencies and stiffness at every step", || {
        sweep_with(&model, &sol.steps, a.count, &ids, &modal)
    });
    if a.count > 0 {
        if let Some(Err(e)) = points
            .iter()
            .all(|p| p.eigenvalues.is_err())
            .then(|| points[0].eigenvalues.clone())
        {
            return Err(anyhow::Error::new(e).context("modal analysis failed at every step"));
        }
    }
    let file = a.model.display().to_string();
    let note = note.as_ref();
    if let Some(p) = &a.csv {
        let csv = report::sweep_csv(&points, a.count, &nodes, a.local, note);
        outputs::write_file(p, &csv)?;
    }
    if a.json {
        let doc = report::sweep_json(&model, &file, &points, &nodes, note);
        crate::emit_json(&doc)?;
    } else {
        emit(&report::sweep_text(
            &model, &file, &points, a.count, &nodes, a.local, note,
        ))?;
    }
    path.finish()
}
