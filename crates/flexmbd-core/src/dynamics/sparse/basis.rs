//! Dense kernels of the Lanczos basis: dot products, Gram–Schmidt updates and combinations of
//! basis columns (parallel on long vectors), and the eigen solver of the small projected
//! matrix.

use crate::linalg::{sym_eigen_seq, EigenError};
use crate::math::small_eigen::{sym_eigen_small, sym_eigen_small_largest, SMALL_EIGEN_MAX};
use faer::{Mat, MatRef};
use rayon::prelude::*;

/// Vectors at least this long are processed in parallel (rayon); shorter ones sequentially,
/// where the thread hand-over would cost more than it saves.
pub(super) const PAR_MIN: usize = 32_768;

/// Rows per parallel chunk of the basis operations.
pub(super) const ROW_CHUNK: usize = 8192;

/// Column `i` of a column-major matrix as a slice.
pub(super) fn col_slice<'a>(v: MatRef<'a, f64>, i: usize) -> &'a [f64] {
    v.col(i)
        .try_as_col_major()
        .expect("basis matrices are column-major")
        .as_slice()
}

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
pub(super) fn basis_dots(v: MatRef<'_, f64>, y: &[f64], c: &mut [f64]) {
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
pub(super) fn dots_rows(v: MatRef<'_, f64>, y: &[f64], r: std::ops::Range<usize>, c: &mut [f64]) {
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
pub(super) fn basis_subtract(v: MatRef<'_, f64>, c: &[f64], w: &mut [f64]) {
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

/// V[:, ..] Y (columns of `y`) into a new matrix with `y.ncols()` columns, each column a sum
/// of the columns of V. Long vectors in blocks of [`ROW_CHUNK`] rows in parallel: a block of V
/// stays in cache for all the columns of the result, and no workspace is needed (a general
/// matrix product packs its operands into per-thread buffers, 64 MiB at 10⁴ beams). Every
/// entry is summed in the same order whatever the number of threads.
pub(super) fn basis_combine(v: MatRef<'_, f64>, y: MatRef<'_, f64>) -> Mat<f64> {
    let mut out = Mat::<f64>::zeros(v.nrows(), y.ncols());
    let block = |r0: usize, mut o: faer::MatMut<'_, f64>| {
        let rows = o.nrows();
        for c in 0..y.ncols() {
            let oc = o
                .as_mut()
                .col_mut(c)
                .try_as_col_major_mut()
                .expect("a column of a column-major matrix")
                .as_slice_mut();
            for j in 0..y.nrows() {
                let f = y[(j, c)];
                if f != 0.0 {
                    let vj = &col_slice(v, j)[r0..r0 + rows];
                    for (x, a) in oc.iter_mut().zip(vj) {
                        *x += f * a;
                    }
                }
            }
        }
    };
    if v.nrows() < PAR_MIN {
        block(0, out.as_mut());
    } else {
        out.as_mut()
            .par_row_chunks_mut(ROW_CHUNK)
            .enumerate()
            .for_each(|(k, o)| block(k * ROW_CHUNK, o));
    }
    out
}

/// V[:, ..m] Y into the first `y.ncols()` columns of `v` (m = `v.ncols()` = `y.nrows()`), in
/// place: block by block of [`ROW_CHUNK`] rows (in parallel on long vectors), each block's
/// result formed in a small buffer before it overwrites the block. The same sums in the same
/// order as [`basis_combine`], without a second basis-sized matrix (the thick restart of the
/// Lanczos basis).
pub(super) fn basis_combine_in_place(v: faer::MatMut<'_, f64>, y: MatRef<'_, f64>) {
    let (m, k) = (y.nrows(), y.ncols());
    debug_assert_eq!(v.ncols(), m);
    let block = |mut o: faer::MatMut<'_, f64>| {
        let rows = o.nrows();
        let mut tmp = vec![0.0; rows * k];
        for c in 0..k {
            let t = &mut tmp[c * rows..(c + 1) * rows];
            for j in 0..m {
                let f = y[(j, c)];
                if f != 0.0 {
                    let vj = o.as_ref().col(j);
                    for (r, x) in t.iter_mut().enumerate() {
                        *x += f * vj[r];
                    }
                }
            }
        }
        for c in 0..k {
            let t = &tmp[c * rows..(c + 1) * rows];
            let mut oc = o.as_mut().col_mut(c);
            for (r, x) in t.iter().enumerate() {
                oc[r] = *x;
            }
        }
    };
    if v.nrows() < PAR_MIN {
        block(v);
    } else {
        v.par_row_chunks_mut(ROW_CHUNK).for_each(block);
    }
}
