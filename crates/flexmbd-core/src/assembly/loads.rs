//! The loads of acceleration fields on the model's mass: gravity and the centrifugal field of a
//! steady rotation ([`crate::model::Spin`]), as nodal forces and moments.
//!
//! One mass model serves the mass matrix and these loads: each element's loads come from
//! [`ElementKind::field_loads`], consistent with its [`ElementKind::mass`] (the beam: the
//! Hermite centre line, `elements/beam/mass.rs`); a point mass m gets m a(r), an inertia tensor
//! the gyroscopic moment −Ω × (I Ω). The loads are computed on the reference configuration and
//! applied as dead loads growing with the load factor (statics).

use crate::assembly::{gather_local, SMALL};
use crate::elements::{ElementKind, NodeId};
use crate::model::Model;

/// The nodal loads of gravity and of the model's spin on the reference configuration: per node
/// (force, moment) in global axes [N, N·m]; all zero without gravity and spin.
pub fn field_loads(model: &Model) -> Vec<([f64; 3], [f64; 3])> {
    field_loads_at(model, &model.x0())
}

/// The nodal loads of gravity and of the model's spin at the coordinates `x` (the loads follow
/// the configuration: time simulation); [`field_loads`] is this on the reference configuration.
pub fn field_loads_at(model: &Model, x: &[f64]) -> Vec<([f64; 3], [f64; 3])> {
    field_loads_with(model, x, &element_nodes(model))
}

/// The nodes of every element, in the order of its [`ElementKind::node_uses`]: made once for
/// [`field_loads_with`] at many states.
pub fn element_nodes(model: &Model) -> Vec<Vec<NodeId>> {
    model
        .elements
        .iter()
        .map(|entry| entry.element.node_uses().iter().map(|u| u.node).collect())
        .collect()
}

/// [`field_loads_at`] with the elements' nodes `nodes` of [`element_nodes`].
pub fn field_loads_with(
    model: &Model,
    x: &[f64],
    nodes: &[Vec<NodeId>],
) -> Vec<([f64; 3], [f64; 3])> {
    let mut out = vec![([0.0; 3], [0.0; 3]); model.nodes.len()];
    let Some(field) = model.loads.acceleration_field() else {
        return out;
    };
    let add = |v: &mut [f64; 3], a: [f64; 3]| {
        for k in 0..3 {
            v[k] += a[k];
        }
    };
    let mut per_use = Vec::new();
    let (mut xs, mut xh) = ([0.0; SMALL], Vec::new());
    for (entry, nodes) in model.elements.iter().zip(nodes) {
        per_use.clear();
        per_use.resize(nodes.len(), ([0.0; 3], [0.0; 3]));
        let xk = gather_local(entry, x, &mut xs, &mut xh);
        entry.element.field_loads(xk, &field, &mut per_use);
        for (&node, (f, m)) in nodes.iter().zip(&per_use) {
            add(&mut out[node].0, *f);
            add(&mut out[node].1, *m);
        }
    }
    for &(node, m) in &model.loads.point_masses {
        let ip = model.nodes[node].ix_pos;
        let a = field.at([x[ip], x[ip + 1], x[ip + 2]]);
        add(&mut out[node].0, a.map(|v| m * v));
    }
    for (node, tensor) in &model.loads.inertias {
        add(&mut out[*node].1, field.gyroscopic_moment(tensor));
    }
    out
}
