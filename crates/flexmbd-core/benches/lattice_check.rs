//! The kinematic analysis in process (issue 14): `cargo bench -p flexmbd-core --bench
//! lattice_check -- [K ...] [--strip N ...]`. Per lattice of K × K × K cube cells of rigid
//! trusses (the kinematics tests' `lattice`, the model `bench/lattice_model.py` writes) and per
//! strip of N rigid beams (a square, regular 6 N × 6 N Dcc): the size of Dcc, the counts, and the
//! times of the model build, `check` (Dcc, SVD, motions, self-stresses) and `advise` (six
//! verified suggestions per state, the CLI's default). Defaults: K = 2 3 4 6, N = 333
//! (1998 × 1998).

use flexmbd_core::kinematics::advice::advise;
use flexmbd_core::kinematics::{check, CheckOptions};
use std::time::Instant;

/// The bench's view of the core crate for the shared test models (they name `crate::model`).
mod model {
    pub use flexmbd_core::model::*;
}
#[allow(dead_code)]
#[path = "../src/kinematics/test_models.rs"]
mod test_models;

fn run(name: &str, build: impl FnOnce() -> flexmbd_core::Model) {
    let t0 = Instant::now();
    let m = build();
    let t1 = Instant::now();
    let x = m.x0();
    let opts = CheckOptions::default();
    let a = check(&m, &m.partition, &x, &opts).expect("check");
    let t2 = Instant::now();
    let adv = advise(&m, &m.partition, &x, &a, &opts, 6).expect("advice");
    let t3 = Instant::now();
    let shown: usize = adv.iter().map(|s| s.suggestions.len()).sum();
    println!(
        "{name}: Dcc {} x {}, rank {}, {} motions, {} self-stresses, {shown} verified suggestions; \
         build {:.4} s, check {:.4} s, advice {:.4} s, check + advice {:.4} s",
        a.m(),
        a.n(),
        a.rank,
        a.n_motions(),
        a.n_self_stresses(),
        (t1 - t0).as_secs_f64(),
        (t2 - t1).as_secs_f64(),
        (t3 - t2).as_secs_f64(),
        (t3 - t1).as_secs_f64(),
    );
}

fn main() {
    let mut ks = Vec::new();
    let mut strips = Vec::new();
    let mut into_strips = false;
    for a in std::env::args().skip(1) {
        if a == "--strip" {
            into_strips = true;
        } else if let Ok(v) = a.parse::<usize>() {
            if into_strips {
                strips.push(v)
            } else {
                ks.push(v)
            }
        }
    }
    if ks.is_empty() && strips.is_empty() {
        ks = vec![2, 3, 4, 6];
        strips = vec![333];
    }
    for k in ks {
        run(&format!("lattice k = {k}"), || test_models::lattice(k));
    }
    for n in strips {
        run(&format!("strip N = {n}"), || {
            test_models::strip(n, &[], &[])
        });
    }
}
