//! Spatial beam of Jonker/Meijaard with six physically meaningful deformation modes.
//!
//! x_k = [r_p; λ_p; r_q; λ_q]  (nx_k = 14: positions and Euler parameters of both ends).
//!
//! Reference triad (ex, ey, ez) from the axis and the orientation vector (local y), see
//! [`super::local_frame`]. Current end triads e_y^p = R(λ_p) ey, e_z^p = R(λ_p) ez, likewise at
//! q; l = ‖r_q − r_p‖, e_l = (r_q − r_p)/l. Auxiliary quantities (paper eq. (2), theory.md §3.3):
//!
//! ```text
//! ē1 = l − l0
//! ē2 = l0 (e_z^p · e_y^q − e_y^p · e_z^q) / 2
//! ē3 = −l0 e_l · e_z^p        ē4 = l0 e_l · e_z^q
//! ē5 =  l0 e_l · e_y^p        ē6 = −l0 e_l · e_y^q
//! ```
//!
//! and the six deformation modes
//!
//! ```text
//! ε1 = ē1 + (2ē3² + ē3ē4 + 2ē4² + 2ē5² + ē5ē6 + 2ē6²)/(30 l0) + c_t ē2²/(2 l0³)
//! ε2 = ē2 + (−ē3ē6 + ē4ē5)/l0
//! ε3 = ē3 + ē2(ē5 + ē6)/(6 l0)      ε4 = ē4 − ē2(ē5 + ē6)/(6 l0)
//! ε5 = ē5 − ē2(ē3 + ē4)/(6 l0)      ε6 = ē6 + ē2(ē3 + ē4)/(6 l0)
//! ```
//!
//! ε1 elongation, ε2 torsion, ε3/ε4 bending about local y at p/q (deflection along local z),
//! ε5/ε6 bending about local z at p/q (deflection along local y). For a sheet whose orientation
//! vector is its width direction (SPACAR Light convention), ε1, ε5, ε6 are the stiff in-plane
//! modes and ε2, ε3, ε4 the compliant ones.
//!
//! Stiffness (theory.md §11.2, SPACAR's storage): S11 = EA/l0, S22 = GJ/l0³, bending blocks
//! EI/(l0³ (1 + Φ)) [[4 + Φ, −(2 − Φ)], [−(2 − Φ), 4 + Φ]], Φ = 12 EI/(kGA l0²).

pub mod closed_form;
pub mod mass;

pub use closed_form::BeamFirst;

use super::{
    fixed_values, local_frame, AccelerationField, ElementKind, FrameError, NodeId, NodeUse,
};
use crate::math::{cst3, dot, mul, norm, rotate, sub, Scalar, SmoothMap, V3};
use crate::section::BeamProps;
use faer::Mat;

/// Spatial beam element (paper eq. (2)).
#[derive(Clone, Debug)]
pub struct Beam {
    /// End nodes p and q (both with position and rotation).
    pub nodes: [NodeId; 2],
    /// l₀ [m]: reference length.
    pub l0: f64,
    /// Reference triad [ex, ey, ez] (rows), ey = orientation vector made orthogonal to ex.
    pub frame: [[f64; 3]; 3],
    /// c_t [m²]: torsion–elongation coupling constant (default 0; Ip/A for a solid section).
    pub ct: f64,
    /// Section stiffnesses [EA, GJ, EIy, EIz] [N, N·m², N·m², N·m²]; zero when not given.
    pub stiffness: [f64; 4],
    /// Shear flexibility EIy/(kGA), EIz/(kGA) [m²]; zero for Euler–Bernoulli.
    pub shear: [f64; 2],
    /// Section and mass data, when the model gives a section: shared by the beams of one
    /// section ([`Beam::set_shared_props`]; 136 bytes each otherwise).
    pub props: Option<std::sync::Arc<BeamProps>>,
}

