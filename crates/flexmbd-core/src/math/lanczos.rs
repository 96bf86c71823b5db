//! The largest eigenvalue of a symmetric positive semi-definite operator by Lanczos with full
//! reorthogonalisation, on one thread and from a fixed start vector (the same bits for any
//! number of threads). The sparse kinematic check uses it for s₁ = ‖Dcc‖₂ (operator DccᵀDcc)
//! and for σ_min of a square factored block (operator A⁻ᵀA⁻¹).

/// A converged (or last) Ritz value of [`largest_eigenvalue`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extreme {
    /// The largest Ritz value θ (≤ λ_max).
    pub value: f64,
    /// Its residual ‖Op y − θ y‖ for the unit Ritz vector y: some eigenvalue lies within it of θ.
    pub residual: f64,
    /// Lanczos steps taken.
    pub steps: usize,
}

/// A Ritz value that changed by less than this, relative, in one step has settled.
pub const SETTLED: f64 = 1e-10;

/// A fixed, non-special unit start vector of length n (a linear congruential sequence).
pub(crate) fn start_vector(n: usize) -> Vec<f64> {
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut v: Vec<f64> = (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            0.5 + ((state >> 11) as f64) / ((1u64 << 53) as f64)
        })
        .collect();
    let nv = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    v.iter_mut().for_each(|a| *a /= nv);
    v
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The largest eigenvalue of the symmetric positive semi-definite operator `apply` (y ← Op x)
/// of dimension n: Lanczos with full reorthogonalisation from a fixed start vector, stopped
/// when the residual of the largest Ritz pair is below `rel_tol` times its value, when the Ritz
/// value changed by less than [`SETTLED`] relative in the last step (its error is of the order
/// of the residual squared over the gap, so it settles long before the residual when the top
/// eigenvalues cluster), after `max_steps` steps, or when the Krylov space is exhausted (then
/// exact).
pub fn largest_eigenvalue(
    n: usize,
    apply: impl FnMut(&[f64], &mut [f64]),
    max_steps: usize,
    rel_tol: f64,
) -> Extreme {
    if n == 0 {
        return Extreme {
            value: 0.0,
            residual: 0.0,
            steps: 0,
        };
    }
    let mut best = Extreme {
        value: 0.0,
        residual: f64::INFINITY,
        steps: 0,
    };
    let exhausted = lanczos(start_vector(n), apply, max_steps, |vals, res| {
        let (theta, r) = (vals[vals.len() - 1], res[res.len() - 1]);
        let kk = vals.len();
        let settled = kk > 2 && (theta - best.value).abs() <= SETTLED * theta.abs();
        best = Extreme {
            value: theta,
            residual: r,
            steps: kk,
        };
        r <= rel_tol * theta.abs() || settled
    });
    if exhausted {
        best.residual = 0.0;
    }
    best
}

/// The `count` eigenvalues of largest magnitude of the symmetric operator `apply` on the
/// Krylov space of `start` (which should lie in the operator's range when it has a null
/// space: pass Op s for some s), largest |θ| first; fewer when that space has fewer
/// dimensions. Stopped as [`largest_eigenvalue`]: when every one of them has a residual below
/// `rel_tol` of its magnitude or has settled, after `max_steps` steps, or when the space is
/// exhausted (then exact, residual 0). `None` for a zero start vector.
pub fn largest_magnitude_eigenvalues(
    start: Vec<f64>,
    apply: impl FnMut(&[f64], &mut [f64]),
    count: usize,
    max_steps: usize,
    rel_tol: f64,
) -> Option<Vec<Extreme>> {
    let ns = dot(&start, &start).sqrt();
    if !(ns > 0.0 && ns.is_finite()) || count == 0 {
        return None;
    }
    let start: Vec<f64> = start.iter().map(|x| x / ns).collect();
    let mut best: Vec<Extreme> = Vec::new();
    let exhausted = lanczos(start, apply, max_steps, |vals, res| {
        let mut order: Vec<usize> = (0..vals.len()).collect();
        order.sort_by(|&i, &j| vals[j].abs().total_cmp(&vals[i].abs()));
        order.truncate(count);
        let now: Vec<Extreme> = order
            .iter()
            .map(|&i| Extreme {
                value: vals[i],
                residual: res[i],
                steps: vals.len(),
            })
            .collect();
        let settled = now.len() == count
            && best.len() == count
            && now
                .iter()
                .zip(&best)
                .all(|(a, b)| (a.value - b.value).abs() <= SETTLED * a.value.abs());
        let converged =
            now.len() == count && now.iter().all(|e| e.residual <= rel_tol * e.value.abs());
        best = now;
        converged || settled
    });
    if exhausted {
        best.iter_mut().for_each(|e| e.residual = 0.0);
    }
    Some(best)
}

