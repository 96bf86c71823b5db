//! The SPACAR importer on real files: every `.dat` fixture in `tests/models` (the public models
//! in `public/`, with their origin and licence in `tests/models/README.md`, and flexmbd's own
//! files in the layouts of SPACAR Light 1.29 and 0.7) parses and gives the counts read off the
//! file by hand; `.dat` → TOML → model gives the same kinematic
//! result; mutated files never panic and fail only with a line number; a hand-written SPACAR
//! parallel guide matches the same guide written in TOML.

use flexmbd_core::kinematics::{check, ConstraintAnalysis};
use flexmbd_core::{CoordKind, DefKind, Model};
use flexmbd_io::spacar::{NodeKind, SpacarModel};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};

/// A fixture of `tests/models` (`public/NAME` for the public models).
fn own(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/models")
        .join(name)
}

/// The public models, copied with their licence into `tests/models/public`.
fn public(name: &str) -> PathBuf {
    own("public").join(name)
}

/// All `.dat` files of `tests/models` and `tests/models/public`.
fn dat_files() -> Vec<PathBuf> {
    let mut v = Vec::new();
    for dir in [own(""), own("public")] {
        let entries = std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
        v.extend(
            entries
                .map(|e| e.unwrap().path())
                .filter(|p| p.extension().is_some_and(|e| e == "dat")),
        );
    }
    v.sort();
    v
}

fn analyse(model: &Model) -> ConstraintAnalysis {
    check(model, &model.partition, &model.x0(), &Default::default()).unwrap()
}

/// What we count by reading a file.
#[derive(Debug, PartialEq)]
struct Counts {
    /// SPACAR translational nodes.
    trans: usize,
    /// SPACAR rotational nodes.
    rot: usize,
    /// flexmbd nodes.
    nodes: usize,
    elements: usize,
    /// Fixed coordinates (x^o).
    fixed: usize,
    /// Input coordinates (INPUTX + DYNX).
    x_input: usize,
    /// Released deformations (RLSE).
    released: usize,
    /// Input deformations (DYNE + INPUTE).
    e_input: usize,
    /// Dcc rows, columns, rank.
    dcc: (usize, usize, usize),
    /// Table 1 row.
    table1: usize,
}

fn counts(m: &SpacarModel, model: &Model, a: &ConstraintAnalysis) -> Counts {
    let x = |k| model.partition.x.iter().filter(|c| **c == k).count();
    let e = |k| model.partition.e.iter().filter(|c| **c == k).count();
    Counts {
        trans: m.count_nodes(NodeKind::Translational),
        rot: m.count_nodes(NodeKind::Rotational),
        nodes: model.nodes.len(),
        elements: model.elements.len(),
        fixed: x(CoordKind::Fixed),
        x_input: x(CoordKind::Input),
        released: e(DefKind::Free),
        e_input: e(DefKind::Input),
        dcc: (a.m(), a.n(), a.rank),
        table1: a.case.row(),
    }
}

