//! The kinematic check in the designer's language (docs/kinematic-analysis.md "Twists and
//! wrenches"): twists of the bodies in the motions, wrenches of the constraints in the
//! self-stresses, the intended freedom and the wires that repair a motion. Every number is
//! derived by hand from the lines of the wires and leaves (reciprocal-screw algebra), in the
//! comments.
//!
//! Conventions of the derivations: a line through p along the unit d is the wrench
//! (F, M₀) = (d, p × d); a twist (ω, v₀) at the origin; their reciprocal product is
//! F · v₀ + M₀ · ω. A vertical line through (x, y) is (0, 0, 1 | y, −x, 0), a line along y
//! through (x, z) is (0, 1, 0 | −z, 0, x).

mod common;

use common::flexures::{leaf_mechanism, wire_guide, wire_guide_with, wire_nodes};
use flexmbd_core::kinematics::classify::{
    classify, classify_intended, Classification, ClassifyOptions,
};
use flexmbd_core::kinematics::freedom::{FreedomMotion, IntendedFreedom};
use flexmbd_core::kinematics::screw::{BodyTwist, BodyWrench, ScrewKind};
use flexmbd_core::kinematics::CheckMethod;
use flexmbd_core::Model;

fn run(m: &Model, intended: &[IntendedFreedom]) -> Classification {
    classify_intended(m, &ClassifyOptions::default(), intended, |_| {}).unwrap()
}

fn translation_x() -> IntendedFreedom {
    IntendedFreedom {
        body: "platform".into(),
        motion: FreedomMotion::Translation {
            direction: [1.0, 0.0, 0.0],
        },
    }
}

fn platform(twists: &[BodyTwist]) -> &BodyTwist {
    twists
        .iter()
        .find(|t| t.body == "platform")
        .expect("the platform moves")
}

