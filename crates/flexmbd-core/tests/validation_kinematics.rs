//! Validation of the kinematic analysis through the public API (validation.md K08; K03 and
//! K04 are checked on the shipped examples in `flexmbd-io/tests/examples.rs`).

use flexmbd_core::kinematics::{check, CheckOptions, ConstraintAnalysis, Table1};
use flexmbd_core::model::Dof;
use flexmbd_core::Model;

/// The test models of the core's kinematics tests (they name `crate::model`).
mod model {
    pub use flexmbd_core::model::*;
}
#[allow(dead_code)]
#[path = "../src/kinematics/test_models.rs"]
mod test_models;

fn run(m: &Model) -> ConstraintAnalysis {
    check(m, &m.partition, &m.x0(), &CheckOptions::default()).unwrap()
}

#[test]
fn k08_twelve_truss_of_the_paper() {
    // K08 / theory.md §7: singular values from an independent numpy reproduction, tolerance
    // 1e-6 as validation.md states; motion of the paper's eq. (16); self-stress ±√3/6.
    let m = test_models::twelve_truss();
    let a = run(&m);
    assert_eq!((a.m(), a.n(), a.rank), (12, 12, 11));
    assert_eq!(a.case, Table1::SquareSingular);
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let expect = [
        3f64.sqrt(),
        phi,
        phi,
        2f64.sqrt(),
        1.0,
        1.0,
        1.0,
        1.0,
        1.0,
        phi - 1.0,
        phi - 1.0,
        0.0,
    ];
    for (s, e) in a.singular_values.iter().zip(expect) {
        assert!(
            (s - e).abs() < 1e-9,
            "singular values {:?}",
            a.singular_values
        );
    }
    // motion: t1 (0, −½, 0), t2 (−½, 0, 0), t3 (0, ½, 0), t4 (½, 0, 0), up to sign
    let mv = &a.motions[0].coordinates;
    assert_eq!(mv.len(), 4, "{mv:?}");
    let sign = mv.iter().find(|c| c.node == "t3").unwrap().value.signum();
    for (node, dof, val) in [
        ("t1", Dof::Y, -0.5),
        ("t2", Dof::X, -0.5),
        ("t3", Dof::Y, 0.5),
        ("t4", Dof::X, 0.5),
    ] {
        let c = mv
            .iter()
            .find(|c| c.node == node && c.dof == dof)
            .expect("entry");
        assert!((c.value - sign * val).abs() < 1e-12, "{node}: {}", c.value);
    }
    // self-stress: all twelve ±√3/6, signs as in theory.md §7 up to overall sign
    let ss = &a.self_stresses[0].deformations;
    assert_eq!(ss.len(), 12);
    let pattern = [-1., -1., 1., 1., -1., -1., 1., 1., -1., 1., -1., 1.];
    let s0 = ss[0].value.signum() * pattern[0];
    for (d, p) in ss.iter().zip(pattern) {
        assert!(
            (d.value - s0 * p * 3f64.sqrt() / 6.0).abs() < 1e-12,
            "{}: {}",
            d.element,
            d.value
        );
    }
}