/// Lanczos with full reorthogonalisation from the unit vector `start`: after each step,
/// `done(θ, r)` sees the Ritz values θ (ascending) of the tridiagonal matrix and their
/// residuals r; the run ends when it returns true, after `max_steps` steps, or when the Krylov
/// space is exhausted (returned: true).
fn lanczos(
    start: Vec<f64>,
    mut apply: impl FnMut(&[f64], &mut [f64]),
    max_steps: usize,
    mut done: impl FnMut(&[f64], &[f64]) -> bool,
) -> bool {
    let n = start.len();
    let mut basis: Vec<Vec<f64>> = vec![start];
    let (mut alpha, mut beta): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut w = vec![0.0; n];
    for k in 0..max_steps.clamp(1, n.max(1)) {
        apply(&basis[k], &mut w);
        let a = dot(&w, &basis[k]);
        alpha.push(a);
        // full reorthogonalisation (twice is enough)
        for _ in 0..2 {
            for q in &basis {
                let c = dot(&w, q);
                w.iter_mut().zip(q).for_each(|(wi, qi)| *wi -= c * qi);
            }
        }
        let b = dot(&w, &w).sqrt();
        // the tridiagonal T_k and its eigenpairs
        let kk = k + 1;
        let t = faer::Mat::from_fn(kk, kk, |i, j| {
            if i == j {
                alpha[i]
            } else if i == j + 1 {
                beta[j]
            } else if j == i + 1 {
                beta[i]
            } else {
                0.0
            }
        });
        if let Ok((vals, vecs)) = crate::linalg::sym_eigen_seq(t.as_ref()) {
            let res: Vec<f64> = (0..kk).map(|i| (b * vecs[(kk - 1, i)]).abs()).collect();
            if done(&vals, &res) {
                return false;
            }
        }
        if b <= f64::EPSILON * alpha.iter().fold(0.0f64, |m, x| m.max(x.abs())) || kk == n {
            return true;
        }
        beta.push(b);
        basis.push(w.iter().map(|x| x / b).collect());
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn largest_magnitude_eigenvalues_of_a_diagonal_operator_with_a_null_space() {
        // diag(−5, 0.1, 3, 4, 0, 0, …): the three of largest magnitude are −5, 4, 3
        let d: Vec<f64> = [-5.0, 0.1, 3.0, 4.0]
            .into_iter()
            .chain(std::iter::repeat_n(0.0, 36))
            .collect();
        let apply = |x: &[f64], y: &mut [f64]| {
            y.iter_mut()
                .zip(x)
                .zip(&d)
                .for_each(|((yi, xi), di)| *yi = di * xi);
        };
        let mut start = vec![0.0; d.len()];
        apply(&start_vector(d.len()), &mut start);
        let e = largest_magnitude_eigenvalues(start, apply, 3, 40, 1e-12).unwrap();
        let v: Vec<f64> = e.iter().map(|e| e.value).collect();
        assert_eq!(v.len(), 3);
        for (a, b) in v.iter().zip([-5.0, 4.0, 3.0]) {
            assert!((a - b).abs() < 1e-12, "{v:?}");
        }
        // five nonzero directions asked, four exist: the space is exhausted with four
        let e = largest_magnitude_eigenvalues(
            vec![1.0, 1.0, 1.0, 1.0],
            |x, y| {
                y.copy_from_slice(x);
                y[0] *= 2.0;
            },
            5,
            40,
            1e-12,
        )
        .unwrap();
        assert!(e.len() <= 4 && e.iter().all(|e| e.residual == 0.0));
        assert!((e[0].value - 2.0).abs() < 1e-12);
    }
}
