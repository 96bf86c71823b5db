//! The sparse state space: the lowest modes by shift-invert Lanczos ([`crate::dynamics::sparse`])
//! and static solves on the same sparse matrix, with force, moment and prescribed-motion inputs
//! and every output of the dense path, reactions included, for models of any size.
//!
//! Held node coordinates that a motion moves or whose reaction is measured are freed in a copy
//! of the model and held again by constraint rows added to the sparse saddle-point system
//! [K, Gᵀ; G, 0]. For every such held quantity a (a held coordinate, or a rigid or prescribed
//! deformation) one static solve with the constraint values c_a (the unit enforced motion) and
//! no load gives its quasi-static field s_a (G s_a = c_a, K s_a + Gᵀ μ_a = 0) and the
//! multipliers μ_a. Then, as in the dense path (module docs of `state_space`):
//!
//! - a motion input m drives the modes through the force −M s_m, and an output row w moves by
//!   w·s_m per unit enforced displacement (its quasi-static gain);
//! - a reaction a is δσ_a = s_a·f − (K s_a)·δx − (M s_a)·δẍ with the lift t_a = s_a, which is
//!   K-orthogonal to the constrained space: (K s_a)·δx = −μ_a·(G δx) = −Σ_m (μ_a·c_m) u_m, so
//!   the stiffness term has no modal part, only the quasi-static gain −μ_a·c_m.
//!
//! With all modes kept, or with the static correction, this equals the dense result for an
//! undamped model (any lift gives the same reaction there); the damping force of a modal
//! damping on a held quantity depends on the lift, so with ζ > 0 the reactions of the two paths
//! differ by O(ζ).

