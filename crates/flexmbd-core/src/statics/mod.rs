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
//! derivative gives a load stiffness), gravity and the centrifugal field of a steady rotation on
//! the elements' and point masses, consistent with the mass matrix (`assembly::loads`: for a
//! beam ρA g l0/2 at each end and the end moments ±ρA l0² (t × g)/12), on the reference
//! configuration. All loads and prescribed values grow linearly with the load factor t
//! from 0 to 1 over the load steps (SPACAR's `DELXF`/`DELINPX`); a step that does not converge
//! (or whose residual grows a thousandfold, `DIVERGENCE`) is halved automatically.
//!
//! Implementation of the Newton iteration (none of it changes the equations or the tolerances):
//! the system is solved in reduced unknowns (`Reduction`: three rotation increments per free
//! node instead of four Euler parameters and a normalisation row), with a sparse LU whose
//! structure and ordering are computed once per solve and which is refactored with the previous
//! pivots (L D Lᵀ for symmetric systems, `math::sparse_lu`); beams use closed-form derivatives
//! (`elements::beam::closed_form`); the Euler parameters are updated so that node triads turn with the
//! chords (`chord_consistent_scale`); a load step starts from the last converged state (a
//! secant predictor only with prescribed coordinates).

use crate::assembly::gather;
use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{CoordKind, DefKind, Model, Target};
use faer::sparse::Triplet;
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
    /// How the load factor moves along the path: fixed load steps (default) or arc length.
    pub path: PathMethod,
}

/// How a static analysis follows its equilibrium path (docs/statics.md, "Path following").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PathMethod {
    /// The load factor (loads and prescribed values together) grows in `steps` equal steps,
    /// each halved as needed; it cannot pass a limit point of the load factor.
    #[default]
    LoadSteps,
    /// Arc length (Crisfield's cylindrical constraint on the coordinates, with the motion of
    /// the prescribed coordinates): the load factor is an unknown, so the path passes limit
    /// points and snap-backs; the step length adapts to the Newton iterations.
    ArcLength,
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
            path: PathMethod::LoadSteps,
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
    for el in 0..model.elements.len() {
        roles.extend(element_roles(model, el));
    }
    roles
}

/// The statics roles of the deformations of element `el`, in mode order.
pub fn element_roles(model: &Model, el: usize) -> Vec<Role> {
    let entry = &model.elements[el];
    let s = entry.element.stiffness();
    (0..entry.element.ne())
        .map(|m| {
            let i = entry.ie + m;
            match model.partition.e[i] {
                DefKind::Input => Role::Input,
                _ if model.explicit_rigid[i] => Role::Rigid,
                DefKind::Free => Role::Flexible,
                DefKind::Fixed if s[(m, m)] > 0.0 => Role::Flexible,
                DefKind::Fixed => Role::Rigid,
            }
        })
        .collect()
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
    /// With arc length ([`PathMethod::ArcLength`]): the path parameter and stability of every
    /// step (same order), and the limit points and bifurcations passed; empty with load steps.
    pub path: Vec<PathPoint>,
    /// Limit points and bifurcations along an arc-length path, in path order.
    pub events: Vec<PathEvent>,
}

/// What arc-length path following knows of a step.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PathPoint {
    /// Path parameter: the arc length from the unloaded state, in the dimensionless norm of
    /// the constraint (translations relative to the model size, rotations in radians/2).
    pub arc_length: f64,
    /// Number of negative eigenvalues of the tangent stiffness on the constraints (0: stable),
    /// from the inertia of its factorisation; `None` when it was factored otherwise (applied
    /// moments make it unsymmetric).
    pub unstable_directions: Option<usize>,
}

/// A critical point passed along an arc-length path.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum PathEvent {
    /// The load factor turns back: a maximum or minimum of the load along the path, at or
    /// next to step `step`.
    LimitPoint {
        /// The step where the load factor is extreme.
        step: usize,
        /// Its load factor.
        load_factor: f64,
    },
    /// The number of unstable directions changes between steps `step` − 1 and `step` while the
    /// load factor goes on: a branch of other equilibria crosses the path there.
    Bifurcation {
        /// The first step after the bifurcation.
        step: usize,
        /// Its load factor.
        load_factor: f64,
        /// Unstable directions before and after.
        unstable: [usize; 2],
    },
}

/// Why a static solution failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// Newton did not converge even with the smallest step.
    #[error("no equilibrium found at load factor {load_factor:.6} (step {step}): after {halvings} step halvings Newton still fails ({reason}); the last converged load factor is {last_converged:.6}. Try more load steps, check for buckling or a snap-through near this load, or for an under-constrained model (a mechanism has no static equilibrium under load)")]
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
    /// A converged state holds numbers that are not finite (coordinates, deformations, stress
    /// resultants, reactions or energy): the arithmetic overflowed double precision.
    #[error("the state at load factor {load_factor:.6} (step {step}) is not finite ({what} contain NaN or infinity): the coordinates or forces overflow double precision (are node positions or loads beyond about 1e150?); {}", last_good_text(*last_good))]
    NonFinite {
        /// Load step.
        step: usize,
        /// Load factor of the state.
        load_factor: f64,
        /// The quantities that are not finite.
        what: String,
        /// The last load factor whose state is finite, if any.
        last_good: Option<f64>,
    },
    /// An element was pushed through itself (zero length or reversed chord) along the path:
    /// the converged state would be a wrong, inverted equilibrium.
    #[error("element `{element}` inverted at load factor {load_factor:.6} (step {step}): its chord passed through zero length or turned against its own axis, so this state is not a valid equilibrium of the structure (often a compressed member far beyond buckling); the last valid load factor is {last_converged:.6}. Try more load steps, a smaller load, or prescribe the displacement instead of the force (displacement control)")]
    Inverted {
        /// Load step.
        step: usize,
        /// Load factor attempted.
        load_factor: f64,
        /// Last load factor with a valid state.
        last_converged: f64,
        /// Element name.
        element: String,
    },
    /// The model has nothing to solve for.
    #[error("the model has no free coordinate: nothing to solve")]
    NothingToSolve,
    /// An arc-length path that does not reach the full load within its step budget.
    #[error("the arc-length path did not reach load factor 1 in {steps} steps (it reached {load_factor:.6}, the largest load factor on the path is {largest:.6}): the load may lie beyond every equilibrium of the structure, or the steps are too short; try fewer, longer steps or a smaller load")]
    PathTooLong {
        /// Steps taken.
        steps: usize,
        /// Load factor reached.
        load_factor: f64,
        /// The largest load factor along the path.
        largest: f64,
    },
    /// A prescribed value that arc length cannot drive.
    #[error("{0}")]
    NotForArcLength(String),
    /// The options are out of range.
    #[error("{what} must be between {min} and {max}, found {found}")]
    BadOption {
        /// Which option (`steps`, `max_iterations`, …).
        what: &'static str,
        /// The smallest value allowed.
        min: usize,
        /// The largest value allowed.
        max: usize,
        /// The value given.
        found: usize,
    },
}

fn last_good_text(last: Option<f64>) -> String {
    match last {
        Some(t) => format!("the last finite state is at load factor {t:.6}"),
        None => "no state of the path is finite".into(),
    }
}

/// The quantities of a step result that hold a non-finite number (empty: all finite).
pub fn non_finite_parts(st: &StepResult) -> Vec<&'static str> {
    let bad = |v: &[f64]| v.iter().any(|x| !x.is_finite());
    let mut out = Vec::new();
    if bad(&st.x) {
        out.push("coordinates");
    }
    if bad(&st.e) {
        out.push("deformations");
    }
    if bad(&st.sigma) {
        out.push("stress resultants");
    }
    if bad(&st.reactions) {
        out.push("reactions");
    }
    if bad(&st.multipliers) {
        out.push("multipliers");
    }
    if !st.energy.is_finite() || !st.residual.is_finite() {
        out.push("energy");
    }
    out
}

