//! Nonlinear statics with large deflections: load steps, prescribed inputs, reactions.
//!
//! Equilibrium (paper eq. (6) with ẍ = 0): Dᵀσ = f, with σ = S e for the flexible deformations
//! and Lagrange multipliers for the constrained ones. Roles of the deformations in statics:
//!
//! - **flexible**: every deformation with finite stiffness (S_ii > 0), or declared free for the
//!   kinematic check, unless the user lists it as `fixed` explicitly;
//! - **rigid**: declared fixed explicitly, or fixed (the kinematic default) with no stiffness —
//!   constraint e_i(x) = 0 with multiplier σ_i;
//! - **input**: a generalised deformation — constraint e_i(x) = t·value with multiplier σ_i.
//!
//! Unknowns: the free coordinates x^c and the multipliers μ. Newton's method on
//!
//! ```text
//! r(x, μ) = Dᵀσ + Σ 2 μ_n λ_n − f_ext(t) = 0   (free coordinates)
//! g(x)    = e_k(x) − target_k(t)        = 0   (constrained deformations)
//!           λ_nᵀλ_n − 1                 = 0   (rotational nodes)
//! [K  Gᵀ] [Δx]     [r]      K = Dᵀ S D + Σᵢ σᵢ ∂²eᵢ/∂x² + Σ 2 μ_n I_λn − ∂f_ext/∂x
//! [G  0 ] [Δμ] = − [g],     G = ∂g/∂x
//! ```
//!
//! Euler parameters: every rotational node with a free λ component has the normalisation
//! constraint λᵀλ − 1 = 0 with a multiplier (SPACAR's implicit `Euler` element). Element
//! deformations do not depend on ‖λ‖ (docs/rotations.md), so its multiplier vanishes for a
//! fully free node; after every Newton update λ is projected back onto the unit sphere.
//!
//! Loads: dead nodal forces, dead moments (global axes; generalised force 2 Λ̄(λ)ᵀ M on λ, whose
//! derivative gives a load stiffness), gravity on point masses and on the beams' mass (ρA l0/2
//! lumped at each end). All loads and prescribed values grow linearly with the load factor t
//! from 0 to 1 over the load steps (SPACAR's `DELXF`/`DELINPX`); a step that does not converge
//! is halved automatically.

use crate::assembly::gather;
use crate::elements::{Element, ElementKind};
use crate::math::lambda_bar;
use crate::model::{CoordKind, DefKind, Model, Target};
use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use rayon::prelude::*;

/// Solver settings.
#[derive(Clone, Copy, Debug)]
pub struct StaticOptions {
    /// Number of load steps (outputs at t = k/steps).
    pub steps: usize,
    /// Maximum Newton iterations per (sub)step.
    pub max_iterations: usize,
    /// Residual tolerance, relative to the force scale (external and internal forces).
    pub tol_force: f64,
    /// Increment and constraint tolerance, relative to the model size (rotations: absolute).
    pub tol_disp: f64,
    /// Maximum number of step halvings in one load step.
    pub max_halvings: usize,
    /// Backtracking line search on ‖r‖² + (k‖g‖)². Off by default: from a straight beam the
    /// Newton step moves nodes along lines instead of arcs and stretches axially stiff elements
    /// (membrane locking), so every merit function rejects a step that pure Newton recovers
    /// from in a few iterations; step halving is the safeguard instead.
    pub line_search: bool,
}

impl Default for StaticOptions {
    fn default() -> Self {
        Self {
            steps: 10,
            max_iterations: 30,
            tol_force: 1e-9,
            tol_disp: 1e-9,
            max_halvings: 12,
            line_search: false,
        }
    }
}

/// Role of a deformation in statics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// σ = S e.
    Flexible,
    /// e = 0, σ a reaction (multiplier).
    Rigid,
    /// e = prescribed value, σ the force needed.
    Input,
}

