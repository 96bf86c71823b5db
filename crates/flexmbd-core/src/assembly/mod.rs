//! Assembly: gather element coordinates x_k from x, evaluate the elements, scatter e_k and
//! D_k = ∂e_k/∂x_k into the global e and D (paper eq. (3): e = 𝒟(x)).

pub mod loads;
pub mod mass;

use crate::elements::ElementKind;
use crate::model::{ElementEntry, Model};
use faer::Mat;

/// Element coordinates x_k gathered from the global x.
pub fn gather(entry: &ElementEntry, x: &[f64]) -> Vec<f64> {
    entry.xmap.iter().map(|&i| x[i]).collect()
}

/// Deformations and first derivatives of the whole model at x.
#[derive(Clone, Debug)]
pub struct Evaluation {
    /// e = 𝒟(x)  (ne).
    pub e: Vec<f64>,
    /// D = ∂e/∂x  (ne × nx), SPACAR `bigd`.
    pub D: Mat<f64>,
}

/// Evaluate e and D at x (dense; the kinematic analysis needs Dcc dense for its SVD).
pub fn evaluate(model: &Model, x: &[f64]) -> Evaluation {
    assert_eq!(x.len(), model.nx, "x has the wrong length");
    let mut e = vec![0.0; model.ne];
    let mut D = Mat::zeros(model.ne, model.nx);
    for entry in &model.elements {
        // gather element coordinates x_k from x
        let xk = gather(entry, x);
        // deformations and first-order derivatives
        let ek = entry.element.deformations(&xk);
        let dk = entry.element.jacobian(&xk);
        // scatter into global e and D
        e[entry.ie..entry.ie + ek.len()].copy_from_slice(&ek);
        for (r, _) in ek.iter().enumerate() {
            for (c, &col) in entry.xmap.iter().enumerate() {
                D[(entry.ie + r, col)] += dk[(r, c)];
            }
        }
    }
    Evaluation { e, D }
}
