//! The sparse eigen path: closed forms (F01, F02, free–free strip), agreement with the dense
//! path (rigid bodies, hinges, massless nodes, pre-stress, degenerate pairs, an unstable
//! state), M-orthonormality, errors.

use super::super::{
    eigenvalues_with, modes_with, EigenSolver, Modal, ModalError, ModalOptions, SPARSE_THRESHOLD,
};
use crate::assembly::mass::mass_times;
use crate::model::{Dof, ElementSpec, Model, ModelBuilder};
use crate::section::{BeamProps, Material, Shape};
use crate::statics::{last_step, StepResult};

fn run(model: &Model, step: &StepResult, count: usize, solver: EigenSolver) -> Modal {
    let m = modes_with(model, step, count, &ModalOptions::with_solver(solver)).unwrap();
    assert_eq!(m.solver, solver);
    m
}

fn steel() -> Material {
    Material {
        e: 210e9,
        g: 210e9 / 2.6,
        rho: 7800.0,
    }
}

/// The peers' strip (bench/README.md): L = 50 mm along x, width 20 mm along y (orientation
/// vector), thickness 0.2 mm along z, clamped at x = 0; Euler–Bernoulli (no shear
/// flexibility), so EI = E b t³/12 with E itself (a beam, not a plate: no 1/(1 − ν²); ν only
/// enters G, torsion). Out-of-plane bending moves the nodes along z.
fn peer_strip(n: usize, shape: Shape) -> Model {
    peer_strip_builder(n, shape).build().unwrap()
}

/// The builder of [`peer_strip`], for models that add to it.
fn peer_strip_builder(n: usize, shape: Shape) -> ModelBuilder {
    let p = BeamProps::from_section(&steel(), &shape, true);
    let mut b = ModelBuilder::new("strip");
    b.add_beam_chain(
        "",
        [0.0; 3],
        [0.05, 0.0, 0.0],
        n,
        Some([0.0, 1.0, 0.0]),
        Some(p),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    b
}

const PEER_SECTION: Shape = Shape::Rectangle { w: 0.02, t: 0.2e-3 };

/// δxᵢᵀ M δxⱼ for all pairs of two sets of shapes.
fn mass_products(model: &Model, x: &[f64], a: &Modal, b: &Modal) -> Vec<Vec<f64>> {
    let refs: Vec<&[f64]> = b.modes.iter().map(|m| m.shape.as_slice()).collect();
    let mb = mass_times(model, x, &refs);
    a.modes
        .iter()
        .map(|ma| {
            mb.iter()
                .map(|v| ma.shape.iter().zip(v).map(|(p, q)| p * q).sum())
                .collect()
        })
        .collect()
}

/// Sparse against dense: the same eigenvalues, and every sparse mode in the span of the dense
/// modes of (nearly) the same eigenvalue, M-normalised.
fn assert_agree(model: &Model, step: &StepResult, count: usize, tol: f64) -> (Modal, Modal) {
    let d = run(model, step, count, EigenSolver::Dense);
    let s = run(model, step, count, EigenSolver::Sparse);
    assert_eq!(d.modes.len(), s.modes.len(), "number of modes");
    assert_eq!(d.ndof, s.ndof, "degrees of freedom");
    assert_eq!(d.massless, s.massless, "massless directions");
    assert_eq!(d.massless_nodes, s.massless_nodes, "massless nodes");
    let scale = d
        .modes
        .iter()
        .fold(0.0f64, |m, x| m.max(x.eigenvalue.abs()));
    for (k, (a, b)) in d.modes.iter().zip(&s.modes).enumerate() {
        assert!(
            (a.eigenvalue - b.eigenvalue).abs() <= tol * a.eigenvalue.abs() + 1e-12 * scale,
            "mode {k}: dense {} sparse {}",
            a.eigenvalue,
            b.eigenvalue
        );
    }
    let p = mass_products(model, &step.x, &s, &d);
    for (k, b) in s.modes.iter().enumerate() {
        // the dense modes of this eigenvalue (a cluster of equal ones)
        let span: f64 = d
            .modes
            .iter()
            .enumerate()
            .filter(|(_, a)| {
                (a.eigenvalue - b.eigenvalue).abs() <= 1e-6 * b.eigenvalue.abs() + 1e-9 * scale
            })
            .map(|(j, _)| p[k][j] * p[k][j])
            .sum();
        // the cluster may continue beyond the last dense mode computed
        let at_end = d.modes.last().is_some_and(|l| {
            (l.eigenvalue - b.eigenvalue).abs() <= 1e-6 * b.eigenvalue.abs() + 1e-9 * scale
        });
        if !at_end {
            assert!((span - 1.0).abs() < 1e-6, "mode {k}: span {span}");
        }
    }
    (d, s)
}

/// Sparse modes are M-orthonormal in x.
fn assert_orthonormal(model: &Model, step: &StepResult, m: &Modal, tol: f64) {
    let p = mass_products(model, &step.x, m, m);
    for (i, row) in p.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            let want = if i == j { 1.0 } else { 0.0 };
            assert!((v - want).abs() < tol, "M-orthonormality ({i}, {j}): {v}");
        }
    }
}

