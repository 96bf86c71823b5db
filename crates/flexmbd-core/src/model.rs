//! The model: nodes, elements and the partition of x and e (paper eq. (4)).
//!
//! A [`Model`] is built once by [`ModelBuilder::build`], which validates everything a user can
//! get wrong and reports it as a [`ModelError`] naming the item. It is never mutated by an
//! analysis; analyses that try a different partition (repair advice) copy the [`Partition`].
//!
//! Coordinates x: every node has its position (x, y, z); a node has rotation coordinates only
//! when an element uses them (beam, hinge, rigid-body reference node) or the model file asks for
//! them. Rotations are four Euler parameters (λ0, λ1, λ2, λ3), λ0 the scalar part, as in SPACAR
//! (see docs/rotations.md). Fixing or prescribing the rotation component "rx" of a node acts on
//! λ1 ("ry" on λ2, "rz" on λ3); λ0 is always dependent, fixed by the normalisation λᵀλ = 1.

use crate::elements::{Beam, Element, ElementKind, FrameError, Hinge, NodeId, Rigid, Truss};
use crate::math::norm;
use std::collections::HashMap;

/// Partition letter of a nodal coordinate (paper eq. (4)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CoordKind {
    /// x^o: fixed (support).
    Fixed,
    /// x^c: dependent (calculable). The default.
    Free,
    /// x^m: independent, a generalised coordinate.
    Input,
}

/// Partition letter of a deformation parameter (paper eq. (4)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum DefKind {
    /// e^o: prescribed zero (rigid). The default.
    Fixed,
    /// e^c: dependent, free to follow.
    Free,
    /// e^m: independent, a generalised coordinate.
    Input,
}

/// A nodal degree of freedom as named in model files.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Dof {
    /// Translation along global x.
    X,
    /// Translation along global y.
    Y,
    /// Translation along global z.
    Z,
    /// Rotation about global x (Euler parameter λ1).
    Rx,
    /// Rotation about global y (Euler parameter λ2).
    Ry,
    /// Rotation about global z (Euler parameter λ3).
    Rz,
}

impl Dof {
    /// All six, in order.
    pub const ALL: [Dof; 6] = [Dof::X, Dof::Y, Dof::Z, Dof::Rx, Dof::Ry, Dof::Rz];
    /// Name as in model files.
    pub fn name(self) -> &'static str {
        ["x", "y", "z", "rx", "ry", "rz"][self.index()]
    }
    /// 0..6.
    pub fn index(self) -> usize {
        self as usize
    }
    /// Parse a model-file name.
    pub fn parse(s: &str) -> Option<Dof> {
        Dof::ALL.into_iter().find(|d| d.name() == s)
    }
    /// True for rx, ry, rz.
    pub fn is_rotation(self) -> bool {
        self.index() >= 3
    }
}

/// A node of the compiled model.
#[derive(Clone, Debug)]
pub struct Node {
    /// Identifier from the model file.
    pub name: String,
    /// Reference position [m].
    pub x0: [f64; 3],
    /// For a node placed `at` another: the host whose position it shares (it has only its own
    /// rotation, e.g. the second rotation node of a hinge).
    pub host: Option<NodeId>,
    /// Index of its x coordinate in the global x (y, z follow); the host's for a hosted node.
    pub ix_pos: usize,
    /// Index of λ0 in x (λ1..λ3 follow), if the node carries rotation coordinates.
    pub ix_rot: Option<usize>,
}

impl Node {
    /// Whether the node carries rotation coordinates (Euler parameters).
    pub fn rot(&self) -> bool {
        self.ix_rot.is_some()
    }
    /// Index in x of a degree of freedom (rotations: λ1..λ3), if the node has it.
    pub fn x_index(&self, dof: Dof) -> Option<usize> {
        match dof.index() {
            i @ 0..3 => Some(self.ix_pos + i),
            i => self.ix_rot.map(|r| r + i - 2),
        }
    }
    /// The coordinates this node owns in x (a hosted node owns only its Euler parameters).
    pub fn own_range(&self) -> std::ops::Range<usize> {
        let start = if self.host.is_some() {
            self.ix_rot.expect("hosted nodes rotate")
        } else {
            self.ix_pos
        };
        let end = self.ix_rot.map_or(self.ix_pos + 3, |r| r + 4);
        start..end
    }
}

/// An element of the compiled model with its place in x and e.
#[derive(Clone, Debug)]
pub struct ElementEntry {
    /// Identifier from the model file.
    pub name: String,
    /// The element.
    pub element: Element,
    /// Index of its first deformation in e (SPACAR `le`).
    pub ie: usize,
    /// Global index in x of each local coordinate (SPACAR `lnp`).
    pub xmap: Vec<usize>,
}

/// Partition of x and e into fixed, dependent and independent parts.
#[derive(Clone, Debug, PartialEq)]
pub struct Partition {
    /// Kind of every nodal coordinate (length nx).
    pub x: Vec<CoordKind>,
    /// Kind of every element deformation (length ne).
    pub e: Vec<DefKind>,
}

/// The compiled, validated model.
#[derive(Clone, Debug)]
pub struct Model {
    /// Model name.
    pub name: String,
    /// Nodes.
    pub nodes: Vec<Node>,
    /// Elements.
    pub elements: Vec<ElementEntry>,
    /// Number of nodal coordinates.
    pub nx: usize,
    /// Number of element deformations (without the implicit Euler normalisations).
    pub ne: usize,
    /// Partition of x and e.
    pub partition: Partition,
    /// Deformations the user declared rigid explicitly (`fixed`), for statics: there every
    /// deformation with finite stiffness is flexible unless listed here (length ne).
    pub explicit_rigid: Vec<bool>,
    /// Loads, masses and prescribed inputs for statics and dynamics.
    pub loads: Loads,
}

