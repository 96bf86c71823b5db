//! Rigid body over any number of nodes.
//!
//! Node 0 is the reference node; it always carries a rotation (λ₀), so the body has an
//! orientation even when all its nodes are otherwise translational. For every other member
//! node i:
//!
//! ```text
//! e_pos,i = R(λ₀)ᵀ (r_i − r₀) − (r_i⁰ − r₀⁰)                     3 deformations
//! e_rot,i = ((z₀·y_i − y₀·z_i)/2, (x₀·z_i − z₀·x_i)/2, (y₀·x_i − x₀·y_i)/2)   3 more if i has a rotation
//! ```
//!
//! with x₀ = R(λ₀) e_x, y_i = R(λ_i) e_y, … the current images of the global axes (every node's
//! reference orientation is the identity). So n nodes that all carry rotations give 6(n − 1)
//! deformations, all rigid: every extra node of a rigid part adds as many constraint rows as
//! coordinates (paper §4.2, theory.md §3.5).

use super::{ElementKind, NodeId, NodeUse};
use crate::math::{cst3, dot, rotate, sub, Scalar, SmoothMap, V3};
use faer::Mat;

/// Rigid body over nodes `nodes[0]` (reference, with rotation) and the others.
#[derive(Clone, Debug)]
pub struct Rigid {
    /// Member nodes; node 0 is the reference node.
    pub nodes: Vec<NodeId>,
    /// Whether member i carries a rotation (always true for member 0).
    pub rot: Vec<bool>,
    /// Whether member i has its own position constraints (false for a member that shares the
    /// position of an earlier member, e.g. a node `at` it; always true for member 0).
    pub pos: Vec<bool>,
    /// Reference offsets r_i⁰ − r₀⁰ of members 1.. (index 0 unused).
    pub offsets: Vec<[f64; 3]>,
}

/// Relative position of member i in the frame of node 0: x = [r₀; λ₀; r_i] (10).
struct RelPos([f64; 3]);
impl SmoothMap<10, 3> for RelPos {
    fn eval<T: Scalar>(&self, x: &[T; 10]) -> [T; 3] {
        // R(λ₀)ᵀ d = R(λ₀*) d, λ₀* the conjugate
        let conj = [x[3], -x[4], -x[5], -x[6]];
        let d = sub([x[7], x[8], x[9]], [x[0], x[1], x[2]]);
        let rel = rotate(&conj, d);
        let o = cst3::<T>(self.0);
        sub(rel, o)
    }
}

/// Relative rotation of member i and node 0: x = [λ₀; λ_i] (8).
struct RelRot;
impl SmoothMap<8, 3> for RelRot {
    fn eval<T: Scalar>(&self, x: &[T; 8]) -> [T; 3] {
        let l0 = [x[0], x[1], x[2], x[3]];
        let li = [x[4], x[5], x[6], x[7]];
        let ax = |l: &[T; 4]| -> [V3<T>; 3] {
            [
                rotate(l, cst3([1.0, 0.0, 0.0])),
                rotate(l, cst3([0.0, 1.0, 0.0])),
                rotate(l, cst3([0.0, 0.0, 1.0])),
            ]
        };
        let [x0, y0, z0] = ax(&l0);
        let [xi, yi, zi] = ax(&li);
        [
            (dot(z0, yi) - dot(y0, zi)).scale(0.5),
            (dot(x0, zi) - dot(z0, xi)).scale(0.5),
            (dot(y0, xi) - dot(x0, yi)).scale(0.5),
        ]
    }
}

impl Rigid {
    /// A rigid body; `positions` are the members' reference positions, `rot` says which members
    /// carry a rotation (member 0 is forced to).
    pub fn new(nodes: Vec<NodeId>, positions: &[[f64; 3]], rot: Vec<bool>) -> Self {
        let pos = vec![true; nodes.len()];
        Self::with_shared_positions(nodes, positions, rot, pos)
    }