/// The first element (name) that is inverted at `x`, having been valid at `prev`.
pub(crate) fn inverted_element(model: &Model, x: &[f64], prev: &[f64]) -> Option<String> {
    model.elements.iter().find_map(|entry| {
        let (xk, pk) = (gather(entry, x), gather(entry, prev));
        entry.element.inverted(&xk, &pk).then(|| entry.name.clone())
    })
}

/// The most load steps [`solve`] takes (every step is kept in memory).
pub const MAX_STEPS: usize = 1_000_000;

/// The most Newton iterations per step [`solve`] takes.
pub const MAX_ITERATIONS: usize = 1_000_000;

/// Problem data derived once from the model.
pub(crate) struct Setup {
    pub(crate) roles: Vec<Role>,
    /// x index → unknown index (free coordinates).
    pub(crate) unknown: Vec<Option<usize>>,
    pub(crate) nf: usize,
    /// e index → constraint index.
    pub(crate) constraint: Vec<Option<usize>>,
    pub(crate) nk: usize,
    /// Flexible part of each element's stiffness (other rows and columns zeroed).
    pub(crate) s_eff: Vec<Mat<f64>>,
    /// Dead nodal forces in x (translations only), at t = 1, including gravity.
    pub(crate) f_dead: Vec<f64>,
    /// Moments at t = 1: (λ0 index, M).
    pub(crate) moments: Vec<(usize, [f64; 3])>,
    /// Prescribed values at t = 1: coordinate targets (index, reference, final).
    pub(crate) x_targets: Vec<(usize, f64)>,
    /// Deformation targets at t = 1.
    pub(crate) e_targets: Vec<f64>,
    /// λ0 index of every rotational node.
    pub(crate) lambda: Vec<usize>,
    /// Normalisation constraints: (λ0 index, constraint index) of nodes with a free λ.
    pub(crate) norm: Vec<(usize, usize)>,
    /// Model size (reference for displacement tolerances).
    pub(crate) l_ref: f64,
    /// Whether x index i is a rotation parameter.
    pub(crate) is_lambda: Vec<bool>,
    /// Order of the KKT entries written by the element assembly.
    pattern: Pattern,
    /// The reduced Newton system (rotations of fully free nodes in tangent coordinates).
    red: Reduction,
}

