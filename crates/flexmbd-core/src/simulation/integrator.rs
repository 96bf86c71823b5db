//! The generalised-α integrator of [`super::simulate`]: set-up, consistent initial state,
//! Newton per step, step control and the energy bookkeeping (module docs of `simulation`).

use super::{
    Energies, Excitation, Frame, Progress, SimError, SimFailure, SimOptions, SimStats, Simulation,
    Start, Stopped, TimeFunction,
};
use crate::assembly::loads::field_loads_at;
use crate::assembly::mass::{for_each_entry, inertia_forces, mass_times};
use crate::elements::ElementKind;
use crate::math::lambda_bar;
use crate::model::{Model, Target};
use crate::statics::{
    assemble, assemble_part, assemble_values, inverted_element, setup, solve, Assembled, KktSolver,
    Part, Setup, StaticOptions,
};

/// Modified Newton: a new iteration matrix when the corrections shrink by less than this
/// factor per iteration (a step that fails with a reused matrix is repeated with full Newton).
const SLOW: f64 = 0.5;

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
    /// Value slot of every mass entry (order of `for_each_entry`), `None` off the free block.
    mass_slot: Vec<Option<usize>>,
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
    /// Whether the last failed step used a reused matrix in some iteration (it is then tried
    /// again with full Newton before the step is halved).
    failed_stale: bool,
    /// Full Newton (a fresh matrix in every iteration) for the next step.
    full_newton: bool,
}

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

fn check_options(model: &Model, exc: &Excitation, o: &SimOptions) -> Result<(), SimError> {
    let bad = |m: String| Err(SimError::Invalid(m));
    if !(o.t_end.is_finite() && o.t_end > 0.0) {
        return bad(format!(
            "the end time must be a finite number > 0 (got {})",
            o.t_end
        ));
    }
    if !(o.dt.is_finite() && o.dt > 0.0) {
        return bad(format!(
            "the step size must be a finite number > 0 (got {})",
            o.dt
        ));
    }
    if !(o.dt_min > 0.0 && o.dt_min <= o.dt && o.dt_max >= o.dt) {
        return bad(format!(
            "the step limits must satisfy 0 < smallest step {} <= step {} <= largest step {}",
            o.dt_min, o.dt, o.dt_max
        ));
    }
    if !(0.0..=1.0).contains(&o.rho_inf) {
        return bad(format!(
            "the spectral radius rho_inf must lie in [0, 1] (got {})",
            o.rho_inf
        ));
    }
    if !(o.atol > 0.0 && o.rtol >= 0.0 && o.atol.is_finite() && o.rtol.is_finite()) {
        return bad(format!(
            "the tolerances must be finite with abs > 0 and rel >= 0 (got {} and {})",
            o.atol, o.rtol
        ));
    }
    if !(o.output_step.is_finite() && o.output_step > 0.0) {
        return bad(format!(
            "the output interval must be > 0 (got {})",
            o.output_step
        ));
    }
    if o.t_end / o.output_step > 1e7 {
        return bad(format!(
            "{:.0} output times requested (end time / output interval); at most 10^7",
            o.t_end / o.output_step
        ));
    }
    if !o.rayleigh.iter().all(|v| v.is_finite() && *v >= 0.0) {
        return bad("the Rayleigh damping coefficients must be finite and >= 0".into());
    }
    if o.max_iterations == 0 || o.static_steps == 0 {
        return bad("the Newton iterations and static steps must be at least 1".into());
    }
    if exc.loads.len() > model.loads.nodal.len() {
        return bad(format!(
            "{} load histories for {} nodal loads",
            exc.loads.len(),
            model.loads.nodal.len()
        ));
    }
    if exc.prescribed.len() > model.loads.prescribed.len() {
        return bad(format!(
            "{} input histories for {} prescribed inputs",
            exc.prescribed.len(),
            model.loads.prescribed.len()
        ));
    }
    let names = model.node_names();
    for (k, f) in exc.loads.iter().enumerate() {
        f.validate().map_err(|e| {
            SimError::Invalid(format!(
                "history of the load at node `{}`: {e}",
                names[model.loads.nodal[k].node]
            ))
        })?;
    }
    for (k, f) in exc.prescribed.iter().enumerate() {
        f.validate().map_err(|e| {
            SimError::Invalid(format!("history of prescribed input {}: {e}", k + 1))
        })?;
        if f.is_discontinuous() {
            return bad(format!(
                "prescribed input {} jumps (a step history): a prescribed motion must be continuous; use a ramp or a table",
                k + 1
            ));
        }
    }
    exc.gravity
        .validate()
        .map_err(|e| SimError::Invalid(format!("history of gravity: {e}")))?;
    for v in &exc.velocities {
        if v.node >= model.nodes.len() || !finite(&v.velocity) || !finite(&v.angular) {
            return bad(
                "an initial velocity names an unknown node or holds a non-finite value".into(),
            );
        }
        if model.nodes[v.node].ix_rot.is_none() && v.angular != [0.0; 3] {
            return bad(format!(
                "initial angular velocity at node `{}`, which has no rotation",
                names[v.node]
            ));
        }
    }
    if model.loads.spin.is_some() {
        return Err(SimError::Unsupported(
            "a steady spin (co-rotating frame) cannot be simulated: model the rotation itself, e.g. a hinge whose angle is prescribed with a speed ramp".into(),
        ));
    }
    Ok(())
}