/// The counts read off each file by hand.
fn expected(file: &str) -> Counts {
    match file {
        // Our strip in the SPACAR Light 1.29 layout: X lines 1, 3, …, 37 (19 translational
        // nodes), 18 BEAMs with rotational nodes 2, 4, …, 38 (19). FIX 1 (x y z) and FIX 2
        // (λ1..λ3): 6 fixed. DYNE 3 4 on every beam: 36 input deformations, no RLSE. Dcc rows:
        // all 18 × 6 deformations; columns: 38 nodes × 3 velocities − 6 fixed = 108. Exact.
        "strip_end_moment.dat" => Counts {
            trans: 19,
            rot: 19,
            nodes: 38,
            elements: 18,
            fixed: 6,
            x_input: 0,
            released: 0,
            e_input: 36,
            dcc: (108, 108, 108),
            table1: 1,
        },
        // Our cantilever in the SPACAR Light 0.7 layout: X 1, 3, 5, 7; 3 BEAMs with rotational
        // nodes 2, 4, 6, 8; FIX 1, FIX 2 (6 fixed); DYNE 1..6 on all three (18). 18 × 18, exact.
        "cantilever_light07.dat" => Counts {
            trans: 4,
            rot: 4,
            nodes: 8,
            elements: 3,
            fixed: 6,
            x_input: 0,
            released: 0,
            e_input: 18,
            dcc: (18, 18, 18),
            table1: 1,
        },
        // Flexible catheter: 24 BEAMs, translational 1, 3, …, 49, rotational 2, 4, …, 50.
        // FIX 49 2, FIX 49 3, FIX 50 (λ1..λ3): 5 fixed. INPUTX 49 1 plus DYNX y, z of 24
        // translational and λ1..λ3 of 24 rotational nodes: 1 + 48 + 72 = 121 inputs. RLSE
        // 2..6 on all: 120 released. Rows: the 24 elongations; columns: x of nodes 1..47.
        "roepnaamstraat__FlexibleInstrumentSimulation__FLEX_CAT_S_3D_V2.dat" => Counts {
            trans: 25,
            rot: 25,
            nodes: 50,
            elements: 24,
            fixed: 5,
            x_input: 121,
            released: 120,
            e_input: 0,
            dcc: (24, 24, 24),
            table1: 1,
        },
        // Rigid catheter: 12 RBEAMs (translational 1, 5, …, 45 → 49: 13 nodes; rotational
        // 2, 6, …, 46: 12) and 33 HINGEs through 22 hinge-only rotational nodes (3, 4, 7, 8,
        // …): 34 rotational. FIX 49 2, FIX 49 3: 2 fixed. INPUTX 49 1, DYNX y z of 12
        // translational nodes, DYNX λ1 of 12 link rotations: 1 + 24 + 12 = 37. RLSE 1 of 33
        // hinges. Rows: 12 × 3 rigid + 33 × 2 hinge = 102; columns 47 × 3 − 2 − 37 = 102.
        "roepnaamstraat__FlexibleInstrumentSimulation__RIG_CAT_S_3D_V2.dat" => Counts {
            trans: 13,
            rot: 34,
            nodes: 47,
            elements: 45,
            fixed: 2,
            x_input: 37,
            released: 33,
            e_input: 0,
            dcc: (102, 102, 102),
            table1: 1,
        },
        // Our parallel guide: 5 translational, 5 rotational nodes, 4 BEAMs; nodes 1/2 and 7/8
        // clamped (12 fixed); RLSE 2 3 4 on beams 2 and 4 (6); DYNE 2 3 4 on beam 1 (3).
        // Rows 4 × 6 − 6 = 18; columns 10 × 3 − 12 = 18; rank 17 (one motion, one self-stress).
        "parallel_guide.dat" => Counts {
            trans: 5,
            rot: 5,
            nodes: 10,
            elements: 4,
            fixed: 12,
            x_input: 0,
            released: 6,
            e_input: 3,
            dcc: (18, 18, 17),
            table1: 2,
        },
        // Our mass-spring (time simulation): TRUSS 1 1 2, FIX 1 (3) and FIX 2 2 3 (2), DYNE 1 1.
        // Rows: the elongation; columns: x of node 2. Exact.
        "mass_spring.dat" => Counts {
            trans: 2,
            rot: 0,
            nodes: 2,
            elements: 1,
            fixed: 5,
            x_input: 0,
            released: 0,
            e_input: 1,
            dcc: (1, 1, 1),
            table1: 1,
        },
        // Our driven beam (time simulation): BEAM 1 1 2 3 4; FIX 1 2 3 (2), FIX 2 (λ1..λ3: 3);
        // INPUTX 1 1; DYNE 1 3 4 5 6. Rows: 6; columns: 4 nodes × 3 − 5 − 1 = 6. Exact.
        "driven_beam.dat" => Counts {
            trans: 2,
            rot: 2,
            nodes: 4,
            elements: 1,
            fixed: 5,
            x_input: 1,
            released: 0,
            e_input: 4,
            dcc: (6, 6, 6),
            table1: 1,
        },
        // Our pendulum (time simulation): RBEAM 1 1 2 3, HINGE 2 4 2 (node 4 hinge-only);
        // FIX 1 (3), FIX 4 (3); DYNE 2 1. Rows: 3 rigid-body + 3 hinge; columns: 4 nodes × 3 −
        // 6 = 6. Exact.
        "pendulum_hinge.dat" => Counts {
            trans: 2,
            rot: 2,
            nodes: 4,
            elements: 2,
            fixed: 6,
            x_input: 0,
            released: 0,
            e_input: 1,
            dcc: (6, 6, 6),
            table1: 1,
        },
        other => panic!("no expected counts for {other}: read the file and add them"),
    }
}

