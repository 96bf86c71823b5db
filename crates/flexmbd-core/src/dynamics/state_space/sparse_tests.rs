//! The sparse state space (lowest modes by Lanczos, static feedthrough from a sparse solve)
//! against the dense one, the static compliance and the Euler–Bernoulli closed form.

use super::tests::{all_io, cantilever, rel_err};
use super::*;
use crate::linearized::{compliance, Tangent};
use crate::statics::last_step;

fn opts(solver: EigenSolver, modes: usize, static_correction: bool) -> StateSpaceOptions {
    StateSpaceOptions {
        damping: 0.02,
        modes: Some(modes),
        static_correction,
        solver,
        ..Default::default()
    }
}

/// Same truncated model on both paths: the eigenvalues, D and the frequency response (which
/// do not depend on the signs of the modes) agree, and the DC gain is the static compliance.
#[test]
fn sparse_state_space_equals_dense_with_static_correction() {
    for rotary in [true, false] {
        for load in [-20.0, 50.0] {
            let model = cantilever(12, rotary, load);
            let step = last_step(&model, 2);
            let tip = model.node_id("n12").unwrap();
            let mid = model.node_id("n6").unwrap();
            let (inputs, mut outputs) = all_io(&model, tip);
            for kind in [OutputKind::Vel, OutputKind::Acc] {
                outputs.push(Output::node(mid, Dof::Y, kind));
            }
            let dense = state_space(
                &model,
                &step,
                &inputs,
                &outputs,
                &opts(EigenSolver::Dense, 5, true),
            )
            .unwrap();
            let sparse = state_space(
                &model,
                &step,
                &inputs,
                &outputs,
                &opts(EigenSolver::Sparse, 5, true),
            )
            .unwrap();
            let case = format!("rotary {rotary}, load {load}");
            assert_eq!(sparse.n_modes(), 5, "{case}");
            assert_eq!(
                (sparse.ndof, sparse.massless),
                (dense.ndof, dense.massless),
                "{case}"
            );
            for (a, b) in sparse.eigenvalues.iter().zip(&dense.eigenvalues) {
                assert!((a - b).abs() < 1e-8 * b, "{case}: {a} vs {b}");
            }
            let dmax = dense.d.norm_max();
            assert!((&sparse.d - &dense.d).norm_max() < 1e-8 * dmax, "{case}");
            let f1 = dense.frequencies()[0];
            for f in [0.1 * f1, 0.9 * f1, 3.0 * f1, 40.0 * f1] {
                let (gs, gd) = (sparse.frequency_response(f), dense.frequency_response(f));
                for o in 0..outputs.len() {
                    // entries far below the largest of their row are round-off couplings
                    let row = gd[o].iter().fold(0.0f64, |m, g| m.max(g.norm()));
                    for j in 0..inputs.len() {
                        assert!(
                            (gs[o][j] - gd[o][j]).norm() <= 1e-7 * gd[o][j].norm() + 1e-10 * row,
                            "{case}, f {f}, ({o}, {j}): {} vs {}",
                            gs[o][j],
                            gd[o][j]
                        );
                    }
                }
            }
            let lin = Tangent::new(&model, &step);
            let c = compliance(&lin, tip).unwrap();
            let dc = sparse.dc_gain().unwrap();
            let dc6 = Mat::from_fn(6, 6, |i, j| dc[(i, j)]);
            assert!(rel_err(&dc6, &c.global) < 1e-6, "{case}");
        }
    }
}

/// Massless twist (no rotary inertia): the sparse path cannot separate the massless static
/// response from the dropped modes', so D carries both even without --static-correction; the
/// DC gain is still exact, and a warning says so.
#[test]
fn sparse_state_space_with_massless_directions_keeps_the_static_gain() {
    let model = cantilever(10, false, -20.0);
    let step = last_step(&model, 2);
    let tip = model.node_id("n10").unwrap();
    let (inputs, outputs) = all_io(&model, tip);
    let ss = state_space(
        &model,
        &step,
        &inputs,
        &outputs,
        &opts(EigenSolver::Sparse, 4, false),
    )
    .unwrap();
    assert!(ss.massless > 0);
    assert!(
        ss.warnings.iter().any(|w| w.contains("without inertia")),
        "{:?}",
        ss.warnings
    );
    let lin = Tangent::new(&model, &step);
    let c = compliance(&lin, tip).unwrap();
    let dc = ss.dc_gain().unwrap();
    assert!(rel_err(&dc, &c.global) < 1e-6);
}

