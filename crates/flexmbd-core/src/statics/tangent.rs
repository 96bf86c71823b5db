//! The element assembly of residual and tangent at a state ([`assemble`], [`assemble_part`],
//! [`assemble_values`]), the loads and the prescribed values.

use super::*;
use crate::assembly::{map_elements, split_at_starts};

/// Everything assembled at one state.
pub(crate) struct Assembled {
    /// Residual on the free coordinates.
    pub(crate) r: Vec<f64>,
    /// Constraint violations.
    pub(crate) g: Vec<f64>,
    /// KKT matrix entries, in the order of [`Pattern`] (or of [`Reduction`] for the reduced
    /// system) followed by the tail entries (moments, normalisations) whose row and column are
    /// in `tail`.
    pub(crate) vals: Vec<f64>,
    /// Number of element entries at the start of `vals`.
    pub(crate) n_el: usize,
    /// Row and column of the entries after the element blocks.
    pub(crate) tail: Vec<(usize, usize)>,
    /// KKT matrix entries as triplets (only from [`assemble_part`], for the linearisation).
    pub(crate) triplets: Vec<Triplet<usize, usize, f64>>,
    /// Force scale for the convergence test.
    pub(crate) f_scale: f64,
    /// Full generalised force balance f_int − f_ext + ∇p on all of x (reactions).
    pub(crate) balance: Vec<f64>,
    /// Element part of `balance` (internal forces Dᵀσ) and the sums of their magnitudes.
    pub(crate) int_force: Vec<f64>,
    pub(crate) int_abs: Vec<f64>,
    pub(crate) e: Vec<f64>,
    pub(crate) sigma: Vec<f64>,
    pub(crate) energy: f64,
    /// Whether `vals` holds the reduced system ([`Reduction`]).
    pub(crate) reduced: bool,
    /// Whether `vals` holds the matrix entries (false after `Part::Residual`: forces,
    /// deformations and constraint violations alone).
    pub(crate) tangent: bool,
}

/// Which part of the tangent to assemble.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Part {
    /// K = K_material + K_geometric (Newton).
    Full,
    /// Dᵀ S D only.
    Material,
    /// Σ σᵢ ∂²eᵢ/∂x² + normalisation multipliers + load stiffness (proportional to the load).
    Geometric,
    /// No tangent: forces, deformations and constraint violations only, without matrix
    /// entries (`vals` and `tail` empty; a modified Newton iteration that reuses its matrix).
    Residual,
}

pub(crate) fn assemble(model: &Model, su: &Setup, x: &[f64], mu: &[f64], t: f64) -> Assembled {
    assemble_values(model, su, x, mu, t, Part::Full, false, Vec::new())
}

/// [`assemble_values`] with the KKT entries as triplets.
pub(crate) fn assemble_part(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
) -> Assembled {
    let mut a = assemble_values(model, su, x, mu, t, part, false, Vec::new());
    let pat = su.pattern.layout();
    let n_el = pat.rows.len();
    a.triplets = (0..n_el)
        .map(|i| Triplet::new(pat.rows[i], pat.cols[i], a.vals[i]))
        .chain(
            a.tail
                .iter()
                .zip(&a.vals[n_el..])
                .map(|(&(r, c), &v)| Triplet::new(r, c, v)),
        )
        .collect();
    a
}

