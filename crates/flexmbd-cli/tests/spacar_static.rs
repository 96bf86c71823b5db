//! `flexmbd static` on SPACAR `.dat` files: the command-line concerns (the file read by its
//! extension, the mapping's warnings on stderr with file and line, an input error with exit code
//! 2). The numbers of the static solutions of `.dat` files (the strip under an end moment against
//! the elastica, the converted TOML, the tip rotation of this cantilever) are checked in process
//! in `crates/flexmbd-io/tests/spacar_static.rs`.

mod common;
use common::{run, Temp};
use serde_json::Value;

/// A small cantilever written for the tests (`tests/models/tip_moment.dat`, shared with the io
/// test): an initial tip moment over two load steps is a warning on stderr, with the line; two
/// rotational inputs on one node stop with exit code 2 and the line.
#[test]
fn warnings_and_errors_of_the_mapping_name_the_line() {
    let t = Temp::new("spacar_warn");
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/models/tip_moment.dat"
    ))
    .unwrap();
    let text = base
        .replace("INPUTX 4\n", "")
        .replace("XF 4 0 0 0\n", "XF 4 0 0 0.2\n");
    let good = t.write("warn.dat", text.as_bytes());
    let out = run(&["static", good.to_str().unwrap(), "--json", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warn.dat:11: XF is an initial load")
            && stderr.contains("over the 2 steps"),
        "{stderr}"
    );
    let doc: Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert!(doc["steps"].is_array(), "{doc}");
    // two rotational inputs on one node: exit code 2, file and line
    let bad = base.replace("XF 4 0 0 0\n", "DELINPX 4 2 0.1\nDELINPX 4 4 0.1\n");
    let bad = t.write("bad.dat", bad.as_bytes());
    let out = run(&["static", bad.to_str().unwrap(), "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("bad.dat:13:1: INPUTX/DELINPX 4: several rotational inputs on one node are not supported"),
        "{stderr}"
    );
}
