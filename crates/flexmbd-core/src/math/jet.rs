//! Forward-mode automatic differentiation of first and second order ("jets").
//!
//! Element deformation functions e = 𝒟(x) are written once, generically over [`Scalar`], and
//! evaluated with
//! - `f64` for the values e,
//! - [`Jet1<N>`] for the values and the exact first derivatives ∂e/∂x,
//! - [`Jet2<N>`] for the values, first derivatives and exact second derivatives ∂²e/∂x².
//!
//! The derivatives are those of the analytic formulas, propagated by the chain rule; they carry
//! no truncation error (unlike finite differences). The contract tests of every element compare
//! them with central differences (`elements::testing`).
//!
//! Chain rule used for a unary function g and a jet a = (v, ∇v, ∇²v):
//! g(a) = (g(v), g'(v) ∇v, g'(v) ∇²v + g''(v) ∇v ∇vᵀ).

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number that may carry derivatives. Implemented by `f64`, [`Jet1`] and [`Jet2`].
pub trait Scalar:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A constant (all derivatives zero).
    fn cst(v: f64) -> Self;
    /// The value without derivatives.
    fn val(&self) -> f64;
    /// Multiplication by a constant.
    fn scale(self, c: f64) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Four-quadrant arctangent of `self / x` (as `f64::atan2`).
    fn atan2(self, x: Self) -> Self;
}

impl Scalar for f64 {
    fn cst(v: f64) -> Self {
        v
    }
    fn val(&self) -> f64 {
        *self
    }
    fn scale(self, c: f64) -> Self {
        self * c
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
}

/// First-order jet: a value and its gradient with respect to N independent variables.
#[derive(Clone, Copy, Debug)]
pub struct Jet1<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient ∂v/∂xᵢ.
    pub g: [f64; N],
}

impl<const N: usize> Jet1<N> {
    /// The independent variable number `i` with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut g = [0.0; N];
        g[i] = 1.0;
        Self { v, g }
    }
    fn chain(self, f: f64, df: f64) -> Self {
        let mut g = [0.0; N];
        for i in 0..N {
            g[i] = df * self.g[i];
        }
        Self { v: f, g }
    }
}

impl<const N: usize> Add for Jet1<N> {
    type Output = Self;
    fn add(mut self, b: Self) -> Self {
        self.v += b.v;
        for i in 0..N {
            self.g[i] += b.g[i];
        }
        self
    }
}
impl<const N: usize> Sub for Jet1<N> {
    type Output = Self;
    fn sub(mut self, b: Self) -> Self {
        self.v -= b.v;
        for i in 0..N {
            self.g[i] -= b.g[i];
        }
        self
    }
}
impl<const N: usize> Neg for Jet1<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}
impl<const N: usize> Mul for Jet1<N> {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        let mut g = [0.0; N];
        for i in 0..N {
            g[i] = self.v * b.g[i] + b.v * self.g[i];
        }
        Self { v: self.v * b.v, g }
    }
}
impl<const N: usize> Div for Jet1<N> {
    type Output = Self;
    fn div(self, b: Self) -> Self {
        // a/b = a · (1/b),  d(1/b) = −db/b²
        let r = 1.0 / b.v;
        self * b.chain(r, -r * r)
    }
}
impl<const N: usize> Scalar for Jet1<N> {
    fn cst(v: f64) -> Self {
        Self { v, g: [0.0; N] }
    }
    fn val(&self) -> f64 {
        self.v
    }
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        for i in 0..N {
            self.g[i] *= c;
        }
        self
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s)
    }
    fn atan2(self, x: Self) -> Self {
        // ∂/∂y atan2(y, x) = x/r²,  ∂/∂x = −y/r²
        let r2 = self.v * self.v + x.v * x.v;
        let (fy, fx) = (x.v / r2, -self.v / r2);
        let mut g = [0.0; N];
        for i in 0..N {
            g[i] = fy * self.g[i] + fx * x.g[i];
        }
        Self {
            v: self.v.atan2(x.v),
            g,
        }
    }
}

/// Second-order jet: value, gradient and (symmetric) Hessian with respect to N variables.
#[derive(Clone, Copy, Debug)]
pub struct Jet2<const N: usize> {
    /// Value.
    pub v: f64,
    /// Gradient ∂v/∂xᵢ.
    pub g: [f64; N],
    /// Hessian ∂²v/∂xᵢ∂xⱼ.
    pub h: [[f64; N]; N],
}

impl<const N: usize> Jet2<N> {
    /// The independent variable number `i` with value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut s = Self::cst(v);
        s.g[i] = 1.0;
        s
    }
    /// g(a) for a unary g with g' = `df`, g'' = `ddf` at a's value.
    fn chain(self, f: f64, df: f64, ddf: f64) -> Self {
        let mut out = Self::cst(f);
        for i in 0..N {
            out.g[i] = df * self.g[i];
            for j in 0..N {
                out.h[i][j] = df * self.h[i][j] + ddf * self.g[i] * self.g[j];
            }
        }
        out
    }
}

