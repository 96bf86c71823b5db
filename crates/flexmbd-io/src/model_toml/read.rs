//! The TOML file → [`ModelSpec`]: what serde read ([`super::schema`]) with the place of every
//! item, the names of degrees of freedom, shapes and settings turned into their types. Values
//! and references are checked by [`ModelSpec::build`].

use super::params::Params;
use super::schema::{self, FileSpec};
use super::spans::{key_span, Lines};
use crate::error::{at, InputError};
use crate::spec::*;
use flexmbd_core::model::Dof;
use std::ops::Range;
use toml::Spanned;

/// Parse TOML model text into a spec; `file` names it in messages; the parameters named in
/// `set` take the values given there.
pub(super) fn parse_spec(
    text: &str,
    file: &str,
    set: &[(String, f64)],
) -> Result<ModelSpec, InputError> {
    let mut f: FileSpec = super::pieces::parse_file(text, file)?;
    // the toml crate hands tables over in key order; file order is what the user wrote (and
    // what "defined before it" and the first error reported refer to)
    for map in [&mut f.nodes, &mut f.fix, &mut f.inputs]
        .into_iter()
        .flatten()
    {
        map.sort_by_key(|_, v| v.span().start);
    }
    let err = |span: &Range<usize>, msg: String| at(file, text, span.start, msg);
    let p = Params::read(f.parameters.as_ref(), set, text, file)?;
    let lines = Lines::new(text);
    let src = |span: &Range<usize>| Src {
        at: Some(lines.pos(span.start)),
        keys: Vec::new(),
    };
    let src_keys = |span: &Range<usize>, keys: &[&str]| Src {
        at: Some(lines.pos(span.start)),
        keys: keys
            .iter()
            .map(|k| (k.to_string(), lines.pos(key_span(text, span, k).start)))
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
        parameters: p.values.clone(),
        ..Default::default()
    };
    for (id, v) in node_table {
        let span = v.span();
        let place = node_value(v.get_ref(), &|s| p.expr_in(s, &span))
            .map_err(|e| e.into_input(|m| err(&span, format!("node `{id}`: {m}"))))?;
        spec.nodes.push(NodeSpec {
            name: id.clone(),
            place,
            comment: None,
            src: src(&span),
        });
    }

    // elements, in file order over all types
    let mut elements: Vec<(Range<usize>, ElementEntrySpec)> = Vec::new();
    let mut push = |span: Range<usize>,
                    id: &str,
                    nodes: &[String],
                    kind,
                    (free, input): (&[i64], &[i64]),
                    damping: Option<f64>| {
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
            damping,
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
            ElementKind::Truss { ea: p.real(&s.ea)? },
            (&s.free, &s.input),
            p.opt(&s.damping)?,
        );
    }
    for t in &f.beam {
        let s = t.get_ref();
        let beam = BeamSpec {
            orient: p.opt_arr(&s.orient)?,
            ct: p.opt(&s.ct)?,
            fixed: s.fixed.clone(),
            section: s.section.clone(),
            material: s.material.clone(),
            segments: s.segments,
            ea: p.opt(&s.ea)?,
            gj: p.opt(&s.gj)?,
            eiy: p.opt(&s.eiy)?,
            eiz: p.opt(&s.eiz)?,
            rho_a: p.opt(&s.rho_a)?,
            shear: None,
            rho_i: None,
        };
        push(
            t.span(),
            &s.id,
            &s.nodes,
            ElementKind::Beam(beam),
            (&s.free, &s.input),
            p.opt(&s.damping)?,
        );
    }
    for t in &f.hinge {
        let s = t.get_ref();
        let kind = ElementKind::Hinge {
            axis: p.arr(&s.axis)?,
            k: p.real(&s.k)?,
        };
        push(
            t.span(),
            &s.id,
            &s.nodes,
            kind,
            (&s.free, &s.input),
            p.opt(&s.damping)?,
        );
    }
    for t in &f.rigid {
        let s = t.get_ref();
        push(
            t.span(),
            &s.id,
            &s.nodes,
            ElementKind::Rigid,
            (&[], &[]),
            None,
        );
    }
    elements.sort_by_key(|e| e.0.start);
    spec.elements = elements.into_iter().map(|e| e.1).collect();

    for m in &f.material {
        let s = m.get_ref();
        spec.materials.push(MaterialSpec {
            name: s.id.clone(),
            e: p.real(&s.e)?,
            g: p.opt(&s.g)?,
            nu: p.opt(&s.nu)?,
            rho: p.real(&s.rho)?,
            damping: p.opt(&s.damping)?,
            src: src(&m.span()),
        });
    }
    for sec in &f.section {
        let shape = section_shape(sec.get_ref(), &p).map_err(|e| {
            e.into_input(|m| err(&sec.span(), format!("section `{}`: {m}", sec.get_ref().id)))
        })?;
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
            force: p.arr(&s.force)?,
            moment: p.arr(&s.moment)?,
            history: s.history.clone(),
            comments: Vec::new(),
            src: src(&l.span()),
        });
    }
    for m in &f.mass {
        let s = m.get_ref();
        spec.masses.push(MassEntry {
            node: s.node.clone(),
            m: p.real(&s.m)?,
            comments: Vec::new(),
            src: src(&m.span()),
        });
    }
    for m in &f.inertia {
        let s = m.get_ref();
        spec.inertias.push(InertiaEntry {
            node: s.node.clone(),
            i: p.arr(&s.i)?,
            comments: Vec::new(),
            src: src(&m.span()),
        });
    }
    let values = &p;
    for sp in &f.prescribe {
        let pr = sp.get_ref();
        let target = prescribe_target(pr).map_err(|m| err(&sp.span(), m))?;
        spec.prescribed.push(PrescribeEntry {
            target,
            value: values.real(&pr.value)?,
            history: pr.history.clone(),
            comments: Vec::new(),
            src: src(&sp.span()),
        });
    }
    if let Some(sp) = &f.statics {
        spec.statics = statics(sp, text, &p, &err)?;
        spec.statics.src = src_keys(&sp.span(), &["steps", "max_iterations", "buckling"]);
    }
    if let Some(sp) = &f.simulate {
        let mut s = simulate(sp.get_ref(), &p).map_err(|e| e.into_input(|m| err(&sp.span(), m)))?;
        s.src = src(&sp.span());
        spec.simulate = Some(s);
    }
    for v in &f.velocity {
        let s = v.get_ref();
        spec.velocities.push(VelocityEntry {
            node: s.node.clone(),
            v: p.arr(&s.v)?,
            omega: p.arr(&s.omega)?,
            src: src(&v.span()),
        });
    }
    for fr in &f.freedom {
        let s = fr.get_ref();
        let rotation = match &s.rotation {
            Some(r) => Some(RotationEntry {
                point: p.arr(&r.point)?,
                axis: p.arr(&r.axis)?,
                pitch: p.real(&r.pitch)?,
            }),
            None => None,
        };
        spec.freedoms.push(FreedomEntry {
            body: s.body.clone(),
            translation: s.translation.as_ref().map(|t| p.arr(t)).transpose()?,
            rotation,
            comments: Vec::new(),
            src: src(&fr.span()),
        });
    }
    Ok(spec)
}