impl<'a> Engine<'a> {
    fn new(model: &'a Model, exc: &Excitation, opts: &SimOptions) -> Result<Self, SimError> {
        check_options(model, exc, opts)?;
        let mut exc = exc.clone();
        exc.loads
            .resize(model.loads.nodal.len(), TimeFunction::Constant);
        exc.prescribed
            .resize(model.loads.prescribed.len(), TimeFunction::Constant);
        let su = setup(model);
        let mut free = vec![0; su.nf];
        for (i, u) in su.unknown.iter().enumerate() {
            if let Some(u) = u {
                free[*u] = i;
            }
        }
        let mut presc = Vec::new();
        let mut inputs = Vec::new();
        for (k, p) in model.loads.prescribed.iter().enumerate() {
            match p.target {
                Target::Coordinate(i) => presc.push(PrescribedCoord {
                    xi: i,
                    value: p.value,
                    f: k,
                    lambda: su.is_lambda[i],
                }),
                Target::Deformation(i) => {
                    if let Some(kc) = su.constraint[i] {
                        let periodic = model.elements.iter().any(|en| {
                            (en.ie..en.ie + en.element.ne()).contains(&i)
                                && en.element.mode_is_periodic(i - en.ie)
                        });
                        inputs.push(InputDef {
                            kc,
                            value: p.value,
                            f: k,
                            periodic,
                        });
                    }
                }
            }
        }
        let mut moments = Vec::new();
        for (k, l) in model.loads.nodal.iter().enumerate() {
            if let Some(r) = model.nodes[l.node].ix_rot {
                if l.moment.iter().any(|m| *m != 0.0) {
                    moments.push((r, l.moment, k));
                }
            }
        }
        // model size for the default absolute tolerance
        let x0 = model.x0();
        let atol = opts.atol;
        let l_ref = su.l_ref;
        // the fixed entry list: assembly triplets, mass, moment stiffness, diagonal
        let asm = assemble_part(model, &su, &x0, &vec![0.0; su.nk], 0.0, Part::Full);
        let n_pat = asm.triplets.len();
        let mut rows: Vec<(usize, usize)> = asm.triplets.iter().map(|t| (t.row, t.col)).collect();
        let mut mass_slot = Vec::new();
        for_each_entry(model, &x0, None, true, |r, c, _| {
            match (su.unknown[r], su.unknown[c]) {
                (Some(a), Some(b)) => {
                    mass_slot.push(Some(rows.len()));
                    rows.push((a, b));
                }
                _ => mass_slot.push(None),
            }
        });
        let mut moment_slot = Vec::new();
        for &(r, _, _) in &moments {
            let mut s = [[None; 4]; 4];
            for (i, si) in s.iter_mut().enumerate() {
                for (j, sij) in si.iter_mut().enumerate() {
                    if let (Some(a), Some(b)) = (su.unknown[r + i], su.unknown[r + j]) {
                        *sij = Some(rows.len());
                        rows.push((a, b));
                    }
                }
            }
            moment_slot.push(s);
        }
        let diag_start = rows.len();
        for u in 0..su.nf {
            rows.push((u, u));
        }
        let n = su.nf + su.nk;
        let entries = |f: &mut dyn FnMut(usize, usize)| {
            for &(r, c) in &rows {
                f(r, c);
            }
        };
        let solver = KktSolver::from_entries(n, rows.len(), &entries, moments.is_empty())
            .map_err(SimError::Initial)?;
        Ok(Self {
            model,
            exc,
            opts: opts.clone(),
            p: Params::new(opts.rho_inf),
            free,
            presc,
            inputs,
            moments,
            atol,
            l_ref,
            n_pat,
            mass_slot,
            moment_slot,
            diag_start,
            n_vals: rows.len(),
            entries: rows,
            su,
            solver,
            jac_h: None,
            failed_stale: false,
            full_newton: false,
        })
    }

