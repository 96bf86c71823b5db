//! The results on the model: animations of motions and modes, fields (stresses, self-stresses,
//! strain energy) and the summary of the kinematic check.

use super::document::*;
use flexmbd_core::dynamics::Modal;
use flexmbd_core::elements::Element;
use flexmbd_core::kinematics::ConstraintAnalysis;
use flexmbd_core::model::Model;
use flexmbd_core::statics::StepResult;

/// Animations are scaled so that the largest nodal translation is this fraction of the model
/// size …
pub const ANIMATION_TRANSLATION: f64 = 0.1;
/// … or the largest nodal rotation is this angle [rad], whichever is reached first.
pub const ANIMATION_ROTATION: f64 = 0.35;

/// Most entries of a self-stress state listed in the panel.
pub(super) const MAX_STATE_ENTRIES: usize = 12;

/// Scale of an animation: the largest translation becomes [`ANIMATION_TRANSLATION`] × size or
/// the largest rotation [`ANIMATION_ROTATION`], whichever comes first (1 for a zero shape).
pub fn animation_scale(u: &[[f64; 3]], w: &[[f64; 3]], size: f64) -> f64 {
    let max = |v: &[[f64; 3]]| {
        v.iter()
            .map(|a| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt())
            .filter(|a| a.is_finite())
            .fold(0.0, f64::max)
    };
    let (mu, mw) = (max(u), max(w));
    let mut s = f64::INFINITY;
    if mu > 0.0 {
        s = s.min(ANIMATION_TRANSLATION * size / mu);
    }
    if mw > 0.0 {
        s = s.min(ANIMATION_ROTATION / mw);
    }
    if s.is_finite() {
        s
    } else {
        1.0
    }
}

pub(super) fn finite_or_zero(v: f64) -> f32 {
    if v.is_finite() {
        v as f32
    } else {
        0.0
    }
}

pub(super) fn flat(v: &[[f64; 3]]) -> Vec<f32> {
    v.iter().flat_map(|a| a.map(finite_or_zero)).collect()
}

/// `v` with `digits` significant digits (fixed notation from 1e-3 to 1e5).
pub fn significant(v: f64, digits: usize) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", digits.saturating_sub(1))
    }
}

/// A singular value that belongs to null vector `k` beyond the rank, with its text.
pub(super) fn null_singular_value(a: &ConstraintAnalysis, k: usize) -> (Option<f64>, String) {
    match a.singular_values.get(a.rank + k) {
        Some(&s) => (Some(s), format!("s = {s:.3e}")),
        None => (Some(0.0), "s = 0 (Dcc has fewer rows than columns)".into()),
    }
}

pub(super) fn motion_animations(
    model: &Model,
    a: &ConstraintAnalysis,
    size: f64,
) -> Vec<ViewAnimation> {
    let n = model.nodes.len();
    a.motions
        .iter()
        .enumerate()
        .map(|(k, motion)| {
            let mut u = vec![[0.0; 3]; n];
            let mut w = vec![[0.0; 3]; n];
            for c in &motion.coordinates {
                if let Some(id) = model.node_id(&c.node) {
                    let i = c.dof.index();
                    if i < 3 {
                        u[id][i] = c.value;
                    } else {
                        w[id][i - 3] = c.value;
                    }
                }
            }
            for (i, node) in model.nodes.iter().enumerate() {
                if let Some(h) = node.host {
                    u[i] = u[h];
                }
            }
            let (value, detail) = null_singular_value(a, k);
            ViewAnimation {
                kind: "motion".into(),
                label: format!("motion {}", k + 1),
                detail,
                value,
                class: None,
                frame: 0,
                scale: animation_scale(&u, &w, size),
                u: flat(&u),
                w: flat(&w),
            }
        })
        .collect()
}

pub(super) fn mode_animations(model: &Model, modal: &Modal, size: f64) -> Vec<ViewAnimation> {
    let n = model.nodes.len();
    modal
        .modes
        .iter()
        .enumerate()
        .map(|(k, mode)| {
            let (u, w): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (0..n)
                .map(|i| mode.nodal.get(i).copied().unwrap_or(([0.0; 3], [0.0; 3])))
                .unzip();
            let f = mode.frequency;
            let (value, detail) = if f.is_finite() {
                (Some(f), format!("{} Hz", significant(f, 4)))
            } else {
                (None, format!("unstable (ω² = {:.3e})", mode.eigenvalue))
            };
            ViewAnimation {
                kind: "mode".into(),
                label: format!("mode {}", k + 1),
                detail,
                value,
                class: Some(
                    crate::modes_report::class_text(mode)
                        .split_whitespace()
                        .collect::<Vec<_>>()
                        .join(" "),
                ),
                frame: 0,
                scale: animation_scale(&u, &w, size),
                u: flat(&u),
                w: flat(&w),
            }
        })
        .collect()
}

