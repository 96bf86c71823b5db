//! The static solutions of shipped examples at the io level (the example read with
//! `flexmbd_io`, the core's static analysis, the `static --json` document of the io writer;
//! formerly run through the binary): the parallel leaf-spring stroke against closed forms, and
//! the Williams toggle (validation.md S05) by arc length.
//!
//! Parallel leaf-spring stroke
//!
//! Model (examples/parallel_leaf_stroke.toml): two steel leaves L = 50 mm, w = 20 mm,
//! t = 0.3 mm (E = 210 GPa, ν = 0.3), 4 Timoshenko elements each, rigid platform, platform x
//! prescribed 0 → 5 mm in 20 steps.

use flexmbd_core::statics::PathMethod;
use serde_json::Value;

const E: f64 = 210e9;
const NU: f64 = 0.3;
const L: f64 = 0.05;
const W: f64 = 0.02;
const T: f64 = 0.0003;

mod common;
use common::{example, node};

#[test]
fn parallel_leaf_stroke_matches_closed_forms() {
    let ex = example("parallel_leaf_stroke.toml");
    let doc = common::static_doc(&common::read(&ex), "parallel_leaf_stroke.toml", None);
    let steps = doc["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 21);

    // closed forms (independent of flexmbd): out-of-plane EIy = E w t³/12, in-plane EIz = E t w³/12
    let (eiy, eiz, ea) = (
        E * W * T.powi(3) / 12.0,
        E * T * W.powi(3) / 12.0,
        E * W * T,
    );
    let g = E / (2.0 * (1.0 + NU));
    let k_shear = 10.0 * (1.0 + NU) / (12.0 + 11.0 * NU); // Cowper, rectangle
    let kga = k_shear * g * W * T;

    // unloaded support stiffness of the platform: z: two leaves in tension/compression, 2EA/L;
    // y: the platform may rotate about x, so each leaf is an in-plane Timoshenko cantilever
    let s0 = &steps[0]["compliance"][0];
    let kz = s0["stiffness_global"][2].as_f64().unwrap();
    let ky = s0["stiffness_global"][1].as_f64().unwrap();
    let ky_exact = 2.0 / (L.powi(3) / (3.0 * eiz) + L / kga);
    assert!(
        (kz - 2.0 * ea / L).abs() < 1e-6 * kz,
        "k_z {kz} vs {}",
        2.0 * ea / L
    );
    assert!((ky - ky_exact).abs() < 1e-6 * ky, "k_y {ky} vs {ky_exact}");

    // small stroke (step 1, δ = 0.25 mm = L/200): actuation force of two guided leaves,
    // F = 24 EI/L³ δ (1 + Φ)⁻¹ with the (here negligible) shear parameter Φ = 12EI/(kGA L²);
    // geometric stiffening is of order (δ/L)², below the 0.1 % tolerance
    let phi = 12.0 * eiy / (kga * L * L);
    let f1 = node(&steps[1], "p")["reaction_force"][0].as_f64().unwrap();
    let f_exact = 24.0 * eiy / L.powi(3) * 0.25e-3 / (1.0 + phi);
    assert!((f1 - f_exact).abs() < 1e-3 * f_exact, "F {f1} vs {f_exact}");

    // equilibrium of the whole: the support reactions balance the actuation force
    let last = &steps[20];
    let fx: f64 = ["g1", "g2", "p"]
        .iter()
        .map(|n| node(last, n)["reaction_force"][0].as_f64().unwrap())
        .sum();
    assert!(fx.abs() < 1e-6, "ΣFx = {fx}");
    // the support stiffness in z drops along the stroke, and the guide stays stable
    let kz_end = last["compliance"][0]["stiffness_global"][2]
        .as_f64()
        .unwrap();
    assert!(kz_end < 0.5 * kz);
    assert!(steps.iter().all(|s| s["unstable_directions"] == 0));
}

#[test]
fn williams_toggle_by_arc_length_through_both_limit_points() {
    // examples/williams_toggle.toml (validation S05, a dead load of 180 N on the frame): by arc
    // length the path passes the limit load P_max = 150.66 N and the following minimum
    // 139.15 N (validation.md, ±0.5 %) and ends at the full load; both limit points are
    // located states of the path, where the smallest eigenvalue of the tangent vanishes (to
    // 1e-6 of its value in the unloaded state); the full load is the output level 20
    let ex = example("williams_toggle.toml");
    let check = |doc: Value| {
        let events = doc["events"].as_array().expect("events");
        assert_eq!(events.len(), 2, "{events:?}");
        for (e, p) in events.iter().zip([150.66, 139.15]) {
            assert_eq!(e["kind"], "limit_point");
            let t = e["load_factor"].as_f64().unwrap();
            assert!((180.0 * t - p).abs() < 5e-3 * p, "{} vs {p}", 180.0 * t);
        }
        let steps = doc["steps"].as_array().unwrap();
        assert_eq!(steps.last().unwrap()["load_factor"], 1.0);
        assert_eq!(steps.last().unwrap()["path"]["level"], 20);
        assert!(steps[1]["path"]["arc_length"].as_f64().unwrap() > 0.0);
        let kappa1 = |k: usize| steps[k]["tangent_eigenvalues"][0].as_f64().expect("κ₁");
        for e in events {
            assert_eq!(e["located"], true, "{e}");
            let k = e["step"].as_u64().unwrap() as usize;
            assert!(
                kappa1(k).abs() < 1e-6 * kappa1(0),
                "{} vs {}",
                kappa1(k),
                kappa1(0)
            );
        }
        assert_eq!(doc["stopped"], Value::Null);
    };
    // the method asked for (`--path arc-length`), with κ at every step
    let text = std::fs::read_to_string(&ex).unwrap();
    let kappa = text.replace("[static]\n", "[static]\ntangent_eigenvalues = true\n");
    assert_ne!(kappa, text);
    let file = flexmbd_io::parse_model_file(&kappa, "williams_toggle.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    check(common::static_doc(
        &file,
        "williams_toggle.toml",
        Some(PathMethod::ArcLength),
    ));
    // the same from the model's [static] table
    let with = kappa.replace("[static]\n", "[static]\npath = \"arc-length\"\n");
    assert_ne!(with, kappa);
    let file = flexmbd_io::parse_model_file(&with, "toggle.toml").unwrap_or_else(|e| panic!("{e}"));
    check(common::static_doc(&file, "toggle.toml", None));
}
