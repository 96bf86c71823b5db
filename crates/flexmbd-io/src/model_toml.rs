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
use crate::limits::{MAX_BUCKLING, MAX_ITERATIONS, MAX_SEGMENTS, MAX_STEPS};
use flexmbd_core::model::{Dof, ElementSpec, Item};
use flexmbd_core::section::{BeamProps, Material, Shape};
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
    #[serde(default)]
    material: Vec<Spanned<MaterialSpec>>,
    #[serde(default)]
    section: Vec<Spanned<SectionSpec>>,
    #[serde(default)]
    load: Vec<Spanned<LoadSpec>>,
    #[serde(default)]
    mass: Vec<Spanned<MassSpec>>,
    #[serde(default)]
    inertia: Vec<Spanned<InertiaSpec>>,
    #[serde(default)]
    prescribe: Vec<Spanned<PrescribeSpec>>,
    #[serde(rename = "static")]
    statics: Option<Spanned<StaticSpec>>,
    simulate: Option<Spanned<simulate::SimulateSpec>>,
    #[serde(default)]
    velocity: Vec<Spanned<simulate::VelocitySpec>>,
}

impl FileSpec {
    const SECTIONS: [&'static str; 16] = [
        "model",
        "nodes",
        "fix",
        "inputs",
        "truss",
        "beam",
        "hinge",
        "rigid",
        "material",
        "section",
        "load",
        "mass",
        "prescribe",
        "static",
        "simulate",
        "velocity",
    ];
}

/// `[[material]]`: E and G (or ν), density.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialSpec {
    id: String,
    #[serde(rename = "E")]
    e: f64,
    #[serde(rename = "G")]
    g: Option<f64>,
    nu: Option<f64>,
    #[serde(default)]
    rho: f64,
}

/// `[[section]]`: a shape with its dimensions [m], or properties given directly.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SectionSpec {
    id: String,
    shape: String,
    w: Option<f64>,
    t: Option<f64>,
    d: Option<f64>,
    d_out: Option<f64>,
    d_in: Option<f64>,
    #[serde(rename = "A")]
    a: Option<f64>,
    #[serde(rename = "Iy")]
    iy: Option<f64>,
    #[serde(rename = "Iz")]
    iz: Option<f64>,
    #[serde(rename = "J")]
    j: Option<f64>,
    k: Option<f64>,
    /// Include shear flexibility (Timoshenko); default true as SPACAR Light.
    #[serde(default = "yes")]
    shear: bool,
}

fn yes() -> bool {
    true
}

/// `[[load]]`: dead force and moment on a node at load factor 1.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LoadSpec {
    node: String,
    #[serde(default)]
    force: [f64; 3],
    #[serde(default)]
    moment: [f64; 3],
    /// φ(t) in a time simulation.
    history: Option<flexmbd_core::simulation::TimeFunction>,
}

/// `[[mass]]`: a point mass on a node.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MassSpec {
    node: String,
    m: f64,
}

/// `[[inertia]]`: an inertia tensor about a rotational node (global axes, reference
/// orientation), `I = [Ixx, Ixy, Ixz, Iyy, Iyz, Izz]` [kg·m²].
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InertiaSpec {
    node: String,
    #[serde(rename = "I")]
    i: [f64; 6],
}

/// `[[prescribe]]`: the final value of an input coordinate or deformation.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PrescribeSpec {
    node: Option<String>,
    dof: Option<String>,
    element: Option<String>,
    mode: Option<i64>,
    value: f64,
    /// φ(t) in a time simulation.
    history: Option<flexmbd_core::simulation::TimeFunction>,
}

/// `[static]`: solver settings and requested outputs.
#[derive(Deserialize, Default, Clone)]
#[serde(deny_unknown_fields)]
struct StaticSpec {
    steps: Option<usize>,
    max_iterations: Option<usize>,
    tol_force: Option<f64>,
    tol_disp: Option<f64>,
    #[serde(default)]
    gravity: [f64; 3],
    spin: Option<[f64; 3]>,
    spin_point: Option<[f64; 3]>,
    #[serde(default)]
    compliance: Vec<String>,
    #[serde(default)]
    buckling: usize,
    #[serde(default)]
    line_search: bool,
    path: Option<String>,
}

