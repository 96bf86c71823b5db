//! Model generators of the kinematics tests, also compiled into the lattice bench
//! (`benches/lattice_check.rs` includes this file; it names only `crate::model`, which the bench
//! re-exports; so do the core's integration tests): a 3D lattice of rigid pin-jointed trusses, a
//! strip of beams and the 12-truss of the paper (validation.md K08).

use crate::model::{Dof, ElementSpec, Model, ModelBuilder};

/// The grid node (i, j, l) of a lattice.
pub fn lattice_node(i: usize, j: usize, l: usize) -> String {
    format!("n{i}_{j}_{l}")
}

/// A lattice of k × k × k cube cells with unit edges: nodes on the (k + 1)³ grid, a rigid
/// truss on every cube edge and one diagonal per face (from the face's lowest corner to its
/// highest), the bottom layer (z = 0) supported. Bars between two supported nodes are left out
/// (they would be rows of zeros). The same model as `bench/lattice_model.py` writes as TOML.
/// Dcc has 3 k (k + 1)² free coordinates as columns and 3 k (k + 1)² + 3 k² (k + 1) − 2 k (k + 1)
/// − k² bars as rows (k = 4: 484 × 300).
pub fn lattice(k: usize) -> Model {
    let mut b = ModelBuilder::new(&format!("lattice k = {k}"));
    let mut bars: Vec<([usize; 3], [usize; 3])> = Vec::new();
    for l in 0..=k {
        for j in 0..=k {
            for i in 0..=k {
                let name = lattice_node(i, j, l);
                b.add_node(&name, [i as f64, j as f64, l as f64], false)
                    .expect("new node");
                if l == 0 {
                    b.fix(&name, None).expect("known node");
                }
                let p = [i, j, l];
                let mut bar = |q: [usize; 3]| {
                    if !(p[2] == 0 && q[2] == 0) {
                        bars.push((p, q));
                    }
                };
                if i < k {
                    bar([i + 1, j, l]);
                }
                if j < k {
                    bar([i, j + 1, l]);
                }
                if l < k {
                    bar([i, j, l + 1]);
                }
                if i < k && j < k {
                    bar([i + 1, j + 1, l]);
                }
                if i < k && l < k {
                    bar([i + 1, j, l + 1]);
                }
                if j < k && l < k {
                    bar([i, j + 1, l + 1]);
                }
            }
        }
    }
    for (t, (p, q)) in bars.iter().enumerate() {
        let (p, q) = (
            lattice_node(p[0], p[1], p[2]),
            lattice_node(q[0], q[1], q[2]),
        );
        b.add_element(
            &format!("b{}", t + 1),
            &[&p, &q],
            ElementSpec::Truss { ea: 0.0 },
            &[],
            &[],
        )
        .expect("valid truss");
    }
    b.build().expect("valid lattice")
}

/// A straight strip of `n` beams along x (unit total length), clamped at x = 0, each beam with
/// the deformation modes `free` free (1-based as in model files; `&[]`: rigid beams), and the
/// listed dofs of the tip taken as generalised coordinates. Rigid beams give a square, regular
/// Dcc of 6 n × 6 n.
pub fn strip(n: usize, free: &[i64], tip_inputs: &[Dof]) -> Model {
    let mut b = ModelBuilder::new(&format!("strip of {n} beams"));
    for i in 0..=n {
        b.add_node(&format!("s{i}"), [i as f64 / n as f64, 0.0, 0.0], true)
            .expect("new node");
    }
    for i in 0..n {
        b.add_element(
            &format!("beam{i}"),
            &[&format!("s{i}"), &format!("s{}", i + 1)],
            ElementSpec::Beam {
                orient: Some([0.0, 1.0, 0.0]),
                ct: 0.0,
            },
            free,
            &[],
        )
        .expect("valid beam");
    }
    b.fix("s0", None).expect("known node");
    if !tip_inputs.is_empty() {
        b.input(&format!("s{n}"), Some(tip_inputs))
            .expect("known node");
    }
    b.build().expect("valid strip")
}

