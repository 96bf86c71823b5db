//! The generalised-α integrator of [`super::simulate`]: set-up, consistent initial state,
//! Newton per step, step control and the energy bookkeeping (module docs of `simulation`).

use super::{
    Energies, Excitation, Frame, Progress, SimError, SimFailure, SimOptions, SimStats, Simulation,
    Start, StartVelocity, Stopped, TimeFunction,
};
use crate::assembly::loads::{element_nodes, field_loads_with};
use crate::assembly::mass::{element_mass, for_each_node_entry, inertia_forces, mass_times};
use crate::assembly::{map_elements, split_at_starts};
use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{Model, Target};
use crate::statics::{
    assemble_part, assemble_values, inverted_element, scale_elements, setup, solve, Assembled,
    KktSolver, Part, Setup, StaticOptions,
};

/// Modified Newton: a new iteration matrix when the corrections shrink by less than this
/// factor per iteration (a step that fails with a reused matrix is repeated with full Newton).
const SLOW: f64 = 0.5;

/// Modified Newton: a new iteration matrix also when the corrections, shrinking at the rate of
/// the last two, would need more than this many further iterations.
const SLOW_ITERATIONS: f64 = 4.0;

/// The generalised-α parameters of ρ∞ (Arnold & Brüls 2007; Chung & Hulbert 1993).
#[derive(Clone, Copy, Debug)]
struct Params {
    am: f64,
    af: f64,
    beta: f64,
    gamma: f64,
}

impl Params {
    fn new(rho: f64) -> Self {
        let am = (2.0 * rho - 1.0) / (rho + 1.0);
        let af = rho / (rho + 1.0);
        let gamma = 0.5 + af - am;
        let beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
        Self {
            am,
            af,
            beta,
            gamma,
        }
    }
    /// β′ and γ′ of the iteration matrix for the step h.
    fn primes(&self, h: f64) -> (f64, f64) {
        (
            (1.0 - self.am) / (self.beta * h * h * (1.0 - self.af)),
            self.gamma / (self.beta * h),
        )
    }
}

/// A prescribed coordinate: x = x⁰ + value φ(t) (positions) or sin(½ value φ(t)) (Euler
/// parameters, statics' convention).
struct PrescribedCoord {
    xi: usize,
    value: f64,
    f: usize,
    lambda: bool,
}

/// An input deformation: e_i = value φ(t), constraint row kc; a periodic angle (a hinge's
/// rotation, measured in (−π, π]) is met modulo 2π, so a driven hinge can turn any number of
/// times.
struct InputDef {
    kc: usize,
    value: f64,
    f: usize,
    periodic: bool,
}

/// Everything evaluated at one state.
struct Eval {
    asm: Assembled,
    /// Total generalised force balance on all of x: M ẍ + h + Dᵀσ + C ẋ − f.
    balance: Vec<f64>,
    /// External loads f on all of x.
    ext: Vec<f64>,
    /// C ẋ on all of x.
    damp: Vec<f64>,
    /// Constraint violations (inputs at their targets).
    g: Vec<f64>,
    /// K_m values (Rayleigh β), same order as `asm.vals`.
    km: Option<Vec<f64>>,
}

/// The state of the integrator.
#[derive(Clone)]
struct State {
    t: f64,
    x: Vec<f64>,
    v: Vec<f64>,
    /// ẍ
    acc: Vec<f64>,
    /// The auxiliary acceleration a.
    aux: Vec<f64>,
    mu: Vec<f64>,
}

