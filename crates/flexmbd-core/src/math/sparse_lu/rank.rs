//! Rank-revealing sparse LU of a rectangular matrix (m × n, any shape): the sparse path of the
//! kinematic check (issue 14).
//!
//! Left-looking Gilbert–Peierls LU with threshold partial pivoting over the rows, column by
//! column in a given order. For each column the part outside the rows already pivoted (its
//! Schur-complement column) is formed; if its largest entry is at most the drop tolerance δ the
//! column is **dependent** (numerically a combination of the columns before it): its entries on
//! the pivoted rows are kept as a column of U and the small rest is dropped (its Frobenius norm
//! is summed). Otherwise a pivot row is chosen among the entries within a factor
//! [`PIVOT_THRESHOLD`] of the largest: the one with the fewest entries in columns still to come
//! (Markowitz's row count), which keeps the factors as sparse as the matrix for the constraint
//! matrices of structures built up from their supports.
//!
//! The result, with Π the rows (pivot rows first, in step order) and Q the columns (basic
//! columns first), is
//!
//!   Π A Q = [L₁; L₂] [U₁ U₂] + E,   ‖E‖_F = [`RankLu::dropped_norm`],
//!
//! L₁ unit lower triangular (r × r), U₁ upper triangular (r × r) with the pivots on its
//! diagonal, r the number of pivots. Hence A − E has rank r exactly and (Weyl)
//! σ_{r+1}(A) ≤ ‖E‖₂ ≤ ‖E‖_F; the r × r submatrix A₁₁ = L₁ U₁ of the pivot rows and basic columns
//! gives σ_r(A) ≥ σ_min(A₁₁) (singular values of a submatrix interlace). The null vectors:
//! dependent column j gives A [−U₁⁻¹ u_j; e_j] = E e_j (a **motion** of Dcc), non-basic row k
//! gives [−L₁⁻ᵀ l_k; e_k]ᵀ A = e_kᵀ E (a **self-stress**): the fundamental bases of the null
//! spaces of A and Aᵀ, one vector per dependent column and per non-basic row.

/// Threshold of the partial pivoting: a candidate pivot must be at least this fraction of the
/// largest entry of its Schur-complement column (the multipliers in L are at most 1 / it).
pub const PIVOT_THRESHOLD: f64 = 0.1;

/// A rank-revealing LU factorisation (module docs). Rows and columns keep their original
/// numbers; steps 0 … r − 1 are the pivots.
#[derive(Debug, Clone)]
pub struct RankLu {
    m: usize,
    n: usize,
    /// The original column of each pivot step.
    pub basic_cols: Vec<usize>,
    /// The original row of each pivot step.
    pub pivot_rows: Vec<usize>,
    /// The dependent columns, in the order they were met.
    pub dependent_cols: Vec<usize>,
    /// The pivot step of each row (`usize::MAX`: a non-basic row).
    row_step: Vec<usize>,
    /// L by steps: rows (original numbers, not yet pivoted at that step) and multipliers.
    l_ptr: Vec<usize>,
    l_row: Vec<usize>,
    l_val: Vec<f64>,
    /// U of the basic columns by steps: (earlier step, value), the pivot apart.
    u_ptr: Vec<usize>,
    u_step: Vec<usize>,
    u_val: Vec<f64>,
    u_diag: Vec<f64>,
    /// U of the dependent columns (same layout), in the order of `dependent_cols`.
    d_ptr: Vec<usize>,
    d_step: Vec<usize>,
    d_val: Vec<f64>,
    dropped2: f64,
    dropped_max: f64,
}

/// A column-compressed matrix, read-only (column pointers, row indices, values).
#[derive(Clone, Copy, Debug)]
pub struct Csc<'a> {
    /// Rows.
    pub m: usize,
    /// Columns.
    pub n: usize,
    /// Column starts (n + 1).
    pub ptr: &'a [usize],
    /// Row indices.
    pub row: &'a [usize],
    /// Values.
    pub val: &'a [f64],
}

