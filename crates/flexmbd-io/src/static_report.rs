//! Reports of a static analysis: per load step the nodal positions and rotations, beam stress
//! resultants and maximum bending stress, reactions, elastic energy, support compliance and
//! buckling multipliers. Text tables, JSON and CSV.

use crate::report::{fmt_num, table};
use flexmbd_core::elements::Element;
use flexmbd_core::math::lambda_bar;
use flexmbd_core::model::{CoordKind, Model};
use flexmbd_core::statics::{StaticSolution, StepResult};
use serde::Serialize;
use serde_json::{json, Value};
use std::fmt::Write as _;

/// The linearised results of one step (compliance, buckling, stability), as the core computes
/// them ([`flexmbd_core::statics::linear::at_step`]).
pub use flexmbd_core::statics::linear::StepLinear as StepExtras;

/// Rotation vector (axis × angle, global axes) of Euler parameters.
pub fn rotation_vector(l: &[f64]) -> [f64; 3] {
    let n = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + l[3] * l[3]).sqrt();
    let (l0, v) = (l[0] / n, [l[1] / n, l[2] / n, l[3] / n]);
    let s = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if s < 1e-300 {
        return [0.0; 3];
    }
    // angle in (−π, π]: take the shorter rotation
    let (s, l0, v) = if l0 < 0.0 {
        (s, -l0, v.map(|a| -a))
    } else {
        (s, l0, v)
    };
    let angle = 2.0 * s.atan2(l0);
    [v[0] / s * angle, v[1] / s * angle, v[2] / s * angle]
}

/// Per-node results of a step.
#[derive(Clone, Debug, Serialize)]
pub struct NodeResult {
    /// Node name.
    pub node: String,
    /// Position [m].
    pub position: [f64; 3],
    /// Displacement from the reference [m].
    pub displacement: [f64; 3],
    /// Rotation vector [rad] (nodes with rotation).
    pub rotation: Option<[f64; 3]>,
    /// Reaction force [N] at fixed or input coordinates.
    pub reaction_force: Option<[f64; 3]>,
    /// Reaction moment [N·m] at fixed or input rotations.
    pub reaction_moment: Option<[f64; 3]>,
}

/// Per-element results of a step.
#[derive(Clone, Debug, Serialize)]
pub struct ElementResult {
    /// Element name.
    pub element: String,
    /// Deformations e.
    pub e: Vec<f64>,
    /// Stress resultants σ (beam: σ1 axial force [N], σ2 ≈ torque/l0, σ3..σ6 ≈ bending end
    /// moments/l0 [N]).
    pub sigma: Vec<f64>,
    /// Largest normal stress in a beam with a section: |N|/A + |M_y| c_z/Iy + |M_z| c_y/Iz with
    /// the end moments M ≈ σ l0 [Pa].
    pub max_stress: Option<f64>,
}

/// Nodal results of a step.
pub fn node_results(model: &Model, step: &StepResult) -> Vec<NodeResult> {
    let x0 = model.x0();
    model
        .nodes
        .iter()
        .map(|n| {
            let p = n.ix_pos;
            let position = [step.x[p], step.x[p + 1], step.x[p + 2]];
            let displacement = [
                position[0] - x0[p],
                position[1] - x0[p + 1],
                position[2] - x0[p + 2],
            ];
            let supported = |i: usize| model.partition.x[i] != CoordKind::Free;
            let reaction_force = (n.host.is_none() && (p..p + 3).any(supported)).then(|| {
                [
                    step.reactions[p],
                    step.reactions[p + 1],
                    step.reactions[p + 2],
                ]
            });
            let (rotation, reaction_moment) = match n.ix_rot {
                Some(r) => {
                    let l = &step.x[r..r + 4];
                    let moment = (r..r + 4).any(supported).then(|| {
                        // M = ½ Λ̄ f_λ (theory.md §8 of spacar-format: SPACAR takes f(λ1..3)/2)
                        let lb = lambda_bar(&[l[0], l[1], l[2], l[3]]);
                        std::array::from_fn(|k| {
                            0.5 * (0..4)
                                .map(|c| lb[k][c] * step.reactions[r + c])
                                .sum::<f64>()
                        })
                    });
                    (Some(rotation_vector(l)), moment)
                }
                None => (None, None),
            };
            NodeResult {
                node: n.name.clone(),
                position,
                displacement,
                rotation,
                reaction_force,
                reaction_moment,
            }
        })
        .collect()
}

