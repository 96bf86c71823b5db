//! The sparse path of the kinematic check (issue 14): Dcc of large models, from a
//! rank-revealing sparse LU instead of the dense SVD.
//!
//! 1. s₁ = ‖Dcc‖₂ by Lanczos on DccᵀDcc ([`crate::math::lanczos`]); the rank threshold is
//!    τ = rank_tol · s₁, the dense path's rule (theory.md §6.2).
//! 2. Π Dcc Q = [L₁; L₂][U₁ U₂] + E ([`RankLu`]), with the columns in a *peeling order* (next, the
//!    columns of the constraint row with the fewest columns not yet ordered: a structure is
//!    ordered from its supports outwards, so that each pivot row has few entries in columns
//!    still to come and the factors stay about as sparse as Dcc) and a column counted as
//!    dependent when its Schur-complement column has no entry above τ.
//! 3. The rank decision, stated with two bounds: the kept values s_r ≥ σ_min(A₁₁) (A₁₁ the r × r
//!    block of pivot rows and basic columns; the singular values of a submatrix interlace),
//!    estimated by Lanczos on A₁₁⁻ᵀA₁₁⁻¹ with the factors; the values counted as zero
//!    s_(r+1) ≤ ‖E‖_F (Dcc − E has rank r, Weyl). The decision is *certain* when both clear the
//!    threshold by the factor [`MARGIN`]: then the dense SVD would count the same rank.
//! 4. Bases: one motion per dependent column j, [−U₁⁻¹ u_j; e_j], and one self-stress per
//!    non-basic row k, [−L₁⁻ᵀ l_k; e_k]: the fundamental bases of the null spaces of Dcc and Dccᵀ
//!    (not orthogonal; any basis of a null space is as valid as another). The defining column
//!    and row of every state are reported; the vectors of the first
//!    [`super::CheckOptions::max_listed_states`] of each kind are computed and listed.

use super::{
    columns, euler_shape, present_motion, present_self_stress, rate_rows, row_defs, rows,
    CheckOptions, ConstraintAnalysis, KinematicsError, SparseRow, Table1,
};
use crate::linalg::LinalgError;
use crate::math::lanczos::largest_eigenvalue;
use crate::math::sparse_lu::rank::{Csc, RankLu};
use crate::model::{Model, Partition};
use faer::Mat;

/// The bounds of a certain decision must clear the threshold by this factor.
pub const MARGIN: f64 = 2.0;

/// Lanczos steps at most, and the relative residual at which they stop.
const LANCZOS_STEPS: usize = 40;
const LANCZOS_TOL: f64 = 1e-8;

/// The rank decision and the bases of the sparse path (module docs).
#[derive(Clone, Debug)]
pub struct SparseDecision {
    /// s₁ = ‖Dcc‖₂ (Lanczos estimate, from below; converged to `s1_rel_residual`).
    pub s1: f64,
    /// Relative residual of the s₁ estimate.
    pub s1_rel_residual: f64,
    /// Estimate of σ_min(A₁₁), a lower bound of s_r (None when r = 0).
    pub s_r_lower: Option<f64>,
    /// Relative residual of that estimate.
    pub s_r_rel_residual: f64,
    /// ‖E‖_F, an upper bound of s_(r+1) (None when r = min(m, n): no value is counted as zero).
    pub s_r1_upper: Option<f64>,
    /// Both bounds clear the threshold by [`MARGIN`].
    pub certain: bool,
    /// The column of each motion (the dependent columns), ascending.
    pub motion_cols: Vec<usize>,
    /// The row of each self-stress state (the non-basic rows), ascending.
    pub self_stress_rows: Vec<usize>,
    /// Nonzeros of Dcc, L and U.
    pub nnz: (usize, usize, usize),
}

impl SparseDecision {
    /// The lower bound of the gap s_r / s_(r+1), when both bounds exist (infinite when
    /// ‖E‖_F = 0).
    pub fn gap_lower(&self) -> Option<f64> {
        match (self.s_r_lower, self.s_r1_upper) {
            (Some(lo), Some(up)) => Some(if up > 0.0 { lo / up } else { f64::INFINITY }),
            _ => None,
        }
    }
}

/// Dcc as compressed columns, from its sparse rows.
struct CscOwned {
    m: usize,
    n: usize,
    ptr: Vec<usize>,
    row: Vec<usize>,
    val: Vec<f64>,
}