/// The frequencies of the modes that bend the strip out of its plane (translational kinetic
/// energy more than 99 % along z), in the order listed.
fn bending_frequencies(m: &Modal) -> Vec<f64> {
    m.modes
        .iter()
        .filter(|m| z_share(m) > 0.99)
        .map(|m| m.frequency)
        .collect()
}

/// Share of the out-of-plane (z) translations in a mode that moves mostly by translation.
fn z_share(m: &super::super::Mode) -> f64 {
    let (mut z, mut all) = (0.0, 0.0);
    for (u, _) in &m.nodal {
        z += u[2] * u[2];
        all += u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    }
    let translational: f64 = m.kinetic.iter().map(|k| k.1).sum();
    if translational < 0.5 || all == 0.0 {
        0.0
    } else {
        z / all
    }
}

#[test]
fn f01_peer_strip_sparse_bending_frequencies_closed_form() {
    // validation.md F01 with the peers' strip: f = (βL)² √(EI/(ρA L⁴))/(2π),
    // βL = 1.875104, 4.694091, 7.854757: 67.0552, 420.2279, 1176.650 Hz. 200 elements,
    // sparse path; the lumped rotary inertia lowers them by 3e-6, 2e-5, 5e-5.
    let model = peer_strip(200, PEER_SECTION);
    let step = last_step(&model, 1);
    let m = run(&model, &step, 10, EigenSolver::Sparse);
    assert_eq!(m.modes.len(), 10);
    let bending = bending_frequencies(&m);
    assert!(bending.len() >= 3, "{bending:?}");
    for (got, want) in bending.iter().zip([67.0552, 420.2279, 1176.650]) {
        assert!(
            (got - want).abs() < 1e-4 * want,
            "{got} Hz vs {want} Hz (Euler–Bernoulli)"
        );
    }
    assert_orthonormal(&model, &step, &m, 1e-9);
    // ascending, and the other modes are the torsion modes of the strip
    for w in m.modes.windows(2) {
        assert!(w[0].eigenvalue <= w[1].eigenvalue);
    }
}

#[test]
fn sparse_matches_dense_on_strips() {
    // the thin strip's masses span many decades (rotary inertia 1e-8 of the translational
    // mass), which costs the dense reduction about 1e-8 on the first eigenvalue at N = 30;
    // the sparse value agrees with its own Lanczos estimate to 3e-11 there
    for (n, tol) in [(4, 1e-9), (10, 1e-9), (30, 5e-8)] {
        let model = peer_strip(n, PEER_SECTION);
        let step = last_step(&model, 1);
        let (_, s) = assert_agree(&model, &step, 10, tol);
        assert_orthonormal(&model, &step, &s, 1e-9);
    }
    // a square section: the two bending planes give exactly equal eigenvalues, which a
    // single-vector Lanczos finds once; the Sturm check finds the second copy
    let model = peer_strip(12, Shape::Rectangle { w: 2e-3, t: 2e-3 });
    let step = last_step(&model, 1);
    let (d, s) = assert_agree(&model, &step, 8, 1e-9);
    assert!((d.modes[0].eigenvalue - d.modes[1].eigenvalue).abs() < 1e-9 * d.modes[1].eigenvalue);
    assert_orthonormal(&model, &step, &s, 1e-9);
}

