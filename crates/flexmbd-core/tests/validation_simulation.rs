//! Validation of the time simulation (issue 13) through the library API, one case per test:
//!
//! - N01 (validation.md §4): spin-up of a flexible beam, against the derived reference table;
//! - N04 (validation.md §4): the period of a large-amplitude rigid pendulum, against the
//!   elliptic-integral closed form;
//! - N03 (validation.md §4): slider-crank with a flexible connecting rod, against the derived
//!   reference extremes;
//! - issue 13 item 6 ("rigid-body and hinge mechanisms work as well as flexures"): a driven
//!   crank-rocker four-bar of rigid links and hinges, and the same four-bar of four hinges and
//!   stiff beams, against the rocker angle of the loop-closure equation (closed form).
//!
//! Every number a test compares with is copied here from its source with the source named; the
//! tolerances are those of validation.md where it gives one.

mod common;

use common::{elliptic_k, pendulum, run, tip_angle};
use flexmbd_core::model::{Dof, ElementSpec, ModelBuilder, Node};
use flexmbd_core::section::BeamProps;
use flexmbd_core::simulation::{
    Excitation, Frame, InitialVelocity, SimOptions, Simulation, TimeFunction,
};
use flexmbd_core::Model;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn node<'a>(model: &'a Model, name: &str) -> &'a Node {
    model
        .nodes
        .iter()
        .find(|n| n.name == name)
        .unwrap_or_else(|| panic!("node `{name}`"))
}

fn id(model: &Model, name: &str) -> usize {
    model.nodes.iter().position(|n| n.name == name).unwrap()
}

/// Position (x, y) of a node in a frame.
fn xy(f: &Frame, n: &Node) -> [f64; 2] {
    [f.x[n.ix_pos], f.x[n.ix_pos + 1]]
}

/// The extreme of a sampled signal (largest of `sign` · y) refined by the parabola through the
/// best sample and its neighbours: (abscissa, value).
fn extreme(s: &[(f64, f64)], sign: f64) -> (f64, f64) {
    let k = (0..s.len())
        .max_by(|&a, &b| (sign * s[a].1).total_cmp(&(sign * s[b].1)))
        .expect("samples");
    if k == 0 || k + 1 == s.len() {
        return s[k];
    }
    let ((x0, y0), (x1, y1), (x2, y2)) = (s[k - 1], s[k], s[k + 1]);
    let h = x1 - x0;
    debug_assert!(((x2 - x1) - h).abs() < 1e-9 * h.abs().max(1e-300));
    let (d1, d2) = (0.5 * (y2 - y0), y2 - 2.0 * y1 + y0);
    if d2 == 0.0 {
        return s[k];
    }
    let u = -d1 / d2;
    (x1 + u * h, y1 + 0.5 * d1 * u)
}

// ---------------------------------------------------------------------------------------------
// N01: spin-up of a flexible beam
// ---------------------------------------------------------------------------------------------

/// validation.md N01 input (AeroBeams.jl parameter set): L = 10 m, EA = 2.8e7 N, GA = 1.0e7 N,
/// EI = 1.4e4 N·m², ρA = 1.2 kg/m, ρI = 6.0e-4 kg·m; θ(t) = Ω_s · SpeedRamp(T_s), T_s = 15 s,
/// Ω_s = 6 rad/s (also 4 and 10 rad/s).
const N01_L: f64 = 10.0;
const N01_EA: f64 = 2.8e7;
const N01_RHO_A: f64 = 1.2;
const N01_OMEGA: f64 = 6.0;
const N01_TS: f64 = 15.0;

/// The closed-form steady centrifugal elongation after the spin-up, ρA Ω² L³ / (3 EA).
fn n01_u1_steady(omega: f64) -> f64 {
    N01_RHO_A * omega.powi(2) * N01_L.powi(3) / (3.0 * N01_EA)
}

/// How the hub's angle is imposed on the root of the beam.
#[derive(Clone, Copy, Debug)]
enum Hub {
    /// The root node's rotation about z is a prescribed coordinate (λ3 = sin ½θ).
    Coordinate,
    /// A hinge about z between a fixed ground node and the root, its angle an input.
    Hinge,
}