pub(super) fn range(values: &[Vec<Option<f32>>], diverging: bool) -> [f64; 2] {
    let all = values.iter().flatten().flatten().map(|&v| v as f64);
    if diverging {
        let m = all.map(f64::abs).fold(0.0, f64::max);
        if m > 0.0 {
            [-m, m]
        } else {
            [-1.0, 1.0]
        }
    } else {
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if !(lo.is_finite() && hi.is_finite()) {
            [0.0, 1.0]
        } else if hi > lo {
            [lo, hi]
        } else {
            [lo, lo + hi.abs().max(1.0)]
        }
    }
}

pub(super) fn field(
    key: &str,
    label: &str,
    unit: &str,
    diverging: bool,
    per: FieldPer,
    values: Vec<Vec<Option<f32>>>,
) -> ViewField {
    let range = range(&values, diverging);
    ViewField {
        key: key.into(),
        label: label.into(),
        unit: unit.into(),
        diverging,
        per,
        values,
        range,
    }
}

/// Per self-stress state: the signed entry of largest magnitude of every element (0 for an
/// element that carries none of it; rigid bodies included).
pub(super) fn self_stress_fields(model: &Model, a: &ConstraintAnalysis) -> Vec<ViewField> {
    a.self_stresses
        .iter()
        .enumerate()
        .map(|(k, state)| {
            let mut v = vec![0.0f64; model.elements.len()];
            for d in &state.deformations {
                if let Some(i) = model.elements.iter().position(|e| e.name == d.element) {
                    if d.value.abs() > v[i].abs() {
                        v[i] = d.value;
                    }
                }
            }
            field(
                &format!("self_stress_{}", k + 1),
                &format!("self-stress state {}", k + 1),
                "unit state",
                true,
                FieldPer::Model,
                vec![v.iter().map(|&x| Some(x as f32)).collect()],
            )
        })
        .collect()
}

/// Stress resultants per step: σ1 of trusses and beams, σ2…σ6 of beams, the hinge moment
/// and the largest normal stress of beams with a section. Fields that are zero everywhere are
/// left out.
pub(super) fn stress_fields(model: &Model, steps: &[&StepResult], per: FieldPer) -> Vec<ViewField> {
    let defs: [(&str, &str, &str, bool); 8] = [
        ("max_stress", "largest normal stress", "Pa", false),
        ("sigma1", "σ1 axial force", "N", true),
        ("sigma2", "σ2 torsion (torque / l0)", "N", true),
        ("sigma3", "σ3 bending about y at p (moment / l0)", "N", true),
        ("sigma4", "σ4 bending about y at q (moment / l0)", "N", true),
        ("sigma5", "σ5 bending about z at p (moment / l0)", "N", true),
        ("sigma6", "σ6 bending about z at q (moment / l0)", "N", true),
        ("hinge_moment", "hinge moment σ1", "N·m", true),
    ];
    let els_per_step: Vec<_> = steps
        .iter()
        .map(|s| crate::static_report::element_results(model, s))
        .collect();
    let mut out = Vec::new();
    for (key, label, unit, diverging) in defs {
        let values: Vec<Vec<Option<f32>>> = els_per_step
            .iter()
            .map(|els| {
                model
                    .elements
                    .iter()
                    .zip(els)
                    .map(|(entry, r)| {
                        let v = match (&entry.element, key) {
                            (Element::Beam(_), "max_stress") => r.max_stress,
                            (Element::Truss(_) | Element::Beam(_), "sigma1") => {
                                r.sigma.first().copied()
                            }
                            (Element::Beam(_), k) if k.starts_with("sigma") => k[5..]
                                .parse::<usize>()
                                .ok()
                                .and_then(|i| r.sigma.get(i - 1).copied()),
                            (Element::Hinge(_), "hinge_moment") => r.sigma.first().copied(),
                            _ => None,
                        };
                        v.filter(|v| v.is_finite()).map(|v| v as f32)
                    })
                    .collect()
            })
            .collect();
        if values.iter().flatten().flatten().any(|v| *v != 0.0) {
            out.push(field(key, label, unit, diverging, per, values));
        }
    }
    out
}

/// Per mode: the share of every element in the mode's strain energy [%].
pub(super) fn strain_energy_field(model: &Model, modal: &Modal) -> ViewField {
    let values = modal
        .modes
        .iter()
        .map(|mode| {
            let mut v: Vec<Option<f32>> = model
                .elements
                .iter()
                .map(|e| (!matches!(e.element, Element::Rigid(_))).then_some(0.0))
                .collect();
            for &(el, _, f) in &mode.strain {
                if let Some(Some(x)) = v.get_mut(el) {
                    *x += (100.0 * f) as f32;
                }
            }
            v
        })
        .collect();
    let mut f = field(
        "strain_energy",
        "share of the mode's strain energy",
        "%",
        false,
        FieldPer::Animation,
        values,
    );
    f.range = [0.0, f.range[1].max(1e-3)];
    f
}

