//! The linearised stage at a converged static state (theory.md §13): the one [`Tangent`] from
//! which every linearised analysis starts — support compliance, buckling and stability (here),
//! natural frequencies and modes, state spaces and sweeps (`dynamics`).
//!
//! At a state with multipliers μ the Newton matrix splits into the material part
//! K_m = Dᵀ S D and the load-proportional geometric part
//! K_g = Σᵢ σᵢ ∂²eᵢ/∂x² + Σ 2μ_n I_λn − ∂f_ext/∂x (stress resultants, Euler normalisation
//! multipliers and the load stiffness of applied moments), with the constraint Jacobian G of
//! the rigid and input deformations and normalisations. In the null space Z of G (the minimal
//! coordinates of the paper) K_m and K_g are SPACAR's K0 and G0. The dynamics add the mass M and
//! the centrifugal softening −Ω² M_P of a steady rotation: the tangent stiffness of the
//! linearised equations of motion is K = K_m + K_g − Ω² M_P.
//!
//! The stage holds each piece in the form its solvers need, each built by one piece of code:
//!
//! - dense, on the free coordinates: K_m, K_g, G ([`Tangent::dense`], built once on first use),
//!   K and M in x ([`Tangent::stiffness_in_x`], [`Tangent::mass_in_x`]) and the minimal basis Z
//!   ([`Tangent::basis`]);
//! - sparse, in the reduced unknowns of the statics Newton system: K (the Newton matrix with
//!   the softening) and M on its pattern (`sparse.rs`), for the shift-invert eigen solver and
//!   the static solves of large models.
//!
//! Dense versus sparse is a choice of solver (`dynamics::auto_solver`), not of the physics.

mod buckling;
mod compliance;
mod dense;
mod request;
pub(crate) mod sparse;

/// The result types of the linearised static results (defined with the static analysis that
/// carries them).
pub use crate::statics::linear::{
    Buckling, Compliance, LinearError, LinearFailure, LinearRequest, StepLinear,
};
pub use buckling::{buckling, stiffness_condition, unstable_directions, ILL_CONDITIONED};
pub use compliance::compliance;
pub use dense::{check_dense_size, dense_bytes, linearize, Linearized};
pub use request::{analyse, at_step};

use crate::kinematics::columns;
use crate::linalg::{numerical_rank, svd, LinalgError};
use crate::model::{DefKind, Model, Partition};
use crate::statics::{roles, Role, StepResult};
use faer::Mat;
use std::sync::OnceLock;

/// The linearised stage at a converged state: the model, the state, and the tangent pieces
/// of every linearised analysis, built when first asked for (module docs).
pub struct Tangent<'a> {
    model: &'a Model,
    step: &'a StepResult,
    dense: OnceLock<Linearized>,
}

impl<'a> Tangent<'a> {
    /// The stage of `model` at the converged `step`; nothing is assembled yet.
    pub fn new(model: &'a Model, step: &'a StepResult) -> Self {
        Self {
            model,
            step,
            dense: OnceLock::new(),
        }
    }

    /// The model.
    pub fn model(&self) -> &'a Model {
        self.model
    }

    /// The state.
    pub fn step(&self) -> &'a StepResult {
        self.step
    }

    /// K_m, K_g and G on the free coordinates (dense; built on the first call, shared by the
    /// compliance, buckling, stability and the dense modal analysis of the state).
    pub fn dense(&self) -> &Linearized {
        self.dense.get_or_init(|| linearize(self.model, self.step))
    }

    /// The tangent stiffness of the linearised dynamics in x (nx × nx): K = K_m + K_g on the
    /// free coordinates (zero rows and columns elsewhere), minus the centrifugal softening
    /// Ω² M_P of a steady rotation (`assembly::mass::softening_matrix`).
    pub fn stiffness_in_x(&self) -> Mat<f64> {
        let (model, lin) = (self.model, self.dense());
        let nx = model.nx;
        let mut kx = Mat::zeros(nx, nx);
        for i in 0..nx {
            let Some(ui) = lin.unknown[i] else { continue };
            for j in 0..nx {
                if let Some(uj) = lin.unknown[j] {
                    kx[(i, j)] = lin.km[(ui, uj)] + lin.kg[(ui, uj)];
                }
            }
        }
        if model.loads.spin.is_some() {
            kx += crate::assembly::mass::softening_matrix(model, &self.step.x);
        }
        kx
    }

    /// The mass matrix M in x (nx × nx) at the state (`assembly::mass::mass_matrix`).
    pub fn mass_in_x(&self) -> Mat<f64> {
        crate::assembly::mass::mass_matrix(self.model, &self.step.x)
    }

    /// Minimal-coordinate basis Z (nx × ndof): velocity coordinates of the free coordinates
    /// (translations and angular velocities: T with ẋ = T v, which satisfies every Euler
    /// normalisation), restricted to the null space of the rigid and prescribed deformation
    /// constraints (Z₂ with G T Z₂ = 0, by SVD): Z = T Z₂.
    ///
    /// A non-finite x (or Jacobian) is an error, not a basis.
    pub fn basis(&self) -> Result<Mat<f64>, LinalgError> {
        let (model, x) = (self.model, &self.step.x[..]);
        // velocity basis T of the statics unknowns (free coordinates)
        let part = Partition {
            x: model.partition.x.clone(),
            e: vec![DefKind::Free; model.ne],
        };
        let cols = columns(model, &part, x);
        let mut t = Mat::zeros(model.nx, cols.len());
        for (j, c) in cols.iter().enumerate() {
            let n = &model.nodes[c.node];
            match n.ix_rot {
                Some(r) if c.dof.is_rotation() => {
                    for k in 0..4 {
                        t[(r + k, j)] = c.lambda_rate[k];
                    }
                }
                _ => t[(n.ix_pos + c.dof.index(), j)] = 1.0,
            }
        }
        // constraint rows: rigid and input deformations
        let ev = crate::assembly::evaluate(model, x);
        let role = roles(model);
        let rows: Vec<usize> = (0..model.ne)
            .filter(|&i| role[i] != Role::Flexible)
            .collect();
        if rows.is_empty() {
            return Ok(t);
        }
        let g = Mat::from_fn(rows.len(), model.nx, |r, c| ev.D[(rows[r], c)]);
        let gt = &g * &t;
        let f = svd(gt.as_ref(), "constraint Jacobian")?;
        let tol = f64::EPSILON.sqrt() * f.s.first().copied().unwrap_or(0.0);
        let r = numerical_rank(&f.s, tol);
        let n = gt.ncols();
        let z2 = Mat::from_fn(n, n - r, |i, j| f.V[(i, r + j)]);
        Ok(&t * &z2)
    }

    /// The sparse form of the stage in the reduced unknowns of the statics Newton system:
    /// K (with the softening) and M on the Newton matrix's pattern (`sparse.rs`).
    pub(crate) fn sparse(&self) -> sparse::SparseTangent {
        sparse::SparseTangent::new(self.model, self.step)
    }
}
