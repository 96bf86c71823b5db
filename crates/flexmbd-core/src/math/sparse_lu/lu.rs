//! LU with partial pivoting of [`SparseLu`]: the left-looking Gilbert–Peierls factorisation,
//! the refactorisation with the recorded pivot order, and the triangular solves.

use super::{
    sort_columns, step, ColRows, LuFailure, RowIndex, SparseLu, DIAG_TOL, NO_STEP, PIVOT_TOL,
};

impl SparseLu {
    /// Factor with partial pivoting (records the pivot order and the structure of L and U).
    pub fn factor<R: RowIndex>(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[R],
        val: &[f64],
    ) -> Result<(), LuFailure> {
        let n = self.n;
        self.factored = false;
        self.symmetric_factors = false;
        self.diagonal_structure = false;
        self.work.resize(n, 0.0);
        self.a_step.clear();
        self.pinv.iter_mut().for_each(|p| *p = NO_STEP);
        self.mark.clear();
        self.mark.resize(n, usize::MAX);
        self.l_idx.clear();
        self.l_start.clear();
        self.l_val.clear();
        self.u_idx.clear();
        self.u_val.clear();
        self.l_ptr[0] = 0;
        self.u_ptr.resize(self.n + 1, 0);
        self.u_ptr[0] = 0;
        let x = &mut self.work;
        for k in 0..n {
            let col = self.q[k] as usize;
            let (lo, hi) = (col_ptr[col], col_ptr[col + 1]);
            // rows reachable from the column's pattern in the graph of L (rows of A numbering),
            // in topological order (reverse DFS post-order)
            self.reach.clear();
            for r in row_idx[lo..hi].iter().map(|r| r.ix()) {
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
                x[row_idx[p].ix()] += val[p];
            }
            // reach holds post-order: process in reverse
            for &r in self.reach.iter().rev() {
                let s = step(self.pinv[r]);
                if s == usize::MAX {
                    continue;
                }
                let u = x[r];
                for p in self.l_ptr[s]..self.l_ptr[s + 1] {
                    // L rows are still in A numbering during the factorisation
                    x[self.l_idx[p] as usize] -= self.l_val[p] * u;
                }
            }
            // pivot: the largest candidate
            let (mut piv, mut piv_abs) = (usize::MAX, -1.0);
            for &r in &self.reach {
                if self.pinv[r] == NO_STEP {
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
                if self.pinv[r] == NO_STEP && self.mark[r] == k && x[r].abs() >= DIAG_TOL * piv_abs
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
            self.pinv[piv] = k as u32;
            for &r in &self.reach {
                let s = step(self.pinv[r]);
                if r != piv && s == usize::MAX {
                    self.l_idx.push(r as u32);
                    self.l_val.push(x[r] / d);
                } else if r != piv {
                    self.u_idx.push(s as u32);
                    self.u_val.push(x[r]);
                }
                x[r] = 0.0;
            }
            self.l_ptr[k + 1] = self.l_idx.len();
            self.u_ptr[k + 1] = self.u_idx.len();
        }
        // L rows to step numbering; U columns sorted by step (valid elimination order)
        for r in self.l_idx.iter_mut() {
            *r = self.pinv[*r as usize];
        }
        sort_columns(&self.u_ptr, &mut self.u_idx, &mut self.u_val);
        self.factored = true;
        Ok(())
    }

    /// Factor a matrix of the same structure with the pivot order of the last [`factor`]
    /// (see the module docs). Returns the smallest |pivot| / max |column entry| met.
    ///
    /// [`factor`]: SparseLu::factor
    pub fn refactor<R: RowIndex>(
        &mut self,
        col_ptr: &[usize],
        row_idx: &[R],
        val: &[f64],
    ) -> Result<f64, LuFailure> {
        // (no structure of U after `release_upper_structure`)
        if !(self.factored || self.symmetric_factors) || self.u_ptr.len() != self.n + 1 {
            return Err(LuFailure::PivotTooSmall);
        }
        self.factored = false;
        self.symmetric_factors = false;
        self.u_val.resize(self.u_idx.len(), 0.0);
        let n = self.n;
        self.l_val.resize(self.l_ptr[n], 0.0);
        let nnz = col_ptr[n];
        if self.a_step.len() != nnz {
            self.a_step.clear();
            self.a_step
                .extend(row_idx[..nnz].iter().map(|&r| self.pinv[r.ix()]));
        }
        self.work.resize(n, 0.0);
        let x = &mut self.work;
        let mut min_ratio: f64 = 1.0;
        for k in 0..n {
            let col = self.q[k] as usize;
            let (lo, hi) = (col_ptr[col], col_ptr[col + 1]);
            for (&s, &v) in self.a_step[lo..hi].iter().zip(&val[lo..hi]) {
                x[s as usize] += v;
            }
            let (ulo, uhi) = (self.u_ptr[k], self.u_ptr[k + 1]);
            for (&s, u_out) in self.u_idx[ulo..uhi].iter().zip(&mut self.u_val[ulo..uhi]) {
                let s = s as usize;
                let u = x[s];
                x[s] = 0.0;
                *u_out = u;
                let (llo, lhi) = (self.l_ptr[s], self.l_ptr[s + 1]);
                for (&i, &l) in self.l_idx[llo..lhi].iter().zip(&self.l_val[llo..lhi]) {
                    x[i as usize] -= l * u;
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
        // y = P b in b itself (no vector of the system's size beside the factors)
        let y = &mut b[..n];
        permute_in_place(y, |i| self.pinv[i] as usize);
        // the entries of column k of L as slices (the same operations in the same order as
        // indexing them one by one, without the bounds checks)
        let rows = ColRows::shared(&self.l_ptr, &self.l_idx, &self.l_start);
        let l_val = &self.l_val;
        let column = |k: usize| {
            let (lo, hi) = (rows.first(k), rows.first(k + 1));
            rows.of(k).iter().zip(&l_val[lo..hi])
        };
        for k in 0..n {
            let v = y[k];
            if v != 0.0 {
                for (&i, &l) in column(k) {
                    y[i as usize] -= l * v;
                }
            }
        }
        if self.symmetric_factors {
            // L D Lᵀ: U = D Lᵀ
            for k in (0..n).rev() {
                let mut v = y[k] / self.u_diag[k];
                for (&i, &l) in column(k) {
                    v -= l * y[i as usize];
                }
                y[k] = v;
            }
        } else {
            // the entries of column k of U as slices, as those of L
            let (u_ptr, u_idx, u_val) = (&self.u_ptr, &self.u_idx, &self.u_val);
            for k in (0..n).rev() {
                let v = y[k] / self.u_diag[k];
                y[k] = v;
                if v != 0.0 {
                    let (lo, hi) = (u_ptr[k], u_ptr[k + 1]);
                    for (&i, &u) in u_idx[lo..hi].iter().zip(&u_val[lo..hi]) {
                        y[i as usize] -= u * v;
                    }
                }
            }
        }
        // z = Q y
        permute_in_place(y, |k| self.q[k] as usize);
    }
}

/// Moves the entry at i of `v` to `dest(i)` for every i (`dest` a permutation), in place:
/// each cycle of the permutation is followed once, the entries already moved marked in a
/// bit set (n / 8 bytes).
fn permute_in_place(v: &mut [f64], dest: impl Fn(usize) -> usize) {
    let n = v.len();
    let mut done = vec![0u64; n.div_ceil(64)];
    for s in 0..n {
        if done[s / 64] >> (s % 64) & 1 == 1 {
            continue;
        }
        let (mut carry, mut j) = (v[s], s);
        loop {
            done[j / 64] |= 1 << (j % 64);
            let d = dest(j);
            if d == s {
                v[s] = carry;
                break;
            }
            carry = std::mem::replace(&mut v[d], carry);
            j = d;
        }
    }
}

/// The pivot of step k of a refactorisation, from the work vector `x` after the updates of
/// column k: the pivot d = x[k] and, scaled by 1/d, the entries of column k of L (`l_idx`: rows
/// in step numbering, values into `l_val`); clears those entries of `x`. Lowers `min_ratio` to
/// |d| / max |column entry| and returns d with whether that ratio is at least `tol` (and d is
/// non-zero, everything finite).
#[inline(always)]
pub(super) fn pivot_step(
    x: &mut [f64],
    k: usize,
    l_idx: &[u32],
    l_val: &mut [f64],
    tol: f64,
    min_ratio: &mut f64,
) -> (f64, bool) {
    let d = x[k];
    x[k] = 0.0;
    let mut cmax: f64 = 0.0;
    for &i in l_idx {
        cmax = cmax.max(x[i as usize].abs());
    }
    let ok = d.abs() >= tol * cmax && d != 0.0 && d.is_finite() && cmax.is_finite();
    if d.abs() < *min_ratio * cmax {
        *min_ratio = d.abs() / cmax;
    }
    let inv = 1.0 / d;
    for (&i, l) in l_idx.iter().zip(l_val) {
        let i = i as usize;
        *l = x[i] * inv;
        x[i] = 0.0;
    }
    (d, ok)
}

/// Depth-first search from row `r` in the graph of L (column s = pinv[row] lists the rows it
/// updates); appends the visited rows to `reach` in post-order. Marks with `k`.
#[allow(clippy::too_many_arguments)]
pub(super) fn dfs(
    r: usize,
    k: usize,
    pinv: &[u32],
    l_ptr: &[usize],
    l_idx: &[u32],
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
        let s = step(pinv[row]);
        if s == usize::MAX {
            usize::MAX
        } else {
            l_ptr[s]
        }
    };
    pstack.push(start(r));
    while let Some(&row) = stack.last() {
        let s = step(pinv[row]);
        let top = pstack.len() - 1;
        let mut descended = false;
        if s != usize::MAX {
            let end = l_ptr[s + 1];
            let mut p = pstack[top];
            while p < end {
                let child = l_idx[p] as usize;
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
