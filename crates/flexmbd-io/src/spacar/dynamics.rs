//! The time simulation of a SPACAR model (mode 1) for `flexmbd simulate`
//! (docs/spacar-import.md §7): the model of [`super::statics`] built for dynamics, plus the
//! settings (`TIMESTEP`, `ERROR`), the masses statics does not need (inertia tensors), and the
//! loads and prescribed inputs as functions of time.
//!
//! **Time dependence.** SPACAR's static section gives "initial" values (`XF`, `INPUTX n c v`),
//! applied in full from the first step, and increments (`DELXF`, `DELINPX`, `DELINPE`), spread
//! over the steps (spacar-format.md §6). In a time simulation the steps are those of `TIMESTEP
//! t_end n`, so an initial value holds from t = 0 and an increment grows linearly from 0 at
//! t = 0 to its value at t_end. `INPUTX n c x ẋ ẍ` may also give the input's velocity and
//! acceleration: the input moves as x + ẋ t (+ ½ ẍ t², which flexmbd's time functions cannot
//! express: an error).
//!
//! **What changes the motion is an error** (file:line): user routines (the loads or motions
//! they compute would be missing), element damping (`EDAMP`/`ED`: how SPACAR scales its constants
//! into the damping matrix is not documented), pre-stress (`ESIG`), initial values or rates of the dynamic
//! degrees of freedom other than the reference at rest (`STARTDE`, `STARTDX`, `INPUTX` values of
//! `DYNX` coordinates), an input that does not start at its reference, an input acceleration,
//! the product of inertia `EM` Jyz/L, and a flexible truss with mass (flexmbd's truss has no
//! consistent mass). What is mapped with an interpretation or an approximation is a warning.

use super::mapping::{fmt_num, fmt_values, NodeMap};
use super::statics::{self, Purpose};
use super::*;
use crate::error::{at_line, InputError};
use crate::limits::MAX_STEPS;
use crate::spec::{
    InertiaEntry, LoadEntry, ModelSpec, PrescribeEntry, PrescribeTarget, SimulateSpec, Src,
    StartSpec,
};
use flexmbd_core::model::Dof;
use flexmbd_core::simulation::{SimOptions, TimeFunction};
use std::collections::{BTreeMap, HashSet};

/// The model spec of a time simulation (with its `[simulate]` settings and the histories of
/// its loads and prescribed inputs) and what the mapping approximates.
pub(super) struct Dynamic {
    /// The spec (DYNX coordinates are unknowns: build it with `build_static`).
    pub spec: ModelSpec,
    /// Warnings, in line order.
    pub warnings: Vec<Warning>,
}

/// The dynamic degrees of freedom: `DYNE` (element, mode) and `DYNX` (node, coordinate), in
/// sets built once, so that the mapping stays linear in the size of the file.
struct Dofs {
    dyne: HashSet<(u32, u32)>,
    dynx: HashSet<(u32, u32)>,
}

impl Dofs {
    fn new(m: &SpacarModel) -> Self {
        let dyne = m
            .dyne
            .iter()
            .flat_map(|l| l.modes.iter().map(move |&k| (l.element, k)))
            .collect();
        let mut dynx = HashSet::new();
        for l in &m.dynx {
            let all: &[u32] = match m.node_kinds.get(&l.node) {
                Some(NodeKind::Rotational) => &[2, 3, 4],
                Some(NodeKind::Translational) => &[1, 2, 3],
                _ => &[],
            };
            for &c in l.coords.as_deref().unwrap_or(all) {
                dynx.insert((l.node, c));
            }
        }
        Self { dyne, dynx }
    }
}

/// Problems that stop the mapping; the one on the earliest line is reported.
#[derive(Default)]
struct Problems {
    fatal: Vec<(usize, String)>,
    warnings: Vec<Warning>,
}

impl Problems {
    fn fatal(&mut self, line: usize, message: String) {
        self.fatal.push((line, message));
    }
    fn warn(&mut self, line: usize, message: String) {
        self.warnings.push(Warning { line, message });
    }
}