/// Element results of a step.
pub fn element_results(model: &Model, step: &StepResult) -> Vec<ElementResult> {
    model
        .elements
        .iter()
        .map(|entry| {
            use flexmbd_core::elements::ElementKind;
            let ne = entry.element.ne();
            let e = step.e[entry.ie..entry.ie + ne].to_vec();
            let sigma = step.sigma[entry.ie..entry.ie + ne].to_vec();
            let max_stress = match &entry.element {
                Element::Beam(b) => b.props.filter(|p| p.area > 0.0).map(|p| {
                    let my = sigma[2].abs().max(sigma[3].abs()) * b.l0;
                    let mz = sigma[4].abs().max(sigma[5].abs()) * b.l0;
                    sigma[0].abs() / p.area + my * p.fibre[0] / p.i[0] + mz * p.fibre[1] / p.i[1]
                }),
                _ => None,
            };
            ElementResult {
                element: entry.name.clone(),
                e,
                sigma,
                max_stress,
            }
        })
        .collect()
}

/// JSON document of a static run.
pub fn static_json(
    model: &Model,
    file: &str,
    sol: &StaticSolution,
    extras: &[StepExtras],
) -> Value {
    let steps: Vec<Value> = sol
        .steps
        .iter()
        .zip(extras)
        .enumerate()
        .map(|(k, (s, x))| {
            json!({
                "step": k,
                "load_factor": s.load_factor,
                "iterations": s.iterations,
                "substeps": s.substeps,
                "residual": s.residual,
                "energy": s.energy,
                "nodes": node_results(model, s),
                "elements": element_results(model, s),
                "compliance": x.compliance.iter().map(|(n, c)| json!({
                    "node": n,
                    "global": c.global,
                    "local": c.local,
                    "stiffness_global": c.stiffness_global(),
                    "stiffness_local": c.stiffness_local(),
                })).collect::<Vec<_>>(),
                "buckling": x.buckling,
                "unstable_directions": x.unstable_directions,
                "warnings": x.failures.iter().map(|f| f.to_string()).collect::<Vec<_>>(),
            })
        })
        .collect();
    json!({ "model": model.name, "file": file, "roles": sol.roles, "steps": steps })
}

const DIRS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// Text report of a static run: a table of all steps, then the last step in detail.
pub fn static_text(
    model: &Model,
    file: &str,
    sol: &StaticSolution,
    extras: &[StepExtras],
) -> String {
    let mut s = String::new();
    let title = if model.name.is_empty() {
        String::new()
    } else {
        format!(": {}", model.name)
    };
    let _ = writeln!(s, "flexmbd static{title}  ({file})\n");
    let rigid = sol
        .roles
        .iter()
        .filter(|r| **r != flexmbd_core::statics::Role::Flexible)
        .count();
    let _ = writeln!(
        s,
        "{} deformations: {} flexible, {} rigid or prescribed\n",
        sol.roles.len(),
        sol.roles.len() - rigid,
        rigid
    );
    // step table
    let mut header = vec!["step", "load", "iter", "energy [J]", "max |u| [m]"];
    let mut names: Vec<String> = Vec::new();
    if let Some(x) = extras.first() {
        for (n, _) in &x.compliance {
            for d in DIRS {
                names.push(format!("k_{d} {n}"));
            }
        }
    }
    header.extend(names.iter().map(String::as_str));
    let with_buckling = extras.iter().any(|x| x.buckling.is_some());
    if with_buckling {
        header.push("buckling mu1");
    }
    header.push("stable");
    let rows: Vec<Vec<String>> = sol
        .steps
        .iter()
        .zip(extras)
        .enumerate()
        .map(|(k, (st, x))| {
            let nodes = node_results(model, st);
            let umax = nodes
                .iter()
                .map(|n| n.displacement.iter().map(|v| v * v).sum::<f64>().sqrt())
                .fold(0.0, f64::max);
            let mut row = vec![
                k.to_string(),
                format!("{:.4}", st.load_factor),
                st.iterations.to_string(),
                fmt_num(st.energy),
                fmt_num(umax),
            ];
            for (_, c) in &x.compliance {
                let k = c.stiffness_local();
                row.extend((0..6).map(|i| {
                    if c.held[i] {
                        "held".into()
                    } else {
                        fmt_num(k[i])
                    }
                }));
            }
            if with_buckling {
                row.push(
                    x.buckling
                        .as_ref()
                        .and_then(|b| b.multipliers.first())
                        .map_or("-".into(), |m| fmt_num(*m)),
                );
            }
            row.push(match x.unstable_directions {
                Some(0) => "yes".into(),
                Some(n) => format!("NO ({n})"),
                None => "-".into(),
            });
            row
        })
        .collect();
    s += &table(&header, &rows);
    if !names.is_empty() {
        s += "  (support stiffness 1/C_ii in the node's local axes: N/m for x, y, z; N·m/rad for rx, ry, rz;\n   held: a support or prescribed input holds that direction)\n";
    }
    for (k, x) in extras.iter().enumerate() {
        for w in &x.failures {
            let _ = writeln!(s, "  step {k}: {w}");
        }
        if let Some(n) = x.unstable_directions.filter(|n| *n > 0) {
            let _ = writeln!(s, "  step {k}: the equilibrium is UNSTABLE ({n} negative stiffness direction(s)): the structure has buckled at or before this load");
        }
    }
    // last step in detail
    let Some(last) = sol.steps.last() else {
        return s;
    };
    let _ = writeln!(
        s,
        "\nLast step (load factor {:.4})\n\nNodes",
        last.load_factor
    );
    let nodes = node_results(model, last);
    let rows: Vec<Vec<String>> = nodes
        .iter()
        .map(|n| {
            let mut r = vec![n.node.clone()];
            r.extend(n.displacement.iter().map(|v| fmt_num(*v)));
            match n.rotation {
                Some(rv) => r.extend(rv.iter().map(|v| fmt_num(*v))),
                None => r.extend(["-".to_string(), "-".into(), "-".into()]),
            }
            r
        })
        .collect();
    s += &table(
        &[
            "node", "ux [m]", "uy [m]", "uz [m]", "rx [rad]", "ry [rad]", "rz [rad]",
        ],
        &rows,
    );
    let rows: Vec<Vec<String>> = nodes
        .iter()
        .filter(|n| n.reaction_force.is_some() || n.reaction_moment.is_some())
        .map(|n| {
            let mut r = vec![n.node.clone()];
            let f = |v: Option<[f64; 3]>| -> Vec<String> {
                v.map_or(vec!["-".into(); 3], |v| {
                    v.iter().map(|a| fmt_num(*a)).collect()
                })
            };
            r.extend(f(n.reaction_force));
            r.extend(f(n.reaction_moment));
            r
        })
        .collect();
    if !rows.is_empty() {
        s += "\nReactions at supports and inputs\n";
        s += &table(
            &[
                "node",
                "Fx [N]",
                "Fy [N]",
                "Fz [N]",
                "Mx [N·m]",
                "My [N·m]",
                "Mz [N·m]",
            ],
            &rows,
        );
    }
    let rows: Vec<Vec<String>> = element_results(model, last)
        .iter()
        .map(|e| {
            let mut r = vec![e.element.clone()];
            r.extend(e.sigma.iter().map(|v| fmt_num(*v)));
            r.resize(7, String::new());
            r.push(e.max_stress.map_or("-".into(), fmt_num));
            r
        })
        .collect();
    s += "\nStress resultants σ (beam: axial force, torque/l0, bending moments/l0 [N]) and largest normal stress\n";
    s += &table(
        &[
            "element",
            "s1",
            "s2",
            "s3",
            "s4",
            "s5",
            "s6",
            "max stress [Pa]",
        ],
        &rows,
    );
    s
}

