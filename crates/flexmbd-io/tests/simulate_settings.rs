//! `[simulate]`, `[[velocity]]` and the histories of a TOML model as read.

use flexmbd_core::model::Target;
use flexmbd_core::simulation::{Start, TimeFunction};
use flexmbd_io::parse_model_file;

const MODEL: &str = r#"
[nodes]
a = [0.0, 0.0, 0.0]
b = [1.0, 0.0, 0.0]
c = [2.0, 0.0, 0.0]
[fix]
a = "all"
[[beam]]
id = "ab"
nodes = ["a", "b"]
EA = 1.0
GJ = 1.0
EIy = 1.0
EIz = 1.0
rho_a = 1.0
[[truss]]
id = "bc"
nodes = ["b", "c"]
EA = 1.0
[[prescribe]]
element = "bc"
mode = 1
value = 0.01
history = { ramp = { start = 0.0, end = 0.5 } }
[[prescribe]]
node = "b"
dof = "z"
value = 0.02
history = { table = [[0.0, 0.0], [1.0, 1.0]] }
[[load]]
node = "c"
force = [0.0, 1.0, 0.0]
history = { sine = { amplitude = 2.0, frequency = 5.0 } }
[[velocity]]
node = "c"
v = [0.0, 0.0, 0.3]
[simulate]
t_end = 2.0
dt = 1e-3
step = "fixed"
rho_inf = 0.8
tolerance = [1e-7, 1e-5]
start = "static"
rayleigh = [0.1, 1e-4]
"#;

/// The histories follow the model's order of prescribed inputs (coordinates first, then
/// deformations), whatever the order in the file; the settings reach the options.
#[test]
fn histories_follow_the_model_order_and_settings_reach_the_options() {
    let f = parse_model_file(MODEL, "m.toml").unwrap();
    let presc = &f.model.loads.prescribed;
    assert!(matches!(presc[0].target, Target::Coordinate(_)));
    assert!(matches!(presc[1].target, Target::Deformation(_)));
    let exc = &f.simulate.excitation;
    assert_eq!(
        exc.prescribed[0],
        TimeFunction::Table(vec![[0.0, 0.0], [1.0, 1.0]])
    );
    assert_eq!(
        exc.prescribed[1],
        TimeFunction::Ramp {
            start: 0.0,
            end: 0.5
        }
    );
    assert_eq!(
        exc.loads[0],
        TimeFunction::Sine {
            amplitude: 2.0,
            frequency: 5.0,
            phase: 0.0,
            offset: 0.0
        }
    );
    assert_eq!(exc.velocities.len(), 1);
    assert_eq!(exc.velocities[0].velocity, [0.0, 0.0, 0.3]);
    let o = f.simulate.options(None).unwrap();
    assert_eq!(
        (o.t_end, o.dt, o.adaptive, o.rho_inf),
        (2.0, 1e-3, false, 0.8)
    );
    assert_eq!((o.atol, o.rtol), (1e-7, 1e-5));
    assert_eq!(o.start, Start::Static);
    assert_eq!(o.rayleigh, [0.1, 1e-4]);
    // the command line's end time wins
    assert_eq!(f.simulate.options(Some(3.0)).unwrap().t_end, 3.0);
}

/// Errors name the file, the line and the item.
#[test]
fn bad_settings_name_file_line_and_item() {
    for (bad, good, item) in [
        ("step = \"fixed\"", "step = \"sometimes\"", "step"),
        ("t_end = 2.0", "t_end = -2.0", "t_end"),
        (
            "history = { ramp = { start = 0.0, end = 0.5 } }",
            "history = { ramp = { start = 0.5, end = 0.5 } }",
            "history",
        ),
        (
            "history = { table = [[0.0, 0.0], [1.0, 1.0]] }",
            "history = { step = { at = 0.1, before = 0.0, after = 1.0 } }",
            "jump",
        ),
        ("node = \"c\"\nv =", "node = \"zz\"\nv =", "zz"),
    ] {
        let text = MODEL.replacen(bad, good, 1);
        assert_ne!(text, MODEL, "{bad}");
        let e = parse_model_file(&text, "m.toml").unwrap_err().to_string();
        assert!(e.starts_with("m.toml:") && e.contains(item), "{good}: {e}");
    }
}
