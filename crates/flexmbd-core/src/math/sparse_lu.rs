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
    /// Column order: step k factors column `q[k]` of A.
    q: Vec<usize>,
    /// Symmetric strategy: prefer the diagonal entry as pivot.
    diag_pref: bool,
    /// Row i of A is pivot row of step `pinv[i]` (valid after a successful factorisation).
    pinv: Vec<usize>,
    l_ptr: Vec<usize>,
    l_idx: Vec<usize>,
    l_val: Vec<f64>,
    u_ptr: Vec<usize>,
    /// Strictly upper entries, ascending step order within each column.
    u_idx: Vec<usize>,
    u_val: Vec<f64>,
    u_diag: Vec<f64>,
    /// Dense work vector (kept zero between uses) and DFS work.
    work: Vec<f64>,
    mark: Vec<usize>,
    stack: Vec<usize>,
    pstack: Vec<usize>,
    reach: Vec<usize>,
    factored: bool,
    /// The factors are L D Lᵀ (from [`SparseLu::refactor_symmetric`]): U is not stored.
    symmetric_factors: bool,
    /// Symmetric refactorisation work: next entry of each column of L.
    next: Vec<usize>,
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
pub(crate) fn csc_residual(
    cp: &[usize],
    ri: &[usize],
    v: &[f64],
    z: &[f64],
    b: &[f64],
) -> (Vec<f64>, f64) {
    let mut res = b.to_vec();
    let mut scale: Vec<f64> = b.iter().map(|x| x.abs()).collect();
    for (j, &zj) in z.iter().enumerate() {
        for p in cp[j]..cp[j + 1] {
            res[ri[p]] -= v[p] * zj;
            scale[ri[p]] += (v[p] * zj).abs();
        }
    }
    let be = res.iter().zip(&scale).fold(0.0, |m: f64, (r, s)| {
        let e = if *s > 0.0 { r.abs() / s } else { r.abs() };
        if e.is_nan() {
            f64::INFINITY
        } else {
            m.max(e)
        }
    });
    (res, be)
}

