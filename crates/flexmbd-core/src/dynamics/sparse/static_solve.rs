//! Static responses on the sparse path: δx = K⁻¹ f on the constrained space, from one sparse
//! factorisation of the statics Newton matrix [K, Gᵀ; G, 0] at the state (σ = 0 of the
//! shift-invert operator), refined (`refined` module: on a 600-element strip the assembled
//! entries are 1e7 times the elastic forces of a smooth displacement, and a plain solve loses up
//! to 1e-5 of the compliance). Used by the state-space model of large models for the static
//! (residual-flexibility) feedthrough.

use super::problem::Problem;
use super::refined::Exact;
use super::shifted::Shifted;
use crate::dynamics::ModalError;
use crate::model::Model;
use crate::statics::{MaterialOperator, StepResult};

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
/// system (coordinate loads, then constraint values), from one factorisation with refined solves. `Err(SparseSingular)` as [`static_responses`].
pub(super) fn saddle_solutions(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    rhs: &[Vec<f64>],
) -> Result<Vec<Vec<f64>>, ModalError> {
    let km = MaterialOperator::new(model, p.lin.setup(), &step.x);
    let g = p.constraint_entries();
    let exact = Exact {
        model,
        km: &km,
        g: &g,
    };
    let mut op = Shifted::refined(p, exact);
    if !op.factor(p, 0.0, true) {
        return Err(ModalError::SparseSingular);
    }
    let mut out = Vec::with_capacity(rhs.len());
    for b in rhs {
        let mut z = vec![0.0; b.len()];
        op.solve(p, b, &mut z);
        if z.iter().any(|v| !v.is_finite()) {
            return Err(ModalError::SparseSingular);
        }
        out.push(z);
    }
    Ok(out)
}
