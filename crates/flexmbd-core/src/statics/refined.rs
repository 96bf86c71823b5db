//! Refined Newton directions for fine meshes: the factorisation of the reduced KKT matrix solves
//! a matrix perturbed by round-off of the size of its largest entries (the axial and bending
//! stiffness of very short beams), so on fine meshes its directions lose the smooth motions'
//! digits and Newton stalls (a strip of 30,000 beams under a transverse tip load; a thin
//! oblique cantilever of 200 beams). The direction is then refined by GMRES
//! (`math::gmres`, preconditioned by the factorisation) with the products of the KKT matrix
//! taken with the material part through the element deformations (K_m δx = Σ Dᵀ S D δx, which
//! resolves the small elastic forces of a smooth displacement), the geometric part (stresses,
//! normalisation multipliers, load stiffness: small entries) and the constraint rows from
//! their own assembled values.

use super::{assemble_values, Assembled, KktSolver, MaterialOperator, Part, Setup};
use crate::math::gmres;
use crate::model::Model;

/// Newton switches to refined directions after this many iterations without convergence.
pub(super) const REFINE_AFTER: usize = 6;

/// A refined direction stops when the factorisation's correction is this small against it (in
/// the coordinates).
const REFINED_TOL: f64 = 1e-10;

/// Refines the Newton direction `dr` (on entry the factorisation's solution of the reduced KKT
/// system with the right-hand side `b`, by `solver`) at the state (x, μ, load factor t) whose
/// assembly is `a`. Returns whether it changed (the factorisation's correction was above the
/// tolerance); unchanged when the solver kept no factorisation to precondition with.
#[allow(clippy::too_many_arguments)]
pub(super) fn refine_direction(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    a: &Assembled,
    solver: &mut KktSolver,
    b: &[f64],
    dr: &mut [f64],
) -> bool {
    if !solver.reusable() {
        // the factorisation was not kept (small pivots, accepted for this right-hand side
        // alone): nothing to precondition with
        return false;
    }
    let nfr = su.red.nfr;
    let geo = assemble_values(model, su, x, mu, t, Part::Geometric, true, Vec::new());
    let km = MaterialOperator::new(model, su, x);
    // (row, column) of every entry, in the order of the values
    let mut entries = Vec::with_capacity(a.vals.len());
    su.red.for_each_entry(&mut |r, c| entries.push((r, c)));
    entries.extend_from_slice(&a.tail);
    debug_assert_eq!(entries.len(), a.vals.len());
    debug_assert_eq!(geo.vals.len(), a.vals.len());
    let product = |v: &[f64], out: &mut [f64]| {
        km.reduced_forces(model, su, &v[..nfr], &mut out[..nfr]);
        out[nfr..].iter_mut().for_each(|o| *o = 0.0);
        for (e, &(r, c)) in entries.iter().enumerate() {
            let value = if r >= nfr || c >= nfr {
                a.vals[e]
            } else {
                geo.vals[e]
            };
            if value != 0.0 {
                out[r] += value * v[c];
            }
        }
    };
    let stats = gmres::refine(
        b,
        dr,
        nfr,
        REFINED_TOL,
        |v| {
            // the factorisation of this iteration's matrix, which `dr` came from
            let _ = solver.solve_again(v);
        },
        product,
    );
    stats.iterations > 0
}
