//! Arc-length path following (issue 17, item 1) against closed forms: the shallow two-bar
//! (von Mises) truss through both limit points under load control, and with a soft spring in
//! series, through a snap-back of the loaded end that displacement control cannot follow; the
//! smallest eigenvalue of the tangent along the path, the located limit points and bifurcations
//! (S05, the truss, the Euler column), and a prescribed end rotation.

mod common;

use flexmbd_core::model::{Dof, ElementSpec, ModelBuilder};
use flexmbd_core::statics::{solve_path, PathEvent, PathMethod, StaticOptions, StaticSolution};
use flexmbd_core::Model;
// `crate::model` and `crate::section` of the shared statics test models
use flexmbd_core::{model, section};

#[path = "../src/statics/test_models.rs"]
mod test_models;

/// Half span, rise [m] and axial stiffness EA [N] of the truss; the load at full load [N].
const A: f64 = 1.0;
const H: f64 = 0.1;
const EA: f64 = 1e6;
const P: f64 = 1000.0;

/// The truss's vertical load at the apex height y, from the equilibrium of the apex with the
/// axial forces N = EA (L − L0)/L0 of the bars (L = √(a² + y²), the truss element's law):
/// P(y) = −2 N y/L = 2 EA (y/L − y/L0).
fn load_at(y: f64) -> f64 {
    let (l, l0) = ((A * A + y * y).sqrt(), (A * A + H * H).sqrt());
    2.0 * EA * (y / l - y / l0)
}

/// The two limit points: dP/dy = 2 EA (a²/L³ − 1/L0) = 0 at L = (a² L0)^⅓, y = ±√(L² − a²).
fn limit_height() -> f64 {
    let l0 = (A * A + H * H).sqrt();
    let l = (A * A * l0).cbrt();
    (l * l - A * A).sqrt()
}

/// The truss in the x-y plane: supports at (±a, 0), apex c at (0, h) free in x and y; with a
/// spring (a truss of stiffness k and length ls) from c up to the loaded node q, free in y
/// only, when `spring` is given; the load −P along y on the loaded node, or its displacement
/// `stroke` prescribed instead.
fn truss(spring: Option<(f64, f64)>, stroke: Option<f64>) -> Model {
    let mut b = ModelBuilder::new("von Mises truss");
    b.add_node("a", [-A, 0.0, 0.0], false).unwrap();
    b.add_node("b", [A, 0.0, 0.0], false).unwrap();
    b.add_node("c", [0.0, H, 0.0], false).unwrap();
    b.fix("a", None).unwrap();
    b.fix("b", None).unwrap();
    b.fix("c", Some(&[Dof::Z])).unwrap();
    for (name, end) in [("ac", "a"), ("bc", "b")] {
        b.add_element(name, &[end, "c"], ElementSpec::Truss { ea: EA }, &[], &[])
            .unwrap();
    }
    let loaded = match spring {
        Some((k, ls)) => {
            b.add_node("q", [0.0, H + ls, 0.0], false).unwrap();
            b.fix("q", Some(&[Dof::X, Dof::Z])).unwrap();
            b.add_element(
                "s",
                &["c", "q"],
                ElementSpec::Truss { ea: k * ls },
                &[],
                &[],
            )
            .unwrap();
            "q"
        }
        None => "c",
    };
    match stroke {
        Some(v) => b.prescribe_coordinate(loaded, Dof::Y, v).unwrap(),
        None => b.add_load(loaded, [0.0, -P, 0.0], [0.0; 3]).unwrap(),
    }
    b.build().unwrap()
}

fn arc(model: &Model, steps: usize) -> StaticSolution {
    arc_with(model, steps, false)
}

/// [`arc`] with the tangent's smallest eigenvalues κ at every step.
fn arc_kappa(model: &Model, steps: usize) -> StaticSolution {
    arc_with(model, steps, true)
}

fn arc_with(model: &Model, steps: usize, tangent_eigenvalues: bool) -> StaticSolution {
    let opts = StaticOptions {
        steps,
        path: PathMethod::ArcLength,
        tangent_eigenvalues,
        ..Default::default()
    };
    solve_path(model, &opts, |_, _| {}).expect("the path reaches the full load")
}

/// y of node `name` at every step.
fn heights(model: &Model, sol: &StaticSolution, name: &str) -> Vec<f64> {
    let i = model.nodes[model.node_id(name).unwrap()].ix_pos + 1;
    sol.steps.iter().map(|s| s.x[i]).collect()
}

