//! Eigenpairs of a small dense symmetric matrix, without the fixed costs of a blocked library
//! solver: the projected matrices of the Krylov–Schur iteration (30 × 30 for ten modes), of
//! which only the eigenvectors of the largest eigenvalues are wanted.
//!
//! 1. **Householder tridiagonalisation** (Golub & Van Loan, *Matrix Computations*, 4th ed.,
//!    §8.3.1): Qᵀ A Q = T with Q = H₀ H₁ ⋯ H_{n−3}, Hₖ = I − τₖ vₖ vₖᵀ zeroing column k
//!    below the subdiagonal; the trailing block is updated by the symmetric rank-2 update
//!    A ← A − v wᵀ − w vᵀ, w = p − ½ τ (pᵀ v) v, p = τ A v. Q is kept as its reflectors.
//! 2. **Implicit QL with Wilkinson shifts** on T (the method of EISPACK's `tql2`/`imtql2`;
//!    Golub & Van Loan §8.3.5 for the QR form): for the unreduced block l … m, the shift is
//!    the eigenvalue of the leading 2 × 2 block nearer d_l, and one sweep of plane rotations
//!    from the bottom of the block to its top chases the bulge. An off-diagonal entry is set
//!    to zero (deflation) when |e_m| ≤ ε (|d_m| + |d_{m+1}|); at most [`MAX_SWEEPS`] sweeps
//!    per eigenvalue, else [`EigenError::NoConvergence`]. The rotations are recorded.
//! 3. **Eigenvectors** of the wanted eigenvalues only: the eigenvector matrix is
//!    Q G₁ ⋯ G_K (G the rotations), so its columns for the wanted unit vectors eₛ are
//!    H₀ ⋯ H_{n−3} G₁ ⋯ G_K eₛ, applied right to left to an n × k block: O(n² k) work
//!    instead of the O(n³) of accumulating all of them.
//!
//! Backward stable: the computed pairs are exact for A + E with ‖E‖ = O(ε ‖A‖), the
//! eigenvectors orthonormal to O(ε). The sign of each eigenvector is arbitrary (the caller
//! fixes one where it matters, `dynamics::fix_sign`).

use crate::linalg::EigenError;
use faer::{Mat, MatRef};

/// Largest order solved by [`sym_eigen_small`] where a caller may choose (beyond it the
/// O(n³) work with plain loops loses against faer's blocked solver).
pub const SMALL_EIGEN_MAX: usize = 128;

/// Most QL sweeps spent on one eigenvalue (EISPACK's limit) before giving up.
pub const MAX_SWEEPS: usize = 30;

/// All eigenpairs of the symmetric matrix `a` (its lower triangle is read): eigenvalues
/// ascending, orthonormal eigenvectors as columns. `NoConvergence` for a non-finite entry or
/// when the QL iteration does not converge.
pub fn sym_eigen_small(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let n = a.nrows();
    let (values, top) = sym_eigen_small_largest(a, n)?;
    Ok((values, Mat::from_fn(n, n, |i, c| top[(i, n - 1 - c)])))
}

