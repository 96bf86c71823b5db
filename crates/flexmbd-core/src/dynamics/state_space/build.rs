//! Building A, B, C, D: the dense path from the reduced matrices (all modes, massless
//! directions condensed, motion inputs and reactions), the sparse path from the lowest modes,
//! and the assembly of both from their modal parts.

use super::lift::{held, held_output, motion_loads, output_row, unit_vector, ReactionRows};
use super::{
    check_options, Input, Motion, Output, OutputKind, Probe, StateSpace, StateSpaceError,
    StateSpaceOptions,
};
use crate::dynamics::{EigenSolver, Reduced};
use crate::model::{CoordKind, Model};
use crate::statics::StepResult;
use faer::Mat;

/// The model-specific parts of a state-space model, from which [`assemble`] builds A, B, C, D.
pub(super) struct Parts {
    /// ω² of the kept modes.
    lam: Vec<f64>,
    /// Φᵀ Bq (kept modes × inputs).
    modal_b: Mat<f64>,
    /// Cx Φ (outputs × kept modes).
    modal_c: Mat<f64>,
    /// Static feedthrough of displacement outputs (outputs × inputs).
    d_static: Mat<f64>,
    /// Quasi-static gains of the motion inputs (outputs × motions).
    motion_gain: Mat<f64>,
    warnings: Vec<String>,
    ndof: usize,
    massless: usize,
    available: usize,
    solver: EigenSolver,
    /// Kind of every internal row of `modal_c`, `d_static`, `motion_gain`.
    kinds: Vec<OutputKind>,
    /// Every output as a signed sum of internal rows, plus a direct feedthrough of the force
    /// inputs (outputs × force inputs): a node or element output is one row; a reaction is
    /// t·f − (K t)·δx − (M t)·δẍ.
    combine: Combine,
    feed: Mat<f64>,
}

/// Every output as a signed sum of internal rows (see [`Parts::combine`]).
pub(super) type Combine = Vec<Vec<(usize, f64)>>;

/// One output per internal row, no feedthrough.
pub(super) fn identity_rows(
    outputs: &[Output],
    n_force: usize,
) -> (Vec<OutputKind>, Combine, Mat<f64>) {
    (
        outputs.iter().map(|o| o.kind).collect(),
        (0..outputs.len()).map(|o| vec![(o, 1.0)]).collect(),
        Mat::zeros(outputs.len(), n_force),
    )
}

/// Warnings for inputs on held directions.
pub(super) fn held_input_warnings(model: &Model, inputs: &[Input], warnings: &mut Vec<String>) {
    for inp in inputs {
        if held(model, inp.node, inp.dof) {
            warnings.push(format!(
                "input {} acts on a held direction (support or prescribed input): it has no effect",
                inp.name(model)
            ));
        }
    }
}

