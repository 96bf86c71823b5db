//! The designer's part of the check report (docs/kinematic-analysis.md "Twists and
//! wrenches"): motions as twists of the bodies, self-stresses as wrenches, the intended
//! freedom and the wire suggestions, as text. (The JSON document holds the same data as the
//! core types, `report::write_check_json`.)

use flexmbd_core::kinematics::advice::{Suggestion, WireAdvice};
use flexmbd_core::kinematics::freedom::{FreedomCheck, FreedomMotion};
use flexmbd_core::kinematics::screw::{BodyTwist, Screw, ScrewAnalysis, ScrewKind};

/// (x, y, z) with six decimals.
fn v3(v: [f64; 3]) -> String {
    // no "-0.000000" for rounding noise
    let z = |a: f64| if a.abs() < 5e-7 { 0.0 } else { a };
    format!("({:.6}, {:.6}, {:.6})", z(v[0]), z(v[1]), z(v[2]))
}

/// The designer's words for a suggested release (after the action's own description): " = a
/// hinge at p about (…)", " = a slide along (…)", " = leave s1 out (…)"; empty otherwise.
pub fn designer_release(sg: &Suggestion) -> String {
    let Some(d) = &sg.designer else {
        return String::new();
    };
    let axis = d.axis.map(v3).unwrap_or_default();
    match (d.kind, &d.node) {
        ("remove", _) => " = leave the element out (it then constrains nothing)".into(),
        ("hinge", Some(n)) => format!(" = a hinge at {n} about {axis}"),
        ("hinge", None) => format!(" = a torsion hinge about the element's axis {axis}"),
        ("slide", _) => format!(" = a slide along {axis}"),
        _ => String::new(),
    }
}

/// One line for a screw: what it is and where.
pub fn describe_screw(s: &Screw) -> String {
    let pitch = |h: Option<f64>| match h {
        Some(h) if h.abs() > 1e-12 => format!(", pitch {h:.6e}"),
        _ => ", pitch 0".to_string(),
    };
    match s.kind {
        ScrewKind::Rotation => format!(
            "rotation about the axis through {} along {}{} (|w| {:.3e})",
            v3(s.point),
            v3(s.direction),
            pitch(s.pitch),
            s.magnitude
        ),
        ScrewKind::Translation => format!(
            "translation along {} (|v| {:.3e})",
            v3(s.direction),
            s.magnitude
        ),
        ScrewKind::Force => format!(
            "force on the line through {} along {}{} (|F| {:.3e})",
            v3(s.point),
            v3(s.direction),
            pitch(s.pitch),
            s.magnitude
        ),
        ScrewKind::Couple => format!("couple about {} (|M| {:.3e})", v3(s.direction), s.magnitude),
    }
}

/// The twists of one motion, one line each: all of them up to `report::TEXT_ALL_ENTRIES`, else
/// the largest by magnitude and a line for the rest (a lattice of many bodies).
fn twist_lines(twists: &[BodyTwist], indent: &str) -> String {
    let mags: Vec<f64> = twists.iter().map(|t| t.screw.magnitude).collect();
    let (shown, rest) = crate::report::top_of(&mags, "twists", indent);
    let mut s = String::new();
    for t in shown.iter().map(|&i| &twists[i]) {
        s += &format!("{indent}{}: {}", t.body, describe_screw(&t.screw));
        if t.rigid_residual > flexmbd_core::kinematics::screw::RIGID_TOL {
            s += &format!(
                " [not rigid in this motion: residual {:.1e}]",
                t.rigid_residual
            );
        }
        s += "\n";
    }
    s + rest.as_deref().unwrap_or("")
}

/// The screws of the motions and self-stresses.
pub fn screws_text(sc: &ScrewAnalysis) -> String {
    let mut s = String::new();
    if sc.motions.is_empty() && sc.self_stresses.is_empty() {
        return s;
    }
    let names: Vec<&str> = sc.bodies.iter().map(|b| b.name.as_str()).collect();
    s += &format!(
        "\nBodies: {} (model size L = {:.4e} m)\n",
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        },
        sc.length_scale
    );
    for (k, m) in sc.motions.iter().enumerate() {
        s += &format!("Motion {} as twists:\n", k + 1);
        if m.bodies.is_empty() {
            s += "    (no body moves: only nodes inside flexures)\n";
        }
        s += &twist_lines(&m.bodies, "    ");
        if !m.flexures.is_empty() {
            let f: Vec<String> = m
                .flexures
                .iter()
                .map(|f| {
                    let modes: Vec<String> = f.modes.iter().map(|d| d.mode_name.clone()).collect();
                    format!("{} ({})", f.element, modes.join(", "))
                })
                .collect();
            s += &format!("    flexures that deform: {}\n", f.join("; "));
        }
    }
    for (k, st) in sc.self_stresses.iter().enumerate() {
        s += &format!("Self-stress state {} as wrenches on the bodies:\n", k + 1);
        let mags: Vec<f64> = st.wrenches.iter().map(|w| w.screw.magnitude).collect();
        let (shown, rest) = crate::report::top_of(&mags, "wrenches", "    ");
        for w in shown.iter().map(|&i| &st.wrenches[i]) {
            s += &format!(
                "    on {} by {}: {}\n",
                w.body,
                w.by,
                describe_screw(&w.screw)
            );
        }
        s += rest.as_deref().unwrap_or("");
    }
    s
}