/// A force and moment on a node, in global axes [N, N·m]. Dead loads (constant direction).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct NodalLoad {
    /// Node index.
    pub node: NodeId,
    /// Force [N].
    pub force: [f64; 3],
    /// Moment [N·m]; needs a rotational node.
    pub moment: [f64; 3],
}

/// What a prescribed value acts on.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Target {
    /// A nodal coordinate (index in x): translations as displacement [m] from the reference,
    /// rotations rx/ry/rz as an angle φ [rad] with λ_i = sin(φ/2).
    Coordinate(usize),
    /// A deformation (index in e), its value [m or rad].
    Deformation(usize),
}

/// A prescribed input value, reached at the end of the load steps.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Prescribed {
    /// What.
    pub target: Target,
    /// Final value.
    pub value: f64,
}

/// Loads, masses and prescribed motions.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Loads {
    /// Nodal forces and moments (reached at load factor 1).
    pub nodal: Vec<NodalLoad>,
    /// Gravitational acceleration [m/s²].
    pub gravity: [f64; 3],
    /// Steady rotation of the whole model (centrifugal loads, analysis in the co-rotating
    /// frame; [`Spin`]).
    pub spin: Option<Spin>,
    /// Point masses at nodes [kg].
    pub point_masses: Vec<(NodeId, f64)>,
    /// Inertia tensors at rotational nodes [kg·m²], global axes in the reference orientation.
    pub inertias: Vec<(NodeId, [[f64; 3]; 3])>,
    /// Prescribed inputs.
    pub prescribed: Vec<Prescribed>,
}

/// A steady rotation of the whole model (a rotor, a rotating blade, a spinning stage): angular
/// velocity `omega` [rad/s] (global axes) about the axis through `point` [m]; the analysis is in
/// the co-rotating frame.
///
/// A static state is an equilibrium under the centrifugal (inertial) loads (validation.md F03:
/// "steady rotation (or the static centrifugal load) first, then a linearised modal analysis
/// about it, including the geometric stiffness"): the field a(r) = Ω² P (r − a), P = I − n nᵀ,
/// on the translational mass and the moment −Ω × (I Ω) on the rotary inertia
/// ([`crate::elements::AccelerationField`], consistent with each element's mass model). The loads
/// are computed on the reference configuration and applied as dead loads that grow with the
/// load factor like every other load (Ω² ramps linearly); they do not follow the deflection:
/// the classical small-deflection pre-stress analysis of rotating beams (centrifugal stiffening
/// through the axial force N(x) = ρAΩ²(L² − x²)/2 of a radial beam). The linearised dynamics add
/// the centrifugal softening −Ω² M_P ([`crate::assembly::mass::softening_matrix`]: the
/// translational mass with the projection P) and leave out the Coriolis (gyroscopic) coupling
/// 2Ω × ṙ: out-of-plane (flapwise) motion is exact, in-plane (lead-lag) motion follows
/// ω² = ω²_elastic − Ω² without the coupling to axial motion (docs/dynamics.md).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Spin {
    /// Angular velocity vector Ω [rad/s].
    pub omega: [f64; 3],
    /// A point on the rotation axis [m].
    pub point: [f64; 3],
}

impl Spin {
    /// Ω² P = Ω² I − Ω Ωᵀ: the centrifugal acceleration of a point at r is Ω² P (r − a).
    pub fn projector(&self) -> [[f64; 3]; 3] {
        let w = self.omega;
        let w2 = crate::math::dot(w, w);
        std::array::from_fn(|i| {
            std::array::from_fn(|k| if i == k { w2 } else { 0.0 } - w[i] * w[k])
        })
    }
}

impl Loads {
    /// The acceleration field of gravity and of the steady rotation together (their sum; the
    /// centrifugal field of the spin), `None` when there is neither.
    pub fn acceleration_field(&self) -> Option<crate::elements::AccelerationField> {
        let field = crate::elements::AccelerationField {
            w: self.spin.map_or([[0.0; 3]; 3], |s| s.projector()),
            point: self.spin.map_or([0.0; 3], |s| s.point),
            uniform: self.gravity,
            omega: self.spin.map_or([0.0; 3], |s| s.omega),
        };
        (!field.is_zero()).then_some(field)
    }
}

impl Model {
    /// The reference configuration x⁰: node positions and identity rotations.
    pub fn x0(&self) -> Vec<f64> {
        let mut x = vec![0.0; self.nx];
        for n in &self.nodes {
            x[n.ix_pos..n.ix_pos + 3].copy_from_slice(&n.x0);
            if let Some(r) = n.ix_rot {
                x[r] = 1.0;
            }
        }
        x
    }
    /// Node names, indexed by NodeId.
    pub fn node_names(&self) -> Vec<String> {
        self.nodes.iter().map(|n| n.name.clone()).collect()
    }
    /// Look up a node by name.
    pub fn node_id(&self, name: &str) -> Option<NodeId> {
        self.nodes.iter().position(|n| n.name == name)
    }
    /// The element and mode (0-based) of global deformation index `k`.
    pub fn deformation_owner(&self, k: usize) -> (usize, usize) {
        let el = self.elements.partition_point(|e| e.ie <= k) - 1;
        (el, k - self.elements[el].ie)
    }
    /// The node and coordinate label of global coordinate index `i` ("x", "y", "z",
    /// "lambda0".."lambda3"); `None` for i ≥ nx.
    pub fn coordinate_owner(&self, i: usize) -> Option<(NodeId, &'static str)> {
        let n = self.nodes.iter().position(|n| n.own_range().contains(&i))?;
        let labels = ["x", "y", "z", "lambda0", "lambda1", "lambda2", "lambda3"];
        let node = &self.nodes[n];
        Some((
            n,
            node.ix_rot
                .filter(|&r| i >= r)
                .map_or(labels[i - node.ix_pos], |r| labels[3 + i - r]),
        ))
    }
    /// Number of rotational nodes (each adds one implicit Euler normalisation constraint).
    pub fn n_rotational_nodes(&self) -> usize {
        self.nodes.iter().filter(|n| n.rot()).count()
    }
}

