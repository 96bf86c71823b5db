//! Solves with the shifted saddle-point matrix A(σ) = [K − σM, Gᵀ; G, 0] that keep their digits
//! where the factorisation alone cannot: GMRES on A(σ) with the factorisation as its (left)
//! preconditioner (`math::gmres`), the products with A(σ) taken as statics takes its residuals,
//! the material part through the element deformations (K_m δx = Σ Dᵀ S D δx), not as a product
//! with the assembled matrix.
//!
//! Why: on fine meshes the assembled entries are many orders of magnitude larger than the
//! elastic forces of a smooth displacement. A factorisation in double precision then solves a
//! matrix perturbed by round-off of the size of those entries: the relative error of a solve
//! grows with the condition of the stiffness (for a clamped strip of N beams much shorter than
//! their cross-section, about N³: a 600-element strip loses 1e-5 of its compliance, the 10⁵-beam
//! strip of issue 14 all digits of its first mode). A product through the deformations resolves
//! the small forces, so the residual it gives is right, and a Krylov iteration on it converges
//! even where the factorisation's error exceeds one.

use super::problem::Problem;
use super::shifted::Shifted;
use crate::math::gmres;
use crate::model::Model;
use crate::statics::MaterialOperator;

/// A refined solve stops when the correction the factorisation gives for its residual, Â⁻¹ (b −
/// A z), is this small against z (both in the coordinates).
pub(super) const REFINED_TOL: f64 = 1e-12;

/// The model a problem came from, with the element Jacobians at its state: what the products
/// through the element deformations need.
#[derive(Clone, Copy)]
pub(super) struct Exact<'a> {
    pub(super) model: &'a Model,
    pub(super) km: &'a MaterialOperator,
    /// The entries of the constraint rows and columns of the saddle-point matrix
    /// ([`Problem::constraint_entries`]).
    pub(super) g: &'a [(usize, usize, f64)],
}

/// A(σ) z: K z − σ M z for the coordinate rows, with the material part of K through the element
/// deformations and its geometric part (symmetric, as factored) and the softening of point
/// masses from their entries; G z for the constraint rows and Gᵀ μ in the coordinate rows (μ
/// the constraint part of z), from the saddle-point matrix, which holds them (with the added
/// rows of [`Problem::with_rows`]). `mv`: room for M z (used at σ ≠ 0), kept by the caller
/// from one product to the next.
pub(super) fn saddle_times(
    p: &Problem,
    ex: Exact<'_>,
    sigma: f64,
    z: &[f64],
    out: &mut [f64],
    mv: &mut Vec<f64>,
) {
    let nc = p.nc;
    let model = ex.model;
    ex.km
        .reduced_forces(model, p.lin.setup(), &z[..nc], &mut out[..nc]);
    out[nc..].iter_mut().for_each(|v| *v = 0.0);
    if !p.lin.geo.is_empty() {
        let mut e = 0;
        p.lin.for_each_entry(|r, c| {
            let g = p.lin.geo[e];
            if g != 0.0 && r < nc && c < nc {
                out[r] += 0.5 * g * z[c];
                out[c] += 0.5 * g * z[r];
            }
            e += 1;
        });
    }
    for &(r, c, kv) in &p.extra_k {
        out[r] += kv * z[c];
    }
    for &(r, c, v) in ex.g {
        out[r] += v * z[c];
    }
    if sigma != 0.0 {
        p.sub_m_times(sigma, &z[..nc], &mut out[..nc], mv);
    }
}

/// Solves A(σ) z = b, b given by its leading entries (the rest zero, as in the operator's
/// right-hand side [M v; 0]; z holds the whole of it on entry): the factorisation's solution
/// in `op`, refined by [`crate::math::gmres::refine_in`] with the products of [`saddle_times`]
/// to [`REFINED_TOL`] in the coordinates, its vectors in the operator's workspace
/// ([`Shifted::refine_ws`]). Returns the last correction against z.
pub(super) fn refined_solve(
    op: &mut Shifted<'_>,
    p: &Problem,
    ex: Exact<'_>,
    b: &[f64],
    z: &mut [f64],
) -> f64 {
    let sigma = op.sigma;
    let mut ws = std::mem::take(&mut op.refine_ws);
    // (M z of the products at σ ≠ 0, made once per solve)
    let mut mv = Vec::new();
    op.solve_factored(z);
    let correction = gmres::refine_in(
        &mut ws,
        b,
        z,
        p.nc,
        REFINED_TOL,
        |v| op.solve_factored(v),
        |v, out| saddle_times(p, ex, sigma, v, out, &mut mv),
    )
    .correction;
    op.refine_ws = ws;
    correction
}
