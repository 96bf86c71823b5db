//! Krylov–Schur restarted Lanczos in the M inner product, with the Sturm check that no
//! eigenvalue was missed (module docs of `sparse`).

use super::basis::{
    basis_combine_in_place, basis_dots, basis_subtract, dot, projected_eigen_largest, Cols,
};
use super::problem::Problem;
use super::shifted::{Rng, Shifted};
use super::TOL;
use crate::dynamics::ModalError;
use faer::Mat;

/// The first `j` columns of `v`, M-orthonormal, and their products `mv` = M v when they are
/// kept.
pub(super) struct Basis<'a> {
    v: &'a [Vec<f64>],
    mv: Option<&'a [Vec<f64>]>,
    /// Number of columns in use.
    j: usize,
}

/// M-inner-product Gram–Schmidt of `w` against the bases (classical Gram–Schmidt with one
/// reorthogonalisation); the coefficients against the first basis go to `h` (length
/// `main.j`), and the M-norm of the result is returned, with `mw` = M w on return.
///
/// Without stored products (`mv`: `None`, the common case) each pass forms M w and takes the
/// coefficients Vᵀ(M w) of both bases from it (they are M-orthogonal to each other): three
/// products with M per call, and no M V beside V (as large as V: 1.5 KB per beam of a strip).
/// With stored products the coefficients are (M V)ᵀ w and M is applied once. A singular M
/// (coordinates without mass) needs those: the operator's vectors then carry large components
/// along the null space of M, and the rounding of M w along it, multiplied by them, cost the
/// Ritz vectors of a prestressed cantilever with massless rotations four digits of their
/// M-orthogonality (1e-8 against 1e-12).
/// `scratch` holds at least as many entries as the larger basis has columns.
pub(super) fn orthogonalise(
    p: &Problem,
    main: &Basis<'_>,
    locked: Option<&Basis<'_>>,
    w: &mut [f64],
    mw: &mut [f64],
    h: &mut [f64],
    scratch: &mut [f64],
) -> f64 {
    h.iter_mut().for_each(|x| *x = 0.0);
    for _pass in 0..2 {
        if main.mv.is_none() {
            p.m_times(w, mw);
        }
        for (b, is_main) in [(Some(main), true), (locked, false)] {
            let Some(b) = b else { continue };
            if b.j == 0 {
                continue;
            }
            let c = &mut scratch[..b.j];
            match b.mv {
                Some(mv) => basis_dots(mv, w, c),
                None => basis_dots(b.v, mw, c),
            }
            basis_subtract(b.v, c, w);
            if is_main {
                h.iter_mut().zip(c.iter()).for_each(|(a, x)| *a += x);
            }
        }
    }
    p.m_times(w, mw);
    let norm2 = dot(w, mw);
    norm2.max(0.0).sqrt()
}

/// Converged Ritz pairs of one Krylov–Schur run: θ (descending) and vectors (columns).
pub(super) struct Run {
    theta: Vec<f64>,
    x: Cols,
    applications: usize,
}

