//! Linearised dynamics about a static equilibrium: natural frequencies and mode shapes
//! (theory.md §13.1–13.2, paper §5).
//!
//! M0 δq̈ + (K0 + N0 + G0) δq = 0 in minimal coordinates q. flexmbd builds q in two stages:
//! the velocity coordinates of the free nodal coordinates (translations and angular
//! velocities: T with ẋ = T v, which satisfies every Euler normalisation), then the null space
//! of the constraint Jacobian of the rigid and prescribed deformations (Z₂ with G T Z₂ = 0).
//! With Z = T Z₂:
//!
//! ```text
//! M0 = Zᵀ M Z,    K0 + G0 = Zᵀ (K_m + K_g) Z
//! ```
//!
//! where K_m = Dᵀ S D and K_g the geometric stiffness of the static state (stress resultants,
//! constraint forces, normalisation multipliers, load stiffness of applied moments), so
//! pre-stress is included (N0 vanishes in a static state, theory.md §13.1). Frequencies are
//! basis independent, so they equal those in the paper's q = (x^m, e^m).
//!
//! Massless directions (coordinates with no inertia, which make SPACAR report a singular mass
//! matrix) are removed by static condensation instead of fake inertias: M0 = Q diag(m) Qᵀ,
//! directions with m ≤ 1e-12 max m are condensed out of the stiffness (exact for the quasi-static
//! response of massless coordinates); they are reported.

pub mod dense_size;
pub mod sparse;
pub mod state_space;
pub mod sweep;

pub use dense_size::check_dense_size;

use crate::elements::ElementKind;
use crate::kinematics::columns;
use crate::linalg::{numerical_rank, svd, sym_def_eigen, EigenError};
use crate::math::sparse_lu::sort_small_by;
use crate::model::{DefKind, Model, Partition};
use crate::statics::linear::{linearize, Linearized};
use crate::statics::{roles, Role, StepResult};
use faer::Mat;

/// One mode.
#[derive(Clone, Debug)]
pub struct Mode {
    /// ω² [rad²/s²] (negative: the equilibrium is unstable).
    pub eigenvalue: f64,
    /// Frequency [Hz] (NaN for a negative eigenvalue).
    pub frequency: f64,
    /// Mass-normalised shape in x (δx; rotations as Euler-parameter increments).
    pub shape: Vec<f64>,
    /// Shape in velocity coordinates: per node (translation, rotation vector), for display.
    pub nodal: Vec<([f64; 3], [f64; 3])>,
    /// Strain energy fractions per (element, mode 0-based), largest first (those ≥ 1e-4);
    /// empty for a rigid-body mode.
    pub strain: Vec<(usize, usize, f64)>,
    /// Kinetic energy fractions per node (translation, rotation), largest first (≥ 1e-4).
    pub kinetic: Vec<(usize, f64, f64)>,
    /// A rigid-body mode (see [`rigid_body_count`]): its eigenvalue is round-off of zero, its
    /// frequency is reported as 0 and it is no sign of instability.
    pub rigid_body: bool,
}

/// Ratio of ω² below which the lowest modes count as rigid-body modes: the lowest `k` modes
/// are rigid-body modes when every |ω²| among them is at most this fraction of the next
/// (positive) eigenvalue, the first elastic one. Rigid-body eigenvalues are round-off of zero
/// (of either sign), about ε times the stiffness scale divided by the mass scale; a gap of nine
/// decades in ω² (4.5 in frequency) right above them separates that round-off from any
/// resolved elastic mode (the validation case F01 free–free has its six rigid-body modes below
/// 1e-9 of the first bending mode).
pub const RIGID_BODY_GAP: f64 = 1e-9;

/// The number of rigid-body modes at the start of `eigenvalues` (ascending ω²): the smallest
/// k ≥ 1 such that eigenvalue k is positive and every |ω²| below it is at most
/// [`RIGID_BODY_GAP`] times it; 0 when there is no such gap (e.g. a truly negative ω² of a
/// buckled state, or only rigid-body modes in the list).
pub fn rigid_body_count(eigenvalues: &[f64]) -> usize {
    let mut below = 0.0f64;
    for (k, &l) in eigenvalues.iter().enumerate() {
        if !l.is_finite() {
            return 0;
        }
        if k > 0 && l > 0.0 && below <= RIGID_BODY_GAP * l {
            return k;
        }
        below = below.max(l.abs());
    }
    0
}

use crate::linalg::all_finite;

