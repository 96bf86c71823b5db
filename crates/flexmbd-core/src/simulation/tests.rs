//! Tests of the integrator against closed forms and conservation laws.

use super::*;
use crate::model::{Dof, ModelBuilder};
use crate::section::BeamProps;

/// K(k) = π / (2 AGM(1, √(1 − k²))), the complete elliptic integral of the first kind.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        a = an;
        b = bn;
    }
    std::f64::consts::PI / (2.0 * a)
}

/// A very stiff uniform bar of length 1 m and 1 kg/m pinned at the origin (rotation about y
/// only), hanging at `theta0` from the downward vertical in the x-z plane, in `n` beams.
fn pendulum(theta0: f64, n: usize, rho_i: f64) -> Model {
    let props = BeamProps {
        ea: 1e10,
        gj: 1e8,
        eiy: 1e8,
        eiz: 1e8,
        rho_a: 1.0,
        rho_i: [2.0 * rho_i, rho_i, rho_i],
        ..Default::default()
    };
    let mut b = ModelBuilder::new("pendulum");
    let end = [theta0.sin(), 0.0, -theta0.cos()];
    b.add_beam_chain("", [0.0; 3], end, n, Some([0.0, 1.0, 0.0]), Some(props))
        .unwrap();
    b.fix("n0", Some(&[Dof::X, Dof::Y, Dof::Z, Dof::Rx, Dof::Rz]))
        .unwrap();
    b.set_gravity([0.0, 0.0, -9.81]).unwrap();
    b.build().unwrap()
}

/// Angle of the tip from the downward vertical.
fn tip_angle(model: &Model, f: &Frame) -> f64 {
    let tip = &model.nodes[model.nodes.len() - 1];
    let (x, z) = (f.x[tip.ix_pos], f.x[tip.ix_pos + 2]);
    x.atan2(-z)
}

/// Times where θ crosses zero downwards (θ from + to −), linearly interpolated.
fn crossings(model: &Model, frames: &[Frame]) -> Vec<f64> {
    let th: Vec<f64> = frames.iter().map(|f| tip_angle(model, f)).collect();
    let mut out = Vec::new();
    for k in 1..frames.len() {
        if th[k - 1] > 0.0 && th[k] <= 0.0 {
            let s = th[k - 1] / (th[k - 1] - th[k]);
            out.push(frames[k - 1].t + s * (frames[k].t - frames[k - 1].t));
        }
    }
    out
}

fn run(model: &Model, exc: &Excitation, o: &SimOptions) -> Simulation {
    simulate(model, exc, o, &mut |_| {}).unwrap()
}

/// validation.md N04: the period of a large-amplitude rigid pendulum, T = (4/ω0) K(sin θ0/2),
/// ω0² = m g (L/2) / I_pin with I_pin = m L²/3 + ρI_y L (the lumped rotary inertia turns with
/// the bar). Tolerance 1e-4 relative.
#[test]
fn n04_large_amplitude_pendulum_period() {
    let rho_i = 1e-5;
    for (deg, n) in [(90.0_f64, 2), (150.0, 3)] {
        let theta0 = deg.to_radians();
        let model = pendulum(theta0, n, rho_i);
        let i_pin = 1.0 / 3.0 + rho_i;
        let w0 = (9.81 * 0.5 / i_pin).sqrt();
        let want = 4.0 / w0 * elliptic_k((0.5 * theta0).sin());
        let mut o = SimOptions::new(2.3 * want);
        o.output_step = 1e-4;
        o.atol = 1e-10;
        o.rtol = 1e-8;
        o.dt = 1e-4;
        let sim = run(&model, &Excitation::default(), &o);
        let c = crossings(&model, &sim.frames);
        assert!(c.len() >= 2, "{deg}°: crossings {c:?}");
        let got = c[1] - c[0];
        assert!(
            ((got - want) / want).abs() < 1e-4,
            "{deg}°: period {got} vs {want}"
        );
        // energy T + V (V = m g z_centre) is kept to 1e-4 of m g L/2, the tolerance of N04
        // (ρ∞ = 0.9 dissipates a little in the stiff axial modes; the energy test with ρ∞ = 1
        // is `undamped_free_vibration_keeps_energy_and_the_modes_frequency`)
        let tip = model.nodes.len() - 1;
        let scale = 9.81 * 0.5;
        for f in &sim.frames {
            let z = f.x[model.nodes[tip].ix_pos + 2];
            let e = f.energy.kinetic + scale * z;
            assert!(
                (e + scale * theta0.cos()).abs() < 1e-4 * scale,
                "energy {e}"
            );
        }
    }
}

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
        crate::model::ElementSpec::Beam {
            orient: Some([0.0, 1.0, 0.0]),
            ct: 0.0,
        },
        &[],
        &[],
    )
    .unwrap();
    b.set_beam_props("rotor", props).unwrap();
    let hinge = crate::model::ElementSpec::Hinge {
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
