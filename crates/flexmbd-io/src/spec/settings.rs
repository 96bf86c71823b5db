//! The analysis settings a model file gives, as the readers return them ([`ModelFile`]), and
//! the checks of `[simulate]` (docs/simulation.md) and `[[velocity]]`.

use super::{SimulateSpec, StartSpec, StepSpec, VelocityEntry};
use flexmbd_core::simulation::{Excitation, InitialVelocity, SimOptions, Start};
use flexmbd_core::Model;

/// Analysis settings read from the model file (`[static]`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// Load steps.
    pub steps: Option<usize>,
    /// Newton iterations per step.
    pub max_iterations: Option<usize>,
    /// Relative residual tolerance.
    pub tol_force: Option<f64>,
    /// Relative increment tolerance.
    pub tol_disp: Option<f64>,
    /// Nodes whose compliance is reported at every step.
    pub compliance: Vec<String>,
    /// Number of buckling multipliers reported at every step.
    pub buckling: usize,
    /// Backtracking line search in Newton.
    pub line_search: bool,
    /// The smallest eigenvalues of the tangent at every step of load steps and strokes (always
    /// with arc length).
    pub tangent_eigenvalues: bool,
    /// How the path is followed (`path = "load-steps"` or `"arc-length"`).
    pub path: flexmbd_core::statics::PathMethod,
}

/// A model file: the model and its analysis settings.
#[derive(Clone, Debug)]
pub struct ModelFile {
    /// The compiled model.
    pub model: Model,
    /// Settings from `[static]`.
    pub settings: Settings,
    /// Settings from `[simulate]`, the histories and `[[velocity]]`.
    pub simulate: SimulateSettings,
    /// The intended freedom (`[[freedom]]`) of the kinematic check.
    pub freedom: Vec<flexmbd_core::kinematics::freedom::IntendedFreedom>,
}

/// The simulation settings of a model file: options the file sets (the rest default or come
/// from the command line) and the excitation.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimulateSettings {
    /// End time [s].
    pub t_end: Option<f64>,
    /// Step size [s].
    pub dt: Option<f64>,
    /// Fixed steps (`step = "fixed"`) instead of step control.
    pub fixed_step: Option<bool>,
    /// Smallest step [s].
    pub dt_min: Option<f64>,
    /// Largest step [s].
    pub dt_max: Option<f64>,
    /// ρ∞.
    pub rho_inf: Option<f64>,
    /// Absolute and relative tolerance (SPACAR's `ERROR abs rel`).
    pub tolerance: Option<[f64; 2]>,
    /// Output interval [s].
    pub output_step: Option<f64>,
    /// Newton iterations per step.
    pub max_iterations: Option<usize>,
    /// Rayleigh α, β.
    pub rayleigh: Option<[f64; 2]>,
    /// Initial state.
    pub start: Option<Start>,
    /// Load steps of the static start.
    pub static_steps: Option<usize>,
    /// Histories and initial velocities.
    pub excitation: Excitation,
}

impl SimulateSettings {
    /// The integrator options: these settings over the defaults of [`SimOptions::new`] for the
    /// end time `t_end` (the file's when `None`). `None` when neither gives an end time.
    pub fn options(&self, t_end: Option<f64>) -> Option<SimOptions> {
        let t_end = t_end.or(self.t_end)?;
        let mut o = SimOptions::new(t_end);
        if let Some(v) = self.dt {
            o.dt = v;
        }
        if let Some(v) = self.fixed_step {
            o.adaptive = !v;
        }
        o.dt_max = self.dt_max.unwrap_or(o.dt_max).max(o.dt);
        o.dt_min = self.dt_min.unwrap_or(o.dt_min).min(o.dt);
        if let Some(v) = self.rho_inf {
            o.rho_inf = v;
        }
        if let Some([a, r]) = self.tolerance {
            o.atol = a;
            o.rtol = r;
        }
        if let Some(v) = self.output_step {
            o.output_step = v;
        }
        if let Some(v) = self.max_iterations {
            o.max_iterations = v;
        }
        if let Some(v) = self.rayleigh {
            o.rayleigh = v;
        }
        if let Some(v) = self.start {
            o.start = v;
        }
        if let Some(v) = self.static_steps {
            o.static_steps = v;
        }
        Some(o)
    }
}

/// Check and convert `[simulate]`; `Err` is the message (the caller adds file and line).
pub(super) fn simulate_settings(spec: &SimulateSpec) -> Result<SimulateSettings, String> {
    let positive = |what: &str, v: Option<f64>| -> Result<Option<f64>, String> {
        match v {
            Some(v) if !(v.is_finite() && v > 0.0) => Err(format!(
                "[simulate]: `{what}` must be a positive number, found {v}"
            )),
            v => Ok(v),
        }
    };
    let fixed_step = spec.step.map(|s| s == StepSpec::Fixed);
    let start = spec.start.map(|s| match s {
        StartSpec::Reference => Start::Reference,
        StartSpec::Static => Start::Static,
    });
    if let Some(r) = spec.rho_inf {
        if !(0.0..=1.0).contains(&r) {
            return Err(format!(
                "[simulate]: `rho_inf` must lie in [0, 1], found {r}"
            ));
        }
    }
    if let Some([a, r]) = spec.tolerance {
        if !(a.is_finite() && a > 0.0 && r.is_finite() && r >= 0.0) {
            return Err(format!(
                "[simulate]: `tolerance = [abs, rel]` needs abs > 0 and rel >= 0, found [{a}, {r}]"
            ));
        }
    }
    if let Some([a, b]) = spec.rayleigh {
        if !(a.is_finite() && a >= 0.0 && b.is_finite() && b >= 0.0) {
            return Err(format!(
                "[simulate]: `rayleigh = [alpha, beta]` must be finite and >= 0, found [{a}, {b}]"
            ));
        }
    }
    for (what, v) in [
        ("max_iterations", spec.max_iterations),
        ("static_steps", spec.static_steps),
    ] {
        if let Some(v) = v {
            if v == 0 || v > crate::limits::MAX_STEPS {
                return Err(format!(
                    "[simulate]: `{what}` must be from 1 to {}, found {v}",
                    crate::limits::MAX_STEPS
                ));
            }
        }
    }
    let gravity = spec.gravity_history.clone().unwrap_or_default();
    gravity
        .validate()
        .map_err(|e| format!("[simulate]: `gravity_history`: {e}"))?;
    Ok(SimulateSettings {
        t_end: positive("t_end", spec.t_end)?,
        dt: positive("dt", spec.dt)?,
        fixed_step,
        dt_min: positive("dt_min", spec.dt_min)?,
        dt_max: positive("dt_max", spec.dt_max)?,
        rho_inf: spec.rho_inf,
        tolerance: spec.tolerance,
        output_step: positive("output_step", spec.output_step)?,
        max_iterations: spec.max_iterations,
        rayleigh: spec.rayleigh,
        start,
        static_steps: spec.static_steps,
        excitation: Excitation {
            gravity,
            ..Default::default()
        },
    })
}

/// An initial velocity of a node that exists (`node` its id).
pub(super) fn velocity(spec: &VelocityEntry, node: usize) -> Result<InitialVelocity, String> {
    if !spec.v.iter().chain(&spec.omega).all(|v| v.is_finite()) {
        return Err(format!(
            "[[velocity]] at node `{}`: the values must be finite numbers",
            spec.node
        ));
    }
    Ok(InitialVelocity {
        node,
        velocity: spec.v,
        angular: spec.omega,
    })
}
