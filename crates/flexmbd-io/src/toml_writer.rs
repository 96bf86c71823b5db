//! A neutral model description ([`ModelSpec`]) that builds a core [`Model`] and serialises to
//! the native TOML format (docs/model-format.md), with comments.
//!
//! Readers of other formats (SPACAR `.dat`) produce a [`ModelSpec`]; [`ModelSpec::build`] and
//! [`write_toml`] then give the same model, so `flexmbd convert` followed by `flexmbd check` on
//! the TOML file gives the result of `flexmbd check` on the original file. Numbers are written
//! with full precision (Rust's shortest round-trip form).

use flexmbd_core::model::{Dof, ElementSpec, Item};
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
    /// Build the core model.
    pub fn build(&self) -> Result<Model, SpecError> {
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
        for f in &self.fix {
            b.fix(&f.node, Some(&f.dofs)).map_err(fail(f.line))?;
            lines.entry(Item::Fix(f.node.clone())).or_insert(f.line);
        }
        for i in &self.inputs {
            b.input(&i.node, Some(&i.dofs)).map_err(fail(i.line))?;
            lines.entry(Item::Input(i.node.clone())).or_insert(i.line);
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
fn comment(out: &mut String, indent: &str, text: &str) {
    let t = text.replace(['\n', '\r'], " ");
    if t.is_empty() {
        out.push_str(indent);
        out.push_str("#\n");
    } else {
        let _ = writeln!(out, "{indent}# {t}");
    }
}

fn trailing(out: &mut String, c: &Option<String>) {
    if let Some(c) = c {
        let _ = write!(out, "  # {}", c.replace(['\n', '\r'], " "));
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
    for (section, list) in [("fix", &spec.fix), ("inputs", &spec.inputs)] {
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
    }
    if !spec.footer.is_empty() {
        out.push('\n');
        for f in &spec.footer {
            comment(&mut out, "", f);
        }
    }
    Ok(out)
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
            inputs: vec![],
            footer: vec!["end".into()],
        };
        let text = write_toml(&spec).unwrap();
        let a = spec.build().unwrap();
        let b = crate::parse_model(&text, "w.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert_eq!(a.name, b.name);
        assert_eq!(a.nx, b.nx);
        assert_eq!(a.partition, b.partition);
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
