//! The inputs and outputs of a state-space model: force and moment inputs ([`Input`]),
//! prescribed-motion inputs ([`Motion`]), outputs ([`Output`], [`Probe`], [`OutputKind`]), with
//! their names, units and descriptions for reports.

use crate::elements::ElementKind;
use crate::model::{Dof, Model};

/// A force (translational direction) or moment (rotational direction) input on a node, in
/// global axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Input {
    /// Node index.
    pub node: usize,
    /// x, y, z: force along the axis [N]; rx, ry, rz: moment about it [N·m].
    pub dof: Dof,
}

/// What an output measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputKind {
    /// Displacement [m] or rotation [rad].
    Disp,
    /// Velocity [m/s] or angular velocity [rad/s].
    Vel,
    /// Acceleration [m/s²] or angular acceleration [rad/s²].
    Acc,
}

impl OutputKind {
    /// Name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            OutputKind::Disp => "disp",
            OutputKind::Vel => "vel",
            OutputKind::Acc => "acc",
        }
    }
    /// Parse a command-line name.
    pub fn parse(s: &str) -> Option<OutputKind> {
        [OutputKind::Disp, OutputKind::Vel, OutputKind::Acc]
            .into_iter()
            .find(|k| k.name() == s)
    }
    /// Power of s in the transfer function (0, 1, 2).
    fn order(self) -> i32 {
        match self {
            OutputKind::Disp => 0,
            OutputKind::Vel => 1,
            OutputKind::Acc => 2,
        }
    }
}

/// What an output measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Probe {
    /// The motion of a node along (translations) or about (rotations) a global axis.
    Node {
        /// Node index.
        node: usize,
        /// Direction.
        dof: Dof,
    },
    /// A deformation of an element, δe (a strain-gauge or an encoder on a hinge).
    Deformation {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
    /// The reaction at a held node coordinate (a support or prescribed input): the force
    /// along, or the moment about, a global axis that the support exerts, as `flexmbd static`
    /// reports reactions.
    Reaction {
        /// Node index.
        node: usize,
        /// Direction.
        dof: Dof,
    },
    /// The stress resultant of a flexible deformation, δσ = S δe (the element's force:
    /// the axial force of a truss or beam, σ2..σ6 ≈ torque and bending moments / l0, a hinge
    /// torque).
    Force {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
}

/// An output: a probe and whether its value, rate or second rate is measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Output {
    /// What is measured.
    pub probe: Probe,
    /// Value (displacement, deformation, force), its velocity or its acceleration.
    pub kind: OutputKind,
}

/// A prescribed-motion (enforced-motion) input, whose input signal is the acceleration:
/// - of a held translational coordinate of a node along a global axis [m/s²], or of a held
///   rotation component about a global axis [rad/s²] (a support, `[inputs]` or
///   `[[prescribe]]` coordinate);
/// - of a held deformation of an element (an `input` mode or a rigid mode, e.g. a linear
///   actuator's elongation or a driven hinge's angle): ë [m/s²] for truss and beam modes
///   (lengths), [rad/s²] for hinge modes (angles).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// A held nodal coordinate.
    Node {
        /// Node index.
        node: usize,
        /// x, y, z (translation) or rx, ry, rz (rotation).
        dof: Dof,
    },
    /// A held deformation.
    Deformation {
        /// Element index.
        element: usize,
        /// Mode, 0-based (printed 1-based).
        mode: usize,
    },
}

