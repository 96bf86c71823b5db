//! Truss: translational nodes p, q; one deformation, the elongation.
//!
//! x_k = [r_p; r_q]  (nx_k = 6)            e₁ = l − l₀,  l = ‖r_q − r_p‖
//! D   = [−nᵀ  nᵀ],  n = (r_q − r_p)/l     ∂²e₁/∂x² = [P −P; −P P],  P = (I − n nᵀ)/l
//!
//! Source: theory.md §3.2; paper §3.3. Stiffness σ₁ = (EA/l₀) e₁ (theory.md §11.4).

use super::{smooth_map_derivatives, ElementKind, NodeId, NodeUse};
use crate::math::{dot, sub, Scalar, SmoothMap};
use faer::Mat;

/// Truss (rod) with axial stiffness only.
#[derive(Clone, Debug)]
pub struct Truss {
    /// End nodes p and q.
    pub nodes: [NodeId; 2],
    /// l₀ [m]: length in the reference configuration.
    pub l0: f64,
    /// EA [N]: axial stiffness; σ₁ = (EA/l₀) e₁. Zero when not given.
    pub ea: f64,
}

impl Truss {
    /// A truss between nodes at reference positions `xp`, `xq`.
    pub fn new(nodes: [NodeId; 2], xp: [f64; 3], xq: [f64; 3]) -> Self {
        let l0 = crate::math::norm(sub(xq, xp));
        Self { nodes, l0, ea: 0.0 }
    }
}

impl SmoothMap<6, 1> for Truss {
    fn eval<T: Scalar>(&self, x: &[T; 6]) -> [T; 1] {
        // e₁ = ‖r_q − r_p‖ − l₀
        let d = sub([x[3], x[4], x[5]], [x[0], x[1], x[2]]);
        [dot(d, d).sqrt() - T::cst(self.l0)]
    }
}

impl ElementKind for Truss {
    fn node_uses(&self) -> Vec<NodeUse> {
        NodeUse::each(&self.nodes, true, false)
    }
    fn ne(&self) -> usize {
        1
    }
    fn mode_name(&self, _k: usize, _node_names: &[String]) -> String {
        "elongation".into()
    }
    /// A slide along the chord.
    fn release(&self, _k: usize, xk: &[f64]) -> Option<super::Release> {
        let d = sub([xk[3], xk[4], xk[5]], [xk[0], xk[1], xk[2]]);
        let n = dot(d, d).sqrt();
        (n > 0.0).then(|| super::Release::Slide {
            axis: [d[0] / n, d[1] / n, d[2] / n],
        })
    }
    smooth_map_derivatives!();
    /// The chord has passed through zero length since `prev`: it points against the previous
    /// chord and the straight path between the two chords passes within l₀/10 of zero (a
    /// rotation of the truss by more than about 170° in one step counts too: it is not a
    /// resolved path either).
    fn inverted(&self, xk: &[f64], prev: &[f64]) -> bool {
        if xk.len() < 6 || prev.len() < 6 {
            return false;
        }
        let d = sub([xk[3], xk[4], xk[5]], [xk[0], xk[1], xk[2]]);
        let p = sub([prev[3], prev[4], prev[5]], [prev[0], prev[1], prev[2]]);
        let l = dot(d, d).sqrt();
        if l.is_nan() || l <= 1e-12 * self.l0 {
            return true;
        }
        if dot(d, p) >= 0.0 {
            return false;
        }
        // distance of the origin to the segment p + s (d − p), 0 ≤ s ≤ 1
        let dp = sub(d, p);
        let s = (-dot(p, dp) / dot(dp, dp)).clamp(0.0, 1.0);
        let c = [p[0] + s * dp[0], p[1] + s * dp[1], p[2] + s * dp[2]];
        dot(c, c).sqrt() < 0.1 * self.l0
    }
    fn stiffness(&self) -> Mat<f64> {
        Mat::from_fn(1, 1, |_, _| self.ea / self.l0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::testing::{check_contract, Contract};

    #[test]
    fn truss_satisfies_element_contract() {
        let t = Truss::new([0, 1], [0.1, -0.2, 0.3], [1.0, 0.5, -0.4]);
        check_contract(
            &t,
            &[[0.1, -0.2, 0.3], [1.0, 0.5, -0.4]],
            Contract::default(),
        );
    }

    #[test]
    fn truss_jacobian_is_unit_direction() {
        // closed form D = [−nᵀ nᵀ]
        let t = Truss::new([0, 1], [0.0; 3], [3.0, 4.0, 0.0]);
        let d = ElementKind::jacobian(&t, &[0.0, 0.0, 0.0, 3.0, 4.0, 0.0]);
        let n = [0.6, 0.8, 0.0];
        for i in 0..3 {
            assert!((d[(0, i)] + n[i]).abs() < 1e-15 && (d[(0, 3 + i)] - n[i]).abs() < 1e-15);
        }
    }
}
