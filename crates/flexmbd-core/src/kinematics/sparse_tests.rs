//! Tests of the sparse path against the dense SVD and against closed-form counts.

use super::sparse::AddedRowBound;
use super::test_models::{lattice, lattice_with_pendants, pendant_node, strip};
use super::*;

fn opts(method: CheckMethod) -> CheckOptions {
    CheckOptions {
        method,
        max_listed_states: usize::MAX,
        ..Default::default()
    }
}

fn both(m: &Model) -> (ConstraintAnalysis, ConstraintAnalysis) {
    let x = m.x0();
    let d = check(m, &m.partition, &x, &opts(CheckMethod::Dense)).unwrap();
    let s = check(m, &m.partition, &x, &opts(CheckMethod::Sparse)).unwrap();
    assert!(d.sparse.is_none() && s.sparse.is_some());
    (d, s)
}

/// An orthonormal basis of the columns of `a` (modified Gram–Schmidt, twice).
fn orthonormal(a: &Mat<f64>) -> Mat<f64> {
    let mut q = a.clone();
    for j in 0..q.ncols() {
        for _ in 0..2 {
            for p in 0..j {
                let c: f64 = (0..q.nrows()).map(|i| q[(i, p)] * q[(i, j)]).sum();
                for i in 0..q.nrows() {
                    q[(i, j)] -= c * q[(i, p)];
                }
            }
        }
        let nj = (0..q.nrows())
            .map(|i| q[(i, j)].powi(2))
            .sum::<f64>()
            .sqrt();
        assert!(nj > 1e-6, "the basis is (nearly) dependent");
        for i in 0..q.nrows() {
            q[(i, j)] /= nj;
        }
    }
    q
}

/// The sine of the largest principal angle between the column spaces of `a` and `b` (of the
/// same dimension), bounded by ‖(I − Q_b Q_bᵀ) Q_a‖_F.
fn subspace_sine(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
    assert_eq!(a.ncols(), b.ncols());
    let (qa, qb) = (orthonormal(a), orthonormal(b));
    let p = qb.transpose() * &qa;
    let r = &qa - &qb * &p;
    r.norm_l2()
}

#[test]
fn sparse_and_dense_paths_agree_on_counts_and_null_spaces() {
    let models = [
        super::test_models::twelve_truss(),
        lattice(2),
        lattice(3),
        lattice_with_pendants(3, 3),
        // rigid beams with torsion and one bending free: motions; the tip's x and y taken as
        // generalised too: self-stresses as well
        strip(12, &[4, 5], &[]),
        strip(8, &[4], &[Dof::X, Dof::Y]),
        strip(6, &[], &[Dof::Z]),
    ];
    for m in &models {
        let (d, s) = both(m);
        let name = &m.name;
        assert_eq!((s.rank, s.m(), s.n()), (d.rank, d.m(), d.n()), "{name}");
        assert_eq!(s.case, d.case, "{name}");
        let sp = s.sparse.as_ref().unwrap();
        assert!(sp.certain, "{name}: {sp:?}");
        // the decision: the bounds on the two sides of the dense singular values
        let r = d.rank;
        if r > 0 {
            let lo = sp.s_r_lower.unwrap();
            assert!(lo <= d.singular_values[r - 1] * (1.0 + 1e-6), "{name}");
        }
        if let Some(up) = sp.s_r1_upper {
            assert!(
                d.singular_values[r] <= up + 1e-14 * d.singular_values[0],
                "{name}"
            );
        }
        assert!((sp.s1 - d.singular_values[0]).abs() <= 1e-6 * d.singular_values[0]);
        // the same null spaces
        assert_eq!(s.null_v.ncols(), d.null_v.ncols(), "{name}");
        assert_eq!(s.null_u.ncols(), d.null_u.ncols(), "{name}");
        if d.null_v.ncols() > 0 {
            let sin = subspace_sine(&s.null_v, &d.null_v);
            assert!(sin < 1e-10, "{name}: motions, sin = {sin:e}");
        }
        if d.null_u.ncols() > 0 {
            let sin = subspace_sine(&s.null_u, &d.null_u);
            assert!(sin < 1e-10, "{name}: self-stresses, sin = {sin:e}");
        }
    }
}