/// The statics role of every deformation (module docs).
pub fn roles(model: &Model) -> Vec<Role> {
    let mut roles = Vec::with_capacity(model.ne);
    for entry in &model.elements {
        let s = entry.element.stiffness();
        for m in 0..entry.element.ne() {
            let i = entry.ie + m;
            roles.push(match model.partition.e[i] {
                DefKind::Input => Role::Input,
                _ if model.explicit_rigid[i] => Role::Rigid,
                DefKind::Free => Role::Flexible,
                DefKind::Fixed if s[(m, m)] > 0.0 => Role::Flexible,
                DefKind::Fixed => Role::Rigid,
            });
        }
    }
    roles
}

/// Converged state at one load step.
#[derive(Clone, Debug)]
pub struct StepResult {
    /// Load factor t (0 … 1).
    pub load_factor: f64,
    /// Nodal coordinates x.
    pub x: Vec<f64>,
    /// Deformations e.
    pub e: Vec<f64>,
    /// Stress resultants σ (flexible: S e; rigid and input: the multipliers).
    pub sigma: Vec<f64>,
    /// Generalised reaction forces at the fixed and input coordinates (zero elsewhere), nx.
    pub reactions: Vec<f64>,
    /// Elastic energy ½ Σ eᵀ S e [J].
    pub energy: f64,
    /// Newton iterations used to reach this step (all sub-steps).
    pub iterations: usize,
    /// Sub-steps used (1 unless halved).
    pub substeps: usize,
    /// Final residual ‖r‖∞ [N].
    pub residual: f64,
    /// Lagrange multipliers μ (constrained deformations, then Euler normalisations).
    pub multipliers: Vec<f64>,
}

/// All load steps, the unloaded state first.
#[derive(Clone, Debug)]
pub struct StaticSolution {
    /// Roles of the deformations.
    pub roles: Vec<Role>,
    /// Steps 0 … n.
    pub steps: Vec<StepResult>,
}

/// Why a static solution failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// Newton did not converge even with the smallest step.
    #[error("no equilibrium found at load factor {load_factor:.6} (step {step}): after {halvings} step halvings Newton still fails ({reason}); the last converged load factor is {last_converged:.6}. Try more load steps (--steps), check for buckling or a snap-through near this load, or for an under-constrained model (a mechanism has no static equilibrium under load)")]
    NoConvergence {
        /// Load step being solved.
        step: usize,
        /// Load factor attempted.
        load_factor: f64,
        /// Last converged load factor.
        last_converged: f64,
        /// Halvings done.
        halvings: usize,
        /// What went wrong in the last attempt.
        reason: String,
    },
    /// The model has nothing to solve for.
    #[error("the model has no free coordinate: nothing to solve")]
    NothingToSolve,
}

/// Problem data derived once from the model.
struct Setup {
    roles: Vec<Role>,
    /// x index → unknown index (free coordinates).
    unknown: Vec<Option<usize>>,
    nf: usize,
    /// e index → constraint index.
    constraint: Vec<Option<usize>>,
    nk: usize,
    /// Flexible part of each element's stiffness (other rows and columns zeroed).
    s_eff: Vec<Mat<f64>>,
    /// Dead nodal forces in x (translations only), at t = 1, including gravity.
    f_dead: Vec<f64>,
    /// Moments at t = 1: (λ0 index, M).
    moments: Vec<(usize, [f64; 3])>,
    /// Prescribed values at t = 1: coordinate targets (index, reference, final).
    x_targets: Vec<(usize, f64)>,
    /// Deformation targets at t = 1.
    e_targets: Vec<f64>,
    /// λ0 index of every rotational node.
    lambda: Vec<usize>,
    /// Normalisation constraints: (λ0 index, constraint index) of nodes with a free λ.
    norm: Vec<(usize, usize)>,
    /// Model size (reference for displacement tolerances).
    l_ref: f64,
    /// Whether x index i is a rotation parameter.
    is_lambda: Vec<bool>,
}

