//! The memory guard of the dense linearised analyses (issue 15, item 2): modes, sweep, state
//! space and the linearised statics refuse a model whose dense matrices exceed the limit of
//! their options, before allocating them; the sparse paths are not limited.

mod common;

use common::{last_step, strip_builder};
use flexmbd_core::dynamics::state_space::{
    state_space, Input, Output, OutputKind, StateSpaceOptions,
};
use flexmbd_core::dynamics::sweep::sweep_with;
use flexmbd_core::dynamics::{
    check_dense_size, dense_size::dense_bytes, modes_with, EigenSolver, ModalError, ModalOptions,
};
use flexmbd_core::linalg::DenseTooLarge;
use flexmbd_core::linearized::{self as linear, LinearError, LinearFailure, LinearRequest};
use flexmbd_core::model::Dof;
use flexmbd_core::Model;

/// The steel strip of `n` beams, 0.2 m long, clamped at the root.
fn clamped_strip(n: usize) -> Model {
    let mut b = strip_builder(n, 0.2);
    b.fix("n0", None).unwrap();
    b.build().unwrap()
}

/// Free nodes of the clamped strip of `n` beams: n, with 3 translations and 4 Euler
/// parameters (7 coordinates) or 6 velocity components each.
fn sizes(n: usize) -> (usize, usize) {
    (7 * n, 6 * n)
}

#[test]
fn the_need_covers_the_matrices_the_dense_path_must_hold() {
    // K and M in x (n_x² each) and the reduced K0 and M0 (n_v² each) are certainly held at
    // once; the linearisation adds K_m and K_g on the free coordinates (n_x² each)
    let n = 40;
    let model = clamped_strip(n);
    let (nx, nv) = sizes(n);
    let (dof, bytes) = dense_bytes(&model, false);
    assert_eq!(dof, nv);
    let at_least = 8 * (2 * nx * nx + 2 * nv * nv) as u128;
    assert!(bytes >= at_least, "{bytes} < {at_least}");
    // the statics unknowns: the free coordinates and λ0 of the clamped root (its held rotation
    // leaves the first Euler parameter to the normalisation)
    let (dof, lin) = linear::dense_bytes(&model, false);
    assert_eq!(dof, nx + 1);
    assert!(lin >= 8 * 2 * (nx * nx) as u128);
    // the state space holds A, (2 n_v)², on top
    let (_, ss) = dense_bytes(&model, true);
    assert!(ss >= bytes + 8 * 4 * (nv * nv) as u128);
}

#[test]
fn dense_paths_refuse_a_model_above_the_limit() {
    // 200 beams: 1200 degrees of freedom, a dense need of about 0.2 GB; a limit of 50 MB
    let n = 200;
    let model = clamped_strip(n);
    let step = last_step(&model, 1);
    let limit = 50 << 20;
    let (_, nv) = sizes(n);
    let dense = ModalOptions {
        solver: EigenSolver::Dense,
        max_dense_bytes: limit,
    };
    let too_large = |e: &DenseTooLarge| {
        assert_eq!(e.dof, nv);
        assert_eq!(e.limit, limit);
        assert!(e.bytes > limit);
        // neutral words: the remedy names the sparse solver, not an option of a front end
        assert!(e.to_string().contains("sparse eigen solver"), "{e}");
        assert!(!e.to_string().contains("--"), "{e}");
    };
    let t = std::time::Instant::now();
    match modes_with(&model, &step, 3, &dense) {
        Err(ModalError::TooLarge(e)) => too_large(&e),
        other => panic!("{:?}", other.map(|m| m.modes.len())),
    }
    match check_dense_size(&model, 3, &dense) {
        Err(ModalError::TooLarge(e)) => too_large(&e),
        other => panic!("{other:?}"),
    }
    // the automatic choice takes the dense path when most modes are asked for (a model of at
    // most DENSE_FALLBACK_DOF degrees of freedom: `dynamics::auto_solver`)
    let auto = ModalOptions {
        max_dense_bytes: limit,
        ..Default::default()
    };
    assert!(matches!(
        check_dense_size(&model, nv, &auto),
        Err(ModalError::TooLarge(_))
    ));
    // every step of a sweep says so, the compliance too
    let tip = model.node_id(&format!("n{n}")).unwrap();
    let pts = sweep_with(&model, std::slice::from_ref(&step), 3, &[tip], &dense);
    assert!(matches!(&pts[0].eigenvalues, Err(ModalError::TooLarge(_))));
    assert!(matches!(
        &pts[0].compliance[0],
        Err(LinearError::TooLarge(_))
    ));
    // the dense state space
    let ss = state_space(
        &model,
        &step,
        &[Input {
            node: tip,
            dof: Dof::Z,
        }],
        &[Output::node(tip, Dof::Z, OutputKind::Disp)],
        &StateSpaceOptions {
            solver: EigenSolver::Dense,
            max_dense_bytes: limit,
            ..Default::default()
        },
    );
    assert!(ss.is_err_and(|e| e.to_string().contains("state space")));
    // compliance and buckling at a static step
    let req = LinearRequest {
        compliance: vec![tip],
        buckling: 1,
        max_dense_bytes: limit,
    };
    let lin = linear::at_step(&model, &step, &req);
    assert!(lin.compliance.is_empty() && lin.buckling.is_none());
    assert!(matches!(
        lin.failures.as_slice(),
        [LinearFailure::TooLarge(LinearError::TooLarge(_))]
    ));
    // refused before anything large was built: the whole test is far below the time of one
    // dense eigen solution of 1200 degrees of freedom
    assert!(t.elapsed().as_secs_f64() < 5.0, "{:?}", t.elapsed());
    // the sparse path is not limited: the lowest bending frequency of the clamped strip,
    // f1 = 1.875104² √(EI/(ρA)) / (2π L²) with I/A = t²/12 (Euler–Bernoulli; shear and rotary
    // inertia lower it by far less than 0.1 % at L/t = 1000)
    let sparse = ModalOptions {
        solver: EigenSolver::Sparse,
        max_dense_bytes: limit,
    };
    let m = modes_with(&model, &step, 1, &sparse).unwrap();
    let (l, t) = (0.2, 0.2e-3);
    let f1 = 1.875104f64.powi(2) * (common::STEEL.e * t * t / (12.0 * common::STEEL.rho)).sqrt()
        / (2.0 * std::f64::consts::PI * l * l);
    let f = m.modes[0].frequency;
    assert!((f - f1).abs() < 1e-3 * f1, "{f} vs {f1}");
}

