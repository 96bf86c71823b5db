//! Materials and beam cross-sections: from dimensions to the stiffness and mass constants of a
//! beam (theory.md §11.2, §12; SPACAR Light `calc_stiffness`, `calc_torsStiff`, `calc_inertia`).
//!
//! Local axes of a section: y along the beam's orientation vector (for a sheet: its width w),
//! z = x × y (for a sheet: its thickness t). Then Iy = ∫z² dA = w t³/12 (out-of-plane bending,
//! modes 3–4) and Iz = ∫y² dA = t w³/12 (in-plane bending, modes 5–6).

use serde::Serialize;

/// Linear elastic isotropic material.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Material {
    /// Young's modulus E [Pa].
    pub e: f64,
    /// Shear modulus G [Pa].
    pub g: f64,
    /// Density ρ [kg/m³].
    pub rho: f64,
}

impl Material {
    /// Poisson's ratio ν = E/(2G) − 1.
    pub fn nu(&self) -> f64 {
        self.e / (2.0 * self.g) - 1.0
    }
}

/// Cross-section shapes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum Shape {
    /// Solid rectangle: width w along local y, thickness t along local z [m].
    Rectangle {
        /// Width (local y).
        w: f64,
        /// Thickness (local z).
        t: f64,
    },
    /// Solid circle of diameter d [m].
    Circle {
        /// Diameter.
        d: f64,
    },
    /// Circular tube, outer and inner diameter [m].
    Tube {
        /// Outer diameter.
        d_out: f64,
        /// Inner diameter.
        d_in: f64,
    },
    /// Properties given directly.
    General {
        /// Area A [m²].
        a: f64,
        /// Iy [m⁴] (bending about local y).
        iy: f64,
        /// Iz [m⁴] (bending about local z).
        iz: f64,
        /// Torsion constant J [m⁴].
        j: f64,
        /// Shear factor k (0 = shear-rigid).
        k: f64,
    },
}

/// Geometric properties of a section.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SectionProps {
    /// Area A [m²].
    pub a: f64,
    /// Second moment about local y, Iy [m⁴].
    pub iy: f64,
    /// Second moment about local z, Iz [m⁴].
    pub iz: f64,
    /// Torsion constant J [m⁴].
    pub j: f64,
    /// Shear factor k (0: shear-rigid, Euler–Bernoulli).
    pub k: f64,
    /// Distance of the outermost fibre along local z and y [m] (bending stress).
    pub fibre: [f64; 2],
}

impl Shape {
    /// Section properties; `nu` enters the shear factor.
    pub fn props(&self, nu: f64) -> SectionProps {
        use std::f64::consts::PI;
        match *self {
            Shape::Rectangle { w, t } => SectionProps {
                a: w * t,
                iy: w * t.powi(3) / 12.0,
                iz: t * w.powi(3) / 12.0,
                j: rectangle_torsion(w, t),
                // Cowper's factor for a rectangle (SPACAR Light)
                k: 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu),
                fibre: [t / 2.0, w / 2.0],
            },
            Shape::Circle { d } => SectionProps {
                a: PI * d * d / 4.0,
                iy: PI * d.powi(4) / 64.0,
                iz: PI * d.powi(4) / 64.0,
                j: PI * d.powi(4) / 32.0,
                k: 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu),
                fibre: [d / 2.0, d / 2.0],
            },
            Shape::Tube { d_out, d_in } => {
                let i = PI * (d_out.powi(4) - d_in.powi(4)) / 64.0;
                // Cowper's factor for a thin-walled tube is 2(1+ν)/(4+3ν); for the general
                // hollow circle with m = d_in/d_out:
                let m = d_in / d_out;
                let m2 = m * m;
                let k = 6.0 * (1.0 + nu) * (1.0 + m2).powi(2)
                    / ((7.0 + 6.0 * nu) * (1.0 + m2).powi(2) + (20.0 + 12.0 * nu) * m2);
                SectionProps {
                    a: PI * (d_out * d_out - d_in * d_in) / 4.0,
                    iy: i,
                    iz: i,
                    j: 2.0 * i,
                    k,
                    fibre: [d_out / 2.0, d_out / 2.0],
                }
            }
            Shape::General { a, iy, iz, j, k } => {
                // outermost fibre unknown: use the radius of a solid square of equal area
                let c = a.sqrt() / 2.0;
                SectionProps {
                    a,
                    iy,
                    iz,
                    j,
                    k,
                    fibre: [c, c],
                }
            }
        }
    }
}

/// Torsion constant of a solid rectangle (Saint-Venant series, SPACAR Light `calc_torsStiff`):
/// with a = min(w, t)/2, b = max(w, t)/2,
/// J = (1/3)(2a)³(2b) [1 − (192/π⁵)(a/b) Σ_{n odd} tanh(nπb/(2a))/n⁵].
pub fn rectangle_torsion(w: f64, t: f64) -> f64 {
    use std::f64::consts::PI;
    let (a, b) = (w.min(t) / 2.0, w.max(t) / 2.0);
    let mut sum = 0.0;
    let mut n = 1.0;
    loop {
        let term = (n * PI * b / (2.0 * a)).tanh() / n.powi(5);
        sum += term;
        if term < 1e-12 * sum || n > 1e4 {
            break;
        }
        n += 2.0;
    }
    (2.0 * a).powi(3) * (2.0 * b) / 3.0 * (1.0 - 192.0 / PI.powi(5) * (a / b) * sum)
}

