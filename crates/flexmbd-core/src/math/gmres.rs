//! GMRES for refining a solve whose factorisation is not accurate enough: left-preconditioned
//! by that factorisation, with the products taken by a more accurate operator than the matrix
//! that was factored (`dynamics::sparse::refined`, statics' Newton steps on fine meshes).
//!
//! Why left preconditioning: its residual Â⁻¹ (b − A z) is the correction the factorisation Â
//! gives, about the error of z, whereas the plain residual b − A z is dominated by the
//! round-off of z times the matrix's large entries. Why GMRES and not iterative refinement:
//! refinement is a fixed-point iteration that diverges once the factorisation's error exceeds
//! one; GMRES converges there too.

/// Krylov vectors per GMRES cycle, and cycles.
const CYCLE: usize = 30;
const MAX_CYCLES: usize = 4;

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// What a refinement did.
#[derive(Clone, Copy, Debug, Default)]
pub struct Refined {
    /// GMRES iterations (products with A).
    pub iterations: usize,
    /// The last correction Â⁻¹ (b − A z) against z, over their first `lead` entries.
    pub correction: f64,
}

/// The vectors of a refinement, kept between refinements of the same size (each solve of a
/// shift-invert Lanczos run is one: vectors of the model's size, mapped afresh by the
/// allocator each time if they were made per solve). The residual and the next product are
/// formed in the Krylov vector they become.
#[derive(Default)]
pub struct Workspace {
    basis: Vec<Vec<f64>>,
}

impl Workspace {
    /// Krylov vectors `..j` and vector `j` (mutable), each of length n.
    fn split(&mut self, j: usize, n: usize) -> (&[Vec<f64>], &mut Vec<f64>) {
        while self.basis.len() <= j {
            self.basis.push(Vec::new());
        }
        let (done, rest) = self.basis.split_at_mut(j);
        let v = &mut rest[0];
        v.resize(n, 0.0);
        (done, v)
    }
}

/// Refines z (on entry the factorisation's solution Â⁻¹ b) towards the solution of A z = b by
/// GMRES on Â⁻¹ A z = Â⁻¹ b: `precondition` applies Â⁻¹ in place, `product` writes A v. The
/// correction is measured over the first `lead` entries (the coordinates of a saddle-point
/// system, without its multipliers, which are in other units). Stops when the correction is at
/// most `tol` of z, or when a cycle no longer halves it (the round-off of the products).
pub fn refine(
    b: &[f64],
    z: &mut [f64],
    lead: usize,
    tol: f64,
    precondition: impl FnMut(&mut [f64]),
    product: impl FnMut(&[f64], &mut [f64]),
) -> Refined {
    refine_in(
        &mut Workspace::default(),
        b,
        z,
        lead,
        tol,
        precondition,
        product,
    )
}

