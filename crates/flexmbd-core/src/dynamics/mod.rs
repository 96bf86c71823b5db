//! Linearised dynamics about a static equilibrium: natural frequencies and mode shapes
//! (theory.md §13.1–13.2, paper §5).
//!
//! M0 δq̈ + (K0 + N0 + G0) δq = 0 in minimal coordinates q. flexmbd builds q in two stages:
//! the velocity coordinates of the free nodal coordinates (translations and angular
//! velocities: T with ẋ = T v, which satisfies every Euler normalisation), then the null space
//! of the constraint Jacobian of the rigid and prescribed deformations (Z₂ with G T Z₂ = 0).
//! With Z = T Z₂:
//!
//! ```text
//! M0 = Zᵀ M Z,    K0 + G0 = Zᵀ (K_m + K_g) Z
//! ```
//!
//! where K_m = Dᵀ S D and K_g the geometric stiffness of the static state (stress resultants,
//! constraint forces, normalisation multipliers, load stiffness of applied moments), so
//! pre-stress is included (N0 vanishes in a static state, theory.md §13.1). Frequencies are
//! basis independent, so they equal those in the paper's q = (x^m, e^m).
//!
//! Massless directions (coordinates with no inertia, which make SPACAR report a singular mass
//! matrix) are removed by static condensation instead of fake inertias: M0 = Q diag(m) Qᵀ,
//! directions with m ≤ 1e-12 max m are condensed out of the stiffness (exact for the quasi-static
//! response of massless coordinates); they are reported.

pub mod mass;
pub mod state_space;
pub mod sweep;

use crate::elements::ElementKind;
use crate::kinematics::columns;
use crate::linalg::{numerical_rank, svd, sym_def_eigen, EigenError};
use crate::model::{DefKind, Model, Partition};
use crate::statics::linear::{linearize, Linearized};
use crate::statics::{roles, Role, StepResult};
use faer::Mat;

/// One mode.
#[derive(Clone, Debug)]
pub struct Mode {
    /// ω² [rad²/s²] (negative: the equilibrium is unstable).
    pub eigenvalue: f64,
    /// Frequency [Hz] (NaN for a negative eigenvalue).
    pub frequency: f64,
    /// Mass-normalised shape in x (δx; rotations as Euler-parameter increments).
    pub shape: Vec<f64>,
    /// Shape in velocity coordinates: per node (translation, rotation vector), for display.
    pub nodal: Vec<([f64; 3], [f64; 3])>,
    /// Strain energy fractions per (element, mode 0-based), largest first (those ≥ 1e-4).
    pub strain: Vec<(usize, usize, f64)>,
    /// Kinetic energy fractions per node (translation, rotation), largest first (≥ 1e-4).
    pub kinetic: Vec<(usize, f64, f64)>,
}

/// Result of a modal analysis.
#[derive(Clone, Debug)]
pub struct Modal {
    /// Modes by increasing eigenvalue.
    pub modes: Vec<Mode>,
    /// Number of minimal coordinates (degrees of freedom of the linearised system).
    pub ndof: usize,
    /// Number of massless directions condensed out.
    pub massless: usize,
    /// Nodes with a coordinate that carries no inertia at all (diagonal of M zero).
    pub massless_nodes: Vec<usize>,
}

/// Why a modal analysis failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModalError {
    /// Linear algebra failure.
    #[error(transparent)]
    Eigen(#[from] EigenError),
    /// No mass at all.
    #[error("the model has no mass: give beams a material with density, or add [[mass]] / [[inertia]] entries")]
    NoMass,
    /// A massless part is a mechanism (its condensed stiffness is singular).
    #[error("massless coordinates form a mechanism (zero stiffness and zero inertia); nodes without inertia: {nodes}. Give them mass or fix them")]
    MasslessMechanism {
        /// Node names.
        nodes: String,
    },
    /// Nothing can move.
    #[error("the model has no degree of freedom: every coordinate is fixed or prescribed")]
    NoDof,
}

