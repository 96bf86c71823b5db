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
    // the dense path resolves the rigid-body eigenvalues to about ε times the highest ω²,
    // which must stay below 1e-9 of the first elastic one: 12 elements (40 are too many for
    // it: the highest ω² of the thin strip grows with the square of the number of elements);
    // the sparse path's eigenvalues are accurate on any mesh: 40
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
