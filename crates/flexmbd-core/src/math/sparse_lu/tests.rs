//! Unit tests of the sparse LU and L D Lᵀ.

use super::*;

/// Dense square test matrix to CSC.
fn csc(a: &[Vec<f64>]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    csc_cols(a, a.len())
}

/// Dense test matrix with `n` columns to CSC.
fn csc_cols(a: &[Vec<f64>], n: usize) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
    let (mut cp, mut ri, mut v) = (vec![0], vec![], vec![]);
    for j in 0..n {
        for (i, row) in a.iter().enumerate() {
            if row[j] != 0.0 {
                ri.push(i);
                v.push(row[j]);
            }
        }
        cp.push(ri.len());
    }
    (cp, ri, v)
}

/// A x for A in CSC form.
fn csc_mul(cp: &[usize], ri: &[usize], v: &[f64], x: &[f64]) -> Vec<f64> {
    let mut b = vec![0.0; x.len()];
    for (j, xj) in x.iter().enumerate() {
        for p in cp[j]..cp[j + 1] {
            b[ri[p]] += v[p] * xj;
        }
    }
    b
}

#[test]
fn factor_and_refactor_solve_random_sparse_systems() {
    let mut rng = crate::elements::testing::Rng(42);
    for n in [1, 2, 5, 17, 60] {
        // random sparse pattern with a zero diagonal in places (needs pivoting)
        let mut a = vec![vec![0.0; n]; n];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                if (i + 2 * j) % 3 == 0 || rng.next() > 0.8 || (i + 1) % n == j {
                    *v = rng.next();
                }
            }
            row[(i + 1) % n] += 2.0;
        }
        let (cp, ri, v) = csc(&a);
        let mut lu = SparseLu::new(n, &cp, &ri).unwrap();
        for pass in 0..3 {
            // perturbed values, same structure
            let v2: Vec<f64> = v
                .iter()
                .map(|x| x * (1.0 + 0.01 * pass as f64 * rng.next()))
                .collect();
            let refactored = pass > 0 && lu.refactor(&cp, &ri, &v2).is_ok();
            if !refactored {
                lu.factor(&cp, &ri, &v2).unwrap();
            }
            let xs: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let mut b = csc_mul(&cp, &ri, &v2, &xs);
            lu.solve(&mut b);
            for i in 0..n {
                assert!(
                    (b[i] - xs[i]).abs() < 1e-9,
                    "n {n} pass {pass}: {} vs {}",
                    b[i],
                    xs[i]
                );
            }
        }
    }
}

#[test]
fn symmetric_refactor_solves_symmetric_indefinite_systems() {
    let mut rng = crate::elements::testing::Rng(7);
    for n in [1, 3, 8, 40, 90] {
        // symmetric pattern with a full diagonal, values symmetric and indefinite
        let mut a = vec![vec![0.0; n]; n];
        for i in 0..n {
            for j in 0..i {
                if (i * 7 + j * 3) % 5 == 0 || i == j + 1 {
                    let v = rng.next();
                    a[i][j] = v;
                    a[j][i] = v;
                }
            }
            a[i][i] = if i % 3 == 0 { -4.0 } else { 4.0 } + rng.next();
        }
        let (cp, ri, _) = csc(&a);
        let mut lu = SparseLu::new(n, &cp, &ri).unwrap();
        assert!(lu.symmetric() && lu.set_diagonal_pivots(&cp, &ri));
        let slots = lu.lower_layout(&cp, &ri);
        for pass in 0..3 {
            let mut a2 = a.clone();
            for (i, row) in a2.iter_mut().enumerate() {
                row[i] *= 1.0 + 0.1 * pass as f64;
            }
            let (_, _, v2) = csc(&a2);
            let lower: Vec<f64> = slots.iter().map(|&p| v2[p as usize]).collect();
            lu.refactor_symmetric(&lower).unwrap();
            let xs: Vec<f64> = (0..n).map(|_| rng.next()).collect();
            let mut b = csc_mul(&cp, &ri, &v2, &xs);
            lu.solve(&mut b);
            for i in 0..n {
                assert!((b[i] - xs[i]).abs() < 1e-10, "n {n}: {} vs {}", b[i], xs[i]);
            }
            // the LU refactorisation with the same pivots agrees
            lu.refactor(&cp, &ri, &v2).unwrap();
            let mut b2 = csc_mul(&cp, &ri, &v2, &xs);
            lu.solve(&mut b2);
            for i in 0..n {
                assert!((b2[i] - xs[i]).abs() < 1e-10);
            }
        }
    }
}