/// Minimal-coordinate basis Z (nx × ndof) at a state: velocity coordinates of the free
/// coordinates, restricted to the null space of the rigid/prescribed deformation constraints.
pub fn minimal_basis(model: &Model, x: &[f64]) -> Mat<f64> {
    // velocity basis T of the statics unknowns (free coordinates)
    let part = Partition {
        x: model.partition.x.clone(),
        e: vec![DefKind::Free; model.ne],
    };
    let cols = columns(model, &part, x);
    let mut t = Mat::zeros(model.nx, cols.len());
    for (j, c) in cols.iter().enumerate() {
        let n = &model.nodes[c.node];
        if c.dof.is_rotation() {
            let r = n.ix_rot.expect("rotation column");
            for k in 0..4 {
                t[(r + k, j)] = c.lambda_rate[k];
            }
        } else {
            t[(n.ix_pos + c.dof.index(), j)] = 1.0;
        }
    }
    // constraint rows: rigid and input deformations
    let ev = crate::assembly::evaluate(model, x);
    let role = roles(model);
    let rows: Vec<usize> = (0..model.ne)
        .filter(|&i| role[i] != Role::Flexible)
        .collect();
    if rows.is_empty() {
        return t;
    }
    let g = Mat::from_fn(rows.len(), model.nx, |r, c| ev.D[(rows[r], c)]);
    let gt = &g * &t;
    let f = svd(gt.as_ref(), "constraint Jacobian").expect("finite");
    let tol = f64::EPSILON.sqrt() * f.s.first().copied().unwrap_or(0.0);
    let r = numerical_rank(&f.s, tol);
    let n = gt.ncols();
    let z2 = Mat::from_fn(n, n - r, |i, j| f.V[(i, r + j)]);
    &t * &z2
}

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

/// The reduced matrices (Z, M0, K0 and the massless split) at a converged static state.
pub fn reduced_matrices(model: &Model, step: &StepResult) -> Result<Reduced, ModalError> {
    let lin = linearize(model, step);
    reduced_matrices_with(model, step, &lin)
}

