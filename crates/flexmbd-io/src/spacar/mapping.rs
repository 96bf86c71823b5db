//! From SPACAR node numbers, elements and partition to flexmbd nodes, elements, fix and inputs.
//!
//! **Nodes.** SPACAR numbers translational nodes (3 coordinates) and rotational nodes (4 Euler
//! parameters) separately; an element pairs them in its slots. flexmbd nodes carry a position
//! and optionally a rotation, so:
//!
//! - translational node `t` → node `"t"` at its `X` position, without rotation;
//! - rotational node `r` that an element pairs with translational node `t` (BEAM, BEAMW,
//!   RBEAM slots p and q) → node `"t@r"` placed `at` `"t"`: it has its own Euler parameters and
//!   shares the position of `"t"` (no extra position coordinates);
//! - rotational node `r` used only by hinges (it has no position in SPACAR) → `"@r"`, placed
//!   `at` the translational node of the nearest paired rotational node (breadth-first through
//!   the hinges; hinges use rotations only, so the place does not matter); a group of
//!   hinge-only rotational nodes with no paired node at all is placed at an artificial node
//!   `"origin"` at (0, 0, 0) whose position is fixed (it has no SPACAR counterpart, so it adds
//!   no columns to Dcc);
//! - a rotational node paired with two different translational nodes is an error (flexmbd
//!   attaches a rotation to one position);
//! - warping nodes (`BEAMW`) are not modelled.
//!
//! This keeps the numbers of both SPACAR nodes visible in every flexmbd name and makes the
//! coordinates map one to one: x, y, z of `"t"` are SPACAR coordinates 1–3 of `t`; rx, ry, rz of
//! `"t@r"` (or `"@r"`) are λ1..λ3 (coordinates 2–4) of `r`.
//!
//! **Elements.** BEAM → beam over `["xp@rp", "xq@rq"]` with the orientation vector; BEAMW → the
//! same beam (modes 7–8 and warping ignored); RBEAM → rigid body over `["xp@rp", "xq"]` (the
//! reference node with its rotation and a position-only member: 3 deformations, as SPACAR's
//! RBEAM); HINGE → hinge over the nodes of `rp` and `rq` with its axis and `k` = first `ESTIFF` value;
//! TRUSS → truss over `["xp", "xq"]` with `EA` = `ESTIFF` value.
//!
//! **Partition.** RLSE → free (e^c); DYNE and INPUTE → input (e^m: SPACAR's dynamic DOFs e^d
//! are rows of Dcc exactly like inputs, theory.md §4); FIX → fix; INPUTX → inputs, DYNX →
//! `dynamic_inputs` (x^d counts with x^m in the kinematic check; it is an unknown in statics).
//! This is the kinematic mapping; the module `statics` adds the static data on top of it.

use super::*;
use crate::error::{at_line, InputError};
use crate::spec::{
    BeamSpec, DofEntry, ElementEntrySpec, ElementKind as Kind, ModelSpec, NodePlace, NodeSpec, Src,
};
use flexmbd_core::model::Dof;
use rustc_hash::FxHashMap as HashMap;
use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write;

/// Name of the artificial position node of hinge-only rotational nodes.
pub const ORIGIN: &str = "origin";

/// How SPACAR node numbers map onto flexmbd node names.
#[derive(Clone, Debug, Default)]
pub struct NodeMap {
    /// Rotational node → (host translational node or `None` for the origin, whether it is
    /// placed through hinges only).
    pub rot_host: BTreeMap<u32, (Option<u32>, bool)>,
    /// Warnings about the mapping (hinge-only groups placed at the origin).
    pub warnings: Vec<Warning>,
}

