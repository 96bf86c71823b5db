//! Arc-length path following (docs/statics.md, "Path following"): the load factor t is an
//! unknown beside the coordinates and multipliers, and every step covers the same length Δl of
//! the path, so the path passes limit points of the load (snap-through) and of any
//! displacement (snap-back).
//!
//! - **Constraint** (Crisfield 1981, cylindrical): ‖Δx‖²_W + Δt² ‖ṗ‖²_W = Δl², with Δx the
//!   increment of the free coordinates since the last converged state (W: translations divided
//!   by the model size L, rotation increments as they are: the norm of the convergence test)
//!   and ṗ the rate of the prescribed coordinates (translations over L, rotations as half
//!   angles; their motion Δt ṗ is part of the path; a path under loads alone has ṗ = 0 and the
//!   plain cylindrical constraint).
//! - **Iteration**: at (x, μ, t) two solves with one factorisation of the Newton matrix K:
//!   K δa = −(r, g) and K δb = −∂(r, g)/∂t (the load rate: the dead loads, the moments, the
//!   targets of prescribed deformations, and K_fp ṗ, G_p ṗ of the prescribed translations). The
//!   correction δ = δa + δt δb keeps the constraint: a quadratic in δt, whose root is the one
//!   whose new increment makes the smaller angle with the old one (Crisfield's choice, which
//!   keeps going forward on the path).
//! - **Predictor**: δt₀ = ±Δl / ‖(δb, ṗ)‖ along the tangent δb at the converged state, with the
//!   sign that continues the previous increment (positive work of the tangent on it: through a
//!   limit point the load factor turns back by itself).
//! - **Step length**: Δl₀ is the length of the first tangent step to t = 1/steps; after a
//!   converged step Δl changes by the smallest of √(5/iterations), 0.05 rad / the turn of the
//!   path in that step (in the coordinates and the load factor scaled by the first tangent)
//!   and (1/steps) / |Δt| (no faster in the load than the load steps), within ½ … 2 per step
//!   and at most 1000 Δl₀;
//!   a step that fails (no convergence, an inverted element) is halved, down to
//!   Δl₀ / 2^max_halvings, where the path stops with the error.
//! - **End**: when the predictor would pass t = 1 on the way up, the last step is solved at
//!   t = 1 exactly (load control from the tangent), so the path ends at the full load; it
//!   stops after 50 × steps steps otherwise ([`SolveError::PathTooLong`]).
//! - **Stability and critical points**: the inertia of the L D Lᵀ factorisation of K at each
//!   converged state gives its number of negative stiffness directions on the constraints; where
//!   it changes within a step, the critical state is located in the step and inserted into the
//!   path (`critical.rs`): a limit point where the load factor turns, a bifurcation where it goes
//!   on ([`PathEvent`]). Every state reports the smallest eigenvalues of the tangent
//!   (`eigen.rs`).
//! - **Prescribed coordinates**: translations x0 + t v and rotations (Euler parameters
//!   sin(t v/2)) move with t; their rate ṗ enters the load rate (K_fp ṗ, G_p ṗ) and the
//!   constraint.

use super::critical::{critical_points, locate, Bracket, Located};
use super::eigen::tangent_eigenvalues;
use super::levels::{level_of, level_states, snap_to_level};
use super::newton::{
    check, expand, increment_size, reduced_rhs, reference_stiffness, step_to, Status, SINGULAR,
};
use super::path::{check_options, record};
use super::{
    apply_prescribed, assemble_values, inverted_element, moment_forces, newton, non_finite_parts,
    normalise_lambda, setup, solve_single_multipliers, Assembled, KktSolver, Newton, Part,
    PathEvent, PathPoint, Role, Setup, SolveError, StaticOptions, StepResult,
};
use crate::assembly::gather;
use crate::elements::ElementKind;
use crate::model::Model;

