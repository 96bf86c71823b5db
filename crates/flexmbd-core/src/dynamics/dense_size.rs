//! The size guard of the dense linearised dynamics (modes, sweep, state space): the memory its
//! matrices need is computed from the model's sizes before anything large is allocated, and a
//! model above the limit stops with [`ModalError::TooLarge`] (docs/reliability.md, "Limits").

use super::solver::dense_for_many_modes;
use super::{velocity_dof, EigenSolver, ModalError, ModalOptions};
use crate::linalg::check_dense_bytes;
use crate::model::Model;

/// Bytes of the dense modal analysis ([`super::reduced_matrices`] and its eigen solution), an
/// estimate of the largest set of matrices alive at once, with n_x coordinates and n_v
/// velocity degrees of freedom ([`velocity_dof`]), in f64:
///
/// - while the reduced matrices are built: the linearisation K_m, K_g, G
///   ([`crate::linearized::dense_bytes`]), K and M in x (2 n_x²), the basis Z (n_x n_v)
///   and, in n_v², the reduced K0 and M0, the eigen decomposition of M0 with its workspace,
///   the massive and massless bases and the condensed stiffness (8 n_v²);
/// - while the eigenpairs are computed: the reduced matrices (M in x: n_x², Z, five n_v²
///   matrices) and the dense eigen solver (its generalised and shifted passes, ten n_v²).
///
/// With `state_space`, also the state-space matrices (A of (2 n_v)², the modes and the static
/// corrections: six n_v² more).
pub fn dense_bytes(model: &Model, state_space: bool) -> (usize, u128) {
    let nv_usize = velocity_dof(model);
    let (nx, nv) = (model.nx as u128, nv_usize as u128);
    let (_, linear) = crate::linearized::dense_bytes(model, true);
    let build = linear + 8 * (2 * nx * nx + nx * nv + 8 * nv * nv);
    let eigen = 8 * (nx * nx + nx * nv + 15 * nv * nv);
    let ss = if state_space { 8 * 6 * nv * nv } else { 0 };
    (nv_usize, build.max(eigen) + ss)
}

/// The size guard of the dense modal analysis: [`ModalError::TooLarge`] when the solver that
/// `opts` choose for `count` modes is the dense one and [`dense_bytes`] exceeds
/// `opts.max_dense_bytes`, or [`ModalError::TooManyModes`] when the automatic choice,
/// [`super::auto_solver`], went dense because more than a third of the modes are asked for.
/// (The dense fallback of a failed sparse solve is guarded where it is taken.)
pub fn check_dense_size(
    model: &Model,
    count: usize,
    opts: &ModalOptions,
) -> Result<(), ModalError> {
    if opts.resolve(model, count) != EigenSolver::Dense {
        return Ok(());
    }
    check_dense_modes(model, count, opts)
}

/// [`check_dense_modal`] for `count` modes on the dense path that `opts` chose: a model too
/// large for it when the automatic choice went dense only because most of the modes are
/// wanted is [`ModalError::TooManyModes`].
pub(crate) fn check_dense_modes(
    model: &Model,
    count: usize,
    opts: &ModalOptions,
) -> Result<(), ModalError> {
    let ndof = velocity_dof(model);
    check_dense_modal(model, opts.max_dense_bytes, false).map_err(|e| match e {
        ModalError::TooLarge(too_large) if dense_for_many_modes(opts, ndof, count) => {
            ModalError::TooManyModes {
                wanted: count,
                ndof,
                too_large,
            }
        }
        e => e,
    })
}

/// [`dense_bytes`] against `limit`, for the modal analysis or (`state_space`) the state space.
pub(crate) fn check_dense_modal(
    model: &Model,
    limit: u64,
    state_space: bool,
) -> Result<(), ModalError> {
    let (dof, bytes) = dense_bytes(model, state_space);
    let (what, remedy) = if state_space {
        (
            "state space (all modes)",
            "use the sparse eigen solver, which keeps the lowest modes only (give their number, \
             with the static correction for the exact static gain)",
        )
    } else {
        (
            "modal analysis (all modes)",
            "use the sparse eigen solver, which computes the lowest modes only",
        )
    };
    check_dense_bytes(what, remedy, dof, bytes, limit)?;
    Ok(())
}