/// [`refine`] with its vectors in `ws`, and `b` given by its leading entries: those of the
/// right-hand side beyond `b.len()` (up to `z.len()`) are zero (the shift-invert operator's
/// right-hand side [M v; 0], whose M v is held by its caller: no copy of the model's size).
pub fn refine_in(
    ws: &mut Workspace,
    b: &[f64],
    z: &mut [f64],
    lead: usize,
    tol: f64,
    mut precondition: impl FnMut(&mut [f64]),
    mut product: impl FnMut(&[f64], &mut [f64]),
) -> Refined {
    let n = z.len();
    debug_assert!(b.len() <= n);
    let mut stats = Refined::default();
    if z.iter().any(|v| !v.is_finite()) {
        return stats;
    }
    let mut last = f64::INFINITY;
    for _cycle in 0..MAX_CYCLES {
        // the preconditioned residual, in the first Krylov vector
        let (_, r) = ws.split(0, n);
        product(z, r);
        let (head, tail) = r.split_at_mut(b.len());
        head.iter_mut().zip(b).for_each(|(r, b)| *r = b - *r);
        tail.iter_mut().for_each(|r| *r = 0.0 - *r);
        precondition(r);
        let (rc, zc) = (norm(&r[..lead]), norm(&z[..lead]));
        stats.correction = if zc > 0.0 { rc / zc } else { rc };
        if stats.correction <= tol || rc >= 0.5 * last || !rc.is_finite() {
            break;
        }
        last = rc;
        let beta = norm(r);
        let z_norm = norm(z);
        r.iter_mut().for_each(|v| *v /= beta);
        // Hessenberg columns (rotated), the Givens rotations, and the rotated right-hand side
        let mut h: Vec<Vec<f64>> = Vec::with_capacity(CYCLE);
        let mut rot: Vec<(f64, f64)> = Vec::with_capacity(CYCLE);
        let mut g = vec![beta];
        for j in 0..CYCLE {
            // the next product, in Krylov vector j + 1
            let (v, w) = ws.split(j + 1, n);
            product(&v[j], w);
            precondition(w);
            stats.iterations += 1;
            // modified Gram–Schmidt, twice, against Krylov vectors 0 ..= j
            let mut col = vec![0.0; j + 2];
            for _pass in 0..2 {
                for (i, v) in v.iter().enumerate() {
                    let d: f64 = v.iter().zip(w.iter()).map(|(a, b)| a * b).sum();
                    w.iter_mut().zip(v).for_each(|(x, a)| *x -= d * a);
                    col[i] += d;
                }
            }
            let hn = norm(w);
            col[j + 1] = hn;
            for (i, &(c, s)) in rot.iter().enumerate() {
                let (a, b) = (col[i], col[i + 1]);
                col[i] = c * a + s * b;
                col[i + 1] = -s * a + c * b;
            }
            let (a, bb) = (col[j], col[j + 1]);
            let d = a.hypot(bb);
            let (c, s) = if d == 0.0 {
                (1.0, 0.0)
            } else {
                (a / d, bb / d)
            };
            col[j] = d;
            col[j + 1] = 0.0;
            rot.push((c, s));
            g.push(-s * g[j]);
            g[j] *= c;
            h.push(col);
            let estimate = g[j + 1].abs();
            if estimate <= 0.1 * tol * z_norm || hn == 0.0 || !hn.is_finite() {
                break;
            }
            if j + 1 < CYCLE {
                w.iter_mut().for_each(|x| *x /= hn);
            }
        }
        // y from the triangular system, then z += V y
        let k = h.len();
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let s: f64 = (i + 1..k).map(|l| h[l][i] * y[l]).sum();
            y[i] = (g[i] - s) / h[i][i];
        }
        if y.iter().any(|v| !v.is_finite()) {
            break;
        }
        // (one Krylov vector per Hessenberg column)
        for (v, &yi) in ws.basis[..k].iter().zip(&y) {
            z.iter_mut().zip(v).for_each(|(a, b)| *a += yi * b);
        }
    }
    stats
}

#[cfg(test)]
mod tests {
    use super::refine;

    /// A z for the tridiagonal A = tridiag(−1, 2 + 0.1 i, −1) (symmetric positive definite).
    fn times(z: &[f64], out: &mut [f64]) {
        let n = z.len();
        for i in 0..n {
            let mut v = (2.0 + 0.1 * i as f64) * z[i];
            if i > 0 {
                v -= z[i - 1];
            }
            if i + 1 < n {
                v -= z[i + 1];
            }
            out[i] = v;
        }
    }

    /// A poor approximate inverse: the diagonal of A, scaled by 0.3 or 3 in turn.
    fn poor_inverse(v: &mut [f64]) {
        for (i, x) in v.iter_mut().enumerate() {
            let f = if i % 2 == 0 { 0.3 } else { 3.0 };
            *x /= f * (2.0 + 0.1 * i as f64);
        }
    }

    #[test]
    fn gmres_converges_where_iterative_refinement_diverges() {
        let n = 60;
        let want: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin() + 0.5).collect();
        let mut b = vec![0.0; n];
        times(&want, &mut b);
        let err = |z: &[f64]| {
            z.iter()
                .zip(&want)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
        };
        // plain refinement z += Â⁻¹ (b − A z) grows the error (Â⁻¹ A has eigenvalues near 3.3)
        let mut z = b.clone();
        poor_inverse(&mut z);
        let e0 = err(&z);
        let mut r = vec![0.0; n];
        for _ in 0..5 {
            times(&z, &mut r);
            r.iter_mut().zip(&b).for_each(|(r, b)| *r = b - *r);
            poor_inverse(&mut r);
            z.iter_mut().zip(&r).for_each(|(a, d)| *a += d);
        }
        assert!(err(&z) > 10.0 * e0, "refinement: {} from {e0}", err(&z));
        // GMRES from the same start reaches the solution
        let mut z = b.clone();
        poor_inverse(&mut z);
        let stats = refine(&b, &mut z, n, 1e-13, poor_inverse, times);
        assert!(err(&z) < 1e-11, "GMRES error {}", err(&z));
        assert!(
            stats.correction <= 1e-13 && stats.iterations <= 60,
            "{stats:?}"
        );
    }
}