/// The time simulation of `m`.
pub(super) fn convert(m: &SpacarModel) -> Result<Dynamic, InputError> {
    let c = statics::convert(m, Purpose::Dynamic)?;
    let map = c.map;
    let mut p = Problems {
        warnings: c.warnings,
        ..Default::default()
    };
    let mut spec = c.spec;
    // the loads and inputs of statics are replaced by the ones with histories
    spec.loads.clear();
    spec.prescribed.clear();

    for u in &m.user_routines {
        let what = match u.keyword.as_str() {
            "USERSIG" => "computes nodal loads and generalised stresses: without it the simulation would miss these loads",
            "USERINP" => "computes the motions of the INPUTX coordinates: without it the inputs would be held still",
            _ => "holds user data of unknown effect",
        };
        p.fatal(u.line, format!("{} {}: the MATLAB routine {what}, and flexmbd cannot run MATLAB routines; convert the model (`flexmbd convert`) and give the loads and motions as a `history` in the TOML file (docs/simulation.md)", u.keyword, u.name));
    }
    let mut settings = SimulateSpec {
        start: Some(StartSpec::Reference),
        ..Default::default()
    };
    let steps = timestep(m, &mut settings, &mut p);
    error_tolerances(m, &mut settings, &mut p);
    if let Some(it) = &m.iterstep {
        p.warn(it.line, format!("ITERSTEP {}: load-step settings of a static analysis, not used by the time simulation (its step size follows TIMESTEP and ERROR)", fmt_values(&it.values)));
    }
    let t_end = settings.t_end;
    let dofs = Dofs::new(m);
    masses(m, &map, &mut spec, &mut p);
    damping_and_start(m, &dofs, &mut p);
    loads(m, &map, t_end, &mut spec, &mut p);
    inputs(m, &map, &dofs, (t_end, steps), &mut spec, &mut p);
    spec.simulate = Some(settings);

    if let Some((line, message)) = p.fatal.into_iter().min_by_key(|f| f.0) {
        return Err(at_line(&m.file, line, 1, message));
    }
    p.warnings.sort_by_key(|w| w.line);
    Ok(Dynamic {
        spec,
        warnings: p.warnings,
    })
}

/// `TIMESTEP t_end n`: end time, first step and output interval t_end/n; returns n.
fn timestep(m: &SpacarModel, s: &mut SimulateSpec, p: &mut Problems) -> Option<usize> {
    let ts = m.timestep.as_ref()?;
    let v = &ts.values;
    let t_end = v[0];
    if !(t_end.is_finite() && t_end > 0.0) {
        p.fatal(
            ts.line,
            format!(
                "TIMESTEP: the end time (field 1) must be a positive number, found {}",
                fmt_num(t_end)
            ),
        );
        return None;
    }
    s.t_end = Some(t_end);
    let Some(&n) = v.get(1) else {
        p.warn(ts.line, format!("TIMESTEP {}: no number of steps (field 2); flexmbd's defaults are used (first step t_end/1000, output every t_end/100)", fmt_num(t_end)));
        return None;
    };
    if !(n >= 1.0 && n == n.trunc() && n <= MAX_STEPS as f64) {
        p.fatal(ts.line, format!("TIMESTEP: the number of steps (field 2) must be a whole number from 1 to {MAX_STEPS} (the limit, docs/reliability.md), found {}", fmt_num(n)));
        return None;
    }
    let h = t_end / n;
    s.dt = Some(h);
    s.output_step = Some(h);
    Some(n as usize)
}

/// `ERROR abs rel`: the tolerances of the step control.
fn error_tolerances(m: &SpacarModel, s: &mut SimulateSpec, p: &mut Problems) {
    let Some(e) = &m.error_tol else { return };
    let abs = e.values[0];
    let rel = match e.values.get(1) {
        Some(&r) => r,
        None => {
            let r = SimOptions::new(1.0).rtol;
            p.warn(e.line, format!("ERROR {}: one value, read as the absolute tolerance; the relative tolerance is flexmbd's default {}", fmt_num(abs), fmt_num(r)));
            r
        }
    };
    if !(abs.is_finite() && abs > 0.0 && rel.is_finite() && rel >= 0.0) {
        p.fatal(
            e.line,
            format!(
                "ERROR: the tolerances abs rel need abs > 0 and rel ≥ 0, found {} {}",
                fmt_num(abs),
                fmt_num(rel)
            ),
        );
        return;
    }
    s.tolerance = Some([abs, rel]);
}

