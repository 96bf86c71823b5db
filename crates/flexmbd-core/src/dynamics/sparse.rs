//! The sparse eigen path for large models (docs/dynamics.md, "Large models").
//!
//! The same eigenproblem as the dense path, (K_m + K_g) v = ω² M v on the minimal coordinates,
//! solved without any dense matrix of the size of the model:
//!
//! - **Coordinates**: the reduced unknowns of the statics Newton system
//!   ([`crate::statics::ReducedLinear`]): free translations, three rotation increments δ per
//!   rotational node (angular velocity ω = 2δ, so these are velocity coordinates), the Euler
//!   parameters of partly held rotational nodes, and one multiplier per kept constraint (rigid
//!   and input deformations, normalisations of partly held nodes). The stiffness is the Newton
//!   matrix of statics at the state: K = K_m + K_g with the pre-stress, the constraint forces,
//!   the normalisation terms and the load stiffness of moments, exactly as in the dense path.
//!   The mass is assembled element by element in the same coordinates (Tᵀ M_e T).
//! - **Constraints** stay in the saddle-point form: the shift-invert operator solves
//!   `[K − σM, Gᵀ; G, 0] [u; μ] = [M v; 0]`, so every vector it returns satisfies G u = 0, and
//!   the Lanczos vectors stay in the constrained space without a null-space basis.
//! - **Factorisation**: the project's own sparse L D Lᵀ (`math::sparse_lu`) with diagonal
//!   pivots, in an AMD order of the coordinates with every constraint row placed right after the
//!   last coordinate it couples (so that its pivot exists); Sylvester's law of inertia then
//!   counts the eigenvalues below the shift (negative pivots minus constraints). When L D Lᵀ
//!   breaks down (a massless rigid part, say), LU with partial pivoting is used instead, without
//!   the inertia count.
//! - **Shift**: σ = 0 when K is positive definite on the constrained space (the inertia says
//!   so); otherwise (zero-frequency motions, a buckled state) σ < 0 is lowered in steps until
//!   no eigenvalue lies below it. So the wanted eigenvalues are the largest θ = 1/(λ − σ). A
//!   shift at which the operator amplifies some directions far more than the last wanted mode
//!   (zero-frequency modes, or a small σ that only just regularises a massless part) is
//!   replaced after a first pass by one a tenth of the wanted range below the lowest
//!   eigenvalue.
//! - **Massless directions** need no special treatment: the operator maps everything onto
//!   vectors whose massless part follows the massive part quasi-statically, which is the static
//!   condensation of the dense path; the start vector is passed through the operator first, and
//!   every converged vector is purified by one more application. Infinite eigenvalues never
//!   appear (they are θ = 0).
//! - **Eigen iteration**: Krylov–Schur restarted Lanczos (Stewart 2001) in the M inner product
//!   with full reorthogonalisation (classical Gram–Schmidt, twice), converged when the residual
//!   of every wanted Ritz pair is below [`TOL`] |θ|. A **Sturm check** (the inertia at a shift
//!   just above the last wanted eigenvalue) then confirms that no eigenvalue was missed (a
//!   multiple eigenvalue, which a single-vector Lanczos may find only once); missed ones are
//!   found by further runs deflated against the modes found.
//! - **Projected eigenproblem**: the Ritz pairs of the (at most a few dozen) projected matrix
//!   come from the project's own small symmetric solver ([`crate::math::small_eigen`]:
//!   Householder tridiagonalisation, implicit QL, only the eigenvectors of the wanted and kept
//!   Ritz values formed), faer's beyond [`SMALL_EIGEN_MAX`]; a general solver's fixed costs
//!   exceed the whole iteration on small models.
//! - **Result**: the Ritz vectors (M-orthonormal by the reorthogonalisation; purified and
//!   orthonormalised again when there are massless directions), and as eigenvalues their
//!   Rayleigh quotients with the strain energy evaluated through the element deformations
//!   ([`crate::statics::ReducedLinear::material_energy2`]): on fine meshes the stiffness
//!   entries exceed the stiffness of a smooth mode by many orders of magnitude, and both the
//!   factorisation (σ + 1/θ) and the product uᵀ K u lose the lowest eigenvalues to round-off.

use super::ModalError;
use crate::elements::ElementKind;
use crate::linalg::{sym_eigen_seq, EigenError};
use crate::math::small_eigen::{sym_eigen_small, sym_eigen_small_largest, SMALL_EIGEN_MAX};
use crate::math::sparse_lu::{amd_order, csc_residual, sort_small, SparseLu};
use crate::model::Model;
use crate::statics::{ReducedLinear, StepResult};
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatRef, Par};
use rayon::prelude::*;

/// Convergence tolerance of a Ritz pair (θ, x) of the shift-invert operator S:
/// ‖S x − θ x‖_M ≤ TOL |θ|.
pub const TOL: f64 = 1e-10;

/// Largest number of operator applications per wanted mode (plus a constant) before the
/// iteration gives up.
const MAX_APPLICATIONS_PER_MODE: usize = 60;

/// Accepted componentwise backward error of a solve with a new factorisation.
const MAX_BACKWARD_ERROR: f64 = 1e-9;

/// Vectors at least this long are processed in parallel (rayon); shorter ones sequentially,
/// where the thread hand-over would cost more than it saves.
const PAR_MIN: usize = 32_768;

/// Rows per parallel chunk of the basis operations.
const ROW_CHUNK: usize = 8192;

/// Column `i` of a column-major matrix as a slice.
fn col_slice<'a>(v: MatRef<'a, f64>, i: usize) -> &'a [f64] {
    v.col(i)
        .try_as_col_major()
        .expect("basis matrices are column-major")
        .as_slice()
}

/// a · b with eight independent partial sums (the additions pipeline instead of waiting for
/// each other).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 8];
    let (ac, ar) = a.split_at(n - n % 8);
    let (bc, br) = b.split_at(n - n % 8);
    for (x, y) in ac.chunks_exact(8).zip(bc.chunks_exact(8)) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    let mut tail = 0.0;
    for (x, y) in ar.iter().zip(br) {
        tail += x * y;
    }
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
}

/// c[i] = V[:, i] · y for the first `c.len()` columns of `v`.
fn basis_dots(v: MatRef<'_, f64>, y: &[f64], c: &mut [f64]) {
    let n = y.len();
    let j = c.len();
    if n < PAR_MIN {
        dots_rows(v, y, 0..n, c);
        return;
    }
    let chunks = n.div_ceil(ROW_CHUNK);
    let sum = (0..chunks)
        .into_par_iter()
        .map(|k| {
            let r = k * ROW_CHUNK..((k + 1) * ROW_CHUNK).min(n);
            let mut part = vec![0.0; j];
            dots_rows(v, y, r, &mut part);
            part
        })
        .reduce(
            || vec![0.0; j],
            |mut a, b| {
                a.iter_mut().zip(&b).for_each(|(x, y)| *x += y);
                a
            },
        );
    c.copy_from_slice(&sum);
}

