//! The dense eigen solver: all eigenpairs of the condensed problem with a diagonal mass, the
//! low end of the spectrum from a shifted inverse.

use super::ModalError;
use crate::linalg::{all_finite, sym_def_eigen};
use faer::Mat;

/// All eigenpairs of K y = λ D y for symmetric K and a positive diagonal D (`mm`): λ ascending,
/// Y D-orthonormal.
///
/// The plain reduction C = D^-½ K D^-½ has an absolute eigenvalue error of about ε‖C‖, and ‖C‖
/// is the highest ω² of the model. With masses over many decades (the rotary inertia of a thin
/// sheet is 1e-8 of its translational mass) that error reaches the lowest modes: a 24-element
/// strip of 0.2 mm lost 0.2 % on its first frequency. So the low end of the spectrum comes from
/// the shifted inverse C' = D^½ (K + sD)⁻¹ D^½ (eigenvalues 1/(λ + s), inverse iteration in
/// one dense step) with s the lowest eigenvalue of the plain pass above its noise; its relative
/// error grows like ε λ/s, the plain pass's like ε λ_max/λ, so modes below √(s λ_max) are
/// taken from the shifted pass and the rest from the plain one.
pub(super) fn diagonal_mass_eigen(
    k: &Mat<f64>,
    mm: &[f64],
) -> Result<(Vec<f64>, Mat<f64>), ModalError> {
    let n = mm.len();
    let d = Mat::from_fn(n, n, |i, j| if i == j { mm[i] } else { 0.0 });
    let (mut lam, mut v) = sym_def_eigen(
        k.as_ref(),
        d.as_ref(),
        "reduced mass",
        "a mass-carrying direction has no inertia",
    )?;
    let lmax = lam.iter().fold(0.0f64, |m, l| m.max(l.abs()));
    if n < 2 || lmax == 0.0 || !lmax.is_finite() {
        return Ok((lam, v));
    }
    let noise = 1e3 * n as f64 * f64::EPSILON * lmax;
    let mut s = lam.iter().copied().find(|&l| l > noise).unwrap_or(noise);
    let sq: Vec<f64> = mm.iter().map(|m| m.sqrt()).collect();
    for _ in 0..4 {
        // K + sD regular (s may meet an eigenvalue: move it)
        let a = Mat::from_fn(n, n, |i, j| {
            k[(i, j)] + if i == j { s * mm[i] } else { 0.0 }
        });
        let rhs = Mat::from_fn(n, n, |i, j| if i == j { sq[i] } else { 0.0 });
        let lu = a.partial_piv_lu();
        let x = faer::prelude::Solve::solve(&lu, &rhs);
        // C' and its round-off: the asymmetry of D^½ X estimates the error of its entries
        let mut asym = 0.0f64;
        for i in 0..n {
            for j in 0..i {
                asym = asym.max((sq[i] * x[(i, j)] - sq[j] * x[(j, i)]).abs());
            }
        }
        let c = Mat::from_fn(n, n, |i, j| 0.5 * (sq[i] * x[(i, j)] + sq[j] * x[(j, i)]));
        let evd = match c.self_adjoint_eigen(faer::Side::Lower) {
            Ok(e) if all_finite(&x) => e,
            _ => {
                s *= 1.7;
                continue;
            }
        };
        let mu = evd.S().column_vector();
        let y = evd.U();
        // λ = 1/μ − s, ascending; v = D^-½ y is D-orthonormal. Kept: |λ + s| ≤ cross + s, i.e.
        // |μ| ≥ 1/(cross + s), and |μ| well above the round-off of C' (the tiny μ of the high
        // modes are round-off of either sign)
        let cross = (s * lmax).sqrt();
        let mu_max = (0..n).fold(0.0f64, |m, i| m.max(mu[i].abs()));
        let mu_min = (1.0 / (cross + s)).max(1e3 * (asym + n as f64 * f64::EPSILON * mu_max));
        let mut order: Vec<(f64, usize)> = (0..n)
            .filter(|&i| mu[i].abs() >= mu_min)
            .map(|i| (1.0 / mu[i] - s, i))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let low = order.len();
        // the plain pass supplies the rest, from the top: it must be above its own noise; and
        // no eigenvalue of the shifted pass may lie below the whole plain spectrum (a round-off
        // μ of C' that passed the filter)
        let spurious = order.iter().filter(|o| o.0 < lam[0] - noise).count();
        let unresolved = spurious + (low..n).filter(|&j| lam[j].abs() <= noise).count();
        if unresolved > 0 {
            let lowest = order
                .iter()
                .map(|o| o.0)
                .find(|&l| l > 0.0)
                .unwrap_or(s)
                .min(s);
            return Err(ModalError::DenseInaccurate {
                unresolved,
                n,
                spread: lmax / lowest,
            });
        }
        for (j, &(l, i)) in order.iter().enumerate() {
            lam[j] = l;
            for r in 0..n {
                v[(r, j)] = y[(r, i)] / sq[r];
            }
        }
        return Ok((lam, v));
    }
    Ok((lam, v))
}
