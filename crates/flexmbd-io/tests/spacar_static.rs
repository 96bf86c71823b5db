//! The static solution of a SPACAR `.dat` file at the io level (the file read and mapped with
//! `flexmbd_io`, the core's static analysis, the `static --json` document of the io writer;
//! formerly run through the binary, whose handling of `.dat` files is tested in
//! `crates/flexmbd-cli/tests/spacar_static.rs`).
//!
//! `strip_end_moment.dat` (flexmbd's own fixture in the layout of SPACAR Light 1.29 output, in
//! `tests/models`; written by `make_fixtures.py` there) is a straight steel strip clamped at
//! x = 0 and loaded by a pure moment at a node inside the span. Everything the references need
//! is read off the file (line numbers of that file; `file_says_what_the_references_assume`
//! checks them against the text):
//!
//! - lines 7–25: translational nodes 1, 3, …, 37 at x = 0, 0.001667, 0.003333, …, 0.03 m
//!   (6 decimals, so the element lengths alternate between 0.001666 and 0.001667 m), y = z = 0;
//! - lines 30–64: `BEAM k 2k−1 2k 2k+1 2k+2 0 0 1`: the orientation vector (local y) is global
//!   z, so bending in the x–y plane is about local y: modes 3 and 4, stiffness EIy;
//! - lines 68–85: `DYNE k 3 4`: only those two modes deform, the other four are rigid;
//! - lines 89–90: `FIX 1`, `FIX 2`: node 1 and its rotation 2 clamped;
//! - lines 98–115: `ESTIFF`, column 3: EIy = 0.0168 N·m² for every beam;
//! - line 141: `ITERSTEP 10 5 …`: 5 load increments (6 states with the unloaded one);
//! - line 145: `DELXF 20 0 0 1`: Mz = 1 N·m on rotational node 20, which beams 9 and 10
//!   pair with translational node 19 at x = 0.015 m (line 16).
//!
//! References, in the x–y plane, for the 9 elements between the clamp and the loaded node
//! (the 9 beyond it carry no moment and stay straight, rotated as a rigid body):
//!
//! - discrete closed form (theory.md §11.3, verified against SPACAR): under a constant moment
//!   each element rotates by exactly 2β = asin(M l0/EI) (ε3 = ε4 = l0 sin β), its chord is
//!   shortened by l0 sin²β/6 (elongation rigid) and turned by β relative to the element's first
//!   node;
//! - Euler–Bernoulli elastica: constant curvature κ = M/EI, θ(s) = κs, x = sin(κs)/κ,
//!   y = (1 − cos κs)/κ, straight beyond s = 0.015 m. The discrete model differs from it by its
//!   discretisation error: asin(κ l0) = κ l0 (1 + ε + O(ε²)) with ε = (M l0/EI)²/6 ≈ 1.64e-3,
//!   so the rotation at every node is κs (1 + ε) to within 1 % of ε, and the position error,
//!   the integral of that rotation error, is at most ε θ(s) s.

use flexmbd_io::ModelFile;
use serde_json::Value;
use std::path::PathBuf;

mod common;
use common::{node, static_doc};

/// The SPACAR fixture.
fn dat() -> PathBuf {
    common::fixture("strip_end_moment.dat")
}

/// Lines 7–25: x of translational nodes 1, 3, …, 37 [m].
const X: [f64; 19] = [
    0.000000, 0.001667, 0.003333, 0.005000, 0.006667, 0.008333, 0.010000, 0.011667, 0.013333,
    0.015000, 0.016667, 0.018333, 0.020000, 0.021667, 0.023333, 0.025000, 0.026667, 0.028333,
    0.030000,
];
/// The number of beams.
const N: usize = X.len() - 1;
/// Lines 98–115, column 3: EIy [N·m²].
const EI: f64 = 0.0168;
/// Line 145: Mz on rotational node 20 [N·m].
const M: f64 = 1.0;
/// Index of the loaded node in `X` (translational node 19, line 16).
const LOADED: usize = 9;
/// Index of the last state: `ITERSTEP 10 5` gives 5 increments after the unloaded state.
const LAST: usize = 5;

/// The fixture mapped as `flexmbd static` maps it; nothing in this file needs approximating:
/// no warnings (the command's stderr stays empty).
fn strip() -> ModelFile {
    let text = std::fs::read_to_string(dat()).expect("the SPACAR fixture");
    let (f, warnings) = common::spacar(&text, "strip_end_moment.dat", false).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    f
}

/// Position (x, y) and rotation about z of the i-th node along the strip (SPACAR translational
/// node 2i+1 and its rotational node 2i+2: flexmbd nodes "2i+1" and "2i+1@2i+2").
fn state(step: &Value, i: usize) -> ([f64; 2], f64) {
    let t = 2 * i + 1;
    let p = &node(step, &t.to_string())["position"];
    let r = &node(step, &format!("{t}@{}", t + 1))["rotation"];
    assert_eq!(r[0].as_f64(), Some(0.0));
    assert_eq!(r[1].as_f64(), Some(0.0));
    (
        [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()],
        r[2].as_f64().unwrap(),
    )
}