fn near(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// |a × b| for unit a, b: zero when parallel.
fn sin_between(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
}

#[test]
fn four_wires_leave_a_rotation_about_a_vertical_axis_and_the_fifth_wire_restores_it() {
    // Wires 1–4 of the five-wire guide, c.x held as generalised coordinate. Constraint lines
    // (a_i, beam elongation rigid): L1 = (0,0,1 | −0.03, 0.05, 0), L2 = (0,0,1 | 0.03, 0.05, 0),
    // L3 = (0,0,1 | 0, −0.05, 0), L4 = (0,1,0 | −0.01, 0, −0.05). Freedom (twists reciprocal
    // to all four): ω must be along z (L1–L3 span f_z, m_x, m_y: v_z = 0, ω_x = ω_y = 0), so
    // T = (0, 0, w | v_x, v_y, 0) with L4: v_y − 0.05 w = 0. Two twists: the translation x and
    // w = 1, v = (v_x, 0.05, 0). c.x held: the velocity of c (the origin) along x is 0, so
    // v_x = 0: T = (0, 0, 1 | 0, 0.05, 0), a rotation (ω · v = 0: pitch 0) about the axis
    // through p with v₀ = p × ω = (p_y, −p_x, 0) = (0, 0.05, 0): p = (−0.05, 0, z), the
    // vertical line through (−0.05, 0), which meets L4 at (−0.05, 0, 0.01).
    let m = wire_guide(&[1, 2, 3, 4], true);
    let c = run(&m, &[translation_x()]);
    assert_eq!(
        (c.analysis.n_motions(), c.analysis.n_self_stresses()),
        (1, 0)
    );
    let t = platform(&c.screws.motions[0].bodies);
    assert_eq!(t.screw.kind, ScrewKind::Rotation);
    assert!(
        sin_between(t.screw.direction, [0.0, 0.0, 1.0]) < 1e-9,
        "{t:?}"
    );
    assert!(t.screw.pitch.expect("a rotation").abs() < 1e-9, "{t:?}");
    assert!(
        near(t.screw.point[0], -0.05, 1e-9) && near(t.screw.point[1], 0.0, 1e-9),
        "{t:?}"
    );
    assert!(t.rigid_residual < 1e-9);
    // every wire bends in it: each attachment a_i is off the axis
    let flexing: Vec<&str> = c.screws.motions[0]
        .flexures
        .iter()
        .map(|f| f.element.as_str())
        .collect();
    assert_eq!(flexing, ["w1", "w2", "w3", "w4"]);
    // The wire suggestion. A line of direction d with d_x = 0 leaves the intended translation
    // x alone (F · v = d_x = 0). Its reciprocal product with T (unit ω) at a point p of it is
    // d · (ω × (p − (−0.05, 0, 0))) = d · (−p_y, p_x + 0.05, 0) = d_y (p_x + 0.05) for
    // d_x = 0: largest, 0.1 m, for d_y = ±1 at p_x = 0.05, i.e. the line from a5 to g5 (the
    // fifth wire of the guide): ground nodes with the x of a platform node are g3 and g5 at
    // x = 0.05, and only a5–g5 is along y (a3–g5 has d_y = 0.08/√(0.08² + 0.01²) = 0.992).
    let wires = &c.wires[0].wires;
    let w = &wires[0];
    assert_eq!((w.from.as_str(), w.to.as_str()), ("a5", "g5"), "{wires:?}");
    assert_eq!((w.body.as_str(), w.other.as_str()), ("platform", "ground"));
    assert!(sin_between(w.direction, [0.0, 1.0, 0.0]) < 1e-12);
    assert!(near(w.reciprocal, 0.1, 1e-9), "{w:?}");
    assert!(w.intended_change.abs() < 1e-12);
    assert_eq!((w.motions_after, w.self_stresses_after), (0, 0));
    for w in wires {
        assert_eq!((w.motions_after, w.self_stresses_after), (0, 0));
        assert!(w.reciprocal > 0.0);
    }
    // repeating the analysis with that wire built: exactly constrained (the five-wire guide)
    let five = run(&wire_guide(&[1, 2, 3, 4, 5], true), &[translation_x()]);
    assert!(five.is_exact());
    // and its freedom, inputs released, is the intended translation
    let f = five.freedom.as_ref().expect("intended freedom stated");
    assert!(f.matches, "{f:?}");
    assert_eq!((f.design_dimension, f.intended_dimension), (1, 1));
    assert!(f.principal_angles[0] < 1e-6);
}

#[test]
fn four_wires_on_the_sparse_path_get_the_same_twist_and_a_verified_wire() {
    // The model of the test above, checked by the sparse rank-revealing LU: the same motion
    // (a rotation about the vertical axis through (−0.05, 0), pitch 0, derived there from the
    // wire lines) and wire suggestions verified by the bound for an added row. The fifth wire
    // a5–g5 (reciprocal product 0.1 m, derived above) is among them, and every suggested wire,
    // built and checked again by the dense SVD, leaves the guide exactly constrained.
    let m = wire_guide(&[1, 2, 3, 4], true);
    let mut opts = ClassifyOptions::default();
    opts.check.method = CheckMethod::Sparse;
    let c = classify_intended(&m, &opts, &[translation_x()], |_| {}).unwrap();
    assert!(c.analysis.sparse.as_ref().expect("sparse path").certain);
    assert_eq!(
        (c.analysis.n_motions(), c.analysis.n_self_stresses()),
        (1, 0)
    );
    let t = platform(&c.screws.motions[0].bodies);
    assert_eq!(t.screw.kind, ScrewKind::Rotation);
    assert!(sin_between(t.screw.direction, [0.0, 0.0, 1.0]) < 1e-9);
    assert!(near(t.screw.point[0], -0.05, 1e-9) && near(t.screw.point[1], 0.0, 1e-9));
    let wires = &c.wires[0].wires;
    assert!(!wires.is_empty());
    let w = wires
        .iter()
        .find(|w| (w.from.as_str(), w.to.as_str()) == ("a5", "g5"))
        .unwrap_or_else(|| panic!("the fifth wire among {wires:?}"));
    assert!(near(w.reciprocal, 0.1, 1e-9), "{w:?}");
    for w in wires {
        assert_eq!((w.motions_after, w.self_stresses_after), (0, 0));
        let built = wire_guide_with(&[1, 2, 3, 4], true, &[(w.from.as_str(), w.to.as_str())]);
        let again = classify(&built, &ClassifyOptions::default()).unwrap();
        assert!(
            again.is_exact(),
            "{} to {}: {:?}",
            w.from,
            w.to,
            again.analysis.case
        );
    }
}

#[test]
fn four_wires_have_a_parasitic_rotation() {
    // Released, the four-wire guide has the two twists of the test above: the translation x
    // and the rotations about vertical axes through (−0.05, y₀) (v₀ = (y₀, 0.05, 0)). Every
    // twist of that span outside the translation x is such a rotation: one parasitic freedom,
    // a rotation about a vertical axis with x = −0.05, pitch 0; nothing missing.
    let c = run(&wire_guide(&[1, 2, 3, 4], false), &[translation_x()]);
    let f = c.freedom.as_ref().expect("intended freedom stated");
    assert!(!f.matches);
    assert_eq!((f.n_design_motions, f.design_dimension), (2, 2));
    assert!(f.missing.is_empty(), "{f:?}");
    assert_eq!(f.parasitic.len(), 1, "{f:?}");
    let t = platform(&f.parasitic[0]);
    assert_eq!(t.screw.kind, ScrewKind::Rotation);
    assert!(
        sin_between(t.screw.direction, [0.0, 0.0, 1.0]) < 1e-9,
        "{t:?}"
    );
    assert!(near(t.screw.point[0], -0.05, 1e-9), "{t:?}");
    assert!(t.screw.pitch.expect("a rotation").abs() < 1e-9);
    // a rotation stated as intended instead: the translation x is then parasitic and the
    // rotation about the z axis through the origin is missing (it is not
    // reciprocal to L4: m · ω = −0.05 ≠ 0)
    let rz = IntendedFreedom {
        body: "c".into(),
        motion: FreedomMotion::Rotation {
            point: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            pitch: 0.0,
        },
    };
    let c = run(&wire_guide(&[1, 2, 3, 4], false), &[rz]);
    let f = c.freedom.as_ref().expect("intended freedom stated");
    assert!(!f.matches);
    assert_eq!((f.missing.len(), f.parasitic.len()), (1, 2), "{f:?}");
}

/// The force of wrench `w` along the unit `u` (the wrench must be a force along u).
fn force_along(w: &BodyWrench, u: [f64; 3]) -> f64 {
    assert_eq!(w.screw.kind, ScrewKind::Force, "{w:?}");
    assert!(sin_between(w.screw.direction, u) < 1e-9, "{w:?}");
    w.force[0] * u[0] + w.force[1] * u[1] + w.force[2] * u[2]
}

#[test]
fn six_wires_fight_along_their_own_lines() {
    // Six wires: the five of the guide and wire 6 through a6 = (0, −0.03, 0) along
    // u6 = (0, 1, 1)/√2, whose line (unnormalised) is (0, 1, 1 | −0.03, 0, 0). All six lines
    // have F_x = 0, the five-dimensional space of wrenches reciprocal to the translation x,
    // which the five independent lines of the guide span: one self-stress Σ σ_i L_i = 0.
    // With σ6 on the unnormalised line = 1:
    //   f_z:  σ1 + σ2 + σ3 + 1 = 0          f_y:  σ4 + σ5 + 1 = 0
    //   m_y:  0.05 (σ1 + σ2 − σ3) = 0       m_z:  0.05 (σ5 − σ4) = 0
    //   m_x:  −0.03 σ1 + 0.03 σ2 − 0.01 (σ4 + σ5) − 0.03 = 0
    // so σ4 = σ5 = −1/2, σ3 = σ1 + σ2 = −1/2, σ2 − σ1 = 2/3: σ1 = −7/12, σ2 = 1/12; on the
    // unit line u6, σ6 = √2. The wrench each wire applies to the platform is a force on its
    // own line (pitch 0) with these ratios (one common factor and sign).
    let c = run(&wire_guide(&[1, 2, 3, 4, 5, 6], true), &[]);
    assert_eq!(
        (c.analysis.n_motions(), c.analysis.n_self_stresses()),
        (0, 1)
    );
    let st = &c.screws.self_stresses[0];
    let on_platform: Vec<&BodyWrench> = st
        .wrenches
        .iter()
        .filter(|w| w.body == "platform")
        .collect();
    assert_eq!(on_platform.len(), 6, "{on_platform:?}");
    assert!(
        on_platform.iter().all(|w| !w.support),
        "no reaction at c.x: F_x = 0"
    );
    let s = 0.5f64.sqrt();
    let sigma = [-7.0 / 12.0, 1.0 / 12.0, -0.5, -0.5, -0.5, 2f64.sqrt()];
    let dirs = [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, s, s],
    ];
    let w6 = on_platform.iter().find(|w| w.by == "w6").unwrap();
    let k = force_along(w6, dirs[5]) / sigma[5];
    for i in 0..6 {
        let w = on_platform
            .iter()
            .find(|w| w.by == format!("w{}", i + 1))
            .unwrap();
        assert!(
            near(force_along(w, dirs[i]), k * sigma[i], 1e-9 * k.abs()),
            "{w:?}"
        );
        assert!(w.screw.pitch.expect("a force").abs() < 1e-9, "{w:?}");
        // the line of action passes through the wire's attachment node
        let (a, _) = wire_nodes(i + 1);
        let r = [
            a[0] - w.screw.point[0],
            a[1] - w.screw.point[1],
            a[2] - w.screw.point[2],
        ];
        let off = sin_between(r, dirs[i]);
        assert!(off < 1e-9, "w{}: {w:?}", i + 1);
    }
}

