//! The linearised problem at a converged static state: support compliance, buckling load
//! multipliers and the stability of the equilibrium (theory.md §13.3, §13.4).
//!
//! At a state with multipliers μ the Newton matrix splits into the material part
//! K_m = Dᵀ S D and the load-proportional geometric part
//! K_g = Σᵢ σᵢ ∂²eᵢ/∂x² + Σ 2μ_n I_λn − ∂f_ext/∂x (stress resultants, Euler normalisation
//! multipliers and the load stiffness of applied moments), with the constraint Jacobian G of
//! the rigid and input deformations and normalisations. In the null space Z of G (the minimal
//! coordinates of the paper) K_m and K_g are SPACAR's K0 and G0.
//!
//! - Compliance of a node: the response of its translation and rotation to unit forces and
//!   moments on it, from [K_m + K_g, Gᵀ; G, 0]; rotations are ω = 2 Λ̄ dλ. Local axes are the
//!   node's current axes. SPACAR's C = DX (K0 + G0)⁻¹ DXᵀ (theory.md §13.4).
//! - Buckling: (K_m + μ K_g) v = 0 in Z, i.e. SPACAR's eig(−K0, G0): μ is the factor by which the
//!   current load may be multiplied before the tangent stiffness becomes singular.
//! - Stability: the number of negative eigenvalues of Zᵀ (K_m + K_g) Z (buckling multipliers
//!   below 1); non-zero means the configuration has buckled.
//!
//! Dense matrices: meant for flexure models of up to a few thousand coordinates.

use super::{assemble_part, setup, Part, StepResult};
use crate::linalg::{sym_def_eigen, EigenError};
use crate::math::{lambda_bar, rotate};
use crate::model::Model;
use faer::Mat;

/// The linearised static problem at a state (dense).
#[derive(Clone, Debug)]
pub struct Linearized {
    /// x index → unknown index.
    pub unknown: Vec<Option<usize>>,
    /// Material stiffness K_m on the free coordinates.
    pub km: Mat<f64>,
    /// Geometric (load-proportional) stiffness K_g on the free coordinates.
    pub kg: Mat<f64>,
    /// Constraint Jacobian G (constraints × free coordinates).
    pub g: Mat<f64>,
}