/// c[i] = V[r, i] · y[r] for the first `c.len()` columns: four columns at a time, each with
/// two partial sums (even and odd rows), so that one pass over y serves four columns and the
/// products vectorise.
fn dots_rows(v: MatRef<'_, f64>, y: &[f64], r: std::ops::Range<usize>, c: &mut [f64]) {
    let y = &y[r.clone()];
    let col = |i: usize| &col_slice(v, i)[r.clone()];
    let mut quads = c.chunks_exact_mut(4);
    let mut i = 0;
    for out in &mut quads {
        let (a, b, cc, d) = (col(i), col(i + 1), col(i + 2), col(i + 3));
        let mut acc = [[0.0f64; 2]; 4];
        let pairs = y
            .chunks_exact(2)
            .zip(a.chunks_exact(2))
            .zip(b.chunks_exact(2))
            .zip(cc.chunks_exact(2).zip(d.chunks_exact(2)));
        for (((yk, ak), bk), (ck, dk)) in pairs {
            for t in 0..2 {
                acc[0][t] += ak[t] * yk[t];
                acc[1][t] += bk[t] * yk[t];
                acc[2][t] += ck[t] * yk[t];
                acc[3][t] += dk[t] * yk[t];
            }
        }
        let mut sums = [
            acc[0][0] + acc[0][1],
            acc[1][0] + acc[1][1],
            acc[2][0] + acc[2][1],
            acc[3][0] + acc[3][1],
        ];
        if y.len() % 2 == 1 {
            let last = y.len() - 1;
            for (q, s) in [a, b, cc, d].iter().zip(sums.iter_mut()) {
                *s += q[last] * y[last];
            }
        }
        out.copy_from_slice(&sums);
        i += 4;
    }
    for out in quads.into_remainder() {
        *out = dot(col(i), y);
        i += 1;
    }
}

/// w −= V[:, ..j] c.
fn basis_subtract(v: MatRef<'_, f64>, c: &[f64], w: &mut [f64]) {
    let update = |start: usize, chunk: &mut [f64]| {
        let len = chunk.len();
        let col = |i: usize| &col_slice(v, i)[start..start + len];
        let mut quads = c.chunks_exact(4);
        let mut i = 0;
        for q in &mut quads {
            let (a, b, cc, d) = (col(i), col(i + 1), col(i + 2), col(i + 3));
            let rows = chunk.iter_mut().zip(a).zip(b).zip(cc.iter().zip(d));
            for (((wk, ak), bk), (ck, dk)) in rows {
                *wk -= (q[0] * ak + q[1] * bk) + (q[2] * ck + q[3] * dk);
            }
            i += 4;
        }
        for &ci in quads.remainder() {
            if ci != 0.0 {
                for (wk, vk) in chunk.iter_mut().zip(col(i)) {
                    *wk -= ci * vk;
                }
            }
            i += 1;
        }
    };
    if w.len() < PAR_MIN {
        update(0, w);
        return;
    }
    w.par_chunks_mut(ROW_CHUNK)
        .enumerate()
        .for_each(|(k, chunk)| update(k * ROW_CHUNK, chunk));
}

/// All eigenpairs of a projected symmetric matrix (lower triangle read), ascending: the
/// hand-written solver for small orders (its fixed costs are far below faer's), faer beyond.
fn projected_eigen(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    if a.nrows() <= SMALL_EIGEN_MAX {
        sym_eigen_small(a)
    } else {
        sym_eigen_seq(a)
    }
}

/// All eigenvalues of a projected symmetric matrix (lower triangle read), ascending, and the
/// eigenvectors of the `k` largest, largest first (as [`projected_eigen`]).
fn projected_eigen_largest(
    a: MatRef<'_, f64>,
    k: usize,
) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    let n = a.nrows();
    if n <= SMALL_EIGEN_MAX {
        sym_eigen_small_largest(a, k)
    } else {
        let (values, vectors) = sym_eigen_seq(a)?;
        let k = k.min(n);
        Ok((values, Mat::from_fn(n, k, |i, c| vectors[(i, n - 1 - c)])))
    }
}

/// Vectors at most this long are combined by [`basis_combine`]'s plain loop (faer's product has
/// set-up costs that only pay off on longer ones).
const COMBINE_LOOP_MAX: usize = 1024;

/// V[:, ..] Y (columns of `y`) into a new matrix with `y.ncols()` columns: for short vectors
/// column by column as sums of the columns of V (no set-up cost), else faer's product.
fn basis_combine(v: MatRef<'_, f64>, y: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(v.nrows(), y.ncols());
    if v.nrows() <= COMBINE_LOOP_MAX {
        for c in 0..y.ncols() {
            let o = out.col_as_slice_mut(c);
            for j in 0..y.nrows() {
                let f = y[(j, c)];
                if f != 0.0 {
                    for (x, vj) in o.iter_mut().zip(col_slice(v, j)) {
                        *x += f * vj;
                    }
                }
            }
        }
        return out;
    }
    let par = if v.nrows() < PAR_MIN {
        Par::Seq
    } else {
        Par::rayon(0)
    };
    matmul(out.as_mut(), Accum::Replace, v, y, 1.0, par);
    out
}

/// The result of the sparse path: eigenvalues ascending and mass-normalised shapes in x.
pub(crate) struct SparseModes {
    /// ω², ascending.
    pub eigenvalues: Vec<f64>,
    /// Shapes δx (length nx), δxᵀ M δx = 1.
    pub shapes: Vec<Vec<f64>>,
    /// Number of minimal coordinates (coordinates minus constraints).
    pub ndof: usize,
    /// Directions without inertia (infinite eigenvalues of the pencil).
    pub massless: usize,
    /// Kinetic energy split of every mode: per node (translation, rotation), the rows of the
    /// node in uᵀ M u (the same split as in x: the rotation increments of a node map onto its
    /// own Euler parameters only).
    pub kinetic: Vec<NodeKinetic>,
    /// Number of rigid-body modes at the start of `eigenvalues` (`rigid` module).
    pub rigid: usize,
    /// When the listed eigenvalues show no gap of their own: the number of eigenvalues below
    /// the probe shift of the `rigid` module, by the inertia.
    pub below_gap: Option<usize>,
}

/// Kinetic energy of one mode per node: (translation, rotation).
type NodeKinetic = Vec<(f64, f64)>;

