//! Sparse LU with partial pivoting for a sequence of matrices with one sparsity structure
//! (the Newton matrices of one static solve), with fast refactorisation.
//!
//! - Column order, computed once per structure: when every diagonal entry is structurally
//!   present, AMD on the pattern of A + Aᵀ with a preference for diagonal pivots (UMFPACK's
//!   symmetric strategy: a stiffness-like matrix then factors like a Cholesky factorisation,
//!   with little fill); otherwise COLAMD with plain partial pivoting.
//! - [`SparseLu::factor`]: left-looking Gilbert–Peierls LU with partial pivoting (the largest
//!   entry of each column, or the diagonal entry when it is at least [`DIAG_TOL`] times the
//!   largest); it records the row pivot order and the structure of L and U.
//! - [`SparseLu::refactor`]: the next matrix with the same row pivot order and therefore the
//!   same structure of L and U: no graph search, only the arithmetic over precomputed index
//!   lists (the "refactor" of KLU). Each pivot is checked against the other entries of its
//!   column (threshold [`PIVOT_TOL`]); when a pivot became too small, the refactorisation
//!   reports it and the caller factors with pivoting again.
//!
//! Indices: `A` is n × n in CSC form. Steps k = 0 … n−1 are the columns in COLAMD order;
//! row `i` of A is eliminated at step `pinv[i]`. L and U are stored by columns in step
//! numbering (L unit lower triangular without its diagonal, U strictly upper with the diagonal
//! apart).

mod lu;
pub mod rank;
mod rows;
mod symmetric;
pub use rows::{share_rows, ColRows};

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::{amd, colamd};
use faer::sparse::SymbolicSparseColMatRef;

/// Symmetric strategy: the diagonal entry is the pivot when |a_kk| ≥ DIAG_TOL max |column|.
pub const DIAG_TOL: f64 = 1e-3;

/// Smallest accepted |pivot| / max |column entry| when refactoring with the previous pivots.
/// Refactoring reports the smallest ratio it met; the caller should check the accuracy of the
/// solution (e.g. its backward error) when that is well below 1.
pub const PIVOT_TOL: f64 = 1e-10;

/// Why a factorisation failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LuFailure {
    /// A column has no nonzero candidate pivot (singular matrix).
    Singular,
    /// Refactorisation only: a pivot fell below the threshold; factor with pivoting instead.
    PivotTooSmall,
}

/// LU factors of one sparsity structure (see the module docs).
#[derive(Debug, Clone)]
pub struct SparseLu {
    n: usize,
    /// Column order: step k factors column `q[k]` of A (u32, as the row indices: 4 bytes per
    /// unknown less, as `pinv`).
    q: Vec<u32>,
    /// Symmetric strategy: prefer the diagonal entry as pivot.
    diag_pref: bool,
    /// Row i of A is pivot row of step `pinv[i]` (valid after a successful factorisation).
    pinv: Vec<u32>,
    l_ptr: Vec<usize>,
    /// Row steps of L's entries (u32: half the memory traffic of the solves), parallel to
    /// `l_val`, or shared between columns when `l_start` is set.
    l_idx: Vec<u32>,
    /// When not empty ([`SparseLu::share_l_rows`]): the rows of column k of L are
    /// `l_idx[l_start[k]..]`, as many as its values. A column whose rows are those of the
    /// column before it without the first (the columns of a supernode: the six of a beam
    /// node) reads them from that column's list, one entry on.
    l_start: Vec<u32>,
    l_val: Vec<f64>,
    u_ptr: Vec<usize>,
    /// Strictly upper entries, ascending step order within each column.
    u_idx: Vec<u32>,
    u_val: Vec<f64>,
    u_diag: Vec<f64>,
    /// The step of every entry of A's row indices (`pinv[row_idx[p]]`, CSC order) for
    /// [`SparseLu::refactor`]; empty until the first refactorisation after the pivot order is
    /// set.
    a_step: Vec<u32>,
    /// Dense work vector of the factorisations (kept zero between uses; empty until one runs,
    /// and released after each L D Lᵀ refactorisation) and DFS work (empty until LU with pivoting
    /// runs).
    work: Vec<f64>,
    mark: Vec<usize>,
    stack: Vec<usize>,
    pstack: Vec<usize>,
    reach: Vec<usize>,
    factored: bool,
    /// The factors are L D Lᵀ (from [`SparseLu::refactor_symmetric`]): U is not stored.
    symmetric_factors: bool,
    /// Lower triangle of A in pivot order (see [`SparseLu::lower_layout`]): entries of step k
    /// are `lower_row[lower_ptr[k]..lower_ptr[k + 1]]` (pivot numbering, ≥ k).
    lower_ptr: Vec<usize>,
    lower_row: Vec<u32>,
    /// Smallest accepted |pivot| / max |column entry| of [`SparseLu::refactor_symmetric`]
    /// ([`PIVOT_TOL`] unless set).
    pivot_tol: f64,
    /// Number of negative pivots of the last [`SparseLu::refactor_symmetric`].
    n_negative: usize,
    /// The structure of the factors is that of diagonal pivots ([`SparseLu::set_diagonal_pivots`]),
    /// so [`SparseLu::refactor_symmetric`] can run, also after a failed attempt.
    diagonal_structure: bool,
}

