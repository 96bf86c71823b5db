//! Kinematic (constraint) analysis: is the mechanism exactly constrained?
//!
//! Dcc = [∂𝒟^o/∂x^c; ∂𝒟^m/∂x^c] (paper eq. (9)): rows are the fixed (e^o) and input (e^m)
//! deformations, columns the dependent coordinates x^c. Its SVD Dcc = U Σ Vᵀ (paper eq. (11))
//! gives the numerical rank r; n − r kinematically indeterminate motions are the null columns of
//! V and m − r statically indeterminate self-stress states the null columns of U (paper §3,
//! theory.md §6). The six cases are those of the paper's Table 1 ([`Table1`]).
//!
//! Rotations. x holds four Euler parameters per rotational node (SPACAR's choice, used by the
//! nonlinear analyses). The SVD is taken of Dcc expressed in *velocity* coordinates: a column per
//! free translation and a column per free rotation component ω (global axes), with
//! λ̇ = ½ Λ̄ᵀ(λ) ω; the Euler normalisation rows then vanish identically and are dropped. This
//! is the paper's counting (six coordinates per node) and gives physically meaningful singular
//! values and motions (rad/s, m/s). The counts n − r and m − r are the same as for SPACAR's
//! Euler-parameter Dcc (theory.md §2.4); both sizes are reported. See docs/rotations.md.

pub mod advice;
pub mod classify;
pub mod freedom;
mod present;
pub mod screw;
pub mod sparse;
pub mod update;
mod wires;

pub use present::{normalize_signed, present_motion, present_self_stress, PRESENT_ZERO};

use crate::assembly::gather;
use crate::elements::{ElementKind, NodeId};
use crate::linalg::{numerical_rank, svd, svd_scratch_bytes, LinalgError};
use crate::math::{dot, lambda_bar};
use crate::model::{CoordKind, DefKind, Dof, Model, Partition};
use faer::Mat;
use serde::Serialize;

/// Options of the kinematic analysis.
#[derive(Clone, Copy, Debug)]
pub struct CheckOptions {
    /// Relative rank tolerance: sᵢ counts as zero when sᵢ ≤ rank_tol · s₁. Default √ε, the test
    /// SPACAR Light uses (theory.md §6.2).
    pub rank_tol: f64,
    /// Memory limit of the dense analysis in bytes: Dcc, its full SVD factors U and V, the null
    /// bases and the SVD's workspace ([`dense_bytes`]). A larger model stops with
    /// [`KinematicsError::TooLarge`] before anything is allocated. Default 4 GiB.
    pub max_dense_bytes: u64,
    /// Dense SVD or sparse rank-revealing LU ([`CheckMethod`]); default automatic by size.
    pub method: CheckMethod,
    /// Sparse path: the motions and self-stress states whose vectors are computed and listed,
    /// at most, of each kind (every state's defining column or row is reported). Default
    /// [`DEFAULT_MAX_LISTED_STATES`]. The dense path lists them all.
    pub max_listed_states: usize,
}

/// How [`check`] finds the rank and the null spaces of Dcc.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CheckMethod {
    /// Dense when the SVD is quick ([`DENSE_WORK_MAX`], [`SPARSE_ABOVE`]) and fits in
    /// [`CheckOptions::max_dense_bytes`], else sparse; a sparse decision that is not certain is
    /// made again by the dense SVD when the matrix has at most [`SPARSE_ABOVE`] rows and
    /// columns and fits ([`CheckMethod::dense_fallback`]).
    #[default]
    Auto,
    /// The dense SVD (all singular values, orthonormal null bases, advice by rank updates).
    Dense,
    /// The sparse rank-revealing LU ([`sparse`]): rank with bounds, fundamental null bases.
    Sparse,
}

/// [`CheckMethod::Auto`] takes the sparse path when Dcc has more rows or columns than this, and
/// never falls back to the dense SVD. (A dense full SVD of a 2,500 × 2,500 matrix takes several
/// seconds on two cores and grows with the cube of the size; the sparse path of a truss lattice
/// of that size about 0.05 s.)
pub const SPARSE_ABOVE: usize = 2500;