/// A cantilever along x with a tip mass and a dead tip load; nondimensional beam of F02
/// (L = EI = ρA = 1, EIz = 100), `rotary`: with rotary inertia.
fn f02_cantilever(n: usize, axial: f64, rotary: bool) -> Model {
    let props = BeamProps {
        ea: 1e7,
        gj: 1.0,
        eiy: 1.0,
        eiz: 100.0,
        rho_a: 1.0,
        rho_i: if rotary { [2e-4, 1e-4, 1e-4] } else { [0.0; 3] },
        ..Default::default()
    };
    let mut b = ModelBuilder::new("f02");
    b.add_beam_chain(
        "",
        [0.0; 3],
        [1.0, 0.0, 0.0],
        n,
        Some([0.0, 0.0, 1.0]),
        Some(props),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    b.add_load(&format!("n{n}"), [axial, 0.0, 0.0], [0.0; 3])
        .unwrap();
    b.build().unwrap()
}

#[test]
fn f02_prestressed_cantilever_massless_rotations() {
    // validation.md F02: ω̄1, ω̄2 of the axially loaded Euler–Bernoulli cantilever at
    // P/P_cr = −0.5, 0, 1, 5 (tension positive), rotations without inertia (condensed out by
    // the dense path; infinite eigenvalues of the sparse operator)
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    for (ratio, w1, w2) in [
        (0.0, 3.5160, 22.0345),
        (-0.5, 2.5346, 21.1052),
        (1.0, 4.8148, 23.7701),
        (5.0, 7.7007, 29.5202),
    ] {
        let model = f02_cantilever(16, ratio * p_cr, false);
        let step = last_step(&model, 2);
        let (d, s) = assert_agree(&model, &step, 8, 1e-8);
        assert!(s.massless > 0 && s.massless == d.massless);
        // the out-of-plane bending modes (y), against the table
        let bending: Vec<f64> = s
            .modes
            .iter()
            .filter(|m| {
                let (mut y, mut all) = (0.0, 0.0);
                for (u, _) in &m.nodal {
                    y += u[1] * u[1];
                    all += u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
                }
                y > 0.99 * all
            })
            .map(|m| m.eigenvalue.sqrt())
            .collect();
        for (got, want) in bending.iter().zip([w1, w2]) {
            assert!(
                (got - want).abs() < 2e-3 * want,
                "P = {ratio} P_cr: {got} vs {want}"
            );
        }
        assert_orthonormal(&model, &step, &s, 1e-8);
    }
}

#[test]
fn prestress_along_a_stroke_and_an_unstable_state() {
    // compression beyond the buckling load on the straight path: the lowest ω² is negative
    // (an unstable equilibrium), which the shift must get below
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    for ratio in [-0.9, -1.5, -3.0] {
        let model = f02_cantilever(12, ratio * p_cr, true);
        let step = last_step(&model, 1);
        let (_, s) = assert_agree(&model, &step, 6, 1e-8);
        if ratio < -1.0 {
            assert!(s.modes[0].eigenvalue < 0.0, "{}", s.modes[0].eigenvalue);
            assert!(s.modes[0].frequency.is_nan());
        }
    }
}

#[test]
fn free_free_strip_zero_frequencies_then_bending() {
    // no support: six rigid-body modes at 0, then βL = 4.730041 (validation.md F01 free–free)
    let p = BeamProps::from_section(&steel(), &Shape::Rectangle { w: 0.02, t: 0.5e-3 }, true);
    let mut b = ModelBuilder::new("free");
    b.add_beam_chain(
        "",
        [0.0; 3],
        [0.1, 0.0, 0.0],
        24,
        Some([0.0, 1.0, 0.0]),
        Some(p),
    )
    .unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let s = run(&model, &step, 10, EigenSolver::Sparse);
    let first_elastic = s.modes[6].eigenvalue;
    for m in &s.modes[..6] {
        assert!(
            m.eigenvalue.abs() < 1e-8 * first_elastic,
            "rigid-body eigenvalue {}",
            m.eigenvalue
        );
    }
    let c = (p.eiy / (p.rho_a * 0.1f64.powi(4))).sqrt();
    let want = 4.730041f64.powi(2) * c / (2.0 * std::f64::consts::PI);
    let bending = s.modes[6..].iter().find(|m| z_share(m) > 0.99).unwrap();
    assert!(
        (bending.frequency - want).abs() < 1e-3 * want,
        "{} vs {want}",
        bending.frequency
    );
    assert_orthonormal(&model, &step, &s, 1e-8);
    // the elastic modes as the dense path gives them
    let d = run(&model, &step, 10, EigenSolver::Dense);
    for (a, b) in d.modes[6..].iter().zip(&s.modes[6..]) {
        assert!(
            (a.eigenvalue - b.eigenvalue).abs() < 1e-8 * a.eigenvalue,
            "{} vs {}",
            a.eigenvalue,
            b.eigenvalue
        );
    }
}

/// A parallel leaf-spring guide: two leaves of 4 beams each, their tips joined by a rigid
/// platform (reference node `p` with mass and inertia); a pendulum arm on a hinge (torsion
/// spring) at the platform; a node `t` without mass held by three stiff trusses to the ground
/// and one to the platform (its translations are massless directions).
fn guide_with_hinge_and_trusses() -> Model {
    let leaf = BeamProps::from_section(&steel(), &Shape::Rectangle { w: 0.01, t: 0.5e-3 }, false);
    let arm = BeamProps::from_section(&steel(), &Shape::Circle { d: 2e-3 }, false);
    let mut b = ModelBuilder::new("guide");
    b.add_beam_chain(
        "a",
        [0.0; 3],
        [0.0, 0.05, 0.0],
        4,
        Some([0.0, 0.0, 1.0]),
        Some(leaf),
    )
    .unwrap();
    b.add_beam_chain(
        "b",
        [0.03, 0.0, 0.0],
        [0.03, 0.05, 0.0],
        4,
        Some([0.0, 0.0, 1.0]),
        Some(leaf),
    )
    .unwrap();
    b.fix("an0", None).unwrap();
    b.fix("bn0", None).unwrap();
    b.add_node("p", [0.015, 0.05, 0.0], true).unwrap();
    b.add_element(
        "platform",
        &["p", "an4", "bn4"],
        ElementSpec::Rigid,
        &[],
        &[],
    )
    .unwrap();
    b.add_point_mass("p", 0.05).unwrap();
    b.add_inertia("p", [2e-5, 0.0, 0.0, 1e-5, 0.0, 3e-5])
        .unwrap();
    // hinge about z at p, then an arm with a mass at its end
    b.add_node_at("h", "p").unwrap();
    b.add_element(
        "hinge",
        &["p", "h"],
        ElementSpec::Hinge {
            axis: [0.0, 0.0, 1.0],
            k: 0.5,
        },
        &[1],
        &[],
    )
    .unwrap();
    b.add_node("e", [0.015, 0.09, 0.0], false).unwrap();
    b.add_element(
        "arm",
        &["h", "e"],
        ElementSpec::Beam {
            orient: Some([0.0, 0.0, 1.0]),
            ct: 0.0,
        },
        &[],
        &[],
    )
    .unwrap();
    b.set_beam_props("arm", arm).unwrap();
    b.add_point_mass("e", 0.01).unwrap();
    // massless node on stiff trusses
    for (name, x) in [
        ("g1", [-0.02, 0.06, 0.0]),
        ("g2", [-0.02, 0.08, 0.01]),
        ("g3", [-0.02, 0.08, -0.01]),
    ] {
        b.add_node(name, x, false).unwrap();
        b.fix(name, None).unwrap();
    }
    b.add_node("t", [-0.01, 0.07, 0.0], false).unwrap();
    for (i, g) in ["g1", "g2", "g3", "p"].iter().enumerate() {
        b.add_element(
            &format!("tr{i}"),
            &["t", g],
            ElementSpec::Truss { ea: 1e5 },
            &[],
            &[],
        )
        .unwrap();
    }
    b.build().unwrap()
}

#[test]
fn rigid_platform_hinge_and_massless_truss_node() {
    let model = guide_with_hinge_and_trusses();
    let step = last_step(&model, 1);
    let (d, s) = assert_agree(&model, &step, 12, 1e-8);
    assert!(
        d.massless >= 3,
        "the truss node's translations: {}",
        d.massless
    );
    let t = model.node_id("t").unwrap();
    assert!(s.massless_nodes.contains(&t));
    assert_orthonormal(&model, &step, &s, 1e-8);
    // the modes keep the platform rigid and the hinge's rigid modes: D δx = 0 for the
    // constrained deformations
    let roles = crate::statics::roles(&model);
    for m in &s.modes {
        for entry in &model.elements {
            let xk = crate::assembly::gather(entry, &step.x);
            let dm = crate::elements::ElementKind::jacobian(&entry.element, &xk);
            for r in 0..dm.nrows() {
                if roles[entry.ie + r] == crate::statics::Role::Flexible {
                    continue;
                }
                let de: f64 = entry
                    .x_indices()
                    .enumerate()
                    .map(|(c, i)| dm[(r, c)] * m.shape[i])
                    .sum();
                let size = m.shape.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                assert!(de.abs() < 1e-9 * size, "{}: {de}", entry.name);
            }
        }
    }
    // under a load (pre-stress in the leaves, forces in the trusses and constraints)
    let loaded = {
        let mut m = model.clone();
        m.loads.nodal.push(crate::model::NodalLoad {
            node: model.node_id("p").unwrap(),
            force: [2.0, -40.0, 0.0],
            moment: [0.0, 0.0, 0.05],
        });
        m
    };
    let step = last_step(&loaded, 4);
    assert_agree(&loaded, &step, 12, 1e-8);
}

#[test]
fn massless_mechanism_and_no_mass_are_errors() {
    // a node hanging on one truss from the strip's tip: its transverse motion has neither
    // stiffness nor inertia
    let mut b = peer_strip_builder(6, PEER_SECTION);
    b.add_node("loose", [0.07, 0.0, 0.0], false).unwrap();
    b.add_element(
        "tie",
        &["n6", "loose"],
        ElementSpec::Truss { ea: 1e4 },
        &[],
        &[],
    )
    .unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let solver = EigenSolver::Sparse;
    match modes_with(&model, &step, 4, &ModalOptions::with_solver(solver)) {
        Err(e @ ModalError::MasslessMechanism { .. }) => {
            let text = e.to_string();
            assert!(text.contains("loose") && text.contains("Give them mass or fix them"));
        }
        other => panic!("{solver:?}: {:?}", other.map(|m| m.ndof)),
    }
    // no density anywhere
    let props = BeamProps {
        ea: 1e6,
        gj: 1.0,
        eiy: 1.0,
        eiz: 1.0,
        ..Default::default()
    };
    let mut b = ModelBuilder::new("nomass");
    b.add_beam_chain("", [0.0; 3], [1.0, 0.0, 0.0], 3, None, Some(props))
        .unwrap();
    b.fix("n0", None).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let e = modes_with(
        &model,
        &step,
        2,
        &ModalOptions::with_solver(EigenSolver::Sparse),
    );
    assert!(matches!(e, Err(ModalError::NoMass)), "{e:?}");
}

#[test]
fn held_input_and_prescribed_coordinate() {
    // a prescribed tip translation is held during the vibration (an input): the strip then
    // vibrates as a propped cantilever in that direction
    let mut b = peer_strip_builder(20, PEER_SECTION);
    b.prescribe_coordinate("n20", Dof::Z, 1e-3).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 2);
    assert_agree(&model, &step, 8, 1e-8);
}