/// The two nodes of a truss, from its x map (x, y, z of each).
pub fn truss_nodes(m: &Model, entry: &crate::model::ElementEntry) -> [usize; 2] {
    [0, 3].map(|o| {
        m.nodes
            .iter()
            .position(|n| n.ix_pos == entry.x_index(o))
            .expect("node of the truss")
    })
}

/// The pendant node t of [`lattice_with_pendants`].
pub fn pendant_node(t: usize) -> String {
    format!("p{t}")
}

/// The lattice of [`lattice`] with `p` ≤ k pendant nodes above its top face: node t at
/// (t + ½, −½, k + ½), held by two rigid trusses to the top nodes (t, 0, k) and (t + 1, 0, k).
/// Each pendant adds three columns and two independent rows, hence one motion: a velocity of
/// the pendant alone along (0, 1, 1)/√2, normal to both of its bars.
pub fn lattice_with_pendants(k: usize, p: usize) -> Model {
    assert!(p <= k, "at most k pendants");
    let base = lattice(k);
    let mut b = ModelBuilder::new(&format!("lattice k = {k} with {p} pendants"));
    for n in &base.nodes {
        b.add_node(&n.name, n.x0, false).expect("new node");
        if n.x0[2] == 0.0 {
            b.fix(&n.name, None).expect("known node");
        }
    }
    for (t, e) in base.elements.iter().enumerate() {
        let [i, j] = truss_nodes(&base, e);
        b.add_element(
            &format!("b{}", t + 1),
            &[&base.nodes[i].name, &base.nodes[j].name],
            ElementSpec::Truss { ea: 0.0 },
            &[],
            &[],
        )
        .expect("valid truss");
    }
    for t in 0..p {
        let name = pendant_node(t);
        b.add_node(&name, [t as f64 + 0.5, -0.5, k as f64 + 0.5], false)
            .expect("new node");
        for (s, i) in [t, t + 1].into_iter().enumerate() {
            b.add_element(
                &format!("pb{t}_{s}"),
                &[&lattice_node(i, 0, k), &name],
                ElementSpec::Truss { ea: 0.0 },
                &[],
                &[],
            )
            .expect("valid truss");
        }
    }
    b.build().expect("valid lattice")
}

/// The 12-truss of the paper (Fig. 2, theory.md §7).
pub fn twelve_truss() -> Model {
    let mut b = ModelBuilder::new("12-truss");
    let pts = [
        ("s1", [1.0, 1.0, 0.0]),
        ("s2", [-1.0, 1.0, 0.0]),
        ("s3", [-1.0, -1.0, 0.0]),
        ("s4", [1.0, -1.0, 0.0]),
        ("t1", [0.0, -1.0, 1.0]),
        ("t2", [1.0, 0.0, 1.0]),
        ("t3", [0.0, 1.0, 1.0]),
        ("t4", [-1.0, 0.0, 1.0]),
    ];
    for (n, p) in pts {
        b.add_node(n, p, false).unwrap();
    }
    let bars = [
        ("s1", "t2"),
        ("s1", "t3"),
        ("s2", "t3"),
        ("s2", "t4"),
        ("s3", "t1"),
        ("s3", "t4"),
        ("s4", "t1"),
        ("s4", "t2"),
        ("t1", "t2"),
        ("t2", "t3"),
        ("t3", "t4"),
        ("t4", "t1"),
    ];
    for (i, (p, q)) in bars.iter().enumerate() {
        b.add_element(
            &format!("{}", i + 1),
            &[p, q],
            ElementSpec::Truss { ea: 0.0 },
            &[],
            &[],
        )
        .unwrap();
    }
    for s in ["s1", "s2", "s3", "s4"] {
        b.fix(s, None).unwrap();
    }
    b.build().unwrap()
}
