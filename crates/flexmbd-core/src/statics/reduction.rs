//! The order of the KKT entries ([`Pattern`]) and the Newton system in reduced unknowns
//! ([`Reduction`]): rotation increments of fully free rotational nodes, singles eliminated.

use super::*;
use crate::math::lists::Lists;

/// Fixed order of the KKT matrix entries written by the assembly (the "triplets" without
/// values). It depends only on the model, so the sparse structure, the map to its value slots
/// and the symbolic factorisation are computed once per solve.
///
/// Order: per element (contiguous block, so that elements write in parallel) the tangent on its
/// free coordinates (row-major over the free local coordinates), then for each constrained mode
/// the pairs (G, Gᵀ) over the free local coordinates; after all elements the load stiffness of
/// the moments, then the Euler normalisations (diagonal, G, Gᵀ).
///
/// Only the linearisation (`assemble_part`) assembles in this order; Newton uses the reduced
/// order ([`Reduction`]). So the entry list is built on first use.
pub(super) struct Pattern {
    /// Rows, columns and element starts of the entries ([`Pattern::layout`]).
    pub(super) layout: std::sync::OnceLock<PatternLayout>,
    /// Free local coordinates of each element: (local index, unknown index).
    pub(super) elem_free: Lists<(u32, u32)>,
    /// Constraint index of each element's constrained modes, by element.
    pub(super) elem_constraints: Lists<u32>,
    /// Number of free coordinates (the constraint rows follow).
    pub(super) nf: usize,
    /// Start of each element's internal forces in the per-element force buffer.
    pub(super) f_start: Vec<usize>,
}

/// The entries of [`Pattern`].
pub(super) struct PatternLayout {
    pub(super) rows: Vec<usize>,
    pub(super) cols: Vec<usize>,
    /// Start of each element's block in `rows`/`cols` (elements + 1 entries).
    pub(super) elem_start: Vec<usize>,
}

impl Pattern {
    /// No entries: what [`crate::statics::ReducedLinear::release_assembly`] leaves.
    pub(super) fn released(nf: usize) -> Self {
        Self {
            layout: std::sync::OnceLock::new(),
            elem_free: Lists::with_capacity(0),
            elem_constraints: Lists::with_capacity(0),
            nf,
            f_start: Vec::new(),
        }
    }

    pub(super) fn new(
        model: &Model,
        unknown: &[Option<usize>],
        constraint: &[Option<usize>],
        nf: usize,
    ) -> Self {
        let mut elem_free = Lists::with_capacity(model.elements.len());
        let mut elem_constraints = Lists::with_capacity(model.elements.len());
        let mut f_start = Vec::with_capacity(model.elements.len() + 1);
        f_start.push(0);
        for entry in &model.elements {
            elem_free.push(
                entry
                    .x_indices()
                    .enumerate()
                    .filter_map(|(a, xa)| unknown[xa].map(|u| (a as u32, u as u32))),
            );
            elem_constraints.push(
                (0..entry.element.ne())
                    .filter_map(|m| constraint[entry.ie + m])
                    .map(|kc| kc as u32),
            );
            f_start.push(f_start.last().copied().unwrap_or(0) + entry.xmap.len());
        }
        elem_free.finish();
        elem_constraints.finish();
        Self {
            layout: std::sync::OnceLock::new(),
            elem_free,
            elem_constraints,
            nf,
            f_start,
        }
    }

    /// The entries (built on first use).
    pub(super) fn layout(&self) -> &PatternLayout {
        self.layout.get_or_init(|| {
            let nf = self.nf;
            let n_el = self.elem_free.len();
            let total: usize = (0..n_el)
                .map(|el| {
                    let (f, c) = (self.elem_free.of(el), self.elem_constraints.of(el));
                    element_entry_count(f.len(), c.len())
                })
                .sum();
            let (mut rows, mut cols) = (Vec::with_capacity(total), Vec::with_capacity(total));
            let mut elem_start = Vec::with_capacity(n_el + 1);
            for el in 0..n_el {
                let (free, cons) = (self.elem_free.of(el), self.elem_constraints.of(el));
                elem_start.push(rows.len());
                element_entries(
                    free,
                    cons.iter().map(|&kc| nf + kc as usize),
                    &mut |r, c| {
                        rows.push(r);
                        cols.push(c);
                    },
                );
            }
            elem_start.push(rows.len());
            PatternLayout {
                rows,
                cols,
                elem_start,
            }
        })
    }
}

