//! Reports of a static analysis: per load step the nodal positions and rotations, beam stress
//! resultants and maximum bending stress, reactions, elastic energy, support compliance and
//! buckling multipliers. Text tables, JSON and CSV.

use crate::report::{fmt_num, heading, table};
use crate::stopped::{json_field, StopNote};
use crate::stream_json::{Seq, Sorted};
use flexmbd_core::model::Model;
use flexmbd_core::statics::{PathEvent, StaticSolution};
use serde::ser::{Serialize, SerializeMap, Serializer};
use serde_json::{json, Value};
use std::fmt::Write as _;

/// The linearised results of one step (compliance, buckling, stability), as the core computes
/// them ([`flexmbd_core::statics::linear::at_step`]).
pub use flexmbd_core::statics::linear::StepLinear as StepExtras;

pub use flexmbd_core::results::{
    element_results, node_results, rotation_vector, ElementResult, NodeResult,
};

/// JSON document of a static run; `stop`: where and why a path that stopped part-way stopped
/// (the `stopped` field, null for a complete path).
pub fn static_json(
    model: &Model,
    file: &str,
    sol: &StaticSolution,
    extras: &[StepExtras],
    stop: Option<&StopNote>,
) -> Value {
    serde_json::to_value(StaticDoc {
        model,
        file,
        sol,
        extras,
        stop,
    })
    .expect("a static run serialises")
}

/// The JSON document of [`static_json`] as it is serialised, streamed step by step and node by
/// node without a tree of the whole (the 10⁴-beam strip's ten steps, 89 MB of text, took
/// 570 MiB as a tree). Keys in the tree's sorted order: the same text.
pub struct StaticDoc<'a> {
    /// The model analysed.
    pub model: &'a Model,
    /// The model file, as given.
    pub file: &'a str,
    /// The load path.
    pub sol: &'a StaticSolution,
    /// The linearised results of every step.
    pub extras: &'a [StepExtras],
    /// Where and why the path stopped part-way, if it did.
    pub stop: Option<&'a StopNote>,
}

impl Serialize for StaticDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, sol) = (self.model, self.sol);
        let mut m = s.serialize_map(Some(6))?;
        m.serialize_entry("events", &Sorted(&sol.events))?;
        m.serialize_entry("file", self.file)?;
        m.serialize_entry("model", &model.name)?;
        m.serialize_entry("roles", &Sorted(&sol.roles))?;
        m.serialize_entry(
            "steps",
            &Seq(|| {
                sol.steps
                    .iter()
                    .zip(self.extras)
                    .enumerate()
                    .map(|(k, (step, x))| StepDoc {
                        model,
                        sol,
                        k,
                        step,
                        x,
                    })
            }),
        )?;
        m.serialize_entry("stopped", &json_field(self.stop))?;
        m.end()
    }
}

/// One step of [`StaticDoc`].
struct StepDoc<'a> {
    model: &'a Model,
    sol: &'a StaticSolution,
    k: usize,
    step: &'a flexmbd_core::statics::StepResult,
    x: &'a StepExtras,
}

impl Serialize for StepDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, st, x) = (self.model, self.step, self.x);
        let mut m = s.serialize_map(Some(14))?;
        m.serialize_entry("buckling", &Sorted(&x.buckling))?;
        m.serialize_entry(
            "compliance",
            &Seq(|| {
                x.compliance.iter().map(|(n, c)| {
                    json!({
                        "node": n,
                        "global": c.global,
                        "local": c.local,
                        "stiffness_global": c.stiffness_global(),
                        "stiffness_local": c.stiffness_local(),
                    })
                })
            }),
        )?;
        let elements = element_results(model, st);
        m.serialize_entry("elements", &Seq(|| elements.iter().map(Sorted)))?;
        drop(elements);
        m.serialize_entry("energy", &st.energy)?;
        m.serialize_entry("iterations", &st.iterations)?;
        m.serialize_entry("load_factor", &st.load_factor)?;
        let nodes = node_results(model, st);
        m.serialize_entry("nodes", &Seq(|| nodes.iter().map(Sorted)))?;
        drop(nodes);
        m.serialize_entry("path", &Sorted(self.sol.path.get(self.k)))?;
        m.serialize_entry("residual", &st.residual)?;
        m.serialize_entry("step", &self.k)?;
        m.serialize_entry("substeps", &st.substeps)?;
        m.serialize_entry("tangent_eigenvalues", &Sorted(&st.tangent_eigenvalues))?;
        m.serialize_entry("unstable_directions", &Sorted(&x.unstable_directions))?;
        m.serialize_entry(
            "warnings",
            &Seq(|| x.failures.iter().map(|f| f.to_string())),
        )?;
        m.end()
    }
}

const DIRS: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

