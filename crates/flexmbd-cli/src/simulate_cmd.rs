//! `flexmbd simulate`: parse the arguments, one core call, the writers.

use crate::{emit, emit_json, load_sim_file, outputs, progress, BadInput};
use flexmbd_core::simulation::{simulate, Excitation, SimFailure, SimOptions, Simulation, Stopped};
use flexmbd_core::Model;
use flexmbd_io::sim_report::{sim_text, write_sim_csv, SimDoc};
use flexmbd_io::vtk::{pvd, sim_grid};
use flexmbd_io::SimulateSettings;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The files of `simulate --csv DIR`.
pub const SIM_CSV: &[outputs::Pattern] = &[
    outputs::Pattern::exact("energy.csv"),
    outputs::Pattern::exact("nodes.csv"),
    outputs::Pattern::exact("elements.csv"),
];

/// The files of `simulate --vtk DIR`.
pub const SIM_VTK: &[outputs::Pattern] = &[
    outputs::Pattern::numbered("sim_", ".vtu"),
    outputs::Pattern::exact("simulate.pvd"),
];

/// The integrator options of the command line (shared by `simulate` and `view --analysis
/// simulate`); each overrides the model's `[simulate]`.
#[derive(clap::Args, Default)]
pub struct SimOptionArgs {
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
}

impl SimOptionArgs {
    /// The first option given, as it is spelled (for a command that does not simulate).
    pub fn first_given(&self) -> Option<&'static str> {
        [
            (self.t_end.is_some(), "--t-end"),
            (self.dt.is_some(), "--dt"),
            (self.fixed_step, "--fixed-step"),
            (self.rho_inf.is_some(), "--rho-inf"),
            (self.tolerance.is_some(), "--tolerance"),
            (self.output_step.is_some(), "--output-step"),
        ]
        .into_iter()
        .find_map(|(given, name)| given.then_some(name))
    }

    /// The integrator options: these arguments over the model file's `[simulate]` settings.
    pub fn options(&self, path: &Path, file: &SimulateSettings) -> Result<SimOptions, BadInput> {
        let over = flexmbd_io::requests::SimOverrides {
            t_end: self.t_end,
            dt: self.dt,
            fixed_step: self.fixed_step,
            rho_inf: self.rho_inf,
            tolerance: self.tolerance.as_ref().map(|t| [t[0], t[1]]),
            output_step: self.output_step,
        };
        over.options(&path.display().to_string(), file, &|name| {
            format!("--{}", name.replace('_', "-"))
        })
        .map_err(|e| BadInput(e.0))
    }
}

/// Arguments of `flexmbd simulate`.
#[derive(clap::Args)]
pub struct SimulateArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    #[command(flatten)]
    options: SimOptionArgs,
    /// Print JSON instead of tables.
    #[arg(long)]
    json: bool,
    /// Also write energy.csv, nodes.csv and elements.csv into this directory.
    #[arg(long, value_name = "DIR")]
    csv: Option<PathBuf>,
    /// Also write ParaView files into this directory: sim_KKKK.vtu per output time and the
    /// collection simulate.pvd (time step = t).
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    /// Print on stderr the wall time of reading the model, of the simulation (set-up, initial
    /// state and integration: the time a program calling the library spends) and of writing
    /// the results.
    #[arg(long)]
    timings: bool,
}

/// Run the simulation with a progress bar: the frames, and how it stopped if it did not reach
/// the end (its frames up to then are returned). A run that could not start is an error.
pub fn run_simulation(
    model: &Model,
    excitation: &Excitation,
    opts: &SimOptions,
) -> anyhow::Result<(Simulation, Option<Stopped>)> {
    let bar = progress::time_bar(opts.t_end);
    let started = std::time::Instant::now();
    let result = simulate(model, excitation, opts, &mut |p| {
        progress::time_tick(&bar, p.t, p.t_end, p.steps, started);
    });
    bar.finish_and_clear();
    match result {
        Ok(sim) => Ok((sim, None)),
        Err(SimFailure::NotStarted(e)) => Err(anyhow::Error::new(e).context("simulation failed")),
        Err(SimFailure::Stopped(s)) => Ok(((*s.partial).clone(), Some(s))),
    }
}

/// Report a stopped run on stderr; exit code 1.
pub fn stopped_exit(stopped: Option<Stopped>) -> ExitCode {
    match stopped {
        None => ExitCode::SUCCESS,
        Some(s) => {
            eprintln!(
                "error: {}",
                flexmbd_io::error::printable(&format!(
                    "simulation stopped: {s} (the results up to then are written)"
                ))
            );
            ExitCode::from(1)
        }
    }
}

/// Write `sim_KKKK.vtu` per frame and `simulate.pvd` into `dir` (prepared before); the `.pvd`
/// of a run that stopped starts with the comment `stopped at t = T s: reason` (the convention
/// of a static path that stops part-way).
fn write_vtk(
    dir: &Path,
    model: &Model,
    sim: &Simulation,
    stopped: Option<&Stopped>,
) -> anyhow::Result<()> {
    let mut entries = Vec::with_capacity(sim.frames.len());
    for (k, f) in sim.frames.iter().enumerate() {
        let name = format!("sim_{k:04}.vtu");
        let p = dir.join(&name);
        outputs::write_file(&p, &sim_grid(model, f).to_vtu())?;
        entries.push((f.t, name));
    }
    let p = dir.join("simulate.pvd");
    let note = stopped.map(|s| format!("stopped at t = {:.6e} s: {}", s.t, s.reason));
    outputs::write_file(&p, &pvd(&entries, note.as_deref()))?;
    Ok(())
}

/// Run `flexmbd simulate`.
pub fn run(a: SimulateArgs) -> anyhow::Result<ExitCode> {
    let path = a.model.as_path();
    if let Some(dir) = &a.csv {
        outputs::check_dir(dir, "--csv", SIM_CSV, &[path])?;
    }
    if let Some(dir) = &a.vtk {
        outputs::check_dir(dir, "--vtk", SIM_VTK, &[path])?;
    }
    let started = std::time::Instant::now();
    let file = load_sim_file(path)?;
    let opts = a.options.options(path, &file.simulate)?;
    let model = &file.model;
    let read = started.elapsed();
    let (sim, stopped) = run_simulation(model, &file.simulate.excitation, &opts)?;
    let simulated = started.elapsed();
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
    if let Some(dir) = &a.vtk {
        outputs::prepare_dir(dir, "--vtk", SIM_VTK, &[path])?;
        write_vtk(dir, model, &sim, stopped.as_ref())?;
    }
    if a.json {
        emit_json(&SimDoc {
            model,
            file: &fname,
            sim: &sim,
            stopped: stopped.as_ref(),
        })?;
    } else {
        emit(&sim_text(model, &fname, &sim, stopped.as_ref()))?;
    }
    if a.timings {
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        let solve = simulated - read;
        eprintln!(
            "timings: read {:.3} ms, simulate {:.3} ms ({} steps, {:.0} steps/s), write {:.3} ms",
            ms(read),
            ms(solve),
            sim.stats.steps,
            sim.stats.steps as f64 / solve.as_secs_f64().max(1e-9),
            ms(started.elapsed() - simulated)
        );
    }
    Ok(stopped_exit(stopped))
}
