//! Facade over the dense solvers (faer), so the backend can change without touching the
//! algorithms.

use faer::{Mat, MatRef};

/// Full singular value decomposition A = U Σ Vᵀ (paper eq. (11)).
#[derive(Clone, Debug)]
pub struct Svd {
    /// Singular values, non-increasing (min(m, n) of them).
    pub s: Vec<f64>,
    /// Left singular vectors, m × m.
    pub U: Mat<f64>,
    /// Right singular vectors, n × n.
    pub V: Mat<f64>,
}

/// Numerical failure of a dense solver.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinalgError {
    /// The SVD iteration did not converge.
    #[error("the singular value decomposition of the {rows} × {cols} matrix did not converge")]
    SvdNoConvergence {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// The matrix holds NaN or infinite entries.
    #[error("the {what} holds a non-finite entry at ({row}, {col})")]
    NonFinite {
        /// Which matrix.
        what: &'static str,
        /// Row.
        row: usize,
        /// Column.
        col: usize,
    },
}

/// The default memory limit of every dense analysis (the kinematic check, the linearised
/// statics, the dense modal analysis and state space): 4 GiB.
pub const DEFAULT_MAX_DENSE_BYTES: u64 = 4 << 30;

const GIB: f64 = (1u64 << 30) as f64;

/// A dense analysis whose matrices would need more memory than its limit allows; found before
/// anything large is allocated ([`check_dense_bytes`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "the dense {what} of this model ({dof} degrees of freedom) needs about {:.1} GiB for its \
     matrices, above the limit of {:.1} GiB (memory grows with the square of the degrees of \
     freedom, time with the cube); {remedy}",
    *bytes as f64 / GIB,
    *limit as f64 / GIB
)]
pub struct DenseTooLarge {
    /// The analysis ("modal analysis", "state space", …).
    pub what: &'static str,
    /// Its number of unknowns.
    pub dof: usize,
    /// Bytes it needs (an estimate of the largest set of matrices alive at once, saturated at
    /// `u64::MAX`).
    pub bytes: u64,
    /// The limit.
    pub limit: u64,
    /// What to do instead, in neutral words.
    pub remedy: &'static str,
}

/// The size guard of a dense analysis: `bytes` (computed in u128, so that it cannot overflow)
/// against `limit`.
pub fn check_dense_bytes(
    what: &'static str,
    remedy: &'static str,
    dof: usize,
    bytes: u128,
    limit: u64,
) -> Result<(), DenseTooLarge> {
    let bytes = u64::try_from(bytes).unwrap_or(u64::MAX);
    if bytes > limit {
        return Err(DenseTooLarge {
            what,
            dof,
            bytes,
            limit,
            remedy,
        });
    }
    Ok(())
}

/// The parallelism of the dense SVD: a fixed split into two parts, whatever the number of
/// threads, so that its results are bit-identical for any number of threads (faer splits the
/// reductions of its bidiagonalisation by the degree it is given, not by the threads of the
/// pool; with `Par::rayon(0)`, the pool's size, `check --json` differed at 1e-14 between one
/// and two threads). On one thread the two parts run one after the other.
pub const SVD_PAR: faer::Par = faer::Par::Rayon(std::num::NonZeroUsize::MIN.saturating_add(1));

/// Bytes of the faer workspace of a full SVD of an m × n matrix (U m × m and V n × n);
/// `usize::MAX` if that overflows. Call it only for sizes whose factors fit in memory.
pub fn svd_scratch_bytes(m: usize, n: usize) -> usize {
    use faer::linalg::svd::{svd_scratch, ComputeSvdVectors};
    if m == 0 || n == 0 {
        return 0;
    }
    svd_scratch::<f64>(
        m,
        n,
        ComputeSvdVectors::Full,
        ComputeSvdVectors::Full,
        SVD_PAR,
        Default::default(),
    )
    .unaligned_bytes_required()
}

