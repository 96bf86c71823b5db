//! The geometry of the page: nodes, elements with their displayed sections, and the frames of
//! the node states (positions and rotations) of a load step.

use super::document::*;
use flexmbd_core::elements::{Element, ElementKind};
use flexmbd_core::model::{CoordKind, DefKind, Dof, Model, Partition};
use flexmbd_core::statics::StepResult;

/// Smallest displayed thickness of a sheet, as a fraction of the model size: a 0.2 mm sheet in
/// a 300 mm guide would be invisible at its real thickness.
pub const MIN_THICKNESS: f64 = 0.004;
/// Smallest displayed diameter of a wire or beam, as a fraction of the model size.
pub const MIN_DIAMETER: f64 = 0.008;
/// Width of a sheet whose section is not given (only its partition or stiffness says it is a
/// sheet), as a fraction of the model size.
pub const NOMINAL_SHEET_WIDTH: f64 = 0.1;

pub(super) fn view_nodes(model: &Model, p: &Partition) -> Vec<ViewNode> {
    model
        .nodes
        .iter()
        .map(|n| {
            let mut fixed = Vec::new();
            let mut input = Vec::new();
            for d in Dof::ALL {
                // a hosted node's translations are its host's
                if n.host.is_some() && !d.is_rotation() {
                    continue;
                }
                if let Some(i) = n.x_index(d) {
                    match p.x[i] {
                        CoordKind::Fixed => fixed.push(d.name().to_string()),
                        CoordKind::Input => input.push(d.name().to_string()),
                        CoordKind::Free => {}
                    }
                }
            }
            ViewNode {
                name: n.name.clone(),
                host: n.host,
                rot: n.rot(),
                fixed,
                input,
            }
        })
        .collect()
}

pub(super) fn mode_names(model: &Model) -> Vec<(String, Vec<String>)> {
    let names = model.node_names();
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for e in &model.elements {
        let t = e.element.type_name();
        if t == "rigid" || out.iter().any(|(k, _)| k == t) {
            continue;
        }
        out.push((
            t.to_string(),
            (0..e.element.ne())
                .map(|m| e.element.mode_name(m, &names))
                .collect(),
        ));
    }
    out
}

pub(super) fn view_element(model: &Model, p: &Partition, k: usize, size: f64) -> ViewElement {
    let entry = &model.elements[k];
    let ne = entry.element.ne();
    let partition: String = (0..ne)
        .map(|m| match p.e[entry.ie + m] {
            DefKind::Fixed => 'r',
            DefKind::Free => 'f',
            DefKind::Input => 'i',
        })
        .collect();
    let (kind, nodes, frame, section) = match &entry.element {
        Element::Truss(t) => (ViewKind::Truss, t.nodes.to_vec(), None, None),
        Element::Beam(b) => (
            ViewKind::Beam,
            b.nodes.to_vec(),
            Some(b.frame),
            Some(beam_section(b, &partition, size)),
        ),
        Element::Hinge(h) => (ViewKind::Hinge, h.nodes.to_vec(), Some(h.frame), None),
        Element::Rigid(r) => (ViewKind::Rigid, r.nodes.clone(), None, None),
    };
    ViewElement {
        name: entry.name.clone(),
        kind,
        nodes,
        frame,
        section,
        partition,
    }
}

