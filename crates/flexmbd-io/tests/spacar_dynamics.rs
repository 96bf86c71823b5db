//! SPACAR time-simulation input (mode 1) mapped for `flexmbd simulate`
//! (docs/spacar-import.md §7): the settings, histories, masses and roles read off flexmbd's own
//! fixtures in `tests/models` (each number below is quoted from the file, with its line), the
//! warnings and errors at their lines, and two motions against closed forms: a pendulum whose
//! hinge rotation is a dynamic degree of freedom without a spring (period from the elliptic
//! integral) and a crank driven by a linearly growing Euler parameter (its position exact at
//! the output times).

use flexmbd_core::simulation::{simulate, Simulation, Start, TimeFunction};
use flexmbd_core::statics::{roles, Role};
use flexmbd_core::DefKind;
use flexmbd_io::spacar::Warning;
use flexmbd_io::ModelFile;
use std::path::{Path, PathBuf};

fn own(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/models")
        .join(name)
}

fn text(name: &str) -> String {
    std::fs::read_to_string(own(name)).unwrap()
}

/// The file `name` with line `line` (1-based) replaced.
fn with_line(name: &str, line: usize, new: &str) -> String {
    let t = text(name);
    let mut lines: Vec<&str> = t.lines().collect();
    lines[line - 1] = new;
    lines.join("\n") + "\n"
}

fn dynamic(text: &str, file: &str) -> Result<(ModelFile, Vec<Warning>), String> {
    let m = flexmbd_io::parse_dat(text, file).map_err(|e| e.to_string())?;
    m.to_dynamic_model_file().map_err(|e| e.to_string())
}

fn lines(w: &[Warning]) -> Vec<usize> {
    w.iter().map(|w| w.line).collect()
}

fn run(f: &ModelFile) -> Simulation {
    let opts = f
        .simulate
        .options(None)
        .expect("TIMESTEP gives the end time");
    simulate(&f.model, &f.simulate.excitation, &opts, &mut |_| {}).unwrap()
}

/// mass_spring.dat: TIMESTEP 0.7 700 (line 18) → t_end 0.7 s, first step and output interval
/// 1 ms; ERROR 1e-8 1e-6 (line 19); XF 2 8 0 0 (line 16) a constant force; XM 2 2.0 (line 15);
/// ESTIFF 1 400 (line 14); DYNE 1 1 (line 11): the spring deforms; STARTDE zero (line 17).
#[test]
fn mass_spring_settings_are_the_numbers_of_the_file() {
    let (f, w) = dynamic(&text("mass_spring.dat"), "mass_spring.dat").unwrap();
    assert!(w.is_empty(), "{w:?}");
    let s = &f.simulate;
    assert_eq!(s.t_end, Some(0.7));
    assert_eq!(s.dt, Some(0.7 / 700.0));
    assert_eq!(s.output_step, Some(0.7 / 700.0));
    assert_eq!(s.tolerance, Some([1e-8, 1e-6]));
    assert_eq!(s.start, Some(Start::Reference));
    let o = s.options(None).unwrap();
    assert_eq!((o.t_end, o.atol, o.rtol), (0.7, 1e-8, 1e-6));
    assert!(o.adaptive, "SPACAR's ERROR is a step control");
    let m = &f.model;
    assert_eq!(m.loads.nodal.len(), 1);
    assert_eq!(m.nodes[m.loads.nodal[0].node].name, "2");
    assert_eq!(m.loads.nodal[0].force, [8.0, 0.0, 0.0]);
    assert_eq!(s.excitation.loads, [TimeFunction::Constant]);
    assert_eq!(m.loads.point_masses.len(), 1);
    assert_eq!(m.loads.point_masses[0].1, 2.0);
    assert_eq!(roles(m), [Role::Flexible]);
}

