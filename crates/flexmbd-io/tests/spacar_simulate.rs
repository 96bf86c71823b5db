//! The time simulation of a SPACAR `.dat` file at the io level (mode 1, docs/spacar-import.md
//! §7; the file read and mapped with `flexmbd_io`, the core's simulation, the `simulate --json`
//! document of the io writer; formerly run through the binary, whose handling of `.dat` files is
//! tested in `crates/flexmbd-cli/tests/simulate_spacar.rs`).
//!
//! `mass_spring.dat` (flexmbd's own fixture in `tests/models`, written for the tests) is a
//! point mass m = 2 kg (`XM 2 2.0`) on a massless spring of EA = 400 N and length 0.5 m
//! (`TRUSS 1 1 2`, `ESTIFF 1 400`, X lines 0 and 0.5), sliding along x (`FIX 2 2 3`),
//! loaded by a constant force F = 8 N from t = 0 (`XF 2 8 0 0`), simulated to 0.7 s with 700
//! output steps (`TIMESTEP 0.7 700`). The closed form of the undamped oscillator under a step
//! load, independent of flexmbd: u(t) = F/k (1 − cos ωt), k = EA/L = 800 N/m, ω = √(k/m), so the
//! period is T = 2π√(m/k) = 0.314159 s and the largest displacement 2F/k = 0.02 m at T/2.

use flexmbd_io::requests::SimOverrides;

mod common;

#[test]
fn mass_spring_dat_oscillates_with_the_closed_form_period() {
    let text = std::fs::read_to_string(common::fixture("mass_spring.dat")).unwrap();
    let (file, warnings) = common::spacar(&text, "mass_spring.dat", true).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    let over = SimOverrides::default();
    let json = common::simulate_file_doc(&file, "mass_spring.dat", &over, None);
    assert_eq!(json["complete"], true);
    let frames = json["frames"].as_array().unwrap();
    // TIMESTEP 0.7 700: t = 0, 0.001, …, 0.7
    assert_eq!(frames.len(), 701);
    assert!((frames[700]["t"].as_f64().unwrap() - 0.7).abs() < 1e-12);

    let (m, k, f) = (2.0f64, 400.0 / 0.5, 8.0);
    let period = 2.0 * std::f64::consts::PI * (m / k).sqrt();
    let t = |fr: &serde_json::Value| fr["t"].as_f64().unwrap();
    // node "2" (the second node), its x displacement and velocity
    let u = |fr: &serde_json::Value| fr["nodes"][1]["position"][0].as_f64().unwrap() - 0.5;
    let v = |fr: &serde_json::Value| fr["nodes"][1]["velocity"][0].as_f64().unwrap();
    // the turning points: the velocity changes sign (maxima at T/2, 3T/2; minima at T, 2T)
    let (mut maxima, mut minima) = (Vec::new(), Vec::new());
    for w in frames.windows(2) {
        let (a, b) = (v(&w[0]), v(&w[1]));
        let at = || t(&w[0]) + a / (a - b) * (t(&w[1]) - t(&w[0]));
        if a > 0.0 && b <= 0.0 {
            maxima.push(at());
        } else if a < 0.0 && b >= 0.0 {
            minima.push(at());
        }
    }
    assert_eq!(
        (maxima.len(), minima.len()),
        (2, 2),
        "{maxima:?} {minima:?}"
    );
    let close = |x: f64, want: f64| (x - want).abs() < 1e-3 * period;
    assert!(close(maxima[0], 0.5 * period), "{maxima:?}, T = {period}");
    assert!(close(minima[0], period), "{minima:?}, T = {period}");
    assert!(close(maxima[1] - maxima[0], period), "{maxima:?}");
    assert!(close(minima[1] - minima[0], period), "{minima:?}");
    // the largest displacement 2F/k, and back to rest at the spring's length at T
    let top = frames.iter().map(u).fold(f64::MIN, f64::max);
    assert!((top - 2.0 * f / k).abs() < 1e-3 * 2.0 * f / k, "{top}");
    let bottom = frames
        .iter()
        .filter(|fr| (t(fr) - period).abs() < 0.01)
        .map(u)
        .fold(f64::MAX, f64::min);
    assert!(bottom.abs() < 1e-3 * 2.0 * f / k, "{bottom}");
}
