//! The designer's language of the kinematic check (Blanding's exact constraint, Hopkins and
//! Culpepper's freedom and constraint topologies; docs/kinematic-analysis.md "Twists and
//! wrenches"): the rigid bodies of a model, the twist of every body in every motion and the
//! wrench every constraint applies to every body in every self-stress state.
//!
//! - A **body** is a set of nodes that move as one: the nodes of an element whose deformations
//!   are all rows of Dcc (none free) and whose nodes carry a frame (a node with position and
//!   rotation, three non-collinear points, or the rotations of nodes at one place), joined
//!   through shared nodes. The nodes whose coordinates are all held, and every body that
//!   holds one of them, form the **ground**. A rigid truss between two points is no body: it is
//!   a constraint line.
//! - A **twist** (ω, v) is the velocity field v(p) = v + ω × (p − c) of a body (c its centre).
//!   With ω ≠ 0 it is a rotation about the axis through c + ω × v / |ω|² along ω with the
//!   pitch h = ω · v / |ω|² (a screw motion if h ≠ 0); with ω = 0 a translation along v.
//! - A **wrench** (F, M) is the force system a constraint applies to a body (moment M about c).
//!   With F ≠ 0 it is a force on the line through c + F × M / |F|² along F with the pitch
//!   F · M / |F|² (zero for a wire); with F = 0 a couple M.
//! - The reciprocal product of a twist and a wrench is their power, F · v(p) + M_p · ω at any
//!   point p: a constraint removes a motion iff it is non-zero.
//!
//! ω counts as zero when |ω| L ≤ [`PURE_TOL`] (|ω| L + |v|), L the size of the model
//! ([`length_scale`]); likewise F for a couple.

use super::{columns, rate_rows, row_defs, Column, ConstraintAnalysis, KinematicsError};
use crate::elements::{ElementKind, NodeId};
use crate::linalg::svd;
use crate::math::{add, cross, dot, norm, sub};
use crate::model::{CoordKind, DefKind, Model, Partition};
use faer::Mat;
use serde::Serialize;

/// A twist is a translation (a wrench a couple) when its angular part times the model size is
/// below this fraction of the whole.
pub const PURE_TOL: f64 = 1e-8;

/// A body is at rest in a motion, an entry is left out of a state, below this fraction of the
/// largest velocity or wrench of the state.
pub const NEGLIGIBLE: f64 = 1e-8;

/// A motion moves a body rigidly when the least-squares twist leaves a residual below this
/// fraction of its nodal velocities.
pub const RIGID_TOL: f64 = 1e-6;

/// 3-vector.
type V = [f64; 3];

fn scale(c: f64, a: V) -> V {
    [c * a[0], c * a[1], c * a[2]]
}

/// The kind of a screw.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ScrewKind {
    /// A twist with ω ≠ 0: rotation about an axis (with a pitch: a screw motion).
    Rotation,
    /// A twist with ω = 0.
    Translation,
    /// A wrench with F ≠ 0: a force on a line of action (with a pitch: a force and a moment
    /// along it).
    Force,
    /// A wrench with F = 0: a pure moment.
    Couple,
}

/// A twist or a wrench as a line: a point on the axis (or line of action), its direction and
/// pitch.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Screw {
    /// What the screw is.
    pub kind: ScrewKind,
    /// The point of the axis or line closest to the body's centre (the centre for a
    /// translation or a couple).
    pub point: [f64; 3],
    /// Unit direction: ω/|ω|, F/|F|, or v/|v|, M/|M| for a translation or a couple.
    pub direction: [f64; 3],
    /// Pitch [m/rad for a twist, m for a wrench]: ω·v/|ω|², F·M/|F|²; `None` for a
    /// translation or a couple (infinite pitch).
    pub pitch: Option<f64>,
    /// |ω|, |F|, or |v|, |M| for a translation or a couple.
    pub magnitude: f64,
}

impl Screw {
    /// The screw of (a, b) given at the point c: a = ω or F, b = v(c) or M_c. Pure (a
    /// translation or couple) when |a| L ≤ [`PURE_TOL`] (|a| L + |b|).
    fn from_pair(a: V, b: V, c: V, l: f64, line: ScrewKind, pure: ScrewKind) -> Self {
        let (na, nb) = (norm(a), norm(b));
        if na * l <= PURE_TOL * (na * l + nb) {
            let direction = if nb > 0.0 {
                scale(1.0 / nb, b)
            } else {
                [0.0; 3]
            };
            return Screw {
                kind: pure,
                point: c,
                direction,
                pitch: None,
                magnitude: nb,
            };
        }
        let a2 = na * na;
        Screw {
            kind: line,
            point: add(c, scale(1.0 / a2, cross(a, b))),
            direction: scale(1.0 / na, a),
            pitch: Some(dot(a, b) / a2),
            magnitude: na,
        }
    }

