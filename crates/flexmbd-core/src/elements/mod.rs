//! Element library. One element = one file implementing [`ElementKind`].
//!
//! Every element k maps its nodal coordinates x_k to deformation parameters
//! e_k = 𝒟_k(x_k) that are invariant under rigid-body motion and zero in the reference
//! configuration (paper eq. (1), theory.md §3). The analyses talk to elements only through
//! [`ElementKind`], via the one dispatch enum [`Element`].
//!
//! Local coordinate layout: the element lists the nodes it uses ([`NodeUse`]); for each, in
//! order, its position r (3, if `pos`) then its Euler parameters λ (4, if `rot`).

pub mod beam;
pub mod hinge;
pub mod rigid;
pub mod truss;

#[cfg(test)]
pub(crate) mod testing;

pub use beam::{Beam, BeamFirst};
pub use hinge::Hinge;
pub use rigid::Rigid;
pub use truss::Truss;

use crate::math::SmoothMap;
use faer::Mat;

/// Index of a node in `Model::nodes`.
pub type NodeId = usize;

/// Which coordinates of a node an element uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeUse {
    /// The node.
    pub node: NodeId,
    /// Uses the position r (3 coordinates).
    pub pos: bool,
    /// Uses the Euler parameters λ (4 coordinates).
    pub rot: bool,
}

impl NodeUse {
    /// Number of local coordinates this use contributes.
    pub fn len(&self) -> usize {
        3 * usize::from(self.pos) + 4 * usize::from(self.rot)
    }
    /// True when the use contributes no coordinates.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The same use (`pos`, `rot`) of each of `nodes`, in order.
    pub fn each(nodes: &[NodeId], pos: bool, rot: bool) -> Vec<NodeUse> {
        nodes
            .iter()
            .map(|&node| NodeUse { node, pos, rot })
            .collect()
    }
}

/// A steady acceleration field acting on the mass of a model: a(r) = W (r − a₀) + g on its
/// translational mass and the gyroscopic moment −Ω × (I Ω) on its rotary inertia. Gravity is
/// W = 0, Ω = 0; a steady rotation Ω about an axis through a₀ is W = Ω² P = Ω² I − Ω Ωᵀ
/// (its centrifugal field, [`crate::model::Spin`]); both at once add up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccelerationField {
    /// W [1/s²]: Ω² P for a steady rotation, zero otherwise.
    pub w: [[f64; 3]; 3],
    /// a₀ [m]: a point on the rotation axis.
    pub point: [f64; 3],
    /// g [m/s²]: the uniform part (gravity).
    pub uniform: [f64; 3],
    /// Ω [rad/s]: the angular velocity of the steady rotation (zero without one).
    pub omega: [f64; 3],
}

impl AccelerationField {
    /// The acceleration W (r − a₀) + g at the point r.
    pub fn at(&self, r: [f64; 3]) -> [f64; 3] {
        let d = [
            r[0] - self.point[0],
            r[1] - self.point[1],
            r[2] - self.point[2],
        ];
        std::array::from_fn(|k| crate::math::dot(self.w[k], d) + self.uniform[k])
    }
    /// The gyroscopic moment −Ω × (I Ω) of a body with inertia tensor `i` (global axes)
    /// turning steadily with the field's rotation (Euler's equation).
    pub fn gyroscopic_moment(&self, i: &[[f64; 3]; 3]) -> [f64; 3] {
        let h: [f64; 3] = std::array::from_fn(|k| crate::math::dot(i[k], self.omega));
        let m = crate::math::cross(self.omega, h);
        [-m[0], -m[1], -m[2]]
    }
    /// True when the field has no effect (no gravity, no rotation).
    pub fn is_zero(&self) -> bool {
        self.uniform == [0.0; 3] && self.omega == [0.0; 3] && self.w == [[0.0; 3]; 3]
    }
}

