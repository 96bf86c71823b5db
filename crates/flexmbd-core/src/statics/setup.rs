//! The problem data derived once from a model: unknowns, constraints, effective stiffnesses,
//! loads and targets at t = 1 ([`Setup`]).

use super::*;
use crate::math::blocks::DistinctBlocks;

/// An index that may be absent, in 4 bytes (`u32::MAX` for none; an `Option<usize>` takes 16):
/// the per-coordinate and per-deformation maps of the setup, which large models hold for the
/// whole analysis (0.3 KB per beam as options).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Slot(u32);

impl Slot {
    pub(crate) const NONE: Slot = Slot(u32::MAX);

    /// The index, if any.
    #[inline]
    pub(crate) fn get(self) -> Option<usize> {
        (self.0 != u32::MAX).then_some(self.0 as usize)
    }
}

impl From<Option<usize>> for Slot {
    fn from(o: Option<usize>) -> Self {
        match o {
            Some(i) => {
                assert!(i < u32::MAX as usize, "index {i} beyond 32 bits");
                Slot(i as u32)
            }
            None => Slot::NONE,
        }
    }
}

/// The options as slots.
pub(crate) fn slots(v: &[Option<usize>]) -> Vec<Slot> {
    v.iter().map(|&o| Slot::from(o)).collect()
}

/// The flexible part of each element's stiffness (other rows and columns zeroed), all in one
/// array, each distinct block once: element `el`'s ne × ne block, column-major, is block
/// `block[el]`, from `start[block[el]]` (a matrix of its own per element took 424 bytes for a
/// beam's 288 of values; the elements of a uniform leaf or wire share one block, 4 bytes each).
pub(crate) struct ElementStiffness {
    block: Vec<u32>,
    blocks: DistinctBlocks,
}

impl ElementStiffness {
    /// The blocks `blocks` (ne × ne each, column-major) of the elements in order, each distinct
    /// one (bit for bit) stored once.
    fn new(n_elements: usize, mut blocks: impl FnMut(usize, &mut Vec<f64>)) -> Self {
        let mut out = Self {
            block: Vec::with_capacity(n_elements),
            blocks: DistinctBlocks::default(),
        };
        let mut b = Vec::new();
        for el in 0..n_elements {
            b.clear();
            blocks(el, &mut b);
            out.block.push(out.blocks.add(&b));
        }
        out.blocks.finish();
        out
    }

    /// The block of element `el`.
    #[inline]
    pub(crate) fn get(&self, el: usize) -> faer::MatRef<'_, f64> {
        let v = self.blocks.get(self.block[el]);
        let ne = v.len().isqrt();
        faer::MatRef::from_column_major_slice(v, ne, ne)
    }
}

/// Problem data derived once from the model.
pub(crate) struct Setup {
    pub(crate) roles: Vec<Role>,
    /// x index → unknown index (free coordinates).
    pub(crate) unknown: Vec<Slot>,
    pub(crate) nf: usize,
    /// e index → constraint index.
    pub(crate) constraint: Vec<Slot>,
    pub(crate) nk: usize,
    /// Flexible part of each element's stiffness (other rows and columns zeroed).
    pub(crate) s_eff: ElementStiffness,
    /// Dead nodal forces in x (translations only), at t = 1, including gravity.
    pub(crate) f_dead: Vec<f64>,
    /// Moments at t = 1: (λ0 index, M).
    pub(crate) moments: Vec<(usize, [f64; 3])>,
    /// Prescribed values at t = 1: coordinate targets (index, reference, final).
    pub(crate) x_targets: Vec<(usize, f64)>,
    /// Deformation targets at t = 1.
    pub(crate) e_targets: Vec<f64>,
    /// λ0 index of every rotational node.
    pub(crate) lambda: Vec<usize>,
    /// Normalisation constraints: (λ0 index, constraint index) of nodes with a free λ.
    pub(crate) norm: Vec<(usize, usize)>,
    /// Model size (reference for displacement tolerances).
    pub(crate) l_ref: f64,
    /// Whether x index i is a rotation parameter.
    pub(crate) is_lambda: Vec<bool>,
    /// Order of the KKT entries written by the element assembly.
    pub(super) pattern: Pattern,
    /// The reduced Newton system (rotations of fully free nodes in tangent coordinates).
    pub(super) red: Reduction,
}

