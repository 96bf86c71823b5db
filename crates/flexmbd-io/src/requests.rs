//! What a front end asks an analysis for, in the words of the command line and of scripts:
//! the static options over a model file's settings, and the named inputs and outputs of a
//! state-space model (`NODE:DIR[:KIND]`, `ELEMENT:MODE:KIND`). One parser for `flexmbd` and the
//! Python package; `flag` names the option or argument in messages (`--input`, `inputs`).

use crate::Settings;
use flexmbd_core::dynamics::state_space::{Input, Motion, Output, OutputKind, Probe};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::model::Dof;
use flexmbd_core::statics::{PathMethod, StaticOptions};
use flexmbd_core::Model;

/// A request that does not fit the model: the message names the option and the item.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct RequestError(pub String);

/// Static options from the file's settings, with the number of load steps and the path method
/// a front end asks for over them (as `flexmbd static` does).
pub fn static_options(
    settings: &Settings,
    steps: Option<usize>,
    path: Option<PathMethod>,
) -> Result<StaticOptions, RequestError> {
    use crate::limits::{MAX_ITERATIONS, MAX_STEPS};
    let mut opts = StaticOptions::default();
    opts.steps = steps.or(settings.steps).unwrap_or(opts.steps);
    if !(1..=MAX_STEPS).contains(&opts.steps) {
        return Err(RequestError(format!(
            "the number of load steps must be from 1 to {MAX_STEPS}, found {}",
            opts.steps
        )));
    }
    opts.max_iterations = settings.max_iterations.unwrap_or(opts.max_iterations);
    if !(1..=MAX_ITERATIONS).contains(&opts.max_iterations) {
        return Err(RequestError(format!(
            "the number of Newton iterations must be from 1 to {MAX_ITERATIONS}, found {}",
            opts.max_iterations
        )));
    }
    opts.tol_force = settings.tol_force.unwrap_or(opts.tol_force);
    opts.tol_disp = settings.tol_disp.unwrap_or(opts.tol_disp);
    opts.line_search = settings.line_search;
    opts.tangent_eigenvalues = settings.tangent_eigenvalues;
    opts.path = path.unwrap_or(settings.path);
    Ok(opts)
}

/// `NODE:DIR[:KIND]` → (node, direction, kind). Node names may contain `:` (segments), so the
/// spec is read from the right.
fn split_spec<'a>(
    flag: &str,
    spec: &'a str,
    kinds: &[&str],
) -> Result<(String, Dof, Option<&'a str>), RequestError> {
    let t: Vec<&str> = spec.split(':').collect();
    let n = t.len();
    let usage = || {
        RequestError(format!(
            "{flag} `{spec}`: expected NODE:DIR or NODE:DIR:KIND with DIR one of x, y, z, rx, ry, rz and KIND one of {}",
            kinds.join(", ")
        ))
    };
    if n < 2 || t.iter().any(|s| s.is_empty()) {
        return Err(usage());
    }
    let dof = |s: &str| Dof::parse(&s.to_ascii_lowercase());
    if let Some(d) = dof(t[n - 1]) {
        return Ok((t[..n - 1].join(":"), d, None));
    }
    if n >= 3 {
        if let Some(d) = dof(t[n - 2]) {
            return Ok((t[..n - 2].join(":"), d, Some(t[n - 1])));
        }
        if kinds.contains(&t[n - 1].to_ascii_lowercase().as_str()) {
            return Err(RequestError(format!(
                "{flag} `{spec}`: unknown direction `{}` (expected x, y, z, rx, ry or rz)",
                t[n - 2]
            )));
        }
    }
    Err(RequestError(format!(
        "{flag} `{spec}`: unknown direction `{}` (expected x, y, z, rx, ry or rz{})",
        t[n - 1],
        if n >= 3 {
            format!(", optionally followed by :{}", kinds.join("|"))
        } else {
            String::new()
        }
    )))
}

fn node_of(
    model: &Model,
    file: &str,
    flag: &str,
    spec: &str,
    name: &str,
) -> Result<usize, RequestError> {
    model.node_id(name).ok_or_else(|| {
        RequestError(format!(
            "{flag} `{spec}`: node `{name}` is not defined in {}",
            file
        ))
    })
}

