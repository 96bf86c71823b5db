//! The shipped pendulum at the io level (examples/pendulum.toml read with `flexmbd_io`, the
//! core's simulation, the `simulate --json` document and the CSV tables of the io writers;
//! formerly run through the binary).

mod common;
use common::example;

/// The shipped pendulum: JSON frames at the output times, a period from the tip's crossings of
/// the vertical within 1e-3 of the elliptic-integral value 1.93334 s (validation.md N04, 90°;
/// the core test holds it to 1e-4 with tighter tolerances), and the CSV tables.
#[test]
fn pendulum_example_frames_period_and_csv() {
    let dir = std::env::temp_dir().join(format!("flexmbd-io-sim-{}", std::process::id()));
    let csv = dir.join("out");
    std::fs::create_dir_all(&csv).unwrap();
    let json = common::simulate_doc(&example("pendulum.toml"), 2.5, Some(&csv));
    assert_eq!(json["complete"], true);
    let frames = json["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 251, "t = 0, 0.01, …, 2.5");
    let angle = |f: &serde_json::Value| {
        let tip = &f["nodes"][1]["position"];
        tip[0].as_f64().unwrap().atan2(-tip[2].as_f64().unwrap())
    };
    let mut crossings = Vec::new();
    for w in frames.windows(2) {
        let (a, b) = (angle(&w[0]), angle(&w[1]));
        if a > 0.0 && b <= 0.0 {
            let (ta, tb) = (w[0]["t"].as_f64().unwrap(), w[1]["t"].as_f64().unwrap());
            crossings.push(ta + a / (a - b) * (tb - ta));
        }
    }
    // released at +90°: the first downward crossing is a quarter period
    let quarter = crossings[0];
    assert!(
        (4.0 * quarter - 1.933335).abs() < 2e-3 * 1.933335,
        "T/4 = {quarter}"
    );
    for f in ["energy.csv", "nodes.csv", "elements.csv"] {
        let text = std::fs::read_to_string(csv.join(f)).unwrap();
        assert!(text.lines().count() > 251, "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