/// Append a column's non-zero entries (index, value) to a compressed layout.
fn push_column(
    ptr: &mut Vec<usize>,
    idx: &mut Vec<usize>,
    val: &mut Vec<f64>,
    entries: Vec<(usize, f64)>,
) {
    for (i, v) in entries {
        if v != 0.0 {
            idx.push(i);
            val.push(v);
        }
    }
    ptr.push(idx.len());
}

impl RankLu {
    /// Factor `a` with its columns in `order` (a permutation of 0 … n − 1), declaring a column
    /// dependent when its Schur-complement column has no entry larger than `drop_tol`.
    pub fn factor(a: Csc<'_>, order: &[usize], drop_tol: f64) -> Self {
        let (m, n) = (a.m, a.n);
        // entries of each row in columns still to come (Markowitz row counts)
        let mut row_left = vec![0usize; m];
        for &r in &a.row[..a.ptr[n]] {
            row_left[r] += 1;
        }
        let mut f = RankLu {
            m,
            n,
            basic_cols: Vec::new(),
            pivot_rows: Vec::new(),
            dependent_cols: Vec::new(),
            row_step: vec![usize::MAX; m],
            l_ptr: vec![0],
            l_row: Vec::new(),
            l_val: Vec::new(),
            u_ptr: vec![0],
            u_step: Vec::new(),
            u_val: Vec::new(),
            u_diag: Vec::new(),
            d_ptr: vec![0],
            d_step: Vec::new(),
            d_val: Vec::new(),
            dropped2: 0.0,
            dropped_max: 0.0,
        };
        let mut x = vec![0.0f64; m];
        let mut in_pattern = vec![false; m];
        let mut pattern: Vec<usize> = Vec::new();
        let mut mark = vec![usize::MAX; m.min(n)];
        let mut topo: Vec<usize> = Vec::new();
        let mut stack: Vec<(usize, usize)> = Vec::new();
        for (t, &j) in order.iter().enumerate() {
            pattern.clear();
            topo.clear();
            for p in a.ptr[j]..a.ptr[j + 1] {
                let i = a.row[p];
                x[i] += a.val[p];
                if !in_pattern[i] {
                    in_pattern[i] = true;
                    pattern.push(i);
                }
            }
            // the steps reached from the pivoted rows of the column, in topological order
            // (depth-first search in the graph of L: step s -> the pivot steps of its rows)
            for pi in 0..pattern.len() {
                let s0 = f.row_step[pattern[pi]];
                if s0 == usize::MAX || mark[s0] == t {
                    continue;
                }
                mark[s0] = t;
                stack.push((s0, f.l_ptr[s0]));
                while let Some(&mut (s, ref mut next)) = stack.last_mut() {
                    let end = f.l_ptr[s + 1];
                    let mut child = None;
                    while *next < end {
                        let c = f.row_step[f.l_row[*next]];
                        *next += 1;
                        if c != usize::MAX && mark[c] != t {
                            child = Some(c);
                            break;
                        }
                    }
                    match child {
                        Some(c) => {
                            mark[c] = t;
                            stack.push((c, f.l_ptr[c]));
                        }
                        None => {
                            topo.push(s);
                            stack.pop();
                        }
                    }
                }
            }
            // x ← L⁻¹ x over the reached steps (reverse post-order is topological)
            let mut u_entries: Vec<(usize, f64)> = Vec::with_capacity(topo.len());
            for &s in topo.iter().rev() {
                let xs = x[f.pivot_rows[s]];
                u_entries.push((s, xs));
                if xs == 0.0 {
                    continue;
                }
                for p in f.l_ptr[s]..f.l_ptr[s + 1] {
                    let i = f.l_row[p];
                    if !in_pattern[i] {
                        in_pattern[i] = true;
                        pattern.push(i);
                    }
                    x[i] -= f.l_val[p] * xs;
                }
            }
            u_entries.sort_unstable_by_key(|e| e.0);
            // the Schur-complement column: the entries on rows not yet pivoted
            let cmax = pattern
                .iter()
                .filter(|&&i| f.row_step[i] == usize::MAX)
                .fold(0.0f64, |mx, &i| mx.max(x[i].abs()));
            for &i in &a.row[a.ptr[j]..a.ptr[j + 1]] {
                row_left[i] -= 1;
            }
            if cmax <= drop_tol || !cmax.is_finite() {
                for &i in &pattern {
                    if f.row_step[i] == usize::MAX {
                        f.dropped2 += x[i] * x[i];
                        f.dropped_max = f.dropped_max.max(x[i].abs());
                    }
                }
                f.dependent_cols.push(j);
                push_column(&mut f.d_ptr, &mut f.d_step, &mut f.d_val, u_entries);
            } else {
                // threshold pivoting, fewest entries to come first, then the larger, then
                // the lower row number
                let mut best: Option<usize> = None;
                for &i in &pattern {
                    if f.row_step[i] != usize::MAX || x[i].abs() < PIVOT_THRESHOLD * cmax {
                        continue;
                    }
                    best = match best {
                        None => Some(i),
                        Some(b) => {
                            let key = |r: usize| (row_left[r], std::cmp::Reverse(x[r].abs()), r);
                            if key(i) < key(b) {
                                Some(i)
                            } else {
                                Some(b)
                            }
                        }
                    };
                }
                let Some(p) = best else {
                    unreachable!("cmax > 0 has a candidate")
                };
                let step = f.basic_cols.len();
                let piv = x[p];
                f.basic_cols.push(j);
                f.pivot_rows.push(p);
                f.row_step[p] = step;
                f.u_diag.push(piv);
                push_column(&mut f.u_ptr, &mut f.u_step, &mut f.u_val, u_entries);
                let mut lcol: Vec<(usize, f64)> = pattern
                    .iter()
                    .filter(|&&i| f.row_step[i] == usize::MAX && x[i] != 0.0)
                    .map(|&i| (i, x[i] / piv))
                    .collect();
                lcol.sort_unstable_by_key(|e| e.0);
                for (i, l) in lcol {
                    f.l_row.push(i);
                    f.l_val.push(l);
                }
                f.l_ptr.push(f.l_row.len());
            }
            for &i in &pattern {
                x[i] = 0.0;
                in_pattern[i] = false;
            }
        }
        f
    }