#[test]
fn von_mises_truss_through_both_limit_points() {
    let model = truss(None, None);
    let sol = arc(&model, 40);
    let y = heights(&model, &sol, "c");
    let n = sol.steps.len();
    assert_eq!(sol.path.len(), n);
    // every point of the path on the closed-form path
    for (st, &y) in sol.steps.iter().zip(&y) {
        let want = load_at(y);
        assert!(
            (st.load_factor * P - want).abs() < 1e-7 * EA * H * H * H,
            "y = {y}: P = {} vs {want}",
            st.load_factor * P
        );
    }
    // from the unloaded state to the full load on the far branch, through y = 0
    assert_eq!(sol.steps[n - 1].load_factor, 1.0);
    assert!(y[n - 1] < -limit_height() && y.iter().any(|&v| v.abs() < 0.2 * H));
    // both limit points found, each at the sampled extreme of the load: P_max = P(y*) and
    // −P_max = P(−y*)
    let p_max = load_at(limit_height());
    let limits: Vec<(usize, f64)> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::LimitPoint {
                step, load_factor, ..
            } => Some((step, load_factor)),
            _ => None,
        })
        .collect();
    assert_eq!(limits.len(), 2, "{:?}", sol.events);
    assert!(
        (limits[0].1 * P - p_max).abs() < 0.01 * p_max,
        "{limits:?} {p_max}"
    );
    assert!(
        (limits[1].1 * P + p_max).abs() < 0.01 * p_max,
        "{limits:?} {p_max}"
    );
    // no load on the unstable branch beyond them
    let (i0, i1) = (limits[0].0, limits[1].0);
    assert!(sol.steps[i0..=i1]
        .iter()
        .all(|s| s.load_factor.abs() <= limits[0].1.max(-limits[1].1)));
    // stability from the inertia: stable outside the limit points, one unstable direction
    // between them (y* > y > −y*; points within 10 % of y* of a limit point left out)
    let ys = limit_height();
    for (p, &y) in sol.path.iter().zip(&y) {
        if (y.abs() - ys).abs() < 0.1 * ys {
            continue;
        }
        let want = if y.abs() < ys { 1 } else { 0 };
        assert_eq!(p.unstable_directions, Some(want), "y = {y}");
    }
    // the path parameter grows
    assert!(sol
        .path
        .windows(2)
        .all(|w| w[1].arc_length > w[0].arc_length));
}

#[test]
fn a_snap_back_that_displacement_control_cannot_follow() {
    // a spring of k = 2000 N/m (ls = 1 m) in series: softer than the steepest unstable slope
    // of the truss, max dP/dy = 2 EA (1/a − 1/L0) = 9950 N/m at y = 0, so the loaded end q
    // (y_q = y_c + ls (1 − P/(k ls)), the spring's law) moves back up while the apex snaps
    let (k, ls) = (2000.0, 1.0);
    let model = truss(Some((k, ls)), None);
    let sol = arc(&model, 40);
    let (yc, yq) = (heights(&model, &sol, "c"), heights(&model, &sol, "q"));
    for ((st, &c), &q) in sol.steps.iter().zip(&yc).zip(&yq) {
        let p = st.load_factor * P;
        assert!((p - load_at(c)).abs() < 1e-7 * EA * H * H * H, "y_c = {c}");
        assert!(
            (q - (c + ls * (1.0 - p / (k * ls)))).abs() < 1e-9,
            "y_q = {q}"
        );
    }
    assert_eq!(sol.steps.last().unwrap().load_factor, 1.0);
    // the snap-back: q first goes down, then back up, then down again
    let turns = yq
        .windows(3)
        .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
        .count();
    assert!(turns >= 2, "{yq:?}");
    let q_low = yq.iter().cloned().fold(f64::INFINITY, f64::min);
    let q_turn = yq
        .windows(3)
        .find(|w| w[1] < w[0] && w[2] > w[1])
        .map(|w| w[1])
        .expect("q turns back");
    // displacement control of q down to the same end point: y_q is the step variable, so it
    // cannot follow the path where y_q turns back; it stops at the first turn of q (or jumps
    // across the states between the turns within one step)
    let end = *yq.last().unwrap() - (H + ls);
    let stroke = truss(Some((k, ls)), Some(end));
    let opts = StaticOptions {
        steps: 200,
        ..Default::default()
    };
    let gap = |y: &[f64]| {
        y.windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0f64, f64::max)
    };
    match solve_path(&stroke, &opts, |_, _| {}) {
        Ok(s) => assert!(gap(&heights(&stroke, &s, "c")) > 0.1 * H),
        Err(s) => {
            let yq_stroke = heights(&stroke, &s.analysis.solution, "q");
            let last = *yq_stroke.last().unwrap();
            assert!((last - q_turn).abs() < 0.01 * ls, "{last} vs {q_turn}");
        }
    }
    // the arc-length path goes on in small steps of the apex, and q comes back down below its
    // turn
    assert!(gap(&yc) < 0.2 * H, "{}", gap(&yc));
    assert!(q_low < q_turn);
}

