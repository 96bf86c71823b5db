//! One variant: the member of the family, then the study's analyses through the library API
//! (the same calls as `flexmbd check`, `static` and `modes`), then its figures of merit.

use crate::record::{Failure, Record, Status};
use crate::spec::{support_dir, support_merit, Study};
use crate::Variant;
use flexmbd_core::dynamics::{modes_with, ModalOptions, ModeClass};
use flexmbd_core::kinematics::classify::{classify, ClassifyOptions};
use flexmbd_core::kinematics::CheckOptions;
use flexmbd_core::linearized::{analyse, at_step, LinearRequest};
use flexmbd_core::statics::{StaticAnalysis, StepResult};
use flexmbd_core::Model;
use flexmbd_io::error::InputError;
use flexmbd_io::ModelFile;

/// Build the member of the family with the variant's parameter values: each value replaces a
/// parameter of the model's `[parameters]` table, or, for a name with a dot, the value at that
/// path of the model document (`sections.sheet.t`).
pub fn member(study: &Study, values: &[f64]) -> Result<ModelFile, flexmbd_io::error::InputError> {
    let set: Vec<(String, f64)> = study
        .parameters
        .iter()
        .zip(values)
        .map(|(p, &v)| (p.name.clone(), v))
        .collect();
    let spec = flexmbd_io::model_toml::parse_spec_with(&study.model_text, &study.model_file, &set)?;
    spec.build_file()
        .map_err(|e| flexmbd_io::model_toml::spec_error(e, &study.model_file))
}

/// Check that every parameter of the study is a parameter of the model or a path to a number
/// in its document; returns the index of the first one that is not, with the reason. The
/// model file itself must read (its errors are returned as they are).
pub fn check_parameters(study: &Study) -> Result<Result<(), (usize, String)>, InputError> {
    let spec = flexmbd_io::model_toml::parse_spec_with(&study.model_text, &study.model_file, &[])?;
    for (i, p) in study.parameters.iter().enumerate() {
        let name = p.name.as_str();
        if name.contains('.') {
            match spec.get(name) {
                Ok(v) if v.is_number() => {}
                Ok(v) => {
                    return Ok(Err((
                        i,
                        format!(
                        "parameter `{name}`: the model's value at this path is {v}, not a number"
                    ),
                    )))
                }
                Err(e) => return Ok(Err((i, format!("parameter `{name}`: {e}")))),
            }
        } else if !spec.parameters.contains_key(name) {
            let declared: Vec<&str> = spec.parameters.keys().map(String::as_str).collect();
            return Ok(Err((
                i,
                format!(
                    "parameter `{name}` is not declared in the model's [parameters] ({}); a path into the model document has dots (`sections.sheet.t`)",
                    if declared.is_empty() { "it has none".to_string() } else { format!("it has {}", declared.join(", ")) }
                ),
            )));
        }
    }
    Ok(Ok(()))
}

/// Evaluate one variant. Never panics and never fails: a failure is a record with its stage
/// and message.
pub fn evaluate(study: &Study, v: &Variant) -> Record {
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let mut r = Record::empty(study, v);
        let out = evaluate_into(study, v, &mut r);
        (r, out)
    }));
    // after a defect, none of the variant's values are trusted: an empty record
    let (mut r, outcome) = run.unwrap_or_else(|p| {
        let failure = Failure::new(
            "internal",
            format!(
                "flexmbd failed on this variant ({}); please report it with the study file",
                panic_text(&p)
            ),
        );
        (Record::empty(study, v), Err(failure))
    });
    if let Err(f) = outcome {
        r.status = Status::Failed;
        r.error = Some(f);
    }
    r
}

fn panic_text(p: &Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".into())
}