/// The beam along x in `n` beams, clamped to the hub at the origin that turns about z; in-plane
/// bending is about local z (orientation vector global y). The section is round in its
/// stiffness (EIy = EIz, GJ = EI), so nothing drives motion out of the plane.
fn spin_up_beam(n: usize, hub: Hub, omega: f64) -> Model {
    let (ei, ga) = (1.4e4, 1.0e7);
    let rho_i = 6.0e-4;
    let props = BeamProps {
        ea: N01_EA,
        gj: ei,
        eiy: ei,
        eiz: ei,
        shear: [ei / ga, ei / ga],
        rho_a: N01_RHO_A,
        rho_i: [2.0 * rho_i, rho_i, rho_i],
        ..Default::default()
    };
    let mut b = ModelBuilder::new("N01 spin-up");
    b.add_beam_chain(
        "",
        [0.0; 3],
        [N01_L, 0.0, 0.0],
        n,
        Some([0.0, 1.0, 0.0]),
        Some(props),
    )
    .unwrap();
    match hub {
        Hub::Coordinate => {
            b.fix("n0", Some(&[Dof::X, Dof::Y, Dof::Z, Dof::Rx, Dof::Ry]))
                .unwrap();
            b.prescribe_coordinate("n0", Dof::Rz, omega).unwrap();
        }
        Hub::Hinge => {
            b.add_node("ground", [0.0; 3], true).unwrap();
            b.fix("ground", None).unwrap();
            b.fix("n0", Some(&[Dof::X, Dof::Y, Dof::Z])).unwrap();
            let hinge = ElementSpec::Hinge {
                axis: [0.0, 0.0, 1.0],
                k: 0.0,
            };
            b.add_element("hub", &["ground", "n0"], hinge, &[], &[1])
                .unwrap();
            b.prescribe_deformation("hub", 1, omega).unwrap();
        }
    }
    b.build().unwrap()
}

/// The tip displacement in the hub frame at every output time: (t, u1, u2), u1 along the
/// rotating root tangent minus L, u2 transverse, positive in the direction of rotation.
fn hub_frame_tip(model: &Model, sim: &Simulation, n: usize, omega: f64) -> Vec<(f64, f64, f64)> {
    let tip = node(model, &format!("n{n}"));
    let ramp = TimeFunction::SpeedRamp { duration: N01_TS };
    sim.frames
        .iter()
        .map(|f| {
            let (s, c) = (omega * ramp.eval(f.t)[0]).sin_cos();
            let [x, y] = xy(f, tip);
            (f.t, c * x + s * y - N01_L, -s * x + c * y)
        })
        .collect()
}

/// The N01 run at spin rate `omega` with the hub driven as `hub` (10 beams; 0–30 s, first step
/// 1 ms, tolerances 1e-8 m / 1e-6, output every 0.05 s): the hub-frame tip rows of
/// [`hub_frame_tip`].
fn n01_run(hub: Hub, omega: f64) -> Vec<(f64, f64, f64)> {
    let n = 10;
    let exc = Excitation {
        prescribed: vec![TimeFunction::SpeedRamp { duration: N01_TS }],
        ..Default::default()
    };
    let mut o = SimOptions::new(30.0);
    o.dt = 1e-3;
    o.atol = 1e-8;
    o.rtol = 1e-6;
    o.output_step = 0.05;
    let model = spin_up_beam(n, hub, omega);
    let sim = run(&model, &exc, &o);
    hub_frame_tip(&model, &sim, n, omega)
}

/// The N01 checks of validation.md common to every spin rate: min u2 within 1 % at its time
/// ± 0.1 s, and the steady u1 (the mean over the residual vibration after the spin-up) within
/// 1 % of the closed form ρA Ω² L³ / (3 EA). `label` names the run in messages.
fn n01_check_min_and_steady(
    rows: &[(f64, f64, f64)],
    omega: f64,
    (min_u2, t_min): (f64, f64),
    label: &str,
) {
    let u2s: Vec<(f64, f64)> = rows.iter().map(|r| (r.0, r.2)).collect();
    let (t_got, u_got) = extreme(&u2s, -1.0);
    assert!(
        ((u_got - min_u2) / min_u2).abs() < 0.01,
        "{label}: min u2 {u_got} vs {min_u2}"
    );
    assert!(
        (t_got - t_min).abs() < 0.1,
        "{label}: min u2 at {t_got} s vs {t_min}"
    );
    let after: Vec<f64> = rows.iter().filter(|r| r.0 > N01_TS).map(|r| r.1).collect();
    let mean = after.iter().sum::<f64>() / after.len() as f64;
    let u1_steady = n01_u1_steady(omega);
    assert!(
        ((mean - u1_steady) / u1_steady).abs() < 0.01,
        "{label}: steady u1 {mean} vs {u1_steady}"
    );
}