/// Target Newton iterations per step of the step-length control.
const TARGET_ITERATIONS: f64 = 5.0;

/// The most steps of a path, per requested load step.
const STEPS_PER_LOAD_STEP: usize = 50;

/// The largest step length, in units of the first one.
const MAX_GROWTH: f64 = 1e3;

/// The turn of the path per step that the step length aims at [rad], measured in the
/// coordinates and the load factor scaled by the first tangent (so that a straight path in
/// either takes long steps and a bend, a limit point or the onset of buckling short ones).
const TARGET_TURN: f64 = 0.05;

/// The rate dx_p/dt of the prescribed coordinates at the load factor t (length nx): v for a
/// translation x0 + t v, (v/2) cos(t v/2) for the Euler parameter sin(t v/2) of a rotation by
/// t v, and for the Euler parameter that follows from the normalisation alone (a node with a
/// single free one, λ_f² = 1 − Σ others²) −Σ λ_i λ̇_i / λ_f.
fn prescribed_rate(su: &Setup, x: &[f64], t: f64) -> Vec<f64> {
    let mut rate = vec![0.0; x.len()];
    for &(i, v) in &su.x_targets {
        rate[i] = if su.is_lambda[i] {
            0.5 * v * (0.5 * t * v).cos()
        } else {
            v
        };
    }
    for &(r, f, _) in &su.red.singles {
        if x[f] != 0.0 {
            let w: f64 = (r..r + 4).filter(|&i| i != f).map(|i| x[i] * rate[i]).sum();
            rate[f] = -w / x[f];
        }
    }
    rate
}

/// ‖ṗ‖²_W, the rate of the prescribed coordinates in the norm of the constraint: (v/L)² for a
/// translation, (v/2)² for a rotation by t v (the rotation increments of the norm are half
/// angles, ω = 2δ).
fn prescribed_rate2(su: &Setup) -> f64 {
    su.x_targets
        .iter()
        .map(|&(i, v)| {
            if su.is_lambda[i] {
                (0.5 * v).powi(2)
            } else {
                (v / su.l_ref).powi(2)
            }
        })
        .sum()
}

/// The rate of the residual and the constraints with the load factor at (x, μ, t),
/// ∂(r, g)/∂t, with `a` the assembly there (its stress resultants).
fn load_rate(model: &Model, su: &Setup, x: &[f64], t: f64, a: &Assembled) -> (Vec<f64>, Vec<f64>) {
    let mut qx = su.f_dead.iter().map(|f| -f).collect::<Vec<f64>>();
    for &(r, m) in &su.moments {
        let f1 = moment_forces(x, r, &m);
        for c in 0..4 {
            qx[r + c] -= f1[c];
        }
    }
    let mut qg = vec![0.0; su.nk];
    for (i, role) in su.roles.iter().enumerate() {
        if let (Role::Input, Some(kc)) = (role, su.constraint[i].get()) {
            qg[kc] = -su.e_targets[i];
        }
    }
    // prescribed coordinates x_p(t): the forces and constraint rates of their motion,
    // K_fp ẋ_p and G_p ẋ_p, element by element, and the rates of the Euler normalisations
    let rate = prescribed_rate(su, x, t);
    for &(r, kc) in &su.norm {
        qg[kc] += (r..r + 4).map(|i| 2.0 * x[i] * rate[i]).sum::<f64>();
    }
    for (el, entry) in model.elements.iter().enumerate() {
        let s = su.s_eff.get(el);
        let v: Vec<f64> = entry.x_indices().map(|i| rate[i]).collect();
        if v.iter().all(|&r| r == 0.0) {
            continue;
        }
        let xk = gather(entry, x);
        let d = entry.element.jacobian(&xk);
        let ne = entry.element.ne();
        let sigma = &a.sigma[entry.ie..entry.ie + ne];
        let dv: Vec<f64> = (0..ne)
            .map(|m| (0..v.len()).map(|c| d[(m, c)] * v[c]).sum())
            .collect();
        let sdv: Vec<f64> = (0..ne)
            .map(|m| (0..ne).map(|n| s[(m, n)] * dv[n]).sum())
            .collect();
        let h = entry.element.hessian_weighted(&xk, sigma);
        for (a_loc, xi) in entry.x_indices().enumerate() {
            let f: f64 = (0..v.len()).map(|b| h[(a_loc, b)] * v[b]).sum::<f64>()
                + (0..ne).map(|m| d[(m, a_loc)] * sdv[m]).sum::<f64>();
            qx[xi] += f;
        }
        for m in 0..ne {
            if let Some(kc) = su.constraint[entry.ie + m].get() {
                qg[kc] += dv[m];
            }
        }
    }
    let mut qr = vec![0.0; su.nf];
    for (i, q) in qx.iter().enumerate() {
        if let Some(u) = su.unknown[i].get() {
            qr[u] = *q;
        }
    }
    (qr, qg)
}

