//! Element outputs of the state-space model (deformations and stress resultants), against
//! closed forms and the statics solver.

use super::motion_tests::{check_base_excitation, damped, out, spring_mass, three_beams};
use super::*;
use crate::statics::last_step;
use faer::c64;

/// |g − exact| < 1e-9 |exact|.
fn assert_close(g: c64, exact: c64, what: &str) {
    assert!(
        (g - exact).norm() < 1e-9 * exact.norm(),
        "{what}: {g} vs {exact}"
    );
}

fn element(model: &Model, name: &str) -> usize {
    model.elements.iter().position(|e| e.name == name).unwrap()
}

/// Spring–mass (k = EA/L = 2000 N/m, m = 0.5 kg, base held): under a force F on the mass the
/// spring stretches by X = F/(m(ωₙ² − ω² + 2iζωₙω)) and carries σ = k X, so
/// σ/F = ωₙ²/(ωₙ² − ω² + 2iζωₙω) (1 at DC: the spring carries the load); the deformation and
/// its rates are X, sX, s²X. Driven at its base instead (input ü), σ = k (x − u) and
/// σ/ü = −k/(s² + 2ζωₙs + ωₙ²).
#[test]
fn spring_force_and_deformation_match_closed_forms() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let model = spring_mass(m, ea, l);
    let step = last_step(&model, 2);
    let (k, wn) = (ea / l, (ea / l / m).sqrt());
    let t = element(&model, "t");
    let outputs = [
        Output {
            probe: Probe::Force {
                element: t,
                mode: 0,
            },
            kind: OutputKind::Disp,
        },
        Output {
            probe: Probe::Deformation {
                element: t,
                mode: 0,
            },
            kind: OutputKind::Disp,
        },
        Output {
            probe: Probe::Deformation {
                element: t,
                mode: 0,
            },
            kind: OutputKind::Vel,
        },
        Output {
            probe: Probe::Deformation {
                element: t,
                mode: 0,
            },
            kind: OutputKind::Acc,
        },
    ];
    assert_eq!(outputs[0].name(&model), "t:1:force");
    assert_eq!(outputs[0].unit(&model), "N");
    assert_eq!(outputs[2].name(&model), "t:1:def:vel");
    assert_eq!(outputs[3].unit(&model), "m/s²");
    let input = Input {
        node: model.node_id("m").unwrap(),
        dof: Dof::X,
    };
    let base = Motion::Node {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let zeta = 0.03;
    let ss = state_space_with_motions(&model, &step, &[input], &[base], &outputs, &damped(zeta))
        .unwrap();
    let dc = ss.dc_gain().unwrap();
    assert!((dc[(0, 0)] - 1.0).abs() < 1e-12, "{}", dc[(0, 0)]);
    assert!((dc[(1, 0)] - 1.0 / k).abs() < 1e-12 / k);
    for f in [0.05, 0.7, 1.2, 6.0].map(|r| r * wn / (2.0 * std::f64::consts::PI)) {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let den = s * s + s * (2.0 * zeta * wn) + wn * wn;
        let g = ss.frequency_response(f);
        let x = c64::new(1.0 / m, 0.0) / den;
        for (o, exact) in [(0, x * k), (1, x), (2, x * s), (3, x * s * s)] {
            assert_close(g[o][0], exact, "g[o][0]");
        }
        let exact = c64::new(-k, 0.0) / den;
        assert_close(g[0][1], exact, "g[0][1]");
    }
}

/// The transmissibility check of the motion tests holds for the spring's deformation too:
/// e = x − u, so with the base held-and-driven the mass output and the deformation output
/// differ by the base motion (quasi-static gain 0 for the deformation).
#[test]
fn deformation_output_is_the_relative_motion() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let model = spring_mass(m, ea, l);
    let step = last_step(&model, 2);
    let wn = (ea / l / m).sqrt();
    let t = element(&model, "t");
    let base = Motion::Node {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let mut outputs = vec![
        out(&model, "m", Dof::X, OutputKind::Disp),
        out(&model, "m", Dof::X, OutputKind::Vel),
        out(&model, "m", Dof::X, OutputKind::Acc),
    ];
    outputs.push(Output {
        probe: Probe::Deformation {
            element: t,
            mode: 0,
        },
        kind: OutputKind::Disp,
    });
    check_base_excitation(
        &model,
        &step,
        base,
        &outputs,
        wn,
        &[1.0, 0.0, 0.0, 0.0],
        |_, _, s, g| {
            // e = x − u: G_e s² = G_x s² − 1
            assert!((g[3][0] * s * s - (g[0][0] * s * s - 1.0)).norm() < 1e-9);
        },
    );
}