#[test]
fn every_model_parses_and_gives_the_counts_of_the_file() {
    let files = dat_files();
    assert!(files.len() >= 5, "{files:?}");
    for p in files {
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let m = flexmbd_io::read_dat(&p).unwrap_or_else(|e| panic!("{e}"));
        let model = m.to_model().unwrap_or_else(|e| panic!("{e}"));
        let a = analyse(&model);
        assert_eq!(counts(&m, &model, &a), expected(&name), "{name}");
        // SPACAR's Euler-parameter Dcc has one more row and column per rotational node
        assert_eq!(
            a.euler_shape,
            (
                a.m() + model.n_rotational_nodes(),
                a.n() + model.n_rotational_nodes()
            ),
            "{name}"
        );
    }
}

#[test]
fn static_data_and_warnings_of_the_fixtures() {
    let read = |p: PathBuf| flexmbd_io::read_dat(&p).unwrap();
    let m = read(own("strip_end_moment.dat"));
    assert_eq!(m.estiff.len(), 18);
    assert_eq!(m.em[0].values.len(), 5);
    assert_eq!(m.delxf[0].node, 20);
    assert_eq!(m.delxf[0].values, [0.0, 0.0, 1.0]);
    assert_eq!(
        m.iterstep.as_ref().unwrap().values,
        [10.0, 5.0, 5e-7, 1.0, 3.0, 0.0]
    );
    // INITIAL, COLOR, BEAMPROPS, CROSSTYPE, CROSSDIM, GRAPHICS, FACECOLOR
    assert_eq!(m.visualization.len(), 7);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);

    let m = read(own("cantilever_light07.dat"));
    assert_eq!(m.xf[0].values, [0.0, 200.0, 0.0]);
    assert_eq!(m.delxf[0].values, [0.0, 0.0, -500.0]);
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);

    let m = read(public(
        "roepnaamstraat__FlexibleInstrumentSimulation__FLEX_CAT_S_3D_V2.dat",
    ));
    assert_eq!(m.estiff[0].values, [0.0, 0.0093, 0.012, 0.012]);
    assert_eq!(m.timestep.as_ref().unwrap().values, [1.2, 8000.0]);
    assert_eq!(m.error_tol.as_ref().unwrap().values, [1e-4, 1e-4]);
    let routines: Vec<(&str, &str)> = m
        .user_routines
        .iter()
        .map(|u| (u.keyword.as_str(), u.name.as_str()))
        .collect();
    assert_eq!(routines, [("USERSIG", "FFESFVA"), ("USERINP", "FFESMVA")]);
    // the two user routines are the only warnings
    let lines: Vec<usize> = m.warnings.iter().map(|w| w.line).collect();
    assert_eq!(lines, [200, 202]);

    let m = read(public(
        "roepnaamstraat__FlexibleInstrumentSimulation__RIG_CAT_S_3D_V2.dat",
    ));
    assert_eq!(m.xm.len(), 33);
    assert_eq!(m.xm[0].values.len(), 6);
    assert_eq!(m.em.len(), 12);
    assert_eq!(m.estiff.len(), 33);
    let model = m.to_model().unwrap();
    // hinge stiffness from ESTIFF
    match &model.elements[1].element {
        flexmbd_core::elements::Element::Hinge(h) => assert_eq!(h.k, 2.8),
        other => panic!("{other:?}"),
    }
    assert_eq!(m.warnings.len(), 2);
}

