//! Tests of the kinematic analysis against independent references.

use super::advice::{self, advise, auto_generalised, Action};
use super::*;
use crate::elements::testing::Rng;
use crate::model::{ElementSpec, ModelBuilder};

const FREE_WIRE: [i64; 5] = [2, 3, 4, 5, 6];

fn run(m: &Model) -> ConstraintAnalysis {
    check(m, &m.partition, &m.x0(), &CheckOptions::default()).unwrap()
}

#[test]
fn twelve_truss_advice_releases_any_bar_and_fixes_a_top_coordinate() {
    let m = test_models::twelve_truss();
    let a = run(&m);
    let adv = advise(&m, &m.partition, &m.x0(), &a, &CheckOptions::default(), 20).unwrap();
    // paper §3.3: releasing the elongation of any one truss removes the over-constraint
    let ss = &adv[0];
    assert_eq!(ss.kind, "self_stress");
    assert_eq!(ss.suggestions.len(), 12);
    for s in &ss.suggestions {
        // releasing a bar also removes the motion? No: m − r drops, n − r stays (theory §6.3)
        assert_eq!((s.motions_after, s.self_stresses_after), (1, 0));
    }
    let mo = &adv[1];
    assert_eq!(mo.kind, "motion");
    // the four top-node coordinates that move in eq. (16)
    assert_eq!(mo.suggestions.len(), 4, "{:?}", mo.suggestions);
    let auto = auto_generalised(&m, &m.partition, &m.x0(), &CheckOptions::default()).unwrap();
    assert_eq!(auto.chosen.len(), 1);
    assert_eq!(auto.analysis.n_motions(), 0);
    assert!(matches!(
        auto.chosen[0],
        Action::FixOrInputCoordinate { .. }
    ));
}

/// Rank of a k × 6 matrix by SVD (independent of the flexmbd code path).
fn rank6(lines: &[[f64; 6]]) -> usize {
    if lines.is_empty() {
        return 0;
    }
    let a = Mat::from_fn(lines.len(), 6, |i, j| lines[i][j]);
    let s = a.singular_values().unwrap();
    s.iter().filter(|&&v| v > 1e-9 * s[0]).count()
}

#[test]
fn random_wire_flexure_guides_match_line_geometry() {
    // theory.md §8.1: k wires (beams with only the elongation fixed) on one rigid body leave
    // 6 − r_L motions and k − r_L self-stresses, r_L the rank of the wires' Plücker coordinates.
    let mut rng = Rng(42);
    for trial in 0..40 {
        let k = 1 + trial % 8;
        let mut b = ModelBuilder::new("wires");
        b.add_node("body", [0.0; 3], false).unwrap();
        let mut body_nodes = vec!["body".to_string()];
        let mut lines = Vec::new();
        for w in 0..k {
            // attachment point on the body and a wire direction; some trials reuse lines
            let (p, dir) = if trial % 5 == 4 && w > 0 && w % 2 == 1 {
                // a wire along the same line as the previous one: dependent
                let prev: &[f64; 6] = &lines[w - 1];
                let d = [prev[0], prev[1], prev[2]];
                let p0 = crate::math::cross(d, [prev[3], prev[4], prev[5]]);
                // point on the line nearest the origin, shifted along it
                (
                    crate::math::add(p0, [0.3 * d[0], 0.3 * d[1], 0.3 * d[2]]),
                    d,
                )
            } else {
                ([rng.next(), rng.next(), rng.next()], rng.unit())
            };
            let a = format!("a{w}");
            let g = format!("g{w}");
            let base = [
                p[0] - 0.5 * dir[0],
                p[1] - 0.5 * dir[1],
                p[2] - 0.5 * dir[2],
            ];
            b.add_node(&a, p, false).unwrap();
            b.add_node(&g, base, false).unwrap();
            b.add_element(
                &format!("w{w}"),
                &[&g, &a],
                ElementSpec::Beam {
                    orient: None,
                    ct: 0.0,
                },
                &FREE_WIRE,
                &[],
            )
            .unwrap();
            b.fix(&g, None).unwrap();
            body_nodes.push(a);
            let m = crate::math::cross(p, dir);
            lines.push([dir[0], dir[1], dir[2], m[0], m[1], m[2]]);
        }
        let refs: Vec<&str> = body_nodes.iter().map(|s| s.as_str()).collect();
        b.add_element("body", &refs, ElementSpec::Rigid, &[], &[])
            .unwrap();
        let m = b.build().unwrap();
        let a = run(&m);
        let rl = rank6(&lines);
        assert_eq!(a.n_motions(), 6 - rl, "trial {trial}: k = {k}, r_L = {rl}");
        assert_eq!(
            a.n_self_stresses(),
            k - rl,
            "trial {trial}: k = {k}, r_L = {rl}"
        );
    }
}

