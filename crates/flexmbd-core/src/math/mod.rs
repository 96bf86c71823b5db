//! Small math shared by elements and analyses: 3-vectors generic over [`Scalar`], Euler
//! parameters. Knows nothing about the model (MuJoCo's `mju_` layer).
//!
//! All small fixed-size vectors are plain `[T; 3]` arrays with the hand-written helpers below;
//! this is the project's one choice for small vector math (no nalgebra).

pub(crate) mod blocks;
pub mod gmres;
pub mod inertia;
pub mod jet;
pub mod lanczos;
pub(crate) mod lists;
pub mod small_eigen;
pub mod sparse_lu;

pub use jet::{Jet1, Jet2, Scalar, SmoothMap};

/// 3-vector.
pub type V3<T> = [T; 3];

/// a + b.
pub fn add<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
/// a − b.
pub fn sub<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// aᵀ b.
pub fn dot<T: Scalar>(a: V3<T>, b: V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// a × b.
pub fn cross<T: Scalar>(a: V3<T>, b: V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// c a for a scalar c carrying derivatives.
pub fn mul<T: Scalar>(c: T, a: V3<T>) -> V3<T> {
    [c * a[0], c * a[1], c * a[2]]
}
/// A constant vector lifted to T.
pub fn cst3<T: Scalar>(a: [f64; 3]) -> V3<T> {
    [T::cst(a[0]), T::cst(a[1]), T::cst(a[2])]
}
/// ‖a‖ (f64).
pub fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
/// a/‖a‖ (f64); the caller guarantees ‖a‖ > 0.
pub fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = norm(a);
    [a[0] / n, a[1] / n, a[2] / n]
}

/// Euler parameters λ = (λ0, λ1, λ2, λ3), λ0 the scalar part (SPACAR's order).
pub type Euler<T> = [T; 4];

/// R(λ) a for Euler parameters λ that need not be of unit length: the rotation of λ/‖λ‖,
///
/// R(λ) = ((λ0² − λ̄ᵀλ̄) I + 2 λ̄ λ̄ᵀ + 2 λ0 λ̃) / (λᵀλ)   (theory.md §2.2, divided by λᵀλ).
///
/// Dividing by λᵀλ makes every deformation independent of the length of λ, so that the
/// Euler-parameter normalisation row of Dcc is orthogonal to all element rows (docs/rotations.md).
pub fn rotate<T: Scalar>(l: &Euler<T>, a: V3<T>) -> V3<T> {
    let lv = [l[1], l[2], l[3]];
    let n2 = l[0] * l[0] + dot(lv, lv);
    // (λ0² − λ̄ᵀλ̄) a + 2 λ̄ (λ̄ᵀ a) + 2 λ0 (λ̄ × a)
    let c0 = l[0] * l[0] - dot(lv, lv);
    let c1 = dot(lv, a).scale(2.0);
    let c2 = l[0].scale(2.0);
    let r = add(add(mul(c0, a), mul(c1, lv)), mul(c2, cross(lv, a)));
    [r[0] / n2, r[1] / n2, r[2] / n2]
}

/// The 3 × 4 matrix Λ̄(λ) with ω = 2 Λ̄ λ̇ (global angular velocity) and, for unit λ and λ̇ ⟂ λ,
/// λ̇ = ½ Λ̄ᵀ ω (theory.md §2.2, [V ST complt.m]).
pub fn lambda_bar(l: &[f64; 4]) -> [[f64; 4]; 3] {
    [
        [-l[1], l[0], -l[3], l[2]],
        [-l[2], l[3], l[0], -l[1]],
        [-l[3], -l[2], l[1], l[0]],
    ]
}

/// Euler parameters of a rotation by `angle` about the unit `axis`.
pub fn euler_from_axis_angle(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

/// Quaternion product a ⊗ b (composition: rotate by b, then by a).
pub fn euler_mul(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The 4 × 4 matrix L(a) of the quaternion product from the left: a ⊗ b = L(a) b (orthogonal
/// for a unit a).
pub fn euler_left(a: &[f64; 4]) -> [[f64; 4]; 4] {
    [
        [a[0], -a[1], -a[2], -a[3]],
        [a[1], a[0], -a[3], a[2]],
        [a[2], a[3], a[0], -a[1]],
        [a[3], -a[2], a[1], a[0]],
    ]
}

/// The rotation matrix R(λ) of [`rotate`] (columns: the rotated unit vectors).
pub fn rotation_matrix(l: &[f64; 4]) -> [[f64; 3]; 3] {
    let mut r = [[0.0; 3]; 3];
    for j in 0..3 {
        let mut e = [0.0; 3];
        e[j] = 1.0;
        let c = rotate(l, e);
        for i in 0..3 {
            r[i][j] = c[i];
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    /// L(a) b is the product of euler_mul, and R is a homomorphism: R(a ⊗ b) = R(a) R(b)
    /// (the composition the co-rotated iteration matrix of the simulation relies on).
    #[test]
    fn left_product_matrix_and_rotation_of_a_product() {
        let a = euler_from_axis_angle(normalize([1.0, -2.0, 0.5]), 0.7);
        let b = euler_from_axis_angle(normalize([0.3, 0.4, -1.0]), -1.9);
        let ab = euler_mul(&a, &b);
        let la = euler_left(&a);
        for i in 0..4 {
            let v: f64 = (0..4).map(|j| la[i][j] * b[j]).sum();
            assert!((v - ab[i]).abs() < 1e-15);
        }
        let (ra, rb, rab) = (
            rotation_matrix(&a),
            rotation_matrix(&b),
            rotation_matrix(&ab),
        );
        for i in 0..3 {
            for j in 0..3 {
                let v: f64 = (0..3).map(|k| ra[i][k] * rb[k][j]).sum();
                assert!((v - rab[i][j]).abs() < 1e-14, "R(a b)[{i}][{j}]");
            }
        }
    }

    #[test]
    fn rotation_about_z_by_quarter_turn() {
        let l = euler_from_axis_angle([0.0, 0.0, 1.0], std::f64::consts::FRAC_PI_2);
        let r = rotate(&l, [1.0, 0.0, 0.0]);
        assert!((r[0]).abs() < 1e-15 && (r[1] - 1.0).abs() < 1e-15 && r[2].abs() < 1e-15);
        // scaling λ does not change the rotation
        let l2 = [2.0 * l[0], 2.0 * l[1], 2.0 * l[2], 2.0 * l[3]];
        let r2 = rotate(&l2, [1.0, 0.0, 0.0]);
        assert!((r2[1] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn lambda_bar_maps_euler_rates_to_angular_velocity() {
        // λ(t) = ω_t ⊗ λ0 with ω_t a small rotation about w: dλ/dt = ½ (0, w) ⊗ λ0
        let l0 = euler_mul(
            &euler_from_axis_angle(normalize([1.0, 2.0, -0.5]), 0.9),
            &euler_from_axis_angle([0.0, 1.0, 0.0], -0.4),
        );
        let w = [0.3, -1.1, 0.7];
        let h = 1e-6;
        let wn = norm(w);
        let lp = euler_mul(&euler_from_axis_angle(normalize(w), wn * h), &l0);
        let lm = euler_mul(&euler_from_axis_angle(normalize(w), -wn * h), &l0);
        let ld: [f64; 4] = std::array::from_fn(|i| (lp[i] - lm[i]) / (2.0 * h));
        let lb = lambda_bar(&l0);
        for r in 0..3 {
            let om: f64 = (0..4).map(|c| 2.0 * lb[r][c] * ld[c]).sum();
            assert!(
                (om - w[r]).abs() < 1e-8,
                "ω component {r}: {om} vs {}",
                w[r]
            );
        }
        // and the rotation matrix derivative agrees: d/dt R a = ω × R a
        let a = [0.2, 0.5, -0.9];
        let ra: [f64; 3] = rotate(&l0, a);
        let rp = rotate(&lp, a);
        let rm = rotate(&lm, a);
        let wx = cross(w, ra);
        for i in 0..3 {
            assert!(((rp[i] - rm[i]) / (2.0 * h) - wx[i]).abs() < 1e-8);
        }
    }
}