    /// Set the prescribed coordinates, their rates and accelerations at t.
    fn apply_prescribed(&self, t: f64, x: &mut [f64], v: &mut [f64], a: &mut [f64]) {
        let x0 = |i: usize| {
            let n = self.model.x0();
            n[i]
        };
        for p in &self.presc {
            let [f, df, ddf] = history(&self.exc.prescribed[p.f], t);
            if p.lambda {
                // λ_i = sin(½ value φ)
                let th = 0.5 * p.value;
                let (s, c) = (th * f).sin_cos();
                x[p.xi] = s;
                v[p.xi] = th * df * c;
                a[p.xi] = th * ddf * c - th * th * df * df * s;
            } else {
                x[p.xi] = x0(p.xi) + p.value * f;
                v[p.xi] = p.value * df;
                a[p.xi] = p.value * ddf;
            }
        }
    }

    /// Targets of the input deformations at t: (value, rate, acceleration) by constraint row.
    fn input_targets(&self, t: f64) -> Vec<(usize, [f64; 3])> {
        self.inputs
            .iter()
            .map(|d| {
                let f = history(&self.exc.prescribed[d.f], t);
                (d.kc, f.map(|v| v * d.value))
            })
            .collect()
    }

    /// External loads at (x, t) on all of x.
    fn external(&self, x: &[f64], t: f64) -> Vec<f64> {
        let model = self.model;
        let mut f = vec![0.0; model.nx];
        let add_moment = |f: &mut [f64], r: usize, m: [f64; 3], s: f64| {
            let lb = lambda_bar(&[x[r], x[r + 1], x[r + 2], x[r + 3]]);
            for c in 0..4 {
                f[r + c] += 2.0 * s * (0..3).map(|k| lb[k][c] * m[k]).sum::<f64>();
            }
        };
        for (k, l) in model.loads.nodal.iter().enumerate() {
            let s = self.exc.loads[k].eval(t)[0];
            let ip = model.nodes[l.node].ix_pos;
            for j in 0..3 {
                f[ip + j] += s * l.force[j];
            }
        }
        for &(r, m, k) in &self.moments {
            add_moment(&mut f, r, m, self.exc.loads[k].eval(t)[0]);
        }
        if model.loads.gravity != [0.0; 3] {
            let s = self.exc.gravity.eval(t)[0];
            for (node, (force, moment)) in field_loads_at(model, x).iter().enumerate() {
                let n = &model.nodes[node];
                for j in 0..3 {
                    f[n.ix_pos + j] += s * force[j];
                }
                if let Some(r) = n.ix_rot {
                    if moment.iter().any(|v| *v != 0.0) {
                        add_moment(&mut f, r, *moment, s);
                    }
                }
            }
        }
        f
    }

