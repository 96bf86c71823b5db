//! The shipped examples at the io level (each test file is its own crate and includes this
//! module): a model file read with `flexmbd_io`, one core call, and the io writer's JSON
//! document — what `flexmbd check|modes|static|simulate --json` prints, without starting a
//! process. The command line's own concerns (arguments, exit codes, formats) are tested in
//! `crates/flexmbd-cli/tests/`.

#![allow(dead_code)]

use flexmbd_core::dynamics::state_space::{
    state_space_with_motions, StateSpace, StateSpaceOptions,
};
use flexmbd_core::dynamics::{modes_with, ModalOptions};
use flexmbd_core::kinematics::classify::{classify_intended, ClassifyOptions};
use flexmbd_core::linearized::{analyse, LinearRequest};
use flexmbd_core::simulation::simulate;
use flexmbd_core::statics::{solve_path, PathMethod, StaticSolution, StepResult, Stopped};
use flexmbd_io::report::{generalised_names, write_check_json, CheckReport};
use flexmbd_io::requests::{parse_input, parse_output, split_inputs, static_options, SimOverrides};
use flexmbd_io::spacar::Warning;
use flexmbd_io::statespace_report::{statespace_json, Origin};
use flexmbd_io::ModelFile;
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The repository's `examples/` folder.
pub fn examples_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// A shipped example model, `examples/NAME`.
pub fn example(name: &str) -> PathBuf {
    examples_dir().join(name)
}

/// One of this crate's test files, `tests/models/NAME`.
pub fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/models")
        .join(name)
}

/// A test model shared with the command-line tests, `crates/flexmbd-cli/tests/models/NAME`: the
/// numbers are checked here, the command line's handling of the same file there.
pub fn cli_model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../flexmbd-cli/tests/models")
        .join(name)
}

/// Read a model file with its settings (the test fails on an input error).
pub fn read(path: &Path) -> ModelFile {
    flexmbd_io::read_model_file(path).unwrap_or_else(|e| panic!("{e}"))
}

/// The `check --json` document of a model file: the kinematic check with the command's
/// defaults (`--auto` when `auto`).
pub fn check_doc(path: &Path, auto: bool) -> Value {
    let f = read(path);
    let m = f.model;
    let opts = ClassifyOptions {
        auto,
        ..Default::default()
    };
    let c = classify_intended(&m, &opts, &f.freedom, |_| {})
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let file = path.display().to_string();
    let report = CheckReport::of(&m, &file, opts.check.rank_tol, &c);
    let names = generalised_names(&m, &c.partition.x, &c.partition.e);
    let mut out = Vec::new();
    write_check_json(&mut out, &report, &names).expect("write to memory");
    serde_json::from_slice(&out).expect("the check document is JSON")
}

/// The `modes --json --count COUNT` document of a model file: the modes about the last step of
/// its static solution (the file's `[static]` settings), automatic solver choice.
pub fn modes_doc(path: &Path, count: usize) -> Value {
    let f = read(path);
    let opts = static_options(&f.settings, None, None).unwrap_or_else(|e| panic!("{}", e.0));
    let sol = solve_path(&f.model, &opts, |_, _| {}).unwrap_or_else(|s| panic!("{}", s.error));
    let step = sol.steps.last().expect("a converged step");
    let modal = modes_with(&f.model, step, count, &ModalOptions::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let file = path.display().to_string();
    flexmbd_io::modes_report::modes_json(&f.model, &file, step.load_factor, &modal, None)
}

/// The `static --json [--path arc-length]` document of a model file `f` read from `file`: the
/// equilibrium path with the file's `[static]` settings (the path method `path` when given) and
/// the linearised results the file asks for.
pub fn static_doc(f: &ModelFile, file: &str, path: Option<PathMethod>) -> Value {
    let mut opts = static_options(&f.settings, None, path).unwrap_or_else(|e| panic!("{}", e.0));
    opts.line_search = f.settings.line_search;
    let compliance = f
        .settings
        .compliance
        .iter()
        .map(|n| f.model.node_id(n).expect("compliance node"))
        .collect();
    let request = LinearRequest {
        compliance,
        buckling: f.settings.buckling,
        ..Default::default()
    };
    let a = analyse(&f.model, &opts, &request, |_, _| {}).unwrap_or_else(|s| panic!("{}", s.error));
    flexmbd_io::static_report::static_json(&f.model, file, &a.solution, &a.linear, None)
}

/// The `simulate --json --t-end T_END [--csv DIR]` document of a model file (the CSV tables
/// written into the existing folder `csv` when given).
pub fn simulate_doc(path: &Path, t_end: f64, csv: Option<&Path>) -> Value {
    let over = SimOverrides {
        t_end: Some(t_end),
        ..Default::default()
    };
    simulate_file_doc(&read(path), &path.display().to_string(), &over, csv)
}

/// The `simulate --json [--csv DIR]` document of a model file `f` read from `file`, with the
/// options `over` over the file's `[simulate]` settings.
pub fn simulate_file_doc(
    f: &ModelFile,
    file: &str,
    over: &SimOverrides,
    csv: Option<&Path>,
) -> Value {
    let opts = over
        .options(file, &f.simulate, &|name| name.to_string())
        .unwrap_or_else(|e| panic!("{}", e.0));
    let sim = simulate(&f.model, &f.simulate.excitation, &opts, &mut |_| {})
        .unwrap_or_else(|e| panic!("{e}"));
    if let Some(dir) = csv {
        flexmbd_io::sim_report::write_sim_csv(dir, &f.model, &sim).expect("write the CSV tables");
    }
    flexmbd_io::sim_report::sim_json(&f.model, file, &sim, None)
}

/// The node `name` of a step of a `static --json` document (or of a frame of `simulate
/// --json`).
pub fn node<'a>(step: &'a Value, name: &str) -> &'a Value {
    step["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .find(|n| n["node"] == name)
        .unwrap_or_else(|| panic!("node {name}"))
}

