//! Validation of the kinematic analysis through the public API (validation.md K05, K06, K07,
//! K08; K03 and K04 are checked on the shipped examples in `flexmbd-io/tests/examples.rs`).

use flexmbd_core::kinematics::{check, CheckOptions, ConstraintAnalysis, Table1};
use flexmbd_core::model::{Dof, ElementSpec, ModelBuilder};
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

/// A rigid truss (a pin-jointed bar, or a point contact along its line).
fn bar(b: &mut ModelBuilder, name: &str, p: &str, q: &str) {
    b.add_element(name, &[p, q], ElementSpec::Truss { ea: 0.0 }, &[], &[])
        .unwrap();
}

/// K05: a platform (reference node `c` at the origin, with rotation) carrying balls on the unit
/// circle at the angles `deg`, one rigid body; each ball sits in a vee: two point contacts, rigid
/// trusses along the normals (e_z ± e_t)/√2 to fixed points, e_t the direction across the
/// groove, from `across(θ)`.
fn coupling(deg: &[f64], across: impl Fn(f64) -> [f64; 3]) -> Model {
    let mut b = ModelBuilder::new("kinematic coupling");
    b.add_node("c", [0.0; 3], true).unwrap();
    let mut members = vec!["c".to_string()];
    for (k, &d) in deg.iter().enumerate() {
        let t = d.to_radians();
        let ball = format!("ball{k}");
        let p = [t.cos(), t.sin(), 0.0];
        b.add_node(&ball, p, false).unwrap();
        members.push(ball.clone());
        let et = across(t);
        for (side, sgn) in [("a", 1.0), ("b", -1.0)] {
            let n: Vec<f64> = (0..3)
                .map(|i| ([0.0, 0.0, 1.0][i] + sgn * et[i]) / 2f64.sqrt())
                .collect();
            let g = format!("g{k}{side}");
            // the fixed end half a unit below the contact along the normal
            b.add_node(
                &g,
                [p[0] - 0.5 * n[0], p[1] - 0.5 * n[1], p[2] - 0.5 * n[2]],
                false,
            )
            .unwrap();
            b.fix(&g, None).unwrap();
            bar(&mut b, &format!("contact{k}{side}"), &g, &ball);
        }
    }
    let names: Vec<&str> = members.iter().map(String::as_str).collect();
    b.add_element("platform", &names, ElementSpec::Rigid, &[], &[])
        .unwrap();
    b.build().unwrap()
}

#[test]
fn k05_kinematic_couplings() {
    // validation.md K05 (D): contacts 6 / 8 / 6, rank of the contact Jacobian 6 / 6 / 5, DOF
    // 0 / 0 / 1 (translation x), over-constraints 0 / 2 / 1. In flexmbd's Dcc the platform is a
    // rigid body: the reference node's 6 velocities plus 3 per ball as columns, 3 rigid rows per
    // ball, so the counts of motions and self-stresses are those of the contacts alone.
    let radial = |t: f64| [-t.sin(), t.cos(), 0.0];
    let maxwell = run(&coupling(&[0.0, 120.0, 240.0], radial));
    assert_eq!((maxwell.m(), maxwell.n(), maxwell.rank), (15, 15, 15));
    assert_eq!(maxwell.case, Table1::SquareRegular);

    let four = run(&coupling(&[0.0, 90.0, 180.0, 270.0], radial));
    assert_eq!((four.m(), four.n(), four.rank), (20, 18, 18));
    assert_eq!((four.motions.len(), four.self_stresses.len()), (0, 2));

    let parallel = run(&coupling(&[0.0, 120.0, 240.0], |_| [0.0, 1.0, 0.0]));
    assert_eq!((parallel.m(), parallel.n(), parallel.rank), (15, 15, 14));
    assert_eq!(parallel.case, Table1::SquareSingular);
    assert_eq!(
        (parallel.motions.len(), parallel.self_stresses.len()),
        (1, 1)
    );
    // the motion: the platform translates along x (the grooves' axis), no rotation: the
    // reference node and the three balls move with x velocity 1/2 each (unit length over 4)
    let mv = &parallel.motions[0].coordinates;
    for node in ["c", "ball0", "ball1", "ball2"] {
        let x = mv
            .iter()
            .find(|c| c.node == node && c.dof == Dof::X)
            .map_or(0.0, |c| c.value);
        assert!((x - 0.5).abs() < 1e-9, "{node}: {mv:?}");
    }
    for c in mv.iter().filter(|c| c.dof != Dof::X) {
        assert!(c.value.abs() < 1e-9, "{mv:?}");
    }
}

/// A planar assembly of rigid bars: joints at `joints` (z = 0, z held), `pinned` of them held.
fn planar(joints: &[(&str, f64, f64)], pinned: &[&str], bars: &[(&str, &str)]) -> Model {
    let mut b = ModelBuilder::new("planar bars");
    for &(n, x, y) in joints {
        b.add_node(n, [x, y, 0.0], false).unwrap();
        b.fix(n, Some(&[Dof::Z])).unwrap();
    }
    for n in pinned {
        b.fix(n, None).unwrap();
    }
    for (k, (p, q)) in bars.iter().enumerate() {
        bar(&mut b, &format!("b{}", k + 1), p, q);
    }
    b.build().unwrap()
}

