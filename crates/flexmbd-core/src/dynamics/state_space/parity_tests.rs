//! Dense and sparse state spaces of the same model agree (issue 12): force, moment and
//! prescribed-motion inputs (of a clamp's translation and rotation, and of an actuator's
//! stroke); node, deformation and stress-resultant outputs, support reactions and the force of
//! a held deformation. The dense result is validated against closed forms and the statics
//! solver elsewhere (tests, motion_tests, element_output_tests); here the sparse one is compared
//! with it through quantities that do not depend on the signs of the modes: the eigenvalues,
//! the static gains and the frequency response, with all modes kept, and truncated with the
//! static correction. Reactions are compared undamped: the damping force of a modal damping on
//! a held quantity depends on how the held direction is lifted (module docs of `sparse`).

use super::tests::cantilever;
use super::*;
use crate::statics::last_step;

/// Both paths with `modes` kept (None: all on the dense path, all modes that carry mass on
/// the sparse one), compared to `tol` relative to the largest entry of each output's row.
#[allow(clippy::too_many_arguments)]
fn compare(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    modes: Option<usize>,
    damping: f64,
    tol: f64,
) -> (StateSpace, StateSpace) {
    let opts = |solver, modes| StateSpaceOptions {
        damping,
        modes,
        static_correction: true,
        solver,
        ..Default::default()
    };
    let dense = state_space_with_motions(
        model,
        step,
        inputs,
        motions,
        outputs,
        &opts(EigenSolver::Dense, modes),
    )
    .unwrap();
    let count = modes.unwrap_or(dense.available_modes);
    let sparse = state_space_with_motions(
        model,
        step,
        inputs,
        motions,
        outputs,
        &opts(EigenSolver::Sparse, Some(count)),
    )
    .unwrap();
    assert_eq!(sparse.solver, EigenSolver::Sparse);
    assert_eq!(sparse.n_modes(), dense.n_modes());
    assert_eq!((sparse.ndof, sparse.massless), (dense.ndof, dense.massless));
    for (a, b) in sparse.eigenvalues.iter().zip(&dense.eigenvalues) {
        assert!((a - b).abs() < tol * b.abs(), "ω²: {a} vs {b}");
    }
    let rows = |g: &[Vec<faer::c64>]| -> Vec<f64> {
        g.iter()
            .map(|r| r.iter().fold(0.0f64, |m, z| m.max(z.norm())))
            .collect()
    };
    let (gd, gs) = (dense.dc_gain().unwrap(), sparse.dc_gain().unwrap());
    // an output's scale: its largest DC gain or response near the first resonance (the DC
    // gain of an acceleration is round-off of zero)
    let f = dense.frequencies();
    let near = rows(&dense.frequency_response(1.3 * f[0]));
    for o in 0..outputs.len() {
        let scale = (0..gd.ncols()).fold(near[o], |m, j| m.max(gd[(o, j)].abs()));
        for j in 0..gd.ncols() {
            assert!(
                (gd[(o, j)] - gs[(o, j)]).abs() <= tol * scale,
                "DC {}, column {j}: dense {} sparse {}",
                outputs[o].name(model),
                gd[(o, j)],
                gs[(o, j)]
            );
        }
    }
    for hz in [0.37 * f[0], 1.3 * f[0], 0.5 * (f[1] + f[2])] {
        let (a, b) = (dense.frequency_response(hz), sparse.frequency_response(hz));
        let scale = rows(&a);
        for o in 0..outputs.len() {
            for j in 0..a[o].len() {
                assert!(
                    (a[o][j] - b[o][j]).norm() <= tol * scale[o],
                    "{hz} Hz, {}, column {j}: dense {} sparse {}",
                    outputs[o].name(model),
                    a[o][j],
                    b[o][j]
                );
            }
        }
    }
    (dense, sparse)
}

/// A pre-stressed cantilever with rotary inertia (no massless direction): forces and moments
/// on the tip, the clamp moved along y and turned about z, every kind of output.
fn cantilever_io(model: &Model) -> (Vec<Input>, Vec<Motion>, Vec<Output>) {
    let (tip, mid, clamp) = (
        model.node_id("n6").unwrap(),
        model.node_id("n3").unwrap(),
        model.node_id("n0").unwrap(),
    );
    let inputs = vec![
        Input {
            node: tip,
            dof: Dof::Y,
        },
        Input {
            node: mid,
            dof: Dof::Rz,
        },
        Input {
            node: tip,
            dof: Dof::Z,
        },
    ];
    let motions = vec![
        Motion::Node {
            node: clamp,
            dof: Dof::Y,
        },
        Motion::Node {
            node: clamp,
            dof: Dof::Rz,
        },
    ];
    let mut outputs: Vec<Output> = [OutputKind::Disp, OutputKind::Vel, OutputKind::Acc]
        .into_iter()
        .flat_map(|kind| {
            [
                Output::node(tip, Dof::Y, kind),
                Output::node(mid, Dof::Rz, kind),
            ]
        })
        .collect();
    outputs.push(Output::node(tip, Dof::Z, OutputKind::Disp));
    for (probe, kind) in [
        (
            Probe::Deformation {
                element: 1,
                mode: 5,
            },
            OutputKind::Disp,
        ),
        (
            Probe::Force {
                element: 0,
                mode: 4,
            },
            OutputKind::Disp,
        ),
        (
            Probe::Force {
                element: 0,
                mode: 5,
            },
            OutputKind::Acc,
        ),
        (
            Probe::Reaction {
                node: clamp,
                dof: Dof::Y,
            },
            OutputKind::Disp,
        ),
        (
            Probe::Reaction {
                node: clamp,
                dof: Dof::Rz,
            },
            OutputKind::Disp,
        ),
        (
            Probe::Reaction {
                node: clamp,
                dof: Dof::Ry,
            },
            OutputKind::Disp,
        ),
    ] {
        outputs.push(Output { probe, kind });
    }
    (inputs, motions, outputs)
}

