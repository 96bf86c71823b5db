//! The sparse eigen path for large models (docs/dynamics.md, "Large models").
//!
//! The same eigenproblem as the dense path, (K_m + K_g) v = ω² M v on the minimal coordinates,
//! solved without any dense matrix of the size of the model:
//!
//! - **Coordinates**: the reduced unknowns of the statics Newton system
//!   ([`crate::statics::ReducedLinear`], the sparse form of the stage `linearized::sparse`): free translations, three rotation increments δ per
//!   rotational node (angular velocity ω = 2δ, so these are velocity coordinates), the Euler
//!   parameters of partly held rotational nodes, and one multiplier per kept constraint (rigid
//!   and input deformations, normalisations of partly held nodes). The stiffness is the Newton
//!   matrix of statics at the state: K = K_m + K_g with the pre-stress, the constraint forces,
//!   the normalisation terms and the load stiffness of moments, exactly as in the dense path.
//!   The mass is assembled element by element in the same coordinates (Tᵀ M_e T).
//! - **Constraints** stay in the saddle-point form: the shift-invert operator solves
//!   `[K − σM, Gᵀ; G, 0] [u; μ] = [M v; 0]`, so every vector it returns satisfies G u = 0, and
//!   the Lanczos vectors stay in the constrained space without a null-space basis.
//! - **Factorisation**: the project's own sparse L D Lᵀ (`math::sparse_lu`) with diagonal
//!   pivots, in an AMD order of the coordinates with every constraint row placed right after the
//!   last coordinate it couples (so that its pivot exists); Sylvester's law of inertia then
//!   counts the eigenvalues below the shift (negative pivots minus constraints). When L D Lᵀ
//!   breaks down (a massless rigid part, say), LU with partial pivoting is used instead, without
//!   the inertia count.
//! - **Shift**: σ = 0 when K is positive definite on the constrained space (the inertia says
//!   so); otherwise (zero-frequency motions, a buckled state) σ < 0 is lowered in steps until
//!   no eigenvalue lies below it. So the wanted eigenvalues are the largest θ = 1/(λ − σ). A
//!   shift at which the operator amplifies some directions far more than the last wanted mode
//!   (zero-frequency modes, or a small σ that only just regularises a massless part) is
//!   replaced after a first pass by one a tenth of the wanted range below the lowest
//!   eigenvalue.
//! - **Massless directions** need no special treatment: the operator maps everything onto
//!   vectors whose massless part follows the massive part quasi-statically, which is the static
//!   condensation of the dense path; the start vector is passed through the operator first, and
//!   every converged vector is purified by one more application. Infinite eigenvalues never
//!   appear (they are θ = 0).
//! - **Eigen iteration**: Krylov–Schur restarted Lanczos (Stewart 2001) in the M inner product
//!   with full reorthogonalisation (classical Gram–Schmidt, twice), converged when the residual
//!   of every wanted Ritz pair is below [`TOL`] |θ|. A **Sturm check** (the inertia at a shift
//!   just above the last wanted eigenvalue) then confirms that no eigenvalue was missed (a
//!   multiple eigenvalue, which a single-vector Lanczos may find only once); missed ones are
//!   found by further runs deflated against the modes found.
//! - **Projected eigenproblem**: the Ritz pairs of the (at most a few dozen) projected matrix
//!   come from the project's own small symmetric solver ([`crate::math::small_eigen`]:
//!   Householder tridiagonalisation, implicit QL, only the eigenvectors of the wanted and kept
//!   Ritz values formed), faer's beyond [`SMALL_EIGEN_MAX`]; a general solver's fixed costs
//!   exceed the whole iteration on small models.
//! - **Result**: the Ritz vectors (M-orthonormal by the reorthogonalisation; purified and
//!   orthonormalised again when there are massless directions), and as eigenvalues their
//!   Rayleigh quotients with the strain energy evaluated through the element deformations
//!   ([`crate::statics::ReducedLinear::material_energy2`]): on fine meshes the stiffness
//!   entries exceed the stiffness of a smooth mode by many orders of magnitude, and both the
//!   factorisation (σ + 1/θ) and the product uᵀ K u lose the lowest eigenvalues to round-off.

