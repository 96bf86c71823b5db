//! Rigid-body modes on both eigen paths (issue 15, item 3): a free-floating steel strip has six
//! (frequency 0 in closed form), identified as such whatever the number of modes asked for,
//! also when every mode asked for is one of them (the sparse path sees no elastic mode then).

mod common;

use common::{last_step, strip_builder, STEEL};
use flexmbd_core::dynamics::sweep::sweep_with;
use flexmbd_core::dynamics::{modes_with, EigenSolver, ModalOptions};

/// Length of the strip [m] and its thickness (along z) [m].
const L: f64 = 0.2;
const T: f64 = 0.2e-3;

/// The first free–free bending frequency of the strip about its thin axis, Euler–Bernoulli:
/// (βL)² √(E t²/(12 ρ)) / (2π L²) with βL = 4.730041 (shear and rotary inertia lower it by far
/// less than 0.1 % at L/t = 1000).
fn first_bending() -> f64 {
    4.730041f64.powi(2) * (STEEL.e * T * T / (12.0 * STEEL.rho)).sqrt()
        / (2.0 * std::f64::consts::PI * L * L)
}

#[test]
fn a_free_strip_has_six_rigid_body_modes_on_both_paths() {
    // 40 elements on the sparse path, 12 on the dense one (finer dense meshes:
    // `the_dense_path_flags_them_on_fine_meshes`)
    for (solver, n) in [(EigenSolver::Sparse, 40), (EigenSolver::Dense, 12)] {
        let model = strip_builder(n, L).build().unwrap();
        let step = last_step(&model, 1);
        let opts = ModalOptions::with_solver(solver);
        // fewer modes than rigid-body modes, all of them, and past them
        for count in [1, 3, 6, 8] {
            let m = modes_with(&model, &step, count, &opts).unwrap();
            assert_eq!(m.modes.len(), count);
            for (k, mode) in m.modes.iter().enumerate() {
                assert_eq!(
                    mode.rigid_body,
                    k < 6,
                    "{solver:?}, {count} modes, mode {k}: ω² = {}",
                    mode.eigenvalue
                );
                if k < 6 {
                    assert_eq!(mode.frequency, 0.0);
                    assert!(mode.strain.is_empty());
                }
            }
            if count == 8 {
                let (f, want) = (m.modes[6].frequency, first_bending());
                assert!((f - want).abs() < 1e-3 * want, "{solver:?}: {f} vs {want}");
            }
        }
        // a sweep of six frequencies: all six are rigid-body modes at every step
        let pts = sweep_with(&model, std::slice::from_ref(&step), 6, &[], &opts);
        assert_eq!(pts[0].rigid_body, 6, "{solver:?}");
        assert_eq!(pts[0].frequencies().unwrap(), vec![0.0; 6]);
    }
}

#[test]
fn a_clamped_strip_has_none() {
    // the same strip clamped at its root: the lowest modes are elastic (the first bending mode
    // at (1.875104/4.730041)² of the free–free one), none is flagged on either path
    let mut b = strip_builder(40, L);
    b.fix("n0", None).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    for solver in [EigenSolver::Sparse, EigenSolver::Dense] {
        for count in [1, 6] {
            let m = modes_with(&model, &step, count, &ModalOptions::with_solver(solver)).unwrap();
            assert!(m.modes.iter().all(|m| !m.rigid_body), "{solver:?} {count}");
            let want = first_bending() * (1.875104f64 / 4.730041).powi(2);
            let f = m.modes[0].frequency;
            assert!((f - want).abs() < 1e-3 * want, "{solver:?}: {f} vs {want}");
        }
    }
}

/// The free–free Euler–Bernoulli bending frequencies of the strip about its thin axis:
/// βₙL = 4.730041, 7.853205 (roots of cos βL cosh βL = 1), f = (βₙL)² √(E t²/(12 ρ)) / (2π L²).
fn free_free_bending(beta_l: f64) -> f64 {
    first_bending() * (beta_l / 4.730041).powi(2)
}

#[test]
fn the_dense_path_flags_them_on_fine_meshes() {
    // the dense eigenvalues of the rigid-body modes are round-off of about ε times the highest
    // ω², which grows with the number of elements of the thin strip (its rotary inertia is 1e-8
    // of the translational mass): at 40 elements it comes within 1e-9 of the first elastic ω².
    // The rigid-body modes are counted from the stiffness instead (their strain energy through
    // the element deformations), so that 12, 40 and 100 elements all have exactly six, and the
    // elastic frequencies above them are the free–free closed form
    for n in [12, 40, 100] {
        let model = strip_builder(n, L).build().unwrap();
        let step = last_step(&model, 1);
        let m = modes_with(
            &model,
            &step,
            8,
            &ModalOptions::with_solver(EigenSolver::Dense),
        )
        .unwrap();
        let flagged: Vec<bool> = m.modes.iter().map(|m| m.rigid_body).collect();
        assert_eq!(
            flagged,
            [[true; 6].as_slice(), &[false; 2]].concat(),
            "{n} elements"
        );
        for (k, beta_l) in [(6, 4.730041), (7, 7.853205)] {
            let (f, want) = (m.modes[k].frequency, free_free_bending(beta_l));
            assert!(
                (f - want).abs() < 1e-3 * want,
                "{n} elements, mode {k}: {f} vs {want}"
            );
        }
    }
}

#[test]
fn a_free_frame_in_space_has_six_rigid_body_modes() {
    // three orthogonal arms of a square steel rod from one corner, 20 beams each, nothing held:
    // a free body in three dimensions has exactly six rigid-body modes (three translations, three
    // rotations), and its first elastic mode is not one of them, on both paths
    use flexmbd_core::model::{ElementSpec, ModelBuilder};
    use flexmbd_core::section::{BeamProps, Shape};
    let props = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 5e-3, t: 5e-3 }, true);
    let mut b = ModelBuilder::new("frame");
    b.add_node("c", [0.0; 3], false).unwrap();
    let n = 20;
    for (arm, axis, orient) in [
        ("x", [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ("y", [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
        ("z", [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
    ] {
        let mut prev = "c".to_string();
        for i in 1..=n {
            let s = 0.1 * i as f64 / n as f64;
            let node = format!("{arm}{i}");
            b.add_node(&node, axis.map(|a| a * s), false).unwrap();
            let el = format!("{arm}b{i}");
            let spec = ElementSpec::Beam {
                orient: Some(orient),
                ct: 0.0,
            };
            b.add_element(&el, &[&prev, &node], spec, &[], &[]).unwrap();
            b.set_beam_props(&el, props).unwrap();
            prev = node;
        }
    }
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    for solver in [EigenSolver::Dense, EigenSolver::Sparse] {
        let m = modes_with(&model, &step, 8, &ModalOptions::with_solver(solver)).unwrap();
        let flagged: Vec<bool> = m.modes.iter().map(|m| m.rigid_body).collect();
        assert_eq!(
            flagged,
            [[true; 6].as_slice(), &[false; 2]].concat(),
            "{solver:?}"
        );
        assert!(m.modes[6].frequency > 0.0, "{solver:?}");
    }
}
