//! The example models in `examples/`, checked at the io level: read with `flexmbd_io`, the
//! core's kinematic check, and the `check --json` document of the io writer (formerly run
//! through the built `flexmbd check --json`).
//!
//! For the straight guides (wire flexures, folded sheets) the counts are also checked against an
//! independent computation inside this file: the rank r_L of the Plücker coordinates (w, p × w)
//! of the constraint lines (wire axes, fold lines), by Gaussian elimination here, not by
//! flexmbd. By theory.md §8.1 the moved body then has 6 − r_L motions and k − r_L self-stress
//! states for k lines; all lines are perpendicular to the guide direction x, so the x
//! translation is one of those motions, and the examples take it as generalised coordinate:
//! flexmbd must report 6 − r_L − 1 motions and k − r_L self-stresses.

use serde_json::Value;

mod common;
use common::examples_dir;

/// The `check --json` document of `examples/name`; `extra` holds the command's options
/// (`--auto` only).
fn check_json(name: &str, extra: &[&str]) -> Value {
    assert!(extra.iter().all(|&e| e == "--auto"), "{extra:?}");
    common::check_doc(&examples_dir().join(name), extra.contains(&"--auto"))
}

fn uint(v: &Value, key: &str) -> usize {
    v[key]
        .as_u64()
        .unwrap_or_else(|| panic!("`{key}` missing or not an integer in {v:#}")) as usize
}

/// Table 1 row, Dcc size and the two counts.
fn assert_counts(
    v: &Value,
    name: &str,
    row: usize,
    size: (usize, usize),
    motions: usize,
    stresses: usize,
) {
    let got = (
        uint(v, "table1_row"),
        (uint(v, "rows"), uint(v, "cols")),
        uint(v, "n_mechanisms"),
        uint(v, "n_self_stresses"),
    );
    assert_eq!(
        got,
        (row, size, motions, stresses),
        "{name}: (table1_row, (rows, cols), n_mechanisms, n_self_stresses); singular values {}",
        v["singular_values"]
    );
    let (m, n) = size;
    assert_eq!(uint(v, "rank"), n - motions, "{name}: rank = n − motions");
    assert_eq!(
        uint(v, "rank"),
        m - stresses,
        "{name}: rank = m − self-stresses"
    );
    let exact = motions == 0 && stresses == 0;
    assert_eq!(v["exactly_constrained"], Value::Bool(exact), "{name}");
    assert_eq!(v["kinematically_determinate"], Value::Bool(motions == 0));
    assert_eq!(v["statically_determinate"], Value::Bool(stresses == 0));
    assert_eq!(v["mechanisms"].as_array().unwrap().len(), motions);
    assert_eq!(v["self_stresses"].as_array().unwrap().len(), stresses);
}