#[test]
fn counts_equal_spacar_euler_form() {
    // theory.md §2.4: the SVD of SPACAR's Euler-parameter Dcc (normalisation rows, λ columns)
    // gives the same n − r and m − r as the velocity form. Built here directly from D.
    let mut rng = Rng(7);
    for trial in 0..10 {
        let k = 3 + trial % 6;
        let mut b = ModelBuilder::new("mix");
        b.add_node("body", [0.0; 3], false).unwrap();
        let mut nodes = vec!["body".to_string()];
        for w in 0..k {
            let p = [rng.next(), rng.next(), rng.next()];
            let d = rng.unit();
            b.add_node(&format!("a{w}"), p, false).unwrap();
            b.add_node(
                &format!("g{w}"),
                [p[0] - d[0], p[1] - d[1], p[2] - d[2]],
                false,
            )
            .unwrap();
            let free: &[i64] = if w % 3 == 0 { &[2, 3, 4] } else { &FREE_WIRE };
            b.add_element(
                &format!("w{w}"),
                &[&format!("g{w}"), &format!("a{w}")],
                ElementSpec::Beam {
                    orient: None,
                    ct: 0.0,
                },
                free,
                &[],
            )
            .unwrap();
            b.fix(&format!("g{w}"), None).unwrap();
            nodes.push(format!("a{w}"));
        }
        let refs: Vec<&str> = nodes.iter().map(|s| s.as_str()).collect();
        b.add_element("body", &refs, ElementSpec::Rigid, &[], &[])
            .unwrap();
        b.input("body", Some(&[Dof::Rz])).unwrap();
        let m = b.build().unwrap();
        let x = m.x0();
        let a = run(&m);
        // Euler form
        let ev = crate::assembly::evaluate(&m, &x);
        let p = &m.partition;
        let cols: Vec<usize> = (0..m.nx).filter(|&i| p.x[i] == CoordKind::Free).collect();
        let mut rows: Vec<Vec<f64>> = (0..m.ne)
            .filter(|&i| p.e[i] != DefKind::Free)
            .map(|i| cols.iter().map(|&j| ev.D[(i, j)]).collect())
            .collect();
        for n in m.nodes.iter().filter(|n| n.rot()) {
            let ir = n.ix_rot.unwrap();
            rows.push(
                cols.iter()
                    .map(|&j| {
                        if (ir..ir + 4).contains(&j) {
                            2.0 * x[j]
                        } else {
                            0.0
                        }
                    })
                    .collect(),
            );
        }
        assert_eq!((rows.len(), cols.len()), a.euler_shape);
        let d = Mat::from_fn(rows.len(), cols.len(), |i, j| rows[i][j]);
        let s = d.singular_values().unwrap();
        let r = s
            .iter()
            .filter(|&&v| v > f64::EPSILON.sqrt() * s[0])
            .count();
        assert_eq!(cols.len() - r, a.n_motions(), "trial {trial}");
        assert_eq!(rows.len() - r, a.n_self_stresses(), "trial {trial}");
    }
}

#[test]
fn table1_covers_all_six_cases() {
    assert_eq!(Table1::classify(3, 3, 3).row(), 1);
    assert_eq!(Table1::classify(3, 3, 2).row(), 2);
    assert_eq!(Table1::classify(4, 3, 3).row(), 3);
    assert_eq!(Table1::classify(4, 3, 2).row(), 4);
    assert_eq!(Table1::classify(3, 4, 3).row(), 5);
    assert_eq!(Table1::classify(3, 4, 2).row(), 6);
}