/// A reduced local coordinate of an element: a column of the map T from reduced to original
/// local coordinates.
#[derive(Clone, Copy, Debug)]
pub(super) enum RCol {
    /// The local coordinate itself.
    Plain(u32),
    /// Rotation increment j of the node whose λ0 is local coordinate `a0`: Δλ = N(λ) δ.
    Rot { a0: u32, j: u8 },
}

/// A reduced column of an element ([`RCol`]) with its reduced unknown, in 8 bytes (the columns
/// of every element are held through a modal analysis: 12 per beam).
#[derive(Clone, Copy, Debug)]
pub(super) struct ElemCol {
    /// [`RCol::Plain`]: the local coordinate; [`RCol::Rot`]: the top bit, then λ0's local
    /// coordinate and j in the two lowest bits.
    col: u32,
    unknown: u32,
}

impl ElemCol {
    const ROT: u32 = 1 << 31;

    fn new(col: RCol, unknown: usize) -> Self {
        let col = match col {
            RCol::Plain(a) => {
                debug_assert!(a < Self::ROT);
                a
            }
            RCol::Rot { a0, j } => {
                debug_assert!(a0 < 1 << 29 && j < 4);
                Self::ROT | a0 << 2 | u32::from(j)
            }
        };
        let unknown = u32::try_from(unknown).expect("reduced unknowns under 2^32");
        Self { col, unknown }
    }

    pub(super) fn rcol(self) -> RCol {
        if self.col & Self::ROT == 0 {
            RCol::Plain(self.col)
        } else {
            RCol::Rot {
                a0: (self.col & !Self::ROT) >> 2,
                j: (self.col & 3) as u8,
            }
        }
    }

    pub(super) fn unknown(self) -> usize {
        self.unknown as usize
    }
}

/// A column of an element's block with the unknown it belongs to ([`element_entries`]).
pub(super) trait Unknown {
    fn unknown_of(&self) -> usize;
}

impl<T> Unknown for (T, usize) {
    fn unknown_of(&self) -> usize {
        self.1
    }
}

impl Unknown for (u32, u32) {
    fn unknown_of(&self) -> usize {
        self.1 as usize
    }
}

impl Unknown for ElemCol {
    fn unknown_of(&self) -> usize {
        self.unknown()
    }
}

