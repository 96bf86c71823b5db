//! The visual outputs of a simulation: `flexmbd simulate --vtk DIR` (a ParaView time series)
//! and `flexmbd view --analysis simulate` (the animated HTML report), with the output-folder
//! safety and a run that stops. The numbers checked come from the model's geometry, the
//! options given and the physics of a rigid bar pendulum, not from flexmbd's own results.

mod common;
use common::*;
use serde_json::Value;
use std::path::Path;

/// examples/pendulum.toml: a bar of length L between `pin` and `tip`, 1 kg (ρA = 1 kg/m over
/// 1 m), released from rest; g = 9.81 m/s² along −z.
const G: f64 = 9.81;

fn pendulum() -> flexmbd_core::Model {
    flexmbd_io::read_model(&example("pendulum.toml")).expect("the example reads")
}

/// Position of the node named `name` in the reference configuration (the model's geometry).
fn reference(m: &flexmbd_core::Model, name: &str) -> [f64; 3] {
    m.nodes[m.node_id(name).expect("node")].x0
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt()
}

/// The values of the DataArray `name` of a .vtu file.
fn array(vtu: &str, name: &str) -> Vec<f64> {
    let i = vtu
        .find(&format!("Name=\"{name}\""))
        .unwrap_or_else(|| panic!("no array {name}"));
    let body = &vtu[i..];
    let start = body.find('>').unwrap() + 1;
    let end = body.find("</DataArray>").unwrap();
    body[start..end]
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

/// The number in `attr="N"` of a .vtu file.
fn xml_count(text: &str, attr: &str) -> usize {
    let i = text.find(&format!("{attr}=\"")).expect(attr) + attr.len() + 2;
    text[i..].split('"').next().unwrap().parse().unwrap()
}

/// The (timestep, file) entries of a .pvd collection.
fn pvd_entries(path: &Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(path).expect("the .pvd");
    text.lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let attr = |a: &str| {
                let i = l.find(&format!("{a}=\"")).unwrap() + a.len() + 2;
                l[i..].split('"').next().unwrap().to_string()
            };
            (attr("timestep").parse().unwrap(), attr("file"))
        })
        .collect()
}

fn vec3(v: &[f64], node: usize) -> [f64; 3] {
    [v[3 * node], v[3 * node + 1], v[3 * node + 2]]
}

