//! Tests of the spec: building, editing by names and paths, serialisation.

use super::*;
use crate::model_toml::{parse_model_file, parse_spec, write_toml};
use flexmbd_core::elements::Element;
use flexmbd_core::kinematics::check;
use flexmbd_core::{CoordKind, Model};

fn example(name: &str) -> ModelSpec {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(name);
    crate::model_toml::read_spec(&path).unwrap()
}

fn beam_props(m: &Model, name: &str) -> flexmbd_core::section::BeamProps {
    let i = m.elements.iter().position(|e| e.name == name).unwrap();
    match &m.elements[i].element {
        Element::Beam(b) => *b.props.clone().unwrap(),
        other => panic!("{other:?}"),
    }
}

fn node(name: &str, x: [f64; 3]) -> NodeSpec {
    NodeSpec {
        name: name.into(),
        place: NodePlace::Position { x, rot: false },
        comment: None,
        src: Src::default(),
    }
}

#[test]
fn specs_that_differ_only_in_lines_are_equal() {
    let text = "[nodes]\na = [0.0, 0.0, 0.0]\nb = [1.0, 0.0, 0.0]\n[[truss]]\nid = \"t\"\nnodes = [\"a\", \"b\"]\n";
    let a = parse_spec(text, "a.toml").unwrap();
    let b = parse_spec(&format!("\n\n# moved down\n{text}"), "b.toml").unwrap();
    assert_eq!(a.elements[0].src.line_number(), Some(4));
    assert_eq!(b.elements[0].src.line_number(), Some(7));
    assert_eq!(a, b);
}

/// Steel sheet of the parallel leaf-spring example, w = 20 mm: after `t` is set to 0.6 mm the
/// beams have EIy = E w t³/12 and EA = E w t (closed form, docs/statics.md), and the section
/// keeps its line.
#[test]
fn a_section_dimension_set_by_path_reaches_the_beams() {
    let mut spec = example("parallel_leaf_stroke.toml");
    let line = spec.sections[0].src.line_number();
    assert!(line.is_some());
    spec.set("sections.leaf.t", 0.6e-3).unwrap();
    assert_eq!(spec.get("sections.leaf.t").unwrap(), 0.6e-3);
    assert_eq!(spec.sections[0].src.line_number(), line);
    let m = spec.build().unwrap();
    let (e, w, t): (f64, f64, f64) = (210e9, 0.02, 0.6e-3);
    let p = beam_props(&m, "leaf1:3");
    assert!(
        (p.eiy - e * w * t.powi(3) / 12.0).abs() < 1e-12 * p.eiy,
        "{}",
        p.eiy
    );
    assert!((p.ea - e * w * t).abs() < 1e-9 * p.ea, "{}", p.ea);
}

#[test]
fn paths_address_nodes_settings_and_entries() {
    let mut spec = example("parallel_leaf_stroke.toml");
    spec.set("nodes.p.x", 0.001).unwrap();
    assert_eq!(
        spec.node("p").unwrap().place,
        NodePlace::Position {
            x: [0.001, 0.0, 0.0],
            rot: false
        }
    );
    spec.set("static.steps", 7).unwrap();
    assert_eq!(spec.statics.steps, Some(7));
    spec.set("simulate.t_end", 0.5).unwrap();
    assert_eq!(spec.simulate.as_ref().unwrap().t_end, Some(0.5));
    spec.set("elements.leaf2.segments", 2).unwrap();
    assert_eq!(
        spec.element("leaf2").unwrap().beam().unwrap().segments,
        Some(2)
    );
    spec.set("prescribed.p.value", 0.002).unwrap();
    assert_eq!(spec.prescribed[0].value, 0.002);
    spec.set("prescribed.#1.value", 0.003).unwrap();
    assert_eq!(spec.prescribed[0].value, 0.003);
    spec.set("materials.steel.E", 200e9).unwrap();
    assert_eq!(spec.materials[0].e, 200e9);
    spec.set("name", "edited").unwrap();
    let m = spec.build().unwrap();
    assert_eq!(m.name, "edited");
    // 2 segments of leaf2: its one intermediate node, at the middle
    let mid = m.node_id("leaf2:1").unwrap();
    assert_eq!(m.nodes[mid].x0, [0.025, 0.0, -0.025]);
    assert!(m.node_id("leaf2:2").is_none());
}