/// Analysis settings read from the model file (`[static]`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Settings {
    /// Load steps.
    pub steps: Option<usize>,
    /// Newton iterations per step.
    pub max_iterations: Option<usize>,
    /// Relative residual tolerance.
    pub tol_force: Option<f64>,
    /// Relative increment tolerance.
    pub tol_disp: Option<f64>,
    /// Nodes whose compliance is reported at every step.
    pub compliance: Vec<String>,
    /// Number of buckling multipliers reported at every step.
    pub buckling: usize,
    /// Backtracking line search in Newton.
    pub line_search: bool,
    /// How the path is followed (`path = "load-steps"` or `"arc-length"`).
    pub path: flexmbd_core::statics::PathMethod,
}

/// A model file: the model and its analysis settings.
#[derive(Clone, Debug)]
pub struct ModelFile {
    /// The compiled model.
    pub model: Model,
    /// Settings from `[static]`.
    pub settings: Settings,
    /// Settings from `[simulate]`, the histories and `[[velocity]]`.
    pub simulate: simulate::SimulateSettings,
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
    ct: Option<f64>,
    #[serde(default)]
    free: Vec<i64>,
    #[serde(default)]
    input: Vec<i64>,
    /// Modes rigid in statics although they have stiffness.
    #[serde(default)]
    fixed: Vec<i64>,
    section: Option<String>,
    material: Option<String>,
    /// Split into this many elements.
    segments: Option<usize>,
    #[serde(rename = "EA")]
    ea: Option<f64>,
    #[serde(rename = "GJ")]
    gj: Option<f64>,
    #[serde(rename = "EIy")]
    eiy: Option<f64>,
    #[serde(rename = "EIz")]
    eiz: Option<f64>,
    /// Mass per length ρA [kg/m] when the constants are given directly.
    rho_a: Option<f64>,
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

/// An element as read: (span, id, nodes, spec, free modes, input modes).
type PendingElement = (
    Range<usize>,
    String,
    Vec<String>,
    ElementSpec,
    Vec<i64>,
    Vec<i64>,
);

/// Read and compile a TOML model file.
pub fn read_model(path: &std::path::Path) -> Result<Model, InputError> {
    read_model_file(path).map(|f| f.model)
}

/// Read a file as UTF-8 text; bytes that are not UTF-8 are an error at their line and column.
fn read_text(path: &std::path::Path, file: &str) -> Result<String, InputError> {
    let bytes = std::fs::read(path).map_err(|source| InputError::Read {
        file: file.to_string(),
        source,
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let start = e.utf8_error().valid_up_to();
        let len = e.utf8_error().error_len().unwrap_or(bytes.len() - start);
        let bad: Vec<String> = bytes[start..start + len]
            .iter()
            .map(|b| format!("0x{b:02X}"))
            .collect();
        // the valid text before the bad bytes gives the line and column
        let before = String::from_utf8_lossy(&bytes[..start]);
        at(
            file,
            &before,
            before.len(),
            format!(
                "the file is not UTF-8: invalid byte {} at byte offset {start}; TOML files are UTF-8 (save the file as UTF-8)",
                bad.join(" ")
            ),
        )
    })
}

/// Parse and compile TOML model text; `file` names it in messages.
pub fn parse_model(text: &str, file: &str) -> Result<Model, InputError> {
    parse_model_file(text, file).map(|f| f.model)
}

/// Read a TOML model file with its analysis settings.
pub fn read_model_file(path: &std::path::Path) -> Result<ModelFile, InputError> {
    let file = path.display().to_string();
    let text = read_text(path, &file)?;
    parse_model_file(&text, &file)
}

/// Parse TOML model text with its analysis settings.
pub fn parse_model_file(text: &str, file: &str) -> Result<ModelFile, InputError> {
    let mut spec: FileSpec = toml::from_str(text).map_err(|e| {
        let msg = e.message().trim().to_string();
        match e.span() {
            Some(span) => at(file, text, span.start, name_item(text, span.start, msg)),
            None => InputError::File {
                file: file.into(),
                message: msg,
            },
        }
    })?;
    // the toml crate hands tables over in key order; file order is what the user wrote (and
    // what "defined before it" and the first error reported refer to)
    for map in [&mut spec.nodes, &mut spec.fix, &mut spec.inputs]
        .into_iter()
        .flatten()
    {
        map.sort_by_key(|_, v| v.span().start);
    }
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
    let mut elements: Vec<PendingElement> = Vec::new();
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
    // beams split into segments get intermediate nodes `id:1`, … and elements `id:1`, …
    let mut beam_props: Vec<(String, Range<usize>, &BeamSpec)> = Vec::new();
    for t in &spec.beam {
        let s = t.get_ref();
        let n = s.segments.unwrap_or(1);
        if n == 0 || n > MAX_SEGMENTS {
            return Err(err(
                &key_span(text, &t.span(), "segments"),
                format!(
                    "element `{}`: `segments` must be from 1 to {MAX_SEGMENTS} (the limit, docs/reliability.md), found {n}",
                    s.id
                ),
            ));
        }
        let e = ElementSpec::Beam {
            orient: s.orient,
            ct: s.ct.unwrap_or(0.0),
        };
        if n == 1 || s.nodes.len() != 2 {
            elements.push((
                t.span(),
                s.id.clone(),
                s.nodes.clone(),
                e,
                s.free.clone(),
                s.input.clone(),
            ));
            beam_props.push((s.id.clone(), t.span(), s));
            continue;
        }
        let pos = |name: &str| -> Option<[f64; 3]> {
            let v = nodes.get(name)?;
            match node_value(v.get_ref()).ok()? {
                NodeDef::At(x, _) => Some(x),
                NodeDef::Hosted(h) => match node_value(nodes.get(&h)?.get_ref()).ok()? {
                    NodeDef::At(x, _) => Some(x),
                    NodeDef::Hosted(_) => None,
                },
            }
        };
        let (Some(p), Some(q)) = (pos(&s.nodes[0]), pos(&s.nodes[1])) else {
            // unknown end nodes: let the builder report them
            elements.push((
                t.span(),
                s.id.clone(),
                s.nodes.clone(),
                e,
                s.free.clone(),
                s.input.clone(),
            ));
            beam_props.push((s.id.clone(), t.span(), s));
            continue;
        };
        let mut chain = vec![s.nodes[0].clone()];
        for k in 1..n {
            let f = k as f64 / n as f64;
            let name = format!("{}:{k}", s.id);
            let x = [
                p[0] + f * (q[0] - p[0]),
                p[1] + f * (q[1] - p[1]),
                p[2] + f * (q[2] - p[2]),
            ];
            b.add_node(&name, x, false)
                .map_err(|e| err(&t.span(), e.to_string()))?;
            spans.insert(Item::Node(name.clone()), t.span());
            chain.push(name);
        }
        chain.push(s.nodes[1].clone());
        for k in 0..n {
            let id = format!("{}:{}", s.id, k + 1);
            let pair = vec![chain[k].clone(), chain[k + 1].clone()];
            elements.push((
                t.span(),
                id.clone(),
                pair,
                e.clone(),
                s.free.clone(),
                s.input.clone(),
            ));
            beam_props.push((id, t.span(), s));
        }
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

    // materials, sections and beam constants
    let materials = read_materials(&spec, file, text)?;
    let sections = read_sections(&spec, file, text)?;
    for (id, span, s) in &beam_props {
        if let Some(props) = beam_constants(s, &materials, &sections)
            .map_err(|m| err(span, format!("element `{}`: {m}", s.id)))?
        {
            b.set_beam_props(id, props)
                .map_err(|e| err(span, e.to_string()))?;
        }
        if !s.fixed.is_empty() {
            b.set_rigid_modes(id, &s.fixed)
                .map_err(|e| err(span, e.to_string()))?;
        }
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

    // loads, masses, prescribed inputs
    for l in &spec.load {
        let s = l.get_ref();
        spans.insert(Item::Load(s.node.clone()), l.span());
        b.add_load(&s.node, s.force, s.moment)
            .map_err(|e| err(&l.span(), toml_message(&e)))?;
    }
    for m in &spec.mass {
        let s = m.get_ref();
        spans.insert(Item::Mass(s.node.clone()), m.span());
        b.add_point_mass(&s.node, s.m)
            .map_err(|e| err(&m.span(), e.to_string()))?;
    }
    for m in &spec.inertia {
        let s = m.get_ref();
        spans.insert(Item::Mass(s.node.clone()), m.span());
        b.add_inertia(&s.node, s.i)
            .map_err(|e| err(&m.span(), e.to_string()))?;
    }
    // what each [[prescribe]] holds, with its line: a second value for one target is an error
    let mut prescribed: HashMap<(String, String), usize> = HashMap::new();
    for (k, p) in spec.prescribe.iter().enumerate() {
        let s = p.get_ref();
        let span = p.span();
        let line = crate::error::line_col(text, span.start).0;
        let target = match (&s.node, &s.dof, &s.element, s.mode) {
            (Some(node), Some(dof), _, _) => {
                // a node `at` another shares its host's translations
                let parsed = Dof::parse(dof);
                let owner = match parsed {
                    Some(d) if !d.is_rotation() => position_owner(nodes, node),
                    _ => node.clone(),
                };
                Some((
                    format!("coordinate {dof} of node `{node}`"),
                    format!("node {owner}"),
                    parsed.map_or_else(|| dof.clone(), |d| d.name().to_string()),
                ))
            }
            (None, None, Some(element), Some(mode)) => Some((
                format!("deformation mode {mode} of element `{element}`"),
                format!("element {element}"),
                mode.to_string(),
            )),
            _ => None,
        };
        if let Some((what, a, b)) = target {
            if let Some(first) = prescribed.insert((a, b), line) {
                return Err(err(
                    &span,
                    format!(
                        "[[prescribe]] {}: {what} is prescribed twice (lines {first} and {line}); give one value",
                        k + 1
                    ),
                ));
            }
        }
        match (&s.node, &s.dof, &s.element, s.mode) {
            (Some(node), Some(dof), None, None) => {
                let d = Dof::parse(dof).ok_or_else(|| {
                    err(&span, format!("prescribe on `{node}`: unknown degree of freedom `{dof}`, expected x, y, z, rx, ry or rz"))
                })?;
                spans.insert(Item::Input(node.clone()), span.clone());
                b.prescribe_coordinate(node, d, s.value).map_err(|e| err(&span, e.to_string()))?;
            }
            (None, None, Some(element), Some(mode)) if mode >= 1 => {
                b.prescribe_deformation(element, mode as usize, s.value).map_err(|e| err(&span, e.to_string()))?;
            }
            _ => {
                return Err(err(
                    &span,
                    "[[prescribe]]: give either `node` and `dof` (a nodal coordinate) or `element` and `mode` (≥ 1, a deformation), and `value`".into(),
                ))
            }
        }
    }
    let st = spec
        .statics
        .as_ref()
        .map(|s| s.get_ref().clone())
        .unwrap_or_default();
    if let Some(sp) = &spec.statics {
        b.set_gravity(st.gravity)
            .map_err(|e| err(&sp.span(), format!("[static]: {e}")))?;
        match (st.spin, st.spin_point) {
            (Some(w), point) => b
                .set_spin(w, point.unwrap_or([0.0; 3]))
                .map_err(|e| err(&sp.span(), format!("[static]: {e}")))?,
            (None, Some(_)) => {
                return Err(err(
                    &sp.span(),
                    "[static]: `spin_point` needs `spin` (the angular velocity [rad/s])".into(),
                ))
            }
            (None, None) => {}
        }
        for (what, v) in [("tol_force", st.tol_force), ("tol_disp", st.tol_disp)] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    return Err(err(
                        &sp.span(),
                        format!("[static]: `{what}` must be a positive number, found {v}"),
                    ));
                }
            }
        }
        for (what, v, max) in [
            ("steps", st.steps, MAX_STEPS),
            ("max_iterations", st.max_iterations, MAX_ITERATIONS),
        ] {
            if let Some(v) = v {
                if v == 0 || v > max {
                    return Err(err(
                        &key_span(text, &sp.span(), what),
                        format!("[static]: `{what}` must be from 1 to {max} (the limit, docs/reliability.md), found {v}"),
                    ));
                }
            }
        }
        if st.buckling > MAX_BUCKLING {
            return Err(err(
                &key_span(text, &sp.span(), "buckling"),
                format!(
                    "[static]: `buckling` must be from 0 to {MAX_BUCKLING} (the limit, docs/reliability.md), found {}",
                    st.buckling
                ),
            ));
        }
        if let Some(p) = &st.path {
            if !matches!(p.as_str(), "load-steps" | "arc-length") {
                return Err(err(
                    &key_span(text, &sp.span(), "path"),
                    format!(
                        "[static]: `path` must be \"load-steps\" or \"arc-length\", found \"{p}\""
                    ),
                ));
            }
        }
        for n in &st.compliance {
            if !nodes.contains_key(n) {
                return Err(err(
                    &sp.span(),
                    format!("[static]: compliance node `{n}` is not defined"),
                ));
            }
        }
    }
    let settings = Settings {
        steps: st.steps,
        max_iterations: st.max_iterations,
        tol_force: st.tol_force,
        tol_disp: st.tol_disp,
        compliance: st.compliance,
        buckling: st.buckling,
        line_search: st.line_search,
        path: match st.path.as_deref() {
            Some("arc-length") => flexmbd_core::statics::PathMethod::ArcLength,
            _ => flexmbd_core::statics::PathMethod::LoadSteps,
        },
    };

