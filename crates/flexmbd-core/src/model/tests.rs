use super::*;

#[test]
fn builder_reports_items() {
    let mut b = ModelBuilder::new("t");
    b.add_node("a", [0.0; 3], false).unwrap();
    assert_eq!(
        b.add_node("a", [1.0; 3], false).unwrap_err(),
        ModelError::DuplicateNode { node: "a".into() }
    );
    b.add_node("b", [0.0; 3], false).unwrap();
    let e = b.add_element("t1", &["a", "b"], ElementSpec::Truss { ea: 0.0 }, &[], &[]);
    assert!(matches!(e, Err(ModelError::ZeroLength { .. })));
    let e = b.add_element("t1", &["a", "c"], ElementSpec::Truss { ea: 0.0 }, &[], &[]);
    assert!(matches!(e, Err(ModelError::UnknownNode { .. })));
    b.fix("a", Some(&[Dof::Rx])).unwrap();
    assert!(matches!(b.build(), Err(ModelError::NoRotation { .. })));
}

#[test]
fn beam_chain_names_positions_and_section() {
    let props = crate::section::BeamProps {
        ea: 2.0,
        gj: 3.0,
        eiy: 4.0,
        eiz: 5.0,
        rho_a: 0.5,
        ..Default::default()
    };
    let mut b = ModelBuilder::new("chain");
    let ids = b
        .add_beam_chain(
            "s:",
            [1.0, 0.0, 0.0],
            [1.0, 3.0, 0.0],
            3,
            Some([0.0, 0.0, 1.0]),
            Some(props),
        )
        .unwrap();
    assert_eq!(ids, vec![0, 1, 2, 3]);
    // names must stay unique
    let e = b.add_beam_chain("s:", [0.0; 3], [1.0; 3], 2, None, None);
    assert!(matches!(e, Err(ModelError::DuplicateNode { .. })), "{e:?}");
    assert!(matches!(
        b.add_beam_chain("t", [0.0; 3], [1.0; 3], 0, None, None),
        Err(ModelError::BadValue { .. })
    ));
    b.fix("s:n0", None).unwrap();
    let m = b.build().unwrap();
    assert_eq!(m.node_id("s:n2"), Some(2));
    assert_eq!(m.nodes[2].x0, [1.0, 2.0, 0.0]);
    assert_eq!(m.elements.len(), 3);
    assert_eq!(m.elements[1].name, "s:b1");
    let Element::Beam(beam) = &m.elements[1].element else {
        panic!("a beam");
    };
    assert_eq!(beam.nodes, [1, 2]);
    assert!((beam.l0 - 1.0).abs() < 1e-15);
    assert_eq!(beam.stiffness, [2.0, 3.0, 4.0, 5.0]);
    assert_eq!(beam.frame[2], [1.0, 0.0, 0.0]);
    assert_eq!(m.elements[2].element.ne(), 6);
}

#[test]
fn element_data_by_name_after_many_elements() {
    // lookups by name (section data, rigid modes, prescribed deformations) on a long chain
    let mut b = ModelBuilder::new("long");
    b.add_beam_chain("", [0.0; 3], [1.0, 0.0, 0.0], 2000, None, None)
        .unwrap();
    b.set_rigid_modes("b1999", &[1]).unwrap();
    b.prescribe_deformation("b1000", 3, 1e-3).unwrap();
    assert!(matches!(
        b.set_beam_props("n5", Default::default()),
        Err(ModelError::NotA { .. })
    ));
    b.fix("n0", None).unwrap();
    let m = b.build().unwrap();
    assert!(m.explicit_rigid[m.elements[1999].ie]);
    assert_eq!(m.partition.e[m.elements[1000].ie + 2], DefKind::Input);
    assert_eq!(
        m.loads.prescribed[0].target,
        Target::Deformation(m.elements[1000].ie + 2)
    );
}

