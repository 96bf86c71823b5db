//! Strip eigenfrequency benchmark (issue 6): the peers' clamped steel strip (bench/README.md,
//! the peer kit's peercommon.py) with N Euler–Bernoulli beam elements, the lowest modes.
//!
//! `cargo bench -p flexmbd-core --bench strip_modes -- [N ...] [--modes M] [--solver S]`
//! (defaults: N = 10 100 1000 10000, M = 10, S = auto). Prints one JSON record per N in the
//! peers' format (peer "flexmbd", problem "strip_modes"): build and solve times, the
//! frequencies, each mode's type (from its shape) and its relative error against the analytic
//! value of its family (Euler–Bernoulli bending, St-Venant torsion, as peercommon.py).
//!
//! Strip: L = 50 mm along x, width b = 20 mm along y (the beams' orientation vector),
//! thickness t = 0.2 mm along z, E = 210 GPa, ν = 0.3, ρ = 7800 kg/m³, clamped at x = 0.
//! Times: `build` = ModelBuilder + build; `solve` = the static state (unloaded, one step) +
//! the modal analysis with its energy split, as `flexmbd modes` computes it. Before timing, the
//! thread pool and faer are started ([`warm_up`], as the peers import their libraries first;
//! `--cold` skips it).

use flexmbd_core::dynamics::{modes_with, EigenSolver, ModalOptions, Mode};
use flexmbd_core::model::ModelBuilder;
use flexmbd_core::section::{BeamProps, Material, Shape};
use flexmbd_core::statics::{solve, StaticOptions};
use std::time::Instant;

const L: f64 = 0.050;
const B: f64 = 0.020;
const T: f64 = 0.2e-3;
const E: f64 = 210e9;
const NU: f64 = 0.3;
const RHO: f64 = 7800.0;
/// Euler–Bernoulli clamped–free roots βₙL (peercommon.BETA_L).
const BETA_L: [f64; 6] = [
    1.875104068711961,
    4.694091132974175,
    7.854757438237613,
    10.995540734875467,
    14.13716839104647,
    17.278759532088237,
];

/// Analytic frequencies [Hz] of the families (peercommon.py): bending about y (out of plane,
/// along z), St-Venant torsion (J = b t³/3 (1 − 0.63 t/b), polar mass ρ(Iy + Iz)), in-plane
/// bending, axial.
fn references(family: &str) -> Vec<f64> {
    let a = B * T;
    let (iyy, izz) = (B * T.powi(3) / 12.0, T * B.powi(3) / 12.0);
    let g = E / (2.0 * (1.0 + NU));
    let j = B * T.powi(3) / 3.0 * (1.0 - 0.630 * T / B);
    let two_pi = 2.0 * std::f64::consts::PI;
    let bending = |ei: f64| -> Vec<f64> {
        BETA_L
            .iter()
            .map(|bl| bl * bl / (two_pi * L * L) * (ei / (RHO * a)).sqrt())
            .collect()
    };
    match family {
        "bend(z)" => bending(E * iyy),
        "inplane(y)" => bending(E * izz),
        "torsion(rx)" => (1..=6)
            .map(|k| (2 * k - 1) as f64 / (4.0 * L) * (g * j / (RHO * (iyy + izz))).sqrt())
            .collect(),
        _ => (1..=3)
            .map(|k| (2 * k - 1) as f64 / (4.0 * L) * (E / RHO).sqrt())
            .collect(),
    }
}

/// The family that carries most of the mode: translations x, y, z and the rotation about x
/// times the width (as the OpenSeesPy peer classifies).
fn family(m: &Mode) -> &'static str {
    let mut s = [0.0; 4];
    for (u, w) in &m.nodal {
        s[0] += u[0] * u[0];
        s[1] += u[1] * u[1];
        s[2] += u[2] * u[2];
        s[3] += (w[0] * B).powi(2);
    }
    let names = ["axial(x)", "inplane(y)", "bend(z)", "torsion(rx)"];
    let k = (0..4).fold(0, |best, i| if s[i] > s[best] { i } else { best });
    names[k]
}

/// Start the libraries before any timing, as the peer scripts import numpy, scipy and their
/// program before theirs: the thread pool (rayon) and faer's dense kernels (a 32 × 32
/// symmetric eigenproblem, a product), whose first call costs about 1.3 ms, mostly for loading
/// their code. `--cold` skips this. flexmbd's own code is not run.
fn warm_up() {
    use rayon::prelude::*;
    let s: f64 = (0..64).into_par_iter().map(|i| i as f64).sum();
    let a = faer::Mat::<f64>::from_fn(32, 32, |i, j| 1.0 / (1.0 + i as f64 + j as f64));
    let e = flexmbd_core::linalg::sym_eigen_seq(a.as_ref()).map(|e| e.0[0]);
    let b = &a * &a;
    std::hint::black_box((s, e.ok(), b[(0, 0)]));
}

