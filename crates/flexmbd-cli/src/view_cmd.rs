//! `flexmbd view`: one self-contained HTML file with a 3D view of the model and the results of
//! an analysis (docs/visualisation.md).

use crate::simulate_cmd::{run_simulation, stopped_exit, SimOptionArgs};
use crate::{emit, load_file, outputs, progress, BadInput};
use anyhow::Context;
use flexmbd_core::dynamics::modes;
use flexmbd_core::kinematics::{columns, rows, CheckOptions};
use flexmbd_core::Model;
use flexmbd_io::html_view::{
    simulate_view_data, view_data, view_html, Classification, ViewResults,
};
use flexmbd_io::report::generalised_names;
use std::path::PathBuf;
use std::process::ExitCode;

/// Largest Dcc (rows × columns) classified for a static or modal view; `check` always
/// classifies.
const MAX_DCC_ENTRIES: usize = 1_000_000;

/// What a report shows.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Analysis {
    /// Kinematic analysis: the reference geometry with its motions and self-stress states.
    Check,
    /// Nonlinear statics: every load step.
    Static,
    /// Natural modes about the static state.
    Modes,
    /// Time simulation: the motion over the output times, with stresses and energies.
    Simulate,
}

/// Arguments of `flexmbd view`.
#[derive(clap::Args)]
pub struct ViewArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    /// The analysis to show.
    #[arg(long, value_enum, default_value = "check")]
    analysis: Analysis,
    /// The HTML file to write (its directory is created).
    #[arg(short = 'o', long = "output", value_name = "FILE.html")]
    output: PathBuf,
    /// Number of modes (modes).
    #[arg(long, default_value_t = 6, value_name = "N", value_parser = crate::parse_count)]
    count: usize,
    /// Number of load steps (static, modes; overrides [static] steps).
    #[arg(long, value_name = "N", value_parser = crate::parse_steps)]
    steps: Option<usize>,
    /// Linearise at this load step of the static solution (modes; default: the last).
    #[arg(long, value_name = "K")]
    at_step: Option<usize>,
    /// Relative rank tolerance of the classification (default sqrt(eps)).
    #[arg(long, value_name = "TOL", allow_negative_numbers = true)]
    rank_tol: Option<f64>,
    /// Maximum number of verified suggestions per motion or self-stress state.
    #[arg(long, default_value_t = 6, value_name = "N")]
    max_suggestions: usize,
    /// Choose generalised coordinates automatically (one per motion) before classifying.
    #[arg(long)]
    auto: bool,
    #[command(flatten, next_help_heading = "Time simulation (--analysis simulate)")]
    sim: SimOptionArgs,
}

use flexmbd_core::kinematics::freedom::IntendedFreedom;

/// The classification with its owned parts.
struct Classified {
    analysis: flexmbd_core::kinematics::ConstraintAnalysis,
    advice: Vec<flexmbd_core::kinematics::advice::StateAdvice>,
    generalised: Vec<String>,
    screws: flexmbd_core::kinematics::screw::ScrewAnalysis,
    wires: Vec<flexmbd_core::kinematics::advice::WireAdvice>,
}

fn classify(
    model: &Model,
    opts: &CheckOptions,
    args: &ViewArgs,
    freedom: &[IntendedFreedom],
) -> anyhow::Result<Classified> {
    let opts = flexmbd_core::kinematics::classify::ClassifyOptions {
        check: *opts,
        auto: args.auto,
        max_suggestions: args.max_suggestions,
    };
    let c = crate::classify_cli(model, &args.model, &opts, freedom)?;
    Ok(Classified {
        generalised: generalised_names(model, &c.partition.x, &c.partition.e),
        analysis: c.analysis,
        advice: c.advice,
        screws: c.screws,
        wires: c.wires,
    })
}