impl SparseLu {
    /// Analyse the structure (COLAMD column order) of an n × n CSC matrix.
    pub fn new(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> Result<Self, String> {
        let nnz = col_ptr[n];
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
        Ok(Self::unfactored(n, q, diag_pref))
    }

    /// The symmetric strategy with a given column (and pivot) order `q` (step k factors column
    /// `q[k]`), for a structurally symmetric matrix with every diagonal entry present: for
    /// example a saddle-point matrix whose constraint rows are ordered after the coordinates
    /// they couple, so that L D Lᵀ with diagonal pivots exists. Follow with
    /// [`SparseLu::set_diagonal_pivots`].
    pub fn with_order(n: usize, q: Vec<usize>) -> Result<Self, String> {
        let mut seen = vec![false; n];
        if q.len() != n
            || q.iter()
                .any(|&c| c >= n || std::mem::replace(&mut seen[c], true))
        {
            return Err("the column order is not a permutation".into());
        }
        Ok(Self::unfactored(n, q, true))
    }

    /// No factors yet, for the column order `q` (step k factors column `q[k]`).
    fn unfactored(n: usize, q: Vec<usize>, diag_pref: bool) -> Self {
        Self {
            n,
            q,
            diag_pref,
            pinv: vec![usize::MAX; n],
            l_ptr: vec![0; n + 1],
            l_idx: Vec::new(),
            l_val: Vec::new(),
            u_ptr: vec![0; n + 1],
            u_idx: Vec::new(),
            u_val: Vec::new(),
            u_diag: vec![0.0; n],
            work: vec![0.0; n],
            mark: vec![usize::MAX; n],
            stack: Vec::with_capacity(n),
            pstack: Vec::with_capacity(n),
            reach: Vec::with_capacity(n),
            factored: false,
            symmetric_factors: false,
            next: Vec::new(),
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

    /// Symmetric strategy: set up the pivot order "all pivots on the diagonal" and its
    /// structure (that of a Cholesky factorisation), for [`refactor`] to take the values.
    /// It is the order that factor chooses for a column diagonally dominant matrix.
    ///
    /// [`refactor`]: SparseLu::refactor
    pub fn set_diagonal_pivots(&mut self, col_ptr: &[usize], row_idx: &[usize]) -> bool {
        if !self.diag_pref {
            return false;
        }
        let n = self.n;
        let symmetric_pattern = (0..n).all(|j| {
            row_idx[col_ptr[j]..col_ptr[j + 1]].iter().all(|&i| {
                row_idx[col_ptr[i]..col_ptr[i + 1]]
                    .binary_search(&j)
                    .is_ok()
            })
        });
        if symmetric_pattern {
            self.symbolic_cholesky(col_ptr, row_idx);
            self.diagonal_structure = true;
            return true;
        }
        let mut v = vec![1.0; col_ptr[n]];
        for j in 0..n {
            let (lo, hi) = (col_ptr[j], col_ptr[j + 1]);
            for p in lo..hi {
                if row_idx[p] == j {
                    v[p] = (hi - lo + 1) as f64;
                }
            }
        }
        let r = self.factor(col_ptr, row_idx, &v);
        if r.is_err() || (0..n).any(|k| self.pinv[self.q[k]] != k) {
            return false;
        }
        // L columns by ascending row (for the symmetric refactorisation)
        sort_columns(&self.l_ptr, &mut self.l_idx, &mut self.l_val);
        self.diagonal_structure = true;
        true
    }

    /// The structure of L and U for diagonal pivots of a structurally symmetric matrix: that
    /// of its Cholesky factor, from the elimination tree (row subtrees, as CSparse's
    /// `cs_schol`/`cs_ereach`), in time proportional to the nonzeros of L.
    fn symbolic_cholesky(&mut self, col_ptr: &[usize], row_idx: &[usize]) {
        const NONE: usize = usize::MAX;
        let n = self.n;
        for k in 0..n {
            self.pinv[self.q[k]] = k;
        }
        // elimination tree of the permuted matrix
        let mut parent = vec![NONE; n];
        let mut ancestor = vec![NONE; n];
        for k in 0..n {
            let col = self.q[k];
            for &r in &row_idx[col_ptr[col]..col_ptr[col + 1]] {
                let mut i = self.pinv[r];
                while i != NONE && i < k {
                    let next = ancestor[i];
                    ancestor[i] = k;
                    if next == NONE {
                        parent[i] = k;
                    }
                    i = next;
                }
            }
        }
        // row k of L (= column k of U): the nodes on the paths from the entries of row k of
        // the lower triangle up the tree to k
        let mark = &mut self.mark;
        mark.iter_mut().for_each(|m| *m = NONE);
        self.u_idx.clear();
        self.u_ptr[0] = 0;
        let mut l_count = vec![0usize; n];
        for k in 0..n {
            mark[k] = k;
            let start = self.u_idx.len();
            let col = self.q[k];
            for &r in &row_idx[col_ptr[col]..col_ptr[col + 1]] {
                let mut i = self.pinv[r];
                if i >= k {
                    continue;
                }
                while mark[i] != k {
                    mark[i] = k;
                    self.u_idx.push(i);
                    l_count[i] += 1;
                    i = parent[i];
                    debug_assert!(i != NONE);
                }
            }
            sort_small(&mut self.u_idx[start..]);
            self.u_ptr[k + 1] = self.u_idx.len();
        }
        // columns of L (rows ascending: k increases)
        self.l_ptr[0] = 0;
        for j in 0..n {
            self.l_ptr[j + 1] = self.l_ptr[j] + l_count[j];
        }
        let mut fill = self.l_ptr[..n].to_vec();
        self.l_idx.clear();
        self.l_idx.resize(self.l_ptr[n], 0);
        for k in 0..n {
            for p in self.u_ptr[k]..self.u_ptr[k + 1] {
                let j = self.u_idx[p];
                self.l_idx[fill[j]] = k;
                fill[j] += 1;
            }
        }
        self.l_val.clear();
        self.l_val.resize(self.l_idx.len(), 0.0);
        // U's values are made by `refactor` (L D Lᵀ does not store U)
        self.u_val.clear();
        self.u_diag.iter_mut().for_each(|d| *d = 1.0);
        self.factored = true;
        self.symmetric_factors = false;
    }

    /// After [`set_diagonal_pivots`]: the layout of the lower triangle of A in pivot order that
    /// [`refactor_symmetric`] reads (sequentially, half of A). Returns, for each of its entries,
    /// the position of that entry in the CSC arrays of A.
    ///
    /// [`set_diagonal_pivots`]: SparseLu::set_diagonal_pivots
    /// [`refactor_symmetric`]: SparseLu::refactor_symmetric
    pub fn lower_layout(&mut self, col_ptr: &[usize], row_idx: &[usize]) -> Vec<usize> {
        let n = self.n;
        // entries on or below the diagonal, to size the arrays exactly
        let count = (0..n)
            .map(|k| {
                let col = self.q[k];
                row_idx[col_ptr[col]..col_ptr[col + 1]]
                    .iter()
                    .filter(|&&r| self.pinv[r] >= k)
                    .count()
            })
            .sum();
        self.lower_ptr.clear();
        self.lower_row.clear();
        self.lower_ptr.reserve_exact(n + 1);
        self.lower_row.reserve_exact(count);
        self.lower_ptr.push(0);
        let mut slot = Vec::with_capacity(count);
        for k in 0..n {
            let col = self.q[k];
            for p in col_ptr[col]..col_ptr[col + 1] {
                let s = self.pinv[row_idx[p]];
                if s >= k {
                    self.lower_row.push(s as u32);
                    slot.push(p);
                }
            }
            self.lower_ptr.push(self.lower_row.len());
        }
        slot
    }

    /// L D Lᵀ refactorisation of a symmetric matrix with the diagonal pivot order of
    /// [`set_diagonal_pivots`], from the values of its lower triangle in the layout of
    /// [`lower_layout`]: the same arithmetic as [`refactor`] restricted to the lower triangle,
    /// about half of it. Returns the smallest |pivot| / max |column entry| met, or 1 when every
    /// pivot is positive: the matrix is then positive definite and L D Lᵀ without pivoting is
    /// backward stable whatever the pivot sizes (as Cholesky).
    ///
    /// [`set_diagonal_pivots`]: SparseLu::set_diagonal_pivots
    /// [`lower_layout`]: SparseLu::lower_layout
    /// [`refactor`]: SparseLu::refactor
    pub fn refactor_symmetric(&mut self, lower: &[f64]) -> Result<f64, LuFailure> {
        if !self.diagonal_structure || !self.diag_pref || lower.len() != self.lower_row.len() {
            return Err(LuFailure::PivotTooSmall);
        }
        self.factored = false;
        self.symmetric_factors = false;
        let n = self.n;
        let x = &mut self.work;
        self.next.clear();
        self.next.extend_from_slice(&self.l_ptr[..n]);
        let mut min_ratio: f64 = 1.0;
        let mut all_positive = true;
        let pivot_tol = self.pivot_tol;
        self.n_negative = 0;
        for k in 0..n {
            let (alo, ahi) = (self.lower_ptr[k], self.lower_ptr[k + 1]);
            for (&s, &a) in self.lower_row[alo..ahi].iter().zip(&lower[alo..ahi]) {
                x[s as usize] += a;
            }
            for p in self.u_ptr[k]..self.u_ptr[k + 1] {
                let s = self.u_idx[p];
                // L(:, s) from row k on (its columns are sorted by row)
                let start = self.next[s];
                let end = self.l_ptr[s + 1];
                debug_assert_eq!(self.l_idx[start], k);
                let u = self.u_diag[s] * self.l_val[start];
                x[k] -= self.l_val[start] * u;
                for (&i, &l) in self.l_idx[start + 1..end]
                    .iter()
                    .zip(&self.l_val[start + 1..end])
                {
                    x[i] -= l * u;
                }
                self.next[s] = start + 1;
            }
            let (llo, lhi) = (self.l_ptr[k], self.l_ptr[k + 1]);
            let (d, ok) = pivot_step(
                x,
                k,
                &self.l_idx[llo..lhi],
                &mut self.l_val[llo..lhi],
                pivot_tol,
                &mut min_ratio,
            );
            all_positive &= d > 0.0;
            self.n_negative += usize::from(d < 0.0);
            self.u_diag[k] = d;
            if !ok {
                return Err(LuFailure::PivotTooSmall);
            }
        }
        self.symmetric_factors = true;
        Ok(if all_positive { 1.0 } else { min_ratio })
    }

    /// Number of nonzeros of L (without the unit diagonal) and U (with the diagonal).
    pub fn nnz(&self) -> (usize, usize) {
        (self.l_idx.len(), self.u_idx.len() + self.n)
    }

    /// Factor with partial pivoting (records the pivot order and the structure of L and U).
    pub fn factor(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        val: &[f64],
    ) -> Result<(), LuFailure> {
        let n = self.n;
        self.factored = false;
        self.symmetric_factors = false;
        self.diagonal_structure = false;
        self.pinv.iter_mut().for_each(|p| *p = usize::MAX);
        self.mark.iter_mut().for_each(|m| *m = usize::MAX);
        self.l_idx.clear();
        self.l_val.clear();
        self.u_idx.clear();
        self.u_val.clear();
        self.l_ptr[0] = 0;
        self.u_ptr[0] = 0;
        let x = &mut self.work;
        for k in 0..n {
            let col = self.q[k];
            let (lo, hi) = (col_ptr[col], col_ptr[col + 1]);
            // rows reachable from the column's pattern in the graph of L (rows of A numbering),
            // in topological order (reverse DFS post-order)
            self.reach.clear();
            for &r in &row_idx[lo..hi] {
                if self.mark[r] != k {
                    dfs(
                        r,
                        k,
                        &self.pinv,
                        &self.l_ptr,
                        &self.l_idx,
                        &mut self.mark,
                        &mut self.stack,
                        &mut self.pstack,
                        &mut self.reach,
                    );
                }
            }
            for p in lo..hi {
                x[row_idx[p]] += val[p];
            }
            // reach holds post-order: process in reverse
            for &r in self.reach.iter().rev() {
                let s = self.pinv[r];
                if s == usize::MAX {
                    continue;
                }
                let u = x[r];
                for p in self.l_ptr[s]..self.l_ptr[s + 1] {
                    // L rows are still in A numbering during the factorisation
                    x[self.l_idx[p]] -= self.l_val[p] * u;
                }
            }
            // pivot: the largest candidate
            let (mut piv, mut piv_abs) = (usize::MAX, -1.0);
            for &r in &self.reach {
                if self.pinv[r] == usize::MAX {
                    let a = x[r].abs();
                    if a > piv_abs || a.is_nan() {
                        piv = r;
                        piv_abs = a;
                    }
                }
            }
            if self.diag_pref && piv != usize::MAX {
                // the diagonal entry (row q[k]) if it is large enough
                let r = col;
                if self.pinv[r] == usize::MAX
                    && self.mark[r] == k
                    && x[r].abs() >= DIAG_TOL * piv_abs
                {
                    piv = r;
                    piv_abs = x[r].abs();
                }
            }
            if piv == usize::MAX || piv_abs == 0.0 || !piv_abs.is_finite() {
                for &r in &self.reach {
                    x[r] = 0.0;
                }
                return Err(LuFailure::Singular);
            }
            let d = x[piv];
            self.u_diag[k] = d;
            self.pinv[piv] = k;
            for &r in &self.reach {
                let s = self.pinv[r];
                if r != piv && s == usize::MAX {
                    self.l_idx.push(r);
                    self.l_val.push(x[r] / d);
                } else if r != piv {
                    self.u_idx.push(s);
                    self.u_val.push(x[r]);
                }
                x[r] = 0.0;
            }
            self.l_ptr[k + 1] = self.l_idx.len();
            self.u_ptr[k + 1] = self.u_idx.len();
        }
        // L rows to step numbering; U columns sorted by step (valid elimination order)
        for r in self.l_idx.iter_mut() {
            *r = self.pinv[*r];
        }
        sort_columns(&self.u_ptr, &mut self.u_idx, &mut self.u_val);
        self.factored = true;
        Ok(())
    }

    /// Factor a matrix of the same structure with the pivot order of the last [`factor`]
    /// (see the module docs). Returns the smallest |pivot| / max |column entry| met.
    ///
    /// [`factor`]: SparseLu::factor
    pub fn refactor(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[usize],
        val: &[f64],
    ) -> Result<f64, LuFailure> {
        if !(self.factored || self.symmetric_factors) {
            return Err(LuFailure::PivotTooSmall);
        }
        self.factored = false;
        self.symmetric_factors = false;
        self.u_val.resize(self.u_idx.len(), 0.0);
        let n = self.n;
        let x = &mut self.work;
        let mut min_ratio: f64 = 1.0;
        for k in 0..n {
            let col = self.q[k];
            for p in col_ptr[col]..col_ptr[col + 1] {
                x[self.pinv[row_idx[p]]] += val[p];
            }
            let (ulo, uhi) = (self.u_ptr[k], self.u_ptr[k + 1]);
            for p in ulo..uhi {
                let s = self.u_idx[p];
                let u = x[s];
                x[s] = 0.0;
                self.u_val[p] = u;
                let (llo, lhi) = (self.l_ptr[s], self.l_ptr[s + 1]);
                for (&i, &l) in self.l_idx[llo..lhi].iter().zip(&self.l_val[llo..lhi]) {
                    x[i] -= l * u;
                }
            }
            let (llo, lhi) = (self.l_ptr[k], self.l_ptr[k + 1]);
            let (d, ok) = pivot_step(
                x,
                k,
                &self.l_idx[llo..lhi],
                &mut self.l_val[llo..lhi],
                PIVOT_TOL,
                &mut min_ratio,
            );
            self.u_diag[k] = d;
            if !ok {
                // the work vector is clean: only column k was scattered, and it is cleared
                return Err(LuFailure::PivotTooSmall);
            }
        }
        self.factored = true;
        Ok(min_ratio)
    }

    /// Solve A z = b in place (`b` becomes z), after a successful factorisation.
    pub fn solve(&mut self, b: &mut [f64]) {
        assert!(
            self.symmetric_factors || (self.factored && self.u_val.len() == self.u_idx.len()),
            "solve without a factorisation"
        );
        let n = self.n;
        let y = &mut self.work[..n];
        for (&pi, &bi) in self.pinv[..n].iter().zip(b.iter()) {
            y[pi] = bi;
        }
        // the entries of column k of L as slices (the same operations in the same order as
        // indexing them one by one, without the bounds checks)
        let (l_ptr, l_idx, l_val) = (&self.l_ptr, &self.l_idx, &self.l_val);
        let column = |k: usize| {
            let (lo, hi) = (l_ptr[k], l_ptr[k + 1]);
            l_idx[lo..hi].iter().zip(&l_val[lo..hi])
        };
        for k in 0..n {
            let v = y[k];
            if v != 0.0 {
                for (&i, &l) in column(k) {
                    y[i] -= l * v;
                }
            }
        }
        if self.symmetric_factors {
            // L D Lᵀ: U = D Lᵀ
            for k in (0..n).rev() {
                let mut v = y[k] / self.u_diag[k];
                for (&i, &l) in column(k) {
                    v -= l * y[i];
                }
                y[k] = v;
            }
        } else {
            for k in (0..n).rev() {
                let v = y[k] / self.u_diag[k];
                y[k] = v;
                if v != 0.0 {
                    for p in self.u_ptr[k]..self.u_ptr[k + 1] {
                        y[self.u_idx[p]] -= self.u_val[p] * v;
                    }
                }
            }
        }
        for (&qk, yk) in self.q[..n].iter().zip(y.iter_mut()) {
            b[qk] = *yk;
            *yk = 0.0;
        }
    }
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
fn sort_columns(ptr: &[usize], idx: &mut [usize], val: &mut [f64]) {
    let mut pairs: Vec<(usize, f64)> = Vec::new();
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

/// The pivot of step k of a refactorisation, from the work vector `x` after the updates of
/// column k: the pivot d = x[k] and, scaled by 1/d, the entries of column k of L (`l_idx`: rows
/// in step numbering, values into `l_val`); clears those entries of `x`. Lowers `min_ratio` to
/// |d| / max |column entry| and returns d with whether that ratio is at least `tol` (and d is
/// non-zero, everything finite).
#[inline(always)]
fn pivot_step(
    x: &mut [f64],
    k: usize,
    l_idx: &[usize],
    l_val: &mut [f64],
    tol: f64,
    min_ratio: &mut f64,
) -> (f64, bool) {
    let d = x[k];
    x[k] = 0.0;
    let mut cmax: f64 = 0.0;
    for &i in l_idx {
        cmax = cmax.max(x[i].abs());
    }
    let ok = d.abs() >= tol * cmax && d != 0.0 && d.is_finite() && cmax.is_finite();
    if d.abs() < *min_ratio * cmax {
        *min_ratio = d.abs() / cmax;
    }
    let inv = 1.0 / d;
    for (&i, l) in l_idx.iter().zip(l_val) {
        *l = x[i] * inv;
        x[i] = 0.0;
    }
    (d, ok)
}

/// Depth-first search from row `r` in the graph of L (column s = pinv[row] lists the rows it
/// updates); appends the visited rows to `reach` in post-order. Marks with `k`.
#[allow(clippy::too_many_arguments)]
fn dfs(
    r: usize,
    k: usize,
    pinv: &[usize],
    l_ptr: &[usize],
    l_idx: &[usize],
    mark: &mut [usize],
    stack: &mut Vec<usize>,
    pstack: &mut Vec<usize>,
    reach: &mut Vec<usize>,
) {
    stack.clear();
    pstack.clear();
    stack.push(r);
    mark[r] = k;
    let start = |row: usize| -> usize {
        let s = pinv[row];
        if s == usize::MAX {
            usize::MAX
        } else {
            l_ptr[s]
        }
    };
    pstack.push(start(r));
    while let Some(&row) = stack.last() {
        let s = pinv[row];
        let top = pstack.len() - 1;
        let mut descended = false;
        if s != usize::MAX {
            let end = l_ptr[s + 1];
            let mut p = pstack[top];
            while p < end {
                let child = l_idx[p];
                p += 1;
                if mark[child] != k {
                    mark[child] = k;
                    pstack[top] = p;
                    stack.push(child);
                    pstack.push(start(child));
                    descended = true;
                    break;
                }
            }
        }
        if !descended {
            stack.pop();
            pstack.pop();
            reach.push(row);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dense test matrix to CSC.
    fn csc(a: &[Vec<f64>]) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        let n = a.len();
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
                let lower: Vec<f64> = slots.iter().map(|&p| v2[p]).collect();
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
}
