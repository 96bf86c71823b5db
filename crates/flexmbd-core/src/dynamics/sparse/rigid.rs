//! Rigid-body modes on the sparse path (docs/dynamics.md, "Rigid-body modes").
//!
//! The dense path sees the whole spectrum, so [`rigid_body_count`] finds the gap of
//! [`RIGID_BODY_GAP`] between the rigid-body modes (round-off of zero) and the first elastic
//! mode. The sparse path lists only the lowest modes asked for: when they are all rigid-body
//! modes the list holds no elastic mode to compare with. The gap is then checked by the inertia
//! instead (Sylvester's law, as the sparse solver's own Sturm check): the number of eigenvalues
//! below a probe shift
//!
//! τ = max(max |ω²| of the list / RIGID_BODY_GAP, 100 max(|σ|, ε λ_ref))
//!
//! (σ the shift of the iteration, λ_ref the largest ratio of a diagonal stiffness to its mass:
//! the second term keeps τ above the round-off of the factorisation, where an inertia count
//! means something). If exactly the listed modes lie below τ, the next eigenvalue is at least
//! τ, so every listed |ω²| is at most RIGID_BODY_GAP times it, and positive: the dense path's
//! criterion holds, and the whole list is rigid-body modes. If more lie below τ (some rigid-body
//! modes were not asked for, e.g. 3 of a free body's 6), the lowest of them are computed as
//! well, up to [`MAX_EXTRA`] more, and the criterion is applied to that longer list. Otherwise
//! (no inertia count, too many eigenvalues below τ) no mode is flagged, as on the dense path
//! when there is no gap.

use super::{modes_of, plain_then_refined, Problem, SparseModes};
use crate::dynamics::{rigid_body_count, ModalError, RIGID_BODY_GAP};
use crate::model::Model;
use crate::statics::StepResult;

/// The most modes beyond those asked for that are computed to list every rigid-body mode (a
/// free body has 6; a free mechanism a few more).
const MAX_EXTRA: usize = 24;

/// Margin of the probe shift over the round-off level of the shifted factorisation.
const ROUND_OFF_MARGIN: f64 = 100.0;

/// A list whose largest |ω²| exceeds this fraction of λ_ref holds no rigid-body mode: their
/// eigenvalues (Rayleigh quotients with the strain energy through the element deformations,
/// `sparse`) are round-off, a few ε λ_ref at most. Such lists (the common case of a supported
/// model with coarse elements) skip the probe and its factorisation.
const PROBE_MAX: f64 = 1e-6;

/// The probe shift τ (module docs), when the listed `eigenvalues` (ascending) show no gap of
/// their own and do not exhaust the `n_finite` finite eigenvalues and may be round-off
/// ([`PROBE_MAX`]); `None` otherwise (no probe).
pub(super) fn probe_shift(
    sigma: f64,
    lambda_ref: f64,
    eigenvalues: &[f64],
    n_finite: usize,
) -> Option<f64> {
    if eigenvalues.is_empty()
        || eigenvalues.len() >= n_finite
        || rigid_body_count(eigenvalues) > 0
        || eigenvalues.iter().any(|l| !l.is_finite())
    {
        return None;
    }
    let top = eigenvalues.iter().fold(0.0f64, |m, l| m.max(l.abs()));
    if top > PROBE_MAX * lambda_ref {
        return None;
    }
    let floor = ROUND_OFF_MARGIN * sigma.abs().max(f64::EPSILON * lambda_ref);
    Some((top / RIGID_BODY_GAP).max(floor))
}

/// The number of rigid-body modes at the start of a list: the dense path's gap criterion on
/// the list, or the whole list when exactly its modes lie below the probe shift.
pub(super) fn count(eigenvalues: &[f64], below_gap: Option<usize>) -> usize {
    match rigid_body_count(eigenvalues) {
        0 if below_gap == Some(eigenvalues.len()) => eigenvalues.len(),
        r => r,
    }
}

/// The lowest `count` modes of `p` with their rigid-body modes identified: when more eigenvalues
/// than those asked for lie below the probe shift, the lowest of them are computed too (at most
/// [`MAX_EXTRA`] more) and counted; the modes returned are the `count` asked for, after the
/// check that the elastic ones are resolved ([`SparseModes::check_accuracy`]); when they are
/// not, all again with refined solves.
pub(super) fn modes_listing_rigid(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    count: usize,
) -> Result<SparseModes, ModalError> {
    plain_then_refined(|refine| {
        let mut sm = modes_of(p, model, step, count, refine)?;
        let listed = sm.eigenvalues.len();
        let more = sm
            .below_gap
            .filter(|&c| sm.rigid == 0 && c > listed && c <= listed + MAX_EXTRA);
        if let Some(c) = more {
            // a failure of the longer run leaves the modes asked for without the flag
            if let Ok(all) = modes_of(p, model, step, c, refine) {
                sm.rigid = all.rigid.min(listed);
            }
        }
        sm.check_accuracy()?;
        Ok(sm)
    })
}
