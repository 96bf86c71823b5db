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
        let given = self.given_unknowns();
        let (vals, mut rhs) = match self.opts.start_velocity {
            StartVelocity::Projected => {
                let ev = self.evaluate(&x, &v, &a, &mu, 0.0);
                let c = Coefs {
                    k: 0.0,
                    m: 0.0,
                    km: 0.0,
                    diag: 1.0,
                };
                let mut rhs: Vec<f64> = self.free.iter().map(|&i| v[i]).collect();
                rhs.extend_from_slice(&b);
                (self.values(&ev, &x, 0.0, c), rhs)
            }
            StartVelocity::LeastDeformation => {
                self.least_deformation_system(&x, &mu, &v, &vp, &given, &b)
            }
        };
        self.solver.solve(&vals, &mut rhs).map_err(|_| {
            SimError::Initial(
                "the constraints are dependent (singular constraint Jacobian), or a coordinate has neither mass nor stiffness: check the kinematics"
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
                km: if self.stiffness_damping() {
                    gp / bp
                } else {
                    0.0
                },
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

    /// The free unknowns of the nodes with a given initial velocity.
    fn given_unknowns(&self) -> Vec<bool> {
        let mut given = vec![false; self.su.nf];
        for iv in &self.exc.velocities {
            let n = &self.model.nodes[iv.node];
            let rot = n.ix_rot.map_or(0..0, |r| r..r + 4);
            for i in (n.ix_pos..n.ix_pos + 3).chain(rot) {
                if let Some(u) = self.su.unknown[i].get() {
                    if u < self.su.nf {
                        given[u] = true;
                    }
                }
            }
        }
        given
    }

    /// The system of [`StartVelocity::LeastDeformation`]: minimise ½ ẋᵀ (K_m + ε M) ẋ over the
    /// free velocities subject to the constraint rates G ẋ = b, with the prescribed rates `vp`
    /// moved to the right-hand side and the given node velocities (`v` at `given`) held by a
    /// penalty. K_m = Dᵀ S D weighs the rates of elastic deformation; ε M (ε = 1e-8 · tr K_m /
    /// tr M over the free unknowns) only decides the directions that deform nothing.
    fn least_deformation_system(
        &self,
        x: &[f64],
        mu: &[f64],
        v: &[f64],
        vp: &[f64],
        given: &[bool],
        b: &[f64],
    ) -> (Vec<f64>, Vec<f64>) {
        let (nf, nx) = (self.su.nf, self.model.nx);
        let zero = vec![0.0; nx];
        let mut ev = self.evaluate(x, &zero, &zero, mu, 0.0);
        ev.km = Some(
            assemble_values(
                self.model,
                &self.su,
                x,
                mu,
                0.0,
                Part::Material,
                false,
                Vec::new(),
            )
            .vals,
        );
        let only = |k: f64, m: f64, km: f64| Coefs {
            k,
            m,
            km,
            diag: 0.0,
        };
        let vals_k = self.values(&ev, x, 0.0, only(0.0, 0.0, 1.0));
        let vals_m = self.values(&ev, x, 0.0, only(0.0, 1.0, 0.0));
        // |diagonal terms| of the free block of a value list
        let diagonal = |vals: &[f64]| -> Vec<f64> {
            self.entries
                .iter()
                .zip(vals)
                .filter(|((r, c), _)| r == c && *r < nf)
                .map(|(_, v)| v.abs())
                .collect()
        };
        let (tr_k, tr_m): (f64, f64) = (
            diagonal(&vals_k).iter().sum(),
            diagonal(&vals_m).iter().sum(),
        );
        let eps = if tr_k > 0.0 && tr_m > 0.0 {
            1e-8 * tr_k / tr_m
        } else {
            1.0
        };
        let mut vals: Vec<f64> = self
            .entries
            .iter()
            .enumerate()
            .map(|(i, &(r, c))| {
                if r < nf && c < nf {
                    vals_k[i] + eps * vals_m[i]
                } else {
                    vals_k[i]
                }
            })
            .collect();
        // the prescribed rates: −(K_m + ε M) ẋ_p on the free rows
        let km_vp = self.material_times(x, vp);
        let m_vp = mass_times(self.model, x, &[vp]).pop().unwrap_or_default();
        let mut rhs: Vec<f64> = self
            .free
            .iter()
            .map(|&i| -(km_vp[i] + eps * m_vp[i]))
            .collect();
        rhs.extend_from_slice(b);
        // the given velocities: a penalty 1e8 times the largest diagonal term, which keeps them
        // to about 1e-8 where they meet the constraints and projects them (weighted least
        // squares) where they do not
        let largest = diagonal(&vals).into_iter().fold(0.0, f64::max);
        let w = 1e8 * if largest > 0.0 { largest } else { 1.0 };
        for u in (0..nf).filter(|&u| given[u]) {
            vals[self.diag_start + u] += w;
            rhs[u] += w * v[self.free[u]];
        }
        (vals, rhs)
    }
}
