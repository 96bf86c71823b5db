//! The factorisation of the shifted saddle-point matrix A(σ) = [K − σM, Gᵀ; G, 0]: L D Lᵀ
//! with diagonal pivots and its inertia (eigenvalues below a shift), LU as the fall-back, and
//! the shift-invert operator.

use super::problem::Problem;
use super::refined::{refined_solve, Exact};
use crate::math::gmres;
use crate::math::sparse_lu::{csc_sym_residual_with, LuFailure, SparseLu};
use crate::model::Model;
use crate::statics::StepResult;

/// Accepted componentwise backward error of a solve with a new factorisation.
pub(super) const MAX_BACKWARD_ERROR: f64 = 1e-9;

/// Deterministic pseudo-random numbers in (−1, 1) (xorshift64*), for start vectors.
pub(super) struct Rng(pub(super) u64);
impl Rng {
    pub(super) fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The structure of both triangles of the saddle-point matrix, and the position of each of its
/// entries in the stored lower triangle ([`Problem::full_positions`]), for the LU fall-back.
pub(super) struct FullPattern {
    ptr: Vec<usize>,
    rows: Vec<u32>,
    at: Vec<u32>,
}

/// A factorisation of the shifted saddle-point matrix A(σ) = [K − σM, Gᵀ; G, 0].
pub(super) struct Shifted<'a> {
    /// L D Lᵀ with diagonal pivots in the saddle order (symbolic structure reused); it reads
    /// the lower triangle of the problem, which is kept in that order.
    pub(super) sym: Option<SparseLu>,
    /// LU with partial pivoting (created when L D Lᵀ fails), with the structure of both
    /// triangles it reads ([`Problem::full_pattern`]).
    pub(super) lu: Option<(SparseLu, FullPattern)>,
    /// Which factorisation holds A(σ): true L D Lᵀ, false LU.
    pub(super) use_sym: bool,
    pub(super) sigma: f64,
    /// Number of eigenvalues below σ (from the inertia), when L D Lᵀ holds A(σ).
    pub(super) below: Option<usize>,
    /// The right-hand side and solution of an application (empty until one is made, and after
    /// [`Shifted::release_factors`]).
    pub(super) rhs: Vec<f64>,
    /// When set, the operator's solves are refined (`refined` module) with products through
    /// the element deformations of this model and state.
    pub(super) exact: Option<Exact<'a>>,
    /// The vectors of the refined solves, kept from one solve to the next (given back while K
    /// is made again: [`Shifted::with_k`]).
    pub(super) refine_ws: gmres::Workspace,
    /// The shift at which the factorisation is made again before the next solve, after
    /// [`Shifted::count_below`] took it for an inertia count.
    restore: Option<f64>,
    /// When set ([`Shifted::release_k_between`]): the problem's K values are released after
    /// a factorisation (after every one with `always`, else while a Lanczos basis is held) and
    /// made again from this model and state before the next one.
    source: Option<(&'a Model, &'a StepResult)>,
    /// With `source`: K released after every factorisation, not only while a basis is held.
    always: bool,
    /// A Lanczos basis is held ([`Shifted::hold_basis`]).
    in_basis: bool,
}

impl<'a> Shifted<'a> {
    pub(super) fn new(p: &Problem) -> Self {
        // (the structure of both triangles for the symbolic factorisation only: released
        // before the factorisation's values are made)
        let sym = p.ordered.then(|| {
            let (ptr, rows) = p.full_pattern();
            let mut lu = SparseLu::with_order(p.n, p.perm.clone()).ok()?;
            if !lu.set_diagonal_pivots(&ptr, &rows) {
                return None;
            }
            // (only L D Lᵀ refactorisations: the LU fall-back is a factorisation of its own)
            lu.release_upper_structure();
            lu.set_pivot_tolerance(0.0);
            Some(lu)
        });
        let sym = sym.flatten();
        Self {
            sym,
            lu: None,
            use_sym: false,
            sigma: f64::NAN,
            below: None,
            rhs: Vec::new(),
            exact: None,
            refine_ws: Default::default(),
            restore: None,
            source: None,
            always: false,
            in_basis: false,
        }
    }

    /// The operator with refined solves ([`Shifted::exact`]).
    pub(super) fn refined(p: &Problem, exact: Exact<'a>) -> Self {
        Self {
            exact: Some(exact),
            ..Self::new(p)
        }
    }

    /// From now on, the problem's K values are released (8 bytes per entry, 0.46 KB per beam
    /// of a strip) where they would add to the peak of a large model's modal analysis, and
    /// made again from `model` at `step` (the stage of the problem) for the next factorisation:
    /// with `always` after every factorisation (refined solves: their vectors and element
    /// Jacobians outlast the iteration), else while a Lanczos basis is held
    /// ([`Shifted::hold_basis`]), so that the inertia counts after an iteration make them
    /// once.
    pub(super) fn release_k_between(
        &mut self,
        p: &Problem,
        model: &'a Model,
        step: &'a StepResult,
        always: bool,
    ) {
        self.source = Some((model, step));
        self.always = always;
        p.release_k();
    }

