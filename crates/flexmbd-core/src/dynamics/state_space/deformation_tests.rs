//! Prescribed-deformation motion inputs of the state-space model (an actuator's elongation, a
//! driven hinge's angle), against closed forms and the statics solver.

use super::motion_tests::{angle_z, check_base_excitation, out, resolvent, three_beams};
use super::*;
use crate::model::{ElementSpec, ModelBuilder};
use crate::statics::last_step;
use faer::c64;

/// A linear actuator (truss `act`, elongation an input) from the fixed ground node `g` to `a`
/// (mass `ma`), then a spring (truss, k = EA/L) from `a` to the mass `m`; all on the x axis,
/// y and z held.
pub(super) fn actuator_spring_mass(ma: f64, m: f64, ea: f64, l: f64) -> Model {
    let mut b = ModelBuilder::new("actuator-spring-mass");
    b.add_node("g", [0.0; 3], false).unwrap();
    b.add_node("a", [0.05, 0.0, 0.0], false).unwrap();
    b.add_node("m", [0.05 + l, 0.0, 0.0], false).unwrap();
    b.add_element(
        "act",
        &["g", "a"],
        ElementSpec::Truss { ea: 0.0 },
        &[],
        &[1],
    )
    .unwrap();
    b.add_element("spring", &["a", "m"], ElementSpec::Truss { ea }, &[1], &[])
        .unwrap();
    b.fix("g", None).unwrap();
    b.fix("a", Some(&[Dof::Y, Dof::Z])).unwrap();
    b.fix("m", Some(&[Dof::Y, Dof::Z])).unwrap();
    b.add_point_mass("a", ma).unwrap();
    b.add_point_mass("m", m).unwrap();
    b.build().unwrap()
}

/// Driving the actuator's elongation e: the actuator end follows exactly (x_a = e, also in
/// acceleration: gain 1, whatever its mass), and the mass behind the spring sees the base
/// excitation transmissibility X/E with ωₙ² = k/m. The input is ë, so X/E = G(s) s².
#[test]
fn actuator_elongation_drives_spring_mass_as_closed_form() {
    let (ma, m, ea, l) = (0.3, 0.5, 200.0, 0.1);
    let model = actuator_spring_mass(ma, m, ea, l);
    let step = last_step(&model, 2);
    let wn = (ea / l / m).sqrt();
    let act = model.elements.iter().position(|e| e.name == "act").unwrap();
    let motion = Motion::Deformation {
        element: act,
        mode: 0,
    };
    assert_eq!(motion.name(&model), "act:1:motion");
    assert_eq!(motion.unit(&model), "m/s²");
    let outputs = [
        out(&model, "m", Dof::X, OutputKind::Disp),
        out(&model, "m", Dof::X, OutputKind::Vel),
        out(&model, "m", Dof::X, OutputKind::Acc),
        out(&model, "a", Dof::X, OutputKind::Disp),
        out(&model, "a", Dof::X, OutputKind::Acc),
    ];
    let g0 = [1.0, 0.0, 0.0, 1.0, 0.0];
    check_base_excitation(&model, &step, motion, &outputs, wn, &g0, |ss, _, s, g| {
        // the actuator end moves with the stroke; its acceleration is the input itself
        assert!((g[3][0] * s * s - 1.0).norm() < 1e-12);
        assert!((g[4][0] - 1.0).norm() < 1e-12);
        assert!((ss.d[(4, 0)] - 1.0).abs() < 1e-12);
        let info = ss.input_info(&model);
        assert_eq!(info[0].deformation, Some((act, 0)));
        assert_eq!(info[0].node, None);
    });
}

/// A driven hinge (angle an input) turns an intermediate rotational node `c`, which carries a
/// rotor of inertia J on a torsion spring k: θ/θ_drive = (2ζωₙs + ωₙ²)/(s² + 2ζωₙs + ωₙ²),
/// ωₙ² = k/J, and `c` follows the drive angle exactly (gain 1).
#[test]
fn driven_hinge_angle_turns_rotor_as_closed_form() {
    let (k, j) = (0.8, 2e-4);
    let mut b = ModelBuilder::new("driven-rotor");
    b.add_node("b", [0.0; 3], true).unwrap();
    b.add_node_at("c", "b").unwrap();
    b.add_node_at("m", "b").unwrap();
    let axis = [0.0, 0.0, 1.0];
    b.add_element(
        "drive",
        &["b", "c"],
        ElementSpec::Hinge { axis, k: 0.0 },
        &[],
        &[1],
    )
    .unwrap();
    b.add_element(
        "spring",
        &["c", "m"],
        ElementSpec::Hinge { axis, k },
        &[1],
        &[],
    )
    .unwrap();
    b.fix("b", None).unwrap();
    b.add_inertia("c", [5e-5, 0.0, 0.0, 5e-5, 0.0, 5e-5])
        .unwrap();
    b.add_inertia("m", [j, 0.0, 0.0, j, 0.0, j]).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 2);
    let wn = (k / j).sqrt();
    let drive = model
        .elements
        .iter()
        .position(|e| e.name == "drive")
        .unwrap();
    let motion = Motion::Deformation {
        element: drive,
        mode: 0,
    };
    assert_eq!(motion.unit(&model), "rad/s²");
    let outputs = [
        out(&model, "m", Dof::Rz, OutputKind::Disp),
        out(&model, "m", Dof::Rz, OutputKind::Vel),
        out(&model, "m", Dof::Rz, OutputKind::Acc),
        out(&model, "c", Dof::Rz, OutputKind::Disp),
        out(&model, "m", Dof::Rx, OutputKind::Disp),
    ];
    let g0 = [1.0, 0.0, 0.0, 1.0, 0.0];
    check_base_excitation(&model, &step, motion, &outputs, wn, &g0, |_, _, s, g| {
        assert!((g[3][0] * s * s - 1.0).norm() < 1e-12);
        assert!(g[4][0].norm() < 1e-12 * g[0][0].norm());
    });
}

