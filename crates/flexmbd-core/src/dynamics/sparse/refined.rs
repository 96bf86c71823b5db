//! Solves with the shifted saddle-point matrix A(σ) = [K − σM, Gᵀ; G, 0] that keep their digits
//! where the factorisation alone cannot: GMRES on A(σ) with the factorisation as its (right)
//! preconditioner, the products with A(σ) taken as statics takes its residuals, the material
//! part through the element deformations (K_m δx = Σ Dᵀ S D δx), not as a product with the
//! assembled matrix.
//!
//! Why: on fine meshes the assembled entries are many orders of magnitude larger than the
//! elastic forces of a smooth displacement. A factorisation in double precision then solves a
//! matrix perturbed by round-off of the size of those entries: the relative error of a solve
//! grows with the condition of the stiffness (for a clamped strip of N beams much shorter than
//! their cross-section, about N³: a 600-element strip loses 1e-5 of its compliance, the 10⁵-beam
//! strip of issue 14 all digits of its first mode). A product through the deformations resolves
//! the small forces, so the residual it gives is right, and a Krylov iteration on it converges
//! even where the factorisation's error exceeds one (which plain iterative refinement, a fixed
//! point iteration, does not: it diverges there).

use super::problem::Problem;
use super::shifted::Shifted;
use crate::model::Model;
use crate::statics::{MaterialOperator, StepResult};

/// A refined solve stops when the correction the factorisation gives for its residual, Â⁻¹ (b −
/// A z), is this small against z (both in the coordinates).
pub(super) const REFINED_TOL: f64 = 1e-12;

/// Krylov vectors per GMRES cycle, and cycles.
const CYCLE: usize = 30;
const MAX_CYCLES: usize = 4;

/// The model and state a problem came from, with the element Jacobians there: what the
/// products through the element deformations need.
#[derive(Clone, Copy)]
pub(super) struct Exact<'a> {
    pub(super) model: &'a Model,
    pub(super) step: &'a StepResult,
    pub(super) km: &'a MaterialOperator,
    /// The entries of the constraint rows and columns of the saddle-point matrix
    /// ([`Problem::constraint_entries`]).
    pub(super) g: &'a [(usize, usize, f64)],
}

/// A(σ) z: K z − σ M z for the coordinate rows, with the material part of K through the element
/// deformations and its geometric part (symmetric, as factored) and the softening of point
/// masses from their entries; G z for the constraint rows and Gᵀ μ in the coordinate rows (μ
/// the constraint part of z), from the saddle-point matrix, which holds them (with the added
/// rows of [`Problem::with_rows`]).
pub(super) fn saddle_times(p: &Problem, ex: Exact<'_>, sigma: f64, z: &[f64], out: &mut [f64]) {
    let nc = p.nc;
    let (model, x) = (ex.model, &ex.step.x);
    let dx = p.lin.to_x(model, x, &z[..nc]);
    let mut fm = vec![0.0; model.nx];
    ex.km.forces(model, p.lin.setup(), &dx, &mut fm);
    let f = p.lin.force_to_coords(x, &fm);
    out[..nc].copy_from_slice(&f[..nc]);
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
        let mut mz = vec![0.0; nc];
        p.m_times(&z[..nc], &mut mz);
        out[..nc]
            .iter_mut()
            .zip(&mz)
            .for_each(|(o, m)| *o -= sigma * m);
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// What a refined solve did.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct RefinedStats {
    /// GMRES iterations (products with A(σ)).
    pub(super) iterations: usize,
    /// The last correction Â⁻¹ (b − A z) against z, in the coordinates.
    pub(super) correction: f64,
}

