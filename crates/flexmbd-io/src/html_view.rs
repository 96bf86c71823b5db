//! The self-contained HTML 3D viewer (`flexmbd view`, docs/visualisation.md).
//!
//! [`view_data`] gathers what the page shows from the model and an analysis into a [`ViewData`]
//! document; [`view_html`] writes one HTML file with everything inlined: the data as JSON in a
//! `<script type="application/json">` block, the viewer (`assets/viewer/viewer.js`,
//! `viewer.css`) and the vendored three.js module build with its OrbitControls
//! (`assets/viewer/vendor/three/`, MIT licence, see `VENDORED.md` there). The page loads three.js
//! from Blob URLs made from the inlined sources, so it works from a `file://` URL with no
//! network.
//!
//! The geometry is computed in the page from the data: every beam is its cross-section swept
//! along the cubic Hermite curve through its end positions with the end tangents of the current
//! node rotations, so the picture follows the node states of a load step or an animated motion
//! or mode.

use crate::vtk::model_size;
use flexmbd_core::dynamics::Modal;
use flexmbd_core::elements::{Element, ElementKind};
use flexmbd_core::kinematics::advice::StateAdvice;
use flexmbd_core::kinematics::ConstraintAnalysis;
use flexmbd_core::model::{CoordKind, DefKind, Dof, Model, Partition};
use flexmbd_core::statics::{StaticSolution, StepResult};
use serde::{Deserialize, Serialize};

mod simulate;
pub use simulate::{simulate_view_data, ViewSimulation, MAX_VIEW_FRAMES, MAX_VIEW_NODE_FRAMES};

/// Version of the vendored three.js (`assets/viewer/vendor/three/VENDORED.md`).
pub const THREE_VERSION: &str = "0.170.0";

const TEMPLATE: &str = include_str!("../assets/viewer/template.html");
const VIEWER_JS: &str = include_str!("../assets/viewer/viewer.js");
const VIEWER_CSS: &str = include_str!("../assets/viewer/viewer.css");
const THREE_JS: &str = include_str!("../assets/viewer/vendor/three/three.module.min.js");
const ORBIT_JS: &str = include_str!("../assets/viewer/vendor/three/OrbitControls.js");
const THREE_LICENSE: &str = include_str!("../assets/viewer/vendor/three/LICENSE");

/// Smallest displayed thickness of a sheet, as a fraction of the model size: a 0.2 mm sheet in
/// a 300 mm guide would be invisible at its real thickness.
pub const MIN_THICKNESS: f64 = 0.004;
/// Smallest displayed diameter of a wire or beam, as a fraction of the model size.
pub const MIN_DIAMETER: f64 = 0.008;
/// Width of a sheet whose section is not given (only its partition or stiffness says it is a
/// sheet), as a fraction of the model size.
pub const NOMINAL_SHEET_WIDTH: f64 = 0.1;
/// Animations are scaled so that the largest nodal translation is this fraction of the model
/// size …
pub const ANIMATION_TRANSLATION: f64 = 0.1;
/// … or the largest nodal rotation is this angle [rad], whichever is reached first.
pub const ANIMATION_ROTATION: f64 = 0.35;

/// Errors of the HTML writer.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The data could not be written as JSON.
    #[error("cannot write the viewer data as JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// The data does not fit the model.
    #[error("viewer data: {0}")]
    Data(String),
}

/// Everything the page shows. Bulk arrays are `f32` (display precision), the numbers printed in
/// the panel are `f64`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewData {
    /// Format version of this document (1).
    pub format: u32,
    /// Program and version that wrote it.
    pub generator: String,
    /// Model name.
    pub title: String,
    /// Model file.
    pub file: String,
    /// `check`, `static`, `modes` or `simulate`.
    pub analysis: String,
    /// Model size: diagonal of the bounding box of the reference nodes [m].
    pub size: f64,
    /// Nodes in model order.
    pub nodes: Vec<ViewNode>,
    /// Elements in model order.
    pub elements: Vec<ViewElement>,
    /// Mode names per element type (`truss`, `beam`, `hinge`).
    pub mode_names: Vec<(String, Vec<String>)>,
    /// Configurations: the reference (check), every load step (static), or the static state
    /// the modes are linearised about (modes).
    pub frames: Vec<ViewFrame>,
    /// Motions (check) or modes (modes), animated about a frame.
    pub animations: Vec<ViewAnimation>,
    /// Element colourings.
    pub fields: Vec<ViewField>,
    /// Kinematic classification (Table 1, counts, advice), if it was computed.
    pub summary: Option<ViewSummary>,
    /// Labelled facts about the analysis for the panel.
    pub info: Vec<(String, String)>,
    /// Remarks (e.g. why the classification was skipped).
    pub notes: Vec<String>,
    /// The time history of a simulation (its frames are the output times).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<ViewSimulation>,
}

