//! Validation of the modal analysis through the public API (validation.md F01, F02; F03 is in
//! `validation_spin.rs`), and the conventions of the modes (signs, rigid-body modes).

mod common;

use common::{last_step, spring_steel_strip, strip};
use flexmbd_core::assembly::mass::mass_matrix;
use flexmbd_core::dynamics::{
    fix_sign, modes, modes_with, rigid_body_count, EigenSolver, ModalOptions, Mode, SIGN_TIE_TOL,
};
use flexmbd_core::section::BeamProps;

/// Out-of-plane bending: most kinetic energy in translation, and the translations along y.
fn y_share(m: &Mode) -> f64 {
    let translational: f64 = m.kinetic.iter().map(|k| k.1).sum();
    let (mut y, mut all) = (0.0, 0.0);
    for (u, _) in &m.nodal {
        y += u[1] * u[1];
        all += u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    }
    if translational < 0.5 || all == 0.0 {
        return 0.0;
    }
    y / all
}

/// The F01 instance: the spring-steel strip (L = 0.1 m, b = 20 mm, t = 0.5 mm, E = 200 GPa,
/// ρ = 7800 kg/m³), the frequency scale √(EI/(ρA L⁴)) and L.
fn f01_strip() -> (BeamProps, f64, f64) {
    let p = spring_steel_strip();
    // √(EI/(ρA L⁴)) = 73.0882 rad/s
    let c = (p.eiy / (p.rho_a * 0.1f64.powi(4))).sqrt();
    (p, c, 0.1)
}

#[test]
fn f01_euler_bernoulli_frequency_roots() {
    f01_clamped_free_strip_bending_frequencies();
    f01_free_free_strip_has_six_rigid_modes_then_bending();
}

fn f01_clamped_free_strip_bending_frequencies() {
    // validation.md F01: β L = 1.875104, 4.694091, 7.854757; f = (βL)² √(EI/(ρA L⁴))/(2π);
    // tolerance 0.1 % with ≥ 10 cubic elements (rotary inertia lowers them by < 0.05 %)
    let (p, c, l) = f01_strip();
    assert!((c - 73.0882).abs() < 1e-3, "{c}");
    let model = strip(10, l, p, true).build().unwrap();
    let step = last_step(&model, 1);
    let modal = modes(&model, &step, 12).unwrap();
    let bending: Vec<&Mode> = modal.modes.iter().filter(|m| y_share(m) > 0.99).collect();
    for (k, beta) in [1.875104f64, 4.694091, 7.854757].iter().enumerate() {
        let want = beta * beta * c / (2.0 * std::f64::consts::PI);
        let got = bending[k].frequency;
        assert!(
            (got - want).abs() < 1e-3 * want,
            "mode {k}: {got} Hz vs {want}"
        );
    }
    // the instance values of the table: 40.899, 256.313, 717.683 Hz
    assert!((bending[0].frequency - 40.899).abs() < 0.05);
    // mass orthonormality of the modes in x: δxᵢᵀ M δxⱼ = δᵢⱼ
    let mx = mass_matrix(&model, &step.x);
    for a in 0..6 {
        for b in 0..6 {
            let va = &modal.modes[a].shape;
            let vb = &modal.modes[b].shape;
            let mut v = 0.0;
            for i in 0..model.nx {
                for j in 0..model.nx {
                    v += va[i] * mx[(i, j)] * vb[j];
                }
            }
            let want = if a == b { 1.0 } else { 0.0 };
            assert!((v - want).abs() < 1e-9, "M-orthonormality ({a}, {b}): {v}");
        }
    }
}

fn f01_free_free_strip_has_six_rigid_modes_then_bending() {
    // free–free: 6 rigid-body modes at 0 Hz, first elastic bending β L = 4.730041
    let (p, c, l) = f01_strip();
    let model = strip(12, l, p, false).build().unwrap();
    let step = last_step(&model, 1);
    let modal = modes(&model, &step, 10).unwrap();
    // rigid-body eigenvalues relative to the first elastic one
    let first_elastic = modal.modes[6].eigenvalue;
    for (k, m) in modal.modes.iter().enumerate() {
        // identified as such: frequency 0, no sign of instability
        assert_eq!(m.rigid_body, k < 6, "mode {k}: {}", m.eigenvalue);
        if k < 6 {
            assert_eq!(m.frequency, 0.0);
        }
    }
    for m in &modal.modes[..6] {
        assert!(
            m.eigenvalue.abs() < 1e-9 * first_elastic,
            "rigid-body eigenvalue {}",
            m.eigenvalue
        );
    }
    let bending: Vec<&Mode> = modal.modes[6..]
        .iter()
        .filter(|m| y_share(m) > 0.99)
        .collect();
    let want = 4.730041f64.powi(2) * c / (2.0 * std::f64::consts::PI);
    assert!(
        (bending[0].frequency - want).abs() < 1e-3 * want,
        "{} vs {want}",
        bending[0].frequency
    );
}