struct Engine<'a> {
    model: &'a Model,
    su: Setup,
    exc: Excitation,
    opts: SimOptions,
    p: Params,
    /// Unknown index → x index.
    free: Vec<usize>,
    presc: Vec<PrescribedCoord>,
    inputs: Vec<InputDef>,
    /// Nodal loads with moments: (λ0 index, moment, load index).
    moments: Vec<(usize, [f64; 3], usize)>,
    /// Absolute tolerance [x units].
    atol: f64,
    /// Model size [m] (the round-off floor of the weights).
    l_ref: f64,
    /// Number of triplets of the assembly.
    n_pat: usize,
    /// Whether each assembly entry lies in the free block (scaled by the coefficient of K).
    in_free: Vec<bool>,
    /// The value slots of the mass entries.
    mass: MassSlots,
    /// First slot of the moment load stiffness (16 per moment; `None` off the free block).
    moment_slot: Vec<[[Option<usize>; 4]; 4]>,
    /// First slot of the diagonal entries (one per free coordinate).
    diag_start: usize,
    n_vals: usize,
    /// (row, column) of every matrix entry, in the order of the values.
    entries: Vec<(usize, usize)>,
    solver: KktSolver,
    /// The step size of the factorised iteration matrix (`None`: no valid factorisation), kept
    /// over steps (modified Newton) while the iterations converge fast.
    jac_h: Option<f64>,
    /// The nodes whose increments co-rotate the carried matrix ([`corot`]).
    corot: Vec<corot::CoRot>,
    /// Their unit Euler parameters at the state of the factorised matrix.
    jac_lambda: Vec<[f64; 4]>,
    /// Their rotations since then (a buffer reused over the iterations).
    turns: Vec<corot::Turn>,
    /// Whether the last failed step used a reused matrix in some iteration (it is then tried
    /// again with full Newton before the step is halved).
    failed_stale: bool,
    /// Full Newton (a fresh matrix in every iteration) for the next step.
    full_newton: bool,
    /// Whether the matrix carried over from an earlier step had to be rebuilt in the last
    /// step: the next step then rebuilds it after the first correction (which the carried
    /// matrix still makes well, from the predictor) instead of waiting for slow convergence.
    carry_fails: bool,
    /// Steps since a carried matrix was last given the chance to serve a whole step.
    since_probe: usize,
    /// Steps left in full Newton after a step failed with reused matrices (far from the
    /// solution, at large steps or in fast motion, reused matrices converge too slowly, and a
    /// failed step costs its iterations and its repetition); the step after them tries reuse
    /// again.
    full_steps: usize,
    /// ẍ at the start of the last accepted step, with that step's size (the predictor).
    acc_before: Option<(f64, Vec<f64>)>,
    /// The same one step earlier.
    acc_before2: Option<(f64, Vec<f64>)>,
    /// The iteration matrix values of the last rebuild (a buffer reused over the steps).
    vals_buf: Vec<f64>,
    /// The assembly's matrix entries of the last rebuild, handed back to the next one.
    asm_spare: Vec<f64>,
    /// The nodes of every element, for the loads of gravity at each state.
    element_nodes: Vec<Vec<crate::elements::NodeId>>,
    /// Whether any damping is proportional to the material stiffness.
    stiffness_damping: bool,
}

/// No value slot: a mass entry off the free block.
const NO_SLOT: u32 = u32::MAX;

/// Where the mass entries go among the iteration matrix values (the order of
/// `for_each_entry`): each element's entries on the free block in consecutive slots, so that
/// every element can add its own in parallel, then the node masses.
struct MassSlots {
    /// Per local entry of an element's mass matrix (row-major on its `xmap`): the slot relative
    /// to the element's first, or [`NO_SLOT`]; element el's are
    /// `local[entry_start[el]..entry_start[el + 1]]` (empty for an element without mass).
    local: Vec<u32>,
    entry_start: Vec<usize>,
    /// The slots of element el are `first + piece_start[el]..first + piece_start[el + 1]`.
    piece_start: Vec<usize>,
    first: usize,
    /// The slot of every node mass entry (order of `for_each_node_entry`), `None` off the free
    /// block.
    node: Vec<Option<usize>>,
}

