//! Closed-form first and second derivatives of the beam deformations (paper eq. (2)).
//!
//! Same functions as the generic [`SmoothMap`](crate::math::SmoothMap) implementation in
//! [`super`] (which stays the reference, see the tests there), evaluated analytically in
//! fixed-size arrays: no jets, no heap allocation.
//!
//! Reduced variables z = (d, λ_p, λ_q) with d = r_q − r_p (11 values). Every auxiliary quantity
//! ē₂…ē₆ is l0 × a dot product of two vector functions of different groups,
//! e_l(d) = d/‖d‖ and R(λ)c for c ∈ {e_y, e_z}. For a fixed vector a,
//!
//! ```text
//! aᵀ R(λ) c = λᵀ M(a, c) λ / λᵀλ,
//! M(a, c) = [ a·c      (c × a)ᵀ                  ]
//!           [ c × a    −(a·c) I + a cᵀ + c aᵀ    ]
//! ```
//!
//! a Rayleigh quotient f = λᵀMλ/n, n = λᵀλ, with ∇f = (2/n)(Mλ − fλ) and
//! ∇²f = (2/n)(M − f I − λ∇fᵀ − ∇fλᵀ). For e_l · c with c fixed:
//! ∇ = P c / l, ∇² = −(c e_lᵀ + e_l cᵀ + (e_l·c)(I − 3 e_l e_lᵀ))/l², P = I − e_l e_lᵀ; and
//! ∇²l = P/l.
//!
//! With B = ∂ē/∂z (6 × 11), G = ∂ε/∂ē and the constant second derivatives of the quadratic
//! map ε = g(ē):
//!
//! ```text
//! D_z = G B,    Σᵢ wᵢ ∂²εᵢ/∂z² = Σ_k v_k ∂²ē_k/∂z² + Bᵀ W B,
//! v = Gᵀ w,     W = Σᵢ wᵢ ∂²gᵢ/∂ē²,
//! ```
//!
//! where Σ_k v_k ∂²ē_k/∂z² is built block by block from the formulas above (the weighted sum of
//! the dot products is again a single dot product or Rayleigh quotient per block). Finally
//! d = r_q − r_p expands z to the 14 element coordinates.

use super::Beam;

/// z index and sign of each of the 14 element coordinates (d = r_q − r_p).
const ZMAP: [(usize, f64); 14] = [
    (0, -1.0),
    (1, -1.0),
    (2, -1.0),
    (3, 1.0),
    (4, 1.0),
    (5, 1.0),
    (6, 1.0),
    (0, 1.0),
    (1, 1.0),
    (2, 1.0),
    (7, 1.0),
    (8, 1.0),
    (9, 1.0),
    (10, 1.0),
];

type M3 = [[f64; 3]; 3];
type M4 = [[f64; 4]; 4];
/// 3 × 4 Jacobian of R(λ)c with respect to λ.
type J34 = [[f64; 4]; 3];

fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross3(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// R(λ)c and its Jacobian with respect to λ (λ of any nonzero length).
fn rot_jac(l: &[f64; 4], c: &[f64; 3]) -> ([f64; 3], J34) {
    let lv = [l[1], l[2], l[3]];
    let n = l[0] * l[0] + dot3(&lv, &lv);
    let inv = 1.0 / n;
    let lc = dot3(&lv, c);
    let c0 = l[0] * l[0] - dot3(&lv, &lv);
    let lxc = cross3(&lv, c);
    // Q(λ)c = (λ0² − λ̄ᵀλ̄) c + 2 λ̄ (λ̄ᵀc) + 2 λ0 λ̄ × c
    let q: [f64; 3] = std::array::from_fn(|i| c0 * c[i] + 2.0 * lv[i] * lc + 2.0 * l[0] * lxc[i]);
    let r: [f64; 3] = std::array::from_fn(|i| q[i] * inv);
    // ∂(Qc)/∂λ0 = 2 λ0 c + 2 λ̄ × c
    // ∂(Qc)/∂λ̄_j = −2 λ̄_j c + 2 e_j (λ̄ᵀc) + 2 λ̄ c_j + 2 λ0 e_j × c
    let mut dq = [[0.0; 4]; 3];
    for i in 0..3 {
        dq[i][0] = 2.0 * (l[0] * c[i] + lxc[i]);
        for j in 0..3 {
            dq[i][1 + j] = 2.0 * (-lv[j] * c[i] + lv[i] * c[j]);
        }
        dq[i][1 + i] += 2.0 * lc;
    }
    // 2 λ0 e_j × c: e_x × c = (0, −c_z, c_y), e_y × c = (c_z, 0, −c_x), e_z × c = (−c_y, c_x, 0)
    let t = 2.0 * l[0];
    dq[1][1] -= t * c[2];
    dq[2][1] += t * c[1];
    dq[0][2] += t * c[2];
    dq[2][2] -= t * c[0];
    dq[0][3] -= t * c[1];
    dq[1][3] += t * c[0];
    // J = ∂(Qc)/∂λ / n − R c (2λ/n)ᵀ
    let mut jac = [[0.0; 4]; 3];
    for i in 0..3 {
        for k in 0..4 {
            jac[i][k] = (dq[i][k] - 2.0 * r[i] * l[k]) * inv;
        }
    }
    (r, jac)
}

/// Adds M(a, c) (module docs) to `m`.
fn add_m(m: &mut M4, a: &[f64; 3], c: &[f64; 3]) {
    let ac = dot3(a, c);
    let cxa = cross3(c, a);
    m[0][0] += ac;
    for j in 0..3 {
        m[0][1 + j] += cxa[j];
        m[1 + j][0] += cxa[j];
        for k in 0..3 {
            m[1 + j][1 + k] += a[j] * c[k] + c[j] * a[k];
        }
        m[1 + j][1 + j] -= ac;
    }
}

/// Hessian of the Rayleigh quotient λᵀMλ/λᵀλ.
fn rayleigh_hessian(m: &M4, l: &[f64; 4]) -> M4 {
    let n = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + l[3] * l[3];
    let ml: [f64; 4] = std::array::from_fn(|i| (0..4).map(|k| m[i][k] * l[k]).sum());
    let f = (0..4).map(|i| l[i] * ml[i]).sum::<f64>() / n;
    let s = 2.0 / n;
    let g: [f64; 4] = std::array::from_fn(|i| s * (ml[i] - f * l[i]));
    let mut h = [[0.0; 4]; 4];
    for i in 0..4 {
        for k in 0..4 {
            h[i][k] = s * (m[i][k] - l[i] * g[k] - g[i] * l[k]);
        }
        h[i][i] -= s * f;
    }
    h
}

/// Jᵀ a (4-vector) for a 3 × 4 Jacobian.
fn jt(j: &J34, a: &[f64; 3]) -> [f64; 4] {
    std::array::from_fn(|k| j[0][k] * a[0] + j[1][k] * a[1] + j[2][k] * a[2])
}

/// Beam deformations with their first derivatives, and what the weighted Hessian needs.
#[derive(Clone, Debug)]
pub struct BeamFirst {
    /// ε (6).
    pub e: [f64; 6],
    /// D = ∂ε/∂x_k (6 × 14).
    pub d: [[f64; 14]; 6],
    l0: f64,
    ct: f64,
    ey: [f64; 3],
    ez: [f64; 3],
    lp: [f64; 4],
    lq: [f64; 4],
    l: f64,
    el: [f64; 3],
    p: M3,
    yp: [f64; 3],
    zp: [f64; 3],
    yq: [f64; 3],
    zq: [f64; 3],
    jyp: J34,
    jzp: J34,
    jyq: J34,
    jzq: J34,
    /// B = ∂ē/∂z (6 × 11).
    bz: [[f64; 11]; 6],
    /// G = ∂ε/∂ē (6 × 6).
    g: [[f64; 6]; 6],
}

impl Beam {
    /// Deformations and their Jacobian in closed form (same as the jet evaluation of
    /// [`SmoothMap`](crate::math::SmoothMap)); [`BeamFirst::hessian`] completes the second
    /// derivatives at the same state.
    pub fn first(&self, x: &[f64; 14]) -> BeamFirst {
        let l0 = self.l0;
        let (ey, ez) = (self.frame[1], self.frame[2]);
        let lp = [x[3], x[4], x[5], x[6]];
        let lq = [x[10], x[11], x[12], x[13]];
        let d = [x[7] - x[0], x[8] - x[1], x[9] - x[2]];
        let l = dot3(&d, &d).sqrt();
        let el = [d[0] / l, d[1] / l, d[2] / l];
        let mut p = [[0.0; 3]; 3];
        for i in 0..3 {
            for k in 0..3 {
                p[i][k] = -el[i] * el[k];
            }
            p[i][i] += 1.0;
        }
        let (yp, jyp) = rot_jac(&lp, &ey);
        let (zp, jzp) = rot_jac(&lp, &ez);
        let (yq, jyq) = rot_jac(&lq, &ey);
        let (zq, jzq) = rot_jac(&lq, &ez);
        let h = 0.5 * l0;
        let b = [
            l - l0,
            (dot3(&zp, &yq) - dot3(&yp, &zq)) * h,
            -(l0 * dot3(&el, &zp)),
            l0 * dot3(&el, &zq),
            l0 * dot3(&el, &yp),
            -(l0 * dot3(&el, &yq)),
        ];
        // B = ∂ē/∂z
        let mut bz = [[0.0; 11]; 6];
        bz[0][..3].copy_from_slice(&el);
        let pl = |c: &[f64; 3], s: f64| -> [f64; 3] {
            // s P c / l
            let ec = dot3(&el, c);
            std::array::from_fn(|i| s * (c[i] - ec * el[i]) / l)
        };
        let g2p = {
            let a = jt(&jzp, &yq);
            let c = jt(&jyp, &zq);
            std::array::from_fn::<f64, 4, _>(|k| h * (a[k] - c[k]))
        };
        let g2q = {
            let a = jt(&jyq, &zp);
            let c = jt(&jzq, &yp);
            std::array::from_fn::<f64, 4, _>(|k| h * (a[k] - c[k]))
        };
        bz[1][3..7].copy_from_slice(&g2p);
        bz[1][7..11].copy_from_slice(&g2q);
        bz[2][..3].copy_from_slice(&pl(&zp, -l0));
        bz[2][3..7].copy_from_slice(&jt(&jzp, &el).map(|v| -l0 * v));
        bz[3][..3].copy_from_slice(&pl(&zq, l0));
        bz[3][7..11].copy_from_slice(&jt(&jzq, &el).map(|v| l0 * v));
        bz[4][..3].copy_from_slice(&pl(&yp, l0));
        bz[4][3..7].copy_from_slice(&jt(&jyp, &el).map(|v| l0 * v));
        bz[5][..3].copy_from_slice(&pl(&yq, -l0));
        bz[5][7..11].copy_from_slice(&jt(&jyq, &el).map(|v| -l0 * v));
        // ε = g(ē) and G = ∂g/∂ē
        let [b1, b2, b3, b4, b5, b6] = b;
        let ct = self.ct;
        let c30 = 1.0 / (30.0 * l0);
        let k6 = 1.0 / (6.0 * l0);
        let l03 = l0 * l0 * l0;
        let quad =
            2.0 * b3 * b3 + b3 * b4 + 2.0 * b4 * b4 + 2.0 * b5 * b5 + b5 * b6 + 2.0 * b6 * b6;
        let (s56, s34) = (b5 + b6, b3 + b4);
        let e = [
            b1 + quad * c30 + b2 * b2 * (ct / (2.0 * l03)),
            b2 + (b4 * b5 - b3 * b6) / l0,
            b3 + b2 * s56 * k6,
            b4 - b2 * s56 * k6,
            b5 - b2 * s34 * k6,
            b6 + b2 * s34 * k6,
        ];
        let g = [
            [
                1.0,
                ct * b2 / l03,
                (4.0 * b3 + b4) * c30,
                (b3 + 4.0 * b4) * c30,
                (4.0 * b5 + b6) * c30,
                (b5 + 4.0 * b6) * c30,
            ],
            [0.0, 1.0, -b6 / l0, b5 / l0, b4 / l0, -b3 / l0],
            [0.0, k6 * s56, 1.0, 0.0, k6 * b2, k6 * b2],
            [0.0, -k6 * s56, 0.0, 1.0, -k6 * b2, -k6 * b2],
            [0.0, -k6 * s34, -k6 * b2, -k6 * b2, 1.0, 0.0],
            [0.0, k6 * s34, k6 * b2, k6 * b2, 0.0, 1.0],
        ];
        // D_z = G B, expanded to x
        let mut dx = [[0.0; 14]; 6];
        for i in 0..6 {
            let mut row = [0.0; 11];
            for k in 0..6 {
                let gik = g[i][k];
                if gik != 0.0 {
                    for (r, bv) in row.iter_mut().zip(&bz[k]) {
                        *r += gik * bv;
                    }
                }
            }
            for (a, &(z, s)) in ZMAP.iter().enumerate() {
                dx[i][a] = s * row[z];
            }
        }
        BeamFirst {
            e,
            d: dx,
            l0,
            ct,
            ey,
            ez,
            lp,
            lq,
            l,
            el,
            p,
            yp,
            zp,
            yq,
            zq,
            jyp,
            jzp,
            jyq,
            jzq,
            bz,
            g,
        }
    }
}

impl BeamFirst {
    /// The blocks of Σ_k v_k ∂²ē_k/∂z² shared by [`Self::hessian`] and
    /// [`Self::hessian_tangent`]: the δdδd block (3 × 3) and the Rayleigh-quotient blocks
    /// λpλp and λqλq (4 × 4).
    fn curvature_blocks(&self, v: &[f64; 6], l0: f64, l: f64) -> ([[f64; 3]; 3], M4, M4) {
        let (el, p) = (&self.el, &self.p);
        // dd: v1 P/l + ∇²(e_l · c), c = l0(−v3 zp + v4 zq + v5 yp − v6 yq)
        let c: [f64; 3] = std::array::from_fn(|i| {
            l0 * (-v[2] * self.zp[i] + v[3] * self.zq[i] + v[4] * self.yp[i] - v[5] * self.yq[i])
        });
        let ec = dot3(el, &c);
        let il2 = 1.0 / (l * l);
        let mut dd = [[0.0; 3]; 3];
        for i in 0..3 {
            for k in 0..3 {
                dd[i][k] = v[0] * p[i][k] / l
                    - (c[i] * el[k] + el[i] * c[k] - 3.0 * ec * el[i] * el[k]) * il2;
            }
            dd[i][i] -= ec * il2;
        }
        // λpλp: Rayleigh quotient of M(a, ez) + M(b, ey),
        // a = v2 (l0/2) yq − v3 l0 el, b = −v2 (l0/2) zq + v5 l0 el
        let hl = 0.5 * l0;
        let mut m = [[0.0; 4]; 4];
        let a_: [f64; 3] = std::array::from_fn(|i| v[1] * hl * self.yq[i] - v[2] * l0 * el[i]);
        let b_: [f64; 3] = std::array::from_fn(|i| -v[1] * hl * self.zq[i] + v[4] * l0 * el[i]);
        add_m(&mut m, &a_, &self.ez);
        add_m(&mut m, &b_, &self.ey);
        let hp = rayleigh_hessian(&m, &self.lp);
        // λqλq: M(a, ey) + M(b, ez), a = v2 (l0/2) zp − v6 l0 el, b = −v2 (l0/2) yp + v4 l0 el
        let mut m = [[0.0; 4]; 4];
        let a_: [f64; 3] = std::array::from_fn(|i| v[1] * hl * self.zp[i] - v[5] * l0 * el[i]);
        let b_: [f64; 3] = std::array::from_fn(|i| -v[1] * hl * self.yp[i] + v[3] * l0 * el[i]);
        add_m(&mut m, &a_, &self.ey);
        add_m(&mut m, &b_, &self.ez);
        let hq = rayleigh_hessian(&m, &self.lq);
        (dd, hp, hq)
    }
    /// Σᵢ wᵢ ∂²εᵢ/∂x² + Dᵀ A D (14 × 14), for weights w and a symmetric 6 × 6 matrix A (e.g. the
    /// stiffness S, giving the tangent stiffness; zero for the weighted Hessian alone).
    pub fn hessian(&self, w: &[f64; 6], a: Option<&[[f64; 6]; 6]>) -> [[f64; 14]; 14] {
        let hz = self.hessian_z(w, a);
        let mut hx = [[0.0; 14]; 14];
        for (r, &(zr, sr)) in ZMAP.iter().enumerate() {
            for (c, &(zc, sc)) in ZMAP.iter().enumerate() {
                hx[r][c] = sr * sc * hz[zr][zc];
            }
        }
        hx
    }

    /// Tᵀ (Σᵢ wᵢ ∂²εᵢ/∂x² + Dᵀ A D) T (12 × 12) for T = diag(I₃, B_p, I₃, B_q), i.e. in the
    /// coordinates (r_p, δ_p, r_q, δ_q) with λ_p = B_p δ_p, λ_q = B_q δ_q (4 × 3 bases of
    /// increments of the Euler parameters, e.g. of λ⊥). Computed in the nine variables
    /// (d, δ_p, δ_q) without forming the 14 × 14 matrix.
    pub fn hessian_tangent(
        &self,
        w: &[f64; 6],
        a: Option<&[[f64; 6]; 6]>,
        bp: &[[f64; 3]; 4],
        bq: &[[f64; 3]; 4],
    ) -> [[f64; 12]; 12] {
        let (l0, l) = (self.l0, self.l);
        let (v, wm) = self.weights(w, a);
        // J B (3 × 3) for the four rotated vectors
        let jb = |j: &J34, b: &[[f64; 3]; 4]| -> [[f64; 3]; 3] {
            std::array::from_fn(|r| {
                std::array::from_fn(|c| (0..4).map(|i| j[r][i] * b[i][c]).sum())
            })
        };
        let (jyp, jzp) = (jb(&self.jyp, bp), jb(&self.jzp, bp));
        let (jyq, jzq) = (jb(&self.jyq, bq), jb(&self.jzq, bq));
        // B_9 = ∂ē/∂(d, δ_p, δ_q)
        let mut b9 = [[0.0; 9]; 6];
        for (k, row) in self.bz.iter().enumerate() {
            b9[k][..3].copy_from_slice(&row[..3]);
            for j in 0..3 {
                b9[k][3 + j] = (0..4).map(|i| row[3 + i] * bp[i][j]).sum();
                b9[k][6 + j] = (0..4).map(|i| row[7 + i] * bq[i][j]).sum();
            }
        }
        // B_9ᵀ W B_9
        let mut wb = [[0.0; 9]; 6];
        for i in 0..6 {
            for k in 0..6 {
                let c = wm[i][k];
                if c != 0.0 {
                    for (o, bv) in wb[i].iter_mut().zip(&b9[k]) {
                        *o += c * bv;
                    }
                }
            }
        }
        // (symmetric: the upper triangle, mirrored)
        let mut h = [[0.0; 9]; 9];
        for r in 0..9 {
            for c in r..9 {
                let v: f64 = (0..6).map(|k| b9[k][r] * wb[k][c]).sum();
                h[r][c] = v;
                h[c][r] = v;
            }
        }
        let p = &self.p;
        let hl = 0.5 * l0;
        let (dd, hp, hq) = self.curvature_blocks(&v, l0, l);
        for i in 0..3 {
            for k in 0..3 {
                h[i][k] += dd[i][k];
            }
        }
        let btab = |h4: &M4, b: &[[f64; 3]; 4]| -> [[f64; 3]; 3] {
            let hb: [[f64; 3]; 4] = std::array::from_fn(|i| {
                std::array::from_fn(|c| (0..4).map(|k| h4[i][k] * b[k][c]).sum())
            });
            std::array::from_fn(|r| {
                std::array::from_fn(|c| (0..4).map(|i| b[i][r] * hb[i][c]).sum())
            })
        };
        let (hp3, hq3) = (btab(&hp, bp), btab(&hq, bq));
        for i in 0..3 {
            for k in 0..3 {
                h[3 + i][3 + k] += hp3[i][k];
                h[6 + i][6 + k] += hq3[i][k];
            }
        }
        // dδp: (P/l) l0 (−v3 Jzp + v5 Jyp) B_p; dδq: (P/l) l0 (v4 Jzq − v6 Jyq) B_q
        let s = l0 / l;
        for i in 0..3 {
            for k in 0..3 {
                let (mut sp, mut sq) = (0.0, 0.0);
                for m in 0..3 {
                    sp += p[i][m] * (-v[2] * jzp[m][k] + v[4] * jyp[m][k]);
                    sq += p[i][m] * (v[3] * jzq[m][k] - v[5] * jyq[m][k]);
                }
                h[i][3 + k] += s * sp;
                h[3 + k][i] += s * sp;
                h[i][6 + k] += s * sq;
                h[6 + k][i] += s * sq;
            }
        }
        // δpδq: v2 (l0/2)((Jzp B_p)ᵀ (Jyq B_q) − (Jyp B_p)ᵀ (Jzq B_q))
        let s = v[1] * hl;
        if s != 0.0 {
            for i in 0..3 {
                for k in 0..3 {
                    let mut t = 0.0;
                    for m in 0..3 {
                        t += jzp[m][i] * jyq[m][k] - jyp[m][i] * jzq[m][k];
                    }
                    h[3 + i][6 + k] += s * t;
                    h[6 + k][3 + i] += s * t;
                }
            }
        }
        // expand d = r_q − r_p: (r_p, δ_p, r_q, δ_q) → (d, δ_p, δ_q) with signs
        const MAP: [(usize, f64); 12] = [
            (0, -1.0),
            (1, -1.0),
            (2, -1.0),
            (3, 1.0),
            (4, 1.0),
            (5, 1.0),
            (0, 1.0),
            (1, 1.0),
            (2, 1.0),
            (6, 1.0),
            (7, 1.0),
            (8, 1.0),
        ];
        let mut out = [[0.0; 12]; 12];
        for (r, &(zr, sr)) in MAP.iter().enumerate() {
            for (c, &(zc, sc)) in MAP.iter().enumerate() {
                out[r][c] = sr * sc * h[zr][zc];
            }
        }
        out
    }

    /// v = Gᵀ w and W = Σᵢ wᵢ ∂²gᵢ/∂ē² (+ Gᵀ A G): the weights of the ē Hessians and of the
    /// products of ē gradients.
    fn weights(&self, w: &[f64; 6], a: Option<&[[f64; 6]; 6]>) -> ([f64; 6], [[f64; 6]; 6]) {
        let l0 = self.l0;
        let g = &self.g;
        let v: [f64; 6] = std::array::from_fn(|k| (0..6).map(|i| w[i] * g[i][k]).sum());
        let c30 = 1.0 / (30.0 * l0);
        let k6 = 1.0 / (6.0 * l0);
        let mut wm = [[0.0; 6]; 6];
        wm[1][1] = w[0] * self.ct / (l0 * l0 * l0);
        wm[2][2] = 4.0 * w[0] * c30;
        wm[3][3] = 4.0 * w[0] * c30;
        wm[4][4] = 4.0 * w[0] * c30;
        wm[5][5] = 4.0 * w[0] * c30;
        wm[2][3] = w[0] * c30;
        wm[4][5] = w[0] * c30;
        wm[3][4] = w[1] / l0;
        wm[2][5] = -w[1] / l0;
        wm[1][4] = (w[2] - w[3]) * k6;
        wm[1][5] = (w[2] - w[3]) * k6;
        wm[1][2] = (w[5] - w[4]) * k6;
        wm[1][3] = (w[5] - w[4]) * k6;
        for i in 0..6 {
            for k in 0..i {
                wm[i][k] = wm[k][i];
            }
        }
        if let Some(a) = a {
            // Gᵀ A G (A is typically block diagonal: skip its zeros)
            let mut ag = [[0.0; 6]; 6];
            for i in 0..6 {
                for m in 0..6 {
                    let aim = a[i][m];
                    if aim != 0.0 {
                        for k in 0..6 {
                            ag[i][k] += aim * g[m][k];
                        }
                    }
                }
            }
            for i in 0..6 {
                for k in i..6 {
                    let v: f64 = (0..6).map(|m| g[m][i] * ag[m][k]).sum();
                    wm[i][k] += v;
                    if k != i {
                        wm[k][i] += v;
                    }
                }
            }
        }
        (v, wm)
    }

    /// The same in the reduced variables z = (d, λ_p, λ_q).
    fn hessian_z(&self, w: &[f64; 6], a: Option<&[[f64; 6]; 6]>) -> [[f64; 11]; 11] {
        let (l0, l) = (self.l0, self.l);
        let (v, wm) = self.weights(w, a);
        // Bᵀ W B
        let bz = &self.bz;
        let mut wb = [[0.0; 11]; 6];
        for i in 0..6 {
            for k in 0..6 {
                let c = wm[i][k];
                if c != 0.0 {
                    for (o, bv) in wb[i].iter_mut().zip(&bz[k]) {
                        *o += c * bv;
                    }
                }
            }
        }
        let mut h = [[0.0; 11]; 11];
        for k in 0..6 {
            for r in 0..11 {
                let br = bz[k][r];
                if br != 0.0 {
                    for (o, wv) in h[r].iter_mut().zip(&wb[k]) {
                        *o += br * wv;
                    }
                }
            }
        }
        // Σ_k v_k ∂²ē_k/∂z², block by block
        let p = &self.p;
        let hl = 0.5 * l0;
        let (dd, hp, hq) = self.curvature_blocks(&v, l0, l);
        for i in 0..3 {
            for k in 0..3 {
                h[i][k] += dd[i][k];
            }
        }
        for i in 0..4 {
            for k in 0..4 {
                h[3 + i][3 + k] += hp[i][k];
                h[7 + i][7 + k] += hq[i][k];
            }
        }
        // dλp: (P/l) l0 (−v3 Jzp + v5 Jyp); dλq: (P/l) l0 (v4 Jzq − v6 Jyq)
        let s = l0 / l;
        for i in 0..3 {
            for k in 0..4 {
                let (mut sp, mut sq) = (0.0, 0.0);
                for m in 0..3 {
                    sp += p[i][m] * (-v[2] * self.jzp[m][k] + v[4] * self.jyp[m][k]);
                    sq += p[i][m] * (v[3] * self.jzq[m][k] - v[5] * self.jyq[m][k]);
                }
                h[i][3 + k] += s * sp;
                h[3 + k][i] += s * sp;
                h[i][7 + k] += s * sq;
                h[7 + k][i] += s * sq;
            }
        }
        // λpλq: v2 (l0/2)(Jzpᵀ Jyq − Jypᵀ Jzq)
        let s = v[1] * hl;
        if s != 0.0 {
            for i in 0..4 {
                for k in 0..4 {
                    let mut t = 0.0;
                    for m in 0..3 {
                        t += self.jzp[m][i] * self.jyq[m][k] - self.jyp[m][i] * self.jzq[m][k];
                    }
                    h[3 + i][7 + k] += s * t;
                    h[7 + k][3 + i] += s * t;
                }
            }
        }
        h
    }
}