/// What a model-building error refers to, so that a file reader can point at its line.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Item {
    /// A node definition.
    Node(String),
    /// An element definition.
    Element(String),
    /// The fix entry of a node.
    Fix(String),
    /// The input entry of a node.
    Input(String),
    /// A load on a node.
    Load(String),
    /// A point mass on a node.
    Mass(String),
    /// Model-wide data (gravity).
    Model,
}

/// Invalid model data. Every variant names the item it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// Two nodes with one name.
    #[error("node `{node}` is defined twice")]
    DuplicateNode {
        /// Node name.
        node: String,
    },
    /// Two elements with one name.
    #[error("element `{element}` is defined twice")]
    DuplicateElement {
        /// Element name.
        element: String,
    },
    /// An element refers to a node that does not exist.
    #[error("element `{element}`: node `{node}` is not defined")]
    UnknownNode {
        /// Element name.
        element: String,
        /// Node name.
        node: String,
    },
    /// An element of the wrong type (or none) for the operation.
    #[error("`{element}` is not a {kind} of this model")]
    NotA {
        /// Element name.
        element: String,
        /// The type wanted.
        kind: &'static str,
    },
    /// A moment on a node without rotation coordinates.
    #[error("load on node `{node}`: a moment needs a rotational node (a beam, hinge or rigid-body reference node, or a node given rotation coordinates)")]
    MomentWithoutRotation {
        /// Node name.
        node: String,
    },
    /// A node is placed `at` a node that is not defined before it.
    #[error("node `{node}`: `at` names node `{host}`, which is not defined before it")]
    UnknownHost {
        /// Node name.
        node: String,
        /// The host named.
        host: String,
    },
    /// A fix or input entry refers to a node that does not exist.
    #[error("{what} entry `{node}`: node `{node}` is not defined")]
    UnknownNodeInEntry {
        /// "fix" or "inputs".
        what: &'static str,
        /// Node name.
        node: String,
    },
    /// Wrong number of nodes for the element type.
    #[error("element `{element}`: a {kind} needs {expected} nodes, found {found}")]
    NodeCount {
        /// Element name.
        element: String,
        /// Element type.
        kind: &'static str,
        /// What is needed, e.g. "2" or "at least 2".
        expected: &'static str,
        /// How many were given.
        found: usize,
    },
    /// The same node appears twice in one element.
    #[error("element `{element}`: node `{node}` appears twice")]
    RepeatedNode {
        /// Element name.
        element: String,
        /// Node name.
        node: String,
    },
    /// The element's end nodes coincide.
    #[error("element `{element}` has zero length ({l0:.3e} m between its nodes)")]
    ZeroLength {
        /// Element name.
        element: String,
        /// Distance between the nodes.
        l0: f64,
    },
    /// The local frame cannot be built.
    #[error("element `{element}`: {source}")]
    Frame {
        /// Element name.
        element: String,
        /// Why.
        source: FrameError,
    },
    /// A deformation mode number outside 1..=ne.
    #[error("element `{element}`: deformation mode {mode} does not exist (a {kind} has modes 1 to {ne})")]
    BadMode {
        /// Element name.
        element: String,
        /// Element type.
        kind: &'static str,
        /// Mode as given (1-based).
        mode: i64,
        /// Number of modes.
        ne: usize,
    },
    /// A mode is listed both as free and as input.
    #[error("element `{element}`: deformation mode {mode} is listed both as free and as input")]
    ModeConflict {
        /// Element name.
        element: String,
        /// Mode (1-based).
        mode: usize,
    },
    /// A rotation dof on a node that has no rotation coordinates.
    #[error("{what} entry `{node}`: `{dof}` is a rotation, but no beam, hinge or rigid body uses the rotation of node `{node}` (give the node rotation coordinates)")]
    NoRotation {
        /// "fix" or "inputs".
        what: &'static str,
        /// Node name.
        node: String,
        /// The dof.
        dof: &'static str,
    },
    /// A dof both fixed and input.
    #[error("node `{node}`: `{dof}` is both fixed and an input")]
    FixAndInput {
        /// Node name.
        node: String,
        /// The dof.
        dof: &'static str,
    },
    /// A non-finite number or non-positive parameter.
    #[error("{item}: `{field}` must be {requirement}, found {value}")]
    BadValue {
        /// The node or element.
        item: Item,
        /// Field name.
        field: &'static str,
        /// e.g. "finite".
        requirement: &'static str,
        /// The value.
        value: f64,
    },
}

impl std::fmt::Display for Item {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Item::Node(n) => write!(f, "node `{n}`"),
            Item::Element(e) => write!(f, "element `{e}`"),
            Item::Fix(n) => write!(f, "fix entry `{n}`"),
            Item::Input(n) => write!(f, "inputs entry `{n}`"),
            Item::Load(n) => write!(f, "load on `{n}`"),
            Item::Mass(n) => write!(f, "mass on `{n}`"),
            Item::Model => write!(f, "model"),
        }
    }
}

impl ModelError {
    /// The model item the error concerns.
    pub fn item(&self) -> Item {
        use ModelError::*;
        match self {
            DuplicateNode { node } | UnknownHost { node, .. } => Item::Node(node.clone()),
            DuplicateElement { element }
            | UnknownNode { element, .. }
            | NodeCount { element, .. }
            | RepeatedNode { element, .. }
            | ZeroLength { element, .. }
            | Frame { element, .. }
            | BadMode { element, .. }
            | ModeConflict { element, .. }
            | NotA { element, .. } => Item::Element(element.clone()),
            MomentWithoutRotation { node } => Item::Load(node.clone()),
            UnknownNodeInEntry { what, node } | NoRotation { what, node, .. } => match *what {
                "fix" => Item::Fix(node.clone()),
                "load" => Item::Load(node.clone()),
                "mass" => Item::Mass(node.clone()),
                _ => Item::Input(node.clone()),
            },
            FixAndInput { node, .. } => Item::Input(node.clone()),
            BadValue { item, .. } => item.clone(),
        }
    }
}