    /// A Lanczos basis is held from now on (`held`), or no longer: K is released now and after
    /// every factorisation while it is ([`Shifted::release_k_between`]).
    pub(super) fn hold_basis(&mut self, p: &Problem, held: bool) {
        self.in_basis = held;
        if held && self.source.is_some() {
            p.release_k();
        }
    }

    /// The problem's K values for a factorisation, and released after it (`f`) as
    /// [`Shifted::release_k_between`] asked.
    fn with_k<T>(&mut self, p: &Problem, f: impl FnOnce(&mut Self) -> T) -> T {
        if let Some((model, step)) = self.source {
            // (the refined solves' vectors would add to the peak of the factorisation)
            self.refine_ws = Default::default();
            p.restore_k(model, step);
        }
        let r = f(self);
        if self.source.is_some() && (self.always || self.in_basis) {
            p.release_k();
        }
        r
    }

    /// Factor A(σ); `allow_lu`: fall back to LU when L D Lᵀ fails. Checks the accuracy of a
    /// trial solve. Returns false when A(σ) could not be factored accurately.
    pub(super) fn factor(&mut self, p: &Problem, sigma: f64, allow_lu: bool) -> bool {
        self.with_k(p, |op| op.factor_with_k(p, sigma, allow_lu))
    }

    /// [`Shifted::factor`] with the K values present.
    fn factor_with_k(&mut self, p: &Problem, sigma: f64, allow_lu: bool) -> bool {
        self.restore = None;
        self.sigma = sigma;
        self.below = None;
        let n_constraints = p.n - p.nc;
        if let Some(lu) = &mut self.sym {
            if refactor_at(lu, p, sigma).is_ok() {
                self.use_sym = true;
                if self.accurate(p) {
                    let neg = self.sym.as_ref().map_or(0, |s| s.negative_pivots());
                    self.below = neg.checked_sub(n_constraints);
                    return true;
                }
            }
        }
        if !allow_lu {
            return false;
        }
        if self.lu.is_none() {
            let (ptr, rows) = p.full_pattern();
            let at = p.full_positions(&ptr, &rows);
            self.lu = SparseLu::new(p.n, &ptr, &rows)
                .ok()
                .map(|lu| (lu, FullPattern { ptr, rows, at }));
        }
        let Some((lu, full)) = &mut self.lu else {
            return false;
        };
        let value = p.shifted_entries(sigma);
        let vals: Vec<f64> = full.at.iter().map(|&q| value(q as usize)).collect();
        if lu.factor(&full.ptr, &full.rows, &vals).is_err() {
            return false;
        }
        self.use_sym = false;
        self.accurate(p)
    }

    /// Backward error of a solve with a pseudo-random right-hand side.
    pub(super) fn accurate(&mut self, p: &Problem) -> bool {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let b: Vec<f64> = (0..p.n).map(|_| rng.next()).collect();
        let mut z = b.clone();
        self.solve_factored(&mut z);
        // (the matrix is kept in the pivot order: the residual in that order)
        let zp: Vec<f64> = p.perm.iter().map(|&c| z[c as usize]).collect();
        let bp: Vec<f64> = p.perm.iter().map(|&c| b[c as usize]).collect();
        let sigma = self.sigma;
        z.iter().all(|v| v.is_finite())
            && csc_sym_residual_with(p.rows(), p.shifted_entries(sigma), &zp, &bp).1
                <= MAX_BACKWARD_ERROR
    }

    /// A solve with the factorisation alone.
    pub(super) fn solve_factored(&mut self, b: &mut [f64]) {
        if self.use_sym {
            if let Some(lu) = &mut self.sym {
                lu.solve(b);
            }
        } else if let Some((lu, _)) = &mut self.lu {
            lu.solve(b);
        }
    }

    /// Whether a refined solve with a pseudo-random right-hand side converges (its correction
    /// below 1e-8): A(σ) is then regular for the accurate products, also where the
    /// factorisation's inertia cannot tell (a matrix as near singular as round-off, which a
    /// free model's is exactly at σ = 0 and a very fine clamped strip's nearly). False without
    /// [`Shifted::exact`].
    pub(super) fn regular_refined(&mut self, p: &Problem) -> bool {
        let Some(ex) = self.exact else {
            return false;
        };
        let mut rng = Rng(0x2545_F491_4F6C_DD1D);
        let mut z = vec![0.0; p.n];
        let mut mb = vec![0.0; p.nc];
        let v: Vec<f64> = (0..p.nc).map(|_| rng.next()).collect();
        p.m_times(&v, &mut mb);
        z[..p.nc].copy_from_slice(&mb);
        refined_solve(self, p, ex, &mb, &mut z) <= 1e-8 && z.iter().all(|v| v.is_finite())
    }

