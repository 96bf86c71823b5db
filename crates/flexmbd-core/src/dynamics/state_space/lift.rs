//! The directions of prescribed motions and constraint reactions in x: the unit direction
//! t_m of an enforced motion lifted onto the rigid and prescribed deformations, its loads
//! Zᵀ K t_m and Zᵀ M t_m, the rows of reactions, and the rows w of node and element outputs.

use super::{Motion, Output, OutputKind, Probe, StateSpaceError};
use crate::dynamics::Reduced;
use crate::elements::ElementKind;
use crate::linearized::Tangent;
use crate::math::lambda_bar;
use crate::model::{CoordKind, Dof, Model};
use crate::statics::StepResult;
use faer::Mat;

/// The generalised loads of a unit enforced motion: k = Zᵀ K t_m, m = Zᵀ M t_m, and the lifted
/// direction t_m in x.
pub(super) struct MotionLoad {
    pub(super) t: Vec<f64>,
    pub(super) k: Vec<f64>,
    pub(super) m: Vec<f64>,
    /// K t_m and M t_m in x (for a reaction at the coordinate).
    pub(super) rows: ReactionRows,
}

/// The rows of a constraint reaction δσ_a = t·f − (K t)·δx − (M t)·δẍ, with t the lifted
/// direction G t = e_a through the free coordinates (module docs).
pub(super) struct ReactionRows {
    pub(super) t: Vec<f64>,
    pub(super) kt: Vec<f64>,
    pub(super) mt: Vec<f64>,
}

