//! The dense form of the modal problem: the reduced matrices M0 = Zᵀ M Z and
//! K0 + G0 = Zᵀ K Z of the stage in the minimal coordinates, the static condensation of the
//! massless directions, and all eigenpairs of the condensed problem.

use super::dense::diagonal_mass_eigen;
use super::ModalError;
use crate::kinematics::columns;
use crate::linalg::{all_finite, EigenError};
use crate::linearized::Tangent;
use crate::model::{DefKind, Model, Partition};
use faer::Mat;

/// The linearised system at a static state in minimal coordinates, with its massless
/// directions split off for static condensation.
///
/// With M0 = Q diag(m) Qᵀ, the coordinates y = Qᵀ δq split into massive (y_m, Q_m, masses
/// m_m > 1e-12 max m) and massless ones (y₀, Q₀). The massless ones follow the massive ones
/// quasi-statically, y₀ = −K₀₀⁻¹ K₀ₘ y_m + K₀₀⁻¹ Q₀ᵀ f, so that the massive ones see the
/// condensed stiffness K_c = K_mm − K_m0 K₀₀⁻¹ K₀ₘ and the force Rᵀ Qᵀ f, R = [I; −K₀₀⁻¹ K₀ₘ].
#[derive(Clone, Debug)]
pub struct Reduced {
    /// Minimal-coordinate basis Z (nx × ndof): δx = Z δq.
    pub z: Mat<f64>,
    /// Mass matrix in x (nx × nx).
    pub mx: Mat<f64>,
    /// Reduced mass M0 = Zᵀ M Z (symmetrised).
    pub m0: Mat<f64>,
    /// Reduced stiffness K0 + G0 = Zᵀ (K_m + K_g) Z (symmetrised).
    pub k0: Mat<f64>,
    /// Massive directions Q_m (ndof × n_m, orthonormal columns).
    pub qm: Mat<f64>,
    /// Masses of the massive directions (M0 restricted to Q_m is diagonal).
    pub mm: Vec<f64>,
    /// Massless directions Q₀ (ndof × n₀, orthonormal columns).
    pub q0: Mat<f64>,
    /// Condensed stiffness K_c (n_m × n_m).
    pub kc: Mat<f64>,
    /// K₀₀⁻¹ K₀ₘ (n₀ × n_m) when there are massless directions.
    pub recover: Option<Mat<f64>>,
    /// K₀₀ = Q₀ᵀ K0 Q₀ (n₀ × n₀, regular when `recover` is set).
    pub k00: Mat<f64>,
    /// Nodes with a free velocity direction without any inertia.
    pub massless_nodes: Vec<usize>,
}

fn sym(a: Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// The reduced matrices (Z, M0, K0 and the massless split) of the linearised stage `t`.
pub fn reduced_matrices(t: &Tangent) -> Result<Reduced, ModalError> {
    let (model, step) = (t.model(), t.step());
    let z = t.basis()?;
    let ndof = z.ncols();
    if ndof == 0 {
        return Err(ModalError::NoDof);
    }
    let kx = t.stiffness_in_x();
    let mx = t.mass_in_x();
    let k0 = sym(z.transpose() * &kx * &z);
    let m0 = sym(z.transpose() * &mx * &z);
    let massless_nodes = massless_nodes(model, &step.x);
    // split M0 into massive and massless directions
    let evd = m0
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|_| EigenError::NoConvergence)?;
    let s = evd.S().column_vector();
    let mmax = (0..ndof).map(|i| s[i]).fold(0.0f64, f64::max);
    if mmax <= 0.0 {
        return Err(ModalError::NoMass);
    }
    let massive: Vec<usize> = (0..ndof).filter(|&i| s[i] > 1e-12 * mmax).collect();
    let zero: Vec<usize> = (0..ndof).filter(|&i| s[i] <= 1e-12 * mmax).collect();
    let q = evd.U();
    let qm = Mat::from_fn(ndof, massive.len(), |i, j| q[(i, massive[j])]);
    let q0 = Mat::from_fn(ndof, zero.len(), |i, j| q[(i, zero[j])]);
    let kmm = sym(qm.transpose() * &k0 * &qm);
    let mm: Vec<f64> = massive.iter().map(|&i| s[i]).collect();
    // static condensation: K_c = K_mm − K_m0 K_00⁻¹ K_0m, recover δq₀ = −K_00⁻¹ K_0m δq_m
    let k00 = sym(q0.transpose() * &k0 * &q0);
    let (kc, recover) = if zero.is_empty() {
        (kmm, None)
    } else {
        let k0m = q0.transpose() * &k0 * &qm;
        let lu = k00.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &k0m);
        let res = &k00 * &sol - &k0m;
        // a singular K₀₀ (a massless direction without stiffness) gives inf/NaN in the solve
        // (norm_max does not see NaN, so every entry is checked), or a solve that does not
        // satisfy its equations, or eigenvalues of K₀₀ at the round-off of K0
        let k00_eig_min = k00
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .map(|v| v.iter().fold(f64::INFINITY, |m, l| m.min(l.abs())))
            .unwrap_or(0.0);
        let k_scale = k0.norm_max();
        if !all_finite(&sol)
            || !all_finite(&res)
            || k00_eig_min.is_nan()
            || k00_eig_min <= 1e2 * f64::EPSILON * k_scale
            || res.norm_max() > 1e-8 * (k00.norm_max() * sol.norm_max() + k0m.norm_max())
        {
            let names: Vec<&str> = massless_nodes
                .iter()
                .map(|&n| model.nodes[n].name.as_str())
                .collect();
            return Err(ModalError::MasslessMechanism {
                nodes: names.join(", "),
            });
        }
        (sym(&kmm - k0m.transpose() * &sol), Some(sol))
    };
    Ok(Reduced {
        z,
        mx,
        m0,
        k0,
        qm,
        mm,
        q0,
        kc,
        recover,
        k00,
        massless_nodes,
    })
}

