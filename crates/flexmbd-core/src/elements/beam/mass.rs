//! The beam's one mass model (theory.md §12), used for the mass matrix M, for gravity and for the
//! centrifugal loads and softening of a steady rotation.
//!
//! - Translational: the centre line is the cubic Hermite curve through the end positions and the
//!   current end tangents t = R(λ) ex, r(ξ) = H1 r_p + H2 l0 t_p + H3 r_q + H4 l0 t_q, and the
//!   kinetic energy is ½ ρA l0 ∫₀¹ |ṙ|² dξ ([V FIS README]: "cubic interpolation of the centre
//!   line", consistent mass). In the reference configuration this is the classical consistent
//!   (Hermite) mass of a beam in bending.
//! - Rotary: J/L · l0 lumped half to each end (SPACAR's log, theory.md §12), the tensor
//!   diag(ρ(Iy+Iz), ρIy, ρIz) in the element's current axes at that end; with ω = 2 Λ̄ λ̇ the
//!   block on λ is 4 Λ̄ᵀ I Λ̄.
//! - Loads of an acceleration field a(r) = W (r − a₀) + g on this mass (gravity: W = 0; a steady
//!   rotation: W = Ω² P): with y = (r_p − a₀, l0 t_p, r_q − a₀, l0 t_q), Hᵢⱼ = ∫₀¹ HᵢHⱼ dξ and
//!   hᵢ = ∫₀¹ Hᵢ dξ = (1/2, 1/12, 1/2, −1/12) the generalised forces of the four Hermite terms
//!   are gᵢ = ρA l0 (Σⱼ Hᵢⱼ W yⱼ + hᵢ g), applied as forces g₁, g₃ at p, q and moments
//!   l0 t × g₂, l0 t × g₄ (the virtual displacement of a tangent term is l0 δθ × t). For gravity
//!   these are the consistent loads of a uniform line load q = ρA g: qL/2 at each end and the end
//!   moments ±qL²/12 (about t × g), which give exact nodal deflections of a beam under its own
//!   weight in the linear range and cancel at the inner nodes of a straight uniform chain.
//!   The rotary inertia adds the gyroscopic moment −Ω × (I Ω) of a steady rotation.

use super::Beam;
use crate::elements::AccelerationField;
use crate::math::inertia::{
    d_rotated, lambda_block, lambda_inertia_force, principal_tensor, rotated_tensor,
    second_rotated, unit,
};
use crate::math::{cross, dot, rotate};
use crate::section::BeamProps;

/// ∫₀¹ Hᵢ Hⱼ dξ for the cubic Hermite functions H1 = 1 − 3ξ² + 2ξ³, H2 = ξ − 2ξ² + ξ³,
/// H3 = 3ξ² − 2ξ³, H4 = −ξ² + ξ³.
pub(crate) const HERMITE: [[f64; 4]; 4] = [
    [13.0 / 35.0, 11.0 / 210.0, 9.0 / 70.0, -13.0 / 420.0],
    [11.0 / 210.0, 1.0 / 105.0, 13.0 / 420.0, -1.0 / 140.0],
    [9.0 / 70.0, 13.0 / 420.0, 13.0 / 35.0, -11.0 / 210.0],
    [-13.0 / 420.0, -1.0 / 140.0, -11.0 / 210.0, 1.0 / 105.0],
];

/// ∫₀¹ Hᵢ dξ of the four Hermite functions.
const HERMITE_INTEGRAL: [f64; 4] = [0.5, 1.0 / 12.0, 0.5, -1.0 / 12.0];

/// The lumped rotary inertia at one end of a beam (half the element's, ρI l₀/2 about its
/// current axes) as a tensor in global axes, with the end's Euler parameters `l`.
fn end_inertia(b: &Beam, p: &BeamProps, l: &[f64]) -> [[f64; 3]; 3] {
    rotated_tensor(l, &b.frame, end_principal(b, p))
}