/// Solves A(σ) z = b in place (b in, z out) by GMRES on Â⁻¹ A(σ) z = Â⁻¹ b (left-preconditioned
/// by the factorisation Â in `op`: its residual is the correction the factorisation gives, about
/// the error of z, where the plain residual b − A z is dominated by the round-off of z times the
/// large entries), from the factorisation's solution. Stops at [`REFINED_TOL`], or when a cycle
/// no longer halves the correction (the round-off of the products).
pub(super) fn refined_solve(
    op: &mut Shifted<'_>,
    p: &Problem,
    ex: Exact<'_>,
    b: &mut [f64],
) -> RefinedStats {
    let (n, nc) = (p.n, p.nc);
    let sigma = op.sigma;
    let mut z = b.to_vec();
    op.solve_factored(&mut z);
    let mut stats = RefinedStats::default();
    if z.iter().any(|v| !v.is_finite()) {
        b.copy_from_slice(&z);
        return stats;
    }
    let mut r = vec![0.0; n];
    let mut w = vec![0.0; n];
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(CYCLE + 1);
    let mut last = f64::INFINITY;
    for _cycle in 0..MAX_CYCLES {
        saddle_times(p, ex, sigma, &z, &mut r);
        r.iter_mut().zip(b.iter()).for_each(|(r, b)| *r = b - *r);
        op.solve_factored(&mut r);
        let (rc, zc) = (norm(&r[..nc]), norm(&z[..nc]));
        stats.correction = if zc > 0.0 { rc / zc } else { rc };
        if stats.correction <= REFINED_TOL || rc >= 0.5 * last || !rc.is_finite() {
            break;
        }
        last = rc;
        let beta = norm(&r);
        let z_norm = norm(&z);
        basis.clear();
        basis.push(r.iter().map(|v| v / beta).collect());
        // Hessenberg columns (rotated), the Givens rotations, and the rotated right-hand side
        let mut h: Vec<Vec<f64>> = Vec::with_capacity(CYCLE);
        let mut rot: Vec<(f64, f64)> = Vec::with_capacity(CYCLE);
        let mut g = vec![beta];
        for j in 0..CYCLE {
            saddle_times(p, ex, sigma, &basis[j], &mut w);
            op.solve_factored(&mut w);
            stats.iterations += 1;
            // modified Gram–Schmidt (enough for GMRES: its least-squares solution stays
            // backward stable without reorthogonalisation)
            let mut col = vec![0.0; j + 2];
            for (i, v) in basis.iter().enumerate() {
                let d: f64 = v.iter().zip(&w).map(|(a, b)| a * b).sum();
                w.iter_mut().zip(v).for_each(|(x, a)| *x -= d * a);
                col[i] = d;
            }
            let hn = norm(&w);
            col[j + 1] = hn;
            for (i, &(c, s)) in rot.iter().enumerate() {
                let (a, b) = (col[i], col[i + 1]);
                col[i] = c * a + s * b;
                col[i + 1] = -s * a + c * b;
            }
            let (a, bb) = (col[j], col[j + 1]);
            let d = a.hypot(bb);
            let (c, s) = if d == 0.0 {
                (1.0, 0.0)
            } else {
                (a / d, bb / d)
            };
            col[j] = d;
            col[j + 1] = 0.0;
            rot.push((c, s));
            g.push(-s * g[j]);
            g[j] *= c;
            h.push(col);
            let estimate = g[j + 1].abs();
            if estimate <= 0.1 * REFINED_TOL * z_norm || hn == 0.0 || !hn.is_finite() {
                break;
            }
            if j + 1 < CYCLE {
                basis.push(w.iter().map(|v| v / hn).collect());
            }
        }
        // y from the triangular system, then z += V y
        let k = h.len();
        let mut y = vec![0.0; k];
        for i in (0..k).rev() {
            let s: f64 = (i + 1..k).map(|l| h[l][i] * y[l]).sum();
            y[i] = (g[i] - s) / h[i][i];
        }
        if y.iter().any(|v| !v.is_finite()) {
            break;
        }
        for (v, &yi) in basis.iter().zip(&y) {
            z.iter_mut().zip(v).for_each(|(a, b)| *a += yi * b);
        }
    }
    b.copy_from_slice(&z);
    stats
}