/// The vertex (x, y) of the parabola through three points.
fn vertex(p: [(f64, f64); 3]) -> (f64, f64) {
    let [(x0, y0), (x1, y1), (x2, y2)] = p;
    // divided differences: y = y0 + d1 (x − x0) + d2 (x − x0)(x − x1)
    let d1 = (y1 - y0) / (x1 - x0);
    let d2 = ((y2 - y1) / (x2 - x1) - d1) / (x2 - x0);
    let x = 0.5 * (x0 + x1) - d1 / (2.0 * d2);
    (x, y0 + d1 * (x - x0) + d2 * (x - x0) * (x - x1))
}

#[test]
fn s05_toggle_under_load_control_by_arc_length() {
    // validation.md S05: P_max = 33.870 lbf at δ = 0.2325 in, then the minimum 31.282 lbf at
    // δ = 0.3925 in (loads ±0.5 %, deflections ±3 %); at 40 lbf the frame has snapped through:
    // between δ = 0.5 in (36.097 lbf) and 0.6 in (53.313 lbf)
    let model = common::toggle_under_load(40.0);
    let sol = arc(&model, 40);
    let iy = model.nodes[model.node_id("n20").unwrap()].ix_pos + 1;
    let pts: Vec<(f64, f64)> = sol
        .steps
        .iter()
        .map(|s| (0.386 - s.x[iy], 40.0 * s.load_factor))
        .collect();
    let limits: Vec<usize> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::LimitPoint { step, .. } => Some(step),
            _ => None,
        })
        .collect();
    assert_eq!(limits.len(), 2, "{:?}", sol.events);
    let at = |k: usize| vertex([pts[k - 1], pts[k], pts[k + 1]]);
    let (d_max, p_max) = at(limits[0]);
    assert!((p_max - 33.870).abs() < 5e-3 * 33.870, "P_max {p_max}");
    assert!((d_max - 0.2325).abs() < 0.03 * 0.2325, "δ at P_max {d_max}");
    let (d_min, p_min) = at(limits[1]);
    assert!((p_min - 31.282).abs() < 5e-3 * 31.282, "P_min {p_min}");
    assert!((d_min - 0.3925).abs() < 0.03 * 0.3925, "δ at P_min {d_min}");
    let (d_end, p_end) = *pts.last().unwrap();
    assert_eq!(p_end, 40.0);
    assert!(d_end > 0.5 && d_end < 0.6, "{d_end}");
    // stable up to the limit point, unstable between the limit points, stable after
    for (k, p) in sol.path.iter().enumerate() {
        if k + 1 < limits[0] || (k > limits[0] + 1 && k + 1 < limits[1]) || k > limits[1] + 1 {
            let want = usize::from(k > limits[0] && k < limits[1]);
            assert_eq!(p.unstable_directions, Some(want), "step {k}");
        }
    }
}

