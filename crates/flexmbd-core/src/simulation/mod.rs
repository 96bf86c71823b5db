//! Nonlinear time simulation of the equations of motion (paper eq. (5), in the coordinates x
//! with Lagrange multipliers; theory.md §9, §14):
//!
//! ```text
//! M(x) ẍ + h(x, ẋ) + Dᵀσ + C ẋ = f(t, x)      (free coordinates)
//! e_k(x) = target_k(t),  λᵀλ − 1 = 0           (rigid and input deformations, normalisations)
//! ```
//!
//! with the mass model of the elements ([`crate::elements::ElementKind::mass`] and
//! [`crate::elements::ElementKind::velocity_forces`]), σ = S e on the flexible deformations and
//! multipliers on the constrained ones (exactly as in statics), Rayleigh damping C = α M + β K_m
//! (K_m = Dᵀ S D, the material stiffness), dead nodal loads and moments and gravity on the
//! current configuration, each scaled by its [`TimeFunction`]; prescribed coordinates and input
//! deformations follow their time functions.
//!
//! Integrator: generalised-α in the form of Arnold & Brüls (2007) for the index-3 system
//! (equilibrium and constraints at t_{n+1}, the auxiliary acceleration a):
//!
//! ```text
//! (1 − α_m) a_{n+1} + α_m a_n = (1 − α_f) ẍ_{n+1} + α_f ẍ_n
//! x_{n+1} = x_n + h ẋ_n + h² (½ − β) a_n + h² β a_{n+1}
//! ẋ_{n+1} = ẋ_n + h (1 − γ) a_n + h γ a_{n+1}
//! α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ + α_f − α_m, β = ¼ (γ + ½)²
//! ```
//!
//! (ρ∞ = 1: the trapezoidal rule). Newton with the iteration matrix
//! [β′ M + γ′ C + K, Gᵀ; G, 0], β′ = (1 − α_m)/(β h² (1 − α_f)), γ′ = γ/(β h), where K is the
//! tangent of statics and the modes (material + geometric + load stiffness), scaled by 1/β′ for
//! conditioning. The constraints hold at every step (no drift); the largest residual is
//! reported. Step control: the local error estimate h² |β − 1/6| ‖ẍ_{n+1} − ẍ_n‖ in the norm of
//! the absolute and relative tolerances, step rejection, halving when Newton fails, landing on
//! output times and on the kinks of the time functions.

pub mod excitation;
mod integrator;

pub use excitation::{TimeFunction, TimeFunctionError};

use crate::elements::NodeId;
use crate::model::Model;
use crate::statics::{Role, SolveError, StepResult};

/// An initial velocity of a node (global axes).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct InitialVelocity {
    /// The node.
    pub node: NodeId,
    /// Velocity of its position [m/s].
    pub velocity: [f64; 3],
    /// Angular velocity of its orientation [rad/s] (rotational nodes).
    pub angular: [f64; 3],
}

/// The time dependence of a model's loads and inputs, and its initial velocities.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Excitation {
    /// φ of each nodal load (`model.loads.nodal`, same order); missing entries are
    /// [`TimeFunction::Constant`].
    pub loads: Vec<TimeFunction>,
    /// φ of each prescribed input (`model.loads.prescribed`, same order); missing entries are
    /// [`TimeFunction::Constant`].
    pub prescribed: Vec<TimeFunction>,
    /// φ of gravity.
    pub gravity: TimeFunction,
    /// Initial velocities; nodes not listed start at rest (or with the rates of their
    /// prescribed inputs). Made consistent with the constraints.
    pub velocities: Vec<InitialVelocity>,
}

/// Where the motion starts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum Start {
    /// The reference configuration, at rest apart from the given initial velocities (a
    /// mechanism released from its drawn position); every prescribed input must be zero at
    /// t = 0.
    #[default]
    Reference,
    /// The static equilibrium under the loads and inputs at t = 0 (a pre-load, released by
    /// the histories), found by nonlinear statics first.
    Static,
}