/// [`CheckMethod::Auto`] tries the sparse path first when the dense SVD's work m·n·min(m, n)
/// exceeds this: about 0.7 s for the singular values alone of a square Dcc on two cores
/// (1,998 × 1,998, 8·10⁹: 2.7 s; the sparse path of the same strip 0.02 s, bench/README.md §3).
pub const DENSE_WORK_MAX: u128 = 2_000_000_000;

/// The default of [`CheckOptions::max_listed_states`].
pub const DEFAULT_MAX_LISTED_STATES: usize = 50;

impl CheckMethod {
    /// The path taken first for an m × n Dcc.
    pub fn resolve(self, m: usize, n: usize, max_dense_bytes: u64) -> CheckMethod {
        let work = m as u128 * n as u128 * m.min(n) as u128;
        match self {
            CheckMethod::Auto
                if m.max(n) > SPARSE_ABOVE
                    || work > DENSE_WORK_MAX
                    || dense_bytes(m, n, max_dense_bytes) > max_dense_bytes =>
            {
                CheckMethod::Sparse
            }
            CheckMethod::Auto => CheckMethod::Dense,
            other => other,
        }
    }

    /// Whether a sparse decision that is not certain is made again by the dense SVD: the
    /// automatic choice, on a Dcc of at most [`SPARSE_ABOVE`] rows and columns whose dense
    /// analysis fits in `max_dense_bytes`.
    pub fn dense_fallback(self, m: usize, n: usize, max_dense_bytes: u64) -> bool {
        self == CheckMethod::Auto
            && m.max(n) <= SPARSE_ABOVE
            && dense_bytes(m, n, max_dense_bytes) <= max_dense_bytes
    }
}

/// The default of [`CheckOptions::max_dense_bytes`]: 4 GiB.
pub const DEFAULT_MAX_DENSE_BYTES: u64 = crate::linalg::DEFAULT_MAX_DENSE_BYTES;

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            rank_tol: f64::EPSILON.sqrt(),
            max_dense_bytes: DEFAULT_MAX_DENSE_BYTES,
            method: CheckMethod::Auto,
            max_listed_states: DEFAULT_MAX_LISTED_STATES,
        }
    }
}

/// A column of the velocity-form Dcc: one free velocity component of a node.
#[derive(Clone, Debug, Serialize)]
pub struct Column {
    /// Node index.
    pub node: NodeId,
    /// Translation x/y/z, or the rotation component rx/ry/rz it stands for.
    pub dof: Dof,
    /// For rotations: the unit angular-velocity direction of this column (global axes); for
    /// translations the unit axis.
    pub dir: [f64; 3],
    /// The Euler-parameter rate per unit velocity, λ̇ = ½ Λ̄ᵀ dir (rotations only).
    #[serde(skip)]
    pub lambda_rate: [f64; 4],
}

/// A row of Dcc: one fixed or input deformation.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Row {
    /// Element index.
    pub element: usize,
    /// Mode, 0-based.
    pub mode: usize,
    /// Fixed (e^o) or input (e^m).
    pub kind: DefKind,
}

/// The six cases of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Table1 {
    /// m = n = r: statically and kinematically determinate (exact constraint).
    SquareRegular,
    /// m = n, r < m: both indeterminate.
    SquareSingular,
    /// m > n, r = n: statically indeterminate (over-constrained), kinematically determinate.
    TallFullRank,
    /// m > n, r < n: both indeterminate.
    TallRankDeficient,
    /// m < n, r = m: statically determinate, kinematically indeterminate (under-constrained).
    WideFullRank,
    /// m < n, r < m: both indeterminate.
    WideRankDeficient,
}

