//! The integrator against closed forms: second-order convergence in the step size (the
//! pendulum of N04), and a hinge driven through several turns from t = 0.

mod common;

use common::{pendulum, run, tip_angle};
use flexmbd_core::model::{Dof, ElementSpec, ModelBuilder};
use flexmbd_core::section::BeamProps;
use flexmbd_core::simulation::{Excitation, InitialVelocity, SimOptions, TimeFunction};
use flexmbd_core::Model;

/// Second-order convergence in the step size on a smooth problem (the 30° pendulum with
/// fixed steps, ρ∞ = 0.9): the error of the tip angle at t = 0.5 s against a run with a much
/// smaller step falls by about 4 per halving.
#[test]
fn second_order_convergence_in_the_step_size() {
    let model = pendulum(30f64.to_radians(), 1, 1e-5);
    let angle = |dt: f64| {
        let mut o = SimOptions::new(0.5);
        o.adaptive = false;
        o.dt = dt;
        o.dt_min = dt * 1e-3;
        o.output_step = 0.5;
        o.atol = 1e-12;
        o.rtol = 1e-10;
        let sim = run(&model, &Excitation::default(), &o);
        tip_angle(&model, sim.frames.last().unwrap())
    };
    let reference = angle(0.5 / 4096.0);
    let errs: Vec<f64> = [0.5 / 32.0, 0.5 / 64.0, 0.5 / 128.0]
        .iter()
        .map(|&dt| (angle(dt) - reference).abs())
        .collect();
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!((1.8..2.3).contains(&order), "order {order} from {errs:?}");
    }
}

/// A rigid rotor (a beam without stiffness: all its deformations are constraints) of length
/// 1 m and 1 kg/m on a hinge about z at the origin, the hinge's angle an input (value `angle`,
/// history given by the caller).
fn driven_rotor(angle: f64) -> Model {
    let props = BeamProps {
        rho_a: 1.0,
        rho_i: [2e-5, 1e-5, 1e-5],
        ..Default::default()
    };
    let mut b = ModelBuilder::new("rotor");
    b.add_node("ground", [0.0; 3], true).unwrap();
    b.add_node_at("hub", "ground").unwrap();
    b.add_node("tip", [1.0, 0.0, 0.0], true).unwrap();
    b.add_element(
        "rotor",
        &["hub", "tip"],
        ElementSpec::Beam {
            orient: Some([0.0, 1.0, 0.0]),
            ct: 0.0,
        },
        &[],
        &[],
    )
    .unwrap();
    b.set_beam_props("rotor", props).unwrap();
    let hinge = ElementSpec::Hinge {
        axis: [0.0, 0.0, 1.0],
        k: 0.0,
    };
    b.add_element("drive", &["ground", "hub"], hinge, &[], &[1])
        .unwrap();
    b.prescribe_deformation("drive", 1, angle).unwrap();
    b.fix("ground", None).unwrap();
    b.build().unwrap()
}

/// A hinge's angle is measured in (−π, π]; as an input it is met modulo 2π, so a driven hinge
/// turns through any number of turns: 3.5 turns in 1 s at constant speed, the rotor's tip at
/// the angle of the input at every output time (1e-9 rad; the run used to stop at π).
#[test]
fn a_driven_hinge_turns_through_several_turns() {
    let angle = 7.0 * std::f64::consts::PI;
    let model = driven_rotor(angle);
    let exc = Excitation {
        prescribed: vec![TimeFunction::Ramp {
            start: 0.0,
            end: 1.0,
        }],
        ..Default::default()
    };
    let mut o = SimOptions::new(1.0);
    o.atol = 1e-10;
    o.rtol = 1e-8;
    let sim = run(&model, &exc, &o);
    assert_eq!(sim.frames.len(), 101);
    let tip = model.nodes[2].ix_pos;
    for f in &sim.frames {
        let got = f.x[tip + 1].atan2(f.x[tip]);
        let d = (got - angle * f.t).rem_euclid(std::f64::consts::TAU);
        let d = d.min(std::f64::consts::TAU - d);
        assert!(d < 1e-9, "t = {}: tip angle off by {d}", f.t);
    }
}

/// A history whose rate jumps at t = 0 (a ramp or table starting there) starts the motion at
/// its rate: the initial velocities take the rates of the interval that starts at 0, not the
/// rest before it. The rotor driven at ω = 2 rad/s from t = 0 has its tip moving at ω L at
/// t = 0 and the kinetic energy ½ (ρA L³/3 + ρI_z L) ω² (the lumped rotary inertia turns with
/// the rotor), and the energy balance holds to 1e-4 of it (the velocities of the index-3
/// integration, 1e-5 here; before, the rotor was at rest at t = 0 and the first step jerked it
/// to speed, outside the energy bookkeeping: a balance error of 0.72 J).
#[test]
fn a_ramp_from_the_start_moves_at_its_speed_at_t0() {
    let omega = 2.0;
    let model = driven_rotor(omega * 0.5);
    let exc = Excitation {
        prescribed: vec![TimeFunction::Table(vec![[0.0, 0.0], [0.5, 1.0]])],
        ..Default::default()
    };
    let mut o = SimOptions::new(0.5);
    o.atol = 1e-10;
    o.rtol = 1e-8;
    let sim = run(&model, &exc, &o);

    let (v, w) = sim.frames[0].node_velocities(&model)[2];
    assert!(
        (v[1] - omega).abs() < 1e-9 && v[0].abs() < 1e-9,
        "tip velocity {v:?}"
    );
    let w = w.unwrap();
    assert!((w[2] - omega).abs() < 1e-9, "tip angular velocity {w:?}");
    let kinetic = 0.5 * omega * omega * (1.0 / 3.0 + 1e-5);
    assert!(
        (sim.frames[0].energy.kinetic - kinetic).abs() < 1e-6 * kinetic,
        "{} vs {kinetic}",
        sim.frames[0].energy.kinetic
    );
    assert!(
        sim.stats.max_energy_error < 1e-4 * kinetic,
        "energy balance error {}",
        sim.stats.max_energy_error
    );
}

