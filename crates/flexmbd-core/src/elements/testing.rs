//! Element contract tests, run for every element type (style.md §9):
//! - e = 0 in the reference configuration;
//! - e invariant under random rigid-body motions (of the reference and of deformed states);
//! - e independent of the length of each λ (so D λ = 0 for each rotational node);
//! - the analytic Jacobian D against central differences of e;
//! - the weighted Hessian Σ wᵢ ∂²eᵢ/∂x² against central differences of wᵀD.

use super::ElementKind;
use super::EULER_IDENTITY;
use crate::math::{add, euler_from_axis_angle, euler_mul, normalize, rotate};

/// Tolerances of the contract check.
#[derive(Clone, Copy, Debug)]
pub struct Contract {
    /// Finite-difference step.
    pub h: f64,
    /// Absolute tolerance on D and Hessian entries (relative to their scale).
    pub tol: f64,
    /// Number of random configurations.
    pub samples: usize,
}

impl Default for Contract {
    fn default() -> Self {
        // central differences with h = 1e-6 have truncation ~h² and rounding ~eps/h ≈ 1e-10
        Self {
            h: 1e-6,
            tol: 1e-7,
            samples: 6,
        }
    }
}

/// Deterministic splitmix64 stream for reproducible tests.
pub struct Rng(pub u64);
impl Rng {
    /// Uniform in [−1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
    /// Random unit vector.
    pub fn unit(&mut self) -> [f64; 3] {
        loop {
            let v = [self.next(), self.next(), self.next()];
            let n = crate::math::norm(v);
            if n > 0.1 && n < 1.0 {
                return normalize(v);
            }
        }
    }
    /// Random rotation (Euler parameters) with angle up to `max_angle`.
    pub fn rotation(&mut self, max_angle: f64) -> [f64; 4] {
        let ax = self.unit();
        euler_from_axis_angle(ax, max_angle * self.next())
    }
}

/// Build x_k from per-use positions and rotations.
fn assemble(el: &dyn ElementKind, pos: &[[f64; 3]], rot: &[[f64; 4]]) -> Vec<f64> {
    let mut x = Vec::new();
    for (i, u) in el.node_uses().iter().enumerate() {
        if u.pos {
            x.extend_from_slice(&pos[i]);
        }
        if u.rot {
            x.extend_from_slice(&rot[i]);
        }
    }
    x
}

#[track_caller]
fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs())),
        "{what}: {a} vs {b}"
    );
}

/// Run the whole contract for `el`, whose node uses have reference positions `ref_pos`.
#[track_caller]
pub fn check_contract(el: &dyn ElementKind, ref_pos: &[[f64; 3]], c: Contract) {
    let uses = el.node_uses();
    assert_eq!(uses.len(), ref_pos.len());
    let ne = el.ne();
    let ident = vec![EULER_IDENTITY; uses.len()];
    let mut rng = Rng(0x5EED ^ ne as u64);

    // zero in the reference configuration
    let x_ref = assemble(el, ref_pos, &ident);
    for (k, e) in el.deformations(&x_ref).iter().enumerate() {
        assert!(
            e.abs() < 1e-14,
            "mode {k} is {e} in the reference configuration"
        );
    }

    for sample in 0..c.samples {
        // a deformed configuration: perturbed positions and rotations
        let pos: Vec<[f64; 3]> = ref_pos
            .iter()
            .map(|p| add(*p, [0.1 * rng.next(), 0.1 * rng.next(), 0.1 * rng.next()]))
            .collect();
        let rot: Vec<[f64; 4]> = (0..uses.len()).map(|_| rng.rotation(0.5)).collect();
        let x = assemble(el, &pos, &rot);
        let e = el.deformations(&x);

        // invariance under a rigid-body motion r ↦ Q r + t, λ ↦ q ⊗ λ
        let q = rng.rotation(3.0);
        let t = [rng.next(), rng.next(), rng.next()];
        let moved = |p: &[[f64; 3]], l: &[[f64; 4]]| {
            let pm: Vec<[f64; 3]> = p.iter().map(|p| add(rotate(&q, *p), t)).collect();
            let lm: Vec<[f64; 4]> = l.iter().map(|l| euler_mul(&q, l)).collect();
            assemble(el, &pm, &lm)
        };
        for (k, v) in el.deformations(&moved(ref_pos, &ident)).iter().enumerate() {
            assert!(
                v.abs() < 1e-12,
                "sample {sample}: moved reference, mode {k} = {v}"
            );
        }
        for (k, (a, b)) in e
            .iter()
            .zip(el.deformations(&moved(&pos, &rot)))
            .enumerate()
        {
            assert_close(
                *a,
                b,
                1e-11,
                &format!("sample {sample}: invariance of mode {k}"),
            );
        }

        // independence of the length of λ
        let scaled: Vec<[f64; 4]> = rot.iter().map(|l| l.map(|v| 1.7 * v)).collect();
        for (k, (a, b)) in e
            .iter()
            .zip(el.deformations(&assemble(el, &pos, &scaled)))
            .enumerate()
        {
            assert_close(
                *a,
                b,
                1e-12,
                &format!("sample {sample}: λ scaling, mode {k}"),
            );
        }

        // D against central differences
        let d = el.jacobian(&x);
        assert_eq!((d.nrows(), d.ncols()), (ne, x.len()));
        let w: Vec<f64> = (0..ne).map(|_| rng.next()).collect();
        let hw = el.hessian_weighted(&x, &w);
        for j in 0..x.len() {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[j] += c.h;
            xm[j] -= c.h;
            let (ep, em) = (el.deformations(&xp), el.deformations(&xm));
            for i in 0..ne {
                let fd = (ep[i] - em[i]) / (2.0 * c.h);
                assert_close(d[(i, j)], fd, c.tol, &format!("D[{i},{j}]"));
            }
            // Hessian column j against differences of wᵀD
            let (dp, dm) = (el.jacobian(&xp), el.jacobian(&xm));
            for k in 0..x.len() {
                let fd: f64 = (0..ne)
                    .map(|i| w[i] * (dp[(i, k)] - dm[(i, k)]))
                    .sum::<f64>()
                    / (2.0 * c.h);
                assert_close(hw[(k, j)], fd, c.tol, &format!("H[{k},{j}]"));
            }
        }
        // symmetry of the Hessian
        for a in 0..x.len() {
            for b in 0..a {
                assert_close(hw[(a, b)], hw[(b, a)], 1e-12, "Hessian symmetry");
            }
        }
    }
    // stiffness is symmetric
    let s = el.stiffness();
    for a in 0..ne {
        for b in 0..a {
            assert_close(s[(a, b)], s[(b, a)], 1e-14, "stiffness symmetry");
        }
    }
}