/// Result of a modal analysis.
#[derive(Clone, Debug)]
pub struct Modal {
    /// Modes by increasing eigenvalue.
    pub modes: Vec<Mode>,
    /// Number of minimal coordinates (degrees of freedom of the linearised system).
    pub ndof: usize,
    /// Number of massless directions condensed out.
    pub massless: usize,
    /// Nodes with a coordinate that carries no inertia at all (diagonal of M zero).
    pub massless_nodes: Vec<usize>,
    /// The eigen solver that computed the modes ([`EigenSolver::Dense`] or
    /// [`EigenSolver::Sparse`]).
    pub solver: EigenSolver,
}

/// Which eigen solver computes the modes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EigenSolver {
    /// The one automatic rule, [`auto_solver`].
    #[default]
    Auto,
    /// All eigenpairs of the dense reduced matrices (minimal basis by SVD, static condensation
    /// of massless directions): O(n³) time, O(n²) memory.
    Dense,
    /// The lowest modes only, by shift-invert Lanczos on the sparse matrices ([`sparse`]):
    /// about linear in the model size.
    Sparse,
}

impl EigenSolver {
    /// Name as on the command line (`auto`, `dense`, `sparse`).
    pub fn name(self) -> &'static str {
        match self {
            EigenSolver::Auto => "auto",
            EigenSolver::Dense => "dense",
            EigenSolver::Sparse => "sparse",
        }
    }
}

/// Settings of a modal analysis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModalOptions {
    /// The eigen solver.
    pub solver: EigenSolver,
    /// Memory limit of the dense eigen path in bytes ([`dense_size::dense_bytes`]): a model
    /// whose dense matrices need more stops with [`ModalError::TooLarge`] before they are
    /// allocated. Default [`crate::linalg::DEFAULT_MAX_DENSE_BYTES`].
    pub max_dense_bytes: u64,
}

impl Default for ModalOptions {
    fn default() -> Self {
        Self {
            solver: EigenSolver::Auto,
            max_dense_bytes: crate::linalg::DEFAULT_MAX_DENSE_BYTES,
        }
    }
}

impl ModalOptions {
    /// The default settings with this eigen solver.
    pub fn with_solver(solver: EigenSolver) -> Self {
        Self {
            solver,
            ..Self::default()
        }
    }
}

/// The sparse path pays off above this many degrees of freedom (velocity coordinates of the
/// free nodal coordinates; [`auto_solver`]). Measured on 2 cores (benches/strip_modes.rs, 6
/// modes of the steel strip): the two paths take the same time at about 24 degrees of freedom
/// (0.3 ms); at 60 the sparse one is 3 times faster (0.6 ms against 1.9 ms), at 420 thirty-six
/// times (3 ms against 116 ms). Below it the dense path, which needs no iteration, costs under
/// a millisecond.
pub const SPARSE_THRESHOLD: usize = 48;

/// The largest model the automatic choice hands to the dense path when it needs all modes
/// ([`auto_solver`]), and to which it falls back when the sparse path fails (repeated
/// constraints, no convergence): O(n³) time and O(n²) memory stay below about a second and
/// 100 MB there.
pub const DENSE_FALLBACK_DOF: usize = 3000;

/// The automatic choice of the eigen solver, the one rule of every linearised analysis (modes,
/// sweeps, state spaces), for a model of `ndof` degrees of freedom ([`velocity_dof`]) of which
/// `wanted` lowest modes are needed (`None`: all of them):
///
/// - sparse when the model has more than [`SPARSE_THRESHOLD`] degrees of freedom and at most a
///   third of its modes are wanted (shift-invert Lanczos finds a few lowest modes in about
///   linear time);
/// - otherwise dense up to [`DENSE_FALLBACK_DOF`] degrees of freedom (all eigenpairs);
/// - sparse above that (the dense matrices would not fit).
///
/// A state space needs all modes unless it keeps the lowest N with the static correction: only
/// then is its truncated model the same on both paths (without the correction the dense path
/// keeps the instantaneous response of the massless directions apart from the dropped modes,
/// which the sparse path cannot).
pub fn auto_solver(ndof: usize, wanted: Option<usize>) -> EigenSolver {
    match wanted {
        Some(c) if ndof > SPARSE_THRESHOLD && c.saturating_mul(3) <= ndof => EigenSolver::Sparse,
        _ if ndof > DENSE_FALLBACK_DOF => EigenSolver::Sparse,
        _ => EigenSolver::Dense,
    }
}