/// The closed-form count of the lattice of `test_models::lattice(k)`.
///
/// Columns: the k (k + 1)² nodes above the supported layer, three velocities each,
/// n = 3 k (k + 1)². Rows: per node (i, j, l) the bars to (i+1, j, l), (i, j+1, l),
/// (i, j, l+1), (i+1, j+1, l), (i+1, j, l+1), (i, j+1, l+1) where they exist, less the
/// 2 k (k + 1) edges and k² diagonals of the supported layer: m = 3 k (k + 1)² + 3 k² (k + 1)
/// − 2 k (k + 1) − k².
///
/// No motion (r = n): take the nodes layer by layer from the bottom, in each layer first those
/// with i ≥ 1 and j ≥ 1, then (i, 0), then (0, j), then (0, 0). Node (i, j, l) with i, j ≥ 1 is
/// held by its bars to (i, j, l−1), (i−1, j, l−1) and (i, j−1, l−1) (the vertical edge and the
/// diagonals of the faces below it, which run from a face's lowest corner to its highest):
/// directions (0, 0, 1), (1, 0, 1), (0, 1, 1), independent. Node (i, 0, l) by (0, 0, 1),
/// (1, 0, 1) and its edge to (i, 1, l), direction (0, 1, 0); node (0, j, l) likewise with
/// (0, 1, 1) and (1, 0, 0); node (0, 0, l) by its vertical edge and its edges to (1, 0, l) and
/// (0, 1, l). Each node is fixed by three independent bars to nodes fixed before it, so these n
/// bars form a regular triangular block of Dcc and r = n. Maxwell's rule corrected by the rank
/// (Calladine): motions n − r = 0, self-stresses m − r = m − n.
fn lattice_closed_form(k: usize) -> (usize, usize, usize, usize) {
    let n = 3 * k * (k + 1) * (k + 1);
    let m = 3 * k * (k + 1) * (k + 1) + 3 * k * k * (k + 1) - 2 * k * (k + 1) - k * k;
    (m, n, 0, m - n)
}

#[test]
fn sparse_path_counts_of_lattices_equal_the_closed_form() {
    for k in [1, 2, 4, 7, 10] {
        let m = lattice(k);
        let s = check(&m, &m.partition, &m.x0(), &opts(CheckMethod::Sparse)).unwrap();
        let (rows, cols, mot, ss) = lattice_closed_form(k);
        assert_eq!((s.m(), s.n()), (rows, cols), "k = {k}");
        assert_eq!((s.n_motions(), s.n_self_stresses()), (mot, ss), "k = {k}");
        let sp = s.sparse.as_ref().unwrap();
        assert!(sp.certain, "k = {k}: {sp:?}");
        assert_eq!(sp.self_stress_rows.len(), ss);
        // every listed self-stress is one: Dccᵀ u = 0 with the Dcc of the dense assembly
        let (_, _, dcc) = assemble_dcc(&m, &m.partition, &m.x0());
        let res = dcc.transpose() * &s.null_u;
        let unorm = s.null_u.norm_l2();
        assert!(res.norm_l2() <= 1e-12 * unorm * sp.s1, "k = {k}");
    }
}

