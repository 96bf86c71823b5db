//! Presentation of null vectors: motions as nodal velocities, self-stress states as stress
//! resultants per element deformation, each of unit length with its largest entry positive
//! (theory.md §6.6).

use super::{Column, DeformationValue, Motion, NodalVelocity, Row, SelfStress};
use crate::elements::{ElementKind, NodeId};
use crate::model::{Dof, Model};

/// Entries below this fraction of a unit vector are shown as zero (rounding noise of the SVD).
pub const PRESENT_ZERO: f64 = 1e-10;

/// Normalise to unit length with the largest-magnitude entry positive; zero tiny entries.
pub fn normalize_signed(v: &mut [f64]) {
    let n = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    if n == 0.0 {
        return;
    }
    let imax = (0..v.len()).fold(0, |b, i| {
        if v[i].abs() > v[b].abs() + 1e-12 {
            i
        } else {
            b
        }
    });
    let s = if v[imax] < 0.0 { -1.0 / n } else { 1.0 / n };
    for a in v.iter_mut() {
        *a *= s;
        if a.abs() < PRESENT_ZERO {
            *a = 0.0;
        }
    }
}

/// A velocity vector over the columns as nodal velocities (translations, global ω).
pub fn present_motion(model: &Model, cols: &[Column], v: &[f64]) -> Motion {
    // accumulate per (node, component): rotations as ω = Σ v_c dir_c (in column order)
    let mut acc: std::collections::BTreeMap<(NodeId, Dof), f64> = Default::default();
    let mut add = |node: NodeId, dof: Dof, val: f64| {
        acc.entry((node, dof))
            .and_modify(|e| *e += val)
            .or_insert(val);
    };
    for (c, &val) in cols.iter().zip(v) {
        if c.dof.is_rotation() {
            for k in 0..3 {
                add(c.node, Dof::ALL[3 + k], val * c.dir[k]);
            }
        } else {
            add(c.node, c.dof, val);
        }
    }
    let entries: Vec<(NodeId, Dof, f64)> = acc.into_iter().map(|((n, d), v)| (n, d, v)).collect();
    let mut vals: Vec<f64> = entries.iter().map(|e| e.2).collect();
    normalize_signed(&mut vals);
    Motion {
        coordinates: entries
            .iter()
            .zip(vals)
            .filter(|(_, v)| *v != 0.0)
            .map(|(e, value)| NodalVelocity {
                node: model.nodes[e.0].name.clone(),
                dof: e.1,
                value,
            })
            .collect(),
    }
}

/// A vector over the rows as element stress resultants.
pub fn present_self_stress(model: &Model, names: &[String], rows: &[Row], u: &[f64]) -> SelfStress {
    let mut vals = u.to_vec();
    normalize_signed(&mut vals);
    SelfStress {
        deformations: rows
            .iter()
            .zip(vals)
            .filter(|(_, v)| *v != 0.0)
            .map(|(r, value)| {
                let entry = &model.elements[r.element];
                DeformationValue {
                    element: entry.name.clone(),
                    mode: r.mode + 1,
                    mode_name: entry.element.mode_name(r.mode, names),
                    value,
                }
            })
            .collect(),
    }
}
