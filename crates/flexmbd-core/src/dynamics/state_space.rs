//! Linear state-space model about a static equilibrium (theory.md §13.5, issue 6 item 5).
//!
//! Modal form with mass-normalised modes Φ (Φᵀ M0 Φ = I, Φᵀ K0 Φ = Ω²) of the minimal
//! coordinates, δq = Φ η, state z = (η, η̇):
//!
//! ```text
//! ż = A z + B u,   y = C z + D u
//! A = [[0, I], [−Ω², −2ζΩ]],   B = [[0], [Φᵀ Bq]]
//! displacement:  C = [Cx Φ, 0]               D = Cx F Bq
//! velocity:      C = [0, Cx Φ]               D = 0
//! acceleration:  C = [−Cx Φ Ω², −Cx Φ 2ζΩ]   D = Cx Φ Φᵀ Bq
//! ```
//!
//! - Inputs u: a force on a node along a global axis, f_x = e_i on the node's position, or a
//!   moment about a global axis, f_λ = 2 Λ̄ᵀ e_k on its Euler parameters (the dual of
//!   ω = 2 Λ̄ λ̇, as in `statics::linear::compliance`); Bq = Zᵀ f_x.
//! - Outputs y: a translation of a node along a global axis (the row e_iᵀ Z) or its rotation
//!   about a global axis (2 Λ̄ δλ: the row 2 (Λ̄ Z)_k), as displacement, velocity or acceleration.
//!   The acceleration follows from ÿ = Cx Φ η̈ with η̈ = −Ω² η − 2ζΩ η̇ + Φᵀ Bq u.
//! - Damping: modal, ratio ζ for every mode (SPACAR Light's choice). For an unstable mode
//!   (ω² < 0) the damping term uses √|ω²|.
//! - F: static flexibility not carried by the kept modes, so that displacement outputs have the
//!   correct static gain. Always the massless part Q₀ K₀₀⁻¹ Q₀ᵀ (directions without inertia are
//!   condensed statically and respond to a force on them instantaneously, see [`Reduced`]);
//!   with `static_correction` also the residual flexibility of the dropped modes,
//!   Σ_dropped φ_k φ_kᵀ / ω_k². Then the DC gain −C A⁻¹ B + D of a displacement output is
//!   Cx K0⁻¹ Bq, the static compliance, because K0⁻¹ = Φ Ω⁻² Φᵀ + Q₀ K₀₀⁻¹ Q₀ᵀ (block
//!   inverse with the Schur complement K_c). Velocity and acceleration outputs cannot contain
//!   the instantaneous massless response (it would need u̇, ü): where it is non-zero the
//!   model warns.
//!
//! Prescribed-motion inputs (base excitation, enforced motion): a held coordinate m (support,
//! `[inputs]` or `[[prescribe]]`) moves by u_m(t): a translation along a global axis, or a
//! small rotation about a global axis of a node whose rotation component is held (a rotary
//! actuator). With t_m its unit direction in x — e_i for a translation, the Euler-parameter
//! rate of a unit rotation δλ = ½ Λ̄ᵀ e_k (so that ω = 2 Λ̄ δλ = e_k) for a rotation — lifted
//! onto the rigid constraints (G t_m = 0 through free coordinates), δx = Z δq + t_m u_m and
//!
//! ```text
//! M0 q̈ + K0 q = −(Zᵀ K t_m) u_m − (Zᵀ M t_m) ü_m
//! q = ψ u_m + r,   ψ = −K0⁻¹ Zᵀ K t_m   (quasi-static response to a unit enforced motion)
//! M0 r̈ + K0 r = −(M0 ψ + Zᵀ M t_m) ü_m
//! ```
//!
//! so r is driven like a force input with Bq = −(M0 ψ + Zᵀ M t_m), and the input is the
//! acceleration ü_m. Each motion input adds the states (u_m, u̇_m), a double integrator
//! (A block [[0, 1], [0, 0]], B entry 1 on u̇_m). An output row w gives the absolute motion
//! δy = Cx r + g u_m with g = Cx ψ + w·t_m: g enters C on u_m (displacement), on u̇_m
//! (velocity) or D (acceleration). K0 is solved directly (dense LU), so massless directions
//! are part of ψ exactly. A rotation output of the moved node about the moved axis has
//! w·t_m = 2 e_kᵀ Λ̄ ½ Λ̄ᵀ e_k = 1: the outputs stay absolute.
//!
//! A held deformation (an `input` mode: an actuator's elongation, a driven hinge's angle) is
//! driven the same way, with t_m the least-squares solution of G t_m = e_row through the free
//! coordinates: the unit change of the driven deformation and none of the other rigid or
//! prescribed ones ([`Motion::Deformation`]).

use super::{reduced_matrices_with, velocity_dof, EigenSolver, ModalError, Reduced};
use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{CoordKind, Dof, Model};
use crate::statics::linear::linearize;
use crate::statics::StepResult;
use faer::{c64, Mat};

/// A force (translational direction) or moment (rotational direction) input on a node, in
/// global axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Input {
    /// Node index.
    pub node: usize,
    /// x, y, z: force along the axis [N]; rx, ry, rz: moment about it [N·m].
    pub dof: Dof,
}

/// What an output measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputKind {
    /// Displacement [m] or rotation [rad].
    Disp,
    /// Velocity [m/s] or angular velocity [rad/s].
    Vel,
    /// Acceleration [m/s²] or angular acceleration [rad/s²].
    Acc,
}

impl OutputKind {
    /// Name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            OutputKind::Disp => "disp",
            OutputKind::Vel => "vel",
            OutputKind::Acc => "acc",
        }
    }
    /// Parse a command-line name.
    pub fn parse(s: &str) -> Option<OutputKind> {
        [OutputKind::Disp, OutputKind::Vel, OutputKind::Acc]
            .into_iter()
            .find(|k| k.name() == s)
    }
    /// Power of s in the transfer function (0, 1, 2).
    fn order(self) -> i32 {
        match self {
            OutputKind::Disp => 0,
            OutputKind::Vel => 1,
            OutputKind::Acc => 2,
        }
    }
}

/// What an output measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Probe {
    /// The motion of a node along (translations) or about (rotations) a global axis.
    Node {
        /// Node index.
        node: usize,
        /// Direction.
        dof: Dof,
    },
    /// A deformation of an element, δe (a strain-gauge or an encoder on a hinge).
    Deformation {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
    /// The reaction at a held node coordinate (a support or prescribed input): the force
    /// along, or the moment about, a global axis that the support exerts, as `flexmbd static`
    /// reports reactions.
    Reaction {
        /// Node index.
        node: usize,
        /// Direction.
        dof: Dof,
    },
    /// The stress resultant of a flexible deformation, δσ = S δe (the element's force:
    /// the axial force of a truss or beam, σ2..σ6 ≈ torque and bending moments / l0, a hinge
    /// torque).
    Force {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
}

/// An output: a probe and whether its value, rate or second rate is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Output {
    /// What is measured.
    pub probe: Probe,
    /// Value (displacement, deformation, force), its velocity or its acceleration.
    pub kind: OutputKind,
}

/// A prescribed-motion (enforced-motion) input, whose input signal is the acceleration:
/// - of a held translational coordinate of a node along a global axis [m/s²], or of a held
///   rotation component about a global axis [rad/s²] (a support, `[inputs]` or
///   `[[prescribe]]` coordinate);
/// - of a held deformation of an element (an `input` mode or a rigid mode, e.g. a linear
///   actuator's elongation or a driven hinge's angle): ë [m/s²] for truss and beam modes
///   (lengths), [rad/s²] for hinge modes (angles).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// A held nodal coordinate.
    Node {
        /// Node index.
        node: usize,
        /// x, y, z (translation) or rx, ry, rz (rotation).
        dof: Dof,
    },
    /// A held deformation.
    Deformation {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
}

impl Motion {
    /// `motion`.
    pub fn kind_name(&self) -> &'static str {
        "motion"
    }
    /// Name `NODE:DIR:motion`, or `ELEMENT:MODE:motion` with the mode 1-based.
    pub fn name(&self, model: &Model) -> String {
        match *self {
            Motion::Node { node, dof } => {
                format!("{}:{}:motion", model.nodes[node].name, dof.name())
            }
            Motion::Deformation { element, mode } => {
                format!("{}:{}:motion", model.elements[element].name, mode + 1)
            }
        }
    }
    /// SI unit of the input (an acceleration or angular acceleration).
    pub fn unit(&self, model: &Model) -> &'static str {
        let angle = match *self {
            Motion::Node { dof, .. } => dof.is_rotation(),
            Motion::Deformation { element, mode } => {
                model.elements[element].element.mode_is_angle(mode)
            }
        };
        if angle {
            "rad/s²"
        } else {
            "m/s²"
        }
    }
    /// Words, e.g. "enforced acceleration of base along global y".
    pub fn describe(&self, model: &Model) -> String {
        match *self {
            Motion::Node { node, dof } => {
                let what = pick(dof, "acceleration", "angular acceleration");
                format!(
                    "enforced {what} of {} {} (prescribed motion)",
                    model.nodes[node].name,
                    direction(dof)
                )
            }
            Motion::Deformation { element, mode } => {
                let entry = &model.elements[element];
                let what = if self.unit(model) == "rad/s²" {
                    "angular acceleration"
                } else {
                    "acceleration"
                };
                format!(
                    "enforced {what} of deformation {} ({}) of {} `{}` (prescribed deformation)",
                    mode + 1,
                    entry.element.mode_name(mode, &model.node_names()),
                    entry.element.type_name(),
                    entry.name
                )
            }
        }
    }
}

/// Description of one input column (a force/moment or a prescribed motion), for reports.
#[derive(Clone, Debug, PartialEq)]
pub struct InputInfo {
    /// `NODE:DIR:KIND`.
    pub name: String,
    /// Node index (force, moment or nodal motion).
    pub node: Option<usize>,
    /// Direction (force, moment or nodal motion).
    pub dof: Option<Dof>,
    /// Element index and 0-based mode (deformation motion).
    pub deformation: Option<(usize, usize)>,
    /// `force`, `moment` or `motion`.
    pub kind: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// Words.
    pub description: String,
}