use super::build::{assemble, held_input_warnings, Parts};
use super::lift::{freed_model, output_row, reactions, unit_vector, Target};
use super::{Input, Motion, Output, OutputKind, StateSpace, StateSpaceError, StateSpaceOptions};
use crate::dynamics::sparse::sparse_modes_held;
use crate::dynamics::EigenSolver;
use crate::linearized::Tangent;
use crate::model::{CoordKind, Model};
use crate::statics::StepResult;
use faer::Mat;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The sparse state space of the lowest `count` modes (module docs). The static feedthrough of
/// displacement outputs is the exact static response minus that of the kept modes,
/// Cx K⁻¹ f − Σ (w·φ)(φ·f)/ω², from one sparse factorisation of the statics Newton matrix:
/// with `static_correction`, and always when the model has massless directions (their
/// instantaneous response; the sparse path cannot separate it from the dropped modes').
pub(super) fn build_sparse(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    count: usize,
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    let rx = reactions(model, outputs)?;
    // motions first, then node reactions, then deformation reactions: all held quantities
    let mut held: Vec<Motion> = motions.to_vec();
    held.extend(&rx.nodes);
    let (free, targets) = freed_model(model, step, &held)?;
    let mut targets = targets;
    targets.extend(rx.deformations.iter().map(|&(_, e)| Target::Deformation(e)));
    // the coordinates held again by added rows (each once), and their rows as vectors in x
    let mut freed: Vec<usize> = Vec::new();
    for t in &targets {
        if let Target::Node { own, .. } = t {
            for &j in own {
                if model.partition.x[j] != CoordKind::Free && !freed.contains(&j) {
                    freed.push(j);
                }
            }
        }
    }
    let rows: Vec<Vec<f64>> = freed
        .iter()
        .map(|&j| {
            let mut e = vec![0.0; model.nx];
            e[j] = 1.0;
            e
        })
        .collect();
    let (sm, problem) = sparse_modes_held(&Tangent::new(&free, step), count, &rows)?;
    let nc = problem.n_coords();
    // constraint values c_a of every held quantity (rows of the saddle system)
    let first = problem.first_added_row();
    let mut values: Vec<Vec<(usize, f64)>> = Vec::with_capacity(targets.len());
    for (k, t) in targets.iter().enumerate() {
        values.push(match t {
            Target::Node { t0, own } => own
                .iter()
                .filter_map(|j| {
                    freed
                        .iter()
                        .position(|f| f == j)
                        .map(|k| (first + k, t0[*j]))
                })
                .collect(),
            Target::Deformation(e) => {
                let Some(r) = problem.deformation_row(*e) else {
                    return Err(match held.get(k) {
                        Some(mo) => StateSpaceError::MotionConstrained {
                            input: mo.name(model),
                        },
                        None => StateSpaceError::ReactionConstrained {
                            output: rx.deformations[k - held.len()].0.clone(),
                        },
                    });
                };
                vec![(r, 1.0)]
            }
        });
    }
    let fields = problem.held_responses(&free, step, &values)?;
    let mut warnings = Vec::new();
    let available = sm.ndof - sm.massless;
    let n = sm.eigenvalues.len();
    if count > n {
        warnings.push(format!(
            "{count} modes asked for: the model has {n} modes that carry mass; all are kept"
        ));
    }
    held_input_warnings(model, inputs, &mut warnings);
    let (nf, nm) = (inputs.len(), motions.len());
    let ni = nf + nm;
    // input loads in x: unit forces and moments, then −M s_m of the motions
    let mut loads: Vec<Vec<f64>> = inputs
        .iter()
        .map(|i| unit_vector(model, step, i.node, i.dof))
        .collect::<Result<_, _>>()?;
    let s_of = |k: usize| fields[k].0.as_slice();
    let refs: Vec<&[f64]> = (0..fields.len()).map(s_of).collect();
    let ms = crate::assembly::mass::mass_times(model, &step.x, &refs);
    loads.extend(ms[..nm].iter().map(|v| v.iter().map(|a| -a).collect()));
    // internal rows: one per output, two per reaction (−μ_a·c_m gains, then M s_a)
    let n_node = rx.nodes.len();
    let mut rows_w: Vec<Option<Vec<f64>>> = Vec::new();
    let mut kinds = Vec::new();
    let mut row_out = Vec::new();
    let mut reaction_rows: Vec<Option<usize>> = Vec::new();
    let mut combine = Vec::with_capacity(outputs.len());
    let mut feed = Mat::zeros(outputs.len(), nf);
    for (o, out) in outputs.iter().enumerate() {
        let reaction = match (rx.deformation_of[o], rx.node_of[o]) {
            (Some(q), _) => Some((nm + n_node + q, -1.0)),
            (None, Some(q)) => Some((nm + q, 1.0)),
            (None, None) => None,
        };
        match reaction {
            None => {
                combine.push(vec![(rows_w.len(), 1.0)]);
                rows_w.push(Some(output_row(model, step, out)?));
                kinds.push(out.kind);
                reaction_rows.push(None);
                row_out.push(o);
            }
            Some((a, sign)) => {
                combine.push(vec![(rows_w.len(), sign), (rows_w.len() + 1, sign)]);
                rows_w.push(None);
                kinds.push(OutputKind::Disp);
                reaction_rows.push(Some(a));
                rows_w.push(Some(ms[a].clone()));
                kinds.push(OutputKind::Acc);
                reaction_rows.push(None);
                row_out.extend([o, o]);
                for (j, f) in loads[..nf].iter().enumerate() {
                    feed[(o, j)] = -sign * dot(&fields[a].0, f);
                }
            }
        }
    }
    let nr = rows_w.len();
    let modal_b = Mat::from_fn(n, ni, |k, j| dot(&sm.shapes[k], &loads[j]));
    let modal_c = Mat::from_fn(nr, n, |o, k| {
        rows_w[o].as_ref().map_or(0.0, |w| dot(w, &sm.shapes[k]))
    });
    let motion_gain = Mat::from_fn(nr, nm, |o, m| match (&rows_w[o], reaction_rows[o]) {
        (Some(w), _) => dot(w, &fields[m].0),
        (None, Some(a)) => -values[m]
            .iter()
            .map(|&(r, v)| fields[a].1[r - nc] * v)
            .sum::<f64>(),
        (None, None) => 0.0,
    });
    for (o, out) in outputs.iter().enumerate() {
        let moved = (0..nm).any(|m| {
            (0..nr).any(|r| {
                row_out[r] == o && kinds[r] == OutputKind::Disp && motion_gain[(r, m)] != 0.0
            })
        });
        if super::lift::held_output(model, out) && !moved {
            warnings.push(format!(
                "output {} is a held direction (support or prescribed input): it is zero",
                out.name(model)
            ));
        }
    }
    let mut d_static = Mat::zeros(nr, ni);
    let residual = opts.static_correction || sm.massless > 0;
    if residual
        && kinds
            .iter()
            .zip(&rows_w)
            .any(|(k, w)| *k == OutputKind::Disp && w.is_some())
    {
        let dx = problem.static_responses(&free, step, &loads)?;
        for o in 0..nr {
            let Some(w) = &rows_w[o] else { continue };
            if kinds[o] != OutputKind::Disp {
                continue;
            }
            for j in 0..ni {
                let modal: f64 = (0..n)
                    .map(|k| modal_c[(o, k)] * modal_b[(k, j)] / sm.eigenvalues[k])
                    .sum();
                d_static[(o, j)] = dot(w, &dx[j]) - modal;
            }
        }
        if sm.massless > 0 && !opts.static_correction {
            warnings.push(format!(
                "the model has {} direction(s) without inertia: D carries their static response together with that of the dropped modes (as the static correction does), which the sparse path cannot separate",
                sm.massless
            ));
        }
    }
    if sm.massless > 0 && kinds.iter().any(|k| *k != OutputKind::Disp) {
        warnings.push(
            "velocity and acceleration outputs miss the instantaneous response of the directions without inertia (proportional to the input's derivative)".into(),
        );
    }
    Ok(assemble(
        inputs,
        motions,
        outputs,
        opts,
        Parts {
            lam: sm.eigenvalues,
            modal_b,
            modal_c,
            d_static,
            motion_gain,
            warnings,
            ndof: sm.ndof,
            massless: sm.massless,
            available,
            solver: EigenSolver::Sparse,
            kinds,
            combine,
            feed,
        },
    ))
}