/// The discrete closed form: position and rotation of every node.
fn discrete() -> Vec<([f64; 2], f64)> {
    let (mut r, mut th) = ([0.0, 0.0], 0.0);
    let mut out = vec![(r, th)];
    for k in 0..N {
        let l0 = X[k + 1] - X[k];
        let beta = if k < LOADED {
            0.5 * (M * l0 / EI).asin()
        } else {
            0.0
        };
        let chord = l0 * (1.0 - beta.sin().powi(2) / 6.0);
        r = [
            r[0] + chord * (th + beta).cos(),
            r[1] + chord * (th + beta).sin(),
        ];
        th += 2.0 * beta;
        out.push((r, th));
    }
    out
}

/// The elastica at arc length s.
fn elastica(s: f64) -> ([f64; 2], f64) {
    let k = M / EI;
    let sl = X[LOADED];
    let arc = |s: f64| [(k * s).sin() / k, (1.0 - (k * s).cos()) / k];
    if s <= sl {
        (arc(s), k * s)
    } else {
        let (p, t) = (arc(sl), k * sl);
        ([p[0] + (s - sl) * t.cos(), p[1] + (s - sl) * t.sin()], t)
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn file_says_what_the_references_assume() {
    let text = std::fs::read_to_string(dat()).expect("the SPACAR fixture");
    let lines: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split_whitespace().collect())
        .collect();
    let line = |n: usize| &lines[n - 1];
    for (i, x) in X.iter().enumerate() {
        let l = line(7 + i);
        assert_eq!(l[..2], ["X", &(2 * i + 1).to_string()], "line {}", 7 + i);
        assert_eq!(l[2].parse::<f64>().unwrap(), *x);
        assert_eq!(l[3..5], ["0.000000", "0.000000"]);
    }
    for k in 1..=N {
        let b = line(28 + 2 * k);
        let want = [2 * k - 1, 2 * k, 2 * k + 1, 2 * k + 2].map(|n| n.to_string());
        assert_eq!(b[..2], ["BEAM", &k.to_string()]);
        assert_eq!(b[2..6], want);
        assert_eq!(b[6..9], ["0.000000", "0.000000", "1.000000"]);
        assert_eq!(line(67 + k)[..], ["DYNE", &k.to_string(), "3", "4"]);
        let e = line(97 + k);
        assert_eq!(e[..2], ["ESTIFF", &k.to_string()]);
        assert_eq!(e[4].parse::<f64>().unwrap(), EI);
    }
    assert_eq!(line(89)[..], ["FIX", "1"]);
    assert_eq!(line(90)[..], ["FIX", "2"]);
    assert_eq!(line(141)[..3], ["ITERSTEP", "10", "5"]);
    assert_eq!(
        line(145)[..],
        ["DELXF", "20", "0.000000", "0.000000", "1.000000"]
    );
    // rotational node 20 belongs to translational node 19, the 10th node (x = 0.015)
    assert_eq!(line(46)[2..6], ["17", "18", "19", "20"]);
    assert_eq!(line(16)[1], "19");
    assert_eq!(X[LOADED], 0.015);
}

#[test]
fn end_moment_on_the_strip_matches_the_elastica() {
    let doc = static_doc(&strip(), "strip_end_moment.dat", None);
    let steps = doc["steps"].as_array().unwrap();
    assert_eq!(steps.len(), LAST + 1, "ITERSTEP 10 5: 5 increments");
    let last = &steps[LAST];
    assert_eq!(last["load_factor"].as_f64(), Some(1.0));
    // 36 flexible deformations (DYNE 3 4 of 18 beams), the other 72 rigid
    let roles = doc["roles"].as_array().unwrap();
    assert_eq!(roles.iter().filter(|r| *r == "flexible").count(), 2 * N);
    assert_eq!(roles.iter().filter(|r| *r == "rigid").count(), 4 * N);

    let length = X[N];
    let disc = discrete();
    let eps = (M * (X[1] - X[0]) / EI).powi(2) / 6.0; // longest element: 0.001667 m
    let theta_l = M * X[LOADED] / EI;
    let (mut worst_disc, mut worst_rot, mut worst_pos) = (0.0f64, 0.0f64, 0.0f64);
    for (i, &s) in X.iter().enumerate() {
        let (p, th) = state(last, i);
        // (a) the discrete closed form, to 1e-8 relative
        let (pd, thd) = disc[i];
        assert!(
            dist(p, pd) <= 1e-8 * length && (th - thd).abs() <= 1e-8 * theta_l,
            "node {i}: flexmbd {p:?} {th} vs discrete {pd:?} {thd}"
        );
        worst_disc = worst_disc.max(dist(p, pd) / length);
        if i == 0 {
            continue;
        }
        // (b) the elastica, to its discretisation error
        let (pe, the) = elastica(s);
        let rel = (th - the) / the;
        assert!(
            (rel / eps - 1.0).abs() < 0.01,
            "node {i}: rotation {th} vs elastica {the}: relative error {rel:.4e}, expected ε = {eps:.4e}"
        );
        assert!(
            dist(p, pe) <= eps * the * s,
            "node {i}: position {p:?} vs elastica {pe:?}: {:.3e} m > ε θ s = {:.3e} m",
            dist(p, pe),
            eps * the * s
        );
        worst_rot = worst_rot.max(rel.abs());
        worst_pos = worst_pos.max(dist(p, pe) / length);
    }
    // the part beyond the loaded node is straight
    let (_, th_l) = state(last, LOADED);
    for i in LOADED..=N {
        assert!((state(last, i).1 - th_l).abs() < 1e-12);
    }
    eprintln!(
        "strip_end_moment.dat: θ(0.015 m) = {th_l:.12} (discrete {:.12}, elastica {theta_l:.12}); \
         max |Δr|/L vs discrete {worst_disc:.1e}; vs elastica: rotation {worst_rot:.4e} \
         (ε = {eps:.4e}), position {worst_pos:.2e}",
        disc[LOADED].1
    );
}

/// `flexmbd convert` of the fixture: the TOML document keeps what it cannot express as comments,
/// and reads back to the same final state.
#[test]
fn converted_toml_gives_the_same_final_state() {
    let spacar = flexmbd_io::read_dat(&dat()).unwrap_or_else(|e| panic!("{e}"));
    let text = spacar.to_toml().unwrap_or_else(|e| panic!("{e}"));
    // the shear flexibilities cannot be written: kept as comments (a pure moment bends each
    // element with ε3 = ε4, where the bending stiffness does not depend on them, theory.md §11.2)
    assert!(text.contains("shear flexibilities ShearY=3.1e-7 ShearZ=0.00012"));
    assert!(text.contains("fixed = [1, 2, 5, 6]"));
    assert!(text.contains("[static]\nsteps = 5\n"));
    let a = static_doc(&strip(), "strip_end_moment.dat", None);
    let toml = flexmbd_io::parse_model_file(&text, "strip_end_moment.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    let b = static_doc(&toml, "strip_end_moment.toml", None);
    let (sa, sb) = (
        a["steps"].as_array().unwrap(),
        b["steps"].as_array().unwrap(),
    );
    assert_eq!(sa.len(), sb.len());
    let mut worst = 0.0f64;
    for i in 0..=N {
        let ((pa, ta), (pb, tb)) = (state(&sa[LAST], i), state(&sb[LAST], i));
        worst = worst.max(dist(pa, pb)).max((ta - tb).abs() * X[N]);
    }
    assert!(worst <= 1e-10 * X[N], "largest difference {worst:.3e} m");
}

/// A small cantilever written for the tests (`crates/flexmbd-cli/tests/models/tip_moment.dat`,
/// shared with the command-line test of the same warnings and errors): the mapping's warnings
/// and errors name the line. With the held Euler parameters λ1..λ3 of node 4 as inputs without
/// a value and a zero tip moment: no warning, `ITERSTEP 10 2`: 2 load steps. An initial tip
/// moment over two load steps is a warning; the beam bends to θ = M L/EI (a single element
/// under a constant moment: 2β = asin(M l0/EI), theory.md §11.3). Two rotational inputs on one
/// node are an error at the second one's line.
#[test]
fn mapping_warnings_and_errors_name_the_line() {
    let base = std::fs::read_to_string(common::cli_model("tip_moment.dat")).unwrap();
    let (f, w) = common::spacar(&base, "warn.dat", false).unwrap();
    assert!(w.is_empty(), "{w:?}");
    let doc = static_doc(&f, "warn.dat", None);
    assert_eq!(doc["steps"].as_array().unwrap().len(), 3);
    // an initial tip moment with two load steps: a warning at the XF line
    let text = base
        .replace("INPUTX 4\n", "")
        .replace("XF 4 0 0 0\n", "XF 4 0 0 0.2\n");
    let (f, w) = common::spacar(&text, "warn.dat", false).unwrap();
    assert!(
        w.iter().any(|w| w.line == 11
            && w.message.starts_with("XF is an initial load")
            && w.message.contains("over the 2 steps")),
        "{w:?}"
    );
    let doc = static_doc(&f, "warn.dat", None);
    let th = node(&doc["steps"][2], "3@4")["rotation"][2]
        .as_f64()
        .unwrap();
    assert!((th - (0.2f64 / 2.0).asin()).abs() < 1e-9, "{th}");
    // two rotational inputs on one node: an input error with file and line
    let bad = base.replace("XF 4 0 0 0\n", "DELINPX 4 2 0.1\nDELINPX 4 4 0.1\n");
    let e = common::spacar(&bad, "bad.dat", false).unwrap_err();
    assert!(
        e.contains(
            "bad.dat:13:1: INPUTX/DELINPX 4: several rotational inputs on one node are not supported"
        ),
        "{e}"
    );
}