/// Cantilever of 3 beams along x (L = 0.3 m, clamped at n0, point masses) pushed sideways at
/// its tip by a linear actuator from the ground node `g` at (0.3, −0.1, 0), whose elongation
/// is prescribed to `stroke`; a dead tip load along x pre-stresses the beam.
pub(super) fn actuated_cantilever(stroke: f64) -> Model {
    let mut b = three_beams("actuated-cantilever");
    b.add_node("g", [0.3, -0.1, 0.0], false).unwrap();
    b.add_element(
        "act",
        &["g", "n3"],
        ElementSpec::Truss { ea: 0.0 },
        &[],
        &[1],
    )
    .unwrap();
    b.prescribe_deformation("act", 1, stroke).unwrap();
    b.fix("n0", None).unwrap();
    b.fix("g", None).unwrap();
    for (k, m) in [(1, 0.01), (2, 0.02), (3, 0.05)] {
        b.add_point_mass(&format!("n{k}"), m).unwrap();
    }
    b.add_load("n3", [-40.0, 0.0, 0.0], [0.0; 3]).unwrap();
    b.build().unwrap()
}

/// DC consistency with pre-stress and a deflected state: the quasi-static response per unit
/// actuator stroke equals the central difference of statics solves with the stroke prescribed
/// to p ± h; and the frequency response matches the resolvent of (A, B, C, D).
#[test]
fn actuator_stroke_static_gain_matches_statics_solver() {
    let p = 0.01;
    let model = actuated_cantilever(p);
    let step = last_step(&model, 4);
    let act = model.elements.iter().position(|e| e.name == "act").unwrap();
    let motion = Motion::Deformation {
        element: act,
        mode: 0,
    };
    let mut outputs = Vec::new();
    for nd in ["n1", "n2", "n3"] {
        for d in [Dof::X, Dof::Y, Dof::Rz] {
            outputs.push(out(&model, nd, d, OutputKind::Disp));
        }
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
    let g = ss.dc_gain().unwrap();
    let h = 1e-6;
    let plus = last_step(&actuated_cantilever(p + h), 4);
    let minus = last_step(&actuated_cantilever(p - h), 4);
    let fd: Vec<f64> = outputs
        .iter()
        .map(|o| {
            let name = &model.nodes[o.node_dof().unwrap().0].name;
            if o.node_dof().unwrap().1 == Dof::Rz {
                (angle_z(&model, &plus.x, name) - angle_z(&model, &minus.x, name)) / (2.0 * h)
            } else {
                let i =
                    model.nodes[o.node_dof().unwrap().0].ix_pos + o.node_dof().unwrap().1.index();
                (plus.x[i] - minus.x[i]) / (2.0 * h)
            }
        })
        .collect();
    let scale = fd.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (o, v) in fd.iter().enumerate() {
        assert!(
            (g[(o, 0)] - v).abs() < 1e-6 * scale,
            "{}: {} vs {v}",
            outputs[o].name(&model),
            g[(o, 0)]
        );
    }
    // the tip moves along the actuator (mostly +y) by about the stroke
    assert!(g[(7, 0)] > 0.5 && g[(7, 0)] < 1.5, "{}", g[(7, 0)]);
    let f1 = ss.frequencies()[0];
    for f in [0.3 * f1, 1.7 * f1] {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f);
        let gm = ss.frequency_response(f);
        let dense = resolvent(&ss, s);
        for o in 0..outputs.len() {
            assert!((dense[o][0] - gm[o][0]).norm() <= 1e-9 * gm[o][0].norm().max(1e-300));
        }
    }
}

/// A flexible deformation, or a rigid body's, cannot be driven; the error says which.
#[test]
fn motion_of_a_flexible_or_rigid_body_deformation_is_refused() {
    let model = actuator_spring_mass(0.3, 0.5, 200.0, 0.1);
    let step = last_step(&model, 2);
    let outputs = [out(&model, "m", Dof::X, OutputKind::Disp)];
    let spring = model
        .elements
        .iter()
        .position(|e| e.name == "spring")
        .unwrap();
    let flexible = Motion::Deformation {
        element: spring,
        mode: 0,
    };
    let e = state_space_with_motions(
        &model,
        &step,
        &[],
        &[flexible],
        &outputs,
        &Default::default(),
    )
    .unwrap_err();
    assert!(
        matches!(e, StateSpaceError::DeformationNotHeld { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("spring"), "{e}");

    let mut b = ModelBuilder::new("rigid");
    b.add_node("a", [0.0; 3], false).unwrap();
    b.add_node("b", [1.0, 0.0, 0.0], false).unwrap();
    b.add_node("c", [2.0, 0.0, 0.0], false).unwrap();
    b.add_element("body", &["a", "b"], ElementSpec::Rigid, &[], &[])
        .unwrap();
    b.add_element("t", &["b", "c"], ElementSpec::Truss { ea: 10.0 }, &[1], &[])
        .unwrap();
    b.fix("a", None).unwrap();
    b.fix("c", Some(&[Dof::Y, Dof::Z])).unwrap();
    b.add_point_mass("c", 1.0).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let body = model
        .elements
        .iter()
        .position(|e| e.name == "body")
        .unwrap();
    let e = state_space_with_motions(
        &model,
        &step,
        &[],
        &[Motion::Deformation {
            element: body,
            mode: 0,
        }],
        &[out(&model, "c", Dof::X, OutputKind::Disp)],
        &Default::default(),
    )
    .unwrap_err();
    assert!(matches!(e, StateSpaceError::RigidBodyMotion { .. }), "{e}");
}