/// The converted TOML file reads back to the model of the static spec (with the DYNX inputs):
/// same nodes, partition, rigid modes, loads, masses and prescribed values; and its kinematic
/// check has the Dcc of the `.dat` file's check (a DYNE deformation with stiffness is not
/// listed in the TOML file instead of an input: a row of Dcc either way).
#[test]
fn dat_to_toml_round_trip() {
    for p in dat_files() {
        let name = p.display().to_string();
        let m = flexmbd_io::read_dat(&p).unwrap();
        let direct = m.to_model().unwrap();
        let (spec, _) = m.to_static_spec().unwrap();
        let full = spec.build().unwrap();
        let text = m.to_toml().unwrap();
        let back = flexmbd_io::parse_model_file(&text, "converted.toml")
            .unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        let (settings, back) = (back.settings, back.model);
        assert_eq!(direct.node_names(), back.node_names(), "{name}");
        assert_eq!(direct.nx, back.nx, "{name}");
        assert_eq!(direct.ne, back.ne, "{name}");
        assert_eq!(full.partition, back.partition, "{name}");
        assert_eq!(full.explicit_rigid, back.explicit_rigid, "{name}");
        assert_eq!(full.loads, back.loads, "{name}");
        assert_eq!(settings.steps, spec.statics.steps, "{name}");
        // the kinematic partitions differ only in DYNE deformations (input vs not listed)
        for (i, (k, t)) in direct.partition.e.iter().zip(&back.partition.e).enumerate() {
            if k != t {
                assert_eq!(
                    (*k, *t),
                    (DefKind::Input, DefKind::Fixed),
                    "{name} deformation {i}"
                );
            }
        }
        assert_eq!(direct.partition.x, back.partition.x, "{name}");
        let (a, b) = (analyse(&direct), analyse(&back));
        assert_eq!(
            (a.m(), a.n(), a.rank, a.n_motions(), a.n_self_stresses()),
            (b.m(), b.n(), b.rank, b.n_motions(), b.n_self_stresses()),
            "{name}"
        );
        assert_eq!(a.case, b.case, "{name}");
        for (x, y) in a.singular_values.iter().zip(&b.singular_values) {
            assert!((x - y).abs() <= 1e-12 * a.singular_values[0], "{name}");
        }
    }
}

#[test]
fn parallel_guide_dat_and_toml_agree() {
    let m = flexmbd_io::read_dat(&own("parallel_guide.dat")).unwrap();
    // lower-case `beam` and Fortran exponents are read without warnings
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert_eq!(m.estiff[2].values, [1e10, 1e6, 1e6, 1e6]);
    let dat = m.to_model().unwrap();
    let toml = flexmbd_io::read_model(&own("parallel_guide.toml")).unwrap();
    let (a, b) = (analyse(&dat), analyse(&toml));
    let summary = |a: &ConstraintAnalysis| {
        (
            a.m(),
            a.n(),
            a.rank,
            a.n_motions(),
            a.n_self_stresses(),
            a.case,
            a.euler_shape,
        )
    };
    assert_eq!(summary(&a), summary(&b));
    assert_eq!((a.n_motions(), a.n_self_stresses()), (1, 1));
    // the motion is the top bar moving along x
    let top = &a.motions[0].coordinates;
    let vx = |node: &str| {
        top.iter()
            .find(|c| c.node == node && c.dof == flexmbd_core::model::Dof::X)
            .map_or(0.0, |c| c.value)
    };
    assert!(
        vx("5").abs() > 0.3 && (vx("5") - vx("3")).abs() < 1e-9,
        "{top:?}"
    );
}

