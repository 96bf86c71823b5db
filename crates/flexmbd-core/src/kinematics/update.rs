//! The counts after a one-row or one-column change of Dcc, from the SVD already computed: the
//! predictions and the verification of the repair advice without a new analysis per candidate.
//!
//! With Dcc = U Σ Vᵀ (paper eq. 11), rank r, U₀ = U[:, r..] and V₀ = V[:, r..] (theory.md §6.5):
//!
//! - **Removing row i** (releasing a fixed deformation, making an input dependent) keeps the rank
//!   iff row i lies in the span of the other rows, i.e. iff some self-stress has a non-zero
//!   i-th entry: ‖U₀[i, :]‖ ≠ 0 (then m − r drops by one and n − r stays), else the rank drops
//!   (n − r grows by one).
//! - **Removing column j** (fixing a coordinate or taking it as generalised) keeps the rank iff
//!   some motion has vⱼ ≠ 0: ‖V₀[j, :]‖ ≠ 0 (n − r drops by one), else the rank drops (m − r
//!   grows by one).
//! - **Adding a row b** (fixing a free deformation or taking it as generalised) raises the rank
//!   iff b has a component in the null space: ‖V₀ᵀ b‖ ≠ 0 (n − r drops by one), else m − r
//!   grows by one.
//!
//! [`Updater::predict`] decides these from the null bases alone in O(1) per candidate (after
//! one O(m (m − r) + n (n − r)) pass), with margins around the rank threshold: where the
//! decision is close it answers [`Prediction::Uncertain`]. [`Updater::counts_after`] is the
//! verification: the exact number of singular values of the changed Dcc above its own threshold
//! rank_tol · s₁' (the rule of [`super::check`]), from a rank-one update of the SVD in O(p)
//! (p = min(m, n); O(nnz(b) · n) more for an added row), without forming the changed matrix.
//!
//! The count. Removing row i: the changed Dcc has the singular values of (U Σ) without row i,
//! whose Gram matrix is Σ (I − u uᵀ) Σ with u = U[i, :p] (rows of U are orthonormal). By
//! Sylvester's law of inertia (congruence with Σ⁻¹) and the Haynsworth inertia formula,
//!
//!   #{σ' > τ} = #{s_k > τ} − 1 + [c² − Σ_k u_k² τ² / (s_k² − τ²) > 0],
//!
//! with c² = 1 − ‖u‖² = Σ_{k ≥ p} U[i, k]² taken from the null columns themselves, so no
//! cancellation near the threshold. Removing column j is the same with u = V[j, :p]. Adding a row
//! b with w = Vᵀ b and g² = Σ_{k ≥ p} w_k²:
//!
//!   #{σ' > τ} = #{s_k > τ} + [g² − τ² − Σ_k w_k² τ² / (s_k² − τ²) > 0].
//!
//! (k runs over the positive singular values.) The threshold τ = rank_tol · s₁' uses the largest
//! singular value s₁' of the changed matrix, found by bisection on the same count where the
//! bracket (s₂ ≤ s₁' ≤ s₁ for a removal, s₁ ≤ s₁' ≤ (s₁² + ‖b‖²)^½ for an added row) changes
//! the count.

use super::{ConstraintAnalysis, KinematicsError, SparseRow};
use faer::Mat;
use std::borrow::Cow;

/// A change of Dcc by one row or one column.
#[derive(Clone, Debug)]
pub enum Change {
    /// Delete row i (release a fixed deformation, or make an input deformation dependent).
    RemoveRow(usize),
    /// Delete column j (fix a coordinate, or take it as generalised).
    RemoveColumn(usize),
    /// Append the row b (fix a free deformation, or take it as generalised; fix a rotation
    /// coordinate whose direction is not a column's, [`super::coordinate_constraint`]).
    AddRow(SparseRow),
}

/// The counts (motions n − r, self-stresses m − r) a change leads to, as predicted from the null
/// bases.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Prediction {
    /// The decision is clear by the margins: these counts.
    Certain((usize, usize)),
    /// Too close to the rank threshold to tell from the null bases: verify.
    Uncertain,
}

/// Margin of the predictions: a bound must clear the threshold by this factor.
const MARGIN: f64 = 4.0;

