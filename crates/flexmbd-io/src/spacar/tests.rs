//! Unit tests of the SPACAR reader: keywords, errors and warnings with their lines, the node
//! mapping, and equivalence with hand-written TOML models for every element type.

use super::*;
use flexmbd_core::kinematics::{check, ConstraintAnalysis};

fn parse(text: &str) -> SpacarModel {
    parse_dat(text, "t.dat").unwrap_or_else(|e| panic!("{e}"))
}

/// The error message of a text that must fail (in parsing or in building the model).
fn fail(text: &str) -> String {
    match parse_dat(text, "t.dat") {
        Err(e) => e.to_string(),
        Ok(m) => match m.to_model() {
            Err(e) => e.to_string(),
            Ok(_) => panic!("expected an error for\n{text}"),
        },
    }
}

fn analyse(model: &Model) -> ConstraintAnalysis {
    check(model, &model.partition, &model.x0(), &Default::default()).unwrap()
}

/// (m, n, rank, motions, self-stresses)
fn counts(a: &ConstraintAnalysis) -> (usize, usize, usize, usize, usize) {
    (a.m(), a.n(), a.rank, a.n_motions(), a.n_self_stresses())
}

/// The .dat and TOML versions of a model give the same kinematic result; returns it.
fn same_as_toml(dat: &str, toml: &str) -> (usize, usize, usize, usize, usize) {
    let m = parse(dat).to_model().unwrap_or_else(|e| panic!("{e}"));
    let t = crate::parse_model(toml, "t.toml").unwrap_or_else(|e| panic!("{e}"));
    let (a, b) = (analyse(&m), analyse(&t));
    assert_eq!(counts(&a), counts(&b));
    assert_eq!(a.euler_shape, b.euler_shape);
    // and the converted TOML reads back to the same
    let conv = parse(dat).to_toml().unwrap();
    let c = crate::parse_model(&conv, "c.toml").unwrap_or_else(|e| panic!("{e}\n{conv}"));
    assert_eq!(counts(&analyse(&c)), counts(&a));
    counts(&a)
}

const CANTILEVER: &str = "\
# a title
X 1 0 0 0
X 3 1 0 0
BEAM 1 1 2 3 4 0 0 1
DYNE 1 3 4
FIX 1
FIX 2
END
HALT
ESTIFF 1 1 2 3 4 5 6
END
END
";