/// All eigenvalues of the symmetric matrix `a` (lower triangle read), ascending, and the
/// eigenvectors of the `k` largest only, largest first (column c belongs to eigenvalue
/// n − 1 − c). The plane rotations of the QL phase are recorded and applied, in reverse, to
/// the k wanted unit vectors, then the Householder reflections: O(n² k) instead of O(n³)
/// for the vectors. Errors as [`sym_eigen_small`].
pub fn sym_eigen_small_largest(
    a: MatRef<'_, f64>,
    k: usize,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let n = a.nrows();
    let k = k.min(n);
    let mut work = vec![0.0; n * n];
    let mut norm2 = 0.0;
    for j in 0..n {
        for i in j..n {
            let v = a[(i, j)];
            if !v.is_finite() {
                return Err(EigenError::NoConvergence);
            }
            work[i + j * n] = v;
            work[j + i * n] = v;
            norm2 += if i == j { v * v } else { 2.0 * v * v };
        }
    }
    let mut d = vec![0.0; n];
    let mut e = vec![0.0; n];
    let mut tau = vec![0.0; n];
    tridiagonalise(
        n,
        &mut work,
        &mut d,
        &mut e,
        &mut tau,
        f64::EPSILON * norm2.sqrt(),
    );
    // QL converges from the top: for a matrix graded downwards (the Lanczos matrices, with the
    // dominant Ritz values first) run it on the reversed matrix, which is QR on T and takes
    // fewer sweeps (LAPACK's dsteqr makes the same choice); the rows of the vectors are
    // reversed back below
    let flip = n > 1 && d[n - 1].abs() < d[0].abs();
    if flip {
        d.reverse();
        e[..n - 1].reverse();
    }
    let mut sweeps = Vec::with_capacity(3 * n);
    let mut rotations = Vec::with_capacity(2 * n * n);
    tridiagonal_ql(n, &mut d, &mut e, &mut sweeps, &mut rotations)?;
    // ascending order (a stable sort of the indices)
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&p, &q| d[p].total_cmp(&d[q]));
    let values = order.iter().map(|&i| d[i]).collect();
    // W (n × k, row-major): the wanted unit vectors, then Z W = G₁ ⋯ G_K W and Q (Z W)
    let mut w = vec![0.0; n * k];
    for c in 0..k {
        w[order[n - 1 - c] * k + c] = 1.0;
    }
    for sweep in sweeps.iter().rev() {
        // the sweep's rotations, last applied first: i = first … last
        let rot = &rotations[sweep.start..sweep.start + (sweep.last + 1 - sweep.first)];
        for (i, &[c, s]) in (sweep.first..=sweep.last).zip(rot.iter().rev()) {
            // rows i and i+1: [wᵢ, wᵢ₊₁] ← [c wᵢ + s wᵢ₊₁, −s wᵢ + c wᵢ₊₁]
            let (lo, hi) = w[i * k..(i + 2) * k].split_at_mut(k);
            for (x, y) in lo.iter_mut().zip(hi.iter_mut()) {
                let (xv, yv) = (*x, *y);
                *x = c * xv + s * yv;
                *y = c * yv - s * xv;
            }
        }
    }
    if flip {
        for i in 0..n / 2 {
            let (lo, hi) = w.split_at_mut((n - 1 - i) * k);
            lo[i * k..(i + 1) * k].swap_with_slice(&mut hi[..k]);
        }
    }
    let mut t = vec![0.0; k];
    let reflections = if k == 0 { 0 } else { n.saturating_sub(2) };
    for step in (0..reflections).rev() {
        let tk = tau[step];
        if tk == 0.0 {
            continue;
        }
        // rows step+1 … n−1 of W: W ← (I − τ v vᵀ) W
        let v = &work[step * n + step + 1..step * n + n];
        let rows = &mut w[(step + 1) * k..];
        t.iter_mut().for_each(|x| *x = 0.0);
        for (vi, row) in v.iter().zip(rows.chunks_exact(k)) {
            for (tc, r) in t.iter_mut().zip(row) {
                *tc += vi * r;
            }
        }
        for (vi, row) in v.iter().zip(rows.chunks_exact_mut(k)) {
            let f = tk * vi;
            for (r, tc) in row.iter_mut().zip(&t) {
                *r -= f * tc;
            }
        }
    }
    Ok((values, Mat::from_fn(n, k, |i, c| w[i * k + c])))
}