/// Failure of a linearised analysis.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinearError {
    /// The tangent system is singular.
    #[error("the tangent stiffness at load factor {load_factor:.4} is singular: the model is a mechanism or has buckled here; compliance is unbounded")]
    Singular {
        /// Load factor of the state.
        load_factor: f64,
    },
    /// An eigenproblem failed.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// A matrix of the state is not finite.
    #[error(transparent)]
    Linalg(#[from] crate::linalg::LinalgError),
    /// The dense matrices would need more memory than the limit allows.
    #[error(transparent)]
    TooLarge(#[from] crate::linalg::DenseTooLarge),
}

fn dense(
    n: usize,
    m: usize,
    tr: &[faer::sparse::Triplet<usize, usize, f64>],
    r0: usize,
    c0: usize,
) -> Mat<f64> {
    let mut a = Mat::zeros(n, m);
    for t in tr {
        if t.row >= r0 && t.row < r0 + n && t.col >= c0 && t.col < c0 + m {
            a[(t.row - r0, t.col - c0)] += t.val;
        }
    }
    a
}

impl Linearized {
    /// The tangent stiffness of the linearised dynamics in x (nx × nx): K = K_m + K_g on the
    /// free coordinates (zero rows and columns elsewhere), minus the centrifugal softening
    /// Ω² M_P of a steady rotation (`assembly::mass::softening_matrix`) at `x`. The one place
    /// where the stiffness of modes and state space is put together.
    pub fn tangent_in_x(&self, model: &Model, x: &[f64]) -> Mat<f64> {
        let nx = model.nx;
        let mut kx = Mat::zeros(nx, nx);
        for i in 0..nx {
            let Some(ui) = self.unknown[i] else { continue };
            for j in 0..nx {
                if let Some(uj) = self.unknown[j] {
                    kx[(i, j)] = self.km[(ui, uj)] + self.kg[(ui, uj)];
                }
            }
        }
        if model.loads.spin.is_some() {
            kx += crate::assembly::mass::softening_matrix(model, x);
        }
        kx
    }
}

/// Bytes of the dense matrices of the linearised results at one step ([`at_step`]), an
/// estimate of the largest set alive at once: K_m and K_g (n_f² each) and G (n_k n_f), with
/// n_f free coordinates and n_k constraints, plus the larger of the compliance's KKT matrix
/// and its LU factors (2 (n_f + n_k)²) and the buckling and stability analyses (the SVD
/// factors of G, n_k² + n_f², the null-space basis and the reduced K_m, K_g with the
/// workspace of the generalised eigenproblem, about 8 n_f² at most). With `modal`, only the
/// linearisation itself (K_m, K_g, G): the part the dense modal analysis adds to its own.
pub fn dense_bytes(model: &Model, modal: bool) -> (usize, u128) {
    let su = setup(model);
    let (nf, nk) = (su.nf as u128, su.nk as u128);
    let lin = 2 * nf * nf + nk * nf;
    let extra = if modal {
        0
    } else {
        (2 * (nf + nk) * (nf + nk)).max(nk * nk + 9 * nf * nf)
    };
    (su.nf, 8 * (lin + extra))
}

/// The size guard of the linearised results: [`LinearError::TooLarge`] when [`dense_bytes`]
/// exceeds `limit`.
pub fn check_dense_size(model: &Model, limit: u64) -> Result<(), LinearError> {
    let (dof, bytes) = dense_bytes(model, false);
    crate::linalg::check_dense_bytes(
        "linearisation (compliance, buckling, stability)",
        "these are computed with dense matrices: ask for them on a model with fewer elements",
        dof,
        bytes,
        limit,
    )?;
    Ok(())
}

/// Linearise at a converged step.
pub fn linearize(model: &Model, step: &StepResult) -> Linearized {
    let su = setup(model);
    let (nf, nk) = (su.nf, su.nk);
    let t = step.load_factor;
    let m = assemble_part(model, &su, &step.x, &step.multipliers, t, Part::Material);
    let g = assemble_part(model, &su, &step.x, &step.multipliers, t, Part::Geometric);
    Linearized {
        unknown: su.unknown,
        km: dense(nf, nf, &m.triplets, 0, 0),
        kg: dense(nf, nf, &g.triplets, 0, 0),
        g: dense(nk, nf, &m.triplets, nf, 0),
    }
}

/// 6 × 6 compliance of a node: rows/columns (x, y, z, rx, ry, rz); column k is the response to
/// a unit force (k < 3) or moment (k ≥ 3).
#[derive(Clone, Debug, serde::Serialize)]
pub struct Compliance {
    /// In global axes [m/N, m/(N·m) = 1/N, rad/N, rad/(N·m)].
    pub global: [[f64; 6]; 6],
    /// In the node's current local axes.
    pub local: [[f64; 6]; 6],
    /// Directions (global x, y, z, rx, ry, rz) held by a support or a prescribed input: their
    /// compliance is zero, their stiffness infinite.
    pub held: [bool; 6],
}

impl Compliance {
    /// Stiffness 1/Cᵢᵢ in each direction (global axes); infinite where the compliance is zero.
    pub fn stiffness_global(&self) -> [f64; 6] {
        std::array::from_fn(|i| 1.0 / self.global[i][i])
    }
    /// Stiffness 1/Cᵢᵢ in each direction (local axes).
    pub fn stiffness_local(&self) -> [f64; 6] {
        std::array::from_fn(|i| 1.0 / self.local[i][i])
    }
}

/// Compliance of `node` at the linearised state (inputs and supports held).
pub fn compliance(
    model: &Model,
    lin: &Linearized,
    step: &StepResult,
    node: usize,
) -> Result<Compliance, LinearError> {
    let (nf, nk) = (lin.km.nrows(), lin.g.nrows());
    let n = nf + nk;
    let kkt = Mat::from_fn(n, n, |i, j| match (i < nf, j < nf) {
        (true, true) => lin.km[(i, j)] + lin.kg[(i, j)],
        (false, true) => lin.g[(i - nf, j)],
        (true, false) => lin.g[(j - nf, i)],
        (false, false) => 0.0,
    });
    let nd = &model.nodes[node];
    let lam = nd
        .ix_rot
        .map(|r| [step.x[r], step.x[r + 1], step.x[r + 2], step.x[r + 3]]);
    let lb = lam.map(|l| lambda_bar(&l));
    // right-hand sides: unit forces and moments
    let mut rhs = Mat::zeros(n, 6);
    for k in 0..3 {
        if let Some(u) = lin.unknown[nd.ix_pos + k] {
            rhs[(u, k)] = 1.0;
        }
        if let (Some(r), Some(lb)) = (nd.ix_rot, lb) {
            for c in 0..4 {
                if let Some(u) = lin.unknown[r + c] {
                    rhs[(u, 3 + k)] = 2.0 * lb[k][c];
                }
            }
        }
    }
    let lu = kkt.partial_piv_lu();
    let sol = faer::prelude::Solve::solve(&lu, &rhs);
    // residual check: a singular system gives garbage or non-finite values
    let res = &kkt * &sol - &rhs;
    let scale = kkt.norm_max() * sol.norm_max() + 1.0;
    if !crate::linalg::all_finite(&sol) || !scale.is_finite() || res.norm_max() > 1e-6 * scale {
        return Err(LinearError::Singular {
            load_factor: step.load_factor,
        });
    }
    let mut c = [[0.0; 6]; 6];
    for k in 0..6 {
        let dx = |i: usize| lin.unknown[i].map_or(0.0, |u| sol[(u, k)]);
        for j in 0..3 {
            c[j][k] = dx(nd.ix_pos + j);
        }
        if let (Some(r), Some(lb)) = (nd.ix_rot, lb) {
            for j in 0..3 {
                c[3 + j][k] = 2.0 * (0..4).map(|cc| lb[j][cc] * dx(r + cc)).sum::<f64>();
            }
        }
    }
    // local axes: v_loc = Rᵀ v_glob, R the node's rotation (columns: images of global axes)
    let rt: [[f64; 3]; 3] = match lam {
        Some(l) => {
            let cols = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|e| rotate(&l, e));
            std::array::from_fn(|i| cols[i]) // row i of Rᵀ = column i of R
        }
        None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };
    let t = |i: usize, j: usize| {
        if i / 3 == j / 3 {
            rt[i % 3][j % 3]
        } else {
            0.0
        }
    };
    let mut local = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let mut v = 0.0;
            for a in 0..6 {
                for b in 0..6 {
                    v += t(i, a) * c[a][b] * t(j, b);
                }
            }
            local[i][j] = v;
        }
    }
    let held = std::array::from_fn(|k| {
        let dof = crate::model::Dof::ALL[k];
        nd.x_index(dof).is_none_or(|i| lin.unknown[i].is_none())
    });
    Ok(Compliance {
        global: c,
        local,
        held,
    })
}

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

