//! Prescribed-motion inputs of the state-space model, against closed forms and the statics
//! solver.

use super::*;
use crate::model::ElementSpec;
use crate::model::ModelBuilder;
use crate::section::BeamProps;
use crate::statics::{solve, StaticOptions};
use faer::c64;

fn last_step(model: &Model) -> StepResult {
    let mut sol = solve(
        model,
        &StaticOptions {
            steps: 2,
            ..Default::default()
        },
        |_, _| {},
    )
    .unwrap();
    sol.steps.pop().unwrap()
}

/// Point mass `m` at x = L on a truss (k = EA/L) whose other end `base` has its x as an input
/// coordinate; y and z of both nodes fixed.
fn spring_mass(m: f64, ea: f64, l: f64) -> Model {
    let mut b = ModelBuilder::new("spring-mass");
    b.add_node("base", [0.0; 3], false).unwrap();
    b.add_node("m", [l, 0.0, 0.0], false).unwrap();
    b.add_element("t", &["base", "m"], ElementSpec::Truss { ea }, &[1], &[])
        .unwrap();
    b.fix("base", Some(&[Dof::Y, Dof::Z])).unwrap();
    b.input("base", Some(&[Dof::X])).unwrap();
    b.fix("m", Some(&[Dof::Y, Dof::Z])).unwrap();
    b.add_point_mass("m", m).unwrap();
    b.build().unwrap()
}

fn out(model: &Model, node: &str, dof: Dof, kind: OutputKind) -> Output {
    Output {
        node: model.node_id(node).unwrap(),
        dof,
        kind,
    }
}

