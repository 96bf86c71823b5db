//! The linearised problem at a converged state in the reduced unknowns of the Newton system
//! ([`ReducedLinear`], the sparse form of `crate::linearized`), and the strain energies of
//! displacements through the element deformations.

use super::*;

/// The linearised problem at a converged state in the reduced unknowns of the Newton system
/// ([`Reduction`]), as sparse entries: the basis of the sparse eigen path of
/// [`crate::dynamics`].
///
/// The unknowns are the free translations and other free coordinates, three rotation
/// increments δ per rotational node whose Euler parameters are all free (Δλ = N(λ) δ with
/// N = Λ̄ᵀ, so the angular velocity is ω = 2 δ: velocity coordinates), and the multipliers of the
/// kept constraints (rigid and input deformations, normalisations of partly held nodes). The
/// matrix is the Newton matrix of statics at the state, [K, Gᵀ; G, 0] with K = K_m + K_g
/// (material and geometric stiffness, normalisation terms, load stiffness of moments): the same
/// stiffness as the dense [`crate::linearized::linearize`], in other coordinates.
pub(crate) struct ReducedLinear {
    pub(super) su: Setup,
    /// Row and column of the entries after the element blocks (moments, normalisations;
    /// 32-bit, as the reduction's columns: three per rotational node).
    pub(super) tail: Vec<(u32, u32)>,
    /// Value of every tail entry. The values of the element blocks are not held: they are
    /// made a block of elements at a time ([`ReducedLinear::element_values`]), as many as
    /// 144 per beam.
    pub tail_vals: Vec<f64>,
    /// The geometric (load-proportional) part K_g of the values of every entry (the element
    /// blocks in [`Reduction`] order, see [`ReducedLinear::for_each_entry`], then the tail):
    /// zero in the constraint rows and columns; empty when it is zero everywhere (an
    /// unstressed state).
    pub geo: Vec<f64>,
}

impl ReducedLinear {
    /// The reduced tangent at a converged step.
    pub(crate) fn new(model: &Model, step: &StepResult) -> Self {
        let su = setup(model);
        let (tail, tail_vals) = tail_entries(model, &su, step, (Part::Full, true));
        let tail: Vec<(u32, u32)> = tail.iter().map(|&(r, c)| (r as u32, c as u32)).collect();
        // the geometric part vanishes in a state without stress resultants, multipliers and
        // moment loads (the unloaded reference state)
        let unstressed = step.sigma.iter().all(|&v| v == 0.0)
            && step.multipliers.iter().all(|&v| v == 0.0)
            && (su.moments.is_empty() || step.load_factor == 0.0);
        let mut geo = if unstressed {
            Vec::new()
        } else {
            let g = assemble_values(
                model,
                &su,
                &step.x,
                &step.multipliers,
                step.load_factor,
                Part::Geometric,
                true,
                Vec::new(),
            );
            debug_assert!(g
                .tail
                .iter()
                .copied()
                .eq(tail.iter().map(|&(r, c)| (r as usize, c as usize))));
            g.vals
        };
        if !geo.is_empty() {
            let nfr = su.red.nfr;
            let mut i = 0;
            let mut clear_constraints = |r: usize, c: usize| {
                if r >= nfr || c >= nfr {
                    geo[i] = 0.0;
                }
                i += 1;
            };
            su.red.for_each_entry(&mut clear_constraints);
            for &(r, c) in &tail {
                clear_constraints(r as usize, c as usize);
            }
        }
        Self {
            su,
            tail,
            tail_vals,
            geo,
        }
    }

    /// The values of the element entries of elements `els` (K = K_m + K_g at `step`, the state
    /// this was made at), written into `out` in the order of
    /// [`ReducedLinear::for_each_entry_in`]: the element part of the matrix a block at a time.
    pub(crate) fn element_values(
        &self,
        model: &Model,
        step: &StepResult,
        els: std::ops::Range<usize>,
        out: &mut [f64],
    ) {
        element_values(
            model,
            &self.su,
            &step.x,
            &step.multipliers,
            Part::Full,
            true,
            els,
            out,
        );
    }