    let model = b.build().map_err(|e| match spans.get(&e.item()) {
        Some(span) => err(span, toml_message(&e)),
        None => InputError::File {
            file: file.into(),
            message: toml_message(&e),
        },
    })?;
    crate::error::require_elements(&model, file)?;
    // the time simulation: [simulate], histories, initial velocities
    let mut sim = match &spec.simulate {
        Some(sp) => simulate::settings(sp.get_ref()).map_err(|m| err(&sp.span(), m))?,
        None => simulate::SimulateSettings::default(),
    };
    for l in &spec.load {
        let h = l.get_ref().history.clone().unwrap_or_default();
        h.validate().map_err(|e| {
            err(
                &l.span(),
                format!("[[load]] at node `{}`: history: {e}", l.get_ref().node),
            )
        })?;
        sim.excitation.loads.push(h);
    }
    // the model lists prescribed coordinates first, then deformations (ModelBuilder::build)
    let (mut h_coord, mut h_def) = (Vec::new(), Vec::new());
    for (k, p) in spec.prescribe.iter().enumerate() {
        let h = p.get_ref().history.clone().unwrap_or_default();
        h.validate()
            .map_err(|e| err(&p.span(), format!("[[prescribe]] {}: history: {e}", k + 1)))?;
        if h.is_discontinuous() {
            return Err(err(
                &p.span(),
                format!("[[prescribe]] {}: history: a prescribed motion cannot jump (a step); use a ramp or a table", k + 1),
            ));
        }
        if p.get_ref().node.is_some() {
            h_coord.push(h);
        } else {
            h_def.push(h);
        }
    }
    sim.excitation.prescribed = h_coord.into_iter().chain(h_def).collect();
    for v in &spec.velocity {
        let s = v.get_ref();
        let node = model.node_id(&s.node).ok_or_else(|| {
            err(
                &v.span(),
                format!("[[velocity]]: node `{}` is not defined", s.node),
            )
        })?;
        if model.nodes[node].ix_rot.is_none() && s.omega != [0.0; 3] {
            return Err(err(
                &v.span(),
                format!(
                    "[[velocity]] at node `{}`: `omega` needs a rotational node",
                    s.node
                ),
            ));
        }
        sim.excitation
            .velocities
            .push(simulate::velocity(s, node).map_err(|m| err(&v.span(), m))?);
    }
    Ok(ModelFile {
        model,
        settings,
        simulate: sim,
    })
}