fn needs_rotation(
    model: &Model,
    flag: &str,
    spec: &str,
    node: usize,
    dof: Dof,
) -> Result<(), RequestError> {
    if dof.is_rotation() && !model.nodes[node].rot() {
        return Err(RequestError(format!(
            "{flag} `{spec}`: node `{}` has no rotation coordinates (only nodes of beams, hinges, rigid bodies with rotation, or `rot = true` have them)",
            model.nodes[node].name
        )));
    }
    Ok(())
}

/// A parsed input (`--input` of `flexmbd statespace`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputSpec {
    /// Force or moment.
    Load(Input),
    /// Prescribed motion (acceleration input).
    Motion(Motion),
}

/// The force and moment inputs, then the prescribed motions, of parsed inputs (the column
/// order of B: loads first, then motions, each in the order given).
pub fn split_inputs(specs: &[InputSpec]) -> (Vec<Input>, Vec<Motion>) {
    let mut loads = Vec::new();
    let mut motions = Vec::new();
    for s in specs {
        match s {
            InputSpec::Load(i) => loads.push(*i),
            InputSpec::Motion(m) => motions.push(*m),
        }
    }
    (loads, motions)
}

/// The element named `name` and its 0-based deformation mode from the 1-based `mode` of the
/// spec (`flag_spec`: the flag and the spec, for the messages; `usage`: what the form means).
fn element_mode(
    model: &Model,
    file: &str,
    (flag, spec): (&str, &str),
    name: &str,
    mode: &str,
    usage: &str,
) -> Result<(usize, usize), RequestError> {
    let Some(element) = model.elements.iter().position(|e| e.name == name) else {
        return Err(RequestError(format!(
            "{flag} `{spec}`: element `{name}` is not defined in {} ({usage})",
            file
        )));
    };
    let entry = &model.elements[element];
    let ne = entry.element.ne() as i64;
    let m: i64 = mode.parse().unwrap_or(0);
    if m < 1 || m > ne {
        return Err(RequestError(format!(
            "{flag} `{spec}`: {} `{name}` has deformation modes 1 to {ne}, not {mode}",
            entry.element.type_name()
        )));
    }
    Ok((element, (m - 1) as usize))
}

/// `ELEMENT:MODE:motion` (MODE a 1-based deformation number) → a prescribed-deformation
/// motion; `None` when the spec has another form (a node input).
fn parse_deformation_motion(
    model: &Model,
    file: &str,
    flag: &str,
    spec: &str,
) -> Result<Option<Motion>, RequestError> {
    let t: Vec<&str> = spec.split(':').collect();
    let n = t.len();
    if n < 3 || !t[n - 1].eq_ignore_ascii_case("motion") || t[n - 2].parse::<i64>().is_err() {
        return Ok(None);
    }
    let name = t[..n - 2].join(":");
    let (element, mode) = element_mode(
        model,
        file,
        (flag, spec),
        &name,
        t[n - 2],
        "ELEMENT:MODE:motion drives deformation MODE of an element",
    )?;
    let entry = &model.elements[element];
    if model.partition.e[entry.ie + mode] == flexmbd_core::model::DefKind::Free {
        let mname = entry.element.mode_name(mode, &model.node_names());
        return Err(RequestError(format!(
            "{flag} `{spec}`: deformation {} ({mname}) of {} `{name}` is free (flexible) in {}; a prescribed-deformation motion needs an `input` mode (list it in the element's `input`, with a [[prescribe]] value where it is not zero)",
            mode + 1,
            entry.element.type_name(),
            file
        )));
    }
    Ok(Some(Motion::Deformation { element, mode }))
}

