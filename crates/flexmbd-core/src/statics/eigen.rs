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

use super::{assemble_values, Assembled, KktSolver, Part, Setup, StepResult};
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
    // on this thread: the matrices are small and this runs at every step of a path
    let kz = if g.nrows() == 0 {
        k
    } else {
        use faer::linalg::matmul::matmul;
        use faer::{Accum, Par};
        let mut kz1 = Mat::<f64>::zeros(nfr, z.ncols());
        matmul(
            kz1.as_mut(),
            Accum::Replace,
            k.as_ref(),
            z.as_ref(),
            1.0,
            Par::Seq,
        );
        let mut kz = Mat::<f64>::zeros(z.ncols(), z.ncols());
        matmul(
            kz.as_mut(),
            Accum::Replace,
            z.transpose(),
            kz1.as_ref(),
            1.0,
            Par::Seq,
        );
        kz
    };
    let kr = Mat::from_fn(kz.nrows(), kz.ncols(), |i, j| {
        0.5 * (kz[(i, j)] + kz[(j, i)])
    });
    let mut ev = crate::linalg::sym_eigenvalues_seq(kr.as_ref()).ok()?;
    ev.sort_by(f64::total_cmp);
    ev.truncate(count);
    Some(ev)
}

/// The [`TANGENT_EIGENVALUES`] smallest κ at the converged step `st`, from its assembly `a`
/// (assembled again in the reduced unknowns when `a` is not), when `asked`: dense for models
/// with at most [`TANGENT_EIGEN_MAX`] reduced coordinates; for larger ones the eigenvalues
/// nearest zero ([`nearest_zero_eigenvalues`]), which are the smallest at a stable state.
pub(super) fn tangent_eigenvalues(
    model: &Model,
    su: &Setup,
    st: &StepResult,
    a: &Assembled,
    asked: bool,
) -> Option<Vec<f64>> {
    if !asked {
        return None;
    }
    let reassembled;
    let a = if a.reduced && a.tangent {
        a
    } else {
        reassembled = reduced_at(model, su, st);
        &reassembled
    };
    kappa(su, a, asked)
}

/// The full tangent (`Part::Full`) of the converged step `st` assembled in the reduced
/// unknowns, the system whose κ this module computes.
fn reduced_at(model: &Model, su: &Setup, st: &StepResult) -> Assembled {
    assemble_values(
        model,
        su,
        &st.x,
        &st.multipliers,
        st.load_factor,
        Part::Full,
        true,
        Vec::new(),
    )
}

/// The κ that [`tangent_eigenvalues`] reports, from a reduced assembly `a`, when `asked`.
pub(super) fn kappa(su: &Setup, a: &Assembled, asked: bool) -> Option<Vec<f64>> {
    if !asked {
        None
    } else if su.red.nfr <= TANGENT_EIGEN_MAX {
        smallest_eigenvalues(su, a, TANGENT_EIGENVALUES)
    } else {
        nearest_zero_eigenvalues(su, a, TANGENT_EIGENVALUES)
    }
}

/// Lanczos steps at most for [`nearest_zero_eigenvalues`].
const NEAREST_ZERO_STEPS: usize = 120;

/// Relative residual of a Ritz value of [`nearest_zero_eigenvalues`]: converged below
/// [`NEAREST_ZERO_TOL`], reported up to [`NEAREST_ZERO_KEEP`].
const NEAREST_ZERO_TOL: f64 = 1e-10;
const NEAREST_ZERO_KEEP: f64 = 1e-6;

