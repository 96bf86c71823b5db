//! [`ModelSpec`]: one complete, editable model document, whatever the file format.
//!
//! ```text
//! model file ─ reader (TOML: model_toml; SPACAR .dat: spacar) ─ ModelSpec ─ build ─ ModelFile
//!                                                                  │           (Model + settings)
//!                                                  edit by name ───┤
//!                                                                  └─ write (TOML)
//! ```
//!
//! A spec holds everything a TOML model file can state (docs/model-format.md, docs/statics.md,
//! docs/simulation.md): nodes, elements (truss, beam with material, section and segments,
//! hinge, rigid body), materials, sections, supports, inputs, loads and prescribed values with
//! their histories, point masses, inertia tensors, initial velocities, gravity, spin, the
//! `[static]` settings and the `[simulate]` settings. Values are kept as written (a beam's
//! `segments` is not expanded, a material's `nu` not turned into G): [`ModelSpec::build`]
//! validates and compiles them, the one build path of every reader (module `build`).
//!
//! Every item keeps where it was written ([`Src`], file line and column, for errors naming
//! file, line and item); [`Src`] is not serialised and compares equal to every other, so two
//! specs that differ only in where their items were written compare equal.
//!
//! Items are addressed by name for editing (module `edit`: `add_node`, `remove_element`,
//! `set("sections.sheet.t", 0.2e-3)`, …). The serialised form (serde, e.g. JSON) uses the
//! keys of the TOML format (`id`, `EA`, `E`, `shape`, …), so an edit path reads like the file.

mod build;
mod edit;
mod props;
pub mod settings;

pub use build::{SpecError, SpecErrorKind};
pub use edit::EditError;
pub use settings::{ModelFile, Settings, SimulateSettings};

use flexmbd_core::model::Dof;
use flexmbd_core::simulation::TimeFunction;
use indexmap::IndexMap;
use serde::{Deserialize, Serialize};

/// A place in a model file: 1-based line and column.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pos {
    /// Line, 1-based.
    pub line: usize,
    /// Column, 1-based.
    pub column: usize,
}

/// Where an item was written, for error messages: the item's place and the places of some of
/// its keys (an error about a key points at its line). Not serialised, and equal to every other
/// `Src`: it is not part of the model.
#[derive(Clone, Debug, Default)]
pub struct Src {
    /// The item's place (its line, or the line of its table's header).
    pub at: Option<Pos>,
    /// Places of keys of the item (`segments`, `steps`, …).
    pub keys: Vec<(String, Pos)>,
}

impl PartialEq for Src {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl Src {
    /// An item on `line` (column 1); line-oriented formats such as SPACAR `.dat`.
    pub fn line(line: usize) -> Self {
        Self {
            at: Some(Pos { line, column: 1 }),
            keys: Vec::new(),
        }
    }
    /// An item on `line`, if known.
    pub fn maybe_line(line: Option<usize>) -> Self {
        line.map_or_else(Self::default, Self::line)
    }
    /// The place of `key`, or of the item when the key's is not known.
    pub fn key(&self, key: &str) -> Option<Pos> {
        self.keys
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, p)| *p)
            .or(self.at)
    }
    /// The item's line, if known.
    pub fn line_number(&self) -> Option<usize> {
        self.at.map(|p| p.line)
    }
}

/// Where a node is.
#[derive(Clone, Debug, PartialEq)]
pub enum NodePlace {
    /// Own position [m]; `rot` asks for rotation coordinates.
    Position {
        /// Position.
        x: [f64; 3],
        /// Rotation coordinates asked for.
        rot: bool,
    },
    /// At the position of a host node (defined before it), with its own rotation.
    At(String),
}

/// A node (`[nodes]`). Serialised as `{ id, x, y, z, rot }` or `{ id, at }`, so that the path
/// `nodes.a.x` is the node's x coordinate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(into = "NodeRepr", try_from = "NodeRepr")]
pub struct NodeSpec {
    /// Name.
    pub name: String,
    /// Position or host.
    pub place: NodePlace,
    /// Comment written after the node.
    pub comment: Option<String>,
    /// Where it was written.
    pub src: Src,
}

/// The serialised form of a [`NodeSpec`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct NodeRepr {
    id: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    x: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    y: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    z: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    rot: Option<bool>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    at: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    comment: Option<String>,
}

