//! Results of a static step in physical units, per node and per element: positions,
//! displacements, rotation vectors, support reactions (forces and moments) and the stress
//! resultants with the largest normal stress of sections. The mechanics of presenting a state;
//! the writers in `flexmbd-io` only format these.

use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{CoordKind, Dof, Model, Target};
use crate::statics::StepResult;
use serde::Serialize;

/// Rotation vector (axis × angle, global axes, angle in (−π, π]) of Euler parameters that need
/// not be of unit length.
pub fn rotation_vector(l: &[f64]) -> [f64; 3] {
    let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + l[3] * l[3]).sqrt();
    let (l0, v) = (l[0] / n, [l[1] / n, l[2] / n, l[3] / n]);
    let s = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if s < 1e-300 {
        return [0.0; 3];
    }
    // angle in (−π, π]: take the shorter rotation
    let (s, l0, v) = if l0 < 0.0 {
        (s, -l0, v.map(|a| -a))
    } else {
        (s, l0, v)
    };
    let angle = 2.0 * s.atan2(l0);
    [v[0] / s * angle, v[1] / s * angle, v[2] / s * angle]
}

/// The moment [N·m] (global axes) of generalised forces `f` on the Euler parameters `l`:
/// M = ½ Λ̄(λ) f_λ, the inverse of f_λ = 2 Λ̄ᵀ M (SPACAR takes f(λ1..3)/2 at the reference).
pub fn moment_of_lambda_forces(l: &[f64], f: &[f64]) -> [f64; 3] {
    let lb = lambda_bar(&[l[0], l[1], l[2], l[3]]);
    std::array::from_fn(|k| 0.5 * (0..4).map(|c| lb[k][c] * f[c]).sum::<f64>())
}

/// Per-node results of a step.
#[derive(Clone, Debug, Serialize)]
pub struct NodeResult {
    /// Node name.
    pub node: String,
    /// Position [m].
    pub position: [f64; 3],
    /// Displacement from the reference [m].
    pub displacement: [f64; 3],
    /// Rotation vector [rad] (nodes with rotation).
    pub rotation: Option<[f64; 3]>,
    /// Reaction force [N] at fixed or input coordinates.
    pub reaction_force: Option<[f64; 3]>,
    /// Reaction moment [N·m] at fixed or input rotations.
    pub reaction_moment: Option<[f64; 3]>,
}

/// Per-element results of a step.
#[derive(Clone, Debug, Serialize)]
pub struct ElementResult {
    /// Element name.
    pub element: String,
    /// Deformations e.
    pub e: Vec<f64>,
    /// Stress resultants σ (beam: σ1 axial force [N], σ2 ≈ torque/l0, σ3..σ6 ≈ bending end
    /// moments/l0 [N]).
    pub sigma: Vec<f64>,
    /// Largest normal stress of an element with a section ([`ElementKind::max_stress`]) [Pa].
    pub max_stress: Option<f64>,
}

/// Nodal results of a step.
pub fn node_results(model: &Model, step: &StepResult) -> Vec<NodeResult> {
    let x0 = model.x0();
    model
        .nodes
        .iter()
        .map(|n| {
            let p = n.ix_pos;
            let position = [step.x[p], step.x[p + 1], step.x[p + 2]];
            let displacement = [
                position[0] - x0[p],
                position[1] - x0[p + 1],
                position[2] - x0[p + 2],
            ];
            let supported = |i: usize| model.partition.x[i] != CoordKind::Free;
            let reaction_force = (n.host.is_none() && (p..p + 3).any(supported)).then(|| {
                [
                    step.reactions[p],
                    step.reactions[p + 1],
                    step.reactions[p + 2],
                ]
            });
            let (rotation, reaction_moment) = match n.ix_rot {
                Some(r) => {
                    let l = &step.x[r..r + 4];
                    let moment = (r..r + 4)
                        .any(supported)
                        .then(|| moment_of_lambda_forces(l, &step.reactions[r..r + 4]));
                    (Some(rotation_vector(l)), moment)
                }
                None => (None, None),
            };
            NodeResult {
                node: n.name.clone(),
                position,
                displacement,
                rotation,
                reaction_force,
                reaction_moment,
            }
        })
        .collect()
}

/// Element results of a step.
pub fn element_results(model: &Model, step: &StepResult) -> Vec<ElementResult> {
    model
        .elements
        .iter()
        .map(|entry| {
            let ne = entry.element.ne();
            let e = step.e[entry.ie..entry.ie + ne].to_vec();
            let sigma = step.sigma[entry.ie..entry.ie + ne].to_vec();
            let max_stress = entry.element.max_stress(&sigma);
            ElementResult {
                element: entry.name.clone(),
                e,
                sigma,
                max_stress,
            }
        })
        .collect()
}

/// The reaction at a prescribed target (a held coordinate or an input deformation) in a step,
/// with its unit: the support force [N] or moment [N·m] of a coordinate (global axes), the
/// stress resultant σ of a deformation (the actuator force [N] or, for an angle, the torque
/// [N·m]).
pub fn target_reaction(model: &Model, step: &StepResult, target: Target) -> (f64, &'static str) {
    match target {
        Target::Coordinate(i) => {
            for n in &model.nodes {
                for d in Dof::ALL {
                    if (n.host.is_none() || d.is_rotation()) && n.x_index(d) == Some(i) {
                        return if d.is_rotation() {
                            let r = n.ix_rot.unwrap_or(i);
                            let m = moment_of_lambda_forces(
                                &step.x[r..r + 4],
                                &step.reactions[r..r + 4],
                            );
                            (m[d.index() - 3], "N·m")
                        } else {
                            (step.reactions[i], "N")
                        };
                    }
                }
            }
            (step.reactions[i], "N")
        }
        Target::Deformation(k) => {
            let (el, m) = model.deformation_owner(k);
            let angle = model.elements[el].element.mode_is_angle(m);
            (step.sigma[k], if angle { "N·m" } else { "N" })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::euler_from_axis_angle;

    #[test]
    fn rotation_vector_is_axis_times_angle() {
        // 0.7 rad about a skew axis, and the same rotation with λ → −λ (same rotation)
        let axis = crate::math::normalize([1.0, -2.0, 0.5]);
        let l = euler_from_axis_angle(axis, 0.7);
        let neg = l.map(|v| -v);
        for lam in [l, neg, l.map(|v| 3.0 * v)] {
            let r = rotation_vector(&lam);
            for k in 0..3 {
                assert!((r[k] - 0.7 * axis[k]).abs() < 1e-14, "{r:?}");
            }
        }
    }

    #[test]
    fn lambda_forces_of_a_moment_give_the_moment_back() {
        // f_λ = 2 Λ̄ᵀ M (the generalised force of a moment, statics) → ½ Λ̄ f_λ = M, since
        // Λ̄ Λ̄ᵀ = I for unit λ
        let l = euler_from_axis_angle(crate::math::normalize([0.3, 0.4, -1.0]), 1.3);
        let m = [0.2, -1.5, 0.7];
        let lb = lambda_bar(&l);
        let f: Vec<f64> = (0..4)
            .map(|c| 2.0 * (0..3).map(|k| lb[k][c] * m[k]).sum::<f64>())
            .collect();
        let back = moment_of_lambda_forces(&l, &f);
        for k in 0..3 {
            assert!((back[k] - m[k]).abs() < 1e-14);
        }
    }
}