/// One element's contribution, written into its own slices (parallel part): deformations,
/// stress resultants, internal forces Dᵀσ on its local coordinates, and its block of KKT
/// entries in [`Pattern`] order (with `reduced`, [`Reduction`] order). Returns the elastic
/// energy.
#[allow(clippy::too_many_arguments)]
pub(super) fn element_local(
    su: &Setup,
    el: usize,
    entry: &crate::model::ElementEntry,
    x: &[f64],
    mu: &[f64],
    part: Part,
    reduced: bool,
    e_out: &mut [f64],
    sigma_out: &mut [f64],
    f_out: &mut [f64],
    vals: &mut [f64],
) -> f64 {
    let s = su.s_eff.get(el);
    let ne = e_out.len();
    // (the unreduced system's columns: read only there, so that the reduced assembly also runs
    // after `Setup::release_assembly`)
    let free = || su.pattern.elem_free.of(el);
    // KKT entries: K on the free local coordinates, then (G, Gᵀ) of the constrained modes
    let constrained = &su.constraint[entry.ie..entry.ie + ne];
    if let (Some(cf), 14) = (entry.element.closed_form(), entry.xmap.len()) {
        // closed-form derivatives in fixed-size arrays (elements/beam/closed_form.rs)
        let xk: [f64; 14] = std::array::from_fn(|i| x[entry.x_index(i)]);
        let first = cf.first(&xk);
        e_out.copy_from_slice(&first.e);
        let s6: [[f64; 6]; 6] = std::array::from_fn(|a| std::array::from_fn(|b| s[(a, b)]));
        let energy = stress(&first.e, sigma_out, |a, b| s6[a][b], constrained, mu);
        let d = &first.d;
        for (c, f) in f_out.iter_mut().enumerate() {
            *f = (0..6).map(|a| d[a][c] * sigma_out[a]).sum();
        }
        if part == Part::Residual {
            return energy;
        }
        let w: [f64; 6] = std::array::from_fn(|a| sigma_out[a]);
        if reduced && su.red.beam_full[el] && part == Part::Full {
            // Tᵀ K T directly in the tangent coordinates of both rotations
            let (bp, bq) = (rot_basis(&xk[3..7]), rot_basis(&xk[10..14]));
            let k = first.hessian_tangent(&w, Some(&s6), &bp, &bq);
            for (o, v) in vals.chunks_exact_mut(12).zip(&k) {
                o.copy_from_slice(v);
            }
            return energy;
        }
        let k = match part {
            Part::Full => first.hessian(&w, Some(&s6)),
            Part::Material => first.hessian(&[0.0; 6], Some(&s6)),
            Part::Geometric | Part::Residual => first.hessian(&w, None),
        };
        if reduced {
            // at most 14 reduced columns
            let mut kt = [0.0; 14 * 14];
            write_reduced(
                su,
                el,
                entry.ie,
                ne,
                &|a| xk[a],
                14,
                &|a, b| k[a][b],
                &|m, b| d[m][b],
                vals,
                &mut kt,
            );
        } else {
            // the closed form's arrays directly (inlined, no dynamic calls per entry)
            write_entries(vals, free(), constrained, |a, b| k[a][b], |m, b| d[m][b]);
        }
        return energy;
    }
    let xk = gather(entry, x);
    let e = entry.element.deformations(&xk);
    let d = entry.element.jacobian(&xk);
    e_out.copy_from_slice(&e);
    let energy = stress(&e, sigma_out, |a, b| s[(a, b)], constrained, mu);
    for (c, f) in f_out.iter_mut().enumerate() {
        *f = (0..ne).map(|a| d[(a, c)] * sigma_out[a]).sum();
    }
    if part == Part::Residual {
        return energy;
    }
    // K_k = Dᵀ S D + Σ σᵢ ∂²eᵢ/∂x²
    let nxk = xk.len();
    let mut k = if part == Part::Material {
        Mat::zeros(nxk, nxk)
    } else {
        entry.element.hessian_weighted(&xk, sigma_out)
    };
    if part != Part::Geometric {
        let sd = s * &d;
        k += d.transpose() * &sd;
    }
    if reduced {
        let mut kt = vec![0.0; nxk * su.red.elem_cols(el).len()];
        write_reduced(
            su,
            el,
            entry.ie,
            ne,
            &|a| xk[a],
            nxk,
            &|a, b| k[(a, b)],
            &|m, b| d[(m, b)],
            vals,
            &mut kt,
        );
    } else {
        write_entries(
            vals,
            free(),
            constrained,
            |a, b| k[(a, b)],
            |m, b| d[(m, b)],
        );
    }
    energy
}

/// σ = S_eff e (`s(a, b)` the entries of S_eff), plus the multipliers `mu` on the modes with a
/// constraint row (`constrained`); returns the elastic energy ½ eᵀ S_eff e.
#[inline]
fn stress(
    e: &[f64],
    sigma: &mut [f64],
    s: impl Fn(usize, usize) -> f64,
    constrained: &[Slot],
    mu: &[f64],
) -> f64 {
    let ne = e.len();
    let mut energy = 0.0;
    for a in 0..ne {
        sigma[a] = (0..ne).map(|b| s(a, b) * e[b]).sum();
        energy += 0.5 * sigma[a] * e[a];
        if let Some(c) = constrained[a].get() {
            sigma[a] += mu[c];
        }
    }
    energy
}

