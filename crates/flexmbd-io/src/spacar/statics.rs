//! The static data of a SPACAR model, mapped on top of the kinematic mapping ([`super::mapping`])
//! for `flexmbd static` and for the converted TOML file (docs/spacar-import.md §5, §6).
//!
//! **Roles of the deformations.** In a SPACAR static analysis only the dynamic degrees of freedom
//! (`DYNE`, e^d) and the released deformations (`RLSE`, e^c) deform; a deformation not listed
//! (e^o) stays rigid even when `ESTIFF` gives it a stiffness, and `INPUTE` deformations are
//! prescribed. flexmbd's statics makes every deformation with stiffness flexible unless it is
//! declared rigid, so:
//!
//! - `DYNE` with stiffness → not listed (still a row of the kinematic check, as an input is;
//!   flexible in statics); `DYNE` without stiffness → input held at its reference value (a warning:
//!   SPACAR would have a degree of freedom without stiffness);
//! - not listed, with stiffness → beam: `fixed` (TOML) / `set_rigid_modes`; truss and hinge: the
//!   stiffness is dropped (the TOML format has no `fixed` for them; the value stays a comment);
//! - `RLSE` → free (flexible with its stiffness, if any), `INPUTE` → input with the prescribed
//!   value from `INPUTE`/`DELINPE`.
//!
//! `DYNX` coordinates are unknowns of the equilibrium: they go to `dynamic_inputs`, which
//! [`ModelSpec::build_static`] leaves free and the TOML writer puts into `[inputs]` (for the
//! kinematic check).
//!
//! **Load stepping.** flexmbd ramps every load and prescribed value from zero to its final value
//! over the steps; SPACAR applies the "initial" values (`XF`, `INPUTX`/`INPUTE` values) in full
//! in the first step and ramps the increments (`DELXF`, `DELINPX`, `DELINPE`). The final values
//! are the same (initial + increment); when an initial value is non-zero and there is more than
//! one step, a warning says that the path differs.

use super::mapping::{fmt_num, fmt_values, header, NodeMap};
use super::*;
use crate::error::{at_line, InputError};
use crate::limits::MAX_STEPS;
use crate::spec::{
    ElementKind as Kind, LoadEntry, MassEntry, ModelSpec, PrescribeEntry, PrescribeTarget, Src,
    StaticSpec,
};
use flexmbd_core::model::Dof;
use flexmbd_core::section::BeamProps;
use rustc_hash::FxHashMap as HashMap;
use std::collections::{BTreeMap, BTreeSet};

/// flexmbd's default number of load steps (`StaticOptions::default().steps`), for the
/// load-path warnings of a file without `ITERSTEP`.
const DEFAULT_STEPS: usize = 10;

/// The model spec with its static data, and what the mapping had to approximate.
pub(super) struct Conversion {
    /// The spec (header comments included).
    pub spec: ModelSpec,
    /// Warnings that concern `flexmbd static` on the `.dat` file (and the TOML file).
    pub warnings: Vec<Warning>,
    /// Warnings that concern the TOML file only (what the format cannot express).
    pub toml_warnings: Vec<Warning>,
    /// The node map the spec was made with (for the time simulation's data).
    pub map: NodeMap,
}

/// Values of an `(item, index)` with an initial value and increments.
#[derive(Default)]
struct Ramp {
    /// Initial (absolute) value and its line; the last one counts.
    initial: Option<(f64, usize)>,
    /// Increments with their lines.
    increments: Vec<(f64, usize)>,
}

impl Ramp {
    fn first_line(&self) -> usize {
        let a = self.initial.map(|i| i.1);
        let b = self.increments.iter().map(|i| i.1).min();
        a.into_iter().chain(b).min().unwrap_or(1)
    }
    fn increment(&self) -> f64 {
        self.increments.iter().map(|i| i.0).sum()
    }
    /// `INPUTX 3 2 0.01 (line 16), DELINPX 3 2 0.02 (line 17)`; `item` = "3 2".
    fn describe(&self, initial_kw: &str, inc_kw: &str, item: &str) -> String {
        let mut parts = Vec::new();
        if let Some((v, line)) = self.initial {
            parts.push(format!("{initial_kw} {item} {} (line {line})", fmt_num(v)));
        }
        for (v, line) in &self.increments {
            parts.push(format!("{inc_kw} {item} {} (line {line})", fmt_num(*v)));
        }
        parts.join(", ")
    }
}

