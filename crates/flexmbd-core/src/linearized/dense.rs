//! The dense form of the stage: the material stiffness K_m, the geometric stiffness K_g and
//! the constraint Jacobian G on the free coordinates (module docs of [`super`]), with the
//! memory guard of the dense linearised results.

use crate::model::Model;
use crate::statics::linear::LinearError;
use crate::statics::{assemble_part, setup, Part, StepResult};
use faer::Mat;

/// The linearised static problem at a state (dense).
#[derive(Clone, Debug)]
pub struct Linearized {
    /// x index → unknown index.
    pub unknown: Vec<Option<usize>>,
    /// Material stiffness K_m on the free coordinates.
    pub km: Mat<f64>,
    /// Geometric (load-proportional) stiffness K_g on the free coordinates.
    pub kg: Mat<f64>,
    /// Constraint Jacobian G (constraints × free coordinates).
    pub g: Mat<f64>,
}

fn dense(
    n: usize,
    m: usize,
    tr: &[faer::sparse::Triplet<usize, usize, f64>],
    r0: usize,
    c0: usize,
) -> Mat<f64> {
    let mut a = Mat::zeros(n, m);
    for t in tr {
        if t.row >= r0 && t.row < r0 + n && t.col >= c0 && t.col < c0 + m {
            a[(t.row - r0, t.col - c0)] += t.val;
        }
    }
    a
}

/// Bytes of the dense matrices of the linearised results at one step ([`super::at_step`]), an
/// estimate of the largest set alive at once: K_m and K_g (n_f² each) and G (n_k n_f), with
/// n_f free coordinates and n_k constraints, plus the larger of the compliance's KKT matrix
/// and its LU factors (2 (n_f + n_k)²) and the buckling and stability analyses (the SVD
/// factors of G, n_k² + n_f², the null-space basis and the reduced K_m, K_g with the
/// workspace of the generalised eigenproblem, about 8 n_f² at most). With `modal`, only the
/// linearisation itself (K_m, K_g, G): the part the dense modal analysis adds to its own.
pub fn dense_bytes(model: &Model, modal: bool) -> (usize, u128) {
    let su = setup(model);
    let (nf, nk) = (su.nf as u128, su.nk as u128);
    let lin = 2 * nf * nf + nk * nf;
    let extra = if modal {
        0
    } else {
        (2 * (nf + nk) * (nf + nk)).max(nk * nk + 9 * nf * nf)
    };
    (su.nf, 8 * (lin + extra))
}

/// The size guard of the linearised results: [`LinearError::TooLarge`] when [`dense_bytes`]
/// exceeds `limit`.
pub fn check_dense_size(model: &Model, limit: u64) -> Result<(), LinearError> {
    let (dof, bytes) = dense_bytes(model, false);
    crate::linalg::check_dense_bytes(
        "linearisation (compliance, buckling, stability)",
        "these are computed with dense matrices: ask for them on a model with fewer elements",
        dof,
        bytes,
        limit,
    )?;
    Ok(())
}

/// The dense K_m, K_g and G at a converged step (built once per state by
/// [`super::Tangent::dense`]).
pub fn linearize(model: &Model, step: &StepResult) -> Linearized {
    let su = setup(model);
    let (nf, nk) = (su.nf, su.nk);
    let t = step.load_factor;
    let m = assemble_part(model, &su, &step.x, &step.multipliers, t, Part::Material);
    let g = assemble_part(model, &su, &step.x, &step.multipliers, t, Part::Geometric);
    Linearized {
        unknown: su.unknown.iter().map(|u| u.get()).collect(),
        km: dense(nf, nf, &m.triplets, 0, 0),
        kg: dense(nf, nf, &g.triplets, 0, 0),
        g: dense(nk, nf, &m.triplets, nf, 0),
    }
}