/// ‖v‖²_W of a reduced increment (the coordinate unknowns; translations over L²).
pub(super) fn norm2(su: &Setup, v: &[f64]) -> f64 {
    dot(su, v, v)
}

/// (u, v)_W of two reduced increments.
fn dot(su: &Setup, u: &[f64], v: &[f64]) -> f64 {
    let l2 = su.l_ref * su.l_ref;
    (0..su.red.nfr)
        .map(|m| {
            let w = if su.red.is_trans[m] { 1.0 / l2 } else { 1.0 };
            w * u[m] * v[m]
        })
        .sum()
}

/// The Newton matrix's solver, made on first use.
fn solver<'a>(
    kkt: &'a mut Option<KktSolver>,
    su: &Setup,
    a: &Assembled,
) -> Result<&'a mut KktSolver, String> {
    match kkt {
        Some(k) => Ok(k),
        None => Ok(kkt.insert(KktSolver::new(su, &a.tail)?)),
    }
}

/// The tangent at a converged state: δb = −K⁻¹ ∂(r, g)/∂t (reduced), with the inertia of K.
pub(super) struct Tangent {
    db: Vec<f64>,
    /// The load rate on the free coordinates (for the multipliers of reduced nodes).
    qr: Vec<f64>,
    pub(super) unstable: Option<usize>,
}

pub(super) fn tangent(
    model: &Model,
    su: &Setup,
    (x, t): (&[f64], f64),
    a: &Assembled,
    kkt: &mut Option<KktSolver>,
) -> Result<Tangent, String> {
    let (qr, qg) = load_rate(model, su, x, t, a);
    let mut db = reduced_rhs(su, x, &qr, &qg);
    let kkt = solver(kkt, su, a)?;
    if kkt.solve(&a.vals, &mut db).is_err() || db.iter().any(|v| !v.is_finite()) {
        return Err(SINGULAR.into());
    }
    let kept = su.red.n - su.red.nfr;
    let unstable = kkt.inertia().and_then(|n| n.checked_sub(kept));
    Ok(Tangent { db, qr, unstable })
}

/// A converged state of the path.
pub(super) struct State {
    pub(super) x: Vec<f64>,
    pub(super) mu: Vec<f64>,
    pub(super) t: f64,
    pub(super) a: Box<Assembled>,
    tangent: Tangent,
}

/// A converged step of the path.
pub(super) struct Step {
    pub(super) x: Vec<f64>,
    pub(super) mu: Vec<f64>,
    pub(super) t: f64,
    pub(super) a: Box<Assembled>,
    pub(super) iterations: usize,
    pub(super) residual: f64,
    /// The path's last step (at t = 1).
    pub(super) end: bool,
}

impl Step {
    /// The step's results ([`record`]), reached in `substeps` sub-steps.
    pub(super) fn record(&self, model: &Model, substeps: usize) -> StepResult {
        let (x, mu, a, t) = (&self.x, &self.mu, &self.a, self.t);
        record(model, x, mu, a, t, self.iterations, substeps, self.residual)
    }
}