impl Table1 {
    /// Classify by the shape and rank of Dcc.
    pub fn classify(m: usize, n: usize, r: usize) -> Self {
        use std::cmp::Ordering::*;
        match (m.cmp(&n), r == m.min(n)) {
            (Equal, true) => Table1::SquareRegular,
            (Equal, false) => Table1::SquareSingular,
            (Greater, true) => Table1::TallFullRank,
            (Greater, false) => Table1::TallRankDeficient,
            (Less, true) => Table1::WideFullRank,
            (Less, false) => Table1::WideRankDeficient,
        }
    }
    /// Row number in the paper's Table 1 (1–6).
    pub fn row(self) -> usize {
        self as usize + 1
    }
    /// One-line description.
    pub fn describe(self) -> &'static str {
        match self {
            Table1::SquareRegular => {
                "exactly constrained: statically and kinematically determinate"
            }
            Table1::SquareSingular => {
                "square but singular: statically and kinematically indeterminate"
            }
            Table1::TallFullRank => {
                "over-constrained: statically indeterminate, kinematically determinate"
            }
            Table1::TallRankDeficient => {
                "over- and under-constrained: statically and kinematically indeterminate"
            }
            Table1::WideFullRank => {
                "under-constrained: statically determinate, kinematically indeterminate"
            }
            Table1::WideRankDeficient => {
                "under- and over-constrained: statically and kinematically indeterminate"
            }
        }
    }
}

/// One entry of a motion: a nodal velocity component.
#[derive(Clone, Debug, Serialize)]
pub struct NodalVelocity {
    /// Node name.
    pub node: String,
    /// Component (x, y, z translations; rx, ry, rz angular velocity about global axes).
    pub dof: Dof,
    /// Value (the motion vector has unit length).
    pub value: f64,
}

/// A kinematically indeterminate motion (null column of V).
#[derive(Clone, Debug, Serialize)]
pub struct Motion {
    /// Non-zero nodal velocities, unit length overall, largest-magnitude entry positive.
    pub coordinates: Vec<NodalVelocity>,
}

/// One entry of a self-stress state.
#[derive(Clone, Debug, Serialize)]
pub struct DeformationValue {
    /// Element name.
    pub element: String,
    /// Mode number, 1-based as in model files.
    pub mode: usize,
    /// Mode name, e.g. "elongation".
    pub mode_name: String,
    /// Value (the state has unit length).
    pub value: f64,
}

/// A statically indeterminate self-stress state (null column of U).
#[derive(Clone, Debug, Serialize)]
pub struct SelfStress {
    /// Non-zero stress resultants per deformation, unit length overall, largest entry positive.
    pub deformations: Vec<DeformationValue>,
}

/// Result of the kinematic analysis.
#[derive(Clone, Debug)]
pub struct ConstraintAnalysis {
    /// Rows of Dcc (fixed and input deformations).
    pub rows: Vec<Row>,
    /// Columns of Dcc (free velocity components).
    pub cols: Vec<Column>,
    /// Size of SPACAR's Euler-parameter Dcc (rows, columns), for comparison with SPACAR.
    pub euler_shape: (usize, usize),
    /// Dcc in velocity form (rows × cols).
    pub Dcc: Mat<f64>,
    /// Singular values, descending.
    pub singular_values: Vec<f64>,
    /// Absolute rank threshold used (rank_tol · s₁).
    pub tol: f64,
    /// Numerical rank r.
    pub rank: usize,
    /// Table 1 case.
    pub case: Table1,
    /// Null columns of V (cols × (n − r)), raw.
    pub null_v: Mat<f64>,
    /// Null columns of U (rows × (m − r)), raw.
    pub null_u: Mat<f64>,
    /// All left singular vectors U (m × m), for the rank updates of the advice
    /// ([`update`]); empty (0 × 0) when a square Dcc was found regular from its singular values
    /// alone ([`ConstraintAnalysis::factors`]).
    pub svd_u: Mat<f64>,
    /// All right singular vectors V (n × n); empty like `svd_u`.
    pub svd_v: Mat<f64>,
    /// Motions, presented.
    pub motions: Vec<Motion>,
    /// Self-stress states, presented.
    pub self_stresses: Vec<SelfStress>,
    /// The sparse path's rank decision and bases (None on the dense path). There,
    /// `singular_values` is empty, `Dcc`, `svd_u` and `svd_v` are 0 × 0, and `null_v`,
    /// `null_u`, `motions` and `self_stresses` hold the listed states of the fundamental bases.
    pub sparse: Option<sparse::SparseDecision>,
}

