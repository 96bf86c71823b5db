//! The document the page shows ([`ViewData`] and its parts, JSON through serde), the analysis
//! results it is made from ([`ViewResults`], [`Classification`]) and the writer's error.

use flexmbd_core::dynamics::Modal;
use flexmbd_core::kinematics::advice::StateAdvice;
use flexmbd_core::kinematics::ConstraintAnalysis;
use flexmbd_core::statics::{StaticSolution, StepResult};
use serde::{Deserialize, Serialize};

/// Errors of the HTML writer.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The data could not be written as JSON.
    #[error("cannot write the viewer data as JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The data does not fit the model.
    #[error("viewer data: {0}")]
    Data(String),
}

/// Everything the page shows. Bulk arrays are `f32` (display precision), the numbers printed in
/// the panel are `f64`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewData {
    /// Format version of this document (1).
    pub format: u32,
    /// Program and version that wrote it.
    pub generator: String,
    /// Model name.
    pub title: String,
    /// Model file.
    pub file: String,
    /// `check`, `static`, `modes` or `simulate`.
    pub analysis: String,
    /// Model size: diagonal of the bounding box of the reference nodes [m].
    pub size: f64,
    /// Nodes in model order.
    pub nodes: Vec<ViewNode>,
    /// Elements in model order.
    pub elements: Vec<ViewElement>,
    /// Mode names per element type (`truss`, `beam`, `hinge`).
    pub mode_names: Vec<(String, Vec<String>)>,
    /// Configurations: the reference (check), every load step (static), or the static state
    /// the modes are linearised about (modes).
    pub frames: Vec<ViewFrame>,
    /// Motions (check) or modes (modes), animated about a frame.
    pub animations: Vec<ViewAnimation>,
    /// Element colourings.
    pub fields: Vec<ViewField>,
    /// Kinematic classification (Table 1, counts, advice), if it was computed.
    pub summary: Option<ViewSummary>,
    /// Labelled facts about the analysis for the panel.
    pub info: Vec<(String, String)>,
    /// Remarks (e.g. why the classification was skipped).
    pub notes: Vec<String>,
    /// The time history of a simulation (its frames are the output times).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<super::ViewSimulation>,
    /// The axes of the bodies' twists in the motions and the lines of action of the wrenches
    /// in the self-stresses (check), each drawn with its motion or self-stress field.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub screw_lines: Vec<ViewScrewLine>,
}

/// A line of the designer's language: a twist axis (rotation), a translation direction, a
/// wrench's line of action (force) or a couple's axis, drawn through `point` along `direction`;
/// or a suggested wire (`wire`), the segment from `point` of `length`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewScrewLine {
    /// The animation (motion) it belongs to.
    pub item: Option<usize>,
    /// The field (self-stress state) it belongs to.
    pub field: Option<String>,
    /// `rotation`, `translation`, `force`, `couple` or `wire`.
    pub kind: String,
    /// A point of the line [m].
    pub point: [f64; 3],
    /// Unit direction.
    pub direction: [f64; 3],
    /// What it is, e.g. `platform: rotation, pitch 0`.
    pub label: String,
    /// A segment of this length from `point` (a suggested wire) instead of a line.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
}

/// A node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewNode {
    /// Name.
    pub name: String,
    /// Host node of a node placed `at` another (same position).
    pub host: Option<usize>,
    /// Whether the node carries a rotation.
    pub rot: bool,
    /// Its fixed (support) degrees of freedom (`x` … `rz`).
    pub fixed: Vec<String>,
    /// Its degrees of freedom that are generalised coordinates (inputs).
    pub input: Vec<String>,
}

/// Element types as the page knows them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ViewKind {
    /// Truss.
    Truss,
    /// Beam.
    Beam,
    /// Hinge.
    Hinge,
    /// Rigid body.
    Rigid,
}

/// An element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewElement {
    /// Name.
    pub name: String,
    /// Type.
    pub kind: ViewKind,
    /// Nodes (a rigid body: reference node first).
    pub nodes: Vec<usize>,
    /// Reference triad (rows): beam [ex, ey, ez], hinge [axis, b, c].
    pub frame: Option<[[f64; 3]; 3]>,
    /// Drawn cross-section of a beam.
    pub section: Option<ViewSection>,
    /// Partition of its deformations, one letter per mode: `r` rigid (fixed), `f` free,
    /// `i` input (generalised coordinate).
    pub partition: String,
}

/// Cross-section shapes the page draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SectionShape {
    /// Rectangle: width along local y, thickness along local z (a sheet when thin).
    Rectangle,
    /// Solid circle (a wire).
    Round,
    /// Circular tube.
    Tube,
}

