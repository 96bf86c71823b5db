//! `flexmbd export`: ParaView files (.vtu/.pvd) and PNG/SVG plots (docs/visualisation.md).

use crate::outputs::{self, EXPORT_PLOTS, EXPORT_VTK};
use crate::{emit, load_with_settings, BadInput};
use anyhow::Context;
use flexmbd_core::dynamics::modes;
use flexmbd_core::dynamics::sweep::{sweep, SweepPoint};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::kinematics::{check, CheckOptions, ConstraintAnalysis};
use flexmbd_core::model::{Model, Target};
use flexmbd_core::statics::StaticSolution;
use flexmbd_io::plots::{Plot, Series};
use flexmbd_io::vtk::{check_grid, mode_grid, pvd, step_grid};
use flexmbd_io::Settings;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Which analysis to export.
#[derive(Clone, Copy, Debug, clap::ValueEnum)]
pub enum Analysis {
    /// Kinematic analysis: the reference geometry with its motions and self-stress states.
    Check,
    /// Nonlinear statics: every load step (export: one file per step and a .pvd collection).
    Static,
    /// Natural modes about the static state (export: one file per mode and a .pvd collection).
    Modes,
}

/// Arguments of `flexmbd export`.
#[derive(clap::Args)]
pub struct ExportArgs {
    /// Model file (.toml, or a SPACAR .dat file).
    model: PathBuf,
    /// The analysis whose results are exported.
    #[arg(long, value_enum)]
    analysis: Analysis,
    /// Write ParaView files (.vtu, .pvd) into this directory.
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    /// Write PNG and SVG plots into this directory.
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
    /// Number of modes (modes) or of frequencies per step in the frequency plot.
    #[arg(long, default_value_t = 6, value_name = "N", value_parser = crate::parse_count)]
    count: usize,
    /// Number of load steps (overrides [static] steps).
    #[arg(long, value_name = "N", value_parser = crate::parse_steps)]
    steps: Option<usize>,
    /// Plot size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x500", value_name = "WxH")]
    plot_size: String,
}

/// `flexmbd export`.
pub fn run_export(args: ExportArgs) -> anyhow::Result<ExitCode> {
    if args.vtk.is_none() && args.plots.is_none() {
        return Err(BadInput("export: give --vtk DIR and/or --plots DIR".into()).into());
    }
    let size = parse_size(&args.plot_size)?;
    let dirs = [
        (&args.vtk, "--vtk", EXPORT_VTK),
        (&args.plots, "--plots", EXPORT_PLOTS),
    ];
    for (dir, flag, patterns) in dirs {
        if let Some(dir) = dir {
            outputs::check_dir(dir, flag, patterns, &[&args.model])?;
        }
    }
    let (model, settings) = load_with_settings(&args.model)?;
    let prepare = || -> anyhow::Result<()> {
        for (dir, flag, patterns) in dirs {
            if let Some(dir) = dir {
                outputs::prepare_dir(dir, flag, patterns, &[&args.model])?;
            }
        }
        Ok(())
    };
    let mut written: Vec<PathBuf> = Vec::new();
    // the static path of a static or modal export (it may have stopped part-way)
    let mut path: Option<crate::partial::Path> = None;
    match args.analysis {
        Analysis::Check => {
            let x = model.x0();
            let a = crate::progress::stage("kinematic analysis", || {
                check(&model, &model.partition, &x, &CheckOptions::default())
            })
            .context("kinematic analysis failed")?;
            prepare()?;
            if let Some(dir) = &args.vtk {
                let p = dir.join("check.vtu");
                write(&p, &check_grid(&model, &a).to_vtu())?;
                written.push(p);
            }
            if let Some(dir) = &args.plots {
                written.extend(write_plot(
                    &singular_plot(&a),
                    &dir.join("singular_values"),
                    size,
                )?);
            }
        }
        Analysis::Static => {
            let run = static_solution(&model, &settings, args.steps)?;
            let sol = run.solution();
            prepare()?;
            if let Some(dir) = &args.vtk {
                let mut entries = Vec::new();
                for (k, st) in sol.steps.iter().enumerate() {
                    let name = format!("static_{k:04}.vtu");
                    let p = dir.join(&name);
                    write(&p, &step_grid(&model, st).to_vtu())?;
                    written.push(p);
                    entries.push((st.load_factor, name));
                }
                let p = dir.join("static.pvd");
                let note = run.note().map(|n| n.line());
                write(&p, &pvd(&entries, note.as_deref()))?;
                written.push(p);
            }
            if let Some(dir) = &args.plots {
                written.extend(stroke_plots(&model, &settings, sol, args.count, dir, size)?);
            }
            path = Some(run);
        }
        Analysis::Modes => {
            let run = static_solution(&model, &settings, args.steps)?;
            let sol = run.solution();
            // a path that stopped part-way: the modes at its last converged step
            let step = sol.steps.last().expect("a path holds a converged step");
            let modal =
                crate::progress::stage("modal analysis", || modes(&model, step, args.count))
                    .context("modal analysis failed")?;
            prepare()?;
            if let Some(dir) = &args.vtk {
                let mut entries = Vec::new();
                for (k, mode) in modal.modes.iter().enumerate() {
                    let name = format!("mode_{:03}.vtu", k + 1);
                    let p = dir.join(&name);
                    write(&p, &mode_grid(&model, step, mode).to_vtu())?;
                    written.push(p);
                    entries.push(((k + 1) as f64, name));
                }
                let p = dir.join("modes.pvd");
                let note = run.note().map(|n| n.line());
                write(&p, &pvd(&entries, note.as_deref()))?;
                written.push(p);
            }
            if let Some(dir) = &args.plots {
                let (stroke, x_label) = stroke_axis(&model, sol);
                let points = crate::progress::stage("frequencies at every step", || {
                    sweep(&model, &sol.steps, args.count, &[])
                });
                if let Some(p) = frequency_plot(&points, &stroke, &x_label) {
                    written.extend(write_plot(&p, &dir.join("frequency_stroke"), size)?);
                }
            }
            path = Some(run);
        }
    }
    let mut text = String::new();
    for p in &written {
        text += &format!("wrote {}\n", p.display());
    }
    emit(&text)?;
    path.map_or(Ok(ExitCode::SUCCESS), crate::partial::Path::finish)
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    Ok(outputs::write_file(path, text)?)
}