/// validation.md N01, Ω_s = 6 rad/s, 0–30 s (the reference: a planar Reissner beam FE with 40
/// elements, lumped mass, velocity Verlet dt = 1e-5 s). Tolerances of validation.md: the u2
/// history (t = 1 … 15 s) within 0.01 m, min u2 = −0.5740 m within 1 % at t = 6.75 s ± 0.1 s,
/// the steady u1 after the spin-up within 1 % of the closed form ρA Ω² L³ / (3 EA) = 0.514 mm.
/// The u1 history, for which validation.md gives no tolerance, is held to 1 % of its peak
/// (18.6 mm), the relative accuracy asked of min u2.
///
/// Both ways to drive the hub: a prescribed rotation coordinate and a driven hinge, whose
/// angle (measured in (−π, π]) is met modulo 2π up to the 135 rad reached at 30 s. 10 beams
/// (the fundamental and the centrifugal stretch are converged to far below the tolerances:
/// 20 beams change min u2 by 4e-5 m).
#[test]
fn n01_spin_up_of_a_flexible_beam() {
    // validation.md N01, Ω_s = 6 rad/s: u2 [m] and u1 [mm] at t = 1 … 15 s
    let u2_table = [
        -0.0205, -0.1024, -0.2173, -0.3424, -0.4686, -0.5438, -0.5715, -0.5430, -0.4604, -0.3630,
        -0.2574, -0.1509, -0.0693, -0.0203, 0.0013,
    ];
    let u1_table = [
        -0.024, -0.606, -2.730, -6.770, -12.662, -16.981, -18.632, -16.642, -11.754, -7.079,
        -3.301, -0.805, 0.233, 0.490, 0.514,
    ];
    let (min_u2, t_min) = (-0.5740, 6.75);
    for hub in [Hub::Coordinate, Hub::Hinge] {
        let rows = n01_run(hub, N01_OMEGA);
        let at = |t: f64| {
            rows.iter()
                .find(|r| (r.0 - t).abs() < 1e-9)
                .expect("an output at every second")
        };
        for (k, (&u2, &u1)) in u2_table.iter().zip(&u1_table).enumerate() {
            let t = (k + 1) as f64;
            let r = at(t);
            assert!(
                (r.2 - u2).abs() < 0.01,
                "{hub:?} t = {t}: u2 {} vs {u2}",
                r.2
            );
            assert!(
                (r.1 * 1e3 - u1).abs() < 0.01 * 18.632,
                "{hub:?} t = {t}: u1 {} mm vs {u1}",
                r.1 * 1e3
            );
        }
        n01_check_min_and_steady(&rows, N01_OMEGA, (min_u2, t_min), &format!("{hub:?}"));
    }
}

