//! Loads, masses, prescribed inputs and the steady rotation of a model.

use super::*;

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

    /// Whether a static path depends on its load factor t: a non-zero nodal force or moment,
    /// gravity or a steady rotation, or a non-zero prescribed value. When none does, every
    /// step of a load-step path is the equilibrium of the first, at every t.
    pub fn scale_with_load_factor(&self) -> bool {
        self.nodal
            .iter()
            .any(|l| l.force.iter().chain(&l.moment).any(|v| *v != 0.0))
            || self.acceleration_field().is_some()
            || self.prescribed.iter().any(|p| p.value != 0.0)
    }
}