/// Full SVD with U (m × m) and V (n × n); empty dimensions give identity factors. Sequential
/// ([`SVD_PAR`]): the same bits for any number of threads.
pub fn svd(a: MatRef<'_, f64>, what: &'static str) -> Result<Svd, LinalgError> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::svd::{svd as faer_svd, svd_scratch, ComputeSvdVectors};
    let (m, n) = (a.nrows(), a.ncols());
    for j in 0..n {
        for i in 0..m {
            if !a[(i, j)].is_finite() {
                return Err(LinalgError::NonFinite {
                    what,
                    row: i,
                    col: j,
                });
            }
        }
    }
    if m == 0 || n == 0 {
        return Ok(Svd {
            s: Vec::new(),
            U: Mat::identity(m, m),
            V: Mat::identity(n, n),
        });
    }
    let no_conv = LinalgError::SvdNoConvergence { rows: m, cols: n };
    let mut s = faer::diag::Diag::<f64>::zeros(m.min(n));
    let mut u = Mat::<f64>::zeros(m, m);
    let mut v = Mat::<f64>::zeros(n, n);
    let mut mem = MemBuffer::try_new(svd_scratch::<f64>(
        m,
        n,
        ComputeSvdVectors::Full,
        ComputeSvdVectors::Full,
        SVD_PAR,
        Default::default(),
    ))
    .map_err(|_| no_conv.clone())?;
    faer_svd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        Some(v.as_mut()),
        SVD_PAR,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| no_conv)?;
    let d = s.column_vector();
    Ok(Svd {
        s: (0..m.min(n)).map(|i| d[i]).collect(),
        U: u,
        V: v,
    })
}

/// Singular values only (descending), sequential ([`SVD_PAR`]).
pub fn singular_values(a: MatRef<'_, f64>) -> Result<Vec<f64>, LinalgError> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::svd::{svd as faer_svd, svd_scratch, ComputeSvdVectors};
    let (m, n) = (a.nrows(), a.ncols());
    if m == 0 || n == 0 {
        return Ok(Vec::new());
    }
    let no_conv = LinalgError::SvdNoConvergence { rows: m, cols: n };
    let mut s = faer::diag::Diag::<f64>::zeros(m.min(n));
    let mut mem = MemBuffer::try_new(svd_scratch::<f64>(
        m,
        n,
        ComputeSvdVectors::No,
        ComputeSvdVectors::No,
        SVD_PAR,
        Default::default(),
    ))
    .map_err(|_| no_conv.clone())?;
    faer_svd(
        a,
        s.as_mut(),
        None,
        None,
        SVD_PAR,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| no_conv)?;
    let d = s.column_vector();
    Ok((0..m.min(n)).map(|i| d[i]).collect())
}

/// Number of singular values above `tol`.
pub fn numerical_rank(s: &[f64], tol: f64) -> usize {
    s.iter().filter(|&&v| v > tol).count()
}

/// Choose `k` columns of `a` by QR with column pivoting (Businger–Golub): at each step the
/// column with the largest norm orthogonal to the columns already chosen. Returns their indices
/// in the order chosen; stops early when the remaining columns vanish (below `tol`).
pub fn pivot_columns(a: MatRef<'_, f64>, k: usize, tol: f64) -> Vec<usize> {
    let (m, n) = (a.nrows(), a.ncols());
    let mut w = a.to_owned();
    let mut chosen = Vec::new();
    for _ in 0..k.min(n) {
        // column of largest remaining norm
        let mut best = None;
        let mut best_norm = tol;
        for j in 0..n {
            if chosen.contains(&j) {
                continue;
            }
            let nj = (0..m).map(|i| w[(i, j)] * w[(i, j)]).sum::<f64>().sqrt();
            if nj > best_norm * (1.0 + 1e-12) {
                best_norm = nj;
                best = Some(j);
            }
        }
        let Some(p) = best else { break };
        chosen.push(p);
        // orthogonalise the others against it (modified Gram–Schmidt)
        let q: Vec<f64> = (0..m).map(|i| w[(i, p)] / best_norm).collect();
        for j in 0..n {
            let c: f64 = (0..m).map(|i| q[i] * w[(i, j)]).sum();
            for i in 0..m {
                w[(i, j)] -= c * q[i];
            }
        }
    }
    chosen
}