/// Phase 1: `a` (n × n column-major, both triangles) to T = Qᵀ A Q. On return `d` holds the
/// diagonal of T, `e[k]` the entry (k+1, k) (`e[n−1]` = 0); Q = H₀ ⋯ H_{n−3} is kept as the
/// reflectors: Hₖ = I − τₖ vₖ vₖᵀ with vₖ in `a[k+1.., k]` (first entry 1), τₖ in `tau[k]`
/// (zero: Hₖ = I). A column whose entries below the subdiagonal have a norm of at most
/// `negligible` (ε ‖A‖_F) is taken as reduced already (H = I, those entries dropped): a
/// perturbation of A no larger than the backward error of a reflection, which saves the
/// reduction of matrices that are tridiagonal up to round-off (the Lanczos matrices with
/// their reorthogonalisation coefficients).
fn tridiagonalise(
    n: usize,
    a: &mut [f64],
    d: &mut [f64],
    e: &mut [f64],
    tau: &mut [f64],
    negligible: f64,
) {
    let mut p = vec![0.0; n];
    for k in 0..n.saturating_sub(2) {
        // x = A[k+1.., k]; H x = β e₁ with H = I − τ v vᵀ, v₀ = 1 (LAPACK's dlarfg)
        let col = k * n;
        let x0 = a[col + k + 1];
        let tail = &a[col + k + 2..col + n];
        let scale = tail.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let tail_norm = if scale == 0.0 {
            0.0
        } else {
            scale * tail.iter().map(|v| (v / scale).powi(2)).sum::<f64>().sqrt()
        };
        if tail_norm <= negligible {
            // tridiagonal in this column up to round-off: H = I
            tau[k] = 0.0;
            e[k] = x0;
            continue;
        }
        let norm = x0.hypot(tail_norm);
        let beta = if x0 >= 0.0 { -norm } else { norm };
        let t = (beta - x0) / beta;
        let inv = 1.0 / (x0 - beta);
        a[col + k + 1] = 1.0;
        for v in &mut a[col + k + 2..col + n] {
            *v *= inv;
        }
        tau[k] = t;
        e[k] = beta;
        // trailing block B = A[k+1.., k+1..] (both triangles), m × m; v = A[k+1.., k]
        let m = n - k - 1;
        let off = k + 1;
        let (head, rest) = a.split_at_mut((k + 1) * n);
        let v = &head[col + off..col + n];
        // p = τ B v, by columns (B symmetric)
        let p = &mut p[..m];
        p.iter_mut().for_each(|x| *x = 0.0);
        for (j, &vj) in v.iter().enumerate() {
            let f = t * vj;
            let bj = &rest[j * n + off..j * n + n];
            for (pi, bij) in p.iter_mut().zip(bj) {
                *pi += bij * f;
            }
        }
        // w = p − ½ τ (pᵀ v) v, into p
        let half = 0.5 * t * dot4(p, v);
        for (pi, vi) in p.iter_mut().zip(v) {
            *pi -= half * vi;
        }
        // B ← B − v wᵀ − w vᵀ
        for j in 0..m {
            let (vj, wj) = (v[j], p[j]);
            let bj = &mut rest[j * n + off..j * n + n];
            for ((bij, vi), wi) in bj.iter_mut().zip(v).zip(p.iter()) {
                *bij -= vi * wj + wi * vj;
            }
        }
    }
    for i in 0..n {
        d[i] = a[i + i * n];
    }
    if n >= 2 {
        e[n - 2] = a[(n - 1) + (n - 2) * n];
    }
    if n >= 1 {
        e[n - 1] = 0.0;
    }
}

/// a · b with four partial sums (they vectorise and pipeline).
fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 4];
    let (ac, ar) = a.split_at(n - n % 4);
    let (bc, br) = b.split_at(n - n % 4);
    for (x, y) in ac.chunks_exact(4).zip(bc.chunks_exact(4)) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ar.iter().zip(br).map(|(x, y)| x * y).sum();
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// The plane rotations of one QL sweep: `rotations[start..]` holds (c, s) for i = last,
/// last − 1, …, first, in the order applied.
struct Sweep {
    start: usize,
    first: usize,
    last: usize,
}