#[test]
fn a_path_that_does_not_exist_is_an_error_naming_it() {
    let mut spec = example("parallel_leaf_stroke.toml");
    for (path, words) in [
        ("sections.sheet.t", "no entry `sheet`"),
        ("sections.leaf.thickness", "no key `thickness`"),
        ("sections.leaf.t.0", "has no keys"),
        ("bogus.x", "no `bogus` in a model"),
        ("nodes", "needs the name of an item"),
        ("loads.#9.force", "from #1 to #"),
        ("nodes.p.x.0", "has no keys"),
    ] {
        let e = spec.set(path, 1.0).unwrap_err().to_string();
        assert!(e.starts_with(&format!("path `{path}`: ")), "{e}");
        assert!(e.contains(words), "{path}: {e}");
        assert!(spec.get(path).is_err(), "{path}");
    }
    let e = spec.set("sections.leaf.t", "thin").unwrap_err().to_string();
    assert!(
        e.contains("sections.leaf.t") && e.contains("invalid type"),
        "{e}"
    );
    // nothing changed
    assert_eq!(spec, example("parallel_leaf_stroke.toml"));
}

/// The tripod of docs/model-format.md built by names: three bars to a free node are a
/// structure, a fourth makes it over-constrained (Dcc 4 × 3 of rank 3, one self-stress; Maxwell
/// count 3 coordinates − 4 bars); removing the fourth bar gives back the exactly constrained one.
#[test]
fn a_model_built_and_edited_by_names() {
    let mut spec = ModelSpec::new("tripod");
    let s = 0.8660254;
    for (n, x) in [
        ("s1", [1.0, 0.0, 0.0]),
        ("s2", [-0.5, s, 0.0]),
        ("s3", [-0.5, -s, 0.0]),
        ("s4", [0.0, 0.0, -1.0]),
        ("t", [0.0, 0.0, 1.0]),
    ] {
        spec.add_node(node(n, x)).unwrap();
        if n != "t" {
            spec.set_fix(n, None);
        }
    }
    for (b, n) in [("b1", "s1"), ("b2", "s2"), ("b3", "s3"), ("b4", "s4")] {
        let e = ElementEntrySpec::new(b, &[n, "t"], ElementKind::Truss { ea: 1e6 });
        spec.add_element(e).unwrap();
    }
    let e = spec.add_node(node("t", [0.0; 3])).unwrap_err();
    assert_eq!(e.to_string(), "node `t` is defined already");
    let m = spec.build().unwrap();
    let a = check(&m, &m.partition, &m.x0(), &Default::default()).unwrap();
    assert_eq!((a.m(), a.n(), a.rank, a.n_self_stresses()), (4, 3, 3, 1));
    spec.remove_element("b4").unwrap();
    assert!(spec.remove_element("b4").is_err());
    let m = spec.build().unwrap();
    let a = check(&m, &m.partition, &m.x0(), &Default::default()).unwrap();
    assert_eq!((a.rank, a.n_motions(), a.n_self_stresses()), (3, 0, 0));
    // replace: the truss b1 becomes one without stiffness, in its place
    let mut b1 = spec.element("b1").unwrap().clone();
    b1.kind = ElementKind::Truss { ea: 0.0 };
    let old = spec.replace_element(b1).unwrap();
    assert_eq!(old.kind, ElementKind::Truss { ea: 1e6 });
    assert_eq!(spec.elements[0].name, "b1");
    // inputs, loads, masses, strokes by node
    spec.set_input("t", Some(&[Dof::Z]));
    spec.set_load("t", [1.0, 0.0, 0.0], [0.0; 3]);
    spec.set_load("t", [2.0, 0.0, 0.0], [0.0; 3]);
    assert_eq!(spec.loads.len(), 1);
    spec.set_mass("t", 0.5);
    spec.set_mass("t", 0.25);
    assert_eq!(spec.masses.len(), 1);
    let z = PrescribeTarget::Coordinate {
        node: "t".into(),
        dof: Dof::Z,
    };
    spec.set_stroke(z.clone(), 1e-3);
    spec.set_stroke(z.clone(), 2e-3);
    assert_eq!(spec.prescribed.len(), 1);
    let m = spec.build().unwrap();
    let t = m.node_id("t").unwrap();
    assert_eq!(m.partition.x[m.nodes[t].ix_pos + 2], CoordKind::Input);
    assert_eq!(m.loads.point_masses, vec![(t, 0.25)]);
    spec.remove_stroke(&z).unwrap();
    spec.remove_mass("t").unwrap();
    assert_eq!(spec.remove_loads("t").unwrap().len(), 1);
    spec.remove_input("t").unwrap();
    assert!(spec.remove_input("t").is_err());
    // removing a node leaves its elements: the build names the missing node
    spec.remove_node("s1").unwrap();
    let e = spec.build().unwrap_err();
    assert!(e.to_string().contains("s1"), "{e}");
}