/// A node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewNode {
    /// Name.
    pub name: String,
    /// Host node of a node placed `at` another (same position).
    pub host: Option<usize>,
    /// Whether the node carries a rotation.
    pub rot: bool,
    /// Its fixed (support) degrees of freedom (`x` … `rz`).
    pub fixed: Vec<String>,
    /// Its degrees of freedom that are generalised coordinates (inputs).
    pub input: Vec<String>,
}

/// Element types as the page knows them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ViewKind {
    /// Truss.
    Truss,
    /// Beam.
    Beam,
    /// Hinge.
    Hinge,
    /// Rigid body.
    Rigid,
}

/// An element.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewElement {
    /// Name.
    pub name: String,
    /// Type.
    pub kind: ViewKind,
    /// Nodes (a rigid body: reference node first).
    pub nodes: Vec<usize>,
    /// Reference triad (rows): beam [ex, ey, ez], hinge [axis, b, c].
    pub frame: Option<[[f64; 3]; 3]>,
    /// Drawn cross-section of a beam.
    pub section: Option<ViewSection>,
    /// Partition of its deformations, one letter per mode: `r` rigid (fixed), `f` free,
    /// `i` input (generalised coordinate).
    pub partition: String,
}

/// Cross-section shapes the page draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SectionShape {
    /// Rectangle: width along local y, thickness along local z (a sheet when thin).
    Rectangle,
    /// Solid circle (a wire).
    Round,
    /// Circular tube.
    Tube,
}

/// The drawn section of a beam.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSection {
    /// Shape.
    pub shape: SectionShape,
    /// Drawn extent along local y [m] (diameter for round sections).
    pub width: f64,
    /// Drawn extent along local z [m].
    pub thickness: f64,
    /// The section's real width and thickness (outer and inner diameter of a tube) [m];
    /// `None` when the model gives no section and the shape was inferred.
    pub actual: Option<[f64; 2]>,
    /// Where the shape comes from: `section`, `stiffness` (ratio of the bending stiffnesses)
    /// or `partition` (which deformations are rigid).
    pub source: String,
}

/// A configuration: positions and rotations of all nodes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewFrame {
    /// Label, e.g. `step 3`.
    pub label: String,
    /// Load factor of a load step.
    pub load_factor: Option<f64>,
    /// Positions, 3 per node [m].
    pub x: Vec<f32>,
    /// Euler parameters λ0…λ3, 4 per node (identity for nodes without rotation).
    pub q: Vec<f32>,
}

/// An animated motion or mode: node states x + s·u and R(s·w)·R, s = a sin 2πt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewAnimation {
    /// `motion` or `mode`.
    pub kind: String,
    /// Label, e.g. `motion 1`.
    pub label: String,
    /// What the selector shows next to the label, e.g. `s = 0 (structural)` or `8.21 Hz`.
    pub detail: String,
    /// Singular value (motion) or frequency [Hz] (mode).
    pub value: Option<f64>,
    /// Index of the frame it is animated about.
    pub frame: usize,
    /// Scale of u and w for the default amplitude.
    pub scale: f64,
    /// Nodal translations, 3 per node.
    pub u: Vec<f32>,
    /// Nodal rotation vectors (global axes), 3 per node.
    pub w: Vec<f32>,
}

/// What a field's value sets are indexed by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FieldPer {
    /// One set for the model.
    Model,
    /// One set per frame.
    Frame,
    /// One set per animation.
    Animation,
}

/// A scalar per element for colouring.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewField {
    /// Stable key (URL parameter `color=`).
    pub key: String,
    /// Label.
    pub label: String,
    /// Unit.
    pub unit: String,
    /// Signed quantity: diverging colour map symmetric about zero.
    pub diverging: bool,
    /// What the value sets are indexed by.
    pub per: FieldPer,
    /// Value sets, each with one value per element (`None`: not defined for that element).
    pub values: Vec<Vec<Option<f32>>>,
    /// Colour range over all sets.
    pub range: [f64; 2],
}

