//! The consistent initial state: static or reference start, velocities projected onto the
//! constraints, initial accelerations and multipliers.

use super::*;

impl Engine<'_> {
    /// The initial state: static start or reference, consistent velocities and accelerations.
    pub(super) fn initial_state(&mut self) -> Result<State, SimError> {
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
}