/// driven_beam.dat, line by line: EM 1 0.5 1e-6 5e-7 5e-7 0 (15); XM 3 0.1 (16); XM 4 inertia
/// 1e-5 0 0 2e-5 0 2e-5 (17); XF 3 0 0 −1 (18) constant; DELXF 3 0 1 0 (19) ramped over
/// [0, 0.5]; INPUTX 1 1 0.0 0.05 0.0 (20): x of node 1 starts at its X value 0.0 with
/// 0.05 m/s; DELINPX 1 1 0.01 (21) adds 0.01 m over the run: the input moves at
/// 0.05 + 0.01/0.5 = 0.07 m/s; GRAVITY (22); ITERSTEP (25) unused; TIMESTEP 0.5 50 (26);
/// ERROR 1e-7 1e-5 (27).
#[test]
fn driven_beam_histories_masses_and_warnings() {
    let (f, w) = dynamic(&text("driven_beam.dat"), "driven_beam.dat").unwrap();
    // DELXF interpreted (19), the input moves from t = 0 in a model with DOFs (20), ITERSTEP (25)
    assert_eq!(lines(&w), [19, 20, 25], "{w:?}");
    let s = &f.simulate;
    assert_eq!(
        (s.t_end, s.dt, s.output_step),
        (Some(0.5), Some(0.01), Some(0.01))
    );
    assert_eq!(s.tolerance, Some([1e-7, 1e-5]));
    let m = &f.model;
    let name = |i: usize| m.nodes[i].name.as_str();
    // loads: one per line, in file order
    assert_eq!(m.loads.nodal.len(), 2);
    assert_eq!(name(m.loads.nodal[0].node), "3");
    assert_eq!(m.loads.nodal[0].force, [0.0, 0.0, -1.0]);
    assert_eq!(m.loads.nodal[1].force, [0.0, 1.0, 0.0]);
    assert_eq!(
        s.excitation.loads,
        [
            TimeFunction::Constant,
            TimeFunction::Ramp {
                start: 0.0,
                end: 0.5
            }
        ]
    );
    assert_eq!(m.loads.gravity, [0.0, 0.0, -9.81]);
    assert_eq!(s.excitation.gravity, TimeFunction::Constant);
    // masses: the point mass, the inertia tensor on the rotational node paired with node 3
    assert_eq!(m.loads.point_masses.len(), 1);
    assert_eq!(
        (name(m.loads.point_masses[0].0), m.loads.point_masses[0].1),
        ("3", 0.1)
    );
    assert_eq!(m.loads.inertias.len(), 1);
    assert_eq!(name(m.loads.inertias[0].0), "3@4");
    assert_eq!(
        m.loads.inertias[0].1,
        [[1e-5, 0.0, 0.0], [0.0, 2e-5, 0.0], [0.0, 0.0, 2e-5]]
    );
    match &m.elements[0].element {
        flexmbd_core::elements::Element::Beam(b) => {
            let p = *b.props.clone().unwrap();
            assert_eq!((p.rho_a, p.rho_i), (0.5, [1e-6, 5e-7, 5e-7]));
        }
        other => panic!("{other:?}"),
    }
    // the input: x of node 1 at 0.07 m/s, with that rate from t = 0
    assert_eq!(m.loads.prescribed.len(), 1);
    let p = m.loads.prescribed[0];
    assert!((p.value - 0.07 * 0.5).abs() < 1e-15, "{}", p.value);
    let h = &s.excitation.prescribed[0];
    for t in [0.0, 0.1, 0.25, 0.5] {
        let [phi, dphi, _] = h.eval(t);
        assert!((p.value * phi - 0.07 * t).abs() < 1e-15, "t = {t}");
        assert!((p.value * dphi - 0.07).abs() < 1e-15, "t = {t}");
    }
    // roles: bending (DYNE 3-6) flexible, elongation and torsion rigid (not listed)
    let r = roles(m);
    assert_eq!(
        &r[..6],
        [
            Role::Rigid,
            Role::Rigid,
            Role::Flexible,
            Role::Flexible,
            Role::Flexible,
            Role::Flexible
        ]
    );
    // the same file for statics: the input's velocity is data of a time simulation (20)
    let (_, w) = flexmbd_io::parse_dat(&text("driven_beam.dat"), "driven_beam.dat")
        .unwrap()
        .to_model_file()
        .unwrap();
    assert_eq!(lines(&w), [20], "{w:?}");
}

