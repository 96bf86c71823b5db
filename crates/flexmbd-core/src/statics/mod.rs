//! Nonlinear statics with large deflections: load steps, prescribed inputs, reactions.
//!
//! Equilibrium (paper eq. (6) with ẍ = 0): Dᵀσ = f, with σ = S e for the flexible deformations
//! and Lagrange multipliers for the constrained ones. Roles of the deformations in statics:
//!
//! - **flexible**: every deformation with finite stiffness (S_ii > 0), or declared free for the
//!   kinematic check, unless the user lists it as `fixed` explicitly;
//! - **rigid**: declared fixed explicitly, or fixed (the kinematic default) with no stiffness —
//!   constraint e_i(x) = 0 with multiplier σ_i;
//! - **input**: a generalised deformation — constraint e_i(x) = t·value with multiplier σ_i.
//!
//! Unknowns: the free coordinates x^c and the multipliers μ. Newton's method on
//!
//! ```text
//! r(x, μ) = Dᵀσ + Σ 2 μ_n λ_n − f_ext(t) = 0   (free coordinates)
//! g(x)    = e_k(x) − target_k(t)        = 0   (constrained deformations)
//!           λ_nᵀλ_n − 1                 = 0   (rotational nodes)
//! [K  Gᵀ] [Δx]     [r]      K = Dᵀ S D + Σᵢ σᵢ ∂²eᵢ/∂x² + Σ 2 μ_n I_λn − ∂f_ext/∂x
//! [G  0 ] [Δμ] = − [g],     G = ∂g/∂x
//! ```
//!
//! Euler parameters: every rotational node with a free λ component has the normalisation
//! constraint λᵀλ − 1 = 0 with a multiplier (SPACAR's implicit `Euler` element). Element
//! deformations do not depend on ‖λ‖ (docs/rotations.md), so its multiplier vanishes for a
//! fully free node; after every Newton update λ is projected back onto the unit sphere.
//!
//! Loads: dead nodal forces, dead moments (global axes; generalised force 2 Λ̄(λ)ᵀ M on λ, whose
//! derivative gives a load stiffness), gravity and the centrifugal field of a steady rotation on
//! the elements' and point masses, consistent with the mass matrix (`assembly::loads`: for a
//! beam ρA g l0/2 at each end and the end moments ±ρA l0² (t × g)/12), on the reference
//! configuration. All loads and prescribed values grow linearly with the load factor t
//! from 0 to 1 over the load steps (SPACAR's `DELXF`/`DELINPX`); a step that does not converge
//! (or whose residual grows a thousandfold, `DIVERGENCE`) is halved automatically.
//!
//! Implementation of the Newton iteration (none of it changes the equations or the tolerances):
//! the system is solved in reduced unknowns (`Reduction`: three rotation increments per free
//! node instead of four Euler parameters and a normalisation row), with a sparse LU whose
//! structure and ordering are computed once per solve and which is refactored with the previous
//! pivots (L D Lᵀ for symmetric systems, `math::sparse_lu`); beams use closed-form derivatives
//! (`elements::beam::closed_form`); the Euler parameters are updated so that node triads turn with the
//! chords (`chord_consistent_scale`); a load step starts from the last converged state (a
//! secant predictor only with prescribed coordinates).

use crate::assembly::{gather, gather_local, SMALL};
use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{CoordKind, DefKind, Model, Target};
use faer::sparse::Triplet;
use faer::Mat;
use rayon::prelude::*;

/// Solver settings.
#[derive(Clone, Copy, Debug)]
pub struct StaticOptions {
    /// Number of load steps (outputs at t = k/steps).
    pub steps: usize,
    /// Maximum Newton iterations per (sub)step.
    pub max_iterations: usize,
    /// Residual tolerance, relative to the force scale (external and internal forces).
    pub tol_force: f64,
    /// Increment and constraint tolerance, relative to the model size (rotations: absolute).
    pub tol_disp: f64,
    /// Maximum number of step halvings in one load step.
    pub max_halvings: usize,
    /// Backtracking line search on ‖r‖² + (k‖g‖)². Off by default: from a straight beam the
    /// Newton step moves nodes along lines instead of arcs and stretches axially stiff elements
    /// (membrane locking), so every merit function rejects a step that pure Newton recovers
    /// from in a few iterations; step halving is the safeguard instead.
    pub line_search: bool,
    /// The smallest eigenvalues κ of the tangent ([`StepResult::tangent_eigenvalues`]) at every
    /// step of load steps and strokes: off by default there (a dense eigen solve per step, which
    /// costs more than the step itself on small models); arc length always computes them, as it
    /// locates limit points and bifurcations with them.
    pub tangent_eigenvalues: bool,
    /// How the load factor moves along the path: fixed load steps (default) or arc length.
    pub path: PathMethod,
}

