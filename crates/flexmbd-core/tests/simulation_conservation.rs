//! Conservation laws of the time integration (issue 13): an undamped flexure keeps its energy
//! over 1000 periods and vibrates at the frequency of the modal analysis (with the exact period
//! elongation of the trapezoidal rule), and a free beam after a force pulse keeps the momentum
//! that the pulse's impulse gave it.

mod common;

use common::run;
use flexmbd_core::assembly::mass::mass_times;
use flexmbd_core::dynamics::modes;
use flexmbd_core::results::moment_of_lambda_forces;
use flexmbd_core::section::BeamProps;
use flexmbd_core::simulation::{Excitation, InitialVelocity, SimOptions, TimeFunction};
use flexmbd_core::statics::{solve, StaticOptions};
use flexmbd_core::Model;

/// A steel leaf 50 mm × 20 mm × 0.3 mm clamped at the origin along x in four beams, with a
/// 10 g mass at its tip; bending about the weak axis moves the tip along z.
fn leaf() -> Model {
    let (e, rho, w, t, l) = (210e9, 7850.0, 0.02, 0.0003, 0.05);
    let (a, iy, iz) = (w * t, w * t * t * t / 12.0, t * w * w * w / 12.0);
    let props = BeamProps {
        ea: e * a,
        gj: 80e9 * w * t * t * t / 3.0,
        eiy: e * iy,
        eiz: e * iz,
        rho_a: rho * a,
        rho_i: [rho * (iy + iz), rho * iy, rho * iz],
        ..Default::default()
    };
    let mut b = common::cantilever(4, l, props);
    b.add_point_mass("n4", 0.01).unwrap();
    b.build().unwrap()
}

/// Undamped free vibration with ρ∞ = 1 (the trapezoidal rule), 40 steps per period, 1000
/// periods: the energy T + U stays within 1e-6 of its start, and the period is the modal one
/// stretched by the trapezoidal rule's exact factor, ω̃ = (2/h) atan(ω h / 2), within 1e-4.
#[test]
fn undamped_free_vibration_keeps_energy_and_the_modes_frequency() {
    let model = leaf();
    let st = solve(&model, &StaticOptions::default(), |_, _| {}).unwrap();
    let modal = modes(&model, st.steps.last().unwrap(), 1).unwrap();
    let omega = modal.modes[0].eigenvalue.sqrt();
    let period = 2.0 * std::f64::consts::PI / omega;
    let h = period / 40.0;
    let omega_num = 2.0 / h * (omega * h / 2.0).atan();
    let period_num = 2.0 * std::f64::consts::PI / omega_num;
    let tip = model.nodes[model.node_id("n4").unwrap()].ix_pos;
    let exc = Excitation {
        velocities: vec![InitialVelocity {
            node: model.node_id("n4").unwrap(),
            velocity: [0.0, 0.0, 1e-3],
            angular: [0.0; 3],
        }],
        ..Default::default()
    };
    let mut o = SimOptions::new(1000.0 * period);
    o.adaptive = false;
    o.dt = h;
    o.dt_min = h * 1e-3;
    o.rho_inf = 1.0;
    o.output_step = h;
    o.atol = 1e-14;
    o.rtol = 1e-10;
    let sim = run(&model, &exc, &o);
    let e0 = sim.frames[0].energy.kinetic + sim.frames[0].energy.strain;
    assert!(e0 > 0.0);
    for f in &sim.frames {
        let e = f.energy.kinetic + f.energy.strain;
        assert!(
            (e - e0).abs() < 1e-6 * e0,
            "t = {}: energy {e} vs {e0}",
            f.t
        );
    }
    // upward zero crossings of the tip deflection (linear interpolation between steps)
    let z: Vec<(f64, f64)> = sim.frames.iter().map(|f| (f.t, f.x[tip + 2])).collect();
    let mut ups = Vec::new();
    for w in z.windows(2) {
        if w[0].1 < 0.0 && w[1].1 >= 0.0 {
            ups.push(w[0].0 + w[0].1 / (w[0].1 - w[1].1) * (w[1].0 - w[0].0));
        }
    }
    assert!(ups.len() >= 990, "{} crossings", ups.len());
    let measured = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as f64;
    assert!(
        ((measured - period_num) / period_num).abs() < 1e-4,
        "period {measured} vs {period_num} (modal {period})"
    );
}