/// validation.md N01, the other two spin rates of its table, Ω_s = 4 and 10 rad/s (the same
/// reference FE): min u2 within 1 % at its time ± 0.1 s, the steady u1 within 1 % of the closed
/// form ρA Ω² L³ / (3 EA) (0.229 and 1.429 mm), and the residual vibration of u2 after the
/// spin-up, which validation.md gives as "≈ ±4 mm" and "≈ ±6.5 mm" (rounded to the mm, so held
/// to ± 1 mm). The prescribed-coordinate hub (the hinge drive is the same model, shown
/// equivalent at 6 rad/s above).
#[test]
fn n01_spin_up_at_4_and_10_rad_per_s() {
    // validation.md N01: (Ω_s, min u2 [m], at t [s], residual amplitude of u2 [m])
    let table = [(4.0, -0.4007, 6.95, 4.0e-3), (10.0, -0.8593, 6.45, 6.5e-3)];
    for (omega, min_u2, t_min, residual) in table {
        let rows = n01_run(Hub::Coordinate, omega);
        n01_check_min_and_steady(&rows, omega, (min_u2, t_min), &format!("Ω = {omega}"));
        let after: Vec<&(f64, f64, f64)> = rows.iter().filter(|r| r.0 > N01_TS).collect();
        let amplitude = after.iter().map(|r| r.2.abs()).fold(0.0, f64::max);
        assert!(
            (amplitude - residual).abs() < 1e-3,
            "Ω = {omega}: residual vibration of u2 ±{amplitude} vs ±{residual}"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// N03: slider-crank with a flexible connecting rod
// ---------------------------------------------------------------------------------------------

/// validation.md N03 input: crank r = 0.15 m at ω = 150 rad/s; rod L = 0.30 m, solid steel
/// d = 6 mm: A = 2.8274e-5 m², I = 6.3617e-11 m⁴, E = 2.0e11 Pa, ν = 0.3, ρ = 7870 kg/m³,
/// Timoshenko k = 0.9 (EA = 5.6549e6 N, EI = 12.7235 N·m²).
const N03_R: f64 = 0.15;
const N03_L: f64 = 0.30;
const N03_OMEGA: f64 = 150.0;

/// The slider-crank of rigid crank, hinges and a rod of `n` beams (even), in the plane z = 0:
/// ground node `o`; the crank a rigid beam from `c0` (at `o`) to the pin `p`, driven by the
/// hinge `drive` between `o` and `c0`; the rod from `r0` (at `p`, joined by the hinge `pin`) to
/// the slider end `r{n}`, which moves along x (y, z fixed) and turns freely (the massless slider
/// and its revolute joint). The input value is the crank angle at `t_end`, reached with a ramp.
fn slider_crank(n: usize, t_end: f64) -> Model {
    let (e, nu, rho, k) = (2.0e11, 0.3, 7870.0, 0.9);
    let (a, i) = (2.8274e-5, 6.3617e-11);
    let g = e / (2.0 * (1.0 + nu));
    let ei = 12.7235;
    let props = BeamProps {
        ea: 5.6549e6,
        gj: g * 2.0 * i,
        eiy: ei,
        eiz: ei,
        shear: [ei / (k * g * a); 2],
        rho_a: rho * a,
        rho_i: [2.0 * rho * i, rho * i, rho * i],
        ..Default::default()
    };
    let mut b = ModelBuilder::new("N03 slider-crank");
    let beam = ElementSpec::Beam {
        orient: Some([0.0, 1.0, 0.0]),
        ct: 0.0,
    };
    let hinge = ElementSpec::Hinge {
        axis: [0.0, 0.0, 1.0],
        k: 0.0,
    };
    b.add_node("o", [0.0; 3], true).unwrap();
    b.add_node_at("c0", "o").unwrap();
    b.add_node("p", [N03_R, 0.0, 0.0], true).unwrap();
    b.add_node_at("r0", "p").unwrap();
    for j in 1..=n {
        let x = N03_R + N03_L * j as f64 / n as f64;
        b.add_node(&format!("r{j}"), [x, 0.0, 0.0], true).unwrap();
    }
    b.add_element("drive", &["o", "c0"], hinge.clone(), &[], &[1])
        .unwrap();
    b.add_element("crank", &["c0", "p"], beam.clone(), &[], &[])
        .unwrap();
    b.add_element("pin", &["p", "r0"], hinge, &[1], &[])
        .unwrap();
    for j in 0..n {
        let name = format!("rod{j}");
        let ends = [format!("r{j}"), format!("r{}", j + 1)];
        b.add_element(&name, &[&ends[0], &ends[1]], beam.clone(), &[], &[])
            .unwrap();
        b.set_beam_props(&name, props).unwrap();
    }
    b.prescribe_deformation("drive", 1, N03_OMEGA * t_end)
        .unwrap();
    b.fix("o", None).unwrap();
    b.fix(&format!("r{n}"), Some(&[Dof::Y, Dof::Z])).unwrap();
    b.build().unwrap()
}

/// validation.md N03: 2 crank revolutions from the rigid mechanism's velocities at crank angle
/// 0 (rod angular velocity −rω/L = −75 rad/s, the rod point at s from the pin at
/// (0, rω − 75 s)). Mid-span deflection w_mid from the chord (positive to the left of pin →
/// slider) and the slider's error against x_rigid = r cos θ + √(L² − r² sin² θ). Reference:
/// the 64-element column (planar Reissner FE, lumped mass, velocity Verlet), tolerance ±2 % on
/// the extremes, ±3° on their crank angles. The first revolution's minimum has two near-equal
/// minima (≈ 286° and ≈ 331°), so only its value is compared. 8 beams (16 change the extremes
/// by less than 0.1 %).
#[test]
fn n03_slider_crank_with_a_flexible_rod() {
    // validation.md N03, 64 elements: (value [mm], crank angle [deg])
    let max1 = (5.110, 47.0);
    let min1 = -3.585;
    let max2 = (4.008, 428.1);
    let min2 = (-5.091, 669.4);
    let slider = 0.236;
    let n = 8;
    let period = TAU / N03_OMEGA;
    let t_end = 2.0 * period;
    let model = slider_crank(n, t_end);
    let wr = -N03_R * N03_OMEGA / N03_L;
    let mut velocities = vec![
        InitialVelocity {
            node: id(&model, "c0"),
            velocity: [0.0; 3],
            angular: [0.0, 0.0, N03_OMEGA],
        },
        InitialVelocity {
            node: id(&model, "p"),
            velocity: [0.0, N03_R * N03_OMEGA, 0.0],
            angular: [0.0, 0.0, N03_OMEGA],
        },
    ];
    for j in 0..=n {
        let s = N03_L * j as f64 / n as f64;
        velocities.push(InitialVelocity {
            node: id(&model, &format!("r{j}")),
            velocity: [0.0, N03_R * N03_OMEGA + wr * s, 0.0],
            angular: [0.0, 0.0, wr],
        });
    }
    let exc = Excitation {
        prescribed: vec![TimeFunction::Ramp {
            start: 0.0,
            end: t_end,
        }],
        velocities,
        ..Default::default()
    };
    let mut o = SimOptions::new(t_end);
    o.dt = period / 1000.0;
    o.output_step = period / 1440.0; // every 0.25° of crank angle
    o.atol = 1e-8;
    o.rtol = 1e-6;
    let sim = run(&model, &exc, &o);
    let (pin, mid, end) = (
        node(&model, "r0"),
        node(&model, &format!("r{}", n / 2)),
        node(&model, &format!("r{n}")),
    );
    let mut w = Vec::new();
    let mut slider_err: f64 = 0.0;
    for f in &sim.frames {
        let (a, m, c) = (xy(f, pin), xy(f, mid), xy(f, end));
        let d = [c[0] - a[0], c[1] - a[1]];
        let len = d[0].hypot(d[1]);
        let theta = N03_OMEGA * f.t;
        w.push((
            theta.to_degrees(),
            1e3 * ((m[0] - a[0]) * -d[1] + (m[1] - a[1]) * d[0]) / len,
        ));
        let x_rigid = N03_R * theta.cos() + (N03_L.powi(2) - (N03_R * theta.sin()).powi(2)).sqrt();
        slider_err = slider_err.max((c[0] - x_rigid).abs());
    }
    let rev = |k: f64| -> Vec<(f64, f64)> {
        w.iter()
            .copied()
            .filter(|r| r.0 >= 360.0 * k - 1e-6 && r.0 <= 360.0 * (k + 1.0) + 1e-6)
            .collect()
    };
    let (r1, r2) = (rev(0.0), rev(1.0));
    let close = |got: f64, want: f64, what: &str| {
        assert!(
            ((got - want) / want).abs() < 0.02,
            "{what}: {got} vs {want}"
        );
    };
    let angle = |got: f64, want: f64, what: &str| {
        assert!((got - want).abs() < 3.0, "{what} at {got}° vs {want}°");
    };
    let (a, v) = extreme(&r1, 1.0);
    close(v, max1.0, "rev. 1 max w_mid [mm]");
    angle(a, max1.1, "rev. 1 max w_mid");
    close(extreme(&r1, -1.0).1, min1, "rev. 1 min w_mid [mm]");
    let (a, v) = extreme(&r2, 1.0);
    close(v, max2.0, "rev. 2 max w_mid [mm]");
    angle(a, max2.1, "rev. 2 max w_mid");
    let (a, v) = extreme(&r2, -1.0);
    close(v, min2.0, "rev. 2 min w_mid [mm]");
    angle(a, min2.1, "rev. 2 min w_mid");
    close(slider_err * 1e3, slider, "max |x_slider − x_rigid| [mm]");
}

// ---------------------------------------------------------------------------------------------
// Four-bar linkage (issue 13 item 6)
// ---------------------------------------------------------------------------------------------

/// The four-bar of `examples/four_bar_hinges.toml` (validation.md K06's, scaled by 0.1): ground
/// pivots g1 = (0, 0), g2 = (0.2, 0); crank g1–j1 = 0.1 m (j1 = (0, 0.1)), coupler j1–j2
/// (j2 = (0.2, 0.15)), rocker g2–j2 = 0.15 m. Grashof (0.1 + 0.206 < 0.2 + 0.15) with the
/// shortest link as the crank: a crank-rocker, the crank turns fully.
const FB_A: f64 = 0.1;
const FB_C: f64 = 0.15;
const FB_D: f64 = 0.2;

/// The coupler length |j2 − j1| of the drawn position.
fn fb_coupler() -> f64 {
    FB_D.hypot(FB_C - FB_A)
}

/// The rocker angle θ4 (from +x, about g2) for the crank angle θ2, from the loop closure
/// |g2 + c (cos θ4, sin θ4) − a (cos θ2, sin θ2)| = b: with w = g2 − j1 = ρ (cos φ, sin φ),
/// ρ c cos(θ4 − φ) = (b² − c² − ρ²)/2, on the branch of the drawn position (θ4 = π/2 at
/// θ2 = π/2; w_x ≥ d − a > 0 keeps φ continuous).
fn fb_rocker_angle(theta2: f64) -> f64 {
    let b = fb_coupler();
    let w = [FB_D - FB_A * theta2.cos(), -FB_A * theta2.sin()];
    let rho = w[0].hypot(w[1]);
    let phi = w[1].atan2(w[0]);
    phi + ((b * b - FB_C * FB_C - rho * rho) / (2.0 * FB_C * rho)).acos()
}

/// The angle difference a − b in (−π, π].
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    if d > PI {
        d - TAU
    } else {
        d
    }
}

/// Crank and rocker as rigid beams on hinges about z to the ground, the crank driven through
/// its hinge `drive` at ω = `omega` (the angle reached at `t_end` with a ramp): the crank from
/// `c1` (at the fixed g1) to j1, the rocker from `r3` (at the fixed g2) to j2.
fn fb_base(name: &str, omega: f64, t_end: f64) -> ModelBuilder {
    let mut b = ModelBuilder::new(name);
    let z = [0.0, 0.0, 1.0];
    let beam = ElementSpec::Beam {
        orient: Some(z),
        ct: 0.0,
    };
    let hinge = ElementSpec::Hinge { axis: z, k: 0.0 };
    b.add_node("g1", [0.0; 3], true).unwrap();
    b.add_node_at("c1", "g1").unwrap();
    b.add_node("j1", [0.0, FB_A, 0.0], true).unwrap();
    b.add_node("g2", [FB_D, 0.0, 0.0], true).unwrap();
    b.add_node_at("r3", "g2").unwrap();
    b.add_node("j2", [FB_D, FB_C, 0.0], true).unwrap();
    b.add_element("crank", &["c1", "j1"], beam.clone(), &[], &[])
        .unwrap();
    b.add_element("rocker", &["r3", "j2"], beam, &[], &[])
        .unwrap();
    b.add_element("drive", &["g1", "c1"], hinge.clone(), &[], &[1])
        .unwrap();
    b.add_element("hD", &["r3", "g2"], hinge, &[1], &[])
        .unwrap();
    b.prescribe_deformation("drive", 1, omega * t_end).unwrap();
    b.fix("g1", None).unwrap();
    b.fix("g2", None).unwrap();
    b
}

/// The largest difference of the simulated rocker angle from the loop closure over the frames.
fn fb_rocker_error(model: &Model, sim: &Simulation, omega: f64) -> f64 {
    let j2 = node(model, "j2");
    sim.frames
        .iter()
        .map(|f| {
            let [x, y] = xy(f, j2);
            let got = y.atan2(x - FB_D);
            // the crank angle from +x: π/2 in the drawn position plus the turned angle
            angle_diff(got, fb_rocker_angle(FRAC_PI_2 + omega * f.t)).abs()
        })
        .fold(0.0, f64::max)
}

/// Options of the four-bar runs: two crank revolutions at ω = 10 rad/s, 100 outputs.
fn fb_options(t_end: f64) -> SimOptions {
    let mut o = SimOptions::new(t_end);
    o.atol = 1e-9;
    o.rtol = 1e-7;
    o
}

/// A rigid crank-rocker: rigid crank and rocker on hinges, the coupler a rigid truss (a link
/// with a ball joint at each end, so the planar loop has no redundant constraint), point masses
/// of 0.5 kg at j1 and j2; the crank driven at constant speed from t = 0 (a ramp: the input's
/// rate at the start sets the initial velocities). Two revolutions: the driven hinge's angle
/// passes its branch cut at ±π twice. The rocker angle follows the loop closure to round-off
/// (1e-9 rad: the constraints are kept at every step; measured 6e-14).
#[test]
fn rigid_four_bar_follows_the_loop_closure() {
    let omega = 10.0;
    let t_end = 2.0 * TAU / omega;
    let mut b = fb_base("rigid crank-rocker", omega, t_end);
    b.add_element(
        "coupler",
        &["j1", "j2"],
        ElementSpec::Truss { ea: 0.0 },
        &[],
        &[],
    )
    .unwrap();
    b.add_point_mass("j1", 0.5).unwrap();
    b.add_point_mass("j2", 0.5).unwrap();
    let model = b.build().unwrap();
    let exc = Excitation {
        prescribed: vec![TimeFunction::Ramp {
            start: 0.0,
            end: t_end,
        }],
        ..Default::default()
    };
    let sim = run(&model, &exc, &fb_options(t_end));
    let err = fb_rocker_error(&model, &sim, omega);
    assert!(err < 1e-9, "rocker angle off the loop closure by {err} rad");
}

/// The same four-bar as a spatial mechanism of four hinges about z and three stiff beams
/// (EI = GJ = 1e6 N·m², EA = 1e9 N, 1 kg/m), as `examples/four_bar_hinges.toml`: the planar loop
/// is over-constrained in space (three self-stresses), which the stiff links absorb. Started
/// with the rigid mechanism's velocities (at θ2 = π/2 the loop closure gives the rocker
/// ω4 = 2ω/3 and a coupler that translates at (−aω, 0)), the rocker angle follows the loop
/// closure within 1e-6 rad (measured 7e-8 rad, and 7.5e-6 rad with EI = 1e4: the links'
/// elastic deflection under the inertia loads, ∝ 1/EI).
#[test]
fn four_bar_of_hinges_and_stiff_links_follows_the_loop_closure() {
    let omega = 10.0;
    let t_end = 2.0 * TAU / omega;
    let mut b = fb_base("four-bar of hinges", omega, t_end);
    let z = [0.0, 0.0, 1.0];
    let hinge = ElementSpec::Hinge { axis: z, k: 0.0 };
    b.add_node_at("k1", "j1").unwrap();
    b.add_node_at("r2", "j2").unwrap();
    b.add_element("hB", &["j1", "k1"], hinge.clone(), &[1], &[])
        .unwrap();
    b.add_element("hC", &["j2", "r2"], hinge, &[1], &[])
        .unwrap();
    let beam = ElementSpec::Beam {
        orient: Some(z),
        ct: 0.0,
    };
    b.add_element("coupler", &["k1", "r2"], beam, &[], &[])
        .unwrap();
    let ei = 1e6;
    let props = BeamProps {
        ea: 1e3 * ei,
        gj: ei,
        eiy: ei,
        eiz: ei,
        rho_a: 1.0,
        rho_i: [2e-4, 1e-4, 1e-4],
        ..Default::default()
    };
    for link in ["crank", "rocker", "coupler"] {
        b.set_beam_props(link, props).unwrap();
    }
    let model = b.build().unwrap();
    let v = |name: &str, velocity: [f64; 3], wz: f64| InitialVelocity {
        node: id(&model, name),
        velocity,
        angular: [0.0, 0.0, wz],
    };
    let u = [-FB_A * omega, 0.0, 0.0];
    let w4 = 2.0 * omega / 3.0;
    let exc = Excitation {
        prescribed: vec![TimeFunction::Ramp {
            start: 0.0,
            end: t_end,
        }],
        velocities: vec![
            v("c1", [0.0; 3], omega),
            v("j1", u, omega),
            v("k1", u, 0.0),
            v("r2", u, 0.0),
            v("j2", u, w4),
            v("r3", [0.0; 3], w4),
        ],
        ..Default::default()
    };
    let sim = run(&model, &exc, &fb_options(t_end));
    let err = fb_rocker_error(&model, &sim, omega);
    assert!(err < 1e-6, "rocker angle off the loop closure by {err} rad");
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