    /// Rayleigh damping forces C ẋ = α M ẋ + β Dᵀ S D ẋ (with M ẋ given).
    fn damping(&self, x: &[f64], v: &[f64], mv: &[f64]) -> Vec<f64> {
        let [alpha, beta] = self.opts.rayleigh;
        let mut d: Vec<f64> = mv.iter().map(|m| alpha * m).collect();
        if beta > 0.0 {
            for (el, entry) in self.model.elements.iter().enumerate() {
                let xk = crate::assembly::gather(entry, x);
                let jac = entry.element.jacobian(&xk);
                let s = &self.su.s_eff[el];
                let ne = jac.nrows();
                let ed: Vec<f64> = (0..ne)
                    .map(|m| (0..xk.len()).map(|c| jac[(m, c)] * v[entry.xmap[c]]).sum())
                    .collect();
                let sd: Vec<f64> = (0..ne)
                    .map(|m| (0..ne).map(|n| s[(m, n)] * ed[n]).sum())
                    .collect();
                for (c, &xi) in entry.xmap.iter().enumerate() {
                    d[xi] += beta * (0..ne).map(|m| jac[(m, c)] * sd[m]).sum::<f64>();
                }
            }
        }
        d
    }

    /// Evaluate at a state.
    fn evaluate(&self, x: &[f64], v: &[f64], a: &[f64], mu: &[f64], t: f64) -> Eval {
        self.evaluate_part(x, v, a, mu, t, Part::Full)
    }

    /// [`Engine::evaluate`] with the tangent (`Part::Full`) or without it (`Part::Residual`).
    fn evaluate_part(
        &self,
        x: &[f64],
        v: &[f64],
        a: &[f64],
        mu: &[f64],
        t: f64,
        part: Part,
    ) -> Eval {
        let model = self.model;
        let asm = if part == Part::Full {
            assemble(model, &self.su, x, mu, 0.0)
        } else {
            assemble_values(model, &self.su, x, mu, 0.0, part, false, Vec::new())
        };
        let km = (self.opts.rayleigh[1] > 0.0 && part == Part::Full).then(|| {
            assemble_values(
                model,
                &self.su,
                x,
                mu,
                0.0,
                Part::Material,
                false,
                Vec::new(),
            )
            .vals
        });
        let ext = self.external(x, t);
        let inertia = inertia_forces(model, x, v, a);
        let mv = if self.opts.rayleigh[0] > 0.0 {
            mass_times(model, x, &[v]).pop().unwrap_or_default()
        } else {
            vec![0.0; model.nx]
        };
        let damp = self.damping(x, v, &mv);
        let balance: Vec<f64> = (0..model.nx)
            .map(|i| asm.balance[i] + inertia[i] + damp[i] - ext[i])
            .collect();
        let mut g = asm.g.clone();
        for (d, (kc, tv)) in self.inputs.iter().zip(self.input_targets(t)) {
            // assemble_part wrote e − 0 for inputs (load factor 0)
            g[kc] -= tv[0];
            if d.periodic {
                // the nearest turn: e lies in (−π, π], the target anywhere
                g[kc] -= std::f64::consts::TAU * (g[kc] / std::f64::consts::TAU).round();
            }
        }
        Eval {
            asm,
            balance,
            ext,
            damp,
            g,
            km,
        }
    }

    /// The matrix values for the coefficients, at x and t.
    fn values(&self, ev: &Eval, x: &[f64], t: f64, c: Coefs) -> Vec<f64> {
        let nf = self.su.nf;
        let mut vals = vec![0.0; self.n_vals];
        debug_assert_eq!(ev.asm.vals.len(), self.n_pat);
        for (i, (&(r, col), &v)) in self.entries.iter().zip(&ev.asm.vals).enumerate() {
            vals[i] = if r < nf && col < nf {
                c.k * v + ev.km.as_ref().map_or(0.0, |km| c.km * km[i])
            } else {
                v
            };
        }
        if c.m != 0.0 {
            let mut k = 0;
            for_each_entry(self.model, x, None, true, |_, _, v| {
                if let Some(s) = self.mass_slot[k] {
                    vals[s] += c.m * v;
                }
                k += 1;
            });
        }
        for (&(_, m, li), slots) in self.moments.iter().zip(&self.moment_slot) {
            let s = self.exc.loads[li].eval(t)[0];
            let am = [
                [0.0, -m[0], -m[1], -m[2]],
                [m[0], 0.0, -m[2], m[1]],
                [m[1], m[2], 0.0, -m[0]],
                [m[2], -m[1], m[0], 0.0],
            ];
            for i in 0..4 {
                for j in 0..4 {
                    if let Some(slot) = slots[i][j] {
                        vals[slot] += -2.0 * s * am[i][j] * c.k;
                    }
                }
            }
        }
        for u in 0..nf {
            vals[self.diag_start + u] = c.diag;
        }
        vals
    }

