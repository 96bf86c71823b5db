//! Tests of `[parameters]`, values written as expressions and the overrides of
//! [`parse_spec_with`]: every expected number is computed by hand in the comments.

use super::{parse_spec, parse_spec_with, write_toml};
use crate::error::InputError;
use crate::spec::{ElementKind, NodePlace, ShapeSpec};

/// A beam of length L with a tip load, its dimensions and load as parameters.
const STRIP: &str = r#"[model]
name = "strip"

[parameters]
L = 0.1
t = 0.2e-3
w = "10*t"             # 2e-3
h = "L/4"              # 0.025
F = "-2*sqrt(4)"       # -4
theta = "30*deg"

[nodes]
a = [0, 0, 0]
b = { x = ["L", 0.0, "-h"], rot = true }

[fix]
a = "all"

[[material]]
id = "steel"
E = "2.1e11"
nu = 0.3
rho = "7800"

[[section]]
id = "s"
shape = "rectangle"
w = "w"
t = "t"

[[beam]]
id = "w1"
nodes = ["a", "b"]
section = "s"
material = "steel"
orient = ["cos(theta)", "sin(theta)", 0]

[[load]]
node = "b"
force = [0, 0, "F"]

[[mass]]
node = "b"
m = "L*w*t*7800"

[static]
gravity = [0, 0, "-9.81"]
tol_force = "1e-3^3"
"#;

fn set(list: &[(&str, f64)]) -> Vec<(String, f64)> {
    list.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

fn close(a: f64, b: f64) {
    assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} != {b}");
}

#[test]
fn parameters_are_evaluated_in_file_order() {
    let s = parse_spec(STRIP, "m.toml").unwrap();
    let names: Vec<&str> = s.parameters.keys().map(String::as_str).collect();
    assert_eq!(names, ["L", "t", "w", "h", "F", "theta"]);
    close(s.parameters["w"], 2e-3);
    close(s.parameters["h"], 0.025);
    close(s.parameters["F"], -4.0);
    close(s.parameters["theta"], std::f64::consts::PI / 6.0);
    let NodePlace::Position { x, rot } = &s.nodes[1].place else {
        panic!("a position")
    };
    assert!(*rot);
    assert_eq!(x[1], 0.0);
    close(x[0], 0.1);
    close(x[2], -0.025);
    let ShapeSpec::Rectangle { w, t } = s.sections[0].shape else {
        panic!("a rectangle")
    };
    close(w, 2e-3);
    close(t, 2e-4);
    close(s.materials[0].e, 2.1e11);
    close(s.materials[0].rho, 7800.0);
    let ElementKind::Beam(b) = &s.elements[0].kind else {
        panic!("a beam")
    };
    let o = b.orient.unwrap();
    // cos 30° = sqrt(3)/2, sin 30° = 1/2
    close(o[0], 3f64.sqrt() / 2.0);
    close(o[1], 0.5);
    close(s.loads[0].force[2], -4.0);
    // 0.1 * 2e-3 * 2e-4 * 7800 = 3.12e-4 kg
    close(s.masses[0].m, 3.12e-4);
    close(s.statics.gravity.unwrap()[2], -9.81);
    close(s.statics.tol_force.unwrap(), 1e-9);
    // the model builds
    s.build_file().unwrap();
}

#[test]
fn an_override_replaces_a_parameter_and_its_dependents_follow() {
    // t = 0.5e-3: w = 5e-3; L = 0.2 (given for h = "L/4" too): h = 0.05;
    // w overridden although it is an expression: w = 1e-2, t keeps its value
    let s = parse_spec_with(STRIP, "m.toml", &set(&[("t", 0.5e-3), ("L", 0.2)])).unwrap();
    close(s.parameters["w"], 5e-3);
    close(s.parameters["h"], 0.05);
    let NodePlace::Position { x, .. } = &s.nodes[1].place else {
        panic!("a position")
    };
    close(x[0], 0.2);
    close(x[2], -0.05);
    let s = parse_spec_with(STRIP, "m.toml", &set(&[("w", 1e-2)])).unwrap();
    close(s.parameters["w"], 1e-2);
    close(s.parameters["t"], 2e-4);
    let ShapeSpec::Rectangle { w, t } = s.sections[0].shape else {
        panic!("a rectangle")
    };
    close(w, 1e-2);
    close(t, 2e-4);
}

#[test]
fn a_dotted_override_is_a_path_of_the_document() {
    let s = parse_spec_with(
        STRIP,
        "m.toml",
        &set(&[
            ("sections.s.t", 3e-4),
            ("nodes.b.y", 0.5),
            ("static.steps", 7.0),
        ]),
    )
    .unwrap();
    let ShapeSpec::Rectangle { w, t } = s.sections[0].shape else {
        panic!("a rectangle")
    };
    // the path sets one value; w = 10*t keeps the parameter's t
    close(t, 3e-4);
    close(w, 2e-3);
    let NodePlace::Position { x, .. } = &s.nodes[1].place else {
        panic!("a position")
    };
    assert_eq!(x[1], 0.5);
    assert_eq!(s.statics.steps, Some(7));
    let e = parse_spec_with(STRIP, "m.toml", &set(&[("sections.zz.t", 1.0)]))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("m.toml: cannot set `sections.zz.t`") && e.contains("no entry `zz`"),
        "{e}"
    );
}

