//! [`ModelBuilder`]: a model built item by item, validated as it goes, compiled once.

use super::*;
use crate::elements::{Beam, FrameError, Hinge, Rigid, Truss};
use crate::math::norm;
use rustc_hash::FxHashMap as HashMap;

/// Length below which two nodes of an element count as coincident [m]. Flexures in precision
/// engineering are far longer than a nanometre; anything shorter is an input error.
pub const MIN_ELEMENT_LENGTH: f64 = 1e-9;

#[derive(Clone, Debug)]
struct PendingElement {
    name: String,
    nodes: Vec<NodeId>,
    spec: ElementSpec,
    free: Vec<usize>,
    input: Vec<usize>,
    /// Section data of a beam ([`ModelBuilder::set_beam_props`]).
    props: Option<crate::section::BeamProps>,
    /// Retardation time τ [s] of its material damping ([`ModelBuilder::set_damping`]).
    damping: f64,
}

/// Builds a [`Model`] item by item; each `add_*` validates what it can at once.
///
/// Names are looked up in hash maps and elements refer to nodes by index, so building is linear
/// in the size of the model (10,000 beams in a few milliseconds).
#[derive(Clone, Debug, Default)]
pub struct ModelBuilder {
    name: String,
    /// (name, position, rotation asked for, host)
    nodes: Vec<(String, [f64; 3], bool, Option<NodeId>)>,
    node_index: HashMap<String, NodeId>,
    elements: Vec<PendingElement>,
    element_names: HashMap<String, usize>,
    /// (node, dofs); `None` = all coordinates the node has.
    fixes: Vec<(String, Option<Vec<Dof>>)>,
    inputs: Vec<(String, Option<Vec<Dof>>)>,
    /// (element index, mode 1-based)
    rigid_modes: Vec<(usize, usize)>,
    loads: Vec<(String, [f64; 3], [f64; 3])>,
    gravity: [f64; 3],
    spin: Option<Spin>,
    masses: Vec<(String, f64)>,
    inertias: Vec<(String, [[f64; 3]; 3])>,
    prescribed_x: Vec<(String, Dof, f64)>,
    /// (element index, mode 1-based, value)
    prescribed_e: Vec<(usize, usize, f64)>,
}

/// `v` is finite, else a [`ModelError::BadValue`] of the item (named only then: reading a model
/// of 10^5 items allocates no name it does not need).
fn check_finite(
    item: impl FnOnce() -> Item,
    field: &'static str,
    v: &[f64],
) -> Result<(), ModelError> {
    match v.iter().find(|x| !x.is_finite()) {
        Some(&value) => Err(ModelError::BadValue {
            item: item(),
            field,
            requirement: "finite",
            value,
        }),
        None => Ok(()),
    }
}