#[test]
fn automatic_choice_and_eigenvalues_only() {
    let small = peer_strip(4, PEER_SECTION);
    let large = peer_strip(SPARSE_THRESHOLD / 6 + 10, PEER_SECTION);
    let auto = ModalOptions::default();
    assert_eq!(auto.resolve(&small, 10), EigenSolver::Dense);
    assert_eq!(auto.resolve(&large, 10), EigenSolver::Sparse);
    // most of the spectrum: dense
    assert_eq!(auto.resolve(&large, usize::MAX), EigenSolver::Dense);
    let forced = ModalOptions::with_solver(EigenSolver::Sparse);
    assert_eq!(forced.resolve(&small, usize::MAX), EigenSolver::Sparse);
    let step = last_step(&large, 1);
    let lam = eigenvalues_with(&large, &step, 5, &auto).unwrap();
    let m = modes_with(&large, &step, 5, &auto).unwrap();
    assert_eq!(m.solver, EigenSolver::Sparse);
    for (a, b) in lam.iter().zip(&m.modes) {
        assert_eq!(*a, b.eigenvalue);
    }
    // all modes of a small model on the sparse path: as many as the dense path has
    let step = last_step(&small, 1);
    let d = run(&small, &step, usize::MAX, EigenSolver::Dense);
    let s = run(&small, &step, usize::MAX, EigenSolver::Sparse);
    assert_eq!(d.modes.len(), s.modes.len());
}