pub(crate) fn setup(model: &Model) -> Setup {
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
    let pattern = Pattern::new(model, &unknown, &constraint, nf);
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
    // gravity and the centrifugal loads of a steady rotation, consistent with the mass model
    // (dead, on the reference configuration)
    if model.loads.acceleration_field().is_some() {
        for (node, (f, m)) in crate::assembly::loads::field_loads(model)
            .iter()
            .enumerate()
        {
            let n = &model.nodes[node];
            for k in 0..3 {
                f_dead[n.ix_pos + k] += f[k];
            }
            if let Some(r) = n.ix_rot {
                if m.iter().any(|v| *v != 0.0) {
                    moments.push((r, *m));
                }
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
    let red = Reduction::new(model, &unknown, &constraint, nf, nk, &norm, &is_lambda);
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
        pattern,
        red,
    }
}

/// Fixed order of the KKT matrix entries written by the assembly (the "triplets" without
/// values). It depends only on the model, so the sparse structure, the map to its value slots
/// and the symbolic factorisation are computed once per solve.
///
/// Order: per element (contiguous block, so that elements write in parallel) the tangent on its
/// free coordinates (row-major over the free local coordinates), then for each constrained mode
/// the pairs (G, Gᵀ) over the free local coordinates; after all elements the load stiffness of
/// the moments, then the Euler normalisations (diagonal, G, Gᵀ).
///
/// Only the linearisation (`assemble_part`) assembles in this order; Newton uses the reduced
/// order ([`Reduction`]). So the entry list is built on first use.
struct Pattern {
    /// Rows, columns and element starts of the entries ([`Pattern::layout`]).
    layout: std::sync::OnceLock<PatternLayout>,
    /// Free local coordinates of each element: (local index, unknown index).
    elem_free: Vec<Vec<(usize, usize)>>,
    /// Constraint index of each element's modes (`None`: flexible), by element.
    elem_constraints: Vec<Vec<usize>>,
    /// Number of free coordinates (the constraint rows follow).
    nf: usize,
    /// Start of each element's internal forces in the per-element force buffer.
    f_start: Vec<usize>,
}

/// The entries of [`Pattern`].
struct PatternLayout {
    rows: Vec<usize>,
    cols: Vec<usize>,
    /// Start of each element's block in `rows`/`cols` (elements + 1 entries).
    elem_start: Vec<usize>,
}

impl Pattern {
    fn new(
        model: &Model,
        unknown: &[Option<usize>],
        constraint: &[Option<usize>],
        nf: usize,
    ) -> Self {
        let mut elem_free = Vec::with_capacity(model.elements.len());
        let mut elem_constraints = Vec::with_capacity(model.elements.len());
        let mut f_start = Vec::with_capacity(model.elements.len() + 1);
        f_start.push(0);
        for entry in &model.elements {
            let free: Vec<(usize, usize)> = entry
                .xmap
                .iter()
                .enumerate()
                .filter_map(|(a, &xa)| unknown[xa].map(|u| (a, u)))
                .collect();
            elem_free.push(free);
            elem_constraints.push(
                (0..entry.element.ne())
                    .filter_map(|m| constraint[entry.ie + m])
                    .collect(),
            );
            f_start.push(f_start.last().copied().unwrap_or(0) + entry.xmap.len());
        }
        Self {
            layout: std::sync::OnceLock::new(),
            elem_free,
            elem_constraints,
            nf,
            f_start,
        }
    }

    /// The entries (built on first use).
    fn layout(&self) -> &PatternLayout {
        self.layout.get_or_init(|| {
            let nf = self.nf;
            let total: usize = self
                .elem_free
                .iter()
                .zip(&self.elem_constraints)
                .map(|(f, c)| element_entry_count(f.len(), c.len()))
                .sum();
            let (mut rows, mut cols) = (Vec::with_capacity(total), Vec::with_capacity(total));
            let mut elem_start = Vec::with_capacity(self.elem_free.len() + 1);
            for (free, cons) in self.elem_free.iter().zip(&self.elem_constraints) {
                elem_start.push(rows.len());
                element_entries(free, cons.iter().map(|&kc| nf + kc), &mut |r, c| {
                    rows.push(r);
                    cols.push(c);
                });
            }
            elem_start.push(rows.len());
            PatternLayout {
                rows,
                cols,
                elem_start,
            }
        })
    }
}

/// A reduced local coordinate of an element: a column of the map T from reduced to original
/// local coordinates.
#[derive(Clone, Copy, Debug)]
enum RCol {
    /// The local coordinate itself.
    Plain(usize),
    /// Rotation increment j of the node whose λ0 is local coordinate `a0`: Δλ = N(λ) δ.
    Rot { a0: usize, j: usize },
}

/// The Newton system in reduced unknowns. A rotational node whose four Euler parameters are
/// all free is described by three increments δ with Δλ = N(λ) δ, N = Λ̄(λ)ᵀ/‖λ‖ (an
/// orthonormal basis of λ⊥, docs/rotations.md), instead of four parameters plus its
/// normalisation constraint and multiplier: the KKT matrix loses two rows and columns per node
/// and its zero diagonal there, and for a model without constraints and moments it is the
/// symmetric tangent stiffness itself (factored as L D Lᵀ). Since λᵀλ = 1 holds at every
/// iterate (`normalise_lambda`), the normalisation row gives Δλ ⟂ λ; the multiplier's term
/// 2μ I becomes 2μ I₃ and the multiplier's update follows from its row of the full system
/// (in `newton`): the direction is that of the full system. Nodes with a single free Euler
/// parameter are eliminated as well (`singles`).
struct Reduction {
    /// Reduced index of every original unknown (free coordinates, then constraints); `None`
    /// for the Euler parameters and normalisations of reduced nodes.
    map: Vec<Option<usize>>,
    /// Reduced nodes: (λ0 x index, first of its three reduced indices, normalisation index).
    nodes: Vec<(usize, usize, usize)>,
    /// Nodes with a single free Euler parameter (a clamped or rotation-driven node): it follows
    /// from the normalisation alone, so neither it nor the normalisation enters the Newton
    /// system; its multiplier solves its row of the equilibrium at every state
    /// (`solve_single_multipliers`). (λ0 x index, x index of that parameter, normalisation
    /// index).
    singles: Vec<(usize, usize, usize)>,
    /// x index of λ0 → index into `nodes`.
    node_at: Vec<Option<usize>>,
    /// Reduced coordinate unknowns (the constraints follow).
    nfr: usize,
    /// Size of the reduced system.
    n: usize,
    /// Whether reduced coordinate unknown u is a translation.
    is_trans: Vec<bool>,
    /// Reduced local coordinates of each element with their reduced unknown.
    elem_cols: Vec<Vec<(RCol, usize)>>,
    /// Beams with all 14 coordinates free, both nodes reduced and no constrained mode: their
    /// reduced entries come directly from `BeamFirst::hessian_tangent`.
    beam_full: Vec<bool>,
    /// Reduced constraint row of each constrained mode of each element.
    elem_cons: Vec<Vec<usize>>,
    /// Number of KKT entries written by the element assembly ([`Reduction::for_each_entry`]).
    n_entries: usize,
    /// The diagonal entries of translations among them.
    diag_trans: Vec<usize>,
    /// Start of each element's entries (elements + 1).
    elem_start: Vec<usize>,
}

impl Reduction {
    fn new(
        model: &Model,
        unknown: &[Option<usize>],
        constraint: &[Option<usize>],
        nf: usize,
        nk: usize,
        norm: &[(usize, usize)],
        is_lambda: &[bool],
    ) -> Self {
        // candidates: all four λ free; every element uses them as one block λ0..λ3
        let mut node_ok = vec![false; model.nx];
        for &(r, _) in norm {
            node_ok[r] = (r..r + 4).all(|i| unknown[i].is_some());
        }
        let mut lambda0 = vec![usize::MAX; model.nx];
        for &(r, _) in norm {
            for i in r..r + 4 {
                lambda0[i] = r;
            }
        }
        for entry in &model.elements {
            let mut a = 0;
            while a < entry.xmap.len() {
                let xi = entry.xmap[a];
                let r = lambda0[xi];
                if r != usize::MAX && node_ok[r] {
                    let block = xi == r
                        && a + 4 <= entry.xmap.len()
                        && (0..4).all(|i| entry.xmap[a + i] == r + i);
                    if !block {
                        node_ok[r] = false;
                    } else {
                        a += 4;
                        continue;
                    }
                }
                a += 1;
            }
        }
        // single free parameter: determined by the normalisation
        let mut singles = Vec::new();
        for &(r, kc) in norm {
            let free: Vec<usize> = (r..r + 4).filter(|&i| unknown[i].is_some()).collect();
            if free.len() == 1 {
                singles.push((r, free[0], kc));
            }
        }
        // numbering: coordinates in x order (three per reduced node), then the constraints
        let mut map = vec![None; nf + nk];
        let single_x: std::collections::HashSet<usize> = singles.iter().map(|v| v.1).collect();
        let mut nodes = Vec::new();
        let mut node_at = vec![None; model.nx];
        let mut is_trans = Vec::new();
        let mut nfr = 0;
        let norm_of: std::collections::HashMap<usize, usize> = norm.iter().cloned().collect();
        let mut i = 0;
        while i < model.nx {
            if node_ok[i] && lambda0[i] == i {
                node_at[i] = Some(nodes.len());
                nodes.push((i, nfr, norm_of[&i]));
                nfr += 3;
                is_trans.extend([false; 3]);
                i += 4;
                continue;
            }
            if let (Some(u), false) = (unknown[i], single_x.contains(&i)) {
                map[u] = Some(nfr);
                is_trans.push(!is_lambda[i]);
                nfr += 1;
            }
            i += 1;
        }
        let mut n = nfr;
        let eliminated: std::collections::HashSet<usize> = nodes
            .iter()
            .map(|v| v.2)
            .chain(singles.iter().map(|v| v.2))
            .collect();
        for kc in 0..nk {
            if !eliminated.contains(&kc) {
                map[nf + kc] = Some(n);
                n += 1;
            }
        }
        // element columns and entry order
        let mut elem_start = Vec::with_capacity(model.elements.len() + 1);
        let mut elem_cols = Vec::with_capacity(model.elements.len());
        let mut beam_full = Vec::with_capacity(model.elements.len());
        let mut elem_cons = Vec::with_capacity(model.elements.len());
        let mut n_entries = 0;
        for entry in &model.elements {
            elem_start.push(n_entries);
            let mut ec = Vec::with_capacity(entry.xmap.len());
            let mut a = 0;
            while a < entry.xmap.len() {
                let xi = entry.xmap[a];
                if let Some(k) = node_at[xi] {
                    let d0 = nodes[k].1;
                    for j in 0..3 {
                        ec.push((RCol::Rot { a0: a, j }, d0 + j));
                    }
                    a += 4;
                    continue;
                }
                if let Some(m) = unknown[xi].and_then(|u| map[u]) {
                    ec.push((RCol::Plain(a), m));
                }
                a += 1;
            }
            let cons: Vec<usize> = (0..entry.element.ne())
                .filter_map(|m| constraint[entry.ie + m])
                .map(|kc| map[nf + kc].expect("element constraints are kept"))
                .collect();
            n_entries += element_entry_count(ec.len(), cons.len());
            elem_cons.push(cons);
            let full = entry.element.closed_form().is_some()
                && ec.len() == 12
                && (0..entry.element.ne()).all(|m| constraint[entry.ie + m].is_none())
                && ec.iter().enumerate().all(|(c, (col, _))| match (c, *col) {
                    (0..=2, RCol::Plain(a)) => a == c,
                    (3..=5, RCol::Rot { a0, j }) => a0 == 3 && j == c - 3,
                    (6..=8, RCol::Plain(a)) => a == c + 1,
                    (9..=11, RCol::Rot { a0, j }) => a0 == 10 && j == c - 9,
                    _ => false,
                });
            beam_full.push(full);
            elem_cols.push(ec);
        }
        elem_start.push(n_entries);
        let mut diag_trans = Vec::new();
        for (ec, &start) in elem_cols.iter().zip(&elem_start) {
            for (a, &(_, ua)) in ec.iter().enumerate() {
                if ua < nfr && is_trans[ua] {
                    diag_trans.push(start + a * ec.len() + a);
                }
            }
        }
        Self {
            map,
            nodes,
            singles,
            diag_trans,
            node_at,
            nfr,
            n,
            is_trans,
            elem_cols,
            beam_full,
            elem_cons,
            n_entries,
            elem_start,
        }
    }

    /// Row and column of every KKT entry written by the element assembly, in order: per
    /// element its block on the reduced columns (row-major), then for each constrained mode
    /// the pairs (G, Gᵀ). Generated, not stored (millions of entries on large models).
    fn for_each_entry(&self, mut f: impl FnMut(usize, usize)) {
        for (ec, cons) in self.elem_cols.iter().zip(&self.elem_cons) {
            element_entries(ec, cons.iter().copied(), &mut f);
        }
    }
}

/// The order of one element's KKT entries ([`Pattern`], [`Reduction`]): the block on its
/// columns (the unknown of each is the second of its pair), row-major, then for each of the
/// constraint rows `cons` the pairs (G, Gᵀ) over the columns.
fn element_entries<T>(
    cols: &[(T, usize)],
    cons: impl Iterator<Item = usize>,
    f: &mut impl FnMut(usize, usize),
) {
    for (_, ua) in cols {
        for (_, ub) in cols {
            f(*ua, *ub);
        }
    }
    for kr in cons {
        for (_, ub) in cols {
            f(kr, *ub);
            f(*ub, kr);
        }
    }
}

/// Number of entries [`element_entries`] writes for `nc` columns and `ncons` constraint rows.
fn element_entry_count(nc: usize, ncons: usize) -> usize {
    nc * nc + 2 * ncons * nc
}

/// Scale of the Euler-parameter increment N δ of a reduced node (|λ| = 1, ‖δ‖² = `d2`) so that
/// the node turns by atan ‖ω‖ instead of 2 atan(‖ω‖/2), ω = 2 Λ̄ N δ the linearised rotation:
/// s = tan(atan(2‖δ‖)/2)/‖δ‖ = 2/(1 + √(1 + 4‖δ‖²)).
///
/// Under the linear update of the positions a chord whose end moves across it by θ times its
/// length turns by atan θ. With this update a node triad that turns with the chord in the
/// linearised step (ω ⟂ chord, ‖ω‖ = θ) also turns by atan θ, whereas the plain update turns it
/// by 2 atan(θ/2): a mismatch of θ³/4 that loads the element's bending modes. On fine meshes
/// that mismatch, times the bending stiffness EI/l0³ of the short elements, dominates the
/// residual after a Newton step and makes Newton diverge (the straight cantilever at
/// N = 10,000). The update agrees with the plain one to first order (s = 1 − ‖δ‖² + …), so it
/// is still Newton's method with its local quadratic convergence, and the converged equilibria
/// are the same.
fn chord_consistent_scale(d2: f64) -> f64 {
    2.0 / (1.0 + (1.0 + 4.0 * d2).sqrt())
}

/// The multiplier of the normalisation of each node with a single free Euler parameter λ_i
/// ([`Reduction`]): the value that makes the equilibrium row of λ_i hold at the current state,
/// r_i + 2 Δμ λ_i = 0; the residual and the generalised forces of the node are updated with it.
/// (The full Newton system gives the same value up to the linearisation error, and at the
/// solution exactly.)
fn solve_single_multipliers(su: &Setup, x: &[f64], mu: &mut [f64], a: &mut Assembled) {
    for &(r, xi, kc) in &su.red.singles {
        let (Some(u), l) = (su.unknown[xi], x[xi]) else {
            continue;
        };
        if l == 0.0 {
            continue;
        }
        let dmu = -a.r[u] / (2.0 * l);
        mu[kc] += dmu;
        for c in r..r + 4 {
            a.balance[c] += 2.0 * dmu * x[c];
            if let Some(uc) = su.unknown[c] {
                a.r[uc] = a.balance[c];
            }
        }
    }
}

/// N(λ) = Λ̄(λ)ᵀ/‖λ‖ (4 × 3): Δλ = N δ spans λ⊥ with orthonormal columns.
fn rot_basis(l: &[f64]) -> [[f64; 3]; 4] {
    let l4 = [l[0], l[1], l[2], l[3]];
    let inv = 1.0 / l4.iter().map(|v| v * v).sum::<f64>().sqrt();
    let lb = lambda_bar(&l4);
    std::array::from_fn(|i| std::array::from_fn(|j| lb[j][i] * inv))
}

/// The reduced element entries Tᵀ K T and G T (see [`Reduction`]), written in its order.
/// `kt` is scratch of at least nx_k × (number of reduced columns).
#[allow(clippy::too_many_arguments)]
fn write_reduced(
    su: &Setup,
    el: usize,
    ie: usize,
    ne: usize,
    xk: &dyn Fn(usize) -> f64,
    nxk: usize,
    k: &dyn Fn(usize, usize) -> f64,
    d: &dyn Fn(usize, usize) -> f64,
    vals: &mut [f64],
    kt: &mut [f64],
) {
    let cols = &su.red.elem_cols[el];
    let nc = cols.len();
    // the columns of T: up to four (local coordinate, coefficient) pairs each
    let mut bases: [[[f64; 3]; 4]; 4] = [[[0.0; 3]; 4]; 4];
    let mut base_a0 = [usize::MAX; 4];
    let mut nb = 0;
    let mut tcol = |c: &RCol| -> ([(usize, f64); 4], usize) {
        match *c {
            RCol::Plain(a) => ([(a, 1.0), (0, 0.0), (0, 0.0), (0, 0.0)], 1),
            RCol::Rot { a0, j } => {
                let slot = match base_a0[..nb].iter().position(|&v| v == a0) {
                    Some(s) => s,
                    None => {
                        let l = [xk(a0), xk(a0 + 1), xk(a0 + 2), xk(a0 + 3)];
                        if nb == bases.len() {
                            // more than four rotational nodes in one element: no cache
                            let nm = rot_basis(&l);
                            return (std::array::from_fn(|i| (a0 + i, nm[i][j])), 4);
                        }
                        bases[nb] = rot_basis(&l);
                        base_a0[nb] = a0;
                        nb += 1;
                        nb - 1
                    }
                };
                (std::array::from_fn(|i| (a0 + i, bases[slot][i][j])), 4)
            }
        }
    };
    let mut ts_buf = [([(0usize, 0.0f64); 4], 0usize); 16];
    let mut ts_vec;
    let ts: &mut [([(usize, f64); 4], usize)] = if nc <= ts_buf.len() {
        &mut ts_buf[..nc]
    } else {
        ts_vec = vec![([(0usize, 0.0f64); 4], 0usize); nc];
        &mut ts_vec
    };
    for (t, (c, _)) in ts.iter_mut().zip(cols) {
        *t = tcol(c);
    }
    // K T
    for a in 0..nxk {
        for (c, (t, len)) in ts.iter().enumerate() {
            kt[a * nc + c] = t[..*len].iter().map(|&(b, w)| w * k(a, b)).sum();
        }
    }
    let mut i = 0;
    for (t1, l1) in ts.iter() {
        for c2 in 0..nc {
            vals[i] = t1[..*l1].iter().map(|&(a, w)| w * kt[a * nc + c2]).sum();
            i += 1;
        }
    }
    for m in 0..ne {
        if su.constraint[ie + m].is_some() {
            for (t, len) in ts.iter() {
                let v: f64 = t[..*len].iter().map(|&(b, w)| w * d(m, b)).sum();
                vals[i] = v;
                vals[i + 1] = v;
                i += 2;
            }
        }
    }
    debug_assert_eq!(i, vals.len());
}

/// Everything assembled at one state.
pub(crate) struct Assembled {
    /// Residual on the free coordinates.
    pub(crate) r: Vec<f64>,
    /// Constraint violations.
    pub(crate) g: Vec<f64>,
    /// KKT matrix entries, in the order of [`Pattern`] (or of [`Reduction`] for the reduced
    /// system) followed by the tail entries (moments, normalisations) whose row and column are
    /// in `tail`.
    pub(crate) vals: Vec<f64>,
    /// Number of element entries at the start of `vals`.
    pub(crate) n_el: usize,
    /// Row and column of the entries after the element blocks.
    pub(crate) tail: Vec<(usize, usize)>,
    /// KKT matrix entries as triplets (only from [`assemble_part`], for the linearisation).
    pub(crate) triplets: Vec<Triplet<usize, usize, f64>>,
    /// Force scale for the convergence test.
    pub(crate) f_scale: f64,
    /// Full generalised force balance f_int − f_ext + ∇p on all of x (reactions).
    pub(crate) balance: Vec<f64>,
    /// Element part of `balance` (internal forces Dᵀσ) and the sums of their magnitudes.
    pub(crate) int_force: Vec<f64>,
    pub(crate) int_abs: Vec<f64>,
    pub(crate) e: Vec<f64>,
    pub(crate) sigma: Vec<f64>,
    pub(crate) energy: f64,
    /// Whether `vals` holds the reduced system ([`Reduction`]).
    pub(crate) reduced: bool,
}

/// Which part of the tangent to assemble.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Part {
    /// K = K_material + K_geometric (Newton).
    Full,
    /// Dᵀ S D only.
    Material,
    /// Σ σᵢ ∂²eᵢ/∂x² + normalisation multipliers + load stiffness (proportional to the load).
    Geometric,
    /// No tangent: forces, deformations and constraint violations only (the matrix values
    /// are left as they are; a modified Newton iteration that reuses its matrix).
    Residual,
}

pub(crate) fn assemble(model: &Model, su: &Setup, x: &[f64], mu: &[f64], t: f64) -> Assembled {
    assemble_values(model, su, x, mu, t, Part::Full, false, Vec::new())
}

/// [`assemble_values`] with the KKT entries as triplets.
pub(crate) fn assemble_part(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
) -> Assembled {
    let mut a = assemble_values(model, su, x, mu, t, part, false, Vec::new());
    let pat = su.pattern.layout();
    let n_el = pat.rows.len();
    a.triplets = (0..n_el)
        .map(|i| Triplet::new(pat.rows[i], pat.cols[i], a.vals[i]))
        .chain(
            a.tail
                .iter()
                .zip(&a.vals[n_el..])
                .map(|(&(r, c), &v)| Triplet::new(r, c, v)),
        )
        .collect();
    a
}

/// One element's contribution, written into its own slices (parallel part): deformations,
/// stress resultants, internal forces Dᵀσ on its local coordinates, and its block of KKT
/// entries in [`Pattern`] order (with `reduced`, [`Reduction`] order). Returns the elastic
/// energy.
#[allow(clippy::too_many_arguments)]
fn element_local(
    su: &Setup,
    el: usize,
    entry: &crate::model::ElementEntry,
    x: &[f64],
    mu: &[f64],
    part: Part,
    reduced: bool,
    e_out: &mut [f64],
    sigma_out: &mut [f64],
    f_out: &mut [f64],
    vals: &mut [f64],
) -> f64 {
    let s = &su.s_eff[el];
    let ne = e_out.len();
    let free = &su.pattern.elem_free[el];
    // σ = S_eff e, plus multipliers on constrained modes
    let stress = |e: &[f64], sigma: &mut [f64]| -> f64 {
        let mut energy = 0.0;
        for a in 0..ne {
            sigma[a] = (0..ne).map(|b| s[(a, b)] * e[b]).sum();
            energy += 0.5 * sigma[a] * e[a];
            if let Some(c) = su.constraint[entry.ie + a] {
                sigma[a] += mu[c];
            }
        }
        energy
    };
    // KKT entries: K on the free local coordinates, then (G, Gᵀ) of the constrained modes
    let write =
        |vals: &mut [f64], k: &dyn Fn(usize, usize) -> f64, d: &dyn Fn(usize, usize) -> f64| {
            let mut i = 0;
            for &(a, _) in free {
                for &(b, _) in free {
                    vals[i] = k(a, b);
                    i += 1;
                }
            }
            for m in 0..ne {
                if su.constraint[entry.ie + m].is_some() {
                    for &(b, _) in free {
                        let v = d(m, b);
                        vals[i] = v;
                        vals[i + 1] = v;
                        i += 2;
                    }
                }
            }
            debug_assert_eq!(i, vals.len());
        };
    if let (Some(cf), 14) = (entry.element.closed_form(), entry.xmap.len()) {
        // closed-form derivatives in fixed-size arrays (elements/beam/closed_form.rs)
        let xk: [f64; 14] = std::array::from_fn(|i| x[entry.xmap[i]]);
        let first = cf.first(&xk);
        e_out.copy_from_slice(&first.e);
        let energy = stress(&first.e, sigma_out);
        let d = &first.d;
        for (c, f) in f_out.iter_mut().enumerate() {
            *f = (0..6).map(|a| d[a][c] * sigma_out[a]).sum();
        }
        if part == Part::Residual {
            return energy;
        }
        let s6: [[f64; 6]; 6] = std::array::from_fn(|a| std::array::from_fn(|b| s[(a, b)]));
        let w: [f64; 6] = std::array::from_fn(|a| sigma_out[a]);
        if reduced && su.red.beam_full[el] && part == Part::Full {
            // Tᵀ K T directly in the tangent coordinates of both rotations
            let (bp, bq) = (rot_basis(&xk[3..7]), rot_basis(&xk[10..14]));
            let k = first.hessian_tangent(&w, Some(&s6), &bp, &bq);
            for (o, v) in vals.chunks_exact_mut(12).zip(&k) {
                o.copy_from_slice(v);
            }
            return energy;
        }
        let k = match part {
            Part::Full => first.hessian(&w, Some(&s6)),
            Part::Material => first.hessian(&[0.0; 6], Some(&s6)),
            Part::Geometric | Part::Residual => first.hessian(&w, None),
        };
        if reduced {
            // at most 14 reduced columns
            let mut kt = [0.0; 14 * 14];
            write_reduced(
                su,
                el,
                entry.ie,
                ne,
                &|a| xk[a],
                14,
                &|a, b| k[a][b],
                &|m, b| d[m][b],
                vals,
                &mut kt,
            );
        } else {
            write(vals, &|a, b| k[a][b], &|m, b| d[m][b]);
        }
        return energy;
    }
    let xk = gather(entry, x);
    let e = entry.element.deformations(&xk);
    let d = entry.element.jacobian(&xk);
    e_out.copy_from_slice(&e);
    let energy = stress(&e, sigma_out);
    for (c, f) in f_out.iter_mut().enumerate() {
        *f = (0..ne).map(|a| d[(a, c)] * sigma_out[a]).sum();
    }
    if part == Part::Residual {
        return energy;
    }
    // K_k = Dᵀ S D + Σ σᵢ ∂²eᵢ/∂x²
    let nxk = xk.len();
    let mut k = if part == Part::Material {
        Mat::zeros(nxk, nxk)
    } else {
        entry.element.hessian_weighted(&xk, sigma_out)
    };
    if part != Part::Geometric {
        let sd = s * &d;
        k += d.transpose() * &sd;
    }
    if reduced {
        let mut kt = vec![0.0; nxk * su.red.elem_cols[el].len()];
        write_reduced(
            su,
            el,
            entry.ie,
            ne,
            &|a| xk[a],
            nxk,
            &|a, b| k[(a, b)],
            &|m, b| d[(m, b)],
            vals,
            &mut kt,
        );
    } else {
        write(vals, &|a, b| k[(a, b)], &|m, b| d[(m, b)]);
    }
    energy
}

/// Models with fewer elements are assembled on the calling thread.
const PAR_ELEMENTS: usize = 256;

/// An element's index with its slices of the KKT values, deformations, stress resultants and
/// internal forces (the parallel part of the assembly).
type ElementSlices<'a> = (
    usize,
    (
        ((&'a mut [f64], &'a mut [f64]), &'a mut [f64]),
        &'a mut [f64],
    ),
);

/// Split `v` into consecutive pieces at the given offsets (`starts` ascending, first 0).
fn split_at_starts<'a>(mut v: &'a mut [f64], starts: &[usize]) -> Vec<&'a mut [f64]> {
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    for w in starts.windows(2) {
        let (head, rest) = v.split_at_mut(w[1] - w[0]);
        out.push(head);
        v = rest;
    }
    out
}

