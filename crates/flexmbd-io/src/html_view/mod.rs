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
mod document;
mod geometry;
mod page;
mod results;
mod simulate;

pub use document::*;
pub use geometry::{beam_section, MIN_DIAMETER, MIN_THICKNESS, NOMINAL_SHEET_WIDTH};
pub use page::{html_escape, script_json, script_text, view_html, THREE_VERSION};
pub use results::{animation_scale, significant, ANIMATION_ROTATION, ANIMATION_TRANSLATION};
pub use simulate::{simulate_view_data, ViewSimulation, MAX_VIEW_FRAMES, MAX_VIEW_NODE_FRAMES};

use crate::vtk::model_size;
use flexmbd_core::model::Model;
use flexmbd_core::statics::StepResult;
use geometry::*;
#[cfg(test)]
use page::{fill, ORBIT_JS, TEMPLATE, THREE_JS, VIEWER_JS};
use results::*;

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
        screw_lines: Vec::new(),
    };
    match results {
        ViewResults::Check => {
            data.frames
                .push(frame(model, "reference", None, &model.x0()));
            if let Some(c) = classification {
                data.animations = motion_animations(model, c.analysis, size);
                data.fields = self_stress_fields(model, c.analysis);
                if let Some(sc) = c.screws {
                    data.screw_lines = screw_lines(sc, c.wires);
                }
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

#[cfg(test)]
mod tests;