/// Loads of unit enforced motions. K on the moved coordinates comes from a linearisation of a
/// copy of the model in which they are free: a translation alone, for a rotation all of
/// λ1..λ3 of the node. This keeps the constraints and multipliers: λ0 is always free, so every
/// rotational node already has its normalisation and multiplier, whose term 2μ I acts only on
/// the node's own (held) rows, which Zᵀ does not see. The direction (e_i, or ½ Λ̄ᵀ e_k on λ)
/// is lifted onto the rigid/prescribed deformation constraints by the least-squares particular
/// solution t_m = t⁰_m + T w, G T w = −G t⁰_m.
pub(super) fn motion_loads(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    motions: &[Motion],
    reactions: &[(String, usize)],
) -> Result<(Vec<MotionLoad>, Vec<ReactionRows>), StateSpaceError> {
    if motions.is_empty() && reactions.is_empty() {
        return Ok((Vec::new(), Vec::new()));
    }
    let (free, targets) = freed_model(model, step, motions)?;
    let role = crate::statics::roles(model);
    // rigid/prescribed deformation constraints (rows of G)
    let rows: Vec<usize> = (0..model.ne)
        .filter(|&i| role[i] != crate::statics::Role::Flexible)
        .collect();
    // unit directions t⁰_m in x before the lifting, and the row of G the motion drives
    let dirs: Vec<(Vec<f64>, Option<usize>)> = targets
        .into_iter()
        .map(|t| match t {
            Target::Node { t0, .. } => (t0, None),
            Target::Deformation(e) => (vec![0.0; model.nx], rows.iter().position(|&r| r == e)),
        })
        .collect();
    let nx = model.nx;
    let kx = Tangent::new(&free, step).stiffness_in_x();
    // the velocity basis of the free coordinates
    let ev = crate::assembly::evaluate(model, &step.x);
    let gt = if rows.is_empty() {
        None
    } else {
        let part = crate::model::Partition {
            x: model.partition.x.clone(),
            e: vec![crate::model::DefKind::Free; model.ne],
        };
        let cols = crate::kinematics::columns(model, &part, &step.x);
        let mut t = Mat::zeros(nx, cols.len());
        for (j, c) in cols.iter().enumerate() {
            let n = &model.nodes[c.node];
            match (c.dof.is_rotation(), n.ix_rot) {
                (true, Some(r)) => {
                    for k in 0..4 {
                        t[(r + k, j)] = c.lambda_rate[k];
                    }
                }
                _ => t[(n.ix_pos + c.dof.index(), j)] = 1.0,
            }
        }
        let g = Mat::from_fn(rows.len(), nx, |r, c| ev.D[(rows[r], c)]);
        let gt = &g * &t;
        Some((g, t, gt))
    };
    let ndof = red.ndof();
    // lift t⁰ onto the constraints: G t = the unit change of `row` (zero for a node motion)
    let lift = |t0: Vec<f64>, row: Option<usize>| -> Option<Vec<f64>> {
        let mut tm = t0;
        if let Some((g, t, gt)) = &gt {
            let target = |r: usize| if Some(r) == row { 1.0 } else { 0.0 };
            let mismatch = |tm: &[f64]| {
                let ge = g * Mat::from_fn(nx, 1, |a, _| tm[a]);
                Mat::from_fn(g.nrows(), 1, |r, _| ge[(r, 0)] - target(r))
            };
            let r0 = mismatch(&tm);
            if r0.norm_max() > 0.0 {
                // least squares G T w = −r0 through the SVD
                let f = crate::linalg::svd(gt.as_ref(), "constraint Jacobian").ok()?;
                let smax = f.s.first().copied().unwrap_or(0.0);
                let tol = f64::EPSILON.sqrt() * smax;
                let mut w = Mat::<f64>::zeros(gt.ncols(), 1);
                for (k, &sk) in f.s.iter().enumerate() {
                    if sk > tol {
                        let c: f64 = (0..g.nrows()).map(|r| f.U[(r, k)] * r0[(r, 0)]).sum();
                        for a in 0..gt.ncols() {
                            w[(a, 0)] -= f.V[(a, k)] * c / sk;
                        }
                    }
                }
                let tw = t * &w;
                for a in 0..nx {
                    tm[a] += tw[(a, 0)];
                }
                if mismatch(&tm).norm_max() > 1e-8 * r0.norm_max().max(smax) {
                    return None;
                }
            }
        }
        Some(tm)
    };
    let mut out = Vec::with_capacity(motions.len());
    for (mo, (t0, row)) in motions.iter().zip(dirs) {
        let Some(tm) = lift(t0, row) else {
            return Err(StateSpaceError::MotionConstrained {
                input: mo.name(model),
            });
        };
        let tmv = Mat::from_fn(nx, 1, |a, _| tm[a]);
        let (ktx, mtx) = (&kx * &tmv, &red.mx * &tmv);
        let k = red.z.transpose() * &ktx;
        let m = red.z.transpose() * &mtx;
        out.push(MotionLoad {
            k: (0..ndof).map(|r| k[(r, 0)]).collect(),
            m: (0..ndof).map(|r| m[(r, 0)]).collect(),
            rows: ReactionRows {
                kt: (0..nx).map(|a| ktx[(a, 0)]).collect(),
                mt: (0..nx).map(|a| mtx[(a, 0)]).collect(),
                t: tm.clone(),
            },
            t: tm,
        });
    }
    let mut rr = Vec::with_capacity(reactions.len());
    for (name, i) in reactions {
        let row = rows.iter().position(|r| r == i);
        let Some(t) = lift(vec![0.0; nx], row).filter(|_| row.is_some()) else {
            return Err(StateSpaceError::ReactionConstrained {
                output: name.clone(),
            });
        };
        let tv = Mat::from_fn(nx, 1, |a, _| t[a]);
        let (kt, mt) = (&kx * &tv, &red.mx * &tv);
        rr.push(ReactionRows {
            kt: (0..nx).map(|a| kt[(a, 0)]).collect(),
            mt: (0..nx).map(|a| mt[(a, 0)]).collect(),
            t,
        });
    }
    Ok((out, rr))
}