impl Input {
    /// `force` or `moment`.
    pub fn kind_name(&self) -> &'static str {
        if self.dof.is_rotation() {
            "moment"
        } else {
            "force"
        }
    }
    /// Name `NODE:DIR:force|moment`.
    pub fn name(&self, model: &Model) -> String {
        format!(
            "{}:{}:{}",
            model.nodes[self.node].name,
            self.dof.name(),
            self.kind_name()
        )
    }
    /// SI unit.
    pub fn unit(&self) -> &'static str {
        if self.dof.is_rotation() {
            "N·m"
        } else {
            "N"
        }
    }
    /// Words, e.g. "force on tip along global y".
    pub fn describe(&self, model: &Model) -> String {
        let axis = axis_name(self.dof);
        let node = &model.nodes[self.node].name;
        if self.dof.is_rotation() {
            format!("moment on {node} about global {axis}")
        } else {
            format!("force on {node} along global {axis}")
        }
    }
}

impl Output {
    /// The motion of a node.
    pub fn node(node: usize, dof: Dof, kind: OutputKind) -> Output {
        Output {
            probe: Probe::Node { node, dof },
            kind,
        }
    }
    /// Whether the output is a constraint reaction: a support reaction, or the force of a rigid
    /// or prescribed deformation (not σ = S e).
    pub fn is_reaction(&self, model: &Model) -> bool {
        match self.probe {
            Probe::Reaction { .. } => true,
            Probe::Force { element, mode } => {
                crate::statics::element_roles(model, element)[mode]
                    != crate::statics::Role::Flexible
            }
            Probe::Node { .. } | Probe::Deformation { .. } => false,
        }
    }
    /// The node and direction of a node output.
    pub fn node_dof(&self) -> Option<(usize, Dof)> {
        match self.probe {
            Probe::Node { node, dof } => Some((node, dof)),
            _ => None,
        }
    }
    /// Name `NODE:DIR:disp|vel|acc`, or `ELEMENT:MODE:def|force` (value) with `:vel` or
    /// `:acc` for its rates.
    pub fn name(&self, model: &Model) -> String {
        match self.probe {
            Probe::Node { node, dof } => format!(
                "{}:{}:{}",
                model.nodes[node].name,
                dof.name(),
                self.kind.name()
            ),
            Probe::Reaction { node, dof } => {
                format!("{}:{}:reaction", model.nodes[node].name, dof.name())
            }
            Probe::Deformation { element, mode } | Probe::Force { element, mode } => {
                let q = if matches!(self.probe, Probe::Force { .. }) {
                    "force"
                } else {
                    "def"
                };
                let rate = match self.kind {
                    OutputKind::Disp => String::new(),
                    k => format!(":{}", k.name()),
                };
                format!("{}:{}:{q}{rate}", model.elements[element].name, mode + 1)
            }
        }
    }
    /// SI unit.
    pub fn unit(&self, model: &Model) -> &'static str {
        let angle =
            |element: usize, mode: usize| model.elements[element].element.mode_is_angle(mode);
        // rows: length, angle, force, torque; columns: value, rate, second rate
        const UNITS: [[&str; 3]; 4] = [
            ["m", "m/s", "m/s²"],
            ["rad", "rad/s", "rad/s²"],
            ["N", "N/s", "N/s²"],
            ["N·m", "N·m/s", "N·m/s²"],
        ];
        let row = match self.probe {
            Probe::Node { dof, .. } => usize::from(dof.is_rotation()),
            Probe::Deformation { element, mode } => usize::from(angle(element, mode)),
            Probe::Force { element, mode } => 2 + usize::from(angle(element, mode)),
            Probe::Reaction { dof, .. } => 2 + usize::from(dof.is_rotation()),
        };
        UNITS[row][self.kind.order() as usize]
    }
    /// Words, e.g. "velocity of tip along global y".
    pub fn describe(&self, model: &Model) -> String {
        match self.probe {
            Probe::Node { node, dof } => {
                let axis = axis_name(dof);
                let node = &model.nodes[node].name;
                let what = match (dof.is_rotation(), self.kind) {
                    (false, OutputKind::Disp) => "displacement",
                    (false, OutputKind::Vel) => "velocity",
                    (false, OutputKind::Acc) => "acceleration",
                    (true, OutputKind::Disp) => "rotation",
                    (true, OutputKind::Vel) => "angular velocity",
                    (true, OutputKind::Acc) => "angular acceleration",
                };
                let prep = if dof.is_rotation() { "about" } else { "along" };
                format!("{what} of {node} {prep} global {axis}")
            }
            Probe::Reaction { node, dof } => {
                let what = pick(dof, "reaction force", "reaction moment");
                format!("{what} at {} {}", model.nodes[node].name, direction(dof))
            }
            Probe::Deformation { element, mode } | Probe::Force { element, mode } => {
                let entry = &model.elements[element];
                let q = if matches!(self.probe, Probe::Force { .. }) {
                    "stress resultant σ"
                } else {
                    "deformation e"
                };
                let rate = match self.kind {
                    OutputKind::Disp => "",
                    OutputKind::Vel => "rate of the ",
                    OutputKind::Acc => "second rate of the ",
                };
                let held = self.is_reaction(model);
                format!(
                    "{rate}{q}{} ({}) of {} `{}`{}",
                    mode + 1,
                    entry.element.mode_name(mode, &model.node_names()),
                    entry.element.type_name(),
                    entry.name,
                    if held {
                        ", the constraint reaction that holds it"
                    } else {
                        ""
                    }
                )
            }
        }
    }
}

fn axis_name(d: Dof) -> &'static str {
    ["x", "y", "z"][d.index() % 3]
}

/// `translation` or `rotation` by the kind of direction.
fn pick(d: Dof, translation: &'static str, rotation: &'static str) -> &'static str {
    if d.is_rotation() {
        rotation
    } else {
        translation
    }
}

/// "along global y" or "about global z".
fn direction(d: Dof) -> String {
    format!("{} global {}", pick(d, "along", "about"), axis_name(d))
}

/// Options of [`state_space`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateSpaceOptions {
    /// Modal damping ratio ζ of every mode (≥ 0).
    pub damping: f64,
    /// Keep the lowest N modes (None: all modes that carry mass).
    pub modes: Option<usize>,
    /// Add the residual static flexibility of the dropped modes to D (displacement outputs),
    /// so that a truncated model keeps the exact static gain.
    pub static_correction: bool,
    /// Eigen solver: `Auto` is dense up to [`DENSE_STATE_SPACE_DOF`] degrees of freedom (all
    /// modes, massless directions condensed exactly, motion inputs) and sparse above it (the
    /// lowest `modes` only, which must then be given).
    pub solver: EigenSolver,
    /// Memory limit of the dense state space in bytes
    /// ([`super::dense_size::dense_bytes`]): above it the dense path stops with
    /// [`ModalError::TooLarge`] before its matrices are allocated. Default
    /// [`crate::linalg::DEFAULT_MAX_DENSE_BYTES`].
    pub max_dense_bytes: u64,
}

/// [`EigenSolver::Auto`] builds the state space densely up to this many degrees of freedom.
pub const DENSE_STATE_SPACE_DOF: usize = super::DENSE_FALLBACK_DOF;

impl Default for StateSpaceOptions {
    fn default() -> Self {
        StateSpaceOptions {
            damping: 0.01,
            modes: None,
            static_correction: false,
            solver: EigenSolver::Auto,
            max_dense_bytes: crate::linalg::DEFAULT_MAX_DENSE_BYTES,
        }
    }
}

/// Why a state-space model could not be built or evaluated.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateSpaceError {
    /// The modal analysis failed.
    #[error(transparent)]
    Modal(#[from] ModalError),
    /// A moment input or rotation output on a node without rotation coordinates.
    #[error("node `{node}` has no rotation coordinates: a moment or rotation needs a rotational node (give the node rotation coordinates or connect it to a beam)")]
    NoRotation {
        /// Node name.
        node: String,
    },
    /// Damping ratio not finite or negative.
    #[error("the damping ratio must be a finite number >= 0, found {0}")]
    BadDamping(f64),
    /// An input, motion or output names a node, element or mode the model does not have.
    #[error("{0}: the model has no such node, element or mode")]
    UnknownId(String),
    /// `modes = Some(0)`.
    #[error("at least one mode must be kept")]
    NoModes,
    /// No input or no output.
    #[error("the state-space model needs at least one input and one output")]
    NoInputOutput,
    /// A kept mode has ω² ≈ 0: A is singular.
    #[error("a kept mode has zero frequency (a rigid-body motion or mechanism): the static gain is unbounded")]
    Singular,
    /// A motion input on a coordinate that is not held.
    #[error("input {input}: a prescribed-motion input needs a coordinate held by a support, an input or a prescribed value, and this one is free; apply a force input (NODE:DIR:force) instead, or hold the coordinate in the model")]
    MotionNotHeld {
        /// Input name.
        input: String,
    },
    /// A motion that the rigid constraints do not allow.
    #[error("input {input}: the rigid or prescribed deformations do not allow this coordinate or deformation to change on its own (it is tied to other held coordinates or deformations); enforce the motion on one that can move, or make the connecting element flexible")]
    MotionConstrained {
        /// Input name.
        input: String,
    },
    /// The sparse state space needs the number of modes.
    #[error("the model has {ndof} degrees of freedom, too many for the dense state space (at most {limit}); the sparse one keeps the lowest modes only: give the number of modes to keep (e.g. 20), with the static correction for the exact static gain")]
    SparseNeedsModes {
        /// Degrees of freedom.
        ndof: usize,
        /// The dense limit.
        limit: usize,
    },
    /// Prescribed-motion inputs on the sparse path.
    #[error("prescribed-motion inputs ({input}) need the dense state space, which takes models of at most {limit} degrees of freedom (this one has {ndof}); use force or moment inputs, or a smaller model")]
    SparseMotion {
        /// The first motion input.
        input: String,
        /// Degrees of freedom.
        ndof: usize,
        /// The dense limit.
        limit: usize,
    },
    /// A force output on a rigid or prescribed deformation.
    #[error("output {output}: this deformation is rigid or prescribed, so its force is a constraint reaction, which the dense state space gives (models up to 3000 degrees of freedom, with the dense or the automatic solver choice) but the sparse one does not")]
    ForceOfHeldDeformation {
        /// Output name.
        output: String,
    },
    /// A support reaction on the sparse path.
    #[error("output {output}: reactions are given by the dense state space only (models up to 3000 degrees of freedom)")]
    SparseReaction {
        /// Output name.
        output: String,
    },
    /// A reaction at a coordinate that is not held.
    #[error("output {output}: this coordinate is free, so it has no reaction; a reaction needs a coordinate held by a support, an input or a prescribed value")]
    ReactionNotHeld {
        /// Output name.
        output: String,
    },
    /// A reaction output whose deformation cannot change on its own.
    #[error("output {output}: the rigid or prescribed deformations tie this deformation to others, so its reaction cannot be separated from theirs; measure a force of a flexible element next to it")]
    ReactionConstrained {
        /// Output name.
        output: String,
    },
    /// A rate of a reaction output.
    #[error("output {output}: the force of a rigid or prescribed deformation (a constraint reaction) is available as a value only, not as :vel or :acc")]
    ReactionRate {
        /// Output name.
        output: String,
    },
    /// A motion input on a deformation that is not held.
    #[error("input {input}: deformation {mode} ({name}) of {kind} `{element}` is flexible; a prescribed-deformation motion needs a held mode: make it an input mode of the element (with a prescribed value where it is not zero), or apply a force input")]
    DeformationNotHeld {
        /// Input name.
        input: String,
        /// Mode, 1-based.
        mode: usize,
        /// Mode name.
        name: String,
        /// Element type.
        kind: &'static str,
        /// Element name.
        element: String,
    },
    /// A motion input on a rigid body's deformation.
    #[error("input {input}: the deformations of a rigid body cannot be driven; drive a hinge, truss or beam mode or a held node coordinate instead")]
    RigidBodyMotion {
        /// Input name.
        input: String,
    },
    /// The stiffness of the minimal coordinates is singular, so there is no quasi-static
    /// response to an enforced motion.
    #[error("input {input}: the stiffness K0 with the moved coordinate held is singular (a mechanism or a rigid-body motion remains), so the quasi-static response to the enforced motion is undefined; hold the remaining rigid-body motions")]
    MotionSingular {
        /// Input name.
        input: String,
    },
}