/// The drawn section of a beam: from its section data when the model gives one (rectangle,
/// circle or tube recognised from the area and the fibre distances), else inferred from the
/// ratio of its bending stiffnesses or from its partition (in-plane bending rigid and
/// out-of-plane bending free: a sheet). Dimensions below [`MIN_THICKNESS`] / [`MIN_DIAMETER`]
/// of the model size are drawn at that minimum.
pub fn beam_section(b: &flexmbd_core::elements::Beam, partition: &str, size: f64) -> ViewSection {
    use std::f64::consts::PI;
    let min_t = MIN_THICKNESS * size;
    let min_d = MIN_DIAMETER * size;
    let rect = |w: f64, t: f64, actual: Option<[f64; 2]>, source: &str| ViewSection {
        shape: SectionShape::Rectangle,
        width: w.max(min_t),
        thickness: t.max(min_t),
        actual,
        source: source.into(),
    };
    let round = |d: f64, inner: Option<f64>, actual: Option<[f64; 2]>, source: &str| ViewSection {
        shape: if inner.is_some() {
            SectionShape::Tube
        } else {
            SectionShape::Round
        },
        width: d.max(min_d),
        thickness: d.max(min_d),
        actual,
        source: source.into(),
    };
    if let Some(p) = b
        .props
        .as_deref()
        .filter(|p| p.area > 0.0 && p.fibre.iter().all(|f| *f > 0.0))
    {
        let (cz, cy) = (p.fibre[0], p.fibre[1]);
        let a = p.area;
        if (a - 4.0 * cz * cy).abs() <= 1e-6 * a {
            return rect(2.0 * cy, 2.0 * cz, Some([2.0 * cy, 2.0 * cz]), "section");
        }
        if (cz - cy).abs() <= 1e-9 * cz.max(cy) {
            let d = 2.0 * cz;
            let solid = PI * cz * cz;
            if (a - solid).abs() <= 1e-6 * a {
                return round(d, None, Some([d, 0.0]), "section");
            }
            if a < solid {
                let d_in = (d * d - 4.0 * a / PI).max(0.0).sqrt();
                return round(d, Some(d_in), Some([d, d_in]), "section");
            }
        }
        // another shape: its bounding rectangle
        return rect(2.0 * cy, 2.0 * cz, Some([2.0 * cy, 2.0 * cz]), "section");
    }
    let sheet_w = NOMINAL_SHEET_WIDTH * size;
    let [_, _, eiy, eiz] = b.stiffness;
    if eiy > 0.0 && eiz > 0.0 {
        // a rectangle has EIz/EIy = (w/t)²
        let ratio = eiz / eiy;
        if ratio > 4.0 {
            return rect(sheet_w, sheet_w / ratio.sqrt(), None, "stiffness");
        }
        if ratio < 0.25 {
            return rect(sheet_w * ratio.sqrt(), sheet_w, None, "stiffness");
        }
        return round(min_d, None, None, "stiffness");
    }
    let m: Vec<char> = partition.chars().collect();
    if m.len() == 6 {
        let rigid = |i: usize| m[i] == 'r';
        // ε3, ε4 bend about local y (deflection along z), ε5, ε6 about local z
        if rigid(4) && rigid(5) && !(rigid(2) && rigid(3)) {
            return rect(sheet_w, min_t, None, "partition");
        }
        if rigid(2) && rigid(3) && !(rigid(4) && rigid(5)) {
            return rect(min_t, sheet_w, None, "partition");
        }
    }
    round(min_d, None, None, "partition")
}

pub(super) fn frame(model: &Model, label: &str, load_factor: Option<f64>, x: &[f64]) -> ViewFrame {
    let mut pos = Vec::with_capacity(3 * model.nodes.len());
    let mut q = Vec::with_capacity(4 * model.nodes.len());
    for n in &model.nodes {
        pos.extend((0..3).map(|i| x[n.ix_pos + i] as f32));
        let l = match n.ix_rot {
            Some(r) => {
                let l = [x[r], x[r + 1], x[r + 2], x[r + 3]];
                let s = l.iter().map(|a| a * a).sum::<f64>().sqrt();
                if s > 0.0 && s.is_finite() {
                    l.map(|a| a / s)
                } else {
                    [1.0, 0.0, 0.0, 0.0]
                }
            }
            None => [1.0, 0.0, 0.0, 0.0],
        };
        q.extend(l.iter().map(|&a| a as f32));
    }
    ViewFrame {
        label: label.to_string(),
        load_factor,
        x: pos,
        q,
    }
}

pub(super) fn max_displacement(model: &Model, st: &StepResult) -> f64 {
    model
        .nodes
        .iter()
        .map(|n| {
            (0..3)
                .map(|i| (st.x[n.ix_pos + i] - n.x0[i]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}