/// How a static analysis follows its equilibrium path (docs/statics.md, "Path following").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PathMethod {
    /// The load factor (loads and prescribed values together) grows in `steps` equal steps,
    /// each halved as needed; it cannot pass a limit point of the load factor.
    #[default]
    LoadSteps,
    /// Arc length (Crisfield's cylindrical constraint on the coordinates, with the motion of
    /// the prescribed coordinates): the load factor is an unknown, so the path passes limit
    /// points and snap-backs; the step length adapts to the Newton iterations.
    ArcLength,
}

impl Default for StaticOptions {
    fn default() -> Self {
        Self {
            steps: 10,
            max_iterations: 30,
            tol_force: 1e-9,
            tol_disp: 1e-9,
            max_halvings: 12,
            line_search: false,
            tangent_eigenvalues: false,
            path: PathMethod::LoadSteps,
        }
    }
}

/// Role of a deformation in statics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// σ = S e.
    Flexible,
    /// e = 0, σ a reaction (multiplier).
    Rigid,
    /// e = prescribed value, σ the force needed.
    Input,
}

/// The statics role of every deformation (module docs).
pub fn roles(model: &Model) -> Vec<Role> {
    let mut roles = Vec::with_capacity(model.ne);
    for el in 0..model.elements.len() {
        roles.extend(element_roles(model, el));
    }
    roles
}

/// The statics roles of the deformations of element `el`, in mode order.
pub fn element_roles(model: &Model, el: usize) -> Vec<Role> {
    let entry = &model.elements[el];
    let s = entry.element.stiffness();
    (0..entry.element.ne())
        .map(|m| {
            let i = entry.ie + m;
            match model.partition.e[i] {
                DefKind::Input => Role::Input,
                _ if model.explicit_rigid[i] => Role::Rigid,
                DefKind::Free => Role::Flexible,
                DefKind::Fixed if s[(m, m)] > 0.0 => Role::Flexible,
                DefKind::Fixed => Role::Rigid,
            }
        })
        .collect()
}

/// Converged state at one load step.
#[derive(Clone, Debug)]
pub struct StepResult {
    /// Load factor t (0 … 1).
    pub load_factor: f64,
    /// Nodal coordinates x.
    pub x: Vec<f64>,
    /// Deformations e.
    pub e: Vec<f64>,
    /// Stress resultants σ (flexible: S e; rigid and input: the multipliers).
    pub sigma: Vec<f64>,
    /// Generalised reaction forces at the fixed and input coordinates (zero elsewhere), nx.
    pub reactions: Vec<f64>,
    /// Elastic energy ½ Σ eᵀ S e [J].
    pub energy: f64,
    /// Newton iterations used to reach this step (all sub-steps).
    pub iterations: usize,
    /// Sub-steps used (1 unless halved).
    pub substeps: usize,
    /// Final residual ‖r‖∞ [N].
    pub residual: f64,
    /// Lagrange multipliers μ (constrained deformations, then Euler normalisations).
    pub multipliers: Vec<f64>,
    /// The smallest eigenvalues κ₁ ≤ κ₂ ≤ … of the tangent stiffness on the constraints
    /// (translations in m, rotations in rad; negative: an unstable direction), at most
    /// [`TANGENT_EIGENVALUES`] of them; `None` where not computed (a model with more than
    /// [`TANGENT_EIGEN_MAX`] reduced coordinates, a state of a time simulation).
    pub tangent_eigenvalues: Option<Vec<f64>>,
}