    /// G w and, with `quad`, also Σ vᵀ ∂²g v: the constraint rows applied to a vector on all
    /// of x (rates), and the second-order terms of the constraint accelerations.
    fn constraint_terms(&self, x: &[f64], w: &[f64], quad: Option<&[f64]>) -> Vec<f64> {
        let su = &self.su;
        let mut out = vec![0.0; su.nk];
        for entry in &self.model.elements {
            let ne = entry.element.ne();
            let cons: Vec<(usize, usize)> = (0..ne)
                .filter_map(|m| su.constraint[entry.ie + m].map(|kc| (m, kc)))
                .collect();
            if cons.is_empty() {
                continue;
            }
            let xk = crate::assembly::gather(entry, x);
            let jac = entry.element.jacobian(&xk);
            let wk: Vec<f64> = entry.xmap.iter().map(|&i| w[i]).collect();
            for &(m, kc) in &cons {
                out[kc] += (0..xk.len()).map(|c| jac[(m, c)] * wk[c]).sum::<f64>();
                if let Some(v) = quad {
                    let vk: Vec<f64> = entry.xmap.iter().map(|&i| v[i]).collect();
                    let mut unit = vec![0.0; ne];
                    unit[m] = 1.0;
                    let hm = entry.element.hessian_weighted(&xk, &unit);
                    let mut q = 0.0;
                    for a in 0..vk.len() {
                        for b in 0..vk.len() {
                            q += vk[a] * hm[(a, b)] * vk[b];
                        }
                    }
                    out[kc] += q;
                }
            }
        }
        for &(r, kc) in &su.norm {
            out[kc] += 2.0 * (0..4).map(|i| x[r + i] * w[r + i]).sum::<f64>();
            if let Some(v) = quad {
                out[kc] += 2.0 * (0..4).map(|i| v[r + i] * v[r + i]).sum::<f64>();
            }
        }
        out
    }

