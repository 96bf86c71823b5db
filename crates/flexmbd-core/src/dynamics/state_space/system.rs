//! The state-space model ([`StateSpace`]) and its evaluation: static gain, frequency response,
//! the default frequency band and Bode magnitude and phase.

use super::{Input, Output};
use super::{InputInfo, Motion, OutputKind, StateSpaceError};
use crate::dynamics::EigenSolver;
use crate::model::Model;
use faer::{c64, Mat};

/// A state-space model in modal coordinates with named inputs and outputs.
#[derive(Clone, Debug)]
pub struct StateSpace {
    /// A (2n × 2n), state (η₁..ηₙ, η̇₁..η̇ₙ).
    pub a: Mat<f64>,
    /// B (2n × inputs).
    pub b: Mat<f64>,
    /// C (outputs × 2n).
    pub c: Mat<f64>,
    /// D (outputs × inputs).
    pub d: Mat<f64>,
    /// Inputs, in the order of the columns of B and D.
    pub inputs: Vec<Input>,
    /// Prescribed-motion inputs: the columns after those of `inputs` (input = ü [m/s²]);
    /// each adds the states (u, u̇) after the modal ones.
    pub motions: Vec<Motion>,
    /// Outputs, in the order of the rows of C and D.
    pub outputs: Vec<Output>,
    /// ω² [rad²/s²] of the kept modes, ascending (the eigenvalues of `modes`).
    pub eigenvalues: Vec<f64>,
    /// Modal damping ratio ζ.
    pub damping: f64,
    /// Number of minimal coordinates.
    pub ndof: usize,
    /// Number of massless directions condensed out (not states).
    pub massless: usize,
    /// Number of modes that carry mass (the most that can be kept).
    pub available_modes: usize,
    /// Whether D carries the residual flexibility of the dropped modes.
    pub static_correction: bool,
    /// Notes for the user (inputs on held directions, outputs that miss an instantaneous part).
    pub warnings: Vec<String>,
    /// The eigen solver used: `Dense` (all modes) or `Sparse` (the lowest, by Lanczos).
    pub solver: EigenSolver,
    /// Quasi-static gain g = Cx ψ + w·t_m of the value outputs per unit enforced displacement
    /// (outputs × motions).
    pub(super) motion_gain: Mat<f64>,
}

impl StateSpace {
    /// Number of kept modes (the state has twice as many entries).
    pub fn n_modes(&self) -> usize {
        self.eigenvalues.len()
    }

    /// Frequencies of the kept modes [Hz] (NaN for ω² < 0).
    pub fn frequencies(&self) -> Vec<f64> {
        self.eigenvalues
            .iter()
            .map(|&l| {
                if l >= 0.0 {
                    l.sqrt() / (2.0 * std::f64::consts::PI)
                } else {
                    f64::NAN
                }
            })
            .collect()
    }

    /// Number of input columns (forces and moments, then motions).
    pub fn n_inputs(&self) -> usize {
        self.inputs.len() + self.motions.len()
    }

    /// Number of states: 2 per kept mode, 2 per motion input.
    pub fn n_states(&self) -> usize {
        self.a.nrows()
    }

    /// State names: `eta_k`, `deta_k`, then `u_j`, `du_j` (enforced displacement and velocity
    /// of input column j, 1-based).
    pub fn state_names(&self) -> Vec<String> {
        let n = self.n_modes();
        let nf = self.inputs.len();
        (1..=n)
            .map(|k| format!("eta_{k}"))
            .chain((1..=n).map(|k| format!("deta_{k}")))
            .chain(
                (0..self.motions.len())
                    .flat_map(|j| [format!("u_{}", nf + j + 1), format!("du_{}", nf + j + 1)]),
            )
            .collect()
    }

    /// Descriptions of the input columns, in order (forces and moments, then motions).
    pub fn input_info(&self, model: &Model) -> Vec<InputInfo> {
        self.inputs
            .iter()
            .map(|i| InputInfo {
                name: i.name(model),
                node: Some(i.node),
                dof: Some(i.dof),
                deformation: None,
                kind: i.kind_name(),
                unit: i.unit(),
                description: i.describe(model),
            })
            .chain(self.motions.iter().map(|m| {
                let (node, dof, deformation) = match *m {
                    Motion::Node { node, dof } => (Some(node), Some(dof), None),
                    Motion::Deformation { element, mode } => (None, None, Some((element, mode))),
                };
                InputInfo {
                    name: m.name(model),
                    node,
                    dof,
                    deformation,
                    kind: m.kind_name(),
                    unit: m.unit(model),
                    description: m.describe(model),
                }
            }))
            .collect()
    }

    /// Quasi-static response of the outputs per unit enforced displacement of each motion
    /// input (outputs × motions): Cx ψ + w·t_m for displacement outputs, 0 for velocity and
    /// acceleration outputs. For a slow enforced displacement u the outputs are this times u.
    pub fn motion_static_gain(&self) -> Mat<f64> {
        Mat::from_fn(self.outputs.len(), self.motions.len(), |o, j| {
            if self.outputs[o].kind == OutputKind::Disp {
                self.motion_gain[(o, j)]
            } else {
                0.0
            }
        })
    }