    /// The screw of a twist: angular velocity ω, velocity v(c) of the body point at c.
    pub fn twist(omega: V, v_c: V, c: V, l: f64) -> Self {
        Self::from_pair(
            omega,
            v_c,
            c,
            l,
            ScrewKind::Rotation,
            ScrewKind::Translation,
        )
    }

    /// The screw of a wrench: force F, moment M_c about c.
    pub fn wrench(force: V, m_c: V, c: V, l: f64) -> Self {
        Self::from_pair(force, m_c, c, l, ScrewKind::Force, ScrewKind::Couple)
    }
}

/// A rigid body of the model (module docs).
#[derive(Clone, Debug, Serialize)]
pub struct Body {
    /// Its name: "ground", the name of its rigid-body element, or of its first element.
    pub name: String,
    /// True for the ground (every node with all coordinates held, and the bodies holding one).
    pub ground: bool,
    /// Its nodes, by name.
    pub nodes: Vec<String>,
    /// The elements inside it, by name.
    pub elements: Vec<String>,
    /// The mean of its node positions (the reference point of its twists and wrenches).
    pub centre: [f64; 3],
    /// Node indices.
    #[serde(skip)]
    pub node_ids: Vec<NodeId>,
    /// Element indices.
    #[serde(skip)]
    pub element_ids: Vec<usize>,
}

