//! Model builders and helpers shared by the core's validation tests (each test file is its own
//! crate and includes this module).

#![allow(dead_code)]

pub mod flexures;

use flexmbd_core::model::{Dof, ModelBuilder, Spin};
use flexmbd_core::section::{BeamProps, Material, Shape};
use flexmbd_core::simulation::{simulate, Excitation, Frame, SimOptions, Simulation};
use flexmbd_core::statics::{solve, SolveError, StaticOptions, StaticSolution, StepResult};
use flexmbd_core::Model;

/// Structural steel: E = 210 GPa, G = E/2.6, ρ = 7800 kg/m³.
pub const STEEL: Material = Material {
    e: 210e9,
    g: 210e9 / 2.6,
    rho: 7800.0,
};

/// Spring steel of the validation instances (S09, F01, X02): E = 200 GPa, G = E/2.6,
/// ρ = 7800 kg/m³.
pub const SPRING_STEEL: Material = Material {
    e: 200e9,
    g: 200e9 / 2.6,
    rho: 7800.0,
};

/// A static solution over `steps` load steps with default settings otherwise.
pub fn solve_steps(model: &Model, steps: usize) -> Result<StaticSolution, SolveError> {
    let opts = StaticOptions {
        steps,
        ..Default::default()
    };
    solve(model, &opts, |_, _| {})
}

/// The last step of a static solution over `steps` load steps (the test fails if it does not
/// converge).
pub fn last_step(model: &Model, steps: usize) -> StepResult {
    let mut sol = solve_steps(model, steps).expect("the static solution converges");
    sol.steps.pop().expect("at least one step")
}

/// `n` beams `n0`…`n{n}` along x from the origin to (l, 0, 0), with beam constants `props` and
/// orientation vector `orient` (the local y axis); nothing held.
pub fn beam_chain(
    name: &str,
    n: usize,
    l: f64,
    orient: [f64; 3],
    props: BeamProps,
) -> ModelBuilder {
    let mut b = ModelBuilder::new(name);
    b.add_beam_chain("", [0.0; 3], [l, 0.0, 0.0], n, Some(orient), Some(props))
        .unwrap();
    b
}

/// A straight cantilever along +x of `n` beams (orientation vector y), clamped at x = 0.
pub fn cantilever(n: usize, l: f64, props: BeamProps) -> ModelBuilder {
    let mut b = beam_chain("cantilever", n, l, [0.0, 1.0, 0.0], props);
    b.fix("n0", None).unwrap();
    b
}

/// Tip position (x, y) and rotation about z of a planar solution `x` of a chain.
pub fn tip(model: &Model, x: &[f64]) -> (f64, f64, f64) {
    let n = model.nodes.last().unwrap();
    let r = n.ix_rot.unwrap();
    (x[n.ix_pos], x[n.ix_pos + 1], 2.0 * x[r + 3].atan2(x[r]))
}

/// A strip along x of `n` beams with its width along global z (orientation vector), so that
/// bending about its weak axis moves the nodes along y; clamped at `n0` when `clamp`.
pub fn strip(n: usize, l: f64, props: BeamProps, clamp: bool) -> ModelBuilder {
    let mut b = beam_chain("strip", n, l, [0.0, 0.0, 1.0], props);
    if clamp {
        b.fix("n0", None).unwrap();
    }
    b
}

/// The spring-steel strip of S09 and F01: b = 20 mm, t = 0.5 mm, E = 200 GPa, ρ = 7800 kg/m³,
/// Euler–Bernoulli; weak-axis EI = 0.0416667 N·m².
pub fn spring_steel_strip() -> BeamProps {
    BeamProps::from_section(
        &SPRING_STEEL,
        &Shape::Rectangle { w: 0.02, t: 0.5e-3 },
        true,
    )
}

/// `n` beams along x from the origin, length `l`, width 20 mm along global y and thickness
/// 0.2 mm along global z (a steel strip, shear-flexible); nothing held.
pub fn strip_builder(n: usize, l: f64) -> ModelBuilder {
    let props = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.02, t: 0.2e-3 }, true);
    beam_chain("blade", n, l, [0.0, 1.0, 0.0], props)
}

/// The strip of [`strip_builder`] clamped at the root, with an optional tip mass, turning with
/// `spin`.
pub fn radial_strip(n: usize, l: f64, tip: f64, spin: Spin) -> Model {
    let mut b = strip_builder(n, l);
    if tip > 0.0 {
        b.add_point_mass(&format!("n{n}"), tip).unwrap();
    }
    b.fix("n0", None).unwrap();
    b.set_spin(spin.omega, spin.point).unwrap();
    b.build().unwrap()
}

/// The material of the S05 toggle: E = 10.3e6 psi (G = E/2.6, no mass).
pub const TOGGLE_MATERIAL: Material = Material {
    e: 10.3e6,
    g: 10.3e6 / 2.6,
    rho: 0.0,
};

/// The members of the S05 toggle: b = 0.753 in (out of plane) × h = 0.243 in,
/// extensible Euler–Bernoulli.
pub fn toggle_props() -> BeamProps {
    BeamProps::from_section(
        &TOGGLE_MATERIAL,
        &Shape::Rectangle { w: 0.753, t: 0.243 },
        true,
    )
}

/// validation.md S05 (Williams toggle frame) in its consistent units (in, lbf, psi): the half
/// model of the clamped two-bar arch, half span 12.943, rise 0.386, b = 0.753, h = 0.243,
/// E = 10.3e6, extensible Euler–Bernoulli, 20 elements; the apex `n20` with its horizontal
/// displacement and rotations held (symmetry), its deflection free.
pub fn toggle_builder() -> ModelBuilder {
    let mut b = ModelBuilder::new("toggle");
    b.add_beam_chain(
        "",
        [12.943, 0.0, 0.0],
        [0.0, 0.386, 0.0],
        20,
        Some([0.0, 0.0, 1.0]),
        Some(toggle_props()),
    )
    .unwrap();
    b.fix("n0", None).unwrap();
    b.fix("n20", Some(&[Dof::X, Dof::Z, Dof::Rx, Dof::Ry, Dof::Rz]))
        .unwrap();
    b
}

/// The toggle of [`toggle_builder`] under a dead load p on the whole frame (−p/2 along y at
/// the apex of the half model).
pub fn toggle_under_load(p: f64) -> Model {
    let mut b = toggle_builder();
    b.add_load("n20", [0.0, -0.5 * p, 0.0], [0.0; 3]).unwrap();
    b.build().unwrap()
}

/// A simulation that must run to its end (the test fails with the error otherwise).
pub fn run(model: &Model, exc: &Excitation, o: &SimOptions) -> Simulation {
    simulate(model, exc, o, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

/// The complete elliptic integral of the first kind K(k), by the arithmetic-geometric mean.
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut g) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - g).abs() > 1e-15 * a {
        (a, g) = (0.5 * (a + g), (a * g).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// A very stiff uniform bar of length 1 m and 1 kg/m pinned at the origin (rotation about y
/// only), hanging at `theta0` from the downward vertical in the x-z plane, in `n` beams.
pub fn pendulum(theta0: f64, n: usize, rho_i: f64) -> Model {
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

/// Angle of the tip of the [`pendulum`] from the downward vertical.
pub fn tip_angle(model: &Model, f: &Frame) -> f64 {
    let tip = &model.nodes[model.nodes.len() - 1];
    let (x, z) = (f.x[tip.ix_pos], f.x[tip.ix_pos + 2]);
    x.atan2(-z)
}