/// The sparse problem: K and M in the reduced coordinates, with the constraint rows.
struct Problem {
    lin: ReducedLinear,
    /// Stiffness entries outside the element pattern (softening of point masses), for the
    /// Rayleigh quotients.
    extra_k: Vec<(usize, usize, f64)>,
    /// The node of every coordinate.
    group: Vec<usize>,
    /// Size of the saddle-point system.
    n: usize,
    /// Number of coordinates (the first `nc` unknowns).
    nc: usize,
    /// CSC structure of the saddle-point matrix (rows sorted, every diagonal entry present).
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// K and M values on that structure (M zero in the constraint rows and columns).
    k: Vec<f64>,
    m: Vec<f64>,
    /// The coordinate block of M (CSC, symmetric, non-zero entries only), for M v.
    m_ptr: Vec<usize>,
    m_idx: Vec<usize>,
    m_val: Vec<f64>,
}

/// A CSC block of a symmetric matrix times a vector: (A v)_j = Σ_p A[p] v[idx[p]] over column
/// j (gather form, parallel over columns).
fn csc_sym_times(ptr: &[usize], idx: &[usize], val: &[f64], v: &[f64], out: &mut [f64]) {
    const CHUNK: usize = 4096;
    if out.len() < PAR_MIN {
        for (j, y) in out.iter_mut().enumerate() {
            let (lo, hi) = (ptr[j], ptr[j + 1]);
            *y = idx[lo..hi]
                .iter()
                .zip(&val[lo..hi])
                .map(|(&i, &a)| a * v[i])
                .sum();
        }
        return;
    }
    out.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, chunk)| {
            for (o, y) in chunk.iter_mut().enumerate() {
                let j = c * CHUNK + o;
                *y = (ptr[j]..ptr[j + 1]).map(|p| val[p] * v[idx[p]]).sum();
            }
        });
}

