//! Row lists of a CSC structure that columns share: the columns of a supernode (for a beam
//! model, the six unknowns of a node) have the same rows below them, each one entry fewer, so
//! one list serves them all.

use super::RowIndex;

/// The rows of each column of a CSC structure: column k has `ptr[k + 1] − ptr[k]` entries,
/// whose rows are `idx[ptr[k]..ptr[k + 1]]` ([`ColRows::plain`]) or, with lists shared
/// between columns ([`share_rows`]), as many from `idx[start[k]]` on ([`ColRows::shared`]).
/// The positions of the entries (of their values) stay `ptr[k]..ptr[k + 1]`.
/// The pointers are `usize`, or `u32` where the structure is large and kept (the sparse modal
/// problem's, 4 bytes per column less).
#[derive(Clone, Copy, Debug)]
pub struct ColRows<'a, P = usize> {
    ptr: &'a [P],
    idx: &'a [u32],
    start: &'a [u32],
}

impl<'a, P: RowIndex> ColRows<'a, P> {
    /// One list per column: column k's rows are `idx[ptr[k]..ptr[k + 1]]`.
    pub fn plain(ptr: &'a [P], idx: &'a [u32]) -> Self {
        Self {
            ptr,
            idx,
            start: &[],
        }
    }

    /// Shared lists ([`share_rows`]); an empty `start` is [`ColRows::plain`].
    pub fn shared(ptr: &'a [P], idx: &'a [u32], start: &'a [u32]) -> Self {
        Self { ptr, idx, start }
    }

    /// The rows of column k.
    #[inline]
    pub fn of(self, k: usize) -> &'a [u32] {
        let (lo, hi) = (self.first(k), self.first(k + 1));
        match self.start.get(k) {
            Some(&start) => &self.idx[start as usize..start as usize + (hi - lo)],
            None => &self.idx[lo..hi],
        }
    }

    /// The position of row `r` in column k (rows ascending), as `binary_search`: `Ok` with its
    /// position where the column has it, `Err` with the position it would take otherwise.
    pub fn find(self, k: usize, r: usize) -> Result<usize, usize> {
        let rows = self.of(k);
        let i = rows.partition_point(|&x| (x as usize) < r);
        let q = self.first(k) + i;
        if rows.get(i).is_some_and(|&x| x as usize == r) {
            Ok(q)
        } else {
            Err(q)
        }
    }

    /// The position of the first value of column k (of none past the last: k = columns).
    #[inline]
    pub fn first(self, k: usize) -> usize {
        self.ptr[k].ix()
    }

    /// Number of columns.
    pub fn ncols(self) -> usize {
        self.ptr.len().saturating_sub(1)
    }
}

/// The lists of a CSC structure (`ptr`, `idx`) stored once for each run of columns whose rows
/// are those of the column before without its first (fundamental supernodes; Liu, Ng &
/// Peyton, "On finding supernodes for sparse matrix computations", SIAM J. Matrix Anal. Appl.
/// 14, 1993): returns the shared lists and the start of each column's rows in them
/// ([`ColRows::shared`]), or `None` when they would not fit 32-bit offsets.
pub fn share_rows<P: RowIndex>(ptr: &[P], idx: &[u32]) -> Option<(Vec<u32>, Vec<u32>)> {
    let n = ptr.len().saturating_sub(1);
    let col = |k: usize| &idx[ptr[k].ix()..ptr[k + 1].ix()];
    let mut out: Vec<u32> = Vec::new();
    let mut start: Vec<u32> = Vec::with_capacity(n);
    for k in 0..n {
        let rows = col(k);
        let shared = k > 0 && {
            let prev = col(k - 1);
            !prev.is_empty() && prev[1..] == *rows
        };
        let at = if shared {
            start[k - 1] as usize + 1
        } else {
            out.extend_from_slice(rows);
            out.len() - rows.len()
        };
        start.push(u32::try_from(at).ok()?);
    }
    out.shrink_to_fit();
    Some((out, start))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every column reads its own rows back from the shared lists, and a run of columns whose
    /// lists are each the one before without its first is stored once (counted by hand).
    #[test]
    fn shared_lists_give_every_column_its_rows() {
        let cols: [&[u32]; 7] = [
            &[0, 1, 2, 5],
            &[1, 2, 5],
            &[2, 5],
            &[3, 4],
            &[4],
            &[5, 6],
            &[],
        ];
        let mut ptr = vec![0];
        let mut idx = Vec::new();
        for c in cols {
            idx.extend_from_slice(c);
            ptr.push(idx.len());
        }
        let (shared, start) = share_rows(&ptr, &idx).unwrap();
        // stored: [0, 1, 2, 5] for columns 0-2, [3, 4] for 3-4, [5, 6] for 5, none for 6
        assert_eq!(shared, [0, 1, 2, 5, 3, 4, 5, 6]);
        let rows = ColRows::shared(&ptr[..], &shared, &start);
        assert_eq!(rows.ncols(), cols.len());
        // rows found where the columns have them, and where they would go otherwise
        assert_eq!(rows.find(1, 2), Ok(5));
        assert_eq!(rows.find(1, 3), Err(6));
        assert_eq!(rows.find(4, 4), Ok(11));
        assert_eq!(rows.find(6, 0), Err(14));
        for (k, c) in cols.iter().enumerate() {
            assert_eq!(rows.of(k), *c, "column {k}");
            assert_eq!(ColRows::plain(&ptr[..], &idx).of(k), *c);
        }
    }
}
