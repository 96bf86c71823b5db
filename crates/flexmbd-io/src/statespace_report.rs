//! Reports of the linear dynamics commands (docs/state-space.md):
//!
//! - `flexmbd statespace`: the state-space model as text, JSON, a MATLAB/Octave `.m` file, and a
//!   Bode table (CSV);
//! - `flexmbd sweep`: frequencies and support stiffness per load step as text, JSON and CSV.

use crate::report::{fmt_num, table};
use crate::stopped::StopNote;
use flexmbd_core::dynamics::state_space::{
    magnitude_phase, to_rows as rows, OutputKind, Probe, StateSpace,
};
use flexmbd_core::dynamics::sweep::SweepPoint;
use flexmbd_core::elements::ElementKind;
use flexmbd_core::Model;
use serde_json::{json, Value};
use std::fmt::Write as _;

/// Where a linearisation was done.
#[derive(Clone, Copy, Debug)]
pub struct Origin<'a> {
    /// Model file as given.
    pub file: &'a str,
    /// Load step index (0: unloaded).
    pub step: usize,
    /// Load factor of the step.
    pub load_factor: f64,
    /// Where and why the static path stopped, when it stopped part-way (the state is then the
    /// last converged one, or the one asked for, short of the full load); `None` for a
    /// complete path.
    pub stopped: Option<&'a StopNote>,
}