/// What releasing one deformation mode makes of an element, in a designer's words
/// ([`ElementKind::release`]; docs/kinematic-analysis.md "Repair in the designer's language").
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Release {
    /// A hinge: a free rotation about the unit `axis` (global) at node use `at` (an index into
    /// [`ElementKind::node_uses`]), or along the whole element for `None` (a torsion release).
    Hinge {
        /// The unit axis.
        axis: [f64; 3],
        /// The node use it sits at.
        at: Option<usize>,
    },
    /// A slide: a free relative translation along the unit `axis`.
    Slide {
        /// The unit axis.
        axis: [f64; 3],
    },
}

/// The element contract: deformations, their first and second derivatives, stiffness, and the
/// element's mass (mass matrix and the loads of acceleration fields on it).
///
/// Sizes: nx_k = Σ `NodeUse::len` over [`ElementKind::node_uses`], ne_k = [`ElementKind::ne`].
pub trait ElementKind {
    /// Nodes and coordinates used, in local-coordinate order.
    fn node_uses(&self) -> Vec<NodeUse>;
    /// Number of deformation parameters ne_k.
    fn ne(&self) -> usize;
    /// Human name of deformation mode `k` (0-based), e.g. "elongation".
    fn mode_name(&self, k: usize, node_names: &[String]) -> String;
    /// True when deformation mode `k` is an angle [rad] (its stress resultant a torque [N·m]);
    /// false for a length [m] (a force [N]), the default.
    fn mode_is_angle(&self, k: usize) -> bool {
        let _ = k;
        false
    }
    /// True when deformation mode `k` is an angle measured modulo 2π, in (−π, π] (the
    /// hinge's exact relative rotation, with its branch cut at ±π): a prescribed value of it
    /// is met modulo 2π, so that an input can be driven through any number of turns. False
    /// (the default) for every other deformation.
    fn mode_is_periodic(&self, k: usize) -> bool {
        let _ = k;
        false
    }
    /// True for a rigid body: its deformations are constraints that can never be released,
    /// given stiffness or driven.
    fn is_rigid_body(&self) -> bool {
        false
    }
    /// What releasing deformation mode `k` (0-based) makes of the element at the local
    /// coordinates `xk`: a hinge or a slide, to first order. `None` (the default) when the
    /// mode's name says it best.
    fn release(&self, k: usize, xk: &[f64]) -> Option<Release> {
        let _ = (k, xk);
        None
    }
    /// The largest normal stress [Pa] in the element's section for the stress resultants
    /// `sigma`, when the element has a section (`None`, the default, otherwise).
    fn max_stress(&self, sigma: &[f64]) -> Option<f64> {
        let _ = sigma;
        None
    }
    /// True when the element is inverted at the local coordinates `xk`: its chord has passed
    /// through zero length or points backwards in the element's own frame, a state its
    /// deformations cannot see (they are even in the chord direction). `prev` holds the local
    /// coordinates of the last accepted state on the path (the reference state at first).
    fn inverted(&self, xk: &[f64], prev: &[f64]) -> bool {
        let _ = (xk, prev);
        false
    }
    /// e_k = 𝒟_k(x_k)  (paper eq. (1)).
    fn deformations(&self, xk: &[f64]) -> Vec<f64>;
    /// D_k = ∂e_k/∂x_k  (ne_k × nx_k).
    fn jacobian(&self, xk: &[f64]) -> Mat<f64>;
    /// Σᵢ wᵢ ∂²eᵢ/∂x_k²  (nx_k × nx_k); with w = σ this is the element's geometric stiffness.
    fn hessian_weighted(&self, xk: &[f64], w: &[f64]) -> Mat<f64>;
    /// S in σ = S e  (ne_k × ne_k); zero where the model gives no stiffness.
    fn stiffness(&self) -> Mat<f64>;
    /// The mass matrix M_k on the local coordinates at `xk` (theory.md §12), written row-major
    /// into `out` (nx_k × nx_k), with the translational kinetic energy weighted by a symmetric
    /// `weight` W (½ ∫ ṙᵀ W ṙ dm; `None` = I) and with or without the rotary inertia (W = Ω² P
    /// without rotary inertia gives the centrifugal softening of a steady rotation). Returns
    /// `false`, leaving `out` alone, for an element that carries no mass (the default).
    fn mass(
        &self,
        xk: &[f64],
        weight: Option<&[[f64; 3]; 3]>,
        rotary: bool,
        out: &mut [f64],
    ) -> bool {
        let _ = (xk, weight, rotary, out);
        false
    }
    /// The velocity-dependent inertia forces h(x, ẋ) of the element's mass model at `xk` with
    /// the rates `vk`, written into `out` (nx_k), so that the element's inertia forces are
    /// M(x) ẍ + h (Lagrange's equations of the kinetic energy ½ ẋᵀ M(x) ẋ of
    /// [`ElementKind::mass`] without weight). Returns `false`, leaving `out` alone, for an
    /// element without mass (the default) or whose mass matrix does not depend on x.
    fn velocity_forces(&self, xk: &[f64], vk: &[f64], out: &mut [f64]) -> bool {
        let _ = (xk, vk, out);
        false
    }
    /// The inertia forces M(x) ẍ + h(x, ẋ) at `xk` with rates `vk` and accelerations `ak`,
    /// written into `out` (nx_k); `false` for an element without mass. The default forms
    /// [`ElementKind::mass`] and adds [`ElementKind::velocity_forces`]; an element may compute
    /// them faster without the matrix.
    fn inertia_forces(&self, xk: &[f64], vk: &[f64], ak: &[f64], out: &mut [f64]) -> bool {
        let n = xk.len();
        let mut m = vec![0.0; n * n];
        if !self.mass(xk, None, true, &mut m) {
            return false;
        }
        for (r, o) in out.iter_mut().enumerate() {
            *o = (0..n).map(|c| m[r * n + c] * ak[c]).sum();
        }
        let mut h = vec![0.0; n];
        if self.velocity_forces(xk, vk, &mut h) {
            out.iter_mut().zip(&h).for_each(|(o, v)| *o += v);
        }
        true
    }
    /// The generalised loads of an acceleration field (gravity, the centrifugal field of a
    /// steady rotation) on the element's mass, consistent with [`ElementKind::mass`], at the
    /// coordinates `xk`: one (force, moment) per node use, global axes, added to `out`
    /// (length: the number of node uses). Nothing for an element without mass (the default).
    fn field_loads(&self, xk: &[f64], field: &AccelerationField, out: &mut [([f64; 3], [f64; 3])]) {
        let _ = (xk, field, out);
    }
    /// The closed-form evaluation in fixed-size arrays of an element on two full nodes (14 local
    /// coordinates, 6 deformations) that has one: the analyses' fast path. `None` (the
    /// default): the analyses use the generic methods above.
    fn closed_form(&self) -> Option<&dyn ClosedForm14> {
        None
    }
}