/// The drawn section of a beam.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSection {
    /// Shape.
    pub shape: SectionShape,
    /// Drawn extent along local y [m] (diameter for round sections).
    pub width: f64,
    /// Drawn extent along local z [m].
    pub thickness: f64,
    /// The section's real width and thickness (outer and inner diameter of a tube) [m];
    /// `None` when the model gives no section and the shape was inferred.
    pub actual: Option<[f64; 2]>,
    /// Where the shape comes from: `section`, `stiffness` (ratio of the bending stiffnesses)
    /// or `partition` (which deformations are rigid).
    pub source: String,
}

/// A configuration: positions and rotations of all nodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewFrame {
    /// Label, e.g. `step 3`.
    pub label: String,
    /// Load factor of a load step.
    pub load_factor: Option<f64>,
    /// Positions, 3 per node [m].
    pub x: Vec<f32>,
    /// Euler parameters λ0…λ3, 4 per node (identity for nodes without rotation).
    pub q: Vec<f32>,
}

/// An animated motion or mode: node states x + s·u and R(s·w)·R, s = a sin 2πt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewAnimation {
    /// `motion` or `mode`.
    pub kind: String,
    /// Label, e.g. `motion 1`.
    pub label: String,
    /// What the selector shows next to the label, e.g. `s = 0 (structural)` or `8.21 Hz`.
    pub detail: String,
    /// Singular value (motion) or frequency [Hz] (mode).
    pub value: Option<f64>,
    /// A mode's class with the fractions that decide it, e.g. `intended β 0.99 ρ 1.00`
    /// (docs/dynamics.md "Mode classes"); `None` for a motion.
    #[serde(default)]
    pub class: Option<String>,
    /// Index of the frame it is animated about.
    pub frame: usize,
    /// Scale of u and w for the default amplitude.
    pub scale: f64,
    /// Nodal translations, 3 per node.
    pub u: Vec<f32>,
    /// Nodal rotation vectors (global axes), 3 per node.
    pub w: Vec<f32>,
}

/// What a field's value sets are indexed by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FieldPer {
    /// One set for the model.
    Model,
    /// One set per frame.
    Frame,
    /// One set per animation.
    Animation,
}

/// A scalar per element for colouring.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewField {
    /// Stable key (URL parameter `color=`).
    pub key: String,
    /// Label.
    pub label: String,
    /// Unit.
    pub unit: String,
    /// Signed quantity: diverging colour map symmetric about zero.
    pub diverging: bool,
    /// What the value sets are indexed by.
    pub per: FieldPer,
    /// Value sets, each with one value per element (`None`: not defined for that element).
    pub values: Vec<Vec<Option<f32>>>,
    /// Colour range over all sets.
    pub range: [f64; 2],
}

/// The kinematic classification for the panel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSummary {
    /// Rows m of Dcc.
    pub rows: usize,
    /// Columns n of Dcc.
    pub cols: usize,
    /// Numerical rank r.
    pub rank: usize,
    /// Row of the paper's Table 1.
    pub table1_row: usize,
    /// Its description.
    pub classification: String,
    /// Kinematically indeterminate motions n − r.
    pub n_motions: usize,
    /// Self-stress states m − r.
    pub n_self_stresses: usize,
    /// No motion and no self-stress.
    pub exactly_constrained: bool,
    /// Relative rank tolerance.
    pub rank_tol: f64,
    /// Absolute rank threshold.
    pub rank_threshold: f64,
    /// s_r / s_(r+1).
    pub rank_gap: Option<f64>,
    /// Singular values, descending.
    pub singular_values: Vec<f64>,
    /// Generalised coordinates.
    pub generalised: Vec<String>,
    /// The self-stress states, each as its largest entries (`element mode (name) value`).
    pub self_stresses: Vec<Vec<String>>,
    /// Verified repair advice.
    pub advice: Vec<ViewAdvice>,
}

/// Advice for one motion or self-stress state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewAdvice {
    /// `motion` or `self_stress`.
    pub kind: String,
    /// The state (0-based).
    pub state: usize,
    /// Verified suggestions, each with the counts after the change.
    pub suggestions: Vec<String>,
}

/// The kinematic analysis to summarise.
pub struct Classification<'a> {
    /// The analysis.
    pub analysis: &'a ConstraintAnalysis,
    /// Its verified advice.
    pub advice: &'a [StateAdvice],
    /// Names of the generalised coordinates.
    pub generalised: &'a [String],
    /// The relative rank tolerance used.
    pub rank_tol: f64,
    /// The motions and self-stresses as twists and wrenches, when computed.
    pub screws: Option<&'a flexmbd_core::kinematics::screw::ScrewAnalysis>,
    /// The verified wires that remove each motion (drawn with the motion).
    pub wires: &'a [flexmbd_core::kinematics::advice::WireAdvice],
}

/// The results to show.
pub enum ViewResults<'a> {
    /// The reference geometry with the motions and self-stresses of the classification.
    Check,
    /// Every load step of a static run.
    Static(&'a StaticSolution),
    /// Modes about a static state.
    Modes {
        /// The state linearised about.
        step: &'a StepResult,
        /// Its index in the static solution.
        index: usize,
        /// The modes.
        modal: &'a Modal,
    },
}