    /// The initial state: static start or reference, consistent velocities and accelerations.
    fn initial_state(&mut self) -> Result<State, SimError> {
        let model = self.model;
        let (nf, nk, nx) = (self.su.nf, self.su.nk, model.nx);
        let (mut x, mut mu) = (model.x0(), vec![0.0; nk]);
        let pre_loaded = model
            .loads
            .nodal
            .iter()
            .enumerate()
            .any(|(k, _)| self.exc.loads[k].eval(0.0)[0] != 0.0)
            || model.loads.gravity != [0.0; 3] && self.exc.gravity.eval(0.0)[0] != 0.0
            || model
                .loads
                .prescribed
                .iter()
                .enumerate()
                .any(|(k, p)| p.value * self.exc.prescribed[k].eval(0.0)[0] != 0.0);
        match self.opts.start {
            Start::Static if pre_loaded => {
                let mut m0 = model.clone();
                for (k, l) in m0.loads.nodal.iter_mut().enumerate() {
                    let s = self.exc.loads[k].eval(0.0)[0];
                    l.force = l.force.map(|v| v * s);
                    l.moment = l.moment.map(|v| v * s);
                }
                for (k, p) in m0.loads.prescribed.iter_mut().enumerate() {
                    p.value *= self.exc.prescribed[k].eval(0.0)[0];
                }
                let sg = self.exc.gravity.eval(0.0)[0];
                m0.loads.gravity = m0.loads.gravity.map(|v| v * sg);
                let sopts = StaticOptions {
                    steps: self.opts.static_steps,
                    ..Default::default()
                };
                let sol = solve(&m0, &sopts, |_, _| {}).map_err(SimError::Start)?;
                let last = sol.steps.last().ok_or_else(|| {
                    SimError::Initial("the static start returned no state".into())
                })?;
                x.clone_from(&last.x);
                mu.clone_from(&last.multipliers);
            }
            Start::Reference => {
                if let Some(k) = model
                    .loads
                    .prescribed
                    .iter()
                    .enumerate()
                    .position(|(k, p)| p.value * self.exc.prescribed[k].eval(0.0)[0] != 0.0)
                {
                    return Err(SimError::Invalid(format!(
                        "prescribed input {} is not zero at t = 0, so the reference configuration is not a valid start: start from the static equilibrium, or give it a history that starts at 0",
                        k + 1
                    )));
                }
            }
            Start::Static => {}
        }
        // velocities: the given ones, the prescribed rates, projected onto the constraints
        let mut v = vec![0.0; nx];
        let mut a = vec![0.0; nx];
        for iv in &self.exc.velocities {
            let n = &model.nodes[iv.node];
            for j in 0..3 {
                v[n.ix_pos + j] = iv.velocity[j];
            }
            if let Some(r) = n.ix_rot {
                let lb = lambda_bar(&[x[r], x[r + 1], x[r + 2], x[r + 3]]);
                for c in 0..4 {
                    v[r + c] = 0.5 * (0..3).map(|k| lb[k][c] * iv.angular[k]).sum::<f64>();
                }
            }
        }
        let mut vp = vec![0.0; nx];
        let mut ap = vec![0.0; nx];
        let mut xt = x.clone();
        self.apply_prescribed(0.0, &mut xt, &mut vp, &mut ap);
        for p in &self.presc {
            v[p.xi] = vp[p.xi];
            a[p.xi] = ap[p.xi];
        }
        let targets = self.input_targets(0.0);
        let mut b = self.constraint_terms(&x, &vp, None);
        b.iter_mut().for_each(|v| *v = -*v);
        for &(kc, tv) in &targets {
            b[kc] += tv[1];
        }
        let ev = self.evaluate(&x, &v, &a, &mu, 0.0);
        let vals = self.values(
            &ev,
            &x,
            0.0,
            Coefs {
                k: 0.0,
                m: 0.0,
                km: 0.0,
                diag: 1.0,
            },
        );
        let mut rhs = vec![0.0; nf + nk];
        for u in 0..nf {
            rhs[u] = v[self.free[u]];
        }
        rhs[nf..].copy_from_slice(&b);
        self.solver.solve(&vals, &mut rhs).map_err(|_| {
            SimError::Initial(
                "the constraints are dependent (singular constraint Jacobian): check the kinematics"
                    .into(),
            )
        })?;
        for u in 0..nf {
            v[self.free[u]] = rhs[u];
        }
        // accelerations and multipliers: [M Gᵀ; G 0] [ẍ; μ] = [−r(ẍ = 0, μ = 0); −c]
        let zero_mu = vec![0.0; nk];
        let ev = self.evaluate(&x, &v, &a, &zero_mu, 0.0);
        let mut c = self.constraint_terms(&x, &a, Some(&v));
        for &(kc, tv) in &targets {
            c[kc] -= tv[2];
        }
        let mut rhs = vec![0.0; nf + nk];
        for u in 0..nf {
            rhs[u] = -ev.balance[self.free[u]];
        }
        for k in 0..nk {
            rhs[nf + k] = -c[k];
        }
        let exact = Coefs {
            k: 0.0,
            m: 1.0,
            km: 0.0,
            diag: 0.0,
        };
        let vals = self.values(&ev, &x, 0.0, exact);
        let mut sol = rhs.clone();
        let ok = self.solver.solve(&vals, &mut sol).is_ok() && finite(&sol);
        if !ok {
            // massless coordinates: the iteration matrix of the first step instead
            let (bp, gp) = self.p.primes(self.opts.dt);
            let reg = Coefs {
                k: 1.0 / bp,
                m: 1.0,
                km: self.opts.rayleigh[1] * gp / bp,
                diag: 0.0,
            };
            let vals = self.values(&ev, &x, 0.0, reg);
            sol.clone_from(&rhs);
            self.solver.solve(&vals, &mut sol).map_err(|_| {
                SimError::Initial(
                    "the iteration matrix is singular at t = 0: a coordinate has neither mass nor stiffness, or the constraints are dependent"
                        .into(),
                )
            })?;
        }
        for u in 0..nf {
            a[self.free[u]] = sol[u];
        }
        mu.copy_from_slice(&sol[nf..]);
        if !finite(&a) || !finite(&v) || !finite(&mu) {
            return Err(SimError::Initial("the initial state is not finite".into()));
        }
        Ok(State {
            t: 0.0,
            aux: a.clone(),
            x,
            v,
            acc: a,
            mu,
        })
    }

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

