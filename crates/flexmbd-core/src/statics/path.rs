//! The equilibrium path over the load steps: [`solve_path`] (with [`solve`] on top of it, and
//! `crate::linearized::analyse` with the linearised results), and what a path that stops part-way keeps ([`Stopped`]).
//!
//! Nothing converged is lost: when a step fails (no convergence even with the smallest
//! sub-step, an inverted element, a state that is not finite), the error comes with every step
//! that converged before it, and with the last converged sub-step when that lies beyond the last
//! full step (the state closest to where the path stopped, e.g. just below a limit point).

use super::eigen::tangent_eigenvalues;
use super::{
    apply_prescribed, assemble, exact_equilibrium, inverted_element, linear, newton,
    non_finite_parts, setup, Assembled, Newton, PathMethod, SolveError, StaticOptions,
    StaticSolution, StepResult, MAX_ITERATIONS, MAX_STEPS,
};
use crate::model::{CoordKind, Model};

/// [`solve`] with `steps` load steps and default settings otherwise, no progress (tests).
#[cfg(test)]
pub(crate) fn solve_steps(model: &Model, steps: usize) -> Result<StaticSolution, SolveError> {
    solve(
        model,
        &StaticOptions {
            steps,
            ..Default::default()
        },
        |_, _| {},
    )
}

/// The last step of [`solve_steps`], which must converge (tests).
#[cfg(test)]
pub(crate) fn last_step(model: &Model, steps: usize) -> StepResult {
    let mut sol = solve_steps(model, steps).expect("the static solution converges");
    sol.steps.pop().expect("at least one step")
}

/// A static analysis: the equilibrium path and the linearised results at every step.
#[derive(Clone, Debug)]
pub struct StaticAnalysis {
    /// The equilibrium at every load step.
    pub solution: StaticSolution,
    /// The linearised results at every step (same order; empty entries when none were asked).
    pub linear: Vec<linear::StepLinear>,
}

/// A static path that stopped before its last load step: why ([`Stopped::error`], also its
/// [`std::error::Error::source`]), and everything that converged before
/// ([`Stopped::analysis`]): the steps, the last one possibly a sub-step between two output
/// steps (the last converged state), with their linearised results when
/// `crate::linearized::analyse` was asked
/// for them.
#[derive(Clone, Debug, thiserror::Error)]
#[error("{}", stopped_text(&self.analysis.solution))]
pub struct Stopped {
    /// Why the path stopped.
    #[source]
    pub error: SolveError,
    /// The converged part of the path (no step when the unloaded state already failed).
    pub analysis: StaticAnalysis,
}

fn stopped_text(sol: &StaticSolution) -> String {
    match sol.steps.last() {
        Some(st) => format!(
            "the static path stopped after step {} (load factor {:.6})",
            sol.steps.len() - 1,
            st.load_factor
        ),
        None => "the static path stopped before any state converged".into(),
    }
}

impl Stopped {
    /// The converged part of the path and why it stopped.
    pub fn into_parts(self) -> (StaticAnalysis, SolveError) {
        (self.analysis, self.error)
    }
}

/// Solve the static equilibrium over the load steps. A path that stops part-way is an error
/// without its converged steps; [`solve_path`] keeps them.
pub fn solve(
    model: &Model,
    opts: &StaticOptions,
    progress: impl FnMut(usize, usize),
) -> Result<StaticSolution, SolveError> {
    solve_path(model, opts, progress).map_err(|s| s.error)
}

/// Solve the static equilibrium over the load steps; a path that stops part-way returns every
/// converged step with the error ([`Stopped`], without linearised results).
#[allow(clippy::result_large_err)]
pub fn solve_path(
    model: &Model,
    opts: &StaticOptions,
    progress: impl FnMut(usize, usize),
) -> Result<StaticSolution, Stopped> {
    let mut steps = Vec::new();
    let (mut path, mut events) = (Vec::new(), Vec::new());
    let r = match opts.path {
        PathMethod::LoadSteps => follow(model, opts, progress, &mut steps, &mut events),
        PathMethod::ArcLength => {
            super::arc::follow(model, opts, progress, &mut steps, &mut path, &mut events)
        }
    };
    let solution = StaticSolution {
        roles: super::roles(model),
        steps,
        path,
        events,
    };
    match r {
        Ok(()) => Ok(solution),
        Err(error) => Err(Stopped {
            error,
            analysis: StaticAnalysis {
                solution,
                linear: Vec::new(),
            },
        }),
    }
}