/// Dcc of a truss lattice assembled by the test itself: a row per bar, +d on the far node's and
/// −d on the near node's free translations (d the unit bar direction: the elongation rate of a
/// bar in its reference configuration), columns the free nodes' x, y, z in node order.
fn lattice_dcc_by_hand(k: usize) -> Mat<f64> {
    let m = test_models::lattice(k);
    let free: Vec<usize> = (0..m.nodes.len())
        .filter(|&i| m.nodes[i].x0[2] > 0.0)
        .collect();
    let col_of = |node: usize| free.iter().position(|&f| f == node).map(|p| 3 * p);
    let mut dcc = Mat::<f64>::zeros(m.elements.len(), 3 * free.len());
    for (r, entry) in m.elements.iter().enumerate() {
        let [p, q] = test_models::truss_nodes(&m, entry);
        let (xp, xq) = (m.nodes[p].x0, m.nodes[q].x0);
        let l = crate::math::norm(crate::math::sub(xq, xp));
        for c in 0..3 {
            let d = (xq[c] - xp[c]) / l;
            if let Some(j) = col_of(q) {
                dcc[(r, j + c)] += d;
            }
            if let Some(j) = col_of(p) {
                dcc[(r, j + c)] -= d;
            }
        }
    }
    dcc
}

#[test]
fn lattice_counts_match_maxwell_and_an_independent_rank() {
    // Maxwell's rule corrected by the rank: motions − self-stresses = n − m for any r, and
    // n − r with r from faer's own SVD of a Dcc the test assembles by hand.
    for k in 1..=3 {
        let m = test_models::lattice(k);
        let a = run(&m);
        let free_nodes = k * (k + 1) * (k + 1);
        let bars = 3 * k * (k + 1) * (k + 1) + 3 * k * k * (k + 1) - 2 * k * (k + 1) - k * k;
        assert_eq!((a.m(), a.n()), (bars, 3 * free_nodes), "k = {k}");
        assert_eq!(
            a.n_motions() as i64 - a.n_self_stresses() as i64,
            a.n() as i64 - a.m() as i64,
            "Maxwell, k = {k}"
        );
        let d = lattice_dcc_by_hand(k);
        let s = d.singular_values().unwrap();
        let r = s
            .iter()
            .filter(|&&v| v > f64::EPSILON.sqrt() * s[0])
            .count();
        assert_eq!(a.rank, r, "k = {k}");
        assert_eq!(a.n_motions(), d.ncols() - r, "k = {k}");
        assert_eq!(a.n_self_stresses(), d.nrows() - r, "k = {k}");
    }
}

/// Every action the advice can take on a model (release or make dependent every row, fix every
/// column's coordinate, fix every free deformation), with its change of Dcc.
fn every_action(m: &Model, x: &[f64], a: &ConstraintAnalysis) -> Vec<(Action, update::Change)> {
    use update::Change;
    let names = m.node_names();
    let mut out = Vec::new();
    for (i, r) in a.rows.iter().enumerate() {
        let action = Action::remove_row(m, &names, r);
        out.push((action, Change::RemoveRow(i)));
    }
    for (j, c) in a.cols.iter().enumerate() {
        let row = coordinate_constraint(m, &a.cols, x, j);
        let change = if row.len() == 1 && row[0].0 == j {
            Change::RemoveColumn(j)
        } else {
            Change::AddRow(row)
        };
        let action = Action::FixOrInputCoordinate {
            node: names[c.node].clone(),
            dof: c.dof,
        };
        out.push((action, change));
    }
    let free: Vec<usize> = (0..m.ne)
        .filter(|&i| m.partition.e[i] == DefKind::Free)
        .collect();
    for (f, row) in rate_rows(m, x, &a.cols, &free).into_iter().enumerate() {
        let (el, mode) = m.deformation_owner(free[f]);
        let entry = &m.elements[el];
        let action = Action::FixOrInputDeformation {
            element: entry.name.clone(),
            mode: mode + 1,
            mode_name: entry.element.mode_name(mode, &names),
        };
        out.push((action, Change::AddRow(row)));
    }
    out
}

/// Predicted (when certain) and rank-updated counts of every action equal a full re-analysis.
fn assert_predictions(m: &Model, x: &[f64], what: &str) -> (usize, usize) {
    let opts = CheckOptions::default();
    let a = check(m, &m.partition, x, &opts).unwrap();
    let upd = update::Updater::new(&a, opts.rank_tol).unwrap();
    let (mut certain, mut total) = (0, 0);
    for (action, change) in every_action(m, x, &a) {
        let p = action.apply(m, &m.partition).unwrap();
        let full = advice::counts(m, &p, x, &opts).unwrap();
        assert_eq!(
            upd.counts_after(&change),
            full,
            "{what}: rank update of {}",
            action.describe()
        );
        if let update::Prediction::Certain(c) = upd.predict(&change) {
            assert_eq!(c, full, "{what}: prediction of {}", action.describe());
            certain += 1;
        }
        total += 1;
    }
    (certain, total)
}