/// A row index of a CSC structure: `usize`, or `u32` where the structure is large and kept (the
/// saddle-point problem of `modes`: 4 bytes per entry instead of 8).
pub trait RowIndex: Copy + PartialOrd + Send + Sync + 'static {
    /// The index as usize.
    fn ix(self) -> usize;
    /// The slice as usize indices (borrowed when it is one), for faer's orderings.
    fn as_usize(s: &[Self]) -> std::borrow::Cow<'_, [usize]>;
}

impl RowIndex for usize {
    fn ix(self) -> usize {
        self
    }
    fn as_usize(s: &[Self]) -> std::borrow::Cow<'_, [usize]> {
        std::borrow::Cow::Borrowed(s)
    }
}

impl RowIndex for u32 {
    fn ix(self) -> usize {
        self as usize
    }
    fn as_usize(s: &[Self]) -> std::borrow::Cow<'_, [usize]> {
        std::borrow::Cow::Owned(s.iter().map(|&r| r as usize).collect())
    }
}

/// Approximate minimum degree ordering (faer's AMD) of a structurally symmetric n × n CSC
/// pattern: the permutation q (position → index) and its inverse.
pub(crate) fn amd_order(
    n: usize,
    col_ptr: &[usize],
    row_idx: &[usize],
) -> Result<(Vec<usize>, Vec<usize>), String> {
    let (mut q, mut q_inv) = (vec![0usize; n], vec![0usize; n]);
    if n == 0 {
        return Ok((q, q_inv));
    }
    let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx);
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(n, row_idx.len()))
        .map_err(|e| format!("out of memory: {e:?}"))?;
    amd::order(
        &mut q,
        &mut q_inv,
        sym,
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| format!("ordering failed: {e:?}"))?;
    Ok((q, q_inv))
}

/// Residual b − A z of a CSC matrix A and the componentwise backward error
/// max_i |b − A z|_i / (|A| |z| + |b|)_i (infinite when it is NaN).
pub(crate) fn csc_residual<R: RowIndex>(
    cp: &[usize],
    ri: &[R],
    v: &[f64],
    z: &[f64],
    b: &[f64],
) -> (Vec<f64>, f64) {
    residual_of(|j| (cp[j], &ri[cp[j]..cp[j + 1]]), |p| v[p], z, b, false)
}

/// [`csc_residual`] of a symmetric matrix of which one triangle is stored (each entry off the
/// diagonal stands for itself and its mirror), with the value of entry p given by `value(p)`
/// (a matrix whose values are formed on the fly, as K − σM).
pub(crate) fn csc_sym_residual_with<P: RowIndex>(
    a: ColRows<'_, P>,
    value: impl Fn(usize) -> f64,
    z: &[f64],
    b: &[f64],
) -> (Vec<f64>, f64) {
    residual_of(|j| (a.first(j), a.of(j)), value, z, b, true)
}

