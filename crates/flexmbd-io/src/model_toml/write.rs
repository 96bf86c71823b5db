//! [`ModelSpec`] → TOML text (docs/model-format.md), with comments: the file reads back to
//! the same spec ([`super::parse_spec`]). Numbers are written with full precision (Rust's
//! shortest round-trip form).

use crate::spec::*;
use flexmbd_core::model::Dof;
use flexmbd_core::simulation::TimeFunction;
use std::fmt::Write;

/// A TOML basic string.
fn quote(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\t' => out.push_str("\\t"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A TOML float, full precision.
fn num(v: f64) -> String {
    // Debug gives the shortest form that reads back exactly, always with a `.` or an exponent
    format!("{v:?}")
}

fn int_list(v: &[i64]) -> String {
    let items: Vec<String> = v.iter().map(i64::to_string).collect();
    format!("[{}]", items.join(", "))
}

fn dof_list(v: &Option<Vec<Dof>>) -> String {
    match v {
        None => quote("all"),
        Some(v) => {
            let items: Vec<String> = v.iter().map(|d| quote(d.name())).collect();
            format!("[{}]", items.join(", "))
        }
    }
}

/// One comment line (line breaks inside become blanks).
/// Control characters (TOML forbids them in comments) are written as `\u{..}`.
fn comment(out: &mut String, indent: &str, text: &str) {
    let t = crate::error::printable(&text.replace(['\n', '\r'], " ")).into_owned();
    if t.is_empty() {
        out.push_str(indent);
        out.push_str("#\n");
    } else {
        let _ = writeln!(out, "{indent}# {t}");
    }
}

fn trailing(out: &mut String, c: &Option<String>) {
    if let Some(c) = c {
        let _ = write!(
            out,
            "  # {}",
            crate::error::printable(&c.replace(['\n', '\r'], " "))
        );
    }
    out.push('\n');
}

fn vec_n(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| num(*x)).collect();
    format!("[{}]", items.join(", "))
}

/// `key = value` lines of a table body.
#[derive(Default)]
struct Body(String);

impl Body {
    fn raw(&mut self, key: &str, value: String) {
        let _ = writeln!(self.0, "{key} = {value}");
    }
    fn num(&mut self, key: &str, v: Option<f64>) {
        if let Some(v) = v {
            self.raw(key, num(v));
        }
    }
    fn int(&mut self, key: &str, v: Option<usize>) {
        if let Some(v) = v {
            self.raw(key, v.to_string());
        }
    }
    fn vec(&mut self, key: &str, v: Option<&[f64]>) {
        if let Some(v) = v {
            self.raw(key, vec_n(v));
        }
    }
    fn text(&mut self, key: &str, v: Option<&str>) {
        if let Some(v) = v {
            self.raw(key, quote(v));
        }
    }
    fn ints(&mut self, key: &str, v: &[i64]) {
        if !v.is_empty() {
            self.raw(key, int_list(v));
        }
    }
    fn history(&mut self, key: &str, h: &Option<TimeFunction>) -> Result<(), String> {
        if let Some(h) = h {
            let v = toml::Value::try_from(h).map_err(|e| format!("`{key}`: {e}"))?;
            self.raw(key, v.to_string());
        }
        Ok(())
    }
}

/// A table (`[name]` or `[[name]]`) with its comment lines above it.
fn table(out: &mut String, header: &str, comments: &[String], body: Body) {
    out.push('\n');
    for c in comments {
        comment(out, "", c);
    }
    let _ = write!(out, "{header}\n{}", body.0);
}

/// A `[fix]` or `[inputs]` table: one key per node, repeated entries merged (their degrees of
/// freedom sorted).
fn dof_table(out: &mut String, section: &str, list: &[&DofEntry]) {
    if list.is_empty() {
        return;
    }
    let _ = writeln!(out, "\n[{section}]");
    let mut merged: Vec<(DofEntry, bool)> = Vec::new();
    for e in list {
        match merged.iter_mut().find(|m| m.0.node == e.node) {
            Some((m, again)) => {
                *again = true;
                m.dofs = match (&m.dofs, &e.dofs) {
                    (Some(a), Some(b)) => {
                        let mut d = a.clone();
                        d.extend(b.iter().filter(|x| !a.contains(x)));
                        Some(d)
                    }
                    _ => None,
                };
                m.comment = match (&m.comment, &e.comment) {
                    (Some(a), Some(b)) => Some(format!("{a}; {b}")),
                    (a, b) => a.clone().or(b.clone()),
                };
            }
            None => merged.push(((*e).clone(), false)),
        }
    }
    for (e, again) in &mut merged {
        if let (Some(d), true) = (&mut e.dofs, *again) {
            d.sort();
        }
        let _ = write!(out, "{} = {}", quote(&e.node), dof_list(&e.dofs));
        trailing(out, &e.comment);
    }
}

impl ModelSpec {
    /// The spec as a TOML model file; see [`write_toml`].
    pub fn to_toml(&self) -> Result<String, String> {
        write_toml(self)
    }
}

