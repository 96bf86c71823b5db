//! The mass matrix M in x (theory.md §12).
//!
//! - Beam, translational: the centre line is the cubic Hermite curve through the end positions
//!   and the current end tangents t = R(λ) ex, r(ξ) = H1 r_p + H2 l0 t_p + H3 r_q + H4 l0 t_q,
//!   and the kinetic energy is ½ ρA l0 ∫₀¹ |ṙ|² dξ ([V FIS README]: "cubic interpolation of the
//!   centre line", consistent mass). In the reference configuration this is the classical
//!   consistent (Hermite) mass of a beam in bending.
//! - Beam, rotary: J/L · l0 lumped half to each end (SPACAR's log, theory.md §12), the tensor
//!   diag(ρ(Iy+Iz), ρIy, ρIz) in the element's current axes at that end; with ω = 2 Λ̄ λ̇ the
//!   block on λ is 4 Λ̄ᵀ I Λ̄.
//! - Point masses m I₃ on a node's position; inertia tensors (global axes, reference
//!   orientation, rotated with the node) on its λ.

use crate::elements::Element;
use crate::math::{lambda_bar, rotate, Scalar, SmoothMap};
use crate::model::Model;
use faer::Mat;

/// ∫₀¹ Hᵢ Hⱼ dξ for the cubic Hermite functions H1 = 1 − 3ξ² + 2ξ³, H2 = ξ − 2ξ² + ξ³,
/// H3 = 3ξ² − 2ξ³, H4 = −ξ² + ξ³.
const HERMITE: [[f64; 4]; 4] = [
    [13.0 / 35.0, 11.0 / 210.0, 9.0 / 70.0, -13.0 / 420.0],
    [11.0 / 210.0, 1.0 / 105.0, 13.0 / 420.0, -1.0 / 140.0],
    [9.0 / 70.0, 13.0 / 420.0, 13.0 / 35.0, -11.0 / 210.0],
    [-13.0 / 420.0, -1.0 / 140.0, -11.0 / 210.0, 1.0 / 105.0],
];

/// v ↦ R(λ) a for a fixed a, as a function of λ (for its derivative).
struct Rotated([f64; 3]);
impl SmoothMap<4, 3> for Rotated {
    fn eval<T: Scalar>(&self, x: &[T; 4]) -> [T; 3] {
        rotate(x, [T::cst(self.0[0]), T::cst(self.0[1]), T::cst(self.0[2])])
    }
}

/// ∂(R(λ) a)/∂λ (3 × 4).
fn d_rotated(l: &[f64], a: [f64; 3]) -> [[f64; 4]; 3] {
    Rotated(a).jacobian(&[l[0], l[1], l[2], l[3]]).1
}

/// Inertia tensor block on λ: 4 Λ̄ᵀ I Λ̄ (4 × 4), I in global axes.
fn lambda_block(l: &[f64], i: &[[f64; 3]; 3]) -> [[f64; 4]; 4] {
    let lb = lambda_bar(&[l[0], l[1], l[2], l[3]]);
    let mut out = [[0.0; 4]; 4];
    for a in 0..4 {
        for b in 0..4 {
            let mut v = 0.0;
            for r in 0..3 {
                for c in 0..3 {
                    v += lb[r][a] * i[r][c] * lb[c][b];
                }
            }
            out[a][b] = 4.0 * v;
        }
    }
    out
}