fn setup(model: &Model) -> Setup {
    let roles = roles(model);
    let mut unknown = vec![None; model.nx];
    let mut nf = 0;
    for i in 0..model.nx {
        if model.partition.x[i] == CoordKind::Free {
            unknown[i] = Some(nf);
            nf += 1;
        }
    }
    let mut constraint = vec![None; model.ne];
    let mut nk = 0;
    for i in 0..model.ne {
        if roles[i] != Role::Flexible {
            constraint[i] = Some(nk);
            nk += 1;
        }
    }
    let s_eff = model
        .elements
        .iter()
        .map(|entry| {
            let s = entry.element.stiffness();
            let flex = |m: usize| roles[entry.ie + m] == Role::Flexible;
            Mat::from_fn(s.nrows(), s.ncols(), |a, b| {
                if flex(a) && flex(b) {
                    s[(a, b)]
                } else {
                    0.0
                }
            })
        })
        .collect();
    // dead loads and gravity
    let mut f_dead = vec![0.0; model.nx];
    let mut moments = Vec::new();
    for l in &model.loads.nodal {
        let n = &model.nodes[l.node];
        for k in 0..3 {
            f_dead[n.ix_pos + k] += l.force[k];
        }
        if let Some(r) = n.ix_rot {
            if l.moment.iter().any(|m| *m != 0.0) {
                moments.push((r, l.moment));
            }
        }
    }
    let g = model.loads.gravity;
    let mut add_weight = |ix: usize, m: f64| {
        for k in 0..3 {
            f_dead[ix + k] += m * g[k];
        }
    };
    for &(node, m) in &model.loads.point_masses {
        add_weight(model.nodes[node].ix_pos, m);
    }
    for entry in &model.elements {
        if let Element::Beam(b) = &entry.element {
            if let Some(p) = &b.props {
                let half = 0.5 * p.rho_a * b.l0;
                add_weight(model.nodes[b.nodes[0]].ix_pos, half);
                add_weight(model.nodes[b.nodes[1]].ix_pos, half);
            }
        }
    }
    // prescribed values
    let mut x_targets = Vec::new();
    let mut e_targets = vec![0.0; model.ne];
    for p in &model.loads.prescribed {
        match p.target {
            Target::Coordinate(i) => x_targets.push((i, p.value)),
            Target::Deformation(i) => e_targets[i] = p.value,
        }
    }
    let lambda: Vec<usize> = model.nodes.iter().filter_map(|n| n.ix_rot).collect();
    let mut norm = Vec::new();
    for &r in &lambda {
        if (r..r + 4).any(|i| unknown[i].is_some()) {
            norm.push((r, nk));
            nk += 1;
        }
    }
    let mut is_lambda = vec![false; model.nx];
    for &r in &lambda {
        is_lambda[r..r + 4].iter_mut().for_each(|v| *v = true);
    }
    // model size
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for n in &model.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(n.x0[k]);
            hi[k] = hi[k].max(n.x0[k]);
        }
    }
    let l_ref = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max).max(1e-12);
    Setup {
        roles,
        unknown,
        nf,
        constraint,
        nk,
        s_eff,
        f_dead,
        moments,
        x_targets,
        e_targets,
        lambda,
        norm,
        l_ref,
        is_lambda,
    }
}

/// Everything assembled at one state.
struct Assembled {
    /// Residual on the free coordinates.
    r: Vec<f64>,
    /// Constraint violations.
    g: Vec<f64>,
    /// KKT matrix entries.
    triplets: Vec<Triplet<usize, usize, f64>>,
    /// Force scale for the convergence test.
    f_scale: f64,
    /// Full generalised force balance f_int − f_ext + ∇p on all of x (reactions).
    balance: Vec<f64>,
    e: Vec<f64>,
    sigma: Vec<f64>,
    energy: f64,
}

/// Per-element evaluation (parallel part).
struct Local {
    e: Vec<f64>,
    sigma: Vec<f64>,
    d: Mat<f64>,
    k: Mat<f64>,
    energy: f64,
}

/// Which part of the tangent to assemble.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Part {
    /// K = K_material + K_geometric (Newton).
    Full,
    /// Dᵀ S D only.
    Material,
    /// Σ σᵢ ∂²eᵢ/∂x² + normalisation multipliers + load stiffness (proportional to the load).
    Geometric,
}