/// A state-space model in modal coordinates with named inputs and outputs.
#[derive(Clone, Debug)]
pub struct StateSpace {
    /// A (2n × 2n), state (η₁..ηₙ, η̇₁..η̇ₙ).
    pub a: Mat<f64>,
    /// B (2n × inputs).
    pub b: Mat<f64>,
    /// C (outputs × 2n).
    pub c: Mat<f64>,
    /// D (outputs × inputs).
    pub d: Mat<f64>,
    /// Inputs, in the order of the columns of B and D.
    pub inputs: Vec<Input>,
    /// Prescribed-motion inputs: the columns after those of `inputs` (input = ü [m/s²]);
    /// each adds the states (u, u̇) after the modal ones.
    pub motions: Vec<Motion>,
    /// Outputs, in the order of the rows of C and D.
    pub outputs: Vec<Output>,
    /// ω² [rad²/s²] of the kept modes, ascending (the eigenvalues of `modes`).
    pub eigenvalues: Vec<f64>,
    /// Modal damping ratio ζ.
    pub damping: f64,
    /// Number of minimal coordinates.
    pub ndof: usize,
    /// Number of massless directions condensed out (not states).
    pub massless: usize,
    /// Number of modes that carry mass (the most that can be kept).
    pub available_modes: usize,
    /// Whether D carries the residual flexibility of the dropped modes.
    pub static_correction: bool,
    /// Notes for the user (inputs on held directions, outputs that miss an instantaneous part).
    pub warnings: Vec<String>,
    /// The eigen solver used: `Dense` (all modes) or `Sparse` (the lowest, by Lanczos).
    pub solver: EigenSolver,
    /// Quasi-static gain g = Cx ψ + w·t_m of the value outputs per unit enforced displacement
    /// (outputs × motions).
    motion_gain: Mat<f64>,
}

/// The generalised loads of a unit enforced motion: k = Zᵀ K t_m, m = Zᵀ M t_m, and the lifted
/// direction t_m in x.
struct MotionLoad {
    t: Vec<f64>,
    k: Vec<f64>,
    m: Vec<f64>,
    /// K t_m and M t_m in x (for a reaction at the coordinate).
    rows: ReactionRows,
}

/// The rows of a constraint reaction δσ_a = t·f − (K t)·δx − (M t)·δẍ, with t the lifted
/// direction G t = e_a through the free coordinates (module docs).
struct ReactionRows {
    t: Vec<f64>,
    kt: Vec<f64>,
    mt: Vec<f64>,
}

/// Loads of unit enforced motions. K on the moved coordinates comes from a linearisation of a
/// copy of the model in which they are free: a translation alone, for a rotation all of
/// λ1..λ3 of the node. This keeps the constraints and multipliers: λ0 is always free, so every
/// rotational node already has its normalisation and multiplier, whose term 2μ I acts only on
/// the node's own (held) rows, which Zᵀ does not see. The direction (e_i, or ½ Λ̄ᵀ e_k on λ)
/// is lifted onto the rigid/prescribed deformation constraints by the least-squares particular
/// solution t_m = t⁰_m + T w, G T w = −G t⁰_m.
fn motion_loads(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    motions: &[Motion],
    reactions: &[(String, usize)],
) -> Result<(Vec<MotionLoad>, Vec<ReactionRows>), StateSpaceError> {
    if motions.is_empty() && reactions.is_empty() {
        return Ok((Vec::new(), Vec::new()));
    }
    let mut free = model.clone();
    let mut freed = Vec::new();
    let role = crate::statics::roles(model);
    // rigid/prescribed deformation constraints (rows of G)
    let rows: Vec<usize> = (0..model.ne)
        .filter(|&i| role[i] != crate::statics::Role::Flexible)
        .collect();
    // unit directions t⁰_m in x before the lifting, and the row of G the motion drives
    let mut dirs = Vec::with_capacity(motions.len());
    for mo in motions {
        let name = mo.name(model);
        match *mo {
            Motion::Node { node, dof } => {
                let n = &model.nodes[node];
                let Some(i) = n.x_index(dof) else {
                    return Err(StateSpaceError::NoRotation {
                        node: n.name.clone(),
                    });
                };
                if model.partition.x[i] == CoordKind::Free {
                    return Err(StateSpaceError::MotionNotHeld { input: name });
                }
                let own: Vec<usize> = match (dof.is_rotation(), n.ix_rot) {
                    (true, Some(r)) => (r + 1..r + 4).collect(),
                    _ => vec![i],
                };
                for j in own {
                    free.partition.x[j] = CoordKind::Free;
                    freed.push(j);
                }
                let mut t0 = unit_vector(model, step, node, dof)?;
                if dof.is_rotation() {
                    // ½ Λ̄ᵀ e_k (the output row is 2 Λ̄ᵀ e_k)
                    t0.iter_mut().for_each(|v| *v *= 0.25);
                }
                dirs.push((t0, None));
            }
            Motion::Deformation { element, mode } => {
                let entry = &model.elements[element];
                if entry.element.is_rigid_body() {
                    return Err(StateSpaceError::RigidBodyMotion { input: name });
                }
                let i = entry.ie + mode;
                let Some(row) = rows.iter().position(|&r| r == i) else {
                    return Err(StateSpaceError::DeformationNotHeld {
                        input: name,
                        mode: mode + 1,
                        name: entry.element.mode_name(mode, &model.node_names()),
                        kind: entry.element.type_name(),
                        element: entry.name.clone(),
                    });
                };
                dirs.push((vec![0.0; model.nx], Some(row)));
            }
        }
    }
    free.loads
        .prescribed
        .retain(|p| !matches!(p.target, crate::model::Target::Coordinate(i) if freed.contains(&i)));
    let nx = model.nx;
    let kx = linearize(&free, step).tangent_in_x(&free, &step.x);
    // the velocity basis of the free coordinates
    let ev = crate::assembly::evaluate(model, &step.x);
    let gt = if rows.is_empty() {
        None
    } else {
        let part = crate::model::Partition {
            x: model.partition.x.clone(),
            e: vec![crate::model::DefKind::Free; model.ne],
        };
        let cols = crate::kinematics::columns(model, &part, &step.x);
        let mut t = Mat::zeros(nx, cols.len());
        for (j, c) in cols.iter().enumerate() {
            let n = &model.nodes[c.node];
            match (c.dof.is_rotation(), n.ix_rot) {
                (true, Some(r)) => {
                    for k in 0..4 {
                        t[(r + k, j)] = c.lambda_rate[k];
                    }
                }
                _ => t[(n.ix_pos + c.dof.index(), j)] = 1.0,
            }
        }
        let g = Mat::from_fn(rows.len(), nx, |r, c| ev.D[(rows[r], c)]);
        let gt = &g * &t;
        Some((g, t, gt))
    };
    let ndof = red.ndof();
    // lift t⁰ onto the constraints: G t = the unit change of `row` (zero for a node motion)
    let lift = |t0: Vec<f64>, row: Option<usize>| -> Option<Vec<f64>> {
        let mut tm = t0;
        if let Some((g, t, gt)) = &gt {
            let target = |r: usize| if Some(r) == row { 1.0 } else { 0.0 };
            let mismatch = |tm: &[f64]| {
                let ge = g * Mat::from_fn(nx, 1, |a, _| tm[a]);
                Mat::from_fn(g.nrows(), 1, |r, _| ge[(r, 0)] - target(r))
            };
            let r0 = mismatch(&tm);
            if r0.norm_max() > 0.0 {
                // least squares G T w = −r0 through the SVD
                let f = crate::linalg::svd(gt.as_ref(), "constraint Jacobian").ok()?;
                let smax = f.s.first().copied().unwrap_or(0.0);
                let tol = f64::EPSILON.sqrt() * smax;
                let mut w = Mat::<f64>::zeros(gt.ncols(), 1);
                for (k, &sk) in f.s.iter().enumerate() {
                    if sk > tol {
                        let c: f64 = (0..g.nrows()).map(|r| f.U[(r, k)] * r0[(r, 0)]).sum();
                        for a in 0..gt.ncols() {
                            w[(a, 0)] -= f.V[(a, k)] * c / sk;
                        }
                    }
                }
                let tw = t * &w;
                for a in 0..nx {
                    tm[a] += tw[(a, 0)];
                }
                if mismatch(&tm).norm_max() > 1e-8 * r0.norm_max().max(smax) {
                    return None;
                }
            }
        }
        Some(tm)
    };
    let mut out = Vec::with_capacity(motions.len());
    for (mo, (t0, row)) in motions.iter().zip(dirs) {
        let Some(tm) = lift(t0, row) else {
            return Err(StateSpaceError::MotionConstrained {
                input: mo.name(model),
            });
        };
        let tmv = Mat::from_fn(nx, 1, |a, _| tm[a]);
        let (ktx, mtx) = (&kx * &tmv, &red.mx * &tmv);
        let k = red.z.transpose() * &ktx;
        let m = red.z.transpose() * &mtx;
        out.push(MotionLoad {
            k: (0..ndof).map(|r| k[(r, 0)]).collect(),
            m: (0..ndof).map(|r| m[(r, 0)]).collect(),
            rows: ReactionRows {
                kt: (0..nx).map(|a| ktx[(a, 0)]).collect(),
                mt: (0..nx).map(|a| mtx[(a, 0)]).collect(),
                t: tm.clone(),
            },
            t: tm,
        });
    }
    let mut rr = Vec::with_capacity(reactions.len());
    for (name, i) in reactions {
        let row = rows.iter().position(|r| r == i);
        let Some(t) = lift(vec![0.0; nx], row).filter(|_| row.is_some()) else {
            return Err(StateSpaceError::ReactionConstrained {
                output: name.clone(),
            });
        };
        let tv = Mat::from_fn(nx, 1, |a, _| t[a]);
        let (kt, mt) = (&kx * &tv, &red.mx * &tv);
        rr.push(ReactionRows {
            kt: (0..nx).map(|a| kt[(a, 0)]).collect(),
            mt: (0..nx).map(|a| mt[(a, 0)]).collect(),
            t,
        });
    }
    Ok((out, rr))
}