#[test]
fn parallel_leaf_guide_translates_perpendicular_to_the_leaves() {
    // K03: each leaf (plane x = ∓0.025) transmits the wrenches (0, f_y, f_z | m_x, −x f_z,
    // x f_y). Twists reciprocal to both planes: ω = 0 (m_x, and m_y, m_z with the two x), and
    // v_y = v_z = 0: the translation along x. The spans share only the couple about x
    // (f = 0): the self-stress is a pair of opposite couples about x on the platform.
    let c = run(&leaf_mechanism(false), &[]);
    assert_eq!(
        (c.analysis.n_motions(), c.analysis.n_self_stresses()),
        (1, 1)
    );
    let t = platform(&c.screws.motions[0].bodies);
    assert_eq!(t.screw.kind, ScrewKind::Translation, "{t:?}");
    assert!(
        sin_between(t.screw.direction, [1.0, 0.0, 0.0]) < 1e-9,
        "{t:?}"
    );
    let on: Vec<&BodyWrench> = c.screws.self_stresses[0]
        .wrenches
        .iter()
        .filter(|w| w.body == "platform")
        .collect();
    assert_eq!(on.len(), 2, "{on:?}");
    for w in &on {
        assert_eq!(w.screw.kind, ScrewKind::Couple, "{w:?}");
        assert!(
            sin_between(w.screw.direction, [1.0, 0.0, 0.0]) < 1e-9,
            "{w:?}"
        );
    }
    assert!(near(
        on[0].moment[0],
        -on[1].moment[0],
        1e-9 * on[0].moment[0].abs()
    ));
}