#[test]
fn predicted_counts_of_every_action_match_a_full_reanalysis() {
    let mut tally = Vec::new();
    let m = test_models::twelve_truss();
    tally.push(assert_predictions(&m, &m.x0(), "12-truss"));
    for k in 1..=2 {
        let m = test_models::lattice(k);
        tally.push(assert_predictions(&m, &m.x0(), &format!("lattice {k}")));
    }
    // strips: rigid (exact), with free bending (motions), over-constrained by tip inputs
    let m = test_models::strip(4, &[], &[]);
    tally.push(assert_predictions(&m, &m.x0(), "rigid strip"));
    let m = test_models::strip(3, &[5, 6], &[Dof::Y]);
    tally.push(assert_predictions(&m, &m.x0(), "bending strip"));
    let m = test_models::strip(2, &[], &[Dof::Z, Dof::Rx]);
    tally.push(assert_predictions(&m, &m.x0(), "over-constrained strip"));
    // turned nodes: fixing a rotation coordinate is then a constraint across the columns
    let m = test_models::strip(3, &[2, 3, 4, 5, 6], &[Dof::Ry]);
    let mut x = m.x0();
    let mut rng = Rng(11);
    for n in &m.nodes {
        if let Some(ir) = n.ix_rot {
            let q = crate::math::euler_from_axis_angle(rng.unit(), 0.7 * rng.next() + 0.2);
            x[ir..ir + 4].copy_from_slice(&q);
        }
    }
    tally.push(assert_predictions(&m, &x, "turned strip"));
    // the predictions decide most candidates without verification
    let (c, t): (usize, usize) = tally.iter().fold((0, 0), |s, v| (s.0 + v.0, s.1 + v.1));
    assert!(2 * c > t, "certain predictions {c} of {t}: {tally:?}");
}

#[test]
fn advice_on_a_lattice_is_verified_and_each_state_removed() {
    // every suggestion's counts are those of a full re-analysis of its changed partition
    let m = test_models::lattice(2);
    let x = m.x0();
    let opts = CheckOptions::default();
    let a = run(&m);
    assert!(a.n_self_stresses() > 0);
    let adv = advise(&m, &m.partition, &x, &a, &opts, 3).unwrap();
    assert_eq!(adv.len(), a.n_self_stresses() + a.n_motions());
    for st in &adv {
        assert!(!st.suggestions.is_empty(), "{} {}", st.kind, st.state);
        for sg in &st.suggestions {
            let p = sg.action.apply(&m, &m.partition).unwrap();
            assert_eq!(
                advice::counts(&m, &p, &x, &opts).unwrap(),
                (sg.motions_after, sg.self_stresses_after)
            );
        }
    }
}

#[test]
fn dense_size_guard_stops_before_allocating() {
    // 200,000 rigid beams: a 1.2e6 x 1.2e6 Dcc would need terabytes
    let m = test_models::strip(200_000, &[], &[]);
    let opts = CheckOptions {
        method: CheckMethod::Dense,
        ..Default::default()
    };
    let e = check(&m, &m.partition, &m.x0(), &opts).unwrap_err();
    let KinematicsError::TooLarge {
        rows, cols, bytes, ..
    } = e
    else {
        panic!("{e:?}");
    };
    assert_eq!((rows, cols), (1_200_000, 1_200_000));
    assert!(bytes > 10_000_000_000_000, "{bytes}");
    let text = e.to_string();
    assert!(
        text.contains("limit of 4.0 GiB") && text.contains("sparse"),
        "{text}"
    );
    assert!(!text.contains("--"), "core names no flag: {text}");
    // a lower limit stops a small model too
    let m = test_models::lattice(2);
    let small = CheckOptions {
        max_dense_bytes: 1000,
        method: CheckMethod::Dense,
        ..Default::default()
    };
    assert!(matches!(
        check(&m, &m.partition, &m.x0(), &small),
        Err(KinematicsError::TooLarge { .. })
    ));
}
