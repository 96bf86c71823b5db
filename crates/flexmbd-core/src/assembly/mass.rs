//! The mass matrix M in x (theory.md §12), element by element through
//! [`ElementKind::mass`] (the beam's model: `elements/beam/mass.rs`), plus point masses m I₃ on a
//! node's position and inertia tensors (global axes, reference orientation, rotated with the
//! node) on its λ; and the centrifugal softening −Ω² M_P of a steady rotation from the same
//! entries.

use crate::assembly::{gather_local, per_element, SMALL};
use crate::elements::ElementKind;
use crate::math::inertia::{lambda_inertia_force, node_inertia_block};
use crate::model::{ElementEntry, Model};
use faer::Mat;

/// Every entry of the mass matrix at x, element by element, as `f(row, column, value)` in x
/// (repeated positions add up): the elements' mass matrices, point masses and inertia
/// tensors. With a `weight` W the translational kinetic energy is ½ ṙᵀ W ṙ (elements and point
/// masses), and `rotary = false` leaves the rotary inertias out (the centrifugal softening).
pub(crate) fn for_each_entry(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(usize, usize, f64),
) {
    for_each_element(model, x, weight, rotary, |entry, me| {
        let n = entry.xmap.len();
        for (r, gr) in entry.x_indices().enumerate() {
            for (c, gc) in entry.x_indices().enumerate() {
                f(gr, gc, me[r * n + c]);
            }
        }
    });
    for_each_node_entry(model, x, weight, rotary, f);
}

/// The elements' mass matrices ([`ElementKind::mass`], row-major) with their coordinates in x,
/// as `f(element, matrix)` (its `xmap` the rows and columns), in the order of the elements; elements without mass are skipped.
pub(crate) fn for_each_element(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(&ElementEntry, &[f64]),
) {
    // in chunks: each evaluated in parallel (large models), then handed to `f` in order, so
    // that the buffer stays small
    const CHUNK: usize = 4096;
    for chunk in model.elements.chunks(CHUNK) {
        let me = per_element(
            chunk,
            |entry| entry.xmap.len() * entry.xmap.len(),
            |entry, out| {
                let mut some = false;
                element_mass(entry, x, weight, rotary, |me| {
                    out.copy_from_slice(me);
                    some = true;
                });
                some
            },
        );
        for (entry, m) in me.each(chunk) {
            f(entry, m);
        }
    }
}

/// The mass matrix of one element at x ([`ElementKind::mass`], row-major on the element's
/// `xmap`), handed to `f` unless the element has no mass: the one evaluation of an element's
/// mass (or, with a `weight`, of its centrifugal softening) for every global form, dense in x
/// or sparse in the reduced unknowns (`linearized::sparse`).
pub(crate) fn element_mass(
    entry: &crate::model::ElementEntry,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    f: impl FnOnce(&[f64]),
) {
    let n = entry.xmap.len();
    // a beam's matrix on the stack, larger elements' on the heap
    let (mut xk_s, mut xk_h) = ([0.0; SMALL], Vec::new());
    let xk = gather_local(entry, x, &mut xk_s, &mut xk_h);
    let (mut me_s, mut me_h) = ([0.0; SMALL * SMALL], Vec::new());
    let me = if n <= SMALL {
        &mut me_s[..n * n]
    } else {
        me_h.resize(n * n, 0.0);
        &mut me_h[..]
    };
    if entry.element.mass(xk, weight, rotary, me) {
        f(me);
    }
}

/// The mass carried by a node, apart from the elements: a point mass on its position or an
/// inertia tensor on its Euler parameters ([`for_each_node_mass`]).
pub(crate) enum NodeMass {
    /// A point mass `mass` on the position at x index `ix` (3 coordinates).
    Point {
        /// x index of the node's position.
        ix: usize,
        /// The mass m.
        mass: f64,
    },
    /// The 4 × 4 block 4 Λ̄ᵀ I Λ̄ of an inertia tensor on the Euler parameters at x index `r`.
    Tensor {
        /// x index of λ0.
        r: usize,
        /// The block on λ.
        block: [[f64; 4]; 4],
    },
}