impl NodeMap {
    /// Work out the hosts of all rotational nodes.
    pub fn new(m: &SpacarModel) -> Result<NodeMap, InputError> {
        let mut home: HashMap<u32, (u32, u32, usize)> =
            HashMap::with_capacity_and_hasher(m.elements.len(), Default::default());
        let mut adj: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for e in &m.elements {
            let pairs: [Option<(u32, u32)>; 2] = match e.kind {
                ElementKind::Beam { xp, rp, xq, rq, .. }
                | ElementKind::BeamW { xp, rp, xq, rq, .. } => [Some((xp, rp)), Some((xq, rq))],
                ElementKind::RBeam { xp, rp, .. } => [Some((xp, rp)), None],
                ElementKind::Hinge { rp, rq, .. } => {
                    adj.entry(rp).or_default().push(rq);
                    adj.entry(rq).or_default().push(rp);
                    [None, None]
                }
                ElementKind::Truss { .. } => [None, None],
            };
            for (t, r) in pairs.into_iter().flatten() {
                match home.get(&r) {
                    Some(&(t0, el, line)) if t0 != t => {
                        return Err(at_line(
                            &m.file,
                            e.line,
                            1,
                            format!(
                                "{} {}: rotational node {r} is paired with translational node {t} here, but with translational node {t0} by element {el} on line {line}; one rotational node at two positions is not supported (flexmbd attaches each rotation to one position node)",
                                e.kind.keyword(),
                                e.number
                            ),
                        ));
                    }
                    Some(_) => {}
                    None => {
                        home.insert(r, (t, e.number, e.line));
                    }
                }
            }
        }
        let mut map = NodeMap::default();
        for (&r, &(t, _, _)) in &home {
            map.rot_host.insert(r, (Some(t), false));
        }
        let hinge_only: Vec<u32> = m
            .node_kinds
            .iter()
            .filter(|(n, k)| **k == NodeKind::Rotational && !home.contains_key(n))
            .map(|(n, _)| *n)
            .collect();
        for r in hinge_only {
            // breadth-first through the hinges to the nearest paired rotational node
            let mut seen = BTreeSet::from([r]);
            let mut queue = VecDeque::from([r]);
            let mut host = None;
            while let Some(n) = queue.pop_front() {
                if let Some(&(t, _, _)) = home.get(&n) {
                    host = Some(t);
                    break;
                }
                for &k in adj.get(&n).into_iter().flatten() {
                    if seen.insert(k) {
                        queue.push_back(k);
                    }
                }
            }
            if host.is_none() {
                let line = m
                    .elements
                    .iter()
                    .find(|e| e.kind.node_slots().iter().any(|s| s.0 == r))
                    .map_or(1, |e| e.line);
                map.warnings.push(Warning {
                    line,
                    message: format!("rotational node {r} is connected by hinges only, and no rotational node of its group belongs to a translational node: it is placed at an artificial node `{ORIGIN}` at (0, 0, 0) with fixed position (hinges use rotations only, so this does not change the kinematic result)"),
                });
            }
            map.rot_host.insert(r, (host, true));
        }
        Ok(map)
    }

    /// flexmbd name of a translational node.
    pub fn trans_name(t: u32) -> String {
        t.to_string()
    }

    /// flexmbd name of a rotational node: `"t@r"` when an element pairs it with translational
    /// node `t`, `"@r"` when only hinges use it.
    pub fn rot_name(&self, r: u32) -> String {
        match self.rot_host.get(&r) {
            Some((Some(t), false)) => format!("{t}@{r}"),
            _ => format!("@{r}"),
        }
    }

    /// flexmbd name of any SPACAR node, if it has one (warping nodes have none).
    pub fn name(&self, m: &SpacarModel, n: u32) -> Option<String> {
        match m.node_kinds.get(&n)? {
            NodeKind::Translational => Some(Self::trans_name(n)),
            NodeKind::Rotational => Some(self.rot_name(n)),
            NodeKind::Warping => None,
        }
    }
}

/// A number for comments: whole numbers without `.0`, others in the shortest exact form.
pub(super) fn fmt_num(x: f64) -> String {
    if x == x.trunc() && x.abs() < 1e15 {
        format!("{x}")
    } else {
        format!("{x:?}")
    }
}

pub(super) fn fmt_values(v: &[f64]) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(" ")
}