impl ConstraintAnalysis {
    /// m, the number of rows.
    pub fn m(&self) -> usize {
        self.rows.len()
    }
    /// n, the number of columns.
    pub fn n(&self) -> usize {
        self.cols.len()
    }
    /// n − r.
    pub fn n_motions(&self) -> usize {
        self.n() - self.rank
    }
    /// m − r.
    pub fn n_self_stresses(&self) -> usize {
        self.m() - self.rank
    }
    /// The gap s_r / s_(r+1) between the last non-zero and first zero singular value, if both
    /// exist (theory.md §6.2).
    pub fn rank_gap(&self) -> Option<f64> {
        if let Some(sp) = &self.sparse {
            return sp.gap_lower();
        }
        let s = &self.singular_values;
        (self.rank > 0 && self.rank < s.len()).then(|| s[self.rank - 1] / s[self.rank].max(1e-300))
    }
    /// U and V of Dcc (paper eq. 11): the stored factors, or a new full SVD of `Dcc` when
    /// [`check`] left them out (a regular square Dcc).
    #[allow(clippy::type_complexity)]
    pub fn factors(
        &self,
    ) -> Result<
        (
            std::borrow::Cow<'_, Mat<f64>>,
            std::borrow::Cow<'_, Mat<f64>>,
        ),
        LinalgError,
    > {
        use std::borrow::Cow;
        if self.svd_u.nrows() == self.m() && self.svd_v.nrows() == self.n() {
            return Ok((Cow::Borrowed(&self.svd_u), Cow::Borrowed(&self.svd_v)));
        }
        let f = svd(self.Dcc.as_ref(), "Dcc")?;
        Ok((Cow::Owned(f.U), Cow::Owned(f.V)))
    }
    /// The singular values around the rank decision: s_(r−k+1) … s_r (kept) and s_(r+1) …
    /// s_(r+k) (counted as zero), as (1-based index, value), at most `k` on each side.
    pub fn singular_values_near_rank(&self, k: usize) -> Vec<(usize, f64)> {
        let s = &self.singular_values;
        let lo = self.rank.saturating_sub(k);
        let hi = (self.rank + k).min(s.len());
        (lo..hi).map(|i| (i + 1, s[i])).collect()
    }
}

/// Why the kinematic analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KinematicsError {
    /// Linear algebra failure.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// The rank tolerance is not a finite non-negative number.
    #[error("the rank tolerance must be a finite number ≥ 0, found {0}")]
    BadTolerance(f64),
    /// The model has no constraint rows: no rigid or input deformation mode, so Dcc has no rows
    /// and there is nothing to classify (such a model is not "exactly constrained").
    #[error("the model has no constraint rows (Dcc has 0 rows: no rigid or input deformation mode), so there is nothing to classify; keep a deformation mode of an element rigid")]
    NoConstraintRows,
    /// An intended freedom names a body the model does not have (or the ground).
    #[error("the intended freedom names `{0}`, which is no moving body of the model (a rigid element, a set of elements with every deformation rigid, or one of their nodes)")]
    UnknownBody(String),
    /// An intended freedom has a zero or non-finite direction, axis, point or pitch.
    #[error("{0}")]
    BadFreedom(String),
    /// A repair action names an element, a mode, a node or a coordinate the model does not have
    /// (an action of another model).
    #[error("the action names {0}, which this model does not have")]
    UnknownInAction(String),
    /// The dense analysis of this Dcc would need more memory than the limit allows (checked
    /// before anything is allocated).
    #[error(
        "the dense kinematic analysis of the {rows} x {cols} Dcc needs {:.1} GiB (Dcc, its full \
         SVD factors U and V and the SVD's workspace), above the limit of {:.1} GiB; the check \
         is dense (memory grows with (rows + cols)^2, time with (rows + cols)^3); the sparse \
         rank-revealing path handles such models",
        *bytes as f64 / GIB,
        *limit as f64 / GIB
    )]
    TooLarge {
        /// Rows of Dcc.
        rows: usize,
        /// Columns of Dcc.
        cols: usize,
        /// Bytes the dense analysis needs (saturated at u64::MAX).
        bytes: u64,
        /// The limit ([`CheckOptions::max_dense_bytes`]).
        limit: u64,
    },
}