#[test]
fn cantilever_keywords_and_counts() {
    let m = parse(CANTILEVER);
    assert_eq!(m.title.as_deref(), Some("a title"));
    assert_eq!(m.name, "t");
    assert_eq!(m.count_nodes(NodeKind::Translational), 2);
    assert_eq!(m.count_nodes(NodeKind::Rotational), 2);
    assert_eq!(m.estiff[0].values, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(m.estiff[0].line, 10);
    assert!(m.structure.complete);
    assert_eq!(m.structure.end_lines, [8, 11, 12]);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert_eq!(m.analysis_hint(), AnalysisHint::Kinematic);
    let model = m.to_model().unwrap();
    let names: Vec<_> = model.node_names();
    assert_eq!(names, ["1", "1@2", "3", "3@4"]);
    // 6 columns (node 3 and its rotation), 6 rows (4 fixed + 2 dynamic) -> exact
    assert_eq!(counts(&analyse(&model)), (6, 6, 6, 0, 0));
}

#[test]
fn lexical_freedom() {
    // lower case, commas, Fortran exponents, the three comment characters, CRLF
    let text = "x 1, 0d0, 0, 0 % c\r\nX 3 1.0D0 0 0 ; c\r\nbeam 1 1 2 3 4\r\nfix 1 # c\r\nFiX 2\r\nrlse 1 2\r\nEND\r\nEND\r\n";
    let m = parse(text);
    assert_eq!(m.positions[1].values, [1.0, 0.0, 0.0]);
    assert_eq!(
        m.elements[0].kind,
        ElementKind::Beam {
            xp: 1,
            rp: 2,
            xq: 3,
            rq: 4,
            orient: None
        }
    );
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
}

#[test]
fn static_section_is_kept() {
    let text = "\
X 1 0 0 0
X 3 1 0 0
BEAM 1 1 2 3 4 0 1 0
INPUTX 3 2
FIX 1
FIX 2
END
HALT
ESTIFF 1 10 20
EM 1 0.5 0.1
ESIG 1 0 0 1
XM 3 2.5
XM 4 1 0 0 1 0 1
XF 3 0 1 0
DELXF 4 0 0 0.3
INPUTX 3 2 0.01
DELINPX 3 2 0.02
GRAVITY 0 0 -9.81
ITERSTEP 10 4 0.0000005 1 3 0
OUTLEVEL 0 1
USERSIG FORCES
END
HALT
INPUTF 1 3 1
OUTX 1 3 1
OUTXP 2 3 2
END
END
VISUALIZATION
BEAMPROPS 1
CROSSTYPE RECT
CROSSDIM 0.02 0.001
";
    let m = parse(text);
    assert_eq!(m.em[0].values, [0.5, 0.1]);
    assert_eq!(m.esig[0].values, [0.0, 0.0, 1.0]);
    assert_eq!(m.xm.len(), 2);
    assert_eq!(m.xf[0].values, [0.0, 1.0, 0.0]);
    assert_eq!(m.delxf[0].line, 15);
    assert_eq!(m.inputx_values[0].value, 0.01);
    assert_eq!(m.delinpx[0].value, 0.02);
    assert_eq!(m.gravity.as_ref().unwrap().values, [0.0, 0.0, -9.81]);
    assert_eq!(m.iterstep.as_ref().unwrap().values.len(), 6);
    assert_eq!(m.outlevel.as_ref().unwrap().values, [0.0, 1.0]);
    assert_eq!(m.user_routines[0].name, "FORCES");
    assert_eq!(m.state_space.len(), 3);
    assert_eq!(m.state_space[2].kind, IoKind::Velocity);
    assert_eq!(m.visualization.len(), 3);
    assert_eq!(m.visualization[2].fields, ["0.02", "0.001"]);
    assert_eq!(m.analysis_hint(), AnalysisHint::StateSpace);
    // the user routine is a warning, nothing else is
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert_eq!(m.warnings[0].line, 21);
    // the TOML writes the static data, and keeps the rest as comments
    let toml = m.to_toml().unwrap();
    for needle in [
        "# XF 3 0 1 0 (line 14): force, initial load",
        "[[load]]\nnode = \"3\"\nforce = [0.0, 1.0, 0.0]\n",
        "# DELXF 4 0 0 0.3 (line 15): moment, load increment",
        "[[load]]\nnode = \"3@4\"\nmoment = [0.0, 0.0, 0.3]\n",
        "[[mass]]\nnode = \"3\"\nm = 2.5\n",
        "# INPUTX 3 2 0.01 (line 16), DELINPX 3 2 0.02 (line 17): coordinate y -> 0.03",
        "[[prescribe]]\nnode = \"3\"\ndof = \"y\"\nvalue = 0.03\n",
        "# ITERSTEP 10 4 5e-7 1 3 0 (line 19): steps = 4",
        "[static]\nsteps = 4\ntol_force = 5e-7\ngravity = [0.0, 0.0, -9.81]\n",
        "EA = 10.0\nGJ = 20.0\nEIy = 0.0\nEIz = 0.0\nrho_a = 0.5\nfixed = [1, 2]\n",
        "XM 4 (\"3@4\"): inertia Ixx Ixy Ixz Iyy Iyz Izz 1 0 0 1 0 1 (line 13)",
        "USERSIG FORCES",
        "OUTXP 2 node 3 (\"3\") direction 2",
        "# ESTIFF: EA=10 GJ=20",
        "linearised state-space model (SPACAR mode 9)",
        "line 11: ESIG 1: pre-stress",
    ] {
        assert!(toml.contains(needle), "{needle} not in\n{toml}");
    }
    // the static model: XF + DELXF at load factor 1, the absolute input coordinate as a
    // displacement, warnings for the initial values (more than one step) and the pre-stress
    let (file, w) = m.to_model_file().unwrap();
    assert_eq!(file.settings.steps, Some(4));
    assert_eq!(file.settings.tol_force, Some(5e-7));
    let lines: Vec<usize> = w.iter().map(|w| w.line).collect();
    assert_eq!(lines, [11, 14, 16], "{w:?}");
    let loads = &file.model.loads;
    assert_eq!(loads.gravity, [0.0, 0.0, -9.81]);
    assert_eq!(loads.nodal.len(), 2);
    assert_eq!(loads.nodal[0].force, [0.0, 1.0, 0.0]);
    assert_eq!(loads.nodal[1].moment, [0.0, 0.0, 0.3]);
    assert_eq!(loads.point_masses, [(2, 2.5)]);
    assert_eq!(loads.prescribed.len(), 1);
    assert!((loads.prescribed[0].value - 0.03).abs() < 1e-15);
}

/// The roles of the deformations in statics and the model built for it.
fn static_model(text: &str) -> (Model, Vec<Warning>) {
    let (file, w) = parse(text)
        .to_model_file()
        .unwrap_or_else(|e| panic!("{e}"));
    (file.model, w)
}

fn roles(model: &Model) -> Vec<flexmbd_core::statics::Role> {
    flexmbd_core::statics::roles(model)
}

#[test]
fn static_roles_follow_spacar() {
    use flexmbd_core::statics::Role::{Flexible as F, Input as I, Rigid as R};
    // beam 1: DYNE 3 4 with stiffness (flexible), 1 2 5 6 not listed but with stiffness (rigid);
    // beam 2: DYNE 2 without stiffness (held), RLSE 5 (free, with EIz), INPUTE 1, 3 4 6 rigid;
    // truss 3 not listed with EA (rigid: EA dropped); truss 4 DYNE with EA (flexible);
    // hinge 5 RLSE 1 with k (flexible), hinge 6 not listed with k (rigid)
    let text = "\
X 1 0 0 0
X 3 1 0 0
X 5 2 0 0
X 7 2 1 0
BEAM 1 1 2 3 4 0 0 1
BEAM 2 3 4 5 6 0 0 1
TRUSS 3 1 7
TRUSS 4 3 7
HINGE 5 6 8 0 0 1
HINGE 6 6 9 0 0 1
RLSE 5 1
DYNE 1 3 4
DYNE 2 2
RLSE 2 5
INPUTE 2 1
DYNE 4 1
FIX 1
FIX 2
FIX 7
FIX 8
FIX 9
END
HALT
ESTIFF 1 10 20 30 40
ESTIFF 2 10 0 30 40
ESTIFF 3 100
ESTIFF 4 100
ESTIFF 5 7
ESTIFF 6 8
INPUTE 2 1 0.001
END
END
";
    let (model, w) = static_model(text);
    let r = roles(&model);
    assert_eq!(&r[0..6], [R, R, F, F, R, R]);
    assert_eq!(&r[6..12], [I, I, R, R, F, R]);
    assert_eq!(&r[12..14], [R, F]);
    assert_eq!(&r[14..17], [F, R, R]);
    assert_eq!(&r[17..20], [R, R, R]);
    // the prescribed deformation; the warnings for the DYNE without stiffness and for the
    // initial value of the input (10 steps by default) name their lines
    assert_eq!(model.loads.prescribed.len(), 1);
    assert_eq!(w.len(), 2, "{w:?}");
    assert_eq!((w[0].line, w[1].line), (13, 30));
    assert!(w[0]
        .message
        .contains("DYNE 2: deformation(s) 2 have no stiffness"));
    assert!(w[1].message.contains("INPUTE 2 1: an initial value"));
    // the kinematic model is unchanged: DYNE is an input
    let kin = parse(text).to_model().unwrap();
    assert_eq!(kin.partition.e[2], flexmbd_core::DefKind::Input);
    // and the TOML says the same as the static model
    let toml = parse(text).to_toml().unwrap();
    let back = crate::parse_model(&toml, "c.toml").unwrap_or_else(|e| panic!("{e}\n{toml}"));
    assert_eq!(roles(&back), r);
    assert_eq!(back.partition, model.partition);
    assert!(toml.contains("fixed = [1, 2, 5, 6]"), "{toml}");
}

#[test]
fn static_loads_moments_and_inputs() {
    let base = "\
X 1 0 0 0
X 3 1 0 0
X 5 2 0 0
BEAM 1 1 2 3 4 0 0 1
BEAM 2 3 4 5 6 0 0 1
DYNE 1 1 2 3 4 5 6
DYNE 2 1 2 3 4 5 6
FIX 1
FIX 2
INPUTX 5 1
INPUTX 6 4
END
HALT
ESTIFF 1 1 2 3 4
ESTIFF 2 1 2 3 4
";
    let model = |extra: &str| {
        let text = format!("{base}{extra}END\nEND\n");
        static_model(&text)
    };
    // pre-2017 generalised forces on λ0..λ3 become the moment f/2; λ0 is dropped with a warning
    let (m, w) = model("DELXF 4 0.5 0 0 0.6\n");
    assert_eq!(m.loads.nodal[0].moment, [0.0, 0.0, 0.3]);
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].line, 16);
    assert!(w[0].message.contains("on λ0"));
    let m = parse(&format!("{base}DELXF 4 0 0 0 0.6\nEND\nEND\n"));
    assert!(m.warnings[0].message.contains("converted to the moment"));
    // XF + DELXF, one load per node; the initial load is a warning with more than one step only
    let (m, w) = model("XF 3 0 1 0\nDELXF 3 0 2 0\nITERSTEP 10 1 1e-6\n");
    assert_eq!(m.loads.nodal.len(), 1);
    assert_eq!(m.loads.nodal[0].force, [0.0, 3.0, 0.0]);
    assert!(w.is_empty(), "{w:?}");
    let (_, w) = model("XF 3 0 1 0\nITERSTEP 10 3 1e-6\n");
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].line, 16);
    assert!(w[0].message.contains("over the 3 steps"));
    // an absolute input coordinate is a displacement from the reference; an Euler parameter
    // an angle φ = 2 asin(λ)
    let (m, w) = model("INPUTX 5 1 2.0\nDELINPX 5 1 0.25\nDELINPX 6 4 0.5\n");
    assert!(w.is_empty(), "{w:?}");
    let p = &m.loads.prescribed;
    assert_eq!(p.len(), 2);
    assert_eq!(p[0].value, 0.25);
    assert!((p[1].value - std::f64::consts::PI / 3.0).abs() < 1e-15);
    // the prescribed angle reaches λ3 = 0.5 exactly at the end
    let node = m.node_id("5@6").unwrap();
    let opts = flexmbd_core::statics::StaticOptions {
        steps: 2,
        ..Default::default()
    };
    let sol = flexmbd_core::statics::solve(&m, &opts, |_, _| {}).unwrap();
    let r = m.nodes[node].ix_rot.unwrap();
    let x = &sol.steps[2].x;
    assert!((x[r + 3] - 0.5).abs() < 1e-12, "{:?}", &x[r..r + 4]);
    assert!((x[m.nodes[node].ix_pos] - 2.25).abs() < 1e-12);
    // an initial value that moves the input: a warning (10 steps by default)
    let (_, w) = model("INPUTX 5 1 2.1\n");
    assert_eq!(w.len(), 1);
    assert!(w[0].message.contains("over the 10 steps"));
}