/// Length below which two nodes of an element count as coincident [m]. Flexures in precision
/// engineering are far longer than a nanometre; anything shorter is an input error.
pub const MIN_ELEMENT_LENGTH: f64 = 1e-9;

/// Element type and data as given by the user, before compilation.
#[derive(Clone, Debug)]
pub enum ElementSpec {
    /// Truss between two nodes.
    Truss {
        /// EA [N].
        ea: f64,
    },
    /// Spatial beam.
    Beam {
        /// Orientation vector (local y); `None` for SPACAR's default.
        orient: Option<[f64; 3]>,
        /// c_t [m²].
        ct: f64,
    },
    /// Hinge with an axis.
    Hinge {
        /// Axis (need not be unit).
        axis: [f64; 3],
        /// Torsion spring k [N·m/rad].
        k: f64,
    },
    /// Rigid body over its nodes.
    Rigid,
}

#[derive(Clone, Debug)]
struct PendingElement {
    name: String,
    nodes: Vec<NodeId>,
    spec: ElementSpec,
    free: Vec<usize>,
    input: Vec<usize>,
    /// Section data of a beam ([`ModelBuilder::set_beam_props`]).
    props: Option<crate::section::BeamProps>,
}

/// Builds a [`Model`] item by item; each `add_*` validates what it can at once.
///
/// Names are looked up in hash maps and elements refer to nodes by index, so building is linear
/// in the size of the model (10,000 beams in a few milliseconds).
#[derive(Clone, Debug, Default)]
pub struct ModelBuilder {
    name: String,
    /// (name, position, rotation asked for, host)
    nodes: Vec<(String, [f64; 3], bool, Option<NodeId>)>,
    node_index: HashMap<String, NodeId>,
    elements: Vec<PendingElement>,
    element_names: HashMap<String, usize>,
    /// (node, dofs); `None` = all coordinates the node has.
    fixes: Vec<(String, Option<Vec<Dof>>)>,
    inputs: Vec<(String, Option<Vec<Dof>>)>,
    /// (element index, mode 1-based)
    rigid_modes: Vec<(usize, usize)>,
    loads: Vec<(String, [f64; 3], [f64; 3])>,
    gravity: [f64; 3],
    spin: Option<Spin>,
    masses: Vec<(String, f64)>,
    inertias: Vec<(String, [[f64; 3]; 3])>,
    prescribed_x: Vec<(String, Dof, f64)>,
    /// (element index, mode 1-based, value)
    prescribed_e: Vec<(usize, usize, f64)>,
}

fn check_finite(item: &Item, field: &'static str, v: &[f64]) -> Result<(), ModelError> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(&value) => Err(ModelError::BadValue {
            item: item.clone(),
            field,
            requirement: "finite",
            value,
        }),
        None => Ok(()),
    }
}