/// Serialise to the native TOML format. A parametric model is written as the member the spec
/// is: `[parameters]` with the values used and the evaluated numbers in every other place
/// (the expressions of the file it was read from are not kept). Fails only for what the format cannot express (free
/// or input modes of a rigid body, a history that is not a time function of the format).
/// The shear flexibilities and rotary inertias of beam constants given directly (SPACAR) are
/// not written (the format has no keys for them).
pub fn write_toml(spec: &ModelSpec) -> Result<String, String> {
    let mut out = String::new();
    for h in &spec.header {
        comment(&mut out, "", h);
    }
    if !spec.header.is_empty() {
        out.push('\n');
    }
    let _ = writeln!(out, "[model]\nname = {}", quote(&spec.name));
    if let Some(d) = &spec.description {
        let _ = writeln!(out, "description = {}", quote(d));
    }
    // the evaluated member: the parameters' values, and evaluated numbers everywhere else
    if !spec.parameters.is_empty() {
        out.push_str("\n[parameters]\n");
        for (name, v) in &spec.parameters {
            let _ = writeln!(out, "{name} = {}", num(*v));
        }
    }
    out.push_str("\n[nodes]\n");
    for n in &spec.nodes {
        let value = match &n.place {
            NodePlace::Position { x, rot: false } => vec_n(x),
            NodePlace::Position { x, rot: true } => format!("{{ x = {}, rot = true }}", vec_n(x)),
            NodePlace::At(h) => format!("{{ at = {} }}", quote(h)),
        };
        let _ = write!(out, "{} = {value}", quote(&n.name));
        trailing(&mut out, &n.comment);
    }
    dof_table(&mut out, "fix", &spec.fix.iter().collect::<Vec<_>>());
    let inputs: Vec<&DofEntry> = spec.inputs.iter().chain(&spec.dynamic_inputs).collect();
    dof_table(&mut out, "inputs", &inputs);
    for m in &spec.materials {
        let mut b = Body::default();
        b.text("id", Some(&m.name));
        b.num("E", Some(m.e));
        b.num("G", m.g);
        b.num("nu", m.nu);
        b.num("rho", Some(m.rho).filter(|r| *r != 0.0));
        b.num("damping", m.damping);
        table(&mut out, "[[material]]", &[], b);
    }
    for s in &spec.sections {
        let mut b = Body::default();
        b.text("id", Some(&s.name));
        match s.shape {
            ShapeSpec::Rectangle { w, t } => {
                b.text("shape", Some("rectangle"));
                b.num("w", Some(w));
                b.num("t", Some(t));
            }
            ShapeSpec::Circle { d } => {
                b.text("shape", Some("circle"));
                b.num("d", Some(d));
            }
            ShapeSpec::Tube { d_out, d_in } => {
                b.text("shape", Some("tube"));
                b.num("d_out", Some(d_out));
                b.num("d_in", Some(d_in));
            }
            ShapeSpec::General { a, iy, iz, j, k } => {
                b.text("shape", Some("general"));
                b.num("A", Some(a));
                b.num("Iy", Some(iy));
                b.num("Iz", Some(iz));
                b.num("J", Some(j));
                b.num("k", k);
            }
        }
        if !s.shear {
            b.raw("shear", "false".into());
        }
        table(&mut out, "[[section]]", &[], b);
    }
    for e in &spec.elements {
        let mut b = Body::default();
        b.text("id", Some(&e.name));
        let nodes: Vec<String> = e.nodes.iter().map(|n| quote(n)).collect();
        b.raw("nodes", format!("[{}]", nodes.join(", ")));
        match &e.kind {
            ElementKind::Truss { ea } => b.num("EA", Some(*ea).filter(|v| *v != 0.0)),
            ElementKind::Beam(s) => {
                b.vec("orient", s.orient.as_ref().map(|v| &v[..]));
                b.num("ct", s.ct);
                b.text("section", s.section.as_deref());
                b.text("material", s.material.as_deref());
                b.int("segments", s.segments);
                for (key, v) in [("EA", s.ea), ("GJ", s.gj), ("EIy", s.eiy), ("EIz", s.eiz)] {
                    b.num(key, v);
                }
                b.num("rho_a", s.rho_a);
            }
            ElementKind::Hinge { axis, k } => {
                b.vec("axis", Some(axis));
                b.num("k", Some(*k).filter(|v| *v != 0.0));
            }
            ElementKind::Rigid => {
                if e.damping.is_some() {
                    return Err(format!(
                        "element `{}`: a rigid body has no material damping",
                        e.name
                    ));
                }
                if !e.free.is_empty() || !e.input.is_empty() {
                    return Err(format!(
                        "element `{}`: the TOML format has no free or input modes for a rigid body",
                        e.name
                    ));
                }
            }
        }
        b.ints("free", &e.free);
        b.ints("input", &e.input);
        if let Some(s) = e.beam() {
            b.ints("fixed", &s.fixed);
        }
        b.num("damping", e.damping);
        table(&mut out, &format!("[[{}]]", e.kind.table()), &e.comments, b);
    }
    write_data(&mut out, spec)?;
    write_settings(&mut out, spec)?;
    if !spec.footer.is_empty() {
        out.push('\n');
        for f in &spec.footer {
            comment(&mut out, "", f);
        }
    }
    Ok(out)
}