impl CscOwned {
    fn from_rows(rows: &[SparseRow], n: usize) -> Self {
        let mut count = vec![0usize; n + 1];
        for r in rows {
            for &(j, _) in r {
                count[j + 1] += 1;
            }
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let ptr = count.clone();
        let nnz = ptr[n];
        let (mut row, mut val) = (vec![0; nnz], vec![0.0; nnz]);
        let mut next = count;
        for (i, r) in rows.iter().enumerate() {
            for &(j, v) in r {
                row[next[j]] = i;
                val[next[j]] = v;
                next[j] += 1;
            }
        }
        Self {
            m: rows.len(),
            n,
            ptr,
            row,
            val,
        }
    }
    fn view(&self) -> Csc<'_> {
        Csc {
            m: self.m,
            n: self.n,
            ptr: &self.ptr,
            row: &self.row,
            val: &self.val,
        }
    }
}

/// The peeling order of the columns (module docs): repeatedly the constraint row with the
/// fewest columns not yet ordered (the earliest such row on ties), its columns appended in
/// ascending order.
pub fn peeling_order(rows: &[SparseRow], n: usize) -> Vec<usize> {
    let m = rows.len();
    let mut rows_of: Vec<Vec<usize>> = vec![Vec::new(); n];
    for (i, r) in rows.iter().enumerate() {
        for &(j, _) in r {
            rows_of[j].push(i);
        }
    }
    let mut left: Vec<usize> = rows.iter().map(|r| r.len()).collect();
    let maxc = left.iter().copied().max().unwrap_or(0);
    // buckets by count, each a FIFO with lazy deletion
    let mut buckets: Vec<std::collections::VecDeque<usize>> =
        vec![std::collections::VecDeque::new(); maxc + 1];
    for i in 0..m {
        buckets[left[i]].push_back(i);
    }
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut lowest = 1;
    while order.len() < n {
        // the row with the fewest open columns (≥ 1)
        let mut pick = None;
        let mut c = lowest.max(1);
        while c <= maxc {
            while let Some(i) = buckets[c].pop_front() {
                if left[i] == c {
                    pick = Some(i);
                    break;
                }
            }
            if pick.is_some() {
                break;
            }
            c += 1;
        }
        lowest = c;
        let new_cols: Vec<usize> = match pick {
            Some(i) => rows[i]
                .iter()
                .map(|e| e.0)
                .filter(|&j| !placed[j])
                .collect(),
            // columns in no row: in index order
            None => (0..n).filter(|&j| !placed[j]).collect(),
        };
        for j in new_cols {
            placed[j] = true;
            order.push(j);
            for &i in &rows_of[j] {
                left[i] -= 1;
                if left[i] > 0 {
                    buckets[left[i]].push_back(i);
                    lowest = lowest.min(left[i]);
                }
            }
        }
    }
    order
}

/// y ← Dcc x and z ← Dccᵀ y, sequential.
fn normal_product(rows: &[SparseRow], x: &[f64], z: &mut [f64]) {
    z.iter_mut().for_each(|v| *v = 0.0);
    for r in rows {
        let y: f64 = r.iter().map(|&(j, v)| v * x[j]).sum();
        if y != 0.0 {
            for &(j, v) in r {
                z[j] += v * y;
            }
        }
    }
}