impl From<NodeSpec> for NodeRepr {
    fn from(n: NodeSpec) -> Self {
        let (x, rot, at) = match n.place {
            NodePlace::Position { x, rot } => (Some(x), Some(rot), None),
            NodePlace::At(h) => (None, None, Some(h)),
        };
        NodeRepr {
            id: n.name,
            x: x.map(|x| x[0]),
            y: x.map(|x| x[1]),
            z: x.map(|x| x[2]),
            rot,
            at,
            comment: n.comment,
        }
    }
}

impl TryFrom<NodeRepr> for NodeSpec {
    type Error = String;
    fn try_from(r: NodeRepr) -> Result<Self, String> {
        let place = match (r.at, r.x, r.y, r.z, r.rot) {
            (Some(h), None, None, None, None | Some(true)) => NodePlace::At(h),
            (Some(_), ..) => {
                return Err(format!(
                    "node `{}`: give either `x`, `y`, `z` (own position) or `at` (a host node)",
                    r.id
                ))
            }
            (None, x, y, z, rot) => NodePlace::Position {
                x: [x.unwrap_or(0.0), y.unwrap_or(0.0), z.unwrap_or(0.0)],
                rot: rot.unwrap_or(false),
            },
        };
        Ok(NodeSpec {
            name: r.id,
            place,
            comment: r.comment,
            src: Src::default(),
        })
    }
}

/// A beam's data (`[[beam]]`): orientation, coupling constant, constants from a `section` and
/// a `material` or given directly, modes kept rigid in statics, and the number of segments.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BeamSpec {
    /// Orientation vector (local y); `None` for SPACAR's default rule.
    pub orient: Option<[f64; 3]>,
    /// Torsion–elongation coupling c_t [m²].
    pub ct: Option<f64>,
    /// Modes rigid in statics although they have stiffness (TOML `fixed`).
    pub fixed: Vec<i64>,
    /// Section name (with `material`).
    pub section: Option<String>,
    /// Material name (with `section`).
    pub material: Option<String>,
    /// Split into this many elements (`id:1`, … with intermediate nodes `id:1`, …).
    pub segments: Option<usize>,
    /// EA [N], given directly.
    #[serde(rename = "EA")]
    pub ea: Option<f64>,
    /// GJ [N·m²], given directly.
    #[serde(rename = "GJ")]
    pub gj: Option<f64>,
    /// EIy [N·m²], given directly.
    #[serde(rename = "EIy")]
    pub eiy: Option<f64>,
    /// EIz [N·m²], given directly.
    #[serde(rename = "EIz")]
    pub eiz: Option<f64>,
    /// Mass per length ρA [kg/m] of constants given directly.
    pub rho_a: Option<f64>,
    /// Shear flexibilities EIy/(kGA), EIz/(kGA) [m²] of constants given directly (SPACAR
    /// `ESTIFF` columns 5–6; the TOML format cannot state them).
    pub shear: Option<[f64; 2]>,
    /// Rotary inertia per length ρ(Iy + Iz), ρIy, ρIz [kg·m] of constants given directly
    /// (SPACAR `EM` columns 2–4; the TOML format cannot state them).
    pub rho_i: Option<[f64; 3]>,
}

impl BeamSpec {
    /// Constants given directly (`EA`, `GJ`, `EIy`, `EIz`, a missing one 0) with the mass per
    /// length `rho_a`.
    pub fn direct(ea: f64, gj: f64, eiy: f64, eiz: f64, rho_a: f64) -> Self {
        Self {
            ea: Some(ea),
            gj: Some(gj),
            eiy: Some(eiy),
            eiz: Some(eiz),
            rho_a: Some(rho_a),
            ..Default::default()
        }
    }
}

/// An element's type and data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "lowercase")]
// a document's element: the beam's data inline keeps it plain to read, bind and edit
#[allow(clippy::large_enum_variant)]
pub enum ElementKind {
    /// `[[truss]]`.
    Truss {
        /// EA [N].
        #[serde(default, rename = "EA")]
        ea: f64,
    },
    /// `[[beam]]`.
    Beam(BeamSpec),
    /// `[[hinge]]`.
    Hinge {
        /// Axis (need not be unit).
        axis: [f64; 3],
        /// Torsion spring k [N·m/rad] on mode 1.
        #[serde(default)]
        k: f64,
    },
    /// `[[rigid]]`.
    Rigid,
}

impl ElementKind {
    /// The TOML table name (`truss`, `beam`, `hinge`, `rigid`).
    pub fn table(&self) -> &'static str {
        match self {
            Self::Truss { .. } => "truss",
            Self::Beam(_) => "beam",
            Self::Hinge { .. } => "hinge",
            Self::Rigid => "rigid",
        }
    }
}