/// Write a plot as PNG and SVG; a failure is an I/O failure (exit 4).
fn write_plot(plot: &Plot, stem: &Path, size: (u32, u32)) -> anyhow::Result<Vec<PathBuf>> {
    plot.write(stem, size)
        .map_err(|e| outputs::IoFailure(e.to_string()).into())
}

fn parse_size(s: &str) -> anyhow::Result<(u32, u32)> {
    let bad = || {
        BadInput(format!(
            "--plot-size: expected WIDTHxHEIGHT such as 800x500, found `{s}`"
        ))
    };
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if !(100..=8000).contains(&w) || !(100..=8000).contains(&h) {
        return Err(bad().into());
    }
    Ok((w, h))
}

/// The static path (it may have stopped part-way, with at least one converged step).
fn static_solution(
    model: &Model,
    settings: &Settings,
    steps: Option<usize>,
) -> anyhow::Result<crate::partial::Path> {
    let mut opts = crate::dynamics_cmd::static_options(settings, steps, None)?;
    opts.line_search = settings.line_search;
    crate::partial::Path::of_solution(
        crate::progress::solve_static(model, &opts),
        "static analysis failed",
    )
}

/// (a) Singular values of Dcc on a log axis with the rank threshold.
fn singular_plot(a: &ConstraintAnalysis) -> Plot {
    let s1 = a.singular_values.first().copied().unwrap_or(1.0);
    let floor = (s1 * 1e-17).max(1e-300);
    Plot {
        title: format!(
            "Singular values of Dcc ({} × {}, rank {})",
            a.m(),
            a.n(),
            a.rank
        ),
        x_label: "index i".into(),
        y_label: "singular value s_i".into(),
        log_y: true,
        series: vec![Series {
            label: "s_i (zeros drawn at 1e-17 s_1)".into(),
            points: a
                .singular_values
                .iter()
                .enumerate()
                .map(|(i, &s)| ((i + 1) as f64, s.max(floor)))
                .collect(),
        }],
        hlines: vec![(format!("rank threshold {:.3e}", a.tol), a.tol.max(floor))],
        markers: true,
        lines: true,
    }
}

/// The x axis of stroke plots: load factor × the first prescribed value, or the load factor.
fn stroke_axis(model: &Model, sol: &StaticSolution) -> (Vec<f64>, String) {
    match model.loads.prescribed.first() {
        Some(p) => {
            let (name, unit) = target_name(model, p.target);
            (
                sol.steps.iter().map(|s| s.load_factor * p.value).collect(),
                format!("stroke {name} [{unit}]"),
            )
        }
        None => (
            sol.steps.iter().map(|s| s.load_factor).collect(),
            "load factor [-]".into(),
        ),
    }
}

