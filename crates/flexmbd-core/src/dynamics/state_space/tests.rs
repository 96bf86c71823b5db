//! Unit tests of the state-space model: DC gain, poles, frequency response, names, errors.

use super::*;
use crate::dynamics::modes;
use crate::linearized::{compliance, Tangent};
use crate::model::ModelBuilder;
use crate::section::BeamProps;
use crate::statics::last_step;

/// Cantilever of `n` beams along x, clamped at n0, tip mass at the free end. With
/// `rotary` the beams carry rotary inertia; without it the twist of every node is massless
/// (the Hermite translational mass sees bending rotations through the end tangents, but not
/// the twist about the beam axis), so those directions are condensed.
pub(super) fn cantilever(n: usize, rotary: bool, axial_load: f64) -> Model {
    let l = 0.1;
    let mut b = ModelBuilder::new("cantilever");
    let props = BeamProps {
        ea: 2e6,
        gj: 0.7,
        eiy: 1.0,
        eiz: 3.0,
        rho_a: 0.1,
        rho_i: if rotary { [2e-6, 1e-6, 1e-6] } else { [0.0; 3] },
        ..Default::default()
    };
    b.add_beam_chain(
        "",
        [0.0; 3],
        [l, 0.0, 0.0],
        n,
        Some([0.0, 0.0, 1.0]),
        Some(props),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    let tip = format!("n{n}");
    b.add_point_mass(&tip, 0.05).unwrap();
    if axial_load != 0.0 {
        b.add_load(&tip, [axial_load, 0.0, 0.0], [0.0; 3]).unwrap();
    }
    b.build().unwrap()
}

pub(super) fn all_io(model: &Model, node: usize) -> (Vec<Input>, Vec<Output>) {
    let _ = model;
    let inputs = Dof::ALL.iter().map(|&dof| Input { node, dof }).collect();
    let outputs = Dof::ALL
        .iter()
        .map(|&dof| Output::node(node, dof, OutputKind::Disp))
        .collect();
    (inputs, outputs)
}

/// max |a − b| / max |b| over the 6 × 6 block.
pub(super) fn rel_err(a: &Mat<f64>, b: &[[f64; 6]; 6]) -> f64 {
    let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut e = 0.0f64;
    for i in 0..6 {
        for j in 0..6 {
            // entries are compared relative to their row and column scale (translations
            // and rotations differ by orders of magnitude)
            let s = (b[i][i].abs() * b[j][j].abs()).sqrt().max(1e-14 * scale);
            e = e.max((a[(i, j)] - b[i][j]).abs() / s);
        }
    }
    e
}

fn check_dc_gain(model: &Model, opts: &StateSpaceOptions) -> (StateSpace, f64) {
    let step = last_step(model, 2);
    let tip = model
        .node_id(&format!("n{}", model.nodes.len() - 1))
        .unwrap();
    let (inputs, outputs) = all_io(model, tip);
    let ss = state_space(model, &step, &inputs, &outputs, opts).unwrap();
    let lin = Tangent::new(model, &step);
    let c = compliance(&lin, tip).unwrap();
    let dc = ss.dc_gain().unwrap();
    (ss.clone(), rel_err(&dc, &c.global))
}

#[test]
fn dc_gain_equals_static_compliance_all_modes() {
    // (a) force/moment inputs and displacement/rotation outputs on the tip, all modes
    for rotary in [true, false] {
        for load in [0.0, -20.0, 50.0] {
            let model = cantilever(4, rotary, load);
            let (ss, err) = check_dc_gain(&model, &StateSpaceOptions::default());
            assert!(err < 1e-6, "rotary {rotary}, load {load}: {err}");
            assert_eq!(ss.massless > 0, !rotary);
            assert_eq!(ss.n_modes(), ss.ndof - ss.massless);
        }
    }
}

#[test]
fn condensed_model_needs_the_massless_feedthrough() {
    // without rotary inertia the twist is massless: the tip rotation about x responds to a
    // moment about x only through D (no mode carries it)
    let model = cantilever(4, false, 0.0);
    let (ss, _) = check_dc_gain(&model, &StateSpaceOptions::default());
    let (rx, ry) = (3, 4);
    assert!(ss.d[(rx, rx)] > 0.0);
    let dc = ss.dc_gain().unwrap();
    assert!((dc[(rx, rx)] - ss.d[(rx, rx)]).abs() < 1e-9 * dc[(rx, rx)]);
    // a force on the (massive) tip translation has no feedthrough
    for o in 0..6 {
        for j in 0..3 {
            assert!(ss.d[(o, j)].abs() < 1e-12 * dc[(1, 1)], "D[{o}, {j}]");
        }
    }
    // bending rotations carry mass through the Hermite tangents: no feedthrough there
    assert!(ss.d[(ry, ry)].abs() < 1e-9 * dc[(ry, ry)]);
}

#[test]
fn truncated_model_keeps_dc_gain_with_static_correction() {
    for rotary in [true, false] {
        let model = cantilever(4, rotary, -20.0);
        let opts = StateSpaceOptions {
            modes: Some(3),
            static_correction: true,
            ..Default::default()
        };
        let (ss, err) = check_dc_gain(&model, &opts);
        assert_eq!(ss.n_modes(), 3);
        assert!(err < 1e-6, "rotary {rotary}: {err}");
        // without the correction a truncated model misses the static part of higher modes
        let opts = StateSpaceOptions {
            modes: Some(3),
            ..Default::default()
        };
        let (_, err) = check_dc_gain(&model, &opts);
        assert!(err > 1e-6, "rotary {rotary}: {err}");
    }
}

#[test]
fn eigenvalues_of_a_are_the_damped_modal_poles() {
    // (b) eig(A) = −ζω ± iω√(1 − ζ²) for the frequencies of `modes`
    let model = cantilever(4, true, 30.0);
    let step = last_step(&model, 2);
    let tip = model.node_id("n4").unwrap();
    let zeta = 0.05;
    let ss = state_space(
        &model,
        &step,
        &[Input {
            node: tip,
            dof: Dof::Y,
        }],
        &[Output::node(tip, Dof::Y, OutputKind::Disp)],
        &super::motion_tests::damped(zeta),
    )
    .unwrap();
    let modal = modes(&model, &step, usize::MAX).unwrap();
    assert_eq!(modal.modes.len(), ss.n_modes());
    let mut poles = ss.a.eigenvalues().unwrap();
    poles.sort_by(|a, b| {
        a.im.abs()
            .total_cmp(&b.im.abs())
            .then(a.im.total_cmp(&b.im))
    });
    for (k, m) in modal.modes.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * m.frequency;
        let re = -zeta * w;
        let im = w * (1.0 - zeta * zeta).sqrt();
        for (p, sign) in [(poles[2 * k], -1.0), (poles[2 * k + 1], 1.0)] {
            assert!(
                (p.re - re).abs() < 1e-9 * w && (p.im - sign * im).abs() < 1e-9 * w,
                "mode {k}: pole {p} vs {re} ± {im}i"
            );
        }
    }
}

