//! Model-building errors that name the item, so that a file reader can point at its line.

use crate::elements::FrameError;

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
    /// More nodal coordinates than 32-bit indices reach (the element maps into x).
    #[error("model: {nx} nodal coordinates, more than the {max} this program indexes")]
    TooLarge {
        /// Number of nodal coordinates.
        nx: usize,
        /// The most it takes.
        max: u32,
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
            TooLarge { .. } => Item::Model,
        }
    }
}
