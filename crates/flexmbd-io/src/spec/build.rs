//! [`ModelSpec::build`]: spec → [`ModelBuilder`] → [`Model`] with its analysis settings, the one
//! build path of every reader (TOML, SPACAR `.dat`) and of specs made or edited in code.
//!
//! The build checks what the format readers cannot check alone (values, references between
//! items, the settings), in a fixed order: nodes; beam segments; elements in order; materials,
//! sections and beam constants; supports and inputs; loads, masses, inertias, prescribed values;
//! `[static]`; the compiled model; `[simulate]`, histories and initial velocities. The first
//! problem is returned with the place of its item ([`Src`]).

use super::props::{beam_constants, read_materials, read_sections};
use super::settings::{simulate_settings, velocity, ModelFile, Settings, SimulateSettings};
use super::*;
use crate::limits::{MAX_BUCKLING, MAX_ITERATIONS, MAX_SEGMENTS, MAX_STEPS};
use flexmbd_core::model::{ElementSpec, Item};
use flexmbd_core::{Model, ModelBuilder, ModelError};
use rustc_hash::FxHashMap as HashMap;

/// What is wrong with a spec.
#[derive(Clone, Debug, PartialEq)]
pub enum SpecErrorKind {
    /// The core rejects an item (the message names it).
    Model(ModelError),
    /// A value or reference the spec checks itself (the message names the item).
    Invalid(String),
    /// The model has no element (nothing to analyse).
    NoElements(String),
}

/// A spec that does not build: what is wrong and where its item was written.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", self.message())]
pub struct SpecError {
    /// What is wrong.
    pub kind: SpecErrorKind,
    /// The item's place, when known.
    pub at: Option<Pos>,
}

impl SpecError {
    /// The message, naming the item.
    pub fn message(&self) -> String {
        match &self.kind {
            SpecErrorKind::Model(e) => e.to_string(),
            SpecErrorKind::Invalid(m) | SpecErrorKind::NoElements(m) => m.clone(),
        }
    }
    /// The line of the item, when known.
    pub fn line(&self) -> Option<usize> {
        self.at.map(|p| p.line)
    }
}

fn invalid(at: Option<Pos>, message: String) -> SpecError {
    SpecError {
        kind: SpecErrorKind::Invalid(message),
        at,
    }
}

fn model_err(src: &Src) -> impl Fn(ModelError) -> SpecError + '_ {
    move |e| SpecError {
        kind: SpecErrorKind::Model(e),
        at: src.at,
    }
}

impl ModelSpec {
    /// Build the core model (every input, including the `dynamic_inputs`).
    pub fn build(&self) -> Result<Model, SpecError> {
        self.build_file().map(|f| f.model)
    }

    /// Build the model with its analysis settings (`[static]`, `[simulate]`, histories,
    /// initial velocities): what a reader returns. The `dynamic_inputs` are inputs.
    pub fn build_file(&self) -> Result<ModelFile, SpecError> {
        self.build_with(true)
    }

    /// [`Self::build_file`] for a static analysis: the `dynamic_inputs` are unknowns, not
    /// inputs (SPACAR's `DYNX` coordinates).
    pub fn build_static(&self) -> Result<ModelFile, SpecError> {
        self.build_with(false)
    }