/// The `count` eigenvalues κ of Zᵀ S K S Z (module docs) nearest zero, ascending, for models
/// too large for the dense eigenvalues: Lanczos on the inverse, whose largest eigenvalues in
/// magnitude are 1/κ. The inverse is applied by the sparse factorisation of the saddle-point
/// matrix [K Gᵀ; G 0] of `a`: y = S⁻¹ x for [K Gᵀ; G 0] [x; λ] = [S⁻¹ b; 0] is y = Z̃ (Z̃ᵀ K̃ Z̃)⁻¹
/// Z̃ᵀ b with K̃ = S K S and Z̃ an orthonormal basis of the null space of G S, so no basis Z is
/// formed. At a stable state (every κ > 0) these are the smallest κ; next to a critical point
/// the one that passes through zero is among them. `None` with applied moments (K is not
/// symmetric there), for a singular tangent, or when Lanczos does not converge.
pub(crate) fn nearest_zero_eigenvalues(
    su: &Setup,
    a: &Assembled,
    count: usize,
) -> Option<Vec<f64>> {
    let red = &su.red;
    let (n, nfr) = (red.n, red.nfr);
    if !a.reduced || !su.moments.is_empty() || nfr == 0 || count == 0 {
        return None;
    }
    let s_inv = |i: usize| if red.is_trans[i] { 1.0 } else { 2.0 };
    let mut kkt = KktSolver::new(su, &a.tail).ok()?;
    let (mut factored, mut failed) = (false, false);
    let mut rhs = vec![0.0; n];
    let mut apply = |x: &[f64], y: &mut [f64]| {
        rhs.fill(0.0);
        for (i, (r, xi)) in rhs.iter_mut().zip(x).enumerate() {
            *r = s_inv(i) * xi;
        }
        let ok = if factored {
            kkt.solve_again(&mut rhs).is_ok()
        } else {
            factored = true;
            kkt.solve(&a.vals, &mut rhs).is_ok() && kkt.reusable()
        };
        if !ok || rhs.iter().any(|v| !v.is_finite()) {
            failed = true;
            y.fill(0.0);
            return;
        }
        for (i, (yi, r)) in y.iter_mut().zip(&rhs).enumerate() {
            *yi = s_inv(i) * r;
        }
    };
    // the start in the range of the inverse (its null space: the directions G S forbids)
    let mut start = vec![0.0; nfr];
    apply(&crate::math::lanczos::start_vector(nfr), &mut start);
    let ritz = crate::math::lanczos::largest_magnitude_eigenvalues(
        start,
        &mut apply,
        count,
        NEAREST_ZERO_STEPS,
        NEAREST_ZERO_TOL,
    )?;
    if failed {
        return None;
    }
    let mut kappa: Vec<f64> = ritz
        .iter()
        .filter(|e| e.value != 0.0 && e.residual <= NEAREST_ZERO_KEEP * e.value.abs())
        .map(|e| 1.0 / e.value)
        .collect();
    kappa.sort_by(f64::total_cmp);
    (!kappa.is_empty()).then_some(kappa)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statics::test_models::column;
    use crate::statics::{setup, solve_path, StaticOptions};

    /// The column of [`column`] with inextensible beams (elongation rigid: constraints G),
    /// EI_y = 1 (weak), EI_z = 4, under the axial load `p` at its end.
    fn inextensible_column(n: usize, p: f64) -> Model {
        let mut b = column(n, 4.0, [-p, 0.0, 0.0]);
        for i in 0..n {
            b.set_rigid_modes(&format!("b{i}"), &[1]).unwrap();
        }
        b.build().unwrap()
    }

    /// The unloaded start is found without the tangent (`newton::exact_equilibrium`): its
    /// tangent eigenvalues are those of the tangent assembled there, which for the unloaded
    /// column are of the material stiffness alone and all positive.
    #[test]
    fn the_tangent_eigenvalues_of_an_unloaded_start_are_of_its_tangent() {
        let model = inextensible_column(20, 0.5);
        let opts = StaticOptions {
            steps: 2,
            tangent_eigenvalues: true,
            ..Default::default()
        };
        let sol = solve_path(&model, &opts, |_, _| {}).unwrap();
        let st = &sol.steps[0];
        assert_eq!(st.iterations, 0);
        let su = setup(&model);
        let a = reduced_at(&model, &su, st);
        assert_eq!(st.tangent_eigenvalues, kappa(&su, &a, true));
        let k = st.tangent_eigenvalues.as_ref().expect("asked for");
        assert!(!k.is_empty() && k.iter().all(|&v| v > 0.0), "{k:?}");
    }

    #[test]
    fn the_eigenvalues_nearest_zero_by_lanczos_are_those_of_the_dense_spectrum() {
        // below the Euler load (stable: the smallest), above it (one negative κ) and in
        // between, against every eigenvalue of the dense Zᵀ S K S Z
        let p_cr = std::f64::consts::PI.powi(2) / 4.0;
        for (n, f) in [(20, 0.5), (20, 1.5), (40, 0.99)] {
            let model = inextensible_column(n, f * p_cr);
            let opts = StaticOptions {
                steps: 4,
                ..Default::default()
            };
            let sol = solve_path(&model, &opts, |_, _| {}).unwrap();
            let st = sol.steps.last().unwrap();
            let su = setup(&model);
            assert!(
                su.red.n > su.red.nfr,
                "the rigid elongations are constraints"
            );
            let a = reduced_at(&model, &su, st);
            let all = smallest_eigenvalues(&su, &a, usize::MAX).unwrap();
            let scale = all.iter().fold(0.0f64, |m, k| m.max(k.abs()));
            let mut want = all.clone();
            want.sort_by(|x, y| x.abs().total_cmp(&y.abs()));
            want.truncate(3);
            want.sort_by(f64::total_cmp);
            let got = nearest_zero_eigenvalues(&su, &a, 3).unwrap();
            assert_eq!(got.len(), 3);
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    (g - w).abs() <= 1e-8 * w.abs() + 1e-13 * scale,
                    "n = {n}, P = {f} P_cr: {got:?} vs {want:?}"
                );
            }
            assert_eq!(got[0] < 0.0, f > 1.0, "{got:?}");
        }
    }
}