#[test]
fn s05_toggle_under_a_stroke_by_arc_length() {
    // the same frame with the apex deflection prescribed to 0.7 in (a stroke): the load is the
    // reaction, P = −2 r_y; validation.md S05: P_max = 33.870 lbf at δ = 0.2325 in, P = 88.184
    // lbf at 0.7 in (±0.5 %, δ ±3 %); the stroke itself never turns back: no limit point
    let mut b = common::toggle_builder();
    b.prescribe_coordinate("n20", Dof::Y, -0.7).unwrap();
    let model = b.build().unwrap();
    let iy = model.nodes[model.node_id("n20").unwrap()].ix_pos + 1;
    let sol = arc(&model, 40);
    assert!(sol.events.is_empty(), "{:?}", sol.events);
    let pts: Vec<(f64, f64)> = sol
        .steps
        .iter()
        .map(|s| (0.386 - s.x[iy], -2.0 * s.reactions[iy]))
        .collect();
    assert!(pts.windows(2).all(|w| w[1].0 > w[0].0));
    let (d_end, p_end) = *pts.last().unwrap();
    assert!((d_end - 0.7).abs() < 1e-12);
    assert!((p_end - 88.184).abs() < 5e-3 * 88.184, "{p_end}");
    // the largest load before the snap (δ < 0.35 in: the frame stiffens again after it)
    let k = (1..pts.len() - 1)
        .filter(|&k| pts[k].0 < 0.35)
        .max_by(|&a, &b| pts[a].1.total_cmp(&pts[b].1))
        .expect("a maximum before the snap");
    let (d_max, p_max) = vertex([pts[k - 1], pts[k], pts[k + 1]]);
    assert!((p_max - 33.870).abs() < 5e-3 * 33.870, "P_max {p_max}");
    assert!((d_max - 0.2325).abs() < 0.03 * 0.2325, "δ at P_max {d_max}");
}

/// The column of [`test_models::column`] (EI_y = 1 N·m², EI_z = 4) in 20 elements, with the
/// tip load (−p, 0, q).
fn column(p: f64, q: f64) -> Model {
    column_of(20, p, q)
}

/// [`column`] with `n` elements.
fn column_of(n: usize, p: f64, q: f64) -> Model {
    test_models::column(n, 4.0, [-p, 0.0, q]).build().unwrap()
}

#[test]
fn a_column_into_post_buckling_bifurcates_and_follows_the_elastica() {
    // Euler load of the cantilever column: P_cr = π² EI / (4 L²)
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    // the perfect column under 2 P_cr stays straight by symmetry, and the path passes the
    // bifurcation at P_cr: one unstable direction from there (buckling about the weak axis)
    let sol = arc(&column(2.0 * p_cr, 0.0), 40);
    let bif: Vec<(f64, [usize; 2])> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::Bifurcation {
                load_factor,
                unstable,
                ..
            } => Some((load_factor, unstable)),
            _ => None,
        })
        .collect();
    assert_eq!(bif.len(), 1, "{:?}", sol.events);
    assert_eq!(bif[0].1, [0, 1]);
    // the first step past P_cr: within one step (at most 1/40 of the load) above t = 1/2
    assert!(bif[0].0 > 0.5 && bif[0].0 < 0.5 + 0.03, "{}", bif[0].0);
    // with a small lateral load (1e-3 P_cr) the column bends smoothly into the elastica of the
    // cantilever: P/P_cr = (2 K(k)/π)² with k = sin(α/2), α the tip rotation (Timoshenko &
    // Gere §2.7), up to 3 P_cr (α about 2.6 rad)
    let model = column(3.0 * p_cr, 1e-3 * p_cr);
    let sol = arc(&model, 60);
    let r = model.nodes[model.node_id("n20").unwrap()].ix_rot.unwrap();
    let (mut far, mut alpha_max) = (0, 0.0f64);
    for st in &sol.steps {
        let l = &st.x[r..r + 4];
        let alpha = 2.0
            * (l[1] * l[1] + l[2] * l[2] + l[3] * l[3])
                .sqrt()
                .atan2(l[0].abs());
        if alpha < 0.3 {
            continue;
        }
        let want = (2.0 * common::elliptic_k((0.5 * alpha).sin()) / std::f64::consts::PI).powi(2);
        let got = 3.0 * st.load_factor;
        assert!(
            (got - want).abs() < 0.01 * want,
            "α = {alpha}: {got} vs {want}"
        );
        far += 1;
        alpha_max = alpha_max.max(alpha);
    }
    // at 3 P_cr: 2K(k)/π = √3, k = 0.96, α = 2.6 rad
    assert!(far > 10 && alpha_max > 2.5, "{far} {alpha_max}");
    assert_eq!(sol.steps.last().unwrap().load_factor, 1.0);
}