/// What changes the motion and cannot be mapped is an error at its line.
#[test]
fn unmappable_dynamic_data_is_an_error_at_its_line() {
    let f = "driven_beam.dat";
    let cases: &[(usize, &str, usize, &str)] = &[
        (24, "EDAMP 1 0.0 0.0 0.1 0.1", 24, "element damping"),
        (24, "ED 1 0.0 0.0 0.1 0.1", 24, "element damping"),
        (
            23,
            "STARTDE 1 3 0.001 0.0",
            23,
            "reference configuration at rest",
        ),
        (
            23,
            "STARTDE 1 3 0.0 2.0",
            23,
            "reference configuration at rest",
        ),
        (
            23,
            "STARTDE 1 1 0.0 0.0",
            23,
            "not a dynamic degree of freedom",
        ),
        (20, "INPUTX 1 1 0.0 0.05 2.0", 20, "acceleration"),
        (20, "INPUTX 1 1 0.01 0.05", 20, "starts at 0.01"),
        (15, "EM 1 0.5 1e-6 5e-7 5e-7 1e-7", 15, "Jyz/L"),
        (25, "USERSIG MYFORCES", 25, "MATLAB"),
        (25, "USERINP MYMOTION", 25, "held still"),
        (25, "ESIG 1 0 0 1", 25, "pre-stress"),
        (26, "TIMESTEP 0.5 50.5", 26, "whole number"),
        (26, "TIMESTEP -0.5 50", 26, "positive"),
        (27, "ERROR 0 1e-5", 27, "abs > 0"),
        (26, "% no TIMESTEP", 19, "end time of TIMESTEP"),
        (21, "DELINPX 1 1 0.01 0.2", 21, "velocity and acceleration"),
    ];
    for &(line, new, at, what) in cases {
        let e = dynamic(&with_line(f, line, new), f).unwrap_err();
        assert!(
            e.starts_with(&format!("{f}:{at}:")) && e.contains(what),
            "`{new}`: {e}"
        );
    }
    // two problems: the earlier line is reported
    let t = with_line(f, 24, "EDAMP 1 0 0 1 1").replace(
        "EM      1   0.5 1.0e-6 5.0e-7 5.0e-7 0.0",
        "EM 1 0.5 1e-6 5e-7 5e-7 1e-7",
    );
    assert!(dynamic(&t, f)
        .unwrap_err()
        .starts_with("driven_beam.dat:15:"));
    // ERROR with one value: the absolute tolerance, a warning
    let (g, w) = dynamic(&with_line(f, 27, "ERROR 1e-6"), f).unwrap();
    assert_eq!(g.simulate.tolerance, Some([1e-6, 1e-4]));
    assert!(lines(&w).contains(&27), "{w:?}");
}

/// The public catheter models compute their loads and motions in MATLAB routines: no
/// simulation without them (FLEX_CAT line 200 `USERSIG FFESFVA`, RIG_CAT line 228).
#[test]
fn user_routines_stop_the_public_models() {
    for (file, line) in [
        (
            "roepnaamstraat__FlexibleInstrumentSimulation__FLEX_CAT_S_3D_V2.dat",
            200,
        ),
        (
            "roepnaamstraat__FlexibleInstrumentSimulation__RIG_CAT_S_3D_V2.dat",
            228,
        ),
    ] {
        let m = flexmbd_io::read_dat(&own("public").join(file)).unwrap();
        let e = m.to_dynamic_model_file().unwrap_err().to_string();
        assert!(
            e.contains(&format!("{file}:{line}:")) && e.contains("USERSIG"),
            "{e}"
        );
    }
}