/// An element's KKT entries in [`Pattern`] order: K (`k(a, b)`) on its free local coordinates
/// `free`, then the pairs (G, Gᵀ) (`d(m, b)`) of each mode m with a constraint row.
#[inline]
fn write_entries(
    vals: &mut [f64],
    free: &[(u32, u32)],
    constrained: &[Slot],
    k: impl Fn(usize, usize) -> f64,
    d: impl Fn(usize, usize) -> f64,
) {
    let mut i = 0;
    for &(a, _) in free {
        for &(b, _) in free {
            vals[i] = k(a as usize, b as usize);
            i += 1;
        }
    }
    for (m, c) in constrained.iter().enumerate() {
        if c.get().is_some() {
            for &(b, _) in free {
                let v = d(m, b as usize);
                vals[i] = v;
                vals[i + 1] = v;
                i += 2;
            }
        }
    }
    debug_assert_eq!(i, vals.len());
}

/// Multiply the entries that element `el` wrote into `vals` (the full, unreduced system of
/// [`assemble_values`]) by `factor(el)`: a damping matrix Σₑ cₑ Dₑᵀ Sₑ Dₑ from the material
/// part.
pub(crate) fn scale_elements(su: &Setup, vals: &mut [f64], factor: impl Fn(usize) -> f64) {
    let layout = su.pattern.layout();
    for (el, w) in layout.elem_start.windows(2).enumerate() {
        let c = factor(el);
        if c != 1.0 {
            vals[w[0]..w[1]].iter_mut().for_each(|v| *v *= c);
        }
    }
}

/// Assemble at (x, μ, t): the KKT entries of the full system (order of [`Pattern`]) or, with
/// `reduced`, of the reduced one ([`Reduction`]); `spare` is a buffer to reuse for them.
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble_values(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
    reduced: bool,
    spare: Vec<f64>,
) -> Assembled {
    let pat = &su.pattern;
    // the residual alone writes no matrix entries
    let no_entries;
    let (n_el, elem_start) = if part == Part::Residual {
        no_entries = vec![0; model.elements.len() + 1];
        (0, &no_entries)
    } else if reduced {
        (su.red.n_entries, &su.red.elem_start)
    } else {
        let layout = pat.layout();
        (layout.rows.len(), &layout.elem_start)
    };
    // every element entry is written by its element: no need to clear a reused buffer; room
    // for the entries [`apply_loads`] appends, so that appending them does not double the
    // buffer (16 MB at 10⁴ beams), and a new buffer when it is short (nothing to copy)
    let capacity = if part == Part::Residual {
        0
    } else {
        n_el + tail_capacity(su)
    };
    let mut vals = spare;
    if vals.capacity() < capacity {
        vals = Vec::with_capacity(capacity);
    }
    vals.truncate(n_el);
    vals.resize(n_el, 0.0);
    let mut e = vec![0.0; model.ne];
    let mut sigma = vec![0.0; model.ne];
    let mut fbuf = vec![0.0; *pat.f_start.last().unwrap_or(&0)];
    let e_starts: Vec<usize> = model
        .elements
        .iter()
        .map(|en| en.ie)
        .chain(std::iter::once(model.ne))
        .collect();
    // the elastic energies added up in element order (the same sum on any number of threads)
    let outs = ElementOuts {
        vals: (&mut vals, elem_start),
        e: (&mut e, &e_starts),
        sigma: &mut sigma,
        f: (&mut fbuf, &pat.f_start),
    };
    let energy: f64 = map_local(
        model,
        su,
        (x, mu),
        part,
        reduced,
        0..model.elements.len(),
        outs,
    )
    .into_iter()
    .sum();

    let mut int_force = vec![0.0; model.nx];
    let mut int_abs = vec![0.0; model.nx];
    for (el, entry) in model.elements.iter().enumerate() {
        // internal forces Dᵀσ
        let f = &fbuf[pat.f_start[el]..pat.f_start[el + 1]];
        for (xi, &fi) in entry.x_indices().zip(f) {
            int_force[xi] += fi;
            int_abs[xi] += fi.abs();
        }
    }
    let mut a = Assembled::of_elements(vals, int_force, int_abs, e, sigma, energy, reduced);
    a.tangent = part != Part::Residual;
    apply_loads(model, su, x, mu, t, part, &mut a);
    a
}