/// The files of the folder, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn vtk_time_series_of_the_pendulum() {
    let dir = Temp::new("sim_vtk");
    let vtk = dir.path("vtk");
    let args = |t_end: &str| {
        vec![
            "simulate".into(),
            example("pendulum.toml").into_os_string(),
            "--t-end".into(),
            t_end.into(),
            "--output-step".into(),
            "0.01".into(),
            "--vtk".into(),
            vtk.clone().into_os_string(),
        ]
    };
    let out = run(&args("0.5"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // one file per output time t = 0, 0.01, …, 0.5 and the collection
    let files = listing(&vtk);
    assert_eq!(files.len(), 52, "{files:?}");
    let entries = pvd_entries(&vtk.join("simulate.pvd"));
    assert_eq!(entries.len(), 51);
    // a complete run: no stop comment
    let collection = std::fs::read_to_string(vtk.join("simulate.pvd")).unwrap();
    assert!(!collection.contains("<!--"), "{collection}");
    for (k, (t, file)) in entries.iter().enumerate() {
        assert!((t - 0.01 * k as f64).abs() < 1e-12, "entry {k}: t = {t}");
        assert_eq!(file, &format!("sim_{k:04}.vtu"));
        assert!(files.contains(file));
    }

    let m = pendulum();
    let (pin, tip) = (m.node_id("pin").unwrap(), m.node_id("tip").unwrap());
    let (pin0, tip0) = (reference(&m, "pin"), reference(&m, "tip"));
    let length = dist(pin0, tip0);
    let read = |k: usize| std::fs::read_to_string(vtk.join(format!("sim_{k:04}.vtu"))).unwrap();
    for k in [0, 25, 50] {
        let text = read(k);
        assert_eq!(xml_count(&text, "NumberOfPoints"), m.nodes.len());
        assert_eq!(
            xml_count(&text, "NumberOfCells"),
            flexmbd_io::vtk::cell_count(&m)
        );
        for f in [
            "displacement",
            "rotation",
            "velocity",
            "angular_velocity",
            "e",
            "sigma",
            "max_stress",
            "element",
        ] {
            assert!(text.contains(&format!("Name=\"{f}\"")), "sim_{k:04}: {f}");
        }
    }
    // t = 0: the reference configuration, at rest
    let first = read(0);
    let points = array(&first, "Points");
    assert!(dist(vec3(&points, tip), tip0) < 1e-12);
    assert!(array(&first, "velocity").iter().all(|v| *v == 0.0));
    // t = 0.5: the bar keeps its length and turns about the pin; the tip's speed follows from
    // the energy of a rigid bar (½ (m L²/3) ω² = m g Δh_centre)
    let last = read(50);
    let points = array(&last, "Points");
    let (p, q) = (vec3(&points, pin), vec3(&points, tip));
    assert!(dist(p, pin0) < 1e-9);
    assert!((dist(p, q) - length).abs() < 1e-6, "{}", dist(p, q));
    let v = vec3(&array(&last, "velocity"), tip);
    let r: [f64; 3] = std::array::from_fn(|i| q[i] - p[i]);
    let speed = dist(v, [0.0; 3]);
    assert!(
        (0..3).map(|i| v[i] * r[i]).sum::<f64>().abs() < 1e-4 * speed * length,
        "the tip moves across the bar (up to the axial vibration of the stiff bar)"
    );
    let drop = tip0[2] - q[2];
    assert!(drop > 0.5, "the bar has swung down: {drop}");
    let omega2 = 3.0 * G * drop / (length * length);
    let expected = omega2.sqrt() * length;
    assert!(
        (speed - expected).abs() < 1e-3 * expected,
        "tip speed {speed}, rigid bar {expected}"
    );
    let w = vec3(&array(&last, "angular_velocity"), tip);
    assert!((dist(w, [0.0; 3]) - omega2.sqrt()).abs() < 1e-3 * omega2.sqrt());
    let u = vec3(&array(&last, "displacement"), tip);
    assert!(dist(u, [q[0] - tip0[0], q[1] - tip0[1], q[2] - tip0[2]]) < 1e-9);

    // the folder now holds a series: refused without --force
    let again = run(&args("0.1"));
    assert_eq!(again.status.code(), Some(2));
    let err = String::from_utf8_lossy(&again.stderr);
    assert!(err.contains("--vtk") && err.contains("--force"), "{err}");
    // with --force the earlier series is replaced (sim_0011 … sim_0050 go), other files stay
    std::fs::write(vtk.join("notes.txt"), "mine").unwrap();
    let mut forced = vec!["--force".into()];
    forced.extend(args("0.1"));
    let out = run(&forced);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let files = listing(&vtk);
    assert_eq!(files.len(), 11 + 1 + 1, "{files:?}");
    assert!(files.contains(&"notes.txt".to_string()));
    assert_eq!(pvd_entries(&vtk.join("simulate.pvd")).len(), 11);
}

/// A bar crushed through itself after a stretch of ordinary motion: the run stops (exit 1);
/// the series up to then is written.
const CRUSH: &[u8] = br#"[model]
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
"#;

#[test]
fn a_stopped_run_writes_its_vtk_series_up_to_the_stop() {
    let dir = Temp::new("sim_vtk_stop");
    let model = dir.write("crush.toml", CRUSH);
    let vtk = dir.path("vtk");
    let (out, json) = run_json(&[
        "simulate".as_ref(),
        model.as_os_str(),
        "--json".as_ref(),
        "--vtk".as_ref(),
        vtk.as_os_str(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = json.expect("the partial results as JSON");
    let t_stop = json["stopped"]["t"].as_f64().unwrap();
    let entries = pvd_entries(&vtk.join("simulate.pvd"));
    // the collection says where the run stopped (the comment of a stopped static path)
    let collection = std::fs::read_to_string(vtk.join("simulate.pvd")).unwrap();
    assert!(
        collection.contains(&format!("<!-- stopped at t = {t_stop:.6e} s: ")),
        "{collection}"
    );
    assert!(entries.len() >= 10, "{}", entries.len());
    assert_eq!(listing(&vtk).len(), entries.len() + 1);
    // the output times of the file (0.001 s) up to the stop, and the last accepted state
    let (last, rest) = entries.split_last().unwrap();
    for (k, (t, _)) in rest.iter().enumerate() {
        assert!((t - 0.001 * k as f64).abs() < 1e-12, "entry {k}: {t}");
    }
    assert!(last.0 <= t_stop + 1e-15 && last.0 > rest.last().unwrap().0);
    assert!(t_stop < 1.0);
}

/// The page's data (the JSON block).
fn page_data(html: &str) -> Value {
    let open = r#"<script type="application/json" id="flexmbd-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start + html[start..].find("</script>").expect("end of data");
    serde_json::from_str(&html[start..end]).expect("data is JSON")
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn html_view_of_the_pendulum_swinging() {
    let dir = Temp::new("sim_view");
    let page = dir.path("pendulum.html");
    let out = run(&[
        "view".as_ref(),
        example("pendulum.toml").as_os_str(),
        "--analysis".as_ref(),
        "simulate".as_ref(),
        "--t-end".as_ref(),
        "0.5".as_ref(),
        "--output-step".as_ref(),
        "0.01".as_ref(),
        "-o".as_ref(),
        page.as_os_str(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(html.contains("function simAdvance("), "the playback script");
    let d = page_data(&html);
    assert_eq!(d["analysis"], "simulate");
    let frames = d["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 51);
    let sim = &d["simulation"];
    let times = f64s(&sim["times"]);
    for (k, t) in times.iter().enumerate() {
        assert!((t - 0.01 * k as f64).abs() < 1e-12, "{k}: {t}");
    }
    assert_eq!(sim["t_end"], 0.5);
    assert!(sim["stopped"].is_null());
    let m = pendulum();
    let tip = sim["tip"].as_u64().unwrap() as usize;
    assert_eq!(d["nodes"][tip]["name"], "tip", "the node that moves most");
    let (pin0, tip0) = (reference(&m, "pin"), reference(&m, "tip"));
    let length = dist(pin0, tip0);
    let pos = |k: usize, i: usize| vec3(&f64s(&frames[k]["x"]), i);
    assert!(dist(pos(0, tip), tip0) < 1e-6, "t = 0: the drawn position");
    let (kinetic, strain) = (f64s(&sim["kinetic"]), f64s(&sim["strain"]));
    assert_eq!(kinetic[0], 0.0);
    for k in 0..frames.len() {
        let q = pos(k, tip);
        // positions are f32 in the page
        assert!((dist(q, pin0) - length).abs() < 1e-5, "frame {k}");
        // energy of a rigid 1 kg bar: T = m g Δh_centre = m g Δz_tip / 2
        let t_expected = 1.0 * G * (tip0[2] - q[2]) / 2.0;
        assert!(
            (kinetic[k] + strain[k] - t_expected).abs() < 1e-3 * t_expected.max(0.1),
            "frame {k}: T + U = {} J, rigid bar {t_expected} J",
            kinetic[k] + strain[k]
        );
    }
    assert!(pos(50, tip)[2] < -0.5, "the tip has swung down");
    // fields per frame: the stress resultants and the node speed (zero at the start)
    let fields = d["fields"].as_array().unwrap();
    let speed = fields.iter().find(|f| f["key"] == "speed").expect("speed");
    assert_eq!(speed["per"], "frame");
    assert_eq!(speed["values"].as_array().unwrap().len(), 51);
    assert!(speed["values"][0]
        .as_array()
        .unwrap()
        .iter()
        .all(|v| v.as_f64() == Some(0.0)));
    assert!(fields.iter().any(|f| f["key"] == "sigma1"));
    assert!(d["animations"].as_array().unwrap().is_empty());
}

#[test]
fn view_simulate_options_and_a_stopped_run() {
    let dir = Temp::new("sim_view_bad");
    let page = dir.path("x.html");
    let fails = |args: &[&std::ffi::OsStr], parts: &[&str]| {
        let out = run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        for p in parts {
            assert!(err.contains(p), "{args:?}: {err}");
        }
        assert!(!page.exists());
    };
    let ex = example("pendulum.toml");
    // a simulation option without --analysis simulate
    fails(
        &[
            "view".as_ref(),
            ex.as_os_str(),
            "--t-end".as_ref(),
            "0.5".as_ref(),
            "-o".as_ref(),
            page.as_os_str(),
        ],
        &["--t-end", "--analysis simulate"],
    );
    fails(
        &[
            "view".as_ref(),
            ex.as_os_str(),
            "--analysis".as_ref(),
            "simulate".as_ref(),
            "--t-end".as_ref(),
            "-1".as_ref(),
            "-o".as_ref(),
            page.as_os_str(),
        ],
        &["--t-end"],
    );
    // no end time anywhere
    let text = std::fs::read_to_string(&ex)
        .unwrap()
        .replace("t_end = 4.0", "");
    let no_end = dir.write("no_end.toml", text.as_bytes());
    fails(
        &[
            "view".as_ref(),
            no_end.as_os_str(),
            "--analysis".as_ref(),
            "simulate".as_ref(),
            "-o".as_ref(),
            page.as_os_str(),
        ],
        &["no end time", "--t-end"],
    );

    // a run that stops: the page shows the frames up to then, exit 1
    let model = dir.write("crush.toml", CRUSH);
    let out = run(&[
        "view".as_ref(),
        model.as_os_str(),
        "--analysis".as_ref(),
        "simulate".as_ref(),
        "-o".as_ref(),
        page.as_os_str(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("stopped"));
    let d = page_data(&std::fs::read_to_string(&page).unwrap());
    assert!(d["frames"].as_array().unwrap().len() >= 10);
    let stopped = d["simulation"]["stopped"].as_str().expect("the stop");
    assert!(stopped.contains("stopped"), "{stopped}");
    assert_eq!(d["simulation"]["t_end"], 1.0);
    assert!(d["notes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|n| n.as_str().unwrap().contains("stopped")));
}