mod basis;
mod lanczos;
mod problem;
mod refined;
mod shifted;

use super::ModalError;
use crate::linalg::EigenError;
use crate::linearized::Tangent;
use crate::model::Model;
use crate::statics::{MaterialOperator, StepResult};
#[cfg(test)]
use basis::projected_eigen_largest;
use basis::{basis_combine, dot, projected_eigen, Cols, PAR_MIN};
use faer::Mat;
use lanczos::lanczos_runs;
use problem::Problem;
use rayon::prelude::*;
use shifted::Shifted;

/// Convergence tolerance of a Ritz pair (θ, x) of the shift-invert operator S:
/// ‖S x − θ x‖_M ≤ TOL |θ|.
pub const TOL: f64 = 1e-10;

/// The largest relative difference between a mode's ω² from the shift-invert iteration (its
/// Ritz value) and the Rayleigh quotient of its vector (strain energy through the element
/// deformations): the Rayleigh quotient is exact to second order in the vector's error, the
/// Ritz value to first order in the error of the solves, so a larger difference means the
/// solves lost the mode's digits ([`ModalError::SparseInaccurate`]). (The clamped strip of 10⁴
/// beams of 5 µm: 3.3·10⁻³ on its first mode, whose Rayleigh quotient is the closed form's to
/// 7 digits; of 10⁵ beams: Ritz values of the wrong sign.)
pub const RITZ_AGREEMENT: f64 = 0.05;

/// Largest number of operator applications per wanted mode (plus a constant) before the
/// iteration gives up.
const MAX_APPLICATIONS_PER_MODE: usize = 60;

/// The result of the sparse path: eigenvalues ascending and mass-normalised shapes in x.
pub(crate) struct SparseModes {
    /// ω², ascending.
    pub eigenvalues: Vec<f64>,
    /// Shapes δx (length nx), δxᵀ M δx = 1.
    pub shapes: Vec<Vec<f64>>,
    /// Number of minimal coordinates (coordinates minus constraints).
    pub ndof: usize,
    /// Directions without inertia (infinite eigenvalues of the pencil).
    pub massless: usize,
    /// Kinetic energy split of every mode: per node (translation, rotation), the rows of the
    /// node in uᵀ M u (the same split as in x: the rotation increments of a node map onto its
    /// own Euler parameters only).
    pub kinetic: Vec<NodeKinetic>,
    /// Number of rigid-body modes at the start of `eigenvalues` (`rigid` module).
    pub rigid: usize,
    /// When the listed eigenvalues show no gap of their own: the number of eigenvalues below
    /// the probe shift of the `rigid` module, by the inertia.
    pub below_gap: Option<usize>,
    /// ω² of every mode from the shift-invert iteration (its Ritz value), in the order of
    /// `eigenvalues` (which are Rayleigh quotients).
    pub ritz: Vec<f64>,
}

impl SparseModes {
    /// [`ModalError::SparseInaccurate`] when an elastic mode's Ritz value and Rayleigh quotient
    /// differ by more than [`RITZ_AGREEMENT`]: a converged Ritz pair of the computed operator
    /// whose vector is not a mode, because the solves lost its digits. (The rigid-body modes
    /// are round-off in both; call this once `rigid` is final.)
    fn check_accuracy(&self) -> Result<(), ModalError> {
        let bad: Vec<usize> = (self.rigid..self.eigenvalues.len())
            .filter(|&k| {
                let (l, r) = (self.eigenvalues[k], self.ritz[k]);
                // (NaN counts as a disagreement)
                let agree = (l - r).abs() <= RITZ_AGREEMENT * l.abs().max(r.abs());
                !agree
            })
            .collect();
        match bad.first() {
            Some(&k) => Err(ModalError::SparseInaccurate {
                mode: k + 1,
                ritz: self.ritz[k],
                rayleigh: self.eigenvalues[k],
                inaccurate: bad.len(),
                listed: self.eigenvalues.len(),
            }),
            None => Ok(()),
        }
    }
}