impl Assembled {
    /// The element part of an assembly (its entries `vals`, internal forces, deformations,
    /// stress resultants and energy), for [`apply_loads`] to complete.
    fn of_elements(
        vals: Vec<f64>,
        int_force: Vec<f64>,
        int_abs: Vec<f64>,
        e: Vec<f64>,
        sigma: Vec<f64>,
        energy: f64,
        reduced: bool,
    ) -> Self {
        Self {
            r: Vec::new(),
            g: Vec::new(),
            n_el: vals.len(),
            vals,
            tail: Vec::new(),
            triplets: Vec::new(),
            f_scale: 0.0,
            balance: Vec::new(),
            int_force,
            int_abs,
            e,
            sigma,
            energy,
            reduced,
            tangent: true,
        }
    }
}

/// The KKT entries of the elements `els` alone, as [`assemble_values`] writes them (the full
/// system's order, or with `reduced` the reduced one's), into `vals` (their entries, in element
/// order; in parallel): the element part of a large tangent a block of elements at a time,
/// without an array of all its entries (`linearized::sparse`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn element_values(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    part: Part,
    reduced: bool,
    els: std::ops::Range<usize>,
    vals: &mut [f64],
) {
    debug_assert!(part != Part::Residual);
    let starts = if reduced {
        &su.red.elem_start[els.start..=els.end]
    } else {
        &su.pattern.layout().elem_start[els.start..=els.end]
    };
    debug_assert_eq!(vals.len(), starts[starts.len() - 1] - starts[0]);
    let entries = &model.elements[els.clone()];
    // the deformations, stress resultants and forces the element writes beside its entries
    let (mut e_starts, mut f_starts) = (vec![0], vec![0]);
    for en in entries {
        e_starts.push(e_starts[e_starts.len() - 1] + en.element.ne());
        f_starts.push(f_starts[f_starts.len() - 1] + en.xmap.len());
    }
    let mut e = vec![0.0; e_starts[entries.len()]];
    let mut sigma = e.clone();
    let mut f = vec![0.0; f_starts[entries.len()]];
    let outs = ElementOuts {
        vals: (vals, starts),
        e: (&mut e, &e_starts),
        sigma: &mut sigma,
        f: (&mut f, &f_starts),
    };
    map_local(model, su, (x, mu), part, reduced, els, outs);
}

/// What [`element_local`] writes for a range of elements, each buffer with the starts of the
/// elements' pieces in it (`sigma` split as `e`).
struct ElementOuts<'a> {
    vals: (&'a mut [f64], &'a [usize]),
    e: (&'a mut [f64], &'a [usize]),
    sigma: &'a mut [f64],
    f: (&'a mut [f64], &'a [usize]),
}

/// [`element_local`] for the elements `els`, each on its own pieces of `outs` (in parallel for
/// many elements); their energies in element order.
fn map_local(
    model: &Model,
    su: &Setup,
    (x, mu): (&[f64], &[f64]),
    part: Part,
    reduced: bool,
    els: std::ops::Range<usize>,
    outs: ElementOuts<'_>,
) -> Vec<f64> {
    let ElementOuts { vals, e, sigma, f } = outs;
    let pieces: Vec<_> = split_at_starts(vals.0, vals.1)
        .into_iter()
        .zip(split_at_starts(e.0, e.1))
        .zip(split_at_starts(sigma, e.1))
        .zip(split_at_starts(f.0, f.1))
        .collect();
    let first = els.start;
    map_elements(
        &model.elements[els],
        pieces,
        |i, entry, (((v, ek), sk), fk)| {
            element_local(su, first + i, entry, x, mu, part, reduced, ek, sk, fk, v)
        },
    )
}

