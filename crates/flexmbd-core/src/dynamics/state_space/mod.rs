//! Linear state-space model about a static equilibrium (theory.md §13.5, issue 6 item 5).
//!
//! Modal form with mass-normalised modes Φ (Φᵀ M0 Φ = I, Φᵀ K0 Φ = Ω²) of the minimal
//! coordinates, δq = Φ η, state z = (η, η̇):
//!
//! ```text
//! ż = A z + B u,   y = C z + D u
//! A = [[0, I], [−Ω², −2ζΩ]],   B = [[0], [Φᵀ Bq]]
//! displacement:  C = [Cx Φ, 0]               D = Cx F Bq
//! velocity:      C = [0, Cx Φ]               D = 0
//! acceleration:  C = [−Cx Φ Ω², −Cx Φ 2ζΩ]   D = Cx Φ Φᵀ Bq
//! ```
//!
//! - Inputs u: a force on a node along a global axis, f_x = e_i on the node's position, or a
//!   moment about a global axis, f_λ = 2 Λ̄ᵀ e_k on its Euler parameters (the dual of
//!   ω = 2 Λ̄ λ̇, as in `statics::linear::compliance`); Bq = Zᵀ f_x.
//! - Outputs y: a translation of a node along a global axis (the row e_iᵀ Z) or its rotation
//!   about a global axis (2 Λ̄ δλ: the row 2 (Λ̄ Z)_k), as displacement, velocity or acceleration.
//!   The acceleration follows from ÿ = Cx Φ η̈ with η̈ = −Ω² η − 2ζΩ η̇ + Φᵀ Bq u.
//! - Damping: modal, ratio ζ for every mode (SPACAR Light's choice). For an unstable mode
//!   (ω² < 0) the damping term uses √|ω²|.
//! - F: static flexibility not carried by the kept modes, so that displacement outputs have the
//!   correct static gain. Always the massless part Q₀ K₀₀⁻¹ Q₀ᵀ (directions without inertia are
//!   condensed statically and respond to a force on them instantaneously, see [`Reduced`]);
//!   with `static_correction` also the residual flexibility of the dropped modes,
//!   Σ_dropped φ_k φ_kᵀ / ω_k². Then the DC gain −C A⁻¹ B + D of a displacement output is
//!   Cx K0⁻¹ Bq, the static compliance, because K0⁻¹ = Φ Ω⁻² Φᵀ + Q₀ K₀₀⁻¹ Q₀ᵀ (block
//!   inverse with the Schur complement K_c). Velocity and acceleration outputs cannot contain
//!   the instantaneous massless response (it would need u̇, ü): where it is non-zero the
//!   model warns.
//!
//! Prescribed-motion inputs (base excitation, enforced motion): a held coordinate m (support,
//! `[inputs]` or `[[prescribe]]`) moves by u_m(t): a translation along a global axis, or a
//! small rotation about a global axis of a node whose rotation component is held (a rotary
//! actuator). With t_m its unit direction in x — e_i for a translation, the Euler-parameter
//! rate of a unit rotation δλ = ½ Λ̄ᵀ e_k (so that ω = 2 Λ̄ δλ = e_k) for a rotation — lifted
//! onto the rigid constraints (G t_m = 0 through free coordinates), δx = Z δq + t_m u_m and
//!
//! ```text
//! M0 q̈ + K0 q = −(Zᵀ K t_m) u_m − (Zᵀ M t_m) ü_m
//! q = ψ u_m + r,   ψ = −K0⁻¹ Zᵀ K t_m   (quasi-static response to a unit enforced motion)
//! M0 r̈ + K0 r = −(M0 ψ + Zᵀ M t_m) ü_m
//! ```
//!
//! so r is driven like a force input with Bq = −(M0 ψ + Zᵀ M t_m), and the input is the
//! acceleration ü_m. Each motion input adds the states (u_m, u̇_m), a double integrator
//! (A block [[0, 1], [0, 0]], B entry 1 on u̇_m). An output row w gives the absolute motion
//! δy = Cx r + g u_m with g = Cx ψ + w·t_m: g enters C on u_m (displacement), on u̇_m
//! (velocity) or D (acceleration). K0 is solved directly (dense LU), so massless directions
//! are part of ψ exactly. A rotation output of the moved node about the moved axis has
//! w·t_m = 2 e_kᵀ Λ̄ ½ Λ̄ᵀ e_k = 1: the outputs stay absolute.
//!
//! A held deformation (an `input` mode: an actuator's elongation, a driven hinge's angle) is
//! driven the same way, with t_m the least-squares solution of G t_m = e_row through the free
//! coordinates: the unit change of the driven deformation and none of the other rigid or
//! prescribed ones ([`Motion::Deformation`]).