#[test]
fn rotations_only_where_used() {
    let mut b = ModelBuilder::new("t");
    b.add_node("a", [0.0; 3], false).unwrap();
    b.add_node("b", [1.0, 0.0, 0.0], false).unwrap();
    b.add_node("c", [2.0, 0.0, 0.0], false).unwrap();
    b.add_element("t", &["a", "b"], ElementSpec::Truss { ea: 0.0 }, &[], &[])
        .unwrap();
    b.add_element(
        "w",
        &["b", "c"],
        ElementSpec::Beam {
            orient: None,
            ct: 0.0,
        },
        &[2],
        &[],
    )
    .unwrap();
    b.fix("a", None).unwrap();
    let m = b.build().unwrap();
    assert_eq!(m.nx, 3 + 7 + 7);
    assert_eq!(m.ne, 7);
    assert_eq!(&m.partition.x[0..3], &[CoordKind::Fixed; 3]);
    assert_eq!(m.partition.e[2], DefKind::Free);
    assert_eq!(m.deformation_owner(6), (1, 5));
}

/// The owner of every coordinate, with a node `at` another (its Euler parameters far from the
/// position it shares with its host; this used to index out of bounds).
#[test]
fn coordinate_owner_of_hosted_nodes() {
    let mut b = ModelBuilder::new("t");
    b.add_node("g", [0.0; 3], true).unwrap();
    b.add_node_at("h", "g").unwrap();
    b.add_node("p", [1.0, 0.0, 0.0], false).unwrap();
    let m = b.build().unwrap();
    let owners: Vec<_> = (0..m.nx).map(|i| m.coordinate_owner(i).unwrap()).collect();
    let labels = ["x", "y", "z", "lambda0", "lambda1", "lambda2", "lambda3"];
    let mut want: Vec<(usize, &str)> = labels.iter().map(|l| (0, *l)).collect();
    want.extend(labels[3..].iter().map(|l| (1, *l)));
    want.extend(labels[..3].iter().map(|l| (2, *l)));
    assert_eq!(owners, want);
    assert_eq!(m.coordinate_owner(m.nx), None);
}

/// A static path depends on its load factor only through non-zero loads, gravity or rotation
/// and non-zero prescribed values; without them every load step is the first one's state.
#[test]
fn loads_that_scale_with_the_load_factor() {
    let chain = || {
        let mut b = ModelBuilder::new("t");
        let props = crate::section::BeamProps::from_section(
            &crate::section::Material {
                e: 210e9,
                g: 80e9,
                rho: 7800.0,
            },
            &crate::section::Shape::Rectangle { w: 0.01, t: 0.001 },
            true,
        );
        b.add_beam_chain(
            "",
            [0.0; 3],
            [0.1, 0.0, 0.0],
            4,
            Some([0.0, 1.0, 0.0]),
            Some(props),
        )
        .unwrap();
        b.fix("n0", None).unwrap();
        b
    };
    let m = chain().build().unwrap();
    assert!(!m.loads.scale_with_load_factor());
    let opts = crate::statics::StaticOptions {
        steps: 3,
        ..Default::default()
    };
    let sol = crate::statics::solve(&m, &opts, |_, _| {}).unwrap();
    assert_eq!(sol.steps.len(), 4);
    assert!(sol.steps.iter().all(|s| s.x == sol.steps[0].x));
    let mut b = chain();
    b.add_load("n4", [0.0; 3], [0.0; 3]).unwrap();
    b.prescribe_coordinate("n4", Dof::Y, 0.0).unwrap();
    assert!(!b.build().unwrap().loads.scale_with_load_factor());
    let mut b = chain();
    b.add_load("n4", [0.0, 0.0, 1e-3], [0.0; 3]).unwrap();
    assert!(b.build().unwrap().loads.scale_with_load_factor());
    let mut b = chain();
    b.add_load("n4", [0.0; 3], [1e-3, 0.0, 0.0]).unwrap();
    assert!(b.build().unwrap().loads.scale_with_load_factor());
    let mut b = chain();
    b.set_gravity([0.0, 0.0, -9.81]).unwrap();
    assert!(b.build().unwrap().loads.scale_with_load_factor());
    let mut b = chain();
    b.prescribe_coordinate("n4", Dof::Z, 1e-4).unwrap();
    assert!(b.build().unwrap().loads.scale_with_load_factor());
}