const GIB: f64 = (1u64 << 30) as f64;

/// Bytes the dense analysis of an m × n Dcc needs: Dcc (m n), U (m²) and V (n²), the null bases
/// (at most m² and n² more) and the SVD's workspace, saturated at `u64::MAX`. The workspace is
/// asked of faer only when the factors alone fit in `limit`.
pub fn dense_bytes(m: usize, n: usize, limit: u64) -> u64 {
    let (mm, nn) = (m as u128, n as u128);
    let factors = 8 * (mm * nn + 2 * mm * mm + 2 * nn * nn);
    if factors > limit as u128 {
        return u64::try_from(factors).unwrap_or(u64::MAX);
    }
    let total = factors + svd_scratch_bytes(m, n) as u128;
    u64::try_from(total).unwrap_or(u64::MAX)
}

/// The size guard of the dense path: an error naming the need and the limit if the m × n
/// analysis does not fit.
pub fn check_dense_size(m: usize, n: usize, limit: u64) -> Result<(), KinematicsError> {
    let bytes = dense_bytes(m, n, limit);
    if bytes > limit {
        return Err(KinematicsError::TooLarge {
            rows: m,
            cols: n,
            bytes,
            limit,
        });
    }
    Ok(())
}

/// The velocity-form columns for a partition at configuration x.
pub fn columns(model: &Model, partition: &Partition, x: &[f64]) -> Vec<Column> {
    let mut cols = Vec::new();
    for (id, n) in model.nodes.iter().enumerate() {
        // a hosted node's position columns are its host's
        for (k, dof) in [Dof::X, Dof::Y, Dof::Z].into_iter().enumerate() {
            if n.host.is_none() && partition.x[n.ix_pos + k] == CoordKind::Free {
                let mut dir = [0.0; 3];
                dir[k] = 1.0;
                cols.push(Column {
                    node: id,
                    dof,
                    dir,
                    lambda_rate: [0.0; 4],
                });
            }
        }
        let Some(ir) = n.ix_rot else { continue };
        // unit λ and Λ̄ᵀ rows: λ̇_j = ½ (Λ̄ᵀ)_j · ω
        let l = &x[ir..ir + 4];
        let ln = l.iter().map(|v| v * v).sum::<f64>().sqrt();
        let lu = [l[0] / ln, l[1] / ln, l[2] / ln, l[3] / ln];
        let lb = lambda_bar(&lu);
        let row = |j: usize| [lb[0][j], lb[1][j], lb[2][j]];
        // constrained directions: λ_j (j = 1..3) not free
        let mut basis: Vec<[f64; 3]> = Vec::new();
        let orth = |v: [f64; 3], basis: &mut Vec<[f64; 3]>| -> Option<[f64; 3]> {
            let mut w = v;
            for b in basis.iter() {
                let c = dot(w, *b);
                w = [w[0] - c * b[0], w[1] - c * b[1], w[2] - c * b[2]];
            }
            let nw = crate::math::norm(w);
            (nw > 1e-8).then(|| {
                let u = [w[0] / nw, w[1] / nw, w[2] / nw];
                basis.push(u);
                u
            })
        };
        for j in 1..4 {
            if partition.x[ir + j] != CoordKind::Free {
                orth(row(j), &mut basis);
            }
        }
        // free directions: the axis of each free component, made orthogonal to the rest
        for j in 1..4 {
            if partition.x[ir + j] != CoordKind::Free {
                continue;
            }
            let mut axis = [0.0; 3];
            axis[j - 1] = 1.0;
            if let Some(dir) = orth(axis, &mut basis) {
                let lambda_rate: [f64; 4] = std::array::from_fn(|c| 0.5 * dot(row(c), dir));
                cols.push(Column {
                    node: id,
                    dof: Dof::ALL[2 + j],
                    dir,
                    lambda_rate,
                });
            }
        }
    }
    cols
}