/// A state inside a step, inserted into the path before the step's end: a located critical
/// point or an output level.
struct Inside {
    /// Distance from the step's start in the norm of the constraint.
    s: f64,
    level: Option<usize>,
    step: StepResult,
    unstable: Option<usize>,
    /// For a critical point: whether the load factor turns there, and the unstable directions
    /// before and after.
    critical: Option<(bool, [usize; 2])>,
}

/// One arc-length step of length `dl` from `s0` along `sign` × the tangent; the converged
/// state with its iterations, or why not.
pub(super) fn arc_step(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    s0: &State,
    (dl, sign, p2): (f64, f64, f64),
    kkt: &mut Option<KktSolver>,
) -> Result<Step, String> {
    let db0 = &s0.tangent.db;
    let dt0 = sign * dl / (norm2(su, db0) + p2).sqrt();
    if !dt0.is_finite() {
        return Err(SINGULAR.into());
    }
    // predictor along the tangent
    let (mut x, mut mu) = (s0.x.clone(), s0.mu.clone());
    let mut total: Vec<f64> = db0.iter().map(|v| dt0 * v).collect();
    let mut dt = dt0;
    let r_pred: Vec<f64> =
        s0.a.r
            .iter()
            .zip(&s0.tangent.qr)
            .map(|(r, q)| r + dt0 * q)
            .collect();
    let dz = expand(su, &s0.x, &s0.mu, &r_pred, &total);
    step_to(su, (&mut x, &mut mu), (&s0.x, &s0.mu), &dz, 1.0);
    let mut t = s0.t + dt0;
    apply_prescribed(model, su, &mut x, t);
    normalise_lambda(su, &mut x);
    let mut last_inc = f64::INFINITY;
    let mut r_start = 0.0;
    let mut k_ref = reference_stiffness(su, &s0.a);
    for it in 1..=opts.max_iterations + 1 {
        let mut a = assemble_values(model, su, &x, &mu, t, Part::Full, true, Vec::new());
        solve_single_multipliers(su, &x, &mut mu, &mut a);
        if it == 1 {
            k_ref = k_ref.max(reference_stiffness(su, &a));
        }
        match check(su, opts, &a, k_ref, last_inc, it - 1, &mut r_start) {
            Status::Converged(residual) => {
                return Ok(Step {
                    x,
                    mu,
                    t,
                    a: Box::new(a),
                    iterations: it - 1,
                    residual,
                    end: false,
                })
            }
            Status::Failed(reason) => return Err(reason),
            Status::Iterate => {}
        }
        let (qr, qg) = load_rate(model, su, &x, t, &a);
        let mut da = reduced_rhs(su, &x, &a.r, &a.g);
        let mut db = reduced_rhs(su, &x, &qr, &qg);
        if solver(kkt, su, &a)?
            .solve_all(&a.vals, &mut [&mut da, &mut db])
            .is_err()
            || da.iter().chain(&db).any(|v| !v.is_finite())
        {
            return Err(SINGULAR.into());
        }
        // δt from the constraint ‖total + δa + δt δb‖² + (dt + δt)² p² = dl²
        let ta: Vec<f64> = total.iter().zip(&da).map(|(u, v)| u + v).collect();
        let a1 = norm2(su, &db) + p2;
        let a2 = 2.0 * (dot(su, &ta, &db) + dt * p2);
        let a3 = norm2(su, &ta) + dt * dt * p2 - dl * dl;
        let disc = a2 * a2 - 4.0 * a1 * a3;
        if !(disc >= 0.0 && a1 > 0.0) {
            return Err("the arc-length constraint has no real root (the step is too long for the curvature of the path)".into());
        }
        let root = |sg: f64| (-a2 + sg * disc.sqrt()) / (2.0 * a1);
        // the root whose new increment makes the smaller angle with the last one
        let cosine = |d: f64| dot(su, &ta, &total) + d * dot(su, &db, &total) + (dt + d) * dt * p2;
        let (d1, d2) = (root(1.0), root(-1.0));
        let ddt = if cosine(d1) >= cosine(d2) { d1 } else { d2 };
        let dr: Vec<f64> = da.iter().zip(&db).map(|(u, v)| u + ddt * v).collect();
        let r_new: Vec<f64> = a.r.iter().zip(&qr).map(|(r, q)| r + ddt * q).collect();
        let dz = expand(su, &x, &mu, &r_new, &dr);
        let (x_old, mu_old) = (x.clone(), mu.clone());
        step_to(su, (&mut x, &mut mu), (&x_old, &mu_old), &dz, 1.0);
        t += ddt;
        apply_prescribed(model, su, &mut x, t);
        normalise_lambda(su, &mut x);
        dt += ddt;
        for (u, v) in total.iter_mut().zip(&dr) {
            *u += v;
        }
        last_inc = increment_size(model, su, &dz[..su.nf]).max(ddt.abs());
    }
    Err("no convergence".into())
}