    fn build_with(&self, dynamic_inputs: bool) -> Result<ModelFile, SpecError> {
        let mut b = ModelBuilder::new(&self.name);
        b.reserve(self.nodes.len(), self.elements.len());
        for n in &self.nodes {
            match &n.place {
                NodePlace::Position { x, rot } => b.add_node(&n.name, *x, *rot),
                NodePlace::At(host) => b.add_node_at(&n.name, host),
            }
            .map_err(model_err(&n.src))?;
        }
        let chains = self.segment_nodes(&mut b)?;
        let mut beams: Vec<(String, &ElementEntrySpec, &BeamSpec)> = Vec::new();
        let mut parts_of: Vec<(String, &ElementEntrySpec)> =
            Vec::with_capacity(self.elements.len());
        for (e, chain) in self.elements.iter().zip(&chains) {
            let spec = match &e.kind {
                ElementKind::Truss { ea } => ElementSpec::Truss { ea: *ea },
                ElementKind::Beam(s) => ElementSpec::Beam {
                    orient: s.orient,
                    ct: s.ct.unwrap_or(0.0),
                },
                ElementKind::Hinge { axis, k } => ElementSpec::Hinge { axis: *axis, k: *k },
                ElementKind::Rigid => ElementSpec::Rigid,
            };
            // beams split into segments: elements `id:1`, … over the chain of nodes
            let parts: Vec<(String, Vec<&str>)> = match chain {
                None => vec![(e.name.clone(), e.nodes.iter().map(String::as_str).collect())],
                Some(c) => (0..c.len() - 1)
                    .map(|k| (format!("{}:{}", e.name, k + 1), vec![&*c[k], &*c[k + 1]]))
                    .collect(),
            };
            for (id, nodes) in parts {
                b.add_element(&id, &nodes, spec.clone(), &e.free, &e.input)
                    .map_err(model_err(&e.src))?;
                parts_of.push((id.clone(), e));
                if let ElementKind::Beam(s) = &e.kind {
                    beams.push((id, e, s));
                }
            }
        }

        let materials = read_materials(&self.materials)?;
        let sections = read_sections(&self.sections)?;
        let mut made = Default::default();
        for (id, e, s) in &beams {
            if let Some(props) = beam_constants(s, &materials, &sections, &mut made)
                .map_err(|m| invalid(e.src.at, format!("element `{}`: {m}", e.name)))?
            {
                b.set_beam_props(id, props).map_err(model_err(&e.src))?;
            }
            if !s.fixed.is_empty() {
                b.set_rigid_modes(id, &s.fixed).map_err(model_err(&e.src))?;
            }
        }
        // material damping: the element's own, else its material's
        for (id, e) in &parts_of {
            let of_material = || {
                let name = e.beam()?.material.as_deref()?;
                self.materials.iter().find(|m| m.name == name)?.damping
            };
            if let Some(tau) = e.damping.or_else(of_material) {
                b.set_damping(id, tau).map_err(model_err(&e.src))?;
            }
        }

        for f in &self.fix {
            b.fix(&f.node, f.dofs.as_deref())
                .map_err(model_err(&f.src))?;
        }
        let dynamic: &[DofEntry] = if dynamic_inputs {
            &self.dynamic_inputs
        } else {
            &[]
        };
        for i in self.inputs.iter().chain(dynamic) {
            b.input(&i.node, i.dofs.as_deref())
                .map_err(model_err(&i.src))?;
        }
        for l in &self.loads {
            b.add_load(&l.node, l.force, l.moment)
                .map_err(model_err(&l.src))?;
        }
        for m in &self.masses {
            b.add_point_mass(&m.node, m.m).map_err(model_err(&m.src))?;
        }
        for m in &self.inertias {
            b.add_inertia(&m.node, m.i).map_err(model_err(&m.src))?;
        }
        self.check_prescribed_once()?;
        for p in &self.prescribed {
            match &p.target {
                PrescribeTarget::Coordinate { node, dof } => {
                    b.prescribe_coordinate(node, *dof, p.value)
                }
                PrescribeTarget::Deformation { element, mode } => {
                    if *mode == 0 {
                        return Err(invalid(p.src.at, "[[prescribe]]: give either `node` and `dof` (a nodal coordinate) or `element` and `mode` (≥ 1, a deformation), and `value`".into()));
                    }
                    b.prescribe_deformation(element, *mode, p.value)
                }
            }
            .map_err(model_err(&p.src))?;
        }
        let settings = self.static_settings(&mut b)?;

        let model = b.build().map_err(|error| SpecError {
            at: self.place_of(&error.item(), dynamic_inputs),
            kind: SpecErrorKind::Model(error),
        })?;
        if let Some(message) = crate::error::no_elements(&model) {
            return Err(SpecError {
                kind: SpecErrorKind::NoElements(message),
                at: None,
            });
        }
        let simulate = self.simulation(&model)?;
        let freedom = self
            .freedoms
            .iter()
            .enumerate()
            .map(|(k, f)| {
                intended(&model, f)
                    .map_err(|m| invalid(f.src.at, format!("[[freedom]] {}: {m}", k + 1)))
            })
            .collect::<Result<_, _>>()?;
        Ok(ModelFile {
            model,
            settings,
            simulate,
            freedom,
        })
    }