/// Phase 2: implicit QL with Wilkinson shifts on the tridiagonal (d, e) (`e[k]` couples k and
/// k+1); `d` becomes the eigenvalues (unordered). The plane rotations are appended to
/// `rotations` in the order applied, as (c, s) for the update of columns i and i+1 of the
/// eigenvector matrix Z: [zᵢ, zᵢ₊₁] ← [c zᵢ − s zᵢ₊₁, s zᵢ + c zᵢ₊₁]; `sweeps` says which i.
fn tridiagonal_ql(
    n: usize,
    d: &mut [f64],
    e: &mut [f64],
    sweeps: &mut Vec<Sweep>,
    rotations: &mut Vec<[f64; 2]>,
) -> Result<(), EigenError> {
    // deflation threshold: ε ‖T‖ (the size of the errors of the reduction to T already), so
    // eigenvalues far below the norm take no extra sweeps for a relative accuracy that the
    // backward error of phase 1 does not support anyway
    let norm = (0..n).fold(0.0f64, |a, i| {
        let below = if i > 0 { e[i - 1].abs() } else { 0.0 };
        a.max(d[i].abs() + e[i].abs() + below)
    });
    let small = f64::EPSILON * norm;
    for l in 0..n {
        let mut tries = 0;
        loop {
            // the end m of the unreduced block starting at l
            let mut m = l;
            while m + 1 < n {
                let dd = d[m].abs() + d[m + 1].abs();
                let em = e[m].abs();
                if em <= f64::EPSILON * dd || em <= small || em < f64::MIN_POSITIVE {
                    e[m] = 0.0;
                    break;
                }
                m += 1;
            }
            if m == l {
                break;
            }
            tries += 1;
            if tries > MAX_SWEEPS {
                return Err(EigenError::NoConvergence);
            }
            // Wilkinson shift: the eigenvalue of [[d_l, e_l], [e_l, d_{l+1}]] nearer d_l,
            // as d_m − shift in g
            let g0 = (d[l + 1] - d[l]) / (2.0 * e[l]);
            let r0 = radius(g0, 1.0);
            let mut g = d[m] - d[l] + e[l] / (g0 + r0.copysign(g0));
            let (mut s, mut c, mut p) = (1.0f64, 1.0f64, 0.0f64);
            let mut split = false;
            let start = rotations.len();
            for i in (l..m).rev() {
                let f = s * e[i];
                let b = c * e[i];
                let r = radius(f, g);
                e[i + 1] = r;
                if r == 0.0 {
                    // the bulge vanished (underflow): the block splits at i+1
                    d[i + 1] -= p;
                    e[m] = 0.0;
                    split = true;
                    break;
                }
                s = f / r;
                c = g / r;
                g = d[i + 1] - p;
                let r = (d[i] - g) * s + 2.0 * c * b;
                p = s * r;
                d[i + 1] = g + p;
                g = c * r - b;
                rotations.push([c, s]);
            }
            let applied = rotations.len() - start;
            if applied > 0 {
                sweeps.push(Sweep {
                    start,
                    first: m - applied,
                    last: m - 1,
                });
            }
            if split {
                continue;
            }
            d[l] -= p;
            e[l] = g;
            e[m] = 0.0;
        }
    }
    Ok(())
}

