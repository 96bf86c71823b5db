//! Mode classes (issue 19 item 2, docs/dynamics.md "Mode classes") on a parallel-leaf guide
//! whose numbers are known in closed form: the intended translation of the platform, its
//! frequency (Rayleigh with the guided-beam shape), the fractions of a massless-leaf guide
//! (exactly 1), the sums of the parts against independent assemblies, and the dense and sparse
//! eigen paths against each other.

mod common;

use common::{last_step, STEEL};
use flexmbd_core::assembly::{evaluate, mass::mass_matrix};
use flexmbd_core::dynamics::{modes_with, EigenSolver, Modal, ModalOptions, ModeClass};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::model::{DefKind, ElementSpec, ModelBuilder};
use flexmbd_core::section::{BeamProps, Material, Shape};
use flexmbd_core::statics::StepResult;
use flexmbd_core::Model;
use std::f64::consts::PI;

/// Leaf length (along z) and spacing (along x) [m].
const L: f64 = 0.05;
const D: f64 = 0.05;
/// Leaf width (along y) and thickness (along x) [m].
const W: f64 = 0.02;
const T: f64 = 0.2e-3;

/// A parallel-leaf guide: two steel leaves (Euler–Bernoulli, `rho` their density) from bases
/// clamped at z = −L up to z = 0, at x = ∓D/2, each in `n` beams with torsion and out-of-plane
/// bending free (`free = [2, 3, 4]`: the motion along x, the thickness normal, is the released
/// one); a rigid platform over the two tops and its centre c, which carries the point mass `m`.
/// c sits at the leaves' mid-height z = −L/2, where the line of the platform's inertia force
/// passes through the inflection points of the S-bent leaves: the translation along x then
/// needs no end moment on the platform and so no axial force in the leaves (no elongation, a
/// deformation the design makes rigid). With `body_inertia`, c also carries an inertia tensor;
/// `m` = 0 leaves the point mass out.
fn guide_builder(n: usize, m: f64, rho: f64, body_inertia: bool) -> ModelBuilder {
    let mat = Material { rho, ..STEEL };
    let props = BeamProps::from_section(&mat, &Shape::Rectangle { w: W, t: T }, true);
    let mut b = ModelBuilder::new("parallel leaves");
    for (leaf, x) in [(1, -0.5 * D), (2, 0.5 * D)] {
        for k in 0..=n {
            let z = -L + L * k as f64 / n as f64;
            b.add_node(&format!("l{leaf}n{k}"), [x, 0.0, z], false)
                .unwrap();
        }
        for k in 0..n {
            let name = format!("l{leaf}b{k}");
            let nodes = [format!("l{leaf}n{k}"), format!("l{leaf}n{}", k + 1)];
            let spec = ElementSpec::Beam {
                orient: Some([0.0, 1.0, 0.0]),
                ct: 0.0,
            };
            b.add_element(&name, &[&nodes[0], &nodes[1]], spec, &[2, 3, 4], &[])
                .unwrap();
            b.set_beam_props(&name, props).unwrap();
        }
        b.fix(&format!("l{leaf}n0"), None).unwrap();
    }
    b.add_node("c", [0.0, 0.0, -0.5 * L], true).unwrap();
    let tops = [format!("l1n{n}"), format!("l2n{n}")];
    b.add_element(
        "platform",
        &["c", &tops[0], &tops[1]],
        ElementSpec::Rigid,
        &[],
        &[],
    )
    .unwrap();
    if m > 0.0 {
        b.add_point_mass("c", m).unwrap();
    }
    if body_inertia {
        b.add_inertia("c", [2e-4, 0.0, 0.0, 3e-4, 0.0, 4e-4])
            .unwrap();
    }
    b
}

fn modal(model: &Model, step: &StepResult, count: usize, solver: EigenSolver) -> Modal {
    modes_with(model, step, count, &ModalOptions::with_solver(solver)).expect("modes")
}

/// E I of a leaf about its width axis, the bending of the motion along x.
fn ei() -> f64 {
    STEEL.e * W * T.powi(3) / 12.0
}