impl Motion {
    /// `motion`.
    pub fn kind_name(&self) -> &'static str {
        "motion"
    }
    /// Name `NODE:DIR:motion`, or `ELEMENT:MODE:motion` with the mode 1-based.
    pub fn name(&self, model: &Model) -> String {
        match *self {
            Motion::Node { node, dof } => {
                format!("{}:{}:motion", model.nodes[node].name, dof.name())
            }
            Motion::Deformation { element, mode } => {
                format!("{}:{}:motion", model.elements[element].name, mode + 1)
            }
        }
    }
    /// SI unit of the input (an acceleration or angular acceleration).
    pub fn unit(&self, model: &Model) -> &'static str {
        let angle = match *self {
            Motion::Node { dof, .. } => dof.is_rotation(),
            Motion::Deformation { element, mode } => {
                model.elements[element].element.mode_is_angle(mode)
            }
        };
        if angle {
            "rad/s²"
        } else {
            "m/s²"
        }
    }
    /// Words, e.g. "enforced acceleration of base along global y".
    pub fn describe(&self, model: &Model) -> String {
        match *self {
            Motion::Node { node, dof } => {
                let what = pick(dof, "acceleration", "angular acceleration");
                format!(
                    "enforced {what} of {} {} (prescribed motion)",
                    model.nodes[node].name,
                    direction(dof)
                )
            }
            Motion::Deformation { element, mode } => {
                let entry = &model.elements[element];
                let what = if self.unit(model) == "rad/s²" {
                    "angular acceleration"
                } else {
                    "acceleration"
                };
                format!(
                    "enforced {what} of deformation {} ({}) of {} `{}` (prescribed deformation)",
                    mode + 1,
                    entry.element.mode_name(mode, &model.node_names()),
                    entry.element.type_name(),
                    entry.name
                )
            }
        }
    }
}

/// Description of one input column (a force/moment or a prescribed motion), for reports.
#[derive(Clone, Debug, PartialEq)]
pub struct InputInfo {
    /// `NODE:DIR:KIND`.
    pub name: String,
    /// Node index (force, moment or nodal motion).
    pub node: Option<usize>,
    /// Direction (force, moment or nodal motion).
    pub dof: Option<Dof>,
    /// Element index and 0-based mode (deformation motion).
    pub deformation: Option<(usize, usize)>,
    /// `force`, `moment` or `motion`.
    pub kind: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// Words.
    pub description: String,
}

impl Input {
    /// `force` or `moment`.
    pub fn kind_name(&self) -> &'static str {
        if self.dof.is_rotation() {
            "moment"
        } else {
            "force"
        }
    }
    /// Name `NODE:DIR:force|moment`.
    pub fn name(&self, model: &Model) -> String {
        format!(
            "{}:{}:{}",
            model.nodes[self.node].name,
            self.dof.name(),
            self.kind_name()
        )
    }
    /// SI unit.
    pub fn unit(&self) -> &'static str {
        if self.dof.is_rotation() {
            "N·m"
        } else {
            "N"
        }
    }
    /// Words, e.g. "force on tip along global y".
    pub fn describe(&self, model: &Model) -> String {
        let axis = axis_name(self.dof);
        let node = &model.nodes[self.node].name;
        if self.dof.is_rotation() {
            format!("moment on {node} about global {axis}")
        } else {
            format!("force on {node} along global {axis}")
        }
    }
}

