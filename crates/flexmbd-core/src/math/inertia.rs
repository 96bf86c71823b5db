//! Rotational kinematics of inertia: the derivative of a rotated vector with respect to the Euler
//! parameters, inertia tensors that turn with a node, and their blocks on λ (theory.md §12).

use super::{cross, dot, lambda_bar, rotate};

/// The unit vector along global axis `k`.
pub fn unit(k: usize) -> [f64; 3] {
    let mut v = [0.0; 3];
    v[k] = 1.0;
    v
}

/// ∂(R(λ) a)/∂λ (3 × 4), in closed form: R(λ) a = r/n² with
/// r = (λ0² − v·v) a + 2 (v·a) v + 2 λ0 (v × a), n² = λ0² + v·v, v = (λ1, λ2, λ3)
/// (as [`rotate`]).
pub fn d_rotated(l: &[f64], a: [f64; 3]) -> [[f64; 4]; 3] {
    let (l0, v) = (l[0], [l[1], l[2], l[3]]);
    let vv = dot(v, v);
    let va = dot(v, a);
    let n2 = l0 * l0 + vv;
    let vxa = cross(v, a);
    let c0 = l0 * l0 - vv;
    let r: [f64; 3] = std::array::from_fn(|i| c0 * a[i] + 2.0 * va * v[i] + 2.0 * l0 * vxa[i]);
    let mut dr = [[0.0; 4]; 3];
    for i in 0..3 {
        dr[i][0] = 2.0 * l0 * a[i] + 2.0 * vxa[i];
    }
    for k in 0..3 {
        let ek = unit(k);
        let exa = cross(ek, a);
        for i in 0..3 {
            dr[i][k + 1] =
                -2.0 * v[k] * a[i] + 2.0 * a[k] * v[i] + 2.0 * va * ek[i] + 2.0 * l0 * exa[i];
        }
    }
    let dn2 = [2.0 * l0, 2.0 * v[0], 2.0 * v[1], 2.0 * v[2]];
    // (dr − r dn2ᵀ/n²)/n², with one division
    let inv = 1.0 / n2;
    let mut out = [[0.0; 4]; 3];
    for i in 0..3 {
        for j in 0..4 {
            out[i][j] = (dr[i][j] - r[i] * dn2[j] * inv) * inv;
        }
    }
    out
}