fn json_list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| format!("{x:.10}")).collect();
    format!("[{}]", items.join(", "))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut ns = Vec::new();
    let mut count = 10;
    let mut solver = EigenSolver::Auto;
    let mut i = 0;
    while i < args.len() {
        match args[i].as_str() {
            "--modes" => {
                count = args
                    .get(i + 1)
                    .and_then(|a| a.parse().ok())
                    .unwrap_or(count);
                i += 1;
            }
            "--solver" => {
                solver = match args.get(i + 1).map(String::as_str) {
                    Some("dense") => EigenSolver::Dense,
                    Some("sparse") => EigenSolver::Sparse,
                    _ => EigenSolver::Auto,
                };
                i += 1;
            }
            a => {
                if let Ok(n) = a.parse::<usize>() {
                    ns.push(n);
                }
            }
        }
        i += 1;
    }
    if ns.is_empty() {
        ns = vec![10, 100, 1000, 10000];
    }
    let steel = Material {
        e: E,
        g: E / (2.0 * (1.0 + NU)),
        rho: RHO,
    };
    let props = BeamProps::from_section(&steel, &Shape::Rectangle { w: B, t: T }, true);
    if !args.iter().any(|a| a == "--cold") {
        warm_up();
    }
    for n in ns {
        let t0 = Instant::now();
        let mut b = ModelBuilder::new("strip");
        b.add_beam_chain(
            "",
            [0.0; 3],
            [L, 0.0, 0.0],
            n,
            Some([0.0, 1.0, 0.0]),
            Some(props),
        )
        .expect("valid strip");
        b.fix("n0", None).expect("node n0 exists");
        let model = b.build().expect("valid strip");
        let t1 = Instant::now();
        let opts = StaticOptions {
            steps: 1,
            ..Default::default()
        };
        let result = solve(&model, &opts, |_, _| {})
            .map_err(|e| e.to_string())
            .and_then(|sol| {
                let step = sol.steps.last().expect("a step");
                modes_with(&model, step, count, &ModalOptions::with_solver(solver))
                    .map_err(|e| e.to_string())
            });
        let t2 = Instant::now();
        let (t_build, t_solve) = ((t1 - t0).as_secs_f64(), (t2 - t1).as_secs_f64());
        let modal = match result {
            Ok(m) => m,
            Err(e) => {
                println!(
                    "{{\"peer\": \"flexmbd\", \"problem\": \"strip_modes\", \"n_elements\": {n}, \"status\": \"failed\", \"wall_s\": null, \"error\": {:?}}}",
                    e
                );
                continue;
            }
        };
        let mut seen = std::collections::HashMap::new();
        let (mut freqs, mut types, mut refs, mut rel) = (vec![], vec![], vec![], vec![]);
        for m in &modal.modes {
            let fam = family(m);
            let k = seen.entry(fam).or_insert(0usize);
            let r = references(fam).get(*k).copied().unwrap_or(f64::NAN);
            *k += 1;
            freqs.push(m.frequency);
            types.push(fam);
            refs.push(r);
            rel.push((m.frequency - r) / r);
        }
        let pick = |fam: &str| -> Vec<f64> {
            freqs
                .iter()
                .zip(&types)
                .filter(|(_, t)| **t == fam)
                .map(|(f, _)| *f)
                .collect()
        };
        let types_json: Vec<String> = types.iter().map(|t| format!("\"{t}\"")).collect();
        let threads = std::env::var("RAYON_NUM_THREADS").unwrap_or_else(|_| "all".into());
        println!(
            "{{\"peer\": \"flexmbd\", \"peer_version\": \"{}\", \"problem\": \"strip_modes\", \"variant\": \"spacar-beam-EB-{}\", \"solver\": \"{}\", \"n_elements\": {n}, \"n_dof\": {}, \"modes\": {count}, \"status\": \"ok\", \"wall_s\": {:.6}, \"t_build_s\": {t_build:.6}, \"t_solve_s\": {t_solve:.6}, \"threads\": \"{threads}\", \"f1_hz\": {:.10}, \"freqs_hz\": {}, \"mode_types\": [{}], \"ref_hz\": {}, \"rel_err\": {}, \"bending_z_hz\": {}, \"torsion_hz\": {}}}",
            env!("CARGO_PKG_VERSION"),
            modal.solver.name(),
            modal.solver.name(),
            modal.ndof,
            t_build + t_solve,
            freqs.first().copied().unwrap_or(f64::NAN),
            json_list(&freqs),
            types_json.join(", "),
            json_list(&refs),
            json_list(&rel),
            json_list(&pick("bend(z)")),
            json_list(&pick("torsion(rx)")),
        );
    }
}