#[test]
fn k06_pin_jointed_bar_assemblies() {
    // validation.md K06 (D): (joint DOF, bars, rank, s, m) of four planar assemblies; the
    // unsupported square has its 3 planar rigid-body motions among flexmbd's motions.
    let cases = [
        (
            planar(
                &[("a", 0.0, 0.0), ("b", 1.0, 0.0), ("c", 2.0, 0.0)],
                &["a", "c"],
                &[("a", "b"), ("b", "c")],
            ),
            (2, 2, 1, 1, 1),
        ),
        (
            planar(
                &[("a", 0.0, 0.0), ("b", 1.0, 0.1), ("c", 2.0, 0.0)],
                &["a", "c"],
                &[("a", "b"), ("b", "c")],
            ),
            (2, 2, 2, 0, 0),
        ),
        (
            planar(
                &[
                    ("p", 0.0, 0.0),
                    ("q", 2.0, 0.0),
                    ("j", 0.0, 1.0),
                    ("k", 2.0, 1.5),
                ],
                &["p", "q"],
                &[("p", "j"), ("j", "k"), ("k", "q")],
            ),
            (4, 3, 3, 0, 1),
        ),
        (
            planar(
                &[
                    ("a", 0.0, 0.0),
                    ("b", 1.0, 0.0),
                    ("c", 1.0, 1.0),
                    ("d", 0.0, 1.0),
                ],
                &[],
                &[
                    ("a", "b"),
                    ("b", "c"),
                    ("c", "d"),
                    ("d", "a"),
                    ("a", "c"),
                    ("b", "d"),
                ],
            ),
            (8, 6, 5, 1, 3),
        ),
    ];
    for (k, (m, (dof, bars, rank, s, mech))) in cases.iter().enumerate() {
        let a = run(m);
        assert_eq!(
            (a.n(), a.m(), a.rank, a.self_stresses.len(), a.motions.len()),
            (*dof, *bars, *rank, *s, *mech),
            "assembly {k}"
        );
    }
}

/// K07: the tensegrity prism, the top triangle turned by `twist` degrees against the bottom.
fn prism(twist: f64) -> Model {
    let mut b = ModelBuilder::new("tensegrity prism");
    for k in 0..3 {
        let (tb, tt) = (
            (120.0 * k as f64).to_radians(),
            (120.0 * k as f64 + twist).to_radians(),
        );
        b.add_node(&format!("B{k}"), [tb.cos(), tb.sin(), 0.0], false)
            .unwrap();
        b.add_node(&format!("T{k}"), [tt.cos(), tt.sin(), 1.0], false)
            .unwrap();
    }
    for k in 0..3 {
        let l = (k + 1) % 3;
        bar(
            &mut b,
            &format!("bottom{k}"),
            &format!("B{k}"),
            &format!("B{l}"),
        );
        bar(
            &mut b,
            &format!("top{k}"),
            &format!("T{k}"),
            &format!("T{l}"),
        );
        bar(
            &mut b,
            &format!("vertical{k}"),
            &format!("B{k}"),
            &format!("T{k}"),
        );
        bar(
            &mut b,
            &format!("diagonal{k}"),
            &format!("B{k}"),
            &format!("T{l}"),
        );
    }
    b.build().unwrap()
}

#[test]
fn k07_tensegrity_prism() {
    // validation.md K07 (D, Calladine 1978): unsupported, 18 DOF, 12 members, rank 11: one
    // self-stress and one mechanism besides the 6 rigid-body motions; the self-stress triangle
    // edges 0.4597, verticals 0.5176, diagonals −1 (normalised), the smallest non-zero singular
    // value 0.609718. The truss rows of Dcc are the unit bar vectors, so Dcc is the transpose of
    // the equilibrium matrix and has its singular values.
    let a = run(&prism(30.0));
    assert_eq!((a.m(), a.n(), a.rank), (12, 18, 11));
    assert_eq!(a.motions.len(), 7);
    assert_eq!(a.self_stresses.len(), 1);
    let s = &a.singular_values;
    assert!((s[10] - 0.609718).abs() < 1e-6, "{s:?}");
    let ss = &a.self_stresses[0].deformations;
    let diag = ss
        .iter()
        .find(|d| d.element == "diagonal0")
        .map(|d| d.value)
        .unwrap();
    for d in ss {
        let want = if d.element.starts_with("diagonal") {
            -1.0
        } else if d.element.starts_with("vertical") {
            0.5176
        } else {
            0.4597
        };
        assert!(
            (d.value / -diag - want).abs() < 1e-4,
            "{}: {} (diagonal {diag})",
            d.element,
            d.value / -diag
        );
    }
    // control: the top turned by 90° instead of 30°: no self-stress, only rigid-body motions
    let c = run(&prism(90.0));
    assert_eq!((c.rank, c.self_stresses.len(), c.motions.len()), (12, 0, 6));
}