impl NodeMass {
    /// The entries (row, column, value) of a point mass's 3 × 3 block relative to its position:
    /// m I, or m W with a `weight` W (every entry, zeros included).
    pub(crate) fn point_entries(
        mass: f64,
        weight: Option<&[[f64; 3]; 3]>,
        mut f: impl FnMut(usize, usize, f64),
    ) {
        for r in 0..3 {
            match weight {
                Some(w) => (0..3).for_each(|c| f(r, c, mass * w[r][c])),
                None => f(r, r, mass),
            }
        }
    }
}

impl NodeMass {
    /// vᵀ M_node v of a vector v in x: m |v_r|² of a point mass, v_λᵀ (4 Λ̄ᵀ I Λ̄) v_λ of an
    /// inertia tensor (twice the kinetic energy of the node's mass at the velocity v).
    pub(crate) fn quadratic_form(&self, v: &[f64]) -> f64 {
        match self {
            NodeMass::Point { ix, mass } => {
                mass * v[*ix..*ix + 3].iter().map(|u| u * u).sum::<f64>()
            }
            NodeMass::Tensor { r, block } => (0..4)
                .map(|a| v[r + a] * (0..4).map(|c| block[a][c] * v[r + c]).sum::<f64>())
                .sum(),
        }
    }
}

/// The point masses, then (with `rotary`) the inertia tensors of the model at x, in model
/// order: the one source of the node masses for M, its products and the softening.
pub(crate) fn for_each_node_mass(
    model: &Model,
    x: &[f64],
    rotary: bool,
    mut f: impl FnMut(NodeMass),
) {
    for &(node, mass) in &model.loads.point_masses {
        f(NodeMass::Point {
            ix: model.nodes[node].ix_pos,
            mass,
        });
    }
    if !rotary {
        return;
    }
    for (node, tensor) in &model.loads.inertias {
        let Some(r) = model.nodes[*node].ix_rot else {
            continue;
        };
        f(NodeMass::Tensor {
            r,
            block: node_inertia_block(&x[r..r + 4], tensor),
        });
    }
}

/// The entries of point masses and inertia tensors (the part of [`for_each_entry`] after the
/// elements).
pub(crate) fn for_each_node_entry(
    model: &Model,
    x: &[f64],
    weight: Option<&[[f64; 3]; 3]>,
    rotary: bool,
    mut f: impl FnMut(usize, usize, f64),
) {
    for_each_node_mass(model, x, rotary, |nm| match nm {
        NodeMass::Point { ix, mass } => {
            NodeMass::point_entries(mass, weight, |r, c, v| f(ix + r, ix + c, v))
        }
        NodeMass::Tensor { r, block } => {
            for a in 0..4 {
                for c in 0..4 {
                    f(r + a, r + c, block[a][c]);
                }
            }
        }
    });
}

/// Dense mass matrix M (nx × nx) at x.
pub fn mass_matrix(model: &Model, x: &[f64]) -> Mat<f64> {
    let mut m = Mat::zeros(model.nx, model.nx);
    for_each_entry(model, x, None, true, |r, c, v| m[(r, c)] += v);
    m
}

/// M v for several vectors v in x at once, element by element (no global matrix): the
/// products that the energy split of the modes needs, also for models too large for a dense M.
pub fn mass_times(model: &Model, x: &[f64], vs: &[&[f64]]) -> Vec<Vec<f64>> {
    let mut out = vec![vec![0.0; model.nx]; vs.len()];
    // per vector the same additions in the same order as entry by entry
    for_each_element(model, x, None, true, |entry, me| {
        let n = entry.xmap.len();
        for (v, o) in vs.iter().zip(out.iter_mut()) {
            for (r, gr) in entry.x_indices().enumerate() {
                let mut acc = o[gr];
                for (c, gc) in entry.x_indices().enumerate() {
                    acc += me[r * n + c] * v[gc];
                }
                o[gr] = acc;
            }
        }
    });
    for_each_node_entry(model, x, None, true, |r, c, m| {
        for (v, o) in vs.iter().zip(out.iter_mut()) {
            o[r] += m * v[c];
        }
    });
    out
}