/// How the velocities at t = 0 are completed from the given ones (paper eq. (5) needs
/// velocities that meet the constraints: the rigid deformations stay rigid, the inputs move at
/// their rates).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub enum StartVelocity {
    /// The given node velocities are kept; every other coordinate takes the velocity with the
    /// least rate of elastic deformation, ė_mᵀ S ė_m with the elements' stiffness S (zero
    /// where the inputs allow it: a driven mechanism starts moving as the rigid-body motion of
    /// its inputs, a driven flexure with its quasi-static velocity field). Directions that
    /// deform nothing (free rigid-body motion) start at rest, in the sense of the least kinetic
    /// energy.
    #[default]
    LeastDeformation,
    /// The velocity closest to the given one (zero where none is given) in the plain Euclidean
    /// norm of x, projected onto the constraints.
    Projected,
}

/// Integrator settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SimOptions {
    /// End time [s].
    pub t_end: f64,
    /// Step size [s]: the fixed step, or the first step with step control.
    pub dt: f64,
    /// Step control by the local error estimate (else fixed steps, halved only when Newton
    /// fails).
    pub adaptive: bool,
    /// Smallest step [s]; below it the run stops.
    pub dt_min: f64,
    /// Largest step [s].
    pub dt_max: f64,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1].
    pub rho_inf: f64,
    /// Absolute tolerance of the local error [units of x: m, and Euler parameters].
    pub atol: f64,
    /// Relative tolerance of the local error.
    pub rtol: f64,
    /// Output interval [s]: results at k · output_step and at t_end.
    pub output_step: f64,
    /// Newton iterations per step before the step is halved.
    pub max_iterations: usize,
    /// Rayleigh damping C = α M + β K_m: [α (1/s), β (s)].
    pub rayleigh: [f64; 2],
    /// The initial state.
    pub start: Start,
    /// How the initial velocities are completed.
    pub start_velocity: StartVelocity,
    /// Load steps of the static start.
    pub static_steps: usize,
    /// Largest number of steps (accepted and rejected) before the run stops.
    pub max_steps: usize,
}

impl SimOptions {
    /// Defaults for a run to `t_end`: 1000 first steps, step control with the tolerances
    /// 1e-6 · model size (absolute) and 1e-4 (relative), 100 output intervals, ρ∞ = 0.9.
    pub fn new(t_end: f64) -> Self {
        Self {
            t_end,
            dt: t_end / 1000.0,
            adaptive: true,
            dt_min: t_end * 1e-12,
            dt_max: t_end,
            rho_inf: 0.9,
            atol: 1e-6,
            rtol: 1e-4,
            output_step: t_end / 100.0,
            max_iterations: 12,
            rayleigh: [0.0, 0.0],
            start: Start::Reference,
            start_velocity: StartVelocity::LeastDeformation,
            static_steps: 10,
            max_steps: 10_000_000,
        }
    }
}

/// Energies at an output time [J].
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Energies {
    /// Kinetic energy ½ ẋᵀ M ẋ.
    pub kinetic: f64,
    /// Strain energy ½ Σ eᵀ S e.
    pub strain: f64,
    /// Work of the external loads (nodal loads, moments, gravity) since t = 0 (trapezoidal rule
    /// on the power over the steps).
    pub external_work: f64,
    /// Work of the prescribed motions (support and actuator forces) since t = 0.
    pub prescribed_work: f64,
    /// Energy dissipated by damping since t = 0.
    pub dissipated: f64,
    /// Balance error: (T + U) − (T₀ + U₀) − W_ext − W_prescribed + W_dissipated.
    pub balance_error: f64,
}

/// The state at an output time.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Time [s].
    pub t: f64,
    /// Nodal coordinates x.
    pub x: Vec<f64>,
    /// Rates ẋ.
    pub v: Vec<f64>,
    /// Accelerations ẍ.
    pub a: Vec<f64>,
    /// Deformations e.
    pub e: Vec<f64>,
    /// Stress resultants σ (flexible: S e; rigid and input: the multipliers).
    pub sigma: Vec<f64>,
    /// Generalised support and actuator forces on the fixed and prescribed coordinates (zero
    /// elsewhere), nx: the force the supports exert to hold them, inertia included.
    pub reactions: Vec<f64>,
    /// Lagrange multipliers (constrained deformations, then Euler normalisations).
    pub multipliers: Vec<f64>,
    /// Energies.
    pub energy: Energies,
}