/// Closed-form values, Jacobian and Hessian products in fixed-size arrays (no heap allocation)
/// for an element on two full nodes: x_k = [r_p; λ_p; r_q; λ_q] (14), six deformations.
pub trait ClosedForm14 {
    /// e, D and the intermediate data of the Hessian products at `xk`.
    fn first(&self, xk: &[f64; 14]) -> BeamFirst;
}

/// All element types; the only `match` over element types lives in this impl.
#[derive(Clone, Debug)]
pub enum Element {
    /// Two-node truss, one deformation.
    Truss(Truss),
    /// Spatial beam, six deformations (paper eq. (2)).
    Beam(Beam),
    /// Hinge between the rotations of two nodes, three deformations.
    Hinge(Hinge),
    /// Rigid body over any number of nodes.
    Rigid(Rigid),
}

impl Element {
    /// Short type name as used in model files.
    pub fn type_name(&self) -> &'static str {
        match self {
            Element::Truss(_) => "truss",
            Element::Beam(_) => "beam",
            Element::Hinge(_) => "hinge",
            Element::Rigid(_) => "rigid",
        }
    }
    fn kind(&self) -> &dyn ElementKind {
        match self {
            Element::Truss(e) => e,
            Element::Beam(e) => e,
            Element::Hinge(e) => e,
            Element::Rigid(e) => e,
        }
    }
}