/// An element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ElementEntrySpec {
    /// Name (id).
    #[serde(rename = "id")]
    pub name: String,
    /// Node names.
    pub nodes: Vec<String>,
    /// Type and data.
    #[serde(flatten)]
    pub kind: ElementKind,
    /// Free (released) modes, 1-based.
    #[serde(default)]
    pub free: Vec<i64>,
    /// Input modes (generalised deformations), 1-based.
    #[serde(default)]
    pub input: Vec<i64>,
    /// Material damping: the retardation time τ [s] (Kelvin–Voigt, σ = S (e + τ ė) in a time
    /// simulation); over the `material`'s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Comment lines written above the element.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

impl ElementEntrySpec {
    /// An element without free or input modes.
    pub fn new(name: &str, nodes: &[&str], kind: ElementKind) -> Self {
        Self {
            name: name.into(),
            nodes: nodes.iter().map(|n| n.to_string()).collect(),
            kind,
            free: Vec::new(),
            input: Vec::new(),
            damping: None,
            comments: Vec::new(),
            src: Src::default(),
        }
    }
    /// The beam data, for a beam.
    pub fn beam(&self) -> Option<&BeamSpec> {
        match &self.kind {
            ElementKind::Beam(b) => Some(b),
            _ => None,
        }
    }
}

/// A material (`[[material]]`): E and G or ν, density.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Name (id).
    #[serde(rename = "id")]
    pub name: String,
    /// Young's modulus E [Pa].
    #[serde(rename = "E")]
    pub e: f64,
    /// Shear modulus G [Pa] (or `nu`).
    #[serde(default, rename = "G")]
    pub g: Option<f64>,
    /// Poisson's ratio ν (or `G`).
    #[serde(default)]
    pub nu: Option<f64>,
    /// Density ρ [kg/m³].
    #[serde(default)]
    pub rho: f64,
    /// Material damping: the retardation time τ [s] of the beams made of it (Kelvin–Voigt,
    /// σ = S (e + τ ė) in a time simulation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// A section's shape and dimensions [m], or its properties given directly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum ShapeSpec {
    /// Solid rectangle: width `w` along local y, thickness `t` along local z.
    Rectangle {
        /// Width.
        w: f64,
        /// Thickness.
        t: f64,
    },
    /// Solid circle of diameter `d`.
    Circle {
        /// Diameter.
        d: f64,
    },
    /// Circular tube.
    Tube {
        /// Outer diameter.
        d_out: f64,
        /// Inner diameter.
        d_in: f64,
    },
    /// Properties given directly.
    General {
        /// Area A [m²].
        #[serde(rename = "A")]
        a: f64,
        /// Iy [m⁴].
        #[serde(rename = "Iy")]
        iy: f64,
        /// Iz [m⁴].
        #[serde(rename = "Iz")]
        iz: f64,
        /// Torsion constant J [m⁴].
        #[serde(rename = "J")]
        j: f64,
        /// Shear factor (0: shear-rigid); `None` is 0.
        #[serde(default)]
        k: Option<f64>,
    },
}

/// A cross-section (`[[section]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SectionSpec {
    /// Name (id).
    #[serde(rename = "id")]
    pub name: String,
    /// Shape and dimensions.
    #[serde(flatten)]
    pub shape: ShapeSpec,
    /// Include shear flexibility (Timoshenko); default true.
    #[serde(default = "yes")]
    pub shear: bool,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

fn yes() -> bool {
    true
}

/// A `[fix]` or `[inputs]` entry.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DofEntry {
    /// Node name.
    pub node: String,
    /// Degrees of freedom; `None` = all the node has (`"all"`).
    pub dofs: Option<Vec<Dof>>,
    /// Comment written after the entry.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub comment: Option<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

impl DofEntry {
    /// An entry for `dofs` of `node` (`None`: all).
    pub fn new(node: &str, dofs: Option<&[Dof]>) -> Self {
        Self {
            node: node.into(),
            dofs: dofs.map(<[Dof]>::to_vec),
            comment: None,
            src: Src::default(),
        }
    }
}