/// `v` unless it is zero.
fn nonzero(v: &[f64; 3]) -> Option<&[f64]> {
    (*v != [0.0; 3]).then_some(&v[..])
}

/// `[[load]]`, `[[mass]]`, `[[inertia]]`, `[[prescribe]]`, `[[velocity]]` and `[[freedom]]`.
fn write_data(out: &mut String, spec: &ModelSpec) -> Result<(), String> {
    for l in &spec.loads {
        let mut b = Body::default();
        b.text("node", Some(&l.node));
        b.vec("force", nonzero(&l.force));
        b.vec("moment", nonzero(&l.moment));
        b.history("history", &l.history)?;
        table(out, "[[load]]", &l.comments, b);
    }
    for m in &spec.masses {
        let mut b = Body::default();
        b.text("node", Some(&m.node));
        b.num("m", Some(m.m));
        table(out, "[[mass]]", &m.comments, b);
    }
    for m in &spec.inertias {
        let mut b = Body::default();
        b.text("node", Some(&m.node));
        b.vec("I", Some(&m.i));
        table(out, "[[inertia]]", &m.comments, b);
    }
    for p in &spec.prescribed {
        let mut b = Body::default();
        match &p.target {
            PrescribeTarget::Coordinate { node, dof } => {
                b.text("node", Some(node));
                b.text("dof", Some(dof.name()));
            }
            PrescribeTarget::Deformation { element, mode } => {
                b.text("element", Some(element));
                b.int("mode", Some(*mode));
            }
        }
        b.num("value", Some(p.value));
        b.history("history", &p.history)?;
        table(out, "[[prescribe]]", &p.comments, b);
    }
    for v in &spec.velocities {
        let mut b = Body::default();
        b.text("node", Some(&v.node));
        b.vec("v", nonzero(&v.v));
        b.vec("omega", nonzero(&v.omega));
        table(out, "[[velocity]]", &[], b);
    }
    for f in &spec.freedoms {
        let mut b = Body::default();
        b.text("body", Some(&f.body));
        b.vec("translation", f.translation.as_ref().map(|t| &t[..]));
        if let Some(r) = &f.rotation {
            b.raw(
                "rotation",
                format!(
                    "{{ point = {}, axis = {}, pitch = {} }}",
                    vec_n(&r.point),
                    vec_n(&r.axis),
                    num(r.pitch)
                ),
            );
        }
        table(out, "[[freedom]]", &f.comments, b);
    }
    Ok(())
}

/// `[static]` and `[simulate]`.
fn write_settings(out: &mut String, spec: &ModelSpec) -> Result<(), String> {
    let st = &spec.statics;
    if !st.is_empty() {
        let mut b = Body::default();
        b.int("steps", st.steps);
        b.int("max_iterations", st.max_iterations);
        b.num("tol_force", st.tol_force);
        b.num("tol_disp", st.tol_disp);
        b.vec("gravity", st.gravity.as_ref().map(|v| &v[..]));
        b.vec("spin", st.spin.as_ref().map(|v| &v[..]));
        b.vec("spin_point", st.spin_point.as_ref().map(|v| &v[..]));
        if !st.compliance.is_empty() {
            let nodes: Vec<String> = st.compliance.iter().map(|n| quote(n)).collect();
            b.raw("compliance", format!("[{}]", nodes.join(", ")));
        }
        b.int("buckling", Some(st.buckling).filter(|n| *n != 0));
        if st.line_search {
            b.raw("line_search", "true".into());
        }
        if st.tangent_eigenvalues {
            b.raw("tangent_eigenvalues", "true".into());
        }
        b.text(
            "path",
            st.path.map(|p| match p {
                PathSpec::LoadSteps => "load-steps",
                PathSpec::ArcLength => "arc-length",
            }),
        );
        table(out, "[static]", &st.comments, b);
    }
    if let Some(s) = &spec.simulate {
        let mut b = Body::default();
        b.num("t_end", s.t_end);
        b.num("dt", s.dt);
        b.text(
            "step",
            s.step.map(|v| match v {
                StepSpec::Adaptive => "adaptive",
                StepSpec::Fixed => "fixed",
            }),
        );
        b.num("dt_min", s.dt_min);
        b.num("dt_max", s.dt_max);
        b.num("rho_inf", s.rho_inf);
        b.vec("tolerance", s.tolerance.as_ref().map(|v| &v[..]));
        b.num("output_step", s.output_step);
        b.int("max_iterations", s.max_iterations);
        b.vec("rayleigh", s.rayleigh.as_ref().map(|v| &v[..]));
        b.text(
            "start",
            s.start.map(|v| match v {
                StartSpec::Reference => "reference",
                StartSpec::Static => "static",
            }),
        );
        b.int("static_steps", s.static_steps);
        b.history("gravity_history", &s.gravity_history)?;
        table(out, "[simulate]", &s.comments, b);
    }
    Ok(())
}