fn describe_intended(m: &FreedomMotion) -> String {
    match m {
        FreedomMotion::Translation { direction } => format!("translation along {}", v3(*direction)),
        FreedomMotion::Rotation { point, axis, pitch } => format!(
            "rotation about the axis through {} along {}, pitch {pitch}",
            v3(*point),
            v3(*axis)
        ),
    }
}

/// The comparison with the intended freedom.
pub fn freedom_text(f: &FreedomCheck) -> String {
    let mut s = String::from("\nIntended freedom (generalised coordinates released):\n");
    for i in &f.intended {
        s += &format!("    {}: {}\n", i.body, describe_intended(&i.motion));
    }
    s += &format!(
        "  design: {} motion(s), dimension {} on the named bodies; intended dimension {}\n",
        f.n_design_motions, f.design_dimension, f.intended_dimension
    );
    if !f.principal_angles.is_empty() {
        let a: Vec<String> = f
            .principal_angles
            .iter()
            .map(|a| format!("{a:.3e}"))
            .collect();
        s += &format!(
            "  principal angles [rad]: {} (equal when every sine <= {:.0e}; rotations weighed by L = {:.4e} m)\n",
            a.join(", "),
            f.tolerance,
            f.length_scale
        );
    }
    if f.matches {
        s += "  => the freedom space equals the intended freedom\n";
        return s;
    }
    for (k, p) in f.parasitic.iter().enumerate() {
        s += &format!("  parasitic freedom {}:\n", k + 1);
        s += &twist_lines(p, "    ");
    }
    for (k, m) in f.missing.iter().enumerate() {
        s += &format!("  missing freedom {}:\n", k + 1);
        s += &twist_lines(m, "    ");
    }
    if f.internal_motions > 0 {
        s += &format!(
            "  {} motion(s) in which no named body moves (parasitic)\n",
            f.internal_motions
        );
    }
    s
}

/// The wire suggestions per motion.
pub fn wires_text(wires: &[WireAdvice]) -> String {
    let mut s = String::new();
    if wires.is_empty() {
        return s;
    }
    s += "\nConstraint lines that remove a motion without a self-stress (each verified; least \
          change of the intended freedom first)\n";
    for w in wires {
        s += &format!("  motion {}: any one of\n", w.motion + 1);
        if w.wires.is_empty() {
            s += "    (none found among the wires between existing nodes)\n";
        }
        for x in &w.wires {
            // the body in brackets, unless the node is in none (then it is its own name)
            let end = |node: &str, body: &str| {
                if node == body {
                    node.to_string()
                } else {
                    format!("{node} ({body})")
                }
            };
            s += &format!(
                "    - a wire from {} to {}: line through {} along {}; reciprocal product \
                 {:.4e}, intended change {:.1e}  -> {} motion(s), {} self-stress(es)\n",
                end(&x.from, &x.body),
                end(&x.to, &x.other),
                v3(x.point),
                v3(x.direction),
                x.reciprocal,
                x.intended_change,
                x.motions_after,
                x.self_stresses_after
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_core::kinematics::screw::{BodyWrench, Screw, SelfStressScrews};

    /// A self-stress state with more wrenches than the text lists in full shows the largest
    /// (by |F|, largest first) and counts the rest; a short one is listed whole.
    #[test]
    fn long_wrench_lists_show_the_largest() {
        let wrench = |k: usize| BodyWrench {
            body: "ground".into(),
            by: format!("b{k}"),
            support: false,
            screw: Screw {
                kind: ScrewKind::Force,
                point: [k as f64, 0.0, 0.0],
                direction: [0.0, 0.0, 1.0],
                pitch: Some(0.0),
                // magnitudes 1 … 60 in a scrambled order
                magnitude: ((k * 37) % 60 + 1) as f64,
            },
            force: [0.0; 3],
            moment: [0.0; 3],
        };
        let analysis = |n: usize| ScrewAnalysis {
            length_scale: 1.0,
            bodies: Vec::new(),
            motions: Vec::new(),
            self_stresses: vec![SelfStressScrews {
                wrenches: (0..n).map(wrench).collect(),
            }],
        };
        let long = screws_text(&analysis(60));
        let lines: Vec<&str> = long.lines().filter(|l| l.starts_with("    on ")).collect();
        assert_eq!(lines.len(), crate::report::TEXT_TOP_ENTRIES);
        assert!(lines[0].ends_with("(|F| 6.000e1)"), "{}", lines[0]);
        assert!(lines[9].ends_with("(|F| 5.100e1)"), "{}", lines[9]);
        assert!(long.contains("    ... and 50 more wrenches of magnitude 50"));
        let short = screws_text(&analysis(crate::report::TEXT_ALL_ENTRIES));
        let n = short.lines().filter(|l| l.starts_with("    on ")).count();
        assert_eq!(n, crate::report::TEXT_ALL_ENTRIES);
        assert!(!short.contains("more wrenches"));
    }
}