/// Force vector in x of a unit input; or the row of an output in x (same vector): for a
/// translation e_i, for a rotation 2 Λ̄ᵀ e_k on the node's λ.
fn unit_vector(
    model: &Model,
    step: &StepResult,
    node: usize,
    dof: Dof,
) -> Result<Vec<f64>, StateSpaceError> {
    let n = &model.nodes[node];
    let mut v = vec![0.0; model.nx];
    if dof.is_rotation() {
        let Some(r) = n.ix_rot else {
            return Err(StateSpaceError::NoRotation {
                node: n.name.clone(),
            });
        };
        let lb = lambda_bar(&[step.x[r], step.x[r + 1], step.x[r + 2], step.x[r + 3]]);
        let k = dof.index() - 3;
        for c in 0..4 {
            v[r + c] = 2.0 * lb[k][c];
        }
    } else {
        v[n.ix_pos + dof.index()] = 1.0;
    }
    Ok(v)
}

/// The row w in x of an output's value, δy = w·δx: e_i or 2 Λ̄ᵀ e_k for a node
/// ([`unit_vector`]), the row Dₐ of the element Jacobian for a deformation, Σ_b S_ab D_b over
/// the flexible deformations b for a stress resultant (σ = S e, as statics).
fn output_row(model: &Model, step: &StepResult, out: &Output) -> Result<Vec<f64>, StateSpaceError> {
    let (element, mode, force) = match out.probe {
        Probe::Node { node, dof } => return unit_vector(model, step, node, dof),
        Probe::Reaction { .. } => {
            return Err(StateSpaceError::SparseReaction {
                output: out.name(model),
            })
        }
        Probe::Deformation { element, mode } => (element, mode, false),
        Probe::Force { element, mode } => (element, mode, true),
    };
    let entry = &model.elements[element];
    let ne = entry.element.ne();
    let coef: Vec<f64> = if force {
        let role = crate::statics::element_roles(model, element);
        let flexible = |b: usize| role[b] == crate::statics::Role::Flexible;
        if !flexible(mode) {
            return Err(StateSpaceError::ForceOfHeldDeformation {
                output: out.name(model),
            });
        }
        let s = entry.element.stiffness();
        (0..ne)
            .map(|b| if flexible(b) { s[(mode, b)] } else { 0.0 })
            .collect()
    } else {
        (0..ne).map(|b| if b == mode { 1.0 } else { 0.0 }).collect()
    };
    let d = entry
        .element
        .jacobian(&crate::assembly::gather(entry, &step.x));
    let mut w = vec![0.0; model.nx];
    for (c, &i) in entry.xmap.iter().enumerate() {
        w[i] += (0..ne).map(|b| coef[b] * d[(b, c)]).sum::<f64>();
    }
    Ok(w)
}

/// Whether an output is a node direction held by a support or prescribed input.
fn held_output(model: &Model, out: &Output) -> bool {
    matches!(out.probe, Probe::Node { node, dof } if held(model, node, dof))
}

/// Whether a direction of a node is held by a support or prescribed input.
fn held(model: &Model, node: usize, dof: Dof) -> bool {
    model.nodes[node]
        .x_index(dof)
        .is_none_or(|i| model.partition.x[i] != CoordKind::Free)
}

/// Build the state-space model at a converged static state.
pub fn state_space(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    state_space_with_motions(model, step, inputs, &[], outputs, opts)
}

/// [`state_space`] with prescribed-motion inputs as well: B and D get the columns of `inputs`
/// (forces, moments), then those of `motions` (enforced accelerations ü [m/s²]); the state
/// gets (u, u̇) of every motion after the modal coordinates (module docs).
pub fn state_space_with_motions(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    check_ids(model, inputs, motions, outputs)?;
    let ndof = velocity_dof(model);
    if uses_sparse(model, opts) {
        check_options(inputs, motions, outputs, opts)?;
        if let Some(m) = motions.first() {
            return Err(StateSpaceError::SparseMotion {
                input: m.name(model),
                ndof,
                limit: DENSE_STATE_SPACE_DOF,
            });
        }
        let Some(count) = opts.modes else {
            return Err(StateSpaceError::SparseNeedsModes {
                ndof,
                limit: DENSE_STATE_SPACE_DOF,
            });
        };
        return build_sparse(model, step, inputs, outputs, count, opts);
    }
    check_dense_size(model, opts)?;
    let lin = linearize(model, step);
    let red = reduced_matrices_with(model, step, &lin)?;
    build(model, step, &red, inputs, motions, outputs, opts)
}

/// Whether [`state_space_with_motions`] takes the sparse path for this model and these
/// options (the solver asked for; `Auto`: above [`DENSE_STATE_SPACE_DOF`] degrees of freedom).
pub fn uses_sparse(model: &Model, opts: &StateSpaceOptions) -> bool {
    match opts.solver {
        EigenSolver::Auto => velocity_dof(model) > DENSE_STATE_SPACE_DOF,
        s => s == EigenSolver::Sparse,
    }
}

/// The size guard of the dense state space: [`ModalError::TooLarge`] when the options choose
/// the dense path and its matrices would exceed `opts.max_dense_bytes`.
pub fn check_dense_size(model: &Model, opts: &StateSpaceOptions) -> Result<(), StateSpaceError> {
    if !uses_sparse(model, opts) {
        super::dense_size::check_dense_modal(model, opts.max_dense_bytes, true)?;
    }
    Ok(())
}

/// Validate the options and the input/output counts.
/// Every node, element and mode an input, motion or output names exists in `model` (the ids are
/// plain indices: a wrong one must be an error, not a panic).
fn check_ids(
    model: &Model,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
) -> Result<(), StateSpaceError> {
    let node = |n: usize, what: &str| {
        (n < model.nodes.len())
            .then_some(())
            .ok_or_else(|| StateSpaceError::UnknownId(format!("{what} of node #{n}")))
    };
    let mode = |el: usize, m: usize, what: &str| match model.elements.get(el) {
        Some(e) if m < e.element.ne() => Ok(()),
        _ => Err(StateSpaceError::UnknownId(format!(
            "{what} of mode {} of element #{el}",
            m + 1
        ))),
    };
    for i in inputs {
        node(i.node, "input")?;
    }
    for m in motions {
        match *m {
            Motion::Node { node: n, .. } => node(n, "motion input")?,
            Motion::Deformation { element, mode: k } => mode(element, k, "motion input")?,
        }
    }
    for o in outputs {
        match o.probe {
            Probe::Node { node: n, .. } | Probe::Reaction { node: n, .. } => node(n, "output")?,
            Probe::Deformation { element, mode: k } | Probe::Force { element, mode: k } => {
                mode(element, k, "output")?
            }
        }
    }
    Ok(())
}