/// Load steps across the snap-through of the S05 toggle (40 lbf, 20 steps): the path jumps
/// from the near to the far branch in one step, which must be the step whose load interval
/// holds the limit load P_max = 33.870 lbf of validation.md (that is where the near branch
/// ends), and that step is reported as a jump; the same frame under a prescribed apex stroke
/// of 0.7 in (which follows the path continuously) reports none.
#[test]
fn load_steps_report_the_jump_across_the_snap_through() {
    let (p, p_max) = (40.0, 33.870);
    let opts = StaticOptions {
        steps: 20,
        ..Default::default()
    };
    let model = common::toggle_under_load(p);
    let sol = solve_path(&model, &opts, |_, _| {}).expect("load steps reach the full load");
    let jumps: Vec<_> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::Jump {
                step,
                from,
                load_factor,
                growth,
            } => Some((step, from, load_factor, growth)),
            _ => None,
        })
        .collect();
    assert_eq!(jumps.len(), 1, "{:?}", sol.events);
    let (step, from, to, growth) = jumps[0];
    assert!(
        from * p < p_max && p_max <= to * p,
        "jump at step {step} over ({}, {}] lbf, P_max {p_max}",
        from * p,
        to * p
    );
    assert!(growth > 5.0);
    // on the far branch at the end: past δ = 0.5 in (36.097 lbf < 40 lbf, validation.md)
    let iy = model.nodes[model.node_id("n20").unwrap()].ix_pos + 1;
    assert!(0.386 - sol.steps.last().unwrap().x[iy] > 0.5);

    let mut b = common::toggle_builder();
    b.prescribe_coordinate("n20", Dof::Y, -0.7).unwrap();
    let stroked = b.build().unwrap();
    let sol = solve_path(&stroked, &opts, |_, _| {}).expect("the stroke is followed");
    assert!(
        !sol.events
            .iter()
            .any(|e| matches!(e, PathEvent::Jump { .. })),
        "{:?}",
        sol.events
    );
}

/// The slope of the closed-form path: dP/dy = 2 EA (a²/L³ − 1/L0) (from P(y) above,
/// d(y/L)/dy = a²/L³).
fn slope_at(y: f64) -> f64 {
    let (l, l0) = ((A * A + y * y).sqrt(), (A * A + H * H).sqrt());
    2.0 * EA * (A * A / l.powi(3) - 1.0 / l0)
}

/// The smallest eigenvalue κ₁ of the truss's tangent stiffness at a step.
fn kappa1(st: &flexmbd_core::statics::StepResult) -> f64 {
    st.tangent_eigenvalues.as_ref().expect("κ reported")[0]
}

#[test]
fn the_smallest_tangent_eigenvalue_of_the_truss_is_its_load_slope() {
    // The apex has two free coordinates, x and y. By symmetry the tangent stiffness is
    // diagonal in them: K_yy = d(internal force)/dy = −dP/dy (the load acts along −y), and
    // K_xx = 2 (EA a²/(L0 L²) + N y²/L³) ≈ 2 EA/L0 ≫ |K_yy| (N the bar force), so κ₁ = −dP/dy
    // at every state, positive outside the limit points, negative between them; the scale
    // of κ₁ is its value at the start, 2 EA h²/L0³.
    let l0 = (A * A + H * H).sqrt();
    let scale = 2.0 * EA * H * H / l0.powi(3);
    let model = truss(None, None);
    let sol = arc_kappa(&model, 40);
    assert!(arc(&model, 40)
        .steps
        .iter()
        .all(|s| s.tangent_eigenvalues.is_none()));
    let y = heights(&model, &sol, "c");
    for (st, &y) in sol.steps.iter().zip(&y) {
        let k = kappa1(st);
        assert!(
            (k + slope_at(y)).abs() < 1e-6 * scale,
            "y = {y}: κ₁ = {k} vs {}",
            -slope_at(y)
        );
        assert_eq!(st.tangent_eigenvalues.as_ref().unwrap().len(), 2);
    }
    assert!((kappa1(&sol.steps[0]) - scale).abs() < 1e-9 * scale);
    // the same under load steps, to 0.9 of the limit load (asked for: off by default there)
    let p_max = load_at(limit_height());
    let mut steps = truss(None, None);
    steps.loads.nodal[0].force[1] = -0.9 * p_max;
    let opts = StaticOptions {
        steps: 9,
        ..Default::default()
    };
    let plain = solve_path(&steps, &opts, |_, _| {}).expect("below the limit load");
    assert!(plain
        .steps
        .iter()
        .all(|st| st.tangent_eigenvalues.is_none()));
    let opts = StaticOptions {
        tangent_eigenvalues: true,
        ..opts
    };
    let sol = solve_path(&steps, &opts, |_, _| {}).expect("below the limit load");
    let y = heights(&steps, &sol, "c");
    for (st, &y) in sol.steps.iter().zip(&y) {
        assert!((kappa1(st) + slope_at(y)).abs() < 1e-6 * scale, "y = {y}");
    }
    // it decreases towards the limit point (last step: 0.9 P_max, still stable)
    let k: Vec<f64> = sol.steps.iter().map(kappa1).collect();
    assert!(
        k.windows(2).all(|w| w[1] < w[0]) && k[k.len() - 1] > 0.0,
        "{k:?}"
    );
}