    /// A solve of the operator, z = A(σ)⁻¹ b for the right-hand side whose leading entries are
    /// `b` (the rest zero; z of the system's size): refined when [`Shifted::exact`] is set.
    pub(super) fn solve(&mut self, p: &Problem, b: &[f64], z: &mut [f64]) {
        if let Some(sigma) = self.restore.take() {
            // accepted at σ before the inertia count took the factorisation
            let _ = self.factor(p, sigma, true);
        }
        let (head, tail) = z.split_at_mut(b.len());
        head.copy_from_slice(b);
        tail.iter_mut().for_each(|r| *r = 0.0);
        match self.exact {
            Some(ex) => {
                refined_solve(self, p, ex, b, z);
            }
            None => self.solve_factored(z),
        }
    }

    /// The shift-invert operator on coordinates: u = first nc of A(σ)⁻¹ [M v; 0].
    pub(super) fn apply(&mut self, p: &Problem, v: &[f64], out: &mut [f64]) {
        // (M v in `out`, the right-hand side's leading part until the solution replaces it)
        p.m_times(v, out);
        self.apply_mv_in(p, out);
    }

    /// The operator for a vector whose product `mv` = M v is known.
    pub(super) fn apply_mv(&mut self, p: &Problem, mv: &[f64], out: &mut [f64]) {
        out.copy_from_slice(mv);
        self.apply_mv_in(p, out);
    }

    /// [`Shifted::apply_mv`] with M v given in `out`, which the result replaces.
    fn apply_mv_in(&mut self, p: &Problem, out: &mut [f64]) {
        let mut rhs = std::mem::take(&mut self.rhs);
        rhs.resize(p.n, 0.0);
        self.solve(p, out, &mut rhs);
        out.copy_from_slice(&rhs[..p.nc]);
        self.rhs = rhs;
    }

    /// Releases what the operator's applications keep from one to the next (its right-hand
    /// side, the refined solves' Krylov vectors) and the values of the factorisations (made
    /// again by the next [`Shifted::factor`] or inertia count): for the phase after the
    /// iteration, which applies the operator no more, and whose mode shapes and inertia count
    /// they would add to.
    pub(super) fn release_factors(&mut self) {
        self.rhs = Vec::new();
        self.refine_ws = Default::default();
        if let Some(lu) = &mut self.sym {
            lu.release_values();
        }
        self.lu = None;
        self.use_sym = false;
        self.sigma = f64::NAN;
        self.below = None;
        self.restore = None;
    }

    /// Number of eigenvalues below `s` by the inertia of A(s), if L D Lᵀ can factor it. The
    /// factorisation is refactored at `s` in place (a copy would be held beside the Lanczos
    /// basis, as large as the factor at 10⁴ beams) and made again at σ before the next solve
    /// ([`Shifted::solve`]): the same values give the same factorisation, so it is accepted
    /// as before.
    pub(super) fn count_below(&mut self, p: &Problem, s: f64) -> Option<usize> {
        self.sym.as_ref()?;
        let sigma = self.sigma;
        let count = self.count_below_in_place(p, s);
        // the operator's shift stays σ
        self.sigma = sigma;
        self.restore = Some(sigma);
        count
    }

    /// [`Shifted::count_below`] in the factorisation itself, without a copy: A(σ) is no longer
    /// factored afterwards (call [`Shifted::factor`] again before a solve).
    pub(super) fn count_below_in_place(&mut self, p: &Problem, s: f64) -> Option<usize> {
        self.sigma = f64::NAN;
        self.below = None;
        self.use_sym = false;
        self.sym.as_ref()?;
        self.with_k(p, |op| inertia_count(op.sym.as_mut()?, p, s))
    }
}

/// The eigenvalues below `s` by the inertia of A(s) = [K − sM, Gᵀ; G, 0], refactored in `lu`
/// (the L D Lᵀ structure): its negative pivots less one per constraint.
fn inertia_count(lu: &mut SparseLu, p: &Problem, s: f64) -> Option<usize> {
    refactor_at(lu, p, s).ok()?;
    lu.negative_pivots().checked_sub(p.n - p.nc)
}

/// L D Lᵀ of A(s) in `lu`, from the lower triangle of the problem in its pivot order, the
/// values formed as the factorisation reads them (no array of them beside the factor).
fn refactor_at(lu: &mut SparseLu, p: &Problem, s: f64) -> Result<f64, LuFailure> {
    lu.refactor_symmetric_on(p.rows(), p.shifted_entries(s))
}