/// R(λ) diag(d) Rᵀ in the frame whose reference axes are the rows of `frame`.
fn rotated_tensor(l: &[f64], frame: &[[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
    let lam = [l[0], l[1], l[2], l[3]];
    let axes: Vec<[f64; 3]> = frame.iter().map(|e| rotate(&lam, *e)).collect();
    let mut i = [[0.0; 3]; 3];
    for k in 0..3 {
        for r in 0..3 {
            for c in 0..3 {
                i[r][c] += d[k] * axes[k][r] * axes[k][c];
            }
        }
    }
    i
}

/// Dense mass matrix M (nx × nx) at x.
pub fn mass_matrix(model: &Model, x: &[f64]) -> Mat<f64> {
    let mut m = Mat::zeros(model.nx, model.nx);
    for entry in &model.elements {
        let Element::Beam(b) = &entry.element else {
            continue;
        };
        let Some(p) = &b.props else { continue };
        let xm = &entry.xmap; // [r_p (3), λ_p (4), r_q (3), λ_q (4)]
        let (lp, lq) = (&x[xm[3]..xm[3] + 4], &x[xm[10]..xm[10] + 4]);
        let ex = b.frame[0];
        // A_a: 3 × (3 or 4) blocks of ∂r(ξ)/∂x_k for the four Hermite terms
        let dtp = d_rotated(lp, ex);
        let dtq = d_rotated(lq, ex);
        let blocks: [(Vec<usize>, Vec<[f64; 3]>); 4] = [
            ((0..3).map(|k| xm[k]).collect(), (0..3).map(unit).collect()),
            (
                (3..7).map(|k| xm[k]).collect(),
                (0..4).map(|c| col(&dtp, c, b.l0)).collect(),
            ),
            ((7..10).map(|k| xm[k]).collect(), (0..3).map(unit).collect()),
            (
                (10..14).map(|k| xm[k]).collect(),
                (0..4).map(|c| col(&dtq, c, b.l0)).collect(),
            ),
        ];
        let ml = p.rho_a * b.l0;
        for (a, (ia, ca)) in blocks.iter().enumerate() {
            for (bb, (ib, cb)) in blocks.iter().enumerate() {
                let h = ml * HERMITE[a][bb];
                for (r, &gr) in ia.iter().enumerate() {
                    for (c, &gc) in ib.iter().enumerate() {
                        m[(gr, gc)] += h * crate::math::dot(ca[r], cb[c]);
                    }
                }
            }
        }
        // rotary inertia, half the element's to each end
        let d = [
            p.rho_i[0] * b.l0 / 2.0,
            p.rho_i[1] * b.l0 / 2.0,
            p.rho_i[2] * b.l0 / 2.0,
        ];
        for (l, r0) in [(lp, xm[3]), (lq, xm[10])] {
            let blk = lambda_block(l, &rotated_tensor(l, &b.frame, d));
            for a in 0..4 {
                for c in 0..4 {
                    m[(r0 + a, r0 + c)] += blk[a][c];
                }
            }
        }
    }
    for &(node, mass) in &model.loads.point_masses {
        let ip = model.nodes[node].ix_pos;
        for k in 0..3 {
            m[(ip + k, ip + k)] += mass;
        }
    }
    for (node, tensor) in &model.loads.inertias {
        let Some(r) = model.nodes[*node].ix_rot else {
            continue;
        };
        let l = &x[r..r + 4];
        // rotate the reference tensor with the node: R I Rᵀ
        let lam = [l[0], l[1], l[2], l[3]];
        let cols: Vec<[f64; 3]> = (0..3).map(|k| rotate(&lam, unit(k))).collect();
        let mut ig = [[0.0; 3]; 3];
        for a in 0..3 {
            for b in 0..3 {
                for p in 0..3 {
                    for q in 0..3 {
                        ig[a][b] += cols[p][a] * tensor[p][q] * cols[q][b];
                    }
                }
            }
        }
        let blk = lambda_block(l, &ig);
        for a in 0..4 {
            for c in 0..4 {
                m[(r + a, r + c)] += blk[a][c];
            }
        }
    }
    m
}

fn unit(k: usize) -> [f64; 3] {
    let mut v = [0.0; 3];
    v[k] = 1.0;
    v
}

fn col(d: &[[f64; 4]; 3], c: usize, l0: f64) -> [f64; 3] {
    [l0 * d[0][c], l0 * d[1][c], l0 * d[2][c]]
}
