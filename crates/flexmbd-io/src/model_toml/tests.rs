//! Tests of the TOML model reader: every kind of bad input gives an [`InputError::At`] on the
//! right line whose message names the item (node, element, fix or inputs entry); good input
//! compiles as documented in docs/model-format.md.
//!
//! The line an error must point at is marked `# <-` in the model text where possible; syntax
//! errors (where a comment would change the error) give the line number explicitly.

use super::parse_model;
use crate::error::InputError;
use flexmbd_core::{CoordKind, DefKind, Model};

/// Parse, expect an error at a known line, return (line, message).
fn error(text: &str) -> (usize, String) {
    match parse_model(text, "m.toml") {
        Err(InputError::At {
            file,
            line,
            column,
            message,
        }) => {
            assert_eq!(file, "m.toml");
            assert!(column >= 1);
            (line, message)
        }
        Err(other) => panic!("expected an error at a line, got: {other}"),
        Ok(_) => panic!("expected an error, the model was accepted:\n{text}"),
    }
}

/// The 1-based line holding the `# <-` marker.
fn marked(text: &str) -> usize {
    let lines: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains("# <-"))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(lines.len(), 1, "exactly one `# <-` marker in\n{text}");
    lines[0]
}

/// Assert the error is at the marked line and its message contains every one of `parts`.
#[track_caller]
fn check(text: &str, parts: &[&str]) {
    let (line, message) = error(text);
    assert_eq!(line, marked(text), "wrong line for: {message}");
    for p in parts {
        assert!(message.contains(p), "`{message}` should contain `{p}`");
    }
}

/// Like [`check`] with an explicit line.
#[track_caller]
fn check_line(text: &str, want: usize, parts: &[&str]) {
    let (line, message) = error(text);
    assert_eq!(line, want, "wrong line for: {message}");
    for p in parts {
        assert!(message.contains(p), "`{message}` should contain `{p}`");
    }
}

/// [`check`] of [`AB`] followed by `body`; the marked line is counted in the whole text.
#[track_caller]
fn check_ab(body: &str, parts: &[&str]) {
    check(
        &format!("{AB}{}", body.strip_prefix('\n').unwrap_or(body)),
        parts,
    );
}

fn ok(text: &str) -> Model {
    match parse_model(text, "m.toml") {
        Ok(m) => m,
        Err(e) => panic!("model rejected: {e}\n{text}"),
    }
}

// ---- nodes ----

#[test]
fn duplicate_node() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
b = [1.0, 0.0, 0.0]
a = [2.0, 0.0, 0.0]  # <-
"#,
        &["node `a`", "defined twice"],
    );
}

#[test]
fn duplicate_node_as_subtable() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
[nodes.a]  # <-
x = [1.0, 0.0, 0.0]
"#,
        &["node `a` is defined twice"],
    );
}

#[test]
fn duplicate_section_and_field() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
[fix]
a = "all"
[fix]  # <-
"#,
        &["the table `[fix]` appears twice"],
    );
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
b = [1.0, 0.0, 0.0]
[[truss]]
id = "t1"
nodes = ["a", "b"]
nodes = ["b", "a"]  # <-
"#,
        &["element `t1`", "`nodes` is given twice"],
    );
}

#[test]
fn nan_position() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
p1 = [1.0, nan, 0.0]  # <-
"#,
        &["node `p1`", "not finite", "NaN"],
    );
}

#[test]
fn inf_position_in_table_form() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
p1 = { x = [1.0, 0.0, -inf], rot = true }  # <-
"#,
        &["node `p1`", "not finite"],
    );
}

#[test]
fn nan_position_in_multiline_array() {
    // the error points at the start of the value
    check(
        r#"[nodes]
p1 = [  # <-
  0.0,
  nan,
  0.0,
]
"#,
        &["node `p1`", "entry 2", "not finite"],
    );
}

#[test]
fn overflowing_number() {
    // a TOML parse error: no comment on the line, it is a syntax error
    check_line(
        "[nodes]\na = [0.0, 0.0, 0.0]\np1 = [1e400, 0.0, 0.0]\n",
        3,
        &["node `p1`", "overflow"],
    );
}

#[test]
fn overflowing_integer() {
    check_line(
        "[nodes]\np1 = [99999999999999999999, 0, 0]\n",
        2,
        &["node `p1`"],
    );
}