/// What a prescribed motion (or a reaction measured as one) moves: held node coordinates, with
/// the unit direction t⁰ in x (e_i, or ½ Λ̄ᵀ e_k on λ for a rotation) and the coordinates a copy
/// of the model frees for it; or a held deformation (its index in e).
pub(super) enum Target {
    /// A held node coordinate.
    Node {
        /// Unit direction in x before any lifting.
        t0: Vec<f64>,
        /// x indices freed in the copy of the model: the translation alone, or λ1..λ3.
        own: Vec<usize>,
    },
    /// A held deformation (index in e).
    Deformation(usize),
}

/// The checked targets of `motions`, and a copy of the model in which their node coordinates
/// are free (without their prescribed values). K on the moved coordinates comes from the
/// linearisation of that copy: a translation alone is freed, for a rotation all of λ1..λ3 of
/// the node. This keeps the constraints and multipliers: λ0 is always free, so every
/// rotational node already has its normalisation and multiplier.
pub(super) fn freed_model(
    model: &Model,
    step: &StepResult,
    motions: &[Motion],
) -> Result<(Model, Vec<Target>), StateSpaceError> {
    let mut free = model.clone();
    let mut freed = Vec::new();
    let role = crate::statics::roles(model);
    let mut targets = Vec::with_capacity(motions.len());
    for mo in motions {
        let name = mo.name(model);
        match *mo {
            Motion::Node { node, dof } => {
                let n = &model.nodes[node];
                let Some(i) = n.x_index(dof) else {
                    return Err(StateSpaceError::NoRotation {
                        node: n.name.clone(),
                    });
                };
                if model.partition.x[i] == CoordKind::Free {
                    return Err(StateSpaceError::MotionNotHeld { input: name });
                }
                let own: Vec<usize> = match (dof.is_rotation(), n.ix_rot) {
                    (true, Some(r)) => (r + 1..r + 4).collect(),
                    _ => vec![i],
                };
                for &j in &own {
                    free.partition.x[j] = CoordKind::Free;
                    freed.push(j);
                }
                let mut t0 = unit_vector(model, step, node, dof)?;
                if dof.is_rotation() {
                    // ½ Λ̄ᵀ e_k (the output row is 2 Λ̄ᵀ e_k)
                    t0.iter_mut().for_each(|v| *v *= 0.25);
                }
                targets.push(Target::Node { t0, own });
            }
            Motion::Deformation { element, mode } => {
                let entry = &model.elements[element];
                if entry.element.is_rigid_body() {
                    return Err(StateSpaceError::RigidBodyMotion { input: name });
                }
                let i = entry.ie + mode;
                if role[i] == crate::statics::Role::Flexible {
                    return Err(StateSpaceError::DeformationNotHeld {
                        input: name,
                        mode: mode + 1,
                        name: entry.element.mode_name(mode, &model.node_names()),
                        kind: entry.element.type_name(),
                        element: entry.name.clone(),
                    });
                }
                targets.push(Target::Deformation(i));
            }
        }
    }
    free.loads
        .prescribed
        .retain(|p| !matches!(p.target, crate::model::Target::Coordinate(i) if freed.contains(&i)));
    Ok((free, targets))
}

/// The reactions that the outputs measure: the forces of rigid or prescribed deformations
/// ((name, index in e), with the output's place in that list) and those of held node
/// coordinates (as the motions of those coordinates, with the output's place). Rates of
/// reactions, and reactions of free coordinates, are errors.
pub(super) struct Reactions {
    pub(super) deformations: Vec<(String, usize)>,
    pub(super) deformation_of: Vec<Option<usize>>,
    pub(super) nodes: Vec<Motion>,
    pub(super) node_of: Vec<Option<usize>>,
}