/// Cantilever of 3 beams (L = 0.3 m) with an axial pre-stress and a lateral tip load `fy`:
/// point masses for the dynamics.
fn loaded_cantilever(fy: f64) -> Model {
    let mut b = three_beams("loaded-cantilever");
    b.fix("n0", None).unwrap();
    for (k, m) in [(1, 0.01), (2, 0.02), (3, 0.05)] {
        b.add_point_mass(&format!("n{k}"), m).unwrap();
    }
    b.add_load("n3", [-30.0, 0.2 + fy, 0.0], [0.0; 3]).unwrap();
    b.build().unwrap()
}

/// Deflected, pre-stressed beams: the static gain of every deformation and stress resultant of
/// the first element per unit tip force equals the central difference of two statics solves
/// (the σ and e that `flexmbd static` reports), also on the sparse path.
#[test]
fn element_outputs_static_gain_matches_statics_solver() {
    let model = loaded_cantilever(0.0);
    let step = last_step(&model, 4);
    let tip = Input {
        node: model.node_id("n3").unwrap(),
        dof: Dof::Y,
    };
    let el = element(&model, "b0");
    let mut outputs = Vec::new();
    for mode in 0..6 {
        for probe in [
            Probe::Deformation { element: el, mode },
            Probe::Force { element: el, mode },
        ] {
            outputs.push(Output {
                probe,
                kind: OutputKind::Disp,
            });
        }
    }
    let h = 1e-4;
    let plus = last_step(&loaded_cantilever(h), 4);
    let minus = last_step(&loaded_cantilever(-h), 4);
    let ie = model.elements[el].ie;
    let fd: Vec<f64> = (0..6)
        .flat_map(|a| {
            [
                (plus.e[ie + a] - minus.e[ie + a]) / (2.0 * h),
                (plus.sigma[ie + a] - minus.sigma[ie + a]) / (2.0 * h),
            ]
        })
        .collect();
    for solver in [EigenSolver::Dense, EigenSolver::Sparse] {
        let ss = state_space(
            &model,
            &step,
            &[tip],
            &outputs,
            &StateSpaceOptions {
                modes: Some(4),
                static_correction: true,
                solver,
                ..Default::default()
            },
        )
        .unwrap();
        let g = ss.dc_gain().unwrap();
        for (o, v) in fd.iter().enumerate() {
            // deformations and forces have their own scales
            let scale = fd
                .iter()
                .skip(o % 2)
                .step_by(2)
                .fold(0.0f64, |a, b| a.max(b.abs()));
            assert!(
                (g[(o, 0)] - v).abs() < 1e-6 * scale,
                "{solver:?} {}: {} vs {v}",
                outputs[o].name(&model),
                g[(o, 0)]
            );
        }
    }
}