#[test]
fn dense_path_resolves_thin_strips_or_says_it_cannot() {
    // The 0.2 mm strip spreads ω² over many decades (its rotary inertia is 1e-8 of the
    // translational mass). The plain dense reduction lost 0.2 % on f1 at 24 elements and gave
    // negative garbage from 50 on; the shifted pass keeps f1 at the closed form 67.0552 Hz
    // (validation.md F01, within the rotary-inertia effect of 1e-5) up to a few hundred
    // elements, and beyond that the dense path reports that it cannot resolve the spectrum.
    for n in [24, 50, 120] {
        let model = peer_strip(n, PEER_SECTION);
        let step = last_step(&model, 1);
        let m = run(&model, &step, 1, EigenSolver::Dense);
        let f1 = m.modes[0].frequency;
        assert!((f1 - 67.0552).abs() < 1e-5 * 67.0552, "{n} elements: {f1}");
    }
    let model = peer_strip(300, PEER_SECTION);
    let step = last_step(&model, 1);
    let err = modes_with(
        &model,
        &step,
        3,
        &ModalOptions::with_solver(EigenSolver::Dense),
    )
    .unwrap_err();
    assert!(matches!(err, ModalError::DenseInaccurate { .. }), "{err}");
    assert!(err.to_string().contains("sparse eigen solver"));
    let sparse = run(&model, &step, 3, EigenSolver::Sparse);
    assert!((sparse.modes[0].frequency - 67.0552).abs() < 1e-5 * 67.0552);
}