/// Above the dense limit the automatic choice is the sparse path (and it needs --modes): a
/// 520-element cantilever (3120 degrees of freedom) with 6 modes and the static correction has
/// the Euler–Bernoulli tip compliances L/EA, L³/(3 EI) and L/EI (Hermite elements are exact at
/// the nodes), and its first frequency agrees with the converged 12-element dense model to
/// 0.1 %.
#[test]
fn large_model_goes_sparse_and_keeps_the_closed_form_compliance() {
    let n = 520;
    let model = cantilever(n, true, 0.0);
    assert!(velocity_dof(&model) > DENSE_STATE_SPACE_DOF);
    let step = last_step(&model, 1);
    let tip = model.node_id(&format!("n{n}")).unwrap();
    let (inputs, outputs) = all_io(&model, tip);
    let no_modes = state_space(&model, &step, &inputs, &outputs, &Default::default());
    assert!(
        matches!(no_modes, Err(StateSpaceError::SparseNeedsModes { .. })),
        "{no_modes:?}"
    );
    let ss = state_space(
        &model,
        &step,
        &inputs,
        &outputs,
        &opts(EigenSolver::Auto, 6, true),
    )
    .unwrap();
    assert_eq!(ss.n_modes(), 6);
    let dc = ss.dc_gain().unwrap();
    // cantilever(): L = 0.1, EA = 2e6; local y = global z (orientation vector), so bending
    // along global y is about local y (EI_y = 1) and along global z about local z (EI_z = 3)
    let l: f64 = 0.1;
    for (i, exact) in [
        (0, l / 2e6),
        (1, l.powi(3) / 3.0),
        (2, l.powi(3) / (3.0 * 3.0)),
        (5, l / 1.0),
        (4, l / 3.0),
    ] {
        assert!(
            (dc[(i, i)] - exact).abs() < 1e-9 * exact,
            "{i}: {} vs {exact}",
            dc[(i, i)]
        );
    }
    // the same beam with 12 elements on the dense path: converged lowest frequency
    let small = cantilever(12, true, 0.0);
    let s_step = last_step(&small, 1);
    let s_tip = small.node_id("n12").unwrap();
    let (si, so) = all_io(&small, s_tip);
    let dense = state_space(
        &small,
        &s_step,
        &si,
        &so,
        &opts(EigenSolver::Dense, 2, false),
    )
    .unwrap();
    let (f_big, f_small) = (ss.frequencies()[0], dense.frequencies()[0]);
    assert!(
        (f_big - f_small).abs() < 1e-3 * f_small,
        "{f_big} vs {f_small}"
    );
}

/// Motion inputs on the sparse path: moving the clamp of a cantilever along y moves the
/// unloaded beam rigidly, so the tip follows one to one (quasi-static gain 1, and the DC gain of
/// a tip force is still the static compliance L³/(3 EI_y)).
#[test]
fn sparse_state_space_takes_motion_inputs() {
    let model = cantilever(4, true, 0.0);
    let step = last_step(&model, 1);
    let tip = model.node_id("n4").unwrap();
    let motion = Motion::Node {
        node: model.node_id("n0").unwrap(),
        dof: Dof::Y,
    };
    let ss = state_space_with_motions(
        &model,
        &step,
        &[Input {
            node: tip,
            dof: Dof::Y,
        }],
        &[motion],
        &[Output::node(tip, Dof::Y, OutputKind::Disp)],
        &opts(EigenSolver::Sparse, 2, true),
    )
    .unwrap();
    assert_eq!(ss.solver, EigenSolver::Sparse);
    let g = ss.dc_gain().unwrap();
    assert!((g[(0, 1)] - 1.0).abs() < 1e-9, "{}", g[(0, 1)]);
    let exact = 0.1f64.powi(3) / 3.0;
    assert!((g[(0, 0)] - exact).abs() < 1e-9 * exact, "{}", g[(0, 0)]);
}
