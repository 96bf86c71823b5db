//! The description of the modes: the sign convention of the shapes, nodal translations and
//! rotations, and the split of strain energy over the element deformations and of kinetic
//! energy over the nodes (element by element, no global matrices).

use super::{Mode, ModeClass};
use crate::elements::ElementKind;
use crate::math::sparse_lu::sort_small_by;
use crate::model::Model;
use crate::statics::StepResult;

/// Relative tolerance of [`fix_sign`]: components whose magnitude is within this fraction of
/// the largest count as equally large.
pub const SIGN_TIE_TOL: f64 = 1e-6;

/// The sign convention of mode shapes, independent of the eigen solver: the component of the
/// shape in x with the largest magnitude is positive; among components within
/// [`SIGN_TIE_TOL`] of the largest, the one with the lowest index decides (docs/dynamics.md,
/// "JSON output").
pub fn fix_sign(shape: &mut [f64]) {
    let big = shape.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if big == 0.0 || !big.is_finite() {
        return;
    }
    let decisive = shape
        .iter()
        .copied()
        .find(|v| v.abs() >= (1.0 - SIGN_TIE_TOL) * big)
        .unwrap_or(big);
    if decisive < 0.0 {
        shape.iter_mut().for_each(|v| *v = -*v);
    }
}

/// The modes with their energy split (element by element, no global matrices): strain
/// energy per element deformation, kinetic energy per node.
pub(super) fn describe_all(
    model: &Model,
    step: &StepResult,
    eigenvalues: &[f64],
    shapes: Vec<Vec<f64>>,
    kinetic: Option<Vec<Vec<(f64, f64)>>>,
) -> Vec<Mode> {
    use rayon::prelude::*;
    let nm = shapes.len();
    // strain energy per element deformation: ½ (D δx)ᵢ (S D δx)ᵢ, D evaluated once per element;
    // per element one list, mode k's energies at k ne … (k + 1) ne
    let element_energies = |entry: &crate::model::ElementEntry| -> Vec<f64> {
        let s = entry.element.stiffness();
        let mut e = crate::statics::deformation_energies(entry, s.as_ref(), &step.x, &shapes);
        e.iter_mut().for_each(|v| *v *= 0.5);
        e
    };
    let small = model.elements.len() < 256;
    let per_element: Vec<Vec<f64>> = if small {
        model.elements.iter().map(element_energies).collect()
    } else {
        model
            .elements
            .par_iter()
            .with_min_len(64)
            .map(element_energies)
            .collect()
    };
    let fractions = super::classes::fractions(model, &step.x, eigenvalues, &shapes, &per_element);
    // kinetic energy per node: the quadratic form δxᵀ M δx split by rows (a node `at` a host
    // has no translation rows of its own)
    let kinetic = kinetic.unwrap_or_else(|| {
        let refs: Vec<&[f64]> = shapes.iter().map(|v| v.as_slice()).collect();
        let m_shapes = crate::assembly::mass::mass_times(model, &step.x, &refs);
        shapes
            .iter()
            .zip(&m_shapes)
            .map(|(shape, m_shape)| {
                let part =
                    |r: std::ops::Range<usize>| -> f64 { r.map(|i| shape[i] * m_shape[i]).sum() };
                model
                    .nodes
                    .iter()
                    .map(|n| {
                        let tr = if n.host.is_none() {
                            part(n.ix_pos..n.ix_pos + 3)
                        } else {
                            0.0
                        };
                        (tr, n.ix_rot.map_or(0.0, |r| part(r..r + 4)))
                    })
                    .collect()
            })
            .collect()
    });
    // each mode with its kinetic energies by node, released as soon as it is described
    type Job = (usize, (Vec<f64>, Vec<(f64, f64)>));
    let one = |(k, (shape, kinetic)): Job| {
        let strain = per_element.iter().enumerate().flat_map(|(el, u)| {
            let ne = u.len() / nm;
            u[k * ne..(k + 1) * ne]
                .iter()
                .enumerate()
                .map(move |(a, &v)| (el, a, v))
        });
        let mut mode = describe(model, step, eigenvalues[k], shape, &kinetic, strain);
        mode.fractions = fractions[k];
        mode.class = ModeClass::of(&mode.fractions, false);
        mode
    };
    let jobs = shapes.into_iter().zip(kinetic).enumerate();
    if small || nm < 2 {
        jobs.map(one).collect()
    } else {
        jobs.collect::<Vec<_>>().into_par_iter().map(one).collect()
    }
}