/// Predictions and exact rank updates of one analysis.
pub struct Updater<'a> {
    a: &'a ConstraintAnalysis,
    /// U and V of Dcc.
    u: Cow<'a, Mat<f64>>,
    v: Cow<'a, Mat<f64>>,
    rank_tol: f64,
    /// ‖U₀[i, :]‖ per row.
    row_null: Vec<f64>,
    /// ‖V₀[j, :]‖ per column.
    col_null: Vec<f64>,
    /// Number of positive singular values.
    p: usize,
}

impl<'a> Updater<'a> {
    /// Prepare the predictions of `a` (O(m (m − r) + n (n − r)); a full SVD if the analysis
    /// left the factors out, [`ConstraintAnalysis::factors`]).
    pub fn new(a: &'a ConstraintAnalysis, rank_tol: f64) -> Result<Self, KinematicsError> {
        let norm_rows = |m: &faer::Mat<f64>| -> Vec<f64> {
            (0..m.nrows())
                .map(|i| {
                    (0..m.ncols())
                        .map(|k| m[(i, k)] * m[(i, k)])
                        .sum::<f64>()
                        .sqrt()
                })
                .collect()
        };
        let p = a.singular_values.iter().filter(|&&s| s > 0.0).count();
        let (u, v) = a.factors()?;
        Ok(Self {
            a,
            u,
            v,
            rank_tol,
            row_null: norm_rows(&a.null_u),
            col_null: norm_rows(&a.null_v),
            p,
        })
    }

    fn before(&self) -> (usize, usize) {
        (self.a.n_motions(), self.a.n_self_stresses())
    }

    fn s(&self, k: usize) -> f64 {
        self.a.singular_values.get(k).copied().unwrap_or(0.0)
    }

    /// The counts after `change`, predicted from the null bases (O(1) for removals, O(nnz(b)
    /// (n − r)) for an added row).
    pub fn predict(&self, change: &Change) -> Prediction {
        let (mot, ss) = self.before();
        let r = self.a.rank;
        let tol = self.a.tol;
        // the small singular values must stay below any threshold the change can give
        let null_clear = |tol_low: f64| self.s(r) * MARGIN < tol_low || self.s(r) == 0.0;
        match change {
            Change::RemoveRow(_) | Change::RemoveColumn(_) => {
                let (c, keep, drop) = match change {
                    Change::RemoveRow(i) => (
                        self.row_null[*i],
                        (mot, ss.saturating_sub(1)),
                        (mot + 1, ss),
                    ),
                    Change::RemoveColumn(j) => (
                        self.col_null[*j],
                        (mot.saturating_sub(1), ss),
                        (mot, ss + 1),
                    ),
                    Change::AddRow(_) => unreachable!("matched above"),
                };
                if r == 0 {
                    return Prediction::Certain(keep);
                }
                // the r kept singular values become ≥ c s_r, and one of them ≤ c s₁; the
                // threshold lies in [rank_tol s₂, rank_tol s₁]
                let tol_low = self.rank_tol * self.s(1);
                if !null_clear(tol_low) {
                    return Prediction::Uncertain;
                }
                if c * self.s(r - 1) > MARGIN * tol {
                    Prediction::Certain(keep)
                } else if c * self.s(0) * MARGIN < tol_low {
                    Prediction::Certain(drop)
                } else {
                    Prediction::Uncertain
                }
            }
            Change::AddRow(b) => {
                let nb = b.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt();
                let nv = &self.a.null_v;
                let g = (0..nv.ncols())
                    .map(|k| {
                        let w: f64 = b.iter().map(|&(j, v)| v * nv[(j, k)]).sum();
                        w * w
                    })
                    .sum::<f64>()
                    .sqrt();
                let (up, same) = ((mot.saturating_sub(1), ss), (mot, ss + 1));
                if nb == 0.0 {
                    return Prediction::Certain(same);
                }
                let tol_high = self.rank_tol * (self.s(0).powi(2) + nb * nb).sqrt();
                if !null_clear(tol) {
                    return Prediction::Uncertain;
                }
                // the new singular value lies in [g s_r / (s_r² + ‖b‖²)^½, g]
                let sr = if r == 0 { f64::INFINITY } else { self.s(r - 1) };
                let lower = if sr.is_infinite() {
                    g
                } else {
                    g * sr / (sr * sr + nb * nb).sqrt()
                };
                if lower > MARGIN * tol_high && mot > 0 {
                    Prediction::Certain(up)
                } else if g * MARGIN < tol {
                    Prediction::Certain(same)
                } else {
                    Prediction::Uncertain
                }
            }
        }
    }

