//! The native TOML model format (docs/model-format.md).
//!
//! ```toml
//! [model]
//! name = "12-truss of the paper, Fig. 2"
//! [nodes]                       # id = position [m], or { x = [...], rot = true }, or { at = "s1" }
//! s1 = [1.0, 1.0, 0.0]
//! [fix]
//! s1 = "all"                    # or a list: ["x", "y", "z", "rx", "ry", "rz"]
//! [[truss]]
//! id = "b1"
//! nodes = ["s1", "t2"]
//! [[beam]]
//! id = "w1"
//! nodes = ["g1", "r1"]
//! orient = [0.0, 0.0, 1.0]      # local y axis
//! free = [2, 3, 4, 5, 6]        # deformation modes, numbered as in the paper
//! input = []
//! [[hinge]]
//! id = "h1"
//! nodes = ["a", "b"]
//! axis = [0.0, 0.0, 1.0]
//! free = [1]
//! [[rigid]]
//! id = "platform"
//! nodes = ["r1", "r2", "r3"]
//! [inputs]                      # nodal coordinates that are generalised coordinates
//! r1 = ["x"]
//! ```
//!
//! Units are SI. Unknown keys, missing fields, non-finite numbers, unknown nodes, duplicate ids
//! and degenerate elements are errors naming file, line and item.