/// What the spec is built for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Purpose {
    /// `flexmbd static` and `flexmbd convert`: loads and prescribed values at their final
    /// values, `DYNE` modes without stiffness held.
    Static,
    /// The time simulation (module `dynamics`): no loads and prescribed values (the module
    /// adds them with their histories), `DYNE` modes without stiffness free, pre-stress an
    /// error.
    Dynamic,
    /// The complete document (`flexmbd convert`): the spec of `Static`, and for a file set up
    /// for a time simulation whose model is the static one, its `[simulate]` settings,
    /// inertia tensors and histories (module `dynamics`).
    Document,
}

/// The static data of `m` on top of its kinematic spec.
pub(super) fn convert(m: &SpacarModel, purpose: Purpose) -> Result<Conversion, InputError> {
    let map = NodeMap::new(m)?;
    let mut spec = super::mapping::to_spec_with(m, purpose == Purpose::Document, &map)?;
    let err = |line: usize, msg: String| at_line(&m.file, line, 1, msg);
    let mut warnings = Vec::new();
    let mut toml_warnings = Vec::new();
    let mut warn = |line: usize, message: String| warnings.push(Warning { line, message });

    // --- load steps ---
    let mut statics = StaticSpec::default();
    if let Some(it) = m.iterstep.as_ref().filter(|_| purpose != Purpose::Dynamic) {
        let v = &it.values;
        let mut used = Vec::new();
        match v.get(1) {
            Some(&n) if n >= 1.0 && n == n.trunc() && n <= MAX_STEPS as f64 => {
                statics.steps = Some(n as usize);
                used.push(format!("steps = {n} (field 2, the number of load increments)"));
            }
            Some(&n) if n > MAX_STEPS as f64 => {
                return Err(err(
                    it.line,
                    format!("ITERSTEP: field 2 (the number of load increments) must be from 1 to {MAX_STEPS} (the limit, docs/reliability.md), found {}", fmt_num(n)),
                ))
            }
            Some(&n) => warn(
                it.line,
                format!("ITERSTEP: field 2 (the number of load increments) must be a whole number ≥ 1, found {}; flexmbd's default of {DEFAULT_STEPS} steps is used", fmt_num(n)),
            ),
            None => {}
        }
        match v.get(2) {
            Some(&t) if t > 0.0 && t < 1.0 => {
                statics.tol_force = Some(t);
                used.push(format!(
                    "tol_force = {} (field 3, the convergence tolerance)",
                    fmt_num(t)
                ));
            }
            Some(&t) => warn(
                it.line,
                format!("ITERSTEP: field 3 (the convergence tolerance) must be between 0 and 1, found {}; flexmbd's default is used", fmt_num(t)),
            ),
            None => {}
        }
        statics.comments.push(format!(
            "ITERSTEP {} (line {}): {}; field 1 (presumably SPACAR's Newton iteration limit) and fields 4-6 are not used (flexmbd halves a load step that does not converge).",
            fmt_values(v),
            it.line,
            if used.is_empty() {
                "nothing used".to_string()
            } else {
                used.join(", ")
            }
        ));
    }
    let n_steps = statics.steps.unwrap_or(DEFAULT_STEPS);
    if let Some(g) = &m.gravity {
        // parse_dat guarantees three numbers
        if let Ok(v) = <[f64; 3]>::try_from(&g.values[..]) {
            statics.gravity = Some(v);
            statics.src = Src::line(g.line);
            statics.comments.push(format!(
                "GRAVITY {} (line {})",
                fmt_values(&g.values),
                g.line
            ));
        }
    }
    spec.statics = statics;

    // --- elements: constants and roles ---
    let by = ByElement::new(m);
    let last = |of: &HashMap<u32, &ElementValues>, el: u32| -> Option<(Vec<f64>, usize)> {
        of.get(&el).map(|v| (v.values.clone(), v.line))
    };
    let listed = |of: &HashMap<u32, Vec<&ModeList>>, el: u32| -> BTreeSet<u32> {
        of.get(&el)
            .into_iter()
            .flatten()
            .flat_map(|l| l.modes.iter().copied())
            .collect()
    };
    let x_of: BTreeMap<u32, [f64; 3]> = m
        .positions
        .iter()
        .filter_map(|p| Some((p.node, <[f64; 3]>::try_from(&p.values[..]).ok()?)))
        .collect();
    let mut shear_beams: Vec<usize> = Vec::new();
    // DYNE deformations flexible in statics (element, mode)
    let mut dyne_flexible: BTreeSet<(u32, u32)> = BTreeSet::new();
    for (e, entry) in m.elements.iter().zip(spec.elements.iter_mut()) {
        let n = e.number;
        debug_assert_eq!(entry.name, n.to_string());
        let estiff = last(&by.estiff, n);
        let em = last(&by.em, n);
        let col = |v: &Option<(Vec<f64>, usize)>, k: usize| {
            v.as_ref()
                .and_then(|(v, _)| v.get(k).copied())
                .unwrap_or(0.0)
        };
        // stiffness of each flexmbd mode
        let stiff: Vec<f64> = match &e.kind {
            ElementKind::Beam { .. } | ElementKind::BeamW { .. } => {
                for (kw, v) in [("ESTIFF", &estiff), ("EM", &em)] {
                    if let Some((vals, line)) = v {
                        if let Some(bad) = vals.iter().find(|x| **x < 0.0) {
                            return Err(err(
                                *line,
                                format!(
                                    "{kw} {n}: the constants of a beam must be ≥ 0, found {}",
                                    fmt_num(*bad)
                                ),
                            ));
                        }
                    }
                }
                if estiff.is_some() || em.is_some() {
                    let p = BeamProps {
                        ea: col(&estiff, 0),
                        gj: col(&estiff, 1),
                        eiy: col(&estiff, 2),
                        eiz: col(&estiff, 3),
                        shear: [col(&estiff, 4), col(&estiff, 5)],
                        ct: 0.0,
                        rho_a: col(&em, 0),
                        rho_i: [col(&em, 1), col(&em, 2), col(&em, 3)],
                        ..Default::default()
                    };
                    if p.shear != [0.0; 2] {
                        shear_beams.push(estiff.as_ref().map_or(e.line, |v| v.1));
                        entry.comments.push(format!(
                            "shear flexibilities ShearY={} ShearZ={} are used by `flexmbd static` on the .dat file; this format cannot express them (the beam below is shear-rigid)",
                            fmt_num(p.shear[0]),
                            fmt_num(p.shear[1])
                        ));
                    }
                    if p.rho_i != [0.0; 3] && purpose == Purpose::Document {
                        entry.comments.push(
                            "rotary inertias (EM columns 2-4) are not written: they matter for dynamics only".into(),
                        );
                    }
                    if let Kind::Beam(b) = &mut entry.kind {
                        let some = |v: f64| Some(v).filter(|v| *v != 0.0);
                        (b.ea, b.gj, b.eiy, b.eiz) =
                            (Some(p.ea), Some(p.gj), Some(p.eiy), Some(p.eiz));
                        b.rho_a = some(p.rho_a);
                        b.shear = Some(p.shear).filter(|v| *v != [0.0; 2]);
                        b.rho_i = Some(p.rho_i).filter(|v| *v != [0.0; 3]);
                    }
                }
                let (ea, gj, eiy, eiz) = (
                    col(&estiff, 0),
                    col(&estiff, 1),
                    col(&estiff, 2),
                    col(&estiff, 3),
                );
                vec![ea, gj, eiy, eiy, eiz, eiz]
            }
            ElementKind::Truss { xp, xq } => {
                lumped_mass(&mut spec.masses, n, &em, &x_of, *xp, *xq);
                vec![col(&estiff, 0)]
            }
            ElementKind::RBeam { xp, xq, .. } => {
                lumped_mass(&mut spec.masses, n, &em, &x_of, *xp, *xq);
                vec![0.0; 3]
            }
            ElementKind::Hinge { .. } => {
                if let Some((v, line)) = &estiff {
                    if v.iter().skip(1).any(|x| *x != 0.0) {
                        warn(*line, format!("ESTIFF {n}: a flexmbd hinge has a spring on deformation 1 (the rotation about its axis) only; the stiffnesses {} of deformations 2-3 are ignored", fmt_values(&v[1..])));
                    }
                }
                vec![col(&estiff, 0), 0.0, 0.0]
            }
        };
        let (rlse, dyne, inpute) = (
            listed(&by.rlse, n),
            listed(&by.dyne, n),
            listed(&by.inpute, n),
        );
        let mut flexible_dyne = Vec::new();
        let mut held_dyne = Vec::new();
        let mut free_dyne = Vec::new();
        let mut kept_rigid = Vec::new();
        for (k, &s) in stiff.iter().enumerate() {
            let mode = k as u32 + 1;
            if dyne.contains(&mode) {
                if s > 0.0 {
                    entry.input.retain(|&i| i != i64::from(mode));
                    flexible_dyne.push(mode);
                    dyne_flexible.insert((n, mode));
                } else if purpose == Purpose::Dynamic {
                    // a degree of freedom without stiffness (a hinge that turns freely)
                    entry.input.retain(|&i| i != i64::from(mode));
                    entry.free.push(i64::from(mode));
                    free_dyne.push(mode);
                } else {
                    held_dyne.push(mode);
                }
            } else if !rlse.contains(&mode) && !inpute.contains(&mode) && s > 0.0 {
                kept_rigid.push(mode);
            }
        }
        if !held_dyne.is_empty() {
            let line = m
                .dyne
                .iter()
                .find(|l| l.element == n)
                .map_or(e.line, |l| l.line);
            warn(line, format!("DYNE {n}: deformation(s) {} have no stiffness (ESTIFF): in statics they are held at their reference value (SPACAR would have a degree of freedom without stiffness)", join(&held_dyne)));
        }
        if !kept_rigid.is_empty() {
            match &mut entry.kind {
                Kind::Beam(b) => {
                    b.fixed = kept_rigid.iter().map(|&k| i64::from(k)).collect();
                }
                Kind::Truss { ea } => *ea = 0.0,
                Kind::Hinge { k, .. } => *k = 0.0,
                Kind::Rigid => {}
            }
        }
        // the document's comments on the element's roles (an analysis does not write them)
        if purpose == Purpose::Document {
            let mut roles = Vec::new();
            if !flexible_dyne.is_empty() {
                roles.push(format!(
                    "flexible (DYNE with stiffness, not listed below): {}",
                    join(&flexible_dyne)
                ));
            }
            if !free_dyne.is_empty() {
                roles.push(format!(
                    "free (DYNE without stiffness, a degree of freedom of the time simulation): {}",
                    join(&free_dyne)
                ));
            }
            if !kept_rigid.is_empty() {
                roles.push(format!(
                    "rigid although ESTIFF gives stiffness (not listed in SPACAR){}: {}",
                    if matches!(entry.kind, Kind::Beam(_)) {
                        ""
                    } else {
                        ", so EA/k is not written"
                    },
                    join(&kept_rigid)
                ));
            }
            if !roles.is_empty() {
                entry
                    .comments
                    .push(format!("statics: {}", roles.join("; ")));
            }
            // the kinematic comment on DYNE lines no longer holds
            for c in &mut entry.comments {
                if c.starts_with("DYNE ") {
                    if let Some(p) = c.find(" -> ") {
                        c.truncate(p);
                        c.push_str(" -> not listed where the mode has stiffness (a row of the kinematic check like an input; flexible in statics), input otherwise");
                    }
                }
            }
        }
        if let Some((v, line)) = last(&by.esig, n) {
            if v.iter().any(|x| *x != 0.0) {
                if purpose == Purpose::Dynamic {
                    return Err(err(line, format!("ESIG {n}: pre-stress (initial stress resultants {}) is not modelled by flexmbd, and it changes the motion: remove the line, or apply the pre-load as a load", fmt_values(&v))));
                }
                warn(line, format!("ESIG {n}: pre-stress (initial stress resultants {}) is not applied by flexmbd statics; ignored", fmt_values(&v)));
            }
        }
    }
    if let Some(&line) = shear_beams.iter().min() {
        toml_warnings.push(Warning {
            line,
            message: format!("{} beam(s), the first here, have shear flexibilities (ESTIFF columns 5-6, ShearY ShearZ): the TOML format cannot express them, so the converted beams are shear-rigid (the values are kept as comments); `flexmbd static` on the .dat file uses them", shear_beams.len()),
        });
    }

    // --- point masses ---
    for v in &m.xm {
        if m.node_kinds.get(&v.node) == Some(&NodeKind::Translational) && v.values.len() == 1 {
            spec.masses.push(MassEntry {
                node: NodeMap::trans_name(v.node),
                m: v.values[0],
                comments: vec![format!(
                    "XM {} {} (line {})",
                    v.node,
                    fmt_num(v.values[0]),
                    v.line
                )],
                src: Src::line(v.line),
            });
        }
        // inertia tensors of rotational nodes: no static effect (the header lists them)
    }

    if purpose != Purpose::Dynamic {
        loads_and_inputs(
            m,
            &map,
            &x_of,
            &dyne_flexible,
            n_steps,
            &mut spec,
            &mut warnings,
        )?;
    }

    // --- DYNX: unknowns in statics, inputs of the check ---
    if let Some(first) = m.dynx.iter().map(|l| l.line).min() {
        toml_warnings.push(Warning {
            line: first,
            message: "DYNX coordinates (dynamic degrees of freedom) are written into [inputs], as the kinematic check needs them; `flexmbd static` on the TOML file therefore holds them at their reference, while `flexmbd static` on the .dat file solves for them".into(),
        });
    }

    // --- the time simulation, when it fits the static model ---
    let mut simulated = false;
    if let (Purpose::Document, Some(ts)) = (purpose, &m.timestep) {
        match super::dynamics::add_simulation(m, &mut spec) {
            Ok(()) => simulated = true,
            Err(why) => toml_warnings.push(Warning {
                line: ts.line,
                message: format!("the time simulation (TIMESTEP, ERROR, inertia tensors, loads and inputs as functions of time) is not written: {why}; `flexmbd simulate` on the .dat file maps it (docs/spacar-import.md §7)"),
            }),
        }
    }

    warnings.sort_by_key(|w| w.line);
    toml_warnings.sort_by_key(|w| w.line);
    let mut notes: Vec<&Warning> = warnings.iter().chain(&toml_warnings).collect();
    notes.sort_by_key(|w| w.line);
    spec.header = header(m, &map, Some(&notes), simulated);
    Ok(Conversion {
        spec,
        warnings,
        toml_warnings,
        map,
    })
}