#[test]
fn wrong_position_length() {
    check(
        r#"[nodes]
p1 = [0.0, 1.0]  # <-
"#,
        &["node `p1`", "3 numbers", "found 2"],
    );
}

#[test]
fn position_not_a_number() {
    check(
        r#"[nodes]
p1 = [0.0, true, 0.0]  # <-
"#,
        &["node `p1`", "entry 2", "not a number"],
    );
}

#[test]
fn node_not_a_position() {
    check(
        r#"[nodes]
p1 = "here"  # <-
"#,
        &["node `p1`", "expected a position"],
    );
}

#[test]
fn node_unknown_key() {
    check(
        r#"[nodes]
p1 = { x = [0.0, 0.0, 0.0], rotation = true }  # <-
"#,
        &["node `p1`", "unknown key `rotation`"],
    );
}

#[test]
fn node_unknown_key_in_subtable() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
[nodes.p1]  # <-
x = [1.0, 0.0, 0.0]
colour = "red"
"#,
        &["node `p1`", "unknown key `colour`"],
    );
}

#[test]
fn node_missing_position() {
    check(
        r#"[nodes]
p1 = { rot = true }  # <-
"#,
        &["node `p1`", "missing field `x`"],
    );
}

#[test]
fn node_rot_not_bool() {
    check(
        r#"[nodes]
p1 = { x = [0.0, 0.0, 0.0], rot = "yes" }  # <-
"#,
        &["node `p1`", "`rot` must be true or false"],
    );
}

#[test]
fn node_at_unknown_host() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
h = { at = "zz" }  # <-
"#,
        &["node `h`", "`zz`", "not defined before it"],
    );
}

#[test]
fn node_at_host_defined_later() {
    // file order counts, not the alphabetical order of the keys
    check(
        r#"[nodes]
z = { at = "a" }  # <-
a = [0.0, 0.0, 0.0]
"#,
        &["node `z`", "`a`", "not defined before it"],
    );
}

#[test]
fn node_at_itself() {
    check(
        r#"[nodes]
h = { at = "h" }  # <-
"#,
        &["node `h`", "not defined before it"],
    );
}

#[test]
fn node_at_and_x() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
h = { at = "a", x = [0.0, 0.0, 0.0] }  # <-
"#,
        &["node `h`", "not both"],
    );
}

#[test]
fn node_at_without_rotation() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
h = { at = "a", rot = false }  # <-
"#,
        &["node `h`", "rot = false"],
    );
}

#[test]
fn node_at_not_a_name() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
h = { at = 1 }  # <-
"#,
        &["node `h`", "`at` must name a node"],
    );
}

#[test]
fn no_nodes_section() {
    match parse_model("[model]\nname = \"x\"\n", "m.toml") {
        Err(InputError::File { file, message }) => {
            assert_eq!(file, "m.toml");
            assert!(message.contains("[nodes]"), "{message}");
        }
        other => panic!("expected a file-level error, got {:?}", other.err()),
    }
}

#[test]
fn nodes_not_a_table() {
    check(
        r#"nodes = 3  # <-
"#,
        &["[nodes]"],
    );
}

// ---- elements ----

const AB: &str = "[nodes]\na = [0.0, 0.0, 0.0]\nb = [1.0, 0.0, 0.0]\nc = [1.0, 1.0, 0.0]\n";

#[test]
fn unknown_node_in_element() {
    check_ab(
        r#"
[[truss]]  # <-
id = "t1"
nodes = ["a", "zz"]
"#,
        &["element `t1`", "node `zz` is not defined"],
    );
}

#[test]
fn unknown_node_in_second_element() {
    check_ab(
        r#"
[[truss]]
id = "t1"
nodes = ["a", "b"]
[[rigid]]  # <-
id = "body"
nodes = ["a", "b", "q"]
"#,
        &["element `body`", "node `q`"],
    );
}

#[test]
fn duplicate_element_id() {
    check_ab(
        r#"
[[truss]]
id = "t1"
nodes = ["a", "b"]
[[beam]]  # <-
id = "t1"
nodes = ["b", "c"]
"#,
        &["element `t1`", "defined twice"],
    );
}

#[test]
fn zero_length_truss() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
b = [0.0, 0.0, 0.0]
[[truss]]  # <-
id = "t1"
nodes = ["a", "b"]
"#,
        &["element `t1`", "zero length"],
    );
}