/// A dead nodal load at load factor 1 (`[[load]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadEntry {
    /// Node name.
    pub node: String,
    /// Force [N], global axes.
    #[serde(default)]
    pub force: [f64; 3],
    /// Moment [N·m], global axes.
    #[serde(default)]
    pub moment: [f64; 3],
    /// φ(t) of a time simulation; `None` is constant.
    #[serde(default)]
    pub history: Option<TimeFunction>,
    /// Comment lines written above the entry.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// A point mass (`[[mass]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MassEntry {
    /// Node name.
    pub node: String,
    /// Mass [kg].
    pub m: f64,
    /// Comment lines written above the entry.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// An inertia tensor about a rotational node (`[[inertia]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InertiaEntry {
    /// Node name.
    pub node: String,
    /// [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] [kg·m²], global axes in the reference orientation.
    #[serde(rename = "I")]
    pub i: [f64; 6],
    /// Comment lines written above the entry.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// What a prescribed value applies to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PrescribeTarget {
    /// A nodal coordinate: displacement [m] or rotation angle φ [rad], λ_i = sin(φ/2).
    Coordinate {
        /// Node name.
        node: String,
        /// Degree of freedom.
        dof: Dof,
    },
    /// A deformation mode (1-based) of an element.
    Deformation {
        /// Element name.
        element: String,
        /// Mode, 1-based.
        mode: usize,
    },
}

/// A prescribed final value of an input (`[[prescribe]]`, a stroke).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PrescribeEntry {
    /// Coordinate or deformation.
    #[serde(flatten)]
    pub target: PrescribeTarget,
    /// Final value, reached at load factor 1.
    pub value: f64,
    /// φ(t) of a time simulation; `None` is constant.
    #[serde(default)]
    pub history: Option<TimeFunction>,
    /// Comment lines written above the entry.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// An initial velocity of a node (`[[velocity]]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocityEntry {
    /// Node name.
    pub node: String,
    /// Velocity [m/s].
    #[serde(default)]
    pub v: [f64; 3],
    /// Angular velocity [rad/s] (a rotational node).
    #[serde(default)]
    pub omega: [f64; 3],
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// A motion a body should have (`[[freedom]]`; docs/kinematic-analysis.md "Intended
/// freedom"): exactly one of `translation` and `rotation`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreedomEntry {
    /// The body: the name of one of its elements (a `[[rigid]]`) or nodes.
    pub body: String,
    /// A translation along this direction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translation: Option<[f64; 3]>,
    /// A rotation about an axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<RotationEntry>,
    /// Comment lines written above the entry.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// The axis of an intended rotation (`rotation = { point, axis, pitch }`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationEntry {
    /// A point of the axis [m].
    pub point: [f64; 3],
    /// The axis direction.
    pub axis: [f64; 3],
    /// Pitch [m/rad] (0: a pure rotation).
    #[serde(default)]
    pub pitch: f64,
}

/// How a static path is followed (`[static] path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PathSpec {
    /// Load steps with halving.
    LoadSteps,
    /// Arc-length path following.
    ArcLength,
}

/// Settings of a static analysis and the fields of the whole model (`[static]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StaticSpec {
    /// Load steps.
    pub steps: Option<usize>,
    /// Newton iterations per step.
    pub max_iterations: Option<usize>,
    /// Relative residual tolerance.
    pub tol_force: Option<f64>,
    /// Relative increment tolerance.
    pub tol_disp: Option<f64>,
    /// Gravitational acceleration [m/s²].
    pub gravity: Option<[f64; 3]>,
    /// Angular velocity of a steady rotation [rad/s].
    pub spin: Option<[f64; 3]>,
    /// A point of the spin axis [m] (default the origin).
    pub spin_point: Option<[f64; 3]>,
    /// Nodes whose compliance is reported at every step.
    pub compliance: Vec<String>,
    /// Number of buckling multipliers reported at every step.
    pub buckling: usize,
    /// Backtracking line search in Newton.
    pub line_search: bool,
    /// The smallest eigenvalues of the tangent at every step of load steps and strokes.
    #[serde(default)]
    pub tangent_eigenvalues: bool,
    /// How the path is followed.
    pub path: Option<PathSpec>,
    /// Comment lines written above the section.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

impl StaticSpec {
    /// True when it states nothing (no `[static]` table is written).
    pub fn is_empty(&self) -> bool {
        *self
            == StaticSpec {
                comments: self.comments.clone(),
                ..Default::default()
            }
    }
}

/// Fixed steps or step control (`[simulate] step`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StepSpec {
    /// Step control.
    Adaptive,
    /// Fixed steps.
    Fixed,
}

/// The initial state of a time simulation (`[simulate] start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StartSpec {
    /// The reference configuration.
    Reference,
    /// The static equilibrium at t = 0.
    Static,
}