fn assemble(model: &Model, su: &Setup, x: &[f64], mu: &[f64], t: f64) -> Assembled {
    assemble_part(model, su, x, mu, t, Part::Full)
}

fn assemble_part(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
) -> Assembled {
    let locals: Vec<Local> = model
        .elements
        .par_iter()
        .enumerate()
        .map(|(el, entry)| {
            let xk = gather(entry, x);
            let e = entry.element.deformations(&xk);
            let d = entry.element.jacobian(&xk);
            let s = &su.s_eff[el];
            let ne = e.len();
            // σ = S_eff e, plus multipliers on constrained modes
            let mut sigma = vec![0.0; ne];
            let mut energy = 0.0;
            for a in 0..ne {
                for b in 0..ne {
                    sigma[a] += s[(a, b)] * e[b];
                }
                energy += 0.5 * sigma[a] * e[a];
                if let Some(c) = su.constraint[entry.ie + a] {
                    sigma[a] += mu[c];
                }
            }
            // K_k = Dᵀ S D + Σ σᵢ ∂²eᵢ/∂x²
            let nxk = xk.len();
            let mut k = if part == Part::Material {
                Mat::zeros(nxk, nxk)
            } else {
                entry.element.hessian_weighted(&xk, &sigma)
            };
            if part != Part::Geometric {
                let sd = s * &d;
                k += d.transpose() * &sd;
            }
            Local {
                e,
                sigma,
                d,
                k,
                energy,
            }
        })
        .collect();

    let (nf, nk) = (su.nf, su.nk);
    let mut balance = vec![0.0; model.nx];
    let mut f_abs = vec![0.0; model.nx];
    let mut g = vec![0.0; nk];
    let mut e = vec![0.0; model.ne];
    let mut sigma = vec![0.0; model.ne];
    let mut energy = 0.0;
    let mut triplets = Vec::new();
    for (entry, loc) in model.elements.iter().zip(&locals) {
        let ne = loc.e.len();
        e[entry.ie..entry.ie + ne].copy_from_slice(&loc.e);
        sigma[entry.ie..entry.ie + ne].copy_from_slice(&loc.sigma);
        energy += loc.energy;
        // internal forces Dᵀσ
        for (c, &xi) in entry.xmap.iter().enumerate() {
            let f: f64 = (0..ne).map(|a| loc.d[(a, c)] * loc.sigma[a]).sum();
            balance[xi] += f;
            f_abs[xi] += f.abs();
        }
        // tangent stiffness on free coordinates
        for (a, &xa) in entry.xmap.iter().enumerate() {
            let Some(ua) = su.unknown[xa] else { continue };
            for (b, &xb) in entry.xmap.iter().enumerate() {
                if let Some(ub) = su.unknown[xb] {
                    triplets.push(Triplet::new(ua, ub, loc.k[(a, b)]));
                }
            }
        }
        // constraint rows G and columns Gᵀ
        for m in 0..ne {
            let Some(kc) = su.constraint[entry.ie + m] else {
                continue;
            };
            let target = match su.roles[entry.ie + m] {
                Role::Input => t * su.e_targets[entry.ie + m],
                _ => 0.0,
            };
            g[kc] = loc.e[m] - target;
            for (b, &xb) in entry.xmap.iter().enumerate() {
                if let Some(ub) = su.unknown[xb] {
                    let v = loc.d[(m, b)];
                    if v != 0.0 {
                        triplets.push(Triplet::new(nf + kc, ub, v));
                        triplets.push(Triplet::new(ub, nf + kc, v));
                    }
                }
            }
        }
    }
    // external dead forces
    for i in 0..model.nx {
        balance[i] -= t * su.f_dead[i];
        f_abs[i] += (t * su.f_dead[i]).abs();
    }
    // moments: f_λ = 2 Λ̄(λ)ᵀ M, load stiffness −∂f/∂λ = −2 A(M)
    for &(r, m) in &su.moments {
        let l = [x[r], x[r + 1], x[r + 2], x[r + 3]];
        let lb = lambda_bar(&l);
        for c in 0..4 {
            let f = 2.0 * t * (0..3).map(|k| lb[k][c] * m[k]).sum::<f64>();
            balance[r + c] -= f;
            f_abs[r + c] += f.abs();
        }
        let a = [
            [0.0, -m[0], -m[1], -m[2]],
            [m[0], 0.0, -m[2], m[1]],
            [m[1], m[2], 0.0, -m[0]],
            [m[2], -m[1], m[0], 0.0],
        ];
        for i in 0..4 {
            let Some(ui) = su.unknown[r + i] else {
                continue;
            };
            for j in 0..4 {
                if let Some(uj) = su.unknown[r + j] {
                    triplets.push(Triplet::new(ui, uj, -2.0 * t * a[i][j]));
                }
            }
        }
    }
    // Euler normalisation constraints λᵀλ − 1 = 0 with multipliers μ_n
    for &(r, kc) in &su.norm {
        let l = &x[r..r + 4];
        g[kc] = l.iter().map(|v| v * v).sum::<f64>() - 1.0;
        for i in 0..4 {
            balance[r + i] += 2.0 * mu[kc] * l[i];
            let Some(ui) = su.unknown[r + i] else {
                continue;
            };
            triplets.push(Triplet::new(ui, ui, 2.0 * mu[kc]));
            triplets.push(Triplet::new(nf + kc, ui, 2.0 * l[i]));
            triplets.push(Triplet::new(ui, nf + kc, 2.0 * l[i]));
        }
    }
    let mut r = vec![0.0; nf];
    for i in 0..model.nx {
        if let Some(u) = su.unknown[i] {
            r[u] = balance[i];
        }
    }
    let f_scale = f_abs.iter().cloned().fold(0.0, f64::max);
    Assembled {
        r,
        g,
        triplets,
        f_scale,
        balance,
        e,
        sigma,
        energy,
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, a| m.max(a.abs()))
}

