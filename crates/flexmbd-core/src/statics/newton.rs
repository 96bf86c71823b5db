//! The Newton iteration of statics on the reduced KKT system ([`super::Reduction`]): the sparse
//! matrix with its reused structure and factorisation ([`KktSolver`]), the pieces of one Newton
//! step (reduced right-hand side, expansion of a reduced increment, convergence test) and the
//! iteration at a fixed load factor ([`newton`]). The arc-length iteration (`arc.rs`) uses the
//! same pieces with the load factor as an unknown.

use super::refined::{refine_direction, REFINE_AFTER};
use super::{
    apply_loads, assemble_values, chord_consistent_scale, inf_norm, normalise_lambda, rot_basis,
    solve_single_multipliers, Assembled, Part, Setup, StaticOptions,
};
use crate::math::sparse_lu::{ColRows, SparseLu};
use crate::model::Model;
use rayon::prelude::*;

/// Lists the (row, column) of every matrix entry, in the order of the values, to a callback.
pub(crate) type EntryLister<'a> = &'a dyn Fn(&mut dyn FnMut(usize, usize));

/// The sparse (reduced) Newton matrix of one solve with its fixed structure: the CSC
/// structure, the map from the assembly's entry order to the value slots, the fill-reducing
/// ordering and the structure of the factors are computed once; each Newton iteration gathers
/// the values and refactors numerically (see [`KktSolver::solve`] and [`SparseLu`]).
pub(crate) struct KktSolver {
    col_ptr: Vec<usize>,
    /// (u32 like the entry indices below: 4 bytes per entry where usize took 8)
    row_idx: Vec<u32>,
    /// The assembled entries summed into CSC value slot k: `src[src_ptr[k]..src_ptr[k + 1]]`
    /// (indices into the assembly order: element blocks, then the tail). Released for a
    /// symmetric matrix (`symmetric`, 1 KB per beam), whose CSC values are its lower
    /// triangle's mirrored (`mirror`).
    src_ptr: Vec<u32>,
    src: Vec<u32>,
    /// Number of assembled entries.
    m: usize,
    /// For a symmetric matrix: the position in `lower` of every CSC value slot, the mirror
    /// entry's above the diagonal (made when LU or a residual first needs the CSC values).
    mirror: Vec<u32>,
    /// The CSC values (empty until LU or a residual needs them).
    values: Vec<f64>,
    lu: SparseLu,
    /// Whether `lu` holds a factorisation whose pivot order can be reused.
    have_pivots: bool,
    /// Symmetric strategy: the same ordering with all pivots on the diagonal (the structure of
    /// a Cholesky factorisation), tried first; `lu` then pivots where it is not good enough.
    diag: Option<SparseLu>,
    /// The matrix is symmetric (no load stiffness of moments): `diag` factors it as L D Lᵀ
    /// from the lower triangle in pivot order, gathered as `lower` from the assembled entries
    /// `lower_src[lower_ptr[e]..lower_ptr[e + 1]]`.
    symmetric: bool,
    lower_ptr: Vec<u32>,
    lower_src: Vec<u32>,
    lower: Vec<f64>,
    /// Whether `values` (CSC) holds the current matrix.
    csc_current: bool,
    /// Negative pivots of the last accepted L D Lᵀ ([`KktSolver::inertia`]).
    inertia: Option<usize>,
    /// The factorisation the last successful [`KktSolver::solve`] used: 1 `diag`, 2 `lu`
    /// (0: none), for [`KktSolver::solve_again`].
    used: u8,
    /// A Newton solve with this matrix structure needed refined directions
    /// ([`super::refined`]) to converge: the next ones refine from their first iteration.
    pub(super) refine: bool,
    /// Keep a refactorisation with small pivots whose solve was accurate for
    /// [`KktSolver::solve_again`] ([`KktSolver::set_keep_small_pivots`]).
    keep_small_pivots: bool,
}

impl KktSolver {
    pub(super) fn new(su: &Setup, tail: &[(usize, usize)]) -> Result<Self, String> {
        let pat = &su.red;
        let m = pat.n_entries + tail.len();
        let entries = |f: &mut dyn FnMut(usize, usize)| {
            pat.for_each_entry(&mut *f);
            for &(r, c) in tail {
                f(r, c);
            }
        };
        Self::from_entries(pat.n, m, &entries, su.moments.is_empty())
    }

