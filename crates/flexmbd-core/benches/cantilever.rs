//! Large-deflection cantilever benchmark: N beam elements, tip load k = PL²/EI = 3 in 10 steps.
//! `cargo bench -p flexmbd-core --bench cantilever -- [N ...]`; prints, per N, the build and
//! solve times, the Newton iterations (all steps), the sub-steps of the load steps (10 without
//! step halving), and the computed tip values u/L, w/L and the tip rotation φ [rad] at full
//! precision (the shortest decimals that read back exactly), followed by their errors against
//! the exact inextensible elastica at k = 3 (u/L = 0.254420185, w/L = 0.603253441,
//! φ = 0.986016947; validation.md S01 rounds them to 5 decimals). `bench/report.py` reads the
//! values from that line.

use flexmbd_core::math::rotate;
use flexmbd_core::statics::{solve, StaticOptions};
use std::time::Instant;
// `crate::model` and `crate::section` of the shared statics test models
use flexmbd_core::{model, section};

#[path = "../src/statics/test_models.rs"]
mod test_models;

/// Exact inextensible elastica at k = 3 (shooting; peercommon.elastica(3), bench/README.md):
/// u/L, w/L, φ.
const ELASTICA_K3: [f64; 3] = [0.254420185, 0.603253441, 0.986016947];

fn main() {
    let ns: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|a| a.parse().ok())
        .collect();
    let ns = if ns.is_empty() {
        vec![10, 100, 1000, 10000]
    } else {
        ns
    };
    for n in ns {
        let t0 = Instant::now();
        let model = test_models::column(n, 1.0, [0.0, -3.0, 0.0])
            .build()
            .unwrap();
        let t1 = Instant::now();
        let sol = solve(&model, &StaticOptions::default(), |_, _| {}).unwrap();
        let dt = t1.elapsed().as_secs_f64();
        let last = sol.steps.last().unwrap();
        let tip = &model.nodes[n];
        let (u, w) = (1.0 - last.x[tip.ix_pos], -last.x[tip.ix_pos + 1]);
        // tip rotation: the turn of the beam axis x in the x-y plane (load along −y)
        let r = tip.ix_rot.unwrap();
        let axis = rotate(
            &[last.x[r], last.x[r + 1], last.x[r + 2], last.x[r + 3]],
            [1.0, 0.0, 0.0],
        );
        let phi = (-axis[1]).atan2(axis[0]);
        let iters: usize = sol.steps.iter().map(|s| s.iterations).sum();
        // sub-steps of the load steps (10 when no step was halved)
        let substeps: usize = sol.steps[1..].iter().map(|s| s.substeps).sum();
        let err: Vec<f64> = [u, w, phi]
            .iter()
            .zip(ELASTICA_K3)
            .map(|(v, e)| (v - e).abs())
            .collect();
        println!(
            "N = {n:6}: build {:.3} s, solve {dt:.3} s, {iters} Newton iterations, {substeps} substeps, \
             u/L {u}, w/L {w}, phi {phi} (errors against the exact elastica: {:.2e}, {:.2e}, {:.2e})",
            (t1 - t0).as_secs_f64(),
            err[0],
            err[1],
            err[2]
        );
    }
}