#[test]
fn zero_length_beam_to_hosted_node() {
    check(
        r#"[nodes]
a = [0.0, 0.0, 0.0]
h = { at = "a" }
[[beam]]  # <-
id = "w1"
nodes = ["a", "h"]
"#,
        &["element `w1`", "zero length"],
    );
}

#[test]
fn orientation_parallel_to_axis() {
    check_ab(
        r#"
[[beam]]  # <-
id = "w1"
nodes = ["a", "b"]
orient = [-2.0, 0.0, 0.0]
"#,
        &["element `w1`", "parallel"],
    );
}

#[test]
fn orientation_zero() {
    check_ab(
        r#"
[[beam]]  # <-
id = "w1"
nodes = ["a", "b"]
orient = [0.0, 0.0, 0.0]
"#,
        &["element `w1`", "orientation vector is zero"],
    );
}

#[test]
fn orientation_nan() {
    check_ab(
        r#"
[[beam]]  # <-
id = "w1"
nodes = ["a", "b"]
orient = [0.0, nan, 1.0]
"#,
        &["element `w1`", "`orient` must be finite", "NaN"],
    );
}

#[test]
fn orientation_wrong_length() {
    check_ab(
        r#"
[[beam]]
id = "w1"
nodes = ["a", "b"]
orient = [0.0, 1.0]  # <-
"#,
        &["element `w1`", "length 2"],
    );
}

#[test]
fn nonfinite_element_numbers() {
    for (kind, extra, field) in [
        ("truss", "EA = nan", "`EA`"),
        ("truss", "EA = inf", "`EA`"),
        ("beam", "ct = -inf", "`ct`"),
        ("hinge", "axis = [0.0, 0.0, 1.0]\nk = nan", "`k`"),
        ("hinge", "axis = [0.0, inf, 1.0]", "`axis`"),
    ] {
        check(
            &format!(
                r#"{AB}
[[{kind}]]  # <-
id = "e1"
nodes = ["a", "b"]
{extra}
"#
            ),
            &["element `e1`", field, "finite"],
        );
    }
}

#[test]
fn overflowing_number_in_element() {
    check_line(
        &format!("{AB}[[truss]]\nid = \"t1\"\nnodes = [\"a\", \"b\"]\nEA = 1e400\n"),
        8,
        &["element `t1`", "overflow"],
    );
}

#[test]
fn hinge_zero_axis() {
    check_ab(
        r#"
[[hinge]]  # <-
id = "h1"
nodes = ["a", "b"]
axis = [0.0, 0.0, 0.0]
"#,
        &["element `h1`", "`axis` must be non-zero"],
    );
}

#[test]
fn unknown_key_in_element() {
    check_ab(
        r#"
[[truss]]
id = "t1"
nodes = ["a", "b"]
[[truss]]
id = "t2"
nodes = ["b", "c"]
colour = "red"  # <-
"#,
        &["element `t2`", "unknown field `colour`"],
    );
}

#[test]
fn unknown_key_before_id() {
    check_ab(
        r#"
[[beam]]
colour = "red"  # <-
id = "w1"
nodes = ["a", "b"]
"#,
        &["element `w1`", "unknown field `colour`"],
    );
}

#[test]
fn rigid_has_no_modes() {
    check_ab(
        r#"
[[rigid]]
id = "body"
nodes = ["a", "b"]
free = [1]  # <-
"#,
        &["element `body`", "unknown field `free`"],
    );
}

#[test]
fn missing_element_fields() {
    check_ab(
        r#"
[[truss]]  # <-
nodes = ["a", "b"]
"#,
        &["[[truss]]", "missing field `id`"],
    );
    check_ab(
        r#"
[[beam]]  # <-
id = "w1"
"#,
        &["element `w1`", "missing field `nodes`"],
    );
    check_ab(
        r#"
[[hinge]]  # <-
id = "h1"
nodes = ["a", "b"]
"#,
        &["element `h1`", "missing field `axis`"],
    );
}

#[test]
fn element_section_not_an_array() {
    check_ab(
        r#"
[truss]  # <-
id = "t1"
nodes = ["a", "b"]
"#,
        &["[[truss]]"],
    );
}

#[test]
fn wrong_type_in_element() {
    check_ab(
        r#"
[[truss]]
id = "t1"
nodes = ["a", "b"]
free = "1"  # <-
"#,
        &["element `t1`", "invalid type"],
    );
}