/// Why a symmetric-definite eigenproblem failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EigenError {
    /// B is not positive definite.
    #[error("the {what} matrix is not positive definite (pivot {index}): {hint}")]
    NotPositiveDefinite {
        /// Which matrix.
        what: &'static str,
        /// Failing pivot.
        index: usize,
        /// What it means for the user.
        hint: &'static str,
    },
    /// The eigen iteration did not converge.
    #[error("the symmetric eigenvalue iteration did not converge")]
    NoConvergence,
}

/// Solve A v = ν B v for symmetric A and symmetric positive definite B (the `sygv` problem,
/// which faer lacks): B = L Lᵀ, C = L⁻¹ A L⁻ᵀ, C y = ν y, v = L⁻ᵀ y. Eigenvalues ascending,
/// vectors B-orthonormal (vᵀ B v = 1) as columns.
pub fn sym_def_eigen(
    a: MatRef<'_, f64>,
    b: MatRef<'_, f64>,
    what: &'static str,
    hint: &'static str,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    use faer::linalg::triangular_solve::{
        solve_lower_triangular_in_place, solve_upper_triangular_in_place,
    };
    use faer::{Par, Side};
    let n = a.nrows();
    if n == 0 {
        return Ok((Vec::new(), Mat::zeros(0, 0)));
    }
    let llt = b
        .llt(Side::Lower)
        .map_err(|e| EigenError::NotPositiveDefinite {
            what,
            index: match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => index,
            },
            hint,
        })?;
    let l = llt.L();
    // W = L⁻¹ A, C = L⁻¹ Wᵀ (A symmetric)
    let mut w = a.to_owned();
    solve_lower_triangular_in_place(l, w.as_mut(), Par::Seq);
    let mut c = w.transpose().to_owned();
    solve_lower_triangular_in_place(l, c.as_mut(), Par::Seq);
    let c = Mat::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    let evd = c
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| EigenError::NoConvergence)?;
    let s = evd.S().column_vector();
    let values: Vec<f64> = (0..n).map(|i| s[i]).collect();
    let mut v = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), v.as_mut(), Par::Seq);
    Ok((values, v))
}

/// All eigenpairs of a small symmetric matrix (its lower triangle is read) on the calling
/// thread: eigenvalues ascending, orthonormal eigenvectors as columns. For the projected
/// matrices of iterative eigen solvers, where handing a 30 × 30 problem to worker threads
/// costs more than solving it.
pub fn sym_eigen_seq(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors};
    let n = a.nrows();
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let mut u = Mat::<f64>::zeros(n, n);
    let par = faer::Par::Seq;
    let mut mem = MemBuffer::try_new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::Yes,
        par,
        Default::default(),
    ))
    .map_err(|_| EigenError::NoConvergence)?;
    self_adjoint_evd(
        a,
        s.as_mut(),
        Some(u.as_mut()),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| EigenError::NoConvergence)?;
    let d = s.column_vector();
    Ok(((0..n).map(|i| d[i]).collect(), u))
}

/// The eigenvalues (ascending) of a small symmetric matrix (its lower triangle is read) on the
/// calling thread, without eigenvectors.
pub fn sym_eigenvalues_seq(a: MatRef<'_, f64>) -> Result<Vec<f64>, EigenError> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self_adjoint_evd, self_adjoint_evd_scratch, ComputeEigenvectors};
    let n = a.nrows();
    let mut s = faer::diag::Diag::<f64>::zeros(n);
    let par = faer::Par::Seq;
    let mut mem = MemBuffer::try_new(self_adjoint_evd_scratch::<f64>(
        n,
        ComputeEigenvectors::No,
        par,
        Default::default(),
    ))
    .map_err(|_| EigenError::NoConvergence)?;
    self_adjoint_evd(
        a,
        s.as_mut(),
        None,
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| EigenError::NoConvergence)?;
    let d = s.column_vector();
    let mut v: Vec<f64> = (0..n).map(|i| d[i]).collect();
    v.sort_by(f64::total_cmp);
    Ok(v)
}

/// True when every entry of `m` is finite (faer's `norm_max` skips NaN, so it cannot tell).
pub fn all_finite(m: &Mat<f64>) -> bool {
    (0..m.ncols()).all(|j| (0..m.nrows()).all(|i| m[(i, j)].is_finite()))
}