#[test]
fn projected_eigenpairs_small_and_faer_branches_agree() {
    // the hand-written solver up to SMALL_EIGEN_MAX, faer beyond: the same eigenvalues and,
    // for the k largest (largest first), eigenvectors that satisfy A y = θ y
    use crate::math::small_eigen::SMALL_EIGEN_MAX;
    use faer::Mat;
    for n in [30, SMALL_EIGEN_MAX, SMALL_EIGEN_MAX + 3] {
        let a = Mat::from_fn(n, n, |i, j| {
            let (i, j) = (i.max(j) as f64, i.min(j) as f64);
            if i == j {
                1.0 / (1.0 + i).powi(2)
            } else {
                0.01 * ((i * 7.0 + j * 3.0) % 11.0 - 5.0) / (1.0 + i + j).powi(2)
            }
        });
        let k = 10;
        let (values, y) = super::projected_eigen_largest(a.as_ref(), k).unwrap();
        let (all, _) = super::projected_eigen(a.as_ref()).unwrap();
        assert_eq!(values.len(), n);
        assert_eq!((y.nrows(), y.ncols()), (n, k));
        let norm = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (p, q) in values.iter().zip(&all) {
            assert!((p - q).abs() <= 1e-13 * norm, "{p} against {q}");
        }
        for c in 0..k {
            let theta = values[n - 1 - c];
            let mut res = 0.0f64;
            for i in 0..n {
                let ay: f64 = (0..n).map(|j| a[(i, j)] * y[(j, c)]).sum();
                res = res.max((ay - theta * y[(i, c)]).abs());
            }
            let len: f64 = (0..n).map(|i| y[(i, c)] * y[(i, c)]).sum();
            assert!(res <= 1e-13 * norm, "n {n}, column {c}: residual {res}");
            assert!((len - 1.0).abs() < 1e-12, "n {n}, column {c}: length {len}");
        }
    }
}

#[test]
fn basis_combined_in_place_equals_the_matrix_product() {
    // the thick restart's V ← V Y (first k columns), in place, and the combination into new
    // vectors, against faer's product of the original V and Y; below and above the parallel
    // threshold (several row blocks)
    use super::basis::{basis_combine, basis_combine_in_place, PAR_MIN, ROW_CHUNK};
    use faer::Mat;
    for rows in [1000, PAR_MIN + ROW_CHUNK / 2] {
        let (m, k) = (31, 17);
        let v0 = Mat::from_fn(rows, m, |i, j| ((i * 31 + j * 17) % 23) as f64 / 23.0 - 0.5);
        let y = Mat::from_fn(m, k, |i, j| ((i * 7 + j * 13) % 19) as f64 / 19.0 - 0.4);
        let want = &v0 * &y;
        let cols0: Vec<Vec<f64>> = (0..m).map(|j| v0.col_as_slice(j).to_vec()).collect();
        let new = basis_combine(&cols0, y.as_ref());
        let mut v = cols0.clone();
        basis_combine_in_place(&mut v, y.as_ref());
        let mut worst = 0.0f64;
        for c in 0..k {
            for i in 0..rows {
                worst = worst.max((v[c][i] - want[(i, c)]).abs());
                worst = worst.max((new[c][i] - want[(i, c)]).abs());
            }
        }
        assert!(worst < 1e-13, "{rows} rows: {worst}");
        assert_eq!(new.len(), k);
        // the columns beyond k are left as they were
        for c in k..m {
            assert_eq!(v[c], cols0[c]);
        }
    }
}