/// Two mass–spring oscillators side by side (a truss of stiffness k = EA/L from a fixed node
/// to a point mass m that moves along the truss only), started with the same velocity v0;
/// the first truss has material damping with retardation time τ (σ = EA/L (e + τ ė)), the
/// second none. Closed forms: x₁(t) = v0/ω_d e^(−ζωt) sin(ω_d t) with ω = √(k/m),
/// ζ = τω/2, ω_d = ω√(1 − ζ²); x₂(t) = v0/ω sin(ωt). The trapezoidal rule (ρ∞ = 1, no
/// numerical damping) with h = 0.5 ms over 2 s (six periods): within 2e-3 of the amplitude.
/// The energy dissipated is the first oscillator's loss of energy alone.
#[test]
fn material_damping_of_one_element_decays_its_oscillator_as_the_closed_form() {
    let (m, k, tau, v0) = (2.0, 800.0, 2e-3, 0.1);
    let mut b = ModelBuilder::new("two oscillators");
    for (i, y) in [(1, 0.0), (2, 1.0)] {
        let (a, p) = (format!("a{i}"), format!("p{i}"));
        b.add_node(&a, [0.0, y, 0.0], false).unwrap();
        b.add_node(&p, [1.0, y, 0.0], false).unwrap();
        b.fix(&a, None).unwrap();
        b.fix(&p, Some(&[Dof::Y, Dof::Z])).unwrap();
        b.add_element(
            &format!("s{i}"),
            &[&a, &p],
            ElementSpec::Truss { ea: k * 1.0 },
            &[],
            &[],
        )
        .unwrap();
        b.add_point_mass(&p, m).unwrap();
    }
    b.set_damping("s1", tau).unwrap();
    assert!(b.set_damping("s2", -1.0).is_err() && b.set_damping("s3", 1.0).is_err());
    let model = b.build().unwrap();
    let node = |n: &str| model.node_id(n).unwrap();
    let exc = Excitation {
        velocities: ["p1", "p2"]
            .iter()
            .map(|n| InitialVelocity {
                node: node(n),
                velocity: [v0, 0.0, 0.0],
                angular: [0.0; 3],
            })
            .collect(),
        ..Default::default()
    };
    let mut o = SimOptions::new(2.0);
    o.adaptive = false;
    o.dt = 5e-4;
    o.rho_inf = 1.0;
    o.output_step = 0.01;
    let sim = run(&model, &exc, &o);
    let w = (k / m).sqrt();
    let zeta = tau * w / 2.0;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let amp = v0 / w;
    let (x1, x2) = (
        model.nodes[node("p1")].ix_pos,
        model.nodes[node("p2")].ix_pos,
    );
    for f in &sim.frames {
        let t = f.t;
        let want1 = v0 / wd * (-zeta * w * t).exp() * (wd * t).sin();
        let want2 = amp * (w * t).sin();
        assert!(
            (f.x[x1] - 1.0 - want1).abs() < 2e-3 * amp,
            "t = {t}: {} vs {want1}",
            f.x[x1] - 1.0
        );
        assert!(
            (f.x[x2] - 1.0 - want2).abs() < 2e-3 * amp,
            "t = {t}: {} vs {want2}",
            f.x[x2] - 1.0
        );
    }
    // the energy lost is the damped oscillator's: ½ m v0² (1 − its energy fraction left)
    let last = sim.frames.last().unwrap();
    let (t, e0) = (last.t, 0.5 * m * v0 * v0);
    let left = {
        let (x, v) = (last.x[x1] - 1.0, last.v[x1]);
        0.5 * m * v * v + 0.5 * k * x * x
    };
    assert!(
        (last.energy.dissipated - (e0 - left)).abs() < 1e-2 * e0,
        "dissipated {} vs {}",
        last.energy.dissipated,
        e0 - left
    );
    // and about e^(−2ζωt) of it is left
    assert!(
        (left / e0 - (-2.0 * zeta * w * t).exp()).abs() < 0.05,
        "{}",
        left / e0
    );
    assert!(last.energy.balance_error.abs() < 1e-3 * e0);
}

/// A sudden axial force on the tip of a fine strip (100 beams of 50 µm, 20 × 0.2 mm steel),
/// with steps far longer than its axial waves take to cross it: a step whose solution drives
/// an element through itself (the light tip node carried far beyond its element's other end)
/// is halved instead of stopping the run, and the numerically damped response settles at the
/// static elongation F L / (E A).
#[test]
fn a_sudden_tip_force_on_a_fine_strip_settles_at_the_static_elongation() {
    let (n, l, f) = (100, 5e-3, 1.0);
    let mut b = common::strip_builder(n, l);
    b.fix("n0", None).unwrap();
    b.add_load(&format!("n{n}"), [f, 0.0, 0.0], [0.0; 3])
        .unwrap();
    let model = b.build().unwrap();
    let mut o = SimOptions::new(0.02);
    o.dt = 2e-4;
    o.output_step = 0.02;
    let sim = run(&model, &Excitation::default(), &o);
    let tip = model.nodes[model.node_id(&format!("n{n}")).unwrap()].ix_pos;
    let u = sim.frames.last().unwrap().x[tip] - l;
    let u_static = f * l / (210e9 * 0.02 * 0.2e-3);
    assert!(
        (u - u_static).abs() < 1e-3 * u_static,
        "{u} against {u_static}"
    );
}
