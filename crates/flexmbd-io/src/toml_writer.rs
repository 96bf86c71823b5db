//! A neutral model description ([`ModelSpec`]) that builds a core [`Model`] and serialises to
//! the native TOML format (docs/model-format.md), with comments.
//!
//! Readers of other formats (SPACAR `.dat`) produce a [`ModelSpec`]; [`ModelSpec::build`] and
//! [`write_toml`] then give the same model, so `flexmbd convert` followed by `flexmbd check` on
//! the TOML file gives the result of `flexmbd check` on the original file. Numbers are written
//! with full precision (Rust's shortest round-trip form).
//!
//! Besides the kinematic model (nodes, elements, `[fix]`, `[inputs]`) a spec carries the data of
//! a static analysis: beam constants, modes kept rigid in statics, loads, point masses,
//! prescribed input values, gravity and load-step settings. [`ModelSpec::build`] builds all of
//! it (the kinematic check ignores the static data); [`ModelSpec::build_static`] builds the
//! model for `flexmbd static`, without the `dynamic_inputs` (SPACAR's `DYNX` coordinates, which
//! are inputs of the kinematic check but unknowns of an equilibrium).

use crate::model_toml::{ModelFile, Settings};
use flexmbd_core::model::{Dof, ElementSpec, Item};
use flexmbd_core::section::BeamProps;
use flexmbd_core::{Model, ModelBuilder, ModelError};
use std::collections::HashMap;
use std::fmt::Write;

/// Where a node is.
#[derive(Clone, Debug, PartialEq)]
pub enum NodePlace {
    /// Own position (m); `rot` asks for rotation coordinates.
    Position {
        /// Position.
        x: [f64; 3],
        /// Rotation coordinates asked for.
        rot: bool,
    },
    /// At the position of a host node, with its own rotation.
    At(String),
}

/// A node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeSpec {
    /// Name.
    pub name: String,
    /// Position or host.
    pub place: NodePlace,
    /// Comment written after the node.
    pub comment: Option<String>,
    /// Source line, for error messages.
    pub line: Option<usize>,
}

/// An element.
#[derive(Clone, Debug)]
pub struct ElementEntrySpec {
    /// Name (id).
    pub name: String,
    /// Node names.
    pub nodes: Vec<String>,
    /// Type and data.
    pub spec: ElementSpec,
    /// Free (released) modes, 1-based.
    pub free: Vec<i64>,
    /// Input modes (generalised deformations), 1-based.
    pub input: Vec<i64>,
    /// Modes kept rigid in statics although they have stiffness (TOML `fixed`; beams only).
    pub rigid: Vec<i64>,
    /// Stiffness and mass constants of a beam (TOML `EA`, `GJ`, `EIy`, `EIz`, `rho_a`; the
    /// shear flexibilities and rotary inertias are built but cannot be written).
    pub props: Option<BeamProps>,
    /// Comment lines written above the element.
    pub comments: Vec<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// A `[fix]` or `[inputs]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct DofEntry {
    /// Node name.
    pub node: String,
    /// Degrees of freedom.
    pub dofs: Vec<Dof>,
    /// Comment written after the entry.
    pub comment: Option<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// A dead nodal load at load factor 1 (`[[load]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct LoadEntry {
    /// Node name.
    pub node: String,
    /// Force (N), global axes.
    pub force: [f64; 3],
    /// Moment [N·m], global axes.
    pub moment: [f64; 3],
    /// Comment lines written above the entry.
    pub comments: Vec<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// A point mass (`[[mass]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct MassEntry {
    /// Node name.
    pub node: String,
    /// Mass (kg).
    pub m: f64,
    /// Comment lines written above the entry.
    pub comments: Vec<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// An inertia tensor about a rotational node (`[[inertia]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct InertiaEntry {
    /// Node name.
    pub node: String,
    /// [Ixx, Ixy, Ixz, Iyy, Iyz, Izz] [kg·m²], global axes in the reference orientation.
    pub i: [f64; 6],
    /// Comment lines written above the entry.
    pub comments: Vec<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// What a prescribed value applies to.
#[derive(Clone, Debug, PartialEq)]
pub enum PrescribeTarget {
    /// A nodal coordinate: displacement (m) or rotation angle φ (rad), λ_i = sin(φ/2).
    Coordinate {
        /// Node name.
        node: String,
        /// Degree of freedom.
        dof: Dof,
    },
    /// A deformation mode (1-based) of an element.
    Deformation {
        /// Element name.
        element: String,
        /// Mode, 1-based.
        mode: usize,
    },
}

/// A prescribed final value of an input (`[[prescribe]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct PrescribeEntry {
    /// Coordinate or deformation.
    pub target: PrescribeTarget,
    /// Final value, reached at load factor 1.
    pub value: f64,
    /// Comment lines written above the entry.
    pub comments: Vec<String>,
    /// Source line.
    pub line: Option<usize>,
}