    /// Where `item`, named by an error of the compiled model, was written: the last definition
    /// of a node or element (a segment `id:k` of beam `id` at the beam), the fix of a node, the
    /// last prescribed value of a node else its first input entry, its last load, its last
    /// inertia else point mass. Looked up only for an error: a valid model of 10^5 items keeps
    /// no table of places.
    fn place_of(&self, item: &Item, dynamic_inputs: bool) -> Option<Pos> {
        fn last<'a, T: 'a>(
            list: impl DoubleEndedIterator<Item = &'a T>,
            hit: impl Fn(&T) -> bool,
            src: impl Fn(&T) -> &Src,
        ) -> Option<Option<Pos>> {
            list.rev().find(|x| hit(x)).map(|x| src(x).at)
        }
        let segment_of = |name: &str| {
            let (beam, k) = name.rsplit_once(':')?;
            k.parse::<usize>().ok()?;
            last(self.elements.iter(), |e| e.name == beam, |e| &e.src)
        };
        let place = match item {
            Item::Node(n) => {
                last(self.nodes.iter(), |x| x.name == *n, |x| &x.src).or_else(|| segment_of(n))
            }
            Item::Element(id) => {
                last(self.elements.iter(), |e| e.name == *id, |e| &e.src).or_else(|| segment_of(id))
            }
            Item::Fix(n) => last(self.fix.iter(), |f| f.node == *n, |f| &f.src),
            Item::Input(n) => {
                let prescribed = self.prescribed.iter().rev().find(
                    |p| matches!(&p.target, PrescribeTarget::Coordinate { node, .. } if node == n),
                );
                let dynamic: &[DofEntry] = if dynamic_inputs {
                    &self.dynamic_inputs
                } else {
                    &[]
                };
                prescribed.map(|p| p.src.at).or_else(|| {
                    let mut all = self.inputs.iter().chain(dynamic);
                    all.find(|i| i.node == *n).map(|i| i.src.at)
                })
            }
            Item::Load(n) => last(self.loads.iter(), |l| l.node == *n, |l| &l.src),
            Item::Mass(n) => last(self.inertias.iter(), |m| m.node == *n, |m| &m.src)
                .or_else(|| last(self.masses.iter(), |m| m.node == *n, |m| &m.src)),
            Item::Model => None,
        };
        place.flatten()
    }

    /// The intermediate nodes of beams split into segments (`id:1`, … at equal spacing), added
    /// to `b`; per element the chain of its nodes, `None` when it is not split (one segment,
    /// or end nodes whose position is not known: the builder then reports them).
    fn segment_nodes(&self, b: &mut ModelBuilder) -> Result<Vec<Option<Vec<String>>>, SpecError> {
        let place: HashMap<&str, &NodePlace> = self
            .nodes
            .iter()
            .rev()
            .map(|n| (n.name.as_str(), &n.place))
            .collect();
        let pos = |name: &str| -> Option<[f64; 3]> {
            match place.get(name)? {
                NodePlace::Position { x, .. } => Some(*x),
                NodePlace::At(h) => match place.get(h.as_str())? {
                    NodePlace::Position { x, .. } => Some(*x),
                    NodePlace::At(_) => None,
                },
            }
        };
        let mut chains = Vec::with_capacity(self.elements.len());
        for e in &self.elements {
            let Some(s) = e.beam() else {
                chains.push(None);
                continue;
            };
            let n = s.segments.unwrap_or(1);
            if n == 0 || n > MAX_SEGMENTS {
                return Err(invalid(
                    e.src.key("segments"),
                    format!(
                        "element `{}`: `segments` must be from 1 to {MAX_SEGMENTS} (the limit, docs/reliability.md), found {n}",
                        e.name
                    ),
                ));
            }
            let ends = match e.nodes.as_slice() {
                [p, q] if n > 1 => pos(p).zip(pos(q)),
                _ => None,
            };
            let Some((p, q)) = ends else {
                chains.push(None);
                continue;
            };
            let mut chain = vec![e.nodes[0].clone()];
            for k in 1..n {
                let f = k as f64 / n as f64;
                let name = format!("{}:{k}", e.name);
                let x: [f64; 3] = std::array::from_fn(|i| p[i] + f * (q[i] - p[i]));
                b.add_node(&name, x, false).map_err(model_err(&e.src))?;
                chain.push(name);
            }
            chain.push(e.nodes[1].clone());
            chains.push(Some(chain));
        }
        Ok(chains)
    }

