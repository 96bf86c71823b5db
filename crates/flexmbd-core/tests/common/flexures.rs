//! Flexure mechanisms of the kinematic screw tests: wire guides (paper Fig. 3a) with a chosen
//! set of wires, the parallel-leaf guide (K03) and the cross-spring pivot (K04).

use flexmbd_core::model::{Dof, ElementSpec, ModelBuilder};
use flexmbd_core::Model;

/// The attachment node a_i on the platform and the ground node g_i of wire i (1..6), in m.
/// Wires 1–5 are those of examples/wire_guide_5.toml (1–3 vertical below the platform, 4 and 5
/// along y beside it); wire 6 runs from a6 = (0, −0.03, 0) down along −(0, 1, 1)/√2 for 50 mm.
pub fn wire_nodes(i: usize) -> ([f64; 3], [f64; 3]) {
    let s = 0.05 / 2f64.sqrt();
    match i {
        1 => ([-0.05, -0.03, 0.0], [-0.05, -0.03, -0.05]),
        2 => ([-0.05, 0.03, 0.0], [-0.05, 0.03, -0.05]),
        3 => ([0.05, 0.0, 0.0], [0.05, 0.0, -0.05]),
        4 => ([-0.05, 0.03, 0.01], [-0.05, 0.08, 0.01]),
        5 => ([0.05, 0.03, 0.01], [0.05, 0.08, 0.01]),
        _ => ([0.0, -0.03, 0.0], [0.0, -0.03 - s, -s]),
    }
}

/// A rigid platform (one `rigid` element `platform` over the centre node c at the origin and
/// the attachment nodes a1…a6) on the wires `wires` (each a beam `w<i>` from g<i> to a<i> with
/// only its elongation rigid); every ground node g1…g6 is fully fixed, also those of wires left
/// out (the places where a wire could go). With `input_x` the platform's x (c.x) is the
/// generalised coordinate, as in examples/wire_guide_5.toml.
pub fn wire_guide(wires: &[usize], input_x: bool) -> Model {
    wire_guide_with(wires, input_x, &[])
}

/// [`wire_guide`] with rigid trusses (`extra1`, `extra2`, …) between the node pairs `extra`.
pub fn wire_guide_with(wires: &[usize], input_x: bool, extra: &[(&str, &str)]) -> Model {
    let mut b = ModelBuilder::new("wire guide");
    b.add_node("c", [0.0; 3], true).unwrap();
    for i in 1..=6 {
        let (a, g) = wire_nodes(i);
        b.add_node(&format!("a{i}"), a, true).unwrap();
        b.add_node(&format!("g{i}"), g, true).unwrap();
        b.fix(&format!("g{i}"), None).unwrap();
    }
    for &i in wires {
        b.add_element(
            &format!("w{i}"),
            &[&format!("g{i}"), &format!("a{i}")],
            ElementSpec::Beam {
                orient: None,
                ct: 0.0,
            },
            &[2, 3, 4, 5, 6],
            &[],
        )
        .unwrap();
    }
    for (k, (p, q)) in extra.iter().enumerate() {
        let truss = ElementSpec::Truss { ea: 1.0 };
        b.add_element(&format!("extra{}", k + 1), &[p, q], truss, &[], &[])
            .unwrap();
    }
    let platform = ["c", "a1", "a2", "a3", "a4", "a5", "a6"];
    b.add_element("platform", &platform, ElementSpec::Rigid, &[], &[])
        .unwrap();
    if input_x {
        b.input("c", Some(&[Dof::X])).unwrap();
    }
    b.build().unwrap()
}

/// Two full-width leaves (beams with orientation vector y: torsion and out-of-plane bending
/// free, elongation and in-plane bending rigid) from fixed bases b1, b2 to t1, t2, joined by a
/// rigid `platform`: the parallel-leaf guide of examples/parallel_leaf_guide.toml (leaves
/// along z in the planes x = ∓0.025) or, with `cross`, the cross-spring pivot of
/// examples/cross_spring_pivot.toml (leaves in the x-z plane crossing on the y axis).
pub fn leaf_mechanism(cross: bool) -> Model {
    let (b1, t1, b2, t2) = if cross {
        (
            [-0.03, 0.0, -0.03],
            [0.03, 0.0, 0.03],
            [0.03, 0.0, -0.03],
            [-0.03, 0.0, 0.03],
        )
    } else {
        (
            [-0.025, 0.0, -0.05],
            [-0.025, 0.0, 0.0],
            [0.025, 0.0, -0.05],
            [0.025, 0.0, 0.0],
        )
    };
    let mut b = ModelBuilder::new(if cross {
        "cross-spring pivot"
    } else {
        "parallel-leaf guide"
    });
    for (n, p) in [("b1", b1), ("t1", t1), ("b2", b2), ("t2", t2)] {
        b.add_node(n, p, true).unwrap();
    }
    for (leaf, nodes) in [("leaf1", ["b1", "t1"]), ("leaf2", ["b2", "t2"])] {
        b.add_element(
            leaf,
            &nodes,
            ElementSpec::Beam {
                orient: Some([0.0, 1.0, 0.0]),
                ct: 0.0,
            },
            &[2, 3, 4],
            &[],
        )
        .unwrap();
    }
    b.add_element("platform", &["t1", "t2"], ElementSpec::Rigid, &[], &[])
        .unwrap();
    b.fix("b1", None).unwrap();
    b.fix("b2", None).unwrap();
    b.build().unwrap()
}