/// The Newton system in reduced unknowns. A rotational node whose four Euler parameters are
/// all free is described by three increments δ with Δλ = N(λ) δ, N = Λ̄(λ)ᵀ/‖λ‖ (an
/// orthonormal basis of λ⊥, docs/rotations.md), instead of four parameters plus its
/// normalisation constraint and multiplier: the KKT matrix loses two rows and columns per node
/// and its zero diagonal there, and for a model without constraints and moments it is the
/// symmetric tangent stiffness itself (factored as L D Lᵀ). Since λᵀλ = 1 holds at every
/// iterate (`normalise_lambda`), the normalisation row gives Δλ ⟂ λ; the multiplier's term
/// 2μ I becomes 2μ I₃ and the multiplier's update follows from its row of the full system
/// (in `newton`): the direction is that of the full system. Nodes with a single free Euler
/// parameter are eliminated as well (`singles`).
pub(super) struct Reduction {
    /// Reduced index of every original unknown (free coordinates, then constraints); `None`
    /// for the Euler parameters and normalisations of reduced nodes.
    pub(super) map: Vec<Slot>,
    /// Reduced nodes: (λ0 x index, first of its three reduced indices, normalisation index).
    pub(super) nodes: Vec<(usize, usize, usize)>,
    /// Nodes with a single free Euler parameter (a clamped or rotation-driven node): it follows
    /// from the normalisation alone, so neither it nor the normalisation enters the Newton
    /// system; its multiplier solves its row of the equilibrium at every state
    /// (`solve_single_multipliers`). (λ0 x index, x index of that parameter, normalisation
    /// index).
    pub(super) singles: Vec<(usize, usize, usize)>,
    /// x index of λ0 → index into `nodes`.
    pub(super) node_at: Vec<Slot>,
    /// Reduced coordinate unknowns (the constraints follow).
    pub(super) nfr: usize,
    /// Size of the reduced system.
    pub(super) n: usize,
    /// Whether reduced coordinate unknown u is a translation.
    pub(super) is_trans: Vec<bool>,
    /// Reduced local coordinates of every element with their reduced unknown, element after
    /// element ([`Reduction::elem_cols`]).
    cols: Lists<ElemCol>,
    /// Beams with all 14 coordinates free, both nodes reduced and no constrained mode: their
    /// reduced entries come directly from `BeamFirst::hessian_tangent`.
    pub(super) beam_full: Vec<bool>,
    /// Reduced constraint row of each constrained mode of each element, element after element
    /// ([`Reduction::elem_cons`]; a list per element took 24 bytes for the none of a beam).
    cons: Lists<u32>,
    /// Number of KKT entries written by the element assembly ([`Reduction::for_each_entry`]).
    pub(super) n_entries: usize,
    /// The diagonal entries of translations among them.
    pub(super) diag_trans: Vec<usize>,
    /// Start of each element's entries (elements + 1).
    pub(super) elem_start: Vec<usize>,
}

