//! Nothing lost (issue 17, item 3), the numbers of the converged part at the io level: a static
//! path that stops part-way keeps every converged step, and the linearised analyses about its
//! last converged state see the limit point. The command line's writing of those steps in every
//! format, the marks and exit code 1 are tested in `crates/flexmbd-cli/tests/stopped_path.rs`.
//!
//! Input: examples/williams_toggle.toml (validation S05, the Williams toggle frame: a dead load
//! of 180 N on the whole frame, beyond its limit load P_max = 150.66 N) with at most 6 Newton
//! iterations per step, so that Newton cannot jump to the far branch and the path stops at the
//! limit point, load factor 150.66/180 = 0.8370 (validation.md: P_max ±0.5 %).

use flexmbd_core::dynamics::state_space::StateSpaceOptions;
use flexmbd_core::dynamics::{modes_with, ModalOptions};
use flexmbd_core::linearized::{at_step, LinearRequest};
use flexmbd_core::statics::Stopped;
use flexmbd_io::ModelFile;
use std::path::Path;

mod common;
use common::example;

/// The limit load factor (validation.md S05).
const LIMIT: f64 = 150.66 / 180.0;

/// The toggle of the example with 6 Newton iterations per step (`max_iterations = 6` in its
/// `[static]` table), and its path, which stops.
fn toggle() -> (ModelFile, Stopped) {
    let mut f = common::read(&example("williams_toggle.toml"));
    assert_eq!(f.settings.steps, Some(20));
    f.settings.max_iterations = Some(6);
    let stopped = common::static_path(&f).expect_err("the path stops at the limit point");
    (f, stopped)
}

/// The path stops after step 17 (steps 0 … 16 on the grid, 17 the last converged sub-step) near
/// the limit point, where the tangent is almost singular: the buckling multiplier of the last
/// state is near 1.
#[test]
fn the_path_stops_at_the_limit_point() {
    let (f, s) = toggle();
    assert!(
        s.error.to_string().contains("no equilibrium found"),
        "{}",
        s.error
    );
    let steps = &s.analysis.solution.steps;
    assert_eq!(steps.len(), 18);
    let t = steps[17].load_factor;
    assert!((t - LIMIT).abs() < 5e-3 * LIMIT, "{t} vs {LIMIT}");
    let request = LinearRequest {
        buckling: 1,
        ..Default::default()
    };
    let mu = at_step(&f.model, &steps[17], &request)
        .buckling
        .expect("buckling")
        .multipliers[0];
    assert!(mu > 1.0 && mu < 1.1, "{mu}");
}

/// Modes and the state space about the last converged state, near the limit point: the lowest
/// frequency is far below that of the unloaded frame (the stiffness vanishes at the limit
/// point).
#[test]
fn the_last_converged_state_is_near_the_limit_point() {
    let (f, s) = toggle();
    let steps = &s.analysis.solution.steps;
    let lowest = |k: usize| {
        modes_with(&f.model, &steps[k], 2, &ModalOptions::default())
            .unwrap_or_else(|e| panic!("{e}"))
            .modes[0]
            .frequency
    };
    let (f0, f17) = (lowest(0), lowest(17));
    assert!(f17 < 0.5 * f0, "{f17} vs {f0}");
    let io = ["apex:y"];
    let opts = StateSpaceOptions::default();
    let lowest = |k: usize| {
        common::state_space_of(&f, "toggle.toml", &steps[k], &io, &io, &opts).frequencies()[0]
    };
    let (f0, f17) = (lowest(0), lowest(17));
    assert!(f17 < 0.5 * f0, "{f17} vs {f0}");
}

/// tests/reliability/manual_wrong_static_inverted_column of the command line: a column crushed
/// through its root in 4 steps; the unloaded state and the last valid sub-step are kept.
#[test]
fn an_inverted_column_keeps_its_valid_steps() {
    let mut f = common::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../flexmbd-cli/tests/reliability/manual_wrong_static_inverted_column/in.toml"),
    );
    f.settings.steps = Some(4);
    let s = common::static_path(&f).expect_err("the path stops");
    assert!(s.error.to_string().contains("inverted"), "{}", s.error);
    let steps = &s.analysis.solution.steps;
    assert_eq!(steps.len(), 2);
    let t = steps[1].load_factor;
    assert!(t > 0.0 && t < 0.25, "{t}");
}