#[test]
fn bode_far_below_resonance_is_the_dc_gain() {
    // (c) |G| and phase at f ≪ f1 equal the DC gain: the magnitude error is ~ (f/f1)², the
    // phase ~ 2ζ f/f1 rad, so at f = 1e-5 f1 both are below 1e-6
    for rotary in [true, false] {
        let model = cantilever(4, rotary, 0.0);
        let step = last_step(&model, 2);
        let tip = model.node_id("n4").unwrap();
        let (inputs, outputs) = all_io(&model, tip);
        let ss = state_space(
            &model,
            &step,
            &inputs,
            &outputs,
            &StateSpaceOptions::default(),
        )
        .unwrap();
        let dc = ss.dc_gain().unwrap();
        let f = 1e-5 * ss.frequencies()[0];
        let g = ss.frequency_response(f);
        for o in 0..6 {
            for j in 0..6 {
                let s = (dc[(o, o)].abs() * dc[(j, j)].abs()).sqrt();
                assert!(
                    (g[o][j] - c64::new(dc[(o, j)], 0.0)).norm() < 1e-6 * s,
                    "({o}, {j}): {} vs {}",
                    g[o][j],
                    dc[(o, j)]
                );
            }
        }
        // collocated displacement/force: magnitude = compliance, phase 0
        let mp = magnitude_phase(&[g[1][1]]);
        assert!((mp[0].0 - dc[(1, 1)]).abs() < 1e-6 * dc[(1, 1)]);
        assert!(mp[0].1.abs() < 1e-3);
    }
}