    /// The rank r: the number of pivots.
    pub fn rank(&self) -> usize {
        self.basic_cols.len()
    }

    /// Rows and columns of the factored matrix.
    pub fn shape(&self) -> (usize, usize) {
        (self.m, self.n)
    }

    /// ‖E‖_F, the Frobenius norm of the dropped entries: σ_{r+1} ≤ it (module docs).
    pub fn dropped_norm(&self) -> f64 {
        self.dropped2.sqrt()
    }

    /// The largest dropped entry.
    pub fn dropped_max(&self) -> f64 {
        self.dropped_max
    }

    /// The smallest |pivot| (infinite without pivots).
    pub fn min_pivot(&self) -> f64 {
        self.u_diag
            .iter()
            .fold(f64::INFINITY, |mn, p| mn.min(p.abs()))
    }

    /// Nonzeros of L and U (with the dependent columns' U).
    pub fn nnz(&self) -> (usize, usize) {
        (
            self.l_row.len(),
            self.u_step.len() + self.u_diag.len() + self.d_step.len(),
        )
    }

    /// The non-basic rows (one self-stress each), ascending.
    pub fn nonbasic_rows(&self) -> Vec<usize> {
        (0..self.m)
            .filter(|&i| self.row_step[i] == usize::MAX)
            .collect()
    }

    /// The pivot step of row i, if it is a pivot row.
    pub fn step_of_row(&self, i: usize) -> Option<usize> {
        let s = self.row_step[i];
        (s != usize::MAX).then_some(s)
    }