    /// As [`Rigid::new`], with `pos[i]` false for members whose position is that of an earlier
    /// member (only their rotation is tied to the body).
    pub fn with_shared_positions(
        nodes: Vec<NodeId>,
        positions: &[[f64; 3]],
        mut rot: Vec<bool>,
        mut pos: Vec<bool>,
    ) -> Self {
        assert_eq!(nodes.len(), positions.len(), "one position per member");
        assert_eq!(nodes.len(), rot.len(), "one rotation flag per member");
        assert_eq!(nodes.len(), pos.len(), "one position flag per member");
        if let Some(r) = rot.first_mut() {
            *r = true;
        }
        if let Some(p) = pos.first_mut() {
            *p = true;
        }
        let offsets = positions.iter().map(|&p| sub(p, positions[0])).collect();
        Self {
            nodes,
            rot,
            pos,
            offsets,
        }
    }

    /// Number of deformations of member i ≥ 1.
    fn member_ne(&self, i: usize) -> usize {
        3 * usize::from(self.pos[i]) + 3 * usize::from(self.rot[i])
    }

    /// Local offset of member i's coordinates in x_k.
    fn local_offsets(&self) -> Vec<usize> {
        let mut off = Vec::with_capacity(self.nodes.len());
        let mut k = 0;
        for u in self.node_uses() {
            off.push(k);
            k += u.len();
        }
        off
    }

    /// Apply `f(i, e_offset, n_deformations)` to every member i ≥ 1.
    fn for_members(&self, mut f: impl FnMut(usize, usize, usize)) {
        let mut ie = 0;
        for i in 1..self.nodes.len() {
            f(i, ie, self.member_ne(i));
            ie += self.member_ne(i);
        }
    }
}

impl Rigid {
    /// For member i at local offset `oi` whose deformations start at `ie`: the local offset of
    /// its position (if constrained) and of its λ with the index of its rotation deformations.
    fn split(&self, i: usize, oi: usize, ie: usize) -> (Option<usize>, Option<(usize, usize)>) {
        let pos = self.pos[i].then_some(oi);
        let rot = self.rot[i].then(|| {
            let or = if self.pos[i] { oi + 3 } else { oi };
            (or, ie + 3 * usize::from(self.pos[i]))
        });
        (pos, rot)
    }
}

