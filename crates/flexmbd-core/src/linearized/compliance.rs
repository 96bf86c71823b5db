//! Support compliance of a node (theory.md §13.4): the response of its translation and
//! rotation to unit forces and moments on it, from [K_m + K_g, Gᵀ; G, 0]; rotations are
//! ω = 2 Λ̄ dλ. SPACAR's C = DX (K0 + G0)⁻¹ DXᵀ.

use super::Tangent;
use crate::math::{lambda_bar, rotate};
use crate::statics::linear::{Compliance, LinearError};
use faer::Mat;

/// Compliance of `node` at the linearised state (inputs and supports held).
pub fn compliance(t: &Tangent, node: usize) -> Result<Compliance, LinearError> {
    let (model, step, lin) = (t.model(), t.step(), t.dense());
    let (nf, nk) = (lin.km.nrows(), lin.g.nrows());
    let n = nf + nk;
    let kkt = Mat::from_fn(n, n, |i, j| match (i < nf, j < nf) {
        (true, true) => lin.km[(i, j)] + lin.kg[(i, j)],
        (false, true) => lin.g[(i - nf, j)],
        (true, false) => lin.g[(j - nf, i)],
        (false, false) => 0.0,
    });
    let nd = &model.nodes[node];
    let lam = nd
        .ix_rot
        .map(|r| [step.x[r], step.x[r + 1], step.x[r + 2], step.x[r + 3]]);
    let lb = lam.map(|l| lambda_bar(&l));
    // right-hand sides: unit forces and moments
    let mut rhs = Mat::zeros(n, 6);
    for k in 0..3 {
        if let Some(u) = lin.unknown[nd.ix_pos + k] {
            rhs[(u, k)] = 1.0;
        }
        if let (Some(r), Some(lb)) = (nd.ix_rot, lb) {
            for c in 0..4 {
                if let Some(u) = lin.unknown[r + c] {
                    rhs[(u, 3 + k)] = 2.0 * lb[k][c];
                }
            }
        }
    }
    let lu = kkt.partial_piv_lu();
    let sol = faer::prelude::Solve::solve(&lu, &rhs);
    // residual check: a singular system gives garbage or non-finite values
    let res = &kkt * &sol - &rhs;
    let scale = kkt.norm_max() * sol.norm_max() + 1.0;
    if !crate::linalg::all_finite(&sol) || !scale.is_finite() || res.norm_max() > 1e-6 * scale {
        return Err(LinearError::Singular {
            load_factor: step.load_factor,
        });
    }
    let mut c = [[0.0; 6]; 6];
    for k in 0..6 {
        let dx = |i: usize| lin.unknown[i].map_or(0.0, |u| sol[(u, k)]);
        for j in 0..3 {
            c[j][k] = dx(nd.ix_pos + j);
        }
        if let (Some(r), Some(lb)) = (nd.ix_rot, lb) {
            for j in 0..3 {
                c[3 + j][k] = 2.0 * (0..4).map(|cc| lb[j][cc] * dx(r + cc)).sum::<f64>();
            }
        }
    }
    // local axes: v_loc = Rᵀ v_glob, R the node's rotation (columns: images of global axes)
    let rt: [[f64; 3]; 3] = match lam {
        Some(l) => {
            let cols = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(|e| rotate(&l, e));
            std::array::from_fn(|i| cols[i]) // row i of Rᵀ = column i of R
        }
        None => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };
    let t = |i: usize, j: usize| {
        if i / 3 == j / 3 {
            rt[i % 3][j % 3]
        } else {
            0.0
        }
    };
    let mut local = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            let mut v = 0.0;
            for a in 0..6 {
                for b in 0..6 {
                    v += t(i, a) * c[a][b] * t(j, b);
                }
            }
            local[i][j] = v;
        }
    }
    let held = std::array::from_fn(|k| {
        let dof = crate::model::Dof::ALL[k];
        nd.x_index(dof).is_none_or(|i| lin.unknown[i].is_none())
    });
    Ok(Compliance {
        global: c,
        local,
        held,
    })
}