/// Number of velocity coordinates of the free nodal coordinates (translations, and one per
/// free rotation component): the degrees of freedom before the rigid and input constraints.
pub fn velocity_dof(model: &Model) -> usize {
    use crate::model::CoordKind;
    model
        .nodes
        .iter()
        .map(|n| {
            let t = if n.host.is_none() {
                (0..3)
                    .filter(|&k| model.partition.x[n.ix_pos + k] == CoordKind::Free)
                    .count()
            } else {
                0
            };
            let r = n.ix_rot.map_or(0, |r| {
                (1..4)
                    .filter(|&k| model.partition.x[r + k] == CoordKind::Free)
                    .count()
            });
            t + r
        })
        .sum()
}

impl ModalOptions {
    /// The solver [`EigenSolver::Auto`] stands for, for `count` modes of `model`.
    pub fn resolve(&self, model: &Model, count: usize) -> EigenSolver {
        match self.solver {
            EigenSolver::Auto => auto_solver(velocity_dof(model), Some(count)),
            s => s,
        }
    }
}

/// Why a modal analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    /// Linear algebra failure.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// A matrix of the state is not finite (coordinates beyond the range of f64 arithmetic).
    #[error("the linearised model at this state is not finite (products of the coordinates overflow double precision: are node positions beyond about 1e150 m?)")]
    NonFinite(#[from] crate::linalg::LinalgError),
    /// No mass at all.
    #[error("the model has no mass: give beams a material with density, or add point masses or inertia tensors")]
    NoMass,
    /// A massless part is a mechanism (its condensed stiffness is singular).
    #[error("massless coordinates form a mechanism (zero stiffness and zero inertia); nodes without inertia: {nodes}. Give them mass or fix them")]
    MasslessMechanism {
        /// Node names.
        nodes: String,
    },
    /// A result of the analysis (eigenvalue, mode shape, matrix) is not finite: never returned
    /// as a result.
    #[error("the modal analysis produced numbers that are not finite ({what}): the linearised model is singular or overflows double precision at this state")]
    NonFiniteResult {
        /// What is not finite.
        what: &'static str,
    },
    /// Nothing can move.
    #[error("the model has no degree of freedom: every coordinate is fixed or prescribed")]
    NoDof,
    /// The dense eigen path would need more memory than the limit allows.
    #[error(transparent)]
    TooLarge(#[from] crate::linalg::DenseTooLarge),
    /// The dense eigen solver cannot resolve part of the spectrum.
    #[error("dense eigen solver: {unresolved} of the {n} modes cannot be resolved in double precision: the model's ω² span {spread:.1e} (masses or stiffnesses over many decades, e.g. the rotary inertia of thin sheets). Use the sparse eigen solver, which computes the lowest modes accurately, or fewer, longer elements")]
    DenseInaccurate {
        /// Modes without an accurate eigenvalue.
        unresolved: usize,
        /// Number of modes.
        n: usize,
        /// Ratio of the largest to the smallest resolved |ω²|.
        spread: f64,
    },
    /// The sparse path found no shift at which the shifted stiffness can be factored.
    #[error("sparse eigen solver: the shifted stiffness matrix [K − σM, Gᵀ; G, 0] is singular at every shift tried, so the model has a motion without both stiffness and inertia, or rigid/prescribed constraints that repeat each other. Check the model with the kinematic check, or use the dense eigen solver, which removes repeated constraints")]
    SparseSingular,
    /// The Lanczos iteration of the sparse path did not converge.
    #[error("sparse eigen solver: only {found} of the {wanted} lowest modes converged after {applications} shift-invert steps (restarted Lanczos, tolerance 1e-10). Ask for fewer modes, or use the dense eigen solver if the model has at most a few thousand degrees of freedom")]
    NotConverged {
        /// Modes converged.
        found: usize,
        /// Modes wanted.
        wanted: usize,
        /// Operator applications used.
        applications: usize,
    },
}

/// Minimal-coordinate basis Z (nx × ndof) at a state: velocity coordinates of the free
/// coordinates, restricted to the null space of the rigid/prescribed deformation constraints.
///
/// A non-finite x (or Jacobian) is an error, not a basis.
pub fn minimal_basis(model: &Model, x: &[f64]) -> Result<Mat<f64>, crate::linalg::LinalgError> {
    // velocity basis T of the statics unknowns (free coordinates)
    let part = Partition {
        x: model.partition.x.clone(),
        e: vec![DefKind::Free; model.ne],
    };
    let cols = columns(model, &part, x);
    let mut t = Mat::zeros(model.nx, cols.len());
    for (j, c) in cols.iter().enumerate() {
        let n = &model.nodes[c.node];
        if c.dof.is_rotation() {
            let r = n.ix_rot.expect("rotation column");
            for k in 0..4 {
                t[(r + k, j)] = c.lambda_rate[k];
            }
        } else {
            t[(n.ix_pos + c.dof.index(), j)] = 1.0;
        }
    }
    // constraint rows: rigid and input deformations
    let ev = crate::assembly::evaluate(model, x);
    let role = roles(model);
    let rows: Vec<usize> = (0..model.ne)
        .filter(|&i| role[i] != Role::Flexible)
        .collect();
    if rows.is_empty() {
        return Ok(t);
    }
    let g = Mat::from_fn(rows.len(), model.nx, |r, c| ev.D[(rows[r], c)]);
    let gt = &g * &t;
    let f = svd(gt.as_ref(), "constraint Jacobian")?;
    let tol = f64::EPSILON.sqrt() * f.s.first().copied().unwrap_or(0.0);
    let r = numerical_rank(&f.s, tol);
    let n = gt.ncols();
    let z2 = Mat::from_fn(n, n - r, |i, j| f.V[(i, r + j)]);
    Ok(&t * &z2)
}

/// The linearised system at a static state in minimal coordinates, with its massless
/// directions split off for static condensation.
///
/// With M0 = Q diag(m) Qᵀ, the coordinates y = Qᵀ δq split into massive (y_m, Q_m, masses
/// m_m > 1e-12 max m) and massless ones (y₀, Q₀). The massless ones follow the massive ones
/// quasi-statically, y₀ = −K₀₀⁻¹ K₀ₘ y_m + K₀₀⁻¹ Q₀ᵀ f, so that the massive ones see the
/// condensed stiffness K_c = K_mm − K_m0 K₀₀⁻¹ K₀ₘ and the force Rᵀ Qᵀ f, R = [I; −K₀₀⁻¹ K₀ₘ].
#[derive(Clone, Debug)]
pub struct Reduced {
    /// Minimal-coordinate basis Z (nx × ndof): δx = Z δq.
    pub z: Mat<f64>,
    /// Mass matrix in x (nx × nx).
    pub mx: Mat<f64>,
    /// Reduced mass M0 = Zᵀ M Z (symmetrised).
    pub m0: Mat<f64>,
    /// Reduced stiffness K0 + G0 = Zᵀ (K_m + K_g) Z (symmetrised).
    pub k0: Mat<f64>,
    /// Massive directions Q_m (ndof × n_m, orthonormal columns).
    pub qm: Mat<f64>,
    /// Masses of the massive directions (M0 restricted to Q_m is diagonal).
    pub mm: Vec<f64>,
    /// Massless directions Q₀ (ndof × n₀, orthonormal columns).
    pub q0: Mat<f64>,
    /// Condensed stiffness K_c (n_m × n_m).
    pub kc: Mat<f64>,
    /// K₀₀⁻¹ K₀ₘ (n₀ × n_m) when there are massless directions.
    pub recover: Option<Mat<f64>>,
    /// K₀₀ = Q₀ᵀ K0 Q₀ (n₀ × n₀, regular when `recover` is set).
    pub k00: Mat<f64>,
    /// Nodes with a free velocity direction without any inertia.
    pub massless_nodes: Vec<usize>,
}

fn sym(a: Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// The reduced matrices (Z, M0, K0 and the massless split) at a converged static state.
pub fn reduced_matrices(model: &Model, step: &StepResult) -> Result<Reduced, ModalError> {
    let lin = linearize(model, step);
    reduced_matrices_with(model, step, &lin)
}

/// [`reduced_matrices`] with the linearisation of the state already at hand.
pub fn reduced_matrices_with(
    model: &Model,
    step: &StepResult,
    lin: &Linearized,
) -> Result<Reduced, ModalError> {
    let z = minimal_basis(model, &step.x)?;
    let ndof = z.ncols();
    if ndof == 0 {
        return Err(ModalError::NoDof);
    }
    let kx = lin.tangent_in_x(model, &step.x);
    let mx = crate::assembly::mass::mass_matrix(model, &step.x);
    let k0 = sym(z.transpose() * &kx * &z);
    let m0 = sym(z.transpose() * &mx * &z);
    let massless_nodes = massless_nodes(model, &step.x);
    // split M0 into massive and massless directions
    let evd = m0
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| EigenError::NoConvergence)?;
    let s = evd.S().column_vector();
    let mmax = (0..ndof).map(|i| s[i]).fold(0.0f64, f64::max);
    if mmax <= 0.0 {
        return Err(ModalError::NoMass);
    }
    let massive: Vec<usize> = (0..ndof).filter(|&i| s[i] > 1e-12 * mmax).collect();
    let zero: Vec<usize> = (0..ndof).filter(|&i| s[i] <= 1e-12 * mmax).collect();
    let q = evd.U();
    let qm = Mat::from_fn(ndof, massive.len(), |i, j| q[(i, massive[j])]);
    let q0 = Mat::from_fn(ndof, zero.len(), |i, j| q[(i, zero[j])]);
    let kmm = sym(qm.transpose() * &k0 * &qm);
    let mm: Vec<f64> = massive.iter().map(|&i| s[i]).collect();
    // static condensation: K_c = K_mm − K_m0 K_00⁻¹ K_0m, recover δq₀ = −K_00⁻¹ K_0m δq_m
    let k00 = sym(q0.transpose() * &k0 * &q0);
    let (kc, recover) = if zero.is_empty() {
        (kmm, None)
    } else {
        let k0m = q0.transpose() * &k0 * &qm;
        let lu = k00.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &k0m);
        let res = &k00 * &sol - &k0m;
        // a singular K₀₀ (a massless direction without stiffness) gives inf/NaN in the solve
        // (norm_max does not see NaN, so every entry is checked), or a solve that does not
        // satisfy its equations, or eigenvalues of K₀₀ at the round-off of K0
        let k00_eig_min = k00
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .map(|v| v.iter().fold(f64::INFINITY, |m, l| m.min(l.abs())))
            .unwrap_or(0.0);
        let k_scale = k0.norm_max();
        if !all_finite(&sol)
            || !all_finite(&res)
            || k00_eig_min.is_nan()
            || k00_eig_min <= 1e2 * f64::EPSILON * k_scale
            || res.norm_max() > 1e-8 * (k00.norm_max() * sol.norm_max() + k0m.norm_max())
        {
            let names: Vec<&str> = massless_nodes
                .iter()
                .map(|&n| model.nodes[n].name.as_str())
                .collect();
            return Err(ModalError::MasslessMechanism {
                nodes: names.join(", "),
            });
        }
        (sym(&kmm - k0m.transpose() * &sol), Some(sol))
    };
    Ok(Reduced {
        z,
        mx,
        m0,
        k0,
        qm,
        mm,
        q0,
        kc,
        recover,
        k00,
        massless_nodes,
    })
}