/// Inertia tensor block on λ: 4 Λ̄ᵀ I Λ̄ (4 × 4), I in global axes (ω = 2 Λ̄ λ̇).
pub fn lambda_block(l: &[f64], i: &[[f64; 3]; 3]) -> [[f64; 4]; 4] {
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

/// R(λ) diag(d) Rᵀ: a tensor with principal values `d` along the axes whose reference directions
/// are the rows of `frame`, turned by the Euler parameters `l`.
pub fn rotated_tensor(l: &[f64], frame: &[[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
    let lam = [l[0], l[1], l[2], l[3]];
    let axes: [[f64; 3]; 3] = std::array::from_fn(|k| rotate(&lam, frame[k]));
    principal_tensor(&axes, d)
}

/// Σₖ dₖ aₖ aₖᵀ: the tensor with principal values `d` along the (unit) `axes`, the rows of
/// `axes`; [`rotated_tensor`] at the reference orientation (λ = (1, 0, 0, 0), where
/// [`rotate`] returns the axes unchanged).
pub fn principal_tensor(axes: &[[f64; 3]; 3], d: [f64; 3]) -> [[f64; 3]; 3] {
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

/// The block on the Euler parameters `l` of an inertia tensor given in global axes at the
/// reference orientation: the tensor turns with the node (R I Rᵀ), then 4 Λ̄ᵀ (R I Rᵀ) Λ̄.
pub fn node_inertia_block(l: &[f64], tensor: &[[f64; 3]; 3]) -> [[f64; 4]; 4] {
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

/// The 3 × 4 matrix Λ(λ) with ω_body = 2 Λ λ̇ (angular velocity in the node's own axes;
/// theory.md §2.2). Like [`super::lambda_bar`] it is linear in λ and Λ(a) b = −Λ(b) a.
pub fn lambda_body(l: &[f64]) -> [[f64; 4]; 3] {
    [
        [-l[1], l[0], l[3], -l[2]],
        [-l[2], -l[3], l[0], l[1]],
        [-l[3], l[2], -l[1], l[0]],
    ]
}

/// The second derivative of R(λ) a along the Euler-parameter rate `ld`:
/// ∂²(R(λ) a)/∂λ² [λ̇, λ̇], so that d²(R a)/dt² = ∂(R a)/∂λ λ̈ + this (exact, of the formula of
/// [`rotate`], in closed form). With the numerator of [`rotate`] written as the symmetric
/// bilinear form r(λ) = Q(λ, λ),
/// Q(p, s) = (p0 s0 − p̄·s̄) a + (p̄·a) s̄ + (s̄·a) p̄ + p0 (s̄ × a) + s0 (p̄ × a),
/// and n = λᵀλ, R a = r/n has along λ̇ the second derivative
/// (r'' − 2 r' n'/n − r n''/n + 2 r n'²/n²)/n with r' = 2 Q(λ, λ̇), r'' = 2 Q(λ̇, λ̇),
/// n' = 2 λᵀλ̇ and n'' = 2 λ̇ᵀλ̇.
pub fn second_rotated(l: &[f64], ld: &[f64], a: [f64; 3]) -> [f64; 3] {
    let (l, ld) = ([l[0], l[1], l[2], l[3]], [ld[0], ld[1], ld[2], ld[3]]);
    let (r, r1, r2) = (
        rotation_form(&l, &l, a),
        rotation_form(&l, &ld, a),
        rotation_form(&ld, &ld, a),
    );
    let dot4 = |p: &[f64; 4], s: &[f64; 4]| p[0] * s[0] + p[1] * s[1] + p[2] * s[2] + p[3] * s[3];
    // n'/n and n''/n, with one division
    let inv = 1.0 / dot4(&l, &l);
    let (a1, a2) = (2.0 * dot4(&l, &ld) * inv, 2.0 * dot4(&ld, &ld) * inv);
    std::array::from_fn(|i| {
        (2.0 * r2[i] - 4.0 * r1[i] * a1 - r[i] * a2 + 2.0 * r[i] * a1 * a1) * inv
    })
}

/// The symmetric bilinear form Q(p, s) of [`second_rotated`], Q(λ, λ) the numerator of
/// [`rotate`].
#[inline(always)]
fn rotation_form(p: &[f64; 4], s: &[f64; 4], a: [f64; 3]) -> [f64; 3] {
    let (pv, sv) = ([p[1], p[2], p[3]], [s[1], s[2], s[3]]);
    let c0 = p[0] * s[0] - dot(pv, sv);
    let (pa, sa) = (dot(pv, a), dot(sv, a));
    let (px, sx) = (cross(pv, a), cross(sv, a));
    std::array::from_fn(|i| c0 * a[i] + pa * sv[i] + sa * pv[i] + p[0] * sx[i] + s[0] * px[i])
}

/// The velocity-dependent inertia force on the Euler parameters of a body with the inertia
/// tensor `i_body` in its own axes (global axes at the reference orientation) and kinetic energy
/// T = ½ ω_bᵀ I ω_b, ω_b = 2 Λ(λ) λ̇ (mass block 4 Λᵀ I Λ, equal to
/// [`lambda_block`]`(λ, R I Rᵀ)` for unit λ). Lagrange's equations
/// d/dt ∂T/∂λ̇ − ∂T/∂λ = 4 Λᵀ I Λ λ̈ + h with Λ(λ̇) λ̇ = 0 and ∂ω_b/∂λ = −2 Λ(λ̇) give
/// h = 4 Λ(λ̇)ᵀ I ω_b.
pub fn lambda_velocity_force(l: &[f64], ld: &[f64], i_body: &[[f64; 3]; 3]) -> [f64; 4] {
    let lb = lambda_body(l);
    let w: [f64; 3] = std::array::from_fn(|r| 2.0 * (0..4).map(|c| lb[r][c] * ld[c]).sum::<f64>());
    let iw: [f64; 3] = std::array::from_fn(|r| dot(i_body[r], w));
    let ldb = lambda_body(ld);
    std::array::from_fn(|c| 4.0 * (0..3).map(|r| ldb[r][c] * iw[r]).sum::<f64>())
}

/// The inertia force on the Euler parameters of a body with the inertia tensor `i_body` in its
/// own axes: 4 Λᵀ I Λ λ̈ + [`lambda_velocity_force`] (the mass block of [`lambda_block`] for
/// unit λ, where Rᵀ Λ̄ = Λ, times λ̈, without forming it).
pub fn lambda_inertia_force(
    l: &[f64],
    ld: &[f64],
    ldd: &[f64],
    i_body: &[[f64; 3]; 3],
) -> [f64; 4] {
    let lb = lambda_body(l);
    let wd: [f64; 3] = std::array::from_fn(|r| (0..4).map(|c| lb[r][c] * ldd[c]).sum::<f64>());
    let iw: [f64; 3] = std::array::from_fn(|r| dot(i_body[r], wd));
    let h = lambda_velocity_force(l, ld, i_body);
    std::array::from_fn(|c| 4.0 * (0..3).map(|r| lb[r][c] * iw[r]).sum::<f64>() + h[c])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kinetic energy ½ ω_bᵀ I ω_b of a body with the inertia tensor `i_body` in its own axes,
    /// ω_b = 2 Λ(λ) λ̇ ([`lambda_velocity_force`]).
    pub fn lambda_kinetic_energy(l: &[f64], ld: &[f64], i_body: &[[f64; 3]; 3]) -> f64 {
        let lb = lambda_body(l);
        let w: [f64; 3] =
            std::array::from_fn(|r| 2.0 * (0..4).map(|c| lb[r][c] * ld[c]).sum::<f64>());
        0.5 * (0..3).map(|r| w[r] * dot(i_body[r], w)).sum::<f64>()
    }

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
    /// The velocity force of a rotating body against Lagrange's equations by central
    /// differences of the kinetic energy T(λ, λ̇) = ½ λ̇ᵀ 4 Λᵀ I Λ λ̇:
    /// h = (∂²T/∂λ̇∂λ) λ̇ − ∂T/∂λ.
    #[test]
    fn lambda_velocity_force_matches_lagrange_by_differences() {
        let mut rng = crate::elements::testing::Rng(5);
        let i_body = [[2.0, 0.3, -0.1], [0.3, 1.5, 0.2], [-0.1, 0.2, 0.7]];
        let t = |l: &[f64; 4], ld: &[f64; 4]| lambda_kinetic_energy(l, ld, &i_body);
        for _ in 0..10 {
            let l: [f64; 4] = std::array::from_fn(|_| rng.next());
            let ld: [f64; 4] = std::array::from_fn(|_| rng.next());
            let h = lambda_velocity_force(&l, &ld, &i_body);
            let e = 1e-5;
            for j in 0..4 {
                // ∂T/∂λ_j
                let (mut lp, mut lm) = (l, l);
                lp[j] += e;
                lm[j] -= e;
                let dt_dl = (t(&lp, &ld) - t(&lm, &ld)) / (2.0 * e);
                // Σ_k ∂²T/∂λ̇_j∂λ_k λ̇_k: derivative of ∂T/∂λ̇_j along λ̇ in λ
                let dtdv = |l: &[f64; 4]| {
                    let (mut vp, mut vm) = (ld, ld);
                    vp[j] += e;
                    vm[j] -= e;
                    (t(l, &vp) - t(l, &vm)) / (2.0 * e)
                };
                let lpp: [f64; 4] = std::array::from_fn(|k| l[k] + e * ld[k]);
                let lmm: [f64; 4] = std::array::from_fn(|k| l[k] - e * ld[k]);
                let mixed = (dtdv(&lpp) - dtdv(&lmm)) / (2.0 * e);
                let fd = mixed - dt_dl;
                assert!(
                    (h[j] - fd).abs() < 1e-5 * (1.0 + fd.abs()),
                    "{j}: {} vs {fd}",
                    h[j]
                );
            }
        }
    }

    /// Euler parameters (any length), their rate and a body vector, pseudo-random in (−1, 1).
    fn random_case(rng: &mut crate::elements::testing::Rng) -> ([f64; 4], [f64; 4], [f64; 3]) {
        (
            std::array::from_fn(|_| rng.next()),
            std::array::from_fn(|_| rng.next()),
            std::array::from_fn(|_| rng.next()),
        )
    }

    /// The closed form against the second-order jet of [`rotate`] (exact derivatives of the
    /// same formula), for Euler parameters of any length.
    #[test]
    fn second_rotated_equals_the_jet_of_rotate() {
        use crate::math::jet::{Jet2, Scalar};
        let mut rng = crate::elements::testing::Rng(29);
        for _ in 0..20 {
            let (l, ld, a) = random_case(&mut rng);
            let lj: [Jet2<1>; 4] = std::array::from_fn(|i| Jet2 {
                v: l[i],
                g: [ld[i]],
                h: [[0.0]],
            });
            let want = rotate(&lj, a.map(Jet2::<1>::cst)).map(|c| c.h[0][0]);
            let got = second_rotated(&l, &ld, a);
            let scale = want.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
            for i in 0..3 {
                assert!(
                    (got[i] - want[i]).abs() <= 1e-12 * scale,
                    "{i}: {} vs {}",
                    got[i],
                    want[i]
                );
            }
        }
    }

    #[test]
    fn second_rotated_matches_central_differences() {
        let mut rng = crate::elements::testing::Rng(17);
        for _ in 0..10 {
            let (l, ld, a) = random_case(&mut rng);
            let s = second_rotated(&l, &ld, a);
            let e = 1e-4;
            let at = |k: f64| {
                let lk: [f64; 4] = std::array::from_fn(|i| l[i] + k * ld[i]);
                rotate(&lk, a)
            };
            let (p, c, m) = (at(e), at(0.0), at(-e));
            for i in 0..3 {
                let fd = (p[i] - 2.0 * c[i] + m[i]) / (e * e);
                assert!(
                    (s[i] - fd).abs() < 1e-5 * (1.0 + fd.abs()),
                    "{i}: {} vs {fd}",
                    s[i]
                );
            }
        }
    }
}
