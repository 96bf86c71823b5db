//! The linearised results of a static analysis at every step ([`at_step`], [`analyse`]; the
//! types are `crate::statics::linear`'s).

use super::buckling::{buckling, stiffness_condition, unstable_directions, ILL_CONDITIONED};
use super::compliance::compliance;
use super::{check_dense_size, Tangent};
use crate::model::Model;
use crate::statics::linear::{LinearFailure, LinearRequest, StepLinear};
use crate::statics::{
    solve_path, StaticAnalysis, StaticOptions, StaticSolution, StepResult, Stopped,
};
use rayon::prelude::*;

/// The linearised results `req` at a converged step: one linearisation, then compliance,
/// buckling and stability from it.
pub fn at_step(model: &Model, step: &StepResult, req: &LinearRequest) -> StepLinear {
    let mut out = StepLinear::default();
    if req.is_empty() {
        return out;
    }
    if let Err(e) = check_dense_size(model, req.max_dense_bytes) {
        out.failures.push(LinearFailure::TooLarge(e));
        return out;
    }
    let t = Tangent::new(model, step);
    if let Some(condition) = stiffness_condition(&t).filter(|&c| c > ILL_CONDITIONED) {
        out.failures.push(LinearFailure::IllConditioned {
            condition,
            digits: condition.log10().round().clamp(0.0, 99.0) as u32,
        });
    }
    for &id in &req.compliance {
        let node = model
            .nodes
            .get(id)
            .map_or_else(|| format!("#{id}"), |n| n.name.clone());
        match compliance(&t, id) {
            Ok(c) => out.compliance.push((node, c)),
            Err(error) => out.failures.push(LinearFailure::Compliance { node, error }),
        }
    }
    if req.buckling > 0 {
        match buckling(&t, req.buckling) {
            Ok(b) => out.buckling = Some(b),
            Err(e) => out.failures.push(LinearFailure::Buckling(e)),
        }
        match unstable_directions(&t) {
            Ok(n) => out.unstable_directions = Some(n),
            Err(e) => out.failures.push(LinearFailure::Stability(e)),
        }
    }
    out
}

/// The static analysis of a model: [`solve_path`] over the load steps, then the linearised
/// results `req` (compliance, buckling, stability) at every step, in parallel over the steps.
/// A path that stops part-way gives them at every converged step, with the error.
#[allow(clippy::result_large_err)]
pub fn analyse(
    model: &Model,
    opts: &StaticOptions,
    req: &LinearRequest,
    progress: impl FnMut(usize, usize),
) -> Result<StaticAnalysis, Stopped> {
    let linearise = |sol: &StaticSolution| -> Vec<StepLinear> {
        sol.steps
            .par_iter()
            .map(|st| at_step(model, st, req))
            .collect()
    };
    match solve_path(model, opts, progress) {
        Ok(solution) => Ok(StaticAnalysis {
            linear: linearise(&solution),
            solution,
        }),
        Err(mut s) => {
            s.analysis.linear = linearise(&s.analysis.solution);
            Err(s)
        }
    }
}