impl Beam {
    /// A beam between nodes at reference positions `xp`, `xq` with orientation vector `orient`
    /// (local y; `None` for SPACAR's default).
    pub fn new(
        nodes: [NodeId; 2],
        xp: [f64; 3],
        xq: [f64; 3],
        orient: Option<[f64; 3]>,
    ) -> Result<Self, FrameError> {
        let axis = sub(xq, xp);
        let frame = local_frame(axis, orient)?;
        Ok(Self {
            nodes,
            l0: norm(axis),
            frame,
            ct: 0.0,
            stiffness: [0.0; 4],
            shear: [0.0; 2],
            props: None,
        })
    }

    /// Take stiffness, c_t and mass data from section constants.
    pub fn set_props(&mut self, p: BeamProps) {
        self.set_shared_props(std::sync::Arc::new(p));
    }

    /// [`Beam::set_props`] with constants shared with other beams.
    pub fn set_shared_props(&mut self, p: std::sync::Arc<BeamProps>) {
        self.stiffness = [p.ea, p.gj, p.eiy, p.eiz];
        self.shear = p.shear;
        self.ct = p.ct;
        self.props = Some(p);
    }

    /// The auxiliary quantities ē1..ē6 (theory.md §3.3).
    fn aux<T: Scalar>(&self, x: &[T; 14]) -> [T; 6] {
        let rp: V3<T> = [x[0], x[1], x[2]];
        let lp = [x[3], x[4], x[5], x[6]];
        let rq: V3<T> = [x[7], x[8], x[9]];
        let lq = [x[10], x[11], x[12], x[13]];
        let l0 = T::cst(self.l0);
        // chord
        let d = sub(rq, rp);
        let l = dot(d, d).sqrt();
        let el = mul(T::cst(1.0) / l, d);
        // current end triads
        let (ey, ez) = (cst3::<T>(self.frame[1]), cst3::<T>(self.frame[2]));
        let (eyp, ezp) = (rotate(&lp, ey), rotate(&lp, ez));
        let (eyq, ezq) = (rotate(&lq, ey), rotate(&lq, ez));
        [
            l - l0,
            (dot(ezp, eyq) - dot(eyp, ezq)) * l0.scale(0.5),
            -(l0 * dot(el, ezp)),
            l0 * dot(el, ezq),
            l0 * dot(el, eyp),
            -(l0 * dot(el, eyq)),
        ]
    }

    fn bending_block(&self, ei: f64, shear: f64) -> [[f64; 2]; 2] {
        let l3 = self.l0.powi(3);
        let phi = if ei > 0.0 {
            12.0 * shear / (self.l0 * self.l0)
        } else {
            0.0
        };
        let c = ei / (l3 * (1.0 + phi));
        [
            [c * (4.0 + phi), -c * (2.0 - phi)],
            [-c * (2.0 - phi), c * (4.0 + phi)],
        ]
    }
}

impl super::ClosedForm14 for Beam {
    fn first(&self, xk: &[f64; 14]) -> BeamFirst {
        Beam::first(self, xk)
    }
}

impl SmoothMap<14, 6> for Beam {
    /// Paper eq. (2).
    fn eval<T: Scalar>(&self, x: &[T; 14]) -> [T; 6] {
        let [b1, b2, b3, b4, b5, b6] = self.aux(x);
        let l0 = self.l0;
        let quad = (b3 * b3).scale(2.0)
            + b3 * b4
            + (b4 * b4).scale(2.0)
            + (b5 * b5).scale(2.0)
            + b5 * b6
            + (b6 * b6).scale(2.0);
        let e1 = b1 + quad.scale(1.0 / (30.0 * l0)) + (b2 * b2).scale(self.ct / (2.0 * l0.powi(3)));
        let e2 = b2 + (b4 * b5 - b3 * b6).scale(1.0 / l0);
        let t56 = (b2 * (b5 + b6)).scale(1.0 / (6.0 * l0));
        let t34 = (b2 * (b3 + b4)).scale(1.0 / (6.0 * l0));
        [e1, e2, b3 + t56, b4 - t56, b5 - t34, b6 + t34]
    }
}

