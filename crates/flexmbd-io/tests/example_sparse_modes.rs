//! The sparse eigen path on the example models (rigid platforms, pre-stress along a stroke,
//! exactly degenerate pairs): the frequencies and mode shapes of the dense path, at the io
//! level (the example read with `flexmbd_io`, the core's modal analysis on both paths; the
//! command line's `--solver` option is tested in `crates/flexmbd-cli/tests/sparse_modes.rs`).

use flexmbd_core::assembly::mass::mass_times;
use flexmbd_core::dynamics::{modes_with, EigenSolver, Modal, ModalError, ModalOptions};
use flexmbd_core::statics::{solve, StaticOptions, StepResult};
use flexmbd_core::Model;

mod common;
use common::example as example_path;

fn example(name: &str) -> (Model, Vec<StepResult>) {
    let f = flexmbd_io::read_model_file(&example_path(name)).expect("example reads");
    let opts = StaticOptions {
        steps: f.settings.steps.unwrap_or(10),
        ..Default::default()
    };
    let sol = solve(&f.model, &opts, |_, _| {}).expect("static solution");
    (f.model, sol.steps)
}

fn modal(model: &Model, step: &StepResult, count: usize, solver: EigenSolver) -> Modal {
    modes_with(model, step, count, &ModalOptions::with_solver(solver)).expect("modes")
}

/// Same eigenvalues (relative `tol`), counts and mode spaces.
fn assert_agree(model: &Model, step: &StepResult, count: usize, tol: f64) -> Modal {
    let d = modal(model, step, count, EigenSolver::Dense);
    let s = modal(model, step, count, EigenSolver::Sparse);
    assert_eq!((d.ndof, d.massless), (s.ndof, s.massless));
    assert_eq!(d.modes.len(), s.modes.len());
    for (k, (a, b)) in d.modes.iter().zip(&s.modes).enumerate() {
        assert!(
            (a.eigenvalue - b.eigenvalue).abs() <= tol * a.eigenvalue.abs(),
            "mode {k}: dense {} sparse {}",
            a.eigenvalue,
            b.eigenvalue
        );
    }
    // each sparse mode lies in the span of the dense modes of its eigenvalue
    let refs: Vec<&[f64]> = d.modes.iter().map(|m| m.shape.as_slice()).collect();
    let md = mass_times(model, &step.x, &refs);
    for (k, b) in s.modes.iter().enumerate() {
        let cluster: Vec<usize> = (0..d.modes.len())
            .filter(|&j| (d.modes[j].eigenvalue - b.eigenvalue).abs() <= 1e-6 * b.eigenvalue.abs())
            .collect();
        if cluster.last() == Some(&(d.modes.len() - 1)) {
            continue; // the cluster may go on beyond the modes computed
        }
        let span: f64 = cluster
            .iter()
            .map(|&j| {
                let p: f64 = b.shape.iter().zip(&md[j]).map(|(u, v)| u * v).sum();
                p * p
            })
            .sum();
        assert!((span - 1.0).abs() < 1e-6, "mode {k}: {span}");
        // an isolated mode has the same kinetic energy split per node on both paths (the
        // sparse one sums the rows of uᵀ M u in its own coordinates, the dense one in x)
        if cluster.len() == 1 {
            let a = &d.modes[cluster[0]];
            let of = |m: &flexmbd_core::dynamics::Mode, node: usize| {
                m.kinetic
                    .iter()
                    .find(|t| t.0 == node)
                    .map_or((0.0, 0.0), |t| (t.1, t.2))
            };
            for node in a.kinetic.iter().chain(&b.kinetic).map(|t| t.0) {
                let (p, q) = (of(a, node), of(b, node));
                assert!(
                    (p.0 - q.0).abs() < 1e-6 && (p.1 - q.1).abs() < 1e-6,
                    "mode {k}, node {node}: dense {p:?}, sparse {q:?}"
                );
            }
        }
    }
    s
}

#[test]
fn paper_guides_with_rigid_platforms() {
    // five sheets: 8.21 Hz first (docs/dynamics.md); six sheets: modes 2 and 3 an exact pair,
    // which the sparse path finds twice
    let (model, steps) = example("paper_dynamic_5_sheets.toml");
    let s = assert_agree(&model, steps.last().unwrap(), 10, 1e-9);
    assert!((s.modes[0].frequency - 8.214).abs() < 1e-3);
    let (model, steps) = example("paper_dynamic_6_sheets.toml");
    let s = assert_agree(&model, steps.last().unwrap(), 10, 1e-9);
    let (f2, f3) = (s.modes[1].frequency, s.modes[2].frequency);
    assert!((f2 - f3).abs() < 1e-6 * f2, "{f2} {f3}");
}

#[test]
fn strip_and_stroke_with_prestress() {
    let (model, steps) = example("strip_f01.toml");
    assert_agree(&model, steps.last().unwrap(), 10, 1e-9);
    // the parallel leaf guide along its 5 mm stroke: pre-stress, a held input
    let (model, steps) = example("parallel_leaf_stroke.toml");
    for step in steps.iter().step_by(5) {
        assert_agree(&model, step, 8, 1e-8);
    }
}

#[test]
fn over_constrained_kinematic_example() {
    // the kinematic six-sheet guide holds its inputs (docs/dynamics.md) and has a self-stress:
    // more rigid constraints than coordinates, one repeating the others. The dense path finds
    // that nothing is left to vibrate; the sparse one cannot factor repeated constraints and
    // says so, and the automatic choice falls back to the dense path.
    let (model, steps) = example("folded_sheet_guide_6.toml");
    let step = steps.last().unwrap();
    let run = |solver| modes_with(&model, step, 6, &ModalOptions::with_solver(solver));
    assert!(matches!(run(EigenSolver::Dense), Err(ModalError::NoDof)));
    assert!(matches!(run(EigenSolver::Auto), Err(ModalError::NoDof)));
    match run(EigenSolver::Sparse) {
        Err(e @ ModalError::SparseSingular) => {
            assert!(e.to_string().contains("dense eigen solver"))
        }
        other => panic!("{:?}", other.map(|m| m.ndof)),
    }
}