/// Nodes with a free velocity direction (translation or angular velocity, as the columns of
/// the minimal basis) that carries no inertia at all, in node order.
pub fn massless_nodes(model: &Model, x: &[f64]) -> Vec<usize> {
    let part = Partition {
        x: model.partition.x.clone(),
        e: vec![DefKind::Free; model.ne],
    };
    let blocks = crate::assembly::mass::node_blocks(model, x);
    let mut massless = vec![false; model.nodes.len()];
    for c in columns(model, &part, x) {
        let v: [f64; 7] = if c.dof.is_rotation() {
            std::array::from_fn(|k| if k < 3 { 0.0 } else { c.lambda_rate[k - 3] })
        } else {
            std::array::from_fn(|k| if k == c.dof.index() { 1.0 } else { 0.0 })
        };
        let b = &blocks[c.node];
        let m: f64 = (0..7)
            .map(|i| v[i] * (0..7).map(|j| b[i][j] * v[j]).sum::<f64>())
            .sum();
        if m <= 0.0 {
            massless[c.node] = true;
        }
    }
    (0..model.nodes.len()).filter(|&i| massless[i]).collect()
}

impl Reduced {
    /// Number of minimal coordinates.
    pub fn ndof(&self) -> usize {
        self.z.ncols()
    }