impl Reduction {
    pub(super) fn new(
        model: &Model,
        unknown: &[Option<usize>],
        constraint: &[Option<usize>],
        nf: usize,
        nk: usize,
        norm: &[(usize, usize)],
        is_lambda: &[bool],
    ) -> Self {
        // candidates: all four λ free; every element uses them as one block λ0..λ3
        let mut node_ok = vec![false; model.nx];
        for &(r, _) in norm {
            node_ok[r] = (r..r + 4).all(|i| unknown[i].is_some());
        }
        let mut lambda0 = vec![usize::MAX; model.nx];
        for &(r, _) in norm {
            for i in r..r + 4 {
                lambda0[i] = r;
            }
        }
        for entry in &model.elements {
            let mut a = 0;
            while a < entry.xmap.len() {
                let xi = entry.x_index(a);
                let r = lambda0[xi];
                if r != usize::MAX && node_ok[r] {
                    let block = xi == r
                        && a + 4 <= entry.xmap.len()
                        && (0..4).all(|i| entry.x_index(a + i) == r + i);
                    if !block {
                        node_ok[r] = false;
                    } else {
                        a += 4;
                        continue;
                    }
                }
                a += 1;
            }
        }
        // single free parameter: determined by the normalisation
        let mut singles = Vec::new();
        for &(r, kc) in norm {
            let free: Vec<usize> = (r..r + 4).filter(|&i| unknown[i].is_some()).collect();
            if free.len() == 1 {
                singles.push((r, free[0], kc));
            }
        }
        // numbering: coordinates in x order (three per reduced node), then the constraints
        let mut map = vec![None; nf + nk];
        let single_x: std::collections::HashSet<usize> = singles.iter().map(|v| v.1).collect();
        let mut nodes = Vec::new();
        let mut node_at = vec![None; model.nx];
        let mut is_trans = Vec::new();
        let mut nfr = 0;
        let norm_of: std::collections::HashMap<usize, usize> = norm.iter().cloned().collect();
        let mut i = 0;
        while i < model.nx {
            if node_ok[i] && lambda0[i] == i {
                node_at[i] = Some(nodes.len());
                nodes.push((i, nfr, norm_of[&i]));
                nfr += 3;
                is_trans.extend([false; 3]);
                i += 4;
                continue;
            }
            if let (Some(u), false) = (unknown[i], single_x.contains(&i)) {
                map[u] = Some(nfr);
                is_trans.push(!is_lambda[i]);
                nfr += 1;
            }
            i += 1;
        }
        let mut n = nfr;
        let eliminated: std::collections::HashSet<usize> = nodes
            .iter()
            .map(|v| v.2)
            .chain(singles.iter().map(|v| v.2))
            .collect();
        for kc in 0..nk {
            if !eliminated.contains(&kc) {
                map[nf + kc] = Some(n);
                n += 1;
            }
        }
        // element columns and entry order
        let mut elem_start = Vec::with_capacity(model.elements.len() + 1);
        let mut cols: Lists<ElemCol> = Lists::with_capacity(model.elements.len());
        let mut beam_full = Vec::with_capacity(model.elements.len());
        let mut cons: Lists<u32> = Lists::with_capacity(model.elements.len());
        let mut n_entries = 0;
        // (each element's columns gathered here and kept at their exact size)
        let mut ec = Vec::new();
        let mut diag_trans = Vec::new();
        for entry in &model.elements {
            let start = n_entries;
            elem_start.push(start);
            ec.clear();
            let mut a = 0;
            while a < entry.xmap.len() {
                let xi = entry.x_index(a);
                if let Some(k) = node_at[xi] {
                    let d0 = nodes[k].1;
                    for j in 0..3 {
                        ec.push(ElemCol::new(
                            RCol::Rot {
                                a0: a as u32,
                                j: j as u8,
                            },
                            d0 + j,
                        ));
                    }
                    a += 4;
                    continue;
                }
                if let Some(m) = unknown[xi].and_then(|u| map[u]) {
                    ec.push(ElemCol::new(RCol::Plain(a as u32), m));
                }
                a += 1;
            }
            cons.push(
                (0..entry.element.ne())
                    .filter_map(|m| constraint[entry.ie + m])
                    .map(|kc| map[nf + kc].expect("element constraints are kept") as u32),
            );
            n_entries += element_entry_count(ec.len(), cons.of(cons.len() - 1).len());
            let full = entry.element.closed_form().is_some()
                && ec.len() == 12
                && (0..entry.element.ne()).all(|m| constraint[entry.ie + m].is_none())
                && ec.iter().enumerate().all(|(c, col)| match (c, col.rcol()) {
                    (0..=2, RCol::Plain(a)) => a as usize == c,
                    (3..=5, RCol::Rot { a0, j }) => a0 == 3 && j as usize == c - 3,
                    (6..=8, RCol::Plain(a)) => a as usize == c + 1,
                    (9..=11, RCol::Rot { a0, j }) => a0 == 10 && j as usize == c - 9,
                    _ => false,
                });
            beam_full.push(full);
            // the diagonal entries of its translations, in its block from `start`
            for (a, ua) in ec.iter().map(|c| c.unknown()).enumerate() {
                if ua < nfr && is_trans[ua] {
                    diag_trans.push(start + a * ec.len() + a);
                }
            }
            cols.push(ec.iter().copied());
        }
        cols.finish();
        cons.finish();
        elem_start.push(n_entries);
        diag_trans.shrink_to_fit();
        Self {
            map: slots(&map),
            nodes,
            singles,
            diag_trans,
            node_at: slots(&node_at),
            nfr,
            n,
            is_trans,
            cols,
            beam_full,
            cons,
            n_entries,
            elem_start,
        }
    }

    /// Row and column of every KKT entry written by the element assembly, in order: per
    /// element its block on the reduced columns (row-major), then for each constrained mode
    /// the pairs (G, Gᵀ). Generated, not stored (millions of entries on large models).
    pub(super) fn for_each_entry(&self, f: impl FnMut(usize, usize)) {
        self.for_each_entry_in(0..self.beam_full.len(), f);
    }

    /// [`Reduction::for_each_entry`] for the elements `els` only.
    pub(super) fn for_each_entry_in(
        &self,
        els: std::ops::Range<usize>,
        mut f: impl FnMut(usize, usize),
    ) {
        for el in els {
            element_entries(self.elem_cols(el), self.elem_cons(el), &mut f);
        }
    }

