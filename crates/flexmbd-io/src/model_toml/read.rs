//! The TOML file → [`ModelSpec`]: what serde read ([`super::schema`]) with the place of every
//! item, the names of degrees of freedom, shapes and settings turned into their types. Values
//! and references are checked by [`ModelSpec::build`].

use super::schema::{self, FileSpec};
use super::spans::{key_span, name_item, pos};
use crate::error::{at, InputError};
use crate::spec::*;
use flexmbd_core::model::Dof;
use std::ops::Range;
use toml::Spanned;

/// Parse TOML model text into a spec; `file` names it in messages.
pub(super) fn parse_spec(text: &str, file: &str) -> Result<ModelSpec, InputError> {
    let mut f: FileSpec = toml::from_str(text).map_err(|e| {
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
    for map in [&mut f.nodes, &mut f.fix, &mut f.inputs]
        .into_iter()
        .flatten()
    {
        map.sort_by_key(|_, v| v.span().start);
    }
    let err = |span: &Range<usize>, msg: String| at(file, text, span.start, msg);
    let src = |span: &Range<usize>| Src {
        at: Some(pos(text, span.start)),
        keys: Vec::new(),
    };
    let src_keys = |span: &Range<usize>, keys: &[&str]| Src {
        at: Some(pos(text, span.start)),
        keys: keys
            .iter()
            .map(|k| (k.to_string(), pos(text, key_span(text, span, k).start)))
            .collect(),
    };
    let Some(node_table) = &f.nodes else {
        return Err(InputError::File {
            file: file.into(),
            message: "the model has no [nodes] section".into(),
        });
    };
    let (name, description) = f
        .model
        .map(|m| (m.name.unwrap_or_default(), m.description))
        .unwrap_or_default();
    let mut spec = ModelSpec {
        name,
        description,
        ..Default::default()
    };
    for (id, v) in node_table {
        let span = v.span();
        let place = node_value(v.get_ref()).map_err(|m| err(&span, format!("node `{id}`: {m}")))?;
        spec.nodes.push(NodeSpec {
            name: id.clone(),
            place,
            comment: None,
            src: src(&span),
        });
    }

    // elements, in file order over all types
    let mut elements: Vec<(Range<usize>, ElementEntrySpec)> = Vec::new();
    let mut push =
        |span: Range<usize>, id: &str, nodes: &[String], kind, free: &[i64], input: &[i64]| {
            let keys: &[&str] = if matches!(kind, ElementKind::Beam(_)) {
                &["segments"]
            } else {
                &[]
            };
            let e = ElementEntrySpec {
                name: id.to_string(),
                nodes: nodes.to_vec(),
                kind,
                free: free.to_vec(),
                input: input.to_vec(),
                comments: Vec::new(),
                src: src_keys(&span, keys),
            };
            elements.push((span, e));
        };
    for t in &f.truss {
        let s = t.get_ref();
        push(
            t.span(),
            &s.id,
            &s.nodes,
            ElementKind::Truss { ea: s.ea },
            &s.free,
            &s.input,
        );
    }
    for t in &f.beam {
        let s = t.get_ref();
        let beam = BeamSpec {
            orient: s.orient,
            ct: s.ct,
            fixed: s.fixed.clone(),
            section: s.section.clone(),
            material: s.material.clone(),
            segments: s.segments,
            ea: s.ea,
            gj: s.gj,
            eiy: s.eiy,
            eiz: s.eiz,
            rho_a: s.rho_a,
            shear: None,
            rho_i: None,
        };
        push(
            t.span(),
            &s.id,
            &s.nodes,
            ElementKind::Beam(beam),
            &s.free,
            &s.input,
        );
    }
    for t in &f.hinge {
        let s = t.get_ref();
        let kind = ElementKind::Hinge {
            axis: s.axis,
            k: s.k,
        };
        push(t.span(), &s.id, &s.nodes, kind, &s.free, &s.input);
    }
    for t in &f.rigid {
        let s = t.get_ref();
        push(t.span(), &s.id, &s.nodes, ElementKind::Rigid, &[], &[]);
    }
    elements.sort_by_key(|e| e.0.start);
    spec.elements = elements.into_iter().map(|e| e.1).collect();

    for m in &f.material {
        let s = m.get_ref();
        spec.materials.push(MaterialSpec {
            name: s.id.clone(),
            e: s.e,
            g: s.g,
            nu: s.nu,
            rho: s.rho,
            src: src(&m.span()),
        });
    }
    for sec in &f.section {
        let shape = section_shape(sec.get_ref())
            .map_err(|m| err(&sec.span(), format!("section `{}`: {m}", sec.get_ref().id)))?;
        spec.sections.push(SectionSpec {
            name: sec.get_ref().id.clone(),
            shape,
            shear: sec.get_ref().shear,
            src: src(&sec.span()),
        });
    }
    for (section, list) in [("fix", &f.fix), ("inputs", &f.inputs)] {
        for (node, v) in list.iter().flat_map(|m| m.iter()) {
            let span = v.span();
            let dofs = dof_list(v.get_ref())
                .map_err(|m| err(&span, format!("{section} entry `{node}`: {m}")))?;
            let entry = DofEntry {
                node: node.clone(),
                dofs,
                comment: None,
                src: src(&span),
            };
            match section {
                "fix" => spec.fix.push(entry),
                _ => spec.inputs.push(entry),
            }
        }
    }
    for l in &f.load {
        let s = l.get_ref();
        spec.loads.push(LoadEntry {
            node: s.node.clone(),
            force: s.force,
            moment: s.moment,
            history: s.history.clone(),
            comments: Vec::new(),
            src: src(&l.span()),
        });
    }
    for m in &f.mass {
        let s = m.get_ref();
        spec.masses.push(MassEntry {
            node: s.node.clone(),
            m: s.m,
            comments: Vec::new(),
            src: src(&m.span()),
        });
    }
    for m in &f.inertia {
        let s = m.get_ref();
        spec.inertias.push(InertiaEntry {
            node: s.node.clone(),
            i: s.i,
            comments: Vec::new(),
            src: src(&m.span()),
        });
    }
    for p in &f.prescribe {
        let target = prescribe_target(p.get_ref()).map_err(|m| err(&p.span(), m))?;
        spec.prescribed.push(PrescribeEntry {
            target,
            value: p.get_ref().value,
            history: p.get_ref().history.clone(),
            comments: Vec::new(),
            src: src(&p.span()),
        });
    }
    if let Some(sp) = &f.statics {
        spec.statics = statics(sp, text).map_err(|(span, m)| err(&span, m))?;
        spec.statics.src = src_keys(&sp.span(), &["steps", "max_iterations", "buckling"]);
    }
    if let Some(sp) = &f.simulate {
        let mut s = simulate(sp.get_ref()).map_err(|m| err(&sp.span(), m))?;
        s.src = src(&sp.span());
        spec.simulate = Some(s);
    }
    for v in &f.velocity {
        let s = v.get_ref();
        spec.velocities.push(VelocityEntry {
            node: s.node.clone(),
            v: s.v,
            omega: s.omega,
            src: src(&v.span()),
        });
    }
    Ok(spec)
}

/// A section's shape with the dimensions it needs.
fn section_shape(s: &schema::SectionSpec) -> Result<ShapeSpec, String> {
    let need = |name: &str, v: Option<f64>| -> Result<f64, String> {
        v.ok_or_else(|| format!("shape `{}` needs `{name}`", s.shape))
    };
    Ok(match s.shape.as_str() {
        "rectangle" => ShapeSpec::Rectangle {
            w: need("w", s.w)?,
            t: need("t", s.t)?,
        },
        "circle" => ShapeSpec::Circle { d: need("d", s.d)? },
        "tube" => ShapeSpec::Tube {
            d_out: need("d_out", s.d_out)?,
            d_in: need("d_in", s.d_in)?,
        },
        "general" => ShapeSpec::General {
            a: need("A", s.a)?,
            iy: need("Iy", s.iy)?,
            iz: need("Iz", s.iz)?,
            j: need("J", s.j)?,
            k: s.k,
        },
        other => {
            return Err(format!(
                "unknown shape `{other}`, expected rectangle, circle, tube or general"
            ))
        }
    })
}

/// A `[[prescribe]]` target: `node` and `dof`, or `element` and `mode` ≥ 1.
fn prescribe_target(s: &schema::PrescribeSpec) -> Result<PrescribeTarget, String> {
    match (&s.node, &s.dof, &s.element, s.mode) {
        (Some(node), Some(dof), None, None) => {
            let dof = Dof::parse(dof).ok_or_else(|| {
                format!("prescribe on `{node}`: unknown degree of freedom `{dof}`, expected x, y, z, rx, ry or rz")
            })?;
            Ok(PrescribeTarget::Coordinate {
                node: node.clone(),
                dof,
            })
        }
        (None, None, Some(element), Some(mode)) if mode >= 1 => Ok(PrescribeTarget::Deformation {
            element: element.clone(),
            mode: mode as usize,
        }),
        _ => Err("[[prescribe]]: give either `node` and `dof` (a nodal coordinate) or `element` and `mode` (≥ 1, a deformation), and `value`".into()),
    }
}

/// `[static]`; `Err` holds the span of the problem.
fn statics(
    sp: &Spanned<schema::StaticSpec>,
    text: &str,
) -> Result<StaticSpec, (Range<usize>, String)> {
    let s = sp.get_ref();
    let path = match s.path.as_deref() {
        None => None,
        Some("load-steps") => Some(PathSpec::LoadSteps),
        Some("arc-length") => Some(PathSpec::ArcLength),
        Some(p) => {
            return Err((
                key_span(text, &sp.span(), "path"),
                format!("[static]: `path` must be \"load-steps\" or \"arc-length\", found \"{p}\""),
            ))
        }
    };
    Ok(StaticSpec {
        steps: s.steps,
        max_iterations: s.max_iterations,
        tol_force: s.tol_force,
        tol_disp: s.tol_disp,
        gravity: s.gravity,
        spin: s.spin,
        spin_point: s.spin_point,
        compliance: s.compliance.clone(),
        buckling: s.buckling,
        line_search: s.line_search,
        path,
        comments: Vec::new(),
        src: Src::default(),
    })
}

/// `[simulate]`.
fn simulate(s: &schema::SimulateSpec) -> Result<SimulateSpec, String> {
    let step = match s.step.as_deref() {
        None => None,
        Some("fixed") => Some(StepSpec::Fixed),
        Some("adaptive") => Some(StepSpec::Adaptive),
        Some(o) => {
            return Err(format!(
                "[simulate]: `step` must be \"adaptive\" or \"fixed\", found \"{o}\""
            ))
        }
    };
    let start = match s.start.as_deref() {
        None => None,
        Some("reference") => Some(StartSpec::Reference),
        Some("static") => Some(StartSpec::Static),
        Some(o) => {
            return Err(format!(
                "[simulate]: `start` must be \"reference\" or \"static\", found \"{o}\""
            ))
        }
    };
    Ok(SimulateSpec {
        t_end: s.t_end,
        dt: s.dt,
        step,
        dt_min: s.dt_min,
        dt_max: s.dt_max,
        rho_inf: s.rho_inf,
        tolerance: s.tolerance,
        output_step: s.output_step,
        max_iterations: s.max_iterations,
        rayleigh: s.rayleigh,
        start,
        static_steps: s.static_steps,
        gravity_history: s.gravity_history.clone(),
        comments: Vec::new(),
        src: Src::default(),
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

/// A node: `[x, y, z]`, `{ x = [x, y, z], rot = bool }` or `{ at = "host" }`.
fn node_value(v: &toml::Value) -> Result<NodePlace, String> {
    match v {
        toml::Value::Array(_) => Ok(NodePlace::Position {
            x: vec3(v, "position")?,
            rot: false,
        }),
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
                return Ok(NodePlace::At(h.clone()));
            }
            let x = t
                .get("x")
                .ok_or("missing field `x` (the position) or `at` (a host node)")?;
            let rot = match t.get("rot") {
                None => false,
                Some(toml::Value::Boolean(b)) => *b,
                Some(other) => return Err(format!("`rot` must be true or false, found {other}")),
            };
            Ok(NodePlace::Position {
                x: vec3(x, "x")?,
                rot,
            })
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