/// The step result from the assembly `a` at the converged state (x, μ) at load factor t.
#[allow(clippy::too_many_arguments)]
pub(super) fn record(
    model: &Model,
    x: &[f64],
    mu: &[f64],
    a: &Assembled,
    t: f64,
    iterations: usize,
    substeps: usize,
    residual: f64,
) -> StepResult {
    let mut reactions = vec![0.0; model.nx];
    for i in 0..model.nx {
        if model.partition.x[i] != CoordKind::Free {
            reactions[i] = a.balance[i];
        }
    }
    StepResult {
        load_factor: t,
        x: x.to_vec(),
        e: a.e.clone(),
        sigma: a.sigma.clone(),
        reactions,
        energy: a.energy,
        iterations,
        substeps,
        residual,
        multipliers: mu.to_vec(),
        tangent_eigenvalues: None,
    }
}

/// The counts of the options within their limits.
pub(super) fn check_options(opts: &StaticOptions) -> Result<(), SolveError> {
    for (what, found, min, max) in [
        ("steps", opts.steps, 0, MAX_STEPS),
        ("max_iterations", opts.max_iterations, 0, MAX_ITERATIONS),
    ] {
        if !(min..=max).contains(&found) {
            return Err(SolveError::BadOption {
                what,
                min,
                max,
                found,
            });
        }
    }
    Ok(())
}