    /// A solver for n × n matrices whose `m` entries (row, column; repeated positions add up)
    /// are listed, in the order of their values, by `entries`; `symmetric` allows the L D Lᵀ
    /// strategy (the matrix is symmetric whatever the values).
    pub(crate) fn from_entries(
        n: usize,
        m: usize,
        entries: EntryLister<'_>,
        symmetric: bool,
    ) -> Result<Self, String> {
        // CSC structure of the entries (rows sorted, duplicates summed) and the entries summed
        // into each value slot: bucket the entries by column, sort each column by row
        if m > u32::MAX as usize {
            return Err("too many matrix entries".into());
        }
        let mut by_col_ptr = vec![0usize; n + 1];
        entries(&mut |_, c| by_col_ptr[c + 1] += 1);
        for c in 0..n {
            by_col_ptr[c + 1] += by_col_ptr[c];
        }
        let mut fill = by_col_ptr.clone();
        let mut by_col = vec![(0u32, 0u32); m];
        let mut i = 0;
        entries(&mut |r, c| {
            by_col[fill[c]] = (r as u32, i as u32);
            fill[c] += 1;
            i += 1;
        });
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        let mut src_ptr = vec![0u32];
        let mut src = Vec::with_capacity(m);
        // (the distinct positions, counted first: pushed without room made, the structure
        // and its pointers took up to twice their size, 8 MB each at 10⁴ beams)
        let mut distinct = 0;
        for c in 0..n {
            let list = &mut by_col[by_col_ptr[c]..by_col_ptr[c + 1]];
            list.sort_unstable();
            distinct += (0..list.len())
                .filter(|&k| k == 0 || list[k - 1].0 != list[k].0)
                .count();
        }
        row_idx.reserve_exact(distinct);
        src_ptr.reserve_exact(distinct);
        col_ptr.push(0);
        for c in 0..n {
            // by row, and by entry index within a row (the summation order of the assembly;
            // sorted above)
            let list = &by_col[by_col_ptr[c]..by_col_ptr[c + 1]];
            for (k, &(r, i)) in list.iter().enumerate() {
                if k == 0 || list[k - 1].0 != r {
                    if k > 0 {
                        src_ptr.push(src.len() as u32);
                    }
                    row_idx.push(r);
                }
                src.push(i);
            }
            if !list.is_empty() {
                src_ptr.push(src.len() as u32);
            }
            col_ptr.push(row_idx.len());
        }
        let lu = SparseLu::new(n, &col_ptr, &row_idx)?;
        let mut diag = lu.clone();
        let mut diag = diag.set_diagonal_pivots(&col_ptr, &row_idx).then_some(diag);
        let symmetric = symmetric && diag.is_some();
        drop(by_col);
        let (mut lower_ptr, mut lower_src) = (vec![0], Vec::new());
        if let (true, Some(d)) = (symmetric, &mut diag) {
            // (a symmetric matrix: `diag` only makes L D Lᵀ, which reads no structure of U)
            d.release_upper_structure();
            let slots = d.lower_layout(&col_ptr, &row_idx);
            let len = |p: u32| (src_ptr[p as usize + 1] - src_ptr[p as usize]) as usize;
            lower_ptr.reserve_exact(slots.len());
            lower_src.reserve_exact(slots.iter().map(|&p| len(p)).sum());
            for p in slots {
                let p = p as usize;
                lower_src.extend_from_slice(&src[src_ptr[p] as usize..src_ptr[p + 1] as usize]);
                lower_ptr.push(lower_src.len() as u32);
            }
            // the CSC values come from `lower` (mirrored) when they are needed
            (src_ptr, src) = (Vec::new(), Vec::new());
        }
        let lower = vec![0.0; lower_ptr.len() - 1];
        Ok(Self {
            col_ptr,
            row_idx,
            src_ptr,
            src,
            m,
            mirror: Vec::new(),
            values: Vec::new(),
            lu,
            have_pivots: false,
            diag,
            symmetric,
            lower_ptr,
            lower_src,
            lower,
            csc_current: false,
            inertia: None,
            used: 0,
            refine: false,
            keep_small_pivots: false,
        })
    }

    /// Solve K z = rhs in place for the KKT matrix with entries `vals` (assembly order).
    ///
    /// Order of attempts: L D Lᵀ with the diagonal pivot order (symmetric matrices; any other
    /// matrix with a full diagonal: LU with that order), then LU with the pivot order of the
    /// last factorisation with pivoting, then a new factorisation with pivoting. A
    /// refactorisation is accepted when its pivots are not small ([`MIN_PIVOT_RATIO`], or all
    /// positive for L D Lᵀ) or else when its solution is accurate ([`MAX_LINEAR_RESIDUAL`]).
    pub(crate) fn solve(&mut self, vals: &[f64], rhs: &mut [f64]) -> Result<(), ()> {
        self.solve_all(vals, &mut [rhs])
    }