/// Parse an input `NODE:DIR[:force|moment|motion]` or `ELEMENT:MODE:motion`.
pub fn parse_input(
    model: &Model,
    file: &str,
    flag: &str,
    spec: &str,
) -> Result<InputSpec, RequestError> {
    if let Some(m) = parse_deformation_motion(model, file, flag, spec)? {
        return Ok(InputSpec::Motion(m));
    }
    let (name, dof, kind) = split_spec(flag, spec, &["force", "moment", "motion"])?;
    let node = node_of(model, file, flag, spec, &name)?;
    if kind.map(str::to_ascii_lowercase).as_deref() == Some("motion") {
        needs_rotation(model, flag, spec, node, dof)?;
        let held = model.nodes[node]
            .x_index(dof)
            .is_some_and(|i| model.partition.x[i] != flexmbd_core::model::CoordKind::Free);
        if !held {
            let load = if dof.is_rotation() { "moment" } else { "force" };
            return Err(RequestError(format!(
                "{flag} `{spec}`: coordinate {} of node `{name}` is free in {}; a prescribed motion needs a held coordinate (a support, [inputs] or [[prescribe]]). Hold it in the model, or use {name}:{}:{load} for a {load} input",
                dof.name(),
                file,
                dof.name()
            )));
        }
        return Ok(InputSpec::Motion(Motion::Node { node, dof }));
    }
    let dof = match kind.map(str::to_ascii_lowercase).as_deref() {
        None => dof,
        Some("force") if dof.is_rotation() => {
            return Err(RequestError(format!(
                "{flag} `{spec}`: a force acts along x, y or z; for a moment about {} write {name}:{} or {name}:{}:moment",
                &dof.name()[1..],
                dof.name(),
                &dof.name()[1..]
            )))
        }
        Some("force") => dof,
        Some("moment") if dof.is_rotation() => dof,
        Some("moment") => Dof::ALL[dof.index() + 3],
        Some(k) => {
            return Err(RequestError(format!(
                "{flag} `{spec}`: unknown input kind `{k}` (expected force, moment or motion)"
            )))
        }
    };
    needs_rotation(model, flag, spec, node, dof)?;
    Ok(InputSpec::Load(Input { node, dof }))
}

/// `ELEMENT:MODE:def|force[:disp|vel|acc]` → an element output; `None` when the spec has
/// another form (a node output).
fn parse_element_output(
    model: &Model,
    file: &str,
    flag: &str,
    spec: &str,
) -> Result<Option<Output>, RequestError> {
    let t: Vec<&str> = spec.split(':').collect();
    let n = t.len();
    let is_q = |s: &str| {
        let s = s.to_ascii_lowercase();
        matches!(s.as_str(), "def" | "deformation" | "force")
    };
    // the quantity is last, or second to last before a kind
    let (q, kind, name_end) = if n >= 3 && is_q(t[n - 1]) && t[n - 2].parse::<i64>().is_ok() {
        (t[n - 1], None, n - 2)
    } else if n >= 4 && is_q(t[n - 2]) && t[n - 3].parse::<i64>().is_ok() {
        (t[n - 2], Some(t[n - 1]), n - 3)
    } else {
        return Ok(None);
    };
    let name = t[..name_end].join(":");
    let kind = match kind.map(str::to_ascii_lowercase).as_deref() {
        None => OutputKind::Disp,
        Some(k) => OutputKind::parse(k).ok_or_else(|| {
            RequestError(format!(
                "{flag} `{spec}`: unknown output kind `{k}` (expected disp, vel or acc)"
            ))
        })?,
    };
    let (element, mode) = element_mode(
        model,
        file,
        (flag, spec),
        &name,
        t[name_end],
        "ELEMENT:MODE:def|force measures deformation MODE of an element or its stress resultant",
    )?;
    let entry = &model.elements[element];
    let probe = if q.eq_ignore_ascii_case("force") {
        // a held mode's force is its constraint reaction; a free mode needs a stiffness
        let free = model.partition.e[entry.ie + mode] == flexmbd_core::model::DefKind::Free;
        if free && entry.element.stiffness()[(mode, mode)] <= 0.0 {
            let mname = entry.element.mode_name(mode, &model.node_names());
            return Err(RequestError(format!(
                "{flag} `{spec}`: deformation {} ({mname}) of {} `{name}` has no stiffness in {}, so it has no elastic force; give the element a stiffness, or measure its deformation ({name}:{}:def)",
                mode + 1,
                entry.element.type_name(),
                file,
                mode + 1
            )));
        }
        Probe::Force { element, mode }
    } else {
        Probe::Deformation { element, mode }
    };
    Ok(Some(Output { probe, kind }))
}