impl ElementKind for Rigid {
    fn node_uses(&self) -> Vec<NodeUse> {
        (0..self.nodes.len())
            .map(|i| NodeUse {
                node: self.nodes[i],
                pos: self.pos[i],
                rot: self.rot[i],
            })
            .collect()
    }
    fn ne(&self) -> usize {
        (1..self.nodes.len()).map(|i| self.member_ne(i)).sum()
    }
    fn is_rigid_body(&self) -> bool {
        true
    }
    fn mode_name(&self, k: usize, node_names: &[String]) -> String {
        let mut name = String::new();
        self.for_members(|i, ie, n| {
            if (ie..ie + n).contains(&k) {
                let j = k - ie;
                let node = node_names.get(self.nodes[i]).map_or("?", |s| s.as_str());
                let comp = ["x", "y", "z"][j % 3];
                name = if j < 3 && self.pos[i] {
                    format!("position {comp} of {node}")
                } else {
                    format!("rotation {comp} of {node}")
                };
            }
        });
        name
    }
    fn deformations(&self, xk: &[f64]) -> Vec<f64> {
        let off = self.local_offsets();
        let mut e = vec![0.0; self.ne()];
        self.for_members(|i, ie, _| {
            let (pos, ir) = self.split(i, off[i], ie);
            if let Some(op) = pos {
                e[ie..ie + 3].copy_from_slice(&RelPos(self.offsets[i]).value(&gather_pos(xk, op)));
            }
            if let Some((or, er)) = ir {
                e[er..er + 3].copy_from_slice(&RelRot.value(&gather_rot(xk, or)));
            }
        });
        e
    }
    fn jacobian(&self, xk: &[f64]) -> Mat<f64> {
        let off = self.local_offsets();
        let mut d = Mat::zeros(self.ne(), xk.len());
        self.for_members(|i, ie, _| {
            let (pos, ir) = self.split(i, off[i], ie);
            if let Some(op) = pos {
                let (_, jp) = RelPos(self.offsets[i]).jacobian(&gather_pos(xk, op));
                for r in 0..3 {
                    for (c, &col) in pos_columns(op).iter().enumerate() {
                        d[(ie + r, col)] += jp[r][c];
                    }
                }
            }
            if let Some((or, er)) = ir {
                let (_, jr) = RelRot.jacobian(&gather_rot(xk, or));
                for r in 0..3 {
                    for (c, &col) in rot_columns(or).iter().enumerate() {
                        d[(er + r, col)] += jr[r][c];
                    }
                }
            }
        });
        d
    }
    fn hessian_weighted(&self, xk: &[f64], w: &[f64]) -> Mat<f64> {
        let off = self.local_offsets();
        let mut h = Mat::zeros(xk.len(), xk.len());
        self.for_members(|i, ie, _| {
            let (pos, ir) = self.split(i, off[i], ie);
            if let Some(op) = pos {
                let wp = [w[ie], w[ie + 1], w[ie + 2]];
                let hp = RelPos(self.offsets[i]).hessian_weighted(&gather_pos(xk, op), &wp);
                let cols = pos_columns(op);
                for (a, &ca) in cols.iter().enumerate() {
                    for (b, &cb) in cols.iter().enumerate() {
                        h[(ca, cb)] += hp[a][b];
                    }
                }
            }
            if let Some((or, er)) = ir {
                let wr = [w[er], w[er + 1], w[er + 2]];
                let hr = RelRot.hessian_weighted(&gather_rot(xk, or), &wr);
                let cols = rot_columns(or);
                for (a, &ca) in cols.iter().enumerate() {
                    for (b, &cb) in cols.iter().enumerate() {
                        h[(ca, cb)] += hr[a][b];
                    }
                }
            }
        });
        h
    }
    fn stiffness(&self) -> Mat<f64> {
        // a rigid body has no finite stiffness: all its deformations are constraints
        Mat::zeros(self.ne(), self.ne())
    }
}

/// Local columns of [r₀ (0..3); λ₀ (3..7); r_i] for member i at local offset `oi`.
fn pos_columns(oi: usize) -> [usize; 10] {
    [0, 1, 2, 3, 4, 5, 6, oi, oi + 1, oi + 2]
}
/// Local columns of [λ₀; λ_i] for a member whose λ_i starts at local offset `or`.
fn rot_columns(or: usize) -> [usize; 8] {
    [3, 4, 5, 6, or, or + 1, or + 2, or + 3]
}
fn gather_pos(xk: &[f64], oi: usize) -> [f64; 10] {
    pos_columns(oi).map(|c| xk[c])
}
fn gather_rot(xk: &[f64], oi: usize) -> [f64; 8] {
    rot_columns(oi).map(|c| xk[c])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::testing::{check_contract, Contract};

    #[test]
    fn rigid_satisfies_element_contract() {
        let pos = [
            [0.0, 0.0, 0.0],
            [1.0, 0.2, 0.0],
            [0.3, -0.7, 0.5],
            [0.1, 0.1, 0.9],
        ];
        let r = Rigid::new(vec![0, 1, 2, 3], &pos, vec![true, false, true, true]);
        assert_eq!(r.ne(), 3 + 6 + 6);
        check_contract(&r, &pos, Contract::default());
        // a member sharing member 1's position contributes its rotation only
        let pos2 = [pos[0], pos[1], pos[1]];
        let r2 = Rigid::with_shared_positions(
            vec![0, 1, 2],
            &pos2,
            vec![true; 3],
            vec![true, true, false],
        );
        assert_eq!(r2.ne(), 6 + 3);
        check_contract(&r2, &pos2, Contract::default());
    }

    #[test]
    fn all_rotational_members_give_6_per_extra_node() {
        let pos = [[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let r = Rigid::new(vec![0, 1, 2], &pos, vec![true; 3]);
        assert_eq!(r.ne(), 12);
    }
}