/// `flexmbd view`.
pub fn run_view(args: ViewArgs) -> anyhow::Result<ExitCode> {
    let opts = CheckOptions {
        rank_tol: args.rank_tol.unwrap_or(CheckOptions::default().rank_tol),
        ..Default::default()
    };
    if !(opts.rank_tol.is_finite() && opts.rank_tol >= 0.0) {
        return Err(BadInput(format!(
            "--rank-tol must be a finite number >= 0, found {}",
            opts.rank_tol
        ))
        .into());
    }
    if matches!(args.analysis, Analysis::Modes) && args.count == 0 {
        return Err(BadInput("--count must be at least 1".into()).into());
    }
    if let (false, Some(flag)) = (
        matches!(args.analysis, Analysis::Simulate),
        args.sim.first_given(),
    ) {
        return Err(BadInput(format!("{flag} is an option of --analysis simulate")).into());
    }
    outputs::check_file(&args.output, "-o", &[&args.model])?;
    let flexmbd_io::ModelFile {
        model,
        settings,
        simulate: sim_settings,
        freedom,
    } = if matches!(args.analysis, Analysis::Simulate) {
        crate::load_sim_file(&args.model)?
    } else {
        load_file(&args.model)?
    };
    let file = args.model.display().to_string();
    let mut notes = Vec::new();

    // the classification: always for check; for static and modes when Dcc is of a size whose
    // dense SVD takes a moment
    let classified = match args.analysis {
        Analysis::Check => Some(classify(&model, &opts, &args, &freedom)?),
        Analysis::Static | Analysis::Modes | Analysis::Simulate => {
            let x = model.x0();
            let (m, n) = (
                rows(&model, &model.partition).len(),
                columns(&model, &model.partition, &x).len(),
            );
            if m.saturating_mul(n) <= MAX_DCC_ENTRIES {
                match classify(&model, &opts, &args, &freedom) {
                    Ok(c) => Some(c),
                    Err(e) => {
                        notes.push(format!("classification not shown: {e:#}"));
                        None
                    }
                }
            } else {
                notes.push(format!(
                    "classification not computed: Dcc would be {m} × {n}; run `flexmbd check` for it"
                ));
                None
            }
        }
    };
    let classification = classified.as_ref().map(|c| Classification {
        analysis: &c.analysis,
        advice: &c.advice,
        generalised: &c.generalised,
        rank_tol: opts.rank_tol,
        screws: Some(&c.screws),
        wires: &c.wires,
    });

    // the simulation of a simulate view that stopped part-way
    let mut stopped = None;
    // the static path of a static or modal view (it may have stopped part-way)
    let mut path: Option<crate::partial::Path> = None;
    let mut data = match args.analysis {
        Analysis::Check => view_data(&model, &file, classification.as_ref(), &ViewResults::Check),
        Analysis::Simulate => {
            let opts = args.sim.options(&args.model, &sim_settings)?;
            let (sim, stop) = run_simulation(&model, &sim_settings.excitation, &opts)?;
            let data = simulate_view_data(
                &model,
                &file,
                classification.as_ref(),
                &sim,
                opts.t_end,
                stop.as_ref(),
            );
            stopped = stop;
            data
        }
        Analysis::Static | Analysis::Modes => {
            let mut sopts = crate::dynamics_cmd::static_options(&settings, args.steps, None)?;
            sopts.line_search = settings.line_search;
            let run = crate::partial::Path::of_solution(
                progress::solve_static(&model, &sopts),
                "static analysis failed",
            )?;
            if let Some(n) = run.note() {
                notes.push(n.line());
            }
            let sol = path.insert(run).solution();
            if matches!(args.analysis, Analysis::Static) {
                view_data(
                    &model,
                    &file,
                    classification.as_ref(),
                    &ViewResults::Static(sol),
                )
            } else {
                // a path that stopped part-way: its last converged step by default
                let k = args.at_step.unwrap_or(sol.steps.len() - 1);
                let Some(step) = sol.steps.get(k) else {
                    return Err(BadInput(format!(
                        "--at-step {k}: the static solution has steps 0 to {}",
                        sol.steps.len() - 1
                    ))
                    .into());
                };
                let modal = progress::stage("modal analysis", || modes(&model, step, args.count))
                    .context("modal analysis failed")?;
                view_data(
                    &model,
                    &file,
                    classification.as_ref(),
                    &ViewResults::Modes {
                        step,
                        index: k,
                        modal: &modal,
                    },
                )
            }
        }
    };
    data.notes.extend(notes);
    let html = view_html(&data).context("cannot write the HTML report")?;
    if let Some(dir) = args.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| {
            outputs::IoFailure(format!("cannot create folder {}: {e}", dir.display()))
        })?;
    }
    outputs::write_file(&args.output, &html)?;
    emit(&format!(
        "wrote {} ({} bytes)\n",
        args.output.display(),
        html.len()
    ))?;
    match path {
        Some(path) => path.finish(),
        None => Ok(stopped_exit(stopped)),
    }
}
