//! The symmetric strategy of [`SparseLu`]: all pivots on the diagonal (the structure of a
//! Cholesky factorisation) and L D Lᵀ refactorisation with an inertia count.

use super::lu::pivot_step;
use super::{sort_columns, sort_small, step, ColRows, LuFailure, RowIndex, SparseLu};

impl SparseLu {
    /// Symmetric strategy: set up the pivot order "all pivots on the diagonal" and its
    /// structure (that of a Cholesky factorisation), for [`refactor`] to take the values.
    /// It is the order that factor chooses for a column diagonally dominant matrix.
    ///
    /// [`refactor`]: SparseLu::refactor
    pub fn set_diagonal_pivots<R: RowIndex>(&mut self, col_ptr: &[usize], row_idx: &[R]) -> bool {
        if !self.diag_pref {
            return false;
        }
        let n = self.n;
        let symmetric_pattern = (0..n).all(|j| {
            row_idx[col_ptr[j]..col_ptr[j + 1]].iter().all(|&i| {
                let i = i.ix();
                row_idx[col_ptr[i]..col_ptr[i + 1]]
                    .binary_search_by(|r| r.ix().cmp(&j))
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
                if row_idx[p].ix() == j {
                    v[p] = (hi - lo + 1) as f64;
                }
            }
        }
        let r = self.factor(col_ptr, row_idx, &v);
        if r.is_err() || (0..n).any(|k| step(self.pinv[self.q[k] as usize]) != k) {
            return false;
        }
        // L columns by ascending row (for the symmetric refactorisation)
        sort_columns(&self.l_ptr, &mut self.l_idx, &mut self.l_val);
        self.diagonal_structure = true;
        true
    }

    /// Releases the structure of U (the row structure of L, 4 bytes per entry of L, and its
    /// pointers) after [`set_diagonal_pivots`], for a factorisation that only ever refactors a
    /// symmetric matrix: [`refactor_symmetric`] does not read it, [`refactor`] fails
    /// afterwards.
    ///
    /// [`set_diagonal_pivots`]: SparseLu::set_diagonal_pivots
    /// [`refactor_symmetric`]: SparseLu::refactor_symmetric
    /// [`refactor`]: SparseLu::refactor
    pub fn release_upper_structure(&mut self) {
        self.u_idx = Vec::new();
        self.u_val = Vec::new();
        self.u_ptr = Vec::new();
        self.a_step = Vec::new();
        if self.diagonal_structure && self.l_start.is_empty() {
            self.share_l_rows();
        }
    }

    /// Releases the values of L (8 bytes per entry), keeping the structure and the order:
    /// no solve until the next [`refactor_symmetric_on`] makes them again. For a phase that
    /// holds no factorisation between two of them.
    ///
    /// [`refactor_symmetric_on`]: SparseLu::refactor_symmetric_on
    pub fn release_values(&mut self) {
        self.l_val = Vec::new();
        self.factored = false;
        self.symmetric_factors = false;
    }

    /// The structure of L and U for diagonal pivots of a structurally symmetric matrix: that
    /// of its Cholesky factor, from the elimination tree (row subtrees, as CSparse's
    /// `cs_schol`/`cs_ereach`), in time proportional to the nonzeros of L.
    fn symbolic_cholesky<R: RowIndex>(&mut self, col_ptr: &[usize], row_idx: &[R]) {
        const NONE: usize = usize::MAX;
        let n = self.n;
        self.a_step.clear();
        for k in 0..n {
            self.pinv[self.q[k] as usize] = k as u32;
        }
        // elimination tree of the permuted matrix
        let mut parent = vec![NONE; n];
        let mut ancestor = vec![NONE; n];
        for k in 0..n {
            let col = self.q[k] as usize;
            for r in row_idx[col_ptr[col]..col_ptr[col + 1]]
                .iter()
                .map(|r| r.ix())
            {
                let mut i = step(self.pinv[r]);
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
        let mut mark = vec![NONE; n];
        self.u_idx.clear();
        self.u_ptr.resize(self.n + 1, 0);
        self.u_ptr[0] = 0;
        let mut l_count = vec![0usize; n];
        for k in 0..n {
            mark[k] = k;
            let start = self.u_idx.len();
            let col = self.q[k] as usize;
            for r in row_idx[col_ptr[col]..col_ptr[col + 1]]
                .iter()
                .map(|r| r.ix())
            {
                let mut i = step(self.pinv[r]);
                if i >= k {
                    continue;
                }
                while mark[i] != k {
                    mark[i] = k;
                    self.u_idx.push(i as u32);
                    l_count[i] += 1;
                    i = parent[i];
                    debug_assert!(i != NONE);
                }
            }
            sort_small(&mut self.u_idx[start..]);
            self.u_ptr[k + 1] = self.u_idx.len();
        }
        // (grown by pushes: up to twice its length in room, 13 MB at 10⁵ beams)
        self.u_idx.shrink_to_fit();
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
                let j = self.u_idx[p] as usize;
                self.l_idx[fill[j]] = k as u32;
                fill[j] += 1;
            }
        }
        // (the values are made by the first refactorisation: not held beside the symbolic
        // work, U's structure and the caller's pattern, at the peak of a large model's set-up)
        self.l_val = Vec::new();
        // U's values are made by `refactor` (L D Lᵀ does not store U)
        self.u_val.clear();
        self.u_diag.iter_mut().for_each(|d| *d = 1.0);
        self.factored = true;
        self.symmetric_factors = false;
    }

    /// After [`set_diagonal_pivots`]: the layout of the lower triangle of A in pivot order that
    /// [`refactor_symmetric`] reads (sequentially, half of A). Returns, for each of its entries,
    /// the position of that entry in the CSC arrays of A (32-bit: A has fewer than 2³² entries,
    /// as the row indices of the factors assume).
    ///
    /// [`set_diagonal_pivots`]: SparseLu::set_diagonal_pivots
    /// [`refactor_symmetric`]: SparseLu::refactor_symmetric
    pub fn lower_layout<R: RowIndex>(&mut self, col_ptr: &[usize], row_idx: &[R]) -> Vec<u32> {
        let n = self.n;
        // entries on or below the diagonal, to size the arrays exactly
        let count = (0..n)
            .map(|k| {
                let col = self.q[k] as usize;
                row_idx[col_ptr[col]..col_ptr[col + 1]]
                    .iter()
                    .filter(|&&r| step(self.pinv[r.ix()]) >= k)
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
            let col = self.q[k] as usize;
            for p in col_ptr[col]..col_ptr[col + 1] {
                let s = step(self.pinv[row_idx[p].ix()]);
                if s >= k {
                    self.lower_row.push(s as u32);
                    slot.push(p as u32);
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
        if lower.len() != self.lower_row.len() {
            return Err(LuFailure::PivotTooSmall);
        }
        self.refactor_symmetric_with(|q| lower[q])
    }

    /// [`SparseLu::refactor_symmetric`] with entry q of the lower triangle's layout given by
    /// `lower(q)`: the values formed as they are read (K − σM from K and M), with no array of
    /// them held beside the factor.
    pub fn refactor_symmetric_with(
        &mut self,
        lower: impl Fn(usize) -> f64,
    ) -> Result<f64, LuFailure> {
        let (ptr, row) = (
            std::mem::take(&mut self.lower_ptr),
            std::mem::take(&mut self.lower_row),
        );
        let r = self.refactor_symmetric_on(ColRows::plain(&ptr, &row), lower);
        (self.lower_ptr, self.lower_row) = (ptr, row);
        r
    }

    /// [`SparseLu::refactor_symmetric_with`] with the layout of the lower triangle in pivot order
    /// given by the caller instead of [`SparseLu::lower_layout`]: the rows of step k are
    /// `a.of(k)` (pivot numbering, ≥ k), the values of its entries at positions
    /// `a.first(k)..a.first(k + 1)`, entry q's value `lower(q)`. For a caller that keeps its
    /// matrix in pivot order (the sparse modal problem), so that the layout is not held twice.
    pub fn refactor_symmetric_on<P: RowIndex>(
        &mut self,
        a: ColRows<'_, P>,
        lower: impl Fn(usize) -> f64,
    ) -> Result<f64, LuFailure> {
        if !self.diagonal_structure || !self.diag_pref || a.ncols() != self.n {
            return Err(LuFailure::PivotTooSmall);
        }
        self.factored = false;
        self.symmetric_factors = false;
        const NONE: u32 = u32::MAX;
        let n = self.n;
        self.l_val.resize(self.l_ptr[n], 0.0);
        // the dense work vector, made for the refactorisation and released after it (the
        // solves need none: [`SparseLu::solve`])
        let mut work = std::mem::take(&mut self.work);
        work.resize(n, 0.0);
        let x = &mut work[..];
        // left-looking, the columns s that update column k (the structure of row k of L) found
        // from linked lists instead of a stored row structure (4 bytes per entry of L): every
        // finished column waits in the list of the row of its next entry (`head`, `link`);
        // `next` is that entry (George & Liu, "Computer solution of large sparse positive
        // definite systems", 1981, §5.4). Made for each refactorisation, not kept beside the
        // factors.
        let mut next = self.l_ptr[..n].to_vec();
        let mut head = vec![NONE; n];
        let mut link = vec![NONE; n];
        let mut cols: Vec<usize> = Vec::new();
        let mut min_ratio: f64 = 1.0;
        let mut all_positive = true;
        let pivot_tol = self.pivot_tol;
        self.n_negative = 0;
        let rows = ColRows::shared(&self.l_ptr, &self.l_idx, &self.l_start);
        // (`at`: the position of an entry among the values of L, in column s)
        let wait = |s: usize, head: &mut [u32], link: &mut [u32], at: usize, end: usize| {
            if at < end {
                let r = rows.of(s)[at - self.l_ptr[s]] as usize;
                link[s] = head[r];
                head[r] = s as u32;
            }
        };
        for k in 0..n {
            let (alo, ahi) = (a.first(k), a.first(k + 1));
            for (q, &s) in (alo..ahi).zip(a.of(k)) {
                x[s as usize] += lower(q);
            }
            // the columns with an entry in row k, in ascending order (the order of the sums
            // does not depend on the lists)
            cols.clear();
            let mut s = head[k];
            while s != NONE {
                cols.push(s as usize);
                s = link[s as usize];
            }
            sort_small(&mut cols);
            for &s in &cols {
                // L(:, s) from row k on (its columns are sorted by row)
                let start = next[s];
                let end = self.l_ptr[s + 1];
                let rows = &rows.of(s)[start - self.l_ptr[s]..];
                debug_assert_eq!(rows[0] as usize, k);
                let u = self.u_diag[s] * self.l_val[start];
                x[k] -= self.l_val[start] * u;
                for (&i, &l) in rows[1..].iter().zip(&self.l_val[start + 1..end]) {
                    x[i as usize] -= l * u;
                }
                next[s] = start + 1;
                wait(s, &mut head, &mut link, start + 1, end);
            }
            let (llo, lhi) = (self.l_ptr[k], self.l_ptr[k + 1]);
            let (d, ok) = pivot_step(
                x,
                k,
                rows.of(k),
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
            wait(k, &mut head, &mut link, llo, lhi);
        }
        self.symmetric_factors = true;
        Ok(if all_positive { 1.0 } else { min_ratio })
    }
}
