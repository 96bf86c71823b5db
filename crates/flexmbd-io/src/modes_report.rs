//! Reports of a modal analysis: frequencies, energy distribution per mode, shapes.

use crate::report::{fmt_num, heading, table};
use crate::stopped::StopNote;
use crate::stream_json::Seq;
use flexmbd_core::dynamics::{Modal, ModeClass};
use flexmbd_core::elements::ElementKind;
use flexmbd_core::Model;
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use serde_json::Value;
use std::fmt::Write as _;

fn strain_text(model: &Model, m: &flexmbd_core::dynamics::Mode, count: usize) -> String {
    let names = model.node_names();
    m.strain
        .iter()
        .take(count)
        .map(|(el, mode, f)| {
            let e = &model.elements[*el];
            format!(
                "{} {} {:.0}%",
                e.name,
                e.element.mode_name(*mode, &names),
                100.0 * f
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

fn kinetic_text(model: &Model, m: &flexmbd_core::dynamics::Mode, count: usize) -> String {
    m.kinetic
        .iter()
        .take(count)
        .map(|(n, t, r)| {
            let name = &model.nodes[*n].name;
            match (t.abs() >= 0.005, r.abs() >= 0.005) {
                (true, true) => format!("{name} transl {:.0}% rot {:.0}%", 100.0 * t, 100.0 * r),
                (false, true) => format!("{name} rot {:.0}%", 100.0 * r),
                _ => format!("{name} transl {:.0}%", 100.0 * t),
            }
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The class of a mode with the fractions that decide it (docs/dynamics.md "Mode classes"):
/// `intended  β 0.99  ρ 1.00`; `rigid body` for a rigid-body mode.
pub(crate) fn class_text(m: &flexmbd_core::dynamics::Mode) -> String {
    if m.class == ModeClass::RigidBody {
        return "rigid body".to_string();
    }
    let rho = m
        .fractions
        .released
        .map_or_else(|| "  – ".to_string(), |r| format!("{r:.2}"));
    format!("{:<8}  β {:.2}  ρ {rho}", m.class.name(), m.fractions.body)
}

/// No point mass and no inertia tensor: every elastic mode is internal (β = 0).
fn has_bodies(model: &Model) -> bool {
    !model.loads.point_masses.is_empty() || !model.loads.inertias.is_empty()
}

/// Text report: one row per mode with where its strain and kinetic energy are; `stop` marks a
/// static path that stopped part-way (the modes are those of a converged step of it).
pub fn modes_text(
    model: &Model,
    file: &str,
    load_factor: f64,
    modal: &Modal,
    stop: Option<&StopNote>,
) -> String {
    let mut s = heading("modes", model, file);
    let _ = writeln!(
        s,
        "linearised at load factor {load_factor:.4}; {} degrees of freedom{}\n",
        modal.ndof,
        if modal.massless > 0 {
            format!(
                ", {} massless direction(s) condensed out statically",
                modal.massless
            )
        } else {
            String::new()
        }
    );
    let rows: Vec<Vec<String>> = modal
        .modes
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let f = if m.rigid_body {
                "0 (rigid-body mode)".to_string()
            } else if m.frequency.is_nan() {
                format!("complex (ω² = {})", fmt_num(m.eigenvalue))
            } else {
                fmt_num(m.frequency)
            };
            vec![
                (k + 1).to_string(),
                f,
                class_text(m),
                strain_text(model, m, 3),
                kinetic_text(model, m, 3),
            ]
        })
        .collect();
    s += &table(
        &[
            "mode",
            "f [Hz]",
            "class",
            "strain energy in",
            "kinetic energy in",
        ],
        &rows,
    );
    if !modal.modes.is_empty() && !has_bodies(model) {
        s += "\nno bodies (masses/inertias on nodes): every mode counts as internal\n";
    }
    if modal
        .modes
        .iter()
        .any(|m| m.eigenvalue < 0.0 && !m.rigid_body)
    {
        s += "\nwarning: negative eigenvalues: the equilibrium is unstable (the structure may have buckled)\n";
    }
    let held = held_inputs(model);
    if !held.is_empty() {
        let _ = writeln!(
            s,
            "\ninputs held at their (prescribed) values during the vibration: {}\n(remove an input from the model to let the mechanism move in that coordinate)",
            held.join(", ")
        );
    }
    if !modal.massless_nodes.is_empty() {
        let names: Vec<&str> = modal
            .massless_nodes
            .iter()
            .map(|&n| model.nodes[n].name.as_str())
            .collect();
        // a long list is shortened in the text (the JSON has all of them)
        const SHOWN: usize = 20;
        let list = if names.len() > SHOWN {
            format!(
                "{}, … and {} more ({} in all)",
                names[..SHOWN].join(", "),
                names.len() - SHOWN,
                names.len()
            )
        } else {
            names.join(", ")
        };
        let _ = writeln!(
            s,
            "\nnodes with coordinates without inertia (handled by static condensation): {list}"
        );
    }
    if let Some(stop) = stop {
        s += &stop.text();
    }
    s
}

/// Generalised coordinates (inputs) of the model: they are held during a vibration.
fn held_inputs(model: &Model) -> Vec<String> {
    crate::report::generalised_names(model, &model.partition.x, &model.partition.e)
}

/// JSON document of a modal analysis; `stopped` as in `flexmbd static --json`.
pub fn modes_json(
    model: &Model,
    file: &str,
    load_factor: f64,
    modal: &Modal,
    stop: Option<&StopNote>,
) -> Value {
    serde_json::to_value(ModesDoc {
        model,
        file,
        load_factor,
        modal,
        stop,
    })
    .expect("a modal analysis serialises")
}

/// The JSON document of [`modes_json`] as it is serialised, streamed from the analysis without
/// a tree of values: for a large model the tree took ten times the text (450 MB for the 46 MB
/// document of ten modes of a 10⁴-beam strip: every energy fraction and shape entry is a map).
/// Keys in the order of the tree's maps (sorted), so that both give the same text.
pub struct ModesDoc<'a> {
    /// The model analysed.
    pub model: &'a Model,
    /// The model file, as given.
    pub file: &'a str,
    /// Load factor of the state the modes are about.
    pub load_factor: f64,
    /// The modes.
    pub modal: &'a Modal,
    /// Why the static path stopped before the state, if it did.
    pub stop: Option<&'a StopNote>,
}

impl Serialize for ModesDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, modal) = (self.model, self.modal);
        let names = model.node_names();
        let mut m = s.serialize_map(Some(9))?;
        m.serialize_entry("file", self.file)?;
        m.serialize_entry("held_inputs", &held_inputs(model))?;
        m.serialize_entry("load_factor", &self.load_factor)?;
        m.serialize_entry("massless_directions", &modal.massless)?;
        m.serialize_entry(
            "massless_nodes",
            &Seq(|| modal.massless_nodes.iter().map(|&n| &model.nodes[n].name)),
        )?;
        m.serialize_entry("model", &model.name)?;
        m.serialize_entry(
            "modes",
            &Seq(|| {
                modal.modes.iter().map(|mode| ModeDoc {
                    model,
                    names: &names,
                    mode,
                })
            }),
        )?;
        m.serialize_entry("ndof", &modal.ndof)?;
        m.serialize_entry("stopped", &crate::stopped::json_field(self.stop))?;
        m.end()
    }
}

/// One mode of [`ModesDoc`].
struct ModeDoc<'a> {
    model: &'a Model,
    names: &'a [String],
    mode: &'a flexmbd_core::dynamics::Mode,
}