impl<const N: usize> Add for Jet2<N> {
    type Output = Self;
    fn add(mut self, b: Self) -> Self {
        self.v += b.v;
        for i in 0..N {
            self.g[i] += b.g[i];
            for j in 0..N {
                self.h[i][j] += b.h[i][j];
            }
        }
        self
    }
}
impl<const N: usize> Sub for Jet2<N> {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        self + b.scale(-1.0)
    }
}
impl<const N: usize> Neg for Jet2<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}
impl<const N: usize> Mul for Jet2<N> {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        // ∇²(ab) = a∇²b + b∇²a + ∇a∇bᵀ + ∇b∇aᵀ
        let mut out = Self::cst(self.v * b.v);
        for i in 0..N {
            out.g[i] = self.v * b.g[i] + b.v * self.g[i];
            for j in 0..N {
                out.h[i][j] = self.v * b.h[i][j]
                    + b.v * self.h[i][j]
                    + self.g[i] * b.g[j]
                    + b.g[i] * self.g[j];
            }
        }
        out
    }
}
impl<const N: usize> Div for Jet2<N> {
    type Output = Self;
    fn div(self, b: Self) -> Self {
        // 1/b: g' = −1/b², g'' = 2/b³
        let r = 1.0 / b.v;
        self * b.chain(r, -r * r, 2.0 * r * r * r)
    }
}
impl<const N: usize> Scalar for Jet2<N> {
    fn cst(v: f64) -> Self {
        Self {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }
    fn val(&self) -> f64 {
        self.v
    }
    fn scale(mut self, c: f64) -> Self {
        self.v *= c;
        for i in 0..N {
            self.g[i] *= c;
            for j in 0..N {
                self.h[i][j] *= c;
            }
        }
        self
    }
    fn sqrt(self) -> Self {
        // g' = 1/(2√v), g'' = −1/(4 v^{3/2})
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }
    fn atan2(self, x: Self) -> Self {
        // f = atan2(y, x), r² = x² + y²:
        // f_y = x/r², f_x = −y/r², f_yy = −2xy/r⁴, f_xx = 2xy/r⁴, f_xy = (y² − x²)/r⁴
        let (y0, x0) = (self.v, x.v);
        let r2 = y0 * y0 + x0 * x0;
        let r4 = r2 * r2;
        let (fy, fx) = (x0 / r2, -y0 / r2);
        let (fyy, fxx, fxy) = (
            -2.0 * x0 * y0 / r4,
            2.0 * x0 * y0 / r4,
            (y0 * y0 - x0 * x0) / r4,
        );
        let mut out = Self::cst(y0.atan2(x0));
        for i in 0..N {
            out.g[i] = fy * self.g[i] + fx * x.g[i];
            for j in 0..N {
                out.h[i][j] = fy * self.h[i][j]
                    + fx * x.h[i][j]
                    + fyy * self.g[i] * self.g[j]
                    + fxx * x.g[i] * x.g[j]
                    + fxy * (x.g[i] * self.g[j] + self.g[i] * x.g[j]);
            }
        }
        out
    }
}

/// A smooth map ℝᴺ → ℝᴹ written generically over [`Scalar`], so that its exact first and
/// second derivatives can be evaluated with jets.
pub trait SmoothMap<const N: usize, const M: usize> {
    /// y = f(x).
    fn eval<T: Scalar>(&self, x: &[T; N]) -> [T; M];

    /// Values f(x).
    fn value(&self, x: &[f64; N]) -> [f64; M] {
        self.eval(x)
    }

    /// Values and Jacobian ∂fᵢ/∂xⱼ (row i).
    fn jacobian(&self, x: &[f64; N]) -> ([f64; M], [[f64; N]; M]) {
        let xj: [Jet1<N>; N] = std::array::from_fn(|i| Jet1::var(x[i], i));
        let y = self.eval(&xj);
        (
            std::array::from_fn(|i| y[i].v),
            std::array::from_fn(|i| y[i].g),
        )
    }

    /// Values, Jacobian and the weighted Hessian Σᵢ wᵢ ∂²fᵢ/∂x².
    fn hessian_weighted(&self, x: &[f64; N], w: &[f64; M]) -> Box<[[f64; N]; N]> {
        let xj: [Jet2<N>; N] = std::array::from_fn(|i| Jet2::var(x[i], i));
        let y = self.eval(&xj);
        let mut h = Box::new([[0.0; N]; N]);
        for k in 0..M {
            if w[k] == 0.0 {
                continue;
            }
            for i in 0..N {
                for j in 0..N {
                    h[i][j] += w[k] * y[k].h[i][j];
                }
            }
        }
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Probe;
    impl SmoothMap<2, 1> for Probe {
        fn eval<T: Scalar>(&self, x: &[T; 2]) -> [T; 1] {
            // f = atan2(x0 x1, x0 + 2) + sqrt(x0² + x1²) / x1
            let (a, b) = (x[0], x[1]);
            [(a * b).atan2(a + T::cst(2.0)) + (a * a + b * b).sqrt() / b]
        }
    }

    #[test]
    fn jets_match_central_differences() {
        let x = [0.7, -1.3];
        let h = 1e-5;
        let (_, jac) = Probe.jacobian(&x);
        let hess = Probe.hessian_weighted(&x, &[1.0]);
        for j in 0..2 {
            let mut xp = x;
            let mut xm = x;
            xp[j] += h;
            xm[j] -= h;
            let fd = (Probe.value(&xp)[0] - Probe.value(&xm)[0]) / (2.0 * h);
            assert!(
                (fd - jac[0][j]).abs() < 1e-8,
                "gradient {j}: {fd} vs {}",
                jac[0][j]
            );
            let (_, jp) = Probe.jacobian(&xp);
            let (_, jm) = Probe.jacobian(&xm);
            for i in 0..2 {
                let fd2 = (jp[0][i] - jm[0][i]) / (2.0 * h);
                assert!((fd2 - hess[i][j]).abs() < 1e-7, "hessian {i}{j}");
            }
        }
    }
}