/// Follow the path by arc length from the unloaded state to load factor 1: every converged
/// state is pushed onto `out` with its [`PathPoint`] onto `path`, the critical points passed
/// ([`critical_points`]: located inside their step where possible) onto `events`, also when
/// the path stops part-way.
pub(super) fn follow(
    model: &Model,
    opts: &StaticOptions,
    progress: impl FnMut(usize, usize),
    out: &mut Vec<StepResult>,
    path: &mut Vec<PathPoint>,
    events: &mut Vec<PathEvent>,
) -> Result<(), SolveError> {
    let mut located = Vec::new();
    let r = run(model, opts, progress, out, (path, &mut located));
    *events = critical_points(out, path, &located);
    r
}

/// [`follow`] without the critical points.
fn run(
    model: &Model,
    opts: &StaticOptions,
    mut progress: impl FnMut(usize, usize),
    out: &mut Vec<StepResult>,
    (path, located): (&mut Vec<PathPoint>, &mut Vec<Located>),
) -> Result<(), SolveError> {
    check_options(opts)?;
    let su = setup(model);
    if su.nf == 0 && su.nk == 0 {
        return Err(SolveError::NothingToSolve);
    }
    let steps = opts.steps.max(1);
    let max_steps = (STEPS_PER_LOAD_STEP * steps).min(super::MAX_STEPS);
    // the unloaded state
    let mut x = model.x0();
    let mut mu = vec![0.0; su.nk];
    let mut kkt = None;
    apply_prescribed(model, &su, &mut x, 0.0);
    normalise_lambda(&su, &mut x);
    let (iterations, residual, a) =
        match newton(model, &su, opts, &mut x, &mut mu, 0.0, &mut kkt, None) {
            Newton::Converged {
                iterations,
                residual,
                state,
            } => (iterations, residual, state),
            Newton::Failed { reason } => {
                return Err(SolveError::NoConvergence {
                    step: 0,
                    load_factor: 0.0,
                    last_converged: 0.0,
                    halvings: 0,
                    reason,
                })
            }
        };
    let mut st = record(model, &x, &mu, &a, 0.0, iterations, 1, residual);
    st.tangent_eigenvalues = tangent_eigenvalues(model, &su, &st, &a, opts.tangent_eigenvalues);
    push_finite(out, st, 0, None)?;
    let tangent0 = tangent(model, &su, (&x, 0.0), &a, &mut kkt)
        .map_err(|r| no_convergence(1, 0.0, 0.0, 0, r))?;
    // the rate of the prescribed coordinates, in the norm of the constraint
    let p2 = prescribed_rate2(&su);
    let dl0 = (norm2(&su, &tangent0.db) + p2).sqrt() / steps as f64;
    if !(dl0.is_finite() && dl0 > 0.0) {
        return Err(SolveError::NotForArcLength(
            "the load factor moves nothing (no load, no prescribed value): there is no path to follow".into(),
        ));
    }
    path.push(PathPoint {
        arc_length: 0.0,
        unstable_directions: tangent0.unstable,
        level: Some(0),
    });
    progress(0, steps);
    let mut cur = State {
        x,
        mu,
        t: 0.0,
        a,
        tangent: tangent0,
    };
    let (dl_min, dl_max) = (dl0 / 2f64.powi(opts.max_halvings as i32), MAX_GROWTH * dl0);
    // the load factor in the units of the coordinates: the length of the first tangent
    let t_scale = dl0 * steps as f64;
    let mut dl = dl0;
    let mut prev: Option<(Vec<f64>, f64)> = None; // the last increment (reduced) and its Δt
    let mut s_total = 0.0;
    let mut largest = 0.0f64;
    for step in 1..=max_steps {
        // the direction that continues the last increment
        let sign = match &prev {
            None => 1.0,
            Some((inc, dt)) => {
                let w = dot(&su, inc, &cur.tangent.db) + dt * p2;
                if w >= 0.0 {
                    1.0
                } else {
                    -1.0
                }
            }
        };
        let mut halvings = 0;
        let done = loop {
            let ds = sign * dl / (norm2(&su, &cur.tangent.db) + p2).sqrt();
            // the last step: load control to t = 1 exactly, from the tangent
            if cur.t < 1.0 && cur.t + ds >= 1.0 && ds > 0.0 {
                if let Some(end) = final_step(
                    model,
                    &su,
                    opts,
                    tangent_to_end(&su, &cur),
                    &cur.x,
                    &mut kkt,
                ) {
                    break end;
                }
            }
            let r = arc_step(model, &su, opts, &cur, (dl, sign, p2), &mut kkt).and_then(|st| {
                match inverted_element(model, &st.x, &cur.x) {
                    Some(name) => Err(format!("element `{name}` inverted")),
                    None => Ok(st),
                }
            });
            // a step that passes t = 1 on the way up ends the path there: load control to
            // t = 1 from the state between the two, or a shorter step
            let r = match r {
                Ok(st) if cur.t < 1.0 && st.t > 1.0 => {
                    let w = (1.0 - cur.t) / (st.t - cur.t);
                    let x: Vec<f64> = cur
                        .x
                        .iter()
                        .zip(&st.x)
                        .map(|(a, b)| a + w * (b - a))
                        .collect();
                    let mu: Vec<f64> = cur
                        .mu
                        .iter()
                        .zip(&st.mu)
                        .map(|(a, b)| a + w * (b - a))
                        .collect();
                    final_step(model, &su, opts, (x, mu), &cur.x, &mut kkt)
                        .ok_or_else(|| "the step passes the full load".to_string())
                }
                r => r,
            };
            match r {
                Ok(st) => break st,
                Err(reason) => {
                    halvings += 1;
                    dl *= 0.5;
                    if dl < dl_min {
                        return Err(no_convergence(
                            step,
                            cur.t,
                            cur.t,
                            halvings - 1,
                            format!("{reason}; at the shortest arc length"),
                        ));
                    }
                }
            }
        };
        let step_end = snap_to_level(model, &su, opts, done, (&cur, p2, steps), &mut kkt);
        let mut st = step_end.record(model, halvings + 1);
        let Step {
            x,
            mu,
            t,
            a,
            iterations,
            end,
            ..
        } = step_end;
        st.tangent_eigenvalues = tangent_eigenvalues(model, &su, &st, &a, opts.tangent_eigenvalues);
        let tangent = match tangent(model, &su, (&x, t), &a, &mut kkt) {
            Ok(tg) => tg,
            Err(r) => {
                push_finite(out, st, step, Some(cur.t))?;
                return Err(no_convergence(step + 1, t, t, 0, r));
            }
        };
        // the increment of this step (reduced, at the old state's basis: for the direction)
        let inc: Vec<f64> = reduced_increment(&su, &cur.x, &x);
        let dt = t - cur.t;
        let chord = (norm2(&su, &inc) + dt * dt * p2).sqrt();
        // the states inside the step, in path order: a critical point (the number of
        // unstable directions changes; the load factor turns there, a limit point, when the
        // next step goes back in t) and the output levels crossed
        let mut inside: Vec<Inside> = Vec::new();
        if let (Some(u0), Some(u1)) = (cur.tangent.unstable, tangent.unstable) {
            if u0 != u1 {
                let bracket = Bracket {
                    from: &cur,
                    to: &a,
                    sign,
                    p2,
                    chord,
                    unstable: [u0, u1],
                };
                if let Some(c) = locate(model, &su, opts, &bracket, &mut kkt) {
                    let mut cs = c.state.record(model, 1);
                    cs.tangent_eigenvalues = c.kappa;
                    let turns = (dot(&su, &inc, &tangent.db) + dt * p2) * sign < 0.0;
                    inside.push(Inside {
                        s: c.s,
                        level: level_of(c.state.t, steps),
                        step: cs,
                        unstable: c.unstable,
                        critical: Some((turns, [u0, u1])),
                    });
                }
            }
        }
        let crossed = level_states(
            model,
            &su,
            opts,
            &cur,
            (&x, &mu, t),
            (steps, p2, chord),
            &mut kkt,
        );
        for l in crossed {
            let mut ls = l.step;
            ls.tangent_eigenvalues =
                tangent_eigenvalues(model, &su, &ls, &l.a, opts.tangent_eigenvalues);
            let unstable = self::tangent(model, &su, (&ls.x, ls.load_factor), &l.a, &mut kkt)
                .ok()
                .and_then(|tg| tg.unstable);
            inside.push(Inside {
                s: l.s,
                level: Some(l.level),
                step: ls,
                unstable,
                critical: None,
            });
        }
        inside.sort_by(|p, q| p.s.total_cmp(&q.s));
        for p in inside {
            push_finite(out, p.step, step, Some(cur.t))?;
            path.push(PathPoint {
                arc_length: s_total + p.s,
                unstable_directions: p.unstable,
                level: p.level,
            });
            if let Some((limit, unstable)) = p.critical {
                located.push(Located {
                    step: out.len() - 1,
                    limit,
                    unstable,
                });
            }
        }
        push_finite(out, st, step, Some(cur.t))?;
        s_total += chord;
        path.push(PathPoint {
            arc_length: s_total,
            unstable_directions: tangent.unstable,
            level: level_of(t, steps),
        });
        largest = largest.max(t);
        progress(((t.clamp(0.0, 1.0)) * steps as f64).floor() as usize, steps);
        if end {
            return Ok(());
        }
        // the step length for the next step: shorter where Newton needs many iterations, where
        // the path turns or where the load factor moves fast, longer otherwise
        if halvings == 0 {
            let by_iterations = (TARGET_ITERATIONS / iterations.max(1) as f64).sqrt();
            let by_turn = match &prev {
                Some((inc0, dt0)) => {
                    let t2 = t_scale * t_scale;
                    let c = dot(&su, inc0, &inc) + t2 * dt0 * dt;
                    let n0 = (norm2(&su, inc0) + t2 * dt0 * dt0).sqrt();
                    let n1 = (norm2(&su, &inc) + t2 * dt * dt).sqrt();
                    let turn = (c / (n0 * n1)).clamp(-1.0, 1.0).acos();
                    TARGET_TURN / turn.max(f64::MIN_POSITIVE)
                }
                None => 1.0,
            };
            // and no longer than a step of the load factor of 1/steps at the current rate
            let by_load = 1.0 / (steps as f64 * dt.abs()).max(f64::MIN_POSITIVE);
            let f = by_iterations.min(by_turn).min(by_load).clamp(0.5, 2.0);
            dl = (dl * f).clamp(dl_min, dl_max);
        }
        prev = Some((inc, dt));
        cur = State {
            x,
            mu,
            t,
            a,
            tangent,
        };
    }
    Err(SolveError::PathTooLong {
        steps: max_steps,
        load_factor: cur.t,
        largest,
    })
}