/// The principal values of the lumped rotary inertia at one end, ρI l₀/2.
fn end_principal(b: &Beam, p: &BeamProps) -> [f64; 3] {
    p.rho_i.map(|v| v * b.l0 / 2.0)
}

/// The mass matrix of a beam with section data on its 14 local coordinates
/// [r_p (3), λ_p (4), r_q (3), λ_q (4)] at their values `xk` (module docs), with the
/// translational kinetic energy weighted by a symmetric `weight` W (½ ρA ∫ ṙᵀ W ṙ instead of
/// ½ ρA ∫ ṙᵀ ṙ; `None` = I), with or without the rotary inertia. W = Ω² P without rotary
/// inertia is the centrifugal softening of a steady rotation. `None` for a beam without mass
/// data.
pub(crate) fn local_mass(
    b: &Beam,
    xk: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
) -> Option<[[f64; 14]; 14]> {
    let p = b.props.as_deref()?;
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
                    let wc = weight.map_or(*vc, |w| std::array::from_fn(|k| dot(w[k], *vc)));
                    m[ia + r][ib + c] += h * dot(*vr, wc);
                }
            }
        }
    }
    if !rotary {
        return Some(m);
    }
    for (l, r0) in [(lp, 3), (lq, 10)] {
        let blk = lambda_block(l, &end_inertia(b, p, l));
        for a in 0..4 {
            for c in 0..4 {
                m[r0 + a][r0 + c] += blk[a][c];
            }
        }
    }
    Some(m)
}

/// The velocity-dependent inertia forces h(x, ẋ) of the beam's mass model at the coordinates
/// `xk` and rates `vk`, so that the inertia forces are M(x) ẍ + h (Lagrange's equations of the
/// kinetic energy of [`local_mass`]; theory.md §9.2, the term M (D²F q̇) q̇):
///
/// - translational: with the Hermite terms y = (r_p, l0 t_p, r_q, l0 t_q), ẏ = J ẋ and
///   ÿ = J ẍ + c, c = (0, l0 ∂²t_p[λ̇_p, λ̇_p], 0, l0 ∂²t_q[λ̇_q, λ̇_q]), the generalised inertia
///   force ρA l0 Σᵢⱼ Hᵢⱼ Jᵢᵀ ÿⱼ has h = ρA l0 Σᵢⱼ Hᵢⱼ Jᵢᵀ cⱼ;
/// - rotary: h = 4 Λ(λ̇)ᵀ I ω_b at each end ([`lambda_velocity_force`]).
///
/// `None` for a beam without mass data.
pub(crate) fn velocity_forces(b: &Beam, xk: &[f64], vk: &[f64]) -> Option<[f64; 14]> {
    // M ẍ + h at ẍ = 0
    inertia_forces(b, xk, vk, &[0.0; 14])
}