/// The 14 local coordinates as an array.
fn local14(xk: &[f64]) -> [f64; 14] {
    assert_eq!(
        xk.len(),
        14,
        "beam: local vector has length {} instead of 14",
        xk.len()
    );
    std::array::from_fn(|i| xk[i])
}

const BEAM_MODES: [&str; 6] = [
    "elongation",
    "torsion",
    "bending about y at p",
    "bending about y at q",
    "bending about z at p",
    "bending about z at q",
];

impl ElementKind for Beam {
    fn node_uses(&self) -> Vec<NodeUse> {
        NodeUse::each(&self.nodes, true, true)
    }
    fn ne(&self) -> usize {
        6
    }
    fn mode_name(&self, k: usize, _node_names: &[String]) -> String {
        BEAM_MODES[k].into()
    }
    /// Elongation: a slide along the chord; torsion: a hinge about the beam axis (along the
    /// element); bending about y or z at p or q: a hinge about that axis of the end's triad.
    fn release(&self, k: usize, xk: &[f64]) -> Option<super::Release> {
        if xk.len() < 14 || k >= 6 {
            return None;
        }
        let unit = |v: V3<f64>| {
            let n = norm(v);
            (n > 0.0).then(|| [v[0] / n, v[1] / n, v[2] / n])
        };
        let lp = [xk[3], xk[4], xk[5], xk[6]];
        let lq = [xk[10], xk[11], xk[12], xk[13]];
        match k {
            0 => unit(sub([xk[7], xk[8], xk[9]], [xk[0], xk[1], xk[2]]))
                .map(|axis| super::Release::Slide { axis }),
            1 => unit(rotate(&lp, self.frame[0]))
                .map(|axis| super::Release::Hinge { axis, at: None }),
            _ => {
                let (l, at) = if k.is_multiple_of(2) {
                    (lp, 0)
                } else {
                    (lq, 1)
                };
                let axis = if k < 4 { self.frame[1] } else { self.frame[2] };
                unit(rotate(&l, axis)).map(|axis| super::Release::Hinge { axis, at: Some(at) })
            }
        }
    }
    fn deformations(&self, xk: &[f64]) -> Vec<f64> {
        fixed_values(self, xk)
    }
    /// The chord has zero length or points backwards against the element axis of both end
    /// triads (e_l · e_x^p ≤ 0 and e_l · e_x^q ≤ 0): the element has been pushed through
    /// itself. Measured in the element's own frame, so large rigid rotations (a beam rolled
    /// into a circle) are not inversions; `prev` is not needed.
    fn inverted(&self, xk: &[f64], _prev: &[f64]) -> bool {
        if xk.len() < 14 {
            return false;
        }
        let d = sub([xk[7], xk[8], xk[9]], [xk[0], xk[1], xk[2]]);
        let l = norm(d);
        if l.is_nan() || l <= 1e-12 * self.l0 {
            return true;
        }
        let ex = self.frame[0];
        let exp = rotate(&[xk[3], xk[4], xk[5], xk[6]], ex);
        let exq = rotate(&[xk[10], xk[11], xk[12], xk[13]], ex);
        dot(d, exp) <= 0.0 && dot(d, exq) <= 0.0
    }
    fn jacobian(&self, xk: &[f64]) -> Mat<f64> {
        // closed form (closed_form.rs); the jet version (SmoothMap) is its reference in the tests
        let d = self.first(&local14(xk)).d;
        Mat::from_fn(6, 14, |i, k| d[i][k])
    }
    fn hessian_weighted(&self, xk: &[f64], w: &[f64]) -> Mat<f64> {
        let w: [f64; 6] = std::array::from_fn(|i| w[i]);
        let h = self.first(&local14(xk)).hessian(&w, None);
        Mat::from_fn(14, 14, |i, k| h[i][k])
    }
    fn stiffness(&self) -> Mat<f64> {
        let [ea, gj, eiy, eiz] = self.stiffness;
        let l = self.l0;
        let by = self.bending_block(eiy, self.shear[0]);
        let bz = self.bending_block(eiz, self.shear[1]);
        let mut s = Mat::zeros(6, 6);
        s[(0, 0)] = ea / l;
        s[(1, 1)] = gj / l.powi(3);
        for i in 0..2 {
            for j in 0..2 {
                s[(2 + i, 2 + j)] = by[i][j];
                s[(4 + i, 4 + j)] = bz[i][j];
            }
        }
        s
    }
    fn mass(
        &self,
        xk: &[f64],
        weight: Option<&[[f64; 3]; 3]>,
        rotary: bool,
        out: &mut [f64],
    ) -> bool {
        let Some(m) = mass::local_mass(self, xk, weight, rotary) else {
            return false;
        };
        for (o, v) in out.chunks_exact_mut(14).zip(&m) {
            o.copy_from_slice(v);
        }
        true
    }
    fn inertia_forces(&self, xk: &[f64], vk: &[f64], ak: &[f64], out: &mut [f64]) -> bool {
        let Some(f) = mass::inertia_forces(self, xk, vk, ak) else {
            return false;
        };
        out.copy_from_slice(&f);
        true
    }
    fn velocity_forces(&self, xk: &[f64], vk: &[f64], out: &mut [f64]) -> bool {
        let Some(h) = mass::velocity_forces(self, xk, vk) else {
            return false;
        };
        out.copy_from_slice(&h);
        true
    }
    fn field_loads(&self, xk: &[f64], field: &AccelerationField, out: &mut [([f64; 3], [f64; 3])]) {
        let Some(loads) = mass::field_loads(self, xk, field) else {
            return;
        };
        for (o, (f, m)) in out.iter_mut().zip(loads) {
            for k in 0..3 {
                o.0[k] += f[k];
                o.1[k] += m[k];
            }
        }
    }
    fn closed_form(&self) -> Option<&dyn super::ClosedForm14> {
        Some(self)
    }
    /// |N|/A + |M_y| c_z/Iy + |M_z| c_y/Iz with the end moments M ≈ σ l0, the larger end.
    fn max_stress(&self, sigma: &[f64]) -> Option<f64> {
        let p = self.props.as_deref().filter(|p| p.area > 0.0)?;
        let my = sigma[2].abs().max(sigma[3].abs()) * self.l0;
        let mz = sigma[4].abs().max(sigma[5].abs()) * self.l0;
        Some(sigma[0].abs() / p.area + my * p.fibre[0] / p.i[0] + mz * p.fibre[1] / p.i[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::elements::testing::{check_contract, Contract};
    use crate::math::{euler_from_axis_angle, normalize};

    fn x_of(rp: [f64; 3], lp: [f64; 4], rq: [f64; 3], lq: [f64; 4]) -> [f64; 14] {
        let mut x = [0.0; 14];
        x[0..3].copy_from_slice(&rp);
        x[3..7].copy_from_slice(&lp);
        x[7..10].copy_from_slice(&rq);
        x[10..14].copy_from_slice(&lq);
        x
    }

    #[test]
    fn beam_satisfies_element_contract() {
        let mut b = Beam::new(
            [0, 1],
            [0.1, 0.2, -0.3],
            [0.9, -0.1, 0.4],
            Some([0.3, 1.0, 0.2]),
        )
        .expect("valid frame");
        b.ct = 0.013;
        check_contract(
            &b,
            &[[0.1, 0.2, -0.3], [0.9, -0.1, 0.4]],
            Contract::default(),
        );
    }

    #[test]
    fn closed_form_derivatives_match_jets() {
        // the closed forms of closed_form.rs against the jet evaluation of eq. (2) (SmoothMap):
        // random frames, c_t ≠ 0, large rotations, λ of non-unit length, stretched chords
        use crate::elements::testing::Rng;
        let mut rng = Rng(0x5eed_beef);
        let close = |a: f64, b: f64, scale: f64, what: &str| {
            assert!(
                (a - b).abs() <= 1e-12 * scale,
                "{what}: closed form {a} vs jet {b} (scale {scale})"
            );
        };
        for sample in 0..200 {
            let xp = [rng.next(), rng.next(), rng.next()];
            let axis = rng.unit();
            let len = 0.05 + 2.0 * rng.next().abs();
            let xq = std::array::from_fn(|i| xp[i] + len * axis[i]);
            let mut b = Beam::new([0, 1], xp, xq, Some(rng.unit())).expect("valid frame");
            b.ct = if sample % 3 == 0 {
                0.0
            } else {
                0.05 * rng.next()
            };
            let rp: [f64; 3] = std::array::from_fn(|i| xp[i] + 0.3 * rng.next());
            let rq: [f64; 3] = std::array::from_fn(|i| xq[i] + 0.3 * len * rng.next());
            let sp = 0.3 + 2.0 * rng.next().abs();
            let sq = 0.3 + 2.0 * rng.next().abs();
            let lp = rng.rotation(3.0).map(|v| sp * v);
            let lq = rng.rotation(3.0).map(|v| sq * v);
            let x = x_of(rp, lp, rq, lq);
            let w: [f64; 6] = std::array::from_fn(|_| rng.next() * 10f64.powf(2.0 * rng.next()));
            let (ej, dj) = SmoothMap::jacobian(&b, &x);
            let hj = SmoothMap::hessian_weighted(&b, &x, &w);
            let f = b.first(&x);
            let hf = f.hessian(&w, None);
            let es = ej.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(len);
            let ds = dj.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            let hs = hj.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
            for i in 0..6 {
                close(f.e[i], ej[i], es, "e");
                for k in 0..14 {
                    close(f.d[i][k], dj[i][k], ds, "D");
                }
            }
            for i in 0..14 {
                for k in 0..14 {
                    close(hf[i][k], hj[i][k], hs, "Σ w ∂²e");
                }
            }
            // with a matrix A: Σ w ∂²e + Dᵀ A D
            let mut s = [[0.0; 6]; 6];
            for i in 0..6 {
                for k in 0..=i {
                    s[i][k] = 1e3 * rng.next();
                    s[k][i] = s[i][k];
                }
            }
            let ha = f.hessian(&w, Some(&s));
            let mut dsd = [[0.0; 14]; 14];
            for i in 0..14 {
                for k in 0..14 {
                    for a in 0..6 {
                        for c in 0..6 {
                            dsd[i][k] += dj[a][i] * s[a][c] * dj[c][k];
                        }
                    }
                }
            }
            let ks = dsd.iter().flatten().fold(hs, |m, v| m.max(v.abs()));
            for i in 0..14 {
                for k in 0..14 {
                    close(ha[i][k], hj[i][k] + dsd[i][k], ks, "Σ w ∂²e + Dᵀ S D");
                }
            }
            // in tangent coordinates: Tᵀ (Σ w ∂²e + Dᵀ S D) T, T = diag(I, B_p, I, B_q)
            let bp: [[f64; 3]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| rng.next()));
            let bq: [[f64; 3]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| rng.next()));
            let mut t = [[0.0; 12]; 14];
            for i in 0..3 {
                t[i][i] = 1.0;
                t[7 + i][6 + i] = 1.0;
            }
            for i in 0..4 {
                for j in 0..3 {
                    t[3 + i][3 + j] = bp[i][j];
                    t[10 + i][9 + j] = bq[i][j];
                }
            }
            let ht = f.hessian_tangent(&w, Some(&s), &bp, &bq);
            for r in 0..12 {
                for c in 0..12 {
                    let mut v = 0.0;
                    for i in 0..14 {
                        for k in 0..14 {
                            v += t[i][r] * (hj[i][k] + dsd[i][k]) * t[k][c];
                        }
                    }
                    close(ht[r][c], v, 16.0 * ks, "Tᵀ (Σ w ∂²e + Dᵀ S D) T");
                }
            }
        }
    }

    #[test]
    fn constant_curvature_gives_equal_bending_l0_sin_beta() {
        // closed form (theory.md §3.3, §11.3): each end rotated by β relative to the chord,
        // symmetric arc, gives ε3 = ε4 = l0 sin β and ε1 = −(chord shortening) + second order
        // term; with the chord length kept at l0 the second-order term is 5 ē3²/(30 l0).
        let b = Beam::new([0, 1], [0.0; 3], [2.0, 0.0, 0.0], Some([0.0, 1.0, 0.0])).unwrap();
        let beta = 0.2;
        // bending about local y (= global y): p rotated by −β, q by +β about y
        let lp = euler_from_axis_angle([0.0, 1.0, 0.0], -beta);
        let lq = euler_from_axis_angle([0.0, 1.0, 0.0], beta);
        let e = b.value(&x_of([0.0; 3], lp, [2.0, 0.0, 0.0], lq));
        let s = 2.0 * beta.sin();
        assert!(
            (e[2] - s).abs() < 1e-14 && (e[3] - s).abs() < 1e-14,
            "{e:?}"
        );
        assert!((e[0] - 5.0 * s * s / 60.0).abs() < 1e-14, "{e:?}");
        for k in [1, 4, 5] {
            assert!(e[k].abs() < 1e-14);
        }
    }

    #[test]
    fn twist_gives_l0_sin_phi_torsion() {
        let b = Beam::new([0, 1], [0.0; 3], [0.0, 0.0, 0.5], None).unwrap();
        let phi = 0.3;
        let lq = euler_from_axis_angle([0.0, 0.0, 1.0], phi);
        let e = b.value(&x_of([0.0; 3], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.5], lq));
        assert!((e[1] - 0.5 * phi.sin()).abs() < 1e-14, "{e:?}");
    }