#[test]
fn materials_and_sections_by_name() {
    let mut spec = example("parallel_leaf_stroke.toml");
    let mut steel = spec.materials[0].clone();
    steel.e = 70e9;
    spec.replace_material(steel.clone()).unwrap();
    steel.name = "alu".into();
    spec.add_material(steel).unwrap();
    assert!(spec.add_section(spec.sections[0].clone()).is_err());
    let e = spec.remove_section("nope").unwrap_err();
    assert_eq!(e.to_string(), "section `nope` is not defined");
    spec.remove_material("alu").unwrap();
    let m = spec.build().unwrap();
    let (e, w, t): (f64, f64, f64) = (70e9, 0.02, 0.0003);
    let p = beam_props(&m, "leaf1:1");
    assert!((p.ea - e * w * t).abs() < 1e-9 * p.ea);
    // a section that no beam may lose its material: the build says so
    spec.remove_material("steel").unwrap();
    let e = spec.build().unwrap_err();
    assert!(
        e.to_string().contains("material `steel` is not defined"),
        "{e}"
    );
}

#[test]
fn every_example_serialises_to_json_and_back() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    for p in std::fs::read_dir(dir).unwrap() {
        let p = p.unwrap().path();
        if p.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        let spec = crate::model_toml::read_spec(&p).unwrap();
        let json = serde_json::to_string(&spec).unwrap();
        let back: ModelSpec = serde_json::from_str(&json).unwrap();
        assert_eq!(back, spec, "{}: {json}", p.display());
    }
}