/// Inertia tensors (`XM` on rotational nodes), and the element masses flexmbd cannot carry.
fn masses(m: &SpacarModel, map: &NodeMap, spec: &mut ModelSpec, p: &mut Problems) {
    for v in &m.xm {
        if m.node_kinds.get(&v.node) != Some(&NodeKind::Rotational) {
            continue; // point masses: in the static spec
        }
        if let Ok(i) = <[f64; 6]>::try_from(&v.values[..]) {
            spec.inertias.push(InertiaEntry {
                node: map.rot_name(v.node),
                i,
                comments: vec![format!(
                    "XM {} {} (line {})",
                    v.node,
                    fmt_values(&v.values),
                    v.line
                )],
                src: Src::line(v.line),
            });
        }
    }
    let by = ByElement::new(m);
    for e in &m.elements {
        let Some(em) = by.em.get(&e.number) else {
            continue;
        };
        match e.kind {
            ElementKind::Beam { .. } | ElementKind::BeamW { .. }
                if em.values.get(4).is_some_and(|j| *j != 0.0) =>
            {
                p.fatal(em.line, format!("EM {}: the product of inertia Jyz/L = {} (column 5) is not modelled (flexmbd's beam has the rotary inertias Jxx/L, Jyy/L, Jzz/L about its local axes), and it changes the motion", e.number, fmt_num(em.values[4])));
            }
            ElementKind::Truss { .. } => {
                let deforms = [&by.dyne, &by.rlse]
                    .iter()
                    .any(|of| of.contains_key(&e.number));
                if deforms && em.values.first().is_some_and(|v| *v != 0.0) {
                    p.fatal(em.line, format!("EM {}: a flexible truss with mass: SPACAR gives it a consistent mass, flexmbd's truss carries none (a lumped mass at its ends would change the motion); put the mass on the nodes with XM, or model the bar as a BEAM", e.number));
                }
            }
            _ => {}
        }
    }
}

/// Element damping and initial conditions: errors unless zero.
fn damping_and_start(m: &SpacarModel, dofs: &Dofs, p: &mut Problems) {
    for v in m
        .edamp
        .iter()
        .filter(|v| v.values.iter().any(|d| *d != 0.0))
    {
        p.fatal(v.line, format!("EDAMP {}: element damping ({}) cannot be mapped: how SPACAR turns these constants into its damping matrix is not documented; convert the model and give the element's material damping as a retardation time τ (`damping` on the element or its material) or Rayleigh damping (`rayleigh = [α, β]` in [simulate]) instead", v.element, fmt_values(&v.values)));
    }
    for v in &m.startde {
        if v.value != 0.0 || v.rate != 0.0 {
            p.fatal(v.line, format!("STARTDE {} {}: an initial deformation {} with rate {}: flexmbd starts a simulation from the reference configuration at rest (dynamic degrees of freedom zero, with zero rates)", v.number, v.index, fmt_num(v.value), fmt_num(v.rate)));
        }
    }
    let x_of: HashMap<u32, &Position> = m.positions.iter().map(|x| (x.node, x)).collect();
    for v in &m.startdx {
        let reference = match m.node_kinds.get(&v.number) {
            Some(NodeKind::Translational) => x_of
                .get(&v.number)
                .and_then(|x| x.values.get(v.index as usize - 1))
                .copied()
                .unwrap_or(0.0),
            _ => 0.0,
        };
        // the value as an absolute coordinate or as a displacement: both "at the reference"
        if (v.value != reference && v.value != 0.0) || v.rate != 0.0 {
            p.fatal(v.line, format!("STARTDX {} {}: an initial value {} with rate {}: flexmbd starts a simulation from the reference configuration at rest (coordinate {} of node {} at {}, rate zero)", v.number, v.index, fmt_num(v.value), fmt_num(v.rate), v.index, v.number, fmt_num(reference)));
        }
    }
    for v in &m.inpute_values {
        if dofs.dyne.contains(&(v.element, v.mode)) && v.value != 0.0 {
            p.fatal(v.line, format!("INPUTE {} {}: an initial value {} of a dynamic degree of freedom (DYNE): flexmbd starts a simulation from the reference configuration (deformation zero)", v.element, v.mode, fmt_num(v.value)));
        }
    }
}