impl Problem {
    fn new(model: &Model, step: &StepResult) -> Self {
        let mut lin = ReducedLinear::new(model, step);
        let (n, nc) = (lin.n(), lin.n_coords());
        let x = &step.x;
        // element mass blocks, in the order of the element entries
        let ne = lin.vals.len();
        let mut m_el = vec![0.0; ne];
        let ranges: Vec<(usize, std::ops::Range<usize>)> = (0..model.elements.len())
            .map(|el| (el, lin.element_entries(el)))
            .collect();
        {
            // split m_el at the element ranges (ascending, disjoint) and fill in parallel
            let mut pieces: Vec<(usize, &mut [f64])> = Vec::with_capacity(ranges.len());
            let mut rest: &mut [f64] = &mut m_el;
            let mut offset = 0;
            for (el, r) in &ranges {
                let (_, tail) = rest.split_at_mut(r.start - offset);
                let (piece, tail) = tail.split_at_mut(r.end - r.start);
                pieces.push((*el, piece));
                rest = tail;
                offset = r.end;
            }
            let fill = |(el, out): (usize, &mut [f64])| {
                let entry = &model.elements[el];
                let n = entry.xmap.len();
                // a beam's 14 coordinates on the stack, larger elements on the heap
                let (mut xk_s, mut me_s) = ([0.0; 14], [0.0; 14 * 14]);
                let (mut xk_h, mut me_h) = (Vec::new(), Vec::new());
                let (xk, me) = if n <= 14 {
                    (&mut xk_s[..n], &mut me_s[..n * n])
                } else {
                    xk_h.resize(n, 0.0);
                    me_h.resize(n * n, 0.0);
                    (&mut xk_h[..], &mut me_h[..])
                };
                xk.iter_mut().zip(&entry.xmap).for_each(|(v, &i)| *v = x[i]);
                if entry.element.mass(xk, None, true, me) {
                    lin.element_block(model, el, x, &|a, c| me[a * n + c], out);
                }
            };
            if pieces.len() < 256 {
                pieces.into_iter().for_each(fill);
            } else {
                pieces.into_par_iter().with_min_len(64).for_each(fill);
            }
        }
        // centrifugal softening of a steady rotation (model::Spin): −Ω² M_P on the elements, on
        // the element pattern, counted with the geometric part (it enters the Rayleigh quotients)
        let w = model.loads.spin.map(|sp| sp.projector());
        if let Some(w) = &w {
            for (el, r) in &ranges {
                let entry = &model.elements[*el];
                let n = entry.xmap.len();
                let xk: Vec<f64> = entry.xmap.iter().map(|&i| x[i]).collect();
                let mut ms = vec![0.0; n * n];
                if entry.element.mass(&xk, Some(w), false, &mut ms) {
                    let mut soft = vec![0.0; r.end - r.start];
                    lin.element_block(model, *el, x, &|a, c| -ms[a * n + c], &mut soft);
                    for (i, v) in r.clone().zip(soft) {
                        lin.vals[i] += v;
                        lin.geo[i] += v;
                    }
                }
            }
        }
        // node masses: point masses (with their softening) and inertia tensors, as
        // (row, column, K value, M value)
        let mut extra: Vec<(usize, usize, f64, f64)> = Vec::new();
        for &(node, mass) in &model.loads.point_masses {
            let ip = model.nodes[node].ix_pos;
            for a in 0..3 {
                let Some(i) = lin.coord_index(ip + a) else {
                    continue;
                };
                for c in 0..3 {
                    let Some(j) = lin.coord_index(ip + c) else {
                        continue;
                    };
                    let kv = w.map_or(0.0, |w| -mass * w[a][c]);
                    let mv = if a == c { mass } else { 0.0 };
                    if kv != 0.0 || mv != 0.0 {
                        extra.push((i, j, kv, mv));
                    }
                }
            }
        }
        for (node, tensor) in &model.loads.inertias {
            let Some(r) = model.nodes[*node].ix_rot else {
                continue;
            };
            let blk = crate::math::inertia::node_inertia_block(&x[r..r + 4], tensor);
            extra.extend(
                lin.lambda_block(x, r, &blk)
                    .into_iter()
                    .map(|(i, j, v)| (i, j, 0.0, v)),
            );
        }
        let extra_k: Vec<(usize, usize, f64)> = extra
            .iter()
            .filter(|e| e.2 != 0.0)
            .map(|e| (e.0, e.1, e.2))
            .collect();
        // CSC: bucket the entries by column (element entries, node masses, the diagonal), sort
        // each column by row, sum duplicates
        let (n_extra, total) = (extra.len(), ne + extra.len() + n);
        let mut count = vec![0usize; n + 1];
        lin.for_each_entry(|_, c| count[c + 1] += 1);
        for &(_, c, _, _) in &extra {
            count[c + 1] += 1;
        }
        for c in 0..n {
            count[c + 1] += 1;
        }
        for c in 0..n {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut by_col = vec![(0u32, 0u32); total];
        let mut i = 0u32;
        lin.for_each_entry(|r, c| {
            by_col[fill[c]] = (r as u32, i);
            fill[c] += 1;
            i += 1;
        });
        for &(r, c, _, _) in &extra {
            by_col[fill[c]] = (r as u32, i);
            fill[c] += 1;
            i += 1;
        }
        for c in 0..n {
            by_col[fill[c]] = (c as u32, i);
            fill[c] += 1;
            i += 1;
        }
        let values = |i: usize| -> (f64, f64) {
            if i < ne {
                (lin.vals[i], m_el[i])
            } else if i < ne + n_extra {
                (extra[i - ne].2, extra[i - ne].3)
            } else {
                (0.0, 0.0)
            }
        };
        // sort each column by row; the number of distinct entries sizes the arrays exactly
        let mut nnz = 0;
        for c in 0..n {
            let list = &mut by_col[count[c]..count[c + 1]];
            sort_small(list);
            nnz += 1 + list.windows(2).filter(|w| w[0].0 != w[1].0).count();
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let (mut row_idx, mut k, mut m) = (
            Vec::with_capacity(nnz),
            Vec::with_capacity(nnz),
            Vec::with_capacity(nnz),
        );
        for c in 0..n {
            let list = &by_col[count[c]..count[c + 1]];
            for (q, &(r, i)) in list.iter().enumerate() {
                let (kv, mv) = values(i as usize);
                if q > 0 && list[q - 1].0 == r {
                    *k.last_mut().expect("previous entry") += kv;
                    *m.last_mut().expect("previous entry") += mv;
                } else {
                    row_idx.push(r as usize);
                    k.push(kv);
                    m.push(mv);
                }
            }
            col_ptr.push(row_idx.len());
        }
        // the load stiffness of moments is not symmetric: its symmetric part, as the dense path
        // (the pattern is symmetric, rows sorted)
        if lin.has_moment_loads() {
            let orig = k.clone();
            for c in 0..n {
                for q in col_ptr[c]..col_ptr[c + 1] {
                    let r = row_idx[q];
                    if r > c {
                        let t = col_ptr[r]
                            + row_idx[col_ptr[r]..col_ptr[r + 1]]
                                .binary_search(&c)
                                .expect("symmetric pattern");
                        let v = 0.5 * (orig[q] + orig[t]);
                        k[q] = v;
                        k[t] = v;
                    }
                }
            }
        }
        // the coordinate block of M (non-zero entries)
        let block = |vals: &[f64]| {
            let nnz = (0..col_ptr[nc])
                .filter(|&p| row_idx[p] < nc && vals[p] != 0.0)
                .count();
            let mut ptr = Vec::with_capacity(nc + 1);
            ptr.push(0);
            let (mut idx, mut val) = (Vec::with_capacity(nnz), Vec::with_capacity(nnz));
            for c in 0..nc {
                for p in col_ptr[c]..col_ptr[c + 1] {
                    if row_idx[p] < nc && vals[p] != 0.0 {
                        idx.push(row_idx[p]);
                        val.push(vals[p]);
                    }
                }
                ptr.push(idx.len());
            }
            (ptr, idx, val)
        };
        let (m_ptr, m_idx, m_val) = block(&m);
        let group = lin.coord_nodes(model);
        Self {
            lin,
            extra_k,
            group,
            n,
            nc,
            col_ptr,
            row_idx,
            k,
            m,
            m_ptr,
            m_idx,
            m_val,
        }
    }

    fn m_times(&self, v: &[f64], out: &mut [f64]) {
        csc_sym_times(&self.m_ptr, &self.m_idx, &self.m_val, v, out);
    }

    /// Diagonal entries of K and M of the coordinates.
    fn diagonals(&self) -> (Vec<f64>, Vec<f64>) {
        let mut kd = vec![0.0; self.nc];
        let mut md = vec![0.0; self.nc];
        for c in 0..self.nc {
            for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                if self.row_idx[p] == c {
                    kd[c] = self.k[p];
                    md[c] = self.m[p];
                }
            }
        }
        (kd, md)
    }

    /// Fill-reducing order for L D Lᵀ with diagonal pivots: AMD on the graph of the nodes (the
    /// unknowns of a node share their couplings, so this is AMD on the coordinate block with
    /// its supervariables found in advance, and far cheaper), each node's coordinates together;
    /// each constraint row placed right after the last coordinate it couples, so that its pivot
    /// (minus a Schur complement of the coordinates) exists.
    fn saddle_order(&self, group: &[usize]) -> Result<Vec<usize>, String> {
        let (n, nc) = (self.n, self.nc);
        // groups numbered 0..ng in order of first appearance
        let mut gid = vec![usize::MAX; group.iter().copied().max().map_or(0, |g| g + 1)];
        let mut members: Vec<Vec<usize>> = Vec::new();
        for (c, &g) in group.iter().enumerate() {
            if gid[g] == usize::MAX {
                gid[g] = members.len();
                members.push(Vec::new());
            }
            members[gid[g]].push(c);
        }
        let ng = members.len();
        // the graph of the groups (CSC, rows sorted, diagonal included)
        let (mut ptr, mut idx) = (vec![0usize], Vec::new());
        let mut mark = vec![usize::MAX; ng];
        for (g, cols) in members.iter().enumerate() {
            let start = idx.len();
            for &c in cols {
                for p in self.col_ptr[c]..self.col_ptr[c + 1] {
                    let r = self.row_idx[p];
                    if r < nc {
                        let h = gid[group[r]];
                        if mark[h] != g {
                            mark[h] = g;
                            idx.push(h);
                        }
                    }
                }
            }
            sort_small(&mut idx[start..]);
            ptr.push(idx.len());
        }
        let (q, _) = amd_order(ng, &ptr, &idx)?;
        // coordinates in group order; position of each coordinate
        let mut coords = Vec::with_capacity(nc);
        for &g in &q {
            coords.extend_from_slice(&members[g]);
        }
        let mut pos = vec![0usize; nc];
        for (k, &c) in coords.iter().enumerate() {
            pos[c] = k;
        }
        // each constraint after the latest of its coordinates
        let mut after: Vec<Vec<usize>> = vec![Vec::new(); nc + 1];
        for c in nc..n {
            let last = (self.col_ptr[c]..self.col_ptr[c + 1])
                .map(|p| self.row_idx[p])
                .filter(|&r| r < nc)
                .map(|r| pos[r] + 1)
                .max()
                .unwrap_or(0);
            after[last].push(c);
        }
        let mut order = Vec::with_capacity(n);
        order.extend_from_slice(&after[0]);
        for (k, &col) in coords.iter().enumerate() {
            order.push(col);
            order.extend_from_slice(&after[k + 1]);
        }
        Ok(order)
    }
}

/// Deterministic pseudo-random numbers in (−1, 1) (xorshift64*), for start vectors.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A factorisation of the shifted saddle-point matrix A(σ) = [K − σM, Gᵀ; G, 0].
struct Shifted {
    /// L D Lᵀ with diagonal pivots in the saddle order (symbolic structure reused), and the
    /// CSC positions of the lower triangle it reads.
    sym: Option<(SparseLu, Vec<usize>)>,
    /// LU with partial pivoting (created when L D Lᵀ fails).
    lu: Option<SparseLu>,
    /// A copy of the L D Lᵀ for the inertia counts at other shifts ([`Shifted::count_below`]).
    counter: Option<SparseLu>,
    /// Which factorisation holds A(σ): true L D Lᵀ, false LU.
    use_sym: bool,
    sigma: f64,
    /// Number of eigenvalues below σ (from the inertia), when L D Lᵀ holds A(σ).
    below: Option<usize>,
    /// Values of A(σ).
    vals: Vec<f64>,
    rhs: Vec<f64>,
    /// The lower triangle handed to the L D Lᵀ refactorisations (reused).
    lower: Vec<f64>,
}

impl Shifted {
    fn new(p: &Problem) -> Self {
        let sym = p.saddle_order(&p.group).ok().and_then(|order| {
            let mut lu = SparseLu::with_order(p.n, order).ok()?;
            if !lu.set_diagonal_pivots(&p.col_ptr, &p.row_idx) {
                return None;
            }
            lu.set_pivot_tolerance(0.0);
            let slots = lu.lower_layout(&p.col_ptr, &p.row_idx);
            Some((lu, slots))
        });
        Self {
            sym,
            lu: None,
            counter: None,
            use_sym: false,
            sigma: f64::NAN,
            below: None,
            vals: vec![0.0; p.k.len()],
            rhs: vec![0.0; p.n],
            lower: Vec::new(),
        }
    }