fn check_options(
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<(), StateSpaceError> {
    let zeta = opts.damping;
    if !(zeta.is_finite() && zeta >= 0.0) {
        return Err(StateSpaceError::BadDamping(zeta));
    }
    if opts.modes == Some(0) {
        return Err(StateSpaceError::NoModes);
    }
    if (inputs.is_empty() && motions.is_empty()) || outputs.is_empty() {
        return Err(StateSpaceError::NoInputOutput);
    }
    Ok(())
}

/// The model-specific parts of a state-space model, from which [`assemble`] builds A, B, C, D.
struct Parts {
    /// ω² of the kept modes.
    lam: Vec<f64>,
    /// Φᵀ Bq (kept modes × inputs).
    modal_b: Mat<f64>,
    /// Cx Φ (outputs × kept modes).
    modal_c: Mat<f64>,
    /// Static feedthrough of displacement outputs (outputs × inputs).
    d_static: Mat<f64>,
    /// Quasi-static gains of the motion inputs (outputs × motions).
    motion_gain: Mat<f64>,
    warnings: Vec<String>,
    ndof: usize,
    massless: usize,
    available: usize,
    solver: EigenSolver,
    /// Kind of every internal row of `modal_c`, `d_static`, `motion_gain`.
    kinds: Vec<OutputKind>,
    /// Every output as a signed sum of internal rows, plus a direct feedthrough of the force
    /// inputs (outputs × force inputs): a node or element output is one row; a reaction is
    /// t·f − (K t)·δx − (M t)·δẍ.
    combine: Combine,
    feed: Mat<f64>,
}

/// Every output as a signed sum of internal rows (see [`Parts::combine`]).
type Combine = Vec<Vec<(usize, f64)>>;

/// One output per internal row, no feedthrough.
fn identity_rows(outputs: &[Output], n_force: usize) -> (Vec<OutputKind>, Combine, Mat<f64>) {
    (
        outputs.iter().map(|o| o.kind).collect(),
        (0..outputs.len()).map(|o| vec![(o, 1.0)]).collect(),
        Mat::zeros(outputs.len(), n_force),
    )
}

/// Warnings for inputs on held directions.
fn held_input_warnings(model: &Model, inputs: &[Input], warnings: &mut Vec<String>) {
    for inp in inputs {
        if held(model, inp.node, inp.dof) {
            warnings.push(format!(
                "input {} acts on a held direction (support or prescribed input): it has no effect",
                inp.name(model)
            ));
        }
    }
}

/// The sparse state space (module docs): the lowest `count` modes by shift-invert Lanczos
/// (mass-normalised shapes φ in x), Φᵀ Bq = φᵀ f and Cx Φ = w·φ directly in x. The static
/// feedthrough of displacement outputs is the exact static response minus that of the kept
/// modes, Cx K⁻¹ f − Σ (w·φ)(φ·f)/ω², from one sparse factorisation of the statics Newton
/// matrix: with `static_correction`, and always when the model has massless directions
/// (their instantaneous response; the sparse path cannot separate it from the dropped modes').
fn build_sparse(
    model: &Model,
    step: &StepResult,
    inputs: &[Input],
    outputs: &[Output],
    count: usize,
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    let (sm, problem) = super::sparse::sparse_modes_kept(model, step, count)?;
    let mut warnings = Vec::new();
    let available = sm.ndof - sm.massless;
    let n = sm.eigenvalues.len();
    if count > n {
        warnings.push(format!(
            "{count} modes asked for: the model has {n} modes that carry mass; all are kept"
        ));
    }
    held_input_warnings(model, inputs, &mut warnings);
    for out in outputs {
        if held_output(model, out) {
            warnings.push(format!(
                "output {} is a held direction (support or prescribed input): it is zero",
                out.name(model)
            ));
        }
    }
    let f: Vec<Vec<f64>> = inputs
        .iter()
        .map(|i| unit_vector(model, step, i.node, i.dof))
        .collect::<Result<_, _>>()?;
    let w: Vec<Vec<f64>> = outputs
        .iter()
        .map(|o| output_row(model, step, o))
        .collect::<Result<_, _>>()?;
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let modal_b = Mat::from_fn(n, inputs.len(), |k, j| dot(&sm.shapes[k], &f[j]));
    let modal_c = Mat::from_fn(outputs.len(), n, |o, k| dot(&w[o], &sm.shapes[k]));
    let (no, ni) = (outputs.len(), inputs.len());
    let mut d_static = Mat::zeros(no, ni);
    let residual = opts.static_correction || sm.massless > 0;
    if residual && outputs.iter().any(|o| o.kind == OutputKind::Disp) {
        let dx = problem.static_responses(model, step, &f)?;
        for (o, out) in outputs.iter().enumerate() {
            if out.kind != OutputKind::Disp {
                continue;
            }
            for j in 0..ni {
                let modal: f64 = (0..n)
                    .map(|k| modal_c[(o, k)] * modal_b[(k, j)] / sm.eigenvalues[k])
                    .sum();
                d_static[(o, j)] = dot(&w[o], &dx[j]) - modal;
            }
        }
        if sm.massless > 0 && !opts.static_correction {
            warnings.push(format!(
                "the model has {} direction(s) without inertia: D carries their static response together with that of the dropped modes (as the static correction does), which the sparse path cannot separate",
                sm.massless
            ));
        }
    }
    if sm.massless > 0 && outputs.iter().any(|o| o.kind != OutputKind::Disp) {
        warnings.push(
            "velocity and acceleration outputs miss the instantaneous response of the directions without inertia (proportional to the input's derivative)".into(),
        );
    }
    let (kinds, combine, feed) = identity_rows(outputs, inputs.len());
    Ok(assemble(
        inputs,
        &[],
        outputs,
        opts,
        Parts {
            lam: sm.eigenvalues,
            modal_b,
            modal_c,
            d_static,
            motion_gain: Mat::zeros(no, 0),
            warnings,
            ndof: sm.ndof,
            massless: sm.massless,
            available,
            solver: EigenSolver::Sparse,
            kinds,
            combine,
            feed,
        },
    ))
}

/// [`state_space_with_motions`] from reduced matrices already at hand (e.g. those of a
/// modal analysis of the same step).
pub fn state_space_from(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    check_ids(model, inputs, motions, outputs)?;
    build(model, step, red, inputs, motions, outputs, opts)
}

fn build(
    model: &Model,
    step: &StepResult,
    red: &Reduced,
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
) -> Result<StateSpace, StateSpaceError> {
    check_options(inputs, motions, outputs, opts)?;
    let mut warnings = Vec::new();
    let (lam, phi) = red.eigen()?;
    let available = lam.len();
    let n = opts.modes.unwrap_or(available).min(available);
    if let Some(k) = opts.modes {
        if k > available {
            warnings.push(format!(
                "{k} modes asked for: the model has {available} modes that carry mass; all are kept"
            ));
        }
    }
    let ndof = red.ndof();
    // force outputs of rigid or prescribed deformations: constraint reactions
    let mut reactions = Vec::new();
    let mut reaction_of = vec![None; outputs.len()];
    for (o, out) in outputs.iter().enumerate() {
        if let Probe::Force { element, mode } = out.probe {
            if out.is_reaction(model) {
                if out.kind != OutputKind::Disp {
                    return Err(StateSpaceError::ReactionRate {
                        output: out.name(model),
                    });
                }
                reaction_of[o] = Some(reactions.len());
                reactions.push((out.name(model), model.elements[element].ie + mode));
            }
        }
    }
    // reactions at held node coordinates: the rows of a unit motion of the coordinate
    let mut node_reactions: Vec<Motion> = Vec::new();
    let mut node_reaction_of = vec![None; outputs.len()];
    for (o, out) in outputs.iter().enumerate() {
        if let Probe::Reaction { node, dof } = out.probe {
            if out.kind != OutputKind::Disp {
                return Err(StateSpaceError::ReactionRate {
                    output: out.name(model),
                });
            }
            let n = &model.nodes[node];
            let Some(i) = n.x_index(dof) else {
                return Err(StateSpaceError::NoRotation {
                    node: n.name.clone(),
                });
            };
            if model.partition.x[i] == CoordKind::Free {
                return Err(StateSpaceError::ReactionNotHeld {
                    output: out.name(model),
                });
            }
            node_reaction_of[o] = Some(node_reactions.len());
            node_reactions.push(Motion::Node { node, dof });
        }
    }
    let all_motions: Vec<Motion> = motions.iter().chain(&node_reactions).copied().collect();
    let (mut mloads, rrows) = motion_loads(model, step, red, &all_motions, &reactions)?;
    let nr_rows: Vec<ReactionRows> = mloads
        .split_off(motions.len())
        .into_iter()
        .map(|ml| ml.rows)
        .collect();
    let (nf, nm) = (inputs.len(), motions.len());
    let ni = nf + nm;
    // quasi-static responses ψ = −K0⁻¹ Zᵀ K t_m (ndof × motions), dense LU of K0
    let mut psi = Mat::<f64>::zeros(ndof, nm);
    if nm > 0 {
        let kt = Mat::from_fn(ndof, nm, |r, j| mloads[j].k[r]);
        let lu = red.k0.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &kt);
        let res = &red.k0 * &sol - &kt;
        for j in 0..nm {
            let sn = sol.col(j).norm_max();
            let ok = sn.is_finite()
                && res.col(j).norm_max() <= 1e-8 * (red.k0.norm_max() * sn + kt.col(j).norm_max());
            if !ok {
                return Err(StateSpaceError::MotionSingular {
                    input: motions[j].name(model),
                });
            }
            for r in 0..ndof {
                psi[(r, j)] = -sol[(r, j)];
            }
        }
    }
    let m0psi = &red.m0 * &psi;
    // Bq = Zᵀ f (ndof × inputs), Cx = rows of the outputs in q (outputs × ndof)
    let mut bq = Mat::zeros(ndof, ni);
    for j in 0..nm {
        // r is driven by −(M0 ψ + Zᵀ M t_m) ü
        for r in 0..ndof {
            bq[(r, nf + j)] = -(m0psi[(r, j)] + mloads[j].m[r]);
        }
    }
    held_input_warnings(model, inputs, &mut warnings);
    let mut forces = Vec::with_capacity(nf);
    for (j, inp) in inputs.iter().enumerate() {
        let f = unit_vector(model, step, inp.node, inp.dof)?;
        for r in 0..ndof {
            bq[(r, j)] = (0..model.nx).map(|i| red.z[(i, r)] * f[i]).sum::<f64>();
        }
        forces.push(f);
    }
    // internal rows: one per output, two per reaction, δσ = t·f − (K t)·δx − (M t)·δẍ
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let (mut row_w, mut kinds, mut row_out) = (Vec::new(), Vec::new(), Vec::new());
    let mut combine = Vec::with_capacity(outputs.len());
    let mut feed = Mat::zeros(outputs.len(), nf);
    for (o, out) in outputs.iter().enumerate() {
        // a deformation's reaction: t·f − (K t)·δx − (M t)·δẍ; a support's: the negative
        let reaction = match (reaction_of[o], node_reaction_of[o]) {
            (Some(q), _) => Some((&rrows[q], -1.0)),
            (None, Some(q)) => Some((&nr_rows[q], 1.0)),
            (None, None) => None,
        };
        match reaction {
            None => {
                combine.push(vec![(row_w.len(), 1.0)]);
                row_w.push(output_row(model, step, out)?);
                kinds.push(out.kind);
                row_out.push(o);
            }
            Some((rr, sign)) => {
                combine.push(vec![(row_w.len(), sign), (row_w.len() + 1, sign)]);
                row_w.push(rr.kt.clone());
                kinds.push(OutputKind::Disp);
                row_w.push(rr.mt.clone());
                kinds.push(OutputKind::Acc);
                row_out.extend([o, o]);
                for (j, f) in forces.iter().enumerate() {
                    feed[(o, j)] = -sign * dot(&rr.t, f);
                }
            }
        }
    }
    let no = row_w.len();
    let mut cx = Mat::zeros(no, ndof);
    let mut motion_gain = Mat::zeros(no, nm);
    for (o, w) in row_w.iter().enumerate() {
        let out = &outputs[row_out[o]];
        for (j, ml) in mloads.iter().enumerate() {
            let direct: f64 = (0..model.nx).map(|i| w[i] * ml.t[i]).sum();
            let quasi: f64 = (0..ndof)
                .map(|r| (0..model.nx).map(|i| w[i] * red.z[(i, r)]).sum::<f64>() * psi[(r, j)])
                .sum();
            motion_gain[(o, j)] = direct + quasi;
        }
        if held_output(model, out)
            && !mloads
                .iter()
                .any(|ml| (0..model.nx).map(|i| w[i] * ml.t[i]).sum::<f64>() != 0.0)
        {
            warnings.push(format!(
                "output {} is a held direction (support or prescribed input): it is zero",
                out.name(model)
            ));
        }
        for r in 0..ndof {
            cx[(o, r)] = (0..model.nx).map(|i| w[i] * red.z[(i, r)]).sum::<f64>();
        }
    }
    let phik = Mat::from_fn(ndof, n, |i, k| phi[(i, k)]);
    let modal_b = phik.transpose() * &bq; // n × ni
    let modal_c = &cx * &phik; // no × n
                               // static flexibility not carried by the kept modes
    let massless_flex = red.massless_flexibility();
    let d_massless = &cx * &massless_flex * &bq; // no × ni
    let mut d_residual = Mat::<f64>::zeros(no, ni);
    if opts.static_correction && n < available {
        let phid = Mat::from_fn(ndof, available - n, |i, k| phi[(i, n + k)] / lam[n + k]);
        let phidt = Mat::from_fn(ndof, available - n, |i, k| phi[(i, n + k)]);
        d_residual = &cx * &phid * (phidt.transpose() * &bq);
    }
    let mut d_static = Mat::zeros(no, ni);
    let fmax = massless_flex.norm_max();
    for (o, kind) in kinds.iter().enumerate() {
        let out = &outputs[row_out[o]];
        let co = cx.row(o).norm_l2();
        for j in 0..ni {
            // below this the massless response is round-off
            let dm = if d_massless[(o, j)].abs() > 1e-9 * co * bq.col(j).norm_l2() * fmax {
                d_massless[(o, j)]
            } else {
                0.0
            };
            if *kind == OutputKind::Disp {
                d_static[(o, j)] = dm + d_residual[(o, j)];
            } else if dm != 0.0 {
                warnings.push(format!(
                    "{} responds instantaneously to {} through coordinates without inertia; that part (proportional to the input's derivative) is not in the model",
                    out.name(model),
                    input_name(model, inputs, motions, j)
                ));
            }
        }
    }
    Ok(assemble(
        inputs,
        motions,
        outputs,
        opts,
        Parts {
            lam: lam[..n].to_vec(),
            modal_b,
            modal_c,
            d_static,
            motion_gain,
            warnings,
            ndof,
            massless: red.massless(),
            available,
            solver: EigenSolver::Dense,
            kinds,
            combine,
            feed,
        },
    ))
}

