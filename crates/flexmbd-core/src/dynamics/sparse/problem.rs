//! The sparse problem: K and M of the stage (`linearized::sparse`: the statics Newton matrix
//! [K, Gᵀ; G, 0] at the state with the softening, and the mass in the same reduced
//! coordinates), with optional added constraint rows, in CSC form, and the fill-reducing
//! saddle-point order of its factorisation.

use super::basis::PAR_MIN;
use crate::linearized::sparse::element_blocks;
use crate::linearized::Tangent;
use crate::math::sparse_lu::{amd_order, share_rows, sort_small, ColRows, RowIndex};
use crate::model::Model;
use crate::statics::ReducedLinear;
use crate::statics::StepResult;
use rayon::prelude::*;

/// The sparse problem: K and M in the reduced coordinates, with the constraint rows.
pub(super) struct Problem {
    pub(super) lin: ReducedLinear,
    /// Stiffness entries outside the element pattern (softening of point masses), for the
    /// Rayleigh quotients.
    pub(super) extra_k: Vec<(usize, usize, f64)>,
    /// Size of the saddle-point system.
    pub(super) n: usize,
    /// Number of coordinates (the first `nc` unknowns).
    pub(super) nc: usize,
    /// The pivot order of the factorisation (step k eliminates unknown `perm[k]`;
    /// [`saddle_order`]), in which the matrix is kept; the identity when no such order was
    /// found (`ordered` false).
    pub(super) perm: Vec<u32>,
    pub(super) ordered: bool,
    /// CSC structure of the lower triangle (row ≥ column) of the symmetric saddle-point matrix
    /// in the pivot order (column k: step k, rows: the steps s ≥ k coupled to it, sorted,
    /// starting with the diagonal; u32 rows, 4 bytes per entry): half the entries of both
    /// triangles, and the very layout the L D Lᵀ factorisation reads (not held a second time
    /// beside it).
    /// (The rows are held as lists shared by the columns of a supernode, [`share_rows`]: a
    /// node's six columns read one list; [`Problem::rows`].)
    col_ptr: Vec<u32>,
    row_idx: Vec<u32>,
    row_start: Vec<u32>,
    /// K values on that structure (the symmetric part of K): released while the Lanczos basis
    /// is held and made again from the model when a factorisation needs them
    /// ([`Problem::release_k`], [`Problem::restore_k`]; 8 bytes per entry).
    k: std::sync::RwLock<Vec<f64>>,
    /// The entries (row, column, value) of the added constraint rows, for making K again.
    added: Vec<(usize, usize, f64)>,
    /// The coordinate block of M (CSC, lower triangle, non-zero entries only, rows sorted), for
    /// M v ([`Problem::m_times`]); an entry of the structure above finds its M value here by
    /// bisection ([`Problem::shifted_entries`]), without a map of 4 bytes per entry.
    pub(super) m_ptr: Vec<u32>,
    pub(super) m_idx: Vec<u32>,
    pub(super) m_val: Vec<f64>,
}

/// A symmetric matrix A, stored as its lower triangle (CSC, rows sorted), times a vector, into
/// `out`: (A v)_j = Σ_i A_ij v_i summed over i ascending, as a gather over the whole column j
/// of both triangles would sum it (the same value to the bit, with half the entries stored).
/// The terms above the diagonal (i < j: entry (j, i) of column i) are scattered first, column
/// by column in order (serial); those on and below it are then gathered onto them (parallel
/// over columns).
fn csc_lower_sym_times(ptr: &[u32], idx: &[u32], val: &[f64], v: &[f64], out: &mut [f64]) {
    const CHUNK: usize = 4096;
    // (the start of a sum of floats, which is where a gather would start)
    let start: f64 = std::iter::empty::<f64>().sum();
    out.iter_mut().for_each(|y| *y = start);
    for (i, &vi) in v.iter().enumerate() {
        let (lo, hi) = (ptr[i] as usize, ptr[i + 1] as usize);
        for (&j, &a) in idx[lo..hi].iter().zip(&val[lo..hi]) {
            if j as usize != i {
                out[j as usize] += a * vi;
            }
        }
    }
    let gather = |j: usize, y: &mut f64| {
        let (lo, hi) = (ptr[j] as usize, ptr[j + 1] as usize);
        *y = idx[lo..hi]
            .iter()
            .zip(&val[lo..hi])
            .fold(*y, |s, (&i, &a)| s + a * v[i as usize]);
    };
    if out.len() < PAR_MIN {
        out.iter_mut().enumerate().for_each(|(j, y)| gather(j, y));
        return;
    }
    out.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(c, chunk)| {
            for (o, y) in chunk.iter_mut().enumerate() {
                gather(c * CHUNK + o, y);
            }
        });
}