/// The sparse state space (module docs): the lowest `count` modes by shift-invert Lanczos
/// (mass-normalised shapes φ in x), Φᵀ Bq = φᵀ f and Cx Φ = w·φ directly in x. The static
/// feedthrough of displacement outputs is the exact static response minus that of the kept
/// modes, Cx K⁻¹ f − Σ (w·φ)(φ·f)/ω², from one sparse factorisation of the statics Newton
/// matrix: with `static_correction`, and always when the model has massless directions
/// (their instantaneous response; the sparse path cannot separate it from the dropped modes').
pub(super) fn build_sparse(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    outputs: &[Output],
    count: usize,
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    let (sm, problem) = crate::dynamics::sparse::sparse_modes_kept(model, step, count)?;
    let mut warnings = Vec::new();
    let available = sm.ndof - sm.massless;
    let n = sm.eigenvalues.len();
    if count > n {
        warnings.push(format!(
            "{count} modes asked for: the model has {n} modes that carry mass; all are kept"
        ));
    }
    held_input_warnings(model, inputs, &mut warnings);
    for out in outputs {
        if held_output(model, out) {
            warnings.push(format!(
                "output {} is a held direction (support or prescribed input): it is zero",
                out.name(model)
            ));
        }
    }
    let f: Vec<Vec<f64>> = inputs
        .iter()
        .map(|i| unit_vector(model, step, i.node, i.dof))
        .collect::<Result<_, _>>()?;
    let w: Vec<Vec<f64>> = outputs
        .iter()
        .map(|o| output_row(model, step, o))
        .collect::<Result<_, _>>()?;
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let modal_b = Mat::from_fn(n, inputs.len(), |k, j| dot(&sm.shapes[k], &f[j]));
    let modal_c = Mat::from_fn(outputs.len(), n, |o, k| dot(&w[o], &sm.shapes[k]));
    let (no, ni) = (outputs.len(), inputs.len());
    let mut d_static = Mat::zeros(no, ni);
    let residual = opts.static_correction || sm.massless > 0;
    if residual && outputs.iter().any(|o| o.kind == OutputKind::Disp) {
        let dx = problem.static_responses(model, step, &f)?;
        for (o, out) in outputs.iter().enumerate() {
            if out.kind != OutputKind::Disp {
                continue;
            }
            for j in 0..ni {
                let modal: f64 = (0..n)
                    .map(|k| modal_c[(o, k)] * modal_b[(k, j)] / sm.eigenvalues[k])
                    .sum();
                d_static[(o, j)] = dot(&w[o], &dx[j]) - modal;
            }
        }
        if sm.massless > 0 && !opts.static_correction {
            warnings.push(format!(
                "the model has {} direction(s) without inertia: D carries their static response together with that of the dropped modes (as the static correction does), which the sparse path cannot separate",
                sm.massless
            ));
        }
    }
    if sm.massless > 0 && outputs.iter().any(|o| o.kind != OutputKind::Disp) {
        warnings.push(
            "velocity and acceleration outputs miss the instantaneous response of the directions without inertia (proportional to the input's derivative)".into(),
        );
    }
    let (kinds, combine, feed) = identity_rows(outputs, inputs.len());
    Ok(assemble(
        inputs,
        &[],
        outputs,
        opts,
        Parts {
            lam: sm.eigenvalues,
            modal_b,
            modal_c,
            d_static,
            motion_gain: Mat::zeros(no, 0),
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

pub(super) fn build(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    check_options(inputs, motions, outputs, opts)?;
    let mut warnings = Vec::new();
    let (lam, phi) = red.eigen()?;
    let available = lam.len();
    let n = opts.modes.unwrap_or(available).min(available);
    if let Some(k) = opts.modes {
        if k > available {
            warnings.push(format!(
                "{k} modes asked for: the model has {available} modes that carry mass; all are kept"
            ));
        }
    }
    let ndof = red.ndof();
    // force outputs of rigid or prescribed deformations: constraint reactions
    let mut reactions = Vec::new();
    let mut reaction_of = vec![None; outputs.len()];
    for (o, out) in outputs.iter().enumerate() {
        if let Probe::Force { element, mode } = out.probe {
            if out.is_reaction(model) {
                if out.kind != OutputKind::Disp {
                    return Err(StateSpaceError::ReactionRate {
                        output: out.name(model),
                    });
                }
                reaction_of[o] = Some(reactions.len());
                reactions.push((out.name(model), model.elements[element].ie + mode));
            }
        }
    }
    // reactions at held node coordinates: the rows of a unit motion of the coordinate
    let mut node_reactions: Vec<Motion> = Vec::new();
    let mut node_reaction_of = vec![None; outputs.len()];
    for (o, out) in outputs.iter().enumerate() {
        if let Probe::Reaction { node, dof } = out.probe {
            if out.kind != OutputKind::Disp {
                return Err(StateSpaceError::ReactionRate {
                    output: out.name(model),
                });
            }
            let n = &model.nodes[node];
            let Some(i) = n.x_index(dof) else {
                return Err(StateSpaceError::NoRotation {
                    node: n.name.clone(),
                });
            };
            if model.partition.x[i] == CoordKind::Free {
                return Err(StateSpaceError::ReactionNotHeld {
                    output: out.name(model),
                });
            }
            node_reaction_of[o] = Some(node_reactions.len());
            node_reactions.push(Motion::Node { node, dof });
        }
    }
    let all_motions: Vec<Motion> = motions.iter().chain(&node_reactions).copied().collect();
    let (mut mloads, rrows) = motion_loads(model, step, red, &all_motions, &reactions)?;
    let nr_rows: Vec<ReactionRows> = mloads
        .split_off(motions.len())
        .into_iter()
        .map(|ml| ml.rows)
        .collect();
    let (nf, nm) = (inputs.len(), motions.len());
    let ni = nf + nm;
    // quasi-static responses ψ = −K0⁻¹ Zᵀ K t_m (ndof × motions), dense LU of K0
    let mut psi = Mat::<f64>::zeros(ndof, nm);
    if nm > 0 {
        let kt = Mat::from_fn(ndof, nm, |r, j| mloads[j].k[r]);
        let lu = red.k0.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &kt);
        let res = &red.k0 * &sol - &kt;
        for j in 0..nm {
            let sn = sol.col(j).norm_max();
            let ok = sn.is_finite()
                && res.col(j).norm_max() <= 1e-8 * (red.k0.norm_max() * sn + kt.col(j).norm_max());
            if !ok {
                return Err(StateSpaceError::MotionSingular {
                    input: motions[j].name(model),
                });
            }
            for r in 0..ndof {
                psi[(r, j)] = -sol[(r, j)];
            }
        }
    }
    let m0psi = &red.m0 * &psi;
    // Bq = Zᵀ f (ndof × inputs), Cx = rows of the outputs in q (outputs × ndof)
    let mut bq = Mat::zeros(ndof, ni);
    for j in 0..nm {
        // r is driven by −(M0 ψ + Zᵀ M t_m) ü
        for r in 0..ndof {
            bq[(r, nf + j)] = -(m0psi[(r, j)] + mloads[j].m[r]);
        }
    }
    held_input_warnings(model, inputs, &mut warnings);
    let mut forces = Vec::with_capacity(nf);
    for (j, inp) in inputs.iter().enumerate() {
        let f = unit_vector(model, step, inp.node, inp.dof)?;
        for r in 0..ndof {
            bq[(r, j)] = (0..model.nx).map(|i| red.z[(i, r)] * f[i]).sum::<f64>();
        }
        forces.push(f);
    }
    // internal rows: one per output, two per reaction, δσ = t·f − (K t)·δx − (M t)·δẍ
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let (mut row_w, mut kinds, mut row_out) = (Vec::new(), Vec::new(), Vec::new());
    let mut combine = Vec::with_capacity(outputs.len());
    let mut feed = Mat::zeros(outputs.len(), nf);
    for (o, out) in outputs.iter().enumerate() {
        // a deformation's reaction: t·f − (K t)·δx − (M t)·δẍ; a support's: the negative
        let reaction = match (reaction_of[o], node_reaction_of[o]) {
            (Some(q), _) => Some((&rrows[q], -1.0)),
            (None, Some(q)) => Some((&nr_rows[q], 1.0)),
            (None, None) => None,
        };
        match reaction {
            None => {
                combine.push(vec![(row_w.len(), 1.0)]);
                row_w.push(output_row(model, step, out)?);
                kinds.push(out.kind);
                row_out.push(o);
            }
            Some((rr, sign)) => {
                combine.push(vec![(row_w.len(), sign), (row_w.len() + 1, sign)]);
                row_w.push(rr.kt.clone());
                kinds.push(OutputKind::Disp);
                row_w.push(rr.mt.clone());
                kinds.push(OutputKind::Acc);
                row_out.extend([o, o]);
                for (j, f) in forces.iter().enumerate() {
                    feed[(o, j)] = -sign * dot(&rr.t, f);
                }
            }
        }
    }
    let no = row_w.len();
    let mut cx = Mat::zeros(no, ndof);
    let mut motion_gain = Mat::zeros(no, nm);
    for (o, w) in row_w.iter().enumerate() {
        let out = &outputs[row_out[o]];
        for (j, ml) in mloads.iter().enumerate() {
            let direct: f64 = (0..model.nx).map(|i| w[i] * ml.t[i]).sum();
            let quasi: f64 = (0..ndof)
                .map(|r| (0..model.nx).map(|i| w[i] * red.z[(i, r)]).sum::<f64>() * psi[(r, j)])
                .sum();
            motion_gain[(o, j)] = direct + quasi;
        }
        if held_output(model, out)
            && !mloads
                .iter()
                .any(|ml| (0..model.nx).map(|i| w[i] * ml.t[i]).sum::<f64>() != 0.0)
        {
            warnings.push(format!(
                "output {} is a held direction (support or prescribed input): it is zero",
                out.name(model)
            ));
        }
        for r in 0..ndof {
            cx[(o, r)] = (0..model.nx).map(|i| w[i] * red.z[(i, r)]).sum::<f64>();
        }
    }
    let phik = Mat::from_fn(ndof, n, |i, k| phi[(i, k)]);
    let modal_b = phik.transpose() * &bq; // n × ni
    let modal_c = &cx * &phik; // no × n
                               // static flexibility not carried by the kept modes
    let massless_flex = red.massless_flexibility();
    let d_massless = &cx * &massless_flex * &bq; // no × ni
    let mut d_residual = Mat::<f64>::zeros(no, ni);
    if opts.static_correction && n < available {
        let phid = Mat::from_fn(ndof, available - n, |i, k| phi[(i, n + k)] / lam[n + k]);
        let phidt = Mat::from_fn(ndof, available - n, |i, k| phi[(i, n + k)]);
        d_residual = &cx * &phid * (phidt.transpose() * &bq);
    }
    let mut d_static = Mat::zeros(no, ni);
    let fmax = massless_flex.norm_max();
    for (o, kind) in kinds.iter().enumerate() {
        let out = &outputs[row_out[o]];
        let co = cx.row(o).norm_l2();
        for j in 0..ni {
            // below this the massless response is round-off
            let dm = if d_massless[(o, j)].abs() > 1e-9 * co * bq.col(j).norm_l2() * fmax {
                d_massless[(o, j)]
            } else {
                0.0
            };
            if *kind == OutputKind::Disp {
                d_static[(o, j)] = dm + d_residual[(o, j)];
            } else if dm != 0.0 {
                warnings.push(format!(
                    "{} responds instantaneously to {} through coordinates without inertia; that part (proportional to the input's derivative) is not in the model",
                    out.name(model),
                    input_name(model, inputs, motions, j)
                ));
            }
        }
    }
    Ok(assemble(
        inputs,
        motions,
        outputs,
        opts,
        Parts {
            lam: lam[..n].to_vec(),
            modal_b,
            modal_c,
            d_static,
            motion_gain,
            warnings,
            ndof,
            massless: red.massless(),
            available,
            solver: EigenSolver::Dense,
            kinds,
            combine,
            feed,
        },
    ))
}

/// A, B, C, D from the modal parts: state (η, η̇, then (u, u̇) of every motion).
pub(super) fn assemble(
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
    parts: Parts,
) -> StateSpace {
    let Parts {
        lam,
        modal_b,
        modal_c,
        d_static,
        motion_gain,
        warnings,
        ndof,
        massless,
        available,
        solver,
        kinds,
        combine,
        feed,
    } = parts;
    let zeta = opts.damping;
    let n = lam.len();
    let (nf, nm, nr, ni) = (
        inputs.len(),
        motions.len(),
        kinds.len(),
        inputs.len() + motions.len(),
    );
    let omega: Vec<f64> = lam.iter().map(|l| l.abs().sqrt()).collect();
    let ns = 2 * n + 2 * nm;
    let mut a = Mat::zeros(ns, ns);
    for k in 0..n {
        a[(k, n + k)] = 1.0;
        a[(n + k, k)] = -lam[k];
        a[(n + k, n + k)] = -2.0 * zeta * omega[k];
    }
    let mut b = Mat::zeros(ns, ni);
    for k in 0..n {
        for j in 0..ni {
            b[(n + k, j)] = modal_b[(k, j)];
        }
    }
    for j in 0..nm {
        a[(2 * n + 2 * j, 2 * n + 2 * j + 1)] = 1.0;
        b[(2 * n + 2 * j + 1, nf + j)] = 1.0;
    }
    // the internal rows
    let mut c_rows = Mat::zeros(nr, ns);
    let mut d_rows = Mat::zeros(nr, ni);
    for (o, kind) in kinds.iter().enumerate() {
        for k in 0..n {
            let ck = modal_c[(o, k)];
            match kind {
                OutputKind::Disp => c_rows[(o, k)] = ck,
                OutputKind::Vel => c_rows[(o, n + k)] = ck,
                OutputKind::Acc => {
                    c_rows[(o, k)] = -ck * lam[k];
                    c_rows[(o, n + k)] = -ck * 2.0 * zeta * omega[k];
                }
            }
        }
        for j in 0..ni {
            d_rows[(o, j)] = match kind {
                OutputKind::Disp => d_static[(o, j)],
                OutputKind::Vel => 0.0,
                OutputKind::Acc => (0..n).map(|k| modal_c[(o, k)] * modal_b[(k, j)]).sum(),
            };
        }
        for j in 0..nm {
            let g = motion_gain[(o, j)];
            match kind {
                OutputKind::Disp => c_rows[(o, 2 * n + 2 * j)] = g,
                OutputKind::Vel => c_rows[(o, 2 * n + 2 * j + 1)] = g,
                OutputKind::Acc => d_rows[(o, nf + j)] += g,
            }
        }
    }
    // the outputs: signed sums of rows; the quasi-static motion gain counts the value rows
    let no = outputs.len();
    let mut c = Mat::zeros(no, ns);
    let mut d = Mat::zeros(no, ni);
    let mut gain = Mat::zeros(no, nm);
    for (o, terms) in combine.iter().enumerate() {
        for &(r, w) in terms {
            for q in 0..ns {
                c[(o, q)] += w * c_rows[(r, q)];
            }
            for j in 0..ni {
                d[(o, j)] += w * d_rows[(r, j)];
            }
            if kinds[r] == OutputKind::Disp {
                for j in 0..nm {
                    gain[(o, j)] += w * motion_gain[(r, j)];
                }
            }
        }
        for j in 0..nf {
            d[(o, j)] += feed[(o, j)];
        }
    }
    StateSpace {
        a,
        b,
        c,
        d,
        inputs: inputs.to_vec(),
        motions: motions.to_vec(),
        outputs: outputs.to_vec(),
        eigenvalues: lam,
        damping: zeta,
        ndof,
        massless,
        available_modes: available,
        static_correction: opts.static_correction,
        warnings,
        solver,
        motion_gain: gain,
    }
}

/// Name of input column j (forces first, then motions).
pub(super) fn input_name(model: &Model, inputs: &[Input], motions: &[Motion], j: usize) -> String {
    match inputs.get(j) {
        Some(i) => i.name(model),
        None => motions[j - inputs.len()].name(model),
    }
}
