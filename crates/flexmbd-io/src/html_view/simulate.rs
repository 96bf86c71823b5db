//! The time history of a simulation in the HTML viewer (`flexmbd view --analysis simulate`,
//! docs/visualisation.md): one frame per output time (node positions and rotations), the
//! stress fields of every frame as for load steps, the node speeds, and the energies for the
//! page's energy plot ([`ViewSimulation`]). The page plays the frames with
//! `assets/viewer/simulate.js`, appended to `viewer.js`.

use super::geometry::{frame, max_displacement};
use super::results::{field, significant, stress_fields, summary};
use super::{Classification, FieldPer, ViewData, ViewError, ViewField, ViewResults};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::simulation::{Simulation, Stopped};
use flexmbd_core::statics::StepResult;
use flexmbd_core::Model;
use serde::{Deserialize, Serialize};

/// The playback and energy plot of the page (`simulate.js`).
pub(super) const SIMULATE_JS: &str = include_str!("../../assets/viewer/simulate.js");

/// Most frames a page holds: a longer run shows every k-th output time (first and last
/// always).
pub const MAX_VIEW_FRAMES: usize = 1000;
/// Most frames × nodes a page holds (about 30 bytes of JSON each).
pub const MAX_VIEW_NODE_FRAMES: usize = 2_000_000;

/// The time history: one entry per frame of [`ViewData::frames`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSimulation {
    /// Time of every frame [s].
    pub times: Vec<f64>,
    /// Kinetic energy T [J].
    pub kinetic: Vec<f64>,
    /// Strain energy U [J].
    pub strain: Vec<f64>,
    /// Net work put in: external + prescribed − dissipated [J].
    pub work: Vec<f64>,
    /// Energy balance error (T + U) − (T₀ + U₀) − W [J].
    pub balance_error: Vec<f64>,
    /// The end time asked for [s] (a stopped run ends before it).
    pub t_end: f64,
    /// Every `stride`-th output time of the run is a frame.
    pub stride: usize,
    /// The node the page reports the position of (the one that moves most; for tests).
    pub tip: usize,
    /// Why the run stopped before `t_end`, if it did.
    pub stopped: Option<String>,
}

/// The output times a page shows: every `stride`-th, and the last.
fn shown_frames(frames: usize, nodes: usize) -> (Vec<usize>, usize) {
    let cap = MAX_VIEW_FRAMES
        .min(MAX_VIEW_NODE_FRAMES / nodes.max(1))
        .max(2);
    if frames <= cap {
        return ((0..frames).collect(), 1);
    }
    let stride = (frames - 1).div_ceil(cap - 1);
    let mut k: Vec<usize> = (0..frames).step_by(stride).collect();
    if k.last() != Some(&(frames - 1)) {
        k.push(frames - 1);
    }
    (k, stride)
}

