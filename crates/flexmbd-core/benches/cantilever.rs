//! Large-deflection cantilever benchmark: N beam elements, tip load k = PL²/EI = 3 in 10 steps.
//! `cargo bench -p flexmbd-core --bench cantilever -- [N ...]`; prints time and accuracy against
//! validation.md S01 (k = 3: u/L = 0.25442, w/L = 0.60325).

use flexmbd_core::model::{ElementSpec, ModelBuilder};
use flexmbd_core::section::BeamProps;
use flexmbd_core::statics::{solve, StaticOptions};
use std::time::Instant;

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
        let mut b = ModelBuilder::new("cantilever");
        for i in 0..=n {
            b.add_node(&format!("n{i}"), [i as f64 / n as f64, 0.0, 0.0], false)
                .unwrap();
        }
        let props = BeamProps {
            ea: 1e7,
            gj: 1.0,
            eiy: 1.0,
            eiz: 1.0,
            ..Default::default()
        };
        for i in 0..n {
            let name = format!("b{i}");
            b.add_element(
                &name,
                &[&format!("n{i}"), &format!("n{}", i + 1)],
                ElementSpec::Beam {
                    orient: Some([0.0, 1.0, 0.0]),
                    ct: 0.0,
                },
                &[],
                &[],
            )
            .unwrap();
            b.set_beam_props(&name, props).unwrap();
        }
        b.fix("n0", None).unwrap();
        b.add_load(&format!("n{n}"), [0.0, -3.0, 0.0], [0.0; 3])
            .unwrap();
        let model = b.build().unwrap();
        let t1 = Instant::now();
        let sol = solve(&model, &StaticOptions::default(), |_, _| {}).unwrap();
        let dt = t1.elapsed().as_secs_f64();
        let last = sol.steps.last().unwrap();
        let tip = model.nodes[n].ix_pos;
        let (u, w) = (1.0 - last.x[tip], -last.x[tip + 1]);
        let iters: usize = sol.steps.iter().map(|s| s.iterations).sum();
        println!(
            "N = {n:6}: build {:.3} s, solve {dt:.3} s, {iters} Newton iterations, u/L err {:.2e}, w/L err {:.2e}",
            (t1 - t0).as_secs_f64(),
            (u - 0.25442).abs(),
            (w - 0.60325).abs()
        );
    }
}