#[test]
fn pendants_give_their_closed_form_motions_on_the_sparse_path() {
    // a pendant held by two bars moves along the normal of both, (0, 1, 1)/√2, alone
    let (k, p) = (5, 4);
    let m = lattice_with_pendants(k, p);
    let s = check(&m, &m.partition, &m.x0(), &opts(CheckMethod::Sparse)).unwrap();
    let (rows, cols, _, ss) = lattice_closed_form(k);
    assert_eq!((s.m(), s.n()), (rows + 2 * p, cols + 3 * p));
    assert_eq!((s.n_motions(), s.n_self_stresses()), (p, ss));
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let mut seen: Vec<String> = s
        .motions
        .iter()
        .map(|mo| {
            assert_eq!(mo.coordinates.len(), 2, "{mo:?}");
            let (a, b) = (&mo.coordinates[0], &mo.coordinates[1]);
            assert_eq!((a.dof, b.dof), (Dof::Y, Dof::Z));
            assert_eq!(a.node, b.node);
            assert!((a.value - h).abs() < 1e-12 && (b.value - h).abs() < 1e-12);
            a.node.clone()
        })
        .collect();
    seen.sort();
    let want: Vec<String> = (0..p).map(pendant_node).collect();
    assert_eq!(seen, want);
    // the advice: fix one of the pendant's coordinates, verified by construction
    let adv = advice::advise(&m, &m.partition, &m.x0(), &s, &opts(CheckMethod::Sparse), 6).unwrap();
    let motion_advice: Vec<_> = adv.iter().filter(|a| a.kind == "motion").collect();
    assert_eq!(motion_advice.len(), p);
    for st in motion_advice {
        assert_eq!(st.suggestions.len(), 1);
        let sg = &st.suggestions[0];
        assert_eq!((sg.motions_after, sg.self_stresses_after), (p - 1, ss));
        // and a full dense re-analysis of the changed partition agrees
        let changed = sg.action.apply(&m, &m.partition).unwrap();
        let c = advice::counts(&m, &changed, &m.x0(), &opts(CheckMethod::Dense)).unwrap();
        assert_eq!(c, (p - 1, ss));
    }
}

#[test]
fn sparse_self_stress_advice_is_confirmed_by_a_dense_reanalysis() {
    let m = lattice(2);
    let o = CheckOptions {
        method: CheckMethod::Sparse,
        max_listed_states: 5,
        ..Default::default()
    };
    let s = check(&m, &m.partition, &m.x0(), &o).unwrap();
    assert_eq!(s.self_stresses.len(), 5);
    let adv = advice::advise(&m, &m.partition, &m.x0(), &s, &o, 6).unwrap();
    assert_eq!(adv.len(), 5);
    for st in &adv {
        let sg = &st.suggestions[0];
        let changed = sg.action.apply(&m, &m.partition).unwrap();
        let c = advice::counts(&m, &changed, &m.x0(), &o).unwrap();
        assert_eq!(c, (sg.motions_after, sg.self_stresses_after));
        assert_eq!(c, (0, s.n_self_stresses() - 1));
    }
}

#[test]
fn automatic_method_is_sparse_above_the_size_and_work_limits() {
    let l = DEFAULT_MAX_DENSE_BYTES;
    // the dense SVD's work m·n·min(m, n) against DENSE_WORK_MAX = 2·10⁹
    assert_eq!(CheckMethod::Auto.resolve(1000, 1000, l), CheckMethod::Dense);
    assert_eq!(CheckMethod::Auto.resolve(2500, 300, l), CheckMethod::Dense);
    assert_eq!(
        CheckMethod::Auto.resolve(1400, 1300, l),
        CheckMethod::Sparse
    );
    assert_eq!(
        CheckMethod::Auto.resolve(2000, 2000, l),
        CheckMethod::Sparse
    );
    assert!(CheckMethod::Auto.dense_fallback(2000, 2000, l));
    // above SPARSE_ABOVE rows or columns: sparse, without the dense fall-back
    assert_eq!(CheckMethod::Auto.resolve(2501, 100, l), CheckMethod::Sparse);
    assert!(!CheckMethod::Auto.dense_fallback(2501, 100, l));
    // the memory limit
    assert_eq!(
        CheckMethod::Auto.resolve(100, 100, 1000),
        CheckMethod::Sparse
    );
    assert!(!CheckMethod::Auto.dense_fallback(100, 100, 1000));
    // a method asked for is taken as it is
    assert_eq!(
        CheckMethod::Dense.resolve(10_000, 10_000, l),
        CheckMethod::Dense
    );
    assert!(!CheckMethod::Sparse.dense_fallback(2000, 2000, l));
}