    /// The exact counts (motions, self-stresses) after `change`: the singular values of the
    /// changed Dcc above rank_tol · s₁' counted by a rank-one update of the SVD (module docs).
    pub fn counts_after(&self, change: &Change) -> (usize, usize) {
        let (m, n) = (self.a.m(), self.a.n());
        let p = self.p;
        let s = &self.a.singular_values[..p];
        match change {
            Change::RemoveRow(_) | Change::RemoveColumn(_) => {
                let (basis, idx, m2, n2) = match change {
                    Change::RemoveRow(i) => (&*self.u, *i, m - 1, n),
                    Change::RemoveColumn(j) => (&*self.v, *j, m, n - 1),
                    Change::AddRow(_) => unreachable!("matched above"),
                };
                if m2 == 0 || n2 == 0 {
                    return (n2, m2);
                }
                let u: Vec<f64> = (0..p).map(|k| basis[(idx, k)]).collect();
                let c2: f64 = (p..basis.ncols()).map(|k| basis[(idx, k)].powi(2)).sum();
                let count = |tau: f64| -> usize {
                    let tau = nudge(tau, s);
                    let above = s.iter().filter(|&&v| v > tau).count();
                    let t2 = tau * tau;
                    let phi = c2
                        - u.iter()
                            .zip(s)
                            .map(|(&uk, &sk)| uk * uk * t2 / ((sk - tau) * (sk + tau)))
                            .sum::<f64>();
                    (above + usize::from(phi > 0.0)).saturating_sub(1)
                };
                let lo = if p > 1 { s[1] } else { 0.0 };
                let hi = if p > 0 { s[0] } else { 0.0 };
                let r2 = self.count_with_own_threshold(&count, lo, hi);
                (n2 - r2, m2 - r2)
            }
            Change::AddRow(b) => {
                let v = &*self.v;
                let mut w = vec![0.0; n];
                for &(j, bj) in b {
                    for (k, wk) in w.iter_mut().enumerate() {
                        *wk += bj * v[(j, k)];
                    }
                }
                let g2: f64 = w[p..].iter().map(|x| x * x).sum();
                let wr = &w[..p];
                let count = |tau: f64| -> usize {
                    let tau = nudge(tau, s);
                    let above = s.iter().filter(|&&v| v > tau).count();
                    let t2 = tau * tau;
                    let psi = g2
                        - t2
                        - wr.iter()
                            .zip(s)
                            .map(|(&wk, &sk)| wk * wk * t2 / ((sk - tau) * (sk + tau)))
                            .sum::<f64>();
                    above + usize::from(psi > 0.0)
                };
                let nb2: f64 = b.iter().map(|e| e.1 * e.1).sum();
                let lo = if p > 0 { s[0] } else { 0.0 };
                let hi = (lo * lo + nb2).sqrt();
                let r2 = self.count_with_own_threshold(&count, lo, hi);
                (n - r2, m + 1 - r2)
            }
        }
    }

    /// The count above rank_tol · s₁', with s₁' ∈ [lo, hi] the largest singular value of the
    /// changed matrix: bisection on `count` (the number of singular values above a level) only
    /// where the bracket changes the answer.
    fn count_with_own_threshold(&self, count: &dyn Fn(f64) -> usize, lo: f64, hi: f64) -> usize {
        let t = self.rank_tol;
        let (c_lo, c_hi) = (count(t * lo), count(t * hi));
        if c_lo == c_hi || hi <= 0.0 {
            return c_hi;
        }
        // s₁' = sup { μ : count(μ) ≥ 1 } in [lo, hi]
        let (mut a, mut b) = (lo, hi);
        for _ in 0..100 {
            let mid = 0.5 * (a + b);
            if mid <= a || mid >= b {
                break;
            }
            if count(mid) >= 1 {
                a = mid;
            } else {
                b = mid;
            }
        }
        count(t * a)
    }
}

/// A level that equals a singular value exactly would make the inertia formula divide by zero;
/// move it up by one ulp (the count is of values strictly above the level either way).
fn nudge(tau: f64, s: &[f64]) -> f64 {
    let mut t = tau;
    while s.contains(&t) {
        t = f64::from_bits(t.to_bits() + 1);
    }
    t
}