/// The Newton tolerance as a fraction of the error weight atol + rtol |x|: the last correction
/// of a converged step is below it. Small against the local error the step control admits (one
/// weight) and the accuracy a fixed step reaches; 1e-2 rather than 1e-3 changed the tip of the
/// flexible pendulum by under 1 % of its step-size error at h = 0.5 … 4 ms and its energy
/// balance not at all, and saved 7–9 % of the iterations and 25–73 % of the matrix updates
/// at h = 1 ms (bench/README.md §4).
const NEWTON_TOL: f64 = 1e-2;

/// The step after a step `h_try` that failed for `reason` (Newton did not converge, an element
/// turned inside out): half of it; `Err` with the message of the run's stop when that is below
/// the smallest step `dt_min`.
fn halved(h_try: f64, dt_min: f64, reason: &str) -> Result<f64, String> {
    let h = 0.5 * h_try;
    if h < dt_min {
        return Err(format!(
            "{reason} even with the smallest step {dt_min:.3e} s"
        ));
    }
    Ok(h)
}

/// Every this many steps a carried matrix that failed lately is tried again for a whole step.
const PROBE_STEPS: usize = 16;

/// The matrix coefficients: K and the moment stiffness, M, K_m, and the unit diagonal.
#[derive(Clone, Copy)]
struct Coefs {
    k: f64,
    m: f64,
    km: f64,
    diag: f64,
}

/// φ, φ', φ'' of a prescribed motion at t: at the start of the run the rates of the first
/// interval (a ramp from t = 0 starts at its speed), elsewhere those of the interval that ends
/// at t (each step ends on the kinks).
fn history(f: &TimeFunction, t: f64) -> [f64; 3] {
    if t <= 0.0 {
        f.eval_right(t)
    } else {
        f.eval(t)
    }
}

fn finite(v: &[f64]) -> bool {
    v.iter().all(|a| a.is_finite())
}

pub(super) fn run(
    model: &Model,
    exc: &Excitation,
    opts: &SimOptions,
    progress: &mut dyn FnMut(Progress),
) -> Result<Simulation, SimFailure> {
    let mut eng = Engine::new(model, exc, opts)?;
    let s0 = eng.initial_state()?;
    eng.integrate(s0, progress)
}

mod corot;
mod forces;
mod initial;
mod setup;