/// The structure of both triangles (CSC, rows sorted) of a symmetric matrix from that of one
/// triangle, each unknown i renamed `label(i)` (a permutation; the identity keeps the
/// numbering).
fn full_of_triangle<P: RowIndex>(
    n: usize,
    tri: ColRows<'_, P>,
    label: impl Fn(usize) -> usize,
) -> (Vec<usize>, Vec<u32>) {
    let mut ptr = vec![0usize; n + 1];
    for t in 0..n {
        let c = label(t);
        for &r in tri.of(t) {
            let r = label(r as usize);
            ptr[c + 1] += 1;
            if r != c {
                ptr[r + 1] += 1;
            }
        }
    }
    for c in 0..n {
        ptr[c + 1] += ptr[c];
    }
    let mut rows = vec![0u32; ptr[n]];
    let mut fill: Vec<usize> = ptr[..n].to_vec();
    for t in 0..n {
        let c = label(t);
        for &r in tri.of(t) {
            let r = label(r as usize);
            rows[fill[c]] = r as u32;
            fill[c] += 1;
            if r != c {
                rows[fill[r]] = c as u32;
                fill[r] += 1;
            }
        }
    }
    for c in 0..n {
        // (already ascending for the identity: insertion sort passes over it once)
        sort_small(&mut rows[ptr[c]..ptr[c + 1]]);
    }
    (ptr, rows)
}

/// The step of every unknown in the pivot order `perm` (step k eliminates unknown `perm[k]`).
fn inverse(perm: &[u32]) -> Vec<u32> {
    let mut inv = vec![0u32; perm.len()];
    for (s, &c) in perm.iter().enumerate() {
        inv[c as usize] = s as u32;
    }
    inv
}

/// The position of entry (r, c) of a symmetric matrix, either triangle, in its stored lower
/// triangle (CSC, rows sorted) whose unknown i is `step(i)`: column min, row max.
fn lower_position<P: RowIndex>(
    tri: ColRows<'_, P>,
    step: impl Fn(usize) -> usize,
    r: usize,
    c: usize,
) -> usize {
    let (a, b) = (step(r), step(c));
    let (s, t) = (a.max(b), a.min(b));
    let q = tri.find(t, s);
    debug_assert!(q.is_ok(), "entry ({s}, {t}) is in the structure");
    q.unwrap_or_else(|q| q)
}

/// The weight of an entry in the stored lower triangle: an entry off the diagonal adds half its
/// value to its place, and so does its mirror (the symmetric part (K + Kᵀ)/2).
fn half(r: usize, c: usize) -> f64 {
    if r == c {
        1.0
    } else {
        0.5
    }
}

/// The lower triangle of P A Pᵀ (step k = unknown `perm[k]`) from that of A, with the values
/// of its entries: each entry (r, c) goes to column min(inv r, inv c), row max(inv r, inv c),
/// the rows of each column sorted.
fn permuted_lower(
    perm: &[u32],
    col_ptr: &[usize],
    row_idx: &[u32],
    k: &[f64],
) -> (Vec<usize>, Vec<u32>, Vec<f64>) {
    let n = perm.len();
    let inv = inverse(perm);
    let place = |q: usize, c: usize| {
        let (a, b) = (inv[row_idx[q] as usize], inv[c]);
        (a.max(b), a.min(b) as usize)
    };
    let mut ptr = vec![0usize; n + 1];
    for c in 0..n {
        for q in col_ptr[c]..col_ptr[c + 1] {
            ptr[place(q, c).1 + 1] += 1;
        }
    }
    for t in 0..n {
        ptr[t + 1] += ptr[t];
    }
    // (row, source entry) of every new position, each column sorted by row
    let mut fill: Vec<usize> = ptr[..n].to_vec();
    let mut at = vec![(0u32, 0u32); ptr[n]];
    for c in 0..n {
        for q in col_ptr[c]..col_ptr[c + 1] {
            let (s, t) = place(q, c);
            at[fill[t]] = (s, q as u32);
            fill[t] += 1;
        }
    }
    drop(fill);
    for t in 0..n {
        sort_small(&mut at[ptr[t]..ptr[t + 1]]);
    }
    let rows = at.iter().map(|&(s, _)| s).collect();
    let kp = at.iter().map(|&(_, q)| k[q as usize]).collect();
    (ptr, rows, kp)
}