use crate::error::{at, InputError};
use flexmbd_core::model::{Dof, ElementSpec, Item};
use flexmbd_core::{Model, ModelBuilder};
use indexmap::IndexMap;
use serde::Deserialize;
use std::collections::HashMap;
use std::ops::Range;
use toml::Spanned;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSpec {
    model: Option<ModelSection>,
    nodes: Option<IndexMap<String, Spanned<toml::Value>>>,
    fix: Option<IndexMap<String, Spanned<toml::Value>>>,
    inputs: Option<IndexMap<String, Spanned<toml::Value>>>,
    #[serde(default)]
    truss: Vec<Spanned<TrussSpec>>,
    #[serde(default)]
    beam: Vec<Spanned<BeamSpec>>,
    #[serde(default)]
    hinge: Vec<Spanned<HingeSpec>>,
    #[serde(default)]
    rigid: Vec<Spanned<RigidSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ModelSection {
    name: Option<String>,
    #[allow(dead_code)]
    description: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TrussSpec {
    id: String,
    nodes: Vec<String>,
    /// EA [N].
    #[serde(rename = "EA", default)]
    ea: f64,
    #[serde(default)]
    free: Vec<i64>,
    #[serde(default)]
    input: Vec<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BeamSpec {
    id: String,
    nodes: Vec<String>,
    orient: Option<[f64; 3]>,
    #[serde(default)]
    ct: f64,
    #[serde(default)]
    free: Vec<i64>,
    #[serde(default)]
    input: Vec<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct HingeSpec {
    id: String,
    nodes: Vec<String>,
    axis: [f64; 3],
    #[serde(default)]
    k: f64,
    #[serde(default)]
    free: Vec<i64>,
    #[serde(default)]
    input: Vec<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RigidSpec {
    id: String,
    nodes: Vec<String>,
}

/// Read and compile a TOML model file.
pub fn read_model(path: &std::path::Path) -> Result<Model, InputError> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| InputError::Read {
        file: file.clone(),
        source,
    })?;
    parse_model(&text, &file)
}

/// Parse and compile TOML model text; `file` names it in messages.
pub fn parse_model(text: &str, file: &str) -> Result<Model, InputError> {
    let spec: FileSpec = toml::from_str(text).map_err(|e| {
        let msg = e.message().trim().to_string();
        match e.span() {
            Some(span) => at(file, text, span.start, msg),
            None => InputError::File {
                file: file.into(),
                message: msg,
            },
        }
    })?;
    let name = spec
        .model
        .as_ref()
        .and_then(|m| m.name.clone())
        .unwrap_or_default();
    let mut b = ModelBuilder::new(&name);
    let mut spans: HashMap<Item, Range<usize>> = HashMap::new();
    let err = |span: &Range<usize>, msg: String| at(file, text, span.start, msg);

    // nodes
    let Some(nodes) = &spec.nodes else {
        return Err(InputError::File {
            file: file.into(),
            message: "the model has no [nodes] section".into(),
        });
    };
    for (id, v) in nodes {
        let span = v.span();
        let def = node_value(v.get_ref()).map_err(|m| err(&span, format!("node `{id}`: {m}")))?;
        spans.insert(Item::Node(id.clone()), span.clone());
        match def {
            NodeDef::At(x0, rot) => b.add_node(id, x0, rot),
            NodeDef::Hosted(host) => b.add_node_at(id, &host),
        }
        .map_err(|e| err(&span, e.to_string()))?;
    }

    // elements, in file order
    let mut elements: Vec<(
        Range<usize>,
        String,
        Vec<String>,
        ElementSpec,
        Vec<i64>,
        Vec<i64>,
    )> = Vec::new();
    for t in &spec.truss {
        let s = t.get_ref();
        elements.push((
            t.span(),
            s.id.clone(),
            s.nodes.clone(),
            ElementSpec::Truss { ea: s.ea },
            s.free.clone(),
            s.input.clone(),
        ));
    }
    for t in &spec.beam {
        let s = t.get_ref();
        let e = ElementSpec::Beam {
            orient: s.orient,
            ct: s.ct,
        };
        elements.push((
            t.span(),
            s.id.clone(),
            s.nodes.clone(),
            e,
            s.free.clone(),
            s.input.clone(),
        ));
    }
    for t in &spec.hinge {
        let s = t.get_ref();
        let e = ElementSpec::Hinge {
            axis: s.axis,
            k: s.k,
        };
        elements.push((
            t.span(),
            s.id.clone(),
            s.nodes.clone(),
            e,
            s.free.clone(),
            s.input.clone(),
        ));
    }
    for t in &spec.rigid {
        let s = t.get_ref();
        elements.push((
            t.span(),
            s.id.clone(),
            s.nodes.clone(),
            ElementSpec::Rigid,
            vec![],
            vec![],
        ));
    }
    elements.sort_by_key(|e| e.0.start);
    for (span, id, nodes, es, free, input) in elements {
        let refs: Vec<&str> = nodes.iter().map(String::as_str).collect();
        b.add_element(&id, &refs, es, &free, &input)
            .map_err(|e| err(&span, e.to_string()))?;
        spans.insert(Item::Element(id), span);
    }

    // supports and generalised coordinates
    for (section, list) in [("fix", &spec.fix), ("inputs", &spec.inputs)] {
        for (node, v) in list.iter().flat_map(|m| m.iter()) {
            let span = v.span();
            let dofs = dof_list(v.get_ref())
                .map_err(|m| err(&span, format!("{section} entry `{node}`: {m}")))?;
            let r = if section == "fix" {
                spans.insert(Item::Fix(node.clone()), span.clone());
                b.fix(node, dofs.as_deref())
            } else {
                spans.insert(Item::Input(node.clone()), span.clone());
                b.input(node, dofs.as_deref())
            };
            r.map_err(|e| err(&span, e.to_string()))?;
        }
    }

    b.build().map_err(|e| match spans.get(&e.item()) {
        Some(span) => err(span, e.to_string()),
        None => InputError::File {
            file: file.into(),
            message: e.to_string(),
        },
    })
}

fn vec3(v: &toml::Value, what: &str) -> Result<[f64; 3], String> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("`{what}` must be an array of 3 numbers"))?;
    if arr.len() != 3 {
        return Err(format!("`{what}` must have 3 numbers, found {}", arr.len()));
    }
    let mut out = [0.0; 3];
    for (i, a) in arr.iter().enumerate() {
        out[i] = match a {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(k) => *k as f64,
            other => return Err(format!("`{what}` entry {} is not a number: {other}", i + 1)),
        };
        if !out[i].is_finite() {
            return Err(format!(
                "`{what}` entry {} is not finite ({})",
                i + 1,
                out[i]
            ));
        }
    }
    Ok(out)
}

/// A node definition.
enum NodeDef {
    /// Own position, rotation asked for.
    At([f64; 3], bool),
    /// Shares the position of a host node, own rotation.
    Hosted(String),
}

/// A node: `[x, y, z]`, `{ x = [x, y, z], rot = bool }` or `{ at = "host" }`.
fn node_value(v: &toml::Value) -> Result<NodeDef, String> {
    match v {
        toml::Value::Array(_) => Ok(NodeDef::At(vec3(v, "position")?, false)),
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !["x", "rot", "at"].contains(&k.as_str()) {
                    return Err(format!("unknown key `{k}`, expected `x`, `rot` or `at`"));
                }
            }
            if let Some(host) = t.get("at") {
                let toml::Value::String(h) = host else {
                    return Err(format!("`at` must name a node, found {host}"));
                };
                if t.contains_key("x") {
                    return Err(
                        "give either `x` (own position) or `at` (a host node), not both".into(),
                    );
                }
                if let Some(toml::Value::Boolean(false)) = t.get("rot") {
                    return Err(
                        "a node `at` another always has its own rotation; remove `rot = false`"
                            .into(),
                    );
                }
                return Ok(NodeDef::Hosted(h.clone()));
            }
            let x = t
                .get("x")
                .ok_or("missing field `x` (the position) or `at` (a host node)")?;
            let rot = match t.get("rot") {
                None => false,
                Some(toml::Value::Boolean(b)) => *b,
                Some(other) => return Err(format!("`rot` must be true or false, found {other}")),
            };
            Ok(NodeDef::At(vec3(x, "x")?, rot))
        }
        other => Err(format!(
            "expected a position [x, y, z] or a table {{ x = [...] }}, found {other}"
        )),
    }
}

/// "all" (None) or a list of dof names.
fn dof_list(v: &toml::Value) -> Result<Option<Vec<Dof>>, String> {
    let bad = |s: &str| {
        format!("unknown degree of freedom `{s}`, expected one of x, y, z, rx, ry, rz or \"all\"")
    };
    match v {
        toml::Value::String(s) if s == "all" => Ok(None),
        toml::Value::String(s) => Dof::parse(s).map(|d| Some(vec![d])).ok_or_else(|| bad(s)),
        toml::Value::Array(a) => a
            .iter()
            .map(|x| match x {
                toml::Value::String(s) => Dof::parse(s).ok_or_else(|| bad(s)),
                other => Err(format!("expected a degree-of-freedom name, found {other}")),
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some),
        other => Err(format!(
            "expected \"all\" or a list like [\"x\", \"rz\"], found {other}"
        )),
    }
}

#[cfg(test)]
mod tests;