    /// One `[[prescribe]]` per coordinate or deformation (a node `at` another shares its
    /// host's translations).
    fn check_prescribed_once(&self) -> Result<(), SpecError> {
        let hosts: HashMap<&str, &str> = self
            .nodes
            .iter()
            .filter_map(|n| match &n.place {
                NodePlace::At(h) => Some((n.name.as_str(), h.as_str())),
                NodePlace::Position { .. } => None,
            })
            .collect();
        // the node whose position coordinates `name` uses (the chain of hosts followed)
        let owner = |name: &str| -> String {
            let mut current = name;
            for _ in 0..hosts.len() {
                match hosts.get(current) {
                    Some(h) => current = h,
                    None => break,
                }
            }
            current.to_string()
        };
        let mut seen: HashMap<(String, String), Option<usize>> = HashMap::default();
        for (k, p) in self.prescribed.iter().enumerate() {
            let (what, key) = match &p.target {
                PrescribeTarget::Coordinate { node, dof } => {
                    let o = if dof.is_rotation() {
                        node.clone()
                    } else {
                        owner(node)
                    };
                    (
                        format!("coordinate {} of node `{node}`", dof.name()),
                        (format!("node {o}"), dof.name().to_string()),
                    )
                }
                PrescribeTarget::Deformation { element, mode } => (
                    format!("deformation mode {mode} of element `{element}`"),
                    (format!("element {element}"), mode.to_string()),
                ),
            };
            let line = p.src.line_number();
            if let Some(first) = seen.insert(key, line) {
                let lines = match (first, line) {
                    (Some(a), Some(b)) => format!(" (lines {a} and {b})"),
                    _ => String::new(),
                };
                return Err(invalid(
                    p.src.at,
                    format!(
                        "[[prescribe]] {}: {what} is prescribed twice{lines}; give one value",
                        k + 1
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Gravity and spin into `b`; the checked `[static]` settings.
    fn static_settings(&self, b: &mut ModelBuilder) -> Result<Settings, SpecError> {
        let st = &self.statics;
        let fail =
            |key: Option<&str>, m: String| invalid(key.map_or(st.src.at, |k| st.src.key(k)), m);
        if let Some(g) = st.gravity {
            b.set_gravity(g)
                .map_err(|e| fail(None, format!("[static]: {e}")))?;
        }
        match (st.spin, st.spin_point) {
            (Some(w), point) => b
                .set_spin(w, point.unwrap_or([0.0; 3]))
                .map_err(|e| fail(None, format!("[static]: {e}")))?,
            (None, Some(_)) => {
                return Err(fail(
                    None,
                    "[static]: `spin_point` needs `spin` (the angular velocity [rad/s])".into(),
                ))
            }
            (None, None) => {}
        }
        for (what, v) in [("tol_force", st.tol_force), ("tol_disp", st.tol_disp)] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(fail(
                    None,
                    format!("[static]: `{what}` must be a positive number, found {v}"),
                ));
            }
        }
        for (what, v, max) in [
            ("steps", st.steps, MAX_STEPS),
            ("max_iterations", st.max_iterations, MAX_ITERATIONS),
        ] {
            if let Some(v) = v.filter(|v| *v == 0 || *v > max) {
                return Err(fail(
                    Some(what),
                    format!("[static]: `{what}` must be from 1 to {max} (the limit, docs/reliability.md), found {v}"),
                ));
            }
        }
        if st.buckling > MAX_BUCKLING {
            return Err(fail(
                Some("buckling"),
                format!(
                    "[static]: `buckling` must be from 0 to {MAX_BUCKLING} (the limit, docs/reliability.md), found {}",
                    st.buckling
                ),
            ));
        }
        for n in &st.compliance {
            if !self.nodes.iter().any(|m| &m.name == n) {
                return Err(fail(
                    None,
                    format!("[static]: compliance node `{n}` is not defined"),
                ));
            }
        }
        Ok(Settings {
            steps: st.steps,
            max_iterations: st.max_iterations,
            tol_force: st.tol_force,
            tol_disp: st.tol_disp,
            compliance: st.compliance.clone(),
            buckling: st.buckling,
            line_search: st.line_search,
            tangent_eigenvalues: st.tangent_eigenvalues,
            path: match st.path {
                Some(PathSpec::ArcLength) => flexmbd_core::statics::PathMethod::ArcLength,
                _ => flexmbd_core::statics::PathMethod::LoadSteps,
            },
        })
    }

    /// `[simulate]`, the histories of loads and prescribed values, and the initial velocities.
    fn simulation(&self, model: &Model) -> Result<SimulateSettings, SpecError> {
        let mut sim = match &self.simulate {
            Some(s) => simulate_settings(s).map_err(|m| invalid(s.src.at, m))?,
            None => SimulateSettings::default(),
        };
        for l in &self.loads {
            let h = l.history.clone().unwrap_or_default();
            h.validate().map_err(|e| {
                invalid(
                    l.src.at,
                    format!("[[load]] at node `{}`: history: {e}", l.node),
                )
            })?;
            sim.excitation.loads.push(h);
        }
        // the model lists prescribed coordinates first, then deformations (ModelBuilder::build)
        let (mut h_coord, mut h_def) = (Vec::new(), Vec::new());
        for (k, p) in self.prescribed.iter().enumerate() {
            let h = p.history.clone().unwrap_or_default();
            let fail =
                |m: String| invalid(p.src.at, format!("[[prescribe]] {}: history: {m}", k + 1));
            h.validate().map_err(|e| fail(e.to_string()))?;
            if h.is_discontinuous() {
                return Err(fail(
                    "a prescribed motion cannot jump (a step); use a ramp or a table".into(),
                ));
            }
            match p.target {
                PrescribeTarget::Coordinate { .. } => h_coord.push(h),
                PrescribeTarget::Deformation { .. } => h_def.push(h),
            }
        }
        sim.excitation.prescribed = h_coord.into_iter().chain(h_def).collect();
        for v in &self.velocities {
            let node = model.node_id(&v.node).ok_or_else(|| {
                invalid(
                    v.src.at,
                    format!("[[velocity]]: node `{}` is not defined", v.node),
                )
            })?;
            if model.nodes[node].ix_rot.is_none() && v.omega != [0.0; 3] {
                return Err(invalid(
                    v.src.at,
                    format!(
                        "[[velocity]] at node `{}`: `omega` needs a rotational node",
                        v.node
                    ),
                ));
            }
            sim.excitation
                .velocities
                .push(velocity(v, node).map_err(|m| invalid(v.src.at, m))?);
        }
        Ok(sim)
    }
}

/// The core's intended freedom of a `[[freedom]]` entry: exactly one of `translation` and
/// `rotation`, finite values, a non-zero direction, a body that names an element or a node.
fn intended(
    model: &Model,
    f: &super::FreedomEntry,
) -> Result<flexmbd_core::kinematics::freedom::IntendedFreedom, String> {
    use flexmbd_core::kinematics::freedom::{FreedomMotion, IntendedFreedom};
    let known = model.elements.iter().any(|e| e.name == f.body) || model.node_id(&f.body).is_some();
    if !known {
        return Err(format!(
            "body `{}` is not an element or a node of the model",
            f.body
        ));
    }
    let direction = |v: &[f64; 3], what: &str| {
        if v.iter().any(|a| !a.is_finite()) || v.iter().all(|a| *a == 0.0) {
            Err(format!(
                "`{what}` must be a non-zero vector of finite numbers"
            ))
        } else {
            Ok(*v)
        }
    };
    let motion = match (&f.translation, &f.rotation) {
        (Some(t), None) => FreedomMotion::Translation {
            direction: direction(t, "translation")?,
        },
        (None, Some(r)) => {
            if r.point.iter().any(|a| !a.is_finite()) || !r.pitch.is_finite() {
                return Err("`rotation`: `point` and `pitch` must be finite numbers".into());
            }
            FreedomMotion::Rotation {
                point: r.point,
                axis: direction(&r.axis, "rotation.axis")?,
                pitch: r.pitch,
            }
        }
        _ => return Err("give exactly one of `translation` and `rotation`".into()),
    };
    Ok(IntendedFreedom {
        body: f.body.clone(),
        motion,
    })
}
