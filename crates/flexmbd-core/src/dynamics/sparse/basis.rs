//! Dense kernels of the Lanczos basis: dot products, Gram–Schmidt updates and combinations of
//! basis columns (parallel on long vectors), and the eigen solver of the small projected
//! matrix.

use crate::linalg::{sym_eigen_seq, EigenError};
use crate::math::small_eigen::{sym_eigen_small, sym_eigen_small_largest, SMALL_EIGEN_MAX};
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// A set of long vectors (the Lanczos basis, Ritz vectors, mode shapes in the coordinates), each
/// its own allocation: columns no longer needed are released one by one (the Ritz vectors
/// replace the basis they are combined in, without a second block of that size beside it).
pub(super) type Cols = Vec<Vec<f64>>;

/// Vectors at least this long are processed in parallel (rayon); shorter ones sequentially,
/// where the thread hand-over would cost more than it saves.
pub(super) const PAR_MIN: usize = 32_768;

/// Rows per parallel chunk of the basis operations.
pub(super) const ROW_CHUNK: usize = 8192;

/// a · b with eight independent partial sums (the additions pipeline instead of waiting for
/// each other).
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
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
pub(super) fn basis_dots(v: &[Vec<f64>], y: &[f64], c: &mut [f64]) {
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
pub(super) fn dots_rows(v: &[Vec<f64>], y: &[f64], r: std::ops::Range<usize>, c: &mut [f64]) {
    let y = &y[r.clone()];
    let col = |i: usize| &v[i][r.clone()];
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
pub(super) fn basis_subtract(v: &[Vec<f64>], c: &[f64], w: &mut [f64]) {
    let update = |start: usize, chunk: &mut [f64]| {
        let len = chunk.len();
        let col = |i: usize| &v[i][start..start + len];
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
pub(super) fn projected_eigen(a: MatRef<'_, f64>) -> Result<(Vec<f64>, Mat<f64>), EigenError> {
    if a.nrows() <= SMALL_EIGEN_MAX {
        sym_eigen_small(a)
    } else {
        sym_eigen_seq(a)
    }
}

/// All eigenvalues of a projected symmetric matrix (lower triangle read), ascending, and the
/// eigenvectors of the `k` largest, largest first (as [`projected_eigen`]).
pub(super) fn projected_eigen_largest(
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

/// V[:, ..] Y (columns of `y`) as new vectors, each a sum of the columns of V. Long vectors in
/// blocks of [`ROW_CHUNK`] rows in parallel: a block of V stays in cache for all the columns of
/// the result, and no workspace is needed. Every entry is summed in the same order whatever the
/// number of threads.
pub(super) fn basis_combine(v: &[Vec<f64>], y: MatRef<'_, f64>) -> Cols {
    let n = v.first().map_or(0, Vec::len);
    let mut out: Cols = vec![vec![0.0; n]; y.ncols()];
    let block = |r0: usize, o: &mut [&mut [f64]]| {
        for (c, oc) in o.iter_mut().enumerate() {
            for j in 0..y.nrows() {
                let f = y[(j, c)];
                if f != 0.0 {
                    let vj = &v[j][r0..r0 + oc.len()];
                    for (x, a) in oc.iter_mut().zip(vj) {
                        *x += f * a;
                    }
                }
            }
        }
    };
    if n < PAR_MIN {
        let mut o: Vec<&mut [f64]> = out.iter_mut().map(|c| c.as_mut_slice()).collect();
        block(0, &mut o);
    } else {
        row_blocks(&mut out)
            .into_par_iter()
            .enumerate()
            .for_each(|(k, mut o)| block(k * ROW_CHUNK, &mut o));
    }
    out
}

/// The columns cut into blocks of [`ROW_CHUNK`] rows: for each block, its piece of every column.
fn row_blocks(cols: &mut [Vec<f64>]) -> Vec<Vec<&mut [f64]>> {
    let n = cols.first().map_or(0, Vec::len);
    let mut blocks: Vec<Vec<&mut [f64]>> = (0..n.div_ceil(ROW_CHUNK))
        .map(|_| Vec::with_capacity(cols.len()))
        .collect();
    for col in cols.iter_mut() {
        for (b, piece) in blocks.iter_mut().zip(col.chunks_mut(ROW_CHUNK)) {
            b.push(piece);
        }
    }
    blocks
}

/// V[:, ..m] Y into the first `y.ncols()` columns of `v` (m = `v.len()` = `y.nrows()`), in
/// place: block by block of [`ROW_CHUNK`] rows (in parallel on long vectors), each block's
/// result formed in a small buffer before it overwrites the block. The same sums in the same
/// order as [`basis_combine`], without a second basis-sized set (the thick restart of the
/// Lanczos basis, and its Ritz vectors at the end of a run).
pub(super) fn basis_combine_in_place(v: &mut [Vec<f64>], y: MatRef<'_, f64>) {
    let (m, k) = (y.nrows(), y.ncols());
    debug_assert_eq!(v.len(), m);
    // (`tmp`: the block's result, one buffer per task, not one per block)
    let block = |tmp: &mut Vec<f64>, o: &mut [&mut [f64]]| {
        let rows = o.first().map_or(0, |c| c.len());
        tmp.clear();
        tmp.resize(rows * k, 0.0);
        for c in 0..k {
            let t = &mut tmp[c * rows..(c + 1) * rows];
            for (j, vj) in o.iter().enumerate() {
                let f = y[(j, c)];
                if f != 0.0 {
                    for (x, a) in t.iter_mut().zip(vj.iter()) {
                        *x += f * a;
                    }
                }
            }
        }
        for (c, oc) in o.iter_mut().take(k).enumerate() {
            oc.copy_from_slice(&tmp[c * rows..(c + 1) * rows]);
        }
    };
    if v.first().map_or(0, Vec::len) < PAR_MIN {
        let mut o: Vec<&mut [f64]> = v.iter_mut().map(|c| c.as_mut_slice()).collect();
        block(&mut Vec::new(), &mut o);
    } else {
        row_blocks(v)
            .into_par_iter()
            .for_each_init(Vec::new, |tmp, mut o| block(tmp, &mut o));
    }
}