/// Settings of a static analysis (`[static]`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StaticSpec {
    /// Load steps.
    pub steps: Option<usize>,
    /// Relative residual tolerance.
    pub tol_force: Option<f64>,
    /// Gravitational acceleration (m/s²).
    pub gravity: Option<[f64; 3]>,
    /// Comment lines written above the section.
    pub comments: Vec<String>,
    /// Source line (of the gravity, for errors).
    pub line: Option<usize>,
}

impl StaticSpec {
    fn is_empty(&self) -> bool {
        self.steps.is_none() && self.tol_force.is_none() && self.gravity.is_none()
    }
}

/// A model in neutral form.
#[derive(Clone, Debug, Default)]
pub struct ModelSpec {
    /// Model name.
    pub name: String,
    /// Comment lines at the top of the file.
    pub header: Vec<String>,
    /// Nodes, hosts before the nodes placed at them.
    pub nodes: Vec<NodeSpec>,
    /// Elements, in order.
    pub elements: Vec<ElementEntrySpec>,
    /// Supports.
    pub fix: Vec<DofEntry>,
    /// Generalised coordinates.
    pub inputs: Vec<DofEntry>,
    /// Generalised coordinates of the kinematic check that are unknowns in statics (SPACAR's
    /// dynamic degrees of freedom `DYNX`); written into `[inputs]`.
    pub dynamic_inputs: Vec<DofEntry>,
    /// Dead loads.
    pub loads: Vec<LoadEntry>,
    /// Point masses.
    pub masses: Vec<MassEntry>,
    /// Inertia tensors of rotational nodes.
    pub inertias: Vec<InertiaEntry>,
    /// Prescribed input values.
    pub prescribed: Vec<PrescribeEntry>,
    /// Static analysis settings.
    pub statics: StaticSpec,
    /// Comment lines at the end of the file.
    pub footer: Vec<String>,
}

/// A model error with the source line of the item it concerns.
#[derive(Clone, Debug, PartialEq)]
pub struct SpecError {
    /// The error.
    pub error: ModelError,
    /// Source line of the item, if known.
    pub line: Option<usize>,
}

impl ModelSpec {
    /// Build the core model with every input, including the `dynamic_inputs` (what the TOML
    /// file written by [`write_toml`] gives).
    pub fn build(&self) -> Result<Model, SpecError> {
        self.builder(true)
    }

    /// Build the model for a static analysis: the `dynamic_inputs` are unknowns, not inputs.
    pub fn build_static(&self) -> Result<ModelFile, SpecError> {
        let model = self.builder(false)?;
        Ok(ModelFile {
            model,
            settings: Settings {
                steps: self.statics.steps,
                tol_force: self.statics.tol_force,
                ..Default::default()
            },
            simulate: Default::default(),
        })
    }