/// Nodal loads, one per `XF`/`DELXF` line: `XF` constant from t = 0, `DELXF` growing linearly
/// from 0 at t = 0 to its value at t_end.
fn loads(
    m: &SpacarModel,
    map: &NodeMap,
    t_end: Option<f64>,
    spec: &mut ModelSpec,
    p: &mut Problems,
) {
    let mut ramped = Vec::new();
    for (kw, list) in [("XF", &m.xf), ("DELXF", &m.delxf)] {
        for v in list {
            let Some(name) = map.name(m, v.node) else {
                continue; // warping node: rejected by parse_dat
            };
            let (force, moment, what) = match (m.node_kinds.get(&v.node), v.values.len()) {
                (Some(NodeKind::Rotational), 4) => {
                    if v.values[0] != 0.0 {
                        p.warn(v.line, format!("{kw} {}: the generalised force {} on λ0 (pre-2017 convention) is dropped: it does no work at the reference orientation", v.node, fmt_num(v.values[0])));
                    }
                    let mm = [v.values[1] / 2.0, v.values[2] / 2.0, v.values[3] / 2.0];
                    ([0.0; 3], mm, "moment (pre-2017 generalised forces / 2)")
                }
                (Some(NodeKind::Rotational), 3) => {
                    ([0.0; 3], [v.values[0], v.values[1], v.values[2]], "moment")
                }
                (_, 3) => ([v.values[0], v.values[1], v.values[2]], [0.0; 3], "force"),
                _ => continue, // rejected by parse_dat
            };
            if force == [0.0; 3] && moment == [0.0; 3] {
                continue;
            }
            let history = if kw == "XF" {
                None
            } else {
                let Some(t) = t_end else {
                    if m.timestep.is_none() {
                        p.fatal(v.line, format!("DELXF {}: a load increment, spread over the time steps, needs the end time of TIMESTEP, which the file does not give (add a line `TIMESTEP t_end n` after HALT)", v.node));
                    } // else: TIMESTEP is wrong, an error at its line
                    continue;
                };
                ramped.push(v.line);
                Some(TimeFunction::Ramp { start: 0.0, end: t })
            };
            spec.loads.push(LoadEntry {
                node: name,
                force,
                moment,
                comments: vec![format!(
                    "{kw} {} {} (line {}): {what}",
                    v.node,
                    fmt_values(&v.values),
                    v.line
                )],
                history,
                src: Src::line(v.line),
            });
        }
    }
    if let (Some(&first), Some(t)) = (ramped.first(), t_end) {
        p.warn(first, format!("DELXF ({} line(s), the first here): a load increment is applied linearly from 0 at t = 0 to its value at t_end = {} (as SPACAR spreads increments over the steps; the time dependence of DELXF in a SPACAR time simulation is not documented)", ramped.len(), fmt_num(t)));
    }
}

/// The motion of one input: initial value (with velocity and acceleration) and increments.
#[derive(Default)]
struct Motion {
    /// Initial value, velocity, acceleration and line (`INPUTX`/`INPUTE` value; the last counts).
    initial: Option<(f64, [f64; 2], usize)>,
    /// Sum of the increments, and the first increment's line.
    increment: Option<(f64, usize)>,
}

impl Motion {
    fn line(&self) -> usize {
        let a = self.initial.map(|i| i.2);
        let b = self.increment.map(|i| i.1);
        a.into_iter().chain(b).min().unwrap_or(1)
    }
    /// The rate of the linear motion (velocity + increment / t_end); `Err` names what is
    /// missing.
    fn rate(&self, t_end: Option<f64>) -> Result<f64, &'static str> {
        let v0 = self.initial.map_or(0.0, |i| i.1[0]);
        match (self.increment, t_end) {
            (Some((d, _)), Some(t)) => Ok(v0 + d / t),
            (None, _) if v0 == 0.0 => Ok(0.0),
            _ => Err("needs the end time of TIMESTEP, which the file does not give (add a line `TIMESTEP t_end n` after HALT)"),
        }
    }
}