    /// The Newton tolerance of a coordinate: 1e-3 of its error weight, but not below the
    /// round-off of the coordinate (100 ε (|x| + model size)).
    fn newton_tol(&self, a: f64, b: f64) -> f64 {
        let m = a.abs().max(b.abs());
        (1e-3 * self.weight(a, b)).max(100.0 * f64::EPSILON * (m + self.l_ref))
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
        for &i in &self.free {
            // predictor ẍ_{n+1} = ẍ_n (a constant acceleration), a_{n+1} from it
            let ap = (p.af * s.acc[i] - p.am * s.aux[i]) / (1.0 - p.am);
            aux_pred[i] = ap;
            let a1 = ap + (1.0 - p.af) / (1.0 - p.am) * s.acc[i];
            n1.x[i] = s.x[i] + h * s.v[i] + h * h * ((0.5 - p.beta) * s.aux[i] + p.beta * a1);
            n1.v[i] = s.v[i] + h * ((1.0 - p.gamma) * s.aux[i] + p.gamma * a1);
            n1.acc[i] = s.acc[i];
        }
        {
            let (x, v, a) = (&mut n1.x, &mut n1.v, &mut n1.acc);
            self.apply_prescribed(t1, x, v, a);
        }
        let coefs = Coefs {
            k: 1.0 / bp,
            m: 1.0 + self.opts.rayleigh[0] * gp / bp,
            km: self.opts.rayleigh[1] * gp / bp,
            diag: 0.0,
        };
        // modified Newton: the factorised matrix of an earlier iteration or step is reused
        // while the corrections shrink at least fourfold per iteration; else it is rebuilt
        let mut last_inc = f64::INFINITY;
        let mut prev_inc = f64::INFINITY;
        // the coordinate with the largest correction (named when Newton fails)
        let mut worst = usize::MAX;
        let mut stale = false;
        let full = std::mem::take(&mut self.full_newton);
        for it in 0..=self.opts.max_iterations {
            // slow: the corrections shrank less than twofold
            let slow = it > 1 && last_inc > SLOW * prev_inc;
            let rebuild = full || self.jac_h != Some(h) || slow || !self.solver.reusable();
            stale |= !rebuild;
            let part = if rebuild { Part::Full } else { Part::Residual };
            let ev = self.evaluate_part(&n1.x, &n1.v, &n1.acc, &n1.mu, t1, part);
            if !finite(&ev.balance) || !finite(&ev.g) {
                self.jac_h = None;
                return Err("the forces became non-finite during the Newton iteration".into());
            }
            if it > 0 && last_inc <= 1.0 {
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
                self.solver.solve_again(&mut rhs).is_ok()
            } else {
                let vals = self.values(&ev, &n1.x, t1, coefs);
                stats.matrix_updates += 1;
                let ok = self.solver.solve(&vals, &mut rhs).is_ok();
                self.jac_h = ok.then_some(h);
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
            prev_inc = if it == 0 { f64::INFINITY } else { last_inc };
            last_inc = inc;
        }
        self.jac_h = None;
        self.failed_stale = stale;
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
            .filter(|&i| self.su.unknown[i].is_none())
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
                if self.su.unknown[i].is_none() {
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
                    h = 0.5 * h_try;
                    if h < o.dt_min {
                        let hint = "reduce the first step or the tolerances, check the model for a coordinate without mass and stiffness or an element driven through itself, or add numerical damping (rho_inf < 1)";
                        return Err(stop(
                            frames,
                            stats,
                            s.t,
                            format!("{reason} even with the smallest step {:.3e} s", o.dt_min),
                            hint,
                        ));
                    }
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
                        return Err(stop(
                            frames,
                            stats,
                            s.t,
                            format!("element `{name}` turned inside out (zero length or reversed chord) in the step to t = {:.6e} s", n1.t),
                            "check the loads and the stiffness of that element; a smaller step does not help an element driven through itself",
                        ));
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