/// The actuator of `actuator_spring_mass` (truss `act`, elongation an input, mass m_a = 0.3 kg
/// at its end `a`) carries the spring: with the stroke held, a force F on the mass gives the
/// actuator tension σ/F = ωₙ²/(ωₙ² − ω² + 2iζωₙω) (equilibrium of the massless-in-effect held
/// node `a`: σ_act = σ_spring); with the stroke driven (input ë), the node accelerates with ë,
/// so σ_act = σ_spring − m_a ë and σ/ë = −k/(s² + 2ζωₙs + ωₙ²) − m_a.
#[test]
fn actuator_force_is_the_constraint_reaction() {
    let (ma, m, ea, l) = (0.3, 0.5, 200.0, 0.1);
    let model = super::deformation_tests::actuator_spring_mass(ma, m, ea, l);
    let step = last_step(&model, 2);
    let (k, wn) = (ea / l, (ea / l / m).sqrt());
    let act = element(&model, "act");
    let outputs = [Output {
        probe: Probe::Force {
            element: act,
            mode: 0,
        },
        kind: OutputKind::Disp,
    }];
    let zeta = 0.02;
    let ss = state_space_with_motions(
        &model,
        &step,
        &[Input {
            node: model.node_id("m").unwrap(),
            dof: Dof::X,
        }],
        &[Motion::Deformation {
            element: act,
            mode: 0,
        }],
        &outputs,
        &damped(zeta),
    )
    .unwrap();
    let dc = ss.dc_gain().unwrap();
    assert!((dc[(0, 0)] - 1.0).abs() < 1e-12, "{}", dc[(0, 0)]);
    // a slow stroke moves everything rigidly: no force
    assert!(dc[(0, 1)].abs() < 1e-9, "{}", dc[(0, 1)]);
    for f in [0.05, 0.7, 1.2, 6.0].map(|r| r * wn / (2.0 * std::f64::consts::PI)) {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let den = s * s + s * (2.0 * zeta * wn) + wn * wn;
        let g = ss.frequency_response(f);
        let exact = c64::new(wn * wn, 0.0) / den;
        assert_close(g[0][0], exact, "g[0][0]");
        let exact = c64::new(-k, 0.0) / den - ma;
        assert_close(g[0][1], exact, "g[0][1]");
    }
}