/// The size L of the model: the diagonal of its nodes' bounding box at x (1 for a single
/// point), the length that makes rotations and translations comparable.
pub fn length_scale(model: &Model, x: &[f64]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for id in 0..model.nodes.len() {
        let p = position(model, x, id);
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let d = norm(sub(hi, lo));
    if d.is_finite() && d > 0.0 {
        d
    } else {
        1.0
    }
}

/// The position of a node at x (a hosted node's is its host's).
pub fn position(model: &Model, x: &[f64], id: NodeId) -> V {
    let i = model.nodes[id].ix_pos;
    [x[i], x[i + 1], x[i + 2]]
}

/// True when every coordinate of the node (its position, λ1..λ3) is fixed or an input: the node
/// stands still in every motion of Dcc.
fn held(model: &Model, partition: &Partition, id: NodeId) -> bool {
    let n = &model.nodes[id];
    let pos = (0..3).all(|k| partition.x[n.ix_pos + k] != CoordKind::Free);
    let rot = n
        .ix_rot
        .is_none_or(|ir| (1..4).all(|k| partition.x[ir + k] != CoordKind::Free));
    pos && rot
}

/// True when an element makes its nodes one body: none of its deformations is free and its
/// nodes carry a frame (module docs).
fn is_body_element(model: &Model, partition: &Partition, x: &[f64], el: usize, l: f64) -> bool {
    let entry = &model.elements[el];
    if (0..entry.element.ne()).any(|k| partition.e[entry.ie + k] == DefKind::Free) {
        return false;
    }
    let uses = entry.element.node_uses();
    if uses.iter().any(|u| u.pos && u.rot) {
        return true;
    }
    // rotations only, all at one place
    let place = |u: &crate::elements::NodeUse| model.nodes[u.node].host.unwrap_or(u.node);
    if !uses.is_empty() && uses.iter().all(|u| u.rot) {
        return uses.iter().all(|u| place(u) == place(&uses[0]));
    }
    // three points not on one line: the point farthest from the first, then any point off
    // the line through both (O(k))
    let pts: Vec<V> = uses
        .iter()
        .filter(|u| u.pos)
        .map(|u| position(model, x, u.node))
        .collect();
    let Some(&p) = pts.first() else {
        return false;
    };
    let far = pts
        .iter()
        .map(|&q| sub(q, p))
        .fold([0.0; 3], |a, d| if norm(d) > norm(a) { d } else { a });
    let nf = norm(far);
    nf > 0.0
        && pts
            .iter()
            .any(|&r| norm(cross(far, sub(r, p))) > 1e-9 * nf * l)
}

fn find(parent: &mut [usize], i: usize) -> usize {
    let mut r = i;
    while parent[r] != r {
        r = parent[r];
    }
    let mut k = i;
    while parent[k] != r {
        let next = parent[k];
        parent[k] = r;
        k = next;
    }
    r
}

/// The rigid bodies of a partition at x: the ground first (if any node is held), then the
/// others in the order of their first element (module docs).
pub fn bodies(model: &Model, partition: &Partition, x: &[f64]) -> Vec<Body> {
    let nn = model.nodes.len();
    let l = length_scale(model, x);
    let mut parent: Vec<usize> = (0..nn).collect();
    let mut in_body = vec![false; nn];
    let body_elements: Vec<usize> = (0..model.elements.len())
        .filter(|&el| is_body_element(model, partition, x, el, l))
        .collect();
    for &el in &body_elements {
        let uses = model.elements[el].element.node_uses();
        for u in &uses {
            in_body[u.node] = true;
            let (a, b) = (find(&mut parent, uses[0].node), find(&mut parent, u.node));
            parent[b] = a;
        }
    }
    // the ground: held nodes and the clusters holding one
    let held_nodes: Vec<bool> = (0..nn).map(|id| held(model, partition, id)).collect();
    let mut ground_root = vec![false; nn];
    for id in 0..nn {
        if held_nodes[id] {
            let r = find(&mut parent, id);
            ground_root[r] = true;
        }
    }
    let names = |ids: &[usize], of: &dyn Fn(usize) -> String| ids.iter().map(|&i| of(i)).collect();
    let node_name = |i: usize| model.nodes[i].name.clone();
    let element_name = |i: usize| model.elements[i].name.clone();
    let centre = |ids: &[NodeId]| {
        let s = ids
            .iter()
            .fold([0.0; 3], |s, &id| add(s, position(model, x, id)));
        scale(1.0 / ids.len().max(1) as f64, s)
    };
    // nodes and elements by their cluster (one pass each)
    let root: Vec<usize> = (0..nn).map(|id| find(&mut parent, id)).collect();
    let mut nodes_of: Vec<Vec<NodeId>> = vec![Vec::new(); nn];
    for id in (0..nn).filter(|&id| in_body[id] && !ground_root[root[id]]) {
        nodes_of[root[id]].push(id);
    }
    let mut elements_of: Vec<Vec<usize>> = vec![Vec::new(); nn];
    for &el in &body_elements {
        elements_of[root[model.elements[el].element.node_uses()[0].node]].push(el);
    }
    let mut out = Vec::new();
    let ground_nodes: Vec<NodeId> = (0..nn)
        .filter(|&id| ground_root[root[id]] && (held_nodes[id] || in_body[id]))
        .collect();
    if !ground_nodes.is_empty() {
        let els: Vec<usize> = body_elements
            .iter()
            .copied()
            .filter(|&el| ground_root[root[model.elements[el].element.node_uses()[0].node]])
            .collect();
        out.push(Body {
            name: "ground".into(),
            ground: true,
            nodes: names(&ground_nodes, &node_name),
            elements: names(&els, &element_name),
            centre: centre(&ground_nodes),
            node_ids: ground_nodes,
            element_ids: els,
        });
    }
    let mut done = vec![false; nn];
    for &el in &body_elements {
        let r = root[model.elements[el].element.node_uses()[0].node];
        if ground_root[r] || done[r] {
            continue;
        }
        done[r] = true;
        let ids = std::mem::take(&mut nodes_of[r]);
        let els = std::mem::take(&mut elements_of[r]);
        let named = els
            .iter()
            .copied()
            .find(|&e| model.elements[e].element.is_rigid_body())
            .unwrap_or(el);
        out.push(Body {
            name: model.elements[named].name.clone(),
            ground: false,
            nodes: names(&ids, &node_name),
            elements: names(&els, &element_name),
            centre: centre(&ids),
            node_ids: ids,
            element_ids: els,
        });
    }
    out
}

/// Nodal velocities of a vector over the columns: translation and angular velocity per node
/// (a hosted node moves with its host).
pub struct VelocityField {
    /// Translational velocity per node.
    pub u: Vec<V>,
    /// Angular velocity per node (zero for a node without rotation).
    pub w: Vec<V>,
}

impl VelocityField {
    /// The field of the column vector `v`.
    pub fn new(model: &Model, cols: &[Column], v: &[f64]) -> Self {
        let nn = model.nodes.len();
        let mut u = vec![[0.0; 3]; nn];
        let mut w = vec![[0.0; 3]; nn];
        for (c, &val) in cols.iter().zip(v) {
            if c.dof.is_rotation() {
                w[c.node] = add(w[c.node], scale(val, c.dir));
            } else {
                u[c.node][c.dof.index()] += val;
            }
        }
        for (id, n) in model.nodes.iter().enumerate() {
            if let Some(h) = n.host {
                u[id] = u[h];
            }
        }
        Self { u, w }
    }
}

/// The twist of one body in one motion.
#[derive(Clone, Debug, Serialize)]
pub struct BodyTwist {
    /// The body's name.
    pub body: String,
    /// Its axis: rotation (point, direction, pitch) or translation (direction).
    pub screw: Screw,
    /// ω.
    pub angular_velocity: [f64; 3],
    /// The velocity of the body point at `screw.point` (h ω on the axis of a rotation).
    pub velocity: [f64; 3],
    /// ‖A t − b‖ / ‖b‖ of the least-squares twist over the body's nodal velocities: above
    /// [`RIGID_TOL`] the nodes do not move as one body in this motion.
    pub rigid_residual: f64,
}

/// The least-squares twist (ω, v(c)) of a body's nodal velocities: v(c) + ω × (p − c) = u at
/// every node, L ω = L ω_node at every node with rotation. Returns (ω, v(c), residual, ‖b‖).
pub fn fit_twist(
    model: &Model,
    x: &[f64],
    body: &Body,
    f: &VelocityField,
    l: f64,
) -> Result<(V, V, f64, f64), KinematicsError> {
    let c = body.centre;
    let mut rows: Vec<([f64; 6], f64)> = Vec::new();
    for &id in &body.node_ids {
        let r = sub(position(model, x, id), c);
        // ω × r = −[r×] ω; [r×] rows: (0, −r2, r1), (r2, 0, −r0), (−r1, r0, 0)
        let rx = [[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]];
        for i in 0..3 {
            let mut a = [0.0; 6];
            for k in 0..3 {
                a[k] = -rx[i][k];
            }
            a[3 + i] = 1.0;
            rows.push((a, f.u[id][i]));
        }
        if model.nodes[id].ix_rot.is_some() {
            for i in 0..3 {
                let mut a = [0.0; 6];
                a[i] = l;
                rows.push((a, l * f.w[id][i]));
            }
        }
    }
    let a = Mat::from_fn(rows.len(), 6, |i, j| rows[i].0[j]);
    let b: Vec<f64> = rows.iter().map(|r| r.1).collect();
    let bn = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    let s = svd(a.as_ref(), "the twist fit of a body")?;
    let cut = 1e-12 * s.s.first().copied().unwrap_or(0.0);
    // t = V Σ⁺ Uᵀ b
    let mut t = [0.0; 6];
    for (k, &sk) in s.s.iter().enumerate() {
        if sk <= cut {
            continue;
        }
        let ub: f64 = (0..b.len()).map(|i| s.U[(i, k)] * b[i]).sum::<f64>() / sk;
        for (j, tj) in t.iter_mut().enumerate() {
            *tj += s.V[(j, k)] * ub;
        }
    }
    let res = rows
        .iter()
        .map(|(a, bi)| {
            let e = (0..6).map(|j| a[j] * t[j]).sum::<f64>() - bi;
            e * e
        })
        .sum::<f64>()
        .sqrt();
    let rel = if bn > 0.0 { res / bn } else { 0.0 };
    Ok(([t[0], t[1], t[2]], [t[3], t[4], t[5]], rel, bn))
}

/// The rate of one free deformation in a motion.
#[derive(Clone, Debug, Serialize)]
pub struct ModeRate {
    /// Mode, 1-based.
    pub mode: usize,
    /// Mode name.
    pub mode_name: String,
    /// ė along the motion (unit length over the columns).
    pub rate: f64,
}

/// A flexure (an element with free deformations) that deforms in a motion.
#[derive(Clone, Debug, Serialize)]
pub struct FlexureRate {
    /// Element name.
    pub element: String,
    /// Its free deformations with a non-zero rate.
    pub modes: Vec<ModeRate>,
}

/// A motion in the designer's language.
#[derive(Clone, Debug, Serialize)]
pub struct MotionScrews {
    /// The twist of every moving body.
    pub bodies: Vec<BodyTwist>,
    /// The flexures that deform.
    pub flexures: Vec<FlexureRate>,
}

/// The wrench one constraint applies to one body in a self-stress state.
#[derive(Clone, Debug, Serialize)]
pub struct BodyWrench {
    /// The body acted on.
    pub body: String,
    /// The element that applies it, or the body's support (`support`).
    pub by: String,
    /// True for the reaction of the body's held coordinates.
    pub support: bool,
    /// The line of action (force or couple, pitch).
    pub screw: Screw,
    /// F.
    pub force: [f64; 3],
    /// The moment about `screw.point`.
    pub moment: [f64; 3],
}

/// A self-stress state in the designer's language.
#[derive(Clone, Debug, Serialize)]
pub struct SelfStressScrews {
    /// The wrench of every participating constraint on every body it touches.
    pub wrenches: Vec<BodyWrench>,
}

/// The screws of a check (module docs).
#[derive(Clone, Debug, Serialize)]
pub struct ScrewAnalysis {
    /// L [m], the model size of [`PURE_TOL`].
    pub length_scale: f64,
    /// The rigid bodies.
    pub bodies: Vec<Body>,
    /// Per listed motion (the columns of `null_v`, presented with unit length and the
    /// largest entry positive like the motions).
    pub motions: Vec<MotionScrews>,
    /// Per listed self-stress state (the columns of `null_u`, presented likewise).
    pub self_stresses: Vec<SelfStressScrews>,
}

/// The twists of the bodies of `bodies` for the column vector `v` (bodies at rest left out).
pub fn body_twists(
    model: &Model,
    x: &[f64],
    cols: &[Column],
    bodies: &[Body],
    v: &[f64],
    l: f64,
) -> Result<Vec<BodyTwist>, KinematicsError> {
    let f = VelocityField::new(model, cols, v);
    let big =
        f.u.iter()
            .zip(&f.w)
            .fold(0.0f64, |m, (u, w)| m.max(norm(*u) + l * norm(*w)));
    let mut out = Vec::new();
    for b in bodies {
        let (omega, v_c, rigid_residual, bn) = fit_twist(model, x, b, &f, l)?;
        if bn <= NEGLIGIBLE * big || big == 0.0 {
            continue;
        }
        let screw = Screw::twist(omega, v_c, b.centre, l);
        let velocity = add(v_c, cross(omega, sub(screw.point, b.centre)));
        out.push(BodyTwist {
            body: b.name.clone(),
            screw,
            angular_velocity: omega,
            velocity,
            rigid_residual,
        });
    }
    Ok(out)
}

/// The screws of the listed motions and self-stress states of `a`, an analysis of `partition`
/// at x (paper eq. (9): the motions are the null vectors of Dcc, the self-stresses those of
/// Dccᵀ; the element forces of a state are D_kᵀσ_k).
pub fn screws(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    a: &ConstraintAnalysis,
) -> Result<ScrewAnalysis, KinematicsError> {
    let l = length_scale(model, x);
    let bodies = bodies(model, partition, x);
    let names = model.node_names();
    // free deformations and their rates over the columns
    let free: Vec<usize> = if a.null_v.ncols() > 0 {
        (0..model.ne)
            .filter(|&i| partition.e[i] == DefKind::Free)
            .collect()
    } else {
        Vec::new()
    };
    let free_rows = rate_rows(model, x, &a.cols, &free);
    let mut motions = Vec::new();
    for k in 0..a.null_v.ncols() {
        let mut v: Vec<f64> = (0..a.n()).map(|j| a.null_v[(j, k)]).collect();
        super::normalize_signed(&mut v);
        let twists = body_twists(model, x, &a.cols, &bodies, &v, l)?;
        let mut flexures: Vec<FlexureRate> = Vec::new();
        for (f, row) in free.iter().zip(&free_rows) {
            let rn = row.iter().map(|e| e.1 * e.1).sum::<f64>().sqrt();
            let rate: f64 = row.iter().map(|&(j, d)| d * v[j]).sum();
            if rate.abs() <= NEGLIGIBLE * rn || rn == 0.0 {
                continue;
            }
            let (el, mode) = model.deformation_owner(*f);
            let entry = &model.elements[el];
            let m = ModeRate {
                mode: mode + 1,
                mode_name: entry.element.mode_name(mode, &names),
                rate,
            };
            match flexures.last_mut() {
                Some(last) if last.element == entry.name => last.modes.push(m),
                _ => flexures.push(FlexureRate {
                    element: entry.name.clone(),
                    modes: vec![m],
                }),
            }
        }
        motions.push(MotionScrews {
            bodies: twists,
            flexures,
        });
    }
    let self_stresses = if a.null_u.ncols() > 0 {
        state_wrenches(model, partition, x, a, &bodies, l)
    } else {
        Vec::new()
    };
    Ok(ScrewAnalysis {
        length_scale: l,
        bodies,
        motions,
        self_stresses,
    })
}

/// The wrenches of every listed self-stress state.
fn state_wrenches(
    model: &Model,
    partition: &Partition,
    x: &[f64],
    a: &ConstraintAnalysis,
    bodies: &[Body],
    l: f64,
) -> Vec<SelfStressScrews> {
    use std::collections::BTreeMap;
    // every velocity component of every node: the element forces at held coordinates too
    let mut all = partition.clone();
    all.x.iter_mut().for_each(|k| *k = CoordKind::Free);
    let cols = columns(model, &all, x);
    let rates = rate_rows(model, x, &cols, &row_defs(model, &a.rows));
    let nn = model.nodes.len();
    let mut out = Vec::new();
    for s in 0..a.null_u.ncols() {
        let mut u: Vec<f64> = (0..a.m()).map(|i| a.null_u[(i, s)]).collect();
        super::normalize_signed(&mut u);
        // generalised force D_kᵀσ_k of each element over the columns
        let mut g: BTreeMap<usize, BTreeMap<usize, f64>> = BTreeMap::new();
        for (i, &ui) in u.iter().enumerate() {
            if ui == 0.0 {
                continue;
            }
            let e = g.entry(a.rows[i].element).or_default();
            for &(j, d) in &rates[i] {
                *e.entry(j).or_insert(0.0) += ui * d;
            }
        }
        let mut found: Vec<(f64, BodyWrench)> = Vec::new();
        for b in bodies {
            let mut pos_in = vec![false; nn];
            let mut rot_in = vec![false; nn];
            for &id in &b.node_ids {
                rot_in[id] = true;
                pos_in[model.nodes[id].host.unwrap_or(id)] = true;
            }
            let c = b.centre;
            let mut total = ([0.0; 3], [0.0; 3]);
            for (&el, gk) in &g {
                // the force on the nodes is −D_kᵀσ_k; the moment about c
                let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
                for (&j, &val) in gk {
                    let col = &cols[j];
                    let p = scale(-val, col.dir);
                    if col.dof.is_rotation() {
                        if rot_in[col.node] {
                            m = add(m, p);
                        }
                    } else if pos_in[col.node] {
                        f = add(f, p);
                        m = add(m, cross(sub(position(model, x, col.node), c), p));
                    }
                }
                total = (add(total.0, f), add(total.1, m));
                // an element that does not touch the body has no wrench on it (and one of size
                // zero is never listed): no name is formatted for it
                if b.element_ids.contains(&el) || (f == [0.0; 3] && m == [0.0; 3]) {
                    continue;
                }
                found.push((
                    norm(f) * l + norm(m),
                    wrench(b, &model.elements[el].name, false, f, m, l),
                ));
            }
            if !b.ground {
                let (f, m) = (scale(-1.0, total.0), scale(-1.0, total.1));
                found.push((norm(f) * l + norm(m), wrench(b, "support", true, f, m, l)));
            }
        }
        let big = found.iter().fold(0.0f64, |m, w| m.max(w.0));
        out.push(SelfStressScrews {
            wrenches: found
                .into_iter()
                .filter(|w| w.0 > NEGLIGIBLE * big && w.0 > 0.0)
                .map(|w| w.1)
                .collect(),
        });
    }
    out
}

/// A wrench (F, M about the body's centre) as a [`BodyWrench`], its moment taken about the
/// point of its line.
fn wrench(b: &Body, by: &str, support: bool, f: V, m_c: V, l: f64) -> BodyWrench {
    let screw = Screw::wrench(f, m_c, b.centre, l);
    // M_p = M_c + (c − p) × F
    let moment = add(m_c, cross(sub(b.centre, screw.point), f));
    BodyWrench {
        body: b.name.clone(),
        by: by.to_string(),
        support,
        screw,
        force: f,
        moment,
    }
}

/// The reciprocal product of a twist (ω, v(p)) and a wrench (F, M_p), both given at one point
/// p: F · v + M · ω, the power of the wrench in the twist (zero: the constraint does not act
/// on that motion).
pub fn reciprocal(omega: V, v_p: V, force: V, m_p: V) -> f64 {
    dot(force, v_p) + dot(m_p, omega)
}
