//! Mode classes (paper §5; docs/dynamics.md "Mode classes"): every elastic mode is *intended*
//! (the bodies move along the motions the kinematic analysis releases), *support* (the bodies
//! move in directions the design constrains: parasitic, they limit the closed-loop bandwidth)
//! or *internal* (the flexures move while the bodies stay nearly still), decided by two
//! energy fractions of the mass-normalised mode Φ at the state (docs/notation.md):
//!
//! ```text
//! β = Φᵀ M_bodies Φ / Φᵀ M Φ                       body fraction
//! ρ = Σ_{i ∈ e^c ∪ e^m} ½ σᵢ δeᵢ / Σᵢ ½ σᵢ δeᵢ       released fraction, σ = S δe, δe = D Φ
//! ```
//!
//! M = M_bodies + M_elements exactly (the point masses and inertia tensors on nodes, and the
//! elements' own distributed mass, `assembly::mass`), so β is a split of one sum; the strain
//! energy of the material stiffness K_m = Dᵀ S D is split over the element deformations, the
//! released ones being those the kinematic analysis leaves free (`free`, e^c, and `input`,
//! e^m, of each element) and the rest (e^o) those the design makes rigid. Element by element,
//! O(nnz) per mode; the same for the dense and the sparse eigen path.

use crate::model::{DefKind, Model};

/// Below this body fraction β a mode is *internal*: less than half of its kinetic energy is in
/// the bodies (point masses and inertias), so it is a vibration of the flexures themselves.
pub const INTERNAL_BELOW: f64 = 0.5;

/// From this released fraction ρ a mode of the bodies (β ≥ [`INTERNAL_BELOW`]) is *intended*:
/// at least half of its elastic energy is in the deformations the kinematic analysis releases;
/// below it, most of it deforms what the design constrains, and the mode is *support*.
pub const INTENDED_FROM: f64 = 0.5;

/// The class of a mode (paper §5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModeClass {
    /// The bodies move along the released deformations: the motion the design intends.
    Intended,
    /// The bodies move and deform what the design constrains (parasitic, support stiffness).
    Support,
    /// The flexures move, the bodies hardly.
    Internal,
    /// A rigid-body mode ([`super::Mode::rigid_body`]): no strain energy to split.
    RigidBody,
}

impl ModeClass {
    /// The name in reports: `intended`, `support`, `internal`, `rigid_body`.
    pub fn name(self) -> &'static str {
        match self {
            ModeClass::Intended => "intended",
            ModeClass::Support => "support",
            ModeClass::Internal => "internal",
            ModeClass::RigidBody => "rigid_body",
        }
    }

    /// The class from the fractions: rigid body, else internal when β < [`INTERNAL_BELOW`],
    /// else intended when ρ ≥ [`INTENDED_FROM`], else support. A mode without material strain
    /// energy (ρ undefined: its stiffness is all pre-stress) deforms nothing the design makes
    /// rigid and counts as intended when its bodies move.
    pub fn of(fractions: &ClassFractions, rigid_body: bool) -> ModeClass {
        if rigid_body {
            ModeClass::RigidBody
        } else if fractions.body < INTERNAL_BELOW {
            ModeClass::Internal
        } else if fractions.released.is_none_or(|r| r >= INTENDED_FROM) {
            ModeClass::Intended
        } else {
            ModeClass::Support
        }
    }
}

/// The parts of a mode's energies that decide its class, and the fractions from them.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ClassFractions {
    /// β = `kinetic_bodies` / (`kinetic_bodies` + `kinetic_elements`), in [0, 1].
    pub body: f64,
    /// ρ = `strain_released` / (`strain_released` + `strain_stiff`), clamped to [0, 1]; `None`
    /// for a rigid-body mode and for a mode without material strain energy.
    pub released: Option<f64>,
    /// Φᵀ M_bodies Φ: the point masses and inertia tensors on nodes.
    pub kinetic_bodies: f64,
    /// Φᵀ M_elements Φ: the elements' own mass.
    pub kinetic_elements: f64,
    /// ½ Σ σᵢ δeᵢ over the released deformations (e^c, e^m).
    pub strain_released: f64,
    /// ½ Σ σᵢ δeᵢ over the other deformations (e^o).
    pub strain_stiff: f64,
}

/// A total strain energy at most this fraction of ½ |ω²| (the energy of a mass-normalised mode
/// whose stiffness is all material) counts as none: ρ is then undefined.
const NO_STRAIN: f64 = 1e-12;

/// The fractions of every mode: `shapes` the mass-normalised modes in x, `eigenvalues` their ω²,
/// `strain` per element the energies ½ σᵢ δeᵢ of every deformation, mode k's at k ne … (k+1) ne
/// (as `describe_all` computes them once for the energy split).
pub(super) fn fractions(
    model: &Model,
    x: &[f64],
    eigenvalues: &[f64],
    shapes: &[Vec<f64>],
    strain: &[Vec<f64>],
) -> Vec<ClassFractions> {
    let nm = shapes.len();
    let mut out = vec![ClassFractions::default(); nm];
    // kinetic: the elements' mass matrices once each, every mode through them
    crate::assembly::mass::for_each_element(model, x, None, true, |entry, me| {
        let n = entry.xmap.len();
        for (f, v) in out.iter_mut().zip(shapes) {
            let mut q = 0.0;
            for (r, gr) in entry.x_indices().enumerate() {
                let mv: f64 = entry
                    .x_indices()
                    .enumerate()
                    .map(|(c, gc)| me[r * n + c] * v[gc])
                    .sum();
                q += v[gr] * mv;
            }
            f.kinetic_elements += q;
        }
    });
    crate::assembly::mass::for_each_node_mass(model, x, true, |nm| {
        for (f, v) in out.iter_mut().zip(shapes) {
            f.kinetic_bodies += nm.quadratic_form(v);
        }
    });
    // strain: the released deformations of each element by the partition of e
    for (entry, u) in model.elements.iter().zip(strain) {
        let ne = u.len().checked_div(nm).unwrap_or(0);
        for (k, f) in out.iter_mut().enumerate() {
            for (a, &ua) in u[k * ne..(k + 1) * ne].iter().enumerate() {
                match model.partition.e.get(entry.ie + a) {
                    Some(DefKind::Free | DefKind::Input) => f.strain_released += ua,
                    _ => f.strain_stiff += ua,
                }
            }
        }
    }
    for (f, &lambda) in out.iter_mut().zip(eigenvalues) {
        let t = f.kinetic_bodies + f.kinetic_elements;
        f.body = if t > 0.0 {
            (f.kinetic_bodies / t).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let u = f.strain_released + f.strain_stiff;
        f.released = (u > NO_STRAIN * 0.5 * lambda.abs() && u > 0.0)
            .then(|| (f.strain_released / u).clamp(0.0, 1.0));
    }
    out
}