#[test]
fn both_limit_points_of_the_truss_are_located_with_ten_steps() {
    // the limit points at y = ±y*, L* = (a² L0)^⅓, where κ₁ = −dP/dy = 0: located inside
    // their steps to 1e-4 of y* (sampled steps: several % off with 20 steps)
    let model = truss(None, None);
    let sol = arc(&model, 10);
    let y = heights(&model, &sol, "c");
    let (ys, p_max) = (limit_height(), load_at(limit_height()));
    let limits: Vec<(usize, f64)> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::LimitPoint {
                step,
                load_factor,
                located: true,
            } => Some((step, load_factor)),
            _ => None,
        })
        .collect();
    assert_eq!(limits.len(), 2, "{:?}", sol.events);
    for ((k, t), sign) in limits.into_iter().zip([1.0, -1.0]) {
        assert!(
            (y[k] - sign * ys).abs() < 1e-4 * ys,
            "y = {} vs {}",
            y[k],
            sign * ys
        );
        assert!(
            (t * P - sign * p_max).abs() < 1e-6 * p_max,
            "{} vs {}",
            t * P,
            sign * p_max
        );
    }
}

#[test]
fn s05_limit_points_located_with_few_steps() {
    // validation.md S05: P_max = 33.870 lbf at δ = 0.2325 in, the minimum 31.282 lbf at
    // δ = 0.3925 in (loads ±0.5 %, deflections ±3 %): the located critical states themselves
    let model = common::toggle_under_load(40.0);
    let sol = arc(&model, 8);
    let iy = model.nodes[model.node_id("n20").unwrap()].ix_pos + 1;
    let limits: Vec<(f64, f64)> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::LimitPoint {
                step,
                load_factor,
                located: true,
            } => Some((0.386 - sol.steps[step].x[iy], 40.0 * load_factor)),
            _ => None,
        })
        .collect();
    assert_eq!(limits.len(), 2, "{:?}", sol.events);
    let [(d_max, p_max), (d_min, p_min)] = [limits[0], limits[1]];
    assert!((p_max - 33.870).abs() < 5e-3 * 33.870, "P_max {p_max}");
    assert!((d_max - 0.2325).abs() < 0.03 * 0.2325, "δ at P_max {d_max}");
    assert!((p_min - 31.282).abs() < 5e-3 * 31.282, "P_min {p_min}");
    assert!((d_min - 0.3925).abs() < 0.03 * 0.3925, "δ at P_min {d_min}");
}

#[test]
fn the_column_bifurcation_is_located_where_the_smallest_eigenvalue_vanishes() {
    // the perfect cantilever column under 2 P_cr, P_cr = π² EI/(4 L²): κ₁ > 0 below P_cr,
    // < 0 above it, and the bifurcation is located at P_cr (t = 1/2) within 1e-3 (the 20
    // elements' discretisation error of the buckling load is below that: S09 gives 1e-3 with
    // 8 elements)
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    let sol = arc_kappa(&column(2.0 * p_cr, 0.0), 10);
    let bif: Vec<(usize, f64)> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::Bifurcation {
                step,
                load_factor,
                unstable: [0, 1],
                located: true,
            } => Some((step, load_factor)),
            _ => None,
        })
        .collect();
    assert_eq!(bif.len(), 1, "{:?}", sol.events);
    let (k, t) = bif[0];
    assert!((2.0 * t - 1.0).abs() < 1e-3, "P/P_cr = {}", 2.0 * t);
    for st in &sol.steps {
        let kappa = kappa1(st);
        if st.load_factor < 0.5 * (1.0 - 2e-3) {
            assert!(kappa > 0.0, "t = {}: κ₁ = {kappa}", st.load_factor);
        } else if st.load_factor > 0.5 * (1.0 + 2e-3) {
            assert!(kappa < 0.0, "t = {}: κ₁ = {kappa}", st.load_factor);
        }
    }
    // at the located state κ₁ is zero to round-off of the stiffness at the start
    let k0 = kappa1(&sol.steps[0]);
    assert!(
        kappa1(&sol.steps[k]).abs() < 1e-6 * k0,
        "{}",
        kappa1(&sol.steps[k])
    );
}