#[test]
fn automatic_method_decides_an_uncertain_sparse_rank_by_the_dense_svd() {
    // A clamped strip of 211 rigid beams: Dcc 1266 × 1266, past DENSE_WORK_MAX, so the
    // automatic choice takes the sparse path first. With the threshold set between the two
    // smallest singular values (from a dense SVD here), and within the sparse path's margin of
    // the smallest, the sparse decision is not certain, and the automatic choice gives the
    // dense analysis: the rank that all singular values decide.
    let m = strip(211, &[], &[]);
    let x = m.x0();
    let cols = columns(&m, &m.partition, &x);
    let rows = rows(&m, &m.partition);
    assert_eq!((rows.len(), cols.len()), (1266, 1266));
    assert_eq!(
        CheckMethod::Auto.resolve(1266, 1266, DEFAULT_MAX_DENSE_BYTES),
        CheckMethod::Sparse
    );
    let dcc = dense_from_rows(&rate_rows(&m, &x, &cols, &row_defs(&m, &rows)), cols.len());
    let sv = crate::linalg::singular_values(dcc.as_ref()).unwrap();
    let (s1, last) = (sv[0], sv[sv.len() - 1]);
    // the threshold 1.5 times below the smallest value: inside the margin of 2 of a certain
    // decision
    let tol = last / 1.5;
    let o = |method| CheckOptions {
        method,
        rank_tol: tol / s1,
        ..Default::default()
    };
    let sp = check(&m, &m.partition, &x, &o(CheckMethod::Sparse)).unwrap();
    assert!(!sp.sparse.as_ref().unwrap().certain);
    let auto = check(&m, &m.partition, &x, &o(CheckMethod::Auto)).unwrap();
    assert!(auto.sparse.is_none(), "the dense SVD decided");
    assert_eq!(auto.rank, sv.iter().filter(|&&v| v > tol).count());
    assert_eq!(auto.rank, 1266);
    assert_eq!(auto.singular_values.len(), 1266);
    // with the default threshold the sparse decision is certain and stands
    let certain = check(&m, &m.partition, &x, &CheckOptions::default()).unwrap();
    assert!(certain.sparse.as_ref().is_some_and(|s| s.certain));
    assert_eq!((certain.rank, certain.n_motions()), (1266, 0));
}

#[test]
fn added_row_bound_is_below_the_dense_singular_value_and_decides_only_rank_raising_rows() {
    // For rows w (pseudo-random, and random rows projected into the row space of Dcc) the
    // bound of AddedRowBound is at most σ_(r+1) of [Dcc; wᵀ] from a dense SVD, a row it
    // passes raises the dense rank by one, and a row with σ_(r+1) a hundred times above the
    // rank threshold is passed.
    let models = [
        strip(12, &[4, 5], &[]),
        lattice_with_pendants(3, 3),
        strip(8, &[4], &[Dof::X, Dof::Y]),
    ];
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for m in &models {
        let (d, s) = both(m);
        let name = &m.name;
        let o = opts(CheckMethod::Sparse);
        let bound = AddedRowBound::new(&s, s.sparse.as_ref().unwrap(), o.rank_tol)
            .unwrap_or_else(|| panic!("{name}: no bound"));
        let n = d.n();
        let (mut passed, mut refused) = (0, 0);
        for trial in 0..40 {
            // a few nonzeros, like a wire's row; every fourth row lies in the row space
            let mut w: Vec<f64> = vec![0.0; n];
            for _ in 0..4 {
                let j = ((next() + 1.0) * 0.5 * n as f64) as usize % n;
                w[j] += next();
            }
            if trial % 4 == 3 {
                // w − N (NᵀN)⁻¹ Nᵀ w with the dense orthonormal null basis
                let q = orthonormal(&d.null_v);
                let c = q.transpose() * faer::col::ColRef::from_slice(&w);
                for (i, wi) in w.iter_mut().enumerate() {
                    *wi -= (0..q.ncols()).map(|k| q[(i, k)] * c[k]).sum::<f64>();
                }
            }
            let row: SparseRow = w
                .iter()
                .enumerate()
                .filter(|e| *e.1 != 0.0)
                .map(|(j, &v)| (j, v))
                .collect();
            let mut a = Mat::<f64>::zeros(d.m() + 1, n);
            for i in 0..d.m() {
                for j in 0..n {
                    a[(i, j)] = d.Dcc[(i, j)];
                }
            }
            for &(j, v) in &row {
                a[(d.m(), j)] = v;
            }
            let sv = a.singular_values().unwrap();
            let r = d.rank;
            let lower = bound.lower_bound(&row);
            assert!(
                lower <= sv[r] * (1.0 + 1e-9),
                "{name}: {lower:e} > {:e}",
                sv[r]
            );
            let tol = o.rank_tol * sv[0];
            let rank_after = sv.iter().filter(|&&x| x > tol).count();
            if bound.raises_rank(&row) {
                assert_eq!(rank_after, r + 1, "{name}");
                passed += 1;
            } else if sv[r] > 100.0 * tol {
                // clearly rank-raising, yet refused: how conservative the bound is
                refused += 1;
            }
        }
        // the bound is not idle, and no row the dense SVD finds clearly rank-raising is refused
        assert!(passed >= 5 && refused == 0, "{name}: {passed} / {refused}");
    }
}

