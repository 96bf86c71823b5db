//! The forces and matrices at a state: prescribed motions, external loads, damping, the
//! evaluation (residual, constraints, tangent) and the iteration matrix values, the constraint
//! rates and their second-order terms.

use super::*;

impl Engine<'_> {
    /// Set the prescribed coordinates, their rates and accelerations at t.
    pub(super) fn apply_prescribed(&self, t: f64, x: &mut [f64], v: &mut [f64], a: &mut [f64]) {
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
    pub(super) fn input_targets(&self, t: f64) -> Vec<(usize, [f64; 3])> {
        self.inputs
            .iter()
            .map(|d| {
                let f = history(&self.exc.prescribed[d.f], t);
                (d.kc, f.map(|v| v * d.value))
            })
            .collect()
    }

    /// External loads at (x, t) on all of x.
    pub(super) fn external(&self, x: &[f64], t: f64) -> Vec<f64> {
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
            for (node, (force, moment)) in field_loads_with(model, x, &self.element_nodes)
                .iter()
                .enumerate()
            {
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

    /// Damping forces C ẋ = α M ẋ + Σₑ (β + τₑ) Dₑᵀ Sₑ Dₑ ẋ (with M ẋ given): Rayleigh damping
    /// of the whole model and the material damping of each element (Kelvin–Voigt,
    /// retardation time τₑ: σ = S (e + τ ė)).
    pub(super) fn damping(&self, x: &[f64], v: &[f64], mv: &[f64]) -> Vec<f64> {
        let alpha = self.opts.rayleigh[0];
        let mut d: Vec<f64> = mv.iter().map(|m| alpha * m).collect();
        if self.stiffness_damping() {
            for (di, ki) in d
                .iter_mut()
                .zip(self.material_times_by(x, v, |el| self.damping_factor(el)))
            {
                *di += ki;
            }
        }
        d
    }

    /// β + τₑ of element `el`: its stiffness-proportional damping [s].
    pub(super) fn damping_factor(&self, el: usize) -> f64 {
        self.opts.rayleigh[1] + self.model.elements[el].damping
    }

    /// Whether any damping is proportional to the material stiffness (β > 0 or an element
    /// with τ > 0).
    pub(super) fn stiffness_damping(&self) -> bool {
        self.stiffness_damping
    }

    /// K_m w = Dᵀ S D w on all of x: the material stiffness applied to a vector, element by
    /// element.
    pub(super) fn material_times(&self, x: &[f64], w: &[f64]) -> Vec<f64> {
        self.material_times_by(x, w, |_| 1.0)
    }

    /// Σₑ cₑ Dₑᵀ Sₑ Dₑ w with the factor cₑ = `factor(e)` of each element (elements with
    /// cₑ = 0 skipped).
    fn material_times_by(&self, x: &[f64], w: &[f64], factor: impl Fn(usize) -> f64) -> Vec<f64> {
        let mut out = vec![0.0; self.model.nx];
        for (el, entry) in self.model.elements.iter().enumerate() {
            let c = factor(el);
            if c == 0.0 {
                continue;
            }
            let xk = crate::assembly::gather(entry, x);
            let jac = entry.element.jacobian(&xk);
            let s = self.su.s_eff.get(el);
            let ne = jac.nrows();
            let ed: Vec<f64> = (0..ne)
                .map(|m| {
                    (0..xk.len())
                        .map(|c| jac[(m, c)] * w[entry.x_index(c)])
                        .sum()
                })
                .collect();
            let sd: Vec<f64> = (0..ne)
                .map(|m| c * (0..ne).map(|n| s[(m, n)] * ed[n]).sum::<f64>())
                .collect();
            for (c, xi) in entry.x_indices().enumerate() {
                out[xi] += (0..ne).map(|m| jac[(m, c)] * sd[m]).sum::<f64>();
            }
        }
        out
    }

    /// Evaluate at a state.
    pub(super) fn evaluate(&self, x: &[f64], v: &[f64], a: &[f64], mu: &[f64], t: f64) -> Eval {
        self.evaluate_part(x, v, a, mu, t, Part::Full, Vec::new())
    }

    /// [`Engine::evaluate`] with the tangent (`Part::Full`) or without it (`Part::Residual`);
    /// `spare` is a buffer to reuse for the tangent's entries.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn evaluate_part(
        &self,
        x: &[f64],
        v: &[f64],
        a: &[f64],
        mu: &[f64],
        t: f64,
        part: Part,
        spare: Vec<f64>,
    ) -> Eval {
        let model = self.model;
        let asm = assemble_values(model, &self.su, x, mu, 0.0, part, false, spare);
        // the damping matrix Σₑ (β + τₑ) Dₑᵀ Sₑ Dₑ
        let km = (self.stiffness_damping() && part == Part::Full).then(|| {
            let mut vals = assemble_values(
                model,
                &self.su,
                x,
                mu,
                0.0,
                Part::Material,
                false,
                Vec::new(),
            )
            .vals;
            scale_elements(&self.su, &mut vals, |el| self.damping_factor(el));
            vals
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
    pub(super) fn values(&self, ev: &Eval, x: &[f64], t: f64, c: Coefs) -> Vec<f64> {
        let mut vals = Vec::new();
        self.values_into(ev, x, t, c, &mut vals);
        vals
    }

    /// [`Engine::values`] into a reused buffer. Every value slot is written (assigned, or
    /// cleared and added to), so a buffer of the right length is reused without clearing it.
    pub(super) fn values_into(&self, ev: &Eval, x: &[f64], t: f64, c: Coefs, vals: &mut Vec<f64>) {
        let nf = self.su.nf;
        debug_assert_eq!(ev.asm.vals.len(), self.n_pat);
        vals.resize(self.n_vals, 0.0);
        for (i, ((o, &free), &v)) in vals[..self.n_pat]
            .iter_mut()
            .zip(&self.in_free)
            .zip(&ev.asm.vals)
            .enumerate()
        {
            *o = if free {
                c.k * v + ev.km.as_ref().map_or(0.0, |km| c.km * km[i])
            } else {
                v
            };
        }
        let ms = &self.mass;
        let last = ms.first + ms.piece_start[ms.piece_start.len() - 1];
        let node_slots = || ms.node.iter().flatten();
        if c.m != 0.0 {
            // element by element (in parallel for large models), each into its own slots (one
            // slot per entry of its mass matrix on the free block)
            let pieces = split_at_starts(&mut vals[ms.first..last], &ms.piece_start);
            map_elements(&self.model.elements, pieces, |el, entry, piece| {
                let local = &ms.local[ms.entry_start[el]..ms.entry_start[el + 1]];
                if local.is_empty() {
                    return;
                }
                element_mass(entry, x, None, true, |me| {
                    for (&o, &v) in local.iter().zip(me) {
                        if o != NO_SLOT {
                            piece[o as usize] = c.m * v;
                        }
                    }
                });
            });
            node_slots().for_each(|&s| vals[s] = 0.0);
            let mut k = 0;
            for_each_node_entry(self.model, x, None, true, |_, _, v| {
                if let Some(s) = ms.node[k] {
                    vals[s] += c.m * v;
                }
                k += 1;
            });
        } else {
            vals[ms.first..last].fill(0.0);
            node_slots().for_each(|&s| vals[s] = 0.0);
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
                        vals[slot] = -2.0 * s * am[i][j] * c.k;
                    }
                }
            }
        }
        for u in 0..nf {
            vals[self.diag_start + u] = c.diag;
        }
    }

    /// G w and, with `quad`, also Σ vᵀ ∂²g v: the constraint rows applied to a vector on all
    /// of x (rates), and the second-order terms of the constraint accelerations.
    pub(super) fn constraint_terms(&self, x: &[f64], w: &[f64], quad: Option<&[f64]>) -> Vec<f64> {
        let su = &self.su;
        let mut out = vec![0.0; su.nk];
        for entry in &self.model.elements {
            let ne = entry.element.ne();
            let cons: Vec<(usize, usize)> = (0..ne)
                .filter_map(|m| su.constraint[entry.ie + m].get().map(|kc| (m, kc)))
                .collect();
            if cons.is_empty() {
                continue;
            }
            let xk = crate::assembly::gather(entry, x);
            let jac = entry.element.jacobian(&xk);
            let wk: Vec<f64> = entry.x_indices().map(|i| w[i]).collect();
            for &(m, kc) in &cons {
                out[kc] += (0..xk.len()).map(|c| jac[(m, c)] * wk[c]).sum::<f64>();
                if let Some(v) = quad {
                    let vk: Vec<f64> = entry.x_indices().map(|i| v[i]).collect();
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
}