/// Name and unit of a prescribed target.
fn target_name(model: &Model, t: Target) -> (String, &'static str) {
    match t {
        Target::Coordinate(i) => {
            let Some((node, label)) = model.coordinate_owner(i) else {
                return (format!("coordinate {i}"), "-");
            };
            let (dof, unit) = match label {
                "lambda1" => ("rx", "rad"),
                "lambda2" => ("ry", "rad"),
                "lambda3" => ("rz", "rad"),
                "lambda0" => ("lambda0", "-"),
                d => (d, "m"),
            };
            (format!("{}:{dof}", model.nodes[node].name), unit)
        }
        Target::Deformation(k) => {
            let (el, m) = model.deformation_owner(k);
            let unit = if model.elements[el].element.mode_is_angle(m) {
                "rad"
            } else {
                "m"
            };
            (format!("{} mode {}", model.elements[el].name, m + 1), unit)
        }
    }
}

/// Reaction at a prescribed target in a step: (value, unit).
fn reaction(
    model: &Model,
    step: &flexmbd_core::statics::StepResult,
    t: Target,
) -> (f64, &'static str) {
    flexmbd_core::results::target_reaction(model, step, t)
}

/// (b) force–stroke, (c) support stiffness vs stroke, (d) frequency vs stroke.
fn stroke_plots(
    model: &Model,
    settings: &Settings,
    sol: &StaticSolution,
    count: usize,
    dir: &Path,
    size: (u32, u32),
) -> anyhow::Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let (stroke, x_label) = stroke_axis(model, sol);
    if let Some(p) = model.loads.prescribed.first() {
        let (name, _) = target_name(model, p.target);
        let unit = reaction(model, &sol.steps[0], p.target).1;
        let plot = Plot {
            title: format!("Force–stroke: reaction at the prescribed input {name}"),
            x_label: x_label.clone(),
            y_label: format!("reaction at {name} [{unit}]"),
            log_y: false,
            series: vec![Series {
                label: format!("reaction {name}"),
                points: sol
                    .steps
                    .iter()
                    .zip(&stroke)
                    .map(|(st, &s)| (s, reaction(model, st, p.target).0))
                    .collect(),
            }],
            hlines: vec![],
            markers: true,
            lines: true,
        };
        written.extend(write_plot(&plot, &dir.join("force_stroke"), size)?);
    }
    let node_ids = settings
        .compliance
        .iter()
        .map(|n| {
            model
                .node_id(n)
                .ok_or_else(|| BadInput(format!("[static] compliance: node `{n}` is not defined")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let points = crate::progress::stage("frequencies and stiffness at every step", || {
        sweep(model, &sol.steps, count, &node_ids)
    });
    for (j, name) in settings.compliance.iter().enumerate() {
        let series: Vec<Series> = ["x", "y", "z"]
            .iter()
            .enumerate()
            .map(|(d, dn)| Series {
                label: format!("k_{dn}"),
                points: points
                    .iter()
                    .zip(&stroke)
                    .map(|(pt, &s)| {
                        let k = pt.compliance[j]
                            .as_ref()
                            .ok()
                            .filter(|c| !c.held[d])
                            .map_or(f64::NAN, |c| c.stiffness_global()[d]);
                        (s, k)
                    })
                    .collect(),
            })
            .collect();
        let plot = Plot {
            title: format!("Support stiffness of {name} (global axes)"),
            x_label: x_label.clone(),
            y_label: "support stiffness 1/C_ii [N/m]".into(),
            log_y: true,
            series,
            hlines: vec![],
            markers: true,
            lines: true,
        };
        if plot
            .series
            .iter()
            .any(|s| s.points.iter().any(|p| p.1.is_finite() && p.1 > 0.0))
        {
            written.extend(write_plot(
                &plot,
                &dir.join(format!("stiffness_{name}")),
                size,
            )?);
        }
    }
    if let Some(p) = frequency_plot(&points, &stroke, &x_label) {
        written.extend(write_plot(&p, &dir.join("frequency_stroke"), size)?);
    }
    Ok(written)
}

/// (d) The lowest frequencies at every step, if any step has them.
fn frequency_plot(points: &[SweepPoint], stroke: &[f64], x_label: &str) -> Option<Plot> {
    let freqs: Vec<Option<Vec<f64>>> = points.iter().map(|p| p.frequencies()).collect();
    let n = freqs.iter().flatten().map(Vec::len).max().unwrap_or(0);
    if n == 0 {
        return None;
    }
    Some(Plot {
        title: "Natural frequencies along the stroke".into(),
        x_label: x_label.into(),
        y_label: "frequency [Hz]".into(),
        log_y: false,
        series: (0..n)
            .map(|i| Series {
                label: format!("mode {}", i + 1),
                points: freqs
                    .iter()
                    .zip(stroke)
                    .map(|(f, &s)| {
                        (
                            s,
                            f.as_ref()
                                .and_then(|f| f.get(i).copied())
                                .unwrap_or(f64::NAN),
                        )
                    })
                    .collect(),
            })
            .collect(),
        hlines: vec![],
        markers: true,
        lines: true,
    })
}