/// The inertia forces M(x) ẍ + h(x, ẋ) of the beam at `xk` with rates `vk` and accelerations
/// `ak`, without forming M: the Hermite terms' accelerations ÿⱼ = Jⱼ ẍ + cⱼ give
/// ρA l0 Σᵢⱼ Hᵢⱼ Jᵢᵀ ÿⱼ, and each end's rotary inertia 4 Λᵀ I Λ λ̈ + 4 Λ(λ̇)ᵀ I ω_b
/// ([`velocity_forces`]; equal to [`local_mass`] times ẍ for unit Euler parameters, where
/// Rᵀ Λ̄ = Λ). `None` for a beam without mass data.
pub(crate) fn inertia_forces(b: &Beam, xk: &[f64], vk: &[f64], ak: &[f64]) -> Option<[f64; 14]> {
    let p = b.props.as_deref()?;
    let ex = b.frame[0];
    let ml = p.rho_a * b.l0;
    let mut f = [0.0; 14];
    let first_row = [0usize, 3, 7, 10];
    let mut ydd = [[0.0; 3]; 4];
    let mut jt = [[[0.0; 4]; 3]; 4];
    for a in 0..4 {
        let r0 = first_row[a];
        if a % 2 == 0 {
            ydd[a] = [ak[r0], ak[r0 + 1], ak[r0 + 2]];
        } else {
            let (l, ld, ldd) = (&xk[r0..r0 + 4], &vk[r0..r0 + 4], &ak[r0..r0 + 4]);
            jt[a] = d_rotated(l, ex);
            let c = second_rotated(l, ld, ex);
            ydd[a] = std::array::from_fn(|k| {
                b.l0 * ((0..4).map(|m| jt[a][k][m] * ldd[m]).sum::<f64>() + c[k])
            });
        }
    }
    for a in 0..4 {
        let s: [f64; 3] =
            std::array::from_fn(|k| ml * (0..4).map(|j| HERMITE[a][j] * ydd[j][k]).sum::<f64>());
        let r0 = first_row[a];
        if a % 2 == 0 {
            for k in 0..3 {
                f[r0 + k] += s[k];
            }
        } else {
            for col in 0..4 {
                f[r0 + col] += b.l0 * (0..3).map(|k| jt[a][k][col] * s[k]).sum::<f64>();
            }
        }
    }
    // the end's tensor in its own axes: `end_inertia` at the reference orientation
    let i_body = principal_tensor(&b.frame, end_principal(b, p));
    for r0 in [3usize, 10] {
        let (l, ld, ldd) = (&xk[r0..r0 + 4], &vk[r0..r0 + 4], &ak[r0..r0 + 4]);
        let g = lambda_inertia_force(l, ld, ldd, &i_body);
        for c in 0..4 {
            f[r0 + c] += g[c];
        }
    }
    Some(f)
}

/// The loads of an acceleration field on the beam's mass at the coordinates `xk` (module docs):
/// (force, moment) at p and at q, global axes; `None` for a beam without mass data.
pub(crate) fn field_loads(
    b: &Beam,
    xk: &[f64],
    field: &AccelerationField,
) -> Option<[([f64; 3], [f64; 3]); 2]> {
    let p = b.props.as_deref()?;
    let (lp, lq) = (
        [xk[3], xk[4], xk[5], xk[6]],
        [xk[10], xk[11], xk[12], xk[13]],
    );
    let ex = b.frame[0];
    let (tp, tq) = (rotate(&lp, ex), rotate(&lq, ex));
    let (ltp, ltq) = (tp.map(|v| b.l0 * v), tq.map(|v| b.l0 * v));
    let a0 = field.point;
    let y = [
        [xk[0] - a0[0], xk[1] - a0[1], xk[2] - a0[2]],
        ltp,
        [xk[7] - a0[0], xk[8] - a0[1], xk[9] - a0[2]],
        ltq,
    ];
    let wy: [[f64; 3]; 4] = std::array::from_fn(|j| std::array::from_fn(|k| dot(field.w[k], y[j])));
    let ml = p.rho_a * b.l0;
    let g: [[f64; 3]; 4] = std::array::from_fn(|i| {
        std::array::from_fn(|k| {
            ml * ((0..4).map(|j| HERMITE[i][j] * wy[j][k]).sum::<f64>()
                + HERMITE_INTEGRAL[i] * field.uniform[k])
        })
    });
    let mut out = [(g[0], cross(ltp, g[1])), (g[2], cross(ltq, g[3]))];
    // the gyroscopic moment of the lumped rotary inertia at each end
    if field.omega != [0.0; 3] {
        for (end, l) in out.iter_mut().zip([&lp, &lq]) {
            let m = field.gyroscopic_moment(&end_inertia(b, p, l));
            for k in 0..3 {
                end.1[k] += m[k];
            }
        }
    }
    Some(out)
}