impl ElementKind for Element {
    fn node_uses(&self) -> Vec<NodeUse> {
        self.kind().node_uses()
    }
    fn ne(&self) -> usize {
        self.kind().ne()
    }
    fn mode_name(&self, k: usize, node_names: &[String]) -> String {
        self.kind().mode_name(k, node_names)
    }
    fn mode_is_angle(&self, k: usize) -> bool {
        self.kind().mode_is_angle(k)
    }
    fn mode_is_periodic(&self, k: usize) -> bool {
        self.kind().mode_is_periodic(k)
    }
    fn is_rigid_body(&self) -> bool {
        self.kind().is_rigid_body()
    }
    fn release(&self, k: usize, xk: &[f64]) -> Option<Release> {
        self.kind().release(k, xk)
    }
    fn max_stress(&self, sigma: &[f64]) -> Option<f64> {
        self.kind().max_stress(sigma)
    }
    fn inverted(&self, xk: &[f64], prev: &[f64]) -> bool {
        self.kind().inverted(xk, prev)
    }
    fn deformations(&self, xk: &[f64]) -> Vec<f64> {
        self.kind().deformations(xk)
    }
    fn jacobian(&self, xk: &[f64]) -> Mat<f64> {
        self.kind().jacobian(xk)
    }
    fn hessian_weighted(&self, xk: &[f64], w: &[f64]) -> Mat<f64> {
        self.kind().hessian_weighted(xk, w)
    }
    fn stiffness(&self) -> Mat<f64> {
        self.kind().stiffness()
    }
    fn mass(
        &self,
        xk: &[f64],
        weight: Option<&[[f64; 3]; 3]>,
        rotary: bool,
        out: &mut [f64],
    ) -> bool {
        self.kind().mass(xk, weight, rotary, out)
    }
    fn velocity_forces(&self, xk: &[f64], vk: &[f64], out: &mut [f64]) -> bool {
        self.kind().velocity_forces(xk, vk, out)
    }
    fn inertia_forces(&self, xk: &[f64], vk: &[f64], ak: &[f64], out: &mut [f64]) -> bool {
        self.kind().inertia_forces(xk, vk, ak, out)
    }
    fn field_loads(&self, xk: &[f64], field: &AccelerationField, out: &mut [([f64; 3], [f64; 3])]) {
        self.kind().field_loads(xk, field, out)
    }
    fn closed_form(&self) -> Option<&dyn ClosedForm14> {
        self.kind().closed_form()
    }
}

/// Reference triad of a two-node element from its axis and an orientation vector (local y).
///
/// SPACAR 2015 rule (theory.md §3.3, [V ST getLocalframe.m]): ex along the element;
/// ey = orientation vector made orthogonal to ex (default: the global axis along which |ex_i| is
/// smallest); ez = ex × ey.
pub fn local_frame(axis: [f64; 3], orient: Option<[f64; 3]>) -> Result<[[f64; 3]; 3], FrameError> {
    use crate::math::{cross, dot, norm, normalize};
    let l = norm(axis);
    if l.is_nan() || l <= 0.0 {
        return Err(FrameError::ZeroAxis);
    }
    let ex = normalize(axis);
    let ey0 = match orient {
        Some(v) => {
            let n = norm(v);
            if n.is_nan() || n <= 0.0 || !n.is_finite() {
                return Err(FrameError::ZeroOrientation);
            }
            normalize(v)
        }
        None => {
            let mut k = 0;
            for i in 1..3 {
                if ex[i].abs() < ex[k].abs() {
                    k = i;
                }
            }
            let mut v = [0.0; 3];
            v[k] = 1.0;
            v
        }
    };
    let c = dot(ey0, ex);
    let s = (1.0 - c * c).max(0.0).sqrt();
    // SPACAR's threshold: orientation (nearly) parallel to the element axis
    if s < ORIENT_PARALLEL_TOL {
        return Err(FrameError::ParallelOrientation);
    }
    let ey = [
        (ey0[0] - c * ex[0]) / s,
        (ey0[1] - c * ex[1]) / s,
        (ey0[2] - c * ex[2]) / s,
    ];
    let ez = cross(ex, ey);
    Ok([ex, ey, ez])
}