/// A, B, C, D from the modal parts: state (η, η̇, then (u, u̇) of every motion).
fn assemble(
    inputs: &[Input],
    motions: &[Motion],
    outputs: &[Output],
    opts: &StateSpaceOptions,
    parts: Parts,
) -> StateSpace {
    let Parts {
        lam,
        modal_b,
        modal_c,
        d_static,
        motion_gain,
        warnings,
        ndof,
        massless,
        available,
        solver,
        kinds,
        combine,
        feed,
    } = parts;
    let zeta = opts.damping;
    let n = lam.len();
    let (nf, nm, nr, ni) = (
        inputs.len(),
        motions.len(),
        kinds.len(),
        inputs.len() + motions.len(),
    );
    let omega: Vec<f64> = lam.iter().map(|l| l.abs().sqrt()).collect();
    let ns = 2 * n + 2 * nm;
    let mut a = Mat::zeros(ns, ns);
    for k in 0..n {
        a[(k, n + k)] = 1.0;
        a[(n + k, k)] = -lam[k];
        a[(n + k, n + k)] = -2.0 * zeta * omega[k];
    }
    let mut b = Mat::zeros(ns, ni);
    for k in 0..n {
        for j in 0..ni {
            b[(n + k, j)] = modal_b[(k, j)];
        }
    }
    for j in 0..nm {
        a[(2 * n + 2 * j, 2 * n + 2 * j + 1)] = 1.0;
        b[(2 * n + 2 * j + 1, nf + j)] = 1.0;
    }
    // the internal rows
    let mut c_rows = Mat::zeros(nr, ns);
    let mut d_rows = Mat::zeros(nr, ni);
    for (o, kind) in kinds.iter().enumerate() {
        for k in 0..n {
            let ck = modal_c[(o, k)];
            match kind {
                OutputKind::Disp => c_rows[(o, k)] = ck,
                OutputKind::Vel => c_rows[(o, n + k)] = ck,
                OutputKind::Acc => {
                    c_rows[(o, k)] = -ck * lam[k];
                    c_rows[(o, n + k)] = -ck * 2.0 * zeta * omega[k];
                }
            }
        }
        for j in 0..ni {
            d_rows[(o, j)] = match kind {
                OutputKind::Disp => d_static[(o, j)],
                OutputKind::Vel => 0.0,
                OutputKind::Acc => (0..n).map(|k| modal_c[(o, k)] * modal_b[(k, j)]).sum(),
            };
        }
        for j in 0..nm {
            let g = motion_gain[(o, j)];
            match kind {
                OutputKind::Disp => c_rows[(o, 2 * n + 2 * j)] = g,
                OutputKind::Vel => c_rows[(o, 2 * n + 2 * j + 1)] = g,
                OutputKind::Acc => d_rows[(o, nf + j)] += g,
            }
        }
    }
    // the outputs: signed sums of rows; the quasi-static motion gain counts the value rows
    let no = outputs.len();
    let mut c = Mat::zeros(no, ns);
    let mut d = Mat::zeros(no, ni);
    let mut gain = Mat::zeros(no, nm);
    for (o, terms) in combine.iter().enumerate() {
        for &(r, w) in terms {
            for q in 0..ns {
                c[(o, q)] += w * c_rows[(r, q)];
            }
            for j in 0..ni {
                d[(o, j)] += w * d_rows[(r, j)];
            }
            if kinds[r] == OutputKind::Disp {
                for j in 0..nm {
                    gain[(o, j)] += w * motion_gain[(r, j)];
                }
            }
        }
        for j in 0..nf {
            d[(o, j)] += feed[(o, j)];
        }
    }
    StateSpace {
        a,
        b,
        c,
        d,
        inputs: inputs.to_vec(),
        motions: motions.to_vec(),
        outputs: outputs.to_vec(),
        eigenvalues: lam,
        damping: zeta,
        ndof,
        massless,
        available_modes: available,
        static_correction: opts.static_correction,
        warnings,
        solver,
        motion_gain: gain,
    }
}

/// Name of input column j (forces first, then motions).
fn input_name(model: &Model, inputs: &[Input], motions: &[Motion], j: usize) -> String {
    match inputs.get(j) {
        Some(i) => i.name(model),
        None => motions[j - inputs.len()].name(model),
    }
}

impl StateSpace {
    /// Number of kept modes (the state has twice as many entries).
    pub fn n_modes(&self) -> usize {
        self.eigenvalues.len()
    }

    /// Frequencies of the kept modes [Hz] (NaN for ω² < 0).
    pub fn frequencies(&self) -> Vec<f64> {
        self.eigenvalues
            .iter()
            .map(|&l| {
                if l >= 0.0 {
                    l.sqrt() / (2.0 * std::f64::consts::PI)
                } else {
                    f64::NAN
                }
            })
            .collect()
    }

    /// Number of input columns (forces and moments, then motions).
    pub fn n_inputs(&self) -> usize {
        self.inputs.len() + self.motions.len()
    }

    /// Number of states: 2 per kept mode, 2 per motion input.
    pub fn n_states(&self) -> usize {
        self.a.nrows()
    }

    /// State names: `eta_k`, `deta_k`, then `u_j`, `du_j` (enforced displacement and velocity
    /// of input column j, 1-based).
    pub fn state_names(&self) -> Vec<String> {
        let n = self.n_modes();
        let nf = self.inputs.len();
        (1..=n)
            .map(|k| format!("eta_{k}"))
            .chain((1..=n).map(|k| format!("deta_{k}")))
            .chain(
                (0..self.motions.len())
                    .flat_map(|j| [format!("u_{}", nf + j + 1), format!("du_{}", nf + j + 1)]),
            )
            .collect()
    }