/// Project every rotational node's λ back onto the unit sphere, scaling only its free
/// components so that fixed and prescribed components keep their values. Element deformations
/// do not depend on ‖λ‖, so this changes nothing physical; it keeps λᵀλ − 1 = 0 so that the
/// normalisation constraint holds exactly after every update.
fn normalise_lambda(su: &Setup, x: &mut [f64]) {
    for &r in &su.lambda {
        let (mut free2, mut fixed2) = (0.0, 0.0);
        for i in r..r + 4 {
            if su.unknown[i].is_some() {
                free2 += x[i] * x[i];
            } else {
                fixed2 += x[i] * x[i];
            }
        }
        if free2 > 0.0 && fixed2 < 1.0 {
            let s = ((1.0 - fixed2) / free2).sqrt();
            for i in r..r + 4 {
                if su.unknown[i].is_some() {
                    x[i] *= s;
                }
            }
        }
    }
}

/// Set fixed and input coordinates for load factor t.
fn apply_prescribed(model: &Model, su: &Setup, x: &mut [f64], t: f64) {
    let x0 = model.x0();
    for &(i, v) in &su.x_targets {
        x[i] = if su.is_lambda[i] {
            (0.5 * t * v).sin()
        } else {
            x0[i] + t * v
        };
    }
}

/// Smallest line-search step before a step is taken anyway.
const MIN_STEP: f64 = 1.0 / 16.0;

/// Outcome of one Newton solve.
enum Newton {
    Converged { iterations: usize, residual: f64 },
    Failed { reason: String },
}