    /// Static (DC) gain (outputs × inputs). Force and moment columns: −C A⁻¹ B + D from a
    /// dense LU of the modal block of A. Motion columns (whose input ü would give an unbounded
    /// displacement): the static response per unit enforced displacement,
    /// [`StateSpace::motion_static_gain`].
    pub fn dc_gain(&self) -> Result<Mat<f64>, StateSpaceError> {
        let ns = 2 * self.n_modes();
        let am = Mat::from_fn(ns, ns, |i, j| self.a[(i, j)]);
        let bm = Mat::from_fn(ns, self.b.ncols(), |i, j| self.b[(i, j)]);
        let cm = Mat::from_fn(self.c.nrows(), ns, |i, j| self.c[(i, j)]);
        let amax = am.norm_max();
        if self
            .eigenvalues
            .iter()
            .any(|l| l.abs() <= 1e-12 * amax.max(1.0))
        {
            return Err(StateSpaceError::Singular);
        }
        let lu = am.partial_piv_lu();
        let sol = faer::prelude::Solve::solve(&lu, &bm);
        let res = &am * &sol - &bm;
        if !crate::linalg::all_finite(&sol)
            || res.norm_max() > 1e-8 * (amax * sol.norm_max() + bm.norm_max())
        {
            return Err(StateSpaceError::Singular);
        }
        let mut g = &self.d - &cm * &sol;
        let nf = self.inputs.len();
        let ms = self.motion_static_gain();
        for o in 0..self.outputs.len() {
            for j in 0..self.motions.len() {
                g[(o, nf + j)] = ms[(o, j)];
            }
        }
        Ok(g)
    }

    /// Frequency response G(i2πf) = C (i2πf I − A)⁻¹ B + D (outputs × inputs), evaluated
    /// block by block, as A is block diagonal: a mode's block gives η = b/(s² + 2ζωs + ω²) and
    /// η̇ = s η per unit of its B row, a motion's double integrator u = ü/s², u̇ = ü/s.
    pub fn frequency_response(&self, f_hz: f64) -> Vec<Vec<c64>> {
        let s = c64::new(0.0, 2.0 * std::f64::consts::PI * f_hz);
        let n = self.n_modes();
        let den: Vec<c64> = (0..n)
            .map(|k| {
                let w = self.eigenvalues[k].abs().sqrt();
                s * s + s * (2.0 * self.damping * w) + self.eigenvalues[k]
            })
            .collect();
        let nf = self.inputs.len();
        (0..self.outputs.len())
            .map(|o| {
                (0..self.n_inputs())
                    .map(|j| {
                        let mut g = c64::new(self.d[(o, j)], 0.0);
                        for k in 0..n {
                            let bk = self.b[(n + k, j)];
                            if bk != 0.0 {
                                g += (s * self.c[(o, n + k)] + self.c[(o, k)]) * bk / den[k];
                            }
                        }
                        if j >= nf {
                            // the motion's own states (u, u̇)
                            let m = 2 * n + 2 * (j - nf);
                            g += (s * self.c[(o, m + 1)] + self.c[(o, m)]) / (s * s);
                        }
                        g
                    })
                    .collect()
            })
            .collect()
    }

    /// `count` log-spaced frequencies [Hz] from 0.1 × the lowest positive to 10 × the highest
    /// kept frequency (None when no kept mode has a positive frequency).
    pub fn default_band(&self, count: usize) -> Option<Vec<f64>> {
        let f: Vec<f64> = self
            .frequencies()
            .into_iter()
            .filter(|f| f.is_finite() && *f > 0.0)
            .collect();
        let lo = f.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = f.iter().copied().fold(0.0f64, f64::max);
        if f.is_empty() {
            return None;
        }
        Some(log_space(0.1 * lo, 10.0 * hi, count))
    }
}

/// A dense matrix as a vector of rows (row-major), for reports.
pub fn to_rows(m: &Mat<f64>) -> Vec<Vec<f64>> {
    (0..m.nrows())
        .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect())
        .collect()
}

/// `count` log-spaced values from `lo` to `hi` (both included; `lo` alone for count 1).
pub fn log_space(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if count <= 1 {
        return vec![lo; count];
    }
    let (a, b) = (lo.ln(), hi.ln());
    (0..count)
        .map(|i| (a + (b - a) * i as f64 / (count - 1) as f64).exp())
        .collect()
}

/// Bode magnitude (absolute, output units per input unit) and phase [deg] of a response
/// sequence, the phase unwrapped along the sequence (continuous, starting in (−180, 180]).
pub fn magnitude_phase(g: &[c64]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(g.len());
    let mut prev: Option<f64> = None;
    for z in g {
        let mut p = z.arg().to_degrees();
        if let Some(q) = prev {
            p += 360.0 * ((q - p) / 360.0).round();
        }
        prev = Some(p);
        out.push((z.norm(), p));
    }
    out
}
