//! Validation F03 (validation.md): a rotating cantilever (steady rotation, `spin`) — the
//! flapwise frequencies of the table, their convergence, the lead-lag softening, and the dense
//! and sparse eigen solvers on a spinning model with point masses. Through the library API
//! only, as a user of the crate calls it.

mod common;

use common::{last_step, radial_strip, STEEL};
use flexmbd_core::dynamics::modes;
use flexmbd_core::model::{ModelBuilder, Spin};
use flexmbd_core::section::{BeamProps, Shape};
use flexmbd_core::statics::{StaticOptions, StepResult};
use flexmbd_core::Model;

/// Flapwise (global z, out of the plane of rotation) natural frequencies ω̄ = ω √(ρA L⁴/EI)
/// of the rotating clamped strip, lowest first.
/// The static state of the rotating clamped strip (L = 50 mm) at Ω̄ = Ω √(ρA L⁴/EI), and
/// √(EI/(ρA L⁴)).
fn blade_state(n: usize, omega_bar: f64) -> (Model, StepResult, f64) {
    let l: f64 = 0.05;
    let p = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.02, t: 0.2e-3 }, true);
    let c = (p.eiy / (p.rho_a * l.powi(4))).sqrt();
    let spin = Spin {
        omega: [0.0, 0.0, omega_bar * c],
        point: [0.0; 3],
    };
    let model = radial_strip(n, l, 0.0, spin);
    let step = last_step(&model, 1);
    (model, step, c)
}
fn flap_frequencies(n: usize, omega_bar: f64) -> Vec<f64> {
    let (model, step, c) = blade_state(n, omega_bar);
    let modal = modes(&model, &step, 12).unwrap();
    modal
        .modes
        .iter()
        .filter(|m| {
            let (z, all) = m.nodal.iter().fold((0.0, 0.0), |(z, a), (u, _)| {
                (z + u[2] * u[2], a + u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
            });
            let translational: f64 = m.kinetic.iter().map(|k| k.1).sum();
            translational > 0.5 && z > 0.99 * all
        })
        .map(|m| m.frequency * 2.0 * std::f64::consts::PI / c)
        .collect()
}

#[test]
fn f03_rotating_cantilever_flapwise_frequencies() {
    // validation.md F03, tolerance 0.1 %: ω̄1..3 at Ω̄ = 0, 1, 2, 5, 8, 12
    let table = [
        (0.0, [3.5160, 22.0345, 61.6972]),
        (1.0, [3.6816, 22.1810, 61.8418]),
        (2.0, [4.1373, 22.6149, 62.2732]),
        (5.0, [6.4495, 25.4461, 65.2050]),
        (8.0, [9.2568, 29.9954, 70.2930]),
        (12.0, [13.1702, 37.6031, 79.6145]),
    ];
    for (omega_bar, want) in table {
        let got = flap_frequencies(24, omega_bar);
        for k in 0..3 {
            let rel = (got[k] - want[k]) / want[k];
            assert!(
                rel.abs() < 1e-3,
                "Ω̄ = {omega_bar}, mode {}: {} vs {} ({rel:e})",
                k + 1,
                got[k],
                want[k]
            );
        }
    }
}

#[test]
fn f03_converges_with_the_number_of_elements() {
    // Ω̄ = 10: ω̄1 = 11.2023; the error shrinks as the mesh is refined
    let err = |n| ((flap_frequencies(n, 10.0)[0] - 11.2023) / 11.2023).abs();
    let (e4, e16) = (err(4), err(16));
    assert!(e16 < 5e-4, "{e16}");
    assert!(e16 < e4, "{e4} → {e16}");
}

#[test]
fn f03_lead_lag_is_softened_by_omega_squared() {
    // validation.md F03: in the plane of rotation ω̄²_lag = ω̄²_flap − Ω̄² (centrifugal
    // softening, Coriolis coupling to the stiff axial motion neglected). A square
    // 0.5 × 0.5 mm section has the same EI both ways; Ω̄ = 8: flap 9.2568, 29.9954 and lag
    // √(9.2568² − 64) = 4.6571, √(29.9954² − 64) = 28.9089.
    let l: f64 = 0.05;
    let shape = Shape::Rectangle {
        w: 0.5e-3,
        t: 0.5e-3,
    };
    let p = BeamProps::from_section(&STEEL, &shape, true);
    let c = (p.eiy / (p.rho_a * l.powi(4))).sqrt();
    let mut b = ModelBuilder::new("square blade");
    b.add_beam_chain(
        "",
        [0.0; 3],
        [l, 0.0, 0.0],
        24,
        Some([0.0, 1.0, 0.0]),
        Some(p),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    b.set_spin([0.0, 0.0, 8.0 * c], [0.0; 3]).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, StaticOptions::default().steps);
    let modal = modes(&model, &step, 8).unwrap();
    let along = |axis: usize| -> Vec<f64> {
        modal
            .modes
            .iter()
            .filter(|m| {
                let (a, all) = m.nodal.iter().fold((0.0, 0.0), |(s, t), (u, _)| {
                    (
                        s + u[axis] * u[axis],
                        t + u.iter().map(|v| v * v).sum::<f64>(),
                    )
                });
                a > 0.99 * all
            })
            .map(|m| m.frequency * 2.0 * std::f64::consts::PI / c)
            .collect()
    };
    let (flap, lag) = (along(2), along(1));
    for (k, (f, g)) in [(9.2568f64, 4.6571f64), (29.9954, 28.9089)]
        .iter()
        .enumerate()
    {
        assert!(
            (flap[k] - f).abs() < 1e-3 * f,
            "flap {k}: {} vs {f}",
            flap[k]
        );
        assert!((lag[k] - g).abs() < 1e-3 * g, "lag {k}: {} vs {g}", lag[k]);
    }
}

#[test]
fn sparse_and_dense_agree_with_spin_and_point_masses() {
    // the same rotating model through both eigen solvers: a strip off the axis (hub radius
    // 10 mm) with a tip mass, spinning about an inclined axis, so that the softening of
    // the beams and of the point mass both enter, in every direction
    use flexmbd_core::dynamics::{modes_with, EigenSolver, ModalOptions};
    let p = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.004, t: 0.001 }, true);
    let mut b = ModelBuilder::new("hub blade");
    b.add_beam_chain(
        "",
        [0.01, 0.0, 0.0],
        [0.06, 0.0, 0.0],
        16,
        Some([0.0, 1.0, 0.0]),
        Some(p),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    b.add_point_mass("n16", 2e-3).unwrap();
    b.set_spin([0.0, 150.0, 400.0], [0.0, 0.0, 0.0]).unwrap();
    let model = b.build().unwrap();
    let step = last_step(&model, StaticOptions::default().steps);
    let run = |solver| {
        modes_with(&model, &step, 6, &ModalOptions::with_solver(solver))
            .unwrap()
            .modes
            .iter()
            .map(|m| m.eigenvalue)
            .collect::<Vec<f64>>()
    };
    let (dense, sparse) = (run(EigenSolver::Dense), run(EigenSolver::Sparse));
    for (k, (d, s)) in dense.iter().zip(&sparse).enumerate() {
        assert!(
            (d - s).abs() < 1e-7 * d.abs(),
            "mode {k}: dense {d}, sparse {s}"
        );
    }
    // and the spin matters: without it the first eigenvalue differs
    let mut still = model.clone();
    still.loads.spin = None;
    let step0 = last_step(&still, StaticOptions::default().steps);
    let f0 = modes(&still, &step0, 1).unwrap().modes[0].eigenvalue;
    assert!((f0 - dense[0]).abs() > 1e-2 * f0, "{f0} vs {}", dense[0]);
}
