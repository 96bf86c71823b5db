//! The Rust side of `bench/python_overhead.py`: the same library calls that `Model.check()`
//! and `Model.modes()` make, in process, timed per call (the fastest of repeated calls, robust
//! on a loaded machine). Prints one JSON line: `{"check_s": …, "modes_s": …, "repeat": …}`.
//!
//! `cargo bench -p flexmbd-py --bench rust_calls -- MODEL.toml [REPEAT]`

use flexmbd_core::dynamics::{modes_with, EigenSolver, ModalOptions};
use flexmbd_core::kinematics::classify::{classify, ClassifyOptions};
use flexmbd_core::statics::{solve_path, StaticOptions};
use std::time::Instant;

fn fastest(v: Vec<f64>) -> f64 {
    v.into_iter().fold(f64::INFINITY, f64::min)
}

fn time(repeat: usize, mut f: impl FnMut()) -> f64 {
    f();
    fastest(
        (0..repeat)
            .map(|_| {
                let t = Instant::now();
                f();
                t.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

fn main() {
    // `cargo bench` passes `--bench`; the model and the repeat count are the other arguments
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let Some(path) = args.first() else {
        eprintln!("usage: rust_calls MODEL.toml [REPEAT]");
        std::process::exit(2);
    };
    let repeat: usize = args.get(1).and_then(|r| r.parse().ok()).unwrap_or(200);
    let file = match flexmbd_io::read_model_file(std::path::Path::new(path)) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let model = &file.model;
    let check_s = time(repeat, || {
        let c = classify(model, &ClassifyOptions::default());
        std::hint::black_box(c.is_ok());
    });
    let opts = flexmbd_io::requests::static_options(&file.settings, None, None)
        .unwrap_or_else(|_| StaticOptions::default());
    let modal = ModalOptions::with_solver(EigenSolver::Auto);
    let modes_s = time(repeat, || {
        let ok = solve_path(model, &opts, |_, _| {}).ok().and_then(|sol| {
            sol.steps
                .last()
                .map(|s| modes_with(model, s, 10, &modal).is_ok())
        });
        std::hint::black_box(ok);
    });
    println!("{{\"check_s\": {check_s:e}, \"modes_s\": {modes_s:e}, \"repeat\": {repeat}}}");
}