#[test]
fn the_platform_translation_is_the_intended_mode_at_the_rayleigh_frequency() {
    // platform m = 1 kg, each leaf m_leaf = ρ W T L = 1.56 g. Rayleigh with the static shape
    // of a clamped–guided beam: stiffness 2 · 12 EI/L³, effective mass of each leaf 13/35 of
    // its own: f = √(24 EI / (L³ (m + 2 (13/35) m_leaf))) / 2π. The shape error is O(μ),
    // μ = m_leaf/m = 1.6e-3, so the Rayleigh frequency is high by O(μ²) ≈ 2.4e-6: tolerance
    // 1e-5 (the leaves' mass term itself moves f by 5.8e-4, so the test sees it).
    let m = 1.0;
    let m_leaf = STEEL.rho * W * T * L;
    let model = guide_builder(4, m, STEEL.rho, false).build().unwrap();
    let step = last_step(&model, 1);
    let r = modal(&model, &step, 4, EigenSolver::Dense);
    let first = &r.modes[0];
    assert_eq!(first.class, ModeClass::Intended);
    let want = (24.0 * ei() / (L.powi(3) * (m + 2.0 * 13.0 / 35.0 * m_leaf))).sqrt() / (2.0 * PI);
    let rel = (first.frequency - want).abs() / want;
    assert!(
        rel < 1e-5,
        "f1 = {} Hz, closed form {want} Hz ({rel:.1e})",
        first.frequency
    );
    // the platform carries all but the leaves' share of the kinetic energy: in the same
    // shape β = m / (m + 2 (13/35) m_leaf) = 0.998842 (to O(μ²)); the strain energy is
    // out-of-plane bending
    let beta = m / (m + 2.0 * 13.0 / 35.0 * m_leaf);
    assert!(
        (first.fractions.body - beta).abs() < 1e-5,
        "{:?} vs {beta}",
        first.fractions
    );
    assert!(
        first.fractions.released.unwrap() > 0.999_999,
        "{:?}",
        first.fractions
    );
    // the next mode, the platform's translation along y, bends the leaves in their plane,
    // which the design makes rigid: support (√(24 E T W³/12 /(L³ m))/2π = 370 Hz)
    let second = &r.modes[1];
    assert_eq!(second.class, ModeClass::Support, "{:?}", classes(&r));
    assert!(second.fractions.body > 0.99, "{:?}", second.fractions);
    assert!(
        second.fractions.released.unwrap() < 1e-6,
        "{:?}",
        second.fractions
    );
}

fn classes(r: &Modal) -> Vec<(f64, ModeClass)> {
    r.modes.iter().map(|m| (m.frequency, m.class)).collect()
}

#[test]
fn massless_leaves_give_exactly_one_for_both_fractions() {
    // ρ = 0: the only mass is the platform's point mass, so β = 1 exactly; the translation
    // along x bends the leaves only out of plane (released): ρ = 1 to round-off. With only the
    // platform's translations carrying mass, the guide has three modes (x, y, z of c); its
    // frequency is the static one √(24 EI/(L³ m))/2π exactly (one cubic element per leaf is
    // exact for the end-loaded beam).
    let m = 0.5;
    let model = guide_builder(1, m, 0.0, false).build().unwrap();
    let step = last_step(&model, 1);
    // (both paths: the sparse one once returned no mode for this model, whose only mass sits on
    // a node that only a rigid body holds)
    for solver in [EigenSolver::Dense, EigenSolver::Sparse] {
        let r = modal(&model, &step, 3, solver);
        let first = &r.modes[0];
        assert_eq!(first.class, ModeClass::Intended, "{solver:?}");
        assert_eq!(first.fractions.body, 1.0, "{solver:?}");
        assert_eq!(first.fractions.kinetic_elements, 0.0, "{solver:?}");
        let rho = first.fractions.released.unwrap();
        assert!((rho - 1.0).abs() < 1e-10, "{solver:?}: ρ = {rho}");
        let want = (24.0 * ei() / (L.powi(3) * m)).sqrt() / (2.0 * PI);
        assert!(
            (first.frequency - want).abs() < 1e-9 * want,
            "{solver:?}: {} vs {want}",
            first.frequency
        );
    }
}