#[test]
fn released_values_are_made_again_by_the_next_symmetric_refactorisation() {
    // an indefinite symmetric tridiagonal matrix: the solve after release and refactorisation
    // is the one before, to the bit, and the inertia is counted again
    let n: usize = 12;
    let a: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| match i.abs_diff(j) {
                    0 => [3.0, -2.5, 4.0][i % 3],
                    1 => 1.0,
                    _ => 0.0,
                })
                .collect()
        })
        .collect();
    let (cp, ri, v) = csc(&a);
    let mut lu = SparseLu::new(n, &cp, &ri).unwrap();
    assert!(lu.set_diagonal_pivots(&cp, &ri));
    let slots = lu.lower_layout(&cp, &ri);
    let lower: Vec<f64> = slots.iter().map(|&p| v[p as usize]).collect();
    let xs: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
    let b = csc_mul(&cp, &ri, &v, &xs);
    lu.refactor_symmetric(&lower).unwrap();
    let negative = lu.negative_pivots();
    assert!(negative > 0 && negative < n);
    let mut z1 = b.clone();
    lu.solve(&mut z1);
    lu.release_values();
    lu.refactor_symmetric(&lower).unwrap();
    assert_eq!(lu.negative_pivots(), negative);
    let mut z2 = b.clone();
    lu.solve(&mut z2);
    assert_eq!(z1, z2);
    for i in 0..n {
        assert!((z1[i] - xs[i]).abs() < 1e-12, "{} vs {}", z1[i], xs[i]);
    }
}

#[test]
fn refactor_detects_a_pivot_that_became_small() {
    // [[2, 1], [1, 1]]: pivot 2 on row 0; then [[1e-6, 1], [1, 1]] needs the other row
    let (cp, ri, v) = csc(&[vec![2.0, 1.0], vec![1.0, 1.0]]);
    let mut lu = SparseLu::new(2, &cp, &ri).unwrap();
    lu.factor(&cp, &ri, &v).unwrap();
    let (_, _, v2) = csc(&[vec![1e-6, 1.0], vec![1.0, 1.0]]);
    assert!(lu.refactor(&cp, &ri, &v2).unwrap() < 1e-5);
    lu.factor(&cp, &ri, &v2).unwrap();
    let mut b = vec![1.0 + 1e-6, 2.0];
    lu.solve(&mut b);
    assert!(
        (b[0] - 1.0).abs() < 1e-12 && (b[1] - 1.0).abs() < 1e-12,
        "{b:?}"
    );
    // singular
    let (_, _, v3) = csc(&[vec![1.0, 1.0], vec![1.0, 1.0]]);
    assert_eq!(lu.factor(&cp, &ri, &v3), Err(LuFailure::Singular));
}