/// The kinematic analysis on the sparse path (module docs); `check` dispatches here.
pub fn check_sparse(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    opts: &CheckOptions,
) -> Result<ConstraintAnalysis, KinematicsError> {
    let cols = columns(model, partition, x);
    let rows = rows(model, partition);
    let (m, n) = (rows.len(), cols.len());
    let dcc = rate_rows(model, x, &cols, &row_defs(model, &rows));
    for (i, r) in dcc.iter().enumerate() {
        if let Some(&(j, _)) = r.iter().find(|e| !e.1.is_finite()) {
            return Err(LinalgError::NonFinite {
                what: "Dcc",
                row: i,
                col: j,
            }
            .into());
        }
    }
    // s₁ and the threshold
    let e1 = largest_eigenvalue(
        n,
        |v, out| normal_product(&dcc, v, out),
        LANCZOS_STEPS,
        LANCZOS_TOL,
    );
    let s1 = e1.value.max(0.0).sqrt();
    let tol = opts.rank_tol * s1;
    // the rank-revealing factorisation
    let csc = CscOwned::from_rows(&dcc, n);
    let order = peeling_order(&dcc, n);
    let lu = RankLu::factor(csc.view(), &order, tol);
    let r = lu.rank();
    // σ_min(A₁₁) by Lanczos on (A₁₁ A₁₁ᵀ)⁻¹
    let (s_r_lower, s_r_res) = if r > 0 {
        let e = largest_eigenvalue(
            r,
            |v, out| {
                out.copy_from_slice(v);
                lu.solve_a11(out);
                lu.solve_a11_t(out);
            },
            LANCZOS_STEPS,
            LANCZOS_TOL,
        );
        let lam = e.value.max(f64::MIN_POSITIVE);
        (Some(1.0 / lam.sqrt()), e.residual / lam)
    } else {
        (None, 0.0)
    };
    let s_r1_upper = (r < m.min(n)).then(|| lu.dropped_norm());
    let certain = s_r_lower.is_none_or(|lo| lo > MARGIN * tol)
        && s_r1_upper.is_none_or(|up| up * MARGIN < tol);
    let mut motion_cols = lu.dependent_cols.clone();
    motion_cols.sort_unstable();
    let self_stress_rows = lu.nonbasic_rows();
    // the listed states
    let dep_index: std::collections::HashMap<usize, usize> = lu
        .dependent_cols
        .iter()
        .enumerate()
        .map(|(k, &j)| (j, k))
        .collect();
    let n_mot = motion_cols.len().min(opts.max_listed_states);
    let n_ss = self_stress_rows.len().min(opts.max_listed_states);
    let mut null_v = Mat::zeros(n, n_mot);
    let mut motions = Vec::with_capacity(n_mot);
    for (c, j) in motion_cols.iter().take(n_mot).enumerate() {
        let z = lu.null_vector(dep_index[j]);
        motions.push(present_motion(model, &cols, &z));
        z.iter().enumerate().for_each(|(i, v)| null_v[(i, c)] = *v);
    }
    let names = model.node_names();
    let mut null_u = Mat::zeros(m, n_ss);
    let mut self_stresses = Vec::with_capacity(n_ss);
    if n_ss > 0 {
        let l2 = lu.l2_rows();
        for (c, &k) in self_stress_rows.iter().take(n_ss).enumerate() {
            let z = lu.left_null_vector(k, &l2[k]);
            self_stresses.push(present_self_stress(model, &names, &rows, &z));
            z.iter().enumerate().for_each(|(i, v)| null_u[(i, c)] = *v);
        }
    }
    let nnz_l_u = lu.nnz();
    Ok(ConstraintAnalysis {
        case: Table1::classify(m, n, r),
        euler_shape: euler_shape(model, partition),
        rows,
        cols,
        Dcc: Mat::zeros(0, 0),
        singular_values: Vec::new(),
        tol,
        rank: r,
        null_v,
        null_u,
        svd_u: Mat::zeros(0, 0),
        svd_v: Mat::zeros(0, 0),
        motions,
        self_stresses,
        sparse: Some(SparseDecision {
            s1,
            s1_rel_residual: if e1.value > 0.0 {
                e1.residual / e1.value
            } else {
                0.0
            },
            s_r_lower,
            s_r_rel_residual: s_r_res,
            s_r1_upper,
            certain,
            motion_cols,
            self_stress_rows,
            nnz: (csc.ptr[n], nnz_l_u.0, nnz_l_u.1),
        }),
    })
}

/// The repair advice of the sparse path: for each listed state the change that removes it by
/// construction — release the non-basic row of a self-stress state, fix (or take as
/// generalised) the dependent coordinate of a motion. The pivot rows and basic columns stay,
/// so σ_min(A₁₁) still bounds the kept singular values from below and the rank stays r; the
/// singular values counted as zero can only decrease (a row or column less). Given only when
/// the decision is certain (else no suggestion is verified). A rotation coordinate of a turned
/// node, whose fixing is not the removal of its column ([`super::coordinate_constraint`]), is
/// not suggested.
pub fn advise_sparse(
    model: &Model,
    x: &[f64],
    a: &ConstraintAnalysis,
    sp: &SparseDecision,
    max_per_state: usize,
) -> Vec<super::advice::StateAdvice> {
    use super::advice::{Action, StateAdvice, Suggestion};
    let names = model.node_names();
    let (mot, ss) = (a.n_motions(), a.n_self_stresses());
    let give = max_per_state > 0 && sp.certain;
    let weight = |v: &[f64], i: usize| {
        let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if nv > 0.0 {
            v[i].abs() / nv
        } else {
            0.0
        }
    };
    let mut out = Vec::new();
    for (k, &i) in sp
        .self_stress_rows
        .iter()
        .take(a.self_stresses.len())
        .enumerate()
    {
        let mut suggestions = Vec::new();
        if give {
            let u: Vec<f64> = (0..a.m()).map(|r| a.null_u[(r, k)]).collect();
            suggestions.push(Suggestion {
                action: Action::remove_row(model, &names, &a.rows[i]),
                weight: weight(&u, i),
                motions_after: mot,
                self_stresses_after: ss - 1,
                designer: None,
            });
        }
        out.push(StateAdvice {
            kind: "self_stress",
            state: k,
            suggestions,
        });
    }
    for (k, &j) in sp.motion_cols.iter().take(a.motions.len()).enumerate() {
        let mut suggestions = Vec::new();
        let row = super::coordinate_constraint(model, &a.cols, x, j);
        if give && row.len() == 1 && row[0].0 == j {
            let v: Vec<f64> = (0..a.n()).map(|c| a.null_v[(c, k)]).collect();
            let col = &a.cols[j];
            suggestions.push(Suggestion {
                action: Action::FixOrInputCoordinate {
                    node: names[col.node].clone(),
                    dof: col.dof,
                },
                weight: weight(&v, j),
                motions_after: mot - 1,
                self_stresses_after: ss,
                designer: None,
            });
        }
        out.push(StateAdvice {
            kind: "motion",
            state: k,
            suggestions,
        });
    }
    out
}

