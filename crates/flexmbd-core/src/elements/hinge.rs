//! Hinge between the rotations of two nodes p and q, with an axis a.
//!
//! x_k = [λ_p; λ_q]  (nx_k = 8). Reference triad (a, b, c) with a the hinge axis and b, c
//! perpendicular to it (built like a beam frame, theory.md §3.3). Current triads
//! a_p = R(λ_p) a, …, a_q = R(λ_q) a, …. Deformations (theory.md §3.4):
//!
//! ```text
//! e1 = atan2(c_p·b_q − b_p·c_q, b_p·b_q + c_p·c_q)   relative rotation about the axis (exact angle)
//! e2 = (a_p·c_q − c_p·a_q)/2                       relative rotation about b (≈ angle)
//! e3 = (b_p·a_q − a_p·b_q)/2                       relative rotation about c (≈ angle)
//! ```
//!
//! All are dot products between the two end triads, hence invariant under a common rotation;
//! e1 is exact for any rotation about the axis (branch cut at ±π). Stiffness σ₁ = k e₁ (torsion
//! spring, N·m/rad), theory.md §11.4.

use super::{local_frame, smooth_map_derivatives, ElementKind, FrameError, NodeId, NodeUse};
use crate::math::{cst3, dot, rotate, Scalar, SmoothMap};
use faer::Mat;

/// Hinge (revolute joint between two rotational nodes).
#[derive(Clone, Debug)]
pub struct Hinge {
    /// Nodes p and q (rotations only).
    pub nodes: [NodeId; 2],
    /// Reference triad [a, b, c] (rows), a = unit hinge axis.
    pub frame: [[f64; 3]; 3],
    /// k [N·m/rad]: torsion spring stiffness on e1; zero when not given.
    pub k: f64,
}

impl Hinge {
    /// A hinge with the given axis.
    pub fn new(nodes: [NodeId; 2], axis: [f64; 3]) -> Result<Self, FrameError> {
        Ok(Self {
            nodes,
            frame: local_frame(axis, None)?,
            k: 0.0,
        })
    }
}

impl SmoothMap<8, 3> for Hinge {
    fn eval<T: Scalar>(&self, x: &[T; 8]) -> [T; 3] {
        let lp = [x[0], x[1], x[2], x[3]];
        let lq = [x[4], x[5], x[6], x[7]];
        let [a, b, c] = self.frame.map(cst3::<T>);
        let (ap, bp, cp) = (rotate(&lp, a), rotate(&lp, b), rotate(&lp, c));
        let (aq, bq, cq) = (rotate(&lq, a), rotate(&lq, b), rotate(&lq, c));
        [
            (dot(cp, bq) - dot(bp, cq)).atan2(dot(bp, bq) + dot(cp, cq)),
            (dot(ap, cq) - dot(cp, aq)).scale(0.5),
            (dot(bp, aq) - dot(ap, bq)).scale(0.5),
        ]
    }
}

const HINGE_MODES: [&str; 3] = [
    "rotation about the axis",
    "rotation about local b",
    "rotation about local c",
];

impl ElementKind for Hinge {
    fn node_uses(&self) -> Vec<NodeUse> {
        NodeUse::each(&self.nodes, false, true)
    }
    fn ne(&self) -> usize {
        3
    }
    fn mode_name(&self, k: usize, _node_names: &[String]) -> String {
        HINGE_MODES[k].into()
    }
    fn mode_is_angle(&self, _k: usize) -> bool {
        true
    }
    fn mode_is_periodic(&self, k: usize) -> bool {
        k == 0
    }
    smooth_map_derivatives!();
    fn stiffness(&self) -> Mat<f64> {
        let mut s = Mat::zeros(3, 3);
        s[(0, 0)] = self.k;
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::testing::{check_contract, Contract};
    use crate::math::{euler_from_axis_angle, euler_mul, normalize};

    #[test]
    fn hinge_satisfies_element_contract() {
        let h = Hinge::new([0, 1], [0.2, -0.5, 1.0]).unwrap();
        check_contract(&h, &[[0.0; 3], [1.0, 0.0, 0.0]], Contract::default());
    }

    #[test]
    fn hinge_measures_exact_relative_angle_about_its_axis() {
        let axis = normalize([1.0, 2.0, 2.0]);
        let h = Hinge::new([0, 1], axis).unwrap();
        let base = euler_from_axis_angle(normalize([0.3, -1.0, 0.1]), 1.1);
        for angle in [-2.5, -0.4, 0.0, 0.7, 3.0] {
            // q = p followed by a rotation about the (rotated) axis: q = p ⊗ rot(axis, angle)
            let lq = euler_mul(&base, &euler_from_axis_angle(axis, angle));
            let mut x = [0.0; 8];
            x[..4].copy_from_slice(&base);
            x[4..].copy_from_slice(&lq);
            let e = h.value(&x);
            assert!((e[0] - angle).abs() < 1e-13, "{angle}: {e:?}");
            assert!(e[1].abs() < 1e-14 && e[2].abs() < 1e-14);
        }
    }
}