/// Parse an output `NODE:DIR[:disp|vel|acc]` or `ELEMENT:MODE:def|force[:disp|vel|acc]`.
pub fn parse_output(
    model: &Model,
    file: &str,
    flag: &str,
    spec: &str,
) -> Result<Output, RequestError> {
    if let Some(o) = parse_element_output(model, file, flag, spec)? {
        return Ok(o);
    }
    let (name, dof, kind) = split_spec(flag, spec, &["disp", "vel", "acc", "reaction"])?;
    let node = node_of(model, file, flag, spec, &name)?;
    if kind.is_some_and(|k| k.eq_ignore_ascii_case("reaction")) {
        needs_rotation(model, flag, spec, node, dof)?;
        let held = model.nodes[node]
            .x_index(dof)
            .is_some_and(|i| model.partition.x[i] != flexmbd_core::model::CoordKind::Free);
        if !held {
            return Err(RequestError(format!(
                "{flag} `{spec}`: coordinate {} of node `{name}` is free in {}; a reaction needs a coordinate held by a support, [inputs] or [[prescribe]]",
                dof.name(),
                file
            )));
        }
        return Ok(Output {
            probe: Probe::Reaction { node, dof },
            kind: OutputKind::Disp,
        });
    }
    let kind = match kind.map(str::to_ascii_lowercase).as_deref() {
        None => OutputKind::Disp,
        Some("displacement" | "rotation") => OutputKind::Disp,
        Some("velocity") => OutputKind::Vel,
        Some("acceleration") => OutputKind::Acc,
        Some(k) => OutputKind::parse(k).ok_or_else(|| {
            RequestError(format!(
                "{flag} `{spec}`: unknown output kind `{k}` (expected disp, vel or acc)"
            ))
        })?,
    };
    needs_rotation(model, flag, spec, node, dof)?;
    Ok(Output::node(node, dof, kind))
}

/// Integrator options a front end gives over a model file's `[simulate]` settings (the
/// command line's `--t-end`, … and the Python keywords `t_end=`, …).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimOverrides {
    /// End time [s].
    pub t_end: Option<f64>,
    /// Step size [s] (first step with step control, or the fixed step).
    pub dt: Option<f64>,
    /// Fixed steps instead of step control.
    pub fixed_step: bool,
    /// ρ∞ in [0, 1].
    pub rho_inf: Option<f64>,
    /// Absolute and relative tolerance of the step control.
    pub tolerance: Option<[f64; 2]>,
    /// Output interval [s].
    pub output_step: Option<f64>,
}

impl SimOverrides {
    /// The integrator options: these over the file's settings. `spell` gives the front end's
    /// name of an option from its neutral name (`t_end`, `dt`, `rho_inf`, `tolerance`,
    /// `output_step`); `file` names the model in messages.
    pub fn options(
        &self,
        file: &str,
        settings: &crate::model_toml::simulate::SimulateSettings,
        spell: &dyn Fn(&str) -> String,
    ) -> Result<flexmbd_core::simulation::SimOptions, RequestError> {
        let positive = |name: &str, v: Option<f64>| match v {
            Some(v) if !(v.is_finite() && v > 0.0) => Err(RequestError(format!(
                "{} must be a positive number, found {v}",
                spell(name)
            ))),
            v => Ok(v),
        };
        let mut set = settings.clone();
        let t_end = positive("t_end", self.t_end)?;
        if let Some(v) = positive("dt", self.dt)? {
            set.dt = Some(v);
        }
        if self.fixed_step {
            set.fixed_step = Some(true);
        }
        if let Some(r) = self.rho_inf {
            if !(0.0..=1.0).contains(&r) {
                return Err(RequestError(format!(
                    "{} must lie in [0, 1], found {r}",
                    spell("rho_inf")
                )));
            }
            set.rho_inf = Some(r);
        }
        if let Some([a, r]) = self.tolerance {
            if !(a.is_finite() && a > 0.0 && r.is_finite() && r >= 0.0) {
                return Err(RequestError(format!(
                    "{} needs ABS > 0 and REL >= 0, found {a} {r}",
                    spell("tolerance")
                )));
            }
            set.tolerance = Some([a, r]);
        }
        if let Some(v) = positive("output_step", self.output_step)? {
            set.output_step = Some(v);
        }
        set.options(t_end).ok_or_else(|| {
            RequestError(format!(
                "{file}: no end time: give {}, or `t_end` in [simulate] (TOML) or TIMESTEP (SPACAR)",
                spell("t_end")
            ))
        })
    }
}
