//! Checking the options and setting up the engine: the fixed entry list of the iteration
//! matrix (assembly, mass, moment load stiffness, diagonal) and its sparse solver.

use super::*;

pub(super) fn check_options(
    model: &Model,
    exc: &Excitation,
    o: &SimOptions,
) -> Result<(), SimError> {
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
    pub(super) fn new(
        model: &'a Model,
        exc: &Excitation,
        opts: &SimOptions,
    ) -> Result<Self, SimError> {
        check_options(model, exc, opts)?;
        let mut exc = exc.clone();
        exc.loads
            .resize(model.loads.nodal.len(), TimeFunction::Constant);
        exc.prescribed
            .resize(model.loads.prescribed.len(), TimeFunction::Constant);
        let su = setup(model);
        let mut free = vec![0; su.nf];
        for (i, u) in su.unknown.iter().enumerate() {
            if let Some(u) = u.get() {
                free[u] = i;
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
                    if let Some(kc) = su.constraint[i].get() {
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
        // the mass entries in the order of `for_each_entry`: element by element (the free
        // pairs of an element in consecutive slots), then the point masses and inertia tensors
        let mut mass = MassSlots {
            local: Vec::new(),
            entry_start: vec![0],
            piece_start: vec![0],
            first: rows.len(),
            node: Vec::new(),
        };
        for entry in &model.elements {
            let start = rows.len();
            element_mass(entry, &x0, None, true, |me| {
                let n = entry.xmap.len();
                for i in 0..me.len() {
                    let (r, c) = (entry.x_index(i / n), entry.x_index(i % n));
                    match (su.unknown[r].get(), su.unknown[c].get()) {
                        (Some(a), Some(b)) => {
                            mass.local.push((rows.len() - start) as u32);
                            rows.push((a, b));
                        }
                        _ => mass.local.push(NO_SLOT),
                    }
                }
            });
            mass.entry_start.push(mass.local.len());
            mass.piece_start.push(rows.len() - mass.first);
        }
        for_each_node_entry(model, &x0, None, true, |r, c, _| {
            match (su.unknown[r].get(), su.unknown[c].get()) {
                (Some(a), Some(b)) => {
                    mass.node.push(Some(rows.len()));
                    rows.push((a, b));
                }
                _ => mass.node.push(None),
            }
        });
        let mut moment_slot = Vec::new();
        for &(r, _, _) in &moments {
            let mut s = [[None; 4]; 4];
            for (i, si) in s.iter_mut().enumerate() {
                for (j, sij) in si.iter_mut().enumerate() {
                    if let (Some(a), Some(b)) = (su.unknown[r + i].get(), su.unknown[r + j].get()) {
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
        if rows.len() > NO_SLOT as usize {
            return Err(SimError::Initial(format!(
                "the iteration matrix would have {} entries, more than its 32-bit mass slots \
                 address ({NO_SLOT})",
                rows.len()
            )));
        }
        let in_free = rows[..n_pat]
            .iter()
            .map(|&(r, c)| r < su.nf && c < su.nf)
            .collect();
        let entries = |f: &mut dyn FnMut(usize, usize)| {
            for &(r, c) in &rows {
                f(r, c);
            }
        };
        let mut solver = KktSolver::from_entries(n, rows.len(), &entries, moments.is_empty())
            .map_err(SimError::Initial)?;
        solver.set_keep_small_pivots(true);
        let corot = corot::corot_nodes(model, &su.unknown);
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
            in_free,
            mass,
            moment_slot,
            diag_start,
            n_vals: rows.len(),
            entries: rows,
            su,
            solver,
            jac_h: None,
            corot,
            jac_lambda: Vec::new(),
            turns: Vec::new(),
            failed_stale: false,
            full_newton: false,
            carry_fails: false,
            since_probe: 0,
            full_steps: 0,
            acc_before: None,
            acc_before2: None,
            vals_buf: Vec::new(),
            asm_spare: Vec::new(),
            element_nodes: element_nodes(model),
            stiffness_damping: opts.rayleigh[1] > 0.0
                || model.elements.iter().any(|e| e.damping > 0.0),
        })
    }
}