fn finite_or_null(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// Input and output descriptions as JSON objects.
fn io_json(model: &Model, ss: &StateSpace) -> (Vec<Value>, Vec<Value>) {
    let inputs = ss
        .input_info(model)
        .into_iter()
        .map(|i| {
            let mut v = json!({
                "name": i.name,
                "kind": i.kind,
                "unit": i.unit,
                "description": i.description,
            });
            if let (Some(node), Some(dof)) = (i.node, i.dof) {
                v["node"] = json!(model.nodes[node].name);
                v["direction"] = json!(dof.name());
            }
            if let Some((element, mode)) = i.deformation {
                let entry = &model.elements[element];
                v["element"] = json!(entry.name);
                v["mode"] = json!(mode + 1);
                v["mode_name"] = json!(entry.element.mode_name(mode, &model.node_names()));
            }
            v
        })
        .collect();
    let outputs = ss
        .outputs
        .iter()
        .map(|o| {
            let mut v = json!({
                "name": o.name(model),
                "kind": o.kind.name(),
                "unit": o.unit(model),
                "description": o.describe(model),
            });
            match o.probe {
                Probe::Node { node, dof } => {
                    v["node"] = json!(model.nodes[node].name);
                    v["direction"] = json!(dof.name());
                }
                Probe::Reaction { node, dof } => {
                    v["node"] = json!(model.nodes[node].name);
                    v["direction"] = json!(dof.name());
                    v["quantity"] = json!("reaction");
                }
                Probe::Deformation { element, mode } | Probe::Force { element, mode } => {
                    let entry = &model.elements[element];
                    v["element"] = json!(entry.name);
                    v["mode"] = json!(mode + 1);
                    v["mode_name"] = json!(entry.element.mode_name(mode, &model.node_names()));
                    v["quantity"] = json!(if matches!(o.probe, Probe::Force { .. }) {
                        "force"
                    } else {
                        "deformation"
                    });
                }
            }
            v
        })
        .collect();
    (inputs, outputs)
}

/// The state-space model as JSON: A, B, C, D as arrays of rows, named inputs and outputs,
/// the kept frequencies and the damping ratio; the DC gain when it exists.
pub fn statespace_json(model: &Model, origin: Origin, ss: &StateSpace) -> Value {
    let (inputs, outputs) = io_json(model, ss);
    let states = ss.state_names();
    json!({
        "file": origin.file,
        "model": model.name,
        "step": origin.step,
        "load_factor": origin.load_factor,
        "damping_ratio": ss.damping,
        "frequencies_hz": ss.frequencies().into_iter().map(finite_or_null).collect::<Vec<_>>(),
        "eigenvalues": ss.eigenvalues,
        "degrees_of_freedom": ss.ndof,
        "solver": ss.solver.name(),
        "massless_directions": ss.massless,
        "modes_available": ss.available_modes,
        "static_correction": ss.static_correction,
        "states": states,
        "state_description": state_description(ss),
        "inputs": inputs,
        "outputs": outputs,
        "A": rows(&ss.a),
        "B": rows(&ss.b),
        "C": rows(&ss.c),
        "D": rows(&ss.d),
        "dc_gain": ss.dc_gain().ok().map(|g| rows(&g)),
        "warnings": ss.warnings,
        "stopped": crate::stopped::json_field(origin.stopped),
    })
}

/// What the states are, in words.
fn state_description(ss: &StateSpace) -> String {
    let mut s = String::from(
        "modal coordinates eta_k of the mass-normalised modes (dq = Phi eta), then their rates",
    );
    if !ss.motions.is_empty() {
        s += "; then per prescribed-motion input j the enforced displacement u_j and velocity du_j";
    }
    s
}

/// A matrix as MATLAB text: `NAME = [a b; c d];` one row per line (full precision).
fn m_matrix(name: &str, m: &[Vec<f64>]) -> String {
    let mut s = format!("{name} = [");
    if m.is_empty() || m[0].is_empty() {
        let _ = writeln!(s, "];");
        return s;
    }
    s.push('\n');
    for (i, row) in m.iter().enumerate() {
        s.push_str("  ");
        let cells: Vec<String> = row.iter().map(|&v| num(v)).collect();
        s.push_str(&cells.join(" "));
        s.push_str(if i + 1 < m.len() { ";\n" } else { "\n" });
    }
    s.push_str("];\n");
    s
}

/// Full-precision number, plain for moderate magnitudes, `1.5e-13` style otherwise.
fn num(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-4..1e15).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

fn m_string(s: &str) -> String {
    format!("'{}'", s.replace('\'', "''"))
}

/// The state-space model as a MATLAB/Octave script.
pub fn statespace_m(model: &Model, origin: Origin, ss: &StateSpace) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "% flexmbd statespace{}  ({})",
        crate::report::model_name(model),
        origin.file
    );
    let _ = writeln!(
        s,
        "% linearised at step {} (load factor {}); damping ratio zeta = {}",
        origin.step, origin.load_factor, ss.damping
    );
    if let Some(stop) = origin.stopped {
        let _ = write!(s, "% {}", stop.csv_comment().trim_start_matches("# "));
    }
    let _ = writeln!(
        s,
        "% state x = [{}]: {}",
        ss.state_names().join(" "),
        state_description(ss)
    );
    let f: Vec<String> = ss
        .frequencies()
        .iter()
        .map(|f| format!("{f:.6e}"))
        .collect();
    let _ = writeln!(s, "% frequencies [Hz]: {}", f.join(" "));
    let ins: Vec<String> = ss
        .input_info(model)
        .iter()
        .enumerate()
        .map(|(k, i)| format!("{} {} [{}]", k + 1, i.name, i.unit))
        .collect();
    let outs: Vec<String> = ss
        .outputs
        .iter()
        .enumerate()
        .map(|(k, o)| format!("{} {} [{}]", k + 1, o.name(model), o.unit(model)))
        .collect();
    let _ = writeln!(s, "% inputs: {}", ins.join("; "));
    let _ = writeln!(s, "% outputs: {}", outs.join("; "));
    for w in &ss.warnings {
        let _ = writeln!(s, "% warning: {w}");
    }
    s += &m_matrix("A", &rows(&ss.a));
    s += &m_matrix("B", &rows(&ss.b));
    s += &m_matrix("C", &rows(&ss.c));
    s += &m_matrix("D", &rows(&ss.d));
    let names = |v: Vec<String>| {
        v.iter()
            .map(String::as_str)
            .map(m_string)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        s,
        "input_names = {{{}}};",
        names(ss.input_info(model).into_iter().map(|i| i.name).collect())
    );
    let _ = writeln!(
        s,
        "output_names = {{{}}};",
        names(ss.outputs.iter().map(|o| o.name(model)).collect())
    );
    let _ = writeln!(
        s,
        "freq_hz = [{}];",
        ss.frequencies()
            .iter()
            .map(|&f| num(f))
            .collect::<Vec<_>>()
            .join(" ")
    );
    s += "% sys = ss(A, B, C, D);\n";
    s += "% sys = ss(A, B, C, D, 'InputName', input_names, 'OutputName', output_names);\n";
    s
}

