//! Wires that remove a motion (docs/kinematic-analysis.md "Repair in the designer's language"):
//! rigid constraint lines between existing nodes of a moving body and of another body or the
//! ground (Blanding's constraint lines), found from the bodies' relative twists in the motion,
//! ranked by how little they act on the intended freedoms, and each verified like every
//! suggestion of [`super::advice`] (a rank update of the dense SVD, or the sparse path's bound
//! for an added row). The suggestions' types are those of [`super::advice`], which re-exports
//! [`wire_advice`].

use super::advice::{WireAdvice, WireSuggestion};
use super::freedom::{intended_power, resolve_body, IntendedFreedom};
use super::screw::{position, ScrewAnalysis, VelocityField, PURE_TOL};
use super::update::{Change, Prediction, Updater};
use super::{CheckOptions, ConstraintAnalysis, KinematicsError, SparseRow};
use crate::math::{add, cross, dot, norm, normalize, sub};
use crate::model::Model;

/// A candidate wire from node `na` to node `ng` along the unit `d`.
struct WireCandidate {
    /// The intended change ([`WireSuggestion::intended_change`]).
    change: f64,
    /// The reciprocal product per unit motion, made dimensionless (a rotation's over L).
    rel: f64,
    na: usize,
    ng: usize,
    d: [f64; 3],
    /// The reciprocal product ([`WireSuggestion::reciprocal`]).
    power: f64,
}

/// How a wire suggestion is verified: by a rank update of the dense SVD, or by the sparse
/// path's bound for an added row.
enum WireCheck<'a> {
    Dense(Updater<'a>),
    Sparse(super::sparse::AddedRowBound),
}

/// Candidate wires tried (verified) per motion, at most.
const MAX_WIRE_TRIES: usize = 200;

/// Node pairs (and body pairs) looked at per motion, at most (the first ones in the order of
/// bodies and nodes).
const MAX_WIRE_PAIRS: usize = 200_000;

/// The row of a rigid wire from node `a` to node `g` along the unit `d` over the columns:
/// ė = d · (u_g − u_a) (the elongation rate of a rigid truss, paper eq. (1)).
fn wire_row(model: &Model, cols: &[super::Column], a: usize, g: usize, d: [f64; 3]) -> SparseRow {
    let (pa, pg) = (
        model.nodes[a].host.unwrap_or(a),
        model.nodes[g].host.unwrap_or(g),
    );
    cols.iter()
        .enumerate()
        .filter(|(_, c)| !c.dof.is_rotation())
        .filter_map(|(j, c)| {
            let k = c.dof.index();
            if c.node == pg {
                Some((j, d[k]))
            } else if c.node == pa {
                Some((j, -d[k]))
            } else {
                None
            }
        })
        .filter(|e| e.1 != 0.0)
        .collect()
}