/// Buckling load multipliers and modes.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Buckling {
    /// Positive multipliers μ, ascending: the current load times μ buckles the structure.
    pub multipliers: Vec<f64>,
    /// Negative multipliers (buckling under the reversed load), by increasing |μ|.
    pub reversed: Vec<f64>,
    /// Buckling modes as increments of x (same order as `multipliers`).
    #[serde(skip)]
    pub modes: Vec<Vec<f64>>,
}

/// Buckling multipliers (at most `count` of each sign) at the linearised state.
pub fn buckling(model: &Model, lin: &Linearized, count: usize) -> Result<Buckling, LinearError> {
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
pub fn unstable_directions(model: &Model, lin: &Linearized) -> Result<usize, LinearError> {
    let b = buckling(model, lin, usize::MAX)?;
    Ok(b.multipliers.iter().filter(|&&m| m < 1.0 - 1e-9).count())
}

/// The linearised results wanted at every step of a static solution (SPACAR's support
/// stiffness along a stroke, with buckling and stability).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearRequest {
    /// Nodes whose compliance (and support stiffness) is wanted.
    pub compliance: Vec<usize>,
    /// Number of buckling multipliers of each sign (0: no buckling and stability analysis).
    pub buckling: usize,
    /// Memory limit of the dense matrices of these results in bytes ([`dense_bytes`]): above
    /// it every step reports [`LinearError::TooLarge`] instead. Default
    /// [`crate::linalg::DEFAULT_MAX_DENSE_BYTES`].
    pub max_dense_bytes: u64,
}