impl Serialize for ModeDoc<'_> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (model, m) = (self.model, self.mode);
        let mut map = s.serialize_map(Some(9))?;
        map.serialize_entry("body_fraction", &m.fractions.body)?;
        map.serialize_entry("class", m.class.name())?;
        map.serialize_entry("eigenvalue", &m.eigenvalue)?;
        map.serialize_entry(
            "frequency_hz",
            &(!m.frequency.is_nan()).then_some(m.frequency),
        )?;
        map.serialize_entry(
            "kinetic_energy",
            &Seq(|| {
                m.kinetic.iter().map(|&(n, t, r)| KineticShare {
                    node: &model.nodes[n].name,
                    rotation: r,
                    translation: t,
                })
            }),
        )?;
        map.serialize_entry("released_fraction", &m.fractions.released)?;
        map.serialize_entry("rigid_body", &m.rigid_body)?;
        map.serialize_entry(
            "shape",
            &Seq(|| {
                m.nodal
                    .iter()
                    .zip(&model.nodes)
                    .map(|((u, w), n)| NodeShape {
                        node: &n.name,
                        rotation: w,
                        translation: u,
                    })
            }),
        )?;
        map.serialize_entry(
            "strain_energy",
            &Seq(|| {
                m.strain.iter().map(|&(el, mode, f)| StrainShare {
                    element: &model.elements[el].name,
                    fraction: f,
                    mode: mode + 1,
                    mode_name: model.elements[el].element.mode_name(mode, self.names),
                })
            }),
        )?;
        map.end()
    }
}

/// A node's share of a mode's kinetic energy (keys sorted).
#[derive(Serialize)]
struct KineticShare<'a> {
    node: &'a str,
    rotation: f64,
    translation: f64,
}

/// A node's entry of a mode shape (keys sorted).
#[derive(Serialize)]
struct NodeShape<'a> {
    node: &'a str,
    rotation: &'a [f64; 3],
    translation: &'a [f64; 3],
}

/// An element deformation's share of a mode's strain energy (keys sorted).
#[derive(Serialize)]
struct StrainShare<'a> {
    element: &'a str,
    fraction: f64,
    mode: usize,
    mode_name: String,
}

#[cfg(test)]
mod tests {
    use super::*;
    use flexmbd_core::dynamics::EigenSolver;

    #[test]
    fn a_long_list_of_massless_nodes_is_shortened_in_the_text_only() {
        // 30 nodes in a row, all listed as massless: the text names the first 20 and the count,
        // the JSON every one
        let mut b = flexmbd_core::ModelBuilder::new("row");
        for i in 0..30 {
            b.add_node(&format!("n{i}"), [i as f64, 0.0, 0.0], false)
                .unwrap();
        }
        for i in 0..29 {
            b.add_element(
                &format!("t{i}"),
                &[&format!("n{i}"), &format!("n{}", i + 1)],
                flexmbd_core::model::ElementSpec::Truss { ea: 1.0 },
                &[],
                &[],
            )
            .unwrap();
        }
        let model = b.build().unwrap();
        let modal = Modal {
            modes: Vec::new(),
            ndof: 0,
            massless: 30,
            massless_nodes: (0..30).collect(),
            solver: EigenSolver::Dense,
        };
        let text = modes_text(&model, "row.toml", 1.0, &modal, None);
        assert!(text.contains("n0, n1,"), "{text}");
        assert!(text.contains("n19, … and 10 more (30 in all)"), "{text}");
        assert!(!text.contains("n20"), "{text}");
        let json = modes_json(&model, "row.toml", 1.0, &modal, None);
        assert_eq!(json["massless_nodes"].as_array().unwrap().len(), 30);
    }
}