/// Assemble at (x, μ, t): the KKT entries of the full system (order of [`Pattern`]) or, with
/// `reduced`, of the reduced one ([`Reduction`]); `spare` is a buffer to reuse for them.
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble_values(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
    reduced: bool,
    spare: Vec<f64>,
) -> Assembled {
    let pat = &su.pattern;
    let (n_el, elem_start) = if reduced {
        (su.red.n_entries, &su.red.elem_start)
    } else {
        let layout = pat.layout();
        (layout.rows.len(), &layout.elem_start)
    };
    // every element entry is written by its element: no need to clear a reused buffer
    let mut vals = spare;
    vals.truncate(n_el);
    vals.resize(n_el, 0.0);
    let mut e = vec![0.0; model.ne];
    let mut sigma = vec![0.0; model.ne];
    let mut fbuf = vec![0.0; *pat.f_start.last().unwrap_or(&0)];
    let e_starts: Vec<usize> = model
        .elements
        .iter()
        .map(|en| en.ie)
        .chain(std::iter::once(model.ne))
        .collect();
    let energy: f64 = {
        let vals_k = split_at_starts(&mut vals, elem_start);
        let e_k = split_at_starts(&mut e, &e_starts);
        let sigma_k = split_at_starts(&mut sigma, &e_starts);
        let f_k = split_at_starts(&mut fbuf, &pat.f_start);
        let one = |(el, (((v, ek), sk), fk)): ElementSlices<'_>| {
            element_local(
                su,
                el,
                &model.elements[el],
                x,
                mu,
                part,
                reduced,
                ek,
                sk,
                fk,
                v,
            )
        };
        if model.elements.len() < PAR_ELEMENTS {
            // small models: the hand-over to worker threads costs more than it saves
            vals_k
                .into_iter()
                .zip(e_k)
                .zip(sigma_k)
                .zip(f_k)
                .enumerate()
                .map(one)
                .sum()
        } else {
            vals_k
                .into_par_iter()
                .zip(e_k)
                .zip(sigma_k)
                .zip(f_k)
                .enumerate()
                .with_min_len(64)
                .map(one)
                .sum()
        }
    };

    let mut int_force = vec![0.0; model.nx];
    let mut int_abs = vec![0.0; model.nx];
    for (el, entry) in model.elements.iter().enumerate() {
        // internal forces Dᵀσ
        let f = &fbuf[pat.f_start[el]..pat.f_start[el + 1]];
        for (&xi, &fi) in entry.xmap.iter().zip(f) {
            int_force[xi] += fi;
            int_abs[xi] += fi.abs();
        }
    }
    let n_el = vals.len();
    let mut a = Assembled {
        r: Vec::new(),
        g: Vec::new(),
        vals,
        n_el,
        tail: Vec::new(),
        triplets: Vec::new(),
        f_scale: 0.0,
        balance: Vec::new(),
        int_force,
        int_abs,
        e,
        sigma,
        energy,
        reduced,
    };
    apply_loads(model, su, x, mu, t, part, &mut a);
    a
}