#[test]
fn overriding_an_undeclared_parameter_lists_the_declared_ones() {
    let e = parse_spec_with(STRIP, "m.toml", &set(&[("thick", 1.0)]))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`thick`") && e.contains("the parameters are: L, t, w, h, F, theta"),
        "{e}"
    );
    let plain = "[nodes]\na = [0, 0, 0]\n";
    let e = parse_spec_with(plain, "m.toml", &set(&[("t", 1.0)]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("declares no parameters"), "{e}");
}

/// The error of `text`: (line, column, message).
fn error(text: &str) -> (usize, usize, String) {
    match parse_spec(text, "m.toml") {
        Err(InputError::At {
            line,
            column,
            message,
            ..
        }) => (line, column, message),
        other => panic!("expected an error at a place, got {other:?}"),
    }
}

#[test]
fn expression_errors_name_line_column_and_item() {
    // an unknown name: line 2, the `h` at column 12 of `m = "2*L + h"`
    let text = "[nodes]\na = [0, 0, 0]\n[[mass]]\nnode = \"a\"\nm = \"2*L + h\"\n";
    let text = format!("[parameters]\nL = 1\n{text}");
    let (line, column, msg) = error(&text);
    assert_eq!((line, column), (7, 12), "{msg}");
    assert!(
        msg.contains("[[mass]] 1 (on `a`)")
            && msg.contains("unknown name `h`")
            && msg.contains("the parameters are: L"),
        "{msg}"
    );
    // a syntax error in a node's position: the `)` at column 17 of `b = [0, "(L + 1))", 0]`
    let text = "[parameters]\nL = 1\n[nodes]\nb = [0, \"(L + 1))\", 0]\n";
    let (line, column, msg) = error(text);
    assert_eq!((line, column), (4, 17), "{msg}");
    assert!(
        msg.contains("node `b`") && msg.contains("unexpected `)`"),
        "{msg}"
    );
    // division by zero in a section
    let text = "[parameters]\nL = 0\n[nodes]\na = [0, 0, 0]\n[[section]]\nid = \"s\"\nshape = \"circle\"\nd = \"1/L\"\n";
    let (line, column, msg) = error(text);
    assert_eq!((line, column), (8, 7), "{msg}");
    assert!(
        msg.contains("section `s`") && msg.contains("division by zero"),
        "{msg}"
    );
    // a parameter that uses one declared after it
    let text = "[parameters]\nh = \"L/2\"\nL = 1\n[nodes]\na = [0, 0, 0]\n";
    let (line, _, msg) = error(text);
    assert_eq!(line, 2, "{msg}");
    assert!(
        msg.contains("parameter `h`") && msg.contains("`L` is declared after `h`"),
        "{msg}"
    );
    // a parameter named like a built-in, and one that is not a name
    let (line, _, msg) = error("[parameters]\nL = 1\npi = 3\n[nodes]\na = [0, 0, 0]\n");
    assert_eq!(line, 3);
    assert!(
        msg.contains("parameter `pi`") && msg.contains("built-in"),
        "{msg}"
    );
    let (line, _, msg) = error("[parameters]\n\"a-b\" = 3\n[nodes]\na = [0, 0, 0]\n");
    assert_eq!(line, 2);
    assert!(msg.contains("parameter `a-b`"), "{msg}");
    // not finite
    let (line, _, msg) = error("[parameters]\nx = \"ln(0)\"\n[nodes]\na = [0, 0, 0]\n");
    assert_eq!(line, 2);
    assert!(msg.contains("not finite"), "{msg}");
    // an integer key takes no expression
    let text = "[parameters]\nn = 2\n[nodes]\na = [0, 0, 0]\nb = [1, 0, 0]\n[[beam]]\nid = \"w\"\nnodes = [\"a\", \"b\"]\nsegments = \"n\"\n";
    let (line, _, msg) = error(text);
    assert_eq!(line, 9);
    assert!(
        msg.contains("element `w`") && msg.contains("whole number"),
        "{msg}"
    );
}

#[test]
fn a_parametric_model_is_written_as_its_evaluated_member() {
    let s = parse_spec_with(STRIP, "m.toml", &set(&[("t", 0.3e-3)])).unwrap();
    let text = write_toml(&s).unwrap();
    assert!(
        text.contains("[parameters]\nL = 0.1\nt = 0.0003\n"),
        "{text}"
    );
    // it reads back to the same member
    let back = parse_spec(&text, "w.toml").unwrap();
    assert_eq!(back, s.without_comments());
    // and as JSON
    let json = serde_json::to_value(&s).unwrap();
    assert_eq!(json["parameters"]["t"], 0.3e-3);
    let plain = serde_json::to_value(parse_spec("[nodes]\na = [0, 0, 0]\n", "m").unwrap());
    assert!(plain.unwrap().get("parameters").is_none());
}

#[test]
fn parameters_can_be_read_but_not_set_on_a_spec() {
    let mut s = parse_spec(STRIP, "m.toml").unwrap();
    assert_eq!(s.get("parameters.L").unwrap(), 0.1);
    let e = s.set("parameters.L", 0.2).unwrap_err().to_string();
    assert!(e.contains("read it again"), "{e}");
}