#[test]
fn static_mapping_errors_name_the_line() {
    let base = "\
X 1 0 0 0
X 3 1 0 0
BEAM 1 1 2 3 4 0 0 1
DYNE 1 3 4
FIX 1
FIX 2
INPUTX 4
END
HALT
ESTIFF 1 1 2 3 4
";
    let cases: &[(&str, &str)] = &[
        (
            "DELINPX 4 2 0.1\nDELINPX 4 3 0.1\n",
            "t.dat:12:1: INPUTX/DELINPX 4: several rotational inputs on one node are not supported",
        ),
        (
            "INPUTX 4 3 0.8\nDELINPX 4 3 0.8\n",
            "t.dat:11:1: INPUTX/DELINPX 4 3: the final Euler parameter λ2 = 1.6 is outside [−1, 1]",
        ),
        (
            "ESTIFF 1 1 -2\n",
            "t.dat:11:1: ESTIFF 1: the constants of a beam must be ≥ 0",
        ),
        ("XM 3 -1\n", "t.dat:11:1: mass on `3`"),
    ];
    for (extra, want) in cases {
        let text = format!("{base}{extra}END\nEND\n");
        let got = match parse(&text).to_model_file() {
            Err(e) => e.to_string(),
            Ok(_) => panic!("expected an error for\n{text}"),
        };
        assert!(got.starts_with(want), "\n{text}\ngot:  {got}\nwant: {want}");
        // the kinematic check does not need the static data
        parse(&text).to_model().unwrap();
    }
    // holding the other components at zero is one rotational input
    let text = format!("{base}INPUTX 4 2 0\nDELINPX 4 4 0.1\nEND\nEND\n");
    assert_eq!(static_model(&text).0.loads.prescribed.len(), 1);
}

