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

mod builder;
mod error;
mod loads;

pub use builder::{ModelBuilder, MIN_ELEMENT_LENGTH};
pub use error::{Item, ModelError};
pub use loads::{Loads, NodalLoad, Prescribed, Spin, Target};

use crate::elements::{Element, ElementKind, NodeId};

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
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
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
    /// Global index in x of each local coordinate (SPACAR `lnp`; 32-bit, 56 bytes for a
    /// beam's 14: [`ElementEntry::x_index`] gives them as `usize`).
    pub xmap: Vec<u32>,
    /// Retardation time τ [s] of the element's material damping (Kelvin–Voigt: σ = S (e + τ ė)
    /// in a time simulation; 0: none).
    pub damping: f64,
}

impl ElementEntry {
    /// Global index in x of local coordinate `a`.
    #[inline]
    pub fn x_index(&self, a: usize) -> usize {
        self.xmap[a] as usize
    }

    /// Global index in x of each local coordinate, in order.
    pub fn x_indices(&self) -> impl ExactSizeIterator<Item = usize> + Clone + '_ {
        self.xmap.iter().map(|&i| i as usize)
    }
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
        // (lazily: a node `at` a host has its Euler parameters far from its position)
        Some((
            n,
            node.ix_rot
                .filter(|&r| i >= r)
                .map_or_else(|| labels[i - node.ix_pos], |r| labels[3 + i - r]),
        ))
    }
    /// Number of rotational nodes (each adds one implicit Euler normalisation constraint).
    pub fn n_rotational_nodes(&self) -> usize {
        self.nodes.iter().filter(|n| n.rot()).count()
    }
}

#[cfg(test)]
mod tests;
