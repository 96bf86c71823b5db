//! Why a state-space model could not be built or evaluated ([`StateSpaceError`]).

use crate::dynamics::ModalError;

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