/// The rows of Dcc for a partition: fixed and input deformations, element by element.
pub fn rows(model: &Model, partition: &Partition) -> Vec<Row> {
    let mut rows = Vec::new();
    for (el, entry) in model.elements.iter().enumerate() {
        for mode in 0..entry.element.ne() {
            let kind = partition.e[entry.ie + mode];
            if kind != DefKind::Free {
                rows.push(Row {
                    element: el,
                    mode,
                    kind,
                });
            }
        }
    }
    rows
}

/// Map a column's unit velocity to a velocity in x (nx).
fn column_in_x(model: &Model, col: &Column) -> Vec<(usize, f64)> {
    let n = &model.nodes[col.node];
    if col.dof.is_rotation() {
        // rotation columns belong to rotational nodes ([`columns`])
        let Some(ir) = n.ix_rot else {
            return Vec::new();
        };
        (0..4).map(|c| (ir + c, col.lambda_rate[c])).collect()
    } else {
        vec![(n.ix_pos + col.dof.index(), 1.0)]
    }
}

/// A sparse row over the columns of Dcc: (column, value), columns ascending.
pub type SparseRow = Vec<(usize, f64)>;

/// The rates ∂e_i/∂(velocity columns) of the deformations `defs` (global indices e_i, any
/// order), as sparse rows in the order of `defs`: row i of D times the column map (paper eq. 9),
/// element by element from each element's own Jacobian D_k. The ne × nx matrix D is never
/// formed; each element with a requested deformation is evaluated once. The sums are taken in
/// the order of the dense product D · (column map), so the values are the same bits.
pub fn rate_rows(model: &Model, x: &[f64], cols: &[Column], defs: &[usize]) -> Vec<SparseRow> {
    assert_eq!(x.len(), model.nx, "x has the wrong length");
    // x index -> (column, ∂x_i per unit column velocity)
    let mut by_x: Vec<Vec<(usize, f64)>> = vec![Vec::new(); model.nx];
    for (j, c) in cols.iter().enumerate() {
        for (i, v) in column_in_x(model, c) {
            by_x[i].push((j, v));
        }
    }
    // deformation -> the positions in `defs` that ask for it
    let mut wanted: Vec<Vec<usize>> = vec![Vec::new(); model.ne];
    for (pos, &i) in defs.iter().enumerate() {
        wanted[i].push(pos);
    }
    let mut out: Vec<SparseRow> = vec![Vec::new(); defs.len()];
    for entry in &model.elements {
        let ne = entry.element.ne();
        if (0..ne).all(|k| wanted[entry.ie + k].is_empty()) {
            continue;
        }
        let dk = entry.element.jacobian(&gather(entry, x));
        for mode in 0..ne {
            let asked = &wanted[entry.ie + mode];
            if asked.is_empty() {
                continue;
            }
            // the row of D over x, duplicates of an x index summed in local order
            let mut dx: Vec<(usize, f64)> = Vec::with_capacity(entry.xmap.len());
            for (c, xi) in entry.x_indices().enumerate() {
                let d = dk[(mode, c)];
                match dx.iter_mut().find(|e| e.0 == xi) {
                    Some(e) => e.1 += d,
                    None => dx.push((xi, 0.0 + d)),
                }
            }
            // times the column map: per column, x indices ascending (the dense product's order)
            let mut terms: Vec<(usize, usize, f64)> = Vec::new();
            for &(xi, d) in &dx {
                for &(j, v) in &by_x[xi] {
                    terms.push((j, xi, d * v));
                }
            }
            terms.sort_by_key(|t| (t.0, t.1));
            let mut row: SparseRow = Vec::new();
            for (j, _, t) in terms {
                match row.last_mut() {
                    Some(last) if last.0 == j => last.1 += t,
                    _ => row.push((j, 0.0 + t)),
                }
            }
            for &pos in asked {
                out[pos] = row.clone();
            }
        }
    }
    out
}

/// The dense matrix of sparse rows (rows × ncols).
pub fn dense_from_rows(rows: &[SparseRow], ncols: usize) -> Mat<f64> {
    let mut a = Mat::zeros(rows.len(), ncols);
    for (i, r) in rows.iter().enumerate() {
        for &(j, v) in r {
            a[(i, j)] = v;
        }
    }
    a
}