    /// Descriptions of the input columns, in order (forces and moments, then motions).
    pub fn input_info(&self, model: &Model) -> Vec<InputInfo> {
        self.inputs
            .iter()
            .map(|i| InputInfo {
                name: i.name(model),
                node: Some(i.node),
                dof: Some(i.dof),
                deformation: None,
                kind: i.kind_name(),
                unit: i.unit(),
                description: i.describe(model),
            })
            .chain(self.motions.iter().map(|m| {
                let (node, dof, deformation) = match *m {
                    Motion::Node { node, dof } => (Some(node), Some(dof), None),
                    Motion::Deformation { element, mode } => (None, None, Some((element, mode))),
                };
                InputInfo {
                    name: m.name(model),
                    node,
                    dof,
                    deformation,
                    kind: m.kind_name(),
                    unit: m.unit(model),
                    description: m.describe(model),
                }
            }))
            .collect()
    }

    /// Quasi-static response of the outputs per unit enforced displacement of each motion
    /// input (outputs × motions): Cx ψ + w·t_m for displacement outputs, 0 for velocity and
    /// acceleration outputs. For a slow enforced displacement u the outputs are this times u.
    pub fn motion_static_gain(&self) -> Mat<f64> {
        Mat::from_fn(self.outputs.len(), self.motions.len(), |o, j| {
            if self.outputs[o].kind == OutputKind::Disp {
                self.motion_gain[(o, j)]
            } else {
                0.0
            }
        })
    }

    /// Static (DC) gain (outputs × inputs). Force and moment columns: −C A⁻¹ B + D from a
    /// dense LU of the modal block of A. Motion columns (whose input ü would give an unbounded
    /// displacement): the static response per unit enforced displacement,
    /// [`StateSpace::motion_static_gain`].
    pub fn dc_gain(&self) -> Result<Mat<f64>, StateSpaceError> {
        let ns = 2 * self.n_modes();
        let am = Mat::from_fn(ns, ns, |i, j| self.a[(i, j)]);
        let bm = Mat::from_fn(ns, self.b.ncols(), |i, j| self.b[(i, j)]);
        let cm = Mat::from_fn(self.c.nrows(), ns, |i, j| self.c[(i, j)]);
        let amax = am.norm_max();
        if self
            .eigenvalues
            .iter()
            .any(|l| l.abs() <= 1e-12 * amax.max(1.0))
        {
            return Err(StateSpaceError::Singular);
        }
        let lu = am.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &bm);
        let res = &am * &sol - &bm;
        if !crate::linalg::all_finite(&sol)
            || res.norm_max() > 1e-8 * (amax * sol.norm_max() + bm.norm_max())
        {
            return Err(StateSpaceError::Singular);
        }
        let mut g = &self.d - &cm * &sol;
        let nf = self.inputs.len();
        let ms = self.motion_static_gain();
        for o in 0..self.outputs.len() {
            for j in 0..self.motions.len() {
                g[(o, nf + j)] = ms[(o, j)];
            }
        }
        Ok(g)
    }

    /// Frequency response G(i2πf) = C (i2πf I − A)⁻¹ B + D (outputs × inputs), evaluated
    /// block by block, as A is block diagonal: a mode's block gives η = b/(s² + 2ζωs + ω²) and
    /// η̇ = s η per unit of its B row, a motion's double integrator u = ü/s², u̇ = ü/s.
    pub fn frequency_response(&self, f_hz: f64) -> Vec<Vec<c64>> {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f_hz);
        let n = self.n_modes();
        let den: Vec<c64> = (0..n)
            .map(|k| {
                let w = self.eigenvalues[k].abs().sqrt();
                s * s + s * (2.0 * self.damping * w) + self.eigenvalues[k]
            })
            .collect();
        let nf = self.inputs.len();
        (0..self.outputs.len())
            .map(|o| {
                (0..self.n_inputs())
                    .map(|j| {
                        let mut g = c64::new(self.d[(o, j)], 0.0);
                        for k in 0..n {
                            let bk = self.b[(n + k, j)];
                            if bk != 0.0 {
                                g += (s * self.c[(o, n + k)] + self.c[(o, k)]) * bk / den[k];
                            }
                        }
                        if j >= nf {
                            // the motion's own states (u, u̇)
                            let m = 2 * n + 2 * (j - nf);
                            g += (s * self.c[(o, m + 1)] + self.c[(o, m)]) / (s * s);
                        }
                        g
                    })
                    .collect()
            })
            .collect()
    }

    /// `count` log-spaced frequencies [Hz] from 0.1 × the lowest positive to 10 × the highest
    /// kept frequency (None when no kept mode has a positive frequency).
    pub fn default_band(&self, count: usize) -> Option<Vec<f64>> {
        let f: Vec<f64> = self
            .frequencies()
            .into_iter()
            .filter(|f| f.is_finite() && *f > 0.0)
            .collect();
        let lo = f.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = f.iter().copied().fold(0.0f64, f64::max);
        if f.is_empty() {
            return None;
        }
        Some(log_space(0.1 * lo, 10.0 * hi, count))
    }
}

/// A dense matrix as a vector of rows (row-major), for reports.
pub fn to_rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// `count` log-spaced values from `lo` to `hi` (both included; `lo` alone for count 1).
pub fn log_space(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if count <= 1 {
        return vec![lo; count];
    }
    let (a, b) = (lo.ln(), hi.ln());
    (0..count)
        .map(|i| (a + (b - a) * i as f64 / (count - 1) as f64).exp())
        .collect()
}

/// Bode magnitude (absolute, output units per input unit) and phase [deg] of a response
/// sequence, the phase unwrapped along the sequence (continuous, starting in (−180, 180]).
pub fn magnitude_phase(g: &[c64]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(g.len());
    let mut prev: Option<f64> = None;
    for z in g {
        let mut p = z.arg().to_degrees();
        if let Some(q) = prev {
            p += 360.0 * ((q - p) / 360.0).round();
        }
        prev = Some(p);
        out.push((z.norm(), p));
    }
    out
}

#[cfg(test)]
#[path = "state_space_motion_tests.rs"]
mod motion_tests;

#[cfg(test)]
#[path = "state_space_deformation_tests.rs"]
mod deformation_tests;

#[cfg(test)]
#[path = "state_space_sparse_tests.rs"]
mod sparse_tests;