#[test]
fn a_prescribed_end_rotation_by_arc_length() {
    // A clamped Euler–Bernoulli cantilever (L = 1 m, EI = 2 N·m², 10 elements) whose tip
    // rotation φ is prescribed to 3 rad: every state has constant curvature (a circle),
    // with the moment of the discrete closed form M = sin(φ/N) EI/l0 (the continuous limit is
    // M = EI φ/L), as under load steps (validation_statics.rs,
    // prescribed_tip_rotation_gives_the_end_moment).
    let (l, ei, n, phi) = (1.0, 2.0, 10, 3.0);
    let props = flexmbd_core::section::BeamProps {
        ea: 1e6,
        gj: 1.0,
        eiy: ei,
        eiz: ei,
        ..Default::default()
    };
    let mut b = common::cantilever(n, l, props);
    b.prescribe_coordinate(&format!("n{n}"), Dof::Rz, phi)
        .unwrap();
    let model = b.build().unwrap();
    let sol = arc(&model, 10);
    assert!(sol.steps.len() > 5);
    assert_eq!(sol.steps.last().unwrap().load_factor, 1.0);
    let r = model.nodes.last().unwrap().ix_rot.unwrap();
    let l0 = l / n as f64;
    for st in &sol.steps[1..] {
        let angle = st.load_factor * phi;
        let (_, _, rot) = common::tip(&model, &st.x);
        assert!((rot - angle).abs() < 1e-12, "{rot} vs {angle}");
        let want = (angle / n as f64).sin() * ei / l0;
        let lam = [st.x[r], st.x[r + 1], st.x[r + 2], st.x[r + 3]];
        let lb = flexmbd_core::math::lambda_bar(&lam);
        let f = [
            0.0,
            st.reactions[r + 1],
            st.reactions[r + 2],
            st.reactions[r + 3],
        ];
        let mz: f64 = 0.5 * (0..4).map(|c| lb[2][c] * f[c]).sum::<f64>();
        assert!(
            (mz - want).abs() < 1e-8 * want,
            "φ = {angle}: {mz} vs {want}"
        );
    }
}

#[test]
fn arc_length_outputs_every_crossing_of_the_requested_load_levels() {
    // With steps = 10 the path of the truss (P = 1000 N, P_max = P(y*) = 381 N) crosses the
    // levels t = 0.1 … 0.3 three times (up to the first limit point, down to the second, up to
    // the full load), t = 0 twice after the start, and t = 0.4 … 1 once: each crossing is an
    // output state at exactly that load factor. The closed form puts the states at zero load
    // at P(y) = 0: y = 0 (the flat, unstable position) and L = L0, y = −h (the mirrored
    // stable state).
    let model = truss(None, None);
    let sol = arc(&model, 10);
    let y = heights(&model, &sol, "c");
    let p_max = load_at(limit_height());
    assert!(p_max / P > 0.3 && p_max / P < 0.4, "{}", p_max / P);
    for k in 0..=10usize {
        let at: Vec<usize> = (0..sol.steps.len())
            .filter(|&i| sol.path[i].level == Some(k))
            .collect();
        let want = match k {
            0..=3 => 3,
            _ => 1,
        };
        assert_eq!(at.len(), want, "level {k}: steps {at:?}");
        for &i in &at {
            assert_eq!(sol.steps[i].load_factor, k as f64 / 10.0);
        }
        if k == 0 {
            let ys: Vec<f64> = at.iter().map(|&i| y[i]).collect();
            for (got, want) in ys.iter().zip([H, 0.0, -H]) {
                assert!((got - want).abs() < 1e-9 * H, "{ys:?}");
            }
        }
    }
    // and no other state is marked
    let marked = sol.path.iter().filter(|p| p.level.is_some()).count();
    assert_eq!(marked, 3 * 4 + 7);
}