/// Entries of a motion as (node, dof) -> value.
fn motion_entries(v: &Value, k: usize) -> Vec<(String, String, f64)> {
    v["mechanisms"][k]["coordinates"]
        .as_array()
        .expect("motion coordinates")
        .iter()
        .map(|c| {
            (
                c["node"].as_str().unwrap().to_string(),
                c["dof"].as_str().unwrap().to_string(),
                c["value"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// Value of (node, dof) in a motion; 0 when not listed (the tool omits zero entries).
fn motion_value(entries: &[(String, String, f64)], node: &str, dof: &str) -> f64 {
    entries
        .iter()
        .find(|e| e.0 == node && e.1 == dof)
        .map_or(0.0, |e| e.2)
}

/// Entries of a self-stress as (element, mode, value).
fn stress_entries(v: &Value, k: usize) -> Vec<(String, u64, f64)> {
    v["self_stresses"][k]["deformations"]
        .as_array()
        .expect("self-stress deformations")
        .iter()
        .map(|d| {
            (
                d["element"].as_str().unwrap().to_string(),
                d["mode"].as_u64().unwrap(),
                d["value"].as_f64().unwrap(),
            )
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Independent line geometry (theory.md §8.1)

type V3 = [f64; 3];

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// A constraint line through `p` along `w`.
#[derive(Clone, Copy, Debug)]
struct Line {
    p: V3,
    w: V3,
}

impl Line {
    /// Plücker coordinates (w, p × w), w normalised. A twist (v, ω), v the velocity of the
    /// point at the origin, respects the line iff (w, p × w) · (v, ω) = 0.
    fn plucker(&self) -> [f64; 6] {
        let n = self.w.iter().map(|a| a * a).sum::<f64>().sqrt();
        let w = self.w.map(|a| a / n);
        let m = cross(self.p, w);
        [w[0], w[1], w[2], m[0], m[1], m[2]]
    }
}

/// Reduced row echelon form with partial pivoting; returns the rank and a basis of the null
/// space (vectors of length `n`).
fn rank_and_null(rows: &[Vec<f64>], n: usize) -> (usize, Vec<Vec<f64>>) {
    let mut a: Vec<Vec<f64>> = rows.to_vec();
    let scale = a
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(1e-300);
    let tol = 1e-9 * scale;
    let mut pivots = Vec::new();
    let mut r = 0;
    for c in 0..n {
        if r == a.len() {
            break;
        }
        let (ip, big) = (r..a.len())
            .map(|i| (i, a[i][c].abs()))
            .fold((r, -1.0), |b, x| if x.1 > b.1 { x } else { b });
        if big <= tol {
            continue;
        }
        a.swap(r, ip);
        let p = a[r][c];
        for x in a[r].iter_mut() {
            *x /= p;
        }
        for i in 0..a.len() {
            if i != r {
                let f = a[i][c];
                if f != 0.0 {
                    for j in 0..n {
                        a[i][j] -= f * a[r][j];
                    }
                }
            }
        }
        pivots.push(c);
        r += 1;
    }
    let null = (0..n)
        .filter(|c| !pivots.contains(c))
        .map(|free| {
            let mut v = vec![0.0; n];
            v[free] = 1.0;
            for (i, &pc) in pivots.iter().enumerate() {
                v[pc] = -a[i][free];
            }
            v
        })
        .collect();
    (r, null)
}

/// Rank of the Plücker coordinates of `lines`.
fn line_rank(lines: &[Line]) -> usize {
    let rows: Vec<Vec<f64>> = lines.iter().map(|l| l.plucker().to_vec()).collect();
    rank_and_null(&rows, 6).0
}

/// The guide checks: every line ⊥ x, and flexmbd's counts (with the platform's x as
/// generalised coordinate) equal 6 − r_L − 1 motions and k − r_L self-stresses.
fn assert_line_counts(v: &Value, name: &str, lines: &[Line], expected_rank: usize) {
    for l in lines {
        assert!(
            l.plucker()[0].abs() < 1e-12,
            "{name}: line {l:?} is not perpendicular to the guide direction x"
        );
    }
    let r_l = line_rank(lines);
    assert_eq!(r_l, expected_rank, "{name}: rank of the constraint lines");
    assert_eq!(
        uint(v, "n_mechanisms"),
        6 - r_l - 1,
        "{name}: motions = 6 − r_L − 1 (x translation taken as generalised coordinate)"
    );
    assert_eq!(
        uint(v, "n_self_stresses"),
        lines.len() - r_l,
        "{name}: self-stresses = k − r_L"
    );
    assert!(
        v["generalised_coordinates"]
            .as_array()
            .unwrap()
            .contains(&Value::from("c.x")),
        "{name}: the platform's x is a generalised coordinate"
    );
}

/// Wire axes of examples/wire_guide_5.toml (base g_i to attachment a_i).
fn wire_lines() -> Vec<Line> {
    let z = [0.0, 0.0, 1.0];
    let y = [0.0, 1.0, 0.0];
    vec![
        Line {
            p: [-0.05, -0.03, 0.0],
            w: z,
        },
        Line {
            p: [-0.05, 0.03, 0.0],
            w: z,
        },
        Line {
            p: [0.05, 0.0, 0.0],
            w: z,
        },
        Line {
            p: [-0.05, 0.03, 0.01],
            w: y,
        },
        Line {
            p: [0.05, 0.03, 0.01],
            w: y,
        },
    ]
}

/// Fold line of a folded sheet of examples/folded_sheet_guide_*.toml: at the end plane
/// x = `x_end`, at angle `theta_deg` around the x axis, through the fold node
/// (x_end, 0.08 cos θ, 0.08 sin θ) along the sheets' common width direction (0, −sin θ, cos θ).
fn fold_line(x_end: f64, theta_deg: f64) -> Line {
    let (s, c) = theta_deg.to_radians().sin_cos();
    Line {
        p: [x_end, 0.08 * c, 0.08 * s],
        w: [0.0, -s, c],
    }
}

/// (end, angle) of the folded sheets 1, 2, ... of each variant, as in the model files.
const FOLDED_5: [(f64, f64); 5] = [
    (-0.1, 90.0),
    (-0.1, 210.0),
    (-0.1, 330.0),
    (0.1, 90.0),
    (0.1, 210.0),
];
const FOLDED_5A: [(f64, f64); 5] = [
    (-0.1, 90.0),
    (-0.1, 210.0),
    (-0.1, 330.0),
    (0.1, 90.0),
    (0.1, 270.0),
];
const FOLDED_6: [(f64, f64); 6] = [
    (-0.1, 90.0),
    (-0.1, 210.0),
    (-0.1, 330.0),
    (0.1, 90.0),
    (0.1, 210.0),
    (0.1, 330.0),
];

fn fold_lines(set: &[(f64, f64)]) -> Vec<Line> {
    set.iter().map(|&(x, t)| fold_line(x, t)).collect()
}

/// Every sheet beam s{i}a, s{i}b (i = 1..k) carries the self-stress in in-plane bending
/// (modes 5/6) and none in elongation.
fn assert_sheets_in_plane_bending(v: &Value, name: &str, k: usize) {
    let st = stress_entries(v, 0);
    for i in 1..=k {
        for leg in ["a", "b"] {
            let el = format!("s{i}{leg}");
            let bending = st
                .iter()
                .filter(|e| e.0 == el && (e.1 == 5 || e.1 == 6))
                .fold(0.0f64, |m, e| m.max(e.2.abs()));
            assert!(
                bending > 1e-3,
                "{name}: sheet {el} has no in-plane bending in the self-stress: {st:?}"
            );
            for e in st.iter().filter(|e| e.0 == el && e.1 == 1) {
                assert!(e.2.abs() < 1e-8, "{name}: {el} elongation {}", e.2);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The examples

#[test]
fn twelve_truss_matches_the_paper() {
    let v = check_json("twelve_truss.toml", &[]);
    assert_counts(&v, "twelve_truss", 2, (12, 12), 1, 1);
    // self-stress: all twelve bars ±√3/6
    let st = stress_entries(&v, 0);
    assert_eq!(st.len(), 12, "{st:?}");
    let s = 3f64.sqrt() / 6.0;
    for e in &st {
        assert!((e.2.abs() - s).abs() < 1e-9, "bar {} carries {}", e.0, e.2);
    }
    assert_eq!(st.iter().filter(|e| e.2 > 0.0).count(), 6);
    // releasing a bar's elongation (its one deformation) leaves it constraining nothing: for a
    // designer, leave the bar out
    for sg in v["suggestions"][0]["suggestions"].as_array().unwrap() {
        assert_eq!(
            (&sg["action"], &sg["mode"]),
            (&Value::from("release"), &Value::from(1))
        );
        assert_eq!(sg["designer"]["kind"], "remove", "{sg}");
    }
    // motion: paper eq. (16), up to the overall sign
    let m = motion_entries(&v, 0);
    let eq16 = [
        ("t1", [0.0, -0.5, 0.0]),
        ("t2", [-0.5, 0.0, 0.0]),
        ("t3", [0.0, 0.5, 0.0]),
        ("t4", [0.5, 0.0, 0.0]),
    ];
    // eq. (16) has t2.x = −0.5; the SVD may return the opposite overall sign
    let sign = -motion_value(&m, "t2", "x").signum();
    for (node, vel) in eq16 {
        for (k, dof) in ["x", "y", "z"].into_iter().enumerate() {
            let got = motion_value(&m, node, dof);
            assert!(
                (got - sign * vel[k]).abs() < 1e-9,
                "{node}.{dof}: {got}, eq. (16) gives {}",
                sign * vel[k]
            );
        }
    }
    assert_eq!(m.len(), 4, "only the four in-plane components move: {m:?}");
}

#[test]
fn wire_guide_is_exactly_constrained() {
    let v = check_json("wire_guide_5.toml", &[]);
    assert_counts(&v, "wire_guide_5", 1, (35, 35), 0, 0);
    assert_line_counts(&v, "wire_guide_5", &wire_lines(), 5);
    // released, the one motion is the translation x (every wire line is perpendicular to
    // x), the file's intended freedom
    assert_freedom_matches(&v, 1);
}

/// The file's `[[freedom]]` equals the design's freedom space of dimension `dim`.
fn assert_freedom_matches(v: &Value, dim: usize) {
    let f = &v["freedom"];
    assert_eq!(f["matches"], Value::Bool(true), "{f:#}");
    assert_eq!(uint(f, "design_dimension"), dim, "{f:#}");
    assert_eq!(uint(f, "intended_dimension"), dim, "{f:#}");
}

#[test]
fn folded_sheet_guide_is_exactly_constrained() {
    let v = check_json("folded_sheet_guide_5.toml", &[]);
    assert_counts(&v, "folded_sheet_guide_5", 1, (65, 65), 0, 0);
    assert_line_counts(&v, "folded_sheet_guide_5", &fold_lines(&FOLDED_5), 5);
    // one generalised bending mode per folded sheet, plus the platform's x
    assert_eq!(uint(&v, "input_deformations"), 5);
    assert_eq!(v["generalised_coordinates"].as_array().unwrap().len(), 6);
}

#[test]
fn folded_sheet_guide_5a_is_under_and_over_constrained() {
    let name = "folded_sheet_guide_5a";
    let v = check_json("folded_sheet_guide_5a.toml", &[]);
    assert_counts(&v, name, 2, (65, 65), 1, 1);
    let lines = fold_lines(&FOLDED_5A);
    // the two lower flexures (4, 5) have parallel constraint directions ...
    let (w4, w5) = (lines[3].plucker(), lines[4].plucker());
    let c = cross([w4[0], w4[1], w4[2]], [w5[0], w5[1], w5[2]]);
    assert!(c.iter().all(|a| a.abs() < 1e-12), "parallel: {w4:?} {w5:?}");
    // ... and the five lines are dependent
    assert_line_counts(&v, name, &lines, 4);

    // The motion: the twist (v, ω) of the platform (about its node c at the origin) reciprocal
    // to all five lines with v_x = 0 (c.x is generalised), compared with flexmbd's motion at c.
    let mut rows: Vec<Vec<f64>> = lines.iter().map(|l| l.plucker().to_vec()).collect();
    rows.push(vec![1.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (r, null) = rank_and_null(&rows, 6);
    assert_eq!((r, null.len()), (5, 1));
    let expect = &null[0];
    let m = motion_entries(&v, 0);
    let got: Vec<f64> = ["x", "y", "z", "rx", "ry", "rz"]
        .iter()
        .map(|d| motion_value(&m, "c", d))
        .collect();
    let unit = |a: &[f64]| {
        let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
        a.iter().map(|x| x / n).collect::<Vec<_>>()
    };
    let (e, g) = (unit(expect), unit(&got));
    let dotp: f64 = e.iter().zip(&g).map(|(a, b)| a * b).sum();
    assert!(
        (dotp.abs() - 1.0).abs() < 1e-9,
        "platform twist {g:?} vs line geometry {e:?}"
    );
    // it is a rotation about the y axis through (−0.1, 0, 0): v_z(c) = −0.1 ω_y
    assert!(
        (e[2] + 0.1 * e[4]).abs() < 1e-12 && e[4].abs() > 0.5,
        "{e:?}"
    );
    // In the designer's language: the platform's twist is that rotation, axis along y through
    // (−0.1, ·, 0), pitch 0.
    let t = &v["screws"]["motions"][0]["bodies"];
    let t = t
        .as_array()
        .unwrap()
        .iter()
        .find(|t| t["body"] == "platform")
        .expect("the platform moves");
    let sc = &t["screw"];
    assert_eq!(sc["kind"], "rotation");
    let num = |x: &Value| x.as_f64().unwrap();
    let (pt, dir) = (&sc["point"], &sc["direction"]);
    assert!((num(&dir[1]).abs() - 1.0).abs() < 1e-9, "{sc}");
    assert!(
        (num(&pt[0]) + 0.1).abs() < 1e-9 && num(&pt[2]).abs() < 1e-9,
        "{sc}"
    );
    assert!(num(&sc["pitch"]).abs() < 1e-9, "{sc}");

    // The self-stress: the dependency Σ cᵢ ℓᵢ = 0 of the five lines (the null vector of the
    // 6 × 5 matrix of their Plücker coordinates); sheet i pushes on the platform with the
    // wrench cᵢ ℓᵢ up to one common factor: a pure force (pitch 0) on its own line.
    let cols: Vec<Vec<f64>> = (0..6)
        .map(|k| lines.iter().map(|l| l.plucker()[k]).collect())
        .collect();
    let (r, dep) = rank_and_null(&cols, 5);
    assert_eq!((r, dep.len()), (4, 1));
    let c = &dep[0];
    let wrenches = v["screws"]["self_stresses"][0]["wrenches"]
        .as_array()
        .unwrap();
    let mut factor: Option<f64> = None;
    for (i, line) in lines.iter().enumerate() {
        let by = format!("s{}b", i + 1);
        let w = wrenches
            .iter()
            .find(|w| w["body"] == "platform" && w["by"] == by)
            .unwrap_or_else(|| panic!("the wrench of {by} on the platform"));
        assert_eq!(w["screw"]["kind"], "force", "{by}");
        assert!(num(&w["screw"]["pitch"]).abs() < 1e-9, "{by}");
        // (F, M about the origin) = (F, p × F + M_p)
        let f: V3 = std::array::from_fn(|k| num(&w["force"][k]));
        let p: V3 = std::array::from_fn(|k| num(&w["screw"]["point"][k]));
        let m: V3 = std::array::from_fn(|k| num(&w["moment"][k]));
        let pf = cross(p, f);
        let got = [f[0], f[1], f[2], pf[0] + m[0], pf[1] + m[1], pf[2] + m[2]];
        let want: Vec<f64> = line.plucker().iter().map(|a| c[i] * a).collect();
        let k = *factor.get_or_insert_with(|| {
            let (g, h) = (got[1], want[1]);
            assert!(h.abs() > 1e-6, "{by}: line {want:?}");
            g / h
        });
        for j in 0..6 {
            assert!(
                (got[j] - k * want[j]).abs() < 1e-9 * (1.0 + k.abs()),
                "{by}: wrench {got:?} vs {k} × {want:?}"
            );
        }
    }

    assert_sheets_in_plane_bending(&v, name, 5);
}

/// Every release of a beam's bending in `v`'s advice is, for the designer, a hinge at that end
/// (p for modes 3, 5; q for 4, 6) about the bending axis of the beam's reference frame: local
/// z = chord × orient (modes 5, 6) or local y = orient made normal to the chord (modes 3, 4),
/// from the model file's nodes and `orient`. Returns how many were checked.
fn assert_bending_releases_are_hinges(v: &Value, file: &str) -> usize {
    let text = std::fs::read_to_string(examples_dir().join(file)).unwrap();
    let spec = flexmbd_io::parse_spec(&text, file).unwrap();
    let node = |n: &str| -> V3 {
        let c = ["x", "y", "z"];
        std::array::from_fn(|k| {
            spec.get(&format!("nodes.{n}.{}", c[k]))
                .unwrap()
                .as_f64()
                .unwrap()
        })
    };
    let unit = |a: V3| {
        let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|x| x / n)
    };
    let mut checked = 0;
    for st in v["suggestions"].as_array().unwrap() {
        for sg in st["suggestions"].as_array().unwrap() {
            let mode = sg["mode"].as_u64().unwrap_or(0);
            if sg["action"] != "release" || !(3..=6).contains(&mode) {
                continue;
            }
            let el = sg["element"].as_str().unwrap();
            let e = spec.get(&format!("elements.{el}")).unwrap();
            if e["type"] != "beam" {
                continue;
            }
            let ends: Vec<&str> = e["nodes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|n| n.as_str().unwrap())
                .collect();
            let (p, q) = (node(ends[0]), node(ends[1]));
            let ex = unit([q[0] - p[0], q[1] - p[1], q[2] - p[2]]);
            let o: V3 = std::array::from_fn(|k| e["orient"][k].as_f64().unwrap());
            let ez = unit(cross(ex, o));
            let ey = cross(ez, ex);
            let axis = if mode >= 5 { ez } else { ey };
            let d = &sg["designer"];
            assert_eq!(d["kind"], "hinge", "{sg}");
            assert_eq!(d["node"], ends[if mode % 2 == 1 { 0 } else { 1 }], "{sg}");
            let got: V3 = std::array::from_fn(|k| d["axis"][k].as_f64().unwrap());
            let c = cross(got, axis);
            assert!(c.iter().all(|a| a.abs() < 1e-9), "{sg}: axis {axis:?}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn six_folded_sheets_are_over_constrained_in_in_plane_bending() {
    let name = "folded_sheet_guide_6";
    let v = check_json("folded_sheet_guide_6.toml", &[]);
    assert_counts(&v, name, 3, (78, 77), 0, 1);
    assert_line_counts(&v, name, &fold_lines(&FOLDED_6), 5);
    assert_sheets_in_plane_bending(&v, name, 6);
    // the repair for a designer: a hinge about the sheet's normal at the released end
    assert!(assert_bending_releases_are_hinges(&v, "folded_sheet_guide_6.toml") >= 5);
    // the rigid cylinder is loaded too (paper: release a torsion of the rigid body)
    assert!(stress_entries(&v, 0).iter().any(|e| e.0 == "platform"));
}

#[test]
fn parallel_leaf_guide_k03() {
    let v = check_json("parallel_leaf_guide.toml", &[]);
    assert_counts(&v, "parallel_leaf_guide", 2, (12, 12), 1, 1);
    assert_freedom_matches(&v, 1);
    // the motion: both top nodes translate along x (the leaves' thickness normal), nothing else
    let m = motion_entries(&v, 0);
    let s = 0.5f64.sqrt();
    assert_eq!(m.len(), 2, "{m:?}");
    assert!((motion_value(&m, "t1", "x") - s).abs() < 1e-9, "{m:?}");
    assert!((motion_value(&m, "t2", "x") - s).abs() < 1e-9, "{m:?}");
    // the self-stress: in-plane bending of both leaves
    let st = stress_entries(&v, 0);
    for leaf in ["leaf1", "leaf2"] {
        assert!(
            st.iter()
                .any(|e| e.0 == leaf && (e.1 == 5 || e.1 == 6) && e.2.abs() > 0.1),
            "{st:?}"
        );
    }

    // --auto picks one generalised coordinate: no motion left, the self-stress stays
    let a = check_json("parallel_leaf_guide.toml", &["--auto"]);
    assert_counts(&a, "parallel_leaf_guide --auto", 3, (12, 11), 0, 1);
    assert_eq!(a["generalised_coordinates"].as_array().unwrap().len(), 1);
    assert_eq!(a["auto"]["chosen"].as_array().unwrap().len(), 1);
    assert_eq!(uint(&a["auto"]["before"], "n_mechanisms"), 1);
    assert_eq!(uint(&a["auto"]["before"], "n_self_stresses"), 1);
}

#[test]
fn cross_spring_pivot_k04() {
    let v = check_json("cross_spring_pivot.toml", &[]);
    assert_counts(&v, "cross_spring_pivot", 2, (12, 12), 1, 1);
    assert_freedom_matches(&v, 1);
    // the motion: rotation about the y axis: ω = (0, ω_y, 0) at both nodes, v = ω × r
    let m = motion_entries(&v, 0);
    let wy = motion_value(&m, "t1", "ry");
    assert!(wy.abs() > 0.5, "{m:?}");
    for (node, r) in [("t1", [0.03, 0.0, 0.03]), ("t2", [-0.03, 0.0, 0.03])] {
        let vel = cross([0.0, wy, 0.0], r);
        for (k, dof) in ["x", "y", "z"].into_iter().enumerate() {
            assert!((motion_value(&m, node, dof) - vel[k]).abs() < 1e-9, "{m:?}");
        }
        assert!((motion_value(&m, node, "ry") - wy).abs() < 1e-9, "{m:?}");
        assert!(motion_value(&m, node, "rx").abs() < 1e-9);
        assert!(motion_value(&m, node, "rz").abs() < 1e-9);
    }
}

#[test]
fn spatial_four_bar_moves_and_has_three_self_stresses() {
    let v = check_json("four_bar_hinges.toml", &[]);
    // Grübler in space: 6·3 − 5·4 = −2 = n − m = motions − self-stresses
    assert_counts(&v, "four_bar_hinges", 4, (26, 24), 1, 3);
    // the motion stays in the plane: no z translation, no rotation about x or y
    let m = motion_entries(&v, 0);
    assert!(
        m.iter().all(|e| !["z", "rx", "ry"].contains(&e.1.as_str())),
        "{m:?}"
    );
    // crank rotates about g1: j1 moves along x with v = ω × (0, 0.1, 0)
    let w = motion_value(&m, "c1", "rz");
    assert!(w.abs() > 0.1, "{m:?}");
    assert!(
        (motion_value(&m, "j1", "x") + 0.1 * w).abs() < 1e-9,
        "{m:?}"
    );
    assert!((motion_value(&m, "j1", "rz") - w).abs() < 1e-9, "{m:?}");
}
