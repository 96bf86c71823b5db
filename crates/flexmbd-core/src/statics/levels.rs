//! The requested output levels on an arc-length path (docs/statics.md, "Path following"): a
//! step that crosses a load factor t_k = k/steps (k = 0 … steps) gives the state at exactly
//! that load factor as an output of its own, on every crossing, like the load steps do once;
//! a step that ends next to a level is moved onto it.

use super::arc::{norm2, reduced_increment, State, Step};
use super::{apply_prescribed, inverted_element, newton, KktSolver, Newton, Setup, StaticOptions};
use super::{Assembled, StepResult};
use crate::model::Model;

/// A state at an output level: the converged state, its level k and its distance s from the
/// start of its step in the norm of the constraint.
pub(super) struct LevelState {
    pub(super) step: StepResult,
    pub(super) a: Box<Assembled>,
    pub(super) level: usize,
    pub(super) s: f64,
}

/// The part of the level spacing 1/steps within which the end of a step is moved onto the
/// level ([`snap_to_level`]).
const SNAP: f64 = 1e-3;

/// The level k of a load factor that is exactly t_k = k/steps (0 ≤ k ≤ steps), else `None`.
pub(super) fn level_of(t: f64, steps: usize) -> Option<usize> {
    let k = (t * steps as f64).round();
    (k >= 0.0 && k <= steps as f64 && k / steps as f64 == t).then_some(k as usize)
}

/// The states at the output levels strictly between the load factors of the step from `from`
/// to the converged state `(x1, μ1, t1)` (chord `chord`, rate `p2` of the prescribed
/// coordinates), in path order: each solved by Newton at t_k exactly (load control), from the
/// state interpolated linearly between the two in t. A level whose state is not found inside
/// the step (Newton fails, an element inverts, or it converges at a distance from `from` beyond
/// the chord: next to a limit point, where the load factor crosses the level twice or not at
/// all within the step) is left out.
#[allow(clippy::too_many_arguments)]
pub(super) fn level_states(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    from: &State,
    (x1, mu1, t1): (&[f64], &[f64], f64),
    (steps, p2, chord): (usize, f64, f64),
    kkt: &mut Option<KktSolver>,
) -> Vec<LevelState> {
    let (t0, n) = (from.t, steps as f64);
    let (lo, hi) = (t0.min(t1), t0.max(t1));
    let mut ks: Vec<usize> = (0..=steps)
        .filter(|&k| {
            let tk = k as f64 / n;
            tk > lo && tk < hi
        })
        .collect();
    if t1 < t0 {
        ks.reverse();
    }
    let mut out = Vec::new();
    for k in ks {
        let tk = k as f64 / n;
        let w = (tk - t0) / (t1 - t0);
        let lerp = |a: &[f64], b: &[f64]| -> Vec<f64> {
            a.iter().zip(b).map(|(p, q)| p + w * (q - p)).collect()
        };
        let (mut x, mut mu) = (lerp(&from.x, x1), lerp(&from.mu, mu1));
        apply_prescribed(model, su, &mut x, tk);
        let Newton::Converged {
            iterations,
            residual,
            state,
        } = newton(model, su, opts, &mut x, &mut mu, tk, kkt, None)
        else {
            continue;
        };
        if inverted_element(model, &x, &from.x).is_some() {
            continue;
        }
        let inc = reduced_increment(su, &from.x, &x);
        let dt = tk - t0;
        let s = (norm2(su, &inc) + dt * dt * p2).sqrt();
        if s.is_nan() || s >= chord {
            continue;
        }
        let step = super::path::record(model, &x, &mu, &state, tk, iterations, 1, residual);
        out.push(LevelState {
            step,
            a: state,
            level: k,
            s,
        });
    }
    out.sort_by(|a, b| a.s.total_cmp(&b.s));
    out
}

/// A step from `from` that ends within [`SNAP`]/steps of an output level t_k, but not on it
/// (on a straight stretch the step control makes the load factor advance by about 1/steps per
/// step): the state at t_k exactly, by Newton from the step's end, when it converges within
/// 1 % of the step's chord of it; the step unchanged otherwise. So such a step is itself the
/// output at that level, not a second state next to it.
pub(super) fn snap_to_level(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    step: Step,
    (from, p2, steps): (&State, f64, usize),
    kkt: &mut Option<KktSolver>,
) -> Step {
    let n = steps as f64;
    let k = (step.t * n).round();
    let tk = k / n;
    if step.end || !(0.0..=n).contains(&k) || tk == step.t || (step.t - tk).abs() > SNAP / n {
        return step;
    }
    let (mut x, mut mu) = (step.x.clone(), step.mu.clone());
    apply_prescribed(model, su, &mut x, tk);
    let Newton::Converged {
        iterations,
        residual,
        state,
    } = newton(model, su, opts, &mut x, &mut mu, tk, kkt, None)
    else {
        return step;
    };
    let dt = step.t - from.t;
    let chord = (norm2(su, &reduced_increment(su, &from.x, &step.x)) + dt * dt * p2).sqrt();
    let dt_snap = tk - step.t;
    let moved = (norm2(su, &reduced_increment(su, &step.x, &x)) + dt_snap * dt_snap * p2).sqrt();
    if moved > 0.01 * chord || inverted_element(model, &x, &from.x).is_some() {
        return step;
    }
    Step {
        x,
        mu,
        t: tk,
        a: state,
        iterations: step.iterations + iterations,
        residual,
        end: false,
    }
}
