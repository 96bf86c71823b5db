//! Prescribed-motion inputs of the state-space model, against closed forms and the statics
//! solver.

use super::*;
use crate::model::ElementSpec;
use crate::model::ModelBuilder;
use crate::section::BeamProps;
use crate::statics::last_step;
use faer::c64;

/// Point mass `m` at x = L on a truss (k = EA/L) whose other end `base` has its x as an input
/// coordinate; y and z of both nodes fixed.
pub(super) fn spring_mass(m: f64, ea: f64, l: f64) -> Model {
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

/// The default options with modal damping ratio `zeta`.
pub(super) fn damped(zeta: f64) -> StateSpaceOptions {
    StateSpaceOptions {
        damping: zeta,
        ..Default::default()
    }
}

pub(super) fn out(model: &Model, node: &str, dof: Dof, kind: OutputKind) -> Output {
    Output::node(model.node_id(node).unwrap(), dof, kind)
}

/// Base excitation of a spring–mass: X/U = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²) (modal damping acts
/// on the spring's deformation, the relative motion); for ζ = 0 this is ωₙ²/(ωₙ² − ω²). The
/// model's input is ü, so X/U = G(s) s².
#[test]
fn spring_mass_base_excitation_matches_closed_form() {
    let (m, ea, l) = (0.5, 200.0, 0.1);
    let model = spring_mass(m, ea, l);
    let step = last_step(&model, 2);
    let wn = (ea / l / m).sqrt();
    let motion = Motion::Node {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let outputs = [
        out(&model, "m", Dof::X, OutputKind::Disp),
        out(&model, "m", Dof::X, OutputKind::Vel),
        out(&model, "m", Dof::X, OutputKind::Acc),
    ];
    check_base_excitation(
        &model,
        &step,
        motion,
        &outputs,
        wn,
        &[1.0, 0.0, 0.0],
        |_, _, _, _| {},
    );
}

/// C (sI − A)⁻¹ B + D by a dense complex solve.
pub(super) fn resolvent(ss: &StateSpace, s: c64) -> Vec<Vec<c64>> {
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

/// Base-excitation transmissibility with modal damping on the relative coordinate:
/// (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²) (for ζ = 0: ωₙ²/(ωₙ² − ω²)).
pub(super) fn transmissibility(s: c64, wn: f64, zeta: f64) -> c64 {
    (s * (2.0 * zeta * wn) + wn * wn) / (s * s + s * (2.0 * zeta * wn) + wn * wn)
}

/// A one-mode system driven by one motion input, for ζ = 0 and ζ = 0.04: one mode with
/// ω² = ωₙ², the quasi-static gains `g0` of the outputs, and outputs 0, 1, 2 (displacement,
/// velocity and acceleration of the driven inertia) with X/U = [`transmissibility`], from the
/// modal sum and from the resolvent of (A, B, C, D). The input is ü, so X/U = G(s) s². Then
/// `more(ss, f, s, g)` checks the other outputs at every frequency.
pub(super) fn check_base_excitation(
    model: &Model,
    step: &StepResult,
    motion: Motion,
    outputs: &[Output],
    wn: f64,
    g0: &[f64],
    more: impl Fn(&StateSpace, f64, c64, &[Vec<c64>]),
) {
    for zeta in [0.0, 0.04] {
        let ss =
            state_space_with_motions(model, step, &[], &[motion], outputs, &damped(zeta)).unwrap();
        assert_eq!(ss.n_modes(), 1);
        assert_eq!(ss.n_states(), 4);
        assert!((ss.eigenvalues[0] - wn * wn).abs() < 1e-9 * wn * wn);
        let gs = ss.motion_static_gain();
        for (o, e) in g0.iter().enumerate() {
            assert!((gs[(o, 0)] - e).abs() < 1e-12, "{o}: {}", gs[(o, 0)]);
        }
        let fn_hz = wn / (2.0 * std::f64::consts::PI);
        for f in [0.01, 0.5, 0.97, 1.1, 8.0].map(|r| r * fn_hz) {
            let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
            let exact = transmissibility(s, wn, zeta);
            let g = ss.frequency_response(f);
            // resolvent C (sI − A)⁻¹ B + D, independent of the modal sum
            let dense = resolvent(&ss, s);
            for (o, p) in [(0usize, 0i32), (1, 1), (2, 2)] {
                // X/U = G s² / sᵖ
                let xu = g[o][0] * s * s / s.powi(p);
                assert!(
                    (xu - exact).norm() < 1e-9 * exact.norm(),
                    "ζ {zeta}, f {f}, output {o}: {xu} vs {exact}"
                );
                assert!((dense[o][0] - g[o][0]).norm() < 1e-9 * g[o][0].norm());
            }
            more(&ss, f, s, &g);
        }
    }
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
    let step = last_step(&model, 2);
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
    let motion = Motion::Node {
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
    let plus = last_step(&clamped_guided(n, tension, Some(h)), 2);
    let minus = last_step(&clamped_guided(n, tension, Some(-h)), 2);
    let mut scale = 0.0f64;
    let fd: Vec<f64> = outputs
        .iter()
        .map(|o| {
            let i = model.nodes[o.node_dof().unwrap().0].ix_pos + o.node_dof().unwrap().1.index();
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
    let mut b = three_beams_of("cantilever", 0.1, 2e6);
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
    let step = last_step(&model, 2);
    let motion = Motion::Node {
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
    let loaded = last_step(&point_mass_cantilever(-grav), 2);
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

/// A motion input on a free coordinate, or a rotation of a node without rotation
/// coordinates, is refused with a specific error.
#[test]
fn motion_on_free_or_missing_coordinate_is_refused() {
    let model = spring_mass(0.5, 200.0, 0.1);
    let step = last_step(&model, 2);
    let outputs = [out(&model, "m", Dof::X, OutputKind::Disp)];
    let free = Motion::Node {
        node: model.node_id("m").unwrap(),
        dof: Dof::X,
    };
    let e = state_space_with_motions(&model, &step, &[], &[free], &outputs, &Default::default())
        .unwrap_err();
    assert!(matches!(e, StateSpaceError::MotionNotHeld { .. }), "{e}");
    let rot = Motion::Node {
        node: model.node_id("base").unwrap(),
        dof: Dof::Rz,
    };
    let e = state_space_with_motions(&model, &step, &[], &[rot], &outputs, &Default::default())
        .unwrap_err();
    assert!(matches!(e, StateSpaceError::NoRotation { .. }), "{e}");
    // a free rotation (the tip of a cantilever) cannot be moved
    let model = point_mass_cantilever(0.0);
    let step = last_step(&model, 2);
    let outputs = [out(&model, "n3", Dof::Y, OutputKind::Disp)];
    let tip = Motion::Node {
        node: model.node_id("n3").unwrap(),
        dof: Dof::Rz,
    };
    let e = state_space_with_motions(&model, &step, &[], &[tip], &outputs, &Default::default())
        .unwrap_err();
    assert!(matches!(e, StateSpaceError::MotionNotHeld { .. }), "{e}");
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
    let step = last_step(&model, 2);
    let motion = Motion::Node {
        node: model.node_id("base").unwrap(),
        dof: Dof::X,
    };
    let outputs = [
        out(&model, "c", Dof::X, OutputKind::Disp),
        out(&model, "c", Dof::X, OutputKind::Acc),
        out(&model, "m", Dof::X, OutputKind::Disp),
    ];
    let zeta = 0.02;
    let ss =
        state_space_with_motions(&model, &step, &[], &[motion], &outputs, &damped(zeta)).unwrap();
    assert_eq!(ss.ndof, 1);
    let wn = (ea / l / m).sqrt();
    for f in [1.0, 10.0, 30.0] {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let g = ss.frequency_response(f);
        assert!((g[0][0] * s * s - 1.0).norm() < 1e-9);
        assert!((g[1][0] - 1.0).norm() < 1e-9);
        let exact = transmissibility(s, wn, zeta);
        assert!((g[2][0] * s * s - exact).norm() < 1e-9 * exact.norm());
    }
}

/// A rotor (inertia J about z) on a torsion spring k (hinge about z) whose base rotation about
/// z is enforced: θ/θ_base = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²), ωₙ² = k/J (modal damping on the
/// spring's twist, the relative rotation, as for the translational base excitation). The input
/// is the angular acceleration, so θ/θ_base = G(s) s²; the base itself follows with gain 1.
#[test]
fn torsion_spring_base_rotation_matches_closed_form() {
    let (k, j) = (0.8, 2e-4);
    let mut b = ModelBuilder::new("rotor");
    b.add_node("b", [0.0; 3], true).unwrap();
    b.add_node_at("m", "b").unwrap();
    b.add_element(
        "h",
        &["b", "m"],
        ElementSpec::Hinge {
            axis: [0.0, 0.0, 1.0],
            k,
        },
        &[1],
        &[],
    )
    .unwrap();
    b.fix("b", Some(&[Dof::X, Dof::Y, Dof::Z, Dof::Rx, Dof::Ry]))
        .unwrap();
    b.input("b", Some(&[Dof::Rz])).unwrap();
    b.add_inertia("m", [j, 0.0, 0.0, j, 0.0, j]).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 2);
    let wn = (k / j).sqrt();
    let motion = Motion::Node {
        node: model.node_id("b").unwrap(),
        dof: Dof::Rz,
    };
    assert_eq!(motion.unit(&model), "rad/s²");
    assert_eq!(motion.name(&model), "b:rz:motion");
    let outputs = [
        out(&model, "m", Dof::Rz, OutputKind::Disp),
        out(&model, "m", Dof::Rz, OutputKind::Vel),
        out(&model, "m", Dof::Rz, OutputKind::Acc),
        out(&model, "b", Dof::Rz, OutputKind::Disp),
        out(&model, "m", Dof::Rx, OutputKind::Disp),
    ];
    let g0 = [1.0, 0.0, 0.0, 1.0, 0.0];
    check_base_excitation(&model, &step, motion, &outputs, wn, &g0, |_, _, s, g| {
        assert!((g[3][0] * s * s - 1.0).norm() < 1e-12);
        assert!(g[4][0].norm() < 1e-12 * g[0][0].norm());
    });
}

/// Cantilever of 3 beams along x (L = 0.3 m) with point masses, clamped at n0 except for rz,
/// which is an input (prescribed to `rz` when given); dead tip load `load`.
fn rotated_clamp(load: [f64; 3], rz: Option<f64>) -> Model {
    let mut b = three_beams("rotated-clamp");
    b.fix("n0", Some(&[Dof::X, Dof::Y, Dof::Z, Dof::Rx, Dof::Ry]))
        .unwrap();
    match rz {
        Some(v) => b.prescribe_coordinate("n0", Dof::Rz, v).unwrap(),
        None => b.input("n0", Some(&[Dof::Rz])).unwrap(),
    }
    for (k, m) in [(1, 0.01), (2, 0.02), (3, 0.05)] {
        b.add_point_mass(&format!("n{k}"), m).unwrap();
    }
    if load != [0.0; 3] {
        b.add_load("n3", load, [0.0; 3]).unwrap();
    }
    b.build().unwrap()
}

/// A builder with 3 massless beams n0–n1–n2–n3 along x (L = 0.3 m, EA = 2e4 N, GJ = 0.7,
/// EI_y = 1, EI_z = 3 N·m², local y along global z).
pub(super) fn three_beams(name: &str) -> ModelBuilder {
    three_beams_of(name, 0.3, 2e4)
}

/// [`three_beams`] of length `l` [m] and axial stiffness `ea` [N].
fn three_beams_of(name: &str, l: f64, ea: f64) -> ModelBuilder {
    let mut b = ModelBuilder::new(name);
    let props = BeamProps {
        ea,
        gj: 0.7,
        eiy: 1.0,
        eiz: 3.0,
        ..Default::default()
    };
    b.add_beam_chain(
        "",
        [0.0; 3],
        [l, 0.0, 0.0],
        3,
        Some([0.0, 0.0, 1.0]),
        Some(props),
    )
    .unwrap();
    b
}

/// Rotation angle about z of a node rotated in the xy plane, from its Euler parameters.
pub(super) fn angle_z(model: &Model, x: &[f64], node: &str) -> f64 {
    let r = model.nodes[model.node_id(node).unwrap()].ix_rot.unwrap();
    2.0 * x[r + 3].atan2(x[r])
}

/// Rotating the clamp of a cantilever about z: unloaded, the quasi-static response is the rigid
/// rotation of the whole beam (y of a node = its distance from the clamp per radian, x = 0, every
/// rotation 1); under a dead tip load (pre-stress, the load does not turn with the beam) it
/// equals the central difference of statics solves with the clamp rotation prescribed to ±h.
#[test]
fn clamp_rotation_static_gain_is_rigid_and_matches_statics_solver() {
    let outputs_of = |model: &Model| -> Vec<Output> {
        ["n1", "n2", "n3"]
            .iter()
            .flat_map(|nd| {
                [
                    out(model, nd, Dof::X, OutputKind::Disp),
                    out(model, nd, Dof::Y, OutputKind::Disp),
                    out(model, nd, Dof::Rz, OutputKind::Disp),
                ]
            })
            .chain([out(model, "n0", Dof::Rz, OutputKind::Disp)])
            .collect()
    };
    // unloaded: rigid rotation
    let model = rotated_clamp([0.0; 3], None);
    let step = last_step(&model, 2);
    let motion = Motion::Node {
        node: model.node_id("n0").unwrap(),
        dof: Dof::Rz,
    };
    let outputs = outputs_of(&model);
    let ss = state_space_with_motions(
        &model,
        &step,
        &[],
        &[motion],
        &outputs,
        &StateSpaceOptions::default(),
    )
    .unwrap();
    let g = ss.motion_static_gain();
    let rigid = [0.0, 0.1, 1.0, 0.0, 0.2, 1.0, 0.0, 0.3, 1.0, 1.0];
    for (o, e) in rigid.iter().enumerate() {
        assert!(
            (g[(o, 0)] - e).abs() < 1e-10,
            "{}: {} vs {e}",
            outputs[o].name(&model),
            g[(o, 0)]
        );
    }
    assert!(ss.warnings.is_empty(), "{:?}", ss.warnings);
    // at low frequency every output follows the clamp: Θ/Θ_base → the rigid gains
    let f = 1e-4 * ss.frequencies()[0];
    let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
    let fr = ss.frequency_response(f);
    for (o, e) in rigid.iter().enumerate() {
        assert!((fr[o][0] * s * s - e).norm() < 1e-6, "{o}");
    }
    // pre-stressed: against the statics solver
    let load = [20.0, 4.0, 0.0];
    let model = rotated_clamp(load, None);
    let step = last_step(&model, 2);
    let outputs = outputs_of(&model);
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
    let h = 1e-5;
    let plus = last_step(&rotated_clamp(load, Some(h)), 2);
    let minus = last_step(&rotated_clamp(load, Some(-h)), 2);
    let dth = angle_z(&model, &plus.x, "n0") - angle_z(&model, &minus.x, "n0");
    assert!((dth - 2.0 * h).abs() < 1e-3 * h, "{dth}");
    let mut differs = 0.0f64;
    for (o, e) in rigid.iter().enumerate() {
        let op = &outputs[o];
        let name = &model.nodes[op.node_dof().unwrap().0].name;
        let v = if op.node_dof().unwrap().1.is_rotation() {
            (angle_z(&model, &plus.x, name) - angle_z(&model, &minus.x, name)) / dth
        } else {
            let i = model.nodes[op.node_dof().unwrap().0].ix_pos + op.node_dof().unwrap().1.index();
            (plus.x[i] - minus.x[i]) / dth
        };
        assert!(
            (g[(o, 0)] - v).abs() < 1e-6 * e.abs().max(0.3),
            "{}: {} vs {v}",
            op.name(&model),
            g[(o, 0)]
        );
        differs = differs.max((v - e).abs());
    }
    // the dead load makes the response differ from the rigid rotation
    assert!(differs > 1e-3, "{differs}");
}

/// The same clamp, first turned by 0.3 rad (`[[prescribe]]`), then moved: the direction
/// ½ Λ̄ᵀ e_z is taken at the current orientation, so the quasi-static response is the rigid
/// rotation of the turned beam: node at distance r from the clamp moves by r (−sin 0.3, cos 0.3)
/// per radian, every rotation 1.
#[test]
fn motion_of_a_turned_clamp_is_rigid_rotation_about_the_current_state() {
    let th: f64 = 0.3;
    let model = rotated_clamp([0.0; 3], Some(th));
    let step = last_step(&model, 2);
    assert!((angle_z(&model, &step.x, "n3") - th).abs() < 1e-9);
    let motion = Motion::Node {
        node: model.node_id("n0").unwrap(),
        dof: Dof::Rz,
    };
    let mut outputs = Vec::new();
    let mut expect = Vec::new();
    for (nd, r) in [("n1", 0.1), ("n2", 0.2), ("n3", 0.3)] {
        outputs.push(out(&model, nd, Dof::X, OutputKind::Disp));
        outputs.push(out(&model, nd, Dof::Y, OutputKind::Disp));
        outputs.push(out(&model, nd, Dof::Rz, OutputKind::Disp));
        outputs.push(out(&model, nd, Dof::Rx, OutputKind::Disp));
        expect.extend([-r * th.sin(), r * th.cos(), 1.0, 0.0]);
    }
    let ss = state_space_with_motions(
        &model,
        &step,
        &[],
        &[motion],
        &outputs,
        &StateSpaceOptions::default(),
    )
    .unwrap();
    let g = ss.motion_static_gain();
    for (o, e) in expect.iter().enumerate() {
        assert!(
            (g[(o, 0)] - e).abs() < 1e-9,
            "{}: {} vs {e}",
            outputs[o].name(&model),
            g[(o, 0)]
        );
    }
}