#[test]
fn a_large_model_locates_its_bifurcation_on_the_inertia() {
    // 60 elements: 360 reduced coordinates, beyond the dense eigenvalues
    // (TANGENT_EIGEN_MAX = 300), so (not asked for) no κ is reported and the bifurcation of the perfect column
    // is located by bisection on the count of unstable directions: at P_cr = π² EI/(4 L²)
    // (t = 1/2 under 2 P_cr) within 1e-3
    const { assert!(6 * 60 > flexmbd_core::statics::TANGENT_EIGEN_MAX) };
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    let sol = arc(&column_of(60, 2.0 * p_cr, 0.0), 10);
    assert!(sol.steps.iter().all(|s| s.tangent_eigenvalues.is_none()));
    let bif: Vec<f64> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::Bifurcation {
                load_factor,
                unstable: [0, 1],
                located: true,
                ..
            } => Some(load_factor),
            _ => None,
        })
        .collect();
    assert_eq!(bif.len(), 1, "{:?}", sol.events);
    assert!(
        (2.0 * bif[0] - 1.0).abs() < 1e-3,
        "P/P_cr = {}",
        2.0 * bif[0]
    );
}

#[test]
fn a_large_model_reports_the_eigenvalues_nearest_zero_when_asked() {
    // the same 60-element column (360 reduced coordinates) with κ asked for: by Lanczos on
    // the inverse tangent (statics/eigen.rs), κ₁ at every state; it passes through zero at
    // the Euler load P_cr = π² EI/(4 L²) (t = 1/2 under 2 P_cr), where the count of unstable
    // directions turns to 1, and is positive before, negative after
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    let model = column_of(60, 2.0 * p_cr, 0.0);
    let opts = StaticOptions {
        steps: 10,
        path: PathMethod::ArcLength,
        tangent_eigenvalues: true,
        ..Default::default()
    };
    let sol = solve_path(&model, &opts, |_, _| {}).expect("the path reaches the full load");
    let k1: Vec<(f64, f64)> = sol
        .steps
        .iter()
        .map(|s| {
            (
                s.load_factor,
                s.tangent_eigenvalues.as_ref().expect("κ asked for")[0],
            )
        })
        .collect();
    for &(t, k) in &k1 {
        if (2.0 * t - 1.0).abs() > 1e-3 {
            assert_eq!(k < 0.0, 2.0 * t > 1.0, "t = {t}: κ₁ = {k}");
        }
    }
    // the zero crossing by linear interpolation between the steps around it: within 1 % of
    // the Euler load (κ₁ is not linear in the load: the steps are 0.2 P_cr apart)
    let w = k1
        .windows(2)
        .find(|w| w[0].1 > 0.0 && w[1].1 <= 0.0)
        .expect("κ₁ changes sign");
    let t0 = w[0].0 + (w[1].0 - w[0].0) * w[0].1 / (w[0].1 - w[1].1);
    assert!((2.0 * t0 - 1.0).abs() < 1e-2, "P/P_cr = {}", 2.0 * t0);
    // the located bifurcation itself has κ₁ ≈ 0 against κ₁ of the unloaded column
    let scale = k1[0].1;
    let located = sol.events.iter().find_map(|e| match *e {
        PathEvent::Bifurcation {
            step,
            located: true,
            ..
        } => Some(step),
        _ => None,
    });
    let step = located.expect("the bifurcation is located");
    let k = sol.steps[step]
        .tangent_eigenvalues
        .as_ref()
        .expect("κ at the critical state")[0];
    assert!(
        k.abs() < 1e-3 * scale,
        "κ₁ = {k} at the bifurcation, κ₁(0) = {scale}"
    );
}

#[test]
fn a_bifurcation_in_the_last_step_is_located() {
    // the perfect column under 1.05 P_cr with steps = 1: the first tangent step passes t = 1,
    // so the path is one step solved at the full load, and the bifurcation inside it is
    // located at P_cr = π² EI/(4 L²), t = 1/1.05, within 1e-3
    let p_cr = std::f64::consts::PI.powi(2) / 4.0;
    let sol = arc(&column(1.05 * p_cr, 0.0), 1);
    let bif: Vec<f64> = sol
        .events
        .iter()
        .filter_map(|e| match *e {
            PathEvent::Bifurcation {
                load_factor,
                located: true,
                ..
            } => Some(load_factor),
            _ => None,
        })
        .collect();
    assert_eq!(bif.len(), 1, "{:?}", sol.events);
    assert!(
        (1.05 * bif[0] - 1.0).abs() < 1e-3,
        "P/P_cr = {}",
        1.05 * bif[0]
    );
    assert_eq!(sol.steps.last().unwrap().load_factor, 1.0);
}