#[test]
fn the_automatic_choice_refuses_most_modes_of_a_model_too_large_for_the_dense_path() {
    // 1200 beams: 7200 degrees of freedom, above DENSE_FALLBACK_DOF. The one automatic rule
    // (`dynamics::auto_solver`) takes the sparse path for a few lowest modes; for more than a
    // third of the modes it takes the dense path (a shift-invert run for most of the spectrum is
    // impractical), whose matrices (about 6 GiB here) exceed the default limit of 4 GiB: the
    // request is refused before anything is allocated, naming the remedy (fewer modes)
    let n = 1200;
    let model = clamped_strip(n);
    let (_, nv) = sizes(n);
    assert!(nv > flexmbd_core::dynamics::DENSE_FALLBACK_DOF);
    let auto = ModalOptions::default();
    assert_eq!(auto.resolve(&model, 5), EigenSolver::Sparse);
    assert!(check_dense_size(&model, 5, &auto).is_ok());
    assert_eq!(auto.resolve(&model, nv / 3), EigenSolver::Sparse);
    assert_eq!(auto.resolve(&model, nv / 3 + 1), EigenSolver::Dense);
    assert_eq!(auto.resolve(&model, 5000), EigenSolver::Dense);
    match check_dense_size(&model, 5000, &auto) {
        Err(ModalError::TooManyModes { wanted, ndof, .. }) => {
            assert_eq!((wanted, ndof), (5000, nv));
        }
        other => panic!("{other:?}"),
    }
    let step = last_step(&model, 1);
    let e = modes_with(&model, &step, 5000, &auto).unwrap_err();
    assert!(matches!(e, ModalError::TooManyModes { .. }), "{e:?}");
    let text = e.to_string();
    assert!(text.contains("at most 2400 modes"), "{text}");
    let pts = sweep_with(&model, std::slice::from_ref(&step), 5000, &[], &auto);
    assert!(matches!(
        pts[0].eigenvalues,
        Err(ModalError::TooManyModes { .. })
    ));
    // the explicit dense solver is refused as too large, as before
    assert!(matches!(
        check_dense_size(&model, 5000, &ModalOptions::with_solver(EigenSolver::Dense)),
        Err(ModalError::TooLarge(_))
    ));
    // with a limit that admits the dense matrices, the automatic choice goes dense
    let roomy = ModalOptions {
        max_dense_bytes: 16 << 30,
        ..ModalOptions::default()
    };
    assert_eq!(roomy.resolve(&model, 5000), EigenSolver::Dense);
    assert!(check_dense_size(&model, 5000, &roomy).is_ok());
}