/// Base excitation of a spring–mass: X/U = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²) (modal damping acts
/// on the spring's deformation, the relative motion); for ζ = 0 this is ωₙ²/(ωₙ² − ω²). The
/// model's input is ü, so X/U = G(s) s².
#[test]
fn spring_mass_base_excitation_matches_closed_form() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let model = spring_mass(m, ea, l);
    let step = last_step(&model);
    let wn = (ea / l / m).sqrt();
    let motion = Motion {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let outputs = [
        out(&model, "m", Dof::X, OutputKind::Disp),
        out(&model, "m", Dof::X, OutputKind::Vel),
        out(&model, "m", Dof::X, OutputKind::Acc),
    ];
    for zeta in [0.0, 0.05] {
        let ss = state_space_with_motions(
            &model,
            &step,
            &[],
            &[motion],
            &outputs,
            &StateSpaceOptions {
                damping: zeta,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(ss.n_modes(), 1);
        assert_eq!(ss.n_states(), 4);
        assert!((ss.eigenvalues[0] - wn * wn).abs() < 1e-9 * wn * wn);
        for f in [0.3, 5.0, 9.0, 11.0, 40.0] {
            let w = 2.0 * std::f64::consts::PI * f;
            let s = c64::new(0.0, w);
            let exact =
                (s * (2.0 * zeta * wn) + wn * wn) / (s * s + s * (2.0 * zeta * wn) + wn * wn);
            let g = ss.frequency_response(f);
            // resolvent C (sI − A)⁻¹ B + D, independent of the modal sum
            let dense = resolvent(&ss, s);
            for (o, p) in [(0usize, 0i32), (1, 1), (2, 2)] {
                // X/U = G s² / sᵖ
                let xu = g[o][0] * s * s / s.powi(p);
                assert!(
                    (xu - exact).norm() < 1e-9 * exact.norm(),
                    "f {f} o {o}: {xu} vs {exact}"
                );
                assert!((dense[o][0] - g[o][0]).norm() < 1e-9 * g[o][0].norm());
            }
        }
    }
}

/// C (sI − A)⁻¹ B + D by a dense complex solve.
fn resolvent(ss: &StateSpace, s: c64) -> Vec<Vec<c64>> {
    let n = ss.a.nrows();
    let m = Mat::<c64>::from_fn(n, n, |i, j| {
        let d = if i == j { s } else { c64::new(0.0, 0.0) };
        d - c64::new(ss.a[(i, j)], 0.0)
    });
    let b = Mat::<c64>::from_fn(n, ss.b.ncols(), |i, j| c64::new(ss.b[(i, j)], 0.0));
    let x = faer::prelude::Solve::solve(&m.partial_piv_lu(), &b);
    (0..ss.c.nrows())
        .map(|o| {
            (0..ss.b.ncols())
                .map(|j| {
                    let mut g = c64::new(ss.d[(o, j)], 0.0);
                    for k in 0..n {
                        g += x[(k, j)] * ss.c[(o, k)];
                    }
                    g
                })
                .collect()
        })
        .collect()
}

/// Beam of `n` elements along x from `a` (clamped) to `e` whose y is an input (everything else
/// of `e` fixed except x), with a tension `tension` along x on `e` (pre-stress) and a point mass
/// at every inner node.
fn clamped_guided(n: usize, tension: f64, prescribe: Option<f64>) -> Model {
    let mut b = ModelBuilder::new("clamped-guided");
    let props = BeamProps {
        ea: 2e5,
        gj: 0.7,
        eiy: 1.0,
        eiz: 3.0,
        rho_a: 0.1,
        rho_i: [2e-6, 1e-6, 1e-6],
        ..Default::default()
    };
    b.add_beam_chain(
        "",
        [0.0; 3],
        [0.2, 0.0, 0.0],
        n,
        Some([0.0, 0.0, 1.0]),
        Some(props),
    )
    .unwrap();
    let end = format!("n{n}");
    b.fix("n0", None).unwrap();
    b.fix(&end, Some(&[Dof::Z, Dof::Rx, Dof::Ry, Dof::Rz]))
        .unwrap();
    match prescribe {
        Some(v) => b.prescribe_coordinate(&end, Dof::Y, v).unwrap(),
        None => b.input(&end, Some(&[Dof::Y])).unwrap(),
    }
    for k in 1..n {
        b.add_point_mass(&format!("n{k}"), 0.02).unwrap();
    }
    if tension != 0.0 {
        b.add_load(&end, [tension, 0.0, 0.0], [0.0; 3]).unwrap();
    }
    b.build().unwrap()
}

/// DC consistency: the static response per unit enforced displacement equals the statics
/// solver's response to a small prescribed stroke (central difference), with pre-stress.
#[test]
fn motion_static_gain_matches_statics_solver() {
    let n = 4;
    let tension = 30.0;
    let model = clamped_guided(n, tension, None);
    let step = last_step(&model);
    let end = format!("n{n}");
    let outputs: Vec<Output> = ["n1", "n2", "n3", end.as_str()]
        .iter()
        .flat_map(|nd| {
            [
                out(&model, nd, Dof::X, OutputKind::Disp),
                out(&model, nd, Dof::Y, OutputKind::Disp),
            ]
        })
        .collect();
    let motion = Motion {
        node: model.node_id(&end).unwrap(),
        dof: Dof::Y,
    };
    let ss = state_space_with_motions(
        &model,
        &step,
        &[],
        &[motion],
        &outputs,
        &StateSpaceOptions::default(),
    )
    .unwrap();
    let g = ss.dc_gain().unwrap();
    let h = 1e-6;
    let plus = last_step(&clamped_guided(n, tension, Some(h)));
    let minus = last_step(&clamped_guided(n, tension, Some(-h)));
    let mut scale = 0.0f64;
    let fd: Vec<f64> = outputs
        .iter()
        .map(|o| {
            let i = model.nodes[o.node].ix_pos + o.dof.index();
            let v = (plus.x[i] - minus.x[i]) / (2.0 * h);
            scale = scale.max(v.abs());
            v
        })
        .collect();
    for (o, v) in fd.iter().enumerate() {
        assert!(
            (g[(o, 0)] - v).abs() < 1e-6 * scale,
            "{}: {} vs {v}",
            outputs[o].name(&model),
            g[(o, 0)]
        );
    }
    // the moved node follows exactly, and the inner nodes move in between
    assert!((g[(7, 0)] - 1.0).abs() < 1e-12);
    assert!(g[(3, 0)] > 0.1 && g[(3, 0)] < 0.9);
    // eigenvalues of A: the modal poles plus a double pole at 0 per motion input
    let mut poles = ss.a.eigenvalues().unwrap();
    poles.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    assert!(poles[0].norm() < 1e-6 && poles[1].norm() < 1e-6);
    assert_eq!(poles.len(), 2 * ss.n_modes() + 2);
    let wmin = ss.eigenvalues[0].sqrt();
    assert!(poles[2].norm() > 0.5 * wmin);
}

/// Cantilever of 3 massless beams with point masses at n1..n3, clamped at n0, optionally
/// under gravity (statics only).
fn point_mass_cantilever(gravity_y: f64) -> Model {
    let mut b = ModelBuilder::new("cantilever");
    let props = BeamProps {
        ea: 2e6,
        gj: 0.7,
        eiy: 1.0,
        eiz: 3.0,
        ..Default::default()
    };
    b.add_beam_chain(
        "",
        [0.0; 3],
        [0.1, 0.0, 0.0],
        3,
        Some([0.0, 0.0, 1.0]),
        Some(props),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    for (k, m) in [(1, 0.01), (2, 0.02), (3, 0.05)] {
        b.add_point_mass(&format!("n{k}"), m).unwrap();
    }
    if gravity_y != 0.0 {
        b.set_gravity([0.0, gravity_y, 0.0]).unwrap();
    }
    b.build().unwrap()
}

/// Moving the clamp of a cantilever in y: the quasi-static response is the rigid translation
/// (gain 1 on every y, 0 on x and rz); at low frequency the outputs follow the support
/// (X/U → 1, Ÿ/Ü → 1), and the first correction is the inertial load of the rigid
/// acceleration: lim (G(s) − 1/s²) of the tip displacement per ü equals the static tip
/// deflection under gravity −1 m/s² along y (statics solver, massless beams so that the
/// gravity load equals the point-mass inertia exactly; the massless rotations are condensed).
#[test]
fn support_motion_of_cantilever_is_rigid_plus_inertial_load() {
    let model = point_mass_cantilever(0.0);
    let step = last_step(&model);
    let motion = Motion {
        node: model.node_id("n0").unwrap(),
        dof: Dof::Y,
    };
    let outputs = [
        out(&model, "n3", Dof::Y, OutputKind::Disp),
        out(&model, "n2", Dof::Y, OutputKind::Vel),
        out(&model, "n3", Dof::Y, OutputKind::Acc),
        out(&model, "n3", Dof::X, OutputKind::Disp),
        out(&model, "n3", Dof::Rz, OutputKind::Disp),
        out(&model, "n0", Dof::Y, OutputKind::Disp),
    ];
    let ss = state_space_with_motions(
        &model,
        &step,
        &[],
        &[motion],
        &outputs,
        &StateSpaceOptions::default(),
    )
    .unwrap();
    assert!(ss.massless > 0);
    let g0 = ss.motion_static_gain();
    for (o, e) in [1.0, 0.0, 0.0, 0.0, 0.0, 1.0].iter().enumerate() {
        assert!((g0[(o, 0)] - e).abs() < 1e-12, "{o}: {}", g0[(o, 0)]);
    }
    // static tip deflection per unit acceleration −y (linear: small g)
    let grav = 1e-3;
    let loaded = last_step(&point_mass_cantilever(-grav));
    let iy = model.nodes[model.node_id("n3").unwrap()].ix_pos + 1;
    let delta = (loaded.x[iy] - step.x[iy]) / grav;
    assert!(delta < 0.0);
    let f1 = ss.frequencies()[0];
    let f = 1e-3 * f1;
    let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
    let g = ss.frequency_response(f);
    let rel = g[0][0] - 1.0 / (s * s);
    assert!(
        (rel.re - delta).abs() < 1e-4 * delta.abs(),
        "{rel} vs {delta}"
    );
    assert!(rel.im.abs() < 1e-4 * delta.abs());
    // X/U, velocity and acceleration ratios → 1 at low frequency
    let xu = g[0][0] * s * s;
    let vu = g[1][0] * s;
    let au = g[2][0];
    for r in [xu, vu, au] {
        assert!((r - 1.0).norm() < 1e-4, "{r}");
    }
    assert!((g[5][0] * s * s - 1.0).norm() < 1e-12);
    assert!((g[3][0] * s * s).norm() < 1e-4);
    assert!(ss.warnings.is_empty(), "{:?}", ss.warnings);
}

/// A motion input on a free coordinate or a rotation is refused with a specific error.
#[test]
fn motion_on_free_or_rotation_is_refused() {
    let model = spring_mass(0.5, 200.0, 0.1);
    let step = last_step(&model);
    let outputs = [out(&model, "m", Dof::X, OutputKind::Disp)];
    let free = Motion {
        node: model.node_id("m").unwrap(),
        dof: Dof::X,
    };
    let e = state_space_with_motions(&model, &step, &[], &[free], &outputs, &Default::default())
        .unwrap_err();
    assert!(matches!(e, StateSpaceError::MotionNotHeld { .. }), "{e}");
    let rot = Motion {
        node: model.node_id("base").unwrap(),
        dof: Dof::Rz,
    };
    let e = state_space_with_motions(&model, &step, &[], &[rot], &outputs, &Default::default())
        .unwrap_err();
    assert!(matches!(e, StateSpaceError::MotionRotation { .. }), "{e}");
}

/// A held coordinate tied to a free one by a rigid truss: the enforced motion is lifted onto
/// the constraint (t_m = e_base + e_c), so `c` follows exactly (gain 1, also in acceleration at
/// any frequency) and the mass behind the spring sees the same transmissibility as without the
/// link, (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²), ωₙ² = k/m.
#[test]
fn motion_through_a_rigid_link_is_lifted_onto_the_constraint() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let mut b = ModelBuilder::new("rigid-link");
    b.add_node("base", [0.0; 3], false).unwrap();
    b.add_node("c", [0.05, 0.0, 0.0], false).unwrap();
    b.add_node("m", [0.05 + l, 0.0, 0.0], false).unwrap();
    b.add_element(
        "r",
        &["base", "c"],
        ElementSpec::Truss { ea: 0.0 },
        &[],
        &[],
    )
    .unwrap();
    b.add_element("t", &["c", "m"], ElementSpec::Truss { ea }, &[1], &[])
        .unwrap();
    for n in ["base", "c", "m"] {
        b.fix(n, Some(&[Dof::Y, Dof::Z])).unwrap();
    }
    b.input("base", Some(&[Dof::X])).unwrap();
    b.add_point_mass("m", m).unwrap();
    b.add_point_mass("c", 0.1).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model);
    let motion = Motion {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let outputs = [
        out(&model, "c", Dof::X, OutputKind::Disp),
        out(&model, "c", Dof::X, OutputKind::Acc),
        out(&model, "m", Dof::X, OutputKind::Disp),
    ];
    let zeta = 0.02;
    let ss = state_space_with_motions(
        &model,
        &step,
        &[],
        &[motion],
        &outputs,
        &StateSpaceOptions {
            damping: zeta,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(ss.ndof, 1);
    let wn = (ea / l / m).sqrt();
    for f in [1.0, 10.0, 30.0] {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let g = ss.frequency_response(f);
        assert!((g[0][0] * s * s - 1.0).norm() < 1e-9);
        assert!((g[1][0] - 1.0).norm() < 1e-9);
        let exact = (s * (2.0 * zeta * wn) + wn * wn) / (s * s + s * (2.0 * zeta * wn) + wn * wn);
        assert!((g[2][0] * s * s - exact).norm() < 1e-9 * exact.norm());
    }
}