    fn builder(&self, dynamic_inputs: bool) -> Result<Model, SpecError> {
        let mut b = ModelBuilder::new(&self.name);
        let mut lines: HashMap<Item, Option<usize>> = HashMap::new();
        let fail = |line: Option<usize>| move |error| SpecError { error, line };
        for n in &self.nodes {
            match &n.place {
                NodePlace::Position { x, rot } => b.add_node(&n.name, *x, *rot),
                NodePlace::At(host) => b.add_node_at(&n.name, host),
            }
            .map_err(fail(n.line))?;
            lines.insert(Item::Node(n.name.clone()), n.line);
        }
        for e in &self.elements {
            let refs: Vec<&str> = e.nodes.iter().map(String::as_str).collect();
            b.add_element(&e.name, &refs, e.spec.clone(), &e.free, &e.input)
                .map_err(fail(e.line))?;
            lines.insert(Item::Element(e.name.clone()), e.line);
        }
        for e in &self.elements {
            if let Some(p) = e.props {
                b.set_beam_props(&e.name, p).map_err(fail(e.line))?;
            }
            if !e.rigid.is_empty() {
                b.set_rigid_modes(&e.name, &e.rigid).map_err(fail(e.line))?;
            }
        }
        for f in &self.fix {
            b.fix(&f.node, Some(&f.dofs)).map_err(fail(f.line))?;
            lines.entry(Item::Fix(f.node.clone())).or_insert(f.line);
        }
        let dynamic: &[DofEntry] = if dynamic_inputs {
            &self.dynamic_inputs
        } else {
            &[]
        };
        for i in self.inputs.iter().chain(dynamic) {
            b.input(&i.node, Some(&i.dofs)).map_err(fail(i.line))?;
            lines.entry(Item::Input(i.node.clone())).or_insert(i.line);
        }
        for l in &self.loads {
            b.add_load(&l.node, l.force, l.moment)
                .map_err(fail(l.line))?;
            lines.entry(Item::Load(l.node.clone())).or_insert(l.line);
        }
        for m in &self.masses {
            b.add_point_mass(&m.node, m.m).map_err(fail(m.line))?;
            lines.entry(Item::Mass(m.node.clone())).or_insert(m.line);
        }
        for m in &self.inertias {
            b.add_inertia(&m.node, m.i).map_err(fail(m.line))?;
            lines.entry(Item::Mass(m.node.clone())).or_insert(m.line);
        }
        for p in &self.prescribed {
            match &p.target {
                PrescribeTarget::Coordinate { node, dof } => {
                    b.prescribe_coordinate(node, *dof, p.value)
                        .map_err(fail(p.line))?;
                    lines.entry(Item::Input(node.clone())).or_insert(p.line);
                }
                PrescribeTarget::Deformation { element, mode } => b
                    .prescribe_deformation(element, *mode, p.value)
                    .map_err(fail(p.line))?,
            }
        }
        if let Some(g) = self.statics.gravity {
            b.set_gravity(g).map_err(fail(self.statics.line))?;
            lines.insert(Item::Model, self.statics.line);
        }
        b.build().map_err(|error| SpecError {
            line: lines.get(&error.item()).copied().flatten(),
            error,
        })
    }
}

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

fn vec3(v: &[f64; 3]) -> String {
    format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]))
}

fn int_list(v: &[i64]) -> String {
    let items: Vec<String> = v.iter().map(i64::to_string).collect();
    format!("[{}]", items.join(", "))
}