/// What the writer writes, the reader reads (a spec as the SPACAR reader makes it: repeated
/// supports, constants given directly, dynamic inputs), and the static build leaves the
/// dynamic inputs free.
#[test]
fn writes_what_the_reader_reads() {
    let at = |line| Src::line(line);
    let spec = ModelSpec {
        name: "a \"quoted\" name\\".into(),
        header: vec!["two\nlines".into()],
        nodes: vec![
            NodeSpec {
                comment: Some("first".into()),
                ..node("1", [0.0; 3])
            },
            NodeSpec {
                name: "1@2".into(),
                place: NodePlace::At("1".into()),
                comment: None,
                src: at(1),
            },
            NodeSpec {
                name: "3".into(),
                place: NodePlace::Position {
                    x: [-2.5e20, 1e-7, 0.1],
                    rot: true,
                },
                comment: None,
                src: at(2),
            },
        ],
        elements: vec![ElementEntrySpec {
            free: vec![2, 3],
            input: vec![4],
            comments: vec!["BEAM 1".into()],
            ..ElementEntrySpec::new(
                "1",
                &["1@2", "3"],
                ElementKind::Beam(BeamSpec {
                    orient: Some([0.0, 0.0, 1.0]),
                    fixed: vec![5],
                    rho_a: Some(0.25),
                    ..BeamSpec::direct(1e6, 2.0, 3.0, 0.0, 0.25)
                }),
            )
        }],
        fix: vec![
            DofEntry {
                comment: Some("FIX 1 1 2".into()),
                ..DofEntry::new("1", Some(&[Dof::Y, Dof::X]))
            },
            DofEntry {
                comment: Some("FIX 1 3".into()),
                ..DofEntry::new("1", Some(&[Dof::Z]))
            },
        ],
        dynamic_inputs: vec![DofEntry::new("3", Some(&[Dof::Z]))],
        loads: vec![LoadEntry {
            node: "1@2".into(),
            force: [0.0, 1.0, 0.0],
            moment: [0.0, 0.0, 0.5],
            history: None,
            comments: vec!["a load".into()],
            src: at(7),
        }],
        masses: vec![MassEntry {
            node: "3".into(),
            m: 0.5,
            comments: vec![],
            src: at(8),
        }],
        prescribed: vec![
            PrescribeEntry {
                target: PrescribeTarget::Coordinate {
                    node: "3".into(),
                    dof: Dof::Rz,
                },
                value: 0.1,
                history: None,
                comments: vec![],
                src: at(9),
            },
            PrescribeEntry {
                target: PrescribeTarget::Deformation {
                    element: "1".into(),
                    mode: 4,
                },
                value: -1e-3,
                history: None,
                comments: vec![],
                src: at(10),
            },
        ],
        statics: StaticSpec {
            steps: Some(3),
            tol_force: Some(1e-7),
            gravity: Some([0.0, -9.81, 0.0]),
            comments: vec!["settings".into()],
            src: at(11),
            ..Default::default()
        },
        footer: vec!["end".into()],
        ..Default::default()
    };
    let text = write_toml(&spec).unwrap();
    let a = spec.build().unwrap();
    let b = parse_model_file(&text, "w.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert_eq!(b.settings.steps, Some(3));
    assert_eq!(b.settings.tol_force, Some(1e-7));
    let b = b.model;
    assert_eq!(a.name, b.name);
    assert_eq!(a.nx, b.nx);
    assert_eq!(a.partition, b.partition);
    assert_eq!(a.loads, b.loads);
    assert_eq!(a.explicit_rigid, b.explicit_rigid);
    let st = spec.build_static().unwrap();
    assert_eq!(st.settings.steps, Some(3));
    let z = st.model.nodes[2].x_index(Dof::Z).unwrap();
    assert_eq!(st.model.partition.x[z], CoordKind::Free);
    assert_eq!(a.partition.x[z], CoordKind::Input);
    assert_eq!(b.nodes[2].x0, [-2.5e20, 1e-7, 0.1]);
    assert!(text.contains("\"1\" = [\"x\", \"y\", \"z\"]  # FIX 1 1 2; FIX 1 3"));
}

#[test]
fn errors_carry_the_line() {
    let spec = ModelSpec {
        nodes: vec![NodeSpec {
            src: Src::line(7),
            ..node("1", [0.0; 3])
        }],
        fix: vec![DofEntry {
            src: Src::line(9),
            ..DofEntry::new("1", Some(&[Dof::Rx]))
        }],
        elements: vec![ElementEntrySpec::new(
            "t",
            &["1", "1"],
            ElementKind::Truss { ea: 0.0 },
        )],
        ..Default::default()
    };
    let e = spec.build().unwrap_err();
    assert_eq!(e.line(), None, "{e}"); // the element has no place
    let spec = ModelSpec {
        elements: vec![],
        ..spec
    };
    let e = spec.build().unwrap_err();
    assert_eq!(e.line(), Some(9), "{e}");
}