/// Stiffness and mass constants of a beam element (SPACAR `ESTIFF` and `EM` columns).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct BeamProps {
    /// EA [N].
    pub ea: f64,
    /// GJ [N·m²].
    pub gj: f64,
    /// EIy [N·m²] (modes 3–4).
    pub eiy: f64,
    /// EIz [N·m²] (modes 5–6).
    pub eiz: f64,
    /// Shear flexibilities EIy/(kGA), EIz/(kGA) [m²]; zero for Euler–Bernoulli.
    pub shear: [f64; 2],
    /// Torsion–elongation constant c_t [m²].
    pub ct: f64,
    /// Mass per length ρA [kg/m].
    pub rho_a: f64,
    /// Rotary inertia per length ρ(Iy + Iz), ρIy, ρIz [kg·m].
    pub rho_i: [f64; 3],
    /// Area A [m²] and outermost fibre distances (local z, local y) [m], for stresses; zero
    /// when the constants were given directly.
    pub area: f64,
    /// Section moduli-related data: [Iy, Iz] [m⁴] and fibres, for stresses.
    pub i: [f64; 2],
    /// Outermost fibre distances along local z and local y [m].
    pub fibre: [f64; 2],
}

impl BeamProps {
    /// The bits of every constant: equal keys, equal constants (to share them between the
    /// beams of one section).
    pub(crate) fn key(&self) -> [u64; 16] {
        // (destructured: a constant added to the struct must be added here)
        let BeamProps {
            ea,
            gj,
            eiy,
            eiz,
            shear,
            ct,
            rho_a,
            rho_i,
            area,
            i,
            fibre,
        } = *self;
        [
            ea, gj, eiy, eiz, shear[0], shear[1], ct, rho_a, rho_i[0], rho_i[1], rho_i[2], area,
            i[0], i[1], fibre[0], fibre[1],
        ]
        .map(f64::to_bits)
    }

    /// Constants of a beam of `material` and `shape`. `shear_rigid` drops the shear flexibility
    /// (Euler–Bernoulli). c_t = (Iy + Iz)/A, the polar radius of gyration squared (theory.md
    /// §3.3: the helix derivation gives exactly this for a section without warping).
    pub fn from_section(material: &Material, shape: &Shape, shear_rigid: bool) -> Self {
        let s = shape.props(material.nu());
        let shear = |ei: f64| {
            if shear_rigid || s.k <= 0.0 {
                0.0
            } else {
                ei / (s.k * material.g * s.a)
            }
        };
        let (eiy, eiz) = (material.e * s.iy, material.e * s.iz);
        BeamProps {
            ea: material.e * s.a,
            gj: material.g * s.j,
            eiy,
            eiz,
            shear: [shear(eiy), shear(eiz)],
            ct: (s.iy + s.iz) / s.a,
            rho_a: material.rho * s.a,
            rho_i: [
                material.rho * (s.iy + s.iz),
                material.rho * s.iy,
                material.rho * s.iz,
            ],
            area: s.a,
            i: [s.iy, s.iz],
            fibre: s.fibre,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thin_rectangle_torsion_tends_to_wt3_over_3() {
        // closed form for w ≫ t: J → w t³/3 (1 − 0.630 t/w); Roark: β = 1/3 − 0.21 t/w (1 − t⁴/(12 w⁴))
        let (w, t) = (0.02, 0.0002);
        let j = rectangle_torsion(w, t);
        let roark =
            w * t.powi(3) * (1.0 / 3.0 - 0.21 * t / w * (1.0 - t.powi(4) / (12.0 * w.powi(4))));
        assert!((j - roark).abs() < 1e-4 * roark, "{j} vs {roark}");
    }

    #[test]
    fn square_torsion_constant_is_0_1406_a4() {
        // Saint-Venant: J = 0.1406 a⁴ for a square (Timoshenko & Goodier), 4 digits
        let j = rectangle_torsion(1.0, 1.0);
        assert!((j - 0.14058).abs() < 2e-5, "{j}");
    }

    #[test]
    fn sheet_properties() {
        let steel = Material {
            e: 200e9,
            g: 200e9 / 2.6,
            rho: 7800.0,
        };
        let p = BeamProps::from_section(&steel, &Shape::Rectangle { w: 0.02, t: 0.5e-3 }, true);
        // S09 instance: I = 2.0833e-13 m⁴, EI = 0.0416667 N·m²
        assert!((p.eiy - 0.0416667).abs() < 1e-7, "{}", p.eiy);
        assert_eq!(p.shear, [0.0, 0.0]);
    }
}