/// Prescribed coordinates and deformations with their histories.
fn inputs(
    m: &SpacarModel,
    map: &NodeMap,
    dofs: &Dofs,
    (t_end, steps): (Option<f64>, Option<usize>),
    spec: &mut ModelSpec,
    p: &mut Problems,
) {
    let mut coords: BTreeMap<(u32, u32), Motion> = BTreeMap::new();
    for v in &m.inputx_values {
        coords.entry((v.node, v.coord)).or_default().initial = Some((v.value, v.rates, v.line));
    }
    for v in &m.delinpx {
        if v.rates != [0.0; 2] {
            p.fatal(v.line, format!("DELINPX {} {}: increments of the velocity and acceleration ({}) have no known meaning in a time simulation", v.node, v.coord, fmt_values(&v.rates)));
        }
        let mo = coords.entry((v.node, v.coord)).or_default();
        let sum = mo.increment.map_or(0.0, |i| i.0) + v.value;
        mo.increment = Some((sum, mo.increment.map_or(v.line, |i| i.1)));
    }
    let x_of: HashMap<u32, &Position> = m.positions.iter().map(|x| (x.node, x)).collect();
    let mut moving_start: Vec<usize> = Vec::new();
    let mut rot_moving: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (&(node, c), mo) in &coords {
        let line = mo.line();
        let kind = m.node_kinds.get(&node).copied();
        let reference = match kind {
            Some(NodeKind::Translational) => x_of
                .get(&node)
                .and_then(|x| x.values.get(c as usize - 1))
                .copied()
                .unwrap_or(0.0),
            _ => 0.0,
        };
        let (x0, [v0, a0]) = mo.initial.map_or((reference, [0.0; 2]), |i| (i.0, i.1));
        if dofs.dynx.contains(&(node, c)) {
            // an initial condition of a dynamic degree of freedom
            if x0 != reference || v0 != 0.0 || a0 != 0.0 {
                p.fatal(line, format!("INPUTX {node} {c}: the coordinate is a dynamic degree of freedom (DYNX); an initial value {} with rate {} is not supported: flexmbd starts a simulation from the reference configuration ({}) at rest", fmt_num(x0), fmt_num(v0), fmt_num(reference)));
            }
            if let Some((_, l)) = mo.increment {
                p.warn(l, format!("DELINPX {node} {c}: the coordinate is a dynamic degree of freedom (DYNX), an unknown of the motion; the increment is ignored"));
            }
            continue;
        }
        if x0 != reference {
            p.fatal(line, format!("INPUTX {node} {c}: the input starts at {} but its reference is {}: flexmbd starts a simulation from the reference configuration; give the node its initial position in the X line (or convert the model and start from the static equilibrium)", fmt_num(x0), fmt_num(reference)));
            continue;
        }
        if a0 != 0.0 {
            p.fatal(line, format!("INPUTX {node} {c}: an input acceleration {} (x + ẋ t + ẍ t²/2) cannot be expressed by flexmbd's time functions (table, ramp, step, sine); convert the model and give the motion as a table", fmt_num(a0)));
            continue;
        }
        let rate = match mo.rate(t_end) {
            Ok(r) => r,
            Err(why) => {
                if m.timestep.is_none() {
                    p.fatal(
                        line,
                        format!("INPUTX/DELINPX {node} {c}: a moving input {why}"),
                    );
                }
                continue;
            }
        };
        let (Some(t), true) = (t_end, rate != 0.0) else {
            continue; // held at the reference
        };
        let (name, dof, value, history, what) = match kind {
            Some(NodeKind::Translational) => (
                NodeMap::trans_name(node),
                Dof::ALL[c as usize - 1],
                rate * t,
                linear(t),
                format!(
                    "coordinate {} moves at {} from its reference {}",
                    ["x", "y", "z"][c as usize - 1],
                    fmt_num(rate),
                    fmt_num(reference)
                ),
            ),
            Some(NodeKind::Rotational) if (2..=4).contains(&c) => {
                let lam = rate * t;
                if !(-1.0..=1.0).contains(&lam) {
                    p.fatal(line, format!("INPUTX/DELINPX {node} {c}: the Euler parameter λ{} reaches {} at t_end, outside [−1, 1]", c - 1, fmt_num(lam)));
                    continue;
                }
                rot_moving.entry(node).or_default().push(line);
                let angle = 2.0 * lam.asin();
                p.warn(line, format!("INPUTX/DELINPX {node} {c}: λ{} grows linearly to {}; flexmbd prescribes the angle 2 asin λ = {} rad at the end, piecewise linear between the output times (λ exact at them)", c - 1, fmt_num(lam), fmt_num(angle)));
                (
                    map.rot_name(node),
                    Dof::ALL[c as usize + 1],
                    angle,
                    euler_table(rate, t, steps.unwrap_or(100), angle),
                    format!("Euler parameter λ{} = {} t", c - 1, fmt_num(rate)),
                )
            }
            _ => continue, // validated: warping nodes have no input, λ0 is never an input
        };
        moving_start.push(line);
        spec.prescribed.push(PrescribeEntry {
            target: PrescribeTarget::Coordinate { node: name, dof },
            value,
            history: Some(history),
            comments: vec![format!("INPUTX/DELINPX {node} {c} (line {line}): {what}")],
            src: Src::line(line),
        });
    }
    for (node, lines) in &rot_moving {
        if lines.len() > 1 {
            p.fatal(lines[1], format!("INPUTX/DELINPX {node}: several moving rotational inputs on one node are not supported (flexmbd prescribes a rotation about one axis per node)"));
        }
    }
    // input deformations (not DYNE: their values are initial conditions, checked above)
    let mut defs: BTreeMap<(u32, u32), Motion> = BTreeMap::new();
    for v in &m.inpute_values {
        defs.entry((v.element, v.mode)).or_default().initial = Some((v.value, [0.0; 2], v.line));
    }
    for v in &m.delinpe {
        let mo = defs.entry((v.element, v.mode)).or_default();
        let sum = mo.increment.map_or(0.0, |i| i.0) + v.value;
        mo.increment = Some((sum, mo.increment.map_or(v.line, |i| i.1)));
    }
    for (&(el, mode), mo) in &defs {
        let line = mo.line();
        if dofs.dyne.contains(&(el, mode)) {
            if let Some((_, l)) = mo.increment {
                p.warn(l, format!("DELINPE {el} {mode}: the deformation is a dynamic degree of freedom (DYNE), an unknown of the motion; the increment is ignored"));
            }
            continue;
        }
        if mode > 6 {
            p.warn(
                line,
                format!(
                    "INPUTE/DELINPE {el} {mode}: warping deformations are not modelled; ignored"
                ),
            );
            continue;
        }
        let e0 = mo.initial.map_or(0.0, |i| i.0);
        if e0 != 0.0 {
            p.fatal(line, format!("INPUTE {el} {mode}: the input deformation starts at {}: flexmbd starts a simulation from the reference configuration (deformation zero)", fmt_num(e0)));
            continue;
        }
        let rate = match mo.rate(t_end) {
            Ok(r) => r,
            Err(why) => {
                if m.timestep.is_none() {
                    p.fatal(
                        line,
                        format!("INPUTE/DELINPE {el} {mode}: a moving input {why}"),
                    );
                }
                continue;
            }
        };
        let (Some(t), true) = (t_end, rate != 0.0) else {
            continue;
        };
        moving_start.push(line);
        spec.prescribed.push(PrescribeEntry {
            target: PrescribeTarget::Deformation {
                element: el.to_string(),
                mode: mode as usize,
            },
            value: rate * t,
            comments: vec![format!(
                "INPUTE/DELINPE {el} {mode} (line {line}): deformation {mode} grows at {}",
                fmt_num(rate)
            )],
            history: Some(linear(t)),
            src: Src::line(line),
        });
    }
    let has_dofs = !(m.dyne.is_empty() && m.dynx.is_empty() && m.rlse.is_empty());
    if let (Some(&first), true) = (moving_start.iter().min(), has_dofs) {
        p.warn(first, format!("{} input(s), the first here, move from t = 0 on: flexmbd starts the other coordinates with the smallest velocities consistent with the constraints, SPACAR with zero rates of the dynamic degrees of freedom (DYNE, DYNX, STARTDE); for a model with such degrees of freedom the first instants may differ", moving_start.len()));
    }
}