#[cfg(test)]
#[path = "state_space_element_output_tests.rs"]
mod element_output_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::modes;
    use crate::model::ModelBuilder;
    use crate::section::BeamProps;
    use crate::statics::last_step;
    use crate::statics::linear::compliance;

    /// Cantilever of `n` beams along x, clamped at n0, tip mass at the free end. With
    /// `rotary` the beams carry rotary inertia; without it the twist of every node is massless
    /// (the Hermite translational mass sees bending rotations through the end tangents, but not
    /// the twist about the beam axis), so those directions are condensed.
    pub(super) fn cantilever(n: usize, rotary: bool, axial_load: f64) -> Model {
        let l = 0.1;
        let mut b = ModelBuilder::new("cantilever");
        let props = BeamProps {
            ea: 2e6,
            gj: 0.7,
            eiy: 1.0,
            eiz: 3.0,
            rho_a: 0.1,
            rho_i: if rotary { [2e-6, 1e-6, 1e-6] } else { [0.0; 3] },
            ..Default::default()
        };
        b.add_beam_chain(
            "",
            [0.0; 3],
            [l, 0.0, 0.0],
            n,
            Some([0.0, 0.0, 1.0]),
            Some(props),
        )
        .unwrap();
        b.fix("n0", None).unwrap();
        let tip = format!("n{n}");
        b.add_point_mass(&tip, 0.05).unwrap();
        if axial_load != 0.0 {
            b.add_load(&tip, [axial_load, 0.0, 0.0], [0.0; 3]).unwrap();
        }
        b.build().unwrap()
    }

    pub(super) fn all_io(model: &Model, node: usize) -> (Vec<Input>, Vec<Output>) {
        let _ = model;
        let inputs = Dof::ALL.iter().map(|&dof| Input { node, dof }).collect();
        let outputs = Dof::ALL
            .iter()
            .map(|&dof| Output::node(node, dof, OutputKind::Disp))
            .collect();
        (inputs, outputs)
    }

    /// max |a − b| / max |b| over the 6 × 6 block.
    pub(super) fn rel_err(a: &Mat<f64>, b: &[[f64; 6]; 6]) -> f64 {
        let scale = b.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut e = 0.0f64;
        for i in 0..6 {
            for j in 0..6 {
                // entries are compared relative to their row and column scale (translations
                // and rotations differ by orders of magnitude)
                let s = (b[i][i].abs() * b[j][j].abs()).sqrt().max(1e-14 * scale);
                e = e.max((a[(i, j)] - b[i][j]).abs() / s);
            }
        }
        e
    }

    fn check_dc_gain(model: &Model, opts: &StateSpaceOptions) -> (StateSpace, f64) {
        let step = last_step(model, 2);
        let tip = model
            .node_id(&format!("n{}", model.nodes.len() - 1))
            .unwrap();
        let (inputs, outputs) = all_io(model, tip);
        let ss = state_space(model, &step, &inputs, &outputs, opts).unwrap();
        let lin = linearize(model, &step);
        let c = compliance(model, &lin, &step, tip).unwrap();
        let dc = ss.dc_gain().unwrap();
        (ss.clone(), rel_err(&dc, &c.global))
    }

    #[test]
    fn dc_gain_equals_static_compliance_all_modes() {
        // (a) force/moment inputs and displacement/rotation outputs on the tip, all modes
        for rotary in [true, false] {
            for load in [0.0, -20.0, 50.0] {
                let model = cantilever(4, rotary, load);
                let (ss, err) = check_dc_gain(&model, &StateSpaceOptions::default());
                assert!(err < 1e-6, "rotary {rotary}, load {load}: {err}");
                assert_eq!(ss.massless > 0, !rotary);
                assert_eq!(ss.n_modes(), ss.ndof - ss.massless);
            }
        }
    }

    #[test]
    fn condensed_model_needs_the_massless_feedthrough() {
        // without rotary inertia the twist is massless: the tip rotation about x responds to a
        // moment about x only through D (no mode carries it)
        let model = cantilever(4, false, 0.0);
        let (ss, _) = check_dc_gain(&model, &StateSpaceOptions::default());
        let (rx, ry) = (3, 4);
        assert!(ss.d[(rx, rx)] > 0.0);
        let dc = ss.dc_gain().unwrap();
        assert!((dc[(rx, rx)] - ss.d[(rx, rx)]).abs() < 1e-9 * dc[(rx, rx)]);
        // a force on the (massive) tip translation has no feedthrough
        for o in 0..6 {
            for j in 0..3 {
                assert!(ss.d[(o, j)].abs() < 1e-12 * dc[(1, 1)], "D[{o}, {j}]");
            }
        }
        // bending rotations carry mass through the Hermite tangents: no feedthrough there
        assert!(ss.d[(ry, ry)].abs() < 1e-9 * dc[(ry, ry)]);
    }

    #[test]
    fn truncated_model_keeps_dc_gain_with_static_correction() {
        for rotary in [true, false] {
            let model = cantilever(4, rotary, -20.0);
            let opts = StateSpaceOptions {
                modes: Some(3),
                static_correction: true,
                ..Default::default()
            };
            let (ss, err) = check_dc_gain(&model, &opts);
            assert_eq!(ss.n_modes(), 3);
            assert!(err < 1e-6, "rotary {rotary}: {err}");
            // without the correction a truncated model misses the static part of higher modes
            let opts = StateSpaceOptions {
                modes: Some(3),
                ..Default::default()
            };
            let (_, err) = check_dc_gain(&model, &opts);
            assert!(err > 1e-6, "rotary {rotary}: {err}");
        }
    }

    #[test]
    fn eigenvalues_of_a_are_the_damped_modal_poles() {
        // (b) eig(A) = −ζω ± iω√(1 − ζ²) for the frequencies of `modes`
        let model = cantilever(4, true, 30.0);
        let step = last_step(&model, 2);
        let tip = model.node_id("n4").unwrap();
        let zeta = 0.05;
        let ss = state_space(
            &model,
            &step,
            &[Input {
                node: tip,
                dof: Dof::Y,
            }],
            &[Output::node(tip, Dof::Y, OutputKind::Disp)],
            &super::motion_tests::damped(zeta),
        )
        .unwrap();
        let modal = modes(&model, &step, usize::MAX).unwrap();
        assert_eq!(modal.modes.len(), ss.n_modes());
        let mut poles = ss.a.eigenvalues().unwrap();
        poles.sort_by(|a, b| {
            a.im.abs()
                .total_cmp(&b.im.abs())
                .then(a.im.total_cmp(&b.im))
        });
        for (k, m) in modal.modes.iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI * m.frequency;
            let re = -zeta * w;
            let im = w * (1.0 - zeta * zeta).sqrt();
            for (p, sign) in [(poles[2 * k], -1.0), (poles[2 * k + 1], 1.0)] {
                assert!(
                    (p.re - re).abs() < 1e-9 * w && (p.im - sign * im).abs() < 1e-9 * w,
                    "mode {k}: pole {p} vs {re} ± {im}i"
                );
            }
        }
    }

    #[test]
    fn bode_far_below_resonance_is_the_dc_gain() {
        // (c) |G| and phase at f ≪ f1 equal the DC gain: the magnitude error is ~ (f/f1)², the
        // phase ~ 2ζ f/f1 rad, so at f = 1e-5 f1 both are below 1e-6
        for rotary in [true, false] {
            let model = cantilever(4, rotary, 0.0);
            let step = last_step(&model, 2);
            let tip = model.node_id("n4").unwrap();
            let (inputs, outputs) = all_io(&model, tip);
            let ss = state_space(
                &model,
                &step,
                &inputs,
                &outputs,
                &StateSpaceOptions::default(),
            )
            .unwrap();
            let dc = ss.dc_gain().unwrap();
            let f = 1e-5 * ss.frequencies()[0];
            let g = ss.frequency_response(f);
            for o in 0..6 {
                for j in 0..6 {
                    let s = (dc[(o, o)].abs() * dc[(j, j)].abs()).sqrt();
                    assert!(
                        (g[o][j] - c64::new(dc[(o, j)], 0.0)).norm() < 1e-6 * s,
                        "({o}, {j}): {} vs {}",
                        g[o][j],
                        dc[(o, j)]
                    );
                }
            }
            // collocated displacement/force: magnitude = compliance, phase 0
            let mp = magnitude_phase(&[g[1][1]]);
            assert!((mp[0].0 - dc[(1, 1)]).abs() < 1e-6 * dc[(1, 1)]);
            assert!(mp[0].1.abs() < 1e-3);
        }
    }

    #[test]
    fn frequency_response_matches_dense_resolvent() {
        // the modal evaluation equals C (sI − A)⁻¹ B + D for every output kind
        let model = cantilever(3, true, 10.0);
        let step = last_step(&model, 2);
        let tip = model.node_id("n3").unwrap();
        let mid = model.node_id("n2").unwrap();
        let inputs = [
            Input {
                node: tip,
                dof: Dof::Y,
            },
            Input {
                node: mid,
                dof: Dof::Rz,
            },
        ];
        let outputs: Vec<Output> = [OutputKind::Disp, OutputKind::Vel, OutputKind::Acc]
            .into_iter()
            .flat_map(|kind| {
                [
                    Output::node(tip, Dof::Y, kind),
                    Output::node(mid, Dof::Rz, kind),
                ]
            })
            .collect();
        let ss = state_space(
            &model,
            &step,
            &inputs,
            &outputs,
            &StateSpaceOptions {
                damping: 0.02,
                ..Default::default()
            },
        )
        .unwrap();
        for f in [0.3 * ss.frequencies()[0], 1.7 * ss.frequencies()[1]] {
            let w = 2.0 * std::f64::consts::PI * f;
            let ns = ss.a.nrows();
            let m = Mat::<c64>::from_fn(ns, ns, |i, j| {
                let d = if i == j {
                    c64::new(0.0, w)
                } else {
                    c64::new(0.0, 0.0)
                };
                d - c64::new(ss.a[(i, j)], 0.0)
            });
            let bc = Mat::<c64>::from_fn(ns, 2, |i, j| c64::new(ss.b[(i, j)], 0.0));
            let x = faer::prelude::Solve::solve(&m.partial_piv_lu(), &bc);
            let g = ss.frequency_response(f);
            for o in 0..outputs.len() {
                for j in 0..2 {
                    let mut want = c64::new(ss.d[(o, j)], 0.0);
                    for i in 0..ns {
                        want += x[(i, j)] * ss.c[(o, i)];
                    }
                    assert!(
                        (g[o][j] - want).norm() < 1e-9 * want.norm().max(1e-30),
                        "f {f}, output {o}, input {j}: {} vs {want}",
                        g[o][j]
                    );
                }
            }
        }
    }

    #[test]
    fn names_and_errors() {
        let model = cantilever(2, true, 0.0);
        let tip = model.node_id("n2").unwrap();
        let i = Input {
            node: tip,
            dof: Dof::Rz,
        };
        assert_eq!(i.name(&model), "n2:rz:moment");
        assert_eq!(i.describe(&model), "moment on n2 about global z");
        let o = Output::node(tip, Dof::X, OutputKind::Acc);
        assert_eq!(o.name(&model), "n2:x:acc");
        assert_eq!(o.unit(&model), "m/s²");
        let step = last_step(&model, 2);
        let bad = StateSpaceOptions {
            damping: -0.1,
            ..Default::default()
        };
        assert_eq!(
            state_space(&model, &step, &[i], &[o], &bad).unwrap_err(),
            StateSpaceError::BadDamping(-0.1)
        );
        // an input on the clamped node is held: warning, zero column
        let g = model.node_id("n0").unwrap();
        let ss = state_space(
            &model,
            &step,
            &[Input {
                node: g,
                dof: Dof::X,
            }],
            &[o],
            &StateSpaceOptions::default(),
        )
        .unwrap();
        assert!(ss.warnings[0].contains("held"), "{:?}", ss.warnings);
        assert_eq!(ss.b.norm_max(), 0.0);
    }

    #[test]
    fn ids_of_another_model_are_errors_not_panics() {
        // node, element and mode ids are plain indices: one past the end of this model
        let model = cantilever(2, true, 0.0);
        let step = last_step(&model, 2);
        let tip = model.node_id("n2").unwrap();
        let (n, ne) = (model.nodes.len(), model.elements.len());
        let good_in = Input {
            node: tip,
            dof: Dof::Z,
        };
        let good_out = Output::node(tip, Dof::Z, OutputKind::Disp);
        let opts = StateSpaceOptions::default();
        let bad_in = Input {
            node: n,
            dof: Dof::Z,
        };
        let err = state_space(&model, &step, &[bad_in], &[good_out], &opts).unwrap_err();
        assert!(matches!(err, StateSpaceError::UnknownId(_)), "{err}");
        for probe in [
            Probe::Node {
                node: n,
                dof: Dof::Z,
            },
            Probe::Reaction {
                node: n,
                dof: Dof::Z,
            },
            Probe::Deformation {
                element: ne,
                mode: 0,
            },
            Probe::Force {
                element: 0,
                mode: 6,
            },
        ] {
            let out = Output {
                probe,
                kind: OutputKind::Disp,
            };
            let err = state_space(&model, &step, &[good_in], &[out], &opts).unwrap_err();
            assert!(
                matches!(err, StateSpaceError::UnknownId(_)),
                "{probe:?}: {err}"
            );
        }
        let motion = Motion::Deformation {
            element: ne,
            mode: 0,
        };
        let err = state_space_with_motions(&model, &step, &[], &[motion], &[good_out], &opts)
            .unwrap_err();
        assert!(matches!(err, StateSpaceError::UnknownId(_)), "{err}");
    }

    #[test]
    fn log_space_and_phase_unwrap() {
        let f = log_space(1.0, 100.0, 3);
        assert!((f[1] - 10.0).abs() < 1e-12 && (f[2] - 100.0).abs() < 1e-12);
        let g = [
            c64::new(1.0, 0.0),
            c64::new(0.0, -1.0),
            c64::new(-1.0, -1e-9),
            c64::new(-1.0, 1e-9),
        ];
        let mp = magnitude_phase(&g);
        assert!((mp[3].1 + 180.0).abs() < 1e-6, "{mp:?}");
    }
}