/// The kinematic classification for the panel.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewSummary {
    /// Rows m of Dcc.
    pub rows: usize,
    /// Columns n of Dcc.
    pub cols: usize,
    /// Numerical rank r.
    pub rank: usize,
    /// Row of the paper's Table 1.
    pub table1_row: usize,
    /// Its description.
    pub classification: String,
    /// Kinematically indeterminate motions n − r.
    pub n_motions: usize,
    /// Self-stress states m − r.
    pub n_self_stresses: usize,
    /// No motion and no self-stress.
    pub exactly_constrained: bool,
    /// Relative rank tolerance.
    pub rank_tol: f64,
    /// Absolute rank threshold.
    pub rank_threshold: f64,
    /// s_r / s_(r+1).
    pub rank_gap: Option<f64>,
    /// Singular values, descending.
    pub singular_values: Vec<f64>,
    /// Generalised coordinates.
    pub generalised: Vec<String>,
    /// The self-stress states, each as its largest entries (`element mode (name) value`).
    pub self_stresses: Vec<Vec<String>>,
    /// Verified repair advice.
    pub advice: Vec<ViewAdvice>,
}

/// Advice for one motion or self-stress state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ViewAdvice {
    /// `motion` or `self_stress`.
    pub kind: String,
    /// The state (0-based).
    pub state: usize,
    /// Verified suggestions, each with the counts after the change.
    pub suggestions: Vec<String>,
}

/// The kinematic analysis to summarise.
pub struct Classification<'a> {
    /// The analysis.
    pub analysis: &'a ConstraintAnalysis,
    /// Its verified advice.
    pub advice: &'a [StateAdvice],
    /// Names of the generalised coordinates.
    pub generalised: &'a [String],
    /// The relative rank tolerance used.
    pub rank_tol: f64,
}

/// The results to show.
pub enum ViewResults<'a> {
    /// The reference geometry with the motions and self-stresses of the classification.
    Check,
    /// Every load step of a static run.
    Static(&'a StaticSolution),
    /// Modes about a static state.
    Modes {
        /// The state linearised about.
        step: &'a StepResult,
        /// Its index in the static solution.
        index: usize,
        /// The modes.
        modal: &'a Modal,
    },
}

/// Most entries of a self-stress state listed in the panel.
const MAX_STATE_ENTRIES: usize = 12;

/// Gather the page's data.
pub fn view_data(
    model: &Model,
    file: &str,
    classification: Option<&Classification<'_>>,
    results: &ViewResults<'_>,
) -> ViewData {
    let size = model_size(model);
    let partition = &model.partition;
    let mut data = ViewData {
        format: 1,
        generator: format!("flexmbd {}", env!("CARGO_PKG_VERSION")),
        title: model.name.clone(),
        file: file.to_string(),
        analysis: match results {
            ViewResults::Check => "check",
            ViewResults::Static(_) => "static",
            ViewResults::Modes { .. } => "modes",
        }
        .to_string(),
        size,
        nodes: view_nodes(model, partition),
        elements: model
            .elements
            .iter()
            .enumerate()
            .map(|(k, _)| view_element(model, partition, k, size))
            .collect(),
        mode_names: mode_names(model),
        frames: Vec::new(),
        animations: Vec::new(),
        fields: Vec::new(),
        summary: classification.map(summary),
        info: Vec::new(),
        notes: Vec::new(),
        simulation: None,
    };
    match results {
        ViewResults::Check => {
            data.frames
                .push(frame(model, "reference", None, &model.x0()));
            if let Some(c) = classification {
                data.animations = motion_animations(model, c.analysis, size);
                data.fields = self_stress_fields(model, c.analysis);
            }
        }
        ViewResults::Static(sol) => {
            for (k, st) in sol.steps.iter().enumerate() {
                data.frames.push(frame(
                    model,
                    &format!("step {k}"),
                    Some(st.load_factor),
                    &st.x,
                ));
            }
            let steps: Vec<&StepResult> = sol.steps.iter().collect();
            data.fields = stress_fields(model, &steps, FieldPer::Frame);
            let last = sol.steps.last();
            data.info.push((
                "load steps".into(),
                format!(
                    "{} (step 0 is the unloaded state)",
                    sol.steps.len().saturating_sub(1)
                ),
            ));
            if let Some(st) = last {
                data.info
                    .push(("final load factor".into(), format!("{:.4}", st.load_factor)));
                data.info.push((
                    "final elastic energy".into(),
                    format!("{} J", crate::report::fmt_num(st.energy)),
                ));
                data.info.push((
                    "largest displacement".into(),
                    format!("{} m", crate::report::fmt_num(max_displacement(model, st))),
                ));
            }
        }
        ViewResults::Modes { step, index, modal } => {
            data.frames.push(frame(
                model,
                &format!("static step {index}"),
                Some(step.load_factor),
                &step.x,
            ));
            data.animations = mode_animations(model, modal, size);
            data.fields = vec![strain_energy_field(model, modal)];
            if step.sigma.iter().any(|s| *s != 0.0) {
                data.fields.extend(
                    stress_fields(model, &[step], FieldPer::Model)
                        .into_iter()
                        .map(|mut f| {
                            f.label = format!("pre-stress: {}", f.label);
                            f
                        }),
                );
            }
            data.info.push((
                "linearised at".into(),
                format!("step {index}, load factor {:.4}", step.load_factor),
            ));
            data.info
                .push(("degrees of freedom".into(), modal.ndof.to_string()));
            if modal.massless > 0 {
                data.info.push((
                    "massless directions".into(),
                    format!("{} (condensed out statically)", modal.massless),
                ));
            }
        }
    }
    data
}