/// A model error in this format's words: the core's neutral message plus the TOML spelling of
/// its remedy where it has one.
fn toml_message(e: &flexmbd_core::ModelError) -> String {
    use flexmbd_core::ModelError::{MomentWithoutRotation, NoRotation};
    match e {
        NoRotation { .. } | MomentWithoutRotation { .. } => {
            format!("{e}; in a TOML model: `rot = true` on the node")
        }
        _ => e.to_string(),
    }
}

type Materials = HashMap<String, Material>;
type Sections = HashMap<String, (Shape, bool)>;

fn positive(what: &str, v: f64) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("`{what}` must be a positive number, found {v}"))
    }
}

fn read_materials(spec: &FileSpec, file: &str, text: &str) -> Result<Materials, InputError> {
    let mut out = HashMap::new();
    for m in &spec.material {
        let s = m.get_ref();
        let fail = |msg: String| {
            at(
                file,
                text,
                m.span().start,
                format!("material `{}`: {msg}", s.id),
            )
        };
        let e = positive("E", s.e).map_err(fail)?;
        let g = match (s.g, s.nu) {
            (Some(g), None) => positive("G", g).map_err(fail)?,
            (None, Some(nu)) if nu.is_finite() && nu > -1.0 && nu < 0.5 => e / (2.0 * (1.0 + nu)),
            (None, Some(nu)) => return Err(fail(format!("`nu` must be in (−1, 0.5), found {nu}"))),
            (Some(_), Some(_)) => return Err(fail("give `G` or `nu`, not both".into())),
            (None, None) => {
                return Err(fail(
                    "missing `G` (shear modulus) or `nu` (Poisson's ratio)".into(),
                ))
            }
        };
        if !(s.rho.is_finite() && s.rho >= 0.0) {
            return Err(fail(format!("`rho` must be ≥ 0, found {}", s.rho)));
        }
        if out
            .insert(s.id.clone(), Material { e, g, rho: s.rho })
            .is_some()
        {
            return Err(fail("defined twice".into()));
        }
    }
    Ok(out)
}