pub(super) fn summary(c: &Classification<'_>) -> ViewSummary {
    let a = c.analysis;
    ViewSummary {
        rows: a.m(),
        cols: a.n(),
        rank: a.rank,
        table1_row: a.case.row(),
        classification: a.case.describe().to_string(),
        n_motions: a.n_motions(),
        n_self_stresses: a.n_self_stresses(),
        exactly_constrained: a.n_motions() == 0 && a.n_self_stresses() == 0,
        rank_tol: c.rank_tol,
        rank_threshold: a.tol,
        rank_gap: a.rank_gap().filter(|g| g.is_finite()),
        singular_values: a.singular_values.clone(),
        generalised: c.generalised.to_vec(),
        self_stresses: a
            .self_stresses
            .iter()
            .map(|s| {
                let mut d: Vec<_> = s.deformations.iter().collect();
                d.sort_by(|x, y| y.value.abs().total_cmp(&x.value.abs()));
                let mut lines: Vec<String> = d
                    .iter()
                    .take(MAX_STATE_ENTRIES)
                    .map(|d| {
                        format!(
                            "{} mode {} ({}) {:+.4}",
                            d.element, d.mode, d.mode_name, d.value
                        )
                    })
                    .collect();
                if d.len() > MAX_STATE_ENTRIES {
                    lines.push(format!("… {} more", d.len() - MAX_STATE_ENTRIES));
                }
                lines
            })
            .collect(),
        advice: c
            .advice
            .iter()
            .map(|s| ViewAdvice {
                kind: s.kind.to_string(),
                state: s.state,
                suggestions: s
                    .suggestions
                    .iter()
                    .map(|g| {
                        format!(
                            "{}{} → {} motion(s), {} self-stress(es)",
                            g.action.describe(),
                            crate::screw_report::designer_release(g),
                            g.motions_after,
                            g.self_stresses_after
                        )
                    })
                    .collect(),
            })
            .collect(),
    }
}

/// The lines of the designer's language: per motion (animation k) the axis or direction of
/// every moving body's twist and the suggested wires that remove it, per self-stress (field
/// `self_stress_k`) the line of action of every wrench on a body that is not the ground.
pub(super) fn screw_lines(
    sc: &flexmbd_core::kinematics::screw::ScrewAnalysis,
    wires: &[flexmbd_core::kinematics::advice::WireAdvice],
) -> Vec<ViewScrewLine> {
    use flexmbd_core::kinematics::screw::{Screw, ScrewKind};
    let kind = |s: &Screw| {
        match s.kind {
            ScrewKind::Rotation => "rotation",
            ScrewKind::Translation => "translation",
            ScrewKind::Force => "force",
            ScrewKind::Couple => "couple",
        }
        .to_string()
    };
    let pitch = |s: &Screw| match s.pitch {
        Some(h) if h.abs() > 1e-12 => format!(", pitch {}", crate::report::fmt_num(h)),
        Some(_) => ", pitch 0".to_string(),
        None => String::new(),
    };
    let mut out = Vec::new();
    for (k, m) in sc.motions.iter().enumerate() {
        for t in &m.bodies {
            out.push(ViewScrewLine {
                item: Some(k),
                field: None,
                kind: kind(&t.screw),
                point: t.screw.point,
                direction: t.screw.direction,
                label: format!("{}: {}{}", t.body, kind(&t.screw), pitch(&t.screw)),
                length: None,
            });
        }
    }
    for wa in wires {
        for w in &wa.wires {
            out.push(ViewScrewLine {
                item: Some(wa.motion),
                field: None,
                kind: "wire".into(),
                point: w.point,
                direction: w.direction,
                label: format!(
                    "suggested wire {} to {}: reciprocal {}, intended change {}",
                    w.from,
                    w.to,
                    crate::report::fmt_num(w.reciprocal),
                    crate::report::fmt_num(w.intended_change)
                ),
                length: Some(w.length),
            });
        }
    }
    let ground: Vec<&str> = sc
        .bodies
        .iter()
        .filter(|b| b.ground)
        .map(|b| b.name.as_str())
        .collect();
    for (k, st) in sc.self_stresses.iter().enumerate() {
        for w in st
            .wrenches
            .iter()
            .filter(|w| !ground.contains(&w.body.as_str()))
        {
            out.push(ViewScrewLine {
                item: None,
                field: Some(format!("self_stress_{}", k + 1)),
                kind: kind(&w.screw),
                point: w.screw.point,
                direction: w.screw.direction,
                label: format!(
                    "{} on {}: {}{}",
                    w.by,
                    w.body,
                    kind(&w.screw),
                    pitch(&w.screw)
                ),
                length: None,
            });
        }
    }
    out
}