impl Problem {
    /// The problem of a modal analysis alone.
    pub(super) fn new(t: &Tangent) -> Self {
        Self::with_rows(t, &[])
    }

    /// The problem with constraint rows added after those of the Newton system: row j holds
    /// the vector `rows[j]` in x (length nx) mapped onto the coordinate unknowns. The state space uses them to hold again
    /// the coordinates it freed in a copy of the model, so that their multipliers are the
    /// reactions and their right-hand sides the enforced motions. The element values of the
    /// stage are released once the saddle-point matrix holds them (12 MB at 10⁴ beams; the
    /// geometric ones too when they are all zero): the products of the refined solves take the
    /// material part through the deformations and the rest from the matrix.
    pub(super) fn with_rows(t: &Tangent, rows: &[Vec<f64>]) -> Self {
        let (model, step) = (t.model(), t.step());
        // K (with the softening) and M of the stage, in the reduced unknowns
        let mut tangent = t.sparse();
        let mut extra = std::mem::take(&mut tangent.nodes);
        let lin = &tangent.lin;
        let rows: Vec<Vec<(usize, f64)>> = rows
            .iter()
            .map(|w| {
                let coords = lin.force_to_coords(&step.x, w);
                coords
                    .into_iter()
                    .enumerate()
                    .filter(|(_, v)| *v != 0.0)
                    .collect()
            })
            .collect();
        let (n0, nc) = (lin.n(), lin.n_coords());
        let n = n0 + rows.len();
        let extra_k: Vec<(usize, usize, f64)> = extra
            .iter()
            .filter(|e| e.2 != 0.0)
            .map(|e| (e.0, e.1, e.2))
            .collect();
        // the added constraint rows (stiffness entries, no mass), both triangles
        let added: Vec<(usize, usize, f64)> = rows
            .iter()
            .enumerate()
            .flat_map(|(j, row)| row.iter().map(move |&(c, v)| (n0 + j, c, v)))
            .collect();
        for &(r, c, v) in &added {
            extra.push((r, c, v, 0.0));
            extra.push((c, r, v, 0.0));
        }
        // CSC structure of the lower triangle (row ≥ column; the matrix is symmetric, and the
        // factorisation and the products read one triangle): the rows of every column
        // (element entries, node masses and added rows, each pair on its lower side, and the
        // diagonal) bucketed, each column sorted with its duplicates removed in place
        let mut count = vec![0usize; n + 1];
        let mut count_entry = |r: usize, c: usize| {
            if r >= c {
                count[c + 1] += 1;
            }
        };
        lin.for_each_entry(&mut count_entry);
        for &(r, c, _, _) in &extra {
            count_entry(r, c);
        }
        for c in 0..n {
            count[c + 1] += 1;
        }
        for c in 0..n {
            count[c + 1] += count[c];
        }
        let mut rows = vec![0u32; count[n]];
        {
            let mut fill = count.clone();
            let mut put = |r: usize, c: usize| {
                if r >= c {
                    rows[fill[c]] = r as u32;
                    fill[c] += 1;
                }
            };
            lin.for_each_entry(&mut put);
            for &(r, c, _, _) in &extra {
                put(r, c);
            }
            for c in 0..n {
                put(c, c);
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut nnz = 0;
        for c in 0..n {
            let (lo, hi) = (count[c], count[c + 1]);
            sort_small(&mut rows[lo..hi]);
            for q in lo..hi {
                if q == lo || rows[q] != rows[q - 1] {
                    rows[nnz] = rows[q];
                    nnz += 1;
                }
            }
            col_ptr.push(nnz);
        }
        drop(count);
        rows.truncate(nnz);
        rows.shrink_to_fit();
        let row_idx = rows;
        // the values, summed into their places in the order of the entries (element entries,
        // then node masses and added rows), each found by bisection in its column, with the
        // weights of the symmetric part (`half`): the lower triangle holds (K + Kᵀ)/2, as the
        // factorisation needs (the load stiffness of moments is not symmetric; the dense path
        // takes the same part). K's entries after the element blocks are added once the
        // structure is in pivot order (`Problem::add_k_rest`, which also serves `restore_k`).
        let at =
            |r: usize, c: usize| lower_position(ColRows::plain(&col_ptr, &row_idx), |i| i, r, c);
        let (mut k, mut m) = (vec![0.0; nnz], vec![0.0; nnz]);
        tangent.element_blocks(model, step, |els, kb, mb| {
            let mut i = 0;
            lin.for_each_entry_in(els, |r, c| {
                let (q, w) = (at(r, c), half(r, c));
                k[q] += w * kb[i];
                m[q] += w * mb[i];
                i += 1;
            });
        });
        for &(r, c, _, mv) in &extra {
            m[at(r, c)] += half(r, c) * mv;
        }
        // the saddle-point matrix holds the stage's values now (the tail's are kept to make K
        // again: a few per rotational node)
        let mut lin = tangent.lin;
        lin.release_assembly();
        // the coordinate block of M (non-zero entries of the lower triangle, rows sorted as
        // in the structure above)
        // (32-bit rows like the rows above: below 4·10⁹ entries, some 3·10⁷ beams, far beyond
        // the memory of the machines this runs on)
        let mut m_ptr = Vec::with_capacity(nc + 1);
        let (mut m_idx, mut m_val) = (Vec::new(), Vec::new());
        m_ptr.push(0);
        for c in 0..nc {
            for p in col_ptr[c]..col_ptr[c + 1] {
                if (row_idx[p] as usize) < nc && m[p] != 0.0 {
                    m_idx.push(row_idx[p]);
                    m_val.push(m[p]);
                }
            }
            m_ptr.push(m_idx.len() as u32);
        }
        m_idx.shrink_to_fit();
        m_val.shrink_to_fit();
        drop(m);
        if lin.geo.iter().all(|&v| v == 0.0) {
            lin.geo = Vec::new();
        }
        let group = lin.coord_nodes(model);
        // the pivot order, and the lower triangle (K and the places of M) permuted into it
        let point: Vec<usize> = group
            .iter()
            .map(|&g| model.nodes.get(g).and_then(|n| n.host).unwrap_or(g))
            .collect();
        let order = {
            let (fp, fr) = full_of_triangle(n, ColRows::plain(&col_ptr, &row_idx), |i| i);
            Self::saddle_order(n, nc, &point, (&fp, &fr)).ok()
        };
        drop((point, group));
        let ordered = order.is_some();
        let perm: Vec<u32> = match order {
            Some(o) => o.into_iter().map(|c| c as u32).collect(),
            None => (0..n as u32).collect(),
        };
        let (col_ptr, row_idx, mut k) = permuted_lower(&perm, &col_ptr, &row_idx, &k);
        let (row_idx, row_start) = share_rows(&col_ptr, &row_idx).unwrap_or((row_idx, Vec::new()));
        // (32-bit like the rows: below 4·10⁹ entries)
        let col_ptr: Vec<u32> = col_ptr.iter().map(|&p| p as u32).collect();
        let mut p = Self {
            lin,
            extra_k,
            added,
            n,
            nc,
            perm,
            ordered,
            col_ptr,
            row_idx,
            row_start,
            k: std::sync::RwLock::new(Vec::new()),
            m_ptr,
            m_idx,
            m_val,
        };
        p.add_k_rest(&inverse(&p.perm), &mut k);
        p.k = std::sync::RwLock::new(k);
        p
    }

    /// The position of entry (r, c), either triangle, in the stored lower triangle, with the
    /// steps `inv` of the pivot order ([`inverse`]).
    fn position_in<'a>(&'a self, inv: &'a [u32]) -> impl Fn(usize, usize) -> usize + 'a {
        move |r, c| lower_position(self.rows(), |i| inv[i] as usize, r, c)
    }

    /// The stored lower triangle's rows by column (pivot steps; the values of column t's
    /// entries are at positions `col_ptr[t]..col_ptr[t + 1]`).
    pub(super) fn rows(&self) -> ColRows<'_, u32> {
        ColRows::shared(&self.col_ptr, &self.row_idx, &self.row_start)
    }

    /// Number of entries of the stored lower triangle.
    pub(super) fn nnz(&self) -> usize {
        self.col_ptr[self.n] as usize
    }

    /// K's entries after the element blocks, added into `k` (the stored lower triangle, whose
    /// unknown i is step `inv[i]`) after its element part, in this order: the tail (load
    /// stiffness of moments, normalisations), the softening of point masses, the added rows.
    fn add_k_rest(&self, inv: &[u32], k: &mut [f64]) {
        let at = self.position_in(inv);
        for (r, c, kv) in self.lin.tail() {
            k[at(r, c)] += half(r, c) * kv;
        }
        for &(r, c, kv) in &self.extra_k {
            k[at(r, c)] += half(r, c) * kv;
        }
        for &(r, c, v) in &self.added {
            k[at(r, c)] += half(r, c) * v;
            k[at(c, r)] += half(c, r) * v;
        }
    }

    /// The entry of M at row `s`, column `t` of the stored lower triangle (pivot steps),
    /// `None` where M has none.
    fn m_entry(&self, s: usize, t: usize) -> Option<f64> {
        let (r, c) = (self.perm[s] as usize, self.perm[t] as usize);
        if r >= self.nc || c >= self.nc {
            return None;
        }
        // (the entry of the lower triangle of M)
        let (r, c) = (r.max(c), r.min(c));
        let m = ColRows::plain(&self.m_ptr, &self.m_idx);
        m.find(c, r).ok().map(|q| self.m_val[q])
    }

    /// The entries of the shifted matrix A(s) = [K − sM, Gᵀ; G, 0] by their position q in the
    /// stored lower triangle. The column of q is followed from one call to the next (a
    /// factorisation asks in ascending order), and searched when q jumps.
    pub(super) fn shifted_entries(&self, s: f64) -> impl Fn(usize) -> f64 + '_ {
        let column = std::cell::Cell::new(0usize);
        let kv = self.k_values();
        debug_assert!(kv.len() == self.nnz(), "K was released");
        move |q| {
            let k = kv[q];
            if s == 0.0 {
                return k;
            }
            let cp = |t: usize| self.col_ptr[t] as usize;
            let mut t = column.get();
            if q < cp(t) || q >= cp(t + 1) {
                // (every column holds its diagonal: the next column when q is just past)
                t = if q >= cp(t + 1) && t + 2 < self.col_ptr.len() && q < cp(t + 2) {
                    t + 1
                } else {
                    self.col_ptr.partition_point(|&x| x as usize <= q) - 1
                };
                column.set(t);
            }
            match self.m_entry(self.rows().of(t)[q - cp(t)] as usize, t) {
                None => k,
                Some(m) => k - s * m,
            }
        }
    }