fn read_sections(spec: &FileSpec, file: &str, text: &str) -> Result<Sections, InputError> {
    let mut out = HashMap::new();
    for sec in &spec.section {
        let s = sec.get_ref();
        let fail = |msg: String| {
            at(
                file,
                text,
                sec.span().start,
                format!("section `{}`: {msg}", s.id),
            )
        };
        let need = |name: &str, v: Option<f64>| -> Result<f64, String> {
            positive(
                name,
                v.ok_or_else(|| format!("shape `{}` needs `{name}`", s.shape))?,
            )
        };
        let shape = match s.shape.as_str() {
            "rectangle" => Shape::Rectangle {
                w: need("w", s.w).map_err(fail)?,
                t: need("t", s.t).map_err(fail)?,
            },
            "circle" => Shape::Circle {
                d: need("d", s.d).map_err(fail)?,
            },
            "tube" => {
                let (d_out, d_in) = (
                    need("d_out", s.d_out).map_err(fail)?,
                    need("d_in", s.d_in).map_err(fail)?,
                );
                if d_in >= d_out {
                    return Err(fail(format!(
                        "`d_in` ({d_in}) must be smaller than `d_out` ({d_out})"
                    )));
                }
                Shape::Tube { d_out, d_in }
            }
            "general" => Shape::General {
                a: need("A", s.a).map_err(fail)?,
                iy: need("Iy", s.iy).map_err(fail)?,
                iz: need("Iz", s.iz).map_err(fail)?,
                j: need("J", s.j).map_err(fail)?,
                k: match s.k {
                    None => 0.0,
                    Some(k) if k.is_finite() && k >= 0.0 => k,
                    Some(k) => {
                        return Err(fail(format!(
                            "`k` (the shear factor) must be ≥ 0 (0: shear-rigid), found {k}"
                        )))
                    }
                },
            },
            other => {
                return Err(fail(format!(
                    "unknown shape `{other}`, expected rectangle, circle, tube or general"
                )))
            }
        };
        if out.insert(s.id.clone(), (shape, s.shear)).is_some() {
            return Err(fail("defined twice".into()));
        }
    }
    Ok(out)
}

