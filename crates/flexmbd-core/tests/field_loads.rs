//! The loads of acceleration fields on the model's mass (`assembly::loads::field_loads`):
//! consistent centrifugal and gravity loads against closed forms, the mass matrix and the
//! resultants, through the library API.

mod common;

use common::{radial_strip, STEEL};
use flexmbd_core::assembly::loads::field_loads;
use flexmbd_core::model::{ModelBuilder, Spin};
use flexmbd_core::section::{BeamProps, Shape};

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
    let mx = flexmbd_core::assembly::mass::mass_matrix(&m, &x0);
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
    let txg = flexmbd_core::math::cross(t, g);
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
    let field = flexmbd_core::elements::AccelerationField {
        w: spin.projector(),
        point: spin.point,
        uniform: [0.0; 3],
        omega: spin.omega,
    };
    assert_eq!(field.gyroscopic_moment(&i), [0.0, 0.0, -1.0]);
}
