//! The co-rotated carried iteration matrix of modified Newton.
//!
//! Elastic and kinetic energy do not change under a rigid rotation of the state: positions
//! p → R(q) p and Euler parameters λ → q ⊗ λ = L(q) λ. With T = diag(R(q), L(q)) per node
//! (orthogonal), the invariance U(T x) = U(x) gives the tangent at the rotated state,
//! K(T x) = T K(x) Tᵀ, and the same for the mass matrix and the Euler normalisations' rows.
//! A matrix factorised at x_b therefore serves a later iterate x, whose nodes have turned by
//! q = λ ⊗ λ_b⁻¹ each, as T A(x_b) Tᵀ: the correction is d = T A(x_b)⁻¹ Tᵀ r, with no new
//! factorisation. Neighbouring nodes turn alike, so the node-wise T is the rigid rotation of
//! every element up to its own deformation increment.
//!
//! Without it, the stiff axial directions of a turning slender beam make a carried matrix
//! useless within a step or two (the corrections of the 10-beam pendulum at 1 ms shrank twofold
//! per iteration instead of fiftyfold), and nearly every step rebuilt and refactorised it.

use super::Engine;
use crate::math::{euler_left, euler_mul, rotation_matrix};

/// A node with free Euler parameters: its λ0 index in x and the unknowns of λ and of its
/// position (`None` unless all three position coordinates are free and its own, not a host's).
pub(super) struct CoRot {
    pub(super) ix_rot: usize,
    pub(super) rot: [usize; 4],
    pub(super) pos: Option<[usize; 3]>,
}

/// The rotation of one node since the matrix was built: R(q) and L(q).
pub(super) struct Turn {
    r: [[f64; 3]; 3],
    l: [[f64; 4]; 4],
}

fn unit(l: [f64; 4]) -> [f64; 4] {
    let n = l.iter().map(|v| v * v).sum::<f64>().sqrt();
    l.map(|v| v / n)
}

fn lambda_at(x: &[f64], r: usize) -> [f64; 4] {
    [x[r], x[r + 1], x[r + 2], x[r + 3]]
}

/// The co-rotated nodes of a model: every node whose four Euler parameters are free.
pub(super) fn corot_nodes(
    model: &crate::model::Model,
    unknown: &[crate::statics::Slot],
) -> Vec<CoRot> {
    model
        .nodes
        .iter()
        .filter_map(|n| {
            let r = n.ix_rot?;
            let u = |i: usize| unknown[i].get();
            let rot = [u(r)?, u(r + 1)?, u(r + 2)?, u(r + 3)?];
            let pos = match (n.host, u(n.ix_pos), u(n.ix_pos + 1), u(n.ix_pos + 2)) {
                (None, Some(a), Some(b), Some(c)) => Some([a, b, c]),
                _ => None,
            };
            Some(CoRot {
                ix_rot: r,
                rot,
                pos,
            })
        })
        .collect()
}