/// A = B C with B (m × r) and C (r × n) random and sparse: rank r (generic), known by
/// construction; the rank-revealing LU finds it, and its null vectors have residuals at
/// round-off.
#[test]
fn rank_revealing_lu_finds_the_rank_of_a_product_and_its_null_spaces() {
    use super::rank::{Csc, RankLu};
    let mut rng = crate::elements::testing::Rng(11);
    for (trial, &(m, n, r)) in [
        (30, 20, 20),
        (20, 30, 20),
        (40, 40, 31),
        (25, 35, 9),
        (12, 12, 0),
    ]
    .iter()
    .enumerate()
    {
        let sparse = |rng: &mut crate::elements::testing::Rng, a: usize, b: usize| {
            let mut x = vec![vec![0.0; b]; a];
            for (i, row) in x.iter_mut().enumerate() {
                for (j, v) in row.iter_mut().enumerate() {
                    if i % b.max(1) == j || rng.next() > 0.6 {
                        *v = rng.next();
                    }
                }
            }
            x
        };
        let bm = sparse(&mut rng, m, r);
        let cm = sparse(&mut rng, r, n);
        let a: Vec<Vec<f64>> = (0..m)
            .map(|i| {
                (0..n)
                    .map(|j| (0..r).map(|k| bm[i][k] * cm[k][j]).sum())
                    .collect()
            })
            .collect();
        let (cp, ri, v) = csc_cols(&a, n);
        let order: Vec<usize> = (0..n).rev().collect();
        let amax = a.iter().flatten().fold(0.0f64, |mx, x| mx.max(x.abs()));
        let lu = RankLu::factor(
            Csc {
                m,
                n,
                ptr: &cp,
                row: &ri,
                val: &v,
            },
            &order,
            1e-10 * amax.max(1.0),
        );
        assert_eq!(lu.rank(), r, "trial {trial}");
        assert_eq!(lu.dependent_cols.len(), n - r, "trial {trial}");
        for k in 0..n - r {
            let z = lu.null_vector(k);
            let az: Vec<f64> = (0..m)
                .map(|i| (0..n).map(|j| a[i][j] * z[j]).sum())
                .collect();
            let nz = z.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(
                az.iter().all(|x| x.abs() <= 1e-11 * nz * amax.max(1.0)),
                "trial {trial}"
            );
        }
        let l2 = lu.l2_rows();
        for k in lu.nonbasic_rows() {
            let z = lu.left_null_vector(k, &l2[k]);
            let nz = z.iter().map(|x| x * x).sum::<f64>().sqrt();
            for j in 0..n {
                let s: f64 = (0..m).map(|i| z[i] * a[i][j]).sum();
                assert!(s.abs() <= 1e-11 * nz * amax.max(1.0), "trial {trial}");
            }
        }
        // A₁₁ solves: A₁₁ (A₁₁⁻¹ b) = b
        let rr = lu.rank();
        let b: Vec<f64> = (0..rr).map(|s| 1.0 + s as f64).collect();
        let mut y = b.clone();
        lu.solve_a11(&mut y);
        for s in 0..rr {
            let i = lu.pivot_rows[s];
            let back: f64 = (0..rr).map(|t| a[i][lu.basic_cols[t]] * y[t]).sum();
            assert!((back - b[s]).abs() <= 1e-9 * b[s].abs(), "trial {trial}");
        }
        let mut y = b.clone();
        lu.solve_a11_t(&mut y);
        for t in 0..rr {
            let j = lu.basic_cols[t];
            let back: f64 = (0..rr).map(|s| a[lu.pivot_rows[s]][j] * y[s]).sum();
            assert!((back - b[t]).abs() <= 1e-9 * b[t].abs(), "trial {trial}");
        }
    }
}

/// The row lists that L's supernodes share ([`SparseLu::release_upper_structure`]) give the
/// same factorisation and solves, to the bit, as one list per column: a chain of dense 6 × 6
/// blocks (the six unknowns of a beam node, coupled to the next node), whose factor's columns
/// come in runs of nested structure, with a natural order and a reversed one.
#[test]
fn shared_row_lists_of_supernodes_solve_as_the_full_lists() {
    let mut rng = crate::elements::testing::Rng(11);
    let (nodes, b) = (7, 6);
    let n = nodes * b;
    let mut a = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in 0..i {
            if i / b == j / b || i / b == j / b + 1 {
                let v = rng.next();
                a[i][j] = v;
                a[j][i] = v;
            }
        }
        a[i][i] = 30.0 + rng.next();
    }
    let (cp, ri, v) = csc(&a);
    for order in [
        (0..n as u32).collect::<Vec<u32>>(),
        (0..n as u32).rev().collect(),
    ] {
        let mut lu = SparseLu::with_order(n, order).unwrap();
        assert!(lu.set_diagonal_pivots(&cp, &ri));
        let slots = lu.lower_layout(&cp, &ri);
        let lower: Vec<f64> = slots.iter().map(|&p| v[p as usize]).collect();
        let xs: Vec<f64> = (0..n).map(|_| rng.next()).collect();
        let rhs = csc_mul(&cp, &ri, &v, &xs);
        lu.refactor_symmetric(&lower).unwrap();
        let mut full = rhs.clone();
        lu.solve(&mut full);
        let rows_before = lu.l_idx.len();
        lu.release_upper_structure();
        // a node's six columns share one list, its last five read it one entry on
        assert_eq!(lu.nnz().0, rows_before);
        assert!(
            lu.l_idx.len() * 3 < rows_before,
            "{} of {rows_before}",
            lu.l_idx.len()
        );
        lu.refactor_symmetric(&lower).unwrap();
        let mut shared = rhs.clone();
        lu.solve(&mut shared);
        for i in 0..n {
            assert_eq!(shared[i].to_bits(), full[i].to_bits(), "entry {i}");
            assert!(
                (shared[i] - xs[i]).abs() < 1e-12,
                "{} vs {}",
                shared[i],
                xs[i]
            );
        }
    }
}
