//! Assembly: gather element coordinates x_k from x, evaluate the elements, scatter e_k and
//! D_k = ∂e_k/∂x_k into the global e and D (paper eq. (3): e = 𝒟(x)).

pub mod loads;
pub mod mass;

use crate::elements::ElementKind;
use crate::model::{ElementEntry, Model};
use faer::Mat;

/// Models with fewer elements are evaluated element by element on the calling thread: the
/// hand-over to worker threads costs more than it saves.
pub(crate) const PAR_ELEMENTS: usize = 256;

/// Split `v` into consecutive pieces at the given offsets (`starts` ascending, first 0).
pub(crate) fn split_at_starts<'a, T>(mut v: &'a mut [T], starts: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    for w in starts.windows(2) {
        let (head, rest) = v.split_at_mut(w[1] - w[0]);
        out.push(head);
        v = rest;
    }
    out
}

/// Every element's local values in one buffer ([`per_element`]): element k's in
/// `buf[starts[k]..starts[k + 1]]`, `has[k]` whether it has any.
pub(crate) struct ElementValues {
    buf: Vec<f64>,
    starts: Vec<usize>,
    has: Vec<bool>,
}

impl ElementValues {
    /// The elements that have values, with them, in element order (`elements` the slice that
    /// [`per_element`] was given).
    pub(crate) fn each<'a>(
        &'a self,
        elements: &'a [ElementEntry],
    ) -> impl Iterator<Item = (&'a ElementEntry, &'a [f64])> + 'a {
        elements
            .iter()
            .zip(self.starts.windows(2))
            .zip(&self.has)
            .filter(|(_, h)| **h)
            .map(|((entry, w), _)| (entry, &self.buf[w[0]..w[1]]))
    }
}

/// `f(el, entry, piece)` for every element `el` with its own `piece` (its slices of output
/// buffers, `pieces` in element order), and what it returns, in element order. In parallel for
/// models of [`PAR_ELEMENTS`] elements and more; each element writes only its own piece, so the
/// numbers are the same on any number of threads.
pub(crate) fn map_elements<P, R, F>(elements: &[ElementEntry], pieces: Vec<P>, f: F) -> Vec<R>
where
    P: Send,
    R: Send,
    F: Fn(usize, &ElementEntry, P) -> R + Sync,
{
    use rayon::prelude::*;
    debug_assert_eq!(pieces.len(), elements.len());
    let one = |(el, (entry, piece)): (usize, (&ElementEntry, P))| f(el, entry, piece);
    if elements.len() < PAR_ELEMENTS {
        elements.iter().zip(pieces).enumerate().map(one).collect()
    } else {
        let mut out = Vec::with_capacity(elements.len());
        elements
            .par_iter()
            .zip(pieces)
            .enumerate()
            .with_min_len(64)
            .map(one)
            .collect_into_vec(&mut out);
        out
    }
}

/// Every element's local values: `f(entry, out)` fills the `width(entry)` values of each
/// element and says whether it has any ([`map_elements`] on one buffer).
pub(crate) fn per_element<W, F>(elements: &[ElementEntry], width: W, f: F) -> ElementValues
where
    W: Fn(&ElementEntry) -> usize,
    F: Fn(&ElementEntry, &mut [f64]) -> bool + Sync,
{
    let mut starts = Vec::with_capacity(elements.len() + 1);
    let mut n = 0;
    starts.push(0);
    for entry in elements {
        n += width(entry);
        starts.push(n);
    }
    let mut buf = vec![0.0; n];
    let pieces = split_at_starts(&mut buf, &starts);
    let has = map_elements(elements, pieces, |_, entry, out| f(entry, out));
    ElementValues { buf, starts, has }
}

/// The largest number of local coordinates that [`gather_local`] holds on the stack (a beam:
/// 14).
pub(crate) const SMALL: usize = 14;

/// `src` at the element's coordinates, in `stack` when they fit (a beam), else in `heap`:
/// [`gather`] without an allocation per element.
pub(crate) fn gather_local<'b>(
    entry: &ElementEntry,
    src: &[f64],
    stack: &'b mut [f64; SMALL],
    heap: &'b mut Vec<f64>,
) -> &'b mut [f64] {
    let n = entry.xmap.len();
    let buf = if n <= SMALL {
        &mut stack[..n]
    } else {
        heap.resize(n, 0.0);
        &mut heap[..]
    };
    buf.iter_mut()
        .zip(entry.x_indices())
        .for_each(|(b, i)| *b = src[i]);
    buf
}

/// Element coordinates x_k gathered from the global x.
pub fn gather(entry: &ElementEntry, x: &[f64]) -> Vec<f64> {
    entry.x_indices().map(|i| x[i]).collect()
}

/// Deformations and first derivatives of the whole model at x.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// e = 𝒟(x)  (ne).
    pub e: Vec<f64>,
    /// D = ∂e/∂x  (ne × nx), SPACAR `bigd`.
    pub D: Mat<f64>,
}

/// Evaluate e and D at x (dense; the kinematic analysis needs Dcc dense for its SVD).
pub fn evaluate(model: &Model, x: &[f64]) -> Evaluation {
    assert_eq!(x.len(), model.nx, "x has the wrong length");
    let mut e = vec![0.0; model.ne];
    let mut D = Mat::zeros(model.ne, model.nx);
    for entry in &model.elements {
        // gather element coordinates x_k from x
        let xk = gather(entry, x);
        // deformations and first-order derivatives
        let ek = entry.element.deformations(&xk);
        let dk = entry.element.jacobian(&xk);
        // scatter into global e and D
        e[entry.ie..entry.ie + ek.len()].copy_from_slice(&ek);
        for (r, _) in ek.iter().enumerate() {
            for (c, col) in entry.x_indices().enumerate() {
                D[(entry.ie + r, col)] += dk[(r, c)];
            }
        }
    }
    Evaluation { e, D }
}