fn col(d: &[[f64; 4]; 3], c: usize, l0: f64) -> [f64; 3] {
    [l0 * d[0][c], l0 * d[1][c], l0 * d[2][c]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::testing::Rng;

    /// The combined inertia forces equal M ẍ + h with the mass matrix, for unit Euler
    /// parameters.
    #[test]
    fn inertia_forces_equal_mass_matrix_times_acceleration_plus_velocity_forces() {
        let mut b = Beam::new([0, 1], [0.0; 3], [0.7, 0.2, -0.1], None).unwrap();
        b.set_props(BeamProps {
            rho_a: 1.3,
            rho_i: [0.4, 0.1, 0.3],
            ..Default::default()
        });
        let mut rng = Rng(31);
        for _ in 0..5 {
            let mut x: [f64; 14] = std::array::from_fn(|_| rng.next());
            for r0 in [3, 10] {
                let n = (0..4).map(|k| x[r0 + k] * x[r0 + k]).sum::<f64>().sqrt();
                (0..4).for_each(|k| x[r0 + k] /= n);
            }
            let v: [f64; 14] = std::array::from_fn(|_| rng.next());
            let a: [f64; 14] = std::array::from_fn(|_| rng.next());
            let m = local_mass(&b, &x, None, true).unwrap();
            let h = velocity_forces(&b, &x, &v).unwrap();
            let f = inertia_forces(&b, &x, &v, &a).unwrap();
            for i in 0..14 {
                let want: f64 = (0..14).map(|j| m[i][j] * a[j]).sum::<f64>() + h[i];
                assert!(
                    (f[i] - want).abs() < 1e-12 * (1.0 + want.abs()),
                    "{i}: {} vs {want}",
                    f[i]
                );
            }
        }
    }

    /// h = Ṁ ẋ − ½ ∂(ẋᵀ M ẋ)/∂x (Lagrange's equations of T = ½ ẋᵀ M(x) ẋ), with the derivatives
    /// of the mass matrix taken by central differences: an independent check of
    /// [`velocity_forces`] against [`local_mass`].
    #[test]
    fn velocity_forces_match_lagrange_by_differences_of_the_mass_matrix() {
        let mut b = Beam::new(
            [0, 1],
            [0.1, -0.2, 0.3],
            [0.9, 0.4, 0.1],
            Some([0.0, 0.0, 1.0]),
        )
        .unwrap();
        b.set_props(BeamProps {
            ea: 1.0,
            gj: 1.0,
            eiy: 1.0,
            eiz: 1.0,
            rho_a: 2.7,
            rho_i: [0.5, 0.2, 0.3],
            ..Default::default()
        });
        let mut rng = Rng(23);
        for _ in 0..5 {
            let mut x: [f64; 14] = std::array::from_fn(|_| 0.3 * rng.next());
            for (r0, n) in [(0usize, [0.1, -0.2, 0.3]), (7, [0.9, 0.4, 0.1])] {
                for k in 0..3 {
                    x[r0 + k] += n[k];
                }
            }
            x[3] += 1.0;
            x[10] += 1.0;
            let v: [f64; 14] = std::array::from_fn(|_| rng.next());
            let h = velocity_forces(&b, &x, &v).unwrap();
            let mass = |x: &[f64; 14]| local_mass(&b, x, None, true).unwrap();
            let e = 1e-6;
            let shifted =
                |d: &[f64; 14], s: f64| -> [f64; 14] { std::array::from_fn(|i| x[i] + s * d[i]) };
            // Ṁ ẋ: derivative of M along ẋ
            let (mp, mm) = (mass(&shifted(&v, e)), mass(&shifted(&v, -e)));
            for i in 0..14 {
                let mdot_v: f64 = (0..14)
                    .map(|j| (mp[i][j] - mm[i][j]) / (2.0 * e) * v[j])
                    .sum();
                let unit: [f64; 14] = std::array::from_fn(|k| if k == i { 1.0 } else { 0.0 });
                let quad = |m: &[[f64; 14]; 14]| -> f64 {
                    (0..14)
                        .map(|a| (0..14).map(|c| v[a] * m[a][c] * v[c]).sum::<f64>())
                        .sum()
                };
                let dq = (quad(&mass(&shifted(&unit, e))) - quad(&mass(&shifted(&unit, -e))))
                    / (2.0 * e);
                let fd = mdot_v - 0.5 * dq;
                assert!(
                    (h[i] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "coordinate {i}: {} vs {fd}",
                    h[i]
                );
            }
        }
    }
}
