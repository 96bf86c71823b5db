//! Checks that need the whole file: node kinds, references, mode and coordinate numbers,
//! conflicting partitions, value counts of the static data.

use super::*;
use crate::error::{at_line, InputError};
use rustc_hash::FxHashMap as HashMap;
use std::collections::BTreeMap;

/// Where each node number was first used by an element (kind, element number, line).
type Uses = BTreeMap<u32, (NodeKind, u32, usize)>;

pub(super) fn validate(m: &mut SpacarModel) -> Result<(), InputError> {
    let file = m.file.clone();
    let err = |line: usize, msg: String| at_line(&file, line, 1, msg);
    let mut warnings = Vec::new();

    // elements: unique numbers, node kinds from the slots
    let mut element_line: HashMap<u32, usize> = HashMap::default();
    let mut uses: Uses = BTreeMap::new();
    for e in &m.elements {
        let item = ItemName(e.kind.keyword(), e.number);
        if let Some(first) = element_line.insert(e.number, e.line) {
            return Err(err(
                e.line,
                format!(
                    "{item}: element {} is already defined on line {first}",
                    e.number
                ),
            ));
        }
        let slots = e.kind.node_slots();
        for (i, &(n, kind)) in slots.iter().enumerate() {
            if slots[..i].iter().any(|&(o, _)| o == n) {
                return Err(err(
                    e.line,
                    format!("{item}: node {n} appears twice in the element"),
                ));
            }
            match uses.get(&n) {
                Some(&(k, other, line)) if k != kind => {
                    return Err(err(
                        e.line,
                        format!(
                            "{item}: node {n} is used as a {} node here, but as a {} node by element {other} on line {line} (a SPACAR node number is either translational, rotational or warping)",
                            kind.name(),
                            k.name()
                        ),
                    ));
                }
                Some(_) => {}
                None => {
                    uses.insert(n, (kind, e.number, e.line));
                }
            }
        }
    }
    m.node_kinds = uses.iter().map(|(&n, &(k, _, _))| (n, k)).collect();
    let kinds = m.node_kinds.clone();

    // X lines
    let mut x_line: HashMap<u32, usize> = HashMap::default();
    for p in &m.positions {
        let item = ItemName("X", p.node);
        if let Some(first) = x_line.insert(p.node, p.line) {
            return Err(err(
                p.line,
                format!(
                    "{item}: node {} already has an X line (line {first})",
                    p.node
                ),
            ));
        }
        match kinds.get(&p.node) {
            None => warnings.push(Warning {
                line: p.line,
                message: format!("{item}: node {} is not used by any element; ignored", p.node),
            }),
            Some(NodeKind::Translational) if p.values.len() == 3 => {}
            Some(NodeKind::Rotational)
                if p.values.len() == 4
                    && p.values[0] > 0.0
                    && p.values[1..].iter().all(|v| *v == 0.0) => {}
            Some(NodeKind::Rotational) => {
                return Err(err(
                    p.line,
                    format!(
                        "{item}: node {} is a rotational node; only the reference orientation (Euler parameters 1 0 0 0) is supported as its initial value",
                        p.node
                    ),
                ))
            }
            Some(k) => {
                return Err(err(
                    p.line,
                    format!(
                        "{item}: node {} is a {} node and takes {} values, found {}",
                        p.node,
                        k.name(),
                        k.n_coords(),
                        p.values.len()
                    ),
                ))
            }
        }
    }
    for (&n, &(k, el, line)) in &uses {
        if k == NodeKind::Translational && !x_line.contains_key(&n) {
            return Err(err(
                line,
                format!("element {el}: translational node {n} has no X line (no position)"),
            ));
        }
    }

    // deformation partition
    // the first element of each number (a repeated number is reported above)
    let mut by_number: HashMap<u32, &Element> =
        HashMap::with_capacity_and_hasher(m.elements.len(), Default::default());
    for e in &m.elements {
        by_number.entry(e.number).or_insert(e);
    }
    let element = |n: u32| by_number.get(&n).copied();
    let mut mode_kind: HashMap<(u32, u32), (&str, usize)> = HashMap::default();
    for (kw, lists) in [("RLSE", &m.rlse), ("DYNE", &m.dyne), ("INPUTE", &m.inpute)] {
        for l in lists {
            let item = ItemName(kw, l.element);
            let Some(e) = element(l.element) else {
                return Err(err(
                    l.line,
                    format!("{item}: element {} is not defined", l.element),
                ));
            };
            for &mode in &l.modes {
                if mode > e.kind.n_modes() {
                    return Err(err(
                        l.line,
                        format!(
                            "{item}: deformation mode {mode} does not exist (a {} has modes 1 to {})",
                            e.kind.keyword(),
                            e.kind.n_modes()
                        ),
                    ));
                }
                match mode_kind.get(&(l.element, mode)) {
                    Some(&(other, line)) if other != kw => {
                        return Err(err(
                            l.line,
                            format!("{item}: deformation mode {mode} is already {other} (line {line})"),
                        ))
                    }
                    Some(&(_, line)) => warnings.push(Warning {
                        line: l.line,
                        message: format!("{item}: deformation mode {mode} is listed again (first on line {line})"),
                    }),
                    None => {
                        mode_kind.insert((l.element, mode), (kw, l.line));
                    }
                }
            }
        }
    }

    // coordinate partition
    let mut coord_kind: HashMap<(u32, u32), (&str, usize)> = HashMap::default();
    let mut unused_nodes = Vec::new();
    for (kw, lists) in [("FIX", &m.fix), ("INPUTX", &m.inputx), ("DYNX", &m.dynx)] {
        for l in lists {
            let item = ItemName(kw, l.node);
            let Some(&kind) = kinds.get(&l.node) else {
                if x_line.contains_key(&l.node) {
                    warnings.push(Warning {
                        line: l.line,
                        message: format!(
                            "{item}: node {} is not used by any element; ignored",
                            l.node
                        ),
                    });
                    unused_nodes.push(l.line);
                    continue;
                }
                return Err(err(
                    l.line,
                    format!("{item}: node {} is not used by any element", l.node),
                ));
            };
            let all: Vec<u32> = match kind {
                NodeKind::Translational => vec![1, 2, 3],
                NodeKind::Rotational => vec![2, 3, 4],
                NodeKind::Warping => vec![1],
            };
            let coords = l.coords.clone().unwrap_or(all);
            for c in coords {
                if c > kind.n_coords() {
                    return Err(err(
                        l.line,
                        format!(
                            "{item}: node {} is a {} node with coordinates 1 to {}, found {c}",
                            l.node,
                            kind.name(),
                            kind.n_coords()
                        ),
                    ));
                }
                if kind == NodeKind::Rotational && c == 1 {
                    return Err(err(
                        l.line,
                        format!(
                            "{item}: coordinate 1 of rotational node {} is λ0, which flexmbd always keeps dependent (normalisation λᵀλ = 1); use coordinates 2–4 (λ1..λ3)",
                            l.node
                        ),
                    ));
                }
                match coord_kind.get(&(l.node, c)) {
                    Some(&(other, line)) if other != kw => {
                        return Err(err(
                            l.line,
                            format!(
                            "{item}: coordinate {c} of node {} is already {other} (line {line})",
                            l.node
                        ),
                        ))
                    }
                    Some(_) => {}
                    None => {
                        coord_kind.insert((l.node, c), (kw, l.line));
                    }
                }
            }
        }
    }

    // static / dynamic data
    let node_kind = |n: u32, line: usize, item: &ItemName| -> Result<NodeKind, InputError> {
        kinds
            .get(&n)
            .copied()
            .ok_or_else(|| err(line, format!("{item}: node {n} is not used by any element")))
    };
    let mut seen: HashMap<(&str, u32), usize> = HashMap::default();
    for (kw, list) in [
        ("ESTIFF", &m.estiff),
        ("EM", &m.em),
        ("ESIG", &m.esig),
        ("EDAMP", &m.edamp),
    ] {
        for v in list {
            let item = ItemName(kw, v.element);
            let Some(e) = element(v.element) else {
                return Err(err(
                    v.line,
                    format!("{item}: element {} is not defined", v.element),
                ));
            };
            let max = match kw {
                "ESTIFF" | "EDAMP" => e.kind.stiffness_columns().len(),
                "EM" => e.kind.mass_columns().len(),
                _ => e.kind.n_modes() as usize,
            };
            if v.values.len() > max {
                let cols = match kw {
                    "ESTIFF" | "EDAMP" => e.kind.stiffness_columns().join(" "),
                    "EM" => e.kind.mass_columns().join(" "),
                    _ => "one per deformation mode".into(),
                };
                return Err(err(
                    v.line,
                    format!(
                        "{item}: a {} takes at most {max} {kw} values ({cols}), found {}",
                        e.kind.keyword(),
                        v.values.len()
                    ),
                ));
            }
            if let Some(first) = seen.insert((kw, v.element), v.line) {
                warnings.push(Warning {
                    line: v.line,
                    message: format!("{item}: given again (first on line {first}); both are kept, the last one counts"),
                });
            }
        }
    }
    for v in &m.xm {
        let item = ItemName("XM", v.node);
        let ok = match node_kind(v.node, v.line, &item)? {
            NodeKind::Translational => v.values.len() == 1,
            NodeKind::Rotational => v.values.len() == 6,
            NodeKind::Warping => false,
        };
        if !ok {
            return Err(err(v.line, format!("{item}: expected a mass (1 value) on a translational node or an inertia tensor Ixx Ixy Ixz Iyy Iyz Izz (6 values) on a rotational node, found {} values on a {} node", v.values.len(), kinds[&v.node].name())));
        }
    }
    for (kw, list) in [("XF", &m.xf), ("DELXF", &m.delxf)] {
        for v in list {
            let item = ItemName(kw, v.node);
            match (node_kind(v.node, v.line, &item)?, v.values.len()) {
                (NodeKind::Translational | NodeKind::Rotational, 3) => {}
                (NodeKind::Rotational, 4) => warnings.push(Warning {
                    line: v.line,
                    message: format!("{item}: four values on a rotational node are the pre-2017 convention (generalised forces on λ0..λ3, i.e. 0 2Mx 2My 2Mz); converted to the moment (Mx, My, Mz) = (f1, f2, f3)/2, exact at the reference orientation (SPACAR before 2017 kept the generalised forces constant, which differs from a constant moment at large rotations)"),
                }),
                (k, n) => {
                    return Err(err(
                        v.line,
                        format!(
                            "{item}: expected 3 values ({}), found {n}",
                            if k == NodeKind::Rotational {
                                "moment Mx My Mz"
                            } else {
                                "force Fx Fy Fz on a translational node, or a moment on a rotational node"
                            }
                        ),
                    ))
                }
            }
        }
    }
    let is_input_coord = |n: u32, c: u32| matches!(coord_kind.get(&(n, c)), Some(&(k, _)) if k == "INPUTX" || k == "DYNX");
    for (kw, list) in [("INPUTX", &m.inputx_values), ("DELINPX", &m.delinpx)] {
        for v in list {
            let item = ItemName(kw, v.node);
            node_kind(v.node, v.line, &item)?;
            if !is_input_coord(v.node, v.coord) {
                return Err(err(
                    v.line,
                    format!(
                        "{item}: coordinate {} of node {} is not an input (no INPUTX or DYNX {} {} in the kinematic section)",
                        v.coord, v.node, v.node, v.coord
                    ),
                ));
            }
        }
    }
    for (kw, list) in [("INPUTE", &m.inpute_values), ("DELINPE", &m.delinpe)] {
        for v in list {
            let item = ItemName(kw, v.element);
            let is_input = matches!(mode_kind.get(&(v.element, v.mode)), Some(&(k, _)) if k == "INPUTE" || k == "DYNE");
            if !is_input {
                return Err(err(
                    v.line,
                    format!(
                        "{item}: deformation mode {} of element {} is not an input (no INPUTE or DYNE in the kinematic section)",
                        v.mode, v.element
                    ),
                ));
            }
        }
    }
    // initial conditions: only of dynamic degrees of freedom
    for v in &m.startde {
        let item = format!("STARTDE {}", v.number);
        if element(v.number).is_none() {
            return Err(err(
                v.line,
                format!("{item}: element {} is not defined", v.number),
            ));
        }
        if !matches!(mode_kind.get(&(v.number, v.index)), Some(&(k, _)) if k == "DYNE") {
            return Err(err(
                v.line,
                format!(
                    "{item}: deformation mode {} of element {} is not a dynamic degree of freedom (no DYNE {} {} in the kinematic section)",
                    v.index, v.number, v.number, v.index
                ),
            ));
        }
    }
    for v in &m.startdx {
        let item = ItemName("STARTDX", v.number);
        node_kind(v.number, v.line, &item)?;
        if !matches!(coord_kind.get(&(v.number, v.index)), Some(&(k, _)) if k == "DYNX") {
            return Err(err(
                v.line,
                format!(
                    "{item}: coordinate {} of node {} is not a dynamic degree of freedom (no DYNX {} {} in the kinematic section)",
                    v.index, v.number, v.number, v.index
                ),
            ));
        }
    }
    for s in &m.state_space {
        let item = ItemName("state-space line", s.index);
        let k = node_kind(s.node, s.line, &item)?;
        if s.dir > k.n_coords() {
            return Err(err(
                s.line,
                format!(
                    "{item}: direction {} does not exist for {} node {}",
                    s.dir,
                    k.name(),
                    s.node
                ),
            ));
        }
    }
    // BEAMW: warping is not modelled
    let beamw: Vec<&Element> = m
        .elements
        .iter()
        .filter(|e| matches!(e.kind, ElementKind::BeamW { .. }))
        .collect();
    if let Some(first) = beamw.first() {
        warnings.push(Warning {
            line: first.line,
            message: format!("{} BEAMW element(s), the first here, are read as BEAMs: warping (the warping nodes, their FIX, INPUTX and DYNX lines, deformations 7-8) is not modelled; it changes stiffness, not the kinematic check (SPACAR keeps deformations 7-8 calculable)", beamw.len()),
        });
    }
    for l in m.rlse.iter().chain(&m.dyne).chain(&m.inpute) {
        if l.modes.iter().any(|&k| k > 6)
            && matches!(
                element(l.element).map(|e| &e.kind),
                Some(ElementKind::BeamW { .. })
            )
        {
            warnings.push(Warning {
                line: l.line,
                message: format!(
                    "element {}: warping deformations 7-8 are ignored",
                    l.element
                ),
            });
        }
    }
    // mapping problems that are not errors (errors are reported by to_model)
    if let Ok(map) = super::mapping::NodeMap::new(m) {
        warnings.extend(map.warnings);
    }
    // drop the entries of unused nodes (already warned)
    for lists in [&mut m.fix, &mut m.inputx, &mut m.dynx] {
        lists.retain(|l| !unused_nodes.contains(&l.line));
    }
    m.warnings.extend(warnings);
    Ok(())
}

/// An item of the file as messages name it (`BEAM 3`, `X 7`): written only when a message is.
#[derive(Clone, Copy)]
struct ItemName<'a>(&'a str, u32);

impl std::fmt::Display for ItemName<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.0, self.1)
    }
}