/// pendulum_hinge.dat: the hinge rotation (DYNE 2 1, line 14, no ESTIFF) is held in statics
/// (a warning) and free in the simulation. Released from the horizontal, the 1 m pendulum
/// with a 1 kg point mass (XM 3 1.0, line 17) passes the vertical at T/4 with
/// T = 4 K(sin 45°)/√(g/L) = 2.3678 s (K(1/√2) = 1.8540746773, elliptic integral of the first
/// kind; g = 9.81, line 18).
#[test]
fn pendulum_from_the_file_swings_with_the_elliptic_period() {
    let t = text("pendulum_hinge.dat");
    let m = flexmbd_io::parse_dat(&t, "pendulum_hinge.dat").unwrap();
    let (st, w) = m.to_model_file().unwrap();
    assert_eq!(lines(&w), [14], "{w:?}");
    let (f, w) = m.to_dynamic_model_file().unwrap();
    assert!(w.is_empty(), "{w:?}");
    let hinge = 3; // the RBEAM's 3 deformations first
    assert_eq!(roles(&st.model)[hinge], Role::Input);
    assert_eq!(f.model.partition.e[hinge], DefKind::Free);
    assert_eq!(roles(&f.model)[hinge], Role::Flexible, "free, no stiffness");
    let sim = run(&f);
    let tip = f.model.node_id("3").unwrap();
    let ix = f.model.nodes[tip].ix_pos;
    let mut quarter = None;
    for w in sim.frames.windows(2) {
        let (a, b) = (w[0].x[ix], w[1].x[ix]);
        if a > 0.0 && b <= 0.0 {
            quarter = Some(w[0].t + a / (a - b) * (w[1].t - w[0].t));
            break;
        }
    }
    let period = 4.0 * 1.854_074_677_301_372 / (9.81f64).sqrt();
    let q = quarter.expect("the pendulum passes the vertical");
    assert!(
        (4.0 * q - period).abs() < 1e-3 * period,
        "T = {} against {period}",
        4.0 * q
    );
}

/// A rigid crank (RBEAM, 1 m) turned about y by its Euler parameter λ2 growing linearly from
/// 0 to 0.5 over 1 s (DELINPX 2 3 0.5, TIMESTEP 1.0 10): the angle 2 asin λ2 reaches 60°; the
/// crank's end is exactly at (cos θ, 0, −sin θ), θ = 2 asin(0.05 k), at every output time.
#[test]
fn a_euler_parameter_input_is_exact_at_the_output_times() {
    let crank = "# a driven crank, written for the flexmbd tests
RBEAM 1 1 2 3
X 1 0 0 0
X 3 1 0 0
FIX 1
FIX 2 2 4
INPUTX 2 3
END
HALT
XM 3 1.0
DELINPX 2 3 0.5
TIMESTEP 1.0 10
END
END
";
    let (f, w) = dynamic(crank, "crank.dat").unwrap();
    // the angle is piecewise linear between the output times (line 11); no DOFs, so no
    // warning about the start
    assert_eq!(lines(&w), [11], "{w:?}");
    let sim = run(&f);
    let tip = f.model.nodes[f.model.node_id("3").unwrap()].ix_pos;
    assert_eq!(sim.frames.len(), 11);
    for (k, fr) in sim.frames.iter().enumerate() {
        let th = 2.0 * (0.05 * k as f64).asin();
        let (x, z) = (fr.x[tip], fr.x[tip + 2]);
        assert!(
            (x - th.cos()).abs() < 1e-9 && (z + th.sin()).abs() < 1e-9,
            "t = {}: ({x}, {z}) against θ = {th}",
            fr.t
        );
    }
}

/// A chain of n springs and masses with every dynamic keyword on every element or node:
/// reading and mapping it stays linear in the size of the file (4 times the lines take well
/// under 16 times as long; the best of three runs, against a busy machine).
#[test]
fn mapping_a_long_file_is_linear_in_its_size() {
    let chain = |n: usize| {
        let mut t = String::from("# a chain of springs, written for the flexmbd tests\nFIX 1\n");
        for k in 1..=n + 1 {
            t += &format!("X {k} {k}.0 0 0\n");
        }
        for k in 1..=n {
            t += &format!("TRUSS {k} {k} {}\nFIX {} 2 3\nDYNE {k} 1\n", k + 1, k + 1);
        }
        t += "END\nHALT\n";
        for k in 1..=n {
            t += &format!(
                "ESTIFF {k} 100\nXM {} 1\nDELXF {} 1 0 0\nSTARTDE {k} 1 0 0\nEDAMP {k} 0\n",
                k + 1,
                k + 1
            );
        }
        t + "TIMESTEP 1 10\nEND\nEND\n"
    };
    let time = |n: usize| {
        let text = chain(n);
        (0..3)
            .map(|_| {
                let t0 = std::time::Instant::now();
                let (f, _) = dynamic(&text, "chain.dat").unwrap();
                assert_eq!(f.simulate.excitation.loads.len(), n);
                t0.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (small, large) = (time(2000), time(8000));
    assert!(large < 10.0 * small, "2000: {small} s, 8000: {large} s");
}