/// The message names a line: `fuzz.dat:LINE:COL: …`.
fn has_line(msg: &str) -> bool {
    let Some(rest) = msg.strip_prefix("fuzz.dat:") else {
        return false;
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    digits > 0 && rest[digits..].starts_with(':')
}

const SPECIAL: &[&str] = &[
    "1e999",
    "-1e999",
    "NaN",
    "inf",
    "1e308",
    "-1e308",
    "1e-320",
    "0",
    "-1",
    "99999999999999999999",
    "4294967296",
    "1.5",
    "",
    "x",
    "END",
    "HALT",
];

/// One random edit of a file's bytes.
fn mutate(rng: &mut StdRng, text: &[u8]) -> Vec<u8> {
    let mut t = text.to_vec();
    let lines =
        |t: &[u8]| -> Vec<Vec<u8>> { t.split(|b| *b == b'\n').map(<[u8]>::to_vec).collect() };
    for _ in 0..rng.random_range(1..=3) {
        match rng.random_range(0..7) {
            0 => {
                // random byte edits
                for _ in 0..rng.random_range(1..6) {
                    if t.is_empty() {
                        break;
                    }
                    let i = rng.random_range(0..t.len());
                    t[i] = match rng.random_range(0..4) {
                        0 => rng.random(),
                        1 => b"0123456789"[rng.random_range(0..10)],
                        2 => b" \t\n#%;,-.eEdD+"[rng.random_range(0..14)],
                        _ => rng.random_range(b'A'..=b'Z'),
                    };
                }
            }
            1 => {
                // truncate
                let n = rng.random_range(0..=t.len());
                t.truncate(n);
            }
            2 => {
                // replace a field with a special value
                let mut ls = lines(&t);
                if ls.is_empty() {
                    continue;
                }
                let li = rng.random_range(0..ls.len());
                let s = String::from_utf8_lossy(&ls[li]).into_owned();
                let mut fields: Vec<&str> = s.split_whitespace().collect();
                if fields.is_empty() {
                    continue;
                }
                let fi = rng.random_range(0..fields.len());
                fields[fi] = SPECIAL[rng.random_range(0..SPECIAL.len())];
                ls[li] = fields.join(" ").into_bytes();
                t = ls.join(&b'\n');
            }
            3 => {
                // delete lines
                let mut ls = lines(&t);
                for _ in 0..rng.random_range(1..4) {
                    if !ls.is_empty() {
                        let i = rng.random_range(0..ls.len());
                        ls.remove(i);
                    }
                }
                t = ls.join(&b'\n');
            }
            4 => {
                // duplicate a line
                let mut ls = lines(&t);
                if !ls.is_empty() {
                    let i = rng.random_range(0..ls.len());
                    let j = rng.random_range(0..=ls.len());
                    let l = ls[i].clone();
                    ls.insert(j, l);
                }
                t = ls.join(&b'\n');
            }
            5 => {
                // swap two lines
                let mut ls = lines(&t);
                if ls.len() > 1 {
                    let (i, j) = (rng.random_range(0..ls.len()), rng.random_range(0..ls.len()));
                    ls.swap(i, j);
                }
                t = ls.join(&b'\n');
            }
            _ => {
                // delete a field
                let mut ls = lines(&t);
                if ls.is_empty() {
                    continue;
                }
                let li = rng.random_range(0..ls.len());
                let s = String::from_utf8_lossy(&ls[li]).into_owned();
                let mut fields: Vec<&str> = s.split_whitespace().collect();
                if !fields.is_empty() {
                    fields.remove(rng.random_range(0..fields.len()));
                }
                ls[li] = fields.join(" ").into_bytes();
                t = ls.join(&b'\n');
            }
        }
    }
    t
}

/// Parse, build, check and convert a mutated file; panics are caught by the caller.
fn exercise(bytes: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(bytes);
    let m = flexmbd_io::parse_dat(&text, "fuzz.dat").map_err(|e| e.to_string())?;
    let model = m.to_model().map_err(|e| e.to_string())?;
    // the analysis may fail on absurd numbers (e.g. coordinates of 1e308), but must not panic
    let _ = check(&model, &model.partition, &model.x0(), &Default::default());
    // the static data maps, or fails with a line
    let (file, _) = m.to_model_file().map_err(|e| e.to_string())?;
    assert_eq!(file.model.nx, model.nx);
    // a model that builds for statics converts to TOML that reads back to the same model
    let toml = m.to_toml().expect("a model that builds converts");
    let back = flexmbd_io::parse_model(&toml, "back.toml")
        .unwrap_or_else(|e| panic!("converted TOML does not read back: {e}\n{toml}"));
    let full = m.to_static_spec().unwrap().0.build().unwrap();
    assert_eq!(back.partition, full.partition);
    assert_eq!(back.loads, full.loads);
    // the time simulation maps, or fails with a line
    if let Err(e) = m.to_dynamic_model_file() {
        return Err(e.to_string());
    }
    Ok(())
}

#[test]
fn mutated_files_never_panic_and_errors_name_a_line() {
    let mut rng = StdRng::seed_from_u64(0x05ba_ca12);
    let (mut ok, mut failed) = (0, 0);
    for p in dat_files() {
        let original = std::fs::read(&p).unwrap();
        for i in 0..250 {
            let bytes = mutate(&mut rng, &original);
            let r = std::panic::catch_unwind(|| exercise(&bytes));
            match r {
                Ok(Ok(())) => ok += 1,
                Ok(Err(msg)) => {
                    failed += 1;
                    assert!(
                        has_line(&msg),
                        "{} mutation {i}: error without a line: {msg}\n{}",
                        p.display(),
                        String::from_utf8_lossy(&bytes)
                    );
                }
                Err(_) => panic!(
                    "{} mutation {i} panicked on:\n{}",
                    p.display(),
                    String::from_utf8_lossy(&bytes)
                ),
            }
        }
    }
    eprintln!("mutations: {ok} read and built, {failed} rejected with a line");
    // both outcomes occur, so the mutations reach past the parser
    assert!(ok > 100 && failed > 100, "ok {ok}, failed {failed}");
}

/// The static data of the fixtures, mapped for `flexmbd static` (docs/spacar-import.md §6).
#[test]
fn static_mapping_of_the_fixtures() {
    use flexmbd_core::statics::{roles, Role};
    let read = |p: PathBuf| flexmbd_io::read_dat(&p).unwrap();
    let count = |m: &Model, r: Role| roles(m).iter().filter(|x| **x == r).count();

    // the strip: DYNE 3 4 flexible (36), the other 72 modes rigid although they have ESTIFF;
    // DELXF 20 0 0 1 (line 145) a moment on "19@20"; ITERSTEP 10 5 5e-7 (line 141)
    let (f, w) = read(own("strip_end_moment.dat")).to_model_file().unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(
        (f.settings.steps, f.settings.tol_force),
        (Some(5), Some(5e-7))
    );
    let m = &f.model;
    assert_eq!((count(m, Role::Flexible), count(m, Role::Rigid)), (36, 72));
    assert_eq!(m.loads.nodal.len(), 1);
    assert_eq!(m.nodes[m.loads.nodal[0].node].name, "19@20");
    assert_eq!(m.loads.nodal[0].moment, [0.0, 0.0, 1.0]);
    match &m.elements[0].element {
        flexmbd_core::elements::Element::Beam(b) => {
            let p = *b.props.clone().unwrap();
            assert_eq!((p.eiy, p.shear), (0.0168, [3.1e-7, 1.2e-4]));
            assert_eq!(p.rho_a, 0.0468);
        }
        other => panic!("{other:?}"),
    }

    // SPACAR Light 0.7 layout: all six modes DYNE (flexible), XF 3 0 200 0 (line 47) an
    // initial load with 6 steps: a warning; one load XF + DELXF on node 3
    let (f, w) = read(own("cantilever_light07.dat")).to_model_file().unwrap();
    let lines: Vec<usize> = w.iter().map(|w| w.line).collect();
    assert_eq!(lines, [47], "{w:?}");
    assert_eq!(f.settings.steps, Some(6));
    assert_eq!(count(&f.model, Role::Flexible), 18);
    assert_eq!(f.model.loads.nodal.len(), 1);
    assert_eq!(f.model.loads.nodal[0].force, [0.0, 200.0, -500.0]);

    // flexible catheter: RLSE 2..6 with ESTIFF flexible, EA = 0 (elongation rigid); the DYNX
    // coordinates are unknowns, only INPUTX 49 1 stays an input; loads in user routines only
    let (f, w) = read(public(
        "roepnaamstraat__FlexibleInstrumentSimulation__FLEX_CAT_S_3D_V2.dat",
    ))
    .to_model_file()
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let m = &f.model;
    assert_eq!((count(m, Role::Flexible), count(m, Role::Rigid)), (120, 24));
    let inputs = m
        .partition
        .x
        .iter()
        .filter(|k| **k == CoordKind::Input)
        .count();
    assert_eq!(inputs, 1);
    assert!(m.loads.nodal.is_empty() && m.loads.prescribed.is_empty());

    // rigid catheter: hinge springs (RLSE 1) flexible, the other two hinge modes and the
    // RBEAMs rigid; the RBEAM masses (EM M/L) lumped at their ends, the XM inertias unused
    let (f, w) = read(public(
        "roepnaamstraat__FlexibleInstrumentSimulation__RIG_CAT_S_3D_V2.dat",
    ))
    .to_model_file()
    .unwrap();
    assert!(w.is_empty(), "{w:?}");
    let m = &f.model;
    assert_eq!((count(m, Role::Flexible), count(m, Role::Rigid)), (33, 102));
    assert_eq!(m.loads.point_masses.len(), 24);
}
