//! The sparse form of the stage: the statics Newton matrix [K, Gᵀ; G, 0] at the state
//! ([`ReducedLinear`]) with the centrifugal softening added to K, and the mass M in the same
//! reduced unknowns (Tᵀ M_e T element by element, point masses and inertia tensors). The
//! element and node masses come from `assembly::mass` (`element_mass`, `for_each_node_mass`),
//! the same evaluation as the dense M and softening in x.

use crate::assembly::mass::{element_mass, for_each_node_mass, NodeMass};
use crate::model::Model;
use crate::statics::{ReducedLinear, StepResult};
use rayon::prelude::*;

/// K and M of the stage in the reduced unknowns of the Newton system.
pub(crate) struct SparseTangent {
    /// The Newton matrix at the state: K = K_m + K_g − Ω² M_P on the element pattern (its
    /// values made a block of elements at a time, [`SparseTangent::element_blocks`]) and the
    /// tail, `geo` its geometric part (with the softening).
    pub(crate) lin: ReducedLinear,
    /// The node masses as (row, column, K value, M value) in the reduced unknowns: point masses
    /// (with their softening) and inertia tensors.
    pub(crate) nodes: Vec<(usize, usize, f64, f64)>,
}

/// Elements per block of [`SparseTangent::element_blocks`]: 144 entries each for a beam, two
/// values per entry, 2.4 MB a block.
const BLOCK: usize = 1024;

impl SparseTangent {
    /// The sparse K and M of `model` at `step`.
    pub(crate) fn new(model: &Model, step: &StepResult) -> Self {
        let mut lin = ReducedLinear::new(model, step);
        let x = &step.x;
        // centrifugal softening of a steady rotation (model::Spin): −Ω² M_P on the elements, on
        // the element pattern, counted with the geometric part (it enters the Rayleigh quotients)
        let w = model.loads.spin.map(|sp| sp.projector());
        if let Some(w) = &w {
            let n_all = lin.n_entries();
            if lin.geo.is_empty() {
                lin.geo = vec![0.0; n_all];
            }
            for el in 0..model.elements.len() {
                let r = lin.element_entries(el);
                let mut soft = vec![0.0; r.end - r.start];
                softening(&lin, model, el, x, w, &mut soft);
                for (i, v) in r.zip(soft) {
                    lin.geo[i] += v;
                }
            }
        }
        // node masses: point masses (with their softening) and inertia tensors
        let mut nodes: Vec<(usize, usize, f64, f64)> = Vec::new();
        for_each_node_mass(model, x, true, |nm| match nm {
            NodeMass::Point { ix, mass } => {
                let mut mv = [[0.0; 3]; 3];
                NodeMass::point_entries(mass, None, |a, c, v| mv[a][c] = v);
                let mut kv = [[0.0; 3]; 3];
                if let Some(w) = &w {
                    NodeMass::point_entries(mass, Some(w), |a, c, v| kv[a][c] = -v);
                }
                for a in 0..3 {
                    let Some(i) = lin.coord_index(ix + a) else {
                        continue;
                    };
                    for c in 0..3 {
                        let Some(j) = lin.coord_index(ix + c) else {
                            continue;
                        };
                        if kv[a][c] != 0.0 || mv[a][c] != 0.0 {
                            nodes.push((i, j, kv[a][c], mv[a][c]));
                        }
                    }
                }
            }
            NodeMass::Tensor { r, block } => nodes.extend(
                lin.lambda_block(x, r, &block)
                    .into_iter()
                    .map(|(i, j, v)| (i, j, 0.0, v)),
            ),
        });
        Self { lin, nodes }
    }

    /// K (with the softening) and M of the element entries, [`BLOCK`] elements at a time (in
    /// parallel within a block): `f(els, k, m)` with the values of the entries of elements
    /// `els` in the order of [`ReducedLinear::for_each_entry_in`]. The element part of a large
    /// model's matrices is never held as one array of its entries (144 of each per beam, 2.3 KB).
    pub(crate) fn element_blocks(
        &self,
        model: &Model,
        step: &StepResult,
        f: impl FnMut(std::ops::Range<usize>, &[f64], &[f64]),
    ) {
        element_blocks(&self.lin, model, step, true, f);
    }
}

/// [`SparseTangent::element_blocks`] of the stage `lin` (made at `step`), M only `with_mass`
/// (else `m` is empty): K alone made again from the model, when a factorisation needs the
/// values it released (`dynamics::sparse`).
pub(crate) fn element_blocks(
    lin: &ReducedLinear,
    model: &Model,
    step: &StepResult,
    with_mass: bool,
    mut f: impl FnMut(std::ops::Range<usize>, &[f64], &[f64]),
) {
    let x = &step.x;
    let w = model.loads.spin.map(|sp| sp.projector());
    let n_el = model.elements.len();
    let (mut k, mut m) = (Vec::new(), Vec::new());
    for a in (0..n_el).step_by(BLOCK) {
        let els = a..(a + BLOCK).min(n_el);
        let lo = lin.element_entries(els.start).start;
        let hi = lin.element_entries(els.end - 1).end;
        k.clear();
        k.resize(hi - lo, 0.0);
        m.clear();
        if with_mass {
            m.resize(hi - lo, 0.0);
        }
        lin.element_values(model, step, els.clone(), &mut k);
        // element mass blocks (and the softening), each element into its own piece
        let mut pieces: Vec<(usize, &mut [f64], &mut [f64])> = Vec::with_capacity(els.len());
        let (mut rest_k, mut rest_m): (&mut [f64], &mut [f64]) = (&mut k, &mut m);
        for el in els.clone() {
            let len = lin.element_entries(el).len();
            let (pk, tk) = rest_k.split_at_mut(len);
            let (pm, tm) = rest_m.split_at_mut(if with_mass { len } else { 0 });
            pieces.push((el, pk, pm));
            (rest_k, rest_m) = (tk, tm);
        }
        let fill = |(el, pk, pm): (usize, &mut [f64], &mut [f64])| {
            let entry = &model.elements[el];
            let n = entry.xmap.len();
            if with_mass {
                element_mass(entry, x, None, true, |me| {
                    lin.element_block(model, el, x, &|a, c| me[a * n + c], pm)
                });
            }
            if let Some(w) = &w {
                let mut soft = vec![0.0; pk.len()];
                softening(lin, model, el, x, w, &mut soft);
                pk.iter_mut().zip(soft).for_each(|(k, s)| *k += s);
            }
        };
        if pieces.len() < 256 {
            pieces.into_iter().for_each(fill);
        } else {
            pieces.into_par_iter().with_min_len(64).for_each(fill);
        }
        f(els, &k, &m);
    }
}

/// −Ω² M_P of element `el` (the centrifugal softening of a steady rotation with projector `w`)
/// on its entries, into `out`.
fn softening(
    lin: &ReducedLinear,
    model: &Model,
    el: usize,
    x: &[f64],
    w: &[[f64; 3]; 3],
    out: &mut [f64],
) {
    let entry = &model.elements[el];
    let n = entry.xmap.len();
    element_mass(entry, x, Some(w), false, |ms| {
        lin.element_block(model, el, x, &|a, c| -ms[a * n + c], out)
    });
}