/// sin of the angle between orientation vector and element axis below which the local frame is
/// undefined (SPACAR 2015 uses the same 1e-5, theory.md §3.3).
pub const ORIENT_PARALLEL_TOL: f64 = 1e-5;

/// Why a local frame cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// The element axis has zero length.
    #[error("the element has zero length")]
    ZeroAxis,
    /// The orientation vector is zero or not finite.
    #[error("the orientation vector is zero")]
    ZeroOrientation,
    /// The orientation vector is (nearly) parallel to the element axis.
    #[error("the orientation vector is parallel to the element axis")]
    ParallelOrientation,
}

// ---- helpers to implement ElementKind on top of a fixed-size SmoothMap ----

/// The three derivative methods of [`ElementKind`] (`deformations`, `jacobian`,
/// `hessian_weighted`) for an element that is a fixed-size [`SmoothMap`] (exact derivatives by
/// jets); use inside `impl ElementKind for …`.
macro_rules! smooth_map_derivatives {
    () => {
        fn deformations(&self, xk: &[f64]) -> Vec<f64> {
            $crate::elements::fixed_values(self, xk)
        }
        fn jacobian(&self, xk: &[f64]) -> faer::Mat<f64> {
            $crate::elements::fixed_jacobian(self, xk)
        }
        fn hessian_weighted(&self, xk: &[f64], w: &[f64]) -> faer::Mat<f64> {
            $crate::elements::fixed_hessian(self, xk, w)
        }
    };
}
pub(crate) use smooth_map_derivatives;

/// Values of a fixed-size map from a local coordinate slice.
pub(crate) fn fixed_values<const N: usize, const M: usize>(
    map: &impl SmoothMap<N, M>,
    xk: &[f64],
) -> Vec<f64> {
    map.value(&as_array(xk)).to_vec()
}

/// Jacobian of a fixed-size map as an M × N matrix.
pub(crate) fn fixed_jacobian<const N: usize, const M: usize>(
    map: &impl SmoothMap<N, M>,
    xk: &[f64],
) -> Mat<f64> {
    let (_, j) = map.jacobian(&as_array(xk));
    Mat::from_fn(M, N, |i, k| j[i][k])
}

/// Weighted Hessian of a fixed-size map as an N × N matrix.
pub(crate) fn fixed_hessian<const N: usize, const M: usize>(
    map: &impl SmoothMap<N, M>,
    xk: &[f64],
    w: &[f64],
) -> Mat<f64> {
    let h = map.hessian_weighted(&as_array(xk), &as_array(w));
    Mat::from_fn(N, N, |i, k| h[i][k])
}

fn as_array<const N: usize>(x: &[f64]) -> [f64; N] {
    assert_eq!(
        x.len(),
        N,
        "local vector has length {} instead of {N}",
        x.len()
    );
    std::array::from_fn(|i| x[i])
}

/// Euler parameters of the identity rotation (every node's reference orientation).
pub const EULER_IDENTITY: [f64; 4] = [1.0, 0.0, 0.0, 0.0];