/// The inertia forces M(x) ẍ + h(x, ẋ) in x (nx), element by element
/// ([`ElementKind::inertia_forces`], without forming M), plus point masses m r̈ and the inertia
/// tensors at nodes (4 Λᵀ I Λ λ̈ + h): the inertia terms of the equations of motion.
pub fn inertia_forces(model: &Model, x: &[f64], v: &[f64], a: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; model.nx];
    // element by element (in parallel for large models), then added up in element order
    let fk = per_element(
        &model.elements,
        |entry| entry.xmap.len(),
        |entry, fk| {
            let mut stack = [[0.0; SMALL]; 3];
            let mut heap = [Vec::new(), Vec::new(), Vec::new()];
            let [s0, s1, s2] = &mut stack;
            let [h0, h1, h2] = &mut heap;
            entry.element.inertia_forces(
                gather_local(entry, x, s0, h0),
                gather_local(entry, v, s1, h1),
                gather_local(entry, a, s2, h2),
                fk,
            )
        },
    );
    for (entry, f) in fk.each(&model.elements) {
        for (i, fi) in entry.x_indices().zip(f) {
            out[i] += fi;
        }
    }
    for &(node, mass) in &model.loads.point_masses {
        let ip = model.nodes[node].ix_pos;
        for k in 0..3 {
            out[ip + k] += mass * a[ip + k];
        }
    }
    for (node, tensor) in &model.loads.inertias {
        let Some(r) = model.nodes[*node].ix_rot else {
            continue;
        };
        let f = lambda_inertia_force(&x[r..r + 4], &v[r..r + 4], &a[r..r + 4], tensor);
        for c in 0..4 {
            out[r + c] += f[c];
        }
    }
    out
}

/// The blocks of M on each node's own coordinates (7 × 7: position x, y, z, then λ0..λ3; a
/// node `at` a host has its host's position, so only its λ block is filled), element by
/// element: the inertia of every velocity direction of a node, without a global matrix.
pub fn node_blocks(model: &Model, x: &[f64]) -> Vec<[[f64; 7]; 7]> {
    // x index → (node, local index 0..7)
    let mut owner = vec![(usize::MAX, 0usize); model.nx];
    for (id, n) in model.nodes.iter().enumerate() {
        if n.host.is_none() {
            for k in 0..3 {
                owner[n.ix_pos + k] = (id, k);
            }
        }
        if let Some(r) = n.ix_rot {
            for k in 0..4 {
                owner[r + k] = (id, 3 + k);
            }
        }
    }
    let mut out = vec![[[0.0; 7]; 7]; model.nodes.len()];
    for_each_entry(model, x, None, true, |gr, gc, v| {
        let ((nr, lr), (nc, lc)) = (owner[gr], owner[gc]);
        if nr == nc && nr != usize::MAX {
            out[nr][lr][lc] += v;
        }
    });
    out
}

/// The centrifugal softening −Ω² M_P (nx × nx) at x: the second derivative of the centrifugal
/// potential −½ ∫ |P^½ Ω (r − a)|² dm of the translational mass (elements and point masses),
/// added to the stiffness of the linearised dynamics. Zero without a spin. The rotary inertias'
/// centrifugal moments are left out (their stiffness, the "propeller moment", matters for the
/// torsion of blades turning about their chord).
pub fn softening_matrix(model: &Model, x: &[f64]) -> Mat<f64> {
    let mut k = Mat::zeros(model.nx, model.nx);
    let Some(spin) = model.loads.spin else {
        return k;
    };
    let w = spin.projector();
    for_each_entry(model, x, Some(&w), false, |r, c, v| k[(r, c)] -= v);
    k
}