    /// [`KktSolver::solve`] for several right-hand sides with one factorisation (accepted on
    /// the first of them). After it, [`KktSolver::inertia`] tells the number of negative
    /// eigenvalues of the matrix when L D Lᵀ factored it.
    pub(super) fn solve_all(&mut self, vals: &[f64], rhs: &mut [&mut [f64]]) -> Result<(), ()> {
        debug_assert_eq!(vals.len(), self.m);
        self.csc_current = false;
        self.inertia = None;
        let bs: Vec<Vec<f64>> = rhs.iter().map(|r| r.to_vec()).collect();
        let bn = norm2(&bs[0]);
        let restore = |rhs: &mut [&mut [f64]], lu: &mut SparseLu| {
            for (r, b) in rhs.iter_mut().zip(&bs) {
                r.copy_from_slice(b);
                lu.solve(r);
            }
        };
        for try_diag in [true, false] {
            let sym = try_diag && self.symmetric;
            // an attempt without a factorisation to refactor gathers nothing
            if (try_diag && self.diag.is_none()) || (!try_diag && !self.have_pivots) {
                continue;
            }
            if sym {
                gather_sum(&mut self.lower, &self.lower_ptr, &self.lower_src, vals);
            } else if !self.csc_current {
                self.gather_csc(vals);
            }
            let (cp, ri, v) = (&self.col_ptr, &self.row_idx, &self.values);
            let lu = if try_diag {
                match &mut self.diag {
                    Some(d) => d,
                    None => continue,
                }
            } else {
                &mut self.lu
            };
            let r = if sym {
                lu.refactor_symmetric(&self.lower)
            } else {
                lu.refactor(cp, ri, v)
            };
            let Ok(ratio) = r else {
                continue;
            };
            restore(rhs, lu);
            let inertia = sym.then(|| lu.negative_pivots());
            self.used = if try_diag { 1 } else { 2 };
            if ratio >= MIN_PIVOT_RATIO {
                self.inertia = inertia;
                return Ok(());
            }
            // small pivots: accept an accurate solution
            if !self.csc_current {
                self.gather_csc(vals);
            }
            let (cp, ri, v) = (&self.col_ptr, &self.row_idx, &self.values);
            let (res, _) = crate::math::sparse_lu::csc_residual(cp, ri, v, rhs[0], &bs[0]);
            if norm2(&res) <= MAX_LINEAR_RESIDUAL * bn {
                // accurate for this right-hand side: kept for `solve_again` only when asked
                // (`keep_small_pivots`)
                if !self.keep_small_pivots {
                    self.used = 0;
                }
                self.inertia = inertia;
                return Ok(());
            }
            self.used = 0;
        }
        // factor with pivoting again
        if !self.csc_current {
            self.gather_csc(vals);
        }
        let (cp, ri, v) = (&self.col_ptr, &self.row_idx, &self.values);
        self.have_pivots = false;
        self.used = 0;
        if self.lu.factor(cp, ri, v).is_err() {
            return Err(());
        }
        self.have_pivots = true;
        restore(rhs, &mut self.lu);
        self.used = 2;
        Ok(())
    }

    /// Keep a refactorisation whose pivots were small but whose solve was accurate (see
    /// [`KktSolver::solve`]) for [`KktSolver::solve_again`]. For a modified Newton iteration
    /// that judges its corrections by how fast they shrink (the time integrator): a poor
    /// direction costs it an iteration, never a wrong result. Off by default: a load path's
    /// eigenvalue iteration needs the solves exact.
    pub(crate) fn set_keep_small_pivots(&mut self, keep: bool) {
        self.keep_small_pivots = keep;
    }

    /// Whether [`KktSolver::solve_again`] has a factorisation to use.
    pub(crate) fn reusable(&self) -> bool {
        self.used != 0
    }

    /// Solve with the factorisation of the last successful [`KktSolver::solve`] whose pivots
    /// were all sound (a modified Newton iteration); `Err` when there is none.
    pub(crate) fn solve_again(&mut self, rhs: &mut [f64]) -> Result<(), ()> {
        match self.used {
            1 => match &mut self.diag {
                Some(d) => d.solve(rhs),
                None => return Err(()),
            },
            2 => self.lu.solve(rhs),
            _ => return Err(()),
        }
        Ok(())
    }