    /// Factor A(σ); `allow_lu`: fall back to LU when L D Lᵀ fails. Checks the accuracy of a
    /// trial solve. Returns false when A(σ) could not be factored accurately.
    fn factor(&mut self, p: &Problem, sigma: f64, allow_lu: bool) -> bool {
        self.sigma = sigma;
        self.below = None;
        for (v, (k, m)) in self.vals.iter_mut().zip(p.k.iter().zip(&p.m)) {
            *v = k - sigma * m;
        }
        let n_constraints = p.n - p.nc;
        if let Some((lu, slots)) = &mut self.sym {
            self.lower.clear();
            self.lower.extend(slots.iter().map(|&s| self.vals[s]));
            if lu.refactor_symmetric(&self.lower).is_ok() {
                self.use_sym = true;
                if self.accurate(p) {
                    let neg = self.sym.as_ref().map_or(0, |s| s.0.negative_pivots());
                    self.below = neg.checked_sub(n_constraints);
                    return true;
                }
            }
        }
        if !allow_lu {
            return false;
        }
        if self.lu.is_none() {
            self.lu = SparseLu::new(p.n, &p.col_ptr, &p.row_idx).ok();
        }
        let Some(lu) = &mut self.lu else {
            return false;
        };
        if lu.factor(&p.col_ptr, &p.row_idx, &self.vals).is_err() {
            return false;
        }
        self.use_sym = false;
        self.accurate(p)
    }

    /// Backward error of a solve with a pseudo-random right-hand side.
    fn accurate(&mut self, p: &Problem) -> bool {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let b: Vec<f64> = (0..p.n).map(|_| rng.next()).collect();
        let mut z = b.clone();
        self.solve(&mut z);
        z.iter().all(|v| v.is_finite())
            && csc_residual(&p.col_ptr, &p.row_idx, &self.vals, &z, &b).1 <= MAX_BACKWARD_ERROR
    }

    fn solve(&mut self, b: &mut [f64]) {
        if self.use_sym {
            if let Some((lu, _)) = &mut self.sym {
                lu.solve(b);
            }
        } else if let Some(lu) = &mut self.lu {
            lu.solve(b);
        }
    }

    /// The shift-invert operator on coordinates: u = first nc of A(σ)⁻¹ [M v; 0].
    fn apply(&mut self, p: &Problem, v: &[f64], out: &mut [f64]) {
        let mut rhs = std::mem::take(&mut self.rhs);
        p.m_times(v, &mut rhs[..p.nc]);
        rhs[p.nc..].iter_mut().for_each(|r| *r = 0.0);
        self.solve(&mut rhs);
        out.copy_from_slice(&rhs[..p.nc]);
        self.rhs = rhs;
    }

    /// The operator for a vector whose product `mv` = M v is known.
    fn apply_mv(&mut self, p: &Problem, mv: &[f64], out: &mut [f64]) {
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs[..p.nc].copy_from_slice(mv);
        rhs[p.nc..].iter_mut().for_each(|r| *r = 0.0);
        self.solve(&mut rhs);
        out.copy_from_slice(&rhs[..p.nc]);
        self.rhs = rhs;
    }

    /// Number of eigenvalues below `s` by the inertia of A(s), if L D Lᵀ can factor it (the
    /// factorisation at σ is kept: a copy of the symbolic structure is used, made once and
    /// refactored at every count).
    fn count_below(&mut self, p: &Problem, s: f64) -> Option<usize> {
        let (lu, slots) = self.sym.as_ref()?;
        self.lower.clear();
        self.lower
            .extend(slots.iter().map(|&q| p.k[q] - s * p.m[q]));
        let counter = self.counter.get_or_insert_with(|| lu.clone());
        counter.refactor_symmetric(&self.lower).ok()?;
        counter.negative_pivots().checked_sub(p.n - p.nc)
    }
}

/// A basis with the products of M: columns of `v` and `mv` = M `v`.
struct Basis<'a> {
    v: MatRef<'a, f64>,
    mv: MatRef<'a, f64>,
    /// Number of columns in use.
    j: usize,
}

/// M-inner-product Gram–Schmidt of `w` against the bases (classical Gram–Schmidt with one
/// reorthogonalisation); the coefficients against the first basis go to `h` (length
/// `main.j`), and the M-norm of the result is returned, with `mw` = M w on return. One
/// product with M, at the end: the coefficients are the products of w with the stored M vᵢ.
/// `scratch` holds at least as many entries as the larger basis has columns.
fn orthogonalise(
    p: &Problem,
    main: &Basis<'_>,
    locked: Option<&Basis<'_>>,
    w: &mut [f64],
    mw: &mut [f64],
    h: &mut [f64],
    scratch: &mut [f64],
) -> f64 {
    h.iter_mut().for_each(|x| *x = 0.0);
    for _pass in 0..2 {
        for (b, is_main) in [(Some(main), true), (locked, false)] {
            let Some(b) = b else { continue };
            if b.j == 0 {
                continue;
            }
            let c = &mut scratch[..b.j];
            basis_dots(b.mv, w, c);
            basis_subtract(b.v, c, w);
            if is_main {
                h.iter_mut().zip(c.iter()).for_each(|(a, x)| *a += x);
            }
        }
    }
    p.m_times(w, mw);
    let norm2 = dot(w, mw);
    norm2.max(0.0).sqrt()
}