/// A problem of a value: a message for its item, or an error placed already (an
/// expression's).
enum ValueError {
    Msg(String),
    Placed(InputError),
}

impl ValueError {
    /// The error, a message placed by `place`.
    fn into_input(self, place: impl FnOnce(String) -> InputError) -> InputError {
        match self {
            Self::Msg(m) => place(m),
            Self::Placed(e) => e,
        }
    }
}

impl From<String> for ValueError {
    fn from(m: String) -> Self {
        Self::Msg(m)
    }
}

impl From<&str> for ValueError {
    fn from(m: &str) -> Self {
        Self::Msg(m.into())
    }
}

impl From<InputError> for ValueError {
    fn from(e: InputError) -> Self {
        Self::Placed(e)
    }
}

/// A section's shape with the dimensions it needs.
fn section_shape(s: &schema::SectionSpec, p: &Params) -> Result<ShapeSpec, ValueError> {
    let need = |name: &str, v: &Option<schema::Real>| -> Result<f64, ValueError> {
        let v = v
            .as_ref()
            .ok_or_else(|| format!("shape `{}` needs `{name}`", s.shape))?;
        Ok(p.real(v)?)
    };
    Ok(match s.shape.as_str() {
        "rectangle" => ShapeSpec::Rectangle {
            w: need("w", &s.w)?,
            t: need("t", &s.t)?,
        },
        "circle" => ShapeSpec::Circle {
            d: need("d", &s.d)?,
        },
        "tube" => ShapeSpec::Tube {
            d_out: need("d_out", &s.d_out)?,
            d_in: need("d_in", &s.d_in)?,
        },
        "general" => ShapeSpec::General {
            a: need("A", &s.a)?,
            iy: need("Iy", &s.iy)?,
            iz: need("Iz", &s.iz)?,
            j: need("J", &s.j)?,
            k: p.opt(&s.k)?,
        },
        other => {
            return Err(format!(
                "unknown shape `{other}`, expected rectangle, circle, tube or general"
            )
            .into())
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

/// `[static]`; `err` places a message at a span.
fn statics(
    sp: &Spanned<schema::StaticSpec>,
    text: &str,
    p: &Params,
    err: &dyn Fn(&Range<usize>, String) -> InputError,
) -> Result<StaticSpec, InputError> {
    let s = sp.get_ref();
    let path = match s.path.as_deref() {
        None => None,
        Some("load-steps") => Some(PathSpec::LoadSteps),
        Some("arc-length") => Some(PathSpec::ArcLength),
        Some(p) => {
            return Err(err(
                &key_span(text, &sp.span(), "path"),
                format!("[static]: `path` must be \"load-steps\" or \"arc-length\", found \"{p}\""),
            ))
        }
    };
    Ok(StaticSpec {
        steps: s.steps,
        max_iterations: s.max_iterations,
        tol_force: p.opt(&s.tol_force)?,
        tol_disp: p.opt(&s.tol_disp)?,
        gravity: p.opt_arr(&s.gravity)?,
        spin: p.opt_arr(&s.spin)?,
        spin_point: p.opt_arr(&s.spin_point)?,
        compliance: s.compliance.clone(),
        buckling: s.buckling,
        line_search: s.line_search,
        tangent_eigenvalues: s.tangent_eigenvalues,
        path,
        comments: Vec::new(),
        src: Src::default(),
    })
}

/// `[simulate]`.
fn simulate(s: &schema::SimulateSpec, p: &Params) -> Result<SimulateSpec, ValueError> {
    let step = match s.step.as_deref() {
        None => None,
        Some("fixed") => Some(StepSpec::Fixed),
        Some("adaptive") => Some(StepSpec::Adaptive),
        Some(o) => {
            return Err(format!(
                "[simulate]: `step` must be \"adaptive\" or \"fixed\", found \"{o}\""
            )
            .into())
        }
    };
    let start = match s.start.as_deref() {
        None => None,
        Some("reference") => Some(StartSpec::Reference),
        Some("static") => Some(StartSpec::Static),
        Some(o) => {
            return Err(format!(
                "[simulate]: `start` must be \"reference\" or \"static\", found \"{o}\""
            )
            .into())
        }
    };
    Ok(SimulateSpec {
        t_end: p.opt(&s.t_end)?,
        dt: p.opt(&s.dt)?,
        step,
        dt_min: p.opt(&s.dt_min)?,
        dt_max: p.opt(&s.dt_max)?,
        rho_inf: p.opt(&s.rho_inf)?,
        tolerance: p.opt_arr(&s.tolerance)?,
        output_step: p.opt(&s.output_step)?,
        max_iterations: s.max_iterations,
        rayleigh: p.opt_arr(&s.rayleigh)?,
        start,
        static_steps: s.static_steps,
        gravity_history: s.gravity_history.clone(),
        comments: Vec::new(),
        src: Src::default(),
    })
}

/// A position: 3 numbers or expressions (`expr` evaluates one).
fn vec3(v: &toml::Value, what: &str, expr: &Expr) -> Result<[f64; 3], ValueError> {
    let arr = v
        .as_array()
        .ok_or_else(|| format!("`{what}` must be an array of 3 numbers"))?;
    if arr.len() != 3 {
        return Err(format!("`{what}` must have 3 numbers, found {}", arr.len()).into());
    }
    let mut out = [0.0; 3];
    for (i, a) in arr.iter().enumerate() {
        out[i] = match a {
            toml::Value::Float(f) => *f,
            toml::Value::Integer(k) => *k as f64,
            toml::Value::String(s) => expr(s)?,
            other => {
                return Err(format!(
                    "`{what}` entry {} is not a number or an expression: {other}",
                    i + 1
                )
                .into())
            }
        };
        if !out[i].is_finite() {
            return Err(format!("`{what}` entry {} is not finite ({})", i + 1, out[i]).into());
        }
    }
    Ok(out)
}

/// Evaluates an expression of a value.
type Expr<'a> = dyn Fn(&str) -> Result<f64, InputError> + 'a;

/// A node: `[x, y, z]`, `{ x = [x, y, z], rot = bool }` or `{ at = "host" }`.
fn node_value(v: &toml::Value, expr: &Expr) -> Result<NodePlace, ValueError> {
    match v {
        toml::Value::Array(_) => Ok(NodePlace::Position {
            x: vec3(v, "position", expr)?,
            rot: false,
        }),
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !["x", "rot", "at"].contains(&k.as_str()) {
                    return Err(format!("unknown key `{k}`, expected `x`, `rot` or `at`").into());
                }
            }
            if let Some(host) = t.get("at") {
                let toml::Value::String(h) = host else {
                    return Err(format!("`at` must name a node, found {host}").into());
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
                Some(other) => {
                    return Err(format!("`rot` must be true or false, found {other}").into())
                }
            };
            Ok(NodePlace::Position {
                x: vec3(x, "x", expr)?,
                rot,
            })
        }
        other => Err(format!(
            "expected a position [x, y, z] or a table {{ x = [...] }}, found {other}"
        )
        .into()),
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
