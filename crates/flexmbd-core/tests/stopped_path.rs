//! Nothing lost (issue 17, item 3): a static path that stops part-way returns every converged
//! step with the error, and the linearised results at those steps.

mod common;

use common::toggle_under_load;
use flexmbd_core::linearized::analyse;
use flexmbd_core::linearized::LinearRequest;
use flexmbd_core::model::ModelBuilder;
use flexmbd_core::statics::{solve, solve_path, SolveError, StaticOptions};

/// The limit load of S05 under load control: P_max = 33.870 lbf (validation.md, ±0.5 %).
const P_MAX: f64 = 33.870;

#[test]
fn a_path_stopped_at_its_limit_point_keeps_every_converged_step() {
    // 40 lbf in 20 steps, at most 6 Newton iterations per step: the steps up to the limit
    // point converge, none beyond (Newton would need more iterations to jump to the far
    // branch), so the path stops at P_max / 40 = 0.8468
    let model = toggle_under_load(40.0);
    let opts = StaticOptions {
        steps: 20,
        max_iterations: 6,
        ..Default::default()
    };
    let stopped = solve_path(&model, &opts, |_, _| {}).unwrap_err();
    let SolveError::NoConvergence { last_converged, .. } = stopped.error else {
        panic!("{:?}", stopped.error);
    };
    let steps = &stopped.analysis.solution.steps;
    // steps 0 … 16 on the grid of 0.05, then the last converged sub-step
    let limit = P_MAX / 40.0;
    assert_eq!(
        steps.len(),
        18,
        "{:?}",
        steps.iter().map(|s| s.load_factor).collect::<Vec<_>>()
    );
    for (k, st) in steps[..17].iter().enumerate() {
        assert!((st.load_factor - 0.05 * k as f64).abs() < 1e-12);
    }
    let last = steps[17].load_factor;
    assert_eq!(last, last_converged);
    assert!(
        last > 0.8 && (last - limit).abs() < 5e-3 * limit,
        "{last} vs {limit}"
    );
    // the stop is an error of the plain solve too, without the steps
    assert_eq!(solve(&model, &opts, |_, _| {}).unwrap_err(), stopped.error);
    // the linearised results at every converged step: stable up to the limit point, where the
    // tangent becomes singular: the buckling multiplier of the current load falls to 1 there,
    // as 1 + O(√(1 − P/P_max)) (within 0.5 % of P_max: 1 + about 0.07 at most)
    let req = LinearRequest {
        buckling: 1,
        ..Default::default()
    };
    let stopped = analyse(&model, &opts, &req, |_, _| {}).unwrap_err();
    let lin = &stopped.analysis.linear;
    assert_eq!(lin.len(), 18);
    assert!(lin.iter().all(|l| l.unstable_directions == Some(0)));
    let mu = lin[17].buckling.as_ref().unwrap().multipliers[0];
    assert!(mu > 1.0 && mu < 1.1, "μ1 at the last state {mu}");
    let mu16 = lin[16].buckling.as_ref().unwrap().multipliers[0];
    assert!(mu16 > mu, "{mu16} {mu}");
    assert!(
        stopped.to_string().contains("stopped after step 17"),
        "{stopped}"
    );
}

#[test]
fn a_path_that_fails_at_once_has_no_step() {
    // no free coordinate: nothing converges, and nothing is returned
    let mut b = ModelBuilder::new("held");
    b.add_node("a", [0.0; 3], false).unwrap();
    b.add_node("b", [1.0, 0.0, 0.0], false).unwrap();
    b.add_element(
        "t",
        &["a", "b"],
        flexmbd_core::model::ElementSpec::Truss { ea: 1.0 },
        &[],
        &[],
    )
    .unwrap();
    b.fix("a", None).unwrap();
    b.fix("b", None).unwrap();
    let model = b.build().unwrap();
    let s = solve_path(&model, &StaticOptions::default(), |_, _| {}).unwrap_err();
    assert!(s.analysis.solution.steps.is_empty());
    assert!(s.to_string().contains("before any state converged"), "{s}");
}