/// The [`Reactions`] of `outputs`.
pub(super) fn reactions(model: &Model, outputs: &[Output]) -> Result<Reactions, StateSpaceError> {
    let mut r = Reactions {
        deformations: Vec::new(),
        deformation_of: vec![None; outputs.len()],
        nodes: Vec::new(),
        node_of: vec![None; outputs.len()],
    };
    for (o, out) in outputs.iter().enumerate() {
        let reaction = matches!(out.probe, Probe::Reaction { .. })
            || (matches!(out.probe, Probe::Force { .. }) && out.is_reaction(model));
        if reaction && out.kind != OutputKind::Disp {
            return Err(StateSpaceError::ReactionRate {
                output: out.name(model),
            });
        }
        match out.probe {
            Probe::Force { element, mode } if reaction => {
                r.deformation_of[o] = Some(r.deformations.len());
                r.deformations
                    .push((out.name(model), model.elements[element].ie + mode));
            }
            Probe::Reaction { node, dof } => {
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
                r.node_of[o] = Some(r.nodes.len());
                r.nodes.push(Motion::Node { node, dof });
            }
            _ => {}
        }
    }
    Ok(r)
}

/// Force vector in x of a unit input; or the row of an output in x (same vector): for a
/// translation e_i, for a rotation 2 Λ̄ᵀ e_k on the node's λ.
pub(super) fn unit_vector(
    model: &Model,
    step: &StepResult,
    node: usize,
    dof: Dof,
) -> Result<Vec<f64>, StateSpaceError> {
    let n = &model.nodes[node];
    let mut v = vec![0.0; model.nx];
    if dof.is_rotation() {
        let Some(r) = n.ix_rot else {
            return Err(StateSpaceError::NoRotation {
                node: n.name.clone(),
            });
        };
        let lb = lambda_bar(&[step.x[r], step.x[r + 1], step.x[r + 2], step.x[r + 3]]);
        let k = dof.index() - 3;
        for c in 0..4 {
            v[r + c] = 2.0 * lb[k][c];
        }
    } else {
        v[n.ix_pos + dof.index()] = 1.0;
    }
    Ok(v)
}

/// The row w in x of an output's value, δy = w·δx: e_i or 2 Λ̄ᵀ e_k for a node
/// ([`unit_vector`]), the row Dₐ of the element Jacobian for a deformation, Σ_b S_ab D_b over
/// the flexible deformations b for a stress resultant (σ = S e, as statics).
pub(super) fn output_row(
    model: &Model,
    step: &StepResult,
    out: &Output,
) -> Result<Vec<f64>, StateSpaceError> {
    let (element, mode, force) = match out.probe {
        // a reaction output is combined from its reaction rows by the callers ([`reactions`]),
        // never from this row; the row of its held coordinate keeps the match total
        Probe::Node { node, dof } | Probe::Reaction { node, dof } => {
            return unit_vector(model, step, node, dof)
        }
        Probe::Deformation { element, mode } => (element, mode, false),
        Probe::Force { element, mode } => (element, mode, true),
    };
    let entry = &model.elements[element];
    let ne = entry.element.ne();
    let coef: Vec<f64> = if force {
        let role = crate::statics::element_roles(model, element);
        // the force of a rigid or prescribed deformation is a reaction ([`Output::is_reaction`]),
        // which never reaches this row
        let flexible = |b: usize| role[b] == crate::statics::Role::Flexible;
        let s = entry.element.stiffness();
        (0..ne)
            .map(|b| if flexible(b) { s[(mode, b)] } else { 0.0 })
            .collect()
    } else {
        (0..ne).map(|b| if b == mode { 1.0 } else { 0.0 }).collect()
    };
    let d = entry
        .element
        .jacobian(&crate::assembly::gather(entry, &step.x));
    let mut w = vec![0.0; model.nx];
    for (c, i) in entry.x_indices().enumerate() {
        w[i] += (0..ne).map(|b| coef[b] * d[(b, c)]).sum::<f64>();
    }
    Ok(w)
}

/// Whether an output is a node direction held by a support or prescribed input.
pub(super) fn held_output(model: &Model, out: &Output) -> bool {
    matches!(out.probe, Probe::Node { node, dof } if held(model, node, dof))
}

/// Whether a direction of a node is held by a support or prescribed input.
pub(super) fn held(model: &Model, node: usize, dof: Dof) -> bool {
    model.nodes[node]
        .x_index(dof)
        .is_none_or(|i| model.partition.x[i] != CoordKind::Free)
}