    /// Number of entries: the element blocks and the tail.
    pub(crate) fn n_entries(&self) -> usize {
        self.su.red.n_entries + self.tail.len()
    }

    /// Row and column of the entries of elements `els` ([`ReducedLinear::for_each_entry`]).
    pub(crate) fn for_each_entry_in(
        &self,
        els: std::ops::Range<usize>,
        f: impl FnMut(usize, usize),
    ) {
        self.su.red.for_each_entry_in(els, f);
    }

    /// The tail entries (after the element blocks): row, column and value.
    pub(crate) fn tail(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.tail
            .iter()
            .zip(&self.tail_vals)
            .map(|(&(r, c), &v)| (r as usize, c as usize, v))
    }

    /// Row and column of every entry, in the order of `vals`.
    pub(crate) fn for_each_entry(&self, mut f: impl FnMut(usize, usize)) {
        self.su.red.for_each_entry(&mut f);
        for &(r, c) in &self.tail {
            f(r as usize, c as usize);
        }
    }

    /// Twice the material strain energy, Σ δeᵀ S δe over the elements' flexible deformations
    /// with δe = D δx, of each shape δx (length nx). Evaluated through the deformations, not as
    /// δxᵀ K_m δx: on fine meshes the entries of K_m are many orders of magnitude larger than
    /// the stiffness of a smooth mode, and the matrix product loses it to round-off.
    pub(crate) fn material_energy2(
        &self,
        model: &Model,
        x: &[f64],
        shapes: &[Vec<f64>],
    ) -> Vec<f64> {
        material_energy2(model, &self.su, x, shapes)
    }

    /// The row of the system that holds deformation `e` (a rigid or input deformation).
    pub(crate) fn constraint_row(&self, e: usize) -> Option<usize> {
        self.su.constraint[e]
            .get()
            .and_then(|k| self.su.red.map[self.su.nf + k].get())
    }

    /// Size of the system (coordinates and kept constraints).
    pub(crate) fn n(&self) -> usize {
        self.su.red.n
    }

    /// Number of coordinate unknowns (they come first; the constraints follow).
    pub(crate) fn n_coords(&self) -> usize {
        self.su.red.nfr
    }

    /// The entries of element `el` (a contiguous range of `rows`/`cols`/`vals`).
    pub(crate) fn element_entries(&self, el: usize) -> std::ops::Range<usize> {
        self.su.red.elem_start[el]..self.su.red.elem_start[el + 1]
    }

    /// Tᵀ L T for a matrix L on the local coordinates of element `el` (`local(a, b)`, local
    /// order of its `xmap`), written into `out` in the order of the element's entries; the
    /// entries of its constraint rows get zero.
    pub(crate) fn element_block(
        &self,
        model: &Model,
        el: usize,
        x: &[f64],
        local: &dyn Fn(usize, usize) -> f64,
        out: &mut [f64],
    ) {
        let entry = &model.elements[el];
        let nxk = entry.xmap.len();
        let mut kt = vec![0.0; nxk * self.su.red.elem_cols(el).len()];
        write_reduced(
            &self.su,
            el,
            entry.ie,
            entry.element.ne(),
            &|a| x[entry.x_index(a)],
            nxk,
            local,
            &|_, _| 0.0,
            out,
            &mut kt,
        );
    }

    /// The reduced index of x coordinate `i` when it is an unknown of its own (a free
    /// translation, or an Euler parameter of a node that is not reduced).
    pub(crate) fn coord_index(&self, i: usize) -> Option<usize> {
        coord_index(&self.su, i)
    }

    /// Entries (row, column, value) of Tᵀ B T for a 4 × 4 block B on the Euler parameters of
    /// the rotational node with λ0 at x index `r` (an inertia tensor).
    pub(crate) fn lambda_block(
        &self,
        x: &[f64],
        r: usize,
        blk: &[[f64; 4]; 4],
    ) -> Vec<(usize, usize, f64)> {
        let mut out = Vec::new();
        if let Some(k) = self.su.red.node_at[r].get() {
            let nb = rot_basis(&x[r..r + 4]);
            let d0 = self.su.red.nodes[k].1;
            for p in 0..3 {
                for q in 0..3 {
                    let mut v = 0.0;
                    for i in 0..4 {
                        for j in 0..4 {
                            v += nb[i][p] * blk[i][j] * nb[j][q];
                        }
                    }
                    out.push((d0 + p, d0 + q, v));
                }
            }
            return out;
        }
        for i in 0..4 {
            let Some(ri) = self.coord_index(r + i) else {
                continue;
            };
            for j in 0..4 {
                if let Some(rj) = self.coord_index(r + j) {
                    out.push((ri, rj, blk[i][j]));
                }
            }
        }
        out
    }