    #[test]
    fn torsion_elongation_coupling_matches_helix_closed_form() {
        // theory.md §3.3: with ε1 held at zero, a uniform twist θ shortens the chord by
        // c_t ē2²/(2 l0³) (first order in c_t), ē2 = l0 sin θ.
        let mut b = Beam::new([0, 1], [0.0; 3], [1.0, 0.0, 0.0], None).unwrap();
        b.ct = 2e-4;
        let th: f64 = 0.1;
        let lq = euler_from_axis_angle([1.0, 0.0, 0.0], th);
        let e = b.value(&x_of([0.0; 3], [1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0], lq));
        let e2 = th.sin();
        assert!((e[0] - b.ct * e2 * e2 / 2.0).abs() < 1e-15);
    }

    #[test]
    fn beam_rejects_orientation_along_axis() {
        let r = Beam::new(
            [0, 1],
            [0.0; 3],
            [1.0, 1.0, 0.0],
            Some(normalize([2.0, 2.0, 0.0])),
        );
        assert_eq!(r.unwrap_err(), FrameError::ParallelOrientation);
    }

    #[test]
    fn stiffness_row_sum_is_2ei_over_l3() {
        // theory.md §11.2: S33 + S34 = 2 EIy/l0³ independent of the shear flexibility
        let mut b = Beam::new([0, 1], [0.0; 3], [0.05, 0.0, 0.0], None).unwrap();
        b.stiffness = [1.0, 2.0, 3.0, 4.0];
        b.shear = [1e-5, 2e-5];
        let s = b.stiffness();
        let l3 = 0.05f64.powi(3);
        assert!(((s[(2, 2)] + s[(2, 3)]) - 6.0 / l3).abs() < 1e-9 * 6.0 / l3);
        assert!(((s[(4, 4)] + s[(5, 4)]) - 8.0 / l3).abs() < 1e-9 * 8.0 / l3);
    }
}