    /// The reduced constraint rows of element `el`'s constrained modes.
    pub(super) fn elem_cons(&self, el: usize) -> impl Iterator<Item = usize> + '_ {
        self.cons.of(el).iter().map(|&r| r as usize)
    }

    /// The reduced local coordinates of element `el` with their reduced unknowns.
    pub(super) fn elem_cols(&self, el: usize) -> &[ElemCol] {
        self.cols.of(el)
    }
}

/// The order of one element's KKT entries ([`Pattern`], [`Reduction`]): the block on its
/// columns (each with its unknown: [`Unknown`]), row-major, then for each of the
/// constraint rows `cons` the pairs (G, Gᵀ) over the columns.
pub(super) fn element_entries<C: Unknown>(
    cols: &[C],
    cons: impl Iterator<Item = usize>,
    f: &mut impl FnMut(usize, usize),
) {
    for ua in cols.iter().map(C::unknown_of) {
        for ub in cols.iter().map(C::unknown_of) {
            f(ua, ub);
        }
    }
    for kr in cons {
        for ub in cols.iter().map(C::unknown_of) {
            f(kr, ub);
            f(ub, kr);
        }
    }
}

/// Number of entries [`element_entries`] writes for `nc` columns and `ncons` constraint rows.
pub(super) fn element_entry_count(nc: usize, ncons: usize) -> usize {
    nc * nc + 2 * ncons * nc
}

/// Scale of the Euler-parameter increment N δ of a reduced node (|λ| = 1, ‖δ‖² = `d2`) so that
/// the node turns by atan ‖ω‖ instead of 2 atan(‖ω‖/2), ω = 2 Λ̄ N δ the linearised rotation:
/// s = tan(atan(2‖δ‖)/2)/‖δ‖ = 2/(1 + √(1 + 4‖δ‖²)).
///
/// Under the linear update of the positions a chord whose end moves across it by θ times its
/// length turns by atan θ. With this update a node triad that turns with the chord in the
/// linearised step (ω ⟂ chord, ‖ω‖ = θ) also turns by atan θ, whereas the plain update turns it
/// by 2 atan(θ/2): a mismatch of θ³/4 that loads the element's bending modes. On fine meshes
/// that mismatch, times the bending stiffness EI/l0³ of the short elements, dominates the
/// residual after a Newton step and makes Newton diverge (the straight cantilever at
/// N = 10,000). The update agrees with the plain one to first order (s = 1 − ‖δ‖² + …), so it
/// is still Newton's method with its local quadratic convergence, and the converged equilibria
/// are the same.
pub(super) fn chord_consistent_scale(d2: f64) -> f64 {
    2.0 / (1.0 + (1.0 + 4.0 * d2).sqrt())
}

/// The multiplier of the normalisation of each node with a single free Euler parameter λ_i
/// ([`Reduction`]): the value that makes the equilibrium row of λ_i hold at the current state,
/// r_i + 2 Δμ λ_i = 0; the residual and the generalised forces of the node are updated with it.
/// (The full Newton system gives the same value up to the linearisation error, and at the
/// solution exactly.)
pub(super) fn solve_single_multipliers(su: &Setup, x: &[f64], mu: &mut [f64], a: &mut Assembled) {
    for &(r, xi, kc) in &su.red.singles {
        let (Some(u), l) = (su.unknown[xi].get(), x[xi]) else {
            continue;
        };
        if l == 0.0 {
            continue;
        }
        let dmu = -a.r[u] / (2.0 * l);
        mu[kc] += dmu;
        for c in r..r + 4 {
            a.balance[c] += 2.0 * dmu * x[c];
            if let Some(uc) = su.unknown[c].get() {
                a.r[uc] = a.balance[c];
            }
        }
    }
}

/// N(λ) = Λ̄(λ)ᵀ/‖λ‖ (4 × 3): Δλ = N δ spans λ⊥ with orthonormal columns.
pub(super) fn rot_basis(l: &[f64]) -> [[f64; 3]; 4] {
    let l4 = [l[0], l[1], l[2], l[3]];
    let inv = 1.0 / l4.iter().map(|v| v * v).sum::<f64>().sqrt();
    let lb = lambda_bar(&l4);
    std::array::from_fn(|i| std::array::from_fn(|j| lb[j][i] * inv))
}

