//! The linearised results of a static analysis at a step, as data (theory.md §13.3, §13.4):
//! what is asked for ([`LinearRequest`]), what came out ([`StepLinear`]: [`Compliance`],
//! [`Buckling`], stability) and what could not be computed ([`LinearFailure`], [`LinearError`]).
//! They are computed by the linearised stage, `crate::linearized` (`at_step`); the types live
//! here because a static analysis ([`super::StaticAnalysis`], also a path that stopped
//! part-way) carries them.

use crate::linalg::EigenError;

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

/// The linearised results wanted at every step of a static solution (SPACAR's support
/// stiffness along a stroke, with buckling and stability).
#[derive(Clone, Debug, PartialEq)]
pub struct LinearRequest {
    /// Nodes whose compliance (and support stiffness) is wanted.
    pub compliance: Vec<usize>,
    /// Number of buckling multipliers of each sign (0: no buckling and stability analysis).
    pub buckling: usize,
    /// Memory limit of the dense matrices of these results in bytes (`crate::linearized::dense_bytes`): above
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

/// The linearised results at one step (`crate::linearized::at_step`).
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