/// Column header of a pair.
fn pair(model: &Model, ss: &StateSpace, o: usize, input: &str) -> String {
    format!("{}/{}", ss.outputs[o].name(model), input)
}

/// Bode table as CSV: `frequency_hz`, then for every output–input pair (outputs outer, inputs
/// inner) the magnitude |G| in absolute units (output unit per input unit, not dB) and the
/// phase in degrees, unwrapped along the frequencies; `stop` ends it with a comment line saying
/// where and why the static path stopped (the state linearised is then short of the full load).
pub fn bode_csv(model: &Model, ss: &StateSpace, freqs: &[f64], stop: Option<&StopNote>) -> String {
    let (no, ni) = (ss.outputs.len(), ss.n_inputs());
    let info = ss.input_info(model);
    let mut s = String::from("frequency_hz");
    for o in 0..no {
        for inp in &info {
            let p = pair(model, ss, o, &inp.name);
            let _ = write!(s, ",mag({p}),phase_deg({p})");
        }
    }
    s.push('\n');
    let g: Vec<Vec<Vec<_>>> = freqs.iter().map(|&f| ss.frequency_response(f)).collect();
    let mut cols: Vec<Vec<(f64, f64)>> = Vec::with_capacity(no * ni);
    for o in 0..no {
        for j in 0..ni {
            let seq: Vec<_> = g.iter().map(|gf| gf[o][j]).collect();
            cols.push(magnitude_phase(&seq));
        }
    }
    for (k, f) in freqs.iter().enumerate() {
        let _ = write!(s, "{}", num(*f));
        for c in &cols {
            let _ = write!(s, ",{},{}", num(c[k].0), num(c[k].1));
        }
        s.push('\n');
    }
    if let Some(stop) = stop {
        s += &stop.csv_comment();
    }
    s
}

