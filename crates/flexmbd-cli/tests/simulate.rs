//! `flexmbd simulate` as a user runs it: arguments, exit codes, formats, the stop with partial
//! results. The physics is tested in the core (`flexmbd-core/tests/validation_simulation.rs`),
//! the shipped pendulum's numbers at the io level (`flexmbd-io/tests/example_simulate.rs`).

mod common;
use common::*;

/// The shipped pendulum: JSON frames at the output times and the CSV tables, and a second run
/// into the same folder refused (the period against validation.md N04 and the full tables:
/// flexmbd-io/tests/example_simulate.rs).
#[test]
fn pendulum_example_runs_with_json_and_csv() {
    let dir = Temp::new("sim_pendulum");
    let csv = dir.path("out");
    let (out, json) = run_json(&[
        "simulate".as_ref(),
        example("pendulum.toml").as_os_str(),
        "--t-end".as_ref(),
        "0.5".as_ref(),
        "--json".as_ref(),
        "--csv".as_ref(),
        csv.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = json.expect("JSON on stdout");
    assert_eq!(json["complete"], true);
    let frames = json["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 51, "t = 0, 0.01, …, 0.5");
    for f in ["energy.csv", "nodes.csv", "elements.csv"] {
        let text = std::fs::read_to_string(csv.join(f)).unwrap();
        assert!(text.lines().count() > 51, "{f}");
    }
    // a second run into the same folder is refused without --force
    let again = run(&[
        "simulate".as_ref(),
        example("pendulum.toml").as_os_str(),
        "--t-end".as_ref(),
        "0.1".as_ref(),
        "--csv".as_ref(),
        csv.as_os_str(),
    ]);
    assert_eq!(again.status.code(), Some(2));
}

#[test]
fn bad_arguments_and_settings_exit_2_with_the_item() {
    let out = run(&[
        "simulate".as_ref(),
        example("pendulum.toml").as_os_str(),
        "--t-end".as_ref(),
        "-1".as_ref(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--t-end"));
    let dir = Temp::new("sim_bad");
    let text = std::fs::read_to_string(example("pendulum.toml"))
        .unwrap()
        .replace("t_end = 4.0", "t_end = 4.0\nrho_inf = 1.5");
    let bad = dir.write("bad.toml", text.as_bytes());
    let out = run(&["simulate".as_ref(), bad.as_os_str()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.toml:") && err.contains("rho_inf"),
        "{err}"
    );
}

/// A run that cannot go on stops with exit 1 and keeps the results up to then: a load that
/// crushes a strip through itself (the inverted-element check) after a stretch of ordinary
/// motion.
#[test]
fn a_stopped_run_writes_the_results_up_to_then() {
    let dir = Temp::new("sim_stop");
    let model = dir.write(
        "crush.toml",
        br#"[model]
name = "crushed bar"
[nodes]
a = [0.0, 0.0, 0.0]
b = [0.1, 0.0, 0.0]
[fix]
a = "all"
b = ["y", "z", "rx", "ry", "rz"]
[[beam]]
id = "bar"
nodes = ["a", "b"]
EA = 1.0
GJ = 1.0
EIy = 1.0
EIz = 1.0
rho_a = 1.0
[[load]]
node = "b"
force = [-1000.0, 0.0, 0.0]
history = { ramp = { start = 0.01, end = 0.02 } }
[simulate]
t_end = 1.0
output_step = 0.001
"#,
    );
    let (out, json) = run_json(&["simulate".as_ref(), model.as_os_str(), "--json".as_ref()]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = json.expect("the partial results as JSON");
    assert_eq!(json["complete"], false);
    let t_stop = json["stopped"]["t"].as_f64().unwrap();
    assert!(t_stop > 0.01 && t_stop < 1.0, "{t_stop}");
    let frames = json["frames"].as_array().unwrap();
    assert!(frames.len() >= 10, "the frames up to the stop are kept");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("stopped") && err.contains("bar"), "{err}");
}

/// Newton that cannot converge (one iteration allowed, at the smallest step) stops the run
/// with the time and the coordinate with the largest correction; exit 1, the frame at t = 0
/// kept.
#[test]
fn a_newton_failure_names_the_coordinate() {
    let dir = Temp::new("sim_newton");
    let text = std::fs::read_to_string(example("pendulum.toml"))
        .unwrap()
        .replace(
            "t_end = 4.0",
            "t_end = 0.1\nmax_iterations = 1\ndt = 0.01\ndt_min = 0.002",
        );
    let model = dir.write("stiff.toml", text.as_bytes());
    let (out, json) = run_json(&["simulate".as_ref(), model.as_os_str(), "--json".as_ref()]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("did not converge") && err.contains("largest at node `"),
        "{err}"
    );
    let json = json.expect("partial results");
    assert_eq!(json["frames"][0]["t"], 0.0);
}

/// `--timings` reports on stderr the read, simulate and write times with the run's step count
/// (the JSON's), and leaves stdout as it is without it.
#[test]
fn timings_go_to_stderr_with_the_step_count() {
    let model = example("pendulum.toml");
    let args = |timings: bool| {
        let mut a = vec![
            "simulate".as_ref(),
            model.as_os_str(),
            "--t-end".as_ref(),
            "0.05".as_ref(),
            "--json".as_ref(),
        ];
        if timings {
            a.push("--timings".as_ref());
        }
        run_json(&a)
    };
    let (plain, plain_json) = args(false);
    let (timed, timed_json) = args(true);
    assert!(timed.status.success());
    assert_eq!(plain.stdout, timed.stdout);
    assert!(plain.stderr.is_empty() || !String::from_utf8_lossy(&plain.stderr).contains("timings"));
    let steps = timed_json.unwrap()["stats"]["steps"].as_u64().unwrap();
    assert_eq!(plain_json.unwrap()["stats"]["steps"].as_u64(), Some(steps));
    let err = String::from_utf8_lossy(&timed.stderr);
    let line = err
        .lines()
        .find(|l| l.starts_with("timings: "))
        .unwrap_or_else(|| panic!("no timings line in {err}"));
    let ms = |what: &str| -> f64 {
        let rest = &line[line
            .find(what)
            .unwrap_or_else(|| panic!("{what} in {line}"))
            + what.len()..];
        rest.trim_start()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    for what in ["read", "simulate", "write"] {
        assert!(ms(what) >= 0.0, "{line}");
    }
    assert!(line.contains(&format!("({steps} steps, ")), "{line}");
}
