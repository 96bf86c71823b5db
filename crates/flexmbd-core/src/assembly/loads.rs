//! The loads of acceleration fields on the model's mass: gravity and the centrifugal field of a
//! steady rotation ([`crate::model::Spin`]), as nodal forces and moments.
//!
//! One mass model serves the mass matrix and these loads: each element's loads come from
//! [`ElementKind::field_loads`], consistent with its [`ElementKind::mass`] (the beam: the
//! Hermite centre line, `elements/beam/mass.rs`); a point mass m gets m a(r), an inertia tensor
//! the gyroscopic moment −Ω × (I Ω). The loads are computed on the reference configuration and
//! applied as dead loads growing with the load factor (statics).

use crate::assembly::gather;
use crate::elements::ElementKind;
use crate::model::Model;

/// The nodal loads of gravity and of the model's spin on the reference configuration: per node
/// (force, moment) in global axes [N, N·m]; all zero without gravity and spin.
pub fn field_loads(model: &Model) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = vec![([0.0; 3], [0.0; 3]); model.nodes.len()];
    let Some(field) = model.loads.acceleration_field() else {
        return out;
    };
    let x0 = model.x0();
    let add = |v: &mut [f64; 3], a: [f64; 3]| {
        for k in 0..3 {
            v[k] += a[k];
        }
    };
    let mut per_use = Vec::new();
    for entry in &model.elements {
        let uses = entry.element.node_uses();
        per_use.clear();
        per_use.resize(uses.len(), ([0.0; 3], [0.0; 3]));
        entry
            .element
            .field_loads(&gather(entry, &x0), &field, &mut per_use);
        for (u, (f, m)) in uses.iter().zip(&per_use) {
            add(&mut out[u.node].0, *f);
            add(&mut out[u.node].1, *m);
        }
    }
    for &(node, m) in &model.loads.point_masses {
        let a = field.at(model.nodes[node].x0);
        add(&mut out[node].0, a.map(|v| m * v));
    }
    for (node, tensor) in &model.loads.inertias {
        add(&mut out[*node].1, field.gyroscopic_moment(tensor));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::modes;
    use crate::model::{ModelBuilder, Spin};
    use crate::section::{BeamProps, Material, Shape};
    use crate::statics::{last_step, StaticOptions};

    const STEEL: Material = Material {
        e: 210e9,
        g: 210e9 / 2.6,
        rho: 7800.0,
    };

    /// `n` beams along x from the origin, length `l`, width 20 mm along global y and thickness
    /// 0.2 mm along global z; clamped at the root; an optional tip mass.
    fn radial_strip(n: usize, l: f64, tip: f64, spin: Spin) -> Model {
        let mut b = ModelBuilder::new("blade");
        let props = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.02, t: 0.2e-3 }, true);
        b.add_beam_chain(
            "",
            [0.0; 3],
            [l, 0.0, 0.0],
            n,
            Some([0.0, 1.0, 0.0]),
            Some(props),
        )
        .unwrap();
        if tip > 0.0 {
            b.add_point_mass(&format!("n{n}"), tip).unwrap();
        }
        b.fix("n0", None).unwrap();
        b.set_spin(spin.omega, spin.point).unwrap();
        b.build().unwrap()
    }

    #[test]
    fn radial_beam_gets_the_consistent_centrifugal_loads() {
        // ρA = 7800 · 20 mm · 0.2 mm = 0.0312 kg/m, L = 2, Ω = 5 about z through the origin,
        // tip mass 0.5 kg: q(x) = ρAΩ² x along x. On an element [x1, x1 + h] the Hermite-
        // consistent end forces are c h (x1/2 + 3h/20) and c h (x1/2 + 7h/20) (∫H1 = ∫H3 = 1/2,
        // ∫H1 ξ = 3/20, ∫H3 ξ = 7/20); the tip mass adds m Ω² L; no moments (t × P r = 0).
        let spin = Spin {
            omega: [0.0, 0.0, 5.0],
            point: [0.0; 3],
        };
        let m = radial_strip(4, 2.0, 0.5, spin);
        let loads = field_loads(&m);
        let (c, h) = (0.0312 * 25.0, 0.5);
        for (i, load) in loads.iter().enumerate() {
            let mut want = 0.0;
            if i > 0 {
                want += c * h * (h * (i - 1) as f64 / 2.0 + 7.0 * h / 20.0);
            }
            if i < 4 {
                want += c * h * (h * i as f64 / 2.0 + 3.0 * h / 20.0);
            } else {
                want += 0.5 * 25.0 * 2.0;
            }
            assert!(
                (load.0[0] - want).abs() < 1e-12 * want.max(1.0),
                "node {i}: {} vs {want}",
                load.0[0]
            );
            assert!(load.0[1].abs() < 1e-15 && load.0[2].abs() < 1e-15);
            assert!(load.1.iter().all(|v| v.abs() < 1e-15), "{:?}", load.1);
        }
    }

    #[test]
    fn gravity_loads_are_the_mass_matrix_times_the_rigid_acceleration() {
        // one mass model: the generalised gravity force is M ẍ_g, ẍ_g the coordinate
        // acceleration of a rigid translation by g (g on every position, λ̈ = 0). On λ a moment m
        // is the generalised force 2 Λ̄ᵀ m = (0, 2m) at the reference orientation. An inclined
        // beam chain with a point mass, so that every Hermite term and the end moments enter.
        let g = [0.3, -9.81, 1.7];
        let p = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.02, t: 0.002 }, true);
        let mut b = ModelBuilder::new("inclined");
        b.add_beam_chain(
            "",
            [0.1, 0.0, 0.2],
            [0.4, 0.5, -0.1],
            3,
            Some([0.0, 0.0, 1.0]),
            Some(p),
        )
        .unwrap();
        b.add_point_mass("n2", 0.25).unwrap();
        b.set_gravity(g).unwrap();
        let m = b.build().unwrap();
        let x0 = m.x0();
        let mx = crate::assembly::mass::mass_matrix(&m, &x0);
        let mut a = vec![0.0; m.nx];
        for n in &m.nodes {
            a[n.ix_pos..n.ix_pos + 3].copy_from_slice(&g);
        }
        let ma: Vec<f64> = (0..m.nx)
            .map(|i| (0..m.nx).map(|j| mx[(i, j)] * a[j]).sum())
            .collect();
        let loads = field_loads(&m);
        let scale = ma.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        for (n, (f, mom)) in m.nodes.iter().zip(&loads) {
            for k in 0..3 {
                assert!((ma[n.ix_pos + k] - f[k]).abs() < 1e-13 * scale, "{f:?}");
            }
            let r = n.ix_rot.unwrap();
            assert!(ma[r].abs() < 1e-13 * scale);
            for k in 0..3 {
                let want = 2.0 * mom[k];
                assert!((ma[r + 1 + k] - want).abs() < 1e-13 * scale, "{mom:?}");
            }
        }
        // and the end moments are there: ρA l0² |t × g|/12 at the first node
        let l0 = ((0.3f64).powi(2) + 0.25 + 0.09).sqrt() / 3.0;
        let t = [0.3 / (3.0 * l0), 0.5 / (3.0 * l0), -0.3 / (3.0 * l0)];
        let txg = crate::math::cross(t, g);
        let want = p.rho_a * l0 * l0 / 12.0;
        for k in 0..3 {
            assert!(
                (loads[0].1[k] - want * txg[k]).abs() < 1e-12 * want,
                "{:?}",
                loads[0].1
            );
        }
    }

    #[test]
    fn offset_axis_loads_reproduce_resultant_and_moment() {
        // a spin Ω = 2 about x through (0, 1, 0): every point of the beam (on y = 0) is 1 m
        // off the axis, so the load is −ρAΩ² per length along y: resultant −(0.0312·2 + 0.5)·4,
        // moment about z at the origin −ρAΩ² L²/2 − m Ω² L (tip mass at x = L)
        let spin = Spin {
            omega: [2.0, 0.0, 0.0],
            point: [0.0, 1.0, 0.0],
        };
        let m = radial_strip(3, 2.0, 0.5, spin);
        let loads = field_loads(&m);
        let fy: f64 = loads.iter().map(|l| l.0[1]).sum();
        let fx: f64 = loads.iter().map(|l| l.0[0]).sum();
        assert!((fy + (0.0312 * 2.0 + 0.5) * 4.0).abs() < 1e-12, "{fy}");
        assert!(fx.abs() < 1e-15);
        let mz: f64 = loads
            .iter()
            .zip(&m.nodes)
            .map(|(l, n)| n.x0[0] * l.0[1] - n.x0[1] * l.0[0] + l.1[2])
            .sum();
        let want = -0.0312 * 4.0 * 2.0 - 0.5 * 4.0 * 2.0;
        assert!((mz - want).abs() < 1e-12, "{mz} vs {want}");
    }

    #[test]
    fn rigid_body_moment_is_minus_omega_cross_i_omega() {
        // I = diag(1, 2, 3), Ω = (1, 1, 0): I Ω = (1, 2, 0), Ω × IΩ = (0, 0, 1)
        let spin = Spin {
            omega: [1.0, 1.0, 0.0],
            point: [0.0; 3],
        };
        let i = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]];
        let field = crate::elements::AccelerationField {
            w: spin.projector(),
            point: spin.point,
            uniform: [0.0; 3],
            omega: spin.omega,
        };
        assert_eq!(field.gyroscopic_moment(&i), [0.0, 0.0, -1.0]);
    }

    /// Flapwise (global z, out of the plane of rotation) natural frequencies ω̄ = ω √(ρA L⁴/EI)
    /// of the rotating clamped strip, lowest first.
    /// The static state of the rotating clamped strip (L = 50 mm) at Ω̄ = Ω √(ρA L⁴/EI), and
    /// √(EI/(ρA L⁴)).
    fn blade_state(n: usize, omega_bar: f64) -> (Model, crate::statics::StepResult, f64) {
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
        use crate::dynamics::{modes_with, EigenSolver, ModalOptions};
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
            modes_with(&model, &step, 6, &ModalOptions { solver })
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
}
