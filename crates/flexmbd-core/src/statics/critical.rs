//! Critical points along an arc-length path (docs/statics.md, "Locating critical points"):
//! where the number of unstable directions of the tangent changes within a step, the state in
//! that step where the tangent is singular is located ([`locate`]), and every critical point
//! passed is reported ([`critical_points`]).
//!
//! **Location.** The count changes from u₀ to u₁ between two converged states when the
//! eigenvalue κ_j, j = min(u₀, u₁) (0-based, ascending: `eigen.rs`), changes sign. The states
//! between them are the arc-length states at the distance s ∈ (0, Δs) from the first on the
//! same cylinder constraint (Δs the chord of the step), so κ_j(s) is a function of one variable:
//! its zero is found by regula falsi with the Illinois modification (Dowell & Jarratt 1971:
//! the end point kept twice in a row has its value halved, superlinear convergence) until s
//! changes by less than [`S_TOL`] Δs (the states themselves are converged to `tol_disp`, 1e-9
//! of the model size by default). Without κ (a model beyond the size of the dense
//! eigenvalues) the bracket is bisected on the inertia count instead. A limit point κ = 0 is
//! the extreme of the load factor (its error is second order in that of s); a bifurcation is
//! the load at which another branch crosses. When a state fails (Newton right at the singular
//! point, an inverted element) the search ends with the best state so far; with none, the
//! step keeps its sampled critical point.

use super::arc::{arc_step, tangent, State, Step};
use super::eigen::{kappa, smallest_eigenvalues};
use super::{
    inverted_element, Assembled, KktSolver, PathEvent, PathPoint, Setup, StaticOptions, StepResult,
};
use crate::model::Model;

/// The convergence of the location: s changes by less than this fraction of the chord.
pub(super) const S_TOL: f64 = 1e-8;

/// The most states solved to locate one critical point.
const MAX_EVALUATIONS: usize = 40;

/// A critical point located inside a step: the index of its state on the path, whether the
/// load factor turns there (a limit point) or goes on (a bifurcation), and the unstable
/// directions before and after.
#[derive(Clone, Copy, Debug)]
pub(super) struct Located {
    pub(super) step: usize,
    pub(super) limit: bool,
    pub(super) unstable: [usize; 2],
}

/// The located critical state: the converged state (with the iterations of its last solve),
/// its distance s from the step's start, and its eigenvalues and inertia.
pub(super) struct Critical {
    pub(super) state: Step,
    pub(super) s: f64,
    pub(super) kappa: Option<Vec<f64>>,
    pub(super) unstable: Option<usize>,
}

/// The step whose critical point is located: from `from`, along `sign` × its tangent, with the
/// rate `p2` of the prescribed translations, to the converged state `to` (its assembly) at the
/// chord `chord`, the unstable directions changing from `unstable[0]` to `unstable[1]`.
pub(super) struct Bracket<'a> {
    pub(super) from: &'a State,
    pub(super) to: &'a Assembled,
    pub(super) sign: f64,
    pub(super) p2: f64,
    pub(super) chord: f64,
    pub(super) unstable: [usize; 2],
}