/// A time [s] with 6 significant digits, without trailing zeros: `0.25`.
fn time_text(t: f64) -> String {
    let s = significant(t, 6);
    if s.contains('.') && !s.contains('e') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A time as a frame label: `t = 0.25 s`.
fn time_label(t: f64) -> String {
    format!("t = {} s", time_text(t))
}

/// Per frame and element: the largest speed of the element's nodes [m/s].
fn speed_field(model: &Model, sim: &Simulation, shown: &[usize]) -> ViewField {
    let values = shown
        .iter()
        .map(|&k| {
            let speed: Vec<f64> = sim.frames[k]
                .node_velocities(model)
                .iter()
                .map(|(v, _)| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
                .collect();
            model
                .elements
                .iter()
                .map(|e| {
                    let s = e
                        .element
                        .node_uses()
                        .iter()
                        .map(|u| speed[u.node])
                        .fold(0.0, f64::max);
                    s.is_finite().then_some(s as f32)
                })
                .collect()
        })
        .collect();
    let mut f = field(
        "speed",
        "largest node speed",
        "m/s",
        false,
        FieldPer::Frame,
        values,
    );
    f.range[0] = 0.0;
    f
}

/// The page's data for a simulation: the frames at the output times, the stress fields of
/// every frame and the node speeds, the energies, facts of the run, and the classification
/// when it was computed. `t_end` is the end time asked for; `stopped` how a run that did not
/// reach it ended (its frames are shown).
pub fn simulate_view_data(
    model: &Model,
    file: &str,
    classification: Option<&Classification<'_>>,
    sim: &Simulation,
    t_end: f64,
    stopped: Option<&Stopped>,
) -> ViewData {
    let mut data = super::view_data(model, file, None, &ViewResults::Check);
    data.analysis = "simulate".into();
    data.summary = classification.map(summary);
    let (shown, stride) = shown_frames(sim.frames.len(), model.nodes.len());
    let steps: Vec<StepResult> = shown.iter().map(|&k| sim.frames[k].as_step()).collect();
    data.frames = shown
        .iter()
        .zip(&steps)
        .map(|(&k, st)| frame(model, &time_label(sim.frames[k].t), None, &st.x))
        .collect();
    data.animations.clear();
    let refs: Vec<&StepResult> = steps.iter().collect();
    data.fields = stress_fields(model, &refs, FieldPer::Frame);
    data.fields.push(speed_field(model, sim, &shown));
    let energy = |f: fn(&flexmbd_core::simulation::Energies) -> f64| -> Vec<f64> {
        shown.iter().map(|&k| f(&sim.frames[k].energy)).collect()
    };
    // the node that moves most over the shown frames (the last of equals)
    let moved = |i: usize| {
        let n = &model.nodes[i];
        steps
            .iter()
            .map(|st| {
                (0..3)
                    .map(|d| (st.x[n.ix_pos + d] - n.x0[d]).powi(2))
                    .sum::<f64>()
            })
            .fold(0.0, f64::max)
    };
    let tip = (0..model.nodes.len())
        .max_by(|&a, &b| moved(a).total_cmp(&moved(b)))
        .unwrap_or(0);
    data.simulation = Some(ViewSimulation {
        times: shown.iter().map(|&k| sim.frames[k].t).collect(),
        kinetic: energy(|e| e.kinetic),
        strain: energy(|e| e.strain),
        work: energy(|e| e.external_work + e.prescribed_work - e.dissipated),
        balance_error: energy(|e| e.balance_error),
        t_end,
        stride,
        tip,
        stopped: stopped.map(|s| {
            format!(
                "The run stopped at t = {:.6e} s: {}; {}.",
                s.t, s.reason, s.hint
            )
        }),
    });
    let st = &sim.stats;
    let info = &mut data.info;
    if let (Some(first), Some(last)) = (sim.frames.first(), sim.frames.last()) {
        info.push((
            "time".into(),
            format!(
                "{} … {} s (asked: {} s)",
                time_text(first.t),
                time_text(last.t),
                time_text(t_end)
            ),
        ));
        info.push((
            "largest displacement".into(),
            format!(
                "{} m",
                crate::report::fmt_num(
                    steps
                        .iter()
                        .map(|s| max_displacement(model, s))
                        .fold(0.0, f64::max)
                )
            ),
        ));
    }
    info.push((
        "output times".into(),
        if stride > 1 {
            format!(
                "{} (every {stride}th of {} shown)",
                data.frames.len(),
                sim.frames.len()
            )
        } else {
            data.frames.len().to_string()
        },
    ));
    info.push((
        "steps".into(),
        format!(
            "{} accepted, {} rejected, {} Newton failures, {} Newton iterations",
            st.steps, st.rejected, st.newton_failures, st.newton_iterations
        ),
    ));
    info.push((
        "step size".into(),
        format!("{:.3e} … {:.3e} s", st.min_step, st.max_step),
    ));
    info.push((
        "largest constraint residual".into(),
        format!("{:.3e}", st.max_constraint_residual),
    ));
    info.push((
        "largest energy balance error".into(),
        format!("{:.3e} J", st.max_energy_error),
    ));
    if let Some(s) = stopped {
        data.notes.push(format!(
            "The simulation stopped at t = {:.6e} s: {}; {}. The frames up to then are shown.",
            s.t, s.reason, s.hint
        ));
    }
    data
}

/// The time history fits the frames and the nodes.
pub(super) fn check_simulation(d: &ViewData) -> Result<(), ViewError> {
    let Some(s) = &d.simulation else {
        return Ok(());
    };
    let n = d.frames.len();
    let lengths = [
        s.times.len(),
        s.kinetic.len(),
        s.strain.len(),
        s.work.len(),
        s.balance_error.len(),
    ];
    if n == 0 || lengths.iter().any(|&l| l != n) {
        return Err(ViewError::Data(format!(
            "the time history has {lengths:?} entries for {n} frames"
        )));
    }
    if s.tip >= d.nodes.len() {
        return Err(ViewError::Data(
            "the time history names a node that does not exist".into(),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::view_html;
    use super::*;

    const PENDULUM: &str = include_str!("../../../../examples/pendulum.toml");

    /// The pendulum released from rest, to t = 0.1 s with outputs every 0.01 s.
    fn pendulum_data() -> (Model, ViewData) {
        let f = crate::parse_model_file(PENDULUM, "pendulum.toml").expect("the example");
        let mut opts = f.simulate.options(Some(0.1)).expect("options");
        opts.output_step = 0.01;
        let sim = flexmbd_core::simulation::simulate(
            &f.model,
            &f.simulate.excitation,
            &opts,
            &mut |_| {},
        )
        .expect("a short run");
        let d = simulate_view_data(&f.model, "pendulum.toml", None, &sim, 0.1, None);
        (f.model, d)
    }

    #[test]
    fn pendulum_frames_times_and_energies() {
        let (m, d) = pendulum_data();
        assert_eq!(d.analysis, "simulate");
        assert_eq!(d.frames.len(), 11, "t = 0, 0.01, …, 0.1");
        let s = d.simulation.as_ref().expect("the time history");
        for (k, t) in s.times.iter().enumerate() {
            assert!((t - 0.01 * k as f64).abs() < 1e-12, "{k}: {t}");
        }
        assert_eq!(d.frames[3].label, "t = 0.03 s");
        assert!(d.frames.iter().all(|f| f.load_factor.is_none()));
        assert_eq!(d.nodes[s.tip].name, "tip");
        // frame 0 is the drawn geometry of the file; released from rest
        let tip0 = m.nodes[s.tip].x0;
        for i in 0..3 {
            assert_eq!(d.frames[0].x[3 * s.tip + i], tip0[i] as f32);
        }
        assert_eq!(s.kinetic[0], 0.0);
        assert!(s.kinetic[10] > 0.0 && s.work[10] > 0.0);
        // the tip falls: z decreases frame by frame
        let z: Vec<f32> = d.frames.iter().map(|f| f.x[3 * s.tip + 2]).collect();
        assert!(z.windows(2).all(|w| w[1] < w[0]), "{z:?}");
        let speed = d.fields.iter().find(|f| f.key == "speed").expect("speed");
        assert_eq!(speed.per, FieldPer::Frame);
        assert_eq!(speed.range[0], 0.0);
        assert!(d.animations.is_empty());
        assert!(d
            .info
            .iter()
            .any(|(k, v)| k == "time" && v.starts_with("0 … 0.1 s")));
    }

    #[test]
    fn the_page_carries_the_history_and_refuses_bad_data() {
        let (_, d) = pendulum_data();
        let html = view_html(&d).expect("page");
        assert!(html.contains("function simAdvance("));
        // the JSON round-trips, the time history included
        let open = r#"<script type="application/json" id="flexmbd-data">"#;
        let start = html.find(open).unwrap() + open.len();
        let end = start + html[start..].find("</script>").unwrap();
        let back: ViewData = serde_json::from_str(&html[start..end]).expect("JSON");
        assert_eq!(back, d);
        // a history that does not fit the frames or the nodes is refused
        let mut bad = d.clone();
        bad.simulation.as_mut().unwrap().kinetic.pop();
        assert!(matches!(view_html(&bad), Err(ViewError::Data(_))));
        let mut bad = d.clone();
        bad.simulation.as_mut().unwrap().tip = d.nodes.len();
        assert!(matches!(view_html(&bad), Err(ViewError::Data(_))));
        // other analyses have none, and their JSON has no `simulation` key
        let mut other = d;
        other.simulation = None;
        assert!(!serde_json::to_string(&other)
            .unwrap()
            .contains("\"simulation\""));
    }

    #[test]
    fn long_runs_show_every_kth_frame_with_the_last() {
        assert_eq!(shown_frames(5, 3), (vec![0, 1, 2, 3, 4], 1));
        let (k, stride) = shown_frames(4001, 3);
        assert_eq!(stride, 5);
        assert_eq!(k.len(), 801);
        assert_eq!(*k.last().unwrap(), 4000);
        let (k, stride) = shown_frames(2500, 3);
        assert!(k.len() <= MAX_VIEW_FRAMES, "{}", k.len());
        assert_eq!((k[1], *k.last().unwrap()), (stride, 2499));
        // many nodes: fewer frames
        let (k, _) = shown_frames(101, 100_000);
        assert!(k.len() * 100_000 <= MAX_VIEW_NODE_FRAMES || k.len() == 2);
        assert_eq!((k[0], *k.last().unwrap()), (0, 100));
    }

    #[test]
    fn time_labels() {
        assert_eq!(time_label(0.0), "t = 0 s");
        assert_eq!(time_label(0.25), "t = 0.25 s");
        assert_eq!(time_label(0.1 + 0.2), "t = 0.3 s");
        assert_eq!(time_label(2.0), "t = 2 s");
    }
}
