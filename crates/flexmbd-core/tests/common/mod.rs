//! Model builders and helpers shared by the core's validation tests (each test file is its own
//! crate and includes this module).

#![allow(dead_code)]

use flexmbd_core::model::{Dof, ModelBuilder, Spin};
use flexmbd_core::section::{BeamProps, Material, Shape};
use flexmbd_core::statics::{solve, StaticOptions, StepResult};
use flexmbd_core::Model;

/// Structural steel: E = 210 GPa, G = E/2.6, ρ = 7800 kg/m³.
pub const STEEL: Material = Material {
    e: 210e9,
    g: 210e9 / 2.6,
    rho: 7800.0,
};

/// The last step of a static solution over `steps` load steps (the test fails if it does not
/// converge).
pub fn last_step(model: &Model, steps: usize) -> StepResult {
    let opts = StaticOptions {
        steps,
        ..Default::default()
    };
    let mut sol = solve(model, &opts, |_, _| {}).expect("the static solution converges");
    sol.steps.pop().expect("at least one step")
}

/// `n` beams along x from the origin, length `l`, width 20 mm along global y and thickness
/// 0.2 mm along global z (a steel strip, shear-flexible); nothing held.
pub fn strip_builder(n: usize, l: f64) -> ModelBuilder {
    let mut b = ModelBuilder::new("blade");
    let props = BeamProps::from_section(&STEEL, &Shape::Rectangle { w: 0.02, t: 0.2e-3 }, true);
    b.add_beam_chain(
        "",
        [0.0; 3],
        [l, 0.0, 0.0],
        n,
        Some([0.0, 1.0, 0.0]),
        Some(props),
    )
    .unwrap();
    b
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

/// validation.md S05 (Williams toggle frame) in its consistent units (in, lbf, psi): the half
/// model of the clamped two-bar arch, half span 12.943, rise 0.386, b = 0.753, h = 0.243,
/// E = 10.3e6, extensible Euler–Bernoulli, 20 elements; the apex `n20` with its horizontal
/// displacement and rotations held (symmetry), its deflection free.
pub fn toggle_builder() -> ModelBuilder {
    let mat = Material {
        e: 10.3e6,
        g: 10.3e6 / 2.6,
        rho: 0.0,
    };
    let props = BeamProps::from_section(&mat, &Shape::Rectangle { w: 0.753, t: 0.243 }, true);
    let mut b = ModelBuilder::new("toggle");
    b.add_beam_chain(
        "",
        [12.943, 0.0, 0.0],
        [0.0, 0.386, 0.0],
        20,
        Some([0.0, 0.0, 1.0]),
        Some(props),
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