/// The matrix entries an assembly at a converged `step` appends after the element entries
/// ([`apply_loads`]: load stiffness of moments, normalisation terms), as (row, column) and
/// value, without the element part.
pub(crate) fn tail_entries(
    model: &Model,
    su: &Setup,
    step: &StepResult,
    (part, reduced): (Part, bool),
) -> (Vec<(usize, usize)>, Vec<f64>) {
    let (x, mu, t) = (&step.x, &step.multipliers, step.load_factor);
    debug_assert!(part != Part::Residual);
    // (the element values, forces and deformations are not needed for the entries: zeros)
    let mut a = Assembled::of_elements(
        Vec::with_capacity(tail_capacity(su)),
        vec![0.0; model.nx],
        vec![0.0; model.nx],
        vec![0.0; model.ne],
        Vec::new(),
        0.0,
        reduced,
    );
    apply_loads(model, su, x, mu, t, part, &mut a);
    a.vals.shrink_to_fit();
    (a.tail, a.vals)
}

/// The parts of an assembly that depend on the load factor t, the multipliers of the
/// normalisations and the prescribed deformations, on top of its element part: external
/// forces and load stiffness, normalisation terms, constraint violations, residual and force
/// scale. Replaces those of an earlier call, so an assembly at the same state can be reused
/// for another t. The load stiffness of moments and the normalisation term 2μ I are
/// load-proportional: they belong to the geometric part, so `Part::Material` writes zeros in
/// their (fixed) matrix positions.
pub(super) fn apply_loads(
    model: &Model,
    su: &Setup,
    x: &[f64],
    mu: &[f64],
    t: f64,
    part: Part,
    a: &mut Assembled,
) {
    let geo = if part == Part::Material { 0.0 } else { 1.0 };
    let (nf, nk) = (su.nf, su.nk);
    let reduced = a.reduced;
    let mut balance = a.int_force.clone();
    let mut f_abs = a.int_abs.clone();
    let mut g = vec![0.0; nk];
    // (room for the entries appended here: `assemble_values` made the buffer with it)
    a.vals.truncate(a.n_el);
    let vals = &mut a.vals;
    // constraint violations of the elements
    for entry in &model.elements {
        for m in 0..entry.element.ne() {
            let i = entry.ie + m;
            let Some(kc) = su.constraint[i].get() else {
                continue;
            };
            let target = match su.roles[i] {
                Role::Input => t * su.e_targets[i],
                _ => 0.0,
            };
            g[kc] = a.e[i] - target;
        }
    }
    // the matrix entries (none for the residual alone), in room made for them
    let entries = part != Part::Residual;
    let mut tail = Vec::with_capacity(if entries { tail_capacity(su) } else { 0 });
    // external dead forces
    for i in 0..model.nx {
        balance[i] -= t * su.f_dead[i];
        f_abs[i] += (t * su.f_dead[i]).abs();
    }
    // moments: f_λ = 2 Λ̄(λ)ᵀ M, load stiffness −∂f/∂λ = −2 A(M)
    for &(r, m) in &su.moments {
        let f1 = moment_forces(x, r, &m);
        for c in 0..4 {
            let f = t * f1[c];
            balance[r + c] -= f;
            f_abs[r + c] += f.abs();
        }
        if !entries {
            continue;
        }
        let am = [
            [0.0, -m[0], -m[1], -m[2]],
            [m[0], 0.0, -m[2], m[1]],
            [m[1], m[2], 0.0, -m[0]],
            [m[2], -m[1], m[0], 0.0],
        ];
        if let (true, Some(k)) = (reduced, su.red.node_at[r].get()) {
            // Nᵀ (−2 t A) N on the node's rotation increments
            let nb = rot_basis(&x[r..r + 4]);
            let d0 = su.red.nodes[k].1;
            for p in 0..3 {
                for q in 0..3 {
                    let mut v = 0.0;
                    for i in 0..4 {
                        for j in 0..4 {
                            v += nb[i][p] * am[i][j] * nb[j][q];
                        }
                    }
                    tail.push((d0 + p, d0 + q));
                    vals.push(-2.0 * t * v * geo);
                }
            }
            continue;
        }
        let idx = |u: usize| {
            if reduced {
                su.red.map[u].get()
            } else {
                Some(u)
            }
        };
        for i in 0..4 {
            let Some(ui) = su.unknown[r + i].get().and_then(idx) else {
                continue;
            };
            for j in 0..4 {
                if let Some(uj) = su.unknown[r + j].get().and_then(idx) {
                    tail.push((ui, uj));
                    vals.push(-2.0 * t * am[i][j] * geo);
                }
            }
        }
    }
    // Euler normalisation constraints λᵀλ − 1 = 0 with multipliers μ_n
    for &(r, kc) in &su.norm {
        let l = &x[r..r + 4];
        g[kc] = l.iter().map(|v| v * v).sum::<f64>() - 1.0;
        for i in 0..4 {
            balance[r + i] += 2.0 * mu[kc] * l[i];
        }
        if !entries {
            continue;
        }
        if let (true, Some(k)) = (reduced, su.red.node_at[r].get()) {
            // Nᵀ (2μ I) N = 2μ I on the rotation increments (N orthonormal)
            let d0 = su.red.nodes[k].1;
            for j in 0..3 {
                tail.push((d0 + j, d0 + j));
                vals.push(2.0 * mu[kc] * geo);
            }
            continue;
        }
        let idx = |u: usize| {
            if reduced {
                su.red.map[u].get()
            } else {
                Some(u)
            }
        };
        let Some(kr) = idx(nf + kc) else {
            continue;
        };
        for i in 0..4 {
            let Some(ui) = su.unknown[r + i].get().and_then(idx) else {
                continue;
            };
            tail.extend([(ui, ui), (kr, ui), (ui, kr)]);
            vals.extend([2.0 * mu[kc] * geo, 2.0 * l[i], 2.0 * l[i]]);
        }
    }
    let mut r = vec![0.0; nf];
    for i in 0..model.nx {
        if let Some(u) = su.unknown[i].get() {
            r[u] = balance[i];
        }
    }
    a.f_scale = f_abs.iter().cloned().fold(0.0, f64::max);
    a.r = r;
    a.g = g;
    // (room was made for 12 entries per rotational node; a reduced node writes 3)
    tail.shrink_to_fit();
    a.tail = tail;
    a.balance = balance;
}