/// Krylov–Schur (thick-restart Lanczos) for the `nev` largest θ of the operator, M-orthogonal
/// to `locked` (M-orthonormal columns). Fewer pairs are returned when the reachable space is
/// smaller (all of them exact then). `Err(applications)` when `max_applications` was reached.
pub(super) fn krylov_schur(
    p: &Problem,
    op: &mut Shifted,
    nev: usize,
    locked: &[Vec<f64>],
    seed: u64,
    max_applications: usize,
    keep_mv: bool,
) -> Result<Run, usize> {
    let nc = p.nc;
    // the basis size of ARPACK's and SciPy's default (ncv = max(2 nev + 1, 20)): at 10⁵ beams
    // and nev = 10 it holds 21 vectors instead of 31 (65 MB less) and restarts no more often
    // in time (bench/README.md §3b)
    let mmax = (2 * nev + 1).max(20).min(nc);
    let mut st = Store {
        v: vec![vec![0.0; nc]; mmax + 1],
        mv: keep_mv.then(|| vec![vec![0.0; nc]; mmax + 1]),
        mvj: vec![0.0; nc],
    };
    let mut h = Mat::<f64>::zeros(mmax, mmax);
    // Gram–Schmidt coefficients and their scratch (the larger of the two bases)
    let mut hc = vec![0.0; mmax + 1];
    let mut scratch = vec![0.0; (mmax + 1).max(locked.len())];
    let mut start_scratch = vec![0.0; 2 * (mmax + 1) + locked.len()];
    let mut rng = Rng(seed);
    let mut applications = 0;
    let ml: Option<Cols> = keep_mv.then(|| {
        locked
            .iter()
            .map(|l| {
                let mut m = vec![0.0; nc];
                p.m_times(l, &mut m);
                m
            })
            .collect()
    });
    let lk = Basis {
        v: locked,
        mv: ml.as_deref(),
        j: locked.len(),
    };
    let lk = (lk.j > 0).then_some(&lk);
    // a start vector from the operator's range, M-orthogonal to the first j basis vectors,
    // normalised into column j (its M product into mvj); false when the reachable space is
    // exhausted
    let mut new_start =
        |st: &mut Store, j: usize, op: &mut Shifted, applications: &mut usize| -> bool {
            for _ in 0..3 {
                // (w formed in column j, M w in mvj: [`Store::split`])
                let (basis, w, mw) = st.split(j);
                // the random vector in mw (overwritten by M w below)
                mw.iter_mut().for_each(|x| *x = rng.next());
                op.apply(p, mw, w);
                *applications += 1;
                p.m_times(w, mw);
                let before: f64 = w.iter().zip(mw.iter()).map(|(a, b)| a * b).sum::<f64>();
                let (h, rest) = start_scratch.split_at_mut(j);
                let after = orthogonalise(p, &basis, lk, w, mw, h, rest);
                if before > 0.0 && after > 1e-8 * before.sqrt() {
                    st.push(j, after);
                    return true;
                }
            }
            false
        };
    if !new_start(&mut st, 0, op, &mut applications) {
        return Ok(Run {
            theta: Vec::new(),
            x: Vec::new(),
            applications,
        });
    }
    let mut k = 0; // size of the kept (restarted) decomposition
    loop {
        // expand from k to mmax: S V_m = V_m H_m + β v_{m+1} e_mᵀ
        let mut beta = 0.0;
        let mut j = k;
        let mut exhausted = false;
        while j < mmax {
            // the operator on the newest column (its M product in mvj), into column j + 1
            let (basis, w, mw) = st.split(j + 1);
            op.apply_mv(p, mw, w);
            applications += 1;
            let hc = &mut hc[..j + 1];
            let b = orthogonalise(p, &basis, lk, w, mw, hc, &mut scratch);
            for (i, c) in hc.iter().enumerate() {
                h[(i, j)] = *c;
            }
            let scale = hc.iter().fold(0.0f64, |a, c| a.max(c.abs()));
            j += 1;
            if b > 1e-12 * scale && b > 0.0 {
                beta = b;
                st.push(j, b);
            } else {
                // an invariant subspace: continue with a new direction (coupling zero)
                beta = 0.0;
                if j < mmax && !new_start(&mut st, j, op, &mut applications) {
                    exhausted = true;
                    break;
                }
            }
        }
        let m = j;
        // Ritz pairs of the symmetric projected matrix (its upper triangle was computed)
        let hs = h.as_ref().submatrix(0, 0, m, m).transpose();
        // wanted: the largest θ (the eigenvalues nearest above the shift); the vectors of the
        // `want` largest (converged) or of the `keep` largest (restart), largest first
        let want = nev.min(m);
        let keep = if m >= 2 {
            (nev + (mmax - nev) / 2).clamp(1, m - 1)
        } else {
            1
        };
        let (s, y) =
            projected_eigen_largest(hs, want.max(keep).min(m)).map_err(|_| applications)?;
        // column c of y belongs to θ = s[m − 1 − c]
        let converged = |c: usize| {
            let t = s[m - 1 - c];
            (beta * y[(m - 1, c)]).abs() <= TOL * t.abs() && t != 0.0
        };
        let conv = (0..want).take_while(|&c| converged(c)).count();
        if conv == want || exhausted || beta == 0.0 {
            // the Ritz vectors in the first `want` columns of the basis, the rest released
            let mut x = st.v;
            x.truncate(m);
            basis_combine_in_place(&mut x, y.subcols(0, want));
            x.truncate(want);
            return Ok(Run {
                theta: (0..want).map(|c| s[m - 1 - c]).collect(),
                x,
                applications,
            });
        }
        if applications >= max_applications {
            return Err(applications);
        }
        // thick restart: the best `keep` Ritz vectors, then the residual vector (whose M
        // product is mvj)
        for basis in std::iter::once(&mut st.v).chain(st.mv.as_mut()) {
            basis_combine_in_place(&mut basis[..m], y.subcols(0, keep));
            // (column m is written again before it is read)
            basis.swap(keep, m);
        }
        h.fill(0.0);
        for c in 0..keep {
            // the coupling of the kept vectors to the residual vector (β times the last row of
            // their Ritz vectors) is computed again by the next orthogonalisation
            h[(c, c)] = s[m - 1 - c];
        }
        k = keep;
    }
}

