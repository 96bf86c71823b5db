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

use crate::elements::{Beam, Element};
use crate::math::{lambda_bar, rotate};
use crate::model::Model;
use crate::section::BeamProps;
use faer::Mat;

/// ∫₀¹ Hᵢ Hⱼ dξ for the cubic Hermite functions H1 = 1 − 3ξ² + 2ξ³, H2 = ξ − 2ξ² + ξ³,
/// H3 = 3ξ² − 2ξ³, H4 = −ξ² + ξ³.
pub(crate) const HERMITE: [[f64; 4]; 4] = [
    [13.0 / 35.0, 11.0 / 210.0, 9.0 / 70.0, -13.0 / 420.0],
    [11.0 / 210.0, 1.0 / 105.0, 13.0 / 420.0, -1.0 / 140.0],
    [9.0 / 70.0, 13.0 / 420.0, 13.0 / 35.0, -11.0 / 210.0],
    [-13.0 / 420.0, -1.0 / 140.0, -11.0 / 210.0, 1.0 / 105.0],
];

/// ∂(R(λ) a)/∂λ (3 × 4), in closed form: R(λ) a = r/n² with
/// r = (λ0² − v·v) a + 2 (v·a) v + 2 λ0 (v × a), n² = λ0² + v·v, v = (λ1, λ2, λ3)
/// (as `math::rotate`).
fn d_rotated(l: &[f64], a: [f64; 3]) -> [[f64; 4]; 3] {
    let (l0, v) = (l[0], [l[1], l[2], l[3]]);
    let vv = crate::math::dot(v, v);
    let va = crate::math::dot(v, a);
    let n2 = l0 * l0 + vv;
    let vxa = crate::math::cross(v, a);
    let c0 = l0 * l0 - vv;
    let r: [f64; 3] = std::array::from_fn(|i| c0 * a[i] + 2.0 * va * v[i] + 2.0 * l0 * vxa[i]);
    let mut dr = [[0.0; 4]; 3];
    for i in 0..3 {
        dr[i][0] = 2.0 * l0 * a[i] + 2.0 * vxa[i];
    }
    for k in 0..3 {
        let mut ek = [0.0; 3];
        ek[k] = 1.0;
        let exa = crate::math::cross(ek, a);
        for i in 0..3 {
            dr[i][k + 1] =
                -2.0 * v[k] * a[i] + 2.0 * a[k] * v[i] + 2.0 * va * ek[i] + 2.0 * l0 * exa[i];
        }
    }
    let dn2 = [2.0 * l0, 2.0 * v[0], 2.0 * v[1], 2.0 * v[2]];
    let mut out = [[0.0; 4]; 3];
    for i in 0..3 {
        for j in 0..4 {
            out[i][j] = dr[i][j] / n2 - r[i] * dn2[j] / (n2 * n2);
        }
    }
    out
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
/// The lumped rotary inertia at one end of a beam (half the element's, ρI l₀/2 about its
/// current axes) as a tensor in global axes, with the end's Euler parameters `l`.
pub(crate) fn beam_end_inertia(b: &Beam, p: &BeamProps, l: &[f64]) -> [[f64; 3]; 3] {
    rotated_tensor(l, &b.frame, p.rho_i.map(|v| v * b.l0 / 2.0))
}

fn rotated_tensor(l: &[f64], frame: &[[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
    let lam = [l[0], l[1], l[2], l[3]];
    let axes: [[f64; 3]; 3] = std::array::from_fn(|k| rotate(&lam, frame[k]));
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

/// The mass matrix of a beam with section data on its 14 local coordinates
/// [r_p (3), λ_p (4), r_q (3), λ_q (4)] at their values `xk`: the consistent Hermite mass of the
/// centre line plus the lumped rotary inertia (module docs). `None` for a beam without mass data.
pub(crate) fn beam_local_mass(b: &Beam, xk: &[f64]) -> Option<[[f64; 14]; 14]> {
    beam_local_mass_with(b, xk, None, true)
}

/// [`beam_local_mass`] with the translational kinetic energy weighted by a symmetric `weight`
/// W (½ ρA ∫ ṙᵀ W ṙ instead of ½ ρA ∫ ṙᵀ ṙ; `None` = I), with or without the rotary
/// inertia. W = Ω² P without rotary inertia is the centrifugal softening of a steady rotation
/// (`crate::spin`).
pub(crate) fn beam_local_mass_with(
    b: &Beam,
    xk: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
) -> Option<[[f64; 14]; 14]> {
    let p = b.props.as_ref()?;
    let (lp, lq) = (&xk[3..7], &xk[10..14]);
    let ex = b.frame[0];
    // ∂r(ξ)/∂x_k for the four Hermite terms: 3 × (3 or 4) blocks
    let dtp = d_rotated(lp, ex);
    let dtq = d_rotated(lq, ex);
    // (first row, number of columns, columns) of each term, without allocations
    let units = [unit(0), unit(1), unit(2), [0.0; 3]];
    let blocks: [(usize, usize, [[f64; 3]; 4]); 4] = [
        (0, 3, units),
        (3, 4, std::array::from_fn(|c| col(&dtp, c, b.l0))),
        (7, 3, units),
        (10, 4, std::array::from_fn(|c| col(&dtq, c, b.l0))),
    ];
    let mut m = [[0.0; 14]; 14];
    let ml = p.rho_a * b.l0;
    for (a, (ia, na, ca)) in blocks.iter().enumerate() {
        for (bb, (ib, nb, cb)) in blocks.iter().enumerate() {
            let h = ml * HERMITE[a][bb];
            for (r, vr) in ca[..*na].iter().enumerate() {
                for (c, vc) in cb[..*nb].iter().enumerate() {
                    let wc = weight.map_or(*vc, |w| {
                        std::array::from_fn(|k| crate::math::dot(w[k], *vc))
                    });
                    m[ia + r][ib + c] += h * crate::math::dot(*vr, wc);
                }
            }
        }
    }
    if !rotary {
        return Some(m);
    }
    for (l, r0) in [(lp, 3), (lq, 10)] {
        let blk = lambda_block(l, &beam_end_inertia(b, p, l));
        for a in 0..4 {
            for c in 0..4 {
                m[r0 + a][r0 + c] += blk[a][c];
            }
        }
    }
    Some(m)
}

/// The block on the Euler parameters `l` of an inertia tensor given in global axes at the
/// reference orientation: the tensor turns with the node (R I Rᵀ), then 4 Λ̄ᵀ (R I Rᵀ) Λ̄.
pub(crate) fn node_inertia_block(l: &[f64], tensor: &[[f64; 3]; 3]) -> [[f64; 4]; 4] {
    let lam = [l[0], l[1], l[2], l[3]];
    let cols: [[f64; 3]; 3] = std::array::from_fn(|k| rotate(&lam, unit(k)));
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
    lambda_block(l, &ig)
}

/// Every entry of the mass matrix at x, element by element, as `f(row, column, value)` in x
/// (repeated positions add up): the beams' Hermite mass and lumped rotary inertia, point masses
/// and inertia tensors. With a `weight` W the translational kinetic energy is ½ ṙᵀ W ṙ
/// (beams and point masses), and `rotary = false` leaves the rotary inertias out
/// ([`beam_local_mass_with`]; the centrifugal softening of `crate::spin`).
pub(crate) fn for_each_entry(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(usize, usize, f64),
) {
    for_each_beam(model, x, weight, rotary, |xmap, me| {
        for (r, &gr) in xmap.iter().enumerate() {
            for (c, &gc) in xmap.iter().enumerate() {
                f(gr, gc, me[r][c]);
            }
        }
    });
    for_each_node_entry(model, x, weight, rotary, f);
}

/// The beams' mass matrices ([`beam_local_mass_with`]) with their coordinates in x, as
/// `f(xmap, matrix)`, in the order of the elements.
fn for_each_beam(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(&[usize], &[[f64; 14]; 14]),
) {
    let mut xk = [0.0; 14];
    for entry in &model.elements {
        let Element::Beam(b) = &entry.element else {
            continue;
        };
        let xk = &mut xk[..entry.xmap.len()];
        xk.iter_mut().zip(&entry.xmap).for_each(|(v, &i)| *v = x[i]);
        let Some(me) = beam_local_mass_with(b, xk, weight, rotary) else {
            continue;
        };
        f(&entry.xmap, &me);
    }
}

/// The entries of point masses and inertia tensors (the part of [`for_each_entry`] after the
/// beams).
fn for_each_node_entry(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(usize, usize, f64),
) {
    for &(node, mass) in &model.loads.point_masses {
        let ip = model.nodes[node].ix_pos;
        for r in 0..3 {
            match weight {
                Some(w) => (0..3).for_each(|c| f(ip + r, ip + c, mass * w[r][c])),
                None => f(ip + r, ip + r, mass),
            }
        }
    }
    if !rotary {
        return;
    }
    for (node, tensor) in &model.loads.inertias {
        let Some(r) = model.nodes[*node].ix_rot else {
            continue;
        };
        let blk = node_inertia_block(&x[r..r + 4], tensor);
        for a in 0..4 {
            for c in 0..4 {
                f(r + a, r + c, blk[a][c]);
            }
        }
    }
}

/// Dense mass matrix M (nx × nx) at x.
pub fn mass_matrix(model: &Model, x: &[f64]) -> Mat<f64> {
    let mut m = Mat::zeros(model.nx, model.nx);
    for_each_entry(model, x, None, true, |r, c, v| m[(r, c)] += v);
    m
}

/// M v for several vectors v in x at once, element by element (no global matrix): the
/// products that the energy split of the modes needs, also for models too large for a dense M.
pub fn mass_times(model: &Model, x: &[f64], vs: &[&[f64]]) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; model.nx]; vs.len()];
    // per vector the same additions in the same order as entry by entry
    for_each_beam(model, x, None, true, |xmap, me| {
        for (v, o) in vs.iter().zip(out.iter_mut()) {
            for (r, &gr) in xmap.iter().enumerate() {
                let mut acc = o[gr];
                for (c, &gc) in xmap.iter().enumerate() {
                    acc += me[r][c] * v[gc];
                }
                o[gr] = acc;
            }
        }
    });
    for_each_node_entry(model, x, None, true, |r, c, m| {
        for (v, o) in vs.iter().zip(out.iter_mut()) {
            o[r] += m * v[c];
        }
    });
    out
}

/// The blocks of M on each node's own coordinates (7 × 7: position x, y, z, then λ0..λ3; a
/// node `at` a host has its host's position, so only its λ block is filled), element by
/// element: the inertia of every velocity direction of a node, without a global matrix.
pub fn node_blocks(model: &Model, x: &[f64]) -> Vec<[[f64; 7]; 7]> {
    // x index → (node, local index 0..7)
    let mut owner = vec![(usize::MAX, 0usize); model.nx];
    for (id, n) in model.nodes.iter().enumerate() {
        if n.host.is_none() {
            for k in 0..3 {
                owner[n.ix_pos + k] = (id, k);
            }
        }
        if let Some(r) = n.ix_rot {
            for k in 0..4 {
                owner[r + k] = (id, 3 + k);
            }
        }
    }
    let mut out = vec![[[0.0; 7]; 7]; model.nodes.len()];
    for_each_entry(model, x, None, true, |gr, gc, v| {
        let ((nr, lr), (nc, lc)) = (owner[gr], owner[gc]);
        if nr == nc && nr != usize::MAX {
            out[nr][lr][lc] += v;
        }
    });
    out
}

fn unit(k: usize) -> [f64; 3] {
    let mut v = [0.0; 3];
    v[k] = 1.0;
    v
}

fn col(d: &[[f64; 4]; 3], c: usize, l0: f64) -> [f64; 3] {
    [l0 * d[0][c], l0 * d[1][c], l0 * d[2][c]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_rotation_derivative_matches_central_differences() {
        let mut rng = crate::elements::testing::Rng(11);
        for _ in 0..20 {
            // not normalised: the formula holds for any λ ≠ 0
            let l: [f64; 4] = std::array::from_fn(|_| rng.next());
            let a: [f64; 3] = std::array::from_fn(|_| rng.next());
            let d = d_rotated(&l, a);
            let h = 1e-6;
            for j in 0..4 {
                let (mut lp, mut lm) = (l, l);
                lp[j] += h;
                lm[j] -= h;
                let (rp, rm) = (rotate(&lp, a), rotate(&lm, a));
                for i in 0..3 {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    assert!((d[i][j] - fd).abs() < 1e-7, "{i} {j}: {} vs {fd}", d[i][j]);
                }
            }
        }
    }
}
