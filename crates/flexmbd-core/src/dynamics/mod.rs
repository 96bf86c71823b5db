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

mod classes;
mod dense;
pub mod dense_size;
mod describe;
mod reduced;
mod solver;
pub mod sparse;
pub mod state_space;
pub mod sweep;

pub use classes::{ClassFractions, ModeClass, INTENDED_FROM, INTERNAL_BELOW};
pub use dense_size::check_dense_size;
pub use describe::{fix_sign, SIGN_TIE_TOL};
pub use reduced::{massless_nodes, reduced_matrices, Reduced};
pub use solver::{
    auto_solver, velocity_dof, EigenSolver, ModalOptions, DENSE_FALLBACK_DOF, SPARSE_THRESHOLD,
};

use crate::linalg::EigenError;
use crate::linearized::Tangent;
use crate::model::Model;
use crate::statics::StepResult;
use describe::describe_all;
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
    /// The class of the mode (paper §5: intended, support, internal, or rigid body).
    pub class: ModeClass,
    /// The body and released fractions that decide [`Mode::class`], with their parts.
    pub fractions: ClassFractions,
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

/// A dense eigenvalue above this fraction of the largest |ω²| is no rigid-body mode: the dense
/// solver resolves the eigenvalues to about 1e3 n ε max |ω²| (`dense.rs`), below it for any
/// model the dense path takes. Below it, the null space of the stiffness decides.
const RIGID_CANDIDATE: f64 = 1e-6;

/// Tolerance of the null space of the scaled reduced stiffness, in units of n ε max |μ|
/// ([`dense_rigid_count`]): a hundred times the round-off of the eigenvalues of an n × n
/// matrix.
pub const RIGID_NULL_TOL: f64 = 100.0;

/// The number of rigid-body modes at the start of the dense spectrum `lam` of `red`: the
/// dimension of the null space of the reduced stiffness K0 + G0 = Zᵀ K Z, counted as its
/// eigenvalues μ with |μ| ≤ [`RIGID_NULL_TOL`] n ε max |μ| after the symmetric diagonal scaling
/// diag(K0)^-½ (which makes the count independent of the units of the coordinates, metres and
/// Euler parameters), at most the number of eigenvalues ω² at the round-off of the dense
/// solver ([`RIGID_CANDIDATE`]).
///
/// Not a gap in ω²: the dense eigenvalues of rigid-body modes are round-off of about ε max ω²,
/// and on fine meshes of thin parts (rotary inertia 1e-8 of the translational mass, the
/// highest ω² growing with the fourth power of the number of elements) that round-off comes
/// within any fixed gap of the first elastic ω² (a 0.2 mm strip of 40 elements: 5e-3 against
/// 2.8e4 rad²/s²). The scaled stiffness alone does not see the mass: its rigid-body
/// eigenvalues stay at 1e-15 of its largest, the first elastic one of that strip at 8e-6.
fn dense_rigid_count(red: &Reduced, lam: &[f64]) -> usize {
    let lmax = lam.iter().fold(0.0f64, |m, l| m.max(l.abs()));
    let candidates = lam
        .iter()
        .take_while(|l| l.abs() <= RIGID_CANDIDATE * lmax)
        .count();
    if candidates == 0 {
        return 0;
    }
    let k = &red.k0;
    let n = k.nrows();
    let dmax = (0..n).fold(0.0f64, |m, i| m.max(k[(i, i)].abs()));
    if !(dmax > 0.0 && dmax.is_finite()) {
        return 0;
    }
    let d: Vec<f64> = (0..n)
        .map(|i| 1.0 / k[(i, i)].abs().max(f64::EPSILON * dmax).sqrt())
        .collect();
    let ks = Mat::from_fn(n, n, |i, j| d[i] * k[(i, j)] * d[j]);
    let Ok(mu) = ks.self_adjoint_eigenvalues(faer::Side::Lower) else {
        return 0;
    };
    let mu_max = mu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = RIGID_NULL_TOL * n as f64 * f64::EPSILON * mu_max;
    mu.iter().filter(|v| v.abs() <= tol).count().min(candidates)
}

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
    /// More than a third of the modes of a model too large for the dense eigen solver.
    #[error("{wanted} modes of a model with {ndof} degrees of freedom: more than a third of them, which the automatic choice computes with the dense eigen solver (all eigenpairs), but its matrices would need about {:.1} GiB, above the limit of {:.1} GiB. Ask for at most {} modes (the lowest, computed by the sparse eigen solver), or choose the eigen solver explicitly", too_large.bytes as f64 / (1u64 << 30) as f64, too_large.limit as f64 / (1u64 << 30) as f64, ndof / 3)]
    TooManyModes {
        /// Modes asked for.
        wanted: usize,
        /// Degrees of freedom.
        ndof: usize,
        /// Why the dense path does not fit.
        too_large: crate::linalg::DenseTooLarge,
    },
    /// The sparse path found no shift at which the shifted stiffness can be factored.
    #[error("sparse eigen solver: the shifted stiffness matrix [K − σM, Gᵀ; G, 0] is singular at every shift tried, so the model has a motion without both stiffness and inertia, or rigid/prescribed constraints that repeat each other. Check the model with the kinematic check, or use the dense eigen solver, which removes repeated constraints")]
    SparseSingular,
    /// The sparse path's shift-invert solves lost the digits of a mode, also when refined: its
    /// Ritz value and the Rayleigh quotient of its vector disagree
    /// ([`sparse::RITZ_AGREEMENT`]).
    #[error("sparse eigen solver: {inaccurate} of the {listed} modes cannot be resolved in double precision, also with the solves refined through the element deformations; the first, mode {mode}, has ω² = {ritz:.6e} from the shift-invert iteration but {rayleigh:.6e} as the Rayleigh quotient of its vector. The stiffness matrix spans more decades than double precision holds (e.g. the bending modes of a chain of very many beams much shorter than their cross-section: its condition grows with the cube of the number of elements). The listed modes are not reliable, and lower ones may be missing. Use fewer, longer elements")]
    SparseInaccurate {
        /// The first inaccurate mode (1-based, in the ascending list).
        mode: usize,
        /// Its ω² from the Lanczos (Ritz) value.
        ritz: f64,
        /// Its ω² as the Rayleigh quotient of its vector.
        rayleigh: f64,
        /// How many listed modes disagree.
        inaccurate: usize,
        /// Modes listed.
        listed: usize,
    },
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
    modes_at(&Tangent::new(model, step), count, opts)
}