/// The constraint that fixing the coordinate of column j adds, as a row over the columns: for a
/// translation the unit row e_j; for a rotation column the fixed Euler parameter λ_k
/// (k = 1, 2, 3 for rx, ry, rz) holds ω along row k of Λ̄ᵀ(λ) (theory.md §2.2), so the row has
/// the entries dir_c · (Λ̄ᵀ)_k on the node's rotation columns c. At λ = (1, 0, 0, 0), and
/// whenever that direction is the column's own, it is again e_j: fixing the coordinate
/// removes column j. Otherwise fixing it restricts the node's angular velocity to a plane that
/// is not spanned by columns, and the counts are those of Dcc with this row appended.
pub fn coordinate_constraint(model: &Model, cols: &[Column], x: &[f64], j: usize) -> SparseRow {
    let c = &cols[j];
    let node = &model.nodes[c.node];
    let Some(ir) = node.ix_rot.filter(|_| c.dof.is_rotation()) else {
        return vec![(j, 1.0)];
    };
    let l = &x[ir..ir + 4];
    let ln = l.iter().map(|v| v * v).sum::<f64>().sqrt();
    let lu = [l[0] / ln, l[1] / ln, l[2] / ln, l[3] / ln];
    let lb = lambda_bar(&lu);
    let k = c.dof.index() - 2;
    let row = [lb[0][k], lb[1][k], lb[2][k]];
    // the node's columns are contiguous; its rotation columns are among the three before and
    // after j
    let lo = j.saturating_sub(3);
    let hi = (j + 4).min(cols.len());
    let entries: SparseRow = (lo..hi)
        .filter(|&i| cols[i].node == c.node && cols[i].dof.is_rotation())
        .map(|i| (i, dot(cols[i].dir, row)))
        .filter(|e| e.1 != 0.0)
        .collect();
    if entries.len() == 1 && entries[0].0 == j {
        return vec![(j, 1.0)];
    }
    entries
}

/// The global deformation index of each row of Dcc.
pub(crate) fn row_defs(model: &Model, rows: &[Row]) -> Vec<usize> {
    rows.iter()
        .map(|r| model.elements[r.element].ie + r.mode)
        .collect()
}

/// D (ne × nx) times the column map: ∂e/∂(velocity coordinates) for all ne deformations (dense;
/// the analyses use the sparse [`rate_rows`]).
pub fn deformation_rates(model: &Model, D: &Mat<f64>, cols: &[Column]) -> Mat<f64> {
    let mut out = Mat::zeros(model.ne, cols.len());
    for (j, c) in cols.iter().enumerate() {
        for (i, v) in column_in_x(model, c) {
            for r in 0..model.ne {
                out[(r, j)] += D[(r, i)] * v;
            }
        }
    }
    out
}

/// Assemble Dcc (velocity form) for a partition at x, dense (no size guard: see [`check`]).
pub fn assemble_dcc(
    model: &Model,
    partition: &Partition,
    x: &[f64],
) -> (Vec<Row>, Vec<Column>, Mat<f64>) {
    let cols = columns(model, partition, x);
    let rows = rows(model, partition);
    let sparse = rate_rows(model, x, &cols, &row_defs(model, &rows));
    let dcc = dense_from_rows(&sparse, cols.len());
    (rows, cols, dcc)
}

/// SPACAR's Euler-parameter Dcc size: rows e^o + e^m + one normalisation per rotational node;
/// columns all x^c including λ0.
pub fn euler_shape(model: &Model, partition: &Partition) -> (usize, usize) {
    let m =
        partition.e.iter().filter(|k| **k != DefKind::Free).count() + model.n_rotational_nodes();
    let n = partition
        .x
        .iter()
        .filter(|k| **k == CoordKind::Free)
        .count();
    (m, n)
}

