//! TOML → spec → TOML → spec is the identity on every example and on the converted SPACAR test
//! models; a model read from a file and the same model written and read again build the same
//! model and give the same analysis results (compared with each other: the two paths are
//! independent up to the writer and the reader).

use super::{parse_spec, write_toml};
use crate::spec::ModelSpec;
use flexmbd_core::dynamics::modes;
use flexmbd_core::kinematics::check;
use flexmbd_core::statics::{solve, StaticOptions};
use flexmbd_core::Model;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn files(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

fn examples() -> Vec<PathBuf> {
    files(&root().join("examples"), "toml")
}

/// Write `spec`, read it back: the same spec, and writing that again gives the same text.
fn round_trip(spec: &ModelSpec, name: &str) -> ModelSpec {
    let text = write_toml(spec).unwrap_or_else(|e| panic!("{name}: {e}"));
    let back = parse_spec(&text, "written.toml").unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
    assert_eq!(back, spec.without_comments(), "{name}:\n{text}");
    let again = write_toml(&back).unwrap();
    assert_eq!(
        parse_spec(&again, "again.toml").unwrap(),
        back,
        "{name}:\n{again}"
    );
    back
}

/// Two builds of one model agree in everything the analyses read.
fn same_model(a: &Model, b: &Model, name: &str) {
    assert_eq!(a.node_names(), b.node_names(), "{name}");
    assert_eq!((a.nx, a.ne), (b.nx, b.ne), "{name}");
    assert_eq!(a.partition, b.partition, "{name}");
    assert_eq!(a.loads, b.loads, "{name}");
    assert_eq!(a.explicit_rigid, b.explicit_rigid, "{name}");
    assert_eq!(a.x0(), b.x0(), "{name}");
}

#[test]
fn every_example_survives_a_round_trip() {
    let all = examples();
    assert!(all.len() >= 15, "{} examples", all.len());
    for p in all {
        let name = p.display().to_string();
        let text = std::fs::read_to_string(&p).unwrap();
        let spec = parse_spec(&text, &name).unwrap();
        let back = round_trip(&spec, &name);
        let (a, b) = (spec.build_file().unwrap(), back.build_file().unwrap());
        same_model(&a.model, &b.model, &name);
        assert_eq!(a.settings, b.settings, "{name}");
        assert_eq!(a.simulate, b.simulate, "{name}");
    }
}

/// The converted SPACAR test models: the converted file reads back to a spec that writes and
/// reads back to itself, and builds the model the `.dat` file's spec builds.
#[test]
fn converted_spacar_models_survive_a_round_trip() {
    let dir = root().join("crates/flexmbd-io/tests/models");
    let mut all = files(&dir, "dat");
    all.extend(files(&dir.join("public"), "dat"));
    assert!(all.len() >= 8, "{} models", all.len());
    for p in all {
        let name = p.display().to_string();
        let m = crate::read_dat(&p).unwrap();
        let (spec, _) = m.to_static_spec().unwrap();
        let text = m.to_toml().unwrap();
        let read = parse_spec(&text, &name).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        round_trip(&read, &name);
        same_model(&spec.build().unwrap(), &read.build().unwrap(), &name);
    }
}

/// check, static and modes of a model read from its file and of the same model written and
/// read again: the same singular values, static states and frequencies.
#[test]
fn written_models_give_the_same_analysis_results() {
    for file in [
        "parallel_leaf_stroke.toml",
        "williams_toggle.toml",
        "strip_f01.toml",
        "rotating_blade.toml",
    ] {
        let text = std::fs::read_to_string(root().join("examples").join(file)).unwrap();
        let spec = parse_spec(&text, file).unwrap();
        let written = write_toml(&spec).unwrap();
        let a = super::parse_model_file(&text, file).unwrap();
        let b = super::parse_model_file(&written, file).unwrap();
        let (ma, mb) = (&a.model, &b.model);
        let ca = check(ma, &ma.partition, &ma.x0(), &Default::default()).unwrap();
        let cb = check(mb, &mb.partition, &mb.x0(), &Default::default()).unwrap();
        assert_eq!(ca.rank, cb.rank, "{file}");
        assert_eq!(ca.singular_values.len(), cb.singular_values.len(), "{file}");
        for (s, t) in ca.singular_values.iter().zip(&cb.singular_values) {
            assert!((s - t).abs() <= 1e-12 * s.abs().max(1.0), "{file}: {s} {t}");
        }
        let opts = StaticOptions {
            steps: a.settings.steps.unwrap_or(4).min(4),
            ..Default::default()
        };
        let (Ok(sa), Ok(sb)) = (solve(ma, &opts, |_, _| {}), solve(mb, &opts, |_, _| {})) else {
            panic!("{file}: static solution")
        };
        let (la, lb) = (sa.steps.last().unwrap(), sb.steps.last().unwrap());
        for (x, y) in la.x.iter().zip(&lb.x) {
            assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{file}: {x} {y}");
        }
        if let (Ok(fa), Ok(fb)) = (modes(ma, la, 3), modes(mb, lb, 3)) {
            assert_eq!(fa.modes.len(), fb.modes.len(), "{file}");
            for (p, q) in fa.modes.iter().zip(&fb.modes) {
                let (f, g) = (p.eigenvalue, q.eigenvalue);
                assert!((f - g).abs() <= 1e-9 * f.abs().max(1.0), "{file}: {f} {g}");
            }
        }
    }
}

/// `flexmbd convert` of a SPACAR time simulation writes `[simulate]`, the inertia tensors and
/// the histories when they fit the static model: `mass_spring.dat` (2 kg on an 800 N/m truss
/// spring under a constant 8 N, TIMESTEP 0.7 700) converted and read back simulates exactly as
/// the `.dat` file, and both follow x(t) = F/k (1 − cos ωt), ω = √(k/m) = 20 rad/s. Where the
/// time simulation does not fit the static model (a DYNE hinge without stiffness, free in the
/// motion and held in statics; beam rotary inertias) the file says why and writes no
/// `[simulate]`.
#[test]
fn converted_time_simulations_simulate_as_the_dat_file() {
    use flexmbd_core::simulation::simulate;
    let dir = root().join("crates/flexmbd-io/tests/models");
    let m = crate::read_dat(&dir.join("mass_spring.dat")).unwrap();
    let text = m.to_toml().unwrap();
    assert!(text.contains("[simulate]\nt_end = 0.7\n"), "{text}");
    let (dat, _) = m.to_dynamic_model_file().unwrap();
    let toml = super::parse_model_file(&text, "mass_spring.toml").unwrap();
    assert_eq!(dat.simulate, toml.simulate);
    let run = |f: &crate::ModelFile| {
        let opts = f.simulate.options(None).unwrap();
        simulate(&f.model, &f.simulate.excitation, &opts, &mut |_| {}).unwrap()
    };
    let (a, b) = (run(&dat), run(&toml));
    assert_eq!(a.frames.len(), b.frames.len());
    let tip = dat.model.nodes[dat.model.node_id("2").unwrap()].ix_pos;
    let (f, k, mass) = (8.0, 800.0, 2.0);
    let w = f64::sqrt(k / mass);
    for (p, q) in a.frames.iter().zip(&b.frames) {
        assert_eq!((p.t, &p.x), (q.t, &q.x));
        let exact = 0.5 + f / k * (1.0 - (w * p.t).cos());
        assert!((p.x[tip] - exact).abs() < 1e-3 * f / k, "t = {}", p.t);
    }
    for (file, why) in [
        ("pendulum_hinge.dat", "other roles in the time simulation"),
        ("driven_beam.dat", "rotary inertias"),
    ] {
        let text = crate::read_dat(&dir.join(file)).unwrap().to_toml().unwrap();
        assert!(!text.contains("[simulate]"), "{file}");
        assert!(text.contains(why), "{file}: {text}");
    }
}