/// [`reduced_matrices`] with the linearisation of the state already at hand.
pub fn reduced_matrices_with(
    model: &Model,
    step: &StepResult,
    lin: &Linearized,
) -> Result<Reduced, ModalError> {
    let z = minimal_basis(model, &step.x);
    let ndof = z.ncols();
    if ndof == 0 {
        return Err(ModalError::NoDof);
    }
    // stiffness on the free coordinates (statics unknown order) lifted to x
    let mut kx = Mat::zeros(model.nx, model.nx);
    for i in 0..model.nx {
        let Some(ui) = lin.unknown[i] else { continue };
        for j in 0..model.nx {
            if let Some(uj) = lin.unknown[j] {
                kx[(i, j)] = lin.km[(ui, uj)] + lin.kg[(ui, uj)];
            }
        }
    }
    let mx = mass::mass_matrix(model, &step.x);
    let k0 = sym(z.transpose() * &kx * &z);
    let m0 = sym(z.transpose() * &mx * &z);
    // nodes with a free velocity direction (translation or angular velocity) without inertia
    let part = Partition {
        x: model.partition.x.clone(),
        e: vec![DefKind::Free; model.ne],
    };
    let mut massless_nodes: Vec<usize> = Vec::new();
    for c in columns(model, &part, &step.x) {
        let n = &model.nodes[c.node];
        let idx: Vec<(usize, f64)> = if c.dof.is_rotation() {
            let r = n.ix_rot.expect("rotation column");
            (0..4).map(|k| (r + k, c.lambda_rate[k])).collect()
        } else {
            vec![(n.ix_pos + c.dof.index(), 1.0)]
        };
        let m: f64 = idx
            .iter()
            .map(|&(i, a)| idx.iter().map(|&(j, b)| a * mx[(i, j)] * b).sum::<f64>())
            .sum();
        if m <= 0.0 && !massless_nodes.contains(&c.node) {
            massless_nodes.push(c.node);
        }
    }
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
        if !sol.norm_max().is_finite()
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
        let n = self.mm.len();
        let mmm = Mat::from_fn(n, n, |i, j| if i == j { self.mm[i] } else { 0.0 });
        let (lam, v) = sym_def_eigen(
            self.kc.as_ref(),
            mmm.as_ref(),
            "reduced mass",
            "a mass-carrying direction has no inertia",
        )?;
        let mut phi = &self.qm * &v;
        if let Some(sol) = &self.recover {
            let y0 = -(sol * &v);
            phi += &self.q0 * &y0;
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

/// Natural frequencies and modes at a converged static state (at most `count` modes).
pub fn modes(model: &Model, step: &StepResult, count: usize) -> Result<Modal, ModalError> {
    let red = reduced_matrices(model, step)?;
    let (lam, phi) = red.eigen()?;
    let nm = count.min(lam.len());
    let mut out = Vec::with_capacity(nm);
    for k in 0..nm {
        // back to x
        let dq = Mat::from_fn(red.ndof(), 1, |i, _| phi[(i, k)]);
        let dx = &red.z * &dq;
        let shape: Vec<f64> = (0..model.nx).map(|i| dx[(i, 0)]).collect();
        out.push(describe(model, step, &red.mx, lam[k], shape));
    }
    Ok(Modal {
        modes: out,
        ndof: red.ndof(),
        massless: red.massless(),
        massless_nodes: red.massless_nodes,
    })
}

fn describe(
    model: &Model,
    step: &StepResult,
    mx: &Mat<f64>,
    eigenvalue: f64,
    shape: Vec<f64>,
) -> Mode {
    let frequency = if eigenvalue >= 0.0 {
        eigenvalue.sqrt() / (2.0 * std::f64::consts::PI)
    } else {
        f64::NAN
    };
    // nodal translations and rotation vectors (ω = 2 Λ̄ δλ)
    let nodal: Vec<([f64; 3], [f64; 3])> = model
        .nodes
        .iter()
        .map(|n| {
            let p = n.ix_pos;
            let u = [shape[p], shape[p + 1], shape[p + 2]];
            let w = n.ix_rot.map_or([0.0; 3], |r| {
                let lb = crate::math::lambda_bar(&[
                    step.x[r],
                    step.x[r + 1],
                    step.x[r + 2],
                    step.x[r + 3],
                ]);
                std::array::from_fn(|k| 2.0 * (0..4).map(|c| lb[k][c] * shape[r + c]).sum::<f64>())
            });
            (u, w)
        })
        .collect();
    // strain energy per element deformation: ½ (D δx)ᵢ (S D δx)ᵢ
    let mut strain = Vec::new();
    let mut total_u = 0.0;
    for (el, entry) in model.elements.iter().enumerate() {
        let xk = crate::assembly::gather(entry, &step.x);
        let d = entry.element.jacobian(&xk);
        let s = entry.element.stiffness();
        let dxk: Vec<f64> = entry.xmap.iter().map(|&i| shape[i]).collect();
        let de: Vec<f64> = (0..d.nrows())
            .map(|r| (0..d.ncols()).map(|c| d[(r, c)] * dxk[c]).sum())
            .collect();
        for a in 0..de.len() {
            let u = 0.5 * de[a] * (0..de.len()).map(|b| s[(a, b)] * de[b]).sum::<f64>();
            total_u += u;
            strain.push((el, a, u));
        }
    }
    // kinetic energy per node: split the quadratic form δxᵀ M δx by rows
    let mut kinetic = Vec::new();
    let mut total_t = 0.0;
    for (i, n) in model.nodes.iter().enumerate() {
        let part = |range: std::ops::Range<usize>| -> f64 {
            range
                .map(|r| shape[r] * (0..model.nx).map(|c| mx[(r, c)] * shape[c]).sum::<f64>())
                .sum()
        };
        let tr = if n.host.is_none() {
            part(n.ix_pos..n.ix_pos + 3)
        } else {
            0.0
        };
        let rt = n.ix_rot.map_or(0.0, |r| part(r..r + 4));
        total_t += tr + rt;
        kinetic.push((i, tr, rt));
    }
    let norm_u = if total_u.abs() > 0.0 { total_u } else { 1.0 };
    let norm_t = if total_t.abs() > 0.0 { total_t } else { 1.0 };
    let mut strain: Vec<(usize, usize, f64)> = strain
        .into_iter()
        .map(|(e, m, u)| (e, m, u / norm_u))
        .filter(|s| s.2.abs() >= 1e-4)
        .collect();
    strain.sort_by(|a, b| b.2.abs().total_cmp(&a.2.abs()));
    let mut kinetic: Vec<(usize, f64, f64)> = kinetic
        .into_iter()
        .map(|(n, a, b)| (n, a / norm_t, b / norm_t))
        .filter(|k| k.1.abs() + k.2.abs() >= 1e-4)
        .collect();
    kinetic.sort_by(|a, b| (b.1 + b.2).total_cmp(&(a.1 + a.2)));
    Mode {
        eigenvalue,
        frequency,
        shape,
        nodal,
        strain,
        kinetic,
    }
}

#[cfg(test)]
mod tests;