#[test]
fn wrong_node_count() {
    for (kind, nodes, expected) in [
        (
            "truss",
            r#"["a", "b", "c"]"#,
            "a truss needs 2 nodes, found 3",
        ),
        ("beam", r#"["a"]"#, "a beam needs 2 nodes, found 1"),
        ("hinge", r#"[]"#, "a hinge needs 2 nodes, found 0"),
        (
            "rigid",
            r#"["a"]"#,
            "a rigid needs at least 2 nodes, found 1",
        ),
    ] {
        let axis = if kind == "hinge" {
            "axis = [0.0, 0.0, 1.0]"
        } else {
            ""
        };
        check(
            &format!(
                r#"{AB}
[[{kind}]]  # <-
id = "e1"
nodes = {nodes}
{axis}
"#
            ),
            &["element `e1`", expected],
        );
    }
}

#[test]
fn repeated_node_in_element() {
    check_ab(
        r#"
[[rigid]]  # <-
id = "body"
nodes = ["a", "b", "a"]
"#,
        &["element `body`", "node `a` appears twice"],
    );
}

#[test]
fn mode_out_of_range() {
    for (kind, list, mode, n) in [
        ("truss", "free = [2]", "mode 2", "modes 1 to 1"),
        ("truss", "input = [0]", "mode 0", "modes 1 to 1"),
        ("beam", "free = [2, 3, 7]", "mode 7", "modes 1 to 6"),
        ("beam", "input = [-1]", "mode -1", "modes 1 to 6"),
        ("hinge", "free = [4]", "mode 4", "modes 1 to 3"),
    ] {
        let axis = if kind == "hinge" {
            "axis = [0.0, 0.0, 1.0]"
        } else {
            ""
        };
        check(
            &format!(
                r#"{AB}
[[{kind}]]  # <-
id = "e1"
nodes = ["a", "b"]
{list}
{axis}
"#
            ),
            &["element `e1`", mode, "does not exist", n],
        );
    }
}

#[test]
fn mode_not_an_integer() {
    check_ab(
        r#"
[[beam]]
id = "w1"
nodes = ["a", "b"]
free = [2.5]  # <-
"#,
        &["element `w1`", "invalid type"],
    );
}

#[test]
fn mode_free_and_input() {
    check_ab(
        r#"
[[beam]]  # <-
id = "w1"
nodes = ["a", "b"]
free = [2, 3, 4]
input = [3]
"#,
        &["element `w1`", "mode 3", "both as free and as input"],
    );
}

// ---- fix and inputs ----

const TRUSS: &str = "[nodes]\na = [0.0, 0.0, 0.0]\nb = [1.0, 0.0, 0.0]\n[[truss]]\nid = \"t1\"\nnodes = [\"a\", \"b\"]\n";

#[test]
fn unknown_dof_name() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = ["x", "w"]  # <-
"#
        ),
        &["fix entry `a`", "unknown degree of freedom `w`"],
    );
    check(
        &format!(
            r#"{TRUSS}[inputs]
b = "X"  # <-
"#
        ),
        &["inputs entry `b`", "unknown degree of freedom `X`"],
    );
}

#[test]
fn dof_list_wrong_type() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = 3  # <-
"#
        ),
        &["fix entry `a`", "expected \"all\""],
    );
    check(
        &format!(
            r#"{TRUSS}[fix]
a = ["x", 1]  # <-
"#
        ),
        &["fix entry `a`", "degree-of-freedom name"],
    );
}

#[test]
fn rotation_dof_on_node_without_rotation() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = ["x", "y", "z", "rz"]  # <-
"#
        ),
        &["fix entry `a`", "`rz` is a rotation", "rot = true"],
    );
    check(
        &format!(
            r#"{TRUSS}[inputs]
b = ["ry"]  # <-
"#
        ),
        &["inputs entry `b`", "`ry` is a rotation"],
    );
}

#[test]
fn fix_or_input_of_unknown_node() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = "all"
q = "all"  # <-
"#
        ),
        &["fix entry `q`", "node `q` is not defined"],
    );
    check(
        &format!(
            r#"{TRUSS}[inputs]
q = ["x"]  # <-
"#
        ),
        &["inputs entry `q`", "node `q` is not defined"],
    );
}

#[test]
fn fixed_and_input() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = "all"
[inputs]
a = ["y"]  # <-
"#
        ),
        &["node `a`", "`y` is both fixed and an input"],
    );
}

