//! The choice of the eigen solver: dense or sparse is a solver behind one interface, with one
//! automatic rule for every linearised analysis (modes, sweeps, state spaces).

use crate::model::Model;

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
    /// whose dense matrices need more stops with [`super::ModalError::TooLarge`] before they are
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
/// - dense when more than a third of them are wanted, whatever the size (all eigenpairs: a
///   shift-invert Lanczos run for most of the spectrum of a large model would take far longer
///   than the dense solve); where the dense matrices exceed the memory limit of the options,
///   the request is refused ([`super::ModalError::TooManyModes`] above
///   [`DENSE_FALLBACK_DOF`] degrees of freedom: ask for fewer modes, or choose the solver
///   explicitly) instead of starting an impractical sparse solve;
/// - for all modes (`None`, a state space without the static correction): dense up to
///   [`DENSE_FALLBACK_DOF`] degrees of freedom, sparse above (which then needs a number of
///   modes).
///
/// A state space needs all modes unless it keeps the lowest N with the static correction: only
/// then is its truncated model the same on both paths (without the correction the dense path
/// keeps the instantaneous response of the massless directions apart from the dropped modes,
/// which the sparse path cannot).
pub fn auto_solver(ndof: usize, wanted: Option<usize>) -> EigenSolver {
    match wanted {
        Some(c) if ndof > SPARSE_THRESHOLD && c.saturating_mul(3) <= ndof => EigenSolver::Sparse,
        Some(_) => EigenSolver::Dense,
        None if ndof > DENSE_FALLBACK_DOF => EigenSolver::Sparse,
        None => EigenSolver::Dense,
    }
}

/// Whether the automatic choice of `opts` took the dense path for `count` modes of a model of
/// more than [`DENSE_FALLBACK_DOF`] degrees of freedom because more than a third of its modes
/// are wanted ([`auto_solver`]): a dense path that does not fit the memory limit is then
/// refused as [`super::ModalError::TooManyModes`] (ask for fewer modes). (On smaller models
/// it is [`super::ModalError::TooLarge`], which names the sparse solver.)
pub(crate) fn dense_for_many_modes(opts: &ModalOptions, ndof: usize, count: usize) -> bool {
    opts.solver == EigenSolver::Auto && ndof > DENSE_FALLBACK_DOF && count.saturating_mul(3) > ndof
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