/// Lists up to this long are sorted by insertion in [`describe`] (the same stable order).
const SHORT_SORT: usize = 64;

fn describe(
    model: &Model,
    step: &StepResult,
    eigenvalue: f64,
    shape: Vec<f64>,
    kinetic: &[(f64, f64)],
    strain: impl Iterator<Item = (usize, usize, f64)> + Clone,
) -> Mode {
    let frequency = if eigenvalue >= 0.0 {
        eigenvalue.sqrt() / (2.0 * std::f64::consts::PI)
    } else {
        f64::NAN
    };
    // nodal translations and rotation vectors (ω = 2 Λ̄ δλ)
    let nodal: Vec<([f64; 3], [f64; 3])> = model
        .nodes
        .iter()
        .map(|n| {
            let p = n.ix_pos;
            let u = [shape[p], shape[p + 1], shape[p + 2]];
            let w = n.ix_rot.map_or([0.0; 3], |r| {
                let lb = crate::math::lambda_bar(&[
                    step.x[r],
                    step.x[r + 1],
                    step.x[r + 2],
                    step.x[r + 3],
                ]);
                std::array::from_fn(|k| 2.0 * (0..4).map(|c| lb[k][c] * shape[r + c]).sum::<f64>())
            });
            (u, w)
        })
        .collect();
    let total_u: f64 = strain.clone().map(|s| s.2).sum();
    let total_t: f64 = kinetic.iter().map(|(tr, rt)| tr + rt).sum();
    let kinetic = kinetic.iter().enumerate().map(|(i, &(tr, rt))| (i, tr, rt));
    let norm_u = if total_u.abs() > 0.0 { total_u } else { 1.0 };
    let norm_t = if total_t.abs() > 0.0 { total_t } else { 1.0 };
    // (the entries of every element's deformations are read twice, not listed)
    let mut strain: Vec<(usize, usize, f64)> = strain
        .map(|(e, m, u)| (e, m, u / norm_u))
        .filter(|s| s.2.abs() >= 1e-4)
        .collect();
    // (held with the mode: no room beyond its entries)
    strain.shrink_to_fit();
    // stable, largest first (insertion for the short lists of small models)
    let larger = |a: &(usize, usize, f64), b: &(usize, usize, f64)| {
        b.2.abs().total_cmp(&a.2.abs()) == std::cmp::Ordering::Less
    };
    if strain.len() <= SHORT_SORT {
        sort_small_by(&mut strain, larger);
    } else {
        strain.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    }
    let mut kinetic: Vec<(usize, f64, f64)> = kinetic
        .map(|(n, a, b)| (n, a / norm_t, b / norm_t))
        .filter(|k| k.1.abs() + k.2.abs() >= 1e-4)
        .collect();
    let larger = |a: &(usize, f64, f64), b: &(usize, f64, f64)| {
        (b.1 + b.2).total_cmp(&(a.1 + a.2)) == std::cmp::Ordering::Less
    };
    if kinetic.len() <= SHORT_SORT {
        sort_small_by(&mut kinetic, larger);
    } else {
        kinetic.sort_by(|a, b| (b.1 + b.2).total_cmp(&(a.1 + a.2)));
    }
    Mode {
        eigenvalue,
        frequency,
        shape,
        nodal,
        strain,
        kinetic,
        rigid_body: false,
        class: ModeClass::Internal,
        fractions: Default::default(),
    }
}