/// The beam's stiffness and mass constants: from `section` + `material`, or given directly.
fn beam_constants(
    s: &BeamSpec,
    materials: &Materials,
    sections: &Sections,
) -> Result<Option<BeamProps>, String> {
    let direct = [s.ea, s.gj, s.eiy, s.eiz];
    let mut props = match (&s.section, &s.material) {
        (Some(sec), Some(mat)) => {
            if direct.iter().any(Option::is_some) {
                return Err(
                    "give `section` and `material`, or `EA`, `GJ`, `EIy`, `EIz` directly, not both"
                        .into(),
                );
            }
            if s.rho_a.is_some() {
                return Err(format!(
                    "`rho_a` is the mass per length of constants given directly; with `section` and `material` the mass per length is the material's `rho` × the section's area: remove `rho_a`, or set `rho` of material `{mat}`"
                ));
            }
            let m = materials
                .get(mat)
                .ok_or_else(|| format!("material `{mat}` is not defined"))?;
            let (shape, shear) = sections
                .get(sec)
                .ok_or_else(|| format!("section `{sec}` is not defined"))?;
            BeamProps::from_section(m, shape, !shear)
        }
        (Some(_), None) => return Err("a `section` needs a `material`".into()),
        (None, Some(_)) => return Err("a `material` needs a `section`".into()),
        (None, None) if direct.iter().any(Option::is_some) => {
            let get = |name: &str, v: Option<f64>| -> Result<f64, String> {
                match v {
                    Some(v) if v.is_finite() && v >= 0.0 => Ok(v),
                    Some(v) => Err(format!("`{name}` must be ≥ 0, found {v}")),
                    None => Ok(0.0),
                }
            };
            BeamProps {
                ea: get("EA", s.ea)?,
                gj: get("GJ", s.gj)?,
                eiy: get("EIy", s.eiy)?,
                eiz: get("EIz", s.eiz)?,
                rho_a: get("rho_a", s.rho_a)?,
                ..Default::default()
            }
        }
        (None, None) if s.rho_a.is_some() => {
            return Err(
                "`rho_a` (mass per length) belongs to constants given directly: give the beam's `EA`, `GJ`, `EIy`, `EIz` with it (a missing one is 0), or a `section` and a `material` with density `rho` instead"
                    .into(),
            )
        }
        (None, None) => return Ok(None),
    };
    if let Some(ct) = s.ct {
        props.ct = ct;
    }
    Ok(Some(props))
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

/// Prefix a TOML-level error message (syntax, unknown key, missing field, wrong type) with the
/// item it is in, found from the text: the last table header before `offset` and, in [nodes],
/// [fix] and [inputs], the key of the entry; in an element table, its `id`.
fn name_item(text: &str, offset: usize, msg: String) -> String {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |p| p + 1);
    let line_end = text[offset..].find('\n').map_or(text.len(), |p| offset + p);
    let before: Vec<&str> = text[..line_start].lines().collect();
    let here = &text[line_start..line_end];
    // the header: the error line itself, or the nearest one above it
    let is_header = |l: &str| l.trim_start().starts_with('[');
    let (header, body_above): (Option<&str>, &[&str]) = if is_header(here) {
        (Some(here), &[])
    } else {
        match before.iter().rposition(|l| is_header(l)) {
            Some(i) => (Some(before[i]), &before[i + 1..]),
            None => (None, &before[..]),
        }
    };
    let header_name = header.map(|h| {
        let h = h.trim().trim_start_matches('[');
        h[..h.find(']').unwrap_or(h.len())].trim().to_string()
    });
    let (section, sub) = match &header_name {
        Some(h) => match h.split_once('.') {
            Some((a, b)) => (a.trim().to_string(), Some(unquote(b.trim()))),
            None => (h.clone(), None),
        },
        None => (String::new(), None),
    };
    let entry_table = matches!(section.as_str(), "nodes" | "fix" | "inputs") && sub.is_some();
    if let (Some(h), "duplicate key") = (&header_name, msg.as_str()) {
        if is_header(here) && !entry_table {
            return format!("the table `[{h}]` appears twice");
        }
    }
    // the entry key: on the error line or the nearest `key =` line above it in the table
    let entry_key = || {
        std::iter::once(here)
            .chain(body_above.iter().rev().copied())
            .find_map(line_key)
    };
    let item = match section.as_str() {
        "nodes" | "fix" | "inputs" if !is_header(here) || sub.is_some() => {
            let what = match section.as_str() {
                "nodes" => "node",
                "fix" => "fix entry",
                _ => "inputs entry",
            };
            let key = sub.or_else(entry_key);
            if let (Some(k), "duplicate key") = (&key, msg.as_str()) {
                return format!("{what} `{k}` is defined twice");
            }
            key.map(|k| format!("{what} `{k}`"))
        }
        "nodes" | "fix" | "inputs" => Some(format!("[{section}]")),
        "model" => Some("[model]".to_string()),
        "truss" | "beam" | "hinge" | "rigid" | "material" | "section" | "load" | "mass"
        | "inertia" | "prescribe"
            if header.is_some_and(|h| !h.trim_start().starts_with("[["))
                && msg.contains("expected a sequence") =>
        {
            return format!("`[{section}]` must be written `[[{section}]]` (one table per entry)");
        }
        "truss" | "beam" | "hinge" | "rigid" | "material" | "section" | "load" | "mass"
        | "inertia" | "prescribe" => {
            // a `key = "..."` line in the table's body (above and below the error line)
            let start = if is_header(here) {
                line_end
            } else {
                line_start
            };
            let below = text[start.min(text.len())..]
                .lines()
                .take_while(|l| !is_header(l));
            let body: Vec<&str> = body_above
                .iter()
                .copied()
                .chain(std::iter::once(here).filter(|l| !is_header(l)))
                .chain(below)
                .collect();
            let value_of = |key: &str| {
                body.iter().find_map(|l| {
                    let (k, v) = l.split_once('=')?;
                    (k.trim() == key).then(|| quoted(v.trim()))?
                })
            };
            // the table's number among the tables of its kind (1-based)
            let array_header = |l: &str| {
                let l = l.trim();
                l.strip_prefix("[[")
                    .and_then(|r| r.split_once("]]"))
                    .is_some_and(|(name, _)| name.trim() == section)
            };
            let index =
                before.iter().filter(|l| array_header(l)).count() + usize::from(array_header(here));
            let what = match section.as_str() {
                "truss" | "beam" | "hinge" | "rigid" => "element",
                other => other,
            };
            Some(match (value_of("id"), section.as_str()) {
                (Some(id), _) => format!("{what} `{id}`"),
                (None, "load" | "mass" | "inertia" | "prescribe") => {
                    match value_of("node").or_else(|| value_of("element")) {
                        Some(n) => format!("[[{section}]] {index} (on `{n}`)"),
                        None => format!("[[{section}]] {index}"),
                    }
                }
                (None, _) => format!("[[{section}]] {index}"),
            })
        }
        "static" => Some("[static]".to_string()),
        // a top-level `section = value` before any header
        "" => match line_key(here) {
            Some(k) if FileSpec::SECTIONS.contains(&k.as_str()) => Some(format!("[{k}]")),
            // a key before the first table header
            Some(k) if msg == "duplicate key" => {
                return format!("`{k}` is given twice before the first [table]");
            }
            _ => None,
        },
        _ => None,
    };
    match item {
        Some(item) => match (line_key(here), msg.as_str()) {
            (Some(k), "duplicate key") => format!("{item}: `{k}` is given twice"),
            _ => format!("{item}: {msg}"),
        },
        None => match msg.strip_prefix("unknown field") {
            // a top-level key is a section
            Some(rest) if header_name.as_deref().is_none_or(|h| !h.contains('.')) => {
                format!("unknown section{rest}")
            }
            _ => msg,
        },
    }
}