/// The page: one self-contained HTML document.
pub fn view_html(data: &ViewData) -> Result<String, ViewError> {
    check_data(data)?;
    simulate::check_simulation(data)?;
    let json = script_json(&serde_json::to_string(data)?);
    let title = if data.title.is_empty() {
        data.file.clone()
    } else {
        data.title.clone()
    };
    Ok(fill(
        TEMPLATE,
        &[
            ("TITLE", html_escape(&title)),
            ("CSS", style_text(VIEWER_CSS)),
            ("DATA", json),
            ("THREE", script_text(THREE_JS)),
            ("ORBIT", script_text(ORBIT_JS)),
            (
                "VIEWER",
                script_text(&format!("{VIEWER_JS}\n{}", simulate::SIMULATE_JS)),
            ),
            ("THREE_VERSION", html_escape(THREE_VERSION)),
            ("THREE_LICENSE", html_escape(THREE_LICENSE)),
        ],
    ))
}

/// Array lengths of the data against its node and element counts (the page indexes them).
fn check_data(d: &ViewData) -> Result<(), ViewError> {
    let (n, ne) = (d.nodes.len(), d.elements.len());
    let bad = |what: String| Err(ViewError::Data(what));
    for (k, f) in d.frames.iter().enumerate() {
        if f.x.len() != 3 * n || f.q.len() != 4 * n {
            return bad(format!(
                "frame {k} has {} positions for {n} nodes",
                f.x.len()
            ));
        }
    }
    for (k, a) in d.animations.iter().enumerate() {
        if a.u.len() != 3 * n || a.w.len() != 3 * n || a.frame >= d.frames.len() {
            return bad(format!("animation {k} does not fit the model"));
        }
    }
    for f in &d.fields {
        let sets = match f.per {
            FieldPer::Model => 1,
            FieldPer::Frame => d.frames.len(),
            FieldPer::Animation => d.animations.len(),
        };
        if f.values.len() != sets || f.values.iter().any(|v| v.len() != ne) {
            return bad(format!("field {} does not fit the model", f.key));
        }
    }
    for (k, e) in d.elements.iter().enumerate() {
        if e.nodes.iter().any(|&i| i >= n) {
            return bad(format!("element {k} names a node that does not exist"));
        }
    }
    Ok(())
}