/// All load steps, the unloaded state first.
#[derive(Clone, Debug)]
pub struct StaticSolution {
    /// Roles of the deformations.
    pub roles: Vec<Role>,
    /// Steps 0 … n.
    pub steps: Vec<StepResult>,
    /// With arc length ([`PathMethod::ArcLength`]): the path parameter and stability of every
    /// step (same order), and the limit points and bifurcations passed; empty with load steps.
    pub path: Vec<PathPoint>,
    /// Limit points and bifurcations along an arc-length path, in path order.
    pub events: Vec<PathEvent>,
}

/// What arc-length path following knows of a step.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PathPoint {
    /// Path parameter: the arc length from the unloaded state, in the dimensionless norm of
    /// the constraint (translations relative to the model size, rotations in radians/2).
    pub arc_length: f64,
    /// Number of negative eigenvalues of the tangent stiffness on the constraints (0: stable),
    /// from the inertia of its factorisation; `None` when it was factored otherwise (applied
    /// moments make it unsymmetric).
    pub unstable_directions: Option<usize>,
    /// The requested output level k of this state, whose load factor is exactly k/steps (the
    /// unloaded state, the full load, and every crossing of a level between); `None` for the
    /// other points of the path.
    pub level: Option<usize>,
}

/// A critical point passed along an arc-length path.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PathEvent {
    /// The load factor turns back: a maximum or minimum of the load along the path, at or
    /// next to step `step`.
    LimitPoint {
        /// The step where the load factor is extreme.
        step: usize,
        /// Its load factor.
        load_factor: f64,
        /// Whether step `step` is the located critical state (the tangent singular there, to
        /// the tolerance of `critical.rs`), not the sampled step nearest to it.
        located: bool,
    },
    /// The number of unstable directions changes while the load factor goes on: a branch of
    /// other equilibria crosses the path there.
    Bifurcation {
        /// The located critical state, or (not `located`) the first step after the
        /// bifurcation.
        step: usize,
        /// Its load factor.
        load_factor: f64,
        /// Unstable directions before and after.
        unstable: [usize; 2],
        /// Whether step `step` is the located critical state (see `LimitPoint`).
        located: bool,
    },
    /// Load steps only: the converged displacement increment of step `step` is `growth` times
    /// that of the step before (and at least 1e-3 of the model size): the path has probably
    /// jumped across a snap-through (a limit point) between the two converged states, which
    /// load steps cannot tell from a smooth path.
    Jump {
        /// The step that jumped.
        step: usize,
        /// The load factor before it.
        from: f64,
        /// Its load factor.
        load_factor: f64,
        /// Its largest coordinate increment divided by that of the step before.
        growth: f64,
    },
}