/// The span of the `key = value` line in the body of a table (whose span starts at its header),
/// or the table's span when the key is not found there.
fn key_span(text: &str, table: &Range<usize>, key: &str) -> Range<usize> {
    let start = table.start.min(text.len());
    let mut offset = start;
    for (k, line) in text[start..].split_inclusive('\n').enumerate() {
        let trimmed = line.trim_start();
        if k > 0 && trimmed.starts_with('[') {
            break; // the next table
        }
        if line_key(line).as_deref() == Some(key) {
            let lead = line.len() - trimmed.len();
            return offset + lead..offset + line.len();
        }
        offset += line.len();
    }
    table.clone()
}

/// The key of a `key = value` line, if the line starts with one.
fn line_key(line: &str) -> Option<String> {
    let (k, _) = line.split_once('=')?;
    let k = k.trim();
    let ok = !k.is_empty()
        && k.chars()
            .all(|c| c.is_alphanumeric() || "_-\"' .".contains(c));
    ok.then(|| unquote(k))
}

/// A key without its quotes.
fn unquote(k: &str) -> String {
    k.trim_matches(|c| c == '"' || c == '\'').to_string()
}

/// The content of a quoted string at the start of `v`.
fn quoted(v: &str) -> Option<String> {
    let q = v.chars().next().filter(|c| *c == '"' || *c == '\'')?;
    let rest = &v[1..];
    Some(rest[..rest.find(q)?].to_string())
}

/// The node whose position coordinates `name` uses: its host for a node `at` another (the
/// chain followed), else itself.
fn position_owner(nodes: &IndexMap<String, Spanned<toml::Value>>, name: &str) -> String {
    let mut current = name.to_string();
    for _ in 0..nodes.len() {
        match nodes.get(&current).map(|v| node_value(v.get_ref())) {
            Some(Ok(NodeDef::Hosted(host))) => current = host,
            _ => break,
        }
    }
    current
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

pub mod simulate;