/// φ = t/T, linear through t = 0 (so that the input has its rate from the start), constant
/// after T.
fn linear(t: f64) -> TimeFunction {
    TimeFunction::Table(vec![[-t, -1.0], [t, 1.0]])
}

/// φ(t) = 2 asin(rate · t)/angle at the output times t_k = k T/n (k = −1 … n), so that
/// λ = sin(½ angle φ) = rate · t_k exactly there.
fn euler_table(rate: f64, t: f64, n: usize, angle: f64) -> TimeFunction {
    let h = t / n as f64;
    let points = (-1..=n as i64)
        .map(|k| {
            let tk = k as f64 * h;
            let lam = (rate * tk).clamp(-1.0, 1.0);
            [tk, 2.0 * lam.asin() / angle]
        })
        .collect();
    TimeFunction::Table(points)
}

/// The time simulation of `m` added to `spec`, its static spec for the converted file
/// ([`statics::Purpose::Document`]): `[simulate]`, the inertia tensors, the loads one per line
/// with their histories, and the histories of the prescribed inputs (scaled to the static
/// values). `Err` says why the time simulation does not fit the static model (then nothing is
/// added): a file can state one model for both.
pub(super) fn add_simulation(m: &SpacarModel, spec: &mut ModelSpec) -> Result<(), String> {
    let d = convert(m).map_err(|e| e.to_string())?.spec;
    if !spec.dynamic_inputs.is_empty() {
        return Err("the DYNX coordinates are [inputs] of the converted file (for the kinematic check) but unknowns of the motion".into());
    }
    for (a, b) in spec.elements.iter().zip(&d.elements) {
        if (&a.kind, &a.free, &a.input) != (&b.kind, &b.free, &b.input) {
            return Err(format!("element {}: its deformations have other roles in the time simulation (a DYNE mode without stiffness is held in statics, free in the motion)", a.name));
        }
        if a.beam().is_some_and(|s| s.rho_i.is_some()) {
            return Err(format!(
                "beam {}: its rotary inertias (EM columns 2-4) cannot be written in this format",
                a.name
            ));
        }
    }
    let masses = |s: &ModelSpec| -> Vec<(String, f64)> {
        s.masses.iter().map(|x| (x.node.clone(), x.m)).collect()
    };
    if masses(spec) != masses(&d) {
        return Err("the masses of the time simulation differ from those of statics".into());
    }
    // the loads, one per line in the simulation, add up to the static ones node by node
    let sums = |s: &ModelSpec| -> BTreeMap<String, [f64; 6]> {
        let mut by: BTreeMap<String, [f64; 6]> = BTreeMap::new();
        for l in &s.loads {
            let v = by.entry(l.node.clone()).or_default();
            for k in 0..3 {
                v[k] += l.force[k];
                v[k + 3] += l.moment[k];
            }
        }
        by.retain(|_, v| *v != [0.0; 6]);
        by
    };
    if sums(spec) != sums(&d) {
        return Err("the loads of the time simulation differ from those of statics".into());
    }
    if spec.prescribed.len() != d.prescribed.len() {
        return Err(
            "the inputs that move in the time simulation are not those statics prescribes".into(),
        );
    }
    let mut prescribed = Vec::with_capacity(d.prescribed.len());
    for p in &d.prescribed {
        let Some(q) = spec.prescribed.iter().find(|q| q.target == p.target) else {
            return Err("an input moves in the time simulation but has no static value".into());
        };
        let f = p.value / q.value;
        let history = match &p.history {
            _ if f == 1.0 => p.history.clone(),
            Some(TimeFunction::Table(points)) if f.is_finite() => Some(TimeFunction::Table(
                points.iter().map(|[t, phi]| [*t, phi * f]).collect(),
            )),
            _ => {
                return Err("a moving input's history cannot be scaled to its static value".into())
            }
        };
        let mut entry = q.clone();
        entry.history = history;
        entry
            .comments
            .extend(p.comments.iter().map(|c| format!("time simulation: {c}")));
        prescribed.push(entry);
    }
    spec.prescribed = prescribed;
    spec.loads = d.loads;
    spec.inertias = d.inertias;
    spec.simulate = d.simulate;
    Ok(())
}