impl Setup {
    /// Releases what only the assembly reads (the element pattern of the unreduced system, the
    /// dead loads and targets, the positions of the translational diagonal entries), for a holder of assembled values that keeps the
    /// setup for its maps and the element stiffnesses (the sparse modal problem: 0.3 KB per
    /// beam). The setup can no longer assemble afterwards.
    pub(crate) fn release_assembly(&mut self) {
        self.pattern = Pattern::released(self.nf);
        self.f_dead = Vec::new();
        self.e_targets = Vec::new();
        self.x_targets = Vec::new();
        self.red.diag_trans = Vec::new();
    }
}

pub(crate) fn setup(model: &Model) -> Setup {
    let roles = roles(model);
    let mut unknown = vec![None; model.nx];
    let mut nf = 0;
    for i in 0..model.nx {
        if model.partition.x[i] == CoordKind::Free {
            unknown[i] = Some(nf);
            nf += 1;
        }
    }
    let mut constraint = vec![None; model.ne];
    let mut nk = 0;
    for i in 0..model.ne {
        if roles[i] != Role::Flexible {
            constraint[i] = Some(nk);
            nk += 1;
        }
    }
    let pattern = Pattern::new(model, &unknown, &constraint, nf);
    let s_eff = ElementStiffness::new(model.elements.len(), |el, out| {
        let entry = &model.elements[el];
        let s = entry.element.stiffness();
        let flex = |m: usize| roles[entry.ie + m] == Role::Flexible;
        let ne = s.nrows();
        debug_assert_eq!(s.ncols(), ne);
        for b in 0..ne {
            for a in 0..ne {
                let v = if flex(a) && flex(b) { s[(a, b)] } else { 0.0 };
                out.push(v);
            }
        }
    });
    // dead loads and gravity
    let mut f_dead = vec![0.0; model.nx];
    let mut moments = Vec::new();
    for l in &model.loads.nodal {
        let n = &model.nodes[l.node];
        for k in 0..3 {
            f_dead[n.ix_pos + k] += l.force[k];
        }
        if let Some(r) = n.ix_rot {
            if l.moment.iter().any(|m| *m != 0.0) {
                moments.push((r, l.moment));
            }
        }
    }
    // gravity and the centrifugal loads of a steady rotation, consistent with the mass model
    // (dead, on the reference configuration)
    if model.loads.acceleration_field().is_some() {
        for (node, (f, m)) in crate::assembly::loads::field_loads(model)
            .iter()
            .enumerate()
        {
            let n = &model.nodes[node];
            for k in 0..3 {
                f_dead[n.ix_pos + k] += f[k];
            }
            if let Some(r) = n.ix_rot {
                if m.iter().any(|v| *v != 0.0) {
                    moments.push((r, *m));
                }
            }
        }
    }
    // prescribed values
    let mut x_targets = Vec::new();
    let mut e_targets = vec![0.0; model.ne];
    for p in &model.loads.prescribed {
        match p.target {
            Target::Coordinate(i) => x_targets.push((i, p.value)),
            Target::Deformation(i) => e_targets[i] = p.value,
        }
    }
    let lambda: Vec<usize> = model.nodes.iter().filter_map(|n| n.ix_rot).collect();
    let mut norm = Vec::new();
    for &r in &lambda {
        if (r..r + 4).any(|i| unknown[i].is_some()) {
            norm.push((r, nk));
            nk += 1;
        }
    }
    let mut is_lambda = vec![false; model.nx];
    for &r in &lambda {
        is_lambda[r..r + 4].iter_mut().for_each(|v| *v = true);
    }
    // model size
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for n in &model.nodes {
        for k in 0..3 {
            lo[k] = lo[k].min(n.x0[k]);
            hi[k] = hi[k].max(n.x0[k]);
        }
    }
    let l_ref = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max).max(1e-12);
    let red = Reduction::new(model, &unknown, &constraint, nf, nk, &norm, &is_lambda);
    Setup {
        roles,
        unknown: slots(&unknown),
        nf,
        constraint: slots(&constraint),
        nk,
        s_eff,
        f_dead,
        moments,
        x_targets,
        e_targets,
        lambda,
        norm,
        l_ref,
        is_lambda,
        pattern,
        red,
    }
}