    /// Whether coordinate unknown `m` is a translation (else an Euler parameter or a rotation
    /// increment).
    pub(crate) fn is_translation(&self, m: usize) -> bool {
        self.su.red.is_trans[m]
    }

    /// The node of every coordinate unknown (a node `at` a host owns only its rotation): the
    /// unknowns of one node share their couplings, which a fill-reducing ordering can use.
    pub(crate) fn coord_nodes(&self, model: &Model) -> Vec<usize> {
        let mut owner = vec![usize::MAX; model.nx];
        for (id, n) in model.nodes.iter().enumerate() {
            for i in n.own_range() {
                owner[i] = id;
            }
        }
        let mut out = vec![usize::MAX; self.su.red.nfr];
        for (i, &o) in owner.iter().enumerate() {
            if let Some(m) = self.coord_index(i) {
                out[m] = o;
            }
        }
        for &(r, d0, _) in &self.su.red.nodes {
            out[d0..d0 + 3].iter_mut().for_each(|v| *v = owner[r]);
        }
        out
    }

    /// Generalised forces on the reduced coordinates of a force vector `f` in x (length nx):
    /// the transpose of [`ReducedLinear::to_x`], so that uᵀ (this) = (to_x u)ᵀ f.
    pub(crate) fn force_to_coords(&self, x: &[f64], f: &[f64]) -> Vec<f64> {
        force_to_coords(&self.su, x, f)
    }

    /// δx (length nx) of a vector `u` of the coordinate unknowns at the state `x`.
    pub(crate) fn to_x(&self, model: &Model, x: &[f64], u: &[f64]) -> Vec<f64> {
        to_x(&self.su, model, x, u)
    }

    /// Releases what only the assembly reads ([`Setup::release_assembly`]), once the values
    /// are held elsewhere: this can no longer assemble afterwards.
    pub(crate) fn release_assembly(&mut self) {
        self.su.release_assembly();
    }

    /// The setup the values were assembled with (the effective stiffnesses).
    pub(crate) fn setup(&self) -> &Setup {
        &self.su
    }
}

/// The reduced index of x coordinate `i` when it is an unknown of its own (a free translation,
/// or an Euler parameter of a node that is not reduced).
fn coord_index(su: &Setup, i: usize) -> Option<usize> {
    su.unknown[i].get().and_then(|u| su.red.map[u].get())
}

/// Generalised forces on the reduced coordinates (the first `su.red.nfr` unknowns of the
/// reduced Newton system) of a force vector `f` in x (length nx) at the state `x`: the
/// transpose of [`to_x`], so that uᵀ (this) = (to_x u)ᵀ f.
fn force_to_coords(su: &Setup, x: &[f64], f: &[f64]) -> Vec<f64> {
    let mut fc = vec![0.0; su.red.nfr];
    for (i, fi) in f.iter().enumerate() {
        if let Some(m) = coord_index(su, i) {
            fc[m] += fi;
        }
    }
    for &(r, d0, _) in &su.red.nodes {
        let nb = rot_basis(&x[r..r + 4]);
        for (j, v) in fc[d0..d0 + 3].iter_mut().enumerate() {
            *v += (0..4).map(|i| nb[i][j] * f[r + i]).sum::<f64>();
        }
    }
    fc
}

/// δx (length nx) of a vector `u` of the reduced coordinate unknowns at the state `x`.
fn to_x(su: &Setup, model: &Model, x: &[f64], u: &[f64]) -> Vec<f64> {
    let mut dx = vec![0.0; model.nx];
    for (i, d) in dx.iter_mut().enumerate() {
        if let Some(m) = coord_index(su, i) {
            *d = u[m];
        }
    }
    for &(r, d0, _) in &su.red.nodes {
        let nb = rot_basis(&x[r..r + 4]);
        for i in 0..4 {
            dx[r + i] = (0..3).map(|j| nb[i][j] * u[d0 + j]).sum();
        }
    }
    dx
}