#[test]
fn static_masses_gravity_and_dynamic_coordinates() {
    // a pendulum of an RBEAM on a hinge, a truss with mass; DYNX coordinates are unknowns in
    // statics (their values ignored, with a warning) and inputs of the kinematic check
    let text = "\
X 1 0 0 0
X 3 1 0 0
X 5 1 -1 0
RBEAM 1 1 2 3
HINGE 2 7 2 0 0 1
TRUSS 3 3 5
RLSE 2 1
FIX 1
FIX 7
FIX 5
DYNX 2 4
END
HALT
ESTIFF 2 5
EM 1 2
EM 3 0.5
XM 3 1.5
XM 2 1 0 0 1 0 1
GRAVITY 0 -10 0
INPUTX 2 4 0.1
END
END
";
    let m = parse(text);
    let (file, w) = m.to_model_file().unwrap();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(w[0].line, 20);
    assert!(w[0].message.contains("dynamic degree of freedom (DYNX)"));
    let model = &file.model;
    let id = |n: &str| model.node_id(n).unwrap();
    let mut masses = model.loads.point_masses.clone();
    masses.sort_by(|a, b| a.partial_cmp(b).unwrap());
    // RBEAM: 2 kg/m × 1 m, half at each end; truss 0.5 kg/m × 1 m; XM 1.5 kg on node 3
    let want = {
        let mut v = vec![
            (id("1"), 1.0),
            (id("3"), 1.0),
            (id("3"), 0.25),
            (id("5"), 0.25),
            (id("3"), 1.5),
        ];
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    };
    assert_eq!(masses, want);
    assert_eq!(model.loads.gravity, [0.0, -10.0, 0.0]);
    let rz = model.nodes[id("1@2")]
        .x_index(flexmbd_core::model::Dof::Rz)
        .unwrap();
    assert_eq!(model.partition.x[rz], flexmbd_core::CoordKind::Free);
    let kin = m.to_model().unwrap();
    assert_eq!(kin.partition.x[rz], flexmbd_core::CoordKind::Input);
    // the TOML keeps DYNX as an input, and says so
    let (toml, w) = m.to_toml_with_warnings().unwrap();
    assert!(
        w.iter().any(|w| w.line == 11 && w.message.contains("DYNX")),
        "{w:?}"
    );
    let back = crate::parse_model(&toml, "c.toml").unwrap();
    assert_eq!(back.partition, kin.partition);
    assert_eq!(back.loads.point_masses.len(), 5);
}