/// Errors found only when the model is compiled (which nodes carry rotations is known then):
/// the place is looked up from the item the error names, at the entry's table header.
#[test]
fn compile_errors_name_the_entry() {
    // a moment on a node that only a truss uses: it has no rotation coordinates
    check(
        &format!("{TRUSS}[[load]]  # <-\nnode = \"b\"\nmoment = [0.0, 0.0, 1.0]\n"),
        &["load on node `b`", "a moment needs a rotational node"],
    );
    // an inertia tensor on such a node
    check(
        &format!(
            "{TRUSS}[[mass]]\nnode = \"b\"\nm = 1.0\n[[inertia]]  # <-\nnode = \"b\"\nI = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0]\n"
        ),
        &["`b`", "inertia", "is a rotation"],
    );
    // a prescribed rotation of such a node, after an input entry of the node
    check(
        &format!(
            "{TRUSS}[inputs]\nb = [\"x\"]\n[[prescribe]]  # <-\nnode = \"b\"\ndof = \"rz\"\nvalue = 0.1\n"
        ),
        &["inputs entry `b`", "`rz` is a rotation"],
    );
}

#[test]
fn duplicate_fix_entry() {
    check(
        &format!(
            r#"{TRUSS}[fix]
a = "all"
a = ["x"]  # <-
"#
        ),
        &["fix entry `a`", "defined twice"],
    );
}

// ---- file level ----

#[test]
fn unknown_section() {
    check(
        &format!(
            r#"{TRUSS}[materials]  # <-
E = 2.1e11
"#
        ),
        &["unknown section `materials`"],
    );
}

#[test]
fn single_bracket_material() {
    check(
        &format!(
            r#"{TRUSS}[material]  # <-
E = 2.1e11
"#
        ),
        &["`[material]` must be written `[[material]]`"],
    );
}

#[test]
fn unknown_model_key() {
    check(
        r#"[model]
name = "x"
title = "y"  # <-
[nodes]
a = [0.0, 0.0, 0.0]
"#,
        &["[model]", "unknown field `title`"],
    );
}

#[test]
fn malformed_toml() {
    // unclosed array: reported at the end of the line
    check_line(
        "[nodes]\na = [0.0, 0.0, 0.0]\nb = [1.0, 0.0\n",
        3,
        &["node `b`", "expected `]`"],
    );
    // unclosed header
    check_line(
        "[nodes]\na = [0.0, 0.0, 0.0]\n[[truss]\nid = \"t1\"\n",
        3,
        &["element `t1`", "expected `]`"],
    );
    // unterminated string: the id cannot be read, the table type is named
    check_line(
        "[nodes]\na = [0.0, 0.0, 0.0]\n[[truss]]\nid = \"t1\nnodes = [\"a\", \"b\"]\n",
        4,
        &["[[truss]]"],
    );
    // a value without a key
    check_line("[nodes]\n= [0.0, 0.0, 0.0]\n", 2, &[]);
}

#[test]
fn empty_file() {
    assert!(matches!(
        parse_model("", "m.toml"),
        Err(InputError::File { .. })
    ));
}

#[test]
fn message_format() {
    let e = parse_model(
        "[nodes]\na = [0.0, 0.0, 0.0]\nb = [0.0, 0.0, 0.0]\n[[truss]]\nid = \"t1\"\nnodes = [\"a\", \"b\"]\n",
        "dir/m.toml",
    )
    .unwrap_err();
    let s = e.to_string();
    assert!(s.starts_with("dir/m.toml:4:1: element `t1`"), "{s}");
}

// ---- good input ----