/// Whether an element has stiffness: a non-zero entry in its effective S.
fn has_stiffness(s: faer::MatRef<'_, f64>, ne: usize) -> bool {
    (0..ne).any(|a| (0..ne).any(|b| s[(a, b)] != 0.0))
}

/// The material stiffness times displacements on the reduced coordinates, K_m u = Σ (D T)ᵀ S
/// (D T u) over the elements' flexible deformations, evaluated through the deformations
/// δe = D T u for the reason given at [`ReducedLinear::material_energy2`]. Each element's D T
/// (its deformation Jacobian on its reduced columns, T as in the reduced Newton system:
/// [`super::reduction::TColumns`]) is computed once and kept: ne × (reduced columns) values per
/// element with stiffness, 72 for a beam of two free rotational nodes (D alone has 84, and a
/// product through it went through vectors in x and back). For the refined solves of the sparse
/// modes and of statics' Newton, which take hundreds of these products.
pub(crate) struct MaterialOperator {
    /// Per element with stiffness: its index, its [`Layout`] in `layouts`, and the offset of
    /// its kept values in `vals`.
    elements: Vec<(u32, u32, usize)>,
    /// The distinct layouts of the elements' D T (the beams of a leaf share one or a few).
    layouts: Vec<Layout>,
    /// The entries kept ([`Code::Kept`]), element by element, row by row.
    vals: Vec<f64>,
}

/// The non-zero entries of an element's D T (ne × nc): row by row, (column, index of its
/// value among the element's kept values, negated: a [`Code::Mirror`]), columns ascending; and
/// column by column, (row, value, negated), rows ascending. A product through them has the
/// sums of one through the full D T less its zero terms, which change no sum that is not zero.
#[derive(Clone, PartialEq, Eq, Hash)]
struct Layout {
    rows: Vec<Vec<(u16, u16, bool)>>,
    cols: Vec<Vec<(u16, u16, bool)>>,
}

/// How an entry of an element's D T is kept: exact zeros are not stored, nor, for a beam whose
/// reduced columns are its two nodes' translations and rotation increments
/// ([`super::reduction::Reduction::beam_full`]), the second node's translation columns where
/// they are the negatives of the first's (bit for bit; the deformations depend on the
/// translations through their difference). A straight beam along an axis keeps 16 of its 72
/// values, a beam in a general direction 54.
#[derive(Clone, Copy, PartialEq)]
enum Code {
    Zero,
    Kept,
    /// The negative of the first node's translation entry of the row (six columns to the left).
    Mirror,
}

impl Code {
    /// The code of entry `c` of `row` (`mirror`: the element's columns allow [`Code::Mirror`]).
    fn of(row: &[f64], c: usize, mirror: bool) -> Self {
        let v = row[c];
        if v == 0.0 {
            Code::Zero
        } else if mirror && (6..9).contains(&c) && v.to_bits() == (-row[c - 6]).to_bits() {
            Code::Mirror
        } else {
            Code::Kept
        }
    }
}