/// A SPACAR file's text mapped as `flexmbd static|modes|statespace FILE.dat` maps it (for a
/// time simulation when `dynamic`, as `flexmbd simulate` does): the model file and every
/// warning, of the reader and of the mapping, which the command prints on stderr; an input
/// error as the command prints it (file, line and item).
pub fn spacar(text: &str, file: &str, dynamic: bool) -> Result<(ModelFile, Vec<Warning>), String> {
    let m = flexmbd_io::parse_dat(text, file).map_err(|e| e.to_string())?;
    let (f, mapped) = if dynamic {
        m.to_dynamic_model_file()
    } else {
        m.to_model_file()
    }
    .map_err(|e| e.to_string())?;
    Ok((f, m.warnings.iter().cloned().chain(mapped).collect()))
}

/// The static path of a model file as every command that linearises about it solves it: the
/// file's `[static]` settings, load steps (a path that stops part-way is the `Err`).
#[allow(clippy::result_large_err)]
pub fn static_path(f: &ModelFile) -> Result<StaticSolution, Stopped> {
    let opts = static_options(&f.settings, None, None).unwrap_or_else(|e| panic!("{}", e.0));
    solve_path(&f.model, &opts, |_, _| {})
}

/// The state space of `flexmbd statespace --input INPUTS… --output OUTPUTS…` about `step` of a
/// model file `f` read from `file` (the specs parsed as the command parses them).
pub fn state_space_of(
    f: &ModelFile,
    file: &str,
    step: &StepResult,
    inputs: &[&str],
    outputs: &[&str],
    opts: &StateSpaceOptions,
) -> StateSpace {
    let specs: Vec<_> = inputs
        .iter()
        .map(|s| parse_input(&f.model, file, "--input", s).unwrap_or_else(|e| panic!("{}", e.0)))
        .collect();
    let (forces, motions) = split_inputs(&specs);
    let outputs: Vec<_> = outputs
        .iter()
        .map(|s| parse_output(&f.model, file, "--output", s).unwrap_or_else(|e| panic!("{}", e.0)))
        .collect();
    state_space_with_motions(&f.model, step, &forces, &motions, &outputs, opts)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The state space and the `statespace --json [--at-step K]` document about step `k` of the
/// complete static path `sol` of `f` (the path is solved once by the caller).
pub fn statespace_doc(
    f: &ModelFile,
    file: &str,
    sol: &StaticSolution,
    k: usize,
    inputs: &[&str],
    outputs: &[&str],
    opts: &StateSpaceOptions,
) -> (StateSpace, Value) {
    let step = &sol.steps[k];
    let ss = state_space_of(f, file, step, inputs, outputs, opts);
    let origin = Origin {
        file,
        step: k,
        load_factor: step.load_factor,
        stopped: None,
    };
    let doc = statespace_json(&f.model, origin, &ss);
    (ss, doc)
}