#[test]
fn cross_spring_pivot_rotates_about_the_crossing_line() {
    // K04: the leaf planes through the y axis along (±sin 45°, 0, cos 45°); a twist reciprocal
    // to every line of both planes must meet every one of them: the rotation about the y axis
    // (the crossing line), pitch 0. The spans share the forces along that line: the self-
    // stress is a pair of opposite forces on the y axis.
    let c = run(&leaf_mechanism(true), &[]);
    assert_eq!(
        (c.analysis.n_motions(), c.analysis.n_self_stresses()),
        (1, 1)
    );
    let t = platform(&c.screws.motions[0].bodies);
    assert_eq!(t.screw.kind, ScrewKind::Rotation, "{t:?}");
    assert!(
        sin_between(t.screw.direction, [0.0, 1.0, 0.0]) < 1e-9,
        "{t:?}"
    );
    assert!(
        near(t.screw.point[0], 0.0, 1e-9) && near(t.screw.point[2], 0.0, 1e-9),
        "{t:?}"
    );
    assert!(t.screw.pitch.expect("a rotation").abs() < 1e-9);
    let on: Vec<&BodyWrench> = c.screws.self_stresses[0]
        .wrenches
        .iter()
        .filter(|w| w.body == "platform")
        .collect();
    assert_eq!(on.len(), 2, "{on:?}");
    for w in &on {
        let _ = force_along(w, [0.0, 1.0, 0.0]);
        assert!(
            near(w.screw.point[0], 0.0, 1e-9) && near(w.screw.point[2], 0.0, 1e-9),
            "{w:?}"
        );
        assert!(w.screw.pitch.expect("a force").abs() < 1e-9);
    }
    assert!(near(
        on[0].force[1],
        -on[1].force[1],
        1e-9 * on[0].force[1].abs()
    ));
    // classify() (no intended freedom) gives the same screws
    assert_eq!(
        classify(&leaf_mechanism(true), &ClassifyOptions::default())
            .unwrap()
            .screws
            .motions
            .len(),
        1
    );
}

#[test]
fn a_freedom_must_name_a_moving_body() {
    use flexmbd_core::kinematics::KinematicsError;
    // a wire alone is a flexure, not a body; the ground does not move; a zero direction
    for (body, direction) in [
        ("w1", [1.0, 0.0, 0.0]),
        ("g1", [1.0, 0.0, 0.0]),
        ("platform", [0.0; 3]),
    ] {
        let f = IntendedFreedom {
            body: body.into(),
            motion: FreedomMotion::Translation { direction },
        };
        let e = classify_intended(
            &wire_guide(&[1, 2, 3, 4, 5], true),
            &ClassifyOptions::default(),
            &[f],
            |_| {},
        )
        .expect_err("refused");
        let expected = if body == "platform" {
            matches!(e.source, KinematicsError::BadFreedom(_))
        } else {
            e.source == KinematicsError::UnknownBody(body.into())
        };
        assert!(expected, "{body}: {e:?}");
    }
}