/// A critical point of an arc-length path in words.
fn event_text(sol: &StaticSolution, e: &PathEvent) -> String {
    match *e {
        PathEvent::LimitPoint {
            step,
            load_factor,
            located,
        } => {
            let before = step
                .checked_sub(1)
                .and_then(|k| sol.steps.get(k))
                .map_or(0.0, |s| s.load_factor);
            let kind = if before < load_factor {
                "a maximum: under a dead load the structure snaps through here"
            } else {
                "a minimum: the end of the unstable part of the path"
            };
            let at = if located { "located at" } else { "near" };
            format!("step {step}: LIMIT POINT, the load factor turns back {at} {load_factor:.6} ({kind})")
        }
        PathEvent::Bifurcation {
            step,
            load_factor,
            unstable,
            located,
        } => format!(
            "step {step}: BIFURCATION {} load factor {load_factor:.6}, unstable directions {} -> {} (another branch of equilibria crosses the path)",
            if located { "located at" } else { "before" },
            unstable[0],
            unstable[1]
        ),
        PathEvent::Jump {
            step,
            from,
            load_factor,
            growth,
        } => format!(
            "step {step}: JUMP between load factors {from:.6} and {load_factor:.6}: the displacement increment grew {growth:.1}-fold; the path has probably snapped through a limit point, which load steps cannot follow (arc-length path following shows it)"
        ),
    }
}

/// Text report of a static run: a table of all steps, then the last step in detail; `stop`
/// marks a path that stopped part-way, after the table.
pub fn static_text(
    model: &Model,
    file: &str,
    sol: &StaticSolution,
    extras: &[StepExtras],
    stop: Option<&StopNote>,
) -> String {
    let mut s = heading("static", model, file);
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
    // step table (with arc length: the path parameter, and the stability from the tangent's
    // inertia where no buckling analysis gives it)
    let arc = !sol.path.is_empty();
    let mut header = vec!["step", "load", "iter", "energy [J]", "max |u| [m]"];
    if arc {
        header.insert(2, "path s");
        header.insert(3, "level");
    }
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
    let with_kappa = sol.steps.iter().any(|s| s.tangent_eigenvalues.is_some());
    if with_kappa {
        header.push("kappa1");
    }
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
            if let Some(p) = sol.path.get(k) {
                row.insert(2, fmt_num(p.arc_length));
                row.insert(3, p.level.map_or(String::new(), |l| l.to_string()));
            }
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
            let unstable = x
                .unstable_directions
                .or_else(|| sol.path.get(k).and_then(|p| p.unstable_directions));
            row.push(match unstable {
                Some(0) => "yes".into(),
                Some(n) => format!("NO ({n})"),
                None => "-".into(),
            });
            if with_kappa {
                row.push(
                    st.tangent_eigenvalues
                        .as_ref()
                        .and_then(|v| v.first())
                        .map_or("-".into(), |k| fmt_num(*k)),
                );
            }
            row
        })
        .collect();
    s += &table(&header, &rows);
    if with_kappa {
        s += "  (kappa1: the smallest eigenvalue of the tangent stiffness on the constraints, translations in m and\n   rotations in rad: N/m, N·m/rad or mixed; negative where the equilibrium is unstable)\n";
    }
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
    for e in &sol.events {
        let _ = writeln!(s, "  {}", event_text(sol, e));
    }
    if let Some(stop) = stop {
        s += &stop.text();
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

/// Write `summary.csv` (one row per step) and `step_K.csv` (nodes and elements per step) into
/// `dir`; `stop` ends `summary.csv` with a comment line saying where and why the path stopped.
pub fn write_csv(
    dir: &std::path::Path,
    model: &Model,
    sol: &StaticSolution,
    extras: &[StepExtras],
    stop: Option<&StopNote>,
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let arc = !sol.path.is_empty();
    let mut sum = String::from("step,load_factor,iterations,residual,energy");
    if arc {
        sum += ",arc_length,level";
    }
    if let Some(x) = extras.first() {
        for (n, _) in &x.compliance {
            for d in DIRS {
                let _ = write!(sum, ",k_{d}_{n}");
            }
        }
    }
    sum += ",buckling_mu1,unstable_directions";
    for i in 1..=flexmbd_core::statics::TANGENT_EIGENVALUES {
        let _ = write!(sum, ",kappa{i}");
    }
    sum += "\n";
    for (k, (st, x)) in sol.steps.iter().zip(extras).enumerate() {
        let _ = write!(
            sum,
            "{k},{},{},{},{}",
            st.load_factor, st.iterations, st.residual, st.energy
        );
        if let Some(p) = sol.path.get(k).filter(|_| arc) {
            let level = p.level.map_or(String::new(), |l| l.to_string());
            let _ = write!(sum, ",{},{level}", p.arc_length);
        }
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
        let _ = write!(sum, ",{mu},{un}");
        let kappa = st.tangent_eigenvalues.as_deref().unwrap_or(&[]);
        for i in 0..flexmbd_core::statics::TANGENT_EIGENVALUES {
            let _ = write!(
                sum,
                ",{}",
                kappa.get(i).map_or(String::new(), f64::to_string)
            );
        }
        sum += "\n";
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
    if let Some(stop) = stop {
        sum += &stop.csv_comment();
    }
    std::fs::write(dir.join("summary.csv"), sum)
}