mod build;
mod error;
mod lift;
mod signals;
mod sparse;
mod system;

pub use error::StateSpaceError;
pub use signals::{Input, InputInfo, Motion, Output, OutputKind, Probe};
pub use system::{log_space, magnitude_phase, to_rows, StateSpace};

use super::{auto_solver, reduced_matrices, velocity_dof, EigenSolver, Reduced};
use crate::elements::ElementKind;
use crate::linearized::Tangent;
#[cfg(test)]
use crate::model::Dof;
use crate::model::Model;
use crate::statics::StepResult;
use build::build;
#[cfg(test)]
use faer::{c64, Mat};
use sparse::build_sparse;

/// Options of [`state_space`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateSpaceOptions {
    /// Modal damping ratio ζ of every mode (≥ 0).
    pub damping: f64,
    /// Keep the lowest N modes (None: all modes that carry mass).
    pub modes: Option<usize>,
    /// Add the residual static flexibility of the dropped modes to D (displacement outputs),
    /// so that a truncated model keeps the exact static gain.
    pub static_correction: bool,
    /// Eigen solver: `Auto` is the one rule of [`crate::dynamics::auto_solver`]: sparse (the
    /// lowest `modes` only, which must then be given) for a large model, or for a truncated one
    /// with the static correction on more than [`crate::dynamics::SPARSE_THRESHOLD`] degrees of
    /// freedom; dense (all modes, massless directions condensed exactly) otherwise.
    pub solver: EigenSolver,
    /// Memory limit of the dense state space in bytes
    /// ([`super::dense_size::dense_bytes`]): above it the dense path stops with
    /// [`crate::dynamics::ModalError::TooLarge`] before its matrices are allocated. Default
    /// [`crate::linalg::DEFAULT_MAX_DENSE_BYTES`].
    pub max_dense_bytes: u64,
}

/// [`EigenSolver::Auto`] builds a state space of all modes densely up to this many degrees of
/// freedom ([`crate::dynamics::auto_solver`]).
pub const DENSE_STATE_SPACE_DOF: usize = super::DENSE_FALLBACK_DOF;

impl Default for StateSpaceOptions {
    fn default() -> Self {
        StateSpaceOptions {
            damping: 0.01,
            modes: None,
            static_correction: false,
            solver: EigenSolver::Auto,
            max_dense_bytes: crate::linalg::DEFAULT_MAX_DENSE_BYTES,
        }
    }
}

/// Build the state-space model at a converged static state.
pub fn state_space(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    state_space_with_motions(model, step, inputs, &[], outputs, opts)
}

/// [`state_space`] with prescribed-motion inputs as well: B and D get the columns of `inputs`
/// (forces, moments), then those of `motions` (enforced accelerations ü [m/s²]); the state
/// gets (u, u̇) of every motion after the modal coordinates (module docs).
pub fn state_space_with_motions(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    state_space_at(&Tangent::new(model, step), inputs, motions, outputs, opts)
}