/// Kinetic energy of one mode per node: (translation, rotation).
type NodeKinetic = Vec<(f64, f64)>;

/// The lowest `count` eigenpairs on the sparse path.
pub(crate) fn sparse_modes(t: &Tangent, count: usize) -> Result<SparseModes, ModalError> {
    rigid::modes_listing_rigid(&Problem::new(t), t.model(), t.step(), count)
}

/// A static field δx (length nx) with the multipliers of every constraint row.
pub(crate) type HeldResponse = (Vec<f64>, Vec<f64>);

/// The sparse problem of a model at a step, kept by [`sparse_modes_held`] for further solves
/// on the same matrices ([`SparseProblem::static_responses`]).
pub(crate) struct SparseProblem(Problem);

/// [`sparse_modes`], keeping the sparse problem for static solves with the same matrices, with
/// constraint rows added after those of the Newton system (each
/// row as (x index, coefficient) pairs of a vector in x, mapped onto the coordinate unknowns):
/// for the state space, which frees held coordinates in a copy of the model and holds them
/// again by these rows.
pub(crate) fn sparse_modes_held(
    t: &Tangent,
    count: usize,
    rows: &[Vec<f64>],
) -> Result<(SparseModes, SparseProblem), ModalError> {
    let p = Problem::with_rows(t, rows);
    let sm = plain_then_refined(|refine| {
        let sm = modes_of(&p, t.model(), t.step(), count, refine)?;
        sm.check_accuracy().map(|()| sm)
    })?;
    // (the static solves with the problem factor it again, with its K values)
    p.restore_k(t.model(), t.step());
    Ok((sm, SparseProblem(p)))
}

impl SparseProblem {
    /// The first added constraint row ([`sparse_modes_held`]); the rows of the Newton system
    /// come before it.
    pub(crate) fn first_added_row(&self) -> usize {
        self.0.lin.n()
    }

    /// The row of the system that holds deformation `e` (a rigid or input deformation).
    pub(crate) fn deformation_row(&self, e: usize) -> Option<usize> {
        self.0.lin.constraint_row(e)
    }

    /// For each list of constraint values (row, value): the solution of the linearised statics
    /// without loads whose constrained quantities take these values, as δx (length nx) and the
    /// multipliers of every constraint row (indexed from the first constraint row, nc).
    pub(crate) fn held_responses(
        &self,
        model: &Model,
        step: &StepResult,
        values: &[Vec<(usize, f64)>],
    ) -> Result<Vec<HeldResponse>, ModalError> {
        let p = &self.0;
        let rhs: Vec<Vec<f64>> = values
            .iter()
            .map(|vals| {
                let mut b = vec![0.0; p.n];
                for &(r, v) in vals {
                    b[r] += v;
                }
                b
            })
            .collect();
        Ok(saddle_solutions(p, model, step, &rhs)?
            .into_iter()
            .map(|z| (p.lin.to_x(model, &step.x, &z[..p.nc]), z[p.nc..].to_vec()))
            .collect())
    }

    /// Number of coordinate unknowns (the constraint rows follow).
    pub(crate) fn n_coords(&self) -> usize {
        self.0.nc
    }

    /// δx = K⁻¹ f of each load in x (module `static_solve`).
    pub(crate) fn static_responses(
        &self,
        model: &Model,
        step: &StepResult,
        loads: &[Vec<f64>],
    ) -> Result<Vec<Vec<f64>>, ModalError> {
        static_responses(&self.0, model, step, loads)
    }
}