/// The Lanczos basis of a run: its columns `v`, M times its newest column `mvj` (the
/// operator's right-hand side) and, when kept ([`orthogonalise`]), M V.
struct Store {
    v: Cols,
    mv: Option<Cols>,
    mvj: Vec<f64>,
}

impl Store {
    /// The first `j` columns as a [`Basis`], with column `j` and `mvj` to form the next vector
    /// w and its M product in (no work vectors of the model's size beside the basis; `mvj`,
    /// the operator's right-hand side, is read before it is overwritten).
    fn split(&mut self, j: usize) -> (Basis<'_>, &mut [f64], &mut [f64]) {
        let (done, rest) = self.v.split_at_mut(j);
        let basis = Basis {
            v: done,
            mv: self.mv.as_deref(),
            j,
        };
        (basis, &mut rest[0], &mut self.mvj)
    }

    /// Column j (holding w) and `mvj` (holding M w) scaled by 1 / norm.
    fn push(&mut self, j: usize, norm: f64) {
        self.v[j].iter_mut().for_each(|a| *a /= norm);
        self.mvj.iter_mut().for_each(|a| *a /= norm);
        if let Some(mv) = &mut self.mv {
            mv[j].copy_from_slice(&self.mvj);
        }
    }
}

/// Krylov–Schur runs at the current shift until the `want` largest θ have converged and the
/// Sturm check (inertia just above the last of them) finds no eigenvalue missed; a missed one
/// (the second copy of a multiple eigenvalue) is found by a further run deflated against the
/// vectors found. Returns the Ritz vectors, their θ and the operator applications used.
/// `keep_mv`: keep M V beside the basis ([`orthogonalise`]), for a singular M.
pub(super) fn lanczos_runs(
    p: &Problem,
    op: &mut Shifted,
    want: usize,
    max_applications: usize,
    keep_mv: bool,
) -> Result<(Cols, Vec<f64>, usize), ModalError> {
    let sigma = op.sigma;
    let mut found: Cols = Vec::new();
    let mut thetas: Vec<f64> = Vec::new();
    let mut applications = 0;
    for run in 0..8u64 {
        let need = want.saturating_sub(thetas.len()).max(1);
        op.hold_basis(p, true);
        let r = krylov_schur(
            p,
            op,
            need,
            &found,
            0x5DEE_CE66_D1CE_4E5B ^ (run + 1).wrapping_mul(0x9E37_79B9),
            max_applications.saturating_sub(applications),
            keep_mv,
        );
        op.hold_basis(p, false);
        let r = r.map_err(|a| ModalError::NotConverged {
            found: thetas.len(),
            wanted: want,
            applications: applications + a,
        })?;
        applications += r.applications;
        if r.theta.is_empty() {
            break;
        }
        found.extend(r.x);
        thetas.extend(&r.theta);
        if thetas.len() < want {
            continue;
        }
        let mut lam: Vec<f64> = thetas.iter().map(|&t| sigma + 1.0 / t).collect();
        lam.sort_by(f64::total_cmp);
        let last = lam[want - 1];
        let scale = lam.iter().fold(sigma.abs(), |a, l| a.max(l.abs()));
        let check = last + 1e-6 * scale.max(f64::MIN_POSITIVE);
        match op.count_below(p, check) {
            Some(below) if below > lam.iter().filter(|&&l| l < check).count() => continue,
            _ => break,
        }
    }
    if thetas.is_empty() {
        return Err(ModalError::NotConverged {
            found: 0,
            wanted: want,
            applications,
        });
    }
    Ok((found, thetas, applications))
}