    /// y ← A₁₁⁻¹ y in place (y over the steps: entry s belongs to pivot row s on input and to
    /// basic column s on output).
    pub fn solve_a11(&self, y: &mut [f64]) {
        let r = self.rank();
        // L₁ y = b, forward by steps (rows of L that are pivot rows only)
        for s in 0..r {
            let ys = y[s];
            if ys == 0.0 {
                continue;
            }
            for p in self.l_ptr[s]..self.l_ptr[s + 1] {
                let t = self.row_step[self.l_row[p]];
                if t != usize::MAX {
                    y[t] -= self.l_val[p] * ys;
                }
            }
        }
        self.solve_u1(y);
    }

    /// y ← U₁⁻¹ y, backward by columns.
    fn solve_u1(&self, y: &mut [f64]) {
        for t in (0..self.rank()).rev() {
            let xt = y[t] / self.u_diag[t];
            y[t] = xt;
            if xt == 0.0 {
                continue;
            }
            for p in self.u_ptr[t]..self.u_ptr[t + 1] {
                y[self.u_step[p]] -= self.u_val[p] * xt;
            }
        }
    }

    /// y ← A₁₁⁻ᵀ y in place (input over basic columns, output over pivot rows, by steps).
    pub fn solve_a11_t(&self, y: &mut [f64]) {
        let r = self.rank();
        // U₁ᵀ z = c, forward
        for t in 0..r {
            let mut v = y[t];
            for p in self.u_ptr[t]..self.u_ptr[t + 1] {
                v -= self.u_val[p] * y[self.u_step[p]];
            }
            y[t] = v / self.u_diag[t];
        }
        self.solve_l1_t(y);
    }

    /// y ← L₁⁻ᵀ y, backward by steps.
    fn solve_l1_t(&self, y: &mut [f64]) {
        for s in (0..self.rank()).rev() {
            let mut v = y[s];
            for p in self.l_ptr[s]..self.l_ptr[s + 1] {
                let t = self.row_step[self.l_row[p]];
                if t != usize::MAX {
                    v -= self.l_val[p] * y[t];
                }
            }
            y[s] = v;
        }
    }

    /// The fundamental null vector of the `k`-th dependent column j: A z = E e_j, z_j = 1, z on
    /// the basic columns −U₁⁻¹ u_j, zero elsewhere (length n, original column numbers).
    pub fn null_vector(&self, k: usize) -> Vec<f64> {
        let mut y = vec![0.0; self.rank()];
        for p in self.d_ptr[k]..self.d_ptr[k + 1] {
            y[self.d_step[p]] = self.d_val[p];
        }
        self.solve_u1(&mut y);
        let mut z = vec![0.0; self.n];
        for (s, v) in y.into_iter().enumerate() {
            z[self.basic_cols[s]] = -v;
        }
        z[self.dependent_cols[k]] = 1.0;
        z
    }

    /// The multipliers of each non-basic row, (step, value) by row: the rows of L₂.
    pub fn l2_rows(&self) -> Vec<Vec<(usize, f64)>> {
        let mut out: Vec<Vec<(usize, f64)>> = vec![Vec::new(); self.m];
        for s in 0..self.rank() {
            for p in self.l_ptr[s]..self.l_ptr[s + 1] {
                let i = self.l_row[p];
                if self.row_step[i] == usize::MAX {
                    out[i].push((s, self.l_val[p]));
                }
            }
        }
        out
    }

    /// The fundamental null vector of Aᵀ of non-basic row k with its row of L₂ (`l2_row`, from
    /// [`RankLu::l2_rows`]): zᵀ A = e_kᵀ E, z_k = 1, z on the pivot rows −L₁⁻ᵀ l_k (length m).
    pub fn left_null_vector(&self, k: usize, l2_row: &[(usize, f64)]) -> Vec<f64> {
        let mut y = vec![0.0; self.rank()];
        for &(s, v) in l2_row {
            y[s] = v;
        }
        self.solve_l1_t(&mut y);
        let mut z = vec![0.0; self.m];
        for (s, v) in y.into_iter().enumerate() {
            z[self.pivot_rows[s]] = -v;
        }
        z[k] = 1.0;
        z
    }
}