    /// The K values (read access; empty while released).
    pub(super) fn k_values(&self) -> std::sync::RwLockReadGuard<'_, Vec<f64>> {
        self.k.read().expect("K is never left half written")
    }

    /// Releases the K values (a factorisation holds what the solves need); a factorisation
    /// makes them again first ([`Problem::restore_k`]).
    pub(super) fn release_k(&self) {
        *self.k.write().expect("K is never left half written") = Vec::new();
    }

    /// The K values made again when they were released: the element part from the model at
    /// `step` (the stage this problem was made of), the tail, the node masses' softening and
    /// the added rows, summed into the stored structure in the order of [`Problem::with_rows`]
    /// (the same values, bit for bit).
    pub(super) fn restore_k(&self, model: &Model, step: &StepResult) {
        if self.k_values().len() == self.nnz() {
            return;
        }
        let inv = inverse(&self.perm);
        let at = self.position_in(&inv);
        let mut k = vec![0.0; self.nnz()];
        element_blocks(&self.lin, model, step, false, |els, kb, _| {
            let mut i = 0;
            self.lin.for_each_entry_in(els, |r, c| {
                k[at(r, c)] += half(r, c) * kb[i];
                i += 1;
            });
        });
        self.add_k_rest(&inv, &mut k);
        *self.k.write().expect("K is never left half written") = k;
    }

    pub(super) fn m_times(&self, v: &[f64], out: &mut [f64]) {
        csc_lower_sym_times(&self.m_ptr, &self.m_idx, &self.m_val, v, out);
    }

    /// out −= s M v, M v formed in `mv` (the caller's, kept from one product to the next).
    pub(super) fn sub_m_times(&self, s: f64, v: &[f64], out: &mut [f64], mv: &mut Vec<f64>) {
        mv.resize(out.len(), 0.0);
        self.m_times(v, mv);
        out.iter_mut().zip(mv.iter()).for_each(|(y, m)| *y -= s * m);
    }

    /// The entries (row, column, value) of the saddle-point matrix in the constraint rows or
    /// columns: G, Gᵀ (with the added rows) and the constraint diagonal.
    pub(super) fn constraint_entries(&self) -> Vec<(usize, usize, f64)> {
        let nc = self.nc;
        let k = self.k_values();
        let mut out = Vec::new();
        for t in 0..self.n {
            let c = self.perm[t] as usize;
            for (q, &s) in (self.col_ptr[t] as usize..).zip(self.rows().of(t)) {
                let (r, v) = (self.perm[s as usize] as usize, k[q]);
                if (r >= nc || c >= nc) && v != 0.0 {
                    out.push((r, c, v));
                    if r != c {
                        out.push((c, r, v));
                    }
                }
            }
        }
        out
    }

    /// The structure of both triangles in the original numbering of the unknowns (CSC, rows
    /// sorted), for the symbolic factorisation and the LU fall-back: made when they need it and
    /// released after.
    pub(super) fn full_pattern(&self) -> (Vec<usize>, Vec<u32>) {
        full_of_triangle(self.n, self.rows(), |i| self.perm[i] as usize)
    }

    /// For every entry of the structure of both triangles ([`Problem::full_pattern`]), the
    /// position of its value in the stored lower triangle.
    pub(super) fn full_positions(&self, ptr: &[usize], rows: &[u32]) -> Vec<u32> {
        let inv = inverse(&self.perm);
        let position = self.position_in(&inv);
        let mut at = Vec::with_capacity(rows.len());
        for c in 0..self.n {
            for &r in &rows[ptr[c]..ptr[c + 1]] {
                at.push(position(r as usize, c) as u32);
            }
        }
        at
    }

    /// Diagonal entries of K and M of the coordinates.
    pub(super) fn diagonals(&self) -> (Vec<f64>, Vec<f64>) {
        let mut kd = vec![0.0; self.nc];
        let mut md = vec![0.0; self.nc];
        let k = self.k_values();
        for (t, &c) in self.perm.iter().enumerate() {
            let c = c as usize;
            if c < self.nc {
                // (each column of the lower triangle starts with its diagonal entry)
                let p = self.col_ptr[t] as usize;
                debug_assert_eq!(self.rows().of(t)[0] as usize, t);
                kd[c] = k[p];
                md[c] = self.m_entry(t, t).unwrap_or(0.0);
            }
        }
        (kd, md)
    }

    /// Fill-reducing order for L D Lᵀ with diagonal pivots: AMD on the graph of the nodes (the
    /// unknowns of a node share their couplings, so this is AMD on the coordinate block with
    /// its supervariables found in advance, and far cheaper), each node's coordinates together;
    /// each constraint row placed right after the last coordinate it couples, so that its pivot
    /// (minus a Schur complement of the coordinates) exists.
    /// `full`: the structure of both triangles; `group`: the point of every coordinate (its
    /// node, or the host of a node placed `at` another, a SPACAR rotational node), so that a
    /// point's translations and rotations stay together.
    fn saddle_order(
        n: usize,
        nc: usize,
        group: &[usize],
        full: (&[usize], &[u32]),
    ) -> Result<Vec<usize>, String> {
        let (col_ptr, row_idx) = full;
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
                for p in col_ptr[c]..col_ptr[c + 1] {
                    let r = row_idx[p] as usize;
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
            let last = (col_ptr[c]..col_ptr[c + 1])
                .map(|p| row_idx[p] as usize)
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