impl ModelBuilder {
    /// An empty model with a name.
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            ..Default::default()
        }
    }

    /// Room for `nodes` more nodes and `elements` more elements (a reader that knows its counts
    /// saves the regrowth of every list).
    pub fn reserve(&mut self, nodes: usize, elements: usize) {
        self.nodes.reserve(nodes);
        self.node_index.reserve(nodes);
        self.elements.reserve(elements);
        self.element_names.reserve(elements);
    }

    /// Add a node at `x0` [m]; `rot` asks for rotation coordinates even if no element uses them.
    pub fn add_node(&mut self, name: &str, x0: [f64; 3], rot: bool) -> Result<NodeId, ModelError> {
        check_finite(|| Item::Node(name.to_string()), "x", &x0)?;
        if self.node_index.contains_key(name) {
            return Err(ModelError::DuplicateNode {
                node: name.to_string(),
            });
        }
        let id = self.nodes.len();
        let name = name.to_string();
        self.node_index.insert(name.clone(), id);
        self.nodes.push((name, x0, rot, None));
        Ok(id)
    }

    /// Add a node `at` an earlier node: it shares the host's position and has its own rotation
    /// (SPACAR: a second rotational node on one translational node, as for a hinge).
    pub fn add_node_at(&mut self, name: &str, host: &str) -> Result<NodeId, ModelError> {
        if self.node_index.contains_key(name) {
            return Err(ModelError::DuplicateNode {
                node: name.to_string(),
            });
        }
        let unknown = || ModelError::UnknownHost {
            node: name.to_string(),
            host: host.to_string(),
        };
        let &h = self.node_index.get(host).ok_or_else(unknown)?;
        // a chain of hosts resolves to the first
        let h = self.nodes[h].3.unwrap_or(h);
        let id = self.nodes.len();
        let x0 = self.nodes[h].1;
        let name = name.to_string();
        self.node_index.insert(name.clone(), id);
        self.nodes.push((name, x0, true, Some(h)));
        Ok(id)
    }

    /// Add an element over named nodes; `free` and `input` list 1-based deformation modes.
    pub fn add_element(
        &mut self,
        name: &str,
        nodes: &[&str],
        spec: ElementSpec,
        free: &[i64],
        input: &[i64],
    ) -> Result<(), ModelError> {
        let el = name.to_string();
        if self.element_names.contains_key(name) {
            return Err(ModelError::DuplicateElement { element: el });
        }
        let (kind, ne, expected) = match &spec {
            ElementSpec::Truss { .. } => ("truss", 1, "2"),
            ElementSpec::Beam { .. } => ("beam", 6, "2"),
            ElementSpec::Hinge { .. } => ("hinge", 3, "2"),
            ElementSpec::Rigid => ("rigid", usize::MAX, "at least 2"),
        };
        let count_ok = if ne == usize::MAX {
            nodes.len() >= 2
        } else {
            nodes.len() == 2
        };
        if !count_ok {
            return Err(ModelError::NodeCount {
                element: el,
                kind,
                expected,
                found: nodes.len(),
            });
        }
        let mut ids = Vec::with_capacity(nodes.len());
        for &n in nodes {
            let id = *self
                .node_index
                .get(n)
                .ok_or_else(|| ModelError::UnknownNode {
                    element: el.clone(),
                    node: n.into(),
                })?;
            if ids.contains(&id) {
                return Err(ModelError::RepeatedNode {
                    element: el,
                    node: n.into(),
                });
            }
            ids.push(id);
        }
        let item = || Item::Element(name.to_string());
        match &spec {
            ElementSpec::Truss { ea } => check_finite(item, "EA", &[*ea])?,
            ElementSpec::Beam { orient, ct } => {
                check_finite(item, "orient", orient.as_ref().map_or(&[][..], |o| &o[..]))?;
                check_finite(item, "ct", &[*ct])?;
            }
            ElementSpec::Hinge { axis, k } => {
                check_finite(item, "axis", axis)?;
                check_finite(item, "k", &[*k])?;
            }
            ElementSpec::Rigid => {}
        }
        // element length and frame
        if kind != "rigid" && kind != "hinge" {
            let l0 = norm(crate::math::sub(self.nodes[ids[1]].1, self.nodes[ids[0]].1));
            if l0 < MIN_ELEMENT_LENGTH {
                return Err(ModelError::ZeroLength { element: el, l0 });
            }
        }
        let frame_err = |source| ModelError::Frame {
            element: name.to_string(),
            source,
        };
        match &spec {
            ElementSpec::Beam { orient, .. } => {
                let (p, q) = (self.nodes[ids[0]].1, self.nodes[ids[1]].1);
                Beam::new([0, 1], p, q, *orient).map_err(frame_err)?;
            }
            ElementSpec::Hinge { axis, .. } => {
                Hinge::new([0, 1], *axis).map_err(|e| match e {
                    FrameError::ZeroAxis => ModelError::BadValue {
                        item: item(),
                        field: "axis",
                        requirement: "non-zero",
                        value: 0.0,
                    },
                    other => frame_err(other),
                })?;
            }
            _ => {}
        }
        // mode lists
        let ne_real = if kind == "rigid" { usize::MAX } else { ne };
        let check_modes = |list: &[i64]| -> Result<Vec<usize>, ModelError> {
            list.iter()
                .map(|&m| {
                    if m >= 1 && (m as usize) <= ne_real {
                        Ok(m as usize)
                    } else {
                        Err(ModelError::BadMode {
                            element: el.clone(),
                            kind,
                            mode: m,
                            ne: if kind == "rigid" { 0 } else { ne },
                        })
                    }
                })
                .collect()
        };
        let free = check_modes(free)?;
        let input = check_modes(input)?;
        if let Some(&m) = free.iter().find(|m| input.contains(m)) {
            return Err(ModelError::ModeConflict {
                element: el,
                mode: m,
            });
        }
        self.element_names.insert(el.clone(), self.elements.len());
        self.elements.push(PendingElement {
            name: el,
            nodes: ids,
            spec,
            free,
            input,
            props: None,
            damping: 0.0,
        });
        Ok(())
    }

    /// Add a straight chain of `n` beams from `start` to `end` [m]: nodes `{prefix}n0` …
    /// `{prefix}n{n}` at equal spacing and elements `{prefix}b0` … `{prefix}b{n−1}` (element i
    /// from node i to node i + 1), all with the orientation vector `orient` (local y; `None` for
    /// SPACAR's default) and, when given, the section data `props`. Returns the node ids in
    /// order, first to last. Every name must be new.
    pub fn add_beam_chain(
        &mut self,
        prefix: &str,
        start: [f64; 3],
        end: [f64; 3],
        n: usize,
        orient: Option<[f64; 3]>,
        props: Option<crate::section::BeamProps>,
    ) -> Result<Vec<NodeId>, ModelError> {
        if n == 0 {
            return Err(ModelError::BadValue {
                item: Item::Element(format!("{prefix}b0")),
                field: "number of beams in the chain",
                requirement: "at least 1",
                value: 0.0,
            });
        }
        let mut ids = Vec::with_capacity(n + 1);
        for i in 0..=n {
            let s = i as f64 / n as f64;
            let x: [f64; 3] = std::array::from_fn(|k| start[k] + s * (end[k] - start[k]));
            ids.push(self.add_node(&format!("{prefix}n{i}"), x, false)?);
        }
        for i in 0..n {
            let (p, q) = (format!("{prefix}n{i}"), format!("{prefix}n{}", i + 1));
            let name = format!("{prefix}b{i}");
            self.add_element(
                &name,
                &[&p, &q],
                ElementSpec::Beam { orient, ct: 0.0 },
                &[],
                &[],
            )?;
            if let Some(props) = props {
                self.set_beam_props(&name, props)?;
            }
        }
        Ok(ids)
    }

    /// Stiffness, mass and section data of a beam added before.
    pub fn set_beam_props(
        &mut self,
        element: &str,
        props: crate::section::BeamProps,
    ) -> Result<(), ModelError> {
        let item = || Item::Element(element.to_string());
        let v = [
            props.ea,
            props.gj,
            props.eiy,
            props.eiz,
            props.shear[0],
            props.shear[1],
            props.ct,
            props.rho_a,
        ];
        check_finite(item, "section constants", &v)?;
        let index = self.element_names.get(element).copied();
        match index.map(|i| &mut self.elements[i]) {
            Some(
                pending @ PendingElement {
                    spec: ElementSpec::Beam { .. },
                    ..
                },
            ) => {
                pending.props = Some(props);
                Ok(())
            }
            _ => Err(ModelError::NotA {
                element: element.to_string(),
                kind: "beam",
            }),
        }
    }

    /// Material damping of an element added before (Kelvin–Voigt): its stress resultants
    /// become σ = S (e + τ ė) in a time simulation, with the retardation time `tau` [s] ≥ 0.
    pub fn set_damping(&mut self, element: &str, tau: f64) -> Result<(), ModelError> {
        let Some(&index) = self.element_names.get(element) else {
            return Err(ModelError::NotA {
                element: element.to_string(),
                kind: "element",
            });
        };
        if !(tau.is_finite() && tau >= 0.0) {
            return Err(ModelError::BadValue {
                item: Item::Element(element.to_string()),
                field: "damping (retardation time τ [s])",
                requirement: "finite and ≥ 0",
                value: tau,
            });
        }
        self.elements[index].damping = tau;
        Ok(())
    }

    /// Declare deformation modes (1-based) rigid in statics even if they have stiffness.
    pub fn set_rigid_modes(&mut self, element: &str, modes: &[i64]) -> Result<(), ModelError> {
        let Some(&index) = self.element_names.get(element) else {
            return Err(ModelError::NotA {
                element: element.to_string(),
                kind: "element",
            });
        };
        let el = &self.elements[index];
        for &m in modes {
            if m < 1 || el.input.contains(&(m as usize)) {
                return Err(ModelError::ModeConflict {
                    element: element.to_string(),
                    mode: m.max(0) as usize,
                });
            }
            self.rigid_modes.push((index, m as usize));
        }
        Ok(())
    }

    /// A dead force [N] and moment [N·m] on a node, reached at load factor 1.
    pub fn add_load(
        &mut self,
        node: &str,
        force: [f64; 3],
        moment: [f64; 3],
    ) -> Result<(), ModelError> {
        let item = || Item::Load(node.to_string());
        check_finite(item, "force", &force)?;
        check_finite(item, "moment", &moment)?;
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "load",
                node: node.into(),
            });
        }
        self.loads.push((node.to_string(), force, moment));
        Ok(())
    }

    /// Gravitational acceleration [m/s²].
    pub fn set_gravity(&mut self, g: [f64; 3]) -> Result<(), ModelError> {
        check_finite(|| Item::Model, "gravity", &g)?;
        self.gravity = g;
        Ok(())
    }

    /// Steady rotation at angular velocity `omega` [rad/s] about the axis through `point`
    /// ([`Spin`]): centrifugal loads in statics, centrifugal softening in dynamics.
    pub fn set_spin(&mut self, omega: [f64; 3], point: [f64; 3]) -> Result<(), ModelError> {
        check_finite(|| Item::Model, "spin", &omega)?;
        check_finite(|| Item::Model, "spin_point", &point)?;
        self.spin = Some(Spin { omega, point });
        Ok(())
    }

    /// A point mass [kg] at a node.
    pub fn add_point_mass(&mut self, node: &str, m: f64) -> Result<(), ModelError> {
        if !(m.is_finite() && m >= 0.0) {
            return Err(ModelError::BadValue {
                item: Item::Mass(node.into()),
                field: "m",
                requirement: "finite and ≥ 0",
                value: m,
            });
        }
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "mass",
                node: node.into(),
            });
        }
        self.masses.push((node.to_string(), m));
        Ok(())
    }

    /// An inertia tensor [kg·m²] about a rotational node, global axes in the reference
    /// orientation (SPACAR `XM n Ixx Ixy Ixz Iyy Iyz Izz`): [Ixx, Ixy, Ixz, Iyy, Iyz, Izz].
    pub fn add_inertia(&mut self, node: &str, i: [f64; 6]) -> Result<(), ModelError> {
        check_finite(|| Item::Mass(node.into()), "inertia", &i)?;
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what: "mass",
                node: node.into(),
            });
        }
        let t = [[i[0], i[1], i[2]], [i[1], i[3], i[4]], [i[2], i[4], i[5]]];
        // positive semi-definite: principal minors
        let m2 = t[0][0] * t[1][1] - t[0][1] * t[0][1];
        let det = t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[1][2])
            - t[0][1] * (t[0][1] * t[2][2] - t[1][2] * t[0][2])
            + t[0][2] * (t[0][1] * t[1][2] - t[1][1] * t[0][2]);
        let scale = i
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        if t[0][0] < 0.0
            || t[1][1] < 0.0
            || t[2][2] < 0.0
            || m2 < -1e-12 * scale * scale
            || det < -1e-12 * scale.powi(3)
        {
            return Err(ModelError::BadValue {
                item: Item::Mass(node.into()),
                field: "inertia",
                requirement: "a positive semi-definite tensor",
                value: det,
            });
        }
        self.inertias.push((node.to_string(), t));
        Ok(())
    }

    /// Prescribe an input coordinate's final value (translation: displacement [m]; rotation:
    /// angle [rad]); the dof becomes an input.
    pub fn prescribe_coordinate(
        &mut self,
        node: &str,
        dof: Dof,
        value: f64,
    ) -> Result<(), ModelError> {
        check_finite(|| Item::Input(node.into()), dof.name(), &[value])?;
        self.entry("inputs", node, Some(&[dof]))?;
        self.prescribed_x.push((node.to_string(), dof, value));
        Ok(())
    }

    /// Prescribe an input deformation's final value; mode 1-based, made an input.
    pub fn prescribe_deformation(
        &mut self,
        element: &str,
        mode: usize,
        value: f64,
    ) -> Result<(), ModelError> {
        check_finite(|| Item::Element(element.into()), "input value", &[value])?;
        let Some(&index) = self.element_names.get(element) else {
            return Err(ModelError::NotA {
                element: element.to_string(),
                kind: "element",
            });
        };
        let el = &mut self.elements[index];
        el.free.retain(|&m| m != mode);
        if !el.input.contains(&mode) {
            el.input.push(mode);
        }
        self.prescribed_e.push((index, mode, value));
        Ok(())
    }

    /// Fix the listed dofs of a node (support); `None` = all its coordinates.
    pub fn fix(&mut self, node: &str, dofs: Option<&[Dof]>) -> Result<(), ModelError> {
        self.entry("fix", node, dofs)
    }

    /// Make the listed dofs of a node generalised coordinates (x^m); `None` = all of them.
    pub fn input(&mut self, node: &str, dofs: Option<&[Dof]>) -> Result<(), ModelError> {
        self.entry("inputs", node, dofs)
    }

    fn entry(
        &mut self,
        what: &'static str,
        node: &str,
        dofs: Option<&[Dof]>,
    ) -> Result<(), ModelError> {
        if !self.node_index.contains_key(node) {
            return Err(ModelError::UnknownNodeInEntry {
                what,
                node: node.into(),
            });
        }
        // `None` (all) is resolved at build time, when rotations are known
        let target = if what == "fix" {
            &mut self.fixes
        } else {
            &mut self.inputs
        };
        target.push((node.to_string(), dofs.map(<[Dof]>::to_vec)));
        Ok(())
    }

    /// Validate and compile the model.
    pub fn build(self) -> Result<Model, ModelError> {
        // the builder's names move into the model (no copies: 10^5 items)
        let ModelBuilder {
            name: model_name,
            nodes: pending_nodes,
            node_index,
            elements: pending,
            element_names: _,
            fixes,
            inputs,
            rigid_modes,
            loads: pending_loads,
            gravity,
            spin,
            masses,
            inertias,
            prescribed_x,
            prescribed_e,
        } = self;
        // which nodes carry rotations
        let mut rot: Vec<bool> = pending_nodes.iter().map(|n| n.2 || n.3.is_some()).collect();
        for e in &pending {
            match e.spec {
                ElementSpec::Beam { .. } | ElementSpec::Hinge { .. } => {
                    for &n in &e.nodes {
                        rot[n] = true;
                    }
                }
                ElementSpec::Rigid => rot[e.nodes[0]] = true,
                ElementSpec::Truss { .. } => {}
            }
        }
        // coordinate layout
        let mut nodes = Vec::with_capacity(pending_nodes.len());
        let mut nx = 0;
        for (i, (name, x0, _, host)) in pending_nodes.into_iter().enumerate() {
            let ix_pos = match host {
                Some(h) => nodes.get(h).map_or(0, |n: &Node| n.ix_pos),
                None => {
                    nx += 3;
                    nx - 3
                }
            };
            let ix_rot = rot[i].then(|| {
                nx += 4;
                nx - 4
            });
            nodes.push(Node {
                name,
                x0,
                host,
                ix_pos,
                ix_rot,
            });
        }
        // (the element maps hold 32-bit indices into x)
        if u32::try_from(nx).is_err() {
            return Err(ModelError::TooLarge { nx, max: u32::MAX });
        }
        // elements
        let mut elements = Vec::with_capacity(pending.len());
        let mut e_kind = Vec::with_capacity(6 * pending.len());
        let mut ne = 0;
        let mut sections: HashMap<[u64; 16], std::sync::Arc<crate::section::BeamProps>> =
            HashMap::default();
        for p in pending {
            let pos = |k: usize| nodes[p.nodes[k]].x0;
            let two = [p.nodes[0], *p.nodes.get(1).unwrap_or(&p.nodes[0])];
            let element = match &p.spec {
                ElementSpec::Truss { ea } => {
                    let mut t = Truss::new(two, pos(0), pos(1));
                    t.ea = *ea;
                    Element::Truss(t)
                }
                ElementSpec::Beam { orient, ct } => {
                    let mut b = Beam::new(two, pos(0), pos(1), *orient).map_err(|source| {
                        ModelError::Frame {
                            element: p.name.clone(),
                            source,
                        }
                    })?;
                    b.ct = *ct;
                    if let Some(props) = p.props {
                        // one shared copy per distinct section
                        let shared = sections
                            .entry(props.key())
                            .or_insert_with(|| std::sync::Arc::new(props));
                        b.set_shared_props(shared.clone());
                    }
                    Element::Beam(b)
                }
                ElementSpec::Hinge { axis, k } => {
                    let mut h = Hinge::new(two, *axis).map_err(|source| ModelError::Frame {
                        element: p.name.clone(),
                        source,
                    })?;
                    h.k = *k;
                    Element::Hinge(h)
                }
                ElementSpec::Rigid => {
                    let positions: Vec<[f64; 3]> = (0..p.nodes.len()).map(pos).collect();
                    let flags = p.nodes.iter().map(|&n| rot[n]).collect();
                    // a member at the position of an earlier member (a node `at` it) adds only
                    // its rotation: its position constraints would be redundant
                    let pos_flags = (0..p.nodes.len())
                        .map(|k| {
                            let ip = nodes[p.nodes[k]].ix_pos;
                            !(0..k).any(|j| nodes[p.nodes[j]].ix_pos == ip)
                        })
                        .collect();
                    Element::Rigid(Rigid::with_shared_positions(
                        p.nodes, &positions, flags, pos_flags,
                    ))
                }
            };
            let n_modes = element.ne();
            for &m in p.free.iter().chain(&p.input) {
                if m > n_modes {
                    return Err(ModelError::BadMode {
                        element: p.name.clone(),
                        kind: element.type_name(),
                        mode: m as i64,
                        ne: n_modes,
                    });
                }
            }
            let mut xmap: Vec<u32> = Vec::with_capacity(14);
            for u in element.node_uses() {
                let n = &nodes[u.node];
                if u.pos {
                    xmap.extend((n.ix_pos..n.ix_pos + 3).map(|i| i as u32));
                }
                if u.rot {
                    let r = n
                        .ix_rot
                        .expect("rotation flags were set for every element use");
                    xmap.extend((r..r + 4).map(|i| i as u32));
                }
            }
            xmap.shrink_to_fit();
            let mut kinds = vec![DefKind::Fixed; n_modes];
            for &m in &p.free {
                kinds[m - 1] = DefKind::Free;
            }
            for &m in &p.input {
                kinds[m - 1] = DefKind::Input;
            }
            e_kind.extend(kinds);
            elements.push(ElementEntry {
                name: p.name,
                element,
                ie: ne,
                xmap,
                damping: p.damping,
            });
            ne += n_modes;
        }
        // partition of x
        let mut x_kind = vec![CoordKind::Free; nx];
        for (what, list, kind) in [
            ("fix", &fixes, CoordKind::Fixed),
            ("inputs", &inputs, CoordKind::Input),
        ] {
            for (name, dofs) in list {
                let n = &nodes[node_index[name]];
                let all = dofs.is_none();
                for &d in dofs.as_deref().unwrap_or(&Dof::ALL) {
                    match n.x_index(d) {
                        Some(i) => {
                            if x_kind[i] != CoordKind::Free && x_kind[i] != kind {
                                return Err(ModelError::FixAndInput {
                                    node: n.name.clone(),
                                    dof: d.name(),
                                });
                            }
                            x_kind[i] = kind;
                        }
                        None if all => {}
                        None => {
                            return Err(ModelError::NoRotation {
                                what,
                                node: n.name.clone(),
                                dof: d.name(),
                            })
                        }
                    }
                }
            }
        }
        // statics data: explicit rigid modes, loads, masses, prescribed values
        let mut explicit_rigid = vec![false; ne];
        // pending element i compiles to elements[i]
        for &(index, mode) in &rigid_modes {
            let el = &elements[index];
            if mode > el.element.ne() {
                return Err(ModelError::BadMode {
                    element: el.name.clone(),
                    kind: el.element.type_name(),
                    mode: mode as i64,
                    ne: el.element.ne(),
                });
            }
            explicit_rigid[el.ie + mode - 1] = true;
        }
        let mut loads = Loads {
            gravity,
            spin,
            ..Default::default()
        };
        for (name, force, moment) in &pending_loads {
            let node = node_index[name];
            if moment.iter().any(|m| *m != 0.0) && !nodes[node].rot() {
                return Err(ModelError::MomentWithoutRotation { node: name.clone() });
            }
            loads.nodal.push(NodalLoad {
                node,
                force: *force,
                moment: *moment,
            });
        }
        for (name, m) in &masses {
            loads.point_masses.push((node_index[name], *m));
        }
        for (name, t) in &inertias {
            let node = node_index[name];
            if !nodes[node].rot() {
                return Err(ModelError::NoRotation {
                    what: "mass",
                    node: name.clone(),
                    dof: "inertia",
                });
            }
            loads.inertias.push((node, *t));
        }
        for (name, dof, value) in &prescribed_x {
            let i =
                nodes[node_index[name]]
                    .x_index(*dof)
                    .ok_or_else(|| ModelError::NoRotation {
                        what: "inputs",
                        node: name.clone(),
                        dof: dof.name(),
                    })?;
            loads.prescribed.push(Prescribed {
                target: Target::Coordinate(i),
                value: *value,
            });
        }
        for &(index, mode, value) in &prescribed_e {
            let el = &elements[index];
            loads.prescribed.push(Prescribed {
                target: Target::Deformation(el.ie + mode - 1),
                value,
            });
        }
        Ok(Model {
            name: model_name,
            nodes,
            elements,
            nx,
            ne,
            partition: Partition {
                x: x_kind,
                e: e_kind,
            },
            explicit_rigid,
            loads,
        })
    }
}