/// The scale of the eigenvalues, from the diagonals of K and M: the largest Rayleigh quotient
/// of a unit coordinate that carries mass; when every coordinate with mass has no stiffness of
/// its own (a point mass on a node that only a rigid body holds: its stiffness reaches it through
/// the constraints), the largest stiffness over the largest mass. It sets the round-off level of
/// the shifts and the shift above every finite eigenvalue that counts the massless directions,
/// so it must never collapse to zero while the model has mass and stiffness.
fn eigenvalue_scale(kd: &[f64], md: &[f64]) -> f64 {
    let own = kd
        .iter()
        .zip(md)
        .filter(|(_, &m)| m > 0.0)
        .map(|(&k, &m)| k.abs() / m)
        .fold(0.0f64, f64::max);
    let k_max = kd.iter().fold(0.0f64, |a, &k| a.max(k.abs()));
    let m_max = md.iter().copied().fold(0.0f64, f64::max);
    let across = if m_max > 0.0 { k_max / m_max } else { 0.0 };
    own.max(across).max(f64::MIN_POSITIVE)
}

/// `modes(refine)` with plain solves, and again with refined ones (`refined` module) when the
/// plain ones lost the modes' digits (the accuracy check's error).
fn plain_then_refined<T>(
    mut modes: impl FnMut(bool) -> Result<T, ModalError>,
) -> Result<T, ModalError> {
    match modes(false) {
        Err(ModalError::SparseInaccurate { .. }) => modes(true),
        r => r,
    }
}