    /// The number of negative eigenvalues of the matrix of the last solve, when L D Lᵀ with
    /// diagonal pivots factored it (a symmetric matrix: no moment loads); `None` otherwise.
    pub(super) fn inertia(&self) -> Option<usize> {
        self.inertia
    }

    /// The CSC values of the matrix with entries `vals`.
    fn gather_csc(&mut self, vals: &[f64]) {
        // (made when first needed: L D Lᵀ of a symmetric matrix reads `lower` alone)
        self.values.resize(self.row_idx.len(), 0.0);
        if self.symmetric {
            // the lower triangle, mirrored above the diagonal
            gather_sum(&mut self.lower, &self.lower_ptr, &self.lower_src, vals);
            if self.mirror.is_empty() {
                self.mirror = self.mirror_positions();
            }
            for (v, &q) in self.values.iter_mut().zip(&self.mirror) {
                *v = self.lower[q as usize];
            }
        } else {
            gather_sum(&mut self.values, &self.src_ptr, &self.src, vals);
        }
        self.csc_current = true;
    }

    /// For a symmetric matrix: the position in `lower` of every CSC value slot (of its mirror
    /// entry when the slot lies above the diagonal in pivot order).
    fn mirror_positions(&mut self) -> Vec<u32> {
        const NONE: u32 = u32::MAX;
        let (cp, ri) = (&self.col_ptr, &self.row_idx);
        let d = self
            .diag
            .as_mut()
            .expect("a symmetric matrix has diagonal pivots");
        let mut at = vec![NONE; ri.len()];
        for (q, p) in d.lower_layout(cp, ri).into_iter().enumerate() {
            at[p as usize] = q as u32;
        }
        let mut mirror = at.clone();
        for c in 0..cp.len() - 1 {
            for p in cp[c]..cp[c + 1] {
                if at[p] == NONE {
                    // (r, c) above the diagonal: the value of (c, r), in column r
                    let r = ri[p] as usize;
                    let p2 = ColRows::plain(cp, ri).find(r, c);
                    debug_assert!(p2.is_ok(), "the pattern is symmetric");
                    mirror[p] = at[p2.unwrap_or_else(|q| q)];
                }
            }
        }
        mirror
    }
}