/// Replace every `{{NAME}}` of the template in one pass (an inserted text is never scanned
/// again, so data that happens to contain `{{…}}` stays as it is).
fn fill(template: &str, values: &[(&str, String)]) -> String {
    let mut out =
        String::with_capacity(template.len() + values.iter().map(|v| v.1.len()).sum::<usize>());
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after.find("}}").and_then(|end| {
            let name = &after[..end];
            values
                .iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| (v, end))
        }) {
            Some((v, end)) => {
                out.push_str(v);
                rest = &after[end + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// JSON inside a `<script>` element: `<`, `>` and `&` as `\u` escapes (valid JSON, and the
/// HTML parser can never see `</script>` or `<!--` in it).
pub fn script_json(json: &str) -> String {
    let mut s = String::with_capacity(json.len());
    for c in json.chars() {
        match c {
            '<' => s.push_str("\\u003c"),
            '>' => s.push_str("\\u003e"),
            '&' => s.push_str("\\u0026"),
            '\u{2028}' => s.push_str("\\u2028"),
            '\u{2029}' => s.push_str("\\u2029"),
            c => s.push(c),
        }
    }
    s
}

/// JavaScript source inside a `<script>` element: `</script` (any case) becomes `<\/script`,
/// which means the same in a JavaScript string, template or regular expression.
pub fn script_text(js: &str) -> String {
    let lower = js.to_ascii_lowercase();
    let mut out = String::with_capacity(js.len());
    let mut last = 0;
    for (i, _) in lower.match_indices("</script") {
        out.push_str(&js[last..i]);
        out.push_str("<\\/");
        last = i + 2;
    }
    out.push_str(&js[last..]);
    out
}

/// CSS inside a `<style>` element (no `</style` in it).
fn style_text(css: &str) -> String {
    css.replace("</", "<\\/")
}

/// Text for HTML element content.
pub fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn view_nodes(model: &Model, p: &Partition) -> Vec<ViewNode> {
    model
        .nodes
        .iter()
        .map(|n| {
            let mut fixed = Vec::new();
            let mut input = Vec::new();
            for d in Dof::ALL {
                // a hosted node's translations are its host's
                if n.host.is_some() && !d.is_rotation() {
                    continue;
                }
                if let Some(i) = n.x_index(d) {
                    match p.x[i] {
                        CoordKind::Fixed => fixed.push(d.name().to_string()),
                        CoordKind::Input => input.push(d.name().to_string()),
                        CoordKind::Free => {}
                    }
                }
            }
            ViewNode {
                name: n.name.clone(),
                host: n.host,
                rot: n.rot(),
                fixed,
                input,
            }
        })
        .collect()
}

fn mode_names(model: &Model) -> Vec<(String, Vec<String>)> {
    let names = model.node_names();
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for e in &model.elements {
        let t = e.element.type_name();
        if t == "rigid" || out.iter().any(|(k, _)| k == t) {
            continue;
        }
        out.push((
            t.to_string(),
            (0..e.element.ne())
                .map(|m| e.element.mode_name(m, &names))
                .collect(),
        ));
    }
    out
}

fn view_element(model: &Model, p: &Partition, k: usize, size: f64) -> ViewElement {
    let entry = &model.elements[k];
    let ne = entry.element.ne();
    let partition: String = (0..ne)
        .map(|m| match p.e[entry.ie + m] {
            DefKind::Fixed => 'r',
            DefKind::Free => 'f',
            DefKind::Input => 'i',
        })
        .collect();
    let (kind, nodes, frame, section) = match &entry.element {
        Element::Truss(t) => (ViewKind::Truss, t.nodes.to_vec(), None, None),
        Element::Beam(b) => (
            ViewKind::Beam,
            b.nodes.to_vec(),
            Some(b.frame),
            Some(beam_section(b, &partition, size)),
        ),
        Element::Hinge(h) => (ViewKind::Hinge, h.nodes.to_vec(), Some(h.frame), None),
        Element::Rigid(r) => (ViewKind::Rigid, r.nodes.clone(), None, None),
    };
    ViewElement {
        name: entry.name.clone(),
        kind,
        nodes,
        frame,
        section,
        partition,
    }
}

/// The drawn section of a beam: from its section data when the model gives one (rectangle,
/// circle or tube recognised from the area and the fibre distances), else inferred from the
/// ratio of its bending stiffnesses or from its partition (in-plane bending rigid and
/// out-of-plane bending free: a sheet). Dimensions below [`MIN_THICKNESS`] / [`MIN_DIAMETER`]
/// of the model size are drawn at that minimum.
pub fn beam_section(b: &flexmbd_core::elements::Beam, partition: &str, size: f64) -> ViewSection {
    use std::f64::consts::PI;
    let min_t = MIN_THICKNESS * size;
    let min_d = MIN_DIAMETER * size;
    let rect = |w: f64, t: f64, actual: Option<[f64; 2]>, source: &str| ViewSection {
        shape: SectionShape::Rectangle,
        width: w.max(min_t),
        thickness: t.max(min_t),
        actual,
        source: source.into(),
    };
    let round = |d: f64, inner: Option<f64>, actual: Option<[f64; 2]>, source: &str| ViewSection {
        shape: if inner.is_some() {
            SectionShape::Tube
        } else {
            SectionShape::Round
        },
        width: d.max(min_d),
        thickness: d.max(min_d),
        actual,
        source: source.into(),
    };
    if let Some(p) = b
        .props
        .filter(|p| p.area > 0.0 && p.fibre.iter().all(|f| *f > 0.0))
    {
        let (cz, cy) = (p.fibre[0], p.fibre[1]);
        let a = p.area;
        if (a - 4.0 * cz * cy).abs() <= 1e-6 * a {
            return rect(2.0 * cy, 2.0 * cz, Some([2.0 * cy, 2.0 * cz]), "section");
        }
        if (cz - cy).abs() <= 1e-9 * cz.max(cy) {
            let d = 2.0 * cz;
            let solid = PI * cz * cz;
            if (a - solid).abs() <= 1e-6 * a {
                return round(d, None, Some([d, 0.0]), "section");
            }
            if a < solid {
                let d_in = (d * d - 4.0 * a / PI).max(0.0).sqrt();
                return round(d, Some(d_in), Some([d, d_in]), "section");
            }
        }
        // another shape: its bounding rectangle
        return rect(2.0 * cy, 2.0 * cz, Some([2.0 * cy, 2.0 * cz]), "section");
    }
    let sheet_w = NOMINAL_SHEET_WIDTH * size;
    let [_, _, eiy, eiz] = b.stiffness;
    if eiy > 0.0 && eiz > 0.0 {
        // a rectangle has EIz/EIy = (w/t)²
        let ratio = eiz / eiy;
        if ratio > 4.0 {
            return rect(sheet_w, sheet_w / ratio.sqrt(), None, "stiffness");
        }
        if ratio < 0.25 {
            return rect(sheet_w * ratio.sqrt(), sheet_w, None, "stiffness");
        }
        return round(min_d, None, None, "stiffness");
    }
    let m: Vec<char> = partition.chars().collect();
    if m.len() == 6 {
        let rigid = |i: usize| m[i] == 'r';
        // ε3, ε4 bend about local y (deflection along z), ε5, ε6 about local z
        if rigid(4) && rigid(5) && !(rigid(2) && rigid(3)) {
            return rect(sheet_w, min_t, None, "partition");
        }
        if rigid(2) && rigid(3) && !(rigid(4) && rigid(5)) {
            return rect(min_t, sheet_w, None, "partition");
        }
    }
    round(min_d, None, None, "partition")
}

fn frame(model: &Model, label: &str, load_factor: Option<f64>, x: &[f64]) -> ViewFrame {
    let mut pos = Vec::with_capacity(3 * model.nodes.len());
    let mut q = Vec::with_capacity(4 * model.nodes.len());
    for n in &model.nodes {
        pos.extend((0..3).map(|i| x[n.ix_pos + i] as f32));
        let l = match n.ix_rot {
            Some(r) => {
                let l = [x[r], x[r + 1], x[r + 2], x[r + 3]];
                let s = l.iter().map(|a| a * a).sum::<f64>().sqrt();
                if s > 0.0 && s.is_finite() {
                    l.map(|a| a / s)
                } else {
                    [1.0, 0.0, 0.0, 0.0]
                }
            }
            None => [1.0, 0.0, 0.0, 0.0],
        };
        q.extend(l.iter().map(|&a| a as f32));
    }
    ViewFrame {
        label: label.to_string(),
        load_factor,
        x: pos,
        q,
    }
}

fn max_displacement(model: &Model, st: &StepResult) -> f64 {
    model
        .nodes
        .iter()
        .map(|n| {
            (0..3)
                .map(|i| (st.x[n.ix_pos + i] - n.x0[i]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max)
}

/// Scale of an animation: the largest translation becomes [`ANIMATION_TRANSLATION`] × size or
/// the largest rotation [`ANIMATION_ROTATION`], whichever comes first (1 for a zero shape).
pub fn animation_scale(u: &[[f64; 3]], w: &[[f64; 3]], size: f64) -> f64 {
    let max = |v: &[[f64; 3]]| {
        v.iter()
            .map(|a| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt())
            .filter(|a| a.is_finite())
            .fold(0.0, f64::max)
    };
    let (mu, mw) = (max(u), max(w));
    let mut s = f64::INFINITY;
    if mu > 0.0 {
        s = s.min(ANIMATION_TRANSLATION * size / mu);
    }
    if mw > 0.0 {
        s = s.min(ANIMATION_ROTATION / mw);
    }
    if s.is_finite() {
        s
    } else {
        1.0
    }
}

fn finite_or_zero(v: f64) -> f32 {
    if v.is_finite() {
        v as f32
    } else {
        0.0
    }
}

fn flat(v: &[[f64; 3]]) -> Vec<f32> {
    v.iter().flat_map(|a| a.map(finite_or_zero)).collect()
}

/// `v` with `digits` significant digits (fixed notation from 1e-3 to 1e5).
pub fn significant(v: f64, digits: usize) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e5).contains(&a) {
        let decimals = (digits as i32 - 1 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.*e}", digits.saturating_sub(1))
    }
}

/// A singular value that belongs to null vector `k` beyond the rank, with its text.
fn null_singular_value(a: &ConstraintAnalysis, k: usize) -> (Option<f64>, String) {
    match a.singular_values.get(a.rank + k) {
        Some(&s) => (Some(s), format!("s = {s:.3e}")),
        None => (Some(0.0), "s = 0 (Dcc has fewer rows than columns)".into()),
    }
}

fn motion_animations(model: &Model, a: &ConstraintAnalysis, size: f64) -> Vec<ViewAnimation> {
    let n = model.nodes.len();
    a.motions
        .iter()
        .enumerate()
        .map(|(k, motion)| {
            let mut u = vec![[0.0; 3]; n];
            let mut w = vec![[0.0; 3]; n];
            for c in &motion.coordinates {
                if let Some(id) = model.node_id(&c.node) {
                    let i = c.dof.index();
                    if i < 3 {
                        u[id][i] = c.value;
                    } else {
                        w[id][i - 3] = c.value;
                    }
                }
            }
            for (i, node) in model.nodes.iter().enumerate() {
                if let Some(h) = node.host {
                    u[i] = u[h];
                }
            }
            let (value, detail) = null_singular_value(a, k);
            ViewAnimation {
                kind: "motion".into(),
                label: format!("motion {}", k + 1),
                detail,
                value,
                frame: 0,
                scale: animation_scale(&u, &w, size),
                u: flat(&u),
                w: flat(&w),
            }
        })
        .collect()
}

fn mode_animations(model: &Model, modal: &Modal, size: f64) -> Vec<ViewAnimation> {
    let n = model.nodes.len();
    modal
        .modes
        .iter()
        .enumerate()
        .map(|(k, mode)| {
            let (u, w): (Vec<[f64; 3]>, Vec<[f64; 3]>) = (0..n)
                .map(|i| mode.nodal.get(i).copied().unwrap_or(([0.0; 3], [0.0; 3])))
                .unzip();
            let f = mode.frequency;
            let (value, detail) = if f.is_finite() {
                (Some(f), format!("{} Hz", significant(f, 4)))
            } else {
                (None, format!("unstable (ω² = {:.3e})", mode.eigenvalue))
            };
            ViewAnimation {
                kind: "mode".into(),
                label: format!("mode {}", k + 1),
                detail,
                value,
                frame: 0,
                scale: animation_scale(&u, &w, size),
                u: flat(&u),
                w: flat(&w),
            }
        })
        .collect()
}

fn range(values: &[Vec<Option<f32>>], diverging: bool) -> [f64; 2] {
    let all = values.iter().flatten().flatten().map(|&v| v as f64);
    if diverging {
        let m = all.map(f64::abs).fold(0.0, f64::max);
        if m > 0.0 {
            [-m, m]
        } else {
            [-1.0, 1.0]
        }
    } else {
        let (lo, hi) = all.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        if !(lo.is_finite() && hi.is_finite()) {
            [0.0, 1.0]
        } else if hi > lo {
            [lo, hi]
        } else {
            [lo, lo + hi.abs().max(1.0)]
        }
    }
}

fn field(
    key: &str,
    label: &str,
    unit: &str,
    diverging: bool,
    per: FieldPer,
    values: Vec<Vec<Option<f32>>>,
) -> ViewField {
    let range = range(&values, diverging);
    ViewField {
        key: key.into(),
        label: label.into(),
        unit: unit.into(),
        diverging,
        per,
        values,
        range,
    }
}

/// Per self-stress state: the signed entry of largest magnitude of every element (0 for an
/// element that carries none of it; rigid bodies included).
fn self_stress_fields(model: &Model, a: &ConstraintAnalysis) -> Vec<ViewField> {
    a.self_stresses
        .iter()
        .enumerate()
        .map(|(k, state)| {
            let mut v = vec![0.0f64; model.elements.len()];
            for d in &state.deformations {
                if let Some(i) = model.elements.iter().position(|e| e.name == d.element) {
                    if d.value.abs() > v[i].abs() {
                        v[i] = d.value;
                    }
                }
            }
            field(
                &format!("self_stress_{}", k + 1),
                &format!("self-stress state {}", k + 1),
                "unit state",
                true,
                FieldPer::Model,
                vec![v.iter().map(|&x| Some(x as f32)).collect()],
            )
        })
        .collect()
}

/// Stress resultants per step: σ1 of trusses and beams, σ2…σ6 of beams, the hinge moment
/// and the largest normal stress of beams with a section. Fields that are zero everywhere are
/// left out.
fn stress_fields(model: &Model, steps: &[&StepResult], per: FieldPer) -> Vec<ViewField> {
    let defs: [(&str, &str, &str, bool); 8] = [
        ("max_stress", "largest normal stress", "Pa", false),
        ("sigma1", "σ1 axial force", "N", true),
        ("sigma2", "σ2 torsion (torque / l0)", "N", true),
        ("sigma3", "σ3 bending about y at p (moment / l0)", "N", true),
        ("sigma4", "σ4 bending about y at q (moment / l0)", "N", true),
        ("sigma5", "σ5 bending about z at p (moment / l0)", "N", true),
        ("sigma6", "σ6 bending about z at q (moment / l0)", "N", true),
        ("hinge_moment", "hinge moment σ1", "N·m", true),
    ];
    let els_per_step: Vec<_> = steps
        .iter()
        .map(|s| crate::static_report::element_results(model, s))
        .collect();
    let mut out = Vec::new();
    for (key, label, unit, diverging) in defs {
        let values: Vec<Vec<Option<f32>>> = els_per_step
            .iter()
            .map(|els| {
                model
                    .elements
                    .iter()
                    .zip(els)
                    .map(|(entry, r)| {
                        let v = match (&entry.element, key) {
                            (Element::Beam(_), "max_stress") => r.max_stress,
                            (Element::Truss(_) | Element::Beam(_), "sigma1") => {
                                r.sigma.first().copied()
                            }
                            (Element::Beam(_), k) if k.starts_with("sigma") => k[5..]
                                .parse::<usize>()
                                .ok()
                                .and_then(|i| r.sigma.get(i - 1).copied()),
                            (Element::Hinge(_), "hinge_moment") => r.sigma.first().copied(),
                            _ => None,
                        };
                        v.filter(|v| v.is_finite()).map(|v| v as f32)
                    })
                    .collect()
            })
            .collect();
        if values.iter().flatten().flatten().any(|v| *v != 0.0) {
            out.push(field(key, label, unit, diverging, per, values));
        }
    }
    out
}

/// Per mode: the share of every element in the mode's strain energy [%].
fn strain_energy_field(model: &Model, modal: &Modal) -> ViewField {
    let values = modal
        .modes
        .iter()
        .map(|mode| {
            let mut v: Vec<Option<f32>> = model
                .elements
                .iter()
                .map(|e| (!matches!(e.element, Element::Rigid(_))).then_some(0.0))
                .collect();
            for &(el, _, f) in &mode.strain {
                if let Some(Some(x)) = v.get_mut(el) {
                    *x += (100.0 * f) as f32;
                }
            }
            v
        })
        .collect();
    let mut f = field(
        "strain_energy",
        "share of the mode's strain energy",
        "%",
        false,
        FieldPer::Animation,
        values,
    );
    f.range = [0.0, f.range[1].max(1e-3)];
    f
}

fn summary(c: &Classification<'_>) -> ViewSummary {
    let a = c.analysis;
    ViewSummary {
        rows: a.m(),
        cols: a.n(),
        rank: a.rank,
        table1_row: a.case.row(),
        classification: a.case.describe().to_string(),
        n_motions: a.n_motions(),
        n_self_stresses: a.n_self_stresses(),
        exactly_constrained: a.n_motions() == 0 && a.n_self_stresses() == 0,
        rank_tol: c.rank_tol,
        rank_threshold: a.tol,
        rank_gap: a.rank_gap().filter(|g| g.is_finite()),
        singular_values: a.singular_values.clone(),
        generalised: c.generalised.to_vec(),
        self_stresses: a
            .self_stresses
            .iter()
            .map(|s| {
                let mut d: Vec<_> = s.deformations.iter().collect();
                d.sort_by(|x, y| y.value.abs().total_cmp(&x.value.abs()));
                let mut lines: Vec<String> = d
                    .iter()
                    .take(MAX_STATE_ENTRIES)
                    .map(|d| {
                        format!(
                            "{} mode {} ({}) {:+.4}",
                            d.element, d.mode, d.mode_name, d.value
                        )
                    })
                    .collect();
                if d.len() > MAX_STATE_ENTRIES {
                    lines.push(format!("… {} more", d.len() - MAX_STATE_ENTRIES));
                }
                lines
            })
            .collect(),
        advice: c
            .advice
            .iter()
            .map(|s| ViewAdvice {
                kind: s.kind.to_string(),
                state: s.state,
                suggestions: s
                    .suggestions
                    .iter()
                    .map(|g| {
                        format!(
                            "{} → {} motion(s), {} self-stress(es)",
                            g.action.describe(),
                            g.motions_after,
                            g.self_stresses_after
                        )
                    })
                    .collect(),
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests;