#[test]
fn frequency_response_matches_dense_resolvent() {
    // the modal evaluation equals C (sI − A)⁻¹ B + D for every output kind
    let model = cantilever(3, true, 10.0);
    let step = last_step(&model, 2);
    let tip = model.node_id("n3").unwrap();
    let mid = model.node_id("n2").unwrap();
    let inputs = [
        Input {
            node: tip,
            dof: Dof::Y,
        },
        Input {
            node: mid,
            dof: Dof::Rz,
        },
    ];
    let outputs: Vec<Output> = [OutputKind::Disp, OutputKind::Vel, OutputKind::Acc]
        .into_iter()
        .flat_map(|kind| {
            [
                Output::node(tip, Dof::Y, kind),
                Output::node(mid, Dof::Rz, kind),
            ]
        })
        .collect();
    let ss = state_space(
        &model,
        &step,
        &inputs,
        &outputs,
        &StateSpaceOptions {
            damping: 0.02,
            ..Default::default()
        },
    )
    .unwrap();
    for f in [0.3 * ss.frequencies()[0], 1.7 * ss.frequencies()[1]] {
        let w = 2.0 * std::f64::consts::PI * f;
        let ns = ss.a.nrows();
        let m = Mat::<c64>::from_fn(ns, ns, |i, j| {
            let d = if i == j {
                c64::new(0.0, w)
            } else {
                c64::new(0.0, 0.0)
            };
            d - c64::new(ss.a[(i, j)], 0.0)
        });
        let bc = Mat::<c64>::from_fn(ns, 2, |i, j| c64::new(ss.b[(i, j)], 0.0));
        let x = faer::prelude::Solve::solve(&m.partial_piv_lu(), &bc);
        let g = ss.frequency_response(f);
        for o in 0..outputs.len() {
            for j in 0..2 {
                let mut want = c64::new(ss.d[(o, j)], 0.0);
                for i in 0..ns {
                    want += x[(i, j)] * ss.c[(o, i)];
                }
                assert!(
                    (g[o][j] - want).norm() < 1e-9 * want.norm().max(1e-30),
                    "f {f}, output {o}, input {j}: {} vs {want}",
                    g[o][j]
                );
            }
        }
    }
}

#[test]
fn names_and_errors() {
    let model = cantilever(2, true, 0.0);
    let tip = model.node_id("n2").unwrap();
    let i = Input {
        node: tip,
        dof: Dof::Rz,
    };
    assert_eq!(i.name(&model), "n2:rz:moment");
    assert_eq!(i.describe(&model), "moment on n2 about global z");
    let o = Output::node(tip, Dof::X, OutputKind::Acc);
    assert_eq!(o.name(&model), "n2:x:acc");
    assert_eq!(o.unit(&model), "m/s²");
    let step = last_step(&model, 2);
    let bad = StateSpaceOptions {
        damping: -0.1,
        ..Default::default()
    };
    assert_eq!(
        state_space(&model, &step, &[i], &[o], &bad).unwrap_err(),
        StateSpaceError::BadDamping(-0.1)
    );
    // an input on the clamped node is held: warning, zero column
    let g = model.node_id("n0").unwrap();
    let ss = state_space(
        &model,
        &step,
        &[Input {
            node: g,
            dof: Dof::X,
        }],
        &[o],
        &StateSpaceOptions::default(),
    )
    .unwrap();
    assert!(ss.warnings[0].contains("held"), "{:?}", ss.warnings);
    assert_eq!(ss.b.norm_max(), 0.0);
}

#[test]
fn ids_of_another_model_are_errors_not_panics() {
    // node, element and mode ids are plain indices: one past the end of this model
    let model = cantilever(2, true, 0.0);
    let step = last_step(&model, 2);
    let tip = model.node_id("n2").unwrap();
    let (n, ne) = (model.nodes.len(), model.elements.len());
    let good_in = Input {
        node: tip,
        dof: Dof::Z,
    };
    let good_out = Output::node(tip, Dof::Z, OutputKind::Disp);
    let opts = StateSpaceOptions::default();
    let bad_in = Input {
        node: n,
        dof: Dof::Z,
    };
    let err = state_space(&model, &step, &[bad_in], &[good_out], &opts).unwrap_err();
    assert!(matches!(err, StateSpaceError::UnknownId(_)), "{err}");
    for probe in [
        Probe::Node {
            node: n,
            dof: Dof::Z,
        },
        Probe::Reaction {
            node: n,
            dof: Dof::Z,
        },
        Probe::Deformation {
            element: ne,
            mode: 0,
        },
        Probe::Force {
            element: 0,
            mode: 6,
        },
    ] {
        let out = Output {
            probe,
            kind: OutputKind::Disp,
        };
        let err = state_space(&model, &step, &[good_in], &[out], &opts).unwrap_err();
        assert!(
            matches!(err, StateSpaceError::UnknownId(_)),
            "{probe:?}: {err}"
        );
    }
    let motion = Motion::Deformation {
        element: ne,
        mode: 0,
    };
    let err =
        state_space_with_motions(&model, &step, &[], &[motion], &[good_out], &opts).unwrap_err();
    assert!(matches!(err, StateSpaceError::UnknownId(_)), "{err}");
}

#[test]
fn log_space_and_phase_unwrap() {
    let f = log_space(1.0, 100.0, 3);
    assert!((f[1] - 10.0).abs() < 1e-12 && (f[2] - 100.0).abs() < 1e-12);
    let g = [
        c64::new(1.0, 0.0),
        c64::new(0.0, -1.0),
        c64::new(-1.0, -1e-9),
        c64::new(-1.0, 1e-9),
    ];
    let mp = magnitude_phase(&g);
    assert!((mp[3].1 + 180.0).abs() < 1e-6, "{mp:?}");
}