fn newton(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    x: &mut [f64],
    mu: &mut [f64],
    t: f64,
) -> Newton {
    let (nf, nk) = (su.nf, su.nk);
    let n = nf + nk;
    normalise_lambda(su, x);
    let mut a = assemble(model, su, x, mu, t);
    let mut last_inc = f64::INFINITY;
    // reference stiffness: the largest diagonal entry of the tangent (translations only: the
    // Euler-parameter entries are in other units)
    let mut is_trans = vec![false; nf];
    for i in 0..model.nx {
        if let (Some(u), false) = (su.unknown[i], su.is_lambda[i]) {
            is_trans[u] = true;
        }
    }
    let k_ref = a
        .triplets
        .iter()
        .filter(|t| t.row == t.col && t.row < nf && is_trans[t.row])
        .fold(0.0f64, |m, t| m.max(t.val.abs()));
    let scale_inc = |dx: &[f64]| -> f64 {
        let mut m: f64 = 0.0;
        for i in 0..model.nx {
            if let Some(u) = su.unknown[i] {
                let v = if su.is_lambda[i] {
                    dx[u].abs()
                } else {
                    dx[u].abs() / su.l_ref
                };
                m = m.max(v);
            }
        }
        m
    };
    for it in 0..=opts.max_iterations {
        let (rn, gn) = (inf_norm(&a.r), inf_norm(&a.g));
        if std::env::var("FLEXMBD_DEBUG_NEWTON").is_ok() {
            eprintln!(
                "t {t:.6} it {it} |r| {rn:.3e} |g| {gn:.3e} inc {last_inc:.3e} fscale {:.3e}",
                a.f_scale
            );
        }
        if !(rn.is_finite() && gn.is_finite()) {
            return Newton::Failed {
                reason: "the residual is not finite".into(),
            };
        }
        // the residual cannot be smaller than the backward error of evaluating internal forces
        // from positions of size l_ref: about ε ‖K‖ l_ref (factor 10 for the sums)
        let floor = 10.0 * f64::EPSILON * k_ref * su.l_ref;
        let force_ok = rn <= (opts.tol_force * a.f_scale).max(floor) || rn == 0.0;
        let geom_ok = gn <= opts.tol_disp * su.l_ref;
        if force_ok && geom_ok && (last_inc <= opts.tol_disp || it == 0 && rn == 0.0 && gn == 0.0) {
            return Newton::Converged {
                iterations: it,
                residual: rn,
            };
        }
        if it == opts.max_iterations {
            return Newton::Failed {
                reason: format!("{it} iterations, residual {rn:.3e} N, constraint error {gn:.3e}"),
            };
        }
        // Newton direction from the KKT system
        let kkt = match SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &a.triplets) {
            Ok(m) => m,
            Err(e) => {
                return Newton::Failed {
                    reason: format!("sparse assembly failed: {e:?}"),
                }
            }
        };
        let lu = match kkt.sp_lu() {
            Ok(lu) => lu,
            Err(_) => {
                return Newton::Failed {
                    reason: "the tangent matrix is singular (a mechanism, or a buckled state)"
                        .into(),
                }
            }
        };
        let rhs = Mat::from_fn(n, 1, |i, _| if i < nf { -a.r[i] } else { -a.g[i - nf] });
        let dz = lu.solve(&rhs);
        let dz: Vec<f64> = (0..n).map(|i| dz[(i, 0)]).collect();
        if dz.iter().any(|v| !v.is_finite()) {
            return Newton::Failed {
                reason: "the tangent matrix is singular (a mechanism, or a buckled state)".into(),
            };
        }
        // backtracking line search on the merit ‖r‖² + (k_ref ‖g‖)², k_ref a stiffness that
        // gives the constraint violation force units
        let merit = |a: &Assembled| {
            let r2: f64 = a.r.iter().map(|v| v * v).sum();
            let g2: f64 = a.g.iter().map(|v| v * v).sum();
            r2 + k_ref * k_ref * g2
        };
        let m0 = merit(&a);
        let mut alpha = 1.0;
        let (x_old, mu_old) = (x.to_vec(), mu.to_vec());
        loop {
            for i in 0..model.nx {
                if let Some(u) = su.unknown[i] {
                    x[i] = x_old[i] + alpha * dz[u];
                }
            }
            for k in 0..nk {
                mu[k] = mu_old[k] + alpha * dz[nf + k];
            }
            normalise_lambda(su, x);
            let trial = assemble(model, su, x, mu, t);
            let m = merit(&trial);
            // accept a decrease, or the smallest step tried
            if !opts.line_search || (m.is_finite() && m < m0) || alpha < MIN_STEP {
                a = trial;
                break;
            }
            alpha *= 0.5;
        }
        last_inc = alpha * scale_inc(&dz[..nf]);
    }
    unreachable!("the loop returns at it == max_iterations")
}