/// Settings of a time simulation (`[simulate]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimulateSpec {
    /// End time [s].
    pub t_end: Option<f64>,
    /// (First) step size [s].
    pub dt: Option<f64>,
    /// Fixed steps or step control.
    pub step: Option<StepSpec>,
    /// Smallest step [s].
    pub dt_min: Option<f64>,
    /// Largest step [s].
    pub dt_max: Option<f64>,
    /// ρ∞ of generalised-α.
    pub rho_inf: Option<f64>,
    /// Absolute and relative tolerance.
    pub tolerance: Option<[f64; 2]>,
    /// Output interval [s].
    pub output_step: Option<f64>,
    /// Newton iterations per step.
    pub max_iterations: Option<usize>,
    /// Rayleigh α, β.
    pub rayleigh: Option<[f64; 2]>,
    /// Initial state.
    pub start: Option<StartSpec>,
    /// Load steps of the static start.
    pub static_steps: Option<usize>,
    /// φ(t) of gravity.
    pub gravity_history: Option<TimeFunction>,
    /// Comment lines written above the section.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub comments: Vec<String>,
    /// Where it was written.
    #[serde(skip)]
    pub src: Src,
}

/// A model document: everything a model file states. See the module documentation.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelSpec {
    /// Model name.
    pub name: String,
    /// Free text (`[model] description`).
    pub description: Option<String>,
    /// Comment lines at the top of the file.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub header: Vec<String>,
    /// The parameters of the file (`[parameters]`, docs/model-format.md), evaluated, in file
    /// order; empty when it has none. The values of the spec are evaluated with them: a spec
    /// is one member of a parametric model, and changing a parameter here changes no value
    /// (read the file again with the new value: `model_toml::parse_spec_with`).
    #[serde(skip_serializing_if = "IndexMap::is_empty")]
    pub parameters: IndexMap<String, f64>,
    /// Nodes, in order; a host before the nodes placed `at` it.
    pub nodes: Vec<NodeSpec>,
    /// Elements, in order.
    pub elements: Vec<ElementEntrySpec>,
    /// Materials.
    pub materials: Vec<MaterialSpec>,
    /// Cross-sections.
    pub sections: Vec<SectionSpec>,
    /// Supports (`[fix]`).
    pub fix: Vec<DofEntry>,
    /// Generalised coordinates (`[inputs]`).
    pub inputs: Vec<DofEntry>,
    /// Generalised coordinates of the kinematic check that are unknowns in statics (SPACAR's
    /// dynamic degrees of freedom `DYNX`): inputs for [`ModelSpec::build`], left free by
    /// [`ModelSpec::build_static`]; written into `[inputs]`.
    pub dynamic_inputs: Vec<DofEntry>,
    /// Dead loads.
    pub loads: Vec<LoadEntry>,
    /// Point masses.
    pub masses: Vec<MassEntry>,
    /// Inertia tensors of rotational nodes.
    pub inertias: Vec<InertiaEntry>,
    /// Prescribed input values (strokes).
    pub prescribed: Vec<PrescribeEntry>,
    /// Initial velocities.
    pub velocities: Vec<VelocityEntry>,
    /// The intended freedom (`[[freedom]]`), compared by the kinematic check.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub freedoms: Vec<FreedomEntry>,
    /// `[static]`.
    #[serde(rename = "static")]
    pub statics: StaticSpec,
    /// `[simulate]`, when the file has one.
    pub simulate: Option<SimulateSpec>,
    /// Comment lines at the end of the file.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub footer: Vec<String>,
}

impl ModelSpec {
    /// An empty model named `name`.
    pub fn new(name: &str) -> Self {
        Self {
            name: name.into(),
            ..Default::default()
        }
    }

    /// The spec without its comments (header, footer and the comments of every item): what a
    /// file written from it and read back holds.
    pub fn without_comments(&self) -> Self {
        let mut s = self.clone();
        s.header.clear();
        s.footer.clear();
        s.statics.comments.clear();
        if let Some(sim) = &mut s.simulate {
            sim.comments.clear();
        }
        s.nodes.iter_mut().for_each(|n| n.comment = None);
        s.elements.iter_mut().for_each(|e| e.comments.clear());
        for d in s
            .fix
            .iter_mut()
            .chain(&mut s.inputs)
            .chain(&mut s.dynamic_inputs)
        {
            d.comment = None;
        }
        s.loads.iter_mut().for_each(|l| l.comments.clear());
        s.masses.iter_mut().for_each(|l| l.comments.clear());
        s.inertias.iter_mut().for_each(|l| l.comments.clear());
        s.prescribed.iter_mut().for_each(|l| l.comments.clear());
        s.freedoms.iter_mut().for_each(|l| l.comments.clear());
        s
    }
}

#[cfg(test)]
mod tests;
