//! `[[freedom]]`, the intended freedom of the kinematic check (docs/model-format.md): read into
//! the `ModelSpec` and the `ModelFile`, written back, and its errors with file and line.

use flexmbd_core::kinematics::freedom::{FreedomMotion, IntendedFreedom};
use flexmbd_io::model_toml::{parse_model_file, parse_spec};

const BASE: &str = r#"
[nodes]
b1 = [0.0, 0.0, -0.05]
t1 = [0.0, 0.0, 0.0]
t2 = [0.05, 0.0, 0.0]

[fix]
b1 = "all"

[[beam]]
id = "leaf"
nodes = ["b1", "t1"]
free = [2, 3, 4]

[[rigid]]
id = "platform"
nodes = ["t1", "t2"]
"#;

#[test]
fn freedoms_are_read_built_and_written_back() {
    let text = format!(
        "{BASE}\n[[freedom]]\nbody = \"platform\"\ntranslation = [1, 0, 0]\n\n\
         [[freedom]]\nbody = \"t2\"\nrotation = {{ point = [0.0, 0.0, -0.05], axis = [0, 1, 0], pitch = 0.001 }}\n"
    );
    let f = parse_model_file(&text, "f.toml").unwrap();
    assert_eq!(
        f.freedom,
        vec![
            IntendedFreedom {
                body: "platform".into(),
                motion: FreedomMotion::Translation {
                    direction: [1.0, 0.0, 0.0]
                },
            },
            IntendedFreedom {
                body: "t2".into(),
                motion: FreedomMotion::Rotation {
                    point: [0.0, 0.0, -0.05],
                    axis: [0.0, 1.0, 0.0],
                    pitch: 0.001
                },
            },
        ]
    );
    let spec = parse_spec(&text, "f.toml").unwrap();
    let written = spec.to_toml().unwrap();
    assert!(written.contains("[[freedom]]"), "{written}");
    let again = parse_spec(&written, "w.toml").unwrap();
    assert_eq!(again.without_comments(), spec.without_comments());
}

/// The error of `extra` appended to the base model.
fn error(extra: &str) -> String {
    let text = format!("{BASE}\n{extra}");
    match parse_model_file(&text, "f.toml") {
        Ok(_) => panic!("accepted: {extra}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_freedoms_name_file_line_and_item() {
    // the [[freedom]] header is line 20 of the text (BASE has 19 lines with its first empty one)
    let line = BASE.lines().count() + 2;
    let e = error("[[freedom]]\nbody = \"nope\"\ntranslation = [1, 0, 0]\n");
    assert!(e.contains(&format!("f.toml:{line}")), "{e}");
    assert!(e.contains("[[freedom]] 1") && e.contains("`nope`"), "{e}");
    let e = error(
        "[[freedom]]\nbody = \"platform\"\ntranslation = [1, 0, 0]\n\
         rotation = { point = [0, 0, 0], axis = [0, 0, 1] }\n",
    );
    assert!(e.contains("exactly one"), "{e}");
    let e = error("[[freedom]]\nbody = \"platform\"\ntranslation = [0, 0, 0]\n");
    assert!(e.contains("non-zero"), "{e}");
    let e = error("[[freedom]]\nbody = \"platform\"\ntranslate = [1, 0, 0]\n");
    assert!(e.contains("translate"), "{e}");
}
