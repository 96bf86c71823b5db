//! Building A, B, C, D: the dense path from the reduced matrices (all modes, massless
//! directions condensed, motion inputs and reactions), the sparse path from the lowest modes,
//! and the assembly of both from their modal parts.

use super::lift::{held, held_output, motion_loads, output_row, unit_vector, ReactionRows};
use super::{
    check_options, Input, Motion, Output, OutputKind, StateSpace, StateSpaceError,
    StateSpaceOptions,
};
use crate::dynamics::{EigenSolver, Reduced};
use crate::model::Model;
use crate::statics::StepResult;
use faer::Mat;

/// The model-specific parts of a state-space model, from which [`assemble`] builds A, B, C, D.
pub(super) struct Parts {
    /// ω² of the kept modes.
    pub(super) lam: Vec<f64>,
    /// Φᵀ Bq (kept modes × inputs).
    pub(super) modal_b: Mat<f64>,
    /// Cx Φ (outputs × kept modes).
    pub(super) modal_c: Mat<f64>,
    /// Static feedthrough of displacement outputs (outputs × inputs).
    pub(super) d_static: Mat<f64>,
    /// Quasi-static gains of the motion inputs (outputs × motions).
    pub(super) motion_gain: Mat<f64>,
    pub(super) warnings: Vec<String>,
    pub(super) ndof: usize,
    pub(super) massless: usize,
    pub(super) available: usize,
    pub(super) solver: EigenSolver,
    /// Kind of every internal row of `modal_c`, `d_static`, `motion_gain`.
    pub(super) kinds: Vec<OutputKind>,
    /// Every output as a signed sum of internal rows, plus a direct feedthrough of the force
    /// inputs (outputs × force inputs): a node or element output is one row; a reaction is
    /// t·f − (K t)·δx − (M t)·δẍ.
    pub(super) combine: Combine,
    pub(super) feed: Mat<f64>,
}

/// Every output as a signed sum of internal rows (see [`Parts::combine`]).
pub(super) type Combine = Vec<Vec<(usize, f64)>>;

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
    // constraint reactions: of rigid or prescribed deformations, and at held node
    // coordinates (the rows of a unit motion of the coordinate)
    let super::lift::Reactions {
        deformations: reactions,
        deformation_of: reaction_of,
        nodes: node_reactions,
        node_of: node_reaction_of,
    } = super::lift::reactions(model, outputs)?;
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
