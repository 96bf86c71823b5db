//! Stroke sweep (issue 6 item 4): the lowest natural frequencies and the support stiffness of
//! chosen nodes at every load step of a static solution.
//!
//! Once the static solution exists the steps are independent, so they are linearised in
//! parallel (rayon); faer's own parallelism inside a worker nests in the same rayon pool.
//! The values are those of `dynamics::modes` and `linearized::compliance` at the step, from
//! one linearised stage ([`Tangent`]) per step.

use super::dense_size::check_dense_modes;
use super::{eigenvalues_rigid, EigenSolver, ModalError, ModalOptions};
use crate::linearized::{
    check_dense_size as check_linear_size, compliance, Compliance, LinearError, Tangent,
};
use crate::model::Model;
use crate::statics::StepResult;
use rayon::prelude::*;

/// The linearised results of one load step.
#[derive(Clone, Debug)]
pub struct SweepPoint {
    /// Step index (0: unloaded).
    pub step: usize,
    /// Load factor of the step.
    pub load_factor: f64,
    /// ω² [rad²/s²] of the lowest modes, ascending, or why the modal analysis failed here.
    pub eigenvalues: Result<Vec<f64>, ModalError>,
    /// Number of rigid-body modes at the start of `eigenvalues` (as [`crate::dynamics::Mode`]'s
    /// `rigid_body`: judged on the whole spectrum on the dense path, by the inertia on the
    /// sparse one); 0 when the modal analysis failed.
    pub rigid_body: usize,
    /// Compliance of each requested node, or why it is unbounded here.
    pub compliance: Vec<Result<Compliance, LinearError>>,
}

impl SweepPoint {
    /// Frequencies [Hz] (0 for rigid-body modes, [`SweepPoint::rigid_body`]; NaN for ω² < 0:
    /// unstable), if the modal analysis succeeded.
    pub fn frequencies(&self) -> Option<Vec<f64>> {
        let rigid = self.rigid_body;
        self.eigenvalues.as_ref().ok().map(|l| {
            l.iter()
                .enumerate()
                .map(|(k, &l)| {
                    if k < rigid {
                        0.0
                    } else if l >= 0.0 {
                        l.sqrt() / (2.0 * std::f64::consts::PI)
                    } else {
                        f64::NAN
                    }
                })
                .collect()
        })
    }
}

/// Frequencies (lowest `count`) and compliances of `nodes` at every step, in step order, with
/// the eigen solver chosen automatically.
pub fn sweep(
    model: &Model,
    steps: &[StepResult],
    count: usize,
    nodes: &[usize],
) -> Vec<SweepPoint> {
    sweep_with(model, steps, count, nodes, &ModalOptions::default())
}

/// [`sweep`] with the settings of the modal analysis (the eigen solver and the memory limit of
/// the dense paths). The dense linearisation of statics is built only for the compliance of
/// `nodes` and for the dense eigen path; when either would exceed the memory limit, every step
/// reports that error ([`ModalError::TooLarge`], [`LinearError::TooLarge`]) instead.
pub fn sweep_with(
    model: &Model,
    steps: &[StepResult],
    count: usize,
    nodes: &[usize],
    opts: &ModalOptions,
) -> Vec<SweepPoint> {
    let solver = opts.resolve(model, count);
    // the size guards of the dense paths, before any step allocates
    let dense_modes = solver == EigenSolver::Dense && count > 0;
    let modal_size = match dense_modes {
        true => check_dense_modes(model, count, opts),
        false => Ok(()),
    };
    let linear_size = match nodes.is_empty() {
        true => Ok(()),
        false => check_linear_size(model, opts.max_dense_bytes),
    };
    steps
        .par_iter()
        .enumerate()
        .map(|(k, st)| {
            // one stage per step: its dense K_m, K_g, G are built once, for the compliance and
            // the dense eigen path alike
            let t = Tangent::new(model, st);
            // the eigenvalues with the number of rigid-body modes among them
            let modal = if count == 0 {
                Ok((Vec::new(), 0))
            } else if dense_modes && modal_size.is_err() {
                modal_size.clone().map(|_| (Vec::new(), 0))
            } else {
                eigenvalues_rigid(&t, count, opts)
            };
            let rigid_body = modal.as_ref().map_or(0, |m| m.1);
            let eigenvalues = modal.map(|m| m.0);
            let compliance = match &linear_size {
                Err(e) => nodes.iter().map(|_| Err(e.clone())).collect(),
                Ok(()) => nodes.iter().map(|&n| compliance(&t, n)).collect(),
            };
            SweepPoint {
                step: k,
                load_factor: st.load_factor,
                eigenvalues,
                rigid_body,
                compliance,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::modes;
    use crate::model::ModelBuilder;
    use crate::section::BeamProps;
    use crate::statics::{solve, StaticOptions};

    #[test]
    fn sweep_equals_modes_and_compliance_at_every_step() {
        // a cantilever with a tip mass under a growing compressive and lateral tip load
        let mut b = ModelBuilder::new("c");
        let props = BeamProps {
            ea: 1e6,
            gj: 1.0,
            eiy: 1.0,
            eiz: 2.0,
            rho_a: 0.1,
            rho_i: [1e-6, 5e-7, 5e-7],
            ..Default::default()
        };
        b.add_beam_chain(
            "",
            [0.0; 3],
            [0.1, 0.0, 0.0],
            4,
            Some([0.0, 0.0, 1.0]),
            Some(props),
        )
        .unwrap();
        b.fix("n0", None).unwrap();
        b.add_point_mass("n4", 0.02).unwrap();
        b.add_load("n4", [-100.0, 0.0, 5.0], [0.0; 3]).unwrap();
        let model = b.build().unwrap();
        let sol = solve(
            &model,
            &StaticOptions {
                steps: 4,
                ..Default::default()
            },
            |_, _| {},
        )
        .unwrap();
        let tip = model.node_id("n4").unwrap();
        let mid = model.node_id("n2").unwrap();
        let pts = sweep(&model, &sol.steps, 3, &[tip, mid]);
        assert_eq!(pts.len(), 5);
        for (k, (p, st)) in pts.iter().zip(&sol.steps).enumerate() {
            assert_eq!(p.step, k);
            let f = p.frequencies().unwrap();
            let m = modes(&model, st, 3).unwrap();
            for (a, b) in f.iter().zip(&m.modes) {
                assert!(
                    (a - b.frequency).abs() < 1e-10 * b.frequency,
                    "{a} {}",
                    b.frequency
                );
            }
            let lin = Tangent::new(&model, st);
            for (c, &n) in p.compliance.iter().zip(&[tip, mid]) {
                let want = compliance(&lin, n).unwrap().stiffness_global();
                let got = c.as_ref().unwrap().stiffness_global();
                for i in 0..6 {
                    assert!((got[i] - want[i]).abs() <= 1e-10 * want[i].abs());
                }
            }
        }
        // the compression lowers the first frequency along the stroke
        let f0 = pts[0].frequencies().unwrap()[0];
        let f4 = pts[4].frequencies().unwrap()[0];
        assert!(f4 < f0, "{f4} vs {f0}");
    }
}