/// A free beam in space (no supports, no gravity) pushed by a triangular force pulse at one end:
/// afterwards the linear momentum equals the pulse's impulse ∫F dt = F t_p / 2 and the angular
/// momentum about the origin its moment ∫ r × F dt, and both and the energy stay constant
/// during the free flight (to the accuracy of the integration: generalised-α is not an
/// energy-momentum scheme, so the bounds are those of the step-size error).
#[test]
fn free_flight_after_a_pulse_keeps_momentum_and_energy() {
    let props = BeamProps {
        ea: 1e6,
        gj: 1e2,
        eiy: 1e2,
        eiz: 2e2,
        rho_a: 1.0,
        rho_i: [2e-4, 1e-4, 1e-4],
        ..Default::default()
    };
    let mut b = common::beam_chain("spaghetti", 6, 1.0, [0.0, 1.0, 0.0], props);
    let f = [0.0, 2.0, 1.0];
    b.add_load("n6", f, [0.0; 3]).unwrap();
    let model = b.build().unwrap();
    let tp = 0.05;
    let exc = Excitation {
        loads: vec![TimeFunction::Table(vec![
            [0.0, 0.0],
            [0.5 * tp, 1.0],
            [tp, 0.0],
        ])],
        ..Default::default()
    };
    let mut o = SimOptions::new(1.0);
    o.dt = 1e-4;
    o.rho_inf = 1.0;
    o.output_step = 0.05;
    o.atol = 1e-12;
    o.rtol = 1e-9;
    let sim = run(&model, &exc, &o);
    // the pulse acts at the tip while it moves; its moment is ∫ r(t) × F φ(t) dt, which for the
    // short pulse is r(0) × impulse to first order: the test of the moment uses the first
    // frame after the pulse and a bound of the tip's travel during it
    let impulse: [f64; 3] = f.map(|v| 0.5 * v * tp);
    let momenta = |fr: &flexmbd_core::simulation::Frame| {
        let p_all = mass_times(&model, &fr.x, &[&fr.v]).pop().unwrap();
        let (mut p, mut l) = ([0.0; 3], [0.0; 3]);
        for n in &model.nodes {
            let r = [fr.x[n.ix_pos], fr.x[n.ix_pos + 1], fr.x[n.ix_pos + 2]];
            let pr = [p_all[n.ix_pos], p_all[n.ix_pos + 1], p_all[n.ix_pos + 2]];
            for k in 0..3 {
                p[k] += pr[k];
            }
            let c = [
                r[1] * pr[2] - r[2] * pr[1],
                r[2] * pr[0] - r[0] * pr[2],
                r[0] * pr[1] - r[1] * pr[0],
            ];
            let ir = n.ix_rot.unwrap();
            let lr = moment_of_lambda_forces(&fr.x[ir..ir + 4], &p_all[ir..ir + 4]);
            for k in 0..3 {
                l[k] += c[k] + lr[k];
            }
        }
        (p, l)
    };
    let after: Vec<_> = sim.frames.iter().filter(|fr| fr.t > tp + 1e-9).collect();
    assert!(after.len() >= 15);
    let (p1, l1) = momenta(after[0]);
    let scale = (impulse[1].powi(2) + impulse[2].powi(2)).sqrt();
    for k in 0..3 {
        assert!(
            (p1[k] - impulse[k]).abs() < 1e-6 * scale,
            "P {p1:?} vs impulse {impulse:?}"
        );
    }
    let e1 = after[0].energy.kinetic + after[0].energy.strain;
    for fr in &after {
        let (p, l) = momenta(fr);
        for k in 0..3 {
            assert!(
                (p[k] - p1[k]).abs() < 1e-6 * scale,
                "t = {}: P {p:?} vs {p1:?}",
                fr.t
            );
            assert!(
                (l[k] - l1[k]).abs() < 1e-5 * scale,
                "t = {}: L {l:?} vs {l1:?}",
                fr.t
            );
        }
        let e = fr.energy.kinetic + fr.energy.strain;
        assert!(
            (e - e1).abs() < 1e-5 * e1,
            "t = {}: energy {e} vs {e1}",
            fr.t
        );
    }
    // the moment of the impulse about the origin: the tip starts at (1, 0, 0) and travels
    // less than |v| t_p during the pulse
    let r0 = [1.0, 0.0, 0.0];
    let want = [
        r0[1] * impulse[2] - r0[2] * impulse[1],
        r0[2] * impulse[0] - r0[0] * impulse[2],
        r0[0] * impulse[1] - r0[1] * impulse[0],
    ];
    for k in 0..3 {
        assert!(
            (l1[k] - want[k]).abs() < 0.02 * scale,
            "L {l1:?} vs {want:?}"
        );
    }
}