/// The load steps: every converged step is pushed onto `out` (the unloaded state first); a
/// step that fails ends the path with its error, after the last converged sub-step has been
/// pushed when it lies beyond the last step in `out`.
fn follow(
    model: &Model,
    opts: &StaticOptions,
    mut progress: impl FnMut(usize, usize),
    out: &mut Vec<StepResult>,
    events: &mut Vec<super::PathEvent>,
) -> Result<(), SolveError> {
    check_options(opts)?;
    let su = setup(model);
    if su.nf == 0 && su.nk == 0 {
        return Err(SolveError::NothingToSolve);
    }
    let mut x = model.x0();
    let mut mu = vec![0.0; su.nk];
    let mut kkt = None;
    let steps = opts.steps.max(1);
    out.reserve(steps + 1);
    // step 0: the unloaded state (with prescribed values at t = 0)
    // the assembly at the last converged state, reused by the next Newton solve when the
    // prescribed coordinates leave x unchanged
    let reuse = su.x_targets.is_empty();
    apply_prescribed(model, &su, &mut x, 0.0);
    // Newton, from an exact equilibrium without the tangent when the start is one
    let newton_from =
        |x: &mut [f64], mu: &mut [f64], t: f64, kkt: &mut _, prev| match exact_equilibrium(
            model, &su, x, mu, t, prev,
        ) {
            Ok(state) => Newton::Converged {
                iterations: 0,
                residual: 0.0,
                state,
            },
            Err(prev) => newton(model, &su, opts, x, mu, t, kkt, prev),
        };
    let mut last = match newton_from(&mut x, &mut mu, 0.0, &mut kkt, None) {
        Newton::Converged {
            iterations,
            residual,
            state,
        } => {
            let mut st = record(model, &x, &mu, &state, 0.0, iterations, 1, residual);
            if opts.tangent_eigenvalues {
                st.tangent_eigenvalues = tangent_eigenvalues(model, &su, &st, &state, true);
            }
            let bad = non_finite_parts(&st);
            if !bad.is_empty() {
                return Err(SolveError::NonFinite {
                    step: 0,
                    load_factor: 0.0,
                    what: bad.join(", "),
                    last_good: None,
                });
            }
            out.push(st);
            Some(state)
        }
        Newton::Failed { reason } => {
            return Err(SolveError::NoConvergence {
                step: 0,
                load_factor: 0.0,
                last_converged: 0.0,
                halvings: 0,
                reason,
            })
        }
    };
    progress(0, steps);
    let dt_nominal = 1.0 / steps as f64;
    let mut t = 0.0;
    let mut dt = dt_nominal;
    let mut prev_x: Option<(Vec<f64>, f64)> = None; // previous converged x and its step size
    for step in 1..=steps {
        let t_end = step as f64 * dt_nominal;
        let (mut iterations, mut substeps, mut halvings) = (0, 0, 0);
        let mut residual = 0.0;
        while t < t_end - 1e-14 {
            let t_try = (t + dt).min(t_end);
            let (x_save, mu_save) = (x.clone(), mu.clone());
            // predictor: secant extrapolation of the free coordinates, only when coordinates
            // are prescribed (otherwise the prescribed ones would move alone). Under loads
            // alone the first Newton step from the converged state is the tangent predictor,
            // and extrapolating positions and Euler parameters along straight lines would turn
            // chords and node triads by different angles (third order in the step): on fine
            // meshes the resulting spurious bending (∝ EI/l0³) makes Newton diverge.
            if let (Some((xp, dtp)), false) = (&prev_x, su.x_targets.is_empty()) {
                let s = (t_try - t) / dtp;
                for i in 0..model.nx {
                    if su.unknown[i].get().is_some() {
                        x[i] += s * (x_save[i] - xp[i]);
                    }
                }
            }
            apply_prescribed(model, &su, &mut x, t_try);
            let prev = if reuse { last.take() } else { None };
            let mut result = newton_from(&mut x, &mut mu, t_try, &mut kkt, prev);
            let mut inverted: Option<String> = None;
            if matches!(result, Newton::Converged { .. }) {
                if let Some(name) = inverted_element(model, &x, &x_save) {
                    result = Newton::Failed {
                        reason: format!("element `{name}` inverted"),
                    };
                    inverted = Some(name);
                }
            }
            match result {
                Newton::Converged {
                    iterations: it,
                    residual: r,
                    state: a,
                } => {
                    iterations += it;
                    substeps += 1;
                    residual = r;
                    last = Some(a);
                    prev_x = Some((x_save, t_try - t));
                    t = t_try;
                    dt = (2.0 * dt).min(dt_nominal);
                }
                Newton::Failed { reason } => {
                    x = x_save;
                    mu = mu_save;
                    halvings += 1;
                    dt *= 0.5;
                    if halvings > opts.max_halvings {
                        // the last converged sub-step, when it lies beyond the last full step
                        if substeps > 0 {
                            let a = assemble(model, &su, &x, &mu, t);
                            let mut st =
                                record(model, &x, &mu, &a, t, iterations, substeps, residual);
                            if opts.tangent_eigenvalues {
                                st.tangent_eigenvalues =
                                    tangent_eigenvalues(model, &su, &st, &a, true);
                            }
                            if non_finite_parts(&st).is_empty() {
                                out.push(st);
                            }
                        }
                        if let Some(element) = inverted.take() {
                            return Err(SolveError::Inverted {
                                step,
                                load_factor: t_try,
                                last_converged: t,
                                element,
                            });
                        }
                        return Err(SolveError::NoConvergence {
                            step,
                            load_factor: t_try,
                            last_converged: t,
                            halvings: halvings - 1,
                            reason,
                        });
                    }
                }
            }
        }
        let a = match last.take() {
            Some(a) => a,
            None => Box::new(assemble(model, &su, &x, &mu, t_end)),
        };
        let mut st = record(model, &x, &mu, &a, t_end, iterations, substeps, residual);
        if opts.tangent_eigenvalues {
            st.tangent_eigenvalues = tangent_eigenvalues(model, &su, &st, &a, true);
        }
        let bad = non_finite_parts(&st);
        if !bad.is_empty() {
            return Err(SolveError::NonFinite {
                step,
                load_factor: t_end,
                what: bad.join(", "),
                last_good: out.last().map(|s: &StepResult| s.load_factor),
            });
        }
        if let Some(e) = jump(&su, out, &st, step) {
            events.push(e);
        }
        out.push(st);
        last = Some(a);
        progress(step, steps);
    }
    Ok(())
}

/// Growth of the largest coordinate increment from one load step to the next above which a
/// step counts as a jump ([`super::PathEvent::Jump`]).
const JUMP_GROWTH: f64 = 5.0;

/// A jump of the load-step path at `step` (the state `st`) after the states `out`: the largest
/// increment of an unknown coordinate grew more than [`JUMP_GROWTH`]-fold over that of the step
/// before, and is at least 1e-3 of the model size.
fn jump(
    su: &super::Setup,
    out: &[StepResult],
    st: &StepResult,
    step: usize,
) -> Option<super::PathEvent> {
    let [.., a, b] = out else { return None };
    let inc = |p: &StepResult, q: &StepResult| {
        su.unknown
            .iter()
            .enumerate()
            .filter(|(_, u)| u.get().is_some())
            .map(|(i, _)| (q.x[i] - p.x[i]).abs())
            .fold(0.0, f64::max)
    };
    let (before, now) = (inc(a, b), inc(b, st));
    (now > 1e-3 * su.l_ref && now > JUMP_GROWTH * before).then(|| super::PathEvent::Jump {
        step,
        from: b.load_factor,
        load_factor: st.load_factor,
        growth: if before > 0.0 {
            now / before
        } else {
            f64::INFINITY
        },
    })
}