/// Beams `b0` … `b{n−1}` from node `{prefix}i` to `{prefix}{i+1}` with the section data
/// `props`, their y axes along global y.
fn add_chain(b: &mut ModelBuilder, prefix: &str, n: usize, props: BeamProps) {
    for i in 0..n {
        let name = format!("b{i}");
        let nodes = [format!("{prefix}{i}"), format!("{prefix}{}", i + 1)];
        let beam = ElementSpec::Beam {
            orient: Some([0.0, 1.0, 0.0]),
            ct: 0.0,
        };
        b.add_element(&name, &[&nodes[0], &nodes[1]], beam, &[], &[])
            .unwrap();
        b.set_beam_props(&name, props).unwrap();
    }
}

#[test]
fn refined_solves_resolve_what_the_factorisation_cannot() {
    // A cantilever of 200 steel beams, 0.3 m long, 10 mm × 60 nm, along (1, 0, 1)/√2: the
    // axial stiffness EA/l and the bending stiffness 12EI/l³ of a beam fall on the same entries
    // (xx, xz, zz), the axial one 6·10⁸ times larger, and the lowest bending eigenvalue lies
    // 4N³ below the beams' bending entries. The plain solves then lose more of the lowest modes
    // than the accuracy check allows (an error before the refinement: Ritz values against
    // Rayleigh quotients); the refined ones (products through the element deformations; about 7
    // GMRES steps per solve) give the closed form of the
    // Euler–Bernoulli cantilever, ω_k = (β_k L)² √(EI/(ρA L⁴)), βL = 1.875104, 4.694091,
    // 7.854757 (the lowest three modes bend in the x–z plane; shear and rotary inertia change
    // them by (t/L)² ≈ 10⁻¹²; 200 cubic elements are exact to about 10⁻⁹).
    let (n, len, t) = (200, 0.3, 6e-8);
    let p = BeamProps::from_section(&steel(), &Shape::Rectangle { w: 0.01, t }, true);
    let axis = [
        std::f64::consts::FRAC_1_SQRT_2,
        0.0,
        std::f64::consts::FRAC_1_SQRT_2,
    ];
    let mut b = ModelBuilder::new("thin oblique cantilever");
    for i in 0..=n {
        let s = len * i as f64 / n as f64;
        b.add_node(&format!("n{i}"), [s * axis[0], 0.0, s * axis[2]], false)
            .unwrap();
    }
    add_chain(&mut b, "n", n, p);
    b.fix("n0", None).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let m = run(&model, &step, 3, EigenSolver::Sparse);
    let (e, rho) = (210e9, 7800.0);
    let w0 = (e * t * t / (12.0 * rho * len.powi(4))).sqrt();
    for (mode, bl) in m.modes.iter().zip([1.875104_f64, 4.694091, 7.854757]) {
        let want = bl * bl * w0;
        let got = mode.eigenvalue.sqrt();
        assert!(
            (got - want).abs() < 1e-5 * want,
            "ω {got} rad/s vs {want} rad/s"
        );
    }
}

#[test]
fn modes_the_solves_cannot_resolve_are_an_error() {
    // The accuracy check on a list whose second mode's Ritz value is 50 % off its Rayleigh
    // quotient (the first, a rigid-body mode, is round-off in both and not checked).
    let sm = super::SparseModes {
        eigenvalues: vec![1e-12, 2.0, 3.0],
        shapes: vec![Vec::new(); 3],
        ndof: 3,
        massless: 0,
        kinetic: vec![Vec::new(); 3],
        rigid: 1,
        below_gap: None,
        ritz: vec![-1e-9, 3.0, 3.0 * (1.0 + 0.5 * super::RITZ_AGREEMENT)],
    };
    let err = sm.check_accuracy().unwrap_err();
    let ModalError::SparseInaccurate {
        mode,
        ritz,
        rayleigh,
        inaccurate,
        listed,
    } = err
    else {
        panic!("{err}");
    };
    assert_eq!(
        (mode, ritz, rayleigh, inaccurate, listed),
        (2, 3.0, 2.0, 1, 3)
    );
    assert!(err.to_string().contains("fewer, longer elements"));
}

