//! Static responses on the sparse path: δx = K⁻¹ f on the constrained space, from one sparse
//! factorisation of the statics Newton matrix [K, Gᵀ; G, 0] at the state (σ = 0 of the
//! shift-invert operator), with iterative refinement. Used by the state-space model of large
//! models for the static (residual-flexibility) feedthrough.
//!
//! The refinement residual is computed as statics computes its residuals: the material part
//! through the element deformations (K_m δx = Σ Dᵀ S D δx), not as a product with the assembled
//! matrix. On fine meshes the assembled entries are many orders of magnitude larger than the
//! elastic forces of a smooth displacement (a 600-element strip: 1e7 against 1), so the
//! assembled product cannot resolve the residual, and a plain solve loses up to 1e-5 of the
//! compliance; through the deformations the refinement recovers it to about 1e-10.

use super::problem::Problem;
use super::shifted::Shifted;
use crate::dynamics::ModalError;
use crate::model::Model;
use crate::statics::StepResult;

/// Largest number of refinement steps.
const MAX_REFINEMENTS: usize = 8;

/// K z for the coordinate rows and G z for the constraint rows of the saddle matrix, with the
/// material part through the element deformations; plus Gᵀ μ (the multipliers are the
/// constraint part of z).
fn saddle_times(p: &Problem, model: &Model, step: &StepResult, z: &[f64]) -> Vec<f64> {
    debug_assert!(
        !p.lin.vals.is_empty(),
        "a problem with its element values (Problem::with_rows)"
    );
    let nc = p.nc;
    let dx = p.lin.to_x(model, &step.x, &z[..nc]);
    let fm = p.lin.material_forces(model, &step.x, &dx);
    let mut out = p.lin.force_to_coords(&step.x, &fm);
    out.resize(p.n, 0.0);
    // geometric part (its symmetric part, as the factored matrix) and the constraint blocks
    let mut e = 0;
    p.lin.for_each_entry(|r, c| {
        let (v, g) = (p.lin.vals[e], p.lin.geo[e]);
        if r >= nc || c >= nc {
            out[r] += v * z[c];
        } else if g != 0.0 {
            out[r] += 0.5 * g * z[c];
            out[c] += 0.5 * g * z[r];
        }
        e += 1;
    });
    for &(r, c, kv) in &p.extra_k {
        out[r] += kv * z[c];
    }
    for &(r, c, v) in &p.added {
        out[r] += v * z[c];
        out[c] += v * z[r];
    }
    out
}

/// δx (length nx) of the linearised statics of the problem `p` (of `model` at `step`, the one
/// the modes came from) for each load vector in x (length nx):
/// K δx + Gᵀ μ = f, G δx = 0 (held coordinates, rigid and prescribed deformations stay).
/// `Err(SparseSingular)` when the stiffness is singular on the constrained space (a mechanism,
/// a buckled state) or the solve does not give finite values.
pub(super) fn static_responses(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    loads: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, ModalError> {
    let rhs: Vec<Vec<f64>> = loads
        .iter()
        .map(|f| {
            let mut b = p.lin.force_to_coords(&step.x, f);
            b.resize(p.n, 0.0);
            b
        })
        .collect();
    Ok(saddle_solutions(p, model, step, &rhs)?
        .iter()
        .map(|z| p.lin.to_x(model, &step.x, &z[..p.nc]))
        .collect())
}

/// The solutions z = [u; μ] of [K, Gᵀ; G, 0] z = b for right-hand sides of the full saddle
/// system (coordinate loads, then constraint values), from one factorisation with iterative
/// refinement. `Err(SparseSingular)` as [`static_responses`].
pub(super) fn saddle_solutions(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    rhs: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, ModalError> {
    let mut op = Shifted::new(p);
    if !op.factor(p, 0.0, true) {
        return Err(ModalError::SparseSingular);
    }
    let mut out = Vec::with_capacity(rhs.len());
    for b in rhs {
        let mut z = b.clone();
        op.solve(&mut z);
        let mut last = f64::INFINITY;
        for _ in 0..MAX_REFINEMENTS {
            let az = saddle_times(p, model, step, &z);
            let mut r: Vec<f64> = b.iter().zip(&az).map(|(b, a)| b - a).collect();
            op.solve(&mut r);
            let size = r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let zmax = z.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if !size.is_finite() || (size > 0.0 && size >= 0.5 * last) {
                break;
            }
            z.iter_mut().zip(&r).for_each(|(a, d)| *a += d);
            last = size;
            if size <= 1e-14 * zmax {
                break;
            }
        }
        if z.iter().any(|v| !v.is_finite()) {
            return Err(ModalError::SparseSingular);
        }
        out.push(z);
    }
    Ok(out)
}