impl MaterialOperator {
    /// The material stiffness of the elements of `su` (their effective stiffnesses) at the
    /// state `x`.
    pub(crate) fn new(model: &Model, su: &Setup, x: &[f64]) -> Self {
        let stiff: Vec<usize> = (0..model.elements.len())
            .filter(|&el| has_stiffness(su.s_eff.get(el), model.elements[el].element.ne()))
            .collect();
        let jac_t = |&el: &usize| -> Vec<f64> {
            let entry = &model.elements[el];
            let (ne, nxe) = (entry.element.ne(), entry.xmap.len());
            let d: Vec<f64> = match (entry.element.closed_form(), ne, nxe) {
                (Some(cf), 6, 14) => {
                    let xk: [f64; 14] = std::array::from_fn(|i| x[entry.x_index(i)]);
                    cf.first(&xk).d.iter().flatten().copied().collect()
                }
                _ => {
                    let d = entry.element.jacobian(&gather(entry, x));
                    (0..ne)
                        .flat_map(|r| (0..nxe).map(move |c| (r, c)))
                        .map(|(r, c)| d[(r, c)])
                        .collect()
                }
            };
            let xk = |a: usize| x[entry.x_index(a)];
            let mut tc = super::reduction::TColumns::new(&xk);
            let cols: Vec<([(usize, f64); 4], usize)> = su
                .red
                .elem_cols(el)
                .iter()
                .map(|c| tc.col(&c.rcol()))
                .collect();
            let mut dt = Vec::with_capacity(ne * cols.len());
            for r in 0..ne {
                let row = &d[r * nxe..(r + 1) * nxe];
                dt.extend(
                    cols.iter()
                        .map(|(t, len)| t[..*len].iter().map(|&(a, w)| w * row[a]).sum::<f64>()),
                );
            }
            dt
        };
        let mut elements = Vec::with_capacity(stiff.len());
        let mut layouts: Vec<Layout> = Vec::new();
        let mut index: rustc_hash::FxHashMap<Layout, u32> = Default::default();
        let mut vals = Vec::new();
        let small =
            |i: usize| u16::try_from(i).expect("element D T of under 2^16 columns and values");
        // (a chunk of elements at a time, in parallel: not every element's D T at once, 0.6 KB
        // per beam)
        const CHUNK: usize = 8192;
        for part in stiff.chunks(CHUNK) {
            let blocks: Vec<Vec<f64>> = if stiff.len() < 256 {
                part.iter().map(jac_t).collect()
            } else {
                part.par_iter().with_min_len(64).map(jac_t).collect()
            };
            for (&el, dt) in part.iter().zip(&blocks) {
                let nc = su.red.elem_cols(el).len();
                let ne = dt.len().checked_div(nc).unwrap_or(0);
                let mirror = su.red.beam_full[el];
                let mut layout = Layout {
                    rows: vec![Vec::new(); ne],
                    cols: vec![Vec::new(); nc],
                };
                let val_at = vals.len();
                for (r, row) in dt.chunks_exact(nc.max(1)).enumerate() {
                    // (the index among the element's kept values of the row's first three)
                    let mut kept_at = [usize::MAX; 3];
                    for c in 0..nc {
                        let (v, neg) = match Code::of(row, c, mirror) {
                            Code::Zero => continue,
                            Code::Kept => {
                                vals.push(row[c]);
                                let v = vals.len() - 1 - val_at;
                                if c < 3 {
                                    kept_at[c] = v;
                                }
                                (v, false)
                            }
                            // (a mirror's source is not zero: it is kept)
                            Code::Mirror => (kept_at[c - 6], true),
                        };
                        layout.rows[r].push((small(c), small(v), neg));
                        layout.cols[c].push((small(r), small(v), neg));
                    }
                }
                let id = *index.entry(layout).or_insert_with_key(|l| {
                    layouts.push(l.clone());
                    (layouts.len() - 1) as u32
                });
                let el = u32::try_from(el).expect("fewer than 2³² elements");
                elements.push((el, id, val_at));
            }
        }
        vals.shrink_to_fit();
        MaterialOperator {
            elements,
            layouts,
            vals,
        }
    }

    /// K_m u on the reduced coordinates (the first `su.red.nfr` unknowns of the reduced Newton
    /// system) at the state the operator was made at.
    /// Written into `f` (length `su.red.nfr`), without a vector of its own (a product of every
    /// iteration of a refined solve).
    pub(crate) fn reduced_forces(&self, model: &Model, su: &Setup, u: &[f64], f: &mut [f64]) {
        debug_assert_eq!(f.len(), su.red.nfr);
        f.iter_mut().for_each(|v| *v = 0.0);
        let mut de = Vec::new();
        let mut sig = Vec::new();
        for &(el, layout, val_at) in &self.elements {
            let el = el as usize;
            let ne = model.elements[el].element.ne();
            let s = su.s_eff.get(el);
            let cols = su.red.elem_cols(el);
            let layout = &self.layouts[layout as usize];
            let vals = &self.vals[val_at..];
            let value = |v: u16, neg: bool| {
                let a = vals[v as usize];
                if neg {
                    -a
                } else {
                    a
                }
            };
            de.clear();
            de.extend(layout.rows.iter().map(|row| {
                row.iter()
                    .map(|&(c, v, neg)| value(v, neg) * u[cols[c as usize].unknown()])
                    .sum::<f64>()
            }));
            sig.clear();
            sig.extend((0..ne).map(|a| (0..ne).map(|b| s[(a, b)] * de[b]).sum::<f64>()));
            for (col, m) in layout.cols.iter().zip(cols.iter().map(|c| c.unknown())) {
                if !col.is_empty() {
                    f[m] += col
                        .iter()
                        .map(|&(r, v, neg)| value(v, neg) * sig[r as usize])
                        .sum::<f64>();
                }
            }
        }
    }
}