/// Converged Ritz pairs of one Krylov–Schur run: θ (descending) and vectors (columns).
struct Run {
    theta: Vec<f64>,
    x: Mat<f64>,
    applications: usize,
}

/// Krylov–Schur (thick-restart Lanczos) for the `nev` largest θ of the operator, M-orthogonal
/// to `locked` (M-orthonormal columns). Fewer pairs are returned when the reachable space is
/// smaller (all of them exact then). `Err(applications)` when `max_applications` was reached.
fn krylov_schur(
    p: &Problem,
    op: &mut Shifted,
    nev: usize,
    locked: &Mat<f64>,
    seed: u64,
    max_applications: usize,
) -> Result<Run, usize> {
    let nc = p.nc;
    let mmax = (2 * nev + 10).max(nev + 20).min(nc);
    let mut v = Mat::<f64>::zeros(nc, mmax + 1);
    let mut mv = Mat::<f64>::zeros(nc, mmax + 1);
    let mut h = Mat::<f64>::zeros(mmax, mmax);
    let mut w = vec![0.0; nc];
    let mut mw = vec![0.0; nc];
    // Gram–Schmidt coefficients and their scratch (the larger of the two bases)
    let mut hc = vec![0.0; mmax + 1];
    let mut scratch = vec![0.0; (mmax + 1).max(locked.ncols())];
    let mut start_scratch = vec![0.0; 2 * (mmax + 1) + locked.ncols()];
    let mut rng = Rng(seed);
    let mut applications = 0;
    let mut ml = Mat::<f64>::zeros(nc, locked.ncols());
    for c in 0..locked.ncols() {
        p.m_times(locked.col_as_slice(c), ml.col_as_slice_mut(c));
    }
    let lk = Basis {
        v: locked.as_ref(),
        mv: ml.as_ref(),
        j: locked.ncols(),
    };
    let lk = (lk.j > 0).then_some(&lk);
    // a start vector from the operator's range, M-orthogonal to the first j basis vectors,
    // normalised into column j; false when the reachable space is exhausted
    let mut new_start = |v: &mut Mat<f64>,
                         mv: &mut Mat<f64>,
                         j: usize,
                         w: &mut Vec<f64>,
                         mw: &mut Vec<f64>,
                         op: &mut Shifted,
                         applications: &mut usize|
     -> bool {
        for _ in 0..3 {
            // the random vector in mw (overwritten by M w below)
            mw.iter_mut().for_each(|x| *x = rng.next());
            op.apply(p, mw, w);
            *applications += 1;
            p.m_times(w, mw);
            let before: f64 = w.iter().zip(mw.iter()).map(|(a, b)| a * b).sum::<f64>();
            let main = Basis {
                v: v.as_ref(),
                mv: mv.as_ref(),
                j,
            };
            let (h, rest) = start_scratch.split_at_mut(j);
            let after = orthogonalise(p, &main, lk, w, mw, h, rest);
            if before > 0.0 && after > 1e-8 * before.sqrt() {
                for (dst, src) in [(&mut *v, &*w), (&mut *mv, &*mw)] {
                    dst.col_as_slice_mut(j)
                        .iter_mut()
                        .zip(src.iter())
                        .for_each(|(a, b)| *a = b / after);
                }
                return true;
            }
        }
        false
    };
    if !new_start(&mut v, &mut mv, 0, &mut w, &mut mw, op, &mut applications) {
        return Ok(Run {
            theta: Vec::new(),
            x: Mat::zeros(nc, 0),
            applications,
        });
    }
    let mut k = 0; // size of the kept (restarted) decomposition
    loop {
        // expand from k to mmax: S V_m = V_m H_m + β v_{m+1} e_mᵀ
        let mut beta = 0.0;
        let mut j = k;
        let mut exhausted = false;
        while j < mmax {
            op.apply_mv(p, mv.col_as_slice(j), &mut w);
            applications += 1;
            let main = Basis {
                v: v.as_ref(),
                mv: mv.as_ref(),
                j: j + 1,
            };
            let hc = &mut hc[..j + 1];
            let b = orthogonalise(p, &main, lk, &mut w, &mut mw, hc, &mut scratch);
            for (i, c) in hc.iter().enumerate() {
                h[(i, j)] = *c;
            }
            let scale = hc.iter().fold(0.0f64, |a, c| a.max(c.abs()));
            j += 1;
            if b > 1e-12 * scale && b > 0.0 {
                beta = b;
                for (dst, src) in [(&mut v, &w), (&mut mv, &mw)] {
                    dst.col_as_slice_mut(j)
                        .iter_mut()
                        .zip(src.iter())
                        .for_each(|(a, c)| *a = c / b);
                }
            } else {
                // an invariant subspace: continue with a new direction (coupling zero)
                beta = 0.0;
                if j < mmax
                    && !new_start(&mut v, &mut mv, j, &mut w, &mut mw, op, &mut applications)
                {
                    exhausted = true;
                    break;
                }
            }
        }
        let m = j;
        // Ritz pairs of the symmetric projected matrix (its upper triangle was computed)
        let hs = h.as_ref().submatrix(0, 0, m, m).transpose();
        // wanted: the largest θ (the eigenvalues nearest above the shift); the vectors of the
        // `want` largest (converged) or of the `keep` largest (restart), largest first
        let want = nev.min(m);
        let keep = if m >= 2 {
            (nev + (mmax - nev) / 2).clamp(1, m - 1)
        } else {
            1
        };
        let (s, y) =
            projected_eigen_largest(hs, want.max(keep).min(m)).map_err(|_| applications)?;
        // column c of y belongs to θ = s[m − 1 − c]
        let converged = |c: usize| {
            let t = s[m - 1 - c];
            (beta * y[(m - 1, c)]).abs() <= TOL * t.abs() && t != 0.0
        };
        let conv = (0..want).take_while(|&c| converged(c)).count();
        if conv == want || exhausted || beta == 0.0 {
            return Ok(Run {
                theta: (0..want).map(|c| s[m - 1 - c]).collect(),
                x: basis_combine(v.subcols(0, m), y.subcols(0, want)),
                applications,
            });
        }
        if applications >= max_applications {
            return Err(applications);
        }
        // thick restart: the best `keep` Ritz vectors, then the residual vector
        let ysel = y.subcols(0, keep);
        for basis in [&mut v, &mut mv] {
            let vk = basis_combine(basis.subcols(0, m), ysel);
            for c in 0..keep {
                basis
                    .col_as_slice_mut(c)
                    .copy_from_slice(vk.col_as_slice(c));
            }
            let resid = basis.col_as_slice(m).to_vec();
            basis.col_as_slice_mut(keep).copy_from_slice(&resid);
        }
        h.fill(0.0);
        for c in 0..keep {
            // the coupling of the kept vectors to the residual vector (β times the last row of
            // their Ritz vectors) is computed again by the next orthogonalisation
            h[(c, c)] = s[m - 1 - c];
        }
        k = keep;
    }
}