#[test]
fn hosted_rotation_nodes_keep_the_fine_strip_accurate() {
    // The peers' strip in 5000 beams as a SPACAR file maps it: a translational node per point
    // and a rotational node placed `at` it, the beams between the rotational nodes. The fill-
    // reducing order groups the coordinates by point (Problem::point): ordered as separate
    // nodes, the solves lost the first bending mode's digits (Ritz value 24 % off its Rayleigh
    // quotient at 10⁴ beams, an error here). F01: 67.0552 Hz, 420.2279 Hz (validation.md;
    // within the lumped rotary inertia's 1e-5).
    let n = 5000;
    let p = BeamProps::from_section(&steel(), &PEER_SECTION, true);
    let mut b = ModelBuilder::new("strip with hosted rotation nodes");
    for i in 0..=n {
        b.add_node(
            &format!("t{i}"),
            [0.05 * i as f64 / n as f64, 0.0, 0.0],
            false,
        )
        .unwrap();
        b.add_node_at(&format!("r{i}"), &format!("t{i}")).unwrap();
    }
    add_chain(&mut b, "r", n, p);
    b.fix("t0", None).unwrap();
    b.fix("r0", None).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let m = run(&model, &step, 3, EigenSolver::Sparse);
    let bending = bending_frequencies(&m);
    assert_eq!(
        bending.len(),
        2,
        "{:?}",
        m.modes.iter().map(|m| m.frequency).collect::<Vec<_>>()
    );
    for (got, want) in bending.iter().zip([67.0552, 420.2279]) {
        assert!((got - want).abs() < 1e-4 * want, "{got} Hz vs {want} Hz");
    }
}

/// K released during the Lanczos phase of refined solves is made again from the model bit for
/// bit (`Problem::restore_k`): element blocks (with the softening of a spin), the tail of
/// moment loads and normalisations, point masses and added constraint rows, on the guide with
/// a hinge, trusses and a rigid platform, and on a pre-stressed spinning strip with a tip mass,
/// a tip moment and a partly held rotation. (The entries after the element blocks are added by
/// one function for both, `Problem::add_k_rest`; the element part is made on each path, and
/// the softening, the tail, the point masses and the added rows each change K here.)
#[test]
fn k_made_again_is_the_same_bit_for_bit() {
    use super::problem::Problem;
    use crate::linearized::Tangent;
    let mut spun = peer_strip_builder(12, PEER_SECTION);
    spun.set_spin([0.0, 0.0, 30.0], [0.0; 3]).unwrap();
    spun.add_point_mass("n12", 2e-3).unwrap();
    spun.add_load("n12", [0.5, 0.0, 1e-3], [0.0, 2e-4, 0.0])
        .unwrap();
    // a node with one rotation held: its Euler parameters stay unknowns, with the
    // normalisation's row and entries in the tail
    spun.fix("n6", Some(&[Dof::Rx])).unwrap();
    for model in [guide_with_hinge_and_trusses(), spun.build().unwrap()] {
        let step = last_step(&model, 2);
        let t = Tangent::new(&model, &step);
        // an added row: the first node's y translation held
        let mut row = vec![0.0; model.nx];
        let n1 = &model.nodes[1];
        row[n1.ix_pos + 1] = 1.0;
        let p = Problem::with_rows(&t, &[row]);
        let k0: Vec<u64> = p.k_values().iter().map(|v| v.to_bits()).collect();
        assert!(k0.iter().any(|&b| b != 0));
        p.release_k();
        assert!(p.k_values().is_empty());
        p.restore_k(&model, &step);
        let k1: Vec<u64> = p.k_values().iter().map(|v| v.to_bits()).collect();
        assert_eq!(k0.len(), k1.len());
        let differ = k0.iter().zip(&k1).filter(|(a, b)| a != b).count();
        assert_eq!(
            differ,
            0,
            "{}: {differ} of {} values differ",
            model.name,
            k0.len()
        );
    }
}