impl Engine<'_> {
    /// Remember the Euler parameters of the state whose matrix was just factorised.
    pub(super) fn corot_built_at(&mut self, x: &[f64]) {
        self.jac_lambda.clear();
        self.jac_lambda
            .extend(self.corot.iter().map(|c| unit(lambda_at(x, c.ix_rot))));
    }

    /// Solve with the carried factorisation, co-rotated to the iterate x:
    /// rhs ← T A(x_b)⁻¹ Tᵀ rhs. `false` when there is no factorisation to reuse.
    pub(super) fn solve_carried(&mut self, x: &[f64], rhs: &mut [f64]) -> bool {
        let mut turns = std::mem::take(&mut self.turns);
        turns.clear();
        turns.extend(self.corot.iter().zip(&self.jac_lambda).map(|(c, lb)| {
            let q = euler_mul(
                &unit(lambda_at(x, c.ix_rot)),
                &[lb[0], -lb[1], -lb[2], -lb[3]],
            );
            Turn {
                r: rotation_matrix(&q),
                l: euler_left(&q),
            }
        }));
        self.turn_rhs(&turns, rhs, true);
        let ok = self.solver.solve_again(rhs).is_ok();
        self.turn_rhs(&turns, rhs, false);
        self.turns = turns;
        ok
    }

    /// rhs ← Tᵀ rhs (`transpose`) or T rhs on the co-rotated nodes' unknowns.
    fn turn_rhs(&self, turns: &[Turn], rhs: &mut [f64], transpose: bool) {
        fn apply<const N: usize>(m: &[[f64; N]; N], idx: &[usize; N], v: &mut [f64], tr: bool) {
            let b = idx.map(|u| v[u]);
            for i in 0..N {
                v[idx[i]] = (0..N)
                    .map(|j| if tr { m[j][i] } else { m[i][j] } * b[j])
                    .sum();
            }
        }
        for (c, t) in self.corot.iter().zip(turns) {
            apply(&t.l, &c.rot, rhs, transpose);
            if let Some(p) = &c.pos {
                apply(&t.r, p, rhs, transpose);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Coefs, Engine, Part};
    use crate::math::{euler_from_axis_angle, euler_mul, normalize, rotate};
    use crate::model::ModelBuilder;
    use crate::section::BeamProps;
    use crate::simulation::{Excitation, SimOptions};

    /// A factorised iteration matrix co-rotated to a rigidly turned state solves exactly as the
    /// matrix built there: a free, bent three-beam chain (no supports, no gravity) turned by
    /// 0.8 rad gives the same corrections to round-off. A wrong composition order (λ ⊗ q, or
    /// Rᵀ) fails by the size of the turn.
    #[test]
    fn co_rotated_matrix_solves_as_the_matrix_of_the_turned_state() {
        let props = BeamProps {
            ea: 2e3,
            gj: 0.5,
            eiy: 0.3,
            eiz: 0.7,
            rho_a: 0.2,
            rho_i: [2e-5, 1e-5, 1e-5],
            ..Default::default()
        };
        let mut b = ModelBuilder::new("free chain");
        b.add_beam_chain(
            "",
            [0.0; 3],
            [0.3, 0.0, 0.0],
            3,
            Some([0.0, 1.0, 0.0]),
            Some(props),
        )
        .unwrap();
        let model = b.build().unwrap();
        let opts = SimOptions::new(1.0);
        let mut eng = Engine::new(&model, &Excitation::default(), &opts).unwrap();
        // a bent, stretched and twisted state
        let mut x = model.x0().to_vec();
        for (k, n) in model.nodes.iter().enumerate() {
            let s = k as f64;
            x[n.ix_pos] *= 1.01;
            x[n.ix_pos + 1] += 0.02 * s * s;
            x[n.ix_pos + 2] -= 0.01 * s;
            let r = n.ix_rot.unwrap();
            let l = euler_from_axis_angle(normalize([0.2, -0.3 * s, 1.0]), 0.1 * s);
            x[r..r + 4].copy_from_slice(&l);
        }
        let q = euler_from_axis_angle(normalize([1.0, 2.0, -0.5]), 0.8);
        let mut xt = x.clone();
        for n in &model.nodes {
            let p = [x[n.ix_pos], x[n.ix_pos + 1], x[n.ix_pos + 2]];
            xt[n.ix_pos..n.ix_pos + 3].copy_from_slice(&rotate(&q, p));
            let r = n.ix_rot.unwrap();
            let l = euler_mul(&q, &[x[r], x[r + 1], x[r + 2], x[r + 3]]);
            xt[r..r + 4].copy_from_slice(&l);
        }
        // the iteration matrix K/β' + M (at rest), factorised at a state
        let zeros = vec![0.0; model.nx];
        let mu = vec![0.0; eng.su.nk];
        let coefs = Coefs {
            k: 1e-4,
            m: 1.0,
            km: 0.0,
            diag: 0.0,
        };
        let n = eng.su.nf + eng.su.nk;
        let rhs: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let solve_at = |eng: &mut Engine, x: &[f64]| {
            let ev = eng.evaluate_part(x, &zeros, &zeros, &mu, 0.0, Part::Full, Vec::new());
            let mut vals = Vec::new();
            eng.values_into(&ev, x, 0.0, coefs, &mut vals);
            let mut d = rhs.clone();
            eng.solver.solve(&vals, &mut d).unwrap();
            eng.corot_built_at(x);
            d
        };
        let fresh = solve_at(&mut eng, &xt);
        solve_at(&mut eng, &x);
        let mut carried = rhs.clone();
        assert!(eng.solve_carried(&xt, &mut carried));
        let scale = fresh.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (i, (a, b)) in carried.iter().zip(&fresh).enumerate() {
            assert!((a - b).abs() < 1e-9 * scale, "unknown {i}: {a} vs {b}");
        }
        // and the plain carried matrix does not (the test can tell)
        let mut plain = rhs.clone();
        eng.solver.solve_again(&mut plain).unwrap();
        let off = plain
            .iter()
            .zip(&fresh)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(off > 1e-2 * scale, "the turn changes the matrix: {off}");
    }
}