/// Short text summary: modes kept, inputs and outputs with their numbers, the DC gain.
pub fn statespace_text(model: &Model, origin: Origin, ss: &StateSpace) -> String {
    let mut s = String::new();
    s.push_str(&crate::report::heading("statespace", model, origin.file));
    let n = ss.n_modes();
    let _ = writeln!(
        s,
        "linearised at step {} (load factor {:.4}); {} degrees of freedom, {} eigen solver{}",
        origin.step,
        origin.load_factor,
        ss.ndof,
        ss.solver.name(),
        if ss.massless > 0 {
            format!(
                ", {} massless direction(s) condensed statically (their static response is in D)",
                ss.massless
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        s,
        "{n} of {} modes kept: {} states (eta_1..eta_{n}, then their rates{}); modal damping ratio {}{}\n",
        ss.available_modes,
        ss.n_states(),
        if ss.motions.is_empty() {
            String::new()
        } else {
            format!(
                ", then u, du of the {} prescribed-motion input(s)",
                ss.motions.len()
            )
        },
        ss.damping,
        if ss.static_correction && n < ss.available_modes {
            "; D carries the static correction of the dropped modes"
        } else {
            ""
        }
    );
    let modes: Vec<Vec<String>> = ss
        .frequencies()
        .iter()
        .zip(&ss.eigenvalues)
        .enumerate()
        .map(|(k, (f, l))| {
            vec![
                (k + 1).to_string(),
                if f.is_nan() {
                    format!("complex (ω² = {})", fmt_num(*l))
                } else {
                    fmt_num(*f)
                },
            ]
        })
        .collect();
    s += &table(&["mode", "f [Hz]"], &modes);
    s.push('\n');
    let ins: Vec<Vec<String>> = ss
        .input_info(model)
        .into_iter()
        .enumerate()
        .map(|(k, i)| vec![format!("u{}", k + 1), i.name, i.description, i.unit.into()])
        .collect();
    s += &table(&["input", "name", "meaning", "unit"], &ins);
    s.push('\n');
    let outs: Vec<Vec<String>> = ss
        .outputs
        .iter()
        .enumerate()
        .map(|(k, o)| {
            vec![
                format!("y{}", k + 1),
                o.name(model),
                o.describe(model),
                o.unit(model).into(),
            ]
        })
        .collect();
    s += &table(&["output", "name", "meaning", "unit"], &outs);
    match ss.dc_gain() {
        Ok(g) => {
            s += "\nstatic (DC) gain −C A⁻¹ B + D (rows: outputs, columns: inputs):\n";
            let mut header = vec!["".to_string()];
            header.extend((1..=ss.n_inputs()).map(|k| format!("u{k}")));
            let hdr: Vec<&str> = header.iter().map(String::as_str).collect();
            let g = rows(&g);
            let table_rows: Vec<Vec<String>> = (0..ss.outputs.len())
                .map(|o| {
                    let mut r = vec![format!("y{}", o + 1)];
                    r.extend((0..ss.n_inputs()).map(|j| fmt_num(g[o][j])));
                    r
                })
                .collect();
            s += &table(&hdr, &table_rows);
            if !ss.motions.is_empty() {
                let first = ss.inputs.len() + 1;
                let _ = writeln!(
                    s,
                    "  (columns u{first}..u{}: prescribed motions; their input is the acceleration, so the column is the quasi-static response per unit enforced displacement, output unit per m, or per rad for a rotation or a hinge angle)",
                    ss.n_inputs()
                );
            }
            if ss.n_modes() < ss.available_modes
                && !ss.static_correction
                && ss.outputs.iter().any(|o| o.kind == OutputKind::Disp)
            {
                s += "  (truncated model: this misses the static flexibility of the dropped modes; keep all modes or use --static-correction to match the static compliance)\n";
            }
        }
        Err(e) => {
            let _ = writeln!(s, "\nno static gain: {e}");
        }
    }
    for w in &ss.warnings {
        let _ = writeln!(s, "\nwarning: {w}");
    }
    if let Some(stop) = origin.stopped {
        s += &stop.text();
    }
    s
}

/// Node names and axes for the sweep reports.
const AXES: [&str; 6] = ["x", "y", "z", "rx", "ry", "rz"];

fn stiffness(c: &flexmbd_core::statics::linear::Compliance, local: bool) -> [f64; 6] {
    // 1/C_ii as `flexmbd static` reports it: infinite where a support or input holds the
    // direction (global axes; in local axes of a rotated node a held direction shows as a very
    // large number)
    if local {
        c.stiffness_local()
    } else {
        c.stiffness_global()
    }
}

fn fmt_k(v: f64) -> String {
    if v.is_infinite() {
        "held".into()
    } else {
        fmt_num(v)
    }
}

/// Sweep as a text table: step, load factor, f1..fN, then k_x..k_rz of every node; `stop`
/// marks a static path that stopped part-way (the table holds its converged steps).
pub fn sweep_text(
    model: &Model,
    file: &str,
    points: &[SweepPoint],
    count: usize,
    nodes: &[String],
    local: bool,
    stop: Option<&StopNote>,
) -> String {
    let mut s = String::new();
    s.push_str(&crate::report::heading("sweep", model, file));
    let mut header: Vec<String> = vec!["step".into(), "load factor".into()];
    header.extend((1..=count).map(|k| format!("f{k} [Hz]")));
    for n in nodes {
        header.extend(AXES.iter().map(|a| format!("{n} k_{a}")));
    }
    let mut notes = Vec::new();
    let rows: Vec<Vec<String>> = points
        .iter()
        .map(|p| {
            let mut r = vec![p.step.to_string(), format!("{:.4}", p.load_factor)];
            match p.frequencies() {
                Some(f) => r.extend((0..count).map(|k| {
                    f.get(k).map_or("-".into(), |v| {
                        if v.is_nan() {
                            "complex".into()
                        } else {
                            fmt_num(*v)
                        }
                    })
                })),
                None => {
                    if let Err(e) = &p.eigenvalues {
                        notes.push(format!("step {}: modes: {e}", p.step));
                    }
                    r.extend((0..count).map(|_| "-".to_string()));
                }
            }
            for (c, n) in p.compliance.iter().zip(nodes) {
                match c {
                    Ok(c) => r.extend(stiffness(c, local).iter().map(|&v| fmt_k(v))),
                    Err(e) => {
                        notes.push(format!("step {}: compliance of `{n}`: {e}", p.step));
                        r.extend((0..6).map(|_| "-".to_string()));
                    }
                }
            }
            r
        })
        .collect();
    let hdr: Vec<&str> = header.iter().map(String::as_str).collect();
    s += &table(&hdr, &rows);
    if !nodes.is_empty() {
        let _ = writeln!(
            s,
            "\n  (support stiffness 1/C_ii in {} axes: N/m for x, y, z; N·m/rad for rx, ry, rz; held: a support or prescribed input holds that direction)",
            if local { "the node's local" } else { "global" }
        );
    }
    if points.iter().any(|p| {
        p.eigenvalues
            .as_ref()
            .is_ok_and(|l| l.iter().skip(p.rigid_body).any(|&v| v < 0.0))
    }) {
        s += "\nwarning: negative eigenvalues (complex frequencies): the equilibrium is unstable there (the structure may have buckled)\n";
    }
    for n in notes {
        let _ = writeln!(s, "warning: {n}");
    }
    if let Some(stop) = stop {
        s += &stop.text();
    }
    s
}

/// Sweep as JSON: per step the frequencies and, per node, the stiffness in global and local
/// axes (null where held) and the 6 × 6 compliance; `stopped` as in `flexmbd static --json`.
pub fn sweep_json(
    model: &Model,
    file: &str,
    points: &[SweepPoint],
    nodes: &[String],
    stop: Option<&StopNote>,
) -> Value {
    let steps: Vec<Value> = points
        .iter()
        .map(|p| {
            let comp: Vec<Value> = p
                .compliance
                .iter()
                .zip(nodes)
                .map(|(c, n)| match c {
                    Ok(c) => json!({
                        "node": n,
                        "stiffness_global": stiffness(c, false).map(finite_or_null),
                        "stiffness_local": stiffness(c, true).map(finite_or_null),
                        "held": c.held,
                        "global": c.global,
                        "local": c.local,
                    }),
                    Err(e) => json!({ "node": n, "error": e.to_string() }),
                })
                .collect();
            json!({
                "step": p.step,
                "load_factor": p.load_factor,
                "frequencies_hz": p.frequencies().map(|f| f.into_iter().map(finite_or_null).collect::<Vec<_>>()),
                "eigenvalues": p.eigenvalues.as_ref().ok(),
                "modes_error": p.eigenvalues.as_ref().err().map(|e| e.to_string()),
                "compliance": comp,
            })
        })
        .collect();
    json!({
        "file": file,
        "model": model.name,
        "steps": steps,
        "stopped": crate::stopped::json_field(stop),
    })
}

/// Sweep as CSV: `step,load_factor,f1_hz..fN_hz,NODE:k_x..NODE:k_rz`; empty cells where a
/// value is unavailable, `inf` where held; `stop` ends it with a comment line.
pub fn sweep_csv(
    points: &[SweepPoint],
    count: usize,
    nodes: &[String],
    local: bool,
    stop: Option<&StopNote>,
) -> String {
    let mut s = String::from("step,load_factor");
    for k in 1..=count {
        let _ = write!(s, ",f{k}_hz");
    }
    for n in nodes {
        for a in AXES {
            let _ = write!(s, ",{n}:k_{a}");
        }
    }
    s.push('\n');
    let cell = |v: f64| {
        if v.is_nan() {
            String::new()
        } else if v.is_infinite() {
            "inf".to_string()
        } else {
            num(v)
        }
    };
    for p in points {
        let _ = write!(s, "{},{}", p.step, num(p.load_factor));
        let f = p.frequencies().unwrap_or_default();
        for k in 0..count {
            let _ = write!(s, ",{}", f.get(k).map_or(String::new(), |&v| cell(v)));
        }
        for c in &p.compliance {
            match c {
                Ok(c) => {
                    for v in stiffness(c, local) {
                        let _ = write!(s, ",{}", cell(v));
                    }
                }
                Err(_) => s.push_str(",,,,,,"),
            }
        }
        s.push('\n');
    }
    if let Some(stop) = stop {
        s += &stop.csv_comment();
    }
    s
}