#[test]
fn errors_name_the_line() {
    let base = "X 1 0 0 0\nX 3 1 0 0\nBEAM 1 1 2 3 4\n";
    let cases: &[(&str, &str)] = &[
        ("FOO 1 2\n", "t.dat:4:1: FOO: unknown keyword in the kinematic section"),
        ("PLBEAM 2 1 2 3 4\n", "t.dat:4:1: PLBEAM: planar elements are not supported"),
        ("X 5 1e999 0 0\n", "t.dat:4:5: X 5: coordinate: the number `1e999` is not finite"),
        ("X 5 NaN 0 0\n", "t.dat:4:5: X 5: coordinate: the number `NaN` is not finite"),
        ("X 5 1 0\n", "t.dat:4:5: X 5: expected 3 coordinates"),
        ("BEAM 1 3 4 5 6\n", "t.dat:4:1: BEAM 1: element 1 is already defined on line 3"),
        ("BEAM 2 2 1 3 4\n", "t.dat:4:1: BEAM 2: node 2 is used as a translational node here, but as a rotational node"),
        ("BEAM 2 3 4 5 6\n", "t.dat:4:1: element 2: translational node 5 has no X line"),
        ("BEAM 2 1 2 3 4 0 0\n", "t.dat:4:19: BEAM 2: missing orientation vector"),
        ("BEAM 2 1 2 3 4 0 0 1 7\n", "t.dat:4:22: BEAM 2: unexpected extra field `7`"),
        ("BEAM 2 1.5 2 3 4\n", "t.dat:4:8: BEAM 2: translational node p: expected a whole number, found `1.5`"),
        ("BEAM 2 0 2 3 4\n", "t.dat:4:8: BEAM 2: translational node p must be a whole number ≥ 1"),
        ("RLSE 9 1\n", "t.dat:4:1: RLSE 9: element 9 is not defined"),
        ("RLSE 1 7\n", "t.dat:4:1: RLSE 1: deformation mode 7 does not exist (a BEAM has modes 1 to 6)"),
        ("RLSE 1\n", "t.dat:4:7: RLSE 1: missing deformation mode numbers"),
        ("RLSE 1 2\nDYNE 1 2\n", "t.dat:5:1: DYNE 1: deformation mode 2 is already RLSE (line 4)"),
        ("FIX 2 1\n", "t.dat:4:1: FIX 2: coordinate 1 of rotational node 2 is λ0"),
        ("FIX 1 4\n", "t.dat:4:1: FIX 1: node 1 is a translational node with coordinates 1 to 3, found 4"),
        ("FIX 1 5\n", "t.dat:4:7: FIX 1: coordinate 5 does not exist"),
        ("FIX 9\n", "t.dat:4:1: FIX 9: node 9 is not used by any element"),
        ("FIX 1 1\nINPUTX 1 1\n", "t.dat:5:1: INPUTX 1: coordinate 1 of node 1 is already FIX (line 4)"),
        ("INPUTX 3 1\nDYNX 3 1\n", "t.dat:5:1: DYNX 3: coordinate 1 of node 3 is already INPUTX (line 4)"),
        ("X 2 0 1 0 0\n", "t.dat:4:1: X 2: node 2 is a rotational node; only the reference orientation"),
        ("X 1 0 0 0\n", "t.dat:4:1: X 1: node 1 already has an X line (line 1)"),
        ("USERFOO bar\n", "t.dat:4:1: USERFOO: user routine `USERFOO` in the kinematic section"),
        ("END\nHALT\nBEAM 2 1 2 3 4\n", "t.dat:6:1: BEAM: BEAM belongs in the kinematic section"),
        ("END\nHALT\nESTIFF 1 1 2 3 4 5 6 7\n", "t.dat:6:1: ESTIFF 1: a BEAM takes at most 6 ESTIFF values (EA GJ EIy EIz ShearY ShearZ), found 7"),
        ("END\nHALT\nESTIFF 8 1\n", "t.dat:6:1: ESTIFF 8: element 8 is not defined"),
        ("END\nHALT\nXM 3 1 2\n", "t.dat:6:1: XM 3: expected a mass (1 value)"),
        ("END\nHALT\nXF 3 1 2\n", "t.dat:6:1: XF 3: expected 3 values"),
        ("END\nHALT\nXF 9 1 2 3\n", "t.dat:6:1: XF 9: node 9 is not used by any element"),
        ("END\nHALT\nINPUTX 3 1 0.5\n", "t.dat:6:1: INPUTX 3: coordinate 1 of node 3 is not an input"),
        ("END\nHALT\nINPUTE 1 2 0.5\n", "t.dat:6:1: INPUTE 1: deformation mode 2 of element 1 is not an input"),
        ("END\nHALT\nGRAVITY 0 -9.81\n", "t.dat:6:9: GRAVITY: expected 3 numbers, found 2"),
        ("END\nHALT\nINPUTX 3 1\n", "t.dat:6:11: INPUTX 3: missing value"),
        ("END\nHALT\nOUTX 1 3 4\n", "t.dat:6:1: state-space line 1: direction 4 does not exist"),
        // errors of the mapping onto the core model
        ("X 5 2 0 0\nBEAM 2 3 2 5 6\n", "t.dat:5:1: BEAM 2: rotational node 2 is paired with translational node 3 here, but with translational node 1"),
        ("X 5 1 0 0\nBEAM 2 3 4 5 6\n", "t.dat:5:1: element `2` has zero length"),
        ("X 5 2 0 0\nBEAM 2 3 4 5 6 1 0 0\n", "t.dat:5:1: element `2`"),
        ("X 5 2 0 0\nRBEAM 2 3 4 5\nRLSE 2 1\n", "t.dat:6:1: RBEAM 2: its deformations cannot be released"),
    ];
    for (extra, want) in cases {
        let text = format!("{base}{extra}");
        let got = fail(&text);
        assert!(got.starts_with(want), "\n{text}\ngot:  {got}\nwant: {want}");
    }
}