/// The lowest `count` eigenpairs of the problem `p` of `model` at `step`.
/// `refine`: refined solves (`refined` module), for when the plain ones lose the modes' digits.
fn modes_of(
    p: &Problem,
    model: &Model,
    step: &StepResult,
    count: usize,
    refine: bool,
) -> Result<SparseModes, ModalError> {
    let nc = p.nc;
    let n_constraints = p.n - nc;
    if nc < n_constraints {
        // more constraints than coordinates: some repeat others (the dense path removes them)
        return Err(ModalError::SparseSingular);
    }
    if nc == n_constraints {
        return Err(ModalError::NoDof);
    }
    if p.m_val.iter().all(|&v| v == 0.0) {
        return Err(ModalError::NoMass);
    }
    let ndof = nc - n_constraints;
    // (released by an earlier run of the plain solves)
    p.restore_k(model, step);
    let exact_parts = refine.then(|| {
        (
            MaterialOperator::new(model, p.lin.setup(), &step.x),
            p.constraint_entries(),
        )
    });
    let mut op = match &exact_parts {
        Some((km, g)) => Shifted::refined(p, refined::Exact { model, km, g }),
        None => Shifted::new(p),
    };
    let (kd, md) = p.diagonals();
    let lambda_ref = eigenvalue_scale(&kd, &md);
    let with_mass = md.iter().filter(|&&m| m > 0.0).count();
    drop((kd, md));
    // massless directions: the finite eigenvalues all lie below a shift far above them, counted
    // in the factorisation itself before it is made at the shift of the iteration, so that no
    // copy of it is needed (when L D Lᵀ cannot count there — a coordinate with neither
    // stiffness nor mass of its own, held only through constraints, is a zero pivot at any
    // shift — the finite eigenvalues are at most as many as the coordinates with mass: M is
    // positive semi-definite, so a zero diagonal entry is a zero row, and its rank on the
    // constrained space is no larger)
    let massless = match op.count_below_in_place(p, 1e8 * lambda_ref) {
        Some(finite) if finite <= ndof => ndof - finite,
        _ => ndof - with_mass.min(ndof),
    };
    // shift: 0 when K is positive definite on the constrained space, else lowered until no
    // eigenvalue lies below it (inertia), starting just above the round-off level
    let mut shifts = vec![0.0];
    let floor = f64::EPSILON * lambda_ref / nc as f64;
    shifts.extend((0..12).map(|i| -floor * 100f64.powi(i)));
    // (refined solves are needed where the factorisation's round-off reaches the lowest
    // eigenvalues: there its inertia may count eigenvalues below a shift that has none, so a
    // shift is also taken when a refined solve at it converges, A(σ) being regular for the
    // accurate products; not when it is singular, as a free model's at σ = 0)
    let inertia_ok = |op: &mut Shifted| op.below == Some(0) || (refine && op.regular_refined(p));
    let mut chosen = None;
    for &s in &shifts {
        if op.factor(p, s, false) && inertia_ok(&mut op) {
            chosen = Some(s);
            break;
        }
    }
    if chosen.is_none() {
        // no L D Lᵀ without eigenvalues below the shift: LU, without the inertia check
        for &s in &shifts {
            if op.factor(p, s, true) {
                chosen = Some(s);
                break;
            }
        }
    }
    let Some(mut sigma) = chosen else {
        let names: Vec<String> = super::massless_nodes(model, &step.x)
            .iter()
            .map(|&i| model.nodes[i].name.clone())
            .collect();
        if !names.is_empty() {
            return Err(ModalError::MasslessMechanism {
                nodes: names.join(", "),
            });
        }
        return Err(ModalError::SparseSingular);
    };
    // an unstressed state's stiffness is positive semi-definite on the constrained space: a
    // shift the inertia had to put far below the round-off of zero eigenvalues (ε λ_ref) counts
    // eigenvalues the model cannot have, so the factorisation has lost the lowest modes; refine
    // from the start instead of a plain run the accuracy check would reject (the 10⁵-beam TOML
    // strip: σ = −1.7e10 and 111 operator applications)
    let unstressed = p.lin.geo.iter().all(|&v| v == 0.0) && p.extra_k.is_empty();
    if !refine && unstressed && sigma < -1e2 * f64::EPSILON * lambda_ref {
        // (this run's factorisation released first: the refined run makes its own)
        drop(op);
        return modes_of(p, model, step, count, true);
    }
    let n_finite = ndof - massless;
    if n_finite == 0 {
        // the mass lies only in directions the constraints remove (as the dense path finds it)
        return Err(ModalError::NoMass);
    }
    let want = count.min(n_finite);
    if want == 0 {
        return Ok(SparseModes {
            eigenvalues: Vec::new(),
            shapes: Vec::new(),
            ndof,
            massless,
            kinetic: Vec::new(),
            rigid: 0,
            below_gap: None,
            ritz: Vec::new(),
        });
    }
    let max_applications = 200 + MAX_APPLICATIONS_PER_MODE * want;
    // the Lanczos phase holds the basis beside the factorisation (with refined solves also
    // GMRES's vectors and the element Jacobians): the peak of a large model's modal analysis,
    // which K is released from (made again from the model for the factorisations)
    op.release_k_between(p, model, step, refine);
    let (mut found, mut thetas, mut applications) =
        lanczos_runs(p, &mut op, want, max_applications, massless > 0)?;
    // A shift that makes the operator amplify some directions far more than the wanted modes
    // costs these digits when they are orthogonalised against those directions: a shift far
    // closer to the lowest eigenvalue than to the last wanted one (zero-frequency motions, an
    // unstable mode), or a small negative shift that only just regularises a matrix singular
    // in directions the constraints remove (a massless or stiffness-free part of a rigid
    // body). Then shift again, clearly below the lowest eigenvalue (the inertia confirms it).
    let mut lam: Vec<f64> = thetas.iter().map(|&t| sigma + 1.0 / t).collect();
    lam.sort_by(f64::total_cmp);
    let (l1, lk) = (lam[0], lam[lam.len().min(want) - 1]);
    let dominated = lk - sigma > 1e6 * (l1 - sigma);
    let barely_regular = sigma < 0.0 && -sigma < 1e-3 * (l1 - sigma);
    if dominated || barely_regular {
        let s2 = (l1 - 0.1 * (lk - l1)).min(-0.5 * l1.abs());
        if op.factor(p, s2, false) && inertia_ok(&mut op) {
            let budget = max_applications.saturating_sub(applications).max(1);
            let (f2, t2, a2) = lanczos_runs(p, &mut op, want, budget, massless > 0)?;
            (found, thetas, sigma, applications) = (f2, t2, s2, applications + a2);
        } else if !op.factor(p, sigma, true) {
            return Err(ModalError::SparseSingular);
        }
    }
    debug_assert!(applications <= 2 * max_applications);
    // the lowest `want` by θ; purified by one more application when there are massless
    // directions (their components then follow the massive ones exactly)
    let mut order: Vec<usize> = (0..thetas.len()).collect();
    order.sort_by(|&a, &b| (sigma + 1.0 / thetas[a]).total_cmp(&(sigma + 1.0 / thetas[b])));
    order.truncate(want);
    let nf = order.len();
    // the wanted Ritz vectors taken out of the found ones (moved, not copied), the others
    // released before the mode shapes in x are made (the peak of a large model's modal
    // analysis)
    let mut found: Vec<Option<Vec<f64>>> = found.into_iter().map(Some).collect();
    let mut y: Cols = Vec::with_capacity(nf);
    for &i in &order {
        let xc = found[i].take().expect("each Ritz vector is taken once");
        if massless > 0 {
            let mut out = vec![0.0; nc];
            op.apply(p, &xc, &mut out);
            y.push(out);
        } else {
            y.push(xc);
        }
    }
    drop(found);
    // the operator is not applied again: its vectors and the factorisation's values are
    // released (the rigid-body probe below refactors at its own shift if it counts)
    op.release_factors();
    // M-orthonormal: the Ritz vectors are (full reorthogonalisation); purified ones are made so
    // again (Löwdin: Y (YᵀMY)^-½, the nearest M-orthonormal set)
    let q: Cols = if massless > 0 {
        let my: Cols = y
            .iter()
            .map(|yc| {
                let mut m = vec![0.0; nc];
                p.m_times(yc, &mut m);
                m
            })
            .collect();
        let g = Mat::from_fn(nf, nf, |a, b| {
            0.5 * (dot(&y[a], &my[b]) + dot(&y[b], &my[a]))
        });
        drop(my);
        let (gs, gu) = projected_eigen(g.as_ref())?;
        if (0..nf).any(|i| gs[i].is_nan() || gs[i] <= 0.0) {
            return Err(ModalError::Eigen(EigenError::NotPositiveDefinite {
                what: "projected mass",
                index: 0,
                hint: "the converged modes are linearly dependent",
            }));
        }
        let inv_sqrt = Mat::from_fn(nf, nf, |a, b| {
            (0..nf)
                .map(|k| gu[(a, k)] * gu[(b, k)] / gs[k].sqrt())
                .sum::<f64>()
        });
        basis_combine(&y, inv_sqrt.as_ref())
    } else {
        y
    };
    // eigenvalues: Rayleigh quotients of the shapes in x, the stiffness through the element
    // deformations, the geometric and point-mass stiffness uᵀ K_g u and the mass uᵀ M u in the
    // coordinates
    let has_geo = p.lin.geo.iter().any(|&v| v != 0.0);
    let shape_of = |u: &Vec<f64>| -> (Vec<f64>, f64, f64) {
        let shape = p.lin.to_x(model, &step.x, u);
        let mut g2 = 0.0;
        if has_geo {
            let mut e = 0;
            p.lin.for_each_entry(|r, c| {
                let gv = p.lin.geo[e];
                if gv != 0.0 {
                    g2 += gv * u[r] * u[c];
                }
                e += 1;
            });
        }
        for &(r, c, kv) in &p.extra_k {
            g2 += kv * u[r] * u[c];
        }
        let mut mu = vec![0.0; nc];
        p.m_times(u, &mut mu);
        let m2: f64 = u.iter().zip(&mu).map(|(a, b)| a * b).sum();
        (shape, g2, m2)
    };
    let parts: Vec<(Vec<f64>, f64, f64)> = if nc < PAR_MIN {
        q.iter().map(shape_of).collect()
    } else {
        q.par_iter().map(shape_of).collect()
    };
    let mut shapes = Vec::with_capacity(nf);
    let mut gm = Vec::with_capacity(nf);
    for (shape, g2, m2) in parts {
        shapes.push(shape);
        gm.push((g2, m2));
    }
    let e2 = p.lin.material_energy2(model, &step.x, &shapes);
    let lam: Vec<f64> = (0..nf).map(|k| (e2[k] + gm[k].0) / gm[k].1).collect();
    // ascending (a stable sort: equal eigenvalues keep the order of their Ritz vectors)
    let mut rank: Vec<usize> = (0..nf).collect();
    rank.sort_by(|&a, &b| lam[a].total_cmp(&lam[b]));
    let eigenvalues: Vec<f64> = rank.iter().map(|&k| lam[k]).collect();
    let ritz: Vec<f64> = rank
        .iter()
        .map(|&k| sigma + 1.0 / thetas[order[k]])
        .collect();
    // the rigid-body probe refactors at its shift, with K made again: the shapes in x (larger
    // than the vectors in the coordinates) are made again after it instead of held through it
    let tau = rigid::probe_shift(sigma, lambda_ref, &eigenvalues, n_finite);
    if tau.is_some() {
        shapes = Vec::new();
    }
    let below_gap = tau.and_then(|tau| op.count_below_in_place(p, tau));
    drop(op);
    // each mode in the order of the eigenvalues from its vector, which is released as soon as
    // the mode is made: the shape (made again when it was released) and the kinetic energy by
    // node
    let mut shapes = shapes.into_iter();
    // (a mode's vector and its shape when it was kept)
    type Job = (Vec<f64>, Option<Vec<f64>>);
    let mut vectors: Vec<Option<Job>> = q.into_iter().map(|u| Some((u, shapes.next()))).collect();
    let jobs: Vec<Job> = rank
        .iter()
        .map(|&k| vectors[k].take().expect("each mode is made once"))
        .collect();
    drop(vectors);
    let group = p.lin.coord_nodes(model);
    let mode_of = |(u, shape): Job| -> (Vec<f64>, NodeKinetic) {
        let shape = shape.unwrap_or_else(|| p.lin.to_x(model, &step.x, &u));
        // (M u formed again: holding it from the eigenvalues on would add a vector per mode)
        let mut mu = vec![0.0; nc];
        p.m_times(&u, &mut mu);
        let mut kinetic = vec![(0.0, 0.0); model.nodes.len()];
        for (m, (&node, (a, b))) in group.iter().zip(u.iter().zip(&mu)).enumerate() {
            if let Some(t) = kinetic.get_mut(node) {
                if p.lin.is_translation(m) {
                    t.0 += a * b;
                } else {
                    t.1 += a * b;
                }
            }
        }
        (shape, kinetic)
    };
    let made: Vec<(Vec<f64>, NodeKinetic)> = if nc < PAR_MIN {
        jobs.into_iter().map(mode_of).collect()
    } else {
        jobs.into_par_iter().map(mode_of).collect()
    };
    let (shapes, kinetic): (Vec<Vec<f64>>, Vec<NodeKinetic>) = made.into_iter().unzip();
    Ok(SparseModes {
        rigid: rigid::count(&eigenvalues, below_gap),
        ritz,
        eigenvalues,
        shapes,
        ndof,
        massless,
        kinetic,
        below_gap,
    })
}

mod rigid;

mod static_solve;
use static_solve::{saddle_solutions, static_responses};

#[cfg(test)]
mod tests;