/// Deflected, pre-stressed beams pushed by an actuator: the static gains of the actuator force
/// per unit stroke and per unit tip force equal central differences of the σ that
/// `flexmbd static` reports for the actuator (its multiplier), on the dense and on the sparse
/// path (the lowest two modes with the static correction).
#[test]
fn actuator_reaction_static_gain_matches_statics_solver() {
    let build = |stroke: f64, fy: f64| {
        let mut m = super::deformation_tests::actuated_cantilever(stroke);
        let tip = m.node_id("n3").unwrap();
        m.loads.nodal.push(crate::model::NodalLoad {
            node: tip,
            force: [0.0, fy, 0.0],
            moment: [0.0; 3],
        });
        m
    };
    let (p, h) = (0.01, 1e-6);
    let model = build(p, 0.0);
    let step = last_step(&model, 4);
    let act = element(&model, "act");
    let ia = model.elements[act].ie;
    let out = Output {
        probe: Probe::Force {
            element: act,
            mode: 0,
        },
        kind: OutputKind::Disp,
    };
    let ss = state_space_with_motions(
        &model,
        &step,
        &[Input {
            node: model.node_id("n3").unwrap(),
            dof: Dof::Y,
        }],
        &[Motion::Deformation {
            element: act,
            mode: 0,
        }],
        &[out],
        &Default::default(),
    )
    .unwrap();
    let g = ss.dc_gain().unwrap();
    let hf = 1e-3;
    let per_force = (last_step(&build(p, hf), 4).sigma[ia]
        - last_step(&build(p, -hf), 4).sigma[ia])
        / (2.0 * hf);
    let per_stroke = (last_step(&build(p + h, 0.0), 4).sigma[ia]
        - last_step(&build(p - h, 0.0), 4).sigma[ia])
        / (2.0 * h);
    assert!(
        (g[(0, 0)] - per_force).abs() < 1e-6 * per_force.abs(),
        "{} vs {per_force}",
        g[(0, 0)]
    );
    assert!(
        (g[(0, 1)] - per_stroke).abs() < 1e-6 * per_stroke.abs(),
        "{} vs {per_stroke}",
        g[(0, 1)]
    );
    let sparse = state_space_with_motions(
        &model,
        &step,
        &[Input {
            node: model.node_id("n3").unwrap(),
            dof: Dof::Y,
        }],
        &[Motion::Deformation {
            element: act,
            mode: 0,
        }],
        &[out],
        &StateSpaceOptions {
            modes: Some(2),
            static_correction: true,
            solver: EigenSolver::Sparse,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(sparse.solver, EigenSolver::Sparse);
    let g = sparse.dc_gain().unwrap();
    assert!(
        (g[(0, 0)] - per_force).abs() < 1e-6 * per_force.abs(),
        "sparse: {} vs {per_force}",
        g[(0, 0)]
    );
    assert!(
        (g[(0, 1)] - per_stroke).abs() < 1e-6 * per_stroke.abs(),
        "sparse: {} vs {per_stroke}",
        g[(0, 1)]
    );
    let rate = state_space(
        &model,
        &step,
        &[Input {
            node: model.node_id("n3").unwrap(),
            dof: Dof::Y,
        }],
        &[Output {
            kind: OutputKind::Vel,
            ..out
        }],
        &Default::default(),
    );
    assert!(
        matches!(rate, Err(StateSpaceError::ReactionRate { .. })),
        "{rate:?}"
    );
}

/// Support reactions (`NODE:DIR:reaction`) in the convention of `flexmbd static`: the force the
/// support exerts on the structure. Spring–mass with its base held: R = −σ_spring, so
/// R/F = −ωₙ²/(ωₙ² − ω² + 2iζωₙω) for a force on the mass (−1 at DC, as the central difference
/// of the statics reactions), and R/ü = k/(s² + 2ζωₙs + ωₙ²) when the (massless) base is driven.
/// Clamped three-beam cantilever (L = 0.3 m): a tip force F_y needs the clamp force −F_y and
/// clamp moment −F_y L about z.
#[test]
fn support_reactions_match_closed_forms_and_statics() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let model = spring_mass(m, ea, l);
    let step = last_step(&model, 2);
    let (k, wn) = (ea / l, (ea / l / m).sqrt());
    let base = model.node_id("base").unwrap();
    let out = Output {
        probe: Probe::Reaction {
            node: base,
            dof: Dof::X,
        },
        kind: OutputKind::Disp,
    };
    assert_eq!(out.name(&model), "base:x:reaction");
    assert_eq!(out.unit(&model), "N");
    let zeta = 0.02;
    let ss = state_space_with_motions(
        &model,
        &step,
        &[Input {
            node: model.node_id("m").unwrap(),
            dof: Dof::X,
        }],
        &[Motion::Node {
            node: base,
            dof: Dof::X,
        }],
        &[out],
        &damped(zeta),
    )
    .unwrap();
    // statics: a force h on the mass
    let with_load = |h: f64| {
        let mut mm = spring_mass(m, ea, l);
        mm.loads.nodal.push(crate::model::NodalLoad {
            node: mm.node_id("m").unwrap(),
            force: [h, 0.0, 0.0],
            moment: [0.0; 3],
        });
        last_step(&mm, 2).reactions[mm.nodes[base].ix_pos]
    };
    let fd = (with_load(1e-3) - with_load(-1e-3)) / 2e-3;
    let dc = ss.dc_gain().unwrap();
    assert!((fd + 1.0).abs() < 1e-9, "statics {fd}");
    assert!((dc[(0, 0)] - fd).abs() < 1e-9, "{} vs {fd}", dc[(0, 0)]);
    for f in [0.05, 0.7, 1.2, 6.0].map(|r| r * wn / (2.0 * std::f64::consts::PI)) {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let den = s * s + s * (2.0 * zeta * wn) + wn * wn;
        let g = ss.frequency_response(f);
        assert_close(g[0][0], c64::new(-wn * wn, 0.0) / den, "R/F");
        assert_close(g[0][1], c64::new(k, 0.0) / den, "R/ü");
    }
    // the clamp of a cantilever
    let mut b = three_beams("clamp");
    b.fix("n0", None).unwrap();
    for (n, mass) in [(1, 0.01), (2, 0.02), (3, 0.05)] {
        b.add_point_mass(&format!("n{n}"), mass).unwrap();
    }
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let n0 = model.node_id("n0").unwrap();
    let outs: Vec<Output> = [Dof::Y, Dof::Rz]
        .iter()
        .map(|&dof| Output {
            probe: Probe::Reaction { node: n0, dof },
            kind: OutputKind::Disp,
        })
        .collect();
    let ss = state_space(
        &model,
        &step,
        &[Input {
            node: model.node_id("n3").unwrap(),
            dof: Dof::Y,
        }],
        &outs,
        &Default::default(),
    )
    .unwrap();
    let dc = ss.dc_gain().unwrap();
    assert!((dc[(0, 0)] + 1.0).abs() < 1e-9, "{}", dc[(0, 0)]);
    assert!((dc[(1, 0)] + 0.3).abs() < 1e-9, "{}", dc[(1, 0)]);
    assert_eq!(outs[1].unit(&model), "N·m");
}