/// Nodes with a free velocity direction (translation or angular velocity, as the columns of
/// the minimal basis) that carries no inertia at all, in node order.
pub fn massless_nodes(model: &Model, x: &[f64]) -> Vec<usize> {
    let part = Partition {
        x: model.partition.x.clone(),
        e: vec![DefKind::Free; model.ne],
    };
    let blocks = crate::assembly::mass::node_blocks(model, x);
    let mut massless = vec![false; model.nodes.len()];
    for c in columns(model, &part, x) {
        let v: [f64; 7] = if c.dof.is_rotation() {
            std::array::from_fn(|k| if k < 3 { 0.0 } else { c.lambda_rate[k - 3] })
        } else {
            std::array::from_fn(|k| if k == c.dof.index() { 1.0 } else { 0.0 })
        };
        let b = &blocks[c.node];
        let m: f64 = (0..7)
            .map(|i| v[i] * (0..7).map(|j| b[i][j] * v[j]).sum::<f64>())
            .sum();
        if m <= 0.0 {
            massless[c.node] = true;
        }
    }
    (0..model.nodes.len()).filter(|&i| massless[i]).collect()
}

impl Reduced {
    /// Number of minimal coordinates.
    pub fn ndof(&self) -> usize {
        self.z.ncols()
    }

    /// Number of massless directions condensed out.
    pub fn massless(&self) -> usize {
        self.q0.ncols()
    }

    /// All eigenpairs of the condensed problem K_c y = ω² M_mm y: the eigenvalues ω²
    /// ascending and the mass-normalised modes Φ in the minimal coordinates q (ndof × n_m,
    /// massless directions recovered), so that Φᵀ M0 Φ = I and Φᵀ K0 Φ = diag(ω²).
    pub fn eigen(&self) -> Result<(Vec<f64>, Mat<f64>), ModalError> {
        let (lam, v) = diagonal_mass_eigen(&self.kc, &self.mm)?;
        let mut phi = &self.qm * &v;
        if let Some(sol) = &self.recover {
            let y0 = -(sol * &v);
            phi += &self.q0 * &y0;
        }
        if lam.iter().any(|l| !l.is_finite()) {
            return Err(ModalError::NonFiniteResult {
                what: "eigenvalues",
            });
        }
        if !all_finite(&phi) {
            return Err(ModalError::NonFiniteResult {
                what: "mode shapes",
            });
        }
        Ok((lam, phi))
    }

    /// Static flexibility of the massless directions, Q₀ K₀₀⁻¹ Q₀ᵀ (ndof × ndof): the part of
    /// the static response K0⁻¹ that no mode carries (the massless coordinates respond to forces
    /// on them instantaneously).
    pub fn massless_flexibility(&self) -> Mat<f64> {
        let n = self.ndof();
        if self.q0.ncols() == 0 {
            return Mat::zeros(n, n);
        }
        let lu = self.k00.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, self.q0.transpose());
        &self.q0 * &sol
    }
}