/// The reduced increment from `x0` to `x1` (free translations and other plain unknowns as
/// differences; the rotation of a reduced node as Nᵀ(λ0) (λ1 − λ0)).
pub(super) fn reduced_increment(su: &Setup, x0: &[f64], x1: &[f64]) -> Vec<f64> {
    let red = &su.red;
    let mut v = vec![0.0; red.n];
    for (i, u) in su.unknown.iter().enumerate() {
        if let Some(m) = u.get().and_then(|u| red.map[u].get()) {
            v[m] = x1[i] - x0[i];
        }
    }
    for &(r, d0, _) in &red.nodes {
        let nb = super::rot_basis(&x0[r..r + 4]);
        for j in 0..3 {
            v[d0 + j] = (0..4).map(|i| nb[i][j] * (x1[r + i] - x0[r + i])).sum();
        }
    }
    v
}

/// The tangent predictor from `cur` to t = 1: (x, μ).
fn tangent_to_end(su: &Setup, cur: &State) -> (Vec<f64>, Vec<f64>) {
    let ds = 1.0 - cur.t;
    let (mut x, mut mu) = (cur.x.clone(), cur.mu.clone());
    let db: Vec<f64> = cur.tangent.db.iter().map(|v| ds * v).collect();
    let r: Vec<f64> = cur
        .a
        .r
        .iter()
        .zip(&cur.tangent.qr)
        .map(|(r, q)| r + ds * q)
        .collect();
    let dz = expand(su, &cur.x, &cur.mu, &r, &db);
    step_to(su, (&mut x, &mut mu), (&cur.x, &cur.mu), &dz, 1.0);
    (x, mu)
}

