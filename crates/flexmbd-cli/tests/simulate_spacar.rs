//! `flexmbd simulate` on SPACAR `.dat` files (mode 1, docs/spacar-import.md §7): the
//! command-line concerns (the file read by its extension with its time-simulation data, the
//! JSON on stdout, exit code 2 at the line of what cannot be mapped). The motion of
//! `mass_spring.dat` against its closed form is checked in process in
//! `crates/flexmbd-io/tests/spacar_simulate.rs`.

mod common;
use common::*;
use std::path::PathBuf;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../flexmbd-io/tests/models/"
    ))
    .join(name)
}

/// One run on `mass_spring.dat` (the first 10 ms of its `TIMESTEP 0.7 700`: 1 ms outputs):
/// exit 0, no warning, the JSON document of the complete run.
#[test]
fn mass_spring_dat_runs_from_its_own_settings() {
    let (out, json) = run_json(&[
        "simulate".as_ref(),
        fixture("mass_spring.dat").as_os_str(),
        "--t-end".as_ref(),
        "0.01".as_ref(),
        "--json".as_ref(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
    let json = json.expect("JSON on stdout");
    assert_eq!(json["complete"], true);
    assert_eq!(json["frames"].as_array().unwrap().len(), 11);
}

/// A public model whose loads come from a MATLAB routine is refused at that line (exit 2).
#[test]
fn user_routines_are_refused_with_their_line() {
    let file = "roepnaamstraat__FlexibleInstrumentSimulation__FLEX_CAT_S_3D_V2.dat";
    let out = run(&[
        "simulate".as_ref(),
        fixture("public").join(file).as_os_str(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!("{file}:200:")) && stderr.contains("USERSIG FFESFVA"),
        "{stderr}"
    );
}