impl Output {
    /// The motion of a node.
    pub fn node(node: usize, dof: Dof, kind: OutputKind) -> Output {
        Output {
            probe: Probe::Node { node, dof },
            kind,
        }
    }
    /// Whether the output is a constraint reaction: a support reaction, or the force of a rigid
    /// or prescribed deformation (not σ = S e).
    pub fn is_reaction(&self, model: &Model) -> bool {
        match self.probe {
            Probe::Reaction { .. } => true,
            Probe::Force { element, mode } => {
                crate::statics::element_roles(model, element)[mode]
                    != crate::statics::Role::Flexible
            }
            Probe::Node { .. } | Probe::Deformation { .. } => false,
        }
    }
    /// The node and direction of a node output.
    pub fn node_dof(&self) -> Option<(usize, Dof)> {
        match self.probe {
            Probe::Node { node, dof } => Some((node, dof)),
            _ => None,
        }
    }
    /// Name `NODE:DIR:disp|vel|acc`, or `ELEMENT:MODE:def|force` (value) with `:vel` or
    /// `:acc` for its rates.
    pub fn name(&self, model: &Model) -> String {
        match self.probe {
            Probe::Node { node, dof } => format!(
                "{}:{}:{}",
                model.nodes[node].name,
                dof.name(),
                self.kind.name()
            ),
            Probe::Reaction { node, dof } => {
                format!("{}:{}:reaction", model.nodes[node].name, dof.name())
            }
            Probe::Deformation { element, mode } | Probe::Force { element, mode } => {
                let q = if matches!(self.probe, Probe::Force { .. }) {
                    "force"
                } else {
                    "def"
                };
                let rate = match self.kind {
                    OutputKind::Disp => String::new(),
                    k => format!(":{}", k.name()),
                };
                format!("{}:{}:{q}{rate}", model.elements[element].name, mode + 1)
            }
        }
    }
    /// SI unit.
    pub fn unit(&self, model: &Model) -> &'static str {
        let angle =
            |element: usize, mode: usize| model.elements[element].element.mode_is_angle(mode);
        // rows: length, angle, force, torque; columns: value, rate, second rate
        const UNITS: [[&str; 3]; 4] = [
            ["m", "m/s", "m/s²"],
            ["rad", "rad/s", "rad/s²"],
            ["N", "N/s", "N/s²"],
            ["N·m", "N·m/s", "N·m/s²"],
        ];
        let row = match self.probe {
            Probe::Node { dof, .. } => usize::from(dof.is_rotation()),
            Probe::Deformation { element, mode } => usize::from(angle(element, mode)),
            Probe::Force { element, mode } => 2 + usize::from(angle(element, mode)),
            Probe::Reaction { dof, .. } => 2 + usize::from(dof.is_rotation()),
        };
        UNITS[row][self.kind.order() as usize]
    }
    /// Words, e.g. "velocity of tip along global y".
    pub fn describe(&self, model: &Model) -> String {
        match self.probe {
            Probe::Node { node, dof } => {
                let axis = axis_name(dof);
                let node = &model.nodes[node].name;
                let what = match (dof.is_rotation(), self.kind) {
                    (false, OutputKind::Disp) => "displacement",
                    (false, OutputKind::Vel) => "velocity",
                    (false, OutputKind::Acc) => "acceleration",
                    (true, OutputKind::Disp) => "rotation",
                    (true, OutputKind::Vel) => "angular velocity",
                    (true, OutputKind::Acc) => "angular acceleration",
                };
                let prep = if dof.is_rotation() { "about" } else { "along" };
                format!("{what} of {node} {prep} global {axis}")
            }
            Probe::Reaction { node, dof } => {
                let what = pick(dof, "reaction force", "reaction moment");
                format!("{what} at {} {}", model.nodes[node].name, direction(dof))
            }
            Probe::Deformation { element, mode } | Probe::Force { element, mode } => {
                let entry = &model.elements[element];
                let q = if matches!(self.probe, Probe::Force { .. }) {
                    "stress resultant σ"
                } else {
                    "deformation e"
                };
                let rate = match self.kind {
                    OutputKind::Disp => "",
                    OutputKind::Vel => "rate of the ",
                    OutputKind::Acc => "second rate of the ",
                };
                let held = self.is_reaction(model);
                format!(
                    "{rate}{q}{} ({}) of {} `{}`{}",
                    mode + 1,
                    entry.element.mode_name(mode, &model.node_names()),
                    entry.element.type_name(),
                    entry.name,
                    if held {
                        ", the constraint reaction that holds it"
                    } else {
                        ""
                    }
                )
            }
        }
    }
}

pub(super) fn axis_name(d: Dof) -> &'static str {
    ["x", "y", "z"][d.index() % 3]
}

/// `translation` or `rotation` by the kind of direction.
pub(super) fn pick(d: Dof, translation: &'static str, rotation: &'static str) -> &'static str {
    if d.is_rotation() {
        rotation
    } else {
        translation
    }
}

/// "along global y" or "about global z".
pub(super) fn direction(d: Dof) -> String {
    format!("{} global {}", pick(d, "along", "about"), axis_name(d))
}