#[test]
fn a_pendant_joint_of_trusses_gets_wires_on_both_paths() {
    // A pendant (a node in no body, held by two bars) moves along n = (0, 1, 1)/√2 alone
    // (test_models::lattice_with_pendants). A wire from it to node g along the unit d stops
    // that motion with the reciprocal product |d · n| (the cosine between wire and motion); the
    // best is the largest over all nodes of the model, computed here from the node positions.
    // Every wire, on both paths, is confirmed by the dense SVD of Dcc with the wire's row
    // (d on the pendant's translations, −d on g's) added: one motion fewer.
    let (k, p) = (3, 1);
    let m = lattice_with_pendants(k, p);
    let x = m.x0();
    let pendant = m.node_id(&pendant_node(0)).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let n = [0.0, h, h];
    let pos = |id: usize| m.nodes[id].x0;
    let cosine = |g: usize| {
        let (a, b) = (pos(pendant), pos(g));
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]).abs() / len
    };
    let best = (0..m.nodes.len())
        .filter(|&g| g != pendant)
        .map(cosine)
        .fold(0.0, f64::max);
    for method in [CheckMethod::Dense, CheckMethod::Sparse] {
        let o = opts(method);
        let a = check(&m, &m.partition, &x, &o).unwrap();
        assert_eq!(a.n_motions(), 1);
        let sc = screw::screws(&m, &m.partition, &x, &a).unwrap();
        let adv = advice::wire_advice(&m, &x, &a, &sc, &[], &o, 5).unwrap();
        assert_eq!(adv.len(), 1, "{method:?}");
        let wires = &adv[0].wires;
        assert_eq!(wires.len(), 5, "{method:?}");
        assert!(
            (wires[0].reciprocal - best).abs() < 1e-12,
            "{method:?}: {wires:?}"
        );
        for w in wires {
            assert_eq!((w.from.as_str(), w.body.as_str()), ("p0", "p0"));
            let g = m.node_id(&w.to).unwrap();
            assert!((w.reciprocal - cosine(g)).abs() < 1e-12, "{w:?}");
            assert_eq!(
                (w.motions_after, w.self_stresses_after),
                (0, a.n_self_stresses())
            );
            let (pa, pg) = (pos(pendant), pos(g));
            let dv = [pg[0] - pa[0], pg[1] - pa[1], pg[2] - pa[2]];
            let len = (dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]).sqrt();
            // Dcc assembled densely (the sparse path keeps none), and the wire's row
            let (_, _, full) = assemble_dcc(&m, &m.partition, &x);
            let mut dcc = Mat::<f64>::zeros(a.m() + 1, a.n());
            for i in 0..a.m() {
                for j in 0..a.n() {
                    dcc[(i, j)] = full[(i, j)];
                }
            }
            for (j, c) in a.cols.iter().enumerate() {
                let k = match c.dof {
                    Dof::X => 0,
                    Dof::Y => 1,
                    Dof::Z => 2,
                    _ => continue,
                };
                let sign = if c.node == pendant {
                    1.0
                } else if c.node == g {
                    -1.0
                } else {
                    0.0
                };
                dcc[(a.m(), j)] = sign * dv[k] / len;
            }
            let sv = dcc.singular_values().unwrap();
            let rank = sv.iter().filter(|&&s| s > o.rank_tol * sv[0]).count();
            assert_eq!(rank, a.n(), "{method:?}: {w:?}");
        }
    }
}
