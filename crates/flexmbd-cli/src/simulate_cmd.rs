//! `flexmbd simulate`: parse the arguments, one core call, the writers.

use crate::{emit, load_sim_file, outputs, progress, BadInput};
use flexmbd_core::simulation::{simulate, SimFailure, Stopped};
use flexmbd_io::sim_report::{sim_json, sim_text, write_sim_csv};
use std::path::PathBuf;
use std::process::ExitCode;

/// The files of `simulate --csv DIR`.
pub const SIM_CSV: &[outputs::Pattern] = &[
    outputs::Pattern::exact("energy.csv"),
    outputs::Pattern::exact("nodes.csv"),
    outputs::Pattern::exact("elements.csv"),
];

/// Arguments of `flexmbd simulate`.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    /// End time [s] (overrides [simulate] t_end).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    t_end: Option<f64>,
    /// Step size [s]: the first step with step control, or the fixed step with --fixed-step
    /// (default: [simulate] dt, else t_end/1000).
    #[arg(long, value_name = "H", allow_negative_numbers = true)]
    dt: Option<f64>,
    /// Fixed steps instead of step control.
    #[arg(long)]
    fixed_step: bool,
    /// Spectral radius at infinite frequency rho_inf in [0, 1] (default 0.9; 1 is the
    /// trapezoidal rule).
    #[arg(long, value_name = "RHO", allow_negative_numbers = true)]
    rho_inf: Option<f64>,
    /// Absolute and relative tolerance of the step control, as SPACAR's ERROR abs rel.
    #[arg(long, num_args = 2, value_names = ["ABS", "REL"])]
    tolerance: Option<Vec<f64>>,
    /// Output interval [s] (default t_end/100).
    #[arg(long, value_name = "DT", allow_negative_numbers = true)]
    output_step: Option<f64>,
    /// Print JSON instead of tables.
    #[arg(long)]
    json: bool,
    /// Also write energy.csv, nodes.csv and elements.csv into this directory.
    #[arg(long, value_name = "DIR")]
    csv: Option<PathBuf>,
}

fn positive(name: &str, v: Option<f64>) -> Result<Option<f64>, BadInput> {
    match v {
        Some(v) if !(v.is_finite() && v > 0.0) => Err(BadInput(format!(
            "{name} must be a positive number, found {v}"
        ))),
        v => Ok(v),
    }
}

/// Run `flexmbd simulate`.
pub fn run(a: SimulateArgs) -> anyhow::Result<ExitCode> {
    let path = a.model.as_path();
    if let Some(dir) = &a.csv {
        outputs::check_dir(dir, "--csv", SIM_CSV, &[path])?;
    }
    let file = load_sim_file(path)?;
    let mut set = file.simulate.clone();
    let t_end = positive("--t-end", a.t_end)?;
    if let Some(v) = positive("--dt", a.dt)? {
        set.dt = Some(v);
    }
    if a.fixed_step {
        set.fixed_step = Some(true);
    }
    if let Some(r) = a.rho_inf {
        if !(0.0..=1.0).contains(&r) {
            return Err(BadInput(format!("--rho-inf must lie in [0, 1], found {r}")).into());
        }
        set.rho_inf = Some(r);
    }
    if let Some(t) = &a.tolerance {
        if !(t[0].is_finite() && t[0] > 0.0 && t[1].is_finite() && t[1] >= 0.0) {
            return Err(BadInput(format!(
                "--tolerance ABS REL needs ABS > 0 and REL >= 0, found {} {}",
                t[0], t[1]
            ))
            .into());
        }
        set.tolerance = Some([t[0], t[1]]);
    }
    if let Some(v) = positive("--output-step", a.output_step)? {
        set.output_step = Some(v);
    }
    let opts = set.options(t_end).ok_or_else(|| {
        BadInput(format!(
            "{}: no end time: give --t-end T, or `t_end` in [simulate] (TOML) or TIMESTEP (SPACAR)",
            path.display()
        ))
    })?;
    let model = &file.model;
    let bar = progress::time_bar(opts.t_end);
    let started = std::time::Instant::now();
    let result = simulate(model, &set.excitation, &opts, &mut |p| {
        progress::time_tick(&bar, p.t, p.t_end, p.steps, started);
    });
    bar.finish_and_clear();
    let (sim, stopped): (_, Option<Stopped>) = match result {
        Ok(sim) => (sim, None),
        Err(SimFailure::NotStarted(e)) => {
            return Err(anyhow::Error::new(e).context("simulation failed"));
        }
        Err(SimFailure::Stopped(s)) => ((*s.partial).clone(), Some(s)),
    };
    let fname = path.display().to_string();
    if let Some(dir) = &a.csv {
        outputs::prepare_dir(dir, "--csv", SIM_CSV, &[path])?;
        write_sim_csv(dir, model, &sim).map_err(|e| {
            outputs::IoFailure(format!(
                "cannot write CSV files into {}: {e}",
                dir.display()
            ))
        })?;
    }
    if a.json {
        emit(
            &(serde_json::to_string_pretty(&sim_json(model, &fname, &sim, stopped.as_ref()))?
                + "\n"),
        )?;
    } else {
        emit(&sim_text(model, &fname, &sim, stopped.as_ref()))?;
    }
    match stopped {
        None => Ok(ExitCode::SUCCESS),
        Some(s) => {
            eprintln!(
                "error: {}",
                flexmbd_io::error::printable(&format!(
                    "simulation stopped: {s} (the results up to then are written)"
                ))
            );
            Ok(ExitCode::from(1))
        }
    }
}
