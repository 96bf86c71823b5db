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
fn start_vector(n: usize) -> Vec<f64> {
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
    mut apply: impl FnMut(&[f64], &mut [f64]),
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
    let mut basis: Vec<Vec<f64>> = vec![start_vector(n)];
    let (mut alpha, mut beta): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut w = vec![0.0; n];
    let mut best = Extreme {
        value: 0.0,
        residual: f64::INFINITY,
        steps: 0,
    };
    for k in 0..max_steps.clamp(1, n) {
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
        // the tridiagonal T_k and its largest eigenpair
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
            let theta = vals[kk - 1];
            let res = (b * vecs[(kk - 1, kk - 1)]).abs();
            let settled = kk > 2 && (theta - best.value).abs() <= SETTLED * theta.abs();
            best = Extreme {
                value: theta,
                residual: res,
                steps: kk,
            };
            if res <= rel_tol * theta.abs() || settled {
                break;
            }
        }
        if b <= f64::EPSILON * alpha.iter().fold(0.0f64, |m, x| m.max(x.abs())) || kk == n {
            best.residual = 0.0;
            break;
        }
        beta.push(b);
        basis.push(w.iter().map(|x| x / b).collect());
    }
    best
}