/// b − A z and its componentwise backward error, column j of A given by `column(j)` (the
/// position of its first value, its rows); `mirror`: each stored entry off the diagonal also
/// stands for its mirror (one triangle of a symmetric matrix).
fn residual_of<'a, R: RowIndex>(
    column: impl Fn(usize) -> (usize, &'a [R]),
    value: impl Fn(usize) -> f64,
    z: &[f64],
    b: &[f64],
    mirror: bool,
) -> (Vec<f64>, f64) {
    let mut res = b.to_vec();
    let mut scale: Vec<f64> = b.iter().map(|x| x.abs()).collect();
    for (j, &zj) in z.iter().enumerate() {
        let (first, rows) = column(j);
        for (p, r) in (first..).zip(rows) {
            let (v, r) = (value(p), r.ix());
            let a = v * zj;
            res[r] -= a;
            scale[r] += a.abs();
            if mirror && r != j {
                let a = v * z[r];
                res[j] -= a;
                scale[j] += a.abs();
            }
        }
    }
    let be = backward_error(&res, &scale);
    (res, be)
}

/// max_i |r_i| / s_i (|r_i| where s_i = 0; infinite when it is NaN).
fn backward_error(res: &[f64], scale: &[f64]) -> f64 {
    res.iter().zip(scale).fold(0.0, |m: f64, (r, s)| {
        let e = if *s > 0.0 { r.abs() / s } else { r.abs() };
        if e.is_nan() {
            f64::INFINITY
        } else {
            m.max(e)
        }
    })
}

impl SparseLu {
    /// Analyse the structure (COLAMD column order) of an n × n CSC matrix.
    pub fn new<R: RowIndex>(n: usize, col_ptr: &[usize], row_idx: &[R]) -> Result<Self, String> {
        check_size(n)?;
        let nnz = col_ptr[n];
        let row_idx = R::as_usize(&row_idx[..nnz]);
        let diag_pref = (0..n).all(|j| {
            row_idx[col_ptr[j]..col_ptr[j + 1]]
                .binary_search(&j)
                .is_ok()
        });
        let q = if diag_pref {
            amd_order(n, col_ptr, &row_idx[..nnz])?.0
        } else {
            let sym = SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, &row_idx[..nnz]);
            let (mut q, mut q_inv) = (vec![0usize; n], vec![0usize; n]);
            let mut mem = MemBuffer::try_new(colamd::order_scratch::<usize>(n, n, nnz))
                .map_err(|e| format!("out of memory: {e:?}"))?;
            colamd::order(
                &mut q,
                &mut q_inv,
                sym,
                Default::default(),
                MemStack::new(&mut mem),
            )
            .map_err(|e| format!("column ordering failed: {e:?}"))?;
            q
        };
        Ok(Self::unfactored(
            n,
            q.iter().map(|&c| c as u32).collect(),
            diag_pref,
        ))
    }

    /// The symmetric strategy with a given column (and pivot) order `q` (step k factors column
    /// `q[k]`), for a structurally symmetric matrix with every diagonal entry present: for
    /// example a saddle-point matrix whose constraint rows are ordered after the coordinates
    /// they couple, so that L D Lᵀ with diagonal pivots exists. Follow with
    /// [`SparseLu::set_diagonal_pivots`].
    pub fn with_order(n: usize, q: Vec<u32>) -> Result<Self, String> {
        check_size(n)?;
        let mut seen = vec![false; n];
        if q.len() != n
            || q.iter().any(|&c| {
                let c = c as usize;
                c >= n || std::mem::replace(&mut seen[c], true)
            })
        {
            return Err("the column order is not a permutation".into());
        }
        Ok(Self::unfactored(n, q, true))
    }

    /// No factors yet, for the column order `q` (step k factors column `q[k]`).
    fn unfactored(n: usize, q: Vec<u32>, diag_pref: bool) -> Self {
        Self {
            n,
            q,
            diag_pref,
            pinv: vec![NO_STEP; n],
            l_ptr: vec![0; n + 1],
            l_idx: Vec::new(),
            l_start: Vec::new(),
            l_val: Vec::new(),
            u_ptr: vec![0; n + 1],
            u_idx: Vec::new(),
            u_val: Vec::new(),
            u_diag: vec![0.0; n],
            a_step: Vec::new(),
            work: Vec::new(),
            // (the search work of LU with pivoting, made when it runs: the symmetric strategy
            // needs none of it beside its factors)
            mark: Vec::new(),
            stack: Vec::new(),
            pstack: Vec::new(),
            reach: Vec::new(),
            factored: false,
            symmetric_factors: false,
            lower_ptr: Vec::new(),
            lower_row: Vec::new(),
            pivot_tol: PIVOT_TOL,
            n_negative: 0,
            diagonal_structure: false,
        }
    }

    /// Set the smallest accepted |pivot| / max |column entry| of
    /// [`SparseLu::refactor_symmetric`] (default [`PIVOT_TOL`]). Zero accepts every non-zero
    /// finite pivot: for L D Lᵀ of a matrix that is known to be factorable with diagonal pivots
    /// (positive definite, or quasi-definite in a suitable order) and whose inertia is wanted;
    /// the caller then checks the accuracy of its solutions.
    pub fn set_pivot_tolerance(&mut self, tol: f64) {
        self.pivot_tol = tol;
    }

    /// Number of negative pivots of the last successful [`SparseLu::refactor_symmetric`]: by
    /// Sylvester's law of inertia, the number of negative eigenvalues of the matrix.
    pub fn negative_pivots(&self) -> usize {
        self.n_negative
    }

    /// Whether the symmetric strategy (AMD, diagonal pivots preferred) is in use.
    pub fn symmetric(&self) -> bool {
        self.diag_pref
    }

    /// Number of nonzeros of L (without the unit diagonal) and U (with the diagonal).
    pub fn nnz(&self) -> (usize, usize) {
        (self.l_ptr[self.n], self.u_idx.len() + self.n)
    }
}