/// [`state_space_with_motions`] at a linearised stage already at hand.
pub fn state_space_at(
    t: &Tangent,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    let (model, step) = (t.model(), t.step());
    check_ids(model, inputs, motions, outputs)?;
    let ndof = velocity_dof(model);
    if uses_sparse(model, opts) {
        check_options(inputs, motions, outputs, opts)?;
        let Some(count) = opts.modes else {
            return Err(StateSpaceError::SparseNeedsModes {
                ndof,
                limit: DENSE_STATE_SPACE_DOF,
            });
        };
        return build_sparse(model, step, inputs, motions, outputs, count, opts);
    }
    check_dense_size(model, opts)?;
    let red = reduced_matrices(t)?;
    build(model, step, &red, inputs, motions, outputs, opts)
}

/// Whether [`state_space_with_motions`] takes the sparse path for this model and these
/// options (the solver asked for; `Auto`: [`crate::dynamics::auto_solver`], with the kept modes
/// as the wanted ones when the static correction is on, else all modes).
pub fn uses_sparse(model: &Model, opts: &StateSpaceOptions) -> bool {
    match opts.solver {
        EigenSolver::Auto => {
            let wanted = opts.modes.filter(|_| opts.static_correction);
            auto_solver(velocity_dof(model), wanted) == EigenSolver::Sparse
        }
        s => s == EigenSolver::Sparse,
    }
}

/// The size guard of the dense state space: [`crate::dynamics::ModalError::TooLarge`] when the options choose
/// the dense path and its matrices would exceed `opts.max_dense_bytes`.
pub fn check_dense_size(model: &Model, opts: &StateSpaceOptions) -> Result<(), StateSpaceError> {
    if !uses_sparse(model, opts) {
        super::dense_size::check_dense_modal(model, opts.max_dense_bytes, true)?;
    }
    Ok(())
}

/// Validate the options and the input/output counts.
/// Every node, element and mode an input, motion or output names exists in `model` (the ids are
/// plain indices: a wrong one must be an error, not a panic).
fn check_ids(
    model: &Model,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
) -> Result<(), StateSpaceError> {
    let node = |n: usize, what: &str| {
        (n < model.nodes.len())
            .then_some(())
            .ok_or_else(|| StateSpaceError::UnknownId(format!("{what} of node #{n}")))
    };
    let mode = |el: usize, m: usize, what: &str| match model.elements.get(el) {
        Some(e) if m < e.element.ne() => Ok(()),
        _ => Err(StateSpaceError::UnknownId(format!(
            "{what} of mode {} of element #{el}",
            m + 1
        ))),
    };
    for i in inputs {
        node(i.node, "input")?;
    }
    for m in motions {
        match *m {
            Motion::Node { node: n, .. } => node(n, "motion input")?,
            Motion::Deformation { element, mode: k } => mode(element, k, "motion input")?,
        }
    }
    for o in outputs {
        match o.probe {
            Probe::Node { node: n, .. } | Probe::Reaction { node: n, .. } => node(n, "output")?,
            Probe::Deformation { element, mode: k } | Probe::Force { element, mode: k } => {
                mode(element, k, "output")?
            }
        }
    }
    Ok(())
}

pub(super) fn check_options(
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<(), StateSpaceError> {
    let zeta = opts.damping;
    if !(zeta.is_finite() && zeta >= 0.0) {
        return Err(StateSpaceError::BadDamping(zeta));
    }
    if opts.modes == Some(0) {
        return Err(StateSpaceError::NoModes);
    }
    if (inputs.is_empty() && motions.is_empty()) || outputs.is_empty() {
        return Err(StateSpaceError::NoInputOutput);
    }
    Ok(())
}

/// [`state_space_with_motions`] from reduced matrices already at hand (e.g. those of a
/// modal analysis of the same step).
pub fn state_space_from(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    check_ids(model, inputs, motions, outputs)?;
    build(model, step, red, inputs, motions, outputs, opts)
}

#[cfg(test)]
mod motion_tests;

#[cfg(test)]
mod deformation_tests;

#[cfg(test)]
mod sparse_tests;

#[cfg(test)]
mod element_output_tests;

#[cfg(test)]
mod parity_tests;

#[cfg(test)]
mod tests;