/// Krylov–Schur runs at the current shift until the `want` largest θ have converged and the
/// Sturm check (inertia just above the last of them) finds no eigenvalue missed; a missed one
/// (the second copy of a multiple eigenvalue) is found by a further run deflated against the
/// vectors found. Returns the Ritz vectors, their θ and the operator applications used.
fn lanczos_runs(
    p: &Problem,
    op: &mut Shifted,
    want: usize,
    max_applications: usize,
) -> Result<(Mat<f64>, Vec<f64>, usize), ModalError> {
    let nc = p.nc;
    let sigma = op.sigma;
    let mut found: Mat<f64> = Mat::zeros(nc, 0);
    let mut thetas: Vec<f64> = Vec::new();
    let mut applications = 0;
    for run in 0..8u64 {
        let need = want.saturating_sub(thetas.len()).max(1);
        let r = krylov_schur(
            p,
            op,
            need,
            &found,
            0x5DEE_CE66_D1CE_4E5B ^ (run + 1).wrapping_mul(0x9E37_79B9),
            max_applications.saturating_sub(applications),
        )
        .map_err(|a| ModalError::NotConverged {
            found: thetas.len(),
            wanted: want,
            applications: applications + a,
        })?;
        applications += r.applications;
        if r.theta.is_empty() {
            break;
        }
        let old = found.ncols();
        let mut all = Mat::<f64>::zeros(nc, old + r.x.ncols());
        for c in 0..old {
            all.col_as_slice_mut(c)
                .copy_from_slice(found.col_as_slice(c));
        }
        for c in 0..r.x.ncols() {
            all.col_as_slice_mut(old + c)
                .copy_from_slice(r.x.col_as_slice(c));
        }
        found = all;
        thetas.extend(&r.theta);
        if thetas.len() < want {
            continue;
        }
        let mut lam: Vec<f64> = thetas.iter().map(|&t| sigma + 1.0 / t).collect();
        lam.sort_by(f64::total_cmp);
        let last = lam[want - 1];
        let scale = lam.iter().fold(sigma.abs(), |a, l| a.max(l.abs()));
        let check = last + 1e-6 * scale.max(f64::MIN_POSITIVE);
        match op.count_below(p, check) {
            Some(below) if below > lam.iter().filter(|&&l| l < check).count() => continue,
            _ => break,
        }
    }
    if thetas.is_empty() {
        return Err(ModalError::NotConverged {
            found: 0,
            wanted: want,
            applications,
        });
    }
    Ok((found, thetas, applications))
}

/// The lowest `count` eigenpairs on the sparse path.
pub(crate) fn sparse_modes(
    model: &Model,
    step: &StepResult,
    count: usize,
) -> Result<SparseModes, ModalError> {
    rigid::modes_listing_rigid(&Problem::new(model, step), model, step, count)
}

/// The sparse problem of a model at a step, kept by [`sparse_modes_kept`] for further solves
/// on the same matrices ([`SparseProblem::static_responses`]).
pub(crate) struct SparseProblem(Problem);

/// [`sparse_modes`], keeping the sparse problem for static solves with the same matrices.
pub(crate) fn sparse_modes_kept(
    model: &Model,
    step: &StepResult,
    count: usize,
) -> Result<(SparseModes, SparseProblem), ModalError> {
    let p = Problem::new(model, step);
    let sm = modes_of(&p, model, step, count)?;
    Ok((sm, SparseProblem(p)))
}

impl SparseProblem {
    /// δx = K⁻¹ f of each load in x (module `sparse_static`).
    pub(crate) fn static_responses(
        &self,
        model: &Model,
        step: &StepResult,
        loads: &[Vec<f64>],
    ) -> Result<Vec<Vec<f64>>, ModalError> {
        static_responses(&self.0, model, step, loads)
    }
}

