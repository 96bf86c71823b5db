//! The smallest eigenvalues of the tangent stiffness on the constraints at a converged state
//! (docs/statics.md, "Stability along the path"): the stiffness κ of the softest directions,
//! signed, reported at every step of every path and used to locate critical points
//! (`critical.rs`).
//!
//! κ₁ ≤ κ₂ ≤ … are the eigenvalues of Zᵀ S K S Z, with K = K_m + K_g the Newton matrix's
//! stiffness block in the reduced unknowns (the same stiffness as `crate::linearized`, in other
//! coordinates), S = diag(1 for translations, ½ for rotation increments δ and Euler parameters:
//! ω = 2δ, so S turns them into radians) and Z an orthonormal basis of the null space of the
//! kept constraints G S. So a pure translation has κ in N/m, a pure rotation in N·m/rad, and a
//! negative κ is a direction in which the equilibrium is unstable (their number is the
//! inertia count of `arc.rs`). With applied moments, whose load stiffness is unsymmetric,
//! κ is that of the symmetric part.

use super::{assemble_values, Assembled, Part, Setup, StepResult};
use crate::model::Model;
use faer::Mat;

/// How many of the smallest eigenvalues κ every step reports.
pub const TANGENT_EIGENVALUES: usize = 3;

/// The most reduced coordinate unknowns with which κ is computed: the dense eigenvalues of
/// an n × n matrix cost O(n³) at every step (about 10 ms at n = 300); larger models report
/// none.
pub const TANGENT_EIGEN_MAX: usize = 300;

/// The `count` smallest eigenvalues κ (ascending, signed; module docs) of the tangent
/// stiffness assembled in `a` (the reduced system); `None` when the model has more than
/// [`TANGENT_EIGEN_MAX`] reduced coordinates, no free direction, or a matrix that is not
/// finite.
pub(crate) fn smallest_eigenvalues(su: &Setup, a: &Assembled, count: usize) -> Option<Vec<f64>> {
    let red = &su.red;
    let (n, nfr) = (red.n, red.nfr);
    if !a.reduced || nfr == 0 || nfr > TANGENT_EIGEN_MAX || count == 0 {
        return None;
    }
    let s = |i: usize| if red.is_trans[i] { 1.0 } else { 0.5 };
    let mut k = Mat::<f64>::zeros(nfr, nfr);
    let mut g = Mat::<f64>::zeros(n - nfr, nfr);
    let mut vals = a.vals.iter();
    let mut add = |r: usize, c: usize| {
        let v = vals.next().copied().unwrap_or(0.0);
        if r < nfr && c < nfr {
            k[(r, c)] += s(r) * v * s(c);
        } else if c < nfr {
            g[(r - nfr, c)] += v * s(c);
        }
    };
    red.for_each_entry(&mut add);
    for &(r, c) in &a.tail {
        add(r, c);
    }
    let z = if g.nrows() == 0 {
        Mat::identity(nfr, nfr)
    } else {
        let f = crate::linalg::svd(g.as_ref(), "constraint Jacobian G").ok()?;
        let tol = f64::EPSILON.sqrt() * f.s.first().copied().unwrap_or(0.0);
        let r = crate::linalg::numerical_rank(&f.s, tol);
        Mat::from_fn(nfr, nfr - r, |i, j| f.V[(i, r + j)])
    };
    if z.ncols() == 0 || !crate::linalg::all_finite(&k) {
        return None;
    }
    let kz = z.transpose() * &k * &z;
    let kr = Mat::from_fn(kz.nrows(), kz.ncols(), |i, j| {
        0.5 * (kz[(i, j)] + kz[(j, i)])
    });
    let mut ev = kr.self_adjoint_eigenvalues(faer::Side::Lower).ok()?;
    ev.sort_by(f64::total_cmp);
    ev.truncate(count);
    Some(ev)
}

/// The [`TANGENT_EIGENVALUES`] smallest κ at the converged step `st`, from its assembly `a`
/// (assembled again in the reduced unknowns when `a` is not).
pub(super) fn tangent_eigenvalues(
    model: &Model,
    su: &Setup,
    st: &StepResult,
    a: &Assembled,
) -> Option<Vec<f64>> {
    if su.red.nfr > TANGENT_EIGEN_MAX {
        return None;
    }
    if a.reduced {
        return smallest_eigenvalues(su, a, TANGENT_EIGENVALUES);
    }
    let r = assemble_values(
        model,
        su,
        &st.x,
        &st.multipliers,
        st.load_factor,
        Part::Full,
        true,
        Vec::new(),
    );
    smallest_eigenvalues(su, &r, TANGENT_EIGENVALUES)
}