/// Why a static solution failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// Newton did not converge even with the smallest step.
    #[error("no equilibrium found at load factor {load_factor:.6} (step {step}): after {halvings} step halvings Newton still fails ({reason}); the last converged load factor is {last_converged:.6}. Try more load steps, check for buckling or a snap-through near this load, or for an under-constrained model (a mechanism has no static equilibrium under load)")]
    NoConvergence {
        /// Load step being solved.
        step: usize,
        /// Load factor attempted.
        load_factor: f64,
        /// Last converged load factor.
        last_converged: f64,
        /// Halvings done.
        halvings: usize,
        /// What went wrong in the last attempt.
        reason: String,
    },
    /// A converged state holds numbers that are not finite (coordinates, deformations, stress
    /// resultants, reactions or energy): the arithmetic overflowed double precision.
    #[error("the state at load factor {load_factor:.6} (step {step}) is not finite ({what} contain NaN or infinity): the coordinates or forces overflow double precision (are node positions or loads beyond about 1e150?); {}", last_good_text(*last_good))]
    NonFinite {
        /// Load step.
        step: usize,
        /// Load factor of the state.
        load_factor: f64,
        /// The quantities that are not finite.
        what: String,
        /// The last load factor whose state is finite, if any.
        last_good: Option<f64>,
    },
    /// An element was pushed through itself (zero length or reversed chord) along the path:
    /// the converged state would be a wrong, inverted equilibrium.
    #[error("element `{element}` inverted at load factor {load_factor:.6} (step {step}): its chord passed through zero length or turned against its own axis, so this state is not a valid equilibrium of the structure (often a compressed member far beyond buckling); the last valid load factor is {last_converged:.6}. Try more load steps, a smaller load, or prescribe the displacement instead of the force (displacement control)")]
    Inverted {
        /// Load step.
        step: usize,
        /// Load factor attempted.
        load_factor: f64,
        /// Last load factor with a valid state.
        last_converged: f64,
        /// Element name.
        element: String,
    },
    /// The model has nothing to solve for.
    #[error("the model has no free coordinate: nothing to solve")]
    NothingToSolve,
    /// An arc-length path that does not reach the full load within its step budget.
    #[error("the arc-length path did not reach load factor 1 in {steps} steps (it reached {load_factor:.6}, the largest load factor on the path is {largest:.6}): the load may lie beyond every equilibrium of the structure, or the steps are too short; try fewer, longer steps or a smaller load")]
    PathTooLong {
        /// Steps taken.
        steps: usize,
        /// Load factor reached.
        load_factor: f64,
        /// The largest load factor along the path.
        largest: f64,
    },
    /// A prescribed value that arc length cannot drive.
    #[error("{0}")]
    NotForArcLength(String),
    /// The options are out of range.
    #[error("{what} must be between {min} and {max}, found {found}")]
    BadOption {
        /// Which option (`steps`, `max_iterations`, …).
        what: &'static str,
        /// The smallest value allowed.
        min: usize,
        /// The largest value allowed.
        max: usize,
        /// The value given.
        found: usize,
    },
}

fn last_good_text(last: Option<f64>) -> String {
    match last {
        Some(t) => format!("the last finite state is at load factor {t:.6}"),
        None => "no state of the path is finite".into(),
    }
}

/// The quantities of a step result that hold a non-finite number (empty: all finite).
pub fn non_finite_parts(st: &StepResult) -> Vec<&'static str> {
    let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
    let mut out = Vec::new();
    if bad(&st.x) {
        out.push("coordinates");
    }
    if bad(&st.e) {
        out.push("deformations");
    }
    if bad(&st.sigma) {
        out.push("stress resultants");
    }
    if bad(&st.reactions) {
        out.push("reactions");
    }
    if bad(&st.multipliers) {
        out.push("multipliers");
    }
    if !st.energy.is_finite() || !st.residual.is_finite() {
        out.push("energy");
    }
    out
}

/// The first element (name) that is inverted at `x`, having been valid at `prev`.
pub(crate) fn inverted_element(model: &Model, x: &[f64], prev: &[f64]) -> Option<String> {
    let (mut xs, mut ps) = ([0.0; SMALL], [0.0; SMALL]);
    let (mut xh, mut ph) = (Vec::new(), Vec::new());
    model.elements.iter().find_map(|entry| {
        let xk = gather_local(entry, x, &mut xs, &mut xh);
        let pk = gather_local(entry, prev, &mut ps, &mut ph);
        entry.element.inverted(xk, pk).then(|| entry.name.clone())
    })
}

/// The most load steps [`solve`] takes (every step is kept in memory).
pub const MAX_STEPS: usize = 1_000_000;

/// The most Newton iterations per step [`solve`] takes.
pub const MAX_ITERATIONS: usize = 1_000_000;

mod reduced;
mod reduction;
mod refined;
mod setup;
mod tangent;
pub(crate) use reduced::*;
use reduction::*;
pub(crate) use setup::*;
pub(crate) use tangent::*;

pub mod linear;
mod newton;
mod path;

/// The sparse Newton matrix of statics (`newton.rs`), also for other analyses of the crate.
pub(crate) use newton::KktSolver;
use newton::{exact_equilibrium, newton, Newton};

pub use path::{solve, solve_path, StaticAnalysis, Stopped};

mod arc;
mod critical;
mod eigen;
mod levels;
#[cfg(test)]
pub(crate) mod test_models;
pub use eigen::{TANGENT_EIGENVALUES, TANGENT_EIGEN_MAX};
#[cfg(test)]
pub(crate) use path::last_step;