impl Frame {
    /// Velocity [m/s] and, for rotational nodes, angular velocity ω = 2 Λ̄ λ̇ [rad/s] (global
    /// axes) of every node.
    pub fn node_velocities(&self, model: &Model) -> Vec<([f64; 3], Option<[f64; 3]>)> {
        model
            .nodes
            .iter()
            .map(|n| {
                let p = n.ix_pos;
                let v = [self.v[p], self.v[p + 1], self.v[p + 2]];
                let w = n.ix_rot.map(|r| {
                    let lb = crate::math::lambda_bar(&[
                        self.x[r],
                        self.x[r + 1],
                        self.x[r + 2],
                        self.x[r + 3],
                    ]);
                    std::array::from_fn(|k| {
                        2.0 * (0..4).map(|c| lb[k][c] * self.v[r + c]).sum::<f64>()
                    })
                });
                (v, w)
            })
            .collect()
    }
    /// The frame as a static step result (load factor = time), for the result tables that
    /// statics and simulation share ([`crate::results`]).
    pub fn as_step(&self) -> StepResult {
        StepResult {
            load_factor: self.t,
            x: self.x.clone(),
            e: self.e.clone(),
            sigma: self.sigma.clone(),
            reactions: self.reactions.clone(),
            energy: self.energy.strain,
            iterations: 0,
            substeps: 1,
            residual: 0.0,
            multipliers: self.multipliers.clone(),
            tangent_eigenvalues: None,
        }
    }
}

/// Counts of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct SimStats {
    /// Accepted steps.
    pub steps: usize,
    /// Steps rejected by the error estimate.
    pub rejected: usize,
    /// Steps whose Newton iteration failed (then halved).
    pub newton_failures: usize,
    /// Newton iterations in all.
    pub newton_iterations: usize,
    /// Iteration matrices built and factorised (modified Newton reuses them).
    pub matrix_updates: usize,
    /// Smallest and largest accepted step [s].
    pub min_step: f64,
    /// Largest accepted step [s].
    pub max_step: f64,
    /// Largest constraint residual max |g| over the accepted steps (deformation units).
    pub max_constraint_residual: f64,
    /// Largest |energy balance error| over the output times [J].
    pub max_energy_error: f64,
}

/// A simulation: the output frames and the counts.
#[derive(Clone, Debug, PartialEq)]
pub struct Simulation {
    /// Roles of the deformations (as statics).
    pub roles: Vec<Role>,
    /// The states at the output times, t = 0 first.
    pub frames: Vec<Frame>,
    /// Counts.
    pub stats: SimStats,
}

/// Progress of a run, for a progress display.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Simulated time [s].
    pub t: f64,
    /// End time [s].
    pub t_end: f64,
    /// Accepted steps.
    pub steps: usize,
}

/// Why a simulation could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    /// An option or the excitation is not valid.
    #[error("{0}")]
    Invalid(String),
    /// The model holds something the integrator does not handle.
    #[error("{0}")]
    Unsupported(String),
    /// The static start failed.
    #[error("the static equilibrium at t = 0 (the start of the simulation) was not found: {0}")]
    Start(SolveError),
    /// The initial accelerations could not be found.
    #[error("no consistent initial accelerations: {0}")]
    Initial(String),
}

/// A run that stopped before the end time: what happened, and every result up to then.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the simulation stopped at t = {t:.6e} s: {reason}; {hint}")]
pub struct Stopped {
    /// Time of the last accepted state [s].
    pub t: f64,
    /// What went wrong.
    pub reason: String,
    /// What to try.
    pub hint: String,
    /// The frames up to t (the last accepted state is the last frame).
    pub partial: Box<Simulation>,
}

/// The outcome of [`simulate`] that is not a complete run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimFailure {
    /// Nothing was simulated.
    #[error(transparent)]
    NotStarted(#[from] SimError),
    /// Simulated up to a time, then stopped.
    #[error(transparent)]
    Stopped(#[from] Stopped),
}

/// Simulate the model from t = 0 to `options.t_end`; `progress` is called after every
/// accepted step.
pub fn simulate(
    model: &Model,
    excitation: &Excitation,
    options: &SimOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Simulation, SimFailure> {
    integrator::run(model, excitation, options, progress)
}