impl SparseLu {
    /// Shares the row lists of L's supernodes ([`share_rows`]): the row indices of a beam
    /// model's factor take a quarter of the room. Only the symmetric refactorisation and the
    /// solves read L afterwards.
    fn share_l_rows(&mut self) {
        if let Some((idx, start)) = share_rows(&self.l_ptr, &self.l_idx) {
            self.l_idx = idx;
            self.l_start = start;
        }
    }
}

/// `pinv` of a row not yet pivotal.
const NO_STEP: u32 = u32::MAX;

/// The step of a row from `pinv`, `usize::MAX` for none.
#[inline]
fn step(s: u32) -> usize {
    if s == NO_STEP {
        usize::MAX
    } else {
        s as usize
    }
}

/// The factors store their row and column indices as u32 (`u32::MAX` marks no step).
fn check_size(n: usize) -> Result<(), String> {
    if n >= u32::MAX as usize {
        return Err(format!(
            "{n} unknowns: too many for the sparse LU (at most 2^32 - 2)"
        ));
    }
    Ok(())
}

/// Longest slice that [`sort_small`] sorts by insertion.
const INSERTION_MAX: usize = 32;

/// Sort a slice ascending: by insertion when it is short (the index lists of one column: a few
/// entries, often nearly sorted, where the general sort's setup and code size cost more than
/// the sorting), else `sort_unstable`.
pub fn sort_small<T: Ord + Copy>(v: &mut [T]) {
    if v.len() > INSERTION_MAX {
        v.sort_unstable();
        return;
    }
    sort_small_by(v, |a, b| a < b);
}

/// Stable insertion sort by `less` (for short slices; quadratic in the length).
pub fn sort_small_by<T>(v: &mut [T], mut less: impl FnMut(&T, &T) -> bool) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && less(&v[j], &v[j - 1]) {
            v.swap(j, j - 1);
            j -= 1;
        }
    }
}

/// Sort the entries of every column (`ptr`: column starts, n + 1 of them) by index.
fn sort_columns(ptr: &[usize], idx: &mut [u32], val: &mut [f64]) {
    let mut pairs: Vec<(u32, f64)> = Vec::new();
    for col in ptr.windows(2) {
        let (lo, hi) = (col[0], col[1]);
        pairs.clear();
        pairs.extend((lo..hi).map(|p| (idx[p], val[p])));
        pairs.sort_unstable_by_key(|p| p.0);
        for (o, (i, v)) in pairs.iter().enumerate() {
            idx[lo + o] = *i;
            val[lo + o] = *v;
        }
    }
}

#[cfg(test)]
mod tests;