/// The kinematic analysis at configuration x (paper §3).
///
/// The path is [`CheckOptions::method`] ([`CheckMethod::resolve`], with the automatic choice's
/// dense fall-back, [`CheckMethod::dense_fallback`]). Dense: a model whose Dcc,
/// SVD factors and workspace exceed [`CheckOptions::max_dense_bytes`] stops with
/// [`KinematicsError::TooLarge`] before anything large is allocated (the automatic choice takes
/// the sparse path instead, [`sparse`]).
pub fn check(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    opts: &CheckOptions,
) -> Result<ConstraintAnalysis, KinematicsError> {
    if !(opts.rank_tol.is_finite() && opts.rank_tol >= 0.0) {
        return Err(KinematicsError::BadTolerance(opts.rank_tol));
    }
    let cols = columns(model, partition, x);
    let rows = rows(model, partition);
    let (m, n) = (rows.len(), cols.len());
    if opts.method.resolve(m, n, opts.max_dense_bytes) == CheckMethod::Sparse {
        let a = sparse::check_sparse(model, partition, x, opts)?;
        let certain = a.sparse.as_ref().is_none_or(|sp| sp.certain);
        if certain || !opts.method.dense_fallback(m, n, opts.max_dense_bytes) {
            return Ok(a);
        }
        // a decision the sparse bounds leave open, on a matrix the dense SVD can take: all
        // singular values decide it
    }
    check_dense_size(m, n, opts.max_dense_bytes)?;
    let dcc = dense_from_rows(&rate_rows(model, x, &cols, &row_defs(model, &rows)), n);
    // SVD and numerical rank (paper eq. 11)
    // A square Dcc (the hoped-for exact constraint) first gets its singular values alone, about
    // a third of the work of the full factors: if it is regular there are no null vectors to
    // find and the factors are left out (an [`update::Updater`] computes them if it is asked).
    if m == n && m > 0 {
        check_finite(dcc.as_ref())?;
        let s = crate::linalg::singular_values(dcc.as_ref())?;
        let tol = opts.rank_tol * s.first().copied().unwrap_or(0.0);
        let rank = numerical_rank(&s, tol);
        if rank == n {
            return Ok(ConstraintAnalysis {
                case: Table1::classify(m, n, rank),
                euler_shape: euler_shape(model, partition),
                rows,
                cols,
                Dcc: dcc,
                singular_values: s,
                tol,
                rank,
                null_v: Mat::zeros(n, 0),
                null_u: Mat::zeros(m, 0),
                svd_u: Mat::zeros(0, 0),
                svd_v: Mat::zeros(0, 0),
                motions: Vec::new(),
                self_stresses: Vec::new(),
                sparse: None,
            });
        }
    }
    let f = svd(dcc.as_ref(), "Dcc")?;
    let tol = opts.rank_tol * f.s.first().copied().unwrap_or(0.0);
    let rank = numerical_rank(&f.s, tol);
    let null_v = Mat::from_fn(n, n - rank, |i, j| f.V[(i, rank + j)]);
    let null_u = Mat::from_fn(m, m - rank, |i, j| f.U[(i, rank + j)]);
    let names = model.node_names();
    let motions = (0..n - rank)
        .map(|j| {
            present_motion(
                model,
                &cols,
                &(0..n).map(|i| null_v[(i, j)]).collect::<Vec<_>>(),
            )
        })
        .collect();
    let self_stresses = (0..m - rank)
        .map(|j| {
            let u: Vec<f64> = (0..m).map(|i| null_u[(i, j)]).collect();
            present_self_stress(model, &names, &rows, &u)
        })
        .collect();
    Ok(ConstraintAnalysis {
        case: Table1::classify(m, n, rank),
        euler_shape: euler_shape(model, partition),
        rows,
        cols,
        Dcc: dcc,
        singular_values: f.s,
        tol,
        rank,
        null_v,
        null_u,
        svd_u: f.U,
        svd_v: f.V,
        motions,
        self_stresses,
        sparse: None,
    })
}

/// The NaN/infinity test of [`svd`], for the path that takes singular values alone.
fn check_finite(a: faer::MatRef<'_, f64>) -> Result<(), LinalgError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            if !a[(i, j)].is_finite() {
                return Err(LinalgError::NonFinite {
                    what: "Dcc",
                    row: i,
                    col: j,
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod sparse_tests;
#[cfg(test)]
pub(crate) mod test_models;
#[cfg(test)]
mod tests;