    /// Number of massless directions condensed out.
    pub fn massless(&self) -> usize {
        self.q0.ncols()
    }

    /// All eigenpairs of the condensed problem K_c y = ω² M_mm y: the eigenvalues ω²
    /// ascending and the mass-normalised modes Φ in the minimal coordinates q (ndof × n_m,
    /// massless directions recovered), so that Φᵀ M0 Φ = I and Φᵀ K0 Φ = diag(ω²).
    pub fn eigen(&self) -> Result<(Vec<f64>, Mat<f64>), ModalError> {
        let (lam, v) = diagonal_mass_eigen(&self.kc, &self.mm)?;
        let mut phi = &self.qm * &v;
        if let Some(sol) = &self.recover {
            let y0 = -(sol * &v);
            phi += &self.q0 * &y0;
        }
        if lam.iter().any(|l| !l.is_finite()) {
            return Err(ModalError::NonFiniteResult {
                what: "eigenvalues",
            });
        }
        if !all_finite(&phi) {
            return Err(ModalError::NonFiniteResult {
                what: "mode shapes",
            });
        }
        Ok((lam, phi))
    }

    /// Static flexibility of the massless directions, Q₀ K₀₀⁻¹ Q₀ᵀ (ndof × ndof): the part of
    /// the static response K0⁻¹ that no mode carries (the massless coordinates respond to forces
    /// on them instantaneously).
    pub fn massless_flexibility(&self) -> Mat<f64> {
        let n = self.ndof();
        if self.q0.ncols() == 0 {
            return Mat::zeros(n, n);
        }
        let lu = self.k00.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, self.q0.transpose());
        &self.q0 * &sol
    }
}

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
fn diagonal_mass_eigen(k: &Mat<f64>, mm: &[f64]) -> Result<(Vec<f64>, Mat<f64>), ModalError> {
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

/// Natural frequencies and modes at a converged static state (at most `count` modes), with
/// the solver chosen automatically ([`EigenSolver::Auto`]).
pub fn modes(model: &Model, step: &StepResult, count: usize) -> Result<Modal, ModalError> {
    modes_with(model, step, count, &ModalOptions::default())
}

/// [`modes`] with settings (the eigen solver).
pub fn modes_with(
    model: &Model,
    step: &StepResult,
    count: usize,
    opts: &ModalOptions,
) -> Result<Modal, ModalError> {
    let l = lowest(model, step, count, opts)?;
    let mut modes = describe_all(model, step, &l.eigenvalues, l.shapes, l.kinetic);
    for m in modes.iter_mut().take(l.rigid) {
        m.rigid_body = true;
        m.frequency = 0.0;
        // its strain energy is round-off of zero: fractions of it mean nothing
        m.strain.clear();
    }
    let finite = |m: &Mode| {
        m.nodal
            .iter()
            .all(|(u, w)| u.iter().chain(w).all(|v| v.is_finite()))
            && m.strain.iter().all(|s| s.2.is_finite())
            && m.kinetic.iter().all(|k| k.1.is_finite() && k.2.is_finite())
    };
    if !modes.iter().all(finite) {
        return Err(ModalError::NonFiniteResult {
            what: "mode shapes or energy fractions",
        });
    }
    Ok(Modal {
        modes,
        ndof: l.ndof,
        massless: l.massless,
        massless_nodes: l.massless_nodes,
        solver: l.solver,
    })
}

/// The lowest `count` eigenvalues ω² only (as [`modes_with`], without the energy split).
pub fn eigenvalues_with(
    model: &Model,
    step: &StepResult,
    count: usize,
    opts: &ModalOptions,
) -> Result<Vec<f64>, ModalError> {
    lowest(model, step, count, opts).map(|l| l.eigenvalues)
}

/// [`eigenvalues_with`] with the number of rigid-body modes at their start ([`Mode::rigid_body`]).
pub(crate) fn eigenvalues_rigid(
    model: &Model,
    step: &StepResult,
    count: usize,
    opts: &ModalOptions,
) -> Result<(Vec<f64>, usize), ModalError> {
    lowest(model, step, count, opts).map(|l| (l.eigenvalues, l.rigid))
}

/// The lowest eigenpairs with the shapes in x, from the solver the options choose.
struct Lowest {
    eigenvalues: Vec<f64>,
    shapes: Vec<Vec<f64>>,
    ndof: usize,
    massless: usize,
    massless_nodes: Vec<usize>,
    solver: EigenSolver,
    /// Kinetic energy per mode and node (translation, rotation), when the solver has it.
    kinetic: Option<Vec<Vec<(f64, f64)>>>,
    /// Number of rigid-body modes at the start ([`rigid_body_count`]).
    rigid: usize,
}

fn lowest(
    model: &Model,
    step: &StepResult,
    count: usize,
    opts: &ModalOptions,
) -> Result<Lowest, ModalError> {
    if opts.resolve(model, count) == EigenSolver::Sparse {
        match sparse::sparse_modes(model, step, count) {
            Ok(mut sm) => {
                sm.shapes.iter_mut().for_each(|s| fix_sign(s));
                if sm.eigenvalues.iter().any(|l| !l.is_finite()) {
                    return Err(ModalError::NonFiniteResult {
                        what: "eigenvalues",
                    });
                }
                if sm.shapes.iter().flatten().any(|v| !v.is_finite()) {
                    return Err(ModalError::NonFiniteResult {
                        what: "mode shapes",
                    });
                }
                return Ok(Lowest {
                    rigid: sm.rigid,
                    eigenvalues: sm.eigenvalues,
                    shapes: sm.shapes,
                    ndof: sm.ndof,
                    massless: sm.massless,
                    massless_nodes: massless_nodes(model, &step.x),
                    solver: EigenSolver::Sparse,
                    kinetic: Some(sm.kinetic),
                });
            }
            // automatic choice: the dense path handles repeated constraints and needs no
            // convergence, when the model is small enough for it
            Err(ModalError::SparseSingular | ModalError::NotConverged { .. })
                if opts.solver == EigenSolver::Auto
                    && velocity_dof(model) <= DENSE_FALLBACK_DOF => {}
            Err(e) => return Err(e),
        }
    }
    dense_size::check_dense_modal(model, opts.max_dense_bytes, false)?;
    let red = reduced_matrices(model, step)?;
    let (lam, phi) = red.eigen()?;
    let nm = count.min(lam.len());
    // back to x
    let phi_m = Mat::from_fn(red.ndof(), nm, |i, k| phi[(i, k)]);
    let dx = &red.z * &phi_m;
    let shapes = (0..nm)
        .map(|k| {
            let mut s: Vec<f64> = (0..model.nx).map(|i| dx[(i, k)]).collect();
            fix_sign(&mut s);
            s
        })
        .collect();
    Ok(Lowest {
        rigid: rigid_body_count(&lam).min(nm),
        eigenvalues: lam[..nm].to_vec(),
        shapes,
        ndof: red.ndof(),
        massless: red.massless(),
        massless_nodes: red.massless_nodes,
        solver: EigenSolver::Dense,
        kinetic: None,
    })
}

/// Relative tolerance of [`fix_sign`]: components whose magnitude is within this fraction of
/// the largest count as equally large.
pub const SIGN_TIE_TOL: f64 = 1e-6;

/// The sign convention of mode shapes, independent of the eigen solver: the component of the
/// shape in x with the largest magnitude is positive; among components within
/// [`SIGN_TIE_TOL`] of the largest, the one with the lowest index decides (docs/dynamics.md,
/// "JSON output").
pub fn fix_sign(shape: &mut [f64]) {
    let big = shape.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if big == 0.0 || !big.is_finite() {
        return;
    }
    let decisive = shape
        .iter()
        .copied()
        .find(|v| v.abs() >= (1.0 - SIGN_TIE_TOL) * big)
        .unwrap_or(big);
    if decisive < 0.0 {
        shape.iter_mut().for_each(|v| *v = -*v);
    }
}

/// The modes with their energy split (element by element, no global matrices): strain
/// energy per element deformation, kinetic energy per node.
fn describe_all(
    model: &Model,
    step: &StepResult,
    eigenvalues: &[f64],
    shapes: Vec<Vec<f64>>,
    kinetic: Option<Vec<Vec<(f64, f64)>>>,
) -> Vec<Mode> {
    use rayon::prelude::*;
    let nm = shapes.len();
    // strain energy per element deformation: ½ (D δx)ᵢ (S D δx)ᵢ, D evaluated once per element;
    // per element one list, mode k's energies at k ne … (k + 1) ne
    let element_energies = |entry: &crate::model::ElementEntry| -> Vec<f64> {
        let s = entry.element.stiffness();
        let mut e = crate::statics::deformation_energies(entry, &s, &step.x, &shapes);
        e.iter_mut().for_each(|v| *v *= 0.5);
        e
    };
    let small = model.elements.len() < 256;
    let per_element: Vec<Vec<f64>> = if small {
        model.elements.iter().map(element_energies).collect()
    } else {
        model
            .elements
            .par_iter()
            .with_min_len(64)
            .map(element_energies)
            .collect()
    };
    // kinetic energy per node: the quadratic form δxᵀ M δx split by rows (a node `at` a host
    // has no translation rows of its own)
    let kinetic = kinetic.unwrap_or_else(|| {
        let refs: Vec<&[f64]> = shapes.iter().map(|v| v.as_slice()).collect();
        let m_shapes = crate::assembly::mass::mass_times(model, &step.x, &refs);
        shapes
            .iter()
            .zip(&m_shapes)
            .map(|(shape, m_shape)| {
                let part =
                    |r: std::ops::Range<usize>| -> f64 { r.map(|i| shape[i] * m_shape[i]).sum() };
                model
                    .nodes
                    .iter()
                    .map(|n| {
                        let tr = if n.host.is_none() {
                            part(n.ix_pos..n.ix_pos + 3)
                        } else {
                            0.0
                        };
                        (tr, n.ix_rot.map_or(0.0, |r| part(r..r + 4)))
                    })
                    .collect()
            })
            .collect()
    });
    let one = |(k, shape): (usize, Vec<f64>)| {
        let mut strain: Vec<(usize, usize, f64)> = Vec::with_capacity(6 * per_element.len());
        for (el, u) in per_element.iter().enumerate() {
            let ne = u.len() / nm;
            strain.extend(
                u[k * ne..(k + 1) * ne]
                    .iter()
                    .enumerate()
                    .map(|(a, &v)| (el, a, v)),
            );
        }
        describe(model, step, eigenvalues[k], shape, &kinetic[k], strain)
    };
    if small || nm < 2 {
        shapes.into_iter().enumerate().map(one).collect()
    } else {
        shapes.into_par_iter().enumerate().map(one).collect()
    }
}

/// Lists up to this long are sorted by insertion in [`describe`] (the same stable order).
const SHORT_SORT: usize = 64;

fn describe(
    model: &Model,
    step: &StepResult,
    eigenvalue: f64,
    shape: Vec<f64>,
    kinetic: &[(f64, f64)],
    strain: Vec<(usize, usize, f64)>,
) -> Mode {
    let frequency = if eigenvalue >= 0.0 {
        eigenvalue.sqrt() / (2.0 * std::f64::consts::PI)
    } else {
        f64::NAN
    };
    // nodal translations and rotation vectors (ω = 2 Λ̄ δλ)
    let nodal: Vec<([f64; 3], [f64; 3])> = model
        .nodes
        .iter()
        .map(|n| {
            let p = n.ix_pos;
            let u = [shape[p], shape[p + 1], shape[p + 2]];
            let w = n.ix_rot.map_or([0.0; 3], |r| {
                let lb = crate::math::lambda_bar(&[
                    step.x[r],
                    step.x[r + 1],
                    step.x[r + 2],
                    step.x[r + 3],
                ]);
                std::array::from_fn(|k| 2.0 * (0..4).map(|c| lb[k][c] * shape[r + c]).sum::<f64>())
            });
            (u, w)
        })
        .collect();
    let total_u: f64 = strain.iter().map(|s| s.2).sum();
    let total_t: f64 = kinetic.iter().map(|(tr, rt)| tr + rt).sum();
    let kinetic = kinetic.iter().enumerate().map(|(i, &(tr, rt))| (i, tr, rt));
    let norm_u = if total_u.abs() > 0.0 { total_u } else { 1.0 };
    let norm_t = if total_t.abs() > 0.0 { total_t } else { 1.0 };
    let mut strain: Vec<(usize, usize, f64)> = strain
        .into_iter()
        .map(|(e, m, u)| (e, m, u / norm_u))
        .filter(|s| s.2.abs() >= 1e-4)
        .collect();
    // stable, largest first (insertion for the short lists of small models)
    let larger = |a: &(usize, usize, f64), b: &(usize, usize, f64)| {
        b.2.abs().total_cmp(&a.2.abs()) == std::cmp::Ordering::Less
    };
    if strain.len() <= SHORT_SORT {
        sort_small_by(&mut strain, larger);
    } else {
        strain.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    }
    let mut kinetic: Vec<(usize, f64, f64)> = kinetic
        .map(|(n, a, b)| (n, a / norm_t, b / norm_t))
        .filter(|k| k.1.abs() + k.2.abs() >= 1e-4)
        .collect();
    let larger = |a: &(usize, f64, f64), b: &(usize, f64, f64)| {
        (b.1 + b.2).total_cmp(&(a.1 + a.2)) == std::cmp::Ordering::Less
    };
    if kinetic.len() <= SHORT_SORT {
        sort_small_by(&mut kinetic, larger);
    } else {
        kinetic.sort_by(|a, b| (b.1 + b.2).total_cmp(&(a.1 + a.2)));
    }
    Mode {
        eigenvalue,
        frequency,
        shape,
        nodal,
        strain,
        kinetic,
        rigid_body: false,
    }
}

#[cfg(test)]
mod tests;