/// The lowest `count` eigenpairs of the problem `p` of `model` at `step`.
fn modes_of(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    count: usize,
) -> Result<SparseModes, ModalError> {
    let nc = p.nc;
    let n_constraints = p.n - nc;
    if nc < n_constraints {
        // more constraints than coordinates: some repeat others (the dense path removes them)
        return Err(ModalError::SparseSingular);
    }
    if nc == n_constraints {
        return Err(ModalError::NoDof);
    }
    if p.m_val.iter().all(|&v| v == 0.0) {
        return Err(ModalError::NoMass);
    }
    let ndof = nc - n_constraints;
    let mut op = Shifted::new(p);
    // scale of the eigenvalues: the largest Rayleigh quotient of a unit coordinate
    let (kd, md) = p.diagonals();
    let lambda_ref = kd
        .iter()
        .zip(&md)
        .filter(|(_, &m)| m > 0.0)
        .map(|(&k, &m)| k.abs() / m)
        .fold(0.0f64, f64::max)
        .max(f64::MIN_POSITIVE);
    // shift: 0 when K is positive definite on the constrained space, else lowered until no
    // eigenvalue lies below it (inertia), starting just above the round-off level
    let mut shifts = vec![0.0];
    let floor = f64::EPSILON * lambda_ref / nc as f64;
    shifts.extend((0..12).map(|i| -floor * 100f64.powi(i)));
    let mut chosen = None;
    for &s in &shifts {
        if op.factor(p, s, false) && op.below == Some(0) {
            chosen = Some(s);
            break;
        }
    }
    if chosen.is_none() {
        // no L D Lᵀ without eigenvalues below the shift: LU, without the inertia check
        for &s in &shifts {
            if op.factor(p, s, true) {
                chosen = Some(s);
                break;
            }
        }
    }
    let Some(mut sigma) = chosen else {
        let names: Vec<String> = super::massless_nodes(model, &step.x)
            .iter()
            .map(|&i| model.nodes[i].name.clone())
            .collect();
        if !names.is_empty() {
            return Err(ModalError::MasslessMechanism {
                nodes: names.join(", "),
            });
        }
        return Err(ModalError::SparseSingular);
    };
    // massless directions: the finite eigenvalues all lie below a shift far above them
    let massless = match op.count_below(p, 1e8 * lambda_ref) {
        Some(finite) if finite <= ndof => ndof - finite,
        _ => md.iter().filter(|&&m| m <= 0.0).count().min(ndof),
    };
    let n_finite = ndof - massless;
    let want = count.min(n_finite);
    if want == 0 {
        return Ok(SparseModes {
            eigenvalues: Vec::new(),
            shapes: Vec::new(),
            ndof,
            massless,
            kinetic: Vec::new(),
            rigid: 0,
            below_gap: None,
        });
    }
    let max_applications = 200 + MAX_APPLICATIONS_PER_MODE * want;
    let (mut found, mut thetas, mut applications) =
        lanczos_runs(p, &mut op, want, max_applications)?;
    // A shift that makes the operator amplify some directions far more than the wanted modes
    // costs these digits when they are orthogonalised against those directions: a shift far
    // closer to the lowest eigenvalue than to the last wanted one (zero-frequency motions, an
    // unstable mode), or a small negative shift that only just regularises a matrix singular
    // in directions the constraints remove (a massless or stiffness-free part of a rigid
    // body). Then shift again, clearly below the lowest eigenvalue (the inertia confirms it).
    let mut lam: Vec<f64> = thetas.iter().map(|&t| sigma + 1.0 / t).collect();
    lam.sort_by(f64::total_cmp);
    let (l1, lk) = (lam[0], lam[lam.len().min(want) - 1]);
    let dominated = lk - sigma > 1e6 * (l1 - sigma);
    let barely_regular = sigma < 0.0 && -sigma < 1e-3 * (l1 - sigma);
    if dominated || barely_regular {
        let s2 = (l1 - 0.1 * (lk - l1)).min(-0.5 * l1.abs());
        if op.factor(p, s2, false) && op.below == Some(0) {
            let budget = max_applications.saturating_sub(applications).max(1);
            let (f2, t2, a2) = lanczos_runs(p, &mut op, want, budget)?;
            (found, thetas, sigma, applications) = (f2, t2, s2, applications + a2);
        } else if !op.factor(p, sigma, true) {
            return Err(ModalError::SparseSingular);
        }
    }
    debug_assert!(applications <= 2 * max_applications);
    // the lowest `want` by θ; purified by one more application when there are massless
    // directions (their components then follow the massive ones exactly)
    let mut order: Vec<usize> = (0..thetas.len()).collect();
    order.sort_by(|&a, &b| (sigma + 1.0 / thetas[a]).total_cmp(&(sigma + 1.0 / thetas[b])));
    order.truncate(want);
    let nf = order.len();
    let mut y = Mat::<f64>::zeros(nc, nf);
    for (c, &i) in order.iter().enumerate() {
        if massless > 0 {
            let xc = found.col_as_slice(i).to_vec();
            op.apply(p, &xc, y.col_as_slice_mut(c));
        } else {
            y.col_as_slice_mut(c).copy_from_slice(found.col_as_slice(i));
        }
    }
    // M-orthonormal: the Ritz vectors are (full reorthogonalisation); purified ones are made so
    // again (Löwdin: Y (YᵀMY)^-½, the nearest M-orthonormal set)
    let q = if massless > 0 {
        let mut my = Mat::<f64>::zeros(nc, nf);
        for c in 0..nf {
            p.m_times(y.col_as_slice(c), my.col_as_slice_mut(c));
        }
        let g = y.transpose() * &my;
        let g = Mat::from_fn(nf, nf, |a, b| 0.5 * (g[(a, b)] + g[(b, a)]));
        let (gs, gu) = projected_eigen(g.as_ref())?;
        if (0..nf).any(|i| gs[i].is_nan() || gs[i] <= 0.0) {
            return Err(ModalError::Eigen(EigenError::NotPositiveDefinite {
                what: "projected mass",
                index: 0,
                hint: "the converged modes are linearly dependent",
            }));
        }
        let inv_sqrt = Mat::from_fn(nf, nf, |a, b| {
            (0..nf)
                .map(|k| gu[(a, k)] * gu[(b, k)] / gs[k].sqrt())
                .sum::<f64>()
        });
        &y * &inv_sqrt
    } else {
        y
    };
    let shapes: Vec<Vec<f64>> = if nc < PAR_MIN {
        (0..nf)
            .map(|k| p.lin.to_x(model, &step.x, q.col_as_slice(k)))
            .collect()
    } else {
        (0..nf)
            .into_par_iter()
            .map(|k| p.lin.to_x(model, &step.x, q.col_as_slice(k)))
            .collect()
    };
    // eigenvalues: Rayleigh quotients, the stiffness through the element deformations
    let e2 = p.lin.material_energy2(model, &step.x, &shapes);
    let mut g2 = vec![0.0; nf];
    if p.lin.geo.iter().any(|&v| v != 0.0) {
        let mut e = 0;
        p.lin.for_each_entry(|r, c| {
            let gv = p.lin.geo[e];
            if gv != 0.0 {
                for (k, g) in g2.iter_mut().enumerate() {
                    *g += gv * q[(r, k)] * q[(c, k)];
                }
            }
            e += 1;
        });
    }
    for &(r, c, kv) in &p.extra_k {
        for (k, g) in g2.iter_mut().enumerate() {
            *g += kv * q[(r, k)] * q[(c, k)];
        }
    }
    let mut modes: Vec<(f64, Vec<f64>, NodeKinetic)> = Vec::with_capacity(nf);
    let mut mu = vec![0.0; nc];
    for (k, shape) in shapes.into_iter().enumerate() {
        let u = q.col_as_slice(k);
        let g2 = g2[k];
        p.m_times(u, &mut mu);
        let m2: f64 = u.iter().zip(&mu).map(|(a, b)| a * b).sum();
        let lam = (e2[k] + g2) / m2;
        let mut kinetic = vec![(0.0, 0.0); model.nodes.len()];
        for (m, (&node, (a, b))) in p.group.iter().zip(u.iter().zip(&mu)).enumerate() {
            if let Some(t) = kinetic.get_mut(node) {
                if p.lin.is_translation(m) {
                    t.0 += a * b;
                } else {
                    t.1 += a * b;
                }
            }
        }
        modes.push((lam, shape, kinetic));
    }
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut eigenvalues = Vec::with_capacity(nf);
    let mut shapes = Vec::with_capacity(nf);
    let mut kinetic = Vec::with_capacity(nf);
    for (l, s, t) in modes {
        eigenvalues.push(l);
        shapes.push(s);
        kinetic.push(t);
    }
    let below_gap = rigid::probe(p, &mut op, sigma, lambda_ref, &eigenvalues, n_finite);
    Ok(SparseModes {
        rigid: rigid::count(&eigenvalues, below_gap),
        eigenvalues,
        shapes,
        ndof,
        massless,
        kinetic,
        below_gap,
    })
}

#[path = "sparse_rigid.rs"]
mod rigid;

#[path = "sparse_static.rs"]
mod static_solve;
use static_solve::static_responses;

#[cfg(test)]
#[path = "sparse_tests.rs"]
mod tests;