/// The columns of an element's T (reduced → original local coordinates, see [`Reduction`]):
/// up to four (local coordinate, coefficient) pairs each, with the rotation bases N(λ) of up to
/// four nodes cached. `xk(a)`: the element's local coordinate a at the state.
pub(super) struct TColumns<'a> {
    xk: &'a dyn Fn(usize) -> f64,
    bases: [[[f64; 3]; 4]; 4],
    base_a0: [usize; 4],
    nb: usize,
}

impl<'a> TColumns<'a> {
    pub(super) fn new(xk: &'a dyn Fn(usize) -> f64) -> Self {
        Self {
            xk,
            bases: [[[0.0; 3]; 4]; 4],
            base_a0: [usize::MAX; 4],
            nb: 0,
        }
    }

    /// The column of reduced coordinate `c`: its pairs and how many there are.
    pub(super) fn col(&mut self, c: &RCol) -> ([(usize, f64); 4], usize) {
        match *c {
            RCol::Plain(a) => ([(a as usize, 1.0), (0, 0.0), (0, 0.0), (0, 0.0)], 1),
            RCol::Rot { a0, j } => {
                let (a0, j) = (a0 as usize, j as usize);
                let slot = match self.base_a0[..self.nb].iter().position(|&v| v == a0) {
                    Some(s) => s,
                    None => {
                        let xk = self.xk;
                        let l = [xk(a0), xk(a0 + 1), xk(a0 + 2), xk(a0 + 3)];
                        if self.nb == self.bases.len() {
                            // more than four rotational nodes in one element: no cache
                            let nm = rot_basis(&l);
                            return (std::array::from_fn(|i| (a0 + i, nm[i][j])), 4);
                        }
                        self.bases[self.nb] = rot_basis(&l);
                        self.base_a0[self.nb] = a0;
                        self.nb += 1;
                        self.nb - 1
                    }
                };
                (std::array::from_fn(|i| (a0 + i, self.bases[slot][i][j])), 4)
            }
        }
    }
}

/// The reduced element entries Tᵀ K T and G T (see [`Reduction`]), written in its order.
/// `kt` is scratch of at least nx_k × (number of reduced columns).
#[allow(clippy::too_many_arguments)]
pub(super) fn write_reduced(
    su: &Setup,
    el: usize,
    ie: usize,
    ne: usize,
    xk: &dyn Fn(usize) -> f64,
    nxk: usize,
    k: &dyn Fn(usize, usize) -> f64,
    d: &dyn Fn(usize, usize) -> f64,
    vals: &mut [f64],
    kt: &mut [f64],
) {
    let cols = su.red.elem_cols(el);
    let nc = cols.len();
    let mut tcol = TColumns::new(xk);
    let mut ts_buf = [([(0usize, 0.0f64); 4], 0usize); 16];
    let mut ts_vec;
    let ts: &mut [([(usize, f64); 4], usize)] = if nc <= ts_buf.len() {
        &mut ts_buf[..nc]
    } else {
        ts_vec = vec![([(0usize, 0.0f64); 4], 0usize); nc];
        &mut ts_vec
    };
    for (t, c) in ts.iter_mut().zip(cols) {
        *t = tcol.col(&c.rcol());
    }
    // K T
    for a in 0..nxk {
        for (c, (t, len)) in ts.iter().enumerate() {
            kt[a * nc + c] = t[..*len].iter().map(|&(b, w)| w * k(a, b)).sum();
        }
    }
    let mut i = 0;
    for (t1, l1) in ts.iter() {
        for c2 in 0..nc {
            vals[i] = t1[..*l1].iter().map(|&(a, w)| w * kt[a * nc + c2]).sum();
            i += 1;
        }
    }
    for m in 0..ne {
        if su.constraint[ie + m].get().is_some() {
            for (t, len) in ts.iter() {
                let v: f64 = t[..*len].iter().map(|&(b, w)| w * d(m, b)).sum();
                vals[i] = v;
                vals[i + 1] = v;
                i += 2;
            }
        }
    }
    debug_assert_eq!(i, vals.len());
}
