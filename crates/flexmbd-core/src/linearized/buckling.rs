//! Buckling load multipliers and the stability of the state (theory.md §13.3), with the
//! condition of the material stiffness: all on the minimal coordinates Z, the null space of G.
//!
//! - Buckling: (K_m + μ K_g) v = 0 in Z, i.e. SPACAR's eig(−K0, G0): μ is the factor by which
//!   the current load may be multiplied before the tangent stiffness becomes singular.
//! - Stability: the number of negative eigenvalues of Zᵀ (K_m + K_g) Z (buckling multipliers
//!   below 1); non-zero means the configuration has buckled.

use super::Tangent;
use crate::linalg::sym_def_eigen;
use crate::statics::linear::{Buckling, LinearError};
use faer::Mat;

/// Null-space basis of G (columns), by SVD.
fn null_space(g: &Mat<f64>) -> Result<Mat<f64>, crate::linalg::LinalgError> {
    let nf = g.ncols();
    if g.nrows() == 0 {
        return Ok(Mat::identity(nf, nf));
    }
    let f = crate::linalg::svd(g.as_ref(), "constraint Jacobian G")?;
    let tol = f64::EPSILON.sqrt() * f.s.first().copied().unwrap_or(0.0);
    let r = crate::linalg::numerical_rank(&f.s, tol);
    Ok(Mat::from_fn(nf, nf - r, |i, j| f.V[(i, r + j)]))
}

fn sym(a: &Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// Buckling multipliers (at most `count` of each sign) at the linearised state.
pub fn buckling(t: &Tangent, count: usize) -> Result<Buckling, LinearError> {
    let (model, lin) = (t.model(), t.dense());
    let z = null_space(&lin.g)?;
    let km = sym(&(z.transpose() * &lin.km * &z));
    let kg = sym(&(z.transpose() * &lin.kg * &z));
    // (K_m + μ K_g) v = 0  ⇔  −K_g v = (1/μ) K_m v
    let (nu, v) = sym_def_eigen(
        (-&kg).as_ref(),
        km.as_ref(),
        "material stiffness",
        "the model has a zero-stiffness motion (a mechanism): fix it or give it stiffness",
    )?;
    let mut pos: Vec<(f64, usize)> = Vec::new();
    let mut neg: Vec<f64> = Vec::new();
    let numax = nu.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    for (i, &n) in nu.iter().enumerate() {
        if n > 1e-12 * numax {
            pos.push((1.0 / n, i));
        } else if n < -1e-12 * numax {
            neg.push(1.0 / n);
        }
    }
    pos.sort_by(|a, b| a.0.total_cmp(&b.0));
    neg.sort_by(|a, b| b.total_cmp(a));
    pos.truncate(count);
    neg.truncate(count);
    let modes = pos
        .iter()
        .map(|&(_, i)| {
            let q = Mat::from_fn(z.ncols(), 1, |r, _| v[(r, i)]);
            let dxf = &z * &q;
            let mut dx = vec![0.0; model.nx];
            for (xi, u) in lin.unknown.iter().enumerate() {
                if let Some(u) = u {
                    dx[xi] = dxf[(*u, 0)];
                }
            }
            dx
        })
        .collect();
    Ok(Buckling {
        multipliers: pos.iter().map(|p| p.0).collect(),
        reversed: neg,
        modes,
    })
}

/// Number of negative eigenvalues of the tangent stiffness Zᵀ(K_m + K_g)Z in the minimal
/// coordinates: zero for a stable equilibrium. With K_m = L Lᵀ its inertia is that of
/// I − L⁻¹(−K_g)L⁻ᵀ, so it equals the number of buckling multipliers μ < 1 — a test independent
/// of the units of the coordinates (metres and Euler parameters).
pub fn unstable_directions(t: &Tangent) -> Result<usize, LinearError> {
    let b = buckling(t, usize::MAX)?;
    Ok(b.multipliers.iter().filter(|&&m| m < 1.0 - 1e-9).count())
}

/// Condition numbers above this make the linearised figures unreliable: with ε ≈ 2.2e-16 the
/// relative error of a solve with the stiffness reaches about ε κ = 2e-3 of the largest
/// quantities, and the small ones (the compliance of a stiff part carried by a soft one, a
/// buckling multiplier near 1) lose their meaning first. Measured on a strip of two materials
/// in series (tests/reliability/manual_wrong_compliance_stiffness_ratio): E ratio 1e8, κ = 2e12,
/// support stiffness off by 2e-5; 1e9, κ = 2e13, 2e-4; 1e11, κ = 3e15, 2e-2; 1e12: wrong sign.
pub const ILL_CONDITIONED: f64 = 1e13;

/// The condition number of the material stiffness K_m restricted to the null space of the
/// constraints, after symmetric diagonal scaling by diag(K_m)^-½ (which makes it independent of
/// the units of the coordinates: metres and Euler parameters): λ_max / λ_min of the scaled,
/// reduced matrix, at most 1/ε (a smallest eigenvalue at round-off). `None` when it cannot be
/// measured (no free direction, no stiffness, a matrix that is not finite).
pub fn stiffness_condition(t: &Tangent) -> Option<f64> {
    let lin = t.dense();
    if lin.km.nrows() == 0 || !crate::linalg::all_finite(&lin.km) {
        return None;
    }
    let z = null_space(&lin.g).ok()?;
    let n = z.ncols();
    if n == 0 {
        return None;
    }
    let kr = sym(&(z.transpose() * &lin.km * &z));
    let dmax = (0..n).fold(0.0f64, |m, i| m.max(kr[(i, i)]));
    if !(dmax > 0.0 && dmax.is_finite()) {
        return None;
    }
    let d: Vec<f64> = (0..n)
        .map(|i| 1.0 / kr[(i, i)].max(f64::EPSILON * dmax).sqrt())
        .collect();
    let ks = Mat::from_fn(n, n, |i, j| d[i] * kr[(i, j)] * d[j]);
    let ev = ks.self_adjoint_eigenvalues(faer::Side::Lower).ok()?;
    let lmax = ev.iter().fold(0.0f64, |m, l| m.max(l.abs()));
    let lmin = ev.iter().fold(f64::INFINITY, |m, &l| m.min(l));
    // a smallest eigenvalue at round-off (of either sign) is a condition number beyond 1/ε
    (lmax > 0.0 && lmax.is_finite()).then(|| lmax / lmin.max(f64::EPSILON * lmax))
}