/// [`modes_with`] at a linearised stage already at hand (its dense pieces are shared with the
/// other analyses of the same state).
pub fn modes_at(t: &Tangent, count: usize, opts: &ModalOptions) -> Result<Modal, ModalError> {
    let (model, step) = (t.model(), t.step());
    let l = lowest(t, count, opts)?;
    let mut modes = describe_all(model, step, &l.eigenvalues, l.shapes, l.kinetic);
    for m in modes.iter_mut().take(l.rigid) {
        m.rigid_body = true;
        m.frequency = 0.0;
        // its strain energy is round-off of zero: fractions of it mean nothing
        m.strain.clear();
        m.fractions.released = None;
        m.class = ModeClass::RigidBody;
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
    lowest(&Tangent::new(model, step), count, opts).map(|l| l.eigenvalues)
}

/// The lowest `count` eigenvalues ω² at a stage with the number of rigid-body modes at their
/// start ([`Mode::rigid_body`]).
pub(crate) fn eigenvalues_rigid(
    t: &Tangent,
    count: usize,
    opts: &ModalOptions,
) -> Result<(Vec<f64>, usize), ModalError> {
    lowest(t, count, opts).map(|l| (l.eigenvalues, l.rigid))
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

fn lowest(t: &Tangent, count: usize, opts: &ModalOptions) -> Result<Lowest, ModalError> {
    let (model, step) = (t.model(), t.step());
    if opts.resolve(model, count) == EigenSolver::Sparse {
        match sparse::sparse_modes(t, count) {
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
    dense_size::check_dense_modes(model, count, opts)?;
    let red = reduced_matrices(t)?;
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
        rigid: dense_rigid_count(&red, &lam).min(nm),
        eigenvalues: lam[..nm].to_vec(),
        shapes,
        ndof: red.ndof(),
        massless: red.massless(),
        massless_nodes: red.massless_nodes,
        solver: EigenSolver::Dense,
        kinetic: None,
    })
}