/// The state inside the step `b` where the tangent is singular (module docs); `None` when an
/// attempt fails.
pub(super) fn locate(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    b: &Bracket<'_>,
    kkt: &mut Option<KktSolver>,
) -> Option<Critical> {
    let [u0, u1] = b.unstable;
    let j = u0.min(u1);
    let kappa_j =
        |a: &Assembled| smallest_eigenvalues(su, a, j + 1).and_then(|v| v.get(j).copied());
    let (mut lo, mut hi) = (0.0, b.chord);
    let (mut f_lo, mut f_hi) = match (kappa_j(&b.from.a), kappa_j(b.to)) {
        (Some(f0), Some(f1)) if f0 * f1 < 0.0 => (f0, f1),
        _ => (f64::NAN, f64::NAN),
    };
    let by_kappa = f_lo.is_finite();
    let mut best: Option<(super::arc::Step, f64, f64)> = None; // state, s, |κ_j|
    let mut kept = 0i8; // the end the last update kept: 1 high (low replaced), −1 low
    let mut s_last = f64::NAN;
    for _ in 0..MAX_EVALUATIONS {
        let mut s = if by_kappa {
            (lo * f_hi - hi * f_lo) / (f_hi - f_lo)
        } else {
            0.5 * (lo + hi)
        };
        if !(s > lo && s < hi) {
            s = 0.5 * (lo + hi);
        }
        // a state that fails (Newton at a singular tangent next to the critical point, an
        // inverted element) ends the search with the best state so far
        let Ok(st) = arc_step(model, su, opts, b.from, (s, b.sign, b.p2), kkt) else {
            break;
        };
        if inverted_element(model, &st.x, &b.from.x).is_some() {
            break;
        }
        let (below, f) = if by_kappa {
            let Some(f) = kappa_j(&st.a) else { break };
            (f * f_lo > 0.0, f)
        } else {
            let u = tangent(model, su, (&st.x, st.t), &st.a, kkt)
                .ok()
                .and_then(|t| t.unstable);
            let Some(u) = u else { break };
            (u == u0, 0.0)
        };
        let done = (s - s_last).abs() <= S_TOL * b.chord || (by_kappa && f == 0.0);
        s_last = s;
        if best.as_ref().is_none_or(|(_, _, g)| f.abs() <= *g) {
            best = Some((st, s, f.abs()));
        }
        if below {
            lo = s;
            f_lo = f;
            if kept == 1 {
                f_hi *= 0.5;
            }
            kept = 1;
        } else {
            hi = s;
            f_hi = f;
            if kept == -1 {
                f_lo *= 0.5;
            }
            kept = -1;
        }
        if done || hi - lo <= S_TOL * b.chord {
            break;
        }
    }
    let (st, s, _) = best?;
    let kappa = kappa(su, &st.a, opts.tangent_eigenvalues);
    let unstable = tangent(model, su, (&st.x, st.t), &st.a, kkt)
        .ok()
        .and_then(|t| t.unstable);
    Some(Critical {
        state: st,
        s,
        kappa,
        unstable,
    })
}

/// The critical points along a path: those located inside a step (`located`), and, sampled, a
/// limit point at every other step where the load factor is extreme (it moves the other way
/// before and after), a bifurcation where the number of unstable directions changes between
/// two steps with no limit point at either of them; in path order.
pub(super) fn critical_points(
    steps: &[StepResult],
    path: &[PathPoint],
    located: &[Located],
) -> Vec<PathEvent> {
    let t: Vec<f64> = steps.iter().map(|s| s.load_factor).collect();
    let limit = |k: usize| k > 0 && k + 1 < t.len() && (t[k] - t[k - 1]) * (t[k + 1] - t[k]) < 0.0;
    // the steps next to a located critical point (its own and the two that bracket it)
    let near = |k: usize| located.iter().any(|l| k + 1 >= l.step && k <= l.step + 1);
    let mut events: Vec<PathEvent> = located
        .iter()
        .map(|l| {
            let load_factor = t[l.step];
            if l.limit {
                PathEvent::LimitPoint {
                    step: l.step,
                    load_factor,
                    located: true,
                }
            } else {
                PathEvent::Bifurcation {
                    step: l.step,
                    load_factor,
                    unstable: l.unstable,
                    located: true,
                }
            }
        })
        .collect();
    let is_located = |k: usize| located.iter().any(|l| l.step == k);
    for k in 1..t.len().min(path.len()) {
        if limit(k - 1) && !near(k - 1) {
            events.push(PathEvent::LimitPoint {
                step: k - 1,
                load_factor: t[k - 1],
                located: false,
            });
        }
        if is_located(k - 1) || is_located(k) {
            continue;
        }
        if let (Some(u0), Some(u1)) = (path[k - 1].unstable_directions, path[k].unstable_directions)
        {
            if u0 != u1 && !limit(k - 1) && !limit(k) {
                events.push(PathEvent::Bifurcation {
                    step: k,
                    load_factor: t[k],
                    unstable: [u0, u1],
                    located: false,
                });
            }
        }
    }
    events.sort_by_key(|e| match *e {
        PathEvent::LimitPoint { step, .. }
        | PathEvent::Bifurcation { step, .. }
        | PathEvent::Jump { step, .. } => step,
    });
    events
}