fn fmt_named(names: &[&str], v: &[f64]) -> String {
    v.iter()
        .enumerate()
        .map(|(i, x)| format!("{}={}", names.get(i).copied().unwrap_or("?"), fmt_num(*x)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn fmt_modes(v: &[u32]) -> String {
    v.iter().map(u32::to_string).collect::<Vec<_>>().join(" ")
}

/// The neutral model of a SPACAR model.
///
/// `comments`: write the SPACAR provenance of every item as comments (the document of
/// `convert`); an analysis of the file skips them (most of the mapping's time on 10^5 beams).
pub(super) fn to_spec(m: &SpacarModel, comments: bool) -> Result<ModelSpec, InputError> {
    to_spec_with(m, comments, &NodeMap::new(m)?)
}

/// [`to_spec`] with the node map of `m` already made.
pub(super) fn to_spec_with(
    m: &SpacarModel,
    comments: bool,
    map: &NodeMap,
) -> Result<ModelSpec, InputError> {
    let err = |line: usize, msg: String| at_line(&m.file, line, 1, msg);
    let x_of: HashMap<u32, &Position> = m.positions.iter().map(|p| (p.node, p)).collect();

    // --- nodes: each translational node, then the rotational nodes placed at it ---
    let mut spec = ModelSpec {
        name: m.name.clone(),
        ..Default::default()
    };
    // the line of the first element that uses each node (one pass: linear in the model size)
    let mut first_line: HashMap<u32, usize> = HashMap::default();
    for e in &m.elements {
        for (n, _) in e.kind.node_slots() {
            first_line.entry(n).or_insert(e.line);
        }
    }
    let first_use = |n: u32| first_line.get(&n).copied();
    let mut hosted: BTreeMap<Option<u32>, Vec<u32>> = BTreeMap::new();
    for (&r, &(t, _)) in &map.rot_host {
        hosted.entry(t).or_default().push(r);
    }
    let rot_node = |r: u32, host: String| {
        let (_, via_hinges) = map.rot_host[&r];
        NodeSpec {
            name: map.rot_name(r),
            place: NodePlace::At(host),
            comment: comments.then(|| {
                if via_hinges {
                    format!("SPACAR rotational node {r} (hinges only, no position of its own)")
                } else {
                    format!("SPACAR rotational node {r}")
                }
            }),
            src: Src::maybe_line(first_use(r)),
        }
    };
    for (&t, kind) in &m.node_kinds {
        if *kind != NodeKind::Translational {
            continue;
        }
        // parse_dat guarantees one X line with 3 values; stay total for hand-made models
        let Some(x) = x_of
            .get(&t)
            .and_then(|p| <[f64; 3]>::try_from(&p.values[..]).ok())
        else {
            return Err(err(
                first_use(t).unwrap_or(1),
                format!("translational node {t} has no X line with 3 coordinates"),
            ));
        };
        let p = x_of[&t];
        spec.nodes.push(NodeSpec {
            name: NodeMap::trans_name(t),
            place: NodePlace::Position { x, rot: false },
            comment: comments.then(|| format!("SPACAR translational node {t}")),
            src: Src::line(p.line),
        });
        for &r in hosted.get(&Some(t)).into_iter().flatten() {
            spec.nodes.push(rot_node(r, NodeMap::trans_name(t)));
        }
    }
    if let Some(rs) = hosted.get(&None) {
        let line = rs.iter().filter_map(|&r| first_use(r)).min();
        spec.nodes.push(NodeSpec {
            name: ORIGIN.into(),
            place: NodePlace::Position {
                x: [0.0; 3],
                rot: false,
            },
            comment: Some(
                "artificial position of hinge-only rotational nodes (not a SPACAR node)".into(),
            ),
            src: Src::maybe_line(line),
        });
        for &r in rs {
            spec.nodes.push(rot_node(r, ORIGIN.into()));
        }
        spec.fix.push(DofEntry {
            node: ORIGIN.into(),
            dofs: Some(vec![Dof::X, Dof::Y, Dof::Z]),
            comment: Some("artificial node: its position is not a SPACAR coordinate".into()),
            src: Src::maybe_line(line),
        });
    }

    // --- elements ---
    let by = ByElement::new(m);
    type Lists<'a> = HashMap<u32, Vec<&'a ModeList>>;
    // the modes the lists name for an element, in order, once each
    let modes = |lists: &[&Lists], el: u32, max: u32| -> Vec<i64> {
        let mut set: Vec<i64> = lists
            .iter()
            .flat_map(|of| of.get(&el).into_iter().flatten())
            .flat_map(|l| l.modes.iter().copied())
            .filter(|&k| k <= max)
            .map(i64::from)
            .collect();
        set.sort_unstable();
        set.dedup();
        set
    };
    for e in &m.elements {
        let n = e.number;
        let estiff = by.estiff.get(&n).map(|v| v.values.as_slice());
        let mut notes = if comments {
            element_notes(&by, e, estiff)
        } else {
            Vec::new()
        };
        let free = modes(&[&by.rlse], n, 6);
        let input = modes(&[&by.dyne, &by.inpute], n, 6);
        let (nodes, spec_el) = match &e.kind {
            ElementKind::Beam { rp, rq, orient, .. } => (
                vec![map.rot_name(*rp), map.rot_name(*rq)],
                Kind::Beam(BeamSpec {
                    orient: *orient,
                    ..Default::default()
                }),
            ),
            ElementKind::BeamW {
                rp,
                wp,
                rq,
                wq,
                orient,
                ..
            } => {
                if comments {
                    notes.push(format!(
                        "BEAMW: warping nodes {wp}, {wq} and deformations 7-8 are not modelled"
                    ));
                }
                (
                    vec![map.rot_name(*rp), map.rot_name(*rq)],
                    Kind::Beam(BeamSpec {
                        orient: *orient,
                        ..Default::default()
                    }),
                )
            }
            ElementKind::RBeam { rp, xq, orient, .. } => {
                let listed = m
                    .rlse
                    .iter()
                    .chain(&m.dyne)
                    .chain(&m.inpute)
                    .find(|l| l.element == n);
                if let Some(l) = listed {
                    return Err(err(
                        l.line,
                        format!("RBEAM {n}: its deformations cannot be released or made inputs in flexmbd (a rigid body has no free or input modes); model the part as a BEAM instead"),
                    ));
                }
                if let Some(o) = orient.filter(|_| comments) {
                    notes.push(format!(
                        "orientation (local y) {} is used by SPACAR for mass and drawing only",
                        fmt_values(&o)
                    ));
                }
                (
                    vec![map.rot_name(*rp), NodeMap::trans_name(*xq)],
                    Kind::Rigid,
                )
            }
            ElementKind::Hinge { rp, rq, axis } => (
                vec![map.rot_name(*rp), map.rot_name(*rq)],
                Kind::Hinge {
                    axis: *axis,
                    k: estiff
                        .as_ref()
                        .and_then(|v| v.first().copied())
                        .unwrap_or(0.0),
                },
            ),
            ElementKind::Truss { xp, xq } => (
                vec![NodeMap::trans_name(*xp), NodeMap::trans_name(*xq)],
                Kind::Truss {
                    ea: estiff
                        .as_ref()
                        .and_then(|v| v.first().copied())
                        .unwrap_or(0.0),
                },
            ),
        };
        spec.elements.push(ElementEntrySpec {
            name: n.to_string(),
            nodes,
            kind: spec_el,
            free,
            input,
            damping: None,
            comments: notes,
            src: Src::line(e.line),
        });
    }

    // --- fix and inputs ---
    let dofs = |kind: NodeKind, coords: &Option<Vec<u32>>| -> Vec<Dof> {
        let all: &[u32] = match kind {
            NodeKind::Translational => &[1, 2, 3],
            NodeKind::Rotational => &[2, 3, 4],
            NodeKind::Warping => &[],
        };
        let cs = coords.as_deref().unwrap_or(all);
        cs.iter()
            .filter_map(|&c| match (kind, c) {
                (NodeKind::Translational, 1..=3) => Some(Dof::ALL[c as usize - 1]),
                (NodeKind::Rotational, 2..=4) => Some(Dof::ALL[c as usize + 1]),
                _ => None,
            })
            .collect()
    };
    for (kw, lists, target) in [
        ("FIX", &m.fix, 0),
        ("INPUTX", &m.inputx, 1),
        ("DYNX", &m.dynx, 2),
    ] {
        for l in lists {
            let Some(&kind) = m.node_kinds.get(&l.node) else {
                continue;
            };
            let Some(name) = map.name(m, l.node) else {
                continue; // warping node
            };
            let d = dofs(kind, &l.coords);
            if d.is_empty() {
                continue;
            }
            let text = || match &l.coords {
                Some(c) => format!("{kw} {} {} (line {})", l.node, fmt_modes(c), l.line),
                None => format!("{kw} {} (line {})", l.node, l.line),
            };
            let entry = DofEntry {
                node: name,
                dofs: Some(d),
                comment: comments.then(text),
                src: Src::line(l.line),
            };
            match target {
                0 => spec.fix.push(entry),
                1 => spec.inputs.push(entry),
                _ => spec.dynamic_inputs.push(entry),
            }
        }
    }

    spec.header = header(m, map, None, false);
    Ok(spec)
}

/// The comments of element `e` in a converted file: its SPACAR line, the mode lists that name
/// it, its stiffness, mass and pre-stress values.
fn element_notes(by: &ByElement, e: &super::Element, estiff: Option<&[f64]>) -> Vec<String> {
    let n = e.number;
    let mut notes = vec![format!(
        "SPACAR {} {} (line {})",
        e.kind.keyword(),
        n,
        e.line
    )];
    for (kw, lists) in [
        ("RLSE", &by.rlse),
        ("DYNE", &by.dyne),
        ("INPUTE", &by.inpute),
    ] {
        for l in lists.get(&n).into_iter().flatten() {
            let to = match kw {
                "RLSE" => "free",
                "DYNE" => "input (dynamic DOFs: rows of Dcc, as in SPACAR)",
                _ => "input",
            };
            notes.push(format!(
                "{kw} {} {} (line {}) -> {to}",
                n,
                fmt_modes(&l.modes),
                l.line
            ));
        }
    }
    if let Some(v) = estiff {
        notes.push(format!(
            "ESTIFF: {}",
            fmt_named(e.kind.stiffness_columns(), v)
        ));
    }
    if let Some(v) = by.em.get(&n) {
        notes.push(format!(
            "EM: {}",
            fmt_named(e.kind.mass_columns(), &v.values)
        ));
    }
    if let Some(v) = by.esig.get(&n) {
        notes.push(format!("ESIG (pre-stress): {}", fmt_values(&v.values)));
    }
    notes
}

/// The comment block at the top of a converted file: provenance, naming, and the SPACAR data
/// the TOML format cannot express yet. `statics`: the static data is mapped too (loads,
/// masses, prescribed values and settings are then commented where they are written), with the
/// notes (warnings) of that mapping. `simulated`: the time simulation is mapped too (`TIMESTEP`,
/// `ERROR` and the inertia tensors are written).
pub(super) fn header(
    m: &SpacarModel,
    map: &NodeMap,
    statics: Option<&[&Warning]>,
    simulated: bool,
) -> Vec<String> {
    let mapped = statics.is_some();
    let mut h = vec![format!(
        "Converted by `flexmbd convert` from the SPACAR file {} (docs/spacar-import.md).",
        m.file
    )];
    if let Some(t) = &m.title {
        h.push(format!("Title: {t}"));
    }
    h.push("Nodes: \"t\" = SPACAR translational node t; \"t@r\" = SPACAR rotational node r, at the position of node t; \"@r\" = rotational node r used by hinges only.".into());
    if mapped {
        h.push("Partition: FIX -> [fix]; INPUTX, DYNX -> [inputs]; RLSE -> free; INPUTE -> input; DYNE -> not listed where the mode has stiffness (a row of the kinematic check, like an input; flexible in statics), input otherwise; deformations SPACAR keeps rigid (not listed) that have stiffness -> `fixed` (beams) or no EA/k (trusses, hinges).".into());
    } else {
        h.push(
            "Partition: FIX -> [fix]; INPUTX, DYNX -> [inputs]; RLSE -> free; DYNE, INPUTE -> input."
                .into(),
        );
    }
    h.push(format!(
        "SPACAR analysis: {}.",
        m.analysis_hint().describe()
    ));
    if simulated {
        h.push("Time simulation: TIMESTEP, ERROR -> [simulate]; XM inertia tensors -> [[inertia]]; XF constant, DELXF, INPUTX, DELINPX, INPUTE, DELINPE as functions of time -> `history` of [[load]] and [[prescribe]] (a stroke's history scaled to its static value), as `flexmbd simulate` on the .dat file maps them (docs/spacar-import.md §7).".into());
    }
    let name = |n: u32| {
        map.name(m, n)
            .map_or_else(|| format!("{n}"), |s| format!("{n} (\"{s}\")"))
    };
    let mut later = Vec::new();
    for (kw, v) in [
        ("ITERSTEP", &m.iterstep),
        ("TIMESTEP", &m.timestep),
        ("ERROR", &m.error_tol),
        ("GRAVITY", &m.gravity),
        ("OUTLEVEL", &m.outlevel),
    ] {
        if mapped && (kw == "ITERSTEP" || kw == "GRAVITY") {
            continue; // at [static]
        }
        if simulated && (kw == "TIMESTEP" || kw == "ERROR") {
            continue; // at [simulate]
        }
        if let Some(v) = v {
            later.push((
                v.line,
                format!("{kw} {} (line {})", fmt_values(&v.values), v.line),
            ));
        }
    }
    for (kw, list) in [("XF", &m.xf), ("DELXF", &m.delxf), ("XM", &m.xm)] {
        for v in list {
            let inertia = kw == "XM" && m.node_kinds.get(&v.node) == Some(&NodeKind::Rotational);
            if mapped && (!inertia || simulated) {
                continue; // at [[load]], [[mass]] and [[inertia]]
            }
            let what = match (kw, m.node_kinds.get(&v.node)) {
                ("XM", Some(NodeKind::Rotational)) => "inertia Ixx Ixy Ixz Iyy Iyz Izz",
                ("XM", _) => "mass",
                (_, Some(NodeKind::Rotational)) if v.values.len() == 4 => {
                    "generalised forces on λ0..λ3 (pre-2017)"
                }
                (_, Some(NodeKind::Rotational)) => "moment",
                _ => "force",
            };
            later.push((
                v.line,
                format!(
                    "{kw} {}: {what} {} (line {})",
                    name(v.node),
                    fmt_values(&v.values),
                    v.line
                ),
            ));
        }
    }
    for (kw, list) in [("INPUTX", &m.inputx_values), ("DELINPX", &m.delinpx)] {
        for v in list.iter().filter(|_| !mapped) {
            later.push((
                v.line,
                format!(
                    "{kw} {} coordinate {} = {} (line {})",
                    name(v.node),
                    v.coord,
                    fmt_num(v.value),
                    v.line
                ),
            ));
        }
    }
    for (kw, list) in [("INPUTE", &m.inpute_values), ("DELINPE", &m.delinpe)] {
        for v in list.iter().filter(|_| !mapped) {
            later.push((
                v.line,
                format!(
                    "{kw} element {} mode {} = {} (line {})",
                    v.element,
                    v.mode,
                    fmt_num(v.value),
                    v.line
                ),
            ));
        }
    }
    for v in &m.edamp {
        later.push((
            v.line,
            format!(
                "EDAMP {}: element damping {} (line {})",
                v.element,
                fmt_values(&v.values),
                v.line
            ),
        ));
    }
    for (kw, list) in [("STARTDE", &m.startde), ("STARTDX", &m.startdx)] {
        for v in list {
            later.push((
                v.line,
                format!(
                    "{kw} {} {}: initial value {} and rate {} (line {})",
                    v.number,
                    v.index,
                    fmt_num(v.value),
                    fmt_num(v.rate),
                    v.line
                ),
            ));
        }
    }
    for u in &m.user_routines {
        later.push((
            u.line,
            format!(
                "{} {} (user MATLAB routine, not supported; line {})",
                u.keyword, u.name, u.line
            ),
        ));
    }
    for s in &m.state_space {
        let kw = match s.kind {
            IoKind::Force => "INPUTF",
            IoKind::Displacement => "OUTX",
            IoKind::Velocity => "OUTXP",
        };
        later.push((
            s.line,
            format!(
                "{kw} {} node {} direction {} (line {})",
                s.index,
                name(s.node),
                s.dir,
                s.line
            ),
        ));
    }
    if !later.is_empty() {
        h.push(if mapped {
            "SPACAR data this format cannot express (inertia tensors matter for dynamics only):"
        } else {
            "SPACAR data this format cannot express yet (stiffness and masses: above each element):"
        }
        .into());
        later.sort_by_key(|l| l.0);
        h.extend(later.into_iter().map(|l| format!("  {}", l.1)));
    }
    if let Some(notes) = statics.filter(|n| !n.is_empty()) {
        h.push("Notes of the conversion (printed as warnings by `flexmbd static` on the .dat file, except those about this format):".into());
        h.extend(
            notes
                .iter()
                .map(|w| format!("  line {}: {}", w.line, w.message)),
        );
    }
    let mut tail = String::new();
    if !m.visualization.is_empty() {
        let _ = write!(
            tail,
            "{} visualisation line(s) not converted. ",
            m.visualization.len()
        );
    }
    if !m.ignored.is_empty() {
        let _ = write!(
            tail,
            "{} line(s) with unknown keywords ignored. ",
            m.ignored.len()
        );
    }
    if !tail.is_empty() {
        h.push(tail.trim_end().to_string());
    }
    h
}