impl ModelBuilder {
    /// An empty model with a name.
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            ..Default::default()
        }
    }

    /// Add a node at `x0` [m]; `rot` asks for rotation coordinates even if no element uses them.
    pub fn add_node(&mut self, name: &str, x0: [f64; 3], rot: bool) -> Result<NodeId, ModelError> {
        check_finite(&Item::Node(name.to_string()), "x", &x0)?;
        if self.node_index.contains_key(name) {
            return Err(ModelError::DuplicateNode {
                node: name.to_string(),
            });
        }
        let id = self.nodes.len();
        self.nodes.push((name.to_string(), x0, rot, None));
        self.node_index.insert(name.to_string(), id);
        Ok(id)
    }

    /// Add a node `at` an earlier node: it shares the host's position and has its own rotation
    /// (SPACAR: a second rotational node on one translational node, as for a hinge).
    pub fn add_node_at(&mut self, name: &str, host: &str) -> Result<NodeId, ModelError> {
        if self.node_index.contains_key(name) {
            return Err(ModelError::DuplicateNode {
                node: name.to_string(),
            });
        }
        let unknown = || ModelError::UnknownHost {
            node: name.to_string(),
            host: host.to_string(),
        };
        let &h = self.node_index.get(host).ok_or_else(unknown)?;
        // a chain of hosts resolves to the first
        let h = self.nodes[h].3.unwrap_or(h);
        let id = self.nodes.len();
        let x0 = self.nodes[h].1;
        self.nodes.push((name.to_string(), x0, true, Some(h)));
        self.node_index.insert(name.to_string(), id);
        Ok(id)
    }

    /// Add an element over named nodes; `free` and `input` list 1-based deformation modes.
    pub fn add_element(
        &mut self,
        name: &str,
        nodes: &[&str],
        spec: ElementSpec,
        free: &[i64],
        input: &[i64],
    ) -> Result<(), ModelError> {
        let el = name.to_string();
        if self.element_names.contains_key(name) {
            return Err(ModelError::DuplicateElement { element: el });
        }
        let (kind, ne, expected) = match &spec {
            ElementSpec::Truss { .. } => ("truss", 1, "2"),
            ElementSpec::Beam { .. } => ("beam", 6, "2"),
            ElementSpec::Hinge { .. } => ("hinge", 3, "2"),
            ElementSpec::Rigid => ("rigid", usize::MAX, "at least 2"),
        };
        let count_ok = if ne == usize::MAX {
            nodes.len() >= 2
        } else {
            nodes.len() == 2
        };
        if !count_ok {
            return Err(ModelError::NodeCount {
                element: el,
                kind,
                expected,
                found: nodes.len(),
            });
        }
        let mut ids = Vec::with_capacity(nodes.len());
        for &n in nodes {
            let id = *self
                .node_index
                .get(n)
                .ok_or_else(|| ModelError::UnknownNode {
                    element: el.clone(),
                    node: n.into(),
                })?;
            if ids.contains(&id) {
                return Err(ModelError::RepeatedNode {
                    element: el,
                    node: n.into(),
                });
            }
            ids.push(id);
        }
        let item = Item::Element(name.to_string());
        match &spec {
            ElementSpec::Truss { ea } => check_finite(&item, "EA", &[*ea])?,
            ElementSpec::Beam { orient, ct } => {
                check_finite(&item, "orient", orient.as_ref().map_or(&[][..], |o| &o[..]))?;
                check_finite(&item, "ct", &[*ct])?;
            }
            ElementSpec::Hinge { axis, k } => {
                check_finite(&item, "axis", axis)?;
                check_finite(&item, "k", &[*k])?;
            }
            ElementSpec::Rigid => {}
        }
        // element length and frame
        if kind != "rigid" && kind != "hinge" {
            let l0 = norm(crate::math::sub(self.nodes[ids[1]].1, self.nodes[ids[0]].1));
            if l0 < MIN_ELEMENT_LENGTH {
                return Err(ModelError::ZeroLength { element: el, l0 });
            }
        }
        let frame_err = |source| ModelError::Frame {
            element: name.to_string(),
            source,
        };
        match &spec {
            ElementSpec::Beam { orient, .. } => {
                let (p, q) = (self.nodes[ids[0]].1, self.nodes[ids[1]].1);
                Beam::new([0, 1], p, q, *orient).map_err(frame_err)?;
            }
            ElementSpec::Hinge { axis, .. } => {
                Hinge::new([0, 1], *axis).map_err(|e| match e {
                    FrameError::ZeroAxis => ModelError::BadValue {
                        item: item.clone(),
                        field: "axis",
                        requirement: "non-zero",
                        value: 0.0,
                    },
                    other => frame_err(other),
                })?;
            }
            _ => {}
        }
        // mode lists
        let ne_real = if kind == "rigid" { usize::MAX } else { ne };
        let check_modes = |list: &[i64]| -> Result<Vec<usize>, ModelError> {
            list.iter()
                .map(|&m| {
                    if m >= 1 && (m as usize) <= ne_real {
                        Ok(m as usize)
                    } else {
                        Err(ModelError::BadMode {
                            element: el.clone(),
                            kind,
                            mode: m,
                            ne: if kind == "rigid" { 0 } else { ne },
                        })
                    }
                })
                .collect()
        };
        let free = check_modes(free)?;
        let input = check_modes(input)?;
        if let Some(&m) = free.iter().find(|m| input.contains(m)) {
            return Err(ModelError::ModeConflict {
                element: el,
                mode: m,
            });
        }
        self.element_names.insert(el.clone(), self.elements.len());
        self.elements.push(PendingElement {
            name: el,
            nodes: ids,
            spec,
            free,
            input,
            props: None,
        });
        Ok(())
    }

    /// Add a straight chain of `n` beams from `start` to `end` [m]: nodes `{prefix}n0` …
    /// `{prefix}n{n}` at equal spacing and elements `{prefix}b0` … `{prefix}b{n−1}` (element i
    /// from node i to node i + 1), all with the orientation vector `orient` (local y; `None` for
    /// SPACAR's default) and, when given, the section data `props`. Returns the node ids in
    /// order, first to last. Every name must be new.
    pub fn add_beam_chain(
        &mut self,
        prefix: &str,
        start: [f64; 3],
        end: [f64; 3],
        n: usize,
        orient: Option<[f64; 3]>,
        props: Option<crate::section::BeamProps>,
    ) -> Result<Vec<NodeId>, ModelError> {
        if n == 0 {
            return Err(ModelError::BadValue {
                item: Item::Element(format!("{prefix}b0")),
                field: "number of beams in the chain",
                requirement: "at least 1",
                value: 0.0,
            });
        }
        let mut ids = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let s = i as f64 / n as f64;
            let x: [f64; 3] = std::array::from_fn(|k| start[k] + s * (end[k] - start[k]));
            ids.push(self.add_node(&format!("{prefix}n{i}"), x, false)?);
        }
        for i in 0..n {
            let (p, q) = (format!("{prefix}n{i}"), format!("{prefix}n{}", i + 1));
            let name = format!("{prefix}b{i}");
            self.add_element(
                &name,
                &[&p, &q],
                ElementSpec::Beam { orient, ct: 0.0 },
                &[],
                &[],
            )?;
            if let Some(props) = props {
                self.set_beam_props(&name, props)?;
            }
        }
        Ok(ids)
    }

    /// Stiffness, mass and section data of a beam added before.
    pub fn set_beam_props(
        &mut self,
        element: &str,
        props: crate::section::BeamProps,
    ) -> Result<(), ModelError> {
        let item = Item::Element(element.to_string());
        let v = [
            props.ea,
            props.gj,
            props.eiy,
            props.eiz,
            props.shear[0],
            props.shear[1],
            props.ct,
            props.rho_a,
        ];
        check_finite(&item, "section constants", &v)?;
        let index = self.element_names.get(element).copied();
        match index.map(|i| &mut self.elements[i]) {
            Some(
                pending @ PendingElement {
                    spec: ElementSpec::Beam { .. },
                    ..
                },
            ) => {
                pending.props = Some(props);
                Ok(())
            }
            _ => Err(ModelError::NotA {
                element: element.to_string(),
                kind: "beam",
            }),
        }
    }

    /// Declare deformation modes (1-based) rigid in statics even if they have stiffness.
    pub fn set_rigid_modes(&mut self, element: &str, modes: &[i64]) -> Result<(), ModelError> {
        let Some(&index) = self.element_names.get(element) else {
            return Err(ModelError::NotA {
                element: element.to_string(),
                kind: "element",
            });
        };
        let el = &self.elements[index];
        for &m in modes {
            if m < 1 || el.input.contains(&(m as usize)) {
                return Err(ModelError::ModeConflict {
                    element: element.to_string(),
                    mode: m.max(0) as usize,
                });
            }
            self.rigid_modes.push((index, m as usize));
        }
        Ok(())
    }

    /// A dead force [N] and moment [N·m] on a node, reached at load factor 1.
    pub fn add_load(
        &mut self,
        node: &str,
        force: [f64; 3],
        moment: [f64; 3],
    ) -> Result<(), ModelError> {
        let item = Item::Load(node.to_string());
        check_finite(&item, "force", &force)?;
        check_finite(&item, "moment", &moment)?;
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "load",
                node: node.into(),
            });
        }
        self.loads.push((node.to_string(), force, moment));
        Ok(())
    }

    /// Gravitational acceleration [m/s²].
    pub fn set_gravity(&mut self, g: [f64; 3]) -> Result<(), ModelError> {
        check_finite(&Item::Model, "gravity", &g)?;
        self.gravity = g;
        Ok(())
    }

    /// Steady rotation at angular velocity `omega` [rad/s] about the axis through `point`
    /// ([`Spin`]): centrifugal loads in statics, centrifugal softening in dynamics.
    pub fn set_spin(&mut self, omega: [f64; 3], point: [f64; 3]) -> Result<(), ModelError> {
        check_finite(&Item::Model, "spin", &omega)?;
        check_finite(&Item::Model, "spin_point", &point)?;
        self.spin = Some(Spin { omega, point });
        Ok(())
    }

    /// A point mass [kg] at a node.
    pub fn add_point_mass(&mut self, node: &str, m: f64) -> Result<(), ModelError> {
        if !(m.is_finite() && m >= 0.0) {
            return Err(ModelError::BadValue {
                item: Item::Mass(node.into()),
                field: "m",
                requirement: "finite and ≥ 0",
                value: m,
            });
        }
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "mass",
                node: node.into(),
            });
        }
        self.masses.push((node.to_string(), m));
        Ok(())
    }

    /// An inertia tensor [kg·m²] about a rotational node, global axes in the reference
    /// orientation (SPACAR `XM n Ixx Ixy Ixz Iyy Iyz Izz`): [Ixx, Ixy, Ixz, Iyy, Iyz, Izz].
    pub fn add_inertia(&mut self, node: &str, i: [f64; 6]) -> Result<(), ModelError> {
        check_finite(&Item::Mass(node.into()), "inertia", &i)?;
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "mass",
                node: node.into(),
            });
        }
        let t = [[i[0], i[1], i[2]], [i[1], i[3], i[4]], [i[2], i[4], i[5]]];
        // positive semi-definite: principal minors
        let m2 = t[0][0] * t[1][1] - t[0][1] * t[0][1];
        let det = t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[1][2])
            - t[0][1] * (t[0][1] * t[2][2] - t[1][2] * t[0][2])
            + t[0][2] * (t[0][1] * t[1][2] - t[1][1] * t[0][2]);
        let scale = i
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        if t[0][0] < 0.0
            || t[1][1] < 0.0
            || t[2][2] < 0.0
            || m2 < -1e-12 * scale * scale
            || det < -1e-12 * scale.powi(3)
        {
            return Err(ModelError::BadValue {
                item: Item::Mass(node.into()),
                field: "inertia",
                requirement: "a positive semi-definite tensor",
                value: det,
            });
        }
        self.inertias.push((node.to_string(), t));
        Ok(())
    }

    /// Prescribe an input coordinate's final value (translation: displacement [m]; rotation:
    /// angle [rad]); the dof becomes an input.
    pub fn prescribe_coordinate(
        &mut self,
        node: &str,
        dof: Dof,
        value: f64,
    ) -> Result<(), ModelError> {
        check_finite(&Item::Input(node.into()), dof.name(), &[value])?;
        self.entry("inputs", node, Some(&[dof]))?;
        self.prescribed_x.push((node.to_string(), dof, value));
        Ok(())
    }

    /// Prescribe an input deformation's final value; mode 1-based, made an input.
    pub fn prescribe_deformation(
        &mut self,
        element: &str,
        mode: usize,
        value: f64,
    ) -> Result<(), ModelError> {
        check_finite(&Item::Element(element.into()), "input value", &[value])?;
        let Some(&index) = self.element_names.get(element) else {
            return Err(ModelError::NotA {
                element: element.to_string(),
                kind: "element",
            });
        };
        let el = &mut self.elements[index];
        el.free.retain(|&m| m != mode);
        if !el.input.contains(&mode) {
            el.input.push(mode);
        }
        self.prescribed_e.push((index, mode, value));
        Ok(())
    }

    /// Fix the listed dofs of a node (support); `None` = all its coordinates.
    pub fn fix(&mut self, node: &str, dofs: Option<&[Dof]>) -> Result<(), ModelError> {
        self.entry("fix", node, dofs)
    }

    /// Make the listed dofs of a node generalised coordinates (x^m); `None` = all of them.
    pub fn input(&mut self, node: &str, dofs: Option<&[Dof]>) -> Result<(), ModelError> {
        self.entry("inputs", node, dofs)
    }

    fn entry(
        &mut self,
        what: &'static str,
        node: &str,
        dofs: Option<&[Dof]>,
    ) -> Result<(), ModelError> {
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what,
                node: node.into(),
            });
        }
        // `None` (all) is resolved at build time, when rotations are known
        let target = if what == "fix" {
            &mut self.fixes
        } else {
            &mut self.inputs
        };
        target.push((node.to_string(), dofs.map(<[Dof]>::to_vec)));
        Ok(())
    }

    /// Validate and compile the model.
    pub fn build(self) -> Result<Model, ModelError> {
        // which nodes carry rotations
        let mut rot: Vec<bool> = self.nodes.iter().map(|n| n.2 || n.3.is_some()).collect();
        for e in &self.elements {
            match e.spec {
                ElementSpec::Beam { .. } | ElementSpec::Hinge { .. } => {
                    for &n in &e.nodes {
                        rot[n] = true;
                    }
                }
                ElementSpec::Rigid => rot[e.nodes[0]] = true,
                ElementSpec::Truss { .. } => {}
            }
        }
        // coordinate layout
        let mut nodes = Vec::with_capacity(self.nodes.len());
        let mut nx = 0;
        for (i, (name, x0, _, host)) in self.nodes.iter().enumerate() {
            let ix_pos = match host {
                Some(h) => nodes.get(*h).map_or(0, |n: &Node| n.ix_pos),
                None => {
                    nx += 3;
                    nx - 3
                }
            };
            let ix_rot = rot[i].then(|| {
                nx += 4;
                nx - 4
            });
            nodes.push(Node {
                name: name.clone(),
                x0: *x0,
                host: *host,
                ix_pos,
                ix_rot,
            });
        }
        // elements
        let mut elements = Vec::with_capacity(self.elements.len());
        let mut e_kind = Vec::new();
        let mut ne = 0;
        for p in &self.elements {
            let pos = |k: usize| nodes[p.nodes[k]].x0;
            let two = [p.nodes[0], *p.nodes.get(1).unwrap_or(&p.nodes[0])];
            let element = match &p.spec {
                ElementSpec::Truss { ea } => {
                    let mut t = Truss::new(two, pos(0), pos(1));
                    t.ea = *ea;
                    Element::Truss(t)
                }
                ElementSpec::Beam { orient, ct } => {
                    let mut b = Beam::new(two, pos(0), pos(1), *orient).map_err(|source| {
                        ModelError::Frame {
                            element: p.name.clone(),
                            source,
                        }
                    })?;
                    b.ct = *ct;
                    if let Some(props) = p.props {
                        b.set_props(props);
                    }
                    Element::Beam(b)
                }
                ElementSpec::Hinge { axis, k } => {
                    let mut h = Hinge::new(two, *axis).map_err(|source| ModelError::Frame {
                        element: p.name.clone(),
                        source,
                    })?;
                    h.k = *k;
                    Element::Hinge(h)
                }
                ElementSpec::Rigid => {
                    let positions: Vec<[f64; 3]> = (0..p.nodes.len()).map(pos).collect();
                    let flags = p.nodes.iter().map(|&n| rot[n]).collect();
                    // a member at the position of an earlier member (a node `at` it) adds only
                    // its rotation: its position constraints would be redundant
                    let pos_flags = (0..p.nodes.len())
                        .map(|k| {
                            let ip = nodes[p.nodes[k]].ix_pos;
                            !(0..k).any(|j| nodes[p.nodes[j]].ix_pos == ip)
                        })
                        .collect();
                    Element::Rigid(Rigid::with_shared_positions(
                        p.nodes.clone(),
                        &positions,
                        flags,
                        pos_flags,
                    ))
                }
            };
            let n_modes = element.ne();
            for &m in p.free.iter().chain(&p.input) {
                if m > n_modes {
                    return Err(ModelError::BadMode {
                        element: p.name.clone(),
                        kind: element.type_name(),
                        mode: m as i64,
                        ne: n_modes,
                    });
                }
            }
            let mut xmap = Vec::new();
            for u in element.node_uses() {
                let n = &nodes[u.node];
                if u.pos {
                    xmap.extend(n.ix_pos..n.ix_pos + 3);
                }
                if u.rot {
                    let r = n
                        .ix_rot
                        .expect("rotation flags were set for every element use");
                    xmap.extend(r..r + 4);
                }
            }
            let mut kinds = vec![DefKind::Fixed; n_modes];
            for &m in &p.free {
                kinds[m - 1] = DefKind::Free;
            }
            for &m in &p.input {
                kinds[m - 1] = DefKind::Input;
            }
            e_kind.extend(kinds);
            elements.push(ElementEntry {
                name: p.name.clone(),
                element,
                ie: ne,
                xmap,
            });
            ne += n_modes;
        }
        // partition of x
        let mut x_kind = vec![CoordKind::Free; nx];
        for (what, list, kind) in [
            ("fix", &self.fixes, CoordKind::Fixed),
            ("inputs", &self.inputs, CoordKind::Input),
        ] {
            for (name, dofs) in list {
                let n = &nodes[self.node_index[name]];
                let all = dofs.is_none();
                for &d in dofs.as_deref().unwrap_or(&Dof::ALL) {
                    match n.x_index(d) {
                        Some(i) => {
                            if x_kind[i] != CoordKind::Free && x_kind[i] != kind {
                                return Err(ModelError::FixAndInput {
                                    node: n.name.clone(),
                                    dof: d.name(),
                                });
                            }
                            x_kind[i] = kind;
                        }
                        None if all => {}
                        None => {
                            return Err(ModelError::NoRotation {
                                what,
                                node: n.name.clone(),
                                dof: d.name(),
                            })
                        }
                    }
                }
            }
        }
        // statics data: explicit rigid modes, loads, masses, prescribed values
        let mut explicit_rigid = vec![false; ne];
        // pending element i compiles to elements[i]
        for &(index, mode) in &self.rigid_modes {
            let el = &elements[index];
            if mode > el.element.ne() {
                return Err(ModelError::BadMode {
                    element: el.name.clone(),
                    kind: el.element.type_name(),
                    mode: mode as i64,
                    ne: el.element.ne(),
                });
            }
            explicit_rigid[el.ie + mode - 1] = true;
        }
        let mut loads = Loads {
            gravity: self.gravity,
            spin: self.spin,
            ..Default::default()
        };
        for (name, force, moment) in &self.loads {
            let node = self.node_index[name];
            if moment.iter().any(|m| *m != 0.0) && !nodes[node].rot() {
                return Err(ModelError::MomentWithoutRotation { node: name.clone() });
            }
            loads.nodal.push(NodalLoad {
                node,
                force: *force,
                moment: *moment,
            });
        }
        for (name, m) in &self.masses {
            loads.point_masses.push((self.node_index[name], *m));
        }
        for (name, t) in &self.inertias {
            let node = self.node_index[name];
            if !nodes[node].rot() {
                return Err(ModelError::NoRotation {
                    what: "mass",
                    node: name.clone(),
                    dof: "inertia",
                });
            }
            loads.inertias.push((node, *t));
        }
        for (name, dof, value) in &self.prescribed_x {
            let i = nodes[self.node_index[name]].x_index(*dof).ok_or_else(|| {
                ModelError::NoRotation {
                    what: "inputs",
                    node: name.clone(),
                    dof: dof.name(),
                }
            })?;
            loads.prescribed.push(Prescribed {
                target: Target::Coordinate(i),
                value: *value,
            });
        }
        for &(index, mode, value) in &self.prescribed_e {
            let el = &elements[index];
            loads.prescribed.push(Prescribed {
                target: Target::Deformation(el.ie + mode - 1),
                value,
            });
        }
        Ok(Model {
            name: self.name,
            nodes,
            elements,
            nx,
            ne,
            partition: Partition {
                x: x_kind,
                e: e_kind,
            },
            explicit_rigid,
            loads,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builder_reports_items() {
        let mut b = ModelBuilder::new("t");
        b.add_node("a", [0.0; 3], false).unwrap();
        assert_eq!(
            b.add_node("a", [1.0; 3], false).unwrap_err(),
            ModelError::DuplicateNode { node: "a".into() }
        );
        b.add_node("b", [0.0; 3], false).unwrap();
        let e = b.add_element("t1", &["a", "b"], ElementSpec::Truss { ea: 0.0 }, &[], &[]);
        assert!(matches!(e, Err(ModelError::ZeroLength { .. })));
        let e = b.add_element("t1", &["a", "c"], ElementSpec::Truss { ea: 0.0 }, &[], &[]);
        assert!(matches!(e, Err(ModelError::UnknownNode { .. })));
        b.fix("a", Some(&[Dof::Rx])).unwrap();
        assert!(matches!(b.build(), Err(ModelError::NoRotation { .. })));
    }

    #[test]
    fn beam_chain_names_positions_and_section() {
        let props = crate::section::BeamProps {
            ea: 2.0,
            gj: 3.0,
            eiy: 4.0,
            eiz: 5.0,
            rho_a: 0.5,
            ..Default::default()
        };
        let mut b = ModelBuilder::new("chain");
        let ids = b
            .add_beam_chain(
                "s:",
                [1.0, 0.0, 0.0],
                [1.0, 3.0, 0.0],
                3,
                Some([0.0, 0.0, 1.0]),
                Some(props),
            )
            .unwrap();
        assert_eq!(ids, vec![0, 1, 2, 3]);
        // names must stay unique
        let e = b.add_beam_chain("s:", [0.0; 3], [1.0; 3], 2, None, None);
        assert!(matches!(e, Err(ModelError::DuplicateNode { .. })), "{e:?}");
        assert!(matches!(
            b.add_beam_chain("t", [0.0; 3], [1.0; 3], 0, None, None),
            Err(ModelError::BadValue { .. })
        ));
        b.fix("s:n0", None).unwrap();
        let m = b.build().unwrap();
        assert_eq!(m.node_id("s:n2"), Some(2));
        assert_eq!(m.nodes[2].x0, [1.0, 2.0, 0.0]);
        assert_eq!(m.elements.len(), 3);
        assert_eq!(m.elements[1].name, "s:b1");
        let Element::Beam(beam) = &m.elements[1].element else {
            panic!("a beam");
        };
        assert_eq!(beam.nodes, [1, 2]);
        assert!((beam.l0 - 1.0).abs() < 1e-15);
        assert_eq!(beam.stiffness, [2.0, 3.0, 4.0, 5.0]);
        assert_eq!(beam.frame[2], [1.0, 0.0, 0.0]);
        assert_eq!(m.elements[2].element.ne(), 6);
    }

    #[test]
    fn element_data_by_name_after_many_elements() {
        // lookups by name (section data, rigid modes, prescribed deformations) on a long chain
        let mut b = ModelBuilder::new("long");
        b.add_beam_chain("", [0.0; 3], [1.0, 0.0, 0.0], 2000, None, None)
            .unwrap();
        b.set_rigid_modes("b1999", &[1]).unwrap();
        b.prescribe_deformation("b1000", 3, 1e-3).unwrap();
        assert!(matches!(
            b.set_beam_props("n5", Default::default()),
            Err(ModelError::NotA { .. })
        ));
        b.fix("n0", None).unwrap();
        let m = b.build().unwrap();
        assert!(m.explicit_rigid[m.elements[1999].ie]);
        assert_eq!(m.partition.e[m.elements[1000].ie + 2], DefKind::Input);
        assert_eq!(
            m.loads.prescribed[0].target,
            Target::Deformation(m.elements[1000].ie + 2)
        );
    }

    #[test]
    fn rotations_only_where_used() {
        let mut b = ModelBuilder::new("t");
        b.add_node("a", [0.0; 3], false).unwrap();
        b.add_node("b", [1.0, 0.0, 0.0], false).unwrap();
        b.add_node("c", [2.0, 0.0, 0.0], false).unwrap();
        b.add_element("t", &["a", "b"], ElementSpec::Truss { ea: 0.0 }, &[], &[])
            .unwrap();
        b.add_element(
            "w",
            &["b", "c"],
            ElementSpec::Beam {
                orient: None,
                ct: 0.0,
            },
            &[2],
            &[],
        )
        .unwrap();
        b.fix("a", None).unwrap();
        let m = b.build().unwrap();
        assert_eq!(m.nx, 3 + 7 + 7);
        assert_eq!(m.ne, 7);
        assert_eq!(&m.partition.x[0..3], &[CoordKind::Fixed; 3]);
        assert_eq!(m.partition.e[2], DefKind::Free);
        assert_eq!(m.deformation_owner(6), (1, 5));
    }
}
