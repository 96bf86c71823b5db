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
    /// The Newton matrix at the state: `vals` K = K_m + K_g − Ω² M_P on the element pattern
    /// and the tail, `geo` its geometric part (with the softening).
    pub(crate) lin: ReducedLinear,
    /// M on the element entries of `lin` (same order as `lin.vals`).
    pub(crate) m_el: Vec<f64>,
    /// The node masses as (row, column, K value, M value) in the reduced unknowns: point masses
    /// (with their softening) and inertia tensors.
    pub(crate) nodes: Vec<(usize, usize, f64, f64)>,
}

impl SparseTangent {
    /// The sparse K and M of `model` at `step`.
    pub(crate) fn new(model: &Model, step: &StepResult) -> Self {
        let mut lin = ReducedLinear::new(model, step);
        let x = &step.x;
        // element mass blocks, in the order of the element entries
        let mut m_el = vec![0.0; lin.vals.len()];
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
                element_mass(entry, x, None, true, |me| {
                    lin.element_block(model, el, x, &|a, c| me[a * n + c], out)
                });
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
        if w.is_some() && lin.geo.is_empty() {
            lin.geo = vec![0.0; lin.vals.len()];
        }
        if let Some(w) = &w {
            for (el, r) in &ranges {
                let entry = &model.elements[*el];
                let n = entry.xmap.len();
                element_mass(entry, x, Some(w), false, |ms| {
                    let mut soft = vec![0.0; r.end - r.start];
                    lin.element_block(model, *el, x, &|a, c| -ms[a * n + c], &mut soft);
                    for (i, v) in r.clone().zip(soft) {
                        lin.vals[i] += v;
                        lin.geo[i] += v;
                    }
                });
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
        Self { lin, m_el, nodes }
    }
}