impl Default for LinearRequest {
    fn default() -> Self {
        Self {
            compliance: Vec::new(),
            buckling: 0,
            max_dense_bytes: crate::linalg::DEFAULT_MAX_DENSE_BYTES,
        }
    }
}

impl LinearRequest {
    /// True when nothing is asked for.
    pub fn is_empty(&self) -> bool {
        self.compliance.is_empty() && self.buckling == 0
    }
}

/// A linearised result that could not be computed at a step, and why.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinearFailure {
    /// The compliance of a node.
    #[error("compliance of `{node}`: {error}")]
    Compliance {
        /// Node name.
        node: String,
        /// Why.
        error: LinearError,
    },
    /// The buckling multipliers.
    #[error("buckling: {0}")]
    Buckling(LinearError),
    /// The stability (count of negative directions of the tangent).
    #[error("stability: {0}")]
    Stability(LinearError),
    /// Nothing could be linearised: the dense matrices would exceed the memory limit.
    #[error("compliance, buckling and stability: {0}")]
    TooLarge(LinearError),
    /// A warning, not a failure: the material stiffness is so ill-conditioned that the
    /// compliance, support stiffness, buckling and stability figures of this step are not
    /// reliable (they are still given).
    #[error("warning: the stiffness matrix is ill-conditioned (condition number {condition:.1e} after scaling: about {digits} of the 16 significant digits of double precision are lost), so the compliance, support stiffness, buckling and stability figures at this step may be wrong by about {:.1e} relative to the largest ones, the small ones even in sign (stiffnesses over many decades, e.g. a very soft element in series with a very stiff one)", f64::EPSILON * condition)]
    IllConditioned {
        /// Condition number of the scaled reduced material stiffness.
        condition: f64,
        /// Decimal digits lost, log10 of the condition number (rounded).
        digits: u32,
    },
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
pub fn stiffness_condition(lin: &Linearized) -> Option<f64> {
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

/// The linearised results at one step ([`at_step`]).
#[derive(Clone, Debug, Default)]
pub struct StepLinear {
    /// Compliance of the requested nodes, by node name, in the order asked.
    pub compliance: Vec<(String, Compliance)>,
    /// Buckling multipliers, when requested.
    pub buckling: Option<Buckling>,
    /// Negative directions of the tangent stiffness (0: stable), when buckling is requested.
    pub unstable_directions: Option<usize>,
    /// What could not be computed at this step (the rest is still there).
    pub failures: Vec<LinearFailure>,
}

/// The linearised results `req` at a converged step: one linearisation, then compliance,
/// buckling and stability from it.
pub fn at_step(model: &Model, step: &StepResult, req: &LinearRequest) -> StepLinear {
    let mut out = StepLinear::default();
    if req.is_empty() {
        return out;
    }
    if let Err(e) = check_dense_size(model, req.max_dense_bytes) {
        out.failures.push(LinearFailure::TooLarge(e));
        return out;
    }
    let lin = linearize(model, step);
    if let Some(condition) = stiffness_condition(&lin).filter(|&c| c > ILL_CONDITIONED) {
        out.failures.push(LinearFailure::IllConditioned {
            condition,
            digits: condition.log10().round().clamp(0.0, 99.0) as u32,
        });
    }
    for &id in &req.compliance {
        let node = model
            .nodes
            .get(id)
            .map_or_else(|| format!("#{id}"), |n| n.name.clone());
        match compliance(model, &lin, step, id) {
            Ok(c) => out.compliance.push((node, c)),
            Err(error) => out.failures.push(LinearFailure::Compliance { node, error }),
        }
    }
    if req.buckling > 0 {
        match buckling(model, &lin, req.buckling) {
            Ok(b) => out.buckling = Some(b),
            Err(e) => out.failures.push(LinearFailure::Buckling(e)),
        }
        match unstable_directions(model, &lin) {
            Ok(n) => out.unstable_directions = Some(n),
            Err(e) => out.failures.push(LinearFailure::Stability(e)),
        }
    }
    out
}