#[test]
fn sparse_equals_dense_with_all_modes_motions_and_reactions() {
    for load in [0.0, -20.0, 40.0] {
        let model = cantilever(6, true, load);
        let step = last_step(&model, 2);
        let (inputs, motions, outputs) = cantilever_io(&model);
        // every mode of the model from Lanczos: the highest ones are resolved to about 1e-7
        let (dense, _) = compare(&model, &step, &inputs, &motions, &outputs, None, 0.0, 1e-6);
        assert_eq!(dense.massless, 0);
    }
}

#[test]
fn sparse_equals_dense_truncated_with_static_correction() {
    let model = cantilever(6, true, -20.0);
    let step = last_step(&model, 2);
    let (inputs, motions, outputs) = cantilever_io(&model);
    compare(
        &model,
        &step,
        &inputs,
        &motions,
        &outputs,
        Some(4),
        0.0,
        1e-7,
    );
    // with damping the motion and node outputs still agree (reactions: module docs)
    let plain: Vec<Output> = outputs
        .iter()
        .copied()
        .filter(|o| !o.is_reaction(&model))
        .collect();
    compare(
        &model,
        &step,
        &inputs,
        &motions,
        &plain,
        Some(4),
        0.03,
        1e-7,
    );
}

/// An actuator (a truss with a prescribed elongation) pushes the tip of a deflected,
/// pre-stressed three-beam cantilever: its stroke as a motion input, its force (a constraint
/// reaction) and the clamp reactions as outputs.
#[test]
fn sparse_equals_dense_for_an_actuator_stroke_and_force() {
    let model = super::deformation_tests::actuated_cantilever(0.01);
    let step = last_step(&model, 4);
    let act = (0..model.elements.len())
        .find(|&e| model.elements[e].name == "act")
        .unwrap();
    let (tip, clamp) = (model.node_id("n3").unwrap(), model.node_id("n0").unwrap());
    let inputs = [Input {
        node: tip,
        dof: Dof::Y,
    }];
    let motions = [Motion::Deformation {
        element: act,
        mode: 0,
    }];
    let outputs = [
        Output::node(tip, Dof::Y, OutputKind::Disp),
        Output::node(tip, Dof::X, OutputKind::Acc),
        Output {
            probe: Probe::Force {
                element: act,
                mode: 0,
            },
            kind: OutputKind::Disp,
        },
        Output {
            probe: Probe::Reaction {
                node: clamp,
                dof: Dof::Y,
            },
            kind: OutputKind::Disp,
        },
        Output {
            probe: Probe::Reaction {
                node: clamp,
                dof: Dof::Rz,
            },
            kind: OutputKind::Disp,
        },
    ];
    compare(&model, &step, &inputs, &motions, &outputs, None, 0.0, 1e-7);
    compare(
        &model,
        &step,
        &inputs,
        &motions,
        &outputs,
        Some(3),
        0.0,
        1e-7,
    );
}

/// The sparse static gain against the Euler–Bernoulli closed forms of a cantilever
/// (L = 0.1 m, EI_y = 1, EI_z = 3 N·m², `cantilever()`): tip force → tip displacement
/// L³/(3 EI), and the clamp reaction to a tip force is the force itself, reversed, with the
/// clamp moment −F L.
#[test]
fn sparse_static_gains_match_the_cantilever_closed_forms() {
    let model = cantilever(6, true, 0.0);
    let step = last_step(&model, 1);
    let (tip, clamp) = (model.node_id("n6").unwrap(), model.node_id("n0").unwrap());
    let reaction = |dof| Output {
        probe: Probe::Reaction { node: clamp, dof },
        kind: OutputKind::Disp,
    };
    let ss = state_space(
        &model,
        &step,
        &[
            Input {
                node: tip,
                dof: Dof::Y,
            },
            Input {
                node: tip,
                dof: Dof::Z,
            },
        ],
        &[
            Output::node(tip, Dof::Y, OutputKind::Disp),
            Output::node(tip, Dof::Z, OutputKind::Disp),
            reaction(Dof::Y),
            reaction(Dof::Rz),
        ],
        &StateSpaceOptions {
            modes: Some(3),
            static_correction: true,
            solver: EigenSolver::Sparse,
            ..Default::default()
        },
    )
    .unwrap();
    let g = ss.dc_gain().unwrap();
    let l: f64 = 0.1;
    for (o, j, exact) in [
        (0, 0, l.powi(3) / 3.0),
        (1, 1, l.powi(3) / 9.0),
        (2, 0, -1.0),
        (3, 0, -l),
    ] {
        assert!(
            (g[(o, j)] - exact).abs() < 1e-9 * exact.abs(),
            "({o}, {j}): {} vs {exact}",
            g[(o, j)]
        );
    }
}