/// The sparse path's verification that a row w added to Dcc raises its rank by one (one motion
/// fewer, the self-stresses unchanged), without a new factorisation.
///
/// With N the listed motions (a subspace of the null space of Dcc), q = ‖P_N w‖ and
/// s_r ≥ `s_r_lower`: on the r + 1 dimensional space of the row space of Dcc plus P_N w,
/// ‖[Dcc; wᵀ] z‖² ≥ s_r² q² / (s_r² + ‖w‖²) ‖z‖² (the smallest eigenvalue of the 2 × 2 form
/// [[s_r² + c², c q], [c q, q²]], |c| ≤ ‖P_R w‖, has the determinant s_r² q² and a trace at
/// most s_r² + ‖w‖²), so by Courant–Fischer σ_(r+1)([Dcc; wᵀ]) ≥ s_r q / √(s_r² + ‖w‖²);
/// σ_(r+2) ≤ s_(r+1) (interlacing) stays below the threshold, which rises at most to
/// rank_tol √(s₁² + ‖w‖²). The rank is r + 1 for certain when the lower bound clears that by
/// [`MARGIN`].
pub struct AddedRowBound {
    /// The listed motions, n × k.
    null: Mat<f64>,
    /// Cholesky factor of NᵀN (lower), k × k.
    chol: Mat<f64>,
    s_r: f64,
    s1: f64,
    rank_tol: f64,
}

impl AddedRowBound {
    /// `None` when the decision of `a` is not certain, its rank is zero or no motion is listed:
    /// then no added row is verified.
    pub fn new(a: &ConstraintAnalysis, sp: &SparseDecision, rank_tol: f64) -> Option<Self> {
        let s_r = sp.s_r_lower?;
        let k = a.null_v.ncols();
        if !sp.certain || k == 0 {
            return None;
        }
        let null = a.null_v.clone();
        let gram = null.transpose() * &null;
        // Cholesky of the small k × k Gram matrix (the listed motions are independent)
        let mut chol = Mat::<f64>::zeros(k, k);
        for j in 0..k {
            let d = gram[(j, j)] - (0..j).map(|p| chol[(j, p)] * chol[(j, p)]).sum::<f64>();
            if d.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            let d = d.sqrt();
            chol[(j, j)] = d;
            for i in j + 1..k {
                let s = gram[(i, j)] - (0..j).map(|p| chol[(i, p)] * chol[(j, p)]).sum::<f64>();
                chol[(i, j)] = s / d;
            }
        }
        Some(Self {
            null,
            chol,
            s_r,
            s1: sp.s1,
            rank_tol,
        })
    }

    /// q = ‖P_N w‖ of the row w.
    pub fn null_part(&self, w: &SparseRow) -> f64 {
        let k = self.null.ncols();
        // b = Nᵀ w; q² = bᵀ (NᵀN)⁻¹ b = ‖L⁻¹ b‖²
        let mut y: Vec<f64> = (0..k)
            .map(|i| w.iter().map(|&(j, v)| v * self.null[(j, i)]).sum())
            .collect();
        for i in 0..k {
            let s: f64 = (0..i).map(|p| self.chol[(i, p)] * y[p]).sum();
            y[i] = (y[i] - s) / self.chol[(i, i)];
        }
        y.iter().map(|v| v * v).sum::<f64>().sqrt()
    }

    /// The lower bound s_r q / √(s_r² + ‖w‖²) of σ_(r+1)([Dcc; wᵀ]).
    pub fn lower_bound(&self, w: &SparseRow) -> f64 {
        let w2: f64 = w.iter().map(|e| e.1 * e.1).sum();
        self.s_r * self.null_part(w) / (self.s_r * self.s_r + w2).sqrt()
    }

    /// True when adding the row w certainly raises the rank by one.
    pub fn raises_rank(&self, w: &SparseRow) -> bool {
        let w2: f64 = w.iter().map(|e| e.1 * e.1).sum();
        self.lower_bound(w) > MARGIN * self.rank_tol * (self.s1 * self.s1 + w2).sqrt()
    }
}