#[test]
fn warnings_name_the_line() {
    let m = parse(
        "\
X 1 0 0 0
X 3 1 0 0
X 7 5 5 5
BEAM 1 1 2 3 4
FIX 7
END
ESTIFF 1 1
FOO 1 2 3
END
END
junk after the end
VISUALIZATION
COLOR 0 0 0
BLINK 1
",
    );
    let w: Vec<(usize, &str)> = m
        .warnings
        .iter()
        .map(|w| (w.line, w.message.as_str()))
        .collect();
    let want: &[(usize, &str)] = &[
        (3, "X 7: node 7 is not used by any element; ignored"),
        (5, "FIX 7: node 7 is not used by any element; ignored"),
        (
            6,
            "END is followed by `ESTIFF` (line 7) instead of HALT or END",
        ),
        (
            8,
            "unknown keyword `FOO` in the static/dynamic section is ignored",
        ),
        (11, "`JUNK` after the closing END END is ignored"),
        (14, "unknown visualisation keyword `BLINK`"),
    ];
    assert_eq!(w.len(), want.len(), "{w:?}");
    for ((gl, gm), (wl, wm)) in w.iter().zip(want) {
        assert_eq!(gl, wl, "{gm}");
        assert!(gm.starts_with(wm), "{gm}");
    }
    assert!(m.fix.is_empty());
    assert_eq!(m.ignored.len(), 2);
    assert_eq!(m.visualization.len(), 2);

    // truncated files
    let m = parse("X 1 0 0 0\nX 3 1 0 0\nBEAM 1 1 2 3 4\n");
    assert_eq!(m.warnings.len(), 1);
    assert!(m.warnings[0]
        .message
        .contains("ends inside the kinematic section"));
    let m = parse("X 1 0 0 0\nX 3 1 0 0\nBEAM 1 1 2 3 4\nEND\nHALT\nESTIFF 1 1\n");
    assert!(m.warnings[0]
        .message
        .contains("without the closing END END"));
    // a static keyword in the kinematic section is read, with a warning
    let m = parse("X 1 0 0 0\nX 3 1 0 0\nBEAM 1 1 2 3 4\nESTIFF 1 1 2\nEND\nEND\n");
    assert_eq!(m.estiff.len(), 1);
    assert_eq!(m.warnings[0].line, 4);
    // an old-style moment with four values
    let m = parse("X 1 0 0 0\nX 3 1 0 0\nBEAM 1 1 2 3 4\nEND\nHALT\nDELXF 4 0 0 0 0.6\nEND\nEND\n");
    assert!(m.warnings[0].message.contains("pre-2017"));
    // identity Euler parameters of a rotational node are accepted
    let m = parse("X 1 0 0 0\nX 3 1 0 0\nX 4 1 0 0 0\nBEAM 1 1 2 3 4\nEND\nEND\n");
    assert!(m.warnings.is_empty());
}