fn dof_list(v: &[Dof]) -> String {
    let items: Vec<String> = v.iter().map(|d| quote(d.name())).collect();
    format!("[{}]", items.join(", "))
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

/// Serialise to the native TOML format. Fails only for what the format cannot express (free
/// or input modes of a rigid body).
pub fn write_toml(spec: &ModelSpec) -> Result<String, String> {
    let mut out = String::new();
    for h in &spec.header {
        comment(&mut out, "", h);
    }
    if !spec.header.is_empty() {
        out.push('\n');
    }
    let _ = writeln!(out, "[model]\nname = {}\n", quote(&spec.name));
    out.push_str("[nodes]\n");
    for n in &spec.nodes {
        let value = match &n.place {
            NodePlace::Position { x, rot: false } => vec3(x),
            NodePlace::Position { x, rot: true } => format!("{{ x = {}, rot = true }}", vec3(x)),
            NodePlace::At(h) => format!("{{ at = {} }}", quote(h)),
        };
        let _ = write!(out, "{} = {value}", quote(&n.name));
        trailing(&mut out, &n.comment);
    }
    let inputs: Vec<DofEntry> = spec
        .inputs
        .iter()
        .chain(&spec.dynamic_inputs)
        .cloned()
        .collect();
    for (section, list) in [("fix", &spec.fix), ("inputs", &inputs)] {
        if list.is_empty() {
            continue;
        }
        let _ = writeln!(out, "\n[{section}]");
        // one key per node: merge repeated entries
        let mut merged: Vec<DofEntry> = Vec::new();
        for e in list {
            match merged.iter_mut().find(|m| m.node == e.node) {
                Some(m) => {
                    for d in &e.dofs {
                        if !m.dofs.contains(d) {
                            m.dofs.push(*d);
                        }
                    }
                    m.comment = match (&m.comment, &e.comment) {
                        (Some(a), Some(b)) => Some(format!("{a}; {b}")),
                        (a, b) => a.clone().or(b.clone()),
                    };
                }
                None => merged.push(e.clone()),
            }
        }
        for e in &mut merged {
            e.dofs.sort();
            let _ = write!(out, "{} = {}", quote(&e.node), dof_list(&e.dofs));
            trailing(&mut out, &e.comment);
        }
    }
    for e in &spec.elements {
        out.push('\n');
        for c in &e.comments {
            comment(&mut out, "", c);
        }
        let (table, extra) = match &e.spec {
            ElementSpec::Truss { ea } => (
                "truss",
                if *ea != 0.0 {
                    format!("EA = {}\n", num(*ea))
                } else {
                    String::new()
                },
            ),
            ElementSpec::Beam { orient, ct } => {
                let mut s = String::new();
                if let Some(o) = orient {
                    let _ = writeln!(s, "orient = {}", vec3(o));
                }
                if *ct != 0.0 {
                    let _ = writeln!(s, "ct = {}", num(*ct));
                }
                if let Some(p) = &e.props {
                    // all four, so that the reader sees constants given directly
                    for (key, v) in [("EA", p.ea), ("GJ", p.gj), ("EIy", p.eiy), ("EIz", p.eiz)] {
                        let _ = writeln!(s, "{key} = {}", num(v));
                    }
                    if p.rho_a != 0.0 {
                        let _ = writeln!(s, "rho_a = {}", num(p.rho_a));
                    }
                }
                ("beam", s)
            }
            ElementSpec::Hinge { axis, k } => {
                let mut s = format!("axis = {}\n", vec3(axis));
                if *k != 0.0 {
                    let _ = writeln!(s, "k = {}", num(*k));
                }
                ("hinge", s)
            }
            ElementSpec::Rigid => {
                if !e.free.is_empty() || !e.input.is_empty() {
                    return Err(format!(
                        "element `{}`: the TOML format has no free or input modes for a rigid body",
                        e.name
                    ));
                }
                ("rigid", String::new())
            }
        };
        if !matches!(e.spec, ElementSpec::Beam { .. }) && (!e.rigid.is_empty() || e.props.is_some())
        {
            return Err(format!(
                "element `{}`: the TOML format has beam constants and `fixed` modes for beams only",
                e.name
            ));
        }
        let nodes: Vec<String> = e.nodes.iter().map(|n| quote(n)).collect();
        let _ = write!(
            out,
            "[[{table}]]\nid = {}\nnodes = [{}]\n{extra}",
            quote(&e.name),
            nodes.join(", ")
        );
        if !e.free.is_empty() {
            let _ = writeln!(out, "free = {}", int_list(&e.free));
        }
        if !e.input.is_empty() {
            let _ = writeln!(out, "input = {}", int_list(&e.input));
        }
        if !e.rigid.is_empty() {
            let _ = writeln!(out, "fixed = {}", int_list(&e.rigid));
        }
    }
    write_static(&mut out, spec);
    if !spec.footer.is_empty() {
        out.push('\n');
        for f in &spec.footer {
            comment(&mut out, "", f);
        }
    }
    Ok(out)
}

/// `[[load]]`, `[[mass]]`, `[[inertia]]`, `[[prescribe]]` and `[static]`.
fn write_static(out: &mut String, spec: &ModelSpec) {
    for l in &spec.loads {
        out.push('\n');
        for c in &l.comments {
            comment(out, "", c);
        }
        let _ = writeln!(out, "[[load]]\nnode = {}", quote(&l.node));
        if l.force != [0.0; 3] {
            let _ = writeln!(out, "force = {}", vec3(&l.force));
        }
        if l.moment != [0.0; 3] {
            let _ = writeln!(out, "moment = {}", vec3(&l.moment));
        }
    }
    for m in &spec.masses {
        out.push('\n');
        for c in &m.comments {
            comment(out, "", c);
        }
        let _ = writeln!(out, "[[mass]]\nnode = {}\nm = {}", quote(&m.node), num(m.m));
    }
    for m in &spec.inertias {
        out.push('\n');
        for c in &m.comments {
            comment(out, "", c);
        }
        let i: Vec<String> = m.i.iter().map(|v| num(*v)).collect();
        let _ = writeln!(
            out,
            "[[inertia]]\nnode = {}\nI = [{}]",
            quote(&m.node),
            i.join(", ")
        );
    }
    for p in &spec.prescribed {
        out.push('\n');
        for c in &p.comments {
            comment(out, "", c);
        }
        match &p.target {
            PrescribeTarget::Coordinate { node, dof } => {
                let _ = writeln!(
                    out,
                    "[[prescribe]]\nnode = {}\ndof = {}",
                    quote(node),
                    quote(dof.name())
                );
            }
            PrescribeTarget::Deformation { element, mode } => {
                let _ = writeln!(
                    out,
                    "[[prescribe]]\nelement = {}\nmode = {mode}",
                    quote(element)
                );
            }
        }
        let _ = writeln!(out, "value = {}", num(p.value));
    }
    let st = &spec.statics;
    if !st.is_empty() {
        out.push('\n');
        for c in &st.comments {
            comment(out, "", c);
        }
        out.push_str("[static]\n");
        if let Some(n) = st.steps {
            let _ = writeln!(out, "steps = {n}");
        }
        if let Some(t) = st.tol_force {
            let _ = writeln!(out, "tol_force = {}", num(t));
        }
        if let Some(g) = &st.gravity {
            let _ = writeln!(out, "gravity = {}", vec3(g));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_what_the_reader_reads() {
        let spec = ModelSpec {
            name: "a \"quoted\" name\\".into(),
            header: vec!["two\nlines".into()],
            nodes: vec![
                NodeSpec {
                    name: "1".into(),
                    place: NodePlace::Position {
                        x: [0.0, 0.0, 0.0],
                        rot: false,
                    },
                    comment: Some("first".into()),
                    line: Some(1),
                },
                NodeSpec {
                    name: "1@2".into(),
                    place: NodePlace::At("1".into()),
                    comment: None,
                    line: Some(1),
                },
                NodeSpec {
                    name: "3".into(),
                    place: NodePlace::Position {
                        x: [-2.5e20, 1e-7, 0.1],
                        rot: true,
                    },
                    comment: None,
                    line: Some(2),
                },
            ],
            elements: vec![ElementEntrySpec {
                name: "1".into(),
                nodes: vec!["1@2".into(), "3".into()],
                spec: ElementSpec::Beam {
                    orient: Some([0.0, 0.0, 1.0]),
                    ct: 0.0,
                },
                free: vec![2, 3],
                input: vec![4],
                rigid: vec![5],
                props: Some(BeamProps {
                    ea: 1e6,
                    gj: 2.0,
                    eiy: 3.0,
                    eiz: 0.0,
                    rho_a: 0.25,
                    ..Default::default()
                }),
                comments: vec!["BEAM 1".into()],
                line: Some(3),
            }],
            fix: vec![
                DofEntry {
                    node: "1".into(),
                    dofs: vec![Dof::Y, Dof::X],
                    comment: Some("FIX 1 1 2".into()),
                    line: Some(4),
                },
                DofEntry {
                    node: "1".into(),
                    dofs: vec![Dof::Z],
                    comment: Some("FIX 1 3".into()),
                    line: Some(5),
                },
            ],
            dynamic_inputs: vec![DofEntry {
                node: "3".into(),
                dofs: vec![Dof::Z],
                comment: None,
                line: Some(6),
            }],
            loads: vec![LoadEntry {
                node: "1@2".into(),
                force: [0.0, 1.0, 0.0],
                moment: [0.0, 0.0, 0.5],
                comments: vec!["a load".into()],
                line: Some(7),
            }],
            masses: vec![MassEntry {
                node: "3".into(),
                m: 0.5,
                comments: vec![],
                line: Some(8),
            }],
            prescribed: vec![
                PrescribeEntry {
                    target: PrescribeTarget::Coordinate {
                        node: "3".into(),
                        dof: Dof::Rz,
                    },
                    value: 0.1,
                    comments: vec![],
                    line: Some(9),
                },
                PrescribeEntry {
                    target: PrescribeTarget::Deformation {
                        element: "1".into(),
                        mode: 4,
                    },
                    value: -1e-3,
                    comments: vec![],
                    line: Some(10),
                },
            ],
            statics: StaticSpec {
                steps: Some(3),
                tol_force: Some(1e-7),
                gravity: Some([0.0, -9.81, 0.0]),
                comments: vec!["settings".into()],
                line: Some(11),
            },
            footer: vec!["end".into()],
            ..Default::default()
        };
        let text = write_toml(&spec).unwrap();
        let a = spec.build().unwrap();
        let b = crate::parse_model_file(&text, "w.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(b.settings.steps, Some(3));
        assert_eq!(b.settings.tol_force, Some(1e-7));
        let b = b.model;
        assert_eq!(a.name, b.name);
        assert_eq!(a.nx, b.nx);
        assert_eq!(a.partition, b.partition);
        assert_eq!(a.loads, b.loads);
        assert_eq!(a.explicit_rigid, b.explicit_rigid);
        // the static build leaves the dynamic inputs free and carries the settings
        let st = spec.build_static().unwrap();
        assert_eq!(st.settings.steps, Some(3));
        let z = st.model.nodes[2].x_index(Dof::Z).unwrap();
        assert_eq!(st.model.partition.x[z], flexmbd_core::CoordKind::Free);
        assert_eq!(a.partition.x[z], flexmbd_core::CoordKind::Input);
        assert_eq!(b.nodes[2].x0, [-2.5e20, 1e-7, 0.1]);
        assert!(text.contains("\"1\" = [\"x\", \"y\", \"z\"]  # FIX 1 1 2; FIX 1 3"));
    }

    #[test]
    fn errors_carry_the_line() {
        let spec = ModelSpec {
            nodes: vec![NodeSpec {
                name: "1".into(),
                place: NodePlace::Position {
                    x: [0.0; 3],
                    rot: false,
                },
                comment: None,
                line: Some(7),
            }],
            fix: vec![DofEntry {
                node: "1".into(),
                dofs: vec![Dof::Rx],
                comment: None,
                line: Some(9),
            }],
            ..Default::default()
        };
        let e = spec.build().unwrap_err();
        assert_eq!(e.line, Some(9));
    }
}