#[test]
fn the_parts_add_up_to_independent_assemblies() {
    // a state with pre-stress (a load on the platform along z stretches the leaves) and an
    // inertia tensor on the platform. Independent sums per mode:
    // - vᵀ M v = 1 (mass-normalised) with M from `mass_matrix`, and the elements' part equal
    //   to vᵀ M' v with M' the mass matrix of the same model without its point mass and inertia:
    //   β = 1 − vᵀ M' v / vᵀ M v;
    // - the strain energy split: ½ δeᵢ (S δe)ᵢ with δe = D v from `assembly::evaluate` (the dense
    //   Jacobian) and S of each element, summed over the free deformations and the others.
    let build = |m: f64, inertia: bool| {
        let mut b = guide_builder(3, m, STEEL.rho, inertia);
        b.add_load("c", [0.0, 0.0, 40.0], [0.0; 3]).unwrap();
        b.build().unwrap()
    };
    let model = build(0.2, true);
    let bare = build(0.0, false);
    assert_eq!(model.nx, bare.nx);
    let step = last_step(&model, 2);
    let r = modal(&model, &step, 8, EigenSolver::Dense);
    let m_all = mass_matrix(&model, &step.x);
    let m_el = mass_matrix(&bare, &step.x);
    let ev = evaluate(&model, &step.x);
    let quad = |m: &faer::Mat<f64>, v: &[f64]| -> f64 {
        (0..v.len())
            .map(|i| v[i] * (0..v.len()).map(|j| m[(i, j)] * v[j]).sum::<f64>())
            .sum()
    };
    let mut kinds = std::collections::HashSet::new();
    for (k, mode) in r.modes.iter().enumerate() {
        let v = &mode.shape;
        let f = &mode.fractions;
        let (t, t_el) = (quad(&m_all, v), quad(&m_el, v));
        assert!((t - 1.0).abs() < 1e-8, "mode {k}: vᵀMv = {t}");
        assert!(
            (f.kinetic_bodies + f.kinetic_elements - t).abs() < 1e-12 * t,
            "mode {k}"
        );
        assert!((f.kinetic_elements - t_el).abs() < 1e-12 * t, "mode {k}");
        assert!((f.body - (1.0 - t_el / t)).abs() < 1e-12, "mode {k}: {f:?}");
        // strain energy from the dense D and each element's S
        let de: Vec<f64> = (0..model.ne)
            .map(|i| (0..model.nx).map(|j| ev.D[(i, j)] * v[j]).sum())
            .collect();
        let (mut released, mut stiff) = (0.0, 0.0);
        for entry in &model.elements {
            let s = entry.element.stiffness();
            let ne = entry.element.ne();
            for a in 0..ne {
                let sigma: f64 = (0..ne).map(|b| s[(a, b)] * de[entry.ie + b]).sum();
                let u = 0.5 * de[entry.ie + a] * sigma;
                match model.partition.e[entry.ie + a] {
                    DefKind::Free | DefKind::Input => released += u,
                    DefKind::Fixed => stiff += u,
                }
            }
        }
        let total = released + stiff;
        assert!(
            (f.strain_released - released).abs() < 1e-9 * total,
            "mode {k}"
        );
        assert!((f.strain_stiff - stiff).abs() < 1e-9 * total, "mode {k}");
        let rho = f.released.unwrap();
        assert!((rho + stiff / total - 1.0).abs() < 1e-12, "mode {k}: {f:?}");
        kinds.insert(mode.class);
    }
    // the spectrum has the three kinds (the leaves' own modes are internal)
    assert_eq!(kinds.len(), 3, "{:?}", classes(&r));
}

#[test]
fn without_bodies_every_mode_is_internal() {
    // no point mass, no inertia: β = 0 for every mode (docs/dynamics.md)
    let model = guide_builder(2, 0.0, STEEL.rho, false).build().unwrap();
    let step = last_step(&model, 1);
    let r = modal(&model, &step, 6, EigenSolver::Dense);
    for m in &r.modes {
        assert_eq!(m.fractions.body, 0.0);
        assert_eq!(m.class, ModeClass::Internal);
    }
}

#[test]
fn dense_and_sparse_paths_give_the_same_classes() {
    // 2 × 8 beams: 102 velocity coordinates, above the automatic switch (48); both forced
    let model = guide_builder(8, 0.3, STEEL.rho, true).build().unwrap();
    let step = last_step(&model, 1);
    let d = modal(&model, &step, 8, EigenSolver::Dense);
    let s = modal(&model, &step, 8, EigenSolver::Sparse);
    assert_eq!(d.solver, EigenSolver::Dense);
    assert_eq!(s.solver, EigenSolver::Sparse);
    for (k, (a, b)) in d.modes.iter().zip(&s.modes).enumerate() {
        assert_eq!(a.class, b.class, "mode {k}");
        let (fa, fb) = (&a.fractions, &b.fractions);
        assert!((fa.body - fb.body).abs() < 1e-8, "mode {k}: {fa:?} {fb:?}");
        let (ra, rb) = (fa.released.unwrap(), fb.released.unwrap());
        assert!((ra - rb).abs() < 1e-8, "mode {k}: {fa:?} {fb:?}");
    }
}

#[test]
fn a_mass_held_still_by_constraints_adds_no_mode_on_either_path() {
    // The massless-leaf guide plus a second body: a rigid arm from a clamped node to a node
    // `g` that carries a point mass. g cannot move (the arm is held at its clamped end), so
    // its mass adds no finite eigenvalue: still the three translations of c (x at the static
    // frequency √(24 EI/(L³ m))/2π), however many modes are asked for; the sparse path must not
    // invent modes from the held mass nor lose the real ones.
    let m = 0.5;
    let mut b = guide_builder(1, m, 0.0, false);
    b.add_node("base", [0.2, 0.0, 0.0], true).unwrap();
    b.fix("base", None).unwrap();
    b.add_node("g", [0.3, 0.0, 0.0], false).unwrap();
    b.add_element("arm", &["base", "g"], ElementSpec::Rigid, &[], &[])
        .unwrap();
    b.add_point_mass("g", 2.0).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, 1);
    let want = (24.0 * ei() / (L.powi(3) * m)).sqrt() / (2.0 * PI);
    for solver in [EigenSolver::Dense, EigenSolver::Sparse] {
        let r = modal(&model, &step, 6, solver);
        assert_eq!(r.modes.len(), 3, "{solver:?}: {:?}", classes(&r));
        let f = r.modes[0].frequency;
        assert!((f - want).abs() < 1e-9 * want, "{solver:?}: {f} vs {want}");
    }
}
