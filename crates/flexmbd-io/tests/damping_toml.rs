//! Material damping (`damping`, the Kelvin–Voigt retardation time τ [s]) in TOML models
//! (docs/model-format.md, docs/simulation.md): on a material for the beams made of it (and
//! their segments), on an element over its material's, written back, and its errors with file
//! and line.

use flexmbd_io::model_toml::{parse_model_file, parse_spec};

const MODEL: &str = r#"
[nodes]
a = [0.0, 0.0, 0.0]
b = [0.1, 0.0, 0.0]
c = [0.2, 0.0, 0.0]

[fix]
a = "all"

[[material]]
id = "steel"
E = 210e9
nu = 0.3
rho = 7800.0
damping = 2e-4

[[section]]
id = "sheet"
shape = "rectangle"
w = 0.02
t = 0.2e-3

[[beam]]
id = "leaf"
nodes = ["a", "b"]
section = "sheet"
material = "steel"
segments = 3

[[beam]]
id = "own"
nodes = ["b", "c"]
section = "sheet"
material = "steel"
damping = 1e-3

[[truss]]
id = "bar"
nodes = ["a", "c"]
EA = 1e5
damping = 5e-3

[[truss]]
id = "plain"
nodes = ["a", "c"]
EA = 1e5
"#;

#[test]
fn damping_of_materials_and_elements_reaches_every_element_and_is_written_back() {
    let f = parse_model_file(MODEL, "d.toml").unwrap_or_else(|e| panic!("{e}"));
    let tau: Vec<(&str, f64)> = f
        .model
        .elements
        .iter()
        .map(|e| (e.name.as_str(), e.damping))
        .collect();
    assert_eq!(
        tau,
        vec![
            ("leaf:1", 2e-4),
            ("leaf:2", 2e-4),
            ("leaf:3", 2e-4),
            ("own", 1e-3),
            ("bar", 5e-3),
            ("plain", 0.0)
        ]
    );
    let spec = parse_spec(MODEL, "d.toml").unwrap();
    let written = spec.to_toml().unwrap();
    let again = parse_spec(&written, "w.toml").unwrap();
    assert_eq!(again.without_comments(), spec.without_comments());
    assert_eq!(written.matches("damping = ").count(), 3, "{written}");
}

#[test]
fn bad_damping_is_refused_with_file_line_and_item() {
    let neg = MODEL.replace("damping = 5e-3", "damping = -1.0");
    let e = parse_model_file(&neg, "d.toml").unwrap_err().to_string();
    let line = 1 + neg[..neg.find("id = \"bar\"").unwrap()]
        .matches('\n')
        .count()
        - 1;
    assert!(
        e.contains("d.toml") && e.contains("bar") && e.contains("≥ 0"),
        "{e}"
    );
    assert!(
        e.contains(&format!(":{line}")) || e.contains(&format!("line {line}")),
        "{e}"
    );
    let mat = MODEL.replace("damping = 2e-4", "damping = nan");
    let e = parse_model_file(&mat, "d.toml").unwrap_err().to_string();
    assert!(e.contains("steel") && e.contains("damping"), "{e}");
    let rigid = format!("{MODEL}\n[[rigid]]\nid = \"r\"\nnodes = [\"b\", \"c\"]\ndamping = 1.0\n");
    let e = parse_model_file(&rigid, "d.toml").unwrap_err().to_string();
    assert!(e.contains("damping"), "{e}");
}