fn evaluate_into(study: &Study, v: &Variant, r: &mut Record) -> Result<(), Failure> {
    let file = member(study, &v.values).map_err(|e| Failure::new("model", e))?;
    let model = &file.model;
    let a = &study.analyses;
    if a.check {
        let c = classify(
            model,
            &ClassifyOptions {
                check: CheckOptions::default(),
                auto: false,
                max_suggestions: 0,
            },
        )
        .map_err(|e| Failure::new("check", e))?;
        let k = &c.analysis;
        r.table1 = Some(k.case.describe().to_string());
        r.set("table1_row", k.case.row() as f64);
        r.set("rank", k.rank as f64);
        r.set("motions", (k.n() - k.rank) as f64);
        r.set("self_stresses", (k.m() - k.rank) as f64);
    }
    if a.modes.is_none() && !a.stroke {
        return Ok(());
    }
    let opts = flexmbd_io::requests::static_options(&file.settings, None, None)
        .map_err(|e| Failure::new("stroke", e.0))?;
    let mut request = LinearRequest::default();
    let mut support = Vec::new();
    if a.stroke {
        for s in &a.support {
            let (node, dir) = support_dir(s).map_err(|m| Failure::new("stroke", m))?;
            let id = model.node_id(&node).ok_or_else(|| {
                Failure::new(
                    "stroke",
                    format!("support `{s}`: node `{node}` is not in the model"),
                )
            })?;
            // one compliance per node, however many of its directions are asked for
            let slot = match request.compliance.iter().position(|&c| c == id) {
                Some(slot) => slot,
                None => {
                    request.compliance.push(id);
                    request.compliance.len() - 1
                }
            };
            support.push((support_merit(s), slot, dir));
        }
        request.buckling = usize::from(a.buckling);
    }
    // The buckling margin needs every loaded state linearised; the support stiffness only the
    // first and the last (the figures of merit are k_start and k_end): then the path is solved
    // alone and linearised at its two ends.
    let ends_only = request.buckling == 0;
    let along = if ends_only {
        LinearRequest::default()
    } else {
        request.clone()
    };
    let (mut analysis, stopped) = match analyse(model, &opts, &along, |_, _| {}) {
        Ok(an) => (an, None),
        Err(s) => {
            let message = format!("{s}: {}", s.error);
            (s.analysis, Some(message))
        }
    };
    if ends_only && !request.is_empty() {
        let steps = &analysis.solution.steps;
        let n = steps.len();
        for i in [0, n.saturating_sub(1)] {
            if let (Some(st), Some(slot)) = (steps.get(i), analysis.linear.get_mut(i)) {
                if slot.compliance.is_empty() {
                    *slot = at_step(model, st, &request);
                }
            }
        }
    }
    if a.stroke {
        stroke_merits(model, &analysis, &support, r);
    }
    if let Some(m) = stopped {
        return Err(Failure::new(if a.stroke { "stroke" } else { "modes" }, m));
    }
    if let Some(count) = a.modes {
        let Some(step) = analysis.solution.steps.last() else {
            return Err(Failure::new("modes", "no static state to linearise about"));
        };
        modes_merits(model, step, count, r)?;
    }
    Ok(())
}

/// The figures of merit of the static path: the load factor reached, the support stiffness at
/// the first and the last state and its drop 1 − k_end/k_start, the largest normal stress and
/// the largest actuation force (a prescribed input's reaction) over the path, and the buckling
/// margin (the smallest buckling load multiplier over the loaded states).
fn stroke_merits(
    model: &Model,
    an: &StaticAnalysis,
    support: &[(String, usize, usize)],
    r: &mut Record,
) {
    let steps = &an.solution.steps;
    let Some(last) = steps.last() else {
        return;
    };
    r.set("stroke_reached", last.load_factor);
    for (name, slot, dir) in support {
        let k_at = |i: usize| -> f64 {
            an.linear
                .get(i)
                .and_then(|l| l.compliance.get(*slot))
                .map_or(f64::NAN, |(_, c)| {
                    if c.held[*dir] {
                        f64::NAN
                    } else {
                        c.stiffness_global()[*dir]
                    }
                })
        };
        let (k0, k1) = (k_at(0), k_at(steps.len() - 1));
        r.set(&format!("{name}_start"), k0);
        r.set(&format!("{name}_end"), k1);
        r.set(&format!("{name}_drop"), 1.0 - k1 / k0);
    }
    let max_stress = steps
        .iter()
        .flat_map(|st| flexmbd_core::results::element_results(model, st))
        .filter_map(|e| e.max_stress)
        .fold(f64::NAN, f64::max);
    r.set("max_stress", max_stress);
    let force = steps
        .iter()
        .flat_map(|st| {
            model.loads.prescribed.iter().map(move |p| {
                flexmbd_core::results::target_reaction(model, st, p.target)
                    .0
                    .abs()
            })
        })
        .fold(f64::NAN, f64::max);
    r.set("max_actuation_force", force);
    let margin = an
        .linear
        .iter()
        .filter_map(|l| l.buckling.as_ref())
        .flat_map(|b| b.multipliers.iter().copied())
        .filter(|m| *m > 0.0)
        .fold(f64::NAN, f64::min);
    r.set("buckling_margin", margin);
}

/// The modal figures of merit at the last static state.
fn modes_merits(
    model: &Model,
    step: &StepResult,
    count: usize,
    r: &mut Record,
) -> Result<(), Failure> {
    let modal = modes_with(model, step, count, &ModalOptions::default())
        .map_err(|e| Failure::new("modes", e))?;
    r.frequencies = modal
        .modes
        .iter()
        .map(|m| m.frequency.is_finite().then_some(m.frequency))
        .collect();
    r.classes = modal
        .modes
        .iter()
        .map(|m| m.class.name().to_string())
        .collect();
    let first = |c: Option<ModeClass>| {
        modal
            .modes
            .iter()
            .find(|m| c.map_or(!m.rigid_body, |c| m.class == c))
            .map_or(f64::NAN, |m| m.frequency)
    };
    let f_int = first(Some(ModeClass::Intended));
    r.set("f1", first(None));
    r.set("f_intended", f_int);
    r.set("f_support", first(Some(ModeClass::Support)));
    r.set("f_internal", first(Some(ModeClass::Internal)));
    r.set("support_ratio", first(Some(ModeClass::Support)) / f_int);
    r.set("internal_ratio", first(Some(ModeClass::Internal)) / f_int);
    Ok(())
}