/// The last step: Newton at t = 1 from the predictor (x, μ) (`from`: the coordinates of the
/// last converged state, for the inversion test); `None` when it fails (the arc-length steps
/// go on instead).
fn final_step(
    model: &Model,
    su: &Setup,
    opts: &StaticOptions,
    (mut x, mut mu): (Vec<f64>, Vec<f64>),
    from: &[f64],
    kkt: &mut Option<KktSolver>,
) -> Option<Step> {
    apply_prescribed(model, su, &mut x, 1.0);
    match newton(model, su, opts, &mut x, &mut mu, 1.0, kkt, None) {
        Newton::Converged {
            iterations,
            residual,
            state,
        } if inverted_element(model, &x, from).is_none() => Some(Step {
            x,
            mu,
            t: 1.0,
            a: state,
            iterations,
            residual,
            end: true,
        }),
        _ => None,
    }
}

fn no_convergence(
    step: usize,
    load_factor: f64,
    last_converged: f64,
    halvings: usize,
    reason: String,
) -> SolveError {
    SolveError::NoConvergence {
        step,
        load_factor,
        last_converged,
        halvings,
        reason,
    }
}

/// Push a step whose numbers are all finite, else the error (`last`: the load factor of the
/// last finite state).
fn push_finite(
    out: &mut Vec<StepResult>,
    st: StepResult,
    step: usize,
    last: Option<f64>,
) -> Result<(), SolveError> {
    let bad = non_finite_parts(&st);
    if !bad.is_empty() {
        return Err(SolveError::NonFinite {
            step,
            load_factor: st.load_factor,
            what: bad.join(", "),
            last_good: last,
        });
    }
    out.push(st);
    Ok(())
}