#[test]
fn node_forms_and_file_order() {
    let m = ok(r#"[nodes]
z = [0.0, 0.0, 0.0]
m = { x = [1.0, 0.0, 0.0] }
a = { x = [2.0, 0.0, 0.0], rot = true }
h = { at = "m" }
hh = { at = "h", rot = true }
[[truss]]
id = "t"
nodes = ["z", "m"]
"#);
    assert_eq!(m.node_names(), ["z", "m", "a", "h", "hh"]);
    let n = |s: &str| &m.nodes[m.node_id(s).unwrap()];
    assert!(!n("z").rot() && !n("m").rot());
    assert!(n("a").rot() && n("h").rot() && n("hh").rot());
    // hosted nodes share the host's position coordinates, a chain resolves to the first host
    assert_eq!(n("h").ix_pos, n("m").ix_pos);
    assert_eq!(n("hh").ix_pos, n("m").ix_pos);
    assert_eq!(n("hh").x0, [1.0, 0.0, 0.0]);
    // 3 + 3 + (3 + 4) + 4 + 4
    assert_eq!(m.nx, 21);
}

#[test]
fn integers_are_numbers() {
    let m = ok(
        "[nodes]\na = [0, 1, -2]\nb = [1, 1, -2]\n[[truss]]\nid = \"t\"\nnodes = [\"a\", \"b\"]\n",
    );
    assert_eq!(m.nodes[0].x0, [0.0, 1.0, -2.0]);
}

#[test]
fn partition_letters() {
    let m = ok(r#"[model]
name = "guide"
description = "ignored"
[nodes]
g = [0.0, 0.0, 0.0]
p = [0.0, 0.0, 0.1]
[fix]
g = "all"
[inputs]
p = ["x", "rz"]
[[beam]]
id = "w1"
nodes = ["g", "p"]
orient = [1.0, 0.0, 0.0]
free = [2, 3, 4, 5, 6]
input = [1]
"#);
    assert_eq!(m.name, "guide");
    let g = &m.nodes[0];
    let p = &m.nodes[1];
    // "all" on a rotating node fixes x, y, z and λ1..λ3; λ0 stays dependent
    for d in 0..3 {
        assert_eq!(m.partition.x[g.ix_pos + d], CoordKind::Fixed);
    }
    let r = g.ix_rot.unwrap();
    assert_eq!(m.partition.x[r], CoordKind::Free);
    for k in 1..4 {
        assert_eq!(m.partition.x[r + k], CoordKind::Fixed);
    }
    // inputs: x and rz (λ3) of p
    assert_eq!(m.partition.x[p.ix_pos], CoordKind::Input);
    assert_eq!(m.partition.x[p.ix_pos + 1], CoordKind::Free);
    assert_eq!(m.partition.x[p.ix_rot.unwrap() + 3], CoordKind::Input);
    assert_eq!(
        m.partition.e,
        [
            DefKind::Input,
            DefKind::Free,
            DefKind::Free,
            DefKind::Free,
            DefKind::Free,
            DefKind::Free
        ]
    );
}

#[test]
fn element_counts() {
    let m = ok(r#"[nodes]
a = [0.0, 0.0, 0.0]
b = [1.0, 0.0, 0.0]
c = [0.0, 1.0, 0.0]
d = { x = [0.0, 0.0, 1.0], rot = true }
h = { at = "b" }
[[truss]]
id = "t"
nodes = ["a", "b"]
[[hinge]]
id = "hg"
nodes = ["b", "h"]
axis = [0, 0, 1]
free = [1]
[[rigid]]
id = "body"
nodes = ["a", "c", "d"]
"#);
    // elements in file order: truss 1, hinge 3, rigid: 3 (c translational) + 6 (d rotates)
    let names: Vec<&str> = m.elements.iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["t", "hg", "body"]);
    assert_eq!(m.ne, 1 + 3 + 9);
    assert_eq!(
        &m.partition.e[1..4],
        [DefKind::Free, DefKind::Fixed, DefKind::Fixed]
    );
    // the rigid body's first node gets a rotation; c does not
    assert!(m.nodes[m.node_id("a").unwrap()].rot());
    assert!(!m.nodes[m.node_id("c").unwrap()].rot());
}

#[test]
fn example_twelve_truss() {
    let text = include_str!("../../../../examples/twelve_truss.toml");
    let m = ok(text);
    assert_eq!(m.nodes.len(), 8);
    assert_eq!(m.elements.len(), 12);
    assert_eq!(m.nx, 24);
}

#[test]
fn spin_in_static_section() {
    // a model needs an element
    const AB: &str = "[nodes]\na = [0.0, 0.0, 0.0]\nb = [1.0, 0.0, 0.0]\n[[truss]]\nid = \"t\"\nnodes = [\"a\", \"b\"]\n";
    let m = ok(&format!(
        "{AB}[static]\nspin = [0.0, 0.0, 12.5]\nspin_point = [1.0, 2.0, 0.0]\n"
    ));
    let spin = m.loads.spin.expect("spin read");
    assert_eq!(spin.omega, [0.0, 0.0, 12.5]);
    assert_eq!(spin.point, [1.0, 2.0, 0.0]);
    // the axis point defaults to the origin
    let m = ok(&format!("{AB}[static]\nspin = [3.0, 0.0, 0.0]\n"));
    assert_eq!(m.loads.spin.map(|s| s.point), Some([0.0; 3]));
    assert_eq!(ok(AB).loads.spin, None);
}

#[test]
fn bad_spin() {
    check_ab(
        "\n[static]  # <-\nspin_point = [0.0, 0.0, 0.0]\n",
        &["[static]", "`spin_point` needs `spin`"],
    );
    check_ab(
        "\n[static]  # <-\nspin = [0.0, nan, 1.0]\n",
        &["[static]", "spin"],
    );
    check_ab(
        "\n[static]\nspin = [0.0, 1.0]  # <-\n",
        &["invalid length 2"],
    );
}

// ---- reliability (issue 15) ----

#[test]
fn a_model_needs_an_element() {
    let e = parse_model(AB, "m.toml").unwrap_err().to_string();
    assert!(
        e.starts_with("m.toml: ") && e.contains("no elements"),
        "{e}"
    );
}

#[test]
fn errors_in_data_tables_name_the_item() {
    check_ab(
        "\n[[material]]  # <-\nid = \"steel\"\nnu = 0.3\n",
        &["material `steel`", "missing field `E`"],
    );
    check_ab(
        "\n[[section]]\nid = \"s\"\nshape = \"rectangle\"\nw = 0.02\nt = 0.001\nfoo = 1  # <-\n",
        &["section `s`", "unknown field `foo`"],
    );
    check_ab(
        "\n[[load]]\nnode = \"a\"\n[[load]]\nnode = \"b\"\nforce = [1.0, 2.0]  # <-\n",
        &["[[load]] 2 (on `b`)", "invalid length 2"],
    );
    check_ab(
        "\n[[mass]]\nnode = \"b\"\nm = true  # <-\n",
        &["[[mass]] 1 (on `b`)", "invalid type"],
    );
    check_ab(
        "\n[[inertia]]\nnode = \"b\"\nI = [1.0, 2.0]  # <-\n",
        &["[[inertia]] 1 (on `b`)", "invalid length 2"],
    );
    check_ab(
        "\n[[prescribe]]\nnode = \"b\"\ndof = \"x\"\nvalue = [1.0]  # <-\n",
        &["[[prescribe]] 1 (on `b`)", "invalid type"],
    );
    check_ab(
        "\n[static]\nsteps = -1  # <-\n",
        &["[static]", "expected usize"],
    );
    check_ab(
        "\n[static]\nmax_iterations = 0  # <-\n",
        &["[static]", "`max_iterations` must be from 1 to 10000"],
    );
    check_ab(
        "\n[[section]]  # <-\nid = \"g\"\nshape = \"general\"\nA = 1.0\nIy = 1.0\nIz = 1.0\nJ = 1.0\nk = -0.5\n",
        &["section `g`", "`k` (the shear factor) must be ≥ 0", "-0.5"],
    );
}

#[test]
fn a_coordinate_is_prescribed_once() {
    // directly, and through a node `at` another (they share the translations)
    let body = "[nodes]\na = [0.0, 0.0, 0.0]\nb = { x = [1.0, 0.0, 0.0], rot = true }\nh = { at = \"b\" }\n[fix]\na = \"all\"\n[[beam]]\nid = \"w\"\nnodes = [\"a\", \"h\"]\norient = [0.0, 1.0, 0.0]\n";
    check(
        &format!("{body}[[prescribe]]\nnode = \"b\"\ndof = \"x\"\nvalue = 0.1\n[[prescribe]]  # <-\nnode = \"h\"\ndof = \"x\"\nvalue = 0.2\n"),
        &["[[prescribe]] 2", "coordinate x of node `h`", "lines 11 and 15"],
    );
    // rotations of a node `at` another are its own
    ok(&format!("{body}[[prescribe]]\nnode = \"b\"\ndof = \"rz\"\nvalue = 0.1\n[[prescribe]]\nnode = \"h\"\ndof = \"rz\"\nvalue = 0.2\n"));
}

#[test]
fn a_duplicate_key_before_any_table_is_named() {
    check(
        "rho_a = 1.0\nrho_a = 1.0  # <-\n[nodes]\na = [0.0, 0.0, 0.0]\n",
        &["`rho_a` is given twice before the first [table]"],
    );
}