/// out[k] = Σ vals[src[ptr[k]..ptr[k + 1]]] (in parallel in chunks; one chunk on the calling
/// thread, which does not even start the thread pool for a small matrix).
fn gather_sum(out: &mut [f64], ptr: &[u32], src: &[u32], vals: &[f64]) {
    const CHUNK: usize = 4096;
    let chunk_sums = |(c, chunk): (usize, &mut [f64])| {
        for (o, v) in chunk.iter_mut().enumerate() {
            let k = c * CHUNK + o;
            *v = src[ptr[k] as usize..ptr[k + 1] as usize]
                .iter()
                .map(|&i| vals[i as usize])
                .sum();
        }
    };
    if out.len() <= CHUNK {
        chunk_sums((0, out));
    } else {
        out.par_chunks_mut(CHUNK).enumerate().for_each(chunk_sums);
    }
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Largest accepted ‖K z − b‖/‖b‖ of a solution from a refactorisation with small pivots.
const MAX_LINEAR_RESIDUAL: f64 = 1e-6;

/// Refactoring with the previous pivots is accepted when every pivot is at least this fraction
/// of the largest entry of its column (threshold partial pivoting); otherwise the matrix is
/// factored with pivoting again.
const MIN_PIVOT_RATIO: f64 = 1e-3;

/// A Newton solve is abandoned (and the load step halved) when the residual exceeds this factor
/// times the largest of its initial residual and the residual after the first iteration.
const DIVERGENCE: f64 = 1e3;

/// Smallest line-search step before a step is taken anyway.
const MIN_STEP: f64 = 1.0 / 16.0;

/// Outcome of one Newton solve.
pub(super) enum Newton {
    /// Converged; `state` is the assembly at the solution.
    Converged {
        iterations: usize,
        residual: f64,
        state: Box<Assembled>,
    },
    Failed {
        reason: String,
    },
}

/// The largest translational diagonal entry of the reduced tangent in `a`: the reference
/// stiffness of the residual floor and of the line search (the Euler-parameter entries are in
/// other units).
pub(super) fn reference_stiffness(su: &Setup, a: &Assembled) -> f64 {
    let red = &su.red;
    let n_el = red.n_entries;
    red.diag_trans
        .iter()
        .map(|&i| a.vals[i])
        .chain(
            a.tail
                .iter()
                .zip(&a.vals[n_el..])
                .filter(|((r, c), _)| r == c && *r < red.nfr && red.is_trans[*r])
                .map(|(_, v)| *v),
        )
        .fold(0.0f64, |m, v| m.max(v.abs()))
}

/// The size of an increment `dx` of the free coordinates (by unknown) for the convergence test:
/// the largest translation relative to the model size, or rotation parameter.
pub(super) fn increment_size(model: &Model, su: &Setup, dx: &[f64]) -> f64 {
    let mut m: f64 = 0.0;
    for i in 0..model.nx {
        if let Some(u) = su.unknown[i].get() {
            let v = if su.is_lambda[i] {
                dx[u].abs()
            } else {
                dx[u].abs() / su.l_ref
            };
            m = m.max(v);
        }
    }
    m
}

/// The state of a Newton iteration after the convergence test ([`check`]).
pub(super) enum Status {
    /// Converged, with the residual ‖r‖∞.
    Converged(f64),
    /// Go on.
    Iterate,
    /// Give up (not finite, diverging, out of iterations).
    Failed(String),
}

/// The convergence test of iteration `it` at the assembly `a` (module docs of statics,
/// "Convergence"): residual at most `tol_force` × the force scale or at the round-off floor,
/// constraint violation and last increment at most `tol_disp` (× L); failure when not finite,
/// out of iterations, or diverging (the residual far above the largest of its first two
/// values, tracked in `r_start`).
pub(super) fn check(
    su: &Setup,
    opts: &StaticOptions,
    a: &Assembled,
    k_ref: f64,
    last_inc: f64,
    it: usize,
    r_start: &mut f64,
) -> Status {
    let (rn, gn) = (inf_norm(&a.r), inf_norm(&a.g));
    if !(rn.is_finite() && gn.is_finite()) {
        return Status::Failed("the residual is not finite".into());
    }
    // the residual cannot be smaller than the backward error of evaluating internal forces
    // from positions of size l_ref: about ε ‖K‖ l_ref (factor 10 for the sums)
    let floor = 10.0 * f64::EPSILON * k_ref * su.l_ref;
    let force_ok = rn <= (opts.tol_force * a.f_scale).max(floor) || rn == 0.0;
    let geom_ok = gn <= opts.tol_disp * su.l_ref;
    if force_ok && geom_ok && (last_inc <= opts.tol_disp || it == 0 && rn == 0.0 && gn == 0.0) {
        return Status::Converged(rn);
    }
    if it == opts.max_iterations {
        return Status::Failed(format!(
            "{it} iterations, residual {rn:.3e} N, constraint error {gn:.3e}"
        ));
    }
    // divergence: the residual grew far beyond those of the start and of the first Newton
    // step (the first step may raise it a lot, e.g. by stretching axially stiff elements);
    // give up early so that the step is halved instead of spending all iterations
    if it <= 1 {
        *r_start = r_start.max(rn);
    } else if rn > DIVERGENCE * r_start.max(floor) {
        return Status::Failed(format!(
            "diverging: residual {rn:.3e} N after {it} iterations (at most {:.3e} N at the start)",
            *r_start
        ));
    }
    Status::Iterate
}

/// The reduced right-hand side −(r, g) of the Newton system at `x`: −r on the kept unknowns,
/// −Nᵀ r_λ on the rotation increments of reduced nodes, −g on the kept constraints.
pub(super) fn reduced_rhs(su: &Setup, x: &[f64], r: &[f64], g: &[f64]) -> Vec<f64> {
    let (red, nf) = (&su.red, su.nf);
    let mut dr = vec![0.0; red.n];
    for (u, m) in red.map.iter().enumerate() {
        if let Some(m) = m.get() {
            dr[m] = if u < nf { -r[u] } else { -g[u - nf] };
        }
    }
    for &(rr, d0, _) in &red.nodes {
        let nb = rot_basis(&x[rr..rr + 4]);
        let rl: [f64; 4] = std::array::from_fn(|i| r[su.unknown[rr + i].get().expect("free λ")]);
        for j in 0..3 {
            dr[d0 + j] = -(0..4).map(|i| nb[i][j] * rl[i]).sum::<f64>();
        }
    }
    dr
}

/// The full increment (free coordinates, then multipliers) of a reduced increment `dr` at
/// (x, μ): Δλ = s N δ with the chord-consistent scale s, and the multiplier of the
/// normalisation of a reduced node from its row of the full system with the residual `r`,
/// λᵀ(K Δx + 2 λ Δμ + r)_λ = 0, which by the invariance of the deformations and of the moment
/// loads under scaling of λ reads μ + Δμ = (r_λ − 2μλ)·Δλ / (2 λᵀλ).
pub(super) fn expand(su: &Setup, x: &[f64], mu: &[f64], r: &[f64], dr: &[f64]) -> Vec<f64> {
    let (red, nf) = (&su.red, su.nf);
    let mut dz = vec![0.0; nf + su.nk];
    for (u, m) in red.map.iter().enumerate() {
        if let Some(m) = m.get() {
            dz[u] = dr[m];
        }
    }
    for &(rr, d0, kc) in &red.nodes {
        let nb = rot_basis(&x[rr..rr + 4]);
        let (mut work, mut l2) = (0.0, 0.0);
        let sc = chord_consistent_scale((0..3).map(|j| dr[d0 + j] * dr[d0 + j]).sum());
        for i in 0..4 {
            let u = su.unknown[rr + i].get().expect("free λ");
            let dl: f64 = (0..3).map(|j| nb[i][j] * dr[d0 + j]).sum();
            dz[u] = sc * dl;
            work += (r[u] - 2.0 * mu[kc] * x[rr + i]) * dl;
            l2 += x[rr + i] * x[rr + i];
        }
        dz[nf + kc] = work / (2.0 * l2) - mu[kc];
    }
    dz
}

/// x ← x_old + α Δx on the free coordinates, μ ← μ_old + α Δμ (`dz` from [`expand`]), λ
/// back on the unit sphere.
pub(super) fn step_to(
    su: &Setup,
    (x, mu): (&mut [f64], &mut [f64]),
    (x_old, mu_old): (&[f64], &[f64]),
    dz: &[f64],
    alpha: f64,
) {
    for (i, xi) in x.iter_mut().enumerate() {
        if let Some(u) = su.unknown[i].get() {
            *xi = x_old[i] + alpha * dz[u];
        }
    }
    for (k, m) in mu.iter_mut().enumerate() {
        *m = mu_old[k] + alpha * dz[su.nf + k];
    }
    normalise_lambda(su, x);
}

/// Newton's method at the load factor t from (x, μ) (`prev`: the reduced assembly at this x and
/// μ for another load factor, whose load part alone is updated).
pub(super) fn newton(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    x: &mut [f64],
    mu: &mut [f64],
    t: f64,
    kkt: &mut Option<KktSolver>,
    prev: Option<Box<Assembled>>,
) -> Newton {
    let nf = su.nf;
    normalise_lambda(su, x);
    // `prev`: the reduced assembly at this x and μ for another load factor (the last
    // converged state): only its load part changes
    let mut a = match prev {
        Some(mut p) if p.reduced && p.tangent => {
            apply_loads(model, su, x, mu, t, Part::Full, &mut p);
            *p
        }
        _ => assemble_values(model, su, x, mu, t, Part::Full, true, Vec::new()),
    };
    solve_single_multipliers(su, x, mu, &mut a);
    let mut last_inc = f64::INFINITY;
    let k_ref = reference_stiffness(su, &a);
    let mut r_start: f64 = 0.0;
    let mut refined = false;
    for it in 0..=opts.max_iterations {
        match check(su, opts, &a, k_ref, last_inc, it, &mut r_start) {
            Status::Converged(residual) => {
                if refined {
                    if let Some(k) = kkt {
                        k.refine = true;
                    }
                }
                return Newton::Converged {
                    iterations: it,
                    residual,
                    state: Box::new(a),
                };
            }
            Status::Failed(reason) => return Newton::Failed { reason },
            Status::Iterate => {}
        }
        // Newton direction from the KKT system (structure and symbolic LU reused)
        let solver = match kkt {
            Some(k) => k,
            None => match KktSolver::new(su, &a.tail) {
                Ok(k) => kkt.insert(k),
                Err(reason) => return Newton::Failed { reason },
            },
        };
        let mut dr = reduced_rhs(su, x, &a.r, &a.g);
        let refine = it >= REFINE_AFTER || solver.refine;
        let b = refine.then(|| dr.clone());
        if solver.solve(&a.vals, &mut dr).is_err() || dr.iter().any(|v| !v.is_finite()) {
            return Newton::Failed {
                reason: SINGULAR.into(),
            };
        }
        if let Some(b) = b {
            // still not converged: the factorisation may have lost the direction's digits
            // (fine meshes), so refine it (`refined` module)
            refined |= refine_direction(model, su, x, mu, t, &a, solver, &b, &mut dr);
        }
        let dz = expand(su, x, mu, &a.r, &dr);
        // backtracking line search on the merit ‖r‖² + (k_ref ‖g‖)², k_ref a stiffness that
        // gives the constraint violation force units
        let merit = |a: &Assembled| {
            let r2: f64 = a.r.iter().map(|v| v * v).sum();
            let g2: f64 = a.g.iter().map(|v| v * v).sum();
            r2 + k_ref * k_ref * g2
        };
        let m0 = merit(&a);
        let mut spare = std::mem::take(&mut a.vals);
        let mut alpha = 1.0;
        let (x_old, mu_old) = (x.to_vec(), mu.to_vec());
        loop {
            step_to(su, (x, mu), (&x_old, &mu_old), &dz, alpha);
            let mut trial = assemble_values(model, su, x, mu, t, Part::Full, true, spare);
            solve_single_multipliers(su, x, mu, &mut trial);
            let m = merit(&trial);
            // accept a decrease, or the smallest step tried
            if !opts.line_search || (m.is_finite() && m < m0) || alpha < MIN_STEP {
                a = trial;
                break;
            }
            spare = std::mem::take(&mut trial.vals);
            alpha *= 0.5;
        }
        last_inc = alpha * increment_size(model, su, &dz[..nf]);
    }
    unreachable!("the loop returns at it == max_iterations")
}

/// The state at `x` for load factor `t` when it is an exact equilibrium — residual and
/// constraint violations exactly zero, where [`newton`] stops at iteration 0 before it uses its
/// tangent ([`check`]) — assembled without the tangent (`Part::Residual`; the tangent is the
/// largest part of a large model's static solve, 1.5 KB per beam of a strip, and an unloaded
/// model, the start of most paths and the whole path of a modal analysis without loads, never
/// needs it). `prev`: an assembly at this x and μ for another load factor, whose element part
/// is reused when it has no tangent either (one with a tangent is Newton's to reuse). `Err`
/// gives back what Newton can reuse when the state is not an exact equilibrium, with x and μ
/// as they were.
pub(super) fn exact_equilibrium(
    model: &Model,
    su: &Setup,
    x: &mut [f64],
    mu: &mut [f64],
    t: f64,
    prev: Option<Box<Assembled>>,
) -> Result<Box<Assembled>, Option<Box<Assembled>>> {
    if prev.as_ref().is_some_and(|p| p.tangent) {
        // Newton's to reuse (before any copy of x and μ)
        return Err(prev);
    }
    // (Newton's first steps on copies of x and μ)
    let mut xn = x.to_vec();
    normalise_lambda(su, &mut xn);
    let mut a = match prev {
        Some(mut p) if p.reduced => {
            apply_loads(model, su, &xn, mu, t, Part::Residual, &mut p);
            p
        }
        _ => Box::new(assemble_values(
            model,
            su,
            &xn,
            mu,
            t,
            Part::Residual,
            true,
            Vec::new(),
        )),
    };
    let mut mun = mu.to_vec();
    solve_single_multipliers(su, &xn, &mut mun, &mut a);
    if inf_norm(&a.r) == 0.0 && inf_norm(&a.g) == 0.0 {
        x.copy_from_slice(&xn);
        mu.copy_from_slice(&mun);
        Ok(a)
    } else {
        Err(None)
    }
}

/// Why a Newton step has no direction.
pub(super) const SINGULAR: &str =
    "the tangent matrix is singular (a mechanism, or a buckled state)";

#[cfg(test)]
mod tests {
    use super::KktSolver;

    /// An unloaded start is an exact equilibrium: found without the tangent, in the state
    /// Newton reaches there (its own assembly, iteration 0); a loaded one is not, and x and μ
    /// are left as they were.
    #[test]
    fn an_exact_equilibrium_is_newtons_first_state_without_the_tangent() {
        use super::{exact_equilibrium, newton, Newton};
        use crate::statics::test_models::column;
        use crate::statics::{setup, StaticOptions};
        let model = column(8, 4.0, [0.3, -0.2, 0.1]).build().unwrap();
        let su = setup(&model);
        let x0 = model.x0();
        let mu0 = vec![0.0; su.nk];
        let (mut x, mut mu) = (x0.clone(), mu0.clone());
        let Ok(exact) = exact_equilibrium(&model, &su, &mut x, &mut mu, 0.0, None) else {
            panic!("the unloaded column is in equilibrium");
        };
        assert!(!exact.tangent && exact.vals.is_empty());
        let (mut xn, mut mun) = (x0.clone(), mu0.clone());
        let opts = StaticOptions::default();
        let Newton::Converged {
            iterations, state, ..
        } = newton(&model, &su, &opts, &mut xn, &mut mun, 0.0, &mut None, None)
        else {
            panic!("Newton converges at the unloaded start");
        };
        assert_eq!(iterations, 0);
        assert!(state.tangent && !state.vals.is_empty());
        assert_eq!((&x, &mu), (&xn, &mun));
        assert_eq!(exact.r, state.r);
        assert_eq!(exact.balance, state.balance);
        assert_eq!((&exact.e, &exact.sigma), (&state.e, &state.sigma));
        // loaded: not an equilibrium, the tangent-less assembly handed on is none
        let (mut x1, mut mu1) = (x0.clone(), mu0.clone());
        let loaded = exact_equilibrium(&model, &su, &mut x1, &mut mu1, 1.0, Some(exact));
        assert!(matches!(loaded, Err(None)));
        assert_eq!((&x1, &mu1), (&x0, &mu0));
    }

    /// b − A z for A given as entries (row, column, value; repeated positions add up).
    fn residual(entries: &[(usize, usize, f64)], z: &[f64], b: &[f64]) -> f64 {
        let mut r = b.to_vec();
        for &(i, j, v) in entries {
            r[i] -= v * z[j];
        }
        r.iter().fold(0.0f64, |m, x| m.max(x.abs()))
    }

    /// Solves with a solver for `entries` (symmetric or not) and returns the largest residual.
    fn solve_residual(n: usize, entries: &[(usize, usize, f64)], symmetric: bool) -> f64 {
        let list = |f: &mut dyn FnMut(usize, usize)| {
            for &(r, c, _) in entries {
                f(r, c);
            }
        };
        let mut kkt = KktSolver::from_entries(n, entries.len(), &list, symmetric).unwrap();
        let vals: Vec<f64> = entries.iter().map(|e| e.2).collect();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut z = b.clone();
        kkt.solve(&vals, &mut z).unwrap();
        residual(entries, &z, &b)
    }

    /// A symmetric saddle-point matrix [K, Gᵀ; G, 0] (K positive definite, its entries split
    /// into repeated positions as an assembly writes them): the same solution through the
    /// structure that keeps only the lower triangle's sources (L D Lᵀ, and LU from the mirrored
    /// lower triangle where L D Lᵀ meets the zero diagonal) as through the full one.
    #[test]
    fn symmetric_solver_mirrors_its_lower_triangle() {
        let k = [
            [4.0, -1.0, 0.0, 0.5],
            [-1.0, 5.0, -2.0, 0.0],
            [0.0, -2.0, 6.0, -1.0],
            [0.5, 0.0, -1.0, 3.0],
        ];
        let g = [1.0, 0.0, -2.0, 1.0];
        let mut entries = Vec::new();
        for (i, row) in k.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                if v != 0.0 {
                    // (two halves, as two elements would add them)
                    entries.push((i, j, 0.25 * v));
                    entries.push((i, j, 0.75 * v));
                }
            }
        }
        for (j, &v) in g.iter().enumerate() {
            if v != 0.0 {
                entries.push((4, j, v));
                entries.push((j, 4, v));
            }
        }
        // (the constraint's zero diagonal listed, so that the pattern has it)
        entries.push((4, 4, 0.0));
        let sym = solve_residual(5, &entries, true);
        let full = solve_residual(5, &entries, false);
        assert!(sym < 1e-12, "symmetric: residual {sym}");
        assert!(full < 1e-12, "general: residual {full}");
        // only the saddle point's zero diagonal: L D Lᵀ with diagonal pivots fails at its
        // first pivot, and LU factors the mirrored lower triangle
        let swap = [(0, 1, 1.0), (1, 0, 1.0), (0, 0, 0.0), (1, 1, 0.0)];
        let r = solve_residual(2, &swap, true);
        assert!(r < 1e-14, "[0 1; 1 0]: residual {r}");
    }
}