/// The mass of a truss or RBEAM (`EM` M/L × length) as point masses, half at each end: the
/// exact static equivalent of the weight of a uniform bar.
fn lumped_mass(
    masses: &mut Vec<MassEntry>,
    n: u32,
    em: &Option<(Vec<f64>, usize)>,
    x_of: &BTreeMap<u32, [f64; 3]>,
    xp: u32,
    xq: u32,
) {
    let Some((v, line)) = em else { return };
    let Some(&ml) = v.first() else { return };
    let (Some(p), Some(q)) = (x_of.get(&xp), x_of.get(&xq)) else {
        return;
    };
    if ml == 0.0 {
        return;
    }
    let l0 = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)).sqrt();
    let half = 0.5 * ml * l0;
    for node in [xp, xq] {
        masses.push(MassEntry {
            node: NodeMap::trans_name(node),
            m: half,
            comments: vec![format!(
                "EM {n} (line {line}): M/L = {} over the length {}, half at each end",
                fmt_num(ml),
                fmt_num(l0)
            )],
            src: Src::line(*line),
        });
    }
}

/// The loads and prescribed values of `flexmbd static`: final SPACAR values (initial +
/// increments), with the load-path warnings.
fn loads_and_inputs(
    m: &SpacarModel,
    map: &NodeMap,
    x_of: &BTreeMap<u32, [f64; 3]>,
    dyne_flexible: &BTreeSet<(u32, u32)>,
    n_steps: usize,
    spec: &mut ModelSpec,
    warnings: &mut Vec<Warning>,
) -> Result<(), InputError> {
    let err = |line: usize, msg: String| at_line(&m.file, line, 1, msg);
    let mut warn = |line: usize, message: String| warnings.push(Warning { line, message });
    // --- loads ---
    let mut loads: Vec<(u32, LoadEntry)> = Vec::new();
    let mut initial_loads = Vec::new();
    for (kw, list) in [("XF", &m.xf), ("DELXF", &m.delxf)] {
        for v in list {
            let Some(name) = map.name(m, v.node) else {
                continue; // warping node: rejected by parse_dat
            };
            let kind = m.node_kinds.get(&v.node).copied();
            let (force, moment, what) = match (kind, v.values.len()) {
                (Some(NodeKind::Rotational), 4) => {
                    if v.values[0] != 0.0 {
                        warn(v.line, format!("{kw} {}: the generalised force {} on λ0 (pre-2017 convention) is dropped: it does no work at the reference orientation", v.node, fmt_num(v.values[0])));
                    }
                    let mm = [v.values[1] / 2.0, v.values[2] / 2.0, v.values[3] / 2.0];
                    (
                        [0.0; 3],
                        mm,
                        format!(
                            "moment {} (pre-2017 generalised forces / 2)",
                            fmt_values(&mm)
                        ),
                    )
                }
                (Some(NodeKind::Rotational), 3) => {
                    let mm = [v.values[0], v.values[1], v.values[2]];
                    ([0.0; 3], mm, "moment".to_string())
                }
                (_, 3) => {
                    let f = [v.values[0], v.values[1], v.values[2]];
                    (f, [0.0; 3], "force".to_string())
                }
                _ => continue, // rejected by parse_dat
            };
            if kw == "XF" && v.values.iter().any(|x| *x != 0.0) {
                initial_loads.push(v.line);
            }
            let text = format!(
                "{kw} {} {} (line {}): {what}, {}",
                v.node,
                fmt_values(&v.values),
                v.line,
                if kw == "XF" {
                    "initial load (SPACAR: in full from the first step)"
                } else {
                    "load increment (ramped over the steps)"
                }
            );
            match loads.iter_mut().find(|(n, _)| *n == v.node) {
                Some((_, l)) => {
                    for k in 0..3 {
                        l.force[k] += force[k];
                        l.moment[k] += moment[k];
                    }
                    l.comments.push(text);
                }
                None => loads.push((
                    v.node,
                    LoadEntry {
                        node: name,
                        force,
                        moment,
                        history: None,
                        comments: vec![text],
                        src: Src::line(v.line),
                    },
                )),
            }
        }
    }
    if n_steps > 1 {
        for line in initial_loads {
            warn(line, format!("XF is an initial load, which SPACAR applies in full in the first load step before ramping DELXF; flexmbd ramps XF + DELXF together from zero over the {n_steps} steps: the load path differs, the final state is the same for a conservative problem"));
        }
    }
    spec.loads = loads.into_iter().map(|(_, l)| l).collect();

    for (kw, list) in [("INPUTX", &m.inputx_values), ("DELINPX", &m.delinpx)] {
        for v in list.iter().filter(|v| v.rates != [0.0; 2]) {
            warn(v.line, format!("{kw} {} {}: the velocity and acceleration ({}) are data of a time simulation (`flexmbd simulate`); statics uses the position value only", v.node, v.coord, fmt_values(&v.rates)));
        }
    }

    // --- prescribed coordinates ---
    let mut coord_kind: BTreeMap<(u32, u32), &str> = BTreeMap::new();
    for (kw, lists) in [("INPUTX", &m.inputx), ("DYNX", &m.dynx)] {
        for l in lists {
            let all: &[u32] = match m.node_kinds.get(&l.node) {
                Some(NodeKind::Rotational) => &[2, 3, 4],
                _ => &[1, 2, 3],
            };
            for &c in l.coords.as_deref().unwrap_or(all) {
                coord_kind.insert((l.node, c), kw);
            }
        }
    }
    let mut ramps: BTreeMap<(u32, u32), Ramp> = BTreeMap::new();
    for v in &m.inputx_values {
        ramps.entry((v.node, v.coord)).or_default().initial = Some((v.value, v.line));
    }
    for v in &m.delinpx {
        ramps
            .entry((v.node, v.coord))
            .or_default()
            .increments
            .push((v.value, v.line));
    }
    let mut rot_inputs: BTreeMap<u32, Vec<(u32, usize)>> = BTreeMap::new();
    for (&(node, c), r) in &ramps {
        let line = r.first_line();
        let text = r.describe("INPUTX", "DELINPX", &format!("{node} {c}"));
        if coord_kind.get(&(node, c)) == Some(&"DYNX") {
            warn(line, format!("INPUTX/DELINPX {node} {c}: the coordinate is a dynamic degree of freedom (DYNX), an unknown of the equilibrium; its value is ignored by flexmbd statics"));
            continue;
        }
        let Some(kind) = m.node_kinds.get(&node).copied() else {
            continue;
        };
        let (name, dof, value, initial_moves, what) = match kind {
            NodeKind::Translational => {
                let Some(x0) = x_of.get(&node).map(|x| x[c as usize - 1]) else {
                    continue;
                };
                let fin = r.initial.map_or(x0, |i| i.0) + r.increment();
                let d = fin - x0;
                (
                    NodeMap::trans_name(node),
                    Dof::ALL[c as usize - 1],
                    d,
                    r.initial.is_some_and(|i| i.0 != x0),
                    format!(
                        "coordinate {} -> {} (reference {}): displacement {}",
                        ["x", "y", "z"][c as usize - 1],
                        fmt_num(fin),
                        fmt_num(x0),
                        fmt_num(d)
                    ),
                )
            }
            NodeKind::Rotational => {
                // validated: coordinates 2-4 (λ1..λ3)
                if !(2..=4).contains(&c) {
                    continue;
                }
                let lam = r.initial.map_or(0.0, |i| i.0) + r.increment();
                if !(-1.0..=1.0).contains(&lam) {
                    return Err(err(line, format!("INPUTX/DELINPX {node} {c}: the final Euler parameter λ{} = {} is outside [−1, 1]", c - 1, fmt_num(lam))));
                }
                let phi = 2.0 * lam.asin();
                if lam != 0.0 {
                    rot_inputs.entry(node).or_default().push((c, line));
                }
                (
                    map.rot_name(node),
                    Dof::ALL[c as usize + 1],
                    phi,
                    r.initial.is_some_and(|i| i.0 != 0.0),
                    format!(
                        "Euler parameter λ{} -> {}: rotation φ = 2 asin(λ) = {} rad",
                        c - 1,
                        fmt_num(lam),
                        fmt_num(phi)
                    ),
                )
            }
            NodeKind::Warping => continue,
        };
        if initial_moves && n_steps > 1 {
            warn(line, format!("INPUTX {node} {c}: an initial value, which SPACAR applies in full in the first load step before ramping DELINPX; flexmbd ramps the whole motion from the reference over the {n_steps} steps: the path differs, the final state is the same for a conservative problem"));
        }
        if value != 0.0 {
            spec.prescribed.push(PrescribeEntry {
                target: PrescribeTarget::Coordinate { node: name, dof },
                value,
                history: None,
                comments: vec![format!("{text}: {what}")],
                src: Src::line(line),
            });
        }
    }
    for (node, cs) in &rot_inputs {
        if cs.len() > 1 {
            let names: Vec<String> = cs.iter().map(|(c, _)| format!("λ{}", c - 1)).collect();
            return Err(err(
                cs[1].1,
                format!("INPUTX/DELINPX {node}: several rotational inputs on one node are not supported ({} are prescribed; flexmbd prescribes a rotation about one axis per node)", names.join(", ")),
            ));
        }
    }

    // --- prescribed deformations ---
    let mut ramps: BTreeMap<(u32, u32), Ramp> = BTreeMap::new();
    for v in &m.inpute_values {
        ramps.entry((v.element, v.mode)).or_default().initial = Some((v.value, v.line));
    }
    for v in &m.delinpe {
        ramps
            .entry((v.element, v.mode))
            .or_default()
            .increments
            .push((v.value, v.line));
    }
    for (&(el, mode), r) in &ramps {
        let line = r.first_line();
        if dyne_flexible.contains(&(el, mode)) {
            warn(line, format!("INPUTE/DELINPE {el} {mode}: the deformation is a dynamic degree of freedom (DYNE) with stiffness, an unknown of the equilibrium; its value is ignored by flexmbd statics"));
            continue;
        }
        if mode > 6 {
            warn(
                line,
                format!(
                    "INPUTE/DELINPE {el} {mode}: warping deformations are not modelled; ignored"
                ),
            );
            continue;
        }
        let value = r.initial.map_or(0.0, |i| i.0) + r.increment();
        if r.initial.is_some_and(|i| i.0 != 0.0) && n_steps > 1 {
            warn(line, format!("INPUTE {el} {mode}: an initial value, which SPACAR applies in full in the first load step before ramping DELINPE; flexmbd ramps the whole value from zero over the {n_steps} steps: the path differs, the final state is the same for a conservative problem"));
        }
        if value != 0.0 {
            spec.prescribed.push(PrescribeEntry {
                target: PrescribeTarget::Deformation {
                    element: el.to_string(),
                    mode: mode as usize,
                },
                value,
                comments: vec![format!(
                    "{}: deformation {mode} of element {el} -> {}",
                    r.describe("INPUTE", "DELINPE", &format!("{el} {mode}")),
                    fmt_num(value)
                )],
                history: None,
                src: Src::line(line),
            });
        }
    }
    Ok(())
}

fn join(v: &[u32]) -> String {
    v.iter().map(u32::to_string).collect::<Vec<_>>().join(" ")
}