/// Twice the material strain energy Σ δeᵀ S δe of each shape δx (length nx) over the
/// elements' flexible deformations (the effective stiffnesses of `su`), δe = D δx
/// ([`ReducedLinear::material_energy2`]).
pub(crate) fn material_energy2(
    model: &Model,
    su: &Setup,
    x: &[f64],
    shapes: &[Vec<f64>],
) -> Vec<f64> {
    let per_element = |el: usize| -> Vec<f64> {
        let entry = &model.elements[el];
        let s = su.s_eff.get(el);
        let ne = entry.element.ne();
        if !has_stiffness(s, ne) {
            return vec![0.0; shapes.len()];
        }
        deformation_energies(entry, s, x, shapes)
            .chunks_exact(ne)
            .map(|e| e.iter().sum())
            .collect()
    };
    let parts: Vec<Vec<f64>> = if model.elements.len() < 256 {
        (0..model.elements.len()).map(per_element).collect()
    } else {
        (0..model.elements.len())
            .into_par_iter()
            .with_min_len(64)
            .map(per_element)
            .collect()
    };
    let mut out = vec![0.0; shapes.len()];
    for p in &parts {
        for (o, v) in out.iter_mut().zip(p) {
            *o += v;
        }
    }
    out
}

/// δeₐ (S δe)ₐ of every deformation a of an element for each displacement δx (length nx),
/// δe = D δx: twice the strain energy of the deformation (with the coupling terms of S split
/// by rows); flat, shape k's values at k ne … (k + 1) ne. Closed-form D in fixed-size arrays
/// for the beam.
pub(crate) fn deformation_energies(
    entry: &crate::model::ElementEntry,
    s: faer::MatRef<'_, f64>,
    x: &[f64],
    shapes: &[Vec<f64>],
) -> Vec<f64> {
    let ne = entry.element.ne();
    let mut out = Vec::with_capacity(ne * shapes.len());
    if let (Some(cf), 6, 14) = (entry.element.closed_form(), ne, entry.xmap.len()) {
        // the same sums as below, without allocations per shape
        let xk: [f64; 14] = std::array::from_fn(|i| x[entry.x_index(i)]);
        let d = cf.first(&xk).d;
        for dx in shapes {
            let de: [f64; 6] = std::array::from_fn(|r| {
                entry
                    .x_indices()
                    .enumerate()
                    .map(|(c, i)| d[r][c] * dx[i])
                    .sum()
            });
            out.extend((0..6).map(|a| de[a] * (0..6).map(|b| s[(a, b)] * de[b]).sum::<f64>()));
        }
        return out;
    }
    let d = entry.element.jacobian(&gather(entry, x));
    for dx in shapes {
        let de = deformation_change(entry, &d, dx);
        out.extend((0..ne).map(|a| de[a] * (0..ne).map(|b| s[(a, b)] * de[b]).sum::<f64>()));
    }
    out
}

/// δe = D δx_k of an element for a displacement δx (length nx).
pub(super) fn deformation_change(
    entry: &crate::model::ElementEntry,
    d: &Mat<f64>,
    dx: &[f64],
) -> Vec<f64> {
    (0..d.nrows())
        .map(|r| {
            entry
                .x_indices()
                .enumerate()
                .map(|(c, i)| d[(r, c)] * dx[i])
                .sum()
        })
        .collect()
}