#[test]
fn f02_prestressed_cantilever_frequencies() {
    // validation.md F02, clamped–free, nondimensional L = EI = ρA = 1, Euler–Bernoulli without
    // rotary inertia (the rotations are massless and condensed out), axial dead force P at the
    // free end; ω̄ = ω √(ρA L⁴/EI). Tolerance 0.2 %.
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    // EIz = 100 separates the other bending plane (equal stiffness would make the two planes'
    // modes degenerate and their eigenvectors arbitrary mixtures)
    let props = BeamProps {
        ea: 1e7,
        gj: 1.0,
        eiy: 1.0,
        eiz: 100.0,
        rho_a: 1.0,
        ..Default::default()
    };
    for (ratio, w1, w2) in [
        (0.0, 3.5160, 22.0345),
        (-0.5, 2.5346, 21.1052),
        (1.0, 4.8148, 23.7701),
        (5.0, 7.7007, 29.5202),
    ] {
        let mut b = strip(16, 1.0, props, true);
        b.add_load("n16", [ratio * p_cr, 0.0, 0.0], [0.0; 3])
            .unwrap();
        let model = b.build().unwrap();
        let step = last_step(&model, 1);
        let modal = modes(&model, &step, 8).unwrap();
        assert!(modal.massless > 0, "rotations carry no inertia here");
        let bending: Vec<&Mode> = modal.modes.iter().filter(|m| y_share(m) > 0.99).collect();
        for (k, want) in [w1, w2].iter().enumerate() {
            let got = bending[k].eigenvalue.sqrt();
            assert!(
                (got - want).abs() < 2e-3 * want,
                "P = {ratio} P_cr, mode {k}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn sign_convention_of_mode_shapes() {
    // the largest component is made positive; near-ties go to the lowest index
    let mut s = vec![0.1, -0.5, 0.3];
    fix_sign(&mut s);
    assert_eq!(s, vec![-0.1, 0.5, -0.3]);
    let mut s = vec![0.0, -1.0, 1.0 - 1e-9, 0.2];
    fix_sign(&mut s);
    assert_eq!(s, vec![0.0, 1.0, -(1.0 - 1e-9), -0.2]);
    let mut s = vec![0.0, 1.0 - 1e-3, -1.0];
    fix_sign(&mut s);
    assert_eq!(s, vec![0.0, -(1.0 - 1e-3), 1.0]);
    let mut zero = vec![0.0; 3];
    fix_sign(&mut zero);
    assert_eq!(zero, vec![0.0; 3]);
    // both eigen solvers give the convention, and so the same shapes (distinct frequencies)
    let (p, _, l) = f01_strip();
    let model = strip(60, l, p, true).build().unwrap();
    let step = last_step(&model, 1);
    let run = |solver| modes_with(&model, &step, 6, &ModalOptions::with_solver(solver)).unwrap();
    let (d, s) = (run(EigenSolver::Dense), run(EigenSolver::Sparse));
    assert_eq!(
        (d.solver, s.solver),
        (EigenSolver::Dense, EigenSolver::Sparse)
    );
    for (a, b) in d.modes.iter().zip(&s.modes) {
        let big = a.shape.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let k = a
            .shape
            .iter()
            .position(|v| v.abs() >= (1.0 - SIGN_TIE_TOL) * big)
            .unwrap();
        assert!(a.shape[k] > 0.0 && b.shape[k] > 0.0, "sign at {k}");
        let diff = a
            .shape
            .iter()
            .zip(&b.shape)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(diff < 1e-6 * big, "shapes differ by {diff}");
    }
}

#[test]
fn rigid_body_modes_need_a_gap_of_nine_decades() {
    // round-off of zero below a positive eigenvalue 1e9 times larger
    assert_eq!(rigid_body_count(&[-4e-9, 2e-9, 3e-6, 2.7e6, 3e7]), 3);
    // a buckled state: a negative eigenvalue of its own size is no rigid-body mode
    assert_eq!(rigid_body_count(&[-5.0, 1e-12, 2.7e6]), 0);
    // no gap, or nothing above the rigid-body modes
    assert_eq!(rigid_body_count(&[1.0, 2.0, 3.0]), 0);
    assert_eq!(rigid_body_count(&[1e-12, -1e-12]), 0);
    assert_eq!(rigid_body_count(&[]), 0);
    assert_eq!(rigid_body_count(&[f64::NAN, 1.0]), 0);
}