/// For every listed motion of a dense analysis: wires between existing nodes of a moving body
/// and of another body or the ground whose reciprocal product with the bodies' relative twist
/// is not zero (the wire stops the motion), each verified to remove exactly that motion and
/// add no self-stress (its row raises the rank of Dcc), ranked by how little they act on the
/// intended freedoms, then by their reciprocal product (docs/kinematic-analysis.md "Repair
/// in the designer's language"). On the sparse path a wire is verified by the bound of
/// [`super::sparse::AddedRowBound`] (no new factorisation), and only when the rank decision is
/// certain.
pub fn wire_advice(
    model: &Model,
    x: &[f64],
    a: &ConstraintAnalysis,
    screws: &ScrewAnalysis,
    intended: &[IntendedFreedom],
    opts: &CheckOptions,
    max_per_state: usize,
) -> Result<Vec<WireAdvice>, KinematicsError> {
    if max_per_state == 0 || a.n_motions() == 0 {
        return Ok(Vec::new());
    }
    let verify = match &a.sparse {
        None => WireCheck::Dense(Updater::new(a, opts.rank_tol)?),
        Some(sp) => match super::sparse::AddedRowBound::new(a, sp, opts.rank_tol) {
            Some(b) => WireCheck::Sparse(b),
            None => return Ok(Vec::new()),
        },
    };
    let bodies = &screws.bodies;
    let l = screws.length_scale;
    let resolved: Vec<(usize, &IntendedFreedom)> = intended
        .iter()
        .filter_map(|f| resolve_body(model, bodies, &f.body).map(|b| (b, f)))
        .collect();
    let want = (a.n_motions() - 1, a.n_self_stresses());
    // each node's body, and the nodes in none
    let mut node_body: Vec<Option<usize>> = vec![None; model.nodes.len()];
    for (i, b) in bodies.iter().enumerate() {
        for &id in &b.node_ids {
            node_body[id] = Some(i);
        }
    }
    let loose: Vec<usize> = (0..model.nodes.len())
        .filter(|&id| node_body[id].is_none())
        .collect();
    let anchor = |id: usize| {
        node_body[id].map_or_else(|| model.nodes[id].name.clone(), |i| bodies[i].name.clone())
    };
    let mut out = Vec::new();
    for (k, ms) in screws.motions.iter().enumerate() {
        let mut v: Vec<f64> = (0..a.n()).map(|j| a.null_v[(j, k)]).collect();
        super::normalize_signed(&mut v);
        let field = VelocityField::new(model, &a.cols, &v);
        // the moving bodies' twists by body index (linear in the bodies, for large models)
        let by_name: std::collections::HashMap<&str, &super::screw::BodyTwist> =
            ms.bodies.iter().map(|t| (t.body.as_str(), t)).collect();
        let moving: Vec<Option<&super::screw::BodyTwist>> = bodies
            .iter()
            .map(|b| by_name.get(b.name.as_str()).copied())
            .collect();
        // the twist of body i at the point p (zero for a body at rest)
        let twist = |i: usize, p: [f64; 3]| {
            moving[i].map_or(([0.0; 3], [0.0; 3]), |t| {
                let w = t.angular_velocity;
                (w, add(t.velocity, cross(w, sub(p, t.screw.point))))
            })
        };
        let mut cands: Vec<WireCandidate> = Vec::new();
        let mut pairs = 0usize;
        // a candidate from node na (of body ia, or none) to node ng, `unit` the size of the
        // relative motion it is measured against, `rotation` whether that is a rotation
        let mut consider = |na: usize, ng: usize, unit: f64, rotation: bool| {
            let (pa, pg) = (position(model, x, na), position(model, x, ng));
            let dv = sub(pg, pa);
            if norm(dv) <= 1e-9 * l {
                return;
            }
            let d = normalize(dv);
            let power = dot(d, sub(field.u[na], field.u[ng])).abs() / unit;
            let rel = if rotation { power / l } else { power };
            if rel <= 1e-6 {
                return;
            }
            let (ia, ig) = (node_body[na], node_body[ng]);
            let change = intended_power(
                &resolved,
                bodies,
                (ia.unwrap_or(usize::MAX), pa),
                (ig.unwrap_or(usize::MAX), pg),
                d,
                l,
            );
            cands.push(WireCandidate {
                change,
                rel,
                na,
                ng,
                d,
                power,
            });
        };
        'bodies: for (ia, ba) in bodies.iter().enumerate() {
            if ba.ground || moving[ia].is_none() {
                continue;
            }
            for (ig, bg) in bodies.iter().enumerate() {
                // a body pair counts like a node pair (bodies in one twist give none)
                pairs += 1;
                if pairs > MAX_WIRE_PAIRS {
                    break 'bodies;
                }
                if ig == ia {
                    continue;
                }
                let (wa, va) = twist(ia, ba.centre);
                let (wg, vg) = twist(ig, ba.centre);
                let (wr, vr) = (sub(wa, wg), sub(va, vg));
                let rotation = norm(wr) * l > PURE_TOL * (norm(wr) * l + norm(vr));
                let unit = if rotation { norm(wr) } else { norm(vr) };
                if unit == 0.0 {
                    continue;
                }
                for &na in &ba.node_ids {
                    for &ng in &bg.node_ids {
                        pairs += 1;
                        if pairs > MAX_WIRE_PAIRS {
                            break 'bodies;
                        }
                        consider(na, ng, unit, rotation);
                    }
                }
            }
            // to a node in no body, measured against the body's own twist
            let (wa, va) = twist(ia, ba.centre);
            let rotation = norm(wa) * l > PURE_TOL * (norm(wa) * l + norm(va));
            let unit = if rotation { norm(wa) } else { norm(va) };
            for &na in &ba.node_ids {
                for &ng in &loose {
                    pairs += 1;
                    if pairs > MAX_WIRE_PAIRS {
                        break 'bodies;
                    }
                    consider(na, ng, unit, rotation);
                }
            }
        }
        // a moving node in no body (a joint of trusses or wires): a wire to any other node,
        // measured against their relative velocity (a translation)
        let umax = field.u.iter().map(|&u| norm(u)).fold(0.0, f64::max);
        'nodes: for &na in &loose {
            if norm(field.u[na]) <= 1e-6 * umax {
                continue;
            }
            for ng in 0..model.nodes.len() {
                pairs += 1;
                if pairs > MAX_WIRE_PAIRS {
                    break 'nodes;
                }
                let unit = norm(sub(field.u[na], field.u[ng]));
                if ng != na && unit > 0.0 {
                    consider(na, ng, unit, false);
                }
            }
        }
        cands.sort_by_key(|c| {
            (
                (c.change * 1e6).round() as u64,
                std::cmp::Reverse((c.rel * 1e9).round() as u64),
            )
        });
        let mut wires: Vec<WireSuggestion> = Vec::new();
        for c in cands.into_iter().take(MAX_WIRE_TRIES) {
            let (na, ng, d) = (c.na, c.ng, c.d);
            if wires.len() >= max_per_state {
                break;
            }
            let pa = position(model, x, na);
            // one wire per line
            let same_line = |w: &WireSuggestion| {
                norm(cross(w.direction, d)) <= 1e-9
                    && norm(cross(sub(pa, w.point), w.direction)) <= 1e-9 * l
            };
            if wires.iter().any(same_line) {
                continue;
            }
            let row = wire_row(model, &a.cols, na, ng, d);
            let (motions_after, self_stresses_after) = match &verify {
                WireCheck::Dense(upd) => {
                    let change_row = Change::AddRow(row);
                    if matches!(upd.predict(&change_row), Prediction::Certain(c) if c != want) {
                        continue;
                    }
                    upd.counts_after(&change_row)
                }
                WireCheck::Sparse(bound) if bound.raises_rank(&row) => want,
                WireCheck::Sparse(_) => continue,
            };
            if (motions_after, self_stresses_after) != want {
                continue;
            }
            wires.push(WireSuggestion {
                from: model.nodes[na].name.clone(),
                to: model.nodes[ng].name.clone(),
                body: anchor(na),
                other: anchor(ng),
                point: pa,
                direction: d,
                length: norm(sub(position(model, x, ng), pa)),
                reciprocal: c.power,
                intended_change: c.change,
                motions_after,
                self_stresses_after,
            });
        }
        out.push(WireAdvice { motion: k, wires });
    }
    Ok(out)
}