impl<'a> Engine<'a> {
    /// The times to land on: outputs, kinks, the end.
    fn events(&self) -> (Vec<f64>, Vec<f64>) {
        let o = &self.opts;
        let n_out = (o.t_end / o.output_step - 1e-9).floor() as usize;
        let mut outputs: Vec<f64> = (1..=n_out).map(|k| k as f64 * o.output_step).collect();
        outputs.retain(|&t| t < o.t_end * (1.0 - 1e-12));
        outputs.push(o.t_end);
        let mut all = outputs.clone();
        for f in self
            .exc
            .loads
            .iter()
            .chain(&self.exc.prescribed)
            .chain(std::iter::once(&self.exc.gravity))
        {
            all.extend(f.kinks(0.0, o.t_end));
        }
        all.sort_by(f64::total_cmp);
        all.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * o.t_end);
        (all, outputs)
    }

    /// Weights of the error norm.
    fn weight(&self, a: f64, b: f64) -> f64 {
        self.atol + self.opts.rtol * a.abs().max(b.abs())
    }

    /// The Newton tolerance of a coordinate: [`NEWTON_TOL`] of its error weight, but not below
    /// the round-off of the coordinate (100 ε (|x| + model size)).
    fn newton_tol(&self, a: f64, b: f64) -> f64 {
        let m = a.abs().max(b.abs());
        (NEWTON_TOL * self.weight(a, b)).max(100.0 * f64::EPSILON * (m + self.l_ref))
    }

    /// One step from `s` to s.t + h; `Err(reason)` when Newton fails.
    fn step(&mut self, s: &State, h: f64, stats: &mut SimStats) -> Result<(State, Eval), String> {
        let (nf, nk) = (self.su.nf, self.su.nk);
        let p = self.p;
        let t1 = s.t + h;
        let (bp, gp) = p.primes(h);
        let mut n1 = s.clone();
        n1.t = t1;
        let mut aux_pred = vec![0.0; self.model.nx];
        // ẍ of the two steps before, when they had this step size
        fn same_h(a: &Option<(f64, Vec<f64>)>, h: f64) -> Option<&[f64]> {
            a.as_ref()
                .filter(|(hp, _)| *hp == h)
                .map(|(_, a)| a.as_slice())
        }
        let earlier = same_h(&self.acc_before, h).zip(same_h(&self.acc_before2, h));
        for &i in &self.free {
            // predictor of ẍ_{n+1}, per coordinate the one that was closer in the last step:
            // ẍ_n (a constant acceleration, for a smooth motion) or ẍ_{n−1} (the least damped
            // high modes alternate from step to step, amplification −ρ∞ at h ω → ∞); a_{n+1}
            // from it
            let pa = match earlier {
                Some((a1, a2)) if (s.acc[i] - a2[i]).abs() < (s.acc[i] - a1[i]).abs() => a1[i],
                _ => s.acc[i],
            };
            let ap = (p.af * s.acc[i] - p.am * s.aux[i]) / (1.0 - p.am);
            aux_pred[i] = ap;
            let a1 = ap + (1.0 - p.af) / (1.0 - p.am) * pa;
            n1.x[i] = s.x[i] + h * s.v[i] + h * h * ((0.5 - p.beta) * s.aux[i] + p.beta * a1);
            n1.v[i] = s.v[i] + h * ((1.0 - p.gamma) * s.aux[i] + p.gamma * a1);
            n1.acc[i] = pa;
        }
        {
            let (x, v, a) = (&mut n1.x, &mut n1.v, &mut n1.acc);
            self.apply_prescribed(t1, x, v, a);
        }
        let coefs = Coefs {
            k: 1.0 / bp,
            m: 1.0 + self.opts.rayleigh[0] * gp / bp,
            km: if self.stiffness_damping() {
                gp / bp
            } else {
                0.0
            },
            diag: 0.0,
        };
        // modified Newton: the factorised matrix of an earlier iteration or step is reused
        // while the corrections shrink at least twofold per iteration; else it is rebuilt
        let mut last_inc = f64::INFINITY;
        let mut prev_inc = f64::INFINITY;
        // the coordinate with the largest correction (named when Newton fails)
        let mut worst = usize::MAX;
        let mut stale = false;
        let full = std::mem::take(&mut self.full_newton) || self.full_steps > 0;
        self.full_steps = self.full_steps.saturating_sub(1);
        // a carried matrix that failed lately is rebuilt after the first correction, except
        // in a probe step every PROBE_STEPS
        self.since_probe += 1;
        let early = self.carry_fails && self.since_probe < PROBE_STEPS;
        if !early {
            self.since_probe = 0;
        }
        // whether this step started on the matrix of an earlier step, and whether that one
        // was rebuilt
        let mut carried = false;
        let mut carry_failed = false;
        // whether the last two corrections came from the same matrix (their ratio is then the
        // contraction rate of the iteration)
        let mut same_matrix = false;
        for it in 0..=self.opts.max_iterations {
            // slow: the corrections of one matrix shrank less than twofold, or at their rate
            // would need more than SLOW_ITERATIONS further iterations
            let slow = same_matrix
                && (last_inc > SLOW * prev_inc
                    || last_inc.ln() > SLOW_ITERATIONS * (prev_inc / last_inc).ln());
            let rebuild = full
                || self.jac_h != Some(h)
                || slow
                || (it == 1 && carried && early)
                || !self.solver.reusable();
            if it == 0 {
                carried = !rebuild;
            } else if carried && rebuild {
                carry_failed = true;
            }
            stale |= !rebuild;
            // converged by the last correction: this evaluation gives the forces at the
            // solution and builds no matrix
            let converged = it > 0 && last_inc <= 1.0;
            let (part, spare) = if rebuild && !converged {
                (Part::Full, std::mem::take(&mut self.asm_spare))
            } else {
                (Part::Residual, Vec::new())
            };
            let mut ev = self.evaluate_part(&n1.x, &n1.v, &n1.acc, &n1.mu, t1, part, spare);
            if !finite(&ev.balance) || !finite(&ev.g) {
                self.jac_h = None;
                return Err("the forces became non-finite during the Newton iteration".into());
            }
            if converged {
                self.carry_fails = carry_failed;
                for &i in &self.free {
                    n1.aux[i] = aux_pred[i] + (1.0 - p.af) / (1.0 - p.am) * n1.acc[i];
                }
                stats.newton_iterations += it;
                return Ok((n1, ev));
            }
            if it == self.opts.max_iterations {
                break;
            }
            let mut rhs = vec![0.0; nf + nk];
            for u in 0..nf {
                rhs[u] = -ev.balance[self.free[u]] / bp;
            }
            for k in 0..nk {
                rhs[nf + k] = -ev.g[k];
            }
            let solved = if !rebuild {
                self.solve_carried(&n1.x, &mut rhs)
            } else {
                let mut vals = std::mem::take(&mut self.vals_buf);
                self.values_into(&ev, &n1.x, t1, coefs, &mut vals);
                self.asm_spare = std::mem::take(&mut ev.asm.vals);
                stats.matrix_updates += 1;
                let ok = self.solver.solve(&vals, &mut rhs).is_ok();
                self.vals_buf = vals;
                self.jac_h = ok.then_some(h);
                self.corot_built_at(&n1.x);
                ok
            };
            if !solved || !finite(&rhs) {
                self.jac_h = None;
                return Err("the iteration matrix is singular".into());
            }
            let mut inc: f64 = 0.0;
            for u in 0..nf {
                let i = self.free[u];
                let d = rhs[u];
                let r = d.abs() / self.newton_tol(n1.x[i], s.x[i]);
                if r > inc || inc.is_nan() {
                    inc = r;
                    worst = i;
                }
                n1.x[i] += d;
                n1.v[i] += gp * d;
                n1.acc[i] += bp * d;
            }
            for k in 0..nk {
                n1.mu[k] += bp * rhs[nf + k];
            }
            same_matrix = it > 0 && !rebuild;
            prev_inc = if it == 0 { f64::INFINITY } else { last_inc };
            last_inc = inc;
        }
        self.jac_h = None;
        self.failed_stale = stale;
        if stale {
            // reused matrices failed: full Newton for the retry and PROBE_STEPS - 1 steps
            // after it
            self.full_steps = PROBE_STEPS;
        }
        stats.newton_iterations += self.opts.max_iterations;
        let place = match self.model.coordinate_owner(worst) {
            Some((node, label)) => {
                format!(
                    ", largest at node `{}` coordinate {label}",
                    self.model.nodes[node].name
                )
            }
            None => String::new(),
        };
        Err(format!(
            "Newton's method did not converge in {} iterations (the last correction is {:.3e} times its tolerance{place})",
            self.opts.max_iterations, last_inc
        ))
    }

    /// Powers at a converged state: external, prescribed motions, dissipation.
    fn powers(&self, s: &State, ev: &Eval) -> [f64; 3] {
        let nx = self.model.nx;
        let p_ext: f64 = (0..nx).map(|i| ev.ext[i] * s.v[i]).sum();
        let mut p_presc: f64 = (0..nx)
            .filter(|&i| self.su.unknown[i].get().is_none())
            .map(|i| ev.balance[i] * s.v[i])
            .sum();
        for (kc, tv) in self.input_targets(s.t) {
            // σ of the input is its multiplier
            p_presc -= s.mu[kc] * tv[1];
        }
        let p_diss: f64 = (0..nx).map(|i| ev.damp[i] * s.v[i]).sum();
        [p_ext, p_presc, p_diss]
    }

    fn frame(&self, s: &State, ev: &Eval, energy: Energies) -> Frame {
        let reactions = (0..self.model.nx)
            .map(|i| {
                if self.su.unknown[i].get().is_none() {
                    ev.balance[i]
                } else {
                    0.0
                }
            })
            .collect();
        Frame {
            t: s.t,
            x: s.x.clone(),
            v: s.v.clone(),
            a: s.acc.clone(),
            e: ev.asm.e.clone(),
            sigma: ev.asm.sigma.clone(),
            reactions,
            multipliers: s.mu.clone(),
            energy,
        }
    }

    fn kinetic(&self, s: &State) -> f64 {
        let mv = mass_times(self.model, &s.x, &[&s.v]);
        0.5 * mv[0].iter().zip(&s.v).map(|(a, b)| a * b).sum::<f64>()
    }

    fn integrate(
        &mut self,
        s0: State,
        progress: &mut dyn FnMut(Progress),
    ) -> Result<Simulation, SimFailure> {
        let o = self.opts.clone();
        let (events, outputs) = self.events();
        let mut stats = SimStats {
            min_step: f64::INFINITY,
            ..Default::default()
        };
        let ev0 = self.evaluate(&s0.x, &s0.v, &s0.acc, &s0.mu, 0.0);
        let e0 = self.kinetic(&s0) + ev0.asm.energy;
        let mut work = [0.0; 3];
        let mut power = self.powers(&s0, &ev0);
        let energy_at = |kin: f64, strain: f64, work: &[f64; 3]| Energies {
            kinetic: kin,
            strain,
            external_work: work[0],
            prescribed_work: work[1],
            dissipated: work[2],
            balance_error: kin + strain - e0 - work[0] - work[1] + work[2],
        };
        let mut frames = vec![self.frame(
            &s0,
            &ev0,
            energy_at(self.kinetic(&s0), ev0.asm.energy, &work),
        )];
        let mut s = s0;
        let mut h = o.dt;
        let mut next_event = 0;
        let mut next_output = 0;
        let mut attempts = 0usize;
        let tol_t = 1e-12 * o.t_end;
        let roles = self.su.roles.clone();
        let stop = |frames: Vec<Frame>, stats: SimStats, t: f64, reason: String, hint: &str| {
            SimFailure::Stopped(Stopped {
                t,
                reason,
                hint: hint.to_string(),
                partial: Box::new(Simulation {
                    roles: roles.clone(),
                    frames,
                    stats,
                }),
            })
        };
        while next_event < events.len() {
            let target = events[next_event];
            let remaining = target - s.t;
            let mut h_try = h.min(o.dt_max);
            if remaining <= h_try * (1.0 + 1e-9) {
                h_try = remaining;
            } else if remaining < 2.0 * h_try {
                h_try = 0.5 * remaining;
            }
            attempts += 1;
            if attempts > o.max_steps {
                return Err(stop(
                    frames,
                    stats,
                    s.t,
                    format!("the largest number of steps ({}) is reached", o.max_steps),
                    "allow more steps, loosen the tolerances or shorten the run",
                ));
            }
            match self.step(&s, h_try, &mut stats) {
                Err(_) if self.failed_stale => {
                    // the same step again with full Newton
                    self.failed_stale = false;
                    self.full_newton = true;
                }
                Err(reason) => {
                    stats.newton_failures += 1;
                    h = match halved(h_try, o.dt_min, &reason) {
                        Ok(h) => h,
                        Err(why) => {
                            let hint = "reduce the first step or the tolerances, check the model for a coordinate without mass and stiffness or an element driven through itself, or add numerical damping (rho_inf < 1)";
                            return Err(stop(frames, stats, s.t, why, hint));
                        }
                    };
                }
                Ok((n1, ev)) => {
                    // local error estimate
                    let c = h_try * h_try * (self.p.beta - 1.0 / 6.0).abs();
                    let mut sum = 0.0;
                    for &i in &self.free {
                        let e = c * (n1.acc[i] - s.acc[i])
                            / self.weight(n1.x[i] - s.x[i] + s.x[i], s.x[i]);
                        sum += e * e;
                    }
                    let err = if self.free.is_empty() {
                        0.0
                    } else {
                        (sum / self.free.len() as f64).sqrt()
                    };
                    if o.adaptive && err > 1.0 && h_try > o.dt_min * 2.0 {
                        stats.rejected += 1;
                        h = (h_try * (0.9 * err.powf(-1.0 / 3.0)).max(0.2)).max(o.dt_min);
                        continue;
                    }
                    if let Some(name) = inverted_element(self.model, &n1.x, &s.x) {
                        // often a step far longer than a short element can follow: a sudden force
                        // on a node of little mass accelerates it so that the predictor (and the
                        // solution Newton finds from it) lies beyond the element's other end.
                        // Halved as a failed step; the run stops only below the smallest step
                        let reason = format!("element `{name}` turned inside out (zero length or reversed chord) in the step to t = {:.6e} s", n1.t);
                        stats.rejected += 1;
                        h = match halved(h_try, o.dt_min, &reason) {
                            Ok(h) => h,
                            Err(why) => {
                                let hint = "check the loads and the stiffness of that element: it is driven through itself";
                                return Err(stop(frames, stats, s.t, why, hint));
                            }
                        };
                        continue;
                    }
                    if !finite(&n1.x) || !finite(&n1.v) || !finite(&n1.mu) {
                        return Err(stop(
                            frames,
                            stats,
                            s.t,
                            format!(
                                "the state became non-finite in the step to t = {:.6e} s",
                                n1.t
                            ),
                            "check the loads and the units of the model",
                        ));
                    }
                    // accepted
                    stats.steps += 1;
                    stats.min_step = stats.min_step.min(h_try);
                    stats.max_step = stats.max_step.max(h_try);
                    let gmax = ev.g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                    stats.max_constraint_residual = stats.max_constraint_residual.max(gmax);
                    let p1 = self.powers(&n1, &ev);
                    for k in 0..3 {
                        work[k] += 0.5 * h_try * (power[k] + p1[k]);
                    }
                    power = p1;
                    if o.adaptive {
                        let f = if err > 0.0 {
                            (0.9 * err.powf(-1.0 / 3.0)).clamp(0.2, 2.0)
                        } else {
                            2.0
                        };
                        // keep the step (and its factorised matrix) unless it may grow by 25 %
                        let f = if (1.0..1.25).contains(&f) { 1.0 } else { f };
                        // a step shortened to land on an event does not limit the next one
                        let base = if h_try < h { h } else { h_try };
                        h = if f < 1.0 { h_try * f } else { base * f }.clamp(o.dt_min, o.dt_max);
                    } else {
                        // fixed steps: back to the step size after halvings
                        h = (2.0 * h.max(h_try)).min(o.dt);
                    }
                    self.acc_before2 = self.acc_before.take();
                    self.acc_before = Some((h_try, std::mem::take(&mut s.acc)));
                    s = n1;
                    if (s.t - target).abs() <= tol_t {
                        s.t = target;
                        next_event += 1;
                        if next_output < outputs.len()
                            && (outputs[next_output] - target).abs() <= tol_t
                        {
                            next_output += 1;
                            let e = energy_at(self.kinetic(&s), ev.asm.energy, &work);
                            stats.max_energy_error =
                                stats.max_energy_error.max(e.balance_error.abs());
                            frames.push(self.frame(&s, &ev, e));
                        }
                    }
                    progress(Progress {
                        t: s.t,
                        t_end: o.t_end,
                        steps: stats.steps,
                    });
                }
            }
        }
        if stats.steps == 0 {
            stats.min_step = 0.0;
        }
        Ok(Simulation {
            roles,
            frames,
            stats,
        })
    }
}