/// The most entries [`apply_loads`] appends after the element entries: 16 per moment and 12
/// per Euler normalisation (fewer in the reduced system).
fn tail_capacity(su: &Setup) -> usize {
    16 * su.moments.len() + 12 * su.norm.len()
}

/// The generalised forces 2 Λ̄(λ)ᵀ M on the Euler parameters (λ0 at x index `r`) of a moment M
/// (global axes) at load factor 1.
pub(super) fn moment_forces(x: &[f64], r: usize, m: &[f64; 3]) -> [f64; 4] {
    let lb = lambda_bar(&[x[r], x[r + 1], x[r + 2], x[r + 3]]);
    std::array::from_fn(|c| 2.0 * (0..3).map(|k| lb[k][c] * m[k]).sum::<f64>())
}

pub(super) fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, a| m.max(a.abs()))
}

/// Project every rotational node's λ back onto the unit sphere, scaling only its free
/// components so that fixed and prescribed components keep their values. Element deformations
/// do not depend on ‖λ‖, so this changes nothing physical; it keeps λᵀλ − 1 = 0 so that the
/// normalisation constraint holds exactly after every update.
pub(super) fn normalise_lambda(su: &Setup, x: &mut [f64]) {
    for &r in &su.lambda {
        let (mut free2, mut fixed2) = (0.0, 0.0);
        for i in r..r + 4 {
            if su.unknown[i].get().is_some() {
                free2 += x[i] * x[i];
            } else {
                fixed2 += x[i] * x[i];
            }
        }
        if free2 > 0.0 && fixed2 < 1.0 {
            let s = ((1.0 - fixed2) / free2).sqrt();
            for i in r..r + 4 {
                if su.unknown[i].get().is_some() {
                    x[i] *= s;
                }
            }
        }
    }
}

/// Set fixed and input coordinates for load factor t.
pub(super) fn apply_prescribed(model: &Model, su: &Setup, x: &mut [f64], t: f64) {
    let x0 = model.x0();
    for &(i, v) in &su.x_targets {
        x[i] = if su.is_lambda[i] {
            (0.5 * t * v).sin()
        } else {
            x0[i] + t * v
        };
    }
}