#[test]
fn beamw_is_a_beam_without_warping() {
    let dat = "\
X 1 0 0 0
X 4 0.1 0 0
BEAMW 1 1 2 3 4 5 6 0 0 1
DYNE 1 1 2 3 4 5 6
RLSE 1 7 8
FIX 1
FIX 2
FIX 3
FIX 6
END
HALT
ESTIFF 1 1 2 3 4 5 6 7
EM 1 1 2 3 4 5 6
END
END
";
    let m = parse(dat);
    assert_eq!(m.count_nodes(NodeKind::Warping), 2);
    let lines: Vec<usize> = m.warnings.iter().map(|w| w.line).collect();
    assert_eq!(lines, [3, 5]);
    let toml = "\
[nodes]
p = [0.0, 0.0, 0.0]
q = [0.1, 0.0, 0.0]
[fix]
p = \"all\"
[[beam]]
id = \"1\"
nodes = [\"p\", \"q\"]
orient = [0.0, 0.0, 1.0]
input = [1, 2, 3, 4, 5, 6]
";
    assert_eq!(same_as_toml(dat, toml), (6, 6, 6, 0, 0));
}

#[test]
fn trusses_twelve_truss_structure() {
    // the 12-truss structure of the paper, Fig. 2 (one motion, one self-stress)
    let dat = "\
X 1  1  1 0
X 2 -1  1 0
X 3 -1 -1 0
X 4  1 -1 0
X 5  0 -1 1
X 6  1  0 1
X 7  0  1 1
X 8 -1  0 1
TRUSS 1 1 6
TRUSS 2 1 7
TRUSS 3 2 7
TRUSS 4 2 8
TRUSS 5 3 5
TRUSS 6 3 8
TRUSS 7 4 5
TRUSS 8 4 6
TRUSS 9 5 6
TRUSS 10 6 7
TRUSS 11 7 8
TRUSS 12 8 5
FIX 1
FIX 2
FIX 3
FIX 4
END
HALT
ESTIFF 1 1000
END
END
";
    let toml = "\
[nodes]
s1 = [1.0, 1.0, 0.0]
s2 = [-1.0, 1.0, 0.0]
s3 = [-1.0, -1.0, 0.0]
s4 = [1.0, -1.0, 0.0]
t1 = [0.0, -1.0, 1.0]
t2 = [1.0, 0.0, 1.0]
t3 = [0.0, 1.0, 1.0]
t4 = [-1.0, 0.0, 1.0]
[fix]
s1 = \"all\"
s2 = \"all\"
s3 = \"all\"
s4 = \"all\"
[[truss]]
id = \"1\"
nodes = [\"s1\", \"t2\"]
[[truss]]
id = \"2\"
nodes = [\"s1\", \"t3\"]
[[truss]]
id = \"3\"
nodes = [\"s2\", \"t3\"]
[[truss]]
id = \"4\"
nodes = [\"s2\", \"t4\"]
[[truss]]
id = \"5\"
nodes = [\"s3\", \"t1\"]
[[truss]]
id = \"6\"
nodes = [\"s3\", \"t4\"]
[[truss]]
id = \"7\"
nodes = [\"s4\", \"t1\"]
[[truss]]
id = \"8\"
nodes = [\"s4\", \"t2\"]
[[truss]]
id = \"9\"
nodes = [\"t1\", \"t2\"]
[[truss]]
id = \"10\"
nodes = [\"t2\", \"t3\"]
[[truss]]
id = \"11\"
nodes = [\"t3\", \"t4\"]
[[truss]]
id = \"12\"
nodes = [\"t4\", \"t1\"]
";
    assert_eq!(same_as_toml(dat, toml), (12, 12, 11, 1, 1));
    // ESTIFF of a truss is its EA
    let model = parse(dat).to_model().unwrap();
    match &model.elements[0].element {
        flexmbd_core::elements::Element::Truss(t) => assert_eq!(t.ea, 1000.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn rbeam_and_hinges_pendulum() {
    // a rigid link hinged to a fixed rotation: one swing motion
    let dat = "\
X 1 0 0 0
X 3 0 -1 0
RBEAM 1 1 2 3 1 0 0
HINGE 2 4 2 0 0 1
RLSE 2 1
FIX 1
FIX 4
END
HALT
ESTIFF 2 3.5
EM 1 0.5
END
END
";
    let m = parse(dat);
    let model = m.to_model().unwrap();
    assert_eq!(model.node_names(), ["1", "1@2", "@4", "3"]);
    // the rigid body has 3 deformations: the position of 3 in the frame of 1@2
    assert_eq!(model.ne, 3 + 3);
    let toml = "\
[nodes]
a = [0.0, 0.0, 0.0]
b = { at = \"a\" }
c = [0.0, -1.0, 0.0]
[fix]
a = [\"x\", \"y\", \"z\"]
b = [\"rx\", \"ry\", \"rz\"]
[[rigid]]
id = \"1\"
nodes = [\"a\", \"c\"]
[[hinge]]
id = \"2\"
nodes = [\"b\", \"a\"]
axis = [0.0, 0.0, 1.0]
free = [1]
";
    assert_eq!(same_as_toml(dat, toml), (5, 6, 5, 1, 0));
    let text = m.to_toml().unwrap();
    assert!(text.contains("k = 3.5"), "{text}");
    assert!(text.contains("# EM: M/L=0.5"), "{text}");
}

#[test]
fn hinge_only_group_gets_an_artificial_origin() {
    let dat = "HINGE 1 1 2 0 0 1\nRLSE 1 1\nFIX 1\nEND\nEND\n";
    let m = parse(dat);
    assert_eq!(m.warnings.len(), 2, "{:?}", m.warnings);
    let model = m.to_model().unwrap();
    assert_eq!(model.node_names(), ["origin", "@1", "@2"]);
    let a = analyse(&model);
    // columns: the rotation of @2 (3); rows: hinge modes 2 and 3
    assert_eq!(counts(&a), (2, 3, 2, 1, 0));
    let toml = m.to_toml().unwrap();
    let c = crate::parse_model(&toml, "c.toml").unwrap();
    assert_eq!(counts(&analyse(&c)), counts(&a));
}

#[test]
fn slider_crank_with_hinges_and_inputs() {
    // slider-crank after Wout-S/oopspa test_slidercrank.m: crank hinge (input angle), flexible
    // crank beam, second hinge, rigid coupler whose end slides along x
    let dat = "\
X 1 0 0 0
X 3 1 1 0
X 5 3 0 0
HINGE 1 2 7 0 0 1
BEAM  2 1 7 3 4 0 0 1
HINGE 3 4 8 0 0 1
BEAM  4 3 8 5 6 0 0 1
INPUTE 1 1
DYNE 2 1 2 3 4 5 6
RLSE 3 1
FIX 1
FIX 2
FIX 5 2 3
END
END
";
    let toml = "\
[nodes]
k1 = [0.0, 0.0, 0.0]
k1b = { at = \"k1\" }
k2 = [1.0, 1.0, 0.0]
k2b = { at = \"k2\" }
k3 = [3.0, 0.0, 0.0]
[fix]
k1 = \"all\"
k3 = [\"y\", \"z\"]
[[hinge]]
id = \"1\"
nodes = [\"k1\", \"k1b\"]
axis = [0.0, 0.0, 1.0]
input = [1]
[[beam]]
id = \"2\"
nodes = [\"k1b\", \"k2\"]
orient = [0.0, 0.0, 1.0]
input = [1, 2, 3, 4, 5, 6]
[[hinge]]
id = \"3\"
nodes = [\"k2\", \"k2b\"]
axis = [0.0, 0.0, 1.0]
free = [1]
[[beam]]
id = \"4\"
nodes = [\"k2b\", \"k3\"]
orient = [0.0, 0.0, 1.0]
";
    let c = same_as_toml(dat, toml);
    // a planar loop of revolute joints in space: one self-stress; no motion with the crank
    // angle given
    assert_eq!((c.3, c.4), (0, 1), "{c:?}");
}