/// Solve the static equilibrium over the load steps.
pub fn solve(
    model: &Model,
    opts: &StaticOptions,
    mut progress: impl FnMut(usize, usize),
) -> Result<StaticSolution, SolveError> {
    let su = setup(model);
    if su.nf == 0 && su.nk == 0 {
        return Err(SolveError::NothingToSolve);
    }
    let mut x = model.x0();
    let mut mu = vec![0.0; su.nk];
    let steps = opts.steps.max(1);
    let mut out = Vec::with_capacity(steps + 1);
    let record = |x: &[f64], mu: &[f64], t: f64, iterations, substeps, residual| -> StepResult {
        let a = assemble(model, &su, x, mu, t);
        let mut reactions = vec![0.0; model.nx];
        for i in 0..model.nx {
            if model.partition.x[i] != CoordKind::Free {
                reactions[i] = a.balance[i];
            }
        }
        StepResult {
            load_factor: t,
            x: x.to_vec(),
            e: a.e,
            sigma: a.sigma,
            reactions,
            energy: a.energy,
            iterations,
            substeps,
            residual,
            multipliers: mu.to_vec(),
        }
    };
    // step 0: the unloaded state (with prescribed values at t = 0)
    apply_prescribed(model, &su, &mut x, 0.0);
    match newton(model, &su, opts, &mut x, &mut mu, 0.0) {
        Newton::Converged {
            iterations,
            residual,
        } => out.push(record(&x, &mu, 0.0, iterations, 1, residual)),
        Newton::Failed { reason } => {
            return Err(SolveError::NoConvergence {
                step: 0,
                load_factor: 0.0,
                last_converged: 0.0,
                halvings: 0,
                reason,
            })
        }
    }
    progress(0, steps);
    let dt_nominal = 1.0 / steps as f64;
    let mut t = 0.0;
    let mut dt = dt_nominal;
    let mut prev: Option<(Vec<f64>, f64)> = None; // previous converged x and its step size
    for step in 1..=steps {
        let t_end = step as f64 * dt_nominal;
        let (mut iterations, mut substeps, mut halvings) = (0, 0, 0);
        let mut residual = 0.0;
        while t < t_end - 1e-14 {
            let t_try = (t + dt).min(t_end);
            let (x_save, mu_save) = (x.clone(), mu.clone());
            // predictor: secant extrapolation of the free coordinates
            if let Some((xp, dtp)) = &prev {
                let s = (t_try - t) / dtp;
                for i in 0..model.nx {
                    if su.unknown[i].is_some() {
                        x[i] += s * (x_save[i] - xp[i]);
                    }
                }
            }
            apply_prescribed(model, &su, &mut x, t_try);
            match newton(model, &su, opts, &mut x, &mut mu, t_try) {
                Newton::Converged {
                    iterations: it,
                    residual: r,
                } => {
                    iterations += it;
                    substeps += 1;
                    residual = r;
                    prev = Some((x_save, t_try - t));
                    t = t_try;
                    dt = (2.0 * dt).min(dt_nominal);
                }
                Newton::Failed { reason } => {
                    x = x_save;
                    mu = mu_save;
                    halvings += 1;
                    dt *= 0.5;
                    if halvings > opts.max_halvings {
                        return Err(SolveError::NoConvergence {
                            step,
                            load_factor: t_try,
                            last_converged: t,
                            halvings: halvings - 1,
                            reason,
                        });
                    }
                }
            }
        }
        out.push(record(&x, &mu, t_end, iterations, substeps, residual));
        progress(step, steps);
    }
    Ok(StaticSolution {
        roles: su.roles,
        steps: out,
    })
}

pub mod linear;

#[cfg(test)]
mod tests;