/// Write `summary.csv` (one row per step) and `step_K.csv` (nodes and elements per step) into `dir`.
pub fn write_csv(
    dir: &std::path::Path,
    model: &Model,
    sol: &StaticSolution,
    extras: &[StepExtras],
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut sum = String::from("step,load_factor,iterations,residual,energy");
    if let Some(x) = extras.first() {
        for (n, _) in &x.compliance {
            for d in DIRS {
                let _ = write!(sum, ",k_{d}_{n}");
            }
        }
    }
    sum += ",buckling_mu1,unstable_directions\n";
    for (k, (st, x)) in sol.steps.iter().zip(extras).enumerate() {
        let _ = write!(
            sum,
            "{k},{},{},{},{}",
            st.load_factor, st.iterations, st.residual, st.energy
        );
        for (_, c) in &x.compliance {
            for v in c.stiffness_local() {
                let _ = write!(sum, ",{v}");
            }
        }
        let mu = x
            .buckling
            .as_ref()
            .and_then(|b| b.multipliers.first())
            .map_or(String::new(), |m| m.to_string());
        let un = x
            .unstable_directions
            .map_or(String::new(), |n| n.to_string());
        let _ = writeln!(sum, ",{mu},{un}");
        // per step: nodes then elements
        let mut t = String::from("kind,name,ux,uy,uz,rx,ry,rz,Fx,Fy,Fz,Mx,My,Mz\n");
        for n in node_results(model, st) {
            let o = |v: Option<[f64; 3]>| {
                v.map_or(",,".to_string(), |v| format!("{},{},{}", v[0], v[1], v[2]))
            };
            let d = n.displacement;
            let _ = writeln!(
                t,
                "node,{},{},{},{},{},{},{}",
                n.node,
                d[0],
                d[1],
                d[2],
                o(n.rotation),
                o(n.reaction_force),
                o(n.reaction_moment)
            );
        }
        t += "kind,name,s1,s2,s3,s4,s5,s6,max_stress\n";
        for e in element_results(model, st) {
            let mut cells: Vec<String> = e.sigma.iter().map(|v| v.to_string()).collect();
            cells.resize(6, String::new());
            let _ = writeln!(
                t,
                "element,{},{},{}",
                e.element,
                cells.join(","),
                e.max_stress.map_or(String::new(), |v| v.to_string())
            );
        }
        std::fs::write(dir.join(format!("step_{k:03}.csv")), t)?;
    }
    std::fs::write(dir.join("summary.csv"), sum)
}