/// The parts of an assembly that depend on the load factor t, the multipliers of the
/// normalisations and the prescribed deformations, on top of its element part: external
/// forces and load stiffness, normalisation terms, constraint violations, residual and force
/// scale. Replaces those of an earlier call, so an assembly at the same state can be reused
/// for another t. The load stiffness of moments and the normalisation term 2μ I are
/// load-proportional: they belong to the geometric part, so `Part::Material` writes zeros in
/// their (fixed) matrix positions.
fn apply_loads(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
    a: &mut Assembled,
) {
    let geo = if part == Part::Material { 0.0 } else { 1.0 };
    let (nf, nk) = (su.nf, su.nk);
    let reduced = a.reduced;
    let mut balance = a.int_force.clone();
    let mut f_abs = a.int_abs.clone();
    let mut g = vec![0.0; nk];
    a.vals.truncate(a.n_el);
    let vals = &mut a.vals;
    // constraint violations of the elements
    for entry in &model.elements {
        for m in 0..entry.element.ne() {
            let i = entry.ie + m;
            let Some(kc) = su.constraint[i] else {
                continue;
            };
            let target = match su.roles[i] {
                Role::Input => t * su.e_targets[i],
                _ => 0.0,
            };
            g[kc] = a.e[i] - target;
        }
    }
    let mut tail = Vec::new();
    // external dead forces
    for i in 0..model.nx {
        balance[i] -= t * su.f_dead[i];
        f_abs[i] += (t * su.f_dead[i]).abs();
    }
    // moments: f_λ = 2 Λ̄(λ)ᵀ M, load stiffness −∂f/∂λ = −2 A(M)
    for &(r, m) in &su.moments {
        let f1 = moment_forces(x, r, &m);
        for c in 0..4 {
            let f = t * f1[c];
            balance[r + c] -= f;
            f_abs[r + c] += f.abs();
        }
        let am = [
            [0.0, -m[0], -m[1], -m[2]],
            [m[0], 0.0, -m[2], m[1]],
            [m[1], m[2], 0.0, -m[0]],
            [m[2], -m[1], m[0], 0.0],
        ];
        if let (true, Some(k)) = (reduced, su.red.node_at[r]) {
            // Nᵀ (−2 t A) N on the node's rotation increments
            let nb = rot_basis(&x[r..r + 4]);
            let d0 = su.red.nodes[k].1;
            for p in 0..3 {
                for q in 0..3 {
                    let mut v = 0.0;
                    for i in 0..4 {
                        for j in 0..4 {
                            v += nb[i][p] * am[i][j] * nb[j][q];
                        }
                    }
                    tail.push((d0 + p, d0 + q));
                    vals.push(-2.0 * t * v * geo);
                }
            }
            continue;
        }
        let idx = |u: usize| if reduced { su.red.map[u] } else { Some(u) };
        for i in 0..4 {
            let Some(ui) = su.unknown[r + i].and_then(idx) else {
                continue;
            };
            for j in 0..4 {
                if let Some(uj) = su.unknown[r + j].and_then(idx) {
                    tail.push((ui, uj));
                    vals.push(-2.0 * t * am[i][j] * geo);
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
        }
        if let (true, Some(k)) = (reduced, su.red.node_at[r]) {
            // Nᵀ (2μ I) N = 2μ I on the rotation increments (N orthonormal)
            let d0 = su.red.nodes[k].1;
            for j in 0..3 {
                tail.push((d0 + j, d0 + j));
                vals.push(2.0 * mu[kc] * geo);
            }
            continue;
        }
        let idx = |u: usize| if reduced { su.red.map[u] } else { Some(u) };
        let Some(kr) = idx(nf + kc) else {
            continue;
        };
        for i in 0..4 {
            let Some(ui) = su.unknown[r + i].and_then(idx) else {
                continue;
            };
            tail.extend([(ui, ui), (kr, ui), (ui, kr)]);
            vals.extend([2.0 * mu[kc] * geo, 2.0 * l[i], 2.0 * l[i]]);
        }
    }
    let mut r = vec![0.0; nf];
    for i in 0..model.nx {
        if let Some(u) = su.unknown[i] {
            r[u] = balance[i];
        }
    }
    a.f_scale = f_abs.iter().cloned().fold(0.0, f64::max);
    a.r = r;
    a.g = g;
    a.tail = tail;
    a.balance = balance;
}

/// The generalised forces 2 Λ̄(λ)ᵀ M on the Euler parameters (λ0 at x index `r`) of a moment M
/// (global axes) at load factor 1.
fn moment_forces(x: &[f64], r: usize, m: &[f64; 3]) -> [f64; 4] {
    let lb = lambda_bar(&[x[r], x[r + 1], x[r + 2], x[r + 3]]);
    std::array::from_fn(|c| 2.0 * (0..3).map(|k| lb[k][c] * m[k]).sum::<f64>())
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

/// The linearised problem at a converged state in the reduced unknowns of the Newton system
/// ([`Reduction`]), as sparse entries: the basis of the sparse eigen path of
/// [`crate::dynamics`].
///
/// The unknowns are the free translations and other free coordinates, three rotation
/// increments δ per rotational node whose Euler parameters are all free (Δλ = N(λ) δ with
/// N = Λ̄ᵀ, so the angular velocity is ω = 2 δ: velocity coordinates), and the multipliers of the
/// kept constraints (rigid and input deformations, normalisations of partly held nodes). The
/// matrix is the Newton matrix of statics at the state, [K, Gᵀ; G, 0] with K = K_m + K_g
/// (material and geometric stiffness, normalisation terms, load stiffness of moments): the same
/// stiffness as the dense [`crate::linearized::linearize`], in other coordinates.
pub(crate) struct ReducedLinear {
    su: Setup,
    /// Row and column of the entries after the element blocks (moments, normalisations).
    tail: Vec<(usize, usize)>,
    /// Value of every entry: the element blocks (in [`Reduction`] order, see
    /// [`ReducedLinear::for_each_entry`]), then the tail.
    pub vals: Vec<f64>,
    /// The geometric (load-proportional) part K_g of the values: zero in the constraint rows
    /// and columns.
    pub geo: Vec<f64>,
}

impl ReducedLinear {
    /// The reduced tangent at a converged step.
    pub(crate) fn new(model: &Model, step: &StepResult) -> Self {
        let su = setup(model);
        let a = assemble_values(
            model,
            &su,
            &step.x,
            &step.multipliers,
            step.load_factor,
            Part::Full,
            true,
            Vec::new(),
        );
        debug_assert_eq!(su.red.n_entries + a.tail.len(), a.vals.len());
        // the geometric part vanishes in a state without stress resultants, multipliers and
        // moment loads (the unloaded reference state)
        let unstressed = step.sigma.iter().all(|&v| v == 0.0)
            && step.multipliers.iter().all(|&v| v == 0.0)
            && (su.moments.is_empty() || step.load_factor == 0.0);
        let mut geo = if unstressed {
            vec![0.0; a.vals.len()]
        } else {
            let g = assemble_values(
                model,
                &su,
                &step.x,
                &step.multipliers,
                step.load_factor,
                Part::Geometric,
                true,
                Vec::new(),
            );
            debug_assert_eq!(g.tail, a.tail);
            g.vals
        };
        let nfr = su.red.nfr;
        let mut i = 0;
        let mut clear_constraints = |r: usize, c: usize| {
            if r >= nfr || c >= nfr {
                geo[i] = 0.0;
            }
            i += 1;
        };
        su.red.for_each_entry(&mut clear_constraints);
        for &(r, c) in &a.tail {
            clear_constraints(r, c);
        }
        Self {
            su,
            tail: a.tail,
            vals: a.vals,
            geo,
        }
    }

    /// Row and column of every entry, in the order of `vals`.
    pub(crate) fn for_each_entry(&self, mut f: impl FnMut(usize, usize)) {
        self.su.red.for_each_entry(&mut f);
        for &(r, c) in &self.tail {
            f(r, c);
        }
    }

    /// Twice the material strain energy, Σ δeᵀ S δe over the elements' flexible deformations
    /// with δe = D δx, of each shape δx (length nx). Evaluated through the deformations, not as
    /// δxᵀ K_m δx: on fine meshes the entries of K_m are many orders of magnitude larger than
    /// the stiffness of a smooth mode, and the matrix product loses it to round-off.
    pub(crate) fn material_energy2(
        &self,
        model: &Model,
        x: &[f64],
        shapes: &[Vec<f64>],
    ) -> Vec<f64> {
        material_energy2(model, &self.su, x, shapes)
    }

    /// The material stiffness times a displacement, K_m δx = Σ Dᵀ S (D δx) over the elements'
    /// flexible deformations, as forces in x (length nx). Evaluated through the deformations δe
    /// = D δx, for the reason given at [`ReducedLinear::material_energy2`]: the product with the
    /// assembled K_m loses the small elastic forces of a smooth displacement to round-off.
    pub(crate) fn material_forces(&self, model: &Model, x: &[f64], dx: &[f64]) -> Vec<f64> {
        let mut f = vec![0.0; model.nx];
        for (el, entry) in model.elements.iter().enumerate() {
            let s = &self.su.s_eff[el];
            let ne = entry.element.ne();
            if (0..ne).all(|a| (0..ne).all(|b| s[(a, b)] == 0.0)) {
                continue;
            }
            let d = entry.element.jacobian(&gather(entry, x));
            let de = deformation_change(entry, &d, dx);
            let sigma: Vec<f64> = (0..ne)
                .map(|a| (0..ne).map(|b| s[(a, b)] * de[b]).sum())
                .collect();
            for (c, &i) in entry.xmap.iter().enumerate() {
                f[i] += (0..ne).map(|r| d[(r, c)] * sigma[r]).sum::<f64>();
            }
        }
        f
    }

    /// Whether the model has applied moments (also those of a spin): their load stiffness is
    /// not symmetric.
    pub(crate) fn has_moment_loads(&self) -> bool {
        !self.su.moments.is_empty()
    }

    /// The row of the system that holds deformation `e` (a rigid or input deformation).
    pub(crate) fn constraint_row(&self, e: usize) -> Option<usize> {
        self.su.constraint[e].and_then(|k| self.su.red.map[self.su.nf + k])
    }

    /// Size of the system (coordinates and kept constraints).
    pub(crate) fn n(&self) -> usize {
        self.su.red.n
    }

    /// Number of coordinate unknowns (they come first; the constraints follow).
    pub(crate) fn n_coords(&self) -> usize {
        self.su.red.nfr
    }

    /// The entries of element `el` (a contiguous range of `rows`/`cols`/`vals`).
    pub(crate) fn element_entries(&self, el: usize) -> std::ops::Range<usize> {
        self.su.red.elem_start[el]..self.su.red.elem_start[el + 1]
    }

    /// Tᵀ L T for a matrix L on the local coordinates of element `el` (`local(a, b)`, local
    /// order of its `xmap`), written into `out` in the order of the element's entries; the
    /// entries of its constraint rows get zero.
    pub(crate) fn element_block(
        &self,
        model: &Model,
        el: usize,
        x: &[f64],
        local: &dyn Fn(usize, usize) -> f64,
        out: &mut [f64],
    ) {
        let entry = &model.elements[el];
        let nxk = entry.xmap.len();
        let mut kt = vec![0.0; nxk * self.su.red.elem_cols[el].len()];
        write_reduced(
            &self.su,
            el,
            entry.ie,
            entry.element.ne(),
            &|a| x[entry.xmap[a]],
            nxk,
            local,
            &|_, _| 0.0,
            out,
            &mut kt,
        );
    }

    /// The reduced index of x coordinate `i` when it is an unknown of its own (a free
    /// translation, or an Euler parameter of a node that is not reduced).
    pub(crate) fn coord_index(&self, i: usize) -> Option<usize> {
        self.su.unknown[i].and_then(|u| self.su.red.map[u])
    }

    /// Entries (row, column, value) of Tᵀ B T for a 4 × 4 block B on the Euler parameters of
    /// the rotational node with λ0 at x index `r` (an inertia tensor).
    pub(crate) fn lambda_block(
        &self,
        x: &[f64],
        r: usize,
        blk: &[[f64; 4]; 4],
    ) -> Vec<(usize, usize, f64)> {
        let mut out = Vec::new();
        if let Some(k) = self.su.red.node_at[r] {
            let nb = rot_basis(&x[r..r + 4]);
            let d0 = self.su.red.nodes[k].1;
            for p in 0..3 {
                for q in 0..3 {
                    let mut v = 0.0;
                    for i in 0..4 {
                        for j in 0..4 {
                            v += nb[i][p] * blk[i][j] * nb[j][q];
                        }
                    }
                    out.push((d0 + p, d0 + q, v));
                }
            }
            return out;
        }
        for i in 0..4 {
            let Some(ri) = self.coord_index(r + i) else {
                continue;
            };
            for j in 0..4 {
                if let Some(rj) = self.coord_index(r + j) {
                    out.push((ri, rj, blk[i][j]));
                }
            }
        }
        out
    }

    /// Whether coordinate unknown `m` is a translation (else an Euler parameter or a rotation
    /// increment).
    pub(crate) fn is_translation(&self, m: usize) -> bool {
        self.su.red.is_trans[m]
    }

    /// The node of every coordinate unknown (a node `at` a host owns only its rotation): the
    /// unknowns of one node share their couplings, which a fill-reducing ordering can use.
    pub(crate) fn coord_nodes(&self, model: &Model) -> Vec<usize> {
        let mut owner = vec![usize::MAX; model.nx];
        for (id, n) in model.nodes.iter().enumerate() {
            for i in n.own_range() {
                owner[i] = id;
            }
        }
        let mut out = vec![usize::MAX; self.su.red.nfr];
        for (i, &o) in owner.iter().enumerate() {
            if let Some(m) = self.coord_index(i) {
                out[m] = o;
            }
        }
        for &(r, d0, _) in &self.su.red.nodes {
            out[d0..d0 + 3].iter_mut().for_each(|v| *v = owner[r]);
        }
        out
    }

    /// Generalised forces on the reduced coordinates of a force vector `f` in x (length nx):
    /// the transpose of [`ReducedLinear::to_x`], so that uᵀ (this) = (to_x u)ᵀ f.
    pub(crate) fn force_to_coords(&self, x: &[f64], f: &[f64]) -> Vec<f64> {
        let mut fc = vec![0.0; self.n_coords()];
        for (i, fi) in f.iter().enumerate() {
            if let Some(m) = self.coord_index(i) {
                fc[m] += fi;
            }
        }
        for &(r, d0, _) in &self.su.red.nodes {
            let nb = rot_basis(&x[r..r + 4]);
            for (j, v) in fc[d0..d0 + 3].iter_mut().enumerate() {
                *v += (0..4).map(|i| nb[i][j] * f[r + i]).sum::<f64>();
            }
        }
        fc
    }

    /// δx (length nx) of a vector `u` of the coordinate unknowns at the state `x`.
    pub(crate) fn to_x(&self, model: &Model, x: &[f64], u: &[f64]) -> Vec<f64> {
        let mut dx = vec![0.0; model.nx];
        for (i, d) in dx.iter_mut().enumerate() {
            if let Some(m) = self.coord_index(i) {
                *d = u[m];
            }
        }
        for &(r, d0, _) in &self.su.red.nodes {
            let nb = rot_basis(&x[r..r + 4]);
            for i in 0..4 {
                dx[r + i] = (0..3).map(|j| nb[i][j] * u[d0 + j]).sum();
            }
        }
        dx
    }
}

/// Twice the material strain energy Σ δeᵀ S δe of each shape δx (length nx) over the
/// elements' flexible deformations (the effective stiffnesses of `su`), δe = D δx
/// ([`ReducedLinear::material_energy2`]).
pub(crate) fn material_energy2(
    model: &Model,
    su: &Setup,
    x: &[f64],
    shapes: &[Vec<f64>],
) -> Vec<f64> {
    let per_element = |el: usize| -> Vec<f64> {
        let entry = &model.elements[el];
        let s = &su.s_eff[el];
        let ne = entry.element.ne();
        if (0..ne).all(|a| (0..ne).all(|b| s[(a, b)] == 0.0)) {
            return vec![0.0; shapes.len()];
        }
        deformation_energies(entry, s, x, shapes)
            .chunks_exact(ne)
            .map(|e| e.iter().sum())
            .collect()
    };
    let parts: Vec<Vec<f64>> = if model.elements.len() < 256 {
        (0..model.elements.len()).map(per_element).collect()
    } else {
        (0..model.elements.len())
            .into_par_iter()
            .with_min_len(64)
            .map(per_element)
            .collect()
    };
    let mut out = vec![0.0; shapes.len()];
    for p in &parts {
        for (o, v) in out.iter_mut().zip(p) {
            *o += v;
        }
    }
    out
}

/// δeₐ (S δe)ₐ of every deformation a of an element for each displacement δx (length nx),
/// δe = D δx: twice the strain energy of the deformation (with the coupling terms of S split
/// by rows); flat, shape k's values at k ne … (k + 1) ne. Closed-form D in fixed-size arrays
/// for the beam.
pub(crate) fn deformation_energies(
    entry: &crate::model::ElementEntry,
    s: &Mat<f64>,
    x: &[f64],
    shapes: &[Vec<f64>],
) -> Vec<f64> {
    let ne = entry.element.ne();
    let mut out = Vec::with_capacity(ne * shapes.len());
    if let (Some(cf), 6, 14) = (entry.element.closed_form(), ne, entry.xmap.len()) {
        // the same sums as below, without allocations per shape
        let xk: [f64; 14] = std::array::from_fn(|i| x[entry.xmap[i]]);
        let d = cf.first(&xk).d;
        for dx in shapes {
            let de: [f64; 6] = std::array::from_fn(|r| {
                entry
                    .xmap
                    .iter()
                    .enumerate()
                    .map(|(c, &i)| d[r][c] * dx[i])
                    .sum()
            });
            out.extend((0..6).map(|a| de[a] * (0..6).map(|b| s[(a, b)] * de[b]).sum::<f64>()));
        }
        return out;
    }
    let d = entry.element.jacobian(&gather(entry, x));
    for dx in shapes {
        let de = deformation_change(entry, &d, dx);
        out.extend((0..ne).map(|a| de[a] * (0..ne).map(|b| s[(a, b)] * de[b]).sum::<f64>()));
    }
    out
}

/// δe = D δx_k of an element for a displacement δx (length nx).
fn deformation_change(entry: &crate::model::ElementEntry, d: &Mat<f64>, dx: &[f64]) -> Vec<f64> {
    (0..d.nrows())
        .map(|r| {
            entry
                .xmap
                .iter()
                .enumerate()
                .map(|(c, &i)| d[(r, c)] * dx[i])
                .sum()
        })
        .collect()
}

pub mod linear;
mod newton;
mod path;

/// The sparse Newton matrix of statics (`newton.rs`), also for other analyses of the crate.
pub(crate) use newton::KktSolver;
use newton::{newton, Newton};

pub use path::{solve, solve_path, StaticAnalysis, Stopped};

mod arc;
#[cfg(test)]
pub(crate) use path::{last_step, solve_steps};

#[cfg(test)]
mod tests;