/// √(a² + b²): the plain formula where the squares can neither overflow nor lose the result
/// to underflow, `hypot` otherwise.
fn radius(a: f64, b: f64) -> f64 {
    let big = a.abs().max(b.abs());
    if big > 1e-150 && big < 1e150 {
        (a * a + b * b).sqrt()
    } else {
        a.hypot(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::sym_eigen_seq;
    use rand::{Rng, SeedableRng};

    /// max |A V − V Λ| / ‖A‖, max |Vᵀ V − I|, and the eigenvalue differences to faer relative
    /// to ‖A‖.
    fn check(a: &Mat<f64>) -> (f64, f64, f64) {
        let n = a.nrows();
        let (lam, v) = sym_eigen_small(a.as_ref()).expect("converges");
        let (lf, _) = sym_eigen_seq(a.as_ref()).expect("faer converges");
        let norm = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .fold(0.0f64, |s, (i, j)| s.max(a[(i, j)].abs()))
            .max(f64::MIN_POSITIVE);
        let av = a * &v;
        let mut res = 0.0f64;
        let mut orth = 0.0f64;
        for c in 0..n {
            for i in 0..n {
                res = res.max((av[(i, c)] - lam[c] * v[(i, c)]).abs() / norm);
                let g: f64 = (0..n).map(|k| v[(k, i)] * v[(k, c)]).sum();
                orth = orth.max((g - if i == c { 1.0 } else { 0.0 }).abs());
            }
        }
        for w in lam.windows(2) {
            assert!(w[0] <= w[1], "ascending");
        }
        let diff = lam
            .iter()
            .zip(&lf)
            .fold(0.0f64, |s, (x, y)| s.max((x - y).abs() / norm));
        (res, orth, diff)
    }

    fn random_sym(n: usize, rng: &mut rand::rngs::StdRng) -> Mat<f64> {
        let b = Mat::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0));
        Mat::from_fn(n, n, |i, j| b[(i, j)] + b[(j, i)])
    }

    /// Q diag(values) Qᵀ with a random orthogonal Q (Householder products).
    fn with_spectrum(values: &[f64], rng: &mut rand::rngs::StdRng) -> Mat<f64> {
        let n = values.len();
        let mut q = Mat::<f64>::identity(n, n);
        for _ in 0..3 {
            let v: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let vv: f64 = v.iter().map(|x| x * x).sum();
            let h = Mat::from_fn(n, n, |i, j| {
                (if i == j { 1.0 } else { 0.0 }) - 2.0 * v[i] * v[j] / vv
            });
            q = &q * &h;
        }
        let d = Mat::from_fn(n, n, |i, j| if i == j { values[i] } else { 0.0 });
        let a = &q * &d * q.transpose();
        Mat::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
    }

    #[test]
    fn random_matrices_match_faer() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        for n in [1, 2, 3, 4, 5, 8, 17, 30, 31, 64, 128] {
            for _ in 0..3 {
                let a = random_sym(n, &mut rng);
                let (res, orth, diff) = check(&a);
                assert!(res < 1e-13 * n as f64, "n {n}: residual {res}");
                assert!(orth < 1e-13 * n as f64, "n {n}: orthogonality {orth}");
                assert!(
                    diff < 1e-13 * n as f64,
                    "n {n}: eigenvalues differ by {diff}"
                );
            }
        }
    }

    #[test]
    fn repeated_clustered_and_graded_spectra() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(11);
        let spectra: Vec<Vec<f64>> = vec![
            vec![2.0; 12],                                              // one eigenvalue
            (0..20).map(|i| if i < 10 { 1.0 } else { -3.0 }).collect(), // two multiple
            (0..25).map(|i| 1.0 + 1e-12 * i as f64).collect(),          // a tight cluster
            (0..30i32).map(|i| 10f64.powi(-i / 2)).collect(),           // graded
            (0..30)
                .map(|i| if i % 3 == 0 { 0.0 } else { i as f64 })
                .collect(), // null space
        ];
        for values in spectra {
            let a = with_spectrum(&values, &mut rng);
            let (res, orth, diff) = check(&a);
            let n = values.len() as f64;
            assert!(res < 1e-13 * n, "residual {res}");
            assert!(orth < 1e-13 * n, "orthogonality {orth}");
            assert!(diff < 1e-13 * n, "eigenvalues differ by {diff}");
            let (lam, _) = sym_eigen_small(a.as_ref()).unwrap();
            let mut want = values.clone();
            want.sort_by(f64::total_cmp);
            let scale = want.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for (x, y) in lam.iter().zip(&want) {
                assert!((x - y).abs() <= 1e-13 * n * scale, "{x} against {y}");
            }
        }
    }

    #[test]
    fn largest_eigenvectors_match_the_full_decomposition() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(17);
        for n in [1, 2, 5, 30, 47] {
            let a = random_sym(n, &mut rng);
            let (all, v) = sym_eigen_small(a.as_ref()).unwrap();
            for k in [0, 1, n / 3, n] {
                let (values, top) = sym_eigen_small_largest(a.as_ref(), k).unwrap();
                assert_eq!(values, all);
                assert_eq!((top.nrows(), top.ncols()), (n, k));
                for c in 0..k {
                    // the same vector up to its sign (the eigenvalues are distinct)
                    let col = n - 1 - c;
                    let p: f64 = (0..n).map(|i| top[(i, c)] * v[(i, col)]).sum();
                    assert!(
                        (p.abs() - 1.0).abs() < 1e-12,
                        "n {n}, k {k}, column {c}: {p}"
                    );
                }
            }
        }
    }

    #[test]
    fn special_matrices() {
        // zero, diagonal (already reduced), tridiagonal, empty, 1 × 1
        let (lam, v) = sym_eigen_small(Mat::<f64>::zeros(6, 6).as_ref()).unwrap();
        assert!(lam.iter().all(|&x| x == 0.0));
        for c in 0..6 {
            for i in 0..6 {
                assert_eq!(v[(i, c)].abs(), if i == c { 1.0 } else { 0.0 });
            }
        }
        let d = Mat::from_fn(5, 5, |i, j| if i == j { 5.0 - i as f64 } else { 0.0 });
        let (lam, _) = sym_eigen_small(d.as_ref()).unwrap();
        assert_eq!(lam, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        // the second-difference matrix: 2 − 2 cos(kπ/(n+1))
        let n = 40;
        let t = Mat::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 2.0,
            1 => -1.0,
            _ => 0.0,
        });
        let (lam, _) = sym_eigen_small(t.as_ref()).unwrap();
        for (k, l) in lam.iter().enumerate() {
            let exact = 2.0 - 2.0 * ((k + 1) as f64 * std::f64::consts::PI / (n + 1) as f64).cos();
            assert!(
                (l - exact).abs() < 1e-14 * 4.0 * n as f64,
                "{l} against {exact}"
            );
        }
        let (lam, v) = sym_eigen_small(Mat::<f64>::zeros(0, 0).as_ref()).unwrap();
        assert!(lam.is_empty() && v.nrows() == 0);
        let (lam, v) = sym_eigen_small(Mat::from_fn(1, 1, |_, _| -3.5).as_ref()).unwrap();
        assert_eq!((lam[0], v[(0, 0)]), (-3.5, 1.0));
        // only the lower triangle is read; non-finite entries are an error
        let mut a = random_sym(7, &mut rand::rngs::StdRng::seed_from_u64(3));
        let (l1, _) = sym_eigen_small(a.as_ref()).unwrap();
        a[(0, 6)] = f64::NAN;
        let (l2, _) = sym_eigen_small(a.as_ref()).unwrap();
        assert_eq!(l1, l2);
        a[(6, 0)] = f64::INFINITY;
        assert_eq!(
            sym_eigen_small(a.as_ref()).unwrap_err(),
            EigenError::NoConvergence
        );
    }

    #[test]
    fn widely_scaled_matrix_keeps_its_large_eigenvalues_relative() {
        // as the projected Krylov–Schur matrices: θ from 1e-2 down to 1e-14 of the largest
        let mut rng = rand::rngs::StdRng::seed_from_u64(5);
        let values: Vec<f64> = (0..30).map(|i| 10f64.powf(-0.5 * i as f64)).collect();
        let a = with_spectrum(&values, &mut rng);
        let (lam, _) = sym_eigen_small(a.as_ref()).unwrap();
        let (lf, _) = sym_eigen_seq(a.as_ref()).unwrap();
        for k in 0..30 {
            // backward stable: errors of ε ‖A‖, so the largest keep their relative accuracy
            let tol = if k >= 26 {
                1e-13 * lf[k].abs()
            } else {
                1e-14 * 30.0
            };
            assert!(
                (lam[k] - lf[k]).abs() <= tol,
                "{k}: {} against {}",
                lam[k],
                lf[k]
            );
        }
    }
}
